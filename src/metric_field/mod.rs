//! A metric field on a mesh: one SPD tensor per vertex, and the one place that reads,
//! checks and interpolates it, so that every command accepts the same files and refuses
//! them with the same messages.
//!
//! Where a field comes from ([`MetricField::read`], [`MetricField::load`]):
//!
//! | given | read as | checked |
//! | --- | --- | --- |
//! | the mesh itself | its point data [`METRIC`] | SPD and finite at every vertex a cell uses |
//! | a mesh file (`.vtu`, `.vtk`, `.msh` with `$NodeData`, `.mesh` with its `.sol`) | its point data [`METRIC`] on the mesh's own vertices | the same count, the same positions (up to 1e-9 of the mesh's extent), SPD |
//! | a Medit `.sol`/`.solb` alone | its type-3 `SolAtVertices`, in the mesh's vertex order, as `mmg2d_O3 MESH -sol X.sol` takes it | the same count, SPD |
//! | a Gmsh data-only `.msh` (`$NodeData` without `$Nodes`/`$Elements`, as `gmsh.view.write` or a solver writes it beside the mesh) | its view `metric` (or its only view), node tag t at vertex t − 1, as the mesh file numbers its nodes | one entry per vertex and no tag beyond them, SPD |
//! | a Gmsh `.pos` view | the tensor (`TT`, `TQ`) records of its last view, as `gmsh -bgm` takes it, at the mesh's vertices ([`pos_view`]) | SPD at every view node |
//!
//! A field is the metric M = R diag(1/h1², 1/h2²) Rᵀ (files carry metrics, not sizes);
//! only the xy block of a 9-component tensor is read.
//!
//! In 3D (`MetricField<Sym3>`, for tetrahedra and surfaces in space) the same files are
//! read by the same functions (`read_field`, `load_field`, `own_field`,
//! `point_data_field`; the 2D names call them), generic over [`FieldTensor`]: the whole
//! 9-component tensor, or 6 components in ParaView's order XX YY ZZ XY YZ XZ, a 3D
//! `.sol` in MMG's order (the formats crate makes it 9 components), and a `.pos` view's
//! `TS`/`TT` records at the mesh's own vertices (`pos_view3`; no interpolation inside a
//! view's tetrahedra yet); positions are compared in x, y and z. Writing is shared too
//! (`write3` says what a 3D field writes). A vertex that no cell uses may carry
//! anything (Gmsh keeps such nodes) and gets the identity.
//!
//! At positions that are not the field's vertices ([`MetricField::interpolate`]) the field
//! is the Log-Euclidean barycentric mean of the corners of the triangle that holds the
//! position, or, outside every triangle, of the nearest triangle at its closest point: the
//! interpolation the remesher uses ([`interpolate`]).
//!
//! Where a field goes ([`MetricField::write`], [`write`](mod@write)): a `.sol`/`.solb`, a `.pos`
//! view, or a mesh file with the field as point data; the remesher's output and the
//! files the adapters hand to MMG and Gmsh are written by the same functions.
//!
//! Who knows what: this module reads and writes files through the formats crate, locates
//! points through [`crate::geometry::TriangleLocator`] and takes the mean from
//! [`crate::metric`]; it knows nothing of the remesher, which uses its [`Interpolator`].

mod expected;
pub(crate) mod interpolate;
pub(crate) mod pos_view;
mod pos_view3;
mod tensor;
pub(crate) mod write;
mod write3;

pub(crate) use expected::planar_triangles;
pub use expected::{expected_vertices, Complexity};
pub use interpolate::{InterpolationError, Interpolator};
pub use tensor::FieldTensor;
pub use write::MetricTarget;

use std::path::Path;

use crate::metric::{SizeTensor, Sym2};
use smartmesh_formats::gmsh::{MshContent, NodeData};
use smartmesh_formats::{read_path, DataArray, Format, TaggedMesh};

/// The name of the point-data array (and of the Gmsh view) that carries a metric, as
/// every reader and writer of smartmesh names it.
pub const METRIC: &str = "metric";

/// A metric field: one SPD tensor per vertex of a mesh, and where it was found; a 2D
/// field ([`Sym2`], the default) or a field on a mesh in space ([`Sym3`](crate::metric::Sym3)).
#[derive(Debug, Clone, PartialEq)]
pub struct MetricField<T: FieldTensor = Sym2> {
    tensors: Vec<T>,
    /// The size tensors the field was made from ([`MetricField::from_sizes`]), kept for
    /// what is written beside the metric.
    sizes: Option<Vec<SizeTensor>>,
    source: String,
}

