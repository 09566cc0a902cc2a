//! Reading a `.vtu`: the array specifications the XML scanner finds, then each array
//! decoded (ASCII, base64 or appended, raw or zlib blocks) into the grid.

use super::decode::{Appended, Decoder};
use super::pieces::PieceBody;
use super::*;

#[derive(Clone, Copy, PartialEq)]
pub(super) enum Format {
    Ascii,
    Binary,
    Appended,
}

/// A `<DataArray>` found by the scan, decoded later.
pub(super) struct Spec {
    pub(super) name: String,
    pub(super) ty: Scalar,
    pub(super) components: usize,
    pub(super) format: Format,
    pub(super) offset: usize,
    pub(super) tuples: Option<usize>,
    /// The inline text (ascii or base64).
    pub(super) text: (usize, usize),
    pub(super) at: usize,
}

/// The `<DataArray>`s of a container. In `<FieldData>` arrays of other than numeric
/// types (ParaView writes strings there) are skipped: they cannot name a tag.
pub(super) fn read_array_specs<'a>(
    s: &mut Scan<'a>,
    container: &Tag<'a>,
    out: &mut Vec<Spec>,
) -> Result<()> {
    if container.empty {
        return Ok(());
    }
    let field = container.name == b"FieldData";
    loop {
        match s.next()? {
            Ev::Start(t) if t.name == b"DataArray" => {
                match spec(&t, s.d) {
                    Ok(sp) => out.push(sp),
                    Err(e) if field && matches!(e.kind, ErrorKind::Unsupported(_)) => {}
                    Err(e) => return Err(e),
                }
                s.skip_subtree(&t)?;
            }
            Ev::Start(t) => s.skip_subtree(&t)?,
            Ev::End(name, _) if name == container.name => return Ok(()),
            Ev::End(name, pos) => {
                return Err(err(
                    pos,
                    ErrorKind::Expected {
                        expected: format!("</{}>", String::from_utf8_lossy(container.name)),
                        found: format!("</{}>", String::from_utf8_lossy(name)),
                    },
                ))
            }
            Ev::Eof => {
                return Err(err(
                    container.at,
                    ErrorKind::UnexpectedEof {
                        context: format!(
                            "<{}> is not closed",
                            String::from_utf8_lossy(container.name)
                        ),
                    },
                ))
            }
        }
    }
}

fn spec(t: &Tag<'_>, d: &[u8]) -> Result<Spec> {
    let name = t.attr_str("Name").unwrap_or_default();
    let ty_name = t.attr_str("type").ok_or_else(|| {
        err(
            t.at,
            ErrorKind::Expected {
                expected: format!("a type= attribute on DataArray `{name}`"),
                found: "none".into(),
            },
        )
    })?;
    let ty = Scalar::from_xml(&ty_name).ok_or_else(|| {
        err(t.at, ErrorKind::Unsupported(format!("DataArray `{name}` of type {ty_name}: smartmesh reads Int8..Int64, UInt8..UInt64, Float32 and Float64")))
    })?;
    let components = t.attr_usize("NumberOfComponents")?.unwrap_or(1);
    if components == 0 {
        return Err(err(
            t.at,
            ErrorKind::Expected {
                expected: format!("NumberOfComponents of `{name}` at least 1"),
                found: "0".into(),
            },
        ));
    }
    let format = match t.attr("format") {
        Some(b"ascii") => Format::Ascii,
        Some(b"binary") => Format::Binary,
        Some(b"appended") => Format::Appended,
        other => {
            return Err(err(
                t.at,
                ErrorKind::Expected {
                    expected: format!("format=\"ascii\", \"binary\" or \"appended\" on `{name}`"),
                    found: show(other.unwrap_or(b"nothing")),
                },
            ))
        }
    };
    let offset = t.attr_usize("offset")?.unwrap_or(0);
    if format == Format::Appended && t.attr("offset").is_none() {
        return Err(err(
            t.at,
            ErrorKind::Expected {
                expected: format!("an offset= attribute on appended DataArray `{name}`"),
                found: "none".into(),
            },
        ));
    }
    let tuples = t.attr_usize("NumberOfTuples")?;
    let text = if t.empty {
        (t.end, t.end)
    } else {
        let len = memchr::memchr(b'<', &d[t.end..]).unwrap_or(d.len() - t.end);
        (t.end, t.end + len)
    };
    Ok(Spec { name, ty, components, format, offset, tuples, text, at: t.at })
}

