//! The skin itself: wall chains, one column of points per wall vertex (several at a convex
//! corner: the fan), the thickness each column may take, and the layer cells between
//! consecutive columns.
//!
//! Invariants of a built [`Skin`]:
//! - wall edges run with the domain on their left, chained into open chains (ends on
//!   another boundary) or closed loops; consecutive columns of a chain bound one strip of
//!   `n` cells (a fan strip's first cell is a triangle at the corner, the rest quads);
//! - a column's direction is the blended (mitred) normal of its vertex, leant towards a
//!   concave corner nearby so that columns do not cross, or, at a chain end whose
//!   neighbouring boundary makes a wall of the domain, that boundary's direction: the
//!   column's points then lie on that boundary (it slides along it);
//! - every column keeps the first height when it is thinned (the ratio drops, down to
//!   1; below that the whole column is scaled), thinning varies by at most half the
//!   thickness per thickness of wall length, and every thinned column is reported;
//! - every cell is positive at its corners and no edge of the skin meets another edge of
//!   the skin or of the boundary, except at shared vertices (checked, then columns
//!   thinned where it fails, until it holds or the skin is refused).

use std::collections::BTreeMap;

use super::{LayerError, Thinned};
use crate::geometry::plane::{
    add, dot, left, norm, ray_hit, rotate, scale, segments_meet, sub, turn, unit, Bbox, BoxIndex,
    EPS, P,
};
use crate::topology::{Classification, Topology};

/// Interior angle (degrees) below which a chain end's neighbouring boundary carries the
/// side of the skin.
const SLIDE_BELOW_DEG: f64 = 160.0;
/// Turn (degrees) from which a concave vertex leans its neighbours.
const CONCAVE_CORNER_DEG: f64 = 25.0;
/// Thinning may change by this much of the thickness per thickness of wall length.
const THIN_SLOPE: f64 = 0.5;
/// The share of the gap a side may take before the topological point that stops it.
const SIDE_SHARE: f64 = 0.8;

/// A side of the skin lying on a neighbouring boundary.
#[derive(Debug, Clone)]
pub(super) struct Side {
    /// Boundary vertices from the chain end on, in order.
    pub path: Vec<usize>,
    /// Arc length at each of them.
    pub arc: Vec<f64>,
    /// Tags (physical, geometrical) of the line cells along it, `None` when none.
    pub tags: Option<(i32, i32)>,
    /// Whether it stops at another wall (whose skin shares the gap).
    pub ends_on_wall: bool,
}

/// One column of points.
#[derive(Debug, Clone)]
pub(super) struct Column {
    /// The wall vertex it grows from.
    pub base: usize,
    /// Its direction (a unit normal times the mitre factor).
    pub dir: P,
    /// Nominal distance of each front from the wall, `n + 1` values from 0.
    pub nominal: Vec<f64>,
    /// The nominal first height and ratio (for thinning).
    pub h0: f64,
    /// Nominal ratio.
    pub ratio: f64,
    /// Share of the nominal thickness it takes (1 unless thinned).
    pub factor: f64,
    /// Why it was thinned.
    pub reason: Option<&'static str>,
    /// When its points lie on a neighbouring boundary.
    pub side: Option<Side>,
    /// Arc length to the point its side may not pass (infinite when free).
    pub side_limit: f64,
    /// Its points, wall first (filled by [`Skin::place`]): `ids[0] == base`.
    pub ids: Vec<usize>,
}

/// The strip between two consecutive columns of a chain.
#[derive(Debug, Clone, Copy)]
pub(super) struct Gap {
    /// Columns (indices into [`Skin::columns`]).
    pub cols: [usize; 2],
    /// Tags (physical, geometrical) of the triangle it replaces at the wall.
    pub tags: (i32, i32),
}

/// A wall chain.
#[derive(Debug, Clone)]
pub(super) struct Chain {
    /// Its columns in order.
    pub cols: Vec<usize>,
    /// Whether it closes on itself.
    pub closed: bool,
}

