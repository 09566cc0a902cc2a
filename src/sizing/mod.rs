//! Sizing: the functions and algorithms that turn geometric characteristics into size
//! tensors (thesis 4.3.5–4.3.7).

pub mod functions;

pub use functions::{
    CurvatureToSize, DistanceFunction, FunctionError, Parameter, SizeProjectionFunction,
};
