//! STL (stereolithography), ASCII and binary: triangles in space, one solid per tag.
//!
//! Source: 3D Systems, *StereoLithography Interface Specification* (1989, section 6.5
//! "Stereolithography Contour (SLC)" aside): ASCII `solid NAME`, then per facet
//! `facet normal nx ny nz`, `outer loop`, three `vertex x y z`, `endloop`,
//! `endfacet`, and `endsolid NAME`; binary an 80-byte header, a little-endian `u32`
//! triangle count, then 50 bytes per triangle: the normal and three vertices as
//! `f32` x, y, z, and a 16-bit "attribute byte count". Keywords are read in any case.
//!
//! Read:
//! - ASCII or binary is told as meshio tells it: a file whose size is exactly
//!   84 + 50 × the count at byte 80 is binary (some binary files start with `solid`
//!   too), else a file that starts with `solid` is ASCII, else it is refused with what
//!   its header announces; so a header announcing 4 billion triangles allocates
//!   nothing;
//! - points are merged exactly: vertices with bit-equal coordinates (after -0.0 is
//!   taken as 0.0) are one point, numbered in the order they are first seen, so that
//!   the same file gives the same mesh, and meshio's numbering (`numpy.unique`, first
//!   seen) is ours; no tolerance, which would merge what the file keeps apart;
//! - normals are read and checked to be numbers (NaN and infinities allowed: some
//!   writers give degenerate facets one) and not kept: a triangle's orientation is its
//!   vertex order, as the specification's right-hand rule says;
//! - ASCII solids are tags of dimension 2, numbered 1, 2, … in file order and named
//!   from `solid NAME`; a solid named `tag<N>` (as the writer names an unnamed tag) is
//!   tag N without a name, an unnamed solid is tag 0, a name given twice is one tag;
//! - binary: the attribute word of each triangle is its tag (0 for most writers; some
//!   put a colour there, which then groups the triangles by colour); the header is
//!   free text and left.
//!
//! Write: ASCII unless [`StlWrite::binary`]. Triangles and quads (a quad `a b c d` as
//! `a b c` and `a c d`, reported), second-order ones by their corners; a volume mesh as
//! its boundary faces (`skin`: what a slicer or viewer wants, reported);
//! each face's normal the unit normal of its vertices by the right-hand rule (0 0 0 for
//! a degenerate one). ASCII: one solid per physical tag in increasing order, named
//! from the tag's name (one line; `tag<N>` for an unnamed tag N, nothing for tag 0),
//! coordinates as shortest round-trip decimals, so that a write → read gives the same
//! points bit for bit. Binary: the tag in the attribute word (tags outside 0..=65535
//! written 0 and reported), coordinates rounded to `f32` (reported when that changes
//! one), names not kept (reported: binary STL has no place for them). Lines, vertex
//! cells, point and cell data, geometrical tags, sets and entities are reported.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::text::{parse_f64, push_f64, show, Tokens};
use crate::{
    CellKind, Error, ErrorKind, NodeIndex, ReadContext, ReadReport, Result, TaggedMesh,
    WriteOptions, WriteReport, Written,
};

/// The reader builds only valid meshes (every index is a point it made).
pub(crate) const CHECKS: crate::Checks =
    crate::Checks { reader_validates: true, writer_validates: false };

/// How to write STL.
#[derive(Debug, Clone, Copy, Default)]
pub struct StlWrite {
    /// Binary (80-byte header, 50 bytes per triangle) rather than ASCII.
    pub binary: bool,
}

/// Points merged by exact coordinates, numbered in first-seen order.
struct Merger {
    points: Vec<[f64; 3]>,
    index: HashMap<[u64; 3], NodeIndex>,
}

impl Merger {
    fn with_capacity(n: usize) -> Self {
        Merger { points: Vec::with_capacity(n), index: HashMap::with_capacity(n) }
    }

    /// The index of point `p` (finite), new if no earlier point has its coordinates.
    fn point(&mut self, p: [f64; 3]) -> std::result::Result<NodeIndex, ErrorKind> {
        // `+ 0.0` makes -0.0 into 0.0: one point, whichever sign a writer gave it.
        let key = p.map(|c| (c + 0.0).to_bits());
        if let Some(&i) = self.index.get(&key) {
            return Ok(i);
        }
        let i = self.points.len();
        if i + 1 >= crate::MAX_POINTS {
            return Err(crate::mesh::past_max_points("STL vertices", i + 1));
        }
        self.points.push(p);
        self.index.insert(key, i as NodeIndex);
        Ok(i as NodeIndex)
    }
}

