//! From a [`TaggedMesh`] and its metric to the remesher's working state: triangles made
//! counter-clockwise, the constrained edges (boundary edges, edges between triangles of
//! different tags, edges of line cells), the corners that never move, and the pieces of
//! curve between corners.
//!
//! Corners are the topological points of [`Topology`] (listed vertex cells, curve ends,
//! junctions), plus the vertices where the tags of the constrained edges change (a Gmsh
//! physical curve made of several elementary curves), plus the vertices where a curve
//! turns by more than the ridge angle (MMG's `-ar` convention). A closed curve with no
//! corner gets its first vertex fixed, so that every piece has two ends.
//!
//! Kept cells (a boundary-layer skin: quads, and the triangles the caller keeps) are
//! taken out of the working triangles: their vertices are corners, their edges that a
//! working triangle shares are one-edge *frozen* pieces (never split, and with both ends
//! fixed never collapsed nor moved), and the line cells along their other edges are
//! carried to the output as they are. The edges of the curves the options freeze
//! (periodic sides) are frozen pieces the same way.

use std::collections::HashMap;

use super::boundary::{LineTags, Piece};
use super::error::RemeshError;
use super::options::RemeshOptions;
use super::work::{key, orient, Role};
use crate::metric::log_spd;
use crate::metric::Sym2;
use crate::topology::{cell_tag, Topology};
use smartmesh_formats::{CellKind, TaggedMesh};

/// Everything the driver starts from.
pub(super) struct Start {
    /// 2D coordinates of the input points.
    pub pts: Vec<[f64; 2]>,
    /// Counter-clockwise input triangles.
    pub tris: Vec<[u32; 3]>,
    /// Face of each triangle (index into `faces`).
    pub face: Vec<u32>,
    /// `(physical, geometrical)` of each face.
    pub faces: Vec<(i32, i32)>,
    /// What each input vertex may do.
    pub role: Vec<Role>,
    /// The pieces.
    pub pieces: Vec<Piece>,
    /// Constrained edges with their piece.
    pub cons: ahash::AHashMap<(u32, u32), u32>,
    /// Vertex cells of the input: `(vertex, physical, geometrical)`.
    pub vertex_cells: Vec<(u32, i32, i32)>,
    /// What the output will not carry.
    pub warnings: Vec<String>,
    /// Kept surface cells, as they were: kind, nodes, physical and geometrical tags.
    pub kept: Vec<(CellKind, Vec<u32>, i32, i32)>,
    /// Line cells along kept cells' edges that no working triangle holds, as they were.
    pub kept_lines: Vec<([u32; 2], i32, i32)>,
}

/// Reads the triangles, constraints and pieces of `mesh`, whose topological points
/// `topology` lists; the surface cells (in [`TaggedMesh::cells`] order) that `keep` flags
/// stay as they are.
pub(super) fn start(
    mesh: &TaggedMesh,
    topology: &Topology,
    metric: &[Sym2],
    opts: &RemeshOptions,
    keep: &[bool],
) -> Result<Start, RemeshError> {
    let n = mesh.points.len();
    if metric.len() != n {
        return Err(RemeshError::MetricCount { items: metric.len(), vertices: n });
    }
    if n > u32::MAX as usize / 4 {
        return Err(RemeshError::TooLarge { vertices: n });
    }
    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
    for (v, p) in mesh.points.iter().enumerate() {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(RemeshError::BadPoint { vertex: v });
        }
    }
    let mut warnings = Vec::new();
    let Cells { tris, tri_tags, line_tags, lines_in_order, vertex_cells, kept, mut frozen } =
        read_cells(mesh, keep, &pts)?;
    let used = check_metric(metric, &tris, n)?;
    let (face, faces) = number_faces(&tri_tags);
    let constrained = constrained_edges(&tris, &face, &line_tags)?;
    let frozen_edges = frozen_edges(&kept, &constrained, opts, &mut frozen);
    let held = |k: &(u32, u32)| constrained.binary_search_by(|c| c.0.cmp(k)).is_ok();
    let kept_lines: Vec<([u32; 2], i32, i32)> = mesh
        .cells()
        .filter(|c| c.0 == CellKind::Line && c.1[0] != c.1[1])
        .filter(|c| {
            let k = key(c.1[0], c.1[1]);
            frozen_edges.contains(&k) && !held(&k)
        })
        .map(|c| ([c.1[0], c.1[1]], c.2, c.3))
        .collect();
    let dropped_lines =
        lines_in_order.iter().filter(|(k, _)| !held(k) && !frozen_edges.contains(k)).count();
    if dropped_lines > 0 {
        warnings
            .push(format!("{dropped_lines} line cells that are not triangle edges are not kept"));
    }
    warnings.extend(data_warnings(mesh));

    let adjacency = Adjacency::new(&constrained, n);
    let (mut corner, breaks) =
        corners(topology, &vertex_cells, &frozen, &constrained, &adjacency, &pts, opts);
    let logs: Vec<Sym2> = metric.iter().map(log_spd).collect();
    let (mut role, mut pieces, cons) =
        walk_pieces(&constrained, &adjacency, &mut corner, &breaks, &pts, &logs);
    for v in 0..n {
        if corner[v] || !used[v] {
            role[v] = Role::Fixed;
        }
    }
    // Both ends of a kept cell's edge are corners: its piece is that one edge.
    for p in &mut pieces {
        p.frozen = p.pts.len() == 2 && frozen_edges.contains(&key(p.ends[0], p.ends[1]));
    }
    Ok(Start {
        pts,
        tris,
        face,
        faces,
        role,
        pieces,
        cons,
        vertex_cells,
        warnings,
        kept,
        kept_lines,
    })
}

