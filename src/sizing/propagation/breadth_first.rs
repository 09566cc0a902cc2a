//! Breadth-first propagation from a source (thesis Algorithms 4.2–4.5, with exact
//! closest points): the seeds first, then level by level, each vertex from the closest
//! segment of its first evaluated neighbour, settled and certified ([`settle`]).
//!
//! Stopping. A vertex is expanded (its neighbours queued) when its distance is at most
//! `max_distance` plus its longest incident edge. Then every vertex within
//! `max_distance` is reached whenever the straight segment to its closest point stays in
//! the mesh: each cell crossed by that segment holds a point within `max_distance`, so
//! its corners are expanded, and the last one touches the source. Reported are the seeds
//! and the vertices within `max_distance`; the others are evaluated in transit only.
//!
//! Determinism: a level is evaluated in parallel (rayon) and committed in queue order;
//! each evaluation reads only earlier levels and is exact, so the reach is the same
//! with any number of threads. A segment's clearance is used once earlier levels put
//! [`CLEARANCE_AFTER`] closest points on it (before, the axis-aligned index certifies):
//! that changes the work, never the answer.

use std::sync::OnceLock;

use rayon::prelude::*;

use super::source::{ClosestPoint, Source};
use super::window::{settle, Evaluation};
use crate::geometry::{Clearance, Nearest, QueryStats};
use crate::mesh_graph::MeshGraph;

/// Knobs of [`propagate`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PropagationOptions {
    /// Evaluate large levels on the rayon thread pool. The result is the same either
    /// way; only the time changes.
    pub parallel: bool,
}

impl Default for PropagationOptions {
    fn default() -> Self {
        PropagationOptions { parallel: true }
    }
}

impl PropagationOptions {
    /// Defaults: parallel.
    pub fn new() -> PropagationOptions {
        PropagationOptions::default()
    }

    /// With or without parallel evaluation.
    pub fn with_parallel(self, parallel: bool) -> PropagationOptions {
        PropagationOptions { parallel }
    }
}

/// What a propagation did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct PropagationReport {
    /// Seed vertices.
    pub seeds: usize,
    /// Vertices whose closest point was computed (reported or in transit).
    pub evaluated: usize,
    /// Vertices reported in the [`Reach`].
    pub reached: usize,
    /// Vertices where the neighbours' guess was not the closest segment and the index
    /// found a strictly closer one: the local minima of pure neighbour propagation.
    pub corrected: usize,
    /// Vertices whose closest point was certified by the clearance of its segment or
    /// vertex (no index search).
    pub certified_locally: usize,
    /// Breadth-first levels.
    pub levels: usize,
    /// Index boxes tested.
    pub boxes_tested: u64,
    /// Segments projected on (guesses and index leaves).
    pub segments_tested: u64,
}

/// The vertices a propagation reached and their closest points on the source, in
/// breadth-first order (seeds first, by index; then level by level, each level in
/// the order its vertices were queued).
///
/// Only the closest segment of each vertex is kept; its closest point is computed again
/// when asked for ([`Reach::closest`]): one projection, the same bits as the
/// propagation's (one function of the same inputs). For a reach of 10^6 vertices that is
/// 4 MB where a table of closest points would be 56 MB of fresh memory, written once and
/// read once by the algorithm that turns them into tensors.
#[derive(Debug, Clone)]
pub struct Reach<'a> {
    graph: &'a MeshGraph,
    source: &'a Source,
    vertices: Vec<u32>,
    /// The closest segment of each vertex of `vertices`.
    segments: Vec<u32>,
    /// Position of each mesh vertex in `vertices`, or `u32::MAX`.
    slot: Vec<u32>,
    report: PropagationReport,
}

impl<'a> Reach<'a> {
    /// Number of reached vertices.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Whether nothing was reached.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Reached vertices in order; the first `report().seeds` are the seeds.
    pub fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// The closest point of the `i`-th reached vertex (in the order of
    /// [`Reach::vertices`]).
    #[inline]
    pub fn closest(&self, i: usize) -> ClosestPoint {
        let p = self.graph.point(self.vertices[i] as usize);
        let segment = self.segments[i];
        self.source.describe(
            p,
            Nearest { segment, projection: self.source.geoms[segment as usize].project(p) },
        )
    }

