//! Neighbour propagation against its brute-force twin (thesis 2.2.10.4: "brute force
//! and neighbour propagation"): exactness on non-convex sources over randomised meshes,
//! the max-distance cut-off, the coarse-mesh wake, and determinism across thread counts.
//!
//! Every mesh here is made by the test itself: jittered structured triangulations of a
//! rectangle (each vertex moved by up to `jitter` times the spacing, each quad split
//! along a random diagonal), seeded so that a failure replays.
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured or skipped is printed for the log.

use proptest::prelude::*;
use smartmesh::formats::{CellBlock, CellKind, TaggedMesh};
use smartmesh::sizing::{
    closest_point_brute_force, propagate, ClosestPoint, PropagationOptions, Reach, Source,
};
use smartmesh::Point2;
use smartmesh::{MeshGraph, Topology};

use smartmesh_test_support::grid::{triangles_crossed_by, JitteredGrid as Grid};
use smartmesh_test_support::measure::distance_to_segment;
use smartmesh_test_support::{Generator, SplitMix64 as Rng};

/// The mesh graph of a grid.
trait GraphOf {
    fn graph(&self) -> MeshGraph;
}

impl GraphOf for Grid {
    fn graph(&self) -> MeshGraph {
        let mut edges = Vec::with_capacity(3 * self.triangles.len());
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges.push([a.min(b), a.max(b)]);
            }
        }
        edges.sort_unstable();
        edges.dedup();
        let cells: Vec<[usize; 4]> =
            self.triangles.iter().map(|t| [t[0], t[1], t[2], usize::MAX]).collect();
        MeshGraph::from_edges(self.coords.clone(), &edges, &cells).unwrap()
    }
}

#[derive(Debug, Default)]
struct Tally {
    vertices: usize,
    /// Distance off by more than 1e-9 relative, or a different foot point without a tie.
    mismatches: usize,
    /// Any field not bit-identical to the brute-force twin.
    not_bitwise: usize,
    /// Vertices whose answer a clearance certified (no index search).
    certified: usize,
}

/// Compares every reached vertex with the brute-force twin.
fn check_exact(graph: &MeshGraph, source: &Source, reach: &Reach) -> Tally {
    let mut t = Tally::default();
    for (v, got) in reach.iter() {
        let want = closest_point_brute_force(source, graph.point(v)).unwrap();
        t.vertices += 1;
        if got != want {
            t.not_bitwise += 1;
        }
        let rel = (got.distance - want.distance).abs() / want.distance.max(1e-300);
        let same_foot = (got.foot[0] - want.foot[0]).hypot(got.foot[1] - want.foot[1])
            <= 1e-9 * want.distance.max(1e-12);
        // A tie: the propagated segment is as close as the brute-force one.
        let seg = source.segments()[got.segment as usize];
        let tie_d = distance_to_segment(graph.point(v), seg.a, seg.b);
        let tie = (tie_d - want.distance).abs() <= 1e-9 * want.distance.max(1e-300);
        if (rel > 1e-9 && want.distance > 0.0) || (!same_foot && !tie) {
            t.mismatches += 1;
        }
    }
    t
}

/// Checks the cut-off rules against brute-force distances of every vertex.
fn check_cutoff(graph: &MeshGraph, source: &Source, reach: &Reach, max: f64) {
    let seeds: std::collections::BTreeSet<u32> = source.seeds().iter().copied().collect();
    for v in 0..graph.num_vertices() {
        let d = closest_point_brute_force(source, graph.point(v)).unwrap().distance;
        match reach.get(v) {
            Some(c) => {
                assert_eq!(c.distance.to_bits(), d.to_bits());
                if seeds.contains(&(v as u32)) {
                    assert!(
                        d <= graph.longest_edge(v) + 1e-12,
                        "seed {v} at {d} is more than one edge from the source"
                    );
                } else {
                    assert!(d <= max, "vertex {v} reported at {d} > {max}");
                }
            }
            None => assert!(d > max, "vertex {v} at {d} <= {max} was not reached"),
        }
    }
}

