//! Fuzz target: the Gmsh reader must return Ok or Err on any bytes, never panic; what it
//! reads, the writer writes in the four encodings (2.2 and 4.1, ASCII and binary), and
//! the reader reads that back with the same points and cells (kind and nodes, in order):
//! the writer's records of every cell kind are crossed, 3D ones included.
#![no_main]

use libfuzzer_sys::fuzz_target;
use smartmesh_formats::{
    gmsh, read_bytes, CellKind, Format, GmshVersion, GmshWrite, ReadContext, TaggedMesh,
    WriteOptions,
};

fn cells(m: &TaggedMesh) -> Vec<(CellKind, Vec<u32>)> {
    m.cells().map(|(k, n, _, _)| (k, n.to_vec())).collect()
}

fuzz_target!(|data: &[u8]| {
    let ctx = ReadContext::alone("msh");
    // Whatever it accepts is a valid mesh (`read_bytes` skips its own check for the
    // readers that check as they read, in builds without debug assertions).
    let Ok(mesh) = read_bytes(Format::Gmsh, data, &ctx) else { return };
    assert_eq!(mesh.validate(), Vec::new());
    for version in [GmshVersion::V22, GmshVersion::V41] {
        for binary in [false, true] {
            let opts =
                WriteOptions { gmsh: GmshWrite { version, binary }, ..WriteOptions::default() };
            // A mesh MSH cannot number (more than 2^31 items) is refused: not a finding.
            let Ok(w) = gmsh::write(&mesh, &opts) else { continue };
            let back = read_bytes(Format::Gmsh, &w.main, &ctx)
                .unwrap_or_else(|e| panic!("{version:?} binary={binary}: {e}"));
            assert_eq!(back.points.len(), mesh.points.len(), "{version:?} binary={binary}");
            assert!(cells(&back) == cells(&mesh), "{version:?} binary={binary}: cells differ");
        }
    }
});
