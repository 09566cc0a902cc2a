//! The sizing engine against analytic or brute-force twins: every algorithm of thesis
//! 4.3.6–4.3.7 on meshes made here (jittered grids, O-meshes around a circle, an ellipse
//! and a non-convex curve, a wedge, a square with a rounded side), plus intersection
//! order, default size, clamping, gradation and determinism across thread counts.
//!
//! The twins never call the propagation: distances and foot points come from a scan
//! over every segment, curvatures from the analytic curve or a hand-written three-point
//! circle, and tensors are compared through their radii along the expected normal and
//! tangent (equal radii along two perpendicular directions pin both sizes and, for an
//! anisotropic tensor, its axes).

use std::f64::consts::PI;

use smartmesh::formats::{CellBlock, CellKind, TaggedMesh};
use smartmesh::sizing::{
    compute_size_field, run_algorithm, three_point_curvature, Algorithm, CurvatureOfBorder,
    CurvatureToSize, DistanceBetweenTwoBorders, DistanceFunction, DistanceToBorder,
    DistanceToImaginaryPolyline, DistanceToPoint, EntitySet, PolylinePoints, SizeField,
    SizeProjectionFunction, SizingError, SizingPlan, Step, StepEvent, Uniform,
};
use smartmesh::Point2;
use smartmesh::{MeshGraph, SizeBounds, SizeTensor, Topology};

// ---------------------------------------------------------------------------------
// Meshes

use smartmesh_test_support::grid::{split_quads, triangles_crossed_by, JitteredGrid};
use smartmesh_test_support::SplitMix64 as Rng;

/// A mesh made here, with its topology and graph.
struct Model {
    coords: Vec<Point2>,
    triangles: Vec<[usize; 3]>,
    topo: Topology,
    graph: MeshGraph,
}

impl Model {
    /// `lines`: (tag, polyline vertices, closed); `points`: (tag, vertex); `face_tag`
    /// gives each triangle its face tag.
    fn new(
        coords: Vec<Point2>,
        triangles: Vec<[usize; 3]>,
        face_tag: impl Fn(Point2) -> i32,
        lines: &[(i32, Vec<usize>, bool)],
        points: &[(i32, usize)],
    ) -> Model {
        let mut mesh = TaggedMesh::new();
        mesh.points = coords.iter().map(|p| [p[0], p[1], 0.0]).collect();
        let mut tris = CellBlock::new(CellKind::Triangle);
        for t in &triangles {
            let c = [
                (coords[t[0]][0] + coords[t[1]][0] + coords[t[2]][0]) / 3.0,
                (coords[t[0]][1] + coords[t[1]][1] + coords[t[2]][1]) / 3.0,
            ];
            let tag = face_tag(c);
            tris.push(t, tag, tag);
        }
        let mut lb = CellBlock::new(CellKind::Line);
        for (tag, vs, closed) in lines {
            for w in vs.windows(2) {
                lb.push(w, *tag, *tag);
            }
            if *closed {
                lb.push(&[vs[vs.len() - 1], vs[0]], *tag, *tag);
            }
        }
        let mut vb = CellBlock::new(CellKind::Vertex);
        for (tag, v) in points {
            vb.push(&[*v], *tag, *tag);
        }
        mesh.blocks = vec![vb, lb, tris];
        let topo = Topology::from_mesh(&mesh);
        let graph = MeshGraph::from_topology(&topo, &mesh).unwrap();
        Model { coords, triangles, topo, graph }
    }

    fn curve(&self, tag: i32) -> usize {
        self.topo
            .curves
            .iter()
            .position(|c| c.tag == Some(tag))
            .unwrap_or_else(|| panic!("no curve {tag}"))
    }
    fn point(&self, tag: i32) -> usize {
        self.topo.points.iter().position(|p| p.tag == Some(tag)).unwrap()
    }
    fn face(&self, tag: i32) -> usize {
        self.topo.faces.iter().position(|f| f.tag == tag).unwrap()
    }
    fn curves(&self, tags: &[i32]) -> EntitySet {
        EntitySet { curves: tags.iter().map(|&t| self.curve(t)).collect(), ..EntitySet::default() }
    }
}

/// A jittered grid of `nx × ny` vertices, spacing `h`, from the origin. Boundary lines:
/// bottom 11 (left to right), right 12, top 13, left 14. Faces: 1 left of `x_split`,
/// 2 right of it. Point 20 at vertex `point`.
fn grid(
    nx: usize,
    ny: usize,
    h: f64,
    jitter: f64,
    seed: u64,
    x_split: f64,
    point: (usize, usize),
) -> Model {
    let JitteredGrid { coords, triangles: tris, .. } =
        JitteredGrid::new(nx, ny, [0.0, 0.0], h, jitter, seed);
    let v = |i: usize, j: usize| j * nx + i;
    let lines = [
        (11, (0..nx).map(|i| v(i, 0)).collect(), false),
        (12, (0..ny).map(|j| v(nx - 1, j)).collect(), false),
        (13, (0..nx).rev().map(|i| v(i, ny - 1)).collect(), false),
        (14, (0..ny).rev().map(|j| v(0, j)).collect(), false),
    ];
    Model::new(
        coords,
        tris,
        |c| if c[0] < x_split { 1 } else { 2 },
        &lines,
        &[(20, v(point.0, point.1))],
    )
}

/// An O-mesh outside the closed curve `border(a)`, `n` points around, `layers` rings
/// moved out by `dr` along the radius each. The border is curve 1 (one closed loop).
fn o_mesh(n: usize, layers: usize, dr: f64, border: impl Fn(f64) -> Point2, seed: u64) -> Model {
    let mut coords = Vec::new();
    for j in 0..layers {
        for i in 0..n {
            let a = 2.0 * PI * i as f64 / n as f64;
            let b = border(a);
            let r = b[0].hypot(b[1]);
            let s = (r + j as f64 * dr) / r;
            coords.push(if j == 0 { b } else { [b[0] * s, b[1] * s] });
        }
    }
    let tris = split_quads(n, layers, true, &mut Rng(seed));
    Model::new(coords, tris, |_| 1, &[(1, (0..n).collect(), true)], &[])
}

// ---------------------------------------------------------------------------------
// Twins and helpers

/// Brute-force closest point of `p` on segments `segs`: (distance, foot, segment,
/// parameter, and whether another segment gives an equally close but different foot).
struct Brute {
    d: f64,
    foot: Point2,
    seg: usize,
    t: f64,
    ambiguous: bool,
}

