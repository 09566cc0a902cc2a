//! `SizeTensor`: orientation + two sizes, stored decomposed (thesis 3.1.4, 3.1.7, 4.3.4),
//! with the conversions to and from metric tensors (thesis 3.1.5, 3.1.6) and the global
//! size and aspect-ratio limits.

use super::sym2::Sym2;

/// What is wrong with a tensor read from a file or built from numbers.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TensorError {
    /// A component is NaN or infinite. The producer of the tensor wrote garbage; no
    /// size can be derived from it.
    #[error("tensor has a non-finite component: [a, b, c] = [{a}, {b}, {c}]")]
    NotFinite {
        /// Component xx.
        a: f64,
        /// Component xy.
        b: f64,
        /// Component yy.
        c: f64,
    },
    /// A metric tensor must be symmetric positive definite (thesis 3.1.3): its smallest
    /// eigenvalue is zero or negative, so some direction would get an infinite or
    /// imaginary size. Typically a size tensor was written where a metric was expected,
    /// or a placeholder (all zeros) was left on an unused node.
    #[error(
        "metric tensor is not positive definite: smallest eigenvalue {smallest_eigenvalue} <= 0"
    )]
    NotPositiveDefinite {
        /// The smallest eigenvalue found.
        smallest_eigenvalue: f64,
    },
    /// A size falls outside [`SizeTensor::MIN_SIZE`, `SizeTensor::MAX_SIZE`]; check the
    /// units of the tensor (a metric holds 1/h², a size tensor h).
    #[error("size {size} is outside [1e-30, 1e30]")]
    SizeOutOfRange {
        /// The offending size.
        size: f64,
    },
}

/// A size tensor: the unit vector of its first axis and the sizes h1 along it and h2
/// along the perpendicular (thesis 3.1.4, 3.1.7.1), i.e. the ellipse of semi-axes h1, h2.
///
/// Stored decomposed, as thesis 4.3.4's `SM_SIZE_TENSOR`: algorithms produce a direction
/// and two sizes, and the intersection consumes exactly that. The axis is kept unit and in
/// the half-plane x > 0 (or x = 0, y > 0); sizes are not sorted, h1 stays with the axis
/// it was given for. `PartialEq` compares representations: (e, h1, h2) and (e⊥, h2, h1) are
/// the same ellipse but different values.
///
/// The metric tensor is M = R diag(1/h1², 1/h2²) Rᵀ with R = [e, e⊥].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeTensor {
    axis: [f64; 2],
    h: [f64; 2],
}

impl SizeTensor {
    /// Smallest size accepted. With [`SizeTensor::MAX_SIZE`] it bounds the ratio of two
    /// sizes by 1e60, so that the fourth powers of such ratios, which the intersection's
    /// Gram matrices form, stay inside the normal f64 range (1e±240), and so do the metric
    /// entries 1/h². Any mesh fits: coordinates carry 16 digits.
    pub const MIN_SIZE: f64 = 1e-30;
    /// Largest size accepted.
    pub const MAX_SIZE: f64 = 1e30;

    /// The size tensor with first axis along `axis` (any non-zero vector; normalised) and
    /// sizes `h1` along it, `h2` across it.
    ///
    /// # Panics
    /// If `axis` is zero or not finite, or a size is outside [`MIN_SIZE`](Self::MIN_SIZE),
    /// [`MAX_SIZE`](Self::MAX_SIZE) or NaN. Use [`SizeTensor::try_new`] for input that was
    /// not checked yet.
    pub fn new(axis: [f64; 2], h1: f64, h2: f64) -> SizeTensor {
        match SizeTensor::try_new(axis, h1, h2) {
            Some(t) => t,
            None => panic!("invalid size tensor: axis {axis:?}, sizes {h1}, {h2}"),
        }
    }

    /// Like [`SizeTensor::new`], but `None` instead of a panic for invalid input.
    pub fn try_new(axis: [f64; 2], h1: f64, h2: f64) -> Option<SizeTensor> {
        let axis = canonical_axis(axis)?;
        if !(in_range(h1) && in_range(h2)) {
            return None;
        }
        Some(SizeTensor { axis, h: [h1, h2] })
    }

