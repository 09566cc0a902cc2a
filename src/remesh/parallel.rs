//! The remesher on every core: a large mesh is cut into parts, every part is remeshed by
//! the serial remesher with its interface frozen, in parallel (rayon), the parts are glued
//! back, and the interfaces are then remeshed by further passes over the triangles around
//! them, cut elsewhere (the scheme ParMmg publishes for 3D: remesh with frozen
//! interfaces, move the interfaces, remesh again).
//!
//! The passes:
//! 0. When the metric asks for more than [`super::Partitioning::coarse_ratio`] times the
//!    input's vertices, the input is first remeshed to the metric divided by that ratio
//!    (by this driver again when that is still large), and that mesh, whose metric is
//!    the input's interpolated, is what the next passes cut: parts that start from a
//!    coarse input would otherwise refine the fans of needles that splitting their
//!    interfaces leaves, several times over.
//! 1. All triangles, cut by recursive coordinate bisection of their metric-weighted
//!    centroids along the axes, one part per [`super::Partitioning::part_vertices`]
//!    expected output vertices; before remeshing, the edges between parts are split to
//!    the metric ([`partition::split_interfaces`]), so the frozen interfaces already
//!    have the lengths the metric asks for.
//! 2. The triangles less than [`super::Partitioning::rings`] edges from a vertex shared
//!    by two parts of pass 1, cut by bisection along the diagonals (one part per
//!    [`super::Partitioning::band_part_vertices`]), so the new cuts cross the strips
//!    around the old interfaces; the rest of the mesh stays as it is, its edges with the
//!    band frozen.
//! 3. The triangles around the vertices shared by two parts of pass 2, one part per
//!    connected component: no two parts touch, so no vertex is left on an interface
//!    between parts that no pass remeshed freely.
//!
//! Invariants:
//! - Deterministic whatever the thread count: the number of parts and the cuts depend on
//!   the mesh and the metric only ([`partition`]); each part's remeshing is the serial,
//!   deterministic remesher; the glued numbering is fixed: the vertices that stay (not
//!   remeshed, or on an interface) in their old order, then each part's new vertices in
//!   part order and the remesher's order; cells likewise.
//! - Interfaces are frozen as the serial remesher freezes curves
//!   ([`RemeshOptions::frozen_curves`]): each part gets line cells with a tag no cell of
//!   the mesh uses on its edges to other parts and to the rest, and vertex cells with that
//!   tag on its shared vertices, so those vertices neither move nor go and those edges
//!   are never split; the glue finds a part's shared vertices again by their exact
//!   coordinates and checks that every one came back.
//! - Tags: each part keeps its face, curve and point tags (the serial remesher's
//!   guarantees); the line and vertex cells on interfaces are copied from the mesh
//!   unchanged.
//! - Meshes below [`super::Partitioning::above`] expected vertices, periodic runs,
//!   mixed meshes with a kept skin, and meshes with cells other than triangles, lines on
//!   triangle edges and vertex cells take the serial path unchanged.
//! - Statistics: counts are summed over parts; `per_pass` has one entry per pass of
//!   this driver; phase seconds are summed over parts (processor seconds), the driver's
//!   own partitioning in `setup` and its gluing in `output`.

use std::collections::HashMap;
use std::time::Instant;

use rayon::prelude::*;

use super::build::data_warnings;
use super::partition::{self, Axes, Flat, NONE};
use super::{
    remesh_keeping, skin_cells, PartitionedPass, PassStats, PhaseSeconds, RemeshError, RemeshEvent,
    RemeshOptions, RemeshStats, Remeshed,
};
use crate::conformity::Conformity;
use crate::metric::complexity::{exceeds, vertices_of_complexity};
use crate::metric::Sym2;
use crate::metric_field::{MetricField, METRIC};
use crate::topology::Topology;
use smartmesh_formats::{CellBlock, CellKind, TaggedMesh};

/// Most parts in a pass.
pub(super) const MAX_PARTS: usize = 1 << 14;

/// A vertex that more than one unit holds: on an interface, or outside every part.
const SHARED: u32 = NONE - 1;

