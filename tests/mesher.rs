//! The mesher against brute-force twins: orientation, the constrained Delaunay property
//! (every circumcircle tested against every neighbour), exact coverage of each input
//! segment by Line cells with its tag, angle and area bounds, region tags and holes,
//! corners recovered by the topology, determinism, clear errors; and against Triangle
//! itself (PyPI `triangle`) on the same `.poly`, skipped when it is not installed unless
//! `SMARTMESH_REQUIRE_INTEROP=1`.

use smartmesh_test_support::formats as common;

use std::collections::BTreeMap;

use smartmesh::formats::{
    read_path, write_bytes, CellKind, Format, RegionSeed, TaggedMesh, WriteOptions,
};
use smartmesh::mesher::{size_to_area, triangulate, MeshError, MeshOptions};
use smartmesh::PointOrigin;
use smartmesh::Topology;
use smartmesh_test_support::measure::{min_angle_deg, quality as triangle_quality, signed_area};

#[path = "support/cli.rs"]
mod cli;
use cli::{fixture, run};

fn read_fixture(name: &str) -> TaggedMesh {
    read_path(&fixture(name), None).unwrap_or_else(|e| panic!("{e}"))
}

fn xy(m: &TaggedMesh, v: usize) -> [f64; 2] {
    [m.points[v][0], m.points[v][1]]
}

fn triangles(m: &TaggedMesh) -> Vec<([usize; 3], i32)> {
    m.cells()
        .filter(|c| c.0 == CellKind::Triangle)
        .map(|(_, n, p, _)| ([n[0] as usize, n[1] as usize, n[2] as usize], p))
        .collect()
}

fn lines(m: &TaggedMesh) -> Vec<([usize; 2], i32)> {
    m.cells()
        .filter(|c| c.0 == CellKind::Line)
        .map(|(_, n, p, _)| ([n[0] as usize, n[1] as usize], p))
        .collect()
}

/// Every triangle counter-clockwise with positive area.
fn check_orientation(m: &TaggedMesh) {
    for (t, _) in triangles(m) {
        let a = signed_area(xy(m, t[0]), xy(m, t[1]), xy(m, t[2]));
        assert!(a > 0.0, "triangle {t:?} has area {a}");
    }
}

/// The constrained Delaunay property, brute force: for every edge shared by two
/// triangles that is not a Line cell, the vertex opposite in one triangle is not strictly
/// inside the other's circumcircle (in-circle determinant, relative tolerance).
fn check_constrained_delaunay(m: &TaggedMesh) -> usize {
    let key = |a: usize, b: usize| (a.min(b), a.max(b));
    let constrained: std::collections::BTreeSet<(usize, usize)> =
        lines(m).iter().map(|(l, _)| key(l[0], l[1])).collect();
    let mut sides: BTreeMap<(usize, usize), Vec<(usize, usize)>> = BTreeMap::new();
    let tris = triangles(m);
    for (ti, (t, _)) in tris.iter().enumerate() {
        for k in 0..3 {
            sides.entry(key(t[k], t[(k + 1) % 3])).or_default().push((ti, t[(k + 2) % 3]));
        }
    }
    let mut checked = 0;
    for (e, s) in &sides {
        assert!(s.len() <= 2, "edge {e:?} is shared by {} triangles", s.len());
        if s.len() < 2 || constrained.contains(e) {
            continue;
        }
        for (i, j) in [(0, 1), (1, 0)] {
            let t = tris[s[i].0].0;
            let d = xy(m, s[j].1);
            let (a, b, c) = (xy(m, t[0]), xy(m, t[1]), xy(m, t[2]));
            let r = |p: [f64; 2]| [p[0] - d[0], p[1] - d[1]];
            let (ra, rb, rc) = (r(a), r(b), r(c));
            let n = |p: [f64; 2]| p[0] * p[0] + p[1] * p[1];
            let det = ra[0] * (rb[1] * n(rc) - n(rb) * rc[1])
                - ra[1] * (rb[0] * n(rc) - n(rb) * rc[0])
                + n(ra) * (rb[0] * rc[1] - rb[1] * rc[0]);
            let scale = (n(ra) + n(rb) + n(rc)).powi(2);
            assert!(det <= 1e-10 * scale, "edge {e:?}: vertex {} is inside the circumcircle of {t:?} (det {det:e}, scale {scale:e})", s[j].1);
        }
        checked += 1;
    }
    checked
}

