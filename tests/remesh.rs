//! The native remesher against brute force, on generated meshes with analytic metric
//! fields (uniform isotropic, a boundary layer growing from a wall, a circular shock-like
//! band) and on the bundled cylinder with its recipe's field: every triangle positive,
//! boundary and interface edges exactly on the original curves and covering them, corners
//! kept, face tags equal to the tag of the input triangle under each centroid, the metric
//! at every output vertex equal to the Log-Euclidean interpolation of the input field
//! there, ≥ 90 % of edges in [1/√2, √2], deterministic.
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured or skipped is printed for the log.

use std::path::Path;

use smartmesh::formats::{sym2_to_tensor9, CellBlock, CellKind, DataArray, TaggedMesh};
use smartmesh::metric::{exp_sym, log_spd};
use smartmesh::metric::{SizeTensor, Sym2};
use smartmesh::remesh::{remesh, BoundaryMode, RemeshOptions, Remeshed};
use smartmesh::{metric_field, Conformity};
use smartmesh::{ControlError, SizeControls};
use smartmesh_test_support::grid::SquareGrid;

const WALL: i32 = 1; // y = 0
const RIGHT: i32 = 2;
const TOP: i32 = 3;
const LEFT: i32 = 4;
const INTERFACE: i32 = 5; // x = 0.5, between faces 10 and 11

/// A structured n×n grid on [0,1]² with alternating diagonals, tagged sides, and
/// optionally two faces (x < 0.5: 10, x > 0.5: 11) with an interface line tag 5.
fn square(n: usize, two_faces: bool) -> TaggedMesh {
    let mut m = SquareGrid {
        n,
        sides: [WALL, RIGHT, TOP, LEFT],
        faces: if two_faces { [10, 11] } else { [10, 10] },
        interface: two_faces.then_some(INTERFACE),
        alternate: true,
    }
    .build();
    m.coordinate_dim = 2;
    m.blocks.reverse(); // lines first
    m.tag_names.insert((1, WALL), "Wall".into());
    m
}

fn with_field(mut m: TaggedMesh, f: impl Fn(f64, f64) -> SizeTensor) -> (TaggedMesh, Vec<Sym2>) {
    let metric: Vec<Sym2> = m.points.iter().map(|p| f(p[0], p[1]).to_metric()).collect();
    let mut v = Vec::new();
    for x in &metric {
        v.extend_from_slice(&sym2_to_tensor9(x.a, x.b, x.c, 1.0));
    }
    m.point_data.insert("metric".into(), DataArray::new(9, v));
    (m, metric)
}

fn uniform(_: f64, _: f64) -> SizeTensor {
    SizeTensor::isotropic(0.05)
}

/// A boundary layer on the wall y = 0: h_normal = 0.002 + 0.2·y up to 0.05, h_tangent = 0.05.
fn boundary_layer(_: f64, y: f64) -> SizeTensor {
    SizeTensor::new([1.0, 0.0], 0.05, (0.002 + 0.2 * y).min(0.05))
}

/// A circular shock-like band of radius 0.3 around (0.5, 0.5): fine across it
/// (0.004 growing with the distance to the circle), 0.05 along it and far from it.
fn shock(x: f64, y: f64) -> SizeTensor {
    let (dx, dy) = (x - 0.5, y - 0.5);
    let r = dx.hypot(dy);
    let across = (0.004 + 0.3 * (r - 0.3).abs()).min(0.05);
    let radial = if r > 1e-12 { [dx / r, dy / r] } else { [1.0, 0.0] };
    SizeTensor::new([-radial[1], radial[0]], 0.05, across)
}

// ---- brute-force checks ---------------------------------------------------------------

fn xy(m: &TaggedMesh, v: usize) -> [f64; 2] {
    [m.points[v][0], m.points[v][1]]
}

