//! VTK: legacy `.vtk` files and XML `.vtu`/`.vtp` files (and parallel `.pvtu`/`.pvtp`).
//!
//! Source: "VTK File Formats", <https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html>
//! (legacy: "Simple Legacy Formats"; XML: "XML File Formats", "Unstructured Grid",
//! "PolyData", "Parallel File Formats", "Appended Data", compressed block headers),
//! checked against what VTK 9.7's own writers produce (the public fixtures, the samples
//! of the interop tests) and what VTK's readers accept (the interop tests).
//!
//! Supported:
//! - legacy datasets `UNSTRUCTURED_GRID`, `POLYDATA`, `STRUCTURED_GRID`,
//!   `RECTILINEAR_GRID` and `STRUCTURED_POINTS` (`legacy/datasets.rs`), file versions
//!   2.0–4.2 (`CELLS n size` with `k i1 .. ik` per cell) and 5.1
//!   (`OFFSETS`/`CONNECTIVITY`), ASCII and BINARY (binary legacy is big-endian),
//!   `METADATA` blocks skipped, `POINT_DATA`/`CELL_DATA` with `SCALARS` (1–4
//!   components), `VECTORS`, `NORMALS`, `TENSORS` (9 values), `TENSORS6` (widened to 9),
//!   `TEXTURE_COORDINATES`, `COLOR_SCALARS`, `GLOBAL_IDS`, `PEDIGREE_IDS`, `FIELD`
//!   arrays; `LOOKUP_TABLE`s are skipped; array names with VTK's `%XX` escapes are
//!   decoded;
//! - XML `UnstructuredGrid` and `PolyData`, any number of `Piece`s, and the parallel
//!   files that name piece files (pieces appended, `xml/pieces.rs`): `ascii`, inline
//!   `binary` (base64) and `appended` (raw or base64) arrays, zlib compression
//!   (`vtkZLibDataCompressor`), `header_type` UInt32 or UInt64, `byte_order`
//!   LittleEndian or BigEndian, every numeric `DataArray` type;
//! - cells: every linear and quadratic type of [`crate::CellKind`] (VTK 1, 3, 5, 9, 10,
//!   12, 13, 14, 21–29, 32), second-order volume cells converted from VTK's node order
//!   to Gmsh's and back (`order.rs`); poly-vertices, poly-lines, triangle strips and
//!   polygons of more than 4 points split, pixels and voxels renumbered (`cells.rs`,
//!   with read notes); polyhedra (42) and the other types refused with the cell and
//!   type named;
//! - tags: cell data `gmsh:physical` and `gmsh:geometrical` (meshio's names), or
//!   `CellEntityIds` (VTK's, e.g. from ParaView's Gmsh reader) when neither is there;
//!   other cell arrays become cell data;
//! - tag names: one dataset-level field array per name holding `[tag, dim]`, which is
//!   meshio's `field_data` convention for Gmsh physical names, so `meshio.read` gives
//!   them back as `field_data`.
//!
//! Written: ASCII or binary legacy 4.2 or 5.1 unstructured grids, and `.vtu` (or `.vtp`
//! PolyData, chosen by the output's name) in ascii, binary or appended (raw) encoding,
//! zlib-compressed or not, little-endian with UInt64 headers (`version="1.0"`, as VTK
//! writes UInt64 headers). Always `gmsh:physical` and `gmsh:geometrical` (Int32) and
//! the cell data; point data as Float64 with its component count; one 9-component
//! point array is the active tensor (`TENSORS` in legacy files, `Tensors=` in XML), so
//! ParaView's Tensor Glyph picks it up: a `size_tensor` if there is one (it glyphs at
//! scale 1), else `metric`, else the first. The 14-node pyramid, which VTK lacks, is
//! written as its 13-node one, the loss listed in the write report.
//!
//! Not supported: writing parallel files and legacy datasets other than unstructured
//! grids, `ImageData`/`StructuredGrid`/`RectilinearGrid` XML files, polyhedra, LZ4 and
//! LZMA compression, string and bit arrays.
//!
//! NaN and infinities: refused in coordinates (and tags); kept in data arrays, as VTK
//! and meshio keep them (`nan`, `inf`, `-inf` in ASCII, as VTK writes them), so that a
//! partial array (a Gmsh view that covers part of the mesh) goes through as it is. The
//! code that uses an array refuses what it cannot use (a metric must be finite and
//! SPD where a triangle uses it).
//!
//! Why by hand and not with the vtkio crate, which the design prefers: measured on the
//! public fixtures and on a 1.5-million-triangle mesh (release build), vtkio 0.6.3 does
//! not read legacy 5.1, VTK's own zlib `.vtu` (its header and blocks are two base64
//! runs) nor appended raw data; 0.7.0-rc2 reads 5.1 and zlib but not appended raw
//! (`unknown variant raw`), took 23–39 s to write zlib `.vtu` (meshio on the same
//! machine: about 4 s), 0.9 s to read it and 1.7 s / 2.5 s to read / write legacy
//! ASCII, failed to read its own legacy binary output, and its errors carry no
//! position. The formats are simple
//! enough that a direct reader and writer are shorter than the adapters would be, and
//! every error gets a line (legacy ASCII) or byte offset. So the crate does not depend
//! on vtkio; VTK's own readers and writers (Python `vtk`) check our files instead, in
//! `tests/vtk_interop.rs`.
//!
//! Speed (same 1.5M-triangle mesh, best of 7, 2-core machine): zlib `.vtu` written in
//! 0.4 s and read in 0.4 s (meshio on the same file and machine: 4.2 s and 1.0 s; the
//! blocks are deflated at level 1 on every core), legacy ASCII read/written in
//! 0.6 s / 0.5 s (meshio: 9.4 s / 10.3 s), legacy binary and appended raw within 1.5–2.2x
//! of copying the file's bytes.

