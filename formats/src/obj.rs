//! Wavefront OBJ: polygonal geometry with groups.
//!
//! Source: Wavefront Technologies, *Object Files (.obj)*, appendix B1 of the Advanced
//! Visualizer manual (version 3.0): sections "Vertex data" (`v`), "Elements" (`p`,
//! `l`, `f`), "Grouping" (`g`, `o`, `s`, `mg`) and "General statement" (line
//! continuation with `\`).
//!
//! Read:
//! - `v x y [z [w]]` (z kept, 0 when absent; the weight `w` only matters to rational
//!   free-form curves and is ignored), also `v x y z r g b`, the vertex-colour extension
//!   of MeshLab and tobj, colours ignored. `coordinate_dim` is 3 when some z ≠ 0, else 2.
//! - `f` with `v`, `v/vt`, `v//vn` or `v/vt/vn` vertices, 3 or 4 of them (Triangle,
//!   Quad). Larger polygons are an error: a fan triangulation would silently invert
//!   the triangles of a non-convex polygon, and a mesh tool must not guess; triangulate
//!   them in the modeller first.
//! - `l` polylines: a k-vertex `l` becomes k−1 Line cells; `p` points: one Vertex cell
//!   per index.
//! - Indices are 1-based; negative ones count back from the last vertex read so far
//!   (`-1` is the latest). Index 0 and indices past the end are errors naming the line.
//!   A positive index may refer to a vertex defined further down (the spec numbers
//!   vertices by order in the file); it is checked at the end. `vt` and `vn` indices
//!   are range-checked the same way, then ignored.
//! - Groups: the name of the last `g` statement (several names are joined by a space,
//!   as the elements belong to all of them), or of the last `o` when no `g` followed it,
//!   becomes a tag (physical = geometrical), numbered 1, 2, ... in the order in which
//!   cells first use it, with `tag_names[(dim, tag)]` for each dimension of its cells.
//!   Cells before any name, after a bare `g` or after `g default` (the spec's default
//!   group) get tag 0. A group named `tag<N>` (N a nonzero integer, as this writer
//!   names unnamed tags) is tag N and gets no name; the other groups are numbered
//!   around those numbers.
//! - Accepted and ignored: `vt`, `vn`, `vp`, `s`, `mg`, `usemtl`, `mtllib`, and the
//!   other display/render attributes (`lod`, `bevel`, `c_interp`, `d_interp`,
//!   `shadow_obj`, `trace_obj`, `maplib`, `usemap`, `ctech`, `stech`). Free-form
//!   geometry (`cstype`, `curv`, `surf`, ...) and the general statements `call`/`csh`
//!   are refused as unsupported rather than dropped; any other keyword is an error
//!   (the spec's list of statements is closed, so it is not OBJ).
//!
//! Why not tobj (checked against tobj 4.0.5): it requires three coordinates per `v`
//! and divides x, y, z by `w`; it reads a 3-vertex `l` as a triangle and ignores `p`;
//! it gives every model (group/object) its own copy of the vertices it uses, so the
//! shared vertex numbering of a mesh is lost unless all of it is merged back; it reads
//! `nan` and `inf` as numbers; and its errors carry no line. Everything that makes a
//! mesh here (shared numbering, `l`, `p`, positions of errors) would have to be redone
//! around it, so the reader is written by hand on [`crate::text::Tokens`].
//!
//! Write: a comment line (no timestamp), `v x y z` for every point (shortest
//! round-trip decimals), then the cells grouped by physical tag: tag 0 first without a
//! `g` (the default group), then each tag in increasing order under `g <name>`, the
//! name being `tag_names[(dim, tag)]` or `tag<N>` when the tag has none; `p`, `l a b`
//! and `f` in mesh order within a group. A mesh whose tags are 1..n (named or not)
//! reads back with the same numbers; otherwise named tags are renumbered and the report
//! says so. Point and cell data, geometrical tags that differ from the physical ones,
//! sets, holes, regions and entities cannot be held and are reported; second-order
//! cells are written by their corner nodes and reported. A mesh with volume cells is
//! written as its boundary (the faces of one volume cell only, outward, see
//! `skin`), as ParaView's *Extract Surface* draws it; the report says so.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::text::{parse_f64, parse_i64, push_f64, push_int, Tokens};
use crate::{
    CellKind, Error, ErrorKind, NodeIndex, ReadContext, Result, TaggedMesh, WriteOptions,
    WriteReport, Written,
};

