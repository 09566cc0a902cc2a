//! The eigen-decomposition of a symmetric 3×3 matrix, the one every 3D conversion uses
//! (size tensor from a metric, logarithm, square root, the simultaneous reduction of the
//! intersection).
//!
//! Contract (what callers rely on): eigenvalues in decreasing order, an orthonormal
//! right-handed frame whose i-th vector belongs to the i-th value, and
//! `Sym3::from_eigen(values, frame)` giving the matrix back to a few ulps of its norm.
//!
//! Method: the cyclic Jacobi method (Rutishauser's formulation, as in Golub & Van Loan
//! 8.5), hand-written rather than nalgebra's symmetric QR because of what the metrics
//! need:
//!
//! - Repeated and near-repeated eigenvalues (isotropic metrics, 1, 1, 1 + 1e-14) are no
//!   special case: every step is a plane rotation, so the frame is a product of rotations,
//!   orthonormal to a few ulps whatever the eigenvalue gaps (a closed form through the
//!   characteristic polynomial loses half the digits there and needs a fallback for the
//!   eigenvectors, i.e. a second algorithm on exactly the inputs that matter most).
//! - Graded SPD matrices H = D A D (a metric of aspect ratio 1e12 expressed in its own
//!   axes or close to them: diagonal and nearly diagonal tensors) get their small
//!   eigenvalues to high *relative* accuracy: with the stopping test
//!   |h_pq| <= ε √(|h_pp h_qq|) two-sided Jacobi computes every eigenvalue with a relative
//!   error of order ε κ(A) rather than ε κ(H) (Demmel & Veselić, "Jacobi's method is more
//!   accurate than QR", SIAM J. Matrix Anal. Appl. 13, 1992). QR's error is ε ‖H‖
//!   absolute, which wipes out 1e-12 next to 1e12. A diagonal matrix is returned exactly.
//! - Any symmetric matrix works (negative, zero, indefinite): nothing takes a square root
//!   of an eigenvalue or divides by one.
//!
//! The matrix is first scaled by a power of two near its largest entry (exact), so no
//! intermediate overflows or underflows for entries anywhere in the f64 range; each
//! rotation's tangent is the smaller root of t² + 2θt − 1 = 0, taken as 1/(2θ) when θ² would
//! overflow. Cost: a 3×3 matrix converges quadratically, in 3 to 6 sweeps of 3 rotations;
//! [`MAX_SWEEPS`] guards the loop (never reached in the tests, including random and
//! degenerate matrices). Non-finite entries give NaN eigenvalues and the identity frame,
//! without panicking.

use super::sym3::Sym3;

/// Eigenvalues, decreasing, and their unit eigenvectors (`frame[i]` for `values[i]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eigen3 {
    /// The eigenvalues, largest first.
    pub values: [f64; 3],
    /// The eigenvectors, orthonormal and right-handed, `frame[i]` for `values[i]`.
    pub frame: [[f64; 3]; 3],
}

/// The most Jacobi sweeps [`eigen3`] makes (a sweep is one rotation per off-diagonal pair).
pub const MAX_SWEEPS: usize = 32;

/// The Jacobi sweeps a decomposition of `m` makes to converge (for tests and benchmarks).
pub fn jacobi_sweeps(m: Sym3) -> usize {
    decompose(m).1
}

/// The eigen-decomposition of `m` (see the module header for the contract and method).
pub fn eigen3(m: Sym3) -> Eigen3 {
    decompose(m).0
}

impl Sym3 {
    /// The eigen-decomposition (see [`eigen3`]).
    pub fn eigen(&self) -> Eigen3 {
        eigen3(*self)
    }
}

/// 2^k with 2^k <= x < 2^(k+1), for a positive normal or subnormal x (exact).
fn power_of_two_below(x: f64) -> f64 {
    let e = x.log2().floor() as i32;
    // powi of 2.0 is exact within the normal range; split for subnormal scales.
    if e < -1000 {
        2f64.powi(e + 200) * 2f64.powi(-200)
    } else {
        2f64.powi(e)
    }
}

