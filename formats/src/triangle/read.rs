//! Reading Triangle's file set. Each file is parsed on its own into a small record of
//! what it lists; `read` then chooses the vertex list, resolves indices and builds the
//! mesh (see the module documentation of `triangle` for the rules).

use std::borrow::Cow;

use crate::error::{Error, ErrorKind, Result};
use crate::scan::Scan;
use crate::text::{check_count, parse_f64, parse_i64, Tokens};
use crate::{
    CellBlock, CellKind, DataArray, NodeIndex, ReadContext, RegionSeed, TaggedMesh, MAX_POINTS,
};

use super::{attribute_name, Kind, AREA, MARKER, RAY_DIRECTION};

/// A vertex list (`.node`, or the first section of a `.poly`).
#[derive(Debug, Default)]
struct NodeList {
    xy: Vec<[f64; 2]>,
    nattr: usize,
    /// `nattr` values per vertex.
    attrs: Vec<f64>,
    markers: Option<Vec<i32>>,
    /// Number of the first vertex: 0 or 1.
    base: i64,
}

/// Segments or edges, and the rays of a Voronoi `.edge`.
#[derive(Debug, Default)]
struct Lines {
    nodes: Vec<NodeIndex>,
    tags: Vec<i32>,
    /// `(origin, marker, direction)`.
    rays: Vec<(NodeIndex, i32, [f64; 2])>,
}

/// What a `.poly` lists besides its vertices.
#[derive(Debug, Default)]
struct PolyRest {
    segments: Lines,
    holes: Vec<[f64; 2]>,
    regions: Vec<RegionSeed>,
}

/// Triangles of a `.ele`, 0-based and already in smartmesh's node order.
#[derive(Debug)]
struct Ele {
    kind: CellKind,
    nodes: Vec<NodeIndex>,
    nattr: usize,
    attrs: Vec<f64>,
}

impl Ele {
    fn len(&self) -> usize {
        self.nodes.len() / self.kind.nodes_per_cell()
    }
}

// ---------------------------------------------------------------------------------------
// Line-by-line records
// ---------------------------------------------------------------------------------------

/// Moves to the next record (skipping blank lines and comments) and returns its line;
/// an end-of-file error naming `what` when there is none.
fn start(t: &mut Tokens<'_>, what: impl FnOnce() -> String) -> Result<u64> {
    t.skip_space();
    if t.remaining().is_empty() {
        return Err(t.error(ErrorKind::UnexpectedEof { context: format!("expected {}", what()) }));
    }
    Ok(t.line())
}

/// The fields of one record (one line), read left to right. Triangle reads a record from
/// one line only: a missing required field is an error at that line, a missing optional
/// field takes its default, extra fields are ignored.
struct Rec<'t, 'a> {
    t: &'t mut Tokens<'a>,
    line: u64,
    item: &'static str,
    num: usize,
}

impl<'t, 'a> Rec<'t, 'a> {
    fn new(t: &'t mut Tokens<'a>, line: u64, item: &'static str, num: usize) -> Self {
        Rec { t, line, item, num }
    }

    fn describe(&self, what: &str) -> String {
        if self.num == 0 {
            format!("{what} in the {}", self.item)
        } else {
            format!("{what} of {} {}", self.item, self.num)
        }
    }

    /// Whether another field follows on this line.
    #[inline]
    fn more(&mut self) -> bool {
        !self.t.at_line_end()
    }

