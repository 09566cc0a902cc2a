//! Reading CGNS/HDF5 files: the first base, every unstructured zone merged (see the
//! module header for what becomes what). Each zone's sections are read whole and
//! checked, then the BCs and subregions claim their cells, then the cells are emitted
//! with the tags the claims resolve to.

use std::collections::BTreeMap;

use hdf5_metno as hdf5;

use super::node::{bad, child_labelled, children_labelled, ints, open, reals, text, Node};
use super::{etype, fields, kind_of, type_name};
use crate::{CellKind, Error, ErrorKind, ReadReport, Result, TaggedMesh, MAX_POINTS};

/// The HDF5 signature, at offset 0 or at a power of two from 512 (after a user block).
const SIGNATURE: &[u8] = b"\x89HDF\r\n\x1a\n";

/// The largest cell count a section may announce: one per point index a mesh can
/// address, times the largest element (27 nodes) — beyond, no mesh can hold it.
const MAX_VALUES: usize = MAX_POINTS.saturating_mul(27);

/// A tag a BC, a subregion, a zone or a section claims: (dimension, name or number).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
enum Label {
    Named(String),
    Number(i32),
}

/// The claims, in file order, and what each wants.
#[derive(Default)]
struct Claims {
    list: Vec<(u8, Label, Option<i32>)>,
    index: BTreeMap<(u8, Label), u32>,
}

impl Claims {
    fn claim(&mut self, dim: u8, label: Label, wanted: Option<i32>) -> u32 {
        let key = (dim, label.clone());
        if let Some(&i) = self.index.get(&key) {
            return i;
        }
        let i = self.list.len() as u32;
        self.list.push((dim, label, wanted));
        self.index.insert(key, i);
        i
    }

    /// The tag number of each claim: the number it wants where free in its dimension
    /// (a `tag<N>` name wants N), then the smallest free numbers in claim order.
    fn resolve(&self, mesh: &mut TaggedMesh) -> Vec<i32> {
        let mut used: BTreeMap<u8, std::collections::BTreeSet<i32>> = BTreeMap::new();
        let mut out = vec![0; self.list.len()];
        for (i, (dim, label, wanted)) in self.list.iter().enumerate() {
            let want = match label {
                Label::Number(n) => Some(*n),
                Label::Named(_) => *wanted,
            };
            if let Some(w) = want.filter(|&w| w > 0) {
                if used.entry(*dim).or_default().insert(w) {
                    out[i] = w;
                }
            }
        }
        for (i, (dim, _, _)) in self.list.iter().enumerate() {
            if out[i] == 0 {
                let u = used.entry(*dim).or_default();
                let n = (1..).find(|n| !u.contains(n)).unwrap_or(1);
                u.insert(n);
                out[i] = n;
            }
        }
        for (i, (dim, label, _)) in self.list.iter().enumerate() {
            if let Label::Named(name) = label {
                mesh.tag_names.insert((*dim, out[i]), name.clone());
            }
        }
        out
    }
}

/// One section read: its first element number, and its elements (kind, nodes 0-based
/// in the merged mesh, Gmsh order) flat.
struct Section {
    name: String,
    start: i64,
    kinds: Vec<CellKind>,
    nodes: Vec<u32>,
    /// The claim each element's tag comes from (`u32::MAX`: none yet).
    claim: Vec<u32>,
}