fn decompose(m: Sym3) -> (Eigen3, usize) {
    const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    if !m.is_finite() {
        return (Eigen3 { values: [f64::NAN; 3], frame: IDENTITY }, 0);
    }
    let largest = m.to_medit().iter().fold(0.0f64, |acc, c| acc.max(c.abs()));
    if largest == 0.0 {
        return (Eigen3 { values: [0.0; 3], frame: IDENTITY }, 0);
    }
    let scale = power_of_two_below(largest);
    let mut a = m.rows();
    for row in a.iter_mut() {
        for x in row.iter_mut() {
            *x /= scale;
        }
    }
    // Columns of v are the eigenvectors: v = product of the rotations.
    let mut v = IDENTITY;
    let mut sweeps = 0;
    while sweeps < MAX_SWEEPS {
        let mut rotated = false;
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            rotated |= rotate(&mut a, &mut v, p, q);
        }
        if !rotated {
            break;
        }
        sweeps += 1;
    }

    let mut order = [0usize, 1, 2];
    // Stable: equal eigenvalues keep the order of the axes (a diagonal gives its axes).
    order.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let values = order.map(|i| a[i][i] * scale);
    let mut frame = order.map(|i| [v[0][i], v[1][i], v[2][i]]);
    // Right-handed: flip the third vector (exact) when the frame is a reflection.
    if dot(cross(frame[0], frame[1]), frame[2]) < 0.0 {
        frame[2] = frame[2].map(|c| -c);
    }
    (Eigen3 { values, frame }, sweeps)
}

