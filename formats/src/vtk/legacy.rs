//! Legacy `.vtk`: `DATASET UNSTRUCTURED_GRID`, ASCII or big-endian BINARY, file
//! versions 2.0–4.2 (`CELLS n size`, each cell `k i1 .. ik`) and 5.1 (`CELLS n+1 m`
//! followed by `OFFSETS` and `CONNECTIVITY` arrays, as VTK 9 writes).
//!
//! The file is keyword-driven text; in BINARY files each array follows its header
//! line's newline as raw big-endian values, then a newline. One cursor
//! ([`Tokens`]) reads both: tokens for headers and ASCII values, [`Tokens::seek`] over
//! binary arrays. Errors name the line in ASCII files and the byte offset in binary ones.

use crate::error::Position;
use crate::text::{check_count, Tokens};
use crate::{
    Error, ErrorKind, Layout, NodeIndex, Result, TaggedMesh, WriteOptions, Written, MAX_POINTS,
};

use super::{
    decode_f64, decode_i64, decode_indices, decode_items, decode_points, offsets, pack_parsed,
    push_num, put, tag_slot, Grid, Named, Plan, Scalar, GEOMETRICAL, PHYSICAL,
};

/// Which data section the arrays that follow belong to.
#[derive(Clone, Copy, PartialEq)]
enum Section {
    Dataset,
    Point,
    Cell,
}

struct Reader<'a> {
    /// The whole file.
    data: &'a [u8],
    /// Offset of `t`'s slice in `data`: after a binary array the cursor restarts there,
    /// so that no time is spent counting lines through binary data.
    base: usize,
    t: Tokens<'a>,
    binary: bool,
    npoints: Option<usize>,
    ncells: Option<usize>,
    section: Section,
    /// Items in the current POINT_DATA / CELL_DATA section.
    items: usize,
    grid: Grid,
}

