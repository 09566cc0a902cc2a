//! What the format tests of both crates share: the public sample meshes written by other
//! tools, a round trip through memory, the Python interpreter and programs of the interop
//! tests, and the usual fingerprint of a tagged mesh.

use std::path::{Path, PathBuf};
use std::process::Command;

use smartmesh_formats::{
    read_bytes, write_bytes, Format, MemorySiblings, ReadContext, TaggedMesh, VtkWrite,
    VtuEncoding, WriteOptions, Written,
};

/// The variable that names the folder of the public sample meshes. CI sets it
/// (`.ci/run`): a test then fails when they are missing, as the interop tests fail without
/// their tools under `SMARTMESH_REQUIRE_INTEROP=1`.
pub const PUBLIC_FIXTURES_VAR: &str = "SMARTMESH_PUBLIC_FIXTURES";

/// The public sample meshes written by other tools: `$SMARTMESH_PUBLIC_FIXTURES`, else
/// `../shared/fixtures/public` beside the repository (where CI's checkout has them; a
/// fresh clone has no `../shared`).
pub fn public_fixtures() -> PathBuf {
    if let Some(p) = std::env::var_os(PUBLIC_FIXTURES_VAR) {
        return PathBuf::from(p);
    }
    // `shared/` sits beside the repository, and this crate one level below it.
    let crate_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let beside = crate_dir.parent().and_then(Path::parent).unwrap_or(crate_dir);
    beside.join("shared/fixtures/public")
}

/// Whether a test that reads the public sample meshes can run. With
/// `SMARTMESH_PUBLIC_FIXTURES` set they are mandatory: a folder that is not there fails
/// the test. Without it, a missing `../shared/fixtures/public` skips the test, saying so
/// ([`crate::skip::skip`]); the caller returns. [`crate::require_public_fixtures`] does
/// both in one line.
pub fn have_public_fixtures() -> bool {
    let dir = public_fixtures();
    if dir.is_dir() {
        return true;
    }
    if std::env::var_os(PUBLIC_FIXTURES_VAR).is_some() {
        panic!("{PUBLIC_FIXTURES_VAR}={}: no such folder of public fixtures", dir.display());
    }
    crate::skip::skip(&format!(
        "the public sample meshes are not at {} (set {PUBLIC_FIXTURES_VAR} to their folder)",
        dir.display()
    ));
    false
}

/// Returns from the calling test, saying that it skips, when the public sample meshes
/// are absent and not required ([`formats::have_public_fixtures`](crate::formats::have_public_fixtures)).
#[macro_export]
macro_rules! require_public_fixtures {
    () => {
        if !$crate::formats::have_public_fixtures() {
            return;
        }
    };
}

/// One public fixture by relative path (`gmsh/naca0012.v41_ascii.msh`); a test calls
/// [`crate::require_public_fixtures`] first.
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
    } else {
        crate::skip::missing_tool(&format!("{py} cannot import the Python modules {modules:?}"));
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
