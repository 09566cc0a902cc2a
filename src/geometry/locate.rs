//! Point location in a triangulation: the triangle that holds a point, with the point's
//! barycentric weights, or, for a point outside every triangle, the nearest triangle and
//! the weights of its closest point.
//!
//! A uniform bucket grid over the triangles' bounding boxes, about one cell per triangle
//! (at most 4096 cells a side), in CSR form: a cell lists every triangle whose box
//! touches it. A point inside the triangulation is answered from its own cell (the
//! triangle it lies deepest in, so a point on a shared edge gets one answer); outside,
//! rings of cells are searched outwards until the nearest triangle is certain (a ring
//! r cells out is at least (r − 1)·cell away), ties going to the lower triangle index.
//! Written by hand because a grid sized to the triangle count answers in O(1) on the
//! coarse meshes it serves, and the crates that index triangles are not dependencies.
//!
//! Invariants: deterministic (no hashing, cells and triangles scanned in index order);
//! weights sum to 1 and are all ≥ 0 for a returned closest point outside.
//!
//! A point is first looked for in the leaf of a quadtree of the triangles' boxes
//! ([`super::box_tree`], which follows the grading of an adapted mesh, where the uniform
//! grid piles many triangles into a few cells); a point that no triangle of the leaf
//! contains goes to the grid. Both scans take the triangle `p` is deepest in, the lowest
//! index on ties, over sets holding every triangle that contains `p`, so they agree.

/// A point whose every barycentric weight in a triangle is above this is inside it
/// beyond any rounding of the weights (a few ulps of 1): the point location stops there.
const DEEP: f64 = 1e-9;

/// Triangles (counter-clockwise, over their points) indexed for point location.
pub(crate) struct TriangleLocator {
    points: Vec<[f64; 2]>,
    tris: Vec<[usize; 3]>,
    origin: [f64; 2],
    cell: f64,
    nx: usize,
    ny: usize,
    /// CSR buckets: triangles of cell `k` are `items[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
    /// The quadtree of the triangles' boxes.
    tree: super::box_tree::BoxTree,
}

impl TriangleLocator {
    /// Indexes `tris` (counter-clockwise) over `points`.
    pub(crate) fn new(points: &[[f64; 2]], tris: &[[usize; 3]]) -> TriangleLocator {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for t in tris {
            for &v in t {
                for k in 0..2 {
                    lo[k] = lo[k].min(points[v][k]);
                    hi[k] = hi[k].max(points[v][k]);
                }
            }
        }
        if tris.is_empty() {
            lo = [0.0; 2];
            hi = [1.0; 2];
        }
        let (w, h) = ((hi[0] - lo[0]).max(1e-300), (hi[1] - lo[1]).max(1e-300));
        let cells = (tris.len().max(1)) as f64;
        let cell = ((w * h) / cells).sqrt().max(w.max(h) / 4096.0);
        let nx = ((w / cell).ceil() as usize).clamp(1, 4096);
        let ny = ((h / cell).ceil() as usize).clamp(1, 4096);
        let mut loc = TriangleLocator {
            points: points.to_vec(),
            tris: tris.to_vec(),
            origin: lo,
            cell,
            nx,
            ny,
            start: Vec::new(),
            items: Vec::new(),
            tree: super::box_tree::BoxTree::new(&[]),
        };
        let mut count = vec![0u32; nx * ny + 1];
        for t in tris {
            let (x0, y0, x1, y1) = loc.cell_range(t);
            for j in y0..=y1 {
                for i in x0..=x1 {
                    count[j * nx + i + 1] += 1;
                }
            }
        }
        for k in 1..count.len() {
            count[k] += count[k - 1];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; count[nx * ny] as usize];
        for (ti, t) in tris.iter().enumerate() {
            let (x0, y0, x1, y1) = loc.cell_range(t);
            for j in y0..=y1 {
                for i in x0..=x1 {
                    let k = j * nx + i;
                    items[fill[k] as usize] = ti as u32;
                    fill[k] += 1;
                }
            }
        }
        loc.start = count;
        loc.items = items;
        let boxes: Vec<([f64; 2], [f64; 2])> = tris
            .iter()
            .map(|t| {
                let p = t.map(|v| points[v]);
                (
                    [p[0][0].min(p[1][0]).min(p[2][0]), p[0][1].min(p[1][1]).min(p[2][1])],
                    [p[0][0].max(p[1][0]).max(p[2][0]), p[0][1].max(p[1][1]).max(p[2][1])],
                )
            })
            .collect();
        loc.tree = super::box_tree::BoxTree::new(&boxes);
        loc
    }

