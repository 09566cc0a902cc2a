//! The native 2D anisotropic remesher: adapts a tagged triangle mesh to a metric field
//! by local operations, every one measured in the metric (thesis 3.5, the role OORT
//! plays in the loop of 7.3.2).
//!
//! Each pass splits the edges longer than √2 in the metric (`split`), flipping
//! diagonals (`swap`) after every split sweep so that the next sweep cuts triangles
//! shaped by the metric rather than the fans left by the previous cuts (on a coarse
//! input with a strongly anisotropic field, splitting without the flips makes about six
//! times the final vertex count, which the collapses then remove), collapses the
//! edges shorter than 1/√2 (`collapse`), flips diagonals to raise the worse metric
//! quality of each pair (`swap`), moves vertices toward a metric-equilateral place
//! (`smooth`), then collapses and flips once more where smoothing left short edges; the
//! passes stop when splits and collapses touch fewer than one triangle in
//! [`RemeshOptions::settle_ratio`], or after [`RemeshOptions::max_passes`], and a last
//! smoothing and swap polish the result.
//!
//! Each operator is a pair, as MMG's `chkcol`/`colver`: a `check` that only reads the
//! working mesh (`work`) and returns a plan or nothing, and an `apply` that carries the
//! plan out through the working mesh's few edits, which keep its adjacency exact. The
//! tuning of the operators (quality floor, sweep counts, gains, the settling rule) is in
//! [`RemeshOptions`].
//!
//! Before any work the expected output size, the metric's complexity
//! ([`crate::metric::complexity`]), is
//! compared with [`RemeshOptions::max_vertices`]: a metric asking for 10¹² vertices is
//! refused in milliseconds instead of filling the memory.
//!
//! What it guarantees, by construction and checked in the tests:
//! - every triangle strictly counter-clockwise (Shewchuk's exact orientation predicate
//!   guards every operation), so never an inverted or zero-area one;
//! - boundary and interface vertices only slide along their own piece of the input curve
//!   (`boundary`); corners and topological points never move nor vanish; no new
//!   boundary edge sweeps across another curve;
//! - every triangle keeps the face tags of the input triangle it came from, every
//!   constrained edge its curve's line tags; vertex cells stay;
//! - the metric at every new or moved vertex is interpolated from the *input* field
//!   ([`crate::metric_field::Interpolator`]), Log-Euclidean, so it stays SPD and does not drift;
//! - a skin of quads (a mixed mesh from `layer`), or any surface cells the caller keeps
//!   ([`remesh_keeping`]), stays frozen: its vertices neither move nor go, its edges
//!   are never split, its cells and their tags are written back unchanged, and the
//!   triangles are remeshed around it; the result is checked as a mixed mesh;
//! - deterministic: single-threaded sweeps in index order, no hash-order iteration;
//!   a mesh expected above [`RemeshOptions::partition`] vertices is remeshed part
//!   by part on every core (`parallel`), with the same output whatever the thread count.

mod band;
mod boundary;
mod build;
mod collapse;
mod error;
pub mod memory;
mod options;
mod output;
mod parallel;
mod partition;
mod radix;
mod smooth;
mod split;
mod stats;
mod swap;
mod work;

use std::time::Instant;

use crate::conformity::Conformity;
use crate::metric::{complexity, Sym2};
use crate::metric_field::Interpolator;
use crate::topology::Topology;
use smartmesh_formats::TaggedMesh;

pub use error::RemeshError;
pub use options::{
    BoundaryMode, Partitioning, RemeshOptions, DEFAULT_MAX_VERTICES, DEFAULT_PARTITION_ABOVE,
    DEFAULT_RELATIVE_HAUSD,
};
pub use stats::{PartitionedPass, PassStats, PhaseSeconds, RemeshCounts, RemeshStats};

/// The remeshed mesh, its metric and what was done.
#[derive(Debug, Clone, PartialEq)]
pub struct Remeshed {
    /// Triangles with their face tags, line cells with their curve tags on boundaries and
    /// interfaces, the input's vertex cells, tag names and entities, and point data
    /// `metric` (9 components).
    pub mesh: TaggedMesh,
    /// The metric at every output vertex.
    pub metric: Vec<Sym2>,
    /// What was done.
    pub stats: RemeshStats,
}

