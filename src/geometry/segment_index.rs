//! A flat bounding-volume hierarchy over a set of segments, for exact closest-segment
//! queries that start from a guess.
//!
//! Method: a binary tree of axis-aligned boxes built top-down by median split of the
//! segment midpoints along the longer side (at most [`LEAF_SIZE`] segments per leaf),
//! stored depth-first in one array (left child right after its parent), with parent
//! links and the leaf of every segment. Two queries:
//! - [`SegmentIndex::closest`]: top-down branch and bound from the root;
//! - [`SegmentIndex::certify`]: given a guess (a segment and its distance, e.g. from a
//!   neighbour in a propagation), scan the guess's leaf, then walk up to the root and
//!   open only the siblings whose box is not farther than the best distance so far.
//!   With a good guess this opens almost nothing, and the answer is exact whatever the
//!   guess: every segment left out lies in a box farther than the answer.
//!
//! Ties: the smaller squared distance wins, then the smaller segment id, exactly as
//! the brute-force scan does, so that both agree bit for bit. Boxes are grown by a few
//! ulps of their coordinates and compared with a relative slack, so that rounding in
//! the foot point can never prune a segment that the scan would pick.
//!
//! Cost: build O(m log m); `certify` visits one sibling box per level, O(log m) box
//! tests (a few nanoseconds each) plus the segments of the leaves it opens.

use super::segment::{Point2, Projection, SegmentGeom};

/// Most segments in one leaf.
pub(crate) const LEAF_SIZE: usize = 4;

/// Sentinel for "no node" / "no segment".
const NONE: u32 = u32::MAX;

/// The answer to a closest-segment query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Nearest {
    /// The segment id (its index in the slice the index was built from).
    pub(crate) segment: u32,
    /// Where the query point projects on it.
    pub(crate) projection: Projection,
}

impl Nearest {
    /// Whether `self` beats `other`: smaller squared distance, then smaller segment id.
    #[inline]
    pub(crate) fn beats(&self, other: &Nearest) -> bool {
        let (d, e) = (self.projection.distance_squared, other.projection.distance_squared);
        d < e || (d == e && self.segment < other.segment)
    }
}

/// Work counters of queries, summed by the caller.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct QueryStats {
    /// Boxes whose distance to the query point was computed.
    pub(crate) boxes: u64,
    /// Segments projected on.
    pub(crate) segments: u64,
}

impl std::ops::AddAssign for QueryStats {
    fn add_assign(&mut self, o: QueryStats) {
        self.boxes += o.boxes;
        self.segments += o.segments;
    }
}

#[derive(Debug, Clone, Copy)]
struct Node {
    min: Point2,
    max: Point2,
    /// Leaf: first item. Internal: index of the right child (the left one is `self + 1`).
    start_or_right: u32,
    /// Leaf: number of items (> 0). Internal: 0.
    count: u32,
}

#[derive(Debug, Clone, Copy)]
struct Item {
    geom: SegmentGeom,
    id: u32,
}

/// Exact closest-segment queries over a fixed set of segments.
#[derive(Debug, Clone)]
pub(crate) struct SegmentIndex {
    nodes: Vec<Node>,
    parent: Vec<u32>,
    items: Vec<Item>,
    /// Leaf node of each segment id.
    leaf_of: Vec<u32>,
}

/// Relative slack on box distances (see the module doc).
const SLACK: f64 = 1.0 + 16.0 * f64::EPSILON;

