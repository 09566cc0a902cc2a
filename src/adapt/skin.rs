//! The LAYER step of `adapt` (the thesis's `--Use-Layer`): once the loop has stopped of
//! itself, the recipe's skin is inserted into the best mesh, the band between the skin
//! and the kept triangles is remeshed to the recipe's field on the best mesh, and the
//! result carries that field as every iteration's mesh does (`metric`, `size_tensor`,
//! `h1`, `h2`, `anisotropy`, `axis1`, `axis2`): at each of its points the field of the
//! best mesh, interpolated (Log-Euclidean) where the point is new.
//!
//! The skinned mesh is the run's result: the caller writes it and the history that
//! describes it ([`LayerRecord`]) as one set, so that the history's size, CRC and counts
//! are those of the file on disk.

use smartmesh_formats::{CellKind, TaggedMesh};

use crate::history::LayerRecord;
use crate::layer::{self, LayerError, LayerOptions, Layered};
use crate::metric::{SizeTensor, Sym2};
use crate::recipe::Recipe;
use crate::recipe::{size_mesh, SizeMeshError};
use crate::remesh::RemeshOptions;

/// Why the skin step failed.
#[derive(Debug, thiserror::Error)]
pub enum SkinError {
    /// Inserting the skin, or remeshing its band.
    #[error("LAYER: {0}")]
    Layer(#[from] LayerError),
    /// Sizing the best mesh with the recipe.
    #[error("LAYER: sizing the best mesh: {0}")]
    Sizing(#[from] SizeMeshError),
}

/// `best` with the skin of `options`, its band remeshed to `recipe`'s field on `best`
/// (at most `max_vertices`), carrying the field's arrays.
pub fn skin(
    best: &TaggedMesh,
    recipe: &Recipe,
    options: &LayerOptions,
    max_vertices: usize,
) -> Result<Layered, SkinError> {
    let inserted = layer::insert(best, options)?;
    let sized = size_mesh(best, recipe, &mut |_| {})?;
    let metric: Vec<Sym2> = sized.field.tensors.iter().map(SizeTensor::to_metric).collect();
    let remesh = RemeshOptions { max_vertices: Some(max_vertices), ..Default::default() };
    // The band remeshed, and the field carried to every point of the result.
    Ok(layer::to_metric::band_to_metric(best, &metric, inserted, &remesh)?)
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
