//! Batches of adaptation runs: many variants of a geometry with one recipe (thesis
//! 6.3.1), from a manifest ([`manifest`]), with one result record per variant appended
//! to `results.jsonl` ([`results`]).
//!
//! A variant is identified by its name and by a content hash ([`content_hash`]) of what
//! decides its result: the bytes of its input and recipe, its options and the program's
//! version. A recorded result whose hash matches, and whose output is still there, need
//! not be run again (`--resume`). Shards ([`Shard`]) split a manifest across the tasks of
//! a job array by the variant's position: variant k goes to shard k mod N, so that each
//! shard gets a spread of the manifest and the shards of one manifest are disjoint and
//! cover it.

pub mod manifest;
pub mod results;

use std::io::Read;
use std::path::Path;

use sha2::{Digest, Sha256};

/// The shell prologue that makes a variant's process die with the batch that started it.
pub use crate::child::GUARD;
pub use manifest::{ManifestError, Variant};
pub use results::{ResultRecord, Status};

/// Families of geometry variants (NACA airfoils, turbine distributors) written as
/// Triangle `.poly` files with a manifest for `smartmesh batch`.
pub mod variants {
    pub use crate::variants::{distributor, naca, parse_values, GeometryError, Pslg};
}

/// Shard `index` of `count` (`--shard i/N`, `i` from 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, in `0..count`.
    pub index: usize,
    /// How many shards.
    pub count: usize,
}

impl Shard {
    /// Parses `i/N` with `0 <= i < N`.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let bad = || {
            format!("`{text}` is not a shard: expected i/N with 0 <= i < N (as --shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT with --array=0-<N-1>)")
        };
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Whether the variant at `position` (from 0, in manifest order) is this shard's.
    pub fn holds(&self, position: usize) -> bool {
        position % self.count == self.index
    }
}

/// The content hash of a variant (SHA-256, hex): the program's version, the variant's
/// name, the bytes of its input and recipe, its output format and its options. Files a
/// recipe includes (`#include`, `@include`) are not part of it.
pub fn content_hash(variant: &Variant) -> std::io::Result<String> {
    // Each part is its length, then its bytes: the boundaries between parts count.
    fn part(h: &mut Sha256, bytes: &[u8]) {
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(bytes);
    }
    let mut h = Sha256::new();
    part(&mut h, b"smartmesh batch 1");
    part(&mut h, env!("CARGO_PKG_VERSION").as_bytes());
    part(&mut h, variant.name.as_bytes());
    hash_file(&mut h, &variant.input)?;
    hash_file(&mut h, &variant.recipe)?;
    part(&mut h, variant.format.as_bytes());
    for a in &variant.args {
        part(&mut h, a.as_bytes());
    }
    let digest = h.finalize();
    Ok(digest.iter().map(|b| format!("{b:02x}")).collect())
}

/// Hashes a regular file's length and bytes as they stream by (a large input is never
/// held whole); a device or pipe is refused before it is opened.
fn hash_file(h: &mut Sha256, path: &Path) -> std::io::Result<()> {
    let named =
        |e: std::io::Error| std::io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    if !std::fs::metadata(path).map_err(named)?.is_file() {
        return Err(named(std::io::Error::other("not a regular file")));
    }
    let mut file = std::fs::File::open(path).map_err(named)?;
    let len = file.metadata().map_err(named)?.len();
    h.update(len.to_le_bytes());
    let copied = std::io::copy(&mut (&mut file).take(len), h).map_err(named)?;
    if copied != len {
        return Err(named(std::io::Error::other("the file changed while it was read")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_are_disjoint_and_cover_the_manifest() {
        for count in 1..6 {
            let shards: Vec<Shard> =
                (0..count).map(|i| Shard::parse(&format!("{i}/{count}")).unwrap()).collect();
            for position in 0..23 {
                assert_eq!(shards.iter().filter(|s| s.holds(position)).count(), 1);
            }
        }
        for bad in ["3/3", "1/0", "a/2", "1", "-1/2", "1/2/3"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn the_hash_follows_content_not_names_of_files() {
        let d = tempfile::tempdir().unwrap();
        let write = |n: &str, t: &str| {
            std::fs::write(d.path().join(n), t).unwrap();
            d.path().join(n)
        };
        let v = Variant {
            line: 1,
            name: "a".into(),
            input: write("in.poly", "geometry"),
            recipe: write("r.toml", "recipe"),
            format: "msh".into(),
            args: vec!["--hmin".into(), "0.1".into()],
            argv: vec!["--hmin=0.1".into()],
        };
        let h = content_hash(&v).unwrap();
        assert_eq!(h.len(), 64);
        let moved = Variant { input: write("copy.poly", "geometry"), line: 7, ..v.clone() };
        assert_eq!(content_hash(&moved).unwrap(), h);
        let edited = Variant { input: write("in2.poly", "geometry "), ..v.clone() };
        assert_ne!(content_hash(&edited).unwrap(), h);
        let other = Variant { args: vec!["--hmin".into(), "0.2".into()], ..v.clone() };
        assert_ne!(content_hash(&other).unwrap(), h);
        // The length prefix keeps the boundary between parts.
        let split = Variant { args: vec!["--hmin0".into(), ".1".into()], ..v.clone() };
        assert_ne!(content_hash(&split).unwrap(), h);
    }
}
