//! Fluent mesh files, written ASCII and read ASCII or binary (`read` parses the
//! sections, `build` rebuilds the cells from their faces): the `.msh` a Fluent session
//! reads with *File > Read > Mesh*, and OpenFOAM's `fluentMeshToFoam` converts.
//!
//! Which files: Fluent's extension is `.msh`, which is Gmsh's too, so a path is Fluent
//! only when its name ends in `.fluent.msh` ([`crate::Format::from_path`]) or when
//! `--from`/`--to fluent` says so; a plain `.msh` stays Gmsh, except that a `.msh` read
//! whose first non-blank byte is `(` ([`claims`]) is read as Fluent.
//!
//! Source: the Fluent User's Guide, appendix *Case and Data File Formats*, sections
//! *Grid Sections* (comment `(0 "...")`, header `(1 "...")`, dimension `(2 ND)`, nodes
//! `(10 (zone first last type ND)(x y [z] ...))`, cells `(12 (zone first last type
//! element-type))`, faces `(13 (zone first last bc-type face-type)(n0 n1 [n2 n3] c0
//! c1 ...))`, zone names `(45 (zone type name)())`), every index and count of those
//! headers in hexadecimal but the zone id of a `(45 ...)` record in decimal
//! (`fluentMeshToFoam` reads `1a` there as no zone, `26` as zone 0x1a); and Debian
//! OpenFOAM's `fluentMeshToFoam`, which the tests run with `checkMesh` after it.
//!
//! What is written:
//! - the cells of the mesh's highest dimension (triangles and quads in 2D; tetrahedra,
//!   hexahedra, wedges, pyramids in 3D; second-order cells by their corners), one
//!   `fluid` cell zone per physical tag, named from the tag's name;
//! - each side of each cell once (see `faces`), `c1 = 0` on the boundary, its nodes
//!   ordered as Fluent's right-hand rule wants: a polygon's normal points into `c0`; an
//!   edge `n0 → n1` has `c0` on its left (z × (n1 − n0) points into `c0`). Measured with
//!   `fluentMeshToFoam` + `checkMesh`: the other order in 3D, or its mirror in 2D, gives
//!   every cell a negative volume;
//! - face zones: the inner faces (`interior`, named `default-interior`); inner faces
//!   under a tagged line (2D) or surface cell (3D) in an `interior` zone named from the
//!   tag; boundary faces by the physical tag of the boundary cell on them, one zone per
//!   tag, its type from the name ([`bc_type`]), boundary faces with no tagged cell in
//!   `defaultFaces` (`wall`);
//! - only the nodes the cells use (Fluent nodes belong to faces);
//! - periodic sides ([`crate::OpenFoamWrite::cyclic`]) as a `periodic` and a
//!   `periodic-shadow` zone with their face pairs (module `periodic`).
//!
//! Refused: a mesh without surface or volume cells, a 2D mesh off the z = 0 plane, a
//! face shared by more than two cells. Reported as dropped: fields, sets, vertex
//! cells, second-order nodes, boundary cells that lie on no cell's side, unused points.
//!
//! Hand-written: no maintained Rust crate writes Fluent meshes.

mod build;
mod faces;
mod periodic;
mod read;

use std::collections::{BTreeMap, BTreeSet};
use std::io::Write as _;

use crate::{CellKind, Error, ErrorKind, Result, TaggedMesh, WriteOptions, WriteReport, Written};
use faces::{centroid, local_faces, orient_outward, Faces, NONE};

/// The writer validates nothing itself: `write_bytes` validates first.
pub(crate) const CHECKS: crate::Checks = crate::Checks::NONE;

/// Fluent's boundary-condition types with their codes, as the `bc-type` of a face
/// zone's header and the type word of its `(45 ...)` name record.
pub const BC_TYPES: [(&str, u32); 15] = [
    ("interior", 2),
    ("wall", 3),
    ("pressure-inlet", 4),
    ("pressure-outlet", 5),
    ("symmetry", 7),
    ("periodic-shadow", 8),
    ("pressure-far-field", 9),
    ("velocity-inlet", 10),
    ("periodic", 12),
    ("fan", 14),
    ("mass-flow-inlet", 20),
    ("interface", 24),
    ("parent", 31),
    ("outflow", 36),
    ("axis", 37),
];

