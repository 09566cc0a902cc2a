//! What the unit tests of geometry, the mesh graph and propagation share: a seedable
//! generator and the brute-force scan.

use super::segment::{Point2, SegmentGeom};
use super::segment_index::Nearest;

/// splitmix64: small, seedable, good enough for test points.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The closest of `segs` to `p` by projecting on every one, ties to the smaller id.
pub(crate) fn brute(segs: &[SegmentGeom], p: Point2) -> Nearest {
    let mut best = Nearest { segment: 0, projection: segs[0].project(p) };
    for (i, s) in segs.iter().enumerate() {
        let c = Nearest { segment: i as u32, projection: s.project(p) };
        if c.beats(&best) {
            best = c;
        }
    }
    best
}
