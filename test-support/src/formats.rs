//! What the format tests of both crates share: the public sample meshes written by other
//! tools, a round trip through memory, the Python interpreter and programs of the interop
//! tests, and the usual fingerprint of a tagged mesh.

use std::path::{Path, PathBuf};
use std::process::Command;

use smartmesh_formats::{
    read_bytes, write_bytes, Format, MemorySiblings, ReadContext, TaggedMesh, VtkWrite,
    VtuEncoding, WriteOptions, Written,
};

/// The public sample meshes written by other tools (`../shared/fixtures/public`), or
/// `$SMARTMESH_PUBLIC_FIXTURES`.
pub fn public_fixtures() -> PathBuf {
    if let Ok(p) = std::env::var("SMARTMESH_PUBLIC_FIXTURES") {
        return PathBuf::from(p);
    }
    // `shared/` sits beside the repository, and this crate one level below it.
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/fixtures/public")
}

/// One public fixture by relative path (`gmsh/naca0012.v41_ascii.msh`).
pub fn public_fixture(rel: &str) -> PathBuf {
    let p = public_fixtures().join(rel);
    assert!(p.exists(), "public fixture {} is missing", p.display());
    p
}

/// Reads a file through the path API (siblings looked up beside it).
pub fn read_file(rel: &str) -> TaggedMesh {
    let p = public_fixture(rel);
    smartmesh_formats::read_path(&p, None).unwrap_or_else(|e| panic!("{e}"))
}

/// Writes `mesh` in `format` and reads it back, through memory.
pub fn roundtrip(
    format: Format,
    ext: &str,
    mesh: &TaggedMesh,
    opts: &WriteOptions,
) -> (Written, TaggedMesh) {
    let written = write_bytes(format, mesh, opts).unwrap_or_else(|e| panic!("write {ext}: {e}"));
    let sib = MemorySiblings::from_written(&written);
    let ctx = ReadContext { siblings: &sib, extension: ext.to_string() };
    let back =
        read_bytes(format, &written.main, &ctx).unwrap_or_else(|e| panic!("read back {ext}: {e}"));
    (written, back)
}

pub use crate::cli::interop_required;

/// The script that reads each `.msh` named on its command line with meshio and with Gmsh,
/// saves it again with Gmsh and reads that back; it prints the counts as one JSON list
/// (`python3 -c SCRIPT FILE…`).
pub const READ_AND_RESAVE: &str = include_str!("read_and_resave.py");

/// The Python interpreter for interop tests (`$SMARTMESH_PYTHON` or `python3`) if it
/// can import every module in `modules`; `None` (the test then skips, saying so)
/// when it cannot, unless interop is required, in which case the test fails.
pub fn python_with(modules: &[&str]) -> Option<String> {
    let py = std::env::var("SMARTMESH_PYTHON").unwrap_or_else(|_| "python3".into());
    let code = modules.iter().map(|m| format!("import {m}")).collect::<Vec<_>>().join("; ");
    let ok =
        Command::new(&py).args(["-c", &code]).output().map(|o| o.status.success()).unwrap_or(false);
    if ok {
        Some(py)
    } else if interop_required() {
        panic!("interop test needs Python modules {modules:?} (SMARTMESH_REQUIRE_INTEROP=1)");
    } else {
        eprintln!("skipping: Python modules {modules:?} not available");
        None
    }
}

/// Runs `python -c script args...` and returns its stdout; panics with stderr on failure.
pub fn run_python(py: &str, script: &str, args: &[&str]) -> String {
    let out = Command::new(py).arg("-c").arg(script).args(args).output().expect("run python");
    assert!(
        out.status.success(),
        "python failed:\n--- stdout\n{}\n--- stderr\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The real `mmg2d_O3` in mmgpy's `bin/` (the one on PATH is a Python wrapper).
pub fn mmg2d(py: &str) -> String {
    let out = run_python(
        py,
        "import mmgpy, os; print(os.path.join(os.path.dirname(mmgpy.__file__), 'bin', 'mmg2d_O3'))",
        &[],
    );
    let exe = out.trim().to_string();
    assert!(Path::new(&exe).exists(), "mmg2d_O3 not found at {exe}");
    exe
}

/// Count of cells per `(kind, physical tag)`, the usual fingerprint of a tagged mesh.
pub fn counts_per_tag(mesh: &TaggedMesh) -> std::collections::BTreeMap<(String, i32), usize> {
    let mut m = std::collections::BTreeMap::new();
    for (kind, _, p, _) in mesh.cells() {
        *m.entry((kind.name().to_string(), p)).or_insert(0) += 1;
    }
    m
}

/// Every variant the VTK writers offer, in a fixed order: legacy 4.2 and 5.1, each ASCII
/// then binary; then `.vtu` ASCII, binary and appended, each plain then zlib (ASCII is
/// never compressed).
pub fn vtk_variants() -> Vec<(Format, VtkWrite)> {
    let mut v = Vec::new();
    for legacy_version in [(4, 2), (5, 1)] {
        for legacy_binary in [false, true] {
            v.push((
                Format::VtkLegacy,
                VtkWrite { legacy_version, legacy_binary, ..VtkWrite::default() },
            ));
        }
    }
    for vtu_encoding in [VtuEncoding::Ascii, VtuEncoding::Binary, VtuEncoding::Appended] {
        for compress in [false, true] {
            if vtu_encoding != VtuEncoding::Ascii || !compress {
                v.push((Format::Vtu, VtkWrite { vtu_encoding, compress, ..VtkWrite::default() }));
            }
        }
    }
    v
}
