//! Clearances of a polyline source: how far from each segment, and from each polyline
//! vertex, the closest point of the source is decided by the few segments around it,
//! so that a closest point found among those is exact without a search of the others.
//!
//! Segment. Let `p` lie on one side of segment `s = [a, b]` at distance `y`, its foot
//! strictly inside `s`. The disc of radius `y` around `p` lies in the *stadium* swept by
//! the discs of radius `y` tangent to `s` on that side, `{z : dist(z, [a, b] + y n) <
//! y}`. A point `q` at height `y_q > 0` above the line of `s` and at distance `dx` from
//! `[a, b]` along it lies outside that stadium as long as `y <= F(q) = (dx² + y_q²) /
//! (2 y_q)` (the radius of the circle tangent to `s` through `q`); points at or below
//! the line never enter it. So if `y` stays below the smallest `F` over the segments
//! outside the *window* of `s` (itself and [`WINDOW`] segments either way along its
//! polyline), none of them is as close to `p` as `s`, and the closest point of the
//! source is the best of the window's segments.
//!
//! Vertex. At a polyline vertex `v` where the polyline turns by θ, the points whose
//! foot is `v` on both of its segments form a cone of angle θ on the outer side of the
//! turn. For `p = v + r m` with `m` in the cone, the disc of radius `r` around `p` is one
//! of the discs of radius `r` through `v` centred along the cone, and a point `q` stays
//! out of all of them as long as `r <= G(q) = |q - v|² / (2 h(q))`, `h(q)` the largest
//! projection of `q - v` on a direction of the cone. The caller asks only when both
//! segments put the foot on `v` (so `m` is in the cone up to rounding), and checks that
//! `m` lies within `κ = 2 sin(θ/4)` (with a little slack) of the cone's mean direction.
//!
//! Vertex from its segments. Let `s` end at `v` and `n` start there, `F_s` and `F_n` on
//! the outer side of the turn. For `q - v` outside the cone, `h(q)` is the larger of the
//! heights `y_s`, `y_n` of `q` over the two lines (an arc of less than a half-turn takes
//! the largest product at an end), and `|q - v|² >= dx² + y²` in either frame (`v` ends
//! the span of both), so `G(q) >= min(F_s(q), F_n(q))`. For `q - v` inside the cone,
//! `G(q) = |q - v| / 2`, and the edge within θ/2 of `q - v` has `F <= |q - v| / (2 cos
//! θ/2)`. So `G >= cos(θ/2) min(F_s, F_n)` everywhere, and the cone's clearance is at
//! least `cos(θ/2)` times the smaller of the two segments' clearances, except for the
//! segments of their windows outside the cone's (the second segment back from `s`, the
//! second ahead of `n`), whose `G` is bounded directly. The segments' clearances are
//! asked for anyway by the points whose foot lies inside them; the cone's own search
//! runs only where this bound falls short of a question.
//!
//! Soundness. Over a box of the tree below or a piece of a segment, `F` and `G` are
//! bounded from below by their smallest numerator over their largest denominator, so
//! every clearance is a lower bound of the true one; segments are cut into [`PIECES`]
//! pieces so that the bound stays tight for the segments just outside a window. A
//! segment outside the window that comes within [`SEPARATION`] (relative to the
//! coordinates) of `s` or `v` — another curve meeting it, a polyline touching itself —
//! leaves no clearance, since there the two distances could tie to rounding. The caller
//! certifies only up to 0.999 of a clearance: with that separation, a margin far above
//! the rounding of the distances it compares, so that the certified answer is the one a
//! scan of every segment computes, bit for bit.
//!
//! Cost: a branch-and-bound walk of a tree of oriented boxes over runs of segments, from
//! the segment's leaf up, per segment side and per vertex that a propagation asks about,
//! seeded with the segments just outside the window, and stopped at the cap of the tier
//! asked (see [`Clearance`]); the tree is built in O(m) for m segments.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use super::chain_tree::ChainNode;
pub(crate) use super::chain_tree::ChainTree;
use super::segment::{Point2, SegmentGeom};
use super::segment_index::{Nearest, QueryStats};

/// Segments either side of a segment whose closest points a certificate compares: the
/// one definition of the window, which the propagation's window of a closest point
/// (`sizing::propagation`, `Source::window`) is built from.
pub(crate) const WINDOW: usize = 2;

