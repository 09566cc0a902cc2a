//! OpenFOAM cases: the extruded polyMesh against what OpenFOAM requires (checked here
//! with geometry written apart from the writer's), the case directory written whole,
//! and the patches named and typed from the tags. `tests/openfoam_interop.rs` runs
//! OpenFOAM's own `checkMesh` on the cases.

use std::path::Path;

use smartmesh_formats::openfoam::{
    extrude, extrude_layer, patch_type, poly_mesh_files, CyclicPair, CyclicTransform, Layer,
    OpenFoamWrite, PolyMesh,
};
use smartmesh_formats::{
    read_path, write_path, CellBlock, CellKind, Format, TaggedMesh, WriteOptions, WriteReport,
};

fn cylinder() -> TaggedMesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cylinder.msh");
    read_path(&path, None).unwrap()
}

/// A 2 x 1 rectangle: a quad [0,1]² and two triangles on [1,2]x[0,1], one of them
/// clockwise; lines tagged Bottom (1, two edges), Outlet (2) and unnamed 3 (the top
/// edge of the quad); the rest of the boundary without lines.
fn mixed() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 1.0, 0.0],
        [9.0, 9.0, 0.0], // used by no cell
    ];
    let mut q = CellBlock::new(CellKind::Quad);
    q.push(&[0u32, 1, 4, 3], 1, 1);
    let mut t = CellBlock::new(CellKind::Triangle);
    t.push(&[1u32, 2, 5], 1, 1);
    t.push(&[1u32, 4, 5], 1, 1); // clockwise
    let mut l = CellBlock::new(CellKind::Line);
    l.push(&[0u32, 1], 1, 1);
    l.push(&[1u32, 2], 1, 1);
    l.push(&[2u32, 5], 2, 2);
    l.push(&[4u32, 3], 3, 3);
    m.blocks = vec![q, t, l];
    m.tag_names.insert((1, 1), "Bottom".into());
    m.tag_names.insert((1, 2), "Outlet".into());
    m
}

fn poly(mesh: &TaggedMesh, dz: f64) -> (PolyMesh, WriteReport) {
    let mut report = WriteReport::default();
    let p = extrude(
        mesh,
        dz,
        |t, _| (mesh.tag_name(1, t).map_or(format!("tag{t}"), str::to_owned), "patch".into()),
        &mut report,
    )
    .unwrap();
    (p, report)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A face's area vector (Newell's method) and centre.
fn face_geometry(p: &PolyMesh, f: &[u32]) -> ([f64; 3], [f64; 3]) {
    let mut n = [0.0; 3];
    let mut c = [0.0; 3];
    for k in 0..f.len() {
        let a = p.points[f[k] as usize];
        let b = p.points[f[(k + 1) % f.len()] as usize];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
        for i in 0..3 {
            c[i] += a[i] / f.len() as f64;
        }
    }
    (n, c)
}