    #[inline]
    fn tok(&mut self, what: &str) -> Result<&'a [u8]> {
        if self.t.at_line_end() {
            return Err(Error::expected(self.line, self.describe(what), "end of line"));
        }
        match self.t.next() {
            Some(tok) => Ok(tok),
            None => Err(Error::expected(self.line, self.describe(what), "end of file")),
        }
    }

    #[inline]
    fn f64(&mut self, what: &str) -> Result<f64> {
        let tok = self.tok(what)?;
        match parse_f64(tok) {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(Error::at_line(
                self.line,
                ErrorKind::NonFinite { what: self.describe(what), value: crate::text::show(tok) },
            )),
            Err(()) => Err(self.bad(what, tok)),
        }
    }

    #[inline]
    fn opt_f64(&mut self, what: &str, default: f64) -> Result<f64> {
        if self.more() {
            self.f64(what)
        } else {
            Ok(default)
        }
    }

    #[inline]
    fn int(&mut self, what: &str) -> Result<i64> {
        let tok = self.tok(what)?;
        parse_i64(tok).ok_or_else(|| self.bad(&format!("{what} (an integer)"), tok))
    }

    #[inline]
    fn opt_int(&mut self, what: &str, default: i64) -> Result<i64> {
        if self.more() {
            self.int(what)
        } else {
            Ok(default)
        }
    }

    /// An optional marker: an integer that fits in 32 bits.
    #[inline]
    fn opt_marker(&mut self) -> Result<i32> {
        let v = self.opt_int("boundary marker", 0)?;
        i32::try_from(v).map_err(|_| {
            Error::expected(
                self.line,
                self.describe("boundary marker (a 32-bit integer)"),
                v.to_string(),
            )
        })
    }

    /// A count of items that need at least `min_bytes` bytes each in what remains.
    fn count(&mut self, what: &str, min_bytes: usize) -> Result<usize> {
        let v = self.int(what)?;
        self.check_count(what, v, min_bytes)
    }

    fn check_count(&self, what: &str, v: i64, min_bytes: usize) -> Result<usize> {
        if v < 0 {
            return Err(Error::expected(
                self.line,
                format!("{what} (a non-negative integer)"),
                v.to_string(),
            ));
        }
        let n = usize::try_from(v).unwrap_or(usize::MAX);
        check_count(n, self.t.remaining().len(), min_bytes, what)
            .map_err(|k| Error::at_line(self.line, k))
    }

    /// A vertex index as written, turned into a 0-based index below `n`.
    #[inline]
    fn index(&mut self, what: &str, base: i64, n: usize) -> Result<NodeIndex> {
        let v = self.int(what)?;
        match v.checked_sub(base) {
            Some(i) if i >= 0 && (i as u64) < n.min(MAX_POINTS) as u64 => Ok(i as NodeIndex),
            _ => {
                let mut what = self.describe(what);
                if v < base {
                    what.push_str(&format!(", numbered from {base} as the first vertex is,"));
                }
                Err(Error::at_line(
                    self.line,
                    ErrorKind::IndexOutOfRange { what, index: v, available: n },
                ))
            }
        }
    }

    /// The item number at the start of a record: checked to be an integer, otherwise
    /// ignored (Triangle numbers items by position).
    #[inline]
    fn number(&mut self) -> Result<i64> {
        self.int("number")
    }

    fn bad(&self, what: &str, tok: &[u8]) -> Error {
        Error::expected(self.line, self.describe(what), crate::text::show(tok))
    }

    /// Skips whatever else is on the line.
    #[inline]
    fn end(self) {
        self.t.rest_of_line();
    }
}

// ---------------------------------------------------------------------------------------
// The fast path: whole records of plain numbers on one line each
// ---------------------------------------------------------------------------------------

/// Records with more attributes than this always take the general path.
const FAST_ATTRIBUTES: usize = 8;

impl Scan<'_> {
    #[inline(always)]
    fn next_f64(&mut self) -> Option<f64> {
        self.blank();
        self.f64()
    }

    #[inline(always)]
    fn next_i32(&mut self) -> Option<i32> {
        self.blank();
        self.int().and_then(|v| i32::try_from(v).ok())
    }

    #[inline(always)]
    fn next_index(&mut self, base: i64, n: usize) -> Option<NodeIndex> {
        self.blank();
        let v = self.int()?.checked_sub(base)?;
        (v >= 0 && (v as u64) < n.min(MAX_POINTS) as u64).then_some(v as NodeIndex)
    }
}