/// Why a mesh's point data cannot serve as a metric field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MetricFieldError {
    /// No point array of that name.
    #[error("no point data `{name}` (the arrays are: {available})")]
    Missing {
        /// The name looked for.
        name: String,
        /// The arrays the mesh has.
        available: String,
    },
    /// The array is not a tensor (9 components) or a packed symmetric one (3 components
    /// in 2D, 6 in 3D).
    #[error("point data `{name}` has {components} components; a {dim}D metric has {expected}")]
    Shape {
        /// The array's name.
        name: String,
        /// Its number of components.
        components: usize,
        /// The dimension of the metric looked for.
        dim: u8,
        /// The counts it may have.
        expected: &'static str,
    },
    /// One item per vertex is needed.
    #[error("point data `{name}` has {items} items for {vertices} vertices")]
    Count {
        /// The array's name.
        name: String,
        /// Items in the array.
        items: usize,
        /// Vertices of the mesh.
        vertices: usize,
    },
    /// A tensor that is not finite, not symmetric or not positive definite.
    #[error("point data `{name}` at vertex {vertex} (0-based) is not a metric: [[{a}, {b}], [{b2}, {c}]] is {why}")]
    NotSpd {
        /// The array's name.
        name: String,
        /// The vertex index.
        vertex: usize,
        /// m11.
        a: f64,
        /// m12.
        b: f64,
        /// m21.
        b2: f64,
        /// m22.
        c: f64,
        /// What is wrong.
        why: &'static str,
    },
    /// A 3D tensor that is not finite, not symmetric or not positive definite.
    #[error("point data `{name}` at vertex {vertex} (0-based) is not a 3D metric: {} (row-major) is {why}", show_rows(.tensor))]
    NotSpd3 {
        /// The array's name.
        name: String,
        /// The vertex index.
        vertex: usize,
        /// The tensor as read, row-major 3×3.
        tensor: Vec<f64>,
        /// What is wrong.
        why: &'static str,
    },
}

/// A row-major 3×3 tensor as `[[a, b, c], [d, e, f], [g, h, i]]`.
fn show_rows(t: &[f64]) -> String {
    let rows: Vec<String> = t
        .chunks(3)
        .map(|r| format!("[{}]", r.iter().map(|x| x.to_string()).collect::<Vec<_>>().join(", ")))
        .collect();
    format!("[{}]", rows.join(", "))
}

/// Why no metric field could be had from a file.
#[derive(Debug, thiserror::Error)]
pub enum MetricError {
    /// The metric file could not be read.
    #[error(transparent)]
    Read(#[from] smartmesh_formats::Error),
    /// The array is missing, of the wrong shape, or holds a tensor that is not a metric.
    #[error("{path}: {error}")]
    Field {
        /// The file that holds (or lacks) the array.
        path: String,
        /// What is wrong with it.
        error: MetricFieldError,
    },
    /// The metric file has another number of vertices than the mesh.
    #[error("{path}: {what} has {items} items, but {mesh} has {vertices} vertices (the metric must live on the mesh's own vertices)")]
    Count {
        /// The metric file.
        path: String,
        /// What in it was counted.
        what: &'static str,
        /// Its items.
        items: usize,
        /// The mesh file.
        mesh: String,
        /// The mesh's vertices.
        vertices: usize,
    },
    /// The metric file has the mesh's number of vertices, but not at the same places.
    #[error("{path}: vertex {vertex} (0-based) is at {at:?}, but vertex {vertex} of {mesh} is at {expected:?}; the metric must live on the mesh's own vertices")]
    Moved {
        /// The metric file.
        path: String,
        /// The first vertex that differs.
        vertex: usize,
        /// Where the metric file has it (x, y, and z for a 3D field).
        at: Vec<f64>,
        /// The mesh file.
        mesh: String,
        /// Where the mesh has it.
        expected: Vec<f64>,
    },
    /// A file that holds no metric in a form smartmesh reads as one.
    #[error("{path}: {why}")]
    NotAMetric {
        /// The file.
        path: String,
        /// What it lacks.
        why: String,
    },
}

/// What a metric file is, told by its extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// A Medit solution alone.
    Sol,
    /// A Gmsh post-processing view.
    Pos,
    /// A mesh file with point data.
    Mesh,
}