/// A built skin.
#[derive(Debug, Clone)]
pub(super) struct Skin {
    /// Every column.
    pub columns: Vec<Column>,
    /// Every strip.
    pub gaps: Vec<Gap>,
    /// Chains.
    pub chains: Vec<Chain>,
    /// Wall vertices.
    pub wall: Vec<bool>,
    /// Wall edges (undirected keys).
    pub wall_edges: std::collections::BTreeSet<[usize; 2]>,
    /// Coordinates: the mesh's, then the skin's new points.
    pub pts: Vec<P>,
    /// Number of mesh points (new points start here).
    pub base_points: usize,
    /// Number of layers.
    pub layers: usize,
}

/// What the skin is built from.
pub(super) struct SkinInput<'a> {
    /// Mesh coordinates.
    pub pts: &'a [P],
    /// The mesh's topology.
    pub topo: &'a Topology,
    /// Tags (physical, geometrical) of each surface cell, as in `topo.surface_cells`.
    pub cell_tags: &'a [(i32, i32)],
    /// Tags of the line cells by edge key.
    pub line_tags: &'a BTreeMap<[usize; 2], (i32, i32)>,
    /// Growth (`h0`, `r`, `n`) of each selected curve, by curve index.
    pub growth: &'a BTreeMap<usize, super::Growth>,
    /// Largest angle between consecutive columns of a fan, radians.
    pub fan_step: f64,
    /// Largest share of the gap in front of a wall the skin may fill.
    pub gap_ratio: f64,
}

fn key(a: usize, b: usize) -> [usize; 2] {
    [a.min(b), a.max(b)]
}

/// Offsets of a column of first height `h0`, ratio `r`, `n` layers, thinned to `factor`
/// of its thickness: the first height is kept and the ratio lowered while it stays at or
/// above 1, else every height is scaled.
pub(super) fn thinned_offsets(h0: f64, r: f64, n: usize, factor: f64) -> Vec<f64> {
    let g = super::Growth { first_height: h0, ratio: r, layers: n };
    if factor >= 1.0 {
        return g.offsets();
    }
    let t = factor * g.thickness();
    if t >= h0 * n as f64 {
        if let Ok(k) = super::Growth::solve(Some(h0), None, Some(n), Some(t)) {
            if k.ratio >= 1.0 - 1e-12 {
                return k.offsets();
            }
        }
    }
    g.offsets().iter().map(|s| s * factor).collect()
}

impl Skin {
    /// Builds the columns and strips, thins them until the skin fits.
    pub(super) fn build(inp: &SkinInput) -> Result<Skin, LayerError> {
        let pts = inp.pts;
        let bd = Boundary::of(inp);
        let wall = Wall::of(inp, &bd)?;
        let layers = wall.layers;
        let mut on_wall = vec![false; pts.len()];
        let mut wall_edges = std::collections::BTreeSet::new();
        for (&a, &(b, _)) in &wall.next {
            on_wall[a] = true;
            on_wall[b] = true;
            wall_edges.insert(key(a, b));
        }
        let vchains = wall.chains()?;
        let mut skin = Skin {
            columns: Vec::new(),
            gaps: Vec::new(),
            chains: Vec::new(),
            wall: on_wall,
            wall_edges,
            pts: pts.to_vec(),
            base_points: pts.len(),
            layers,
        };
        for (vs, closed) in vchains {
            skin.add_chain(inp, &bd, &wall, &vs, closed);
        }
        skin.fit(inp)?;
        Ok(skin)
    }

