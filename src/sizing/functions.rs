//! Size functions: the bridges from a geometric quantity (a distance, a curvilinear
//! abscissa, a curvature) to a physical size (thesis 3.3 and 4.3.5).
//!
//! Each function is built once from its recipe parameters, checked by `try_new`, and then
//! evaluated many times with `eval`. Three exist, as in the thesis and its appendix A:
//!
//! | type | thesis | recipe list | parameters |
//! | --- | --- | --- | --- |
//! | [`DistanceFunction`] | 4.3.5.1, 3.3.1, 7.4.3 | `CREATE_DISTANCE_FUNCTIONS` | MINSIZE, MAXSIZE, MAXDISTANCE, EXPONENT |
//! | [`SizeProjectionFunction`] | 4.3.5.2 | `CREATE_PROJECTION_FUNCTIONS` | MAXSIZE, MAXDISTANCE, EXPONENT |
//! | [`CurvatureToSize`] | 4.3.5.3, 3.3.2 | `CREATE_CURVATURE_TO_SIZE_FUNCTIONS` | MINSIZE, MAXSIZE, SIZE_OF_ERROR |
//!
//! The thesis defines no separate function for the curvilinear abscissa along a polyline:
//! its distance-to-imaginary-polyline algorithm (4.3.6.5, `POLYLINE_DISTANCE_FUNCTION` in
//! appendix A.1.6) feeds the abscissa s' of the projected point to an ordinary
//! [`DistanceFunction`], so that one serves.
//!
//! Following thesis 7.4.3, the size at the source may be larger than the size at the
//! maximal distance (sizes that shrink away from the source) or equal to it (constant):
//! MINSIZE and MAXSIZE of a distance or projection function are read as SIZE_AT_BORDER and
//! SIZE_AT_MAX_DISTANCE. For a curvature-to-size function they stay true bounds.

use std::fmt;

use crate::metric::SizeTensor;

/// A parameter of a size function, named as the recipe names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parameter {
    /// Size at the source (distance 0): `MINSIZE`, or `SIZE_AT_BORDER` (thesis 7.4.3).
    SizeAtSource,
    /// Size at the maximal distance: `MAXSIZE`, or `SIZE_AT_MAX_DISTANCE` (thesis 7.4.3).
    SizeAtMaxDistance,
    /// Maximal distance of influence: `MAXDISTANCE`.
    MaxDistance,
    /// Growth exponent: `EXPONENT`.
    Exponent,
    /// Lower bound of a curvature-to-size function: `MINSIZE`.
    MinSize,
    /// Upper bound of a curvature-to-size function: `MAXSIZE`.
    MaxSize,
    /// Chordal deviation δ of a curvature-to-size function: `SIZE_OF_ERROR`.
    SizeOfError,
}

impl Parameter {
    /// The recipe key of appendix A.
    pub fn recipe_key(self) -> &'static str {
        match self {
            Parameter::SizeAtSource | Parameter::MinSize => "MINSIZE",
            Parameter::SizeAtMaxDistance | Parameter::MaxSize => "MAXSIZE",
            Parameter::MaxDistance => "MAXDISTANCE",
            Parameter::Exponent => "EXPONENT",
            Parameter::SizeOfError => "SIZE_OF_ERROR",
        }
    }

    fn meaning(self) -> &'static str {
        match self {
            Parameter::SizeAtSource => "size at the source",
            Parameter::SizeAtMaxDistance => "size at the maximal distance",
            Parameter::MaxDistance => "maximal distance",
            Parameter::Exponent => "growth exponent",
            Parameter::MinSize => "smallest size",
            Parameter::MaxSize => "largest size",
            Parameter::SizeOfError => "chordal deviation",
        }
    }
}

impl fmt::Display for Parameter {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({})", self.recipe_key(), self.meaning())
    }
}

/// A size function parameter out of its valid range. The recipe reader adds the file and
/// the line.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FunctionError {
    /// The value is outside the range the message gives: change it in the recipe.
    #[error("{parameter} = {value} is out of range: expected {expected}")]
    OutOfRange {
        /// Which parameter.
        parameter: Parameter,
        /// The value given.
        value: f64,
        /// The valid range, in words.
        expected: &'static str,
    },
    /// A curvature-to-size function clamps its sizes to [MINSIZE, MAXSIZE], so MINSIZE
    /// must not exceed MAXSIZE: swap them.
    #[error("MINSIZE = {min_size} exceeds MAXSIZE = {max_size}: a curvature-to-size function needs MINSIZE <= MAXSIZE")]
    MinAboveMax {
        /// MINSIZE as given.
        min_size: f64,
        /// MAXSIZE as given.
        max_size: f64,
    },
}

