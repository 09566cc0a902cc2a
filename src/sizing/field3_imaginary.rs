//! Twins of the free sources in space (DISTANCE_TO_IMAGINARY_POLYLINE with (x, y, z)
//! points, DISTANCE_TO_IMAGINARY_SURFACE): every closest point bit for bit a scan of
//! every segment or triangle, every tensor the definition written here to 1e-12, the
//! coarse-mesh rule's tetrahedra those of a scan of every tetrahedron, and the exact
//! piece–tetrahedron test against a separating-axis test on generic cases. Hard cases:
//! a helix, a folded (non-convex) sheet, two sheets close together, a coarse mesh the
//! source crosses far from every vertex.

use smartmesh_formats::TaggedMesh;
use smartmesh_test_support::grid::kuhn_box;

use super::tests::{plan, run};
use super::twins::{jittered_box, metric_gap, same_on_any_thread_count};
use super::*;
use crate::geometry::space::meets::piece_meets_tet;
use crate::geometry::space::{closest_brute, SurfacePoint, TriangleGeom};
use crate::sizing::algorithms::{
    Algorithm, DistanceToImaginaryPolyline, DistanceToImaginarySurface, EntitySet, PolylinePoints,
    Sheet,
};
use crate::sizing::functions::{DistanceFunction, SizeProjectionFunction};
use crate::sizing::space::crossed_corners_brute;
use crate::sizing::space::unit3;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// A helix of `n` points around the z axis through the box's middle.
fn helix(n: usize, centre: [f64; 3], radius: f64, pitch: f64) -> Vec<[f64; 3]> {
    (0..n)
        .map(|i| {
            let a = i as f64 * 0.7;
            [centre[0] + radius * a.cos(), centre[1] + radius * a.sin(), centre[2] + pitch * a]
        })
        .collect()
}

/// The polyline step; its reach is the larger of `perp`'s and `away` (the projection's
/// maximum distance).
fn polyline_step(points: Vec<[f64; 3]>, perp: DistanceFunction, away: f64) -> Algorithm {
    Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
        perpendicular: perp,
        polyline_distance: DistanceFunction::try_new(0.05, 0.4, 2.0, 1.0).unwrap(),
        projection: SizeProjectionFunction::try_new(0.5, away, 1.0).unwrap(),
        polyline: PolylinePoints::Space(points),
        within: EntitySet::default(),
    })
}

fn sheet_step(points: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>, reach: f64) -> Algorithm {
    Algorithm::DistanceToImaginarySurface(DistanceToImaginarySurface {
        perpendicular: DistanceFunction::try_new(0.01, 0.3, 0.5 * reach, 1.0).unwrap(),
        parallel: DistanceFunction::try_new(0.2, 0.5, reach, 1.0).unwrap(),
        sheet: Sheet { path: "sheet.stl".into(), points, triangles },
        within: EntitySet::default(),
    })
}

/// The brute-force closest point on the pieces `pieces` (each three corners).
fn scan(pieces: &[[[f64; 3]; 3]], p: [f64; 3]) -> SurfacePoint {
    let geoms: Vec<TriangleGeom> =
        pieces.iter().map(|c| TriangleGeom::new(c[0], c[1], c[2])).collect();
    closest_brute(&geoms, p).unwrap()
}

/// The field of `step` on `mesh` with an h_max, its source as the step builds it, and
/// the pieces of that source.
fn field_and_source(mesh: &TaggedMesh, step: &Algorithm) -> (SizeField3, SpaceSource) {
    let topology = Topology::from_mesh(mesh);
    let space = SpaceMesh::new(mesh, &topology).unwrap();
    let source = match step.work_in_space(&space, &topology).unwrap() {
        SpaceWork::FromSource { source, .. } => source,
        _ => panic!("a source"),
    };
    (run(mesh, &plan(vec![step.clone()], Some(10.0))).unwrap(), source)
}

