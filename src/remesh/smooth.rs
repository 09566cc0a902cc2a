//! Vertex smoothing: a free vertex moves toward the mean of the places that would make
//! each triangle of its ball equilateral in the metric; a piece vertex slides along
//! its piece to the parameter that equalises the metric lengths of its two piece edges,
//! unless its piece edges would then stray from the curve past the Hausdorff bound.
//! A move is kept only when every triangle of the ball stays strictly counter-clockwise
//! and the worst of them gets better (or stays and the ball's summed quality rises); the
//! metric at the new place comes from the input field.
//!
//! [`check`] returns the [`Move`] (or `None`); [`apply`] makes it.

use super::options::RemeshOptions;
use super::work::{op_quality, orient, Role, Work};
use crate::metric::Sym2;

/// A move that [`check`] accepted: `v` goes to `at` with metric `metric` and role
/// `role` (a sliding vertex's new parameter).
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Move {
    v: u32,
    at: [f64; 2],
    metric: Sym2,
    role: Role,
}

/// The two thresholds of a move: the relative gain of the worst ball quality it must
/// bring (smaller gains are not worth the work they cause: every move re-opens its ball
/// for the swaps), and the worst ball quality below which a vertex gets more candidate
/// places (rare, and where the minimum quality of the mesh is decided).
#[derive(Debug, Clone, Copy)]
struct Thresholds {
    gain: f64,
    poor: f64,
}

/// One sweep over the active vertices (those whose ball changed since they were last
/// tried) in index order; a vertex that moves activates its neighbours. Returns the
/// number of moves.
pub(super) fn smooth_sweep(w: &mut Work, opts: &RemeshOptions) -> usize {
    let mut n = 0;
    for v in 0..w.num_vertices() as u32 {
        if !w.take_active(v) {
            continue;
        }
        if let Some(m) = check(w, v, opts) {
            apply(w, &m);
            n += 1;
        }
    }
    n
}

/// Where `v` should go, if anywhere: fixed and dead vertices and those no triangle uses
/// stay.
pub(super) fn check(w: &Work, v: u32, opts: &RemeshOptions) -> Option<Move> {
    if w.ball(v).is_empty() {
        return None;
    }
    let th = Thresholds { gain: opts.smooth_gain, poor: opts.smooth_poor };
    match w.role(v) {
        Role::Free => plan_free(w, v, th),
        Role::Slides { piece, s } => plan_on_piece(w, v, piece, s, th),
        Role::Fixed | Role::Dead => None,
    }
}

/// Makes a move of [`check`]; the edges around `v` are marked for the swaps and its
/// neighbours for the next sweep, `v` itself is not tried again before its ball changes.
pub(super) fn apply(w: &mut Work, m: &Move) {
    w.place(m.v, m.at, m.metric, m.role);
    w.mark_moved(m.v);
    w.take_active(m.v);
}

/// The worst and the summed quality of `v`'s ball.
fn ball_quality(w: &Work, v: u32) -> (f64, f64) {
    w.ball(v)
        .iter()
        .map(|&t| w.quality(t))
        .fold((f64::INFINITY, 0.0), |(m, s), q| (m.min(q), s + q))
}

/// Whether a ball with worst and summed quality `new` is better than `old`: a better
/// worst triangle, or the same worst (not lower) and a better sum.
fn better(new: (f64, f64), old: (f64, f64), gain: f64) -> bool {
    new.0 > old.0 * (1.0 + gain) || (new.0 >= old.0 && new.1 > old.1 * (1.0 + gain))
}

/// The worst and summed quality of `v`'s ball with `v` at `p` carrying `m`, or `None`
/// when a triangle would not be strictly counter-clockwise or would be worse than
/// `floor`. A place whose worst triangle is below the worst of the ball now (or of the
/// best place so far) is never [`better`], so the callers pass that as `floor` and the
/// scan of the ball stops at the first triangle below it, with the same outcome.
fn ball_quality_at(w: &Work, v: u32, p: [f64; 2], m: &Sym2, floor: f64) -> Option<(f64, f64)> {
    let (mut q, mut sum) = (f64::INFINITY, 0.0);
    for &t in w.ball(v) {
        let tri = w.tri(t);
        let pts = tri.map(|x| if x == v { p } else { w.point(x) });
        if orient(pts[0], pts[1], pts[2]) <= 0.0 {
            return None;
        }
        let ms = tri.map(|x| if x == v { *m } else { w.metric(x) });
        let x = op_quality(pts, [&ms[0], &ms[1], &ms[2]]);
        if x < floor {
            return None;
        }
        q = q.min(x);
        sum += x;
    }
    Some((q, sum))
}

/// The place that makes triangle (·, a, b) equilateral in the metric `m`, on the left of
/// a→b: the midpoint plus √3/2 of the edge turned by a right angle *in the metric*
/// (J = adj(M)·R₉₀/√det M turns by 90° and keeps metric lengths).
fn ideal_apex(a: [f64; 2], b: [f64; 2], m: &Sym2) -> [f64; 2] {
    let e = [b[0] - a[0], b[1] - a[1]];
    let k = 0.5 * 3f64.sqrt() / m.det().max(f64::MIN_POSITIVE).sqrt();
    let je = [(-m.b * e[0] - m.c * e[1]) * k, (m.a * e[0] + m.b * e[1]) * k];
    [0.5 * (a[0] + b[0]) + je[0], 0.5 * (a[1] + b[1]) + je[1]]
}