mod cells;
mod decode;
mod grid;
mod legacy;
mod order;
mod xml;

pub(crate) use decode::*;
pub(crate) use grid::{Grid, Named};

use std::borrow::Cow;

use crate::{
    DataArray, ReadContext, ReadReport, Result, TaggedMesh, WriteOptions, WriteReport, Written,
};

/// Both VTK readers check coordinates, connectivity and array lengths as they read
/// them (`Grid::into_mesh`); the writers leave validation to `write_bytes`.
pub(crate) const CHECKS: crate::Checks =
    crate::Checks { reader_validates: true, writer_validates: false };

/// Reads a legacy `.vtk` file (versions 2.0 to 5.1, ASCII or binary).
pub fn read_legacy(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_legacy_reported(bytes, ctx).map(|(m, _)| m)
}

/// [`read_legacy`], with what was changed on the way (cells split).
pub fn read_legacy_reported(
    bytes: &[u8],
    _ctx: &ReadContext<'_>,
) -> Result<(TaggedMesh, ReadReport)> {
    legacy::read(bytes)?.into_mesh()
}

/// Reads a `.vtu` (XML UnstructuredGrid) file in any encoding VTK writes.
pub fn read_vtu(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_vtu_reported(bytes, ctx).map(|(m, _)| m)
}

/// [`read_vtu`], with what was changed on the way (cells split).
pub fn read_vtu_reported(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<(TaggedMesh, ReadReport)> {
    xml::read(bytes, ctx)?.into_mesh()
}

/// How to write VTK files (the `vtk` group of [`WriteOptions`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VtkWrite {
    /// Legacy `.vtk` file version: `(4, 2)` (the default, read by every VTK and meshio)
    /// or `(5, 1)`.
    pub legacy_version: (u8, u8),
    /// Legacy `.vtk` in binary rather than ASCII.
    pub legacy_binary: bool,
    /// XML `.vtu` data encoding.
    pub vtu_encoding: VtuEncoding,
    /// zlib compression of `.vtu` binary and appended data (on by default).
    pub compress: bool,
}

