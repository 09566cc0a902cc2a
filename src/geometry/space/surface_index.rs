//! Exact closest points on a triangulated surface: a bounding-volume hierarchy over its
//! triangles that gives, for any query point, bit for bit what the brute-force scan over
//! every triangle with the same kernel ([`TriangleGeom::project`]) gives: the distance,
//! the closest point, the triangle (the lowest index among equally near ones) and the
//! feature it lies on.
//!
//! Method (hand-written: parry3d's `TriMesh` answers the same query with the same kind of
//! tree, but neither its ties nor its rounding match a brute-force scan; the benchmark
//! `surface_distance` compares the two: 1.8x parry's throughput per core on 10^6
//! queries, short of the 2x aimed at):
//! - Build: top-down binary tree, each node split by the binned surface-area heuristic
//!   ([`split_sah`]; below depth [`SAH_DEPTH`], and where it finds no plane, at the
//!   median of the triangles' box centres along the longer side of the centres' box,
//!   ties by triangle index), at most [`LEAF_SIZE`] triangles per leaf. Every choice
//!   depends only on the input, so the same input always gives the same tree.
//!   Each node stores the boxes of both children side by side. The binary tree is then
//!   collapsed two levels into one: a searched node has up to four children whose
//!   boxes are tested in one pass (half the stack traffic of the binary tree). The
//!   triangles are stored in leaf order, their boxes in arrays of their own, axis by
//!   axis (what a leaf scan reads first: one vectorised pass gives a leaf's distances).
//! - Query: branch and bound, nearer children first, pruning a box only when its squared
//!   distance is strictly above the best so far, and skipping a triangle whose own box
//!   is. Why this never loses the scan's answer: the kernel never returns less than the
//!   squared distance to the triangle's box, computed by the same expression as a node's
//!   box distance, and rounding is monotone, so a pruned box holds only triangles whose
//!   computed distance is strictly larger than the best (a tie is never pruned, and
//!   ties go to the lower index as in the scan).
//! - Many queries ([`SurfaceIndex::closest_many`]): points taken in Morton order, in
//!   fixed chunks run in parallel, each query starting from the answer of the previous
//!   one as its first bound. The answer does not depend on the start (only the work
//!   does), nor on the chunking, so the output is the same on every thread count.
//!
//! Cost: build O(m log m) for m triangles; a query O(log m) box tests plus the kernels of
//! the few leaves whose boxes reach the answer's distance.

use rayon::prelude::*;

use super::triangle::{gap, Point3, TriangleGeom, TriangleProjection};

/// Most triangles in one leaf.
pub(crate) const LEAF_SIZE: usize = 16;

/// Sentinel for "no node" / "no triangle".
const NONE: u32 = u32::MAX;

/// Queries per parallel chunk of [`SurfaceIndex::closest_many`] (fixed: the chunking
/// does not depend on the thread count).
const CHUNK: usize = 1024;

/// The answer to a closest-point query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SurfacePoint {
    /// The triangle (its index in the list the index was built from).
    pub(crate) triangle: u32,
    /// Where the query point projects on it.
    pub(crate) projection: TriangleProjection,
}

impl SurfacePoint {
    /// Whether `self` beats `other`: smaller squared distance, then smaller triangle.
    #[inline]
    pub(crate) fn beats(&self, other: &SurfacePoint) -> bool {
        let (d, e) = (self.projection.distance_squared, other.projection.distance_squared);
        d < e || (d == e && self.triangle < other.triangle)
    }

    /// Distance from the query point to the surface.
    pub(crate) fn distance(&self) -> f64 {
        self.projection.distance_squared.sqrt()
    }

    /// The unit vector from the closest point to `p` (the query point), `None` when `p`
    /// lies on the surface. For a closest point on an edge or at a vertex this is the
    /// direction a wall-aligned size takes as "across"; in a face it is the normal on
    /// `p`'s side.
    pub(crate) fn away(&self, p: Point3) -> Option<Point3> {
        let f = self.projection.foot;
        let q = [p[0] - f[0], p[1] - f[1], p[2] - f[2]];
        let len = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
        (len > 0.0 && len.is_finite()).then(|| [q[0] / len, q[1] / len, q[2] / len])
    }
}

