//! What the 3D sizing measures on a mesh in space, below the algorithms that use it:
//! the mesh with its vertex adjacency ([`SpaceMesh`]) and the sources in space
//! (`SpaceSource`: surfaces, segments and points in one exact closest-point index).
//! The driver that runs a plan on a mesh in space is [`crate::sizing::field3`].

mod crossed;
mod mesh;
#[allow(dead_code)] // the distance algorithms come next
mod source;

pub(crate) use crossed::crossed_corners;
#[cfg(test)]
pub(crate) use crossed::crossed_corners_brute;
pub use mesh::SpaceMesh;
#[allow(unused_imports)] // the distance algorithms come next
pub(crate) use source::{unit3, PieceKind3, SpaceClosest, SpaceSource, SpaceSourceBuilder};
