//! `SizeTensor3`: an orthonormal frame and three sizes, stored decomposed like the 2D
//! [`SizeTensor`](super::SizeTensor) (thesis 3.1.4, 4.3.4), with the conversions to and
//! from metric tensors M = R diag(1/h²) Rᵀ and the global limits of [`SizeBounds`].
//!
//! Invariants: the three axes are orthonormal to rounding and right-handed (the third is
//! the cross product of the first two), every size is in [`SizeTensor::MIN_SIZE`],
//! [`SizeTensor::MAX_SIZE`] (the same range as in 2D, for the same reason: fourth powers
//! of size ratios, which the intersection forms, stay inside f64). Sizes are not sorted:
//! each stays with the axis it was given for.

use super::eigen3::{cross, dot};
use super::size_tensor::{SizeBounds, SizeTensor};
use super::sym3::Sym3;

/// What is wrong with a 3D tensor read from a file or built from numbers (the 3D
/// counterpart of [`TensorError`](super::TensorError)).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TensorError3 {
    /// A component is NaN or infinite: the producer of the tensor wrote garbage.
    #[error("tensor has a non-finite component: [m11 m12 m22 m13 m23 m33] = {components:?}")]
    NotFinite {
        /// The components in MMG's `.sol` order.
        components: [f64; 6],
    },
    /// A metric tensor must be symmetric positive definite: its smallest eigenvalue is zero
    /// or negative, so some direction would get an infinite or imaginary size (a size
    /// tensor written where a metric was expected, or an all-zero placeholder).
    #[error(
        "metric tensor is not positive definite: smallest eigenvalue {smallest_eigenvalue} <= 0"
    )]
    NotPositiveDefinite {
        /// The smallest eigenvalue found.
        smallest_eigenvalue: f64,
    },
    /// A size falls outside [1e-30, 1e30]; check the units (a metric holds 1/h², a size
    /// tensor h).
    #[error("size {size} is outside [1e-30, 1e30]")]
    SizeOutOfRange {
        /// The offending size.
        size: f64,
    },
}

/// A 3D size tensor: an orthonormal right-handed frame and the sizes h1, h2, h3 along its
/// axes, i.e. the ellipsoid of those semi-axes. The metric is M = R diag(1/h²) Rᵀ with R
/// the matrix whose columns are the axes. `PartialEq` compares representations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeTensor3 {
    frame: [[f64; 3]; 3],
    h: [f64; 3],
}

impl SizeTensor3 {
    /// The size tensor with first axis along `first` and second along the part of `second`
    /// perpendicular to it (both normalised; the third axis is their cross product), sizes
    /// `h` along them. `None` when the axes are zero, parallel or not finite, or a size is
    /// outside [`SizeTensor::MIN_SIZE`], [`SizeTensor::MAX_SIZE`] or NaN.
    pub fn try_new(first: [f64; 3], second: [f64; 3], h: [f64; 3]) -> Option<SizeTensor3> {
        if !h.iter().all(|&x| in_range(x)) {
            return None;
        }
        let e0 = unit(first)?;
        // Gram–Schmidt twice ("twice is enough"): orthogonal to rounding even when
        // `second` is nearly parallel to `first`.
        let mut e1 = second;
        for _ in 0..2 {
            let d = dot(e1, e0);
            e1 = [e1[0] - d * e0[0], e1[1] - d * e0[1], e1[2] - d * e0[2]];
        }
        let n1 = norm(second);
        // NaN passes here and is refused by `unit` below.
        if norm(e1) <= 1e-12 * n1 {
            return None;
        }
        let e1 = unit(e1)?;
        let e2 = unit(cross(e0, e1))?;
        Some(SizeTensor3 { frame: [e0, e1, e2], h })
    }

    /// Like [`SizeTensor3::try_new`], but panics on invalid input.
    ///
    /// # Panics
    /// When [`SizeTensor3::try_new`] would return `None`.
    pub fn new(first: [f64; 3], second: [f64; 3], h: [f64; 3]) -> SizeTensor3 {
        match SizeTensor3::try_new(first, second, h) {
            Some(t) => t,
            None => panic!("invalid size tensor: axes {first:?}, {second:?}, sizes {h:?}"),
        }
    }

