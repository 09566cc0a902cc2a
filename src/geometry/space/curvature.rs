//! Principal curvatures and directions of a triangulated surface at its vertices, each
//! smooth side of a ridge on its own; and the curvature of a curve in space through
//! three points. The 3D CURVATURE_OF_BORDER sizes a surface from these.
//!
//! Estimator: a local polynomial fit of the surface as a height function over the
//! tangent plane of the vertex (an "osculating jet", Cazals & Pouget, *Estimating
//! differential quantities using polynomial fitting of osculating jets*, CAGD 22(2),
//! 2005; the estimator of CGAL's `Monge_via_jet_fitting`), then the principal
//! curvatures and directions of the fitted graph at the vertex from its first and
//! second fundamental forms. Chosen over the per-face tensor averaging of Rusinkiewicz
//! (2004) and the cotangent operators because:
//! - its error is proved: a degree-n fit on points of the surface gives the k-th
//!   derivatives to O(h^(n−k+1)) whatever the sampling, so the cubic fit used wherever
//!   the neighbourhood allows gives curvatures to O(h²) on irregular meshes too, where
//!   the tensor averaging and the discrete Laplacian are only O(h) or do not converge;
//! - the linear terms of the fit absorb an error of the first normal guess (an
//!   angle-weighted mean of the triangles' normals), and the curvature is read from the
//!   full graph formulas, so the guess does not bias the result;
//! - it is exact where the surface is exactly a graph of the fitted degree over the
//!   guessed plane: zero on a plane (heights exactly zero give coefficients exactly
//!   zero), the saddle z = x² − y² at a symmetric vertex;
//! - a neighbourhood is a set of points, so a side of a ridge is simply the points of
//!   that side.
//!
//! Ridges. The caller gives the edges not to smooth across (ridges, curves where
//! surfaces meet); edges of three or more triangles count as ridges too. The triangles
//! connected through the other edges form *patches*. A vertex gets one [`CurvatureSide`]
//! per patch among its triangles, fitted on that patch's points only: on a cube's edge
//! each face sees its own plane (zero curvature), and no dihedral angle is smeared into a
//! curvature. Vertices on a ridge are flagged ([`SurfaceCurvature::on_ridge`]) for the
//! caller to treat the ridge as a curve (see [`three_point_curvature`]).
//!
//! Neighbourhood and degree. The vertices of the patch within two rings of the vertex
//! (rings through the patch's triangles only). Points seen from the vertex more than 60°
//! off the tangent plane guess, or on its normal line, are left out: the graph would
//! fold there (a coarse sphere's antipode). Coordinates are scaled by the farthest
//! point's distance in the plane so the monomials lie in [−1, 1]. The cubic (9
//! coefficients, none constant: the fit passes through the vertex) when at least 12
//! points give a condition number under 10^4; else the quadric (5) with at least 5
//! points under 10^6; else the osculating paraboloid without linear terms (3) under
//! 10^8; else the umbilic paraboloid z = k (x² + y²) / 2 (one coefficient: an
//! octahedron's vertex, whose four neighbours lie on two lines); with no point at all, no
//! curvature ([`Fit::None`], k = 0). Least squares by nalgebra's SVD, whose singular
//! values give the condition number.
//!
//! Hand-written on nalgebra rather than with a geometry crate: no well-kept Rust crate
//! estimates curvature on a triangle mesh with ridges kept apart.
//!
//! Cost: per vertex side, O(p) to gather p points and one SVD of a p×9 matrix.

use nalgebra::{DMatrix, DVector};

use super::triangle::Point3;

/// What the fit at a vertex side could use (see the module header).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Fit {
    /// A cubic height function: curvatures to O(h²).
    Cubic,
    /// A quadric height function with linear terms: curvatures to O(h).
    Quadric,
    /// The osculating paraboloid over the plane guess (no linear terms).
    Paraboloid,
    /// The umbilic paraboloid z = k (x² + y²) / 2 over the plane guess: one curvature,
    /// both directions alike (points too few or too aligned for more).
    Umbilic,
    /// Too few or too badly placed points: no curvature (k = 0), the normal only.
    None,
}

