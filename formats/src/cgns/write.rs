//! Writing a mesh as one CGNS base with one unstructured zone (see the module header):
//! a plan (sections, tag ranges, names) made from the mesh alone, then the HDF5 nodes,
//! written to a temporary file whose bytes are the output (libhdf5 writes files).

use std::collections::{BTreeMap, BTreeSet};

use hdf5_metno as hdf5;
use hdf5_metno::Group;

use super::node::{create, create_ints, h5_write, root, Data};
use super::{bc_type, cgns_order, cgns_type, fields};
use crate::{CellKind, Error, ErrorKind, TaggedMesh, WriteReport, Written};

/// One `Elements_t` section: cells of one dimension, tag and kind.
struct Section {
    name: String,
    etype: i64,
    start: i64,
    conn: Vec<i64>,
    count: usize,
}

/// The element range of one (dimension, tag), and its CGNS names.
struct TagRange {
    dim: u8,
    tag: i32,
    first: i64,
    last: i64,
    /// The BC or subregion node's name.
    node: String,
    /// The family (from the tag name), if named.
    family: Option<String>,
    /// For vertex cells: their points (1-based), at `Vertex`.
    points: Vec<i64>,
}

/// A CGNS name: ASCII without `/`, at most 32 characters, not empty.
fn cgns_name(s: &str) -> String {
    let mut n: String = s
        .trim()
        .chars()
        .map(|c| if c.is_ascii() && !c.is_ascii_control() && c != '/' { c } else { '_' })
        .take(32)
        .collect();
    if n.is_empty() || n == "." || n == ".." {
        n = "_".into();
    }
    n
}

/// `want` made a CGNS name unique among `taken` (a ` 2`, ` 3`, … suffix within 32
/// characters), then taken.
fn unique(want: &str, taken: &mut BTreeSet<String>) -> String {
    let base = cgns_name(want);
    let mut name = base.clone();
    let mut i = 2;
    while taken.contains(&name) {
        let suffix = format!(" {i}");
        let keep: String = base.chars().take(32 - suffix.len()).collect();
        name = format!("{keep}{suffix}");
        i += 1;
    }
    taken.insert(name.clone());
    name
}

fn kind_word(kind: CellKind) -> String {
    format!("{kind:?}")
}

/// The whole layout, from the mesh alone.
struct Plan {
    cell_dim: u8,
    sections: Vec<Section>,
    tags: Vec<TagRange>,
    /// Family name → BC type for boundary families, `None` for the others.
    families: BTreeMap<String, Option<&'static str>>,
    zone_cells: usize,
}

