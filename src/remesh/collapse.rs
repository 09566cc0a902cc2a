//! Edge collapse: a vertex at the end of an edge too short in the metric is merged into
//! the other end. A free vertex may go anywhere its ball allows; a piece vertex only
//! along its own piece (so it stays on its curve and the curve loses no corner); a fixed
//! vertex never goes. Refused when the ball would fold (exact orientation), when the
//! link condition fails (the merge would glue two edges), when a new edge would be
//! longer than the split bound (no split–collapse cycles), when the worst triangle would
//! get worse than the quality floor allows, when the new boundary edge would stray from
//! the curve it replaces by more than the Hausdorff bound ([`RemeshOptions::hausd`]:
//! so coarsening a curve keeps its shape and the domain's area), when the new edge on a
//! bending stretch of a curve would be longer than the unit length (the area a chord cuts
//! off a curve grows as the cube of its length: coarsening a curve stops at the metric's
//! size, not at the split bound, so the curve keeps as many vertices as its metric asks
//! and no fewer), or when it would cross a curve.
//!
//! As MMG's `chkcol`/`colver`, the operator is a pair: [`check`] reads the mesh and
//! returns a [`CollapsePlan`] (or `None`, having changed nothing); [`apply`] carries a
//! plan out and checks nothing.

use super::options::RemeshOptions;
use super::split::metric_midpoint;
use super::work::{op_quality, orient, Op, Role, Work};
use crate::metric::length::metric_edge_length;
use crate::metric::Sym2;

/// The longest a collapse may make an edge on a bending stretch of a curve: the unit
/// metric length (elsewhere the split bound).
const CURVE_LMAX: f64 = 1.0;

/// A collapse that [`check`] accepted.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CollapsePlan {
    /// The vertex that goes.
    a: u32,
    /// The vertex that stays (and maybe moves).
    b: u32,
    /// The one or two triangles of edge `ab`, which disappear.
    killed: [u32; 2],
    /// How many of `killed` there are.
    nkilled: usize,
    /// Where `b` ends up, and its metric there.
    at: [f64; 2],
    metric: Sym2,
    /// For a piece vertex `a`: its other neighbour `c` along the piece and the piece;
    /// `bc` becomes the constrained edge in place of `ac`.
    relink: Option<(u32, u32)>,
}

/// Sweeps over the edges shorter than `opts.collapse_below`, shortest first, until none
/// collapses or `opts.collapse_sweeps` ran; after the first sweep only the edges around
/// merged vertices are looked at again (nothing else changed). New edges may be no longer
/// than `lmax`. Returns the number of collapses.
pub(super) fn collapse_sweeps(w: &mut Work, lmax: f64, opts: &RemeshOptions) -> usize {
    let mut edges = w.edges();
    let mut n = 0;
    for _ in 0..opts.collapse_sweeps {
        let mut cand: Vec<(f64, u32, u32)> = edges
            .iter()
            .filter_map(|&(a, b)| {
                super::band::length_below(w, a, b, opts.collapse_below).map(|l| (l, a, b))
            })
            .collect();
        // The edges are distinct, so the order is total and an unstable sort gives it.
        cand.sort_unstable_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let mut hit = Vec::new();
        for (_, a, b) in cand {
            if w.is_dead(a) || w.is_dead(b) || w.edge_tris(a, b).1 == 0 {
                continue;
            }
            let floor = opts.quality_floor;
            if w.still_refused(Op::Collapse, a, b) {
                // The brute-force twin: the three checks refuse again.
                debug_assert!(
                    check(w, a, b, lmax, false, floor).is_none()
                        && check(w, b, a, lmax, false, floor).is_none()
                        && check(w, a, b, lmax, true, floor).is_none(),
                    "kept refusal of {a}-{b}"
                );
                continue;
            }
            let plan = check(w, a, b, lmax, false, floor)
                .or_else(|| check(w, b, a, lmax, false, floor))
                .or_else(|| check(w, a, b, lmax, true, floor));
            if let Some(plan) = plan {
                let kept = plan.b;
                apply(w, &plan);
                n += 1;
                hit.push(kept);
            } else {
                w.refuse(Op::Collapse, a, b);
            }
        }
        if hit.is_empty() {
            break;
        }
        edges = w.edges_around(&hit);
    }
    n
}