/// Every input segment is covered, end to end and exactly once, by output Line cells
/// with its tag that lie on it; and every output Line cell lies on one input segment.
fn check_segment_coverage(input: &TaggedMesh, out: &TaggedMesh) {
    let out_lines = lines(out);
    let mut used = vec![0usize; out_lines.len()];
    for (kind, n, tag, _) in input.cells() {
        if kind != CellKind::Line {
            continue;
        }
        let (a, b) = (xy(input, n[0] as usize), xy(input, n[1] as usize));
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let param = |p: [f64; 2]| ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2;
        let off = |p: [f64; 2]| ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]).abs() / len2.sqrt();
        let mut pieces: Vec<(f64, f64)> = Vec::new();
        for (li, (l, ltag)) in out_lines.iter().enumerate() {
            let (p, q) = (xy(out, l[0]), xy(out, l[1]));
            let (tp, tq) = (param(p), param(q));
            let tol = 1e-9 * len2.sqrt();
            if off(p) <= tol
                && off(q) <= tol
                && (-1e-12..=1.0 + 1e-12).contains(&tp)
                && (-1e-12..=1.0 + 1e-12).contains(&tq)
            {
                assert_eq!(*ltag, tag, "a Line cell on a segment of tag {tag} has tag {ltag}");
                used[li] += 1;
                pieces.push((tp.min(tq), tp.max(tq)));
            }
        }
        pieces.sort_by(|x, y| x.0.total_cmp(&y.0));
        assert!(!pieces.is_empty(), "segment {a:?}-{b:?} has no Line cell");
        assert!(
            pieces[0].0.abs() < 1e-12 && (pieces.last().unwrap().1 - 1.0).abs() < 1e-12,
            "segment {a:?}-{b:?} is not covered to its ends"
        );
        for w in pieces.windows(2) {
            assert!(
                (w[0].1 - w[1].0).abs() < 1e-12,
                "segment {a:?}-{b:?}: gap or overlap between pieces {w:?}"
            );
        }
    }
    for (li, &u) in used.iter().enumerate() {
        assert_eq!(u, 1, "output Line cell {li} lies on {u} input segments");
    }
}

/// An input vertex and the segments (as end point pairs) that meet there.
type Apex = ([f64; 2], Vec<([f64; 2], [f64; 2])>);

/// Input vertices where two segments meet at less than 60 degrees (Ruppert's bound does
/// not hold next to them), as coordinates with their incident segments.
fn small_input_angles(input: &TaggedMesh) -> Vec<Apex> {
    let mut at: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (kind, n, _, _) in input.cells() {
        if kind == CellKind::Line {
            let (a, b) = (n[0] as usize, n[1] as usize);
            at.entry(a).or_default().push(b);
            at.entry(b).or_default().push(a);
        }
    }
    let mut out = Vec::new();
    for (&v, nb) in &at {
        let c = xy(input, v);
        let mut small = false;
        for i in 0..nb.len() {
            for j in i + 1..nb.len() {
                let (p, q) = (xy(input, nb[i]), xy(input, nb[j]));
                let (u, w) = ([p[0] - c[0], p[1] - c[1]], [q[0] - c[0], q[1] - c[1]]);
                let ang =
                    (u[0] * w[1] - u[1] * w[0]).abs().atan2(u[0] * w[0] + u[1] * w[1]).to_degrees();
                small |= ang < 60.0;
            }
        }
        if small {
            out.push((c, nb.iter().map(|&w| (c, xy(input, w))).collect()));
        }
    }
    out
}

