//! Edge splitting: an edge longer than the bound in the metric gets a new vertex where
//! its metric length is halved: on the segment for an interior edge, at that fraction of
//! the parameter range on its piece for a constrained edge (so the vertex lies on the original curve, or on its smooth
//! reconstruction). The metric of the new vertex comes from the input field.

use super::work::{key, orient, Work, FREE};
use super::BoundaryMode;

/// Sweeps until no edge is longer than `lmax`: in each, every edge longer than `lmax`,
/// longest first, is split unless one of its triangles was already changed in this sweep
/// (splitting a fresh triangle again in the same sweep would make slivers). After the
/// first sweep only the edges of changed triangles are looked at again. Returns the
/// number of splits.
pub fn split_sweeps(w: &mut Work, lmax: f64) -> usize {
    let mut edges = w.edges();
    let mut n = 0;
    loop {
        let mut cand: Vec<(f64, u32, u32)> =
            edges.iter().map(|&(a, b)| (w.length(a, b), a, b)).filter(|c| c.0 > lmax).collect();
        cand.sort_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let mut touched = vec![false; w.tris.len()];
        let mut k_sweep = 0;
        for (_, a, b) in cand {
            let (ts, k) = w.edge_tris(a, b);
            if k == 0 || k > 2 || ts[..k].iter().any(|&t| touched[t as usize]) {
                continue;
            }
            if split(w, a, b, &ts[..k], &mut touched) {
                k_sweep += 1;
            }
        }
        n += k_sweep;
        if k_sweep == 0 {
            break;
        }
        edges.clear();
        for (t, &hit) in touched.iter().enumerate() {
            if hit {
                let v = w.tris[t];
                for k in 0..3 {
                    edges.push(key(v[k], v[(k + 1) % 3]));
                }
            }
        }
        edges.sort_unstable();
        edges.dedup();
    }
    n
}

/// The fraction of edge `ab` at which its metric length is halved. With the size
/// varying geometrically along the edge (the interpolation of
/// [`crate::conformity::metric_edge_length`]), the length density is la·rˢ with
/// r = lb/la, so the half-length point is t = ln((1 + r)/2)/ln r (½ when r = 1). Splitting
/// at the Euclidean midpoint of a graded edge would leave one half short.
pub fn metric_midpoint(w: &Work, a: u32, b: u32) -> f64 {
    let (pa, pb) = (w.pts[a as usize], w.pts[b as usize]);
    let e = [pb[0] - pa[0], pb[1] - pa[1]];
    let la = w.met[a as usize].quadratic_form(e).max(0.0).sqrt();
    let lb = w.met[b as usize].quadratic_form(e).max(0.0).sqrt();
    if !(la > 0.0 && lb > 0.0) {
        return 0.5;
    }
    let r = lb / la;
    if (r - 1.0).abs() < 1e-6 {
        return 0.5;
    }
    ((0.5 * (1.0 + r)).ln() / r.ln()).clamp(0.1, 0.9)
}

/// Splits edge `ab` held by triangles `ts`; false (nothing changed) when a new triangle
/// would not be strictly counter-clockwise or a new boundary edge would cross a curve.
fn split(w: &mut Work, a: u32, b: u32, ts: &[u32], touched: &mut Vec<bool>) -> bool {
    let piece = w.cons.get(&key(a, b)).copied();
    let (pm, mm, pid, sm) = match piece {
        Some(p) => {
            let near = if w.piece[a as usize] == p {
                w.s[a as usize]
            } else if w.piece[b as usize] == p {
                w.s[b as usize]
            } else {
                0.0
            };
            let (sa, sb) = (w.param_on(a, p, near), w.param_on(b, p, near));
            let sm = sa + metric_midpoint(w, a, b) * (sb - sa);
            let (pm, mm) = w.on_piece(p, sm);
            if w.mode == BoundaryMode::Smooth
                && !(w.bd.chord_clear(p, sa, w.pts[a as usize], sm, pm)
                    && w.bd.chord_clear(p, sm, pm, sb, w.pts[b as usize]))
            {
                return false;
            }
            (pm, mm, p, sm)
        }
        None => {
            let (pa, pb) = (w.pts[a as usize], w.pts[b as usize]);
            let t = metric_midpoint(w, a, b);
            let pm = [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])];
            (pm, w.bg.metric_at(pm), FREE, 0.0)
        }
    };
    // Each triangle (x, y, c) with {x, y} = {a, b} becomes (x, m, c) and (m, y, c).
    let mut plan: Vec<(u32, [u32; 3])> = Vec::with_capacity(2);
    for &t in ts {
        let v = w.tris[t as usize];
        let i = (0..3)
            .find(|&i| (v[i] == a && v[(i + 1) % 3] == b) || (v[i] == b && v[(i + 1) % 3] == a));
        let Some(i) = i else { return false };
        let (x, y, c) = (v[i], v[(i + 1) % 3], v[(i + 2) % 3]);
        let (px, py, pc) = (w.pts[x as usize], w.pts[y as usize], w.pts[c as usize]);
        if orient(px, pm, pc) <= 0.0 || orient(pm, py, pc) <= 0.0 {
            return false;
        }
        plan.push((t, [x, y, c]));
    }
    let m = w.add_vertex(pm, mm, pid, sm);
    for (t, [x, y, c]) in plan {
        let face = w.face[t as usize];
        w.tris[t as usize] = [x, m, c];
        w.detach(y, t);
        w.vtris[m as usize].push(t);
        let t2 = w.add_tri([m, y, c], face);
        touched[t as usize] = true;
        touched.resize(t2 as usize + 1, false);
        touched[t2 as usize] = true;
        w.mark(c);
    }
    w.mark(m);
    if let Some(p) = piece {
        w.cons.remove(&key(a, b));
        w.cons.insert(key(a, m), p);
        w.cons.insert(key(m, b), p);
    }
    true
}
