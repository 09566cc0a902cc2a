//! Log-Euclidean interpolation of 3D metrics and size tensors, the 3D counterpart of the
//! 2D [`log_spd`](super::log_spd) / [`exp_sym`](super::exp_sym) /
//! [`log_euclidean`](super::log_euclidean) (Arsigny et al. 2006): exp(Σ wᵢ log Sᵢ).
//!
//! The logarithm of a size tensor is R diag(ln h) Rᵀ, read off the stored decomposition;
//! the logarithm of a metric and the exponential take one [`eigen3`](super::eigen3) each
//! (Jacobi: exact on repeated eigenvalues, which isotropic metrics have). The exponential
//! of a symmetric matrix is SPD, so the mean is always a valid tensor, and since
//! log M = −2 log S, interpolating metrics or sizes is one mean. Sums are accumulated in
//! the order given, from zero, so every caller gets the same bits for the same input.

use super::eigen3::eigen3;
use super::size_tensor3::SizeTensor3;
use super::sym3::Sym3;

/// The matrix logarithm of an SPD metric; eigenvalues are floored at the smallest
/// positive normal number, so a matrix that is not quite positive definite still has a
/// finite logarithm.
pub fn log_spd3(m: &Sym3) -> Sym3 {
    let e = eigen3(*m);
    Sym3::from_eigen(e.values.map(|l| l.max(f64::MIN_POSITIVE).ln()), e.frame)
}

/// The matrix exponential of a symmetric matrix: always SPD.
pub fn exp_sym3(l: &Sym3) -> Sym3 {
    let e = eigen3(*l);
    Sym3::from_eigen(e.values.map(f64::exp), e.frame)
}

fn weighted_sum<'l>(weighted: impl IntoIterator<Item = (f64, &'l Sym3)>) -> Sym3 {
    let mut s = Sym3::ZERO;
    for (w, l) in weighted {
        s = s + w * *l;
    }
    s
}

/// exp(Σ wᵢ Lᵢ) for metric logarithms `l` (from [`log_spd3`]) and weights `w`.
pub fn log_euclidean3(w: &[f64], l: &[&Sym3]) -> Sym3 {
    exp_sym3(&weighted_sum(w.iter().copied().zip(l.iter().copied())))
}

impl SizeTensor3 {
    /// The weighted Log-Euclidean mean exp(Σ wᵢ log Sᵢ) of size tensors (weights: the
    /// barycentric coordinates for an interpolation). `None` when there is no tensor, a
    /// weight is not finite, or a resulting size falls outside the size range.
    pub fn log_euclidean_mean<'t>(
        weighted: impl IntoIterator<Item = (f64, &'t SizeTensor3)>,
    ) -> Option<SizeTensor3> {
        let mut logs: Vec<(f64, Sym3)> = Vec::with_capacity(4);
        for (w, t) in weighted {
            if !w.is_finite() {
                return None;
            }
            logs.push((w, Sym3::from_eigen(t.sizes().map(f64::ln), t.frame())));
        }
        if logs.is_empty() {
            return None;
        }
        let e = eigen3(weighted_sum(logs.iter().map(|(w, l)| (*w, l))));
        SizeTensor3::try_new(e.frame[0], e.frame[1], e.values.map(f64::exp))
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Matrix3;
    use proptest::prelude::*;

    use super::*;
    use crate::metric::testgen3::{arb_frame, arb_log, arb_spd, max_abs, max_diff};

    fn na(m: &Sym3) -> Matrix3<f64> {
        let r = m.rows();
        Matrix3::from_fn(|i, j| r[i][j])
    }

    #[test]
    fn geometric_mean_of_isotropic_sizes() {
        let (a, b) = (SizeTensor3::isotropic(1.0), SizeTensor3::isotropic(4.0));
        let m = SizeTensor3::log_euclidean_mean([(0.5, &a), (0.5, &b)]).unwrap();
        assert!(m.sizes().iter().all(|h| (h - 2.0).abs() < 1e-15), "{m:?}");
        assert!(SizeTensor3::log_euclidean_mean(std::iter::empty()).is_none());
        assert!(SizeTensor3::log_euclidean_mean([(f64::NAN, &a)]).is_none());
        let tiny = SizeTensor3::isotropic(1e-20);
        assert!(SizeTensor3::log_euclidean_mean([(2.0, &tiny)]).is_none());
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]

        /// Twin: nalgebra's general matrix exponential (Padé with scaling and squaring).
        #[test]
        fn exp_agrees_with_nalgebra(m in arb_spd(-1.0, 0.5)) {
            // Any symmetric matrix: the log of an SPD one, with eigenvalues of both signs.
            let l = log_spd3(&m);
            let ours = exp_sym3(&l);
            let theirs = na(&l).exp();
            for i in 0..3 {
                for j in 0..3 {
                    prop_assert!((ours.get(i, j) - theirs[(i, j)]).abs() <= 1e-13 * max_abs(&ours));
                }
            }
            // And exp inverts log.
            prop_assert!(max_diff(&ours, &m) <= 64.0 * f64::EPSILON * max_abs(&m), "{m:?}");
        }

        #[test]
        fn metric_and_size_means_agree(
            f in (arb_frame(), arb_frame()),
            h in (arb_log(-3.0, 0.0), arb_log(-3.0, 0.0), arb_log(-3.0, 0.0)),
            w in 0.0..1.0f64,
        ) {
            let a = SizeTensor3::try_new(f.0[0], f.0[1], [h.0, h.1, h.2]).unwrap();
            let b = SizeTensor3::try_new(f.1[0], f.1[1], [h.2, h.0, h.1]).unwrap();
            let sizes = SizeTensor3::log_euclidean_mean([(1.0 - w, &a), (w, &b)]).unwrap();
            let (la, lb) = (log_spd3(&a.to_metric()), log_spd3(&b.to_metric()));
            let metric = log_euclidean3(&[1.0 - w, w], &[&la, &lb]);
            let want = sizes.to_metric();
            prop_assert!(max_diff(&metric, &want) <= 1e-9 * max_abs(&want), "{metric:?} vs {want:?}");
            // The volume (product of sizes, det M^(-1/2)) interpolates geometrically.
            let vol = |t: &SizeTensor3| t.sizes().iter().product::<f64>();
            let want_vol = vol(&a).powf(1.0 - w) * vol(&b).powf(w);
            prop_assert!((vol(&sizes) / want_vol - 1.0).abs() < 1e-12);
        }
    }
}
