//! Coarsening of matched periodic sides: a vertex of the master side and its image on the
//! slave side are removed together, each collapsed onto its neighbour along its side, so
//! the sides stay matched while they lose the vertices the metric does not need.
//!
//! A vertex `v` between `u` and `w` on a master polyline goes when all of these hold:
//! - the merged edge `u`–`w` is at most 1 long in the metric (the mean of its ends'
//!   tensors, as [`super::refine_sides`] measures), on the master side and for the
//!   images `u'`–`w'` on the slave side: so [`super::refine_sides`] never splits it
//!   again, and edges end between 1/2 and 1 where the metric is coarser than the sides;
//! - neither `v` nor its image is a topological point (a corner, a curve end, a
//!   junction), on a quadrangle, or on the sides of another pair;
//! - every triangle around `v` (and around its image) that survives the collapse stays
//!   positive, its quality ([`crate::quality::triangle_quality`]) at least the smaller of
//!   0.1 and the worst quality around the vertex before (the remesher, which runs next,
//!   improves the triangles inside; the floor only keeps them from going flat).
//!
//! Vertices are visited along each polyline in order, greedily; after a collapse the next
//! candidate is the old `w` with `u` as its neighbour. Unmatched pairs are left as they
//! are. Invariant: a pair matched on the input is matched on the output with the same
//! coordinates for every vertex kept (vertices are removed, never moved).

use std::collections::{BTreeMap, BTreeSet};

use smartmesh_formats::{CellBlock, CellKind, TaggedMesh};

use super::{check, side, snap, PeriodicPair};
use crate::metric::Sym2;
use crate::quality::{signed_area, triangle_quality};
use crate::topology::Topology;

/// The quality a triangle around a removed vertex may always drop to.
const QUALITY_FLOOR: f64 = 0.1;

/// `mesh` and `metric` with the matched sides of `pairs` coarsened alike (module docs).
/// Point data and cell data are dropped when a vertex goes (the remesher carries only the
/// metric); otherwise the input is returned as it is.
pub fn coarsen_sides(
    mesh: &TaggedMesh,
    metric: &[Sym2],
    pairs: &[PeriodicPair],
) -> (TaggedMesh, Vec<Sym2>) {
    if pairs.is_empty() || metric.len() != mesh.points.len() {
        return (mesh.clone(), metric.to_vec());
    }
    let mut mesh = mesh.clone();
    snap(&mut mesh, pairs);
    let topology = Topology::from_mesh(&mesh);
    let xy = |v: usize| [mesh.points[v][0], mesh.points[v][1]];
    // Vertices no collapse may touch: topological points, quadrangle corners, and those
    // on the sides of more than one pair.
    let mut fixed: BTreeSet<usize> = topology.points.iter().map(|p| p.vertex).collect();
    let mut triangles: Vec<[usize; 3]> = Vec::new();
    for (kind, nodes, _, _) in mesh.cells() {
        match kind {
            CellKind::Triangle => {
                triangles.push([nodes[0] as usize, nodes[1] as usize, nodes[2] as usize])
            }
            k if k.dim() == 2 => fixed.extend(nodes.iter().map(|&v| v as usize)),
            _ => {}
        }
    }
    let mut sides_of: BTreeMap<usize, usize> = BTreeMap::new();
    for pair in pairs {
        let label = pair.label();
        for names in [&pair.master, &pair.slave] {
            if let Ok((vertices, _, _)) = side(&topology, names, &label) {
                for v in vertices {
                    *sides_of.entry(v).or_default() += 1;
                }
            }
        }
    }
    fixed.extend(sides_of.iter().filter(|e| *e.1 > 1).map(|e| *e.0));
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); mesh.points.len()];
    for (t, tri) in triangles.iter().enumerate() {
        for &v in tri {
            around[v].push(t);
        }
    }
    let mut alive = vec![true; triangles.len()];
    // Where each removed vertex went.
    let mut onto: BTreeMap<usize, usize> = BTreeMap::new();
    let length = |u: usize, w: usize| {
        let d = [mesh.points[w][0] - mesh.points[u][0], mesh.points[w][1] - mesh.points[u][1]];
        (0.5 * (metric[u] + metric[w])).quadratic_form(d).max(0.0).sqrt()
    };
    for pair in pairs {
        let label = pair.label();
        let Ok(m) = check(&mesh.points, &topology, pair) else { continue };
        let (Ok((mv, _, _)), Ok((sv, _, _))) =
            (side(&topology, &pair.master, &label), side(&topology, &pair.slave, &label))
        else {
            continue;
        };
        if !m.matched {
            continue;
        }
        let partner: BTreeMap<usize, usize> = mv
            .iter()
            .filter_map(|&v| {
                let q = pair.transform.apply(xy(v));
                let d = |w: usize| (mesh.points[w][0] - q[0]).hypot(mesh.points[w][1] - q[1]);
                sv.iter().copied().min_by(|&a, &b| d(a).total_cmp(&d(b))).map(|w| (v, w))
            })
            .collect();
        for name in &pair.master {
            let Ok(curves) = topology.resolve_curves(name) else { continue };
            for c in curves {
                for polyline in &topology.curves[c].polylines {
                    let p = &polyline.vertices;
                    let n = p.len();
                    if n < 3 {
                        continue;
                    }
                    let mut u = p[0];
                    for k in 1..n - 1 {
                        let (v, w) = (p[k], p[(k + 1) % n]);
                        let (Some(&u2), Some(&v2), Some(&w2)) =
                            (partner.get(&u), partner.get(&v), partner.get(&w))
                        else {
                            u = v;
                            continue;
                        };
                        let keep = fixed.contains(&v)
                            || fixed.contains(&v2)
                            || length(u, w) > 1.0
                            || length(u2, w2) > 1.0
                            || !collapsible(&mesh, &triangles, &alive, &around[v], v, u)
                            || !collapsible(&mesh, &triangles, &alive, &around[v2], v2, u2);
                        if keep {
                            u = v;
                            continue;
                        }
                        for (from, to) in [(v, u), (v2, u2)] {
                            collapse(&mut triangles, &mut alive, &mut around, from, to);
                            onto.insert(from, to);
                        }
                    }
                }
            }
        }
    }
    if onto.is_empty() {
        return (mesh, metric.to_vec());
    }
    rebuild(&mesh, metric, &triangles, &alive, &onto)
}

