//! A quadtree of triangle bounding boxes, for point location in strongly graded
//! background meshes: the triangles whose box may hold a point are those of the one leaf
//! the point falls in.
//!
//! Invariants: every triangle whose (closed) box contains a point `p` inside the root box
//! is listed in the leaf [`BoxTree::candidates`] returns for `p` (a box is filed in every
//! quadrant its closed box touches, and `p` descends into the quadrant holding it, the
//! upper one on a split line); a leaf lists its triangles in increasing order, so that a
//! scan of it breaks ties as a scan of all triangles in order would. A node is split while
//! it holds more than [`LEAF`] boxes, above [`MAX_DEPTH`], and while splitting separates
//! them: some quadrant gets fewer boxes than the node, and the boxes filed in more than
//! one quadrant are at most as many again as the node's (boxes that all cover the centre,
//! a fan around a vertex, stay in one leaf), and while the boxes filed, counted with their copies, stay
//! within [`BUDGET`] per box (a split files the node's boxes again, copies counted): boxes that cover the whole domain (a strip meshed by long
//! triangles) are copied into every quadrant, and without a bound the tree would split
//! to its full depth.
//!
//! A uniform grid sized to the triangle count answers in O(1) on a uniform mesh, but an
//! adapted mesh of an airfoil in a far field 50 chords away has most of its triangles
//! within a few cells of such a grid; the tree's leaves follow the grading.

/// Most boxes in a leaf that may still be split.
const LEAF: usize = 8;
/// Deepest level (2^-24 of the root's side).
const MAX_DEPTH: usize = 24;
/// Copies of boxes (a box filed in more than one quadrant) in the whole tree, per box
/// (plus 1024).
const BUDGET: usize = 12;

#[derive(Debug, Clone, Copy)]
struct Node {
    lo: [f64; 2],
    hi: [f64; 2],
    /// First of the four children (0: a leaf).
    child: u32,
    /// The leaf's boxes: `items[start..end]`.
    start: u32,
    end: u32,
}

/// The quadtree.
#[derive(Debug, Clone)]
pub(crate) struct BoxTree {
    nodes: Vec<Node>,
    items: Vec<u32>,
    /// Box copies the splits may still file.
    budget: usize,
}

impl BoxTree {
    /// Files the boxes `(lo, hi)`, one per triangle.
    pub(crate) fn new(boxes: &[([f64; 2], [f64; 2])]) -> BoxTree {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for (a, b) in boxes {
            for k in 0..2 {
                lo[k] = lo[k].min(a[k]);
                hi[k] = hi[k].max(b[k]);
            }
        }
        if boxes.is_empty() {
            (lo, hi) = ([0.0; 2], [1.0; 2]);
        }
        let mut tree = BoxTree {
            nodes: vec![Node { lo, hi, child: 0, start: 0, end: 0 }],
            items: Vec::new(),
            budget: BUDGET * boxes.len() + 1024,
        };
        let all: Vec<u32> = (0..boxes.len() as u32).collect();
        tree.build(0, all, boxes, 0);
        tree
    }

    fn build(&mut self, node: usize, list: Vec<u32>, boxes: &[([f64; 2], [f64; 2])], depth: usize) {
        let Node { lo, hi, .. } = self.nodes[node];
        let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        if list.len() > LEAF && depth < MAX_DEPTH {
            let quads = quadrants(lo, mid, hi);
            let parts: Vec<Vec<u32>> = quads
                .iter()
                .map(|(qlo, qhi)| {
                    list.iter()
                        .copied()
                        .filter(|&t| {
                            let (a, b) = boxes[t as usize];
                            a[0] <= qhi[0] && b[0] >= qlo[0] && a[1] <= qhi[1] && b[1] >= qlo[1]
                        })
                        .collect()
                })
                .collect();
            let filed: usize = parts.iter().map(Vec::len).sum();
            let copies = filed.saturating_sub(list.len());
            // A split pays when it separates the boxes: not when most of them cross its
            // lines (a fan around a vertex, boxes larger than the node).
            let separates = copies <= list.len() && parts.iter().any(|p| p.len() < list.len());
            if separates && copies <= self.budget {
                self.budget -= copies;
                let child = self.nodes.len();
                self.nodes[node].child = child as u32;
                for (qlo, qhi) in quads {
                    self.nodes.push(Node { lo: qlo, hi: qhi, child: 0, start: 0, end: 0 });
                }
                for (k, part) in parts.into_iter().enumerate() {
                    self.build(child + k, part, boxes, depth + 1);
                }
                return;
            }
        }
        let start = self.items.len() as u32;
        self.items.extend(list);
        self.nodes[node].start = start;
        self.nodes[node].end = self.items.len() as u32;
    }

