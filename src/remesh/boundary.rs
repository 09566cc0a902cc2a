//! The boundary and interface geometry the remesher keeps: the input's constrained
//! curves cut into *pieces* between corners, each an original polyline parametrised by
//! arc length. A vertex on a piece is known by its parameter `s`, so it can only slide
//! along its own piece and its position is always a function of `s`: on the original
//! polyline ([`BoundaryMode::Polyline`]) or on a C¹ cubic Hermite reconstruction through
//! the original vertices ([`BoundaryMode::Smooth`], the default, as MMG's): at each
//! vertex the tangent of the circle through it and its two neighbours (exact on circles
//! and lines, O(h²) elsewhere), at a corner end the mirror of the next tangent across the
//! end chord; the pieces break at corners, so corners stay corners, and a segment whose
//! two tangents lie along its chord is the chord itself, so straight runs stay exactly
//! straight. Through a fixed vertex that is no corner of the curve (a closed loop's
//! start) the tangent takes the point beyond it ([`Beyond`]); the kept points of
//! [`super::RemeshOptions::keep_points`] are corners, so a loop that keeps them keeps
//! its input's segments. The metric of a piece vertex is
//! the Log-Euclidean interpolation, along the piece, of the input metric at the two
//! original vertices around `s`: from the input field, like the interior.
//!
//! [`Piece::deviation`] measures how far a new boundary edge strays from the curve it
//! replaces: a collapse on a curve is refused past the Hausdorff bound
//! ([`super::RemeshOptions::hausd`]), so coarsening keeps the area and the curve.
//! [`Piece::bends_between`] tells a bending stretch from a straight run: there a chord
//! cuts off area growing as the cube of its length, so a collapse on a bending stretch
//! stops at the metric's unit length rather than the split bound.
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
    /// Unit tangent at each point, for the smooth reconstruction.
    tangents: Vec<[f64; 2]>,
    /// Whether segment `k` is a straight run (both end tangents along its chord): the
    /// reconstruction is the chord itself there, exactly.
    straight: Vec<bool>,
    /// Line cell tags.
    pub tags: LineTags,
    /// Remesher vertex at the start (`s = 0`) and end (`s = length`); the same vertex
    /// for a closed loop with a single corner.
    pub ends: [u32; 2],
    /// An edge of a kept cell: never split.
    pub frozen: bool,
}

/// The points just beyond a piece's two ends where its curve goes on smoothly (a closed
/// loop's start), `None` at a corner.
pub(super) type Beyond = [Option<[f64; 2]>; 2];

impl Piece {
    /// A piece through `pts` with the log-metrics `logs`, tags and end vertices; `beyond`
    /// gives the curve's next points past each end where it goes on smoothly.
    pub(super) fn new(
        pts: Vec<[f64; 2]>,
        logs: Vec<Sym2>,
        tags: LineTags,
        ends: [u32; 2],
        beyond: Beyond,
    ) -> Piece {
        let mut s = vec![0.0; pts.len()];
        for i in 1..pts.len() {
            s[i] = s[i - 1] + dist(pts[i - 1], pts[i]);
        }
        let tangents = tangents(&pts, beyond);
        let straight = (0..pts.len().saturating_sub(1))
            .map(|k| {
                let c = unit(pts[k], pts[k + 1]);
                [tangents[k], tangents[k + 1]].iter().all(|t| cross(*t, c).abs() <= 1e-12)
            })
            .collect();
        Piece { pts, s, logs, tangents, straight, tags, ends, frozen: false }
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
        self.on_segment(k, t, mode)
    }