/// Why a surface cannot be indexed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(crate) enum SurfaceError {
    /// A triangle names a vertex that does not exist.
    #[error("triangle {triangle} names vertex {vertex}, but there are only {count} vertices")]
    VertexOutOfRange { triangle: usize, vertex: u32, count: usize },
    /// A vertex of a triangle has an infinite or NaN coordinate.
    #[error("triangle {triangle} has vertex {vertex} with a non-finite coordinate")]
    NonFinite { triangle: usize, vertex: u32 },
    /// More triangles than the index numbers (2^32 − 1).
    #[error("{0} triangles: at most 4294967294 can be indexed")]
    TooMany(usize),
}

/// One node: the boxes of both children (`lo[axis][child]`), and for each child either
/// a node index (`count == 0`) or a leaf's range of triangle slots (`count > 0`). A
/// child `NONE` with `count == 0` is empty (only the root's second child, when the
/// whole surface fits in one leaf).
#[derive(Debug, Clone, Copy)]
struct Node {
    lo: [[f64; 2]; 3],
    hi: [[f64; 2]; 3],
    child: [u32; 2],
    count: [u32; 2],
}

/// Number of children of a [`Wide`] node.
const WIDTH: usize = 4;

/// A node of the searched tree: the binary tree collapsed two levels into one, up to
/// [`WIDTH`] children whose boxes are stored axis by axis (`lo[axis][child]`, as in
/// [`Node`]) so that one pass computes every child's box distance. A child is a node
/// index (`count == 0`), a leaf's range of triangle slots (`count > 0`), or absent
/// (`child == NONE`, `count == 0`, box empty, only at the end of the list).
#[derive(Debug, Clone, Copy)]
struct Wide {
    lo: [[f64; WIDTH]; 3],
    hi: [[f64; WIDTH]; 3],
    child: [u32; WIDTH],
    count: [u32; WIDTH],
}

impl Wide {
    /// Squared distances from `p` to every child's box, each exactly as
    /// [`box_distance_squared`](super::triangle::box_distance_squared) computes it (an
    /// absent child's empty box gives +∞). One pass over the four, written so that it
    /// vectorises ([`gap`] has no NaN fix-ups).
    #[inline]
    fn distances(&self, p: Point3) -> [f64; WIDTH] {
        let mut d = [0.0; WIDTH];
        for (c, dc) in d.iter_mut().enumerate() {
            let gx = gap(self.lo[0][c], self.hi[0][c], p[0]);
            let gy = gap(self.lo[1][c], self.hi[1][c], p[1]);
            let gz = gap(self.lo[2][c], self.hi[2][c], p[2]);
            *dc = gx * gx + gy * gy + gz * gz;
        }
        d
    }
}

/// A triangle while building: its id, box and box centre.
#[derive(Debug, Clone, Copy)]
struct BuildItem {
    id: u32,
    lo: Point3,
    hi: Point3,
}

impl BuildItem {
    fn centre(&self, k: usize) -> f64 {
        0.5 * self.lo[k] + 0.5 * self.hi[k]
    }
}

/// Exact closest-point queries over a fixed triangulated surface.
#[derive(Debug, Clone)]
pub(crate) struct SurfaceIndex {
    /// The searched tree (root at 0), see [`Wide`].
    nodes: Vec<Wide>,
    /// Triangles in leaf order, with their ids and, apart, their boxes axis by axis
    /// (`lo[axis][slot]`, `hi[axis][slot]`): the boxes are what a leaf scan reads first,
    /// packed so that one pass of fixed length computes a whole leaf's box distances.
    /// The box arrays carry [`LEAF_SIZE`] padding slots (empty boxes) at the end, so that
    /// pass may read `LEAF_SIZE` slots from any leaf's first.
    tris: Vec<TriangleGeom>,
    lo: [Vec<f64>; 3],
    hi: [Vec<f64>; 3],
    ids: Vec<u32>,
    /// Slot in `tris` of each triangle id.
    slot_of: Vec<u32>,
}