/// Whether `a` may be merged into `b`, and how. With `to_middle` (both ends free), the
/// merged vertex goes to the edge's metric midpoint instead of staying at `b`: the new
/// edges are then about half the short edge shorter, which lets a short edge go where
/// merging onto an end would make too long an edge. New edges may be no longer than
/// `lmax`; the worst triangle of the ball may not drop below the smaller of its worst
/// before and `floor`.
pub(super) fn check(
    w: &Work,
    a: u32,
    b: u32,
    lmax: f64,
    to_middle: bool,
    floor: f64,
) -> Option<CollapsePlan> {
    let ra = w.role(a);
    if matches!(ra, Role::Fixed | Role::Dead) {
        return None;
    }
    if to_middle && (ra != Role::Free || w.role(b) != Role::Free) {
        return None;
    }
    let (killed, nkilled) = w.edge_tris(a, b);
    if nkilled == 0 || nkilled > 2 {
        return None;
    }
    let ts = &killed[..nkilled];
    let along = w.constraint(a, b);
    // The other end of `a`'s piece edge, for a piece vertex.
    let mut relink: Option<(u32, u32)> = None;
    if let Role::Slides { piece: pa, .. } = ra {
        if along != Some(pa) {
            return None;
        }
        let nb = w.curve_neighbours(a)?;
        let c = if nb[0].0 == b {
            nb[1].0
        } else if nb[1].0 == b {
            nb[0].0
        } else {
            return None;
        };
        if c == b {
            return None;
        }
        relink = Some((c, pa));
    } else if along.is_some() {
        return None;
    }
    // Link condition: the corners opposite `ab` are joined to both ends by
    // construction; no other vertex may be.
    if w.common_neighbours(a, b) != nkilled {
        return None;
    }
    // The balls after the merge, with `b` at `pb` carrying `mb`.
    let (pb, mb) = if to_middle {
        let t = metric_midpoint(w, a, b);
        let (p, q) = (w.point(a), w.point(b));
        let m = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
        (m, w.background().metric_at(m))
    } else {
        (w.point(b), w.metric(b))
    };
    let moved: &[u32] = if to_middle { w.ball(b) } else { &[] };
    // The worst quality before, from the kept qualities: a triangle after the merge below
    // `worst` refuses the collapse at once, the outcome the whole scan would give.
    let old_min =
        w.ball(a).iter().chain(moved).map(|&t| w.quality(t)).fold(f64::INFINITY, f64::min);
    let worst = old_min.min(floor);
    let mut new_min = f64::INFINITY;
    for &t in w.ball(a).iter().chain(moved) {
        if ts.contains(&t) {
            continue;
        }
        let v = w.tri(t).map(|x| if x == a { b } else { x });
        let p = v.map(|x| if x == b { pb } else { w.point(x) });
        if orient(p[0], p[1], p[2]) <= 0.0 {
            return None;
        }
        let ms = v.map(|x| if x == b { mb } else { w.metric(x) });
        let q = op_quality(p, [&ms[0], &ms[1], &ms[2]]);
        if q < worst {
            return None;
        }
        for (k, &x) in v.iter().enumerate() {
            if x != b && metric_edge_length(pb, p[k], &mb, &ms[k]) > lmax {
                return None;
            }
        }
        new_min = new_min.min(q);
    }
    if new_min < worst {
        return None;
    }
    if let (Some((c, pa)), Role::Slides { s: sa, .. }) = (relink, ra) {
        let (sb, sc) = (w.param_on(b, pa, sa), w.param_on(c, pa, sa));
        let piece = &w.boundary().pieces[pa as usize];
        let bent_long = piece.bends_between(sb, sc)
            && metric_edge_length(pb, w.point(c), &mb, &w.metric(c)) > CURVE_LMAX;
        if bent_long
            || piece.deviation(sb, sc, pb, w.point(c), w.mode()) > w.hausd()
            || !w.boundary().chord_clear(pa, sb, pb, sc, w.point(c))
        {
            return None;
        }
    }
    Some(CollapsePlan { a, b, killed, nkilled, at: pb, metric: mb, relink })
}

/// Carries out a plan of [`check`] on the mesh it was made on.
pub(super) fn apply(w: &mut Work, plan: &CollapsePlan) {
    let CollapsePlan { a, b, .. } = *plan;
    for &t in &plan.killed[..plan.nkilled] {
        w.kill_tri(t);
    }
    for t in w.ball(a).to_vec() {
        let v = w.tri(t).map(|x| if x == a { b } else { x });
        w.set_tri(t, v);
    }
    w.kill_vertex(a);
    w.place(b, plan.at, plan.metric, w.role(b));
    w.mark_ball(b);
    w.unconstrain(a, b);
    if let Some((c, piece)) = plan.relink {
        w.unconstrain(a, c);
        w.constrain(b, c, piece);
    }
}
