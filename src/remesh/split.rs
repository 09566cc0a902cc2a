//! Edge splitting: an edge longer than the bound in the metric gets a new vertex where
//! its metric length is halved: on the segment for an interior edge, at that fraction of
//! the parameter range on its piece for a constrained edge (so the vertex lies on the
//! original curve, or on its smooth reconstruction); the edges of kept cells (frozen
//! pieces) are never split. The metric of the new vertex comes
//! from the input field.
//!
//! [`check`] returns a [`SplitPlan`] (the new vertex and the triangles it cuts) or
//! `None`; [`apply`] carries it out.

use super::options::BoundaryMode;
use super::work::{key, orient, Op, Role, Work};
use crate::metric::Sym2;

/// A split that [`check`] accepted.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SplitPlan {
    /// The edge.
    a: u32,
    b: u32,
    /// The new vertex: place, metric, role.
    at: [f64; 2],
    metric: Sym2,
    role: Role,
    /// Each triangle `t` of the edge as `(t, [x, y, c])`, with `xy` the edge in the
    /// triangle's order and `c` the opposite corner; it becomes `(x, m, c)` and
    /// `(m, y, c)`.
    halves: [(u32, [u32; 3]); 2],
    /// How many of `halves` there are.
    n: usize,
}

/// The vertex limit of a split phase was passed (the caller turns it into an error).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct LimitReached;

