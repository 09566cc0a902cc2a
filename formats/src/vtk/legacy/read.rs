//! Reading a legacy file: the header, the keywords of the grid, its points and cells.

use crate::error::Position;
use crate::text::{check_count, Tokens};
use crate::{Error, ErrorKind, Layout, NodeIndex, Result, MAX_POINTS};

use crate::text::show;

use super::datasets::{Dataset, Shape};
use crate::vtk::{
    decode_f64, decode_i64, decode_indices, decode_items, decode_points, pack_parsed, Grid, Named,
    Scalar,
};

/// Which data section the arrays that follow belong to.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Section {
    Dataset,
    Point,
    Cell,
}

pub(super) struct Reader<'a> {
    /// The whole file.
    pub(super) data: &'a [u8],
    /// Offset of `t`'s slice in `data`: after a binary array the cursor restarts there,
    /// so that no time is spent counting lines through binary data.
    pub(super) base: usize,
    pub(super) t: Tokens<'a>,
    pub(super) binary: bool,
    pub(super) npoints: Option<usize>,
    pub(super) ncells: Option<usize>,
    pub(super) section: Section,
    /// Items in the current POINT_DATA / CELL_DATA section.
    pub(super) items: usize,
    pub(super) grid: Grid,
    pub(super) dataset: Dataset,
    /// What a dataset other than an unstructured grid gathers.
    pub(super) shape: Shape,
}

impl<'a> Reader<'a> {
    pub(super) fn pos(&self) -> usize {
        self.base + self.t.pos()
    }

    pub(super) fn here(&self) -> Position {
        if self.binary {
            Position::Byte(self.pos() as u64)
        } else {
            Position::Line(self.t.line())
        }
    }

    pub(super) fn err(&self, kind: ErrorKind) -> Error {
        Error { path: None, at: Some(self.here()), kind }
    }

    /// Errors from [`Tokens`] name a line; in a binary file the byte offset is the
    /// useful position.
    pub(super) fn fix(&self, mut e: Error) -> Error {
        if self.binary {
            e.at = Some(Position::Byte(self.pos() as u64));
        }
        e
    }

