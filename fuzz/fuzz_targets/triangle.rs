//! Fuzz target: the Triangle reader must return Ok or Err on any bytes, never panic.
//!
//! A Triangle mesh is a set of files, so the input is split at NUL bytes (which no
//! Triangle file holds): `.ele`, then its `.node`, `.poly`, `.edge` and `.area`
//! siblings, as many as there are parts. Without a NUL the bytes are read alone as a
//! `.node`, a `.poly` (each holds its own vertices) and a stream of unknown kind.
#![no_main]

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::{read_bytes, Format, MemorySiblings, ReadContext};

fuzz_target!(|data: &[u8]| {
    let mut parts = data.split(|&b| b == 0);
    let main = parts.next().unwrap_or_default();
    let mut siblings = MemorySiblings::default();
    for (ext, part) in ["node", "poly", "edge", "area"].into_iter().zip(parts) {
        siblings.files.insert(ext.to_string(), part.to_vec());
    }
    if siblings.files.is_empty() {
        for ext in ["node", "poly", ""] {
            let _ = read_bytes(Format::Triangle, main, &ReadContext::alone(ext));
        }
    } else {
        let _ = read_bytes(
            Format::Triangle,
            main,
            &ReadContext { siblings: &siblings, extension: "ele".into() },
        );
    }
});
