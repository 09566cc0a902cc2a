//! A binary tree of oriented boxes over runs of consecutive segments, for the
//! branch-and-bound searches of the clearances and for exact closest-segment queries
//! far from a source.

use super::segment::{Point2, SegmentGeom};
use super::segment_index::{Nearest, QueryStats};

/// A binary tree over runs of consecutive segments (the order of the slice, in which
/// each polyline is one run), each node bounded by a box along its chord. Why not the
/// axis-aligned index: a clearance must rule out the polyline's own segments just
/// outside the window, which curve away from the segment by a fraction of their
/// length; a box along the run's chord is about as thin as that bend and separates
/// them, an axis-aligned one around a slanted run is as wide as the run and does not.
#[derive(Debug)]
pub(crate) struct ChainTree {
    pub(crate) nodes: Vec<ChainNode>,
    /// Parent of each node (`u32::MAX` for the root).
    pub(crate) parent: Vec<u32>,
    /// Leaf of each segment.
    pub(crate) leaf_of: Vec<u32>,
}

#[derive(Debug, Clone)]
pub(crate) struct ChainNode {
    /// The box's frame: origin, unit axis, extents along and across the axis.
    pub(crate) o: Point2,
    pub(crate) u: Point2,
    pub(crate) s: [f64; 2],
    pub(crate) t: [f64; 2],
    /// Segments `lo..hi`.
    pub(crate) lo: u32,
    pub(crate) hi: u32,
    /// Children (`u32::MAX` for a leaf).
    pub(crate) left: u32,
    pub(crate) right: u32,
}

impl ChainNode {
    /// Corners of the box, in order round it.
    #[inline]
    pub(crate) fn corners(&self) -> [Point2; 4] {
        let (o, u, s, t) = (self.o, self.u, self.s, self.t);
        let at = |a: f64, b: f64| [o[0] + a * u[0] - b * u[1], o[1] + a * u[1] + b * u[0]];
        [at(s[0], t[0]), at(s[1], t[0]), at(s[1], t[1]), at(s[0], t[1])]
    }

    /// Squared distance from `p` to the box (0 inside).
    #[inline]
    pub(crate) fn distance_squared(&self, p: Point2) -> f64 {
        let (dx, dy) = (p[0] - self.o[0], p[1] - self.o[1]);
        let (a, b) = (dx * self.u[0] + dy * self.u[1], dy * self.u[0] - dx * self.u[1]);
        let da = (self.s[0] - a).max(a - self.s[1]).max(0.0);
        let db = (self.t[0] - b).max(b - self.t[1]).max(0.0);
        da * da + db * db
    }
}

/// Relative slack on box distances, as in the segment index.
const SLACK: f64 = 1.0 + 16.0 * f64::EPSILON;

/// Most segments in a leaf of the chain tree.
const CHAIN_LEAF: usize = 4;

impl ChainTree {
    /// The tree over `geoms` in their order, boxes grown by `grow` for rounding.
    pub(crate) fn new(geoms: &[SegmentGeom], grow: f64) -> ChainTree {
        let cap = 2 * geoms.len() / CHAIN_LEAF + 2;
        let mut t = ChainTree {
            nodes: Vec::with_capacity(cap),
            parent: Vec::with_capacity(cap),
            leaf_of: vec![u32::MAX; geoms.len()],
        };
        if !geoms.is_empty() {
            t.build(geoms, 0, geoms.len(), grow, u32::MAX);
        }
        t
    }

