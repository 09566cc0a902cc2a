//! MSH 2.2: `$Nodes` (and `$ParametricNodes`) and `$Elements` with per-element tags
//! (reference manual, "MSH file format version 2 (Legacy)"), and the 2.2 writer.

use super::cursor::{le_f64, le_i32};
use super::header::{write_mesh_format, write_physical_names};
use super::reader::{cell_kind, RawBlock, Reader};
use super::tags::TagMap;
use super::views::write_views;
use crate::text::{push_f64, push_int};
use crate::{
    CellBlock, CellKind, Error, ErrorKind, NodeIndex, Position, Result, TaggedMesh, WriteReport,
};

// ---------------------------------------------------------------------------------
// Reading

/// `$Nodes`: `tag x y z` per node; `$ParametricNodes` adds the classifying entity and
/// its parametric coordinates, which are read past.
pub(super) fn read_nodes(r: &mut Reader<'_>, section_at: Position, parametric: bool) -> Result<()> {
    let binary = r.c.binary;
    let section = if parametric { "ParametricNodes" } else { "Nodes" };
    let n = r.c.count("number of nodes", if binary { 28 } else { 8 })?;
    r.node_blocks.push((r.node_tags.len(), section_at));
    r.points.reserve(n);
    r.node_tags.reserve(n);
    let bad_tag = |t: i64| ErrorKind::Expected {
        expected: "a node number of at least 1".into(),
        found: t.to_string(),
    };
    if binary {
        r.c.end_text_line()?;
        if !parametric {
            let p = r.c.pos();
            let data = r.c.take_array(n, 28, "nodes (4 + 3 x 8 bytes each)")?;
            for (i, ch) in data.chunks_exact(28).enumerate() {
                let t = le_i32(ch);
                if t <= 0 {
                    return Err(r.c.byte_err(p + i * 28, bad_tag(t as i64)));
                }
                let xyz = [le_f64(&ch[4..12]), le_f64(&ch[12..20]), le_f64(&ch[20..28])];
                if !xyz.iter().all(|c| c.is_finite()) {
                    return Err(r.c.byte_err(
                        p + i * 28 + 4,
                        ErrorKind::NonFinite {
                            what: format!("a coordinate of node {t}"),
                            value: format!("{xyz:?}"),
                        },
                    ));
                }
                r.node_tags.push(t as u64);
                r.points.push(xyz);
            }
        } else {
            for _ in 0..n {
                let p = r.c.pos();
                let t = r.c.bin_i32("node number")?;
                if t <= 0 {
                    return Err(r.c.byte_err(p, bad_tag(t as i64)));
                }
                let xyz = [
                    r.c.bin_f64("x coordinate")?,
                    r.c.bin_f64("y coordinate")?,
                    r.c.bin_f64("z coordinate")?,
                ];
                let dp = r.c.pos();
                let dim = r.c.bin_i32("dimension of the classifying entity")?;
                r.c.bin_i32("tag of the classifying entity")?;
                let extra = parametric_count(dim).ok_or_else(|| {
                    r.c.byte_err(
                        dp,
                        ErrorKind::Expected {
                            expected: "an entity dimension 0 to 3".into(),
                            found: dim.to_string(),
                        },
                    )
                })?;
                r.c.take(8 * extra, "parametric coordinates")?;
                r.node_tags.push(t as u64);
                r.points.push(xyz);
            }
        }
    } else {
        let mut s = r.c.scan();
        for _ in 0..n {
            let t = r.c.scan_u64(&mut s, "node number")?;
            let line = s.line();
            if t == 0 {
                r.c.unscan(&s);
                return Err(r.c.err(bad_tag(0)));
            }
            let xyz = [
                r.c.scan_f64(&mut s, "x coordinate")?,
                r.c.scan_f64(&mut s, "y coordinate")?,
                r.c.scan_f64(&mut s, "z coordinate")?,
            ];
            if parametric {
                r.c.unscan(&s);
                let dim = r.c.i32("dimension of the classifying entity")?;
                r.c.i32("tag of the classifying entity")?;
                let extra = parametric_count(dim).ok_or_else(|| {
                    r.c.err(ErrorKind::Expected {
                        expected: "an entity dimension 0 to 3".into(),
                        found: dim.to_string(),
                    })
                })?;
                for _ in 0..extra {
                    r.c.f64("parametric coordinate")?;
                }
                s = r.c.scan();
            }
            if s.line() != line || !s.at_line_end() {
                let expected = if parametric {
                    "a node number, 3 coordinates, an entity and its parametric coordinates on one line"
                } else {
                    "a node number and 3 coordinates on one line"
                };
                return Err(r.c.err_at(
                    Position::Line(line),
                    ErrorKind::Expected {
                        expected: expected.into(),
                        found: "another number of values".into(),
                    },
                ));
            }
            r.node_tags.push(t);
            r.points.push(xyz);
        }
        r.c.unscan(&s);
    }
    r.nodes_changed();
    r.c.expect_end(section)
}

