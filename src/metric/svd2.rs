//! Closed-form singular value decomposition of a general 2×2 matrix, the kernel of the
//! simultaneous reduction in the robust size-tensor intersection (thesis 3.2.2).
//!
//! Source: J. Blinn, "Consider the lowly 2×2 matrix", Jim Blinn's Corner, IEEE Computer
//! Graphics and Applications (1996). Split M = [[E+F, G−H], [G+H, E−F]] into a scaled
//! rotation (E, H) and a scaled reflection (F, G); with Q = hypot(E, H), R = hypot(F, G),
//! a2 = atan2(H, E), a1 = atan2(G, F):
//!
//!   M = Rot(φ) diag(Q + R, Q − R) Rot(θ),   φ = (a2 + a1)/2,   θ = (a2 − a1)/2.
//!
//! Nothing is squared, so entries up to the top of the f64 range do not overflow (the
//! sizes of two size tensors can differ by 10^200). The smaller singular value is
//! det/σ1 with the determinant supplied by the caller, who knows it exactly as a product
//! of sizes (Q − R would cancel for thin ellipses). Cost: two `hypot`, two `atan2`, two
//! `sin_cos`.

/// `M = σ1 u vᵀ + σ2 u⊥ v⊥ᵀ` with unit `u`, `v` and ⊥ the rotation by +90°.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Svd2 {
    /// First left singular vector.
    pub u: [f64; 2],
    /// First right singular vector.
    pub v: [f64; 2],
    /// σ1 >= |σ2|; σ2 has the sign of the determinant.
    pub sigma: [f64; 2],
}

/// SVD of `[[m00, m01], [m10, m11]]` whose determinant is `det` (passed in because the
/// callers know it to full relative accuracy).
pub(crate) fn svd2(m: [[f64; 2]; 2], det: f64) -> Svd2 {
    let [[m00, m01], [m10, m11]] = m;
    let e = 0.5 * m00 + 0.5 * m11;
    let f = 0.5 * m00 - 0.5 * m11;
    let g = 0.5 * m10 + 0.5 * m01;
    let h = 0.5 * m10 - 0.5 * m01;
    let q = e.hypot(h);
    let r = f.hypot(g);
    let s1 = q + r;
    let s2 = if s1 > 0.0 { det / s1 } else { 0.0 };
    let a1 = g.atan2(f);
    let a2 = h.atan2(e);
    let phi = 0.5 * (a2 + a1);
    let theta = 0.5 * (a2 - a1);
    let (sp, cp) = phi.sin_cos();
    let (st, ct) = theta.sin_cos();
    // Rot(θ) = Vᵀ, so the first column of V is (cos θ, −sin θ).
    Svd2 { u: [cp, sp], v: [ct, -st], sigma: [s1, s2] }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recompose(s: &Svd2) -> [[f64; 2]; 2] {
        let [ux, uy] = s.u;
        let [vx, vy] = s.v;
        let (px, py) = (-uy, ux);
        let (qx, qy) = (-vy, vx);
        let [s1, s2] = s.sigma;
        [
            [s1 * ux * vx + s2 * px * qx, s1 * ux * vy + s2 * px * qy],
            [s1 * uy * vx + s2 * py * qx, s1 * uy * vy + s2 * py * qy],
        ]
    }

    #[test]
    fn recomposes_general_matrices() {
        for m in [
            [[1.0, 2.0], [3.0, 4.0]],
            [[2.0, 0.0], [0.0, 1.0]],
            [[0.0, -1.0], [1.0, 0.0]],
            [[1e6, 1e-6], [-3.0, 1e-3]],
            [[1.0, 0.0], [0.0, 1.0]],
        ] {
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            let s = svd2(m, det);
            let back = recompose(&s);
            let scale = s.sigma[0];
            for i in 0..2 {
                for j in 0..2 {
                    assert!((back[i][j] - m[i][j]).abs() <= 8.0 * f64::EPSILON * scale, "{m:?}");
                }
            }
            assert!(s.sigma[0] >= s.sigma[1].abs());
        }
    }

    #[test]
    fn huge_entries_do_not_overflow() {
        let m = [[1e300, 0.0], [0.0, 1e-300]];
        let s = svd2(m, 1.0);
        assert_eq!(s.sigma, [1e300, 1e-300]);
    }
}
