//! The boundary and interface geometry the remesher keeps: the input's constrained
//! curves cut into *pieces* between corners, each an original polyline parametrised by
//! arc length. A vertex on a piece is known by its parameter `s`, so it can only slide
//! along its own piece and its position is always a function of `s`: on the original
//! polyline ([`BoundaryMode::Polyline`]) or on a C¹ cubic Hermite reconstruction through
//! the original vertices ([`BoundaryMode::Smooth`]; tangents by centred differences in
//! arc length, so straight runs stay exactly straight). The metric of a piece vertex is
//! the Log-Euclidean interpolation, along the piece, of the input metric at the two
//! original vertices around `s`: from the input field, like the interior.
//!
//! [`Boundary::chord_clear`] is the guard against boundary crossings: replacing the arc
//! between two piece vertices by the straight edge between them sweeps the region between
//! the edge and the original arc, and that region must not hold any other original
//! boundary or interface segment.

use super::options::BoundaryMode;
use crate::geometry::segment::orient;
use crate::geometry::{SegmentGeom, SegmentIndex};
use crate::metric::log_euclidean;
use crate::metric::Sym2;

/// The tags of the line cells of a piece: `(physical, geometrical)`, or `None` when the
/// input listed no line cell there (a derived boundary or interface).
pub(super) type LineTags = Option<(i32, i32)>;

/// One constrained curve piece between two corners.
pub(super) struct Piece {
    /// Original polyline points, in order.
    pub pts: Vec<[f64; 2]>,
    /// Cumulative arc length at each point (`s[0] = 0`).
    pub s: Vec<f64>,
    /// Logarithm of the input metric at each point.
    pub logs: Vec<Sym2>,
    /// dP/ds at each point, for the smooth reconstruction.
    tangents: Vec<[f64; 2]>,
    /// Line cell tags.
    pub tags: LineTags,
    /// Remesher vertex at the start (`s = 0`) and end (`s = length`); the same vertex
    /// for a closed loop with a single corner.
    pub ends: [u32; 2],
    /// An edge of a kept cell: never split.
    pub frozen: bool,
}

impl Piece {
    /// A piece through `pts` with the log-metrics `logs`, tags and end vertices.
    pub(super) fn new(
        pts: Vec<[f64; 2]>,
        logs: Vec<Sym2>,
        tags: LineTags,
        ends: [u32; 2],
    ) -> Piece {
        let mut s = vec![0.0; pts.len()];
        for i in 1..pts.len() {
            s[i] = s[i - 1] + dist(pts[i - 1], pts[i]);
        }
        let n = pts.len();
        let tangents = (0..n)
            .map(|i| {
                let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
                let ds = s[b] - s[a];
                if ds > 0.0 {
                    [(pts[b][0] - pts[a][0]) / ds, (pts[b][1] - pts[a][1]) / ds]
                } else {
                    [0.0, 0.0]
                }
            })
            .collect();
        Piece { pts, s, logs, tangents, tags, ends, frozen: false }
    }

    /// Arc length of the piece.
    pub(super) fn length(&self) -> f64 {
        *self.s.last().unwrap_or(&0.0)
    }

    /// The segment holding parameter `s` and the fraction along it.
    fn segment(&self, s: f64) -> (usize, f64) {
        let n = self.s.len();
        let k = self.s.partition_point(|&x| x <= s).clamp(1, n - 1) - 1;
        let len = self.s[k + 1] - self.s[k];
        let t = if len > 0.0 { ((s - self.s[k]) / len).clamp(0.0, 1.0) } else { 0.0 };
        (k, t)
    }

    /// The position at parameter `s`.
    pub(super) fn point(&self, s: f64, mode: BoundaryMode) -> [f64; 2] {
        let (k, t) = self.segment(s);
        let (a, b) = (self.pts[k], self.pts[k + 1]);
        if t == 0.0 {
            return a;
        }
        if t == 1.0 {
            return b;
        }
        match mode {
            BoundaryMode::Polyline => [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
            BoundaryMode::Smooth => {
                let h = self.s[k + 1] - self.s[k];
                let (ma, mb) = (self.tangents[k], self.tangents[k + 1]);
                let (t2, t3) = (t * t, t * t * t);
                let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
                let h10 = t3 - 2.0 * t2 + t;
                let h01 = -2.0 * t3 + 3.0 * t2;
                let h11 = t3 - t2;
                [
                    h00 * a[0] + h10 * h * ma[0] + h01 * b[0] + h11 * h * mb[0],
                    h00 * a[1] + h10 * h * ma[1] + h01 * b[1] + h11 * h * mb[1],
                ]
            }
        }
    }

    /// The metric at parameter `s`, interpolated along the piece from the input.
    pub(super) fn metric(&self, s: f64) -> Sym2 {
        let (k, t) = self.segment(s);
        log_euclidean(&[1.0 - t, t], &[&self.logs[k], &self.logs[k + 1]])
    }

    /// Indices of the original points strictly between parameters `lo < hi`.
    fn inner_points(&self, lo: f64, hi: f64) -> std::ops::Range<usize> {
        self.s.partition_point(|&x| x <= lo)..self.s.partition_point(|&x| x < hi)
    }
}

/// Every piece, and an index of every original constrained segment.
pub(super) struct Boundary {
    /// The pieces.
    pub pieces: Vec<Piece>,
    index: SegmentIndex,
    /// `(piece, segment)` of each indexed segment.
    owner: Vec<(u32, u32)>,
}

impl Boundary {
    /// Indexes the segments of `pieces`.
    pub(super) fn new(pieces: Vec<Piece>) -> Boundary {
        let mut segs = Vec::new();
        let mut owner = Vec::new();
        for (p, piece) in pieces.iter().enumerate() {
            for k in 0..piece.pts.len().saturating_sub(1) {
                segs.push(SegmentGeom::new(piece.pts[k], piece.pts[k + 1]));
                owner.push((p as u32, k as u32));
            }
        }
        Boundary { pieces, index: SegmentIndex::new(&segs), owner }
    }

