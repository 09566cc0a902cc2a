//! The native 2D anisotropic remesher: adapts a tagged triangle mesh to a metric field
//! by local operations, every one measured in the metric (thesis 3.5, the role OORT
//! plays in the loop of 7.3.2).
//!
//! Each pass splits the edges longer than √2 in the metric (`split`), collapses the
//! edges shorter than 1/√2 (`collapse`), flips diagonals to raise the worse metric
//! quality of each pair (`swap`), moves vertices toward a metric-equilateral place
//! (`smooth`), then collapses and flips once more where smoothing left short edges; the
//! passes stop when splits and collapses touch fewer than a fivehundredth of the
//! triangles, or after [`RemeshOptions::max_passes`], and a last smoothing and swap
//! polish the result.
//!
//! What it guarantees, by construction and checked in the tests:
//! - every triangle strictly counter-clockwise (Shewchuk's exact orientation predicate
//!   guards every operation), so never an inverted or zero-area one;
//! - boundary and interface vertices only slide along their own piece of the input curve
//!   ([`boundary`]); corners and topological points never move nor vanish; no new
//!   boundary edge sweeps across another curve;
//! - every triangle keeps the face tags of the input triangle it came from, every
//!   constrained edge its curve's line tags; vertex cells stay;
//! - the metric at every new or moved vertex is interpolated from the *input* field
//!   (`background`), Log-Euclidean, so it stays SPD and does not drift;
//! - deterministic: single-threaded sweeps in index order, no hash-order iteration.

mod background;
pub mod boundary;
mod build;
mod collapse;
mod output;
mod smooth;
mod split;
mod swap;
mod work;

use std::time::Instant;

use serde::Serialize;

use crate::conformity::{Conformity, CONFORMING};
use crate::formats::TaggedMesh;
use crate::metric::Sym2;

pub use background::{exp_sym, log_spd};

/// Where vertices on boundaries and interfaces are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryMode {
    /// On the original polyline (the boundary never changes shape).
    #[default]
    Polyline,
    /// On a C¹ cubic reconstruction through the original boundary vertices (curved
    /// boundaries get rounder as they are refined; straight runs stay straight).
    Smooth,
}

/// How to remesh.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RemeshOptions {
    /// Passes of split, collapse, swap and smooth at most.
    pub max_passes: usize,
    /// Smoothing sweeps per pass.
    pub smooth_sweeps: usize,
    /// Placement of boundary and interface vertices.
    pub boundary: BoundaryMode,
    /// A curve vertex where the curve turns by more than this angle is a corner (fixed).
    pub ridge_angle_degrees: f64,
    /// Split edges longer than this metric length.
    pub split_above: f64,
    /// Collapse edges shorter than this metric length.
    pub collapse_below: f64,
    /// Points of the input geometry that stay vertices: a boundary or interface vertex at
    /// exactly one of these coordinates is a corner (never moved nor removed). The
    /// adaptation loop passes the vertices of the `.poly` it started from, so that every
    /// boundary edge stays on an input segment however many times the mesh is remeshed
    /// (without them, a vertex at a bend milder than the ridge angle may be collapsed, its
    /// two edges replaced by a chord, and the next remeshing takes the chord as the
    /// boundary).
    #[serde(skip)]
    pub keep_points: Vec<[f64; 2]>,
}

impl Default for RemeshOptions {
    fn default() -> Self {
        RemeshOptions {
            max_passes: 12,
            smooth_sweeps: 2,
            boundary: BoundaryMode::Polyline,
            ridge_angle_degrees: 45.0,
            split_above: CONFORMING[1],
            collapse_below: CONFORMING[0],
            keep_points: Vec::new(),
        }
    }
}

/// What one pass did.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PassStats {
    /// Edges split.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Diagonals flipped.
    pub swaps: usize,
    /// Vertices moved.
    pub moves: usize,
    /// Triangles at the end of the pass.
    pub triangles: usize,
}

/// Seconds spent in each phase.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PhaseSeconds {
    /// Reading the input: constraints, pieces, background index.
    pub setup: f64,
    /// Splitting.
    pub split: f64,
    /// Collapsing.
    pub collapse: f64,
    /// Swapping.
    pub swap: f64,
    /// Smoothing.
    pub smooth: f64,
    /// Building the output mesh and measuring it.
    pub output: f64,
}