impl Kind {
    fn of(path: &Path, format: Option<Format>) -> Kind {
        if format.is_some() {
            return Kind::Mesh;
        }
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "sol" | "solb" => Kind::Sol,
            "pos" => Kind::Pos,
            _ => Kind::Mesh,
        }
    }
}

impl<T: FieldTensor> MetricField<T> {
    /// A field from its tensors (one per vertex, each SPD) and a description of where it
    /// came from.
    pub fn new(tensors: Vec<T>, source: impl Into<String>) -> MetricField<T> {
        MetricField { tensors, sizes: None, source: source.into() }
    }

    /// The tensors, one per vertex.
    pub fn tensors(&self) -> &[T] {
        &self.tensors
    }

    /// The tensors, one per vertex.
    pub fn into_tensors(self) -> Vec<T> {
        self.tensors
    }

    /// Where the field came from, in words: "`metric` of FILE".
    pub fn source(&self) -> &str {
        &self.source
    }

    /// [`MetricField::from_point_data`] for a field of either dimension (a 3D field reads
    /// 9 components or ParaView's 6).
    pub fn point_data_field(mesh: &TaggedMesh, name: &str) -> Result<Self, MetricFieldError> {
        let array = mesh.point_data.get(name).ok_or_else(|| MetricFieldError::Missing {
            name: name.to_string(),
            available: if mesh.point_data.is_empty() {
                "none".to_string()
            } else {
                mesh.point_data.keys().cloned().collect::<Vec<_>>().join(", ")
            },
        })?;
        let tensors = validate(array, mesh, name)?;
        Ok(MetricField { tensors, sizes: None, source: format!("`{name}`") })
    }

    /// [`MetricField::own`] for a field of either dimension.
    pub fn own_field(mesh: &TaggedMesh, mesh_path: &Path) -> Result<Self, MetricError> {
        let path = mesh_path.display().to_string();
        let field = Self::point_data_field(mesh, METRIC)
            .map_err(|error| MetricError::Field { path: path.clone(), error })?;
        Ok(MetricField { source: format!("`{METRIC}` of {path}"), ..field })
    }

    /// [`MetricField::load`] for a field of either dimension.
    pub fn load_field(
        mesh: &TaggedMesh,
        mesh_path: &Path,
        metric_path: Option<&Path>,
    ) -> Result<Option<Self>, MetricError> {
        match metric_path {
            Some(p) => Self::read_field(p, None, mesh, mesh_path).map(Some),
            None if !mesh.point_data.contains_key(METRIC) => Ok(None),
            None => Self::own_field(mesh, mesh_path).map(Some),
        }
    }

    /// [`MetricField::read`] for a field of either dimension. A 3D `.pos` view (`TS`
    /// records on tetrahedra, `TT` on triangles in space) is read at its nodes, which
    /// must be the mesh's vertices (see `pos_view3`).
    pub fn read_field(
        path: &Path,
        format: Option<Format>,
        mesh: &TaggedMesh,
        mesh_path: &Path,
    ) -> Result<Self, MetricError> {
        match Kind::of(path, format) {
            Kind::Sol => read_sol(path, mesh, mesh_path),
            Kind::Pos => {
                let (name, tensors) = T::read_pos(path, mesh)?;
                Ok(MetricField {
                    tensors,
                    sizes: None,
                    source: format!("view `{name}` of {}", path.display()),
                })
            }
            Kind::Mesh => match read_mesh_or_data(path, format)? {
                MshContent::Mesh(other) => on_same_vertices(mesh, mesh_path, &other, path),
                MshContent::NodeData(data) => on_node_data(mesh, mesh_path, data, path),
            },
        }
    }
}

impl MetricField {
    /// The field named `name` in `mesh`'s point data, one SPD tensor per vertex: a
    /// 9-component tensor (its xy block) or a packed 2D one (m11 m12 m22). Vertices that no
    /// cell uses may carry any value (Gmsh keeps such nodes); they get the identity.
    pub fn from_point_data(mesh: &TaggedMesh, name: &str) -> Result<MetricField, MetricFieldError> {
        Self::point_data_field(mesh, name)
    }

