//! The topology of a mesh in space against brute-force twins: the patches of each surface
//! by a union-find over every pair of its cells, and the ridges by every pair of surface
//! cells sharing an edge with a dihedral angle measured apart (the angle between the two
//! half-planes the cells span from the edge, not their normals). Hard cases: a non-convex
//! L-shaped block, two sheets close together, a turn of 45° ± 1e-9, a cylinder (no ridge
//! on its smooth side, ridges at its rims), a coarse regular tetrahedron and the coarse
//! public sample meshes (quads, prisms, Medit `Ridges` and `Corners`).

use std::collections::{BTreeMap, BTreeSet};

use smartmesh::formats::{CellBlock, CellKind, TaggedMesh};
use smartmesh::recipe::EntityRef;
use smartmesh::{cell_tag, CurveOrigin, PointOrigin, Topology, TopologyOptions};
use smartmesh_test_support::formats::{public_fixture, python_with, run_python};

type P = [f64; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: P, b: P) -> P {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// The surface cells of `mesh` by their corners, with their tags, read from the blocks.
fn surface_cells(mesh: &TaggedMesh) -> Vec<(Vec<usize>, i32)> {
    mesh.cells()
        .filter(|c| c.0.dim() == 2)
        .map(|(k, nodes, p, g)| {
            let n = k.linear().nodes_per_cell();
            (nodes[..n].iter().map(|&v| v as usize).collect(), cell_tag(p, g))
        })
        .collect()
}

/// Whether cell `c` has the edge `{a, b}` as one of its sides.
fn has_side(c: &[usize], a: usize, b: usize) -> bool {
    (0..c.len()).any(|i| {
        let (x, y) = (c[i], c[(i + 1) % c.len()]);
        (x, y) == (a, b) || (x, y) == (b, a)
    })
}

/// The turn of the normals across edge `{a, b}` shared by cells `c` and `d`, in degrees:
/// 180° less the angle between the half-planes each cell spans from the edge (from the
/// first of its corners off the edge, taken perpendicular to the edge).
fn turn_deg(pts: &[P], a: usize, b: usize, c: &[usize], d: &[usize]) -> f64 {
    let e = sub(pts[b], pts[a]);
    let half = |cell: &[usize]| {
        let o = *cell.iter().find(|&&v| v != a && v != b).unwrap();
        let w = sub(pts[o], pts[a]);
        let t = dot(w, e) / dot(e, e);
        sub(w, [e[0] * t, e[1] * t, e[2] * t])
    };
    let (u, v) = (half(c), half(d));
    let x = cross(u, v);
    let between = dot(x, x).sqrt().atan2(dot(u, v)).to_degrees();
    180.0 - between
}

/// The twin of the ridges: every pair of surface cells sharing a side, every cell with
/// that side (counted over all cells) of one tag, no line cell on it, and a turn above
/// `angle` or more than two such cells (a non-manifold edge).
fn twin_ridges(mesh: &TaggedMesh, angle: f64) -> BTreeSet<[usize; 2]> {
    let cells = surface_cells(mesh);
    let lines: BTreeSet<[usize; 2]> = mesh
        .cells()
        .filter(|c| c.0.dim() == 1)
        .map(|(_, n, ..)| {
            let (a, b) = (n[0] as usize, n[1] as usize);
            [a.min(b), a.max(b)]
        })
        .collect();
    let mut out = BTreeSet::new();
    for i in 0..cells.len() {
        for j in i + 1..cells.len() {
            let (c, d) = (&cells[i].0, &cells[j].0);
            for k in 0..c.len() {
                let (a, b) = (c[k], c[(k + 1) % c.len()]);
                if !has_side(d, a, b) || cells[i].1 != cells[j].1 {
                    continue;
                }
                let key = [a.min(b), a.max(b)];
                let sharing: Vec<i32> =
                    cells.iter().filter(|x| has_side(&x.0, a, b)).map(|x| x.1).collect();
                let one_tag = sharing.iter().all(|&t| t == cells[i].1);
                let turns = sharing.len() > 2 || turn_deg(&mesh.points, a, b, c, d) > angle;
                if one_tag && turns && !lines.contains(&key) {
                    out.insert(key);
                }
            }
        }
    }
    out
}

/// The twin of the patches: per tag, a union-find over every pair of its cells that
/// share a side.
fn twin_patches(mesh: &TaggedMesh) -> BTreeMap<i32, usize> {
    let cells = surface_cells(mesh);
    let mut parent: Vec<usize> = (0..cells.len()).collect();
    fn root(p: &mut [usize], x: usize) -> usize {
        if p[x] == x {
            x
        } else {
            let r = root(p, p[x]);
            p[x] = r;
            r
        }
    }
    for i in 0..cells.len() {
        for j in i + 1..cells.len() {
            let c = &cells[i].0;
            let shares = (0..c.len()).any(|k| has_side(&cells[j].0, c[k], c[(k + 1) % c.len()]));
            if shares && cells[i].1 == cells[j].1 {
                let (a, b) = (root(&mut parent, i), root(&mut parent, j));
                parent[a] = b;
            }
        }
    }
    let mut out = BTreeMap::new();
    for (i, cell) in cells.iter().enumerate() {
        if root(&mut parent, i) == i {
            *out.entry(cell.1).or_insert(0) += 1;
        }
    }
    out
}

/// The ridge edges the topology found, by key.
fn ridges(topo: &Topology) -> BTreeSet<[usize; 2]> {
    topo.curves
        .iter()
        .filter(|c| c.origin == CurveOrigin::Ridge)
        .flat_map(|c| &c.polylines)
        .flat_map(|p| p.edges())
        .map(|[a, b]| [a.min(b), a.max(b)])
        .collect()
}

/// The topology's patches per surface tag.
fn patches(topo: &Topology) -> BTreeMap<i32, usize> {
    let space = topo.space.as_ref().expect("a mesh in space");
    topo.faces.iter().zip(&space.surfaces).map(|(f, s)| (f.tag, s.patches)).collect()
}

/// Both twins on `mesh` at `angle`; returns the topology.
fn agrees_with_twins(mesh: &TaggedMesh, angle: f64, what: &str) -> Topology {
    let topo = Topology::from_mesh_with(mesh, &TopologyOptions { ridge_angle_deg: angle });
    assert_eq!(ridges(&topo), twin_ridges(mesh, angle), "{what}: ridges at {angle}°");
    assert_eq!(patches(&topo), twin_patches(mesh), "{what}: patches");
    topo
}

/// Two triangles sharing the edge (0,0,0)–(1,0,0), consistently oriented, the second
/// turned about the edge by `turn` degrees from the first's plane; tag 5 for both.
fn hinge(turn: f64) -> TaggedMesh {
    let t = turn.to_radians();
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, -1.0, 0.0], [0.5, t.cos(), t.sin()]];
    let b = m.block_mut(CellKind::Triangle);
    b.push(&[0, 1, 2], 5, 5);
    b.push(&[1, 0, 3], 5, 5);
    m
}