fn triangles(m: &TaggedMesh) -> Vec<([usize; 3], i32)> {
    m.cells()
        .filter(|c| c.0 == CellKind::Triangle)
        .map(|c| ([c.1[0] as usize, c.1[1] as usize, c.1[2] as usize], c.2))
        .collect()
}

fn lines(m: &TaggedMesh) -> Vec<([usize; 2], i32)> {
    m.cells()
        .filter(|c| c.0 == CellKind::Line)
        .map(|c| ([c.1[0] as usize, c.1[1] as usize], c.2))
        .collect()
}

fn cross(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Barycentric weights of `p` in triangle `t` of `m`.
fn bary(m: &TaggedMesh, t: [usize; 3], p: [f64; 2]) -> [f64; 3] {
    let [a, b, c] = t.map(|v| xy(m, v));
    let d = cross(a, b, c);
    [cross(p, b, c) / d, cross(a, p, c) / d, cross(a, b, p) / d]
}

/// The input triangle containing `p` (brute force over every triangle): the one `p`
/// is deepest in.
fn containing(m: &TaggedMesh, p: [f64; 2]) -> ([usize; 3], i32, [f64; 3]) {
    triangles(m)
        .into_iter()
        .map(|(t, tag)| (t, tag, bary(m, t, p)))
        .max_by(|x, y| {
            x.2.iter()
                .cloned()
                .fold(f64::INFINITY, f64::min)
                .total_cmp(&y.2.iter().cloned().fold(f64::INFINITY, f64::min))
        })
        .unwrap()
}

fn assert_valid_square(
    what: &str,
    input: &TaggedMesh,
    input_metric: &[Sym2],
    out: &Remeshed,
    two_faces: bool,
) {
    let m = &out.mesh;
    let tris = triangles(m);
    assert!(!tris.is_empty(), "{what}: no triangle");
    // Every triangle strictly positive.
    for (t, _) in &tris {
        let a = cross(xy(m, t[0]), xy(m, t[1]), xy(m, t[2]));
        assert!(a > 0.0, "{what}: triangle {t:?} has area {a}");
    }
    // Boundary edges (brute force: edges of one triangle) and tagged lines.
    let mut count = std::collections::BTreeMap::new();
    for (t, _) in &tris {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let boundary: Vec<(usize, usize)> = count.iter().filter(|e| *e.1 == 1).map(|e| *e.0).collect();
    let ls = lines(m);
    let line_set: std::collections::BTreeMap<(usize, usize), i32> =
        ls.iter().map(|(l, tag)| ((l[0].min(l[1]), l[0].max(l[1])), *tag)).collect();
    for e in &boundary {
        assert!(line_set.contains_key(e), "{what}: boundary edge {e:?} has no line cell");
    }
    // Each tagged curve: every edge on its original straight side, lengths summing to the
    // side's length, edges not overlapping.
    let side = |tag: i32| -> Box<dyn Fn([f64; 2]) -> Option<f64>> {
        match tag {
            WALL => Box::new(|p: [f64; 2]| (p[1] == 0.0).then_some(p[0])),
            RIGHT => Box::new(|p: [f64; 2]| (p[0] == 1.0).then_some(p[1])),
            TOP => Box::new(|p: [f64; 2]| (p[1] == 1.0).then_some(p[0])),
            LEFT => Box::new(|p: [f64; 2]| (p[0] == 0.0).then_some(p[1])),
            _ => Box::new(|p: [f64; 2]| (p[0] == 0.5).then_some(p[1])),
        }
    };
    let tags: &[i32] =
        if two_faces { &[WALL, RIGHT, TOP, LEFT, INTERFACE] } else { &[WALL, RIGHT, TOP, LEFT] };
    for &tag in tags {
        let on = side(tag);
        let mut spans: Vec<(f64, f64)> = Vec::new();
        for (l, t) in &ls {
            if *t != tag {
                continue;
            }
            let (a, b) = (on(xy(m, l[0])), on(xy(m, l[1])));
            let (Some(a), Some(b)) = (a, b) else {
                panic!(
                    "{what}: line {l:?} of curve {tag} is off its side: {:?} {:?}",
                    xy(m, l[0]),
                    xy(m, l[1])
                )
            };
            spans.push((a.min(b), a.max(b)));
        }
        spans.sort_by(|x, y| x.0.total_cmp(&y.0));
        assert!(!spans.is_empty(), "{what}: curve {tag} vanished");
        assert_eq!(spans[0].0, 0.0, "{what}: curve {tag} does not start at its corner");
        assert_eq!(spans.last().unwrap().1, 1.0, "{what}: curve {tag} does not end at its corner");
        for k in 1..spans.len() {
            assert_eq!(
                spans[k].0,
                spans[k - 1].1,
                "{what}: curve {tag} has a gap or an overlap at {}",
                spans[k].0
            );
        }
        if tag == INTERFACE {
            // Interface edges are shared by two triangles, one of each face.
            for (l, t) in &ls {
                if *t == INTERFACE {
                    assert_eq!(
                        count[&(l[0].min(l[1]), l[0].max(l[1]))],
                        2,
                        "{what}: interface edge {l:?}"
                    );
                }
            }
        }
    }
    // Corners at the same coordinates.
    let mut corners = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    if two_faces {
        corners.extend([[0.5, 0.0], [0.5, 1.0]]);
    }
    for c in corners {
        assert!(m.points.iter().any(|p| p[0] == c[0] && p[1] == c[1]), "{what}: corner {c:?} lost");
    }
    // Face tags: the input triangle under each centroid.
    for (t, tag) in &tris {
        let p = t.map(|v| xy(m, v));
        let g = [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0];
        let (_, want, _) = containing(input, g);
        assert_eq!(*tag, want, "{what}: triangle {t:?} with centroid {g:?}");
    }
    // The metric at every vertex: the Log-Euclidean interpolation of the input field.
    let logs: Vec<Sym2> = input_metric.iter().map(log_spd).collect();
    for (v, got) in out.metric.iter().enumerate() {
        let (t, _, w) = containing(input, xy(m, v));
        let w = w.map(|x| x.max(0.0));
        let sum = w[0] + w[1] + w[2];
        let l = (w[0] / sum) * logs[t[0]] + (w[1] / sum) * logs[t[1]] + (w[2] / sum) * logs[t[2]];
        let want = exp_sym(&l);
        let scale = want.a.abs().max(want.c.abs());
        let err = (got.a - want.a).abs().max((got.b - want.b).abs()).max((got.c - want.c).abs());
        assert!(
            err <= 1e-8 * scale,
            "{what}: metric at vertex {v} {:?}: {got:?} vs {want:?}",
            xy(m, v)
        );
    }
    // The written metric and the stats agree with a fresh measurement.
    let field = metric_field(m, "metric").unwrap();
    let c = Conformity::of_mesh(m, &field).unwrap();
    assert_eq!(Some(&c), out.stats.conformity.as_ref());
}

fn run(
    what: &str,
    mesh: &TaggedMesh,
    metric: &[Sym2],
    opts: &RemeshOptions,
    two_faces: bool,
) -> Remeshed {
    let out = remesh(mesh, metric, opts).unwrap_or_else(|e| panic!("{what}: {e}"));
    let c = out.stats.conformity.as_ref().unwrap();
    eprintln!(
        "{what}: {} -> {} triangles in {} passes; in band {:.3}, mean q {:.3}, min q {:.3}",
        out.stats.input[1],
        out.stats.output[1],
        out.stats.passes,
        c.conforming_share,
        c.mean_quality,
        c.min_quality
    );
    assert_valid_square(what, mesh, metric, &out, two_faces);
    out
}

#[test]
fn uniform_isotropic_field_conforms() {
    let (mesh, metric) = with_field(square(8, false), uniform);
    let out = run("uniform", &mesh, &metric, &RemeshOptions::default(), false);
    let c = out.stats.conformity.unwrap();
    assert!(c.conforming_share >= 0.9, "{c:?}");
    // Area 1 at h = 0.05: an equilateral mesh has about 1/(√3/4 · 0.05²) ≈ 924 triangles.
    assert!((600..1400).contains(&out.stats.output[1]), "{}", out.stats.output[1]);
}

#[test]
fn boundary_layer_field_conforms_with_an_interface() {
    let (mesh, metric) = with_field(square(10, true), boundary_layer);
    let out = run("boundary layer", &mesh, &metric, &RemeshOptions::default(), true);
    let c = out.stats.conformity.unwrap();
    assert!(c.conforming_share >= 0.9, "{c:?}");
    // The wall is resolved: the shortest edge on it is ~0.05 long, the first layer ~0.002 thick.
    let m = &out.mesh;
    let near_wall = m.points.iter().filter(|p| p[1] > 0.0 && p[1] < 0.004).count();
    assert!(near_wall >= 10, "{near_wall} vertices within 0.004 of the wall");
}

#[test]
fn shock_band_field_conforms_in_both_boundary_modes() {
    let (mesh, metric) = with_field(square(10, false), shock);
    for mode in [BoundaryMode::Polyline, BoundaryMode::Smooth] {
        let opts = RemeshOptions { boundary: mode, ..RemeshOptions::default() };
        let out = run(&format!("shock {mode:?}"), &mesh, &metric, &opts, false);
        assert!(out.stats.conformity.unwrap().conforming_share >= 0.9);
    }
}

#[test]
fn remeshing_is_deterministic() {
    let (mesh, metric) = with_field(square(10, true), shock);
    let a = remesh(&mesh, &metric, &RemeshOptions::default()).unwrap();
    let b = remesh(&mesh, &metric, &RemeshOptions::default()).unwrap();
    assert_eq!(a.mesh, b.mesh);
    assert_eq!(a.metric, b.metric);
}

#[test]
fn bad_metrics_are_refused_naming_the_vertex() {
    let (mesh, mut metric) = with_field(square(4, false), uniform);
    metric[7] = Sym2::new(1.0, 2.0, 1.0);
    let e = remesh(&mesh, &metric, &RemeshOptions::default()).unwrap_err().to_string();
    assert!(e.contains("vertex 7"), "{e}");
    metric[7] = Sym2::new(f64::NAN, 0.0, 1.0);
    let e = remesh(&mesh, &metric, &RemeshOptions::default()).unwrap_err().to_string();
    assert!(e.contains("vertex 7"), "{e}");
    metric.pop();
    let e = remesh(&mesh, &metric, &RemeshOptions::default()).unwrap_err().to_string();
    assert!(e.contains("24 tensors for 25 vertices"), "{e}");
}

/// The bundled cylinder with the metric its recipe asks for: valid, corners and the
/// stagnation point kept, every boundary vertex on the original polylines.
#[test]
fn cylinder_recipe_field() {
    use smartmesh::recipe::Recipe;
    use smartmesh::sizing::compute_size_field;
    use smartmesh::{MeshGraph, Topology};
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let mesh = smartmesh::formats::read_path(&dir.join("cylinder.msh"), None).unwrap();
    let recipe = Recipe::from_path(&dir.join("cylinder.toml")).unwrap();
    let topo = Topology::from_mesh(&mesh);
    let plan = recipe.resolve(&topo).unwrap().plan;
    let graph = MeshGraph::from_topology(&topo, &mesh).unwrap();
    let field = compute_size_field(&graph, &topo, &plan, &mut |_| {}).unwrap();
    let metric: Vec<Sym2> = field.tensors.iter().map(|t| t.to_metric()).collect();
    // On the polylines, so that every boundary vertex is checked on an input segment
    // (the smooth reconstruction is checked against exact curves in remesh_curved.rs).
    let opts = RemeshOptions { boundary: BoundaryMode::Polyline, ..Default::default() };
    let out = remesh(&mesh, &metric, &opts).unwrap();
    let c = out.stats.conformity.clone().unwrap();
    eprintln!(
        "cylinder: {:?} -> {:?}, {} passes, in band {:.3}, mean q {:.3}, min q {:.3}",
        out.stats.input,
        out.stats.output,
        out.stats.passes,
        c.conforming_share,
        c.mean_quality,
        c.min_quality
    );
    let m = &out.mesh;
    for (t, _) in triangles(m) {
        assert!(cross(xy(m, t[0]), xy(m, t[1]), xy(m, t[2])) > 0.0);
    }
    // Topological points of the input (vertex cells, junctions) still at their place.
    let in_topo = Topology::from_mesh(&mesh);
    for p in &in_topo.points {
        let q = xy(&mesh, p.vertex);
        assert!(
            m.points.iter().any(|r| r[0] == q[0] && r[1] == q[1]),
            "topological point {q:?} lost"
        );
    }
    assert_eq!(m.num_cells_of(CellKind::Vertex), mesh.num_cells_of(CellKind::Vertex));
    // Every line vertex on an original line segment of the same tag.
    let segs: Vec<([f64; 2], [f64; 2], i32)> =
        lines(&mesh).into_iter().map(|(l, t)| (xy(&mesh, l[0]), xy(&mesh, l[1]), t)).collect();
    for (l, tag) in lines(m) {
        for v in l {
            let p = xy(m, v);
            let d = segs
                .iter()
                .filter(|s| s.2 == tag)
                .map(|(a, b, _)| {
                    let e = [b[0] - a[0], b[1] - a[1]];
                    let t = (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1])
                        / (e[0] * e[0] + e[1] * e[1]))
                        .clamp(0.0, 1.0);
                    (a[0] + t * e[0] - p[0]).hypot(a[1] + t * e[1] - p[1])
                })
                .fold(f64::INFINITY, f64::min);
            assert!(d < 1e-12, "line vertex {p:?} (tag {tag}) is {d} off its curve");
        }
    }
    // Per tag, the total chord length is at most the original curve's length, and close.
    let mut tags: Vec<i32> = segs.iter().map(|s| s.2).collect();
    tags.sort_unstable();
    tags.dedup();
    for tag in tags {
        let len = |pts: &[([f64; 2], [f64; 2])]| {
            pts.iter().map(|(a, b)| (b[0] - a[0]).hypot(b[1] - a[1])).sum::<f64>()
        };
        let before =
            len(&segs.iter().filter(|s| s.2 == tag).map(|s| (s.0, s.1)).collect::<Vec<_>>());
        let after = len(&lines(m)
            .into_iter()
            .filter(|l| l.1 == tag)
            .map(|(l, _)| (xy(m, l[0]), xy(m, l[1])))
            .collect::<Vec<_>>());
        assert!(
            after <= before * (1.0 + 1e-12) && after >= 0.98 * before,
            "curve {tag}: {after} vs {before}"
        );
    }
    assert!(c.conforming_share >= 0.8, "{c:?}");
    assert!(c.min_quality > 0.0);
}