/// Pieces a segment is cut into for its lower bounds.
pub(crate) const PIECES: usize = 8;

/// Distance, relative to the largest coordinate, under which a segment outside a window
/// counts as touching the segment or vertex of the window.
pub(crate) const SEPARATION: f64 = 1e-9;

/// A node is opened only when its bound is below this fraction of the clearance found
/// so far, and the clearance kept is that fraction of the smallest value found: still
/// a lower bound (every node left closed is at least that far), for far fewer nodes
/// where many parts of the source are about equally close (a circle seen from inside).
const SETTLE: f64 = 0.75;

/// The cone of directions at a polyline vertex from which the vertex is the foot on
/// both of its segments (the outer side of the turn).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ConeShape {
    /// Mean direction (unit).
    pub(crate) mean: Point2,
    /// Square of the largest distance between a unit vector of the cone and `mean`
    /// (with a little slack).
    pub(crate) kappa_squared: f64,
    /// Its edges.
    sector: Sector,
    /// `cos(θ/2)`, shaved by a few ulps.
    half_cos: f64,
    /// The side (0 left, 1 right) of both segments on which the cone lies.
    outer: usize,
}

/// Clearances of the segments (each side) and interior polyline vertices of a source.
///
/// Each is computed the first time a propagation asks for it, up to a *tier*: the
/// searches of tier k stop at `caps[k]` (8 times the previous tier's, from a few
/// segment lengths up to a few times the source's extent, then no cap), and a question at distance
/// d is asked of the first tier that can answer it. A tier's value is a fixed function
/// of the source (the previous tier's when that one found its clearance below its cap,
/// else its own search), so the answers do not depend on the order of the questions or
/// on the thread count; vertices near the source cost only short searches.
#[derive(Debug)]
pub(crate) struct Clearance {
    geoms: Vec<SegmentGeom>,
    links: Vec<Links>,
    gap: f64,
    /// Search caps, increasing.
    caps: Vec<f64>,
    /// Clearance of segment `s`, side `k` (0 left, 1 right), tier `t` at
    /// `(2 s + k) * tiers + t` (0: none).
    segment: Vec<Memo>,
    /// The cone at the end of each segment that has a next one.
    cone: Vec<Option<ConeShape>>,
    /// Clearance of the cone at the end of segment `s`, tier `t`, at `s * tiers + t`:
    /// from the two segments' clearances, and from the cone's own search.
    cone_derived: Vec<Memo>,
    cone_radius: Vec<Memo>,
    /// Runs of segments in oriented boxes, for the clearances and for exact queries
    /// (shared with the source that made it).
    tree: Arc<ChainTree>,
}

/// A value computed at most a few times and then read: the bits of an `f64`, or
/// `u64::MAX` (a NaN no computation here returns) before the first computation. Why not
/// `OnceLock`: half the memory (8 bytes per tier of every segment side) and a plain load
/// to read. Two threads may both compute a missing value; it is a fixed function of the
/// source, so both store the same bits.
#[derive(Debug)]
struct Memo(AtomicU64);

impl Default for Memo {
    fn default() -> Memo {
        Memo(AtomicU64::new(u64::MAX))
    }
}

impl Memo {
    #[inline]
    fn get_or_compute(&self, f: impl FnOnce() -> f64) -> f64 {
        let bits = self.0.load(Ordering::Relaxed);
        if bits != u64::MAX {
            return f64::from_bits(bits);
        }
        let v = f();
        let b = v.to_bits();
        self.0.store(if b == u64::MAX { f64::NAN.to_bits() } else { b }, Ordering::Relaxed);
        v
    }
}

/// Polyline links of a segment: previous and next along its polyline.
pub(crate) type Links = (Option<u32>, Option<u32>);

/// Ratio of the search caps of consecutive tiers.
const TIER_GROWTH: f64 = 8.0;

/// Share of a clearance up to which it certifies: a margin far above the rounding of the
/// distances compared (see the module header).
const CERTIFIED: f64 = 0.999;

/// `1 / CERTIFIED`, so that a question costs a product rather than a division (the
/// margin is the same to an ulp).
const BY_CERTIFIED: f64 = 1.0 / CERTIFIED;

