//! Size-tensor intersection and union in 3D by simultaneous reduction (thesis 3.2.2's
//! robust form, the 2D [`SizeTensor::intersection`](super::SizeTensor::intersection)
//! lifted to ellipsoids).
//!
//! Method: T = D1⁻¹ R1ᵀ maps the first ellipsoid E1 onto the unit ball; there E2 becomes
//! { y : yᵀ N y <= 1 } with N = F Fᵀ, F = D1 R1ᵀ R2 D2⁻¹ (built from the stored frames and
//! sizes, never from a metric matrix). The eigen-decomposition N = V diag(μ) Vᵀ
//! ([`eigen3`](super::eigen3), Jacobi: orthonormal V whatever the multiplicities, graded
//! μ relatively accurate) is the simultaneous reduction: along vᵢ the unit ball has radius
//! 1 and E2 radius 1/√μᵢ. The largest ellipsoid inside both that shares these axes has
//! semi-axes min(1, 1/√μᵢ) (the union: max), which is M1 ∩ M2 = P⁻ᵀ diag(max(λ1ᵢ, λ2ᵢ)) P⁻¹
//! in metric terms. Mapped back by T⁻¹ it is K·ball with K = R1 D1 V diag(s); its sizes
//! and axes are the eigen-decomposition of D1 V diag(s²) Vᵀ D1 (square roots of the
//! eigenvalues), turned by R1.
//!
//! Invariants: commutative bit for bit (operands put in a fixed order first),
//! idempotent, and when one ellipsoid contains the other (bounding spheres, or all μ on
//! one side of 1 within `NESTED_SLACK`) the inner one (union: the outer one) is returned
//! exactly; the result touches each input along the reduced axes where it is the smaller
//! (larger) of the two. Containment holds to a relative ε·aspect ratio.

use super::eigen3::{dot, eigen3};
use super::size_tensor3::SizeTensor3;
use super::sym3::Sym3;

/// Relative slack of the nesting test: reduced radii within a few ulps of 1 count as 1.
const NESTED_SLACK: f64 = 8.0 * f64::EPSILON;

#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Intersection,
    Union,
}

impl SizeTensor3 {
    /// The largest ellipsoid (size tensor) contained in both `self` and `other`, by
    /// simultaneous reduction (see the module header). Never fails; not associative.
    pub fn intersection(&self, other: &SizeTensor3) -> SizeTensor3 {
        combine(self, other, Mode::Intersection)
    }

    /// The smallest ellipsoid of the same simultaneous reduction containing both `self`
    /// and `other` (in metric terms P⁻ᵀ diag(min(λ1ᵢ, λ2ᵢ)) P⁻¹).
    pub fn union(&self, other: &SizeTensor3) -> SizeTensor3 {
        combine(self, other, Mode::Union)
    }
}

/// A total order on representations, so that `combine(a, b)` and `combine(b, a)` do the
/// same arithmetic.
fn ordered<'t>(a: &'t SizeTensor3, b: &'t SizeTensor3) -> (&'t SizeTensor3, &'t SizeTensor3) {
    let key = |t: &SizeTensor3| {
        let f = t.frame();
        let mut k = t.sizes().to_vec();
        k.extend(f.iter().flatten());
        k
    };
    let (ka, kb) = (key(a), key(b));
    for (x, y) in ka.iter().zip(&kb) {
        match x.total_cmp(y) {
            std::cmp::Ordering::Less => return (a, b),
            std::cmp::Ordering::Greater => return (b, a),
            std::cmp::Ordering::Equal => {}
        }
    }
    (a, b)
}

/// The simultaneous reduction of `e2` against `e1`: μ (decreasing) and the reduced axes
/// vᵢ in the space where `e1` is the unit ball.
fn reduce(e1: &SizeTensor3, e2: &SizeTensor3) -> ([f64; 3], [[f64; 3]; 3]) {
    let (f1, h1) = (e1.frame(), e1.sizes());
    let (f2, h2) = (e2.frame(), e2.sizes());
    let f: [[f64; 3]; 3] =
        std::array::from_fn(|i| std::array::from_fn(|j| h1[i] * dot(f1[i], f2[j]) / h2[j]));
    let n = Sym3 {
        xx: dot(f[0], f[0]),
        xy: dot(f[0], f[1]),
        yy: dot(f[1], f[1]),
        xz: dot(f[0], f[2]),
        yz: dot(f[1], f[2]),
        zz: dot(f[2], f[2]),
    };
    let e = eigen3(n);
    (e.values, e.frame)
}