/// Reads a CGNS/HDF5 file from its bytes.
pub(super) fn read(bytes: &[u8]) -> Result<(TaggedMesh, ReadReport)> {
    check_signature(bytes)?;
    // libhdf5 reads files: the bytes go to a temporary one first.
    let mut tmp = tempfile::Builder::new()
        .prefix("smartmesh-")
        .suffix(".cgns")
        .tempfile()
        .map_err(|e| Error::new(ErrorKind::Io(e)))?;
    std::io::Write::write_all(&mut tmp, bytes).map_err(|e| Error::new(ErrorKind::Io(e)))?;
    let file = hdf5::File::open(tmp.path()).map_err(|e| {
        Error::at_byte(
            0,
            ErrorKind::Expected { expected: "a readable HDF5 file".into(), found: e.to_string() },
        )
    })?;
    let root_group = file.as_group().map_err(|e| bad("/", "the root group", e.to_string()))?;
    let root = Node {
        group: root_group,
        path: "/".into(),
        name: String::new(),
        label: String::new(),
        code: "MT".into(),
    };
    let mut report = ReadReport::default();
    let bases = children_labelled(&root, "CGNSBase_t")?;
    let Some(base) = bases.first() else {
        return Err(bad("/", "a CGNSBase_t node", "none"));
    };
    if bases.len() > 1 {
        report.note(format!("{} bases: only the first, `{}`, was read", bases.len(), base.name));
    }
    let dims = ints(base, 2)?;
    let (cell_dim, phys_dim) = match dims[..] {
        [c, p] if (1..=3).contains(&c) && (1..=3).contains(&p) && c <= p => (c as u8, p as u8),
        _ => {
            return Err(bad(
                &base.path,
                "cell and physical dimensions (1 to 3, cell <= physical)",
                format!("{dims:?}"),
            ))
        }
    };
    let zones = children_labelled(base, "Zone_t")?;
    if zones.is_empty() {
        return Err(bad(&base.path, "a Zone_t node", "none"));
    }
    let mut mesh = TaggedMesh::new();
    let mut claims = Claims::default();
    let mut sections = Vec::new();
    let mut solutions: Vec<BTreeMap<String, Vec<f64>>> = Vec::new();
    for zone in &zones {
        let offset = mesh.points.len();
        read_zone(zone, phys_dim, cell_dim, &mut mesh, &mut claims, &mut sections, &mut report)?;
        let nv = mesh.points.len() - offset;
        solutions.push(read_solutions(zone, nv, &mut report)?);
    }
    if zones.len() > 1 {
        report.note(format!(
            "{} zones read as one mesh, each zone's points apart (CGNS zones share no points)",
            zones.len()
        ));
    }
    let tags = claims.resolve(&mut mesh);
    for s in sections {
        let mut at = 0;
        for (i, &kind) in s.kinds.iter().enumerate() {
            let n = kind.nodes_per_cell();
            let tag = tags.get(s.claim[i] as usize).copied().unwrap_or(1);
            mesh.block_mut(kind).push(&s.nodes[at..at + n], tag, tag);
            at += n;
        }
    }
    merge_solutions(&mut mesh, &zones, solutions, &mut report);
    mesh.coordinate_dim =
        if phys_dim < 3 || (cell_dim < 3 && mesh.points.iter().all(|p| p[2] == 0.0)) {
            2
        } else {
            3
        };
    Ok((mesh, report))
}

fn check_signature(bytes: &[u8]) -> Result<()> {
    if bytes.starts_with(b"@(#)ADF")
        || bytes.get(..64).is_some_and(|h| h.windows(3).any(|w| w == b"ADF"))
            && !bytes.starts_with(SIGNATURE)
    {
        return Err(Error::at_byte(0, ErrorKind::Expected {
            expected: "a CGNS file in HDF5 (this one is CGNS's older ADF; `cgnsconvert -h IN OUT` converts it)".into(),
            found: "the ADF signature".into(),
        }));
    }
    let mut at = 0usize;
    while at < bytes.len() {
        if bytes[at..].starts_with(SIGNATURE) {
            return Ok(());
        }
        at = if at == 0 { 512 } else { at * 2 };
    }
    Err(Error::at_byte(
        0,
        ErrorKind::Expected {
            expected: "the HDF5 signature (\\x89HDF) of a CGNS/HDF5 file".into(),
            found: format!("{:?}", String::from_utf8_lossy(&bytes[..bytes.len().min(8)])),
        },
    ))
}

