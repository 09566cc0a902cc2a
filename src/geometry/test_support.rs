//! What the unit tests of geometry, the mesh graph and propagation share: a seedable
//! generator and the brute-force scan.

use smartmesh_test_support::{Generator, SplitMix64};

use super::segment::{Point2, SegmentGeom};
use super::segment_index::Nearest;

/// The tests' splitmix64 (`smartmesh_test_support`), with `unit` callable without the
/// crate's trait in scope.
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        let mut g = SplitMix64(self.0);
        let u = g.unit();
        self.0 = g.0;
        u
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
