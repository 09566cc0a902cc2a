//! Edge collapse: a vertex at the end of an edge too short in the metric is merged into
//! the other end. A free vertex may go anywhere its ball allows; a piece vertex only
//! along its own piece (so it stays on its curve and the curve loses no corner); a fixed
//! vertex never goes. Refused when the ball would fold (exact orientation), when the
//! link condition fails (the merge would glue two edges), when a new edge would be
//! longer than the split bound (no split–collapse cycles), when the worst triangle would
//! get worse than the quality floor allows, or when the new boundary edge would cross a
//! curve.

use super::work::{key, orient, Work, DEAD, FIXED, FREE};

/// Sweeps over the edges shorter than `lmin`, shortest first, until none collapses or
/// `max_sweeps` ran; after the first sweep only the edges around merged vertices are
/// looked at again (nothing else changed). Returns the number of collapses.
pub fn collapse_sweeps(w: &mut Work, lmin: f64, lmax: f64, max_sweeps: usize) -> usize {
    let mut edges = w.edges();
    let mut n = 0;
    for _ in 0..max_sweeps {
        let mut cand: Vec<(f64, u32, u32)> =
            edges.iter().map(|&(a, b)| (w.length(a, b), a, b)).filter(|c| c.0 < lmin).collect();
        cand.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let mut hit = Vec::new();
        for (_, a, b) in cand {
            if w.piece[a as usize] == DEAD
                || w.piece[b as usize] == DEAD
                || w.edge_tris(a, b).1 == 0
            {
                continue;
            }
            if collapse(w, a, b, lmax, false)
                || collapse(w, b, a, lmax, false)
                || collapse(w, a, b, lmax, true)
            {
                n += 1;
                hit.push(if w.piece[a as usize] == DEAD { b } else { a });
            }
        }
        if hit.is_empty() {
            break;
        }
        edges = w.edges_around(&hit);
    }
    n
}

/// Merges `a` into `b`; false (nothing changed) when not allowed. With `to_middle`
/// (both ends free), the merged vertex goes to the edge's metric midpoint instead of
/// staying at `b`: the new edges are then about half the short edge shorter, which
/// lets a short edge go where merging onto an end would make too long an edge.
pub fn collapse(w: &mut Work, a: u32, b: u32, lmax: f64, to_middle: bool) -> bool {
    let pa = w.piece[a as usize];
    if pa == FIXED || pa == DEAD {
        return false;
    }
    if to_middle && (pa != FREE || w.piece[b as usize] != FREE) {
        return false;
    }
    let (ts, k) = w.edge_tris(a, b);
    if k == 0 || k > 2 {
        return false;
    }
    let ts = &ts[..k];
    let along = w.cons.get(&key(a, b)).copied();
    // The other end of `a`'s piece edge, for a piece vertex.
    let mut other: Option<u32> = None;
    if pa != FREE {
        if along != Some(pa) {
            return false;
        }
        let Some(nb) = w.curve_neighbours(a) else { return false };
        let c = if nb[0].0 == b {
            nb[1].0
        } else if nb[1].0 == b {
            nb[0].0
        } else {
            return false;
        };
        if c == b {
            return false;
        }
        other = Some(c);
    } else if along.is_some() {
        return false;
    }
    // Link condition.
    let opp: Vec<u32> = ts
        .iter()
        .map(|&t| w.tris[t as usize].into_iter().find(|&x| x != a && x != b).unwrap_or(a))
        .collect();
    let na = w.neighbours(a);
    let nb = w.neighbours(b);
    let common = na.iter().filter(|x| nb.binary_search(x).is_ok()).count();
    if common != opp.len() || opp.iter().any(|x| nb.binary_search(x).is_err()) {
        return false;
    }
    // The balls after the merge, with `b` at `pb` carrying `mb`.
    let (pb, mb) = if to_middle {
        let t = super::split::metric_midpoint(w, a, b);
        let (p, q) = (w.pts[a as usize], w.pts[b as usize]);
        let m = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
        (m, w.bg.metric_at(m))
    } else {
        (w.pts[b as usize], w.met[b as usize])
    };
    let (mut old_min, mut new_min) = (f64::INFINITY, f64::INFINITY);
    let moved: &[u32] = if to_middle { &w.vtris[b as usize] } else { &[] };
    for &t in w.vtris[a as usize].iter().chain(moved) {
        old_min = old_min.min(w.quality(t));
        if ts.contains(&t) {
            continue;
        }
        let v = w.tris[t as usize].map(|x| if x == a { b } else { x });
        let p = v.map(|x| if x == b { pb } else { w.pts[x as usize] });
        if orient(p[0], p[1], p[2]) <= 0.0 {
            return false;
        }
        let ms = v.map(|x| if x == b { mb } else { w.met[x as usize] });
        for (k, &x) in v.iter().enumerate() {
            if x != b && crate::conformity::metric_edge_length(pb, p[k], &mb, &ms[k]) > lmax {
                return false;
            }
        }
        new_min = new_min.min(super::work::op_quality(p, [&ms[0], &ms[1], &ms[2]]));
    }
    if new_min < old_min.min(0.3) {
        return false;
    }
    if let Some(c) = other {
        let sa = w.s[a as usize];
        let (sb, sc) = (w.param_on(b, pa, sa), w.param_on(c, pa, sa));
        if !w.bd.chord_clear(pa, sb, pb, sc, w.pts[c as usize]) {
            return false;
        }
    }
    // Apply.
    for &t in ts {
        w.alive[t as usize] = false;
        for x in w.tris[t as usize] {
            if x != a {
                w.detach(x, t);
            }
        }
    }
    let ball = std::mem::take(&mut w.vtris[a as usize]);
    for t in ball {
        if ts.contains(&t) {
            continue;
        }
        for x in w.tris[t as usize].iter_mut() {
            if *x == a {
                *x = b;
            }
        }
        w.vtris[b as usize].push(t);
    }
    w.piece[a as usize] = DEAD;
    w.pts[b as usize] = pb;
    w.met[b as usize] = mb;
    w.mark_ball(b);
    w.cons.remove(&key(a, b));
    if let Some(c) = other {
        w.cons.remove(&key(a, c));
        w.cons.insert(key(b, c), pa);
    }
    true
}
