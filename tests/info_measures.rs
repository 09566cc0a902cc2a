//! What `info` measures: triangle quality over the mesh's own triangles (the halves of
//! a quad are not triangles of the mesh), a surface in space measured in each
//! triangle's own plane, and the skin's layers only where quads stand beside triangles.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;

use cli::{ok, smartmesh};

/// A legacy VTK file of `points` and `cells` (VTK type, nodes).
fn vtk(points: &[[f64; 3]], cells: &[(u8, &[usize])]) -> String {
    let mut s =
        String::from("# vtk DataFile Version 4.2\ninfo test\nASCII\nDATASET UNSTRUCTURED_GRID\n");
    s += &format!("POINTS {} double\n", points.len());
    for p in points {
        s += &format!("{} {} {}\n", p[0], p[1], p[2]);
    }
    let size: usize = cells.iter().map(|c| c.1.len() + 1).sum();
    s += &format!("CELLS {} {size}\n", cells.len());
    for (_, nodes) in cells {
        let list: Vec<String> = nodes.iter().map(|v| v.to_string()).collect();
        s += &format!("{} {}\n", nodes.len(), list.join(" "));
    }
    s += &format!("CELL_TYPES {}\n", cells.len());
    for (t, _) in cells {
        s += &format!("{t}\n");
    }
    s
}

fn info_json(dir: &std::path::Path, text: &str) -> (serde_json::Value, String) {
    let f = dir.join("m.vtk");
    std::fs::write(&f, text).unwrap();
    let f = f.to_str().unwrap();
    let json = serde_json::from_str(&ok(&smartmesh(&["info", "--json", f], None))).unwrap();
    (json, ok(&smartmesh(&["info", f], None)))
}

/// An equilateral triangle and, apart, a quad ten times longer than wide: the triangle
/// quality is the triangle's (min angle 60°), not that of the quad's halves (5.7°).
#[test]
fn the_halves_of_a_quad_are_not_measured_as_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let h = 3f64.sqrt() / 2.0;
    let points = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.5, h, 0.0],
        [2.0, 0.0, 0.0],
        [12.0, 0.0, 0.0],
        [12.0, 1.0, 0.0],
        [2.0, 1.0, 0.0],
    ];
    let (j, text) = info_json(dir.path(), &vtk(&points, &[(5, &[0, 1, 2]), (9, &[3, 4, 5, 6])]));
    let q = &j["quality"];
    assert_eq!(q["triangles"], 1, "{j}");
    assert!((q["min_angle_deg"].as_f64().unwrap() - 60.0).abs() < 1e-9, "{j}");
    assert!((q["min_quality"].as_f64().unwrap() - 1.0).abs() < 1e-12, "{j}");
    assert_eq!(j["quads"]["quality"]["quads"], 1, "{j}");
    assert!(
        text.contains("quality     1 triangle:") && text.contains("min angle 60.00 deg"),
        "{text}"
    );
}

/// A 3x3 grid of quads has no skin: no "layers from the walls", no triangle figures.
#[test]
fn a_mesh_of_quads_alone_has_no_layers() {
    let dir = tempfile::tempdir().unwrap();
    let mut points = Vec::new();
    for j in 0..4 {
        for i in 0..4 {
            points.push([i as f64, j as f64, 0.0]);
        }
    }
    let quads: Vec<[usize; 4]> = (0..3)
        .flat_map(|j| (0..3).map(move |i| [j * 4 + i, j * 4 + i + 1, j * 4 + i + 5, j * 4 + i + 4]))
        .collect();
    let cells: Vec<(u8, &[usize])> = quads.iter().map(|q| (9, &q[..])).collect();
    let (j, text) = info_json(dir.path(), &vtk(&points, &cells));
    assert!(text.contains("quads       9:"), "{text}");
    assert!(!text.contains("layers"), "{text}");
    assert!(!text.contains("triangles:"), "{text}");
    assert_eq!(j["quads"]["quality"]["layers"], serde_json::json!([]), "{j}");
    assert!(j["quality"].is_null(), "{j}");
}

/// An L-shaped fold: a unit square in the xy-plane and one in the xz-plane, two right
/// triangles each. In each triangle's own plane none is flat, every angle is 45° or 90°
/// and the area is 2 (in the xy-plane the second square would be flat, of area 0).
#[test]
fn a_surface_in_space_is_measured_in_each_triangles_own_plane() {
    let dir = tempfile::tempdir().unwrap();
    let points = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 1.0],
        [0.0, 0.0, 1.0],
    ];
    let cells: [(u8, &[usize]); 4] =
        [(5, &[0, 1, 2]), (5, &[0, 2, 3]), (5, &[0, 5, 4]), (5, &[0, 4, 1])];
    let (j, text) = info_json(dir.path(), &vtk(&points, &cells));
    let q = &j["quality"];
    assert_eq!(q["triangles"], 4, "{j}");
    assert_eq!(q["inverted_or_flat"], 0, "{j}");
    assert!((q["min_angle_deg"].as_f64().unwrap() - 45.0).abs() < 1e-9, "{j}");
    assert!((q["area_range"][0].as_f64().unwrap() - 0.5).abs() < 1e-12, "{j}");
    let area: f64 = j["topology"]["faces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["area"].as_f64().unwrap())
        .sum();
    assert!((area - 2.0).abs() < 1e-12, "{j}");
    assert!(text.contains("0 inverted or flat"), "{text}");
}
