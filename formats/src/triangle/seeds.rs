//! Hole points and region seeds for the `.poly` written beside a mesh's `.ele`, so that
//! Triangle (`-pA`) meshing that `.poly` again finds the same domain: without them it
//! meshes every part the segments enclose, the inside of a cylinder too.
//!
//! - Holes: the boundary edges of the triangles (edges of one triangle) fall into loops
//!   (joined at shared vertices). For each loop made of segments only, one hole point
//!   sits just across one of its edges, on the side with no triangle: inside the hole
//!   for an inner loop, outside the domain for the outer one (where Triangle carves
//!   anyway, and which `-c` would otherwise keep). A loop with an edge that is no segment
//!   gets none: Triangle's hole flood would leak through that edge into the domain. The
//!   point is off the edge's midpoint by half the distance to the nearest other segment
//!   or boundary edge (and at most a quarter of the edge), so the short step from the
//!   midpoint crosses nothing: it lands in the untriangulated face across the edge.
//! - Regions, when some triangle has a tag: the triangles joined through edges that are
//!   not segments are what one seed floods; each such part gets a seed at the centroid
//!   of its first triangle, with that triangle's tag as the attribute and no area bound.
//!
//! Sorting edges keeps it O(n log n) and deterministic; each hole costs one pass over
//! the segments and boundary edges.

use crate::{CellKind, RegionSeed, TaggedMesh};

/// Union-find with path halving.
struct Sets(Vec<usize>);

impl Sets {
    fn new(n: usize) -> Sets {
        Sets((0..n).collect())
    }

    fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    fn union(&mut self, a: usize, b: usize) {
        let (a, b) = (self.find(a), self.find(b));
        // The smaller root wins, so that roots do not depend on the order of unions.
        if a != b {
            let (lo, hi) = (a.min(b), a.max(b));
            self.0[hi] = lo;
        }
    }
}

fn xy(mesh: &TaggedMesh, v: u32) -> [f64; 2] {
    let p = mesh.points[v as usize];
    [p[0], p[1]]
}

/// Distance from `p` to the segment `a`–`b`.
fn distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// Hole points and region seeds of `mesh` (see the module documentation). The mesh is
/// valid (every node in range).
pub(super) fn derive(mesh: &TaggedMesh) -> (Vec<[f64; 2]>, Vec<RegionSeed>) {
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    // Triangles by their corners, with their tags.
    let mut tris: Vec<([u32; 3], i32)> = Vec::new();
    for b in &mesh.blocks {
        if matches!(b.kind, CellKind::Triangle | CellKind::Triangle6) {
            tris.extend(b.cells().zip(&b.physical).map(|(c, &p)| ([c[0], c[1], c[2]], p)));
        }
    }
    let mut segments: Vec<(u32, u32)> = mesh
        .blocks
        .iter()
        .filter(|b| b.kind == CellKind::Line)
        .flat_map(|b| b.cells().map(|c| key(c[0], c[1])))
        .collect();
    segments.sort_unstable();
    segments.dedup();
    let is_segment = |e: (u32, u32)| segments.binary_search(&e).is_ok();

    // Every triangle edge with its triangle and the opposite corner, sorted by edge.
    let mut edges: Vec<((u32, u32), usize, u32)> = Vec::with_capacity(3 * tris.len());
    for (t, &(c, _)) in tris.iter().enumerate() {
        for k in 0..3 {
            edges.push((key(c[k], c[(k + 1) % 3]), t, c[(k + 2) % 3]));
        }
    }
    edges.sort_unstable();

    let mut parts = Sets::new(tris.len());
    let mut boundary: Vec<((u32, u32), u32)> = Vec::new();
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 {
            j += 1;
        }
        if j - i == 1 {
            boundary.push((edges[i].0, edges[i].2));
        } else if !is_segment(edges[i].0) {
            for k in i + 1..j {
                parts.union(edges[i].1, edges[k].1);
            }
        }
        i = j;
    }

    // Boundary loops: boundary edges joined at their vertices.
    let mut verts: Vec<u32> = boundary.iter().flat_map(|&((a, b), _)| [a, b]).collect();
    verts.sort_unstable();
    verts.dedup();
    let index = |v: u32| verts.binary_search(&v).unwrap_or(0);
    let mut loops = Sets::new(verts.len());
    for &((a, b), _) in &boundary {
        loops.union(index(a), index(b));
    }
    // Per loop: whether every edge is a segment, and its first edge.
    let mut first: Vec<Option<usize>> = vec![None; verts.len()];
    let mut closed = vec![true; verts.len()];
    for (k, &(e, _)) in boundary.iter().enumerate() {
        let r = loops.find(index(e.0));
        first[r].get_or_insert(k);
        closed[r] &= is_segment(e);
    }
    let mut holes = Vec::new();
    for r in 0..verts.len() {
        let Some(k) = first[r].filter(|_| closed[r]) else { continue };
        let ((a, b), c) = boundary[k];
        let (pa, pb, pc) = (xy(mesh, a), xy(mesh, b), xy(mesh, c));
        let m = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
        let len = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let mut n = [-(pb[1] - pa[1]) / len, (pb[0] - pa[0]) / len];
        if n[0] * (pc[0] - m[0]) + n[1] * (pc[1] - m[1]) > 0.0 {
            n = [-n[0], -n[1]];
        }
        let others = segments.iter().copied().chain(boundary.iter().map(|&(e, _)| e));
        let clear = others
            .filter(|&e| e != (a, b))
            .map(|(p, q)| distance(m, xy(mesh, p), xy(mesh, q)))
            .fold(0.5 * len, f64::min);
        let d = 0.5 * clear;
        let h = [m[0] + d * n[0], m[1] + d * n[1]];
        // A degenerate edge (or one touching another) has no room across it.
        if d > 0.0 && d.is_finite() && (h[0] != m[0] || h[1] != m[1]) {
            holes.push(h);
        }
    }

    let mut regions = Vec::new();
    if tris.iter().any(|&(_, tag)| tag != 0) {
        let mut seen = vec![false; tris.len()];
        for (t, &(c, tag)) in tris.iter().enumerate() {
            let r = parts.find(t);
            if std::mem::replace(&mut seen[r], true) {
                continue;
            }
            let p = c.map(|v| xy(mesh, v));
            regions.push(RegionSeed {
                point: [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0],
                attribute: tag as f64,
                max_area: -1.0,
            });
        }
    }
    (holes, regions)
}