/// The Fluent type of a boundary zone from its name, with the OpenFOAM writer's rule
/// ([`crate::openfoam::patch_type`]) deciding what is a wall; then, in this order,
/// `symmetry`, `pressure-far-field` (far, freestream), `pressure-inlet` (an inlet
/// whose name says pressure), `velocity-inlet` (inlet, inflow), `pressure-outlet`
/// (outlet, outflow), `interface`. `None` when the name says none of these.
pub fn bc_type(name: &str) -> Option<&'static str> {
    let lower = name.to_ascii_lowercase();
    let has = |words: &[&str]| words.iter().any(|w| lower.contains(w));
    Some(if crate::openfoam::patch_type(name) == "wall" {
        "wall"
    } else if has(&["symmetry"]) {
        "symmetry"
    } else if has(&["far", "freestream"]) {
        "pressure-far-field"
    } else if has(&["inlet", "inflow"]) && has(&["pressure"]) {
        "pressure-inlet"
    } else if has(&["inlet", "inflow"]) {
        "velocity-inlet"
    } else if has(&["outlet", "outflow"]) {
        "pressure-outlet"
    } else if has(&["interface"]) {
        "interface"
    } else {
        return None;
    })
}

/// The type of the boundary zone `name`: the user's (`--patch-type NAME=TYPE`, read
/// from [`crate::OpenFoamWrite::patch_types`]) when it is a Fluent type, or OpenFOAM's
/// `wall` / `symmetryPlane` / `symmetry`; else [`bc_type`]'s guess; else `wall`, Fluent's
/// own default for a boundary zone, said in the report.
fn zone_type(name: &str, opts: &WriteOptions, report: &mut WriteReport) -> &'static str {
    if let Some(t) = opts.openfoam.patch_types.get(name) {
        if let Some(&(f, _)) = BC_TYPES.iter().find(|(f, _)| f.eq_ignore_ascii_case(t)) {
            return f;
        }
        match t.as_str() {
            "wall" => return "wall",
            "symmetryPlane" | "symmetry" => return "symmetry",
            _ => {}
        }
    }
    bc_type(name).unwrap_or_else(|| {
        report.drop(format!(
            "zone `{name}`: its name says no boundary type, written as `wall` \
             (`--patch-type {name}=TYPE` chooses one)"
        ));
        "wall"
    })
}

fn code(bc: &str) -> u32 {
    BC_TYPES.iter().find(|(n, _)| *n == bc).map_or(3, |&(_, c)| c)
}

/// `name` as a Fluent zone name: blanks, quotes and parentheses become `_`.
fn zone_word(name: &str) -> String {
    let w: String = name
        .trim()
        .chars()
        .map(|c| if c.is_whitespace() || c.is_control() || "\"'()".contains(c) { '_' } else { c })
        .collect();
    if w.is_empty() {
        "_".into()
    } else {
        w
    }
}

/// Fluent's cell element types.
fn cell_type(kind: CellKind) -> u32 {
    match kind.linear() {
        CellKind::Triangle => 1,
        CellKind::Tetra => 2,
        CellKind::Quad => 3,
        CellKind::Hexa => 4,
        CellKind::Pyramid => 5,
        CellKind::Wedge => 6,
        _ => 0,
    }
}

/// Whether `bytes` look like a Fluent mesh rather than a Gmsh one: the first
/// non-blank byte is `(` (a Gmsh file starts with `$MeshFormat`).
pub fn claims(bytes: &[u8]) -> bool {
    bytes.iter().find(|c| !c.is_ascii_whitespace()) == Some(&b'(')
}

/// Reads a Fluent mesh (ASCII, or with binary node, cell and face sections): see
/// `read` and `build` for what is read and how cells are rebuilt from faces.
pub fn read_reported(
    bytes: &[u8],
    _ctx: &crate::ReadContext<'_>,
) -> Result<(TaggedMesh, crate::ReadReport)> {
    let raw = read::parse(bytes)?;
    let mut report = crate::ReadReport::default();
    let mesh = build::build(&raw, &mut report)?;
    build::check_periodic(&raw, &mut report)?;
    Ok((mesh, report))
}

fn cannot(reason: impl Into<String>) -> Error {
    Error::new(ErrorKind::CannotWrite { format: "Fluent", reason: reason.into() })
}

/// A float with a decimal point (`1.0e-5`, not ryu's `1e-5`), which every Fluent
/// reader's number pattern accepts.
fn push_float(out: &mut Vec<u8>, v: f64) {
    let start = out.len();
    crate::text::push_f64(out, v);
    if !out[start..].contains(&b'.') {
        let at = out[start..].iter().position(|&c| c == b'e').map_or(out.len(), |p| start + p);
        out.splice(at..at, *b".0");
    }
}

/// One face zone: its id, type, name and faces, and its side of a periodic pair.
struct FaceZone {
    bc: &'static str,
    name: String,
    faces: Vec<u32>,
    periodic: Option<(usize, bool)>,
}

