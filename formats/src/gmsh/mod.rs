//! Gmsh MSH files, versions 2.2 and 4.1, ASCII and binary: reader and writer.
//!
//! Source: the Gmsh reference manual, section "MSH file format" (4.1) and "MSH file
//! format version 2 (Legacy)" (<https://gmsh.info/doc/texinfo/gmsh.html#MSH-file-format>),
//! checked against Gmsh's own code (`src/geo/GModelIO_MSH2.cpp`, `GModelIO_MSH4.cpp`,
//! `src/post/PViewDataGModelIO_MSH.cpp`, `PViewIO.cpp`).
//!
//! Hand-written rather than built on `mshio` (the crate the design names for 4.1),
//! after measuring it (`bench_against_mshio` in `formats/tests/gmsh.rs`, release, on a
//! 4.1 file of 751,689 nodes and 1,499,912 triangles): it parses ASCII in 0.78 s where
//! this reader builds the whole mesh in 0.20 s, and binary in 0.33 s against 0.06 s;
//! its errors carry no line (a letter in a node tag reads "An invalid entity tag value
//! was encountered" and a hex dump; here "25: expected node tag (a non-negative
//! integer), found `x`"); it
//! panics (`unimplemented!`) on a binary header whose size_t is 3 bytes; it refuses
//! parametric nodes ("not supported yet"); and it reads neither `$PhysicalNames` nor
//! `$NodeData`, nor MSH 2.2, so a second parser would have been needed beside it anyway.
//!
//! Reading:
//! - `$MeshFormat` 2.x or 4.1, ASCII (`0`) or binary (`1`); binary files must be
//!   little-endian (a byte-swapped endianness marker is an error naming its offset);
//!   4.1 binary takes `size_t` of 4 or 8 bytes;
//! - `$PhysicalNames` → [`TaggedMesh::tag_names`];
//! - 4.1 `$Entities` → [`TaggedMesh::entities`] (every entity, with its physical tags);
//!   the physical tag of a cell is the first physical tag of its entity (0 when none
//!   or without `$Entities`, as for Gmsh: such a file has no groups), its geometrical
//!   tag the entity tag; the cells of a group named [`UNTAGGED`] are read as untagged
//!   (tag 0, see below);
//! - `$Nodes` (and 2.x `$ParametricNodes`): parametric coordinates are read past;
//!   nodes no element uses are kept. Points are ordered by node tag (the file's order
//!   when tags ascend, as Gmsh writes them); tags may be sparse: they are looked up in
//!   a dense table when the largest tag is within 4x the node count, else in a sorted
//!   table — never a table sized by an arbitrary largest tag;
//! - `$Elements` of the kinds [`CellKind::from_gmsh_type`] knows; any other type (a
//!   tetrahedron, a third-order triangle...) is an error that names it. Cells are
//!   ordered by element tag (file order for Gmsh's files). 2.x elements carry physical
//!   and elementary tags; further (partition) tags are read past. Gmsh 2.2 writes an
//!   element once per physical group of its entity: such consecutive copies are read
//!   as one cell, and their groups listed in `entities[(dim, elementary)]` (the only
//!   entries a 2.x file gives that table) second-order cells (`gmsh -2 -order 2`) are read as
//!   the linear cells of their corners, and the nodes only they use beyond their corners
//!   (mid-edge, mid-face) are dropped with their point data (`linear.rs`: smartmesh is a
//!   linear tool);
//! - `$NodeData`, `$ElementData` (→ point and cell data named after the view's first
//!   string tag) and `$ElementNodeData` (→ cell data with components × nodes values per
//!   cell, padded with NaN for cells with fewer nodes). When a view appears with several
//!   time steps, the last section in the file wins; sections of the same step (a
//!   partitioned view) are merged. Items a view does not cover are NaN;
//! - `$Comments`, `$Periodic`, `$GhostElements`, `$Parametrizations`,
//!   `$PartitionedEntities`, `$InterpolationScheme`, Gmsh's `$Edges`/`$Faces`, and any
//!   section the format does not define (`$Comment`, `$Foo`: Gmsh's documentation says
//!   readers ignore them, and Gmsh and meshio do) are skipped up to their `$End` line,
//!   which must be there.
//!
//! Writing ([`crate::WriteOptions::gmsh_version`], [`crate::WriteOptions::binary`]):
//! - 4.1: `$PhysicalNames`, `$Entities` (one entity per dimension and geometrical tag,
//!   with the physical tags of [`TaggedMesh::entities`] where it lists them; cells of
//!   one entity with different physical tags are split onto new entities, which the
//!   report says), `$Nodes` in entity blocks (a node goes to the lowest-dimensional
//!   entity using it; nodes no cell uses go to the first entity of the highest
//!   dimension, so Gmsh keeps them), `$Elements` by entity and type, node and element
//!   tags = index + 1;
//! - 2.2: the same with a physical and an elementary tag on each element, written once
//!   per physical group where `entities` lists several, as Gmsh does;
//! - in both, when some cells have a physical tag, the cells of dimension `d` without
//!   one are written in a group of their own, numbered one above the largest physical
//!   tag of dimension `d` and named [`UNTAGGED`] (`untagged.rs`: Gmsh keeps only the
//!   cells of physical groups, meshio needs a group on every block); the report says so;
//! - each point array as `$NodeData`, each cell array as `$ElementData` (tensors as 9
//!   row-major components, Gmsh's layout); non-finite items are left out (read back as
//!   missing, NaN). What MSH cannot hold (point and cell sets, PSLG holes and regions,
//!   quotes in names...) is listed in the [`WriteReport`]. Same mesh, same bytes.
//!
//! Not supported: MSH 1, 3 and 4.0, big-endian binary files, 3D and third-order
//! elements, partitioned entities (their cells are read without physical tags),
//! interpolation schemes.
//!
//! Points keep the three coordinates MSH stores; `coordinate_dim` is 3 when some z is
//! not 0, else 2.
//!
//! Cost: one pass over the bytes, O(n) but for files whose tags are out of order
//! (sorted in runs). ASCII numbers go through a small scanner for plain digits and
//! floats, with [`crate::text::Tokens`] behind it for anything else and for errors;
//! binary arrays through `chunks_exact` + `from_le_bytes`. Writing fills one pre-sized
//! buffer with `text::push_f64` / `push_int` numbers.

mod linear;
mod msh2;
mod msh4;
mod untagged;

pub use untagged::UNTAGGED;

use std::collections::BTreeMap;

use crate::text::{self, Tokens};
use crate::{
    CellKind, DataArray, Error, ErrorKind, GmshVersion, NodeIndex, Position, ReadContext, Result,
    TaggedMesh, WriteOptions, WriteReport, Written, MAX_POINTS,
};

/// Reads an MSH 2.x or 4.1 file, ASCII or binary.
pub fn read(bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    let mut r = Reader::new(bytes);
    r.read_mesh_format()?;
    while let Some(tok) = r.c.t.next() {
        let at = r.c.here_before(tok.len());
        if tok.first() != Some(&b'$') || tok.len() < 2 {
            return Err(Error {
                path: None,
                at: Some(at),
                kind: ErrorKind::Expected {
                    expected: "a section header such as `$Nodes`".into(),
                    found: show(tok),
                },
            });
        }
        let name = &tok[1..];
        match name {
            b"PhysicalNames" => r.read_physical_names()?,
            b"Entities" if r.v4 => msh4::read_entities(&mut r)?,
            b"Nodes" if r.v4 => msh4::read_nodes(&mut r, at)?,
            b"Elements" if r.v4 => msh4::read_elements(&mut r)?,
            b"Nodes" => msh2::read_nodes(&mut r, at, false)?,
            b"ParametricNodes" if !r.v4 => msh2::read_nodes(&mut r, at, true)?,
            b"Elements" => msh2::read_elements(&mut r)?,
            b"NodeData" => r.read_view(ViewKind::Node)?,
            b"ElementData" => r.read_view(ViewKind::Element)?,
            b"ElementNodeData" => r.read_view(ViewKind::ElementNode)?,
            // Sections Gmsh defines that carry nothing a TaggedMesh holds. A 2.x file may
            // hold MSH3-style `$Entities` (Gmsh's Mesh.SaveTopology).
            b"Comments"
            | b"Periodic"
            | b"GhostElements"
            | b"Parametrizations"
            | b"PartitionedEntities"
            | b"InterpolationScheme"
            | b"Edges"
            | b"Faces"
            | b"Entities" => r.skip_section(name, at)?,
            b"MeshFormat" => {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Inconsistent("a second $MeshFormat section".into()),
                })
            }
            _ if name.starts_with(b"End") => {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Expected {
                        expected: "a section header such as `$Nodes`".into(),
                        found: format!("{}, which closes no open section", show(tok)),
                    },
                })
            }
            // Gmsh's format documentation: "any section with an unrecognized header is
            // simply ignored" (`$Comment`, a tool's own section); Gmsh and meshio skip it.
            _ => r.skip_section(name, at)?,
        }
    }
    r.finish()
}

