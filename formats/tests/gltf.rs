//! glTF 2.0 writer: what we write read back with the `gltf` crate (positions, indices,
//! colours against the input), .glb and .gltf carrying the same data, the container's
//! layout, colour fields, the report, and the Khronos validator on our files.

use smartmesh_formats::GltfWrite;
use smartmesh_test_support::formats as common;

use std::path::PathBuf;
use std::process::Command;

use base64::Engine as _;
use proptest::prelude::*;
use smartmesh_formats::arbitrary::{arb_tagged_mesh, MeshFeatures};
use smartmesh_formats::{
    sym2_to_tensor9, write_bytes, CellBlock, CellKind, DataArray, ErrorKind, Format, TaggedMesh,
    WriteOptions, Written,
};

/// The two-domain OBJ fixture (119 quads, 248 triangles), a few boundary lines, and
/// point fields: `size` (scalar), `velocity` (3-vector), `metric` (tensor whose finest
/// size is known in closed form: diag(1/hx², 1/hy²) has h = min(hx, hy)).
fn fixture_mesh() -> TaggedMesh {
    let mut m = common::read_file("obj/two_domains_mixed.obj");
    m.blocks.push(CellBlock {
        kind: CellKind::Line,
        nodes: vec![0, 6, 6, 7, 7, 8],
        physical: vec![5; 3],
        geometrical: vec![5; 3],
    });
    let size: Vec<f64> = m.points.iter().map(|p| 0.1 + p[0] * p[0] + 0.5 * p[1]).collect();
    let velocity: Vec<f64> = m.points.iter().flat_map(|p| [p[1], -p[0], 0.0]).collect();
    let metric: Vec<f64> = m.points.iter().flat_map(metric_at).collect();
    m.point_data.insert("size".into(), DataArray::new(1, size));
    m.point_data.insert("velocity".into(), DataArray::new(3, velocity));
    m.point_data.insert("metric".into(), DataArray::new(9, metric));
    m
}

fn sizes_at(p: &[f64; 3]) -> (f64, f64) {
    (0.05 + 0.1 * p[0], 0.02 + 0.3 * p[1])
}

fn metric_at(p: &[f64; 3]) -> [f64; 9] {
    let (hx, hy) = sizes_at(p);
    sym2_to_tensor9(1.0 / (hx * hx), 0.0, 1.0 / (hy * hy), 1.0)
}

fn opts(main: Option<&str>, field: Option<&str>) -> WriteOptions {
    WriteOptions {
        gltf: GltfWrite { color_field: field.map(str::to_string), ..Default::default() },
        main_name: main.map(str::to_string),
        ..Default::default()
    }
}

fn write(mesh: &TaggedMesh, o: &WriteOptions) -> Written {
    write_bytes(Format::Gltf, mesh, o).unwrap_or_else(|e| panic!("{e}"))
}

/// What a viewer gets from our file.
#[derive(Debug, PartialEq)]
struct Drawn {
    positions: Vec<[f32; 3]>,
    colours: Option<Vec<[f32; 3]>>,
    triangles: Vec<u32>,
    lines: Vec<u32>,
    extras: Option<serde_json::Value>,
    unlit: bool,
}

