//! MSH 4.1: `$Entities`, `$Nodes` and `$Elements` in entity blocks (reference manual,
//! "MSH file format"); the writer in `plan` (where each cell and node goes) and `write`
//! (the sections).

mod plan;
mod write;

pub(super) use write::write;

use super::cursor::{le_f64, le_i32, le_size};
use super::reader::{cell_kind, short_record, RawBlock, Reader};
use crate::{ErrorKind, Position, Result};

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
            let tag = if binary { r.c.bin_i32("entity tag")? } else { r.c.i32("entity tag")? };
            let (phys, bbox) = entity_tail(r, dim, tag, at)?;
            r.entity_boxes.insert((dim as u8, tag), bbox);
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

/// `$PartitionedEntities` (a mesh split by `gmsh -part N` or `gmsh.model.mesh.partition`):
/// the entities the elements of a partitioned file are classified on, each with its
/// parent (the model entity it is a part of) and its own physical tags. Read so that a
/// cell gets the physical tag of its partitioned entity and, as geometrical tag, its
/// parent's (what Gmsh writes as elementary tag in MSH 2.2: the same mesh reads alike
/// in both versions). Ghost entities and the partitions of each entity are read past.
pub(super) fn read_partitioned_entities(r: &mut Reader<'_>) -> Result<()> {
    let binary = r.c.binary;
    let st = r.size_t;
    let names = ["points", "curves", "surfaces", "volumes"];
    let mut counts = [0usize; 4];
    if binary {
        r.c.end_text_line()?;
        r.partitions = r.c.bin_count(st, "number of partitions", 0)?;
        let ghosts = r.c.bin_count(st, "number of ghost entities", 8)?;
        r.c.take_array(ghosts, 8, "ghost entities")?;
        for d in 0..4 {
            let min = if d == 0 { 12 + 2 * st + 24 } else { 12 + 3 * st + 48 };
            counts[d] = r.c.bin_count(st, &format!("number of partitioned {}", names[d]), min)?;
        }
    } else {
        r.partitions = r.c.count("number of partitions", 0)?;
        let ghosts = r.c.count("number of ghost entities", 4)?;
        for _ in 0..ghosts {
            r.c.i32("ghost entity tag")?;
            r.c.i32("ghost entity partition")?;
        }
        for d in 0..4 {
            let min = if d == 0 { 18 } else { 26 };
            counts[d] = r.c.count(&format!("number of partitioned {}", names[d]), min)?;
        }
    }
    for (dim, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            let at = r.c.mark();
            let (tag, parent_dim, parent_tag);
            let phys;
            if binary {
                tag = r.c.bin_i32("entity tag")?;
                parent_dim = r.c.bin_i32("parent dimension")?;
                parent_tag = r.c.bin_i32("parent tag")?;
                let n = r.c.bin_count(st, "number of partitions of the entity", 4)?;
                r.c.take_array(n, 4, "partition tags")?;
                phys = entity_tail(r, dim, tag, at)?.0;
            } else {
                tag = r.c.i32("entity tag")?;
                parent_dim = r.c.i32("parent dimension")?;
                parent_tag = r.c.i32("parent tag")?;
                let n = r.c.count("number of partitions of the entity", 2)?;
                for _ in 0..n {
                    r.c.i32("partition tag")?;
                }
                phys = entity_tail(r, dim, tag, at)?.0;
            }
            // A part of a model entity of its own dimension stands for it; a partition
            // boundary (a curve whose parent is a surface) stands for itself.
            let geometrical = if parent_dim == dim as i32 { parent_tag } else { tag };
            if r.partitioned.insert((dim as u8, tag), (geometrical, phys)).is_some() {
                return Err(r.c.err_at(
                    at,
                    ErrorKind::Inconsistent(format!(
                        "partitioned {} {tag} is defined twice in $PartitionedEntities",
                        &names[dim][..names[dim].len() - 1]
                    )),
                ));
            }
        }
    }
    r.c.expect_end("PartitionedEntities")
}