impl Clearance {
    /// The clearances of `geoms` (linked by `links`), with `scale` the largest
    /// coordinate magnitude of the source and `horizon` the largest finite search cap
    /// (past it, a last tier searches without a cap).
    #[cfg(test)]
    pub(crate) fn new(
        geoms: &[SegmentGeom],
        links: &[Links],
        scale: f64,
        horizon: f64,
    ) -> Clearance {
        Clearance::new_over(Clearance::tree_of(geoms, scale), geoms, links, scale, horizon)
    }

    /// [`Clearance::new`] over a tree of `geoms` already built ([`Clearance::tree_of`]).
    pub(crate) fn new_over(
        tree: Arc<ChainTree>,
        geoms: &[SegmentGeom],
        links: &[Links],
        scale: f64,
        horizon: f64,
    ) -> Clearance {
        let lengths: Vec<f64> = geoms
            .iter()
            .filter(|g| g.inv_len2 > 0.0)
            .map(|g| g.length())
            .filter(|l| l.is_finite())
            .collect();
        let mean = if lengths.is_empty() {
            0.0
        } else {
            lengths.iter().sum::<f64>() / lengths.len() as f64
        };
        let mut caps = Vec::new();
        let mut c = 32.0 * mean;
        while c < horizon && caps.len() < 16 && c > 0.0 {
            caps.push(c);
            c *= TIER_GROWTH;
        }
        Clearance::with_caps(tree, geoms, links, scale, caps)
    }

    /// The clearances of `geoms` for questions no farther than `farthest` from the
    /// source: one tier that answers them all (its searches capped just past
    /// `farthest`), then the uncapped one. For a propagation that asks at every
    /// distance up to `farthest` about most segments, one search per segment side
    /// where [`Clearance::new`]'s tiers would make one per tier.
    ///
    /// `tree` is the tree of `geoms`, built already ([`Clearance::tree_of`]).
    pub(crate) fn up_to_over(
        tree: Arc<ChainTree>,
        geoms: &[SegmentGeom],
        links: &[Links],
        scale: f64,
        farthest: f64,
    ) -> Clearance {
        let cap = farthest * BY_CERTIFIED / SETTLE * (1.0 + 1e-9);
        let caps = if cap > 0.0 && cap.is_finite() { vec![cap] } else { Vec::new() };
        Clearance::with_caps(tree, geoms, links, scale, caps)
    }

    /// The tree of oriented boxes the clearances of `geoms` search (`scale` the largest
    /// coordinate magnitude), which also answers exact closest-segment queries: a
    /// source builds it once for both.
    pub(crate) fn tree_of(geoms: &[SegmentGeom], scale: f64) -> Arc<ChainTree> {
        Arc::new(ChainTree::new(geoms, 16.0 * f64::EPSILON * scale))
    }

    /// The clearances with the finite search caps `caps` (increasing), then the
    /// uncapped tier.
    fn with_caps(
        tree: Arc<ChainTree>,
        geoms: &[SegmentGeom],
        links: &[Links],
        scale: f64,
        mut caps: Vec<f64>,
    ) -> Clearance {
        let gap = SEPARATION * scale.max(f64::MIN_POSITIVE);
        caps.push(f64::INFINITY);
        let tiers = caps.len();
        let mut me = Clearance {
            geoms: geoms.to_vec(),
            links: links.to_vec(),
            gap,
            caps,
            segment: (0..2 * geoms.len() * tiers).map(|_| Memo::default()).collect(),
            cone: Vec::new(),
            cone_derived: (0..geoms.len() * tiers).map(|_| Memo::default()).collect(),
            cone_radius: (0..geoms.len() * tiers).map(|_| Memo::default()).collect(),
            tree,
        };
        me.cone = (0..geoms.len()).map(|s| me.cone_shape(s)).collect();
        me
    }

    /// The tier that answers a question at distance `d`.
    #[inline]
    fn tier(&self, need: f64) -> usize {
        self.caps.iter().position(|&c| SETTLE * c >= need).unwrap_or(self.caps.len() - 1)
    }

    fn segment_value(&self, s: usize, side: usize, t: usize) -> f64 {
        let tiers = self.caps.len();
        self.segment[(2 * s + side) * tiers + t].get_or_compute(|| {
            if t > 0 {
                let below = self.segment_value(s, side, t - 1);
                if below < SETTLE * self.caps[t - 1] {
                    return below;
                }
            }
            self.search_segment(s, side, self.caps[t])
        })
    }