/// The curvature of one smooth side of the surface at a vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CurvatureSide {
    /// The patch (index into the patches, numbered by their first triangle).
    pub(crate) patch: u32,
    /// The unit normal of the fitted surface, oriented as the side's triangles (as the
    /// first of them when they disagree).
    pub(crate) normal: Point3,
    /// The principal curvatures, largest in absolute value first; positive where the
    /// surface bends toward `normal` (a sphere with outward normals: −1/R).
    pub(crate) k: [f64; 2],
    /// The unit principal directions (tangent, orthogonal), in the order of `k`.
    pub(crate) directions: [Point3; 2],
    /// The fit used.
    pub(crate) fit: Fit,
}

/// Why curvatures cannot be computed: an index past the points.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum CurvatureError {
    /// A triangle (or ridge, `triangle: None`) names a vertex past the points.
    VertexOutOfRange { triangle: Option<usize>, vertex: u32, len: usize },
}

/// The curvatures of a surface at every vertex, one side per patch around it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SurfaceCurvature {
    /// CSR offsets into `sides`, one run per vertex.
    offsets: Vec<u32>,
    sides: Vec<CurvatureSide>,
    /// Whether each vertex is on a ridge edge (given, or of 3+ triangles).
    ridge: Vec<bool>,
    /// The patch of each triangle.
    patch_of: Vec<u32>,
}