/// Parametric coordinates of a node classified on an entity of dimension `dim` (Gmsh
/// writes u on curves, u v on surfaces).
fn parametric_count(dim: i32) -> Option<usize> {
    match dim {
        0 | 3 => Some(0),
        1 => Some(1),
        2 => Some(2),
        _ => None,
    }
}

/// Collects 2.2 elements into raw blocks, reading Gmsh's copies of an element for each
/// further physical group of its entity as one cell.
struct Collector {
    cur: Option<RawBlock>,
    /// Tag of the element read last (a cell or a copy).
    last_tag: u64,
}

/// One element as read: where, its kind and tag, physical and elementary tags.
struct Element {
    at: Position,
    kind: CellKind,
    tag: u64,
    physical: i32,
    geometrical: i32,
}

impl Collector {
    fn add(&mut self, r: &mut Reader<'_>, e: Element, nodes: &[NodeIndex]) {
        let Element { at, kind, tag, physical, geometrical } = e;
        let follows = self.last_tag.checked_add(1) == Some(tag);
        self.last_tag = tag;
        if let Some(b) = &self.cur {
            if b.kind == kind {
                let k = kind.nodes_per_cell();
                let i = b.tags.len() - 1;
                if follows
                    && b.geometrical[i] == geometrical
                    && b.physical[i] != physical
                    && b.nodes[i * k..] == *nodes
                {
                    // Same element, same entity, another physical group, the next
                    // number: Gmsh's way of writing an entity in several groups.
                    copy_of(r, tag, i, (kind.dim(), geometrical), [b.physical[i], physical]);
                    return;
                }
            } else if let Some(done) = self.cur.take() {
                r.push_raw(done);
            }
        }
        let b = self.cur.get_or_insert_with(|| RawBlock {
            kind,
            at,
            tags: super::tags::TagList::new(),
            nodes: Vec::new(),
            physical: Vec::new(),
            geometrical: Vec::new(),
            entity: None,
        });
        b.tags.push(tag);
        b.nodes.extend_from_slice(nodes);
        b.physical.push(physical);
        b.geometrical.push(geometrical);
    }
}

/// Element `tag` is Gmsh's copy of cell `i` of the block being filled for another
/// physical group of its entity `entity`: the tag reads as that cell, and the entity
/// lists both groups (`groups`: the cell's, then the copy's).
fn copy_of(r: &mut Reader<'_>, tag: u64, i: usize, entity: (u8, i32), groups: [i32; 2]) {
    r.aliases.push((tag, r.n_raw_cells + i));
    let list = r.entities.entry(entity).or_default();
    for p in groups {
        if !list.contains(&p) {
            list.push(p);
        }
    }
}