fn plan_free(w: &Work, v: u32, th: Thresholds) -> Option<Move> {
    let p = w.point(v);
    // The mean of the ideal apexes over the ball, each in its triangle's metric.
    let (mut sx, mut sy, mut k) = (0.0, 0.0, 0usize);
    for &t in w.ball(v) {
        let tri = w.tri(t);
        let i = tri.iter().position(|&x| x == v).unwrap_or(0);
        let (a, b) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
        let m = (1.0 / 3.0) * (w.metric(v) + w.metric(a) + w.metric(b));
        let q = ideal_apex(w.point(a), w.point(b), &m);
        sx += q[0];
        sy += q[1];
        k += 1;
    }
    if k == 0 {
        return None;
    }
    let target = [sx / k as f64, sy / k as f64];
    let old = ball_quality(w, v);
    let mut cands = vec![target, [0.5 * (p[0] + target[0]), 0.5 * (p[1] + target[1])]];
    if old.0 < th.poor {
        // A poor ball: also try the place that makes its worst triangle equilateral,
        // and halfway there; the best of all candidates wins.
        if let Some(worst) =
            w.ball(v).iter().copied().min_by(|&x, &y| w.quality(x).total_cmp(&w.quality(y)))
        {
            let tri = w.tri(worst);
            let i = tri.iter().position(|&x| x == v).unwrap_or(0);
            let (a, b) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
            let m = (1.0 / 3.0) * (w.metric(v) + w.metric(a) + w.metric(b));
            let q = ideal_apex(w.point(a), w.point(b), &m);
            cands.push(q);
            cands.push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
            cands.push([0.5 * (target[0] + q[0]), 0.5 * (target[1] + q[1])]);
        }
    }
    let mut best: Option<([f64; 2], Sym2, (f64, f64))> = None;
    for np in cands {
        let nm = w.background().metric_at(np);
        let floor = best.as_ref().map_or(old.0, |b| old.0.max(b.2 .0));
        if let Some(q) = ball_quality_at(w, v, np, &nm, floor) {
            if better(q, old, th.gain) && best.as_ref().map_or(true, |b| better(q, b.2, th.gain)) {
                best = Some((np, nm, q));
                if old.0 >= th.poor {
                    break;
                }
            }
        }
    }
    best.map(|(at, metric, _)| Move { v, at, metric, role: Role::Free })
}

fn plan_on_piece(w: &Work, v: u32, pid: u32, sv: f64, th: Thresholds) -> Option<Move> {
    let [(u, su), (x, sx)] = w.curve_neighbours(v)?;
    if !(su < sv && sv < sx) {
        return None;
    }
    let (l1, l2) = (w.length(u, v), w.length(v, x));
    // With the density constant on each side, lengths scale with the parameter: solve
    // l1·(t − su)/(sv − su) = l2·(sx − t)/(sx − sv).
    let (ka, kb) = (l1 / (sv - su), l2 / (sx - sv));
    if !(ka > 0.0 && kb > 0.0) {
        return None;
    }
    let target = (ka * su + kb * sx) / (ka + kb);
    let old = ball_quality(w, v);
    let mut cands = vec![target, 0.5 * (sv + target)];
    if old.0 < th.poor {
        // A poor ball: also sample the parameter range between the neighbours.
        cands.extend((1..8).map(|i| su + (sx - su) * i as f64 / 8.0));
    }
    // (parameter, place, metric, (worst, summed) quality)
    type Candidate = (f64, [f64; 2], Sym2, (f64, f64));
    let mut best: Option<Candidate> = None;
    let bd = w.boundary();
    let piece = &bd.pieces[pid as usize];
    let (pu, px) = (w.point(u), w.point(x));
    // How far the two piece edges stray from the curve with `v` at parameter `t`, place
    // `p`: a move may not take them past the Hausdorff bound (nor further past it).
    let stray = |t: f64, p: [f64; 2]| {
        piece.deviation(su, t, pu, p, w.mode()).max(piece.deviation(t, sx, p, px, w.mode()))
    };
    let mut now: Option<f64> = None;
    let mut within = |t: f64, p: [f64; 2]| {
        let d = stray(t, p);
        d <= w.hausd() || d <= *now.get_or_insert_with(|| stray(sv, w.point(v)))
    };
    for t in cands {
        if !(su < t && t < sx) {
            continue;
        }
        let (np, nm) = w.on_piece(pid, t);
        let floor = best.as_ref().map_or(old.0, |b| old.0.max(b.3 .0));
        if let Some(q) = ball_quality_at(w, v, np, &nm, floor) {
            if better(q, old, th.gain)
                && best.as_ref().map_or(true, |b| better(q, b.3, th.gain))
                && bd.chord_clear(pid, su, pu, t, np)
                && bd.chord_clear(pid, t, np, sx, px)
                && within(t, np)
            {
                best = Some((t, np, nm, q));
                if old.0 >= th.poor {
                    break;
                }
            }
        }
    }
    best.map(|(s, at, metric, _)| Move { v, at, metric, role: Role::Slides { piece: pid, s } })
}