    /// Builds the subtree over segments `lo..hi`; a leaf's box holds its segments' end
    /// points (grown by `grow` for rounding), an inner node's the corners of its
    /// children's boxes, so that the build is linear in the segments.
    fn build(
        &mut self,
        geoms: &[SegmentGeom],
        lo: usize,
        hi: usize,
        grow: f64,
        parent: u32,
    ) -> u32 {
        let me = self.nodes.len() as u32;
        let run = &geoms[lo..hi];
        let chord = [run[run.len() - 1].b[0] - run[0].a[0], run[run.len() - 1].b[1] - run[0].a[1]];
        let n = chord[0].hypot(chord[1]);
        let u = if n > 0.0 && n.is_finite() { [chord[0] / n, chord[1] / n] } else { [1.0, 0.0] };
        let o = run[0].a;
        self.nodes.push(ChainNode {
            o,
            u,
            s: [0.0; 2],
            t: [0.0; 2],
            lo: lo as u32,
            hi: hi as u32,
            left: u32::MAX,
            right: u32::MAX,
        });
        self.parent.push(parent);
        let mut points: Vec<Point2> = Vec::new();
        let g = if hi - lo > CHAIN_LEAF {
            let mid = lo + (hi - lo) / 2;
            let l = self.build(geoms, lo, mid, grow, me);
            let r = self.build(geoms, mid, hi, grow, me);
            self.nodes[me as usize].left = l;
            self.nodes[me as usize].right = r;
            points.extend_from_slice(&self.nodes[l as usize].corners());
            points.extend_from_slice(&self.nodes[r as usize].corners());
            // The children's corners were rounded once more than their boxes.
            4.0 * f64::EPSILON * o[0].abs().max(o[1].abs())
        } else {
            for (k, g) in run.iter().enumerate() {
                self.leaf_of[lo + k] = me;
                points.push(g.a);
                points.push(g.b);
            }
            grow
        };
        let (mut s, mut t) =
            ([f64::INFINITY, f64::NEG_INFINITY], [f64::INFINITY, f64::NEG_INFINITY]);
        for q in &points {
            let (dx, dy) = (q[0] - o[0], q[1] - o[1]);
            let (a, b) = (dx * u[0] + dy * u[1], dy * u[0] - dx * u[1]);
            s = [s[0].min(a), s[1].max(a)];
            t = [t[0].min(b), t[1].max(b)];
        }
        let (s, t) = ([s[0] - g, s[1] + g], [t[0] - g, t[1] + g]);
        let node = &mut self.nodes[me as usize];
        node.s = s;
        node.t = t;
        me
    }

    /// Branch and bound for the smallest value over the segments, from `best`: the leaf
    /// of segment `start`, then up to the root, opening a sibling only when
    /// `bound(node)`, a lower bound of its segments' values, is below `settle` times
    /// the best so far (nearer child first); `value(id, best)` lowers `best` by segment
    /// `id`. Returns the smallest value found, or `best`.
    pub(crate) fn search_from(
        &self,
        start: u32,
        mut best: f64,
        settle: f64,
        bound: impl Fn(&ChainNode) -> f64,
        mut value: impl FnMut(u32, &mut f64),
    ) -> f64 {
        let Some(&leaf) = self.leaf_of.get(start as usize) else { return best };
        // One pending sibling per level: a tree of 2^32 segments is 31 levels deep.
        let mut stack: [(u32, f64); 96] = [(0, 0.0); 96];
        let mut run = |root: u32, lb: f64, best: &mut f64, stack: &mut [(u32, f64); 96]| {
            stack[0] = (root, lb);
            let mut top = 1;
            while top > 0 {
                top -= 1;
                let (at, lb) = stack[top];
                // NaN bounds open the node.
                if lb >= settle * *best {
                    continue;
                }
                let n = &self.nodes[at as usize];
                if n.left == u32::MAX {
                    for id in n.lo..n.hi {
                        value(id, best);
                    }
                    continue;
                }
                let (bl, br) =
                    (bound(&self.nodes[n.left as usize]), bound(&self.nodes[n.right as usize]));
                let (near, far) = if bl <= br {
                    ((n.left, bl), (n.right, br))
                } else {
                    ((n.right, br), (n.left, bl))
                };
                if top + 2 <= stack.len() {
                    stack[top] = far;
                    stack[top + 1] = near;
                    top += 2;
                } else {
                    // Deeper than any tree here: no clearance rather than a skipped node.
                    *best = 0.0;
                    return;
                }
            }
        };
        run(leaf, 0.0, &mut best, &mut stack);
        let mut node = leaf;
        while self.parent[node as usize] != u32::MAX {
            let par = self.parent[node as usize];
            let pn = &self.nodes[par as usize];
            let sib = if pn.left == node { pn.right } else { pn.left };
            let lb = bound(&self.nodes[sib as usize]);
            if lb < settle * best || lb.is_nan() {
                run(sib, lb, &mut best, &mut stack);
            }
            node = par;
        }
        best
    }

