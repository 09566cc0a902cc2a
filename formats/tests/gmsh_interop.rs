//! Gmsh itself (its Python API) and meshio read what smartmesh writes.
//!
//! The oracle for Gmsh is Gmsh's own reading of the public fixture of the same model
//! and version: the file smartmesh writes must give Gmsh the same physical groups
//! (dimension, tag, name), the same number of entities of each dimension, the same
//! node count and the same element count of each type. Every file smartmesh writes is
//! read by meshio as a whole, and saved again by Gmsh without losing an element.

use smartmesh_formats::GmshWrite;
use smartmesh_test_support::formats as common;

use smartmesh_formats::{
    gmsh, sym2_to_tensor9, CellBlock, CellKind, DataArray, GmshVersion, TaggedMesh, WriteOptions,
};

const GMSH_SUMMARY: &str = r#"
import sys, json, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
out = []
for path in sys.argv[1:]:
    gmsh.clear()
    gmsh.open(path)
    ents = gmsh.model.getEntities()
    tags, _, _ = gmsh.model.mesh.getNodes()
    counts = {}
    for d, t in ents:
        types, etags, _ = gmsh.model.mesh.getElements(d, t)
        for ty, e in zip(types, etags):
            counts[str(int(ty))] = counts.get(str(int(ty)), 0) + len(e)
    views = []
    for v in gmsh.view.getTags():
        name = gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(v))
        dtype, vtags, data, time, ncomp = gmsh.view.getModelData(v, 0)
        views.append([name, dtype, int(ncomp), len(vtags)])
    out.append({
        "groups": sorted([d, t, gmsh.model.getPhysicalName(d, t)] for d, t in gmsh.model.getPhysicalGroups()),
        "entities": [sum(1 for d, _ in ents if d == k) for k in range(4)],
        "nodes": len(tags),
        "elements": counts,
        "views": views,
    })
    for v in gmsh.view.getTags():
        gmsh.view.remove(v)
print(json.dumps(out))
gmsh.finalize()
"#;

const MESHIO_SUMMARY: &str = r#"
import sys, json, meshio
out = []
for path in sys.argv[1:]:
    m = meshio.read(path)
    cells = {}
    for b in m.cells:
        cells[b.type] = cells.get(b.type, 0) + len(b.data)
    out.append({"points": len(m.points), "cells": cells, "point_data": sorted([k, list(v.shape)] for k, v in m.point_data.items() if not k.startswith("gmsh:"))})
print(json.dumps(out))
"#;

fn with_metric(mut m: TaggedMesh) -> TaggedMesh {
    let v: Vec<f64> = m
        .points
        .iter()
        .flat_map(|p| sym2_to_tensor9(1.0 + p[0] * p[0], 0.1, 2.0 + p[1] * p[1], 1.0))
        .collect();
    m.point_data.insert("metric".into(), DataArray::new(9, v));
    m
}

fn summaries(py: &str, script: &str, paths: &[String]) -> Vec<serde_json::Value> {
    let args: Vec<&str> = paths.iter().map(String::as_str).collect();
    let out = common::run_python(py, script, &args);
    let last = out.lines().last().unwrap_or("");
    match serde_json::from_str(last) {
        Ok(serde_json::Value::Array(v)) => v,
        _ => panic!("unexpected output:\n{out}"),
    }
}

#[test]
fn gmsh_reads_what_smartmesh_writes() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    for model in ["naca0012", "square_hole"] {
        let src = with_metric(common::read_file(&format!("gmsh/{model}.v41_ascii.msh")));
        for (version, v) in [(GmshVersion::V22, "v22"), (GmshVersion::V41, "v41")] {
            for binary in [false, true] {
                let enc = if binary { "binary" } else { "ascii" };
                let opts =
                    WriteOptions { gmsh: GmshWrite { version, binary }, ..WriteOptions::default() };
                let written = gmsh::write(&src, &opts).unwrap();
                let path = dir.path().join(format!("{model}.{v}_{enc}.msh"));
                std::fs::write(&path, &written.main).unwrap();
                let fixture = common::public_fixture(&format!("gmsh/{model}.{v}_{enc}.msh"));
                let s = summaries(
                    &py,
                    GMSH_SUMMARY,
                    &[fixture.display().to_string(), path.display().to_string()],
                );
                let (theirs, ours) = (&s[0], &s[1]);
                let what = format!("{model} {v} {enc}");
                assert_eq!(ours["groups"], theirs["groups"], "{what}: physical groups");
                assert_eq!(ours["entities"], theirs["entities"], "{what}: entities per dimension");
                assert_eq!(ours["nodes"], theirs["nodes"], "{what}: nodes");
                assert_eq!(ours["elements"], theirs["elements"], "{what}: elements per type");
                // The metric: a 9-component node view over every node.
                let views = ours["views"].as_array().unwrap();
                assert_eq!(views.len(), 1, "{what}: {views:?}");
                assert_eq!(
                    views[0],
                    serde_json::json!(["metric", "NodeData", 9, src.points.len()]),
                    "{what}"
                );
            }
        }
    }
}