/// Writes `mesh` as a Fluent ASCII mesh.
pub fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> Result<Written> {
    let mut report = WriteReport::default();
    report_unheld(mesh, &mut report);
    let dim =
        mesh.blocks.iter().map(|b| b.kind.dim()).filter(|&d| d >= 2).max().ok_or_else(|| {
            cannot("a Fluent mesh needs surface (2D) or volume (3D) cells; this mesh has none")
        })?;
    let points = &mesh.points;
    let lower: usize =
        mesh.blocks.iter().filter(|b| (1..dim - 1).contains(&b.kind.dim())).map(|b| b.len()).sum();
    if lower > 0 {
        report.drop(format!("{lower} line cells: a 3D Fluent mesh holds cells and faces"));
    }

    // Cells of the top dimension, grouped by physical tag (Fluent numbers each zone's
    // cells contiguously): (tag, block, cell), stable within a tag.
    let mut cells: Vec<(i32, u32, u32)> = Vec::new();
    for (b, block) in mesh.blocks.iter().enumerate() {
        if block.kind.dim() == dim {
            cells.extend(block.physical.iter().enumerate().map(|(i, &t)| (t, b as u32, i as u32)));
        }
    }
    cells.sort_by_key(|c| c.0);
    let corners = |&(_, b, i): &(i32, u32, u32)| {
        let block = &mesh.blocks[b as usize];
        &block.cell(i as usize)[..block.kind.linear().nodes_per_cell()]
    };

    // The nodes the cells use, renumbered in point order.
    let mut new_index = vec![NONE; points.len()];
    for c in &cells {
        for &v in corners(c) {
            new_index[v as usize] = 0;
        }
    }
    let mut used: Vec<u32> = Vec::new();
    for (v, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = used.len() as u32;
            used.push(v as u32);
        }
    }
    if used.len() < points.len() {
        report.drop(format!(
            "{} points no cell uses: Fluent nodes belong to faces",
            points.len() - used.len()
        ));
    }
    if dim == 2 && used.iter().any(|&v| points[v as usize][2] != 0.0) {
        return Err(cannot("a 2D Fluent mesh lies in the z = 0 plane; this one does not"));
    }

    let faces = build_faces(mesh, &cells, corners)?;
    let zones = face_zones(mesh, dim, &faces, opts, &mut report);
    let sides: Vec<_> = zones.iter().map(|z| (z.periodic, z.faces.as_slice())).collect();
    let pairs =
        periodic::pair_faces(points, &faces, &sides, &opts.openfoam.cyclic).map_err(cannot)?;
    let mut out = Vec::with_capacity(64 + 40 * used.len() + 40 * faces.len());
    write_all(&mut out, mesh, dim, &cells, &used, &new_index, &faces, &zones, &pairs)
        .map_err(|e| cannot(e.to_string()))?;
    Ok(Written { main: out, siblings: Vec::new(), report })
}

/// Every side of every cell once, oriented out of its first cell.
fn build_faces<'m>(
    mesh: &'m TaggedMesh,
    cells: &[(i32, u32, u32)],
    corners: impl Fn(&(i32, u32, u32)) -> &'m [u32],
) -> Result<Faces> {
    let mut faces = Faces::default();
    let mut side = Vec::with_capacity(4);
    for (c, cell) in cells.iter().enumerate() {
        let nodes = corners(cell);
        let centre = centroid(nodes, &mesh.points);
        let kind = mesh.blocks[cell.1 as usize].kind;
        for local in local_faces(kind) {
            side.clear();
            side.extend(local.iter().map(|&l| nodes[l]));
            orient_outward(&mut side, &mesh.points, centre);
            if !faces.add(&side, c as u32) {
                return Err(cannot(format!(
                    "the side {side:?} of a {} cell is shared by more than two cells",
                    kind.name()
                )));
            }
        }
    }
    Ok(faces)
}

