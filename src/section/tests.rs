//! Twins of the cut: one tetrahedron at many planes against the convex hull of every
//! crossing computed apart; meshed boxes whose sections are known exactly; the
//! restricted ellipse of metrics worked by hand.

use super::*;
use crate::metric::SizeTensor;

fn tet_mesh(points: Vec<[f64; 3]>, tets: &[[usize; 4]]) -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = points;
    let mut b = CellBlock::new(CellKind::Tetra);
    for t in tets {
        b.nodes.extend(t.iter().map(|&v| v as NodeIndex));
        b.physical.push(1);
        b.geometrical.push(1);
    }
    m.blocks.push(b);
    m
}

/// The polygons of a section, as point lists in (u, v).
fn polygons(s: &Section) -> Vec<Vec<[f64; 2]>> {
    s.mesh
        .cells()
        .filter(|c| c.0.dim() == 2)
        .map(|(_, nodes, _, _)| {
            nodes
                .iter()
                .map(|&i| [s.mesh.points[i as usize][0], s.mesh.points[i as usize][1]])
                .collect()
        })
        .collect()
}

fn area(s: &Section) -> f64 {
    polygons(s).iter().map(|p| 0.5 * twice_area(p)).sum()
}

/// Brute force: every corner on the plane and every crossing of the six edges computed
/// by the parametric line, then their convex hull (monotone chain), counter-clockwise.
fn brute_hull(p: &[[f64; 3]; 4], plane: CutPlane) -> Vec<[f64; 2]> {
    let k = plane.axis.index();
    let [iu, iv] = plane.axis.in_plane();
    let mut pts: Vec<[f64; 2]> = Vec::new();
    for i in 0..4 {
        if p[i][k] == plane.value {
            pts.push([p[i][iu], p[i][iv]]);
        }
        for j in i + 1..4 {
            let (da, db) = (p[i][k] - plane.value, p[j][k] - plane.value);
            if da * db < 0.0 {
                let t = da / (da - db);
                pts.push([
                    p[i][iu] + t * (p[j][iu] - p[i][iu]),
                    p[i][iv] + t * (p[j][iv] - p[i][iv]),
                ]);
            }
        }
    }
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup_by(|a, b| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12);
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut hull: Vec<[f64; 2]> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[f64; 2]>> =
            if pass == 0 { Box::new(pts.iter()) } else { Box::new(pts.iter().rev()) };
        for &q in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

fn close(a: [f64; 2], b: [f64; 2]) -> bool {
    (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
}

#[test]
fn one_tetrahedron_at_many_planes_is_the_hull_of_its_crossings() {
    let p = [[0.0, 0.0, 0.0], [1.0, 0.1, 0.2], [0.3, 1.0, 0.4], [0.2, 0.3, 1.0]];
    let mesh = tet_mesh(p.to_vec(), &[[0, 1, 2, 3]]);
    let mut planes = Vec::new();
    for axis in [Axis::X, Axis::Y, Axis::Z] {
        // Through every corner (one, two corners on the plane: 0.0 holds vertex 0 alone
        // on x and y), and between them.
        for v in [-0.5, 0.0, 0.05, 0.1, 0.2, 0.25, 0.3, 0.35, 0.4, 0.7, 1.0, 1.5] {
            planes.push(CutPlane { axis, value: v });
        }
    }
    let mut shapes = BTreeMap::new();
    for plane in planes {
        let s = cut(&mesh, None, plane);
        let hull = brute_hull(&p, plane);
        let polys = polygons(&s);
        if hull.len() < 3 {
            assert!(polys.is_empty(), "{plane}: touches only, yet {polys:?}");
            continue;
        }
        assert_eq!(polys.len(), 1, "{plane}");
        let poly = &polys[0];
        assert_eq!(poly.len(), hull.len(), "{plane}: {poly:?} vs {hull:?}");
        assert!(twice_area(poly) > 0.0, "{plane}: counter-clockwise");
        assert!((twice_area(poly) - twice_area(&hull)).abs() < 1e-14, "{plane}");
        // Same cycle: the hull's first point is somewhere on ours, then both run on.
        let at = poly.iter().position(|&q| close(q, hull[0])).expect("hull point on the cut");
        for (i, h) in hull.iter().enumerate() {
            assert!(close(poly[(at + i) % poly.len()], *h), "{plane}: {poly:?} vs {hull:?}");
        }
        *shapes.entry(poly.len()).or_insert(0) += 1;
    }
    assert!(shapes[&3] > 0 && shapes[&4] > 0, "triangles and quads both met: {shapes:?}");
}

#[test]
fn every_case_of_corners_on_the_plane() {
    // z of the four corners, and how many corners the cut should have (0: nothing).
    let cases: [([f64; 4], usize); 9] = [
        ([-1.0, 1.0, 1.0, 1.0], 3),
        ([-1.0, -1.0, 1.0, 1.0], 4),
        ([0.0, -1.0, 1.0, 1.0], 3),
        ([0.0, -1.0, -1.0, 1.0], 3),
        ([0.0, 0.0, -1.0, 1.0], 3),
        ([0.0, 0.0, 0.0, 1.0], 3),
        ([0.0, 1.0, 1.0, 1.0], 0),
        ([0.0, 0.0, 1.0, 1.0], 0),
        ([1.0, 1.0, 1.0, 2.0], 0),
    ];
    let xy = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.3, 0.3]];
    for (z, n) in cases {
        let p: [[f64; 3]; 4] = std::array::from_fn(|i| [xy[i][0], xy[i][1], z[i]]);
        let mesh = tet_mesh(p.to_vec(), &[[0, 1, 2, 3]]);
        let plane = CutPlane { axis: Axis::Z, value: 0.0 };
        let polys = polygons(&cut(&mesh, None, plane));
        let got = polys.first().map_or(0, Vec::len);
        assert_eq!(got, n, "z {z:?}");
        if n > 0 {
            let hull = brute_hull(&p, plane);
            assert!((twice_area(&polys[0]) - twice_area(&hull)).abs() < 1e-14, "z {z:?}");
        }
    }
}