/// Writes MSH 4.1 or 2.2 (per `opts.gmsh_version`), ASCII or binary (`opts.binary`).
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    if let Some(p) = mesh.validate().into_iter().next() {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "Gmsh MSH",
            reason: p.to_string(),
        }));
    }
    write_validated(mesh, opts)
}

/// [`write`] of a mesh that [`TaggedMesh::validate`] found without problems (as
/// `write_bytes` checks first, with the same error): not checked again.
pub(crate) fn write_validated(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let mut report = WriteReport::default();
    // Tags in MSH binary data sections and 2.2 elements are C ints.
    let n_cells = mesh.num_cells();
    if mesh.points.len() >= i32::MAX as usize || n_cells >= (i32::MAX / 2) as usize {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "Gmsh MSH",
            reason: "more nodes or elements than MSH's 32-bit tags can number".into(),
        }));
    }
    let grouped = untagged::grouped(mesh, &mut report);
    let mut out = Vec::with_capacity(estimate_size(mesh, opts.binary));
    match opts.gmsh_version {
        GmshVersion::V41 => msh4::write(&grouped, opts.binary, &mut out, &mut report)?,
        GmshVersion::V22 => msh2::write(&grouped, opts.binary, &mut out, &mut report)?,
    }
    report_unheld(mesh, &mut report);
    Ok(Written { main: out, siblings: Vec::new(), report })
}

fn estimate_size(mesh: &TaggedMesh, binary: bool) -> usize {
    let nodes: usize = mesh.blocks.iter().map(|b| b.nodes.len() + b.len()).sum();
    let data: usize = mesh
        .point_data
        .values()
        .chain(mesh.cell_data.values())
        .map(|a| a.len() * (a.expanded_components() + 1))
        .sum();
    if binary {
        mesh.points.len() * 40 + nodes * 8 + data * 8 + 4096
    } else {
        mesh.points.len() * 64 + nodes * 9 + data * 22 + 4096
    }
}

/// What MSH has no place for.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    for (name, set) in &mesh.point_sets {
        report
            .drop(format!("point set `{name}` ({} points): Gmsh MSH has no point sets", set.len()));
    }
    for (name, set) in &mesh.cell_sets {
        report.drop(format!("cell set `{name}` ({} cells): Gmsh MSH has no cell sets", set.len()));
    }
    if !mesh.holes.is_empty() {
        report.drop(format!(
            "{} hole point(s) of the planar straight-line graph: Gmsh MSH holds none",
            mesh.holes.len()
        ));
    }
    if !mesh.regions.is_empty() {
        report.drop(format!(
            "{} region seed(s) of the planar straight-line graph: Gmsh MSH holds none",
            mesh.regions.len()
        ));
    }
}

// ---------------------------------------------------------------------------------
// Reading: the cursor

/// A cursor that reads text tokens and binary arrays from the same bytes, and names
/// lines in ASCII files and byte offsets in binary ones.
pub(super) struct Cursor<'a> {
    /// Tokens over `full[base..]`.
    pub t: Tokens<'a>,
    full: &'a [u8],
    /// 0 in ASCII files; in binary ones, where `t` was last restarted, so that moving
    /// past binary data costs nothing (lines are not counted there).
    base: usize,
    pub binary: bool,
}

pub(super) fn show(tok: &[u8]) -> String {
    let s = String::from_utf8_lossy(&tok[..tok.len().min(40)]).into_owned();
    if tok.len() > 40 {
        format!("`{s}…`")
    } else {
        format!("`{s}`")
    }
}

impl<'a> Cursor<'a> {
    fn new(full: &'a [u8]) -> Self {
        Cursor { t: Tokens::new(full), full, base: 0, binary: false }
    }

    /// Byte offset of the cursor in the file.
    #[inline]
    pub fn pos(&self) -> usize {
        self.base + self.t.pos()
    }

    /// Moves forward to byte offset `abs`.
    #[inline]
    pub fn seek(&mut self, abs: usize) {
        let abs = abs.min(self.full.len());
        if self.binary {
            self.base = abs;
            self.t = Tokens::new(&self.full[abs..]);
        } else {
            self.t.seek(abs.saturating_sub(self.base));
        }
    }

    /// The bytes not read yet.
    pub fn remaining(&self) -> &'a [u8] {
        &self.full[self.pos()..]
    }

    /// Where the cursor is: a byte offset in binary files, a line in ASCII ones.
    pub fn here(&self) -> Position {
        if self.binary {
            Position::Byte(self.pos() as u64)
        } else {
            Position::Line(self.t.line())
        }
    }

    /// Where the next token starts (in a binary file, where the cursor is: binary data
    /// must not be skipped as if it were white space).
    pub fn mark(&mut self) -> Position {
        if !self.binary {
            self.t.skip_space();
        }
        self.here()
    }

    /// Where the token of `len` bytes just read started.
    pub fn here_before(&self, len: usize) -> Position {
        if self.binary {
            Position::Byte(self.pos().saturating_sub(len) as u64)
        } else {
            Position::Line(self.t.line())
        }
    }

    pub fn err(&self, kind: ErrorKind) -> Error {
        Error { path: None, at: Some(self.here()), kind }
    }

    pub fn err_at(&self, at: Position, kind: ErrorKind) -> Error {
        Error { path: None, at: Some(at), kind }
    }

    pub fn byte_err(&self, offset: usize, kind: ErrorKind) -> Error {
        Error::at_byte(offset as u64, kind)
    }

    /// Runs a text read; in a binary file its error is placed at the token's offset.
    #[inline]
    fn text<T>(&mut self, f: impl FnOnce(&mut Tokens<'a>) -> Result<T>) -> Result<T> {
        if self.binary {
            self.t.skip_space();
            let start = self.pos();
            f(&mut self.t).map_err(|mut e| {
                e.at = Some(Position::Byte(start as u64));
                e
            })
        } else {
            f(&mut self.t)
        }
    }

    #[inline]
    pub fn usize(&mut self, what: &str) -> Result<usize> {
        self.text(|t| t.usize(what))
    }

    #[inline]
    pub fn u64(&mut self, what: &str) -> Result<u64> {
        self.text(|t| t.usize(what)).map(|v| v as u64)
    }

    #[inline]
    pub fn i32(&mut self, what: &str) -> Result<i32> {
        self.text(|t| t.i32(what))
    }

    #[inline]
    pub fn i64(&mut self, what: &str) -> Result<i64> {
        self.text(|t| t.i64(what))
    }

    #[inline]
    pub fn f64(&mut self, what: &str) -> Result<f64> {
        self.text(|t| t.f64(what))
    }

    /// A count from a text header, checked against the bytes left.
    pub fn count(&mut self, what: &str, min_bytes_per_item: usize) -> Result<usize> {
        self.text(|t| t.count(what, min_bytes_per_item))
    }

    pub fn token(&mut self, what: &str) -> Result<&'a [u8]> {
        self.text(|t| t.token(what))
    }

    /// The `$End...` line of section `name`.
    pub fn expect_end(&mut self, name: &str) -> Result<()> {
        let end = format!("$End{name}");
        match self.t.next() {
            Some(tok) if tok == end.as_bytes() => Ok(()),
            Some(tok) => {
                let at = self.here_before(tok.len());
                Err(self.err_at(
                    at,
                    ErrorKind::Expected {
                        expected: format!("`{end}` (or fewer items than the section holds)"),
                        found: show(tok),
                    },
                ))
            }
            None => {
                Err(self.err(ErrorKind::UnexpectedEof { context: format!("expected `{end}`") }))
            }
        }
    }

    /// Ends a text line before binary data: the rest of the line must be blank, and the
    /// cursor moves just past its newline.
    pub fn end_text_line(&mut self) -> Result<()> {
        let at = self.here();
        let rest = self.t.rest_of_line();
        if rest.is_empty() {
            Ok(())
        } else {
            Err(self.err_at(
                at,
                ErrorKind::Expected {
                    expected: "the end of the line before binary data".into(),
                    found: show(rest),
                },
            ))
        }
    }

    /// The next `n` bytes of binary data.
    #[inline]
    pub fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8]> {
        let pos = self.pos();
        let data = self.full;
        if data.len() - pos < n {
            return Err(self.byte_err(
                pos,
                ErrorKind::UnexpectedEof {
                    context: format!("{what}: {n} bytes needed, {} left", data.len() - pos),
                },
            ));
        }
        self.seek(pos + n);
        Ok(&data[pos..pos + n])
    }

    /// `n * size` bytes, with the product checked.
    pub fn take_array(&mut self, n: usize, size: usize, what: &str) -> Result<&'a [u8]> {
        let pos = self.pos();
        let total = n.checked_mul(size).ok_or_else(|| {
            self.byte_err(
                pos,
                ErrorKind::ImplausibleCount {
                    what: what.into(),
                    count: n as u64,
                    limit: "the byte count overflows".into(),
                },
            )
        })?;
        self.take(total, what)
    }

    #[inline]
    pub fn bin_i32(&mut self, what: &str) -> Result<i32> {
        let b = self.take(4, what)?;
        Ok(le_i32(b))
    }

    /// A binary `size_t` of `st` bytes (4 or 8).
    #[inline]
    pub fn bin_size(&mut self, st: usize, what: &str) -> Result<u64> {
        let b = self.take(st, what)?;
        Ok(le_size(b, st))
    }

    /// A binary count, checked against the bytes left.
    pub fn bin_count(&mut self, st: usize, what: &str, min_bytes_per_item: usize) -> Result<usize> {
        let pos = self.pos();
        let n = self.bin_size(st, what)?;
        let left = self.full.len() - self.pos();
        let n = usize::try_from(n).unwrap_or(usize::MAX);
        text::check_count(n, left, min_bytes_per_item, what).map_err(|k| self.byte_err(pos, k))
    }

    /// A binary double that must be finite.
    pub fn bin_f64(&mut self, what: &str) -> Result<f64> {
        let pos = self.pos();
        let v = le_f64(self.take(8, what)?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self
                .byte_err(pos, ErrorKind::NonFinite { what: what.into(), value: v.to_string() }))
        }
    }
}

