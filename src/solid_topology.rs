//! The volumes of a 3D mesh as `info` reports them: the topology's volumes
//! ([`crate::topology::TopoVolume`], the volume cells sharing a tag and the surfaces
//! bounding each) with the measure of each, the sum of its cells' signed volumes.
//!
//! Second-order cells are measured as [`crate::signed_volume`] does. Cost: one pass over
//! the volume cells, plus the topology's.

use std::collections::BTreeMap;

use serde::Serialize;
use smartmesh_formats::TaggedMesh;

use crate::quality3d::signed_volume;
use crate::topology::{cell_tag, Topology};

/// One topological volume.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TopoVolume {
    /// The tag (physical, or geometrical when the cells have no physical tag).
    pub tag: i32,
    /// Its name, when the file names it.
    pub name: Option<String>,
    /// Volume cells carrying it.
    pub cells: usize,
    /// The sum of its cells' signed volumes ([`signed_volume`]).
    pub volume: f64,
    /// Cell faces on its boundary.
    pub boundary_faces: usize,
    /// The surfaces its boundary faces lie on, by tag.
    pub bounded_by: Vec<BoundingSurface>,
    /// Boundary faces no surface cell of the file covers.
    pub untagged_faces: usize,
}

/// A surface on the boundary of a volume.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundingSurface {
    /// The surface's tag.
    pub tag: i32,
    /// Its name, when the file names it.
    pub name: Option<String>,
    /// The volume's boundary faces on it.
    pub faces: usize,
}

/// The topological volumes of `mesh` (whose topology is `topo`), by tag, measured; empty
/// when it has no volume cell.
pub(crate) fn volumes(mesh: &TaggedMesh, topo: &Topology) -> Vec<TopoVolume> {
    let Some(space) = &topo.space else { return Vec::new() };
    let mut measure: BTreeMap<i32, f64> = BTreeMap::new();
    let mut p = Vec::with_capacity(27);
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
        let n = b.kind.nodes_per_cell();
        for (cell, (&ph, &g)) in b.cells().zip(b.physical.iter().zip(&b.geometrical)) {
            p.clear();
            p.extend(cell[..n].iter().map(|&i| mesh.points[i as usize]));
            *measure.entry(cell_tag(ph, g)).or_insert(0.0) +=
                signed_volume(b.kind, &p).unwrap_or(0.0);
        }
    }
    space
        .volumes
        .iter()
        .map(|v| TopoVolume {
            tag: v.tag,
            name: v.name.clone(),
            cells: v.cells,
            volume: measure.get(&v.tag).copied().unwrap_or(0.0),
            boundary_faces: v.boundary_faces,
            bounded_by: v
                .bounded_by
                .iter()
                .map(|&(f, faces)| BoundingSurface {
                    tag: topo.faces[f].tag,
                    name: topo.faces[f].name.clone(),
                    faces,
                })
                .collect(),
            untagged_faces: v.untagged_faces,
        })
        .collect()
}
