//! MSH 4.1: `$Entities`, `$Nodes` and `$Elements` in entity blocks (reference manual,
//! "MSH file format"), and the writer that plans the entities.

use std::collections::BTreeMap;

use super::cursor::{le_f64, le_i32, le_size};
use super::header::{write_mesh_format, write_physical_names};
use super::reader::{cell_kind, RawBlock, Reader};
use super::views::write_views;
use crate::text::{push_f64, push_int};
use crate::{CellKind, Error, ErrorKind, NodeIndex, Position, Result, TaggedMesh, WriteReport};

// ---------------------------------------------------------------------------------
// Reading

/// `$Entities`: the physical tags of every point, curve, surface and volume.
pub(super) fn read_entities(r: &mut Reader<'_>) -> Result<()> {
    let binary = r.c.binary;
    let st = r.size_t;
    let names = ["points", "curves", "surfaces", "volumes"];
    let mut counts = [0usize; 4];
    if binary {
        r.c.end_text_line()?;
        for d in 0..4 {
            let min = if d == 0 { 4 + 24 + st } else { 4 + 48 + 2 * st };
            counts[d] = r.c.bin_count(st, &format!("number of {}", names[d]), min)?;
        }
    } else {
        for d in 0..4 {
            counts[d] =
                r.c.count(&format!("number of {}", names[d]), if d == 0 { 10 } else { 18 })?;
        }
    }
    for (dim, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            let at = r.c.mark();
            let n_coords = if dim == 0 { 3 } else { 6 };
            let tag;
            let mut phys = Vec::new();
            if binary {
                tag = r.c.bin_i32("entity tag")?;
                // Coordinates (points) or bounding boxes: read past, not kept.
                r.c.take(8 * n_coords, "entity coordinates")?;
                let n = r.c.bin_count(st, "number of physical tags", 4)?;
                phys.extend(r.c.take_array(n, 4, "physical tags")?.chunks_exact(4).map(le_i32));
                if dim > 0 {
                    let n = r.c.bin_count(st, "number of bounding entities", 4)?;
                    r.c.take_array(n, 4, "bounding entity tags")?;
                }
            } else {
                tag = r.c.i32("entity tag")?;
                for _ in 0..n_coords {
                    r.c.f64(if dim == 0 { "point coordinate" } else { "bounding box coordinate" })?;
                }
                let n = r.c.count("number of physical tags", 2)?;
                for _ in 0..n {
                    phys.push(r.c.i32("physical tag")?);
                }
                if dim > 0 {
                    let n = r.c.count("number of bounding entities", 2)?;
                    for _ in 0..n {
                        r.c.i32("bounding entity tag")?;
                    }
                }
            }
            if r.entities.insert((dim as u8, tag), phys).is_some() {
                return Err(r.c.err_at(
                    at,
                    ErrorKind::Inconsistent(format!(
                        "{} {tag} is defined twice in $Entities",
                        &names[dim][..names[dim].len() - 1]
                    )),
                ));
            }
        }
    }
    r.c.expect_end("Entities")
}

/// The four `size_t` of a `$Nodes` or `$Elements` header: blocks, items, min and max tag.
fn section_header(
    r: &mut Reader<'_>,
    item: &str,
    min_block: usize,
    min_item: usize,
) -> Result<(usize, usize)> {
    section_header_tags(r, item, min_block, min_item).map(|(blocks, n, _, _)| (blocks, n))
}

/// [`section_header`] with the smallest and largest tag it announces.
fn section_header_tags(
    r: &mut Reader<'_>,
    item: &str,
    min_block: usize,
    min_item: usize,
) -> Result<(usize, usize, u64, u64)> {
    if r.c.binary {
        let st = r.size_t;
        r.c.end_text_line()?;
        let blocks = r.c.bin_count(st, &format!("number of {item} blocks"), min_block)?;
        let n = r.c.bin_count(st, &format!("number of {item}s"), min_item)?;
        let lo = r.c.bin_size(st, &format!("smallest {item} tag"))?;
        let hi = r.c.bin_size(st, &format!("largest {item} tag"))?;
        Ok((blocks, n, lo, hi))
    } else {
        let blocks = r.c.count(&format!("number of {item} blocks"), min_block)?;
        let n = r.c.count(&format!("number of {item}s"), min_item)?;
        let lo = r.c.u64(&format!("smallest {item} tag"))?;
        let hi = r.c.u64(&format!("largest {item} tag"))?;
        Ok((blocks, n, lo, hi))
    }
}

