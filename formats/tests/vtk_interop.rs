//! VTK's own readers (and meshio's, when installed) read every variant we write; and
//! we read every encoding VTK's own writers produce. Skips when Python lacks `vtk`
//! (`pip install vtk meshio`), unless `SMARTMESH_REQUIRE_INTEROP=1`.

use smartmesh_test_support::formats as common;

use smartmesh_formats::{
    read_bytes, write_bytes, CellBlock, CellKind, DataArray, Format, ReadContext, TaggedMesh,
    WriteOptions,
};

/// Every variant the writers offer: (file name, format, options).
fn variants() -> Vec<(String, Format, WriteOptions)> {
    common::vtk_variants()
        .into_iter()
        .map(|(format, vtk)| {
            let name = if format == Format::VtkLegacy {
                let (major, minor) = vtk.legacy_version;
                format!(
                    "legacy{major}{minor}_{}.vtk",
                    if vtk.legacy_binary { "binary" } else { "ascii" }
                )
            } else {
                let enc = format!("{:?}", vtk.vtu_encoding).to_lowercase();
                format!("{enc}{}.vtu", if vtk.compress { "_zlib" } else { "" })
            };
            (name, format, WriteOptions { vtk, ..WriteOptions::default() })
        })
        .collect()
}

/// The naca0012 fixture with names, boundary lines, a vertex and more data.
fn mesh() -> TaggedMesh {
    let mut m = common::read_file("vtk/naca0012_binary_zlib.vtu");
    m.tag_names.insert((2, 3), "Fluid".into());
    m.tag_names.insert((1, 7), "far field".into());
    let mut lines = CellBlock::new(CellKind::Line);
    lines.push(&[0, 1], 7, 70);
    lines.push(&[1, 2], 7, 71);
    let mut verts = CellBlock::new(CellKind::Vertex);
    verts.push(&[5], 9, -9);
    m.blocks.insert(0, lines);
    m.blocks.push(verts);
    let nc = m.num_cells();
    let np = m.points.len();
    m.cell_data.insert(
        "quality".into(),
        DataArray::new(1, (0..nc).map(|i| 1.0 / (i as f64 + 3.0)).collect()),
    );
    m.point_data.insert(
        "velocity".into(),
        DataArray::new(3, (0..3 * np).map(|i| (i as f64 * 0.37).sin()).collect()),
    );
    m.point_data
        .insert("four".into(), DataArray::new(4, (0..4 * np).map(|i| -(i as f64) / 7.0).collect()));
    m
}

fn tags(m: &TaggedMesh) -> (Vec<u8>, Vec<u8>) {
    let p = m.blocks.iter().flat_map(|b| b.physical.iter()).flat_map(|v| v.to_le_bytes()).collect();
    let g =
        m.blocks.iter().flat_map(|b| b.geometrical.iter()).flat_map(|v| v.to_le_bytes()).collect();
    (p, g)
}

const VTK_READS: &str = r#"
import sys, json
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy as v2n
log = vtk.vtkStringOutputWindow()
vtk.vtkOutputWindow.SetInstance(log)
d = sys.argv[1]
metric = np.fromfile(f"{d}/metric.f64", dtype="<f8")
phys = np.fromfile(f"{d}/physical.i32", dtype="<i4")
geom = np.fromfile(f"{d}/geometrical.i32", dtype="<i4")
out = {}
seen = 0
for name in sys.argv[2:]:
    r = vtk.vtkXMLUnstructuredGridReader() if name.endswith(".vtu") else vtk.vtkUnstructuredGridReader()
    r.SetFileName(f"{d}/{name}")
    r.Update()
    g = r.GetOutput()
    pd, cd, fd = g.GetPointData(), g.GetCellData(), g.GetFieldData()
    m = pd.GetArray("metric")
    p = cd.GetArray("gmsh:physical")
    q = cd.GetArray("gmsh:geometrical")
    t = pd.GetTensors()
    out[name] = dict(
        log=log.GetOutput()[seen:],
        points=g.GetNumberOfPoints(),
        cells=g.GetNumberOfCells(),
        types=sorted(set(g.GetCellType(i) for i in range(g.GetNumberOfCells()))),
        metric_components=m.GetNumberOfComponents() if m else 0,
        metric_equal=bool(m is not None and np.array_equal(v2n(m).ravel(), metric)),
        physical_equal=bool(p is not None and np.array_equal(v2n(p).ravel(), phys)),
        geometrical_equal=bool(q is not None and np.array_equal(v2n(q).ravel(), geom)),
        tensors=t.GetName() if t else None,
        names={fd.GetArrayName(i): v2n(fd.GetArray(i)).ravel().tolist() for i in range(fd.GetNumberOfArrays())},
    )
    seen = len(log.GetOutput())
