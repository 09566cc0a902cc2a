//! How the partitioned remesher ([`super::parallel`]) cuts a mesh into parts: triangle
//! adjacency, the metric weight of each triangle, recursive coordinate bisection, the band
//! of triangles around a set of vertices, connected components, and the splitting of the
//! edges between parts to the metric before the first pass.
//!
//! Design and invariants:
//! - Every rule here depends on the mesh and the metric only, never on the thread count:
//!   ties in every sort are broken by the triangle index, parts are numbered in the
//!   order the bisection visits them, components by their smallest triangle.
//! - A triangle's weight is its complexity ∫ √det M (the output vertices it will hold,
//!   up to 2/√3), so bisection balances the work of the remeshing, not the input count.
//! - [`bisect`] cuts along the axes ([`Axes::Straight`]) or along the diagonals
//!   ([`Axes::Diagonal`]): a second pass cut along the diagonals crosses the strips
//!   around the first pass's axis-aligned cuts instead of running along them.
//! - [`split_interfaces`] bisects every edge between two parts until each piece is at
//!   most `split_above` long in the metric, the metric of a new point interpolated
//!   Log-Euclidean along its edge from the edge's ends (what the remesher's background
//!   gives on that edge), and fans the triangles on both sides; every new triangle is
//!   checked with the exact orientation predicate, and when one would not keep its
//!   parent's orientation nothing is split.

use std::collections::BTreeMap;

use rayon::prelude::*;

use super::work::orient;
use crate::metric::complexity::{half_log_det, log_integral_of_exp};
use crate::metric::length::metric_edge_length;
use crate::metric::{exp_sym, log_spd, Sym2};

/// No neighbour, no part.
pub(super) const NONE: u32 = u32::MAX;

/// The neighbour of each triangle across each of its edges (edge `k` from corner `k` to
/// corner `k + 1`), [`NONE`] on a boundary; `None` when an edge has more than two
/// triangles.
pub(super) fn neighbours(tris: &[[u32; 3]]) -> Option<Vec<[u32; 3]>> {
    let mut half: Vec<(u32, u32, u32)> = tris
        .par_iter()
        .enumerate()
        .flat_map_iter(|(t, v)| {
            (0..3).map(move |k| {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                (a.min(b), a.max(b), t as u32 * 3 + k as u32)
            })
        })
        .collect();
    // Every key is distinct (the half-edge index is in it): the order is total.
    half.par_sort_unstable();
    let mut nb = vec![[NONE; 3]; tris.len()];
    let mut i = 0;
    while i < half.len() {
        let mut j = i + 1;
        while j < half.len() && half[j].0 == half[i].0 && half[j].1 == half[i].1 {
            j += 1;
        }
        match j - i {
            1 => {}
            2 => {
                let (x, y) = (half[i].2, half[i + 1].2);
                nb[(x / 3) as usize][(x % 3) as usize] = y / 3;
                nb[(y / 3) as usize][(y % 3) as usize] = x / 3;
            }
            _ => return None,
        }
        i = j;
    }
    Some(nb)
}

/// The triangles around each vertex, as offsets into one list (compressed rows).
pub(super) fn vertex_triangles(n: usize, tris: &[[u32; 3]]) -> (Vec<usize>, Vec<u32>) {
    let mut start = vec![0usize; n + 1];
    for t in tris {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut list = vec![0u32; start[n]];
    for (t, v) in tris.iter().enumerate() {
        for &v in v {
            list[fill[v as usize]] = t as u32;
            fill[v as usize] += 1;
        }
    }
    (start, list)
}

/// The complexity ∫ √det M of each triangle, M interpolated Log-Euclidean.
pub(super) fn weights(pts: &[[f64; 2]], tris: &[[u32; 3]], metric: &[Sym2]) -> Vec<f64> {
    let hld: Vec<f64> = metric.par_iter().map(half_log_det).collect();
    tris.par_iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| pts[v as usize]);
            let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
            let w = log_integral_of_exp(area, t.map(|v| hld[v as usize])).exp();
            if w.is_finite() {
                w
            } else {
                0.0
            }
        })
        .collect()
}

