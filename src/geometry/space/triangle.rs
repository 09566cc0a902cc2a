//! The closest point of a triangle in space to a query point, with the feature (vertex,
//! edge, face interior) it lies on: the kernel every 3D distance goes through, the
//! surface index and its brute-force twin alike, so that equal inputs give bit-identical
//! distances and ties can be broken the same way everywhere.
//!
//! Method (hand-written: parry3d's `Triangle` projection and Ericson's "closest point on
//! triangle" decide the Voronoi region from products of dot products, whose cancellation
//! loses every digit for a point 10^8 away from a 10^-9 triangle; this kernel does not):
//! - The normal `n` is the cross product of the two edges at the largest angle (the two
//!   shorter edges), the best conditioned of the three; it is oriented as
//!   `(b − a) × (c − a)`.
//! - Edge functions `w_k = (n × e_k) · (p − v_k)` (one dot product each with the vectors
//!   `n × e_k` stored) say on which side of each edge line the point projects. All three
//!   non-negative: the foot is in the face, at the signed height `n·(p − a) / |n|`.
//!   Otherwise the closest point lies on an edge whose `w_k` is negative (for a convex
//!   polygon the nearest boundary point is on an edge that separates the projection from
//!   it, and at a vertex at least one of its two edges does), so only those edges are
//!   projected on.
//! - Each edge is projected on in one canonical direction (from its lexicographically
//!   smaller end), and a projection snapped to an end is that vertex exactly: two
//!   triangles that share an edge or a vertex give bit-identical distances to it.
//! - A degenerate triangle (zero area, repeated vertices, or a cap whose largest angle
//!   has a sine below 2^-26, where a face height computed from the rounded normal could
//!   be worse than the distance to the nearest edge) is its three edges.
//! - The squared distance returned is never below the squared distance to the
//!   triangle's bounding box (computed in the same way as a box of the index): the true
//!   distance never is, and this is what lets the index prune a box without ever losing
//!   a triangle the brute-force scan would pick (see `surface_index`).
//!
//! Accuracy (checked against an independent minimisation in the tests): for a triangle
//! whose largest angle has sine `s`, the distance is within a few `ε (|p − a| + L) / s`
//! of the exact one (`L` the longest edge, `ε` the machine epsilon); a face or edge
//! decision can only be wrong for a point within that margin of the region's border,
//! where both candidates are that close. Cost: 3 dot products and a comparison for a
//! point above the face, one or two segment projections otherwise.

/// A point of space.
pub(crate) type Point3 = [f64; 3];

/// Which part of a triangle a closest point lies on. Vertices and edges are numbered in
/// the triangle's own order: edge `k` runs from vertex `k` to vertex `(k + 1) % 3`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Feature {
    /// A corner of the triangle (0, 1 or 2).
    Vertex(u8),
    /// The inside of an edge (0, 1 or 2).
    Edge(u8),
    /// The inside of the face.
    Face,
}

/// Where a point projects on a triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TriangleProjection {
    /// Squared distance from the point to the triangle (see the module doc).
    pub(crate) distance_squared: f64,
    /// The closest point of the triangle.
    pub(crate) foot: Point3,
    /// The part of the triangle the closest point lies on.
    pub(crate) feature: Feature,
}

/// A triangle with what a projection needs stored once.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TriangleGeom {
    /// Corners in the given order.
    v: [Point3; 3],
    /// Normal (oriented as `(v1 − v0) × (v2 − v0)`, not unit); zero when degenerate.
    n: Point3,
    /// `1 / |n|²`, 0 when degenerate.
    inv_n2: f64,
    /// `n × (v[k+1] − v[k])`: points into the triangle across edge `k`.
    m: [Point3; 3],
    /// Edge `k` is projected on from this local vertex (the lexicographically smaller end).
    edge_start: [u8; 3],
    /// `1 / |e_k|²`, 0 for a zero-length edge (which then behaves as a point).
    edge_inv_len2: [f64; 3],
    /// Bounding box.
    lo: Point3,
    hi: Point3,
}

