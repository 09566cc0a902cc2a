//! Twins of [`eigen3`](super::eigen3) against nalgebra's general solvers on random and
//! degenerate symmetric matrices: the real Schur form (eigenvalues of a general matrix)
//! and the symmetric QR iteration; and the eigenvalues the matrix was built from.
//!
//! nalgebra 0.33's SVD is not a twin: on such matrices it misses small singular values by
//! up to 2e-10 of the norm (dimforge/nalgebra#1072, #1172; e.g. 1.2986e5 ⊕
//! [[5.1665e-5, −3.8743e-4], [·, 3.3845e-3]] gives 3.4066e-3 for 3.4289e-3, which LAPACK
//! through numpy confirms), far above the ulps the others agree to.
//!
//! Tolerances are relative to the largest entry of the matrix: that is all a matrix
//! stored by its entries determines (Weyl: a perturbation of the entries by δ moves every
//! eigenvalue by at most 3δ).

// Indices pair three arrays at once; ranges read best.
#![allow(clippy::needless_range_loop)]

use nalgebra::{Matrix3, Schur, SymmetricEigen};
use proptest::prelude::*;

use super::testgen3::{arb_frame, arb_sym3, arb_values, frame_defect, max_abs, max_diff};
use super::{eigen3, Sym3};

fn na(m: &Sym3) -> Matrix3<f64> {
    let r = m.rows();
    Matrix3::from_fn(|i, j| r[i][j])
}

fn sorted_desc(mut v: [f64; 3]) -> [f64; 3] {
    v.sort_by(|x, y| y.total_cmp(x));
    v
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn reconstruction_and_orthonormality(m in arb_sym3()) {
        let e = eigen3(m);
        let norm = max_abs(&m);
        let back = Sym3::from_eigen(e.values, e.frame);
        prop_assert!(max_diff(&back, &m) <= 24.0 * f64::EPSILON * norm, "{m:?}: {e:?}");
        let (defect, right_handed) = frame_defect(&e.frame);
        prop_assert!(defect <= 8.0 * f64::EPSILON && right_handed, "{m:?}: {e:?}");
        prop_assert!(e.values[0] >= e.values[1] && e.values[1] >= e.values[2]);
        prop_assert!(super::jacobi_sweeps(m) <= 8, "{m:?}");
    }

    #[test]
    fn eigenvalues_agree_with_the_values_built_in((v, f) in (arb_values(), arb_frame())) {
        let m = Sym3::from_eigen(v, f);
        let e = eigen3(m);
        let want = sorted_desc(v);
        let scale = v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for k in 0..3 {
            prop_assert!((e.values[k] - want[k]).abs() <= 24.0 * f64::EPSILON * scale,
                "{v:?}: {e:?}");
        }
    }

    #[test]
    fn eigenvalues_agree_with_nalgebra_schur_and_symmetric_qr(m in arb_sym3()) {
        let e = eigen3(m);
        let norm = max_abs(&m);
        let tol = 64.0 * f64::EPSILON * norm;
        // nalgebra's Schur iteration stalls on nearly scalar matrices (equal shifts), so it
        // is given M − cI, c the mean diagonal (exact to a rounding of the norm).
        let c = m.trace() / 3.0;
        let shifted = na(&m) - Matrix3::identity() * c;
        // A scalar matrix (M − cI = 0) stalls it too; its eigenvalues are c. On a few
        // graded matrices it does not converge at all (then the others still compare).
        let schur = if shifted.amax() == 0.0 {
            Some(nalgebra::Vector3::zeros())
        } else {
            Schur::try_new(shifted, f64::EPSILON, 100_000).and_then(|s| s.eigenvalues())
        };
        let schur = schur.map(|s| sorted_desc([s[0] + c, s[1] + c, s[2] + c]));
        let qr = SymmetricEigen::new(na(&m)).eigenvalues;
        let qr = sorted_desc([qr[0], qr[1], qr[2]]);
        for k in 0..3 {
            if let Some(schur) = schur {
                prop_assert!((e.values[k] - schur[k]).abs() <= tol, "schur {m:?}: {e:?} vs {schur:?}");
            }
            prop_assert!((e.values[k] - qr[k]).abs() <= tol, "qr {m:?}: {e:?} vs {qr:?}");
        }
    }

    #[test]
    fn eigenvectors_satisfy_the_eigen_equation(m in arb_sym3()) {
        // M e = λ e for each pair to a few ulps of the norm (near-repeated values may give
        // any basis of their eigenspace; the residual does not care).
        let e = eigen3(m);
        let norm = max_abs(&m);
        for k in 0..3 {
            let mv = m.mul_vec(e.frame[k]);
            for i in 0..3 {
                prop_assert!((mv[i] - e.values[k] * e.frame[k][i]).abs() <= 32.0 * f64::EPSILON * norm,
                    "{m:?}: {e:?}");
            }
        }
    }
}
