//! The geometric model recovered from the tags of a mesh: topological points, curves
//! and faces, and the classification of every mesh vertex, edge and surface cell on
//! one of them (thesis 2.2.1, 4.3.2).
//!
//! Files tag cells, not geometry. A topological face is the set of surface cells
//! (triangles, quads) sharing a tag; a topological curve the set of mesh edges of line
//! cells sharing a tag. Where a file lists no line cell for part of the boundary, or
//! for the interface between two faces, those mesh edges form *derived* curves (tag
//! `None`), so that every boundary edge lies on some curve. Topological points are the
//! vertex cells a file lists, plus the points no file needs to list: the end points
//! of open curve pieces and the junctions where curves meet.
//!
//! An entity is named by a tag or a tag name ([`EntityRef`]); [`Topology::resolve`] is
//! the one lookup that finds it (in `resolve.rs`).
//!
//! A mesh in space (volume cells, or surface cells off one plane z = const) gets more
//! (`space.rs`, `volumes.rs`; [`Topology::space`]): the faces are its surfaces, each with
//! its patches and boundary loops; ridges inside a surface found by the dihedral angle
//! join the derived curves ([`CurveOrigin::Ridge`]); the vertices a Medit file lists as
//! `Corners` or `RequiredVertices` are points ([`PointOrigin::Corner`]); and the volumes
//! with the surfaces bounding each. A planar mesh gets none of it (`space` is `None`):
//! its topology is the 2D one.
//!
//! The module knows only connectivity and coordinates; it never reads a metric.
//! Cost: O(cells): the surface edges by a counting sort on their smaller vertex.

use std::collections::BTreeMap;

// A fast hasher for the maps of curve edges and points (SipHash's resistance to chosen
// keys buys nothing here). Every iteration over them is sorted before use, so the
// output does not depend on the hash order. The surface edges, millions on a large
// mesh, are no map at all: see `surface_edges`.
use ahash::AHashMap as HashMap;

use smartmesh_formats::{CellKind, TaggedMesh};

mod resolve;
mod space;
mod volumes;

pub use resolve::{EntityHits, EntityRef};
pub use space::{SpaceTopology, SurfaceShape, TopologyOptions, DEFAULT_RIDGE_ANGLE_DEG};
pub use volumes::TopoVolume;

/// What a topological entity is known by: a tag from the file, or nothing when it was
/// derived from the mesh (boundary or interface edges that no line cell covers).
pub type EntityTag = Option<i32>;

/// A topological face: the surface cells sharing one tag.
#[derive(Debug, Clone, PartialEq)]
pub struct TopoFace {
    /// The tag (physical, or geometrical when the cell has no physical tag).
    pub tag: i32,
    /// The tag's name, when the file names it.
    pub name: Option<String>,
    /// Indices of its cells in [`Topology::surface_cells`].
    pub cells: Vec<usize>,
}

/// An ordered run of mesh vertices along a curve.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Polyline {
    /// Mesh vertex indices in order. For a closed polyline the first vertex is not
    /// repeated at the end.
    pub vertices: Vec<usize>,
    /// Whether the last vertex connects back to the first.
    pub closed: bool,
}

impl Polyline {
    /// Number of mesh edges along the polyline.
    pub fn num_edges(&self) -> usize {
        if self.closed {
            self.vertices.len()
        } else {
            self.vertices.len().saturating_sub(1)
        }
    }

    /// Iterator over consecutive vertex pairs (including the closing pair).
    pub fn edges(&self) -> impl Iterator<Item = [usize; 2]> + '_ {
        let n = self.vertices.len();
        (0..self.num_edges()).map(move |i| [self.vertices[i], self.vertices[(i + 1) % n]])
    }
}