/// Reads up to `max` records `<number> <fields...>` whose fields `fields` parses, and
/// hands each to `push`, as long as every record is complete, on one line, and nothing
/// else is on that line. Returns how many were read; the tokenizer is moved past them,
/// and the general path takes the record that stopped it (with its defaults, comments
/// and errors).
#[inline(always)]
fn fast<R>(
    t: &mut Tokens<'_>,
    max: usize,
    mut fields: impl FnMut(&mut Scan<'_>) -> Option<R>,
    mut push: impl FnMut(R),
    enabled: bool,
) -> usize {
    if !enabled {
        return 0;
    }
    let mut s = Scan::new(t.data(), t.pos());
    let (mut done, mut end) = (0, t.pos());
    while done < max {
        s.ws();
        if s.int().is_none() {
            break;
        }
        let Some(r) = fields(&mut s) else { break };
        if !s.eol() {
            break;
        }
        push(r);
        done += 1;
        end = s.pos;
    }
    t.seek(end);
    done
}

// ---------------------------------------------------------------------------------------
// One parser per file
// ---------------------------------------------------------------------------------------

/// The vertex list: `<n> [<dim> [<#attributes> [<#markers>]]]`, then one vertex a line.
fn parse_nodes(t: &mut Tokens<'_>, file: &str) -> Result<NodeList> {
    let line = start(t, || {
        format!(
            "the header of the {file} file (number of vertices, dimension, attributes, markers)"
        )
    })?;
    let mut r = Rec::new(t, line, "header", 0);
    // A vertex record is at least "1 0 0\n".
    let n = r.count("number of vertices", 6)?;
    if n > MAX_POINTS {
        return Err(Error::at_line(line, crate::mesh::past_max_points("vertices", n)));
    }
    let dim = r.opt_int("dimension", 2)?;
    if dim != 2 {
        return Err(Error::expected(
            line,
            "dimension 2 (Triangle is two-dimensional)",
            dim.to_string(),
        ));
    }
    let nattr = r.opt_int("number of attributes", 0)?;
    // Attributes may be left out of the records (they are then 0), so the check is that
    // the file could be this big at all, not that each record holds them.
    let nattr = r.check_count("number of attributes", nattr, 1)?;
    check_count(n.saturating_mul(nattr), r.t.remaining().len(), 1, "vertex attributes")
        .map_err(|k| Error::at_line(line, k))?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    if !(0..=1).contains(&nmarkers) {
        return Err(Error::expected(line, "0 or 1 boundary markers", nmarkers.to_string()));
    }
    r.end();
    let mut list = NodeList {
        xy: Vec::with_capacity(n),
        nattr,
        attrs: Vec::with_capacity(n * nattr),
        markers: (nmarkers == 1).then(|| Vec::with_capacity(n)),
        base: 1,
    };
    let mut i = 0;
    while i < n {
        if i > 0 {
            i += fast(
                t,
                n - i,
                |s| {
                    let (x, y) = (s.next_f64()?, s.next_f64()?);
                    let mut a = [0.0; FAST_ATTRIBUTES];
                    for slot in a.iter_mut().take(nattr) {
                        *slot = s.next_f64()?;
                    }
                    let m = if nmarkers == 1 { Some(s.next_i32()?) } else { None };
                    Some((x, y, a, m))
                },
                |(x, y, a, m)| {
                    list.xy.push([x, y]);
                    list.attrs.extend_from_slice(&a[..nattr]);
                    if let (Some(ms), Some(m)) = (list.markers.as_mut(), m) {
                        ms.push(m);
                    }
                },
                nattr <= FAST_ATTRIBUTES,
            );
            if i == n {
                break;
            }
        }
        let line = start(t, || format!("vertex {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "vertex", i + 1);
        let number = r.number()?;
        if i == 0 {
            list.base = match number {
                0 | 1 => number,
                _ => {
                    return Err(Error::expected(
                        line,
                        "0 or 1 as the number of the first vertex",
                        number.to_string(),
                    ))
                }
            };
        }
        let x = r.f64("x coordinate")?;
        let y = r.f64("y coordinate")?;
        list.xy.push([x, y]);
        for _ in 0..nattr {
            let a = r.opt_f64("attribute", 0.0)?;
            list.attrs.push(a);
        }
        if let Some(m) = list.markers.as_mut() {
            m.push(r.opt_marker()?);
        }
        r.end();
        i += 1;
    }
    Ok(list)
}

/// The triangles: `<n> [<nodes per triangle> [<#attributes>]]`, then one triangle a line.
fn parse_ele(t: &mut Tokens<'_>, nv: usize, base: i64) -> Result<Ele> {
    let line = start(t, || {
        "the header of the .ele file (number of triangles, nodes per triangle, attributes)".into()
    })?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of triangles", 8)?;
    let corners = r.opt_int("nodes per triangle", 3)?;
    let kind = match corners {
        3 => CellKind::Triangle,
        6 => CellKind::Triangle6,
        _ => {
            return Err(Error::at_line(
                line,
                ErrorKind::Unsupported(format!(
                    "triangles with {corners} nodes (Triangle writes 3, or 6 with -o2)"
                )),
            ))
        }
    };
    let nattr = r.opt_int("number of attributes", 0)?;
    let nattr = r.check_count("number of attributes", nattr, 1)?;
    check_count(n.saturating_mul(nattr), r.t.remaining().len(), 1, "triangle attributes")
        .map_err(|k| Error::at_line(line, k))?;
    r.end();
    let k = kind.nodes_per_cell();
    let mut ele =
        Ele { kind, nodes: Vec::with_capacity(n * k), nattr, attrs: Vec::with_capacity(n * nattr) };
    let mut v = [0 as NodeIndex; 6];
    let mut i = 0;
    while i < n {
        i += fast(
            t,
            n - i,
            |s| {
                let mut w = [0 as NodeIndex; 6];
                for slot in w.iter_mut().take(k) {
                    *slot = s.next_index(base, nv)?;
                }
                let mut a = [0.0; FAST_ATTRIBUTES];
                for slot in a.iter_mut().take(nattr) {
                    *slot = s.next_f64()?;
                }
                Some((w, a))
            },
            |(w, a)| {
                if k == 6 {
                    ele.nodes.extend_from_slice(&[w[0], w[1], w[2], w[5], w[3], w[4]]);
                } else {
                    ele.nodes.extend_from_slice(&w[..3]);
                }
                ele.attrs.extend_from_slice(&a[..nattr]);
            },
            nattr <= FAST_ATTRIBUTES,
        );
        if i == n {
            break;
        }
        let line = start(t, || format!("triangle {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "triangle", i + 1);
        r.number()?;
        for slot in v.iter_mut().take(k) {
            *slot = r.index("vertex", base, nv)?;
        }
        if k == 6 {
            // Triangle: nodes 4, 5, 6 lie opposite corners 1, 2, 3 (on edges 2-3, 3-1,
            // 1-2); smartmesh (as Gmsh) wants edges 1-2, 2-3, 3-1.
            ele.nodes.extend_from_slice(&[v[0], v[1], v[2], v[5], v[3], v[4]]);
        } else {
            ele.nodes.extend_from_slice(&v[..3]);
        }
        for _ in 0..nattr {
            let a = r.opt_f64("attribute", 0.0)?;
            ele.attrs.push(a);
        }
        r.end();
        i += 1;
    }
    Ok(ele)
}

/// Segments: `<n> [<#markers>]`, then `<#> <end> <end> [marker]`.
fn parse_segments(t: &mut Tokens<'_>, nv: usize, base: i64, file: &str) -> Result<Lines> {
    let line = start(t, || {
        format!("the segment header of the {file} file (number of segments, markers)")
    })?;
    let mut r = Rec::new(t, line, "segment header", 0);
    let n = r.count("number of segments", 6)?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    if !(0..=1).contains(&nmarkers) {
        return Err(Error::expected(line, "0 or 1 boundary markers", nmarkers.to_string()));
    }
    r.end();
    let mut lines =
        Lines { nodes: Vec::with_capacity(2 * n), tags: Vec::with_capacity(n), rays: Vec::new() };
    let mut i = 0;
    while i < n {
        i += fast(
            t,
            n - i,
            |s| {
                let (a, b) = (s.next_index(base, nv)?, s.next_index(base, nv)?);
                let m = if nmarkers == 1 { s.next_i32()? } else { 0 };
                Some((a, b, m))
            },
            |(a, b, m)| {
                lines.nodes.extend_from_slice(&[a, b]);
                lines.tags.push(m);
            },
            true,
        );
        if i == n {
            break;
        }
        let line = start(t, || format!("segment {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "segment", i + 1);
        r.number()?;
        let a = r.index("first endpoint", base, nv)?;
        let b = r.index("second endpoint", base, nv)?;
        let m = if nmarkers == 1 { r.opt_marker()? } else { 0 };
        r.end();
        lines.nodes.extend_from_slice(&[a, b]);
        lines.tags.push(m);
        i += 1;
    }
    Ok(lines)
}

/// Holes: `<n>`, then `<#> <x> <y>`.
fn parse_holes(t: &mut Tokens<'_>, file: &str) -> Result<Vec<[f64; 2]>> {
    let line = start(t, || format!("the number of holes in the {file} file"))?;
    let mut r = Rec::new(t, line, "hole header", 0);
    let n = r.count("number of holes", 6)?;
    r.end();
    let mut holes = Vec::with_capacity(n);
    for i in 0..n {
        let line = start(t, || format!("hole {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "hole", i + 1);
        r.number()?;
        let x = r.f64("x coordinate")?;
        let y = r.f64("y coordinate")?;
        r.end();
        holes.push([x, y]);
    }
    Ok(holes)
}

/// Regions (optional section): `<n>`, then `<#> <x> <y> <attribute> [<max area>]`; a
/// missing area takes the attribute's value, as Triangle reads it.
fn parse_regions(t: &mut Tokens<'_>) -> Result<Vec<RegionSeed>> {
    t.skip_space();
    if t.remaining().is_empty() {
        return Ok(Vec::new());
    }
    let line = t.line();
    let mut r = Rec::new(t, line, "region header", 0);
    let n = r.count("number of regions", 8)?;
    r.end();
    let mut regions = Vec::with_capacity(n);
    for i in 0..n {
        let line = start(t, || format!("region {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "region", i + 1);
        r.number()?;
        let x = r.f64("x coordinate")?;
        let y = r.f64("y coordinate")?;
        let attribute = r.f64("regional attribute or area constraint")?;
        let max_area = r.opt_f64("maximum area", attribute)?;
        r.end();
        regions.push(RegionSeed { point: [x, y], attribute, max_area });
    }
    Ok(regions)
}

/// What follows the vertex list of a `.poly`: segments, holes and the optional regions.
/// Anything after the regions is ignored, as Triangle ignores it.
fn parse_poly_rest(t: &mut Tokens<'_>, nv: usize, base: i64) -> Result<PolyRest> {
    let segments = parse_segments(t, nv, base, ".poly")?;
    let holes = parse_holes(t, ".poly")?;
    let regions = parse_regions(t)?;
    Ok(PolyRest { segments, holes, regions })
}

/// Edges: `<n> [<#markers>]`, then `<#> <end> <end> [marker]`, or for the infinite rays
/// of a Voronoi diagram `<#> <end> -1 <dx> <dy> [marker]`.
fn parse_edges(t: &mut Tokens<'_>, nv: usize, base: i64) -> Result<Lines> {
    let line = start(t, || "the header of the .edge file (number of edges, markers)".into())?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of edges", 6)?;
    let nmarkers = r.opt_int("number of boundary markers", 0)?;
    if !(0..=1).contains(&nmarkers) {
        return Err(Error::expected(line, "0 or 1 boundary markers", nmarkers.to_string()));
    }
    r.end();
    let mut lines =
        Lines { nodes: Vec::with_capacity(2 * n), tags: Vec::with_capacity(n), rays: Vec::new() };
    let mut i = 0;
    while i < n {
        // Rays (second endpoint -1) are left to the general path.
        i += fast(
            t,
            n - i,
            |s| {
                let (a, b) = (s.next_index(base, nv)?, s.next_index(base, nv)?);
                let m = if nmarkers == 1 { s.next_i32()? } else { 0 };
                Some((a, b, m))
            },
            |(a, b, m)| {
                lines.nodes.extend_from_slice(&[a, b]);
                lines.tags.push(m);
            },
            true,
        );
        if i == n {
            break;
        }
        let line = start(t, || format!("edge {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "edge", i + 1);
        r.number()?;
        let a = r.index("first endpoint", base, nv)?;
        // -1 is never a vertex (numbering starts at 0 or 1): it marks a ray.
        let save = r.t.clone();
        let second = r.int("second endpoint")?;
        if second == -1 {
            let dx = r.f64("ray direction x")?;
            let dy = r.f64("ray direction y")?;
            let m = if nmarkers == 1 { r.opt_marker()? } else { 0 };
            r.end();
            lines.rays.push((a, m, [dx, dy]));
            i += 1;
            continue;
        }
        *r.t = save;
        let b = r.index("second endpoint", base, nv)?;
        let m = if nmarkers == 1 { r.opt_marker()? } else { 0 };
        r.end();
        lines.nodes.extend_from_slice(&[a, b]);
        lines.tags.push(m);
        i += 1;
    }
    Ok(lines)
}

/// Area bounds: `<n>`, then `<#> [<area>]` (no area, or a negative one: no bound).
fn parse_area(t: &mut Tokens<'_>, ntri: usize) -> Result<Vec<f64>> {
    let line = start(t, || "the number of triangles in the .area file".into())?;
    let mut r = Rec::new(t, line, "header", 0);
    let n = r.count("number of triangles", 4)?;
    if n != ntri {
        return Err(Error::at_line(
            line,
            ErrorKind::Inconsistent(format!(
                "the .area file lists {n} triangles, the .ele file {ntri}"
            )),
        ));
    }
    r.end();
    let mut areas = Vec::with_capacity(n);
    let mut i = 0;
    while i < n {
        i += fast(t, n - i, |s| s.next_f64(), |a| areas.push(a), true);
        if i == n {
            break;
        }
        let line = start(t, || format!("triangle {} of {n}", i + 1))?;
        let mut r = Rec::new(t, line, "triangle", i + 1);
        r.number()?;
        areas.push(r.opt_f64("maximum area", -1.0)?);
        r.end();
        i += 1;
    }
    Ok(areas)
}

fn tokens(bytes: &[u8]) -> Tokens<'_> {
    Tokens::with_comments(bytes, b'#')
}

// ---------------------------------------------------------------------------------------
// The set
// ---------------------------------------------------------------------------------------

/// Reads the main file and the set beside it.
pub(super) fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    // Records are lines: a lone carriage return ends one too.
    let bytes = &*crate::text::lone_cr_as_newline(bytes);
    let Some(main) = Kind::from_ext(&ctx.extension) else {
        return read_stream(bytes);
    };
    // Siblings are read only when the rules below need them.
    let load = |k: Kind| -> Result<Option<Cow<'_, [u8]>>> {
        if k == main {
            Ok(Some(Cow::Borrowed(bytes)))
        } else {
            Ok(ctx.siblings.read_sibling(k.ext())?.map(|b| {
                match crate::text::lone_cr_as_newline(&b) {
                    Cow::Owned(fixed) => Cow::Owned(fixed),
                    Cow::Borrowed(_) => Cow::Owned(b),
                }
            }))
        }
    };
    // Errors in a sibling name the sibling; those in the main file get its path from the
    // caller.
    let in_file = |k: Kind| {
        move |e: Error| if k == main { e } else { e.with_path(ctx.siblings.describe(k.ext())) }
    };

    let node_bytes = load(Kind::Node)?;
    let node = match &node_bytes {
        Some(b) => Some(parse_nodes(&mut tokens(b), ".node").map_err(in_file(Kind::Node))?),
        None => None,
    };

    // The .poly: its own vertex list, or 0 vertices and the .node's.
    let poly_bytes = load(Kind::Poly)?;
    let mut poly_nodes = None;
    let mut poly_rest = None;
    if let Some(b) = &poly_bytes {
        let mut t = tokens(b);
        let own = parse_nodes(&mut t, ".poly").map_err(in_file(Kind::Poly))?;
        let (nv, base) = if !own.xy.is_empty() {
            if let Some(node) = &node {
                if node.xy.len() != own.xy.len()
                    || node.xy.iter().zip(&own.xy).any(|(a, b)| {
                        a[0].to_bits() != b[0].to_bits() || a[1].to_bits() != b[1].to_bits()
                    })
                {
                    return Err(Error::new(ErrorKind::Inconsistent(format!(
                        "{} lists its own {} vertices, which differ from the {} of {}; read one of the two files without the other",
                        ctx.siblings.describe("poly"),
                        own.xy.len(),
                        node.xy.len(),
                        ctx.siblings.describe("node"),
                    ))));
                }
            }
            (own.xy.len(), own.base)
        } else if let Some(node) = &node {
            (node.xy.len(), node.base)
        } else {
            return Err(Error::new(ErrorKind::Inconsistent(format!(
                "{} lists 0 vertices, which means that they are in {}, but there is no such file",
                ctx.siblings.describe("poly"),
                ctx.siblings.describe("node")
            ))));
        };
        poly_rest = Some(parse_poly_rest(&mut t, nv, base).map_err(in_file(Kind::Poly))?);
        if !own.xy.is_empty() {
            poly_nodes = Some(own);
        }
    }

    // The vertex list of the set: the main file's when it has one, else the .node's.
    let verts = match (node, poly_nodes) {
        (Some(_), Some(p)) if main == Kind::Poly => p,
        (Some(n), _) => n,
        (None, Some(p)) => p,
        (None, None) => {
            return Err(Error::new(ErrorKind::Inconsistent(format!(
                "the vertices of this {} file are in {}, which does not exist",
                main.ext(),
                ctx.siblings.describe("node")
            ))))
        }
    };
    let nv = verts.xy.len();

    let ele = match load(Kind::Ele)? {
        Some(b) => Some(parse_ele(&mut tokens(&b), nv, verts.base).map_err(in_file(Kind::Ele))?),
        None => None,
    };

    // Line cells: from the main file when it is a .poly or .edge, else the .poly, else
    // the .edge.
    let use_edge = main == Kind::Edge || poly_rest.is_none();
    let mut lines = None;
    if use_edge {
        if let Some(b) = load(Kind::Edge)? {
            lines =
                Some(parse_edges(&mut tokens(&b), nv, verts.base).map_err(in_file(Kind::Edge))?);
        }
    }
    let (segments, holes, regions) = match poly_rest {
        Some(p) => (Some(p.segments), p.holes, p.regions),
        None => (None, Vec::new(), Vec::new()),
    };
    if !use_edge {
        lines = segments;
    }

    let area = match load(Kind::Area)? {
        Some(b) => {
            let Some(ele) = &ele else {
                return Err(Error::new(ErrorKind::Inconsistent(format!(
                    "{} bounds the areas of the triangles of {}, which does not exist",
                    ctx.siblings.describe("area"),
                    ctx.siblings.describe("ele")
                ))));
            };
            Some(parse_area(&mut tokens(&b), ele.len()).map_err(in_file(Kind::Area))?)
        }
        None => None,
    };

    Ok(assemble(verts, ele, lines, holes, regions, area))
}

/// A stream: a `.node`, or a `.poly` with its own vertices.
fn read_stream(bytes: &[u8]) -> Result<TaggedMesh> {
    let mut t = tokens(bytes);
    let verts = parse_nodes(&mut t, ".node or .poly")?;
    t.skip_space();
    if t.remaining().is_empty() {
        return Ok(assemble(verts, None, None, Vec::new(), Vec::new(), None));
    }
    if verts.xy.is_empty() {
        return Err(t.error(ErrorKind::Inconsistent(
            "this .poly lists 0 vertices, which means that they are in a .node file beside it; a stream has none (read the file by its path)".into(),
        )));
    }
    let rest = parse_poly_rest(&mut t, verts.xy.len(), verts.base)?;
    Ok(assemble(verts, None, Some(rest.segments), rest.holes, rest.regions, None))
}

/// Builds the mesh: blocks in the order rays (Vertex), lines, triangles; cell data over
/// all of them.
fn assemble(
    verts: NodeList,
    ele: Option<Ele>,
    lines: Option<Lines>,
    holes: Vec<[f64; 2]>,
    regions: Vec<RegionSeed>,
    area: Option<Vec<f64>>,
) -> TaggedMesh {
    let mut mesh = TaggedMesh::new();
    let nv = verts.xy.len();
    mesh.points = verts.xy.iter().map(|&[x, y]| [x, y, 0.0]).collect();
    if let Some(m) = &verts.markers {
        mesh.point_data
            .insert(MARKER.into(), DataArray::new(1, m.iter().map(|&v| v as f64).collect()));
    }
    for k in 0..verts.nattr {
        let values = (0..nv).map(|i| verts.attrs[i * verts.nattr + k]).collect();
        mesh.point_data.insert(attribute_name(k + 1), DataArray::new(1, values));
    }

    let lines = lines.unwrap_or_default();
    let nrays = lines.rays.len();
    let nlines = lines.tags.len();
    if nrays > 0 {
        let mut b = CellBlock::new(CellKind::Vertex);
        for &(origin, m, _) in &lines.rays {
            b.push(&[origin], m, m);
        }
        mesh.blocks.push(b);
    }
    if nlines > 0 {
        mesh.blocks.push(CellBlock {
            kind: CellKind::Line,
            nodes: lines.nodes,
            physical: lines.tags.clone(),
            geometrical: lines.tags,
        });
    }
    let before = nrays + nlines;
    let ntri = ele.as_ref().map_or(0, Ele::len);
    let total = before + ntri;

    if nrays > 0 {
        let mut dir = vec![0.0; 3 * total];
        for (i, &(_, _, [dx, dy])) in lines.rays.iter().enumerate() {
            dir[3 * i] = dx;
            dir[3 * i + 1] = dy;
        }
        mesh.cell_data.insert(RAY_DIRECTION.into(), DataArray::new(3, dir));
    }

    if let Some(ele) = ele {
        // The first attribute is the tag when every triangle's is an integer.
        let first_is_tag = ele.nattr > 0
            && (0..ntri).all(|i| {
                let a = ele.attrs[i * ele.nattr];
                a.fract() == 0.0 && a >= i32::MIN as f64 && a <= i32::MAX as f64
            });
        let tags: Vec<i32> = if first_is_tag {
            (0..ntri).map(|i| ele.attrs[i * ele.nattr] as i32).collect()
        } else {
            vec![0; ntri]
        };
        for k in 0..ele.nattr {
            let mut values = vec![0.0; total];
            for i in 0..ntri {
                values[before + i] = ele.attrs[i * ele.nattr + k];
            }
            mesh.cell_data.insert(attribute_name(k + 1), DataArray::new(1, values));
        }
        if let Some(area) = area {
            let mut values = vec![-1.0; total];
            values[before..].copy_from_slice(&area);
            mesh.cell_data.insert(AREA.into(), DataArray::new(1, values));
        }
        if ntri > 0 {
            mesh.blocks.push(CellBlock {
                kind: ele.kind,
                nodes: ele.nodes,
                physical: tags.clone(),
                geometrical: tags,
            });
        }
    }
    mesh.holes = holes;
    mesh.regions = regions;
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MemorySiblings, NoSiblings};

    fn ctx<'a>(sib: &'a MemorySiblings, ext: &str) -> ReadContext<'a> {
        ReadContext { siblings: sib, extension: ext.into() }
    }

    fn set(files: &[(&str, &str)]) -> MemorySiblings {
        MemorySiblings {
            files: files.iter().map(|(e, s)| (e.to_string(), s.as_bytes().to_vec())).collect(),
        }
    }

    #[test]
    fn missing_fields_take_triangle_defaults() {
        let sib = set(&[]);
        let m = read(b"3 2 2 1\n1 0 0\n2 1 0 7\n3 0 1 7 8 9\n", &ctx(&sib, "node")).unwrap();
        assert_eq!(m.point_data["triangle:attribute1"].values, vec![0.0, 7.0, 7.0]);
        assert_eq!(m.point_data["triangle:attribute2"].values, vec![0.0, 0.0, 8.0]);
        assert_eq!(m.point_data[MARKER].values, vec![0.0, 0.0, 9.0]);
    }

    #[test]
    fn region_without_area_takes_its_attribute() {
        let sib = set(&[]);
        let m = read(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n0\n1\n1 0.2 0.2 5\n", &ctx(&sib, "poly"))
            .unwrap();
        assert_eq!(
            m.regions,
            vec![RegionSeed { point: [0.2, 0.2], attribute: 5.0, max_area: 5.0 }]
        );
    }

    #[test]
    fn second_order_triangles_are_reordered() {
        let sib = set(&[("node", "6 2 0 0\n0 0 0\n1 2 0\n2 0 2\n3 1 1\n4 0 1\n5 1 0\n")]);
        let m = read(b"1 6 0\n0 0 1 2 3 4 5\n", &ctx(&sib, "ele")).unwrap();
        assert_eq!(m.blocks[0].kind, CellKind::Triangle6);
        // Triangle: 3 opposite corner 0 (edge 1-2), 4 opposite 1 (edge 2-0), 5 opposite 2 (edge 0-1).
        assert_eq!(m.blocks[0].nodes, vec![0, 1, 2, 5, 3, 4]);
    }

    #[test]
    fn stream_is_node_or_poly() {
        let c = ReadContext { siblings: &NoSiblings, extension: String::new() };
        let m = read(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n", &c).unwrap();
        assert_eq!(m.points.len(), 3);
        let m = read(b"3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 1\n1 1 2 4\n0\n", &c).unwrap();
        assert_eq!(m.blocks[0].physical, vec![4]);
    }
}