    /// The size tensor whose first axis makes the angle `radians` with the x axis.
    pub fn from_angle(radians: f64, h1: f64, h2: f64) -> Option<SizeTensor> {
        let (s, c) = radians.sin_cos();
        SizeTensor::try_new([c, s], h1, h2)
    }

    /// The isotropic size tensor of size `h` (thesis 3.1.7.2), axes x and y.
    ///
    /// # Panics
    /// If `h` is outside [`MIN_SIZE`](Self::MIN_SIZE), [`MAX_SIZE`](Self::MAX_SIZE).
    pub fn isotropic(h: f64) -> SizeTensor {
        SizeTensor::new([1.0, 0.0], h, h)
    }

    /// Builds from already checked parts (unit axis, sizes in range), canonicalising the
    /// sign of the axis.
    pub(crate) fn from_parts(axis: [f64; 2], h: [f64; 2]) -> SizeTensor {
        let axis = if axis[0] < 0.0 || (axis[0] == 0.0 && axis[1] < 0.0) {
            [-axis[0], -axis[1]]
        } else {
            axis
        };
        SizeTensor { axis, h: [clamp_size(h[0]), clamp_size(h[1])] }
    }

    /// Unit vector of the first axis.
    pub fn axis(&self) -> [f64; 2] {
        self.axis
    }

    /// Unit vector of the second axis, the first turned by +90°.
    pub fn second_axis(&self) -> [f64; 2] {
        [-self.axis[1], self.axis[0]]
    }

    /// Angle of the first axis with the x axis, in radians, in (−π/2, π/2].
    pub fn angle(&self) -> f64 {
        self.axis[1].atan2(self.axis[0])
    }

    /// The sizes `[h1, h2]` along the first and second axis.
    pub fn sizes(&self) -> [f64; 2] {
        self.h
    }

    /// Size along the first axis.
    pub fn h1(&self) -> f64 {
        self.h[0]
    }

    /// Size along the second axis.
    pub fn h2(&self) -> f64 {
        self.h[1]
    }

    /// The smaller size.
    pub fn h_min(&self) -> f64 {
        self.h[0].min(self.h[1])
    }

    /// The larger size.
    pub fn h_max(&self) -> f64 {
        self.h[0].max(self.h[1])
    }

    /// h_max / h_min, at least 1.
    pub fn aspect_ratio(&self) -> f64 {
        self.h_max() / self.h_min()
    }

    /// Length of the vector `v` measured in the metric: sqrt(vᵀ M v), computed from the
    /// decomposition as hypot(v·e/h1, v·e⊥/h2), a sum of squares without cancellation
    /// whatever the aspect ratio. An edge conforms to the tensor when this is near 1.
    pub fn metric_length(&self, v: [f64; 2]) -> f64 {
        let [ex, ey] = self.axis;
        let along = (v[0] * ex + v[1] * ey) / self.h[0];
        let across = (v[1] * ex - v[0] * ey) / self.h[1];
        along.hypot(across)
    }

    /// The desired edge length in the direction `dir` (any non-zero vector): the radius of
    /// the ellipse in that direction, |dir| / metric_length(dir).
    pub fn size_along(&self, dir: [f64; 2]) -> f64 {
        dir[0].hypot(dir[1]) / self.metric_length(dir)
    }

    /// The metric tensor M = R diag(1/h1², 1/h2²) Rᵀ (thesis 3.1.6), what files carry.
    pub fn to_metric(&self) -> Sym2 {
        Sym2::from_eigen(
            [(self.h[0] * self.h[0]).recip(), (self.h[1] * self.h[1]).recip()],
            self.axis,
        )
    }

    /// The size matrix R diag(h1, h2) Rᵀ (thesis Eq. 3.3): what ParaView's tensor glyph
    /// should be given to draw the size ellipses at scale 1.
    pub fn to_size_matrix(&self) -> Sym2 {
        Sym2::from_eigen(self.h, self.axis)
    }

