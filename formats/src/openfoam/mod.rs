//! OpenFOAM cases: a 2D mesh extruded one cell thick, or a 3D mesh as it is, written as
//! `constant/polyMesh` (ASCII or binary), with the minimal `system/` files `checkMesh`
//! and the solvers need; and read back.
//!
//! Source: the OpenFOAM User Guide, section 5.1 *Mesh description* (polyMesh: `points`,
//! `faces`, `owner`, `neighbour`, `boundary`; internal faces in upper-triangular order,
//! owner < neighbour, a face's normal by the right-hand rule on its points pointing
//! from owner to neighbour and out of the domain on boundaries) and 5.2.2 (2D cases:
//! one cell thick, front and back faces in `empty` patches). Checked with Debian's
//! OpenFOAM 1912 `checkMesh`.
//!
//! Write ([`write_case`]): the output path is the case directory (created if absent,
//! its other contents left alone). What a 2D mesh becomes ([`extrude()`]): triangles
//! prisms and quads hexahedra between z = 0 and z = `dz` ([`OpenFoamWrite::extrude`];
//! by default a hundredth of the mesh's largest extent), second-order cells by their
//! corners; each line tag a patch named from its tag name (made an OpenFOAM word;
//! `tag<N>` when unnamed, said in the report), of type `wall` when the name says a
//! wall and not an open boundary (see [`patch_type`]) or as [`OpenFoamWrite::patch_types`] maps it, else
//! `patch`; boundary edges without a line cell in `defaultFaces`; `front` (z = dz) and
//! `back` (z = 0) `empty`. `constant/polyMesh` is written whole into a temporary
//! directory beside it and renamed into place (an old one is replaced only then);
//! `system/controlDict`, `fvSchemes` and `fvSolution` are written only where absent.
//!
//! A mesh with volume cells (tetrahedra, hexahedra, prisms, pyramids) is written
//! directly ([`volume_poly_mesh`]): one patch per surface tag on the boundary, named and
//! typed as the line tags of a 2D mesh are, `defaultFaces` for boundary faces without a
//! surface cell; `cellZones` from the volume tags (a zone per tag, when named or
//! several), `faceZones` from the surface tags on internal faces. The report lists what
//! the case does not keep: higher-order nodes, line and vertex cells with their tags'
//! names, and the numbers of named tags (patches and zones are known by name only).
//!
//! Read ([`read_case`]): a 2D case, one cell thick along z, back into a 2D mesh; a case
//! without `empty` or `wedge` patches back into a 3D mesh, with its `cellZones` and
//! `faceZones` as tags (see the modules `read` and `read3d`).
//!
//! `wedge` ([`OpenFoamWrite::wedge`], axisymmetric cases): the mesh in y >= 0 is turned
//! by ±angle/2 about the x axis, its points on the axis shared by both planes.
//!
//! Periodic sides ([`OpenFoamWrite::cyclic`], set by `--cyclic` or a recipe's PERIODIC
//! section): each pair's master tags one `cyclic` patch, its slave tags another, faces
//! in matching order (module `cyclic`).
//!
//! Not done yet: cellZones/faceZones of a 2D
//! mesh's face tags and inner curves; the report says what is left.

pub(crate) mod cyclic;
pub mod extrude;
mod read;
mod read3d;
mod volume;

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use crate::text::{push_f64, push_int};
use crate::{Error, ErrorKind, Format, Result, TaggedMesh, WriteReport};

pub use cyclic::{CyclicPair, CyclicTransform};
pub use extrude::{extrude, extrude_layer, Layer, Patch, PolyMesh};
pub use read::{read_case, read_poly_mesh};
pub(crate) use read3d::cell_nodes;
pub use volume::volume_poly_mesh;

