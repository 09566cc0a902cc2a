//! Point sets as Gmsh holds them: named physical groups of point elements.
//!
//! Medit's `Corners` and `RequiredVertices` are sets of vertices (the points MMG must
//! keep); Gmsh has no sets, but a physical group of dimension 0 named after the set,
//! holding one point entity per vertex, says the same and reads back in Gmsh, meshio
//! and smartmesh as topological points. So before a mesh is written as MSH its point
//! sets become Vertex cells:
//! - each set gets a new 0D physical tag (after every 0D tag in use), named after it;
//! - a vertex that already has a Vertex cell with a physical tag keeps it, and its entity
//!   lists the set's group too (`entities[(0, g)]`, which the MSH writers read); any other
//!   vertex gets one new Vertex cell, on a new point entity, whatever the number of sets
//!   it is in, and its entity lists every such set's group;
//! - the new cells come after all others, so cell indices (cell sets) do not move; cell
//!   data get 0 for them.

use std::collections::BTreeMap;

use crate::{CellBlock, CellKind, NodeIndex, TaggedMesh};

/// `mesh` with its point sets as Vertex cells (see the module documentation); `None`
/// when it has no point set.
pub(crate) fn as_vertex_cells(mesh: &TaggedMesh) -> Option<TaggedMesh> {
    if mesh.point_sets.is_empty() {
        return None;
    }
    let mut out = mesh.clone();
    let sets = std::mem::take(&mut out.point_sets);

    // Tags in use, so that new ones do not collide.
    let vertex_cells: Vec<_> = mesh.cells().filter(|c| c.0 == CellKind::Vertex).collect();
    let mut next_physical = vertex_cells
        .iter()
        .map(|c| c.2)
        .chain(mesh.tag_names.keys().filter(|k| k.0 == 0).map(|k| k.1))
        .chain(mesh.entities.iter().filter(|(k, _)| k.0 == 0).flat_map(|(_, v)| v.iter().copied()))
        .fold(0, i32::max)
        .saturating_add(1);
    let mut next_entity = vertex_cells
        .iter()
        .map(|c| c.3)
        .chain(mesh.entities.keys().filter(|k| k.0 == 0).map(|k| k.1))
        .fold(0, i32::max)
        .saturating_add(1);
    // The entity of each vertex that has a tagged Vertex cell, with that cell's group.
    let mut entity_of: BTreeMap<usize, (i32, i32)> = BTreeMap::new();
    for &(_, nodes, p, g) in &vertex_cells {
        if p != 0 {
            entity_of.entry(nodes[0] as usize).or_insert((g, p));
        }
    }

    let mut added = CellBlock::new(CellKind::Vertex);
    for (name, items) in &sets {
        let tag = next_physical;
        next_physical = next_physical.saturating_add(1);
        out.tag_names.insert((0, tag), name.clone());
        let mut items = items.clone();
        items.sort_unstable();
        items.dedup();
        for v in items {
            let (g, first) = *entity_of.entry(v).or_insert_with(|| {
                let g = next_entity;
                next_entity = next_entity.saturating_add(1);
                added.push(&[v as NodeIndex], tag, g);
                (g, tag)
            });
            let groups = out.entities.entry((0, g)).or_insert_with(|| vec![first]);
            if !groups.contains(&tag) {
                groups.push(tag);
            }
        }
    }
    if !added.is_empty() {
        for a in out.cell_data.values_mut() {
            let n = a.values.len() + added.len() * a.components;
            a.values.resize(n, 0.0);
        }
        out.blocks.push(added);
    }
    Some(out)
}