/// The records of a binary element block of `K`-node elements (`data`, from byte `p`
/// of the file): what [`Collector::add`] does for each, decoded straight into the block
/// being filled, with the previous cell kept at hand for the check for Gmsh's copies.
#[allow(clippy::too_many_arguments)]
fn binary_block<const K: usize>(
    r: &mut Reader<'_>,
    col: &mut Collector,
    map: &TagMap,
    kind: CellKind,
    data: &[u8],
    p: usize,
    ntags: usize,
) -> Result<()> {
    let rec = 4 * (1 + ntags + K);
    let off = 4 * (1 + ntags);
    let count = data.len() / rec;
    // The block being filled when it has this kind (room made for the new elements),
    // a new one otherwise, with room for them all (the count is bounded by the bytes).
    match &mut col.cur {
        Some(b) if b.kind == kind => {
            b.nodes.reserve(count * K);
            b.physical.reserve(count);
            b.geometrical.reserve(count);
        }
        cur => {
            if let Some(done) = cur.take() {
                r.push_raw(done);
            }
            *cur = Some(RawBlock {
                kind,
                at: Position::Byte(p as u64),
                tags: super::tags::TagList::new(),
                nodes: Vec::with_capacity(count * K),
                physical: Vec::with_capacity(count),
                geometrical: Vec::with_capacity(count),
                entity: None,
            });
        }
    }
    let Some(b) = &mut col.cur else { return Ok(()) };
    // The last cell of the block: its tags and nodes.
    let mut prev: Option<(i32, i32, [NodeIndex; K])> = b.tags.len().checked_sub(1).map(|i| {
        let mut nodes = [0 as NodeIndex; K];
        nodes.copy_from_slice(&b.nodes[i * K..(i + 1) * K]);
        (b.physical[i], b.geometrical[i], nodes)
    });
    let mut last_tag = col.last_tag;
    let mut partitions = 0;
    let node = |nt: i32| u64::try_from(nt).ok().and_then(|t| map.node(t));
    for (e, ch) in data.chunks_exact(rec).enumerate() {
        let at = p + e * rec;
        let et = le_i32(ch);
        if et <= 0 {
            return Err(r.c.byte_err(
                at,
                ErrorKind::Expected {
                    expected: "an element number of at least 1".into(),
                    found: et.to_string(),
                },
            ));
        }
        let physical = if ntags >= 1 { le_i32(&ch[4..]) } else { 0 };
        let geometrical = if ntags >= 2 { le_i32(&ch[8..]) } else { 0 };
        // The partitions the element is in (negative: a ghost cell of that partition).
        for j in 3..ntags {
            partitions = partitions.max(le_i32(&ch[4 + 4 * j..]).unsigned_abs() as usize);
        }
        let nb = &ch[off..off + 4 * K];
        let mut nodes = [0 as NodeIndex; K];
        for (j, slot) in nodes.iter_mut().enumerate() {
            let nt = le_i32(&nb[4 * j..4 * j + 4]);
            let Some(v) = node(nt) else {
                return Err(r.c.byte_err(at + off + 4 * j, missing(et as u64, nt as i64)));
            };
            *slot = v;
        }
        let tag = et as u64;
        let follows = last_tag.checked_add(1) == Some(tag);
        last_tag = tag;
        if let Some((p0, g0, n0)) = &prev {
            if *p0 != physical && follows && *g0 == geometrical && *n0 == nodes {
                // Same element, same entity, another physical group, the next number:
                // Gmsh's way of writing an entity in several groups.
                copy_of(r, tag, b.tags.len() - 1, (kind.dim(), geometrical), [*p0, physical]);
                continue;
            }
        }
        b.tags.push(tag);
        b.nodes.extend_from_slice(&nodes);
        b.physical.push(physical);
        b.geometrical.push(geometrical);
        prev = Some((physical, geometrical, nodes));
    }
    col.last_tag = last_tag;
    r.partitions = r.partitions.max(partitions);
    Ok(())
}