fn plan(mesh: &TaggedMesh, report: &mut WriteReport) -> Plan {
    let max_dim = mesh.blocks.iter().filter(|b| !b.is_empty()).map(|b| b.kind.dim()).max();
    let cell_dim = max_dim.unwrap_or(2).max(2);
    // (descending dimension, tag, kind) → cells in mesh order.
    let mut groups: BTreeMap<(u8, i32, CellKind), Vec<(usize, usize)>> = BTreeMap::new();
    for (bi, b) in mesh.blocks.iter().enumerate() {
        for i in 0..b.len() {
            groups.entry((3 - b.kind.dim(), b.physical[i], b.kind)).or_default().push((bi, i));
        }
    }
    let mut taken: BTreeSet<String> = ["ZoneType", "GridCoordinates", "ZoneBC", "FlowSolution"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut bc_taken = BTreeSet::new();
    let mut renamed = BTreeSet::new();
    let mut sections = Vec::new();
    let mut tags: Vec<TagRange> = Vec::new();
    let mut families = BTreeMap::new();
    let mut corners = BTreeMap::new();
    let mut family_of: BTreeMap<String, String> = BTreeMap::new();
    let mut same_name: BTreeMap<(u8, String), Vec<i32>> = BTreeMap::new();
    let mut family_taken: BTreeSet<String> = ["Zone1".to_string()].into_iter().collect();
    let mut next = 1i64;
    let mut zone_cells = 0;
    for (&(rdim, tag, kind), cells) in &groups {
        let dim = 3 - rdim;
        let (etype, by_corners) = cgns_type(kind);
        let written = if by_corners { kind.linear() } else { kind };
        if by_corners {
            *corners.entry(kind).or_insert(0usize) += cells.len();
        }
        let order = cgns_order(written);
        let mut conn = Vec::with_capacity(cells.len() * order.len());
        for &(bi, i) in cells {
            let c = mesh.blocks[bi].cell(i);
            conn.extend(order.iter().map(|&k| i64::from(c[k]) + 1));
        }
        let label = match mesh.tag_name(dim, tag) {
            Some(n) => n.to_string(),
            None => format!("tag{tag}"),
        };
        let want = if sections.is_empty() {
            "GridElements".to_string()
        } else {
            format!("{} {label}", kind_word(written))
        };
        let name = unique(&want, &mut taken);
        let start = next;
        next += cells.len() as i64;
        if dim == cell_dim {
            zone_cells += cells.len();
        }
        let points = if dim == 0 { conn.clone() } else { Vec::new() };
        sections.push(Section { name, etype, start, conn, count: cells.len() });
        match tags.last_mut() {
            Some(t) if t.dim == dim && t.tag == tag => {
                t.last = next - 1;
                t.points.extend(points);
            }
            _ => {
                // Every tag has a family (an unnamed one `tag<N>`): BCs are then
                // `FamilySpecified`, the one BC type every reader takes (ParaView's
                // reads no other but Dirichlet and Neumann), the family saying which.
                let want =
                    mesh.tag_name(dim, tag).map_or_else(|| format!("tag{tag}"), String::from);
                // One family per name, beside the zone under the base.
                let f = family_of
                    .entry(want.clone())
                    .or_insert_with(|| unique(&want, &mut family_taken))
                    .clone();
                if f != want {
                    renamed.insert(format!("`{want}` as `{f}`"));
                }
                same_name.entry((dim, f.clone())).or_default().push(tag);
                let family = Some(f);
                let boundary = dim + 1 == cell_dim;
                if let Some(f) = &family {
                    let bc = boundary.then(|| bc_type(Some(f)));
                    families
                        .entry(f.clone())
                        .and_modify(|b: &mut Option<&str>| *b = b.or(bc))
                        .or_insert(bc);
                }
                let want = family.clone().unwrap_or_else(|| format!("tag{tag}"));
                let node =
                    if boundary { unique(&want, &mut bc_taken) } else { unique(&want, &mut taken) };
                tags.push(TagRange {
                    dim,
                    tag,
                    first: start,
                    last: next - 1,
                    node,
                    family,
                    points,
                });
            }
        }
    }
    for (kind, n) in corners {
        report.drop(format!(
            "the second-order nodes of {n} {kind:?} cells: written as their linear corners \
             (CGNS's node order of that kind is not mapped)"
        ));
    }
    // Vertex cells are tagged through their points (no element location is 0-D): a
    // point under vertex cells of several tags reads back under one of them.
    let mut at_point: BTreeMap<u32, BTreeSet<i32>> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind == CellKind::Vertex) {
        for (i, c) in b.cells().enumerate() {
            at_point.entry(c[0]).or_default().insert(b.physical[i]);
        }
    }
    let shared = at_point.values().filter(|t| t.len() > 1).count();
    if shared > 0 {
        report.drop(format!(
            "the tags of vertex cells on {shared} points that carry vertex cells of several \
             tags: CGNS tags vertex cells by their points, so each such point reads back \
             under one tag"
        ));
    }
    for ((dim, name), tags) in same_name.iter().filter(|(_, t)| t.len() > 1) {
        report.drop(format!(
            "the tag numbers {tags:?} of dimension {dim}: they share the name `{name}`, one \
             CGNS family, and read back as one tag"
        ));
    }
    if !renamed.is_empty() {
        report.drop(format!(
            "tag names made CGNS names (ASCII, no `/`, at most 32 characters): {}",
            renamed.into_iter().collect::<Vec<_>>().join(", ")
        ));
    }
    Plan { cell_dim, sections, tags, families, zone_cells }
}