/// A topological curve: mesh edges sharing a tag, as ordered polylines.
#[derive(Debug, Clone, PartialEq)]
pub struct TopoCurve {
    /// The tag, `None` for a derived curve.
    pub tag: EntityTag,
    /// The tag's name, when the file names it.
    pub name: Option<String>,
    /// Its edges as ordered polylines, split at topological points. Boundary pieces are
    /// oriented with the domain on their left (the direction the adjacent cell runs
    /// along the edge).
    pub polylines: Vec<Polyline>,
    /// Whether every edge of the curve bounds exactly one surface cell.
    pub on_boundary: bool,
    /// Where it comes from: line cells, boundary or interface edges, or ridges.
    pub origin: CurveOrigin,
}

/// Where a topological curve comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CurveOrigin {
    /// Line cells of the file sharing its tag.
    Tagged,
    /// Boundary edges, or edges where two faces meet, that no line cell covers.
    Derived,
    /// Edges inside one surface of a mesh in space across which the cells' normals turn
    /// by more than the ridge angle (or that three cells of it share).
    Ridge,
}

/// A topological point.
#[derive(Debug, Clone, PartialEq)]
pub struct TopoPoint {
    /// The tag of the vertex cell that lists it, `None` when it was recovered.
    pub tag: EntityTag,
    /// The tag's name, when the file names it.
    pub name: Option<String>,
    /// The mesh vertex.
    pub vertex: usize,
    /// Why it is a topological point.
    pub origin: PointOrigin,
}

/// Why a mesh vertex is a topological point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PointOrigin {
    /// A vertex cell of the file lists it.
    Listed,
    /// The end of an open curve piece.
    CurveEnd,
    /// Where curves meet, or where a curve meets itself more than twice.
    Junction,
    /// A corner or required vertex a Medit file lists (`Corners`, `RequiredVertices`), in
    /// a mesh in space.
    Corner,
}

/// The topological entity a mesh vertex lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Classification {
    /// On topological point `i` of [`Topology::points`].
    Point(usize),
    /// Inside topological curve `i` of [`Topology::curves`].
    Curve(usize),
    /// Inside topological face `i` of [`Topology::faces`].
    Face(usize),
    /// Used by no surface cell, line or vertex cell (a node Gmsh keeps, such as a
    /// circle's centre).
    Unused,
}

/// A surface cell (triangle or quad; second-order cells by their corners).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SurfaceCell {
    /// Corner vertices; `corners[3] == usize::MAX` for a triangle.
    pub corners: [usize; 4],
    /// Index of its topological face.
    pub face: usize,
}

impl SurfaceCell {
    /// Number of corners, 3 or 4.
    pub fn len(&self) -> usize {
        if self.corners[3] == usize::MAX {
            3
        } else {
            4
        }
    }

    /// Always false: a cell has corners.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The corners as a slice.
    pub fn vertices(&self) -> &[usize] {
        &self.corners[..self.len()]
    }
}

/// The geometric model of a tagged mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Topology {
    /// Topological points, listed ones first (in file order), then recovered ones by
    /// vertex index.
    pub points: Vec<TopoPoint>,
    /// Topological curves: tagged ones by tag, then derived ones.
    pub curves: Vec<TopoCurve>,
    /// Topological faces, by tag.
    pub faces: Vec<TopoFace>,
    /// Every surface cell of the mesh, in file order.
    pub surface_cells: Vec<SurfaceCell>,
    /// The entity each mesh vertex is classified on.
    pub vertex_class: Vec<Classification>,
    /// Every mesh edge `[a, b]` with `a < b`, sorted, and the entity it is classified
    /// on (a curve, or the face of its cells).
    pub edges: Vec<([usize; 2], Classification)>,
    /// For a mesh in space: the ridge angle, each surface's shape and the volumes;
    /// `None` for a planar mesh.
    pub space: Option<SpaceTopology>,
}

/// The tag of a cell as the topology (and so every recipe) knows it: its physical tag, or
/// its geometrical (elementary) tag when it has no physical one (0).
pub fn cell_tag(physical: i32, geometrical: i32) -> i32 {
    if physical != 0 {
        physical
    } else {
        geometrical
    }
}

fn corner_count(kind: CellKind) -> usize {
    kind.linear().nodes_per_cell()
}

#[inline]
fn key(a: usize, b: usize) -> [usize; 2] {
    if a < b {
        [a, b]
    } else {
        [b, a]
    }
}