    /// Adds the columns of one wall chain (`vs`, closed or not), the strips between
    /// them with the tags of the wall edge they stand on, and leans them at concave
    /// corners.
    fn add_chain(
        &mut self,
        inp: &SkinInput,
        bd: &Boundary,
        wall: &Wall,
        vs: &[usize],
        closed: bool,
    ) {
        let m = vs.len();
        let mut chain = Chain { cols: Vec::new(), closed };
        // Columns of each vertex (one, or a fan), and the tags of the strip after each.
        let mut first_of: Vec<usize> = Vec::with_capacity(m);
        let mut last_of: Vec<usize> = Vec::with_capacity(m);
        for i in 0..m {
            let prev = if i > 0 {
                Some(vs[i - 1])
            } else if closed {
                Some(vs[m - 1])
            } else {
                None
            };
            let next = if i + 1 < m {
                Some(vs[i + 1])
            } else if closed {
                Some(vs[0])
            } else {
                None
            };
            first_of.push(self.columns.len());
            self.add_vertex_columns(inp, bd, wall, vs[i], prev, next);
            last_of.push(self.columns.len() - 1);
        }
        let edge_tags = |a: usize, b: usize| -> (i32, i32) {
            bd.cell.get(&[a, b]).map_or((0, 0), |&c| inp.cell_tags[c])
        };
        for i in 0..m {
            for c in first_of[i]..=last_of[i] {
                chain.cols.push(c);
            }
            let next_first = if i + 1 < m {
                Some(first_of[i + 1])
            } else if closed {
                Some(first_of[0])
            } else {
                None
            };
            let out_tags = next_first.map(|_| edge_tags(vs[i], vs[(i + 1) % m]));
            // Fan strips take the tags of the wall edge after the corner.
            for c in first_of[i]..last_of[i] {
                let t = out_tags.unwrap_or_else(|| edge_tags(vs[i - 1], vs[i]));
                self.gaps.push(Gap { cols: [c, c + 1], tags: t });
            }
            if let (Some(nf), Some(t)) = (next_first, out_tags) {
                self.gaps.push(Gap { cols: [last_of[i], nf], tags: t });
            }
        }
        lean_at_concave_corners(self, vs, closed, &first_of, &last_of);
        self.chains.push(chain);
    }

    /// Adds the columns of wall vertex `v` between its wall neighbours `prev` and `next`:
    /// one along the bisector, a fan at a convex corner sharper than the fan step, or,
    /// at a chain's end, one along the wall's normal or sliding on the boundary beside it.
    fn add_vertex_columns(
        &mut self,
        inp: &SkinInput,
        bd: &Boundary,
        wall: &Wall,
        v: usize,
        prev: Option<usize>,
        next: Option<usize>,
    ) {
        let pts = inp.pts;
        let layers = self.layers;
        let curves: Vec<usize> = [prev.map(|p| wall.next[&p].1), next.map(|_| wall.next[&v].1)]
            .into_iter()
            .flatten()
            .collect();
        let (h0, ratio) = {
            let gs: Vec<&super::Growth> = curves.iter().map(|c| &inp.growth[c]).collect();
            let k = gs.len() as f64;
            (
                gs.iter().map(|g| g.first_height).sum::<f64>() / k,
                gs.iter().map(|g| g.ratio).sum::<f64>() / k,
            )
        };
        let nominal = super::Growth { first_height: h0, ratio, layers }.offsets();
        let d_in = prev.map(|p| unit(sub(pts[v], pts[p])));
        let d_out = next.map(|q| unit(sub(pts[q], pts[v])));
        let mut dirs: Vec<P> = Vec::new();
        let mut side = None;
        let mut side_limit = f64::INFINITY;
        match (d_in, d_out) {
            (Some(di), Some(do_)) => {
                let th = turn(di, do_);
                let (ni, no) = (left(di), left(do_));
                if th < -inp.fan_step {
                    let k = (th.abs() / inp.fan_step).ceil() as usize;
                    for j in 0..=k {
                        dirs.push(rotate(ni, th * j as f64 / k as f64));
                    }
                } else {
                    let mid = unit(add(ni, no));
                    let c = dot(mid, ni).max(1.0 / 3.0);
                    dirs.push(scale(mid, 1.0 / c));
                }
            }
            (None, Some(do_)) | (Some(do_), None) => {
                let at_start = d_in.is_none();
                let nb = if at_start { bd.prev.get(&v) } else { bd.next.get(&v) };
                let mut dir = left(do_);
                if let Some(&u) = nb {
                    let ds = unit(sub(pts[u], pts[v]));
                    // Interior angle at v between the wall and the neighbour.
                    let th = if at_start { turn(scale(ds, -1.0), do_) } else { turn(do_, ds) };
                    let alpha = std::f64::consts::PI - th;
                    if alpha.to_degrees() < SLIDE_BELOW_DEG {
                        dir = ds;
                        let (s, lim) = side_path(
                            inp,
                            v,
                            u,
                            if at_start { &bd.prev } else { &bd.next },
                            &self.wall,
                            nominal[layers],
                        );
                        side = Some(s);
                        side_limit = lim;
                    }
                }
                dirs.push(dir);
            }
            (None, None) => unreachable!("a chain has at least one edge"),
        }
        for d in dirs {
            self.columns.push(Column {
                base: v,
                dir: d,
                nominal: nominal.clone(),
                h0,
                ratio,
                factor: 1.0,
                reason: None,
                side: side.clone(),
                side_limit,
                ids: Vec::new(),
            });
        }
    }