impl SurfaceIndex {
    /// Indexes the triangles `triangles` (corner indices into `vertices`); triangle ids
    /// are their positions in the slice.
    pub(crate) fn new(
        vertices: &[Point3],
        triangles: &[[u32; 3]],
    ) -> Result<SurfaceIndex, SurfaceError> {
        let geoms = triangle_geoms(vertices, triangles)?;
        let mut items: Vec<BuildItem> = geoms
            .iter()
            .enumerate()
            .map(|(i, g)| {
                let (lo, hi) = g.bounds();
                BuildItem { id: i as u32, lo, hi }
            })
            .collect();
        let mut binary = Vec::with_capacity(items.len() / 2 + 1);
        let mut nodes = Vec::with_capacity(items.len() / 4 + 1);
        if !items.is_empty() {
            build(&mut items, 0, 0, &mut binary);
            collapse(&binary, 0, &mut nodes);
        }
        let ids: Vec<u32> = items.iter().map(|it| it.id).collect();
        let tris: Vec<TriangleGeom> = ids.iter().map(|&i| geoms[i as usize]).collect();
        let pad = tris.len() + LEAF_SIZE;
        let mut lo: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(pad));
        let mut hi: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(pad));
        for g in &tris {
            let (l, h) = g.bounds();
            for k in 0..3 {
                lo[k].push(l[k]);
                hi[k].push(h[k]);
            }
        }
        for k in 0..3 {
            lo[k].resize(pad, f64::INFINITY);
            hi[k].resize(pad, f64::NEG_INFINITY);
        }
        let mut slot_of = vec![NONE; ids.len()];
        for (s, &i) in ids.iter().enumerate() {
            slot_of[i as usize] = s as u32;
        }
        Ok(SurfaceIndex { nodes, tris, lo, hi, ids, slot_of })
    }

    /// Number of indexed triangles.
    pub(crate) fn len(&self) -> usize {
        self.tris.len()
    }

    /// Whether no triangle is indexed.
    pub(crate) fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// The triangle with id `id`.
    pub(crate) fn triangle(&self, id: u32) -> &TriangleGeom {
        &self.tris[self.slot_of[id as usize] as usize]
    }

    /// The unit normal of triangle `id`, oriented as `(v1 − v0) × (v2 − v0)`; `None`
    /// for a degenerate triangle.
    pub(crate) fn normal(&self, id: u32) -> Option<Point3> {
        self.triangle(id).unit_normal()
    }

    /// The exact closest point of the surface to `p`; `None` when the surface is empty
    /// or `p` is not finite.
    pub(crate) fn closest(&self, p: Point3) -> Option<SurfacePoint> {
        self.closest_from(p, NONE)
    }

    /// As [`closest`](Self::closest), with triangle `seed` tried first as a bound: the
    /// answer is the same whatever the seed (an id out of range is ignored); only the
    /// work is smaller when the seed is near.
    pub(crate) fn closest_from(&self, p: Point3, seed: u32) -> Option<SurfacePoint> {
        if self.tris.is_empty() || !p.iter().all(|c| c.is_finite()) {
            return None;
        }
        let mut best = SurfacePoint {
            triangle: NONE,
            projection: TriangleProjection {
                distance_squared: f64::INFINITY,
                foot: p,
                feature: super::triangle::Feature::Face,
            },
        };
        if let Some(&slot) = self.slot_of.get(seed as usize) {
            best = SurfacePoint { triangle: seed, projection: self.tris[slot as usize].project(p) };
        }
        self.search(p, &mut best);
        (best.triangle != NONE).then_some(best)
    }

    /// The closest point of every point of `points`, in their order, computed in
    /// parallel; the same output on every thread count.
    pub(crate) fn closest_many(&self, points: &[Point3]) -> Vec<Option<SurfacePoint>> {
        let order = morton_order(points);
        let found: Vec<Option<SurfacePoint>> = order
            .par_chunks(CHUNK)
            .flat_map_iter(|chunk| {
                let mut seed = NONE;
                chunk.iter().map(move |&i| {
                    let r = self.closest_from(points[i], seed);
                    if let Some(r) = r {
                        seed = r.triangle;
                    }
                    r
                })
            })
            .collect();
        let mut out = vec![None; points.len()];
        for (&i, r) in order.iter().zip(found) {
            out[i] = r;
        }
        out
    }

    /// Branch and bound from the root, nearer children first. A stack entry is a node
    /// or a leaf with its box distance, checked again when popped since the bound may
    /// have shrunk. The binary depth is at most [`SAH_DEPTH`] + 33 (median splits below
    /// it), so the collapsed depth is at most 37; a node pushes at most [`WIDTH`]
    /// entries after its own pop, so the stack holds at most 37 × 3 + 4 entries.
    fn search(&self, p: Point3, best: &mut SurfacePoint) {
        // (node or first slot, leaf count (0: node), box distance)
        let mut stack = [(0u32, 0u32, 0.0f64); 128];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let (at, count, dist) = stack[top];
            if dist > best.projection.distance_squared {
                continue;
            }
            if count > 0 {
                self.scan_leaf(at as usize, count as usize, p, best);
                continue;
            }
            let node = &self.nodes[at as usize];
            let d = node.distances(p);
            let bound = best.projection.distance_squared;
            // The children within the bound, sorted by decreasing distance (insertion
            // sort of at most four; equal distances keep child order), pushed so that
            // the nearest is popped first and tightens the bound.
            let mut kept = [(0.0f64, 0usize); WIDTH];
            let mut n = 0;
            for (c, &dc) in d.iter().enumerate() {
                if dc <= bound && !(node.child[c] == NONE && node.count[c] == 0) {
                    let mut i = n;
                    while i > 0 && kept[i - 1].0 < dc {
                        kept[i] = kept[i - 1];
                        i -= 1;
                    }
                    kept[i] = (dc, c);
                    n += 1;
                }
            }
            for &(dc, c) in &kept[..n] {
                stack[top] = (node.child[c], node.count[c], dc);
                top += 1;
            }
        }
    }

    #[inline]
    fn scan_leaf(&self, first: usize, count: usize, p: Point3, best: &mut SurfacePoint) {
        // Every box distance of the leaf in one pass of fixed length (vectorised), each
        // as `box_distance_squared` computes it; padding slots are never used.
        let mut floors = [0.0f64; LEAF_SIZE];
        let (lo, hi) = (&self.lo, &self.hi);
        let span = first..first + LEAF_SIZE;
        let (lx, ly, lz) = (&lo[0][span.clone()], &lo[1][span.clone()], &lo[2][span.clone()]);
        let (hx, hy, hz) = (&hi[0][span.clone()], &hi[1][span.clone()], &hi[2][span]);
        for (i, f) in floors.iter_mut().enumerate() {
            let gx = gap(lx[i], hx[i], p[0]);
            let gy = gap(ly[i], hy[i], p[1]);
            let gz = gap(lz[i], hz[i], p[2]);
            *f = gx * gx + gy * gy + gz * gz;
        }
        for (s, &floor) in (first..first + count).zip(&floors) {
            if floor > best.projection.distance_squared {
                continue;
            }
            // The boxes are the triangles' own (`bounds`), so this is `project(p)`.
            let projection = self.tris[s].project_above(p, floor);
            let c = SurfacePoint { triangle: self.ids[s], projection };
            if c.beats(best) {
                *best = c;
            }
        }
    }
}

