//! Plane geometry with tolerances: vector arithmetic on `[f64; 2]`, segment crossing,
//! overlap of convex polygons (separating axes), ray casting, point–segment distance, and
//! an index of boxes. The boundary-layer skin builds with it and [`crate::validity`]
//! checks mixed meshes with it.
//!
//! Tolerances are relative to the lengths involved (`EPS` times a length): these tests
//! decide whether shapes come *too close*, not on which side of a line a point lies, so
//! they need no exact predicate; the one sign test that decides validity, a corner's
//! orientation, is the exact [`super::segment::orient`] ([`crate::validity`]).

use super::box_tree::BoxTree;

/// A point of the plane.
pub(crate) type P = [f64; 2];

/// Relative tolerance of the predicates.
pub(crate) const EPS: f64 = 1e-10;

#[inline]
pub(crate) fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1]]
}
#[inline]
pub(crate) fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1]]
}
#[inline]
pub(crate) fn scale(a: P, s: f64) -> P {
    [a[0] * s, a[1] * s]
}
#[inline]
pub(crate) fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
#[inline]
pub(crate) fn cross(a: P, b: P) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
#[inline]
pub(crate) fn norm(a: P) -> f64 {
    a[0].hypot(a[1])
}
#[inline]
pub(crate) fn unit(a: P) -> P {
    let l = norm(a);
    if l > 0.0 {
        scale(a, 1.0 / l)
    } else {
        a
    }
}
/// The left normal of a direction (the domain side of a boundary edge).
#[inline]
pub(crate) fn left(a: P) -> P {
    [-a[1], a[0]]
}
/// `a` rotated by `angle` radians counter-clockwise.
#[inline]
pub(crate) fn rotate(a: P, angle: f64) -> P {
    let (s, c) = angle.sin_cos();
    [c * a[0] - s * a[1], s * a[0] + c * a[1]]
}
/// Twice the signed area of `abc` (positive counter-clockwise).
#[inline]
pub(crate) fn orient(a: P, b: P, c: P) -> f64 {
    cross(sub(b, a), sub(c, a))
}
/// The signed angle from direction `a` to direction `b`, in (−π, π].
#[inline]
pub(crate) fn turn(a: P, b: P) -> f64 {
    cross(a, b).atan2(dot(a, b))
}

/// Distance from `p` to segment `ab`.
pub(crate) fn segment_distance(p: P, a: P, b: P) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    let t = if l2 > 0.0 { (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    norm(sub(p, add(a, scale(ab, t))))
}

/// Whether segments `pq` and `rs` share a point (crossing, touching or overlapping), with
/// a tolerance relative to their lengths. Callers skip pairs that share an end vertex.
pub(crate) fn segments_meet(p: P, q: P, r: P, s: P) -> bool {
    let tol = EPS * (norm(sub(q, p)) + norm(sub(s, r))).powi(2);
    let d1 = orient(p, q, r);
    let d2 = orient(p, q, s);
    let d3 = orient(r, s, p);
    let d4 = orient(r, s, q);
    if ((d1 > tol && d2 < -tol) || (d1 < -tol && d2 > tol))
        && ((d3 > tol && d4 < -tol) || (d3 < -tol && d4 > tol))
    {
        return true;
    }
    let len = norm(sub(q, p)).max(norm(sub(s, r)));
    let near = EPS.sqrt() * len;
    segment_distance(r, p, q) <= near
        || segment_distance(s, p, q) <= near
        || segment_distance(p, r, s) <= near
        || segment_distance(q, r, s) <= near
}

/// Distance along the ray `o + t d` (unit `d`, `t > 0`) to segment `ab`, if it hits it.
pub(crate) fn ray_hit(o: P, d: P, a: P, b: P) -> Option<f64> {
    let e = sub(b, a);
    let den = cross(d, e);
    if den.abs() < 1e-300 {
        return None;
    }
    let w = sub(a, o);
    let t = cross(w, e) / den;
    let u = cross(w, d) / den;
    (t > 0.0 && (-EPS..=1.0 + EPS).contains(&u)).then_some(t)
}

/// Whether two convex counter-clockwise polygons overlap: no edge normal of either
/// separates them by `margin` or more. A positive margin also counts polygons closer
/// than it as overlapping; a small negative one lets polygons that touch (share an edge
/// or a corner) count as apart.
pub(crate) fn convex_overlap(a: &[P], b: &[P], margin: f64) -> bool {
    for (poly, other) in [(a, b), (b, a)] {
        for i in 0..poly.len() {
            let e = sub(poly[(i + 1) % poly.len()], poly[i]);
            let out = scale(unit(left(e)), -1.0);
            let gap =
                other.iter().map(|&q| dot(sub(q, poly[i]), out)).fold(f64::INFINITY, f64::min);
            if gap >= margin {
                return false;
            }
        }
    }
    true
}

/// Whether `p` lies strictly inside the counter-clockwise convex polygon, by more than
/// `tol`.
pub(crate) fn inside_convex(p: P, poly: &[P], tol: f64) -> bool {
    (0..poly.len()).all(|i| {
        let a = poly[i];
        let b = poly[(i + 1) % poly.len()];
        orient(a, b, p) > tol * norm(sub(b, a))
    })
}

/// Axis-aligned box.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Bbox {
    /// Lower corner.
    pub lo: P,
    /// Upper corner.
    pub hi: P,
}