/// The `entityDim entityTag x n` header of a block.
fn block_header(
    r: &mut Reader<'_>,
    third: &str,
    item: &str,
    min_item: usize,
) -> Result<(i32, i32, i32, usize)> {
    let at = r.c.mark();
    let (dim, tag, x, n) = if r.c.binary {
        let dim = r.c.bin_i32("entity dimension")?;
        let tag = r.c.bin_i32("entity tag")?;
        let x = r.c.bin_i32(third)?;
        let n = r.c.bin_count(r.size_t, &format!("number of {item}s in the block"), min_item)?;
        (dim, tag, x, n)
    } else {
        let dim = r.c.i32("entity dimension")?;
        let tag = r.c.i32("entity tag")?;
        let x = r.c.i32(third)?;
        let n = r.c.count(&format!("number of {item}s in the block"), min_item)?;
        (dim, tag, x, n)
    };
    if !(0..=3).contains(&dim) {
        return Err(r.c.err_at(
            at,
            ErrorKind::Expected {
                expected: "an entity dimension 0 to 3".into(),
                found: dim.to_string(),
            },
        ));
    }
    Ok((dim, tag, x, n))
}

/// `$Nodes`: entity blocks of tags then coordinates (and parametric coordinates, read past).
pub(super) fn read_nodes(r: &mut Reader<'_>, section_at: Position) -> Result<()> {
    if r.c.binary && r.points.is_empty() && r.node_tags.is_empty() {
        let start = r.c.pos();
        let blocks_before = r.node_blocks.len();
        if binary_nodes_in_tag_order(r, section_at)? {
            return Ok(());
        }
        // Tags of another kind: the section again, in file order.
        r.c.seek(start);
        r.points = Vec::new();
        r.node_tags = super::tags::TagList::new();
        r.node_blocks.truncate(blocks_before);
    }
    let binary = r.c.binary;
    let st = r.size_t;
    // Smallest node: `1\n0 0 0\n` in ASCII, a size_t and 3 doubles in binary.
    let min_node = if binary { st + 24 } else { 8 };
    let (n_blocks, n_nodes) =
        section_header(r, "node", if binary { 12 + st } else { 8 }, min_node)?;
    r.points.reserve(n_nodes);
    r.node_tags.reserve(n_nodes);
    let mut total = 0usize;
    for _ in 0..n_blocks {
        let (block_at, n, width) = node_block_header(r, min_node, n_nodes, &mut total)?;
        r.node_blocks.push((r.node_tags.len(), block_at));
        if binary {
            let p = r.c.pos();
            let tags = r.c.take_array(n, st, "node tags")?;
            for (i, ch) in tags.chunks_exact(st).enumerate() {
                let t = le_size(ch, st);
                if t == 0 {
                    return Err(r.c.byte_err(
                        p + i * st,
                        ErrorKind::Expected {
                            expected: "a node tag of at least 1 (0 is reserved)".into(),
                            found: "0".into(),
                        },
                    ));
                }
                r.node_tags.push(t);
            }
            let p = r.c.pos();
            let coords = r.c.take_array(n, 8 * width, "node coordinates")?;
            for (i, ch) in coords.chunks_exact(8 * width).enumerate() {
                let xyz = [le_f64(&ch[0..8]), le_f64(&ch[8..16]), le_f64(&ch[16..24])];
                if !xyz.iter().all(|c| c.is_finite()) {
                    return Err(r.c.byte_err(
                        p + i * 8 * width,
                        ErrorKind::NonFinite {
                            what: "a node coordinate".into(),
                            value: format!("{xyz:?}"),
                        },
                    ));
                }
                r.points.push(xyz);
            }
        } else {
            let mut s = r.c.scan();
            for _ in 0..n {
                let t = r.c.scan_u64(&mut s, "node tag")?;
                if t == 0 {
                    r.c.unscan(&s);
                    return Err(r.c.err(ErrorKind::Expected {
                        expected: "a node tag of at least 1 (0 is reserved)".into(),
                        found: "0".into(),
                    }));
                }
                r.node_tags.push(t);
            }
            for _ in 0..n {
                let x = r.c.scan_f64(&mut s, "x coordinate")?;
                let line = s.line();
                let xyz = [
                    x,
                    r.c.scan_f64(&mut s, "y coordinate")?,
                    r.c.scan_f64(&mut s, "z coordinate")?,
                ];
                for _ in 3..width {
                    r.c.scan_f64(&mut s, "parametric coordinate")?;
                }
                if s.line() != line {
                    return Err(r.c.err_at(
                        Position::Line(line),
                        ErrorKind::Expected {
                            expected: format!("{width} coordinates on the line"),
                            found: "fewer".into(),
                        },
                    ));
                }
                r.points.push(xyz);
            }
            r.c.unscan(&s);
        }
    }
    if total != n_nodes {
        return Err(r.c.err_at(
            section_at,
            ErrorKind::Inconsistent(format!(
                "$Nodes announces {n_nodes} nodes, but its blocks hold {total}"
            )),
        ));
    }
    r.nodes_changed();
    r.c.expect_end("Nodes")
}

