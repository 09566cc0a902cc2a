//! Gradient and Hessian recovery of a scalar P1 field: one value per vertex, linear on
//! each triangle, whose own second derivatives are zero. Two methods:
//!
//! - [`Method::L2Projection`]: a gradient recovered at every vertex, then its P1
//!   gradient projected onto P1 with the lumped mass matrix (each vertex takes the
//!   area-weighted mean of its triangles' gradients of the recovered gradient),
//!   symmetrised, for the Hessian. The first half is no longer the lumped projection
//!   of the field's own P1 gradient (the method of this name until then, exact only at
//!   the vertices two rings inside a structured mesh, never at the boundary, and
//!   divergent on Delaunay meshes, since no mean of a vertex's cell gradients is exact
//!   on quadratics on irregular patches) but the edge fit of `super::edge_fit`: the
//!   linear vector field closest, in least squares over the vertex's patch, to the P1
//!   gradient's component along each edge at the edge's midpoint, where that component
//!   is exact for a quadratic; a discrete L2 projection of the P1 gradient onto linear
//!   fields, not the finite-element one. Why exact: the fit returns a quadratic's
//!   gradient at every vertex, interior and boundary (boundary patches grow a ring), so
//!   the recovered gradient is the linear field ∇u at the vertices, its P1 gradient is the
//!   constant Hessian on every triangle, and any mean of it is the Hessian. Cost: a QR of
//!   about 12 × 6 per vertex (boundary vertices: two rings, about 40 × 6) and two passes
//!   over the triangles. On smooth fields it converges at second order inside smooth
//!   images of a grid (as the plain double projection did, with smaller errors) and at
//!   first order on jittered grids and Delaunay meshes, the boundary included (the tests
//!   measure both).
//! - [`Method::QuadraticFit`]: at each vertex the quadratic
//!   u(x) = u_v + g·d + ½ dᵀ H d (d = x − x_v) that fits the values of the vertex's patch
//!   in the least-squares sense (Householder QR on coordinates scaled by the patch's
//!   radius). The patch is the vertices within k edges, k = 1 first, grown one ring at a
//!   time until the fit is determined: at least six other vertices (one more than the
//!   five unknowns, which keeps the fit from interpolating a thin patch) and a triangular
//!   factor whose smallest diagonal is no less than 1e-7 of its largest. Boundary
//!   vertices, whose first ring is short and one-sided, so get two or more rings. Exact
//!   (to rounding) on quadratic fields at every vertex, interior and boundary, on any
//!   mesh. Unlike [`super::recovery3`]'s fit, patches do not grow on their condition
//!   number: the first determined ones are well conditioned in the plane (at most 76 on
//!   the tests' Delaunay meshes, against 8e4 at a face vertex in space), and growing
//!   those above 40 traded the worst boundary vertex (2.1 to 1.1) for interior ones
//!   (0.72 to 0.82).
//!
//! Quadrangles are split along their 0–2 diagonal. Triangles of zero area are skipped.
//! A vertex that no cell uses gets a zero gradient and Hessian. Results are a function of
//! the mesh and values only, whatever the thread count.

use rayon::prelude::*;

use super::edge_fit::recovered_gradients;
use super::patch::{drop_roundoff, least_squares, Adjacency, Patch};
use crate::geometry::Point2;
use crate::metric::Sym2;

/// How derivatives are recovered (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// A gradient fitted to the P1 gradient's edge components, then its P1 gradient's
    /// lumped L2 projection.
    L2Projection,
    /// A least-squares quadratic on each vertex's patch.
    #[default]
    QuadraticFit,
}

impl Method {
    /// Every method, in the order the CLI lists them.
    pub const ALL: [Method; 2] = [Method::QuadraticFit, Method::L2Projection];

    /// Its name on the command line and in recipes: `quadratic-fit`, `l2-projection`.
    pub fn name(self) -> &'static str {
        match self {
            Method::L2Projection => "l2-projection",
            Method::QuadraticFit => "quadratic-fit",
        }
    }

    /// The method named `name`.
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }
}