fn run_case(name: &str, graph: &MeshGraph, source: &Source, max: f64) -> Tally {
    let reach = propagate(graph, source, max, &PropagationOptions::new());
    let t = check_exact(graph, source, &reach);
    let r = reach.report();
    eprintln!(
        "{name}: {} vertices reached, {} evaluated, {} segments, {} certified by a clearance, {} corrected by the index, {:.1} boxes + {:.1} segments per vertex, mismatches {}, not bit-identical {}",
        reach.len(),
        r.evaluated,
        source.segments().len(),
        r.certified_locally,
        r.corrected,
        r.boxes_tested as f64 / r.evaluated as f64,
        r.segments_tested as f64 / r.evaluated as f64,
        t.mismatches,
        t.not_bitwise
    );
    Tally { certified: r.certified_locally, ..t }
}

/// A cambered airfoil-like closed curve (NACA 4-digit shape), `n` points per side,
/// chord 1 from `(0, 0)`, with a thin trailing edge.
fn airfoil(n: usize, thickness: f64, camber: f64) -> Vec<Point2> {
    let shape = |x: f64| {
        let yt = 5.0
            * thickness
            * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x * x + 0.2843 * x.powi(3)
                - 0.1036 * x.powi(4));
        let p = 0.4;
        let yc = if x < p {
            camber / (p * p) * (2.0 * p * x - x * x)
        } else {
            camber / ((1.0 - p) * (1.0 - p)) * ((1.0 - 2.0 * p) + 2.0 * p * x - x * x)
        };
        (yc, yt)
    };
    let mut pts = Vec::new();
    // Upper side from the trailing edge to the leading edge, then the lower side back.
    for k in 0..n {
        let x = 0.5 * (1.0 + (std::f64::consts::PI * k as f64 / n as f64).cos());
        let (yc, yt) = shape(x);
        pts.push([x, yc + yt]);
    }
    for k in 0..n {
        let x = 0.5 * (1.0 - (std::f64::consts::PI * k as f64 / n as f64).cos());
        let (yc, yt) = shape(x);
        pts.push([x, yc - yt]);
    }
    pts
}

