//! The mesh the adaptation loop starts from. A mesh is taken as it is; a planar
//! straight-line graph (a Triangle `.poly`, or any file with no surface cell) must be
//! triangulated first. This is the one place that decides, so that the mesher, once it
//! is part of the build, is called from here.

use std::path::Path;

use smartmesh_formats::{read_path, CellKind, Format, TaggedMesh};

/// Why there is no starting mesh.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// The file could not be read (the error names the file and the line).
    #[error("{0}")]
    Read(#[from] smartmesh_formats::Error),
    /// The input is a planar straight-line graph, and this build has no mesher.
    #[error("{path}: a planar straight-line graph ({lines} segments, no triangle) is not a mesh yet; triangulate it first with `smartmesh mesh` (not part of this build), or give the adapt loop a mesh of the domain (.msh, .mesh, .vtu, .ele …)")]
    NeedsMesher {
        /// The input, as given.
        path: String,
        /// Its segments.
        lines: usize,
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
    Err(StartError::NeedsMesher { path: input.display().to_string(), lines: mesh.num_cells_of(CellKind::Line) + mesh.num_cells_of(CellKind::Line3) })
}
