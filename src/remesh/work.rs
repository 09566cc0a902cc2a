//! The mutable triangle mesh the operators edit: coordinates, metrics, the [`Role`] of
//! each vertex, counter-clockwise triangles with their face, vertex → triangle adjacency,
//! and the constrained edges with their piece.
//!
//! The fields are private: the operators read through accessors and change the mesh only
//! through the few edits below ([`Work::add_vertex`], [`Work::add_tri`],
//! [`Work::set_tri`], [`Work::kill_tri`], [`Work::place`], …), each of which keeps the
//! adjacency exact (a triangle is in the list of each of its corners, and only there).
//!
//! Triangles are never reused or reordered while remeshing (dead ones are flagged and
//! dropped at the end), adjacency lists change only by removing an entry in place or
//! appending one, and every sweep walks vectors in index order, so the result does not
//! depend on anything but the input. The constrained-edge map is only ever looked up,
//! never iterated.

use super::boundary::Boundary;
use super::options::BoundaryMode;
use crate::metric::length::{metric_edge_length, quality_in_metric};
use crate::metric::Sym2;
use crate::metric_field::Interpolator;

/// What a vertex may do.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Role {
    /// Free to move in its face.
    Free,
    /// Slides along piece `piece` of the boundary, at arc-length parameter `s`.
    Slides {
        /// The piece.
        piece: u32,
        /// The parameter on it.
        s: f64,
    },
    /// Never moves nor vanishes: a corner, a topological point, a node no triangle uses.
    Fixed,
    /// Removed by a collapse.
    Dead,
}

impl Role {
    /// The piece of a sliding vertex.
    #[inline]
    pub(super) fn piece(self) -> Option<u32> {
        match self {
            Role::Slides { piece, .. } => Some(piece),
            _ => None,
        }
    }
}

/// Key of the undirected edge `ab`.
#[inline]
pub(super) fn key(a: u32, b: u32) -> (u32, u32) {
    if a < b {
        (a, b)
    } else {
        (b, a)
    }
}

pub(crate) use crate::geometry::segment::orient;

/// Metric quality used to accept or refuse an operation: the shape quality in the
/// arithmetic mean of the corner metrics (SPD, and three times cheaper than the
/// Log-Euclidean centroid metric that [`crate::conformity`] reports with).
#[inline]
pub(super) fn op_quality(p: [[f64; 2]; 3], m: [&Sym2; 3]) -> f64 {
    let mean = (1.0 / 3.0) * (*m[0] + *m[1] + *m[2]);
    quality_in_metric(p[0], p[1], p[2], &mean)
}

/// The operators whose refusals [`Work::refuse`] keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Op {
    Split = 0,
    Collapse = 1,
}

/// The mesh under edit.
pub(super) struct Work<'a> {
    /// Coordinates.
    pts: Vec<[f64; 2]>,
    /// Metric at each vertex (interpolated from the input field).
    met: Vec<Sym2>,
    /// What each vertex may do.
    role: Vec<Role>,
    /// Triangles using each vertex.
    vtris: Vec<Vec<u32>>,
    /// Counter-clockwise triangles.
    tris: Vec<[u32; 3]>,
    /// Face (index into the face tag table) of each triangle.
    face: Vec<u32>,
    /// Whether each triangle is still in the mesh.
    alive: Vec<bool>,
    /// Operation quality of each triangle ([`op_quality`]), kept up to date by every
    /// edit that changes a triangle's corners or a corner's place or metric.
    qual: Vec<f64>,
    /// Scratch marks of [`Work::edges_around`], all `false` between calls.
    tri_mark: Vec<bool>,
    /// Scratch buffer of the radix sorts of edge keys.
    sort_scratch: Vec<u64>,
    /// Constrained edges and their piece.
    cons: ahash::AHashMap<(u32, u32), u32>,
    /// Vertices whose ball changed since the last swap phase, listed once each.
    dirty: Vec<u32>,
    /// Whether each vertex is in `dirty`.
    is_dirty: Vec<bool>,
    /// Whether the next smoothing sweep should try each vertex (its ball changed since
    /// it was last tried).
    active: Vec<bool>,
    /// Edit clock: one tick per edit.
    clock: u64,
    /// For each vertex, the tick of the last edit that could change what a split or a
    /// collapse check of one of its edges reads: its triangles, their corners' places,
    /// metrics and roles (a moved vertex stamps its whole ball).
    stamp: Vec<u64>,
    /// Refused checks by edge key and tick, per operator (split, collapse): while neither
    /// end was stamped after the tick, the same check reads the same mesh and refuses
    /// again, so it is not run (lookups only, never iterated).
    refused: [ahash::AHashMap<u64, u64>; 2],
    /// The input field.
    bg: &'a Interpolator,
    /// The input curves.
    bd: &'a Boundary,
    /// Where piece vertices are placed.
    mode: BoundaryMode,
    /// Largest distance a collapse may put between a curve and its new edge.
    hausd: f64,
}

