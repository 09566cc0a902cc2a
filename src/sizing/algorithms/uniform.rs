//! UNIFORM (thesis 2.2.10.1, 4.3.6.1, Algorithm 4.1): the isotropic size `s` on every
//! mesh vertex of the given topological entities — a face's cells' corners (so its
//! bounding curves and points too), a curve's polyline vertices, a point's vertex. No
//! propagation. Vertices are listed once, in increasing index order.

use super::{
    check_entities, Around, Arguments, Contribution, Declaration, Failure, Parameter, ParameterKind,
    SizingAlgorithm, Work,
};
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor;
use super::EntitySet;
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

/// UNIFORM: isotropic `size` on every vertex of the entities (a face's vertices include
/// those of its bounding curves and points).
#[derive(Debug, Clone, PartialEq)]
pub struct Uniform {
    /// The size.
    pub size: f64,
    /// Where it applies.
    pub on: EntitySet,
}

impl SizingAlgorithm for Uniform {
    const DECLARATION: Declaration = Declaration {
        keyword: "UNIFORM",
        name: "uniform",
        doc: "The isotropic size SIZE on every mesh vertex of the regions (thesis 4.3.6.1).",
        parameters: &[
            Parameter {
                field: "size",
                aliases: &[],
                keys: &["SIZE"],
                kind: ParameterKind::Size,
                line_break_after: false,
                doc: "The size.",
            },
            Parameter {
                field: "regions",
                aliases: &[],
                keys: &["REGIONS"],
                kind: ParameterKind::Regions { dimensions: &[2, 1, 0], optional: false },
                line_break_after: false,
                doc: "Where it applies: faces, curves or points.",
            },
        ],
    };

    type Tensor<'a> = std::convert::Infallible;

    fn from_arguments(arguments: &mut Arguments) -> Option<Uniform> {
        Some(Uniform { size: arguments.size("size")?, on: arguments.entities("regions")? })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![&self.on]
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        None
    }

    fn work<'a>(
        &'a self,
        graph: &'a MeshGraph,
        topology: &'a Topology,
    ) -> Result<Work<Self::Tensor<'a>>, Failure> {
        let size = self.size;
        if !(SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&size) {
            return Err(Failure::InvalidSize { size });
        }
        let vertices = entity_vertices(graph, topology, &self.on)?;
        let t = SizeTensor::isotropic(size);
        let tensors = vec![t; vertices.len()];
        Ok(Work::Listed(Contribution { vertices, tensors, seeds: 0 }))
    }
}
