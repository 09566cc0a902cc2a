//! Periodic sides: two sets of boundary curves, a *master* and a *slave*, that a solver
//! glues because a transform (a translation, or a rotation about a centre) maps the
//! master onto the slave (thesis 6.3.2.4, the distributor's periodic pitch).
//!
//! [`check`] measures one pair on a mesh, by brute force over the curves' vertices and
//! edges (curves hold thousands of vertices at most, so O(master × slave) is cheap):
//!
//! - the shapes: every master vertex mapped by the transform lies on a slave edge and
//!   every slave vertex mapped back lies on a master edge, within [`SHAPE_TOLERANCE`]
//!   times the diagonal of the mesh's bounding box; otherwise the pair is refused
//!   ([`PeriodicError::NotImages`]) naming both sides and the distance found;
//! - the vertices: the largest distance between a master vertex's image and the nearest
//!   slave vertex, and between a slave vertex's preimage and the nearest master vertex
//!   ([`PairMatch::max_distance`]). A solver can glue the sides vertex to vertex when it
//!   is at rounding level ([`PairMatch::matched`]).
//!
//! Invariant kept by the remesher: the vertices and edges of the curves of a periodic pair
//! are coarsened alike ([`coarsen_sides`]: a vertex and its image removed together),
//! split alike ([`refine_sides`]) and then frozen (the remesher's
//! `RemeshOptions::periodic`), so a mesh whose sides match keeps them matching, bit for
//! bit, through `remesh` and `adapt`.

mod coarsen;
mod sides;

pub use coarsen::coarsen_sides;
pub use sides::{Rechecked, Sides, Snapped};

use crate::topology::{EntityRef, Topology};

/// Largest distance, relative to the diagonal of the mesh's bounding box, between a side
/// and the image of the other for the two to count as images of each other.
pub const SHAPE_TOLERANCE: f64 = 1e-6;

/// Largest distance, relative to the diagonal of the mesh's bounding box, between a
/// vertex's image and its partner for the two to count as one glued vertex.
pub const MATCH_TOLERANCE: f64 = 1e-12;

/// The map from the master side to the slave side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transform {
    /// p ↦ p + vector.
    Translation([f64; 2]),
    /// p ↦ centre + R(angle) (p − centre), the angle in degrees, counter-clockwise.
    Rotation {
        /// The centre.
        centre: [f64; 2],
        /// The angle, degrees.
        angle_degrees: f64,
    },
}

impl Transform {
    /// The image of `p`.
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        match *self {
            Transform::Translation(t) => [p[0] + t[0], p[1] + t[1]],
            Transform::Rotation { centre: c, angle_degrees } => {
                let (s, co) = angle_degrees.to_radians().sin_cos();
                let (x, y) = (p[0] - c[0], p[1] - c[1]);
                [c[0] + co * x - s * y, c[1] + s * x + co * y]
            }
        }
    }

    /// The inverse map.
    pub fn inverse(&self) -> Transform {
        match *self {
            Transform::Translation(t) => Transform::Translation([-t[0], -t[1]]),
            Transform::Rotation { centre, angle_degrees } => {
                Transform::Rotation { centre, angle_degrees: -angle_degrees }
            }
        }
    }

    /// Whether every number is finite.
    pub fn is_finite(&self) -> bool {
        match *self {
            Transform::Translation(t) => t.iter().all(|x| x.is_finite()),
            Transform::Rotation { centre, angle_degrees } => {
                centre.iter().all(|x| x.is_finite()) && angle_degrees.is_finite()
            }
        }
    }
}

/// One periodic pair: the curves (tags or names) of each side, and the map.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicPair {
    /// The master side's curves.
    pub master: Vec<EntityRef>,
    /// The slave side's curves.
    pub slave: Vec<EntityRef>,
    /// Master to slave.
    pub transform: Transform,
}