/// Remeshes `mesh` part by part when it is large enough and of a kind the partitioned
/// path takes (module header); `None` when the serial path should run.
pub(super) fn remesh_partitioned(
    mesh: &TaggedMesh,
    metric: &[Sym2],
    opts: &RemeshOptions,
    progress: &mut dyn FnMut(RemeshEvent),
) -> Result<Option<Remeshed>, RemeshError> {
    let t0 = Instant::now();
    let Some(cut) = opts.partition else { return Ok(None) };
    if !opts.periodic.is_empty() || metric.len() != mesh.points.len() {
        return Ok(None);
    }
    if skin_cells(mesh).iter().any(|&k| k) {
        return Ok(None);
    }
    let Some(mut flat) = flatten(mesh, metric) else { return Ok(None) };
    // The Hausdorff bound of the whole mesh, not of each part's bounding box.
    let mut opts = opts.clone();
    opts.hausd = Some(opts.hausd_for(&flat.pts));
    let opts = &opts;
    let weight = partition::weights(&flat.pts, &flat.tris, &flat.metric);
    let estimate = vertices_of_complexity(weight.iter().sum());
    // A NaN estimate (a field no one could measure) goes to the serial path, which reports it.
    if estimate.is_nan() || estimate < cut.above as f64 {
        return Ok(None);
    }
    if let Some(limit) = opts.max_vertices {
        if exceeds(estimate, limit) {
            return Err(RemeshError::TooManyVertices { estimate, limit });
        }
    }
    super::memory::check(estimate)?;
    if partition::neighbours(&flat.tris).is_none() {
        return Ok(None);
    }
    if !lines_on_triangle_edges(&flat) {
        return Ok(None);
    }
    let initial = if opts.measure { measure(&flat) } else { None };
    let input = [flat.pts.len(), flat.tris.len()];
    let iface = unused_tag(&flat);
    let mut sub = opts.clone();
    sub.frozen_curves.push(iface);
    sub.measure = false;
    sub.partition = None;
    let mut stats = RemeshStats::starting(input, initial, data_warnings(mesh));

    // Pass 0: an input much coarser than the output is first remeshed to the metric
    // scaled down (this same driver when that is still large), so that the parts start
    // from edges a few times too long rather than from fans of needles.
    if cut.coarse_ratio > 1 && (flat.pts.len() as f64) * (cut.coarse_ratio as f64) < estimate {
        let c = cut.coarse_ratio as f64;
        let scaled: Vec<Sym2> =
            flat.metric.iter().map(|m| Sym2::new(m.a / c, m.b / c, m.c / c)).collect();
        let mut o = opts.clone();
        (o.measure, o.max_vertices) = (false, None);
        let t = Instant::now();
        let coarse = super::remesh_with_progress(mesh, &scaled, &o, &mut |_| {})?;
        let metric: Vec<Sym2> =
            coarse.metric.iter().map(|m| Sym2::new(m.a * c, m.b * c, m.c * c)).collect();
        flat = flatten(&coarse.mesh, &metric).ok_or_else(|| {
            RemeshError::Invalid("the coarse pass left a degenerate triangle".into())
        })?;
        let s = &coarse.stats;
        stats.passes += 1;
        (stats.splits, stats.collapses) = (stats.splits + s.splits, stats.collapses + s.collapses);
        (stats.swaps, stats.moves) = (stats.swaps + s.swaps, stats.moves + s.moves);
        stats.per_pass.push(PassStats {
            splits: s.splits,
            collapses: s.collapses,
            swaps: s.swaps,
            moves: s.moves,
            triangles: s.output[1],
        });
        add_seconds(&mut stats.seconds, &s.seconds);
        if s.partitioned.is_empty() {
            let wall = t.elapsed().as_secs_f64();
            stats.partitioned.push(PartitionedPass {
                driver_seconds: wall,
                seconds: wall,
                ..PartitionedPass::default()
            });
        } else {
            stats.partitioned.extend(s.partitioned.iter().cloned());
        }
        progress(RemeshEvent::Pass { pass: 0, of: 3, triangles: s.output[1] });
    }
    let t1 = Instant::now();
    let weight = partition::weights(&flat.pts, &flat.tris, &flat.metric);
    let Some(nb) = partition::neighbours(&flat.tris) else {
        return Err(RemeshError::Invalid("an edge of the coarse pass has three triangles".into()));
    };

    // Pass 1: everything, cut along the axes; the cuts split to the metric first.
    let parts = part_count(estimate, cut.part_vertices).max(2);
    let mut part = vec![NONE; flat.tris.len()];
    let centroid = centroids(&flat);
    let mut items: Vec<u32> = (0..flat.tris.len() as u32).collect();
    partition::bisect(&centroid, &weight, &mut items, parts, Axes::Straight, 0, &mut part);
    drop((centroid, weight, items));
    if let Some((split, split_part)) =
        partition::split_interfaces(&flat, &part, &nb, opts.split_above)
    {
        flat = split;
        part = split_part;
    }
    stats.seconds.setup += t0.elapsed().as_secs_f64();
    let setup = t1.elapsed().as_secs_f64();
    let adjacency = Adjacency::of(&flat)
        .ok_or_else(|| RemeshError::Invalid("an edge has three triangles".into()))?;
    let (mut flat, mut seeds) = run_pass(&flat, &part, parts, &adjacency, &sub, iface, &mut stats)?;
    drop(adjacency);
    add_driver(&mut stats, setup);
    progress(RemeshEvent::Pass { pass: 1, of: 3, triangles: flat.tris.len() });

    for pass in 2..=3 {
        if !seeds.iter().any(|&s| s) {
            break;
        }
        let t = Instant::now();
        let Some(adjacency) = Adjacency::of(&flat) else {
            return Err(RemeshError::Invalid(
                "an edge of the glued parts has three triangles".into(),
            ));
        };
        let selected = partition::band(&flat.tris, &adjacency.around, &seeds, cut.rings);
        let (part, parts) = if pass == 2 {
            let weight = partition::weights(&flat.pts, &flat.tris, &flat.metric);
            let in_band: f64 = (0..weight.len()).filter(|&t| selected[t]).map(|t| weight[t]).sum();
            let parts = part_count(vertices_of_complexity(in_band), cut.band_part_vertices);
            let centroid = centroids(&flat);
            let mut items: Vec<u32> =
                (0..flat.tris.len() as u32).filter(|&t| selected[t as usize]).collect();
            let mut part = vec![NONE; flat.tris.len()];
            partition::bisect(&centroid, &weight, &mut items, parts, Axes::Diagonal, 0, &mut part);
            (part, parts)
        } else {
            partition::components(&selected, &adjacency.nb)
        };
        drop(selected);
        let setup = t.elapsed().as_secs_f64();
        stats.seconds.setup += setup;
        let (next, next_seeds) =
            run_pass(&flat, &part, parts, &adjacency, &sub, iface, &mut stats)?;
        add_driver(&mut stats, setup);
        flat = next;
        seeds = next_seeds;
        progress(RemeshEvent::Pass { pass, of: 3, triangles: flat.tris.len() });
    }

    let t = Instant::now();
    let out = unflatten(mesh, &flat);
    stats.output = [flat.pts.len(), flat.tris.len()];
    if opts.measure {
        stats.conformity = measure(&flat);
    }
    stats.seconds.output += t.elapsed().as_secs_f64();
    Ok(Some(Remeshed { mesh: out, metric: flat.metric, stats }))
}

