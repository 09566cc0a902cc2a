//! The mutable triangle mesh the operators edit: coordinates, metrics, what each vertex
//! may do (free, on a piece at parameter `s`, fixed), counter-clockwise triangles with
//! their face, vertex → triangle adjacency, and the constrained edges with their piece.
//!
//! Triangles are never reused or reordered while remeshing (dead ones are flagged and
//! dropped at the end) and every sweep walks vectors in index order, so the result does
//! not depend on anything but the input. The constrained-edge map is only ever looked
//! up, never iterated.

use super::background::Background;
use super::boundary::Boundary;
use super::BoundaryMode;
use crate::conformity::{metric_edge_length, quality_in_metric};
use crate::metric::Sym2;

/// `piece` value of a vertex free to move in its face.
pub const FREE: u32 = u32::MAX;
/// `piece` value of a vertex that never moves nor vanishes (corner, topological point,
/// a node no triangle uses).
pub const FIXED: u32 = u32::MAX - 1;
/// `piece` value of a vertex removed by a collapse.
pub const DEAD: u32 = u32::MAX - 2;

/// Key of the undirected edge `ab`.
#[inline]
pub fn key(a: u32, b: u32) -> (u32, u32) {
    if a < b {
        (a, b)
    } else {
        (b, a)
    }
}

pub use crate::geometry::segment::orient;

/// Metric quality used to accept or refuse an operation: the shape quality in the
/// arithmetic mean of the corner metrics (SPD, and three times cheaper than the
/// Log-Euclidean centroid metric that [`crate::conformity`] reports with).
#[inline]
pub fn op_quality(p: [[f64; 2]; 3], m: [&Sym2; 3]) -> f64 {
    let mean = (1.0 / 3.0) * (*m[0] + *m[1] + *m[2]);
    quality_in_metric(p[0], p[1], p[2], &mean)
}

/// The mesh under edit.
pub struct Work<'a> {
    /// Coordinates.
    pub pts: Vec<[f64; 2]>,
    /// Metric at each vertex (interpolated from the input field).
    pub met: Vec<Sym2>,
    /// Piece of a vertex sliding on a curve, or [`FREE`], [`FIXED`], [`DEAD`].
    pub piece: Vec<u32>,
    /// Arc-length parameter on its piece.
    pub s: Vec<f64>,
    /// Triangles using each vertex.
    pub vtris: Vec<Vec<u32>>,
    /// Counter-clockwise triangles.
    pub tris: Vec<[u32; 3]>,
    /// Face (index into the face tag table) of each triangle.
    pub face: Vec<u32>,
    /// Whether each triangle is still in the mesh.
    pub alive: Vec<bool>,
    /// Constrained edges and their piece.
    pub cons: ahash::AHashMap<(u32, u32), u32>,
    /// Vertices whose ball changed since the last swap phase, listed once each.
    pub dirty: Vec<u32>,
    /// Whether each vertex is in `dirty`.
    pub is_dirty: Vec<bool>,
    /// Whether the next smoothing sweep should try each vertex (its ball changed since
    /// it was last tried).
    pub active: Vec<bool>,
    /// The input field.
    pub bg: &'a Background,
    /// The input curves.
    pub bd: &'a Boundary,
    /// Where piece vertices are placed.
    pub mode: BoundaryMode,
}

