//! Twins of the coarse-mesh rule of a free source on cells other than tetrahedra
//! (`sizing::space::crossed_corners`): hexahedra (warped by jitter), prisms, pyramids, and
//! a surface mesh in space of triangles or of warped quadrilaterals. On each, a helix and
//! a folded sheet mark the corners a scan of every piece against every cell marks; on an
//! unwarped hexahedral grid, the cells a segment meets are those an independent slab test
//! finds; coarse meshes crossed far from every vertex size the corners of the crossed
//! cells, and only those; the field is the same on 1 and 3 threads. And SOLUTION_HESSIAN
//! on those cells (split into tetrahedra for the recovery), exact on a quadratic at every
//! vertex.

use smartmesh_formats::{CellBlock, CellKind, TaggedMesh};

use super::tests::{plan, run};
use super::twins::same_on_any_thread_count;
use super::*;
use crate::sizing::algorithms::{
    Algorithm, DistanceToImaginaryPolyline, DistanceToImaginarySurface, EntitySet, PolylinePoints,
    Sheet,
};
use crate::sizing::functions::{DistanceFunction, SizeProjectionFunction};
use crate::sizing::space::crossed_corners_brute;

struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The grid points of the box [0, 1]³ with `n` cells a side, interior points moved by up
/// to `jitter` cells; point (i, j, k) has index (k (n + 1) + j) (n + 1) + i.
fn grid(n: usize, jitter: f64, seed: u64) -> TaggedMesh {
    let mut r = Random(seed);
    let mut mesh = TaggedMesh::new();
    mesh.coordinate_dim = 3;
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let interior = [i, j, k].iter().all(|&x| x > 0 && x < n);
                let p: [f64; 3] = std::array::from_fn(|d| {
                    let x = [i, j, k][d] as f64 / n as f64;
                    if interior {
                        x + jitter * (r.next() - 0.5) / n as f64
                    } else {
                        x
                    }
                });
                mesh.points.push(p);
            }
        }
    }
    mesh
}

/// The corners of cube (i, j, k) of the grid, in Gmsh's hexahedron order.
fn cube(n: usize, i: usize, j: usize, k: usize) -> [u32; 8] {
    let id = |a: usize, b: usize, c: usize| (((k + c) * (n + 1) + j + b) * (n + 1) + i + a) as u32;
    [
        id(0, 0, 0),
        id(1, 0, 0),
        id(1, 1, 0),
        id(0, 1, 0),
        id(0, 0, 1),
        id(1, 0, 1),
        id(1, 1, 1),
        id(0, 1, 1),
    ]
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Hexa,
    Wedge,
    Pyramid,
}

/// The grid's cubes as hexahedra, as two prisms each, or as six pyramids each around a
/// centre point added per cube (its face the base).
fn volume_mesh(n: usize, jitter: f64, seed: u64, kind: Kind) -> TaggedMesh {
    let mut mesh = grid(n, jitter, seed);
    let ck = match kind {
        Kind::Hexa => CellKind::Hexa,
        Kind::Wedge => CellKind::Wedge,
        Kind::Pyramid => CellKind::Pyramid,
    };
    let mut block = CellBlock::new(ck);
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = cube(n, i, j, k);
                match kind {
                    Kind::Hexa => block.push(&c, 1, 1),
                    Kind::Wedge => {
                        block.push(&[c[0], c[1], c[2], c[4], c[5], c[6]], 1, 1);
                        block.push(&[c[0], c[2], c[3], c[4], c[6], c[7]], 1, 1);
                    }
                    Kind::Pyramid => {
                        let centre: [f64; 3] = std::array::from_fn(|d| {
                            c.iter().map(|&v| mesh.points[v as usize][d]).sum::<f64>() / 8.0
                        });
                        let apex = mesh.points.len() as u32;
                        mesh.points.push(centre);
                        for f in CellKind::Hexa.faces() {
                            block.push(&[c[f[0]], c[f[1]], c[f[2]], c[f[3]], apex], 1, 1);
                        }
                    }
                }
            }
        }
    }
    mesh.blocks.push(block);
    mesh
}