#[inline]
fn sub(a: Point3, b: Point3) -> Point3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline]
fn dot(a: Point3, b: Point3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline]
fn cross(a: Point3, b: Point3) -> Point3 {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// Squared distance from `p` to the box `[lo, hi]`, as every box test of this module
/// computes it: per axis `max(lo − p, p − hi, 0)`, squares summed x, y, z. Rounding is
/// monotone, so a box inside another is never computed nearer than it.
#[inline]
pub(crate) fn box_distance_squared(lo: Point3, hi: Point3, p: Point3) -> f64 {
    let gx = gap(lo[0], hi[0], p[0]);
    let gy = gap(lo[1], hi[1], p[1]);
    let gz = gap(lo[2], hi[2], p[2]);
    gx * gx + gy * gy + gz * gz
}

/// `max(lo − p, p − hi, 0)`: how far `p` lies outside `[lo, hi]` along one axis.
/// Written with comparisons rather than `f64::max` (whose NaN rule costs extra
/// instructions and keeps loops over several boxes from vectorising); equal to
/// `(lo - p).max(p - hi).max(0.0)` whenever `p` is finite or `lo`, `hi` are (a NaN `p`
/// gives 0 both ways), which covers every use: the index only searches finite points,
/// and a triangle's box is finite.
#[inline(always)]
pub(crate) fn gap(lo: f64, hi: f64, p: f64) -> f64 {
    let (a, b) = (lo - p, p - hi);
    let g = if a > b { a } else { b };
    if g > 0.0 {
        g
    } else {
        0.0
    }
}

/// Whether `a` comes before `b` in the lexicographic total order of coordinates.
fn lex_less(a: Point3, b: Point3) -> bool {
    a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])).then(a[2].total_cmp(&b[2])).is_lt()
}

/// Below this sine of the largest angle a triangle is taken as its three edges (2^-26,
/// about the square root of ε: the face height's error ε/s then equals the edge
/// answer's error s).
const MIN_SINE: f64 = 1.0 / 67_108_864.0;

