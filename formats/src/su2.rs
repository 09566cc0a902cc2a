//! SU2 native mesh files (`.su2`), ASCII, 2D.
//!
//! Source: the SU2 documentation, *Mesh File* (su2code.github.io/docs_v7/Mesh-File):
//! `NDIME=` the dimension, `NELEM=` the interior elements, one per line as the VTK
//! type number then its 0-based point indices (an element index may follow),
//! `NPOIN=` the points, one per line as `NDIME` coordinates (a point index may
//! follow), `NMARK=` the boundary markers, each a `MARKER_TAG=` name then
//! `MARKER_ELEMS=` and its elements. `%` starts a comment. A multi-zone file starts
//! with `NZONE=` and opens each zone with `IZONE=`. Element types (VTK's): line 3,
//! triangle 5, quadrilateral 9; tetrahedron 10, hexahedron 12, prism 13, pyramid 14.
//!
//! Read:
//! - the sections in any order within a zone; blank and `%` lines anywhere;
//!   `KEY=value`, `KEY= value` and `KEY = value` alike; `NPOIN=` may carry a second
//!   number (the count of points owned by a partition), which is ignored, and each
//!   point or element line may end with one or two integers (indices), ignored too;
//! - interior triangles and quads get the zone's number (1-based) as physical and
//!   geometrical tag, unnamed: SU2 names no volume;
//! - each marker's lines get one tag of dimension 1 named from `MARKER_TAG`; a marker
//!   named `tag<N>` (as this writer names an unnamed tag) is tag N without a name, the
//!   others are numbered 1, 2, … in file order around those numbers; a name given
//!   twice is one tag;
//! - several zones (`NZONE`): read as one mesh, each zone's points apart (SU2 zones do
//!   not share points), the report saying so;
//! - `NDIME= 3`, the 3D cells (10, 12, 13, 14) and any other type are refused naming
//!   the line; so are counts past the bytes left (nothing is allocated for them),
//!   point indices past `NPOIN`, and `NMARK`/`NZONE` counts the file does not keep;
//! - free-form deformation boxes (`FFD_NBOX=` and what follows, written by SU2's
//!   shape design tools after the mesh) end the mesh; the report says they were left.
//!
//! Write: the layout of the documentation's example, with its comment headers:
//! `NDIME= 2`, `NELEM=` with every triangle and quad (element index last), `NPOIN=`
//! with `x y index` (shortest round-trip decimals), `NMARK=` with one marker per
//! physical tag of the line cells, in increasing tag order, each cell in mesh order.
//! A marker is named from the tag name, made a single SU2 word (blanks, `=`, `%`,
//! parentheses and commas, which SU2's configuration files cannot hold in a marker
//! name, become `_`); an unnamed tag `p` is `tag<p>`; both are reported. The report
//! lists what SU2 cannot hold: face tags, point and cell data, sets, z coordinates,
//! vertex cells, second-order nodes (cells written by their corners).

use std::collections::BTreeMap;

use crate::mesh::node_index;
use crate::text::{check_count, parse_f64, parse_i64, push_f64, push_int, show, trim};
use crate::{
    CellBlock, CellKind, Error, ErrorKind, ReadContext, ReadReport, Result, TaggedMesh,
    WriteOptions, WriteReport, Written,
};

/// The reader checks every index and coordinate it reads (see [`crate::Checks`]).
pub(crate) const CHECKS: crate::Checks =
    crate::Checks { reader_validates: true, writer_validates: false };

/// SU2's (VTK's) element type numbers.
const LINE: i64 = 3;
const TRIANGLE: i64 = 5;
const QUAD: i64 = 9;

/// The name of an SU2 element type, for messages.
fn type_name(t: i64) -> Option<&'static str> {
    Some(match t {
        1 => "vertex",
        LINE => "line",
        TRIANGLE => "triangle",
        QUAD => "quadrilateral",
        10 => "tetrahedron",
        12 => "hexahedron",
        13 => "prism",
        14 => "pyramid",
        _ => return None,
    })
}

// ---------------------------------------------------------------------------------
// Reading

