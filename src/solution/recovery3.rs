//! Gradient and Hessian recovery of a scalar P1 field on tetrahedra: the 3D counterpart
//! of [`super::recovery`], with the same two [`Method`]s and the same errors (and the same
//! checks of the values); what does not depend on the dimension (the vertex adjacency,
//! the patches grown ring by ring, the QR solve, the round-off floor) is shared in
//! `super::patch`.
//!
//! - [`Method::L2Projection`]: the gradient of the edge fit (`super::edge_fit`: at each
//!   vertex the linear vector field closest, in least squares over its patch, to the P1
//!   gradient's component along each edge at the edge's midpoint, which is exact for a
//!   quadratic), then the lumped-mass L2 projection of that gradient's P1 gradient (each
//!   vertex takes the volume-weighted mean over its tetrahedra), symmetrised. Exact on
//!   quadratics at every vertex, interior and boundary, on any mesh: the fit returns the
//!   exact gradient everywhere (boundary vertices, whose one-sided star leaves it
//!   undetermined, take two rings), so the recovered gradient is linear, its P1 gradient
//!   the constant Hessian on every tetrahedron, and its mean the Hessian. The lumped
//!   projection of the field's own P1 gradient, which this method applied twice until
//!   then, is exact only where patches are point-symmetric (two layers inside a
//!   Freudenthal–Kuhn grid): a tetrahedron's P1 gradient of a quadratic is its gradient at
//!   no one point. It is kept where no patch within four rings determines the fit (a
//!   connected part of a few tetrahedra, or flat ones), exact there on linear fields only.
//!   Cost: a QR of about 50 × 12 per vertex (a star's edges; boundary vertices about 150
//!   × 12) and two passes over the tetrahedra. On smooth fields it converges at second
//!   order inside smooth images of a Kuhn grid, faster than first on jittered grids, and
//!   at first order at the worst vertex, boundary included (the tests measure it).
//! - [`Method::QuadraticFit`]: at each vertex the quadratic
//!   u(x) = u_v + g·d + ½ dᵀ H d (d = x − x_v, nine unknowns) fitted to the values of the
//!   vertex's patch in the least-squares sense (coordinates scaled by the patch's radius).
//!   The patch is the vertices within k edges, k = 1 first, grown a ring at a time until
//!   the fit is determined (at least ten other vertices, one more than the unknowns, and
//!   a triangular factor whose smallest diagonal is no less than 1e-4 of its largest) and
//!   well conditioned: a condition number ‖R‖‖R⁻¹‖ (Frobenius, in the patch's scaling) of
//!   at most `WELL` = 100, else the best conditioned determined patch within four
//!   rings. The conditioning matters on fields that are not quadratics: the fit passes
//!   their cubic part, O(|∇³u| r³) at a patch of radius r, to the Hessian amplified by
//!   about the condition number over r². A first ring inside a mesh measures 13 to 20 on
//!   the tests' jittered grids and is kept; a boundary vertex's is one-sided, and on a
//!   face of a jittered grid its ten neighbours determine the fit with condition numbers
//!   up to 8e4, which gave Hessians 100 times the field's (the test of convergence at
//!   every vertex); its second ring measures about 30. Growing only on the diagonal ratio
//!   (1e-2, 3e-2) did not track the conditioning: errors stayed at 35 or small meshes
//!   had no determined patch. Growing every boundary patch would need the boundary; the
//!   condition number needs nothing but the patch, and also catches a degenerate interior
//!   patch. Exact (to rounding) on quadratic fields at every vertex, interior and
//!   boundary, on any mesh, whatever patch is chosen.
//!
//! Tetrahedra of zero volume are skipped by the projection (their edges still join
//! patches). A vertex that no tetrahedron uses gets a zero gradient and Hessian, whatever
//! its value. Results are a function of the mesh and values only, whatever the thread
//! count.

use rayon::prelude::*;

use super::edge_fit::recovered_gradients;
use super::patch::{drop_roundoff, least_squares_conditioned, Adjacency, Patch};
use super::recovery::check_values;
use super::{Method, RecoveryError};
use crate::metric::Sym3;

/// A point in space.
pub type Point3 = [f64; 3];

/// Recovered first and second derivatives in space, one of each per vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivatives3 {
    /// The gradient at each vertex.
    pub gradient: Vec<[f64; 3]>,
    /// The Hessian at each vertex.
    pub hessian: Vec<Sym3>,
}

/// A P1 mesh of tetrahedra as recovery sees it: points, tetrahedra, and the vertex
/// adjacency of their edges.
#[derive(Debug, Clone)]
pub struct P1Mesh3<'a> {
    points: &'a [Point3],
    tets: Vec<[u32; 4]>,
    adjacency: Adjacency,
}