/// Checks the index against the scan on every vertex and the crossed tetrahedra against
/// theirs; returns the corners crossed.
fn check_source(mesh: &TaggedMesh, source: &SpaceSource, pieces: &[[[f64; 3]; 3]]) -> Vec<bool> {
    let mut seed = u32::MAX;
    for p in &mesh.points {
        let a = source.closest_from(*p, seed).unwrap();
        seed = a.piece;
        let b = scan(pieces, *p);
        assert_eq!(a.distance_squared.to_bits(), b.projection.distance_squared.to_bits(), "{p:?}");
        assert_eq!((a.piece, a.foot), (b.triangle, b.projection.foot), "{p:?}");
    }
    let crossed = crossed_corners(mesh, source);
    assert_eq!(crossed, crossed_corners_brute(mesh, source));
    crossed
}

/// The tube tensor of the module header of DISTANCE_TO_IMAGINARY_POLYLINE, written here
/// from the scan's closest point.
fn tube(a: &Algorithm, points: &[[f64; 3]], p: [f64; 3]) -> Option<SizeTensor3> {
    let Algorithm::DistanceToImaginaryPolyline(a) = a else { unreachable!() };
    let pieces: Vec<[[f64; 3]; 3]> = points.windows(2).map(|w| [w[0], w[1], w[1]]).collect();
    let c = scan(&pieces, p);
    let (i, foot, d) =
        (c.triangle as usize, c.projection.foot, c.projection.distance_squared.sqrt());
    let s: f64 = points[..=i].windows(2).map(|w| norm(sub(w[1], w[0]))).sum::<f64>()
        + norm(sub(foot, points[i]));
    let dir = |k: usize| unit3(sub(points[k + 1], points[k])).unwrap();
    let t = if foot == points[i] && i > 0 {
        unit3(std::array::from_fn(|k| dir(i)[k] + dir(i - 1)[k]))?
    } else if foot == points[i + 1] && i + 2 < points.len() {
        unit3(std::array::from_fn(|k| dir(i)[k] + dir(i + 1)[k]))?
    } else {
        dir(i)
    };
    let n = unit3(sub(p, foot))?;
    let hp = a.perpendicular.eval(d);
    let ht = a.projection.eval(d, a.polyline_distance.eval(s));
    SizeTensor3::try_new(n, t, [hp, ht, hp])
}

/// Every vertex the field reached off the line has the tube tensor to 1e-12; every vertex
/// within reach or crossed was reached, no other.
fn check_tube(mesh: &TaggedMesh, step: &Algorithm, points: &[[f64; 3]], reach: f64) -> usize {
    let (field, source) = field_and_source(mesh, step);
    let pieces: Vec<[[f64; 3]; 3]> = points.windows(2).map(|w| [w[0], w[1], w[1]]).collect();
    let crossed = check_source(mesh, &source, &pieces);
    let mut checked = 0;
    for (v, p) in mesh.points.iter().enumerate() {
        let d2 = scan(&pieces, *p).projection.distance_squared;
        assert_eq!(field.reached[v], d2 <= reach * reach || crossed[v], "vertex {v}");
        if field.reached[v] && d2 > 1e-6 {
            let want = tube(step, points, *p).expect("a frame");
            let gap = metric_gap(&field.tensors[v].to_metric(), &want.to_metric());
            assert!(gap < 1e-12, "vertex {v}: {gap}");
            checked += 1;
        }
    }
    same_on_any_thread_count(mesh, &plan(vec![step.clone()], Some(10.0)));
    checked
}

#[test]
fn a_helix_in_space_is_its_twin() {
    let mesh = jittered_box(7, [1.0, 1.0, 1.2], 0.3, 11);
    let points = helix(24, [0.5, 0.5, 0.1], 0.3, 0.06);
    let perp = DistanceFunction::try_new(0.02, 0.3, 0.25, 1.0).unwrap();
    let n = check_tube(&mesh, &polyline_step(points.clone(), perp, 0.6), &points, 0.6);
    assert!(n > 100, "{n} vertices checked");
}