fn project(p: Point2, a: Point2, b: Point2) -> (f64, Point2, f64) {
    let d = [b[0] - a[0], b[1] - a[1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let f = if t == 0.0 {
        a
    } else if t == 1.0 {
        b
    } else {
        [a[0] + t * d[0], a[1] + t * d[1]]
    };
    ((p[0] - f[0]).hypot(p[1] - f[1]), f, t)
}

fn brute(p: Point2, segs: &[[Point2; 2]]) -> Brute {
    let mut best = Brute { d: f64::INFINITY, foot: [0.0; 2], seg: 0, t: 0.0, ambiguous: false };
    for (i, s) in segs.iter().enumerate() {
        let (d, f, t) = project(p, s[0], s[1]);
        if d < best.d {
            best = Brute { d, foot: f, seg: i, t, ambiguous: false };
        }
    }
    for s in segs {
        let (d, f, _) = project(p, s[0], s[1]);
        if (d - best.d).abs() <= 1e-9 * best.d.max(1e-12)
            && (f[0] - best.foot[0]).hypot(f[1] - best.foot[1]) > 1e-9
        {
            best.ambiguous = true;
        }
    }
    best
}

/// The segments of a polyline of mesh vertices.
fn segments(coords: &[Point2], vs: &[usize], closed: bool) -> Vec<[Point2; 2]> {
    let mut s: Vec<[Point2; 2]> = vs.windows(2).map(|w| [coords[w[0]], coords[w[1]]]).collect();
    if closed {
        s.push([coords[vs[vs.len() - 1]], coords[vs[0]]]);
    }
    s
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Asserts that `t` has size `hn` along `n` and `ht` across it, to `tol` relative.
fn assert_frame(t: &SizeTensor, n: Point2, hn: f64, ht: f64, tol: f64, what: &str) {
    let got_n = t.size_along(n);
    let got_t = t.size_along([-n[1], n[0]]);
    assert!(rel(got_n, hn) <= tol && rel(got_t, ht) <= tol, "{what}: sizes ({got_n}, {got_t}) along normal/tangent, expected ({hn}, {ht}); tensor {t:?}");
}

fn unit(v: Point2) -> Point2 {
    let n = v[0].hypot(v[1]);
    [v[0] / n, v[1] / n]
}

fn df(s0: f64, s1: f64, dmax: f64, e: f64) -> DistanceFunction {
    DistanceFunction::try_new(s0, s1, dmax, e).unwrap()
}

fn plan(h_max: Option<f64>, steps: Vec<(&str, Algorithm)>) -> SizingPlan {
    SizingPlan {
        h_max,
        steps: steps
            .into_iter()
            .map(|(l, a)| Step { label: l.to_string(), algorithm: a, names: Vec::new() })
            .collect(),
        ..SizingPlan::default()
    }
}

fn run(m: &Model, p: &SizingPlan) -> SizeField {
    compute_size_field(&m.graph, &m.topo, p, &mut |_| {}).unwrap()
}

// ---------------------------------------------------------------------------------
// UNIFORM and DISTANCE_TO_POINT

#[test]
fn uniform_is_exact_on_faces_curves_and_points() {
    let m = grid(30, 20, 0.05, 0.3, 1, 0.7, (10, 10));
    let p = plan(
        Some(1.0),
        vec![
            (
                "left face",
                Algorithm::Uniform(Uniform {
                    size: 0.3,
                    on: EntitySet { faces: vec![m.face(1)], ..EntitySet::default() },
                }),
            ),
            ("bottom", Algorithm::Uniform(Uniform { size: 0.1, on: m.curves(&[11]) })),
            (
                "point",
                Algorithm::Uniform(Uniform {
                    size: 0.05,
                    on: EntitySet { points: vec![m.point(20)], ..EntitySet::default() },
                }),
            ),
        ],
    );
    let f = run(&m, &p);
    // Twin: the corners of triangles whose centroid is left of 0.7, the bottom row, the point.
    let n = m.coords.len();
    let mut want = vec![1.0f64; n];
    for t in &m.triangles {
        let cx = (m.coords[t[0]][0] + m.coords[t[1]][0] + m.coords[t[2]][0]) / 3.0;
        if cx < 0.7 {
            for &v in t {
                want[v] = 0.3;
            }
        }
    }
    for w in want.iter_mut().take(30) {
        *w = w.min(0.1);
    }
    want[10 * 30 + 10] = 0.05;
    for (v, &w) in want.iter().enumerate() {
        assert_eq!(f.tensors[v].sizes(), [w, w], "vertex {v}");
        assert_eq!(f.reached[v], w < 1.0);
    }
    assert_eq!(f.steps[1].vertices_reached, 30);
    assert_eq!(f.steps[2].vertices_reached, 1);
    assert!(f.warnings.is_empty());
}

#[test]
fn distance_to_point_matches_euclidean_distance() {
    let m = grid(41, 41, 0.025, 0.3, 2, 2.0, (20, 15));
    let fun = df(0.02, 0.3, 0.4, 2.0);
    let pt = m.coords[15 * 41 + 20];
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "p",
                Algorithm::DistanceToPoint(DistanceToPoint {
                    function: fun,
                    sources: EntitySet { points: vec![m.point(20)], ..EntitySet::default() },
                }),
            )],
        ),
    );
    let mut inside = 0;
    for (v, p) in m.coords.iter().enumerate() {
        let d = (p[0] - pt[0]).hypot(p[1] - pt[1]);
        if d <= 0.4 {
            inside += 1;
            let h = fun.eval(d);
            assert!(f.reached[v]);
            assert!(
                rel(f.tensors[v].h1(), h) < 1e-12 && rel(f.tensors[v].h2(), h) < 1e-12,
                "vertex {v}"
            );
        } else {
            assert!(!f.reached[v], "vertex {v} at {d} beyond 0.4 reached");
            assert_eq!(f.tensors[v].sizes(), [1.0, 1.0]);
        }
    }
    assert_eq!(f.steps[0].vertices_reached, inside);

    // A curve as source: its vertices are points (not its segments).
    let fun = df(0.01, 0.2, 0.15, 1.0);
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "curve",
                Algorithm::DistanceToPoint(DistanceToPoint {
                    function: fun,
                    sources: m.curves(&[11]),
                }),
            )],
        ),
    );
    for (v, p) in m.coords.iter().enumerate() {
        let d = (0..41)
            .map(|i| (p[0] - m.coords[i][0]).hypot(p[1] - m.coords[i][1]))
            .fold(f64::INFINITY, f64::min);
        assert_eq!(f.reached[v], d <= 0.15, "vertex {v}");
        if d <= 0.15 {
            assert!(rel(f.tensors[v].h1(), fun.eval(d)) < 1e-12);
        }
    }
}

// ---------------------------------------------------------------------------------
// DISTANCE_TO_BORDER

/// Brute-force DISTANCE_TO_BORDER tensor frame at `p` for border segments `segs`
/// (closed loop `closed`): the normal and the distance, or None on a tie.
fn border_frame(p: Point2, segs: &[[Point2; 2]], closed: bool) -> Option<(Point2, f64)> {
    let b = brute(p, segs);
    if b.ambiguous {
        return None;
    }
    if b.d == 0.0 {
        // On the border: averaged tangents at a vertex, the segment's inside.
        let dir = |s: &[Point2; 2]| unit([s[1][0] - s[0][0], s[1][1] - s[0][1]]);
        let mut t = dir(&segs[b.seg]);
        let k = segs.len();
        let other = if b.t == 0.0 {
            if b.seg > 0 {
                Some(b.seg - 1)
            } else if closed {
                Some(k - 1)
            } else {
                None
            }
        } else if b.t == 1.0 {
            if b.seg + 1 < k {
                Some(b.seg + 1)
            } else if closed {
                Some(0)
            } else {
                None
            }
        } else {
            None
        };
        if let Some(o) = other {
            let u = dir(&segs[o]);
            t = unit([t[0] + u[0], t[1] + u[1]]);
        }
        return Some(([-t[1], t[0]], 0.0));
    }
    Some((unit([p[0] - b.foot[0], p[1] - b.foot[1]]), b.d))
}

#[test]
fn distance_to_border_matches_brute_force_on_a_non_convex_curve() {
    // A five-lobed curve: concave between the lobes, so feet jump between lobes and
    // many vertices see a polyline corner.
    let shape = |a: f64| {
        let r = 0.5 * (1.0 + 0.35 * (5.0 * a).cos());
        [r * a.cos(), r * a.sin()]
    };
    let m = o_mesh(300, 40, 0.012, shape, 3);
    let segs = segments(&m.coords, &(0..300).collect::<Vec<_>>(), true);
    let perp = df(0.005, 0.1, 0.25, 1.5);
    let par = df(0.03, 0.2, 0.35, 1.0);
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "wall",
                Algorithm::DistanceToBorder(DistanceToBorder {
                    perpendicular: perp,
                    parallel: par,
                    borders: m.curves(&[1]),
                }),
            )],
        ),
    );
    let (mut checked, mut corner_feet, mut within) = (0, 0, 0);
    for (v, &p) in m.coords.iter().enumerate() {
        let b = brute(p, &segs);
        if b.d <= 0.35 {
            within += 1;
        }
        assert_eq!(f.reached[v], b.d <= 0.35, "vertex {v} at {}", b.d);
        let Some((n, d)) = border_frame(p, &segs, true) else { continue };
        if d > 0.35 {
            continue;
        }
        corner_feet += usize::from(d > 0.0 && (b.t == 0.0 || b.t == 1.0));
        assert_frame(
            &f.tensors[v],
            n,
            perp.eval(d),
            par.eval(d),
            1e-9,
            &format!("vertex {v} at d = {d}"),
        );
        checked += 1;
    }
    assert_eq!(f.steps[0].vertices_reached, within);
    assert!(
        checked > 5000 && corner_feet > 100,
        "checked {checked}, feet on corners {corner_feet}"
    );
}

