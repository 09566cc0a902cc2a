//! smartmesh: anisotropic size fields from the geometry of a 2D tagged mesh.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub use smartmesh_formats as formats;

pub mod metric;
pub mod sizing;

pub use metric::{SizeBounds, SizeTensor, Sym2};