    /// The size tensor of a metric tensor (thesis 3.1.5): h_i = 1/sqrt(λ_i), first axis along
    /// the eigenvector of the larger eigenvalue (so h1 <= h2).
    ///
    /// The conversion is backward stable: the metric rebuilt from the result equals `m` to
    /// a few ulps of its norm. The larger size of a very anisotropic metric is only as
    /// accurate as the entries determine it, about ε·(h_max/h_min)² relative.
    pub fn try_from_metric(m: &Sym2) -> Result<SizeTensor, TensorError> {
        m.check_spd()?;
        let e = m.eigen();
        let h = [e.values[0].sqrt().recip(), e.values[1].sqrt().recip()];
        for size in h {
            if !in_range(size) {
                return Err(TensorError::SizeOutOfRange { size });
            }
        }
        let axis =
            canonical_axis(e.vector).ok_or(TensorError::NotFinite { a: m.a, b: m.b, c: m.c })?;
        Ok(SizeTensor { axis, h })
    }

    /// The tensor limited by global bounds, as a CFD user expects:
    ///
    /// 1. each size is clamped to [h_min, h_max];
    /// 2. if then h_max/h_min of the tensor exceeds the bounds' aspect ratio, the larger size
    ///    is shrunk to smaller × max_aspect_ratio.
    ///
    /// Step 2 shrinks rather than grows, so the size across a boundary layer (the small one,
    /// the one the physics needs) is kept and the result never asks for a coarser mesh than
    /// step 1. The orientation is unchanged.
    pub fn clamp(&self, bounds: &SizeBounds) -> SizeTensor {
        let mut h = [
            self.h[0].clamp(bounds.h_min, bounds.h_max),
            self.h[1].clamp(bounds.h_min, bounds.h_max),
        ];
        let (big, small) = if h[0] >= h[1] { (0, 1) } else { (1, 0) };
        let limit = h[small] * bounds.max_aspect_ratio;
        if h[big] > limit {
            h[big] = limit;
        }
        SizeTensor { axis: self.axis, h }
    }
}

/// Global limits on size tensors: sizes in [h_min, h_max], aspect ratio at most
/// `max_aspect_ratio` (see [`SizeTensor::clamp`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeBounds {
    h_min: f64,
    h_max: f64,
    max_aspect_ratio: f64,
}

impl SizeBounds {
    /// Bounds with `MIN_SIZE <= h_min <= h_max <= MAX_SIZE` and `max_aspect_ratio >= 1`
    /// (`f64::INFINITY` for no limit); `None` otherwise.
    pub fn try_new(h_min: f64, h_max: f64, max_aspect_ratio: f64) -> Option<SizeBounds> {
        let ok = in_range(h_min) && in_range(h_max) && h_min <= h_max && max_aspect_ratio >= 1.0;
        ok.then_some(SizeBounds { h_min, h_max, max_aspect_ratio })
    }

    /// The smallest size allowed.
    pub fn h_min(&self) -> f64 {
        self.h_min
    }

    /// The largest size allowed.
    pub fn h_max(&self) -> f64 {
        self.h_max
    }

    /// The largest aspect ratio allowed.
    pub fn max_aspect_ratio(&self) -> f64 {
        self.max_aspect_ratio
    }
}

fn in_range(h: f64) -> bool {
    (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&h)
}

fn clamp_size(h: f64) -> f64 {
    h.clamp(SizeTensor::MIN_SIZE, SizeTensor::MAX_SIZE)
}