    /// Thickness of column `c` as it stands.
    fn thickness(&self, c: usize) -> f64 {
        let col = &self.columns[c];
        col.nominal[self.layers] * col.factor
    }

    /// Sets the factors from the gaps in front of each column, then thins where the skin
    /// does not fit, until it does.
    fn fit(&mut self, inp: &SkinInput) -> Result<(), LayerError> {
        self.check_first_heights()?;
        let pts = inp.pts;
        // Obstacles: every boundary edge and every line cell edge.
        let mut obstacles: Vec<[usize; 2]> = Vec::new();
        let mut seen = std::collections::BTreeSet::new();
        for sc in &inp.topo.surface_cells {
            let vs = sc.vertices();
            for i in 0..vs.len() {
                let k = key(vs[i], vs[(i + 1) % vs.len()]);
                if !seen.insert(k) {
                    seen.remove(&k);
                }
            }
        }
        obstacles.extend(seen.iter().copied());
        for &k in inp.line_tags.keys() {
            if !seen.contains(&k) {
                obstacles.push(k);
            }
        }
        // Grown by the reach of `ray_hit`'s tolerance along the obstacle.
        let oboxes: Vec<Bbox> = obstacles
            .iter()
            .map(|&[a, b]| Bbox::of(&[pts[a], pts[b]]).grown(2.0 * EPS * norm(sub(pts[b], pts[a]))))
            .collect();
        let ogrid = BoxIndex::new(&oboxes);
        for c in 0..self.columns.len() {
            let col = &self.columns[c];
            let t = col.nominal[self.layers];
            if let Some(side) = &col.side {
                let (share, why) = if side.ends_on_wall {
                    (inp.gap_ratio, "gap")
                } else {
                    (SIDE_SHARE, "side ends at a topological point")
                };
                if share * col.side_limit < t {
                    self.thin(c, share * col.side_limit / t, why);
                }
                continue;
            }
            let o = pts[col.base];
            let d = unit(col.dir);
            let reach = t * norm(col.dir) / inp.gap_ratio;
            let q = Bbox::of(&[o, add(o, scale(d, reach))]);
            let mut hit = f64::INFINITY;
            for e in ogrid.query(q) {
                let [a, b] = obstacles[e as usize];
                if a == col.base || b == col.base {
                    continue;
                }
                if let Some(s) = ray_hit(o, d, pts[a], pts[b]) {
                    hit = hit.min(s);
                }
            }
            let allowed = inp.gap_ratio * hit;
            let len = t * norm(col.dir);
            if allowed < len {
                self.thin(c, allowed / len, "gap");
            }
        }
        self.smooth_factors();
        for round in 0..40 {
            self.place();
            let bad = self.bad_gaps(&obstacles);
            if bad.is_empty() {
                return Ok(());
            }
            if round == 39 {
                let g = self.gaps[bad[0]];
                let p = self.pts[self.columns[g.cols[0]].base];
                return Err(LayerError::CannotFit { at: p });
            }
            for g in bad {
                for c in self.gaps[g].cols {
                    let f = self.columns[c].factor * 0.75;
                    self.thin(c, f, "front collision");
                }
            }
            self.smooth_factors();
        }
        Ok(())
    }