/// Smallest angle of every triangle at least `bound`, except triangles whose shortest
/// edge joins two points on the segments of one small input angle. Returns how many
/// triangles were exempt.
fn check_min_angle(input: &TaggedMesh, out: &TaggedMesh, bound: f64) -> usize {
    let apexes = small_input_angles(input);
    let on = |p: [f64; 2], (a, b): ([f64; 2], [f64; 2])| {
        let d = [b[0] - a[0], b[1] - a[1]];
        let l = d[0].hypot(d[1]);
        let t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / (l * l);
        ((p[0] - a[0]) * d[1] - (p[1] - a[1]) * d[0]).abs() / l < 1e-9 * l
            && (-1e-12..=1.0 + 1e-12).contains(&t)
    };
    let mut exempt = 0;
    for (t, _) in triangles(out) {
        let p = [xy(out, t[0]), xy(out, t[1]), xy(out, t[2])];
        let ang = min_angle_deg(p[0], p[1], p[2]);
        if ang >= bound - 1e-9 {
            continue;
        }
        let l2 = |i: usize| {
            let (a, b) = (p[i], p[(i + 1) % 3]);
            (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
        };
        let k = (0..3).min_by(|&i, &j| l2(i).total_cmp(&l2(j))).unwrap();
        let (a, b) = (p[k], p[(k + 1) % 3]);
        let near = apexes
            .iter()
            .any(|(_, segs)| segs.iter().any(|&s| on(a, s)) && segs.iter().any(|&s| on(b, s)));
        assert!(
            near,
            "triangle {p:?} has smallest angle {ang} < {bound} away from any small input angle"
        );
        exempt += 1;
    }
    exempt
}

fn area_of(m: &TaggedMesh, t: [usize; 3]) -> f64 {
    signed_area(xy(m, t[0]), xy(m, t[1]), xy(m, t[2]))
}

fn centroid(m: &TaggedMesh, t: [usize; 3]) -> [f64; 2] {
    let p = [xy(m, t[0]), xy(m, t[1]), xy(m, t[2])];
    [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0]
}

#[test]
fn square_with_hole_and_two_regions() {
    let input = read_fixture("square_hole.poly");
    let out = triangulate(&input, &MeshOptions::default()).unwrap();
    check_orientation(&out);
    assert!(check_constrained_delaunay(&out) > 100);
    check_segment_coverage(&input, &out);
    assert_eq!(check_min_angle(&input, &out, 20.7), 0, "the square has no small input angle");
    let mut area = [0.0; 2];
    for (t, tag) in triangles(&out) {
        let c = centroid(&out, t);
        assert!(
            !((0.2..=0.4).contains(&c[0]) && (0.4..=0.6).contains(&c[1])),
            "triangle {t:?} is in the hole"
        );
        let expected = if c[0] < 0.6 { 10 } else { 20 };
        assert_eq!(tag, expected, "triangle at {c:?}");
        if tag == 20 {
            assert!(area_of(&out, t) <= 0.002, "region 20's bound");
        }
        area[(tag == 20) as usize] += area_of(&out, t);
    }
    // The left region is 0.6 minus the hole's 0.04, the right one 0.4.
    assert!((area[0] - 0.56).abs() < 1e-12 && (area[1] - 0.4).abs() < 1e-12, "areas {area:?}");
    // The right region (bounded) is finer than the left one.
    let count = |tag| triangles(&out).iter().filter(|t| t.1 == tag).count();
    assert!(count(20) >= 200, "region 20 has {} triangles; 0.4 / 0.002 = 200 at least", count(20));
}

#[test]
fn topology_of_the_output_has_the_input_curves_and_corners() {
    let input = read_fixture("square_hole.poly");
    let out = triangulate(&input, &MeshOptions::default()).unwrap();
    let topo = Topology::from_mesh(&out);
    let mut tags: Vec<i32> = topo.curves.iter().filter_map(|c| c.tag).collect();
    tags.sort();
    assert_eq!(tags, vec![1, 2, 3, 4, 5, 6], "one curve per marker and no derived curve");
    assert_eq!(topo.curves.len(), 6);
    assert_eq!(topo.faces.iter().map(|f| f.tag).collect::<Vec<_>>(), vec![10, 20]);
    let mut corners: Vec<[f64; 2]> = topo.points.iter().map(|p| xy(&out, p.vertex)).collect();
    corners.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    let mut expected: Vec<[f64; 2]> = input.points.iter().map(|p| [p[0], p[1]]).collect();
    expected.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    assert_eq!(
        corners, expected,
        "every vertex of the .poly is a corner (tag change, junction or right angle)"
    );
    assert!(
        topo.points.iter().all(|p| p.origin == PointOrigin::Listed),
        "corners are listed as Vertex cells"
    );
    // The Vertex cells' tags are distinct.
    let mut vt: Vec<i32> = out.cells().filter(|c| c.0 == CellKind::Vertex).map(|c| c.2).collect();
    vt.sort();
    vt.dedup();
    assert_eq!(vt.len(), 10);
}

#[test]
fn airfoil_with_area_bound_and_thirty_degrees() {
    let input = read_fixture("naca0012.poly");
    let opts = MeshOptions { min_angle_deg: 30.0, max_area: Some(0.01), ..MeshOptions::default() };
    let out = triangulate(&input, &opts).unwrap();
    check_orientation(&out);
    check_constrained_delaunay(&out);
    check_segment_coverage(&input, &out);
    let exempt = check_min_angle(&input, &out, 30.0);
    assert!(exempt < 20, "{exempt} triangles exempt near the trailing edge");
    for (t, tag) in triangles(&out) {
        assert!(area_of(&out, t) <= 0.01);
        assert_eq!(tag, 1);
        let c = centroid(&out, t);
        assert!(
            !((0.05..0.95).contains(&c[0]) && c[1].abs() < 0.01),
            "triangle inside the airfoil at {c:?}"
        );
    }
    let total: f64 = triangles(&out).iter().map(|t| area_of(&out, t.0)).sum();
    assert!(total < 20.0 && total > 19.9, "box minus airfoil, got {total}");
    // Corners: the four box corners and the trailing edge (a sharp turn); the leading
    // edge turns by less than 30 degrees between neighbouring pieces.
    let topo = Topology::from_mesh(&out);
    let pts: Vec<[f64; 2]> = topo.points.iter().map(|p| xy(&out, p.vertex)).collect();
    assert_eq!(pts.len(), 5, "{pts:?}");
    assert!(pts.contains(&[1.0, 0.0]) && pts.contains(&[-2.0, -2.0]) && pts.contains(&[3.0, 2.0]));
}

/// A region's own area bound on a graph without interfaces (spade excludes the outside
/// itself there): every triangle of the region within it, the angle bound kept.
#[test]
fn region_area_bound_on_the_airfoil() {
    let mut input = read_fixture("naca0012.poly");
    input.regions[0].max_area = 0.004;
    let out = triangulate(&input, &MeshOptions::default()).unwrap();
    for (t, tag) in triangles(&out) {
        assert_eq!(tag, 1);
        assert!(area_of(&out, t) <= 0.004, "area {}", area_of(&out, t));
    }
    assert!(triangles(&out).len() as f64 >= 19.9 / 0.004);
    check_constrained_delaunay(&out);
    check_min_angle(&input, &out, 20.7);
}

#[test]
fn uniform_size_bounds_every_area() {
    let input = read_fixture("square_hole.poly");
    let h = 0.05;
    let out =
        triangulate(&input, &MeshOptions { size: Some(h), ..MeshOptions::default() }).unwrap();
    let bound = size_to_area(h);
    assert!((bound - 3f64.sqrt() / 4.0 * h * h).abs() < 1e-18);
    for (t, _) in triangles(&out) {
        assert!(area_of(&out, t) <= bound.min(0.002) || centroid(&out, t)[0] < 0.6);
        assert!(area_of(&out, t) <= bound);
    }
    check_constrained_delaunay(&out);
    check_segment_coverage(&input, &out);
    check_min_angle(&input, &out, 20.7);
}

#[test]
fn deterministic() {
    let input = read_fixture("naca0012.poly");
    let opts = MeshOptions { max_area: Some(0.02), ..MeshOptions::default() };
    let a = triangulate(&input, &opts).unwrap();
    let b = triangulate(&input, &opts).unwrap();
    assert_eq!(a, b);
    let w = |m: &TaggedMesh| write_bytes(Format::Gmsh, m, &WriteOptions::default()).unwrap().main;
    assert_eq!(w(&a), w(&b));
}

/// A mesh as a graph: its Line cells and Vertex cells; its triangles say what is inside.
#[test]
fn a_gmsh_mesh_is_remeshed_from_its_lines() {
    let input = read_fixture("cylinder.msh");
    let out =
        triangulate(&input, &MeshOptions { size: Some(0.1), ..MeshOptions::default() }).unwrap();
    check_orientation(&out);
    check_constrained_delaunay(&out);
    check_segment_coverage(&input, &out);
    for (t, tag) in triangles(&out) {
        assert_eq!(tag, 10, "the Fluid face");
        let c = centroid(&out, t);
        assert!((c[0] - 1.0).hypot(c[1] - 0.5) > 0.14, "triangle inside the cylinder at {c:?}");
    }
    let total: f64 = triangles(&out).iter().map(|t| area_of(&out, t.0)).sum();
    let input_area: f64 = triangles(&input).iter().map(|t| area_of(&input, t.0)).sum();
    assert!((total - input_area).abs() < 1e-9, "{total} vs the input's {input_area}");
    let topo = Topology::from_mesh(&out);
    let named: Vec<&str> = topo.curves.iter().filter_map(|c| c.name.as_deref()).collect();
    for n in ["Inlet", "Outlet", "Walls", "Cylinder"] {
        assert!(named.contains(&n), "curve {n} in {named:?}");
    }
    assert!(topo
        .points
        .iter()
        .any(|p| p.tag == Some(20) && p.name.as_deref() == Some("Stagnation")));
}

fn pslg(points: &[[f64; 2]], segments: &[[usize; 2]]) -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = points.iter().map(|p| [p[0], p[1], 0.0]).collect();
    let b = m.block_mut(CellKind::Line);
    for (k, s) in segments.iter().enumerate() {
        b.push(s, k as i32 + 1, k as i32 + 1);
    }
    m
}

