//! A metric field written where the tools of the trade read it (DESIGN.md, "Conventions
//! of the tools we talk to"); the one writer of the `metric` array, whether `size`
//! exports a field, the remesher returns its mesh or an adapter hands a metric to MMG or
//! Gmsh.
//!
//! | output | what is written | who reads it |
//! | --- | --- | --- |
//! | `.sol` / `.solb` | `SolAtVertices`, one type-3 tensor (m11 m12 m22) per vertex | `mmg2d_O3 mesh.mesh -sol out.sol` |
//! | `.mesh` / `.meshb` | the mesh, and the metric in the `.sol`/`.solb` beside it | `mmg2d_O3 out.mesh` |
//! | `.msh` | the mesh with one `$NodeData` view `metric` (9 components) | `gmsh -bgm out.msh` (BAMG), Gmsh GUI |
//! | `.pos` | a parsed post-processing view of `TT`/`TQ` records (9 components per node) | `gmsh -bgm out.pos` (BAMG) |
//! | `.vtu` / `.vtk` | the mesh with point data `metric` and, for a field made from sizes, `size_tensor`, `h1`, `h2`, `anisotropy`, `axis1`, `axis2` | ParaView, VTK |
//!
//! The 9-component tensor is the metric's xy block with a z entry equal to its larger
//! eigenvalue, 1/h_min² (exactly that, from the sizes, for a field made from sizes), so
//! that a 3D reader sees an SPD tensor no larger than the in-plane ones.
//! `size_tensor` = R diag(h1, h2) Rᵀ is written beside it for VTK because ParaView's Tensor
//! Glyph scales by eigenvalues: the size tensor draws the size ellipses at scale 1 (its z
//! entry is the smaller size, so glyphs stay flat but visible). `axis1`/`axis2` are the two
//! axes scaled by their sizes.
//!
//! Gmsh honours an anisotropic background view only with its BAMG algorithm
//! (`-setnumber Mesh.Algorithm 7`); the other 2D algorithms ignore it with a warning.
//!
//! A 3D field ([`crate::metric::Sym3`]) goes to the same targets through the same
//! [`MetricField::write`]; what it writes is in `write3`.
//!
//! Invariants: a field is written whole or not at all (atomic renames, no half-written
//! file); the field has one tensor per vertex of the mesh it is written with.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use smartmesh_formats::{
    sym2_to_tensor9, write_all_atomically, write_path, DataArray, Error, ErrorKind, Format,
    TaggedMesh, WriteOptions, WriteReport,
};

use super::{FieldTensor, MetricField, METRIC};
use crate::metric::SizeTensor;

/// Where a metric goes, told by the output's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MetricTarget {
    /// A Medit solution alone (`.sol`, or `.solb` when binary).
    Sol {
        /// `.solb`.
        binary: bool,
    },
    /// A Gmsh `.pos` view.
    Pos,
    /// A mesh file of this format with the metric as point data (Medit writes its `.sol`
    /// beside the mesh).
    Mesh(Format),
}

impl MetricTarget {
    /// The target for `path`, or `None` when its extension names no target (OBJ and glTF
    /// hold no tensor; Triangle files hold no field that tools read as a metric).
    pub fn from_path(path: &Path) -> Option<MetricTarget> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "sol" => Some(MetricTarget::Sol { binary: false }),
            "solb" => Some(MetricTarget::Sol { binary: true }),
            "pos" => Some(MetricTarget::Pos),
            _ => match Format::from_path(path)? {
                f @ (Format::Gmsh
                | Format::Vtu
                | Format::VtkLegacy
                | Format::Medit
                | Format::Cgns) => Some(MetricTarget::Mesh(f)),
                _ => None,
            },
        }
    }

    /// The extensions accepted, for error messages.
    pub const EXTENSIONS: &'static str = ".sol .solb .mesh .meshb .msh .pos .vtu .vtk .cgns";
}

/// What [`MetricField::write`] wrote.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Written {
    /// The files written, main file first.
    pub files: Vec<PathBuf>,
    /// What the target could not hold.
    pub dropped: Vec<String>,
}

/// Cell arrays that carry tags rather than fields (kept in every output).
fn is_tag_array(name: &str) -> bool {
    name.starts_with("gmsh:") || name.starts_with("medit:") || name == "CellEntityIds"
}

impl MetricField {
    /// The field of these size tensors (one per vertex): the metrics
    /// M = R diag(1/h1², 1/h2²) Rᵀ, the sizes kept for what is written beside the metric.
    pub fn from_sizes(sizes: &[SizeTensor], source: impl Into<String>) -> MetricField {
        MetricField {
            tensors: sizes.iter().map(SizeTensor::to_metric).collect(),
            sizes: Some(sizes.to_vec()),
            source: source.into(),
        }
    }

    /// The point array [`METRIC`]: per vertex the row-major 3×3 tensor of the metric, z
    /// entry its larger eigenvalue (see the module documentation).
    pub fn to_array(&self) -> DataArray {
        let mut values = Vec::with_capacity(9 * self.tensors.len());
        match &self.sizes {
            Some(sizes) => {
                for (m, t) in self.tensors.iter().zip(sizes) {
                    values.extend_from_slice(&sym2_to_tensor9(
                        m.a,
                        m.b,
                        m.c,
                        1.0 / (t.h_min() * t.h_min()),
                    ));
                }
            }
            None => {
                for m in &self.tensors {
                    values.extend_from_slice(&sym2_to_tensor9(m.a, m.b, m.c, m.eigen().values[0]));
                }
            }
        }
        DataArray::new(9, values)
    }