/// At 45° ± 1e-9: above the ridge angle is a ridge, below is not (and at the angle none,
/// as in MMG); the twin agrees on each side, and on the mirror (the second triangle
/// listed against the first's orientation).
#[test]
fn a_turn_just_above_the_ridge_angle_is_a_ridge_and_just_below_is_not() {
    for (turn, ridge) in [(45.0 + 1e-9, true), (45.0 - 1e-9, false), (90.0, true), (10.0, false)] {
        let mut m = hinge(turn);
        let topo = agrees_with_twins(&m, 45.0, &format!("hinge {turn}"));
        assert_eq!(ridges(&topo).len(), usize::from(ridge), "turn {turn}");
        // The second triangle reversed: the normals are flipped back before comparing.
        m.blocks[0].nodes[3..6].copy_from_slice(&[0, 1, 3]);
        let topo = agrees_with_twins(&m, 45.0, &format!("hinge {turn} reversed"));
        assert_eq!(ridges(&topo).len(), usize::from(ridge), "turn {turn}, reversed");
    }
    // The option moves the threshold: 60° leaves a 50° turn alone.
    let m = hinge(50.0);
    assert_eq!(ridges(&agrees_with_twins(&m, 60.0, "hinge 50")).len(), 0);
    assert_eq!(ridges(&agrees_with_twins(&m, 40.0, "hinge 50")).len(), 1);
    // The ridge's two ends meet the free boundary: two topological points.
    let topo = Topology::from_mesh(&hinge(90.0));
    let points: Vec<usize> = topo.points.iter().map(|p| p.vertex).collect();
    assert_eq!(points, [0, 1]);
}