    /// The mesh's own [`METRIC`] array (`mesh` read from `mesh_path`).
    pub fn own(mesh: &TaggedMesh, mesh_path: &Path) -> Result<MetricField, MetricError> {
        Self::own_field(mesh, mesh_path)
    }

    /// The metric on `mesh` (read from `mesh_path`): from the file `metric_path` when
    /// given ([`MetricField::read`]), else the mesh's own [`METRIC`] array; `Ok(None)` when
    /// neither is asked for nor present.
    pub fn load(
        mesh: &TaggedMesh,
        mesh_path: &Path,
        metric_path: Option<&Path>,
    ) -> Result<Option<MetricField>, MetricError> {
        Self::load_field(mesh, mesh_path, metric_path)
    }

    /// The metric file `path` (of `format` when given, else told by its extension) as a
    /// field on `mesh`'s vertices (`mesh` read from `mesh_path`); see the module
    /// documentation for the kinds of file and their checks.
    pub fn read(
        path: &Path,
        format: Option<Format>,
        mesh: &TaggedMesh,
        mesh_path: &Path,
    ) -> Result<MetricField, MetricError> {
        Self::read_field(path, format, mesh, mesh_path)
    }

    /// A field with the mesh it lives on, to be interpolated elsewhere (the input of a
    /// remeshing, for `remesh --measure --background`): a mesh file with its [`METRIC`]
    /// array, a `.pos` view (its records are the triangles), or a `.sol`/`.solb` with the
    /// Medit mesh of the same name beside it (`x.mesh`, else `x.meshb`), as MMG pairs them.
    /// A Gmsh data-only `.msh` has no positions: it is read as a field on `mesh`'s own
    /// vertices (`mesh` read from `mesh_path`, checked as [`MetricField::read`] does), and
    /// no background mesh is returned.
    pub fn read_background(
        path: &Path,
        mesh: &TaggedMesh,
        mesh_path: &Path,
    ) -> Result<(Option<TaggedMesh>, MetricField), MetricError> {
        match Kind::of(path, None) {
            Kind::Pos => {
                let view = pos_view::read_path(path)?;
                let source = format!("view `{}` of {}", view.name(), path.display());
                let (mesh, tensors) = view.into_mesh();
                Ok((Some(mesh), MetricField { tensors, sizes: None, source }))
            }
            Kind::Sol => {
                let mesh_path = ["mesh", "meshb"]
                    .iter()
                    .map(|e| path.with_extension(e))
                    .find(|p| p.is_file())
                    .ok_or_else(|| MetricError::NotAMetric {
                        path: path.display().to_string(),
                        why: format!(
                            "a solution holds values at vertices, not their positions: a background needs its mesh ({} beside it), or give a .pos, .vtu or .msh",
                            path.with_extension("mesh").display()
                        ),
                    })?;
                let bytes = std::fs::read(&mesh_path)
                    .map_err(|e| smartmesh_formats::Error::from(e).with_path(&mesh_path))?;
                let ext = mesh_path.extension().and_then(|e| e.to_str()).unwrap_or("mesh");
                let mesh = smartmesh_formats::read_bytes(
                    Format::Medit,
                    &bytes,
                    &smartmesh_formats::ReadContext::alone(ext),
                )
                .map_err(|e| e.with_path(&mesh_path))?;
                let field = read_sol(path, &mesh, &mesh_path)?;
                Ok((Some(mesh), field))
            }
            Kind::Mesh => match read_mesh_or_data(path, None)? {
                MshContent::Mesh(background) => {
                    let field = MetricField::own(&background, path)?;
                    Ok((Some(background), field))
                }
                MshContent::NodeData(data) => {
                    Ok((None, on_node_data(mesh, mesh_path, data, path)?))
                }
            },
        }
    }

    /// This field (on the vertices of `mesh`) at `points`, by the interpolation the
    /// remesher uses (see the module documentation). Measures any mesh, ours or another
    /// tool's, against the same field.
    pub fn interpolate(
        &self,
        mesh: &TaggedMesh,
        points: &[[f64; 2]],
    ) -> Result<MetricField, InterpolationError> {
        let tensors = interpolate::interpolate(mesh, &self.tensors, points)?;
        Ok(MetricField { tensors, sizes: None, source: format!("{}, interpolated", self.source) })
    }
}