impl TriangleGeom {
    /// The triangle `(a, b, c)`. Coordinates are taken to be finite (the index checks).
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN must count as flat.
    pub(crate) fn new(a: Point3, b: Point3, c: Point3) -> TriangleGeom {
        let v = [a, b, c];
        let e = [sub(b, a), sub(c, b), sub(a, c)];
        let len2 = [dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])];
        // The largest angle is opposite the longest edge; its two edges are the others.
        let longest = if len2[0] >= len2[1] && len2[0] >= len2[2] {
            0
        } else if len2[1] >= len2[2] {
            1
        } else {
            2
        };
        // At vertex k = longest + 2 the edges are e[k] (to k+1) and -e[k+2] (to k+2).
        let k = (longest + 2) % 3;
        let n = cross(e[k], sub(v[(k + 2) % 3], v[k]));
        let n2 = dot(n, n);
        let short2 = len2[(longest + 1) % 3] * len2[(longest + 2) % 3];
        let flat = !(n2 > MIN_SINE * MIN_SINE * short2) || !n2.is_finite();
        let (n, inv_n2) = if flat { ([0.0; 3], 0.0) } else { (n, 1.0 / n2) };
        let m = [cross(n, e[0]), cross(n, e[1]), cross(n, e[2])];
        let mut edge_start = [0u8; 3];
        let mut edge_inv_len2 = [0.0; 3];
        for k in 0..3 {
            let (s, t) = (k, (k + 1) % 3);
            edge_start[k] = if lex_less(v[t], v[s]) { t as u8 } else { s as u8 };
            edge_inv_len2[k] =
                if len2[k] > 0.0 && len2[k].is_finite() { 1.0 / len2[k] } else { 0.0 };
        }
        let mut lo = a;
        let mut hi = a;
        for p in [b, c] {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        TriangleGeom { v, n, inv_n2, m, edge_start, edge_inv_len2, lo, hi }
    }

    /// The corners.
    pub(crate) fn vertices(&self) -> [Point3; 3] {
        self.v
    }

    /// The bounding box `(lo, hi)`.
    pub(crate) fn bounds(&self) -> (Point3, Point3) {
        (self.lo, self.hi)
    }

    /// Whether the triangle is taken as its three edges (see the module doc).
    pub(crate) fn is_degenerate(&self) -> bool {
        self.inv_n2 == 0.0
    }

    /// The unit normal, oriented as `(v1 − v0) × (v2 − v0)`; `None` when degenerate.
    pub(crate) fn unit_normal(&self) -> Option<Point3> {
        if self.is_degenerate() {
            return None;
        }
        let s = self.inv_n2.sqrt();
        Some([self.n[0] * s, self.n[1] * s, self.n[2] * s])
    }

    /// Projects `p` on the triangle (see the module doc).
    #[inline]
    pub(crate) fn project(&self, p: Point3) -> TriangleProjection {
        self.project_above(p, box_distance_squared(self.lo, self.hi, p))
    }

    /// [`project`](Self::project) given `floor`, the squared distance from `p` to the
    /// triangle's box as [`box_distance_squared`] computes it (the surface index has it
    /// already): the same result bit for bit when `floor` is that value.
    #[inline]
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN must count as outside.
    pub(crate) fn project_above(&self, p: Point3, floor: f64) -> TriangleProjection {
        let mut best = if self.inv_n2 > 0.0 {
            let w = [
                dot(self.m[0], sub(p, self.v[0])),
                dot(self.m[1], sub(p, self.v[1])),
                dot(self.m[2], sub(p, self.v[2])),
            ];
            if w[0] >= 0.0 && w[1] >= 0.0 && w[2] >= 0.0 {
                let h = dot(self.n, sub(p, self.v[0]));
                let s = h * self.inv_n2;
                let foot = [p[0] - s * self.n[0], p[1] - s * self.n[1], p[2] - s * self.n[2]];
                TriangleProjection { distance_squared: h * s, foot, feature: Feature::Face }
            } else {
                // `!(w >= 0)` also takes NaN (a non-finite point): every edge is then tried.
                let mut best: Option<TriangleProjection> = None;
                for (k, wk) in w.iter().enumerate() {
                    if !(*wk >= 0.0) {
                        let c = self.project_on_edge(k, p);
                        if best.map_or(true, |b| c.distance_squared < b.distance_squared) {
                            best = Some(c);
                        }
                    }
                }
                best.unwrap_or_else(|| self.project_on_edges(p))
            }
        } else {
            self.project_on_edges(p)
        };
        if floor > best.distance_squared {
            best.distance_squared = floor;
        }
        best
    }

    /// The nearest of the three edges (the first on ties).
    fn project_on_edges(&self, p: Point3) -> TriangleProjection {
        let mut best = self.project_on_edge(0, p);
        for k in 1..3 {
            let c = self.project_on_edge(k, p);
            if c.distance_squared < best.distance_squared {
                best = c;
            }
        }
        best
    }

    /// Projects `p` on edge `k`, walked from its canonical start.
    #[inline]
    #[allow(clippy::neg_cmp_op_on_partial_ord)] // NaN must snap to the start.
    fn project_on_edge(&self, k: usize, p: Point3) -> TriangleProjection {
        let s = self.edge_start[k] as usize;
        let e = if s == k { (k + 1) % 3 } else { k };
        let (a, b) = (self.v[s], self.v[e]);
        let d = sub(b, a);
        let t = dot(sub(p, a), d) * self.edge_inv_len2[k];
        // `!(t > 0)` also catches NaN.
        let (foot, feature) = if !(t > 0.0) {
            (a, Feature::Vertex(s as u8))
        } else if t >= 1.0 {
            (b, Feature::Vertex(e as u8))
        } else {
            ([a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]], Feature::Edge(k as u8))
        };
        let q = sub(p, foot);
        TriangleProjection { distance_squared: dot(q, q), foot, feature }
    }
}

/// Exact orientation of `d` against the plane through `a`, `b`, `c` (Shewchuk's adaptive
/// predicate): positive when `d` lies on the side `(b − a) × (c − a)` points to, negative
/// on the other, zero only when the four points are coplanar.
#[inline]
pub(crate) fn orient3d(a: Point3, b: Point3, c: Point3, d: Point3) -> f64 {
    let co = |p: Point3| robust::Coord3D { x: p[0], y: p[1], z: p[2] };
    // `robust` counts positive below the plane (where abc looks clockwise).
    -robust::orient3d(co(a), co(b), co(c), co(d))
}