/// Every rule of OpenFOAM's polyMesh, checked from the faces alone.
fn assert_valid(p: &PolyMesh) {
    let ni = p.neighbour.len();
    assert_eq!(p.owner.len(), p.faces.len());
    // Cell centres: the mean of each cell's face centres.
    let mut centre = vec![[0.0; 3]; p.n_cells];
    let mut count = vec![0.0; p.n_cells];
    let mut faces_of = vec![0usize; p.n_cells];
    for (fi, f) in p.faces.iter().enumerate() {
        let (_, c) = face_geometry(p, f);
        let mut add = |cell: usize| {
            for i in 0..3 {
                centre[cell][i] += c[i];
            }
            count[cell] += 1.0;
            faces_of[cell] += 1;
        };
        add(p.owner[fi] as usize);
        if fi < ni {
            add(p.neighbour[fi] as usize);
        }
    }
    for (c, n) in centre.iter_mut().zip(&count) {
        for v in c.iter_mut() {
            *v /= n;
        }
    }
    // Prisms have 5 faces, hexahedra 6; on a wedge's axis, tetrahedra 4 and pyramids 5.
    assert!(faces_of.iter().all(|&n| (4..=6).contains(&n)), "{faces_of:?}");
    for fi in 0..ni {
        assert!(p.owner[fi] < p.neighbour[fi], "face {fi}: owner must be below neighbour");
        if fi > 0 {
            let prev = (p.owner[fi - 1], p.neighbour[fi - 1]);
            assert!(prev < (p.owner[fi], p.neighbour[fi]), "face {fi}: not upper-triangular");
        }
        let (n, _) = face_geometry(p, &p.faces[fi]);
        let d = sub(centre[p.neighbour[fi] as usize], centre[p.owner[fi] as usize]);
        assert!(dot(n, d) > 0.0, "internal face {fi} points from neighbour to owner");
    }
    for fi in ni..p.faces.len() {
        let (n, c) = face_geometry(p, &p.faces[fi]);
        assert!(dot(n, sub(c, centre[p.owner[fi] as usize])) > 0.0, "boundary face {fi} points in");
    }
    // Patches cover the boundary faces exactly, in order.
    assert_eq!(p.patches.iter().map(|q| q.n_faces).sum::<usize>(), p.faces.len() - ni);
    // Every point used.
    let mut used = vec![false; p.points.len()];
    for f in &p.faces {
        for &v in f {
            used[v as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u));
}

#[test]
fn a_mixed_mesh_extrudes_to_a_valid_poly_mesh() {
    let m = mixed();
    let (p, report) = poly(&m, 0.1);
    assert_valid(&p);
    assert_eq!(p.n_cells, 3);
    assert_eq!(p.points.len(), 12, "the unused point is left out");
    assert_eq!(p.neighbour.len(), 2);
    let patches: Vec<_> = p.patches.iter().map(|q| (q.name.as_str(), q.n_faces)).collect();
    assert_eq!(
        patches,
        [("defaultFaces", 2), ("Bottom", 2), ("Outlet", 1), ("tag3", 1), ("front", 3), ("back", 3)]
    );
    assert!(p.patches[4..].iter().all(|q| q.kind == "empty"));
    let dropped = report.dropped.join("\n");
    assert!(dropped.contains("1 clockwise"), "{dropped}");
    assert!(dropped.contains("1 points no triangle"), "{dropped}");
    assert!(dropped.contains("2 boundary edges without a line cell"), "{dropped}");
    // z from 0 to dz.
    assert!(p.points.iter().all(|q| q[2] == 0.0 || q[2] == 0.1));
}

#[test]
fn the_cylinder_extrudes_to_a_valid_poly_mesh() {
    let m = cylinder();
    let (p, _) = poly(&m, 0.04);
    assert_valid(&p);
    assert_eq!(p.n_cells, m.num_cells_of(CellKind::Triangle));
    let names: Vec<_> = p.patches.iter().map(|q| q.name.as_str()).collect();
    assert_eq!(names, ["Inlet", "Outlet", "Walls", "Cylinder", "front", "back"]);
}

#[test]
fn cells_that_fold_or_share_an_edge_three_times_are_refused() {
    let mut m = mixed();
    // A third cell on edge 1-4.
    m.points.push([0.5, 0.5, 0.0]);
    m.blocks[1].push(&[1u32, 4, 7], 1, 1);
    let mut report = WriteReport::default();
    let e = extrude(&m, 1.0, |_, _| ("x".into(), "patch".into()), &mut report).unwrap_err();
    assert!(e.contains("shared by 3 cells"), "{e}");
    let mut m = mixed();
    m.points[4] = m.points[1];
    let e = extrude(&m, 1.0, |_, _| ("x".into(), "patch".into()), &mut report).unwrap_err();
    assert!(e.contains("zero area"), "{e}");
}

#[test]
fn patch_types_come_from_the_names() {
    for (name, kind) in [
        ("Walls", "wall"),
        ("Airfoil", "wall"),
        ("cylinder_surface", "wall"),
        ("Upper", "wall"),
        ("Inlet", "patch"),
        ("FarField", "patch"),
        ("LowerPeriodic1", "patch"),
        ("Outlet", "patch"),
        ("tag3", "patch"),
    ] {
        assert_eq!(patch_type(name), kind, "{name}");
    }
    // A user's map wins.
    let opts = OpenFoamWrite {
        extrude: Some(1.0),
        patch_types: [("Outlet".to_string(), "wall".to_string())].into(),
        ..Default::default()
    };
    let (files, _) = poly_mesh_files(&mixed(), &opts).unwrap();
    let boundary = String::from_utf8(files.iter().find(|f| f.0 == "boundary").unwrap().1.clone());
    let boundary = boundary.unwrap();
    let outlet = &boundary[boundary.find("Outlet").unwrap()..];
    assert!(outlet[..outlet.find('}').unwrap()].contains("type            wall;"), "{boundary}");
}

#[test]
fn names_become_openfoam_words_and_unnamed_tags_are_said() {
    let mut m = mixed();
    m.tag_names.insert((1, 1), "far field (x=0)".into());
    m.tag_names.insert((1, 2), "front".into());
    let (files, report) = poly_mesh_files(&m, &OpenFoamWrite::default()).unwrap();
    let boundary = String::from_utf8(files[4].1.clone()).unwrap();
    assert!(boundary.contains("    far_field__x=0_\n"), "{boundary}");
    assert!(
        boundary.contains("    front_"),
        "a tag named front does not take the empty patch's name"
    );
    let dropped = report.dropped.join("\n");
    assert!(dropped.contains("line tag 3 has no name: written as patch `tag3`"), "{dropped}");
    assert!(dropped.contains("z = 0.02 (a hundredth"), "{dropped}");
}

#[test]
fn the_case_directory_is_written_whole_and_keeps_what_the_user_wrote() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("cyl.foam");
    assert_eq!(Format::from_path(&case), Some(Format::OpenFoam));
    let opts = WriteOptions {
        openfoam: OpenFoamWrite { extrude: Some(0.5), ..Default::default() },
        ..WriteOptions::default()
    };
    write_path(&case, &cylinder(), None, &opts).unwrap();
    for f in ["points", "faces", "owner", "neighbour", "boundary"] {
        assert!(case.join("constant/polyMesh").join(f).is_file(), "{f}");
    }
    let control = case.join("system/controlDict");
    assert!(std::fs::read_to_string(&control).unwrap().contains("FoamFile"));
    std::fs::write(&control, "mine").unwrap();
    // Again, with another mesh: polyMesh replaced, the user's controlDict kept, nothing
    // left behind in constant/.
    write_path(&case, &mixed(), Some(Format::OpenFoam), &opts).unwrap();
    assert_eq!(std::fs::read_to_string(&control).unwrap(), "mine");
    let owner = std::fs::read_to_string(case.join("constant/polyMesh/owner")).unwrap();
    assert!(owner.contains("nCells:3 "), "{owner}");
    let left: Vec<_> =
        std::fs::read_dir(case.join("constant")).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(left, ["polyMesh"]);
    // A mesh that cannot be extruded leaves the case as it was.
    let mut bad = mixed();
    bad.points[4] = bad.points[1];
    assert!(write_path(&case, &bad, None, &opts).is_err());
    assert_eq!(std::fs::read_to_string(case.join("constant/polyMesh/owner")).unwrap(), owner);
}