impl PeriodicPair {
    /// "master 302, 303 and slave 306, 307" as messages name the pair.
    pub fn label(&self) -> String {
        format!("master {} and slave {}", labels(&self.master), labels(&self.slave))
    }

    /// The tags of the master's and of the slave's curves on `topology`, each side's in
    /// the order its curves are listed, without repeats: what a solver format names the
    /// two sides by (OpenFOAM `cyclic` patches, Fluent periodic zones).
    pub fn side_tags(&self, topology: &Topology) -> Result<(Vec<i32>, Vec<i32>), PeriodicError> {
        let label = self.label();
        let tags = |names: &[EntityRef]| -> Result<Vec<i32>, PeriodicError> {
            let (_, _, found) = side(topology, names, &label)?;
            let mut out: Vec<i32> = Vec::with_capacity(found.len());
            for t in found {
                if !out.contains(&t) {
                    out.push(t);
                }
            }
            Ok(out)
        };
        Ok((tags(&self.master)?, tags(&self.slave)?))
    }
}

/// The curves as a command line spells them, "302, 303".
fn labels(curves: &[EntityRef]) -> String {
    curves.iter().map(EntityRef::label).collect::<Vec<_>>().join(", ")
}

/// How well one pair matches on a mesh.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PairMatch {
    /// The pair, as [`PeriodicPair::label`] names it.
    pub label: String,
    /// Vertices on the master side.
    pub master_vertices: usize,
    /// Vertices on the slave side.
    pub slave_vertices: usize,
    /// The largest distance between a vertex's image and the nearest vertex of the other
    /// side (both ways).
    pub max_distance: f64,
    /// Whether the sides can be glued vertex to vertex: as many vertices on each, every
    /// one within [`MATCH_TOLERANCE`] of the diagonal of its partner.
    pub matched: bool,
    /// The curve tags of both sides (the remesher freezes them).
    pub curve_tags: Vec<i32>,
}

/// Why a pair is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PeriodicError {
    /// A side names no curve of the mesh, or a curve without a tag.
    #[error("periodic pair {pair}: {why}")]
    Curve {
        /// The pair.
        pair: String,
        /// What is wrong.
        why: String,
    },
    /// The sides are not images of each other.
    #[error("periodic pair {pair}: the sides are not images of each other by the transform: a vertex of the {side} side at ({x}, {y}) is {distance:.3e} from the other side's image (tolerance {tolerance:.3e}, {SHAPE_TOLERANCE:e} of the domain's diagonal)")]
    NotImages {
        /// The pair.
        pair: String,
        /// "master" or "slave".
        side: &'static str,
        /// The vertex farthest off.
        x: f64,
        /// Its y.
        y: f64,
        /// How far.
        distance: f64,
        /// The tolerance.
        tolerance: f64,
    },
}

/// One side of a pair on a mesh: its vertices (sorted), its edges, its curves' tags.
pub(crate) type Side = (Vec<usize>, Vec<[usize; 2]>, Vec<i32>);

/// The vertices and edges of the curves `names` (tags or names) of `topology`, and the
/// curves' tags.
pub(crate) fn side(
    topology: &Topology,
    names: &[EntityRef],
    pair: &str,
) -> Result<Side, PeriodicError> {
    let bad = |why: String| PeriodicError::Curve { pair: pair.to_string(), why };
    if names.is_empty() {
        return Err(bad("a side lists no curve".into()));
    }
    let mut vertices = std::collections::BTreeSet::new();
    let mut edges = Vec::new();
    let mut tags = Vec::new();
    for name in names {
        let found = topology.resolve_curves(name).map_err(|e| bad(e.to_string()))?;
        for c in found {
            let curve = &topology.curves[c];
            tags.extend(curve.tag);
            for p in &curve.polylines {
                vertices.extend(p.vertices.iter().copied());
                edges.extend(p.edges());
            }
        }
    }
    if edges.is_empty() {
        return Err(bad(format!("curves {} have no edge", labels(names))));
    }
    Ok((vertices.into_iter().collect(), edges, tags))
}

