//! Gmsh itself (its Python API) reads the volume meshes smartmesh writes, and smartmesh
//! reads the volume meshes Gmsh writes.
//!
//! - One element of every volume and surface kind, linear and second order (the affine
//!   image of Gmsh's reference element, `gmsh3d_support`), written in 2.2 and 4.1,
//!   ASCII and binary: Gmsh finds the physical volumes and surfaces with their names,
//!   one element of each type, each node where the element's map puts Gmsh's own
//!   reference node (`getElementProperties`), and at every Gauss point a Jacobian
//!   determinant equal to the map's, so a volume equal to the one computed here.
//! - Gmsh meshes a model of hexahedra, prisms, tetrahedra and pyramids at order 2
//!   (complete and incomplete): smartmesh reads its counts, writes the mesh in the four
//!   encodings, and Gmsh reads back each element with the same nodes in the same order
//!   and the same volume.
//! - A tetrahedral model partitioned by Gmsh (4.1 and 2.2) reads as the unpartitioned
//!   mesh: the same cells per kind, physical and geometrical tag.

mod gmsh3d_support;

use std::collections::BTreeMap;

use gmsh3d_support as s3;
use smartmesh_formats::{
    gmsh, read_bytes_reported, CellKind, Format, GmshVersion, GmshWrite, ReadContext, TaggedMesh,
    WriteOptions,
};
use smartmesh_test_support::formats as common;

const ALL: [(GmshVersion, bool, &str); 4] = [
    (GmshVersion::V22, false, "v22_ascii"),
    (GmshVersion::V22, true, "v22_binary"),
    (GmshVersion::V41, false, "v41_ascii"),
    (GmshVersion::V41, true, "v41_binary"),
];

fn opts(version: GmshVersion, binary: bool) -> WriteOptions {
    WriteOptions { gmsh: GmshWrite { version, binary }, ..WriteOptions::default() }
}

/// For each file: its physical groups with names, its element count per type, Gmsh's
/// reference node coordinates of each type present, and for each element (by tag) its
/// type, node coordinates, and the volume (area) and smallest and largest Jacobian
/// determinant at the Gauss points of order 4.
const GMSH_ELEMENTS: &str = r#"
import sys, json, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
out = []
for path in sys.argv[1:]:
    gmsh.clear()
    gmsh.open(path)
    counts, refs, elements = {}, {}, {}
    ntags, coords, _ = gmsh.model.mesh.getNodes()
    xyz = {int(t): coords[3 * i:3 * i + 3].tolist() for i, t in enumerate(ntags)}
    types = sorted({int(t) for d in (2, 3) for t in gmsh.model.mesh.getElementTypes(d)})
    for t in types:
        name, dim, order, nn, local, _ = gmsh.model.mesh.getElementProperties(t)
        refs[str(t)] = [list(local[i * dim:(i + 1) * dim]) for i in range(nn)]
        etags, enodes = gmsh.model.mesh.getElementsByType(t)
        counts[str(t)] = len(etags)
        pts, w = gmsh.model.mesh.getIntegrationPoints(t, "Gauss4")
        _, det, _ = gmsh.model.mesh.getJacobians(t, pts)
        ng = len(w)
        for i, e in enumerate(etags):
            d = det[i * ng:(i + 1) * ng]
            elements[str(int(e))] = {
                "type": t,
                "nodes": [xyz[int(n)] for n in enodes[i * nn:(i + 1) * nn]],
                "volume": float(sum(a * b for a, b in zip(w, d))),
                "det": [float(min(d)), float(max(d))],
            }
    out.append({
        "groups": sorted([d, t, gmsh.model.getPhysicalName(d, t)] for d, t in gmsh.model.getPhysicalGroups()),
        "counts": counts, "refs": refs, "elements": elements,
    })
print(json.dumps(out))
gmsh.finalize()
"#;

fn gmsh_elements(py: &str, paths: &[String]) -> Vec<serde_json::Value> {
    let args: Vec<&str> = paths.iter().map(String::as_str).collect();
    let out = common::run_python(py, GMSH_ELEMENTS, &args);
    match serde_json::from_str(out.lines().last().unwrap_or("")) {
        Ok(serde_json::Value::Array(v)) => v,
        _ => panic!("unexpected output:\n{out}"),
    }
}