/// A regular tetrahedron's skin, one tag: every edge turns by 180° − 70.53°, six ridges
/// meeting three at each corner: four points, one ridge curve in six pieces, one patch,
/// no boundary.
#[test]
fn a_coarse_tetrahedron_has_six_ridges_and_four_corners() {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points = vec![[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]];
    let b = m.block_mut(CellKind::Triangle);
    for t in [[0u32, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]] {
        b.push(&t, 1, 1);
    }
    let topo = agrees_with_twins(&m, 45.0, "tetrahedron");
    assert_eq!(ridges(&topo).len(), 6);
    assert_eq!(topo.points.len(), 4);
    assert!(topo.points.iter().all(|p| p.origin == PointOrigin::Junction));
    assert_eq!(topo.curves.len(), 1);
    assert_eq!(topo.curves[0].polylines.len(), 6);
    let s = &topo.space.as_ref().unwrap().surfaces[0];
    assert_eq!((s.patches, s.boundary.len()), (1, 0));
    // Above the turn (109.47°) nothing is a ridge, and the surface has no curve at all.
    let flat = agrees_with_twins(&m, 110.0, "tetrahedron at 110°");
    assert!(flat.curves.is_empty() && flat.points.is_empty());
}

/// Two parallel unit squares 1e-3 apart, each a grid of triangles, under one tag: one
/// surface of two patches, each bounded by one closed loop of its 4n edges; nothing
/// joins them (no shared vertex), and no ridge (both flat).
#[test]
fn two_close_sheets_are_two_patches_of_one_surface() {
    let n = 6;
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    for z in [0.0, 1e-3] {
        for j in 0..=n {
            for i in 0..=n {
                m.points.push([i as f64 / n as f64, j as f64 / n as f64, z]);
            }
        }
    }
    let at = |s: usize, i: usize, j: usize| (s * (n + 1) * (n + 1) + j * (n + 1) + i) as u32;
    let b = m.block_mut(CellKind::Triangle);
    for s in 0..2 {
        for j in 0..n {
            for i in 0..n {
                b.push(&[at(s, i, j), at(s, i + 1, j), at(s, i + 1, j + 1)], 7, 7);
                b.push(&[at(s, i, j), at(s, i + 1, j + 1), at(s, i, j + 1)], 7, 7);
            }
        }
    }
    let topo = agrees_with_twins(&m, 45.0, "two sheets");
    let s = &topo.space.as_ref().unwrap().surfaces[0];
    assert_eq!(s.patches, 2);
    assert_eq!(s.boundary.len(), 2);
    assert!(s.boundary.iter().all(|l| l.closed && l.num_edges() == 4 * n));
    assert!(ridges(&topo).is_empty());
    // The same squares at one z are a planar mesh: no 3D topology at all.
    let mut flat = m.clone();
    for p in &mut flat.points {
        p[2] = 0.0;
    }
    assert!(Topology::from_mesh(&flat).space.is_none());
}

/// A mesh made by Gmsh's Python API (`script` writes `sys.argv[1]`), read back.
fn gmsh_mesh(script: &str) -> Option<TaggedMesh> {
    let py = python_with(&["gmsh"])?;
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("m.msh");
    run_python(&py, script, &[path.to_str().unwrap()]);
    Some(smartmesh::read_path(&path, None).unwrap())
}