/// Reads our output with the `gltf` crate (which validates the JSON): the buffer comes
/// from the GLB chunk, the `bin` sibling or the data URI.
fn read_back(w: &Written) -> Drawn {
    let g = gltf::Gltf::from_slice(&w.main)
        .unwrap_or_else(|e| panic!("gltf crate refuses our file: {e}"));
    let buffer = g.buffers().next().expect("one buffer");
    let bytes: Vec<u8> = match buffer.source() {
        gltf::buffer::Source::Bin => g.blob.clone().expect("GLB BIN chunk"),
        gltf::buffer::Source::Uri(uri) => {
            match uri.strip_prefix("data:application/octet-stream;base64,") {
                Some(b64) => base64::engine::general_purpose::STANDARD.decode(b64).unwrap(),
                None => {
                    assert!(
                        !uri.contains(':') && !uri.contains('/'),
                        "relative file URI expected, got {uri}"
                    );
                    w.siblings.iter().find(|(e, _)| e == "bin").expect("bin sibling").1.clone()
                }
            }
        }
    };
    // byteLength exact (a GLB chunk may only add up to 3 bytes of padding).
    assert!(
        bytes.len() >= buffer.length() && bytes.len() - buffer.length() < 4,
        "{} vs {}",
        bytes.len(),
        buffer.length()
    );
    assert_eq!(g.meshes().count(), 1);
    let mesh = g.meshes().next().unwrap();
    let mut d = Drawn {
        positions: Vec::new(),
        colours: None,
        triangles: Vec::new(),
        lines: Vec::new(),
        extras: mesh.extras().as_ref().map(|r| serde_json::from_str(r.get()).unwrap()),
        unlit: false,
    };
    for prim in mesh.primitives() {
        let r = prim.reader(|_| Some(&bytes[..]));
        let positions: Vec<[f32; 3]> = r.read_positions().expect("POSITION").collect();
        let pos_acc = prim.get(&gltf::Semantic::Positions).unwrap();
        assert_eq!(pos_acc.data_type(), gltf::accessor::DataType::F32);
        let (min, max) =
            (pos_acc.min().expect("POSITION min"), pos_acc.max().expect("POSITION max"));
        for k in 0..3 {
            let lo = positions.iter().map(|p| p[k]).fold(f32::INFINITY, f32::min);
            let hi = positions.iter().map(|p| p[k]).fold(f32::NEG_INFINITY, f32::max);
            // As f32: serde_json's default float parsing may be 1 ulp off in f64 (the
            // Khronos validator below checks the bounds exactly).
            assert_eq!(min[k].as_f64().unwrap() as f32, lo);
            assert_eq!(max[k].as_f64().unwrap() as f32, hi);
        }
        let colours: Option<Vec<[f32; 3]>> = r.read_colors(0).map(|c| c.into_rgb_f32().collect());
        let idx_acc = prim.indices().expect("indices");
        assert_eq!(idx_acc.data_type(), gltf::accessor::DataType::U32);
        let indices: Vec<u32> = r.read_indices().unwrap().into_u32().collect();
        assert!(indices.iter().all(|&i| (i as usize) < positions.len()));
        if d.positions.is_empty() {
            d.positions = positions;
            d.colours = colours;
        } else {
            assert_eq!(d.positions, positions, "primitives share POSITION");
            assert_eq!(d.colours, colours, "primitives share COLOR_0");
        }
        d.unlit = prim.material().unlit();
        match prim.mode() {
            gltf::mesh::Mode::Triangles => d.triangles = indices,
            gltf::mesh::Mode::Lines => d.lines = indices,
            m => panic!("unexpected mode {m:?}"),
        }
    }
    d
}

/// The triangles and lines we expect: quads `a b c d` as `a b c` + `a c d`.
fn expected_indices(m: &TaggedMesh) -> (Vec<u32>, Vec<u32>) {
    let (mut t, mut l) = (Vec::new(), Vec::new());
    for (k, n, _, _) in m.cells() {
        let n: Vec<u32> = n.to_vec();
        match k {
            CellKind::Triangle | CellKind::Triangle6 => t.extend_from_slice(&n[..3]),
            CellKind::Quad | CellKind::Quad8 | CellKind::Quad9 => {
                t.extend_from_slice(&[n[0], n[1], n[2], n[0], n[2], n[3]])
            }
            CellKind::Line | CellKind::Line3 => l.extend_from_slice(&n[..2]),
            CellKind::Vertex => {}
            k => panic!("no {} cell in a glTF test mesh", k.name()),
        }
    }
    (t, l)
}

fn luminance(c: &[f32; 3]) -> f64 {
    0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64
}

