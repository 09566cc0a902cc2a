//! What each format keeps of a 3D mesh: a unit cube of 6 tetrahedra (physical volume 10
//! "Solid"), its 12 boundary triangles on three named surfaces, 4 named line cells, a
//! named vertex cell, a scalar and a vector point field and a cell field, converted by
//! `smartmesh convert` into every format smartmesh writes. For each target the table
//! below says what reads back (order aside) and what is lost; every loss must be listed
//! in `convert --json`'s `dropped` (which stderr also shows). A format whose 3D writer is
//! still being built may refuse the mesh instead, with an error naming the volume cells.
//!
//! To update: change the format's one line in [`TABLE`].
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured or skipped is printed for the log.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;

use std::collections::BTreeMap;
use std::path::Path;

use smartmesh::formats::{read_path, CellKind, DataArray, Format, TaggedMesh};

/// What a mesh holds, compared column by column after the round trip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Column {
    /// The points' coordinates (as a set).
    Points,
    /// The volume cells, by kind.
    Volumes,
    /// The surface cells, by kind.
    Faces,
    /// The line cells, by kind.
    Lines,
    /// The vertex cells.
    Vertices,
    /// The cells per (kind, physical tag), over the kinds that read back.
    Tags,
    /// The tags' names.
    Names,
    /// The point data arrays, by name (values as a set).
    PointData,
    /// The cell data array `id`.
    CellData,
}
use Column::*;

const ALL: [Column; 9] =
    [Points, Volumes, Faces, Lines, Vertices, Tags, Names, PointData, CellData];