#[test]
fn a_file_stdout_or_a_bad_thickness_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("x.foam");
    std::fs::write(&file, "").unwrap();
    let e = write_path(&file, &mixed(), None, &WriteOptions::default()).unwrap_err();
    assert!(e.to_string().contains("is a directory"), "{e}");
    let e = write_path(Path::new("-"), &mixed(), Some(Format::OpenFoam), &WriteOptions::default())
        .unwrap_err();
    assert!(e.to_string().contains("directory"), "{e}");
    let opts = OpenFoamWrite { extrude: Some(-1.0), ..Default::default() };
    assert!(poly_mesh_files(&mixed(), &opts).is_err());
    // No triangle or quad: nothing to extrude.
    let mut lines_only = mixed();
    lines_only.blocks.drain(..2);
    assert!(poly_mesh_files(&lines_only, &OpenFoamWrite::default()).is_err());
}

/// Each cell as its nodes turned to start at the smallest, counter-clockwise made
/// canonical, sorted: the cells whatever their first node and order.
fn canonical_cells(m: &TaggedMesh, kinds: &[CellKind]) -> Vec<Vec<u32>> {
    let mut out: Vec<Vec<u32>> = m
        .cells()
        .filter(|c| kinds.contains(&c.0))
        .map(|(_, n, _, _)| {
            let k = (0..n.len()).min_by_key(|&i| n[i]).unwrap();
            let mut v: Vec<u32> = (0..n.len()).map(|i| n[(k + i) % n.len()]).collect();
            if v.len() > 2 && v[1] > v[v.len() - 1] {
                v[1..].reverse();
            }
            v
        })
        .collect();
    out.sort();
    out
}