/// Progress of a run, for a progress bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RemeshEvent {
    /// A pass ended.
    Pass {
        /// Its number, from 1.
        pass: usize,
        /// The most passes there will be.
        of: usize,
        /// Triangles now.
        triangles: usize,
    },
}

/// The triangle cells of `mesh`.
fn triangles(mesh: &TaggedMesh) -> Vec<[usize; 3]> {
    mesh.cells()
        .filter(|c| c.0 == smartmesh_formats::CellKind::Triangle)
        .map(|c| [c.1[0] as usize, c.1[1] as usize, c.1[2] as usize])
        .collect()
}

fn collapse_phase(
    w: &mut work::Work,
    opts: &RemeshOptions,
    lmax_after: f64,
    ps: &mut PassStats,
    secs: &mut PhaseSeconds,
) {
    let t = Instant::now();
    ps.collapses += collapse::collapse_sweeps(w, lmax_after, opts);
    secs.collapse += t.elapsed().as_secs_f64();
}

fn swap_phase(
    w: &mut work::Work,
    opts: &RemeshOptions,
    ps: &mut PassStats,
    secs: &mut PhaseSeconds,
    everything: bool,
) {
    let t = Instant::now();
    ps.swaps += swap::swap_sweeps(w, opts, everything).0;
    secs.swap += t.elapsed().as_secs_f64();
}

fn smooth_phase(w: &mut work::Work, opts: &RemeshOptions, secs: &mut PhaseSeconds) -> usize {
    let t = Instant::now();
    let mut moves = 0;
    for _ in 0..opts.smooth_sweeps {
        moves += smooth::smooth_sweep(w, opts);
    }
    secs.smooth += t.elapsed().as_secs_f64();
    moves
}

/// Remeshes `mesh` to `metric` (one SPD tensor per point; [`crate::conformity::metric_field`]
/// reads and checks one from point data).
///
/// ```
/// use std::path::Path;
/// use smartmesh::formats::{read_path, CellKind};
/// use smartmesh::{MetricField, METRIC};
/// use smartmesh::remesh::{remesh, RemeshOptions};
///
/// let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
/// let mesh = read_path(&dir.join("cylinder.msh"), None)?;
/// let text = std::fs::read_to_string(dir.join("cylinder.toml"))?;
/// let recipe = smartmesh::recipe::serde_io::read_toml(&text, &dir.join("cylinder.toml"))?;
/// let sized = smartmesh::recipe::size_mesh(&mesh, &recipe, &mut |_| {})?;
/// let metric = MetricField::from_sizes(&sized.field.tensors, "the recipe's field");
/// let out = remesh(&mesh, metric.tensors(), &RemeshOptions::default())?;
/// // Refined where the recipe asks, tags kept, the field carried as point data.
/// assert!(out.mesh.num_cells_of(CellKind::Triangle) > mesh.num_cells_of(CellKind::Triangle));
/// assert_eq!(out.mesh.tag_name(2, 10), Some("Fluid"));
/// assert_eq!(out.mesh.point_data[METRIC].len(), out.mesh.points.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn remesh(
    mesh: &TaggedMesh,
    metric: &[Sym2],
    opts: &RemeshOptions,
) -> Result<Remeshed, RemeshError> {
    remesh_with_progress(mesh, metric, opts, &mut |_| {})
}

/// [`remesh`], reporting each pass to `progress`.
pub fn remesh_with_progress(
    mesh: &TaggedMesh,
    metric: &[Sym2],
    opts: &RemeshOptions,
    progress: &mut dyn FnMut(RemeshEvent),
) -> Result<Remeshed, RemeshError> {
    remesh_with_topology(mesh, &Topology::from_mesh(mesh), metric, opts, progress)
}