    /// Refuses first heights that the skin's own crossing test cannot tell from the
    /// wall: a strip's first front meets its wall edge in [`segments_meet`] when they are
    /// within √EPS of the longer segment, and thinning only brings them closer, so such
    /// a skin never fits. Fans (no wall edge) are exempt.
    fn check_first_heights(&self) -> Result<(), LayerError> {
        for g in &self.gaps {
            let [a, b] = g.cols.map(|c| &self.columns[c]);
            if a.base == b.base {
                continue;
            }
            let len = norm(sub(self.pts[b.base], self.pts[a.base]));
            let height = a.nominal[1].min(b.nominal[1]);
            let bound = EPS.sqrt() * len;
            if height < bound {
                let (p, q) = (self.pts[a.base], self.pts[b.base]);
                return Err(LayerError::FirstHeightTooSmall {
                    at: [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])],
                    height,
                    edge: len,
                    bound,
                });
            }
        }
        Ok(())
    }

    fn thin(&mut self, c: usize, f: f64, why: &'static str) {
        let col = &mut self.columns[c];
        if f < col.factor {
            col.factor = f.max(0.0);
            col.reason = Some(why);
        }
    }

    /// Limits how fast the factor changes along each chain.
    fn smooth_factors(&mut self) {
        for _ in 0..100 {
            let mut changed = false;
            for ch in 0..self.chains.len() {
                let n = self.chains[ch].cols.len();
                let closed = self.chains[ch].closed;
                let pairs: Vec<(usize, usize)> = (0..n)
                    .filter_map(|i| {
                        if i + 1 < n {
                            Some((self.chains[ch].cols[i], self.chains[ch].cols[i + 1]))
                        } else if closed && n > 1 {
                            Some((self.chains[ch].cols[i], self.chains[ch].cols[0]))
                        } else {
                            None
                        }
                    })
                    .collect();
                for &(a, b) in pairs.iter().chain(pairs.iter().rev()) {
                    for (x, y) in [(a, b), (b, a)] {
                        let d = norm(sub(
                            self.pts[self.columns[x].base],
                            self.pts[self.columns[y].base],
                        ));
                        let t = self.columns[y].nominal[self.layers].max(1e-300);
                        let cap = self.columns[x].factor + THIN_SLOPE * d / t;
                        if self.columns[y].factor > cap + 1e-12 {
                            let why = self.columns[x].reason.unwrap_or("gap");
                            self.columns[y].factor = cap;
                            self.columns[y].reason = Some(why);
                            changed = true;
                        }
                    }
                }
            }
            if !changed {
                break;
            }
        }
    }

    /// Computes every column's points (ids in `ids`, coordinates appended to `pts`).
    pub(super) fn place(&mut self) {
        self.pts.truncate(self.base_points);
        let n = self.layers;
        for c in 0..self.columns.len() {
            let col = &self.columns[c];
            let offs = thinned_offsets(col.h0, col.ratio, n, col.factor);
            let o = self.pts[col.base];
            let mut ids = vec![col.base];
            for &s in &offs[1..] {
                let p = match &col.side {
                    Some(side) => along(&self.pts, side, s),
                    None => add(o, scale(col.dir, s)),
                };
                ids.push(self.pts.len());
                self.pts.push(p);
            }
            self.columns[c].ids = ids;
        }
    }

    /// Corners of the cell of strip `g` at layer `k` (3 for the first cell of a fan strip).
    pub(super) fn cell(&self, g: usize, k: usize) -> Vec<usize> {
        let [a, b] = self.gaps[g].cols;
        let (ca, cb) = (&self.columns[a].ids, &self.columns[b].ids);
        if k == 0 && ca[0] == cb[0] {
            vec![ca[0], cb[1], ca[1]]
        } else {
            vec![ca[k], cb[k], cb[k + 1], ca[k + 1]]
        }
    }

    /// Strips with a non-positive cell or an edge meeting another edge of the skin or of
    /// the boundary. Under test, checked against its all-pairs twin on every skin small
    /// enough.
    fn bad_gaps(&self, obstacles: &[[usize; 2]]) -> Vec<usize> {
        let bad = self.bad_gaps_by(obstacles, false);
        #[cfg(test)]
        if self.columns.len() * self.layers < 4000 {
            assert_eq!(bad, self.bad_gaps_by(obstacles, true), "the all-pairs twin disagrees");
        }
        bad
    }

    /// [`Skin::bad_gaps`], the pairs from [`crate::geometry::near_pairs::near_pairs`] or, `brute`, all.
    fn bad_gaps_by(&self, obstacles: &[[usize; 2]], brute: bool) -> Vec<usize> {
        let n = self.layers;
        let mut bad = std::collections::BTreeSet::new();
        for g in 0..self.gaps.len() {
            for k in 0..n {
                let poly: Vec<P> = self.cell(g, k).iter().map(|&v| self.pts[v]).collect();
                if !crate::validity::positive_corners(&poly) {
                    bad.insert(g);
                }
            }
        }
        // Skin segments (with the strip that owns them, or none for columns' own edges).
        let mut segs: Vec<([usize; 2], Vec<usize>)> = Vec::new();
        let mut col_gaps: Vec<Vec<usize>> = vec![Vec::new(); self.columns.len()];
        for (g, gap) in self.gaps.iter().enumerate() {
            col_gaps[gap.cols[0]].push(g);
            col_gaps[gap.cols[1]].push(g);
        }
        for (c, col) in self.columns.iter().enumerate() {
            for k in 0..n {
                segs.push(([col.ids[k], col.ids[k + 1]], col_gaps[c].clone()));
            }
        }
        for (g, gap) in self.gaps.iter().enumerate() {
            let (ca, cb) = (&self.columns[gap.cols[0]].ids, &self.columns[gap.cols[1]].ids);
            for k in 1..=n {
                segs.push(([ca[k], cb[k]], vec![g]));
            }
        }
        let first_obstacle = segs.len();
        for &o in obstacles {
            segs.push((o, Vec::new()));
        }
        // Grown by the distance at which `segments_meet` calls two segments met (√EPS of
        // the longer: each by twice that of its own).
        let ends: Vec<[P; 2]> =
            segs.iter().map(|(s, _)| [self.pts[s[0]], self.pts[s[1]]]).collect();
        let items: Vec<(&[P], f64)> =
            ends.iter().map(|e| (&e[..], 2.0 * EPS.sqrt() * norm(sub(e[1], e[0])))).collect();
        let candidates = if brute {
            let n = items.len() as u32;
            (0..n).flat_map(|i| (i + 1..n).map(move |j| (i, j))).collect()
        } else {
            crate::geometry::near_pairs::near_pairs(&items)
        };
        for (i, j) in candidates {
            let (i, j) = (i as usize, j as usize);
            // Two obstacles are not the skin's business.
            if i >= first_obstacle {
                continue;
            }
            let [a, b] = segs[i].0;
            let [c, d] = segs[j].0;
            if a == c || a == d || b == c || b == d {
                continue;
            }
            // A side lying on its boundary is not a crossing.
            if j >= first_obstacle && self.on_side(a, b, c, d) {
                continue;
            }
            if segments_meet(self.pts[a], self.pts[b], self.pts[c], self.pts[d]) {
                bad.extend(segs[i].1.iter().copied());
                bad.extend(segs[j].1.iter().copied());
            }
        }
        bad.into_iter().collect()
    }

    /// Whether skin segment `ab` starts or ends on a side lying along boundary edge `cd`
    /// (a side's own edges lie on it, the strips' edges end on it).
    fn on_side(&self, a: usize, b: usize, c: usize, d: usize) -> bool {
        self.columns.iter().any(|col| {
            col.side.as_ref().is_some_and(|s| {
                (col.ids.contains(&a) || col.ids.contains(&b))
                    && s.path.contains(&c)
                    && s.path.contains(&d)
            })
        })
    }

    /// The columns that were thinned, for the report.
    pub(super) fn thinned(&self) -> Vec<Thinned> {
        let mut out = Vec::new();
        for (c, col) in self.columns.iter().enumerate() {
            if col.factor < 1.0 - 1e-9 {
                let p = self.pts[col.base];
                out.push(Thinned {
                    vertex: col.base,
                    at: p,
                    factor: col.factor,
                    thickness: self.thickness(c),
                    nominal: col.nominal[self.layers],
                    reason: col.reason.unwrap_or("gap").to_string(),
                });
            }
        }
        out
    }
}

