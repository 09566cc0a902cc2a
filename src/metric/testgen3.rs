//! Test generators shared by the 3D metric twins: random rotations, eigenvalue patterns
//! that are hard for eigen-solvers (repeated, near-repeated, graded, signed) and size
//! tensors of large aspect ratio.

// Not every generator is used by every twin module.
#![allow(dead_code)]

use proptest::prelude::*;

use super::eigen3::{cross, dot};
use super::Sym3;

/// The rotation of a (normalised) quaternion [w, x, y, z]; rows are the rotated axes.
pub(crate) fn quaternion_frame(q: [f64; 4]) -> [[f64; 3]; 3] {
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    let [w, x, y, z] = q.map(|c| c / n);
    [
        [1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y + w * z), 2.0 * (x * z - w * y)],
        [2.0 * (x * y - w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z + w * x)],
        [2.0 * (x * z + w * y), 2.0 * (y * z - w * x), 1.0 - 2.0 * (x * x + y * y)],
    ]
}

/// A random rotation (uniform enough: a normalised Gaussian-ish quaternion), or the
/// identity, or a rotation by a tiny angle (nearly diagonal matrices).
pub(crate) fn arb_frame() -> impl Strategy<Value = [[f64; 3]; 3]> {
    let q = (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64);
    prop_oneof![
        4 => q.prop_filter("non-zero", |q| q.0.abs() + q.1.abs() + q.2.abs() + q.3.abs() > 1e-3)
            .prop_map(|q| quaternion_frame([q.0, q.1, q.2, q.3])),
        1 => Just(quaternion_frame([1.0, 0.0, 0.0, 0.0])),
        1 => (-1e-9..1e-9f64, -1e-9..1e-9f64, -1e-9..1e-9f64)
            .prop_map(|q| quaternion_frame([1.0, q.0, q.1, q.2])),
    ]
}

/// Positive values log-uniform in [10^lo, 10^hi].
pub(crate) fn arb_log(lo: f64, hi: f64) -> impl Strategy<Value = f64> + Clone {
    (lo..hi).prop_map(|e| 10f64.powf(e))
}

/// Eigenvalue triples: independent, repeated, near-repeated, graded 1e-12..1e12, signed,
/// with zeros.
pub(crate) fn arb_values() -> impl Strategy<Value = [f64; 3]> {
    let tiny = prop_oneof![Just(0.0), -1e-14..1e-14f64, -1e-10..1e-10f64];
    prop_oneof![
        (-10.0..10.0f64, -10.0..10.0f64, -10.0..10.0f64).prop_map(|(a, b, c)| [a, b, c]),
        arb_log(-12.0, 12.0).prop_map(|a| [a, a, a]),
        (arb_log(-12.0, 12.0), arb_log(-12.0, 12.0)).prop_map(|(a, b)| [a, b, a]),
        (arb_log(-6.0, 6.0), tiny.clone(), tiny.clone()).prop_map(|(a, s, t)| [
            a,
            a * (1.0 + s),
            a * (1.0 + t)
        ]),
        (arb_log(-12.0, 12.0), arb_log(-12.0, 12.0), arb_log(-12.0, 12.0))
            .prop_map(|(a, b, c)| [a, b, c]),
        (arb_log(-12.0, 12.0), arb_log(-12.0, 12.0)).prop_map(|(a, b)| [-a, 0.0, b]),
        (arb_log(-3.0, 3.0), tiny).prop_map(|(a, s)| [-a, a * (1.0 + s), 0.0]),
    ]
}

/// A symmetric matrix with eigenvalues from [`arb_values`] in a frame from [`arb_frame`].
pub(crate) fn arb_sym3() -> impl Strategy<Value = Sym3> {
    (arb_values(), arb_frame()).prop_map(|(v, f)| Sym3::from_eigen(v, f))
}

/// An SPD matrix with eigenvalues log-uniform in [10^-lo, 10^hi], sometimes repeated.
pub(crate) fn arb_spd(lo: f64, hi: f64) -> impl Strategy<Value = Sym3> {
    let v = arb_log(lo, hi);
    prop_oneof![
        (v.clone(), v.clone(), v.clone()).prop_map(|(a, b, c)| [a, b, c]),
        (v.clone(), v.clone()).prop_map(|(a, b)| [a, a, b]),
        v.prop_map(|a| [a, a, a]),
    ]
    .prop_flat_map(|v| arb_frame().prop_map(move |f| Sym3::from_eigen(v, f)))
}

/// Largest |entry|.
pub(crate) fn max_abs(m: &Sym3) -> f64 {
    m.to_medit().iter().fold(0.0f64, |acc, c| acc.max(c.abs()))
}

/// Largest |entry| of a − b.
pub(crate) fn max_diff(a: &Sym3, b: &Sym3) -> f64 {
    let (a, b) = (a.to_medit(), b.to_medit());
    (0..6).fold(0.0f64, |acc, i| acc.max((a[i] - b[i]).abs()))
}

/// Largest |entry| of F Fᵀ − I, and whether F is right-handed.
pub(crate) fn frame_defect(f: &[[f64; 3]; 3]) -> (f64, bool) {
    let mut worst = 0.0f64;
    for i in 0..3 {
        for j in 0..3 {
            let want = if i == j { 1.0 } else { 0.0 };
            worst = worst.max((dot(f[i], f[j]) - want).abs());
        }
    }
    (worst, dot(cross(f[0], f[1]), f[2]) > 0.0)
}

/// Unit directions spread over the sphere (a Fibonacci lattice) plus the given ones.
pub(crate) fn directions(n: usize, extra: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut d: Vec<[f64; 3]> = (0..n)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let t = golden * i as f64;
            [r * t.cos(), r * t.sin(), z]
        })
        .collect();
    d.extend_from_slice(extra);
    d
}