/// Reads a `.vtu` or `.vtp` file, every piece (merged), or a parallel `.pvtu`/`.pvtp`
/// file and the pieces it names.
pub(crate) fn read(d: &[u8], ctx: &crate::ReadContext<'_>) -> Result<Grid> {
    read_any(d, Some(ctx))
}

/// Reads the file of a piece a parallel file names: a serial file.
pub(super) fn read_piece(d: &[u8]) -> Result<Grid> {
    read_any(d, None)
}

/// Reads a serial file, or with `ctx` (where its pieces are found) a parallel one.
fn read_any(d: &[u8], ctx: Option<&crate::ReadContext<'_>>) -> Result<Grid> {
    let mut s = Scan { d, pos: 0 };
    let (root, kind) = root_tag(&mut s, d)?;
    if kind.parallel {
        let Some(ctx) = ctx else {
            return Err(err(
                root.at,
                ErrorKind::Unsupported(format!(
                    "a {} as a piece of a parallel file: its pieces must be serial files",
                    kind.name
                )),
            ));
        };
        return super::parallel::read(&mut s, &root, ctx);
    }
    let (big, hsize, zlib) = encoding(&root)?;
    let Body { field, pieces, appended } = scan_body(&mut s, d)?;
    if pieces.is_empty() {
        return Err(err(
            root.at,
            ErrorKind::Expected {
                expected: format!("a <Piece> in <{}>", kind.name),
                found: "none".into(),
            },
        ));
    }
    let mut app_offsets: Vec<usize> = field
        .iter()
        .chain(pieces.iter().flat_map(PieceBody::specs))
        .filter(|s| s.format == Format::Appended)
        .map(|s| s.offset)
        .collect();
    app_offsets.sort_unstable();
    app_offsets.dedup();
    let dec = Decoder { d, big, hsize, zlib, appended, app_offsets };
    let mut grids = Vec::with_capacity(pieces.len());
    for (i, p) in pieces.iter().enumerate() {
        let nc = p.cells_total();
        check_counts(d, p.np, nc, p.at)?;
        let mut g = Grid { points: read_points(&dec, &p.pts, p.np, p.at)?, ..Grid::default() };
        if kind.poly {
            super::pieces::read_poly_cells(&dec, p, &mut g)?;
        } else {
            read_cells(&dec, &p.cells, nc, p.np, p.at, &mut g)?;
        }
        // Dataset field data (tag names) once, with the first piece.
        let field: &[Spec] = if i == 0 { &field } else { &[] };
        read_data_arrays(&dec, &p.point, &p.cell, field, p.np, nc, &mut g)?;
        grids.push((g, p.at));
    }
    super::pieces::merge(grids)
}

/// What the root element says the file holds.
pub(super) struct Kind {
    /// The dataset element's name (`UnstructuredGrid`, `PolyData`...).
    pub(super) name: &'static str,
    /// PolyData rather than UnstructuredGrid.
    pub(super) poly: bool,
    /// A parallel file (`PUnstructuredGrid`, `PPolyData`) naming its pieces' files.
    pub(super) parallel: bool,
}

/// The root element, `<VTKFile type="...">` of a type smartmesh reads.
pub(super) fn root_tag<'a>(s: &mut Scan<'a>, d: &[u8]) -> Result<(Tag<'a>, Kind)> {
    let root = match s.next()? {
        Ev::Start(t) => t,
        Ev::End(_, p) => {
            return Err(err(
                p,
                ErrorKind::Expected { expected: "<VTKFile>".into(), found: "an end tag".into() },
            ))
        }
        Ev::Eof => {
            return Err(err(
                d.len(),
                ErrorKind::UnexpectedEof { context: "expected <VTKFile>".into() },
            ))
        }
    };
    if root.name != b"VTKFile" {
        return Err(err(
            root.at,
            ErrorKind::Expected {
                expected: "<VTKFile>".into(),
                found: format!("<{}>", String::from_utf8_lossy(root.name)),
            },
        ));
    }
    let kind = match root.attr("type") {
        Some(b"UnstructuredGrid") => Kind { name: "UnstructuredGrid", poly: false, parallel: false },
        Some(b"PolyData") => Kind { name: "PolyData", poly: true, parallel: false },
        Some(b"PUnstructuredGrid") => Kind { name: "PUnstructuredGrid", poly: false, parallel: true },
        Some(b"PPolyData") => Kind { name: "PPolyData", poly: true, parallel: true },
        other => {
            return Err(err(
                root.at,
                ErrorKind::Unsupported(format!(
                    "VTK XML type {}: smartmesh reads UnstructuredGrid (.vtu), PolyData (.vtp) and their parallel files (.pvtu, .pvtp)",
                    show(other.unwrap_or(b"(none)"))
                )),
            ))
        }
    };
    Ok((root, kind))
}

