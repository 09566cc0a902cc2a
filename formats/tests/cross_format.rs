//! Every public fixture through every format that can hold it: write, read back,
//! compare with what the format promises to keep. Points bitwise (every writer prints
//! the shortest decimal that reads back exactly), cells as multisets (formats may
//! regroup cells by tag), tags, names and fields where the format holds them; and
//! what a format cannot hold must appear in the write report.

use smartmesh_formats::{GmshWrite, MeditWrite, VtkWrite};
use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use smartmesh_formats::{CellKind, Format, GmshVersion, TaggedMesh, VtuEncoding, WriteOptions};

/// What a target format keeps.
#[derive(Debug, Clone, Copy)]
struct Caps {
    quads: bool,
    lines: bool,
    vertices: bool,
    geometrical: bool,
    names: bool,
    /// All point data (`true`), or only the `metric`/`size` arrays MMG reads (`false`).
    point_data: PointData,
    cell_data: bool,
    z: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum PointData {
    All,
    MetricOnly,
    None,
}

struct Target {
    name: &'static str,
    format: Format,
    ext: &'static str,
    opts: WriteOptions,
    caps: Caps,
}

fn targets() -> Vec<Target> {
    let o = WriteOptions::default;
    let full = Caps {
        quads: true,
        lines: true,
        vertices: true,
        geometrical: true,
        names: true,
        point_data: PointData::All,
        cell_data: true,
        z: true,
    };
    let vtk = Caps { ..full };
    let medit = Caps {
        quads: true,
        lines: true,
        vertices: false,
        geometrical: false,
        names: false,
        point_data: PointData::MetricOnly,
        cell_data: false,
        z: false,
    };
    let obj = Caps {
        quads: true,
        lines: true,
        vertices: true,
        geometrical: false,
        names: true,
        point_data: PointData::None,
        cell_data: false,
        z: true,
    };
    let triangle = Caps {
        quads: false,
        lines: true,
        vertices: false,
        geometrical: false,
        names: false,
        point_data: PointData::None,
        cell_data: false,
        z: false,
    };
    vec![
        Target {
            name: "gmsh 2.2 ascii",
            format: Format::Gmsh,
            ext: "msh",
            opts: WriteOptions {
                gmsh: GmshWrite { version: GmshVersion::V22, ..Default::default() },
                ..o()
            },
            caps: full,
        },
        Target {
            name: "gmsh 2.2 binary",
            format: Format::Gmsh,
            ext: "msh",
            opts: WriteOptions {
                gmsh: GmshWrite { version: GmshVersion::V22, binary: true },
                ..o()
            },
            caps: full,
        },
        Target { name: "gmsh 4.1 ascii", format: Format::Gmsh, ext: "msh", opts: o(), caps: full },
        Target {
            name: "gmsh 4.1 binary",
            format: Format::Gmsh,
            ext: "msh",
            opts: WriteOptions { gmsh: GmshWrite { binary: true, ..Default::default() }, ..o() },
            caps: full,
        },
        Target {
            name: "vtk 4.2 ascii",
            format: Format::VtkLegacy,
            ext: "vtk",
            opts: o(),
            caps: vtk,
        },
        Target {
            name: "vtk 4.2 binary",
            format: Format::VtkLegacy,
            ext: "vtk",
            opts: WriteOptions {
                vtk: VtkWrite { legacy_binary: true, ..Default::default() },
                ..o()
            },
            caps: vtk,
        },
        Target {
            name: "vtk 5.1 ascii",
            format: Format::VtkLegacy,
            ext: "vtk",
            opts: WriteOptions {
                vtk: VtkWrite { legacy_version: (5, 1), ..Default::default() },
                ..o()
            },
            caps: vtk,
        },
        Target {
            name: "vtk 5.1 binary",
            format: Format::VtkLegacy,
            ext: "vtk",
            opts: WriteOptions {
                vtk: VtkWrite { legacy_version: (5, 1), legacy_binary: true, ..Default::default() },
                ..o()
            },
            caps: vtk,
        },
        Target {
            name: "vtu ascii",
            format: Format::Vtu,
            ext: "vtu",
            opts: WriteOptions {
                vtk: VtkWrite { vtu_encoding: VtuEncoding::Ascii, ..Default::default() },
                ..o()
            },
            caps: vtk,
        },
        Target {
            name: "vtu binary",
            format: Format::Vtu,
            ext: "vtu",
            opts: WriteOptions { vtk: VtkWrite { compress: false, ..Default::default() }, ..o() },
            caps: vtk,
        },
        Target { name: "vtu zlib", format: Format::Vtu, ext: "vtu", opts: o(), caps: vtk },
        Target {
            name: "vtu appended",
            format: Format::Vtu,
            ext: "vtu",
            opts: WriteOptions {
                vtk: VtkWrite { vtu_encoding: VtuEncoding::Appended, ..Default::default() },
                ..o()
            },
            caps: vtk,
        },
        Target {
            name: "medit ascii",
            format: Format::Medit,
            ext: "mesh",
            opts: WriteOptions { main_name: Some("x.mesh".into()), ..o() },
            caps: medit,
        },
        Target {
            name: "medit binary",
            format: Format::Medit,
            ext: "meshb",
            opts: WriteOptions {
                medit: MeditWrite { binary: true },
                main_name: Some("x.meshb".into()),
                ..o()
            },
            caps: medit,
        },
        Target { name: "obj", format: Format::Obj, ext: "obj", opts: o(), caps: obj },
        Target {
            name: "triangle",
            format: Format::Triangle,
            ext: "ele",
            opts: WriteOptions { main_name: Some("x.ele".into()), ..o() },
            caps: triangle,
        },
    ]
}

fn fixtures() -> Vec<String> {
    let root = common::public_fixtures();
    let mut out = Vec::new();
    for dir in ["gmsh", "vtk", "medit", "obj", "triangle"] {
        let mut names: Vec<String> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| Format::from_path(n).is_some())
            .collect();
        names.sort();
        for n in names {
            // Triangle sets are read once through their .ele (or .poly / .node when that is all there is).
            if dir == "triangle" {
                let stem = n.rsplit_once('.').unwrap().0.to_string();
                let has = |e: &str| root.join(dir).join(format!("{stem}.{e}")).exists();
                let ext = n.rsplit_once('.').unwrap().1;
                let main = if has("ele") {
                    "ele"
                } else if has("poly") {
                    "poly"
                } else {
                    "node"
                };
                if ext != main {
                    continue;
                }
            }
            out.push(format!("{dir}/{n}"));
        }
    }
    out
}