/// The header of the next `$Nodes` block, checked: where it starts, its node count and
/// the width of one node's record in values (3 coordinates, plus the parametric ones);
/// `total` counts the nodes of the blocks so far against the section's `n_nodes`.
fn node_block_header(
    r: &mut Reader<'_>,
    min_node: usize,
    n_nodes: usize,
    total: &mut usize,
) -> Result<(Position, usize, usize)> {
    let block_at = r.c.mark();
    let (dim, _tag, parametric, n) = block_header(r, "parametric flag", "node", min_node)?;
    if parametric != 0 && parametric != 1 {
        return Err(r.c.err_at(
            block_at,
            ErrorKind::Expected {
                expected: "a parametric flag 0 or 1".into(),
                found: parametric.to_string(),
            },
        ));
    }
    *total += n;
    if *total > n_nodes {
        return Err(r.c.err_at(
            block_at,
            ErrorKind::Inconsistent(format!(
                "the node blocks hold more nodes than the $Nodes header announces ({n_nodes})"
            )),
        ));
    }
    Ok((block_at, n, 3 + if parametric == 1 { dim as usize } else { 0 }))
}

/// A binary `$Nodes` section, the first one, whose node tags are exactly the `lo..=hi`
/// its header announces, one node each (how Gmsh and smartmesh number nodes, whatever
/// the order of the blocks): every point goes straight to its place in tag order, so that
/// no copy puts them in order later and tags map to points by a subtraction.
///
/// Every check of the general reader is made, in the same order, with the same errors.
/// `Ok(false)` when the tags are of another kind (a tag outside `lo..=hi`, a tag given
/// twice, a header that does not announce a full range): the caller then reads the
/// section again in file order, and reports what that reading reports.
fn binary_nodes_in_tag_order(r: &mut Reader<'_>, section_at: Position) -> Result<bool> {
    let st = r.size_t;
    let min_node = st + 24;
    let (n_blocks, n_nodes, lo, hi) = section_header_tags(r, "node", 12 + st, min_node)?;
    if n_nodes == 0 || lo == 0 || hi.checked_sub(lo) != Some(n_nodes as u64 - 1) {
        return Ok(false);
    }
    // The count was checked against the bytes left, so this is at most the file's size.
    let mut points = vec![[0.0f64; 3]; n_nodes];
    // Runs of consecutive tags `(first tag, length)`: they must not overlap.
    let mut runs: Vec<(u64, usize)> = Vec::new();
    let mut total = 0usize;
    for _ in 0..n_blocks {
        let (block_at, n, width) = node_block_header(r, min_node, n_nodes, &mut total)?;
        r.node_blocks.push((total - n, block_at));
        let p = r.c.pos();
        let tags = r.c.take_array(n, st, "node tags")?;
        for (i, ch) in tags.chunks_exact(st).enumerate() {
            let t = le_size(ch, st);
            if t == 0 {
                return Err(r.c.byte_err(
                    p + i * st,
                    ErrorKind::Expected {
                        expected: "a node tag of at least 1 (0 is reserved)".into(),
                        found: "0".into(),
                    },
                ));
            }
            if t < lo || t > hi {
                return Ok(false);
            }
            match runs.last_mut() {
                Some(run) if run.0.checked_add(run.1 as u64) == Some(t) => run.1 += 1,
                _ => runs.push((t, 1)),
            }
        }
        let p = r.c.pos();
        let rec = 8 * width;
        let coords = r.c.take_array(n, rec, "node coordinates")?;
        for (i, (tag, ch)) in tags.chunks_exact(st).zip(coords.chunks_exact(rec)).enumerate() {
            let xyz = [le_f64(&ch[0..8]), le_f64(&ch[8..16]), le_f64(&ch[16..24])];
            if !xyz.iter().all(|c| c.is_finite()) {
                return Err(r.c.byte_err(
                    p + i * rec,
                    ErrorKind::NonFinite {
                        what: "a node coordinate".into(),
                        value: format!("{xyz:?}"),
                    },
                ));
            }
            // In range: checked with the tags above.
            points[(le_size(tag, st) - lo) as usize] = xyz;
        }
    }
    if total != n_nodes {
        return Err(r.c.err_at(
            section_at,
            ErrorKind::Inconsistent(format!(
                "$Nodes announces {n_nodes} nodes, but its blocks hold {total}"
            )),
        ));
    }
    // `n_nodes` tags in a range of `n_nodes`: each is there once if no two runs overlap.
    runs.sort_unstable();
    if runs.windows(2).any(|w| w[0].0.saturating_add(w[0].1 as u64) > w[1].0) {
        return Ok(false);
    }
    r.points = points;
    r.node_tags = super::tags::TagList::Range { first: lo, len: n_nodes };
    r.nodes_changed();
    r.c.expect_end("Nodes")?;
    Ok(true)
}