/// The directions [`bisect`] cuts across.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Axes {
    /// x and y: cuts are vertical or horizontal lines.
    Straight,
    /// x + y and x − y: cuts are lines at 45°.
    Diagonal,
}

/// Splits `items` (triangle indices, with their centroids and weights indexed by
/// triangle) into `parts` parts of equal weight by recursive coordinate bisection, each
/// cut across the longer extent of the centroids. Writes the part of each item into
/// `part` (indexed by triangle), numbering parts from `first`.
pub(super) fn bisect(
    centroid: &[[f64; 2]],
    weight: &[f64],
    items: &mut [u32],
    parts: usize,
    axes: Axes,
    first: u32,
    part: &mut [u32],
) {
    if parts <= 1 || items.len() <= 1 {
        items.iter().for_each(|&t| part[t as usize] = first);
        return;
    }
    let coord = |t: u32, axis: usize| -> f64 {
        let c = centroid[t as usize];
        match (axes, axis) {
            (Axes::Straight, a) => c[a],
            (Axes::Diagonal, 0) => c[0] + c[1],
            (Axes::Diagonal, _) => c[0] - c[1],
        }
    };
    let extent = |axis: usize| {
        let (lo, hi) = items.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &t| {
            let x = coord(t, axis);
            (lo.min(x), hi.max(x))
        });
        hi - lo
    };
    let axis = if extent(1) > extent(0) { 1 } else { 0 };
    items.par_sort_unstable_by(|&a, &b| coord(a, axis).total_cmp(&coord(b, axis)).then(a.cmp(&b)));
    let left = parts / 2;
    let total: f64 = items.iter().map(|&t| weight[t as usize]).sum();
    let mut cut = items.len() * left / parts;
    if total > 0.0 && total.is_finite() {
        let goal = total * left as f64 / parts as f64;
        let mut acc = 0.0;
        cut = items.len();
        for (i, &t) in items.iter().enumerate() {
            if acc >= goal {
                cut = i;
                break;
            }
            acc += weight[t as usize];
        }
    }
    let cut = cut.clamp(1, items.len() - 1);
    let (l, r) = items.split_at_mut(cut);
    bisect(centroid, weight, l, left, axes, first, part);
    bisect(centroid, weight, r, parts - left, axes, first + left as u32, part);
}

/// The triangles with a corner less than `rings` edges away from a `seed` vertex.
pub(super) fn band(
    tris: &[[u32; 3]],
    around: &(Vec<usize>, Vec<u32>),
    seed: &[bool],
    rings: usize,
) -> Vec<bool> {
    let (start, list) = around;
    let mut reached = seed.to_vec();
    let mut front: Vec<u32> = (0..seed.len() as u32).filter(|&v| seed[v as usize]).collect();
    for _ in 1..rings {
        let mut next = Vec::new();
        for &v in &front {
            for &t in &list[start[v as usize]..start[v as usize + 1]] {
                for &w in &tris[t as usize] {
                    if !reached[w as usize] {
                        reached[w as usize] = true;
                        next.push(w);
                    }
                }
            }
        }
        front = next;
    }
    tris.iter().map(|t| t.iter().any(|&v| reached[v as usize])).collect()
}

/// The connected components (through edges) of the `selected` triangles, numbered by
/// their smallest triangle; [`NONE`] for the others. Returns the parts and their count.
pub(super) fn components(selected: &[bool], nb: &[[u32; 3]]) -> (Vec<u32>, usize) {
    let mut part = vec![NONE; selected.len()];
    let mut count = 0u32;
    let mut stack = Vec::new();
    for t in 0..selected.len() {
        if !selected[t] || part[t] != NONE {
            continue;
        }
        part[t] = count;
        stack.push(t as u32);
        while let Some(u) = stack.pop() {
            for &n in &nb[u as usize] {
                if n != NONE && selected[n as usize] && part[n as usize] == NONE {
                    part[n as usize] = count;
                    stack.push(n);
                }
            }
        }
        count += 1;
    }
    (part, count as usize)
}

