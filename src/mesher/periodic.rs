//! The starting mesh of a graph with periodic sides: every vertex of the slave side the
//! exact image of a vertex of the master side, and the reverse, so that a solver can glue
//! the two sides vertex to vertex (thesis 6.3.2.4).
//!
//! How:
//! 1. Each pair is checked on the graph itself ([`crate::periodic::check`]): each side
//!    the other's image within [`SHAPE_TOLERANCE`] of the diagonal, else
//!    [`MeshError::Periodic`] naming the pair.
//! 2. The graph's sides are made alike (`symmetrise`): the images of the slave's
//!    vertices are inserted into the master's segments and the images of the master's
//!    into the slave's, the slave's copies placed at exactly `transform(master point)`
//!    (existing slave vertices within the tolerance are moved there by
//!    [`crate::periodic::snap`]). A curve in two pairs passes its points on through both;
//!    this repeats until nothing is inserted.
//! 3. The graph is triangulated ([`super::triangulate`]). The refinement may split a
//!    segment of one side and not the same segment of the other (its neighbourhood
//!    differs); then the mesh's new side vertices are inserted into the graph's segments,
//!    made alike again, and the graph triangulated again from scratch. The segment
//!    vertices only grow, toward what the refinement asks of the finer side, so this
//!    settles; not at once, though: spade splits a subsegment a power of two from one of
//!    its ends, and which end it picks may differ between the sides, so a round can ask
//!    for new splits. Measured on the distributor's graphs (`examples/distributor`):
//!    1 round at the default options, 3 to 12 with `--size` 1.5 to 0.3 (so up to 12
//!    triangulations' time). After [`MAX_ROUNDS`] it is
//!    [`MeshError::PeriodicUnsettled`].
//!
//! Invariant of the result: for every pair, [`crate::periodic::check`] says matched:
//! as many vertices on each side, each within [`crate::periodic::MATCH_TOLERANCE`] of
//! the diagonal of its partner's image (the slave's are the images computed once, so the
//! gap is rounding). The quality guarantees of [`super::triangulate`] hold, since the
//! last mesh is its output for a graph.

use std::collections::BTreeMap;

use smartmesh_formats::{CellBlock, CellKind, TaggedMesh};

use super::{triangulate, MeshError, MeshOptions};
use crate::periodic::{check, diagonal, side, snap, PeriodicPair, SHAPE_TOLERANCE};
use crate::topology::Topology;

/// A point placed along an edge: its parameter and its coordinates.
type Placed = (f64, [f64; 2]);

/// Most triangulations before the sides are declared unsettled.
pub(super) const MAX_ROUNDS: usize = 24;

/// Most passes over the pairs, per round, before the insertions are declared unsettled
/// (each pass carries points one pair further along a chain of pairs).
const MAX_PASSES: usize = 16;

/// [`triangulate`] with the sides of `pairs` matched vertex to vertex (module docs).
/// Without pairs it is [`triangulate`].
pub fn triangulate_periodic(
    graph: &TaggedMesh,
    opts: &MeshOptions,
    pairs: &[PeriodicPair],
) -> Result<TaggedMesh, MeshError> {
    if pairs.is_empty() {
        return triangulate(graph, opts);
    }
    opts.validate()?;
    let mut g = graph.clone();
    // The mesher reads no cell data; splitting segments would misalign it.
    g.cell_data.clear();
    g.cell_sets.clear();
    let topology = Topology::from_mesh(&g);
    for pair in pairs {
        check(&g.points, &topology, pair)?;
    }
    symmetrise(&mut g, pairs, &[])?;
    for round in 0..MAX_ROUNDS {
        let mesh = triangulate(&g, opts)?;
        let topology = Topology::from_mesh(&mesh);
        let mut extra = Vec::new();
        let mut unmatched = None;
        for pair in pairs {
            let m = check(&mesh.points, &topology, pair)?;
            if m.matched {
                continue;
            }
            unmatched.get_or_insert(m.label);
            let label = pair.label();
            for names in [&pair.master, &pair.slave] {
                let (vertices, _, _) = side(&topology, names, &label)?;
                extra.extend(vertices.iter().map(|&v| [mesh.points[v][0], mesh.points[v][1]]));
            }
        }
        let Some(label) = unmatched else {
            return Ok(mesh);
        };
        if round + 1 == MAX_ROUNDS || !symmetrise(&mut g, pairs, &extra)? {
            return Err(MeshError::PeriodicUnsettled { pair: label, rounds: round + 1 });
        }
    }
    unreachable!("the last round returns")
}

/// Where `p` falls on segment `a`–`b`: the parameter of its projection and its distance.
fn on_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 > 0.0 { ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2 } else { 0.0 };
    let t = t.clamp(0.0, 1.0);
    (t, (p[0] - a[0] - t * d[0]).hypot(p[1] - a[1] - t * d[1]))
}