/// [`remesh_with_progress`] for a caller that has `mesh`'s [`Topology`] already (the
/// adaptation loop builds it once per mesh, for the sizing and the remeshing). The skin
/// of a mixed mesh ([`skin_cells`]) is kept frozen.
pub fn remesh_with_topology(
    mesh: &TaggedMesh,
    topology: &Topology,
    metric: &[Sym2],
    opts: &RemeshOptions,
    progress: &mut dyn FnMut(RemeshEvent),
) -> Result<Remeshed, RemeshError> {
    if opts.periodic.is_empty() {
        if let Some(out) = parallel::remesh_partitioned(mesh, metric, opts, progress)? {
            return Ok(out);
        }
        return remesh_keeping(mesh, topology, metric, opts, &skin_cells(mesh), progress);
    }
    // Periodic sides: coarsened and split alike on both sides to the metric, then frozen.
    let (coarse, metric) = crate::periodic::coarsen_sides(mesh, metric, &opts.periodic);
    let (refined, metric) = crate::periodic::refine_sides(&coarse, &metric, &opts.periodic);
    let topology = Topology::from_mesh(&refined);
    let mut opts = opts.clone();
    for pair in &opts.periodic {
        if let Ok(m) = crate::periodic::check(&refined.points, &topology, pair) {
            opts.frozen_curves.extend(m.curve_tags);
        }
    }
    remesh_keeping(&refined, &topology, &metric, &opts, &skin_cells(&refined), progress)
}

/// The skin of a mixed mesh, by surface cell in [`TaggedMesh::cells`] order: every
/// quadrangle, and every triangle whose three corners are corners of quadrangles (the
/// fan triangles at a skin's convex corners, when the skin has two layers or more).
/// All `false` on a triangle mesh.
pub fn skin_cells(mesh: &TaggedMesh) -> Vec<bool> {
    use smartmesh_formats::CellKind;
    let mut on_quad = vec![false; mesh.points.len()];
    for (kind, nodes, _, _) in mesh.cells() {
        if kind == CellKind::Quad {
            nodes.iter().for_each(|&v| on_quad[v as usize] = true);
        }
    }
    mesh.cells()
        .filter(|c| c.0.dim() == 2)
        .map(|(kind, nodes, _, _)| match kind {
            CellKind::Quad => true,
            CellKind::Triangle => nodes.iter().all(|&v| on_quad[v as usize]),
            _ => false,
        })
        .collect()
}

/// Whether the native remesher can take `mesh` as it is: a mesh with quads must be a
/// valid mixed mesh with triangles left to remesh (the quads, and the triangles of a
/// skin, stay frozen). What [`remesh_keeping`] checks first, for a caller that must
/// refuse before any work (`adapt`, which would otherwise fail at its first remeshing).
pub fn check_quads(mesh: &TaggedMesh) -> Result<(), RemeshError> {
    if !mesh.cells().any(|c| c.0 == smartmesh_formats::CellKind::Quad) {
        return Ok(());
    }
    let keep = skin_cells(mesh);
    if keep.iter().all(|&k| k) {
        return Err(RemeshError::AllKept);
    }
    let v = crate::validity::check_mesh(mesh);
    if !v.is_valid() {
        return Err(RemeshError::InvalidMixed(v.problems().join("; ")));
    }
    Ok(())
}