/// The face zones, in the order written: inner faces, tagged inner faces, tagged
/// boundary faces, then `defaultFaces`.
fn face_zones(
    mesh: &TaggedMesh,
    dim: u8,
    faces: &Faces,
    opts: &WriteOptions,
    report: &mut WriteReport,
) -> Vec<FaceZone> {
    let mut tag = vec![0i32; faces.len()];
    let (mut off, mut clash) = (0usize, 0usize);
    for block in mesh.blocks.iter().filter(|b| b.kind.dim() == dim - 1) {
        let n = block.kind.linear().nodes_per_cell();
        for (i, cell) in block.cells().enumerate() {
            let t = block.physical[i];
            match faces.find(&cell[..n]) {
                Some(f) if t != 0 => {
                    clash += usize::from(tag[f] != 0 && tag[f] != t);
                    tag[f] = t;
                }
                Some(_) => {}
                None => off += 1,
            }
        }
    }
    if off > 0 {
        report.drop(format!("{off} boundary cells on no cell's side: Fluent faces are sides"));
    }
    if clash > 0 {
        report.drop(format!("{clash} faces under two tagged cells: the last tag kept"));
    }
    // (class, tag): 0 inner, 1 tagged inner, 2 tagged boundary, 3 untagged boundary;
    // the boundary faces of a periodic side's tags all under the side's first tag.
    let roles = periodic::roles(&opts.openfoam.cyclic);
    let first_of = |t: i32| match roles.get(&t) {
        Some(&(k, m)) => {
            let p = &opts.openfoam.cyclic[k];
            if m {
                p.master[0]
            } else {
                p.slave[0]
            }
        }
        None => t,
    };
    let mut groups: BTreeMap<(u8, i32), Vec<u32>> = BTreeMap::new();
    for (f, &t) in tag.iter().enumerate() {
        let class = match (faces.c1[f] == NONE, t != 0) {
            (false, false) => 0,
            (false, true) => 1,
            (true, true) => 2,
            (true, false) => 3,
        };
        let t = if class == 2 { first_of(t) } else { t };
        groups.entry((class, t)).or_default().push(f as u32);
    }
    let mut names = BTreeSet::new();
    let mut zones = Vec::new();
    let name_of = |t: i32, report: &mut WriteReport| match mesh.tag_name(dim - 1, t) {
        Some(n) => zone_word(n),
        None => {
            report.drop(format!("face tag {t} has no name: written as zone `tag{t}`"));
            format!("tag{t}")
        }
    };
    for ((class, t), list) in groups {
        let periodic = roles.get(&t).copied().filter(|_| class == 2);
        let base = match (class, periodic) {
            (0, _) => "default-interior".to_string(),
            (3, _) => "defaultFaces".to_string(),
            // A side of several tags: one zone named from them all, as OpenFOAM's.
            (_, Some((k, m))) => {
                let p = &opts.openfoam.cyclic[k];
                let side = if m { &p.master } else { &p.slave };
                side.iter().map(|&t| name_of(t, report)).collect::<Vec<_>>().join("_")
            }
            (_, None) => name_of(t, report),
        };
        let mut name = base.clone();
        let mut k = 1;
        while !names.insert(name.clone()) {
            k += 1;
            name = format!("{base}_{k}");
        }
        let bc = match (class, periodic) {
            (0 | 1, _) => "interior",
            (3, _) => "wall",
            (_, Some((_, true))) => "periodic",
            (_, Some((_, false))) => "periodic-shadow",
            _ => zone_type(&name, opts, report),
        };
        zones.push(FaceZone { bc, name, faces: list, periodic });
    }
    zones
}

/// The hexadecimal of `v` (Fluent writes every index so).
macro_rules! hex {
    ($v:expr) => {
        format_args!("{:x}", $v)
    };
}