fn xyz(v: &serde_json::Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [a[0].as_f64().unwrap(), a[1].as_f64().unwrap(), a[2].as_f64().unwrap()]
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1.0)
}

#[test]
fn gmsh_reads_every_3d_kind_smartmesh_writes_with_its_volume() {
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let (m, maps) = s3::every_kind();
    let mut paths = Vec::new();
    for (version, binary, enc) in ALL {
        let w = gmsh::write(&m, &opts(version, binary)).unwrap();
        assert!(w.report.dropped.is_empty(), "{enc}: {:?}", w.report.dropped);
        let p = dir.path().join(format!("every_kind.{enc}.msh"));
        std::fs::write(&p, &w.main).unwrap();
        paths.push(p.display().to_string());
    }
    let groups: Vec<serde_json::Value> =
        m.tag_names.iter().map(|(&(d, t), n)| serde_json::json!([d, t, n])).collect();
    let kinds: Vec<CellKind> = m.blocks.iter().map(|b| b.kind).collect();
    for (s, (_, _, enc)) in gmsh_elements(&py, &paths).iter().zip(ALL) {
        assert_eq!(s["groups"].as_array().unwrap(), &groups, "{enc}: physical groups");
        let counts: BTreeMap<String, u64> = serde_json::from_value(s["counts"].clone()).unwrap();
        let want: BTreeMap<String, u64> =
            kinds.iter().map(|k| (k.gmsh_type().to_string(), 1)).collect();
        assert_eq!(counts, want, "{enc}: elements per type");
        for &k in &kinds {
            // The test's reference table is Gmsh's.
            let refs = s["refs"][k.gmsh_type().to_string()].as_array().unwrap();
            let ours = s3::reference(k);
            assert_eq!(refs.len(), ours.len(), "{enc}: {}", k.name());
            for (r, o) in refs.iter().zip(&ours) {
                let r: Vec<f64> =
                    r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
                assert_eq!(r[..], o[..r.len()], "{enc}: {} reference node", k.name());
            }
        }
        // Element tag t is cell t − 1: its nodes where its map puts Gmsh's reference
        // nodes, its Jacobian the map's.
        for (i, (k, _, _, _)) in m.cells().enumerate() {
            let e = &s["elements"][(i + 1).to_string()];
            let what = format!("{enc}: {} (element {})", k.name(), i + 1);
            assert_eq!(e["type"].as_i64(), Some(k.gmsh_type() as i64), "{what}");
            let map = maps[i];
            for (j, (node, r)) in
                e["nodes"].as_array().unwrap().iter().zip(s3::reference(k)).enumerate()
            {
                let (got, want) = (xyz(node), map.apply(r));
                assert!(
                    got.iter().zip(&want).all(|(a, b)| close(*a, *b, 1e-14)),
                    "{what}: node {j} at {got:?}, its map puts it at {want:?}"
                );
            }
            if k.dim() == 3 {
                let det = map.det();
                let (lo, hi) = (e["det"][0].as_f64().unwrap(), e["det"][1].as_f64().unwrap());
                assert!(
                    close(lo, det, 1e-12) && close(hi, det, 1e-12),
                    "{what}: det {lo}..{hi} vs {det}"
                );
                let v = e["volume"].as_f64().unwrap();
                let corners = s3::corner_volume(k, &s3::points_of(&m, m.cells().nth(i).unwrap().1));
                assert!(close(v, corners, 1e-12), "{what}: Gmsh's volume {v}, here {corners}");
                assert!(close(v, det * s3::reference_measure(k), 1e-12), "{what}");
            }
        }
    }
}