/// Reads an STL file.
pub fn read(bytes: &[u8], ctx: &ReadContext<'_>) -> Result<TaggedMesh> {
    read_reported(bytes, ctx).map(|(m, _)| m)
}

/// [`read`], with notes on what was read ([`ReadReport`]).
pub fn read_reported(bytes: &[u8], _ctx: &ReadContext<'_>) -> Result<(TaggedMesh, ReadReport)> {
    let mut report = ReadReport::default();
    let announced = (bytes.len() >= 84)
        .then(|| u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]));
    let mut mesh = match announced {
        Some(n) if 84 + 50 * n as u64 == bytes.len() as u64 => read_binary(bytes, n as usize, &mut report)?,
        _ if starts_with_solid(bytes) => read_ascii(bytes)?,
        Some(n) => {
            return Err(Error::at_byte(
                80,
                ErrorKind::Inconsistent(format!(
                    "not ASCII STL (it does not start with `solid`), and as binary STL its header announces {n} triangles, which take {} bytes, but the file has {}",
                    84 + 50 * n as u64,
                    bytes.len()
                )),
            ))
        }
        None => {
            return Err(Error::expected(
                1,
                "`solid` (ASCII STL) or an 84-byte binary STL header",
                show(&bytes[..bytes.len().min(16)]),
            ))
        }
    };
    let degenerate = mesh
        .blocks
        .iter()
        .flat_map(|b| b.cells())
        .filter(|c| c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
        .count();
    if degenerate > 0 {
        report.note(format!(
            "{degenerate} facets have two vertices at the same coordinates: kept as degenerate triangles"
        ));
    }
    mesh.coordinate_dim = 3;
    Ok((mesh, report))
}

fn starts_with_solid(bytes: &[u8]) -> bool {
    let start = bytes.iter().position(|b| !b.is_ascii_whitespace()).unwrap_or(bytes.len());
    bytes[start..].len() >= 5 && bytes[start..start + 5].eq_ignore_ascii_case(b"solid")
}

fn read_binary(bytes: &[u8], n: usize, report: &mut ReadReport) -> Result<TaggedMesh> {
    let mut merger = Merger::with_capacity(n / 2 + 3);
    let mut mesh = TaggedMesh::new();
    let block = mesh.block_mut(CellKind::Triangle);
    block.nodes.reserve(3 * n);
    block.physical.reserve(n);
    block.geometrical.reserve(n);
    let f = |b: &[u8], k: usize| f32::from_le_bytes([b[k], b[k + 1], b[k + 2], b[k + 3]]);
    for t in 0..n {
        let at = 84 + 50 * t;
        let rec = &bytes[at..at + 50];
        let mut tri = [0 as NodeIndex; 3];
        for (v, slot) in tri.iter_mut().enumerate() {
            let p: [f64; 3] = std::array::from_fn(|k| f64::from(f(rec, 12 + 12 * v + 4 * k)));
            if let Some(k) = p.iter().position(|c| !c.is_finite()) {
                return Err(Error::at_byte(
                    (at + 12 + 12 * v + 4 * k) as u64,
                    ErrorKind::NonFinite {
                        what: format!(
                            "coordinate {} of vertex {} of triangle {t}",
                            ["x", "y", "z"][k],
                            v + 1
                        ),
                        value: p[k].to_string(),
                    },
                ));
            }
            *slot = merger.point(p).map_err(|k| Error::at_byte(at as u64, k))?;
        }
        let tag = i32::from(u16::from_le_bytes([rec[48], rec[49]]));
        block.push(&tri, tag, tag);
    }
    let tags: BTreeSet<i32> = block.physical.iter().copied().collect();
    if tags.iter().any(|&t| t != 0) {
        report.note(format!(
            "the attribute words of the triangles read as their tags ({} distinct: {})",
            tags.len(),
            tags.iter().take(8).map(i32::to_string).collect::<Vec<_>>().join(", ")
        ));
    }
    mesh.points = merger.points;
    Ok(mesh)
}

/// The next keyword, which must be `word` (any case).
fn keyword(t: &mut Tokens<'_>, word: &str) -> Result<()> {
    let tok = t.token(&format!("`{word}`"))?;
    if tok.eq_ignore_ascii_case(word.as_bytes()) {
        Ok(())
    } else {
        Err(t.expected(format!("`{word}`"), tok))
    }
}