/// Colours follow the values: viridis' luminance grows along the map, so sorting the
/// vertices by value sorts them by luminance; the extremes are viridis' ends.
fn check_colours(values: &[f64], colours: &[[f32; 3]]) {
    assert_eq!(values.len(), colours.len());
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    for w in order.windows(2) {
        if values[w[1]] > values[w[0]] {
            assert!(
                luminance(&colours[w[1]]) >= luminance(&colours[w[0]]) - 1e-6,
                "colour not monotone in value"
            );
        }
    }
    // matplotlib's viridis(0) = (0.267004, 0.004874, 0.329415), viridis(1) =
    // (0.993248, 0.906157, 0.143936) in sRGB; COLOR_0 holds them linear.
    let lin = |c: f64| if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) };
    let close = |c: &[f32; 3], s: [f64; 3]| (0..3).all(|k| (c[k] as f64 - lin(s[k])).abs() < 1e-5);
    assert!(close(&colours[order[0]], [0.267004, 0.004874, 0.329415]), "{:?}", colours[order[0]]);
    assert!(
        close(&colours[*order.last().unwrap()], [0.993248, 0.906157, 0.143936]),
        "{:?}",
        colours[*order.last().unwrap()]
    );
    for c in colours {
        assert!(c.iter().all(|x| (0.0..=1.0).contains(x)));
    }
}

fn extras_range(d: &Drawn) -> (String, f64, f64) {
    let e = d.extras.as_ref().expect("extras");
    (
        e["color_field"].as_str().unwrap().to_string(),
        e["color_min"].as_f64().unwrap(),
        e["color_max"].as_f64().unwrap(),
    )
}