/// The cells of the input, sorted out: working triangles (counter-clockwise) and their
/// tags, line cells by edge (first tags win) and in order, vertex cells, kept cells, and
/// the vertices kept cells freeze.
struct Cells {
    tris: Vec<[u32; 3]>,
    tri_tags: Vec<(i32, i32)>,
    line_tags: HashMap<(u32, u32), (i32, i32)>,
    lines_in_order: Vec<((u32, u32), (i32, i32))>,
    vertex_cells: Vec<(u32, i32, i32)>,
    kept: Vec<(CellKind, Vec<u32>, i32, i32)>,
    frozen: Vec<bool>,
}

/// Sorts the cells of `mesh` (whose points are `pts`); refuses degenerate triangles,
/// unsupported cells and a mesh with no working triangle.
fn read_cells(mesh: &TaggedMesh, keep: &[bool], pts: &[[f64; 2]]) -> Result<Cells, RemeshError> {
    let mut tris = Vec::new();
    let mut tri_tags = Vec::new();
    let mut line_tags: HashMap<(u32, u32), (i32, i32)> = HashMap::new();
    let mut lines_in_order: Vec<((u32, u32), (i32, i32))> = Vec::new();
    let mut vertex_cells = Vec::new();
    let mut kept = Vec::new();
    let mut frozen = vec![false; pts.len()];
    let mut surface = 0;
    for (kind, nodes, phys, geo) in mesh.cells() {
        if kind.dim() == 2 {
            surface += 1;
            if keep.get(surface - 1).copied().unwrap_or(false) {
                if kind.is_second_order() {
                    return Err(RemeshError::UnsupportedCell { kind: kind.name() });
                }
                nodes.iter().for_each(|&v| frozen[v as usize] = true);
                kept.push((kind, nodes.to_vec(), phys, geo));
                continue;
            }
        }
        match kind {
            CellKind::Triangle => {
                let t = [nodes[0], nodes[1], nodes[2]];
                let index = tris.len();
                let o =
                    orient(pts[nodes[0] as usize], pts[nodes[1] as usize], pts[nodes[2] as usize]);
                if o == 0.0 || t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                    return Err(RemeshError::DegenerateTriangle {
                        triangle: index,
                        vertices: [nodes[0] as usize, nodes[1] as usize, nodes[2] as usize],
                    });
                }
                tris.push(if o > 0.0 { t } else { [t[0], t[2], t[1]] });
                tri_tags.push((phys, geo));
            }
            CellKind::Line => {
                if nodes[0] != nodes[1] {
                    let k = key(nodes[0], nodes[1]);
                    if let std::collections::hash_map::Entry::Vacant(e) = line_tags.entry(k) {
                        e.insert((phys, geo));
                        lines_in_order.push((k, (phys, geo)));
                    }
                }
            }
            CellKind::Vertex => vertex_cells.push((nodes[0], phys, geo)),
            other => return Err(RemeshError::UnsupportedCell { kind: other.name() }),
        }
    }
    if tris.is_empty() {
        return Err(if kept.is_empty() { RemeshError::NoTriangles } else { RemeshError::AllKept });
    }
    Ok(Cells { tris, tri_tags, line_tags, lines_in_order, vertex_cells, kept, frozen })
}