/// The encoding the root element declares: big-endian, the size of a header word, zlib.
fn encoding(root: &Tag<'_>) -> Result<(bool, usize, bool)> {
    let big = match root.attr("byte_order") {
        None | Some(b"LittleEndian") => false,
        Some(b"BigEndian") => true,
        Some(o) => {
            return Err(err(
                root.at,
                ErrorKind::Expected {
                    expected: "byte_order=\"LittleEndian\" or \"BigEndian\"".into(),
                    found: show(o),
                },
            ))
        }
    };
    let hsize = match root.attr("header_type") {
        None | Some(b"UInt32") => 4,
        Some(b"UInt64") => 8,
        Some(o) => {
            return Err(err(
                root.at,
                ErrorKind::Expected {
                    expected: "header_type=\"UInt32\" or \"UInt64\"".into(),
                    found: show(o),
                },
            ))
        }
    };
    let zlib = match root.attr("compressor") {
        None | Some(b"") => false,
        Some(b"vtkZLibDataCompressor") => true,
        Some(o) => {
            return Err(err(
                root.at,
                ErrorKind::Unsupported(format!(
                    "compressor {}: smartmesh reads zlib (vtkZLibDataCompressor) only",
                    show(o)
                )),
            ))
        }
    };
    Ok((big, hsize, zlib))
}

/// What the scan of the dataset finds: the dataset's field data, each piece, the
/// appended data.
#[derive(Default)]
struct Body {
    field: Vec<Spec>,
    pieces: Vec<PieceBody>,
    appended: Option<Appended>,
}

/// Scans the elements inside `<VTKFile>`, up to its end or to `<AppendedData>`.
fn scan_body(s: &mut Scan<'_>, d: &[u8]) -> Result<Body> {
    let mut body = Body::default();
    loop {
        match s.next()? {
            Ev::Start(t) if t.name == b"UnstructuredGrid" || t.name == b"PolyData" => {}
            Ev::Start(t) if t.name == b"FieldData" => read_array_specs(s, &t, &mut body.field)?,
            Ev::Start(t) if t.name == b"Piece" => {
                let mut p = PieceBody::new(&t)?;
                if !t.empty {
                    scan_piece(s, &t, &mut p)?;
                }
                body.pieces.push(p);
            }
            Ev::Start(t) if t.name == b"AppendedData" => {
                body.appended = Some(appended_data(&t, d)?);
                break;
            }
            Ev::Start(t) => s.skip_subtree(&t)?,
            Ev::End(b"UnstructuredGrid" | b"PolyData", _) => {}
            Ev::End(b"VTKFile", _) | Ev::Eof => break,
            Ev::End(n, p) => {
                return Err(err(
                    p,
                    ErrorKind::Expected {
                        expected: "</UnstructuredGrid>, </PolyData> or </VTKFile>".into(),
                        found: format!("</{}>", String::from_utf8_lossy(n)),
                    },
                ))
            }
        }
    }
    Ok(body)
}