    /// The lower bound of the cone's clearance from its segments' (see the module
    /// header), their tier `t`.
    fn cone_derived_value(&self, s: usize, shape: &ConeShape, t: usize) -> f64 {
        let tiers = self.caps.len();
        self.cone_derived[s * tiers + t].get_or_compute(|| {
            let Some(n) = self.next(s as u32) else { return 0.0 };
            let sides = shape.half_cos
                * self.segment_value(s, shape.outer, t).min(self.segment_value(
                    n as usize,
                    shape.outer,
                    t,
                ));
            self.cone_outside_segment_windows(s as u32, n, shape, sides)
        })
    }

    fn cone_value(&self, s: usize, t: usize) -> f64 {
        let tiers = self.caps.len();
        self.cone_radius[s * tiers + t].get_or_compute(|| {
            if t > 0 {
                let below = self.cone_value(s, t - 1);
                if below < SETTLE * self.caps[t - 1] {
                    return below;
                }
            }
            match &self.cone[s] {
                Some(shape) => self.search_cone(s, shape, self.caps[t]),
                None => 0.0,
            }
        })
    }

    /// Whether the clearance of segment `s` on the side of `p` covers `p` at distance
    /// `d` (with `p`'s foot strictly inside `s`): then the best of the segment's window
    /// is the closest point of the whole source.
    #[inline]
    pub(crate) fn covers_segment(&self, s: u32, p: Point2, d: f64) -> bool {
        let g = &self.geoms[s as usize];
        let cr = g.d[0] * (p[1] - g.a[1]) - g.d[1] * (p[0] - g.a[0]);
        let need = d * BY_CERTIFIED;
        if need.is_nan() {
            return false;
        }
        let t = self.tier(need);
        let value = |side: usize| self.segment_value(s as usize, side, t);
        let c = if cr > 0.0 {
            value(0)
        } else if cr < 0.0 {
            value(1)
        } else {
            value(0).min(value(1))
        };
        c >= need
    }

    /// Whether the cone at the end of segment `s` (its end point `v`, where it meets the
    /// next one) covers `p` at distance `d` from `v`.
    #[inline]
    pub(crate) fn covers_vertex(&self, s: u32, p: Point2, d: f64) -> bool {
        let Some(shape) = &self.cone[s as usize] else { return false };
        let need = d * BY_CERTIFIED;
        if need.is_nan() {
            return false;
        }
        let v = self.geoms[s as usize].b;
        let e = [p[0] - v[0] - d * shape.mean[0], p[1] - v[1] - d * shape.mean[1]];
        if e[0] * e[0] + e[1] * e[1] > shape.kappa_squared * d * d {
            return false;
        }
        let t = self.tier(need);
        self.cone_derived_value(s as usize, shape, t) >= need
            || self.cone_value(s as usize, t) >= need
    }

    /// The exact closest segment to `p`, starting from the guess `seed` (the projection
    /// of `p` on `seed.segment`), searched over the oriented boxes: the guess's leaf,
    /// then up to the root, opening the siblings whose box is not farther than the best
    /// so far. Ties as [`Nearest::beats`]; the answer does not depend on the guess.
    pub(crate) fn closest(&self, p: Point2, seed: Nearest, stats: &mut QueryStats) -> Nearest {
        self.tree.closest(&self.geoms, p, seed, stats)
    }
}

/// `x` range and `y` range (along and across a segment's frame) of some points.
#[derive(Clone, Copy)]
struct Rect {
    x: [f64; 2],
    y: [f64; 2],
}

impl Rect {
    fn of(points: &[Point2]) -> Rect {
        let mut r =
            Rect { x: [f64::INFINITY, f64::NEG_INFINITY], y: [f64::INFINITY, f64::NEG_INFINITY] };
        for q in points {
            r.x = [r.x[0].min(q[0]), r.x[1].max(q[0])];
            r.y = [r.y[0].min(q[1]), r.y[1].max(q[1])];
        }
        r
    }
}

/// The frame of a segment: origin `a`, unit direction `t`, left normal, length.
struct Frame {
    a: Point2,
    t: Point2,
    len: f64,
}

