//! The propagation's closest points against the brute-force scan, bit for bit.

use super::*;
use crate::geometry::test_support::Rng;
use crate::geometry::{Nearest, Point2, QueryStats};
use crate::mesh_graph::MeshGraph;

/// A jittered `k × k` grid on [0, 1]² joined by its grid edges, plus `extra`
/// isolated pairs of vertices far off (other components).
fn grid(k: usize, rng: &mut Rng, extra: usize) -> MeshGraph {
    let mut coords = Vec::new();
    for j in 0..k {
        for i in 0..k {
            coords.push([
                (i as f64 + 0.3 * rng.unit()) / k as f64,
                (j as f64 + 0.3 * rng.unit()) / k as f64,
            ]);
        }
    }
    let mut edges = Vec::new();
    for j in 0..k {
        for i in 0..k {
            if i + 1 < k {
                edges.push([j * k + i, j * k + i + 1]);
            }
            if j + 1 < k {
                edges.push([j * k + i, (j + 1) * k + i]);
            }
        }
    }
    for e in 0..extra {
        let v = coords.len();
        coords.push([3.0 + e as f64, 0.0]);
        coords.push([3.0 + e as f64, 0.1]);
        edges.push([v, v + 1]);
    }
    MeshGraph::from_edges(coords, &edges, &[]).unwrap()
}

/// Every closest point of `VertexOrder` against the brute-force scan, bit for bit,
/// over whole meshes: a jittered grid with sources along its vertices that meet
/// (a comb: a bottom row and columns down onto it, so that three segments meet at
/// vertices on the source, the smaller ids outside the row's window), a wavy free
/// curve that doubles back, and a point; runs cut anywhere.
#[test]
fn vertex_order_is_the_brute_force_scan() {
    let mut rng = Rng(21);
    let k = 30;
    let graph = grid(k, &mut rng, 0);
    let row: Vec<usize> = (0..k).collect();
    let mut comb = Source::builder(&graph);
    for col in [3, 11, 12, 20] {
        comb.mesh_polyline(&(0..k / 2).rev().map(|j| j * k + col).collect::<Vec<_>>(), false);
    }
    comb.mesh_polyline(&row, false);
    let ring: Vec<usize> = (0..k).map(|i| k + i).chain((0..k).rev().map(|i| 5 * k + i)).collect();
    let wavy: Vec<Point2> = (0..300)
        .map(|i| i as f64 / 299.0)
        .map(|t| [0.5 + 0.45 * (9.0 * t).sin() * t, 0.5 + 0.4 * (5.0 * t).cos() * (1.0 - 0.5 * t)])
        .collect();
    let sources = [
        comb.build().unwrap(),
        Source::builder(&graph)
            .mesh_polyline(&ring, true)
            .mesh_polyline(&row, false)
            .build()
            .unwrap(),
        Source::builder(&graph).polyline(&wavy, false).build().unwrap(),
        Source::builder(&graph).point([0.3, 0.7]).build().unwrap(),
    ];
    let n = graph.num_vertices();
    for (case, source) in sources.iter().enumerate() {
        for farthest in [2.0, 0.1] {
            let order = VertexOrder::new(&graph, source, farthest);
            for start in [0, 7, n / 3] {
                let mut v = start;
                let mut visited = 0;
                order.for_each(start..n, |u, c| {
                    assert_eq!(u, v);
                    let want = closest_point_brute_force(source, graph.point(u)).unwrap();
                    assert_eq!(
                        format!("{c:?}"),
                        format!("{want:?}"),
                        "source {case}, vertex {u}, runs from {start}"
                    );
                    v += 1;
                    visited += 1;
                });
                assert_eq!(visited, n - start);
            }
        }
    }
}