/// What CGNS, as written here, does not hold.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({} components): written per point only",
            a.components
        ));
    }
    for name in mesh.point_sets.keys() {
        report.drop(format!("point set `{name}`"));
    }
    for name in mesh.cell_sets.keys() {
        report.drop(format!("cell set `{name}`"));
    }
    let differ: usize = mesh.blocks.iter().map(|b| b.tags_differ()).sum();
    if differ > 0 {
        report.drop(format!(
            "the geometrical tags of {differ} cells that differ from their physical tags: \
             CGNS gives a cell one boundary or region"
        ));
    }
    if !mesh.holes.is_empty() || !mesh.regions.is_empty() {
        report.drop("hole and region seed points (Triangle's .poly)");
    }
}

/// Writes a mesh as a CGNS/HDF5 file.
pub(super) fn write(mesh: &TaggedMesh) -> crate::Result<Written> {
    let mut report = WriteReport::default();
    report_unheld(mesh, &mut report);
    let p = plan(mesh, &mut report);
    let tmp = tempfile::Builder::new()
        .prefix("smartmesh-")
        .suffix(".cgns")
        .tempfile()
        .map_err(|e| Error::new(ErrorKind::Io(e)))?;
    write_file(tmp.path(), mesh, &p, &mut report).map_err(h5_write)?;
    let main = std::fs::read(tmp.path()).map_err(|e| Error::new(ErrorKind::Io(e)))?;
    Ok(Written { main, siblings: Vec::new(), report })
}

fn write_file(
    path: &std::path::Path,
    mesh: &TaggedMesh,
    p: &Plan,
    report: &mut WriteReport,
) -> hdf5::Result<()> {
    use hdf5_metno::plist::file_create::LinkCreationOrder;
    let file = hdf5::File::with_options()
        .with_fcpl(|c| c.link_creation_order(LinkCreationOrder::Indexed))
        .create(path)?;
    root(&file)?;
    create(&file, "CGNSLibraryVersion", "CGNSLibraryVersion_t", Data::R4(&[3.4]))?;
    let dims = [i32::from(p.cell_dim), 3];
    let base = create(&file, "Base", "CGNSBase_t", Data::I4(&dims, &[2]))?;
    let sizes = [mesh.points.len() as i64, p.zone_cells as i64, 0];
    let zone = create_ints(&base, "Zone1", "Zone_t", &sizes, &[1, 3])?;
    create(&zone, "ZoneType", "ZoneType_t", Data::C1("Unstructured"))?;
    let coords = create(&zone, "GridCoordinates", "GridCoordinates_t", Data::Empty)?;
    for (axis, name) in ["CoordinateX", "CoordinateY", "CoordinateZ"].iter().enumerate() {
        let v: Vec<f64> = mesh.points.iter().map(|q| q[axis]).collect();
        create(&coords, name, "DataArray_t", Data::R8(&v))?;
    }
    for s in &p.sections {
        let head = [s.etype as i32, 0];
        let g = create(&zone, &s.name, "Elements_t", Data::I4(&head, &[2]))?;
        create_ints(
            &g,
            "ElementRange",
            "IndexRange_t",
            &[s.start, s.start + s.count as i64 - 1],
            &[2],
        )?;
        create_ints(&g, "ElementConnectivity", "DataArray_t", &s.conn, &[s.conn.len()])?;
    }
    write_tags(&zone, p)?;
    write_solution(&zone, mesh, report)?;
    for (name, bc) in &p.families {
        let f = create(&base, name, "Family_t", Data::Empty)?;
        match bc {
            Some(bc) => create(&f, "FamilyBC", "FamilyBC_t", Data::C1(bc))?,
            // A family with no child trips ParaView's reader ("Mismatch in number of
            // children"): a region's family says what it is.
            None => {
                create(&f, "description", "Descriptor_t", Data::C1("cells of a smartmesh region"))?
            }
        };
    }
    file.close()
}

