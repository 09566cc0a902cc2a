//! What the topology adds for a mesh in space (volume cells, or surface cells off one
//! plane z = const): ridges found by the dihedral angle between adjacent surface cells,
//! the corners a Medit file lists, and the shape of each surface: its connected patches
//! and the loops of edges that bound it.
//!
//! A *ridge* is a mesh edge that exactly two cells of one surface share, that no line
//! cell of the file covers, and across which the cells' unit normals turn by more than
//! the ridge angle (MMG's `-ar`, 45° by default): `n1 · n2 < cos(angle)`, the normals
//! oriented alike (one is flipped when both cells run along the edge the same way).
//! At exactly the angle an edge is *not* a ridge, as in MMG (`ps < dhd`). An edge that
//! three or more cells of one surface share (non-manifold) is a ridge whatever the angle;
//! an edge of a degenerate cell (zero normal) is none. An edge that three or more cells
//! of several surfaces share is where surfaces meet (an interface curve) even when its
//! first two cells are of one surface. Edges where two surfaces meet are
//! curves already (the interface curves of `topology.rs`), so ridges lie inside a
//! surface: the box edges of one `Walls` surface, the rims of a cylinder tagged whole.
//!
//! A *patch* is a set of cells of one surface connected through shared edges (a union-find
//! over the sorted cell edges; hand-written, ten lines, rather than a graph crate). The
//! *boundary* of a surface is every edge that its own cells have a number of times other
//! than two, chained in order into loops (split only where the boundary touches itself).
//!
//! Cost: one sort of the surface cells' edges, O(E log E), then linear passes.

use std::collections::BTreeMap;

use smartmesh_formats::{CellKind, TaggedMesh};

use super::{chain_polylines, key, Polyline, SurfaceCell};

/// The default ridge angle in degrees (MMG's `-ar`).
pub const DEFAULT_RIDGE_ANGLE_DEG: f64 = 45.0;

/// How the topology of a mesh is recovered.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopologyOptions {
    /// Mesh edges inside one surface across which the cells' normals turn by more than
    /// this angle (degrees) are ridges, in a mesh in space (MMG's `-ar`).
    pub ridge_angle_deg: f64,
}

impl Default for TopologyOptions {
    fn default() -> Self {
        TopologyOptions { ridge_angle_deg: DEFAULT_RIDGE_ANGLE_DEG }
    }
}

/// The shape of one surface of a mesh in space.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SurfaceShape {
    /// Connected sets of its cells (through shared edges).
    pub patches: usize,
    /// Its boundary edges chained in order: closed loops, or open pieces where the
    /// boundary touches itself. Each runs the way the surface's first cell along each
    /// edge runs.
    pub boundary: Vec<Polyline>,
    /// The topological curves its boundary edges lie on, ascending.
    pub curves: Vec<usize>,
}

/// What the topology holds only for a mesh in space.
#[derive(Debug, Clone, PartialEq)]
pub struct SpaceTopology {
    /// The ridge angle used, in degrees.
    pub ridge_angle_deg: f64,
    /// Per topological face (surface), in the same order, its shape.
    pub surfaces: Vec<SurfaceShape>,
    /// The topological volumes, by tag.
    pub volumes: Vec<super::volumes::TopoVolume>,
    /// Line cells the file lists as ridges (Medit `Ridges`): curves already, counted.
    pub file_ridge_edges: usize,
}

/// Whether `mesh` lies in space: it has volume cells, or its points do not all share
/// one z (a NaN z is off every plane), as [`crate::planar`] tells a 2D mesh.
pub(super) fn in_space(mesh: &TaggedMesh) -> bool {
    if mesh.blocks.iter().any(|b| b.kind.dim() == 3 && !b.is_empty()) {
        return true;
    }
    let Some(first) = mesh.points.first() else { return false };
    mesh.points.iter().any(|p| p[2] != first[2] || !p[2].is_finite())
}