/// The box [0, a] × [0, b] × [0, c] as an `n`³ grid of cubes, six tetrahedra each
/// (Kuhn: round the main diagonal), the interior grid points moved by a seeded jitter
/// of up to `jitter` of a cell so that most cuts are generic.
fn meshed_box(dims: [f64; 3], n: usize, jitter: f64) -> TaggedMesh {
    let id = |i: usize, j: usize, k: usize| (k * (n + 1) + j) * (n + 1) + i;
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut points = vec![[0.0; 3]; (n + 1).pow(3)];
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let ijk = [i, j, k];
                let mut p = [0.0; 3];
                for d in 0..3 {
                    p[d] = dims[d] * ijk[d] as f64 / n as f64;
                    if ijk.iter().all(|&q| q > 0 && q < n) {
                        p[d] += jitter * dims[d] / n as f64 * rnd();
                    }
                }
                points[id(i, j, k)] = p;
            }
        }
    }
    let mut tets = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let c = |b: usize| id(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2 & 1));
                // The six paths from corner 0 to corner 7 along the cube's edges.
                for (a, b) in [(1, 3), (1, 5), (2, 3), (2, 6), (4, 5), (4, 6)] {
                    tets.push([c(0), c(a), c(b), c(7)]);
                }
            }
        }
    }
    tet_mesh(points, &tets)
}

#[test]
fn cut_of_a_meshed_box_has_the_boxs_section_area() {
    let dims = [2.0, 1.0, 3.0];
    for jitter in [0.0, 0.3] {
        let mesh = meshed_box(dims, 4, jitter);
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            let k = axis.index();
            let [iu, iv] = axis.in_plane();
            // Grid planes (faces in the plane, shared by two tetrahedra), the walls, and
            // planes in between.
            for f in [0.0, 0.1, 0.25, 0.5, 0.61, 0.75, 1.0] {
                let plane = CutPlane { axis, value: f * dims[k] };
                let s = cut(&mesh, None, plane);
                let want = dims[iu] * dims[iv];
                assert!(
                    (area(&s) - want).abs() < 1e-12,
                    "jitter {jitter}, {plane}: area {} vs {want}",
                    area(&s)
                );
                assert!(polygons(&s).iter().all(|p| twice_area(p) > 0.0));
                assert!((s.area - area(&s)).abs() < 1e-12);
                no_double_edges(&s, &format!("jitter {jitter}, {plane}"));
            }
        }
    }
}