/// Decodes VTK's `%XX` escapes in legacy names (`vtkDataWriter` writes spaces and
/// other special characters that way).
fn decode_name(raw: &[u8]) -> String {
    let mut out = Vec::with_capacity(raw.len());
    let mut i = 0;
    while i < raw.len() {
        if raw[i] == b'%' && i + 2 < raw.len() {
            let h = std::str::from_utf8(&raw[i + 1..i + 3])
                .ok()
                .and_then(|s| u8::from_str_radix(s, 16).ok());
            if let Some(b) = h {
                out.push(b);
                i += 3;
                continue;
            }
        }
        out.push(raw[i]);
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// Encodes a name for a legacy file as `vtkDataWriter` does: printable ASCII other
/// than space, `"` and `%` as is, every other byte as `%XX`.
fn encode_name(out: &mut Vec<u8>, name: &str) {
    const HEX: &[u8; 16] = b"0123456789ABCDEF";
    for &b in name.as_bytes() {
        if b.is_ascii_graphic() && b != b'"' && b != b'%' {
            out.push(b);
        } else {
            out.extend_from_slice(&[b'%', HEX[(b >> 4) as usize], HEX[(b & 15) as usize]]);
        }
    }
}

use crate::text::show;

impl<'a> Reader<'a> {
    fn pos(&self) -> usize {
        self.base + self.t.pos()
    }

    fn here(&self) -> Position {
        if self.binary {
            Position::Byte(self.pos() as u64)
        } else {
            Position::Line(self.t.line())
        }
    }

    fn err(&self, kind: ErrorKind) -> Error {
        Error { path: None, at: Some(self.here()), kind }
    }

    /// Errors from [`Tokens`] name a line; in a binary file the byte offset is the
    /// useful position.
    fn fix(&self, mut e: Error) -> Error {
        if self.binary {
            e.at = Some(Position::Byte(self.pos() as u64));
        }
        e
    }

    fn word(&mut self, what: &str) -> Result<&'a [u8]> {
        self.t.token(what).map_err(|e| self.fix(e))
    }

    fn usize(&mut self, what: &str) -> Result<usize> {
        self.t.usize(what).map_err(|e| self.fix(e))
    }

    /// A header count, checked against the bytes left: `ascii_min` bytes per item in
    /// ASCII files, `binary_min` in binary ones.
    fn count(&mut self, what: &str, ascii_min: usize, binary_min: usize) -> Result<usize> {
        let n = self.usize(what)?;
        let min = if self.binary { binary_min } else { ascii_min };
        check_count(n, self.t.remaining().len(), min, what).map_err(|k| self.err(k))
    }

    fn scalar(&mut self) -> Result<Scalar> {
        let tok = self.word("a data type")?;
        Scalar::from_legacy(tok).ok_or_else(|| {
            self.err(ErrorKind::Expected {
                expected: "a numeric data type (char, unsigned_char, short, int, long, float, double, vtktypeint64...)".into(),
                found: show(tok),
            })
        })
    }

    /// Consumes the next token if it is `word` (any case). Written with a clone rather
    /// than [`Tokens::peek`]: when the word is absent nothing may be consumed, not even
    /// the newline before a binary array, whose first byte may look like whitespace.
    fn take_word(&mut self, word: &[u8]) -> bool {
        let save = self.t.clone();
        if self.t.next().is_some_and(|w| w.eq_ignore_ascii_case(word)) {
            return true;
        }
        self.t = save;
        false
    }

    /// In a binary file, moves past the newline that ends a header line: the array's
    /// bytes start right after it.
    fn end_header(&mut self) {
        if self.binary {
            self.t.rest_of_line();
        }
    }

    /// The `n * ty.size()` bytes of a binary array, the cursor moved past them.
    fn binary_bytes(&mut self, n: usize, ty: Scalar, what: &str) -> Result<&'a [u8]> {
        let rem = self.t.remaining();
        let need = n.checked_mul(ty.size()).filter(|&b| b <= rem.len()).ok_or_else(|| {
            self.err(ErrorKind::UnexpectedEof {
                context: format!(
                    "{what}: {n} values of {} bytes, {} bytes left",
                    ty.size(),
                    rem.len()
                ),
            })
        })?;
        self.base = self.pos() + need;
        self.t = Tokens::new(&self.data[self.base..]);
        Ok(&rem[..need])
    }

    /// Reads `n` values as `f64` (ASCII or binary), refusing NaN and infinities.
    fn floats(&mut self, n: usize, ty: Scalar, what: &str, out: &mut Vec<f64>) -> Result<()> {
        self.floats_of(n, ty, what, out, true)
    }

    /// Reads the `n` values of a data array as `f64` (ASCII or binary), NaN and
    /// infinities kept (`nan`, `inf` as VTK writes them in ASCII; see `decode_f64`).
    fn data_floats(&mut self, n: usize, ty: Scalar, what: &str, out: &mut Vec<f64>) -> Result<()> {
        self.floats_of(n, ty, what, out, false)
    }

    fn floats_of(
        &mut self,
        n: usize,
        ty: Scalar,
        what: &str,
        out: &mut Vec<f64>,
        finite_only: bool,
    ) -> Result<()> {
        if self.binary {
            let start = self.pos();
            let bytes = self.binary_bytes(n, ty, what)?;
            decode_f64(bytes, ty, true, n, out, finite_only)
                .map_err(|i| non_finite(start, i, ty, what))
        } else if finite_only {
            out.reserve(n);
            for _ in 0..n {
                out.push(self.t.f64(what)?);
            }
            Ok(())
        } else {
            out.reserve(n);
            for _ in 0..n {
                let tok = self.t.token(what)?;
                let v = crate::text::parse_f64(tok)
                    .map_err(|_| Error::expected(self.t.line(), what, show(tok)))?;
                out.push(v);
            }
            Ok(())
        }
    }

    /// Reads `n` integers (ASCII or binary).
    fn ints(&mut self, n: usize, ty: Scalar, what: &str, out: &mut Vec<i64>) -> Result<()> {
        if self.binary {
            let start = self.pos();
            let bytes = self.binary_bytes(n, ty, what)?;
            decode_i64(bytes, ty, true, n, out).map_err(|i| {
                Error::at_byte(
                    (start + i * ty.size()) as u64,
                    ErrorKind::Expected {
                        expected: format!("{what}: an integer"),
                        found: format!("value {i}"),
                    },
                )
            })
        } else {
            out.reserve(n);
            for _ in 0..n {
                out.push(self.t.i64(what)?);
            }
            Ok(())
        }
    }

    /// Skips a `METADATA` block: lines up to the first blank one.
    fn skip_metadata(&mut self) {
        self.t.rest_of_line();
        while !self.t.remaining().is_empty() {
            if self.t.rest_of_line().is_empty() {
                break;
            }
        }
    }

    fn read_points(&mut self) -> Result<()> {
        let at = self.here();
        let n = self.count("points", 6, 3)?;
        let ty = self.scalar()?;
        self.end_header();
        if self.binary {
            let start = self.pos();
            let bytes = self.binary_bytes(3 * n, ty, "point coordinates")?;
            self.grid.points = decode_points(bytes, ty, true, n).map_err(|i| {
                Error::at_byte(
                    (start + i * ty.size()) as u64,
                    ErrorKind::NonFinite {
                        what: format!("coordinate {} of point {}", i % 3, i / 3),
                        value: "NaN or infinity".into(),
                    },
                )
            })?;
        } else {
            let mut flat = Vec::new();
            self.floats(3 * n, ty, "point coordinate", &mut flat)?;
            self.grid.points = flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        }
        self.npoints = Some(n);
        if self.grid.cells_at.is_some() && self.grid.connectivity.iter().any(|&v| v as usize >= n) {
            return Err(Error {
                path: None,
                at: Some(at),
                kind: ErrorKind::Inconsistent(
                    "CELLS before POINTS refer to points that do not exist".into(),
                ),
            });
        }
        Ok(())
    }

    /// Checks that a node index names an existing point (when POINTS came first, as it
    /// does in every file VTK writes).
    #[inline]
    fn node(&self, v: i64, cell: usize) -> Result<NodeIndex> {
        let max = self.npoints.unwrap_or(MAX_POINTS).min(MAX_POINTS);
        if v < 0 || v as u64 >= max as u64 {
            return Err(self.err(ErrorKind::IndexOutOfRange {
                what: format!("cell {cell}"),
                index: v,
                available: self.npoints.unwrap_or(0),
            }));
        }
        Ok(v as NodeIndex)
    }

    fn read_cells(&mut self) -> Result<()> {
        let at = self.here();
        let n = self.count("cells", 2, 4)?;
        let size = self.count("cell list size", 2, 4)?;
        // Version 5.1: `CELLS noffsets nconnectivity`, then two typed arrays.
        if self.take_word(b"OFFSETS") {
            let oty = self.scalar()?;
            self.end_header();
            let mut offs = Vec::new();
            self.ints(n, oty, "cell offset", &mut offs)?;
            let ncells = n.saturating_sub(1);
            if offs.first().is_some_and(|&o| o != 0) || n == 0 {
                return Err(self.err(ErrorKind::Expected {
                    expected: "OFFSETS starting at 0 (CELLS gives one offset more than cells)"
                        .into(),
                    found: match offs.first() {
                        Some(o) => format!("a first offset of {o}"),
                        None => "no offset (CELLS 0)".into(),
                    },
                }));
            }
            if offs.windows(2).any(|w| w[1] < w[0])
                || offs.last().is_some_and(|&o| o as u64 != size as u64)
            {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Inconsistent(format!(
                        "OFFSETS must rise from 0 to the connectivity size {size}"
                    )),
                });
            }
            let w = self.word("`CONNECTIVITY`")?;
            if !w.eq_ignore_ascii_case(b"CONNECTIVITY") {
                return Err(self.err(ErrorKind::Expected {
                    expected: "`CONNECTIVITY`".into(),
                    found: show(w),
                }));
            }
            let cty = self.scalar()?;
            self.end_header();
            if self.binary {
                let start = self.pos();
                let bytes = self.binary_bytes(size, cty, "cell nodes")?;
                let np = self.npoints.unwrap_or(usize::MAX);
                self.grid.connectivity =
                    decode_indices(bytes, cty, true, size, np).map_err(|(i, v)| {
                        let cell = offs.partition_point(|&o| o as usize <= i).saturating_sub(1);
                        let mut e = self.node(v, cell).err().unwrap_or_else(|| {
                            self.err(ErrorKind::Expected {
                                expected: "an integer node index".into(),
                                found: v.to_string(),
                            })
                        });
                        e.at = Some(Position::Byte((start + i * cty.size()) as u64));
                        e
                    })?;
            } else {
                let mut out = Vec::with_capacity(size);
                for c in 0..ncells {
                    for _ in offs[c]..offs[c + 1] {
                        let v = self.t.i64("cell node")?;
                        out.push(self.node(v, c)?);
                    }
                }
                self.grid.connectivity = out;
            }
            self.grid.offsets = offs.into_iter().map(|o| o as usize).collect();
            self.ncells = Some(ncells);
        } else {
            if size < n {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Inconsistent(format!(
                        "CELLS {n} {size}: the list size must count one node count per cell"
                    )),
                });
            }
            self.end_header();
            let mut offs = Vec::with_capacity(n + 1);
            // The nodes of a binary list go into an array of the length the counts
            // promise (zeroed fresh pages, written once), grown only if a damaged file's
            // counts overrun it.
            let mut conn = if self.binary {
                vec![0 as NodeIndex; size - n]
            } else {
                Vec::with_capacity(size - n)
            };
            offs.push(0usize);
            let mut left = size;
            if self.binary {
                let start = self.pos();
                let bytes = self.binary_bytes(size, Scalar::I32, "cell list")?;
                let word = |i: usize| {
                    i32::from_be_bytes(bytes[4 * i..4 * i + 4].try_into().expect("4 bytes")) as i64
                };
                // The largest index is folded in the pass that decodes them, and the
                // faulty one looked for only when it is out of range. Negative indices
                // wrap to 2^31 and more, which no point count admits.
                let (mut p, mut q, mut max) = (0, 0, 0 as NodeIndex);
                for c in 0..n {
                    if left == 0 {
                        return Err(Error::at_byte(
                            (start + 4 * p) as u64,
                            ErrorKind::Inconsistent(format!(
                                "CELLS {n} {size}: the list ends before cell {c}"
                            )),
                        ));
                    }
                    let k = word(p);
                    left -= 1;
                    if k < 0 || k as usize > left {
                        return Err(Error::at_byte(
                            (start + 4 * p) as u64,
                            ErrorKind::Expected {
                                expected: format!("a node count for cell {c}, at most {left}"),
                                found: k.to_string(),
                            },
                        ));
                    }
                    let k = k as usize;
                    if q + k > conn.len() {
                        conn.resize(q + k, 0);
                    }
                    for (d, b) in conn[q..q + k]
                        .iter_mut()
                        .zip(bytes[4 * (p + 1)..4 * (p + 1 + k)].chunks_exact(4))
                    {
                        *d = i32::from_be_bytes(b.try_into().expect("4 bytes")) as NodeIndex;
                        max = max.max(*d);
                    }
                    p += 1 + k;
                    q += k;
                    left -= k;
                    offs.push(q);
                }
                conn.truncate(q);
                // A 32-bit cell list names no point past i32::MAX.
                let np = self.npoints.unwrap_or(usize::MAX).min(1 << 31);
                if let Some(i) = (q > 0 && max as usize >= np)
                    .then(|| conn.iter().position(|&v| v as usize >= np))
                    .flatten()
                {
                    let c = offs.partition_point(|&o| o <= i) - 1;
                    let at = start + 4 * (i + c + 1);
                    return Err(Error::at_byte(
                        at as u64,
                        ErrorKind::IndexOutOfRange {
                            what: format!("cell {c}"),
                            index: conn[i] as i32 as i64,
                            available: np,
                        },
                    ));
                }
            } else {
                for c in 0..n {
                    if left == 0 {
                        return Err(self.err(ErrorKind::Inconsistent(format!(
                            "CELLS {n} {size}: the list ends before cell {c}"
                        ))));
                    }
                    let k = self.t.i64("node count")?;
                    left -= 1;
                    if k < 0 || k as usize > left {
                        return Err(self.err(ErrorKind::Expected {
                            expected: format!("a node count for cell {c}, at most {left}"),
                            found: k.to_string(),
                        }));
                    }
                    for _ in 0..k {
                        let v = self.t.i64("cell node")?;
                        conn.push(self.node(v, c)?);
                    }
                    left -= k as usize;
                    offs.push(conn.len());
                }
            }
            if left != 0 {
                return Err(Error {
                    path: None,
                    at: Some(at),
                    kind: ErrorKind::Inconsistent(format!(
                        "CELLS announces a list of {size} integers but its {n} cells use {}",
                        size - left
                    )),
                });
            }
            self.grid.offsets = offs;
            self.grid.connectivity = conn;
            self.ncells = Some(n);
        }
        self.grid.cells_at = Some(at);
        Ok(())
    }

    fn read_cell_types(&mut self) -> Result<()> {
        let at = self.here();
        let n = self.count("cell types", 2, 4)?;
        if let Some(nc) = self.ncells {
            if n != nc {
                return Err(self.err(ErrorKind::Inconsistent(format!(
                    "CELL_TYPES {n} after CELLS with {nc} cells"
                ))));
            }
        }
        self.end_header();
        let bad = |i: usize, t: i64| ErrorKind::Expected {
            expected: format!("a VTK cell type (0 to 255) for cell {i}"),
            found: t.to_string(),
        };
        if self.binary {
            let start = self.pos();
            let bytes = self.binary_bytes(n, Scalar::I32, "cell types")?;
            let word = |c: &[u8]| i32::from_be_bytes(c.try_into().expect("4 bytes"));
            if let Some(i) = bytes.chunks_exact(4).position(|c| !(0..=255).contains(&word(c))) {
                return Err(Error::at_byte(
                    (start + 4 * i) as u64,
                    bad(i, word(&bytes[4 * i..4 * i + 4]) as i64),
                ));
            }
            self.grid.types = bytes.chunks_exact(4).map(|c| c[3]).collect();
        } else {
            let mut types = Vec::with_capacity(n);
            for i in 0..n {
                let t = self.t.i64("cell type")?;
                if !(0..=255).contains(&t) {
                    return Err(self.err(bad(i, t)));
                }
                types.push(t as u8);
            }
            self.grid.types = types;
        }
        self.grid.types_at = Some(at);
        self.ncells.get_or_insert(n);
        Ok(())
    }

    /// POINT_DATA n / CELL_DATA n.
    fn start_section(&mut self, section: Section) -> Result<()> {
        let n = self.usize("an item count")?;
        let expected = if section == Section::Point { self.npoints } else { self.ncells };
        let what = if section == Section::Point { "POINT_DATA" } else { "CELL_DATA" };
        match expected {
            Some(e) if e != n => {
                return Err(self
                    .err(ErrorKind::Inconsistent(format!("{what} {n}, but the dataset has {e}"))))
            }
            None => {
                return Err(self.err(ErrorKind::Expected {
                    expected: format!("POINTS and CELLS before {what}"),
                    found: format!("`{what}`"),
                }))
            }
            _ => {}
        }
        self.section = section;
        self.items = n;
        Ok(())
    }

    fn push_array(&mut self, name: String, components: usize, values: Vec<f64>, at: Position) {
        self.push_laid_out(name, components, values, Layout::Plain, at);
    }

    fn push_laid_out(
        &mut self,
        name: String,
        components: usize,
        values: Vec<f64>,
        layout: Layout,
        at: Position,
    ) {
        let a = Named::new(name, components, values, layout, at);
        match self.section {
            Section::Dataset => self.grid.field_arrays.push(a),
            Section::Point => self.grid.point_arrays.push(a),
            Section::Cell => self.grid.cell_arrays.push(a),
        }
    }

    fn need_section(&self, key: &[u8]) -> Result<()> {
        if self.section == Section::Dataset {
            return Err(self.err(ErrorKind::Expected {
                expected: "POINT_DATA or CELL_DATA before a data attribute".into(),
                found: show(key),
            }));
        }
        Ok(())
    }

    /// An attribute array: `components` values per item of the current section.
    fn attribute(
        &mut self,
        name: String,
        components: usize,
        ty: Scalar,
        at: Position,
    ) -> Result<()> {
        let n = self
            .items
            .checked_mul(components)
            .ok_or_else(|| self.err(ErrorKind::Inconsistent("array too large".into())))?;
        check_count(n, self.t.remaining().len(), if self.binary { ty.size() } else { 2 }, &name)
            .map_err(|k| self.err(k))?;
        self.float_array(name, components, n, ty, at)
    }

    /// `n` values of an array of `components` floats per item, 9-component binary ones
    /// packed where they can be ([`decode_items`]), added to the current section.
    fn float_array(
        &mut self,
        name: String,
        components: usize,
        n: usize,
        ty: Scalar,
        at: Position,
    ) -> Result<()> {
        let what = format!("value of `{name}`");
        if !self.binary {
            let mut values = Vec::new();
            self.data_floats(n, ty, &what, &mut values)?;
            let (values, layout) = pack_parsed(values, components);
            self.push_laid_out(name, components, values, layout, at);
            return Ok(());
        }
        let start = self.pos();
        let bytes = self.binary_bytes(n, ty, &what)?;
        let (values, layout) = decode_items(bytes, ty, true, n, components)
            .map_err(|i| non_finite(start, i, ty, &what))?;
        self.push_laid_out(name, components, values, layout, at);
        Ok(())
    }

    fn read_field(&mut self) -> Result<()> {
        let _field_name = self.word("a field name")?;
        let k = self.count("field arrays", 8, 8)?;
        let mut i = 0;
        while i < k {
            let at = self.here();
            let raw = self.word("an array name")?;
            if raw.eq_ignore_ascii_case(b"METADATA") {
                self.skip_metadata();
                continue;
            }
            i += 1;
            if raw == b"NULL_ARRAY" {
                continue;
            }
            let name = decode_name(raw);
            let comps = self.usize("a component count")?;
            let tuples = self.usize("a tuple count")?;
            let tyw = self.word("a data type")?;
            let Some(ty) = Scalar::from_legacy(tyw) else {
                return Err(self.err(ErrorKind::Unsupported(format!(
                    "field array `{name}` of type {}: smartmesh reads numeric arrays",
                    show(tyw)
                ))));
            };
            if comps == 0 {
                return Err(self.err(ErrorKind::Expected {
                    expected: format!("at least one component in `{name}`"),
                    found: "0".into(),
                }));
            }
            match self.section {
                Section::Point | Section::Cell if tuples != self.items => {
                    return Err(self.err(ErrorKind::Inconsistent(format!(
                        "field array `{name}` has {tuples} tuples in a section of {}",
                        self.items
                    ))));
                }
                _ => {}
            }
            let n = comps
                .checked_mul(tuples)
                .ok_or_else(|| self.err(ErrorKind::Inconsistent("array too large".into())))?;
            check_count(
                n,
                self.t.remaining().len(),
                if self.binary { ty.size() } else { 2 },
                &name,
            )
            .map_err(|k| self.err(k))?;
            self.end_header();
            // A binary 32-bit cell tag array (how smartmesh and Gmsh write them) goes
            // straight into tags: every i32 is a tag, so there is nothing to check.
            if self.binary
                && self.section == Section::Cell
                && comps == 1
                && ty == Scalar::I32
                && tag_slot(&name).is_some()
            {
                let bytes = self.binary_bytes(n, ty, "cell tags")?;
                let tags = bytes
                    .chunks_exact(4)
                    .map(|c| i32::from_be_bytes(c.try_into().expect("4 bytes")))
                    .collect();
                self.grid.cell_tags.push((name, tags, at));
                continue;
            }
            self.float_array(name, comps, n, ty, at)?;
        }
        Ok(())
    }

    fn read_attribute(&mut self, key: &'a [u8]) -> Result<()> {
        const KEYWORDS: [&[u8]; 11] = [
            b"SCALARS",
            b"VECTORS",
            b"NORMALS",
            b"TENSORS",
            b"TENSORS6",
            b"TEXTURE_COORDINATES",
            b"GLOBAL_IDS",
            b"PEDIGREE_IDS",
            b"COLOR_SCALARS",
            b"LOOKUP_TABLE",
            b"FIELD",
        ];
        let k = key.to_ascii_uppercase();
        if KEYWORDS.contains(&k.as_slice()) {
            self.need_section(key)?;
        }
        let at = self.here();
        match k.as_slice() {
            b"SCALARS" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                let comps = if self.t.at_line_end() { 1 } else { self.usize("a component count")? };
                if !(1..=4).contains(&comps) {
                    return Err(self.err(ErrorKind::Expected { expected: "1 to 4 components".into(), found: comps.to_string() }));
                }
                if self.take_word(b"LOOKUP_TABLE") {
                    self.word("a lookup table name")?;
                }
                self.end_header();
                self.attribute(name, comps, ty, at)
            }
            b"VECTORS" | b"NORMALS" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                self.end_header();
                self.attribute(name, 3, ty, at)
            }
            b"TENSORS" | b"TENSORS6" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                self.end_header();
                if k == b"TENSORS" {
                    self.attribute(name, 9, ty, at)
                } else {
                    // XX YY ZZ XY YZ XZ, widened to the row-major 9 components that
                    // tensors travel as.
                    let n = self.items;
                    check_count(n, self.t.remaining().len(), 6 * if self.binary { ty.size() } else { 2 }, &name).map_err(|k| self.err(k))?;
                    let mut six = Vec::new();
                    self.data_floats(6 * n, ty, &format!("value of `{name}`"), &mut six)?;
                    let values = six.chunks_exact(6).flat_map(|s| [s[0], s[3], s[5], s[3], s[1], s[4], s[5], s[4], s[2]]).collect();
                    self.push_array(name, 9, values, at);
                    Ok(())
                }
            }
            b"TEXTURE_COORDINATES" => {
                let name = decode_name(self.word("an array name")?);
                let dim = self.usize("a dimension")?;
                if !(1..=3).contains(&dim) {
                    return Err(self.err(ErrorKind::Expected { expected: "1 to 3 texture dimensions".into(), found: dim.to_string() }));
                }
                let ty = self.scalar()?;
                self.end_header();
                self.attribute(name, dim, ty, at)
            }
            b"GLOBAL_IDS" | b"PEDIGREE_IDS" => {
                let name = decode_name(self.word("an array name")?);
                let ty = self.scalar()?;
                self.end_header();
                self.attribute(name, 1, ty, at)
            }
            b"COLOR_SCALARS" => {
                // Floats in [0, 1] in ASCII files, unsigned chars in binary ones.
                let name = decode_name(self.word("an array name")?);
                let comps = self.usize("a component count")?;
                if !(1..=4).contains(&comps) {
                    return Err(self.err(ErrorKind::Expected { expected: "1 to 4 components".into(), found: comps.to_string() }));
                }
                self.end_header();
                if self.binary {
                    self.attribute(name, comps, Scalar::U8, at)?;
                    let last = match self.section {
                        Section::Point => self.grid.point_arrays.last_mut(),
                        _ => self.grid.cell_arrays.last_mut(),
                    };
                    if let Some(a) = last {
                        a.values.iter_mut().for_each(|v| *v /= 255.0);
                    }
                    Ok(())
                } else {
                    self.attribute(name, comps, Scalar::F64, at)
                }
            }
            b"LOOKUP_TABLE" => {
                // A colour table for SCALARS: not mesh data, skipped.
                self.word("a lookup table name")?;
                let n = self.count("lookup table entries", 8, 4)?;
                self.end_header();
                let mut skip = Vec::new();
                if self.binary {
                    self.binary_bytes(4 * n, Scalar::U8, "lookup table")?;
                } else {
                    self.floats(4 * n, Scalar::F64, "lookup table value", &mut skip)?;
                }
                Ok(())
            }
            _ => Err(self.err(ErrorKind::Expected {
                expected: "a VTK legacy keyword (POINTS, CELLS, CELL_TYPES, POINT_DATA, CELL_DATA, SCALARS, VECTORS, TENSORS, FIELD...)".into(),
                found: show(key),
            })),
        }
    }
}