impl Default for VtkWrite {
    fn default() -> Self {
        VtkWrite {
            legacy_version: (4, 2),
            legacy_binary: false,
            vtu_encoding: VtuEncoding::Binary,
            compress: true,
        }
    }
}

/// VTK XML data encoding.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VtuEncoding {
    /// Numbers as text.
    Ascii,
    /// base64 inline binary.
    #[default]
    Binary,
    /// Raw appended data after the XML.
    Appended,
}

/// Writes a legacy `.vtk` file: version `opts.vtk.legacy_version` ((4, 2) or (5, 1)),
/// binary when `opts.vtk.legacy_binary`.
pub fn write_legacy(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let (mesh, lost) = order::to_vtk(mesh);
    let mut w = legacy::write(&mesh, opts)?;
    w.report.dropped.extend(lost);
    Ok(w)
}

/// Writes a `.vtu` file with `opts.vtk.vtu_encoding`, zlib-compressed when `opts.vtk.compress`
/// (ascii is never compressed).
///
/// The output's name chooses the dataset: a `.vtp` is written as PolyData (vertices,
/// lines and polygons only; see `poly_order`); parallel files (`.pvtu`, `.pvtp`) are
/// read, not written.
pub fn write_vtu(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    write_vtu_into(mesh, opts, Vec::new())
}

/// [`write_vtu`], the file built in `spare`'s memory (cleared first; memory the process
/// already touched is not faulted in again).
pub(crate) fn write_vtu_into(
    mesh: &TaggedMesh,
    opts: &WriteOptions,
    spare: Vec<u8>,
) -> Result<Written> {
    let ext = opts
        .main_name
        .as_deref()
        .and_then(|n| n.rsplit_once('.'))
        .map(|(_, e)| e.to_ascii_lowercase())
        .unwrap_or_default();
    if ext == "pvtu" || ext == "pvtp" {
        return Err(crate::Error::new(crate::ErrorKind::CannotWrite {
            format: "VTK XML",
            reason: format!(
                "a parallel .{ext} names piece files; smartmesh writes one .vtu (or .vtp) holding the whole mesh"
            ),
        }));
    }
    if ext == "vtp" {
        let mesh = poly_order(mesh)?;
        return xml::write(&mesh, opts, true, spare);
    }
    let (mesh, lost) = order::to_vtk(mesh);
    let mut w = xml::write(&mesh, opts, false, spare)?;
    w.report.dropped.extend(lost);
    Ok(w)
}

/// The mesh with its blocks in PolyData's order (vertices, lines, then triangles and
/// quads, each group in block order) and its cell data following them; refused when it
/// holds cells PolyData has no place for (second-order and volume cells).
fn poly_order(mesh: &TaggedMesh) -> Result<Cow<'_, TaggedMesh>> {
    use crate::CellKind as K;
    if let Some(b) = mesh
        .blocks
        .iter()
        .find(|b| !b.is_empty() && !matches!(b.kind, K::Vertex | K::Line | K::Triangle | K::Quad))
    {
        return Err(crate::Error::new(crate::ErrorKind::CannotWrite {
            format: "VTK XML PolyData (.vtp)",
            reason: format!(
                "{} {} cells: PolyData holds vertices, lines, triangles and quads; write a .vtu",
                b.len(),
                b.kind.name()
            ),
        }));
    }
    let dims: Vec<u8> = mesh.blocks.iter().map(|b| b.kind.dim()).collect();
    if dims.windows(2).all(|w| w[0] <= w[1]) {
        return Ok(Cow::Borrowed(mesh));
    }
    // Block `i`'s cells start at `first[i]` in the mesh's cell order.
    let mut first = Vec::with_capacity(mesh.blocks.len());
    let mut n = 0;
    for b in &mesh.blocks {
        first.push(n);
        n += b.len();
    }
    let mut order: Vec<usize> = (0..mesh.blocks.len()).collect();
    order.sort_by_key(|&i| dims[i]);
    let mut m = mesh.clone();
    m.blocks = order.iter().map(|&i| mesh.blocks[i].clone()).collect();
    for (name, a) in &mesh.cell_data {
        let k = a.components;
        let values = order
            .iter()
            .flat_map(|&i| {
                let (s, e) = (first[i], first[i] + mesh.blocks[i].len());
                a.values[s * k..e * k].iter().copied()
            })
            .collect();
        m.cell_data.insert(name.clone(), DataArray { values, ..a.clone() });
    }
    Ok(Cow::Owned(m))
}