#[allow(clippy::too_many_arguments)]
fn write_all(
    out: &mut Vec<u8>,
    mesh: &TaggedMesh,
    dim: u8,
    cells: &[(i32, u32, u32)],
    used: &[u32],
    new_index: &[u32],
    faces: &Faces,
    zones: &[FaceZone],
    pairs: &[periodic::FacePairs],
) -> std::io::Result<()> {
    writeln!(out, "(0 \"Fluent mesh written by smartmesh\")")?;
    writeln!(out, "(1 \"smartmesh {}\")", env!("CARGO_PKG_VERSION"))?;
    writeln!(out, "(2 {dim})")?;
    // Nodes: zone 1.
    writeln!(out, "(10 (0 1 {} 0 {dim}))", hex!(used.len()))?;
    writeln!(out, "(10 (1 1 {} 1 {dim})(", hex!(used.len()))?;
    for &v in used {
        let p = mesh.points[v as usize];
        for (k, &x) in p[..dim as usize].iter().enumerate() {
            if k > 0 {
                out.push(b' ');
            }
            push_float(out, x);
        }
        out.push(b'\n');
    }
    writeln!(out, "))")?;
    // Cells: one zone per physical tag, ids from 2.
    writeln!(out, "(12 (0 1 {} 0))", hex!(cells.len()))?;
    let mut names: Vec<(usize, &'static str, String)> = Vec::new();
    let mut id = 2usize;
    let mut first = 0usize;
    while first < cells.len() {
        let t = cells[first].0;
        let last = first + cells[first..].iter().take_while(|c| c.0 == t).count();
        let kinds: BTreeSet<u32> =
            cells[first..last].iter().map(|c| cell_type(mesh.blocks[c.1 as usize].kind)).collect();
        let range = format!("{} {} {}", hex!(id), hex!(first + 1), hex!(last));
        if kinds.len() == 1 {
            writeln!(out, "(12 ({range} 1 {}))", hex!(kinds.first().copied().unwrap_or(0)))?;
        } else {
            writeln!(out, "(12 ({range} 1 0)(")?;
            for c in &cells[first..last] {
                writeln!(out, "{}", hex!(cell_type(mesh.blocks[c.1 as usize].kind)))?;
            }
            writeln!(out, "))")?;
        }
        let name = match mesh.tag_name(dim, t) {
            Some(n) => zone_word(n),
            None if t == 0 => "fluid".to_string(),
            None => format!("fluid{t}"),
        };
        names.push((id, "fluid", name));
        id += 1;
        first = last;
    }
    // Faces.
    writeln!(out, "(13 (0 1 {} 0))", hex!(faces.len()))?;
    let mut next = 1usize;
    // Each zone's id and first face, for the periodic face pairs.
    let mut placed: Vec<(usize, usize)> = Vec::with_capacity(zones.len());
    for zone in zones {
        placed.push((id, next));
        let sizes: BTreeSet<usize> =
            zone.faces.iter().map(|&f| faces.face(f as usize).len()).collect();
        let mixed = sizes.len() > 1;
        let face_type = if mixed { 0 } else { sizes.first().copied().unwrap_or(2) };
        let last = next + zone.faces.len() - 1;
        writeln!(
            out,
            "(13 ({} {} {} {} {})(",
            hex!(id),
            hex!(next),
            hex!(last),
            hex!(code(zone.bc)),
            hex!(face_type)
        )?;
        for &f in &zone.faces {
            let nodes = faces.face(f as usize);
            if mixed {
                write!(out, "{} ", hex!(nodes.len()))?;
            }
            // Faces are kept with their normal out of c0; Fluent's right-hand normal
            // of a polygon points into c0, and that of an edge n0 → n1 is z × (n1 - n0),
            // into c0 too when the edge keeps c0 on its left: reverse polygons only.
            let mut write_node = |v: &u32| write!(out, "{} ", hex!(new_index[*v as usize] + 1));
            if nodes.len() > 2 {
                nodes.iter().rev().try_for_each(&mut write_node)?;
            } else {
                nodes.iter().try_for_each(&mut write_node)?;
            }
            let c1 = faces.c1[f as usize];
            let c1 = if c1 == NONE { 0 } else { c1 + 1 };
            writeln!(out, "{} {}", hex!(faces.c0[f as usize] + 1), hex!(c1))?;
        }
        writeln!(out, "))")?;
        names.push((id, zone.bc, zone.name.clone()));
        id += 1;
        next = last + 1;
    }
    // Periodic face pairs: a master face, then its shadow.
    for p in pairs {
        let ((mid, m0), (sid, s0)) = (placed[p.master_zone], placed[p.shadow_zone]);
        let n = p.shadow_of.len();
        writeln!(out, "(18 (1 {} {} {})(", hex!(n), hex!(mid), hex!(sid))?;
        for (i, &s) in p.shadow_of.iter().enumerate() {
            writeln!(out, "{} {}", hex!(m0 + i), hex!(s0 + s as usize))?;
        }
        writeln!(out, "))")?;
    }
    for (id, kind, name) in names {
        writeln!(out, "(45 ({id} {kind} {name})())")?;
    }
    Ok(())
}

fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    for (name, a) in mesh.point_data.iter().chain(&mesh.cell_data) {
        report.drop(format!(
            "data `{name}` ({} components): a Fluent mesh file holds no fields",
            a.expanded_components()
        ));
    }
    let vertices = mesh.num_cells_of(CellKind::Vertex);
    if vertices > 0 {
        report.drop(format!("{vertices} vertex cells: Fluent meshes hold cells and faces"));
    }
    for kind in CellKind::ALL.iter().filter(|k| k.is_second_order()) {
        let n = mesh.num_cells_of(*kind);
        if n > 0 {
            report.drop(format!(
                "the mid-side nodes of {n} {} cells: written by their corners",
                kind.name()
            ));
        }
    }
    for name in mesh.point_sets.keys().chain(mesh.cell_sets.keys()) {
        report.drop(format!("set `{name}`: a Fluent mesh file holds no sets"));
    }
}
