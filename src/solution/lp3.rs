//! The Lp-optimal metric in space: the 3D counterpart of [`super::lp`] (whose header
//! gives the framework), on tetrahedra with Hessians [`Sym3`]. In n dimensions the metric
//! that minimises the Lp norm of the P1 interpolation error of a field of Hessian H among
//! metrics of a given complexity is (Loseille & Alauzet, "Continuous mesh framework",
//! SIAM J. Numer. Anal. 49, 2011, part II, eq. for M_Lp)
//!
//! M = D · det(|H|)^(−1/(2p+n)) · |H|,  here n = 3: exponent −1/(2p+3),
//!
//! and its complexity C = ∫ √det M = D^(3/2) ∫ det(|H|)^(p/(2p+3)) (the 2D code's
//! C = D ∫ det(|H|)^(p/(2p+2)) with n = 2), so that D = (C / ∫ det|H|^(p/(2p+3)))^(2/3),
//! their D_Lp = N^(2/n) (∫ det|H|^(p/(2p+n)))^(−2/n) with N = C.
//!
//! - A vertex count N ([`Target::Vertices`](super::Target::Vertices)): C = N / (6√2 /
//!   [`TETS_PER_VERTEX`](crate::metric::complexity3::TETS_PER_VERTEX))
//!   ([`vertices_of_complexity3`](crate::metric::complexity3::vertices_of_complexity3)),
//!   computed exactly for the Log-Euclidean interpolation of the vertex metrics
//!   ([`complexity3`](crate::metric::complexity3::complexity3)); D exact at once without
//!   bounds, by the 2D code's bisection on ln D to 1e-4 relative with them.
//! - An error ε ([`Target::Error`](super::Target::Error)): over a tetrahedron whose edges
//!   have unit length in M, the mean of |u − Πu| for a quadratic u is
//!   tr(M^(−1/2) |H| M^(−1/2)) / 20 (u − Πu =
//!   −½ Σ λᵢλⱼ eᵢⱼᵀ H eᵢⱼ over the six edges, the mean of λᵢλⱼ is 1/20, and Σ eeᵀ = 2 M⁻¹
//!   over the edges of a regular unit tetrahedron; in 2D 1/12 and 3/2 give the 1/16 of
//!   [`super::lp`]). For the optimal metric that trace is 3/(D det|H|^(−1/(2p+3))), so
//!   the Lp error is (3/(20 D)) (∫ det|H|^(p/(2p+3)))^(1/p) and D follows in closed form;
//!   the bounds act after.
//!
//! Degenerate Hessians as in 2D: each |eigenvalue| floored at the larger of 1e-12 of the
//! largest over the mesh and λ_max/r² at its vertex (r the largest aspect ratio); a
//! Hessian zero everywhere gives the uniform metric of the target. Bounds: sizes clamped
//! to [h_min, h_max] and the aspect ratio to r ([`SizeTensor3::clamp`]).
//!
//! The normalisation is [`super::lp`]'s, written once for both dimensions over
//! `LpSpace` (`solution::lp_space`; here n = 3: [`P1Mesh3`] with [`Sym3`] Hessians and
//! [`SizeTensor3`] tensors).

use crate::metric::{SizeTensor3, Sym3};
use crate::solution::lp::{lp_metric_in, vertices_in, LpMetricOf};
use crate::solution::lp_space::LpSpace;
use crate::solution::{LpError, LpOptions, P1Mesh3};

/// The metric in space and how it came out (`vertices` is
/// [`vertices_of_complexity3`](crate::metric::complexity3::vertices_of_complexity3) of the
/// exact complexity).
pub type LpMetric3 = LpMetricOf<SizeTensor3>;

/// The Lp-optimal metric of `hessians` (one per vertex of `mesh`); see the module
/// documentation.
pub fn lp_metric3(
    mesh: &P1Mesh3<'_>,
    hessians: &[Sym3],
    options: &LpOptions,
) -> Result<LpMetric3, LpError> {
    lp_metric_in(mesh, hessians, options)
}

/// The vertices a mesh conforming to `tensors` (one per vertex of `mesh`) has.
pub fn vertices_of3(mesh: &P1Mesh3<'_>, tensors: &[SizeTensor3]) -> f64 {
    vertices_in(mesh, &mesh.cells(), tensors)
}

#[cfg(test)]
mod tests;