/// Line cells per tag name, as sorted point pairs.
fn lines_by_name(m: &TaggedMesh) -> std::collections::BTreeMap<String, Vec<[u32; 2]>> {
    let mut out: std::collections::BTreeMap<String, Vec<[u32; 2]>> = Default::default();
    for (kind, n, p, _) in m.cells() {
        if kind == CellKind::Line {
            let name = m.tag_name(1, p).map_or_else(|| format!("tag{p}"), str::to_owned);
            out.entry(name).or_default().push([n[0].min(n[1]), n[0].max(n[1])]);
        }
    }
    for v in out.values_mut() {
        v.sort();
    }
    out
}

#[test]
fn a_written_case_reads_back_as_the_2d_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let mut cyl = cylinder();
    cyl.blocks.retain(|b| b.kind != CellKind::Vertex);
    let cases =
        [("cyl.foam", cyl.clone(), false), ("mixed.foam", mixed(), false), ("cyl.foam", cyl, true)];
    for (name, mesh, binary) in cases {
        let case = dir.path().join(if binary { "binary" } else { "ascii" }).join(name);
        std::fs::create_dir_all(case.parent().unwrap()).unwrap();
        let opts = WriteOptions {
            openfoam: OpenFoamWrite { binary, ..Default::default() },
            ..WriteOptions::default()
        };
        write_path(&case, &mesh, None, &opts).unwrap();
        if binary {
            let faces = std::fs::read(case.join("constant/polyMesh/faces")).unwrap();
            assert!(faces.windows(15).any(|w| w == b"faceCompactList"));
        }
        let back = read_path(&case, None).unwrap_or_else(|e| panic!("{e}"));
        // The points no cell uses are left out; the others keep their order and bits.
        let used: Vec<[f64; 3]> = if name == "mixed.foam" {
            mesh.points[..6].to_vec()
        } else {
            mesh.points.iter().map(|p| [p[0], p[1], 0.0]).collect()
        };
        assert_eq!(back.points, used, "{name}");
        let kinds = [CellKind::Triangle, CellKind::Quad];
        assert_eq!(canonical_cells(&back, &kinds), canonical_cells(&mesh, &kinds), "{name}");
        let mut want = lines_by_name(&mesh);
        if name == "mixed.foam" {
            // The boundary edges without a line cell.
            want.insert("defaultFaces".into(), vec![[0, 3], [4, 5]]);
        }
        assert_eq!(lines_by_name(&back), want, "{name}");
        // Every cell counter-clockwise.
        for (_, n, _, _) in back.cells().filter(|c| c.0.dim() == 2) {
            let p = |i: usize| back.points[n[i] as usize];
            let area: f64 = (0..n.len())
                .map(|i| p(i)[0] * p((i + 1) % n.len())[1] - p((i + 1) % n.len())[0] * p(i)[1])
                .sum();
            assert!(area > 0.0);
        }
    }
}