/// The mesh a [`Work`] starts from.
pub(super) struct Parts {
    /// Coordinates.
    pub pts: Vec<[f64; 2]>,
    /// Metric at each vertex.
    pub met: Vec<Sym2>,
    /// What each vertex may do.
    pub role: Vec<Role>,
    /// Counter-clockwise triangles.
    pub tris: Vec<[u32; 3]>,
    /// Face of each triangle.
    pub face: Vec<u32>,
    /// Constrained edges and their piece.
    pub cons: ahash::AHashMap<(u32, u32), u32>,
}

/// What the operators read besides the mesh: the input field and curves, and where
/// piece vertices are placed.
#[derive(Clone, Copy)]
pub(super) struct Context<'a> {
    /// The input field.
    pub background: &'a Interpolator,
    /// The input curves.
    pub boundary: &'a Boundary,
    /// Where piece vertices are placed.
    pub mode: BoundaryMode,
    /// Largest distance a collapse may put between a curve and its new edge.
    pub hausd: f64,
}

impl<'a> Work<'a> {
    /// The mesh `parts` ready for editing in `context`.
    pub(super) fn new(parts: Parts, context: Context<'a>) -> Work<'a> {
        let Parts { pts, met, role, tris, face, cons } = parts;
        let n = pts.len();
        let mut vtris = vec![Vec::new(); n];
        for (i, t) in tris.iter().enumerate() {
            for &v in t {
                vtris[v as usize].push(i as u32);
            }
        }
        let ntri = tris.len();
        let qual = tris
            .iter()
            .map(|v| op_quality(v.map(|i| pts[i as usize]), v.map(|i| &met[i as usize])))
            .collect();
        Work {
            pts,
            met,
            role,
            vtris,
            tris,
            face,
            alive: vec![true; ntri],
            qual,
            tri_mark: vec![false; ntri],
            sort_scratch: Vec::new(),
            cons,
            dirty: Vec::new(),
            is_dirty: vec![false; n],
            active: vec![true; n],
            clock: 0,
            stamp: vec![0; n],
            refused: Default::default(),
            bg: context.background,
            bd: context.boundary,
            mode: context.mode,
            hausd: context.hausd,
        }
    }

    /// Makes room for `vertices` vertices and `triangles` triangles in all (a hint:
    /// nothing changes but the capacities).
    pub(super) fn reserve(&mut self, vertices: usize, triangles: usize) {
        let (dv, dt) =
            (vertices.saturating_sub(self.pts.len()), triangles.saturating_sub(self.tris.len()));
        self.pts.reserve(dv);
        self.met.reserve(dv);
        self.role.reserve(dv);
        self.vtris.reserve(dv);
        self.is_dirty.reserve(dv);
        self.active.reserve(dv);
        self.stamp.reserve(dv);
        self.tris.reserve(dt);
        self.face.reserve(dt);
        self.alive.reserve(dt);
        self.tri_mark.reserve(dt);
        self.qual.reserve(dt);
    }

    /// Vertices made so far, dead ones included.
    #[inline]
    pub(super) fn num_vertices(&self) -> usize {
        self.pts.len()
    }

    /// Triangles made so far, dead ones included.
    #[inline]
    pub(super) fn num_slots(&self) -> usize {
        self.tris.len()
    }

    /// Live triangles.
    pub(super) fn live_triangles(&self) -> usize {
        self.alive.iter().filter(|&&a| a).count()
    }

    /// Position of `v`.
    #[inline]
    pub(super) fn point(&self, v: u32) -> [f64; 2] {
        self.pts[v as usize]
    }

    /// Metric at `v`.
    #[inline]
    pub(super) fn metric(&self, v: u32) -> Sym2 {
        self.met[v as usize]
    }

    /// What `v` may do.
    #[inline]
    pub(super) fn role(&self, v: u32) -> Role {
        self.role[v as usize]
    }

    /// Whether `v` was removed.
    #[inline]
    pub(super) fn is_dead(&self, v: u32) -> bool {
        self.role[v as usize] == Role::Dead
    }

    /// Corners of triangle `t`.
    #[inline]
    pub(super) fn tri(&self, t: u32) -> [u32; 3] {
        self.tris[t as usize]
    }

    /// Face of triangle `t`.
    #[inline]
    pub(super) fn face(&self, t: u32) -> u32 {
        self.face[t as usize]
    }

    /// Whether triangle `t` is in the mesh.
    #[inline]
    pub(super) fn is_alive(&self, t: u32) -> bool {
        self.alive[t as usize]
    }

    /// The live triangles around `v`.
    #[inline]
    pub(super) fn ball(&self, v: u32) -> &[u32] {
        &self.vtris[v as usize]
    }

    /// The piece of constrained edge `ab`, or `None` for a free edge.
    #[inline]
    pub(super) fn constraint(&self, a: u32, b: u32) -> Option<u32> {
        self.cons.get(&key(a, b)).copied()
    }

    /// The input field.
    #[inline]
    pub(super) fn background(&self) -> &'a Interpolator {
        self.bg
    }