/// What the surface cells say of one mesh edge.
struct EdgeInfo {
    /// Cells that have it.
    count: u32,
    /// Its direction in the first of them.
    forward: [usize; 2],
    /// The faces of the first two of them (the first twice when only one has it).
    faces: [usize; 2],
}

/// The mesh edges of `cells` (on `n` vertices), sorted by key (smaller vertex first),
/// with what the cells say of each; occurrences count in cell order. Why not a hash map:
/// on a mesh of millions of cells each insertion is a cache miss in a table of over
/// 100 MB, where a counting sort by smaller vertex, then a sort of each vertex's few
/// edges, reads and writes memory in order.
fn surface_edges(cells: &[SurfaceCell], n: usize) -> Vec<([usize; 2], EdgeInfo)> {
    let mut start = vec![0usize; n + 1];
    for sc in cells {
        let vs = sc.vertices();
        for i in 0..vs.len() {
            start[vs[i].min(vs[(i + 1) % vs.len()]) + 1] += 1;
        }
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    // (larger vertex, whether it is the edge's end, face), by smaller vertex, in cell order.
    let mut by_lo: Vec<(u32, bool, u32)> = vec![(0, false, 0); start[n]];
    let mut fill = start.clone();
    for sc in cells {
        let vs = sc.vertices();
        for i in 0..vs.len() {
            let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
            let lo = a.min(b);
            by_lo[fill[lo]] = (a.max(b) as u32, a < b, sc.face as u32);
            fill[lo] += 1;
        }
    }
    let mut out = Vec::with_capacity(by_lo.len() / 2 + 1);
    for lo in 0..n {
        let run = &mut by_lo[start[lo]..start[lo + 1]];
        // Stable: equal edges stay in cell order.
        run.sort_by_key(|e| e.0);
        let mut i = 0;
        while i < run.len() {
            let hi = run[i].0 as usize;
            let mut j = i + 1;
            while j < run.len() && run[j].0 as usize == hi {
                j += 1;
            }
            let (first, second) = (run[i], run[if j - i >= 2 { i + 1 } else { i }]);
            let forward = if first.1 { [lo, hi] } else { [hi, lo] };
            out.push((
                [lo, hi],
                EdgeInfo {
                    count: (j - i) as u32,
                    forward,
                    faces: [first.2 as usize, second.2 as usize],
                },
            ));
            i = j;
        }
    }
    out
}

impl Topology {
    /// Recovers the topology of `mesh` from its tags, with the default options.
    pub fn from_mesh(mesh: &TaggedMesh) -> Topology {
        Topology::from_mesh_with(mesh, &TopologyOptions::default())
    }

    /// Recovers the topology of `mesh` from its tags (`options`: the ridge angle of a
    /// mesh in space).
    pub fn from_mesh_with(mesh: &TaggedMesh, options: &TopologyOptions) -> Topology {
        let n = mesh.points.len();
        let in_space = space::in_space(mesh);

        // Faces and surface cells.
        let mut face_index: BTreeMap<i32, usize> = BTreeMap::new();
        let mut raw_cells: Vec<([usize; 4], i32)> = Vec::new();
        for (kind, nodes, p, g) in mesh.cells() {
            if kind.dim() == 2 {
                let k = corner_count(kind);
                let mut c = [usize::MAX; 4];
                for (slot, &v) in c[..k].iter_mut().zip(&nodes[..k]) {
                    *slot = v as usize;
                }
                let t = cell_tag(p, g);
                face_index.entry(t).or_insert(0);
                raw_cells.push((c, t));
            }
        }
        let mut faces: Vec<TopoFace> = face_index
            .keys()
            .map(|&t| TopoFace {
                tag: t,
                name: mesh.tag_name(2, t).map(str::to_owned),
                cells: Vec::new(),
            })
            .collect();
        for (i, v) in face_index.values_mut().enumerate() {
            *v = i;
        }
        let mut surface_cells = Vec::with_capacity(raw_cells.len());
        for (i, (c, t)) in raw_cells.into_iter().enumerate() {
            let f = face_index[&t];
            faces[f].cells.push(i);
            surface_cells.push(SurfaceCell { corners: c, face: f });
        }

        // Mesh edges of surface cells: the directed occurrence tells the boundary
        // orientation, the set of faces tells interfaces.
        let edge_list = surface_edges(&surface_cells, n);
        let edge_info = |k: &[usize; 2]| {
            edge_list.binary_search_by(|e| e.0.cmp(k)).ok().map(|i| &edge_list[i].1)
        };

        // Curves from line cells, by tag.
        let mut curve_edges: BTreeMap<i32, Vec<[usize; 2]>> = BTreeMap::new();
        let mut on_curve: HashMap<[usize; 2], ()> = HashMap::new();
        for (kind, nodes, p, g) in mesh.cells() {
            if kind.dim() == 1 && nodes[0] != nodes[1] {
                let (a, b) = (nodes[0] as usize, nodes[1] as usize);
                let k = key(a, b);
                curve_edges.entry(cell_tag(p, g)).or_default().push([a, b]);
                on_curve.insert(k, ());
            }
        }
        // Derived curves: boundary edges and face interfaces no line cell covers,
        // grouped by the face pair they separate.
        let mut derived: BTreeMap<(usize, usize), Vec<[usize; 2]>> = BTreeMap::new();
        for (k, e) in &edge_list {
            let boundary = e.count == 1;
            let interface = e.count >= 2 && e.faces[0] != e.faces[1];
            if (boundary || interface) && !on_curve.contains_key(k) {
                let pair = if boundary {
                    (e.faces[0], usize::MAX)
                } else {
                    (e.faces[0].min(e.faces[1]), e.faces[0].max(e.faces[1]))
                };
                derived.entry(pair).or_default().push(e.forward);
            }
        }

        // In space, ridges inside each surface (one curve per surface), and the edges
        // where three surfaces or more meet that the first two cells do not tell.
        let cell_edges = if in_space { space::cell_edges(&surface_cells) } else { Vec::new() };
        let found = if in_space {
            let cos_limit = options.ridge_angle_deg.to_radians().cos();
            let covered = |k: &[usize; 2]| on_curve.contains_key(k);
            space::ridges(&mesh.points, &surface_cells, &cell_edges, covered, cos_limit)
        } else {
            space::Found::default()
        };
        for (pair, e) in found.junctions {
            derived.entry(pair).or_default().push(e);
        }
        let mut curve_list: Vec<(EntityTag, CurveOrigin, Vec<[usize; 2]>)> =
            curve_edges.into_iter().map(|(t, e)| (Some(t), CurveOrigin::Tagged, e)).collect();
        curve_list.extend(derived.into_values().map(|e| (None, CurveOrigin::Derived, e)));
        curve_list.extend(found.ridges.into_values().map(|e| (None, CurveOrigin::Ridge, e)));

        // Topological points: listed vertex cells, then ends and junctions. A vertex is a
        // junction when it touches edges of several curves, or more than two edges of
        // one curve.
        let mut points: Vec<TopoPoint> = Vec::new();
        let mut point_of_vertex: HashMap<usize, usize> = HashMap::new();
        for (kind, nodes, p, g) in mesh.cells() {
            if kind == CellKind::Vertex && !point_of_vertex.contains_key(&(nodes[0] as usize)) {
                let t = cell_tag(p, g);
                point_of_vertex.insert(nodes[0] as usize, points.len());
                points.push(TopoPoint {
                    tag: Some(t),
                    name: mesh.tag_name(0, t).map(str::to_owned),
                    vertex: nodes[0] as usize,
                    origin: PointOrigin::Listed,
                });
            }
        }
        if in_space {
            for v in space::listed_corners(mesh) {
                if let std::collections::hash_map::Entry::Vacant(e) = point_of_vertex.entry(v) {
                    e.insert(points.len());
                    points.push(TopoPoint {
                        tag: None,
                        name: None,
                        vertex: v,
                        origin: PointOrigin::Corner,
                    });
                }
            }
        }
        let mut degree: Vec<u32> = vec![0; n];
        let mut first_curve: Vec<usize> = vec![usize::MAX; n];
        let mut multi_curve: Vec<bool> = vec![false; n];
        for (ci, (_, _, edges)) in curve_list.iter().enumerate() {
            for e in edges {
                for &v in e {
                    degree[v] += 1;
                    if first_curve[v] == usize::MAX {
                        first_curve[v] = ci;
                    } else if first_curve[v] != ci {
                        multi_curve[v] = true;
                    }
                }
            }
        }
        for v in 0..n {
            if point_of_vertex.contains_key(&v) || degree[v] == 0 {
                continue;
            }
            let origin = if multi_curve[v] || degree[v] > 2 {
                PointOrigin::Junction
            } else if degree[v] == 1 {
                PointOrigin::CurveEnd
            } else {
                continue;
            };
            point_of_vertex.insert(v, points.len());
            points.push(TopoPoint { tag: None, name: None, vertex: v, origin });
        }

        // Ordered polylines per curve, split at topological points, boundary pieces
        // oriented like their cells.
        let curves: Vec<TopoCurve> = curve_list
            .iter()
            .map(|(tag, origin, edges)| {
                let oriented: Vec<[usize; 2]> = edges
                    .iter()
                    .map(|&[a, b]| match edge_info(&key(a, b)) {
                        Some(info) if info.count == 1 => info.forward,
                        _ => [a, b],
                    })
                    .collect();
                let on_boundary =
                    edges.iter().all(|&[a, b]| edge_info(&key(a, b)).is_some_and(|i| i.count == 1));
                TopoCurve {
                    tag: *tag,
                    name: tag.and_then(|t| mesh.tag_name(1, t)).map(str::to_owned),
                    polylines: chain_polylines(&oriented, |v| point_of_vertex.contains_key(&v)),
                    on_boundary,
                    origin: *origin,
                }
            })
            .collect();

        // Classification.
        let mut vertex_class = vec![Classification::Unused; n];
        for sc in &surface_cells {
            for &v in sc.vertices() {
                vertex_class[v] = Classification::Face(sc.face);
            }
        }
        for (ci, c) in curves.iter().enumerate() {
            for pl in &c.polylines {
                for &v in &pl.vertices {
                    vertex_class[v] = Classification::Curve(ci);
                }
            }
        }
        for (pi, p) in points.iter().enumerate() {
            vertex_class[p.vertex] = Classification::Point(pi);
        }
        let mut curve_of_edge: HashMap<[usize; 2], usize> = HashMap::new();
        for (ci, c) in curves.iter().enumerate() {
            for pl in &c.polylines {
                for [a, b] in pl.edges() {
                    curve_of_edge.entry(key(a, b)).or_insert(ci);
                }
            }
        }
        let mut edges: Vec<([usize; 2], Classification)> = edge_list
            .iter()
            .map(|(k, info)| {
                (
                    *k,
                    curve_of_edge
                        .get(k)
                        .map_or(Classification::Face(info.faces[0]), |&c| Classification::Curve(c)),
                )
            })
            .collect();
        // Line cells that bound no surface cell (a lone wake line) are edges too. Hash
        // order does not matter: the list is sorted by edge just below.
        #[allow(clippy::iter_over_hash_type)]
        for (k, &c) in &curve_of_edge {
            if edge_info(k).is_none() {
                edges.push((*k, Classification::Curve(c)));
            }
        }
        edges.sort_unstable_by_key(|e| e.0);

        let space = in_space.then(|| SpaceTopology {
            ridge_angle_deg: options.ridge_angle_deg,
            surfaces: space::shapes(&surface_cells, faces.len(), &cell_edges, |k| {
                curve_of_edge.get(k).copied()
            }),
            volumes: volumes::volumes(mesh, &surface_cells),
            file_ridge_edges: space::file_ridge_edges(mesh),
        });
        Topology { points, curves, faces, surface_cells, vertex_class, edges, space }
    }

    /// The curve with `tag`, if any.
    pub fn curve_by_tag(&self, tag: i32) -> Option<&TopoCurve> {
        self.curves.iter().find(|c| c.tag == Some(tag))
    }

    /// Number of boundary polylines that close on themselves (loops), which for a
    /// domain with `h` holes is `h + 1` when each loop is one curve piece.
    pub fn closed_polylines(&self) -> usize {
        self.curves.iter().flat_map(|c| &c.polylines).filter(|p| p.closed).count()
    }
}

/// Chains directed edges into polylines. Pieces start at vertices for which
/// `is_point` holds (or at open ends) and stop at the next such vertex; what remains
/// are closed loops, each started at its smallest vertex for determinism.
fn chain_polylines(edges: &[[usize; 2]], is_point: impl Fn(usize) -> bool) -> Vec<Polyline> {
    // Outgoing and incoming edge lists per vertex (undirected walk that prefers the
    // stored direction, so boundary pieces keep their orientation).
    let mut adj: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new(); // vertex -> (edge, other)
    for (i, &[a, b]) in edges.iter().enumerate() {
        adj.entry(a).or_default().push((i, b));
        adj.entry(b).or_default().push((i, a));
    }
    let mut used = vec![false; edges.len()];
    let mut out = Vec::new();

    let walk = |start_edge: usize, from: usize, used: &mut Vec<bool>| -> Polyline {
        let mut verts = vec![from];
        let mut e = start_edge;
        let mut cur = from;
        loop {
            used[e] = true;
            let [a, b] = edges[e];
            let next = if a == cur { b } else { a };
            if next == from {
                return Polyline { vertices: verts, closed: true };
            }
            verts.push(next);
            if is_point(next) {
                return Polyline { vertices: verts, closed: false };
            }
            // Continue along an unused edge, preferring one stored as leaving `next`.
            let cand = adj[&next]
                .iter()
                .filter(|(ei, _)| !used[*ei])
                .min_by_key(|(ei, _)| (edges[*ei][0] != next, *ei));
            match cand {
                Some(&(ei, _)) => {
                    cur = next;
                    e = ei;
                }
                None => return Polyline { vertices: verts, closed: false },
            }
        }
    };

    // Open pieces: start at topological points and open ends, along edges leaving them
    // first (keeps orientation), then the rest.
    let starts: Vec<usize> =
        adj.keys().copied().filter(|&v| is_point(v) || adj[&v].len() == 1).collect();
    for pass in 0..2 {
        for &v in &starts {
            let list = adj[&v].clone();
            for (ei, _) in list {
                if used[ei] {
                    continue;
                }
                let leaves = edges[ei][0] == v;
                if (pass == 0) != leaves {
                    continue;
                }
                let pl = walk(ei, v, &mut used);
                out.push(orient_open(pl, edges));
            }
        }
    }
    // Closed loops.
    for (i, &[a, _]) in edges.iter().enumerate() {
        if !used[i] {
            let start = a;
            out.push(walk(i, start, &mut used));
        }
    }
    out
}

/// An open piece walked against its stored edge direction is reversed, so that
/// boundary pieces run with the domain on their left.
fn orient_open(mut pl: Polyline, edges: &[[usize; 2]]) -> Polyline {
    if pl.vertices.len() >= 2 {
        let (a, b) = (pl.vertices[0], pl.vertices[1]);
        if !edges.contains(&[a, b]) && edges.contains(&[b, a]) {
            pl.vertices.reverse();
        }
    }
    pl
}

#[cfg(test)]
mod tests {
    use super::*;
    use smartmesh_formats::CellBlock;

    /// `surface_edges` against its twin, a map filled cell by cell in order: random
    /// triangles and quadrilaterals on 40 vertices (so edges repeat, in both
    /// directions, across several faces, some degenerate), every key, count,
    /// direction and face pair the same, in key order.
    #[test]
    fn surface_edges_match_a_map_filled_in_cell_order() {
        let mut state = 12345u64;
        let mut next = |m: usize| {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 33) % m as u64) as usize
        };
        for _ in 0..50 {
            let n = 40;
            let cells: Vec<SurfaceCell> = (0..200)
                .map(|_| {
                    let quad = next(3) == 0;
                    let mut corners = [usize::MAX; 4];
                    for c in corners.iter_mut().take(if quad { 4 } else { 3 }) {
                        *c = next(n);
                    }
                    SurfaceCell { corners, face: next(3) }
                })
                .collect();
            // Key → (count, forward, faces).
            type Said = (u32, [usize; 2], [usize; 2]);
            let mut twin: BTreeMap<[usize; 2], Said> = BTreeMap::new();
            for sc in &cells {
                let vs = sc.vertices();
                for i in 0..vs.len() {
                    let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
                    let e = twin.entry(key(a, b)).or_insert((0, [a, b], [sc.face, sc.face]));
                    if e.0 == 1 {
                        e.2[1] = sc.face;
                    }
                    e.0 += 1;
                }
            }
            let got: Vec<([usize; 2], Said)> = surface_edges(&cells, n)
                .into_iter()
                .map(|(k, e)| (k, (e.count, e.forward, e.faces)))
                .collect();
            let want: Vec<([usize; 2], Said)> = twin.into_iter().collect();
            assert_eq!(got, want);
        }
    }

    /// A unit square split in two triangles, tagged face 7, with two tagged sides
    /// (bottom tag 1, right tag 2) and no line cells on the top and left.
    fn square() -> TaggedMesh {
        let mut m = TaggedMesh::new();
        m.points = vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
        let mut t = CellBlock::new(CellKind::Triangle);
        t.push(&[0, 1, 2], 7, 7);
        t.push(&[0, 2, 3], 7, 7);
        let mut l = CellBlock::new(CellKind::Line);
        l.push(&[1, 0], 1, 1);
        l.push(&[1, 2], 2, 2);
        m.blocks = vec![l, t];
        m.tag_names.insert((1, 1), "Bottom".into());
        m
    }

    #[test]
    fn square_curves_points_and_classification() {
        let topo = Topology::from_mesh(&square());
        assert_eq!(topo.faces.len(), 1);
        assert_eq!(topo.faces[0].tag, 7);
        // Bottom, Right, and one derived curve for top+left.
        assert_eq!(topo.curves.len(), 3);
        let bottom = topo.curve_by_tag(1).unwrap();
        assert_eq!(bottom.name.as_deref(), Some("Bottom"));
        // Oriented with the domain on the left: 0 -> 1, although the file said 1 -> 0.
        assert_eq!(bottom.polylines, vec![Polyline { vertices: vec![0, 1], closed: false }]);
        let derived = &topo.curves[2];
        assert_eq!(derived.tag, None);
        assert_eq!(derived.polylines, vec![Polyline { vertices: vec![2, 3, 0], closed: false }]);
        // Junction points where curves meet: 0, 1, 2; vertex 3 lies inside the derived curve.
        let pts: Vec<usize> = topo.points.iter().map(|p| p.vertex).collect();
        assert_eq!(pts, vec![0, 1, 2]);
        assert!(topo.points.iter().all(|p| p.origin == PointOrigin::Junction));
        assert_eq!(topo.vertex_class[3], Classification::Curve(2));
        assert_eq!(topo.edges.len(), 5);
        assert_eq!(topo.edges.iter().filter(|e| matches!(e.1, Classification::Face(_))).count(), 1);
    }

    #[test]
    fn closed_curve_without_points_stays_one_loop() {
        let mut m = square();
        m.blocks.retain(|b| b.kind == CellKind::Triangle);
        let topo = Topology::from_mesh(&m);
        assert_eq!(topo.curves.len(), 1);
        assert!(topo.points.is_empty());
        assert_eq!(
            topo.curves[0].polylines,
            vec![Polyline { vertices: vec![0, 1, 2, 3], closed: true }]
        );
        assert_eq!(topo.closed_polylines(), 1);
    }

    #[test]
    fn unused_nodes_are_reported() {
        let mut m = square();
        m.points.push([0.5, 0.5, 0.0]);
        let topo = Topology::from_mesh(&m);
        assert_eq!(topo.vertex_class[4], Classification::Unused);
    }
}
