//! `smartmesh report --cut`: the planar cut of a tetrahedral box drawn as a planar mesh.
//! The picture parses, its area is the box's section, the surfaces' traces are the
//! legend's named curves, the ellipses are those of the 3D metric restricted to the
//! plane (sizes worked by hand, true size in pixels), the PNG is a picture, and bad
//! planes exit 2 with a clear message.

use std::path::{Path, PathBuf};

use smartmesh::formats::{write_path, TaggedMesh, WriteOptions};
use smartmesh::metric::Sym3;
use smartmesh::{MetricField, MetricTarget};
use smartmesh_test_support::grid::kuhn_box;

#[path = "support/cli.rs"]
mod cli;
use cli::{run, stderr, stdout};

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// The box [0, 2] × [0, 1] × [0, 3] (4 cubes a side), volume "Box", its sides named.
fn named_box() -> TaggedMesh {
    let mut mesh = kuhn_box(4, [2.0, 1.0, 3.0]);
    mesh.tag_names.insert((3, 1), "Box".into());
    for (tag, name) in [(11, "West"), (12, "East"), (13, "South"), (14, "North")] {
        mesh.tag_names.insert((2, tag), name.into());
    }
    for (tag, name) in [(15, "Floor"), (16, "Roof")] {
        mesh.tag_names.insert((2, tag), name.into());
    }
    mesh
}

/// Sizes (0.05, 0.2, 0.1) along x, y, z, all scaled by 2^y: along any edge log h is
/// linear in y, so the Log-Euclidean mean at a crossing of the plane y = c is the
/// metric of sizes (0.05, 0.2, 0.1) · 2^c exactly.
fn metric_at(p: [f64; 3]) -> Sym3 {
    let k = 2f64.powf(p[1]);
    let h = [0.05 * k, 0.2 * k, 0.1 * k];
    Sym3::diagonal(h.map(|h| 1.0 / (h * h)))
}

fn write_case(dir: &Path) -> (PathBuf, PathBuf) {
    let mesh = named_box();
    let path = dir.join("box.msh");
    write_path(&path, &mesh, None, &WriteOptions::default()).unwrap();
    let sol = dir.join("box.sol");
    let field = MetricField::new(mesh.points.iter().map(|&p| metric_at(p)).collect(), "test");
    field
        .write(&sol, &mesh, MetricTarget::from_path(&sol).unwrap(), &WriteOptions::default())
        .unwrap();
    (path, sol)
}

fn by_id<'a>(doc: &'a roxmltree::Document<'a>, id: &str) -> Option<roxmltree::Node<'a, 'a>> {
    doc.descendants().find(|n| n.attribute("id") == Some(id))
}

fn has_class(n: &roxmltree::Node<'_, '_>, class: &str) -> bool {
    n.attribute("class").is_some_and(|c| c.split(' ').any(|x| x == class))
}

fn attr(n: &roxmltree::Node<'_, '_>, name: &str) -> f64 {
    n.attribute(name).unwrap_or_else(|| panic!("no {name}")).parse().unwrap()
}