/// The error for value `i` of a binary array starting at byte `start`: not finite.
fn non_finite(start: usize, i: usize, ty: Scalar, what: &str) -> Error {
    Error::at_byte(
        (start + i * ty.size()) as u64,
        ErrorKind::NonFinite {
            what: format!("{what}, value {i}"),
            value: "NaN or infinity".into(),
        },
    )
}

/// Reads a legacy file.
pub(crate) fn read(bytes: &[u8]) -> Result<Grid> {
    let mut t = Tokens::new(bytes);
    let first = t.rest_of_line();
    const MAGIC: &[u8] = b"# vtk DataFile Version";
    if first.len() < MAGIC.len() || !first[..MAGIC.len()].eq_ignore_ascii_case(MAGIC) {
        return Err(Error::expected(1, "`# vtk DataFile Version x.y`", show(first)));
    }
    let _title = t.rest_of_line();
    let kind = t.token("ASCII or BINARY")?;
    let binary = if kind.eq_ignore_ascii_case(b"ASCII") {
        false
    } else if kind.eq_ignore_ascii_case(b"BINARY") {
        true
    } else {
        return Err(t.expected("ASCII or BINARY", kind));
    };
    let mut r = Reader {
        data: bytes,
        base: 0,
        t,
        binary,
        npoints: None,
        ncells: None,
        section: Section::Dataset,
        items: 0,
        grid: Grid::default(),
    };
    let mut dataset = false;
    while let Some(key) = r.t.next() {
        let k = key.to_ascii_uppercase();
        match k.as_slice() {
            b"DATASET" => {
                let ty = r.word("a dataset type")?;
                if !ty.eq_ignore_ascii_case(b"UNSTRUCTURED_GRID") {
                    return Err(r.err(ErrorKind::Unsupported(format!(
                        "legacy dataset {}: smartmesh reads UNSTRUCTURED_GRID",
                        show(ty)
                    ))));
                }
                dataset = true;
            }
            b"METADATA" => r.skip_metadata(),
            b"FIELD" => r.read_field()?,
            _ if !dataset => {
                return Err(r.err(ErrorKind::Expected {
                    expected: "`DATASET UNSTRUCTURED_GRID`".into(),
                    found: show(key),
                }))
            }
            b"POINTS" => r.read_points()?,
            b"CELLS" => r.read_cells()?,
            b"CELL_TYPES" => r.read_cell_types()?,
            b"POINT_DATA" => r.start_section(Section::Point)?,
            b"CELL_DATA" => r.start_section(Section::Cell)?,
            _ => r.read_attribute(key)?,
        }
    }
    if !dataset {
        return Err(r.err(ErrorKind::UnexpectedEof {
            context: "expected `DATASET UNSTRUCTURED_GRID`".into(),
        }));
    }
    if r.npoints.is_none() {
        return Err(r.err(ErrorKind::UnexpectedEof { context: "expected POINTS".into() }));
    }
    if r.grid.types_at.is_none() && r.grid.cells_at.is_some() {
        return Err(
            r.err(ErrorKind::UnexpectedEof { context: "expected CELL_TYPES after CELLS".into() })
        );
    }
    if r.grid.cells_at.is_none() {
        if r.grid.types_at.is_some() {
            return Err(r.err(ErrorKind::UnexpectedEof {
                context: "expected CELLS before CELL_TYPES".into(),
            }));
        }
        r.grid.offsets = vec![0];
    }
    Ok(r.grid)
}

