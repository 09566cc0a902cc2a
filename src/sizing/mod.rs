//! Sizing: the functions and algorithms that turn geometric characteristics into size
//! tensors (thesis 4.3.5–4.3.7), and the propagation engine they share.

pub mod functions;
pub mod plan;
pub mod propagation;

pub use functions::{
    CurvatureToSize, DistanceFunction, FunctionError, Parameter, SizeProjectionFunction,
};
pub use plan::{Algorithm, EntitySet, SizingPlan, Step};
/// Neighbour propagation from a source with exact closest points (thesis 2.2.10.4–5, 4.3.6).
pub use propagation::{
    closest_point_brute_force, propagate, ClosestPoint, PieceKind, PropagationOptions, PropagationReport, Reach, Source, SourceBuilder,
    SourceError, SourcePolyline, SourceSegment,
};