/// A triangle mesh with its metric, tags and lower-dimensional cells: what the passes
/// hand each other.
#[derive(Debug, Clone, Default)]
pub(super) struct Flat {
    /// Coordinates.
    pub pts: Vec<[f64; 2]>,
    /// The metric at each point.
    pub metric: Vec<Sym2>,
    /// Triangles.
    pub tris: Vec<[u32; 3]>,
    /// `(physical, geometrical)` of each triangle.
    pub tri_tags: Vec<(i32, i32)>,
    /// Line cells with their tags.
    pub lines: Vec<([u32; 2], (i32, i32))>,
    /// Vertex cells with their tags.
    pub vertex_cells: Vec<(u32, (i32, i32))>,
}

/// `m` at parameter `s` of the edge from the metric of log `la` to that of log `lb`.
fn along(la: &Sym2, lb: &Sym2, s: f64) -> Sym2 {
    exp_sym(&Sym2::new(
        (1.0 - s) * la.a + s * lb.a,
        (1.0 - s) * la.b + s * lb.b,
        (1.0 - s) * la.c + s * lb.c,
    ))
}

/// Splits every edge between two parts (`part` per triangle, `nb` its neighbours) longer
/// than `split_above` in the metric, as the module header says. Returns the new mesh and
/// the part of each of its triangles, or `None` when nothing was split.
pub(super) fn split_interfaces(
    mesh: &Flat,
    part: &[u32],
    nb: &[[u32; 3]],
    split_above: f64,
) -> Option<(Flat, Vec<u32>)> {
    let mut out = mesh.clone();
    let mut splits: BTreeMap<(u32, u32), Vec<u32>> = BTreeMap::new();
    for (t, v) in mesh.tris.iter().enumerate() {
        for k in 0..3 {
            let n = nb[t][k];
            if n == NONE || (n as usize) < t || part[n as usize] == part[t] {
                continue;
            }
            let (a, b) = (v[k].min(v[(k + 1) % 3]), v[k].max(v[(k + 1) % 3]));
            let (pa, pb) = (mesh.pts[a as usize], mesh.pts[b as usize]);
            let (ma, mb) = (mesh.metric[a as usize], mesh.metric[b as usize]);
            let l = metric_edge_length(pa, pb, &ma, &mb);
            if l.is_nan() || l <= split_above {
                continue;
            }
            let (la, lb) = (log_spd(&ma), log_spd(&mb));
            // Parameters of the cut points, by bisection of every piece still too long.
            let mut cuts = vec![0.0, 1.0];
            let at = |s: f64| [pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1])];
            loop {
                let mut next = vec![cuts[0]];
                let mut changed = false;
                for w in cuts.windows(2) {
                    let (s0, s1) = (w[0], w[1]);
                    let l = metric_edge_length(
                        at(s0),
                        at(s1),
                        &along(&la, &lb, s0),
                        &along(&la, &lb, s1),
                    );
                    if l > split_above && s1 - s0 > 1e-9 {
                        next.push(0.5 * (s0 + s1));
                        changed = true;
                    }
                    next.push(s1);
                }
                cuts = next;
                if !changed || cuts.len() > 1 << 16 {
                    break;
                }
            }
            let mut ids = Vec::with_capacity(cuts.len() - 2);
            for &s in &cuts[1..cuts.len() - 1] {
                ids.push(out.pts.len() as u32);
                out.pts.push(at(s));
                out.metric.push(along(&la, &lb, s));
            }
            splits.insert((a, b), ids);
        }
    }
    if splits.is_empty() {
        return None;
    }
    // Points strictly inside edge u→w, in that order.
    let inside = |u: u32, w: u32| -> Vec<u32> {
        match splits.get(&(u.min(w), u.max(w))) {
            Some(l) if u < w => l.clone(),
            Some(l) => l.iter().rev().copied().collect(),
            None => Vec::new(),
        }
    };
    out.tris.clear();
    out.tri_tags.clear();
    let mut new_part = Vec::with_capacity(mesh.tris.len());
    for (t, v) in mesh.tris.iter().enumerate() {
        let on = [inside(v[0], v[1]), inside(v[1], v[2]), inside(v[2], v[0])];
        let before = out.tris.len();
        fan(*v, on, &mut out.tris);
        let sign = orient_of(&mesh.pts, *v).signum();
        for s in &out.tris[before..] {
            if orient_of(&out.pts, *s).signum() != sign || sign == 0.0 {
                return None;
            }
        }
        for _ in before..out.tris.len() {
            out.tri_tags.push(mesh.tri_tags[t]);
            new_part.push(part[t]);
        }
    }
    out.lines.clear();
    for &([a, b], tags) in &mesh.lines {
        let mut chain = vec![a];
        chain.extend(inside(a, b));
        chain.push(b);
        for w in chain.windows(2) {
            out.lines.push(([w[0], w[1]], tags));
        }
    }
    Some((out, new_part))
}