#[test]
fn positions_indices_and_colours_read_back() {
    smartmesh_test_support::require_public_fixtures!();
    let m = fixture_mesh();
    let w = write(&m, &opts(Some("out.gltf"), None));
    let d = read_back(&w);
    let expect_pos: Vec<[f32; 3]> =
        m.points.iter().map(|p| [p[0] as f32, p[1] as f32, p[2] as f32]).collect();
    assert_eq!(d.positions, expect_pos);
    let (t, l) = expected_indices(&m);
    assert_eq!(d.triangles, t);
    assert_eq!(d.triangles.len(), 3 * (248 + 2 * 119));
    assert_eq!(d.lines, l);
    // Default colour field: the first scalar point field, `size`.
    let size = &m.point_data["size"].values;
    check_colours(size, d.colours.as_ref().unwrap());
    let (name, lo, hi) = extras_range(&d);
    assert_eq!(name, "size");
    assert_eq!(lo, size.iter().copied().fold(f64::INFINITY, f64::min));
    assert_eq!(hi, size.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    assert!(d.unlit);
}

#[test]
fn tensor_fields_colour_by_finest_size() {
    smartmesh_test_support::require_public_fixtures!();
    let m = fixture_mesh();
    let d = read_back(&write(&m, &opts(None, Some("metric"))));
    let h: Vec<f64> = m.points.iter().map(|p| sizes_at(p).0.min(sizes_at(p).1)).collect();
    check_colours(&h, d.colours.as_ref().unwrap());
    let (name, lo, hi) = extras_range(&d);
    assert_eq!(name, "metric");
    let (elo, ehi) = (
        h.iter().copied().fold(f64::INFINITY, f64::min),
        h.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    assert!(
        (lo - elo).abs() <= 1e-12 * elo && (hi - ehi).abs() <= 1e-12 * ehi,
        "{lo} {hi} vs {elo} {ehi}"
    );
    assert!(d.extras.as_ref().unwrap()["color_quantity"].as_str().unwrap().contains("finest size"));
}

#[test]
fn vector_fields_colour_by_magnitude() {
    smartmesh_test_support::require_public_fixtures!();
    let m = fixture_mesh();
    let d = read_back(&write(&m, &opts(None, Some("velocity"))));
    let mag: Vec<f64> = m.points.iter().map(|p| (p[0] * p[0] + p[1] * p[1]).sqrt()).collect();
    check_colours(&mag, d.colours.as_ref().unwrap());
    let (name, lo, hi) = extras_range(&d);
    assert_eq!((name.as_str(), lo), ("velocity", 0.0));
    assert_eq!(hi, mag.iter().copied().fold(0.0, f64::max));
}

#[test]
fn glb_and_gltf_carry_the_same_data() {
    smartmesh_test_support::require_public_fixtures!();
    let m = fixture_mesh();
    let gltf_file = write(&m, &opts(Some("mesh.gltf"), Some("metric")));
    let glb_file = write(&m, &opts(Some("mesh.glb"), Some("metric")));
    let mut glb_opts = opts(Some("mesh.gltf"), Some("metric"));
    glb_opts.gltf.glb = true;
    let glb_flag = write(&m, &glb_opts);
    let stdout = write(&m, &opts(None, Some("metric")));
    assert!(glb_file.siblings.is_empty() && stdout.siblings.is_empty());
    assert_eq!(glb_file.main[..4], *b"glTF");
    assert_eq!(glb_flag.main, glb_file.main);
    let a = read_back(&gltf_file);
    assert_eq!(a, read_back(&glb_file));
    assert_eq!(a, read_back(&stdout));
    assert_eq!(gltf_file.report, glb_file.report);
}

#[test]
fn same_mesh_same_bytes() {
    smartmesh_test_support::require_public_fixtures!();
    let m = fixture_mesh();
    for o in [opts(Some("a.gltf"), None), opts(Some("a.glb"), Some("metric")), opts(None, None)] {
        let (x, y) = (write(&m, &o), write(&m, &o));
        assert_eq!(x.main, y.main);
        assert_eq!(x.siblings, y.siblings);
    }
}

#[test]
fn glb_container_layout() {
    smartmesh_test_support::require_public_fixtures!();
    let w = write(&fixture_mesh(), &opts(Some("m.glb"), None));
    let b = &w.main;
    let u32_at = |o: usize| u32::from_le_bytes(b[o..o + 4].try_into().unwrap()) as usize;
    assert_eq!(&b[0..4], b"glTF");
    assert_eq!(u32_at(4), 2);
    assert_eq!(u32_at(8), b.len());
    let json_len = u32_at(12);
    assert_eq!(&b[16..20], b"JSON");
    assert_eq!(json_len % 4, 0);
    let json = &b[20..20 + json_len];
    let trimmed = json.iter().rposition(|&c| c == b'}').unwrap() + 1;
    assert!(json[trimmed..].iter().all(|&c| c == b' '), "JSON chunk padded with spaces");
    let doc: serde_json::Value = serde_json::from_slice(&json[..trimmed]).unwrap();
    let bin_at = 20 + json_len;
    let bin_len = u32_at(bin_at);
    assert_eq!(&b[bin_at + 4..bin_at + 8], b"BIN\0");
    assert_eq!(bin_len % 4, 0);
    assert_eq!(bin_at + 8 + bin_len, b.len());
    assert_eq!(doc["buffers"][0]["byteLength"].as_u64().unwrap() as usize, bin_len);
    assert!(doc["buffers"][0].get("uri").is_none());
    for v in doc["bufferViews"].as_array().unwrap() {
        assert_eq!(v["byteOffset"].as_u64().unwrap() % 4, 0);
    }
}

#[test]
fn gltf_names_its_bin_after_the_main_file() {
    smartmesh_test_support::require_public_fixtures!();
    let m = fixture_mesh();
    let w = write(&m, &opts(Some("naca 0012.v2.gltf"), None));
    let doc: serde_json::Value = serde_json::from_slice(&w.main).unwrap();
    assert_eq!(doc["buffers"][0]["uri"], "naca%200012.v2.bin");
    assert_eq!(w.siblings.len(), 1);
    assert_eq!(w.siblings[0].0, "bin");
    assert_eq!(doc["buffers"][0]["byteLength"].as_u64().unwrap() as usize, w.siblings[0].1.len());
    // Through the file API: the .bin lands beside the .gltf under that name.
    let dir = tempfile::tempdir().unwrap();
    smartmesh_formats::write_path(
        &dir.path().join("naca 0012.v2.gltf"),
        &m,
        None,
        &WriteOptions::default(),
    )
    .unwrap();
    assert!(dir.path().join("naca 0012.v2.bin").exists());
    // Stdout: one file with the buffer inside.
    let w = write(&m, &opts(None, None));
    let doc: serde_json::Value = serde_json::from_slice(&w.main).unwrap();
    assert!(doc["buffers"][0]["uri"]
        .as_str()
        .unwrap()
        .starts_with("data:application/octet-stream;base64,"));
}

#[test]
fn no_field_no_colour() {
    smartmesh_test_support::require_public_fixtures!();
    let mut m = fixture_mesh();
    m.point_data.clear();
    let w = write(&m, &opts(None, None));
    let d = read_back(&w);
    assert!(d.colours.is_none() && d.extras.is_none() && !d.unlit);
    // Only a tensor: no scalar to pick by default, so no colours, and the report says why.
    let mut m = fixture_mesh();
    m.point_data.retain(|k, _| k == "metric");
    let w = write(&m, &opts(None, None));
    assert!(read_back(&w).colours.is_none());
    assert!(w.report.dropped.iter().any(|d| d.contains("`metric`")), "{:?}", w.report.dropped);
}

#[test]
fn lines_only_and_nothing_to_draw() {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
    m.blocks.push(CellBlock {
        kind: CellKind::Line,
        nodes: vec![0, 1, 1, 2],
        physical: vec![0, 0],
        geometrical: vec![0, 0],
    });
    let d = read_back(&write(&m, &opts(None, None)));
    assert!(d.triangles.is_empty());
    assert_eq!(d.lines, vec![0, 1, 1, 2]);
    m.blocks[0] = CellBlock {
        kind: CellKind::Vertex,
        nodes: vec![0],
        physical: vec![0],
        geometrical: vec![0],
    };
    let e = write_bytes(Format::Gltf, &m, &WriteOptions::default()).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::CannotWrite { .. }), "{e}");
}