impl Frame {
    #[inline]
    fn local(&self, z: Point2) -> Point2 {
        let (dx, dy) = (z[0] - self.a[0], z[1] - self.a[1]);
        [dx * self.t[0] + dy * self.t[1], dy * self.t[0] - dx * self.t[1]]
    }

    /// The range of frame coordinates over a node's box: its centre's coordinates
    /// plus or minus the box's half extents projected on the frame's axes.
    #[inline]
    fn rect_of_box(&self, n: &ChainNode) -> Rect {
        let hs = 0.5 * (n.s[1] - n.s[0]);
        let ht = 0.5 * (n.t[1] - n.t[0]);
        let (ms, mt) = (0.5 * (n.s[0] + n.s[1]), 0.5 * (n.t[0] + n.t[1]));
        let c = [n.o[0] + ms * n.u[0] - mt * n.u[1], n.o[1] + ms * n.u[1] + mt * n.u[0]];
        let [cx, cy] = self.local(c);
        // Axis u and its left normal in the frame: (u·t, u·ν) and (-(u·ν), u·t).
        let ut = n.u[0] * self.t[0] + n.u[1] * self.t[1];
        let un = n.u[1] * self.t[0] - n.u[0] * self.t[1];
        let ex = hs * ut.abs() + ht * un.abs();
        let ey = hs * un.abs() + ht * ut.abs();
        // Rounding of the centre and products, well inside the tree's growth.
        let slack = 4.0 * f64::EPSILON * (cx.abs() + cy.abs() + ex + ey);
        Rect { x: [cx - ex - slack, cx + ex + slack], y: [cy - ey - slack, cy + ey + slack] }
    }

    /// Lower bound of `F` on side `side` (0 left, 1 right) over the points of `r`
    /// (frame coordinates), 0 where they come within `gap` of the segment.
    #[inline]
    fn bound(&self, r: Rect, side: usize, gap: f64) -> f64 {
        let dx = if r.x[1] < 0.0 {
            -r.x[1]
        } else if r.x[0] > self.len {
            r.x[0] - self.len
        } else {
            0.0
        };
        let y_abs = if r.y[0] > 0.0 {
            r.y[0]
        } else if r.y[1] < 0.0 {
            -r.y[1]
        } else {
            0.0
        };
        if dx * dx + y_abs * y_abs < gap * gap {
            return 0.0;
        }
        let (lo, hi) = if side == 0 { (r.y[0], r.y[1]) } else { (-r.y[1], -r.y[0]) };
        if hi <= 0.0 {
            f64::INFINITY
        } else {
            (dx * dx + lo.max(0.0) * lo.max(0.0)) / (2.0 * hi)
        }
    }
}

/// The sector of unit vectors between `n1` and `n2` (less than a half-turn apart).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sector {
    n1: Point2,
    n2: Point2,
}

impl Sector {
    /// `max (e · m)` over the unit vectors `m` of the sector: `|e|` when `e` points into
    /// it, else the larger of its two edges' products. A convex function of `e`.
    #[inline]
    fn support(&self, e: Point2) -> f64 {
        let c1 = self.n1[0] * e[1] - self.n1[1] * e[0];
        let c2 = e[0] * self.n2[1] - e[1] * self.n2[0];
        let turn = self.n1[0] * self.n2[1] - self.n1[1] * self.n2[0];
        let inside = if turn >= 0.0 { c1 >= 0.0 && c2 >= 0.0 } else { c1 <= 0.0 && c2 <= 0.0 };
        let edges =
            (e[0] * self.n1[0] + e[1] * self.n1[1]).max(e[0] * self.n2[0] + e[1] * self.n2[1]);
        if inside {
            e[0].hypot(e[1]).max(edges)
        } else {
            edges
        }
    }
}

/// `G >= D / (2 h)` from the smallest squared distance `d2` and the largest support `h`.
#[inline]
fn cone_bound(d2: f64, h: f64) -> f64 {
    if h <= 0.0 {
        f64::INFINITY
    } else {
        d2 / (2.0 * h)
    }
}

/// The searches behind the clearances.
impl Clearance {
    fn next(&self, s: u32) -> Option<u32> {
        self.links[s as usize].1
    }

    fn prev(&self, s: u32) -> Option<u32> {
        self.links[s as usize].0
    }