/// Makes, with Gmsh, the samples of the other tests in `argv[1]` from the scripts
/// `argv[2]` (hex_prism_pyr) and `argv[3]` (box_cyl): hex_prism_pyr at order 2
/// complete (4.1 binary) and incomplete (2.2 ASCII), and at order 1 with and without
/// parametric coordinates (`Mesh.SaveParametric`: u v w on volume nodes in 4.1);
/// box_cyl whole (4.1 ASCII) and partitioned in 3 (4.1 ASCII and 2.2 binary).
const GMSH_MAKE: &str = r#"
import sys, os, gmsh
out, hpp, box = sys.argv[1:4]
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
for incomplete, name, version, binary in [(0, "hpp_o2", 4.1, 1), (1, "hpp_o2i", 2.2, 0)]:
    gmsh.clear()
    gmsh.open(hpp)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", incomplete)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(2)
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", binary)
    gmsh.write(os.path.join(out, name + ".msh"))
gmsh.clear()
gmsh.open(hpp)
gmsh.model.mesh.generate(3)
gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 0)
for version, binary, name in [(4.1, 1, "hpp.msh"), (4.1, 0, "hpp_par.v41.msh"), (2.2, 1, "hpp_par.v22.msh")]:
    gmsh.option.setNumber("Mesh.SaveParametric", 0 if name == "hpp.msh" else 1)
    gmsh.option.setNumber("Mesh.MshFileVersion", version)
    gmsh.option.setNumber("Mesh.Binary", binary)
    gmsh.write(os.path.join(out, name))
gmsh.option.setNumber("Mesh.SaveParametric", 0)
gmsh.clear()
gmsh.open(box)
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.17)
gmsh.model.mesh.generate(3)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.option.setNumber("Mesh.Binary", 0)
gmsh.write(os.path.join(out, "box.msh"))
gmsh.model.mesh.partition(3)
gmsh.write(os.path.join(out, "box_part.v41.msh"))
gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.write(os.path.join(out, "box_part.v22.msh"))
gmsh.finalize()
print("ok")
"#;

