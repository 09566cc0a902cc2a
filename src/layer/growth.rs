//! The heights of the layers: first height `h0`, growth ratio `r`, `n` layers, total
//! thickness `T = h0 (rⁿ − 1)/(r − 1)` (`n h0` when `r = 1`). Any three of the four fix
//! the fourth, as snappyHexMesh accepts; the ratio defaults to 1.2 when it is not given and
//! two of the others are. A layer count solved from `T` is rounded, and the ratio is then
//! solved again so that `h0` and `T` hold exactly.
//!
//! The first height may also come from a target y⁺ at a Reynolds number over a reference
//! length, through the flat-plate skin friction at that length: Blasius's laminar
//! `Cf = 0.664 Re^(-1/2)` below `Re = 5·10⁵`, White's turbulent `Cf = 0.026 Re^(-1/7)`
//! above (F. M. White, *Fluid Mechanics*, 7th ed., eq. 7.45). With `u_τ = U √(Cf/2)`,
//! `y = y⁺ ν / u_τ = y⁺ L / (Re √(Cf/2))`.

/// Most layers one skin may have.
pub const MAX_LAYERS: usize = 1000;

/// The ratio used when only two of `h0`, `n`, `T` are given.
pub const DEFAULT_RATIO: f64 = 1.2;

/// Heights of a skin's layers.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Growth {
    /// Height of the first cell, at the wall.
    pub first_height: f64,
    /// Ratio of each layer's height to the one below.
    pub ratio: f64,
    /// Number of layers.
    pub layers: usize,
}

/// Why the heights could not be fixed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GrowthError {
    /// Too few values.
    #[error("the layer heights need the first height and the layer count or the thickness (or the layer count and the thickness); {0}")]
    TooFew(String),
    /// A value out of range.
    #[error("{0}")]
    OutOfRange(String),
    /// Four values that disagree.
    #[error("first height {h0}, ratio {r} and {n} layers make a thickness of {t_from}, not the {t} given; give three of the four")]
    Inconsistent {
        /// First height.
        h0: f64,
        /// Ratio.
        r: f64,
        /// Layers.
        n: usize,
        /// The thickness they make.
        t_from: f64,
        /// The thickness given.
        t: f64,
    },
}

fn thickness_of(h0: f64, r: f64, n: usize) -> f64 {
    if (r - 1.0).abs() < 1e-12 {
        h0 * n as f64
    } else {
        h0 * (r.powi(n as i32) - 1.0) / (r - 1.0)
    }
}

/// The ratio `r` with `thickness_of(h0, r, n) == t` (bisection in log r; the thickness grows
/// with r).
fn solve_ratio(h0: f64, n: usize, t: f64) -> f64 {
    let (mut lo, mut hi) = ((1e-3f64).ln(), (1e3f64).ln());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if thickness_of(h0, mid.exp(), n) < t {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi)).exp()
}

fn positive(name: &str, v: Option<f64>) -> Result<Option<f64>, GrowthError> {
    match v {
        Some(x) if !(x > 0.0 && x.is_finite()) => {
            Err(GrowthError::OutOfRange(format!("{name} {x}: expected a positive number")))
        }
        _ => Ok(v),
    }
}

