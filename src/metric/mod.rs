//! Metric algebra (2D, and the 3D matrix `Sym3`): size tensors, metric tensors and the operations the sizing
//! algorithms and the remesher need (thesis chapter 3 and 4.3.4).
//!
//! - [`SizeTensor`]: what the code reasons in — the orientation of the first axis and two
//!   sizes h1, h2 (desired edge lengths), stored decomposed as thesis 4.3.4 asks.
//! - [`Sym2`]: a plain symmetric 2×2 matrix for hot loops and for files, which carry metric
//!   tensors M = R diag(1/h1², 1/h2²) Rᵀ.
//! - [`eigen2`]: the closed-form symmetric 2×2 eigen-decomposition behind the conversions.
//! - [`SizeTensor::intersection`] / [`SizeTensor::union`]: the robust size-tensor
//!   intersection of thesis 3.2.2 and its dual, by simultaneous reduction.
//! - [`SizeTensor::clamp`] with [`SizeBounds`]: global h_min, h_max and aspect-ratio limits.
//! - [`SizeTensor::log_euclidean_mean`] and, on metrics, [`log_spd`], [`exp_sym`],
//!   [`log_euclidean`]: the one weighted Log-Euclidean interpolation, which keeps tensors SPD.
//! - [`length`]: the metric length of an edge and the metric quality of a triangle.
//! - [`Sym3`]: the symmetric 3×3 matrix of 3D metrics, with the orders files carry it in.
//! - [`eigen3`]: its eigen-decomposition by cyclic Jacobi, exact on repeated, nearly
//!   repeated and graded (1e-12..1e12) tensors.
//! - [`SizeTensor3`]: three sizes along an orthonormal frame, to and from metrics
//!   ([`TensorError3`] for what is not one), limited by the same [`SizeBounds`];
//!   [`SizeTensor3::intersection`] / [`SizeTensor3::union`] by simultaneous reduction;
//!   [`SizeTensor3::log_euclidean_mean`], [`log_spd3`], [`exp_sym3`], [`log_euclidean3`].
//! - [`gradate_edge_generic`] over [`GradedTensor`]: the one-edge gradation rule of both
//!   dimensions; [`gradate_edge3`]: anisotropic gradation across one edge in 3D (T_q ⊆ g^ℓ T_p by
//!   intersection, so anisotropy is kept).
//! - [`length3`]: the metric length of an edge and the mean-ratio quality of a
//!   tetrahedron in 3D.
//! - [`complexity`]: the metric's complexity ∫ √det M over triangles, and the vertex count
//!   it asks for.
//! - [`complexity3`]: the same over tetrahedra for a 3D metric, and its vertex count.

pub mod complexity;
pub mod complexity3;
mod eigen2;
mod eigen3;
#[cfg(test)]
mod eigen3_twins;
mod gradation;
mod gradation3;
mod interpolation;
mod interpolation3;
mod intersection;
mod intersection3;
pub mod length;
pub mod length3;
mod size_tensor;
mod size_tensor3;
mod svd2;
mod sym2;
mod sym3;
#[cfg(test)]
mod testgen3;

pub use eigen2::{eigen2, Eigen2};
pub use eigen3::{eigen3, jacobi_sweeps, Eigen3, MAX_SWEEPS};
pub use gradation::{gradate_edge_generic, GradedTensor};
pub use gradation3::{gradate_edge3, grow3, growth_factor3, SLACK3};
pub use interpolation::{exp_sym, log_euclidean, log_spd};
pub use interpolation3::{exp_sym3, log_euclidean3, log_spd3};
pub use size_tensor::{SizeBounds, SizeTensor, TensorError};
pub use size_tensor3::{SizeTensor3, TensorError3};
pub use sym2::Sym2;
pub use sym3::Sym3;