/// A quick scanner for the hot loops of the ASCII readers: plain unsigned integers and
/// finite floats followed by white space. Anything else, and every error, goes back to
/// [`Tokens`], which parses or explains it; the `Cursor` is kept at the scanner's last
/// synchronisation point, so that its line count stays right.
pub(super) struct Scan<'a> {
    d: &'a [u8],
    pos: usize,
    line: u64,
    /// Start of the token being read, where `Tokens` resumes after a miss.
    start: usize,
}

impl Scan<'_> {
    #[inline(always)]
    fn skip_space(&mut self) {
        while let Some(&c) = self.d.get(self.pos) {
            match c {
                b' ' | b'\t' | b'\r' => self.pos += 1,
                b'\n' => {
                    self.line += 1;
                    self.pos += 1;
                }
                _ => break,
            }
        }
        self.start = self.pos;
    }

    #[inline(always)]
    fn ends_token(&self, at: usize) -> bool {
        self.d.get(at).map_or(true, |&c| matches!(c, b' ' | b'\t' | b'\r' | b'\n'))
    }

    #[inline(always)]
    fn uint(&mut self) -> Option<u64> {
        self.skip_space();
        let mut v: u64 = 0;
        let mut p = self.pos;
        while let Some(&c) = self.d.get(p) {
            let digit = c.wrapping_sub(b'0');
            if digit > 9 {
                break;
            }
            v = v.wrapping_mul(10).wrapping_add(digit as u64);
            p += 1;
        }
        // 19 digits cannot overflow a u64; longer numbers go to the careful parser.
        if p == self.pos || p - self.pos > 19 || !self.ends_token(p) {
            return None;
        }
        self.pos = p;
        Some(v)
    }

    #[inline(always)]
    fn float(&mut self) -> Option<f64> {
        self.skip_space();
        let (v, n) = fast_float2::parse_partial::<f64, _>(&self.d[self.pos..]).ok()?;
        if n == 0 || !v.is_finite() || !self.ends_token(self.pos + n) {
            return None;
        }
        self.pos += n;
        Some(v)
    }

    /// Bytes not read yet.
    pub fn bytes_left(&self) -> usize {
        self.d.len() - self.pos
    }

    /// The line of the last number read.
    #[inline]
    pub fn line(&self) -> u64 {
        self.line
    }

    /// Whether only blanks remain on the current line.
    #[inline]
    pub fn at_line_end(&self) -> bool {
        let mut p = self.pos;
        while let Some(&c) = self.d.get(p) {
            match c {
                b' ' | b'\t' | b'\r' => p += 1,
                b'\n' => return true,
                _ => return false,
            }
        }
        true
    }
}

impl<'a> Cursor<'a> {
    /// A scanner at the cursor.
    pub fn scan(&self) -> Scan<'a> {
        Scan { d: self.full, pos: self.pos(), line: self.t.line(), start: self.pos() }
    }

    /// Moves the cursor to where the scanner is (before an error or a text read).
    pub fn unscan(&mut self, s: &Scan<'a>) {
        self.seek(s.pos);
    }

    #[inline(always)]
    pub fn scan_u64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<u64> {
        match s.uint() {
            Some(v) => Ok(v),
            None => self.slow_u64(s, what),
        }
    }

    #[cold]
    #[inline(never)]
    fn slow_u64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<u64> {
        self.seek(s.start);
        let v = self.u64(what)?;
        *s = self.scan();
        Ok(v)
    }

    #[inline(always)]
    pub fn scan_i64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<i64> {
        match s.uint() {
            Some(v) if v <= i64::MAX as u64 => Ok(v as i64),
            _ => self.slow_i64(s, what),
        }
    }

    #[cold]
    #[inline(never)]
    fn slow_i64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<i64> {
        self.seek(s.start);
        let v = self.i64(what)?;
        *s = self.scan();
        Ok(v)
    }

    #[inline(always)]
    pub fn scan_f64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<f64> {
        match s.float() {
            Some(v) => Ok(v),
            None => self.slow_f64(s, what),
        }
    }

    #[cold]
    #[inline(never)]
    fn slow_f64(&mut self, s: &mut Scan<'a>, what: &str) -> Result<f64> {
        self.seek(s.start);
        let v = self.f64(what)?;
        *s = self.scan();
        Ok(v)
    }
}

#[inline]
pub(super) fn le_i32(b: &[u8]) -> i32 {
    i32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

#[inline]
pub(super) fn le_f64(b: &[u8]) -> f64 {
    f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
}

#[inline(always)]
pub(super) fn le_size(b: &[u8], st: usize) -> u64 {
    if st == 8 {
        u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]])
    } else {
        u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64
    }
}

// ---------------------------------------------------------------------------------
// Reading: tag tables

const NONE: usize = usize::MAX;

/// Tag → index: nothing stored when the tags are `first, first + 1, ...` for values
/// `0, 1, ...` (how Gmsh numbers), a dense table when they are nearly contiguous, a
/// sorted one otherwise.
pub(super) enum TagMap {
    Range { first: u64, len: usize },
    Dense(Vec<usize>),
    Sparse(Vec<(u64, usize)>),
}

impl TagMap {
    /// The map of `(tag, value)` pairs; `Err(tag)` names a tag given twice.
    fn build<I: Iterator<Item = (u64, usize)> + Clone>(
        items: I,
    ) -> std::result::Result<TagMap, u64> {
        let mut first = None;
        let (count, max, range) = items.clone().fold((0usize, 0u64, true), |(c, m, r), (t, v)| {
            let f = *first.get_or_insert(t);
            (c + 1, m.max(t), r && v == c && t.checked_sub(f) == Some(c as u64))
        });
        if range {
            return Ok(TagMap::Range { first: first.unwrap_or(1), len: count });
        }
        // Dense within a small multiple of the count: memory bounded by the file size.
        if max < (count as u64).saturating_mul(4).saturating_add(1024) {
            let mut table = vec![NONE; max as usize + 1];
            for (t, v) in items {
                let slot = &mut table[t as usize];
                if *slot != NONE {
                    return Err(t);
                }
                *slot = v;
            }
            Ok(TagMap::Dense(table))
        } else {
            let mut v: Vec<(u64, usize)> = items.collect();
            v.sort_unstable();
            if let Some(w) = v.windows(2).find(|w| w[0].0 == w[1].0) {
                return Err(w[0].0);
            }
            Ok(TagMap::Sparse(v))
        }
    }

    /// The position of node `tag` in a map of node positions, which
    /// [`Reader::take_node_map`] keeps below `MAX_POINTS`.
    #[inline]
    pub fn node(&self, tag: u64) -> Option<NodeIndex> {
        self.get(tag).map(|v| v as NodeIndex)
    }