    /// The input curves.
    #[inline]
    pub(super) fn boundary(&self) -> &'a Boundary {
        self.bd
    }

    /// Where piece vertices are placed.
    #[inline]
    pub(super) fn mode(&self) -> BoundaryMode {
        self.mode
    }

    /// Largest distance a collapse may put between a curve and its new edge.
    #[inline]
    pub(super) fn hausd(&self) -> f64 {
        self.hausd
    }

    /// Metric length of edge `ab`.
    #[inline]
    pub(super) fn length(&self, a: u32, b: u32) -> f64 {
        metric_edge_length(
            self.pts[a as usize],
            self.pts[b as usize],
            &self.met[a as usize],
            &self.met[b as usize],
        )
    }

    /// Operation quality of triangle `t` (kept, not recomputed).
    #[inline]
    pub(super) fn quality(&self, t: u32) -> f64 {
        self.qual[t as usize]
    }

    /// Operation quality of the triangle with corners `v`.
    #[inline]
    pub(super) fn quality_of(&self, v: [u32; 3]) -> f64 {
        op_quality(
            v.map(|i| self.pts[i as usize]),
            [&self.met[v[0] as usize], &self.met[v[1] as usize], &self.met[v[2] as usize]],
        )
    }

    /// The (one or two) live triangles holding edge `ab`.
    pub(super) fn edge_tris(&self, a: u32, b: u32) -> ([u32; 2], usize) {
        let mut out = [u32::MAX; 2];
        let mut n = 0;
        for &t in &self.vtris[a as usize] {
            if self.tris[t as usize].contains(&b) {
                if n < 2 {
                    out[n] = t;
                }
                n += 1;
            }
        }
        (out, n)
    }

    /// The vertices joined to `v`, sorted: the brute-force twin of
    /// [`Work::common_neighbours`] and [`Work::curve_neighbours`] in the tests.
    #[cfg(test)]
    pub(super) fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut n: Vec<u32> = self.vtris[v as usize]
            .iter()
            .flat_map(|&t| self.tris[t as usize])
            .filter(|&x| x != v)
            .collect();
        n.sort_unstable();
        n.dedup();
        n
    }

    /// How many distinct vertices are joined to both `a` and `b`: the link condition of
    /// a collapse of `ab` without building the two neighbour lists.
    pub(super) fn common_neighbours(&self, a: u32, b: u32) -> usize {
        let ball = &self.vtris[a as usize];
        let mut n = 0;
        for (i, &t) in ball.iter().enumerate() {
            for x in self.tris[t as usize] {
                if x == a || x == b {
                    continue;
                }
                // Counted once: at its first triangle in `a`'s ball.
                if ball[..i].iter().any(|&u| self.tris[u as usize].contains(&x)) {
                    continue;
                }
                if self.vtris[b as usize].iter().any(|&u| self.tris[u as usize].contains(&x)) {
                    n += 1;
                }
            }
        }
        n
    }

    /// Parameter of `v` on piece `p`: its own when it slides on `p`, else that of the
    /// piece's end it is; `near` chooses the end of a loop with one corner.
    pub(super) fn param_on(&self, v: u32, p: u32, near: f64) -> f64 {
        if let Role::Slides { piece, s } = self.role[v as usize] {
            if piece == p {
                return s;
            }
        }
        let piece = &self.bd.pieces[p as usize];
        let len = piece.length();
        if piece.ends[0] == piece.ends[1] {
            if near < 0.5 * len {
                0.0
            } else {
                len
            }
        } else if v == piece.ends[0] {
            0.0
        } else {
            len
        }
    }

    /// The parameter of `v` when it slides on `p`, the `near` hint for the other end of an
    /// edge on `p` otherwise.
    #[inline]
    pub(super) fn param_or(&self, v: u32, p: u32, otherwise: f64) -> f64 {
        match self.role[v as usize] {
            Role::Slides { piece, s } if piece == p => s,
            _ => otherwise,
        }
    }

    /// The two neighbours of piece vertex `v` along its piece, as `(vertex, parameter)`,
    /// the one with the smaller parameter first.
    pub(super) fn curve_neighbours(&self, v: u32) -> Option<[(u32, f64); 2]> {
        let Role::Slides { piece: p, s: sv } = self.role[v as usize] else { return None };
        let mut found: [(u32, f64); 2] = [(u32::MAX, 0.0); 2];
        let mut n = 0;
        for &t in &self.vtris[v as usize] {
            for u in self.tris[t as usize] {
                if u == v || found[..n.min(2)].iter().any(|f| f.0 == u) {
                    continue;
                }
                if self.cons.get(&key(u, v)) == Some(&p) {
                    if n == 2 {
                        return None;
                    }
                    found[n] = (u, self.param_on(u, p, sv));
                    n += 1;
                }
            }
        }
        if n != 2 {
            return None;
        }
        // By parameter, then by vertex.
        found.sort_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)));
        Some(found)
    }

    /// Notes that the ball of `v` changed (the next swap phase looks there).
    #[inline]
    pub(super) fn mark(&mut self, v: u32) {
        self.active[v as usize] = true;
        if !self.is_dirty[v as usize] {
            self.is_dirty[v as usize] = true;
            self.dirty.push(v);
        }
    }

    /// Marks `v` and every neighbour of it.
    pub(super) fn mark_ball(&mut self, v: u32) {
        self.mark(v);
        for i in 0..self.vtris[v as usize].len() {
            let t = self.vtris[v as usize][i];
            for u in self.tris[t as usize] {
                self.mark(u);
            }
        }
    }

    /// Notes that `v` moved: its neighbours' balls changed shape, so the next smoothing
    /// sweep tries them, but only the edges around `v` are listed for the swap phase. A
    /// flip check reads the two triangles of its edge (and whether the new diagonal is
    /// an edge already, which a move does not change), and the triangles a move changes
    /// are those of `v`'s ball, every edge of which is around `v`; listing the
    /// neighbours too, as [`Work::mark_ball`] does, would only re-check edges whose two
    /// triangles did not change.
    pub(super) fn mark_moved(&mut self, v: u32) {
        self.mark(v);
        for i in 0..self.vtris[v as usize].len() {
            let t = self.vtris[v as usize][i];
            for u in self.tris[t as usize] {
                self.active[u as usize] = true;
            }
        }
    }

    /// Whether the next smoothing sweep should try `v`; clears the mark.
    #[inline]
    pub(super) fn take_active(&mut self, v: u32) -> bool {
        std::mem::replace(&mut self.active[v as usize], false)
    }

    /// Takes the changed vertices, sorted, and clears the marks.
    pub(super) fn take_dirty(&mut self) -> Vec<u32> {
        let mut d = std::mem::take(&mut self.dirty);
        for &v in &d {
            self.is_dirty[v as usize] = false;
        }
        super::radix::sort_u32(&mut d);
        d
    }

    /// Appends a live triangle.
    pub(super) fn add_tri(&mut self, v: [u32; 3], face: u32) -> u32 {
        let t = self.tris.len() as u32;
        self.tris.push(v);
        self.face.push(face);
        self.alive.push(true);
        self.qual.push(self.quality_of(v));
        self.tri_mark.push(false);
        self.tick();
        for x in v {
            self.vtris[x as usize].push(t);
            self.stamp[x as usize] = self.clock;
        }
        t
    }

    /// Gives live triangle `t` the corners `v`: it leaves the lists of the corners it
    /// loses and joins those of the corners it gains, in corner order.
    pub(super) fn set_tri(&mut self, t: u32, v: [u32; 3]) {
        let old = self.tris[t as usize];
        self.tris[t as usize] = v;
        self.qual[t as usize] = self.quality_of(v);
        self.tick();
        for x in old.into_iter().chain(v) {
            self.stamp[x as usize] = self.clock;
        }
        for x in old {
            if !v.contains(&x) {
                self.detach(x, t);
            }
        }
        for x in v {
            if !old.contains(&x) {
                self.vtris[x as usize].push(t);
            }
        }
    }

    /// Removes triangle `t` from the mesh.
    pub(super) fn kill_tri(&mut self, t: u32) {
        self.alive[t as usize] = false;
        self.tick();
        for x in self.tris[t as usize] {
            self.detach(x, t);
            self.stamp[x as usize] = self.clock;
        }
    }

    /// Removes `t` from the adjacency of `v`.
    fn detach(&mut self, v: u32, t: u32) {
        let list = &mut self.vtris[v as usize];
        if let Some(i) = list.iter().position(|&x| x == t) {
            list.remove(i);
        }
    }

    /// Appends a vertex.
    pub(super) fn add_vertex(&mut self, p: [f64; 2], m: Sym2, role: Role) -> u32 {
        let v = self.pts.len() as u32;
        self.pts.push(p);
        self.met.push(m);
        self.role.push(role);
        self.vtris.push(Vec::new());
        self.is_dirty.push(false);
        self.active.push(true);
        self.tick();
        self.stamp.push(self.clock);
        v
    }

    /// Puts `v` at `p` with metric `m` and role `role` (a sliding vertex with its new
    /// parameter).
    pub(super) fn place(&mut self, v: u32, p: [f64; 2], m: Sym2, role: Role) {
        self.pts[v as usize] = p;
        self.met[v as usize] = m;
        self.role[v as usize] = role;
        self.tick();
        self.stamp[v as usize] = self.clock;
        for i in 0..self.vtris[v as usize].len() {
            let t = self.vtris[v as usize][i] as usize;
            self.qual[t] = self.quality_of(self.tris[t]);
            for x in self.tris[t] {
                self.stamp[x as usize] = self.clock;
            }
        }
    }

    /// Marks `v` removed; no live triangle may use it any more.
    pub(super) fn kill_vertex(&mut self, v: u32) {
        debug_assert!(self.vtris[v as usize].is_empty());
        self.role[v as usize] = Role::Dead;
        self.tick();
        self.stamp[v as usize] = self.clock;
    }

    /// Makes `ab` a constrained edge of piece `p`.
    pub(super) fn constrain(&mut self, a: u32, b: u32, p: u32) {
        self.cons.insert(key(a, b), p);
        self.tick();
        self.stamp[a as usize] = self.clock;
        self.stamp[b as usize] = self.clock;
    }

    /// Makes `ab` free (it left the mesh).
    pub(super) fn unconstrain(&mut self, a: u32, b: u32) {
        self.cons.remove(&key(a, b));
        self.tick();
        self.stamp[a as usize] = self.clock;
        self.stamp[b as usize] = self.clock;
    }

    /// The edit clock now: [`Work::changed_since`] of it is empty.
    pub(super) fn now(&self) -> u64 {
        self.clock
    }

    /// The live vertices stamped after tick `t`, in index order.
    pub(super) fn changed_since(&self, t: u64) -> Vec<u32> {
        (0..self.stamp.len() as u32)
            .filter(|&v| self.stamp[v as usize] > t && !self.is_dead(v))
            .collect()
    }

    #[inline]
    fn tick(&mut self) {
        self.clock += 1;
    }

    /// Whether the check of operator `op` on edge `ab` was refused and neither end was
    /// stamped since: the check would read the same mesh and refuse again.
    #[inline]
    pub(super) fn still_refused(&self, op: Op, a: u32, b: u32) -> bool {
        let k = key(a, b);
        match self.refused[op as usize].get(&(((k.0 as u64) << 32) | k.1 as u64)) {
            Some(&at) => self.stamp[a as usize] <= at && self.stamp[b as usize] <= at,
            None => false,
        }
    }

    /// Notes that the check of operator `op` on edge `ab` refused it now.
    #[inline]
    pub(super) fn refuse(&mut self, op: Op, a: u32, b: u32) {
        let k = key(a, b);
        self.refused[op as usize].insert(((k.0 as u64) << 32) | k.1 as u64, self.clock);
    }

    /// Every live undirected edge once, in triangle order (an interior edge from the
    /// triangle that runs along it from the smaller vertex, a boundary edge from its only
    /// triangle): deterministic, and no global sort.
    pub(super) fn edges(&self) -> Vec<(u32, u32)> {
        let mut e: Vec<(u32, u32)> = Vec::with_capacity(self.tris.len() * 3 / 2 + 16);
        for (t, v) in self.tris.iter().enumerate() {
            if !self.alive[t] {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                // A boundary edge joins two vertices that are not free; checking that
                // first spares the adjacency scan for nearly every interior edge.
                if a < b
                    || (self.role[a as usize] != Role::Free
                        && self.role[b as usize] != Role::Free
                        && self.edge_tris(a, b).1 == 1)
                {
                    e.push(key(a, b));
                }
            }
        }
        e
    }

    /// The edges around the vertices in `around` (each once, sorted): where the next
    /// sweep has work after a sweep that changed only those vertices' balls.
    pub(super) fn edges_around(&mut self, around: &[u32]) -> Vec<(u32, u32)> {
        // Each triangle once (a triangle is around up to three of the vertices), then
        // each edge once: sorted as packed 64-bit keys, the order of the pairs.
        let mut tris: Vec<u32> = Vec::new();
        for &x in around {
            if self.is_dead(x) {
                continue;
            }
            for &t in &self.vtris[x as usize] {
                if !self.tri_mark[t as usize] {
                    self.tri_mark[t as usize] = true;
                    tris.push(t);
                }
            }
        }
        let mut e: Vec<u64> = Vec::with_capacity(3 * tris.len());
        for &t in &tris {
            self.tri_mark[t as usize] = false;
            let v = self.tris[t as usize];
            for k in 0..3 {
                let (a, b) = key(v[k], v[(k + 1) % 3]);
                e.push(((a as u64) << 32) | b as u64);
            }
        }
        super::radix::sort_u64(&mut e, &mut self.sort_scratch);
        e.dedup();
        e.into_iter().map(|k| ((k >> 32) as u32, k as u32)).collect()
    }

    /// Sorts the undirected edges `e` (each as `(smaller, larger)`) and drops repeats:
    /// the order of `sort_unstable`, by radix.
    pub(super) fn sort_edges(&mut self, e: &mut Vec<(u32, u32)>) {
        let mut k: Vec<u64> = e.iter().map(|&(a, b)| ((a as u64) << 32) | b as u64).collect();
        super::radix::sort_u64(&mut k, &mut self.sort_scratch);
        k.dedup();
        e.clear();
        e.extend(k.into_iter().map(|k| ((k >> 32) as u32, k as u32)));
    }

    /// The constrained edges of live triangles on pieces that carry line tags, each as
    /// `(piece, smaller parameter, start, end)` oriented by increasing parameter.
    pub(super) fn piece_edges(&self) -> Vec<(u32, f64, u32, u32)> {
        let mut on_piece = Vec::new();
        for (a, b) in self.edges() {
            if let Some(&p) = self.cons.get(&(a, b)) {
                if self.bd.pieces[p as usize].tags.is_none() {
                    continue;
                }
                let near = self.param_or(a, p, self.param_or(b, p, 0.0));
                let (sa, sb) = (self.param_on(a, p, near), self.param_on(b, p, near));
                let (u, v) = if sa <= sb { (a, b) } else { (b, a) };
                on_piece.push((p, sa.min(sb), u, v));
            }
        }
        on_piece
    }

    /// Position and metric of a point at parameter `s` on piece `p`.
    pub(super) fn on_piece(&self, p: u32, s: f64) -> ([f64; 2], Sym2) {
        let piece = &self.bd.pieces[p as usize];
        (piece.point(s, self.mode), piece.metric(s))
    }

    /// Whether every live triangle is counter-clockwise with positive area (checked
    /// exactly).
    pub(super) fn all_positive(&self) -> bool {
        self.tris.iter().enumerate().all(|(t, v)| {
            !self.alive[t]
                || orient(self.pts[v[0] as usize], self.pts[v[1] as usize], self.pts[v[2] as usize])
                    > 0.0
        })
    }

    /// Brute-force check of every invariant the operators must keep, for the tests:
    /// triangles strictly counter-clockwise, adjacency lists exact, no edge with more than
    /// two triangles, every boundary edge constrained and every constrained edge live,
    /// piece vertices exactly where their parameter puts them, fixed vertices where the
    /// input had them.
    #[cfg(test)]
    pub(super) fn consistency(&self, input: &[[f64; 2]]) -> Result<(), String> {
        for (t, v) in self.tris.iter().enumerate() {
            if !self.alive[t] {
                continue;
            }
            let p = v.map(|x| self.pts[x as usize]);
            if orient(p[0], p[1], p[2]) <= 0.0 {
                return Err(format!("triangle {t} {v:?} is not counter-clockwise"));
            }
            if self.qual[t].to_bits() != self.quality_of(*v).to_bits() {
                return Err(format!("triangle {t} {v:?}: kept quality is stale"));
            }
            for &x in v {
                if self.is_dead(x) || !self.vtris[x as usize].contains(&(t as u32)) {
                    return Err(format!("triangle {t} missing from the list of vertex {x}"));
                }
            }
        }
        for (x, list) in self.vtris.iter().enumerate() {
            let mut l = list.clone();
            l.sort_unstable();
            l.dedup();
            if l.len() != list.len()
                || list.iter().any(|&t| {
                    !self.alive[t as usize] || !self.tris[t as usize].contains(&(x as u32))
                })
            {
                return Err(format!("bad triangle list at vertex {x}"));
            }
        }
        let mut occ: Vec<(u32, u32)> = Vec::new();
        for (t, v) in self.tris.iter().enumerate() {
            if self.alive[t] {
                for k in 0..3 {
                    occ.push(key(v[k], v[(k + 1) % 3]));
                }
            }
        }
        occ.sort_unstable();
        let mut live_constrained = 0;
        let mut i = 0;
        while i < occ.len() {
            let j = occ[i..].iter().position(|e| *e != occ[i]).map_or(occ.len(), |k| i + k);
            let e = occ[i];
            if j - i > 2 {
                return Err(format!("edge {e:?} has {} triangles", j - i));
            }
            let c = self.cons.contains_key(&e);
            if j - i == 1 && !c {
                return Err(format!("boundary edge {e:?} is not constrained"));
            }
            live_constrained += usize::from(c);
            i = j;
        }
        if live_constrained != self.cons.len() {
            return Err(format!(
                "{} constrained edges, {live_constrained} of them live",
                self.cons.len()
            ));
        }
        // The allocation-free neighbour queries against sorted neighbour lists.
        for &(a, b) in &occ {
            let nb = self.neighbours(b);
            let both = self.neighbours(a).iter().filter(|x| nb.binary_search(x).is_ok()).count();
            if self.common_neighbours(a, b) != both {
                return Err(format!("edge {a}-{b}: {both} common neighbours miscounted"));
            }
        }
        for v in 0..self.pts.len() as u32 {
            if let Role::Slides { piece: p, s } = self.role[v as usize] {
                let mut on: Vec<(u32, f64)> = self
                    .neighbours(v)
                    .into_iter()
                    .filter(|&u| self.cons.get(&key(u, v)) == Some(&p))
                    .map(|u| (u, self.param_on(u, p, s)))
                    .collect();
                on.sort_by(|x, y| x.1.total_cmp(&y.1));
                let brute = (on.len() == 2).then(|| [on[0], on[1]]);
                if self.curve_neighbours(v) != brute {
                    return Err(format!("vertex {v}: curve neighbours differ from {brute:?}"));
                }
            }
        }
        for v in 0..self.pts.len() {
            match self.role[v] {
                Role::Fixed if v < input.len() && self.pts[v] != input[v] => {
                    return Err(format!("fixed vertex {v} moved"));
                }
                Role::Slides { piece, s } => {
                    let (q, _) = self.on_piece(piece, s);
                    if q != self.pts[v] {
                        return Err(format!(
                            "vertex {v} is off its piece {piece}: {:?} vs {q:?}",
                            self.pts[v]
                        ));
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }
}