/// An L-shaped block (a unit cube less a quarter, so with a re-entrant edge) meshed with
/// tetrahedra, its whole skin one physical surface: the 18 edges of the L-prism are
/// ridges (the re-entrant one turns by 90° too), meeting three at each of its 12
/// corners; one patch, no boundary; the volume is bounded by that surface alone.
#[test]
fn an_l_shaped_block_has_its_18_edges_as_ridges() {
    let Some(m) = gmsh_mesh(
        r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
a = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
b = gmsh.model.occ.addBox(0.5, 0.5, 0, 1, 1, 1)
gmsh.model.occ.cut([(3, a)], [(3, b)])
gmsh.model.occ.synchronize()
gmsh.model.addPhysicalGroup(2, [s for _, s in gmsh.model.getEntities(2)], 1, "Skin")
gmsh.model.addPhysicalGroup(3, [v for _, v in gmsh.model.getEntities(3)], 2, "Block")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.2)
gmsh.model.mesh.generate(3)
gmsh.write(sys.argv[1])
"#,
    ) else {
        return;
    };
    let topo = agrees_with_twins(&m, 45.0, "L-block");
    let corners: BTreeSet<[i64; 3]> =
        topo.points.iter().map(|p| m.points[p.vertex].map(|x| (x * 2.0).round() as i64)).collect();
    assert_eq!(topo.points.len(), 12, "{corners:?}");
    assert_eq!(corners.len(), 12);
    let ridge = topo.curves.iter().find(|c| c.origin == CurveOrigin::Ridge).unwrap();
    assert_eq!(ridge.polylines.len(), 18);
    let length: f64 = ridge
        .polylines
        .iter()
        .flat_map(|p| p.edges())
        .map(|[a, b]| dot(sub(m.points[a], m.points[b]), sub(m.points[a], m.points[b])).sqrt())
        .sum();
    // Perimeter of the L (two of 1, four of 0.5) twice, and six vertical unit edges.
    assert!((length - (2.0 * 4.0 + 6.0)).abs() < 1e-9, "{length}");
    let space = topo.space.as_ref().unwrap();
    assert_eq!((space.surfaces[0].patches, space.surfaces[0].boundary.len()), (1, 0));
    assert_eq!(space.volumes.len(), 1);
    assert_eq!(space.volumes[0].bounded_by.iter().map(|b| b.0).collect::<Vec<_>>(), [0]);
    assert_eq!(space.volumes[0].untagged_faces, 0);
    // One lookup: the names of the surface and of the volume.
    let hits = topo.resolve(&EntityRef::Name("Block".into()));
    assert_eq!((hits[2].len(), hits[3].clone()), (0, vec![0]));
    assert_eq!(topo.resolve(&EntityRef::Tag(1))[2], [0]);
}

/// A cylinder (radius 0.5, height 1, about 31 segments around: 11.6° between facets)
/// meshed on its surface, one tag: no ridge along its smooth side nor its seam, and the
/// two rims (90°) are ridges, each a closed loop of rim edges with no point on it.
#[test]
fn a_cylinder_has_ridges_at_its_rims_only() {
    let Some(m) = gmsh_mesh(
        r#"
import sys, gmsh
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, 1, 0.5)
gmsh.model.occ.synchronize()
gmsh.model.addPhysicalGroup(2, [s for _, s in gmsh.model.getEntities(2)], 3, "Can")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.1)
gmsh.model.mesh.generate(2)
gmsh.write(sys.argv[1])
"#,
    ) else {
        return;
    };
    let topo = agrees_with_twins(&m, 45.0, "cylinder");
    let r = ridges(&topo);
    let on_rim = |v: usize| {
        let p = m.points[v];
        ((p[0] * p[0] + p[1] * p[1]).sqrt() - 0.5).abs() < 1e-9
            && (p[2].abs() < 1e-9 || (p[2] - 1.0).abs() < 1e-9)
    };
    assert!(r.iter().all(|e| on_rim(e[0]) && on_rim(e[1])), "a ridge off the rims");
    let rim_edges = topo
        .edges
        .iter()
        .filter(|(e, _)| {
            // Rim vertices about 0.1 apart: a longer edge is a chord across a cap.
            let d = sub(m.points[e[0]], m.points[e[1]]);
            on_rim(e[0]) && on_rim(e[1]) && d[2] == 0.0 && dot(d, d) < 0.15 * 0.15
        })
        .count();
    assert_eq!(r.len(), rim_edges);
    assert!(rim_edges > 50, "{rim_edges}");
    let ridge = topo.curves.iter().find(|c| c.origin == CurveOrigin::Ridge).unwrap();
    assert_eq!(ridge.polylines.len(), 2);
    assert!(ridge.polylines.iter().all(|p| p.closed));
    assert!(topo.points.is_empty());
}

