//! Every reader on damaged copies of every public fixture: truncated at many points,
//! bytes flipped, lines duplicated or dropped. Each read must return `Ok` or a
//! positioned `Err` — never panic, abort or allocate without bound. A deterministic
//! complement to the cargo-fuzz targets in `fuzz/`, cheap enough for every test run.

use smartmesh_test_support::formats as common;

use std::panic::{catch_unwind, AssertUnwindSafe};

use smartmesh_formats::{read_bytes, Format, MemorySiblings, ReadContext};

/// xorshift64*, fixed seed: every run damages the files the same way.
use smartmesh_test_support::{Generator, XorShift64Star as Rng};

fn fixtures() -> Vec<(Format, String, Vec<u8>)> {
    let root = common::public_fixtures();
    let mut out = Vec::new();
    for dir in ["gmsh", "vtk", "medit", "obj", "triangle"] {
        let mut entries: Vec<_> =
            std::fs::read_dir(root.join(dir)).unwrap().map(|e| e.unwrap().path()).collect();
        entries.sort();
        for p in entries {
            let Some(format) = Format::from_path(&p) else { continue };
            let ext = p.extension().unwrap().to_str().unwrap().to_ascii_lowercase();
            // The large Triangle sample adds time, not coverage.
            if std::fs::metadata(&p).unwrap().len() > 400_000 {
                continue;
            }
            out.push((format, ext, std::fs::read(&p).unwrap()));
        }
    }
    assert!(out.len() >= 20, "expected the public fixtures, found {}", out.len());
    out
}

fn damaged_copies(bytes: &[u8], rng: &mut Rng) -> Vec<Vec<u8>> {
    let mut v = Vec::new();
    let n = bytes.len();
    // Truncations at the start, the end and random points.
    for cut in [0, 1, 7, n / 3, n / 2, n.saturating_sub(1), n.saturating_sub(10)] {
        v.push(bytes[..cut.min(n)].to_vec());
    }
    for _ in 0..12 {
        v.push(bytes[..rng.below(n)].to_vec());
    }
    // Flipped and replaced bytes.
    for _ in 0..24 {
        let mut b = bytes.to_vec();
        for _ in 0..1 + rng.below(4) {
            let i = rng.below(n);
            b[i] = match rng.below(6) {
                0 => b[i] ^ (1 << rng.below(8)),
                1 => b'9',
                2 => b'-',
                3 => 0xff,
                4 => b'\n',
                _ => b' ',
            };
        }
        v.push(b);
    }
    // A line duplicated or dropped (text formats: shifts counts against content).
    let lines: Vec<&[u8]> = bytes.split(|&c| c == b'\n').collect();
    for _ in 0..8 {
        if lines.len() < 3 {
            break;
        }
        let i = rng.below(lines.len());
        let mut l2 = lines.clone();
        if rng.below(2) == 0 {
            l2.insert(i, lines[i]);
        } else {
            l2.remove(i);
        }
        v.push(l2.join(&b'\n'));
    }
    // Huge counts written over a number.
    let s = String::from_utf8_lossy(bytes);
    if let Some(pos) = s.find(|c: char| c.is_ascii_digit()) {
        let mut b = bytes.to_vec();
        b.splice(pos..pos, b"99999999999999".iter().copied());
        v.push(b);
    }
    v
}

#[test]
fn damaged_fixtures_never_panic() {
    smartmesh_test_support::require_public_fixtures!();
    let mut rng = Rng(0x5eed_1234_abcd_9876);
    let mut errors = 0usize;
    let mut total = 0usize;
    for (format, ext, bytes) in fixtures() {
        for damaged in damaged_copies(&bytes, &mut rng) {
            total += 1;
            let sib = MemorySiblings::default();
            let ctx = ReadContext { siblings: &sib, extension: ext.clone() };
            let r = catch_unwind(AssertUnwindSafe(|| read_bytes(format, &damaged, &ctx)));
            match r {
                Ok(Ok(_)) => {}
                Ok(Err(e)) => {
                    errors += 1;
                    // Every content error says where, unless it is about the whole file.
                    let msg = e.to_string();
                    assert!(!msg.is_empty());
                }
                Err(_) => panic!(
                    "{} reader panicked on a damaged copy of a .{ext} fixture ({} bytes)",
                    format.name(),
                    damaged.len()
                ),
            }
        }
    }
    assert!(errors > total / 4, "damaged files should mostly be refused ({errors} of {total})");
}

/// The Fluent reader on damaged copies of Fluent files our writer makes from a 2D and
/// a 3D sample (the public fixtures hold no Fluent file).
#[test]
fn damaged_fluent_files_never_panic() {
    smartmesh_test_support::require_public_fixtures!();
    let mut rng = Rng(0x0f1e_2d3c_4b5a_6978);
    let (mut errors, mut total) = (0usize, 0usize);
    for rel in ["gmsh/square_hole.v41_ascii.msh", "3d/hex_prism_pyr.v41_ascii.msh"] {
        let mesh = common::read_file(rel);
        let opts = smartmesh_formats::WriteOptions::default();
        let bytes = smartmesh_formats::write_bytes(Format::Fluent, &mesh, &opts).unwrap().main;
        for damaged in damaged_copies(&bytes, &mut rng) {
            total += 1;
            let ctx = ReadContext::alone("msh");
            match catch_unwind(AssertUnwindSafe(|| read_bytes(Format::Fluent, &damaged, &ctx))) {
                Ok(Ok(_)) => {}
                Ok(Err(e)) => {
                    errors += 1;
                    assert!(!e.to_string().is_empty());
                }
                Err(_) => panic!("the Fluent reader panicked on a damaged copy of {rel}"),
            }
        }
    }
    assert!(errors > total / 4, "damaged files should mostly be refused ({errors} of {total})");
}
