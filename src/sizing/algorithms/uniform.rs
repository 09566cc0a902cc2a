//! UNIFORM (thesis 2.2.10.1, 4.3.6.1, Algorithm 4.1): the isotropic size `s` on every
//! mesh vertex of the given topological entities — a face's cells' corners (so its
//! bounding curves and points too), a curve's polyline vertices, a point's vertex. No
//! propagation. Vertices are listed once, in increasing index order.
//!
//! In space the same, and a volume's vertices are the corners of its cells (those whose
//! tag, as the topology reads it, is the volume's).

use super::{
    check_entities, Around, Arguments, Contribution, Declaration, Failure, Parameter, ParameterKind,
    SizingAlgorithm, Work,
};
use super::{SpaceWork};
use crate::mesh_graph::MeshGraph;
use crate::metric::{SizeTensor, SizeTensor3};
use crate::sizing::space::SpaceMesh;
use super::EntitySet;
use crate::topology::{cell_tag, Topology};

/// The vertices of `on`, sorted, each once; an error for an index out of range.
pub(crate) fn entity_vertices(
    graph: &MeshGraph,
    topology: &Topology,
    on: &EntitySet,
) -> Result<Vec<u32>, Failure> {
    let mut mark = vec![false; graph.num_vertices()];
    mark_entity_vertices(&mut mark, topology, on)?;
    Ok((0..mark.len() as u32).filter(|&v| mark[v as usize]).collect())
}

/// Marks the vertices of the points, curves and faces of `on` (not its volumes).
fn mark_entity_vertices(
    mark: &mut [bool],
    topology: &Topology,
    on: &EntitySet,
) -> Result<(), Failure> {
    check_entities(topology, on)?;
    let n = mark.len();
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
    Ok(())
}

/// The vertices of `on` on a mesh in space, volumes included, sorted, each once.
pub(crate) fn entity_vertices_in_space(
    mesh: &SpaceMesh<'_>,
    topology: &Topology,
    on: &EntitySet,
) -> Result<Vec<u32>, Failure> {
    let mut mark = vec![false; mesh.num_vertices()];
    mark_entity_vertices(&mut mark, topology, on)?;
    mark_volume_vertices(mesh, topology, &on.volumes, &mut mark)?;
    Ok((0..mark.len() as u32).filter(|&v| mark[v as usize]).collect())
}

/// Marks in `mark` (one per vertex) the corners of the volume cells of the
/// topological volumes `volumes` (indices into the topology's volumes): the cells whose
/// tag ([`cell_tag`]) is a volume's.
pub(crate) fn mark_volume_vertices(
mesh: &SpaceMesh<'_>,
    topology: &Topology,
    volumes: &[usize],
    mark: &mut [bool],
) -> Result<(), Failure> {
    if volumes.is_empty() {
        return Ok(());
    }
    let all = topology.space.as_ref().map_or(&[][..], |s| &s.volumes[..]);
    let mut tags = Vec::with_capacity(volumes.len());
    for &v in volumes {
        let volume = all.get(v).ok_or(Failure::EntityOutOfRange {
            what: "volume",
            index: v,
            len: all.len(),
        })?;
        tags.push(volume.tag);
    }
    tags.sort_unstable();
    let n = mark.len();
    for block in mesh.tagged().blocks.iter().filter(|b| b.kind.dim() == 3) {
        let corners = block.kind.linear().nodes_per_cell();
        for (i, cell) in block.cells().enumerate() {
            let tag = cell_tag(block.physical[i], block.geometrical[i]);
            if tags.binary_search(&tag).is_err() {
                continue;
            }
            for &x in cell.iter().take(corners) {
                let x = x as usize;
                *mark.get_mut(x).ok_or(Failure::EntityOutOfRange {
                    what: "mesh vertex",
                    index: x,
                    len: n,
                })? = true;
            }
        }
    }
    Ok(())
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
                kind: ParameterKind::Regions { dimensions: &[2, 1, 0], optional: false, lift: true },
                line_break_after: false,
                doc: "Where it applies: faces, curves or points (volumes and surfaces in space).",
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

    const IN_SPACE: bool = true;

    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        let size = self.size;
        if !(SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&size) {
            return Err(Failure::InvalidSize { size });
        }
        let vertices = entity_vertices_in_space(mesh, topology, &self.on)?;
        let tensors = vec![SizeTensor3::isotropic(size); vertices.len()];
        Ok(SpaceWork::Listed { vertices, tensors })
    }
}