/// The tensors of `array` (point data `name` of `mesh`), checked: the shape, one item per
/// vertex, SPD and finite at every vertex a cell of `mesh` uses.
fn validate<T: FieldTensor>(
    array: &DataArray,
    mesh: &TaggedMesh,
    name: &str,
) -> Result<Vec<T>, MetricFieldError> {
    let packed = array.layout == smartmesh_formats::Layout::Symmetric2;
    if !T::accepts(array.components, packed) {
        return Err(MetricFieldError::Shape {
            name: name.to_string(),
            components: array.components,
            dim: T::DIM,
            expected: T::SHAPES,
        });
    }
    if array.len() != mesh.points.len() {
        return Err(MetricFieldError::Count {
            name: name.to_string(),
            items: array.len(),
            vertices: mesh.points.len(),
        });
    }
    let mut used = vec![false; mesh.points.len()];
    for (_, nodes, _, _) in mesh.cells() {
        for &n in nodes {
            if let Some(u) = used.get_mut(n as usize) {
                *u = true;
            }
        }
    }
    let mut out = Vec::with_capacity(array.len());
    for (v, &in_use) in used.iter().enumerate() {
        match T::from_item(array.item(v), packed) {
            Ok(t) => out.push(t),
            Err(_) if !in_use => out.push(T::IDENTITY),
            Err((why, t)) if T::DIM == 2 => {
                return Err(MetricFieldError::NotSpd {
                    name: name.to_string(),
                    vertex: v,
                    a: t[0],
                    b: t[1],
                    b2: t[2],
                    c: t[3],
                    why,
                })
            }
            Err((why, tensor)) => {
                return Err(MetricFieldError::NotSpd3 {
                    name: name.to_string(),
                    vertex: v,
                    tensor,
                    why,
                })
            }
        }
    }
    Ok(out)
}

/// Why [[a, b], [b2, c]] is not a metric, `None` when it is one.
pub(crate) fn not_a_metric(a: f64, b: f64, b2: f64, c: f64) -> Option<&'static str> {
    if ![a, b, b2, c].iter().all(|x| x.is_finite()) {
        Some("not finite")
    } else if (b - b2).abs() > 1e-9 * (a.abs() + c.abs()) {
        Some("not symmetric")
    } else if !(a > 0.0 && c > 0.0 && a * c - b * b > 0.0) {
        Some("not positive definite")
    } else {
        None
    }
}

/// `array` (point data [`METRIC`] of the file `path`) validated against `mesh`'s cells: a
/// vertex that no cell of *this* mesh uses may carry anything.
fn on_mesh<T: FieldTensor>(
    mesh: &TaggedMesh,
    array: &DataArray,
    path: &str,
) -> Result<Vec<T>, MetricError> {
    validate(array, mesh, METRIC)
        .map_err(|error| MetricError::Field { path: path.to_string(), error })
}

/// A Medit solution file alone, in `mesh`'s vertex order.
fn read_sol<T: FieldTensor>(
    path: &Path,
    mesh: &TaggedMesh,
    mesh_path: &Path,
) -> Result<MetricField<T>, MetricError> {
    let shown = path.display().to_string();
    let bytes =
        std::fs::read(path).map_err(|e| smartmesh_formats::Error::from(e).with_path(path))?;
    let Some((items, arrays)) =
        smartmesh_formats::medit::read_sol_alone(&bytes).map_err(|e| e.with_path(path))?
    else {
        return Err(MetricError::NotAMetric {
            path: shown,
            why: "no SolAtVertices: the file holds no solution at vertices".into(),
        });
    };
    if items != mesh.points.len() {
        return Err(MetricError::Count {
            path: shown,
            what: "SolAtVertices",
            items,
            mesh: mesh_path.display().to_string(),
            vertices: mesh.points.len(),
        });
    }
    let Some(array) = arrays.get(METRIC) else {
        let available = arrays.keys().cloned().collect::<Vec<_>>().join(", ");
        return Err(MetricError::Field {
            path: shown,
            error: MetricFieldError::Missing { name: METRIC.into(), available },
        });
    };
    let tensors = on_mesh(mesh, array, &shown)?;
    Ok(MetricField { tensors, sizes: None, source: format!("`{METRIC}` of {shown}") })
}

