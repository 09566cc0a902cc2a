//! The loop in space against an analytic field and a scripted remesher: the iteration,
//! the best mesh, the history, the rules and the limits, with no external tool (the
//! runs through `mmg3d_O3` are in `tests/adapt_space.rs`).

use std::cell::RefCell;

use smartmesh_formats::{CellKind, TaggedMesh};
use smartmesh_test_support::grid::kuhn_box;

use super::*;
use crate::adapt::{INTERRUPTED, RUNNING};
use crate::history::History;

/// The isotropic field of size `h` everywhere.
fn uniform(h: f64) -> impl Fn(&TaggedMesh) -> Result<SpaceField, SpaceSizingError> {
    move |mesh: &TaggedMesh| {
        Ok(SpaceField {
            metric: vec![(1.0 / (h * h)) * Sym3::IDENTITY; mesh.points.len()],
            warnings: vec!["a warning".into()],
        })
    }
}

/// A remesher that hands out the boxes of `sides` cubes a side in turn (then fails),
/// keeping the metrics it was given.
struct Scripted {
    sides: Vec<usize>,
    given: RefCell<Vec<Vec<Sym3>>>,
}

impl Adapter for Scripted {
    fn name(&self) -> &str {
        "scripted"
    }
    fn adapt(
        &self,
        _: &TaggedMesh,
        _: &crate::topology::Topology,
        _: &[crate::metric::Sym2],
    ) -> Result<Adapted, AdapterError> {
        unreachable!("the loop in space calls adapt_space")
    }
    fn adapt_space(&self, mesh: &TaggedMesh, metric: &[Sym3]) -> Result<Adapted, AdapterError> {
        assert_eq!(metric.len(), mesh.points.len());
        let k = self.given.borrow().len();
        self.given.borrow_mut().push(metric.to_vec());
        match self.sides.get(k) {
            Some(&n) => Ok(Adapted { mesh: kuhn_box(n, [1.0; 3]), stats: None }),
            None => Err(AdapterError::Input("no more meshes".into())),
        }
    }
}

/// Keeps every history and every best mesh handed on; interrupted once `stop_after`
/// records have come.
#[derive(Default)]
struct Kept {
    histories: Vec<History>,
    bests: Vec<TaggedMesh>,
    stop_after: Option<usize>,
}

