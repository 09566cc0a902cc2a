//! Singular value decomposition of a graded 2×2 matrix M = diag(α) Rot diag(β), the kernel
//! of the simultaneous reduction in the robust size-tensor intersection (thesis 3.2.2): both
//! matrices that the intersection decomposes have that form (a diagonal of sizes, a
//! rotation, a diagonal of sizes).
//!
//! Method: the right (left) singular vectors are the eigenvectors of MᵀM (M Mᵀ), which for
//! this structure have closed-form entries with no cancellation but a difference of data:
//!
//!   MᵀM = [[β1²(α1²c² + α2²s²), β1β2 c s (α2² − α1²)], [·, β2²(α1²s² + α2²c²)]]
//!   M Mᵀ = [[α1²(β1²c² + β2²s²), α1α2 c s (β1² − β2²)], [·, α2²(β1²s² + β2²c²)]]
//!
//! with x² − y² evaluated as (x − y)(x + y). Each entry is then accurate to a few ulps
//! relative to itself, so [`eigen2`](super::eigen2)'s half-angle eigenvector gets small
//! components (nearly aligned ellipses, the hard case of thin intersections) to full
//! relative accuracy — an angle from `atan2` sums would carry an absolute error of ε
//! instead, which a 1e6 aspect ratio turns into 1e-10 on the sizes. σ1 is the square root
//! of the larger eigenvalue (a sum, no cancellation) and σ2 = det M / σ1 with
//! det M = α1α2β1β2 exactly, so both singular values are accurate to a few ulps whatever
//! the aspect ratio. α and β are first divided by their largest entry, so nothing squared
//! overflows. Cost: one closed-form symmetric eigen-solve.

use super::eigen2::eigen2;
use super::sym2::Sym2;

/// The singular values of a matrix and its first right singular vector.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Singular {
    /// First right singular vector (unit, up to sign, which ellipse axes ignore).
    pub vector: [f64; 2],
    /// σ1 >= σ2 > 0.
    pub sigma: [f64; 2],
}

/// x² − y² without the cancellation of the squares.
fn diff_of_squares(x: f64, y: f64) -> f64 {
    (x - y) * (x + y)
}

/// Singular values and first right singular vector of diag(α) [[c, −s], [s, c]] diag(β),
/// with α, β > 0 and (c, s) a unit vector. The left singular vectors of that matrix are the
/// right ones of its transpose, `right_singular(β, [c, −s], α)`.
pub(crate) fn right_singular(alpha: [f64; 2], rotation: [f64; 2], beta: [f64; 2]) -> Singular {
    let ka = alpha[0].max(alpha[1]);
    let kb = beta[0].max(beta[1]);
    let (a1, a2) = (alpha[0] / ka, alpha[1] / ka);
    let (b1, b2) = (beta[0] / kb, beta[1] / kb);
    let [c, s] = rotation;
    let (cc, ss) = (c * c, s * s);
    let gram = Sym2 {
        a: b1 * b1 * (a1 * a1 * cc + a2 * a2 * ss),
        b: b1 * b2 * c * s * diff_of_squares(a2, a1),
        c: b2 * b2 * (a1 * a1 * ss + a2 * a2 * cc),
    };
    let e = eigen2(gram);
    let s1 = e.values[0].sqrt();
    let det = a1 * a2 * b1 * b2 * (cc + ss);
    let s2 = if s1 > 0.0 { (det / s1).min(s1) } else { 0.0 };
    let k = ka * kb;
    Singular { vector: e.vector, sigma: [s1 * k, s2 * k] }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matrix(alpha: [f64; 2], rot: [f64; 2], beta: [f64; 2]) -> [[f64; 2]; 2] {
        let [c, s] = rot;
        [
            [alpha[0] * c * beta[0], -alpha[0] * s * beta[1]],
            [alpha[1] * s * beta[0], alpha[1] * c * beta[1]],
        ]
    }

    fn check(alpha: [f64; 2], rot: [f64; 2], beta: [f64; 2]) {
        let m = matrix(alpha, rot, beta);
        let d = right_singular(alpha, rot, beta);
        let left = right_singular(beta, [rot[0], -rot[1]], alpha);
        assert_eq!(d.sigma, left.sigma);
        // M v = ±σ1 u and M v⊥ = ±σ2 u⊥.
        let [vx, vy] = d.vector;
        let mv = [m[0][0] * vx + m[0][1] * vy, m[1][0] * vx + m[1][1] * vy];
        let mp = [-m[0][0] * vy + m[0][1] * vx, -m[1][0] * vy + m[1][1] * vx];
        let along = (mv[0] * left.vector[0] + mv[1] * left.vector[1]).abs();
        let across = (-mp[0] * left.vector[1] + mp[1] * left.vector[0]).abs();
        assert!((along / d.sigma[0] - 1.0).abs() < 1e-14, "{alpha:?} {rot:?} {beta:?}: {d:?}");
        assert!((across / d.sigma[1] - 1.0).abs() < 1e-10, "{alpha:?} {rot:?} {beta:?}: {d:?}");
        assert!(d.sigma[0] >= d.sigma[1]);
    }

    #[test]
    fn decomposes_graded_matrices() {
        let t = 0.3f64;
        check([1.0, 2.0], [t.cos(), t.sin()], [3.0, 0.5]);
        check([1.0, 1e-6], [t.cos(), t.sin()], [1.0, 1.0]);
        check([1.0, 1.0], [1.0, 0.0], [1.0, 1.0]);
        check([1e6, 1.0], [1e-7f64.cos(), 1e-7f64.sin()], [1e-6, 1.0]);
        check([1e30, 1e-30], [0.6, 0.8], [1e-30, 1e30]);
    }

    #[test]
    fn extreme_ratios_neither_overflow_nor_underflow() {
        let d = right_singular([1e30, 1e-30], [1.0, 0.0], [1e30, 1e-30]);
        assert!((d.sigma[0] / 1e60 - 1.0).abs() < 1e-15, "{d:?}");
        assert!((d.sigma[1] / 1e-60 - 1.0).abs() < 1e-15, "{d:?}");
        let d = right_singular([1.0, 1e-60], [0.0, 1.0], [1.0, 1e-60]);
        assert!((d.sigma[0] / 1e-60 - 1.0).abs() < 1e-15, "{d:?}");
        assert!((d.sigma[1] / 1e-60 - 1.0).abs() < 1e-15, "{d:?}");
    }
}