/// Distance from `p` to segment `a`–`b`.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// Measures `pair` on the mesh of `points` whose topology is `topology`.
pub fn check(
    points: &[[f64; 3]],
    topology: &Topology,
    pair: &PeriodicPair,
) -> Result<PairMatch, PeriodicError> {
    let label = pair.label();
    let (mv, me, mut tags) = side(topology, &pair.master, &label)?;
    let (sv, se, slave_tags) = side(topology, &pair.slave, &label)?;
    tags.extend(slave_tags);
    let xy = |v: usize| [points[v][0], points[v][1]];
    let diagonal = diagonal(points);
    let tolerance = SHAPE_TOLERANCE * diagonal;
    let inverse = pair.transform.inverse();
    // Shapes: each side's vertices mapped onto the other side's edges.
    for (name, verts, map, edges) in
        [("master", &mv, pair.transform, &se), ("slave", &sv, inverse, &me)]
    {
        for &v in verts {
            let q = map.apply(xy(v));
            let d = edges
                .iter()
                .map(|e| to_segment(q, xy(e[0]), xy(e[1])))
                .fold(f64::INFINITY, f64::min);
            if d.is_nan() || d > tolerance {
                let [x, y] = xy(v);
                return Err(PeriodicError::NotImages {
                    pair: label,
                    side: name,
                    x,
                    y,
                    distance: d,
                    tolerance,
                });
            }
        }
    }
    // Vertices: each image to the nearest vertex of the other side.
    let mut max_distance = 0.0f64;
    for (verts, map, other) in [(&mv, pair.transform, &sv), (&sv, inverse, &mv)] {
        for &v in verts {
            let q = map.apply(xy(v));
            let d = other
                .iter()
                .map(|&w| {
                    let p = xy(w);
                    (p[0] - q[0]).hypot(p[1] - q[1])
                })
                .fold(f64::INFINITY, f64::min);
            max_distance = max_distance.max(d);
        }
    }
    tags.sort_unstable();
    tags.dedup();
    Ok(PairMatch {
        label,
        master_vertices: mv.len(),
        slave_vertices: sv.len(),
        max_distance,
        matched: mv.len() == sv.len() && max_distance <= MATCH_TOLERANCE * diagonal,
        curve_tags: tags,
    })
}

/// Measures every pair of `pairs` on `mesh`.
pub fn check_all(
    mesh: &smartmesh_formats::TaggedMesh,
    pairs: &[PeriodicPair],
) -> Result<Vec<PairMatch>, PeriodicError> {
    if pairs.is_empty() {
        return Ok(Vec::new());
    }
    let topology = Topology::from_mesh(mesh);
    pairs.iter().map(|p| check(&mesh.points, &topology, p)).collect()
}