/// [`remesh_with_topology`] keeping the surface cells that `keep` flags (in
/// [`TaggedMesh::cells`] order) as they are: their vertices neither move nor go, their
/// edges are constraints that are never split, and they are written back unchanged
/// (renumbered) after the remeshed triangles. An input with kept cells must pass, and
/// the result is checked as a
/// mixed mesh ([`crate::check_mesh`]: positive cells, no overlap, no
/// hanging vertex) before it is returned.
pub fn remesh_keeping(
    mesh: &TaggedMesh,
    topology: &Topology,
    metric: &[Sym2],
    opts: &RemeshOptions,
    keep: &[bool],
    progress: &mut dyn FnMut(RemeshEvent),
) -> Result<Remeshed, RemeshError> {
    let t0 = Instant::now();
    // A mixed input must already be valid: otherwise a bad result would be blamed on
    // the remesher rather than on the file.
    if keep.iter().any(|&k| k) && mesh.cells().any(|c| c.0 == smartmesh_formats::CellKind::Quad) {
        let v = crate::validity::check_mesh(mesh);
        if !v.is_valid() {
            return Err(RemeshError::InvalidMixed(v.problems().join("; ")));
        }
    }
    let st = build::start(mesh, topology, metric, opts, keep)?;
    let input_tris: Vec<[usize; 3]> = st.tris.iter().map(|t| t.map(|v| v as usize)).collect();
    let estimate = complexity::expected_vertices(&st.pts, &input_tris, metric);
    if let Some(limit) = opts.max_vertices {
        if complexity::exceeds(estimate, limit) {
            return Err(RemeshError::TooManyVertices { estimate, limit });
        }
    }
    if estimate.is_finite() {
        memory::check(estimate)?;
    }
    // Past this many vertices the splits stop: twice the limit, and never near the end
    // of the 32-bit indices.
    let cap = opts
        .max_vertices
        .map_or(u32::MAX as usize / 2, |l| l.saturating_mul(2).min(u32::MAX as usize / 2));
    let bg = Interpolator::new(&st.pts, &input_tris, metric);
    let initial = if opts.measure { Conformity::of(&st.pts, &input_tris, metric) } else { None };
    drop(input_tris);
    let bd = boundary::Boundary::new(st.pieces);
    let hausd = opts.hausd_for(&st.pts);
    #[cfg(test)]
    let input_points = st.pts.clone();
    let (n, ntri) = (st.pts.len(), st.tris.len());
    let parts = work::Parts {
        pts: st.pts,
        met: metric.to_vec(),
        role: st.role,
        tris: st.tris,
        face: st.face,
        cons: st.cons,
    };
    let context = work::Context { background: &bg, boundary: &bd, mode: opts.boundary, hausd };
    let mut w = work::Work::new(parts, context);
    // Room for the expected output at once (no doubling slack nor copies as the mesh
    // grows): the estimate and a margin, within the split cap.
    let room = (1.25 * estimate).min(cap as f64) as usize;
    w.reserve(room, 2 * room);
    let mut stats = RemeshStats::starting([n, ntri], initial, st.warnings);
    stats.seconds.setup = t0.elapsed().as_secs_f64();
    // Collapses may not create edges longer than this: the split bound, so that a
    // collapse never hands the next split sweep work.
    let lmax_after = opts.split_above;
    // When the previous split phase started: a later one looks only around what changed.
    let mut split_since: Option<u64> = None;
    for pass in 0..opts.max_passes {
        let mut ps = PassStats::default();
        let t = Instant::now();
        // Flips between the split sweeps, timed with the splits.
        let mut flips = 0;
        let mut between = |w: &mut work::Work| {
            let (k, moved) = swap::swap_sweeps(w, opts, false);
            flips += k;
            moved
        };
        let started = w.now();
        let split = split::split_sweeps(&mut w, opts.split_above, cap, split_since, &mut between);
        split_since = Some(started);
        ps.splits += split.map_err(|_| RemeshError::Grew {
            vertices: w.num_vertices(),
            limit: opts.max_vertices.unwrap_or(cap),
            estimate,
        })?;
        ps.swaps += flips;
        stats.seconds.split += t.elapsed().as_secs_f64();
        collapse_phase(&mut w, opts, lmax_after, &mut ps, &mut stats.seconds);
        swap_phase(&mut w, opts, &mut ps, &mut stats.seconds, pass == 0);
        ps.moves += smooth_phase(&mut w, opts, &mut stats.seconds);
        // Smoothing moves lengths out of the band again: a last collapse and swap.
        collapse_phase(&mut w, opts, lmax_after, &mut ps, &mut stats.seconds);
        swap_phase(&mut w, opts, &mut ps, &mut stats.seconds, false);
        ps.triangles = w.live_triangles();
        stats.passes = pass + 1;
        stats.splits += ps.splits;
        stats.collapses += ps.collapses;
        stats.swaps += ps.swaps;
        stats.moves += ps.moves;
        // Settled when the topology barely changes any more; what is left is smoothing's
        // business, which the pass just did.
        let settled = (ps.splits + ps.collapses).saturating_mul(opts.settle_ratio) <= ps.triangles;
        progress(RemeshEvent::Pass {
            pass: pass + 1,
            of: opts.max_passes,
            triangles: ps.triangles,
        });
        stats.per_pass.push(ps);
        if settled {
            break;
        }
    }
    // A last polish: the final collapses and swaps left some balls unsmoothed.
    if stats.passes > 0 {
        let moves = smooth_phase(&mut w, opts, &mut stats.seconds);
        let mut ps = PassStats { moves, ..PassStats::default() };
        swap_phase(&mut w, opts, &mut ps, &mut stats.seconds, false);
        stats.moves += ps.moves;
        stats.swaps += ps.swaps;
        if let Some(last) = stats.per_pass.last_mut() {
            last.moves += ps.moves;
            last.swaps += ps.swaps;
        }
    }
    debug_assert!(w.all_positive());
    #[cfg(test)]
    if let Err(e) = w.consistency(&input_points) {
        panic!("remesher invariant broken: {e}");
    }
    let t = Instant::now();
    let (out, out_metric) =
        output::assemble(mesh, &w, &st.faces, &st.vertex_cells, &st.kept, &st.kept_lines);
    // The working mesh is no longer needed: its memory goes before the measuring.
    drop(w);
    if !st.kept.is_empty() {
        let v = crate::validity::check_mesh(&out);
        if !v.is_valid() {
            return Err(RemeshError::Invalid(v.problems().join("; ")));
        }
    }
    stats.output = [out.points.len(), out.num_cells_of(smartmesh_formats::CellKind::Triangle)];
    if opts.measure {
        let out_pts: Vec<[f64; 2]> = out.points.iter().map(|p| [p[0], p[1]]).collect();
        stats.conformity = Conformity::of(&out_pts, &triangles(&out), &out_metric);
    }
    stats.seconds.output = t.elapsed().as_secs_f64();
    Ok(Remeshed { mesh: out, metric: out_metric, stats })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metric::SizeTensor;
    use smartmesh_formats::{CellBlock, CellKind};

    /// A jittered n×n grid on [0,1]² (deterministic jitter), boundary tagged 1..4.
    fn grid(n: usize) -> TaggedMesh {
        let mut m = TaggedMesh::new();
        let mut s = 7u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for j in 0..=n {
            for i in 0..=n {
                let inner = i > 0 && i < n && j > 0 && j < n;
                let (dx, dy) = if inner {
                    (0.3 * rnd() / n as f64, 0.3 * rnd() / n as f64)
                } else {
                    (0.0, 0.0)
                };
                m.points.push([i as f64 / n as f64 + dx, j as f64 / n as f64 + dy, 0.0]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut t = CellBlock::new(CellKind::Triangle);
        let mut l = CellBlock::new(CellKind::Line);
        for j in 0..n {
            for i in 0..n {
                t.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)], 1, 1);
                t.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)], 1, 1);
            }
        }
        for k in 0..n {
            l.push(&[id(k, 0), id(k + 1, 0)], 1, 1);
            l.push(&[id(n, k), id(n, k + 1)], 2, 2);
            l.push(&[id(k + 1, n), id(k, n)], 3, 3);
            l.push(&[id(0, k + 1), id(0, k)], 4, 4);
        }
        m.blocks = vec![l, t];
        m
    }

    /// Every invariant checked by brute force after the run (the check runs inside
    /// `remesh` in test builds), on fields that refine, coarsen and rotate.
    #[test]
    fn invariants_hold_on_rotating_refining_and_coarsening_fields() {
        let mesh = grid(12);
        let fields: [&dyn Fn(f64, f64) -> SizeTensor; 3] = [
            &|x, y| SizeTensor::from_angle(6.0 * (x + y), 0.08, 0.01 + 0.02 * x).unwrap(),
            &|_, _| SizeTensor::isotropic(0.4),
            &|x, y| {
                SizeTensor::from_angle(
                    0.0,
                    0.05,
                    0.003 + 0.1 * (y - 0.5 - 0.2 * (6.0 * x).sin()).abs(),
                )
                .unwrap()
            },
        ];
        for (k, f) in fields.iter().enumerate() {
            let metric: Vec<Sym2> = mesh.points.iter().map(|p| f(p[0], p[1]).to_metric()).collect();
            for mode in [BoundaryMode::Polyline, BoundaryMode::Smooth] {
                let out = remesh(
                    &mesh,
                    &metric,
                    &RemeshOptions { boundary: mode, ..RemeshOptions::default() },
                )
                .unwrap();
                assert!(out.stats.output[1] > 0, "field {k}");
            }
        }
    }
}
