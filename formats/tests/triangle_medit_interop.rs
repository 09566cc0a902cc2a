//! The owners' tools read what smartmesh writes: PyPI `triangle` (Shewchuk's Triangle
//! compiled as a Python extension) loads and triangulates our .node/.ele/.poly, MMG's
//! `mmg2d_O3` (PyPI `mmgpy`) adapts our .mesh + .sol and .meshb + .solb, and meshio reads
//! our .mesh and .meshb. Each test skips when its Python modules are missing, unless
//! `SMARTMESH_REQUIRE_INTEROP=1` (CI), where it fails. Install with
//! `pip install triangle mmgpy meshio`.

use smartmesh_formats::GmshWrite;
use smartmesh_test_support::formats as common;

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Command;

use common::{counts_per_tag, public_fixture, python_with, read_file, run_python};
use smartmesh_formats::{read_path, write_path, CellKind, Format, TaggedMesh, WriteOptions};

fn write(mesh: &TaggedMesh, path: &Path) {
    let report =
        write_path(path, mesh, None, &WriteOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert!(report.dropped.is_empty(), "{}: {:?}", path.display(), report.dropped);
}

/// Parses the whitespace-separated numbers of one output line.
fn numbers(line: &str) -> Vec<f64> {
    line.split_whitespace()
        .map(|t| t.parse().unwrap_or_else(|_| panic!("not a number: {t}")))
        .collect()
}

// -----------------------------------------------------------------------------------------
// Triangle
// -----------------------------------------------------------------------------------------

/// Prints, one per line: vertices, vertex markers, triangles, segments, segment markers,
/// holes (flattened), then the number of triangles of a quality triangulation of the PSLG.
const TRIANGLE_LOAD: &str = r#"
import sys, triangle
d = triangle.load(sys.argv[1], sys.argv[2])
def flat(k):
    return " ".join(repr(float(v)) for v in d[k].ravel()) if k in d else ""
for k in ["vertices", "vertex_markers", "triangles", "segments", "segment_markers", "holes"]:
    print(flat(k))
pslg = {k: d[k] for k in ["vertices", "segments", "holes"] if k in d}
print(len(triangle.triangulate(pslg, "pqc")["triangles"]))
"#;

fn check_triangle_load(py: &str, dir: &Path, name: &str, m: &TaggedMesh) {
    let out = run_python(py, TRIANGLE_LOAD, &[dir.to_str().unwrap(), name]);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 7, "{out}");
    let xy: Vec<f64> = m.points.iter().flat_map(|p| [p[0], p[1]]).collect();
    // Bitwise: Python prints the shortest repr, which reads back exactly.
    assert_eq!(
        numbers(lines[0]).iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        xy.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
    if let Some(mk) = m.point_data.get("triangle:marker") {
        assert_eq!(numbers(lines[1]), mk.values);
    }
    let tri: Vec<f64> = m
        .blocks
        .iter()
        .filter(|b| b.kind == CellKind::Triangle)
        .flat_map(|b| b.nodes.iter().map(|&v| v as f64))
        .collect();
    assert_eq!(numbers(lines[2]), tri);
    let seg = m.blocks.iter().find(|b| b.kind == CellKind::Line).expect("segments");
    assert_eq!(numbers(lines[3]), seg.nodes.iter().map(|&v| v as f64).collect::<Vec<_>>());
    assert_eq!(numbers(lines[4]), seg.physical.iter().map(|&v| v as f64).collect::<Vec<_>>());
    assert_eq!(numbers(lines[5]), m.holes.iter().flat_map(|h| *h).collect::<Vec<_>>());
    let n: usize = lines[6].trim().parse().unwrap();
    assert!(n > 0, "Triangle made no triangles from our PSLG");
}

#[test]
fn triangle_loads_our_mesh_set() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["triangle"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    // Triangle's own output, read and written again by us as out.node + .ele + .poly.
    let m = read_file("triangle/double_hex.2.ele");
    write(&m, &dir.path().join("out.node"));
    assert!(dir.path().join("out.ele").exists() && dir.path().join("out.poly").exists());
    check_triangle_load(&py, dir.path(), "out", &m);
}

#[test]
fn triangle_loads_our_pslg() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["triangle"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = read_file("triangle/box.poly");
    write(&m, &dir.path().join("pslg.poly"));
    assert!(!dir.path().join("pslg.node").exists(), "a self-contained .poly");
    check_triangle_load(&py, dir.path(), "pslg", &m);
}

#[test]
fn triangle_refines_our_mesh_with_area_bounds() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["triangle"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = read_file("triangle/bbox.1.area");
    write(&m, &dir.path().join("b.ele"));
    // -r refines the given mesh, -a without a number reads the per-triangle bounds.
    let script = r#"
import sys, triangle
d = triangle.load(sys.argv[1], "b")
print(" ".join(repr(float(a)) for a in d["triangle_max_area"].ravel()))
t = triangle.triangulate({k: d[k] for k in ["vertices", "triangles", "triangle_max_area"]}, "ra")
print(len(t["triangles"]))
"#;
    let out = run_python(&py, script, &[dir.path().to_str().unwrap()]);
    let lines: Vec<&str> = out.lines().collect();
    let area: Vec<f64> = m.cell_data["triangle:area"].values.clone();
    assert_eq!(numbers(lines[0]), area);
    let n: usize = lines[1].trim().parse().unwrap();
    assert!(n > 12, "the 0.02 bound on one triangle should split it ({n} triangles)");
}

// -----------------------------------------------------------------------------------------
// MMG
// -----------------------------------------------------------------------------------------

fn run_mmg(exe: &str, input: &Path, sol: &Path, output: &Path) {
    let out = Command::new(exe)
        .arg("-in")
        .arg(input)
        .arg("-sol")
        .arg(sol)
        .arg("-out")
        .arg(output)
        .arg("-v")
        .arg("1")
        .output()
        .expect("run mmg2d_O3");
    assert!(
        out.status.success(),
        "mmg2d_O3 failed ({}):\n{}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

fn tags_of(m: &TaggedMesh, kind: CellKind) -> BTreeSet<i32> {
    m.cells().filter(|c| c.0 == kind).map(|c| c.2).collect()
}

#[test]
fn mmg2d_adapts_our_mesh_and_metric() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = common::mmg2d(&py);
    let input = read_file("medit/square_hole_input.mesh");
    assert!(input.point_data.contains_key("metric"));
    for (name, out_name) in [("in.mesh", "out.mesh"), ("in.meshb", "out.meshb")] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        write(&input, &path);
        // mmg2d_O3 looks for `in.sol` by default, even beside a .meshb: name the .solb.
        let sol = dir.path().join(if name.ends_with('b') { "in.solb" } else { "in.sol" });
        assert!(sol.exists());
        let out_path = dir.path().join(out_name);
        run_mmg(&exe, &path, &sol, &out_path);
        // MMG keeps our references: walls 1, hole 2, domain 3.
        let adapted = read_path(&out_path, None).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(tags_of(&adapted, CellKind::Line), BTreeSet::from([1, 2]), "{name}");
        assert_eq!(tags_of(&adapted, CellKind::Triangle), BTreeSet::from([3]), "{name}");
        // The metric was read: MMG 5.8 adapts this input to the 844 triangles of
        // square_hole_mmg (a default metric gives about 70).
        assert!(adapted.num_cells_of(CellKind::Triangle) > 500, "{name}");
        // And it wrote back a metric we read.
        assert_eq!(adapted.point_data["metric"].len(), adapted.points.len());
    }
}

// -----------------------------------------------------------------------------------------
// meshio
// -----------------------------------------------------------------------------------------

const MESHIO_READ: &str = r#"
import sys, meshio
m = meshio.read(sys.argv[1])
print(len(m.points))
for block, refs in zip(m.cells, m.cell_data["medit:ref"]):
    print(block.type, len(block.data), " ".join(str(int(r)) for r in refs))
"#;

#[test]
fn meshio_reads_our_mesh() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = python_with(&["meshio"]) else { return };
    let m = read_file("medit/square_hole_mmg.mesh");
    for name in ["m.mesh", "m.meshb"] {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        write(&m, &path);
        let out = run_python(&py, MESHIO_READ, &[path.to_str().unwrap()]);
        let mut lines = out.lines();
        assert_eq!(lines.next().unwrap().trim(), m.points.len().to_string(), "{name}");
        let mut seen = Vec::new();
        for line in lines {
            let mut f = line.split_whitespace();
            let (kind, n) =
                (f.next().unwrap().to_string(), f.next().unwrap().parse::<usize>().unwrap());
            let refs: Vec<i32> = f.map(|t| t.parse().unwrap()).collect();
            assert_eq!(refs.len(), n);
            seen.push((kind, refs));
        }
        let ours: Vec<(String, Vec<i32>)> =
            m.blocks.iter().map(|b| (b.kind.name().to_string(), b.physical.clone())).collect();
        assert_eq!(seen, ours, "{name}");
    }
    // What meshio writes, we read: the same counts per tag.
    let dir = tempfile::tempdir().unwrap();
    let back = dir.path().join("meshio.mesh");
    let src = public_fixture("medit/square_hole_mmg.mesh");
    run_python(
        &py,
        "import sys, meshio; meshio.write(sys.argv[2], meshio.read(sys.argv[1]))",
        &[src.to_str().unwrap(), back.to_str().unwrap()],
    );
    let theirs = read_path(&back, Some(Format::Medit)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(counts_per_tag(&theirs), counts_per_tag(&m));
}

/// Point cells of `m` (their coordinates) that `out` has no vertex at, exactly.
fn lost_points(m: &TaggedMesh, out: &TaggedMesh) -> Vec<[f64; 3]> {
    let have: BTreeSet<[u64; 2]> =
        out.points.iter().map(|p| [p[0].to_bits(), p[1].to_bits()]).collect();
    m.cells()
        .filter(|c| c.0 == CellKind::Vertex)
        .map(|c| m.points[c.1[0] as usize])
        .filter(|p| !have.contains(&[p[0].to_bits(), p[1].to_bits()]))
        .collect()
}

#[test]
fn mmg2d_keeps_the_topological_points_of_our_mesh() {
    let Some(py) = python_with(&["mmgpy"]) else { return };
    let exe = common::mmg2d(&py);
    // The bundled cylinder: its stagnation point is a point cell in the middle of the
    // cylinder's curve, which MMG would move as it remeshes the curve.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cylinder.msh");
    let mut m = read_path(&path, None).unwrap();
    assert!(m.num_cells_of(CellKind::Vertex) > 0);
    m.point_data
        .insert("size".into(), smartmesh_formats::DataArray::new(1, vec![0.021; m.points.len()]));
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("cyl.mesh");
    let report = write_path(&input, &m, None, &WriteOptions::default()).unwrap();
    assert!(!report.dropped.iter().any(|d| d.contains("vertex cells")), "{:?}", report.dropped);
    let out_path = dir.path().join("out.mesh");
    run_mmg(&exe, &input, &dir.path().join("cyl.sol"), &out_path);
    let out = read_path(&out_path, None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(lost_points(&m, &out), Vec::<[f64; 3]>::new());
}

#[test]
fn medit_corners_become_a_named_group_of_points_in_msh() {
    smartmesh_test_support::require_public_fixtures!();
    // MMG's output lists 4 Corners; Gmsh holds them as the physical points "Corners".
    let m = read_file("medit/square_hole_mmg.mesh");
    let corners = m.point_sets["Corners"].clone();
    assert_eq!(corners.len(), 4);
    let dir = tempfile::tempdir().unwrap();
    for (name, opts) in [
        ("x41.msh", WriteOptions::default()),
        (
            "x22.msh",
            WriteOptions {
                gmsh: GmshWrite {
                    version: smartmesh_formats::GmshVersion::V22,
                    ..Default::default()
                },
                ..Default::default()
            },
        ),
    ] {
        let path = dir.path().join(name);
        let report = write_path(&path, &m, None, &opts).unwrap();
        assert!(!report.dropped.iter().any(|d| d.contains("Corners")), "{:?}", report.dropped);
        let back = read_path(&path, None).unwrap();
        let tag = back
            .tag_names
            .iter()
            .find(|(k, v)| k.0 == 0 && v.as_str() == "Corners")
            .map(|(k, _)| k.1)
            .unwrap_or_else(|| panic!("{name}: no 0D group Corners in {:?}", back.tag_names));
        let mut at: Vec<usize> = back
            .cells()
            .filter(|c| c.0 == CellKind::Vertex && c.2 == tag)
            .map(|c| c.1[0] as usize)
            .collect();
        at.sort_unstable();
        assert_eq!(at, corners, "{name}");
    }
    // And Gmsh itself sees the group with its four points.
    let Some(py) = python_with(&["gmsh"]) else { return };
    let out = common::run_python(
        &py,
        r#"
import sys, gmsh
gmsh.initialize(["-v", "0"])
gmsh.open(sys.argv[1])
for dim, tag in gmsh.model.getPhysicalGroups(0):
    nodes, _ = gmsh.model.mesh.getNodesForPhysicalGroup(dim, tag)
    print(gmsh.model.getPhysicalName(dim, tag), len(nodes))
gmsh.finalize()
"#,
        &[dir.path().join("x41.msh").to_str().unwrap()],
    );
    assert!(out.lines().any(|l| l.trim() == "Corners 4"), "{out}");
}

/// Meshes `<dir>/<name>.node` + `.poly` with Triangle `-pA` and prints the area of its
/// triangles by regional attribute: `attribute area` lines.
const TRIANGLE_PA: &str = r##"
import sys, triangle, numpy as np
d = triangle.load(sys.argv[1], sys.argv[2])
pslg = {k: d[k] for k in ["vertices", "segments", "holes"] if k in d}
# triangle.load reads a region's attribute as its area bound: read them here.
tok = " ".join(l.split("#")[0] for l in open(sys.argv[1] + "/" + sys.argv[2] + ".poly")).split()
nv, _, na, nm = map(int, tok[:4]); i = 4 + nv * (3 + na + nm)
ns, sm = map(int, tok[i:i + 2]); i += 2 + ns * (3 + sm)
nh = int(tok[i]); i += 1 + 3 * nh
nr = int(tok[i]) if i < len(tok) else 0
if nr:
    pslg["regions"] = np.array(tok[i + 1:i + 1 + 5 * nr], dtype=float).reshape(-1, 5)[:, 1:]
t = triangle.triangulate(pslg, "pA")
v, tri = t["vertices"], t["triangles"]
a, b, c = v[tri[:, 0]], v[tri[:, 1]], v[tri[:, 2]]
area = 0.5 * np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
attr = t["triangle_attributes"][:, 0] if "triangle_attributes" in t else np.zeros(len(tri))
for k in sorted(set(attr)):
    print(repr(float(k)), repr(float(area[attr == k].sum())))
"##;

#[test]
fn triangle_meshes_the_same_domain_from_the_poly_beside_our_ele() {
    let Some(py) = python_with(&["triangle", "numpy"]) else { return };
    // Gmsh's channel with a cylinder: its inside must stay a hole, its fluid tag 10.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/cylinder.msh");
    let mut m = read_path(&path, None).unwrap();
    m.blocks.retain(|b| matches!(b.kind, CellKind::Line | CellKind::Triangle));
    let dir = tempfile::tempdir().unwrap();
    write_path(&dir.path().join("cyl.ele"), &m, None, &WriteOptions::default()).unwrap();
    let out = run_python(&py, TRIANGLE_PA, &[dir.path().to_str().unwrap(), "cyl"]);
    let mut ours = std::collections::BTreeMap::<i32, f64>::new();
    for c in m.cells().filter(|c| c.0 == CellKind::Triangle) {
        let p = |k: usize| m.points[c.1[k] as usize];
        let (a, b, q) = (p(0), p(1), p(2));
        let area = 0.5 * ((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])).abs();
        *ours.entry(c.2).or_default() += area;
    }
    let theirs: Vec<(f64, f64)> = out
        .lines()
        .map(|l| {
            let v = numbers(l);
            (v[0], v[1])
        })
        .collect();
    assert_eq!(theirs.len(), ours.len(), "Triangle: {out}\nours: {ours:?}");
    for ((attr, area), (tag, our)) in theirs.iter().zip(&ours) {
        assert_eq!(*attr, *tag as f64, "{out}");
        assert!((area - our).abs() <= 1e-9 * our, "tag {tag}: Triangle {area}, ours {our}");
    }
}
