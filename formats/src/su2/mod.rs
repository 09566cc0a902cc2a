//! SU2 native mesh files (`.su2`), ASCII, 2D and 3D.
//!
//! Source: the SU2 documentation, *Mesh File* (su2code.github.io/docs_v7/Mesh-File):
//! `NDIME=` the dimension, `NELEM=` the interior elements, one per line as the VTK
//! type number then its 0-based point indices (an element index may follow),
//! `NPOIN=` the points, one per line as `NDIME` coordinates (a point index may
//! follow), `NMARK=` the boundary markers, each a `MARKER_TAG=` name then
//! `MARKER_ELEMS=` and its elements. `%` starts a comment. A multi-zone file starts
//! with `NZONE=` and opens each zone with `IZONE=`. Element types (VTK's): line 3,
//! triangle 5, quadrilateral 9; tetrahedron 10, hexahedron 12, prism 13, pyramid 14.
//! The nodes of each element are in VTK's order (the documentation's figures), which is
//! Gmsh's for every kind but the prism: VTK's prism 0-1-2 turns clockwise seen from
//! 3-4-5, Gmsh's counter-clockwise, so SU2's prism is Gmsh's 0 2 1 3 5 4 (what Gmsh's
//! own SU2 and VTK exports write, checked with Gmsh 4.15).
//!
//! Read:
//! - the sections in any order within a zone; blank and `%` lines anywhere;
//!   `KEY=value`, `KEY= value` and `KEY = value` alike; `NPOIN=` may carry a second
//!   number (the count of points owned by a partition), which is ignored, and each
//!   point or element line may end with one or two integers (indices), ignored too;
//! - `NDIME= 2`: interior triangles and quads, markers of lines, points of 2
//!   coordinates; `NDIME= 3`: interior tetrahedra, hexahedra, prisms and pyramids,
//!   markers of triangles and quads, points of 3 coordinates. `NDIME=` comes before
//!   the zone's other sections, which need it;
//! - interior cells get the zone's number (1-based) as physical and geometrical tag,
//!   unnamed: SU2 names no volume;
//! - each marker's cells get one tag of dimension NDIME - 1 named from `MARKER_TAG`; a marker
//!   named `tag<N>` (as this writer names an unnamed tag) is tag N without a name, the
//!   others are numbered 1, 2, … in file order around those numbers; a name given
//!   twice is one tag;
//! - several zones (`NZONE`): read as one mesh, each zone's points apart (SU2 zones do
//!   not share points), the report saying so;
//! - an element type the zone's dimension does not take (a tetrahedron in a 2D mesh,
//!   a line marker in a 3D one) and any other type are refused naming the line; so
//!   are counts past the bytes left (nothing is allocated for them),
//!   point indices past `NPOIN`, and `NMARK`/`NZONE` counts the file does not keep;
//! - free-form deformation boxes (`FFD_NBOX=` and what follows, written by SU2's
//!   shape design tools after the mesh) end the mesh; the report says they were left.
//!
//! Write ([`write()`]): the layout of the documentation's example, with its comment
//! headers. A mesh with volume cells is 3D: `NDIME= 3`, `NELEM=` with every volume cell
//! (element index last), `NPOIN=` with `x y z index`, `NMARK=` with one marker per
//! physical tag of the triangles and quads; otherwise 2D: `NDIME= 2`, the triangles and
//! quads inside, `x y index`, a marker per tag of the line cells. Markers in increasing
//! tag order, each cell in mesh order.
//! A marker is named from the tag name, made a single SU2 word (blanks, `=`, `%`,
//! parentheses and commas, which SU2's configuration files cannot hold in a marker
//! name, become `_`); an unnamed tag `p` is `tag<p>`; both are reported. The report
//! lists what SU2 cannot hold: interior tags, point and cell data, sets, z coordinates
//! of a 2D mesh, cells of a lower dimension than the markers', second-order nodes
//! (cells written by their corners).

mod write;

pub use write::write;

use crate::mesh::node_index;
use crate::text::{check_count, parse_f64, parse_i64, show, trim};
use crate::{CellBlock, CellKind, Error, ErrorKind, ReadContext, ReadReport, Result, TaggedMesh};

/// The reader checks every index and coordinate it reads (see [`crate::Checks`]).
pub(crate) const CHECKS: crate::Checks =
    crate::Checks { reader_validates: true, writer_validates: false };

/// SU2's (VTK's) element type numbers.
const LINE: i64 = 3;
const TRIANGLE: i64 = 5;
const QUAD: i64 = 9;
const TETRA: i64 = 10;
const HEXA: i64 = 12;
const PRISM: i64 = 13;
const PYRAMID: i64 = 14;

/// The SU2 type of a linear kind.
fn su2_type(kind: CellKind) -> Option<i64> {
    Some(match kind {
        CellKind::Line => LINE,
        CellKind::Triangle => TRIANGLE,
        CellKind::Quad => QUAD,
        CellKind::Tetra => TETRA,
        CellKind::Hexa => HEXA,
        CellKind::Wedge => PRISM,
        CellKind::Pyramid => PYRAMID,
        _ => return None,
    })
}

/// Which Gmsh node each SU2 (VTK) position of a linear kind holds: the prism's
/// triangles turn the other way (see the module header); an involution, so the same
/// table converts both ways.
fn su2_order(kind: CellKind) -> &'static [usize] {
    const IDENTITY: [usize; 8] = [0, 1, 2, 3, 4, 5, 6, 7];
    match kind {
        CellKind::Wedge => &[0, 2, 1, 3, 5, 4],
        k => &IDENTITY[..k.nodes_per_cell().min(8)],
    }
}

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