#[test]
fn distance_to_border_on_a_circle_is_radial() {
    let r0 = 0.4;
    let m = o_mesh(256, 30, 0.01, |a| [r0 * a.cos(), r0 * a.sin()], 4);
    let segs = segments(&m.coords, &(0..256).collect::<Vec<_>>(), true);
    let perp = df(0.002, 0.05, 0.2, 1.0);
    let par = df(0.02, 0.1, 0.2, 1.0);
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "c",
                Algorithm::DistanceToBorder(DistanceToBorder {
                    perpendicular: perp,
                    parallel: par,
                    borders: m.curves(&[1]),
                }),
            )],
        ),
    );
    for (v, &p) in m.coords.iter().enumerate() {
        let (n, d) = border_frame(p, &segs, true).unwrap();
        // Rings 0.2 away from the circle sit at 0.2 from the polygon to rounding: skip.
        if d <= 0.2 - 1e-9 {
            assert_frame(&f.tensors[v], n, perp.eval(d), par.eval(d), 1e-9, "circle");
            // The normal is radial to within the polygon's chord error.
            let radial = unit(p);
            assert!((n[0] * radial[0] + n[1] * radial[1]).abs() > 0.99);
        }
    }
}

// ---------------------------------------------------------------------------------
// CURVATURE_OF_BORDER

#[test]
fn curvature_of_a_circle_is_one_over_r() {
    let r0 = 0.5;
    let m = o_mesh(256, 30, 0.01, |a| [r0 * a.cos(), r0 * a.sin()], 5);
    let segs = segments(&m.coords, &(0..256).collect::<Vec<_>>(), true);
    let perp = df(0.005, 0.1, 0.3, 1.0);
    let curv = CurvatureToSize::try_new(0.001, 0.5, 0.001).unwrap();
    let proj = SizeProjectionFunction::try_new(0.2, 0.25, 1.0).unwrap();
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "c",
                Algorithm::CurvatureOfBorder(CurvatureOfBorder {
                    perpendicular: perp,
                    curvature: curv,
                    projection: proj,
                    borders: m.curves(&[1]),
                }),
            )],
        ),
    );
    let h_border = curv.eval(1.0 / r0);
    assert!((h_border - 2.0 * (0.001f64 * 0.999).sqrt()).abs() < 1e-12);
    let mut n_checked = 0;
    for (v, &p) in m.coords.iter().enumerate() {
        let (n, d) = border_frame(p, &segs, true).unwrap();
        if d <= 0.3 {
            assert_frame(
                &f.tensors[v],
                n,
                perp.eval(d),
                proj.eval(d, h_border),
                1e-9,
                &format!("vertex {v} at {d}"),
            );
            n_checked += 1;
        }
    }
    assert!(n_checked > 5000);
}

#[test]
fn curvature_of_an_ellipse_follows_the_analytic_curvature() {
    let (a, b) = (0.6, 0.3);
    let n = 400;
    let m = o_mesh(n, 12, 0.01, |t| [a * t.cos(), b * t.sin()], 6);
    let perp = df(0.005, 0.1, 0.1, 1.0);
    let curv = CurvatureToSize::try_new(0.001, 1.0, 0.0005).unwrap();
    let proj = SizeProjectionFunction::try_new(0.2, 0.1, 1.0).unwrap();
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "e",
                Algorithm::CurvatureOfBorder(CurvatureOfBorder {
                    perpendicular: perp,
                    curvature: curv,
                    projection: proj,
                    borders: m.curves(&[1]),
                }),
            )],
        ),
    );
    let mut worst: f64 = 0.0;
    for i in 0..n {
        let t = 2.0 * PI * i as f64 / n as f64;
        let kappa = a * b / (a * a * t.sin().powi(2) + b * b * t.cos().powi(2)).powf(1.5);
        // Tangent of the ellipse, analytically.
        let tan = unit([-a * t.sin(), b * t.cos()]);
        let tensor = &f.tensors[i];
        let h_t = tensor.size_along(tan);
        worst = worst.max(rel(h_t, curv.eval(kappa)));
        // Exact twin: the three-point circle written out here.
        let (p0, p1, p2) = (m.coords[(i + n - 1) % n], m.coords[i], m.coords[(i + 1) % n]);
        let (ab, bc, ac) = (
            [p1[0] - p0[0], p1[1] - p0[1]],
            [p2[0] - p1[0], p2[1] - p1[1]],
            [p2[0] - p0[0], p2[1] - p0[1]],
        );
        let k3 = 2.0 * (ab[0] * bc[1] - ab[1] * bc[0]).abs()
            / (ab[0].hypot(ab[1]) * bc[0].hypot(bc[1]) * ac[0].hypot(ac[1]));
        let chord_t = unit([p2[0] - p0[0], p2[1] - p0[1]]);
        let avg_t = unit([unit(ab)[0] + unit(bc)[0], unit(ab)[1] + unit(bc)[1]]);
        assert!((avg_t[0] * chord_t[0] + avg_t[1] * chord_t[1]).abs() > 0.999);
        assert_frame(
            tensor,
            [-avg_t[1], avg_t[0]],
            perp.eval(0.0),
            curv.eval(k3),
            1e-9,
            &format!("border vertex {i}"),
        );
    }
    assert!(worst < 2e-3, "tangent size vs analytic curvature: worst relative error {worst}");
}

/// The documented corner rules (module `curvature_of_border`): a square [0,1]×[0,0.6]
/// whose top side is a circular arc of radius 1 (turning 60° at its ends, 90° at the
/// bottom corners), tagged as one closed curve (corners found by angle) and as four
/// curves meeting at topological points.
#[test]
fn curvature_at_corners_of_a_square_with_a_rounded_side() {
    let (nx, ny) = (41usize, 25usize);
    let big_r = 1.0;
    let sag = big_r - (big_r * big_r - 0.25f64).sqrt();
    let top = |x: f64| 0.6 + (big_r * big_r - (x - 0.5) * (x - 0.5)).sqrt() - (big_r - sag);
    let mut coords = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let x = i as f64 / (nx - 1) as f64;
            coords.push([x, top(x) * j as f64 / (ny - 1) as f64]);
        }
    }
    let tris = split_quads(nx, ny, false, &mut Rng(7));
    let v = |i: usize, j: usize| j * nx + i;
    let bottom: Vec<usize> = (0..nx).map(|i| v(i, 0)).collect();
    let right: Vec<usize> = (0..ny).map(|j| v(nx - 1, j)).collect();
    let arc: Vec<usize> = (0..nx).rev().map(|i| v(i, ny - 1)).collect();
    let left: Vec<usize> = (0..ny).rev().map(|j| v(0, j)).collect();
    let mut ring: Vec<usize> = bottom.clone();
    ring.extend(&right[1..]);
    ring.extend(&arc[1..]);
    ring.extend(&left[1..left.len() - 1]);
    let one_curve = Model::new(coords.clone(), tris.clone(), |_| 1, &[(1, ring, true)], &[]);
    let four_curves = Model::new(
        coords.clone(),
        tris,
        |_| 1,
        &[(1, bottom, false), (2, right, false), (3, arc, false), (4, left, false)],
        &[],
    );

    let perp = df(0.002, 0.05, 0.2, 1.0);
    let curv = CurvatureToSize::try_new(0.001, 0.5, 0.001).unwrap();
    let proj = SizeProjectionFunction::try_new(0.3, 0.2, 1.0).unwrap();
    let h_arc = curv.eval(1.0 / big_r);
    let h_straight = curv.eval(0.0);
    assert_eq!(h_straight, 0.5);
    // What averaging across the corner would give: a three-point circle of radius about
    // one edge, so a size about 7 times finer than the arc's.
    let smeared = curv.eval(three_point_curvature(
        coords[v(nx - 1, ny - 2)],
        coords[v(nx - 1, ny - 1)],
        coords[v(nx - 2, ny - 1)],
    ));
    assert!(smeared < 0.2 * h_arc, "{smeared} vs {h_arc}");

    for (name, m, tags) in
        [("one closed curve", &one_curve, vec![1]), ("four curves", &four_curves, vec![1, 2, 3, 4])]
    {
        let f = run(
            m,
            &plan(
                Some(1.0),
                vec![(
                    "c",
                    Algorithm::CurvatureOfBorder(CurvatureOfBorder {
                        perpendicular: perp,
                        curvature: curv,
                        projection: proj,
                        borders: m.curves(&tags),
                    }),
                )],
            ),
        );
        let t = |i, j| f.tensors[v(i, j)];
        // Bottom corners (90° between straight sides): the intersection of the two
        // sides' tensors, i.e. isotropic perpendicular(0).
        for (i, j) in [(0, 0), (nx - 1, 0)] {
            let s = t(i, j).sizes();
            assert!(
                rel(s[0], perp.eval(0.0)) < 1e-12 && rel(s[1], perp.eval(0.0)) < 1e-12,
                "{name}: bottom corner ({i}, {j}): {s:?}"
            );
        }
        // Top-right corner (60° turn): the intersection of the right side's tensor
        // (tangent up, size C(0)) and the arc's (tangent along the arc, size C(1/R)).
        let c = coords[v(nx - 1, ny - 1)];
        let arc_dir =
            unit([coords[v(nx - 2, ny - 1)][0] - c[0], coords[v(nx - 2, ny - 1)][1] - c[1]]);
        let side_up = SizeTensor::new([1.0, 0.0], perp.eval(0.0), h_straight);
        let side_arc = SizeTensor::new([-arc_dir[1], arc_dir[0]], perp.eval(0.0), h_arc);
        let want = side_up.intersection(&side_arc);
        for k in 0..16 {
            let a = PI * k as f64 / 16.0;
            let u = [a.cos(), a.sin()];
            assert!(
                rel(t(nx - 1, ny - 1).size_along(u), want.size_along(u)) < 1e-9,
                "{name}: top corner along {u:?}"
            );
        }
        // Next to the corner, each side keeps its own curvature: the arc vertex has the
        // arc's size C(1/R) along the arc, the side vertex the straight size C(0).
        let q = coords[v(nx - 2, ny - 1)];
        let qn = coords[v(nx - 3, ny - 1)];
        let (u1, u2) = (unit([q[0] - qn[0], q[1] - qn[1]]), unit([c[0] - q[0], c[1] - q[1]]));
        let tan = unit([u1[0] + u2[0], u1[1] + u2[1]]);
        assert_frame(
            &t(nx - 2, ny - 1),
            [-tan[1], tan[0]],
            perp.eval(0.0),
            h_arc,
            1e-9,
            &format!("{name}: arc vertex next to the corner"),
        );
        assert!(
            rel(t(nx - 1, ny - 2).size_along([0.0, 1.0]), h_straight) < 1e-12,
            "{name}: side vertex next to the corner"
        );
        // Nowhere off the corners is a tangent size finer than the arc's: the corner's
        // three-point curvature is smeared on no vertex.
        let corners = [v(0, 0), v(nx - 1, 0), v(nx - 1, ny - 1), v(0, ny - 1)];
        for (w, tw) in f.tensors.iter().enumerate() {
            if f.reached[w] && !corners.contains(&w) {
                assert!(tw.h_max() >= h_arc * (1.0 - 1e-9), "{name}: vertex {w} {tw:?}");
            }
        }
    }
}

