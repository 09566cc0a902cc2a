//! The mesh the adaptation loop starts from. A mesh is taken as it is; a planar
//! straight-line graph (a Triangle `.poly`, or any file with no surface cell) is
//! triangulated first by [`crate::mesher`] with its default options (Triangle's `-pq`:
//! quality triangles, no area bound): the loop refines it to the recipe's field.

use std::path::Path;

use smartmesh_formats::{read_path_reported, CellKind, Format, TaggedMesh};

use crate::mesher::{triangulate_periodic, MeshOptions};
use crate::periodic::PeriodicPair;

/// Why there is no starting mesh.
#[derive(Debug, thiserror::Error)]
pub enum StartError {
    /// The file could not be read (the error names the file and the line).
    #[error("{0}")]
    Read(#[from] smartmesh_formats::Error),
    /// The input does not lie in one plane z = const ([`crate::plane`]).
    #[error("{path}: {source}")]
    NotPlanar {
        /// The input, as given.
        path: String,
        /// The point off the plane.
        source: crate::planar::NotPlanar,
    },
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
    mesh.cells().any(|c| {
        matches!(
            c.0,
            CellKind::Triangle
                | CellKind::Triangle6
                | CellKind::Quad
                | CellKind::Quad8
                | CellKind::Quad9
        )
    })
}

/// The starting mesh of `input` (read as `format` when given, else by extension), a
/// graph meshed with the sides of `pairs` matched vertex to vertex.
pub fn starting_mesh(
    input: &Path,
    format: Option<Format>,
    pairs: &[PeriodicPair],
) -> Result<TaggedMesh, StartError> {
    Ok(start_sized(input, format, None, pairs)?.mesh)
}

/// Where the loop starts: the mesh, and the vertices of the geometry that every
/// remeshing must keep.
#[derive(Debug, Clone)]
pub struct Start {
    /// The starting mesh.
    pub mesh: TaggedMesh,
    /// For a planar straight-line graph, the vertices of its segments (the geometry:
    /// boundaries stay on its segments when these stay vertices); empty for a mesh,
    /// whose boundary is taken as it is.
    pub geometry_points: Vec<[f64; 2]>,
    /// What the reader could not keep, and the second-order cells made linear.
    pub notes: Vec<String>,
    /// The z of the input's plane ([`crate::planar::plane`]): the loop computes in (x, y),
    /// and its outputs go back to this plane ([`crate::planar::place`]).
    pub plane_z: f64,
}

/// The starting mesh of `input` and its geometry's vertices (see [`Start`]).
pub fn start(input: &Path, format: Option<Format>) -> Result<Start, StartError> {
    start_sized(input, format, None, &[])
}

/// [`start`], a planar straight-line graph meshed uniformly to about `vertices`
/// vertices when given (edge length from the area of its bounding box: a solver's first
/// solution needs a mesh that resolves something), else with the mesher's defaults; the
/// sides of `pairs` meshed matched vertex to vertex ([`crate::mesher::triangulate_periodic`];
/// a mesh is taken as it is, its pairs left to the caller).
pub fn start_sized(
    input: &Path,
    format: Option<Format>,
    vertices: Option<f64>,
    pairs: &[PeriodicPair],
) -> Result<Start, StartError> {
    let (mut mesh, report) =
        read_path_reported(input, format.or_else(|| Format::from_path(input)))?;
    let mut notes = report.notes;
    let plane_z = crate::planar::plane(&mesh)
        .map_err(|source| StartError::NotPlanar { path: input.display().to_string(), source })?;
    // The loop sizes and remeshes linear cells.
    notes.extend(mesh.linearise());
    if has_surface(&mesh) {
        return Ok(Start { mesh, geometry_points: Vec::new(), notes, plane_z });
    }
    let mut options = MeshOptions::default();
    if let (Some(n), Some((lo, hi))) = (vertices, mesh.bounding_box()) {
        // A mesh of equilateral triangles of edge h has about 2A/(√3 h²) vertices.
        let area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
        let h = (2.0 * area / (3f64.sqrt() * n.max(1.0))).sqrt();
        options.size = Some(h).filter(|h| h.is_finite() && *h > 0.0);
    }
    let triangulated = triangulate_periodic(&mesh, &options, pairs)
        .map_err(|source| StartError::Mesher { path: input.display().to_string(), source })?;
    let mut on_segment = vec![false; mesh.points.len()];
    for (kind, nodes, _, _) in mesh.cells() {
        if kind.dim() == 1 {
            for &v in nodes {
                on_segment[v as usize] = true;
            }
        }
    }
    let geometry_points = mesh
        .points
        .iter()
        .zip(&on_segment)
        .filter(|(_, &s)| s)
        .map(|(p, _)| [p[0], p[1]])
        .collect();
    Ok(Start { mesh: triangulated, geometry_points, notes, plane_z })
}