/// How to write an OpenFOAM case.
#[derive(Debug, Clone, Default)]
pub struct OpenFoamWrite {
    /// The thickness of the one cell layer; `None`: a hundredth of the mesh's largest
    /// extent (1 for a mesh without extent).
    pub extrude: Option<f64>,
    /// Patch types by patch name (`Inlet` → `patch`), over [`patch_type`]'s guess.
    pub patch_types: BTreeMap<String, String>,
    /// An axisymmetric wedge of this angle in degrees about the x axis (front and back
    /// `wedge` patches at ±angle/2) instead of a slab.
    pub wedge: Option<f64>,
    /// Binary `points`, `faces`, `owner` and `neighbour` (little-endian, 32-bit labels,
    /// 64-bit scalars), as OpenFOAM's `writeFormat binary` writes them.
    pub binary: bool,
    /// Periodic side pairs written as two `cyclic` patches each (see the module
    /// `cyclic`); their tags' faces must be images of each other by the transform.
    pub cyclic: Vec<CyclicPair>,
}

/// Words in a patch name that make it a `patch` whatever else it says (compared in
/// lower case): the open and the paired boundaries (`UpperPeriodic1`, `FarField`).
pub const PATCH_WORDS: [&str; 12] = [
    "inlet",
    "outlet",
    "inflow",
    "outflow",
    "far",
    "freestream",
    "periodic",
    "cyclic",
    "symmetry",
    "open",
    "atmosphere",
    "interface",
];

/// Words in a patch name that make it a `wall` (compared in lower case): the solid
/// boundaries of the usual CFD cases.
pub const WALL_WORDS: [&str; 13] = [
    "wall", "airfoil", "aerofoil", "cylinder", "body", "wing", "blade", "vane", "hull", "obstacle",
    "naca", "upper", "lower",
];

/// The OpenFOAM type of a patch from its name: `patch` when it holds one of
/// [`PATCH_WORDS`] (`Inlet`, `FarField`, `LowerPeriodic1`), else `wall` when it holds
/// one of [`WALL_WORDS`] (`Walls`, `Airfoil`, `Upper`, `cylinder_surface`), else `patch`.
pub fn patch_type(name: &str) -> &'static str {
    let lower = name.to_ascii_lowercase();
    if PATCH_WORDS.iter().any(|w| lower.contains(w)) {
        "patch"
    } else if WALL_WORDS.iter().any(|w| lower.contains(w)) {
        "wall"
    } else {
        "patch"
    }
}

/// `name` as an OpenFOAM word: blanks, quotes and `/ ; { } ( )` become `_`, and a name
/// that starts with a digit gets `patch_` before it.
fn foam_word(name: &str) -> String {
    let mut w: String = name
        .trim()
        .chars()
        .map(|c| {
            if c.is_whitespace() || c.is_control() || "\"'/;{}()\\$#".contains(c) {
                '_'
            } else {
                c
            }
        })
        .collect();
    if w.starts_with(|c: char| c.is_ascii_digit() || c == '-' || c == '+' || c == '.') {
        w.insert_str(0, "patch_");
    }
    w
}