const SQUARE: [[f64; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
const LOOP: [[usize; 2]; 4] = [[0, 1], [1, 2], [2, 3], [3, 0]];

#[test]
fn keep_convex_hull_meshes_the_hull_of_an_open_graph() {
    // An L-shaped open polyline: carving eats everything, the hull keeps the triangle.
    let m = pslg(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]], &[[0, 1], [1, 2]]);
    assert_eq!(triangulate(&m, &MeshOptions::default()), Err(MeshError::NothingToMesh));
    let out = triangulate(
        &m,
        &MeshOptions { keep_convex_hull: true, max_area: Some(0.01), ..MeshOptions::default() },
    )
    .unwrap();
    let total: f64 = triangles(&out).iter().map(|t| area_of(&out, t.0)).sum();
    assert!((total - 0.5).abs() < 1e-12);
    check_constrained_delaunay(&out);
    check_segment_coverage(&m, &out);
}

#[test]
fn no_refinement_is_the_plain_constrained_triangulation() {
    let m = pslg(&SQUARE, &LOOP);
    let out =
        triangulate(&m, &MeshOptions { min_angle_deg: 0.0, ..MeshOptions::default() }).unwrap();
    assert_eq!(out.points.len(), 4);
    assert_eq!(triangles(&out).len(), 2);
    assert_eq!(lines(&out).len(), 4);
}