/// Two components 0.01 apart: an annulus (r from 0.5 to 0.6, face 10) around a disk
/// (r = 0.49, face 11), under a coarse isotropic metric (h = 0.3). A chord of the
/// annulus' inner circle that long bulges ≈ 0.02 into the hole, across the disk's
/// boundary, and nothing in the annulus' own triangles sees the disk: only the crossing
/// guard keeps the boundaries apart.
#[test]
fn thin_gap_never_crossed() {
    let nt = 240usize;
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 2;
    // Rings: 0..3 the annulus (0.5, 0.55, 0.6), 3..6 the disk (0.49, 0.35, 0.2), then the centre.
    for r in [0.5, 0.55, 0.6, 0.49, 0.35, 0.2] {
        for i in 0..nt {
            let t = std::f64::consts::TAU * i as f64 / nt as f64;
            m.points.push([r * t.cos(), r * t.sin(), 0.0]);
        }
    }
    m.points.push([0.0, 0.0, 0.0]);
    let centre = 6 * nt;
    let id = |i: usize, j: usize| j * nt + i % nt;
    let mut tb = CellBlock::new(CellKind::Triangle);
    let mut lb = CellBlock::new(CellKind::Line);
    for i in 0..nt {
        for j in 0..2 {
            tb.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)], 10, 10);
            tb.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)], 10, 10);
        }
        for j in [4, 3] {
            // Disk rings from inside out: 5 -> 4 -> 3.
            tb.push(&[id(i, j + 1), id(i + 1, j + 1), id(i + 1, j)], 11, 11);
            tb.push(&[id(i, j + 1), id(i + 1, j), id(i, j)], 11, 11);
        }
        tb.push(&[centre, id(i, 5), id(i + 1, 5)], 11, 11);
        lb.push(&[id(i, 0), id(i + 1, 0)], 2, 2);
        lb.push(&[id(i, 2), id(i + 1, 2)], 1, 1);
        lb.push(&[id(i, 3), id(i + 1, 3)], 3, 3);
    }
    m.blocks = vec![lb, tb];
    let (mesh, metric) = with_field(m, |_, _| SizeTensor::isotropic(0.3));
    for mode in [BoundaryMode::Polyline, BoundaryMode::Smooth] {
        let out =
            remesh(&mesh, &metric, &RemeshOptions { boundary: mode, ..RemeshOptions::default() })
                .unwrap();
        let o = &out.mesh;
        let tris = triangles(o);
        assert!(tris.len() < mesh.num_cells_of(CellKind::Triangle), "{mode:?}: nothing coarsened");
        for (t, _) in &tris {
            assert!(cross(xy(o, t[0]), xy(o, t[1]), xy(o, t[2])) > 0.0, "{mode:?}");
        }
        // Brute force: no two boundary edges cross or touch away from a shared end.
        let ls: Vec<([f64; 2], [f64; 2])> =
            lines(o).into_iter().map(|(l, _)| (xy(o, l[0]), xy(o, l[1]))).collect();
        for i in 0..ls.len() {
            for j in i + 1..ls.len() {
                let (a, b) = ls[i];
                let (c, d) = ls[j];
                if a == c || a == d || b == c || b == d {
                    continue;
                }
                let s1 = cross(a, b, c) * cross(a, b, d);
                let s2 = cross(c, d, a) * cross(c, d, b);
                assert!(
                    !(s1 <= 0.0 && s2 <= 0.0),
                    "{mode:?}: boundary edges {:?} and {:?} cross",
                    ls[i],
                    ls[j]
                );
            }
        }
        // Every boundary vertex of the polyline mode on its original circle polygon.
        if mode == BoundaryMode::Polyline {
            for (l, tag) in lines(o) {
                for v in l {
                    let r = xy(o, v)[0].hypot(xy(o, v)[1]);
                    let want = [0.0, 0.6, 0.5, 0.49][tag as usize];
                    assert!(
                        r <= want + 1e-12
                            && r >= want * (std::f64::consts::PI / nt as f64).cos() - 1e-12,
                        "{mode:?}: vertex at r = {r} on curve {tag}"
                    );
                }
            }
        }
    }
}

