//! Which edges leave the length band, without the logarithm for the many that do not.
//!
//! The metric length of an edge is the logarithmic mean of its lengths in its two end
//! metrics ([`crate::metric::length::metric_edge_length`]), which lies between them. The
//! split and collapse sweeps measure every listed edge to keep the few outside the band;
//! an edge whose two end lengths are both inside the bound (by more than rounding) is
//! inside it too, and is dropped after two quadratic forms instead of a logarithm. The
//! kept lengths are computed as `metric_edge_length` computes them, so they are the same
//! numbers and the sweeps' order is unchanged.

use super::work::Work;
use crate::metric::length::geometric_mean_length;

/// Relative margin between the end lengths and a bound within which the full length is
/// computed: the logarithmic mean is computed to within a few ulps of its exact value,
/// which lies between the end lengths.
const MARGIN: f64 = 1e-12;

/// The lengths of edge `ab` in the metrics of `a` and of `b`.
#[inline]
fn end_lengths(w: &Work, a: u32, b: u32) -> (f64, f64) {
    let (pa, pb) = (w.point(a), w.point(b));
    let e = [pb[0] - pa[0], pb[1] - pa[1]];
    (w.metric(a).quadratic_form(e).max(0.0).sqrt(), w.metric(b).quadratic_form(e).max(0.0).sqrt())
}

/// The metric length of `ab` when it is above `lmax` (what `w.length(a, b) > lmax` keeps).
#[inline]
pub(super) fn length_above(w: &Work, a: u32, b: u32, lmax: f64) -> Option<f64> {
    let (la, lb) = end_lengths(w, a, b);
    let l = if la.max(lb) <= lmax * (1.0 - MARGIN) {
        None
    } else {
        Some(geometric_mean_length(la, lb)).filter(|&l| l > lmax)
    };
    debug_assert_eq!(l.is_some(), w.length(a, b) > lmax, "edge {a}-{b}");
    l
}

/// The metric length of `ab` when it is below `lmin` (what `w.length(a, b) < lmin` keeps).
#[inline]
pub(super) fn length_below(w: &Work, a: u32, b: u32, lmin: f64) -> Option<f64> {
    let (la, lb) = end_lengths(w, a, b);
    let l = if la.min(lb) >= lmin * (1.0 + MARGIN) {
        None
    } else {
        Some(geometric_mean_length(la, lb)).filter(|&l| l < lmin)
    };
    debug_assert_eq!(l.is_some(), w.length(a, b) < lmin, "edge {a}-{b}");
    l
}

#[cfg(test)]
mod tests {
    use crate::metric::length::{geometric_mean_length, metric_edge_length};
    use crate::metric::Sym2;

    /// The rule the filters rest on, against the length itself: on random edges and
    /// metrics, and on end lengths a few ulps apart, the logarithmic mean is never
    /// outside the end lengths, and `metric_edge_length` is the mean of the end lengths
    /// computed as `end_lengths` computes them (bit for bit).
    #[test]
    fn length_lies_between_end_lengths_and_equals_their_mean() {
        let mut s = 99u64;
        let mut rnd = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..100_000 {
            let m = |r: &mut dyn FnMut() -> f64| {
                let (a, c) = (0.1 + 1e4 * r(), 0.1 + 1e4 * r());
                Sym2 { a, b: 0.9 * (a * c).sqrt() * (2.0 * r() - 1.0), c }
            };
            let (ma, mb) = (m(&mut rnd), m(&mut rnd));
            let (p, q) = ([rnd(), rnd()], [rnd(), rnd()]);
            let e = [q[0] - p[0], q[1] - p[1]];
            let (la, lb) =
                (ma.quadratic_form(e).max(0.0).sqrt(), mb.quadratic_form(e).max(0.0).sqrt());
            let l = metric_edge_length(p, q, &ma, &mb);
            assert_eq!(l.to_bits(), geometric_mean_length(la, lb).to_bits());
            assert!(la.min(lb) * (1.0 - 1e-14) <= l && l <= la.max(lb) * (1.0 + 1e-14));
        }
        for k in 0..2000 {
            let la = 0.5 + rnd();
            let lb = f64::from_bits(la.to_bits() + (k % 7) as u64 - 3);
            let l = geometric_mean_length(la, lb);
            assert!(la.min(lb) * (1.0 - 1e-14) <= l && l <= la.max(lb) * (1.0 + 1e-14));
        }
    }
}
