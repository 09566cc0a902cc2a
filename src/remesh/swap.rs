//! Edge swapping: the diagonal of two triangles that share an unconstrained edge is
//! flipped when that raises the worse of their two metric qualities. Constrained edges
//! (boundaries, interfaces) never flip, so face tags never mix.
//!
//! [`check`] returns a [`SwapPlan`] or `None`; [`apply`] flips.

use super::options::RemeshOptions;
use super::work::{orient, Work};

/// A flip that [`check`] accepted: triangles `t1 = (a, b, c)` and `t2 = (b, a, d)`
/// become `(c, a, d)` and `(d, b, c)`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SwapPlan {
    t1: u32,
    t2: u32,
    n1: [u32; 3],
    n2: [u32; 3],
    /// The four corners, `[a, b, c, d]`.
    corners: [u32; 4],
}

/// Sweeps of flips until none is left or `opts.swap_sweeps` ran: the first sweep tries
/// the edges around every vertex whose ball changed since the last swap phase (every
/// edge when `everything`), the next ones only the edges around the vertices a flip
/// touched (sorted, so the order is fixed). Returns the number of flips and the corners
/// of the flipped pairs (each once, in the order first touched).
pub(super) fn swap_sweeps(
    w: &mut Work,
    opts: &RemeshOptions,
    everything: bool,
) -> (usize, Vec<u32>) {
    let mut n = 0;
    let dirty = w.take_dirty();
    let mut todo = if everything { w.edges() } else { w.edges_around(&dirty) };
    let mut touched = vec![false; w.num_vertices()];
    let mut all: Vec<u32> = Vec::new();
    for _ in 0..opts.swap_sweeps {
        let mut hit: Vec<u32> = Vec::new();
        for &(a, b) in &todo {
            if w.constraint(a, b).is_some() {
                continue;
            }
            if let Some(plan) = check(w, a, b, opts.swap_gain) {
                apply(w, &plan);
                n += 1;
                for x in plan.corners {
                    if !touched[x as usize] {
                        touched[x as usize] = true;
                        hit.push(x);
                    }
                }
            }
        }
        if hit.is_empty() {
            break;
        }
        for &x in &hit {
            touched[x as usize] = false;
        }
        todo = w.edges_around(&hit);
        all.extend_from_slice(&hit);
    }
    super::radix::sort_u32(&mut all);
    all.dedup();
    (n, all)
}

/// Whether flipping edge `ab` is allowed and raises the worse quality of the pair by
/// more than the relative `gain`.
pub(super) fn check(w: &Work, a: u32, b: u32, gain: f64) -> Option<SwapPlan> {
    let (ts, k) = w.edge_tris(a, b);
    if k != 2 {
        return None;
    }
    // Orient so that t1 = (a, b, c) and t2 = (b, a, d).
    let rot = |v: [u32; 3], x: u32| -> [u32; 3] {
        let i = v.iter().position(|&y| y == x).unwrap_or(0);
        [v[i], v[(i + 1) % 3], v[(i + 2) % 3]]
    };
    let (mut t1, mut t2) = (ts[0], ts[1]);
    let mut v1 = rot(w.tri(t1), a);
    if v1[1] != b {
        std::mem::swap(&mut t1, &mut t2);
        v1 = rot(w.tri(t1), a);
    }
    let v2 = rot(w.tri(t2), b);
    if v1[1] != b || v2[1] != a {
        return None;
    }
    let (c, d) = (v1[2], v2[2]);
    if c == d || w.face(t1) != w.face(t2) {
        return None;
    }
    let (n1, n2) = ([c, a, d], [d, b, c]);
    let p = |v: [u32; 3]| v.map(|x| w.point(x));
    let (q1, q2) = (p(n1), p(n2));
    if orient(q1[0], q1[1], q1[2]) <= 0.0 || orient(q2[0], q2[1], q2[2]) <= 0.0 {
        return None;
    }
    // The worse new triangle must beat the bound: the second is not measured when the
    // first already fails it (nearly every flip tried is refused).
    let bound = w.quality(t1).min(w.quality(t2)) * (1.0 + gain);
    if w.quality_of(n1) <= bound || w.quality_of(n2) <= bound {
        return None;
    }
    if w.ball(c).iter().any(|&t| w.tri(t).contains(&d)) {
        return None; // cd is already an edge
    }
    Some(SwapPlan { t1, t2, n1, n2, corners: [a, b, c, d] })
}

/// Carries out a plan of [`check`].
pub(super) fn apply(w: &mut Work, plan: &SwapPlan) {
    w.set_tri(plan.t1, plan.n1);
    w.set_tri(plan.t2, plan.n2);
}
