//! How to remesh: the user's choices (passes, boundary placement, ridge angle, the
//! conforming band, the size and vertex limits) and the tuning of the operators (quality
//! floor, sweep counts, gains, the settling rule), all in one [`RemeshOptions`] whose
//! defaults are the values the benchmarks and the tests were measured with.

use serde::Serialize;

use crate::metric::length::CONFORMING;

/// Where vertices on boundaries and interfaces are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryMode {
    /// On the original polyline (the boundary never changes shape).
    Polyline,
    /// On a C¹ cubic reconstruction through the original boundary vertices (curved
    /// boundaries get rounder as they are refined; corners stay corners and straight
    /// runs straight), as MMG does by default.
    #[default]
    Smooth,
}

/// Vertices a remeshing may make unless the caller allows more: 5·10⁶, about 10⁷
/// triangles. The peak memory of `smartmesh remesh` grows by about 0.55 KB per output
/// vertex (measured with `/usr/bin/time -f %M` on a uniform metric over the unit square,
/// 13 000 → 52 000 output vertices: 24 → 45 MB), so the default keeps a run near 3 GB,
/// and the refusal comes before the work starts ([`RemeshOptions::max_vertices`]).
pub const DEFAULT_MAX_VERTICES: usize = 5_000_000;

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
    /// Largest distance a collapse on a curve may put between the curve (the smooth
    /// reconstruction, or the polyline with [`BoundaryMode::Polyline`]) and the new
    /// boundary edge, as MMG's `-hausd` bounds its coarsening. `None`:
    /// [`DEFAULT_RELATIVE_HAUSD`] times the largest side of the input's bounding box.
    pub hausd: Option<f64>,
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
    /// Curves (by the tag of their line cells, physical else geometrical) whose vertices
    /// and edges stay as they are: never split, collapsed nor moved. The sides of a
    /// periodic pair ([`crate::periodic`]) are frozen so that matching sides stay matched.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub frozen_curves: Vec<i32>,
    /// Periodic pairs: before remeshing, each matched pair's sides are coarsened alike
    /// ([`crate::periodic::coarsen_sides`]) and their edges split alike to the metric
    /// ([`crate::periodic::refine_sides`]); then the sides' curves are frozen.
    #[serde(skip)]
    pub periodic: Vec<crate::periodic::PeriodicPair>,
    /// Most vertices the output may have. The expected count (the metric's complexity,
    /// [`crate::metric::complexity`]) is compared with it before any work, and the run is refused
    /// ([`super::RemeshError::TooManyVertices`]) when above; the splits stop at twice it,
    /// should the estimate be wrong. `None`: no limit.
    pub max_vertices: Option<usize>,
    /// Whether to measure the input's and the output's conformity to the metric
    /// ([`super::RemeshStats::initial`], [`super::RemeshStats::conformity`]); the
    /// adaptation loop measures each mesh against the recipe's own field and turns it off.
    pub measure: bool,
    /// A collapse may not leave the worst triangle of the ball below the smaller of its
    /// worst before and this metric quality.
    pub quality_floor: f64,
    /// Collapse sweeps per collapse phase at most (each sweep looks again only around the
    /// vertices the previous one merged).
    pub collapse_sweeps: usize,
    /// Swap sweeps per swap phase at most.
    pub swap_sweeps: usize,
    /// Relative gain of the worse quality of the pair that a flip must bring (keeps sweeps
    /// from flipping back and forth on ties).
    pub swap_gain: f64,
    /// Relative gain of the worst ball quality that a smoothing move must bring.
    pub smooth_gain: f64,
    /// Below this worst ball quality a smoothed vertex gets more candidate places.
    pub smooth_poor: f64,
    /// The passes have settled when `(splits + collapses) × settle_ratio` is at most the
    /// triangle count (one change per `settle_ratio` triangles).
    pub settle_ratio: usize,
    /// When and how a large mesh is cut into parts remeshed in parallel, their
    /// interfaces frozen and then remeshed by later passes (`super::parallel`); the
    /// output is the same whatever the thread count. `None`: always the serial remesher.
    pub partition: Option<Partitioning>,
}

/// The default Hausdorff bound on collapses along curves, relative to the largest side
/// of the input's bounding box: MMG's default `-hausd 0.01` on a domain of unit size.
pub const DEFAULT_RELATIVE_HAUSD: f64 = 0.01;

/// Expected output vertices above which the remesher partitions the mesh by default.
pub const DEFAULT_PARTITION_ABOVE: usize = 100_000;

/// When and how the remesher cuts a mesh into parts (`super::parallel`). None of it
/// depends on the thread count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Partitioning {
    /// Partition when the expected output vertex count is at least this.
    pub above: usize,
    /// Expected output vertices per part in the first pass.
    pub part_vertices: usize,
    /// Expected output vertices per part in the second pass (the band around the first
    /// pass's interfaces).
    pub band_part_vertices: usize,
    /// Width of the band a later pass remeshes, in edges from an interface vertex.
    pub rings: usize,
    /// When the metric asks for more than this many times the input's vertex count, the
    /// input is first remeshed to the metric divided by it (sizes times its square root),
    /// and that mesh is partitioned. 0 or 1: never.
    pub coarse_ratio: usize,
}

impl Default for Partitioning {
    fn default() -> Self {
        Partitioning {
            above: DEFAULT_PARTITION_ABOVE,
            part_vertices: 50_000,
            band_part_vertices: 12_500,
            rings: 4,
            coarse_ratio: 16,
        }
    }
}

impl RemeshOptions {
    /// The Hausdorff bound on collapses along curves for a mesh with points `pts`:
    /// [`RemeshOptions::hausd`], or its default.
    pub(super) fn hausd_for(&self, pts: &[[f64; 2]]) -> f64 {
        self.hausd.unwrap_or_else(|| {
            let mut lo = [f64::INFINITY; 2];
            let mut hi = [f64::NEG_INFINITY; 2];
            for p in pts {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
            let side = (hi[0] - lo[0]).max(hi[1] - lo[1]);
            if side.is_finite() {
                DEFAULT_RELATIVE_HAUSD * side
            } else {
                f64::INFINITY
            }
        })
    }
}

impl Default for RemeshOptions {
    fn default() -> Self {
        RemeshOptions {
            max_passes: 12,
            smooth_sweeps: 2,
            boundary: BoundaryMode::Smooth,
            ridge_angle_degrees: 45.0,
            hausd: None,
            split_above: CONFORMING[1],
            collapse_below: CONFORMING[0],
            keep_points: Vec::new(),
            frozen_curves: Vec::new(),
            periodic: Vec::new(),
            max_vertices: Some(DEFAULT_MAX_VERTICES),
            measure: true,
            quality_floor: 0.3,
            collapse_sweeps: 4,
            swap_sweeps: 8,
            swap_gain: 1e-6,
            smooth_gain: 1e-3,
            smooth_poor: 0.8,
            settle_ratio: 500,
            partition: Some(Partitioning::default()),
        }
    }
}