print(json.dumps(out))
"#;

const MESHIO_READS: &str = r#"
import sys, json, warnings
import numpy as np
import traceback
import meshio
warnings.simplefilter("ignore")
d = sys.argv[1]
metric = np.fromfile(f"{d}/metric.f64", dtype="<f8")
phys = np.fromfile(f"{d}/physical.i32", dtype="<i4")
out = {}
for name in sys.argv[2:]:
    try:
        m = meshio.read(f"{d}/{name}")
    except Exception:
        out[name] = dict(error=traceback.format_exc())
        continue
    met = m.point_data.get("metric")
    p = m.cell_data.get("gmsh:physical")
    out[name] = dict(
        points=len(m.points),
        cells=sum(len(c.data) for c in m.cells),
        metric_equal=bool(met is not None and np.array_equal(np.asarray(met).ravel(), metric)),
        physical_equal=bool(p is not None and np.array_equal(np.concatenate(p).ravel(), phys)),
        fluid=np.asarray(m.field_data.get("Fluid", [])).ravel().tolist(),
    )
print(json.dumps(out))
"#;

fn write_all(dir: &std::path::Path, m: &TaggedMesh) -> Vec<String> {
    let mut names = Vec::new();
    for (name, format, opts) in variants() {
        let w = write_bytes(format, m, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        std::fs::write(dir.join(&name), &w.main).unwrap();
        names.push(name);
    }
    let metric: Vec<u8> =
        m.point_data["metric"].expanded().values.iter().flat_map(|v| v.to_le_bytes()).collect();
    std::fs::write(dir.join("metric.f64"), metric).unwrap();
    let (p, g) = tags(m);
    std::fs::write(dir.join("physical.i32"), p).unwrap();
    std::fs::write(dir.join("geometrical.i32"), g).unwrap();
    names
}

#[test]
fn vtk_reads_every_variant_we_write() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["vtk", "numpy"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = mesh();
    let names = write_all(dir.path(), &m);
    let mut args = vec![dir.path().to_str().unwrap()];
    args.extend(names.iter().map(String::as_str));
    let out: serde_json::Value =
        serde_json::from_str(&common::run_python(&py, VTK_READS, &args)).unwrap();
    for name in &names {
        let r = &out[name];
        assert_eq!(r["log"], "", "{name}: VTK complained");
        assert_eq!(r["points"], 1904, "{name}");
        assert_eq!(r["cells"], m.num_cells(), "{name}");
        assert_eq!(r["types"], serde_json::json!([1, 3, 5]), "{name}");
        assert_eq!(r["metric_components"], 9, "{name}");
        assert_eq!(r["metric_equal"], true, "{name}: metric values");
        assert_eq!(r["physical_equal"], true, "{name}: gmsh:physical");
        assert_eq!(r["geometrical_equal"], true, "{name}: gmsh:geometrical");
        assert_eq!(r["tensors"], "metric", "{name}: the active tensor Tensor Glyph uses");
        assert_eq!(r["names"]["Fluid"], serde_json::json!([3, 2]), "{name}");
        assert_eq!(r["names"]["far field"], serde_json::json!([7, 1]), "{name}");
    }
}

#[test]
fn meshio_reads_every_variant_we_write() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["meshio", "numpy"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = mesh();
    let mut names = write_all(dir.path(), &m);
    // meshio 5.3 maps the legacy type `int` to a 64-bit integer in 5.1 files, so it
    // misreads every binary 5.1 file with an Int32 array, VTK's own included
    // (checked with vtkUnstructuredGridWriter, SetFileVersion(51), binary).
    // `int` is VTK's name (it refuses `vtktypeint32`), so we keep it.
    names.retain(|n| n != "legacy51_binary.vtk");
    let mut args = vec![dir.path().to_str().unwrap()];
    args.extend(names.iter().map(String::as_str));
    let out: serde_json::Value =
        serde_json::from_str(&common::run_python(&py, MESHIO_READS, &args)).unwrap();
    for name in &names {
        let r = &out[name];
        assert!(
            r["error"].is_null(),
            "{name}: meshio failed: {}",
            r["error"].as_str().unwrap_or("")
        );
        assert_eq!(r["points"], 1904, "{name}");
        assert_eq!(r["cells"], m.num_cells(), "{name}");
        assert_eq!(r["metric_equal"], true, "{name}: metric values");
        assert_eq!(r["physical_equal"], true, "{name}: gmsh:physical");
        assert_eq!(r["fluid"], serde_json::json!([3, 2]), "{name}: tag name as meshio field_data");
    }
}

const VTK_WRITES: &str = r#"
import sys, os
import vtk
src, d = sys.argv[1], sys.argv[2]
r = vtk.vtkXMLUnstructuredGridReader()
r.SetFileName(src)
r.Update()
g = r.GetOutput()
names = []
for order in ("Little", "Big"):
    for header in (32, 64):
        for mode in ("Ascii", "Binary", "Appended", "AppendedBase64"):
            for zlib in (False, True):
                if mode == "Ascii" and zlib:
                    continue
                name = f"vtk_{order}_{header}_{mode}_{'zlib' if zlib else 'none'}.vtu"
                w = vtk.vtkXMLUnstructuredGridWriter()
                w.SetInputData(g)
                w.SetFileName(os.path.join(d, name))
                getattr(w, f"SetByteOrderTo{order}Endian")()
                getattr(w, f"SetHeaderTypeToUInt{header}")()
                if mode == "Ascii":
                    w.SetDataModeToAscii()
                elif mode == "Binary":
                    w.SetDataModeToBinary()
                else:
                    w.SetDataModeToAppended()
                    w.SetEncodeAppendedData(mode == "AppendedBase64")
                if zlib:
                    w.SetCompressorTypeToZLib()
                else:
                    w.SetCompressorTypeToNone()
                assert w.Write() == 1, name
                names.append(name)
for version in (42, 51):
    for binary in (False, True):
        name = f"vtk_legacy{version}_{'binary' if binary else 'ascii'}.vtk"
        w = vtk.vtkUnstructuredGridWriter()
        w.SetInputData(g)
        w.SetFileName(os.path.join(d, name))
        w.SetFileVersion(version)
        if binary:
            w.SetFileTypeToBinary()
        else:
            w.SetFileTypeToASCII()
        assert w.Write() == 1, name
        names.append(name)
print("\n".join(names))
"#;

#[test]
fn we_read_every_encoding_vtk_writes() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(py) = common::python_with(&["vtk"]) else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = mesh();
    let src = dir.path().join("source.vtu");
    std::fs::write(&src, write_bytes(Format::Vtu, &m, &WriteOptions::default()).unwrap().main)
        .unwrap();
    let listing =
        common::run_python(&py, VTK_WRITES, &[src.to_str().unwrap(), dir.path().to_str().unwrap()]);
    let names: Vec<&str> = listing.lines().collect();
    assert_eq!(names.len(), 32);
    for name in names {
        let bytes = std::fs::read(dir.path().join(name)).unwrap();
        let format = if name.ends_with(".vtu") { Format::Vtu } else { Format::VtkLegacy };
        let back = read_bytes(format, &bytes, &ReadContext::alone("vtk"))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(back.blocks, m.blocks, "{name}: cells and tags");
        assert_eq!(back.tag_names, m.tag_names, "{name}: names");
        let keys = |a: &std::collections::BTreeMap<String, DataArray>| {
            a.keys().cloned().collect::<Vec<_>>()
        };
        assert_eq!(keys(&back.point_data), keys(&m.point_data), "{name}");
        assert_eq!(keys(&back.cell_data), keys(&m.cell_data), "{name}");
        if name.contains("legacy") && name.contains("ascii") {
            // VTK's legacy ASCII writer keeps 11 significant digits.
            let close = |a: &[f64], b: &[f64]| {
                a.len() == b.len()
                    && a.iter().zip(b).all(|(x, y)| (x - y).abs() <= 1e-10 * x.abs().max(y.abs()))
            };
            let flat = |m: &TaggedMesh| m.points.iter().flatten().copied().collect::<Vec<_>>();
            assert!(close(&flat(&back), &flat(&m)), "{name}: points");
            for (k, a) in &m.point_data {
                assert!(close(&back.point_data[k].values, &a.values), "{name}: {k}");
            }
        } else {
            assert_eq!(back, m, "{name}");
        }
    }
}