#[test]
fn unsupported_and_broken_meshes_are_refused() {
    let (mut mesh, metric) = with_field(square(2, false), uniform);
    let mut q = mesh.clone();
    q.block_mut(CellKind::Quad).push(&[0, 1, 4, 3], 10, 10);
    let e = remesh(&q, &metric, &RemeshOptions::default()).unwrap_err().to_string();
    assert!(e.contains("quad"), "{e}");
    // A third triangle on edge 0-4 (0-based vertices of the 2x2 grid).
    mesh.block_mut(CellKind::Triangle).push(&[0, 4, 2], 10, 10);
    let e = remesh(&mesh, &metric, &RemeshOptions::default()).unwrap_err().to_string();
    assert!(e.contains("shared by 3 triangles"), "{e}");
    let (mut flat, metric) = with_field(square(2, false), uniform);
    flat.block_mut(CellKind::Triangle).push(&[0, 1, 2], 10, 10);
    let e = remesh(&flat, &metric, &RemeshOptions::default()).unwrap_err().to_string();
    assert!(e.contains("zero area"), "{e}");
}

/// The expected vertex count (the metric's complexity) is what the remesher makes, give
/// or take the boundary: within 25 % on refining, graded and anisotropic fields.
#[test]
fn expected_vertices_predict_the_output() {
    use smartmesh::expected_vertices;
    for (name, f) in [
        ("uniform", uniform as fn(f64, f64) -> SizeTensor),
        ("boundary layer", boundary_layer),
        ("shock", shock),
    ] {
        let (mesh, metric) = with_field(square(10, false), f);
        let expected = expected_vertices(&mesh, &metric);
        let made = remesh(&mesh, &metric, &RemeshOptions::default()).unwrap().stats.output[0];
        let ratio = made as f64 / expected;
        eprintln!("{name}: expected {expected:.0}, made {made} ({ratio:.3})");
        assert!((0.8..1.25).contains(&ratio), "{name}: expected {expected:.0}, made {made}");
    }
}