#[test]
fn cut_of_a_box_is_its_section_with_named_traces_and_restricted_ellipses() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, sol) = write_case(dir.path());
    let c = 0.3;
    let out = dir.path().join("cut.svg");
    let o = run(&[
        "report",
        s(&mesh),
        "--metric",
        s(&sol),
        "--cut",
        &format!("y={c}"),
        "-o",
        s(&out),
        "--json",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let cut = &json["report"]["cut"];
    assert!((cut["area"].as_f64().unwrap() - 6.0).abs() < 1e-12, "{cut}");
    assert_eq!(cut["axes"], serde_json::json!(["x", "z"]));
    assert_eq!(cut["ellipses"], "restriction");
    assert_eq!(cut["counts"]["tetrahedra"], 6 * 64);
    assert!(json["report"]["conformity"].is_null());

    let text = std::fs::read_to_string(&out).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    for id in ["title", "overview", "legend", "zoom-1"] {
        assert!(by_id(&doc, id).is_some(), "panel {id} missing");
    }
    assert!(by_id(&doc, "hist-length").is_none(), "no conformity charts on a cut");
    let title: Vec<&str> =
        by_id(&doc, "title").unwrap().descendants().filter_map(|n| n.text()).collect();
    assert!(title.iter().any(|t| t.contains("restricted to the plane")), "{title:?}");
    assert!(title.iter().any(|t| t.contains("not its projection")), "{title:?}");

    // The surfaces met by the plane are the legend's curves, by name; the volume its face.
    let legend: Vec<&str> = by_id(&doc, "legend")
        .unwrap()
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .collect();
    for entry in ["volume 1 Box", "surface 11 West", "surface 12 East", "surface 15 Floor"] {
        assert!(legend.contains(&entry), "legend {legend:?} lacks {entry}");
    }
    assert!(!legend.iter().any(|l| l.contains("South") || l.contains("untagged")), "{legend:?}");
    let overview = by_id(&doc, "overview").unwrap();
    let curves = overview.descendants().filter(|n| has_class(n, "curve")).count();
    assert_eq!(curves, 4, "the four walls the plane crosses");

    // Every ellipse: semi-axes 0.05 · 2^c along x (horizontal, angle 0) and 0.1 · 2^c
    // along z, times the group's scale (true size or the factor it says).
    let k = 2f64.powf(c);
    let mut seen = 0;
    for group in doc.descendants().filter(|n| has_class(n, "ellipses")) {
        let scale = attr(&group, "data-scale");
        for e in group.children().filter(|n| n.has_tag_name("ellipse")) {
            let (rx, ry) = (attr(&e, "rx"), attr(&e, "ry"));
            let angle: f64 = e.attribute("transform").unwrap()["rotate(".len()..]
                .split(' ')
                .next()
                .unwrap()
                .parse()
                .unwrap();
            let (along_x, along_z) = if angle.abs() < 1e-6 || (angle.abs() - 180.0).abs() < 1e-6 {
                (rx, ry)
            } else {
                assert!((angle.abs() - 90.0).abs() < 1e-6, "angle {angle}");
                (ry, rx)
            };
            assert!((along_x - 0.05 * k * scale).abs() < 2e-3, "{along_x} vs {}", 0.05 * k * scale);
            assert!((along_z - 0.1 * k * scale).abs() < 2e-3, "{along_z} vs {}", 0.1 * k * scale);
            seen += 1;
        }
    }
    assert!(seen > 20, "{seen} ellipses");

    // The PNG is the same picture, rasterised.
    let png = dir.path().join("cut.png");
    let o = run(&["report", s(&mesh), "--metric", s(&sol), "--cut", "y=0.3", "-o", s(&png)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mut decoder = png::Decoder::new(std::fs::File::open(&png).unwrap());
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.width, 1200);
    let px: Vec<&[u8]> = buf[..info.buffer_size()].chunks(info.color_type.samples()).collect();
    let drawn = px.iter().filter(|p| p[..3] != [255, 255, 255]).count();
    assert!(drawn * 5 > px.len(), "only {drawn} of {} pixels drawn", px.len());
}

#[test]
fn a_grid_plane_keeps_each_face_once() {
    // y = 0.5 holds faces of the tetrahedra (shared by the two layers around it): the
    // area is still the section's, not twice it.
    let dir = tempfile::tempdir().unwrap();
    let (mesh, _) = write_case(dir.path());
    let out = dir.path().join("grid.svg");
    let o = run(&["report", s(&mesh), "--cut", "y=0.5", "-o", s(&out), "--json"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let json: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let cut = &json["report"]["cut"];
    assert!((cut["area"].as_f64().unwrap() - 6.0).abs() < 1e-12, "{cut}");
    assert_eq!(cut["counts"]["faces_in_plane"], 2 * 16, "{cut}");
    assert_eq!(cut["counts"]["quads"], 0, "{cut}");
    assert!(cut.get("ellipses").is_none(), "no metric given: {cut}");
}

#[test]
fn bad_planes_exit_two_and_say_why() {
    let dir = tempfile::tempdir().unwrap();
    let (mesh, _) = write_case(dir.path());
    let out = dir.path().join("x.svg");
    for (cut, expected) in [
        ("z=7", "cuts no tetrahedron: their z runs over [0, 3]"),
        ("w=1", "unknown axis"),
        ("z=abc", "no finite number"),
    ] {
        let o = run(&["report", s(&mesh), "--cut", cut, "-o", s(&out)]);
        assert_eq!(o.status.code(), Some(2), "{cut}");
        assert!(stderr(&o).contains(expected), "{cut}: {}", stderr(&o));
        assert!(!out.exists(), "{cut}: no picture written");
    }
    // A planar mesh has nothing to cut.
    let mut flat = TaggedMesh::new();
    flat.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let mut b = smartmesh::formats::CellBlock::new(smartmesh::formats::CellKind::Triangle);
    b.push(&[0, 1, 2], 1, 1);
    flat.blocks.push(b);
    let tri = dir.path().join("tri.msh");
    write_path(&tri, &flat, None, &WriteOptions::default()).unwrap();
    let o = run(&["report", s(&tri), "--cut", "z=0", "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no tetrahedron to cut"), "{}", stderr(&o));
}