#[test]
fn exactness_campaign_on_non_convex_sources() {
    let mut total = Tally::default();
    let mut add = |t: Tally| {
        total.vertices += t.vertices;
        total.mismatches += t.mismatches;
        total.not_bitwise += t.not_bitwise;
        total.certified += t.certified;
    };

    // 1. Airfoil-like closed curve, free polyline, on a mesh about as coarse as the
    //    airfoil is thick near its trailing edge.
    let g = Grid::new(181, 151, [-0.8, -0.75], 0.01, 0.3, 1);
    let graph = g.graph();
    let foil: Vec<Point2> =
        airfoil(300, 0.12, 0.04).into_iter().map(|p| [p[0] * 1.2 - 0.2, p[1] * 1.2]).collect();
    let source = Source::builder(&graph).polyline(&foil, true).build().unwrap();
    add(run_case("airfoil", &graph, &source, f64::INFINITY));

    // 2. S-shaped curve, free polyline.
    let g = Grid::new(171, 171, [0.0, 0.0], 0.006, 0.3, 2);
    let graph = g.graph();
    let s: Vec<Point2> = (0..=600)
        .map(|k| {
            let u = k as f64 / 600.0;
            let a = 2.0 * std::f64::consts::PI * (u - 0.5) * 1.5;
            [0.5 + 0.35 * a.sin() * (1.0 - 0.3 * u), 0.1 + 0.8 * u]
        })
        .collect();
    let source = Source::builder(&graph).polyline(&s, false).build().unwrap();
    add(run_case("S-curve", &graph, &source, f64::INFINITY));

    // 3. U-bend along mesh edges, arms 2 edges apart, on a jittered mesh.
    let g = Grid::new(161, 161, [0.0, 0.0], 0.01, 0.3, 3);
    let graph = g.graph();
    let mut u = g.row(80, 20, 140);
    u.extend(g.column(140, 80, 82).into_iter().skip(1));
    u.extend(g.row(82, 140, 30).into_iter().skip(1));
    let source = Source::builder(&graph).mesh_polyline(&u, false).build().unwrap();
    add(run_case("U-bend (mesh edges, gap 2 edges)", &graph, &source, f64::INFINITY));

    // 4. Two close walls, free polylines 1.3 edges apart, wavy so that the medial axis
    //    between them is not a grid line.
    let g = Grid::new(161, 161, [0.0, 0.0], 0.01, 0.3, 4);
    let graph = g.graph();
    let wall = |y0: f64| -> Vec<Point2> {
        (0..=250)
            .map(|k| [0.1 + 1.4 * k as f64 / 250.0, y0 + 0.02 * (9.0 * k as f64 / 250.0).sin()])
            .collect()
    };
    let source = Source::builder(&graph)
        .polyline(&wall(0.8), false)
        .polyline(&wall(0.813), false)
        .build()
        .unwrap();
    add(run_case("two close walls (free, gap 1.3 edges)", &graph, &source, f64::INFINITY));

    // 5. Two walls along mesh rows one edge apart.
    let g = Grid::new(141, 141, [0.0, 0.0], 0.01, 0.3, 5);
    let graph = g.graph();
    let source = Source::builder(&graph)
        .mesh_polyline(&g.row(70, 10, 130), false)
        .mesh_polyline(&g.row(71, 130, 10), false)
        .build()
        .unwrap();
    add(run_case("two walls (mesh edges, gap 1 edge)", &graph, &source, f64::INFINITY));

    // 6. A polyline that doubles back on itself: hairpins 0.4 edge apart.
    let g = Grid::new(151, 151, [0.0, 0.0], 0.01, 0.3, 6);
    let graph = g.graph();
    let mut z = Vec::new();
    for k in 0..6 {
        let y = 0.3 + 0.004 * k as f64 + 0.1 * (k / 2) as f64;
        let (x0, x1) = if k % 2 == 0 { (0.2, 1.3) } else { (1.3, 0.25) };
        for m in 0..=40 {
            let x = x0 + (x1 - x0) * m as f64 / 40.0;
            z.push([x, y + 0.01 * (20.0 * x).sin()]);
        }
    }
    let source = Source::builder(&graph).polyline(&z, false).build().unwrap();
    add(run_case("polyline doubling back", &graph, &source, f64::INFINITY));

    // 7. A coarse mesh around a fine, wiggly closed curve (many segments per cell).
    let g = Grid::new(121, 121, [-1.2, -1.2], 0.02, 0.3, 7);
    let graph = g.graph();
    let star: Vec<Point2> = (0..2000)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / 2000.0;
            let r = 0.7 + 0.25 * (7.0 * a).cos() + 0.02 * (90.0 * a).sin();
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    let source =
        Source::builder(&graph).polyline(&star, true).vertex(g.vertex(60, 60)).build().unwrap();
    add(run_case("star with fine wiggles + a point", &graph, &source, f64::INFINITY));

    eprintln!(
        "total: {} vertices, {} certified by a clearance, {} mismatches, {} not bit-identical",
        total.vertices, total.certified, total.mismatches, total.not_bitwise
    );
    assert!(total.vertices >= 100_000);
    // Most answers come from the clearance certificate, so the campaign tests it, not
    // only the index search behind it.
    assert!(
        total.certified * 5 >= total.vertices * 2,
        "{} of {} certified by a clearance",
        total.certified,
        total.vertices
    );
    assert_eq!(total.mismatches, 0);
    assert_eq!(total.not_bitwise, 0);
}