/// Valid but extreme metrics are refused before any work, with the estimate and the
/// option to raise (one vertex asking for h = 1e-6, entries of 1e300, h = 1e-4
/// everywhere); a raised limit or `hmin` lets the same input through.
#[test]
fn metrics_asking_for_too_many_vertices_are_refused_at_once() {
    let (mesh, metric) = with_field(square(4, false), uniform);
    let started = std::time::Instant::now();
    let mut tiny = metric.clone();
    tiny[12] = SizeTensor::isotropic(1e-6).to_metric();
    let mut huge = metric.clone();
    huge[12] = Sym2::new(1e300, 0.0, 1e300);
    let fine = vec![SizeTensor::isotropic(1e-4).to_metric(); metric.len()];
    for (name, m) in [("h = 1e-6 at one vertex", &tiny), ("1e300", &huge), ("h = 1e-4", &fine)] {
        let e = remesh(&mesh, m, &RemeshOptions::default()).unwrap_err();
        assert!(e.is_limit(), "{name}: {e}");
        let text = e.to_string();
        assert!(text.contains("--max-vertices") && text.contains("5000000"), "{name}: {text}");
    }
    assert!(started.elapsed().as_secs_f64() < 5.0, "refused before any work");
    // The estimate is in the message: 2/√3 · 10⁸ for h = 1e-4 on the unit square.
    let e = remesh(&mesh, &fine, &RemeshOptions::default()).unwrap_err().to_string();
    assert!(e.contains("1.15e8"), "{e}");
    // A limit under what the field asks for refuses a plain run too; none lets it run.
    let low = RemeshOptions { max_vertices: Some(100), ..RemeshOptions::default() };
    assert!(remesh(&mesh, &metric, &low).unwrap_err().is_limit());
    let unlimited = RemeshOptions { max_vertices: None, ..RemeshOptions::default() };
    assert!(remesh(&mesh, &metric, &unlimited).is_ok());
    // hmin, the size controls' (`remesh --hmin`), bounds the tiny size: the run goes
    // through, and no edge is much below hmin.
    let mut bounded = tiny.clone();
    SizeControls { h_min: Some(0.02), ..SizeControls::default() }
        .apply(&mesh, &mut bounded)
        .unwrap();
    let out = remesh(&mesh, &bounded, &RemeshOptions::default()).unwrap();
    assert!(out.stats.output[0] < 20_000, "{:?}", out.stats.output);
    let bad = SizeControls { h_min: Some(0.1), h_max: Some(0.01), ..SizeControls::default() };
    let e = bad.apply(&mesh, &mut metric.clone()).unwrap_err();
    assert!(matches!(e, ControlError::Bounds { .. }), "{e}");
}