/// Each edge of the cut's polygons has at most two polygons, on opposite sides of it,
/// and those with one lie on the box's walls: no overlap and no double line.
fn no_double_edges(s: &Section, what: &str) {
    let mut edges: BTreeMap<(u32, u32), Vec<bool>> = BTreeMap::new();
    for (kind, nodes, _, _) in s.mesh.cells() {
        if kind.dim() != 2 {
            continue;
        }
        for i in 0..nodes.len() {
            let (a, b) = (nodes[i], nodes[(i + 1) % nodes.len()]);
            edges.entry((a.min(b), a.max(b))).or_default().push(a < b);
        }
    }
    let (lo, hi) = s.mesh.bounding_box().unwrap();
    for ((a, b), dirs) in edges {
        match dirs.as_slice() {
            [x, y] => assert_ne!(x, y, "{what}: two polygons on one side of an edge"),
            [_] => {
                let (p, q) = (s.mesh.points[a as usize], s.mesh.points[b as usize]);
                let wall = (0..2)
                    .any(|d| (p[d] == lo[d] && q[d] == lo[d]) || (p[d] == hi[d] && q[d] == hi[d]));
                assert!(wall, "{what}: a free edge inside the section {p:?} {q:?}");
            }
            more => panic!("{what}: {} polygons on one edge", more.len()),
        }
    }
}

#[test]
fn faces_in_the_plane_are_kept_once_with_the_first_tag() {
    // Two tetrahedra on both sides of the face (0, 1, 2) in z = 0, tagged 1 and 2.
    let p =
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.2, 0.2, 1.0], [0.2, 0.2, -1.0]];
    let mut mesh = tet_mesh(p, &[[0, 1, 2, 3], [0, 2, 1, 4]]);
    mesh.blocks[0].physical[1] = 2;
    let s = cut(&mesh, None, CutPlane { axis: Axis::Z, value: 0.0 });
    assert_eq!(s.counts.faces_in_plane, 1);
    assert_eq!(polygons(&s).len(), 1);
    assert_eq!(s.mesh.blocks[0].physical, vec![1]);
    assert!((area(&s) - 0.5).abs() < 1e-15);
}

#[test]
fn surface_traces_are_segments_once_per_tag() {
    let mut mesh = meshed_box([1.0, 1.0, 1.0], 2, 0.0);
    // The wall x = 0 as tagged triangles (tag 7), and the grid plane z = 0.5 inside as a
    // tagged surface lying in the cut (tag 8).
    let mut tri = CellBlock::new(CellKind::Triangle);
    let id = |i: usize, j: usize, k: usize| (k * 3 + j) * 3 + i;
    for j in 0..2 {
        for k in 0..2 {
            for t in [
                [id(0, j, k), id(0, j + 1, k), id(0, j + 1, k + 1)],
                [id(0, j, k), id(0, j + 1, k + 1), id(0, j, k + 1)],
            ] {
                tri.nodes.extend(t.map(|v| v as NodeIndex));
                tri.physical.push(7);
                tri.geometrical.push(7);
            }
        }
    }
    for i in 0..2 {
        for j in 0..2 {
            for t in [
                [id(i, j, 1), id(i + 1, j, 1), id(i + 1, j + 1, 1)],
                [id(i, j, 1), id(i + 1, j + 1, 1), id(i, j + 1, 1)],
            ] {
                tri.nodes.extend(t.map(|v| v as NodeIndex));
                tri.physical.push(8);
                tri.geometrical.push(8);
            }
        }
    }
    mesh.blocks.push(tri);
    mesh.tag_names.insert((2, 7), "Wall".into());
    mesh.tag_names.insert((3, 1), "Box".into());
    // z = 0.3: the wall's trace is the segment x = 0, y in [0, 1]: four segments (both
    // triangles of each of its two columns cross it); the in-plane surface is not met.
    let s = cut(&mesh, None, CutPlane { axis: Axis::Z, value: 0.3 });
    let lines: Vec<(i32, [f64; 2], [f64; 2])> = line_cells(&s);
    assert_eq!(lines.len(), 4, "{lines:?}");
    let wall_len: f64 = lines.iter().filter(|l| l.0 == 7).map(|l| (l.1[1] - l.2[1]).abs()).sum();
    assert!((wall_len - 1.0).abs() < 1e-12 && lines.iter().all(|l| l.1[0] == 0.0 && l.2[0] == 0.0));
    assert_eq!(s.mesh.tag_name(1, 7), Some("Wall"));
    assert_eq!(s.mesh.tag_name(2, 1), Some("Box"));
    // z = 0.5: the wall's trace is the two grid edges x = 0; the in-plane surface gives
    // the boundary of its patch (8 edges), not its 8 inner edges.
    let s = cut(&mesh, None, CutPlane { axis: Axis::Z, value: 0.5 });
    let lines = line_cells(&s);
    assert_eq!(lines.iter().filter(|l| l.0 == 7).count(), 2, "{lines:?}");
    assert_eq!(lines.iter().filter(|l| l.0 == 8).count(), 8, "{lines:?}");
    assert!((area(&s) - 1.0).abs() < 1e-12);
}