/// The VTK cell type of a kind the writers were given: [`order::to_vtk`] has turned
/// the one kind without a VTK type (the 14-node pyramid) into one with.
pub(crate) fn vtk_type_of(kind: crate::CellKind) -> u8 {
    kind.vtk_type().unwrap_or(27)
}

/// Cell data names of the tags, as meshio writes them for Gmsh meshes.
pub(crate) const PHYSICAL: &str = "gmsh:physical";
pub(crate) const GEOMETRICAL: &str = "gmsh:geometrical";
/// VTK's name for a per-cell entity id (vtkGmshReader, Exodus, ParaView).
pub(crate) const ENTITY_IDS: &str = "CellEntityIds";

/// Which of the tag arrays (physical, geometrical, entity ids) a cell array named
/// `name` is, if it is one.
pub(crate) fn tag_slot(name: &str) -> Option<usize> {
    [PHYSICAL, GEOMETRICAL, ENTITY_IDS].iter().position(|t| *t == name)
}

/// What both writers write, decided once: tag arrays, data arrays in name order, the
/// active tensor, tag names, and what is dropped.
pub(crate) struct Plan<'m> {
    pub physical: Vec<i32>,
    pub geometrical: Vec<i32>,
    /// The arrays to write, packed tensors expanded to VTK's 9 components.
    pub cell_arrays: Vec<(&'m str, Cow<'m, DataArray>)>,
    pub point_arrays: Vec<(&'m str, Cow<'m, DataArray>)>,
    /// The point array written as the active tensor.
    pub tensor: Option<&'m str>,
    /// Tag names as `(name, tag, dim)`, one array each.
    pub names: Vec<(&'m str, i32, u8)>,
    pub report: WriteReport,
}