/// The clearance certificate (a closest point decided by the segments around it, no
/// index search) on random smooth curves, open and closed, with sharp corners and
/// close passes: every answer is the brute-force one, bit for bit, and a good share of
/// them (at least 30 %) come from the certificate.
#[test]
fn clearance_certificates_match_brute_force_on_random_curves() {
    let mut rng = Rng(77);
    let mut total = Tally::default();
    for case in 0..24 {
        let g = Grid::new(71, 71, [-1.1, -1.1], 2.2 / 70.0, 0.3, 100 + case);
        let graph = g.graph();
        // Tens of vertices per segment, so that most segments earn a clearance.
        let n = 60 + (rng.unit() * 340.0) as usize;
        let closed = case % 3 != 0;
        let modes: Vec<(f64, f64, f64)> = (0..4)
            .map(|m| (rng.unit() * 0.25 / (m + 1) as f64, (m + 2) as f64, rng.unit() * 6.3))
            .collect();
        let corner_every =
            if case % 4 == 1 { 1 + (rng.unit() * 50.0) as usize } else { usize::MAX };
        let mut pts: Vec<Point2> = (0..n)
            .map(|k| {
                let span = if closed { 2.0 * std::f64::consts::PI } else { 4.0 };
                let a = span * k as f64 / n as f64;
                let r =
                    0.6 + modes.iter().map(|&(amp, f, ph)| amp * (f * a + ph).cos()).sum::<f64>();
                // Every `corner_every`-th point pushed out: a polyline with corners.
                let r = if k % corner_every == 0 { r * 1.08 } else { r };
                [r * a.cos(), r * a.sin()]
            })
            .collect();
        if case % 5 == 2 {
            // A second curve passing close by.
            pts.truncate(n / 2);
        }
        let mut b = Source::builder(&graph);
        b.polyline(&pts, closed);
        if case % 5 == 2 {
            let other: Vec<Point2> = pts.iter().map(|p| [p[0] * 0.97, p[1] * 0.97]).collect();
            b.polyline(&other, false);
        }
        let source = b.build().unwrap();
        let reach = propagate(&graph, &source, f64::INFINITY, &PropagationOptions::new());
        let t = check_exact(&graph, &source, &reach);
        total.vertices += t.vertices;
        total.mismatches += t.mismatches;
        total.not_bitwise += t.not_bitwise;
        total.certified += reach.report().certified_locally;
    }
    eprintln!("random curves: {} vertices, {} certified by a clearance, {} mismatches, {} not bit-identical", total.vertices, total.certified, total.mismatches, total.not_bitwise);
    assert_eq!((total.mismatches, total.not_bitwise), (0, 0));
    assert!(
        total.certified * 10 >= total.vertices * 3,
        "{} of {} certified",
        total.certified,
        total.vertices
    );
}

/// Vertices whose foot lies a hair from a segment end, far out on the side away from
/// which the polyline turns (or on a straight run of collinear segments): there the
/// propagation takes the segment without projecting on its neighbours, and the next
/// segment is as close to within rounding. Columns of vertices at segment ends offset
/// by 0, ±10^-12, ±10^-9 and ±10^-6 of a segment length, rows from 10^-3 to 10^3
/// segment lengths out; a straight wall along y = 0 and a convex arc seen from outside.
/// Every answer must be the brute-force scan's, bit for bit.
#[test]
fn feet_next_to_segment_ends_on_convex_sides_and_straight_runs() {
    let offsets = [-1e-6, -1e-9, -1e-12, 0.0, 1e-12, 1e-9, 1e-6, 0.5];
    let heights: Vec<f64> =
        std::iter::once(0.0).chain((0..30).map(|k| 1e-3 * 1.6f64.powi(k))).collect();
    // Segment ends: uneven lengths about 1 along a line, or angles along an arc of radius 50.
    let ends: Vec<f64> = (0..=20)
        .scan(0.0, |x, k| {
            let at = *x;
            *x += 1.0 + 0.3 * (k as f64).sin();
            Some(at)
        })
        .collect();
    let mut columns: Vec<f64> = Vec::new();
    for w in ends.windows(2) {
        let len = w[1] - w[0];
        columns.extend(offsets.iter().map(|o| w[0] + o * len).filter(|&x| x >= 0.0));
    }
    columns.push(*ends.last().unwrap());
    columns.sort_by(f64::total_cmp);
    columns.dedup();
    let mut total = Tally::default();
    for arc in [false, true] {
        let (nx, ny) = (columns.len(), heights.len());
        let mut g = Grid::new(nx, ny, [0.0, 0.0], 1.0, 0.0, 3);
        let radius = 50.0;
        let place = |along: f64, out: f64| -> Point2 {
            if arc {
                // Arc length `along` on the circle, `out` beyond it.
                let a = along / radius;
                [(radius + out) * a.cos(), (radius + out) * a.sin()]
            } else {
                [along, out]
            }
        };
        for (j, &y) in heights.iter().enumerate() {
            for (i, &x) in columns.iter().enumerate() {
                g.coords[j * nx + i] = place(x, y);
            }
        }
        let graph = g.graph();
        let wall: Vec<Point2> = ends.iter().map(|&x| place(x, 0.0)).collect();
        // Clockwise along the arc's outside is the polyline's right: both sides are tried.
        for reversed in [false, true] {
            let pts: Vec<Point2> =
                if reversed { wall.iter().rev().copied().collect() } else { wall.clone() };
            let source = Source::builder(&graph).polyline(&pts, false).build().unwrap();
            let t = run_case(
                if arc { "convex arc" } else { "straight wall" },
                &graph,
                &source,
                f64::INFINITY,
            );
            total.vertices += t.vertices;
            total.mismatches += t.mismatches;
            total.not_bitwise += t.not_bitwise;
            total.certified += t.certified;
        }
    }
    assert_eq!((total.mismatches, total.not_bitwise), (0, 0), "{total:?}");
    assert!(
        total.certified * 2 >= total.vertices,
        "{total:?}: the clearances should certify most of these vertices"
    );
}