/// Adds `seconds` of the driver's own work to the last pass's times.
fn add_driver(stats: &mut RemeshStats, seconds: f64) {
    if let Some(p) = stats.partitioned.last_mut() {
        p.driver_seconds += seconds;
        p.seconds += seconds;
    }
}

/// One part per `per` expected vertices, at least one.
fn part_count(expected: f64, per: usize) -> usize {
    let k = (expected / per.max(1) as f64).ceil();
    if k.is_finite() && k >= 1.0 {
        (k as usize).min(MAX_PARTS)
    } else {
        1
    }
}

fn centroids(f: &Flat) -> Vec<[f64; 2]> {
    f.tris
        .par_iter()
        .map(|t| {
            let p = t.map(|v| f.pts[v as usize]);
            [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0]
        })
        .collect()
}

fn measure(f: &Flat) -> Option<Conformity> {
    let tris: Vec<[usize; 3]> = f.tris.iter().map(|t| t.map(|v| v as usize)).collect();
    Conformity::of(&f.pts, &tris, &f.metric)
}

/// The triangles (made counter-clockwise), lines and vertex cells of `mesh`; `None` when
/// it has other cells, a degenerate triangle or a point that is not finite (the serial
/// path reports those).
fn flatten(mesh: &TaggedMesh, metric: &[Sym2]) -> Option<Flat> {
    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    if pts.iter().any(|p| !(p[0].is_finite() && p[1].is_finite())) {
        return None;
    }
    let mut f = Flat { metric: metric.to_vec(), ..Flat::default() };
    let n = pts.len() as u64;
    for (kind, nodes, p, g) in mesh.cells() {
        if nodes.iter().any(|&v| v as u64 >= n) {
            return None;
        }
        match kind {
            CellKind::Triangle => {
                let t = [nodes[0], nodes[1], nodes[2]];
                let o =
                    super::work::orient(pts[t[0] as usize], pts[t[1] as usize], pts[t[2] as usize]);
                if o == 0.0 || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                    return None;
                }
                f.tris.push(if o > 0.0 { t } else { [t[0], t[2], t[1]] });
                f.tri_tags.push((p, g));
            }
            CellKind::Line if nodes[0] != nodes[1] => f.lines.push(([nodes[0], nodes[1]], (p, g))),
            CellKind::Vertex => f.vertex_cells.push((nodes[0], (p, g))),
            _ => return None,
        }
    }
    f.pts = pts;
    Some(f)
}