/// Reads one zone's points and sections, and the claims of its BCs and subregions.
fn read_zone(
    zone: &Node,
    phys_dim: u8,
    cell_dim: u8,
    mesh: &mut TaggedMesh,
    claims: &mut Claims,
    sections: &mut Vec<Section>,
    report: &mut ReadReport,
) -> Result<()> {
    let zt = child_labelled(zone, "ZoneType_t")?
        .ok_or_else(|| bad(&zone.path, "a ZoneType_t child", "none"))?;
    let kind = text(&zt)?;
    if kind != "Unstructured" {
        return Err(Error::new(ErrorKind::Unsupported(format!(
            "zone {} is {kind}: smartmesh reads unstructured CGNS zones",
            zone.path
        ))));
    }
    let sizes = ints(zone, 9)?;
    let nv = match sizes[..] {
        [nv, _, _] if nv >= 0 && (nv as u64) <= MAX_POINTS as u64 => nv as usize,
        _ => {
            return Err(bad(
                &zone.path,
                "the sizes of an unstructured zone (3 integers, vertices first)",
                format!("{sizes:?}"),
            ))
        }
    };
    let offset = mesh.points.len();
    if offset + nv > MAX_POINTS {
        return Err(bad(
            &zone.path,
            format!("at most {MAX_POINTS} points in all zones"),
            format!("{}", offset + nv),
        ));
    }
    read_coordinates(zone, nv, phys_dim, mesh)?;
    let first_section = sections.len();
    for sec in children_labelled(zone, "Elements_t")? {
        sections.push(read_section(&sec, offset, nv, report)?);
    }
    // Element numbers are unique within a zone.
    let mut ranges: Vec<(i64, i64, &str)> = sections[first_section..]
        .iter()
        .map(|s| (s.start, s.start + s.kinds.len() as i64 - 1, s.name.as_str()))
        .collect();
    ranges.sort();
    for w in ranges.windows(2) {
        if w[1].0 <= w[0].1 && w[1].1 >= w[1].0 {
            return Err(bad(
                &zone.path,
                "element ranges that do not overlap",
                format!("`{}` and `{}` overlap", w[0].2, w[1].2),
            ));
        }
    }
    let zone_secs = &mut sections[first_section..];
    claim_tags(zone, offset, nv, zone_secs, claims, mesh)?;
    // What no BC or subregion claimed: a tag per zone for cells of the zone's
    // dimension, a tag per section for the others.
    for s in zone_secs.iter_mut() {
        for (i, k) in s.kinds.iter().enumerate() {
            if s.claim[i] == u32::MAX {
                let d = k.dim();
                let name = if d == cell_dim { zone.name.clone() } else { s.name.clone() };
                s.claim[i] = claims.claim(d, label_of(&name), None);
            }
        }
    }
    Ok(())
}

/// `tag<N>` is the unnamed tag N (as the writer names an unnamed tag), any other name
/// a named tag.
fn label_of(name: &str) -> Label {
    match name.strip_prefix("tag").and_then(|n| n.parse::<i32>().ok()) {
        Some(n) if n > 0 => Label::Number(n),
        _ => Label::Named(name.to_string()),
    }
}