/// Work per vertex stays O(1) amortised (thesis 7.3.5): the segment index looks at a
/// bounded number of boxes and segments per evaluated vertex, and that number does not
/// grow with the mesh: 10 times more vertices, with the source refined alike (the same
/// number of segments per mesh edge) or not at all. A scan per vertex would grow with
/// the segments. Counts, not clocks.
#[test]
fn work_per_vertex_does_not_grow_with_the_source_or_the_mesh() {
    let mut per_vertex = Vec::new();
    for (n, segments) in [(101usize, 1000usize), (317, 3162), (317, 1000)] {
        let g = Grid::new(n, n, [0.0, 0.0], 1.0 / (n - 1) as f64, 0.3, 51);
        let graph = g.graph();
        let curve: Vec<Point2> = (0..segments)
            .map(|k| {
                let a = 2.0 * std::f64::consts::PI * k as f64 / segments as f64;
                let r = 0.3 + 0.08 * (7.0 * a).cos() + 0.01 * (40.0 * a).sin();
                [0.5 + r * a.cos(), 0.5 + r * a.sin()]
            })
            .collect();
        let source = Source::builder(&graph).polyline(&curve, true).build().unwrap();
        let reach = propagate(&graph, &source, f64::INFINITY, &PropagationOptions::new());
        assert_eq!(reach.len(), n * n, "every vertex reached");
        let r = reach.report();
        let (boxes, segs) = (
            r.boxes_tested as f64 / r.evaluated as f64,
            r.segments_tested as f64 / r.evaluated as f64,
        );
        eprintln!("{} vertices, {segments} segments: {boxes:.1} boxes and {segs:.1} segments tested per vertex", n * n);
        assert!(segs < 0.05 * segments as f64, "{segs} segments per vertex: a scan of the source");
        per_vertex.push((boxes, segs));
    }
    let (b0, s0) = per_vertex[0];
    for &(b1, s1) in &per_vertex[1..] {
        assert!(
            b1 <= 1.5 * b0 + 4.0 && s1 <= 1.5 * s0 + 4.0,
            "work per vertex grew: {b0:.1} -> {b1:.1} boxes, {s0:.1} -> {s1:.1} segments"
        );
    }
}

#[test]
fn source_from_topology_curves_and_points() {
    // A 40 × 40 jittered grid as a TaggedMesh: a tagged line along a U of mesh edges
    // (tag 5) and a tagged vertex (tag 9).
    let g = Grid::new(40, 40, [0.0, 0.0], 0.1, 0.3, 11);
    let mut mesh = TaggedMesh::new();
    mesh.points = g.coords.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let mut tris = CellBlock::new(CellKind::Triangle);
    for t in &g.triangles {
        tris.push(t, 1, 1);
    }
    let mut lines = CellBlock::new(CellKind::Line);
    let mut u = g.row(20, 5, 30);
    u.extend(g.column(30, 20, 22).into_iter().skip(1));
    u.extend(g.row(22, 30, 8).into_iter().skip(1));
    for w in u.windows(2) {
        lines.push(w, 5, 5);
    }
    let mut verts = CellBlock::new(CellKind::Vertex);
    verts.push(&[g.vertex(10, 5)], 9, 9);
    mesh.blocks = vec![verts, lines, tris];
    let topo = Topology::from_mesh(&mesh);
    let graph = MeshGraph::from_topology(&topo, &mesh).unwrap();
    let curve = topo.curves.iter().position(|c| c.tag == Some(5)).unwrap();
    let point = topo.points.iter().position(|p| p.tag == Some(9)).unwrap();
    let source = Source::builder(&graph)
        .topology_curve(&topo, curve)
        .topology_point(&topo, point)
        .build()
        .unwrap();
    let reach = propagate(&graph, &source, 0.7, &PropagationOptions::new());
    let t = check_exact(&graph, &source, &reach);
    assert_eq!((t.mismatches, t.not_bitwise), (0, 0));
    check_cutoff(&graph, &source, &reach, 0.7);
    // Vertices of the curve are at distance 0, abscissa along the U.
    let c = reach.get(u[3]).unwrap();
    assert_eq!(c.distance, 0.0);
    assert!(c.abscissa > 0.0);
    // Out-of-range entities are errors, not panics.
    assert!(Source::builder(&graph).topology_curve(&topo, 99).build().is_err());
    assert!(Source::builder(&graph).vertex(1_000_000).build().is_err());
    assert!(Source::builder(&graph).polyline(&[[0.0, f64::NAN]], false).build().is_err());
    assert!(Source::builder(&graph).polyline(&[], false).build().is_err());
}

