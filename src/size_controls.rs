//! The size controls of MMG's command line (`-hmin`, `-hmax`, `-hgrad`, `-hausd`) for a
//! metric that is already on a mesh: what `smartmesh remesh` applies to the metric it
//! reads, and what `smartmesh adapt` applies for `--hausd` before the remeshers that have
//! no such option of their own (the native one and Gmsh's BAMG, through
//! [`crate::adapters`]' wrapping adapter).
//!
//! Order: the Hausdorff bound first, then the clamp to [hmin, hmax] (hmin wins over the
//! curvature: a user who sets it means it), then the gradation, which only shrinks sizes.
//!
//! The Hausdorff bound: an edge of length h on a curve of radius R lies at most
//! s = h² / (8R) from it (the sagitta), so s <= hausd asks h <= sqrt(8 R hausd). R at a
//! vertex of a boundary or interface curve is the radius of the circle through it and its
//! two neighbours along the curve (infinite on a straight run, so no bound there); at the
//! ends of an open curve there is none. The tensor is intersected with the disc of that
//! radius: the size along the curve is bounded, a finer size across it is kept. This is
//! MMG's rule; the curve is the mesh's own polyline, so the bound follows the geometry
//! as the mesh describes it.

use smartmesh_formats::TaggedMesh;

use crate::mesh_graph::{MeshGraph, MeshGraphError};
use crate::metric::{SizeBounds, SizeTensor, Sym2};
use crate::sizing::gradation::apply_gradation;
use crate::topology::Topology;

/// Controls on a metric; `None` leaves that control off.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SizeControls {
    /// Smallest size.
    pub h_min: Option<f64>,
    /// Largest size.
    pub h_max: Option<f64>,
    /// Gradation factor (>= 1) per unit of metric length.
    pub gradation: Option<f64>,
    /// Largest distance between a curve and the edges along it.
    pub hausd: Option<f64>,
}

/// Why the controls could not be applied.
#[derive(Debug, thiserror::Error)]
pub enum ControlError {
    /// A tensor of the metric is not a metric (the vertex is 0-based).
    #[error("the metric at vertex {vertex} (0-based) is not a finite positive definite tensor")]
    NotSpd {
        /// The vertex.
        vertex: usize,
    },
    /// The metric does not have one tensor per vertex.
    #[error("the metric has {items} tensors for {vertices} vertices")]
    Count {
        /// Tensors.
        items: usize,
        /// Vertices.
        vertices: usize,
    },
    /// hmin larger than hmax, or out of range.
    #[error("size bounds [{h_min}, {h_max}] are not a range of sizes in [1e-30, 1e30]")]
    Bounds {
        /// hmin.
        h_min: f64,
        /// hmax.
        h_max: f64,
    },
    /// The mesh is not a graph.
    #[error("{0}")]
    Graph(#[from] MeshGraphError),
}

impl SizeControls {
    /// Whether no control is set.
    pub fn is_empty(&self) -> bool {
        *self == SizeControls::default()
    }

