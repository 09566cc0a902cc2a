//! DISTANCE_BETWEEN_TWO_BORDERS (thesis 3.4, 4.3.6.4, Algorithm 4.3, Fig. 4.6): sizes
//! from the local thickness of a gap between two borders.
//!
//! Thickness: d = d1 + d2, the exact distances from the vertex to the first and to the
//! second border, each from its own propagation up to the reach R. A vertex with
//! d <= R gets a tensor; d1, d2 <= d, so both propagations reach every such vertex.
//! This covers, as thesis 4.3.6.4's loop over the first border means to, every vertex
//! of the first border within reach (d = distance to the second border there), not only
//! the first one found.
//!
//! Sizes: thesis 4.3.6.4 feeds d1 + d2 to both distance functions in all three of its
//! cases (on the first border d "becomes the distance to the second", which is d1 + d2
//! with d1 = 0), so both are evaluated at the thickness: `perpendicular(d)` across the
//! gap, `parallel(d)` along it. Between two parallel walls the tensor is then constant.
//!
//! Orientation (thesis Fig. 4.6): with **d1**, **d2** the vectors from the vertex to its
//! closest points, the normal is w = d2 **d1**/d1 − d1 **d2**/d2, normalised: near one
//! border it follows that border's normal, halfway it is the mean of both. On a border
//! (d1 = 0 or d2 = 0) it is that border's normal, as in DISTANCE_TO_BORDER; when w
//! vanishes (both borders seen in the same direction at equal distances) it is the
//! direction of the nearer border.
//!
//! Reach R: the larger of the two functions' maximum distances (module [`super`]).

use super::{
    border_source, normal_at, on_source, reach_of, tensor, unit, Failure, Junctions, Sink,
};
use crate::geometry::Point2;
use crate::mesh_graph::MeshGraph;
use crate::sizing::functions::DistanceFunction;
use crate::sizing::plan::EntitySet;
use crate::sizing::propagation::{propagate, ClosestPoint, PropagationOptions, Source};
use crate::topology::Topology;

#[allow(clippy::too_many_arguments)]
pub(crate) fn run<S: Sink>(
    graph: &MeshGraph,
    topology: &Topology,
    perpendicular: &DistanceFunction,
    parallel: &DistanceFunction,
    first: &EntitySet,
    second: &EntitySet,
    options: &PropagationOptions,
    sink: S,
) -> Result<S::Output, Failure> {
    let s1 = border_source(graph, topology, first, true)?;
    let s2 = border_source(graph, topology, second, true)?;
    let (j1, j2) = (Junctions::new(&s1), Junctions::new(&s2));
    let r = reach_of(&[perpendicular.max_distance(), parallel.max_distance()]);
    let reach1 = propagate(graph, &s1, r, options);
    let reach2 = propagate(graph, &s2, r, options);
    sink.take_reach(reach1, |v, c1| {
        let Some(c2) = reach2.get(v) else { return Ok(None) };
        let thickness = c1.distance + c2.distance;
        // NaN distances (non-finite coordinates) fail this test too.
        if thickness.is_nan() || thickness > r {
            return Ok(None);
        }
        let p = graph.point(v);
        let n = gap_normal(p, (&s1, &j1, c1), (&s2, &j2, &c2));
        tensor(v, n, perpendicular.eval(thickness), parallel.eval(thickness)).map(Some)
    })
}

/// The weighted normal of thesis Fig. 4.6 (see the module header).
fn gap_normal(
    p: Point2,
    first: (&Source, &Junctions, &ClosestPoint),
    second: (&Source, &Junctions, &ClosestPoint),
) -> Option<Point2> {
    let (s1, j1, c1) = first;
    let (s2, j2, c2) = second;
    if on_source(s1, c1) {
        return normal_at(s1, j1, p, c1);
    }
    if on_source(s2, c2) {
        return normal_at(s2, j2, p, c2);
    }
    let (d1, d2) = (c1.distance, c2.distance);
    let u1 = [(c1.foot[0] - p[0]) / d1, (c1.foot[1] - p[1]) / d1];
    let u2 = [(c2.foot[0] - p[0]) / d2, (c2.foot[1] - p[1]) / d2];
    let w = [d2 * u1[0] - d1 * u2[0], d2 * u1[1] - d1 * u2[1]];
    if w[0].hypot(w[1]) > 1e-9 * (d1 + d2) {
        unit(w)
    } else if d1 <= d2 {
        unit(u1)
    } else {
        unit(u2)
    }
}