/// Every edge of every surface cell, as `(smaller vertex, larger vertex, cell, whether
/// the cell runs from the smaller to the larger)`, sorted: the runs of one edge are
/// consecutive, their cells ascending.
pub(super) fn cell_edges(cells: &[SurfaceCell]) -> Vec<(u32, u32, u32, bool)> {
    let mut out = Vec::with_capacity(cells.len() * 3);
    for (ci, sc) in cells.iter().enumerate() {
        let vs = sc.vertices();
        for i in 0..vs.len() {
            let (a, b) = (vs[i], vs[(i + 1) % vs.len()]);
            if a != b {
                out.push((a.min(b) as u32, a.max(b) as u32, ci as u32, a < b));
            }
        }
    }
    out.sort_unstable();
    out
}

/// The runs of equal edges of `edges` (from [`cell_edges`]), as index ranges.
fn runs(edges: &[(u32, u32, u32, bool)]) -> impl Iterator<Item = std::ops::Range<usize>> + '_ {
    let mut i = 0;
    std::iter::from_fn(move || {
        if i >= edges.len() {
            return None;
        }
        let mut j = i + 1;
        while j < edges.len() && (edges[j].0, edges[j].1) == (edges[i].0, edges[i].1) {
            j += 1;
        }
        let r = i..j;
        i = j;
        Some(r)
    })
}

/// The unit normal of a surface cell (a quad's from its diagonals), `None` when
/// degenerate.
pub(super) fn unit_normal(points: &[[f64; 3]], sc: &SurfaceCell) -> Option<[f64; 3]> {
    let v = sc.vertices();
    let p = |i: usize| points[v[i]];
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let (u, w) = if v.len() == 4 {
        (sub(p(2), p(0)), sub(p(3), p(1)))
    } else {
        (sub(p(1), p(0)), sub(p(2), p(0)))
    };
    let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    (len > 0.0 && len.is_finite()).then(|| [n[0] / len, n[1] / len, n[2] / len])
}

/// Edges found in space, each directed as its first cell runs along it.
#[derive(Default)]
pub(super) struct Found {
    /// The ridge edges inside each surface (see the module documentation), by face.
    pub ridges: BTreeMap<usize, Vec<[usize; 2]>>,
    /// Edges where three or more cells meet, of several surfaces, whose first two cells
    /// are of one (which `topology.rs`'s interfaces, told by the first two, miss): by the
    /// pair of the first surface and the first other one.
    pub junctions: Vec<((usize, usize), [usize; 2])>,
}

/// The ridges and the missed interface edges of the surface cells (see [`Found`]).
/// `covered`: whether a line cell covers an edge. `cos_limit`: the cosine of the ridge
/// angle.
pub(super) fn ridges(
    points: &[[f64; 3]],
    cells: &[SurfaceCell],
    edges: &[(u32, u32, u32, bool)],
    covered: impl Fn(&[usize; 2]) -> bool,
    cos_limit: f64,
) -> Found {
    let mut out = Found::default();
    for r in runs(edges) {
        let run = &edges[r];
        if run.len() < 2 {
            continue;
        }
        let (c0, c1) = (cells[run[0].2 as usize], cells[run[1].2 as usize]);
        // Two surfaces meet here: an interface curve already.
        if c0.face != c1.face {
            continue;
        }
        let k = [run[0].0 as usize, run[0].1 as usize];
        if covered(&k) {
            continue;
        }
        let forward = if run[0].3 { k } else { [k[1], k[0]] };
        if let Some(other) = run.iter().map(|e| cells[e.2 as usize].face).find(|&f| f != c0.face) {
            out.junctions.push(((c0.face.min(other), c0.face.max(other)), forward));
            continue;
        }
        let ridge = run.len() > 2
            || match (unit_normal(points, &c0), unit_normal(points, &c1)) {
                (Some(n0), Some(n1)) => {
                    let dot = n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2];
                    // Consistent cells run along a shared edge in opposite directions.
                    let dot = if run[0].3 == run[1].3 { -dot } else { dot };
                    dot < cos_limit
                }
                _ => false,
            };
        if ridge {
            out.ridges.entry(c0.face).or_default().push(forward);
        }
    }
    out
}

