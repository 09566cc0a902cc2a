//! Fuzz target: the STL reader must return Ok or Err on any bytes, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::{read_bytes, Format, ReadContext};

fuzz_target!(|data: &[u8]| {
    // Whatever it accepts is a valid mesh (`read_bytes` skips its own check for the
    // readers that check as they read, in builds without debug assertions).
    if let Ok(mesh) = read_bytes(Format::Stl, data, &ReadContext::alone("stl")) {
        assert_eq!(mesh.validate(), Vec::new());
    }
});