// ---------------------------------------------------------------------------------
// Reading

/// The next argument of the current statement, `None` at its end (end of line, end of
/// file or a comment). A `\` ending a line continues the statement on the next one.
#[inline]
fn arg<'a>(t: &mut Tokens<'a>) -> Option<&'a [u8]> {
    loop {
        if t.at_line_end() {
            return None;
        }
        let tok = t.next()?;
        if let Some(stripped) = tok.strip_suffix(b"\\") {
            if t.at_line_end() && t.remaining().first() == Some(&b'\n') {
                // Join the next line: step over the newline (counting it).
                t.seek(t.pos() + 1);
                if stripped.is_empty() {
                    continue;
                }
                return Some(stripped);
            }
        }
        return Some(tok);
    }
}

/// Skips the rest of a statement whose content is ignored.
fn skip_statement(t: &mut Tokens<'_>) {
    while arg(t).is_some() {}
}

use crate::text::show;

/// A coordinate: finite decimal.
#[inline]
fn coordinate(tok: &[u8], line: u64, what: &str) -> Result<f64> {
    match parse_f64(tok) {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => {
            Err(Error::at_line(line, ErrorKind::NonFinite { what: what.into(), value: show(tok) }))
        }
        Err(()) => Err(Error::expected(line, what, show(tok))),
    }
}

/// Resolves indices of one kind (`v`, `vt` or `vn`) against the items read so far.
struct IndexSpace {
    /// Items read so far.
    count: usize,
    /// The largest positive index that pointed past `count` when it was read, and its
    /// line: legal if the file defines that many items by its end.
    forward: Option<(i64, u64)>,
    /// Statement keyword, for messages.
    what: &'static str,
}

impl IndexSpace {
    fn new(what: &'static str) -> Self {
        IndexSpace { count: 0, forward: None, what }
    }

    /// The 0-based item of a 1-based or negative (relative) index.
    #[inline]
    fn resolve(&mut self, idx: i64, line: u64) -> Result<usize> {
        if idx > 0 {
            let i = (idx - 1) as u64;
            if i >= self.count as u64 && self.forward.map_or(true, |(m, _)| idx > m) {
                self.forward = Some((idx, line));
            }
            usize::try_from(i).map_err(|_| self.out_of_range(idx, line, self.count))
        } else if idx < 0 {
            let back = idx.unsigned_abs();
            if back <= self.count as u64 {
                Ok(self.count - back as usize)
            } else {
                Err(self.out_of_range(idx, line, self.count))
            }
        } else {
            Err(Error::expected(
                line,
                format!("a {} index (1-based, or negative to count back)", self.what),
                "`0`",
            ))
        }
    }

    fn out_of_range(&self, idx: i64, line: u64, available: usize) -> Error {
        Error::at_line(
            line,
            ErrorKind::IndexOutOfRange {
                what: format!("{} index", self.what),
                index: idx,
                available,
            },
        )
    }

    /// Checks the forward references once every item is known.
    fn finish(&self) -> Result<()> {
        match self.forward {
            Some((idx, line)) if idx as u64 > self.count as u64 => {
                Err(self.out_of_range(idx, line, self.count))
            }
            _ => Ok(()),
        }
    }
}

/// Which parts an element's vertex may carry.
#[derive(Clone, Copy)]
enum VertexForm {
    /// `p`: `v` only.
    Point,
    /// `l`: `v` or `v/vt`.
    Line,
    /// `f`: `v`, `v/vt`, `v//vn`, `v/vt/vn`.
    Face,
}

struct Reader {
    v: IndexSpace,
    vt: IndexSpace,
    vn: IndexSpace,
    /// Current group or object name, `None` for the default group (tag 0).
    current: Option<Vec<u8>>,
    /// Provisional id (1-based) of `current`, allocated when a cell first uses it.
    current_id: Option<i32>,
    /// Provisional id - 1 → name, in order of first use.
    group_names: Vec<Vec<u8>>,
    /// Dimensions (bit d for dim d) of the cells of each provisional group.
    group_dims: Vec<u8>,
    lookup: HashMap<Vec<u8>, i32>,
}