    #[inline]
    pub fn get(&self, tag: u64) -> Option<usize> {
        match self {
            TagMap::Range { first, len } => {
                tag.checked_sub(*first).filter(|&d| d < *len as u64).map(|d| d as usize)
            }
            TagMap::Dense(t) => t.get(usize::try_from(tag).ok()?).copied().filter(|&v| v != NONE),
            TagMap::Sparse(v) => v.binary_search_by_key(&tag, |&(t, _)| t).ok().map(|i| v[i].1),
        }
    }
}

// ---------------------------------------------------------------------------------
// Reading: state shared by both versions

/// Element tags of a block: a range while they count up by one, as Gmsh writes them.
pub(super) enum TagList {
    Range { first: u64, len: usize },
    List(Vec<u64>),
}

impl TagList {
    pub fn new() -> Self {
        TagList::Range { first: 0, len: 0 }
    }

    #[inline(always)]
    pub fn push(&mut self, t: u64) {
        // The next tag of a range (the common case) here, anything else out of line.
        if let TagList::Range { first, len } = self {
            if *len > 0 && first.checked_add(*len as u64) == Some(t) {
                *len += 1;
                return;
            }
        }
        self.push_other(t);
    }

    #[inline(never)]
    fn push_other(&mut self, t: u64) {
        match self {
            TagList::Range { first, len } => {
                if *len == 0 {
                    *first = t;
                    *len = 1;
                } else if first.checked_add(*len as u64) == Some(t) {
                    *len += 1;
                } else {
                    let mut v: Vec<u64> = (0..*len as u64).map(|i| *first + i).collect();
                    v.push(t);
                    *self = TagList::List(v);
                }
            }
            TagList::List(v) => v.push(t),
        }
    }

    pub fn len(&self) -> usize {
        match self {
            TagList::Range { len, .. } => *len,
            TagList::List(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Room for `n` more tags once they are a list (a range needs none).
    pub fn reserve(&mut self, n: usize) {
        if let TagList::List(v) = self {
            v.reserve(n);
        }
    }

    /// Whether every tag is above the one before it.
    fn strictly_ascending(&self) -> bool {
        match self {
            TagList::Range { .. } => true,
            TagList::List(v) => v.windows(2).all(|w| w[0] < w[1]),
        }
    }

    #[inline]
    fn get(&self, i: usize) -> u64 {
        match self {
            TagList::Range { first, .. } => first + i as u64,
            TagList::List(v) => v[i],
        }
    }

    fn iter(&self) -> impl DoubleEndedIterator<Item = u64> + ExactSizeIterator + Clone + '_ {
        (0..self.len()).map(move |i| self.get(i))
    }

    fn contains(&self, t: u64) -> bool {
        match self {
            TagList::Range { first, len } => t.checked_sub(*first).is_some_and(|d| d < *len as u64),
            TagList::List(v) => v.contains(&t),
        }
    }

    /// The last tag if every tag is above `prev` and above the one before it.
    fn ascending_after(&self, prev: u64) -> Option<u64> {
        match self {
            TagList::Range { len: 0, .. } => Some(prev),
            TagList::Range { first, len } => (*first > prev).then(|| first + *len as u64 - 1),
            TagList::List(v) => {
                let mut p = prev;
                for &t in v {
                    if t <= p {
                        return None;
                    }
                    p = t;
                }
                Some(p)
            }
        }
    }
}

/// Elements of one kind as read, before they are put in tag order.
pub(super) struct RawBlock {
    pub kind: CellKind,
    pub at: Position,
    pub tags: TagList,
    /// Node positions in file order (indices into `Reader::points`).
    pub nodes: Vec<NodeIndex>,
    /// Per cell; empty for 4.1 blocks until `finish` fills them from the entity.
    pub physical: Vec<i32>,
    pub geometrical: Vec<i32>,
    /// 4.1: the `(dim, tag)` entity of the block.
    pub entity: Option<(u8, i32)>,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum ViewKind {
    Node,
    Element,
    ElementNode,
}

impl ViewKind {
    fn section(self) -> &'static str {
        match self {
            ViewKind::Node => "NodeData",
            ViewKind::Element => "ElementData",
            ViewKind::ElementNode => "ElementNodeData",
        }
    }
}

/// The targets of a view's entries in file order: `0, 1, 2, ...` as a count while they
/// are so (a view of every node in node order), a list otherwise.
struct Targets {
    identity: usize,
    /// Every target once they are not `0, 1, 2, ...`; empty until then.
    list: Vec<usize>,
    /// Room to make for the list when it is needed.
    hint: usize,
}

impl Targets {
    fn with_capacity(hint: usize) -> Self {
        Targets { identity: 0, list: Vec::new(), hint }
    }

    #[inline]
    fn push(&mut self, t: usize) {
        if self.list.is_empty() && t == self.identity {
            self.identity += 1;
        } else {
            if self.list.is_empty() {
                self.list.reserve(self.hint.max(self.identity + 1));
                self.list.extend(0..self.identity);
            }
            self.list.push(t);
        }
    }

    fn len(&self) -> usize {
        if self.list.is_empty() {
            self.identity
        } else {
            self.list.len()
        }
    }

    /// Whether the targets are `0, 1, 2, ..., len - 1`.
    fn is_identity(&self) -> bool {
        self.list.is_empty() || self.list.iter().enumerate().all(|(i, &t)| i == t)
    }

    fn iter(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.len()).map(move |i| if self.list.is_empty() { i } else { self.list[i] })
    }

    fn append(&mut self, other: &Targets) {
        for t in other.iter() {
            self.push(t);
        }
    }
}

/// Binary view entries of `N` values each (a 4-byte tag, then the values): the values
/// as one array, made in a single pass over the table, and each entry's target pushed
/// (a target that `map` lacks is not). Also the first entry whose tag `map` lacks or
/// whose values are not all finite, for the caller to report.
fn decode_entries<const N: usize>(
    table: &[u8],
    map: &TagMap,
    targets: &mut Targets,
) -> (Vec<f64>, Option<usize>) {
    let rec = 4 + 8 * N;
    let mut bad = None;
    let rows: Vec<[f64; N]> = table
        .chunks_exact(rec)
        .enumerate()
        .map(|(e, ch)| {
            let mut row = [0.0; N];
            let mut ok = true;
            for (j, x) in row.iter_mut().enumerate() {
                *x = le_f64(&ch[4 + 8 * j..12 + 8 * j]);
                ok &= x.is_finite();
            }
            match u64::try_from(le_i32(ch)).ok().and_then(|t| map.get(t)) {
                Some(t) => targets.push(t),
                None => ok = false,
            }
            if !ok && bad.is_none() {
                bad = Some(e);
            }
            row
        })
        .collect();
    (rows.into_flattened(), bad)
}

/// One post-processing view as read.
struct View {
    kind: ViewKind,
    name: String,
    /// Where its header is, for errors found when the array is built.
    at: Position,
    step: i64,
    ncomp: usize,
    /// Node positions (file order) or raw cell ids.
    targets: Targets,
    /// ElementNodeData: where each entry's values start in `values` (one more than
    /// `targets`); empty otherwise, every entry then has `ncomp` values.
    offsets: Vec<usize>,
    values: Vec<f64>,
}

pub(super) struct Reader<'a> {
    pub c: Cursor<'a>,
    pub v4: bool,
    /// Bytes of a binary `size_t` (4.1).
    pub size_t: usize,
    pub points: Vec<[f64; 3]>,
    /// Node tags in file order: a range while they count up by one.
    pub node_tags: TagList,
    /// First node index of each node block and where the block starts.
    pub node_blocks: Vec<(usize, Position)>,
    node_map: Option<TagMap>,
    pub raw: Vec<RawBlock>,
    pub n_raw_cells: usize,
    elem_map: Option<TagMap>,
    /// 2.2 copies of an element for another physical group: tag → raw cell id.
    pub aliases: Vec<(u64, usize)>,
    pub tag_names: BTreeMap<(u8, i32), String>,
    pub entities: BTreeMap<(u8, i32), Vec<i32>>,
    views: Vec<View>,
    view_count: usize,
}