impl Observer for Kept {
    fn interrupted(&mut self) -> bool {
        self.stop_after.is_some_and(|n| self.histories.len() >= n)
    }
    fn record(
        &mut self,
        h: &History,
        best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh_formats::Error> {
        self.histories.push(h.clone());
        self.bests.extend(best.cloned());
        Ok(())
    }
}

fn options(max_iterations: usize) -> AdaptOptions {
    AdaptOptions { max_iterations, max_growth: None, ..AdaptOptions::default() }
}

/// The share of edges of `mesh`'s tetrahedra whose length times `1/h` is in [1/√2, √2],
/// counted here (the field of [`uniform`]).
fn share(mesh: &TaggedMesh, h: f64) -> f64 {
    let mut edges = std::collections::BTreeSet::new();
    for (k, n, _, _) in mesh.cells() {
        if k == CellKind::Tetra {
            for i in 0..4 {
                for j in i + 1..4 {
                    edges.insert((n[i].min(n[j]), n[i].max(n[j])));
                }
            }
        }
    }
    let ok = edges
        .iter()
        .filter(|&&(a, b)| {
            let (p, q) = (mesh.points[a as usize], mesh.points[b as usize]);
            let l = (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>().sqrt() / h;
            (0.5f64.sqrt()..=2f64.sqrt()).contains(&l)
        })
        .count();
    ok as f64 / edges.len() as f64
}

#[test]
fn the_most_conforming_mesh_is_kept_and_a_failure_leaves_it() {
    // Field h = 0.2: the box of 5 cubes a side has its axis edges at length 1, its
    // face diagonals at √2 and body diagonals at √3; boxes of 2 and 12 are far off.
    let sizing = uniform(0.2);
    let adapter = Scripted { sides: vec![5, 12], given: RefCell::new(Vec::new()) };
    let mut kept = Kept::default();
    let start = kuhn_box(2, [1.0; 3]);
    let out =
        run_space(start, &sizing, &adapter, &options(5), "box", "uniform", &mut kept).unwrap();
    let h = &out.history;
    // Three records: the start, the two meshes; the third remeshing failed.
    assert_eq!(h.iterations.len(), 3, "{h:?}");
    assert!(matches!(out.failure, Some(AdaptError::Iteration { iteration: 3, .. })));
    assert!(h.stopped.contains("iteration 3 failed while remeshing"), "{}", h.stopped);
    let shares: Vec<f64> = [2, 5, 12].iter().map(|&n| share(&kuhn_box(n, [1.0; 3]), 0.2)).collect();
    for ((r, s), n) in h.iterations.iter().zip(&shares).zip([2, 5, 12]) {
        assert!((r.conforming_share - s).abs() < 1e-12, "{} vs {s}", r.conforming_share);
        let space = r.space.as_ref().unwrap();
        assert_eq!(space.cell, "tetrahedron");
        assert_eq!(space.non_positive, 0);
        // The boundary triangles, 12 n², apart from the 6 n³ tetrahedra.
        assert_eq!((r.triangles, space.cells), (12 * n * n, 6 * n * n * n));
        assert_eq!(r.vertices, (n + 1).pow(3));
    }
    let best = (0..3).max_by(|&a, &b| shares[a].total_cmp(&shares[b])).unwrap();
    assert_eq!(best, 1, "{shares:?}");
    assert_eq!(h.best_iteration, 1);
    assert_eq!(out.best.points.len(), 6 * 6 * 6);
    // Handed on: the start, then the 5-box; the best carries its field.
    assert_eq!(kept.bests.len(), 2);
    assert_eq!(kept.bests[1].points.len(), 216);
    let metric = &out.best.point_data["metric"];
    assert_eq!(metric.components, 9);
    let m = 1.0 / (0.2 * 0.2);
    assert_eq!(metric.values[..9], [m, 0.0, 0.0, 0.0, m, 0.0, 0.0, 0.0, m]);
    assert!(out.best.point_data.contains_key("size_tensor"));
    // A record after every iteration and once at the end; the last names the stop.
    assert_eq!(kept.histories.len(), 4);
    assert!(kept.histories[..3].iter().all(|h| h.stopped == RUNNING));
    assert_eq!(out.warnings, vec!["iteration 0: a warning".to_string()]);
    assert_eq!(h.adapter, "scripted");
}

#[test]
fn an_unchanged_mesh_converges_and_the_later_iteration_wins_the_tie() {
    let sizing = uniform(0.2);
    let adapter = Scripted { sides: vec![5, 5, 5], given: RefCell::new(Vec::new()) };
    let mut kept = Kept::default();
    let out =
        run_space(kuhn_box(5, [1.0; 3]), &sizing, &adapter, &options(8), "box", "u", &mut kept)
            .unwrap();
    let h = &out.history;
    assert!(h.converged, "{}", h.stopped);
    assert_eq!(h.iterations.len(), 2);
    assert_eq!(h.best_iteration, 1);
    assert!(h.stopped.starts_with("converged at iteration 1"), "{}", h.stopped);
    assert!(out.failure.is_none());
}

#[test]
fn ctrl_c_stops_between_iterations_keeping_the_best() {
    let sizing = uniform(0.2);
    let adapter = Scripted { sides: vec![5, 3, 4, 6], given: RefCell::new(Vec::new()) };
    // Interrupted once the start and iteration 1 are recorded.
    let mut kept = Kept { stop_after: Some(2), ..Kept::default() };
    let out =
        run_space(kuhn_box(2, [1.0; 3]), &sizing, &adapter, &options(8), "box", "u", &mut kept)
            .unwrap();
    let h = &out.history;
    assert_eq!(h.stopped, INTERRUPTED);
    assert_eq!(h.iterations.len(), 2);
    assert_eq!(h.best_iteration, 1);
    assert_eq!(adapter.given.borrow().len(), 1, "a remeshing started after the interruption");
    assert_eq!(kept.histories.last().unwrap().stopped, INTERRUPTED);
}

#[test]
fn a_field_asking_for_too_much_is_refused_and_growth_is_limited_by_the_3d_exponent() {
    // h = 0.02 on the unit cube asks for about 6√2 · 125 000 / 5.6 ≈ 189 000 vertices.
    let sizing = uniform(0.02);
    let adapter = Scripted { sides: vec![5], given: RefCell::new(Vec::new()) };
    let start = kuhn_box(2, [1.0; 3]);
    let limited = AdaptOptions { max_vertices: Some(1000), ..options(3) };
    let out =
        run_space(start.clone(), &sizing, &adapter, &limited, "box", "u", &mut Kept::default())
            .unwrap();
    assert!(matches!(out.failure, Some(AdaptError::TooManyVertices { iteration: 1, .. })));
    assert!(adapter.given.borrow().is_empty());
    assert!(out.failure.unwrap().is_limit());
    // With a growth limit of 4 the remesher gets the field scaled to 4 · 27 vertices.
    let grown = AdaptOptions { max_growth: Some(4.0), ..options(1) };
    let out = run_space(start.clone(), &sizing, &adapter, &grown, "box", "u", &mut Kept::default())
        .unwrap();
    let given = adapter.given.borrow()[0].clone();
    let n = crate::metric_field::expected_vertices(&start, &given);
    assert!((n / 108.0 - 1.0).abs() < 1e-9, "the scaled field asks for {n}");
    let r = out.history.iterations[1].remeshing.as_ref().unwrap();
    assert!((r.growth_limited_to.unwrap() / 108.0 - 1.0).abs() < 1e-12);
    // Never converged on a growth-limited iteration.
    assert!(!out.history.converged);
}

/// A budget of `n` vertices, constant over the iterations.
fn budget(n: f64) -> crate::adapt::Budget {
    crate::adapt::Budget {
        schedule: crate::adapt::solver::Schedule { start: n, growth: 1.0, target: n },
        from: "test".into(),
        hard: (None, None),
        recipe_share: crate::adapt::budget::RECIPE_SHARE,
    }
}

/// The surface of the tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1): four triangles.
fn tetrahedron_surface() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for t in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        m.block_mut(CellKind::Triangle).push(&t, 1, 1);
    }
    m
}