impl Reader {
    /// The provisional tag of a new cell of dimension `dim` (0 for the default group).
    #[inline]
    fn tag(&mut self, dim: u8) -> i32 {
        let Some(name) = &self.current else { return 0 };
        let id = match self.current_id {
            Some(id) => id,
            None => {
                let next = self.group_names.len() as i32 + 1;
                let id = *self.lookup.entry(name.clone()).or_insert(next);
                if id == next {
                    self.group_names.push(name.clone());
                    self.group_dims.push(0);
                }
                self.current_id = Some(id);
                id
            }
        };
        self.group_dims[(id - 1) as usize] |= 1 << dim;
        id
    }

    fn set_group(&mut self, name: Option<Vec<u8>>) {
        self.current = name;
        self.current_id = None;
    }

    /// One vertex reference of an element: its 0-based point index.
    #[inline]
    fn vertex(&mut self, tok: &[u8], line: u64, form: VertexForm) -> Result<NodeIndex> {
        let mut parts = tok.splitn(3, |&c| c == b'/');
        let v = parts.next().unwrap_or_default();
        let vi = parse_i64(v).ok_or_else(|| {
            Error::expected(line, "a vertex index (`v`, `v/vt`, `v//vn` or `v/vt/vn`)", show(tok))
        })?;
        let p = crate::mesh::node_index(self.v.resolve(vi, line)?)
            .map_err(|k| Error::at_line(line, k))?;
        if tok.len() == v.len() {
            return Ok(p);
        }
        let vt = parts.next().unwrap_or_default();
        let vn = parts.next();
        let allowed = match form {
            VertexForm::Point => false,
            VertexForm::Line => vn.is_none() && !vt.is_empty(),
            VertexForm::Face => !(vt.is_empty() && vn.map_or(true, <[u8]>::is_empty)),
        };
        if !allowed {
            let expected = match form {
                VertexForm::Point => "a point index `v` (the spec allows no `/` in `p`)",
                VertexForm::Line => "a line vertex `v` or `v/vt`",
                VertexForm::Face => "a face vertex `v`, `v/vt`, `v//vn` or `v/vt/vn`",
            };
            return Err(Error::expected(line, expected, show(tok)));
        }
        if !vt.is_empty() {
            let i = parse_i64(vt).ok_or_else(|| {
                Error::expected(line, "a texture vertex index after `/`", show(tok))
            })?;
            self.vt.resolve(i, line)?;
        }
        if let Some(vn) = vn.filter(|s| !s.is_empty()) {
            let i = parse_i64(vn).ok_or_else(|| {
                Error::expected(line, "a normal index after `//` or the second `/`", show(tok))
            })?;
            self.vn.resolve(i, line)?;
        }
        Ok(p)
    }
}

/// The name given by a `g` or `o` statement: its arguments joined by one space; `None`
/// when there are none.
fn read_name(t: &mut Tokens<'_>) -> Option<Vec<u8>> {
    let mut name: Option<Vec<u8>> = None;
    while let Some(a) = arg(t) {
        match &mut name {
            None => name = Some(a.to_vec()),
            Some(n) => {
                n.push(b' ');
                n.extend_from_slice(a);
            }
        }
    }
    name
}

/// `tag<N>` with N a nonzero `i32` written canonically (as this writer writes it).
fn default_tag_number(name: &[u8]) -> Option<i32> {
    let digits = name.strip_prefix(b"tag")?;
    let n = i32::try_from(parse_i64(digits)?).ok()?;
    let mut canonical = Vec::new();
    push_int(&mut canonical, n);
    (n != 0 && canonical == digits).then_some(n)
}

/// Statements of the spec that carry nothing for a polygonal mesh.
const IGNORED: &[&[u8]] = &[
    b"vp",
    b"s",
    b"mg",
    b"usemtl",
    b"mtllib",
    b"lod",
    b"bevel",
    b"c_interp",
    b"d_interp",
    b"shadow_obj",
    b"trace_obj",
    b"maplib",
    b"usemap",
    b"ctech",
    b"stech",
];

/// Statements of the spec smartmesh does not read: free-form geometry, and the general
/// statements that would read another file or run a command.
const UNSUPPORTED: &[&[u8]] = &[
    b"cstype", b"deg", b"bmat", b"step", b"curv", b"curv2", b"surf", b"parm", b"trim", b"hole",
    b"scrv", b"sp", b"end", b"con", b"call", b"csh",
];