/// Union-find with path halving.
fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        parent[x as usize] = parent[parent[x as usize] as usize];
        x = parent[x as usize];
    }
    x
}

/// The shape of each of `faces` surfaces: patches, boundary loops and the curves they lie
/// on (`curve_of`: the curve of an edge key, if any).
pub(super) fn shapes(
    cells: &[SurfaceCell],
    faces: usize,
    edges: &[(u32, u32, u32, bool)],
    curve_of: impl Fn(&[usize; 2]) -> Option<usize>,
) -> Vec<SurfaceShape> {
    let mut parent: Vec<u32> = (0..cells.len() as u32).collect();
    let mut boundary: Vec<Vec<[usize; 2]>> = vec![Vec::new(); faces];
    for r in runs(edges) {
        let run = &edges[r];
        // Per face in this run: its cell count and its first cell's direction.
        let mut seen: Vec<(usize, usize, [usize; 2])> = Vec::new();
        for &(lo, hi, c, fwd) in run {
            let f = cells[c as usize].face;
            match seen.iter_mut().find(|s| s.0 == f) {
                Some(s) => {
                    s.1 += 1;
                    let first =
                        run.iter().find(|e| cells[e.2 as usize].face == f).map_or(c, |e| e.2);
                    let (a, b) = (find(&mut parent, first), find(&mut parent, c));
                    parent[a.max(b) as usize] = a.min(b);
                }
                None => {
                    let d =
                        if fwd { [lo as usize, hi as usize] } else { [hi as usize, lo as usize] };
                    seen.push((f, 1, d));
                }
            }
        }
        for (f, n, d) in seen {
            if n != 2 {
                boundary[f].push(d);
            }
        }
    }
    let mut patches = vec![0usize; faces];
    for c in 0..cells.len() as u32 {
        if find(&mut parent, c) == c {
            patches[cells[c as usize].face] += 1;
        }
    }
    boundary
        .into_iter()
        .zip(patches)
        .map(|(b, patches)| {
            let mut degree: BTreeMap<usize, u32> = BTreeMap::new();
            for e in &b {
                for v in e {
                    *degree.entry(*v).or_insert(0) += 1;
                }
            }
            let mut curves: Vec<usize> =
                b.iter().filter_map(|&[x, y]| curve_of(&key(x, y))).collect();
            curves.sort_unstable();
            curves.dedup();
            SurfaceShape {
                patches,
                boundary: chain_polylines(&b, |v| degree.get(&v).is_some_and(|&d| d != 2)),
                curves,
            }
        })
        .collect()
}

/// The vertices a Medit file lists as `Corners` or `RequiredVertices` (in range),
/// ascending, once each.
pub(super) fn listed_corners(mesh: &TaggedMesh) -> Vec<usize> {
    let mut v: Vec<usize> = ["Corners", "RequiredVertices"]
        .iter()
        .filter_map(|s| mesh.point_sets.get(*s))
        .flatten()
        .copied()
        .filter(|&i| i < mesh.points.len())
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// The line cells a Medit file lists as `Ridges` (a set of global cell indices).
pub(super) fn file_ridge_edges(mesh: &TaggedMesh) -> usize {
    let Some(set) = mesh.cell_sets.get("Ridges") else { return 0 };
    let mut kinds: Vec<(usize, CellKind)> = Vec::new();
    let mut at = 0;
    for b in &mesh.blocks {
        kinds.push((at, b.kind));
        at += b.len();
    }
    set.iter()
        .filter(|&&i| {
            i < at && {
                let k = kinds.partition_point(|(start, _)| *start <= i);
                k > 0 && kinds[k - 1].1.dim() == 1
            }
        })
        .count()
}