/// Which of the `n` vertices a triangle uses; the metric must be finite and SPD there.
fn check_metric(metric: &[Sym2], tris: &[[u32; 3]], n: usize) -> Result<Vec<bool>, RemeshError> {
    let mut used = vec![false; n];
    for t in tris {
        for &v in t {
            used[v as usize] = true;
        }
    }
    for (v, m) in metric.iter().enumerate() {
        if used[v]
            && !(m.a.is_finite()
                && m.b.is_finite()
                && m.c.is_finite()
                && m.a > 0.0
                && m.c > 0.0
                && m.det() > 0.0)
        {
            return Err(RemeshError::NotSpd { vertex: v, a: m.a, b: m.b, c: m.c });
        }
    }
    Ok(used)
}

/// The face of each triangle (its tag pair numbered by first use), and the tag pair of
/// each face.
fn number_faces(tri_tags: &[(i32, i32)]) -> (Vec<u32>, Vec<(i32, i32)>) {
    let mut face_of: std::collections::BTreeMap<(i32, i32), u32> =
        std::collections::BTreeMap::new();
    let face: Vec<u32> = tri_tags
        .iter()
        .map(|tg| {
            let next = face_of.len() as u32;
            *face_of.entry(*tg).or_insert(next)
        })
        .collect();
    let mut faces = vec![(0, 0); face_of.len()];
    for (tg, &i) in &face_of {
        faces[i as usize] = *tg;
    }
    (face, faces)
}

/// The label of a constrained edge: its line tags and the pair of faces beside it.
type Label = (LineTags, u32, u32);

/// A constrained edge (its vertices, smaller first) and its label.
type Constrained = ((u32, u32), Label);

/// The constrained edges, sorted, with their label: boundary edges, edges between two
/// faces, edges of line cells. Refuses an edge held by more than two triangles.
fn constrained_edges(
    tris: &[[u32; 3]],
    face: &[u32],
    line_tags: &HashMap<(u32, u32), (i32, i32)>,
) -> Result<Vec<Constrained>, RemeshError> {
    // Edges of the triangles, sorted, with the triangles holding them.
    let mut occ: Vec<((u32, u32), u32)> = Vec::with_capacity(tris.len() * 3);
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            occ.push((key(t[k], t[(k + 1) % 3]), i as u32));
        }
    }
    occ.sort_unstable();
    let mut constrained: Vec<Constrained> = Vec::new();
    let mut i = 0;
    while i < occ.len() {
        let mut j = i;
        while j < occ.len() && occ[j].0 == occ[i].0 {
            j += 1;
        }
        let e = occ[i].0;
        if j - i > 2 {
            return Err(RemeshError::NonManifold {
                edge: [e.0 as usize, e.1 as usize],
                triangles: j - i,
            });
        }
        let f0 = face[occ[i].1 as usize];
        let f1 = if j - i == 2 { face[occ[i + 1].1 as usize] } else { u32::MAX };
        let lt = line_tags.get(&e).copied();
        if j - i == 1 || f0 != f1 || lt.is_some() {
            constrained.push((e, (lt, f0.min(f1), f0.max(f1))));
        }
        i = j;
    }
    Ok(constrained)
}