/// A surface in space: the height field z = 0.5 + 0.15 sin(5x) cos(4y) over [0, 1]² with
/// `n` cells a side, as triangles or as (warped) quadrilaterals.
fn surface_mesh(n: usize, quads: bool) -> TaggedMesh {
    let mut mesh = TaggedMesh::new();
    mesh.coordinate_dim = 3;
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            mesh.points.push([x, y, 0.5 + 0.15 * (5.0 * x).sin() * (4.0 * y).cos()]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut block = CellBlock::new(if quads { CellKind::Quad } else { CellKind::Triangle });
    for j in 0..n {
        for i in 0..n {
            let q = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
            if quads {
                block.push(&q, 1, 1);
            } else {
                block.push(&[q[0], q[1], q[2]], 1, 1);
                block.push(&[q[0], q[2], q[3]], 1, 1);
            }
        }
    }
    mesh.blocks.push(block);
    mesh
}

fn polyline_step(points: Vec<[f64; 3]>, reach: f64) -> Algorithm {
    Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
        perpendicular: DistanceFunction::try_new(0.01, 0.3, reach, 1.0).unwrap(),
        polyline_distance: DistanceFunction::try_new(0.05, 0.4, 2.0, 1.0).unwrap(),
        projection: SizeProjectionFunction::try_new(0.5, reach, 1.0).unwrap(),
        polyline: PolylinePoints::Space(points),
        within: EntitySet::default(),
    })
}

fn sheet_step(points: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>, reach: f64) -> Algorithm {
    Algorithm::DistanceToImaginarySurface(DistanceToImaginarySurface {
        perpendicular: DistanceFunction::try_new(0.01, 0.3, reach, 1.0).unwrap(),
        parallel: DistanceFunction::try_new(0.2, 0.5, reach, 1.0).unwrap(),
        sheet: Sheet { path: "sheet.stl".into(), points, triangles },
        within: EntitySet::default(),
    })
}

/// The source `step` builds on `mesh`.
fn source_of(mesh: &TaggedMesh, step: &Algorithm) -> SpaceSource {
    let topology = Topology::from_mesh(mesh);
    let space = SpaceMesh::new(mesh, &topology).unwrap();
    let source = match step.work_in_space(&space, &topology).unwrap() {
        SpaceWork::FromSource { source, .. } => source,
        _ => panic!("a source"),
    };
    source
}

/// The corners `step` marks on `mesh`, checked against the scan of every cell; every
/// marked corner is reached by the step's field.
fn crossed_twin(mesh: &TaggedMesh, step: &Algorithm) -> Vec<bool> {
    let source = source_of(mesh, step);
    let crossed = crossed_corners(mesh, &source);
    assert_eq!(crossed, crossed_corners_brute(mesh, &source));
    let field = run(mesh, &plan(vec![step.clone()], Some(10.0))).unwrap();
    assert!(crossed.iter().zip(&field.reached).all(|(c, r)| !c || *r));
    assert_eq!(field.steps[0].seeds, crossed.iter().filter(|&&c| c).count());
    crossed
}

fn helix() -> Vec<[f64; 3]> {
    (0..30)
        .map(|i| {
            let a = i as f64 * 0.6;
            [0.5 + 0.3 * a.cos(), 0.5 + 0.3 * a.sin(), 0.05 + 0.05 * a]
        })
        .collect()
}

/// A zigzag sheet across the box: strips alternating between the heights `low` and
/// `high` (each strip rising 0.05 across y).
pub(super) fn folded_sheet(low: f64, high: f64) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let (mut points, mut triangles) = (Vec::new(), Vec::new());
    for i in 0..7 {
        let x = -0.1 + 0.2 * i as f64;
        let z = if i % 2 == 0 { low } else { high };
        points.push([x, -0.1, z]);
        points.push([x, 1.1, z + 0.05]);
        if i > 0 {
            let k = 2 * i as u32;
            triangles.push([k - 2, k, k + 1]);
            triangles.push([k - 2, k + 1, k - 1]);
        }
    }
    (points, triangles)
}

