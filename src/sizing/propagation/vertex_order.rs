//! Closest points in vertex order, for a step whose reach covers the whole mesh: no
//! breadth-first levels, no list of reached vertices, each closest point handed on
//! where it is found.
//!
//! [`reach_covers_mesh`] decides when this applies: every connected component holds a
//! seed and a bound of the distances, one closest-point query per occupied cell of the
//! graph's grid, is within the maximum distance, so that [`super::propagate`] would
//! report every vertex. Then [`VertexOrder`] evaluates the vertices in index order, in
//! runs of [`VERTEX_RUN`], each from the closest segment of a nearby vertex before it in
//! its run, settled and certified as in the propagation (with one clearance tier capped
//! just past the farthest vertex, since every vertex asks). The same exact closest
//! points, bit for bit, in another order; the runs have a fixed size, so the work does
//! not depend on the thread count. Its exact queries (the reach test's, a run's first
//! vertex, the vertices past their clearance) all go to the clearances' tree of
//! oriented boxes, so such a step never builds the axis-aligned index.

use std::sync::OnceLock;

use super::breadth_first::CLEARANCE_AFTER;
use super::source::{ClosestPoint, Source};
use super::window::settle;
use crate::geometry::{Clearance, QueryStats};
use crate::mesh_graph::MeshGraph;

/// Vertices in a run of [`VertexOrder::for_each`] as the sizing driver cuts them: the
/// first vertex of a run is found by the index, every other one from a vertex before it
/// in the run. A fixed size, so that the work done does not depend on the thread count.
pub(crate) const VERTEX_RUN: usize = 4096;

/// Whether [`propagate`] from `source` up to `max_distance` reports every vertex of the
/// mesh, and if so a distance no vertex is farther than from the source. It does when
/// every connected component of the graph holds a seed and every vertex lies within
/// `max_distance` of the source: then every vertex is expanded, so the breadth-first
/// search visits each component of a seed whole and reports all of it.
///
/// The distances are bounded from above with one closest-point query per cell of the
/// graph's occupancy grid ([`MeshGraph::occupied_cells`], about 64 vertices a cell): no
/// point of a cell is farther from the source than the cell's centre is, plus half its
/// diagonal. The largest of these bounds, plus a margin for rounding, must be within
/// `max_distance`; the first cell past it ends the test. Otherwise, or with
/// non-finite coordinates, the answer is `None` and the caller propagates.
pub(crate) fn reach_covers_mesh(
    graph: &MeshGraph,
    source: &Source,
    max_distance: f64,
) -> Option<f64> {
    let n = graph.num_vertices();
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if n == 0 || !source.has_finite_segment() || !(max_distance >= 0.0) {
        return None;
    }
    let mut seeded = vec![false; graph.num_components()];
    for &v in source.seeds.iter().filter(|&&v| (v as usize) < n) {
        seeded[graph.component(v as usize)] = true;
    }
    if !seeded.iter().all(|&s| s) {
        return None;
    }
    // Non-finite coordinates: propagation would report only some vertices.
    let (lo, hi) = graph.bounds()?;
    let (slo, shi) = source.bounds?;
    let scale =
        [lo, hi, slo, shi].iter().flat_map(|p| [p[0].abs(), p[1].abs()]).fold(0.0, f64::max);
    if !scale.is_finite() {
        return None;
    }
    // Rounding of the centres, of the distances and of the sums.
    let margin = 64.0 * f64::EPSILON * scale;
    let mut farthest = 0.0f64;
    // Every coordinate is finite here: the chain tree answers, each search from the
    // previous cell's closest segment (cells come in grid order).
    let mut guess = None;
    for &(a, b) in graph.occupied_cells() {
        let centre = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let half_diagonal = 0.5 * (b[0] - a[0]).hypot(b[1] - a[1]);
        let nearest = source.closest_in_chain(centre, guess, &mut QueryStats::default());
        guess = Some(nearest.segment);
        let bound = nearest.projection.distance() + half_diagonal + margin;
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(bound <= max_distance) {
            return None;
        }
        farthest = farthest.max(bound);
    }
    Some(farthest)
}

/// Exact closest points in vertex order, for a step that reaches every vertex (see
/// [`reach_covers_mesh`]): no breadth-first levels, no list of reached vertices, and
/// each closest point handed on where it is found. A vertex takes as guess the closest
/// segment of the vertex just before it when that one lies within its longest edge,
/// else of its first neighbour evaluated before it in the same run (else, again, of the
/// vertex before), and is then settled and certified as in [`propagate`]: the same
/// exact closest points, bit for bit, in another order.
pub(crate) struct VertexOrder<'a> {
    graph: &'a MeshGraph,
    source: &'a Source,
    /// Clearances for questions up to the farthest vertex ([`Clearance::up_to_over`]):
    /// every vertex is asked about, so the far questions come for most segments, and
    /// one search per segment side answers them all.
    clearance: OnceLock<Clearance>,
    farthest: f64,
    /// Every vertex is evaluated, on average `n / m` per segment: clearances pay when
    /// that is at least [`CLEARANCE_AFTER`], the share at which [`propagate`] computes
    /// a segment's clearance.
    clearances_pay: bool,
}

impl<'a> VertexOrder<'a> {
    /// The evaluator of the vertices of `graph` against `source`, none of them farther
    /// than `farthest` from it ([`reach_covers_mesh`]).
    pub(crate) fn new(graph: &'a MeshGraph, source: &'a Source, farthest: f64) -> VertexOrder<'a> {
        let clearances_pay =
            graph.num_vertices() >= CLEARANCE_AFTER as usize * source.segments.len();
        VertexOrder { graph, source, clearance: OnceLock::new(), farthest, clearances_pay }
    }

    /// Calls `visit` with each vertex of `range` and its closest point, in order.
    pub(crate) fn for_each(
        &self,
        range: std::ops::Range<usize>,
        mut visit: impl FnMut(usize, &ClosestPoint),
    ) {
        let (graph, source) = (self.graph, self.source);
        let lo = range.start;
        let mut found = vec![u32::MAX; range.len()];
        // Every vertex is evaluated: the clearances will be asked for.
        let clearance = if self.clearances_pay {
            Some(self.clearance.get_or_init(|| source.clearance_up_to(self.farthest)))
        } else {
            None
        };
        if range.is_empty() {
            return;
        }
        // The run's first vertex has nothing before it: the tree answers, before the
        // loop, so that the loop holds only the evaluations from a guess.
        let first = source.closest_in_chain(graph.point(lo), None, &mut QueryStats::default());
        for v in range {
            let p = graph.point(v);
            let earlier = |u: usize| (lo..v).contains(&u).then(|| found[u - lo]);
            // The vertex before, when it lies within the vertex's longest edge (as its
            // neighbours do): the usual case of a mesh numbered with some locality, and
            // one test, where a scan of the neighbours mispredicts on how many come
            // before the first evaluated one. Else that first one, else the vertex before.
            let previous_is_near = v > lo && {
                let q = graph.point(v - 1);
                let reach = graph.longest_edge(v);
                (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) <= reach * reach
            };
            let guess = if previous_is_near {
                Some(found[v - 1 - lo])
            } else {
                graph
                    .neighbours(v)
                    .iter()
                    .find_map(|&u| earlier(u as usize))
                    .or_else(|| v.checked_sub(1).and_then(earlier))
            };
            // Every vertex after the first has a guess (the vertex before, at least).
            let nearest = match guess {
                Some(seg) => settle(source, p, seg, |_| clearance).nearest,
                None => first,
            };
            found[v - lo] = nearest.segment;
            visit(v, &source.describe(p, nearest));
        }
    }
}
