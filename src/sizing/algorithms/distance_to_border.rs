//! DISTANCE_TO_BORDER (thesis 2.2.10.4, 4.3.7.1, Algorithm 4.5): anisotropic sizes from
//! the distance d to the border curves — `perpendicular(d)` along the normal,
//! `parallel(d)` along the tangent, the axes taken at the exact closest point:
//!
//! - off the border, the normal is the direction from the closest point to the vertex
//!   (at a foot on a polyline corner, the direction the vertex is seen from the corner);
//! - on the border (d = 0), the normal of the border there: the segment's, or at a
//!   polyline vertex that of the averaged neighbour segments (the segments of every
//!   border polyline meeting at that vertex).
//!
//! Points in the border set are point sources: around them the normal is radial, and
//! on the point itself the tensor is isotropic, of the smaller size.
//!
//! Reach: the larger of the two functions' maximum distances (see the module
//! [`super`]).

use super::{border_source, normal_at, reach_of, tensor, Failure, Junctions, Sink};
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::functions::DistanceFunction;
use crate::sizing::plan::EntitySet;
use crate::sizing::propagation::{ClosestPoint, PropagationOptions, Source};
use crate::topology::Topology;

pub(crate) fn run<S: Sink>(
    graph: &MeshGraph,
    topology: &Topology,
    perpendicular: &DistanceFunction,
    parallel: &DistanceFunction,
    borders: &EntitySet,
    options: &PropagationOptions,
    sink: S,
) -> Result<S::Output, Failure> {
    let source = border_source(graph, topology, borders, true)?;
    let junctions = Junctions::new(&source);
    let reach = reach_of(&[perpendicular.max_distance(), parallel.max_distance()]);
    sink.take_source(graph, &source, reach, options, |v, c| {
        border_tensor(graph, &source, &junctions, perpendicular, parallel, v, c)
    })
}

/// The tensor of vertex `v` from its closest point `c`. Always inlined, so that a sink
/// that evaluates every vertex in one loop has it there, with what `c` holds that it
/// does not read (side, abscissa) left uncomputed.
#[inline(always)]
fn border_tensor(
    graph: &MeshGraph,
    source: &Source,
    junctions: &Junctions,
    perpendicular: &DistanceFunction,
    parallel: &DistanceFunction,
    v: usize,
    c: &ClosestPoint,
) -> Result<Option<SizeTensor>, Failure> {
    let n = normal_at(source, junctions, graph.point(v), c);
    tensor(v, n, perpendicular.eval(c.distance), parallel.eval(c.distance)).map(Some)
}