#[test]
fn colour_field_errors() {
    smartmesh_test_support::require_public_fixtures!();
    let mut m = fixture_mesh();
    m.cell_data.insert("quality".into(), DataArray::new(1, vec![1.0; m.num_cells()]));
    m.point_data.insert("pair".into(), DataArray::new(4, vec![0.0; 4 * m.points.len()]));
    for (field, needle) in
        [("nope", "no point field `nope`"), ("quality", "cell data"), ("pair", "4 components")]
    {
        let e = write_bytes(Format::Gltf, &m, &opts(None, Some(field))).unwrap_err();
        assert!(
            matches!(e.kind, ErrorKind::CannotWrite { .. }) && e.to_string().contains(needle),
            "{field}: {e}"
        );
    }
}

#[test]
fn values_without_a_colour_are_grey() {
    smartmesh_test_support::require_public_fixtures!();
    let mut m = fixture_mesh();
    let metric = m.point_data.get_mut("metric").unwrap();
    metric.values[..9].copy_from_slice(&sym2_to_tensor9(-1.0, 0.0, -1.0, 1.0));
    let w = write(&m, &opts(None, Some("metric")));
    let d = read_back(&w);
    let c = d.colours.unwrap()[0];
    assert!(c[0] == c[1] && c[1] == c[2], "grey expected, got {c:?}");
    assert!(
        w.report.dropped.iter().any(|l| l.starts_with("1 vertices of `metric`")),
        "{:?}",
        w.report.dropped
    );
}