impl SurfaceCurvature {
    /// The sides of vertex `v` (none for a vertex of no triangle), by ascending patch.
    pub(crate) fn sides(&self, v: usize) -> &[CurvatureSide] {
        &self.sides[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }

    /// Whether `v` lies on a ridge edge.
    pub(crate) fn on_ridge(&self, v: usize) -> bool {
        self.ridge[v]
    }

    /// The patch of triangle `t`.
    pub(crate) fn patch_of(&self, t: usize) -> u32 {
        self.patch_of[t]
    }

    /// The side of `v` on patch `patch`, if `v` has one.
    pub(crate) fn side(&self, v: usize, patch: u32) -> Option<&CurvatureSide> {
        self.sides(v).iter().find(|s| s.patch == patch)
    }
}

/// The curvature of the circle through `a`, `b`, `c` in space, κ = 2|AB × BC| / (|AB|
/// |BC| |AC|) (0 when two points coincide or the three are aligned): the 2D three-point
/// curvature of a curve, in the plane of the three points.
pub(crate) fn three_point_curvature(a: Point3, b: Point3, c: Point3) -> f64 {
    let (ab, bc, ac) = (sub(b, a), sub(c, b), sub(c, a));
    let den = norm(ab) * norm(bc) * norm(ac);
    let k = 2.0 * norm(cross(ab, bc)) / den;
    if den > 0.0 && k.is_finite() {
        k
    } else {
        0.0
    }
}

/// The principal curvatures of the surface `triangles` over `points` at each vertex,
/// smooth sides of the `ridges` apart (see the module header).
pub(crate) fn surface_curvature(
    points: &[Point3],
    triangles: &[[u32; 3]],
    ridges: &[[u32; 2]],
) -> Result<SurfaceCurvature, CurvatureError> {
    let n = points.len();
    for (t, tri) in triangles.iter().enumerate() {
        if let Some(&v) = tri.iter().find(|&&v| v as usize >= n) {
            return Err(CurvatureError::VertexOutOfRange { triangle: Some(t), vertex: v, len: n });
        }
    }
    if let Some(&v) = ridges.iter().flatten().find(|&&v| v as usize >= n) {
        return Err(CurvatureError::VertexOutOfRange { triangle: None, vertex: v, len: n });
    }
    let (patch_of, ridge) = patches(n, triangles, ridges);
    // Vertex → triangles, CSR, triangles ascending.
    let mut start = vec![0u32; n + 1];
    for tri in triangles {
        for &v in tri {
            start[v as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut incident = vec![0u32; start[n] as usize];
    for (t, tri) in triangles.iter().enumerate() {
        for &v in tri {
            incident[fill[v as usize] as usize] = t as u32;
            fill[v as usize] += 1;
        }
    }
    let star = Star { points, triangles, patch_of: &patch_of, start: &start, incident: &incident };
    let mut offsets = Vec::with_capacity(n + 1);
    offsets.push(0u32);
    let mut sides = Vec::new();
    for v in 0..n {
        let mut own: Vec<u32> = star.around(v).map(|t| patch_of[t as usize]).collect();
        own.sort_unstable();
        own.dedup();
        for patch in own {
            if let Some(side) = star.side(v, patch) {
                sides.push(side);
            }
        }
        offsets.push(sides.len() as u32);
    }
    Ok(SurfaceCurvature { offsets, sides, ridge, patch_of })
}

/// The patch of each triangle (union-find across manifold edges that are no ridge,
/// numbered by first triangle) and whether each vertex is on a ridge edge.
fn patches(n: usize, triangles: &[[u32; 3]], ridges: &[[u32; 2]]) -> (Vec<u32>, Vec<bool>) {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    let mut ridge_keys: Vec<(u32, u32)> = ridges.iter().map(|e| key(e[0], e[1])).collect();
    ridge_keys.sort_unstable();
    let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (tri[i], tri[(i + 1) % 3]);
            if a != b {
                let (lo, hi) = key(a, b);
                edges.push((lo, hi, t as u32));
            }
        }
    }
    edges.sort_unstable();
    let mut parent: Vec<u32> = (0..triangles.len() as u32).collect();
    let mut on_ridge = vec![false; n];
    for &(a, b) in &ridge_keys {
        on_ridge[a as usize] = true;
        on_ridge[b as usize] = true;
    }
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && (edges[j].0, edges[j].1) == (edges[i].0, edges[i].1) {
            j += 1;
        }
        let (a, b) = (edges[i].0, edges[i].1);
        if j - i > 2 {
            on_ridge[a as usize] = true;
            on_ridge[b as usize] = true;
        } else if j - i == 2 && ridge_keys.binary_search(&(a, b)).is_err() {
            let (x, y) = (find(&mut parent, edges[i].2), find(&mut parent, edges[i + 1].2));
            parent[x.max(y) as usize] = x.min(y);
        }
        i = j;
    }
    // Roots are the smallest triangle of each set: number them in triangle order.
    let mut label = vec![u32::MAX; triangles.len()];
    let mut next = 0;
    let mut patch_of = Vec::with_capacity(triangles.len());
    for t in 0..triangles.len() as u32 {
        let r = find(&mut parent, t) as usize;
        if label[r] == u32::MAX {
            label[r] = next;
            next += 1;
        }
        patch_of.push(label[r]);
    }
    (patch_of, on_ridge)
}

/// Union-find root with path halving.
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

/// The surface with its vertex → triangle incidence and patches.
struct Star<'a> {
    points: &'a [Point3],
    triangles: &'a [[u32; 3]],
    patch_of: &'a [u32],
    start: &'a [u32],
    incident: &'a [u32],
}