/// What happens to the test mesh in one format.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fate {
    /// Written; these columns read back, the others are listed as dropped.
    Keeps(&'static [Column]),
    /// Written and not readable by smartmesh (glTF): these columns must be listed as
    /// dropped. (No line has it while glTF refuses volume cells.)
    #[allow(dead_code)]
    WriteOnly(&'static [Column]),
    /// Refused with an error that names the volume cells.
    Refused,
    /// KNOWN BUG, reported: refused with an error that does not name the volume cells.
    RefusedUnclearly,
    /// KNOWN BUG, reported: written, and reading it back fails. (No line has it now.)
    #[allow(dead_code)]
    Unreadable,
    /// KNOWN BUG, reported: written, keeping the first columns; of the others, those of
    /// the second list are lost without a word (the rest are listed). (No line has it
    /// now.)
    #[allow(dead_code)]
    SilentLoss(&'static [Column], &'static [Column]),
}
use Fate::*;

/// One line per target ([`Line`]).
const TABLE: &[Line] = &[
    ("v41.msh", &[], Keeps(&ALL), false),
    ("v41b.msh", &["--binary"], Keeps(&ALL), false),
    ("v22.msh", &["--gmsh-version", "2.2"], Keeps(&ALL), false),
    ("v22b.msh", &["--gmsh-version", "2.2", "--binary"], Keeps(&ALL), false),
    ("out.vtk", &[], Keeps(&ALL), false),
    ("outb.vtk", &["--binary"], Keeps(&ALL), false),
    ("out.vtu", &[], Keeps(&ALL), false),
    ("out.mesh", &[], Keeps(&[Points, Volumes, Faces, Lines, Tags]), false),
    ("out.meshb", &[], Keeps(&[Points, Volumes, Faces, Lines, Tags]), false),
    // The boundary faces only (the 12 triangles the mesh has), as Extract Surface.
    ("out.obj", &[], Keeps(&[Points, Faces, Lines, Vertices]), false),
    ("out.gltf", &[], WriteOnly(&[Volumes]), false),
    ("out.glb", &[], WriteOnly(&[Volumes]), false),
    ("out.su2", &[], Keeps(&[Points, Volumes, Faces]), false),
    ("out.ele", &[], Refused, false),
    // The patches and zones read back numbered in file order, the lines' names left.
    ("out.foam", &[], Keeps(&[Points, Volumes, Faces]), false),
    ("out.stl", &[], Keeps(&[Points, Faces, Tags]), false),
    ("out.smesh", &[], Keeps(&[Points, Faces, Lines, Vertices, Tags]), false),
    ("tg.ele", &["--to", "tetgen"], Keeps(&[Points, Volumes, Faces, Lines, Tags]), false),
    // Fluent is written only: the fields and the vertex and line cells are said lost.
    ("out.fluent.msh", &[], WriteOnly(&[Vertices, Lines, PointData, CellData]), false),
    // Built with the `cgns` feature (else the line skips, saying so): cell data left.
    (
        "out.cgns",
        &[],
        Keeps(&[Points, Volumes, Faces, Lines, Vertices, Tags, Names, PointData]),
        false,
    ),
];

/// The second-order box_cyl of the public sample meshes (tetra10, triangle6, line3 and
/// their names, as Gmsh wrote it), one line per target: what keeps second-order cells.
const TABLE_O2: &[Line] = &[
    ("v41.msh", &[], Keeps(&ALL), false),
    ("v22.msh", &["--gmsh-version", "2.2"], Keeps(&ALL), false),
    ("v41b.msh", &["--binary"], Keeps(&ALL), false),
    ("v22b.msh", &["--gmsh-version", "2.2", "--binary"], Keeps(&ALL), false),
    ("out.vtu", &[], Keeps(&ALL), false),
    ("out.vtk", &[], Keeps(&ALL), false),
    // The mesh has no vertex cell and no data: those columns are kept by any format.
    (
        "out.mesh",
        &[],
        Keeps(&[Points, Volumes, Faces, Lines, Vertices, Tags, PointData, CellData]),
        false,
    ),
    ("out.obj", &[], Keeps(&[Points, Vertices, Tags, PointData, CellData]), false),
    ("out.glb", &[], WriteOnly(&[Volumes]), false),
    ("out.su2", &[], Keeps(&[Points, Vertices, Tags, PointData, CellData]), false),
    ("out.ele", &[], Refused, false),
    // Second-order cells by their corners, the lines' names left.
    ("out.foam", &[], Keeps(&[Vertices, Tags, PointData, CellData]), false),
    ("out.cgns", &[], Keeps(&ALL), false),
];

/// hex_prism_pyr of the public sample meshes (hexahedra, prisms, pyramids, tetrahedra,
/// quads and triangles, named) through Gmsh's four variants.
const TABLE_MIXED: &[Line] = &[
    ("v41.msh", &[], Keeps(&ALL), false),
    ("v41b.msh", &["--binary"], Keeps(&ALL), false),
    ("v22.msh", &["--gmsh-version", "2.2"], Keeps(&ALL), false),
    ("v22b.msh", &["--gmsh-version", "2.2", "--binary"], Keeps(&ALL), false),
    ("out.cgns", &[], Keeps(&ALL), false),
];

/// The format of each line, so that a format added to smartmesh gets a line (a missing
/// arm does not compile).
fn covered(f: Format) -> bool {
    let ext = match f {
        Format::Triangle => "ele",
        Format::Gmsh => "msh",
        Format::VtkLegacy => "vtk",
        Format::Vtu => "vtu",
        Format::Obj => "obj",
        Format::Medit => "mesh",
        Format::Gltf => "gltf",
        Format::Su2 => "su2",
        Format::OpenFoam => "foam",
        Format::Stl => "stl",
        Format::TetGen => "smesh",
        Format::Fluent => "fluent.msh",
        Format::Cgns => "cgns",
    };
    TABLE.iter().any(|(name, ..)| name.ends_with(&format!(".{ext}")))
}

/// The unit cube cut into 6 tetrahedra around its diagonal 0-7, with its boundary.
fn cube_mesh() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    for k in 0..8 {
        m.points.push([(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64]);
    }
    let pts = m.points.clone();
    let p = |i: u32| pts[i as usize];
    let det = |t: [u32; 4]| {
        let (a, b, c, d) = (p(t[0]), p(t[1]), p(t[2]), p(t[3]));
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let w = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
        u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])
    };
    let mut tets = Vec::new();
    for (a, b) in [(1, 2), (2, 1), (1, 4), (4, 1), (2, 4), (4, 2)] {
        let mut t = [0u32, a, a | b, 7];
        if det(t) < 0.0 {
            t.swap(1, 2);
        }
        tets.push(t);
    }
    // Boundary faces: those of one tetrahedron, outward (the face opposite each corner,
    // ordered against the corner).
    let mut faces: BTreeMap<[u32; 3], [u32; 3]> = BTreeMap::new();
    for t in &tets {
        for f in [[t[0], t[2], t[1]], [t[0], t[1], t[3]], [t[0], t[3], t[2]], [t[1], t[2], t[3]]] {
            let mut k = f;
            k.sort_unstable();
            if faces.remove(&k).is_none() {
                faces.insert(k, f);
            }
        }
    }
    let b = m.block_mut(CellKind::Tetra);
    for t in &tets {
        b.push(t, 10, 1);
    }
    let tris: Vec<[u32; 3]> = faces.into_values().collect();
    assert_eq!(tris.len(), 12);
    for f in &tris {
        let xs: Vec<f64> = f.iter().map(|&i| p(i)[0]).collect();
        let tag = if xs.iter().all(|&x| x == 0.0) {
            1
        } else if xs.iter().all(|&x| x == 1.0) {
            2
        } else {
            3
        };
        m.block_mut(CellKind::Triangle).push(f, tag, tag);
    }
    for e in [[0u32, 1], [1, 3], [3, 2], [2, 0]] {
        m.block_mut(CellKind::Line).push(&e, 20, 1);
    }
    m.block_mut(CellKind::Vertex).push(&[0u32], 30, 1);
    for (dim, tag, name) in [
        (3, 10, "Solid"),
        (2, 1, "Left"),
        (2, 2, "Right"),
        (2, 3, "Walls"),
        (1, 20, "Edges"),
        (0, 30, "Corner"),
    ] {
        m.tag_names.insert((dim, tag), name.to_string());
    }
    let f: Vec<f64> = m.points.iter().map(|q| q[0] + 2.0 * q[1] + 3.0 * q[2]).collect();
    let u: Vec<f64> = m.points.iter().flat_map(|q| [q[2], -q[1], 0.5 * q[0]]).collect();
    m.point_data.insert("f".into(), DataArray::new(1, f));
    m.point_data.insert("u".into(), DataArray::new(3, u));
    let n = m.num_cells();
    m.cell_data.insert("id".into(), DataArray::new(1, (1..=n).map(|i| i as f64).collect()));
    m
}