/// The coarse public meshes: box_cyl (its 16-segment cylinder turns by up to 47.2°
/// across 21 edges; its Walls' box edges are ridges), hex_prism_pyr (quads and
/// triangles, three volumes, two patches of Top), the Medit surface and MMG's output
/// (every edge of its `Ridges` is a line cell, its `Corners` and `RequiredVertices` are
/// points).
#[test]
fn the_public_3d_meshes_agree_with_the_twins() {
    smartmesh_test_support::require_public_fixtures!();
    for rel in [
        "3d/box_cyl.v41_ascii.msh",
        "3d/hex_prism_pyr.v41_ascii.msh",
        "3d/box_cyl_surf_input.mesh",
        "3d/box_cyl_mmg.mesh",
    ] {
        let m = smartmesh::read_path(&public_fixture(rel), None).unwrap();
        // The twins are quadratic: the larger MMG mesh at the default angle only.
        let angles: &[f64] = if rel.contains("mmg") { &[45.0] } else { &[30.0, 45.0, 60.0] };
        for &angle in angles {
            agrees_with_twins(&m, angle, rel);
        }
    }
    let m = smartmesh::read_path(&public_fixture("3d/box_cyl.v41_ascii.msh"), None).unwrap();
    let topo = Topology::from_mesh(&m);
    let walls = topo.faces.iter().position(|f| f.tag == 3).unwrap();
    let cylinder = topo.faces.iter().position(|f| f.tag == 4).unwrap();
    let r = ridges(&topo);
    assert_eq!(r.len(), 48 + 21);
    let space = topo.space.as_ref().unwrap();
    // Walls: bounded by the inlet and outlet squares and the two circles.
    assert_eq!(space.surfaces[walls].boundary.len(), 4);
    assert_eq!(space.surfaces[cylinder].boundary.len(), 2);
    assert!(space.surfaces.iter().all(|s| s.patches == 1));

    let m = smartmesh::read_path(&public_fixture("3d/hex_prism_pyr.v41_ascii.msh"), None).unwrap();
    let topo = Topology::from_mesh(&m);
    let top = topo.faces.iter().position(|f| f.tag == 12).unwrap();
    assert_eq!(topo.space.as_ref().unwrap().surfaces[top].patches, 2);

    let m = smartmesh::read_path(&public_fixture("3d/box_cyl_mmg.mesh"), None).unwrap();
    let topo = Topology::from_mesh(&m);
    let space = topo.space.as_ref().unwrap();
    assert_eq!(space.file_ridge_edges, 205);
    assert!(ridges(&topo).is_empty(), "MMG lists every ridge it keeps");
    let listed: BTreeSet<usize> =
        ["Corners", "RequiredVertices"].iter().flat_map(|s| m.point_sets[*s].clone()).collect();
    let corners: BTreeSet<usize> =
        topo.points.iter().filter(|p| p.origin == PointOrigin::Corner).map(|p| p.vertex).collect();
    assert_eq!(corners, listed);
    assert_eq!(corners.len(), 33);
}