// ---------------------------------------------------------------------------------
// DISTANCE_BETWEEN_TWO_BORDERS

/// The thesis Fig. 4.6 normal and the thickness, by brute force on both borders.
fn gap_twin(p: Point2, s1: &[[Point2; 2]], s2: &[[Point2; 2]]) -> Option<(Point2, f64)> {
    let (b1, b2) = (brute(p, s1), brute(p, s2));
    if b1.ambiguous || b2.ambiguous {
        return None;
    }
    let thickness = b1.d + b2.d;
    if b1.d == 0.0 {
        return border_frame(p, s1, false).map(|(n, _)| (n, thickness));
    }
    if b2.d == 0.0 {
        return border_frame(p, s2, false).map(|(n, _)| (n, thickness));
    }
    let u1 = [(b1.foot[0] - p[0]) / b1.d, (b1.foot[1] - p[1]) / b1.d];
    let u2 = [(b2.foot[0] - p[0]) / b2.d, (b2.foot[1] - p[1]) / b2.d];
    Some((unit([b2.d * u1[0] - b1.d * u2[0], b2.d * u1[1] - b1.d * u2[1]]), thickness))
}

#[test]
fn two_parallel_walls_give_a_constant_thickness() {
    let gap = 0.1;
    let m = grid(201, 11, 0.01, 0.3, 8, 9.0, (5, 5));
    let perp = df(0.005, 0.05, 0.3, 1.0);
    let par = df(0.05, 0.2, 0.3, 1.0);
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "gap",
                Algorithm::DistanceBetweenTwoBorders(DistanceBetweenTwoBorders {
                    perpendicular: perp,
                    parallel: par,
                    first: m.curves(&[11]),
                    second: m.curves(&[13]),
                }),
            )],
        ),
    );
    for v in 0..m.coords.len() {
        assert!(f.reached[v]);
        assert_frame(
            &f.tensors[v],
            [0.0, 1.0],
            perp.eval(gap),
            par.eval(gap),
            1e-9,
            &format!("vertex {v}"),
        );
    }
    assert_eq!(f.steps[0].vertices_reached, m.coords.len());
    assert_eq!(f.steps[0].seeds, 201);
}

#[test]
fn two_borders_in_a_wedge() {
    // Polar mesh r in [0.2, 1], θ in [0, α]; walls θ = 0 (first) and θ = α (second).
    let alpha = 30f64.to_radians();
    let (nr, nt) = (41usize, 31usize);
    let mut coords = Vec::new();
    for j in 0..nt {
        for i in 0..nr {
            let (r, th) =
                (0.2 + 0.8 * i as f64 / (nr - 1) as f64, alpha * j as f64 / (nt - 1) as f64);
            coords.push(if j == 0 { [r, 0.0] } else { [r * th.cos(), r * th.sin()] });
        }
    }
    let tris = split_quads(nr, nt, false, &mut Rng(9));
    let wall1: Vec<usize> = (0..nr).collect();
    let wall2: Vec<usize> = (0..nr).map(|i| (nt - 1) * nr + i).collect();
    let m = Model::new(
        coords.clone(),
        tris,
        |_| 1,
        &[(1, wall1.clone(), false), (2, wall2.clone(), false)],
        &[],
    );
    let (s1, s2) = (segments(&coords, &wall1, false), segments(&coords, &wall2, false));
    let perp = df(0.005, 0.08, 0.3, 1.0);
    let par = df(0.02, 0.2, 0.25, 2.0);
    let f = run(
        &m,
        &plan(
            Some(1.0),
            vec![(
                "wedge",
                Algorithm::DistanceBetweenTwoBorders(DistanceBetweenTwoBorders {
                    perpendicular: perp,
                    parallel: par,
                    first: m.curves(&[1]),
                    second: m.curves(&[2]),
                }),
            )],
        ),
    );
    let (mut checked, mut analytic) = (0, 0);
    for (v, &p) in coords.iter().enumerate() {
        let (b1, b2) = (brute(p, &s1), brute(p, &s2));
        assert_eq!(f.reached[v], b1.d + b2.d <= 0.3, "vertex {v}");
        let Some((n, t)) = gap_twin(p, &s1, &s2) else { continue };
        if t > 0.3 {
            continue;
        }
        assert_frame(&f.tensors[v], n, perp.eval(t), par.eval(t), 1e-9, &format!("vertex {v}"));
        checked += 1;
        // Analytic thickness where both feet fall inside the walls.
        let (r, th) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
        if b1.t > 0.0 && b1.t < 1.0 && b2.t > 0.0 && b2.t < 1.0 {
            assert!((t - r * (th.sin() + (alpha - th).sin())).abs() < 1e-12);
            analytic += 1;
        }
    }
    assert!(checked > 300 && analytic > 200, "{checked} {analytic}");
}

// ---------------------------------------------------------------------------------
// DISTANCE_TO_IMAGINARY_POLYLINE