impl SegmentIndex {
    /// Builds the index over `segments`; segment ids are their positions in the slice.
    /// Segments with non-finite coordinates are left out of the index.
    pub(crate) fn new(segments: &[SegmentGeom]) -> SegmentIndex {
        let mut items: Vec<Item> = segments
            .iter()
            .enumerate()
            .filter(|(_, g)| g.a.iter().chain(&g.b).all(|c| c.is_finite()))
            .map(|(i, g)| Item { geom: *g, id: i as u32 })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 2);
        let mut parent = Vec::with_capacity(nodes.capacity());
        if !items.is_empty() {
            build(&mut items, 0, &mut nodes, &mut parent, NONE);
        }
        let mut leaf_of = vec![NONE; segments.len()];
        for (n, node) in nodes.iter().enumerate() {
            if node.count > 0 {
                for it in &items
                    [node.start_or_right as usize..(node.start_or_right + node.count) as usize]
                {
                    leaf_of[it.id as usize] = n as u32;
                }
            }
        }
        SegmentIndex { nodes, parent, items, leaf_of }
    }

    /// Number of indexed segments.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether no segment is indexed.
    #[cfg(test)]
    pub(crate) fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Depth of the tree (1 for a single leaf, 0 when empty).
    #[cfg(test)]
    pub(crate) fn depth(&self) -> usize {
        (0..self.nodes.len())
            .filter(|&n| self.nodes[n].count > 0)
            .map(|mut n| {
                let mut d = 1;
                while self.parent[n] != NONE {
                    n = self.parent[n] as usize;
                    d += 1;
                }
                d
            })
            .max()
            .unwrap_or(0)
    }

    /// The bounding box of an index of `segments` (its root's box, `None` when empty),
    /// without building it: the grown boxes of the segments with finite ends, folded.
    pub(crate) fn bounds_of(segments: &[SegmentGeom]) -> Option<(Point2, Point2)> {
        let (mut min, mut max) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        let mut any = false;
        for g in segments.iter().filter(|g| g.a.iter().chain(&g.b).all(|c| c.is_finite())) {
            let (lo, hi) = seg_box(g);
            let (lo, hi) = grown_box(lo, hi);
            for k in 0..2 {
                min[k] = min[k].min(lo[k]);
                max[k] = max[k].max(hi[k]);
            }
            any = true;
        }
        any.then_some((min, max))
    }

    /// The exact closest segment to `p`, searched from the root.
    pub(crate) fn closest(&self, p: Point2, stats: &mut QueryStats) -> Option<Nearest> {
        if self.nodes.is_empty() {
            return None;
        }
        let first = self.items[0];
        let mut best = Nearest { segment: first.id, projection: first.geom.project(p) };
        stats.segments += 1;
        self.descend(0, p, &mut best, stats);
        Some(best)
    }

    /// The exact closest segment to `p`, starting from the guess `seed` (which must be
    /// the projection of `p` on segment `seed.segment`). The answer does not depend on
    /// the guess; only the work does.
    pub(crate) fn certify(&self, p: Point2, seed: Nearest, stats: &mut QueryStats) -> Nearest {
        let mut best = seed;
        let leaf = match self.leaf_of.get(seed.segment as usize) {
            Some(&l) if l != NONE => l,
            _ => {
                return match self.closest(p, stats) {
                    Some(c) if c.beats(&best) => c,
                    _ => best,
                }
            }
        };
        self.scan_leaf(leaf as usize, p, &mut best, stats);
        let mut node = leaf;
        while self.parent[node as usize] != NONE {
            let par = self.parent[node as usize];
            let sib =
                if node == par + 1 { self.nodes[par as usize].start_or_right } else { par + 1 };
            stats.boxes += 1;
            if self.box_distance_squared(sib as usize, p)
                <= best.projection.distance_squared * SLACK
            {
                self.descend(sib as usize, p, &mut best, stats);
            }
            node = par;
        }
        best
    }

    /// Calls `f` with the id of every segment whose box overlaps the box `[min, max]`.
    pub(crate) fn for_each_overlapping(
        &self,
        min: Point2,
        max: Point2,
        mut f: impl FnMut(u32, &SegmentGeom),
    ) {
        if self.nodes.is_empty() {
            return;
        }
        let mut stack = [0u32; 128];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let at = stack[top];
            let n = &self.nodes[at as usize];
            if n.min[0] > max[0] || n.max[0] < min[0] || n.min[1] > max[1] || n.max[1] < min[1] {
                continue;
            }
            if n.count > 0 {
                for it in
                    &self.items[n.start_or_right as usize..(n.start_or_right + n.count) as usize]
                {
                    let g = &it.geom;
                    let (lo, hi) = seg_box(g);
                    if !(lo[0] > max[0] || hi[0] < min[0] || lo[1] > max[1] || hi[1] < min[1]) {
                        f(it.id, g);
                    }
                }
            } else {
                stack[top] = n.start_or_right;
                stack[top + 1] = at + 1;
                top += 2;
            }
        }
    }

    #[inline]
    fn box_distance_squared(&self, n: usize, p: Point2) -> f64 {
        let b = &self.nodes[n];
        let dx = (b.min[0] - p[0]).max(p[0] - b.max[0]).max(0.0);
        let dy = (b.min[1] - p[1]).max(p[1] - b.max[1]).max(0.0);
        dx * dx + dy * dy
    }

    #[inline]
    fn scan_leaf(&self, n: usize, p: Point2, best: &mut Nearest, stats: &mut QueryStats) {
        let node = &self.nodes[n];
        let items =
            &self.items[node.start_or_right as usize..(node.start_or_right + node.count) as usize];
        stats.segments += items.len() as u64;
        for it in items {
            let c = Nearest { segment: it.id, projection: it.geom.project(p) };
            if c.beats(best) {
                *best = c;
            }
        }
    }

    /// Branch and bound below `root`, nearer child first. Each stacked node keeps its
    /// box distance, checked again when popped since the bound may have shrunk. The
    /// stack holds at most one node per level of a median-split tree (< 64 levels for
    /// any `u32` count of segments).
    fn descend(&self, root: usize, p: Point2, best: &mut Nearest, stats: &mut QueryStats) {
        let mut stack = [(0u32, 0.0f64); 64];
        stack[0] = (root as u32, 0.0);
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (n, dist) = stack[top];
            if dist > best.projection.distance_squared * SLACK {
                continue;
            }
            let node = &self.nodes[n as usize];
            if node.count > 0 {
                self.scan_leaf(n as usize, p, best, stats);
                continue;
            }
            let (l, r) = (n + 1, node.start_or_right);
            let dl = self.box_distance_squared(l as usize, p);
            let dr = self.box_distance_squared(r as usize, p);
            stats.boxes += 2;
            let bound = best.projection.distance_squared * SLACK;
            // Push the farther first so that the nearer is opened first and tightens
            // the bound before the farther is looked at again.
            let (near, far) = if dl <= dr { ((l, dl), (r, dr)) } else { ((r, dr), (l, dl)) };
            if far.1 <= bound {
                stack[top] = far;
                top += 1;
            }
            if near.1 <= bound {
                stack[top] = near;
                top += 1;
            }
        }
    }
}