#[test]
fn report_lists_what_gltf_cannot_hold() {
    smartmesh_test_support::require_public_fixtures!();
    let mut m = fixture_mesh();
    m.points[1][0] = 0.1; // not a float32
    m.blocks.push(CellBlock {
        kind: CellKind::Vertex,
        nodes: vec![2],
        physical: vec![9],
        geometrical: vec![9],
    });
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle6,
        nodes: vec![0, 1, 2, 3, 4, 5],
        physical: vec![1],
        geometrical: vec![1],
    });
    m.cell_data.insert("quality".into(), DataArray::new(1, vec![1.0; m.num_cells()]));
    let w = write(&m, &opts(None, Some("metric")));
    let all = w.report.dropped.join("\n");
    for needle in [
        "119 quad cells split into 2 triangles",
        "1 vertex cells not drawn",
        "1 triangle6 cells drawn by their corners",
        "coordinates rounded to 32-bit floats",
        "glTF holds no tags",
        "tag names (Left, Right)",
        "`metric` (9 components) written only as vertex colours",
        "`size`",
        "`velocity`",
        "`quality`",
    ] {
        assert!(all.contains(needle), "report lacks {needle}:\n{all}");
    }
    // An exactly representable mesh says nothing about rounding.
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.25, 0.0]];
    m.blocks.push(CellBlock {
        kind: CellKind::Triangle,
        nodes: vec![0, 1, 2],
        physical: vec![0],
        geometrical: vec![0],
    });
    assert!(write(&m, &opts(None, None)).report.dropped.is_empty());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn prop_what_we_draw_is_the_mesh(mesh in arb_tagged_mesh(MeshFeatures::ALL), glb in any::<bool>()) {
        let o = WriteOptions { gltf: GltfWrite { glb, color_field: Some("metric".into()) }, ..opts(Some("p.gltf"), None) };
        let w = write(&mesh, &o);
        let d = read_back(&w);
        let pos: Vec<[f32; 3]> = mesh.points.iter().map(|p| [p[0] as f32, p[1] as f32, p[2] as f32]).collect();
        prop_assert_eq!(d.positions, pos);
        let (t, l) = expected_indices(&mesh);
        prop_assert_eq!(d.triangles, t);
        prop_assert_eq!(d.lines, l);
        prop_assert_eq!(d.colours.map(|c| c.len()), Some(mesh.points.len()));
    }
}

// ---------------------------------------------------------------------------------
// The Khronos glTF validator (npm `gltf-validator`) on our files.

/// The validator's package folder: `$SMARTMESH_GLTF_VALIDATOR`, or installed once with
/// npm under the test target's temporary folder. `None` (skip) when node or npm is
/// missing or the install fails, unless interop is required.
fn gltf_validator() -> Option<PathBuf> {
    let give_up = |why: String| {
        smartmesh_test_support::skip::missing_tool(&format!(
            "interop test needs the Khronos glTF validator: {why}"
        ));
        None
    };
    if Command::new("node").arg("--version").output().map(|o| !o.status.success()).unwrap_or(true) {
        return give_up("node is not available".into());
    }
    if let Ok(p) = std::env::var("SMARTMESH_GLTF_VALIDATOR") {
        return Some(PathBuf::from(p));
    }
    let prefix = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("gltf-validator");
    let package = prefix.join("node_modules/gltf-validator");
    if !package.join("package.json").exists() {
        std::fs::create_dir_all(&prefix).unwrap();
        let out = Command::new("npm")
            .args(["install", "--no-audit", "--no-fund", "--silent", "--prefix"])
            .arg(&prefix)
            .arg("gltf-validator")
            .output();
        match out {
            Ok(o) if o.status.success() && package.join("package.json").exists() => {}
            Ok(o) => {
                return give_up(format!(
                    "npm install gltf-validator failed: {}",
                    String::from_utf8_lossy(&o.stderr)
                ))
            }
            Err(e) => return give_up(format!("npm is not available: {e}")),
        }
    }
    Some(package)
}