/// Recovered first and second derivatives, one of each per vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivatives {
    /// The gradient at each vertex.
    pub gradient: Vec<[f64; 2]>,
    /// The Hessian at each vertex.
    pub hessian: Vec<Sym2>,
}

/// Why derivatives could not be recovered.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RecoveryError {
    /// The field has another number of values than the mesh has vertices.
    #[error("the field has {values} values for {vertices} vertices")]
    Count {
        /// Values given.
        values: usize,
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// A value (at a vertex some cell uses) that is NaN or infinite.
    #[error("the field's value at vertex {vertex} (0-based) is {value}, not a finite number")]
    NotFinite {
        /// The vertex.
        vertex: usize,
        /// Its value.
        value: f64,
    },
    /// A coordinate that is NaN or infinite.
    #[error("vertex {vertex} (0-based) has a coordinate that is not finite")]
    NonFiniteVertex {
        /// The vertex.
        vertex: usize,
    },
    /// A cell corner past the vertices.
    #[error("cell {cell} names vertex {vertex}, but the mesh has {len}")]
    CornerOutOfRange {
        /// The cell.
        cell: usize,
        /// The corner's vertex.
        vertex: usize,
        /// The number of vertices.
        len: usize,
    },
    /// No quadratic can be fitted around a vertex: its connected part of the mesh has
    /// too few vertices (six in the plane, ten in space), or they all lie on a conic
    /// (a quadric) through it.
    #[error("no quadratic fits the field around vertex {vertex} (0-based): its part of the mesh has {patch} other vertices, on no determined patch (a quadratic needs five in the plane, nine in space, not on one conic or quadric)")]
    Undetermined {
        /// The vertex.
        vertex: usize,
        /// Vertices of its largest patch.
        patch: usize,
    },
}

/// A P1 mesh as recovery sees it: points, triangles, and the vertex adjacency of the cell
/// edges.
#[derive(Debug, Clone)]
pub struct P1Mesh<'a> {
    points: &'a [Point2],
    triangles: Vec<[u32; 3]>,
    adjacency: Adjacency,
}

