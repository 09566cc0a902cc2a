//! Distance from a point to a segment, with the foot point and its parameter along the
//! segment (thesis 4.3.6.3, Fig. 4.4): project the point on the line spanned by the
//! segment and snap the projection to the nearer end when it falls outside.
//!
//! Cost: a handful of flops per query once the segment's direction and inverse squared
//! length are stored ([`SegmentGeom`]). Every caller that compares distances (the
//! propagation, its spatial index and their brute-force twin) goes through
//! [`SegmentGeom::project`], so that equal inputs give bit-identical distances and ties
//! can be broken the same way everywhere.

/// A point of the plane.
pub type Point2 = [f64; 2];

/// Where a point projects on a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Projection {
    /// Squared distance from the point to the foot point.
    pub(crate) distance_squared: f64,
    /// The closest point of the segment.
    pub(crate) foot: Point2,
    /// Parameter of the foot point along the segment, in `[0, 1]` (0 at the start).
    pub(crate) t: f64,
}

impl Projection {
    /// Distance from the point to the foot point.
    #[inline]
    pub(crate) fn distance(&self) -> f64 {
        self.distance_squared.sqrt()
    }
}

/// A segment with what a projection needs stored once: start, end, direction and
/// inverse squared length (0 for a degenerate segment, which then behaves as a point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SegmentGeom {
    /// Start point.
    pub(crate) a: Point2,
    /// End point.
    pub(crate) b: Point2,
    /// `b - a`.
    pub(crate) d: Point2,
    /// `1 / |b - a|²`, or 0 when `a == b`.
    pub(crate) inv_len2: f64,
}

impl SegmentGeom {
    /// The segment from `a` to `b`.
    pub(crate) fn new(a: Point2, b: Point2) -> SegmentGeom {
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let inv_len2 = if len2 > 0.0 && len2.is_finite() { 1.0 / len2 } else { 0.0 };
        SegmentGeom { a, b, d, inv_len2 }
    }

    /// Length of the segment.
    pub(crate) fn length(&self) -> f64 {
        (self.d[0] * self.d[0] + self.d[1] * self.d[1]).sqrt()
    }

    /// Projects `p` on the segment. The foot point is exactly `a` (t = 0) or `b`
    /// (t = 1) when the projection is snapped, never `a + 1·(b − a)` rounded: two
    /// segments that share an end then give bit-identical distances to it.
    #[inline]
    pub(crate) fn project(&self, p: Point2) -> Projection {
        let ap = [p[0] - self.a[0], p[1] - self.a[1]];
        let t = (ap[0] * self.d[0] + ap[1] * self.d[1]) * self.inv_len2;
        // `!(t > 0.0)` also catches NaN from non-finite input.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        let (t, foot) = if !(t > 0.0) {
            (0.0, self.a)
        } else if t >= 1.0 {
            (1.0, self.b)
        } else {
            (t, [self.a[0] + t * self.d[0], self.a[1] + t * self.d[1]])
        };
        let dx = p[0] - foot[0];
        let dy = p[1] - foot[1];
        Projection { distance_squared: dx * dx + dy * dy, foot, t }
    }
}

/// Exact orientation of `(a, b, c)` (Shewchuk's adaptive predicate): positive when
/// counter-clockwise, zero only when the three points are collinear.
#[inline]
pub(crate) fn orient(a: Point2, b: Point2, c: Point2) -> f64 {
    robust::orient2d(
        robust::Coord { x: a[0], y: a[1] },
        robust::Coord { x: b[0], y: b[1] },
        robust::Coord { x: c[0], y: c[1] },
    )
}