const VALIDATE_JS: &str = r#"
const fs = require('fs'), path = require('path');
const validator = require(process.argv[2]);
(async () => {
  for (const f of process.argv.slice(3)) {
    const r = await validator.validateBytes(new Uint8Array(fs.readFileSync(f)), {
      uri: path.basename(f), maxIssues: 0, writeTimestamp: false,
      externalResourceFunction: (uri) => new Promise((res, rej) =>
        fs.readFile(path.resolve(path.dirname(f), decodeURIComponent(uri)), (e, d) => e ? rej(e.toString()) : res(new Uint8Array(d)))),
    });
    const msgs = r.issues.messages.map(m => `${m.severity} ${m.code} ${m.pointer || ''}: ${m.message}`);
    console.log(JSON.stringify({ file: path.basename(f), errors: r.issues.numErrors, warnings: r.issues.numWarnings,
      resources: (r.info && r.info.resources || []).length, messages: msgs }));
  }
})().catch(e => { console.error(e); process.exit(1); });
"#;

#[test]
fn interop_khronos_validator_finds_no_errors() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(validator) = gltf_validator() else { return };
    let dir = tempfile::tempdir().unwrap();
    let m = fixture_mesh();
    let mut files = Vec::new();
    for (name, field) in [
        ("coloured.gltf", Some("metric")),
        ("coloured.glb", Some("metric")),
        ("plain mesh.gltf", None),
        ("plain.glb", None),
    ] {
        let path = dir.path().join(name);
        smartmesh_formats::write_path(&path, &m, None, &opts(None, field)).unwrap();
        files.push(path);
    }
    let embedded = dir.path().join("embedded.gltf");
    std::fs::write(&embedded, write(&m, &opts(None, Some("size"))).main).unwrap();
    files.push(embedded);
    let script = dir.path().join("validate.js");
    std::fs::write(&script, VALIDATE_JS).unwrap();
    let out =
        Command::new("node").arg(&script).arg(&validator).args(&files).output().expect("run node");
    assert!(out.status.success(), "validator failed: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let reports: Vec<serde_json::Value> =
        text.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert_eq!(reports.len(), files.len());
    for r in &reports {
        assert_eq!(r["errors"], 0, "{r}");
        assert_eq!(r["warnings"], 0, "{r}");
    }
    // The .gltf files' buffers were loaded from the .bin beside them.
    assert!(reports[0]["resources"].as_u64().unwrap() >= 1, "{}", reports[0]);
}

/// A pyramid and a tetrahedron on one of its sides: a volume mesh is drawn by its
/// boundary faces (the shared one left out), closed and outward, with its z, and the
/// report says so.
#[test]
fn a_volume_mesh_is_drawn_by_its_boundary() {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = vec![
        [0.0, 0.0, 0.5],
        [1.0, 0.0, 0.5],
        [1.0, 1.0, 0.5],
        [0.0, 1.0, 0.5],
        [0.5, 0.5, 1.5],
        [0.5, -1.0, 1.0],
    ];
    // Gmsh's orders: the base 0-1-2-3 turns counter-clockwise seen from the apex 4;
    // the tetrahedron's 5 lies on the side of (p1 - p0) x (p4 - p0).
    m.block_mut(CellKind::Pyramid).push(&[0u32, 1, 2, 3, 4], 1, 1);
    m.block_mut(CellKind::Tetra).push(&[0u32, 1, 4, 5], 1, 1);
    let w = write(&m, &opts(Some("v.glb"), None));
    assert!(
        w.report.dropped.iter().any(|d| d.contains("boundary") && d.contains("7 faces")),
        "{:?}",
        w.report.dropped
    );
    let d = read_back(&w);
    assert_eq!(d.positions.len(), 6);
    assert_eq!(d.positions[4], [0.5, 0.5, 1.5]);
    // The base quad as 2 triangles, 3 pyramid sides, 3 tetrahedron faces.
    assert_eq!(d.triangles.len(), 3 * 8);
    let p = |i: u32| d.positions[i as usize].map(f64::from);
    let vol: f64 = d
        .triangles
        .chunks(3)
        .map(|t| {
            let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum();
    assert!((vol - (1.0 / 3.0 + 1.25 / 6.0)).abs() < 1e-12, "{vol}");
}
