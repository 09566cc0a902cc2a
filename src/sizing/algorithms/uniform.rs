//! UNIFORM (thesis 2.2.10.1, 4.3.6.1, Algorithm 4.1): the isotropic size `s` on every
//! mesh vertex of the given topological entities — a face's cells' corners (so its
//! bounding curves and points too), a curve's polyline vertices, a point's vertex. No
//! propagation. Vertices are listed once, in increasing index order.

use super::{check_entities, Contribution, Failure, Sink};
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use crate::sizing::plan::EntitySet;
use crate::topology::Topology;

/// The vertices of `on`, sorted, each once; an error for an index out of range.
pub(crate) fn entity_vertices(
    graph: &MeshGraph,
    topology: &Topology,
    on: &EntitySet,
) -> Result<Vec<u32>, Failure> {
    check_entities(topology, on)?;
    let n = graph.num_vertices();
    let mut mark = vec![false; n];
    let mut put = |v: usize| -> Result<(), Failure> {
        match mark.get_mut(v) {
            Some(m) => {
                *m = true;
                Ok(())
            }
            None => Err(Failure::EntityOutOfRange { what: "mesh vertex", index: v, len: n }),
        }
    };
    for &f in &on.faces {
        for &c in &topology.faces[f].cells {
            let cell = topology.surface_cells.get(c).ok_or(Failure::EntityOutOfRange {
                what: "surface cell",
                index: c,
                len: topology.surface_cells.len(),
            })?;
            for &v in cell.vertices() {
                put(v)?;
            }
        }
    }
    for &c in &on.curves {
        for pl in &topology.curves[c].polylines {
            for &v in &pl.vertices {
                put(v)?;
            }
        }
    }
    for &p in &on.points {
        put(topology.points[p].vertex)?;
    }
    Ok((0..n as u32).filter(|&v| mark[v as usize]).collect())
}

pub(crate) fn run<S: Sink>(
    graph: &MeshGraph,
    topology: &Topology,
    size: f64,
    on: &EntitySet,
    sink: S,
) -> Result<S::Output, Failure> {
    if !(SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&size) {
        return Err(Failure::InvalidSize { size });
    }
    let vertices = entity_vertices(graph, topology, on)?;
    let t = SizeTensor::isotropic(size);
    let tensors = vec![t; vertices.len()];
    sink.take_list(Contribution { vertices, tensors, seeds: 0 })
}