const SIZE_RANGE: &str = "a size in [1e-30, 1e30]";
const POSITIVE: &str = "a finite number > 0";

fn check_size(parameter: Parameter, value: f64) -> Result<f64, FunctionError> {
    if (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&value) {
        Ok(value)
    } else {
        Err(FunctionError::OutOfRange { parameter, value, expected: SIZE_RANGE })
    }
}

fn check_positive(parameter: Parameter, value: f64) -> Result<f64, FunctionError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(FunctionError::OutOfRange { parameter, value, expected: POSITIVE })
    }
}

/// `t^e` for `t` in [0, 1]. The exponents recipes use most skip `powf`, which costs
/// several times a square root and is evaluated twice per vertex by most algorithms:
/// t^1 is `t`, t^2 is `t·t` and t^0.5 is `sqrt(t)` (IEEE 754 rounds a product and a square
/// root correctly, which the C library's `pow` does not promise: it may be an ulp off),
/// t^1.5 is `t·sqrt(t)` (two roundings). Each is within an ulp of `powf`.
#[inline]
fn power(t: f64, e: f64) -> f64 {
    if e == 1.0 {
        t
    } else if e == 2.0 {
        t * t
    } else if e == 0.5 {
        t.sqrt()
    } else if e == 1.5 {
        t * t.sqrt()
    } else {
        t.powf(e)
    }
}

/// s0 + (d/d_max)^e (s1 − s0), with d clamped to [0, d_max], exact at both ends and kept
/// between s0 and s1 (rounding of the difference cannot overshoot). Comparisons rather
/// than `f64::clamp`, which checks its bounds with a branch on every call, twice per
/// vertex: the ends are returned as they are, and a NaN distance gives a NaN size, as
/// `clamp` would, for the caller to reject.
#[inline]
fn graded(s0: f64, s1: f64, d: f64, max_distance: f64, exponent: f64) -> f64 {
    let t = d / max_distance;
    if t >= 1.0 {
        return s1;
    }
    if t <= 0.0 {
        return s0;
    }
    let w = power(t, exponent);
    let s = s0 + w * (s1 - s0);
    let (lo, hi) = if s0 <= s1 { (s0, s1) } else { (s1, s0) };
    if s < lo {
        lo
    } else if s > hi {
        hi
    } else {
        s
    }
}

/// Size as a function of the distance to a source (thesis 4.3.5.1, 3.3.1):
///
///   s(d) = s_source + (d / d_max)^e (s_max_distance − s_source),   0 <= d <= d_max.
///
/// e = 1 grows linearly, e = 2 or 3 slowly near the source then faster, e = 1/2 fast then
/// slowly (thesis 3.3.1). As thesis 7.4.3 proposes, the size at the source may be larger
/// than the size at the maximal distance (the size shrinks away from the source) or equal
/// to it. Distances past d_max give the size at d_max and negative ones the size at the
/// source, so the function is continuous and monotone on the whole line; algorithms stop
/// at d_max anyway. Also the `POLYLINE_DISTANCE_FUNCTION` of thesis 4.3.6.5, evaluated at
/// a curvilinear abscissa.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceFunction {
    size_at_source: f64,
    size_at_max_distance: f64,
    max_distance: f64,
    exponent: f64,
}

impl DistanceFunction {
    /// Checks the parameters: both sizes in [1e-30, 1e30], `max_distance` and `exponent`
    /// finite and > 0.
    pub fn try_new(
        size_at_source: f64,
        size_at_max_distance: f64,
        max_distance: f64,
        exponent: f64,
    ) -> Result<DistanceFunction, FunctionError> {
        Ok(DistanceFunction {
            size_at_source: check_size(Parameter::SizeAtSource, size_at_source)?,
            size_at_max_distance: check_size(Parameter::SizeAtMaxDistance, size_at_max_distance)?,
            max_distance: check_positive(Parameter::MaxDistance, max_distance)?,
            exponent: check_positive(Parameter::Exponent, exponent)?,
        })
    }

    /// The size at distance `d` (NaN gives NaN).
    pub fn eval(&self, d: f64) -> f64 {
        graded(self.size_at_source, self.size_at_max_distance, d, self.max_distance, self.exponent)
    }

    /// The size at distance 0 (`MINSIZE` / `SIZE_AT_BORDER`).
    pub fn size_at_source(&self) -> f64 {
        self.size_at_source
    }

    /// The size at the maximal distance (`MAXSIZE` / `SIZE_AT_MAX_DISTANCE`).
    pub fn size_at_max_distance(&self) -> f64 {
        self.size_at_max_distance
    }