#[test]
fn bad_graphs_get_clear_errors() {
    let mut dup = pslg(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [1.0, 0.0]], &LOOP);
    let e = triangulate(&dup, &MeshOptions::default()).unwrap_err();
    assert_eq!(e, MeshError::DuplicatePoint { first: 1, second: 4, at: [1.0, 0.0] });
    assert!(e.to_string().contains("points 1 and 4 are both at (1, 0)"), "{e}");
    dup.points[4] = [-0.0, 0.0, 0.0];
    assert!(matches!(
        triangulate(&dup, &MeshOptions::default()),
        Err(MeshError::DuplicatePoint { first: 0, second: 4, .. })
    ));

    let zero = pslg(&SQUARE, &[[0, 1], [1, 2], [2, 2], [2, 3], [3, 0]]);
    assert_eq!(
        triangulate(&zero, &MeshOptions::default()),
        Err(MeshError::ZeroLengthSegment { segment: 3, point: 2 })
    );

    let twice = pslg(&SQUARE, &[[0, 1], [1, 2], [2, 3], [3, 0], [1, 0]]);
    assert_eq!(
        triangulate(&twice, &MeshOptions::default()),
        Err(MeshError::DuplicateSegment { first: 1, second: 5 })
    );

    let crossing = pslg(&SQUARE, &[[0, 1], [1, 2], [2, 3], [3, 0], [0, 2], [1, 3]]);
    let e = triangulate(&crossing, &MeshOptions::default()).unwrap_err();
    assert!(matches!(e, MeshError::SegmentsCross { segment: 5 | 6, other: Some(5 | 6) }), "{e:?}");
    assert!(e.to_string().contains("crosses segment"), "{e}");

    let mut outside = pslg(&SQUARE, &LOOP);
    outside.points.push([2.0, 2.0, 0.0]);
    outside.regions.push(RegionSeed { point: [2.0, 0.5], attribute: 3.0, max_area: -1.0 });
    assert_eq!(
        triangulate(&outside, &MeshOptions::default()),
        Err(MeshError::RegionOutside { region: 1, point: [2.0, 0.5] })
    );
    outside.regions[0].point = [1.5, 1.5];
    assert_eq!(
        triangulate(&outside, &MeshOptions::default()),
        Err(MeshError::RegionOutside { region: 1, point: [1.5, 1.5] })
    );
    outside.regions[0].point = [1.0, 0.5];
    assert!(matches!(
        triangulate(&outside, &MeshOptions::default()),
        Err(MeshError::SeedOnSegment { what: "region", number: 1, .. })
    ));
    // A real regional attribute (Triangle's are reals) is no tag: it travels as a field.
    outside.regions[0] = RegionSeed { point: [0.5, 0.5], attribute: 2.5, max_area: -1.0 };
    let real = triangulate(&outside, &MeshOptions::default()).unwrap();
    assert!(triangles(&real).iter().all(|&(_, tag)| tag == 0));
    let field = &real.cell_data["triangle:attribute1"].values;
    let ntri = triangles(&real).len();
    assert!(field[field.len() - ntri..].iter().all(|&a| a == 2.5));
    assert!(field[..field.len() - ntri].iter().all(|&a| a == 0.0));

    let mut holed = pslg(&SQUARE, &LOOP);
    holed.holes.push([0.5, 0.5]);
    assert_eq!(triangulate(&holed, &MeshOptions::default()), Err(MeshError::NothingToMesh));

    let capped =
        MeshOptions { max_area: Some(0.001), max_vertices: Some(50), ..MeshOptions::default() };
    let e = triangulate(&pslg(&SQUARE, &LOOP), &capped).unwrap_err();
    assert!(matches!(e, MeshError::RefinementIncomplete { .. }) && !e.is_input_error(), "{e:?}");
    assert!(e.to_string().contains("--max-vertices"), "{e}");

    for bad in [
        MeshOptions { min_angle_deg: 40.0, ..MeshOptions::default() },
        MeshOptions { max_area: Some(-1.0), ..MeshOptions::default() },
        MeshOptions { size: Some(0.0), ..MeshOptions::default() },
    ] {
        assert!(matches!(
            triangulate(&pslg(&SQUARE, &LOOP), &bad),
            Err(MeshError::BadOption { .. })
        ));
    }
}