fn seg_box(g: &SegmentGeom) -> (Point2, Point2) {
    ([g.a[0].min(g.b[0]), g.a[1].min(g.b[1])], [g.a[0].max(g.b[0]), g.a[1].max(g.b[1])])
}

/// A segment's box `lo..hi` grown by a few ulps of its coordinates: a rounded foot point
/// may stray that far outside the exact box.
#[inline]
fn grown_box(lo: Point2, hi: Point2) -> (Point2, Point2) {
    let m = lo[0].abs().max(lo[1].abs()).max(hi[0].abs()).max(hi[1].abs());
    let grow = 8.0 * f64::EPSILON * m + f64::MIN_POSITIVE;
    ([lo[0] - grow, lo[1] - grow], [hi[0] + grow, hi[1] + grow])
}

/// Builds the subtree over `items[..]` (which start at `offset` in the full item array),
/// appending nodes depth-first; returns the node index.
fn build(
    items: &mut [Item],
    offset: usize,
    nodes: &mut Vec<Node>,
    parent: &mut Vec<u32>,
    par: u32,
) -> u32 {
    let me = nodes.len() as u32;
    let (mut min, mut max) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let (mut cmin, mut cmax) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for it in items.iter() {
        let (lo, hi) = seg_box(&it.geom);
        let (glo, ghi) = grown_box(lo, hi);
        for k in 0..2 {
            min[k] = min[k].min(glo[k]);
            max[k] = max[k].max(ghi[k]);
            let c = 0.5 * (lo[k] + hi[k]);
            cmin[k] = cmin[k].min(c);
            cmax[k] = cmax[k].max(c);
        }
    }
    nodes.push(Node { min, max, start_or_right: offset as u32, count: items.len() as u32 });
    parent.push(par);
    if items.len() <= LEAF_SIZE {
        return me;
    }
    let axis = if cmax[0] - cmin[0] >= cmax[1] - cmin[1] { 0 } else { 1 };
    let mid = items.len() / 2;
    // Median by midpoint, ties by id: the same input always gives the same tree.
    items.select_nth_unstable_by(mid, |x, y| {
        let cx = x.geom.a[axis] + x.geom.b[axis];
        let cy = y.geom.a[axis] + y.geom.b[axis];
        cx.total_cmp(&cy).then(x.id.cmp(&y.id))
    });
    let (left, right) = items.split_at_mut(mid);
    build(left, offset, nodes, parent, me);
    let r = build(right, offset + mid, nodes, parent, me);
    nodes[me as usize].start_or_right = r;
    nodes[me as usize].count = 0;
    me
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_support::brute;

    #[test]
    fn closest_and_certify_agree_with_scan() {
        // A zigzag of 200 segments.
        let pts: Vec<Point2> =
            (0..=200).map(|i| [i as f64 * 0.1, if i % 2 == 0 { 0.0 } else { 0.3 }]).collect();
        let segs: Vec<SegmentGeom> = pts.windows(2).map(|w| SegmentGeom::new(w[0], w[1])).collect();
        let idx = SegmentIndex::new(&segs);
        assert_eq!(idx.len(), 200);
        let mut st = QueryStats::default();
        for k in 0..500 {
            let p = [(k as f64 * 0.0731) % 22.0 - 1.0, (k as f64 * 0.377) % 3.0 - 1.5];
            let b = brute(&segs, p);
            assert_eq!(idx.closest(p, &mut st), Some(b));
            for guess in [0u32, 57, 199] {
                let seed = Nearest { segment: guess, projection: segs[guess as usize].project(p) };
                assert_eq!(idx.certify(p, seed, &mut st), b);
            }
        }
    }

    #[test]
    fn overlap_walk_finds_every_box() {
        let segs: Vec<SegmentGeom> =
            (0..50).map(|i| SegmentGeom::new([i as f64, 0.0], [i as f64 + 0.5, 1.0])).collect();
        let idx = SegmentIndex::new(&segs);
        let mut found = Vec::new();
        idx.for_each_overlapping([10.2, 0.4], [12.1, 0.6], |id, _| found.push(id));
        found.sort_unstable();
        assert_eq!(found, vec![10, 11, 12]);
    }

    #[test]
    fn empty_index() {
        let idx = SegmentIndex::new(&[]);
        assert!(idx.is_empty());
        assert_eq!(idx.closest([0.0, 0.0], &mut QueryStats::default()), None);
        assert_eq!(idx.depth(), 0);
    }
}
