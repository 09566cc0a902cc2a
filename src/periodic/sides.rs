//! The sequence every command that keeps periodic sides runs, in one place: the input's
//! slave vertices snapped onto the master's images and each pair measured ([`Sides`]),
//! then, once the work is done, each pair measured again and the first one whose match
//! the work broke named ([`Sides::recheck`]).
//!
//! Invariant: `moved`, `before` and a recheck's `after` hold one entry per pair, in the
//! order of `pairs`. A pair that did not match on the input may stay unmatched: only a
//! match lost counts as broken.

use smartmesh_formats::TaggedMesh;

use super::{check_all, snap, PairMatch, PeriodicError, PeriodicPair};

/// The periodic pairs of a mesh with their slave vertices snapped, before they are
/// measured ([`Snapped::check`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Snapped {
    /// The pairs.
    pub pairs: Vec<PeriodicPair>,
    /// Per pair, the largest move of a slave vertex onto its master's image (0: none).
    pub moved: Vec<f64>,
}

/// The periodic pairs of the input of some work, snapped and measured.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Sides {
    /// The pairs.
    pub pairs: Vec<PeriodicPair>,
    /// Per pair, the largest move of a slave vertex onto its master's image (0: none).
    pub moved: Vec<f64>,
    /// Per pair, its match on the input once snapped.
    pub before: Vec<PairMatch>,
}

/// The pairs measured again on the work's result.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rechecked {
    /// Per pair, its match on the result.
    pub after: Vec<PairMatch>,
    /// The first pair that matched on the input and no longer does.
    pub broken: Option<usize>,
}

impl Sides {
    /// Snaps the slave vertices of `pairs` on `mesh` onto the master's images ([`snap`]);
    /// [`Snapped::check`] then measures them.
    pub fn snap(mesh: &mut TaggedMesh, pairs: &[PeriodicPair]) -> Snapped {
        Snapped { pairs: pairs.to_vec(), moved: snap(mesh, pairs) }
    }

    /// [`Sides::snap`] and [`Snapped::check`] in one.
    pub fn snap_and_check(
        mesh: &mut TaggedMesh,
        pairs: &[PeriodicPair],
    ) -> Result<Sides, PeriodicError> {
        Sides::snap(mesh, pairs).check(mesh)
    }

    /// The pairs that did not match on the input (kept as they are).
    pub fn unmatched(&self) -> impl Iterator<Item = &PairMatch> {
        self.before.iter().filter(|m| !m.matched)
    }

    /// Each pair measured on `result`, and the first whose match was lost.
    pub fn recheck(&self, result: &TaggedMesh) -> Result<Rechecked, PeriodicError> {
        let after = check_all(result, &self.pairs)?;
        let broken = self.before.iter().zip(&after).position(|(b, a)| b.matched && !a.matched);
        Ok(Rechecked { after, broken })
    }
}

impl Snapped {
    /// Each pair measured on `mesh` (the mesh snapped): refused when its sides are not
    /// images of each other.
    pub fn check(self, mesh: &TaggedMesh) -> Result<Sides, PeriodicError> {
        let before = check_all(mesh, &self.pairs)?;
        Ok(Sides { pairs: self.pairs, moved: self.moved, before })
    }
}