/// The kernels of `triangles`, in their order, checked.
pub(crate) fn triangle_geoms(
    vertices: &[Point3],
    triangles: &[[u32; 3]],
) -> Result<Vec<TriangleGeom>, SurfaceError> {
    if triangles.len() >= NONE as usize {
        return Err(SurfaceError::TooMany(triangles.len()));
    }
    let mut out = Vec::with_capacity(triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        let mut v = [[0.0; 3]; 3];
        for (k, &i) in tri.iter().enumerate() {
            let p = *vertices.get(i as usize).ok_or(SurfaceError::VertexOutOfRange {
                triangle: t,
                vertex: i,
                count: vertices.len(),
            })?;
            if !p.iter().all(|c| c.is_finite()) {
                return Err(SurfaceError::NonFinite { triangle: t, vertex: i });
            }
            v[k] = p;
        }
        out.push(TriangleGeom::new(v[0], v[1], v[2]));
    }
    Ok(out)
}

/// The brute-force twin: the closest of `geoms` (in id order) to `p` by projecting on
/// every one, ties to the smaller id; `None` when empty or `p` is not finite.
pub(crate) fn closest_brute(geoms: &[TriangleGeom], p: Point3) -> Option<SurfacePoint> {
    if !p.iter().all(|c| c.is_finite()) {
        return None;
    }
    let mut best: Option<SurfacePoint> = None;
    for (i, g) in geoms.iter().enumerate() {
        let c = SurfacePoint { triangle: i as u32, projection: g.project(p) };
        if best.map_or(true, |b| c.beats(&b)) {
            best = Some(c);
        }
    }
    best
}