impl Star<'_> {
    fn around(&self, v: usize) -> impl Iterator<Item = u32> + '_ {
        self.incident[self.start[v] as usize..self.start[v + 1] as usize].iter().copied()
    }

    /// The curvature of the side of `v` on `patch`; `None` when its triangles have no
    /// normal (all degenerate) or `v` is not finite.
    fn side(&self, v: usize, patch: u32) -> Option<CurvatureSide> {
        let p = self.points[v];
        if !p.iter().all(|x| x.is_finite()) {
            return None;
        }
        let normal = self.normal_guess(v, patch)?;
        // Two rings through the patch's triangles.
        let mut ring: Vec<u32> = Vec::new();
        for t in self.around(v).filter(|&t| self.patch_of[t as usize] == patch) {
            ring.extend(self.triangles[t as usize]);
        }
        ring.sort_unstable();
        ring.dedup();
        let first = ring.clone();
        for &u in &first {
            for t in self.around(u as usize).filter(|&t| self.patch_of[t as usize] == patch) {
                ring.extend(self.triangles[t as usize]);
            }
        }
        ring.sort_unstable();
        ring.dedup();
        let neighbours: Vec<Point3> = ring
            .iter()
            .filter(|&&u| u as usize != v)
            .map(|&u| self.points[u as usize])
            .filter(|q| q.iter().all(|x| x.is_finite()))
            .collect();
        Some(fit_side(p, normal, &neighbours, patch))
    }

    /// The angle-weighted mean of the unit normals of the side's triangles at `v`
    /// (Thürmer & Wüthrich's weights: independent of how the star is split into
    /// triangles), the triangles oriented alike through the edges they share at `v`, as
    /// the first where the file orients them otherwise.
    fn normal_guess(&self, v: usize, patch: u32) -> Option<Point3> {
        // (next, previous) vertex of each triangle of the side, seen from v.
        let mut fan: Vec<(u32, u32, u32)> = Vec::new();
        for t in self.around(v).filter(|&t| self.patch_of[t as usize] == patch) {
            let tri = self.triangles[t as usize];
            let k = tri.iter().position(|&u| u as usize == v)?;
            fan.push((t, tri[(k + 1) % 3], tri[(k + 2) % 3]));
        }
        // Orientation of each triangle: +1 as the first, −1 flipped, 0 not reached yet.
        let mut sign = vec![0.0f64; fan.len()];
        let mut queue = vec![0usize];
        if !fan.is_empty() {
            sign[0] = 1.0;
        }
        while let Some(i) = queue.pop() {
            let (_, a, b) = fan[i];
            for j in 0..fan.len() {
                let (_, c, d) = fan[j];
                if sign[j] != 0.0 {
                    continue;
                }
                // Alike: a shared vertex is next in one and previous in the other.
                if a == d || b == c {
                    sign[j] = sign[i];
                } else if a == c || b == d {
                    sign[j] = -sign[i];
                } else {
                    continue;
                }
                queue.push(j);
            }
        }
        let a = self.points[v];
        let mut sum = [0.0; 3];
        let mut first: Option<Point3> = None;
        for (&(_, b, c), &s) in fan.iter().zip(&sign) {
            let (ab, ac) = (sub(self.points[b as usize], a), sub(self.points[c as usize], a));
            let Some(n) = unit(cross(ab, ac)) else { continue };
            let s = if s < 0.0 { -1.0 } else { 1.0 };
            let cosine = dot(ab, ac) / (norm(ab) * norm(ac));
            let w = s * cosine.clamp(-1.0, 1.0).acos();
            first.get_or_insert([s * n[0], s * n[1], s * n[2]]);
            sum = [sum[0] + w * n[0], sum[1] + w * n[1], sum[2] + w * n[2]];
        }
        unit(sum).or(first)
    }
}