/// The file `path` (of `format` when given, else told by its extension) as a mesh, or,
/// for a Gmsh data-only file, as its node views.
fn read_mesh_or_data(path: &Path, format: Option<Format>) -> Result<MshContent, MetricError> {
    let format = format.or_else(|| Format::from_path(path));
    if format != Some(Format::Gmsh) || path.as_os_str() == "-" {
        return Ok(MshContent::Mesh(read_path(path, format)?));
    }
    let bytes =
        std::fs::read(path).map_err(|e| smartmesh_formats::Error::from(e).with_path(path))?;
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("msh").to_ascii_lowercase();
    Ok(smartmesh_formats::gmsh::read_mesh_or_data(
        &bytes,
        &smartmesh_formats::ReadContext::alone(&ext),
    )
    .map_err(|e| e.with_path(path))?)
}

/// The view [`METRIC`] (or the only view) of a Gmsh data-only file `path` as a field on
/// `mesh`'s vertices: one entry per vertex, node tag t at vertex t − 1.
fn on_node_data<T: FieldTensor>(
    mesh: &TaggedMesh,
    mesh_path: &Path,
    data: NodeData,
    path: &Path,
) -> Result<MetricField<T>, MetricError> {
    let shown = path.display().to_string();
    let name = if data.arrays.contains_key(METRIC) || data.arrays.len() != 1 {
        METRIC.to_string()
    } else {
        data.arrays.keys().next().cloned().unwrap_or_default()
    };
    let Some(array) = data.arrays.get(&name) else {
        let available = if data.arrays.is_empty() {
            "none".to_string()
        } else {
            data.arrays.keys().cloned().collect::<Vec<_>>().join(", ")
        };
        return Err(MetricError::Field {
            path: shown,
            error: MetricFieldError::Missing { name, available },
        });
    };
    let entries = data.entries.get(&name).copied().unwrap_or(0);
    let count = |what: &'static str, items: usize| MetricError::Count {
        path: shown.clone(),
        what,
        items,
        mesh: mesh_path.display().to_string(),
        vertices: mesh.points.len(),
    };
    if entries != mesh.points.len() {
        return Err(count("$NodeData (a data-only file, node tag t at vertex t - 1)", entries));
    }
    if array.len() != mesh.points.len() {
        return Err(count("$NodeData (node tags up to the largest it gives)", array.len()));
    }
    let tensors = validate(array, mesh, &name)
        .map_err(|error| MetricError::Field { path: shown.clone(), error })?;
    Ok(MetricField { tensors, sizes: None, source: format!("view `{name}` of {shown}") })
}

/// The [`METRIC`] array of `other` (read from `other_path`) as a field on `mesh`'s
/// vertices: the same count, the same positions.
fn on_same_vertices<T: FieldTensor>(
    mesh: &TaggedMesh,
    mesh_path: &Path,
    other: &TaggedMesh,
    other_path: &Path,
) -> Result<MetricField<T>, MetricError> {
    let path = other_path.display().to_string();
    let Some(array) = other.point_data.get(METRIC) else {
        // Let from_point_data word the error (it lists the arrays there are).
        let error = MetricField::<T>::point_data_field(other, METRIC)
            .err()
            .unwrap_or(MetricFieldError::Missing { name: METRIC.into(), available: "none".into() });
        return Err(MetricError::Field { path, error });
    };
    if array.len() != mesh.points.len() {
        return Err(MetricError::Count {
            path,
            what: "point data `metric`",
            items: array.len(),
            mesh: mesh_path.display().to_string(),
            vertices: mesh.points.len(),
        });
    }
    // Same count is not enough: the vertices must be the mesh's.
    let moved = if T::DIM == 2 {
        first_moved_vertex(mesh, other)
    } else {
        first_moved_vertex_3d(mesh, other)
    };
    if let Some(v) = moved {
        let d = T::DIM as usize;
        return Err(MetricError::Moved {
            path,
            vertex: v,
            at: other.points[v][..d].to_vec(),
            mesh: mesh_path.display().to_string(),
            expected: mesh.points[v][..d].to_vec(),
        });
    }
    let tensors = on_mesh(mesh, array, &path)?;
    Ok(MetricField { tensors, sizes: None, source: format!("`{METRIC}` of {path}") })
}

