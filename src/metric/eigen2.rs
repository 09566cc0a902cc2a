//! Closed-form eigen-decomposition of a symmetric 2×2 matrix.
//!
//! Source: the size-tensor conversions of thesis 3.1.5–3.1.6 and the robust size metric
//! intersection of thesis 3.2.2, which both start from "the decomposition into
//! eigenvectors and eigenvalues" of a 2×2 SPD matrix. The formulas follow the careful
//! closed form of LAPACK's `DLAEV2` (Demmel and Kahan) for the eigenvalues, and the
//! half-angle form of the Jacobi rotation for the eigenvector:
//!
//! - m = (a + c)/2, r = hypot((a − c)/2, b); the eigenvalue of larger magnitude is
//!   m ± r taken with the sign of m (a sum, no cancellation); the other is det/that one,
//!   evaluated as (a/λ)·c − (b/λ)·b so that nothing overflows before the division;
//! - the first eigenvector is (cos θ, sin θ) with (cos 2θ, sin 2θ) = ((a − c)/2, b)/r;
//!   cos θ or sin θ, whichever is the larger, comes from the half-angle square root and
//!   the other from sin 2θ / 2·(that one), so no branch divides by a small number.
//!
//! Cost: one `hypot`, one or two square roots, a handful of flops; no trigonometry.
//! Robustness: equal eigenvalues (r = 0) give the x axis; tiny off-diagonals and nearly
//! equal eigenvalues go through the same formulas without a special case. The result is
//! backward stable: the eigenvalues carry an absolute error of a few ulps of the largest
//! magnitude, which is all a matrix stored by its entries determines.

use super::sym2::Sym2;

/// Eigenvalues and first eigenvector of a symmetric 2×2 matrix.
///
/// `M = values[0] v vᵀ + values[1] v⊥ v⊥ᵀ` with `v = vector` (unit) and `v⊥ = (−v_y, v_x)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eigen2 {
    /// The eigenvalues, the larger first: `values[0] >= values[1]`.
    pub values: [f64; 2],
    /// The unit eigenvector of `values[0]`; the eigenvector of `values[1]` is its
    /// perpendicular (−v_y, v_x).
    pub vector: [f64; 2],
}

/// Eigen-decomposition of a symmetric 2×2 matrix in closed form (thesis 3.2.2).
///
/// Never panics; non-finite entries give non-finite values.
pub fn eigen2(m: Sym2) -> Eigen2 {
    let Sym2 { a, b, c } = m;
    // Halves first: a + c may overflow where a/2 + c/2 does not.
    let half_sum = 0.5 * a + 0.5 * c;
    let half_diff = 0.5 * a - 0.5 * c;
    let r = half_diff.hypot(b);

    // DLAEV2: the eigenvalue of larger magnitude without cancellation, the other one
    // through the determinant, divided early so that the products stay in range.
    let (large, small) = if a.abs() >= c.abs() { (a, c) } else { (c, a) };
    let (l1, l2) = if half_sum > 0.0 {
        let l1 = half_sum + r;
        (l1, (large / l1) * small - (b / l1) * b)
    } else if half_sum < 0.0 {
        let l2 = half_sum - r;
        ((large / l2) * small - (b / l2) * b, l2)
    } else {
        (r, -r)
    };
    // Rounding may swap nearly equal eigenvalues; keep the order the contract promises.
    let values = if l1 >= l2 { [l1, l2] } else { [l2, l1] };

    let vector = if r > 0.0 && r.is_finite() {
        let cos2 = half_diff / r;
        let sin2 = b / r;
        if cos2 >= 0.0 {
            let x = (0.5 + 0.5 * cos2).sqrt();
            [x, sin2 / (2.0 * x)]
        } else {
            let y = (0.5 - 0.5 * cos2).sqrt();
            [sin2 / (2.0 * y), y]
        }
    } else if r == 0.0 {
        [1.0, 0.0]
    } else {
        [f64::NAN, f64::NAN]
    };
    Eigen2 { values, vector }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn residual(m: Sym2, e: &Eigen2) -> f64 {
        let [x, y] = e.vector;
        let p = [-y, x];
        let r1 = [m.a * x + m.b * y - e.values[0] * x, m.b * x + m.c * y - e.values[0] * y];
        let r2 = [
            m.a * p[0] + m.b * p[1] - e.values[1] * p[0],
            m.b * p[0] + m.c * p[1] - e.values[1] * p[1],
        ];
        r1[0].hypot(r1[1]).max(r2[0].hypot(r2[1]))
    }

    #[test]
    fn diagonal_and_isotropic() {
        let e = eigen2(Sym2::new(2.0, 0.0, 1.0));
        assert_eq!(e.values, [2.0, 1.0]);
        assert_eq!(e.vector, [1.0, 0.0]);
        let e = eigen2(Sym2::new(1.0, 0.0, 2.0));
        assert_eq!(e.values, [2.0, 1.0]);
        assert_eq!(e.vector, [0.0, 1.0]);
        let e = eigen2(Sym2::new(3.0, 0.0, 3.0));
        assert_eq!(e.values, [3.0, 3.0]);
        assert_eq!(e.vector, [1.0, 0.0]);
    }

    #[test]
    fn rotated_by_30_degrees() {
        let t = 30f64.to_radians();
        let m = Sym2::from_eigen([4.0, 0.25], [t.cos(), t.sin()]);
        let e = eigen2(m);
        assert!((e.values[0] - 4.0).abs() < 1e-15 * 4.0);
        assert!((e.values[1] - 0.25).abs() < 1e-15 * 4.0);
        let dot = e.vector[0] * t.cos() + e.vector[1] * t.sin();
        assert!((dot.abs() - 1.0).abs() < 1e-15);
    }

    #[test]
    fn tiny_off_diagonal_and_near_equal() {
        for m in [
            Sym2::new(1.0, 1e-300, 1.0),
            Sym2::new(1.0, 1e-17, 1.0 + f64::EPSILON),
            Sym2::new(1.0 + f64::EPSILON, -1e-17, 1.0),
            Sym2::new(1e-300, 1e-310, 1e-300),
            Sym2::new(1e300, 1e300, 1e300),
            Sym2::new(-2.0, 0.5, 3.0),
            Sym2::new(-1.0, 1e-20, -1.0),
        ] {
            let e = eigen2(m);
            let scale = m.a.abs().max(m.b.abs()).max(m.c.abs());
            assert!(e.values[0] >= e.values[1], "{m:?}");
            assert!(residual(m, &e) <= 4.0 * f64::EPSILON * scale, "{m:?} {e:?}");
            assert!((e.vector[0].hypot(e.vector[1]) - 1.0).abs() < 4.0 * f64::EPSILON);
        }
    }

    #[test]
    fn small_eigenvalue_of_a_graded_matrix_is_relative_accurate() {
        // diag(1e200, 1e-200) would lose the small one to a − (a − c) in the naive m − r.
        let e = eigen2(Sym2::new(1e200, 0.0, 1e-200));
        assert_eq!(e.values, [1e200, 1e-200]);
    }

    #[test]
    fn non_finite_input_does_not_panic() {
        let e = eigen2(Sym2::new(f64::NAN, 0.0, 1.0));
        assert!(e.values[0].is_nan() || e.values[1].is_nan());
        let _ = eigen2(Sym2::new(f64::INFINITY, 1.0, 1.0));
    }
}