/// What a run did and how the result conforms.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RemeshStats {
    /// Passes run.
    pub passes: usize,
    /// Edges split, in all.
    pub splits: usize,
    /// Edges collapsed.
    pub collapses: usize,
    /// Diagonals flipped.
    pub swaps: usize,
    /// Vertices moved.
    pub moves: usize,
    /// Each pass.
    pub per_pass: Vec<PassStats>,
    /// Seconds per phase.
    pub seconds: PhaseSeconds,
    /// Input vertices and triangles.
    pub input: [usize; 2],
    /// Output vertices and triangles.
    pub output: [usize; 2],
    /// Conformity of the input mesh to the metric.
    pub initial: Option<Conformity>,
    /// Conformity of the output mesh to its metric.
    pub conformity: Option<Conformity>,
    /// What the output does not carry.
    pub warnings: Vec<String>,
}

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

/// Why a mesh cannot be remeshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RemeshError {
    /// The metric does not have one tensor per point.
    #[error("the metric has {items} tensors for {vertices} vertices")]
    MetricCount {
        /// Tensors given.
        items: usize,
        /// Points of the mesh.
        vertices: usize,
    },
    /// A vertex used by a triangle has a metric that is not finite and SPD.
    #[error("the metric at vertex {vertex} (0-based), [[{a}, {b}], [{b}, {c}]], is not finite and positive definite")]
    NotSpd {
        /// The vertex.
        vertex: usize,
        /// m11.
        a: f64,
        /// m12.
        b: f64,
        /// m22.
        c: f64,
    },
    /// A point with a non-finite coordinate.
    #[error("vertex {vertex} (0-based) has a coordinate that is not finite")]
    BadPoint {
        /// The vertex.
        vertex: usize,
    },
    /// A cell kind the remesher does not handle.
    #[error("the remesher handles triangles, lines and vertex cells; the mesh has {kind} cells (convert or split them first)")]
    UnsupportedCell {
        /// The kind's name.
        kind: &'static str,
    },
    /// No triangle at all.
    #[error("the mesh has no triangles")]
    NoTriangles,
    /// A triangle with zero area or a repeated vertex.
    #[error("triangle {triangle} (0-based, vertices {vertices:?}) has zero area")]
    DegenerateTriangle {
        /// The triangle.
        triangle: usize,
        /// Its vertices.
        vertices: [usize; 3],
    },
    /// An edge shared by more than two triangles.
    #[error(
        "edge {edge:?} is shared by {triangles} triangles; the remesher needs a manifold mesh"
    )]
    NonManifold {
        /// The edge.
        edge: [usize; 2],
        /// How many triangles hold it.
        triangles: usize,
    },
    /// More vertices than the remesher's 32-bit indices allow.
    #[error("{vertices} vertices is more than the remesher handles")]
    TooLarge {
        /// Points of the mesh.
        vertices: usize,
    },
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

/// The metric of a background mesh (`background` with one tensor per point in
/// `metric`) at `points`, by the interpolation the remesher uses: Log-Euclidean
/// barycentric in the triangle holding the point, or at the closest point of the nearest
/// triangle outside. Measures any mesh (ours, another tool's) against the same field.
pub fn interpolate_metric(
    background: &TaggedMesh,
    metric: &[Sym2],
    points: &[[f64; 2]],
) -> Result<Vec<Sym2>, RemeshError> {
    if metric.len() != background.points.len() {
        return Err(RemeshError::MetricCount {
            items: metric.len(),
            vertices: background.points.len(),
        });
    }
    let pts: Vec<[f64; 2]> = background.points.iter().map(|p| [p[0], p[1]]).collect();
    let tris: Vec<[usize; 3]> = background
        .cells()
        .filter(|c| c.0 == crate::formats::CellKind::Triangle)
        .map(|c| [c.1[0] as usize, c.1[1] as usize, c.1[2] as usize])
        .collect();
    if tris.is_empty() {
        return Err(RemeshError::NoTriangles);
    }
    let bg = background::Background::new(&pts, &tris, metric);
    Ok(points.iter().map(|&p| bg.metric_at(p)).collect())
}

fn collapse_phase(
    w: &mut work::Work,
    opts: &RemeshOptions,
    lmax_after: f64,
    ps: &mut PassStats,
    secs: &mut PhaseSeconds,
) {
    let t = Instant::now();
    ps.collapses += collapse::collapse_sweeps(w, opts.collapse_below, lmax_after, 4);
    secs.collapse += t.elapsed().as_secs_f64();
}

fn swap_phase(w: &mut work::Work, ps: &mut PassStats, secs: &mut PhaseSeconds, everything: bool) {
    let t = Instant::now();
    ps.swaps += swap::swap_sweeps(w, 8, everything);
    secs.swap += t.elapsed().as_secs_f64();
}