/// Writes a legacy file.
pub(crate) fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let v51 = match opts.vtk.legacy_version {
        (4, 2) => false,
        (5, 1) => true,
        (a, b) => {
            return Err(Error::new(ErrorKind::CannotWrite {
                format: "VTK legacy",
                reason: format!("file version {a}.{b}: smartmesh writes 4.2 and 5.1"),
            }))
        }
    };
    let binary = opts.vtk.legacy_binary;
    let mut plan = Plan::new(mesh, "VTK legacy");
    let np = mesh.points.len();
    let nc = mesh.num_cells();
    let nconn: usize = mesh.blocks.iter().map(|b| b.nodes.len()).sum();
    if !v51 && nconn + nc > i32::MAX as usize {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "VTK legacy 4.2",
            reason: "more than 2^31 cell list entries; write version 5.1".into(),
        }));
    }
    let data_values = plan.point_arrays.iter().map(|(_, a)| a.values.len()).sum::<usize>()
        + plan.cell_arrays.iter().map(|(_, a)| a.values.len()).sum::<usize>();
    let per_value = if binary { 8 } else { 20 };
    let mut out = Vec::with_capacity(
        512 + np * 3 * per_value + (nconn + nc) * 8 + nc * 24 + data_values * per_value,
    );

    out.extend_from_slice(if v51 {
        b"# vtk DataFile Version 5.1\n"
    } else {
        b"# vtk DataFile Version 4.2\n"
    });
    out.extend_from_slice(b"written by smartmesh\n");
    out.extend_from_slice(if binary { b"BINARY\n" } else { b"ASCII\n" });
    out.extend_from_slice(b"DATASET UNSTRUCTURED_GRID\n");

    out.extend_from_slice(b"POINTS ");
    crate::text::push_int(&mut out, np);
    out.extend_from_slice(b" double\n");
    if binary {
        put(&mut out, mesh.points.as_flattened(), f64::to_be_bytes);
        out.push(b'\n');
    } else {
        for p in &mesh.points {
            push_num(&mut out, p[0]);
            out.push(b' ');
            push_num(&mut out, p[1]);
            out.push(b' ');
            push_num(&mut out, p[2]);
            out.push(b'\n');
        }
    }

    if v51 {
        let offs = offsets(mesh);
        out.extend_from_slice(b"CELLS ");
        crate::text::push_int(&mut out, nc + 1);
        out.push(b' ');
        crate::text::push_int(&mut out, nconn);
        out.extend_from_slice(b"\nOFFSETS vtktypeint64\n");
        if binary {
            put(&mut out, &offs, |o| (o as i64).to_be_bytes());
            out.push(b'\n');
        } else {
            for o in &offs {
                crate::text::push_int(&mut out, *o);
                out.push(b'\n');
            }
        }
        out.extend_from_slice(b"CONNECTIVITY vtktypeint64\n");
        for b in &mesh.blocks {
            if binary {
                put(&mut out, &b.nodes, |v| (v as i64).to_be_bytes());
            } else {
                for cell in b.cells() {
                    for (j, &v) in cell.iter().enumerate() {
                        if j > 0 {
                            out.push(b' ');
                        }
                        crate::text::push_int(&mut out, v);
                    }
                    out.push(b'\n');
                }
            }
        }
        if binary {
            out.push(b'\n');
        }
    } else {
        out.extend_from_slice(b"CELLS ");
        crate::text::push_int(&mut out, nc);
        out.push(b' ');
        crate::text::push_int(&mut out, nc + nconn);
        out.push(b'\n');
        for b in &mesh.blocks {
            let k = b.kind.nodes_per_cell();
            if binary {
                match k {
                    2 => cell_records::<2, 3>(&mut out, &b.nodes),
                    3 => cell_records::<3, 4>(&mut out, &b.nodes),
                    4 => cell_records::<4, 5>(&mut out, &b.nodes),
                    _ => {
                        for cell in b.cells() {
                            out.extend_from_slice(&(k as i32).to_be_bytes());
                            for &v in cell {
                                out.extend_from_slice(&(v as i32).to_be_bytes());
                            }
                        }
                    }
                }
                continue;
            }
            for cell in b.cells() {
                crate::text::push_int(&mut out, k);
                for &v in cell {
                    out.push(b' ');
                    crate::text::push_int(&mut out, v);
                }
                out.push(b'\n');
            }
        }
        if binary {
            out.push(b'\n');
        }
    }

    out.extend_from_slice(b"CELL_TYPES ");
    crate::text::push_int(&mut out, nc);
    out.push(b'\n');
    for b in &mesh.blocks {
        let t = super::vtk_type_of(b.kind) as i32;
        if binary {
            for _ in 0..b.len() {
                out.extend_from_slice(&t.to_be_bytes());
            }
        } else {
            for _ in 0..b.len() {
                crate::text::push_int(&mut out, t);
                out.push(b'\n');
            }
        }
    }
    if binary {
        out.push(b'\n');
    }

    // Tag names: meshio's `field_data` layout, one `[tag, dim]` array per name, as
    // dataset field data. After CELL_TYPES rather than right after DATASET: VTK reads
    // it in either place, meshio's reader only here (after DATASET it files the arrays
    // under the dataset's own keywords and drops them).
    if !plan.names.is_empty() {
        out.extend_from_slice(b"FIELD FieldData ");
        crate::text::push_int(&mut out, plan.names.len());
        out.push(b'\n');
        for &(name, tag, dim) in &plan.names {
            encode_name(&mut out, name);
            out.extend_from_slice(b" 1 2 int\n");
            if binary {
                put(&mut out, &[tag, dim as i32], i32::to_be_bytes);
            } else {
                crate::text::push_int(&mut out, tag);
                out.push(b' ');
                crate::text::push_int(&mut out, dim);
            }
            out.push(b'\n');
        }
    }

    // Cell data: the tags and the cell arrays, all as field arrays (as VTK writes
    // arrays that are not the active attributes).
    out.extend_from_slice(b"CELL_DATA ");
    crate::text::push_int(&mut out, nc);
    out.extend_from_slice(b"\nFIELD FieldData ");
    crate::text::push_int(&mut out, 2 + plan.cell_arrays.len());
    out.push(b'\n');
    for (name, tags) in [(PHYSICAL, &plan.physical), (GEOMETRICAL, &plan.geometrical)] {
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(b" 1 ");
        crate::text::push_int(&mut out, nc);
        out.extend_from_slice(b" int\n");
        write_ints(&mut out, tags, binary);
    }
    for (name, a) in &plan.cell_arrays {
        write_field_array(&mut out, name, a, binary);
    }

    // Point data: the active tensor as TENSORS (9 values per point, which ParaView's
    // Tensor Glyph uses), every other array as a field array with its own count.
    if !plan.point_arrays.is_empty() {
        out.extend_from_slice(b"POINT_DATA ");
        crate::text::push_int(&mut out, np);
        out.push(b'\n');
        if let Some(tname) = plan.tensor {
            let a = &plan
                .point_arrays
                .iter()
                .find(|(n, _)| *n == tname)
                .expect("the tensor is one of the point arrays")
                .1;
            out.extend_from_slice(b"TENSORS ");
            encode_name(&mut out, tname);
            out.extend_from_slice(b" double\n");
            write_floats(&mut out, &a.values, 9, binary);
        }
        let rest: Vec<_> =
            plan.point_arrays.iter().filter(|(n, _)| Some(*n) != plan.tensor).collect();
        if !rest.is_empty() {
            out.extend_from_slice(b"FIELD FieldData ");
            crate::text::push_int(&mut out, rest.len());
            out.push(b'\n');
            for (name, a) in rest {
                write_field_array(&mut out, name, a, binary);
            }
        }
    }
    let report = std::mem::take(&mut plan.report);
    Ok(Written { main: out, siblings: Vec::new(), report })
}