/// `$Elements`: entity blocks of one element type each.
pub(super) fn read_elements(r: &mut Reader<'_>) -> Result<()> {
    let section_at = r.c.mark();
    let binary = r.c.binary;
    let st = r.size_t;
    let (n_blocks, n_elems) = section_header(
        r,
        "element",
        if binary { 12 + st } else { 8 },
        if binary { 2 * st } else { 4 },
    )?;
    let map = r.take_node_map()?;
    let mut total = 0usize;
    for _ in 0..n_blocks {
        let block_at = r.c.mark();
        let (dim, tag, etype, n) =
            block_header(r, "element type", "element", if binary { 2 * st } else { 4 })?;
        let kind = cell_kind(etype).map_err(|k| r.c.err_at(block_at, k))?;
        let k = kind.nodes_per_cell();
        total += n;
        if total > n_elems {
            return Err(r.c.err_at(block_at, ErrorKind::Inconsistent(format!("the element blocks hold more elements than the $Elements header announces ({n_elems})"))));
        }
        let mut b = RawBlock {
            kind,
            at: block_at,
            tags: super::tags::TagList::new(),
            nodes: Vec::with_capacity(n * k),
            physical: Vec::new(),
            geometrical: vec![tag; n],
            entity: Some((dim as u8, tag)),
        };
        if binary {
            let p = r.c.pos();
            let data = r.c.take_array(n, (1 + k) * st, "elements")?;
            if st == 8 {
                binary_elements::<8>(r, &map, &mut b, data, p)?;
            } else {
                binary_elements::<4>(r, &map, &mut b, data, p)?;
            }
        } else {
            let mut s = r.c.scan();
            for _ in 0..n {
                let et = r.c.scan_u64(&mut s, "element tag")?;
                let line = s.line();
                if et == 0 {
                    r.c.unscan(&s);
                    return Err(r.c.err(ErrorKind::Expected {
                        expected: "an element tag of at least 1 (0 is reserved)".into(),
                        found: "0".into(),
                    }));
                }
                b.tags.push(et);
                for _ in 0..k {
                    let nt = r.c.scan_u64(&mut s, "node tag")?;
                    let Some(v) = map.node(nt) else {
                        r.c.unscan(&s);
                        return Err(r.c.err(missing(et, nt)));
                    };
                    b.nodes.push(v);
                }
                if s.line() != line || !s.at_line_end() {
                    return Err(r.c.err_at(
                        Position::Line(line),
                        ErrorKind::Expected {
                            expected: format!(
                                "{k} node tags after element {et} (a {})",
                                kind.name()
                            ),
                            found: "another number of values on the line".into(),
                        },
                    ));
                }
            }
            r.c.unscan(&s);
        }
        r.push_raw(b);
    }
    if total != n_elems {
        return Err(r.c.err_at(
            section_at,
            ErrorKind::Inconsistent(format!(
                "$Elements announces {n_elems} elements, but its blocks hold {total}"
            )),
        ));
    }
    r.put_node_map(map);
    r.c.expect_end("Elements")
}

fn missing(et: u64, nt: u64) -> ErrorKind {
    ErrorKind::Inconsistent(format!(
        "element {et} refers to node {nt}, which no $Nodes section defines"
    ))
}