/// Remeshes `mesh` to `metric` (one SPD tensor per point; [`crate::conformity::metric_field`]
/// reads and checks one from point data).
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
    let t0 = Instant::now();
    let st = build::start(mesh, metric, opts)?;
    let bg = build::background(&st, metric);
    let input_tris: Vec<[usize; 3]> = st.tris.iter().map(|t| t.map(|v| v as usize)).collect();
    let initial = Conformity::of(&st.pts, &input_tris, metric);
    let bd = boundary::Boundary::new(st.pieces);
    #[cfg(test)]
    let input_points = st.pts.clone();
    let n = st.pts.len();
    let mut vtris = vec![Vec::new(); n];
    for (i, t) in st.tris.iter().enumerate() {
        for &v in t {
            vtris[v as usize].push(i as u32);
        }
    }
    let ntri = st.tris.len();
    let mut w = work::Work {
        pts: st.pts,
        met: metric.to_vec(),
        piece: st.piece,
        s: st.s,
        vtris,
        tris: st.tris,
        face: st.face,
        alive: vec![true; ntri],
        dirty: Vec::new(),
        is_dirty: vec![false; n],
        active: vec![true; n],
        cons: st.cons,
        bg: &bg,
        bd: &bd,
        mode: opts.boundary,
    };
    let mut stats = RemeshStats {
        passes: 0,
        splits: 0,
        collapses: 0,
        swaps: 0,
        moves: 0,
        per_pass: Vec::new(),
        seconds: PhaseSeconds { setup: t0.elapsed().as_secs_f64(), ..PhaseSeconds::default() },
        input: [n, ntri],
        output: [0, 0],
        initial,
        conformity: None,
        warnings: st.warnings,
    };
    // Collapses may not create edges longer than this: a little under the split bound,
    // so that a collapse never hands the next split sweep work.
    let lmax_after = opts.split_above;
    for pass in 0..opts.max_passes {
        let mut ps = PassStats::default();
        let t = Instant::now();
        ps.splits += split::split_sweeps(&mut w, opts.split_above);
        stats.seconds.split += t.elapsed().as_secs_f64();
        collapse_phase(&mut w, opts, lmax_after, &mut ps, &mut stats.seconds);
        swap_phase(&mut w, &mut ps, &mut stats.seconds, pass == 0);
        let t = Instant::now();
        for _ in 0..opts.smooth_sweeps {
            ps.moves += smooth::smooth_sweep(&mut w);
        }
        stats.seconds.smooth += t.elapsed().as_secs_f64();
        // Smoothing moves lengths out of the band again: a last collapse and swap.
        collapse_phase(&mut w, opts, lmax_after, &mut ps, &mut stats.seconds);
        swap_phase(&mut w, &mut ps, &mut stats.seconds, false);
        ps.triangles = w.alive.iter().filter(|&&a| a).count();
        stats.passes = pass + 1;
        stats.splits += ps.splits;
        stats.collapses += ps.collapses;
        stats.swaps += ps.swaps;
        stats.moves += ps.moves;
        // Settled when the topology barely changes any more (a fivehundredth of the
        // triangles); what is left is smoothing's business, which the pass just did.
        let settled = (ps.splits + ps.collapses) * 500 <= ps.triangles;
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
        let t = Instant::now();
        let mut moves = 0;
        for _ in 0..opts.smooth_sweeps {
            moves += smooth::smooth_sweep(&mut w);
        }
        stats.seconds.smooth += t.elapsed().as_secs_f64();
        let mut ps = PassStats { moves, ..PassStats::default() };
        swap_phase(&mut w, &mut ps, &mut stats.seconds, false);
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
    let (out, out_metric) = output::assemble(mesh, &w, &st.faces, &st.vertex_cells);
    let out_pts: Vec<[f64; 2]> = out.points.iter().map(|p| [p[0], p[1]]).collect();
    let out_tris: Vec<[usize; 3]> = out
        .cells()
        .filter(|c| c.0 == crate::formats::CellKind::Triangle)
        .map(|c| [c.1[0] as usize, c.1[1] as usize, c.1[2] as usize])
        .collect();
    stats.output = [out_pts.len(), out_tris.len()];
    stats.conformity = Conformity::of(&out_pts, &out_tris, &out_metric);
    stats.seconds.output = t.elapsed().as_secs_f64();
    Ok(Remeshed { mesh: out, metric: out_metric, stats })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formats::{CellBlock, CellKind};
    use crate::metric::SizeTensor;

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