fn read_coordinates(zone: &Node, nv: usize, phys_dim: u8, mesh: &mut TaggedMesh) -> Result<()> {
    let grids = children_labelled(zone, "GridCoordinates_t")?;
    let grid = grids
        .iter()
        .find(|g| g.name == "GridCoordinates")
        .or(grids.first())
        .ok_or_else(|| bad(&zone.path, "a GridCoordinates_t child", "none"))?;
    let arrays = children_labelled(grid, "DataArray_t")?;
    let start = mesh.points.len();
    mesh.points.resize(start + nv, [0.0; 3]);
    for (axis, name) in ["CoordinateX", "CoordinateY", "CoordinateZ"].iter().enumerate() {
        let Some(a) = arrays.iter().find(|a| a.name == *name) else {
            if axis < phys_dim as usize {
                return Err(bad(
                    &grid.path,
                    format!("a {name} array (physical dimension {phys_dim})"),
                    "none",
                ));
            }
            continue;
        };
        let v = reals(a, nv)?;
        if v.len() != nv {
            return Err(bad(
                &a.path,
                format!("{nv} coordinates (the zone's vertices)"),
                format!("{}", v.len()),
            ));
        }
        for (i, x) in v.into_iter().enumerate() {
            if !x.is_finite() {
                return Err(Error::new(ErrorKind::NonFinite {
                    what: format!("{} value {}", a.path, i + 1),
                    value: x.to_string(),
                }));
            }
            mesh.points[start + i][axis] = x;
        }
    }
    Ok(())
}

/// One `Elements_t` node: its type, range and connectivity, every node index checked.
fn read_section(sec: &Node, offset: usize, nv: usize, report: &mut ReadReport) -> Result<Section> {
    let head = ints(sec, 2)?;
    let t = *head.first().ok_or_else(|| bad(&sec.path, "the element type", "no data"))?;
    let range_node = open(&sec.group, &sec.path, "ElementRange")?;
    let range = ints(&range_node, 2)?;
    let (start, count) = match range[..] {
        [a, b] if a >= 1 && b >= a - 1 => (a, (b - a + 1) as u64),
        _ => {
            return Err(bad(
                &range_node.path,
                "an element range `first last` (first >= 1)",
                format!("{range:?}"),
            ))
        }
    };
    let conn_node = open(&sec.group, &sec.path, "ElementConnectivity")?;
    if t == etype::NGON_N || t == etype::NFACE_N {
        return Err(Error::new(ErrorKind::Unsupported(format!(
            "{} is a polyhedral section ({}); smartmesh reads element sections of fixed kinds and MIXED",
            sec.path,
            type_name(t)
        ))));
    }
    let per = if t == etype::MIXED { 28 } else { kind_of(t).map_or(0, |k| k.1) as u64 };
    if per == 0 {
        return Err(bad(&sec.path, "a CGNS element type (SIDS ElementType_t)", type_name(t)));
    }
    let limit = count.saturating_mul(per).min(MAX_VALUES as u64) as usize;
    let conn = ints(&conn_node, limit)?;
    // Every element has at least one value: a count past the values is no count.
    if count > conn.len() as u64 {
        return Err(bad(
            &range_node.path,
            format!("at most {} elements (the connectivity's values)", conn.len()),
            format!("{count}"),
        ));
    }
    let count = count as usize;
    let mut s = Section {
        name: sec.name.clone(),
        start,
        kinds: Vec::with_capacity(count),
        nodes: Vec::with_capacity(conn.len()),
        claim: vec![u32::MAX; count],
    };
    let mut at = 0usize;
    let mut corners_only = 0usize;
    for e in 0..count {
        let et = if t == etype::MIXED {
            let et = *conn
                .get(at)
                .ok_or_else(|| bad(&conn_node.path, format!("{count} elements"), format!("{e}")))?;
            at += 1;
            et
        } else {
            t
        };
        let Some((kind, n, corners)) = kind_of(et) else {
            return Err(bad(
                &conn_node.path,
                format!("a fixed element type for element {}", start + e as i64),
                type_name(et),
            ));
        };
        let Some(cell) = conn.get(at..at + n) else {
            return Err(bad(
                &conn_node.path,
                format!("{n} nodes for element {} ({})", start + e as i64, type_name(et)),
                format!("{} values left", conn.len() - at.min(conn.len())),
            ));
        };
        at += n;
        let order = super::cgns_order(kind);
        for &k in order {
            let v = cell[k];
            if v < 1 || v as u64 > nv as u64 {
                return Err(Error::new(ErrorKind::IndexOutOfRange {
                    what: format!("{} element {}", conn_node.path, start + e as i64),
                    index: v,
                    available: nv,
                }));
            }
            s.nodes.push((offset + v as usize - 1) as u32);
        }
        corners_only += usize::from(corners);
        s.kinds.push(kind);
    }
    if at != conn.len() {
        return Err(bad(
            &conn_node.path,
            format!("the nodes of {count} elements ({at} values)"),
            format!("{} values", conn.len()),
        ));
    }
    if corners_only > 0 {
        report.note(format!(
            "{}: {corners_only} second-order {} elements read by their corners",
            sec.path,
            type_name(t)
        ));
    }
    Ok(s)
}

