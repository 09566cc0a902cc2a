//! smartmesh: anisotropic size fields from the geometry of a 2D tagged mesh.
//!
//! Features:
//! - [`formats`]: read and write Triangle, Gmsh, VTK, OBJ, Medit and glTF files into one
//!   [`formats::TaggedMesh`] (the `smartmesh-formats` crate, usable on its own);
//! - [`topology`]: topological points, curves and faces recovered from the tags, every
//!   mesh vertex and edge classified on one of them;
//! - [`solid_topology`] and [`quality3d`]: the volumes of a 3D mesh, the surfaces that
//!   bound each, and the volume and shape quality of its cells (`info`);
//! - [`metric`]: size tensors and metric algebra (intersection, union, clamping);
//! - [`sizing`]: size functions, and neighbour propagation from sources with exact
//!   closest points;
//! - [`recipe`]: sizing recipes (libconfig as in the thesis, TOML, JSON) into one
//!   validated model, resolved against a mesh into a sizing plan;
//! - [`mesher`]: the starting mesh, a constrained Delaunay triangulation with quality
//!   refinement of a planar straight-line graph (Triangle `.poly` or a mesh's lines);
//! - [`planar`]: the one plane z = const a 2D mesh lies in, or the point off it;
//! - [`conformity`]: metric edge lengths and metric quality of a mesh against a field;
//! - [`adapters`]: remeshers behind one trait (MMG's `mmg2d_O3`, Gmsh's BAMG), tags
//!   restored on their output;
//! - [`adapt`](mod@adapt): the adaptation loop (size → remesh → size … until converged);
//! - [`child`]: external programs run in a process group of their own, with a bounded
//!   share of their output kept, stopped on interruption and dying with smartmesh;
//! - [`batch`]: manifests of geometry variants, their content hashes and result records
//!   (`smartmesh batch`);
//! - [`remesh`](mod@remesh): the native anisotropic remesher (split, collapse, swap, smooth in the
//!   metric; boundaries, interfaces, corners and tags kept);
//! - [`layer`]: the structured boundary-layer skin (thesis 5.4.2): quads along chosen
//!   curves, the triangles pushed away, and the quality of mixed meshes;
//! - [`validity`]: whether a mixed triangle/quad mesh is valid (positive cells, no
//!   overlap, no hanging vertex), for the skin, the remesher and `info`;
//! - [`history`]: the convergence history of an adaptation run (`history.json`);
//! - [`metric_field`]: a metric field on a mesh, read from point data, a `.sol`, a `.pos`
//!   or a mesh file, checked, interpolated elsewhere, and written for MMG (.sol), Gmsh
//!   (.msh, .pos) and VTK/ParaView (.vtu, .vtk);
//! - [`report`]: pictures (SVG, PNG) of a mesh, its metric, conformity and history;
//! - [`solution`]: metrics from a computed scalar field (Hessian recovery, Lp metric);
//! - [`variants`]: families of geometries with one set of tags (NACA 4-digit airfoils,
//!   the turbine distributors) written as `.poly` files with a batch manifest;
//! - the entry points at the root: [`read_path`], [`size_mesh`], [`remesh()`], [`adapt()`],
//!   [`MetricField`], with the types they take and give.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

// For users: the formats crate under the root's name. The library's own modules import
// `smartmesh_formats` directly; the root is the front door, not an internal hub.
pub use smartmesh_formats as formats;

pub mod adapt;
pub mod adapters;
pub mod batch;
pub mod child;
pub mod conformity;
pub(crate) mod geometry;
pub mod history;
pub mod layer;
pub(crate) mod mesh_graph;
pub mod mesher;
pub mod metric;
pub mod metric_field;
pub mod periodic;
pub mod planar;
pub(crate) mod quality;
pub mod quality3d;
pub mod recipe;
pub mod remesh;
pub mod report;
pub(crate) mod size_controls;
pub mod sizing;
pub mod solid_topology;
pub mod solution;
pub(crate) mod summary;
pub mod topology;
pub mod validity;
pub mod variants;

// The curated surface: what a user of the library needs, at the root. The crate's
// own modules (`geometry`, `mesh_graph`, `quality`, `size_controls`, `summary`) show
// only the types named here.
pub use adapt::{run as adapt, AdaptError, AdaptOptions, Observer, Outcome, Tolerances};
pub use adapters::{adapter, Adapter, AdapterKind, AdapterOptions};
pub use conformity::Conformity;
pub use formats::{read_path, write_path, Format, TaggedMesh, WriteOptions};
pub use geometry::Point2;
pub use mesh_graph::{MeshGraph, MeshGraphError};
pub use metric::{SizeBounds, SizeTensor, Sym2};
pub use metric_field::{MetricError, MetricField, MetricTarget, METRIC};
pub use quality::QualitySummary;
pub use recipe::{size_mesh, MeshSizing, SizeMeshError};
pub use recipe::{Recipe, RecipeError};
pub use remesh::{remesh, RemeshError, RemeshOptions, Remeshed};
pub use size_controls::{ControlError, SizeControls};
pub use sizing::SizeField;
pub use summary::{HistogramBins, MeshSummary, SolidSummary};
pub use topology::Topology;
