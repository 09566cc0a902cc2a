//! Fuzz target: the VtkLegacy reader must return Ok or Err on any bytes, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::{read_bytes, Format, ReadContext};

fuzz_target!(|data: &[u8]| {
    let _ = read_bytes(Format::VtkLegacy, data, &ReadContext::alone("vtk"));
});
