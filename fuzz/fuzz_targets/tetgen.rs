//! Fuzz target: the TetGen reader must return Ok or Err on any bytes, never panic.
//!
//! A TetGen mesh is a set of files, so the input is split at NUL bytes (which no TetGen
//! file holds): `.ele`, then its `.node`, `.face` and `.edge` siblings, as many as there
//! are parts. Without a NUL the bytes are read alone as a `.node`, a `.smesh`, a `.poly`
//! (each holds its own vertices) and a stream of unknown kind.
#![no_main]

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::{read_bytes, Format, MemorySiblings, ReadContext};

fuzz_target!(|data: &[u8]| {
    let mut parts = data.split(|&b| b == 0);
    let main = parts.next().unwrap_or_default();
    let mut siblings = MemorySiblings::default();
    for (ext, part) in ["node", "face", "edge"].into_iter().zip(parts) {
        siblings.files.insert(ext.to_string(), part.to_vec());
    }
    if siblings.files.is_empty() {
        for ext in ["node", "smesh", "poly", ""] {
            let _ = read_bytes(Format::TetGen, main, &ReadContext::alone(ext));
        }
    } else {
        let _ = read_bytes(
            Format::TetGen,
            main,
            &ReadContext { siblings: &siblings, extension: "ele".into() },
        );
    }
});