/// A collinear point on a segment splits it; both pieces keep the segment's tag.
#[test]
fn a_vertex_on_a_segment_splits_it() {
    let m = pslg(&[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.0]], &LOOP);
    let out =
        triangulate(&m, &MeshOptions { min_angle_deg: 0.0, ..MeshOptions::default() }).unwrap();
    check_segment_coverage(&m, &out);
    assert_eq!(lines(&out).len(), 5);
}

#[test]
fn cli_meshes_and_reports() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sq.msh");
    let o = run(&[
        "mesh",
        fixture("square_hole.poly").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--json",
        "--max-area",
        "0.01",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let back = read_path(&out, None).unwrap();
    assert_eq!(s["triangles"].as_u64().unwrap() as usize, back.num_cells_of(CellKind::Triangle));
    assert_eq!(s["corners"], 10);
    assert_eq!(s["faces"], 2);
    assert!(s["quality"]["min_angle_deg"].as_f64().unwrap() >= 20.7);
    assert_eq!(
        back.num_cells_of(CellKind::Line),
        triangulate(
            &read_fixture("square_hole.poly"),
            &MeshOptions { max_area: Some(0.01), ..MeshOptions::default() }
        )
        .unwrap()
        .num_cells_of(CellKind::Line)
    );
}

#[test]
fn cli_bad_input_exits_2_naming_the_file_and_leaves_no_output() {
    let dir = tempfile::tempdir().unwrap();
    let poly = dir.path().join("cross.poly");
    std::fs::write(
        &poly,
        "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n5 1 3\n6 2 4\n0\n",
    )
    .unwrap();
    let out = dir.path().join("out.vtu");
    let o = run(&["mesh", poly.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    // Segments 5 and 6 are on lines 11 and 12; the error names the line of one of them.
    assert!(
        (err.contains("cross.poly:11: segment 5") || err.contains("cross.poly:12: segment 6"))
            && err.contains("crosses segment"),
        "{err}"
    );
    assert!(!out.exists());
    let seed = dir.path().join("seed.poly");
    std::fs::write(&seed, "# square with a region seed outside\n4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n4 0\n1 1 2\n2 2 3\n3 3 4\n4 4 1\n0\n1\n1 2.0 0.5 7 -1\n").unwrap();
    let o = run(&["mesh", seed.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("seed.poly:14: region 1's point (2, 0.5) is outside the domain"), "{err}");
    let o = run(&[
        "mesh",
        fixture("square_hole.poly").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--min-angle",
        "50",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("minimum angle 50"));
}

/// Triangle on a .poly with the given switches (`A` regional attributes, a bare `a`
/// the regional area bounds beside a global `a0.01`): count, smallest angle, mean quality.
const TRIANGLE_SCRIPT: &str = r#"
import sys, json, math
import numpy as np
import triangle

def read_poly(path):
    rows = [l.split('#')[0].split() for l in open(path)]
    rows = [r for r in rows if r]
    i = 0
    nv = int(rows[i][0]); i += 1
    verts = [[float(r[1]), float(r[2])] for r in rows[i:i + nv]]; i += nv
    ns = int(rows[i][0]); i += 1
    segs = [[int(r[1]), int(r[2])] for r in rows[i:i + ns]]
    marks = [int(r[3]) for r in rows[i:i + ns]]; i += ns
    nh = int(rows[i][0]); i += 1
    holes = [[float(r[1]), float(r[2])] for r in rows[i:i + nh]]; i += nh
    regions = []
    if i < len(rows):
        nr = int(rows[i][0]); i += 1
        regions = [[float(x) for x in r[1:5]] for r in rows[i:i + nr]]
    d = dict(vertices=np.array(verts), segments=np.array(segs), segment_markers=np.array(marks))
    if holes: d['holes'] = np.array(holes)
    if regions: d['regions'] = np.array(regions)
    return d

t = triangle.triangulate(read_poly(sys.argv[1]), sys.argv[2])
v, tri = t['vertices'], t['triangles']
def ang(a, b, c):
    u, w = b - a, c - a
    return math.degrees(math.atan2(abs(u[0]*w[1]-u[1]*w[0]), u @ w))
mins, qs = [], []
for a, b, c in tri:
    A, B, C = v[a], v[b], v[c]
    mins.append(min(ang(A, B, C), ang(B, C, A), ang(C, A, B)))
    area = 0.5 * ((B[0]-A[0])*(C[1]-A[1]) - (B[1]-A[1])*(C[0]-A[0]))
    s = ((A-B)**2).sum() + ((B-C)**2).sum() + ((C-A)**2).sum()
    qs.append(4 * math.sqrt(3) * abs(area) / s)
print(json.dumps(dict(triangles=len(tri), min_angle=min(mins), mean_quality=sum(qs)/len(qs))))
"#;

#[test]
fn compares_with_triangle() {
    let Some(py) = common::python_with(&["triangle", "numpy"]) else { return };
    for (name, switches, angle, area) in [
        ("square_hole.poly", "pq30Aa0.01a", 30.0, 0.01),
        ("naca0012.poly", "pq30a0.01", 30.0, 0.01),
        ("naca0012.poly", "pq20.7a0.001", 20.7, 0.001),
    ] {
        let theirs: serde_json::Value = serde_json::from_str(&common::run_python(
            &py,
            TRIANGLE_SCRIPT,
            &[fixture(name).to_str().unwrap(), switches],
        ))
        .unwrap();
        let input = read_fixture(name);
        let out = triangulate(
            &input,
            &MeshOptions { min_angle_deg: angle, max_area: Some(area), ..MeshOptions::default() },
        )
        .unwrap();
        let tris = triangles(&out);
        let ours = tris.len() as f64;
        let n = theirs["triangles"].as_f64().unwrap();
        let q: f64 = tris
            .iter()
            .map(|(t, _)| triangle_quality(xy(&out, t[0]), xy(&out, t[1]), xy(&out, t[2])))
            .sum::<f64>()
            / ours;
        let their_q = theirs["mean_quality"].as_f64().unwrap();
        eprintln!("{name} {switches}: smartmesh {ours} triangles, mean quality {q:.4}; Triangle {n} triangles, mean quality {their_q:.4}, min angle {:.2}", theirs["min_angle"]);
        assert!(
            ours / n > 0.5 && ours / n < 2.0,
            "{name}: {ours} triangles against Triangle's {n}"
        );
        assert!(
            (q - their_q).abs() < 0.05,
            "{name}: mean quality {q} against Triangle's {their_q}"
        );
        check_min_angle(&input, &out, angle);
    }
}

mod random_graphs {
    //! Random graphs on a small integer grid, where duplicates, crossings, collinear
    //! overlaps, segments through vertices and seeds on segments are common: the mesher
    //! never panics nor fails internally, and every mesh it returns passes the checks.
    use super::*;
    use proptest::prelude::*;

    fn graph() -> impl Strategy<Value = TaggedMesh> {
        (
            proptest::collection::vec((0i32..6, 0i32..6), 3..10),
            proptest::collection::vec((0usize..10, 0usize..10, 0i32..3), 0..10),
            proptest::collection::vec((0i32..10, 0i32..10), 0..2),
            proptest::collection::vec((0i32..10, 0i32..10, 0i32..3), 0..2),
            proptest::bool::weighted(0.7),
        )
            .prop_map(|(pts, segs, holes, regions, boxed)| {
                // Mostly distinct points and segments (so that most graphs mesh), with
                // the odd duplicate left in.
                let mut kept: Vec<(i32, i32)> = Vec::new();
                for (i, p) in pts.into_iter().enumerate() {
                    if i % 5 == 4 || !kept.contains(&p) {
                        kept.push(p);
                    }
                }
                let mut pts = kept;
                if pts.len() < 3 {
                    pts.extend([(0, 0), (5, 0), (0, 5)]);
                }
                let n = pts.len();
                let mut m = TaggedMesh::new();
                m.points = pts.iter().map(|&(x, y)| [x as f64, y as f64, 0.0]).collect();
                let b = m.block_mut(CellKind::Line);
                let mut seen = std::collections::BTreeSet::new();
                for (k, (a, c, t)) in segs.into_iter().enumerate() {
                    let (a, c) = (a % n, c % n);
                    if k % 7 == 6 || (a != c && seen.insert((a.min(c), a.max(c)))) {
                        b.push(&[a, c], t, t);
                    }
                }
                if boxed {
                    // A frame around the grid, so that most graphs enclose something.
                    let f = m.points.len();
                    m.points.extend([
                        [-1.0, -1.0, 0.0],
                        [6.0, -1.0, 0.0],
                        [6.0, 6.0, 0.0],
                        [-1.0, 6.0, 0.0],
                    ]);
                    let b = m.block_mut(CellKind::Line);
                    for k in 0..4 {
                        b.push(&[f + k, f + (k + 1) % 4], 9, 9);
                    }
                }
                m.holes =
                    holes.iter().map(|&(x, y)| [x as f64 * 0.5 + 0.25, y as f64 * 0.5]).collect();
                m.regions = regions
                    .iter()
                    .map(|&(x, y, a)| RegionSeed {
                        point: [x as f64 * 0.5, y as f64 * 0.5 + 0.25],
                        attribute: a as f64,
                        max_area: 0.5,
                    })
                    .collect();
                m
            })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]
        #[test]
        fn never_panics_and_meshes_are_sound(m in graph(), hull in any::<bool>(), angle in prop_oneof![Just(0.0), Just(20.7), Just(28.0)]) {
            let opts = MeshOptions { keep_convex_hull: hull, min_angle_deg: angle, max_area: Some(0.3), ..MeshOptions::default() };
            // About a quarter of these graphs mesh (checked when this test was written);
            // the rest are refused for crossings, duplicates or enclosing nothing.
            match triangulate(&m, &opts) {
                Ok(out) => {
                    check_orientation(&out);
                    check_constrained_delaunay(&out);
                    check_segment_coverage(&m, &out);
                    for (t, _) in triangles(&out) {
                        prop_assert!(area_of(&out, t) <= 0.3);
                    }
                }
                Err(e) => prop_assert!(e.is_input_error(), "{e}"),
            }
        }
    }
}

/// A size far below the domain's (`--size 0.0001` on square_hole.poly, about 10⁸
/// vertices) is refused before refining, with the estimate and the option to raise,
/// exit 2 and no output; the library says the same, fast, and a size the limit allows
/// still meshes.
#[test]
fn sizes_asking_for_too_many_vertices_are_refused_before_refining() {
    let started = std::time::Instant::now();
    let opts = MeshOptions { size: Some(1e-4), ..MeshOptions::default() };
    let e = triangulate(&read_fixture("square_hole.poly"), &opts).unwrap_err();
    assert!(matches!(e, MeshError::TooManyVertices { .. }) && e.is_input_error(), "{e:?}");
    assert!(e.to_string().contains("--max-vertices"), "{e}");
    // A limit raised above the estimate would let it through; one under the default
    // cannot lower the guard below it (it is the refinement's budget instead).
    let MeshError::TooManyVertices { estimate, limit } = e else { unreachable!() };
    assert!(estimate > 1e7 && estimate < 1e9 && limit == 5_000_000, "{estimate} {limit}");
    assert!(started.elapsed().as_secs_f64() < 5.0);

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fine.msh");
    let poly = fixture("square_hole.poly");
    let o = run(&["mesh", poly.to_str().unwrap(), "-o", out.to_str().unwrap(), "--size", "0.0001"]);
    assert_eq!(o.status.code(), Some(2), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("vertices") && err.contains("--max-vertices"), "{err}");
    assert!(!out.exists());
}

/// The estimate of the area bounds is close to what refinement makes.
#[test]
fn the_area_bound_estimate_is_close_to_the_mesh() {
    for h in [0.05, 0.02] {
        let opts = MeshOptions { size: Some(h), ..MeshOptions::default() };
        let m = triangulate(&read_fixture("square_hole.poly"), &opts).unwrap();
        let small = MeshOptions { max_vertices: Some(10), ..opts.clone() };
        // A budget of 10 under the estimate: refinement stops at it, and says so.
        let e = triangulate(&read_fixture("square_hole.poly"), &small).unwrap_err();
        assert!(matches!(e, MeshError::RefinementIncomplete { .. }), "{e:?}");
        let estimate =
            smartmesh::mesher::expected_vertices(&read_fixture("square_hole.poly"), &opts)
                .unwrap()
                .unwrap();
        let ratio = m.points.len() as f64 / estimate;
        eprintln!("h = {h}: estimate {estimate:.0}, made {} ({ratio:.3})", m.points.len());
        assert!(
            (0.7..1.4).contains(&ratio),
            "h = {h}: estimate {estimate:.0}, made {}",
            m.points.len()
        );
    }
}