    /// Closest points, in the order of [`Reach::vertices`].
    pub fn closest_points(&self) -> impl ExactSizeIterator<Item = ClosestPoint> + '_ {
        (0..self.len()).map(|i| self.closest(i))
    }

    /// The closest point of vertex `v`, if reached.
    pub fn get(&self, v: usize) -> Option<ClosestPoint> {
        match self.slot.get(v) {
            Some(&s) if s != u32::MAX => Some(self.closest(s as usize)),
            _ => None,
        }
    }

    /// `(vertex, closest point)` in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (usize, ClosestPoint)> + '_ {
        (0..self.len()).map(|i| (self.vertices[i] as usize, self.closest(i)))
    }

    /// The position of each mesh vertex in [`Reach::vertices`], `u32::MAX` for the
    /// vertices not reached: a lookup by vertex, for a pass in vertex order.
    pub(crate) fn positions(&self) -> &[u32] {
        &self.slot
    }

    /// What the propagation did.
    pub fn report(&self) -> &PropagationReport {
        &self.report
    }

    /// The reached vertices, giving up the rest.
    pub(crate) fn into_vertices(self) -> Vec<u32> {
        self.vertices
    }
}

const UNSEEN: u32 = u32::MAX;
const QUEUED: u32 = u32::MAX - 1;
/// Levels smaller than this are evaluated on the calling thread.
const PARALLEL_MIN_LEVEL: usize = 2048;
/// Closest points that earlier levels must have put on a segment before its clearance
/// is used (see [`evaluate_from_neighbours`]): a first-tier clearance is a short search
/// (a few tens of segment lengths), which the vertices of the second ring out repay.
pub(super) const CLEARANCE_AFTER: u32 = 2;