impl<'a> Reader<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Reader {
            c: Cursor::new(bytes),
            v4: true,
            size_t: 8,
            points: Vec::new(),
            node_tags: TagList::new(),
            node_blocks: Vec::new(),
            node_map: None,
            raw: Vec::new(),
            n_raw_cells: 0,
            elem_map: None,
            aliases: Vec::new(),
            tag_names: BTreeMap::new(),
            entities: BTreeMap::new(),
            views: Vec::new(),
            view_count: 0,
        }
    }

    fn read_mesh_format(&mut self) -> Result<()> {
        let t = &mut self.c.t;
        match t.next() {
            Some(b"$MeshFormat") => {}
            Some(tok) if tok.starts_with(b"$NOD") || tok.starts_with(b"$NOE") => {
                return Err(self.c.err(ErrorKind::Unsupported("MSH version 1 (a file without $MeshFormat); save it as MSH 2.2 or 4.1 with Gmsh".into())))
            }
            Some(tok) => return Err(self.c.err(ErrorKind::Expected { expected: "`$MeshFormat` (a Gmsh MSH file starts with it)".into(), found: show(tok) })),
            None => return Err(self.c.err(ErrorKind::UnexpectedEof { context: "expected `$MeshFormat`; the file is empty".into() })),
        }
        let vtok = self.c.token("the MSH version number")?;
        let version = text::parse_f64(vtok).map_err(|_| {
            self.c.err(ErrorKind::Expected {
                expected: "the MSH version number".into(),
                found: show(vtok),
            })
        })?;
        self.v4 = if (version - 4.1).abs() < 1e-9 {
            true
        } else if (2.0..3.0).contains(&version) {
            false
        } else if (4.0..4.1).contains(&version) {
            return Err(self.c.err(ErrorKind::Unsupported(format!(
                "MSH version {} (smartmesh reads 2.2 and 4.1; save it again with Gmsh: -format msh41)",
                String::from_utf8_lossy(vtok)
            ))));
        } else {
            return Err(self.c.err(ErrorKind::Unsupported(format!(
                "MSH version {} (smartmesh reads 2.2 and 4.1)",
                String::from_utf8_lossy(vtok)
            ))));
        };
        let file_type = self.c.i64("the file type (0 for ASCII, 1 for binary)")?;
        if file_type != 0 && file_type != 1 {
            return Err(self.c.err(ErrorKind::Expected {
                expected: "the file type 0 (ASCII) or 1 (binary)".into(),
                found: format!("`{file_type}`"),
            }));
        }
        let data_size = self.c.i64("the data size")?;
        if file_type == 1 {
            if self.v4 && data_size != 8 && data_size != 4 {
                return Err(self.c.err(ErrorKind::Unsupported(format!(
                    "binary MSH 4.1 with a size_t of {data_size} bytes (4 or 8 expected)"
                ))));
            }
            if !self.v4 && data_size != 8 {
                return Err(self.c.err(ErrorKind::Unsupported(format!(
                    "binary MSH 2 with data size {data_size} (only 8, sizeof(double), is defined)"
                ))));
            }
            self.size_t = data_size as usize;
            self.c.end_text_line()?;
            self.c.binary = true;
            let pos = self.c.pos();
            let b = self.c.take(4, "the endianness marker (the integer 1)")?;
            let le = le_i32(b);
            if le != 1 {
                let kind = if i32::from_be_bytes([b[0], b[1], b[2], b[3]]) == 1 {
                    ErrorKind::Unsupported("a big-endian binary file (the endianness marker, the integer 1, is byte-swapped); smartmesh reads little-endian MSH files: convert it with Gmsh on a little-endian machine".into())
                } else {
                    ErrorKind::Expected {
                        expected: "the endianness marker, the integer 1 as 4 binary bytes".into(),
                        found: format!("bytes {:02x} {:02x} {:02x} {:02x}", b[0], b[1], b[2], b[3]),
                    }
                };
                return Err(self.c.byte_err(pos, kind));
            }
        }
        self.c.expect_end("MeshFormat")
    }

    fn read_physical_names(&mut self) -> Result<()> {
        let n = self.c.count("number of physical names", 7)?;
        for _ in 0..n {
            let dim = self.c.i32("physical group dimension")?;
            if !(0..=3).contains(&dim) {
                return Err(self.c.err(ErrorKind::Expected {
                    expected: "a physical group dimension 0 to 3".into(),
                    found: format!("`{dim}`"),
                }));
            }
            let tag = self.c.i32("physical tag")?;
            let at = self.c.here();
            let rest = self.c.t.rest_of_line();
            let name = quoted(rest).ok_or_else(|| {
                self.c.err_at(
                    at,
                    ErrorKind::Expected {
                        expected: "a name in double quotes".into(),
                        found: show(rest),
                    },
                )
            })?;
            self.tag_names.insert((dim as u8, tag), String::from_utf8_lossy(name).into_owned());
        }
        self.c.expect_end("PhysicalNames")
    }

    /// Skips a section smartmesh does not hold (or does not know), up to its `$End` line.
    fn skip_section(&mut self, name: &[u8], at: Position) -> Result<()> {
        let mut end = b"\n$End".to_vec();
        end.extend_from_slice(name);
        let rest = self.c.remaining();
        let mut from = 0;
        loop {
            let Some(i) = memchr::memmem::find(&rest[from..], &end) else {
                let n = String::from_utf8_lossy(name);
                return Err(self.c.err_at(
                    at,
                    ErrorKind::UnexpectedEof {
                        context: format!("section `${n}` has no `$End{n}` line"),
                    },
                ));
            };
            let after = from + i + end.len();
            // The marker must be the whole token (`$EndComments`, not `$EndCommentsX`).
            if rest.get(after).map_or(true, |c| c.is_ascii_whitespace()) {
                let pos = self.c.pos() + from + i + 1;
                self.c.seek(pos);
                self.c.t.next();
                return Ok(());
            }
            from = after;
        }
    }

    /// The node tag → node position table, built when first needed after nodes change.
    pub fn take_node_map(&mut self) -> Result<TagMap> {
        // Cells address points with 32-bit indices: past that, no file is read.
        if self.points.len() > MAX_POINTS {
            let at = self.node_blocks.first().map_or(Position::Byte(0), |b| b.1);
            return Err(Error {
                path: None,
                at: Some(at),
                kind: crate::mesh::past_max_points("nodes", self.points.len()),
            });
        }
        if let Some(m) = self.node_map.take() {
            return Ok(m);
        }
        if let TagList::Range { first, len } = self.node_tags {
            if len > 0 {
                // What `build` makes of tags `first, first + 1, ...`, without the pass.
                return Ok(TagMap::Range { first, len });
            }
        }
        TagMap::build(self.node_tags.iter().zip(0..)).map_err(|dup| self.duplicate_node(dup))
    }

    fn duplicate_node(&self, dup: u64) -> Error {
        // Where the second definition is: the block holding its last occurrence.
        let last = self.node_tags.iter().rposition(|t| t == dup).unwrap_or(0);
        let at = self
            .node_blocks
            .iter()
            .rev()
            .find(|(start, _)| *start <= last)
            .map_or(Position::Byte(0), |b| b.1);
        Error {
            path: None,
            at: Some(at),
            kind: ErrorKind::Inconsistent(format!(
                "node tag {dup} is defined twice (the second time in the node block here)"
            )),
        }
    }

    pub fn put_node_map(&mut self, m: TagMap) {
        self.node_map = Some(m);
    }

    pub fn nodes_changed(&mut self) {
        self.node_map = None;
    }

    pub fn push_raw(&mut self, b: RawBlock) {
        self.n_raw_cells += b.tags.len();
        self.elem_map = None;
        self.raw.push(b);
    }

    fn raw_tags(&self) -> impl Iterator<Item = (u64, usize)> + Clone + '_ {
        self.raw.iter().flat_map(|b| b.tags.iter()).zip(0..).chain(self.aliases.iter().copied())
    }

    fn take_elem_map(&mut self) -> Result<TagMap> {
        if let Some(m) = self.elem_map.take() {
            return Ok(m);
        }
        TagMap::build(self.raw_tags()).map_err(|dup| self.duplicate_element(dup))
    }

    fn duplicate_element(&self, dup: u64) -> Error {
        let at = self
            .raw
            .iter()
            .rev()
            .find(|b| b.tags.contains(dup))
            .map_or(Position::Byte(0), |b| b.at);
        Error {
            path: None,
            at: Some(at),
            kind: ErrorKind::Inconsistent(format!(
                "element tag {dup} is used twice (the second time in the element block here)"
            )),
        }
    }

    /// `$NodeData`, `$ElementData`, `$ElementNodeData` (same layout in 2.2 and 4.1).
    fn read_view(&mut self, kind: ViewKind) -> Result<()> {
        let section = kind.section();
        self.view_count += 1;
        // String tags, one per line: the first is the view's name.
        let n_str = self.c.count("number of string tags", 1)?;
        self.c.t.rest_of_line();
        let mut name = None;
        for i in 0..n_str {
            self.c.t.skip_space();
            let at = self.c.here();
            let line = self.c.t.rest_of_line();
            if line.is_empty() {
                return Err(self.c.err_at(
                    at,
                    ErrorKind::UnexpectedEof {
                        context: format!("expected string tag {} of ${section}", i + 1),
                    },
                ));
            }
            if i == 0 {
                let s = quoted(line).unwrap_or(line);
                name = Some(String::from_utf8_lossy(s).into_owned());
            }
        }
        let name = match name {
            Some(n) if !n.is_empty() => n,
            _ => format!("{section}{}", self.view_count),
        };
        let n_real = self.c.count("number of real tags", 2)?;
        for _ in 0..n_real {
            self.c.f64("real tag (the time value)")?;
        }
        let header_at = self.c.mark();
        let n_int = self.c.count("number of integer tags", 2)?;
        if n_int < 3 {
            return Err(self.c.err(ErrorKind::Expected {
                expected: format!("at least 3 integer tags in ${section} (time step, number of components, number of entries)"),
                found: n_int.to_string(),
            }));
        }
        let step = self.c.i64("time step (integer tag 1)")?;
        let ncomp = self.c.usize("number of components (integer tag 2)")?;
        if ncomp == 0 {
            return Err(self.c.err(ErrorKind::Expected {
                expected: "a number of components of at least 1 (1, 3 or 9)".into(),
                found: "0".into(),
            }));
        }
        // Smallest entry: a tag and its values, `1 0\n` in ASCII.
        let min_entry = if self.c.binary {
            ncomp.saturating_mul(8).saturating_add(4)
        } else {
            ncomp.saturating_mul(2).saturating_add(2)
        };
        let min_entry = if kind == ViewKind::ElementNode {
            min_entry.saturating_add(if self.c.binary { 4 } else { 2 })
        } else {
            min_entry
        };
        if ncomp > self.c.remaining().len() {
            return Err(self.c.err(ErrorKind::ImplausibleCount {
                what: format!("${section} number of components"),
                count: ncomp as u64,
                limit: "more than the bytes left in the file".into(),
            }));
        }
        let n = self.c.count("number of entries (integer tag 3)", min_entry)?;
        for _ in 3..n_int {
            self.c.i64("integer tag")?;
        }
        let map = match kind {
            ViewKind::Node => self.take_node_map()?,
            _ => self.take_elem_map()?,
        };
        let what = if kind == ViewKind::Node { "node" } else { "element" };
        let mut targets = Targets::with_capacity(n);
        let mut offsets = Vec::new();
        // Binary entries of 1, 3 or 9 values are decoded into an array of their own.
        let fixed = self.c.binary && kind != ViewKind::ElementNode && matches!(ncomp, 1 | 3 | 9);
        let mut values = if fixed { Vec::new() } else { Vec::with_capacity(n * ncomp) };
        if kind == ViewKind::ElementNode {
            offsets.reserve(n + 1);
            offsets.push(0);
        }
        let unknown = |c: &Cursor, at: Position, tag: i64| {
            c.err_at(at, ErrorKind::Inconsistent(format!("${section} `{name}` gives a value for {what} {tag}, which the mesh does not have")))
        };
        if self.c.binary && kind != ViewKind::ElementNode {
            // Fixed-size entries (a tag and `ncomp` doubles): the whole table is taken
            // at once and each value checked as it is converted.
            self.c.end_text_line()?;
            let rec = 4 + 8 * ncomp;
            let p0 = self.c.pos();
            let table =
                self.c.take_array(n, rec, "data entries (a 4-byte tag and 8-byte values each)")?;
            let mut bad = None;
            match ncomp {
                1 => (values, bad) = decode_entries::<1>(table, &map, &mut targets),
                3 => (values, bad) = decode_entries::<3>(table, &map, &mut targets),
                9 => (values, bad) = decode_entries::<9>(table, &map, &mut targets),
                _ => {}
            }
            // The first faulty entry, then (when the width is another) every entry checked
            // and converted one after the other; the errors are the same.
            let from = if fixed { bad.unwrap_or(n) } else { 0 };
            for (e, ch) in table.chunks_exact(rec).enumerate().skip(from) {
                let tag = le_i32(ch);
                let target = u64::try_from(tag).ok().and_then(|t| map.get(t)).ok_or_else(|| {
                    unknown(&self.c, Position::Byte((p0 + e * rec) as u64), tag as i64)
                })?;
                let mut finite = true;
                values.extend(ch[4..].chunks_exact(8).map(|c| {
                    let v = le_f64(c);
                    finite &= v.is_finite();
                    v
                }));
                if !finite {
                    let j =
                        ch[4..].chunks_exact(8).position(|c| !le_f64(c).is_finite()).unwrap_or(0);
                    let v = le_f64(&ch[4 + 8 * j..]);
                    return Err(self.c.byte_err(
                        p0 + e * rec + 4 + 8 * j,
                        ErrorKind::NonFinite {
                            what: format!("a value of `{name}`"),
                            value: v.to_string(),
                        },
                    ));
                }
                targets.push(target);
            }
        } else if self.c.binary {
            self.c.end_text_line()?;
            for _ in 0..n {
                let pos = self.c.pos();
                let tag = self.c.bin_i32("the tag of a data entry")?;
                let target = u64::try_from(tag)
                    .ok()
                    .and_then(|t| map.get(t))
                    .ok_or_else(|| unknown(&self.c, Position::Byte(pos as u64), tag as i64))?;
                let mult = if kind == ViewKind::ElementNode {
                    let p = self.c.pos();
                    let m = self.c.bin_i32("the number of nodes of an entry")?;
                    positive_mult(m as i64).ok_or_else(|| {
                        self.c.byte_err(
                            p,
                            ErrorKind::Expected {
                                expected: "a positive number of nodes per element".into(),
                                found: m.to_string(),
                            },
                        )
                    })?
                } else {
                    1
                };
                let k = ncomp * mult;
                let p = self.c.pos();
                let b = self.c.take_array(k, 8, "data values")?;
                for (j, ch) in b.chunks_exact(8).enumerate() {
                    let v = le_f64(ch);
                    if !v.is_finite() {
                        return Err(self.c.byte_err(
                            p + 8 * j,
                            ErrorKind::NonFinite {
                                what: format!("a value of `{name}`"),
                                value: v.to_string(),
                            },
                        ));
                    }
                    values.push(v);
                }
                targets.push(target);
                if kind == ViewKind::ElementNode {
                    offsets.push(values.len());
                }
            }
        } else {
            let mut s = self.c.scan();
            for _ in 0..n {
                let tag = self.c.scan_i64(&mut s, "the tag of a data entry")?;
                let line = Position::Line(s.line());
                let target = u64::try_from(tag)
                    .ok()
                    .and_then(|t| map.get(t))
                    .ok_or_else(|| unknown(&self.c, line, tag))?;
                let mult = if kind == ViewKind::ElementNode {
                    let m = self.c.scan_i64(&mut s, "the number of nodes of an entry")?;
                    positive_mult(m).ok_or_else(|| {
                        self.c.err_at(
                            line,
                            ErrorKind::Expected {
                                expected: "a positive number of nodes per element".into(),
                                found: m.to_string(),
                            },
                        )
                    })?
                } else {
                    1
                };
                let k = ncomp * mult;
                if k > s.bytes_left() / 2 + 1 {
                    return Err(self.c.err_at(
                        line,
                        ErrorKind::UnexpectedEof {
                            context: format!("entry of `{name}` with {k} values"),
                        },
                    ));
                }
                for _ in 0..k {
                    values.push(self.c.scan_f64(&mut s, "a data value")?);
                }
                targets.push(target);
                if kind == ViewKind::ElementNode {
                    offsets.push(values.len());
                }
            }
            self.c.unscan(&s);
        }
        match kind {
            ViewKind::Node => self.node_map = Some(map),
            _ => self.elem_map = Some(map),
        }
        self.c.expect_end(section)?;
        let view = View { kind, name, at: header_at, step, ncomp, targets, offsets, values };
        // The same view again: another partition of the same step is merged, another
        // step replaces it (the last step in the file is kept).
        if let Some(old) = self.views.iter_mut().find(|v| v.kind == kind && v.name == view.name) {
            if old.step == view.step {
                if old.ncomp != view.ncomp {
                    return Err(self.c.err_at(
                        header_at,
                        ErrorKind::Inconsistent(format!("view `{}` has {} components here and {} in an earlier section of the same step", view.name, view.ncomp, old.ncomp)),
                    ));
                }
                if kind == ViewKind::ElementNode {
                    let base = old.values.len();
                    old.offsets.extend(view.offsets[1..].iter().map(|o| o + base));
                }
                old.targets.append(&view.targets);
                old.values.extend(view.values);
            } else {
                *old = view;
            }
        } else {
            self.views.push(view);
        }
        Ok(())
    }

    /// Puts points in node-tag order and cells in element-tag order, resolves 4.1
    /// physical tags and builds the data arrays.
    fn finish(mut self) -> Result<TaggedMesh> {
        let mut mesh = TaggedMesh::new();
        mesh.tag_names = std::mem::take(&mut self.tag_names);

        // Points in ascending node-tag order; `node_rank[file position]` is the index.
        let node_rank: Option<Vec<usize>> = if self.node_tags.strictly_ascending() {
            mesh.points = std::mem::take(&mut self.points);
            None
        } else {
            let mut runs = Vec::new();
            runs_of(self.node_tags.iter(), 0, &mut runs);
            let runs = sorted_runs(runs).map_err(|dup| self.duplicate_node(dup))?;
            let mut rank = vec![0; self.points.len()];
            mesh.points.reserve(self.points.len());
            for &(_, pos, len) in &runs {
                for (j, r) in rank[pos..pos + len].iter_mut().enumerate() {
                    *r = mesh.points.len() + j;
                }
                mesh.points.extend_from_slice(&self.points[pos..pos + len]);
            }
            Some(rank)
        };

        // Physical tags of 4.1 blocks: the first physical tag of the entity.
        for b in &mut self.raw {
            if let Some(e) = b.entity {
                let p = self.entities.get(&e).and_then(|v| v.first()).copied().unwrap_or(0);
                b.physical = vec![p; b.tags.len()];
            }
            if let Some(rank) = &node_rank {
                for v in &mut b.nodes {
                    *v = rank[*v as usize] as NodeIndex;
                }
            }
        }

        // Cells in ascending element-tag order; `cell_rank[raw id]` is the index.
        let ascending =
            self.raw.iter().try_fold(0u64, |prev, b| b.tags.ascending_after(prev)).is_some();
        let cell_rank: Option<Vec<usize>> = if ascending {
            for b in std::mem::take(&mut self.raw) {
                match mesh.blocks.last_mut() {
                    Some(last) if last.kind == b.kind => {
                        last.nodes.extend_from_slice(&b.nodes);
                        last.physical.extend_from_slice(&b.physical);
                        last.geometrical.extend_from_slice(&b.geometrical);
                    }
                    _ => mesh.blocks.push(crate::CellBlock {
                        kind: b.kind,
                        nodes: b.nodes,
                        physical: b.physical,
                        geometrical: b.geometrical,
                    }),
                }
            }
            None
        } else {
            // Runs of consecutive tags within each block, put in tag order and copied.
            let mut runs = Vec::new();
            let mut starts = Vec::with_capacity(self.raw.len());
            let mut id = 0;
            for b in &self.raw {
                starts.push(id);
                match &b.tags {
                    TagList::Range { first, len } if *len > 0 => runs.push((*first, id, *len)),
                    TagList::Range { .. } => {}
                    TagList::List(v) => runs_of(v.iter().copied(), id, &mut runs),
                }
                id += b.tags.len();
            }
            let runs = sorted_runs(runs).map_err(|dup| self.duplicate_element(dup))?;
            // The rank of each cell is needed only to place element data.
            let mut rank = if self.views.iter().any(|v| v.kind != ViewKind::Node) {
                vec![0; id]
            } else {
                Vec::new()
            };
            let mut out = 0;
            for &(_, id, len) in &runs {
                let bi = starts.partition_point(|&s| s <= id) - 1;
                let b = &mut self.raw[bi];
                let (i, k) = (id - starts[bi], b.kind.nodes_per_cell());
                if i == 0
                    && len == b.tags.len()
                    && mesh.blocks.last().map(|l| l.kind) != Some(b.kind)
                {
                    // A whole block in place: moved, not copied.
                    let (nodes, physical, geometrical) = (
                        std::mem::take(&mut b.nodes),
                        std::mem::take(&mut b.physical),
                        std::mem::take(&mut b.geometrical),
                    );
                    mesh.blocks.push(crate::CellBlock {
                        kind: b.kind,
                        nodes,
                        physical,
                        geometrical,
                    });
                } else {
                    let dst = mesh.block_mut(b.kind);
                    dst.nodes.extend_from_slice(&b.nodes[i * k..(i + len) * k]);
                    dst.physical.extend_from_slice(&b.physical[i..i + len]);
                    dst.geometrical.extend_from_slice(&b.geometrical[i..i + len]);
                }
                if let Some(r) = rank.get_mut(id..id + len) {
                    for (j, r) in r.iter_mut().enumerate() {
                        *r = out + j;
                    }
                }
                out += len;
            }
            Some(rank)
        };

        // Data views.
        let n_points = mesh.points.len();
        let n_cells = mesh.num_cells();
        for v in std::mem::take(&mut self.views) {
            let (rank, n) = match v.kind {
                ViewKind::Node => (&node_rank, n_points),
                _ => (&cell_rank, n_cells),
            };
            let place = |t: usize| rank.as_ref().map_or(t, |r| r[t]);
            let width = if v.kind == ViewKind::ElementNode {
                v.offsets.windows(2).map(|w| w[1] - w[0]).max().unwrap_or(v.ncomp)
            } else {
                v.ncomp
            };
            // A view covering few items with many components must not make the array
            // of every item huge: at most about the file's size in values.
            let limit = self.c.full.len() + (1 << 20);
            if n.checked_mul(width).map_or(true, |t| t > limit) {
                return Err(self.c.err_at(
                    v.at,
                    ErrorKind::ImplausibleCount {
                        what: format!("view `{}` ({width} values for each of {n} items)", v.name),
                        count: (n as u64).saturating_mul(width as u64),
                        limit: format!(
                            "more values than the file's {} bytes justify",
                            self.c.full.len()
                        ),
                    },
                ));
            }
            let array = if v.kind == ViewKind::ElementNode {
                let mut values = vec![f64::NAN; n * width];
                for (e, t) in v.targets.iter().enumerate() {
                    let src = &v.values[v.offsets[e]..v.offsets[e + 1]];
                    let dst = place(t) * width;
                    values[dst..dst + src.len()].copy_from_slice(src);
                    values[dst + src.len()..dst + width].fill(f64::NAN);
                }
                DataArray::new(width, values)
            } else if rank.is_none() && v.targets.len() == n && v.targets.is_identity() {
                // One value per item in item order (what Gmsh and smartmesh write):
                // the values read are the array.
                DataArray::new(v.ncomp, v.values)
            } else {
                let k = v.ncomp;
                let mut values = vec![f64::NAN; n * k];
                for (e, t) in v.targets.iter().enumerate() {
                    let dst = place(t) * k;
                    values[dst..dst + k].copy_from_slice(&v.values[e * k..(e + 1) * k]);
                }
                DataArray::new(k, values)
            };
            match v.kind {
                ViewKind::Node => mesh.point_data.insert(v.name, array),
                _ => mesh.cell_data.insert(v.name, array),
            };
        }
        mesh.entities = std::mem::take(&mut self.entities);
        // MSH always stores z; a mesh is 2D when every z is 0 (the convention of the
        // other readers).
        mesh.coordinate_dim = if mesh.points.iter().all(|p| p[2] == 0.0) { 2 } else { 3 };
        untagged::ungroup(&mut mesh);
        linear::reduce(&mut mesh);
        Ok(mesh)
    }
}