    /// The position at fraction `t` of segment `k`. The smooth reconstruction is the
    /// cubic Hermite curve with the unit tangents at the segment's ends, each scaled to
    /// 2c / (1 + cos a), c the chord and a the tangent's angle to it: the length that
    /// makes the cubic follow a circular arc (error about 2·10⁻⁴ of the radius for a
    /// quarter circle, falling as the sixth power of the arc's angle), and c on a
    /// straight run, where the curve is the chord at uniform speed.
    fn on_segment(&self, k: usize, t: f64, mode: BoundaryMode) -> [f64; 2] {
        let (a, b) = (self.pts[k], self.pts[k + 1]);
        if t == 0.0 {
            return a;
        }
        if t == 1.0 {
            return b;
        }
        if mode == BoundaryMode::Polyline || self.straight[k] {
            return [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        }
        let c = dist(a, b);
        let chord = unit(a, b);
        let (ta, tb) = (self.tangents[k], self.tangents[k + 1]);
        let la = 2.0 * c / (1.0 + dot(ta, chord).max(0.0));
        let lb = 2.0 * c / (1.0 + dot(tb, chord).max(0.0));
        let (t2, t3) = (t * t, t * t * t);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        [
            h00 * a[0] + h10 * la * ta[0] + h01 * b[0] + h11 * lb * tb[0],
            h00 * a[1] + h10 * la * ta[1] + h01 * b[1] + h11 * lb * tb[1],
        ]
    }

    /// The largest distance between the curve from parameter `s0` to `s1` (in `mode`)
    /// and the segment from `p0` to `p1`: the curve's original points in between and, on
    /// the smooth reconstruction, eight points on each of its cubic segments (the cubic
    /// of a segment bends once, so its farthest point from a chord is near one of them).
    pub(super) fn deviation(
        &self,
        s0: f64,
        s1: f64,
        p0: [f64; 2],
        p1: [f64; 2],
        mode: BoundaryMode,
    ) -> f64 {
        let (lo, hi) = if s0 <= s1 { (s0, s1) } else { (s1, s0) };
        let mut worst: f64 = 0.0;
        let mut see = |q: [f64; 2]| worst = worst.max(point_segment_distance(q, p0, p1));
        let inner = self.inner_points(lo, hi);
        for i in inner.clone() {
            see(self.pts[i]);
        }
        if mode == BoundaryMode::Smooth {
            let first = inner.start.saturating_sub(1);
            let last = inner.end.min(self.pts.len() - 1);
            for k in first..last {
                if self.straight[k] {
                    continue;
                }
                let (a, b) = (self.s[k], self.s[k + 1]);
                for j in 1..8 {
                    let sk = a + (b - a) * j as f64 / 8.0;
                    if sk > lo && sk < hi {
                        see(self.on_segment(k, j as f64 / 8.0, mode));
                    }
                }
            }
        }
        worst
    }

    /// Whether the piece bends anywhere between parameters `s0` and `s1` (in either
    /// order): some segment crossed is not a straight run.
    pub(super) fn bends_between(&self, s0: f64, s1: f64) -> bool {
        let (lo, hi) = if s0 <= s1 { (s0, s1) } else { (s1, s0) };
        let first = self.segment(lo).0;
        let last = self.segment(hi).0;
        (first..=last).any(|k| !self.straight[k])
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

fn dot(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[0] + u[1] * v[1]
}

fn cross(u: [f64; 2], v: [f64; 2]) -> f64 {
    u[0] * v[1] - u[1] * v[0]
}

/// The unit vector from `a` to `b` (zero when they coincide).
fn unit(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let d = dist(a, b);
    if d > 0.0 {
        [(b[0] - a[0]) / d, (b[1] - a[1]) / d]
    } else {
        [0.0, 0.0]
    }
}

/// Distance from `q` to the segment `ab`.
fn point_segment_distance(q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1]];
    let l2 = dot(e, e);
    let t = if l2 > 0.0 { (dot([q[0] - a[0], q[1] - a[1]], e) / l2).clamp(0.0, 1.0) } else { 0.0 };
    dist(q, [a[0] + t * e[0], a[1] + t * e[1]])
}

/// The unit tangent at `b` of the circle through `a`, `b`, `c` (the line's direction
/// when they are collinear): with u = b − a and v = c − b, the direction of
/// u·|v|/|u| + v·|u|/|v|, which on a circle splits the angle between the chords in the
/// ratio of the arcs they span. Exact on circles and straight lines whatever the
/// spacing, within O(h²) of the curve's tangent elsewhere.
fn circle_tangent(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [f64; 2] {
    let (lu, lv) = (dist(a, b), dist(b, c));
    if !(lu > 0.0 && lv > 0.0) {
        return unit(a, c);
    }
    if orient(a, b, c) == 0.0 {
        // Exactly collinear: the chord's own direction, so straight runs stay straight.
        return unit(a, b);
    }
    let (r, q) = (lv / lu, lu / lv);
    let t = [(b[0] - a[0]) * r + (c[0] - b[0]) * q, (b[1] - a[1]) * r + (c[1] - b[1]) * q];
    unit([0.0, 0.0], t)
}

/// The tangent at one end of chord `ab` of the circle whose tangent at the other end is
/// `tb`: its mirror image across the chord (a circular arc is symmetric about its
/// chord's bisector; both tangents oriented from `a` to `b`).
fn mirrored(tb: [f64; 2], a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let c = unit(a, b);
    let k = 2.0 * dot(tb, c);
    [k * c[0] - tb[0], k * c[1] - tb[1]]
}

/// Unit tangents at the points of a polyline (oriented along it): at an inner point,
/// or at an end the curve goes on smoothly past (`beyond`), that of the circle through
/// it and its two neighbours; at a corner end, the mirror across the first (last) chord
/// of the next point's tangent, so that the end segment is an arc of that circle; the
/// chord on a piece of one segment.
fn tangents(pts: &[[f64; 2]], beyond: Beyond) -> Vec<[f64; 2]> {
    let n = pts.len();
    if n < 2 {
        return vec![[0.0, 0.0]; n];
    }
    let mut t: Vec<[f64; 2]> = (0..n)
        .map(|i| match (i, i + 1 == n) {
            (0, _) => match beyond[0] {
                Some(p) => circle_tangent(p, pts[0], pts[1]),
                None => unit(pts[0], pts[1]),
            },
            (_, true) => match beyond[1] {
                Some(p) => circle_tangent(pts[n - 2], pts[n - 1], p),
                None => unit(pts[n - 2], pts[n - 1]),
            },
            _ => circle_tangent(pts[i - 1], pts[i], pts[i + 1]),
        })
        .collect();
    if n >= 3 {
        if beyond[0].is_none() {
            t[0] = mirrored(t[1], pts[0], pts[1]);
        }
        if beyond[1].is_none() {
            t[n - 1] = mirrored(t[n - 2], pts[n - 2], pts[n - 1]);
        }
    }
    t
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
        let p = Piece::new(pts, logs, None, [0, 1], [None, None]);
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
        let c = Piece::new(pts, vec![Sym2::new(0.0, 0.0, 0.0); n], None, [0, 1], [None, None]);
        let s = 0.5 * (c.s[3] + c.s[4]);
        let r = |q: [f64; 2]| q[0].hypot(q[1]);
        assert!(
            (r(c.point(s, BoundaryMode::Smooth)) - 1.0).abs()
                < 0.1 * (1.0 - r(c.point(s, BoundaryMode::Polyline)))
        );
    }

    /// The largest distance between the smooth reconstruction of the `n`-point polyline
    /// on `curve` (one closed loop, going on smoothly through its start) and the curve,
    /// measured at seven points of each segment against the exact closest point (found by
    /// ternary search of the curve's parameter near the segment).
    fn closed_error(n: usize, curve: impl Fn(f64) -> [f64; 2]) -> (f64, f64) {
        let u: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
        let pts: Vec<[f64; 2]> = u.iter().map(|&x| curve(x)).collect();
        let beyond = [Some(pts[n - 1]), Some(pts[1])];
        let c =
            Piece::new(pts.clone(), vec![Sym2::new(0.0, 0.0, 0.0); n + 1], None, [0, 0], beyond);
        let (mut smooth, mut poly): (f64, f64) = (0.0, 0.0);
        for k in 0..n {
            for j in 1..8 {
                let s = c.s[k] + (c.s[k + 1] - c.s[k]) * j as f64 / 8.0;
                for (mode, worst) in
                    [(BoundaryMode::Smooth, &mut smooth), (BoundaryMode::Polyline, &mut poly)]
                {
                    let q = c.point(s, mode);
                    let (mut lo, mut hi) = (u[k] - 0.5 / n as f64, u[k + 1] + 0.5 / n as f64);
                    for _ in 0..200 {
                        let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                        if dist(curve(a), q) < dist(curve(b), q) {
                            hi = b;
                        } else {
                            lo = a;
                        }
                    }
                    *worst = worst.max(dist(curve(0.5 * (lo + hi)), q));
                }
            }
        }
        (smooth, poly)
    }

    #[test]
    fn the_reconstruction_follows_circles_and_converges_on_an_ellipse() {
        use std::f64::consts::TAU;
        // A circle, unevenly spaced: the tangents are exact, the cubic follows each arc
        // within about 2.7e-4 R (angle / 90°)^6 (here arcs up to 36°: 1.1e-6 R).
        let circle = |u: f64| {
            let a = TAU * (u + 0.3 * (TAU * u).sin() / TAU);
            [2.0 * a.cos(), 2.0 * a.sin()]
        };
        let (smooth, poly) = closed_error(16, circle);
        assert!(smooth < 2.0 * 1.2e-6, "circle: {smooth:e}");
        assert!(poly > 1e3 * smooth, "circle: polyline {poly:e}");
        // An ellipse of axes 1 and 0.3: halving the spacing divides the error by 2^k with
        // k above 3 (the tangents' O(h²) error makes it O(h³); measured 3.3 and 3.1), the
        // polyline's by 4; at 128 points 40 times below the polyline's.
        let ellipse = |u: f64| [(TAU * u).cos(), 0.3 * (TAU * u).sin()];
        let e: Vec<(f64, f64)> = [32, 64, 128].iter().map(|&n| closed_error(n, ellipse)).collect();
        for w in e.windows(2) {
            let (smooth_order, poly_order) = ((w[0].0 / w[1].0).log2(), (w[0].1 / w[1].1).log2());
            assert!(smooth_order > 3.0, "{e:?}: order {smooth_order}");
            assert!((poly_order - 2.0).abs() < 0.2, "{e:?}: polyline order {poly_order}");
        }
        assert!(e[2].0 < 0.05 * e[2].1, "{e:?}");
    }

    #[test]
    fn deviation_is_the_sagitta_on_a_circle() {
        // Arc of the unit circle through 9 points; the chord between the points at
        // parameters s1 and s7 spans 6 arcs of 22.5°: its sagitta is 1 − cos(67.5°), at
        // the original point 4, so exact in both modes.
        let pts = arc(8);
        let c =
            Piece::new(pts.clone(), vec![Sym2::new(0.0, 0.0, 0.0); 9], None, [0, 1], [None, None]);
        let sagitta = 1.0 - (3.0 * std::f64::consts::PI / 8.0).cos();
        for mode in [BoundaryMode::Smooth, BoundaryMode::Polyline] {
            let d = c.deviation(c.s[7], c.s[1], pts[1], pts[7], mode);
            assert!((d - sagitta).abs() < 1e-12, "{mode:?}: {d} vs {sagitta}");
        }
        // Between two neighbours: nothing of the polyline strays, the circle's cap does
        // (1 − cos(11.25°)), which the samples of the cubic find within 2 %.
        let d = c.deviation(c.s[2], c.s[3], pts[2], pts[3], BoundaryMode::Polyline);
        assert_eq!(d, 0.0);
        let d = c.deviation(c.s[2], c.s[3], pts[2], pts[3], BoundaryMode::Smooth);
        let cap = 1.0 - (std::f64::consts::PI / 16.0).cos();
        assert!((d - cap).abs() < 0.02 * cap, "{d} vs {cap}");
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
            Piece::new(top.clone(), z(n), None, [0, 1], [None, None]),
            Piece::new(wall, z(2), None, [2, 3], [None, None]),
        ]);
        let p0 = &b.pieces[0];
        // Short chord near the end: clear. Chord over the top: the wall is inside.
        assert!(b.chord_clear(0, p0.s[0], top[0], p0.s[2], top[2]));
        assert!(!b.chord_clear(0, p0.s[1], top[1], p0.s[7], top[7]));
    }
}