/// Whether every line cell lies on a triangle edge.
fn lines_on_triangle_edges(f: &Flat) -> bool {
    let (start, list) = partition::vertex_triangles(f.pts.len(), &f.tris);
    f.lines.iter().all(|&([a, b], _)| {
        list[start[a as usize]..start[a as usize + 1]]
            .iter()
            .any(|&t| f.tris[t as usize].contains(&b))
    })
}

/// A tag no cell of `f` uses.
fn unused_tag(f: &Flat) -> i32 {
    let tags = f
        .tri_tags
        .iter()
        .chain(f.lines.iter().map(|l| &l.1))
        .chain(f.vertex_cells.iter().map(|c| &c.1));
    let most = tags.fold(0i32, |m, &(p, g)| m.max(p).max(g));
    most.saturating_add(1).max(1)
}

/// The mesh `f` with `input`'s tag names and entities, its cells in blocks (vertices,
/// lines, triangles) as the serial remesher writes them, and its metric as point data.
fn unflatten(input: &TaggedMesh, f: &Flat) -> TaggedMesh {
    let mut mesh = TaggedMesh::new();
    mesh.coordinate_dim = input.coordinate_dim;
    mesh.tag_names = input.tag_names.clone();
    mesh.entities = input.entities.clone();
    mesh.points = f.pts.iter().map(|p| [p[0], p[1], 0.0]).collect();
    if !f.vertex_cells.is_empty() {
        let mut b = CellBlock::new(CellKind::Vertex);
        for &(v, (p, g)) in &f.vertex_cells {
            b.push(&[v], p, g);
        }
        mesh.blocks.push(b);
    }
    if !f.lines.is_empty() {
        let mut b = CellBlock::new(CellKind::Line);
        for &(l, (p, g)) in &f.lines {
            b.push(&l, p, g);
        }
        mesh.blocks.push(b);
    }
    let mut b = CellBlock::new(CellKind::Triangle);
    for (t, &(p, g)) in f.tris.iter().zip(&f.tri_tags) {
        b.push(t, p, g);
    }
    mesh.blocks.push(b);
    let field = MetricField::new(f.metric.clone(), "the remeshed field");
    mesh.point_data.insert(METRIC.into(), field.to_array());
    mesh
}

/// One part's remeshing: its cells and metric, and for each of its vertices the glued
/// vertex it is ([`NONE`]: a new one).
struct PartOut {
    flat: Flat,
    glued: Vec<u32>,
    stats: RemeshStats,
}

/// Who touches whom in a [`Flat`]: the neighbours of each triangle
/// ([`partition::neighbours`]) and the triangles around each vertex
/// ([`partition::vertex_triangles`]), built once per pass.
struct Adjacency {
    nb: Vec<[u32; 3]>,
    around: (Vec<usize>, Vec<u32>),
}

impl Adjacency {
    /// `None` when an edge has more than two triangles.
    fn of(f: &Flat) -> Option<Adjacency> {
        let nb = partition::neighbours(&f.tris)?;
        Some(Adjacency { nb, around: partition::vertex_triangles(f.pts.len(), &f.tris) })
    }
}

/// The exact coordinates of a point, as a key.
fn bits(p: [f64; 2]) -> (u64, u64) {
    (p[0].to_bits(), p[1].to_bits())
}