/// Appends the maximal runs of consecutive tags `(first tag, first position, length)`
/// of `tags`, whose first is at position `pos0`.
fn runs_of(tags: impl Iterator<Item = u64>, pos0: usize, out: &mut Vec<(u64, usize, usize)>) {
    let start = out.len();
    for (i, t) in tags.enumerate() {
        if out.len() > start {
            if let Some(r) = out.last_mut() {
                if r.0.checked_add(r.2 as u64) == Some(t) {
                    r.2 += 1;
                    continue;
                }
            }
        }
        out.push((t, pos0 + i, 1));
    }
}

/// Runs in tag order; `Err(tag)` names a tag two runs share.
fn sorted_runs(
    mut runs: Vec<(u64, usize, usize)>,
) -> std::result::Result<Vec<(u64, usize, usize)>, u64> {
    runs.sort_unstable();
    match runs.windows(2).find(|w| w[0].0.saturating_add(w[0].2 as u64) > w[1].0) {
        Some(w) => Err(w[1].0),
        None => Ok(runs),
    }
}

fn positive_mult(m: i64) -> Option<usize> {
    (1..=1 << 16).contains(&m).then_some(m as usize)
}

/// The text between the first pair of double quotes of a line.
fn quoted(line: &[u8]) -> Option<&[u8]> {
    let a = memchr::memchr(b'"', line)?;
    let b = memchr::memchr(b'"', &line[a + 1..])?;
    Some(&line[a + 1..a + 1 + b])
}