#[test]
fn straight_wake_has_the_analytic_abscissa_and_respects_within() {
    let m = grid(101, 51, 0.02, 0.3, 10, 1.0, (3, 3));
    let wake = vec![[0.5, 0.5], [0.9, 0.5], [1.5, 0.5]];
    let perp = df(0.005, 0.1, 0.2, 1.0);
    let along = df(0.01, 0.05, 1.0, 1.0);
    let proj = SizeProjectionFunction::try_new(0.2, 0.3, 1.0).unwrap();
    let alg = |within: EntitySet| {
        Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
            perpendicular: perp,
            polyline_distance: along,
            projection: proj,
            polyline: PolylinePoints::Plane(wake.clone()),
            within,
        })
    };
    let f = run(&m, &plan(Some(1.0), vec![("wake", alg(EntitySet::default()))]));
    let segs = vec![[wake[0], wake[1]], [wake[1], wake[2]]];
    let mut n_inner = 0;
    for (v, &p) in m.coords.iter().enumerate() {
        let b = brute(p, &segs);
        assert_eq!(f.reached[v], b.d <= 0.3, "vertex {v}");
        if b.d > 0.3 {
            continue;
        }
        if p[0] > 0.5 && p[0] < 1.5 {
            // Analytic: d = |y - 0.5|, abscissa x - 0.5, axes y and x.
            let d = (p[1] - 0.5).abs();
            assert_frame(
                &f.tensors[v],
                [0.0, 1.0],
                perp.eval(d),
                proj.eval(d, along.eval(p[0] - 0.5)),
                1e-9,
                &format!("vertex {v}"),
            );
            n_inner += 1;
        } else {
            // Beyond an end: radial from the end point.
            let s = if p[0] <= 0.5 { 0.0 } else { 1.0 };
            assert_frame(
                &f.tensors[v],
                unit([p[0] - b.foot[0], p[1] - b.foot[1]]),
                perp.eval(b.d),
                proj.eval(b.d, along.eval(s)),
                1e-9,
                "cap",
            );
        }
    }
    assert!(n_inner > 500);

    // Restricted to the left face (cells with centroid x < 1): other vertices untouched.
    let f2 = run(
        &m,
        &plan(
            Some(1.0),
            vec![("wake", alg(EntitySet { faces: vec![m.face(1)], ..EntitySet::default() }))],
        ),
    );
    let mut in_face = vec![false; m.coords.len()];
    for t in &m.triangles {
        if (m.coords[t[0]][0] + m.coords[t[1]][0] + m.coords[t[2]][0]) / 3.0 < 1.0 {
            t.iter().for_each(|&v| in_face[v] = true);
        }
    }
    for (v, &inf) in in_face.iter().enumerate() {
        assert_eq!(f2.reached[v], f.reached[v] && inf, "vertex {v}");
        if f2.reached[v] {
            assert_eq!(f2.tensors[v], f.tensors[v]);
        }
    }
}

/// Issue item 5: a wake whose reach (0.05) is far below the edge length (1) still marks
/// the vertices of every triangle it crosses.
#[test]
fn coarse_mesh_wake_marks_every_crossed_triangle() {
    let m = grid(11, 11, 1.0, 0.25, 31, 99.0, (5, 5));
    let wake: Vec<Point2> = (0..=20)
        .map(|k| [2.3 + 0.3 * k as f64, 4.6 + 0.04 * k as f64 + 0.5 * (0.5 * k as f64).sin()])
        .collect();
    let perp = df(0.01, 0.2, 0.05, 1.0);
    let along = df(0.01, 0.2, 6.0, 1.0);
    let proj = SizeProjectionFunction::try_new(0.2, 0.05, 1.0).unwrap();
    let alg = Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
        perpendicular: perp,
        polyline_distance: along,
        projection: proj,
        polyline: PolylinePoints::Plane(wake.clone()),
        within: EntitySet::default(),
    });
    let f = run(&m, &plan(Some(1.0), vec![("wake", alg)]));
    // Oracle: triangles containing a point of the wake sampled every 1e-3.
    let crossed = triangles_crossed_by(&m.coords, &m.triangles, &wake);
    for &t in &crossed {
        for &v in &m.triangles[t] {
            assert!(
                f.reached[v] && f.tensors[v].h_max() < 1.0,
                "vertex {v} of a crossed triangle keeps the default size: {:?}",
                f.tensors[v]
            );
        }
    }
    let crossed = crossed.len();
    assert!(crossed >= 8, "crossed {crossed}");
    assert!(f.default_size == 1.0 && f.reached.iter().filter(|r| **r).count() < m.coords.len());
}

// ---------------------------------------------------------------------------------
// The driver: order, default, clamp, gradation, determinism, errors, events

fn three_steps(m: &Model) -> Vec<(&'static str, Algorithm)> {
    vec![
        (
            "border",
            Algorithm::DistanceToBorder(DistanceToBorder {
                perpendicular: df(0.01, 0.2, 0.4, 1.0),
                parallel: df(0.1, 0.3, 0.4, 1.0),
                borders: m.curves(&[11, 14]),
            }),
        ),
        (
            "point",
            Algorithm::DistanceToPoint(DistanceToPoint {
                function: df(0.02, 0.3, 0.5, 1.0),
                sources: EntitySet { points: vec![m.point(20)], ..EntitySet::default() },
            }),
        ),
        (
            "gap",
            Algorithm::DistanceBetweenTwoBorders(DistanceBetweenTwoBorders {
                perpendicular: df(0.02, 0.2, 0.8, 1.0),
                parallel: df(0.05, 0.4, 0.8, 1.0),
                first: m.curves(&[12]),
                second: m.curves(&[14]),
            }),
        ),
        (
            "uniform",
            Algorithm::Uniform(Uniform {
                size: 0.08,
                on: EntitySet { faces: vec![m.face(2)], ..EntitySet::default() },
            }),
        ),
    ]
}

/// The field against its twin made from each step's [`Contribution`] (`run_algorithm`:
/// the reached vertices in propagation order, a tensor each), merged vertex by vertex in
/// plan order, then the default size and the clamp: the same bits, on a plan whose steps
/// reach all of the mesh, part of it (the point, where the field merges in vertex order
/// or as a list depending on the share reached), vertices skipped inside the reach (the
/// gap's thickness test), a face (UNIFORM), on 1 and 2 threads.
#[test]
fn field_is_the_contributions_merged_in_plan_order() {
    let m = grid(121, 81, 0.01, 0.3, 21, 0.6, (30, 40));
    let steps = [
        (
            "border",
            Algorithm::DistanceToBorder(DistanceToBorder {
                perpendicular: df(0.01, 0.2, 0.4, 1.0),
                parallel: df(0.1, 0.3, 0.4, 1.0),
                borders: m.curves(&[11, 14]),
            }),
        ),
        (
            "small point",
            Algorithm::DistanceToPoint(DistanceToPoint {
                function: df(0.005, 0.05, 0.04, 1.0),
                sources: EntitySet { points: vec![m.point(20)], ..EntitySet::default() },
            }),
        ),
        (
            "gap",
            Algorithm::DistanceBetweenTwoBorders(DistanceBetweenTwoBorders {
                perpendicular: df(0.02, 0.2, 0.5, 1.0),
                parallel: df(0.05, 0.4, 0.5, 1.0),
                first: m.curves(&[11]),
                second: m.curves(&[14]),
            }),
        ),
        (
            "uniform",
            Algorithm::Uniform(Uniform {
                size: 0.08,
                on: EntitySet { faces: vec![m.face(2)], ..EntitySet::default() },
            }),
        ),
    ];
    let bits = |ts: &[SizeTensor]| {
        ts.iter()
            .flat_map(|t| [t.axis()[0], t.axis()[1], t.h1(), t.h2()].map(f64::to_bits))
            .collect::<Vec<u64>>()
    };
    let n = m.coords.len();
    // Last steps: UNIFORM (a list), the gap and the border (merged in vertex order, which
    // finishes the field in the same pass); the default from the bounding box or h_max.
    for (order, h_max) in [([0, 1, 2, 3], None), ([3, 1, 0, 2], None), ([1, 3, 2, 0], Some(0.5))] {
        let mut p = plan(h_max, order.iter().map(|&k| steps[k].clone()).collect());
        p.h_min = Some(0.012);
        p.max_aspect_ratio = Some(6.0);
        let mut tensors = vec![SizeTensor::isotropic(1.0); n];
        let mut reached = vec![false; n];
        let mut counts = Vec::new();
        for (i, s) in p.steps.iter().enumerate() {
            let c = run_algorithm(&m.graph, &m.topo, &s.algorithm, i, &s.label).unwrap();
            for (&v, t) in c.vertices.iter().zip(&c.tensors) {
                let v = v as usize;
                tensors[v] = if reached[v] { tensors[v].intersection(t) } else { *t };
                reached[v] = true;
            }
            counts.push((s.label.clone(), c.len(), c.seeds));
        }
        let default = h_max.unwrap_or((1.2f64).hypot(0.8));
        let bounds =
            SizeBounds::try_new(0.012, h_max.unwrap_or(SizeTensor::MAX_SIZE), 6.0).unwrap();
        for (t, r) in tensors.iter_mut().zip(&reached) {
            let t0 = if *r { *t } else { SizeTensor::isotropic(default) };
            *t = t0.clamp(&bounds);
        }
        let count = |label: &str| counts.iter().find(|c| c.0 == label).unwrap().1;
        assert!(
            count("border") * 8 >= n && count("gap") * 8 >= n && count("small point") * 8 < n,
            "steps merged in vertex order and one as a list: {counts:?}"
        );
        assert!(count("gap") < n / 2, "the gap skips vertices within its reach: {counts:?}");
        assert!(reached.iter().any(|r| !r), "some vertex keeps the default size");
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let f = pool.install(|| run(&m, &p));
            let (got, want) = (bits(&f.tensors), bits(&tensors));
            let differ = (0..n)
                .filter(|&v| got[4 * v..4 * v + 4] != want[4 * v..4 * v + 4])
                .collect::<Vec<_>>();
            assert!(
                differ.is_empty(),
                "order {order:?}, {threads} threads: {} vertices differ, the first {:?}",
                differ.len(),
                differ.first().map(|&v| (v, f.tensors[v], tensors[v]))
            );
            assert_eq!(f.reached, reached);
            assert_eq!(
                f.steps
                    .iter()
                    .map(|s| (s.label.clone(), s.vertices_reached, s.seeds))
                    .collect::<Vec<_>>(),
                counts
            );
            assert_eq!(f.default_size, default);
        }
    }
}