fn read_ascii(bytes: &[u8]) -> Result<TaggedMesh> {
    let data = crate::text::lone_cr_as_newline(bytes);
    let mut t = Tokens::new(&data);
    let mut merger = Merger::with_capacity(1024);
    let mut mesh = TaggedMesh::new();
    // Solid names in file order, and each triangle's solid (its index into `names`).
    let mut names: Vec<String> = Vec::new();
    let mut tri = CellBlock3::default();
    while let Some(tok) = t.next() {
        if !tok.eq_ignore_ascii_case(b"solid") {
            return Err(t.expected("`solid`", tok));
        }
        let name = String::from_utf8_lossy(t.rest_of_line()).into_owned();
        let solid = match names.iter().position(|n| *n == name) {
            Some(i) => i,
            None => {
                names.push(name);
                names.len() - 1
            }
        };
        loop {
            let tok = t.token("`facet` or `endsolid`")?;
            if tok.eq_ignore_ascii_case(b"endsolid") {
                // The name after `endsolid` is optional and may differ: left.
                t.rest_of_line();
                break;
            }
            if !tok.eq_ignore_ascii_case(b"facet") {
                return Err(t.expected("`facet` or `endsolid`", tok));
            }
            keyword(&mut t, "normal")?;
            for c in ["x", "y", "z"] {
                let tok = t.token(&format!("the normal's {c}"))?;
                if parse_f64(tok).is_err() {
                    return Err(t.expected(format!("the normal's {c} (a number)"), tok));
                }
            }
            keyword(&mut t, "outer")?;
            keyword(&mut t, "loop")?;
            let mut v = [0 as NodeIndex; 3];
            for slot in &mut v {
                keyword(&mut t, "vertex")?;
                let p = [t.f64("a vertex's x")?, t.f64("a vertex's y")?, t.f64("a vertex's z")?];
                *slot = merger.point(p).map_err(|k| t.error(k))?;
            }
            match t.token("`endloop`")? {
                tok if tok.eq_ignore_ascii_case(b"endloop") => {}
                tok if tok.eq_ignore_ascii_case(b"vertex") => {
                    return Err(t.error(ErrorKind::Unsupported(
                        "a facet of more than 3 vertices: STL facets are triangles".into(),
                    )))
                }
                tok => return Err(t.expected("`endloop`", tok)),
            }
            keyword(&mut t, "endfacet")?;
            tri.nodes.extend_from_slice(&v);
            tri.solid.push(solid as u32);
        }
    }
    if names.is_empty() {
        return Err(Error::expected(t.line(), "`solid`", "the end of the file"));
    }
    let tags = solid_tags(&names);
    let block = mesh.block_mut(CellKind::Triangle);
    block.nodes = tri.nodes;
    block.physical = tri.solid.iter().map(|&s| tags[s as usize].0).collect();
    block.geometrical = block.physical.clone();
    if block.is_empty() {
        mesh.blocks.clear();
    }
    for (tag, name) in tags {
        if let Some(name) = name {
            mesh.tag_names.insert((2, tag), name);
        }
    }
    mesh.points = merger.points;
    Ok(mesh)
}

/// Triangles being read: corners and solid index.
#[derive(Default)]
struct CellBlock3 {
    nodes: Vec<NodeIndex>,
    solid: Vec<u32>,
}