/// The kind of a Gmsh element type, or an error that names the type.
pub(super) fn cell_kind(t: i32) -> std::result::Result<CellKind, ErrorKind> {
    CellKind::from_gmsh_type(t).ok_or_else(|| {
        let name = match t {
            4 => "4-node tetrahedron",
            5 => "8-node hexahedron",
            6 => "6-node prism",
            7 => "5-node pyramid",
            11 => "10-node second-order tetrahedron",
            12 => "27-node second-order hexahedron",
            13 => "18-node second-order prism",
            14 => "14-node second-order pyramid",
            17 => "20-node second-order hexahedron",
            18 => "15-node second-order prism",
            19 => "13-node second-order pyramid",
            20 => "9-node third-order incomplete triangle",
            21 => "10-node third-order triangle",
            22 => "12-node fourth-order incomplete triangle",
            23 => "15-node fourth-order triangle",
            24 => "15-node fifth-order incomplete triangle",
            25 => "21-node fifth-order triangle",
            26 => "4-node third-order line",
            27 => "5-node fourth-order line",
            28 => "6-node fifth-order line",
            29..=31 => "high-order tetrahedron",
            92 | 93 => "high-order hexahedron",
            _ => "an element type smartmesh does not know",
        };
        ErrorKind::Unsupported(format!(
            "Gmsh element type {t} ({name}): smartmesh is 2D and reads points, lines, triangles and quadrangles of order 1 and 2 (types 15, 1, 8, 2, 9, 3, 16, 10)"
        ))
    })
}