/// A coarse box (8 cells) and a short polyline inside one cell, far from every vertex
/// compared with its reach: the corners of the tetrahedra it crosses, and those only.
#[test]
fn a_polyline_crossing_a_coarse_mesh_sizes_the_cells_it_crosses() {
    let mesh = kuhn_box(2, [1.0, 1.0, 1.0]);
    let points = vec![[0.2, 0.27, 0.31], [0.33, 0.21, 0.18], [0.3, 0.3, 0.4]];
    let perp = DistanceFunction::try_new(0.01, 0.05, 0.02, 1.0).unwrap();
    let step = polyline_step(points.clone(), perp, 0.02);
    check_tube(&mesh, &step, &points, 0.02);
    let (field, source) = field_and_source(&mesh, &step);
    let pieces: Vec<[[f64; 3]; 3]> = points.windows(2).map(|w| [w[0], w[1], w[1]]).collect();
    let nearest = mesh
        .points
        .iter()
        .map(|p| scan(&pieces, *p).projection.distance_squared.sqrt())
        .fold(f64::INFINITY, f64::min);
    assert!(nearest > 0.1, "{nearest}");
    let crossed = crossed_corners(&mesh, &source);
    let count = crossed.iter().filter(|&&c| c).count();
    assert!(count >= 4, "{count}");
    assert_eq!(field.reached, crossed);
    assert!(field.steps[0].seeds == count);
}

/// The wall tensor of DISTANCE_TO_IMAGINARY_SURFACE off the sheet, written here.
fn wall(a: &Algorithm, pieces: &[[[f64; 3]; 3]], p: [f64; 3]) -> Option<SizeTensor3> {
    let Algorithm::DistanceToImaginarySurface(a) = a else { unreachable!() };
    let c = scan(pieces, p);
    let d = c.projection.distance_squared.sqrt();
    let n = unit3(sub(p, c.projection.foot))?;
    let (hp, ht) = (a.perpendicular.eval(d), a.parallel.eval(d));
    let other = if n[0].abs() < 0.5 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    SizeTensor3::try_new(n, other, [hp, ht, ht])
}

fn check_sheet(
    mesh: &TaggedMesh,
    points: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    reach: f64,
) -> usize {
    let step = sheet_step(points.clone(), triangles.clone(), reach);
    let (field, source) = field_and_source(mesh, &step);
    let pieces: Vec<[[f64; 3]; 3]> =
        triangles.iter().map(|t| t.map(|k| points[k as usize])).collect();
    let crossed = check_source(mesh, &source, &pieces);
    let mut checked = 0;
    for (v, p) in mesh.points.iter().enumerate() {
        let d2 = scan(&pieces, *p).projection.distance_squared;
        assert_eq!(field.reached[v], d2 <= reach * reach || crossed[v], "vertex {v}");
        if field.reached[v] && d2 > 1e-6 {
            let want = wall(&step, &pieces, *p).expect("a frame");
            let gap = metric_gap(&field.tensors[v].to_metric(), &want.to_metric());
            assert!(gap < 1e-12, "vertex {v}: {gap}");
            checked += 1;
        }
    }
    same_on_any_thread_count(mesh, &plan(vec![step], Some(10.0)));
    checked
}