    /// The exact closest of `geoms` (the segments the tree was built on) to `p`, starting
    /// from the guess `seed` (the projection of `p` on `seed.segment`): the guess's leaf, then up to the root, opening the
    /// siblings whose oriented box is not farther than the best so far, nearer child
    /// first. Ties as [`Nearest::beats`]; the answer does not depend on the guess.
    pub(crate) fn closest(
        &self,
        geoms: &[SegmentGeom],
        p: Point2,
        seed: Nearest,
        stats: &mut QueryStats,
    ) -> Nearest {
        let t = self;
        let mut best = seed;
        let Some(&leaf) = t.leaf_of.get(seed.segment as usize) else { return best };
        let mut stack = [(0u32, 0.0f64); 96];
        stack[0] = (leaf, 0.0);
        self.descend(geoms, p, &mut stack, 1, &mut best, stats);
        let mut node = leaf;
        while t.parent[node as usize] != u32::MAX {
            let par = t.parent[node as usize];
            let pn = &t.nodes[par as usize];
            let sib = if pn.left == node { pn.right } else { pn.left };
            stats.boxes += 1;
            let d = t.nodes[sib as usize].distance_squared(p);
            if d <= best.projection.distance_squared * SLACK {
                stack[0] = (sib, d);
                self.descend(geoms, p, &mut stack, 1, &mut best, stats);
            }
            node = par;
        }
        best
    }

    /// A guess for [`ChainTree::closest`] where none is known: the best segment of the
    /// leaf reached from the root by always taking the child whose box is nearer to `p`.
    /// A search from a far guess opens every box nearer than that guess, which around a
    /// closed curve is most of the tree; from this one, about a path's worth.
    pub(crate) fn guess_near(
        &self,
        geoms: &[SegmentGeom],
        p: Point2,
        stats: &mut QueryStats,
    ) -> Option<Nearest> {
        let mut n = self.nodes.first()?;
        while n.left != u32::MAX {
            let (l, r) = (&self.nodes[n.left as usize], &self.nodes[n.right as usize]);
            stats.boxes += 2;
            n = if l.distance_squared(p) <= r.distance_squared(p) { l } else { r };
        }
        stats.segments += u64::from(n.hi - n.lo);
        (n.lo..n.hi)
            .map(|id| Nearest { segment: id, projection: geoms[id as usize].project(p) })
            .reduce(|a, b| if b.beats(&a) { b } else { a })
    }

    /// Branch and bound below the nodes on `stack[..top]` (each with its box distance).
    fn descend(
        &self,
        geoms: &[SegmentGeom],
        p: Point2,
        stack: &mut [(u32, f64); 96],
        mut top: usize,
        best: &mut Nearest,
        stats: &mut QueryStats,
    ) {
        let t = self;
        while top > 0 {
            top -= 1;
            let (at, lb) = stack[top];
            if lb > best.projection.distance_squared * SLACK {
                continue;
            }
            let n = &t.nodes[at as usize];
            if n.left == u32::MAX {
                stats.segments += u64::from(n.hi - n.lo);
                for id in n.lo..n.hi {
                    let c = Nearest { segment: id, projection: geoms[id as usize].project(p) };
                    if c.beats(best) {
                        *best = c;
                    }
                }
                continue;
            }
            stats.boxes += 2;
            let (l, r) = (n.left, n.right);
            let (dl, dr) =
                (t.nodes[l as usize].distance_squared(p), t.nodes[r as usize].distance_squared(p));
            let bound = best.projection.distance_squared * SLACK;
            let (near, far) = if dl <= dr { ((l, dl), (r, dr)) } else { ((r, dr), (l, dl)) };
            // The stack holds at most one pending sibling per level (< 64 levels).
            if far.1 <= bound && top < stack.len() {
                stack[top] = far;
                top += 1;
            }
            if near.1 <= bound && top < stack.len() {
                stack[top] = near;
                top += 1;
            }
        }
    }
}
