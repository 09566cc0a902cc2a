//! Robust size-tensor intersection (thesis 3.2.2) and its dual, the union.
//!
//! Method (thesis 3.2.2, after its reference [28]): map the first ellipse E1 onto the unit
//! circle by T = D1⁻¹ R1ᵀ (R1 its axes, D1 = diag(h1, h2)); in that space E2 becomes
//! E2' = { y : |G y| <= 1 } with G = D2⁻¹ R2ᵀ R1 D1. The singular value decomposition
//! G = U diag(σ1, σ2) Vᵀ gives the common axes v1, v2 (the simultaneous reduction) and the
//! semi-axes 1/σ_i of E2'. The largest ellipse inside both is, in that space, the ellipse
//! of axes v_i and semi-axes min(1, 1/σ_i); the smallest containing both takes max(1, 1/σ_i).
//! Both are optimal: each is symmetric about v1 and v2, and no axis-aligned ellipse inside
//! (containing) both can have a longer (shorter) semi-axis. T⁻¹ maps the result back: its
//! sizes and axes are the SVD of D1 V diag(s1, s2), turned by R1. In metric terms this is
//! the standard M1 ∩ M2 = P⁻ᵀ diag(max(λ1_i, λ2_i)) P⁻¹ (union: min).
//!
//! Why this formulation: it never forms a metric matrix, so nothing squares an aspect
//! ratio. Both matrices it decomposes are graded, diagonal × rotation × diagonal, with the
//! relative rotation taken from the two stored unit vectors by compensated products (its
//! sine is exact for nearly parallel axes); `svd2::right_singular` gets their singular vectors to
//! full relative accuracy and their smaller singular values from exact determinants
//! (products of sizes). So equal, nested, isotropic, nearly degenerate and 1e6-aspect
//! inputs go through the same code, nothing divides by a gap between eigenvalues, and
//! Alauzet's failure cases (thesis 3.2.1: equal or nested matrices) do not exist. Nested
//! inputs (one σ test) return the inner (outer) input bit for bit. The sizes agree with
//! 60-digit evaluations to 1e-12 at aspect ratio 1e6 (tests/metric.rs).
//!
//! Cost: two symmetric 2×2 eigen-solves in closed form, a few square roots and divisions,
//! no trigonometry.

use super::size_tensor::SizeTensor;
use super::svd2::right_singular;

/// Relative slack of the nesting test: singular values within a few ulps of 1 count as 1,
/// so A ∩ A returns A exactly instead of a rounded copy.
const NESTED_SLACK: f64 = 8.0 * f64::EPSILON;

#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Intersection,
    Union,
}

impl SizeTensor {
    /// The largest size tensor (ellipse) contained in both `self` and `other`: the robust
    /// size-tensor intersection of thesis 3.2.2. In metric terms, the metric whose unit
    /// ball lies in both unit balls, M1 ∩ M2 = P⁻ᵀ diag(max(λ1_i, λ2_i)) P⁻¹.
    ///
    /// Never fails. Commutative bit for bit (the operands are put in a fixed order first),
    /// idempotent, and returns the inner tensor exactly when one contains the other. Not
    /// associative (thesis 3.2.2). Containment holds to rounding: for every direction u,
    /// `result.size_along(u) <= self.size_along(u)` within a relative error of order
    /// ε·aspect ratio (the stored unit axis carries an angle error of order ε, which moves
    /// the radius of a thin ellipse that much).
    pub fn intersection(&self, other: &SizeTensor) -> SizeTensor {
        combine(self, other, Mode::Intersection)
    }

    /// The smallest size tensor (ellipse) containing both `self` and `other`, in the same
    /// simultaneous reduction as [`SizeTensor::intersection`] (in metric terms
    /// P⁻ᵀ diag(min(λ1_i, λ2_i)) P⁻¹). Same guarantees, with containment reversed.
    pub fn union(&self, other: &SizeTensor) -> SizeTensor {
        combine(self, other, Mode::Union)
    }
}

/// A total order on representations, so that `combine(a, b)` and `combine(b, a)` do the
/// same arithmetic.
fn ordered<'t>(a: &'t SizeTensor, b: &'t SizeTensor) -> (&'t SizeTensor, &'t SizeTensor) {
    let key = |t: &SizeTensor| [t.h1(), t.h2(), t.axis()[0], t.axis()[1]];
    let (ka, kb) = (key(a), key(b));
    for i in 0..4 {
        match ka[i].total_cmp(&kb[i]) {
            std::cmp::Ordering::Less => return (a, b),
            std::cmp::Ordering::Greater => return (b, a),
            std::cmp::Ordering::Equal => {}
        }
    }
    (a, b)
}

