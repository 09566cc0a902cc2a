//! The partitioned remesher (`remesh::parallel`) against the serial one and against
//! brute-force checks, on meshes small enough for a debug build, with part sizes made
//! small so that all three passes run: the glued mesh is a valid conforming
//! triangulation (`smartmesh::check_mesh`: positive cells, no overlap, every edge
//! shared by at most two triangles, no hanging vertex), its boundary edges are exactly its
//! boundary line cells and cover the input's sides with their tags, the interface curve
//! and the face tags are kept, the conformity and quality are near the serial remesher's,
//! and the output is the same whatever the thread count.

use smartmesh::formats::{CellKind, TaggedMesh};
use smartmesh::metric::{SizeTensor, Sym2};
use smartmesh::remesh::{remesh, Partitioning, RemeshOptions, Remeshed};
use smartmesh::Conformity;
use smartmesh_test_support::grid::SquareGrid;

const SIDES: [i32; 4] = [1, 2, 3, 4];
const INTERFACE: i32 = 5;

/// A coarse n×n grid of the unit square, faces 10 (x < 1/2) and 11, interface line 5.
fn square(n: usize) -> TaggedMesh {
    SquareGrid { n, sides: SIDES, faces: [10, 11], interface: Some(INTERFACE), alternate: true }
        .build()
}

fn boundary_layer(_: f64, y: f64) -> SizeTensor {
    SizeTensor::new([1.0, 0.0], 0.03, (0.002 + 0.2 * y).min(0.03))
}

fn shock(x: f64, y: f64) -> SizeTensor {
    let r = ((x - 0.45).powi(2) + (y - 0.55).powi(2)).sqrt();
    let d = (r - 0.3).abs();
    let n = [(x - 0.45) / r.max(1e-9), (y - 0.55) / r.max(1e-9)];
    SizeTensor::new([-n[1], n[0]], 0.03, (0.003 + 0.3 * d).min(0.03))
}

fn metric_of(m: &TaggedMesh, f: fn(f64, f64) -> SizeTensor) -> Vec<Sym2> {
    m.points.iter().map(|p| f(p[0], p[1]).to_metric()).collect()
}

fn small_parts() -> Partitioning {
    Partitioning {
        above: 0,
        part_vertices: 1500,
        band_part_vertices: 200,
        rings: 4,
        coarse_ratio: 8,
    }
}

fn run(mesh: &TaggedMesh, metric: &[Sym2], partition: Option<Partitioning>) -> Remeshed {
    remesh(mesh, metric, &RemeshOptions { partition, ..RemeshOptions::default() }).unwrap()
}

fn tris(m: &TaggedMesh) -> Vec<([usize; 3], i32)> {
    m.cells()
        .filter(|c| c.0 == CellKind::Triangle)
        .map(|c| ([c.1[0] as usize, c.1[1] as usize, c.1[2] as usize], c.2))
        .collect()
}

fn xy(m: &TaggedMesh, v: usize) -> [f64; 2] {
    [m.points[v][0], m.points[v][1]]
}