/// The OBJ reader checks indices as it reads, but `validate` runs after it; its writer
/// leaves it to `write_bytes` too.
pub(crate) const CHECKS: crate::Checks = crate::Checks::NONE;

/// Reads a mesh.
pub fn read(bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    let bytes = crate::text::lone_cr_as_newline(bytes);
    let mut t = Tokens::with_comments(&bytes, b'#');
    let mut mesh = TaggedMesh::new();
    let mut r = Reader {
        v: IndexSpace::new("vertex"),
        vt: IndexSpace::new("texture vertex"),
        vn: IndexSpace::new("normal"),
        current: None,
        current_id: None,
        group_names: Vec::new(),
        group_dims: Vec::new(),
        lookup: HashMap::new(),
    };
    let mut any_z = false;
    while let Some(kw) = t.next() {
        let line = t.line();
        match kw {
            b"v" => {
                let mut c = [0.0f64; 3];
                let mut n = 0usize;
                while let Some(a) = arg(&mut t) {
                    const WHAT: [&str; 7] = [
                        "x coordinate",
                        "y coordinate",
                        "z coordinate",
                        "w weight or red",
                        "green",
                        "blue",
                        "value",
                    ];
                    let val = coordinate(a, t.line(), WHAT[n.min(6)])?;
                    if n < 3 {
                        c[n] = val;
                    }
                    n += 1;
                }
                if !matches!(n, 2..=4 | 6) {
                    return Err(Error::expected(
                        t.line(),
                        "2 to 4 numbers after `v` (x y [z [w]]), or x y z r g b",
                        format!("{n}"),
                    ));
                }
                any_z |= c[2] != 0.0;
                mesh.points.push(c);
                r.v.count += 1;
            }
            b"vt" => {
                skip_statement(&mut t);
                r.vt.count += 1;
            }
            b"vn" => {
                skip_statement(&mut t);
                r.vn.count += 1;
            }
            b"f" => {
                let mut idx = [0 as NodeIndex; 4];
                let mut k = 0usize;
                while let Some(a) = arg(&mut t) {
                    if k == 4 {
                        let mut total = 5;
                        while arg(&mut t).is_some() {
                            total += 1;
                        }
                        return Err(Error::expected(
                            line,
                            "a face of 3 or 4 vertices (smartmesh reads triangles and quads; triangulate larger polygons first)",
                            format!("{total} vertices"),
                        ));
                    }
                    idx[k] = r.vertex(a, t.line(), VertexForm::Face)?;
                    k += 1;
                }
                let kind = match k {
                    3 => CellKind::Triangle,
                    4 => CellKind::Quad,
                    _ => {
                        return Err(Error::expected(
                            line,
                            "a face of 3 or 4 vertices",
                            format!("{k} vertices"),
                        ))
                    }
                };
                let tag = r.tag(2);
                mesh.block_mut(kind).push(&idx[..k], tag, tag);
            }
            b"l" => {
                let mut prev: Option<NodeIndex> = None;
                let mut k = 0usize;
                while let Some(a) = arg(&mut t) {
                    let p = r.vertex(a, t.line(), VertexForm::Line)?;
                    if let Some(q) = prev {
                        let tag = r.tag(1);
                        mesh.block_mut(CellKind::Line).push(&[q, p], tag, tag);
                    }
                    prev = Some(p);
                    k += 1;
                }
                if k < 2 {
                    return Err(Error::expected(
                        line,
                        "a line element of at least 2 vertices",
                        format!("{k}"),
                    ));
                }
            }
            b"p" => {
                let mut k = 0usize;
                while let Some(a) = arg(&mut t) {
                    let p = r.vertex(a, t.line(), VertexForm::Point)?;
                    let tag = r.tag(0);
                    mesh.block_mut(CellKind::Vertex).push(&[p], tag, tag);
                    k += 1;
                }
                if k == 0 {
                    return Err(Error::expected(
                        line,
                        "at least one vertex index after `p`",
                        "none",
                    ));
                }
            }
            b"g" => {
                let name = read_name(&mut t).filter(|n| n != b"default");
                r.set_group(name);
            }
            b"o" => {
                let name = read_name(&mut t);
                r.set_group(name);
            }
            _ if IGNORED.contains(&kw) => skip_statement(&mut t),
            _ if UNSUPPORTED.contains(&kw) => {
                return Err(Error::at_line(
                    line,
                    ErrorKind::Unsupported(format!(
                        "OBJ statement `{}` (free-form geometry and general statements); smartmesh reads polygonal OBJ: v, p, l, f",
                        String::from_utf8_lossy(kw)
                    )),
                ));
            }
            _ => {
                return Err(Error::expected(
                    line,
                    "an OBJ statement (v, vt, vn, f, l, p, g, o, s, usemtl, mtllib, ...)",
                    show(kw),
                ))
            }
        }
    }
    r.v.finish()?;
    r.vt.finish()?;
    r.vn.finish()?;
    mesh.coordinate_dim = if any_z { 3 } else { 2 };
    number_groups(&mut mesh, &r.group_names, &r.group_dims);
    Ok(mesh)
}

