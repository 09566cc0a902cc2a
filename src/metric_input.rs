//! Where a command's metric field comes from: `--metric M`, a mesh file whose point data
//! `metric` lives on the vertices of the mesh being looked at (as `smartmesh size -o
//! M.vtu` writes it), or else the mesh's own `metric` array. `info` and `report` share
//! this, so that both accept the same files and refuse them with the same messages.

use std::path::Path;

use crate::conformity::{metric_field, MetricFieldError};
use crate::formats::{read_path, Format, TaggedMesh};
use crate::metric::Sym2;

/// The name of the point-data array that carries a metric.
pub const METRIC: &str = "metric";

/// A metric field and where it was found.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedMetric {
    /// One SPD tensor per vertex of the mesh.
    pub field: Vec<Sym2>,
    /// In words: "`metric` of FILE".
    pub source: String,
}

/// Why no metric field could be had.
#[derive(Debug, thiserror::Error)]
pub enum MetricInputError {
    /// The metric file could not be read.
    #[error(transparent)]
    Read(#[from] crate::formats::Error),
    /// The array is missing, of the wrong shape, or holds a tensor that is not a metric.
    #[error("{path}: {error}")]
    Field {
        /// The file that holds (or lacks) the array.
        path: String,
        /// What is wrong with it.
        error: MetricFieldError,
    },
    /// The metric file has another number of vertices than the mesh.
    #[error("{path}: point data `metric` has {items} items, but {mesh} has {vertices} vertices (the metric must live on the mesh's own vertices)")]
    Count {
        /// The metric file.
        path: String,
        /// Its items.
        items: usize,
        /// The mesh file.
        mesh: String,
        /// The mesh's vertices.
        vertices: usize,
    },
}

/// The metric on `mesh` (read from `mesh_path`): from the file `metric_path` when given,
/// else the mesh's own `metric` array; `Ok(None)` when neither is asked for nor present.
pub fn load(
    mesh: &TaggedMesh,
    mesh_path: &Path,
    metric_path: Option<&Path>,
    metric_format: Option<Format>,
) -> Result<Option<LoadedMetric>, MetricInputError> {
    match metric_path {
        Some(p) => {
            let other = read_path(p, metric_format.or_else(|| Format::from_path(p)))?;
            from_other(mesh, mesh_path, &other, p).map(Some)
        }
        None => {
            if !mesh.point_data.contains_key(METRIC) {
                return Ok(None);
            }
            let field = metric_field(mesh, METRIC).map_err(|error| MetricInputError::Field {
                path: mesh_path.display().to_string(),
                error,
            })?;
            Ok(Some(LoadedMetric {
                field,
                source: format!("`{METRIC}` of {}", mesh_path.display()),
            }))
        }
    }
}

/// The `metric` array of `other` (read from `other_path`) as a field on `mesh`'s vertices.
pub fn from_other(
    mesh: &TaggedMesh,
    mesh_path: &Path,
    other: &TaggedMesh,
    other_path: &Path,
) -> Result<LoadedMetric, MetricInputError> {
    let path = other_path.display().to_string();
    let Some(array) = other.point_data.get(METRIC) else {
        // Let metric_field word the error (it lists the arrays there are).
        let error = metric_field(other, METRIC)
            .err()
            .unwrap_or(MetricFieldError::Missing { name: METRIC.into(), available: "none".into() });
        return Err(MetricInputError::Field { path, error });
    };
    if array.len() != mesh.points.len() {
        return Err(MetricInputError::Count {
            path,
            items: array.len(),
            mesh: mesh_path.display().to_string(),
            vertices: mesh.points.len(),
        });
    }
    // Validate against `mesh`'s cells: a vertex that no cell of *this* mesh uses may
    // carry anything.
    let mut carrier = TaggedMesh::new();
    carrier.points.clone_from(&mesh.points);
    carrier.blocks.clone_from(&mesh.blocks);
    carrier.point_data.insert(METRIC.to_string(), array.clone());
    let field = metric_field(&carrier, METRIC)
        .map_err(|error| MetricInputError::Field { path: path.clone(), error })?;
    Ok(LoadedMetric { field, source: format!("`{METRIC}` of {path}") })
}
