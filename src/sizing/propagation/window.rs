//! Polyline geometry of a closest point: its *window* (the segments around it along the
//! polyline whose closest points a clearance certificate compares), the march of a guess
//! along the polyline, and [`settle`], which turns a guess into the exact closest point.
//!
//! The window is [`WINDOW`] segments either way from a foot inside a segment, and
//! [`WINDOW`] either side of a polyline vertex for a foot on it: the window the
//! clearances of [`crate::geometry::clearance`] are computed for, from the one constant.
//! A clearance certifies the best of the window only; past it, or before the segment
//! has earned its clearance, an exact search decides. So [`settle`] returns the exact
//! closest point (ties: smaller segment id) whatever the guess; the guess changes only
//! the work done.

use super::source::Source;
use crate::geometry::clearance::WINDOW;
use crate::geometry::segment::orient;
use crate::geometry::{Clearance, Nearest, Point2, QueryStats};

/// Steps of the march along the polyline from a guess, and rounds of moves to the best
/// of the window.
const MARCH_STEPS: usize = 4;

/// The closest segment a vertex settled on, and how.
pub(super) struct Evaluation {
    pub(super) nearest: Nearest,
    pub(super) corrected: bool,
    pub(super) local: bool,
    pub(super) stats: QueryStats,
}

impl Source {
    /// The segments whose closest points must be compared with `best`'s before its
    /// clearance can decide: [`WINDOW`] segments either way from its segment when the
    /// foot is inside it, [`WINDOW`] either side of the vertex (its own segment among
    /// them) when the foot is a polyline vertex. Past a polyline's end the entry is the
    /// last segment reached, and the entries left over are `best`'s own segment, so
    /// that a caller projects on all of them with no test: a projection made again
    /// changes nothing.
    #[inline]
    pub(super) fn window(&self, best: &Nearest) -> [u32; 2 * WINDOW] {
        let s = best.segment;
        let t = best.projection.t;
        let (behind, ahead) = if t > 0.0 && t < 1.0 {
            (WINDOW, WINDOW)
        } else if t == 0.0 {
            (WINDOW, WINDOW - 1)
        } else {
            (WINDOW - 1, WINDOW)
        };
        let mut out = [s; 2 * WINDOW];
        let mut at = s;
        for slot in &mut out[..behind] {
            at = self.segments[at as usize].prev.unwrap_or(at);
            *slot = at;
        }
        let mut at = s;
        for slot in &mut out[behind..behind + ahead] {
            at = self.segments[at as usize].next.unwrap_or(at);
            *slot = at;
        }
        out
    }

    /// The sides of segment `s` (bit 0 left, bit 1 right) behind which the rest of its
    /// window lies: every other segment of the window on the far side of the line of
    /// `s` or on it (the exact orientation predicate), and beyond the span of `s` along
    /// it (the segments after `s` past its end, those before it short of its start).
    /// Convex sides of a border and straight runs have both; a side into which the
    /// polyline turns has neither.
    pub(super) fn window_sides_behind(&self, s: usize) -> u8 {
        let g = &self.geoms[s];
        if g.inv_len2 == 0.0 {
            return 0;
        }
        let (a, b) = (g.a, g.b);
        // Along the line of s: ahead of b, or before a, clearly (or the shared end itself).
        let beyond = |q: Point2, from: Point2, sign: f64| {
            if q == from {
                return true;
            }
            let dot = sign * ((q[0] - from[0]) * g.d[0] + (q[1] - from[1]) * g.d[1]);
            let scale =
                ((q[0] - from[0]).abs() + (q[1] - from[1]).abs()) * (g.d[0].abs() + g.d[1].abs());
            dot > 1e-9 * scale
        };
        let mut sides = 3u8;
        let mut check = |w: u32, forward: bool| {
            if w as usize == s {
                return;
            }
            let gw = &self.geoms[w as usize];
            for q in [gw.a, gw.b] {
                let along = if forward { beyond(q, b, 1.0) } else { beyond(q, a, -1.0) };
                if !along {
                    sides = 0;
                }
                let o = orient(a, b, q);
                if o > 0.0 {
                    sides &= !1;
                } else if o < 0.0 {
                    sides &= !2;
                }
            }
        };
        for forward in [false, true] {
            let mut at = s as u32;
            for _ in 0..WINDOW {
                let step = if forward {
                    self.segments[at as usize].next
                } else {
                    self.segments[at as usize].prev
                };
                match step {
                    Some(w) => {
                        check(w, forward);
                        at = w;
                    }
                    None => break,
                }
            }
        }
        sides
    }