/// The point at arc length `s` along a side (beyond its end, on the last edge's line).
fn along(pts: &[P], side: &Side, s: f64) -> P {
    let k = side.arc.len();
    for i in 1..k {
        if s <= side.arc[i] || i == k - 1 {
            let (a, b) = (pts[side.path[i - 1]], pts[side.path[i]]);
            let l = side.arc[i] - side.arc[i - 1];
            let t = if l > 0.0 { (s - side.arc[i - 1]) / l } else { 0.0 };
            return add(a, scale(sub(b, a), t));
        }
    }
    pts[side.path[0]]
}

/// The mesh's boundary edges, directed as their single cell runs along them.
struct Boundary {
    /// a -> b for each boundary edge a-b.
    next: BTreeMap<usize, usize>,
    /// b -> a for each boundary edge a-b.
    prev: BTreeMap<usize, usize>,
    /// The cell of each directed boundary edge.
    cell: BTreeMap<[usize; 2], usize>,
}

impl Boundary {
    fn of(inp: &SkinInput) -> Boundary {
        let mut count: BTreeMap<[usize; 2], (u32, [usize; 2], usize)> = BTreeMap::new();
        for (ci, sc) in inp.topo.surface_cells.iter().enumerate() {
            let vs = sc.vertices();
            for i in 0..vs.len() {
                let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
                let e = count.entry(key(a, b)).or_insert((0, [a, b], ci));
                e.0 += 1;
            }
        }
        let mut bd =
            Boundary { next: BTreeMap::new(), prev: BTreeMap::new(), cell: BTreeMap::new() };
        for (_, &(c, [a, b], ci)) in count.iter() {
            if c == 1 {
                bd.next.insert(a, b);
                bd.prev.insert(b, a);
                bd.cell.insert([a, b], ci);
            }
        }
        bd
    }
}