fn missing(et: u64, nt: i64) -> ErrorKind {
    ErrorKind::Inconsistent(format!(
        "element {et} refers to node {nt}, which no $Nodes section defines"
    ))
}

/// `$Elements`: `number type ntags tags... nodes...` per element (ASCII), or blocks of
/// elements of one type after a 3-int header (binary).
pub(super) fn read_elements(r: &mut Reader<'_>) -> Result<()> {
    let binary = r.c.binary;
    let n = r.c.count("number of elements", 8)?;
    let map: TagMap = r.take_node_map()?;
    let mut col = Collector { cur: None, last_tag: 0 };
    // Room for the largest cell (27 nodes, a second-order hexahedron).
    let mut nodes = [0 as NodeIndex; 27];
    if binary {
        r.c.end_text_line()?;
        let mut done = 0usize;
        while done < n {
            let hp = r.c.pos();
            let etype = r.c.bin_i32("element type")?;
            let count = r.c.bin_i32("number of elements that follow")?;
            let ntags = r.c.bin_i32("number of tags")?;
            let kind = cell_kind(etype).map_err(|k| r.c.byte_err(hp, k))?;
            if count <= 0 || done + count as usize > n {
                return Err(r.c.byte_err(
                    hp + 4,
                    ErrorKind::Inconsistent(format!("an element block of {count} elements, where {} of the {n} announced remain", n - done)),
                ));
            }
            if ntags < 0 {
                return Err(r.c.byte_err(
                    hp + 8,
                    ErrorKind::Expected {
                        expected: "a number of tags of at least 0".into(),
                        found: ntags.to_string(),
                    },
                ));
            }
            let (count, ntags, k) = (count as usize, ntags as usize, kind.nodes_per_cell());
            let rec = 4 * (1 + ntags + k);
            let p = r.c.pos();
            let data = r.c.take_array(count, rec, "elements")?;
            match k {
                1 => binary_block::<1>(r, &mut col, &map, kind, data, p, ntags)?,
                2 => binary_block::<2>(r, &mut col, &map, kind, data, p, ntags)?,
                3 => binary_block::<3>(r, &mut col, &map, kind, data, p, ntags)?,
                4 => binary_block::<4>(r, &mut col, &map, kind, data, p, ntags)?,
                5 => binary_block::<5>(r, &mut col, &map, kind, data, p, ntags)?,
                6 => binary_block::<6>(r, &mut col, &map, kind, data, p, ntags)?,
                8 => binary_block::<8>(r, &mut col, &map, kind, data, p, ntags)?,
                9 => binary_block::<9>(r, &mut col, &map, kind, data, p, ntags)?,
                10 => binary_block::<10>(r, &mut col, &map, kind, data, p, ntags)?,
                13 => binary_block::<13>(r, &mut col, &map, kind, data, p, ntags)?,
                14 => binary_block::<14>(r, &mut col, &map, kind, data, p, ntags)?,
                15 => binary_block::<15>(r, &mut col, &map, kind, data, p, ntags)?,
                18 => binary_block::<18>(r, &mut col, &map, kind, data, p, ntags)?,
                20 => binary_block::<20>(r, &mut col, &map, kind, data, p, ntags)?,
                // 27, the largest cell ([`CellKind::nodes_per_cell`]).
                _ => binary_block::<27>(r, &mut col, &map, kind, data, p, ntags)?,
            }
            done += count;
        }
    } else {
        let mut s = r.c.scan();
        for _ in 0..n {
            let et = r.c.scan_u64(&mut s, "element number")?;
            let line = s.line();
            if et == 0 {
                r.c.unscan(&s);
                return Err(r.c.err(ErrorKind::Expected {
                    expected: "an element number of at least 1".into(),
                    found: "0".into(),
                }));
            }
            let etype = r.c.scan_i64(&mut s, "element type")?;
            let kind = match i32::try_from(etype)
                .map_err(|_| ErrorKind::Expected {
                    expected: "an element type".into(),
                    found: etype.to_string(),
                })
                .and_then(cell_kind)
            {
                Ok(k) => k,
                Err(k) => {
                    r.c.unscan(&s);
                    return Err(r.c.err(k));
                }
            };
            let ntags = r.c.scan_u64(&mut s, "number of tags")?;
            let (mut physical, mut geometrical) = (0, 0);
            for j in 0..ntags {
                // Physical, elementary, the number of partitions, the partitions.
                let v = r.c.scan_i64(&mut s, "element tag")?;
                let Ok(v) = i32::try_from(v) else {
                    r.c.unscan(&s);
                    return Err(r.c.err(ErrorKind::Expected {
                        expected: "an element tag (a 32-bit integer)".into(),
                        found: v.to_string(),
                    }));
                };
                match j {
                    0 => physical = v,
                    1 => geometrical = v,
                    // The partitions the element is in (negative: a ghost cell).
                    3.. => r.partitions = r.partitions.max(v.unsigned_abs() as usize),
                    _ => {}
                }
            }
            let k = kind.nodes_per_cell();
            for slot in &mut nodes[..k] {
                let nt = r.c.scan_i64(&mut s, "node number")?;
                let Some(v) = u64::try_from(nt).ok().and_then(|t| map.node(t)) else {
                    r.c.unscan(&s);
                    return Err(r.c.err(missing(et, nt)));
                };
                *slot = v;
            }
            if s.line() != line || !s.at_line_end() {
                return Err(Error::at_line(
                    line,
                    ErrorKind::Expected {
                        expected: format!("element {et}: its type, {ntags} tags and {k} node numbers (a {}) on one line", kind.name()),
                        found: "another number of values".into(),
                    },
                ));
            }
            col.add(
                r,
                Element { at: Position::Line(line), kind, tag: et, physical, geometrical },
                &nodes[..k],
            );
        }
        r.c.unscan(&s);
    }
    if let Some(b) = col.cur.take() {
        r.push_raw(b);
    }
    r.put_node_map(map);
    r.c.expect_end("Elements")
}

