//! Fuzz target: the OpenFOAM polyMesh reader must return Ok or Err on any bytes, never
//! panic. The input is split at NUL bytes into `points`, `faces`, `owner`, `neighbour`
//! and `boundary` (missing ones are empty files).
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::openfoam::read_poly_mesh;

const FILES: [&str; 5] = ["points", "faces", "owner", "neighbour", "boundary"];

fuzz_target!(|data: &[u8]| {
    let parts: Vec<&[u8]> = data.splitn(FILES.len(), |&b| b == 0).collect();
    let file = |name: &str| {
        let i = FILES.iter().position(|&f| f == name).unwrap_or(0);
        Ok(parts.get(i).copied().unwrap_or(b"").to_vec())
    };
    if let Ok(mesh) = read_poly_mesh(file, Path::new("polyMesh")) {
        assert_eq!(mesh.validate(), Vec::new());
    }
});