/// The non-blank, non-comment lines of the file, each with its 1-based number.
struct Records<'a> {
    data: &'a [u8],
    pos: usize,
    line: u64,
}

impl<'a> Records<'a> {
    /// The next record (comment cut, trimmed, not empty) and its line.
    fn next(&mut self) -> Option<(u64, &'a [u8])> {
        while self.pos < self.data.len() {
            let start = self.pos;
            let end =
                memchr::memchr(b'\n', &self.data[start..]).map_or(self.data.len(), |i| start + i);
            self.pos = end + 1;
            self.line += 1;
            let raw = &self.data[start..end];
            let raw = memchr::memchr(b'%', raw).map_or(raw, |i| &raw[..i]);
            let rec = trim(raw);
            if !rec.is_empty() {
                return Some((self.line, rec));
            }
        }
        None
    }

    fn bytes_left(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    /// The next record, or an end-of-file error naming what was expected.
    fn expect(&mut self, what: &str) -> Result<(u64, &'a [u8])> {
        let line = self.line + 1;
        self.next().ok_or_else(|| {
            Error::at_line(line, ErrorKind::UnexpectedEof { context: format!("expected {what}") })
        })
    }
}

/// Splits a record into its blank-separated words.
fn words(rec: &[u8]) -> impl Iterator<Item = &[u8]> {
    rec.split(|c| c.is_ascii_whitespace()).filter(|w| !w.is_empty())
}

/// A `KEY= value` record: the key (upper-cased) and the value, both trimmed.
fn keyword(rec: &[u8]) -> Option<(String, &[u8])> {
    let eq = memchr::memchr(b'=', rec)?;
    let key = String::from_utf8_lossy(trim(&rec[..eq])).to_ascii_uppercase();
    Some((key, trim(&rec[eq + 1..])))
}

/// The first word of `value` as a count, checked against the bytes left.
fn count(
    value: &[u8],
    line: u64,
    what: &str,
    bytes_left: usize,
    min_bytes: usize,
) -> Result<usize> {
    let first = words(value).next().unwrap_or(b"");
    match parse_i64(first) {
        Some(n) if n >= 0 => check_count(n as usize, bytes_left, min_bytes, what)
            .map_err(|k| Error::at_line(line, k)),
        _ => Err(Error::expected(line, format!("{what} (a non-negative integer)"), show(first))),
    }
}

/// The interior element or marker element of one record: its kind and 0-based nodes.
fn element(rec: &[u8], line: u64, interior: bool, nodes: &mut Vec<usize>) -> Result<CellKind> {
    let mut w = words(rec);
    let first = w.next().unwrap_or(b"");
    let t = parse_i64(first)
        .ok_or_else(|| Error::expected(line, "an SU2 element type number", show(first)))?;
    let (kind, expected) = match (t, interior) {
        (TRIANGLE, true) => (CellKind::Triangle, 3),
        (QUAD, true) => (CellKind::Quad, 4),
        (LINE, false) => (CellKind::Line, 2),
        (10 | 12 | 13 | 14, _) => {
            return Err(Error::at_line(
                line,
                ErrorKind::Unsupported(format!(
                    "SU2 element type {t} ({}) is a 3D cell; smartmesh reads 2D SU2 meshes (lines, triangles, quadrilaterals)",
                    type_name(t).unwrap_or("?")
                )),
            ))
        }
        _ => {
            let place = if interior {
                "an interior element of a 2D mesh: triangle (5) or quadrilateral (9)"
            } else {
                "a marker element of a 2D mesh: line (3)"
            };
            let found = match type_name(t) {
                Some(n) => format!("type {t} ({n})"),
                None => format!("type {t}, which SU2 does not define"),
            };
            return Err(Error::expected(line, place, found));
        }
    };
    nodes.clear();
    for tok in w {
        match parse_i64(tok) {
            Some(v) if v >= 0 => nodes.push(v as usize),
            _ => {
                return Err(Error::expected(
                    line,
                    "a point index (a non-negative integer)",
                    show(tok),
                ))
            }
        }
    }
    // The nodes, then at most an element index (and a second number some writers add).
    if nodes.len() < expected || nodes.len() > expected + 2 {
        return Err(Error::expected(
            line,
            format!(
                "{expected} point indices after element type {t} (then an optional element index)"
            ),
            format!("{} numbers", nodes.len()),
        ));
    }
    nodes.truncate(expected);
    Ok(kind)
}

/// One zone being read.
#[derive(Default)]
struct Zone {
    /// Index of the zone's first point in the mesh.
    first_point: usize,
    npoin: Option<usize>,
    nmark: Option<(usize, u64)>,
    markers: usize,
    /// The largest point index an element of the zone names, and its line.
    max_node: Option<(usize, u64)>,
    ndime_seen: bool,
    nelem_seen: bool,
}

impl Zone {
    fn check_end(&self, number: usize, line: u64) -> Result<()> {
        let npoin = self.npoin.unwrap_or(0);
        if let Some((node, at)) = self.max_node {
            if node >= npoin {
                return Err(Error::at_line(
                    at,
                    ErrorKind::IndexOutOfRange {
                        what: format!("an element of zone {number}"),
                        index: node as i64,
                        available: npoin,
                    },
                ));
            }
        }
        if !self.ndime_seen {
            return Err(Error::expected(line, format!("`NDIME=` in zone {number}"), "none"));
        }
        if let Some((n, at)) = self.nmark {
            if n != self.markers {
                return Err(Error::at_line(
                    at,
                    ErrorKind::Inconsistent(format!(
                        "NMARK= {n} but zone {number} has {} markers (MARKER_TAG=)",
                        self.markers
                    )),
                ));
            }
        }
        Ok(())
    }
}

/// Reads an SU2 mesh.
pub fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_reported(bytes, ctx).map(|(m, _)| m)
}