fn line_cells(s: &Section) -> Vec<(i32, [f64; 2], [f64; 2])> {
    s.mesh
        .blocks
        .iter()
        .filter(|b| b.kind == CellKind::Line)
        .flat_map(|b| {
            b.cells().zip(&b.physical).map(|(n, &t)| {
                let p = |i: u32| [s.mesh.points[i as usize][0], s.mesh.points[i as usize][1]];
                (t, p(n[0]), p(n[1]))
            })
        })
        .collect()
}

#[test]
fn restricted_ellipse_of_a_diagonal_metric_by_hand() {
    let (hx, hy, hz) = (0.1, 0.4, 2.0);
    let m = Sym3::diagonal([1.0 / (hx * hx), 1.0 / (hy * hy), 1.0 / (hz * hz)]);
    for (axis, want) in [(Axis::X, [hy, hz]), (Axis::Y, [hx, hz]), (Axis::Z, [hx, hy])] {
        let t = SizeTensor::try_from_metric(&restrict(&m, axis)).unwrap();
        let mut got = t.sizes();
        got.sort_by(f64::total_cmp);
        assert!(
            (got[0] - want[0]).abs() < 1e-12 && (got[1] - want[1]).abs() < 1e-12,
            "{axis:?}: {got:?}"
        );
        // The first in-plane axis carries the first size.
        let a = t.axis();
        let along_u = (t.size_along([1.0, 0.0]) - want[0]).abs() < 1e-12;
        assert!(along_u, "{axis:?}: axis {a:?}");
    }
}

#[test]
fn a_leaning_ellipsoid_is_restricted_not_projected() {
    // Sizes (h1, h2, h3) along a frame turned by 45° about y: the plane z = c holds the
    // y axis (size h2) and the x axis, whose metric length is
    // √(cos² / h1² + sin² / h3²) per unit: the restricted size along x is its inverse.
    // The projection (the ellipsoid's shadow) would reach √(cos² h1² + sin² h3²).
    let (h1, h2, h3) = (0.1, 0.5, 1.0);
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let frame = [[s, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, s]];
    let m = Sym3::from_eigen([1.0 / (h1 * h1), 1.0 / (h2 * h2), 1.0 / (h3 * h3)], frame);
    let t = SizeTensor::try_from_metric(&restrict(&m, Axis::Z)).unwrap();
    let along_x = 1.0 / (0.5 / (h1 * h1) + 0.5 / (h3 * h3)).sqrt();
    assert!((t.size_along([1.0, 0.0]) - along_x).abs() < 1e-12);
    assert!((t.size_along([0.0, 1.0]) - h2).abs() < 1e-12);
    let shadow = (0.5 * h1 * h1 + 0.5 * h3 * h3).sqrt();
    assert!(shadow > 5.0 * along_x, "the projection differs: {shadow} vs {along_x}");
}

#[test]
fn metric_at_a_crossing_is_the_log_euclidean_mean_of_the_edge() {
    // One tetrahedron, corners at z = -1 (isotropic h = 1) and z = 1 (h = 4): the plane
    // z = 0 crosses each edge at t = 1/2, where the mean size is √(1·4) = 2.
    let p = vec![[0.0, 0.0, -1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0], [1.0, 1.0, 1.0]];
    let mesh = tet_mesh(p, &[[0, 1, 2, 3]]);
    let iso = |h: f64| Sym3::diagonal([1.0 / (h * h); 3]);
    let metric = vec![iso(1.0), iso(4.0), iso(4.0), iso(4.0)];
    let s = cut(&mesh, Some(&metric), CutPlane { axis: Axis::Z, value: 0.0 });
    let restricted = s.metric.as_ref().unwrap();
    assert_eq!(restricted.len(), 3);
    for m in restricted {
        let t = SizeTensor::try_from_metric(m).unwrap();
        assert!((t.h1() - 2.0).abs() < 1e-12 && (t.h2() - 2.0).abs() < 1e-12, "{t:?}");
    }
}

#[test]
fn planes_parse_and_bad_ones_say_what_is_expected() {
    assert_eq!(CutPlane::parse("z=0.5"), Ok(CutPlane { axis: Axis::Z, value: 0.5 }));
    assert_eq!(CutPlane::parse(" X = -1e-3 "), Ok(CutPlane { axis: Axis::X, value: -1e-3 }));
    for bad in ["z", "w=1", "z=", "z=nan", "z=inf", "z=1,5"] {
        let e = CutPlane::parse(bad).unwrap_err();
        assert!(e.contains("expected x=VALUE"), "{bad}: {e}");
    }
}