    /// The triangles, as given.
    pub(crate) fn triangles(&self) -> &[[usize; 3]] {
        &self.tris
    }

    /// Whether there is no triangle to locate in.
    pub(crate) fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    fn cell_of(&self, p: [f64; 2]) -> (usize, usize) {
        let i = ((p[0] - self.origin[0]) / self.cell).floor();
        let j = ((p[1] - self.origin[1]) / self.cell).floor();
        (i.clamp(0.0, (self.nx - 1) as f64) as usize, j.clamp(0.0, (self.ny - 1) as f64) as usize)
    }

    fn cell_range(&self, t: &[usize; 3]) -> (usize, usize, usize, usize) {
        let p = [self.points[t[0]], self.points[t[1]], self.points[t[2]]];
        let lo = [p[0][0].min(p[1][0]).min(p[2][0]), p[0][1].min(p[1][1]).min(p[2][1])];
        let hi = [p[0][0].max(p[1][0]).max(p[2][0]), p[0][1].max(p[1][1]).max(p[2][1])];
        let (x0, y0) = self.cell_of(lo);
        let (x1, y1) = self.cell_of(hi);
        (x0, y0, x1, y1)
    }

    /// Barycentric coordinates of `p` in triangle `t`.
    fn barycentric(&self, t: usize, p: [f64; 2]) -> [f64; 3] {
        let [a, b, c] = self.tris[t].map(|v| self.points[v]);
        let d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        let l1 = ((b[0] - p[0]) * (c[1] - p[1]) - (b[1] - p[1]) * (c[0] - p[0])) / d;
        let l2 = ((c[0] - p[0]) * (a[1] - p[1]) - (c[1] - p[1]) * (a[0] - p[0])) / d;
        [l1, l2, 1.0 - l1 - l2]
    }

