//! Files, streams and siblings: dispatch to the format modules, stdin/stdout for `-`;
//! files are written through [`crate::output`] (all or nothing).

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, ErrorKind, Result};
use crate::{Format, ReadContext, ReadReport, TaggedMesh, WriteOptions, WriteReport, Written};

/// Where a reader finds the files beside the main one (Triangle's `.node` beside its
/// `.ele`, Medit's `.sol` beside its `.mesh`).
pub trait SiblingSource {
    /// The bytes of the sibling with extension `ext` (no dot), `Ok(None)` when there is
    /// none.
    fn read_sibling(&self, ext: &str) -> Result<Option<Vec<u8>>>;
    /// How to name the sibling in messages.
    fn describe(&self, ext: &str) -> String;
    /// [`read_sibling`](Self::read_sibling), borrowed where the bytes are already in
    /// memory.
    fn sibling_bytes(&self, ext: &str) -> Result<Option<std::borrow::Cow<'_, [u8]>>> {
        Ok(self.read_sibling(ext)?.map(std::borrow::Cow::Owned))
    }
    /// The bytes of a file the main one names by a relative path (a parallel VTK
    /// file's pieces), `Ok(None)` when there is none or it cannot be looked up (a
    /// stream). Where to find it in messages: [`describe_beside`](Self::describe_beside).
    fn read_beside(&self, _name: &str) -> Result<Option<Vec<u8>>> {
        Ok(None)
    }
    /// How to name a file [`read_beside`](Self::read_beside) looks for.
    fn describe_beside(&self, name: &str) -> String {
        name.to_string()
    }
}

/// A path relative to the main file's folder, refused when absolute or when it climbs
/// out of that folder (a file does not get to name any file on the machine).
fn beside(dir: &Path, name: &str) -> Option<PathBuf> {
    let rel = Path::new(name);
    let plain = rel.components().all(|c| matches!(c, std::path::Component::Normal(_)));
    (plain && !name.is_empty()).then(|| dir.join(rel))
}

/// No siblings: a stream.
pub struct NoSiblings;

impl SiblingSource for NoSiblings {
    fn read_sibling(&self, _ext: &str) -> Result<Option<Vec<u8>>> {
        Ok(None)
    }
    fn describe(&self, ext: &str) -> String {
        format!("<stdin>.{ext}")
    }
}

/// Siblings on disk: the main path with its last extension replaced.
pub struct PathSiblings {
    base: PathBuf,
}

impl PathSiblings {
    /// Siblings of `main` (`dir/naca.1.ele` → `dir/naca.1.<ext>`).
    pub fn new(main: &Path) -> Self {
        PathSiblings { base: main.with_extension("") }
    }

    /// The path of the sibling with extension `ext`.
    pub fn path(&self, ext: &str) -> PathBuf {
        let mut s = self.base.clone().into_os_string();
        s.push(".");
        s.push(ext);
        PathBuf::from(s)
    }
}

impl SiblingSource for PathSiblings {
    fn read_sibling(&self, ext: &str) -> Result<Option<Vec<u8>>> {
        let p = self.path(ext);
        match std::fs::read(&p) {
            Ok(b) => Ok(Some(b)),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(Error::new(ErrorKind::Unreadable(e)).with_path(p)),
        }
    }
    fn describe(&self, ext: &str) -> String {
        self.path(ext).display().to_string()
    }
    fn read_beside(&self, name: &str) -> Result<Option<Vec<u8>>> {
        let dir = self.base.parent().unwrap_or(Path::new(""));
        let Some(p) = beside(dir, name) else { return Ok(None) };
        match std::fs::read(&p) {
            Ok(b) => Ok(Some(b)),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(Error::new(ErrorKind::Unreadable(e)).with_path(p)),
        }
    }
    fn describe_beside(&self, name: &str) -> String {
        let dir = self.base.parent().unwrap_or(Path::new(""));
        beside(dir, name).map_or_else(|| name.to_string(), |p| p.display().to_string())
    }
}

/// Siblings held in memory, for tests and for round trips without files.
#[derive(Debug, Default, Clone)]
pub struct MemorySiblings {
    /// Extension (no dot) → bytes.
    pub files: BTreeMap<String, Vec<u8>>,
}

impl MemorySiblings {
    /// The siblings a writer produced.
    pub fn from_written(w: &Written) -> Self {
        MemorySiblings { files: w.siblings.iter().cloned().collect() }
    }
}

