//! The pairs of items (segments, cells, points) that may meet, for the boundary-layer
//! skin's crossing test and the mixed-mesh check ([`crate::validity`]): every pair whose
//! grown convex hulls meet is listed.
//!
//! A quadtree of boxes ([`BoxTree`]) finds items that are near; but the cells and
//! fronts of a skin are thin and slanted, stacked along their column, and their
//! axis-aligned boxes all overlap within a column's box, which no split separates: a
//! query there returns the whole column, and the test was quadratic in the layer count
//! (200 layers: 10 s; 1 000, the documented maximum, no result in 300 s). Here each
//! leaf's items are instead swept along the normal of their mean direction (the
//! doubled-angle mean of their longest edges, so that opposite directions agree): in a
//! column that is across the layers, where the items' projections are as thin as the
//! layers, so each item meets its neighbours only.
//!
//! Invariant (exactness): two items whose grown hulls share a point have boxes that
//! share it, so both are filed in a leaf holding it; there their projections on any
//! axis, grown alike, overlap, and the sweep lists every pair whose projections and
//! boxes overlap. The tests compare with all pairs on meshes with every orientation.

use super::box_tree::BoxTree;
use super::plane::{dot, norm, sub, Bbox, P};

/// Leaves with at most this many items are tested pair by pair.
const SMALL_LEAF: usize = 16;

/// Every pair `(i, j)`, `i < j`, of `items` (each its corners, 1 to 4 points, and how far
/// its hull is grown) whose grown boxes meet, and others near them; sorted, each once.
/// The pairs whose grown hulls meet are all in it.
pub(crate) fn near_pairs(items: &[(&[P], f64)]) -> Vec<(u32, u32)> {
    if items.is_empty() {
        return Vec::new();
    }
    let boxes: Vec<Bbox> = items.iter().map(|&(pts, g)| Bbox::of(pts).grown(g)).collect();
    let pairs: Vec<([f64; 2], [f64; 2])> = boxes.iter().map(|b| (b.lo, b.hi)).collect();
    let tree = BoxTree::new(&pairs);
    let meet = |a: &Bbox, b: &Bbox| {
        a.lo[0] <= b.hi[0] && b.lo[0] <= a.hi[0] && a.lo[1] <= b.hi[1] && b.lo[1] <= a.hi[1]
    };
    // Pairs as `i << 32 | j`: one integer to sort and deduplicate (a pair sharing
    // several leaves is found in each), in the same order as `(i, j)`.
    let mut out: Vec<u64> = Vec::new();
    let pair = |i: u32, j: u32| (u64::from(i.min(j)) << 32) | u64::from(i.max(j));
    let mut order: Vec<(f64, f64, u32)> = Vec::new();
    let mut active: Vec<(f64, u32)> = Vec::new();
    for leaf in tree.leaves() {
        if leaf.len() <= SMALL_LEAF {
            for (k, &i) in leaf.iter().enumerate() {
                for &j in &leaf[k + 1..] {
                    if meet(&boxes[i as usize], &boxes[j as usize]) {
                        out.push(pair(i, j));
                    }
                }
            }
            continue;
        }
        let n = sweep_normal(leaf.iter().map(|&i| items[i as usize].0));
        order.clear();
        for &i in leaf {
            let (pts, g) = items[i as usize];
            let (lo, hi) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &p| {
                let x = dot(p, n);
                (lo.min(x), hi.max(x))
            });
            order.push((lo - g, hi + g, i));
        }
        order.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
        active.clear();
        for &(lo, hi, i) in &order {
            active.retain(|&(h, _)| h >= lo);
            for &(_, j) in &active {
                if meet(&boxes[i as usize], &boxes[j as usize]) {
                    out.push(pair(i, j));
                }
            }
            active.push((hi, i));
        }
    }
    out.sort_unstable();
    out.dedup();
    out.into_iter().map(|k| ((k >> 32) as u32, k as u32)).collect()
}