/// [`read`], with what was left or merged ([`ReadReport`]).
pub fn read_reported(bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<(TaggedMesh, ReadReport)> {
    let mut report = ReadReport::default();
    let mut r = Records { data: bytes, pos: 0, line: 0 };
    let mut mesh = TaggedMesh::new();
    // Marker names in order of first appearance, and each marker's lines.
    let mut marker_names: Vec<String> = Vec::new();
    let mut marker_lines: Vec<CellBlock> = Vec::new();
    let mut nzone: Option<(usize, u64)> = None;
    let mut zone_number = 1usize;
    let mut zones_seen = 0usize;
    let mut zone = Zone::default();
    let mut in_zone = false;
    let mut current_marker: Option<usize> = None;
    let mut nodes = Vec::with_capacity(4);
    let mut last_line = 0;
    while let Some((line, rec)) = r.next() {
        last_line = line;
        let Some((key, value)) = keyword(rec) else {
            return Err(Error::expected(
                line,
                "an SU2 keyword (`NDIME=`, `NELEM=`, `NPOIN=`, `NMARK=`, …)",
                show(rec),
            ));
        };
        if key.starts_with("FFD_") {
            report.note(format!(
                "line {line}: the free-form deformation boxes (`{key}=` and after) are not mesh and were left"
            ));
            break;
        }
        let number = |what: &str| -> Result<i64> {
            let first = words(value).next().unwrap_or(b"");
            parse_i64(first).ok_or_else(|| Error::expected(line, what.to_string(), show(first)))
        };
        match key.as_str() {
            "NZONE" => {
                if in_zone || nzone.is_some() {
                    return Err(Error::expected(line, "`NZONE=` once, before every zone", "`NZONE=` here"));
                }
                let n = count(value, line, "NZONE", r.bytes_left() + 1, 8)?;
                nzone = Some((n, line));
            }
            "IZONE" => {
                let k = number("a zone number after `IZONE=`")?;
                if in_zone {
                    zone.check_end(zone_number, line)?;
                }
                zones_seen += 1;
                if k != zones_seen as i64 {
                    return Err(Error::expected(line, format!("`IZONE= {zones_seen}`"), format!("`IZONE= {k}`")));
                }
                zone_number = zones_seen;
                zone = Zone { first_point: mesh.points.len(), ..Zone::default() };
                in_zone = true;
                current_marker = None;
            }
            "NDIME" => {
                in_zone = true;
                if zone.ndime_seen {
                    return Err(Error::expected(line, "one `NDIME=` per zone", "a second one"));
                }
                zone.ndime_seen = true;
                match number("the dimension after `NDIME=` (2 or 3)")? {
                    2 => {}
                    3 => {
                        return Err(Error::at_line(
                            line,
                            ErrorKind::Unsupported(
                                "3D SU2 meshes (NDIME= 3): smartmesh's meshes carry 2D cells only (lines, triangles, quadrilaterals)".into(),
                            ),
                        ))
                    }
                    d => return Err(Error::expected(line, "`NDIME= 2` or `NDIME= 3`", format!("`NDIME= {d}`"))),
                }
            }
            "NELEM" => {
                in_zone = true;
                if zone.nelem_seen {
                    return Err(Error::expected(line, "one `NELEM=` per zone", "a second one"));
                }
                zone.nelem_seen = true;
                let n = count(value, line, "NELEM", r.bytes_left(), 6)?;
                let tag = i32::try_from(zone_number).unwrap_or(i32::MAX);
                for _ in 0..n {
                    let (l, rec) = r.expect("an interior element")?;
                    let kind = element(rec, l, true, &mut nodes)?;
                    note_max(&mut zone, &nodes, l);
                    let shifted = shift(&nodes, zone.first_point, l)?;
                    mesh.block_mut(kind).push(&shifted[..nodes.len()], tag, tag);
                }
            }
            "NPOIN" => {
                in_zone = true;
                if zone.npoin.is_some() {
                    return Err(Error::expected(line, "one `NPOIN=` per zone", "a second one"));
                }
                let n = count(value, line, "NPOIN", r.bytes_left(), 4)?;
                if mesh.points.len() + n >= crate::MAX_POINTS {
                    return Err(Error::at_line(line, crate::mesh::past_max_points("NPOIN", mesh.points.len() + n)));
                }
                zone.npoin = Some(n);
                mesh.points.reserve(n);
                for _ in 0..n {
                    let (l, rec) = r.expect("a point")?;
                    mesh.points.push(point(rec, l)?);
                }
            }
            "NMARK" => {
                in_zone = true;
                if zone.nmark.is_some() {
                    return Err(Error::expected(line, "one `NMARK=` per zone", "a second one"));
                }
                let n = count(value, line, "NMARK", r.bytes_left() + 1, 12)?;
                zone.nmark = Some((n, line));
            }
            "MARKER_TAG" => {
                if zone.nmark.is_none() {
                    return Err(Error::expected(line, "`NMARK=` before the first `MARKER_TAG=`", "`MARKER_TAG=`"));
                }
                if value.is_empty() {
                    return Err(Error::expected(line, "a marker name after `MARKER_TAG=`", "nothing"));
                }
                let name = String::from_utf8_lossy(value).into_owned();
                zone.markers += 1;
                let i = match marker_names.iter().position(|n| *n == name) {
                    Some(i) => i,
                    None => {
                        marker_names.push(name);
                        marker_lines.push(CellBlock::new(CellKind::Line));
                        marker_names.len() - 1
                    }
                };
                current_marker = Some(i);
            }
            "MARKER_ELEMS" => {
                let Some(i) = current_marker.take() else {
                    return Err(Error::expected(line, "`MARKER_TAG=` before `MARKER_ELEMS=`", "`MARKER_ELEMS=`"));
                };
                let n = count(value, line, "MARKER_ELEMS", r.bytes_left(), 6)?;
                for _ in 0..n {
                    let (l, rec) = r.expect("a marker element")?;
                    element(rec, l, false, &mut nodes)?;
                    note_max(&mut zone, &nodes, l);
                    let shifted = shift(&nodes, zone.first_point, l)?;
                    // Tags are given once every name is known (see `marker_tags`).
                    marker_lines[i].push(&shifted[..2], i as i32, i as i32);
                }
            }
            _ => {
                return Err(Error::expected(
                    line,
                    "an SU2 keyword (NDIME, NELEM, NPOIN, NMARK, MARKER_TAG, MARKER_ELEMS, NZONE, IZONE)",
                    format!("`{}=`", crate::text::quote_prefix(key.as_bytes())),
                ))
            }
        }
    }
    if !in_zone && mesh.points.is_empty() {
        return Err(Error::expected(last_line.max(1), "an SU2 mesh (`NDIME=` …)", "none"));
    }
    zone.check_end(zone_number, last_line.max(1))?;
    if let Some((n, at)) = nzone {
        if n != zones_seen.max(1) {
            return Err(Error::at_line(
                at,
                ErrorKind::Inconsistent(format!(
                    "NZONE= {n} but the file has {} zones (IZONE=)",
                    zones_seen.max(1)
                )),
            ));
        }
    }
    if zones_seen > 1 {
        report.note(format!(
            "{zones_seen} zones read as one mesh: the interior cells of zone k have tag k, and each zone keeps its own points (SU2 zones share none)"
        ));
    }
    let tags = marker_tags(&marker_names);
    for (i, mut block) in marker_lines.into_iter().enumerate() {
        let (tag, name) = &tags[i];
        block.physical.fill(*tag);
        block.geometrical.fill(*tag);
        if let Some(name) = name {
            mesh.tag_names.insert((1, *tag), name.clone());
        }
        if !block.is_empty() {
            mesh.blocks.push(block);
        }
    }
    mesh.coordinate_dim = 2;
    Ok((mesh, report))
}

/// Records the largest point index of an element, for the check at the zone's end.
fn note_max(zone: &mut Zone, nodes: &[usize], line: u64) {
    let m = nodes.iter().copied().max().unwrap_or(0);
    if zone.max_node.map_or(true, |(old, _)| m > old) {
        zone.max_node = Some((m, line));
    }
}

/// Point indices of a zone moved past the zones before it, checked against 32 bits.
fn shift(nodes: &[usize], first: usize, line: u64) -> Result<[crate::NodeIndex; 4]> {
    let mut out = [0; 4];
    for (o, &n) in out.iter_mut().zip(nodes) {
        *o = node_index(n.saturating_add(first)).map_err(|k| Error::at_line(line, k))?;
    }
    Ok(out)
}

/// A point record: two finite coordinates, then at most two integers.
fn point(rec: &[u8], line: u64) -> Result<[f64; 3]> {
    let mut w = words(rec);
    let mut p = [0.0; 3];
    for (k, c) in p.iter_mut().take(2).enumerate() {
        let what = if k == 0 { "an x coordinate" } else { "a y coordinate" };
        let tok = w.next().ok_or_else(|| Error::expected(line, what, "the end of the line"))?;
        *c = match parse_f64(tok) {
            Ok(v) if v.is_finite() => v,
            Ok(_) => {
                return Err(Error::at_line(
                    line,
                    ErrorKind::NonFinite { what: what.into(), value: show(tok) },
                ))
            }
            Err(()) => return Err(Error::expected(line, what, show(tok))),
        };
    }
    for (k, tok) in w.enumerate() {
        if k >= 2 || parse_i64(tok).is_none() {
            return Err(Error::expected(
                line,
                "2 coordinates then an optional point index (NDIME= 2)",
                show(tok),
            ));
        }
    }
    Ok(p)
}

/// The tag and name of each marker: `tag<N>` is tag N unnamed; the others are numbered
/// 1, 2, … in order, skipping the numbers `tag<N>` markers take.
fn marker_tags(names: &[String]) -> Vec<(i32, Option<String>)> {
    let generated: Vec<Option<i32>> = names.iter().map(|n| generated_tag(n)).collect();
    let taken: std::collections::BTreeSet<i32> = generated.iter().flatten().copied().collect();
    let mut next = 1;
    names
        .iter()
        .zip(generated)
        .map(|(name, g)| match g {
            Some(t) => (t, None),
            None => {
                while taken.contains(&next) {
                    next += 1;
                }
                next += 1;
                (next - 1, Some(name.clone()))
            }
        })
        .collect()
}

/// N when `name` is `tag<N>` (N an integer written without a sign or leading zeros).
fn generated_tag(name: &str) -> Option<i32> {
    let digits = name.strip_prefix("tag")?;
    let v: i32 = digits.parse().ok()?;
    (v >= 0 && v.to_string() == digits).then_some(v)
}

// ---------------------------------------------------------------------------------
// Writing

/// `name` as one SU2 marker word: blanks and the characters SU2's mesh and
/// configuration files give a meaning (`=`, `%`, parentheses, commas, `;`) become `_`.
fn marker_word(name: &str) -> String {
    name.trim()
        .chars()
        .map(|c| if c.is_whitespace() || c.is_control() || "=%(),;".contains(c) { '_' } else { c })
        .collect()
}

/// Writes a mesh as an SU2 file.
pub fn write(mesh: &TaggedMesh, _opts: &WriteOptions) -> Result<Written> {
    let mut report = WriteReport::default();
    report_unheld(mesh, &mut report);
    let mut out = Vec::with_capacity(64 + 24 * mesh.points.len() + 16 * mesh.num_cells());
    out.extend_from_slice(
        b"% SU2 mesh written by smartmesh\n%\n% Problem dimension\n%\nNDIME= 2\n",
    );

    // Interior elements: triangles and quads (second order by their corners).
    let interior: Vec<&CellBlock> = mesh.blocks.iter().filter(|b| b.kind.dim() == 2).collect();
    let nelem: usize = interior.iter().map(|b| b.len()).sum();
    out.extend_from_slice(b"%\n% Inner element connectivity\n%\nNELEM= ");
    push_int(&mut out, nelem);
    out.push(b'\n');
    let mut index = 0usize;
    let mut face_tags = BTreeMap::new();
    for b in &interior {
        let (t, corners) = match b.kind {
            CellKind::Triangle | CellKind::Triangle6 => (TRIANGLE, 3),
            _ => (QUAD, 4),
        };
        for (i, c) in b.cells().enumerate() {
            push_int(&mut out, t);
            for &v in &c[..corners] {
                out.push(b' ');
                push_int(&mut out, v);
            }
            out.push(b' ');
            push_int(&mut out, index);
            out.push(b'\n');
            index += 1;
            *face_tags.entry(b.physical[i]).or_insert(0usize) += 1;
        }
    }
    if face_tags.keys().any(|&t| t != 1) {
        let list: Vec<String> = face_tags
            .iter()
            .map(|(&t, n)| match mesh.tag_name(2, t) {
                Some(name) => format!("{t} `{name}` ({n} cells)"),
                None => format!("{t} ({n} cells)"),
            })
            .collect();
        report.drop(format!(
            "face tags {}: SU2 names no volume, so the interior cells read back with tag 1 (zone 1)",
            list.join(", ")
        ));
    }

    out.extend_from_slice(b"%\n% Node coordinates\n%\nNPOIN= ");
    push_int(&mut out, mesh.points.len());
    out.push(b'\n');
    let mut with_z = 0usize;
    for (i, p) in mesh.points.iter().enumerate() {
        if !p[0].is_finite() || !p[1].is_finite() {
            return Err(crate::io::refused(crate::Format::Su2, mesh));
        }
        push_f64(&mut out, p[0]);
        out.push(b' ');
        push_f64(&mut out, p[1]);
        out.push(b' ');
        push_int(&mut out, i);
        out.push(b'\n');
        with_z += usize::from(p[2] != 0.0);
    }
    if with_z > 0 {
        report.drop(format!(
            "the z coordinates of {with_z} points: a 2D SU2 mesh (NDIME= 2) holds x and y"
        ));
    }

    // Markers: the line cells grouped by physical tag, in increasing tag order.
    let mut by_tag: BTreeMap<i32, Vec<[crate::NodeIndex; 2]>> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 1) {
        for (i, c) in b.cells().enumerate() {
            by_tag.entry(b.physical[i]).or_default().push([c[0], c[1]]);
        }
    }
    out.extend_from_slice(b"%\n% Boundary elements\n%\nNMARK= ");
    push_int(&mut out, by_tag.len());
    out.push(b'\n');
    let mut used: BTreeMap<String, i32> = BTreeMap::new();
    for (&tag, cells) in &by_tag {
        let name = marker_name(mesh, tag, &used, &mut report);
        used.insert(name.clone(), tag);
        out.extend_from_slice(b"MARKER_TAG= ");
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(b"\nMARKER_ELEMS= ");
        push_int(&mut out, cells.len());
        out.push(b'\n');
        for c in cells {
            out.extend_from_slice(b"3 ");
            push_int(&mut out, c[0]);
            out.push(b' ');
            push_int(&mut out, c[1]);
            out.push(b'\n');
        }
    }
    for (&(d, t), name) in &mesh.tag_names {
        if d == 1 && !by_tag.contains_key(&t) {
            report.drop(format!("tag name `{name}` (dimension 1, tag {t}) names no line cell; SU2 keeps a marker only with its elements"));
        }
    }
    Ok(Written { main: out, siblings: Vec::new(), report })
}

