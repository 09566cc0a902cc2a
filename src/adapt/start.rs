//! The mesh the adaptation loop starts from. A mesh is taken as it is; a planar
//! straight-line graph (a Triangle `.poly`, or any file with no surface cell) is
//! triangulated first by [`crate::mesher`] with its default options (Triangle's `-pq`:
//! quality triangles, no area bound): the loop refines it to the recipe's field.

use std::path::Path;

use smartmesh_formats::{read_path, CellKind, Format, TaggedMesh};

use crate::mesher::{triangulate, MeshOptions};

/// Why there is no starting mesh.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// The file could not be read (the error names the file and the line).
    #[error("{0}")]
    Read(#[from] smartmesh_formats::Error),
    /// The input is a planar straight-line graph that the mesher could not triangulate.
    #[error("{path}: {source}")]
    Mesher {
        /// The input, as given.
        path: String,
        /// What the mesher said.
        source: crate::mesher::MeshError,
    },
}

/// Whether `mesh` has cells the loop can size and remesh.
fn has_surface(mesh: &TaggedMesh) -> bool {
    mesh.cells().any(|c| matches!(c.0, CellKind::Triangle | CellKind::Triangle6 | CellKind::Quad | CellKind::Quad8 | CellKind::Quad9))
}

/// The starting mesh of `input` (read as `format` when given, else by extension).
pub fn starting_mesh(input: &Path, format: Option<Format>) -> Result<TaggedMesh, StartError> {
    let mesh = read_path(input, format.or_else(|| Format::from_path(input)))?;
    if has_surface(&mesh) {
        return Ok(mesh);
    }
    triangulate(&mesh, &MeshOptions::default()).map_err(|source| StartError::Mesher { path: input.display().to_string(), source })
}