/// The wall: the boundary edges of the chosen curves, directed as the boundary.
struct Wall {
    /// a -> (b, curve) for each wall edge a-b.
    next: BTreeMap<usize, (usize, usize)>,
    /// b -> a for each wall edge a-b.
    prev: BTreeMap<usize, usize>,
    /// The number of layers, the same on every curve.
    layers: usize,
}

impl Wall {
    fn of(inp: &SkinInput, bd: &Boundary) -> Result<Wall, LayerError> {
        let topo = inp.topo;
        let mut next: BTreeMap<usize, (usize, usize)> = BTreeMap::new();
        let mut prev: BTreeMap<usize, usize> = BTreeMap::new();
        let mut layers = None;
        for (&ci, g) in inp.growth {
            if *layers.get_or_insert(g.layers) != g.layers {
                return Err(LayerError::Bad(
                    "every curve of one skin needs the same number of layers".into(),
                ));
            }
            let curve = &topo.curves[ci];
            for pl in &curve.polylines {
                for [a, b] in pl.edges() {
                    let (a, b) = if bd.next.get(&a) == Some(&b) {
                        (a, b)
                    } else if bd.next.get(&b) == Some(&a) {
                        (b, a)
                    } else {
                        return Err(LayerError::Bad(format!(
                            "curve {} has an edge inside the domain ({a}-{b}); layers grow on boundary curves only",
                            curve_label(topo, ci)
                        )));
                    };
                    next.insert(a, (b, ci));
                    prev.insert(b, a);
                }
            }
        }
        let layers = layers.ok_or_else(|| LayerError::Bad("no curve selected".into()))?;
        Ok(Wall { next, prev, layers })
    }

    /// The wall's chains of vertices, with whether each is closed: open ones from their
    /// starts, then loops from their smallest vertex.
    fn chains(&self) -> Result<Vec<(Vec<usize>, bool)>, LayerError> {
        let wnext = &self.next;
        let mut vchains: Vec<(Vec<usize>, bool)> = Vec::new();
        let mut done: std::collections::BTreeSet<usize> = Default::default();
        let starts: Vec<usize> =
            wnext.keys().copied().filter(|a| !self.prev.contains_key(a)).collect();
        for s in starts {
            let mut c = vec![s];
            let mut v = s;
            while let Some(&(b, _)) = wnext.get(&v) {
                done.insert(v);
                c.push(b);
                v = b;
            }
            done.insert(v);
            vchains.push((c, false));
        }
        for &a in wnext.keys() {
            if done.contains(&a) {
                continue;
            }
            let mut c = vec![a];
            done.insert(a);
            let mut v = wnext[&a].0;
            while v != a {
                if !done.insert(v) {
                    return Err(LayerError::Bad(format!("the wall crosses itself at vertex {v}")));
                }
                c.push(v);
                v = wnext[&v].0;
            }
            vchains.push((c, true));
        }
        Ok(vchains)
    }
}

