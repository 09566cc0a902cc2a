//! Log-Euclidean interpolation of size tensors, for the remesher (new vertices on split
//! edges, smoothing).
//!
//! Method: Arsigny, Fillard, Pennec and Ayache, "Log-Euclidean metrics for fast and simple
//! calculus on diffusion tensors" (Magnetic Resonance in Medicine, 2006): average the matrix
//! logarithms and take the exponential, exp(Σ w_i log S_i). The logarithm of a size tensor
//! is R diag(ln h1, ln h2) Rᵀ, read off the stored decomposition without any eigen-solve;
//! the sum is symmetric, so one closed-form [`eigen2`](super::eigen2) and two `exp` give the
//! result. Every symmetric matrix has an SPD exponential, so the result is always a valid
//! tensor; since log M = −2 log S, interpolating metrics or sizes is the same thing. Sizes
//! interpolate geometrically (the mean of h = 1 and h = 4 with weights ½ is 2), and the
//! determinant too, which a linear mix of metrics does not do (it swells).

use super::size_tensor::SizeTensor;
use super::sym2::Sym2;

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
        let mut sum = Sym2::new(0.0, 0.0, 0.0);
        let mut any = false;
        for (w, t) in weighted {
            if !w.is_finite() {
                return None;
            }
            let log = Sym2::from_eigen([t.h1().ln(), t.h2().ln()], t.axis());
            sum = sum + w * log;
            any = true;
        }
        if !any {
            return None;
        }
        let e = sum.eigen();
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
}
