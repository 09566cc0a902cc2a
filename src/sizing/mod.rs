//! Sizing: the functions and algorithms that turn geometric characteristics into size
//! tensors (thesis 4.3.5–4.3.7), the propagation engine they share, the engine that runs
//! a plan into a size field, and the gradation pass (thesis 7.4.1); [`space`] runs the
//! same plan on a mesh in space, [`field3`] is its driver.

pub mod algorithms;
mod evaluate;
pub mod field;
pub mod field3;
pub mod functions;
pub mod gradation;
mod gradation3;
pub mod plan;
pub mod propagation;
pub mod space;

/// Metrics from a computed scalar field: Hessian recovery, the Lp metric and the
/// solution files they are read from.
pub mod solution {
    pub use crate::solution::*;
}

/// Three-point (Menger) curvature and the corner angle of CURVATURE_OF_BORDER (thesis 4.3.7.2).
pub use algorithms::curvature_of_border::{three_point_curvature, CORNER_ANGLE};
/// What one algorithm gives: reached vertices with one tensor each.
pub use algorithms::Contribution;
pub use algorithms::{
    Algorithm, CurvatureOfBorder, DistanceBetweenTwoBorders, DistanceToBorder,
    DistanceToImaginaryPolyline, DistanceToPoint, PolylinePoints, SolutionHessian, Uniform,
};
/// The sizing engine: a plan run on a mesh into one size tensor per vertex (thesis 4.3.6).
pub use field::{
    compute_size_field, plan_bounds, run_algorithm, SizeField, SizingError, StepEvent, StepReport,
};
/// The sizing engine on a mesh in space: a plan run into one 3D size tensor per vertex.
pub use field3::{compute_size_field3, SizeField3};
pub use functions::{
    CurvatureToSize, DistanceFunction, FunctionError, Parameter, SizeProjectionFunction,
};
/// Anisotropic size gradation (Alauzet's metric gradation, thesis 7.4.1).
pub use gradation::{apply_gradation, grow, growth_factor, GradationReport};
pub use plan::{EntitySet, SizingPlan, Step};
/// Neighbour propagation from a source with exact closest points (thesis 2.2.10.4–5, 4.3.6).
pub use propagation::{
    closest_point_brute_force, propagate, ClosestPoint, PieceKind, PropagationOptions,
    PropagationReport, Reach, Source, SourceBuilder, SourceError, SourcePolyline, SourceSegment,
};
pub use space::SpaceMesh;