/// The thickness of the layer: the option, or a hundredth of the largest extent.
fn thickness(mesh: &TaggedMesh, opts: &OpenFoamWrite) -> Result<f64> {
    if let Some(dz) = opts.extrude {
        if !(dz.is_finite() && dz > 0.0) {
            return Err(Error::new(ErrorKind::CannotWrite {
                format: Format::OpenFoam.name(),
                reason: format!("the extrusion thickness {dz} is not a positive number"),
            }));
        }
        return Ok(dz);
    }
    // The extent of what is extruded: a point no cell uses (a circle's centre) is left.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 2) {
        for &v in &b.nodes {
            let p = mesh.points[v as usize];
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    Ok(if extent > 0.0 { extent / 100.0 } else { 1.0 })
}

/// A file of `constant/polyMesh`: its name and bytes.
pub type CaseFile = (&'static str, Vec<u8>);

/// The polyMesh files of `mesh` (`points`, `faces`, `owner`, `neighbour`, `boundary`),
/// and the report of what was changed or left.
pub fn poly_mesh_files(
    mesh: &TaggedMesh,
    opts: &OpenFoamWrite,
) -> Result<(Vec<CaseFile>, WriteReport)> {
    if !mesh.validate().is_empty() {
        return Err(crate::io::refused(Format::OpenFoam, mesh));
    }
    let mut report = WriteReport::default();
    report_unheld(mesh, &mut report);
    if mesh.blocks.iter().any(|b| b.kind.dim() == 3) {
        return volume_files(mesh, opts, report);
    }
    let layer = match opts.wedge {
        Some(angle) => Layer::Wedge(angle),
        None => {
            let dz = thickness(mesh, opts)?;
            if opts.extrude.is_none() {
                report.drop(format!(
                    "the 2D mesh written as one cell layer from z = 0 to z = {dz} (a hundredth of its extent; --extrude DZ sets it)"
                ));
            }
            Layer::Slab(dz)
        }
    };
    let name_of = |tag: i32, report: &mut WriteReport| -> (String, String) {
        let name = match mesh.tag_name(1, tag) {
            Some(n) => {
                let w = foam_word(n);
                if w.is_empty() {
                    report.drop(format!("line tag {tag}'s blank name written as patch `tag{tag}`"));
                    format!("tag{tag}")
                } else {
                    if w != n {
                        report.drop(format!("line tag {tag}'s name `{n}` written as patch `{w}`: an OpenFOAM word has no blanks, quotes or `/;{{}}()`"));
                    }
                    w
                }
            }
            None => {
                report.drop(format!("line tag {tag} has no name: written as patch `tag{tag}`"));
                format!("tag{tag}")
            }
        };
        let kind =
            opts.patch_types.get(&name).cloned().unwrap_or_else(|| patch_type(&name).to_string());
        (name, kind)
    };
    let mut patch_of = BTreeMap::new();
    let mut named = |tag: i32, report: &mut WriteReport| {
        let (name, kind) = name_of(tag, report);
        patch_of.insert(tag, name.clone());
        (name, kind)
    };
    let mut poly = extrude_layer(mesh, layer, &mut named, &mut report).map_err(refused)?;
    cyclic::couple(&mut poly, &opts.cyclic, &patch_of).map_err(refused)?;
    Ok((files(&poly, opts.binary), report))
}

/// The error of a mesh the writer cannot write, for `reason`.
fn refused(reason: String) -> Error {
    Error::new(ErrorKind::CannotWrite { format: Format::OpenFoam.name(), reason })
}

/// `name` as an OpenFOAM word, or `tag<N>` when it is none; the report says what
/// changed.
fn word_or_tag(name: Option<&str>, what: &str, tag: i32, report: &mut WriteReport) -> String {
    match name {
        Some(n) => {
            let w = foam_word(n);
            if w.is_empty() {
                report.drop(format!("{what} tag {tag}'s blank name written as `tag{tag}`"));
                format!("tag{tag}")
            } else {
                if w != n {
                    report.drop(format!("{what} tag {tag}'s name `{n}` written as `{w}`: an OpenFOAM word has no blanks, quotes or `/;{{}}()`"));
                }
                w
            }
        }
        None => {
            report.drop(format!("{what} tag {tag} has no name: written as `tag{tag}`"));
            format!("tag{tag}")
        }
    }
}

/// The polyMesh files of a mesh with volume cells, written directly
/// ([`volume_poly_mesh`]): patches from the surface tags, zones from the volume tags
/// and the surface tags inside.
fn volume_files(
    mesh: &TaggedMesh,
    opts: &OpenFoamWrite,
    mut report: WriteReport,
) -> Result<(Vec<CaseFile>, WriteReport)> {
    if opts.extrude.is_some() || opts.wedge.is_some() {
        report.drop("--extrude and --wedge: a 3D mesh is written as it is, not extruded");
    }
    report_volume_losses(mesh, &mut report);
    let patch_name = |tag: i32, report: &mut WriteReport| -> (String, String) {
        let name = word_or_tag(mesh.tag_name(2, tag), "surface", tag, report);
        let kind =
            opts.patch_types.get(&name).cloned().unwrap_or_else(|| patch_type(&name).to_string());
        (name, kind)
    };
    let zone_name = |d: u8, tag: i32| -> String {
        mesh.tag_name(d, tag)
            .map(foam_word)
            .filter(|w| !w.is_empty())
            .unwrap_or(format!("tag{tag}"))
    };
    let mut inner = WriteReport::default();
    let mut patch_of = BTreeMap::new();
    let named = |tag: i32, report: &mut WriteReport| {
        let (name, kind) = patch_name(tag, report);
        patch_of.insert(tag, name.clone());
        (name, kind)
    };
    let mut poly = volume_poly_mesh(mesh, named, zone_name, &mut inner).map_err(refused)?;
    cyclic::couple(&mut poly, &opts.cyclic, &patch_of).map_err(refused)?;
    report.dropped.extend(inner.dropped);
    Ok((files(&poly, opts.binary), report))
}

/// What a 3D polyMesh does not hold of `mesh`: line and vertex cells with their tags'
/// names, and the tag numbers (patches and zones are known by
/// name, and `read_case` numbers them 1, 2, … in file order).
fn report_volume_losses(mesh: &TaggedMesh, report: &mut WriteReport) {
    let low = |b: &&crate::CellBlock| b.kind.dim() < 2;
    let lines = mesh.blocks.iter().filter(low).map(|b| b.len()).sum::<usize>();
    if lines > 0 {
        let names: std::collections::BTreeSet<String> = mesh
            .blocks
            .iter()
            .filter(low)
            .flat_map(|b| b.physical.iter().map(move |&t| (b.kind.dim(), t)))
            .filter_map(|(d, t)| mesh.tag_name(d, t).map(|n| format!("`{n}`")))
            .collect();
        let names = if names.is_empty() {
            String::new()
        } else {
            format!(", with their tags' names {}", names.into_iter().collect::<Vec<_>>().join(", "))
        };
        report.drop(format!(
            "{lines} line and vertex cells{names}: a 3D polyMesh has patches of faces only"
        ));
    }
    let named = mesh
        .blocks
        .iter()
        .filter(|b| b.kind.dim() >= 2)
        .any(|b| b.physical.iter().any(|&t| mesh.tag_name(b.kind.dim(), t).is_some()));
    if named {
        report.drop(
            "the numbers of the named surface and volume tags: a polyMesh knows patches and zones by name only, read back numbered 1, 2, … in file order",
        );
    }
}

/// A `cellZones` or `faceZones` file (always ASCII: OpenFOAM reads each file by its
/// own header).
fn zones_file(object: &'static str, zones: &[(String, Vec<u32>)]) -> Vec<u8> {
    let mut out = header("regIOobject", object, None, false);
    let (kind, list) =
        if object == "cellZones" { ("cellZone", "cellLabels") } else { ("faceZone", "faceLabels") };
    push_int(&mut out, zones.len());
    out.extend_from_slice(b"\n(\n");
    for (name, items) in zones {
        out.extend_from_slice(
            format!("{name}\n{{\n    type {kind};\n{list} List<label> ").as_bytes(),
        );
        labels(&mut out, items, false);
        out.extend_from_slice(b";\n");
        if kind == "faceZone" {
            // flipMap false: each face's normal points from its owner, the zone's side.
            out.extend_from_slice(b"flipMap List<bool> ");
            labels(&mut out, &vec![0; items.len()], false);
            out.extend_from_slice(b";\n");
        }
        out.extend_from_slice(b"}\n");
    }
    out.extend_from_slice(b")\n");
    out
}

/// The FoamFile header of a polyMesh file; binary files say their byte layout
/// (`arch`), as OpenFOAM's own writers do.
fn header(class: &str, object: &str, note: Option<&str>, binary: bool) -> Vec<u8> {
    let mut s = String::from(
        "/*--------------------------------*- C++ -*----------------------------------*\\\n\
         |  Written by smartmesh                                                       |\n\
         \\*---------------------------------------------------------------------------*/\n\
         FoamFile\n{\n    version     2.0;\n",
    );
    if binary {
        s.push_str("    format      binary;\n    arch        \"LSB;label=32;scalar=64\";\n");
    } else {
        s.push_str("    format      ascii;\n");
    }
    let _ = writeln!(s, "    class       {class};");
    if let Some(note) = note {
        let _ = writeln!(s, "    note        \"{note}\";");
    }
    let _ = writeln!(s, "    location    \"constant/polyMesh\";");
    let _ = writeln!(s, "    object      {object};\n}}\n");
    s.into_bytes()
}

/// A list of labels: in ASCII one per line; in binary (OpenFOAM's `List` in a binary
/// stream) the count, then `(`, the 32-bit little-endian labels and `)`; an empty list
/// is `0()` either way.
fn labels(out: &mut Vec<u8>, values: &[u32], binary: bool) {
    push_int(out, values.len());
    if values.is_empty() {
        out.extend_from_slice(b"()\n");
        return;
    }
    if binary {
        out.extend_from_slice(b"\n(");
        for &v in values {
            out.extend_from_slice(&(v as i32).to_le_bytes());
        }
        out.extend_from_slice(b")\n");
        return;
    }
    out.extend_from_slice(b"\n(\n");
    for &v in values {
        push_int(out, v);
        out.push(b'\n');
    }
    out.extend_from_slice(b")\n");
}

/// The five polyMesh files of `poly`, ASCII or binary (`boundary` is a dictionary,
/// always ASCII). Binary faces are a `faceCompactList`: the offsets of each face's
/// labels, then the labels.
fn files(poly: &PolyMesh, binary: bool) -> Vec<CaseFile> {
    let mut points = header("vectorField", "points", None, binary);
    push_int(&mut points, poly.points.len());
    if binary && !poly.points.is_empty() {
        points.extend_from_slice(b"\n(");
        for p in &poly.points {
            for c in p {
                points.extend_from_slice(&c.to_le_bytes());
            }
        }
        points.extend_from_slice(b")\n");
    } else {
        points.extend_from_slice(b"\n(\n");
        for p in &poly.points {
            points.push(b'(');
            push_f64(&mut points, p[0]);
            points.push(b' ');
            push_f64(&mut points, p[1]);
            points.push(b' ');
            push_f64(&mut points, p[2]);
            points.extend_from_slice(b")\n");
        }
        points.extend_from_slice(b")\n");
    }

    let faces = if binary {
        let mut faces = header("faceCompactList", "faces", None, true);
        let mut offsets = Vec::with_capacity(poly.faces.len() + 1);
        let mut flat = Vec::new();
        offsets.push(0u32);
        for f in &poly.faces {
            flat.extend_from_slice(f);
            offsets.push(flat.len() as u32);
        }
        labels(&mut faces, &offsets, true);
        faces.push(b'\n');
        labels(&mut faces, &flat, true);
        faces
    } else {
        let mut faces = header("faceList", "faces", None, false);
        push_int(&mut faces, poly.faces.len());
        faces.extend_from_slice(b"\n(\n");
        for f in &poly.faces {
            push_int(&mut faces, f.len());
            faces.push(b'(');
            for (k, &v) in f.iter().enumerate() {
                if k > 0 {
                    faces.push(b' ');
                }
                push_int(&mut faces, v);
            }
            faces.extend_from_slice(b")\n");
        }
        faces.extend_from_slice(b")\n");
        faces
    };

    let note = format!(
        "nPoints:{}  nCells:{}  nFaces:{}  nInternalFaces:{}",
        poly.points.len(),
        poly.n_cells,
        poly.faces.len(),
        poly.neighbour.len()
    );
    let mut owner = header("labelList", "owner", Some(&note), binary);
    labels(&mut owner, &poly.owner, binary);
    let mut neighbour = header("labelList", "neighbour", Some(&note), binary);
    labels(&mut neighbour, &poly.neighbour, binary);

    let mut boundary = header("polyBoundaryMesh", "boundary", None, false);
    let mut s = format!("{}\n(\n", poly.patches.len());
    let mut start = poly.neighbour.len();
    for p in &poly.patches {
        let _ = writeln!(s, "    {}\n    {{", p.name);
        let _ = writeln!(s, "        type            {};", p.kind);
        if p.kind == "wall" || p.kind == "empty" {
            let _ = writeln!(s, "        inGroups        List<word> 1({});", p.kind);
        }
        for (key, value) in &p.entries {
            let _ = writeln!(s, "        {key:<15} {value};");
        }
        let _ = writeln!(s, "        nFaces          {};", p.n_faces);
        let _ = writeln!(s, "        startFace       {start};\n    }}");
        start += p.n_faces;
    }
    s.push_str(")\n");
    boundary.extend_from_slice(s.as_bytes());

    let mut out = vec![
        ("points", points),
        ("faces", faces),
        ("owner", owner),
        ("neighbour", neighbour),
        ("boundary", boundary),
    ];
    if !poly.cell_zones.is_empty() {
        out.push(("cellZones", zones_file("cellZones", &poly.cell_zones)));
    }
    if !poly.face_zones.is_empty() {
        out.push(("faceZones", zones_file("faceZones", &poly.face_zones)));
    }
    out
}

/// What an OpenFOAM mesh written from a 2D mesh does not hold.
fn report_unheld(mesh: &TaggedMesh, report: &mut WriteReport) {
    for (name, a) in &mesh.point_data {
        report.drop(format!(
            "point data `{name}` ({} components): a polyMesh holds no fields",
            a.expanded_components()
        ));
    }
    for (name, a) in &mesh.cell_data {
        report.drop(format!(
            "cell data `{name}` ({} components): a polyMesh holds no fields",
            a.expanded_components()
        ));
    }
    let face_tags: std::collections::BTreeSet<i32> = mesh
        .blocks
        .iter()
        .filter(|b| b.kind.dim() == 2)
        .flat_map(|b| b.physical.iter().copied())
        .collect();
    // A 3D mesh's surface tags are its patches and face zones.
    if face_tags.len() > 1 && !mesh.blocks.iter().any(|b| b.kind.dim() == 3) {
        report.drop(format!(
            "face tags {face_tags:?}: cellZones are not written yet, so the cells carry no tag"
        ));
    }
    let vertices = mesh.num_cells_of(crate::CellKind::Vertex);
    if vertices > 0 {
        report
            .drop(format!("{vertices} vertex cells: a polyMesh has cells, faces and points only"));
    }
    // Every higher-order kind, volumes included (a tetra10 is written as its tetra).
    let mut curved: BTreeMap<&str, usize> = BTreeMap::new();
    for b in mesh.blocks.iter().filter(|b| b.kind.linear() != b.kind && !b.is_empty()) {
        *curved.entry(b.kind.name()).or_default() += b.len();
    }
    for (kind, n) in curved {
        report.drop(format!(
            "the mid-edge nodes of {n} {kind} cells: a polyMesh is first order (written by their corners)"
        ));
    }
    for name in mesh.point_sets.keys() {
        report.drop(format!("point set `{name}`: pointZones are not written"));
    }
    for name in mesh.cell_sets.keys() {
        report.drop(format!("cell set `{name}`: cellZones are not written"));
    }
}

/// `system/` files a case needs for `checkMesh` and a steady solver to start, written
/// only where absent.
const SYSTEM_FILES: [(&str, &str); 3] = [
    (
        "controlDict",
        "application     simpleFoam;\nstartFrom       startTime;\nstartTime       0;\nstopAt          endTime;\nendTime         1;\ndeltaT          1;\nwriteControl    timeStep;\nwriteInterval   1;\nwriteFormat     ascii;\nwritePrecision  12;\nrunTimeModifiable false;\n",
    ),
    (
        "fvSchemes",
        "ddtSchemes\n{\n    default         steadyState;\n}\ngradSchemes\n{\n    default         Gauss linear;\n}\ndivSchemes\n{\n    default         none;\n}\nlaplacianSchemes\n{\n    default         Gauss linear corrected;\n}\ninterpolationSchemes\n{\n    default         linear;\n}\nsnGradSchemes\n{\n    default         corrected;\n}\n",
    ),
    ("fvSolution", "solvers\n{\n}\n"),
];

fn dictionary(object: &str, location: &str, body: &str) -> Vec<u8> {
    format!(
        "/*--------------------------------*- C++ -*----------------------------------*\\\n\
         |  Written by smartmesh                                                       |\n\
         \\*---------------------------------------------------------------------------*/\n\
         FoamFile\n{{\n    version     2.0;\n    format      ascii;\n    class       dictionary;\n    location    \"{location}\";\n    object      {object};\n}}\n\n{body}"
    )
    .into_bytes()
}

/// The `system/` files (name and bytes) of a case whose directory `system` lacks them:
/// for a writer that puts a case's files in place with others as one set.
pub fn missing_system_files(system: &Path) -> Vec<CaseFile> {
    SYSTEM_FILES
        .iter()
        .filter(|(name, _)| !system.join(name).exists())
        .map(|(name, body)| (*name, dictionary(name, "system", body)))
        .collect()
}

/// Writes `mesh` as the OpenFOAM case directory `dir`: `constant/polyMesh` whole or
/// not at all, and the `system/` files that are missing.
pub fn write_case(dir: &Path, mesh: &TaggedMesh, opts: &OpenFoamWrite) -> Result<WriteReport> {
    let (files, report) = poly_mesh_files(mesh, opts).map_err(|e| e.with_path(dir))?;
    let unwritable =
        |e: std::io::Error, p: &Path| Error::new(ErrorKind::Unwritable(e)).with_path(p);
    if dir.exists() && !dir.is_dir() {
        return Err(Error::new(ErrorKind::CannotWrite {
            format: Format::OpenFoam.name(),
            reason: "an OpenFOAM case is a directory, and this path is a file".into(),
        })
        .with_path(dir));
    }
    let constant = dir.join("constant");
    std::fs::create_dir_all(&constant).map_err(|e| unwritable(e, &constant))?;
    // The new polyMesh is complete in a temporary directory before it takes the place
    // of the old one; another process writing the same case meets only whole ones.
    let tmp = tempfile::Builder::new()
        .prefix(".polyMesh.")
        .tempdir_in(&constant)
        .map_err(|e| unwritable(e, &constant))?;
    for (name, bytes) in &files {
        let p = tmp.path().join(name);
        std::fs::write(&p, bytes).map_err(|e| unwritable(e, &p))?;
    }
    let target = constant.join("polyMesh");
    if target.exists() {
        // A directory cannot be renamed over a non-empty one: move the old one aside
        // first, then remove it once the new one is in place.
        let old = tempfile::Builder::new()
            .prefix(".polyMesh.old.")
            .tempdir_in(&constant)
            .map_err(|e| unwritable(e, &constant))?;
        let aside = old.path().join("polyMesh");
        std::fs::rename(&target, &aside).map_err(|e| unwritable(e, &target))?;
        if let Err(e) = std::fs::rename(tmp.path(), &target) {
            let _ = std::fs::rename(&aside, &target);
            return Err(unwritable(e, &target));
        }
        drop(old);
    } else {
        std::fs::rename(tmp.path(), &target).map_err(|e| unwritable(e, &target))?;
    }
    let _ = tmp.keep();
    let system = dir.join("system");
    std::fs::create_dir_all(&system).map_err(|e| unwritable(e, &system))?;
    for (name, body) in SYSTEM_FILES {
        let p = system.join(name);
        if !p.exists() {
            crate::output::write_all_atomically(&[(p, dictionary(name, "system", body))])?;
        }
    }
    Ok(report)
}