/// Whether moving `v` onto `u` keeps every triangle of `ring` (those around `v`) that
/// does not hold `u` positive and of good enough quality (module docs).
fn collapsible(
    mesh: &TaggedMesh,
    triangles: &[[usize; 3]],
    alive: &[bool],
    ring: &[usize],
    v: usize,
    u: usize,
) -> bool {
    let xy = |w: usize| [mesh.points[w][0], mesh.points[w][1]];
    let live: Vec<[usize; 3]> = ring.iter().filter(|&&t| alive[t]).map(|&t| triangles[t]).collect();
    if !live.iter().any(|t| t.contains(&u)) {
        // `u`–`v` is no edge of the mesh: not the side's neighbour after all.
        return false;
    }
    let worst = live
        .iter()
        .map(|t| triangle_quality(xy(t[0]), xy(t[1]), xy(t[2])))
        .fold(f64::INFINITY, f64::min);
    let floor = worst.min(QUALITY_FLOOR);
    live.iter().filter(|t| !t.contains(&u)).all(|t| {
        let p = t.map(|w| if w == v { xy(u) } else { xy(w) });
        signed_area(p[0], p[1], p[2]) > 0.0 && triangle_quality(p[0], p[1], p[2]) >= floor
    })
}

/// Moves `v` onto `u`: the triangles holding both go, the others take `u` for `v`.
fn collapse(
    triangles: &mut [[usize; 3]],
    alive: &mut [bool],
    around: &mut [Vec<usize>],
    v: usize,
    u: usize,
) {
    for t in std::mem::take(&mut around[v]) {
        if !alive[t] {
            continue;
        }
        if triangles[t].contains(&u) {
            alive[t] = false;
        } else {
            for w in triangles[t].iter_mut() {
                if *w == v {
                    *w = u;
                }
            }
            around[u].push(t);
        }
    }
}

/// The mesh after the collapses: triangles as they are now, other cells with their
/// vertices sent where they went (line cells that shrink to a point dropped), the removed
/// vertices taken out and the rest renumbered in order.
fn rebuild(
    mesh: &TaggedMesh,
    metric: &[Sym2],
    triangles: &[[usize; 3]],
    alive: &[bool],
    onto: &BTreeMap<usize, usize>,
) -> (TaggedMesh, Vec<Sym2>) {
    let mut index = vec![usize::MAX; mesh.points.len()];
    let mut out = mesh.clone();
    out.points.clear();
    let mut kept_metric = Vec::new();
    for v in 0..mesh.points.len() {
        if !onto.contains_key(&v) {
            index[v] = out.points.len();
            out.points.push(mesh.points[v]);
            kept_metric.push(metric[v]);
        }
    }
    let to = |mut v: usize| {
        while let Some(&w) = onto.get(&v) {
            v = w;
        }
        index[v]
    };
    let mut next_triangle = 0;
    let mut blocks = Vec::new();
    for block in &mesh.blocks {
        let mut nb = CellBlock::new(block.kind);
        for (c, nodes) in block.cells().enumerate() {
            let (phys, geo) = (block.physical[c], block.geometrical[c]);
            if block.kind == CellKind::Triangle {
                let t = next_triangle;
                next_triangle += 1;
                if alive[t] {
                    nb.push(&triangles[t].map(|v| index[v]), phys, geo);
                }
                continue;
            }
            let v: Vec<usize> = nodes.iter().map(|&n| to(n as usize)).collect();
            if block.kind == CellKind::Line && v[0] == v[1] {
                continue;
            }
            nb.push(&v, phys, geo);
        }
        blocks.push(nb);
    }
    out.blocks = blocks;
    out.point_data.clear();
    out.cell_data.clear();
    out.point_sets.clear();
    out.cell_sets.clear();
    (out, kept_metric)
}