#[test]
fn what_needs_the_plane_or_volume_cells_is_refused_before_any_work() {
    let sizing = uniform(0.2);
    let adapter = Scripted { sides: vec![], given: RefCell::new(Vec::new()) };
    let layer = crate::layer::LayerOptions::default();
    let o = AdaptOptions { layer: Some(layer), ..options(1) };
    let e = run_space(kuhn_box(1, [1.0; 3]), &sizing, &adapter, &o, "b", "u", &mut Kept::default())
        .unwrap_err();
    assert!(matches!(e, AdaptError::Planar(_)), "{e}");
    // On a surface: no complexity, so no budget; no tetrahedra to recover a Hessian on.
    let o = AdaptOptions { budget: Some(budget(10.0)), ..options(1) };
    let surface = tetrahedron_surface();
    let e = run_space(surface.clone(), &sizing, &adapter, &o, "s", "u", &mut Kept::default())
        .unwrap_err();
    assert!(matches!(e, AdaptError::Surface(SURFACE_BUDGET)), "{e}");
    assert!(e.to_string().contains("integral of √det M over volume cells"), "{e}");
    let solver = SolverLoop {
        command: "true {mesh} {solution}".into(),
        dir: std::env::temp_dir(),
        mesh_extension: "vtu".into(),
        solution_extension: "vtu".into(),
        fields: vec![],
        goal: crate::adapt::solver::Goal::Error(0.01),
        p: 2.0,
        method: Default::default(),
        bounds: SizeBounds::try_new(1e-3, 1.0, 100.0).unwrap(),
    };
    let e = run_space_with_solver(
        surface,
        &sizing,
        Some(&solver),
        &adapter,
        &options(1),
        "s",
        "u",
        &mut Kept::default(),
    )
    .unwrap_err();
    assert!(matches!(e, AdaptError::Surface(SURFACE_SOLVER)), "{e}");
    assert!(adapter.given.borrow().is_empty());
    // A field that is no recipe takes no solution's step.
    let e = sizing.size_for(&kuhn_box(1, [1.0; 3]), &[solver.step(0, &["u".into()])], None);
    assert!(e.unwrap_err().to_string().contains("takes no step"));
}