/// Normalises `v` and turns it into the half-plane x > 0 (or x = 0, y > 0).
fn canonical_axis(v: [f64; 2]) -> Option<[f64; 2]> {
    let n = v[0].hypot(v[1]);
    if !(n > 0.0 && n.is_finite()) {
        return None;
    }
    // A vector that is unit to rounding is kept as it is, so that rebuilding a tensor from
    // `axis()` gives back the same bits.
    let u = if (n - 1.0).abs() <= 2.0 * f64::EPSILON { v } else { [v[0] / n, v[1] / n] };
    Some(if u[0] < 0.0 || (u[0] == 0.0 && u[1] < 0.0) { [-u[0], -u[1]] } else { u })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constructors_validate() {
        assert!(SizeTensor::try_new([0.0, 0.0], 1.0, 1.0).is_none());
        assert!(SizeTensor::try_new([f64::NAN, 1.0], 1.0, 1.0).is_none());
        assert!(SizeTensor::try_new([1.0, 0.0], 0.0, 1.0).is_none());
        assert!(SizeTensor::try_new([1.0, 0.0], -1.0, 1.0).is_none());
        assert!(SizeTensor::try_new([1.0, 0.0], 1.0, f64::INFINITY).is_none());
        assert!(SizeTensor::try_new([1.0, 0.0], 1.0, f64::NAN).is_none());
        assert!(SizeTensor::try_new([1.0, 0.0], 1e-31, 1.0).is_none());
        let t = SizeTensor::try_new([-3.0, -4.0], 2.0, 1.0).unwrap();
        assert_eq!(t.axis(), [0.6, 0.8]);
        assert_eq!(t.sizes(), [2.0, 1.0]);
        assert_eq!(t.second_axis(), [-0.8, 0.6]);
    }

    #[test]
    #[should_panic(expected = "invalid size tensor")]
    fn new_panics_on_invalid_input() {
        let _ = SizeTensor::new([1.0, 0.0], -1.0, 1.0);
    }

    #[test]
    fn metric_of_an_axis_aligned_tensor() {
        let t = SizeTensor::new([1.0, 0.0], 0.5, 4.0);
        assert_eq!(t.to_metric(), Sym2::new(4.0, 0.0, 1.0 / 16.0));
        assert_eq!(t.to_size_matrix(), Sym2::new(0.5, 0.0, 4.0));
        assert_eq!(t.metric_length([0.5, 0.0]), 1.0);
        assert_eq!(t.size_along([0.0, -3.0]), 4.0);
    }

    #[test]
    fn metric_errors_name_the_problem() {
        let e = SizeTensor::try_from_metric(&Sym2::new(1.0, 2.0, 1.0)).unwrap_err();
        assert!(matches!(e, TensorError::NotPositiveDefinite { .. }), "{e}");
        assert!(e.to_string().contains("not positive definite"));
        let e = SizeTensor::try_from_metric(&Sym2::new(0.0, 0.0, 0.0)).unwrap_err();
        assert!(matches!(e, TensorError::NotPositiveDefinite { .. }));
        let e = SizeTensor::try_from_metric(&Sym2::new(f64::NAN, 0.0, 1.0)).unwrap_err();
        assert!(matches!(e, TensorError::NotFinite { .. }));
        let e = SizeTensor::try_from_metric(&Sym2::new(1e-250, 0.0, 1.0)).unwrap_err();
        assert!(matches!(e, TensorError::SizeOutOfRange { .. }));
    }

    #[test]
    fn clamp_keeps_the_small_size_and_shrinks_the_large_one() {
        let b = SizeBounds::try_new(0.1, 10.0, 100.0).unwrap();
        let t = SizeTensor::new([0.0, 1.0], 0.001, 50.0);
        let c = t.clamp(&b);
        assert_eq!(c.sizes(), [0.1, 10.0]);
        let b = SizeBounds::try_new(0.1, 10.0, 20.0).unwrap();
        let c = t.clamp(&b);
        assert_eq!(c.sizes(), [0.1, 2.0]);
        assert_eq!(c.axis(), t.axis());
        let b = SizeBounds::try_new(1e-3, 1e3, 5.0).unwrap();
        let c = SizeTensor::new([1.0, 0.0], 40.0, 2.0).clamp(&b);
        assert_eq!(c.sizes(), [10.0, 2.0]);
        assert!(SizeBounds::try_new(1.0, 0.5, 2.0).is_none());
        assert!(SizeBounds::try_new(0.5, 1.0, 0.9).is_none());
        assert!(SizeBounds::try_new(0.5, 1.0, f64::NAN).is_none());
        assert!(SizeBounds::try_new(0.5, 1.0, f64::INFINITY).is_some());
    }
}