/// The binary `K i1 .. iK` records (`R = K + 1` big-endian words) of cells of `K`
/// nodes, one stack record a cell appended whole (no zeroing pass over the output).
fn cell_records<const K: usize, const R: usize>(out: &mut Vec<u8>, nodes: &[NodeIndex]) {
    let mut rec = [[0u8; 4]; R];
    rec[0] = (K as i32).to_be_bytes();
    for cell in nodes.chunks_exact(K) {
        for (w, &v) in rec[1..].iter_mut().zip(cell) {
            *w = (v as i32).to_be_bytes();
        }
        out.extend_from_slice(rec.as_flattened());
    }
}

fn write_ints(out: &mut Vec<u8>, v: &[i32], binary: bool) {
    if binary {
        put(out, v, i32::to_be_bytes);
    } else {
        for x in v {
            crate::text::push_int(out, *x);
            out.push(b'\n');
        }
    }
    if binary {
        out.push(b'\n');
    }
}

fn write_floats(out: &mut Vec<u8>, v: &[f64], per_line: usize, binary: bool) {
    if binary {
        put(out, v, f64::to_be_bytes);
        out.push(b'\n');
    } else {
        for item in v.chunks(per_line.max(1)) {
            for (j, &x) in item.iter().enumerate() {
                if j > 0 {
                    out.push(b' ');
                }
                push_num(out, x);
            }
            out.push(b'\n');
        }
    }
}

fn write_field_array(out: &mut Vec<u8>, name: &str, a: &crate::DataArray, binary: bool) {
    encode_name(out, name);
    out.push(b' ');
    crate::text::push_int(out, a.components);
    out.push(b' ');
    crate::text::push_int(out, a.len());
    out.extend_from_slice(b" double\n");
    write_floats(out, &a.values, a.components, binary);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_through_percent_escapes() {
        let mut out = Vec::new();
        encode_name(&mut out, "far field 100%");
        assert_eq!(out, b"far%20field%20100%25");
        assert_eq!(decode_name(&out), "far field 100%");
        assert_eq!(decode_name(b"a%2"), "a%2");
    }
}