    /// The triangles of the leaf holding `p` (clamped into the root box): every triangle
    /// whose box contains `p`, and others near it, in increasing order.
    pub(crate) fn candidates(&self, p: [f64; 2]) -> &[u32] {
        let mut n = self.nodes[0];
        while n.child != 0 {
            let mid = [0.5 * (n.lo[0] + n.hi[0]), 0.5 * (n.lo[1] + n.hi[1])];
            let k = usize::from(p[0] >= mid[0]) + 2 * usize::from(p[1] >= mid[1]);
            n = self.nodes[n.child as usize + k];
        }
        &self.items[n.start as usize..n.end as usize]
    }
}

impl BoxTree {
    /// The boxes of each leaf, in increasing order. Two boxes that meet are both filed
    /// in a leaf holding a point they share (every leaf whose closed region holds it).
    pub(crate) fn leaves(&self) -> impl Iterator<Item = &[u32]> + '_ {
        self.nodes
            .iter()
            .filter(|n| n.child == 0)
            .map(|n| &self.items[n.start as usize..n.end as usize])
    }

    /// Every box that meets the closed box `[lo, hi]` (and others near it), each once, in
    /// increasing order: the boxes of every leaf whose closed region meets it. A box
    /// meeting the query shares a point with it; that point lies in a leaf the box is
    /// filed in (a box is filed in every quadrant its closed box touches), and the leaf
    /// meets the query. Points of the query outside the root box meet nothing filed.
    pub(crate) fn query(&self, lo: [f64; 2], hi: [f64; 2], out: &mut Vec<u32>) {
        out.clear();
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let n = self.nodes[i];
            if lo[0] > n.hi[0] || hi[0] < n.lo[0] || lo[1] > n.hi[1] || hi[1] < n.lo[1] {
                continue;
            }
            if n.child == 0 {
                out.extend_from_slice(&self.items[n.start as usize..n.end as usize]);
            } else {
                stack.extend((0..4).map(|k| n.child as usize + k));
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

/// The four quadrants of `[lo, hi]` split at `mid`: lower left, lower right, upper left,
/// upper right (the order [`BoxTree::candidates`] indexes them in).
fn quadrants(lo: [f64; 2], mid: [f64; 2], hi: [f64; 2]) -> [([f64; 2], [f64; 2]); 4] {
    [
        ([lo[0], lo[1]], [mid[0], mid[1]]),
        ([mid[0], lo[1]], [hi[0], mid[1]]),
        ([lo[0], mid[1]], [mid[0], hi[1]]),
        ([mid[0], mid[1]], [hi[0], hi[1]]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Boxes graded over seven orders of magnitude, with boxes over the whole domain, a
    /// fan of boxes that all hold one point, and boxes on split lines.
    fn graded_boxes(rand: &mut impl FnMut() -> f64) -> Vec<([f64; 2], [f64; 2])> {
        let mut boxes = Vec::new();
        for _ in 0..3000 {
            let size = 0.05 * 10f64.powf(-6.0 * rand());
            let c = [rand() * rand(), rand() * rand()];
            let (w, h) = (size * rand(), size * rand());
            boxes.push(([c[0] - w, c[1] - h], [c[0] + w, c[1] + h]));
        }
        for k in 0..5 {
            boxes.push(([-0.1 - 1e-3 * k as f64, -0.1], [1.1, 1.1 + 1e-3 * k as f64]));
        }
        for k in 0..50 {
            boxes.push(([0.005 - 1e-3 * k as f64, 0.004], [0.006, 0.007 + 1e-4 * k as f64]));
        }
        // Degenerate boxes (an axis-aligned segment, a point) and one on the root's edge.
        boxes.push(([0.25, 0.3], [0.5, 0.3]));
        boxes.push(([0.125, 0.125], [0.125, 0.125]));
        boxes.push(([1.1, 0.5], [1.1, 0.6]));
        boxes
    }

    /// Brute-force twin of [`BoxTree::query`]: every box meeting a query box is listed,
    /// once, in increasing order; queries of every scale, degenerate ones, ones touching a
    /// box at one side only and ones partly or wholly outside the root.
    #[test]
    fn a_box_query_lists_every_box_it_meets() {
        let mut s = 7u64;
        let mut rand = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let boxes = graded_boxes(&mut rand);
        let tree = BoxTree::new(&boxes);
        let mut out = Vec::new();
        for i in 0..6000 {
            let (lo, hi) = match i % 4 {
                0 => {
                    let size = 0.3 * 10f64.powf(-7.0 * rand());
                    let c = [rand() * 1.4 - 0.2, rand() * 1.4 - 0.2];
                    ([c[0] - size * rand(), c[1] - size * rand()], [c[0] + size, c[1] + size])
                }
                // A box's own box, and one touching it on its right side only.
                1 => boxes[i % boxes.len()],
                2 => {
                    let (a, b) = boxes[i % boxes.len()];
                    ([b[0], a[1]], [b[0] + 1e-9, a[1]])
                }
                _ => {
                    let p = [rand() * 1.2 - 0.1, rand() * 1.2 - 0.1];
                    (p, p)
                }
            };
            tree.query(lo, hi, &mut out);
            assert!(out.windows(2).all(|w| w[0] < w[1]));
            for (t, (a, b)) in boxes.iter().enumerate() {
                if a[0] <= hi[0] && lo[0] <= b[0] && a[1] <= hi[1] && lo[1] <= b[1] {
                    assert!(
                        out.binary_search(&(t as u32)).is_ok(),
                        "{lo:?} {hi:?}: box {t} missing"
                    );
                }
            }
        }
        // Not everything: the index prunes (on average far fewer than all boxes).
        tree.query([0.5, 0.5], [0.5001, 0.5001], &mut out);
        assert!(out.len() < boxes.len() / 10, "{}", out.len());
    }

    /// Brute-force twin: every box containing a point is among the candidates, in
    /// increasing order, on boxes graded over seven orders of magnitude.
    #[test]
    fn candidates_hold_every_box_containing_the_point() {
        let mut s = 99u64;
        let mut rand = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let boxes = graded_boxes(&mut rand);
        let tree = BoxTree::new(&boxes);
        assert!(tree.nodes.len() > 100, "the tree follows the grading");
        assert!(tree.items.len() <= BUDGET * boxes.len() + 1024 + boxes.len());
        for i in 0..20000 {
            let p = if i % 2 == 0 {
                [rand() * 1.2 - 0.1, rand() * 1.2 - 0.1]
            } else {
                let (a, b) = boxes[i % boxes.len()];
                [a[0] + (b[0] - a[0]) * rand(), a[1] + (b[1] - a[1]) * rand()]
            };
            let c = tree.candidates(p);
            assert!(c.windows(2).all(|w| w[0] < w[1]));
            for (t, (a, b)) in boxes.iter().enumerate() {
                if a[0] <= p[0] && p[0] <= b[0] && a[1] <= p[1] && p[1] <= b[1] {
                    assert!(c.binary_search(&(t as u32)).is_ok(), "{p:?}: box {t} missing");
                }
            }
        }
    }
}