/// x·y − z·w with one rounding error (Kahan's algorithm with a fused multiply-add).
fn diff_of_products(x: f64, y: f64, z: f64, w: f64) -> f64 {
    let zw = z * w;
    let err = z.mul_add(w, -zw);
    x.mul_add(y, -zw) - err
}

fn combine(a: &SizeTensor, b: &SizeTensor, mode: Mode) -> SizeTensor {
    let (e1, e2) = ordered(a, b);
    if e1 == e2 {
        return *e1;
    }
    let (inner_2, inner_1) = match mode {
        // E2 inside E1: the intersection is E2, the union E1.
        Mode::Intersection => (*e2, *e1),
        Mode::Union => (*e1, *e2),
    };
    // Bounding circles decide the easy nestings without any rounding.
    if e2.h_max() <= e1.h_min() {
        return inner_2;
    }
    if e1.h_max() <= e2.h_min() {
        return inner_1;
    }

    let [p, q] = e1.sizes();
    let [r1, r2] = e2.sizes();
    let [c1, s1] = e1.axis();
    let [c2, s2] = e2.axis();
    // R2ᵀ R1 = [[C, −S], [S, C]], the rotation by angle(e1) − angle(e2), from the stored unit
    // vectors with compensated products (S is small and exact for nearly parallel axes).
    let cos = diff_of_products(c1, c2, -s1, s2);
    let sin = diff_of_products(s1, c2, c1, s2);
    // G = D2⁻¹ R2ᵀ R1 D1 = diag(1/r1, 1/r2) Rot(C, S) diag(p, q).
    let sg = right_singular([r1.recip(), r2.recip()], [cos, sin], [p, q]);
    let [sigma1, sigma2] = sg.sigma;

    if sigma2 >= 1.0 - NESTED_SLACK {
        // E2' lies in the unit disc: E2 ⊂ E1.
        return inner_2;
    }
    if sigma1 <= 1.0 + NESTED_SLACK {
        // The unit disc lies in E2': E1 ⊂ E2.
        return inner_1;
    }

    // σ1 > 1 > σ2: the semi-axes along v1, v2 in the space where E1 is the unit circle.
    let scale = match mode {
        Mode::Intersection => [sigma1.recip(), 1.0],
        Mode::Union => [1.0, sigma2.recip()],
    };
    // B = D1 [v1 v2] diag(scale) with v2 = v1⊥, again graded; the result's axes are its
    // left singular vectors, the right ones of Bᵀ = diag(scale) Rot(v)ᵀ D1.
    let [vx, vy] = sg.vector;
    let sb = right_singular(scale, [vx, -vy], [p, q]);
    // Back to the world frame: R1 u.
    let [ux, uy] = sb.vector;
    let axis = [c1 * ux - s1 * uy, s1 * ux + c1 * uy];
    let n = axis[0].hypot(axis[1]);
    SizeTensor::from_parts([axis[0] / n, axis[1] / n], sb.sigma)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_axis_aligned_ellipses() {
        let a = SizeTensor::new([1.0, 0.0], 4.0, 1.0);
        let b = SizeTensor::new([1.0, 0.0], 1.0, 4.0);
        let i = a.intersection(&b);
        assert!((i.h1() - 1.0).abs() < 1e-15 && (i.h2() - 1.0).abs() < 1e-15, "{i:?}");
        let u = a.union(&b);
        assert!((u.h_min() - 4.0).abs() < 1e-14 && (u.h_max() - 4.0).abs() < 1e-14, "{u:?}");
        let c = SizeTensor::new([1.0, 0.0], 2.0, 0.5);
        let i = c.intersection(&SizeTensor::isotropic(1.0));
        assert!((i.size_along([1.0, 0.0]) - 1.0).abs() < 1e-15, "{i:?}");
        assert!((i.size_along([0.0, 1.0]) - 0.5).abs() < 1e-15, "{i:?}");
    }

    #[test]
    fn nested_returns_the_inner_one_exactly() {
        let big = SizeTensor::new([1.0, 1.0], 10.0, 3.0);
        let small = SizeTensor::new([1.0, -2.0], 2.0, 0.5);
        assert_eq!(big.intersection(&small), small);
        assert_eq!(small.intersection(&big), small);
        assert_eq!(big.union(&small), big);
        assert_eq!(big.intersection(&big), big);
    }

    #[test]
    fn diff_of_products_is_exact_for_cancelling_terms() {
        let x = 1.0 + f64::EPSILON;
        assert_eq!(
            diff_of_products(x, x, 1.0, 1.0),
            2.0 * f64::EPSILON + f64::EPSILON * f64::EPSILON
        );
    }
}
