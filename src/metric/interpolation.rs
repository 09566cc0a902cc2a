//! Log-Euclidean interpolation of metrics and size tensors: the one implementation the
//! remesher (new vertices on split edges, smoothing, the background field), the
//! conformity measure (a triangle's centroid metric) and metric files given at other
//! positions all use.
//!
//! Method: Arsigny, Fillard, Pennec and Ayache, "Log-Euclidean metrics for fast and simple
//! calculus on diffusion tensors" (Magnetic Resonance in Medicine, 2006): average the matrix
//! logarithms and take the exponential, exp(Σ w_i log S_i). The logarithm of a size tensor
//! is R diag(ln h1, ln h2) Rᵀ, read off the stored decomposition without any eigen-solve;
//! the logarithm of a metric takes one closed-form [`eigen2`](super::eigen2). The weighted
//! sum is symmetric, so one more closed-form eigen-decomposition and two `exp` give the
//! result. Every symmetric matrix has an SPD exponential, so the result is always a valid
//! tensor; since log M = −2 log S, interpolating metrics or sizes is the same thing. Sizes
//! interpolate geometrically (the mean of h = 1 and h = 4 with weights ½ is 2), and the
//! determinant too, which a linear mix of metrics does not do (it swells).
//!
//! Callers that interpolate the same tensors many times keep their logarithms
//! ([`log_spd`]) and call [`log_euclidean`] on them; the sum is always accumulated in the
//! order given, from zero, so that every caller gets the same bits for the same input.

use super::eigen2::{eigen2, Eigen2};
use super::size_tensor::SizeTensor;
use super::sym2::Sym2;

/// The matrix logarithm of an SPD metric (closed-form eigen-decomposition; eigenvalues
/// are floored at the smallest positive normal number, so a matrix that is not quite
/// positive definite still has a finite logarithm).
#[inline]
pub fn log_spd(m: &Sym2) -> Sym2 {
    let e = eigen2(*m);
    Sym2::from_eigen(
        [e.values[0].max(f64::MIN_POSITIVE).ln(), e.values[1].max(f64::MIN_POSITIVE).ln()],
        e.vector,
    )
}

/// The matrix exponential of a symmetric matrix: always SPD.
#[inline]
pub fn exp_sym(l: &Sym2) -> Sym2 {
    let e = eigen2(*l);
    Sym2::from_eigen([e.values[0].exp(), e.values[1].exp()], e.vector)
}

/// Σ wᵢ Lᵢ accumulated in order from zero: the one weighted sum of logarithms.
#[inline]
fn weighted_sum<'l>(weighted: impl IntoIterator<Item = (f64, &'l Sym2)>) -> Sym2 {
    let mut s = Sym2::new(0.0, 0.0, 0.0);
    for (w, l) in weighted {
        s = s + w * *l;
    }
    s
}

/// exp(Σ wᵢ Lᵢ) for metric logarithms `l` (from [`log_spd`]) and weights `w`.
#[inline]
pub fn log_euclidean(w: &[f64], l: &[&Sym2]) -> Sym2 {
    exp_sym(&weighted_sum(w.iter().copied().zip(l.iter().copied())))
}

impl SizeTensor {
    /// The weighted Log-Euclidean mean exp(Σ w_i log S_i) of size tensors.
    ///
    /// For an interpolation the weights are the barycentric coordinates (they sum to 1);
    /// other finite weights are accepted and scale the logarithm. `None` when there is no
    /// tensor, a weight is not finite, or a resulting size falls outside
    /// [`MIN_SIZE`](SizeTensor::MIN_SIZE), [`MAX_SIZE`](SizeTensor::MAX_SIZE) (possible only
    /// with weights that do not sum to 1).
    pub fn log_euclidean_mean<'t>(
        weighted: impl IntoIterator<Item = (f64, &'t SizeTensor)>,
    ) -> Option<SizeTensor> {
        let mut logs: Vec<(f64, Sym2)> = Vec::with_capacity(3);
        for (w, t) in weighted {
            if !w.is_finite() {
                return None;
            }
            logs.push((w, Sym2::from_eigen([t.h1().ln(), t.h2().ln()], t.axis())));
        }
        if logs.is_empty() {
            return None;
        }
        let e: Eigen2 = weighted_sum(logs.iter().map(|(w, l)| (*w, l))).eigen();
        SizeTensor::try_new(e.vector, e.values[0].exp(), e.values[1].exp())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometric_mean_of_isotropic_sizes() {
        let a = SizeTensor::isotropic(1.0);
        let b = SizeTensor::isotropic(4.0);
        let m = SizeTensor::log_euclidean_mean([(0.5, &a), (0.5, &b)]).unwrap();
        assert!((m.h1() - 2.0).abs() < 1e-15 && (m.h2() - 2.0).abs() < 1e-15);
    }

    #[test]
    fn single_tensor_with_weight_one_is_itself() {
        let t = SizeTensor::from_angle(0.3, 1e-3, 2.0).unwrap();
        let m = SizeTensor::log_euclidean_mean([(1.0, &t)]).unwrap();
        for k in 0..16 {
            let u = (k as f64 * 0.2).sin_cos();
            let (x, y) = (m.size_along([u.0, u.1]), t.size_along([u.0, u.1]));
            assert!((x - y).abs() <= 1e-13 * y, "{m:?} {t:?}");
        }
    }

    #[test]
    fn empty_or_bad_weights() {
        let t = SizeTensor::isotropic(1.0);
        assert!(SizeTensor::log_euclidean_mean(std::iter::empty()).is_none());
        assert!(SizeTensor::log_euclidean_mean([(f64::NAN, &t)]).is_none());
        let tiny = SizeTensor::isotropic(1e-20);
        assert!(SizeTensor::log_euclidean_mean([(2.0, &tiny)]).is_none());
    }

    #[test]
    fn log_exp_round_trip_and_geometric_sizes() {
        let m = SizeTensor::from_angle(0.4, 0.01, 0.3).unwrap().to_metric();
        let back = exp_sym(&log_spd(&m));
        assert!(
            (back.a - m.a).abs() < 1e-9 * m.a
                && (back.b - m.b).abs() < 1e-9 * m.a
                && (back.c - m.c).abs() < 1e-9 * m.a
        );
        let (a, b) =
            (SizeTensor::isotropic(1.0).to_metric(), SizeTensor::isotropic(4.0).to_metric());
        let mid = log_euclidean(&[0.5, 0.5], &[&log_spd(&a), &log_spd(&b)]);
        assert!((mid.a - 0.25).abs() < 1e-14 && mid.b.abs() < 1e-14);
    }

    /// The metric path and the size path are one mean: log M = −2 log S, so the mean of
    /// metrics is the metric of the mean of sizes.
    #[test]
    fn metric_and_size_means_agree() {
        let s = [
            SizeTensor::from_angle(0.3, 0.02, 0.5).unwrap(),
            SizeTensor::from_angle(-1.1, 0.4, 0.05).unwrap(),
            SizeTensor::isotropic(0.1),
        ];
        let w = [0.2, 0.5, 0.3];
        let sizes = SizeTensor::log_euclidean_mean(w.iter().copied().zip(&s)).unwrap();
        let logs: Vec<Sym2> = s.iter().map(|t| log_spd(&t.to_metric())).collect();
        let metric = log_euclidean(&w, &[&logs[0], &logs[1], &logs[2]]);
        let want = sizes.to_metric();
        for (x, y) in [(metric.a, want.a), (metric.b, want.b), (metric.c, want.c)] {
            assert!((x - y).abs() <= 1e-9 * want.a.max(want.c), "{metric:?} vs {want:?}");
        }
    }
}
