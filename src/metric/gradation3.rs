//! Anisotropic size gradation on one edge in 3D: the law of the 2D sizing pass
//! (`sizing::gradation`, Alauzet 2010 with the exponential growth law) as a library
//! function, used by `sizing::gradation3`.
//!
//! For an edge pq, with ℓ = ℓ_{M_p}(pq) the edge's length in the tensor at p, the tensor
//! at q must lie inside T_p grown by η = g^ℓ (same axes, all three sizes times η):
//! T_q ⊆ η T_p. Where it does not, T_q is replaced by T_q ∩ η T_p, the simultaneous
//! reduction of [`SizeTensor3::intersection`]: sizes only shrink, and only in the
//! directions where η T_p is smaller, so an anisotropic T_q keeps its anisotropy (an
//! isotropic gradation, which bounds every size by the smallest, destroys it: the
//! warning of MMG's PR #120).
//!
//! The rule itself is [`super::gradation::gradate_edge_generic`], shared with 2D; this
//! file names its 3D form and its tests.

use super::gradation::{gradate_edge_generic, GradedTensor};
use super::size_tensor3::SizeTensor3;

/// Relative slack under which a tensor counts as already inside the grown one (as the
/// 2D pass's `SLACK`), so rounding noise does not shrink it again.
pub const SLACK3: f64 = 1e-9;

/// `t` with its three sizes multiplied by `factor` (kept in the size range).
pub fn grow3(t: &SizeTensor3, factor: f64) -> SizeTensor3 {
    t.grown(factor)
}

/// The growth factor η = g^ℓ allowed from a vertex with tensor `from` along `edge`.
pub fn growth_factor3(from: &SizeTensor3, edge: [f64; 3], gradation: f64) -> f64 {
    gradation.powf(from.metric_length(edge))
}

/// The tensor at q after bounding it by the one at p across the edge vector
/// `edge` = q − p with gradation `gradation` (>= 1): `Some(T_q ∩ η T_p)` when T_q is not
/// already inside η T_p (to [`SLACK3`]), `None` when nothing changes.
pub fn gradate_edge3(
    tp: &SizeTensor3,
    tq: &SizeTensor3,
    edge: [f64; 3],
    gradation: f64,
) -> Option<SizeTensor3> {
    gradate_edge_generic(tp, tq, edge, gradation, SLACK3)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metric::testgen3::directions;

    #[test]
    fn anisotropy_survives_gradation() {
        // A wall layer at p: 1e-3 across the wall (z), 0.1 along it. At q, 0.05 above it,
        // a coarse isotropic 1.0. The bound shrinks q along the wall and across it, but
        // keeps q anisotropic (an isotropic gradation would make it 1e-3·η everywhere).
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        let tp = SizeTensor3::new(x, y, [0.1, 0.1, 1e-3]);
        let tq = SizeTensor3::isotropic(1.0);
        let edge = [0.0, 0.0, 1e-3];
        let g = 1.5;
        let eta = growth_factor3(&tp, edge, g);
        assert!((eta - 1.5).abs() < 1e-12);
        let out = gradate_edge3(&tp, &tq, edge, g).unwrap();
        assert!((out.size_along([0.0, 0.0, 1.0]) - 1.5e-3).abs() < 1e-12, "{out:?}");
        assert!((out.size_along(x) - 0.15).abs() < 1e-12, "{out:?}");
        assert!(out.aspect_ratio() > 99.0, "{out:?}");
        // The result lies inside η T_p and inside T_q on many directions, and is the
        // identity when applied again.
        let grown = grow3(&tp, eta);
        for d in directions(500, &[]) {
            assert!(out.size_along(d) <= grown.size_along(d) * (1.0 + 1e-9));
            assert!(out.size_along(d) <= tq.size_along(d) * (1.0 + 1e-9));
        }
        assert!(gradate_edge3(&tp, &out, edge, g).is_none());
        // A q already inside the grown tensor is left alone.
        assert!(gradate_edge3(&tp, &SizeTensor3::isotropic(1e-3), edge, g).is_none());
    }

    #[test]
    fn crossing_anisotropies_keep_both_directions() {
        // Two layers crossing at right angles: q fine along x, p fine along z. q keeps its
        // fine x size and gains a bounded z size; the y size stays the coarse one grown.
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        let tp = SizeTensor3::new(x, y, [1.0, 1.0, 1e-2]);
        let tq = SizeTensor3::new(x, y, [1e-2, 1.0, 1.0]);
        let out = gradate_edge3(&tp, &tq, [0.0, 1.0, 0.0], 2.0).unwrap();
        assert!((out.size_along(x) - 1e-2).abs() < 1e-14, "{out:?}");
        assert!((out.size_along([0.0, 0.0, 1.0]) - 2e-2).abs() < 1e-14, "{out:?}");
        assert!((out.size_along(y) - 1.0).abs() < 1e-14, "{out:?}");
    }
}
