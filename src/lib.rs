//! smartmesh: anisotropic size fields from the geometry of a 2D tagged mesh.
//!
//! The public modules, each the home of one job:
//! - [`metric`]: size tensors and metric algebra (intersection, union, clamping);
//! - [`sizing`]: size functions, neighbour propagation from sources with exact closest
//!   points, and metrics from a computed scalar field ([`sizing::solution`]: Hessian
//!   recovery, Lp metric);
//! - [`recipe`]: sizing recipes (libconfig as in the thesis, TOML, JSON) into one
//!   validated model, resolved against a mesh into a sizing plan;
//! - [`mesher`]: the starting mesh, a constrained Delaunay triangulation with quality
//!   refinement of a planar straight-line graph (Triangle `.poly` or a mesh's lines);
//! - [`remesh`](mod@remesh): the native anisotropic remesher (split, collapse, swap, smooth
//!   in the metric; boundaries, interfaces, corners and tags kept);
//! - [`periodic`]: pairs of sides meshed alike, their matching and checks;
//! - [`layer`]: the structured boundary-layer skin (thesis 5.4.2): quads along chosen
//!   curves, the triangles pushed away, and the validity and quality of mixed meshes;
//! - [`adapt`](mod@adapt): the adaptation loop (size → remesh → size … until converged)
//!   behind one [`Adapter`] trait (the native remesher, MMG's `mmg2d_O3`, Gmsh's BAMG);
//! - [`batch`]: manifests of geometry variants, their content hashes and result records
//!   (`smartmesh batch`), and the families of variants ([`batch::variants`]);
//! - [`report`]: pictures (SVG, PNG) of a mesh, its metric, conformity and history.
//!
//! At the root: [`formats`] (read and write Triangle, Gmsh, VTK, OBJ, Medit, glTF and more
//! into one [`TaggedMesh`]; the `smartmesh-formats` crate, usable on its own), the entry
//! points [`read_path`], [`size_mesh`], [`remesh()`], [`adapt()`], and the types they take
//! and give: the [`Topology`] recovered from the tags, the [`MetricField`] on a mesh, its
//! [`Conformity`], the plane a 2D mesh lies in ([`plane`]), the [`History`] of a run, the
//! validity of a mixed mesh ([`check_mesh`], [`check_cells`] and its all-pairs twin
//! [`check_cells_brute`]) and, for a mesh with volume cells, its [`SolidSummary`] (volumes,
//! bounding surfaces, cell quality) and the measures of one volume cell ([`signed_volume`],
//! [`scaled_jacobian`], the tetrahedron's [`tet_mean_ratio`] and others).
//!
//! The crate's other modules are private; the items of theirs a user needs are named
//! here or in the public module they belong to.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

// For users: the formats crate under the root's name. The library's own modules import
// `smartmesh_formats` directly; the root is the front door, not an internal hub.
pub use smartmesh_formats as formats;

pub mod adapt;
mod adapters;
pub mod batch;
mod child;
mod conformity;
mod geometry;
mod history;
pub mod layer;
mod mesh_graph;
pub mod mesher;
pub mod metric;
mod metric_field;
pub mod periodic;
mod planar;
mod quality;
mod quality3d;
pub mod recipe;
pub mod remesh;
pub mod report;
mod section;
mod size_controls;
pub mod sizing;
mod solid_topology;
mod solution;
mod summary;
mod topology;
mod validity;
mod variants;

// The curated surface: what a user of the library needs, at the root. The private
// modules show only the items named here (or in the public module they belong to:
// `adapt` for the interruption of external programs, `batch::variants`,
// `sizing::solution`).
pub use adapt::{run as adapt, AdaptError, AdaptOptions, Observer, Outcome, Tolerances};
pub use adapters::restore::physical_tags;
pub use adapters::{adapter, Adapted, Adapter, AdapterError, AdapterKind, AdapterOptions};
pub use conformity::{metric_field, Conformity, Ugawg};
pub use formats::{read_path, write_path, Format, TaggedMesh, WriteOptions};
pub use geometry::Point2;
pub use history::{
    BudgetRecord, History, IterationRecord, LayerRecord, PhaseTimes, RemeshingRecord, SolverRecord,
    SpaceRecord, WrittenFile,
};
pub use mesh_graph::{MeshGraph, MeshGraphError};
pub use metric::{SizeBounds, SizeTensor, Sym2};
pub use metric_field::{
    expected_vertices, Complexity, FieldTensor, InterpolationError, Interpolator, MetricError,
    MetricField, MetricFieldError, MetricTarget, METRIC,
};
pub use planar::{place, plane, NotPlanar};
pub use quality::QualitySummary;
pub use quality3d::{
    exact_volume, hex_scaled_jacobian, pyramid_scaled_jacobian, scaled_jacobian, signed_volume,
    tet_aspect_ratio, tet_dihedral_angles, tet_dihedral_range, tet_mean_ratio, tet_scaled_jacobian,
    tet_volume, wedge_scaled_jacobian, KindQuality, TetraQuality, VolumeQuality,
};
pub use recipe::{size_mesh, MeshSizing, SizeMeshError};
pub use recipe::{Recipe, RecipeError};
pub use remesh::{remesh, RemeshError, RemeshOptions, Remeshed};
pub use size_controls::{ControlError, SizeControls};
pub use sizing::SizeField;
pub use summary::{HistogramBins, MeshSummary, SolidSummary};
pub use topology::{
    cell_tag, Classification, CurveOrigin, EntityHits, EntityTag, PointOrigin, Polyline,
    SpaceTopology, SurfaceCell, SurfaceShape, TopoCurve, TopoFace, TopoPoint, TopoVolume, Topology,
    TopologyOptions, DEFAULT_RIDGE_ANGLE_DEG,
};
pub use validity::{check_cells, check_cells_brute, check_mesh, surface_cells, Validity};