/// Brute-force checks of a remeshed square: see the file header.
fn check_square(out: &TaggedMesh) {
    let validity = smartmesh::check_mesh(out);
    assert!(validity.is_valid(), "{:?}", validity.problems());
    let t = tris(out);
    // Every edge in one or two triangles, in opposite directions; boundary edges listed.
    let mut edges: std::collections::BTreeMap<(usize, usize), Vec<(usize, usize)>> =
        Default::default();
    for (k, (v, _)) in t.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (v[i], v[(i + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push((k, usize::from(a < b)));
        }
    }
    let mut boundary = std::collections::BTreeSet::new();
    for (e, ts) in &edges {
        assert!(ts.len() <= 2, "edge {e:?} in {} triangles", ts.len());
        if ts.len() == 2 {
            assert_ne!(ts[0].1, ts[1].1, "edge {e:?}: both triangles on one side");
        } else {
            boundary.insert(*e);
        }
    }
    // Line cells: the sides and the interface, with their lengths and positions.
    let mut length = std::collections::BTreeMap::new();
    let mut side_edges = std::collections::BTreeSet::new();
    for (kind, n, tag, _) in out.cells() {
        if kind != CellKind::Line {
            continue;
        }
        let (a, b) = (n[0] as usize, n[1] as usize);
        let (p, q) = (xy(out, a), xy(out, b));
        *length.entry(tag).or_insert(0.0) += (q[0] - p[0]).hypot(q[1] - p[1]);
        let on = |c: usize, x: f64| p[c] == x && q[c] == x;
        let placed = match tag {
            1 => on(1, 0.0),
            2 => on(0, 1.0),
            3 => on(1, 1.0),
            4 => on(0, 0.0),
            INTERFACE => on(0, 0.5),
            _ => false,
        };
        assert!(placed, "line {tag} from {p:?} to {q:?}");
        assert!(edges.contains_key(&(a.min(b), a.max(b))), "line {tag} is not a triangle edge");
        if tag != INTERFACE {
            side_edges.insert((a.min(b), a.max(b)));
        }
    }
    assert_eq!(side_edges, boundary, "boundary edges and side line cells differ");
    for tag in [1, 2, 3, 4, INTERFACE] {
        assert!((length[&tag] - 1.0).abs() < 1e-12, "curve {tag}: length {}", length[&tag]);
    }
    // Face tags by side of the interface.
    for (v, tag) in &t {
        let x = v.iter().map(|&i| out.points[i][0]).sum::<f64>() / 3.0;
        assert_eq!(*tag, if x < 0.5 { 10 } else { 11 }, "triangle {v:?}");
    }
}

fn conformity(r: &Remeshed) -> Conformity {
    r.stats.conformity.clone().unwrap()
}

#[test]
fn the_glued_mesh_is_valid_keeps_its_curves_and_conforms_like_the_serial_one() {
    let mesh = square(10);
    for (name, f) in
        [("boundary layer", boundary_layer as fn(f64, f64) -> SizeTensor), ("shock", shock)]
    {
        let metric = metric_of(&mesh, f);
        let serial = run(&mesh, &metric, None);
        let parts = run(&mesh, &metric, Some(small_parts()));
        check_square(&serial.mesh);
        check_square(&parts.mesh);
        let (s, p) = (conformity(&serial), conformity(&parts));
        eprintln!(
            "{name}: serial {} vertices, {:.3} conforming, quality mean {:.3} min {:.3}, lengths {:?}; \
             parts {} vertices, {:.3} conforming, quality mean {:.3} min {:.3}, lengths {:?}",
            serial.stats.output[0], s.conforming_share, s.mean_quality, s.min_quality, s.edge_length_range,
            parts.stats.output[0], p.conforming_share, p.mean_quality, p.min_quality, p.edge_length_range,
        );
        eprintln!("{name}: per pass {:?}", parts.stats.per_pass);
        assert_eq!(parts.stats.passes, 4, "{name}: the coarse pass and three passes ran");
        let ratio = parts.stats.output[0] as f64 / serial.stats.output[0] as f64;
        // Within 10 %: both conform, and the counts of conforming meshes differ that much.
        assert!((0.9..1.1).contains(&ratio), "{name}: vertices {ratio}");
        assert!(p.conforming_share >= s.conforming_share - 0.02, "{name}");
        assert!(p.mean_quality >= s.mean_quality - 0.02, "{name}");
        // No region left unadapted: no edge much longer than the serial remesher leaves.
        assert!(p.edge_length_range[1] <= s.edge_length_range[1].max(2.0), "{name}");
    }
}

#[test]
fn the_output_is_the_same_whatever_the_thread_count() {
    let mesh = square(10);
    let metric = metric_of(&mesh, shock);
    let mut outs = Vec::new();
    for threads in [1, 2, 4] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        outs.push(pool.install(|| run(&mesh, &metric, Some(small_parts()))));
    }
    assert_eq!(outs[0].mesh, outs[1].mesh);
    assert_eq!(outs[0].mesh, outs[2].mesh);
    assert_eq!(outs[0].metric, outs[2].metric);
    assert_eq!(outs[0].stats.per_pass, outs[2].stats.per_pass);
}

#[test]
fn small_meshes_stay_on_the_serial_path() {
    let mesh = square(10);
    let metric = metric_of(&mesh, boundary_layer);
    let default = run(&mesh, &metric, Some(Partitioning::default()));
    let serial = run(&mesh, &metric, None);
    assert_eq!(default.mesh, serial.mesh);
}

#[path = "support/cli.rs"]
mod cli;

/// `smartmesh remesh --partition-above 0` on the cylinder: the same bytes with 1, 2 and
/// 4 threads (RAYON_NUM_THREADS) and with `--threads 3`, a valid mesh, and the
/// partitioned passes in the statistics.
#[test]
fn the_cli_writes_the_same_bytes_whatever_the_thread_count() {
    use cli::{bundled, ok, smartmesh};
    let dir = tempfile::tempdir().unwrap();
    let field = dir.path().join("field.vtu");
    let field = field.to_str().unwrap();
    let size = ["size", &bundled("cylinder.msh"), "--recipe", &bundled("cylinder.toml")];
    ok(&smartmesh(&[&size[..], &["-o", field]].concat(), None));
    let mut outputs = Vec::new();
    for (i, (env, flag)) in
        [(Some("1"), "0"), (Some("2"), "0"), (Some("4"), "0"), (None, "3")].into_iter().enumerate()
    {
        let out = dir.path().join(format!("out{i}.msh"));
        let args = [
            "remesh",
            &bundled("cylinder.msh"),
            "--metric",
            field,
            "--partition-above",
            "0",
            "--threads",
            flag,
            "--json",
            "-o",
            out.to_str().unwrap(),
        ];
        let json: serde_json::Value = serde_json::from_str(&ok(&smartmesh(&args, env))).unwrap();
        assert!(json["passes"].as_u64().unwrap() >= 2, "{json}");
        assert!(json["conformity"]["conforming_share"].as_f64().unwrap() >= 0.9, "{json}");
        outputs.push(std::fs::read(&out).unwrap());
    }
    for o in &outputs[1..] {
        assert!(o == &outputs[0], "outputs differ with the thread count");
    }
    let mesh = smartmesh::formats::read_path(&dir.path().join("out0.msh"), None).unwrap();
    let validity = smartmesh::check_mesh(&mesh);
    assert!(validity.is_valid(), "{:?}", validity.problems());
    assert_eq!(mesh.tag_name(2, 10), Some("Fluid"));
}