/// The unit normal of the mean direction of the items' longest edges (doubled angles,
/// weighted by length); `[0, 1]` when they have none.
fn sweep_normal<'a>(items: impl Iterator<Item = &'a [P]>) -> P {
    let (mut c, mut s) = (0.0, 0.0);
    for pts in items {
        let mut best = [0.0, 0.0];
        for k in 0..pts.len() {
            let e = sub(pts[(k + 1) % pts.len()], pts[k]);
            if norm(e) > norm(best) {
                best = e;
            }
        }
        let len = norm(best);
        if len > 0.0 {
            // cos 2θ and sin 2θ, times the length.
            c += (best[0] * best[0] - best[1] * best[1]) / len;
            s += 2.0 * best[0] * best[1] / len;
        }
    }
    if c == 0.0 && s == 0.0 {
        return [0.0, 1.0];
    }
    let half = 0.5 * s.atan2(c);
    [-half.sin(), half.cos()]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// All pairs whose grown boxes meet.
    fn brute(items: &[(&[P], f64)]) -> Vec<(u32, u32)> {
        let boxes: Vec<Bbox> = items.iter().map(|&(p, g)| Bbox::of(p).grown(g)).collect();
        let mut out = Vec::new();
        for i in 0..items.len() {
            for j in i + 1..items.len() {
                let (a, b) = (boxes[i], boxes[j]);
                if a.lo[0] <= b.hi[0]
                    && b.lo[0] <= a.hi[0]
                    && a.lo[1] <= b.hi[1]
                    && b.lo[1] <= a.hi[1]
                {
                    out.push((i as u32, j as u32));
                }
            }
        }
        out
    }

    /// Stacked slanted segments and quads in columns of every direction (a fan of 24),
    /// points and random segments: every pair whose hulls meet (tested exactly) is
    /// listed, and a stack of 2 000 thin slanted quads gives near-linearly many pairs.
    #[test]
    fn every_meeting_pair_is_listed_and_stacks_give_few_pairs() {
        let mut s = 3u64;
        let mut rand = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut shapes: Vec<Vec<P>> = Vec::new();
        for c in 0..24 {
            let a = c as f64 * std::f64::consts::TAU / 24.0;
            let (d, t) = ([a.cos(), a.sin()], [-a.sin(), a.cos()]);
            let o = [0.3 * d[0], 0.3 * d[1]];
            for k in 0..60 {
                let h = 1e-3 * k as f64;
                let p = |u: f64, v: f64| [o[0] + v * d[0] + u * t[0], o[1] + v * d[1] + u * t[1]];
                shapes.push(vec![p(0.0, h), p(0.08, h)]);
                shapes.push(vec![p(0.0, h), p(0.08, h), p(0.08, h + 1e-3), p(0.0, h + 1e-3)]);
            }
        }
        for _ in 0..300 {
            let p = [rand() - 0.5, rand() - 0.5];
            shapes.push(vec![p]);
            shapes.push(vec![p, [p[0] + 0.1 * rand(), p[1] + 0.1 * rand()]]);
        }
        let items: Vec<(&[P], f64)> =
            shapes.iter().enumerate().map(|(i, s)| (&s[..], 1e-4 * (i % 3) as f64)).collect();
        let fast = near_pairs(&items);
        let all = brute(&items);
        // Every pair whose boxes meet and whose grown hulls meet (by the hulls' distance)
        // is listed.
        let hull_meet = |i: usize, j: usize| {
            let (a, b) = (&shapes[i], &shapes[j]);
            let g = items[i].1 + items[j].1;
            let d = |p: P, s: &[P]| {
                (0..s.len())
                    .map(|k| {
                        crate::geometry::plane::segment_distance(p, s[k], s[(k + 1) % s.len()])
                    })
                    .fold(f64::INFINITY, f64::min)
            };
            a.iter().any(|&p| d(p, b) <= g)
                || b.iter().any(|&p| d(p, a) <= g)
                || (a.len() > 1
                    && b.len() > 1
                    && (0..a.len()).any(|x| {
                        (0..b.len()).any(|y| {
                            crate::geometry::plane::segments_meet(
                                a[x],
                                a[(x + 1) % a.len()],
                                b[y],
                                b[(y + 1) % b.len()],
                            )
                        })
                    }))
        };
        let mut met = 0;
        for &(i, j) in &all {
            if hull_meet(i as usize, j as usize) {
                met += 1;
                assert!(fast.binary_search(&(i, j)).is_ok(), "{i} {j} missing");
            }
        }
        assert!(met > 1000, "{met}");
        // A stack of thin slanted quads: pairs grow linearly.
        let mut stack: Vec<Vec<P>> = Vec::new();
        let (d, t) = ([0.6, 0.8], [-0.8, 0.6]);
        for k in 0..2000 {
            let h = 1e-5 * k as f64;
            let p = |u: f64, v: f64| [v * d[0] + u * t[0], v * d[1] + u * t[1]];
            stack.push(vec![p(0.0, h), p(0.05, h), p(0.05, h + 1e-5), p(0.0, h + 1e-5)]);
        }
        let items: Vec<(&[P], f64)> = stack.iter().map(|s| (&s[..], 0.0)).collect();
        let pairs = near_pairs(&items);
        assert!(pairs.len() < 10 * stack.len(), "{} pairs", pairs.len());
        assert!(brute(&items).len() > 100 * stack.len());
    }
}