#[test]
fn the_budget_normalises_the_field_and_divides_by_the_remeshers_ratio() {
    // Uniform h = 0.2 on the unit cube asks for 6√2 · 125 / 5.6 ≈ 189 vertices; a budget
    // of 500 scales it, and the remesher's boxes (5³ = 125 vertices for a field of 500,
    // then 8³) set the ratio the next target is divided by.
    let sizing = uniform(0.2);
    let adapter = Scripted { sides: vec![4, 7], given: RefCell::new(Vec::new()) };
    let start = kuhn_box(2, [1.0; 3]);
    let o = AdaptOptions { budget: Some(budget(500.0)), ..options(2) };
    let mut kept = Kept::default();
    let out = run_space(start.clone(), &sizing, &adapter, &o, "box", "u", &mut kept).unwrap();
    let given = adapter.given.borrow();
    let n0 = crate::metric_field::expected_vertices(&start, &given[0]);
    assert!((n0 / 500.0 - 1.0).abs() < 1e-9, "{n0}");
    // Iteration 1 made 125 of 500: ratio 1/4, clamped to 1/2, so 1000 asked next.
    let n1 = crate::metric_field::expected_vertices(&kuhn_box(4, [1.0; 3]), &given[1]);
    assert!((n1 / 1000.0 - 1.0).abs() < 1e-9, "{n1}");
    let b = out.history.budget.as_ref().unwrap();
    assert_eq!(b.vertices, 500.0);
    // Iteration 2 made 512 of 1000: the secant through (500, 125) and (1000, 512) has
    // slope ln 4.096 / ln 2, kept at 2, so the next target is 1000 · (500/512)^(1/2).
    let want = [500.0, 1000.0, 1000.0 * (500.0f64 / 512.0).sqrt()];
    assert_eq!(b.normalised_to.len(), 3);
    for (got, want) in b.normalised_to.iter().zip(want) {
        assert!((got / want - 1.0).abs() < 1e-9, "{:?}", b.normalised_to);
    }
    // The mesh on the budget (512 of 500) is the best, off-budget ones are not.
    assert_eq!(out.history.best_iteration, 2);
}

#[test]
fn a_field_that_does_not_fit_the_start_is_an_input_error() {
    let sizing = |_: &TaggedMesh| -> Result<SpaceField, SpaceSizingError> {
        Ok(SpaceField { metric: vec![Sym3::IDENTITY; 3], warnings: Vec::new() })
    };
    let adapter = Scripted { sides: vec![], given: RefCell::new(Vec::new()) };
    let e = run_space(
        kuhn_box(1, [1.0; 3]),
        &sizing,
        &adapter,
        &options(1),
        "b",
        "u",
        &mut Kept::default(),
    )
    .unwrap_err();
    assert!(matches!(e, AdaptError::Start { phase: Phase::Size, .. }), "{e}");
    assert!(e.to_string().contains("3 tensors for 8 vertices"), "{e}");
}