#[test]
fn crossed_cells_of_every_kind_are_their_scan() {
    let meshes = [
        volume_mesh(4, 0.5, 1, Kind::Hexa),
        volume_mesh(4, 0.5, 2, Kind::Wedge),
        volume_mesh(3, 0.5, 3, Kind::Pyramid),
        surface_mesh(6, false),
        surface_mesh(6, true),
    ];
    let (points, triangles) = folded_sheet(0.33, 0.61);
    for (m, mesh) in meshes.iter().enumerate() {
        // Reaches far below the cells: the marks come from the crossings.
        let by_line = crossed_twin(mesh, &polyline_step(helix(), 0.01));
        let by_sheet = crossed_twin(mesh, &sheet_step(points.clone(), triangles.clone(), 0.01));
        let (a, b) =
            (by_line.iter().filter(|&&c| c).count(), by_sheet.iter().filter(|&&c| c).count());
        // The helix pierces a surface once or twice: a few triangles.
        assert!(a >= 3 && b >= 8, "mesh {m}: {a} {b}");
        assert!(a < mesh.points.len() && b < mesh.points.len(), "mesh {m}: {a} {b}");
    }
}

/// Whether segment `pq` meets the box [lo, hi] (slab test, in floating point), and the
/// length of the overlap of its parameter intervals (negative: apart).
fn slab(p: [f64; 3], q: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> (bool, f64) {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for d in 0..3 {
        let dir = q[d] - p[d];
        let (a, b) = ((lo[d] - p[d]) / dir, (hi[d] - p[d]) / dir);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0 <= t1, t1 - t0)
}

/// On an unwarped hexahedral grid, the corners marked for a random segment are the
/// corners of the cells the slab test says it meets (cases within 1e-9 of a tie skipped).
#[test]
fn crossed_hexahedra_are_the_slab_tests_cells() {
    let n = 4;
    let mesh = volume_mesh(n, 0.0, 0, Kind::Hexa);
    let mut r = Random(23);
    let mut checked = 0;
    for _ in 0..60 {
        let p: [f64; 3] = std::array::from_fn(|_| r.next() * 1.2 - 0.1);
        let q: [f64; 3] = std::array::from_fn(|_| r.next() * 1.2 - 0.1);
        let mut want = vec![false; mesh.points.len()];
        let mut tie = false;
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let c = cube(n, i, j, k);
                    let (lo, hi) = (mesh.points[c[0] as usize], mesh.points[c[6] as usize]);
                    let (meets, overlap) = slab(p, q, lo, hi);
                    tie |= overlap.abs() < 1e-9;
                    if meets {
                        c.iter().for_each(|&v| want[v as usize] = true);
                    }
                }
            }
        }
        if tie {
            continue;
        }
        let source = source_of(&mesh, &polyline_step(vec![p, q], 0.01));
        assert_eq!(crossed_corners(&mesh, &source), want, "{p:?} {q:?}");
        checked += 1;
    }
    assert!(checked > 40, "{checked}");
}

/// A coarse mesh (2 cells a side, or a 2 × 2 surface) crossed inside one cell, far from
/// every vertex compared with the reach: exactly that cell's corners are sized.
#[test]
fn coarse_cells_crossed_far_from_their_corners_are_sized() {
    let hexes = volume_mesh(2, 0.0, 0, Kind::Hexa);
    let line = vec![[0.2, 0.27, 0.31], [0.33, 0.21, 0.18], [0.3, 0.3, 0.4]];
    let small = (vec![[0.2, 0.2, 0.23], [0.4, 0.25, 0.27], [0.3, 0.4, 0.25]], vec![[0, 1, 2]]);
    let cell = cube(2, 0, 0, 0).map(|v| v as usize);
    for step in [polyline_step(line, 0.02), sheet_step(small.0, small.1, 0.02)] {
        let crossed = crossed_twin(&hexes, &step);
        let want: Vec<bool> = (0..hexes.points.len()).map(|v| cell.contains(&v)).collect();
        assert_eq!(crossed, want);
        let field = run(&hexes, &plan(vec![step], Some(10.0))).unwrap();
        assert_eq!(field.reached, want);
    }
    // A vertical segment piercing one triangle of a coarse surface, away from its corners.
    let surface = surface_mesh(2, false);
    let step = polyline_step(vec![[0.3, 0.1, 0.0], [0.3, 0.1, 1.0]], 0.02);
    let crossed = crossed_twin(&surface, &step);
    let marked: Vec<usize> = (0..crossed.len()).filter(|&v| crossed[v]).collect();
    assert_eq!(marked, vec![0, 1, 4]);
    let field = run(&surface, &plan(vec![step], Some(10.0))).unwrap();
    assert_eq!(field.reached, crossed);
}