fn read_path(p: &std::path::Path) -> TaggedMesh {
    smartmesh_formats::read_path(p, None).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn smartmesh_reads_and_rewrites_gmsh_second_order_and_partitioned_volume_meshes() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["gmsh"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let hpp = common::public_fixture("3d/hex_prism_pyr.geo_unrolled");
    let boxg = common::public_fixture("3d/box_cyl.geo_unrolled");
    let args = [d.display().to_string(), hpp.display().to_string(), boxg.display().to_string()];
    common::run_python(&py, GMSH_MAKE, &args.iter().map(String::as_str).collect::<Vec<_>>());

    // Second order: what Gmsh counts, we read; what we write, Gmsh reads element by
    // element as it wrote it.
    for (name, kinds) in [
        ("hpp_o2", [CellKind::Hexa27, CellKind::Wedge18, CellKind::Pyramid14, CellKind::Tetra10]),
        ("hpp_o2i", [CellKind::Hexa20, CellKind::Wedge15, CellKind::Pyramid13, CellKind::Tetra10]),
    ] {
        let orig = d.join(format!("{name}.msh"));
        let m = read_path(&orig);
        // The element counts of the fixture's description, at order 2.
        for (k, n) in kinds.iter().zip([27, 54, 9, 152]) {
            assert_eq!(m.num_cells_of(*k), n, "{name}: {}", k.name());
        }
        let mut paths = vec![orig.display().to_string()];
        for (version, binary, enc) in ALL {
            let w = gmsh::write(&m, &opts(version, binary)).unwrap();
            let p = d.join(format!("{name}.ours.{enc}.msh"));
            std::fs::write(&p, &w.main).unwrap();
            paths.push(p.display().to_string());
        }
        let s = gmsh_elements(&py, &paths);
        let theirs = &s[0];
        for (ours, enc) in s[1..].iter().zip(ALL.map(|a| a.2)) {
            let what = format!("{name} written as {enc}");
            assert_eq!(ours["groups"], theirs["groups"], "{what}: groups");
            assert_eq!(ours["counts"], theirs["counts"], "{what}: counts");
            // Elements are numbered alike (Gmsh's tags are 1..n, read in tag order).
            let (a, b) =
                (theirs["elements"].as_object().unwrap(), ours["elements"].as_object().unwrap());
            assert_eq!(a.len(), b.len(), "{what}");
            for (tag, e) in a {
                let f = &b[tag];
                assert_eq!(e["type"], f["type"], "{what}: element {tag}");
                assert_eq!(e["nodes"], f["nodes"], "{what}: element {tag}: nodes");
                let (u, v) = (e["volume"].as_f64().unwrap(), f["volume"].as_f64().unwrap());
                assert!(close(u, v, 1e-13), "{what}: element {tag}: volume {u} vs {v}");
            }
        }
        // The model's volumes (plane faces: the corners give them): 1, 1 and 0.6 (the
        // script names its groups only: Gmsh numbers them in their order).
        let mut per_group = BTreeMap::new();
        for (k, cell, p, _) in m.cells().filter(|c| c.0.dim() == 3) {
            let group = m.tag_name(3, p).unwrap_or("?").to_string();
            *per_group.entry(group).or_insert(0.0) +=
                s3::corner_volume(k, &s3::points_of(&m, cell));
        }
        let want: BTreeMap<String, f64> = [("Hexa", 1.0), ("Prisms", 1.0), ("TetPyr", 0.6)]
            .map(|(n, v)| (n.to_string(), v))
            .into();
        assert_eq!(per_group.keys().collect::<Vec<_>>(), want.keys().collect::<Vec<_>>(), "{name}");
        for (g, v) in &per_group {
            assert!(close(*v, want[g], 1e-12), "{name}: volume of {g} = {v}");
        }
    }

    // Parametric coordinates (three on volume nodes) are read past: the same mesh.
    let plain = read_path(&d.join("hpp.msh"));
    assert_eq!(plain.num_cells_of(CellKind::Pyramid), 9);
    for file in ["hpp_par.v41.msh", "hpp_par.v22.msh"] {
        let m = read_path(&d.join(file));
        // Gmsh writes ASCII coordinates to 16 digits, binary ones exactly.
        assert_eq!(m.points.len(), plain.points.len(), "{file}");
        for (p, q) in m.points.iter().zip(&plain.points) {
            assert!(p.iter().zip(q).all(|(a, b)| close(*a, *b, 1e-15)), "{file}: {p:?} {q:?}");
        }
        // Gmsh numbers 2.2 elements by type, 4.1 ones by entity: the same cells sorted.
        let cells = |m: &TaggedMesh| {
            let mut c: Vec<_> = m.cells().map(|(k, n, p, _)| (k, n.to_vec(), p)).collect();
            c.sort();
            c
        };
        assert!(cells(&m) == cells(&plain), "{file}: cells");
    }

    // Partitioned: the cells of the whole mesh, per kind, physical and geometrical tag.
    let fingerprint = |m: &TaggedMesh| {
        let mut c: BTreeMap<(CellKind, i32, i32), usize> = BTreeMap::new();
        for (k, _, p, g) in m.cells() {
            *c.entry((k, p, g)).or_insert(0) += 1;
        }
        c
    };
    let whole = read_path(&d.join("box.msh"));
    assert!(whole.num_cells_of(CellKind::Tetra) > 2000);
    for file in ["box_part.v41.msh", "box_part.v22.msh"] {
        let bytes = std::fs::read(d.join(file)).unwrap();
        let (m, report) =
            read_bytes_reported(Format::Gmsh, &bytes, &ReadContext::alone("msh")).unwrap();
        assert_eq!(fingerprint(&m), fingerprint(&whole), "{file}");
        assert_eq!(m.tag_names, whole.tag_names, "{file}");
        assert!(
            report.notes.iter().any(|n| n.contains("3 partitions")),
            "{file}: {:?}",
            report.notes
        );
    }
}

/// For each file: Gmsh's views (name, type, components, tags, values of the first step)
/// and meshio's cells per type and point data names.
const VIEWS_AND_MESHIO: &str = r#"
import sys, json, gmsh, meshio
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
out = []
for path in sys.argv[1:]:
    gmsh.clear()
    gmsh.open(path)
    views = []
    for v in gmsh.view.getTags():
        name = gmsh.option.getString("View[%d].Name" % gmsh.view.getIndex(v))
        dtype, tags, data, _, ncomp = gmsh.view.getModelData(v, 0)
        views.append([name, dtype, int(ncomp), [int(t) for t in tags], [[float(x) for x in d] for d in data]])
        gmsh.view.remove(v)
    try:
        m = meshio.read(path)
    except ValueError as e:
        out.append({"views": views, "meshio_error": str(e)})
        continue
    cells = {}
    for b in m.cells:
        cells[b.type] = cells.get(b.type, 0) + len(b.data)
    out.append({"views": views, "meshio_cells": cells,
                "meshio_point_data": sorted(k for k in m.point_data if not k.startswith("gmsh:"))})
print(json.dumps(out))
gmsh.finalize()
"#;

#[test]
fn gmsh_reads_node_and_element_data_on_3d_meshes_and_meshio_their_cells() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["gmsh", "meshio"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    for (file, cells) in [
        ("box_cyl.v41_binary.msh", vec![("line", 16), ("tetra", 2187), ("triangle", 1012)]),
        (
            "hex_prism_pyr.v22_ascii.msh",
            vec![
                ("hexahedron", 27),
                ("pyramid", 9),
                ("quad", 81),
                ("tetra", 152),
                ("triangle", 126),
                ("wedge", 54),
            ],
        ),
    ] {
        let mut m = common::read_file(&format!("3d/{file}"));
        let f: Vec<f64> = m.points.iter().map(|p| p[0] + 2.0 * p[1] + 3.0 * p[2]).collect();
        m.point_data.insert("f".into(), smartmesh_formats::DataArray::new(1, f.clone()));
        let c: Vec<f64> = (0..m.num_cells()).map(|i| 0.5 * i as f64).collect();
        m.cell_data.insert("cell_id".into(), smartmesh_formats::DataArray::new(1, c.clone()));
        let mut paths = Vec::new();
        for (version, binary, enc) in ALL {
            let w = gmsh::write(&m, &opts(version, binary)).unwrap();
            let p = dir.path().join(format!("{file}.{enc}.msh"));
            std::fs::write(&p, &w.main).unwrap();
            paths.push(p.display().to_string());
        }
        let args: Vec<&str> = paths.iter().map(String::as_str).collect();
        let out = common::run_python(&py, VIEWS_AND_MESHIO, &args);
        let s: Vec<serde_json::Value> =
            serde_json::from_str(out.lines().last().unwrap_or("")).expect("json");
        let want_cells: BTreeMap<String, u64> =
            cells.iter().map(|&(k, n)| (k.to_string(), n)).collect();
        for (r, (_, _, enc)) in s.iter().zip(ALL) {
            let what = format!("{file} as {enc}");
            if enc.starts_with("v22") {
                // meshio 5.3.5 splits 2.2 cells by entity but not their `$ElementData`:
                // it refuses Gmsh's own 2.2 file of box_cyl with an element view alike.
                let e = r["meshio_error"].as_str().unwrap_or_default();
                assert!(e.contains("Incompatible cell data"), "{what}: {r}");
            } else {
                let got: BTreeMap<String, u64> =
                    serde_json::from_value(r["meshio_cells"].clone()).unwrap();
                assert_eq!(got, want_cells, "{what}: meshio's cells");
                assert_eq!(r["meshio_point_data"], serde_json::json!(["f"]), "{what}");
            }
            let views = r["views"].as_array().unwrap();
            assert_eq!(views.len(), 2, "{what}: {views:?}");
            for v in views {
                let (name, dtype) = (v[0].as_str().unwrap(), v[1].as_str().unwrap());
                let (want, kind) = if name == "f" { (&f, "NodeData") } else { (&c, "ElementData") };
                assert_eq!(dtype, kind, "{what}: {name}");
                let tags = v[3].as_array().unwrap();
                assert_eq!(tags.len(), want.len(), "{what}: {name}: every item");
                // Tag t is item t − 1 (nodes and elements are numbered in mesh order).
                for (t, x) in tags.iter().zip(v[4].as_array().unwrap()) {
                    let (t, x) = (t.as_u64().unwrap() as usize, x[0].as_f64().unwrap());
                    // To an ulp: serde_json's default float parsing is not exact.
                    assert!(close(x, want[t - 1], 4e-16), "{what}: {name} at tag {t}: {x}");
                }
            }
        }
    }
}