#[test]
fn max_distance_cut_off() {
    let g = Grid::new(90, 90, [0.0, 0.0], 0.02, 0.3, 21);
    let graph = g.graph();
    let foil: Vec<Point2> =
        airfoil(80, 0.12, 0.02).into_iter().map(|p| [p[0] + 0.4, p[1] + 0.9]).collect();
    let mut u = g.row(20, 10, 70);
    u.extend(g.column(70, 20, 22).into_iter().skip(1));
    u.extend(g.row(22, 70, 10).into_iter().skip(1));
    let sources = [
        Source::builder(&graph).polyline(&foil, true).build().unwrap(),
        Source::builder(&graph).mesh_polyline(&u, false).build().unwrap(),
        Source::builder(&graph).vertex(g.vertex(45, 60)).point([0.33, 1.21]).build().unwrap(),
    ];
    for source in &sources {
        for max in [0.0, 0.01, 0.05, 0.13, 0.4] {
            let reach = propagate(&graph, source, max, &PropagationOptions::new());
            check_cutoff(&graph, source, &reach, max);
        }
    }
}

/// Item 5 of issue 3: a wake with a tiny max distance on a mesh with edge length 1
/// must still mark the vertices of every triangle it crosses.
#[test]
fn coarse_mesh_wake_marks_every_crossed_triangle() {
    let g = Grid::new(11, 11, [0.0, 0.0], 1.0, 0.25, 31);
    let graph = g.graph();
    let wake: Vec<Point2> = (0..=20)
        .map(|k| [2.3 + 0.3 * k as f64, 4.6 + 0.04 * k as f64 + 0.5 * (0.5 * k as f64).sin()])
        .collect();
    let source = Source::builder(&graph).polyline(&wake, false).build().unwrap();
    let reach = propagate(&graph, &source, 0.05, &PropagationOptions::new());
    // Independent oracle: triangles that contain a point of the wake sampled every 1e-3.
    let crossed = triangles_crossed_by(&g.coords, &g.triangles, &wake);
    for &t in &crossed {
        for &v in &g.triangles[t] {
            assert!(reach.get(v).is_some(), "vertex {v} of a crossed triangle is not marked");
        }
    }
    let crossed = crossed.len();
    assert!(crossed >= 8, "the wake should cross several triangles, crossed {crossed}");
    let t = check_exact(&graph, &source, &reach);
    assert_eq!((t.mismatches, t.not_bitwise), (0, 0));
    // Nothing but the crossed cells' corners: all of them lie within one edge.
    assert!(reach.iter().all(|(v, c)| c.distance <= 0.05 || source.seeds().contains(&(v as u32))));
}

#[test]
fn same_output_whatever_the_thread_count() {
    let g = Grid::new(200, 200, [0.0, 0.0], 0.01, 0.3, 41);
    let graph = g.graph();
    // Many rows as sources, so that levels are large enough to run in parallel.
    let mut b = Source::builder(&graph);
    for j in (5..200).step_by(12) {
        b.mesh_polyline(&g.row(j, 3, 196), false);
    }
    let s: Vec<Point2> = (0..=300)
        .map(|k| [0.1 + 1.8 * k as f64 / 300.0, 1.0 + 0.3 * (k as f64 / 20.0).sin()])
        .collect();
    b.polyline(&s, false);
    let source = b.build().unwrap();
    let run = |threads: usize, parallel: bool| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| {
            propagate(&graph, &source, 0.3, &PropagationOptions::new().with_parallel(parallel))
        })
    };
    let serial = run(1, false);
    let key =
        |r: &Reach| (r.vertices().to_vec(), r.closest_points().collect::<Vec<_>>(), *r.report());
    for threads in [1, 2, 4] {
        let r = run(threads, true);
        assert_eq!(key(&r), key(&serial), "{threads} threads");
    }
    assert!(serial.len() > 30_000);
}