impl SiblingSource for MemorySiblings {
    fn read_sibling(&self, ext: &str) -> Result<Option<Vec<u8>>> {
        Ok(self.files.get(ext).cloned())
    }
    fn describe(&self, ext: &str) -> String {
        format!("<memory>.{ext}")
    }
    fn sibling_bytes(&self, ext: &str) -> Result<Option<std::borrow::Cow<'_, [u8]>>> {
        Ok(self.files.get(ext).map(|b| std::borrow::Cow::Borrowed(b.as_slice())))
    }
    /// A file by its relative name, kept in `files` under that name.
    fn read_beside(&self, name: &str) -> Result<Option<Vec<u8>>> {
        Ok(self.files.get(name).cloned())
    }
}

/// Reads a mesh in `format` from bytes. The result is valid ([`TaggedMesh::validate`]
/// finds no problem), so whatever a reader let through, no cell refers to a missing
/// point and no data array has the wrong length.
pub fn read_bytes(format: Format, bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_bytes_reported(format, bytes, ctx).map(|(mesh, _)| mesh)
}

/// [`read_bytes`], with what the reader changed on the way ([`ReadReport`]: a
/// second-order Gmsh mesh read as linear).
pub fn read_bytes_reported(
    format: Format,
    bytes: &[u8],
    ctx: &ReadContext<'_>,
) -> Result<(TaggedMesh, ReadReport)> {
    let mut report = ReadReport::default();
    let mesh = match format {
        // A 3D .node/.ele/.poly/.edge is TetGen's (see `tetgen::claims`).
        Format::TetGen => {
            let (mesh, r) = crate::tetgen::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Triangle if crate::tetgen::claims(bytes, ctx) => {
            let (mesh, r) = crate::tetgen::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Triangle => crate::triangle::read(bytes, ctx)?,
        // A `.msh` whose first non-blank byte is `(` is Fluent's.
        Format::Gmsh if crate::fluent::claims(bytes) => {
            let (mesh, r) = crate::fluent::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Fluent => {
            let (mesh, r) = crate::fluent::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Gmsh => {
            let (mesh, r) = crate::gmsh::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::VtkLegacy => {
            let (mesh, r) = crate::vtk::read_legacy_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Vtu => {
            let (mesh, r) = crate::vtk::read_vtu_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Obj => crate::obj::read(bytes, ctx)?,
        Format::Medit => {
            let (mesh, r) = crate::medit::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Su2 => {
            let (mesh, r) = crate::su2::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Stl => {
            let (mesh, r) = crate::stl::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Cgns => {
            let (mesh, r) = crate::cgns::read_reported(bytes, ctx)?;
            report = r;
            mesh
        }
        Format::Gltf => {
            return Err(Error::new(ErrorKind::Unsupported(
                "reading glTF (smartmesh writes it for viewers)".into(),
            )))
        }
        Format::OpenFoam => {
            return Err(Error::new(ErrorKind::Unsupported(
                "reading an OpenFOAM case from bytes: it is a directory, read it by its path"
                    .into(),
            )))
        }
    };
    if format.checks().reader_validates {
        debug_assert_eq!(
            mesh.validate(),
            Vec::new(),
            "the {} reader let an invalid mesh through",
            format.name()
        );
    } else if let Some(p) = mesh.validate().into_iter().next() {
        return Err(Error::new(ErrorKind::Inconsistent(p.to_string())));
    }
    Ok((mesh, report))
}

/// The error for writing a mesh that [`TaggedMesh::validate`] refuses, in `format`:
/// the first problem it finds.
pub(crate) fn refused(format: Format, mesh: &TaggedMesh) -> Error {
    let reason = mesh
        .validate()
        .into_iter()
        .next()
        .map_or_else(|| "the mesh is inconsistent".to_string(), |p| p.to_string());
    Error::new(ErrorKind::CannotWrite { format: format.name(), reason })
}

/// Writes a mesh in `format` to bytes (the main file and its siblings). A mesh that
/// [`TaggedMesh::validate`] refuses is not written.
pub fn write_bytes(format: Format, mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    write_bytes_into(format, mesh, opts, Vec::new())
}

/// [`write_bytes`], the main file written into `spare`'s memory where the writer can
/// (Gmsh, Medit `.meshb`, VTU): memory a process already touched is not faulted in again, which in a binary
/// conversion of 10^6 cells costs more than the conversion itself.
fn write_bytes_into(
    format: Format,
    mesh: &TaggedMesh,
    opts: &WriteOptions,
    spare: Vec<u8>,
) -> Result<Written> {
    if !format.checks().writer_validates && !mesh.validate().is_empty() {
        return Err(refused(format, mesh));
    }
    match format {
        Format::Triangle => crate::triangle::write(mesh, opts),
        // Validated above, with the error `gmsh::write` would give. Point sets become
        // named groups of point elements, which MSH holds.
        Format::Gmsh => match crate::point_sets::as_vertex_cells(mesh) {
            Some(lowered) => crate::gmsh::write_validated(&lowered, opts, spare),
            None => crate::gmsh::write_validated(mesh, opts, spare),
        },
        Format::VtkLegacy => crate::vtk::write_legacy(mesh, opts),
        Format::Vtu => crate::vtk::write_vtu_into(mesh, opts, spare),
        Format::Obj => crate::obj::write(mesh, opts),
        Format::Medit => crate::medit::write_into(mesh, opts, spare),
        Format::Gltf => crate::gltf::write(mesh, opts),
        Format::Su2 => crate::su2::write(mesh, opts),
        Format::Stl => crate::stl::write(mesh, opts),
        Format::TetGen => crate::tetgen::write(mesh, opts),
        Format::Fluent => crate::fluent::write(mesh, opts),
        Format::Cgns => crate::cgns::write(mesh, opts),
        Format::OpenFoam => Err(Error::new(ErrorKind::CannotWrite {
            format: format.name(),
            reason: "an OpenFOAM case is a directory of files, not one file or a stream; \
                write a .msh, then `smartmesh convert MESH.msh CASE.foam`"
                .into(),
        })),
    }
}

fn resolve_format(path: &Path, format: Option<Format>) -> Result<Format> {
    match format {
        Some(f) => Ok(f),
        None => Format::from_path(path).ok_or_else(|| unknown_format(path)),
    }
}

/// The error for a path whose extension names no format, naming the path.
fn unknown_format(path: &Path) -> Error {
    let ext = path.extension().map(|e| e.to_string_lossy().into_owned());
    Error::new(ErrorKind::UnknownFormat(ext.unwrap_or_default())).with_path(path)
}

fn is_stdio(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// Reads a mesh from a path (`-` for stdin, which needs `format`). Siblings are
/// looked up beside the path. Errors carry the path.
///
/// ```
/// use std::path::Path;
/// use smartmesh_formats::{read_path, CellKind};
///
/// let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cylinder.msh");
/// let mesh = read_path(&path, None)?; // the format told by the extension
/// assert_eq!(mesh.points.len(), 1148);
/// assert_eq!(mesh.num_cells_of(CellKind::Triangle), 2134);
/// assert_eq!(mesh.tag_name(2, 10), Some("Fluid"));
/// # Ok::<(), smartmesh_formats::Error>(())
/// ```
pub fn read_path(path: &Path, format: Option<Format>) -> Result<TaggedMesh> {
    read_path_reported(path, format).map(|(mesh, _)| mesh)
}

/// [`read_path`], with what the reader changed on the way ([`ReadReport`]).
pub fn read_path_reported(path: &Path, format: Option<Format>) -> Result<(TaggedMesh, ReadReport)> {
    read_path_reported_without(path, format, &[])
}

/// Siblings on disk but those whose extension is listed.
struct SiblingsBut<'a> {
    inner: PathSiblings,
    left_out: &'a [&'a str],
}

impl SiblingSource for SiblingsBut<'_> {
    fn read_sibling(&self, ext: &str) -> Result<Option<Vec<u8>>> {
        if self.left_out.contains(&ext) {
            return Ok(None);
        }
        self.inner.read_sibling(ext)
    }
    fn describe(&self, ext: &str) -> String {
        self.inner.describe(ext)
    }
    fn read_beside(&self, name: &str) -> Result<Option<Vec<u8>>> {
        self.inner.read_beside(name)
    }
    fn describe_beside(&self, name: &str) -> String {
        self.inner.describe_beside(name)
    }
}

/// [`read_path_reported`] as if the siblings with the extensions `left_out` were not
/// there (`["sol", "solb"]`: a Medit mesh without its solution, which may be unreadable
/// or of another mesh).
pub fn read_path_reported_without(
    path: &Path,
    format: Option<Format>,
    left_out: &[&str],
) -> Result<(TaggedMesh, ReadReport)> {
    read_path_keeping_bytes(path, format, left_out).map(|(mesh, report, _)| (mesh, report))
}

/// [`read_path_reported_without`], handing back the buffer the file was read into, for
/// [`write_path_reusing`] to write the output into the same memory (a conversion).
pub fn read_path_keeping_bytes(
    path: &Path,
    format: Option<Format>,
    left_out: &[&str],
) -> Result<(TaggedMesh, ReadReport, Vec<u8>)> {
    if is_stdio(path) {
        let format = format.ok_or_else(|| Error::new(ErrorKind::UnknownFormat(String::new())))?;
        let mut bytes = Vec::new();
        std::io::stdin().lock().read_to_end(&mut bytes)?;
        let ctx = ReadContext { siblings: &NoSiblings, extension: String::new() };
        let (mesh, report) = read_bytes_reported(format, &bytes, &ctx)?;
        return Ok((mesh, report, bytes));
    }
    let format = resolve_format(path, format)?;
    if format == Format::OpenFoam {
        return Ok((crate::openfoam::read_case(path)?, ReadReport::default(), Vec::new()));
    }
    let bytes =
        std::fs::read(path).map_err(|e| Error::new(ErrorKind::Unreadable(e)).with_path(path))?;
    let siblings = SiblingsBut { inner: PathSiblings::new(path), left_out };
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let ctx = ReadContext { siblings: &siblings, extension: ext };
    let (mesh, report) =
        read_bytes_reported(format, &bytes, &ctx).map_err(|e| e.with_path(path))?;
    Ok((mesh, report, bytes))
}

/// Writes a mesh to a path (`-` for stdout, which needs `format` and a format without
/// siblings). Every file goes to a temporary name beside its target first and is
/// renamed only when all are complete.
pub fn write_path(
    path: &Path,
    mesh: &TaggedMesh,
    format: Option<Format>,
    opts: &WriteOptions,
) -> Result<WriteReport> {
    write_path_reusing(path, mesh, format, opts, Vec::new())
}

/// [`write_path`], the main file built in `spare`'s memory where the writer can (the
/// bytes [`read_path_keeping_bytes`] read; their contents do not matter). Still written
/// to a temporary file renamed once complete.
pub fn write_path_reusing(
    path: &Path,
    mesh: &TaggedMesh,
    format: Option<Format>,
    opts: &WriteOptions,
    spare: Vec<u8>,
) -> Result<WriteReport> {
    if is_stdio(path) {
        let format = format
            .ok_or_else(|| Error::new(ErrorKind::UnknownFormat(String::new())).on_stdout())?;
        let mut opts = opts.clone();
        opts.main_name = None;
        let written = write_bytes_into(format, mesh, &opts, spare)?;
        if !written.siblings.is_empty() {
            let exts: Vec<_> = written.siblings.iter().map(|(e, _)| format!(".{e}")).collect();
            return Err(Error::new(ErrorKind::CannotWrite {
                format: format.name(),
                reason: format!(
                    "it needs sibling files ({}), which stdout cannot hold; name an output file",
                    exts.join(", ")
                ),
            }));
        }
        write_stream(&mut std::io::stdout().lock(), &written.main)?;
        return Ok(written.report);
    }
    let format = resolve_format(path, format)?;
    if format == Format::OpenFoam {
        return crate::openfoam::write_case(path, mesh, &opts.openfoam);
    }
    let mut opts = opts.clone();
    opts.main_name = path.file_name().and_then(|n| n.to_str()).map(str::to_owned);
    let written = write_bytes_into(format, mesh, &opts, spare).map_err(|e| e.with_path(path))?;
    let siblings = PathSiblings::new(path);
    let mut targets = vec![(path.to_path_buf(), written.main)];
    for (ext, bytes) in written.siblings {
        targets.push((siblings.path(&ext), bytes));
    }
    crate::output::write_all_atomically(&targets)?;
    Ok(written.report)
}

/// Writes `bytes` to standard output (`out`); errors name it.
fn write_stream(out: &mut impl Write, bytes: &[u8]) -> Result<()> {
    out.write_all(bytes).and_then(|()| out.flush()).map_err(|e| Error::from(e).on_stdout())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A stream on a full disk.
    struct Full;

    impl Write for Full {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::Error::from_raw_os_error(28))
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_failing_stdout_is_named_as_the_output() {
        let e = write_stream(&mut Full, b"x").unwrap_err();
        assert!(e.to_string().starts_with("<stdout>: "), "{e}");
        assert!(!e.is_input_error());
    }
    /// A writer handed used memory (a conversion's input bytes) writes the same bytes as
    /// one given none, in every format that takes it and every VTU encoding.
    #[test]
    fn reused_memory_gives_the_same_bytes() {
        use crate::{CellBlock, CellKind, TaggedMesh, VtuEncoding};
        let mut mesh = TaggedMesh::new();
        mesh.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mut b = CellBlock::new(CellKind::Tetra);
        b.push(&[0, 1, 2, 3], 7, 7);
        mesh.blocks.push(b);
        let used = vec![0xA5u8; 1 << 16];
        for (format, name) in
            [(Format::Gmsh, "m.msh"), (Format::Medit, "m.meshb"), (Format::Vtu, "m.vtu")]
        {
            for enc in [VtuEncoding::Ascii, VtuEncoding::Binary, VtuEncoding::Appended] {
                for compress in [false, true] {
                    let mut opts =
                        WriteOptions { main_name: Some(name.into()), ..WriteOptions::default() };
                    opts.vtk.vtu_encoding = enc;
                    opts.vtk.compress = compress;
                    let fresh = write_bytes_into(format, &mesh, &opts, Vec::new()).unwrap();
                    let reused = write_bytes_into(format, &mesh, &opts, used.clone()).unwrap();
                    assert_eq!(fresh.main, reused.main, "{name} {enc:?} {compress}");
                }
            }
        }
    }
}