impl Bbox {
    /// The box of points.
    pub(crate) fn of(points: &[P]) -> Bbox {
        let mut b = Bbox { lo: [f64::INFINITY; 2], hi: [f64::NEG_INFINITY; 2] };
        for p in points {
            b.lo = [b.lo[0].min(p[0]), b.lo[1].min(p[1])];
            b.hi = [b.hi[0].max(p[0]), b.hi[1].max(p[1])];
        }
        b
    }
    /// The box grown by `d` on every side.
    pub(crate) fn grown(self, d: f64) -> Bbox {
        Bbox { lo: [self.lo[0] - d, self.lo[1] - d], hi: [self.hi[0] + d, self.hi[1] + d] }
    }
    /// The smallest box holding both.
    pub(crate) fn union(self, o: Bbox) -> Bbox {
        Bbox {
            lo: [self.lo[0].min(o.lo[0]), self.lo[1].min(o.lo[1])],
            hi: [self.hi[0].max(o.hi[0]), self.hi[1].max(o.hi[1])],
        }
    }
}

/// Items (by index) filed by their boxes in a quadtree whose leaves follow the grading
/// ([`super::box_tree`]): a skin along an airfoil 50 chords inside a far field
/// does not fall into a few buckets, as in a uniform grid. A query lists every item whose
/// (closed) box meets the query box, and possibly others near it, each once, in
/// increasing index order (deterministic). Callers whose tests reach past a box (a
/// margin, a tolerance) grow the boxes they file by that reach.
pub(crate) struct BoxIndex {
    tree: BoxTree,
}

impl BoxIndex {
    /// The index of `boxes`.
    pub(crate) fn new(boxes: &[Bbox]) -> BoxIndex {
        let pairs: Vec<(P, P)> = boxes.iter().map(|b| (b.lo, b.hi)).collect();
        BoxIndex { tree: BoxTree::new(&pairs) }
    }

    /// The items whose box may meet `b`, each once, ascending.
    pub(crate) fn query(&self, b: Bbox) -> Vec<u32> {
        let mut out = Vec::new();
        self.tree.query(b.lo, b.hi, &mut out);
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_and_crossing_agree_with_hand_cases() {
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let shifted = |dx: f64| sq.map(|p| [p[0] + dx, p[1]]);
        assert!(convex_overlap(&sq, &shifted(0.5), 0.0));
        assert!(!convex_overlap(&sq, &shifted(1.0), -1e-12), "sharing an edge is no overlap");
        assert!(convex_overlap(&sq, &shifted(1.05), 0.1), "closer than the margin");
        assert!(!convex_overlap(&sq, &shifted(1.5), 0.1));
        let tri = [[0.5, 0.5], [3.0, 0.5], [0.5, 3.0]];
        assert!(convex_overlap(&sq, &tri, 0.0));
        assert!(segments_meet([0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0]));
        assert!(!segments_meet([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]));
        assert!(segments_meet([0.0, 0.0], [1.0, 0.0], [0.5, 0.0], [0.5, 1.0]), "T junction");
        assert_eq!(ray_hit([0.0, 0.0], [0.0, 1.0], [-1.0, 2.0], [1.0, 2.0]), Some(2.0));
        assert_eq!(ray_hit([0.0, 0.0], [0.0, 1.0], [-1.0, -2.0], [1.0, -2.0]), None);
        assert!(inside_convex([0.5, 0.5], &sq, 0.0) && !inside_convex([1.5, 0.5], &sq, 0.0));
    }

    #[test]
    fn index_queries_find_what_brute_force_finds() {
        let boxes: Vec<Bbox> = (0..200)
            .map(|i| {
                let x = (i as f64 * 0.618).fract() * 10.0;
                let y = (i as f64 * 0.414).fract() * 10.0;
                Bbox { lo: [x, y], hi: [x + 0.3 + (i % 7) as f64 * 0.2, y + 0.4] }
            })
            .collect();
        let g = BoxIndex::new(&boxes);
        let q = Bbox { lo: [3.0, 3.0], hi: [5.0, 4.0] };
        let brute: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| {
                let b = boxes[i as usize];
                b.lo[0] <= q.hi[0] && q.lo[0] <= b.hi[0] && b.lo[1] <= q.hi[1] && q.lo[1] <= b.hi[1]
            })
            .collect();
        let found = g.query(q);
        assert!(brute.iter().all(|i| found.contains(i)), "{brute:?} ⊄ {found:?}");
    }
}