    /// The isotropic size tensor of size `h`, axes x, y, z.
    ///
    /// # Panics
    /// If `h` is outside [`SizeTensor::MIN_SIZE`], [`SizeTensor::MAX_SIZE`].
    pub fn isotropic(h: f64) -> SizeTensor3 {
        SizeTensor3::new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [h; 3])
    }

    /// Builds from an already orthonormal right-handed frame, clamping the sizes into range.
    pub(crate) fn from_parts(frame: [[f64; 3]; 3], h: [f64; 3]) -> SizeTensor3 {
        SizeTensor3 { frame, h: h.map(|x| x.clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE)) }
    }

    /// The three unit axes, `frame()[i]` for `sizes()[i]`.
    pub fn frame(&self) -> [[f64; 3]; 3] {
        self.frame
    }

    /// The sizes along the three axes.
    pub fn sizes(&self) -> [f64; 3] {
        self.h
    }

    /// The smallest size.
    pub fn h_min(&self) -> f64 {
        self.h[0].min(self.h[1]).min(self.h[2])
    }

    /// The largest size.
    pub fn h_max(&self) -> f64 {
        self.h[0].max(self.h[1]).max(self.h[2])
    }

    /// h_max / h_min, at least 1.
    pub fn aspect_ratio(&self) -> f64 {
        self.h_max() / self.h_min()
    }

    /// Length of `v` measured in the metric, √(vᵀ M v), from the decomposition as the norm
    /// of (v·eᵢ / hᵢ): a sum of squares without cancellation whatever the aspect ratio.
    pub fn metric_length(&self, v: [f64; 3]) -> f64 {
        let c = [0, 1, 2].map(|i| dot(v, self.frame[i]) / self.h[i]);
        c[0].hypot(c[1]).hypot(c[2])
    }

    /// The desired edge length in the direction `dir` (any non-zero vector): the radius of
    /// the ellipsoid in that direction, |dir| / metric_length(dir).
    pub fn size_along(&self, dir: [f64; 3]) -> f64 {
        norm(dir) / self.metric_length(dir)
    }

    /// The metric tensor M = R diag(1/h²) Rᵀ, what files carry.
    pub fn to_metric(&self) -> Sym3 {
        Sym3::from_eigen(self.h.map(|x| (x * x).recip()), self.frame)
    }

    /// The size matrix R diag(h) Rᵀ: what ParaView's tensor glyph should be given to draw
    /// the size ellipsoids at scale 1.
    pub fn to_size_matrix(&self) -> Sym3 {
        Sym3::from_eigen(self.h, self.frame)
    }

    /// The size tensor of a metric tensor: hᵢ = 1/√λᵢ along the eigenvectors of
    /// [`eigen3`](super::eigen3), so h1 <= h2 <= h3. Backward stable, like the 2D
    /// conversion: the metric rebuilt from the result equals `m` to a few ulps of its norm.
    pub fn try_from_metric(m: &Sym3) -> Result<SizeTensor3, TensorError3> {
        m.check_spd()?;
        let e = m.eigen();
        let h = e.values.map(|l| l.sqrt().recip());
        for size in h {
            if !in_range(size) {
                return Err(TensorError3::SizeOutOfRange { size });
            }
        }
        Ok(SizeTensor3 { frame: e.frame, h })
    }

    /// The tensor limited by global bounds, as in 2D ([`SizeTensor::clamp`]): each size
    /// clamped to [h_min, h_max], then every size above smallest × max_aspect_ratio shrunk
    /// to it. The smallest size (the one the physics asks for) is kept, nothing grows
    /// beyond the clamp of step 1, and the frame is unchanged.
    pub fn clamp(&self, bounds: &SizeBounds) -> SizeTensor3 {
        let h = self.h.map(|x| x.clamp(bounds.h_min(), bounds.h_max()));
        let limit = h[0].min(h[1]).min(h[2]) * bounds.max_aspect_ratio();
        SizeTensor3 { frame: self.frame, h: h.map(|x| x.min(limit)) }
    }
}