/// The element numbers or vertex indices a BC or subregion names: its location and
/// its list (`PointRange` expanded, `PointList`, or the older `ElementRange`/`ElementList`,
/// which are element numbers whatever the location).
fn region_items(node: &Node, limit: usize) -> Result<Option<(bool, Vec<i64>)>> {
    let location = match child_labelled(node, "GridLocation_t")? {
        Some(l) => text(&l)?,
        None => "Vertex".to_string(),
    };
    let by_element = location != "Vertex";
    for c in super::node::children(node)? {
        let (elements, items) = match (c.name.as_str(), c.label.as_str()) {
            ("PointRange", _) | (_, "IndexRange_t") if c.name != "ElementRange" => {
                (by_element, range_items(&c, limit)?)
            }
            ("ElementRange", _) => (true, range_items(&c, limit)?),
            ("PointList", _) => (by_element, ints(&c, limit)?),
            ("ElementList", _) => (true, ints(&c, limit)?),
            _ => continue,
        };
        return Ok(Some((elements, items)));
    }
    Ok(None)
}

fn range_items(node: &Node, limit: usize) -> Result<Vec<i64>> {
    let r = ints(node, 2)?;
    match r[..] {
        [a, b] if a >= 1 && b >= a && ((b - a) as u64) < limit as u64 => Ok((a..=b).collect()),
        _ => Err(bad(
            &node.path,
            format!("a range `first last` of at most {limit} items"),
            format!("{r:?}"),
        )),
    }
}

/// The claims of the zone's BCs and subregions on its elements (and vertex cells).
fn claim_tags(
    zone: &Node,
    offset: usize,
    nv: usize,
    secs: &mut [Section],
    claims: &mut Claims,
    mesh: &mut TaggedMesh,
) -> Result<()> {
    let total: usize = secs.iter().map(|s| s.kinds.len()).sum();
    let mut holders = Vec::new();
    if let Some(zbc) = child_labelled(zone, "ZoneBC_t")? {
        holders.extend(children_labelled(&zbc, "BC_t")?);
    }
    holders.extend(children_labelled(zone, "ZoneSubRegion_t")?);
    // Element number → (section, index), sections by start.
    let mut order: Vec<usize> = (0..secs.len()).collect();
    order.sort_by_key(|&i| secs[i].start);
    for h in holders {
        let family = match child_labelled(&h, "FamilyName_t")? {
            Some(f) => Some(text(&f)?),
            None => None,
        };
        let wanted = match super::node::children_labelled(&h, "Descriptor_t")?
            .into_iter()
            .find(|d| d.name == "smartmesh_tag")
        {
            Some(d) => text(&d)?.trim().parse::<i32>().ok(),
            None => None,
        };
        let label = match &family {
            Some(f) if !f.is_empty() => label_of(f),
            _ => label_of(&h.name),
        };
        let Some((by_element, items)) = region_items(&h, total.max(nv))? else { continue };
        if by_element {
            for e in items {
                let found = order
                    .iter()
                    .map(|&i| &secs[i])
                    .position(|s| e >= s.start && e < s.start + s.kinds.len() as i64);
                let Some(p) = found else {
                    return Err(Error::new(ErrorKind::IndexOutOfRange {
                        what: format!("{} element", h.path),
                        index: e,
                        available: total,
                    }));
                };
                let s = &mut secs[order[p]];
                let i = (e - s.start) as usize;
                s.claim[i] = claims.claim(s.kinds[i].dim(), label.clone(), wanted);
            }
        } else {
            // Vertices: the vertex cells on them take the tag; without any, a point set.
            let mut points = Vec::with_capacity(items.len());
            for v in items {
                if v < 1 || v as u64 > nv as u64 {
                    return Err(Error::new(ErrorKind::IndexOutOfRange {
                        what: format!("{} vertex", h.path),
                        index: v,
                        available: nv,
                    }));
                }
                points.push(offset + v as usize - 1);
            }
            let set: std::collections::BTreeSet<usize> = points.iter().copied().collect();
            let mut tagged = false;
            for s in secs.iter_mut() {
                for i in 0..s.kinds.len() {
                    if s.kinds[i] == CellKind::Vertex {
                        let at = s.nodes_before(i);
                        if set.contains(&(s.nodes[at] as usize)) {
                            s.claim[i] = claims.claim(0, label.clone(), wanted);
                            tagged = true;
                        }
                    }
                }
            }
            if !tagged {
                let name = family.unwrap_or_else(|| h.name.clone());
                mesh.point_sets.entry(name).or_default().extend(points);
            }
        }
    }
    Ok(())
}