/// Sweeps until no edge is longer than `lmax`: in each, every edge longer than `lmax`,
/// longest first, is split unless one of its triangles was already changed in this sweep
/// (splitting a fresh triangle again in the same sweep would make slivers). After each
/// sweep that split something, `between` may edit the mesh (the remesher flips
/// diagonals there, so that the next sweep cuts metric-shaped triangles rather than
/// the fans the previous cuts made) and returns the vertices whose balls it changed.
/// After the first sweep only the edges of changed triangles and around those vertices
/// are looked at again. With `since`, the tick at which the previous split phase
/// started, the first sweep looks only at the edges around the vertices stamped after it:
/// every other edge is as that phase left it, short or refused (and [`Work::still_refused`]
/// would skip it), so the splits are those a sweep over every edge makes, and a late pass
/// costs what it changes. Returns the number of splits, or [`LimitReached`] as soon as the
/// mesh has more than `cap` vertices.
pub(super) fn split_sweeps(
    w: &mut Work,
    lmax: f64,
    cap: usize,
    since: Option<u64>,
    between: &mut dyn FnMut(&mut Work) -> Vec<u32>,
) -> Result<usize, LimitReached> {
    let mut edges = match since {
        None => w.edges(),
        Some(t) => {
            // Past a quarter of the vertices, listing every edge costs less than
            // gathering and sorting the edges around them; the sweep is the same.
            let changed = w.changed_since(t);
            let full = 4 * changed.len() > w.num_vertices();
            let edges = if full { w.edges() } else { w.edges_around(&changed) };
            #[cfg(debug_assertions)]
            for (a, b) in if full { Vec::new() } else { w.edges() } {
                // Every long edge left out is one whose refusal still holds.
                debug_assert!(
                    w.length(a, b) <= lmax
                        || edges.binary_search(&(a, b)).is_ok()
                        || w.still_refused(Op::Split, a, b),
                    "long edge {a}-{b} left out"
                );
            }
            edges
        }
    };
    let mut n = 0;
    loop {
        let mut cand: Vec<(f64, u32, u32)> = edges
            .iter()
            .filter_map(|&(a, b)| super::band::length_above(w, a, b, lmax).map(|l| (l, a, b)))
            .collect();
        // The edges are distinct, so the order is total and an unstable sort gives it.
        cand.sort_unstable_by(|x, y| y.0.total_cmp(&x.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        let mut touched = vec![false; w.num_slots()];
        let mut k_sweep = 0;
        for (_, a, b) in cand {
            let (ts, k) = w.edge_tris(a, b);
            if k == 0 || k > 2 || ts[..k].iter().any(|&t| touched[t as usize]) {
                continue;
            }
            if w.still_refused(Op::Split, a, b) {
                // The brute-force twin: the check itself refuses again.
                debug_assert!(check(w, a, b, &ts[..k]).is_none(), "kept refusal of {a}-{b}");
                continue;
            }
            match check(w, a, b, &ts[..k]) {
                Some(plan) => {
                    if w.num_vertices() >= cap {
                        return Err(LimitReached);
                    }
                    apply(w, &plan, &mut touched);
                    k_sweep += 1;
                }
                None => w.refuse(Op::Split, a, b),
            }
        }
        n += k_sweep;
        if k_sweep == 0 {
            break;
        }
        let moved = between(w);
        edges = w.edges_around(&moved);
        for (t, &hit) in touched.iter().enumerate() {
            if hit {
                let v = w.tri(t as u32);
                for k in 0..3 {
                    edges.push(key(v[k], v[(k + 1) % 3]));
                }
            }
        }
        w.sort_edges(&mut edges);
    }
    Ok(n)
}

/// The fraction of edge `ab` at which its metric length is halved. With the size
/// varying geometrically along the edge (the interpolation of
/// [`crate::metric::length::metric_edge_length`]), the length density is la·rˢ with
/// r = lb/la, so the half-length point is t = ln((1 + r)/2)/ln r (½ when r = 1). Splitting
/// at the Euclidean midpoint of a graded edge would leave one half short.
pub(super) fn metric_midpoint(w: &Work, a: u32, b: u32) -> f64 {
    let (pa, pb) = (w.point(a), w.point(b));
    let e = [pb[0] - pa[0], pb[1] - pa[1]];
    let la = w.metric(a).quadratic_form(e).max(0.0).sqrt();
    let lb = w.metric(b).quadratic_form(e).max(0.0).sqrt();
    if !(la > 0.0 && lb > 0.0) {
        return 0.5;
    }
    let r = lb / la;
    if (r - 1.0).abs() < 1e-6 {
        return 0.5;
    }
    ((0.5 * (1.0 + r)).ln() / r.ln()).clamp(0.1, 0.9)
}

/// Whether edge `ab`, held by triangles `ts`, may be split, and where: refused when a
/// new triangle would not be strictly counter-clockwise or a new boundary edge would
/// cross a curve.
pub(super) fn check(w: &Work, a: u32, b: u32, ts: &[u32]) -> Option<SplitPlan> {
    let (at, metric, role) = match w.constraint(a, b) {
        Some(p) if w.boundary().pieces[p as usize].frozen => return None,
        Some(p) => {
            let near = w.param_or(a, p, w.param_or(b, p, 0.0));
            let (sa, sb) = (w.param_on(a, p, near), w.param_on(b, p, near));
            let sm = sa + metric_midpoint(w, a, b) * (sb - sa);
            let (pm, mm) = w.on_piece(p, sm);
            if w.mode() == BoundaryMode::Smooth
                && !(w.boundary().chord_clear(p, sa, w.point(a), sm, pm)
                    && w.boundary().chord_clear(p, sm, pm, sb, w.point(b)))
            {
                return None;
            }
            (pm, mm, Role::Slides { piece: p, s: sm })
        }
        None => {
            let (pa, pb) = (w.point(a), w.point(b));
            let t = metric_midpoint(w, a, b);
            let pm = [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])];
            (pm, w.background().metric_at(pm), Role::Free)
        }
    };
    let mut halves = [(u32::MAX, [u32::MAX; 3]); 2];
    for (slot, &t) in halves.iter_mut().zip(ts) {
        let v = w.tri(t);
        let i = (0..3)
            .find(|&i| (v[i] == a && v[(i + 1) % 3] == b) || (v[i] == b && v[(i + 1) % 3] == a))?;
        let (x, y, c) = (v[i], v[(i + 1) % 3], v[(i + 2) % 3]);
        let (px, py, pc) = (w.point(x), w.point(y), w.point(c));
        if orient(px, at, pc) <= 0.0 || orient(at, py, pc) <= 0.0 {
            return None;
        }
        *slot = (t, [x, y, c]);
    }
    Some(SplitPlan { a, b, at, metric, role, halves, n: ts.len().min(2) })
}

/// Carries out a plan of [`check`]; the triangles it changes or makes are flagged in
/// `touched` (grown as needed).
pub(super) fn apply(w: &mut Work, plan: &SplitPlan, touched: &mut Vec<bool>) {
    let m = w.add_vertex(plan.at, plan.metric, plan.role);
    for &(t, [x, y, c]) in &plan.halves[..plan.n] {
        let face = w.face(t);
        w.set_tri(t, [x, m, c]);
        let t2 = w.add_tri([m, y, c], face);
        touched[t as usize] = true;
        touched.resize(t2 as usize + 1, false);
        touched[t2 as usize] = true;
        w.mark(c);
    }
    w.mark(m);
    if let Some(p) = plan.role.piece() {
        w.unconstrain(plan.a, plan.b);
        w.constrain(plan.a, m, p);
        w.constrain(m, plan.b, p);
    }
}