#[test]
fn tensors_are_intersected_in_plan_order() {
    let m = grid(31, 31, 1.0 / 30.0, 0.3, 12, 0.6, (12, 18));
    let steps = three_steps(&m);
    let all = run(&m, &plan(Some(1.0), steps.clone()));
    let singles: Vec<SizeField> =
        steps.iter().map(|s| run(&m, &plan(Some(1.0), vec![s.clone()]))).collect();
    let mut overlaps = 0;
    for v in 0..m.coords.len() {
        let mut want: Option<SizeTensor> = None;
        let mut k = 0;
        for s in &singles {
            if s.reached[v] {
                k += 1;
                want = Some(match want {
                    Some(w) => w.intersection(&s.tensors[v]),
                    None => s.tensors[v],
                });
            }
        }
        overlaps += usize::from(k >= 2);
        assert_eq!(all.tensors[v], want.unwrap_or(SizeTensor::isotropic(1.0)), "vertex {v}");
    }
    assert!(overlaps > 50, "{overlaps} vertices reached by two steps or more");
    // Each report keeps its step's label and keyword.
    assert_eq!(
        all.steps.iter().map(|s| s.algorithm).collect::<Vec<_>>(),
        ["DISTANCE_TO_BORDER", "DISTANCE_TO_POINT", "DISTANCE_BETWEEN_TWO_BORDERS", "UNIFORM"]
    );
}

#[test]
fn default_size_and_its_warning() {
    let m = grid(21, 11, 0.1, 0.2, 13, 9.0, (4, 4));
    let step = (
        "point",
        Algorithm::DistanceToPoint(DistanceToPoint {
            function: df(0.02, 0.2, 0.3, 1.0),
            sources: EntitySet { points: vec![m.point(20)], ..EntitySet::default() },
        }),
    );
    let f = run(&m, &plan(None, vec![step.clone()]));
    let diag = (2.0f64).hypot(1.0);
    assert!(rel(f.default_size, diag) < 1e-15);
    assert_eq!(f.warnings.len(), 1);
    assert!(f.warnings[0].contains("bounding-box diagonal"), "{}", f.warnings[0]);
    let far = 20 + 10 * 21; // the top-right corner
    assert!(!f.reached[far] && f.tensors[far] == SizeTensor::isotropic(f.default_size));
    let g = run(&m, &plan(Some(0.7), vec![step]));
    assert!(g.warnings.is_empty());
    assert_eq!((g.default_size, g.tensors[far]), (0.7, SizeTensor::isotropic(0.7)));
}

#[test]
fn global_bounds_clamp_every_tensor() {
    let m = grid(31, 31, 1.0 / 30.0, 0.3, 14, 0.6, (12, 18));
    let raw = run(&m, &plan(None, three_steps(&m)));
    let mut p = plan(Some(0.15), three_steps(&m));
    p.h_min = Some(0.02);
    p.max_aspect_ratio = Some(3.0);
    let f = run(&m, &p);
    let b = SizeBounds::try_new(0.02, 0.15, 3.0).unwrap();
    for v in 0..m.coords.len() {
        let want =
            if raw.reached[v] { raw.tensors[v].clamp(&b) } else { SizeTensor::isotropic(0.15) };
        assert_eq!(f.tensors[v], want);
        assert!(
            f.tensors[v].h_min() >= 0.02
                && f.tensors[v].h_max() <= 0.15
                && f.tensors[v].aspect_ratio() <= 3.0 * (1.0 + 1e-15)
        );
    }
}

/// The metric of `t`, written out: R diag(1/h1², 1/h2²) Rᵀ as (a, b, c) = [[a, b], [b, c]].
fn metric(t: &SizeTensor) -> [f64; 3] {
    let [c, s] = t.axis();
    let [h1, h2] = t.sizes();
    let (l1, l2) = (1.0 / (h1 * h1), 1.0 / (h2 * h2));
    [c * c * l1 + s * s * l2, c * s * (l1 - l2), s * s * l1 + c * c * l2]
}

/// Whether ellipse `a` lies inside ellipse `b` scaled by `1 + slack`: M_a − M_b/(1+s)² is
/// positive semi-definite (to rounding).
fn inside(a: &SizeTensor, b: &SizeTensor, slack: f64) -> bool {
    let (ma, mb) = (metric(a), metric(b));
    let k = 1.0 / ((1.0 + slack) * (1.0 + slack));
    let d = [ma[0] - k * mb[0], ma[1] - k * mb[1], ma[2] - k * mb[2]];
    let tr = d[0] + d[2];
    let det = d[0] * d[2] - d[1] * d[1];
    let lmin = 0.5 * tr - (0.25 * (d[0] - d[2]).powi(2) + d[1] * d[1]).sqrt();
    let scale = ma[0].abs() + ma[2].abs() + ma[1].abs();
    let _ = det;
    lmin >= -1e-12 * scale
}

#[test]
fn gradation_bounds_growth_on_every_edge_and_never_grows_a_size() {
    let m = grid(61, 61, 1.0 / 60.0, 0.3, 15, 0.5, (20, 40));
    let g = 1.3;
    let steps = vec![
        (
            "border",
            Algorithm::DistanceToBorder(DistanceToBorder {
                perpendicular: df(0.002, 0.05, 0.15, 1.0),
                parallel: df(0.02, 0.1, 0.15, 1.0),
                borders: m.curves(&[11]),
            }),
        ),
        (
            "point",
            Algorithm::DistanceToPoint(DistanceToPoint {
                function: df(0.003, 0.02, 0.05, 1.0),
                sources: EntitySet { points: vec![m.point(20)], ..EntitySet::default() },
            }),
        ),
    ];
    let before = run(&m, &plan(Some(0.5), steps.clone()));
    let mut p = plan(Some(0.5), steps);
    p.gradation = Some(g);
    let after = run(&m, &p);
    let report = after.gradation.unwrap();
    assert!(report.converged && report.updates > 1000, "{report:?}");
    let mut edges = 0;
    for a in 0..m.coords.len() {
        assert!(inside(&after.tensors[a], &before.tensors[a], 1e-12), "vertex {a} grew");
        for &b in m.graph.neighbours(a) {
            let (tp, tq) = (&after.tensors[a], &after.tensors[b as usize]);
            let e = [
                m.coords[b as usize][0] - m.coords[a][0],
                m.coords[b as usize][1] - m.coords[a][1],
            ];
            let mp = metric(tp);
            let ell =
                (mp[0] * e[0] * e[0] + 2.0 * mp[1] * e[0] * e[1] + mp[2] * e[1] * e[1]).sqrt();
            let eta = g.powf(ell);
            let grown = SizeTensor::new(tp.axis(), tp.h1() * eta, tp.h2() * eta);
            assert!(inside(tq, &grown, 1e-8), "edge {a}-{b}: {tq:?} not inside {grown:?}");
            edges += 1;
        }
    }
    assert!(edges > 20_000);
    // Without gradation the bound fails somewhere, so the test above can fail.
    let broken = (0..m.coords.len()).any(|a| {
        m.graph.neighbours(a).iter().any(|&b| {
            let tp = &before.tensors[a];
            let e = [
                m.coords[b as usize][0] - m.coords[a][0],
                m.coords[b as usize][1] - m.coords[a][1],
            ];
            let eta = g.powf(tp.metric_length(e));
            !inside(
                &before.tensors[b as usize],
                &SizeTensor::new(tp.axis(), tp.h1() * eta, tp.h2() * eta),
                1e-8,
            )
        })
    });
    assert!(broken);
}