/// A folded sheet: a zigzag of strips across the box (non-convex, with valleys that
/// see two strips), and two parallel sheets 0.01 apart; a coarse box crossed by a sheet
/// away from its vertices.
#[test]
fn folded_and_close_sheets_are_their_twins() {
    let mesh = jittered_box(6, [1.0, 1.0, 1.0], 0.3, 5);
    let (points, triangles) = super::crossed::folded_sheet(0.3, 0.6);
    assert!(check_sheet(&mesh, points, triangles, 0.5) > 50);
    let two: Vec<[f64; 3]> = [0.4, 0.41]
        .iter()
        .flat_map(|&z| {
            [[-0.1, -0.1, z], [1.1, -0.1, z + 0.02], [1.1, 1.1, z], [-0.1, 1.1, z - 0.01]]
        })
        .collect();
    let tris = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    assert!(check_sheet(&mesh, two.clone(), tris.clone(), 0.5) > 50);
    let coarse = kuhn_box(2, [1.0, 1.0, 1.0]);
    let small: Vec<[f64; 3]> = vec![[0.2, 0.2, 0.23], [0.4, 0.25, 0.27], [0.3, 0.4, 0.25]];
    check_sheet(&coarse, small.clone(), vec![[0, 1, 2]], 0.02);
    let (field, source) = field_and_source(&coarse, &sheet_step(small, vec![[0, 1, 2]], 0.02));
    let crossed = crossed_corners(&coarse, &source);
    assert!(crossed.iter().filter(|&&c| c).count() >= 4);
    assert_eq!(field.reached, crossed);
}

/// A float separating-axis test of a segment or triangle against a tetrahedron, with the
/// smallest separation found (near zero: a case too close to call in floating point).
fn sat(piece: &[[f64; 3]; 3], t: &[[f64; 3]; 4]) -> (bool, f64) {
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    };
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let mut axes = Vec::new();
    for f in [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]] {
        axes.push(cross(sub(t[f[1]], t[f[0]]), sub(t[f[2]], t[f[0]])));
    }
    let pe: Vec<[f64; 3]> = [(0, 1), (1, 2), (2, 0)]
        .iter()
        .map(|&(i, j)| sub(piece[j], piece[i]))
        .filter(|e| norm(*e) > 0.0)
        .collect();
    axes.push(cross(sub(piece[1], piece[0]), sub(piece[2], piece[0])));
    for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
        for e in &pe {
            axes.push(cross(sub(t[j], t[i]), *e));
        }
    }
    let mut best = f64::INFINITY;
    for a in axes {
        let l = norm(a);
        if l < 1e-12 {
            continue;
        }
        let a = a.map(|x| x / l);
        let (tl, th) = t
            .iter()
            .map(|p| dot(*p, a))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
        let (pl, ph) = piece
            .iter()
            .map(|p| dot(*p, a))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| (l.min(x), h.max(x)));
        let gap = (pl - th).max(tl - ph);
        if gap > 0.0 {
            return (false, gap);
        }
        best = best.min(-gap);
    }
    (true, best)
}

/// The exact test agrees with the separating-axis test on random segments, triangles
/// and points against random tetrahedra, wherever the float test is clear; touching
/// cases built exactly (a shared corner, a point on a face) meet.
#[test]
fn the_exact_piece_tetrahedron_test_is_its_twin() {
    let mut state = 7u64;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut met, mut apart) = (0, 0);
    for case in 0..4000 {
        let t: [[f64; 3]; 4] = std::array::from_fn(|_| std::array::from_fn(|_| next()));
        let mut piece: [[f64; 3]; 3] =
            std::array::from_fn(|_| std::array::from_fn(|_| next() * 1.4 - 0.2));
        match case % 3 {
            0 => piece[2] = piece[1],
            1 => piece[1] = piece[0],
            _ => {}
        }
        if case % 3 == 1 {
            piece[2] = piece[0];
        }
        let (float, margin) = sat(&piece, &t);
        if margin.abs() < 1e-9 {
            continue;
        }
        assert_eq!(piece_meets_tet(&piece, &t), float, "case {case}: {piece:?} {t:?}");
        if float {
            met += 1
        } else {
            apart += 1
        }
    }
    assert!(met > 500 && apart > 500, "{met} {apart}");
    let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    assert!(piece_meets_tet(&[[1.0, 0.0, 0.0], [2.0, 1.0, 0.0], [2.0, 1.0, 0.0]], &t));
    assert!(piece_meets_tet(&[[0.25, 0.25, 0.5], [0.25, 0.25, 0.5], [0.25, 0.25, 0.5]], &t));
    assert!(piece_meets_tet(&[[0.25, 0.25, -1.0], [0.25, 0.25, -1.0], [0.25, 0.25, 0.0]], &t));
    assert!(piece_meets_tet(&[[-1.0, 0.5, 0.0], [2.0, 0.5, 0.0], [2.0, 0.5, 0.0]], &t));
    assert!(!piece_meets_tet(
        &[[-1.0, 0.5, -1e-300], [2.0, 0.5, -1e-300], [2.0, 0.5, -1e-300]],
        &t
    ));
    assert!(piece_meets_tet(&[[0.2, 0.2, -1.0], [0.2, 0.2, 2.0], [2.0, 2.0, 2.0]], &t));
}

