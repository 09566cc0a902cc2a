//! Geometry in space for the 3D sizing: the closest point of a triangle to a point with
//! the feature it lies on ([`triangle`]), exact closest points on a triangulated surface
//! through a bounding-volume hierarchy that agrees bit for bit with the brute-force scan
//! ([`surface_index`]), the exact 3D orientation predicate ([`orient3d`]), whether a
//! segment or a triangle meets a tetrahedron or a cell's hull, from its signs alone
//! ([`meets`]), and the principal curvatures of a triangulated surface with its ridges
//! kept apart, and of a curve through three points ([`curvature`]).
//!
//! Everything here works on plain `[f64; 3]` points and knows nothing of meshes or tags;
//! nothing here imports the rest of smartmesh (the benchmark `surface_distance` compiles
//! these files on their own).

pub(crate) mod curvature;
#[cfg(test)]
pub(crate) mod curvature_tests;
#[cfg(test)]
mod index_tests;
pub(crate) mod meets;
#[cfg(test)]
mod meets_tests;
pub(crate) mod surface_index;
#[cfg(test)]
mod tests;
pub(crate) mod triangle;

// The 3D sizing's entry points (not used yet).
#[allow(unused_imports)]
pub(crate) use surface_index::{closest_brute, SurfaceError, SurfaceIndex, SurfacePoint};
#[allow(unused_imports)]
pub(crate) use triangle::{orient3d, Feature, Point3, TriangleGeom, TriangleProjection};