/// A 2D mesh (one plane) has no 3D topology: the ridge angle changes nothing.
#[test]
fn a_planar_mesh_is_untouched_by_the_ridge_angle() {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut t = CellBlock::new(CellKind::Triangle);
    t.push(&[0, 1, 2], 1, 1);
    // Inverted: in space it would turn by 180°.
    t.push(&[0, 3, 2], 1, 1);
    m.blocks.push(t);
    let a = Topology::from_mesh(&m);
    let b = Topology::from_mesh_with(&m, &TopologyOptions { ridge_angle_deg: 1.0 });
    assert_eq!(a, b);
    assert!(a.space.is_none());
    assert!(a.curves.iter().all(|c| c.origin != CurveOrigin::Ridge));
}

/// One lookup for every dimension on a hand-built 3D mesh: two tetrahedra sharing a face
/// (volumes 10 "Left" and 11 "Right"), their outer faces tagged 1 "Skin" and the shared
/// one 2 "Middle", a vertex cell tagged 1: each reference's hits equal a scan of every
/// entity's tag and name, and each volume is bounded by the skin (3 faces) and the middle.
#[test]
fn resolve_finds_surfaces_and_volumes_as_a_scan_does() {
    let mut m = TaggedMesh::new();
    m.coordinate_dim = 3;
    m.points =
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
    let t = m.block_mut(CellKind::Tetra);
    t.push(&[0, 1, 2, 3], 10, 10);
    t.push(&[1, 2, 3, 4], 11, 11);
    let tri = m.block_mut(CellKind::Triangle);
    for f in [[0u32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 4], [2, 3, 4], [3, 1, 4]] {
        tri.push(&f, 1, 1);
    }
    tri.push(&[1, 2, 3], 2, 2);
    m.block_mut(CellKind::Vertex).push(&[0], 1, 1);
    for (dim, tag, name) in
        [(3, 10, "Left"), (3, 11, "Right"), (2, 1, "Skin"), (2, 2, "Middle"), (0, 1, "Origin")]
    {
        m.tag_names.insert((dim, tag), name.to_string());
    }
    let topo = Topology::from_mesh(&m);
    let space = topo.space.as_ref().unwrap();
    type Volume = (i32, usize, usize, Vec<(usize, usize)>);
    let volumes: Vec<Volume> =
        space.volumes.iter().map(|v| (v.tag, v.cells, v.vertices, v.bounded_by.clone())).collect();
    assert_eq!(volumes, [(10, 1, 4, vec![(0, 3), (1, 1)]), (11, 1, 4, vec![(0, 3), (1, 1)])]);
    let scan = |e: &EntityRef| -> [Vec<usize>; 4] {
        let hit = |tag: Option<i32>, name: Option<&String>| match e {
            EntityRef::Tag(t) => tag == Some(*t),
            EntityRef::Name(n) => name == Some(n),
        };
        let pick = |v: Vec<(Option<i32>, Option<&String>)>| -> Vec<usize> {
            v.into_iter().enumerate().filter(|(_, (t, n))| hit(*t, *n)).map(|(i, _)| i).collect()
        };
        [
            pick(topo.points.iter().map(|p| (p.tag, p.name.as_ref())).collect()),
            pick(topo.curves.iter().map(|c| (c.tag, c.name.as_ref())).collect()),
            pick(topo.faces.iter().map(|f| (Some(f.tag), f.name.as_ref())).collect()),
            pick(space.volumes.iter().map(|v| (Some(v.tag), v.name.as_ref())).collect()),
        ]
    };
    for e in [
        EntityRef::Tag(1),
        EntityRef::Tag(2),
        EntityRef::Tag(10),
        EntityRef::Tag(11),
        EntityRef::Tag(12),
        EntityRef::Name("Left".into()),
        EntityRef::Name("Skin".into()),
        EntityRef::Name("Origin".into()),
        EntityRef::Name("nothing".into()),
    ] {
        assert_eq!(topo.resolve(&e).0, scan(&e), "{e:?}");
    }
    assert_eq!(topo.resolve(&EntityRef::Name("Right".into()))[3], [1]);
    assert_eq!(topo.resolve(&EntityRef::Tag(1))[0], [0]);
}
