//! A metric field between its vertices: the Log-Euclidean barycentric mean
//! exp(Σ λᵢ log Mᵢ) of the corner metrics of the triangle that holds a point, or, outside
//! every triangle (a chord of a curved boundary cutting into a hole), of the nearest
//! triangle at its closest point (Arsigny et al. 2006; the one implementation of the mean
//! is [`crate::metric::log_euclidean`], the one point location
//! [`crate::geometry::TriangleLocator`]).
//!
//! The remesher interpolates every new or moved vertex from its *input* field through an
//! [`Interpolator`], and `remesh --measure --background` measures any mesh against a
//! field through [`super::MetricField::interpolate`]: one interpolation for both, so a
//! mesh is measured against the field the remesher followed.
//!
//! Invariants: every interpolated tensor is SPD when the corner tensors are (the mean of
//! logarithms is symmetric, its exponential SPD); the logarithms are taken once, at
//! construction.

use crate::geometry::TriangleLocator;
use crate::metric::{log_euclidean, log_spd, Sym2};
use smartmesh_formats::{CellKind, TaggedMesh};

/// A triangulation with the logarithm of its metric at every vertex.
pub struct Interpolator {
    locator: TriangleLocator,
    logs: Vec<Sym2>,
}

impl Interpolator {
    /// Indexes `tris` (counter-clockwise) over `points`, with metrics `metric` (one per
    /// point, SPD).
    pub fn new(points: &[[f64; 2]], tris: &[[usize; 3]], metric: &[Sym2]) -> Interpolator {
        let logs = metric.iter().map(log_spd).collect();
        Interpolator { locator: TriangleLocator::new(points, tris), logs }
    }

    /// The field at `p` (the identity when there is no triangle).
    pub fn metric_at(&self, p: [f64; 2]) -> Sym2 {
        if self.locator.is_empty() {
            return Sym2::IDENTITY;
        }
        let (t, w) = self.locator.locate(p);
        let v = self.locator.triangles()[t];
        log_euclidean(&w, &[&self.logs[v[0]], &self.logs[v[1]], &self.logs[v[2]]])
    }
}

/// Why a field cannot be interpolated from a mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InterpolationError {
    /// The metric does not have one tensor per point.
    #[error("the metric has {items} tensors for {vertices} vertices")]
    Count {
        /// Tensors given.
        items: usize,
        /// Points of the mesh.
        vertices: usize,
    },
    /// No triangle to interpolate in.
    #[error("the mesh has no triangles")]
    NoTriangles,
}

/// The field `metric` (one tensor per point of `mesh`) at `points`, interpolated in the
/// triangles of `mesh`.
pub(crate) fn interpolate(
    mesh: &TaggedMesh,
    metric: &[Sym2],
    points: &[[f64; 2]],
) -> Result<Vec<Sym2>, InterpolationError> {
    if metric.len() != mesh.points.len() {
        return Err(InterpolationError::Count { items: metric.len(), vertices: mesh.points.len() });
    }
    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    let tris: Vec<[usize; 3]> = mesh
        .cells()
        .filter(|c| c.0 == CellKind::Triangle)
        .map(|c| [c.1[0] as usize, c.1[1] as usize, c.1[2] as usize])
        .collect();
    if tris.is_empty() {
        return Err(InterpolationError::NoTriangles);
    }
    let field = Interpolator::new(&pts, &tris, metric);
    Ok(points.iter().map(|&p| field.metric_at(p)).collect())
}