/// `ZoneBC` with a `BC_t` per boundary tag, a `ZoneSubRegion_t` per other tag.
fn write_tags(zone: &Group, p: &Plan) -> hdf5::Result<()> {
    let boundary: Vec<&TagRange> = p.tags.iter().filter(|t| t.dim + 1 == p.cell_dim).collect();
    if !boundary.is_empty() {
        let zbc = create(zone, "ZoneBC", "ZoneBC_t", Data::Empty)?;
        let location = if p.cell_dim == 3 { "FaceCenter" } else { "EdgeCenter" };
        for t in boundary {
            let bc = create(&zbc, &t.node, "BC_t", Data::C1("FamilySpecified"))?;
            create(&bc, "GridLocation", "GridLocation_t", Data::C1(location))?;
            create_ints(&bc, "PointRange", "IndexRange_t", &[t.first, t.last], &[1, 2])?;
            tag_children(&bc, t)?;
        }
    }
    for t in p.tags.iter().filter(|t| t.dim + 1 != p.cell_dim) {
        let dims = [i32::from(t.dim.max(1))];
        let r = create(zone, &t.node, "ZoneSubRegion_t", Data::I4(&dims, &[1]))?;
        if t.dim == 0 {
            create(&r, "GridLocation", "GridLocation_t", Data::C1("Vertex"))?;
            create_ints(&r, "PointList", "IndexArray_t", &t.points, &[1, t.points.len()])?;
        } else {
            let location = match t.dim {
                d if d == p.cell_dim => "CellCenter",
                1 => "EdgeCenter",
                _ => "FaceCenter",
            };
            create(&r, "GridLocation", "GridLocation_t", Data::C1(location))?;
            create_ints(&r, "PointRange", "IndexRange_t", &[t.first, t.last], &[1, 2])?;
        }
        tag_children(&r, t)?;
    }
    Ok(())
}

/// The `FamilyName` of a tag and the `smartmesh_tag` descriptor with its number.
fn tag_children(g: &Group, t: &TagRange) -> hdf5::Result<()> {
    if let Some(f) = &t.family {
        create(g, "FamilyName", "FamilyName_t", Data::C1(f))?;
    }
    create(g, "smartmesh_tag", "Descriptor_t", Data::C1(&t.tag.to_string()))?;
    Ok(())
}

/// `FlowSolution` at `Vertex` with every point field (see `fields`).
fn write_solution(zone: &Group, mesh: &TaggedMesh, report: &mut WriteReport) -> hdf5::Result<()> {
    if mesh.point_data.is_empty() {
        return Ok(());
    }
    let sol = create(zone, "FlowSolution", "FlowSolution_t", Data::Empty)?;
    create(&sol, "GridLocation", "GridLocation_t", Data::C1("Vertex"))?;
    let mut taken: BTreeSet<String> = ["GridLocation".to_string()].into_iter().collect();
    for (name, array) in &mesh.point_data {
        let a = array.expanded();
        let suffixes = fields::suffixes(a.components);
        let room = 32 - suffixes.iter().map(|s| s.len()).max().unwrap_or(0);
        let base: String = cgns_name(name).chars().take(room).collect();
        if base != *name {
            report
                .drop(format!("the point field name `{name}`: written as the CGNS name `{base}`"));
        }
        for (c, s) in suffixes.iter().enumerate() {
            let v: Vec<f64> = (0..a.len()).map(|i| a.item(i)[c]).collect();
            let n = unique(&format!("{base}{s}"), &mut taken);
            create(&sol, &n, "DataArray_t", Data::R8(&v))?;
        }
    }
    Ok(())
}
