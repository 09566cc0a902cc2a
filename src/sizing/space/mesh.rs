//! A mesh in space as the 3D sizing driver walks it: the tagged mesh (points, cells,
//! point data, for the algorithms that read them) and its vertex adjacency over every
//! mesh edge — the edges of the volume cells (through the formats crate's one face
//! table, [`CellKind::faces`]), of the surface cells and of the line cells, each once —
//! for the gradation pass.
//!
//! Built once per sizing. Deterministic: every neighbour list is sorted by vertex index.
//! Cost: one sort of the cells' edges, O(E log E); indices are `u32`.

use smartmesh_formats::{CellKind, TaggedMesh};

use crate::mesh_graph::MeshGraphError;
use crate::topology::Topology;

/// A mesh in space with its vertex adjacency (see the module header).
#[derive(Debug, Clone)]
pub struct SpaceMesh<'a> {
    mesh: &'a TaggedMesh,
    /// CSR offsets into `adjacent`, one run per vertex.
    offsets: Vec<u32>,
    adjacent: Vec<u32>,
}

impl<'a> SpaceMesh<'a> {
    /// The mesh `mesh` with the edges of its cells and of the `topology` found on it
    /// (its surface and curve edges). An error when a cell names a vertex the mesh does
    /// not have, or when the mesh is too large for `u32` indices.
    pub fn new(mesh: &'a TaggedMesh, topology: &Topology) -> Result<SpaceMesh<'a>, MeshGraphError> {
        let n = mesh.points.len();
        if n >= u32::MAX as usize {
            return Err(MeshGraphError::TooLarge(n));
        }
        let mut edges: Vec<(u32, u32)> = Vec::new();
        let mut push = |a: usize, b: usize| -> Result<(), MeshGraphError> {
            for v in [a, b] {
                if v >= n {
                    return Err(MeshGraphError::VertexOutOfRange { index: v, len: n });
                }
            }
            if a != b {
                edges.push((a.min(b) as u32, a.max(b) as u32));
            }
            Ok(())
        };
        for block in &mesh.blocks {
            let kind = block.kind.linear();
            let polygons: &[&[usize]] = match kind.dim() {
                3 => kind.faces(),
                2 if kind == CellKind::Triangle => &[&[0, 1, 2]],
                2 => &[&[0, 1, 2, 3]],
                1 => &[&[0, 1]],
                _ => &[],
            };
            for cell in block.cells() {
                for poly in polygons {
                    for i in 0..poly.len() {
                        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
                        if let (Some(&a), Some(&b)) = (cell.get(a), cell.get(b)) {
                            push(a as usize, b as usize)?;
                        }
                    }
                }
            }
        }
        for &([a, b], _) in &topology.edges {
            push(a, b)?;
        }
        edges.sort_unstable();
        edges.dedup();
        if 2 * edges.len() >= u32::MAX as usize {
            return Err(MeshGraphError::TooLarge(2 * edges.len()));
        }
        let mut offsets = vec![0u32; n + 1];
        for &(a, b) in &edges {
            offsets[a as usize + 1] += 1;
            offsets[b as usize + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut adjacent = vec![0u32; 2 * edges.len()];
        for &(a, b) in &edges {
            adjacent[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            adjacent[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        // Edges are sorted by (a, b): each run of `a` got its larger ends in order, but
        // the smaller ends of `b` come first only by the order of the pairs; sort runs.
        for v in 0..n {
            adjacent[offsets[v] as usize..offsets[v + 1] as usize].sort_unstable();
        }
        Ok(SpaceMesh { mesh, offsets, adjacent })
    }

    /// The tagged mesh (its cells and point data).
    pub fn tagged(&self) -> &'a TaggedMesh {
        self.mesh
    }

    /// The coordinates of the vertices.
    pub fn points(&self) -> &'a [[f64; 3]] {
        &self.mesh.points
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.mesh.points.len()
    }

    /// Number of mesh edges.
    pub fn num_edges(&self) -> usize {
        self.adjacent.len() / 2
    }

    /// The neighbours of vertex `v`, ascending.
    pub fn neighbours(&self, v: usize) -> &[u32] {
        &self.adjacent[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }
}
