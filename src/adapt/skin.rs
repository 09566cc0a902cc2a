//! The LAYER step of `adapt` (the thesis's `--Use-Layer`): once the loop has stopped of
//! itself, the skin of [`crate::adapt::AdaptOptions::layer`] is inserted into the best
//! mesh, the band between the skin and the kept triangles is remeshed to the best
//! iteration's field (the loop's own, recipe and solver alike: the mesh is not sized
//! again), and the result carries that field as every iteration's mesh does (`metric`,
//! `size_tensor`, `h1`, `h2`, `anisotropy`, `axis1`, `axis2`): at each of its points the
//! field of the best mesh, interpolated (Log-Euclidean) where the point is new.
//!
//! The skinned mesh is the run's result: the loop hands it and the history that
//! describes it ([`LayerRecord`]) to its observer as one set, so that the history's size,
//! CRC and counts are those of the file on disk.

use smartmesh_formats::{CellKind, TaggedMesh};

use crate::history::LayerRecord;
use crate::layer::{self, LayerError, LayerOptions, Layered};
use crate::metric::Sym2;
use crate::remesh::RemeshOptions;
use crate::topology::Topology;

/// Why the skin step failed.
#[derive(Debug, thiserror::Error)]
pub enum SkinError {
    /// Inserting the skin, or remeshing its band.
    #[error("LAYER: {0}")]
    Layer(#[from] LayerError),
}

/// Checks before any work that every wall curve of `options` is a curve of `mesh`.
pub fn check_curves(mesh: &TaggedMesh, options: &LayerOptions) -> Result<(), LayerError> {
    let topo = Topology::from_mesh(mesh);
    for c in &options.curves {
        layer::resolve_curve(&topo, &c.curve)?;
    }
    Ok(())
}

/// `best` with the skin of `options`, its band remeshed to `metric` (one tensor per
/// vertex of `best`, at most `max_vertices`), carrying the field's arrays.
pub fn skin(
    best: &TaggedMesh,
    metric: &[Sym2],
    options: &LayerOptions,
    max_vertices: usize,
) -> Result<Layered, SkinError> {
    let inserted = layer::insert(best, options)?;
    let remesh = RemeshOptions { max_vertices: Some(max_vertices), ..Default::default() };
    // The band remeshed, and the field carried to every point of the result.
    Ok(layer::to_metric::band_to_metric(best, metric, inserted, &remesh)?)
}

/// What the history records of the skin step: the layers and the mesh written.
pub fn record(l: &Layered) -> LayerRecord {
    let count = |k: CellKind| l.mesh.blocks.iter().filter(|b| b.kind == k).map(|b| b.len()).sum();
    LayerRecord {
        layers: l.report.layers,
        columns: l.report.columns,
        thinned_columns: l.report.thinned.len(),
        vertices: l.mesh.points.len(),
        triangles: count(CellKind::Triangle),
        quads: count(CellKind::Quad),
    }
}