/// Binary element records of `ST`-byte `size_t`s: a tag then the node tags.
fn binary_elements<const ST: usize>(
    r: &Reader<'_>,
    map: &super::tags::TagMap,
    b: &mut RawBlock,
    data: &[u8],
    p: usize,
) -> Result<()> {
    let k = b.kind.nodes_per_cell();
    let rec = (1 + k) * ST;
    for (e, ch) in data.chunks_exact(rec).enumerate() {
        let et = le_size(ch, ST);
        if et == 0 {
            return Err(r.c.byte_err(
                p + e * rec,
                ErrorKind::Expected {
                    expected: "an element tag of at least 1 (0 is reserved)".into(),
                    found: "0".into(),
                },
            ));
        }
        b.tags.push(et);
        for (j, t) in ch[ST..].chunks_exact(ST).enumerate() {
            let nt = le_size(t, ST);
            let Some(v) = map.node(nt) else {
                return Err(r.c.byte_err(p + e * rec + (j + 1) * ST, missing(et, nt)));
            };
            b.nodes.push(v);
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------
// Writing

const UNSET: u32 = u32::MAX;

/// A model entity as written.
struct Ent {
    dim: u8,
    tag: i32,
    phys: Vec<i32>,
    lo: [f64; 3],
    hi: [f64; 3],
    has_box: bool,
    /// The node of a point entity's vertex cell.
    point: Option<usize>,
}

impl Ent {
    fn grow(&mut self, p: &[f64; 3]) {
        if self.has_box {
            for ((lo, hi), &c) in self.lo.iter_mut().zip(&mut self.hi).zip(p) {
                *lo = lo.min(c);
                *hi = hi.max(c);
            }
        } else {
            self.lo = *p;
            self.hi = *p;
            self.has_box = true;
        }
    }
}

fn kind_index(k: CellKind) -> usize {
    CellKind::ALL.iter().position(|&x| x == k).unwrap_or(0)
}

/// Consecutive cells of one mesh block with the same physical and geometrical tag:
/// `len` cells from `start` in block `block`.
#[derive(Clone, Copy)]
struct Run {
    block: u32,
    start: u32,
    len: u32,
}

/// Where every cell and node goes: entities, element blocks, node blocks.
struct Plan {
    ents: Vec<Ent>,
    /// Element blocks `(entity, kind)` with their cells as runs (a range of `runs`),
    /// in mesh order within each.
    groups: Vec<(u32, CellKind, std::ops::Range<usize>)>,
    runs: Vec<Run>,
    /// Node blocks `(entity, nodes)`.
    node_groups: Vec<(u32, std::ops::Range<usize>)>,
    nodes: Vec<u32>,
}

fn plan(mesh: &TaggedMesh, report: &mut WriteReport) -> Result<Plan> {
    // 1. The (dimension, geometrical tag, physical tag) of every cell, by runs of
    //    consecutive cells that share them (a mesh's cells are mostly grouped so).
    let mut combos: BTreeMap<(u8, i32, i32), u32> = BTreeMap::new();
    let mut first_phys: BTreeMap<(u8, i32), i32> = BTreeMap::new();
    // `(run, combination)` in mesh order.
    let mut cell_runs: Vec<(Run, u32)> = Vec::new();
    let mut last: Option<((u8, i32, i32), u32)> = None;
    for (bi, b) in mesh.blocks.iter().enumerate() {
        let dim = b.kind.dim();
        let (phys, geom) = (&b.physical[..], &b.geometrical[..b.physical.len()]);
        let mut i = 0;
        while i < phys.len() {
            let (p, g) = (phys[i], geom[i]);
            let mut j = i + 1;
            while j < phys.len() && phys[j] == p && geom[j] == g {
                j += 1;
            }
            let key = (dim, g, p);
            let id = match last {
                Some((k, id)) if k == key => id,
                _ => {
                    let n = combos.len() as u32;
                    let id = *combos.entry(key).or_insert(n);
                    first_phys.entry((dim, g)).or_insert(p);
                    last = Some((key, id));
                    id
                }
            };
            cell_runs.push((Run { block: bi as u32, start: i as u32, len: (j - i) as u32 }, id));
            i = j;
        }
    }

    // 2. Free tags per dimension, above every tag in use.
    let mut next_free = [1i64; 4];
    for &(d, g, _) in combos.keys() {
        next_free[d as usize] = next_free[d as usize].max(g as i64 + 1);
    }
    for &(d, t) in mesh.entities.keys() {
        if d <= 3 {
            next_free[d as usize] = next_free[d as usize].max(t as i64 + 1);
        }
    }
    let mut alloc = |d: u8| -> Result<i32> {
        let t = next_free[d as usize];
        next_free[d as usize] += 1;
        i32::try_from(t).map_err(|_| {
            Error::new(ErrorKind::CannotWrite {
                format: "Gmsh MSH",
                reason: format!("no free {d}D entity tag is left above the largest one in use"),
            })
        })
    };

    // 3. An entity per (dimension, geometrical tag); cells of other physical tags than
    //    the entity's first move to new entities.
    let mut ents: BTreeMap<(u8, i32), Vec<i32>> = BTreeMap::new();
    let mut combo_ent: Vec<(u8, i32)> = vec![(0, 0); combos.len()];
    let by_entity = {
        let mut m: BTreeMap<(u8, i32), Vec<(i32, u32)>> = BTreeMap::new();
        for (&(d, g, p), &id) in &combos {
            m.entry((d, g)).or_default().push((p, id));
        }
        m
    };
    let mut untagged = 0usize;
    for ((d, g), list) in &by_entity {
        let (d, g) = (*d, *g);
        if g <= 0 {
            for &(p, id) in list {
                let t = alloc(d)?;
                ents.insert((d, t), if p != 0 { vec![p] } else { vec![] });
                combo_ent[id as usize] = (d, t);
                untagged += 1;
            }
            continue;
        }
        let listed = mesh.entities.get(&(d, g)).filter(|l| !l.is_empty());
        let home = match listed {
            Some(l) if list.iter().any(|&(p, _)| p == l[0]) => l[0],
            _ => first_phys.get(&(d, g)).copied().unwrap_or(0),
        };
        let tags = match listed {
            Some(l) if l.contains(&home) => {
                std::iter::once(home).chain(l.iter().copied().filter(|&p| p != home)).collect()
            }
            Some(l) => {
                report.drop(format!(
                    "{d}D entity {g}: its physical groups {l:?} do not include its cells' group {home}; written with group {home} only"
                ));
                if home != 0 {
                    vec![home]
                } else {
                    vec![]
                }
            }
            None if home != 0 => vec![home],
            None => vec![],
        };
        ents.insert((d, g), tags);
        let mut moved = Vec::new();
        for &(p, id) in list {
            if p == home {
                combo_ent[id as usize] = (d, g);
            } else {
                let t = alloc(d)?;
                ents.insert((d, t), if p != 0 { vec![p] } else { vec![] });
                combo_ent[id as usize] = (d, t);
                moved.push(format!("group {p} → entity {t}"));
            }
        }
        if !moved.is_empty() {
            report.drop(format!(
                "{d}D entity {g} holds cells of several physical groups; MSH 4.1 gives groups to entities, not cells, so those of the other groups are written as cells of new entities ({}), with another geometrical tag",
                moved.join(", ")
            ));
        }
    }
    if untagged > 0 {
        report.drop(format!(
            "cells without a positive geometrical tag written as cells of {untagged} new entities (Gmsh entity tags are strictly positive)"
        ));
    }
    // Entities without cells keep their groups.
    for (&(d, t), list) in &mesh.entities {
        if d > 3 || t <= 0 {
            report.drop(format!(
                "entity ({d}, {t}): Gmsh entities have a dimension 0 to 3 and a positive tag"
            ));
        } else {
            ents.entry((d, t)).or_insert_with(|| list.clone());
        }
    }
    // Nodes with no cell need an entity to be written in.
    let host_key = if mesh.num_cells() == 0 && !mesh.points.is_empty() {
        let key = (2, alloc(2)?);
        ents.insert(key, Vec::new());
        Some(key)
    } else {
        None
    };

    // 4. Entities in (dimension, tag) order.
    let index: BTreeMap<(u8, i32), u32> =
        ents.keys().enumerate().map(|(i, &k)| (k, i as u32)).collect();
    let mut ents: Vec<Ent> = ents
        .into_iter()
        .map(|((dim, tag), phys)| Ent {
            dim,
            tag,
            phys,
            lo: [0.0; 3],
            hi: [0.0; 3],
            has_box: false,
            point: None,
        })
        .collect();
    let combo_idx: Vec<u32> = combo_ent.iter().map(|k| index[k]).collect();

    // 5. Element blocks by (entity, kind): a counting sort of the runs (stable, so the
    //    cells of a block keep the mesh's order).
    let nk = CellKind::ALL.len();
    let mut counts = vec![0usize; ents.len() * nk + 1];
    let run_key = |&(run, id): &(Run, u32)| {
        combo_idx[id as usize] as usize * nk + kind_index(mesh.blocks[run.block as usize].kind)
    };
    for cr in &cell_runs {
        counts[run_key(cr) + 1] += 1;
    }
    for i in 1..counts.len() {
        counts[i] += counts[i - 1];
    }
    let mut runs = vec![Run { block: 0, start: 0, len: 0 }; cell_runs.len()];
    {
        let mut fill = counts.clone();
        for cr in &cell_runs {
            let key = run_key(cr);
            runs[fill[key]] = cr.0;
            fill[key] += 1;
        }
    }
    drop(cell_runs);
    let mut groups = Vec::new();
    for key in 0..ents.len() * nk {
        if counts[key + 1] > counts[key] {
            groups.push(((key / nk) as u32, CellKind::ALL[key % nk], counts[key]..counts[key + 1]));
        }
    }

    // 6. Each node on the first (lowest-dimensional) entity that uses it; bounding boxes.
    let mut node_ent = vec![UNSET; mesh.points.len()];
    for (e, kind, range) in &groups {
        let ent = &mut ents[*e as usize];
        for run in &runs[range.clone()] {
            let b = &mesh.blocks[run.block as usize];
            let k = b.kind.nodes_per_cell();
            let (s, n) = (run.start as usize, run.len as usize);
            for &v in &b.nodes[s * k..(s + n) * k] {
                let v = v as usize;
                // A node first met in this entity has grown its box already: a triangle
                // mesh shares each node among about six cells, so most grows are skipped.
                if node_ent[v] == UNSET {
                    node_ent[v] = *e;
                    ent.grow(&mesh.points[v]);
                } else if node_ent[v] != *e {
                    ent.grow(&mesh.points[v]);
                }
                if *kind == CellKind::Vertex && ent.point.is_none() {
                    ent.point = Some(v);
                }
            }
        }
    }
    // Nodes no cell uses: on the first entity of the highest dimension with cells.
    let host = match host_key {
        Some(k) => Some(index[&k]),
        None => groups
            .iter()
            .map(|g| g.0)
            .max_by_key(|&e| (ents[e as usize].dim, std::cmp::Reverse(ents[e as usize].tag))),
    };
    if let Some(h) = host {
        for (v, e) in node_ent.iter_mut().enumerate() {
            if *e == UNSET {
                *e = h;
                ents[h as usize].grow(&mesh.points[v]);
            }
        }
    }

    // 7. Node blocks: a counting sort of the nodes by entity.
    let mut ncounts = vec![0usize; ents.len() + 1];
    for &e in &node_ent {
        ncounts[e as usize + 1] += 1;
    }
    for i in 1..ncounts.len() {
        ncounts[i] += ncounts[i - 1];
    }
    let mut nodes = vec![0u32; node_ent.len()];
    let mut fill = ncounts.clone();
    for (v, &e) in node_ent.iter().enumerate() {
        nodes[fill[e as usize]] = v as u32;
        fill[e as usize] += 1;
    }
    let node_groups = (0..ents.len())
        .filter(|&e| ncounts[e + 1] > ncounts[e])
        .map(|e| (e as u32, ncounts[e]..ncounts[e + 1]))
        .collect();
    Ok(Plan { ents, groups, runs, node_groups, nodes })
}

/// Appends a `size_t` (8 bytes: the files say so in `$MeshFormat`).
#[inline]
fn push_size(out: &mut Vec<u8>, v: usize) {
    out.extend_from_slice(&(v as u64).to_le_bytes());
}

fn push_f64s(out: &mut Vec<u8>, vs: &[f64], binary: bool) {
    for &v in vs {
        if binary {
            out.extend_from_slice(&v.to_le_bytes());
        } else {
            out.push(b' ');
            push_f64(out, v);
        }
    }
}

fn write_entities(out: &mut Vec<u8>, mesh: &TaggedMesh, plan: &Plan, binary: bool) {
    out.extend_from_slice(b"$Entities\n");
    let mut counts = [0usize; 4];
    for e in &plan.ents {
        counts[e.dim as usize] += 1;
    }
    if binary {
        for c in counts {
            push_size(out, c);
        }
    } else {
        for (i, c) in counts.iter().enumerate() {
            push_int(out, *c);
            out.push(if i < 3 { b' ' } else { b'\n' });
        }
    }
    let first_node: BTreeMap<u32, usize> =
        plan.node_groups.iter().map(|(e, r)| (*e, plan.nodes[r.start] as usize)).collect();
    for (ei, e) in plan.ents.iter().enumerate() {
        if binary {
            out.extend_from_slice(&e.tag.to_le_bytes());
        } else {
            push_int(out, e.tag);
        }
        if e.dim == 0 {
            let p = e
                .point
                .or_else(|| first_node.get(&(ei as u32)).copied())
                .map_or([0.0; 3], |v| mesh.points[v]);
            push_f64s(out, &p, binary);
        } else {
            push_f64s(out, &e.lo, binary);
            push_f64s(out, &e.hi, binary);
        }
        if binary {
            push_size(out, e.phys.len());
            for p in &e.phys {
                out.extend_from_slice(&p.to_le_bytes());
            }
            if e.dim > 0 {
                push_size(out, 0);
            }
        } else {
            out.push(b' ');
            push_int(out, e.phys.len());
            for p in &e.phys {
                out.push(b' ');
                push_int(out, *p);
            }
            if e.dim > 0 {
                out.extend_from_slice(b" 0");
            }
            out.push(b'\n');
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndEntities\n");
}

fn write_header4(out: &mut Vec<u8>, blocks: usize, n: usize, binary: bool) {
    let (lo, hi) = if n == 0 { (0, 0) } else { (1, n) };
    if binary {
        for v in [blocks, n, lo, hi] {
            push_size(out, v);
        }
    } else {
        for (i, v) in [blocks, n, lo, hi].into_iter().enumerate() {
            push_int(out, v);
            out.push(if i < 3 { b' ' } else { b'\n' });
        }
    }
}

fn write_block_header(out: &mut Vec<u8>, dim: u8, tag: i32, third: i32, n: usize, binary: bool) {
    if binary {
        out.extend_from_slice(&(dim as i32).to_le_bytes());
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&third.to_le_bytes());
        push_size(out, n);
    } else {
        push_int(out, dim);
        out.push(b' ');
        push_int(out, tag);
        out.push(b' ');
        push_int(out, third);
        out.push(b' ');
        push_int(out, n);
        out.push(b'\n');
    }
}

fn write_nodes(out: &mut Vec<u8>, mesh: &TaggedMesh, plan: &Plan, binary: bool) {
    out.extend_from_slice(b"$Nodes\n");
    write_header4(out, plan.node_groups.len(), mesh.points.len(), binary);
    for (e, range) in &plan.node_groups {
        let ent = &plan.ents[*e as usize];
        let nodes = &plan.nodes[range.clone()];
        write_block_header(out, ent.dim, ent.tag, 0, nodes.len(), binary);
        if binary {
            for &v in nodes {
                push_size(out, v as usize + 1);
            }
            for &v in nodes {
                // One fixed-size record per point (one capacity check, not three).
                let mut rec = [0u8; 24];
                for (j, c) in mesh.points[v as usize].iter().enumerate() {
                    rec[8 * j..8 * j + 8].copy_from_slice(&c.to_le_bytes());
                }
                out.extend_from_slice(&rec);
            }
        } else {
            for &v in nodes {
                push_int(out, v + 1);
                out.push(b'\n');
            }
            for &v in nodes {
                let p = &mesh.points[v as usize];
                push_f64(out, p[0]);
                out.push(b' ');
                push_f64(out, p[1]);
                out.push(b' ');
                push_f64(out, p[2]);
                out.push(b'\n');
            }
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndNodes\n");
}

fn write_elements(out: &mut Vec<u8>, mesh: &TaggedMesh, plan: &Plan, binary: bool) {
    out.extend_from_slice(b"$Elements\n");
    write_header4(out, plan.groups.len(), mesh.num_cells(), binary);
    let offsets: Vec<usize> = mesh
        .blocks
        .iter()
        .scan(0, |s, b| {
            let r = *s;
            *s += b.len();
            Some(r)
        })
        .collect();
    for (e, kind, range) in &plan.groups {
        let ent = &plan.ents[*e as usize];
        let runs = &plan.runs[range.clone()];
        let n: usize = runs.iter().map(|r| r.len as usize).sum();
        write_block_header(out, ent.dim, ent.tag, kind.gmsh_type(), n, binary);
        for run in runs {
            let b = &mesh.blocks[run.block as usize];
            let k = b.kind.nodes_per_cell();
            let (s, len) = (run.start as usize, run.len as usize);
            // Element tags: the cell's index in the mesh + 1, consecutive along a run.
            let first = offsets[run.block as usize] + s + 1;
            let nodes = &b.nodes[s * k..(s + len) * k];
            if binary {
                match k {
                    1 => element_records::<1>(out, first, nodes),
                    2 => element_records::<2>(out, first, nodes),
                    3 => element_records::<3>(out, first, nodes),
                    4 => element_records::<4>(out, first, nodes),
                    6 => element_records::<6>(out, first, nodes),
                    8 => element_records::<8>(out, first, nodes),
                    _ => element_records::<9>(out, first, nodes),
                }
                continue;
            }
            for (j, cell) in nodes.chunks_exact(k).enumerate() {
                push_int(out, first + j);
                for &v in cell {
                    out.push(b' ');
                    push_int(out, v + 1);
                }
                out.push(b'\n');
            }
        }
    }
    if binary {
        out.push(b'\n');
    }
    out.extend_from_slice(b"$EndElements\n");
}

/// The binary records of a run of `K`-node elements numbered from `first`: the element
/// tag and the node tags, 8 bytes each, assembled on the stack and appended whole (one
/// capacity check per element rather than per number; `K` known, so the copy is of a
/// fixed size).
fn element_records<const K: usize>(out: &mut Vec<u8>, first: usize, nodes: &[NodeIndex]) {
    let mut rec = [0u8; 80];
    for (j, cell) in nodes.chunks_exact(K).enumerate() {
        rec[..8].copy_from_slice(&((first + j) as u64).to_le_bytes());
        for (i, &v) in cell.iter().enumerate() {
            rec[8 + 8 * i..16 + 8 * i].copy_from_slice(&(v as u64 + 1).to_le_bytes());
        }
        out.extend_from_slice(&rec[..8 * (K + 1)]);
    }
}

/// Writes MSH 4.1.
pub(super) fn write(
    mesh: &TaggedMesh,
    binary: bool,
    out: &mut Vec<u8>,
    report: &mut WriteReport,
) -> Result<()> {
    let plan = plan(mesh, report)?;
    write_mesh_format(out, "4.1", binary);
    write_physical_names(out, mesh, report);
    write_entities(out, mesh, &plan, binary);
    write_nodes(out, mesh, &plan, binary);
    write_elements(out, mesh, &plan, binary);
    write_views(out, mesh, binary, &|i| i as u64 + 1, report);
    Ok(())
}