    /// The segments `k` steps from `s` along `step`, for k in `from..=to` (at most 8;
    /// `u32::MAX` where the polyline ends).
    fn walk(&self, s: u32, step: impl Fn(u32) -> Option<u32>, from: usize, to: usize) -> [u32; 8] {
        let mut out = [u32::MAX; 8];
        let mut at = s;
        let mut n = 0;
        for k in 1..=to {
            match step(at) {
                Some(next) => at = next,
                None => break,
            }
            if k >= from && n < out.len() {
                out[n] = at;
                n += 1;
            }
        }
        out
    }

    /// The window of segment `s`: itself and [`WINDOW`] segments either way along its
    /// polyline (`u32::MAX` past its ends).
    fn segment_window(&self, s: u32) -> [u32; 2 * WINDOW + 1] {
        let (back, ahead) =
            (self.walk(s, |x| self.prev(x), 1, WINDOW), self.walk(s, |x| self.next(x), 1, WINDOW));
        [s, back[0], back[1], ahead[0], ahead[1]]
    }

    /// The window of the cone at the end of segment `s` (which has a next one, `n`):
    /// the segment before `s`, `s`, `n`, the one after `n`.
    fn cone_window(&self, s: u32, n: u32) -> [Option<u32>; 4] {
        [self.prev(s), Some(s), Some(n), self.next(n)]
    }

    /// Lower bound of `G` (the cone at `v` with edges `sector`) over segment `id`, when
    /// below `best`; else `best`. The whole segment first, its pieces only where that
    /// could lower `best`.
    fn cone_bound_of_segment(&self, id: u32, v: Point2, sector: &Sector, best: f64) -> f64 {
        let gap2 = self.gap * self.gap;
        let g = &self.geoms[id as usize];
        let h = |q: Point2| sector.support([q[0] - v[0], q[1] - v[1]]);
        let whole = g.project(v).distance_squared;
        if whole >= gap2 && cone_bound(whole, h(g.a).max(h(g.b))) >= best {
            return best;
        }
        let pts = self.piece_points(id);
        let mut best = best;
        for w in pts.windows(2) {
            let d2 = SegmentGeom::new(w[0], w[1]).project(v).distance_squared;
            let b = if d2 < gap2 { 0.0 } else { cone_bound(d2, h(w[0]).max(h(w[1]))) };
            best = best.min(b);
        }
        best
    }

    /// Lower bound of `G` over the segments of the windows of `s` and of its next one
    /// `n` that lie outside the cone's window (those the two segments' clearances do not
    /// rule out for the cone), when below `best`; else `best`.
    fn cone_outside_segment_windows(&self, s: u32, n: u32, shape: &ConeShape, best: f64) -> f64 {
        let v = self.geoms[s as usize].b;
        let cone = self.cone_window(s, n);
        let mut best = best;
        let (ws, wn) = (self.segment_window(s), self.segment_window(n));
        for (k, &id) in ws.iter().chain(&wn).enumerate() {
            // Each segment once, none of the cone's window.
            let seen = ws.iter().chain(&wn).take(k).any(|&x| x == id);
            if id != u32::MAX && !seen && !cone.contains(&Some(id)) {
                best = self.cone_bound_of_segment(id, v, &shape.sector, best);
            }
        }
        best
    }

    /// Pieces of segment `id`, as `PIECES + 1` points.
    fn piece_points(&self, id: u32) -> [Point2; PIECES + 1] {
        let g = &self.geoms[id as usize];
        std::array::from_fn(|k| {
            let t = k as f64 / PIECES as f64;
            [g.a[0] + t * g.d[0], g.a[1] + t * g.d[1]]
        })
    }

