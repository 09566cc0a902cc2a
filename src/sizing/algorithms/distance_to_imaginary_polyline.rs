//! DISTANCE_TO_IMAGINARY_POLYLINE (thesis 4.3.6.5, Algorithm 4.4): a polyline given by
//! coordinates (a wake, a shock) that need not follow mesh edges. With d the distance
//! to it and s' the curvilinear abscissa of the closest point (0 at its first point):
//! normal size `perpendicular(d)`, tangent size `projection(d, polyline_distance(s'))`,
//! the normal from the closest point to the vertex (the polyline's own normal for a
//! vertex on it, averaged at its corners).
//!
//! Coarse meshes (issue item 5): the propagation seeds the corners of every cell the
//! polyline touches, and reports them whatever their distance, so a polyline whose
//! reach is smaller than the local edge length still marks every cell it crosses. Those
//! corners get the tensor of their true distance (the functions hold their end values
//! past their maximum distance): the mesh is refined towards the polyline, and an
//! adaptation loop then brings vertices within reach. Giving them the size at the
//! polyline instead would refine the whole crossed cells to that size.
//!
//! `within`: when it names entities, only their vertices get a tensor (a face's: the
//! corners of its cells). The
//! distance is still the Euclidean distance to the whole polyline (the propagation runs
//! over the whole mesh and the result is filtered), so a face boundary cuts the field
//! without bending it.
//!
//! Reach: the larger maximum distance of the perpendicular and projection functions
//! (the abscissa function's maximum distance is along the polyline, not away from it).

use super::{normal_at, reach_of, tensor, Failure, Junctions, Sink};
use crate::geometry::Point2;
use crate::mesh_graph::MeshGraph;
use crate::sizing::functions::{DistanceFunction, SizeProjectionFunction};
use crate::sizing::plan::EntitySet;
use crate::sizing::propagation::{PropagationOptions, SourceBuilder};
use crate::topology::Topology;

#[allow(clippy::too_many_arguments)]
pub(crate) fn run<S: Sink>(
    graph: &MeshGraph,
    topology: &Topology,
    perpendicular: &DistanceFunction,
    polyline_distance: &DistanceFunction,
    projection: &SizeProjectionFunction,
    polyline: &[Point2],
    within: &EntitySet,
    options: &PropagationOptions,
    sink: S,
) -> Result<S::Output, Failure> {
    if polyline.is_empty() {
        return Err(Failure::EmptyPolyline);
    }
    let inside = if within.is_empty() {
        None
    } else {
        Some(super::uniform::entity_vertices(graph, topology, within)?)
    };
    let mut mask = vec![inside.is_none(); graph.num_vertices()];
    if let Some(vs) = &inside {
        for &v in vs {
            mask[v as usize] = true;
        }
    }
    let source = SourceBuilder::new(graph).polyline(polyline, false).build()?;
    let junctions = Junctions::new(&source);
    let reach = reach_of(&[perpendicular.max_distance(), projection.max_distance()]);
    sink.take_source(graph, &source, reach, options, |v, c| {
        if !mask[v] {
            return Ok(None);
        }
        let n = normal_at(&source, &junctions, graph.point(v), c);
        let h_line = polyline_distance.eval(c.abscissa);
        tensor(v, n, perpendicular.eval(c.distance), projection.eval(c.distance, h_line)).map(Some)
    })
}