/// The edges of the kept cells and of the frozen curves (whose ends join `frozen`).
fn frozen_edges(
    kept: &[(CellKind, Vec<u32>, i32, i32)],
    constrained: &[Constrained],
    opts: &RemeshOptions,
    frozen: &mut [bool],
) -> std::collections::BTreeSet<(u32, u32)> {
    // Edges of the kept cells; those a working triangle holds become frozen pieces.
    let mut frozen_edges: std::collections::BTreeSet<(u32, u32)> = Default::default();
    for (_, nodes, _, _) in kept {
        for k in 0..nodes.len() {
            frozen_edges.insert(key(nodes[k], nodes[(k + 1) % nodes.len()]));
        }
    }
    // Edges of frozen curves: one-edge frozen pieces too, their ends corners.
    if !opts.frozen_curves.is_empty() {
        for (e, (lt, _, _)) in constrained {
            if lt.is_some_and(|(p, g)| opts.frozen_curves.contains(&cell_tag(p, g))) {
                frozen_edges.insert(*e);
                frozen[e.0 as usize] = true;
                frozen[e.1 as usize] = true;
            }
        }
    }
    frozen_edges
}

/// Constrained adjacency per vertex (CSR over the sorted edge list).
struct Adjacency {
    deg: Vec<u32>,
    adj: Vec<u32>,
}

impl Adjacency {
    fn new(constrained: &[Constrained], n: usize) -> Adjacency {
        let mut deg = vec![0u32; n + 1];
        for (e, _) in constrained {
            deg[e.0 as usize + 1] += 1;
            deg[e.1 as usize + 1] += 1;
        }
        for v in 0..n {
            deg[v + 1] += deg[v];
        }
        let mut fill = deg.clone();
        let mut adj = vec![0u32; deg[n] as usize];
        for (ci, (e, _)) in constrained.iter().enumerate() {
            for v in [e.0, e.1] {
                adj[fill[v as usize] as usize] = ci as u32;
                fill[v as usize] += 1;
            }
        }
        Adjacency { deg, adj }
    }

    /// The constrained edges at `v`, by index.
    fn around(&self, v: u32) -> &[u32] {
        &self.adj[self.deg[v as usize] as usize..self.deg[v as usize + 1] as usize]
    }
}

/// The corners: topological points, vertex cells, frozen vertices, kept points, and
/// the vertices of constrained edges where the edge count or the label changes or the
/// curve turns by more than the ridge angle. Returned with the *breaks*, at which the
/// smooth reconstruction stops: all of these corners (a closed loop's start, made a
/// corner later, is the one fixed vertex the curve goes on smoothly through).
fn corners(
    topology: &Topology,
    vertex_cells: &[(u32, i32, i32)],
    frozen: &[bool],
    constrained: &[Constrained],
    adjacency: &Adjacency,
    pts: &[[f64; 2]],
    opts: &RemeshOptions,
) -> (Vec<bool>, Vec<bool>) {
    let n = pts.len();
    let mut corner = vec![false; n];
    for p in &topology.points {
        corner[p.vertex] = true;
    }
    for &(v, _, _) in vertex_cells {
        corner[v as usize] = true;
    }
    for (c, &f) in corner.iter_mut().zip(frozen) {
        *c |= f;
    }
    let cos_ridge = opts.ridge_angle_degrees.to_radians().cos();
    let keep_points: std::collections::BTreeSet<[u64; 2]> =
        opts.keep_points.iter().map(|p| [p[0].to_bits(), p[1].to_bits()]).collect();
    let mut kept = vec![false; n];
    for v in 0..n as u32 {
        let es = adjacency.around(v);
        if es.is_empty() {
            continue;
        }
        kept[v as usize] = !keep_points.is_empty()
            && keep_points.contains(&[pts[v as usize][0].to_bits(), pts[v as usize][1].to_bits()]);
        if es.len() != 2 {
            corner[v as usize] = true;
            continue;
        }
        let (e1, e2) = (&constrained[es[0] as usize], &constrained[es[1] as usize]);
        if e1.1 != e2.1 {
            corner[v as usize] = true;
            continue;
        }
        let other = |e: (u32, u32)| if e.0 == v { e.1 } else { e.0 };
        let (u, w) = (pts[other(e1.0) as usize], pts[other(e2.0) as usize]);
        let p = pts[v as usize];
        let (d1, d2) = ([p[0] - u[0], p[1] - u[1]], [w[0] - p[0], w[1] - p[1]]);
        let c = (d1[0] * d2[0] + d1[1] * d2[1]) / (d1[0].hypot(d1[1]) * d2[0].hypot(d2[1]));
        if c < cos_ridge {
            corner[v as usize] = true;
        }
    }
    // Kept points are breaks too: the geometry the loop started from is its segments,
    // and every boundary edge stays on one of them (a curve through them would leave
    // them).
    for (c, k) in corner.iter_mut().zip(kept) {
        *c |= k;
    }
    let breaks = corner.clone();
    (corner, breaks)
}