    /// The clearance of segment `s` on side `side` (0 left, 1 right), searched up to
    /// `cap`.
    fn search_segment(&self, s: usize, side: usize, cap: f64) -> f64 {
        let g = &self.geoms[s];
        let len = g.length();
        if g.inv_len2 == 0.0 || !len.is_finite() {
            return 0.0;
        }
        let frame = Frame { a: g.a, t: [g.d[0] / len, g.d[1] / len], len };
        let s = s as u32;
        let window = self.segment_window(s);
        let mut best = cap;
        let value = |id: u32, best: &mut f64| {
            if window.contains(&id) {
                return;
            }
            // The whole segment first: pieces only where it could lower the clearance,
            // that is, where its bound is below SETTLE times the best so far, as for
            // the tree's nodes (the value kept is SETTLE times the smallest found).
            let g = &self.geoms[id as usize];
            if frame.bound(Rect::of(&[frame.local(g.a), frame.local(g.b)]), side, self.gap)
                >= SETTLE * *best
            {
                return;
            }
            let pts = self.piece_points(id).map(|q| frame.local(q));
            for w in pts.windows(2) {
                *best = best.min(frame.bound(Rect::of(w), side, self.gap));
            }
        };
        // Seed with the segments just outside the window, then search the rest.
        for id in self
            .walk(s, |x| self.prev(x), WINDOW + 1, WINDOW + 2)
            .into_iter()
            .chain(self.walk(s, |x| self.next(x), WINDOW + 1, WINDOW + 2))
        {
            if id != u32::MAX {
                value(id, &mut best);
            }
        }
        SETTLE
            * self.tree.search_from(
                s,
                best,
                SETTLE,
                |node| frame.bound(frame.rect_of_box(node), side, self.gap),
                value,
            )
    }

    fn cone_shape(&self, s: usize) -> Option<ConeShape> {
        let s32 = s as u32;
        let n = self.next(s32)?;
        let (g1, g2) = (&self.geoms[s], &self.geoms[n as usize]);
        let (l1, l2) = (g1.length(), g2.length());
        if g1.inv_len2 == 0.0
            || g2.inv_len2 == 0.0
            || !(l1.is_finite() && l2.is_finite())
            || g1.b != g2.a
        {
            return None;
        }
        let (d1, d2) = ([g1.d[0] / l1, g1.d[1] / l1], [g2.d[0] / l2, g2.d[1] / l2]);
        let turn = d1[0] * d2[1] - d1[1] * d2[0];
        // The outer side of the turn: right of a left turn, left otherwise.
        let (n1, n2) = if turn > 0.0 {
            ([d1[1], -d1[0]], [d2[1], -d2[0]])
        } else {
            ([-d1[1], d1[0]], [-d2[1], d2[0]])
        };
        let sum = [n1[0] + n2[0], n1[1] + n2[1]];
        let norm = sum[0].hypot(sum[1]);
        // NaN (a fold, or non-finite input) counts as degenerate too.
        if norm.is_nan() || norm <= 1e-6 {
            return None;
        }
        let mean = [sum[0] / norm, sum[1] / norm];
        let kappa = (n1[0] - mean[0]).hypot(n1[1] - mean[1]) * (1.0 + 1e-6) + 1e-9;
        // cos(θ/2) = |n1 + n2| / 2, a little less for the rounding of the normals.
        let half_cos = (0.5 * norm * (1.0 - 1e-9)).min(1.0);
        let outer = if turn > 0.0 { 1 } else { 0 };
        Some(ConeShape {
            mean,
            kappa_squared: kappa * kappa,
            sector: Sector { n1, n2 },
            half_cos,
            outer,
        })
    }

    /// The clearance of the cone at the end of segment `s`, searched up to `cap`.
    fn search_cone(&self, s: usize, shape: &ConeShape, cap: f64) -> f64 {
        let s32 = s as u32;
        let Some(n) = self.next(s32) else { return 0.0 };
        let sector = shape.sector;
        let v = self.geoms[s].b;
        let window = self.cone_window(s32, n);
        let mut best = cap;
        let gap2 = self.gap * self.gap;
        let value = |id: u32, best: &mut f64| {
            if !window.contains(&Some(id)) {
                *best = self.cone_bound_of_segment(id, v, &sector, *best);
            }
        };
        for id in self.walk(s32, |x| self.prev(x), 2, 3).into_iter().chain(self.walk(
            n,
            |x| self.next(x),
            2,
            3,
        )) {
            if id != u32::MAX {
                value(id, &mut best);
            }
        }
        let radius = self.tree.search_from(
            s32,
            best,
            SETTLE,
            |node| {
                let d2 = node.distance_squared(v);
                if d2 < gap2 {
                    return 0.0;
                }
                let h = node
                    .corners()
                    .iter()
                    .map(|q| sector.support([q[0] - v[0], q[1] - v[1]]))
                    .fold(f64::NEG_INFINITY, f64::max);
                cone_bound(d2, h)
            },
            value,
        ) * SETTLE;
        radius
    }
}

#[cfg(test)]
mod tests;