/// The end of an entity's record in `$Entities` and `$PartitionedEntities`, alike in
/// both: its coordinates (a point's) or bounding box, checked (finite; no minimum above
/// its maximum: Gmsh writes zeros for an entity without a box, meshio zeros always) and
/// returned as `[min, max]` (a point's coordinates twice), which the writer keeps where
/// it holds the entity's nodes; its physical tags, returned; its bounding entities
/// (curves and up), read past. `at` is where the record starts.
fn entity_tail(
    r: &mut Reader<'_>,
    dim: usize,
    tag: i32,
    at: Position,
) -> Result<(Vec<i32>, [f64; 6])> {
    let n_coords = if dim == 0 { 3 } else { 6 };
    let mut xyz = [0.0f64; 6];
    let coords_at = r.c.pos();
    if r.c.binary {
        let b = r.c.take(8 * n_coords, "entity coordinates")?;
        for (c, ch) in xyz.iter_mut().zip(b.chunks_exact(8)) {
            *c = le_f64(ch);
        }
    } else {
        let what = if dim == 0 { "point coordinate" } else { "bounding box coordinate" };
        for c in &mut xyz[..n_coords] {
            *c = r.c.f64(what)?;
        }
    }
    check_box(
        r,
        &xyz[..n_coords],
        dim,
        tag,
        if r.c.binary { Position::Byte(coords_at as u64) } else { at },
    )?;
    if dim == 0 {
        xyz.copy_within(0..3, 3);
    }
    if r.c.binary {
        let st = r.size_t;
        let n = r.c.bin_count(st, "number of physical tags", 4)?;
        let phys = r.c.take_array(n, 4, "physical tags")?.chunks_exact(4).map(le_i32).collect();
        if dim > 0 {
            let n = r.c.bin_count(st, "number of bounding entities", 4)?;
            r.c.take_array(n, 4, "bounding entity tags")?;
        }
        return Ok((phys, xyz));
    }
    let n = r.c.count("number of physical tags", 2)?;
    let mut phys = Vec::with_capacity(n);
    for _ in 0..n {
        phys.push(r.c.i32("physical tag")?);
    }
    if dim > 0 {
        let n = r.c.count("number of bounding entities", 2)?;
        for _ in 0..n {
            r.c.i32("bounding entity tag")?;
        }
    }
    Ok((phys, xyz))
}

/// An entity's point (`dim` 0) or bounding box `min max` (`dim` 1 to 3), as read: every
/// value finite, and each minimum at most its maximum.
fn check_box(r: &Reader<'_>, v: &[f64], dim: usize, tag: i32, at: Position) -> Result<()> {
    const NAMES: [&str; 4] = ["point", "curve", "surface", "volume"];
    if let Some(x) = v.iter().find(|x| !x.is_finite()) {
        return Err(r.c.err_at(
            at,
            ErrorKind::NonFinite {
                what: format!("a coordinate of the box of {} {tag} in $Entities", NAMES[dim]),
                value: x.to_string(),
            },
        ));
    }
    if v.len() == 6 {
        if let Some(k) = (0..3).find(|&k| v[k] > v[k + 3]) {
            return Err(r.c.err_at(
                at,
                ErrorKind::Inconsistent(format!(
                    "the bounding box of {} {tag} in $Entities has its minimum {} above its maximum {} along {}",
                    NAMES[dim],
                    v[k],
                    v[k + 3],
                    ["x", "y", "z"][k]
                )),
            ));
        }
    }
    Ok(())
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
        if kind.dim() as i32 != dim {
            // Gmsh classifies an element on an entity of its own dimension; the physical
            // group of a block comes from its entity, so a mismatch would mislabel it.
            return Err(r.c.err_at(
                block_at,
                ErrorKind::Inconsistent(format!(
                    "a block of {}s (dimension {}) on entity {tag} of dimension {dim}: an element block's entity has the elements' dimension",
                    kind.name(),
                    kind.dim()
                )),
            ));
        }
        let k = kind.nodes_per_cell();
        // Now that the kind is known, the count against the bytes an element of it
        // takes at least (a 27-node hexahedron's record is 14 times a point's): the
        // block's arrays are made for `n` of them.
        let min = if binary { (1 + k) * st } else { 2 * (1 + k) };
        let left = r.c.remaining().len();
        if (n as u128) * (min as u128) > left as u128 {
            let what = format!("{}s in the block", kind.name());
            let e = crate::text::check_count(n, left, min, &what).err();
            return Err(r.c.err_at(block_at, e.unwrap_or(ErrorKind::Inconsistent(what))));
        }
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
                let short = || format!("{k} node tags after element {et} (a {})", kind.name());
                for _ in 0..k {
                    let nt =
                        r.c.scan_u64(&mut s, "node tag")
                            .map_err(|e| short_record(e, line, short))?;
                    let Some(v) = map.node(nt) else {
                        r.c.unscan(&s);
                        return Err(short_record(r.c.err(missing(et, nt)), line, short));
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
