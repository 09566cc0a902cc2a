//! The mesh as an external remesher wants it: first-order triangles (and, for a mesh in
//! space, tetrahedra), line and vertex cells only, and no vertex that no cell uses.
//!
//! [`prepare`] makes a planar mesh for the 2D tools (points put on z = 0);
//! [`prepare_space`] a mesh in space for `mmg3d_O3` (tetrahedra, with their boundary
//! triangles, lines and vertex cells) or `mmgs_O3` (triangles, lines and vertex cells),
//! coordinates kept. Prisms, pyramids and hexahedra are refused: MMG remeshes
//! tetrahedra only, and splitting them would change the cells a user gave.
//!
//! - quadrangles are split along their first diagonal (thesis 5.4.1: the library works
//!   on triangles), second-order cells keep their corners;
//! - vertices no cell uses (Gmsh keeps a circle's centre) are dropped: MMG would keep
//!   them as isolated points and BAMG has nothing to do with them;
//! - tags, tag names and Gmsh entities are kept; point and cell data and sets are not
//!   (the metric is given separately, and a remesher invalidates everything else).

use smartmesh_formats::{CellKind, NodeIndex, TaggedMesh};

use super::AdapterError;
use crate::metric::Sym2;

/// A mesh ready for a tool, and where its vertices came from.
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    /// Linear triangles, lines and vertex cells over the used vertices.
    pub mesh: TaggedMesh,
    /// For each vertex of `mesh`, its index in the original mesh.
    pub original: Vec<usize>,
}

impl Prepared {
    /// `metric` (one per original vertex) restricted to the prepared vertices.
    pub(crate) fn metric<T: Copy>(&self, metric: &[T]) -> Vec<T> {
        self.original.iter().map(|&v| metric[v]).collect()
    }
}

/// What a tool takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Shape {
    /// A planar mesh of triangles (quadrangles split), put on z = 0.
    Planar,
    /// Triangles in space (`mmgs_O3`).
    Surface,
    /// Tetrahedra with their boundary triangles (`mmg3d_O3`).
    Volume,
}

/// Prepares `mesh`, whose `metric` must have one tensor per vertex.
pub(crate) fn prepare(mesh: &TaggedMesh, metric: &[Sym2]) -> Result<Prepared, AdapterError> {
    prepare_shape(mesh, metric.len(), Shape::Planar)
}

/// Prepares `mesh`, a mesh in space of `shape` ([`Shape::Surface`] or
/// [`Shape::Volume`]) with `n_metric` tensors, one per vertex.
pub(crate) fn prepare_space(
    mesh: &TaggedMesh,
    n_metric: usize,
    shape: Shape,
) -> Result<Prepared, AdapterError> {
    prepare_shape(mesh, n_metric, shape)
}

fn prepare_shape(
    mesh: &TaggedMesh,
    n_metric: usize,
    shape: Shape,
) -> Result<Prepared, AdapterError> {
    if n_metric != mesh.points.len() {
        return Err(AdapterError::Input(format!(
            "{n_metric} metric tensors for {} mesh vertices",
            mesh.points.len()
        )));
    }
    let n = mesh.points.len();
    let mut out = TaggedMesh::new();
    out.tag_names = mesh.tag_names.clone();
    out.entities = mesh.entities.clone();
    out.holes = mesh.holes.clone();
    out.regions = mesh.regions.clone();
    // Blocks in a fixed order: vertices, lines, triangles, tetrahedra.
    let mut vertices = smartmesh_formats::CellBlock::new(CellKind::Vertex);
    let mut lines = smartmesh_formats::CellBlock::new(CellKind::Line);
    let mut triangles = smartmesh_formats::CellBlock::new(CellKind::Triangle);
    let mut tetrahedra = smartmesh_formats::CellBlock::new(CellKind::Tetra);
    for (kind, nodes, p, g) in mesh.cells() {
        if let Some(&bad) = nodes.iter().find(|&&v| v as usize >= n) {
            return Err(AdapterError::Input(format!(
                "a {} cell refers to vertex {bad}; the mesh has {n}",
                kind.name()
            )));
        }
        match kind {
            CellKind::Vertex => vertices.push(nodes, p, g),
            CellKind::Line | CellKind::Line3 => lines.push(&nodes[..2], p, g),
            CellKind::Triangle | CellKind::Triangle6 => triangles.push(&nodes[..3], p, g),
            CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 if shape == Shape::Planar => {
                triangles.push(&[nodes[0], nodes[1], nodes[2]], p, g);
                triangles.push(&[nodes[0], nodes[2], nodes[3]], p, g);
            }
            CellKind::Tetra | CellKind::Tetra10 if shape == Shape::Volume => {
                tetrahedra.push(&nodes[..4], p, g)
            }
            _ => return Err(AdapterError::Kind(refused(kind, shape))),
        }
    }
    let (empty, what) = match shape {
        Shape::Planar => (triangles.is_empty(), "no triangle or quadrangle to remesh"),
        Shape::Surface => (triangles.is_empty(), "no triangle to remesh (mmgs remeshes surfaces)"),
        Shape::Volume => (
            tetrahedra.is_empty(),
            "no tetrahedron to remesh (mmg3d remeshes tetrahedral meshes; a surface goes to mmgs)",
        ),
    };
    if empty {
        return Err(AdapterError::Kind(format!("the mesh has {what}")));
    }
    // Renumber the used vertices in their original order.
    let mut new_index = vec![NodeIndex::MAX; n];
    for b in [&vertices, &lines, &triangles, &tetrahedra] {
        for &v in &b.nodes {
            new_index[v as usize] = 0;
        }
    }
    let mut original = Vec::with_capacity(n);
    for (v, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            // Fewer used vertices than the indices of the input can name.
            *slot = original.len() as NodeIndex;
            original.push(v);
        }
    }
    for mut b in [vertices, lines, triangles, tetrahedra] {
        if b.is_empty() {
            continue;
        }
        for v in &mut b.nodes {
            *v = new_index[*v as usize];
        }
        out.blocks.push(b);
    }
    out.points = match shape {
        Shape::Planar => {
            original.iter().map(|&v| [mesh.points[v][0], mesh.points[v][1], 0.0]).collect()
        }
        Shape::Surface | Shape::Volume => original.iter().map(|&v| mesh.points[v]).collect(),
    };
    Ok(Prepared { mesh: out, original })
}