/// The marker name of line tag `tag`, reported when it is not the tag name as it stands.
fn marker_name(
    mesh: &TaggedMesh,
    tag: i32,
    used: &BTreeMap<String, i32>,
    report: &mut WriteReport,
) -> String {
    let generated = format!("tag{tag}");
    let name = match mesh.tag_name(1, tag) {
        None => {
            report.drop(format!(
                "line tag {tag} has no name: written as marker `{generated}` (read back as tag {tag})"
            ));
            generated
        }
        Some(orig) => {
            let word = marker_word(orig);
            if word.is_empty() {
                report.drop(format!(
                    "line tag {tag}'s name `{orig}` is blank: written as marker `{generated}`"
                ));
                generated
            } else if generated_tag(&word).is_some_and(|t| t != tag) {
                report.drop(format!("line tag {tag}'s name `{orig}` would read back as another tag: written as marker `{generated}`"));
                generated
            } else {
                if word != orig {
                    report.drop(format!("line tag {tag}'s name `{orig}` written as marker `{word}`: an SU2 marker name is one word without `=`, `%`, parentheses or commas"));
                }
                word
            }
        }
    };
    if let Some(other) = used.get(&name) {
        let unique = format!("{name}_tag{tag}");
        report.drop(format!(
            "line tags {other} and {tag} share the marker name `{name}`: tag {tag} written as `{unique}`"
        ));
        return unique;
    }
    name
}