    /// The arrays written for the field in a VTK file: [`METRIC`] and, for a field made
    /// from sizes ([`MetricField::from_sizes`]), `size_tensor` (9 components each,
    /// row-major 3×3), `h1`, `h2`, `anisotropy` (h_max / h_min), `axis1`, `axis2` (3
    /// components).
    pub fn arrays(&self) -> BTreeMap<String, DataArray> {
        let mut out = BTreeMap::new();
        out.insert(METRIC.to_string(), self.to_array());
        let Some(sizes) = &self.sizes else { return out };
        let n = sizes.len();
        let mut size = Vec::with_capacity(9 * n);
        let (mut h1, mut h2, mut aniso) =
            (Vec::with_capacity(n), Vec::with_capacity(n), Vec::with_capacity(n));
        let (mut ax1, mut ax2) = (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n));
        for t in sizes.iter() {
            let s = t.to_size_matrix();
            size.extend_from_slice(&sym2_to_tensor9(s.a, s.b, s.c, t.h_min()));
            let [a, b] = t.sizes();
            h1.push(a);
            h2.push(b);
            aniso.push(t.aspect_ratio());
            let (e1, e2) = (t.axis(), t.second_axis());
            ax1.extend_from_slice(&[a * e1[0], a * e1[1], 0.0]);
            ax2.extend_from_slice(&[b * e2[0], b * e2[1], 0.0]);
        }
        out.insert("size_tensor".to_string(), DataArray::new(9, size));
        out.insert("h1".to_string(), DataArray::new(1, h1));
        out.insert("h2".to_string(), DataArray::new(1, h2));
        out.insert("anisotropy".to_string(), DataArray::new(1, aniso));
        out.insert("axis1".to_string(), DataArray::new(3, ax1));
        out.insert("axis2".to_string(), DataArray::new(3, ax2));
        out
    }

    /// The bytes of a Medit solution file holding the field (`.solb` when `binary`), as
    /// `mmg2d_O3 -sol` reads it.
    pub fn sol_bytes(&self, binary: bool) -> Result<Vec<u8>, Error> {
        smartmesh_formats::medit::write_sol(&[(METRIC, &self.to_array())], 2, binary)
    }

    /// The bytes of a `.pos` file holding the field on the triangles and quadrangles of
    /// `mesh` (whose vertices the field lives on) as one view [`METRIC`], as
    /// `gmsh -bgm` reads it.
    pub fn pos_bytes(&self, mesh: &TaggedMesh) -> Result<Vec<u8>, Error> {
        smartmesh_formats::gmsh::pos::write_tensor_view(mesh, &self.to_array(), METRIC)
    }
}

impl<T: FieldTensor> MetricField<T> {
    /// Writes the field (one tensor per vertex of `mesh`) to `path` as `target` wants,
    /// atomically (no half-written file on failure). `opts` chooses the binary/version
    /// variants of mesh targets. A 3D field goes to the same targets (see `write3`).
    pub fn write(
        &self,
        path: &Path,
        mesh: &TaggedMesh,
        target: MetricTarget,
        opts: &WriteOptions,
    ) -> Result<Written, Error> {
        if self.tensors.len() != mesh.points.len() {
            return Err(Error::new(ErrorKind::Inconsistent(format!(
                "{} size tensors for {} mesh vertices",
                self.tensors.len(),
                mesh.points.len()
            )))
            .with_path(path));
        }
        match target {
            MetricTarget::Sol { binary } => {
                let array = T::metric_array(self);
                let bytes =
                    smartmesh_formats::medit::write_sol(&[(METRIC, &array)], T::DIM, binary)
                        .map_err(|e| e.with_path(path))?;
                write_all_atomically(&[(path.to_path_buf(), bytes)])?;
                Ok(Written { files: vec![path.to_path_buf()], dropped: Vec::new() })
            }
            MetricTarget::Pos => {
                let bytes = smartmesh_formats::gmsh::pos::write_tensor_view(
                    mesh,
                    &T::metric_array(self),
                    METRIC,
                )
                .map_err(|e| e.with_path(path))?;
                write_all_atomically(&[(path.to_path_buf(), bytes)])?;
                Ok(Written { files: vec![path.to_path_buf()], dropped: Vec::new() })
            }
            MetricTarget::Mesh(format) => {
                let mut out = mesh.clone();
                let mut dropped = Vec::new();
                match format {
                    // `gmsh -bgm` takes the last view of the file and MMG reads one
                    // solution: the metric goes alone, and the mesh's own fields are left
                    // out (said).
                    Format::Gmsh | Format::Medit => {
                        for name in
                            std::mem::take(&mut out.point_data).into_keys().filter(|k| k != METRIC)
                        {
                            dropped.push(format!(
                                "point data `{name}`: left out so that the metric is the only field"
                            ));
                        }
                        for name in out.cell_data.keys().filter(|k| !is_tag_array(k)) {
                            dropped.push(format!(
                                "cell data `{name}`: left out so that the metric is the only field"
                            ));
                        }
                        out.cell_data.retain(|k, _| is_tag_array(k));
                        out.point_data.insert(METRIC.to_string(), T::metric_array(self));
                    }
                    _ => out.point_data.extend(T::vtk_arrays(self)),
                }
                let report: WriteReport = write_path(path, &out, Some(format), opts)?;
                dropped.extend(report.dropped);
                let mut files = vec![path.to_path_buf()];
                if format == Format::Medit {
                    let binary = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("meshb"));
                    files.push(path.with_extension(if binary { "solb" } else { "sol" }));
                }
                Ok(Written { files, dropped })
            }
        }
    }
}