/// Replaces provisional group ids by the final tags and names the groups.
fn number_groups(mesh: &mut TaggedMesh, names: &[Vec<u8>], dims: &[u8]) {
    if names.is_empty() {
        return;
    }
    let explicit: Vec<Option<i32>> = names.iter().map(|n| default_tag_number(n)).collect();
    let taken: BTreeSet<i32> = explicit.iter().flatten().copied().collect();
    let mut next = 1i32;
    let mut tags = Vec::with_capacity(names.len());
    for (i, e) in explicit.iter().enumerate() {
        let tag = match e {
            Some(n) => *n,
            None => {
                while taken.contains(&next) {
                    next += 1;
                }
                next += 1;
                let tag = next - 1;
                let name = String::from_utf8_lossy(&names[i]).into_owned();
                for d in 0..3u8 {
                    if dims[i] & (1 << d) != 0 {
                        mesh.tag_names.insert((d, tag), name.clone());
                    }
                }
                tag
            }
        };
        tags.push(tag);
    }
    for b in &mut mesh.blocks {
        for p in b.physical.iter_mut().chain(b.geometrical.iter_mut()) {
            if *p > 0 {
                *p = tags[(*p - 1) as usize];
            }
        }
    }
}

// ---------------------------------------------------------------------------------
// Writing

