//! The mesh as an external remesher wants it: first-order triangles, line and vertex
//! cells only, and no vertex that no cell uses.
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
    pub(crate) fn metric(&self, metric: &[Sym2]) -> Vec<Sym2> {
        self.original.iter().map(|&v| metric[v]).collect()
    }
}

/// Prepares `mesh`, whose `metric` must have one tensor per vertex.
pub(crate) fn prepare(mesh: &TaggedMesh, metric: &[Sym2]) -> Result<Prepared, AdapterError> {
    if metric.len() != mesh.points.len() {
        return Err(AdapterError::Input(format!(
            "{} metric tensors for {} mesh vertices",
            metric.len(),
            mesh.points.len()
        )));
    }
    let n = mesh.points.len();
    let mut out = TaggedMesh::new();
    out.tag_names = mesh.tag_names.clone();
    out.entities = mesh.entities.clone();
    out.holes = mesh.holes.clone();
    out.regions = mesh.regions.clone();
    // Blocks in a fixed order: vertices, lines, triangles.
    let mut vertices = smartmesh_formats::CellBlock::new(CellKind::Vertex);
    let mut lines = smartmesh_formats::CellBlock::new(CellKind::Line);
    let mut triangles = smartmesh_formats::CellBlock::new(CellKind::Triangle);
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
            CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 => {
                triangles.push(&[nodes[0], nodes[1], nodes[2]], p, g);
                triangles.push(&[nodes[0], nodes[2], nodes[3]], p, g);
            }
            _ => {
                return Err(AdapterError::Input(format!(
                    "{} cells: the 2D remeshers take no volume cells",
                    kind.name()
                )))
            }
        }
    }
    if triangles.is_empty() {
        return Err(AdapterError::Input("the mesh has no triangle or quadrangle to remesh".into()));
    }
    // Renumber the used vertices in their original order.
    let mut new_index = vec![NodeIndex::MAX; n];
    for b in [&vertices, &lines, &triangles] {
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
    for mut b in [vertices, lines, triangles] {
        if b.is_empty() {
            continue;
        }
        for v in &mut b.nodes {
            *v = new_index[*v as usize];
        }
        out.blocks.push(b);
    }
    out.points = original.iter().map(|&v| [mesh.points[v][0], mesh.points[v][1], 0.0]).collect();
    Ok(Prepared { mesh: out, original })
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
}