/// Builds the node over `items` (which start at slot `offset`), appending nodes
/// depth-first; returns the node's index. `items.len() > 0`.
fn build(items: &mut [BuildItem], offset: usize, depth: usize, nodes: &mut Vec<Node>) -> u32 {
    let me = nodes.len() as u32;
    let empty = Node {
        lo: [[f64::INFINITY; 2]; 3],
        hi: [[f64::NEG_INFINITY; 2]; 3],
        child: [NONE; 2],
        count: [0; 2],
    };
    nodes.push(empty);
    let halves: Vec<(usize, usize)> = if items.len() <= LEAF_SIZE {
        vec![(0, items.len())]
    } else {
        let mid = if depth < SAH_DEPTH { split_sah(items) } else { None };
        let mid = mid.unwrap_or_else(|| split(items));
        vec![(0, mid), (mid, items.len())]
    };
    let mut node = empty;
    for (c, &(from, to)) in halves.iter().enumerate() {
        let part = &mut items[from..to];
        for it in part.iter() {
            for k in 0..3 {
                node.lo[k][c] = node.lo[k][c].min(it.lo[k]);
                node.hi[k][c] = node.hi[k][c].max(it.hi[k]);
            }
        }
        if part.len() <= LEAF_SIZE {
            node.child[c] = (offset + from) as u32;
            node.count[c] = part.len() as u32;
        } else {
            node.child[c] = build(part, offset + from, depth + 1, nodes);
        }
    }
    nodes[me as usize] = node;
    me
}

/// Collapses binary node `b` and its binary children into one [`Wide`] node (each
/// internal child replaced by its own two children), appending wide nodes depth-first;
/// returns the node's index. The boxes are copied, never recomputed, so every box is
/// the one the binary tree built (a child's box inside its parent's).
fn collapse(binary: &[Node], b: u32, out: &mut Vec<Wide>) -> u32 {
    let me = out.len() as u32;
    let mut wide = Wide {
        lo: [[f64::INFINITY; WIDTH]; 3],
        hi: [[f64::NEG_INFINITY; WIDTH]; 3],
        child: [NONE; WIDTH],
        count: [0; WIDTH],
    };
    out.push(wide);
    let node = &binary[b as usize];
    let mut n = 0;
    for c in 0..2 {
        let (child, count) = (node.child[c], node.count[c]);
        if child == NONE && count == 0 {
            continue;
        }
        let entries: Vec<(&Node, usize)> = if count == 0 {
            let inner = &binary[child as usize];
            (0..2)
                .filter(|&g| !(inner.child[g] == NONE && inner.count[g] == 0))
                .map(|g| (inner, g))
                .collect()
        } else {
            vec![(node, c)]
        };
        for (from, g) in entries {
            for k in 0..3 {
                wide.lo[k][n] = from.lo[k][g];
                wide.hi[k][n] = from.hi[k][g];
            }
            wide.count[n] = from.count[g];
            wide.child[n] = if from.count[g] == 0 {
                collapse(binary, from.child[g], out)
            } else {
                from.child[g]
            };
            n += 1;
        }
    }
    out[me as usize] = wide;
    me
}

/// Bins per axis of the surface-area split.
const SAH_BINS: usize = 16;

/// Below this depth a node is split by surface area, deeper at the median (which bounds
/// the depth: at most `SAH_DEPTH + 33` binary levels).
const SAH_DEPTH: usize = 40;

/// Half the surface area of the box `[lo, hi]` (0 for an empty one).
fn half_area(lo: Point3, hi: Point3) -> f64 {
    let d = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    if d.iter().any(|x| x.is_nan() || *x < 0.0) {
        return 0.0;
    }
    d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
}