/// The box of [`kuhn_box`] (6 cubes a side) cut at x = 0.5 into two volumes: tag 1 for
/// x < 0.5, tag 2 beyond.
fn two_volumes() -> TaggedMesh {
    let mut mesh = kuhn_box(6, [1.0, 1.0, 1.0]);
    let points = mesh.points.clone();
    for block in mesh.blocks.iter_mut().filter(|b| b.kind == smartmesh_formats::CellKind::Tetra) {
        let cells: Vec<Vec<u32>> = block.cells().map(|c| c.to_vec()).collect();
        for (i, c) in cells.iter().enumerate() {
            let x: f64 = c.iter().map(|&v| points[v as usize][0]).sum::<f64>() / 4.0;
            let tag = if x > 0.5 { 2 } else { 1 };
            block.physical[i] = tag;
            block.geometrical[i] = tag;
        }
    }
    mesh
}

/// REGIONS on a free source in space: with a volume (or a surface) named, the vertices
/// of that volume (the corners of its cells: x ≥ 0.5) or surface (x = 1) are sized as
/// without REGIONS, bit for bit, crossed corners included, and no other vertex is.
#[test]
fn regions_keep_a_free_source_to_their_vertices() {
    let mesh = two_volumes();
    let topology = Topology::from_mesh(&mesh);
    let volumes = &topology.space.as_ref().unwrap().volumes;
    let second = volumes.iter().position(|v| v.tag == 2).unwrap();
    let side = super::tests::face(&mesh, 12);
    let points = helix(24, [0.5, 0.5, 0.1], 0.3, 0.06);
    let perp = DistanceFunction::try_new(0.02, 0.3, 0.25, 1.0).unwrap();
    let (sheet, tris) = (
        vec![[0.3, -0.1, 0.43], [1.2, -0.1, 0.41], [1.2, 1.1, 0.47], [0.3, 1.1, 0.45]],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    let regions = [
        (EntitySet { volumes: vec![second], ..EntitySet::default() }, 0.5),
        (EntitySet { faces: vec![side], ..EntitySet::default() }, 1.0),
    ];
    for (within, x_min) in regions {
        for mut step in
            [polyline_step(points.clone(), perp, 0.6), sheet_step(sheet.clone(), tris.clone(), 0.3)]
        {
            let everywhere = run(&mesh, &plan(vec![step.clone()], Some(10.0))).unwrap();
            match &mut step {
                Algorithm::DistanceToImaginaryPolyline(a) => a.within = within.clone(),
                Algorithm::DistanceToImaginarySurface(a) => a.within = within.clone(),
                _ => unreachable!(),
            }
            let field = run(&mesh, &plan(vec![step.clone()], Some(10.0))).unwrap();
            let (mut inside, mut outside) = (0, 0);
            for (v, p) in mesh.points.iter().enumerate() {
                let in_region = p[0] >= x_min;
                assert_eq!(field.reached[v], everywhere.reached[v] && in_region, "vertex {v}");
                if field.reached[v] {
                    assert_eq!(field.tensors[v], everywhere.tensors[v], "vertex {v}");
                    inside += 1;
                } else if everywhere.reached[v] {
                    outside += 1;
                }
            }
            assert!(inside > 10 && outside > 10, "{inside} {outside}");
            same_on_any_thread_count(&mesh, &plan(vec![step], Some(10.0)));
        }
    }
}