/// The cells as a sorted multiset of (kind, nodes, physical, geometrical-or-0).
fn cell_multiset(m: &TaggedMesh, caps: Caps) -> Vec<(CellKind, Vec<u32>, i32, i32)> {
    let mut v: Vec<_> = m
        .cells()
        .filter(|(k, ..)| {
            (caps.quads || *k != CellKind::Quad)
                && (caps.lines || *k != CellKind::Line)
                && (caps.vertices || *k != CellKind::Vertex)
        })
        .map(|(k, n, p, g)| (k, n.to_vec(), p, if caps.geometrical { g } else { 0 }))
        .collect();
    v.sort();
    v
}

/// Tag names of the tags that cells still carry.
fn used_names(
    m: &TaggedMesh,
    cells: &[(CellKind, Vec<u32>, i32, i32)],
) -> BTreeMap<(u8, i32), String> {
    let mut out = BTreeMap::new();
    for (k, _, p, _) in cells {
        if let Some(n) = m.tag_name(k.dim(), *p) {
            out.insert((k.dim(), *p), n.to_string());
        }
    }
    out
}

#[test]
fn every_fixture_through_every_format() {
    smartmesh_test_support::require_public_fixtures!();
    let mut checked = 0;
    let mut failures = Vec::new();
    for rel in fixtures() {
        let mesh = common::read_file(&rel);
        for t in targets() {
            let caps = t.caps;
            let has_second_order = mesh.blocks.iter().any(|b| b.kind.is_second_order());
            let has_quads = mesh.num_cells_of(CellKind::Quad) > 0;
            if has_second_order || (has_quads && !caps.quads) || mesh.num_cells() == 0 {
                continue;
            }
            let (written, mut back) = common::roundtrip(t.format, t.ext, &mesh, &t.opts);
            let mut problems = Vec::new();
            // MSH holds a point set as a 0D physical group named after it: check it and
            // take it out before the cells are compared.
            if t.format == Format::Gmsh {
                for (name, set) in &mesh.point_sets {
                    let tag = back
                        .tag_names
                        .iter()
                        .find(|(k, v)| k.0 == 0 && *v == name)
                        .map(|(k, _)| k.1);
                    let Some(tag) = tag else {
                        problems.push(format!("point set `{name}` has no 0D group"));
                        continue;
                    };
                    back.tag_names.remove(&(0, tag));
                    let mut at = Vec::new();
                    for b in back.blocks.iter_mut().filter(|b| b.kind == CellKind::Vertex) {
                        let keep: Vec<bool> = b.physical.iter().map(|&p| p != tag).collect();
                        at.extend(
                            b.nodes.iter().zip(&keep).filter(|x| !*x.1).map(|x| *x.0 as usize),
                        );
                        let mut k = keep.iter();
                        b.nodes.retain(|_| *k.next().unwrap_or(&true));
                        let mut k = keep.iter();
                        b.physical.retain(|_| *k.next().unwrap_or(&true));
                        let mut k = keep.iter();
                        b.geometrical.retain(|_| *k.next().unwrap_or(&true));
                    }
                    let mut want = set.clone();
                    want.sort_unstable();
                    want.dedup();
                    at.sort_unstable();
                    if at != want {
                        problems.push(format!("point set `{name}`: {at:?}, expected {want:?}"));
                    }
                }
            }
            if back.points.len() != mesh.points.len() {
                problems.push(format!(
                    "{} points, expected {}",
                    back.points.len(),
                    mesh.points.len()
                ));
            } else {
                let dims = if caps.z { 3 } else { 2 };
                if let Some(i) = (0..mesh.points.len()).find(|&i| {
                    (0..dims).any(|k| back.points[i][k].to_bits() != mesh.points[i][k].to_bits())
                }) {
                    problems.push(format!(
                        "point {i} is {:?}, expected {:?}",
                        back.points[i], mesh.points[i]
                    ));
                }
            }
            // Gmsh 4.1 entity tags are strictly positive: cells without one are placed on
            // new entities, which the report says; their physical tags must still hold.
            let mut caps = caps;
            if written.report.dropped.iter().any(|d| d.contains("new entities")) {
                caps.geometrical = false;
            }
            let (a, b) = (cell_multiset(&mesh, caps), cell_multiset(&back, caps));
            if a != b {
                problems.push(format!("cells differ ({} vs {})", a.len(), b.len()));
            }
            if caps.names && used_names(&mesh, &a) != used_names(&back, &b) {
                problems.push(format!(
                    "names differ: {:?} vs {:?}",
                    used_names(&mesh, &a),
                    used_names(&back, &b)
                ));
            }
            let expected_pd: Vec<&String> = match caps.point_data {
                PointData::All => mesh.point_data.keys().collect(),
                PointData::MetricOnly => {
                    mesh.point_data.keys().filter(|k| *k == "metric").take(1).collect()
                }
                PointData::None => vec![],
            };
            for k in &expected_pd {
                match back.point_data.get(*k) {
                    None => problems.push(format!("point data `{k}` lost")),
                    Some(arr) => {
                        let orig = &mesh.point_data[*k];
                        let same = if caps.point_data == PointData::MetricOnly {
                            // Medit keeps the 2D part m11 m12 m22 of the tensor.
                            (0..orig.len()).all(|i| {
                                let (x, y) = (orig.tensor9(i), arr.tensor9(i));
                                [0, 1, 4].iter().all(|&c| x[c].to_bits() == y[c].to_bits())
                            })
                        } else {
                            arr == orig
                        };
                        if !same {
                            problems.push(format!("point data `{k}` changed"));
                        }
                    }
                }
            }
            // Nothing lost in silence: arrays that did not survive are in the report.
            for k in mesh.point_data.keys() {
                if !back.point_data.contains_key(k)
                    && !written.report.dropped.iter().any(|d| d.contains(k.as_str()))
                {
                    problems.push(format!("point data `{k}` dropped without a word in the report"));
                }
            }
            if caps.cell_data {
                for (k, arr) in &mesh.cell_data {
                    if back.cell_data.get(k) != Some(arr)
                        && !written.report.dropped.iter().any(|d| d.contains(k.as_str()))
                    {
                        problems.push(format!("cell data `{k}` changed or lost"));
                    }
                }
            }
            if !problems.is_empty() {
                failures.push(format!("{rel} -> {}: {}", t.name, problems.join("; ")));
            }
            checked += 1;
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {checked} round trips failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(checked > 150, "only {checked} round trips ran");
}

/// A mesh `validate` refuses is refused by every writer, with its first problem as the
/// reason, whether the writer validates first or checks as it writes (Medit).
#[test]
fn every_writer_refuses_an_invalid_mesh_with_validates_message() {
    use smartmesh_formats::{write_bytes, CellBlock, DataArray, ErrorKind};
    let valid = || {
        let mut m = TaggedMesh::new();
        m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let mut tris = CellBlock::new(CellKind::Triangle);
        tris.push(&[0, 1, 2], 1, 1);
        tris.push(&[0, 2, 3], 1, 1);
        let mut lines = CellBlock::new(CellKind::Line);
        lines.push(&[0, 1], 2, 2);
        let mut corners = CellBlock::new(CellKind::Vertex);
        corners.push(&[3], 3, 3);
        m.blocks = vec![corners, lines, tris];
        m.point_data.insert("size".into(), DataArray::new(1, vec![0.1; 4]));
        m
    };
    let broken: Vec<(&str, TaggedMesh)> = vec![
        ("non-finite coordinate", {
            let mut m = valid();
            m.points[2][1] = f64::NAN;
            m
        }),
        ("infinite z", {
            let mut m = valid();
            m.points[1][2] = f64::INFINITY;
            m
        }),
        ("triangle node past the points", {
            let mut m = valid();
            m.blocks[2].nodes[4] = 9;
            m
        }),
        ("line node past the points", {
            let mut m = valid();
            m.blocks[1].nodes[1] = 4;
            m
        }),
        // Medit has no point elements: the block is dropped, yet the mesh is refused.
        ("vertex node past the points", {
            let mut m = valid();
            m.blocks[0].nodes[0] = 7;
            m
        }),
        ("block lengths", {
            let mut m = valid();
            m.blocks[2].geometrical.pop();
            m
        }),
        ("short point data", {
            let mut m = valid();
            m.point_data.insert("size".into(), DataArray::new(1, vec![0.1; 3]));
            m
        }),
        ("point set past the points", {
            let mut m = valid();
            m.point_sets.insert("Corners".into(), vec![0, 4]);
            m
        }),
        ("cell set past the cells", {
            let mut m = valid();
            m.cell_sets.insert("Ridges".into(), vec![1, 4]);
            m
        }),
    ];
    for t in targets() {
        assert!(write_bytes(t.format, &valid(), &t.opts).is_ok(), "{}: the valid mesh", t.name);
        for (what, m) in &broken {
            let problems = m.validate();
            assert!(!problems.is_empty(), "{what}: validate finds it");
            let e = write_bytes(t.format, m, &t.opts).expect_err(&format!("{}: {what}", t.name));
            match &e.kind {
                ErrorKind::CannotWrite { reason, .. } => {
                    assert_eq!(reason, &problems[0].to_string(), "{}: {what}", t.name)
                }
                other => panic!("{}: {what}: {other:?}", t.name),
            }
        }
    }
}