/// A multiset of rounded values, to compare arrays whatever the order.
fn bag(values: impl Iterator<Item = f64>) -> Vec<i64> {
    let mut v: Vec<i64> = values.map(|x| (x * 1e9).round() as i64).collect();
    v.sort_unstable();
    v
}

/// The value of `column` in `m`, as text to compare and show.
fn column(m: &TaggedMesh, c: Column) -> String {
    let kinds = |dim: u8| -> BTreeMap<&str, usize> {
        let mut k = BTreeMap::new();
        for b in m.blocks.iter().filter(|b| b.kind.dim() == dim) {
            *k.entry(b.kind.name()).or_insert(0) += b.len();
        }
        k
    };
    match c {
        Points => {
            let mut p: Vec<[i64; 3]> =
                m.points.iter().map(|q| q.map(|x| (x * 1e9).round() as i64)).collect();
            p.sort_unstable();
            format!("{p:?}")
        }
        Volumes => format!("{:?}", kinds(3)),
        Faces => format!("{:?}", kinds(2)),
        Lines => format!("{:?}", kinds(1)),
        Vertices => format!("{:?}", kinds(0)),
        Tags => unreachable!("compared by `tags`"),
        Names => format!("{:?}", m.tag_names),
        PointData => {
            let d: BTreeMap<&String, (usize, Vec<i64>)> = m
                .point_data
                .iter()
                .map(|(n, a)| (n, (a.components, bag(a.values.iter().copied()))))
                .collect();
            format!("{d:?}")
        }
        CellData => match m.cell_data.get("id") {
            Some(a) => format!("{:?}", bag(a.values.iter().copied())),
            None => "none".into(),
        },
    }
}

/// The cells per (kind, physical tag) of `m`, over the kinds `other` has.
fn tags(m: &TaggedMesh, other: &TaggedMesh) -> String {
    let mut t: BTreeMap<(&str, i32), usize> = BTreeMap::new();
    for (k, _, p, _) in m.cells() {
        if other.num_cells_of(k) > 0 {
            *t.entry((k.name(), p)).or_insert(0) += 1;
        }
    }
    format!("{t:?}")
}

/// The words a `dropped` line about `column` has (any of them).
fn words(c: Column) -> &'static [&'static str] {
    match c {
        Points => &["z coordinates", "points"],
        Volumes => &["tetra"],
        Faces => &["triangle"],
        Lines => &["line", "segment"],
        Vertices => &["vertex", "point cells"],
        Tags => &["tag", "reference", "marker", "attribute"],
        Names => &["name"],
        PointData => &["point data", "`f`", "`u`"],
        CellData => &["cell data", "`id`"],
    }
}

/// Adds to `errors` when no line of `dropped` speaks of `c`.
fn lost_is_listed(target: &str, c: Column, dropped: &[String], errors: &mut Vec<String>) {
    if !dropped.iter().any(|d| words(c).iter().any(|w| d.to_lowercase().contains(w))) {
        errors.push(format!("{target}: {c:?} is lost and no dropped line says so: {dropped:#?}"));
    }
}