fn orient_of(pts: &[[f64; 2]], t: [u32; 3]) -> f64 {
    orient(pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize])
}

/// Triangulates triangle `t` with the points `on[k]` strictly inside its edge `k` (from
/// corner `k` to corner `k + 1`, in that order): cut from the middle point of the first
/// split edge to the opposite corner, and again in each half.
fn fan(t: [u32; 3], on: [Vec<u32>; 3], out: &mut Vec<[u32; 3]>) {
    let Some(k) = (0..3).find(|&k| !on[k].is_empty()) else {
        out.push(t);
        return;
    };
    let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
    let mid = on[k].len() / 2;
    let m = on[k][mid];
    let [e0, e1, e2] = on;
    let (ab, bc, ca) = match k {
        0 => (e0, e1, e2),
        1 => (e1, e2, e0),
        _ => (e2, e0, e1),
    };
    fan([a, m, c], [ab[..mid].to_vec(), Vec::new(), ca], out);
    fan([m, b, c], [ab[mid + 1..].to_vec(), bc, Vec::new()], out);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An n×n grid of the unit square, two triangles per cell.
    fn grid(n: usize) -> Flat {
        let mut f = Flat::default();
        for j in 0..=n {
            for i in 0..=n {
                f.pts.push([i as f64 / n as f64, j as f64 / n as f64]);
                f.metric.push(Sym2::new(400.0, 0.0, 2500.0));
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                f.tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                f.tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
                f.tri_tags.extend([(1, 1), (1, 1)]);
            }
        }
        f
    }

    #[test]
    fn neighbours_agree_with_all_pairs() {
        let f = grid(5);
        let nb = neighbours(&f.tris).unwrap();
        for (t, v) in f.tris.iter().enumerate() {
            for k in 0..3 {
                let e = [v[k].min(v[(k + 1) % 3]), v[k].max(v[(k + 1) % 3])];
                let other = f
                    .tris
                    .iter()
                    .enumerate()
                    .position(|(u, w)| u != t && w.contains(&e[0]) && w.contains(&e[1]));
                assert_eq!(nb[t][k], other.map_or(NONE, |u| u as u32));
            }
        }
    }

    #[test]
    fn bisection_balances_weight_and_numbers_parts_alike() {
        let f = grid(12);
        let c: Vec<[f64; 2]> = f
            .tris
            .iter()
            .map(|t| {
                let p = t.map(|v| f.pts[v as usize]);
                [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0]
            })
            .collect();
        let w = weights(&f.pts, &f.tris, &f.metric);
        for axes in [Axes::Straight, Axes::Diagonal] {
            for parts in [2, 3, 5, 8] {
                let mut items: Vec<u32> = (0..f.tris.len() as u32).collect();
                let mut part = vec![NONE; f.tris.len()];
                bisect(&c, &w, &mut items, parts, axes, 0, &mut part);
                let mut sum = vec![0.0; parts];
                for (t, &p) in part.iter().enumerate() {
                    sum[p as usize] += w[t];
                }
                let total: f64 = w.iter().sum();
                let most = total / f.tris.len() as f64 * 2.0;
                for s in &sum {
                    // Within a few triangles of the share (the cut is between triangles).
                    assert!((s - total / parts as f64).abs() <= 2.0 * most, "{sum:?}");
                }
                // Same parts from items given in another order.
                let mut rev: Vec<u32> = (0..f.tris.len() as u32).rev().collect();
                let mut again = vec![NONE; f.tris.len()];
                bisect(&c, &w, &mut rev, parts, axes, 0, &mut again);
                assert_eq!(part, again);
            }
        }
    }

    #[test]
    fn split_interfaces_keeps_area_orientation_and_conforms() {
        let f = grid(4);
        let nb = neighbours(&f.tris).unwrap();
        let part: Vec<u32> = (0..f.tris.len()).map(|t| (t % 8 < 4) as u32).collect();
        let (g, gp) = split_interfaces(&f, &part, &nb, 2f64.sqrt()).unwrap();
        let area = |m: &Flat| -> f64 { m.tris.iter().map(|&t| orient_of(&m.pts, t) / 2.0).sum() };
        assert!((area(&f) - area(&g)).abs() < 1e-12);
        assert!(g.tris.iter().all(|&t| orient_of(&g.pts, t) > 0.0));
        assert_eq!(gp.len(), g.tris.len());
        // Conforming: every edge has one or two triangles, and the cut edges are short.
        let gnb = neighbours(&g.tris).unwrap();
        for (t, v) in g.tris.iter().enumerate() {
            for k in 0..3 {
                let n = gnb[t][k];
                if n != NONE && gp[n as usize] != gp[t] {
                    let (a, b) = (v[k] as usize, v[(k + 1) % 3] as usize);
                    let l = metric_edge_length(g.pts[a], g.pts[b], &g.metric[a], &g.metric[b]);
                    assert!(l <= 2f64.sqrt(), "{l}");
                }
            }
        }
        // Brute-force twin of conformity: boundary edges are those of the square only.
        for (t, v) in g.tris.iter().enumerate() {
            for k in 0..3 {
                if gnb[t][k] == NONE {
                    let (p, q) = (g.pts[v[k] as usize], g.pts[v[(k + 1) % 3] as usize]);
                    let on_side =
                        |i: usize| (p[i] == 0.0 && q[i] == 0.0) || (p[i] == 1.0 && q[i] == 1.0);
                    assert!(on_side(0) || on_side(1), "{p:?} {q:?}");
                }
            }
        }
    }

    #[test]
    fn band_and_components_agree_with_brute_force() {
        let f = grid(8);
        let around = vertex_triangles(f.pts.len(), &f.tris);
        let mut seed = vec![false; f.pts.len()];
        seed[76] = true;
        seed[3] = true;
        let b = band(&f.tris, &around, &seed, 2);
        // Brute force: vertices within one edge of a seed.
        let near: Vec<bool> = (0..f.pts.len() as u32)
            .map(|v| {
                seed[v as usize]
                    || f.tris.iter().any(|t| t.contains(&v) && t.iter().any(|&w| seed[w as usize]))
            })
            .collect();
        for (t, v) in f.tris.iter().enumerate() {
            assert_eq!(b[t], v.iter().any(|&w| near[w as usize]));
        }
        let nb = neighbours(&f.tris).unwrap();
        let (comp, count) = components(&b, &nb);
        assert_eq!(count, 2);
        assert_eq!(comp.iter().position(|&c| c == 0), b.iter().position(|&x| x));
    }
}