#[test]
fn crossed_cells_give_the_same_field_on_any_thread_count() {
    let (points, triangles) = folded_sheet(0.33, 0.61);
    for mesh in [volume_mesh(5, 0.5, 9, Kind::Hexa), surface_mesh(8, true)] {
        same_on_any_thread_count(&mesh, &plan(vec![polyline_step(helix(), 0.02)], Some(10.0)));
        let sheet = sheet_step(points.clone(), triangles.clone(), 0.02);
        same_on_any_thread_count(&mesh, &plan(vec![sheet], Some(10.0)));
    }
}

/// SOLUTION_HESSIAN on hexahedra, prisms and pyramids (split into tetrahedra on their
/// corners for the recovery): on a quadratic field with Hessian H, both recoveries are
/// exact at every vertex, so every vertex's metric is the same multiple c H, and the
/// normalisation over the cells' volume gives the c of a tetrahedral mesh of the same box
/// (the analytic twin: c = C^(2/3) det(H)^(-1/3), C the complexity of N vertices over the
/// unit box's volume).
#[test]
fn solution_hessian_on_every_volume_cell_is_exact_on_a_quadratic() {
    use crate::sizing::algorithms::SolutionHessian;
    use crate::solution::{Method, Target};
    use smartmesh_formats::DataArray;
    use smartmesh_test_support::grid::kuhn_box;
    let h: [[f64; 3]; 3] = [[2.0, 0.5, 0.1], [0.5, 1.0, -0.3], [0.1, -0.3, 3.0]];
    let u = |p: &[f64; 3]| {
        let mut q = 0.3 * p[0] - p[2];
        for i in 0..3 {
            for j in 0..3 {
                q += 0.5 * h[i][j] * p[i] * p[j];
            }
        }
        q
    };
    let det = h[0][0] * (h[1][1] * h[2][2] - h[1][2] * h[2][1])
        - h[0][1] * (h[1][0] * h[2][2] - h[1][2] * h[2][0])
        + h[0][2] * (h[1][0] * h[2][1] - h[1][1] * h[2][0]);
    let n: f64 = 3000.0;
    // The complexity of N vertices (a unit mesh's tetrahedra per vertex), over the unit box.
    let complexity = n / crate::metric::complexity3::vertices_of_complexity3(1.0);
    let c = complexity.powf(2.0 / 3.0) * det.powf(-1.0 / 3.0);
    for method in [Method::QuadraticFit, Method::L2Projection] {
        let step = Algorithm::SolutionHessian(SolutionHessian {
            fields: vec!["u".into()],
            target: Target::Vertices(n),
            p: 2.0,
            method,
            h_min: Some(1e-6),
            h_max: Some(100.0),
            max_aspect: Some(1e6),
        });
        // Warped cells (jittered): a warped face split along different diagonals by its
        // two cells leaves the tetrahedra's volume a little off the box's, so only the
        // common multiple is checked; planar ones: the multiple too.
        let meshes = [
            (volume_mesh(4, 0.4, 5, Kind::Hexa), false),
            (volume_mesh(4, 0.4, 6, Kind::Wedge), false),
            (volume_mesh(3, 0.4, 7, Kind::Pyramid), false),
            (volume_mesh(4, 0.0, 0, Kind::Hexa), true),
            (volume_mesh(4, 0.0, 0, Kind::Wedge), true),
            (volume_mesh(3, 0.0, 0, Kind::Pyramid), true),
            (kuhn_box(4, [1.0, 1.0, 1.0]), true),
        ];
        for (m, (mut mesh, planar)) in meshes.into_iter().enumerate() {
            let values = mesh.points.iter().map(u).collect();
            mesh.point_data.insert("u".into(), DataArray::new(1, values));
            let field = run(&mesh, &plan(vec![step.clone()], None)).unwrap();
            assert!(field.reached.iter().all(|&r| r), "mesh {m}");
            let first = field.tensors[0].to_metric().to_row_major()[0] / h[0][0];
            if planar {
                assert!((first - c).abs() < 1e-9 * c, "{method:?} mesh {m}: {first} {c}");
            }
            for (v, t) in field.tensors.iter().enumerate() {
                let metric = t.to_metric().to_row_major();
                for i in 0..3 {
                    for j in 0..3 {
                        let (got, want) = (metric[3 * i + j], first * h[i][j]);
                        assert!(
                            (got - want).abs() < 1e-9 * first,
                            "{method:?} mesh {m} vertex {v}: {got} {want}"
                        );
                    }
                }
            }
        }
    }
}