#[test]
fn malformed_cases_are_refused_naming_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("m.foam");
    let poly = case.join("constant/polyMesh");
    let fresh = || write_path(&case, &mixed(), None, &WriteOptions::default()).unwrap();
    let edit = |file: &str, from: &str, to: &str| {
        let p = poly.join(file);
        let s = std::fs::read_to_string(&p).unwrap();
        assert!(s.contains(from), "{from} in {s}");
        std::fs::write(&p, s.replacen(from, to, 1)).unwrap();
    };
    let cases: [(&str, &str, &str, &str); 7] = [
        ("faces", "4(", "4(99 ", "refers to 99"),
        ("points", "(0.0 0.0 0.0)", "(0.0 nan 0.0)", "not a finite number"),
        ("points", "12\n(", "1200000000\n(", "cannot hold"),
        (
            "faces",
            "format      ascii;",
            "format      binary;\narch \"LSB;label=64\";",
            "arch `LSB;label=64`",
        ),
        ("boundary", "nFaces          2;", "nFaces          200;", "at most"),
        ("owner", "\n0\n", "\nx\n", "expected a cell"),
        ("boundary", "type            empty;", "type            patch;", ""),
    ];
    for (file, from, to, what) in cases {
        fresh();
        edit(file, from, to);
        let e = read_path(&case, None).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains(what), "{what}: {msg}");
        if what.is_empty() {
            // front became a plain patch, back is still empty: its faces have no two
            // points on the base.
            continue;
        }
        assert!(msg.contains(&format!("polyMesh/{file}:")), "{msg}");
    }
    fresh();
    std::fs::remove_file(poly.join("neighbour")).unwrap();
    let e = read_path(&case, None).unwrap_err();
    assert!(e.to_string().contains("neighbour"), "{e}");
}

#[test]
fn damaged_poly_mesh_files_never_panic() {
    use smartmesh_formats::openfoam::read_poly_mesh;
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    for binary in [false, true] {
        let opts = OpenFoamWrite { binary, ..Default::default() };
        let (files, _) = poly_mesh_files(&mixed(), &opts).unwrap();
        for which in 0..files.len() {
            let original = &files[which].1;
            let mut copies: Vec<Vec<u8>> =
                (0..original.len()).step_by(7).map(|n| original[..n].to_vec()).collect();
            for _ in 0..300 {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let mut b = original.clone();
                let i = (seed % b.len() as u64) as usize;
                b[i] = [b'9', b'-', b'(', b')', b'{', b';', 0xff, b'/'][(seed >> 40) as usize % 8];
                copies.push(b);
            }
            for damaged in copies {
                let get = |name: &str| {
                    let (k, (_, bytes)) =
                        files.iter().enumerate().find(|(_, (n, _))| *n == name).unwrap();
                    Ok(if k == which { damaged.clone() } else { bytes.clone() })
                };
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    read_poly_mesh(get, Path::new("polyMesh"))
                }));
                match r {
                    Ok(Ok(m)) => assert_eq!(m.validate(), Vec::new()),
                    Ok(Err(e)) => assert!(e.path.is_some(), "{e}"),
                    Err(_) => panic!("panicked on damaged `{}`", files[which].0),
                }
            }
        }
    }
}

#[test]
fn a_cell_label_past_the_faces_allocates_nothing() {
    use smartmesh_formats::openfoam::read_poly_mesh;
    let (files, _) = poly_mesh_files(&mixed(), &OpenFoamWrite::default()).unwrap();
    let get = |name: &str| {
        let bytes = files.iter().find(|(n, _)| *n == name).unwrap().1.clone();
        Ok(if name == "neighbour" {
            String::from_utf8(bytes).unwrap().replace("\n2\n)", "\n4000000000\n)").into_bytes()
        } else {
            bytes
        })
    };
    let e = read_poly_mesh(get, Path::new("polyMesh")).unwrap_err();
    assert!(e.to_string().contains("at most"), "{e}");
}