impl Growth {
    /// The heights from any three of first height, ratio, layer count and thickness (the
    /// ratio defaulting to [`DEFAULT_RATIO`]).
    pub fn solve(
        first_height: Option<f64>,
        ratio: Option<f64>,
        layers: Option<usize>,
        thickness: Option<f64>,
    ) -> Result<Growth, GrowthError> {
        let h0 = positive("first height", first_height)?;
        let r = positive("growth ratio", ratio)?;
        let t = positive("thickness", thickness)?;
        if let Some(n) = layers {
            if n == 0 || n > MAX_LAYERS {
                return Err(GrowthError::OutOfRange(format!(
                    "{n} layers: expected 1 to {MAX_LAYERS}"
                )));
            }
        }
        if let Some(r) = r {
            if !(0.1..=10.0).contains(&r) {
                return Err(GrowthError::OutOfRange(format!(
                    "growth ratio {r}: expected 0.1 to 10"
                )));
            }
        }
        let g = match (h0, r, layers, t) {
            (Some(h0), Some(r), Some(n), t) => {
                let made = thickness_of(h0, r, n);
                if let Some(t) = t {
                    if (made - t).abs() > 1e-9 * t.max(made) {
                        return Err(GrowthError::Inconsistent { h0, r, n, t_from: made, t });
                    }
                }
                Growth { first_height: h0, ratio: r, layers: n }
            }
            (Some(h0), None, Some(n), Some(t)) => {
                Growth { first_height: h0, ratio: solve_ratio(h0, n, t), layers: n }
            }
            (None, r, Some(n), Some(t)) => {
                let r = r.unwrap_or(DEFAULT_RATIO);
                Growth { first_height: t / thickness_of(1.0, r, n), ratio: r, layers: n }
            }
            (Some(h0), r, None, Some(t)) => {
                let r = r.unwrap_or(DEFAULT_RATIO);
                if t < h0 {
                    return Err(GrowthError::OutOfRange(format!(
                        "thickness {t} is below the first height {h0}"
                    )));
                }
                // The real count that makes `t` exactly, rounded; then the ratio again.
                let exact = if (r - 1.0).abs() < 1e-12 {
                    t / h0
                } else {
                    (1.0 + t * (r - 1.0) / h0).ln() / r.ln()
                };
                let n = (exact.round() as usize).max(1);
                if n > MAX_LAYERS {
                    return Err(GrowthError::OutOfRange(format!(
                        "thickness {t} needs {n} layers of first height {h0} (at most {MAX_LAYERS})"
                    )));
                }
                let ratio = if n == 1 { 1.0 } else { solve_ratio(h0, n, t) };
                let first_height = if n == 1 { t } else { h0 };
                Growth { first_height, ratio, layers: n }
            }
            (Some(h0), None, Some(n), None) => {
                Growth { first_height: h0, ratio: DEFAULT_RATIO, layers: n }
            }
            _ => {
                let given: Vec<&str> = [
                    (h0.is_some(), "first height"),
                    (r.is_some(), "ratio"),
                    (layers.is_some(), "layer count"),
                    (t.is_some(), "thickness"),
                ]
                .iter()
                .filter(|g| g.0)
                .map(|g| g.1)
                .collect();
                let said = if given.is_empty() {
                    "none was given".to_string()
                } else {
                    format!("only {} given", given.join(" and "))
                };
                return Err(GrowthError::TooFew(said));
            }
        };
        Ok(g)
    }

    /// The height of each layer, wall first.
    pub fn heights(&self) -> Vec<f64> {
        let mut h = Vec::with_capacity(self.layers);
        let mut x = self.first_height;
        for _ in 0..self.layers {
            h.push(x);
            x *= self.ratio;
        }
        h
    }

    /// Distance of each layer front from the wall: `0, h0, h0 + h1, …, T` (`n + 1` values).
    pub fn offsets(&self) -> Vec<f64> {
        let mut s = vec![0.0];
        let mut acc = 0.0;
        for h in self.heights() {
            acc += h;
            s.push(acc);
        }
        s
    }

    /// Total thickness.
    pub fn thickness(&self) -> f64 {
        thickness_of(self.first_height, self.ratio, self.layers)
    }
}

/// Flat-plate skin-friction coefficient at Reynolds number `re` (laminar Blasius below
/// 5·10⁵, White's turbulent correlation above).
pub fn skin_friction(re: f64) -> f64 {
    if re < 5e5 {
        0.664 / re.sqrt()
    } else {
        0.026 / re.powf(1.0 / 7.0)
    }
}

