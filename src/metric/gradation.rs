//! The one-edge rule of anisotropic size gradation, once for both dimensions: Alauzet's
//! bound T_q ⊆ η T_p with η = g^ℓ, ℓ = ℓ_{M_p}(pq) (the law is stated in
//! `sizing::gradation`'s header), for any tensor that can measure an edge, grow and
//! intersect ([`GradedTensor`], implemented by [`SizeTensor`] and [`SizeTensor3`]).
//! The 2D rule (`sizing::gradation::gradate_edge`) and the 3D one ([`gradate_edge3`])
//! are this function with their tensor type and slack, so they do the same floating
//! point operations in the same order.
//!
//! [`gradate_edge3`]: super::gradate_edge3

use super::size_tensor::SizeTensor;
use super::size_tensor3::SizeTensor3;

/// What the gradation of one edge needs of a size tensor.
pub trait GradedTensor: Copy + PartialEq {
    /// An edge vector (q − p) in the tensor's space.
    type Vector;
    /// The length of `edge` measured in this tensor.
    fn metric_length_of(&self, edge: Self::Vector) -> f64;
    /// The smallest and the largest size.
    fn size_range(&self) -> (f64, f64);
    /// The tensor with every size multiplied by `factor` (same axes, sizes kept in range).
    fn grown(&self, factor: f64) -> Self;
    /// The robust intersection (the largest tensor inside both).
    fn intersect(&self, other: &Self) -> Self;
}

impl GradedTensor for SizeTensor {
    type Vector = [f64; 2];
    fn metric_length_of(&self, edge: [f64; 2]) -> f64 {
        self.metric_length(edge)
    }
    fn size_range(&self) -> (f64, f64) {
        (self.h_min(), self.h_max())
    }
    fn grown(&self, factor: f64) -> Self {
        let [h1, h2] = self.sizes();
        SizeTensor::from_parts(self.axis(), [h1 * factor, h2 * factor])
    }
    fn intersect(&self, other: &Self) -> Self {
        self.intersection(other)
    }
}

impl GradedTensor for SizeTensor3 {
    type Vector = [f64; 3];
    fn metric_length_of(&self, edge: [f64; 3]) -> f64 {
        self.metric_length(edge)
    }
    fn size_range(&self) -> (f64, f64) {
        (self.h_min(), self.h_max())
    }
    fn grown(&self, factor: f64) -> Self {
        SizeTensor3::from_parts(self.frame(), self.sizes().map(|h| h * factor))
    }
    fn intersect(&self, other: &Self) -> Self {
        self.intersection(other)
    }
}

/// The tensor at q after bounding it by the one at p across `edge` = q − p with
/// gradation `gradation` (>= 1): `Some(T_q ∩ η T_p)` when T_q is not already inside
/// η T_p grown by the relative `slack`, `None` when nothing changes (also when η is
/// infinite or NaN: no bound).
pub fn gradate_edge_generic<T: GradedTensor>(
    tp: &T,
    tq: &T,
    edge: T::Vector,
    gradation: f64,
    slack: f64,
) -> Option<T> {
    let eta = gradation.powf(tp.metric_length_of(edge));
    // A grown ball (disc) of radius h_min(T_p)·η that holds T_q: nothing to do.
    if !eta.is_finite() || tp.size_range().0 * eta >= tq.size_range().1 {
        return None;
    }
    if tq.intersect(&tp.grown(eta * (1.0 + slack))) == *tq {
        return None;
    }
    Some(tq.intersect(&tp.grown(eta)))
}