/// The tag and name of each solid: empty is tag 0; `tag<N>` is tag N unnamed; the
/// others 1, 2, … in order, skipping the numbers the `tag<N>` solids take.
fn solid_tags(names: &[String]) -> Vec<(i32, Option<String>)> {
    let generated: Vec<Option<i32>> = names.iter().map(|n| generated_tag(n)).collect();
    let taken: BTreeSet<i32> = generated.iter().flatten().copied().collect();
    let mut next = 1;
    names
        .iter()
        .zip(generated)
        .map(|(name, g)| match g {
            Some(t) => (t, None),
            None if name.is_empty() => (0, None),
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

/// N when `name` is `tag<N>` (N a positive integer without sign or leading zeros).
fn generated_tag(name: &str) -> Option<i32> {
    let digits = name.strip_prefix("tag")?;
    let v: i32 = digits.parse().ok()?;
    (v > 0 && v.to_string() == digits).then_some(v)
}

// ---------------------------------------------------------------------------------
// Writing

/// The unit normal of a triangle by the right-hand rule, 0 for a degenerate one.
fn normal(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 && len.is_finite() {
        n.map(|x| x / len)
    } else {
        [0.0; 3]
    }
}

/// The solid name of tag `tag` (one line), reported when not the tag's name as it is.
fn solid_name(mesh: &TaggedMesh, tag: i32, report: &mut WriteReport) -> String {
    let generated = format!("tag{tag}");
    if tag == 0 {
        if let Some(n) = mesh.tag_name(2, 0) {
            report.drop(format!("name `{n}` of tag 0: an unnamed solid is tag 0"));
        }
        return String::new();
    }
    let Some(orig) = mesh.tag_name(2, tag) else {
        report.drop(format!("surface tag {tag} has no name: written as solid `{generated}` (read back as tag {tag})"));
        return generated;
    };
    let clean: String = orig.chars().map(|c| if c.is_control() { ' ' } else { c }).collect();
    let clean = clean.trim().to_string();
    if clean.is_empty() || generated_tag(&clean).is_some_and(|t| t != tag) {
        report.drop(format!("surface tag {tag}'s name `{orig}` written as solid `{generated}`"));
        return generated;
    }
    if clean != orig {
        report.drop(format!(
            "surface tag {tag}'s name `{orig}` written as solid `{clean}` (one line)"
        ));
    }
    clean
}

/// Writes a mesh as STL.
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let mut report = WriteReport::default();
    let skinned = crate::skin::skin(mesh, "STL", &mut report);
    let mesh: &TaggedMesh = &skinned;
    report_unheld(mesh, &mut report);
    // The triangles of each physical tag, in mesh order.
    let mut by_tag: BTreeMap<i32, Vec<[NodeIndex; 3]>> = BTreeMap::new();
    let mut quads = 0usize;
    let mut second = 0usize;
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 2) {
        second += if b.kind.is_second_order() { b.len() } else { 0 };
        for (c, &p) in b.cells().zip(&b.physical) {
            let list = by_tag.entry(p).or_default();
            if b.kind.linear() == CellKind::Quad {
                quads += 1;
                list.push([c[0], c[1], c[2]]);
                list.push([c[0], c[2], c[3]]);
            } else {
                list.push([c[0], c[1], c[2]]);
            }
        }
    }
    if quads > 0 {
        report.drop(format!(
            "{quads} quadrilaterals written as 2 triangles each: STL facets are triangles"
        ));
    }
    if second > 0 {
        report.drop(format!("{second} second-order surface cells written by their corners: STL facets are flat triangles"));
    }
    if let Some((i, _)) =
        mesh.points.iter().enumerate().find(|(_, p)| !p.iter().all(|c| c.is_finite()))
    {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: "STL",
            reason: format!("point {i} has a non-finite coordinate"),
        }));
    }
    let main = if opts.stl.binary {
        write_binary(mesh, &by_tag, &mut report)?
    } else {
        write_ascii(mesh, &by_tag, &mut report)
    };
    Ok(Written { main, siblings: Vec::new(), report })
}

fn write_ascii(
    mesh: &TaggedMesh,
    by_tag: &BTreeMap<i32, Vec<[NodeIndex; 3]>>,
    report: &mut WriteReport,
) -> Vec<u8> {
    let total: usize = by_tag.values().map(Vec::len).sum();
    let mut out = Vec::with_capacity(64 + total * 260);
    let mut used: BTreeMap<String, i32> = BTreeMap::new();
    let push3 = |out: &mut Vec<u8>, p: [f64; 3]| {
        for (k, c) in p.iter().enumerate() {
            if k > 0 {
                out.push(b' ');
            }
            push_f64(out, *c);
        }
        out.push(b'\n');
    };
    for (&tag, tris) in by_tag {
        let name = solid_name(mesh, tag, report);
        if let Some(other) = used.insert(name.clone(), tag) {
            report.drop(format!("surface tags {other} and {tag} share the solid name `{name}`: they read back as one tag"));
        }
        out.extend_from_slice(b"solid");
        if !name.is_empty() {
            out.push(b' ');
            out.extend_from_slice(name.as_bytes());
        }
        out.push(b'\n');
        for t in tris {
            let [a, b, c] = t.map(|i| mesh.points[i as usize]);
            out.extend_from_slice(b"  facet normal ");
            push3(&mut out, normal(a, b, c));
            out.extend_from_slice(b"    outer loop\n");
            for p in [a, b, c] {
                out.extend_from_slice(b"      vertex ");
                push3(&mut out, p);
            }
            out.extend_from_slice(b"    endloop\n  endfacet\n");
        }
        out.extend_from_slice(b"endsolid");
        if !name.is_empty() {
            out.push(b' ');
            out.extend_from_slice(name.as_bytes());
        }
        out.push(b'\n');
    }
    if by_tag.is_empty() {
        out.extend_from_slice(b"solid\nendsolid\n");
    }
    out
}