/// A group name OBJ can hold: one line, no comment marker, no continuation, single
/// spaces (the reader joins a `g` statement's names with one space).
fn sanitize_name(name: &str) -> String {
    let cleaned: String = name
        .chars()
        .map(|c| if c == '#' || c == '\\' || c.is_control() { '_' } else { c })
        .collect();
    cleaned.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Writes a mesh.
pub fn write(mesh: &TaggedMesh, _opts: &WriteOptions) -> Result<Written> {
    let mut report = WriteReport::default();
    // A volume mesh is written as its boundary faces, as ParaView's Extract Surface
    // draws it: what a viewer or modeller reading OBJ expects.
    let skinned = crate::skin::skin(mesh, "OBJ", &mut report);
    let mesh: &TaggedMesh = &skinned;
    report_unheld(mesh, &mut report);

    // Group names: one per (physical tag, dimension) that cells use.
    let mut used: BTreeSet<(i32, u8)> = BTreeSet::new();
    for b in &mesh.blocks {
        let d = b.kind.dim();
        let mut last = None;
        for &p in &b.physical {
            if last != Some(p) {
                used.insert((p, d));
                last = Some(p);
            }
        }
    }
    // Tag 0 first (no `g`), then tags in increasing order.
    let mut order: Vec<(i32, u8)> = used.iter().copied().filter(|&(p, _)| p == 0).collect();
    order.extend(used.iter().copied().filter(|&(p, _)| p != 0));
    let mut groups: Vec<String> = Vec::new(); // group index → name ("" for tag 0)
    let mut group_index: BTreeMap<String, usize> = BTreeMap::new();
    let mut group_of: BTreeMap<(i32, u8), usize> = BTreeMap::new();
    let mut group_tags: Vec<Vec<(i32, u8)>> = Vec::new();
    for &(p, d) in &order {
        let name = if p == 0 {
            if let Some(n) = mesh.tag_name(d, 0) {
                report.drop(format!("name `{n}` of tag 0 (dimension {d}): tag 0 is OBJ's default group, which has no name"));
            }
            String::new()
        } else {
            match mesh.tag_name(d, p).map(|n| (n, sanitize_name(n))) {
                Some((orig, clean)) if !clean.is_empty() && clean != "default" => {
                    if clean != orig {
                        report.drop(format!("tag name `{orig}` (dimension {d}, tag {p}) written as `{clean}`: OBJ group names are one line without `#` or `\\`"));
                    }
                    clean
                }
                Some((orig, _)) => {
                    report.drop(format!("tag name `{orig}` (dimension {d}, tag {p}) cannot be an OBJ group name; written as `tag{p}`"));
                    format!("tag{p}")
                }
                None => format!("tag{p}"),
            }
        };
        let gi = *group_index.entry(name.clone()).or_insert_with(|| {
            groups.push(name);
            group_tags.push(Vec::new());
            groups.len() - 1
        });
        group_tags[gi].push((p, d));
        group_of.insert((p, d), gi);
    }
    report_numbering(&groups, &group_tags, &mut report);
    for (&(d, p), n) in &mesh.tag_names {
        if !used.contains(&(p, d)) {
            report.drop(format!("tag name `{n}` (dimension {d}, tag {p}) names no cell; OBJ keeps a group only with its elements"));
        }
    }

    // Bucket the cells by group, keeping mesh order within each (a stable counting sort).
    let total = mesh.num_cells();
    let mut cell_group: Vec<u32> = Vec::with_capacity(total);
    let mut counts = vec![0usize; groups.len()];
    for b in &mesh.blocks {
        let d = b.kind.dim();
        let mut last: Option<(i32, usize)> = None;
        for &p in &b.physical {
            let gi = match last {
                Some((lp, gi)) if lp == p => gi,
                _ => group_of[&(p, d)],
            };
            last = Some((p, gi));
            counts[gi] += 1;
            cell_group.push(gi as u32);
        }
    }
    let mut start: Vec<usize> = Vec::with_capacity(groups.len() + 1);
    let mut acc = 0;
    for c in &counts {
        start.push(acc);
        acc += c;
    }
    let mut fill = start.clone();
    // (block index, cell index) in output order.
    let mut sorted: Vec<(u32, u32)> = vec![(0, 0); total];
    let mut gidx = 0;
    for (bi, b) in mesh.blocks.iter().enumerate() {
        for ci in 0..b.len() {
            let gi = cell_group[gidx] as usize;
            gidx += 1;
            sorted[fill[gi]] = (bi as u32, ci as u32);
            fill[gi] += 1;
        }
    }

    // Pre-size: a coordinate is at most ~24 bytes, an index at most ~8 in practice.
    let node_count: usize = mesh.blocks.iter().map(|b| b.nodes.len()).sum();
    let mut out: Vec<u8> =
        Vec::with_capacity(64 + mesh.points.len() * 60 + total * 4 + node_count * 8);
    out.extend_from_slice(b"# written by smartmesh-formats ");
    out.extend_from_slice(env!("CARGO_PKG_VERSION").as_bytes());
    out.extend_from_slice(b" (Wavefront OBJ)\n");
    for (i, p) in mesh.points.iter().enumerate() {
        if !p.iter().all(|c| c.is_finite()) {
            return Err(Error::new(ErrorKind::CannotWrite {
                format: "OBJ",
                reason: format!("point {i} has a non-finite coordinate"),
            }));
        }
        out.extend_from_slice(b"v ");
        push_f64(&mut out, p[0]);
        out.push(b' ');
        push_f64(&mut out, p[1]);
        out.push(b' ');
        if p[2] == 0.0 && p[2].is_sign_positive() {
            out.push(b'0');
        } else {
            push_f64(&mut out, p[2]);
        }
        out.push(b'\n');
    }
    let mut second_order: BTreeMap<CellKind, (usize, usize)> = BTreeMap::new();
    for (gi, name) in groups.iter().enumerate() {
        let range = start[gi]..start[gi] + counts[gi];
        if range.is_empty() {
            continue;
        }
        if !name.is_empty() {
            out.extend_from_slice(b"g ");
            out.extend_from_slice(name.as_bytes());
            out.push(b'\n');
        }
        for &(bi, ci) in &sorted[range] {
            let b = &mesh.blocks[bi as usize];
            let cell = b.cell(ci as usize);
            let (keyword, corners): (&[u8], usize) = match b.kind {
                CellKind::Vertex => (b"p", 1),
                CellKind::Line | CellKind::Line3 => (b"l", 2),
                CellKind::Triangle | CellKind::Triangle6 => (b"f", 3),
                CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 => (b"f", 4),
                _ => return Err(volume_cells(b.kind)),
            };
            if b.kind.is_second_order() {
                second_order.entry(b.kind).or_insert((0, corners)).0 += 1;
            }
            out.extend_from_slice(keyword);
            for &v in &cell[..corners] {
                out.push(b' ');
                push_int(&mut out, v + 1);
            }
            out.push(b'\n');
        }
    }
    for (kind, (n, corners)) in second_order {
        report.drop(format!(
            "{n} {} cells written by their {corners} corner nodes: OBJ has no second-order elements (the other nodes stay as vertices)",
            kind.name()
        ));
    }
    Ok(Written { main: out, siblings: Vec::new(), report })
}

/// What OBJ cannot hold at all.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    for (name, a) in &mesh.point_data {
        report.drop(format!(
            "point data `{name}` ({}): OBJ holds no fields",
            crate::words::components(a.expanded_components())
        ));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({}): OBJ holds no fields",
            crate::words::components(a.expanded_components())
        ));
    }
    let differ: usize = mesh.blocks.iter().map(|b| b.tags_differ()).sum();
    if differ > 0 {
        report.drop(format!("geometrical tags of {differ} cells differ from their physical tags: OBJ keeps one group per cell, the physical tag"));
    }
    if !mesh.entities.is_empty() {
        report.drop(format!(
            "the entity table ({} entities with their physical groups): OBJ has none",
            mesh.entities.len()
        ));
    }
    for name in mesh.point_sets.keys() {
        report.drop(format!("point set `{name}`: OBJ holds no sets"));
    }
    for name in mesh.cell_sets.keys() {
        report.drop(format!("cell set `{name}`: OBJ holds no sets"));
    }
    if !mesh.holes.is_empty() {
        report.drop(format!("{} hole points: OBJ holds none", mesh.holes.len()));
    }
    if !mesh.regions.is_empty() {
        report.drop(format!("{} region seeds: OBJ holds none", mesh.regions.len()));
    }
}