#[test]
fn a_wedge_turns_the_mesh_about_the_x_axis_and_collapses_the_axis_faces() {
    let m = mixed();
    let mut report = WriteReport::default();
    let name = |t: i32, _: &mut WriteReport| {
        (m.tag_name(1, t).map_or(format!("tag{t}"), str::to_owned), "patch".to_string())
    };
    let p = extrude_layer(&m, Layer::Wedge(5.0), name, &mut report).unwrap();
    assert_valid(&p);
    // The three points on y = 0 are shared: 6 below, 3 above.
    assert_eq!(p.points.len(), 9);
    let half = 2.5f64.to_radians();
    for q in &p.points {
        let r = (q[1] * q[1] + q[2] * q[2]).sqrt();
        assert!(q[2] == 0.0 || (q[2].abs() - r * half.sin()).abs() < 1e-15, "{q:?}");
    }
    // Bottom (the axis) has no face left; front and back are wedges.
    let names: Vec<_> = p.patches.iter().map(|q| (q.name.as_str(), q.kind.as_str())).collect();
    assert_eq!(
        names,
        [
            ("defaultFaces", "patch"),
            ("Outlet", "patch"),
            ("tag3", "patch"),
            ("front", "wedge"),
            ("back", "wedge")
        ]
    );
    assert!(report.dropped.iter().any(|d| d.contains("2 boundary edges on the wedge's axis")));
    // Below the axis is refused.
    let mut below = mixed();
    below.points[5][1] = -0.5;
    let mut report = WriteReport::default();
    let e = extrude_layer(
        &below,
        Layer::Wedge(5.0),
        |_, _| (String::new(), String::new()),
        &mut report,
    )
    .unwrap_err();
    assert!(e.contains("y < 0"), "{e}");
}

// ---------------------------------------------------------------------------------
// 3D meshes, written without extrusion

use smartmesh_formats::openfoam::volume_poly_mesh;
use smartmesh_test_support::formats as common;

/// The polyMesh of a 3D mesh, patches named by their surface tag's name.
fn volume_poly(mesh: &TaggedMesh) -> (PolyMesh, WriteReport) {
    let mut report = WriteReport::default();
    let p = volume_poly_mesh(
        mesh,
        |t, _| (mesh.tag_name(2, t).map_or(format!("tag{t}"), str::to_owned), "patch".into()),
        |d, t| mesh.tag_name(d, t).map_or(format!("tag{t}"), str::to_owned),
        &mut report,
    )
    .unwrap();
    (p, report)
}

/// Each volume cell as its kind and sorted corner coordinates, with its tag's name,
/// and each surface cell likewise: what a 3D round trip keeps whatever the numbering.
fn cells_by_points(m: &TaggedMesh) -> Vec<(CellKind, String, Vec<[u64; 3]>)> {
    let mut v: Vec<_> = m
        .cells()
        .filter(|c| c.0.dim() >= 2)
        .map(|(k, n, p, _)| {
            let mut pts: Vec<[u64; 3]> =
                n.iter().map(|&i| m.points[i as usize].map(f64::to_bits)).collect();
            pts.sort();
            (k, m.tag_name(k.dim(), p).unwrap_or("").to_string(), pts)
        })
        .collect();
    v.sort();
    v
}

/// The volume of each cell of Gmsh's order, cut into positively oriented tetrahedra.
fn cell_volumes(m: &TaggedMesh) -> Vec<f64> {
    m.cells()
        .filter(|c| c.0.dim() == 3)
        .map(|(k, n, _, _)| {
            let p = |i: usize| m.points[n[i] as usize];
            let tet = |a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]| {
                let (u, v, w) = (sub(b, a), sub(c, a), sub(d, a));
                dot(
                    u,
                    [
                        v[1] * w[2] - v[2] * w[1],
                        v[2] * w[0] - v[0] * w[2],
                        v[0] * w[1] - v[1] * w[0],
                    ],
                ) / 6.0
            };
            let cut: &[[usize; 4]] = match k {
                CellKind::Tetra => &[[0, 1, 2, 3]],
                CellKind::Pyramid => &[[0, 1, 2, 4], [0, 2, 3, 4]],
                CellKind::Wedge => &[[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]],
                _ => &[[0, 1, 3, 4], [1, 2, 3, 6], [1, 3, 4, 6], [1, 4, 5, 6], [3, 4, 6, 7]],
            };
            cut.iter().map(|t| tet(p(t[0]), p(t[1]), p(t[2]), p(t[3]))).sum()
        })
        .collect()
}