impl<'m> Plan<'m> {
    pub(crate) fn new(mesh: &'m TaggedMesh, format: &str) -> Plan<'m> {
        let mut report = WriteReport::default();
        let nc = mesh.num_cells();
        let mut physical = Vec::with_capacity(nc);
        let mut geometrical = Vec::with_capacity(nc);
        for b in &mesh.blocks {
            physical.extend_from_slice(&b.physical);
            geometrical.extend_from_slice(&b.geometrical);
        }
        let mut cell_arrays = Vec::new();
        for (name, a) in &mesh.cell_data {
            if name == PHYSICAL || name == GEOMETRICAL {
                report.drop(format!(
                    "cell data `{name}`: {format} stores the cell tags under that name"
                ));
            } else if name.is_empty() {
                report.drop(format!("a cell data array without a name: {format} needs one"));
            } else {
                cell_arrays.push((name.as_str(), a.expanded()));
            }
        }
        let mut point_arrays: Vec<(&str, Cow<'_, DataArray>)> =
            mesh.point_data.iter().map(|(k, v)| (k.as_str(), v.expanded())).collect();
        if point_arrays.iter().any(|(k, _)| k.is_empty()) {
            report.drop(format!("a point data array without a name: {format} needs one"));
            point_arrays.retain(|(k, _)| !k.is_empty());
        }
        let tensors: Vec<&str> =
            point_arrays.iter().filter(|(_, a)| a.components == 9).map(|(k, _)| *k).collect();
        let tensor = ["size_tensor", "metric"]
            .into_iter()
            .find(|n| tensors.contains(n))
            .or(tensors.first().copied());
        let mut names = Vec::new();
        let mut seen = std::collections::BTreeSet::new();
        for (&(dim, tag), name) in &mesh.tag_names {
            if name.is_empty() {
                report.drop(format!("the empty name of tag ({dim}, {tag}): {format} needs a name"));
            } else if seen.insert(name.as_str()) {
                names.push((name.as_str(), tag, dim));
            } else {
                report.drop(format!("tag name `{name}` of ({dim}, {tag}): {format} keeps one tag per name and it is already used"));
            }
        }
        if !mesh.entities.is_empty() {
            report.drop(format!(
                "entity table ({} entities): {format} has no place for it",
                mesh.entities.len()
            ));
        }
        for (name, set) in &mesh.point_sets {
            report.drop(format!(
                "point set `{name}` ({} points): {format} has no point sets",
                set.len()
            ));
        }
        for (name, set) in &mesh.cell_sets {
            report.drop(format!(
                "cell set `{name}` ({} cells): {format} has no cell sets",
                set.len()
            ));
        }
        if !mesh.holes.is_empty() || !mesh.regions.is_empty() {
            report.drop(format!(
                "{} holes and {} region seeds: {format} has no place for them",
                mesh.holes.len(),
                mesh.regions.len()
            ));
        }
        Plan { physical, geometrical, cell_arrays, point_arrays, tensor, names, report }
    }
}

/// Appends a float as the shortest decimal that reads back exactly; integral values
/// (most tensor entries are 0 or 1) take the faster integer path, which reads back
/// just as exactly and is shorter (`0` rather than `0.0`).
#[inline]
pub(crate) fn push_num(out: &mut Vec<u8>, v: f64) {
    if !v.is_finite() {
        // As VTK writes them, and reads them back (not ryu's `NaN`).
        let s: &[u8] = if v.is_nan() {
            b"nan"
        } else if v > 0.0 {
            b"inf"
        } else {
            b"-inf"
        };
        out.extend_from_slice(s);
    } else if v.fract() == 0.0 && v.abs() < 1.0e15 && !(v == 0.0 && v.is_sign_negative()) {
        crate::text::push_int(out, v as i64);
    } else {
        crate::text::push_f64(out, v);
    }
}

/// Appends `v` as fixed-width binary values: the buffer grows once and the values are
/// converted in place, a loop the compiler turns into plain (or byte-swapping) copies.
#[inline]
pub(crate) fn put<T: Copy, const W: usize>(out: &mut Vec<u8>, v: &[T], f: impl Fn(T) -> [u8; W]) {
    // Runs of 16 values assembled on the stack and appended whole: one capacity check a
    // run, and no zeroing pass first (growing the output with zeros, then overwriting
    // them, wrote every byte of a large array twice).
    out.reserve(v.len() * W);
    let mut run = [[0u8; W]; 16];
    let mut runs = v.chunks_exact(16);
    for r in &mut runs {
        for (b, &x) in run.iter_mut().zip(r) {
            *b = f(x);
        }
        out.extend_from_slice(run.as_flattened());
    }
    for &x in runs.remainder() {
        out.extend_from_slice(&f(x));
    }
}

/// Offsets (`ncells + 1`, from 0) and connectivity of a mesh in block order.
pub(crate) fn offsets(mesh: &TaggedMesh) -> Vec<u64> {
    let mut offs = Vec::with_capacity(mesh.num_cells() + 1);
    let mut o = 0u64;
    offs.push(0);
    for b in &mesh.blocks {
        let k = b.kind.nodes_per_cell() as u64;
        for _ in 0..b.len() {
            o += k;
            offs.push(o);
        }
    }
    offs
}

/// Number of worker threads for block compression: the machine's, at most 8.
pub(crate) fn threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get()).min(8)
}