    /// The maximal distance of influence (`MAXDISTANCE`).
    pub fn max_distance(&self) -> f64 {
        self.max_distance
    }

    /// The exponent (`EXPONENT`).
    pub fn exponent(&self) -> f64 {
        self.exponent
    }
}

/// Size projection function (thesis 4.3.5.2): like [`DistanceFunction`] but the size at the
/// source, s0, varies along the source and is given at each evaluation:
///
///   s(d, s0) = s0 + (d / d_max)^e (s_max_distance − s0),   0 <= d <= d_max.
///
/// It carries a size known on a boundary (from curvature, or from a function of the
/// curvilinear abscissa) into the domain. Same extension outside [0, d_max] and same
/// freedom as in thesis 7.4.3: s0 may exceed the size at the maximal distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeProjectionFunction {
    size_at_max_distance: f64,
    max_distance: f64,
    exponent: f64,
}

impl SizeProjectionFunction {
    /// Checks the parameters: the size in [1e-30, 1e30], `max_distance` and `exponent`
    /// finite and > 0.
    pub fn try_new(
        size_at_max_distance: f64,
        max_distance: f64,
        exponent: f64,
    ) -> Result<SizeProjectionFunction, FunctionError> {
        Ok(SizeProjectionFunction {
            size_at_max_distance: check_size(Parameter::SizeAtMaxDistance, size_at_max_distance)?,
            max_distance: check_positive(Parameter::MaxDistance, max_distance)?,
            exponent: check_positive(Parameter::Exponent, exponent)?,
        })
    }

    /// The size at distance `d` from a source point whose size is `size_at_source`.
    pub fn eval(&self, d: f64, size_at_source: f64) -> f64 {
        graded(size_at_source, self.size_at_max_distance, d, self.max_distance, self.exponent)
    }

    /// The size at the maximal distance (`MAXSIZE` / `SIZE_AT_MAX_DISTANCE`).
    pub fn size_at_max_distance(&self) -> f64 {
        self.size_at_max_distance
    }

    /// The maximal distance of influence (`MAXDISTANCE`).
    pub fn max_distance(&self) -> f64 {
        self.max_distance
    }

    /// The exponent (`EXPONENT`).
    pub fn exponent(&self) -> f64 {
        self.exponent
    }
}

/// Curvature-to-size function (thesis 4.3.5.3, 3.3.2): the length h of a chord whose
/// deviation from the osculating circle of radius r = 1/κ is δ (`SIZE_OF_ERROR`),
///
///   h = 2 sqrt(δ (2r − δ)),   clamped to [s_min, s_max].
///
/// A straight boundary (κ = 0, r = ∞) gets s_max. When δ >= r the formula would fall
/// again (its maximum 2r is at δ = r, the chord through the centre); any chord of such a
/// small circle deviates less than δ, so the size is the diameter 2r there. That keeps h
/// continuous and decreasing in κ; the clamp to s_min then applies. The sign of κ is
/// ignored.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureToSize {
    min_size: f64,
    max_size: f64,
    size_of_error: f64,
}

impl CurvatureToSize {
    /// Checks the parameters: both sizes in [1e-30, 1e30] with `min_size <= max_size`, the
    /// chordal deviation `size_of_error` finite and > 0.
    pub fn try_new(
        min_size: f64,
        max_size: f64,
        size_of_error: f64,
    ) -> Result<CurvatureToSize, FunctionError> {
        let min_size = check_size(Parameter::MinSize, min_size)?;
        let max_size = check_size(Parameter::MaxSize, max_size)?;
        if min_size > max_size {
            return Err(FunctionError::MinAboveMax { min_size, max_size });
        }
        let size_of_error = check_positive(Parameter::SizeOfError, size_of_error)?;
        Ok(CurvatureToSize { min_size, max_size, size_of_error })
    }

    /// The size for curvature `curvature` (1/length; NaN gives NaN).
    pub fn eval(&self, curvature: f64) -> f64 {
        self.eval_radius(curvature.abs().recip())
    }

    /// The size for the radius of curvature `radius` (`f64::INFINITY` for a straight line).
    pub fn eval_radius(&self, radius: f64) -> f64 {
        let r = radius.abs();
        let delta = self.size_of_error;
        let h = if r > delta { 2.0 * (delta * (2.0 * r - delta)).sqrt() } else { 2.0 * r };
        h.clamp(self.min_size, self.max_size)
    }

    /// The smallest size (`MINSIZE`).
    pub fn min_size(&self) -> f64 {
        self.min_size
    }

    /// The largest size (`MAXSIZE`).
    pub fn max_size(&self) -> f64 {
        self.max_size
    }