/// `(b - a) × (c - a)`: positive when `c` lies left of the line from `a` to `b`.
#[inline]
pub(crate) fn cross(a: Point2, b: Point2, c: Point2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether the closed segments `pq` and `rs` share a point, with a tolerance `tol`
/// on the distance between them: near misses count as contact, so that callers
/// that use this to mark cells err on the side of marking.
pub(crate) fn segments_touch(p: Point2, q: Point2, r: Point2, s: Point2, tol: f64) -> bool {
    let d1 = cross(p, q, r);
    let d2 = cross(p, q, s);
    let d3 = cross(r, s, p);
    let d4 = cross(r, s, q);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    // Not a proper crossing: they touch iff an end of one lies (within tol) on the other.
    let tol2 = tol * tol;
    let pq = SegmentGeom::new(p, q);
    let rs = SegmentGeom::new(r, s);
    pq.project(r).distance_squared <= tol2
        || pq.project(s).distance_squared <= tol2
        || rs.project(p).distance_squared <= tol2
        || rs.project(q).distance_squared <= tol2
}

/// Whether the closed segment `pq` meets the closed polygon `corners` (a mesh cell:
/// triangle or quad, either orientation), within `tol`.
pub(crate) fn segment_touches_polygon(p: Point2, q: Point2, corners: &[Point2], tol: f64) -> bool {
    let k = corners.len();
    if k == 0 {
        return false;
    }
    if point_in_polygon(p, corners) {
        return true;
    }
    (0..k).any(|i| segments_touch(p, q, corners[i], corners[(i + 1) % k], tol))
}

/// Crossing-number test (even–odd rule); points on the boundary may go either way,
/// which [`segment_touches_polygon`] covers with its edge tests.
pub(crate) fn point_in_polygon(p: Point2, corners: &[Point2]) -> bool {
    let k = corners.len();
    let mut inside = false;
    for i in 0..k {
        let a = corners[i];
        let b = corners[(i + 1) % k];
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_inside_and_snapped() {
        let s = SegmentGeom::new([0.0, 0.0], [2.0, 0.0]);
        let p = s.project([1.0, 1.0]);
        assert_eq!(p.foot, [1.0, 0.0]);
        assert_eq!(p.t, 0.5);
        assert_eq!(p.distance_squared, 1.0);
        let p = s.project([-1.0, 0.0]);
        assert_eq!((p.t, p.foot, p.distance_squared), (0.0, [0.0, 0.0], 1.0));
        let p = s.project([3.0, 4.0]);
        assert_eq!((p.t, p.foot, p.distance_squared), (1.0, [2.0, 0.0], 17.0));
    }

    #[test]
    fn degenerate_segment_is_a_point() {
        let s = SegmentGeom::new([1.0, 1.0], [1.0, 1.0]);
        let p = s.project([4.0, 5.0]);
        assert_eq!((p.t, p.foot, p.distance()), (0.0, [1.0, 1.0], 5.0));
    }

    #[test]
    fn shared_end_gives_identical_distances() {
        let a = [0.1, 0.7];
        let b = [0.3, 0.9];
        let c = [0.35, 1.7];
        // Beyond `b` along `ab` (t > 1) and before `b` along `bc` (t < 0).
        let p = [1.3, 0.8];
        let d1 = SegmentGeom::new(a, b).project(p);
        let d2 = SegmentGeom::new(b, c).project(p);
        assert_eq!(d1.foot, b);
        assert_eq!(d2.foot, b);
        assert_eq!(d1.distance_squared.to_bits(), d2.distance_squared.to_bits());
    }

    #[test]
    fn contact_tests() {
        let tri = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        assert!(segment_touches_polygon([0.1, 0.1], [0.2, 0.2], &tri, 0.0));
        assert!(segment_touches_polygon([-1.0, 0.5], [2.0, 0.5], &tri, 0.0));
        assert!(!segment_touches_polygon([1.0, 1.0], [2.0, 2.0], &tri, 0.0));
        // Through a corner exactly.
        assert!(segment_touches_polygon([-1.0, 1.0], [1.0, -1.0], &tri, 1e-12));
        assert!(segments_touch([0.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0], 0.0));
        assert!(!segments_touch([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], 0.0));
    }
}