/// The chain tree's exact query against the brute-force scan, bit for bit, from no
/// guess (the tree's own), from the farthest segment, and from the closest: points
/// near and far around a closed wavy curve with a row beside it, and a point source.
#[test]
fn closest_in_chain_is_the_brute_force_scan() {
    let mut rng = Rng(31);
    let graph = grid(20, &mut rng, 0);
    let wavy: Vec<Point2> = (0..400)
        .map(|i| 2.0 * std::f64::consts::PI * i as f64 / 400.0)
        .map(|a| {
            [
                0.5 + (0.3 + 0.1 * (5.0 * a).cos()) * a.cos(),
                0.5 + (0.3 + 0.1 * (5.0 * a).cos()) * a.sin(),
            ]
        })
        .collect();
    let sources = [
        Source::builder(&graph)
            .polyline(&wavy, true)
            .mesh_polyline(&(0..20).collect::<Vec<_>>(), false)
            .build()
            .unwrap(),
        Source::builder(&graph).point([0.3, 0.7]).build().unwrap(),
    ];
    for (case, source) in sources.iter().enumerate() {
        // Segments projected from no guess and from the farthest one.
        let (mut own, mut from_far) = (0u64, 0u64);
        for _ in 0..400 {
            let p = [4.0 * rng.unit() - 1.5, 4.0 * rng.unit() - 1.5];
            let want = closest_point_brute_force(source, p).unwrap();
            let far = (0..source.segments.len() as u32)
                .max_by(|&a, &b| {
                    source.geoms[a as usize]
                        .project(p)
                        .distance_squared
                        .total_cmp(&source.geoms[b as usize].project(p).distance_squared)
                })
                .unwrap();
            for guess in [None, Some(far), Some(want.segment)] {
                let mut stats = QueryStats::default();
                let got = source.describe(p, source.closest_in_chain(p, guess, &mut stats));
                assert_eq!(
                    format!("{got:?}"),
                    format!("{want:?}"),
                    "source {case}, point {p:?}, guess {guess:?}"
                );
                if guess.is_none() {
                    own += stats.segments;
                }
            }
            // The tree's search itself from the farthest segment: the same answer.
            let mut stats = QueryStats { segments: 1, ..QueryStats::default() };
            let seed = Nearest { segment: far, projection: source.geoms[far as usize].project(p) };
            let got =
                source.describe(p, source.chain_tree().closest(&source.geoms, p, seed, &mut stats));
            assert_eq!(
                format!("{got:?}"),
                format!("{want:?}"),
                "source {case}, point {p:?}, from segment {far}"
            );
            from_far += stats.segments;
        }
        // The tree's own guess keeps the search to a few leaves, where a far one
        // opens much of the tree around a closed curve.
        eprintln!("source {case}: {own} segments projected from the tree's guess, {from_far} from the farthest segment");
        assert!(own <= 40 * 400, "source {case}: {own} segments projected for 400 queries");
        if case == 0 {
            assert!(2 * own < from_far, "source {case}: {own} from the tree's guess against {from_far} from the farthest segment");
        }
    }
}

/// The bound of `reach_covers_mesh` against the brute-force distances: never below
/// the farthest vertex's distance, so that it says the mesh is covered only when
/// `propagate` reports every vertex; it decides for reaches a little beyond the
/// farthest vertex; it never decides where a component has no seed.
#[test]
fn reach_covers_mesh_bounds_the_farthest_vertex() {
    let mut rng = Rng(11);
    let mut decided = 0;
    for case in 0..60 {
        let graph = grid(12 + case % 7, &mut rng, usize::from(case % 5 == 0));
        // A free wavy polyline, or a single point, somewhere in the square.
        let count = if case % 4 == 3 { 1 } else { 2 + (rng.unit() * 40.0) as usize };
        let (cx, cy, amp) = (rng.unit(), rng.unit(), 0.3 * rng.unit());
        let points: Vec<Point2> = (0..count)
            .map(|i| {
                [i as f64 / count as f64, cy + amp * (7.0 * i as f64 / count as f64 + cx).sin()]
            })
            .collect();
        let source = Source::builder(&graph).polyline(&points, false).build().unwrap();
        let farthest = (0..graph.num_vertices())
            .map(|v| closest_point_brute_force(&source, graph.point(v)).unwrap().distance)
            .fold(0.0, f64::max);
        // Not so where a component holds no seed (or a point off the mesh none).
        let all = propagate(&graph, &source, f64::INFINITY, &PropagationOptions::new()).len()
            == graph.num_vertices();
        for max in [0.5 * farthest, 0.999 * farthest, farthest, 2.0 * farthest, 10.0, f64::INFINITY]
        {
            match reach_covers_mesh(&graph, &source, max) {
                Some(bound) => {
                    decided += 1;
                    assert!(
                        bound >= farthest && bound <= max,
                        "case {case}: bound {bound}, farthest vertex {farthest}, max {max}"
                    );
                    assert_eq!(
                        propagate(&graph, &source, max, &PropagationOptions::new()).len(),
                        graph.num_vertices(),
                        "case {case}"
                    );
                }
                // Undecided: short of twice the farthest distance, or where
                // propagation does not report every vertex either.
                None => assert!(
                    max < 2.0 * farthest || !all,
                    "case {case}: undecided at {max} (farthest {farthest})"
                ),
            }
        }
        if graph.num_components() > 1 {
            assert_eq!(
                reach_covers_mesh(&graph, &source, f64::INFINITY),
                None,
                "case {case}: a component without a seed"
            );
        }
    }
    assert!(decided >= 100, "{decided} of 360 reaches decided");
}