impl Work<'_> {
    /// Metric length of edge `ab`.
    #[inline]
    pub fn length(&self, a: u32, b: u32) -> f64 {
        metric_edge_length(
            self.pts[a as usize],
            self.pts[b as usize],
            &self.met[a as usize],
            &self.met[b as usize],
        )
    }

    /// Operation quality of triangle `t`.
    #[inline]
    pub fn quality(&self, t: u32) -> f64 {
        let v = self.tris[t as usize];
        self.quality_of(v)
    }

    /// Operation quality of the triangle with corners `v`.
    #[inline]
    pub fn quality_of(&self, v: [u32; 3]) -> f64 {
        op_quality(
            v.map(|i| self.pts[i as usize]),
            [&self.met[v[0] as usize], &self.met[v[1] as usize], &self.met[v[2] as usize]],
        )
    }

    /// The (one or two) live triangles holding edge `ab`.
    pub fn edge_tris(&self, a: u32, b: u32) -> ([u32; 2], usize) {
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

    /// The vertices joined to `v`, sorted.
    pub fn neighbours(&self, v: u32) -> Vec<u32> {
        let mut n: Vec<u32> = self.vtris[v as usize]
            .iter()
            .flat_map(|&t| self.tris[t as usize])
            .filter(|&x| x != v)
            .collect();
        n.sort_unstable();
        n.dedup();
        n
    }

    /// Parameter of `v` on piece `p`; `near` chooses the end of a loop with one corner.
    pub fn param_on(&self, v: u32, p: u32, near: f64) -> f64 {
        if self.piece[v as usize] == p {
            return self.s[v as usize];
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

    /// The two neighbours of piece vertex `v` along its piece, as `(vertex, parameter)`,
    /// the one with the smaller parameter first.
    pub fn curve_neighbours(&self, v: u32) -> Option<[(u32, f64); 2]> {
        let p = self.piece[v as usize];
        let sv = self.s[v as usize];
        let mut found: Vec<(u32, f64)> = Vec::with_capacity(2);
        for u in self.neighbours(v) {
            if self.cons.get(&key(u, v)) == Some(&p) {
                found.push((u, self.param_on(u, p, sv)));
            }
        }
        if found.len() != 2 {
            return None;
        }
        found.sort_by(|x, y| x.1.total_cmp(&y.1));
        Some([found[0], found[1]])
    }

    /// Notes that the ball of `v` changed (the next swap phase looks there).
    #[inline]
    pub fn mark(&mut self, v: u32) {
        self.active[v as usize] = true;
        if !self.is_dirty[v as usize] {
            self.is_dirty[v as usize] = true;
            self.dirty.push(v);
        }
    }

    /// Marks `v` and every neighbour of it.
    pub fn mark_ball(&mut self, v: u32) {
        self.mark(v);
        for u in self.neighbours(v) {
            self.mark(u);
        }
    }

    /// Takes the changed vertices, sorted, and clears the marks.
    pub fn take_dirty(&mut self) -> Vec<u32> {
        let mut d = std::mem::take(&mut self.dirty);
        for &v in &d {
            self.is_dirty[v as usize] = false;
        }
        d.sort_unstable();
        d
    }

    /// Appends a live triangle.
    pub fn add_tri(&mut self, v: [u32; 3], face: u32) -> u32 {
        let t = self.tris.len() as u32;
        self.tris.push(v);
        self.face.push(face);
        self.alive.push(true);
        for x in v {
            self.vtris[x as usize].push(t);
        }
        t
    }

    /// Removes `t` from the adjacency of `v`.
    pub fn detach(&mut self, v: u32, t: u32) {
        let list = &mut self.vtris[v as usize];
        if let Some(i) = list.iter().position(|&x| x == t) {
            list.remove(i);
        }
    }

    /// Appends a vertex.
    pub fn add_vertex(&mut self, p: [f64; 2], m: Sym2, piece: u32, s: f64) -> u32 {
        let v = self.pts.len() as u32;
        self.pts.push(p);
        self.met.push(m);
        self.piece.push(piece);
        self.s.push(s);
        self.vtris.push(Vec::new());
        self.is_dirty.push(false);
        self.active.push(true);
        v
    }

    /// Every live undirected edge once, in triangle order (an interior edge from the
    /// triangle that runs along it from the smaller vertex, a boundary edge from its only
    /// triangle): deterministic, and no global sort.
    pub fn edges(&self) -> Vec<(u32, u32)> {
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
                    || (self.piece[a as usize] != FREE
                        && self.piece[b as usize] != FREE
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
    pub fn edges_around(&self, around: &[u32]) -> Vec<(u32, u32)> {
        let mut e: Vec<(u32, u32)> = Vec::new();
        for &x in around {
            if self.piece[x as usize] == DEAD {
                continue;
            }
            for &t in &self.vtris[x as usize] {
                let v = self.tris[t as usize];
                for k in 0..3 {
                    e.push(key(v[k], v[(k + 1) % 3]));
                }
            }
        }
        e.sort_unstable();
        e.dedup();
        e
    }

    /// Position and metric of a point at parameter `s` on piece `p`.
    pub fn on_piece(&self, p: u32, s: f64) -> ([f64; 2], Sym2) {
        let piece = &self.bd.pieces[p as usize];
        (piece.point(s, self.mode), piece.metric(s))
    }

    /// Whether every live triangle is counter-clockwise with positive area (checked
    /// exactly).
    pub fn all_positive(&self) -> bool {
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
    pub fn consistency(&self, input: &[[f64; 2]]) -> Result<(), String> {
        for (t, v) in self.tris.iter().enumerate() {
            if !self.alive[t] {
                continue;
            }
            let p = v.map(|x| self.pts[x as usize]);
            if orient(p[0], p[1], p[2]) <= 0.0 {
                return Err(format!("triangle {t} {v:?} is not counter-clockwise"));
            }
            for &x in v {
                if self.piece[x as usize] == DEAD || !self.vtris[x as usize].contains(&(t as u32)) {
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
        for v in 0..self.pts.len() {
            let p = self.piece[v];
            if p == FIXED && v < input.len() && self.pts[v] != input[v] {
                return Err(format!("fixed vertex {v} moved"));
            }
            if p != FIXED && p != FREE && p != DEAD {
                let (q, _) = self.on_piece(p, self.s[v]);
                if q != self.pts[v] {
                    return Err(format!(
                        "vertex {v} is off its piece {p}: {:?} vs {q:?}",
                        self.pts[v]
                    ));
                }
            }
        }
        Ok(())
    }
}