/// Walks the boundary from chain end `v` through `u` (following `step`) for a side of a
/// skin `t` thick: stops at a topological point, a wall vertex, a change of line tags or
/// past three thicknesses. Returns the side and the arc length it may not pass.
fn side_path(
    inp: &SkinInput,
    v: usize,
    u: usize,
    step: &BTreeMap<usize, usize>,
    wall: &[bool],
    t: f64,
) -> (Side, f64) {
    let pts = inp.pts;
    let tags = inp.line_tags.get(&key(v, u)).copied();
    let mut side = Side { path: vec![v], arc: vec![0.0], tags, ends_on_wall: false };
    let mut prev = v;
    let mut cur = u;
    loop {
        let s = side.arc.last().copied().unwrap_or(0.0) + norm(sub(pts[cur], pts[prev]));
        side.path.push(cur);
        side.arc.push(s);
        let stop = matches!(inp.topo.vertex_class[cur], Classification::Point(_)) || wall[cur];
        if stop {
            side.ends_on_wall = wall[cur];
            return (side, s);
        }
        if s > 3.0 * t {
            return (side, f64::INFINITY);
        }
        match step.get(&cur) {
            Some(&nx) if nx != v && inp.line_tags.get(&key(cur, nx)).copied() == tags => {
                prev = cur;
                cur = nx;
            }
            _ => return (side, s),
        }
    }
}

/// Leans the columns near each concave corner of a chain towards the corner's mitre, so
/// that their tops spread over the corner instead of crossing its column.
fn lean_at_concave_corners(
    skin: &mut Skin,
    vs: &[usize],
    closed: bool,
    first_of: &[usize],
    last_of: &[usize],
) {
    let m = vs.len();
    let pts = skin.pts.clone();
    let idx = |i: isize| -> Option<usize> {
        if closed {
            Some(i.rem_euclid(m as isize) as usize)
        } else if (0..m as isize).contains(&i) {
            Some(i as usize)
        } else {
            None
        }
    };
    let turn_at = |i: usize| -> Option<f64> {
        let p = idx(i as isize - 1)?;
        let q = idx(i as isize + 1)?;
        Some(turn(unit(sub(pts[vs[i]], pts[vs[p]])), unit(sub(pts[vs[q]], pts[vs[i]]))))
    };
    let mut lean: Vec<(f64, P)> = vec![(0.0, [0.0, 0.0]); m];
    for i in 0..m {
        let Some(th) = turn_at(i) else { continue };
        if th.to_degrees() < CONCAVE_CORNER_DEG || first_of[i] != last_of[i] {
            continue;
        }
        let corner = skin.columns[first_of[i]].clone();
        let t = corner.nominal[skin.layers];
        for step in [1isize, -1] {
            let Some(j1) = idx(i as isize + step) else { continue };
            let t_away0 = unit(sub(pts[vs[j1]], pts[vs[i]]));
            let tau = dot(corner.dir, t_away0);
            if tau <= 0.0 {
                continue;
            }
            let reach = 2.0 * tau * t;
            let mut x = 0.0;
            let mut j = i;
            for _ in 0..m {
                let Some(jn) = idx(j as isize + step) else { break };
                if jn == i {
                    break;
                }
                x += norm(sub(pts[vs[jn]], pts[vs[j]]));
                if x >= reach || first_of[jn] != last_of[jn] {
                    break;
                }
                if turn_at(jn).is_some_and(|a| a.abs().to_degrees() >= CONCAVE_CORNER_DEG) {
                    break;
                }
                let t_away = unit(sub(pts[vs[jn]], pts[vs[j]]));
                let g = tau * (1.0 - x / reach);
                if g > lean[jn].0 {
                    lean[jn] = (g, t_away);
                }
                j = jn;
            }
        }
    }
    for i in 0..m {
        let (g, t_away) = lean[i];
        if g <= 0.0 {
            continue;
        }
        let c = &mut skin.columns[first_of[i]];
        let n = unit(left(t_away));
        let n = if dot(n, c.dir) < 0.0 { scale(n, -1.0) } else { n };
        let along_n = dot(c.dir, n);
        let own = dot(c.dir, t_away);
        if g > own {
            c.dir = add(scale(n, along_n), scale(t_away, g));
        }
    }
}

fn curve_label(topo: &Topology, c: usize) -> String {
    let cv = &topo.curves[c];
    match (&cv.name, cv.tag) {
        (Some(n), _) => format!("`{n}`"),
        (None, Some(t)) => t.to_string(),
        (None, None) => format!("#{c} (derived)"),
    }
}