/// First-cell height for a target `y_plus` at Reynolds number `re` over the reference
/// `length`.
pub fn first_height_for_y_plus(y_plus: f64, re: f64, length: f64) -> Result<f64, GrowthError> {
    for (name, v) in [("y+", y_plus), ("Reynolds number", re), ("reference length", length)] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(GrowthError::OutOfRange(format!("{name} {v}: expected a positive number")));
        }
    }
    Ok(y_plus * length / (re * (skin_friction(re) / 2.0).sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sum(g: &Growth) -> f64 {
        g.heights().iter().sum()
    }

    #[test]
    fn three_of_four_fix_the_fourth() {
        let g = Growth::solve(Some(0.01), Some(1.5), Some(4), None).unwrap();
        assert!((g.thickness() - 0.01 * (1.0 + 1.5 + 2.25 + 3.375)).abs() < 1e-15);
        assert!((sum(&g) - g.thickness()).abs() < 1e-15);
        let r = Growth::solve(Some(0.01), None, Some(4), Some(g.thickness())).unwrap();
        assert!((r.ratio - 1.5).abs() < 1e-9, "{r:?}");
        let h = Growth::solve(None, Some(1.5), Some(4), Some(g.thickness())).unwrap();
        assert!((h.first_height - 0.01).abs() < 1e-12);
        let n = Growth::solve(Some(0.01), Some(1.5), None, Some(g.thickness())).unwrap();
        assert_eq!(n.layers, 4);
        assert!((n.ratio - 1.5).abs() < 1e-9);
        // Thickness not reachable with an integer count: count rounded, ratio re-solved.
        let m = Growth::solve(Some(0.01), Some(1.2), None, Some(0.1)).unwrap();
        assert!((sum(&m) - 0.1).abs() < 1e-9 && m.first_height == 0.01, "{m:?}");
        let flat = Growth::solve(Some(0.1), Some(1.0), Some(3), None).unwrap();
        assert!((flat.thickness() - 0.3).abs() < 1e-15);
        let offs = g.offsets();
        assert_eq!(offs.len(), 5);
        assert!((offs[4] - g.thickness()).abs() < 1e-15);
    }

    #[test]
    fn bad_or_too_few_values_are_refused() {
        assert!(matches!(Growth::solve(Some(0.01), None, None, None), Err(GrowthError::TooFew(_))));
        assert!(matches!(
            Growth::solve(None, Some(1.2), Some(3), None),
            Err(GrowthError::TooFew(_))
        ));
        assert!(Growth::solve(Some(-1.0), Some(1.2), Some(3), None).is_err());
        assert!(Growth::solve(Some(0.1), Some(1.2), Some(0), None).is_err());
        assert!(matches!(
            Growth::solve(Some(0.1), Some(1.2), Some(3), Some(1.0)),
            Err(GrowthError::Inconsistent { .. })
        ));
    }

    #[test]
    fn y_plus_height_matches_the_correlations_by_hand() {
        // Laminar: Re 5000, y+ 1, L 1: Cf = 0.664/sqrt(5000), y = 1/(5000 sqrt(Cf/2)).
        let cf: f64 = 0.664 / 5000f64.sqrt();
        let y = first_height_for_y_plus(1.0, 5000.0, 1.0).unwrap();
        assert!((y - 1.0 / (5000.0 * (cf / 2.0).sqrt())).abs() < 1e-15);
        assert!((y - 2.9185e-3).abs() < 1e-6, "{y}");
        // Turbulent: Re 1e6: Cf = 0.026 / 1e6^(1/7).
        let cf: f64 = 0.026 / 1e6f64.powf(1.0 / 7.0);
        let y = first_height_for_y_plus(1.0, 1e6, 2.0).unwrap();
        assert!((y - 2.0 / (1e6 * (cf / 2.0).sqrt())).abs() < 1e-15);
        assert!(first_height_for_y_plus(1.0, 0.0, 1.0).is_err());
    }
}