    /// Whether the straight edge from `pu` (parameter `su`) to `pv` (parameter `sv`) on
    /// piece `p` leaves the region between itself and the original arc free of every other
    /// original constrained segment (no proper crossing, no end strictly inside).
    pub(super) fn chord_clear(&self, p: u32, su: f64, pu: [f64; 2], sv: f64, pv: [f64; 2]) -> bool {
        let piece = &self.pieces[p as usize];
        let (su, pu, sv, pv) = if su <= sv { (su, pu, sv, pv) } else { (sv, pv, su, pu) };
        let mut poly = vec![pu];
        poly.extend(piece.inner_points(su, sv).map(|i| piece.pts[i]));
        poly.push(pv);
        if poly.len() == 2 && piece.point_on_polyline(su, pu) && piece.point_on_polyline(sv, pv) {
            // Both ends on one original segment: the edge is the arc itself.
            return true;
        }
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for q in &poly {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let mut clear = true;
        self.index.for_each_overlapping(lo, hi, |id, seg| {
            if !clear {
                return;
            }
            let (q, k) = self.owner[id as usize];
            if q == p {
                let (a, b) = (piece.s[k as usize], piece.s[k as usize + 1]);
                if b >= su && a <= sv {
                    return;
                }
            }
            if segment_enters_polygon(seg.a, seg.b, &poly) {
                clear = false;
            }
        });
        clear
    }
}

impl Piece {
    /// Whether `p` is the polyline point at `s` (so the vertex sits on the polyline).
    fn point_on_polyline(&self, s: f64, p: [f64; 2]) -> bool {
        self.point(s, BoundaryMode::Polyline) == p
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// Whether segment `ab` properly crosses an edge of the closed polygon `poly`, or has an
/// end strictly inside it (ends on a polygon corner do not count: pieces meet there).
fn segment_enters_polygon(a: [f64; 2], b: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    for i in 0..n {
        let (c, d) = (poly[i], poly[(i + 1) % n]);
        let (o1, o2) = (orient(a, b, c), orient(a, b, d));
        let (o3, o4) = (orient(c, d, a), orient(c, d, b));
        if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
            return true;
        }
    }
    [a, b].iter().any(|p| !poly.contains(p) && strictly_inside(*p, poly))
}

/// Even–odd test that counts points on the polygon's edges as outside.
fn strictly_inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let n = poly.len();
    for i in 0..n {
        let (c, d) = (poly[i], poly[(i + 1) % n]);
        if orient(c, d, p) == 0.0
            && p[0] >= c[0].min(d[0])
            && p[0] <= c[0].max(d[0])
            && p[1] >= c[1].min(d[1])
            && p[1] <= c[1].max(d[1])
        {
            return false;
        }
    }
    crate::geometry::segment::point_in_polygon(p, poly)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(n: usize) -> Vec<[f64; 2]> {
        (0..=n)
            .map(|i| std::f64::consts::PI * i as f64 / n as f64)
            .map(|t| [t.cos(), t.sin()])
            .collect()
    }

    #[test]
    fn polyline_and_smooth_points() {
        let pts = vec![[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]];
        let logs = vec![Sym2::new(0.0, 0.0, 0.0); 3];
        let p = Piece::new(pts, logs, None, [0, 1]);
        assert_eq!(p.length(), 3.0);
        // A straight run stays straight, and at the right arc length, in both modes.
        for s in [0.0, 0.5, 1.0, 2.2, 3.0] {
            assert_eq!(p.point(s, BoundaryMode::Polyline), [s, 0.0]);
            let q = p.point(s, BoundaryMode::Smooth);
            assert!((q[0] - s).abs() < 1e-12 && q[1] == 0.0, "{s}: {q:?}");
        }
        // On an arc the smooth reconstruction is closer to the circle than the chord.
        let pts = arc(8);
        let n = pts.len();
        let c = Piece::new(pts, vec![Sym2::new(0.0, 0.0, 0.0); n], None, [0, 1]);
        let s = 0.5 * (c.s[3] + c.s[4]);
        let r = |q: [f64; 2]| q[0].hypot(q[1]);
        assert!(
            (r(c.point(s, BoundaryMode::Smooth)) - 1.0).abs()
                < 0.1 * (1.0 - r(c.point(s, BoundaryMode::Polyline)))
        );
    }

    #[test]
    fn chord_across_a_close_wall_is_refused() {
        // An arc (piece 0) and a flat wall (piece 1) just under its top: the chord between
        // the arc's ends cuts the wall's segment region.
        let top = arc(8);
        let wall = vec![[-0.3, 0.9], [0.3, 0.9]];
        let z = |n| vec![Sym2::new(0.0, 0.0, 0.0); n];
        let n = top.len();
        let b = Boundary::new(vec![
            Piece::new(top.clone(), z(n), None, [0, 1]),
            Piece::new(wall, z(2), None, [2, 3]),
        ]);
        let p0 = &b.pieces[0];
        // Short chord near the end: clear. Chord over the top: the wall is inside.
        assert!(b.chord_clear(0, p0.s[0], top[0], p0.s[2], top[2]));
        assert!(!b.chord_clear(0, p0.s[1], top[1], p0.s[7], top[7]));
    }
}
