//! Sizing recipes (thesis 5.3 and appendix A): the user's choice of algorithms, functions
//! and regions, read from libconfig (the thesis format, through the C preprocessor),
//! TOML or JSON into one validated model, [`Recipe`], and resolved against a mesh into a
//! [`SizingPlan`](crate::sizing::SizingPlan).
//!
//! - [`model`]: the model (serde), its validation, reading and writing;
//! - [`preprocess`] and [`libconfig`]: cpp and `@include`, then the libconfig syntax
//!   with lines;
//! - [`appendix`]: the keywords of appendix A and their spelling variants, to and from
//!   the model;
//! - [`serde_io`]: TOML and JSON;
//! - [`resolve`]: regions to topological entities, functions built, steps labelled;
//! - [`on_mesh`]: a recipe's size field on a mesh in one call (topology, resolution, the
//!   mesh graph, then the sizing engine, which knows no recipe);
//! - [`suggest`] and [`error`]: errors that name file, line and key, and the nearest
//!   valid name.

pub mod appendix;
pub mod bounds;
pub mod error;
pub mod layer;
pub mod libconfig;
pub mod model;
pub mod on_mesh;
pub mod periodic;
pub mod preprocess;
mod rebase;
pub mod resolve;
pub mod serde_io;
mod sheet;
pub mod suggest;

pub use bounds::{BoundsError, GlobalOverrides};
pub use error::{RecipeError, RecipeErrorKind};
pub use layer::{CurveValues, LayerSpec, SpecError};
pub use model::{
    AlgorithmSpec, EntityRef, FunctionKind, FunctionSpec, Global, PolylinePoints, Recipe,
    RecipeFormat,
};
/// A recipe's field on a mesh in one call (topology, resolution, graph, engine).
pub use on_mesh::{
    size_mesh, size_mesh_in_space, size_mesh_with_steps, size_mesh_with_topology, MeshSizing,
    MeshSizing3, SizeMeshError,
};
pub use periodic::PeriodicSpec;
pub use preprocess::ReadOptions;
pub use resolve::{RegionReport, Resolved};