/// Scans the containers of `<Piece>` `t`, up to `</Piece>`.
fn scan_piece<'a>(s: &mut Scan<'a>, t: &Tag<'a>, p: &mut PieceBody) -> Result<()> {
    loop {
        match s.next()? {
            Ev::Start(c) => match c.name {
                b"PointData" => read_array_specs(s, &c, &mut p.point)?,
                b"CellData" => read_array_specs(s, &c, &mut p.cell)?,
                b"Points" => {
                    read_array_specs(s, &c, &mut p.pts)?;
                    // VTK leaves the coordinates unnamed; messages name them.
                    for sp in p.pts.iter_mut().filter(|sp| sp.name.is_empty()) {
                        sp.name = "Points".into();
                    }
                }
                b"Cells" => read_array_specs(s, &c, &mut p.cells)?,
                b"Verts" => read_array_specs(s, &c, &mut p.poly[0])?,
                b"Lines" => read_array_specs(s, &c, &mut p.poly[1])?,
                b"Polys" => read_array_specs(s, &c, &mut p.poly[2])?,
                b"Strips" => read_array_specs(s, &c, &mut p.poly[3])?,
                _ => s.skip_subtree(&c)?,
            },
            Ev::End(b"Piece", _) => return Ok(()),
            Ev::End(n, p) => {
                return Err(err(
                    p,
                    ErrorKind::Expected {
                        expected: "</Piece>".into(),
                        found: format!("</{}>", String::from_utf8_lossy(n)),
                    },
                ))
            }
            Ev::Eof => {
                return Err(err(
                    t.at,
                    ErrorKind::UnexpectedEof { context: "<Piece> is not closed".into() },
                ))
            }
        }
    }
}

/// Where the data of `<AppendedData>` `t` lies, and how it is encoded.
fn appended_data(t: &Tag<'_>, d: &[u8]) -> Result<Appended> {
    let raw = match t.attr("encoding") {
        Some(b"raw") => true,
        Some(b"base64") | None => false,
        Some(o) => {
            return Err(err(
                t.at,
                ErrorKind::Expected {
                    expected: "encoding=\"raw\" or \"base64\"".into(),
                    found: show(o),
                },
            ))
        }
    };
    // The data starts after `_`; raw bytes may contain anything, so the
    // scan stops here.
    let us = memchr::memchr(b'_', &d[t.end..]).map(|i| t.end + i).ok_or_else(|| {
        err(
            t.end,
            ErrorKind::Expected {
                expected: "`_` before the appended data".into(),
                found: "none".into(),
            },
        )
    })?;
    let base = us + 1;
    let end = memchr::memmem::rfind(&d[base..], b"</AppendedData>").map_or(d.len(), |i| base + i);
    let end = if raw { end } else { base + crate::text::trim(&d[base..end]).len() };
    Ok(Appended { base, end, raw })
}

/// Piece sizes are attacker-controlled: each array is checked against its bytes
/// before it is allocated, and an empty file cannot claim a billion points.
/// A point needs 3 bytes of data and a cell 1 even at zlib's best ratio.
fn check_counts(d: &[u8], np: usize, nc: usize, piece_at: usize) -> Result<()> {
    for (n, what, per) in [(np, "NumberOfPoints", 3), (nc, "NumberOfCells", 1)] {
        let most = d.len().saturating_mul(MAX_INFLATE_RATIO) / per;
        if n > most {
            return Err(err(
                piece_at,
                ErrorKind::ImplausibleCount {
                    what: what.into(),
                    count: n as u64,
                    limit: format!(
                        "a file of {} bytes holds at most {most}, even compressed at zlib's 1032:1",
                        d.len()
                    ),
                },
            ));
        }
    }
    Ok(())
}

/// The `np` points, from the first `<Points>` array (none needed when `np` is 0).
fn read_points(
    dec: &Decoder<'_>,
    pts: &[Spec],
    np: usize,
    piece_at: usize,
) -> Result<Vec<[f64; 3]>> {
    let empty_points = Spec {
        name: "Points".into(),
        ty: Scalar::F64,
        components: 3,
        format: Format::Ascii,
        offset: 0,
        tuples: None,
        text: (0, 0),
        at: piece_at,
    };
    let p = match pts.first() {
        Some(p) => p,
        None if np == 0 => &empty_points,
        None => {
            return Err(err(
                piece_at,
                ErrorKind::Expected {
                    expected: "a <Points> DataArray".into(),
                    found: "none".into(),
                },
            ))
        }
    };
    if p.components != 3 && np > 0 {
        return Err(err(
            p.at,
            ErrorKind::Expected {
                expected: "3 components in Points".into(),
                found: p.components.to_string(),
            },
        ));
    }
    dec.points(p, np)
}

/// The number of values of `n` tuples of `sp`.
fn values(n: usize, sp: &Spec) -> Result<usize> {
    n.checked_mul(sp.components).ok_or_else(|| {
        err(
            sp.at,
            ErrorKind::ImplausibleCount {
                what: format!("values of `{}`", sp.name),
                count: sp.components as u64,
                limit: "too many components".into(),
            },
        )
    })
}