/// Propagates from `source` over `graph` up to `max_distance` (thesis Algorithms 4.2–4.5,
/// with exact closest points). A negative or NaN `max_distance` reaches the seeds only;
/// an infinite one reaches the seeds' connected components.
pub fn propagate<'a>(
    graph: &'a MeshGraph,
    source: &'a Source,
    max_distance: f64,
    options: &PropagationOptions,
) -> Reach<'a> {
    let n = graph.num_vertices();
    let max = if max_distance >= 0.0 { max_distance } else { 0.0 };
    let mut report = PropagationReport::default();
    let mut slot = vec![UNSEEN; n];
    // Room for every vertex up front: pages that are never written are never touched,
    // and growing by doubling would copy the largest arrays of the propagation.
    let mut order: Vec<u32> = Vec::with_capacity(n);
    // The closest segment of each evaluated vertex, in evaluation order; the projection
    // is computed again for the reported ones (the same bits: one function of the same
    // inputs), which costs less than keeping it for every vertex.
    let mut found: Vec<u32> = Vec::with_capacity(n);
    // Whether each evaluated vertex is reported: a seed, or within max_distance
    // (parallel to `order`, pushed where the expansion test computes the distance).
    let mut keep: Vec<bool> = Vec::with_capacity(n);
    let mut evaluations: Vec<Evaluation> = Vec::new();
    let mut next: Vec<u32> = Vec::new();
    let mut frontier: Vec<u32> = if !source.has_finite_segment() {
        Vec::new()
    } else {
        source.seeds.iter().copied().filter(|&v| (v as usize) < n).collect()
    };
    // The guess of each seed, by vertex, for the first level.
    let guess_of =
        |v: u32| source.seeds.binary_search(&v).ok().map_or(u32::MAX, |i| source.seed_guess[i]);
    for &v in &frontier {
        slot[v as usize] = QUEUED;
    }
    report.seeds = frontier.len();
    // Built the first time a segment earns its clearance: a fixed function of the
    // source, whichever thread builds it.
    let clearance: OnceLock<Clearance> = OnceLock::new();
    // Closest points committed on each segment so far.
    let mut feet = vec![0u32; source.segments.len()];
    let mut level = 0usize;
    while !frontier.is_empty() {
        let evaluate = |&v: &u32| -> Evaluation {
            if level == 0 {
                let mut stats = QueryStats::default();
                let p = graph.point(v as usize);
                let g = guess_of(v);
                let nearest = if (g as usize) < source.geoms.len() {
                    source.index().certify(
                        p,
                        Nearest { segment: g, projection: source.geoms[g as usize].project(p) },
                        &mut stats,
                    )
                } else {
                    source.index().closest(p, &mut stats).expect("index is not empty")
                };
                Evaluation { nearest, corrected: false, local: false, stats }
            } else {
                evaluate_from_neighbours(
                    graph, source, &clearance, &feet, &slot, &found, v as usize,
                )
            }
        };
        // One buffer for every level's evaluations, reused.
        if options.parallel && frontier.len() >= PARALLEL_MIN_LEVEL {
            frontier.par_iter().with_min_len(256).map(evaluate).collect_into_vec(&mut evaluations);
        } else {
            evaluations.clear();
            evaluations.extend(frontier.iter().map(evaluate));
        }
        // Commit the level, then queue the neighbours of the vertices to expand.
        next.clear();
        for (&v, e) in frontier.iter().zip(&evaluations) {
            slot[v as usize] = found.len() as u32;
            found.push(e.nearest.segment);
            feet[e.nearest.segment as usize] = feet[e.nearest.segment as usize].saturating_add(1);
            order.push(v);
            report.corrected += usize::from(e.corrected);
            report.certified_locally += usize::from(e.local);
            report.boxes_tested += e.stats.boxes;
            report.segments_tested += e.stats.segments;
        }
        for (&v, e) in frontier.iter().zip(&evaluations) {
            let d = e.nearest.projection.distance();
            keep.push(level == 0 || d <= max);
            if d <= max + graph.longest_edge(v as usize) {
                for &u in graph.neighbours(v as usize) {
                    if slot[u as usize] == UNSEEN {
                        slot[u as usize] = QUEUED;
                        next.push(u);
                    }
                }
            }
        }
        std::mem::swap(&mut frontier, &mut next);
        level += 1;
    }
    report.levels = level;
    report.evaluated = order.len();
    // Keep the seeds and the vertices within max_distance, in place; the slot array
    // becomes the lookup of the reported vertices.
    let mut kept = 0;
    for i in 0..order.len() {
        let v = order[i];
        if keep[i] {
            slot[v as usize] = kept as u32;
            order[kept] = v;
            found[kept] = found[i];
            kept += 1;
        } else {
            slot[v as usize] = UNSEEN;
        }
    }
    order.truncate(kept);
    found.truncate(kept);
    report.reached = kept;
    Reach { graph, source, vertices: order, segments: found, slot, report }
}

/// The closest point of vertex `v` from its evaluated neighbours' segments, settled
/// on a local optimum along the polyline, then certified by the clearance of its
/// segment or vertex, or else by the index.
fn evaluate_from_neighbours(
    graph: &MeshGraph,
    source: &Source,
    clearance: &OnceLock<Clearance>,
    feet: &[u32],
    slot: &[u32],
    found: &[u32],
    v: usize,
) -> Evaluation {
    let p = graph.point(v);
    // The guess: the closest segment of the first evaluated neighbour. Neighbours lie
    // within an edge of each other, so their segments are the same or a few steps apart
    // along the polyline, where the march and the window below reach; comparing every
    // neighbour's segment first costs more projections than it saves steps.
    let guess = graph.neighbours(v).iter().find_map(|&u| {
        let s = slot[u as usize];
        (s < QUEUED).then(|| found[s as usize])
    });
    let Some(seg) = guess else {
        // Queued vertices always have an evaluated neighbour; stay exact regardless.
        let mut stats = QueryStats::default();
        let nearest = source.index().closest(p, &mut stats).expect("index is not empty");
        return Evaluation { nearest, corrected: false, local: false, stats };
    };
    // A clearance costs a few index searches to compute: it is asked for only once
    // earlier levels put enough feet on the segment to pay it back.
    settle(source, p, seg, |s| {
        (feet[s as usize] >= CLEARANCE_AFTER).then(|| clearance.get_or_init(|| source.clearance()))
    })
}