/// Remeshes the triangles of `f` that `part` puts in parts `0..parts` (each part apart,
/// in parallel, its interface frozen) and glues the result. Returns the glued mesh and,
/// per glued vertex, whether two parts shared it.
fn run_pass(
    f: &Flat,
    part: &[u32],
    parts: usize,
    adjacency: &Adjacency,
    opts: &RemeshOptions,
    iface: i32,
    stats: &mut RemeshStats,
) -> Result<(Flat, Vec<bool>), RemeshError> {
    let pass_start = Instant::now();
    let t = Instant::now();
    let (start, list) = &adjacency.around;
    let around = |v: u32| &list[start[v as usize]..start[v as usize + 1]];
    // The unit of each vertex: a part that holds all its triangles, else SHARED; and
    // whether two parts hold it (a seed of the next pass's band).
    let (owner, between): (Vec<u32>, Vec<bool>) = (0..f.pts.len() as u32)
        .into_par_iter()
        .map(|v| {
            let mut it = around(v).iter().map(|&t| part[t as usize]);
            let Some(first) = it.next() else { return (SHARED, false) };
            let (mut alike, mut held, mut two) = (true, (first != NONE).then_some(first), false);
            for p in it {
                alike &= p == first;
                match held {
                    _ if p == NONE => {}
                    None => held = Some(p),
                    Some(h) => two |= h != p,
                }
            }
            (if alike && first != NONE { first } else { SHARED }, two)
        })
        .unzip();
    let line_owner: Vec<u32> = f
        .lines
        .par_iter()
        .map(|&([a, b], _)| {
            let mut ps = around(a)
                .iter()
                .filter(|&&t| f.tris[t as usize].contains(&b))
                .map(|&t| part[t as usize]);
            let first = ps.next().unwrap_or(NONE);
            if first != NONE && ps.all(|p| p == first) {
                first
            } else {
                SHARED
            }
        })
        .collect();
    let mut members: Vec<Vec<u32>> = vec![Vec::new(); parts];
    for (t, &p) in part.iter().enumerate() {
        if p != NONE {
            members[p as usize].push(t as u32);
        }
    }
    stats.seconds.setup += t.elapsed().as_secs_f64();

    let in_parts = Instant::now();
    let outs: Vec<(PartOut, f64)> = members
        .par_iter()
        .enumerate()
        .map(|(p, tris)| {
            let t = Instant::now();
            remesh_part(f, tris, p as u32, part, &adjacency.nb, &owner, &line_owner, opts, iface)
                .map(|o| (o, t.elapsed().as_secs_f64()))
        })
        .collect::<Result<_, _>>()?;
    let in_parts = in_parts.elapsed().as_secs_f64();
    let part_seconds: Vec<f64> = outs.iter().map(|o| o.1).collect();

    let t = Instant::now();
    // Glue: the vertices that stay, in their old order, then each part's new ones.
    let mut g = Flat::default();
    let mut new_id = vec![NONE; f.pts.len()];
    let mut seeds = Vec::new();
    for v in 0..f.pts.len() {
        if owner[v] == SHARED {
            new_id[v] = g.pts.len() as u32;
            g.pts.push(f.pts[v]);
            g.metric.push(f.metric[v]);
            seeds.push(between[v]);
        }
    }
    for (t, &p) in part.iter().enumerate() {
        if p == NONE {
            g.tris.push(f.tris[t].map(|v| new_id[v as usize]));
            g.tri_tags.push(f.tri_tags[t]);
        }
    }
    for (l, &o) in f.lines.iter().zip(&line_owner) {
        if o == SHARED {
            g.lines.push((l.0.map(|v| new_id[v as usize]), l.1));
        }
    }
    for &(v, tags) in &f.vertex_cells {
        if owner[v as usize] == SHARED {
            g.vertex_cells.push((new_id[v as usize], tags));
        }
    }
    let mut per = PassStats::default();
    for (out, _) in outs {
        let id: Vec<u32> = out
            .glued
            .iter()
            .zip(&out.flat.pts)
            .zip(&out.flat.metric)
            .map(|((&glued, &pt), &m)| {
                if glued != NONE {
                    return new_id[glued as usize];
                }
                g.pts.push(pt);
                g.metric.push(m);
                seeds.push(false);
                g.pts.len() as u32 - 1
            })
            .collect();
        g.tris.extend(out.flat.tris.iter().map(|t| t.map(|v| id[v as usize])));
        g.tri_tags.extend_from_slice(&out.flat.tri_tags);
        g.lines.extend(out.flat.lines.iter().map(|&(l, tags)| (l.map(|v| id[v as usize]), tags)));
        g.vertex_cells
            .extend(out.flat.vertex_cells.iter().map(|&(v, tags)| (id[v as usize], tags)));
        let s = &out.stats;
        per.splits += s.splits;
        per.collapses += s.collapses;
        per.swaps += s.swaps;
        per.moves += s.moves;
        add_seconds(&mut stats.seconds, &s.seconds);
        for w in &s.warnings {
            if !stats.warnings.contains(w) {
                stats.warnings.push(w.clone());
            }
        }
    }
    per.triangles = g.tris.len();
    stats.passes += 1;
    stats.splits += per.splits;
    stats.collapses += per.collapses;
    stats.swaps += per.swaps;
    stats.moves += per.moves;
    stats.per_pass.push(per);
    stats.seconds.output += t.elapsed().as_secs_f64();
    let seconds = pass_start.elapsed().as_secs_f64();
    stats.partitioned.push(PartitionedPass {
        part_seconds,
        driver_seconds: seconds - in_parts,
        seconds,
    });
    Ok((g, seeds))
}