/// The `nc` cells (types, offsets, connectivity) of `<Cells>` into `g`.
pub(super) fn read_cells(
    dec: &Decoder<'_>,
    cells: &[Spec],
    nc: usize,
    np: usize,
    piece_at: usize,
    g: &mut Grid,
) -> Result<()> {
    let find = |name: &str| cells.iter().find(|s| s.name == name);
    if nc > 0 || !cells.is_empty() {
        let missing = |n: &str| {
            err(
                piece_at,
                ErrorKind::Expected {
                    expected: format!("a `{n}` DataArray in <Cells>"),
                    found: "none".into(),
                },
            )
        };
        let ty = find("types").ok_or_else(|| missing("types"))?;
        // Types and offsets are decoded straight into their final arrays.
        dec.ints_into(ty, nc, &mut g.types, "a VTK cell type (0 to 255)", |t| {
            u8::try_from(t).ok()
        })?;
        g.types_at = at(ty.at);
        let off = find("offsets").ok_or_else(|| missing("offsets"))?;
        g.offsets = Vec::with_capacity(nc + 1);
        g.offsets.push(0);
        dec.ints_into(off, nc, &mut g.offsets, "a cell end offset (0 or more)", |e| {
            usize::try_from(e).ok()
        })?;
        // Polygons and poly-lines have any number of nodes: the last offset is checked
        // against the connectivity's bytes before anything of that size is allocated.
        let bad_step = |w: &[usize]| w[1] < w[0];
        if g.offsets.windows(2).any(bad_step) {
            let i = g.offsets.windows(2).position(bad_step).unwrap_or(0);
            let (prev, e) = (g.offsets[i], g.offsets[i + 1]);
            return Err(err(
                off.at,
                ErrorKind::Inconsistent(format!("offsets must rise by the node count of each cell; cell {i} ends at {e} after {prev}")),
            ));
        }
        let prev = *g.offsets.last().unwrap_or(&0);
        let con = find("connectivity").ok_or_else(|| missing("connectivity"))?;
        g.connectivity = dec.indices(con, prev, np, &g.offsets)?;
        g.cells_at = at(con.at);
    } else {
        g.offsets = vec![0];
    }
    Ok(())
}

/// The point, cell and field data arrays into `g`.
fn read_data_arrays(
    dec: &Decoder<'_>,
    point: &[Spec],
    cell: &[Spec],
    field: &[Spec],
    np: usize,
    nc: usize,
    g: &mut Grid,
) -> Result<()> {
    for sp in point {
        let (values, layout) = dec.items(sp, values(np, sp)?)?;
        g.point_arrays.push(Named::new(
            sp.name.clone(),
            sp.components,
            values,
            layout,
            Position::Byte(sp.at as u64),
        ));
    }
    for sp in cell {
        // Integer cell tag arrays go straight into 32-bit tags (no f64 copy of them).
        if sp.components == 1 && !sp.ty.is_float() && tag_slot(&sp.name).is_some() {
            let mut tags = Vec::new();
            dec.ints_into(sp, values(nc, sp)?, &mut tags, "a 32-bit integer tag", |v| {
                i32::try_from(v).ok()
            })?;
            g.cell_tags.push((sp.name.clone(), tags, Position::Byte(sp.at as u64)));
            continue;
        }
        let (values, layout) = dec.items(sp, values(nc, sp)?)?;
        g.cell_arrays.push(Named::new(
            sp.name.clone(),
            sp.components,
            values,
            layout,
            Position::Byte(sp.at as u64),
        ));
    }
    for sp in field {
        // Field arrays other than numbers (strings) are skipped by `spec` refusing
        // them; the tuple count is optional. Only arrays of two values can name a tag
        // (`into_mesh`), so the others are not decoded at all.
        // Without a count, one that announces more than `UNCOUNTED_MAX` bytes is
        // skipped before anything is allocated.
        let count = sp.tuples.and_then(|t| t.checked_mul(sp.components));
        if count.is_some_and(|n| n != 2) {
            continue;
        }
        let values = match dec.floats(sp, count, false) {
            Err(e) if count.is_none() && matches!(e.kind, ErrorKind::ImplausibleCount { .. }) => {
                continue
            }
            r => r?,
        };
        g.field_arrays.push(Named::new(
            sp.name.clone(),
            sp.components,
            values,
            Layout::Plain,
            Position::Byte(sp.at as u64),
        ));
    }
    Ok(())
}