/// The first vertex of `mesh` that `other` does not have at the same place, up to
/// rounding in a text file (1e-9 of the mesh's extent); `other` holds at least as many
/// points as `mesh`. A field read from another file lives on the mesh only if there is
/// none.
pub(crate) fn first_moved_vertex(mesh: &TaggedMesh, other: &TaggedMesh) -> Option<usize> {
    let (lo, hi) = mesh.bounding_box().unwrap_or(([0.0; 3], [1.0; 3]));
    let tol = 1e-9 * (hi[0] - lo[0]).abs().max((hi[1] - lo[1]).abs()).max(1e-300);
    (0..mesh.points.len())
        .find(|&v| (0..2).any(|k| (other.points[v][k] - mesh.points[v][k]).abs() > tol))
}

/// [`first_moved_vertex`] in space: x, y and z within 1e-9 of the mesh's largest extent.
fn first_moved_vertex_3d(mesh: &TaggedMesh, other: &TaggedMesh) -> Option<usize> {
    let (lo, hi) = mesh.bounding_box().unwrap_or(([0.0; 3], [1.0; 3]));
    let extent = (0..3).map(|k| (hi[k] - lo[k]).abs()).fold(1e-300, f64::max);
    let tol = 1e-9 * extent;
    (0..mesh.points.len())
        .find(|&v| (0..3).any(|k| (other.points[v][k] - mesh.points[v][k]).abs() > tol))
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::CellKind;

    /// A triangle and a fourth vertex that no cell uses.
    fn triangle() -> TaggedMesh {
        let mut mesh = TaggedMesh::new();
        mesh.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [5.0, 5.0, 0.0]];
        mesh.block_mut(CellKind::Triangle).push(&[0, 1, 2], 1, 1);
        mesh
    }

    fn write_sol(dir: &Path, name: &str, rows: &[&str]) -> std::path::PathBuf {
        let p = dir.join(name);
        let text = format!(
            "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n{}\n1 3\n{}\nEnd\n",
            rows.len(),
            rows.join("\n")
        );
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn a_solution_alone_is_taken_in_vertex_order_checked_where_cells_use_it() {
        let dir = tempfile::tempdir().unwrap();
        let mesh = triangle();
        let mesh_path = dir.path().join("t.vtu");
        let good = write_sol(dir.path(), "a.sol", &["4 0 4", "4 1 4", "9 0 1", "-1 0 -1"]);
        let f = MetricField::read(&good, None, &mesh, &mesh_path).unwrap();
        assert_eq!(
            f.tensors(),
            [
                Sym2::new(4.0, 0.0, 4.0),
                Sym2::new(4.0, 1.0, 4.0),
                Sym2::new(9.0, 0.0, 1.0),
                Sym2::IDENTITY
            ]
        );
        assert!(f.source().contains("a.sol"));
        let bad = write_sol(dir.path(), "b.sol", &["4 0 4", "1 2 1", "9 0 1", "1 0 1"]);
        let e = MetricField::read(&bad, None, &mesh, &mesh_path).unwrap_err().to_string();
        assert!(
            e.contains("b.sol") && e.contains("vertex 1") && e.contains("positive definite"),
            "{e}"
        );
        let short = write_sol(dir.path(), "c.sol", &["4 0 4", "1 0 1", "9 0 1"]);
        let e = MetricField::read(&short, None, &mesh, &mesh_path).unwrap_err();
        assert!(matches!(e, MetricError::Count { items: 3, vertices: 4, .. }), "{e}");
        let empty = dir.path().join("d.sol");
        std::fs::write(&empty, "MeshVersionFormatted 2\nDimension 2\nEnd\n").unwrap();
        let e = MetricField::read(&empty, None, &mesh, &mesh_path).unwrap_err().to_string();
        assert!(e.contains("d.sol") && e.contains("no SolAtVertices"), "{e}");
    }

    #[test]
    fn the_extension_tells_the_kind_unless_a_format_is_named() {
        assert_eq!(Kind::of(Path::new("x.SOL"), None), Kind::Sol);
        assert_eq!(Kind::of(Path::new("x.solb"), None), Kind::Sol);
        assert_eq!(Kind::of(Path::new("x.pos"), None), Kind::Pos);
        assert_eq!(Kind::of(Path::new("x.vtu"), None), Kind::Mesh);
        assert_eq!(Kind::of(Path::new("x.pos"), Some(Format::Vtu)), Kind::Mesh);
    }
}