/// Says which tags will not read back with the same number: the reader numbers named
/// groups 1, 2, ... in order of appearance, around the numbers of `tag<N>` groups.
fn report_numbering(groups: &[String], group_tags: &[Vec<(i32, u8)>], report: &mut WriteReport) {
    let taken: BTreeSet<i32> =
        groups.iter().filter_map(|g| default_tag_number(g.as_bytes())).collect();
    let mut next = 1;
    for (g, tags) in groups.iter().zip(group_tags) {
        if g.is_empty() {
            continue;
        }
        let read_back = match default_tag_number(g.as_bytes()) {
            Some(n) => n,
            None => {
                while taken.contains(&next) {
                    next += 1;
                }
                next += 1;
                next - 1
            }
        };
        let distinct: BTreeSet<i32> = tags.iter().map(|t| t.0).collect();
        if distinct.len() > 1 {
            let list: Vec<String> =
                tags.iter().map(|(p, d)| format!("{p} (dimension {d})")).collect();
            report.drop(format!(
                "tags {} share the group name `{g}`: OBJ reads them back as one tag, {read_back}",
                list.join(", ")
            ));
        } else if let Some(&p) = distinct.first() {
            if p != read_back {
                report.drop(format!("tag {p} (group `{g}`) reads back as tag {read_back}: OBJ numbers named groups by order of appearance"));
            }
        }
    }
    // A tag with different names in different dimensions becomes several groups.
    let mut names_of: BTreeMap<i32, BTreeSet<&str>> = BTreeMap::new();
    for (g, tags) in groups.iter().zip(group_tags) {
        for (p, _) in tags {
            if *p != 0 {
                names_of.entry(*p).or_default().insert(g);
            }
        }
    }
    for (p, names) in names_of {
        if names.len() > 1 {
            let names: Vec<&str> = names.into_iter().collect();
            report.drop(format!("tag {p} has a different name in each dimension ({}): OBJ groups have no dimension, so they read back as separate tags", names.join(", ")));
        }
    }
}

/// OBJ holds points, lines and faces: a volume cell left after [`crate::skin::skin`]
/// (none is) would be refused, not flattened.
fn volume_cells(kind: CellKind) -> Error {
    Error::new(ErrorKind::CannotWrite {
        format: "OBJ",
        reason: format!("{} cells: OBJ holds surfaces, not volumes", kind.name()),
    })
}