/// The world directions of the reduced axes of the pair (R1 D1 vᵢ, normalised), in the
/// order [`SizeTensor3::intersection`] uses: along them the result's radius is the min
/// (union: max) of the two inputs' radii.
#[cfg(test)]
fn reduced_directions(a: &SizeTensor3, b: &SizeTensor3) -> [[f64; 3]; 3] {
    let (e1, e2) = ordered(a, b);
    let (_, v) = reduce(e1, e2);
    let (f1, h1) = (e1.frame(), e1.sizes());
    v.map(|vk| {
        let d: [f64; 3] =
            std::array::from_fn(|c| (0..3).map(|i| h1[i] * vk[i] * f1[i][c]).sum::<f64>());
        let n = dot(d, d).sqrt();
        d.map(|x| x / n)
    })
}

fn combine(a: &SizeTensor3, b: &SizeTensor3, mode: Mode) -> SizeTensor3 {
    let (e1, e2) = ordered(a, b);
    if e1 == e2 {
        return *e1;
    }
    let (inner_2, inner_1) = match mode {
        Mode::Intersection => (*e2, *e1),
        Mode::Union => (*e1, *e2),
    };
    if e2.h_max() <= e1.h_min() {
        return inner_2;
    }
    if e1.h_max() <= e2.h_min() {
        return inner_1;
    }
    let (mu, v) = reduce(e1, e2);
    if mu[2] >= 1.0 - NESTED_SLACK {
        // E2's radii are all within the unit ball: E2 ⊂ E1.
        return inner_2;
    }
    if mu[0] <= 1.0 + NESTED_SLACK {
        return inner_1;
    }
    // Squared semi-axes in the reduced space.
    let s2 = mu.map(|m| {
        let m = m.max(f64::MIN_POSITIVE);
        match mode {
            Mode::Intersection => 1.0 / m.max(1.0),
            Mode::Union => 1.0 / m.min(1.0),
        }
    });
    // H = D1 V diag(s²) Vᵀ D1 in E1's frame: the square of the result's size matrix.
    let h1 = e1.sizes();
    let entry =
        |i: usize, j: usize| h1[i] * h1[j] * (0..3).map(|k| v[k][i] * s2[k] * v[k][j]).sum::<f64>();
    let h = Sym3 {
        xx: entry(0, 0),
        xy: entry(0, 1),
        yy: entry(1, 1),
        xz: entry(0, 2),
        yz: entry(1, 2),
        zz: entry(2, 2),
    };
    let eh = eigen3(h);
    let f1 = e1.frame();
    let frame =
        eh.frame.map(|u| std::array::from_fn(|c| (0..3).map(|i| u[i] * f1[i][c]).sum::<f64>()));
    SizeTensor3::from_parts(frame, eh.values.map(|x| x.max(0.0).sqrt()))
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::metric::testgen3::{arb_frame, arb_log, directions};

    fn arb_tensor(max_aspect: f64) -> impl Strategy<Value = SizeTensor3> {
        let la = max_aspect.log10();
        (arb_frame(), arb_log(-2.0, 2.0), 0.0..la, 0.0..la).prop_map(|(f, h, a, b)| {
            SizeTensor3::try_new(f[0], f[1], [h, h * 10f64.powf(a), h * 10f64.powf(b)]).unwrap()
        })
    }

    fn arb_pair() -> impl Strategy<Value = (SizeTensor3, SizeTensor3)> {
        prop_oneof![
            (arb_tensor(100.0), arb_tensor(100.0)),
            (arb_tensor(1e4), arb_tensor(1e4)),
            (arb_tensor(100.0), arb_log(-2.0, 2.0))
                .prop_map(|(a, h)| (a, SizeTensor3::isotropic(h))),
            (arb_tensor(1e3), -1e-9..1e-9f64, 0.5..2.0f64).prop_map(|(a, t, k)| {
                let f = a.frame();
                let g = [f[0][0] + t * f[1][0], f[0][1] + t * f[1][1], f[0][2] + t * f[1][2]];
                let h = a.sizes();
                (a, SizeTensor3::try_new(g, f[1], [h[0] * k, h[1] / k, h[2]]).unwrap())
            }),
        ]
    }

    /// Largest relative excess of `inner`'s radius over `outer`'s on the directions.
    fn excess(inner: &SizeTensor3, outer: &SizeTensor3, dirs: &[[f64; 3]]) -> f64 {
        dirs.iter()
            .map(|&d| inner.size_along(d) / outer.size_along(d) - 1.0)
            .fold(f64::MIN, f64::max)
    }

    #[test]
    fn crossing_axis_aligned_ellipsoids() {
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        let a = SizeTensor3::new(x, y, [4.0, 1.0, 2.0]);
        let b = SizeTensor3::new(x, y, [1.0, 4.0, 3.0]);
        let i = a.intersection(&b);
        for (d, want) in [(x, 1.0), (y, 1.0), ([0.0, 0.0, 1.0], 2.0)] {
            assert!((i.size_along(d) - want).abs() < 1e-14, "{i:?}");
        }
        let u = a.union(&b);
        for (d, want) in [(x, 4.0), (y, 4.0), ([0.0, 0.0, 1.0], 3.0)] {
            assert!((u.size_along(d) - want).abs() < 1e-14, "{u:?}");
        }
    }

    #[test]
    fn nested_returns_the_inner_one_exactly() {
        let big = SizeTensor3::new([1.0, 1.0, 0.0], [0.0, 0.0, 1.0], [10.0, 3.0, 5.0]);
        let small = SizeTensor3::new([1.0, -2.0, 0.5], [0.0, 1.0, 1.0], [2.0, 0.5, 1.0]);
        assert_eq!(big.intersection(&small), small);
        assert_eq!(small.intersection(&big), small);
        assert_eq!(big.union(&small), big);
        assert_eq!(big.intersection(&big), big);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(1000))]

        #[test]
        fn intersection_is_inside_both_and_touches_along_the_reduced_axes((a, b) in arb_pair()) {
            let i = a.intersection(&b);
            let r = reduced_directions(&a, &b);
            let dirs = directions(400, &r);
            let aspect = a.aspect_ratio().max(b.aspect_ratio());
            let tol = 64.0 * f64::EPSILON * aspect * aspect;
            prop_assert!(excess(&i, &a, &dirs) <= tol && excess(&i, &b, &dirs) <= tol, "{a:?} ∩ {b:?} = {i:?}");
            for d in r {
                let want = a.size_along(d).min(b.size_along(d));
                prop_assert!((i.size_along(d) / want - 1.0).abs() <= tol, "{a:?} ∩ {b:?} = {i:?} along {d:?}");
            }
            let u = a.union(&b);
            prop_assert!(excess(&a, &u, &dirs) <= tol && excess(&b, &u, &dirs) <= tol, "{a:?} ∪ {b:?} = {u:?}");
            for d in r {
                let want = a.size_along(d).max(b.size_along(d));
                prop_assert!((u.size_along(d) / want - 1.0).abs() <= tol);
            }
        }

        #[test]
        fn commutative_and_idempotent((a, b) in arb_pair()) {
            prop_assert_eq!(a.intersection(&b), b.intersection(&a));
            prop_assert_eq!(a.union(&b), b.union(&a));
            prop_assert_eq!(a.intersection(&a), a);
            let i = a.intersection(&b);
            // Idempotent on the result: i ⊂ a, so i ∩ a is i (to the nesting slack).
            let again = i.intersection(&a);
            let dirs = directions(100, &[]);
            let aspect = a.aspect_ratio().max(b.aspect_ratio());
            let tol = 64.0 * f64::EPSILON * aspect * aspect;
            prop_assert!(excess(&i, &again, &dirs).abs() <= tol && excess(&again, &i, &dirs).abs() <= tol);
        }
    }
}