/// Fits the height function at `p` over the plane of `guess` to `neighbours` and reads
/// the principal curvatures (see the module header).
fn fit_side(p: Point3, guess: Point3, neighbours: &[Point3], patch: u32) -> CurvatureSide {
    let (e1, e2) = tangent_basis(guess);
    let mut local: Vec<[f64; 3]> = Vec::with_capacity(neighbours.len());
    for &q in neighbours {
        let d = sub(q, p);
        let (x, y, z) = (dot(d, e1), dot(d, e2), dot(d, guess));
        let r = x.hypot(y);
        // Within 60° of the plane (|z| <= √3 r), off the normal line.
        if r > 0.0 && z.abs() <= 3f64.sqrt() * r {
            local.push([x, y, z]);
        }
    }
    let none =
        CurvatureSide { patch, normal: guess, k: [0.0, 0.0], directions: [e1, e2], fit: Fit::None };
    let scale = local.iter().map(|l| l[0].hypot(l[1])).fold(0.0, f64::max);
    if scale == 0.0 || !scale.is_finite() {
        return none;
    }
    for l in &mut local {
        *l = [l[0] / scale, l[1] / scale, l[2] / scale];
    }
    let attempts = [
        (Fit::Cubic, 12, 1e4),
        (Fit::Quadric, 5, 1e6),
        (Fit::Paraboloid, 3, 1e8),
        (Fit::Umbilic, 1, f64::INFINITY),
    ];
    for (fit, min_points, max_condition) in attempts {
        if local.len() < min_points {
            continue;
        }
        let Some(c) = least_squares(&local, fit, max_condition) else { continue };
        // Derivatives at the vertex, back in the unscaled coordinates.
        let (fx, fy) = (c[0], c[1]);
        let (fxx, fxy, fyy) = (2.0 * c[2] / scale, c[3] / scale, 2.0 * c[4] / scale);
        if let Some((normal, k, directions)) = monge(e1, e2, guess, [fx, fy, fxx, fxy, fyy]) {
            return CurvatureSide { patch, normal, k, directions, fit };
        }
    }
    none
}

/// The coefficients [a_x, a_y, a_xx, a_xy, a_yy, (cubic ones)] of the least-squares fit
/// z = a_x x + a_y y + a_xx x² + a_xy xy + a_yy y² (+ x³, x²y, xy², y³) to `local`, the
/// linear ones zero for the paraboloids, a_xx = a_yy and a_xy = 0 for the umbilic one;
/// `None` when the condition number exceeds `max_condition` or the solve fails.
fn least_squares(local: &[[f64; 3]], fit: Fit, max_condition: f64) -> Option<[f64; 5]> {
    if fit == Fit::Umbilic {
        let (num, den) = local.iter().fold((0.0, 0.0), |(n, d), l| {
            let r2 = l[0] * l[0] + l[1] * l[1];
            (n + l[2] * r2, d + r2 * r2)
        });
        let a = num / den;
        return (den > 0.0 && a.is_finite()).then_some([0.0, 0.0, a, 0.0, a]);
    }
    let monomials = |x: f64, y: f64| -> [f64; 9] {
        [x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y]
    };
    let (first, count) = match fit {
        Fit::Cubic => (0, 9),
        Fit::Quadric => (0, 5),
        Fit::Paraboloid => (2, 3),
        Fit::Umbilic | Fit::None => return None,
    };
    let a =
        DMatrix::from_fn(local.len(), count, |i, j| monomials(local[i][0], local[i][1])[first + j]);
    let b = DVector::from_fn(local.len(), |i, _| local[i][2]);
    let svd = a.svd(true, true);
    let (smax, smin) = (svd.singular_values.max(), svd.singular_values.min());
    if !(smin > 0.0 && smax / smin <= max_condition) {
        return None;
    }
    let x = svd.solve(&b, 0.0).ok()?;
    let mut out = [0.0; 5];
    for j in 0..count.min(5 - first) {
        out[first + j] = x[j];
    }
    out.iter().all(|c| c.is_finite()).then_some(out)
}