// ---------------------------------------------------------------------------------
// Writing: parts shared by both versions

pub(super) fn write_mesh_format(out: &mut Vec<u8>, version: &str, binary: bool) {
    out.extend_from_slice(b"$MeshFormat\n");
    out.extend_from_slice(version.as_bytes());
    out.extend_from_slice(if binary { b" 1 8\n" } else { b" 0 8\n" });
    if binary {
        out.extend_from_slice(&1i32.to_le_bytes());
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndMeshFormat\n");
}

/// A name as a quoted MSH string: Gmsh's reader stops at the next quote and at the end
/// of the line, and keeps 127 characters of a physical name.
fn quote_name(name: &str, what: &str, max_len: Option<usize>, report: &mut WriteReport) -> String {
    let mut s: String = name
        .chars()
        .map(|c| {
            if c == '"' {
                '\''
            } else if c == '\n' || c == '\r' {
                ' '
            } else {
                c
            }
        })
        .collect();
    if s != name {
        report.drop(format!("{what} `{name}`: double quotes and line breaks cannot stand in an MSH name; written as `{s}`"));
    }
    if let Some(max) = max_len {
        if s.len() > max {
            let mut cut = max;
            while !s.is_char_boundary(cut) {
                cut -= 1;
            }
            s.truncate(cut);
            report.drop(format!("{what} `{name}`: MSH names hold {max} characters; cut to `{s}`"));
        }
    }
    s
}

pub(super) fn write_physical_names(out: &mut Vec<u8>, mesh: &TaggedMesh, report: &mut WriteReport) {
    let names: Vec<_> = mesh.tag_names.iter().filter(|((d, _), _)| *d <= 3).collect();
    for ((d, t), n) in &mesh.tag_names {
        if *d > 3 {
            report.drop(format!(
                "name `{n}` of tag {t} of dimension {d}: MSH physical groups have dimension 0 to 3"
            ));
        }
    }
    if names.is_empty() {
        return;
    }
    out.extend_from_slice(b"$PhysicalNames\n");
    text::push_int(out, names.len());
    out.push(b'\n');
    for ((d, t), n) in names {
        let q = quote_name(n, "physical name", Some(127), report);
        text::push_int(out, *d);
        out.push(b' ');
        text::push_int(out, *t);
        out.extend_from_slice(b" \"");
        out.extend_from_slice(q.as_bytes());
        out.extend_from_slice(b"\"\n");
    }
    out.extend_from_slice(b"$EndPhysicalNames\n");
}

/// Every point array as `$NodeData` (node tag = index + 1) and every cell array as
/// `$ElementData` (element tag `cell_tag(i)`).
pub(super) fn write_views(
    out: &mut Vec<u8>,
    mesh: &TaggedMesh,
    binary: bool,
    cell_tag: &dyn Fn(usize) -> u64,
    report: &mut WriteReport,
) {
    for (name, a) in &mesh.point_data {
        write_view(out, "NodeData", "point data", name, a, binary, |i| i as u64 + 1, report);
    }
    for (name, a) in &mesh.cell_data {
        write_view(out, "ElementData", "cell data", name, a, binary, cell_tag, report);
    }
}

/// The binary entries of a view of `N` values per item: the 4-byte tag and the values
/// as one record of known size (one capacity check per item). Every item is written;
/// `true` when every value was finite.
fn view_records<const N: usize>(
    out: &mut Vec<u8>,
    a: &DataArray,
    tag: impl Fn(usize) -> u64,
) -> bool {
    let mut rec = [0u8; 76];
    let mut finite = true;
    for (i, v) in a.values.chunks_exact(N).enumerate() {
        rec[..4].copy_from_slice(&(tag(i) as i32).to_le_bytes());
        for (j, x) in v.iter().enumerate() {
            finite &= x.is_finite();
            rec[4 + 8 * j..12 + 8 * j].copy_from_slice(&x.to_le_bytes());
        }
        out.extend_from_slice(&rec[..4 + 8 * N]);
    }
    finite
}

/// A view's section header, up to its number of entries `n`.
fn view_header(out: &mut Vec<u8>, section: &str, quoted: &str, k: usize, n: usize) {
    out.extend_from_slice(b"$");
    out.extend_from_slice(section.as_bytes());
    out.extend_from_slice(b"\n1\n\"");
    out.extend_from_slice(quoted.as_bytes());
    out.extend_from_slice(b"\"\n1\n0\n3\n0\n");
    text::push_int(out, k);
    out.push(b'\n');
    text::push_int(out, n);
    out.push(b'\n');
}

fn view_end(out: &mut Vec<u8>, section: &str, binary: bool) {
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$End");
    out.extend_from_slice(section.as_bytes());
    out.push(b'\n');
}

#[allow(clippy::too_many_arguments)]
fn write_view(
    out: &mut Vec<u8>,
    section: &str,
    what: &str,
    name: &str,
    a: &DataArray,
    binary: bool,
    tag: impl Fn(usize) -> u64,
    report: &mut WriteReport,
) {
    // Gmsh's tensors are 9 components: a packed symmetric one is written in full.
    let a = &*a.expanded();
    let k = a.components;
    if !matches!(k, 1 | 3 | 9) {
        report.drop(format!(
            "{what} `{name}` has {k} components: Gmsh draws views of 1, 3 or 9; written as is (Gmsh reads it but may not display it)"
        ));
    }
    // Binary, of a common width: fixed-size records of every item, the values checked
    // finite as they are written (one pass). An array with a NaN or an infinity (rare)
    // is written again below, without those items.
    if binary && matches!(k, 1 | 3 | 9) {
        let start = out.len();
        let mut quoting = WriteReport::default();
        let q = quote_name(name, what, None, &mut quoting);
        view_header(out, section, &q, k, a.len());
        let finite = match k {
            1 => view_records::<1>(out, a, &tag),
            3 => view_records::<3>(out, a, &tag),
            _ => view_records::<9>(out, a, &tag),
        };
        if finite {
            report.dropped.extend(quoting.dropped);
            view_end(out, section, binary);
            return;
        }
        out.truncate(start);
    }
    let items = a.values.chunks_exact(k);
    let n = items.clone().filter(|v| v.iter().all(|x| x.is_finite())).count();
    if n < a.len() {
        report.drop(format!("{what} `{name}`: {} item(s) with NaN or infinite values left out (read back as missing)", a.len() - n));
    }
    let q = quote_name(name, what, None, report);
    view_header(out, section, &q, k, n);
    for (i, v) in items.enumerate() {
        if !v.iter().all(|x| x.is_finite()) {
            continue;
        }
        if binary {
            out.extend_from_slice(&(tag(i) as i32).to_le_bytes());
            for x in v {
                out.extend_from_slice(&x.to_le_bytes());
            }
        } else {
            text::push_int(out, tag(i));
            for &x in v {
                out.push(b' ');
                text::push_f64(out, x);
            }
            out.push(b'\n');
        }
    }
    view_end(out, section, binary);
}