/// The piece of each constrained edge.
type PieceOfEdge = ahash::AHashMap<(u32, u32), u32>;

/// The pieces: walks from every corner along each unvisited constrained edge to the next
/// corner; then the loops without corner, from their smallest vertex (which becomes a
/// corner, but no break: the reconstruction goes on smoothly through it). Returns the
/// role of each vertex on a piece, the pieces, and the piece of each constrained edge.
fn walk_pieces(
    constrained: &[Constrained],
    adjacency: &Adjacency,
    corner: &mut [bool],
    breaks: &[bool],
    pts: &[[f64; 2]],
    logs: &[Sym2],
) -> (Vec<Role>, Vec<Piece>, PieceOfEdge) {
    let n = pts.len();
    let around = |v: u32| adjacency.around(v);
    let mut visited = vec![false; constrained.len()];
    let mut role = vec![Role::Free; n];
    let mut pieces: Vec<Piece> = Vec::new();
    let mut cons: PieceOfEdge = ahash::AHashMap::with_capacity(constrained.len());
    let mut walk =
        |start: u32, first: u32, corner: &[bool], visited: &mut Vec<bool>, role: &mut Vec<Role>| {
            let pid = pieces.len() as u32;
            let tags = constrained[first as usize].1 .0;
            let mut verts = vec![start];
            let mut e = first;
            let mut cur = start;
            loop {
                visited[e as usize] = true;
                cons.insert(constrained[e as usize].0, pid);
                let (a, b) = constrained[e as usize].0;
                let next = if a == cur { b } else { a };
                verts.push(next);
                if corner[next as usize] {
                    break;
                }
                let Some(&ne) = around(next).iter().find(|&&x| !visited[x as usize]) else { break };
                cur = next;
                e = ne;
            }
            // Past an end that is no break, the curve's next point (along the one other
            // constrained edge there).
            let past = |x: u32, along: u32| -> Option<[f64; 2]> {
                let es = around(x);
                if breaks[x as usize] || es.len() != 2 {
                    return None;
                }
                let o = if es[0] == along { es[1] } else { es[0] };
                let (a, b) = constrained[o as usize].0;
                Some(pts[if a == x { b } else { a } as usize])
            };
            let last = *verts.last().unwrap_or(&verts[0]);
            let p = Piece::new(
                verts.iter().map(|&v| pts[v as usize]).collect(),
                verts.iter().map(|&v| logs[v as usize]).collect(),
                tags,
                [verts[0], last],
                [past(verts[0], first), past(last, e)],
            );
            for (i, &v) in verts.iter().enumerate() {
                if !corner[v as usize] {
                    role[v as usize] = Role::Slides { piece: pid, s: p.s[i] };
                }
            }
            pieces.push(p);
        };
    for v in 0..n as u32 {
        if corner[v as usize] {
            for &e in around(v) {
                if !visited[e as usize] {
                    walk(v, e, corner, &mut visited, &mut role);
                }
            }
        }
    }
    for ci in 0..constrained.len() {
        if !visited[ci] {
            let v = constrained[ci].0 .0;
            corner[v as usize] = true;
            for &e in around(v) {
                if !visited[e as usize] {
                    walk(v, e, corner, &mut visited, &mut role);
                }
            }
        }
    }
    (role, pieces, cons)
}

/// What the output of a remeshing of `mesh` does not carry of its point and cell data.
pub(super) fn data_warnings(mesh: &TaggedMesh) -> Vec<String> {
    let mut warnings = Vec::new();
    for name in mesh.point_data.keys() {
        if name != crate::metric_field::METRIC {
            warnings.push(format!(
                "point data `{name}` is not carried (only the metric is interpolated)"
            ));
        }
    }
    for name in mesh.cell_data.keys() {
        warnings.push(format!("cell data `{name}` is not carried"));
    }
    warnings
}
