//! Vertex smoothing: a free vertex moves toward the mean of the places that would make
//! each triangle of its ball equilateral in the metric; a piece vertex slides along
//! its piece to the parameter that equalises the metric lengths of its two piece edges.
//! A move is kept only when every triangle of the ball stays strictly counter-clockwise
//! and the worst of them gets better (or stays and the ball's summed quality rises); the metric at the new place comes from the input
//! field.

use super::work::{orient, Work, DEAD, FIXED, FREE};
use crate::metric::Sym2;

/// Relative gain of the worst ball quality a move must bring: smaller gains are not
/// worth the work they cause (every move re-opens its ball for the swaps).
const GAIN: f64 = 1e-3;

/// Below this worst ball quality a vertex gets more candidate places (rare, and where
/// the minimum quality of the mesh is decided).
const POOR: f64 = 0.8;

/// One sweep over the active vertices (those whose ball changed since they were last
/// tried) in index order; a vertex that moves activates its neighbours. Returns the
/// number of moves.
pub fn smooth_sweep(w: &mut Work) -> usize {
    let mut n = 0;
    for v in 0..w.pts.len() as u32 {
        if !w.active[v as usize] {
            continue;
        }
        w.active[v as usize] = false;
        let p = w.piece[v as usize];
        if p == FIXED || p == DEAD || w.vtris[v as usize].is_empty() {
            continue;
        }
        if if p == FREE { smooth_free(w, v) } else { smooth_on_piece(w, v) } {
            n += 1;
            w.mark_ball(v);
            w.active[v as usize] = false;
        }
    }
    n
}

/// The worst and the summed quality of `v`'s ball.
fn ball_quality(w: &Work, v: u32) -> (f64, f64) {
    w.vtris[v as usize]
        .iter()
        .map(|&t| w.quality(t))
        .fold((f64::INFINITY, 0.0), |(m, s), q| (m.min(q), s + q))
}

/// Whether a ball with worst and summed quality `new` is better than `old`: a better
/// worst triangle, or the same worst (not lower) and a better sum.
fn better(new: (f64, f64), old: (f64, f64)) -> bool {
    new.0 > old.0 * (1.0 + GAIN) || (new.0 >= old.0 && new.1 > old.1 * (1.0 + GAIN))
}

/// The worst and summed quality of `v`'s ball with `v` at `p` carrying `m`, or `None`
/// when a triangle would not be strictly counter-clockwise.
fn ball_quality_at(w: &Work, v: u32, p: [f64; 2], m: &Sym2) -> Option<(f64, f64)> {
    let (mut q, mut sum) = (f64::INFINITY, 0.0);
    for &t in &w.vtris[v as usize] {
        let tri = w.tris[t as usize];
        let pts = tri.map(|x| if x == v { p } else { w.pts[x as usize] });
        if orient(pts[0], pts[1], pts[2]) <= 0.0 {
            return None;
        }
        let ms = tri.map(|x| if x == v { *m } else { w.met[x as usize] });
        let x = super::work::op_quality(pts, [&ms[0], &ms[1], &ms[2]]);
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

fn smooth_free(w: &mut Work, v: u32) -> bool {
    let p = w.pts[v as usize];
    // The mean of the ideal apexes over the ball, each in its triangle's metric.
    let (mut sx, mut sy, mut k) = (0.0, 0.0, 0usize);
    for &t in &w.vtris[v as usize] {
        let tri = w.tris[t as usize];
        let i = tri.iter().position(|&x| x == v).unwrap_or(0);
        let (a, b) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
        let m = (1.0 / 3.0) * (w.met[v as usize] + w.met[a as usize] + w.met[b as usize]);
        let q = ideal_apex(w.pts[a as usize], w.pts[b as usize], &m);
        sx += q[0];
        sy += q[1];
        k += 1;
    }
    if k == 0 {
        return false;
    }
    let target = [sx / k as f64, sy / k as f64];
    let old = ball_quality(w, v);
    let mut cands = vec![target, [0.5 * (p[0] + target[0]), 0.5 * (p[1] + target[1])]];
    if old.0 < POOR {
        // A poor ball: also try the place that makes its worst triangle equilateral,
        // and halfway there; the best of all candidates wins.
        if let Some(worst) = w.vtris[v as usize]
            .iter()
            .copied()
            .min_by(|&x, &y| w.quality(x).total_cmp(&w.quality(y)))
        {
            let tri = w.tris[worst as usize];
            let i = tri.iter().position(|&x| x == v).unwrap_or(0);
            let (a, b) = (tri[(i + 1) % 3], tri[(i + 2) % 3]);
            let m = (1.0 / 3.0) * (w.met[v as usize] + w.met[a as usize] + w.met[b as usize]);
            let q = ideal_apex(w.pts[a as usize], w.pts[b as usize], &m);
            cands.push(q);
            cands.push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
            cands.push([0.5 * (target[0] + q[0]), 0.5 * (target[1] + q[1])]);
        }
    }
    let mut best: Option<([f64; 2], Sym2, (f64, f64))> = None;
    for np in cands {
        let nm = w.bg.metric_at(np);
        if let Some(q) = ball_quality_at(w, v, np, &nm) {
            if better(q, old) && best.as_ref().map_or(true, |b| better(q, b.2)) {
                best = Some((np, nm, q));
                if old.0 >= POOR {
                    break;
                }
            }
        }
    }
    if let Some((np, nm, _)) = best {
        w.pts[v as usize] = np;
        w.met[v as usize] = nm;
        return true;
    }
    false
}

fn smooth_on_piece(w: &mut Work, v: u32) -> bool {
    let Some([(u, su), (x, sx)]) = w.curve_neighbours(v) else { return false };
    let pid = w.piece[v as usize];
    let sv = w.s[v as usize];
    if !(su < sv && sv < sx) {
        return false;
    }
    let (l1, l2) = (w.length(u, v), w.length(v, x));
    // With the density constant on each side, lengths scale with the parameter: solve
    // l1·(t − su)/(sv − su) = l2·(sx − t)/(sx − sv).
    let (ka, kb) = (l1 / (sv - su), l2 / (sx - sv));
    if !(ka > 0.0 && kb > 0.0) {
        return false;
    }
    let target = (ka * su + kb * sx) / (ka + kb);
    let old = ball_quality(w, v);
    let mut cands = vec![target, 0.5 * (sv + target)];
    if old.0 < POOR {
        // A poor ball: also sample the parameter range between the neighbours.
        cands.extend((1..8).map(|i| su + (sx - su) * i as f64 / 8.0));
    }
    // (parameter, place, metric, (worst, summed) quality)
    type Candidate = (f64, [f64; 2], Sym2, (f64, f64));
    let mut best: Option<Candidate> = None;
    for t in cands {
        if !(su < t && t < sx) {
            continue;
        }
        let (np, nm) = w.on_piece(pid, t);
        if let Some(q) = ball_quality_at(w, v, np, &nm) {
            if better(q, old)
                && best.as_ref().map_or(true, |b| better(q, b.3))
                && w.bd.chord_clear(pid, su, w.pts[u as usize], t, np)
                && w.bd.chord_clear(pid, t, np, sx, w.pts[x as usize])
            {
                best = Some((t, np, nm, q));
                if old.0 >= POOR {
                    break;
                }
            }
        }
    }
    if let Some((t, np, nm, _)) = best {
        w.pts[v as usize] = np;
        w.met[v as usize] = nm;
        w.s[v as usize] = t;
        return true;
    }
    false
}