// ---------------------------------------------------------------------------------
// Writing

/// One binary element of `K` nodes: number, two tags and the 1-based nodes, assembled
/// on the stack and appended whole (a copy of a size known at compile time).
#[inline(always)]
fn element_record<const K: usize>(out: &mut Vec<u8>, head: [i32; 3], cell: &[NodeIndex]) {
    // Room for the largest cell: 3 + 27 numbers.
    let mut rec = [0u8; 120];
    for (j, v) in head.into_iter().enumerate() {
        rec[4 * j..4 * j + 4].copy_from_slice(&v.to_le_bytes());
    }
    for (j, &v) in cell[..K].iter().enumerate() {
        rec[12 + 4 * j..16 + 4 * j].copy_from_slice(&(v as i32 + 1).to_le_bytes());
    }
    out.extend_from_slice(&rec[..4 * (3 + K)]);
}

/// The binary elements of a block of `K`-node cells none of which has copies: what
/// [`write`] does for each cell, numbering from `num`; each cell's element tag pushed
/// to `cell_tag` when given.
fn block_records<const K: usize>(
    out: &mut Vec<u8>,
    b: &CellBlock,
    num: &mut u32,
    mut cell_tag: Option<&mut Vec<u32>>,
) {
    let mut prev: Option<(i32, i32, &[NodeIndex])> = None;
    for ((cell, &p), &g) in b.nodes.chunks_exact(K).zip(&b.physical).zip(&b.geometrical) {
        // A cell equal to the one before but for its physical tag: a gap in the
        // numbering, as in `write`.
        if let Some((p0, g0, c0)) = prev {
            if p0 != p && g0 == g && c0 == cell {
                *num += 1;
            }
        }
        if let Some(t) = &mut cell_tag {
            t.push(*num + 1);
        }
        *num += 1;
        element_record::<K>(out, [*num as i32, p, g], cell);
        prev = Some((p, g, cell));
    }
}