/// Inserts into the periodic sides of `g` the points of `extra` that lie on them, then
/// the images of each side's vertices into the other side, until both sides of every
/// pair have the same vertices (the slave's at the master's exact images). Returns
/// whether a point was inserted.
fn symmetrise(
    g: &mut TaggedMesh,
    pairs: &[PeriodicPair],
    extra: &[[f64; 2]],
) -> Result<bool, MeshError> {
    let tolerance = SHAPE_TOLERANCE * diagonal(&g.points);
    let mut inserted = false;
    // The mesh's points onto whichever side's segments hold them.
    if !extra.is_empty() {
        let topology = Topology::from_mesh(g);
        let mut wanted = Vec::new();
        for pair in pairs {
            let label = pair.label();
            for names in [&pair.master, &pair.slave] {
                let (vertices, edges, _) = side(&topology, names, &label)?;
                wanted.extend(places(g, &vertices, &edges, extra, tolerance));
            }
        }
        inserted |= split(g, wanted);
    }
    for _ in 0..MAX_PASSES {
        let mut changed = false;
        for pair in pairs {
            let topology = Topology::from_mesh(g);
            let label = pair.label();
            let (mv, me, _) = side(&topology, &pair.master, &label)?;
            let (sv, se, _) = side(&topology, &pair.slave, &label)?;
            let xy = |v: usize| [g.points[v][0], g.points[v][1]];
            let inverse = pair.transform.inverse();
            // The slave's vertices onto the master, then the master's (all of them,
            // the new ones too) onto the slave, at their exact images.
            let to_master: Vec<[f64; 2]> = sv.iter().map(|&v| inverse.apply(xy(v))).collect();
            let wanted = places(g, &mv, &me, &to_master, tolerance);
            changed |= split(g, wanted);
            let topology = Topology::from_mesh(g);
            let (mv, _, _) = side(&topology, &pair.master, &label)?;
            let xy = |v: usize| [g.points[v][0], g.points[v][1]];
            let to_slave: Vec<[f64; 2]> = mv.iter().map(|&v| pair.transform.apply(xy(v))).collect();
            let wanted = places(g, &sv, &se, &to_slave, tolerance);
            changed |= split(g, wanted);
            snap(g, std::slice::from_ref(pair));
        }
        inserted |= changed;
        if !changed {
            return Ok(inserted);
        }
    }
    let label = pairs.first().map(PeriodicPair::label).unwrap_or_default();
    Err(MeshError::PeriodicUnsettled { pair: label, rounds: 0 })
}

/// The points of `candidates` that lie on an edge of `edges` (within `tolerance`) and
/// are not within `tolerance` of a vertex of `vertices`: each with its edge and its
/// parameter along it.
fn places(
    g: &TaggedMesh,
    vertices: &[usize],
    edges: &[[usize; 2]],
    candidates: &[[f64; 2]],
    tolerance: f64,
) -> Vec<([usize; 2], f64, [f64; 2])> {
    let xy = |v: usize| [g.points[v][0], g.points[v][1]];
    let mut out = Vec::new();
    for &p in candidates {
        let near = |q: [f64; 2]| (q[0] - p[0]).hypot(q[1] - p[1]) <= tolerance;
        if vertices.iter().any(|&v| near(xy(v))) {
            continue;
        }
        let best = edges
            .iter()
            .map(|&e| (e, on_segment(p, xy(e[0]), xy(e[1]))))
            .min_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        if let Some((e, (t, d))) = best {
            if d <= tolerance && t > 0.0 && t < 1.0 {
                out.push((e, t, p));
            }
        }
    }
    out
}

/// Splits the Line cells of `g` at the points of `wanted` (edge, parameter, point),
/// points closer than the tolerance along one edge taken once. New points are appended
/// (point data extended with zeros: a new vertex has no marker of its own). Returns
/// whether anything was split.
fn split(g: &mut TaggedMesh, wanted: Vec<([usize; 2], f64, [f64; 2])>) -> bool {
    if wanted.is_empty() {
        return false;
    }
    let tolerance = SHAPE_TOLERANCE * diagonal(&g.points);
    // Per edge (from its smaller vertex), the new points in order.
    let mut by_edge: BTreeMap<(usize, usize), Vec<Placed>> = BTreeMap::new();
    for ([a, b], t, p) in wanted {
        let (key, t) = if a < b { ((a, b), t) } else { ((b, a), 1.0 - t) };
        by_edge.entry(key).or_default().push((t, p));
    }
    let mut inside: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (key, mut pts) in by_edge {
        pts.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut list: Vec<usize> = Vec::new();
        let mut last: Option<[f64; 2]> = None;
        for (_, p) in pts {
            if last.is_some_and(|q| (q[0] - p[0]).hypot(q[1] - p[1]) <= tolerance) {
                continue;
            }
            last = Some(p);
            list.push(g.points.len());
            g.points.push([p[0], p[1], 0.0]);
        }
        inside.insert(key, list);
    }
    let n = g.points.len();
    for a in g.point_data.values_mut() {
        a.values.resize(n * a.components, 0.0);
    }
    for block in &mut g.blocks {
        if block.kind != CellKind::Line {
            continue;
        }
        let mut nb = CellBlock::new(CellKind::Line);
        for (c, nodes) in block.cells().enumerate() {
            let (u, w) = (nodes[0] as usize, nodes[1] as usize);
            let mut chain = vec![u];
            match inside.get(&(u.min(w), u.max(w))) {
                Some(l) if u < w => chain.extend(l.iter().copied()),
                Some(l) => chain.extend(l.iter().rev().copied()),
                None => {}
            }
            chain.push(w);
            for s in chain.windows(2) {
                nb.push(&[s[0], s[1]], block.physical[c], block.geometrical[c]);
            }
        }
        *block = nb;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_on_a_segment_has_its_parameter_and_distance() {
        assert_eq!(on_segment([0.25, 1.0], [0.0, 0.0], [1.0, 0.0]), (0.25, 1.0));
        assert_eq!(on_segment([2.0, 0.0], [0.0, 0.0], [1.0, 0.0]), (1.0, 1.0));
    }
}
