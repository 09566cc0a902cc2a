//! Fluent ASCII meshes (`.fluent.msh`) as written (reading: `fluent_read.rs`): small
//! 2D and 3D meshes of every linear cell kind written and parsed back here, each
//! face's orientation checked by an independent twin (the divergence theorem: every
//! cell closed, its volume or area from its faces equal to the geometry's), zone names
//! and types from tag names, and the refusals. `fluentMeshToFoam` + `checkMesh` and
//! meshio read the files in `tests/fluent_interop.rs` of the smartmesh crate.

use std::collections::BTreeMap;

use smartmesh_formats::{
    fluent, write_bytes, CellBlock, CellKind, ErrorKind, Format, TaggedMesh, WriteOptions,
};

fn block(kind: CellKind, cells: &[(&[u32], i32)]) -> CellBlock {
    let mut b = CellBlock::new(kind);
    for (nodes, tag) in cells {
        b.push(nodes, *tag, *tag);
    }
    b
}

/// A 2 x 2 square of one quad and six triangles, some numbered clockwise; bottom
/// `Inlet` (1), right `Wall` (2), left unnamed (4), top untagged, an inner `Interface`
/// (5) along y = 1 from x = 0 to 1, and one unused point.
fn square() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    for j in 0..3 {
        for i in 0..3 {
            m.points.push([i as f64, j as f64, 0.0]);
        }
    }
    m.points.push([9.0, 9.0, 0.0]);
    m.blocks.push(block(CellKind::Quad, &[(&[0, 1, 4, 3], 7)]));
    m.blocks.push(block(
        CellKind::Triangle,
        &[
            (&[1, 2, 5], 7),
            (&[1, 4, 5], 7), // clockwise
            (&[3, 4, 7], 7),
            (&[3, 6, 7], 7), // clockwise
            (&[4, 5, 8], 7),
            (&[4, 8, 7], 7),
        ],
    ));
    m.blocks.push(block(
        CellKind::Line,
        &[
            (&[0, 1], 1),
            (&[1, 2], 1),
            (&[2, 5], 2),
            (&[5, 8], 2),
            (&[0, 3], 4),
            (&[3, 6], 4),
            (&[3, 4], 5),
        ],
    ));
    m.tag_names.insert((1, 1), "Inlet".into());
    m.tag_names.insert((1, 2), "Wall".into());
    m.tag_names.insert((1, 5), "Interface".into());
    m.tag_names.insert((2, 7), "Air".into());
    m
}

/// A hexahedron (unit cube), two wedges beside it (the cube [1,2]x[0,1]x[0,1] cut along
/// its diagonal), a pyramid on the hexahedron and a tetrahedron on a wedge: volume
/// 1 + 1 + 1/6 + 1/12. Floor (z = 0, triangles and a quad) `Floor`, x = 2 `Outlet`,
/// the inner quad between the hexahedron and a wedge `Interface`.
fn blocks3d() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    #[rustfmt::skip]
    let p = [
        [0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.],
        [0., 0., 1.], [1., 0., 1.], [1., 1., 1.], [0., 1., 1.],
        [2., 0., 0.], [2., 1., 0.], [2., 0., 1.], [2., 1., 1.],
        [0.5, 0.5, 1.5], [1.5, 0.5, 1.5],
    ];
    m.points.extend(p);
    m.blocks.push(block(CellKind::Hexa, &[(&[0, 1, 2, 3, 4, 5, 6, 7], 1)]));
    m.blocks.push(block(CellKind::Wedge, &[(&[1, 8, 9, 5, 10, 11], 2), (&[1, 9, 2, 5, 11, 6], 2)]));
    m.blocks.push(block(CellKind::Pyramid, &[(&[4, 5, 6, 7, 12], 1)]));
    m.blocks.push(block(CellKind::Tetra, &[(&[5, 10, 11, 13], 2)]));
    m.blocks.push(block(
        CellKind::Quad,
        &[(&[0, 1, 2, 3], 1), (&[8, 9, 11, 10], 2), (&[1, 2, 6, 5], 3)],
    ));
    m.blocks.push(block(CellKind::Triangle, &[(&[1, 8, 9], 1), (&[1, 9, 2], 1)]));
    m.tag_names.insert((2, 1), "Floor".into());
    m.tag_names.insert((2, 2), "Outlet".into());
    m.tag_names.insert((2, 3), "Interface".into());
    m
}