/// Gmsh's mixed mesh (hexahedra, prisms, tetrahedra, pyramids): a valid polyMesh by
/// every rule, patches from the boundary surface groups, the inner `Interface` group a
/// face zone, a cell zone per volume group; read back, the same cells (kinds, corners,
/// names, positive volumes), ASCII and binary.
#[test]
fn a_mixed_3d_mesh_is_written_directly_and_reads_back() {
    smartmesh_test_support::require_public_fixtures!();
    let m = common::read_file("3d/hex_prism_pyr.v41_ascii.msh");
    let (p, report) = volume_poly(&m);
    assert_valid(&p);
    assert_eq!(p.n_cells, 242);
    let patches: Vec<(&str, usize)> =
        p.patches.iter().map(|q| (q.name.as_str(), q.n_faces)).collect();
    assert_eq!(patches, [("Bottom", 27), ("Top", 44), ("Sides", 118)]);
    let zones: Vec<(&str, usize)> =
        p.cell_zones.iter().map(|z| (z.0.as_str(), z.1.len())).collect();
    assert_eq!(zones, [("Hexa", 27), ("Prisms", 54), ("TetPyr", 161)]);
    assert_eq!(p.face_zones.len(), 1);
    assert_eq!((p.face_zones[0].0.as_str(), p.face_zones[0].1.len()), ("Interface", 18));
    assert!(p.face_zones[0].1.iter().all(|&f| (f as usize) < p.neighbour.len()));
    assert!(report.dropped.is_empty(), "{:?}", report.dropped);

    let want = cells_by_points(&m);
    let volumes = cell_volumes(&m);
    for binary in [false, true] {
        let dir = tempfile::tempdir().unwrap();
        let case = dir.path().join("mixed.foam");
        let opts = WriteOptions {
            openfoam: OpenFoamWrite { binary, ..Default::default() },
            ..Default::default()
        };
        write_path(&case, &m, Some(Format::OpenFoam), &opts).unwrap();
        let back = read_path(&case, Some(Format::OpenFoam)).unwrap();
        assert_eq!(back.coordinate_dim, 3);
        assert_eq!(cells_by_points(&back), want, "binary {binary}");
        let got = cell_volumes(&back);
        assert!(got.iter().all(|&v| v > 0.0));
        // Same cells in the same order: the same volumes, to rounding.
        for (a, b) in got.iter().zip(&volumes) {
            assert!((a - b).abs() <= 1e-14, "{a} {b}");
        }
    }
}

/// box_cyl's tetrahedra: valid, its four surface groups as patches (the cylinder a
/// wall), the line cells said to be left, and one cell zone (the volume is named).
#[test]
fn a_tetrahedral_mesh_with_a_hole_is_written_directly() {
    smartmesh_test_support::require_public_fixtures!();
    let m = common::read_file("3d/box_cyl.v41_ascii.msh");
    let (files, report) = poly_mesh_files(&m, &OpenFoamWrite::default()).unwrap();
    let boundary =
        String::from_utf8(files.iter().find(|f| f.0 == "boundary").unwrap().1.clone()).unwrap();
    let cylinder = &boundary[boundary.find("Cylinder").unwrap()..];
    assert!(
        cylinder[..cylinder.find('}').unwrap()].contains("type            wall;"),
        "{boundary}"
    );
    assert!(report.dropped.iter().any(|d| d.contains("16 line and vertex cells")), "{report:?}");
    assert!(files.iter().any(|f| f.0 == "cellZones"));
    assert!(!files.iter().any(|f| f.0 == "faceZones"));
    let (p, _) = volume_poly(&m);
    assert_valid(&p);
    let patches: Vec<(&str, usize)> =
        p.patches.iter().map(|q| (q.name.as_str(), q.n_faces)).collect();
    assert_eq!(patches, [("Inlet", 90), ("Outlet", 90), ("Walls", 714), ("Cylinder", 118)]);
}

/// A cell given in the mirrored order is written with its faces outward; boundary
/// faces without a surface cell go to `defaultFaces`.
#[test]
fn a_mirrored_cell_is_turned_and_untagged_faces_are_default_faces() {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.], [1., 1., 1.]];
    m.block_mut(CellKind::Tetra).push(&[0u32, 2, 1, 3], 1, 1); // mirrored
    m.block_mut(CellKind::Tetra).push(&[1u32, 2, 3, 4], 1, 1);
    let (p, report) = volume_poly(&m);
    assert_valid(&p);
    assert_eq!(p.patches.len(), 1);
    assert_eq!((p.patches[0].name.as_str(), p.patches[0].n_faces), ("defaultFaces", 6));
    assert!(report.dropped.iter().any(|d| d.contains("1 volume cells given in the mirrored")));
}