fn add_seconds(to: &mut PhaseSeconds, s: &PhaseSeconds) {
    to.setup += s.setup;
    to.split += s.split;
    to.collapse += s.collapse;
    to.swap += s.swap;
    to.smooth += s.smooth;
    to.output += s.output;
}

/// Remeshes part `p` (the triangles `tris` of `f`) with its interface frozen.
#[allow(clippy::too_many_arguments)]
fn remesh_part(
    f: &Flat,
    tris: &[u32],
    p: u32,
    part: &[u32],
    nb: &[[u32; 3]],
    owner: &[u32],
    line_owner: &[u32],
    opts: &RemeshOptions,
    iface: i32,
) -> Result<PartOut, RemeshError> {
    let mut verts: Vec<u32> = tris.iter().flat_map(|&t| f.tris[t as usize]).collect();
    verts.sort_unstable();
    verts.dedup();
    let local = |v: u32| verts.binary_search(&v).map(|i| i as u32).unwrap_or(NONE);
    let mut sub = TaggedMesh::new();
    sub.points = verts.iter().map(|&v| [f.pts[v as usize][0], f.pts[v as usize][1], 0.0]).collect();
    let metric: Vec<Sym2> = verts.iter().map(|&v| f.metric[v as usize]).collect();
    let mut vb = CellBlock::new(CellKind::Vertex);
    let mut frozen: HashMap<(u64, u64), u32> = HashMap::new();
    for (i, &v) in verts.iter().enumerate() {
        if owner[v as usize] == SHARED {
            vb.push(&[i as u32], iface, iface);
            frozen.insert(bits(f.pts[v as usize]), v);
        }
    }
    for &(v, (ph, g)) in &f.vertex_cells {
        if owner[v as usize] == p {
            vb.push(&[local(v)], ph, g);
        }
    }
    let mut lb = CellBlock::new(CellKind::Line);
    for (&(l, (ph, g)), &o) in f.lines.iter().zip(line_owner) {
        if o == p {
            lb.push(&l.map(local), ph, g);
        }
    }
    let mut tb = CellBlock::new(CellKind::Triangle);
    for &t in tris {
        let v = f.tris[t as usize];
        for k in 0..3 {
            let n = nb[t as usize][k];
            if n != NONE && part[n as usize] != p {
                lb.push(&[local(v[k]), local(v[(k + 1) % 3])], iface, iface);
            }
        }
        let (ph, g) = f.tri_tags[t as usize];
        tb.push(&v.map(local), ph, g);
    }
    sub.blocks = vec![vb, lb, tb];
    let topology = Topology::from_mesh(&sub);
    let keep = vec![false; tris.len()];
    let out = remesh_keeping(&sub, &topology, &metric, opts, &keep, &mut |_| {})?;
    drop((sub, topology, metric));
    let mut flat = Flat {
        pts: out.mesh.points.iter().map(|q| [q[0], q[1]]).collect(),
        metric: out.metric,
        ..Flat::default()
    };
    for (kind, nodes, ph, g) in out.mesh.cells() {
        match kind {
            CellKind::Triangle => {
                flat.tris.push([nodes[0], nodes[1], nodes[2]]);
                flat.tri_tags.push((ph, g));
            }
            CellKind::Line if (ph, g) != (iface, iface) => {
                flat.lines.push(([nodes[0], nodes[1]], (ph, g)))
            }
            CellKind::Vertex if (ph, g) != (iface, iface) => {
                flat.vertex_cells.push((nodes[0], (ph, g)))
            }
            _ => {}
        }
    }
    let glued: Vec<u32> =
        flat.pts.iter().map(|&q| frozen.get(&bits(q)).copied().unwrap_or(NONE)).collect();
    let found = glued.iter().filter(|&&v| v != NONE).count();
    if found != frozen.len() {
        return Err(RemeshError::Invalid(format!(
            "part {p}: {found} of its {} interface vertices came back",
            frozen.len()
        )));
    }
    Ok(PartOut { flat, glued, stats: out.stats })
}