    pub(super) fn word(&mut self, what: &str) -> Result<&'a [u8]> {
        self.t.token(what).map_err(|e| self.fix(e))
    }

    pub(super) fn usize(&mut self, what: &str) -> Result<usize> {
        self.t.usize(what).map_err(|e| self.fix(e))
    }

    /// A header count, checked against the bytes left: `ascii_min` bytes per item in
    /// ASCII files, `binary_min` in binary ones.
    pub(super) fn count(
        &mut self,
        what: &str,
        ascii_min: usize,
        binary_min: usize,
    ) -> Result<usize> {
        let n = self.usize(what)?;
        let min = if self.binary { binary_min } else { ascii_min };
        check_count(n, self.t.remaining().len(), min, what).map_err(|k| self.err(k))
    }

    pub(super) fn scalar(&mut self) -> Result<Scalar> {
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
    pub(super) fn take_word(&mut self, word: &[u8]) -> bool {
        let save = self.t.clone();
        if self.t.next().is_some_and(|w| w.eq_ignore_ascii_case(word)) {
            return true;
        }
        self.t = save;
        false
    }

    /// In a binary file, moves past the newline that ends a header line: the array's
    /// bytes start right after it.
    pub(super) fn end_header(&mut self) {
        if self.binary {
            self.t.rest_of_line();
        }
    }

    /// The `n * ty.size()` bytes of a binary array, the cursor moved past them.
    pub(super) fn binary_bytes(&mut self, n: usize, ty: Scalar, what: &str) -> Result<&'a [u8]> {
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
    pub(super) fn floats(
        &mut self,
        n: usize,
        ty: Scalar,
        what: &str,
        out: &mut Vec<f64>,
    ) -> Result<()> {
        self.floats_of(n, ty, what, out, true)
    }

    /// Reads the `n` values of a data array as `f64` (ASCII or binary), NaN and
    /// infinities kept (`nan`, `inf` as VTK writes them in ASCII; see `decode_f64`).
    pub(super) fn data_floats(
        &mut self,
        n: usize,
        ty: Scalar,
        what: &str,
        out: &mut Vec<f64>,
    ) -> Result<()> {
        self.floats_of(n, ty, what, out, false)
    }

    pub(super) fn floats_of(
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
    pub(super) fn ints(
        &mut self,
        n: usize,
        ty: Scalar,
        what: &str,
        out: &mut Vec<i64>,
    ) -> Result<()> {
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
    pub(super) fn skip_metadata(&mut self) {
        self.t.rest_of_line();
        while !self.t.remaining().is_empty() {
            if self.t.rest_of_line().is_empty() {
                break;
            }
        }
    }

    pub(super) fn read_points(&mut self) -> Result<()> {
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
    pub(super) fn node(&self, v: i64, cell: usize) -> Result<NodeIndex> {
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

    pub(super) fn read_cells(&mut self) -> Result<()> {
        let at = self.here();
        let (offsets, connectivity) = self.read_cell_list()?;
        self.ncells = Some(offsets.len() - 1);
        self.grid.offsets = offsets;
        self.grid.connectivity = connectivity;
        self.grid.cells_at = Some(at);
        Ok(())
    }

    /// A cell list after its keyword (`CELLS`, or POLYDATA's `POLYGONS`...): `n size`
    /// then `k i1 .. ik` per cell, or (version 5.1) `OFFSETS` and `CONNECTIVITY`
    /// arrays. Returns the offsets (`n + 1` from 0) and the connectivity.
    pub(super) fn read_cell_list(&mut self) -> Result<(Vec<usize>, Vec<NodeIndex>)> {
        let at = self.here();
        let connectivity;
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
                connectivity = decode_indices(bytes, cty, true, size, np).map_err(|(i, v)| {
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
                connectivity = out;
            }
            Ok((offs.into_iter().map(|o| o as usize).collect(), connectivity))
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
            Ok((offs, conn))
        }
    }

    pub(super) fn read_cell_types(&mut self) -> Result<()> {
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
    pub(super) fn start_section(&mut self, section: Section) -> Result<()> {
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

    pub(super) fn push_array(
        &mut self,
        name: String,
        components: usize,
        values: Vec<f64>,
        at: Position,
    ) {
        self.push_laid_out(name, components, values, Layout::Plain, at);
    }

    pub(super) fn push_laid_out(
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

    pub(super) fn need_section(&self, key: &[u8]) -> Result<()> {
        if self.section == Section::Dataset {
            return Err(self.err(ErrorKind::Expected {
                expected: "POINT_DATA or CELL_DATA before a data attribute".into(),
                found: show(key),
            }));
        }
        Ok(())
    }

    /// An attribute array: `components` values per item of the current section.
    pub(super) fn attribute(
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
    pub(super) fn float_array(
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
        dataset: Dataset::Unstructured,
        shape: Shape::default(),
    };
    let mut dataset = false;
    while let Some(key) = r.t.next() {
        let k = key.to_ascii_uppercase();
        match k.as_slice() {
            b"DATASET" => {
                let ty = r.word("a dataset type")?;
                r.dataset = Dataset::from_name(ty).ok_or_else(|| {
                    r.err(ErrorKind::Unsupported(format!(
                        "legacy dataset {}: smartmesh reads UNSTRUCTURED_GRID, POLYDATA, STRUCTURED_GRID, RECTILINEAR_GRID and STRUCTURED_POINTS",
                        show(ty)
                    )))
                })?;
                dataset = true;
            }
            b"METADATA" => r.skip_metadata(),
            b"FIELD" => r.read_field()?,
            _ if !dataset => {
                return Err(r.err(ErrorKind::Expected {
                    expected: "`DATASET` and its type (UNSTRUCTURED_GRID, POLYDATA...)".into(),
                    found: show(key),
                }))
            }
            _ if r.dataset != Dataset::Unstructured && r.dataset_keyword(key)? => {}
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
            context: "expected `DATASET` and its type (UNSTRUCTURED_GRID, POLYDATA...)".into(),
        }));
    }
    r.finish_dataset()?;
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