/// A 2 x 1 channel of quads whose bottom (tag 1) and top (tag 4) are periodic by
/// (0, 1): two `cyclic` patches naming each other, the top's faces in the order of the
/// bottom's; a wrong translation, a count mismatch and an unknown tag are refused.
#[test]
fn periodic_sides_become_cyclic_patches_or_are_refused() {
    let mut m = TaggedMesh::new();
    m.points = (0..6).map(|k| [(k % 3) as f64, (k / 3) as f64, 0.0]).collect();
    let mut q = CellBlock::new(CellKind::Quad);
    q.push(&[0u32, 1, 4, 3], 1, 1);
    q.push(&[1u32, 2, 5, 4], 1, 1);
    let mut l = CellBlock::new(CellKind::Line);
    l.push(&[0u32, 1], 1, 1);
    l.push(&[1u32, 2], 1, 1);
    l.push(&[2u32, 5], 2, 2);
    l.push(&[4u32, 3], 4, 4); // the top, listed out of the bottom's order
    l.push(&[5u32, 4], 4, 4);
    l.push(&[3u32, 0], 3, 3);
    m.blocks = vec![q, l];
    m.tag_names.insert((1, 1), "Bottom".into());
    m.tag_names.insert((1, 4), "Top".into());
    let pair = |t: [f64; 3], slave: i32| OpenFoamWrite {
        extrude: Some(1.0),
        cyclic: vec![CyclicPair {
            master: vec![1],
            slave: vec![slave],
            transform: CyclicTransform::Translation(t),
        }],
        ..Default::default()
    };
    let (files, _) = poly_mesh_files(&m, &pair([0.0, 1.0, 0.0], 4)).unwrap();
    let text = |name: &str| {
        String::from_utf8(files.iter().find(|f| f.0 == name).unwrap().1.clone()).unwrap()
    };
    let boundary = text("boundary");
    assert_eq!(boundary.matches("type            cyclic;").count(), 2, "{boundary}");
    assert!(boundary.contains("neighbourPatch  Top;"), "{boundary}");
    assert!(boundary.contains("neighbourPatch  Bottom;"), "{boundary}");
    assert!(boundary.contains("separationVector (0 1 0);"), "{boundary}");
    assert!(boundary.contains("separationVector (0 -1 0);"), "{boundary}");
    // The faces after the 1 internal one: Bottom's two then Top's two, the top face i
    // over the bottom face i, its first point over the bottom face's first point.
    let faces: Vec<Vec<u32>> = text("faces")
        .lines()
        .filter(|l| l.starts_with("4("))
        .map(|l| l[2..l.len() - 1].split(' ').map(|v| v.parse().unwrap()).collect())
        .collect();
    let start = boundary.find("Bottom").unwrap();
    let first: usize = boundary[start..]
        .lines()
        .find_map(|l| l.trim().strip_prefix("startFace").map(|v| v.trim().trim_end_matches(';')))
        .unwrap()
        .parse()
        .unwrap();
    let plane = |v: u32| [(v % 6 % 3) as f64, (v % 6 / 3) as f64, (v / 6) as f64];
    for i in 0..2 {
        let (b, t) = (&faces[first + i], &faces[first + 2 + i]);
        let (pb, pt) = (plane(b[0]), plane(t[0]));
        assert_eq!([pb[0], pb[1] + 1.0, pb[2]], pt, "face {i}: {b:?} and {t:?}");
        let centre = |f: &[u32]| f.iter().map(|&v| plane(v)[0]).sum::<f64>();
        assert_eq!(centre(b), centre(t), "face {i}: {b:?} and {t:?}");
    }

    for (opts, says) in [
        (pair([0.0, -1.0, 0.0], 4), "not images of each other"),
        (pair([0.0, 1.0, 0.0], 2), "1 on the slave side"),
        (pair([0.0, 1.0, 0.0], 7), "tag 7 is no boundary patch"),
    ] {
        let e = poly_mesh_files(&m, &opts).unwrap_err().to_string();
        assert!(e.contains(says), "{e}");
    }
}