impl Sym3 {
    /// Checks that the matrix is symmetric positive definite, as a metric tensor must be:
    /// finite entries and all three eigenvalues strictly positive.
    pub fn check_spd(&self) -> Result<(), TensorError3> {
        if !self.is_finite() {
            return Err(TensorError3::NotFinite { components: self.to_medit() });
        }
        let smallest = self.eigen().values[2];
        if smallest > 0.0 {
            Ok(())
        } else {
            Err(TensorError3::NotPositiveDefinite { smallest_eigenvalue: smallest })
        }
    }
}

fn in_range(h: f64) -> bool {
    (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&h)
}

pub(crate) fn norm(v: [f64; 3]) -> f64 {
    v[0].hypot(v[1]).hypot(v[2])
}

/// `v` normalised, `None` when zero or not finite.
fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(v);
    (n > 0.0 && n.is_finite()).then(|| v.map(|c| c / n))
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::metric::testgen3::{arb_frame, arb_log, arb_spd, frame_defect, max_abs, max_diff};

    #[test]
    fn constructors_validate() {
        let x = [1.0, 0.0, 0.0];
        assert!(SizeTensor3::try_new([0.0; 3], x, [1.0; 3]).is_none());
        assert!(SizeTensor3::try_new(x, [2.0, 0.0, 0.0], [1.0; 3]).is_none());
        assert!(SizeTensor3::try_new(x, [0.0, f64::NAN, 1.0], [1.0; 3]).is_none());
        assert!(SizeTensor3::try_new(x, [0.0, 1.0, 0.0], [1.0, 0.0, 1.0]).is_none());
        assert!(SizeTensor3::try_new(x, [0.0, 1.0, 0.0], [1.0, 1.0, f64::NAN]).is_none());
        assert!(SizeTensor3::try_new(x, [0.0, 1.0, 0.0], [1.0, 1e31, 1.0]).is_none());
        let t = SizeTensor3::try_new([0.0, 0.0, 2.0], [3.0, 0.0, 1.0], [1.0, 2.0, 3.0]).unwrap();
        assert_eq!(t.frame(), [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        assert_eq!((t.h_min(), t.h_max(), t.aspect_ratio()), (1.0, 3.0, 3.0));
    }

    #[test]
    #[should_panic(expected = "invalid size tensor")]
    fn new_panics_on_invalid_input() {
        let _ = SizeTensor3::new([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 1.0, 1.0]);
    }

    #[test]
    fn metric_and_size_matrix_of_an_axis_aligned_tensor() {
        let t = SizeTensor3::new([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.5, 4.0, 2.0]);
        assert_eq!(t.to_metric(), Sym3::diagonal([0.25, 4.0, 1.0 / 16.0]));
        assert_eq!(t.to_size_matrix(), Sym3::diagonal([2.0, 0.5, 4.0]));
        assert_eq!(t.metric_length([0.0, 0.5, 0.0]), 1.0);
        assert_eq!(t.size_along([0.0, 0.0, -3.0]), 4.0);
        assert_eq!(t.size_along([7.0, 0.0, 0.0]), 2.0);
        let back = SizeTensor3::try_from_metric(&t.to_metric()).unwrap();
        assert_eq!(back.sizes(), [0.5, 2.0, 4.0]);
    }

    #[test]
    fn metric_errors_name_the_problem() {
        let e = SizeTensor3::try_from_metric(&Sym3::diagonal([1.0, -1.0, 1.0])).unwrap_err();
        assert!(matches!(e, TensorError3::NotPositiveDefinite { .. }), "{e}");
        assert!(e.to_string().contains("not positive definite"));
        let e = SizeTensor3::try_from_metric(&Sym3::ZERO).unwrap_err();
        assert!(matches!(e, TensorError3::NotPositiveDefinite { .. }));
        let bad = Sym3 { yz: f64::INFINITY, ..Sym3::IDENTITY };
        let e = SizeTensor3::try_from_metric(&bad).unwrap_err();
        assert!(matches!(e, TensorError3::NotFinite { .. }), "{e}");
        assert!(e.to_string().contains("inf"));
        let e = SizeTensor3::try_from_metric(&Sym3::diagonal([1.0, 1e-250, 1.0])).unwrap_err();
        assert!(matches!(e, TensorError3::SizeOutOfRange { .. }));
        // Semi-definite (rank 2): a zero eigenvalue is refused too.
        let rank2 = Sym3 { xx: 1.0, xy: 1.0, yy: 1.0, xz: 0.0, yz: 0.0, zz: 1.0 };
        assert!(SizeTensor3::try_from_metric(&rank2).is_err());
    }

    #[test]
    fn clamp_keeps_the_small_size_and_shrinks_the_large_ones() {
        let t = SizeTensor3::new([1.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.001, 50.0, 3.0]);
        let b = SizeBounds::try_new(0.1, 10.0, 100.0).unwrap();
        assert_eq!(t.clamp(&b).sizes(), [0.1, 10.0, 3.0]);
        let b = SizeBounds::try_new(0.1, 10.0, 20.0).unwrap();
        let c = t.clamp(&b);
        assert_eq!(c.sizes(), [0.1, 2.0, 2.0]);
        assert_eq!(c.frame(), t.frame());
        let b = SizeBounds::try_new(1e-3, 1e3, f64::INFINITY).unwrap();
        assert_eq!(t.clamp(&b), t);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        #[test]
        fn metric_round_trip(m in arb_spd(-6.0, 6.0)) {
            let t = SizeTensor3::try_from_metric(&m).unwrap();
            let (defect, right) = frame_defect(&t.frame());
            prop_assert!(defect <= 8.0 * f64::EPSILON && right);
            let back = t.to_metric();
            prop_assert!(max_diff(&back, &m) <= 32.0 * f64::EPSILON * max_abs(&m), "{m:?} -> {t:?}");
            let h = t.sizes();
            prop_assert!(h[0] <= h[1] && h[1] <= h[2]);
        }

        #[test]
        fn metric_length_is_the_quadratic_form(
            f in arb_frame(), h in (arb_log(-3.0, 3.0), arb_log(-3.0, 3.0), arb_log(-3.0, 3.0)),
            v in (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64),
        ) {
            let t = SizeTensor3::try_new(f[0], f[1], [h.0, h.1, h.2]).unwrap();
            let v = [v.0, v.1, v.2];
            let form = t.to_metric().quadratic_form(v).sqrt();
            // The form rounds M's entries: a relative error up to ε·(h_max/h_min)².
            let tol = 32.0 * f64::EPSILON * t.aspect_ratio().powi(2);
            prop_assert!((t.metric_length(v) - form).abs() <= tol * form);
            // The size matrix is the square root of the inverse metric: S M S = I, to the
            // rounding of M, ε·(h_max/h_min)².
            let s = t.to_size_matrix();
            let m = t.to_metric();
            for e in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
                let back = s.mul_vec(m.mul_vec(s.mul_vec(e)));
                for i in 0..3 {
                    prop_assert!((back[i] - e[i]).abs() < 64.0 * f64::EPSILON * t.aspect_ratio().powi(2));
                }
            }
        }

        #[test]
        fn clamp_respects_the_bounds(
            f in arb_frame(), h in (arb_log(-6.0, 6.0), arb_log(-6.0, 6.0), arb_log(-6.0, 6.0)),
            lo in arb_log(-4.0, 0.0), span in arb_log(0.0, 4.0), aspect in arb_log(0.0, 3.0),
        ) {
            let t = SizeTensor3::try_new(f[0], f[1], [h.0, h.1, h.2]).unwrap();
            let b = SizeBounds::try_new(lo, lo * span, aspect).unwrap();
            let c = t.clamp(&b);
            prop_assert!(c.h_min() >= b.h_min() && c.h_max() <= b.h_max());
            prop_assert!(c.aspect_ratio() <= aspect * (1.0 + 4.0 * f64::EPSILON));
            for i in 0..3 {
                // Never larger than the plain clamp (shrinks only).
                prop_assert!(c.sizes()[i] <= t.sizes()[i].clamp(b.h_min(), b.h_max()));
            }
        }
    }
}
