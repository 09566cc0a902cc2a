//! Fuzz target: the Fluent reader (ASCII and binary sections) must return Ok or Err on
//! any bytes, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::{read_bytes, Format, ReadContext};

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = read_bytes(Format::Fluent, data, &ReadContext::alone("msh")) {
        assert_eq!(mesh.validate(), Vec::new());
    }
});