impl<'a> P1Mesh3<'a> {
    /// The mesh of `points` and tetrahedra `tets` (either orientation).
    pub fn new(points: &'a [Point3], tets: &[[u32; 4]]) -> Result<P1Mesh3<'a>, RecoveryError> {
        let n = points.len();
        if let Some(vertex) = points.iter().position(|p| !p.iter().all(|x| x.is_finite())) {
            return Err(RecoveryError::NonFiniteVertex { vertex });
        }
        let mut edges: Vec<[u32; 2]> = Vec::with_capacity(6 * tets.len());
        for (cell, t) in tets.iter().enumerate() {
            if let Some(&v) = t.iter().find(|&&v| v as usize >= n) {
                return Err(RecoveryError::CornerOutOfRange { cell, vertex: v as usize, len: n });
            }
            for i in 0..4 {
                for j in i + 1..4 {
                    let (a, b) = (t[i], t[j]);
                    if a != b {
                        edges.push([a.min(b), a.max(b)]);
                    }
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let adjacency = Adjacency::new(n, &edges);
        Ok(P1Mesh3 { points, tets: tets.to_vec(), adjacency })
    }

    /// The points.
    pub fn points(&self) -> &[Point3] {
        self.points
    }

    /// The tetrahedra.
    pub fn tets(&self) -> &[[u32; 4]] {
        &self.tets
    }

    /// The neighbours of `v` along tetrahedron edges, sorted.
    pub fn neighbours(&self, v: usize) -> &[u32] {
        self.adjacency.of(v)
    }

    /// Whether some tetrahedron uses `v`.
    pub fn is_used(&self, v: usize) -> bool {
        self.adjacency.is_used(v)
    }
}

/// The gradient and Hessian of the P1 field `values` on the tetrahedra of `mesh` by
/// `method`.
pub fn recover3(
    mesh: &P1Mesh3<'_>,
    values: &[f64],
    method: Method,
) -> Result<Derivatives3, RecoveryError> {
    check_values(values, mesh.points.len(), &mesh.adjacency)?;
    let mut d = match method {
        Method::L2Projection => fit_then_project(mesh, values),
        Method::QuadraticFit => quadratic_fit(mesh, values)?,
    };
    // The largest absolute row sum bounds the spectral radius.
    let radius = |h: &Sym3| {
        h.rows().iter().map(|r| r.iter().map(|x| x.abs()).sum::<f64>()).fold(0.0, f64::max)
    };
    drop_roundoff(mesh.points, &mesh.adjacency, values, &mut d.hessian, radius, Sym3::ZERO);
    Ok(d)
}

fn distance(a: Point3, b: Point3) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1]).hypot(a[2] - b[2])
}

fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// The volume of tetrahedron `t` and the gradient of the P1 function with corner values
/// `f` on it (`None` for a tetrahedron of zero volume): with edges eᵢ = pᵢ − p₀ and
/// differences dᵢ = fᵢ − f₀, g = (d₁ e₂×e₃ + d₂ e₃×e₁ + d₃ e₁×e₂) / (e₁·e₂×e₃).
fn p1_gradient(points: &[Point3], t: [u32; 4], f: [f64; 4]) -> Option<(f64, [f64; 3])> {
    let [p0, p1, p2, p3] = t.map(|v| points[v as usize]);
    let (e1, e2, e3) = (sub(p1, p0), sub(p2, p0), sub(p3, p0));
    let (c23, c31, c12) = (cross(e2, e3), cross(e3, e1), cross(e1, e2));
    let det = e1[0] * c23[0] + e1[1] * c23[1] + e1[2] * c23[2];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let d = [f[1] - f[0], f[2] - f[0], f[3] - f[0]];
    let g = std::array::from_fn(|k| (d[0] * c23[k] + d[1] * c31[k] + d[2] * c12[k]) / det);
    Some((det.abs() / 6.0, g))
}

/// The lumped-mass L2 projection onto P1 of the element gradients of each of the `K` P1
/// fields `fields` (vertex-major): for each vertex and field, the volume-weighted mean
/// gradient of its tetrahedra.
fn project_gradients<const K: usize>(
    mesh: &P1Mesh3<'_>,
    fields: &[[f64; K]],
) -> Vec<[[f64; 3]; K]> {
    let n = mesh.points.len();
    let mut sum = vec![[[0.0; 3]; K]; n];
    let mut weight = vec![0.0; n];
    for &t in &mesh.tets {
        let mut grads = [[0.0; 3]; K];
        let mut volume = 0.0;
        for (j, g) in grads.iter_mut().enumerate() {
            match p1_gradient(mesh.points, t, t.map(|v| fields[v as usize][j])) {
                Some((vol, gr)) => {
                    volume = vol;
                    *g = gr;
                }
                None => volume = 0.0,
            }
        }
        if volume == 0.0 {
            continue;
        }
        for v in t {
            let v = v as usize;
            weight[v] += volume;
            for (s, g) in sum[v].iter_mut().zip(&grads) {
                for k in 0..3 {
                    s[k] += volume * g[k];
                }
            }
        }
    }
    for (s, &w) in sum.iter_mut().zip(&weight) {
        if w > 0.0 {
            for g in s.iter_mut() {
                g.iter_mut().for_each(|x| *x /= w);
            }
        }
    }
    sum
}

/// The `l2-projection` method: the edge fit's gradient (the lumped projection where no
/// patch determines the fit), then the lumped projection of that gradient's P1 gradient.
fn fit_then_project(mesh: &P1Mesh3<'_>, values: &[f64]) -> Derivatives3 {
    let scalar: Vec<[f64; 1]> = values.iter().map(|&v| [v]).collect();
    let projected: Vec<[f64; 3]> =
        project_gradients(mesh, &scalar).into_iter().map(|g| g[0]).collect();
    let gradient = recovered_gradients::<3, 9>(mesh.points, &mesh.adjacency, values, &projected);
    let second = project_gradients(mesh, &gradient);
    // second[v][i][j] = ∂j (∂i u): symmetrised.
    let hessian = second
        .into_iter()
        .map(|s| Sym3 {
            xx: s[0][0],
            xy: 0.5 * (s[0][1] + s[1][0]),
            yy: s[1][1],
            xz: 0.5 * (s[0][2] + s[2][0]),
            yz: 0.5 * (s[1][2] + s[2][1]),
            zz: s[2][2],
        })
        .collect();
    Derivatives3 { gradient, hessian }
}

/// Fewest other vertices a fit takes: one more than the unknowns.
const MIN_PATCH: usize = 10;

/// Columns of the fit: gx, gy, gz, hxx, hxy, hyy, hxz, hyz, hzz.
const COLS: usize = 9;

/// Smallest ratio of the triangular factor's diagonal entries for a determined fit:
/// stricter than the plane's 1e-7, since nine unknowns on a one-sided patch are worse
/// conditioned. With 1e-7 a boundary vertex of a jittered grid kept its first ring and a
/// quadratic's Hessian came out 5e-8 wrong (the values' rounding times the conditioning);
/// with 1e-4 such patches grow a ring and every vertex is exact to 1e-9 (the tests).
const DETERMINED: f64 = 1e-4;

/// Largest condition number of a fit (in the patch's scaling) taken without trying a
/// further ring.
const WELL: f64 = 100.0;

/// Most rings tried for a fit whose condition number is at most [`WELL`].
const MAX_RINGS: usize = 4;

fn quadratic_fit(mesh: &P1Mesh3<'_>, values: &[f64]) -> Result<Derivatives3, RecoveryError> {
    let n = mesh.points.len();
    let fits: Vec<Result<([f64; 3], Sym3), RecoveryError>> = (0..n)
        .into_par_iter()
        .map_init(
            || Patch::new(n),
            |patch, v| {
                if !mesh.is_used(v) {
                    return Ok(([0.0; 3], Sym3::ZERO));
                }
                patch
                    .grow_conditioned(&mesh.adjacency, v, MIN_PATCH, MAX_RINGS, WELL, |p| {
                        solve_fit(mesh.points, values, v, p.others)
                    })
                    .map_err(|patch| RecoveryError::Undetermined { vertex: v, patch })
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
    Ok(Derivatives3 { gradient, hessian })
}

/// The patch the quadratic fit takes at vertex `v` of `mesh` (for the tests' twin);
/// `None` when no patch is determined.
#[cfg(test)]
pub(crate) fn fit_patch(mesh: &P1Mesh3<'_>, v: usize) -> Option<Vec<u32>> {
    let values = vec![0.0; mesh.points.len()];
    let mut patch = Patch::new(mesh.points.len());
    patch
        .grow_conditioned(&mesh.adjacency, v, MIN_PATCH, MAX_RINGS, WELL, |p| {
            solve_fit(mesh.points, &values, v, p.others).map(|(_, c)| (p.others.to_vec(), c))
        })
        .ok()
}

/// The row of the fit for offset `d` (already scaled): the quadratic's monomials.
fn fit_row(d: Point3) -> [f64; COLS] {
    let [x, y, z] = d;
    [x, y, z, 0.5 * x * x, x * y, 0.5 * y * y, x * z, y * z, 0.5 * z * z]
}

/// The least-squares quadratic at `v` through the values at `others` and the fit's
/// condition number in the patch's scaling, `None` when it is not determined.
fn solve_fit(
    points: &[Point3],
    values: &[f64],
    v: usize,
    others: &[u32],
) -> Option<(([f64; 3], Sym3), f64)> {
    let p = points[v];
    let scale = others.iter().map(|&u| distance(points[u as usize], p)).fold(0.0, f64::max);
    if scale.is_nan() || scale <= 0.0 {
        return None;
    }
    let mut a = Vec::with_capacity(others.len());
    let mut b = Vec::with_capacity(others.len());
    for &u in others {
        let d = sub(points[u as usize], p).map(|x| x / scale);
        a.push(fit_row(d));
        b.push(values[u as usize] - values[v]);
    }
    let (c, condition) = least_squares_conditioned::<COLS>(&mut a, &mut b, DETERMINED)?;
    let s2 = scale * scale;
    let gradient = [c[0] / scale, c[1] / scale, c[2] / scale];
    let hessian = Sym3 {
        xx: c[3] / s2,
        xy: c[4] / s2,
        yy: c[5] / s2,
        xz: c[6] / s2,
        yz: c[7] / s2,
        zz: c[8] / s2,
    };
    Some(((gradient, hessian), condition))
}

#[cfg(test)]
mod tests;