impl<'a> P1Mesh<'a> {
    /// The mesh of `points` and `cells` (four corners each, the fourth `u32::MAX` for a
    /// triangle; a quadrangle is split along its 0–2 diagonal, its four sides kept as
    /// edges).
    pub fn new(points: &'a [Point2], cells: &[[u32; 4]]) -> Result<P1Mesh<'a>, RecoveryError> {
        let n = points.len();
        if let Some(vertex) = points.iter().position(|p| !(p[0].is_finite() && p[1].is_finite())) {
            return Err(RecoveryError::NonFiniteVertex { vertex });
        }
        let mut triangles = Vec::with_capacity(cells.len());
        let mut edges: Vec<[u32; 2]> = Vec::with_capacity(3 * cells.len());
        for (i, c) in cells.iter().enumerate() {
            let k = if c[3] == u32::MAX { 3 } else { 4 };
            for &v in &c[..k] {
                if v as usize >= n {
                    return Err(RecoveryError::CornerOutOfRange {
                        cell: i,
                        vertex: v as usize,
                        len: n,
                    });
                }
            }
            triangles.push([c[0], c[1], c[2]]);
            if k == 4 {
                triangles.push([c[0], c[2], c[3]]);
            }
            for j in 0..k {
                let (a, b) = (c[j], c[(j + 1) % k]);
                if a != b {
                    edges.push([a.min(b), a.max(b)]);
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let adjacency = Adjacency::new(n, &edges);
        Ok(P1Mesh { points, triangles, adjacency })
    }

    /// The mesh of `points` and `triangles`.
    pub fn from_triangles(
        points: &'a [Point2],
        triangles: &[[u32; 3]],
    ) -> Result<P1Mesh<'a>, RecoveryError> {
        let cells: Vec<[u32; 4]> = triangles.iter().map(|t| [t[0], t[1], t[2], u32::MAX]).collect();
        P1Mesh::new(points, &cells)
    }

    /// The points.
    pub fn points(&self) -> &[Point2] {
        self.points
    }

    /// The triangles (quadrangles split).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The neighbours of `v` along cell edges, sorted.
    pub fn neighbours(&self, v: usize) -> &[u32] {
        self.adjacency.of(v)
    }

    /// Whether some cell uses `v`.
    pub fn is_used(&self, v: usize) -> bool {
        self.adjacency.is_used(v)
    }
}

/// The gradient and Hessian of the P1 field `values` on `mesh` by `method`.
pub fn recover(
    mesh: &P1Mesh<'_>,
    values: &[f64],
    method: Method,
) -> Result<Derivatives, RecoveryError> {
    check_values(values, mesh.points.len(), &mesh.adjacency)?;
    let mut d = match method {
        Method::L2Projection => fit_then_project(mesh, values),
        Method::QuadraticFit => quadratic_fit(mesh, values)?,
    };
    // The largest absolute row sum bounds the spectral radius.
    let radius = |h: &Sym2| h.a.abs().max(h.c.abs()) + h.b.abs();
    let zero = Sym2::new(0.0, 0.0, 0.0);
    drop_roundoff(mesh.points, &mesh.adjacency, values, &mut d.hessian, radius, zero);
    Ok(d)
}

/// The field's values against a mesh of `n` vertices (in both dimensions): one per
/// vertex, finite wherever a cell (as `adjacency` says) uses the vertex.
pub(super) fn check_values(
    values: &[f64],
    n: usize,
    adjacency: &Adjacency,
) -> Result<(), RecoveryError> {
    if values.len() != n {
        return Err(RecoveryError::Count { values: values.len(), vertices: n });
    }
    if let Some(vertex) = (0..n).find(|&v| adjacency.is_used(v) && !values[v].is_finite()) {
        return Err(RecoveryError::NotFinite { vertex, value: values[vertex] });
    }
    Ok(())
}

/// Twice the signed area of triangle `t` and the gradient of the P1 function with
/// corner values `f` on it (`None` for a triangle of zero area).
fn p1_gradient(points: &[Point2], t: [u32; 3], f: [f64; 3]) -> Option<(f64, [f64; 2])> {
    let [p0, p1, p2] = t.map(|v| points[v as usize]);
    let (x1, y1) = (p1[0] - p0[0], p1[1] - p0[1]);
    let (x2, y2) = (p2[0] - p0[0], p2[1] - p0[1]);
    let area2 = x1 * y2 - y1 * x2;
    if area2 == 0.0 {
        return None;
    }
    let (d1, d2) = (f[1] - f[0], f[2] - f[0]);
    Some((area2, [(d1 * y2 - d2 * y1) / area2, (d2 * x1 - d1 * x2) / area2]))
}

/// The lumped-mass L2 projection onto P1 of the element gradients of each of the `k`
/// P1 fields `fields` (vertex-major, `k` values per vertex): `2k` values per vertex,
/// field-major (∂x f0, ∂y f0, ∂x f1, …).
fn project_gradients<const K: usize>(mesh: &P1Mesh<'_>, fields: &[[f64; K]]) -> Vec<[[f64; 2]; K]> {
    let n = mesh.points.len();
    let mut sum = vec![[[0.0; 2]; K]; n];
    let mut weight = vec![0.0; n];
    for &t in &mesh.triangles {
        let mut grads = [[0.0; 2]; K];
        let mut area = 0.0;
        for (j, g) in grads.iter_mut().enumerate() {
            let f = t.map(|v| fields[v as usize][j]);
            match p1_gradient(mesh.points, t, f) {
                Some((a2, gr)) => {
                    area = 0.5 * a2.abs();
                    *g = gr;
                }
                None => area = 0.0,
            }
        }
        if area == 0.0 {
            continue;
        }
        for v in t {
            let v = v as usize;
            weight[v] += area;
            for j in 0..K {
                sum[v][j][0] += area * grads[j][0];
                sum[v][j][1] += area * grads[j][1];
            }
        }
    }
    for (s, &w) in sum.iter_mut().zip(&weight) {
        if w > 0.0 {
            for g in s.iter_mut() {
                g[0] /= w;
                g[1] /= w;
            }
        }
    }
    sum
}

/// The `l2-projection` method: the edge fit's gradient (the lumped projection where no
/// patch determines the fit), then the lumped projection of that gradient's P1 gradient.
fn fit_then_project(mesh: &P1Mesh<'_>, values: &[f64]) -> Derivatives {
    let scalar: Vec<[f64; 1]> = values.iter().map(|&v| [v]).collect();
    let projected: Vec<[f64; 2]> =
        project_gradients(mesh, &scalar).into_iter().map(|g| g[0]).collect();
    let gradient = recovered_gradients::<2, 5>(mesh.points, &mesh.adjacency, values, &projected);
    let second = project_gradients(mesh, &gradient);
    let hessian =
        second.into_iter().map(|[gx, gy]| Sym2::new(gx[0], 0.5 * (gx[1] + gy[0]), gy[1])).collect();
    Derivatives { gradient, hessian }
}

/// Fewest other vertices a fit takes.
const MIN_PATCH: usize = 6;

/// Columns of the fit: gx, gy, hxx, hxy, hyy.
const COLS: usize = 5;

/// Smallest ratio of the triangular factor's diagonal entries for a determined fit.
const DETERMINED: f64 = 1e-7;

fn quadratic_fit(mesh: &P1Mesh<'_>, values: &[f64]) -> Result<Derivatives, RecoveryError> {
    let n = mesh.points.len();
    let fits: Vec<Result<([f64; 2], Sym2), RecoveryError>> = (0..n)
        .into_par_iter()
        .map_init(
            || Patch::new(n),
            |patch, v| {
                if !mesh.is_used(v) {
                    return Ok(([0.0; 2], Sym2::new(0.0, 0.0, 0.0)));
                }
                fit_at(mesh, values, v, patch)
            },
        )
        .collect();
    let mut gradient = Vec::with_capacity(n);
    let mut hessian = Vec::with_capacity(n);
    for f in fits {
        let (g, h) = f?;
        gradient.push(g);
        hessian.push(h);
    }
    Ok(Derivatives { gradient, hessian })
}

fn fit_at(
    mesh: &P1Mesh<'_>,
    values: &[f64],
    v: usize,
    patch: &mut Patch,
) -> Result<([f64; 2], Sym2), RecoveryError> {
    patch
        .grow(&mesh.adjacency, v, MIN_PATCH, |p| solve_fit(mesh.points, values, v, p.others))
        .map_err(|patch| RecoveryError::Undetermined { vertex: v, patch })
}

/// The least-squares quadratic at `v` through the values at `others`, `None` when it is
/// not determined.
fn solve_fit(
    points: &[Point2],
    values: &[f64],
    v: usize,
    others: &[u32],
) -> Option<([f64; 2], Sym2)> {
    let p = points[v];
    let scale = others
        .iter()
        .map(|&u| {
            let q = points[u as usize];
            (q[0] - p[0]).hypot(q[1] - p[1])
        })
        .fold(0.0, f64::max);
    if scale.is_nan() || scale <= 0.0 {
        return None;
    }
    let m = others.len();
    let mut a = vec![[0.0; COLS]; m];
    let mut b = vec![0.0; m];
    for (i, &u) in others.iter().enumerate() {
        let q = points[u as usize];
        let (x, y) = ((q[0] - p[0]) / scale, (q[1] - p[1]) / scale);
        a[i] = [x, y, 0.5 * x * x, x * y, 0.5 * y * y];
        b[i] = values[u as usize] - values[v];
    }
    let c = least_squares::<COLS>(&mut a, &mut b, DETERMINED)?;
    let s2 = scale * scale;
    Some(([c[0] / scale, c[1] / scale], Sym2::new(c[2] / s2, c[3] / s2, c[4] / s2)))
}

#[cfg(test)]
mod tests;