/// What SU2 cannot hold at all, and what it holds only in part.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    for (name, a) in &mesh.point_data {
        report.drop(format!(
            "point data `{name}` ({} components): an SU2 mesh holds no fields",
            a.expanded_components()
        ));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({} components): an SU2 mesh holds no fields",
            a.expanded_components()
        ));
    }
    let differ: usize = mesh
        .blocks
        .iter()
        .filter(|b| b.kind.dim() == 1)
        .map(|b| b.physical.iter().zip(&b.geometrical).filter(|(p, g)| p != g).count())
        .sum();
    if differ > 0 {
        report.drop(format!("geometrical tags of {differ} line cells: SU2 keeps one marker per boundary element, the physical tag"));
    }
    let vertices = mesh.num_cells_of(CellKind::Vertex);
    if vertices > 0 {
        report.drop(format!(
            "{vertices} vertex cells: a 2D SU2 mesh holds lines, triangles and quadrilaterals"
        ));
    }
    for kind in [CellKind::Line3, CellKind::Triangle6, CellKind::Quad8, CellKind::Quad9] {
        let n = mesh.num_cells_of(kind);
        if n > 0 {
            report.drop(format!("the mid-edge nodes of {n} {} cells: SU2 meshes are first order (written by their corners)", kind.name()));
        }
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("the entity table ({} entities): SU2 has none", mesh.entities.len()));
    }
    for name in mesh.point_sets.keys() {
        report.drop(format!("point set `{name}`: SU2 holds no sets"));
    }
    for name in mesh.cell_sets.keys() {
        report.drop(format!("cell set `{name}`: SU2 holds no sets"));
    }
    if !mesh.holes.is_empty() {
        report.drop(format!("{} hole points: SU2 holds none", mesh.holes.len()));
    }
    if !mesh.regions.is_empty() {
        report.drop(format!("{} region seeds: SU2 holds none", mesh.regions.len()));
    }
}