#[test]
fn same_field_whatever_the_thread_count() {
    let m = grid(201, 201, 0.005, 0.3, 16, 0.5, (100, 150));
    let mut p = plan(Some(0.2), three_steps(&m));
    p.steps.push(Step {
        label: "wake".into(),
        algorithm: Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
            perpendicular: df(0.002, 0.1, 0.3, 1.0),
            polyline_distance: df(0.01, 0.1, 1.0, 1.0),
            projection: SizeProjectionFunction::try_new(0.2, 0.3, 1.0).unwrap(),
            polyline: PolylinePoints::Plane(vec![[0.1, 0.5], [0.5, 0.6], [0.9, 0.4]]),
            within: EntitySet::default(),
        }),
        names: Vec::new(),
    });
    p.steps.push(Step {
        label: "curvature".into(),
        algorithm: Algorithm::CurvatureOfBorder(CurvatureOfBorder {
            perpendicular: df(0.002, 0.1, 0.3, 1.0),
            curvature: CurvatureToSize::try_new(0.001, 0.2, 0.001).unwrap(),
            projection: SizeProjectionFunction::try_new(0.2, 0.3, 1.0).unwrap(),
            borders: m.curves(&[11, 12, 13, 14]),
        }),
        names: Vec::new(),
    });
    p.gradation = Some(1.5);
    let run_in = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| run(&m, &p))
    };
    let (one, two) = (run_in(1), run_in(2));
    let bits = |f: &SizeField| {
        f.tensors
            .iter()
            .flat_map(|t| [t.axis()[0], t.axis()[1], t.h1(), t.h2()].map(f64::to_bits))
            .collect::<Vec<u64>>()
    };
    assert_eq!(bits(&one), bits(&two));
    assert_eq!(one.steps, two.steps);
    assert!(one.steps[0].vertices_reached > 4096, "levels large enough to run in parallel");
}

/// The six algorithms as one-step plans run side by side on a rayon pool (several
/// algorithms at once, each also spreading its levels and vertex ranges over the
/// threads) give, bit for bit, the fields that running them one after the other on
/// one thread gives; and the plan of all six agrees with itself on 1, 2 and 4 threads.
#[test]
fn algorithms_run_side_by_side_give_the_same_bits() {
    use rayon::prelude::*;
    // 0.6 wide, so that the two side walls of the gap step are within its reach.
    let m = grid(161, 161, 0.6 / 160.0, 0.3, 17, 0.3, (80, 120));
    let mut steps = three_steps(&m);
    steps.push((
        "wake",
        Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
            perpendicular: df(0.002, 0.1, 0.3, 1.0),
            polyline_distance: df(0.01, 0.1, 1.0, 1.0),
            projection: SizeProjectionFunction::try_new(0.2, 0.3, 1.0).unwrap(),
            polyline: PolylinePoints::Plane(vec![[0.1, 0.5], [0.5, 0.6], [0.9, 0.4]]),
            within: EntitySet::default(),
        }),
    ));
    steps.push((
        "curvature",
        Algorithm::CurvatureOfBorder(CurvatureOfBorder {
            perpendicular: df(0.002, 0.1, 0.3, 1.0),
            curvature: CurvatureToSize::try_new(0.001, 0.2, 0.001).unwrap(),
            projection: SizeProjectionFunction::try_new(0.2, 0.3, 1.0).unwrap(),
            borders: m.curves(&[11, 12, 13, 14]),
        }),
    ));
    let kinds: std::collections::BTreeSet<&str> = steps.iter().map(|(_, a)| a.keyword()).collect();
    assert_eq!(kinds.len(), 6, "all six algorithms");
    let plans: Vec<SizingPlan> = steps.iter().map(|s| plan(Some(0.2), vec![s.clone()])).collect();
    let bits = |f: &SizeField| {
        f.tensors
            .iter()
            .flat_map(|t| [t.axis()[0], t.axis()[1], t.h1(), t.h2()].map(f64::to_bits))
            .collect::<Vec<u64>>()
    };
    let pool =
        |threads: usize| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let one_by_one: Vec<Vec<u64>> =
        pool(1).install(|| plans.iter().map(|p| bits(&run(&m, p))).collect());
    for threads in [2, 4] {
        let side_by_side: Vec<Vec<u64>> =
            pool(threads).install(|| plans.par_iter().map(|p| bits(&run(&m, p))).collect());
        for (i, (a, b)) in one_by_one.iter().zip(&side_by_side).enumerate() {
            assert!(
                a == b,
                "{} on {threads} threads side by side differs from one thread",
                steps[i].0
            );
        }
    }
    let all = plan(Some(0.2), steps);
    let reference = pool(1).install(|| run(&m, &all));
    assert!(reference.steps.iter().all(|s| s.vertices_reached > 0), "{:?}", reference.steps);
    for threads in [2, 4] {
        let f = pool(threads).install(|| run(&m, &all));
        assert_eq!(bits(&f), bits(&reference), "six steps on {threads} threads");
        assert_eq!(f.steps, reference.steps);
    }
}

#[test]
fn errors_are_values() {
    let m = grid(11, 11, 0.1, 0.2, 17, 0.5, (5, 5));
    let go = |p: &SizingPlan| compute_size_field(&m.graph, &m.topo, p, &mut |_| {});
    let perp = df(0.01, 0.1, 0.2, 1.0);
    let e = go(&plan(
        None,
        vec![(
            "u",
            Algorithm::Uniform(Uniform {
                size: 0.1,
                on: EntitySet { curves: vec![999], ..EntitySet::default() },
            }),
        )],
    ))
    .unwrap_err();
    assert!(
        matches!(e, SizingError::EntityOutOfRange { step: 0, what: "curve", index: 999, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("step 0 (u)"));
    let e = go(&plan(
        None,
        vec![(
            "b",
            Algorithm::DistanceToBorder(DistanceToBorder {
                perpendicular: perp,
                parallel: perp,
                borders: EntitySet::default(),
            }),
        )],
    ))
    .unwrap_err();
    assert!(matches!(e, SizingError::NoSource { .. }), "{e:?}");
    let faces = EntitySet { faces: vec![0], ..EntitySet::default() };
    let e = go(&plan(
        None,
        vec![(
            "b",
            Algorithm::DistanceToBorder(DistanceToBorder {
                perpendicular: perp,
                parallel: perp,
                borders: faces,
            }),
        )],
    ))
    .unwrap_err();
    assert!(matches!(e, SizingError::UnsupportedEntity { what: "face", .. }), "{e:?}");
    let proj = SizeProjectionFunction::try_new(0.2, 0.3, 1.0).unwrap();
    let wake = |polyline: Vec<Point2>| {
        Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
            perpendicular: perp,
            polyline_distance: perp,
            projection: proj,
            polyline: PolylinePoints::Plane(polyline),
            within: EntitySet::default(),
        })
    };
    assert!(matches!(
        go(&plan(None, vec![("w", wake(vec![]))])).unwrap_err(),
        SizingError::EmptyPolyline { .. }
    ));
    assert!(matches!(
        go(&plan(None, vec![("w", wake(vec![[0.0, f64::NAN]]))])).unwrap_err(),
        SizingError::NonFinitePoint { point: 0, .. }
    ));
    assert!(matches!(
        go(&plan(
            None,
            vec![("u", Algorithm::Uniform(Uniform { size: 0.0, on: EntitySet::default() }))]
        ))
        .unwrap_err(),
        SizingError::InvalidSize { .. }
    ));
    let mut p = plan(Some(0.1), vec![]);
    p.h_min = Some(0.5);
    assert!(matches!(go(&p).unwrap_err(), SizingError::InvalidBounds { .. }));
    let mut p = plan(Some(0.1), vec![]);
    p.gradation = Some(0.5);
    assert!(matches!(go(&p).unwrap_err(), SizingError::InvalidGradation(_)));
    // A single point of a wake is a point source; the empty plan gives the default.
    assert!(go(&plan(Some(0.3), vec![("w", wake(vec![[0.5, 0.5]]))])).is_ok());
    let f = go(&plan(Some(0.3), vec![])).unwrap();
    assert!(
        f.tensors.iter().all(|t| *t == SizeTensor::isotropic(0.3)) && !f.reached.iter().any(|r| *r)
    );
}

