//! Fuzz target: the OpenFOAM polyMesh reader must return Ok or Err on any bytes, never
//! panic. The input is split at NUL bytes into `points`, `faces`, `owner`, `neighbour`,
//! `boundary`, `cellZones` and `faceZones` (missing polyMesh files are empty; missing
//! zone files are absent, as in a case without zones).
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::openfoam::read_poly_mesh;
use smartmesh_formats::{Error, ErrorKind};

const FILES: [&str; 7] =
    ["points", "faces", "owner", "neighbour", "boundary", "cellZones", "faceZones"];

fuzz_target!(|data: &[u8]| {
    let parts: Vec<&[u8]> = data.splitn(FILES.len(), |&b| b == 0).collect();
    let file = |name: &str| {
        let i = FILES.iter().position(|&f| f == name).unwrap_or(0);
        match parts.get(i) {
            Some(p) => Ok(p.to_vec()),
            None if i >= 5 => Err(Error::new(ErrorKind::Unreadable(std::io::Error::from(
                std::io::ErrorKind::NotFound,
            )))),
            None => Ok(Vec::new()),
        }
    };
    if let Ok(mesh) = read_poly_mesh(file, Path::new("polyMesh")) {
        assert_eq!(mesh.validate(), Vec::new());
    }
});