/// Why a cell of `kind` cannot go to a tool of `shape`.
fn refused(kind: CellKind, shape: Shape) -> String {
    let name = kind.name();
    match shape {
        Shape::Planar => format!(
            "{name} cells: the 2D remeshers take no volume cells (a tetrahedral mesh goes to mmg3d, --adapter mmg3d)"
        ),
        Shape::Surface if kind.dim() == 3 => format!(
            "{name} cells: mmgs remeshes triangulated surfaces; a tetrahedral mesh goes to mmg3d (--adapter mmg3d)"
        ),
        Shape::Surface => format!("{name} cells: mmgs takes triangles, lines and vertices only"),
        Shape::Volume => format!(
            "{name} cells: mmg3d remeshes tetrahedra (with their triangles, lines and vertices) only; split other volume cells first"
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_quads_drops_unused_vertices_and_reindexes_the_metric() {
        let mut m = TaggedMesh::new();
        m.points = vec![
            [9.0, 9.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        m.block_mut(CellKind::Quad).push(&[1, 2, 3, 4], 7, 1);
        m.block_mut(CellKind::Line).push(&[1, 2], 3, 2);
        let metric: Vec<Sym2> = (0..5).map(|i| Sym2::new(i as f64 + 1.0, 0.0, 1.0)).collect();
        let p = prepare(&m, &metric).unwrap();
        assert_eq!(p.mesh.points.len(), 4);
        assert_eq!(p.original, [1, 2, 3, 4]);
        assert_eq!(p.mesh.num_cells_of(CellKind::Triangle), 2);
        assert_eq!(p.mesh.num_cells_of(CellKind::Line), 1);
        assert!(p.mesh.cells().all(|(_, _, phys, _)| phys == 7 || phys == 3));
        assert_eq!(p.metric(&metric)[0].a, 2.0);
        assert!(prepare(&m, &metric[..4]).is_err());
    }

    #[test]
    fn a_mesh_in_space_keeps_z_and_goes_to_the_tool_of_its_kind() {
        let mut m = TaggedMesh::new();
        m.points = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [5.0, 5.0, 5.0],
        ];
        m.block_mut(CellKind::Tetra).push(&[0, 1, 2, 3], 10, 10);
        m.block_mut(CellKind::Triangle).push(&[0, 2, 1], 1, 1);
        let p = prepare_space(&m, 5, Shape::Volume).unwrap();
        assert_eq!(p.original, [0, 1, 2, 3]);
        assert_eq!(p.mesh.points[3], [0.0, 0.0, 1.0]);
        assert_eq!(p.mesh.num_cells_of(CellKind::Tetra), 1);
        let e = prepare_space(&m, 5, Shape::Surface).unwrap_err().to_string();
        assert!(e.contains("mmg3d"), "{e}");
        let e = prepare(&m, &[Sym2::new(1.0, 0.0, 1.0); 5]).unwrap_err().to_string();
        assert!(e.contains("mmg3d"), "{e}");
        m.blocks.retain(|b| b.kind == CellKind::Triangle);
        let e = prepare_space(&m, 5, Shape::Volume).unwrap_err().to_string();
        assert!(e.contains("mmgs"), "{e}");
        assert!(prepare_space(&m, 4, Shape::Surface).is_err());
    }
}