#[test]
fn observer_hears_every_step() {
    let m = grid(11, 11, 0.1, 0.2, 18, 0.5, (5, 5));
    let p = plan(
        Some(1.0),
        vec![
            ("a", Algorithm::Uniform(Uniform { size: 0.1, on: m.curves(&[11]) })),
            ("b", Algorithm::Uniform(Uniform { size: 0.2, on: m.curves(&[12]) })),
        ],
    );
    let mut events = Vec::new();
    compute_size_field(&m.graph, &m.topo, &p, &mut |e| events.push(e)).unwrap();
    assert_eq!(
        events,
        vec![
            StepEvent::Started { index: 0, label: "a".into(), of: 2 },
            StepEvent::Finished { index: 0, reached: 11 },
            StepEvent::Started { index: 1, label: "b".into(), of: 2 },
            StepEvent::Finished { index: 1, reached: 11 },
        ]
    );
}

/// A step whose reach covers the whole mesh is evaluated in vertex order and merged as
/// it goes, with no propagation: the field must be, bit for bit, the step's
/// contribution (which always propagates, breadth first) merged and finished by hand.
/// Sources that are hard for a guess taken from the vertex before: a wavy closed
/// border seen from outside (its lobes put the medial axis inside the mesh), two close
/// walls of a grid, a wake that doubles back on itself, a point; meshes fine and
/// coarse (fewer vertices than segments: no clearances), on 1 and 2 threads, and a
/// mesh in two pieces of which only one holds the source (then the step propagates).
#[test]
fn full_reach_in_vertex_order_is_the_propagated_field() {
    let lobes = |a: f64| {
        let r = 1.0 + 0.25 * (5.0 * a).cos();
        [r * a.cos(), r * a.sin()]
    };
    let projection = SizeProjectionFunction::try_new(0.2, 50.0, 1.0).unwrap();
    let far = 50.0;
    let doubling_back =
        vec![[0.05, 0.3], [0.5, 0.35], [0.95, 0.3], [0.5, 0.36], [0.06, 0.45], [0.9, 0.5]];
    let steps = |m: &Model, border: &[i32], with_point: bool| -> Vec<(&'static str, Algorithm)> {
        let mut s = vec![
            (
                "border",
                Algorithm::DistanceToBorder(DistanceToBorder {
                    perpendicular: df(0.001, 0.1, far, 1.5),
                    parallel: df(0.01, 0.2, far, 1.0),
                    borders: m.curves(border),
                }),
            ),
            (
                "curvature",
                Algorithm::CurvatureOfBorder(CurvatureOfBorder {
                    perpendicular: df(0.002, 0.1, far, 1.0),
                    curvature: CurvatureToSize::try_new(0.001, 0.2, 0.001).unwrap(),
                    projection,
                    borders: m.curves(border),
                }),
            ),
            (
                "wake",
                Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
                    perpendicular: df(0.002, 0.1, far, 1.0),
                    polyline_distance: df(0.01, 0.1, 1.0, 1.0),
                    projection,
                    polyline: PolylinePoints::Plane(doubling_back.clone()),
                    within: EntitySet::default(),
                }),
            ),
        ];
        if with_point {
            s.push((
                "point",
                Algorithm::DistanceToPoint(DistanceToPoint {
                    function: df(0.005, 0.05, far, 2.0),
                    sources: EntitySet { points: vec![m.point(20)], ..EntitySet::default() },
                }),
            ));
        }
        s
    };
    let bits = |ts: &[SizeTensor]| {
        ts.iter()
            .flat_map(|t| [t.axis()[0], t.axis()[1], t.h1(), t.h2()].map(f64::to_bits))
            .collect::<Vec<u64>>()
    };
    let grid_walls = grid(61, 41, 0.01, 0.3, 3, 0.3, (30, 20));
    let cases: Vec<(&str, Model, Vec<i32>, bool)> = vec![
        ("lobes, fine", o_mesh(400, 30, 0.02, lobes, 4), vec![1], false),
        ("lobes, coarse", o_mesh(400, 2, 0.3, lobes, 5), vec![1], false),
        ("grid, two close walls", grid_walls, vec![11, 13], true),
    ];
    for (name, m, border, with_point) in &cases {
        let n = m.coords.len();
        for (label, algorithm) in steps(m, border, *with_point) {
            let c = run_algorithm(&m.graph, &m.topo, &algorithm, 0, label).unwrap();
            assert_eq!(c.len(), n, "{name}, {label}: every vertex within reach");
            let mut want = vec![SizeTensor::isotropic(1.0); n];
            for (&v, t) in c.vertices.iter().zip(&c.tensors) {
                want[v as usize] = t
                    .clamp(&SizeBounds::try_new(SizeTensor::MIN_SIZE, 1.0, f64::INFINITY).unwrap());
            }
            for threads in [1, 2] {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let f = pool.install(|| run(m, &plan(Some(1.0), vec![(label, algorithm.clone())])));
                let (got, expected) = (bits(&f.tensors), bits(&want));
                let differ = (0..n)
                    .filter(|&v| got[4 * v..4 * v + 4] != expected[4 * v..4 * v + 4])
                    .collect::<Vec<_>>();
                assert!(
                    differ.is_empty(),
                    "{name}, {label}, {threads} threads: {} vertices differ, the first {:?}",
                    differ.len(),
                    differ.first().map(|&v| (v, f.tensors[v], want[v]))
                );
                assert!(f.reached.iter().all(|&r| r));
                assert_eq!(
                    (f.steps[0].vertices_reached, f.steps[0].seeds),
                    (c.len(), c.seeds),
                    "{name}, {label}"
                );
            }
            // As the second step, after UNIFORM on the face: intersected into the field
            // as it goes.
            let uniform = Algorithm::Uniform(Uniform {
                size: 0.02,
                on: EntitySet { faces: vec![m.face(1)], ..EntitySet::default() },
            });
            let u = run_algorithm(&m.graph, &m.topo, &uniform, 0, "uniform").unwrap();
            let mut want: Vec<Option<SizeTensor>> = vec![None; n];
            for (&v, t) in u.vertices.iter().zip(&u.tensors) {
                want[v as usize] = Some(*t);
            }
            for (&v, t) in c.vertices.iter().zip(&c.tensors) {
                let w = &mut want[v as usize];
                *w = Some(w.map_or(*t, |w| w.intersection(t)));
            }
            let bounds = SizeBounds::try_new(SizeTensor::MIN_SIZE, 1.0, f64::INFINITY).unwrap();
            let want: Vec<SizeTensor> =
                want.into_iter().map(|t| t.unwrap().clamp(&bounds)).collect();
            for threads in [1, 2] {
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let f = pool.install(|| {
                    run(
                        m,
                        &plan(
                            Some(1.0),
                            vec![("uniform", uniform.clone()), (label, algorithm.clone())],
                        ),
                    )
                });
                let (got, expected) = (bits(&f.tensors), bits(&want));
                let differ =
                    (0..n).filter(|&v| got[4 * v..4 * v + 4] != expected[4 * v..4 * v + 4]).count();
                assert_eq!(
                    differ, 0,
                    "{name}, uniform then {label}, {threads} threads: vertices differ"
                );
                assert_eq!(f.steps[1].vertices_reached, n);
            }
        }
    }
    // Two pieces: the lobes' O-mesh, and a grid far off with no source. The border
    // reaches the first piece only.
    let a = o_mesh(200, 10, 0.03, lobes, 6);
    let b = grid(11, 11, 0.1, 0.2, 7, 0.5, (5, 5));
    let offset = a.coords.len();
    let mut coords = a.coords.clone();
    coords.extend(b.coords.iter().map(|p| [p[0] + 5.0, p[1]]));
    let mut tris = a.triangles.clone();
    tris.extend(b.triangles.iter().map(|t| t.map(|v| v + offset)));
    let m = Model::new(coords, tris, |_| 1, &[(1, (0..200).collect(), true)], &[]);
    let algorithm = Algorithm::DistanceToBorder(DistanceToBorder {
        perpendicular: df(0.001, 0.1, far, 1.5),
        parallel: df(0.01, 0.2, far, 1.0),
        borders: m.curves(&[1]),
    });
    let c = run_algorithm(&m.graph, &m.topo, &algorithm, 0, "border").unwrap();
    assert_eq!(c.len(), offset, "the piece without a source is not reached");
    let f = run(&m, &plan(Some(1.0), vec![("border", algorithm)]));
    assert_eq!(f.reached.iter().filter(|&&r| r).count(), offset);
    for (&v, t) in c.vertices.iter().zip(&c.tensors) {
        assert_eq!(bits(&[f.tensors[v as usize]]), bits(&[*t]));
    }
}