/// Writes MSH 2.2: nodes tagged index + 1, each cell with its physical and elementary
/// tag, once more for each further physical group `entities` lists for its entity.
pub(super) fn write(
    mesh: &TaggedMesh,
    binary: bool,
    out: &mut Vec<u8>,
    report: &mut WriteReport,
) -> Result<()> {
    write_mesh_format(out, "2.2", binary);
    write_physical_names(out, mesh, report);

    out.extend_from_slice(b"$Nodes\n");
    push_int(out, mesh.points.len());
    out.push(b'\n');
    for (i, p) in mesh.points.iter().enumerate() {
        if binary {
            // One fixed-size record per node (one capacity check, not four).
            let mut rec = [0u8; 28];
            rec[..4].copy_from_slice(&(i as i32 + 1).to_le_bytes());
            for (j, c) in p.iter().enumerate() {
                rec[4 + 8 * j..12 + 8 * j].copy_from_slice(&c.to_le_bytes());
            }
            out.extend_from_slice(&rec);
        } else {
            push_int(out, i + 1);
            for &c in p {
                out.push(b' ');
                push_f64(out, c);
            }
            out.push(b'\n');
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndNodes\n");

    // Further physical groups of each cell's entity, as Gmsh writes them: copies.
    let extra = |dim: u8, g: i32, p: i32| -> &[i32] {
        match mesh.entities.get(&(dim, g)) {
            Some(l) if l.len() > 1 && l.contains(&p) => l,
            _ => &[],
        }
    };
    let copies = |dim: u8, g: i32, p: i32| extra(dim, g, p).iter().filter(move |&&q| q != p);
    // Dimensions with an entity in several groups: only their cells can have copies.
    let mut copied = [false; 4];
    for (&(d, _), l) in &mesh.entities {
        if l.len() > 1 {
            if let Some(c) = copied.get_mut(d as usize) {
                *c = true;
            }
        }
    }
    let has_copies = |dim: u8| copied[dim as usize];
    // Elements a block is written as: its cells and their copies.
    let elements = |b: &CellBlock| -> usize {
        let dim = b.kind.dim();
        if has_copies(dim) {
            b.physical
                .iter()
                .zip(&b.geometrical)
                .map(|(&p, &g)| 1 + copies(dim, g, p).count())
                .sum()
        } else {
            b.len()
        }
    };
    let mut total = 0usize;
    let mut negative = 0usize;
    for b in &mesh.blocks {
        total += elements(b);
        negative += b.geometrical.iter().map(|&g| (g < 0) as usize).sum::<usize>();
    }
    if total >= (i32::MAX / 2) as usize {
        return Err(Error::new(ErrorKind::CannotWrite { format: "Gmsh MSH", reason: format!("{total} elements (with the copies for further physical groups) are more than MSH 2.2 can number") }));
    }
    if negative > 0 {
        report.drop(format!("{negative} cell(s) with a negative geometrical tag: written, but Gmsh skips such elements when it reads MSH 2.2"));
    }
    // The entities of the cells, a tag looked up once per run of equal tags.
    let mut in_cells = std::collections::BTreeSet::new();
    for b in &mesh.blocks {
        let mut last = None;
        for &g in &b.geometrical {
            if last != Some(g) {
                in_cells.insert((b.kind.dim(), g));
                last = Some(g);
            }
        }
    }
    let lone = mesh.entities.keys().filter(|k| !in_cells.contains(k)).count();
    if lone > 0 {
        report.drop(format!("{lone} entities without cells (and their physical groups): MSH 2.2 has no entity table"));
    }

    out.extend_from_slice(b"$Elements\n");
    push_int(out, total);
    out.push(b'\n');
    // The element tag of each cell, for `$ElementData`: only when there is cell data.
    let keep_tags = !mesh.cell_data.is_empty();
    let mut cell_tag: Vec<u32> = Vec::with_capacity(if keep_tags { mesh.num_cells() } else { 0 });
    let mut num: u32 = 0;
    for b in &mesh.blocks {
        let dim = b.kind.dim();
        let t = b.kind.gmsh_type();
        if binary && !b.is_empty() {
            for v in [t, elements(b) as i32, 2] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        if binary && !has_copies(dim) {
            let tags = keep_tags.then_some(&mut cell_tag);
            match b.kind.nodes_per_cell() {
                1 => block_records::<1>(out, b, &mut num, tags),
                2 => block_records::<2>(out, b, &mut num, tags),
                3 => block_records::<3>(out, b, &mut num, tags),
                4 => block_records::<4>(out, b, &mut num, tags),
                5 => block_records::<5>(out, b, &mut num, tags),
                6 => block_records::<6>(out, b, &mut num, tags),
                8 => block_records::<8>(out, b, &mut num, tags),
                9 => block_records::<9>(out, b, &mut num, tags),
                10 => block_records::<10>(out, b, &mut num, tags),
                13 => block_records::<13>(out, b, &mut num, tags),
                14 => block_records::<14>(out, b, &mut num, tags),
                15 => block_records::<15>(out, b, &mut num, tags),
                18 => block_records::<18>(out, b, &mut num, tags),
                20 => block_records::<20>(out, b, &mut num, tags),
                _ => block_records::<27>(out, b, &mut num, tags),
            }
            continue;
        }
        for (i, cell) in b.cells().enumerate() {
            let (p, g) = (b.physical[i], b.geometrical[i]);
            // A cell equal to the one before but for its physical tag would read as
            // Gmsh's copy of it: a gap in the numbering keeps it a cell of its own.
            if i > 0 && b.geometrical[i - 1] == g && b.physical[i - 1] != p && b.cell(i - 1) == cell
            {
                num += 1;
            }
            if keep_tags {
                cell_tag.push(num + 1);
            }
            for q in std::iter::once(p).chain(copies(dim, g, p).copied()) {
                num += 1;
                if binary {
                    match cell.len() {
                        1 => element_record::<1>(out, [num as i32, q, g], cell),
                        2 => element_record::<2>(out, [num as i32, q, g], cell),
                        3 => element_record::<3>(out, [num as i32, q, g], cell),
                        4 => element_record::<4>(out, [num as i32, q, g], cell),
                        5 => element_record::<5>(out, [num as i32, q, g], cell),
                        6 => element_record::<6>(out, [num as i32, q, g], cell),
                        8 => element_record::<8>(out, [num as i32, q, g], cell),
                        9 => element_record::<9>(out, [num as i32, q, g], cell),
                        10 => element_record::<10>(out, [num as i32, q, g], cell),
                        13 => element_record::<13>(out, [num as i32, q, g], cell),
                        14 => element_record::<14>(out, [num as i32, q, g], cell),
                        15 => element_record::<15>(out, [num as i32, q, g], cell),
                        18 => element_record::<18>(out, [num as i32, q, g], cell),
                        20 => element_record::<20>(out, [num as i32, q, g], cell),
                        _ => element_record::<27>(out, [num as i32, q, g], cell),
                    }
                } else {
                    push_int(out, num);
                    out.push(b' ');
                    push_int(out, t);
                    out.extend_from_slice(b" 2 ");
                    push_int(out, q);
                    out.push(b' ');
                    push_int(out, g);
                    for &v in cell {
                        out.push(b' ');
                        push_int(out, v + 1);
                    }
                    out.push(b'\n');
                }
            }
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndElements\n");
    write_views(out, mesh, binary, &|i| cell_tag[i] as u64, report);
    Ok(())
}