    /// The chordal deviation δ (`SIZE_OF_ERROR`).
    pub fn size_of_error(&self) -> f64 {
        self.size_of_error
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_function_of_the_appendix_example() {
        // F3: MINSIZE = 0.05; MAXSIZE = 0.25; MAXDISTANCE = 0.5; EXPONENT = 3.0.
        let f = DistanceFunction::try_new(0.05, 0.25, 0.5, 3.0).unwrap();
        assert_eq!(f.eval(0.0), 0.05);
        assert_eq!(f.eval(0.5), 0.25);
        assert!((f.eval(0.25) - (0.05 + 0.125 * 0.2)).abs() < 1e-16);
        assert_eq!(f.eval(7.0), 0.25);
        assert_eq!(f.eval(-1.0), 0.05);
        assert!(f.eval(f64::NAN).is_nan());
    }

    #[test]
    fn curvature_to_size_special_cases() {
        let f = CurvatureToSize::try_new(0.1, 1.0, 0.1).unwrap();
        assert_eq!(f.eval(0.0), 1.0);
        assert_eq!(f.eval_radius(f64::INFINITY), 1.0);
        assert_eq!(f.eval(f64::INFINITY), 0.1);
        assert_eq!(f.eval(-0.0), 1.0);
        // r = 1: h = 2 sqrt(0.1 · 1.9).
        assert!((f.eval(1.0) - 2.0 * 0.19f64.sqrt()).abs() < 1e-15);
        assert_eq!(f.eval(-1.0), f.eval(1.0));
    }

    /// The shortcuts of `power` against `powf`, on 10^5 values of t spread over [0, 1]
    /// and its ends: t^1 the same bits, t^2, t^0.5 and t^1.5 within an ulp (the C
    /// library's `pow` may itself be an ulp from the correctly rounded `sqrt`).
    #[test]
    fn power_shortcuts_agree_with_powf() {
        let ulp = |x: f64| f64::from_bits(x.to_bits() + 1) - x;
        let mut ts: Vec<f64> = (0..100_000).map(|k| (k as f64 / 99_999.0).powi(3)).collect();
        ts.extend([0.0, f64::MIN_POSITIVE, 1e-300, 0.5, 1.0 - f64::EPSILON, 1.0]);
        for &t in &ts {
            assert_eq!(power(t, 1.0).to_bits(), t.to_bits());
            for e in [2.0, 0.5, 1.5] {
                let (fast, slow) = (power(t, e), t.powf(e));
                assert!(
                    (fast - slow).abs() <= ulp(slow),
                    "t = {t:e}, e = {e}: {fast:e} against {slow:e}"
                );
            }
            assert_eq!(power(t, 0.5).to_bits(), t.sqrt().to_bits());
        }
        assert_eq!(power(0.3, 3.0), 0.3f64.powf(3.0));
    }

    /// `graded` against its definition written with `f64::clamp`, bit for bit: inside
    /// (0, d_max), at both ends, past them, negative, infinite and NaN distances, sizes
    /// growing, shrinking and equal, every exponent shortcut and `powf`.
    #[test]
    fn graded_is_the_clamped_formula() {
        let by_definition = |s0: f64, s1: f64, d: f64, m: f64, e: f64| {
            let t = (d / m).clamp(0.0, 1.0);
            if t >= 1.0 {
                return s1;
            }
            (s0 + power(t, e) * (s1 - s0)).clamp(s0.min(s1), s0.max(s1))
        };
        let mut ds: Vec<f64> = (0..2_000).map(|k| (k as f64 / 1_000.0 - 0.5) * 3.0).collect();
        ds.extend([
            0.0,
            -0.0,
            1.0,
            1.0 - f64::EPSILON,
            1.0 + f64::EPSILON,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            1e-300,
        ]);
        for (s0, s1) in
            [(0.001, 0.1), (0.1, 0.001), (0.3, 0.3), (1e-30, 1e30), (0.7, 0.7000000000000001)]
        {
            for m in [1.0, 0.37, 1e-6] {
                for e in [1.0, 2.0, 0.5, 1.5, 3.0, 0.25] {
                    for &d in &ds {
                        let (fast, slow) =
                            (graded(s0, s1, d * m, m, e), by_definition(s0, s1, d * m, m, e));
                        assert!(
                            fast.to_bits() == slow.to_bits() || (fast.is_nan() && slow.is_nan()),
                            "s0 {s0}, s1 {s1}, d {}, m {m}, e {e}: {fast:e} against {slow:e}",
                            d * m
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn messages_name_the_parameter_and_range() {
        let e = DistanceFunction::try_new(0.1, 1.0, -5.0, 1.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "MAXDISTANCE (maximal distance) = -5 is out of range: expected a finite number > 0"
        );
    }
}
