//! Plane geometry kernels the sizing algorithms share: the distance from a point to a
//! segment with its foot point and parameter (thesis 4.3.6.3, "common methods"), the
//! contact test between a segment and a mesh cell, a spatial index over a set of
//! segments that answers exact closest-segment queries, and the clearances of a
//! polyline source, which let most closest points be certified without a search; and
//! point location in a triangulation (the triangle holding a point, or the nearest); a
//! quadtree of boxes that follows the grading (point and box queries); plane geometry
//! with tolerances for the boundary-layer skin and the mixed-mesh check ([`plane`]), and
//! the pairs of shapes that may meet ([`near_pairs`]). The exact orientation predicate
//! (`segment::orient`) is the one every sign test that decides validity uses.
//! Geometry in space ([`space`]): exact closest points on a triangulated surface, the 3D
//! orientation predicate.
//!
//! Everything here works on plain `[f64; 2]` (in `space`, `[f64; 3]`) points and knows nothing of meshes or tags.

pub(crate) mod box_tree;
mod chain_tree;
pub(crate) mod clearance;
pub(crate) mod locate;
pub(crate) mod near_pairs;
pub(crate) mod plane;
pub(crate) mod segment;
pub(crate) mod segment_index;
// Not yet used by the sizing: the 3D algorithms are its callers.
#[allow(dead_code)]
pub(crate) mod space;
#[cfg(test)]
pub(crate) mod test_support;

pub(crate) use clearance::Clearance;
pub(crate) use locate::TriangleLocator;
pub use segment::Point2;
pub(crate) use segment::{Projection, SegmentGeom};
pub(crate) use segment_index::{Nearest, QueryStats, SegmentIndex};