#[test]
fn side_and_abscissa() {
    let graph = MeshGraph::from_edges(vec![[0.0, 0.0]], &[], &[]).unwrap();
    // A counter-clockwise square: the inside is on the left.
    let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let source = Source::builder(&graph).polyline(&sq, true).build().unwrap();
    let c = source.closest_point([0.5, 0.2]).unwrap();
    assert_eq!((c.segment, c.side, c.parameter), (0, 1, 0.5));
    assert!((c.distance - 0.2).abs() < 1e-15);
    let c = source.closest_point([1.5, 0.5]).unwrap();
    assert_eq!((c.segment, c.side), (1, -1));
    assert!((c.abscissa - 1.5).abs() < 1e-15);
    // Outside a corner: the foot is the corner, side from the corner's mean normal.
    let c = source.closest_point([1.3, -0.2]).unwrap();
    assert_eq!((c.foot, c.side), ([1.0, 0.0], -1));
    let c = source.closest_point([0.9, 0.8]).unwrap();
    assert_eq!(c.side, 1);
    assert!((c.signed_distance() - 0.1).abs() < 1e-12);
    // A point source has no side.
    let p = Source::builder(&graph).point([2.0, 2.0]).build().unwrap();
    assert_eq!(p.closest_point([3.0, 2.0]).map(|c| (c.distance, c.side)), Some((1.0, 0)));
}

fn eq_brute(source: &Source, p: Point2) -> Result<(), TestCaseError> {
    let a: Option<ClosestPoint> = source.closest_point(p);
    let b = closest_point_brute_force(source, p);
    prop_assert_eq!(a, b);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random polylines (open or closed, possibly self-crossing, with repeated points)
    /// and random point clouds: the index query equals the brute-force scan.
    #[test]
    fn index_matches_brute_force_on_random_polylines(
        polys in prop::collection::vec((prop::collection::vec((-1.0f64..2.0, -1.0f64..2.0), 1..40), any::<bool>()), 1..4),
        cloud in prop::collection::vec((-2.0f64..3.0, -2.0f64..3.0), 1..200),
    ) {
        let graph = MeshGraph::from_edges(vec![[0.0, 0.0]], &[], &[]).unwrap();
        let mut b = Source::builder(&graph);
        for (pts, closed) in &polys {
            let pts: Vec<Point2> = pts.iter().map(|&(x, y)| [x, y]).collect();
            b.polyline(&pts, *closed);
        }
        let source = b.build().unwrap();
        for &(x, y) in &cloud {
            eq_brute(&source, [x, y])?;
        }
        // Points of the source itself, and a vertex shared by two segments.
        for s in source.segments() {
            eq_brute(&source, s.a)?;
            eq_brute(&source, [0.5 * (s.a[0] + s.b[0]), 0.5 * (s.a[1] + s.b[1])])?;
        }
    }

    /// Random polylines on a random coarse mesh: the propagation is exact and cut off
    /// where it should be.
    #[test]
    fn propagation_matches_brute_force_on_random_polylines(
        seed in any::<u64>(),
        pts in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0), 1..25),
        closed in any::<bool>(),
        max in 0.0f64..0.6,
    ) {
        let g = Grid::new(24, 24, [0.0, 0.0], 1.0 / 23.0, 0.3, seed);
        let graph = g.graph();
        let pts: Vec<Point2> = pts.iter().map(|&(x, y)| [x, y]).collect();
        let source = Source::builder(&graph).polyline(&pts, closed).build().unwrap();
        let reach = propagate(&graph, &source, max, &PropagationOptions::new());
        let t = check_exact(&graph, &source, &reach);
        prop_assert_eq!((t.mismatches, t.not_bitwise), (0, 0));
        check_cutoff(&graph, &source, &reach, max);
    }
}