/// Reorders `items` into two parts by the binned surface-area heuristic (the split
/// plane, among [`SAH_BINS`] − 1 per axis of the centres' box, that minimises
/// `area(left) × |left| + area(right) × |right|`, the first on ties); returns the split
/// position, or `None` when every plane leaves one side empty. Why: the boxes of a
/// surface's patches fit tighter than with median splits, so fewer of them reach a
/// query's distance. Deterministic: the same input order gives the same parts.
fn split_sah(items: &mut [BuildItem]) -> Option<usize> {
    let (mut cmin, mut cmax) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for it in items.iter() {
        for k in 0..3 {
            cmin[k] = cmin[k].min(it.centre(k));
            cmax[k] = cmax[k].max(it.centre(k));
        }
    }
    let bin = |it: &BuildItem, k: usize| -> usize {
        let w = cmax[k] - cmin[k];
        let b = ((it.centre(k) - cmin[k]) * (SAH_BINS as f64 / w)) as usize;
        b.min(SAH_BINS - 1)
    };
    let mut best: Option<(f64, usize, usize)> = None;
    for k in 0..3 {
        let w = cmax[k] - cmin[k];
        if w.is_nan() || w <= 0.0 {
            continue;
        }
        let mut lo = [[f64::INFINITY; 3]; SAH_BINS];
        let mut hi = [[f64::NEG_INFINITY; 3]; SAH_BINS];
        let mut count = [0usize; SAH_BINS];
        for it in items.iter() {
            let b = bin(it, k);
            count[b] += 1;
            for a in 0..3 {
                lo[b][a] = lo[b][a].min(it.lo[a]);
                hi[b][a] = hi[b][a].max(it.hi[a]);
            }
        }
        // Cost of the right side of each plane, swept from the right.
        let mut right = [0.0; SAH_BINS];
        let (mut rlo, mut rhi, mut rn) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0);
        for b in (1..SAH_BINS).rev() {
            for a in 0..3 {
                rlo[a] = rlo[a].min(lo[b][a]);
                rhi[a] = rhi[a].max(hi[b][a]);
            }
            rn += count[b];
            right[b] = half_area(rlo, rhi) * rn as f64;
        }
        let (mut llo, mut lhi, mut ln) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3], 0);
        for b in 1..SAH_BINS {
            for a in 0..3 {
                llo[a] = llo[a].min(lo[b - 1][a]);
                lhi[a] = lhi[a].max(hi[b - 1][a]);
            }
            ln += count[b - 1];
            if ln == 0 || ln == items.len() {
                continue;
            }
            let cost = half_area(llo, lhi) * ln as f64 + right[b];
            if best.map_or(true, |(c, _, _)| cost < c) {
                best = Some((cost, k, b));
            }
        }
    }
    let (_, k, plane) = best?;
    // In-place partition: left part first.
    let mut mid = 0;
    for i in 0..items.len() {
        if bin(&items[i], k) < plane {
            items.swap(i, mid);
            mid += 1;
        }
    }
    Some(mid)
}

/// Reorders `items` into two halves at the median of the box centres along the longer
/// side of the centres' box (ties by id); returns the split position.
fn split(items: &mut [BuildItem]) -> usize {
    let (mut cmin, mut cmax) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for it in items.iter() {
        for k in 0..3 {
            cmin[k] = cmin[k].min(it.centre(k));
            cmax[k] = cmax[k].max(it.centre(k));
        }
    }
    let ext = [cmax[0] - cmin[0], cmax[1] - cmin[1], cmax[2] - cmin[2]];
    let axis = if ext[0] >= ext[1] && ext[0] >= ext[2] {
        0
    } else if ext[1] >= ext[2] {
        1
    } else {
        2
    };
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |x, y| {
        x.centre(axis).total_cmp(&y.centre(axis)).then(x.id.cmp(&y.id))
    });
    mid
}

/// Indices of the finite points of `points` in Morton (Z-curve) order over their
/// bounding box, ties by index, then those of the non-finite points.
fn morton_order(points: &[Point3]) -> Vec<usize> {
    let finite = |p: &Point3| p.iter().all(|c| c.is_finite());
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points.iter().filter(|p| finite(p)) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    const LEVELS: f64 = ((1u64 << 21) - 1) as f64;
    let scale: Vec<f64> = (0..3)
        .map(|k| {
            let w = hi[k] - lo[k];
            if w > 0.0 && w.is_finite() {
                LEVELS / w
            } else {
                0.0
            }
        })
        .collect();
    let mut keyed: Vec<(u64, usize)> = points
        .par_iter()
        .enumerate()
        .map(|(i, p)| {
            if !finite(p) {
                return (u64::MAX, i);
            }
            let mut code = 0u64;
            for k in 0..3 {
                // In [0, 2^21 - 1]; `as` saturates, so rounding cannot overflow.
                let q = (((p[k] - lo[k]) * scale[k]) as u64).min((1 << 21) - 1);
                code |= spread(q) << k;
            }
            (code, i)
        })
        .collect();
    keyed.par_sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The 21 low bits of `x` spread to every third bit.
fn spread(x: u64) -> u64 {
    let mut x = x & 0x1f_ffff;
    x = (x | x << 32) & 0x1f_0000_0000_ffff;
    x = (x | x << 16) & 0x1f_0000_ff00_00ff;
    x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
    x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
    x = (x | x << 2) & 0x1249_2492_4924_9249;
    x
}