/// The diagonal of the bounding box of `points`: the length the side tolerances scale with.
pub(crate) fn diagonal(points: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

/// Moves the slave vertices of every pair whose sides pair up one to one, each slave
/// vertex within [`SHAPE_TOLERANCE`] of the diagonal of a master vertex's image, onto
/// those exact images: a file written with fewer digits than a double (Gmsh's `.msh` at
/// its defaults) leaves gaps of 1e-9 that a solver gluing vertices may not accept.
/// Returns, per pair, the largest move (0 where the sides do not pair up; those are left
/// as they are).
pub fn snap(mesh: &mut smartmesh_formats::TaggedMesh, pairs: &[PeriodicPair]) -> Vec<f64> {
    if pairs.is_empty() {
        return Vec::new();
    }
    let topology = Topology::from_mesh(mesh);
    let tolerance = SHAPE_TOLERANCE * diagonal(&mesh.points);
    let mut moved = Vec::new();
    for pair in pairs {
        let label = pair.label();
        let (Ok((mv, _, _)), Ok((sv, _, _))) =
            (side(&topology, &pair.master, &label), side(&topology, &pair.slave, &label))
        else {
            moved.push(0.0);
            continue;
        };
        let xy = |v: usize| [mesh.points[v][0], mesh.points[v][1]];
        let mut moves: Vec<(usize, [f64; 2], f64)> = Vec::new();
        for &m in &mv {
            let q = pair.transform.apply(xy(m));
            let near = sv.iter().map(|&w| {
                let p = xy(w);
                (w, (p[0] - q[0]).hypot(p[1] - q[1]))
            });
            if let Some((w, d)) = near.min_by(|a, b| a.1.total_cmp(&b.1)) {
                moves.push((w, q, d));
            }
        }
        let mut partners: Vec<usize> = moves.iter().map(|m| m.0).collect();
        partners.sort_unstable();
        partners.dedup();
        let one_to_one = mv.len() == sv.len() && partners.len() == sv.len();
        if !one_to_one || moves.iter().any(|m| m.2.is_nan() || m.2 > tolerance) {
            moved.push(0.0);
            continue;
        }
        let mut largest = 0.0f64;
        for (w, q, d) in moves {
            mesh.points[w][0] = q[0];
            mesh.points[w][1] = q[1];
            largest = largest.max(d);
        }
        moved.push(largest);
    }
    moved
}

/// `mesh`, its sides first snapped ([`snap`]), with the edges of its matched periodic
/// sides split so that none is longer than
/// 1 in the metric at either side's ends (sized to the finer of the two images), the same
/// splits on both sides: each new slave vertex is the image of a new master vertex, so
/// the sides stay matched. New vertices are appended (their metric interpolated along the
/// edge; a triangle with one split edge is fanned from its opposite vertex, one with more
/// from its centroid); line cells are split alike; point data is dropped (the remesher
/// carries only the metric). Unmatched pairs, and edges of non-triangle cells, are left
/// as they are. [`coarsen_sides`] removes what the metric does not need.
pub fn refine_sides(
    mesh: &smartmesh_formats::TaggedMesh,
    metric: &[crate::metric::Sym2],
    pairs: &[PeriodicPair],
) -> (smartmesh_formats::TaggedMesh, Vec<crate::metric::Sym2>) {
    use smartmesh_formats::{CellBlock, CellKind};
    use std::collections::BTreeMap;
    let mut out = mesh.clone();
    let mut metric = metric.to_vec();
    if pairs.is_empty() || metric.len() != mesh.points.len() {
        return (out, metric);
    }
    snap(&mut out, pairs);
    let snapped = out.clone();
    let mesh = &snapped;
    let topology = Topology::from_mesh(mesh);
    let key = |a: usize, b: usize| if a < b { (a, b) } else { (b, a) };
    // Edges no split may touch: those of quads and other non-triangle surface cells.
    let mut locked = std::collections::BTreeSet::new();
    for (kind, nodes, _, _) in mesh.cells() {
        if kind.dim() == 2 && kind != CellKind::Triangle {
            for k in 0..nodes.len() {
                locked.insert(key(nodes[k] as usize, nodes[(k + 1) % nodes.len()] as usize));
            }
        }
    }
    // New vertices of each split edge, from its smaller end to its larger one.
    let mut splits: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    let xy = |p: &[f64; 3]| [p[0], p[1]];
    for pair in pairs {
        let label = pair.label();
        let Ok(m) = check(&mesh.points, &topology, pair) else { continue };
        let (Ok((_, me, _)), Ok((sv, _, _))) =
            (side(&topology, &pair.master, &label), side(&topology, &pair.slave, &label))
        else {
            continue;
        };
        if !m.matched {
            continue;
        }
        let partner = |q: [f64; 2]| {
            sv.iter().copied().min_by(|&u, &w| {
                let d = |v: usize| (mesh.points[v][0] - q[0]).hypot(mesh.points[v][1] - q[1]);
                d(u).total_cmp(&d(w))
            })
        };
        for &[a, b] in &me {
            let (pa, pb) = (xy(&mesh.points[a]), xy(&mesh.points[b]));
            let (Some(a2), Some(b2)) =
                (partner(pair.transform.apply(pa)), partner(pair.transform.apply(pb)))
            else {
                continue;
            };
            if locked.contains(&key(a, b)) || locked.contains(&key(a2, b2)) {
                continue;
            }
            // The points strictly inside edge u→w so far, in that order.
            let placed = |u: usize, w: usize| -> Option<Vec<[f64; 2]>> {
                let l = splits.get(&key(u, w))?;
                let mut pts: Vec<[f64; 2]> = l.iter().map(|&v| xy(&out.points[v])).collect();
                if u > w {
                    pts.reverse();
                }
                Some(pts)
            };
            // Where the new master points go: a side already split by another pair is
            // copied to the other (the chain of pairs stays matched); else the metric says.
            let (pb2, inverse) = (xy(&mesh.points[b2]), pair.transform.inverse());
            let on_a_to_b: Vec<[f64; 2]> = match (placed(a, b), placed(a2, b2)) {
                (Some(_), Some(_)) => continue,
                (Some(pts), None) => pts,
                (None, Some(pts)) => pts.iter().map(|&q| inverse.apply(q)).collect(),
                (None, None) => {
                    let length = |u: usize, w: usize| {
                        let d = [
                            mesh.points[w][0] - mesh.points[u][0],
                            mesh.points[w][1] - mesh.points[u][1],
                        ];
                        let m = 0.5 * (metric[u] + metric[w]);
                        m.quadratic_form(d).max(0.0).sqrt()
                    };
                    let l = length(a, b).max(length(a2, b2));
                    if !l.is_finite() || l <= 1.0 {
                        continue;
                    }
                    let k = (l.ceil() as usize).min(1 << 16);
                    (1..k)
                        .map(|i| {
                            let t = i as f64 / k as f64;
                            [pa[0] + t * (pb[0] - pa[0]), pa[1] + t * (pb[1] - pa[1])]
                        })
                        .collect()
                }
            };
            let (old_master, old_slave) = (placed(a, b).is_some(), placed(a2, b2).is_some());
            let (mut on_master, mut on_slave) = (Vec::new(), Vec::new());
            let along = |p: [f64; 2], u: [f64; 2], w: [f64; 2]| {
                let d = [w[0] - u[0], w[1] - u[1]];
                (((p[0] - u[0]) * d[0] + (p[1] - u[1]) * d[1]) / (d[0] * d[0] + d[1] * d[1]))
                    .clamp(0.0, 1.0)
            };
            for &p in &on_a_to_b {
                let q = pair.transform.apply(p);
                let pa2 = xy(&mesh.points[a2]);
                for (pt, ends, t, list, exists) in [
                    (p, (a, b), along(p, pa, pb), &mut on_master, old_master),
                    (q, (a2, b2), along(q, pa2, pb2), &mut on_slave, old_slave),
                ] {
                    if exists {
                        continue;
                    }
                    list.push(out.points.len());
                    out.points.push([pt[0], pt[1], 0.0]);
                    metric.push((1.0 - t) * metric[ends.0] + t * metric[ends.1]);
                }
            }
            if on_a_to_b.is_empty() {
                continue;
            }
            for ((u, w), mut list) in [((a, b), on_master), ((a2, b2), on_slave)] {
                if list.is_empty() {
                    continue;
                }
                if u > w {
                    list.reverse();
                }
                splits.insert(key(u, w), list);
            }
        }
    }
    if splits.is_empty() {
        return (out, metric);
    }
    // The points strictly inside edge u→w, in that order.
    let inside = |u: usize, w: usize| -> Vec<usize> {
        match splits.get(&key(u, w)) {
            Some(l) if u < w => l.clone(),
            Some(l) => l.iter().rev().copied().collect(),
            None => Vec::new(),
        }
    };
    let mut blocks = Vec::new();
    for block in &mesh.blocks {
        let mut nb = CellBlock::new(block.kind);
        for (c, nodes) in block.cells().enumerate() {
            let (phys, geo) = (block.physical[c], block.geometrical[c]);
            let v: Vec<usize> = nodes.iter().map(|&n| n as usize).collect();
            match block.kind {
                CellKind::Line => {
                    let mut chain = vec![v[0]];
                    chain.extend(inside(v[0], v[1]));
                    chain.push(v[1]);
                    for w in chain.windows(2) {
                        nb.push(&[w[0], w[1]], phys, geo);
                    }
                }
                CellKind::Triangle => {
                    let split: Vec<usize> = (0..3)
                        .filter(|&k| splits.contains_key(&key(v[k], v[(k + 1) % 3])))
                        .collect();
                    match split.as_slice() {
                        [] => nb.push(&v, phys, geo),
                        &[k] => {
                            let (a, b, c) = (v[k], v[(k + 1) % 3], v[(k + 2) % 3]);
                            let mut chain = vec![a];
                            chain.extend(inside(a, b));
                            chain.push(b);
                            for w in chain.windows(2) {
                                nb.push(&[w[0], w[1], c], phys, geo);
                            }
                        }
                        _ => {
                            let mut ring = Vec::new();
                            for k in 0..3 {
                                ring.push(v[k]);
                                ring.extend(inside(v[k], v[(k + 1) % 3]));
                            }
                            let centre = out.points.len();
                            let g = |i: usize| {
                                (mesh.points[v[0]][i] + mesh.points[v[1]][i] + mesh.points[v[2]][i])
                                    / 3.0
                            };
                            out.points.push([g(0), g(1), 0.0]);
                            metric.push((1.0 / 3.0) * (metric[v[0]] + metric[v[1]] + metric[v[2]]));
                            for i in 0..ring.len() {
                                nb.push(&[ring[i], ring[(i + 1) % ring.len()], centre], phys, geo);
                            }
                        }
                    }
                }
                _ => nb.push(&v, phys, geo),
            }
        }
        blocks.push(nb);
    }
    out.blocks = blocks;
    out.point_data.clear();
    out.cell_data.clear();
    (out, metric)
}

impl std::fmt::Display for PairMatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "periodic {}: {} and {} vertices, largest distance between a vertex's image and its partner {:.3e} ({})",
            self.label,
            self.master_vertices,
            self.slave_vertices,
            self.max_distance,
            if self.matched { "matched" } else { "NOT matched vertex to vertex" }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_transform_and_its_inverse_cancel() {
        for t in [
            Transform::Translation([3.5, -88.0]),
            Transform::Rotation { centre: [1.0, -2.0], angle_degrees: 36.0 },
        ] {
            for p in [[0.0, 0.0], [10.0, -7.5], [-1e3, 2e2]] {
                let q = t.inverse().apply(t.apply(p));
                assert!((q[0] - p[0]).abs() < 1e-12 && (q[1] - p[1]).abs() < 1e-12, "{q:?}");
            }
        }
        // A quarter turn about (1, 1) takes (2, 1) to (1, 2).
        let q = Transform::Rotation { centre: [1.0, 1.0], angle_degrees: 90.0 }.apply([2.0, 1.0]);
        assert!((q[0] - 1.0).abs() < 1e-15 && (q[1] - 2.0).abs() < 1e-15, "{q:?}");
    }

    #[test]
    fn the_distance_to_a_segment_is_the_analytic_one() {
        assert_eq!(to_segment([0.5, 2.0], [0.0, 0.0], [1.0, 0.0]), 2.0);
        assert_eq!(to_segment([-3.0, 4.0], [0.0, 0.0], [1.0, 0.0]), 5.0);
        assert_eq!(to_segment([4.0, 4.0], [0.0, 0.0], [1.0, 0.0]), 5.0);
        assert_eq!(to_segment([4.0, 4.0], [1.0, 0.0], [1.0, 0.0]), 5.0);
    }
}