/// One line of a table: output file, extra `convert` arguments, what it keeps, and
/// whether "refused" is accepted instead while the format's 3D writer is being built.
type Line = (&'static str, &'static [&'static str], Fate, bool);

#[test]
fn every_format_has_a_line_in_the_table() {
    for f in [
        Format::Triangle,
        Format::Gmsh,
        Format::VtkLegacy,
        Format::Vtu,
        Format::Obj,
        Format::Medit,
        Format::Gltf,
        Format::Su2,
        Format::OpenFoam,
        Format::Stl,
        Format::TetGen,
        Format::Fluent,
        Format::Cgns,
    ] {
        assert!(covered(f), "{} has no line in the table", f.name());
    }
}

#[test]
fn every_format_keeps_a_3d_mesh_or_lists_what_it_loses() {
    let errors = walk(&cube_mesh(), TABLE);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn every_format_keeps_second_order_cells_or_lists_them() {
    smartmesh_test_support::require_public_fixtures!();
    let mesh = smartmesh_test_support::formats::read_file("3d/box_cyl_o2.v41_ascii.msh");
    let errors = walk(&mesh, TABLE_O2);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

#[test]
fn gmsh_keeps_hexahedra_prisms_and_pyramids() {
    smartmesh_test_support::require_public_fixtures!();
    let mesh = smartmesh_test_support::formats::read_file("3d/hex_prism_pyr.v41_ascii.msh");
    let errors = walk(&mesh, TABLE_MIXED);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// Converts `mesh` (written as MSH 4.1) to every target of `table`, prints what each
/// keeps and returns what disagrees with the table.
fn walk(mesh: &TaggedMesh, table_lines: &[Line]) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.msh");
    smartmesh::formats::write_path(&input, mesh, None, &Default::default()).unwrap();
    let input = input.to_str().unwrap();
    let mut table = String::new();
    let mut errors = Vec::new();
    for &(name, args, fate, in_flux) in table_lines {
        let out = dir.path().join(name);
        let out_s = out.to_str().unwrap();
        let mut a = vec!["convert", input, out_s, "--json"];
        a.extend(args);
        let run = cli::smartmesh(&a, None);
        if !run.status.success() {
            let err = cli::stderr(&run);
            assert_eq!(run.status.code(), Some(2), "{name}: {err}");
            // A build without the `cgns` feature refuses CGNS, saying so.
            if !cfg!(feature = "cgns") && name.ends_with(".cgns") && err.contains("`cgns` feature")
            {
                eprintln!("note: {name} left: this build has no `cgns` feature");
                continue;
            }
            assert!(
                matches!(fate, Refused | RefusedUnclearly) || in_flux,
                "{name} refused the mesh where the table says {fate:?}: {err}"
            );
            let clear = err.contains("tetra") && err.contains(name);
            if clear == (fate == RefusedUnclearly) {
                errors.push(format!(
                    "{name}: the refusal is {}clear, unlike the table says: {err}",
                    if clear { "" } else { "un" }
                ));
            }
            table += &format!("{name:<10} refused: {}\n", err.trim());
            continue;
        }
        assert!(
            !matches!(fate, Refused | RefusedUnclearly),
            "{name} wrote the mesh where the table says refused: update it"
        );
        let j: serde_json::Value = serde_json::from_str(&cli::stdout(&run)).unwrap();
        let dropped: Vec<String> = j["dropped"]
            .as_array()
            .unwrap()
            .iter()
            .map(|d| d.as_str().unwrap().to_string())
            .collect();
        let (kept_cols, silent): (&[Column], &[Column]) = match fate {
            Keeps(k) => (k, &[]),
            SilentLoss(k, silent) => (k, silent),
            WriteOnly(_) | Refused | RefusedUnclearly | Unreadable => (&[], &[]),
        };
        if let WriteOnly(lost) = fate {
            for &c in lost {
                lost_is_listed(name, c, &dropped, &mut errors);
            }
            continue;
        }
        let back = match (read_path(Path::new(&out), None), fate) {
            (Err(e), Unreadable) => {
                table += &format!("{name:<10} does not read back: {e}\n");
                continue;
            }
            (Err(e), _) => panic!("{name}: {e}"),
            (Ok(_), Unreadable) => {
                errors.push(format!("{name} reads back where the table says it does not"));
                continue;
            }
            (Ok(back), _) => back,
        };
        let mut kept = Vec::new();
        for c in ALL {
            let same = if c == Tags {
                tags(&back, mesh) == tags(mesh, &back)
            } else {
                column(&back, c) == column(mesh, c)
            };
            if same {
                kept.push(c);
            } else if !silent.contains(&c) {
                lost_is_listed(name, c, &dropped, &mut errors);
            }
        }
        table += &format!("{name:<10} keeps {kept:?}\n");
        if kept != kept_cols {
            errors.push(format!("{name}: the table's line is out of date: keeps {kept:?}"));
        }
    }
    eprintln!("{table}");
    errors
}