/// A face as read: its nodes (1-based), c0, c1.
type Face = (Vec<u64>, u64, u64);

/// What the test reads back of a Fluent file.
#[derive(Default, Debug)]
struct Parsed {
    dim: usize,
    nodes: Vec<[f64; 3]>,
    /// (zone, first, last, type, element type) of each cell zone.
    cell_zones: Vec<[u64; 5]>,
    /// (zone, bc type, face type) and its faces: nodes (1-based), c0, c1.
    face_zones: Vec<([u64; 3], Vec<Face>)>,
    /// Zone id -> (type, name) of the `(45 ...)` records (decimal ids).
    names: BTreeMap<u64, (String, String)>,
    declared_faces: u64,
    declared_cells: u64,
}

fn hex(t: &str) -> u64 {
    u64::from_str_radix(t, 16).unwrap_or_else(|_| panic!("not hexadecimal: {t}"))
}

/// Parses what the writer writes (one header per line, bodies until `))`).
fn parse(text: &str) -> Parsed {
    let mut p = Parsed::default();
    let mut lines = text.lines();
    while let Some(line) = lines.next() {
        let inner = |l: &str| -> Vec<String> {
            let s = &l[l.find(" (").unwrap() + 2..];
            s[..s.find(')').unwrap()].split_whitespace().map(String::from).collect()
        };
        let body = line.ends_with('(');
        if line.starts_with("(2 ") {
            p.dim = line[3..line.len() - 1].parse().unwrap();
        } else if line.starts_with("(10 (") {
            let h: Vec<u64> = inner(line).iter().map(|t| hex(t)).collect();
            if body {
                for _ in h[1]..=h[2] {
                    let l = lines.next().unwrap();
                    let mut x = [0.0; 3];
                    for (k, t) in l.split_whitespace().enumerate() {
                        assert!(t.contains('.'), "a coordinate without a point: {t}");
                        x[k] = t.parse().unwrap();
                    }
                    p.nodes.push(x);
                }
                assert_eq!(lines.next(), Some("))"));
            }
        } else if line.starts_with("(12 (") {
            let h: Vec<u64> = inner(line).iter().map(|t| hex(t)).collect();
            if h[0] == 0 {
                p.declared_cells = h[2];
            } else {
                assert!(!body || h[4] == 0, "a body only for mixed zones: {line}");
                if body {
                    for _ in h[1]..=h[2] {
                        hex(lines.next().unwrap());
                    }
                    assert_eq!(lines.next(), Some("))"));
                }
                p.cell_zones.push([h[0], h[1], h[2], h[3], h[4]]);
            }
        } else if line.starts_with("(13 (") {
            let h: Vec<u64> = inner(line).iter().map(|t| hex(t)).collect();
            if h[0] == 0 {
                p.declared_faces = h[2];
                continue;
            }
            let mut faces = Vec::new();
            for _ in h[1]..=h[2] {
                let mut v: Vec<u64> = lines.next().unwrap().split_whitespace().map(hex).collect();
                if h[4] == 0 {
                    let n = v.remove(0) as usize;
                    assert_eq!(v.len(), n + 2);
                } else {
                    assert_eq!(v.len() as u64, h[4] + 2);
                }
                let c1 = v.pop().unwrap();
                let c0 = v.pop().unwrap();
                faces.push((v, c0, c1));
            }
            assert_eq!(lines.next(), Some("))"));
            p.face_zones.push(([h[0], h[3], h[4]], faces));
        } else if line.starts_with("(45 (") {
            let w = inner(line);
            p.names.insert(w[0].parse().unwrap(), (w[1].clone(), w[2].clone()));
        }
    }
    p
}