    /// The weights of the closest point of triangle `t` to `p`, and its squared distance.
    pub(crate) fn closest(&self, t: usize, p: [f64; 2]) -> ([f64; 3], f64) {
        let l = self.barycentric(t, p);
        if l.iter().all(|&x| x >= 0.0) {
            return (l, 0.0);
        }
        let v = self.tris[t].map(|v| self.points[v]);
        let mut best = ([1.0, 0.0, 0.0], f64::INFINITY);
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            let e = [b[0] - a[0], b[1] - a[1]];
            let ee = e[0] * e[0] + e[1] * e[1];
            let s = if ee > 0.0 {
                (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / ee).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let q = [a[0] + s * e[0], a[1] + s * e[1]];
            let d2 = (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
            if d2 < best.1 {
                let mut w = [0.0; 3];
                w[k] = 1.0 - s;
                w[(k + 1) % 3] = s;
                best = (w, d2);
            }
        }
        best
    }

    /// The triangle containing `p` (the one `p` is deepest in) or, outside the
    /// triangulation, the nearest one, with the weights of `p` (or of its closest point).
    /// With no triangle at all: triangle 0 and weights (1, 0, 0), which callers check
    /// with [`TriangleLocator::is_empty`] first.
    pub(crate) fn locate(&self, p: [f64; 2]) -> (usize, [f64; 3]) {
        if let Some(found) = self.deepest(self.tree.candidates(p), p) {
            return found;
        }
        let (ci, cj) = self.cell_of(p);
        let k = cj * self.nx + ci;
        let mut best: Option<(usize, [f64; 3], f64)> = None;
        for &t in &self.items[self.start[k] as usize..self.start[k + 1] as usize] {
            let l = self.barycentric(t as usize, p);
            let m = l[0].min(l[1]).min(l[2]);
            if best.as_ref().map_or(true, |b| m > b.2) {
                best = Some((t as usize, l, m));
            }
        }
        if let Some((t, l, m)) = best {
            if m >= 0.0 {
                return (t, l);
            }
        }
        // Outside (or in a cell without a containing triangle): rings of cells around
        // p until the nearest triangle is certain (a ring r cells out is at least
        // (r − 1)·cell away).
        let mut near: Option<(usize, [f64; 3], f64)> = None;
        let rmax = self.nx.max(self.ny);
        for r in 0..=rmax {
            if let Some((_, _, d2)) = near {
                let bound = (r as f64 - 1.0).max(0.0) * self.cell;
                if bound * bound > d2 {
                    break;
                }
            }
            let (i0, i1) = (ci as isize - r as isize, ci as isize + r as isize);
            let (j0, j1) = (cj as isize - r as isize, cj as isize + r as isize);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let on_ring = i == i0 || i == i1 || j == j0 || j == j1;
                    if !on_ring || i < 0 || j < 0 || i >= self.nx as isize || j >= self.ny as isize
                    {
                        continue;
                    }
                    let k = j as usize * self.nx + i as usize;
                    for &t in &self.items[self.start[k] as usize..self.start[k + 1] as usize] {
                        let (w, d2) = self.closest(t as usize, p);
                        if near
                            .as_ref()
                            .map_or(true, |n| d2 < n.2 || (d2 == n.2 && (t as usize) < n.0))
                        {
                            near = Some((t as usize, w, d2));
                        }
                    }
                }
            }
        }
        near.map(|(t, w, _)| (t, w)).unwrap_or((0, [1.0, 0.0, 0.0]))
    }

    /// The triangle of `candidates` that `p` is deepest in (the first on ties), if `p` is
    /// in one of them. A triangle that holds `p` with every weight above [`DEEP`] is
    /// that triangle: in a triangulation (no two triangles overlap) `p` is in no other,
    /// whose smallest weight is then at most zero up to rounding, far below [`DEEP`];
    /// so the scan stops there, with the answer the whole scan gives.
    fn deepest(&self, candidates: &[u32], p: [f64; 2]) -> Option<(usize, [f64; 3])> {
        let mut best: Option<(usize, [f64; 3], f64)> = None;
        for &t in candidates {
            let l = self.barycentric(t as usize, p);
            let m = l[0].min(l[1]).min(l[2]);
            if m > DEEP {
                return Some((t as usize, l));
            }
            if best.as_ref().map_or(true, |b| m > b.2) {
                best = Some((t as usize, l, m));
            }
        }
        best.filter(|b| b.2 >= 0.0).map(|(t, l, _)| (t, l))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute-force twin of `locate`: every triangle tried.
    #[test]
    fn locate_agrees_with_brute_force_inside_and_outside() {
        // A 6x6 grid of squares on [0,1]² with the middle square removed (a hole).
        let n = 6;
        let pts: Vec<[f64; 2]> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| [i as f64 / n as f64, j as f64 / n as f64]))
            .collect();
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                if (i, j) == (2, 2) || (i, j) == (3, 3) {
                    continue;
                }
                let v = j * (n + 1) + i;
                tris.push([v, v + 1, v + n + 2]);
                tris.push([v, v + n + 2, v + n + 1]);
            }
        }
        let loc = TriangleLocator::new(&pts, &tris);
        let mut s = 12345u64;
        for _ in 0..2000 {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let x = (s >> 11) as f64 / (1u64 << 53) as f64 * 1.4 - 0.2;
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let y = (s >> 11) as f64 / (1u64 << 53) as f64 * 1.4 - 0.2;
            let p = [x, y];
            let (t, _) = loc.locate(p);
            let dist = |t: usize| loc.closest(t, p).1;
            let best = (0..tris.len()).map(dist).fold(f64::INFINITY, f64::min);
            assert!(dist(t) <= best + 1e-15, "{p:?}: got {} vs {}", dist(t), best);
        }
    }
}