    /// Whether no other segment of `best`'s window can be as close to `p` as `best`,
    /// with no projection on them: the foot lies inside the segment, `p` is on a side
    /// behind which the rest of the window lies ([`Source::window_sides_behind`]), and
    /// the foot is far enough from both ends. Then every point of those segments is at
    /// least `sqrt(y² + m²)` from `p`, `y` its distance to the line and `m` the foot's
    /// distance to the nearer end, and `m² >= 2·10^-12 (d² + len²)` puts that far
    /// beyond the rounding of any computed distance (a few ulps of `d²`), so a scan
    /// computes them all larger, as the projections would.
    #[inline]
    pub(super) fn window_behind(&self, p: Point2, best: &Nearest) -> bool {
        let t = best.projection.t;
        let bits = self.behind[best.segment as usize];
        if bits == 0 || !(t > 0.0 && t < 1.0) {
            return false;
        }
        let g = &self.geoms[best.segment as usize];
        let cr = g.d[0] * (p[1] - g.a[1]) - g.d[1] * (p[0] - g.a[0]);
        let bit = if cr > 0.0 {
            1
        } else if cr < 0.0 {
            2
        } else {
            return false;
        };
        let len2 = g.d[0] * g.d[0] + g.d[1] * g.d[1];
        let m = t.min(1.0 - t);
        bits & bit != 0 && m * m * len2 >= 2e-12 * (best.projection.distance_squared + len2)
    }

    /// Whether `best`, the best of its window for `p`, is the closest point of the
    /// whole source by the clearance of its segment or vertex (within 0.999 of it, see
    /// [`Clearance`]).
    #[inline]
    pub(super) fn certified(&self, clearance: &Clearance, p: Point2, best: &Nearest) -> bool {
        let s = best.segment;
        let t = best.projection.t;
        let d = best.projection.distance_squared.sqrt();
        // A point on the source: a clearance of 0 (another curve touching there, whose
        // segments lie outside the window) would still cover it, and a segment of a
        // smaller id at distance 0 too may lie outside the window. The search decides.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(d > 0.0) {
            return false;
        }
        if t > 0.0 && t < 1.0 {
            return clearance.covers_segment(s, p, d);
        }
        match if t == 0.0 { self.segments[s as usize].prev } else { Some(s) } {
            Some(into) => clearance.covers_vertex(into, p, d),
            None => false,
        }
    }
}

/// The projection of `p` on segment `q`, counted in `stats`.
#[inline]
fn project(source: &Source, p: Point2, q: u32, stats: &mut QueryStats) -> Nearest {
    stats.segments += 1;
    Nearest { segment: q, projection: source.geoms[q as usize].project(p) }
}

/// Moves `best` along the polyline while its foot is an end of its segment and the
/// segment across that end is closer.
#[inline]
fn march_across_ends(source: &Source, p: Point2, best: &mut Nearest, stats: &mut QueryStats) {
    for _ in 0..MARCH_STEPS {
        let s = &source.segments[best.segment as usize];
        let step = if best.projection.t == 0.0 {
            s.prev
        } else if best.projection.t == 1.0 {
            s.next
        } else {
            None
        };
        let Some(q) = step else { break };
        let c = project(source, p, q, stats);
        if c.beats(best) {
            *best = c;
        } else {
            break;
        }
    }
}

/// The exact closest point of `p` from the guess `seg`: settled on a local optimum along
/// the polyline, then certified by the clearance of its segment or vertex (where
/// `clearance_if_it_pays` gives the clearances for the segment reached), or else by an
/// index search.
#[inline]
pub(super) fn settle<'c>(
    source: &Source,
    p: Point2,
    seg: u32,
    clearance_if_it_pays: impl FnOnce(u32) -> Option<&'c Clearance>,
) -> Evaluation {
    let mut stats = QueryStats::default();
    let mut best = project(source, p, seg, &mut stats);
    // First march along the polyline while the foot sits on a segment end (thesis
    // 4.3.6.3): one projection a step, where the window would take three, and the
    // usual way off a guess, since a neighbour's segment often ends just short of the
    // vertex's foot. Then move to the best segment of the window until it is the best
    // of its own window, and try the clearance; else search.
    march_across_ends(source, p, &mut best, &mut stats);
    if let Some(clearance) = clearance_if_it_pays(best.segment) {
        for _ in 0..MARCH_STEPS {
            let mut moved = false;
            if !source.window_behind(p, &best) {
                // All four, with no test of which were projected before (the march's)
                // or are repeats: the tests mispredicted more than the projections cost.
                for q in source.window(&best) {
                    let c = project(source, p, q, &mut stats);
                    if c.beats(&best) {
                        best = c;
                        moved = true;
                    }
                }
            }
            if !moved {
                if source.certified(clearance, p, &best) {
                    return Evaluation { nearest: best, corrected: false, local: true, stats };
                }
                break;
            }
        }
        // Beyond the clearance, far from the source: the oriented boxes.
        let nearest = clearance.closest(p, best, &mut stats);
        return Evaluation {
            nearest,
            corrected: nearest.projection.distance_squared < best.projection.distance_squared,
            local: false,
            stats,
        };
    }
    // Near the source: the axis-aligned index around the guess's leaf.
    let nearest = source.index().certify(p, best, &mut stats);
    Evaluation {
        nearest,
        corrected: nearest.projection.distance_squared < best.projection.distance_squared,
        local: false,
        stats,
    }
}