/// The interior element or marker element of one record in a zone of dimension
/// `ndime`: its kind and 0-based nodes in Gmsh's order.
fn element(
    rec: &[u8],
    line: u64,
    interior: bool,
    ndime: u8,
    nodes: &mut Vec<usize>,
) -> Result<CellKind> {
    let mut w = words(rec);
    let first = w.next().unwrap_or(b"");
    let t = parse_i64(first)
        .ok_or_else(|| Error::expected(line, "an SU2 element type number", show(first)))?;
    let kind = match (t, interior, ndime) {
        (TRIANGLE, true, 2) | (TRIANGLE, false, 3) => CellKind::Triangle,
        (QUAD, true, 2) | (QUAD, false, 3) => CellKind::Quad,
        (LINE, false, 2) => CellKind::Line,
        (TETRA, true, 3) => CellKind::Tetra,
        (HEXA, true, 3) => CellKind::Hexa,
        (PRISM, true, 3) => CellKind::Wedge,
        (PYRAMID, true, 3) => CellKind::Pyramid,
        _ => {
            let place = match (interior, ndime) {
                (true, 2) => "an interior element of a 2D mesh: triangle (5) or quadrilateral (9)",
                (false, 2) => "a marker element of a 2D mesh: line (3)",
                (true, _) => "an interior element of a 3D mesh: tetrahedron (10), hexahedron (12), prism (13) or pyramid (14)",
                (false, _) => "a marker element of a 3D mesh: triangle (5) or quadrilateral (9)",
            };
            let found = match type_name(t) {
                Some(n) => format!("type {t} ({n})"),
                None => format!("type {t}, which SU2 does not define"),
            };
            return Err(Error::expected(line, place, found));
        }
    };
    let expected = kind.nodes_per_cell();
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
    if kind == CellKind::Wedge {
        let su2 = [nodes[0], nodes[1], nodes[2], nodes[3], nodes[4], nodes[5]];
        for (n, &k) in nodes.iter_mut().zip(su2_order(kind)) {
            *n = su2[k];
        }
    }
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
    /// `NDIME=` of the zone, once read.
    ndime: Option<u8>,
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
        if self.ndime.is_none() {
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
    // Marker names in order of first appearance, and each marker's cells (a block per
    // run of one kind, in file order).
    let mut marker_names: Vec<String> = Vec::new();
    let mut marker_cells: Vec<Vec<CellBlock>> = Vec::new();
    let mut dims = [false; 2];
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
                if zone.ndime.is_some() {
                    return Err(Error::expected(line, "one `NDIME=` per zone", "a second one"));
                }
                if zone.npoin.is_some() || zone.nelem_seen || zone.nmark.is_some() {
                    return Err(Error::expected(line, "`NDIME=` first in its zone", "`NDIME=` after the zone's elements or points"));
                }
                match number("the dimension after `NDIME=` (2 or 3)")? {
                    d @ (2 | 3) => {
                        zone.ndime = Some(d as u8);
                        dims[d as usize - 2] = true;
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
                    let kind = element(rec, l, true, zone_dim(&zone, line)?, &mut nodes)?;
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
                    mesh.points.push(point(rec, l, zone_dim(&zone, line)?)?);
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
                        marker_cells.push(Vec::new());
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
                    let kind = element(rec, l, false, zone_dim(&zone, line)?, &mut nodes)?;
                    note_max(&mut zone, &nodes, l);
                    let shifted = shift(&nodes, zone.first_point, l)?;
                    let blocks = &mut marker_cells[i];
                    if blocks.last().map(|b| b.kind) != Some(kind) {
                        blocks.push(CellBlock::new(kind));
                    }
                    // Tags are given once every name is known (see `marker_tags`).
                    let block = blocks.last_mut().expect("just pushed");
                    block.push(&shifted[..nodes.len()], i as i32, i as i32);
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
    for (i, blocks) in marker_cells.into_iter().enumerate() {
        let (tag, name) = &tags[i];
        for mut block in blocks {
            block.physical.fill(*tag);
            block.geometrical.fill(*tag);
            if let Some(name) = name {
                mesh.tag_names.insert((block.kind.dim(), *tag), name.clone());
            }
            mesh.blocks.push(block);
        }
    }
    mesh.coordinate_dim = if dims[1] { 3 } else { 2 };
    Ok((mesh, report))
}

/// Records the largest point index of an element, for the check at the zone's end.
fn note_max(zone: &mut Zone, nodes: &[usize], line: u64) {
    let m = nodes.iter().copied().max().unwrap_or(0);
    if zone.max_node.map_or(true, |(old, _)| m > old) {
        zone.max_node = Some((m, line));
    }
}

/// The dimension of the zone, which a section at `line` needs.
fn zone_dim(zone: &Zone, line: u64) -> Result<u8> {
    zone.ndime.ok_or_else(|| {
        Error::expected(line, "`NDIME=` before the zone's elements and points", "none")
    })
}

/// Point indices of a zone moved past the zones before it, checked against 32 bits.
fn shift(nodes: &[usize], first: usize, line: u64) -> Result<[crate::NodeIndex; 8]> {
    let mut out = [0; 8];
    for (o, &n) in out.iter_mut().zip(nodes) {
        *o = node_index(n.saturating_add(first)).map_err(|k| Error::at_line(line, k))?;
    }
    Ok(out)
}

/// A point record: `ndime` finite coordinates, then at most two integers.
fn point(rec: &[u8], line: u64, ndime: u8) -> Result<[f64; 3]> {
    let mut w = words(rec);
    let mut p = [0.0; 3];
    for (k, c) in p.iter_mut().take(ndime as usize).enumerate() {
        let what = ["an x coordinate", "a y coordinate", "a z coordinate"][k];
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
                format!("{ndime} coordinates then an optional point index (NDIME= {ndime})"),
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