    /// Applies the controls to `metric` (one tensor per vertex of `mesh`).
    pub fn apply(&self, mesh: &TaggedMesh, metric: &mut [Sym2]) -> Result<(), ControlError> {
        if self.is_empty() {
            return Ok(());
        }
        if metric.len() != mesh.points.len() {
            return Err(ControlError::Count { items: metric.len(), vertices: mesh.points.len() });
        }
        let topology = Topology::from_mesh(mesh);
        let mut tensors = Vec::with_capacity(metric.len());
        for (vertex, m) in metric.iter().enumerate() {
            tensors
                .push(SizeTensor::try_from_metric(m).map_err(|_| ControlError::NotSpd { vertex })?);
        }
        if let Some(hausd) = self.hausd {
            for (v, h) in curvature_bounds(mesh, &topology, hausd) {
                tensors[v] = tensors[v].intersection(&SizeTensor::isotropic(h));
            }
        }
        if self.h_min.is_some() || self.h_max.is_some() {
            let (h_min, h_max) = (
                self.h_min.unwrap_or(SizeTensor::MIN_SIZE),
                self.h_max.unwrap_or(SizeTensor::MAX_SIZE),
            );
            let bounds = SizeBounds::try_new(h_min, h_max, f64::INFINITY)
                .ok_or(ControlError::Bounds { h_min, h_max })?;
            for t in &mut tensors {
                *t = t.clamp(&bounds);
            }
        }
        if let Some(g) = self.gradation {
            let graph = MeshGraph::from_topology(&topology, mesh)?;
            apply_gradation(&graph, &mut tensors, g.max(1.0));
        }
        for (m, t) in metric.iter_mut().zip(&tensors) {
            *m = t.to_metric();
        }
        Ok(())
    }
}

/// For each interior vertex of a curve polyline where the curve bends, the largest size
/// that keeps the edges within `hausd` of the curve (see the module header); a vertex on
/// several curves gets the smallest bound.
pub(crate) fn curvature_bounds(
    mesh: &TaggedMesh,
    topology: &Topology,
    hausd: f64,
) -> Vec<(usize, f64)> {
    let p = |v: usize| [mesh.points[v][0], mesh.points[v][1]];
    let mut bound: Vec<Option<f64>> = vec![None; mesh.points.len()];
    for curve in &topology.curves {
        for line in &curve.polylines {
            let n = line.vertices.len();
            let inner = if line.closed { 0..n } else { 1..n.saturating_sub(1) };
            for i in inner {
                let prev = line.vertices[(i + n - 1) % n];
                let next = line.vertices[(i + 1) % n];
                let v = line.vertices[i];
                let Some(r) = circumradius(p(prev), p(v), p(next)) else { continue };
                let h = (8.0 * r * hausd).sqrt();
                if (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&h) {
                    bound[v] = Some(bound[v].map_or(h, |b: f64| b.min(h)));
                }
            }
        }
    }
    bound.into_iter().enumerate().filter_map(|(v, b)| Some((v, b?))).collect()
}

/// The radius of the circle through `a`, `b`, `c`; `None` when they are collinear (or two
/// coincide).
fn circumradius(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<f64> {
    let len = |u: [f64; 2], w: [f64; 2]| (u[0] - w[0]).hypot(u[1] - w[1]);
    let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    let r = len(a, b) * len(b, c) * len(c, a) / (2.0 * cross.abs());
    (r.is_finite() && r > 0.0).then_some(r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::{CellBlock, CellKind};

    /// A regular n-gon of radius `r` as a fan of triangles, its boundary as Line cells of
    /// tag 1.
    fn polygon(n: usize, r: f64) -> TaggedMesh {
        let mut mesh = TaggedMesh::default();
        mesh.points.push([0.0, 0.0, 0.0]);
        for k in 0..n {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            mesh.points.push([r * t.cos(), r * t.sin(), 0.0]);
        }
        let ring = |k: usize| 1 + k % n;
        let mut tri = CellBlock::new(CellKind::Triangle);
        let mut lines = CellBlock::new(CellKind::Line);
        for k in 0..n {
            tri.push(&[0, ring(k), ring(k + 1)], 2, 2);
            lines.push(&[ring(k), ring(k + 1)], 1, 1);
        }
        mesh.blocks.push(tri);
        mesh.blocks.push(lines);
        mesh
    }

    #[test]
    fn the_hausdorff_bound_is_the_sagitta_rule_on_the_circle_through_three_vertices() {
        let mesh = polygon(64, 2.0);
        let mut metric = vec![Sym2::new(1.0, 0.0, 1.0); mesh.points.len()];
        let hausd = 1e-3;
        SizeControls { hausd: Some(hausd), ..Default::default() }
            .apply(&mesh, &mut metric)
            .unwrap();
        // The circle through three vertices of a regular polygon is its circumcircle.
        let h = (8.0 * 2.0 * hausd).sqrt();
        for m in &metric[1..] {
            let t = SizeTensor::try_from_metric(m).unwrap();
            assert!((t.h_max() - h).abs() < 1e-9 * h, "{} vs {h}", t.h_max());
        }
        // The centre is on no curve: left as it was.
        assert_eq!(metric[0], Sym2::new(1.0, 0.0, 1.0));
    }

    #[test]
    fn bounds_clamp_and_gradation_only_shrinks() {
        let mesh = polygon(16, 1.0);
        let mut metric = vec![Sym2::new(1.0, 0.0, 1.0); mesh.points.len()];
        metric[0] = SizeTensor::isotropic(0.01).to_metric();
        let c = SizeControls {
            h_min: Some(0.05),
            h_max: Some(0.5),
            gradation: Some(1.05),
            hausd: None,
        };
        c.apply(&mesh, &mut metric).unwrap();
        let sizes: Vec<f64> =
            metric.iter().map(|m| SizeTensor::try_from_metric(m).unwrap().h_max()).collect();
        assert!((sizes[0] - 0.05).abs() < 1e-12, "{}", sizes[0]);
        assert!(sizes[1..].iter().all(|&h| (0.05 - 1e-12..=0.5 + 1e-12).contains(&h)));
        // Graded from 0.05 over a unit distance (20 units of metric length, 1.05^20 = 2.65).
        assert!(sizes[1] < 0.5, "{sizes:?}");
        let bad = SizeControls { h_min: Some(2.0), h_max: Some(1.0), ..Default::default() };
        assert!(matches!(bad.apply(&mesh, &mut metric), Err(ControlError::Bounds { .. })));
    }
}