/// The unit normal, principal curvatures (largest magnitude first) and directions at the
/// origin of the graph z = f(x, y) over the frame (e1, e2, n), from its derivatives
/// [f_x, f_y, f_xx, f_xy, f_yy]: the eigenpairs of the second fundamental form relative
/// to the first (II v = k I v), solved through the Cholesky factor of I.
#[allow(clippy::type_complexity)]
fn monge(
    e1: Point3,
    e2: Point3,
    n: Point3,
    d: [f64; 5],
) -> Option<(Point3, [f64; 2], [Point3; 2])> {
    let [fx, fy, fxx, fxy, fyy] = d;
    let w = (1.0 + fx * fx + fy * fy).sqrt();
    let (e, f, g) = (1.0 + fx * fx, fx * fy, 1.0 + fy * fy);
    let (l, m, nn) = (fxx / w, fxy / w, fyy / w);
    // I = C Cᵀ with C = [[c11, 0], [c21, c22]]; A = C⁻¹ II C⁻ᵀ.
    let c11 = e.sqrt();
    let c21 = f / c11;
    let c22 = (g - c21 * c21).sqrt();
    // C⁻¹ = [[1/c11, 0], [−c21/(c11 c22), 1/c22]].
    let (i11, i21, i22) = (1.0 / c11, -c21 / (c11 * c22), 1.0 / c22);
    // B = C⁻¹ II (2×2), A = B C⁻ᵀ.
    let b = [[i11 * l, i11 * m], [i21 * l + i22 * m, i21 * m + i22 * nn]];
    let a11 = b[0][0] * i11;
    let a12 = b[0][0] * i21 + b[0][1] * i22;
    let a22 = b[1][0] * i21 + b[1][1] * i22;
    let (values, vectors) = symmetric_eigen2(a11, a12, a22);
    let normal = unit([
        n[0] - fx * e1[0] - fy * e2[0],
        n[1] - fx * e1[1] - fy * e2[1],
        n[2] - fx * e1[2] - fy * e2[2],
    ])?;
    let direction = |y: [f64; 2]| -> Option<Point3> {
        // x = C⁻ᵀ y, then the tangent (x1, x2, f_x x1 + f_y x2) in space.
        let x2 = y[1] / c22;
        let x1 = (y[0] - c21 * x2) / c11;
        let h = fx * x1 + fy * x2;
        unit([
            x1 * e1[0] + x2 * e2[0] + h * n[0],
            x1 * e1[1] + x2 * e2[1] + h * n[1],
            x1 * e1[2] + x2 * e2[2] + h * n[2],
        ])
    };
    let (d0, d1) = (direction(vectors[0])?, direction(vectors[1])?);
    let ok = values.iter().all(|k| k.is_finite());
    ok.then_some(if values[0].abs() >= values[1].abs() {
        (normal, values, [d0, d1])
    } else {
        (normal, [values[1], values[0]], [d1, d0])
    })
}

/// Eigenvalues and unit eigenvectors of [[a, b], [b, c]] by one Jacobi rotation (exact
/// on a diagonal matrix, stable on equal eigenvalues).
fn symmetric_eigen2(a: f64, b: f64, c: f64) -> ([f64; 2], [[f64; 2]; 2]) {
    let theta = 0.5 * (2.0 * b).atan2(a - c);
    let (s, co) = theta.sin_cos();
    let l0 = a * co * co + 2.0 * b * s * co + c * s * s;
    let l1 = a * s * s - 2.0 * b * s * co + c * co * co;
    ([l0, l1], [[co, s], [-s, co]])
}

/// Two unit vectors completing unit `n` into an orthonormal right-handed frame.
pub(crate) fn tangent_basis(n: Point3) -> (Point3, Point3) {
    // Cross with the axis least aligned with n.
    let axis = if n[0].abs() <= n[1].abs() && n[0].abs() <= n[2].abs() {
        [1.0, 0.0, 0.0]
    } else if n[1].abs() <= n[2].abs() {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    };
    let e1 = unit(cross(axis, n)).unwrap_or([1.0, 0.0, 0.0]);
    (e1, cross(n, e1))
}

pub(crate) fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn norm(a: Point3) -> f64 {
    dot(a, a).sqrt()
}

pub(crate) fn unit(a: Point3) -> Option<Point3> {
    let l = norm(a);
    (l > 0.0 && l.is_finite()).then(|| [a[0] / l, a[1] / l, a[2] / l])
}