#[test]
fn gmsh_keeps_unused_nodes_and_split_entities() {
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    // A square of two triangles in two physical groups on one geometrical entity, and
    // a node no cell uses.
    let mut m = TaggedMesh::new();
    m.points =
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.5, 0.5, 0.0]];
    let mut t = smartmesh_formats::CellBlock::new(smartmesh_formats::CellKind::Triangle);
    t.push(&[0, 1, 2], 1, 1);
    t.push(&[0, 2, 3], 2, 1);
    m.blocks.push(t);
    m.tag_names.insert((2, 1), "A".into());
    m.tag_names.insert((2, 2), "B".into());
    let mut paths = Vec::new();
    for binary in [false, true] {
        let opts = WriteOptions {
            gmsh: GmshWrite { version: GmshVersion::V41, binary },
            ..WriteOptions::default()
        };
        let path = dir.path().join(format!("split{binary}.msh"));
        std::fs::write(&path, gmsh::write(&m, &opts).unwrap().main).unwrap();
        paths.push(path.display().to_string());
    }
    for s in summaries(&py, GMSH_SUMMARY, &paths) {
        assert_eq!(s["groups"], serde_json::json!([[2, 1, "A"], [2, 2, "B"]]));
        assert_eq!(s["entities"], serde_json::json!([0, 0, 2, 0]));
        assert_eq!(s["nodes"], 5);
        assert_eq!(s["elements"], serde_json::json!({"2": 2}));
    }
}

#[test]
fn meshio_reads_what_smartmesh_writes() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    for model in ["naca0012", "square_hole"] {
        let src = with_metric(common::read_file(&format!("gmsh/{model}.v41_ascii.msh")));
        let mut paths = Vec::new();
        for version in [GmshVersion::V22, GmshVersion::V41] {
            for binary in [false, true] {
                let opts =
                    WriteOptions { gmsh: GmshWrite { version, binary }, ..WriteOptions::default() };
                let path = dir.path().join(format!("{model}_{version:?}_{binary}.msh"));
                std::fs::write(&path, gmsh::write(&src, &opts).unwrap().main).unwrap();
                paths.push(path.display().to_string());
            }
        }
        let expected_cells: serde_json::Map<String, serde_json::Value> = [
            ("vertex", smartmesh_formats::CellKind::Vertex),
            ("line", smartmesh_formats::CellKind::Line),
            ("triangle", smartmesh_formats::CellKind::Triangle),
        ]
        .iter()
        .filter(|(_, k)| src.num_cells_of(*k) > 0)
        .map(|(n, k)| (n.to_string(), serde_json::json!(src.num_cells_of(*k))))
        .collect();
        for (path, s) in paths.iter().zip(summaries(&py, MESHIO_SUMMARY, &paths)) {
            assert_eq!(s["points"], src.points.len(), "{path}");
            assert_eq!(s["cells"], serde_json::Value::Object(expected_cells.clone()), "{path}");
            assert_eq!(
                s["point_data"],
                serde_json::json!([["metric", [src.points.len(), 9]]]),
                "{path}"
            );
        }
    }
}

/// Asserts that meshio reads all `cells` of each file and that Gmsh keeps every element
/// when it saves the file again.
fn assert_read_and_resaved(py: &str, files: &[(String, usize)]) {
    let paths: Vec<String> = files.iter().map(|(p, _)| p.clone()).collect();
    for ((path, cells), s) in files.iter().zip(summaries(py, common::READ_AND_RESAVE, &paths)) {
        assert_eq!(s["meshio"], *cells, "{path}: meshio");
        let total: u64 = s["before"].as_object().unwrap().values().filter_map(|v| v.as_u64()).sum();
        assert_eq!(total as usize, *cells, "{path}: Gmsh reads {}", s["before"]);
        assert_eq!(s["after"], s["before"], "{path}: Gmsh saved it again");
    }
}

/// Triangle's `A.1.ele` (boundary markers on its segments, no regional attribute) and a
/// mesh whose vertex and line cells are partly untagged, in each version and encoding:
/// meshio reads every cell ("Incompatible cell data 'gmsh:physical'" before) and Gmsh
/// saves every element again (it kept only those of physical groups).
#[test]
fn meshio_and_gmsh_read_meshes_with_untagged_cells_whole() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["gmsh", "meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let a = common::read_file("triangle/A.1.ele");
    let mut partly = TaggedMesh::new();
    partly.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut t = CellBlock::new(CellKind::Triangle);
    t.push(&[0, 1, 2], 1, 1);
    t.push(&[0, 2, 3], 1, 1);
    let mut l = CellBlock::new(CellKind::Line);
    l.push(&[0, 1], 0, 1);
    l.push(&[1, 2], 5, 2);
    let mut v = CellBlock::new(CellKind::Vertex);
    v.push(&[0], 0, 0);
    partly.blocks = vec![t, l, v];
    let mut files = Vec::new();
    for (name, mesh) in [("A", &a), ("partly", &partly)] {
        for (version, binary) in [
            (GmshVersion::V22, false),
            (GmshVersion::V22, true),
            (GmshVersion::V41, false),
            (GmshVersion::V41, true),
        ] {
            let opts =
                WriteOptions { gmsh: GmshWrite { version, binary }, ..WriteOptions::default() };
            let path = dir.path().join(format!("{name}_{version:?}_{binary}.msh"));
            std::fs::write(&path, gmsh::write(mesh, &opts).unwrap().main).unwrap();
            files.push((path.display().to_string(), mesh.num_cells()));
        }
    }
    assert_read_and_resaved(&py, &files);
}