fn write_binary(
    mesh: &TaggedMesh,
    by_tag: &BTreeMap<i32, Vec<[NodeIndex; 3]>>,
    report: &mut WriteReport,
) -> Result<Vec<u8>> {
    let total: usize = by_tag.values().map(Vec::len).sum();
    let count = u32::try_from(total).map_err(|_| {
        Error::new(ErrorKind::CannotWrite {
            format: "STL",
            reason: format!("{total} triangles: binary STL counts them in 32 bits"),
        })
    })?;
    let mut out = Vec::with_capacity(84 + 50 * total);
    let mut header = [b' '; 80];
    let text = b"binary STL written by smartmesh; attribute word = surface tag";
    header[..text.len()].copy_from_slice(text);
    out.extend_from_slice(&header);
    out.extend_from_slice(&count.to_le_bytes());
    let mut outside = BTreeSet::new();
    for (&tag, tris) in by_tag {
        let word = u16::try_from(tag).unwrap_or_else(|_| {
            outside.insert(tag);
            0
        });
        for t in tris {
            let [a, b, c] = t.map(|i| mesh.points[i as usize]);
            for p in [normal(a, b, c), a, b, c] {
                for x in p {
                    out.extend_from_slice(&(x as f32).to_le_bytes());
                }
            }
            out.extend_from_slice(&word.to_le_bytes());
        }
    }
    if !outside.is_empty() {
        report.drop(format!(
            "surface tags {outside:?} written as attribute word 0: binary STL holds tags 0..=65535"
        ));
    }
    let named: Vec<String> =
        by_tag.keys().filter_map(|&t| mesh.tag_name(2, t)).map(|n| format!("`{n}`")).collect();
    if !named.is_empty() {
        report.drop(format!("the tag names {}: binary STL has no place for names (ASCII STL keeps them as solid names)", named.join(", ")));
    }
    let used: BTreeSet<NodeIndex> = by_tag.values().flatten().flatten().copied().collect();
    let rounded = used
        .iter()
        .filter(|&&i| mesh.points[i as usize].iter().any(|&c| f64::from(c as f32) != c))
        .count();
    if rounded > 0 {
        report.drop(format!("the coordinates of {rounded} points rounded to 32-bit floats: binary STL holds no more"));
    }
    Ok(out)
}

/// What STL cannot hold.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    let mut lower: BTreeMap<CellKind, usize> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() < 2) {
        *lower.entry(b.kind).or_insert(0) += b.len();
    }
    for (k, n) in lower {
        report.drop(format!("{n} {} cells: STL holds triangles only", k.name()));
    }
    for (name, a) in &mesh.point_data {
        report.drop(format!(
            "point data `{name}` ({}): STL holds no fields",
            crate::words::components(a.expanded_components())
        ));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({}): STL holds no fields",
            crate::words::components(a.expanded_components())
        ));
    }
    let differ: usize = mesh.blocks.iter().map(|b| b.tags_differ()).sum();
    if differ > 0 {
        report.drop(format!(
            "geometrical tags of {differ} cells: STL keeps one solid per cell, the physical tag"
        ));
    }
    if !mesh.entities.is_empty() {
        report.drop(format!("the entity table ({} entities): STL has none", mesh.entities.len()));
    }
    for name in mesh.point_sets.keys().chain(mesh.cell_sets.keys()) {
        report.drop(format!("set `{name}`: STL holds no sets"));
    }
    if !mesh.holes.is_empty() || !mesh.regions.is_empty() {
        report.drop("hole points and region seeds: STL holds none");
    }
    let used: BTreeSet<NodeIndex> = mesh
        .blocks
        .iter()
        .filter(|b| b.kind.dim() == 2)
        .flat_map(|b| b.nodes.iter().copied())
        .collect();
    let unused = mesh.points.len() - used.len().min(mesh.points.len());
    if unused > 0 {
        report.drop(format!(
            "{unused} points no surface cell uses: STL writes the vertices of its triangles only"
        ));
    }
}