fn write(mesh: &TaggedMesh, opts: &WriteOptions) -> (Parsed, Vec<String>) {
    let w = write_bytes(Format::Fluent, mesh, opts).unwrap_or_else(|e| panic!("{e}"));
    (parse(std::str::from_utf8(&w.main).unwrap()), w.report.dropped)
}

/// The twin: each cell's faces with Fluent's orientation (a polygon's right-hand
/// normal, or z x (n1 - n0) for an edge, points into c0) must close the cell (outward
/// area vectors sum to zero) and give it, by the divergence theorem, a positive
/// measure; returns the measures.
fn cell_measures(p: &Parsed) -> Vec<f64> {
    let ncells = p.declared_cells as usize;
    let mut closure = vec![[0.0f64; 3]; ncells];
    let mut measure = vec![0.0f64; ncells];
    for (_, faces) in &p.face_zones {
        for (nodes, c0, c1) in faces {
            let x: Vec<[f64; 3]> = nodes.iter().map(|&v| p.nodes[v as usize - 1]).collect();
            let n = x.len();
            let mut mid = [0.0; 3];
            for q in &x {
                for k in 0..3 {
                    mid[k] += q[k] / n as f64;
                }
            }
            // Area vector pointing into c0.
            let a = if n == 2 {
                [-(x[1][1] - x[0][1]), x[1][0] - x[0][0], 0.0]
            } else {
                let mut s = [0.0; 3];
                for i in 1..n - 1 {
                    let (u, v) = (sub(x[i], x[0]), sub(x[i + 1], x[0]));
                    let c = [
                        u[1] * v[2] - u[2] * v[1],
                        u[2] * v[0] - u[0] * v[2],
                        u[0] * v[1] - u[1] * v[0],
                    ];
                    for k in 0..3 {
                        s[k] += c[k] / 2.0;
                    }
                }
                s
            };
            let d = p.dim as f64;
            let flux = (mid[0] * a[0] + mid[1] * a[1] + mid[2] * a[2]) / d;
            assert!(*c0 >= 1, "c0 must be a cell");
            let c = *c0 as usize - 1;
            measure[c] -= flux;
            for k in 0..3 {
                closure[c][k] -= a[k];
            }
            if *c1 != 0 {
                let c = *c1 as usize - 1;
                measure[c] += flux;
                for k in 0..3 {
                    closure[c][k] += a[k];
                }
            }
        }
    }
    for (c, s) in closure.iter().enumerate() {
        assert!(s.iter().all(|v| v.abs() < 1e-12), "cell {c} is not closed: {s:?}");
        assert!(measure[c] > 0.0, "cell {c} has measure {} from its faces", measure[c]);
    }
    measure
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The face zones as (id, bc type, face count, name) and the cell zones' names.
fn zones(p: &Parsed) -> Vec<(String, String, usize)> {
    p.face_zones
        .iter()
        .map(|(h, faces)| {
            let (kind, name) = &p.names[&h[0]];
            assert_eq!(
                fluent::BC_TYPES.iter().find(|(n, _)| n == kind).map(|&(_, c)| c as u64),
                Some(h[1]),
                "{kind}"
            );
            (kind.clone(), name.clone(), faces.len())
        })
        .collect()
}

#[test]
fn a_2d_mesh_closes_every_cell_with_its_named_zones() {
    let (p, dropped) = write(&square(), &WriteOptions::default());
    assert_eq!(p.dim, 2);
    assert_eq!(p.nodes.len(), 9, "the unused point is left out");
    assert_eq!(p.declared_cells, 7);
    assert_eq!(p.cell_zones, vec![[2, 1, 7, 1, 0]], "quad + triangles: one mixed zone");
    assert_eq!(p.names[&2], ("fluid".to_string(), "Air".to_string()));
    let measures = cell_measures(&p);
    assert!((measures.iter().sum::<f64>() - 4.0).abs() < 1e-12, "{measures:?}");
    assert_eq!(
        zones(&p),
        vec![
            ("interior".into(), "default-interior".into(), 6),
            ("interior".into(), "Interface".into(), 1),
            ("velocity-inlet".into(), "Inlet".into(), 2),
            ("wall".into(), "Wall".into(), 2),
            ("wall".into(), "tag4".into(), 2),
            ("wall".into(), "defaultFaces".into(), 2),
        ]
    );
    assert_eq!(p.declared_faces, 15);
    let interior = &p.face_zones[0].1;
    assert!(interior.iter().all(|(_, c0, c1)| *c0 > 0 && *c1 > 0));
    assert!(p.face_zones[2..].iter().all(|(_, f)| f.iter().all(|(_, _, c1)| *c1 == 0)));
    for what in ["1 points no cell uses", "face tag 4 has no name", "zone `tag4`"] {
        assert!(dropped.iter().any(|d| d.contains(what)), "{what}: {dropped:?}");
    }
}

#[test]
fn a_3d_mesh_of_every_linear_kind_closes_every_cell() {
    let (p, dropped) = write(&blocks3d(), &WriteOptions::default());
    assert_eq!(p.dim, 3);
    assert_eq!(p.nodes.len(), 14);
    assert_eq!(p.cell_zones.len(), 2);
    // Tag 1: hexahedron + pyramid (mixed); tag 2: wedges + tetrahedron (mixed).
    assert_eq!(p.cell_zones[0], [2, 1, 2, 1, 0]);
    assert_eq!(p.cell_zones[1], [3, 3, 5, 1, 0]);
    let measures = cell_measures(&p);
    let expected = [1.0, 1.0 / 6.0, 0.5, 0.5, 1.0 / 12.0];
    for (m, e) in measures.iter().zip(expected) {
        assert!((m - e).abs() < 1e-12, "{measures:?}");
    }
    let z = zones(&p);
    assert_eq!(z[0].0, "interior");
    assert_eq!(z[1], ("interior".into(), "Interface".into(), 1));
    assert_eq!(z[2], ("wall".into(), "Floor".into(), 3));
    assert_eq!(p.face_zones[2].0[2], 0, "a quad and two triangles: a mixed face zone");
    assert_eq!(z[3], ("pressure-outlet".into(), "Outlet".into(), 1));
    assert_eq!(z[4].1, "defaultFaces");
    // 6 + 5 + 5 + 5 + 4 sides, the 4 inner ones counted twice.
    assert_eq!(p.declared_faces, 21);
    assert!(dropped.iter().any(|d| d.contains("zone `Floor`")), "{dropped:?}");
}

#[test]
fn indices_are_hexadecimal_and_name_records_decimal() {
    // 40 x 1 quads: 82 nodes (0x52), 40 cells (0x28); 12 named boundary segments, so
    // that zone ids pass 9.
    let mut m = TaggedMesh::new();
    for i in 0..=40 {
        m.points.push([i as f64, 0.0, 0.0]);
        m.points.push([i as f64, 1.0, 0.0]);
    }
    let mut quads = CellBlock::new(CellKind::Quad);
    let mut lines = CellBlock::new(CellKind::Line);
    for i in 0..40u32 {
        quads.push(&[2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1], 0, 0);
        if i < 12 {
            lines.push(&[2 * i, 2 * i + 2], i as i32 + 1, 1);
            m.tag_names.insert((1, i as i32 + 1), format!("wall {i}"));
        }
    }
    m.blocks.push(quads);
    m.blocks.push(lines);
    let w = write_bytes(Format::Fluent, &m, &WriteOptions::default()).unwrap();
    let text = std::str::from_utf8(&w.main).unwrap();
    assert!(text.contains("\n(10 (1 1 52 1 2)(\n"), "{text}");
    assert!(text.contains("\n(12 (2 1 28 1 3))\n"), "one quad zone, no body");
    assert!(text.contains("\n(13 (e "), "zone 14 in hexadecimal");
    assert!(text.contains("\n(45 (15 wall wall_11)())\n"), "decimal id, blank made `_`");
    let p = parse(text);
    assert_eq!(p.names.len(), 1 + 1 + 12 + 1);
    cell_measures(&p);
}

#[test]
fn zone_types_follow_the_name_map_and_the_user() {
    for (name, t) in [
        ("Airfoil", Some("wall")),
        ("cylinder_surface", Some("wall")),
        ("FarField", Some("pressure-far-field")),
        ("Inlet", Some("velocity-inlet")),
        ("PressureInlet", Some("pressure-inlet")),
        ("outflow", Some("pressure-outlet")),
        ("Symmetry", Some("symmetry")),
        ("LowerPeriodic1", None),
        ("Sides", None),
    ] {
        assert_eq!(fluent::bc_type(name), t, "{name}");
    }
    let mut opts = WriteOptions::default();
    opts.openfoam.patch_types.insert("Wall".into(), "symmetryPlane".into());
    opts.openfoam.patch_types.insert("Inlet".into(), "mass-flow-inlet".into());
    let (p, _) = write(&square(), &opts);
    let z = zones(&p);
    assert_eq!(z[2].0, "mass-flow-inlet");
    assert_eq!(z[3].0, "symmetry");
}

#[test]
fn what_fluent_cannot_hold_is_refused_or_reported() {
    let refused = |m: &TaggedMesh, what: &str| {
        let e = write_bytes(Format::Fluent, m, &WriteOptions::default()).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::CannotWrite { .. }), "{e}");
        assert!(e.to_string().contains(what), "{what}: {e}");
    };
    let mut lines_only = TaggedMesh::new();
    lines_only.points.extend([[0.0; 3], [1.0, 0.0, 0.0]]);
    lines_only.blocks.push(block(CellKind::Line, &[(&[0, 1], 1)]));
    refused(&lines_only, "needs surface (2D) or volume (3D) cells");
    let mut lifted = square();
    lifted.points[4][2] = 0.5;
    refused(&lifted, "z = 0 plane");
    let mut fin = square();
    fin.points.push([1.0, 1.0, 1.0]);
    fin.coordinate_dim = 3;
    let mut tris = CellBlock::new(CellKind::Tetra);
    for apex in [[0.5, 0.5, 1.0], [0.5, 0.5, -1.0], [0.7, 0.2, 1.0]] {
        fin.points.push(apex);
        let a = fin.points.len() as u32 - 1;
        tris.push(&[0, 1, 4, a], 0, 0);
    }
    fin.blocks.push(tris);
    refused(&fin, "shared by more than two cells");

    let mut extra = square();
    extra.point_data.insert("u".into(), smartmesh_formats::DataArray::new(1, vec![0.0; 10]));
    extra.blocks.push(block(CellKind::Line, &[(&[6, 8], 9)]));
    let (_, dropped) = write(&extra, &WriteOptions::default());
    for what in ["data `u`", "1 boundary cells on no cell's side"] {
        assert!(dropped.iter().any(|d| d.contains(what)), "{what}: {dropped:?}");
    }
}

#[test]
fn a_fluent_path_is_named_so_and_a_plain_msh_stays_gmsh() {
    assert_eq!(Format::from_path("case.fluent.msh"), Some(Format::Fluent));
    assert_eq!(Format::from_path("dir/CASE.Fluent.MSH"), Some(Format::Fluent));
    assert_eq!(Format::from_path("case.msh"), Some(Format::Gmsh));
    assert_eq!(Format::from_name("fluent"), Some(Format::Fluent));
    assert!(Format::Fluent.can_read());
}