/// One Jacobi rotation annihilating a[p][q], unless it is already negligible in the
/// relative sense of Demmel & Veselić. Returns whether it rotated.
fn rotate(a: &mut [[f64; 3]; 3], v: &mut [[f64; 3]; 3], p: usize, q: usize) -> bool {
    let apq = a[p][q];
    let (app, aqq) = (a[p][p], a[q][q]);
    // Square roots taken apart so that the product of two small diagonals cannot underflow.
    if apq.abs() <= f64::EPSILON * app.abs().sqrt() * aqq.abs().sqrt() {
        return false;
    }
    let theta = (aqq - app) / (2.0 * apq);
    // The smaller root of t² + 2θt − 1 = 0 (rotation angle at most π/4); 1/(2θ) when θ² would
    // overflow (and 0 when θ itself is infinite: then a[p][q] is below every other entry's
    // last bit and the rotation is the identity).
    let t = if theta.abs() > 1e150 {
        0.5 / theta
    } else {
        let t = 1.0 / (theta.abs() + (theta * theta + 1.0).sqrt());
        if theta < 0.0 {
            -t
        } else {
            t
        }
    };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    let tau = s / (1.0 + c);
    let h = t * apq;
    a[p][p] = app - h;
    a[q][q] = aqq + h;
    a[p][q] = 0.0;
    a[q][p] = 0.0;
    let r = 3 - p - q;
    let (arp, arq) = (a[r][p], a[r][q]);
    a[r][p] = arp - s * (arq + tau * arp);
    a[r][q] = arq + s * (arp - tau * arq);
    a[p][r] = a[r][p];
    a[q][r] = a[r][q];
    for row in v.iter_mut() {
        let (g, k) = (row[p], row[q]);
        row[p] = g - s * (k + tau * g);
        row[q] = k + s * (g - tau * k);
    }
    true
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest |entry| of M − Σ λᵢ eᵢ eᵢᵀ.
    fn residual(m: Sym3, e: &Eigen3) -> f64 {
        let back = Sym3::from_eigen(e.values, e.frame).to_medit();
        m.to_medit().iter().zip(back).fold(0.0f64, |acc, (x, y)| acc.max((x - y).abs()))
    }

    /// Largest |entry| of F Fᵀ − I.
    fn orthonormality(f: &[[f64; 3]; 3]) -> f64 {
        let mut worst = 0.0f64;
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { 1.0 } else { 0.0 };
                worst = worst.max((dot(f[i], f[j]) - want).abs());
            }
        }
        worst
    }

    fn norm(m: Sym3) -> f64 {
        m.to_medit().iter().fold(0.0f64, |acc, c| acc.max(c.abs()))
    }

    fn check(m: Sym3) -> Eigen3 {
        let e = eigen3(m);
        assert!(e.values[0] >= e.values[1] && e.values[1] >= e.values[2], "{m:?}: {e:?}");
        assert!(residual(m, &e) <= 16.0 * f64::EPSILON * norm(m), "{m:?}: {e:?}");
        assert!(orthonormality(&e.frame) <= 8.0 * f64::EPSILON, "{m:?}: {e:?}");
        assert!(dot(cross(e.frame[0], e.frame[1]), e.frame[2]) > 0.0);
        assert!(jacobi_sweeps(m) < 8, "{m:?}: {} sweeps", jacobi_sweeps(m));
        e
    }

    #[test]
    fn decomposition_rebuilds_the_matrix_in_decreasing_order() {
        let m = Sym3 { xx: 4.0, xy: 1.0, yy: 3.0, xz: 0.5, yz: -0.25, zz: 2.0 };
        check(m);
    }

    #[test]
    fn diagonal_matrices_are_returned_exactly() {
        let e = check(Sym3::diagonal([1e-12, 1e12, 1.0]));
        assert_eq!(e.values, [1e12, 1.0, 1e-12]);
        assert_eq!(e.frame, [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]);
        let e = check(Sym3::IDENTITY);
        assert_eq!(e.values, [1.0; 3]);
        assert_eq!(e.frame, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let e = check(Sym3::diagonal([-1.0, 0.0, 2.0]));
        assert_eq!(e.values, [2.0, 0.0, -1.0]);
        let e = check(Sym3::ZERO);
        assert_eq!(e.values, [0.0; 3]);
    }

    #[test]
    fn nearly_diagonal_graded_matrices_keep_relative_accuracy() {
        // Off-diagonals small against √(h_pp h_qq): every eigenvalue is within a relative
        // ~off²/(h_pp h_qq) of its diagonal entry (Demmel & Veselić), here ~1e-8 at worst.
        let m = Sym3 { xx: 1e12, xy: 1e-2, yy: 1.0, xz: 1e-6, yz: 1e-10, zz: 1e-12 };
        let e = check(m);
        for (got, want) in e.values.iter().zip([1e12, 1.0, 1e-12]) {
            assert!((got - want).abs() <= 1e-7 * want, "{got} vs {want}");
        }
        // A graded SPD matrix H = D A D, D = diag(1e6, 1, 1e-6), A well conditioned:
        // the product of the eigenvalues must be det H = det(D)² det A to a few ulps
        // although the smallest one is 1e-24 of the largest.
        let a = Sym3 { xx: 2.0, xy: 0.5, yy: 3.0, xz: -0.3, yz: 0.7, zz: 1.5 };
        let d = [1e6, 1.0, 1e-6];
        let h = Sym3 {
            xx: d[0] * a.xx * d[0],
            xy: d[0] * a.xy * d[1],
            yy: d[1] * a.yy * d[1],
            xz: d[0] * a.xz * d[2],
            yz: d[1] * a.yz * d[2],
            zz: d[2] * a.zz * d[2],
        };
        let e = check(h);
        let product = e.values[0] * e.values[1] * e.values[2];
        assert!((product / a.det() - 1.0).abs() < 1e-13, "{product} vs {}", a.det());
        assert!(e.values[2] > 0.0);
    }

    #[test]
    fn repeated_and_near_repeated_eigenvalues() {
        // A generic rotation (unit quaternion (0.9, 0.3, −0.2, 0.25) normalised).
        let frame = crate::metric::testgen3::quaternion_frame([0.9, 0.3, -0.2, 0.25]);
        for values in [
            [1.0, 1.0, 1.0],
            [1.0 + 1e-14, 1.0, 1.0],
            [1.0, 1.0, 1.0 - 1e-14],
            [2.0, 2.0, 1.0],
            [3.0, 1.0 + 1e-15, 1.0],
            [1e12, 1e12 * (1.0 + 1e-13), 1e-12],
            [1e12, 1.0, 1e-12],
            [-1.0, -1.0, 1e-300],
            [5.0, 0.0, -5.0],
            [1e-300, 1e-300, 1e-310],
            [1e300, -1e300, 1e300],
        ] {
            let m = Sym3::from_eigen(values, frame);
            let e = check(m);
            let mut want = values;
            want.sort_by(|x, y| y.total_cmp(x));
            for (got, want) in e.values.iter().zip(want) {
                assert!((got - want).abs() <= 16.0 * f64::EPSILON * norm(m), "{values:?}: {e:?}");
            }
        }
    }

    #[test]
    fn non_finite_input_does_not_panic() {
        let e = eigen3(Sym3 { xx: f64::NAN, ..Sym3::IDENTITY });
        assert!(e.values.iter().all(|v| v.is_nan()));
        let e = eigen3(Sym3 { xy: f64::INFINITY, ..Sym3::IDENTITY });
        assert!(e.values.iter().all(|v| v.is_nan()));
    }
}