impl Section {
    /// Where element `i`'s nodes start in `nodes`.
    fn nodes_before(&self, i: usize) -> usize {
        self.kinds[..i].iter().map(|k| k.nodes_per_cell()).sum()
    }
}

/// The vertex arrays of the zone's `FlowSolution_t` nodes (name → values).
fn read_solutions(
    zone: &Node,
    nv: usize,
    report: &mut ReadReport,
) -> Result<BTreeMap<String, Vec<f64>>> {
    let mut out = BTreeMap::new();
    for sol in children_labelled(zone, "FlowSolution_t")? {
        let location = match child_labelled(&sol, "GridLocation_t")? {
            Some(l) => text(&l)?,
            None => "Vertex".to_string(),
        };
        if location != "Vertex" {
            report.note(format!(
                "{}: a solution at {location} was left (smartmesh reads solutions at Vertex)",
                sol.path
            ));
            continue;
        }
        for a in children_labelled(&sol, "DataArray_t")? {
            let v = reals(&a, nv)?;
            if v.len() != nv {
                return Err(bad(
                    &a.path,
                    format!("{nv} values (the zone's vertices)"),
                    format!("{}", v.len()),
                ));
            }
            if out.contains_key(&a.name) {
                report.note(format!("{}: a second array `{}` was left", a.path, a.name));
                continue;
            }
            out.insert(a.name.clone(), v);
        }
    }
    Ok(out)
}

/// The zones' arrays as point data: an array every zone has, zone after zone; one some
/// zones lack is left, said in a note.
fn merge_solutions(
    mesh: &mut TaggedMesh,
    zones: &[Node],
    mut solutions: Vec<BTreeMap<String, Vec<f64>>>,
    report: &mut ReadReport,
) {
    let Some(first) = solutions.first() else { return };
    let names: Vec<String> = first.keys().cloned().collect();
    let mut arrays = Vec::new();
    for name in names {
        if solutions.iter().all(|s| s.contains_key(&name)) {
            let mut v = Vec::with_capacity(mesh.points.len());
            for s in solutions.iter_mut() {
                v.extend(s.remove(&name).unwrap_or_default());
            }
            arrays.push((name, v));
        }
    }
    for (z, s) in solutions.iter().enumerate() {
        for name in s.keys() {
            report.note(format!(
                "the solution array `{name}` of zone {}: not in every zone, left",
                zones.get(z).map_or("?", |n| n.path.as_str())
            ));
        }
    }
    mesh.point_data.extend(fields::assemble(arrays));
}
