//! DISTANCE_TO_POINT (thesis 2.2.10.2, 4.3.6.2, Algorithm 4.2): the isotropic size
//! `function(d)`, d the Euclidean distance from the vertex to the nearest source point,
//! on every vertex within the function's maximum distance.
//!
//! Sources are topological points; a curve given as a source contributes each vertex of
//! its polylines as a point (not its segments: for the distance to a curve use
//! DISTANCE_TO_BORDER). Several sources act as one set: the distance is to the nearest,
//! as in the other algorithms, rather than one run per point intersected (which differs
//! only for functions that shrink away from the source, thesis 7.4.3).

use super::{check_entities, Failure, Sink};
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::functions::DistanceFunction;
use crate::sizing::plan::EntitySet;
use crate::sizing::propagation::{PropagationOptions, SourceBuilder};
use crate::topology::Topology;

pub(crate) fn run<S: Sink>(
    graph: &MeshGraph,
    topology: &Topology,
    function: &DistanceFunction,
    sources: &EntitySet,
    options: &PropagationOptions,
    sink: S,
) -> Result<S::Output, Failure> {
    check_entities(topology, sources)?;
    if let Some(&index) = sources.faces.first() {
        return Err(Failure::UnsupportedEntity { what: "face", index });
    }
    let mut b = SourceBuilder::new(graph);
    for &p in &sources.points {
        b.topology_point(topology, p);
    }
    for &c in &sources.curves {
        for pl in &topology.curves[c].polylines {
            for &v in &pl.vertices {
                b.vertex(v);
            }
        }
    }
    let source = b.build()?;
    if source.segments().is_empty() {
        return Err(Failure::NoSource);
    }
    sink.take_source(graph, &source, function.max_distance(), options, |v, c| {
        let h = function.eval(c.distance);
        SizeTensor::try_new([1.0, 0.0], h, h).map(Some).ok_or(Failure::Degenerate { vertex: v })
    })
}
