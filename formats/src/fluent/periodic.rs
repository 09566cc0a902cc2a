//! Periodic sides as Fluent periodic zones: the boundary faces of a pair's master tags
//! make one face zone of type `periodic` (bc-type 12), those of its slave tags one of
//! type `periodic-shadow` (8), and a periodic face-pair section
//! `(18 (first last periodic-zone shadow-zone)(f p ...))` lists, one line per master
//! face, its face index and that of its shadow (hexadecimal, as the Fluent User's
//! Guide's *Periodic Shadow Faces* section gives it). The pairs are those of
//! [`crate::OpenFoamWrite::cyclic`] (`--cyclic`, or a recipe's PERIODIC section).
//!
//! The faces are matched by the OpenFOAM writer's rule (`openfoam::cyclic::order_slave`:
//! each master face's centre mapped by the transform lands on its shadow's, within
//! 10^-6 of the bounding-box diagonal); sides that are not images of each other, or
//! with as many faces, refuse the write naming the pair. The transform itself is not in
//! a Fluent mesh file (Fluent keeps it in the case file and recomputes it from the face
//! pairs), so it is not written.

use std::collections::BTreeMap;

use super::faces::{Faces, NONE};
use crate::openfoam::cyclic::{diagonal, order_slave};
use crate::CyclicPair;

/// Which side of which pair a boundary tag is on: tag → (pair, master side).
pub(super) fn roles(pairs: &[CyclicPair]) -> BTreeMap<i32, (usize, bool)> {
    let mut out = BTreeMap::new();
    for (k, p) in pairs.iter().enumerate() {
        for &t in &p.master {
            out.entry(t).or_insert((k, true));
        }
        for &t in &p.slave {
            out.entry(t).or_insert((k, false));
        }
    }
    out
}

/// A written face zone's side of a periodic pair (pair, master side), and its faces.
pub(super) type ZoneSide<'a> = (Option<(usize, bool)>, &'a [u32]);

/// One `(18 ...)` section: the zone indices (into the written face zones) of the
/// periodic and the shadow side, and for each master face (by position in its zone)
/// the position of its shadow face in the shadow zone.
pub(super) struct FacePairs {
    /// The `periodic` zone's index.
    pub master_zone: usize,
    /// The `periodic-shadow` zone's index.
    pub shadow_zone: usize,
    /// The shadow zone position of each master face, in master zone order.
    pub shadow_of: Vec<u32>,
}

/// Pairs the faces of each periodic pair: `zones` holds, per written face zone, its
/// role (pair, master side) if it is a periodic one, and its faces.
pub(super) fn pair_faces(
    points: &[[f64; 3]],
    faces: &Faces,
    zones: &[ZoneSide<'_>],
    pairs: &[CyclicPair],
) -> Result<Vec<FacePairs>, String> {
    let diag = diagonal(points);
    let mut out = Vec::with_capacity(pairs.len());
    for (k, pair) in pairs.iter().enumerate() {
        let label =
            format!("periodic pair {} (master {:?}, slave {:?})", k + 1, pair.master, pair.slave);
        if !pair.transform.is_valid() {
            return Err(format!(
                "{label}: the transform has a number that is not finite or a zero axis"
            ));
        }
        let find = |master: bool| {
            zones.iter().position(|z| z.0 == Some((k, master))).ok_or_else(|| {
                format!(
                    "{label}: no boundary face carries the {} tags",
                    if master { "master" } else { "slave" }
                )
            })
        };
        let (m, s) = (find(true)?, find(false)?);
        let listed = |z: usize| -> Vec<(Vec<u32>, u32)> {
            zones[z]
                .1
                .iter()
                .enumerate()
                .map(|(i, &f)| (faces.face(f as usize).to_vec(), i as u32))
                .collect()
        };
        let (master, slave) = (listed(m), listed(s));
        if master.len() != slave.len() {
            return Err(format!(
                "{label}: {} faces on the master side, {} on the slave side",
                master.len(),
                slave.len()
            ));
        }
        let ordered = order_slave(points, &master, slave, &pair.transform, diag)
            .map_err(|e| format!("{label}: {e}"))?;
        debug_assert!(ordered.iter().all(|o| o.1 != NONE));
        out.push(FacePairs {
            master_zone: m,
            shadow_zone: s,
            shadow_of: ordered.into_iter().map(|(_, i)| i).collect(),
        });
    }
    Ok(out)
}
