//! The planar cut of a tetrahedral mesh by an axis-aligned plane x, y or z = c: the exact
//! intersection polygons of its tetrahedra (triangles and quadrilaterals), the traces of
//! its tagged surface triangles (segments), and a 3D metric carried to the cut's points
//! and restricted to the plane. It knows no picture: `report --cut` draws what it returns
//! as it draws a planar mesh.
//!
//! The cut is a planar `TaggedMesh` in the plane's coordinates (u, v) — (y, z) for a cut
//! x = c, (x, z) for y = c, (x, y) for z = c — whose faces carry the volume tags of the
//! tetrahedra they come from, whose line cells carry the surface tags of the triangles
//! they come from, and whose tag names move down one dimension (a volume's name names a
//! face of the cut, a surface's a curve).
//!
//! Exactness. Each corner is classified by comparing its coordinate with c exactly
//! (below, on, above: no tolerance, so a point on the plane is on it). A tetrahedron
//! crossing the plane gives the convex hull of its edges' crossings and its corners on
//! the plane: a triangle (one corner alone on its side; or one corner on the plane and
//! the others on both sides; or two on it and the others on both sides) or a quad (two
//! and two). A tetrahedron that only touches the plane at a corner or an edge gives
//! nothing: that corner or edge belongs to the polygons of the tetrahedra that cross.
//! A face lying in the plane is shared by the tetrahedra on both of its sides: it is
//! kept once (by its sorted corners, with the tag of the first tetrahedron that has it),
//! so the polygons tile the section without overlap and without double lines, and their
//! areas sum to the section's. Every point of the cut is named by where it comes from
//! (a vertex on the plane, or an edge crossing it, computed once from the edge's
//! lower-numbered end), so neighbouring polygons share their points and edges.
//!
//! Surfaces: a tagged triangle crossing the plane gives the segment between its two
//! crossings (or its corner on the plane and the crossing opposite); an edge lying in
//! the plane gives that edge; triangles lying in the plane give the edges of their
//! patch's boundary (the edges that one in-plane triangle of the tag has). Each segment
//! is kept once per tag. Only triangles are traced (the surface cells of a tetrahedral
//! mesh); other volume cells than tetrahedra are counted and left out.
//!
//! The metric: at an edge crossing at parameter t, the Log-Euclidean mean
//! exp((1 − t) log M_a + t log M_b) of the ends' metrics (the mean every 3D
//! interpolation of smartmesh takes); at a vertex on the plane, its own. Its
//! *restriction* to the plane is the 2×2 block of the plane's two axes: the ellipse
//! {x in the plane : xᵀ M x = 1} is exactly the ellipsoid's section through its centre,
//! the unit ball of the metric for edges lying in the plane. It is no projection (the
//! ellipsoid's shadow on the plane, larger wherever the ellipsoid leans out of it).
//!
//! Cost: O(cells) and a map of the cut's points, O(cut) memory.

use std::collections::BTreeMap;
use std::fmt;

use smartmesh_formats::{CellBlock, CellKind, NodeIndex, TaggedMesh};

use crate::metric::{log_euclidean3, log_spd3, Sym2, Sym3};
use crate::topology::cell_tag;

#[cfg(test)]
mod tests;

/// A coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z.
    Z,
}

impl Axis {
    /// The coordinate's index in a point.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
            Axis::Z => 2,
        }
    }

    /// The plane's two axes, the picture's horizontal then vertical one: (y, z) for a
    /// cut x = c, (x, z) for y = c, (x, y) for z = c.
    pub fn in_plane(self) -> [usize; 2] {
        match self {
            Axis::X => [1, 2],
            Axis::Y => [0, 2],
            Axis::Z => [0, 1],
        }
    }

    /// Its letter.
    pub fn name(self) -> &'static str {
        ["x", "y", "z"][self.index()]
    }
}

/// The plane `axis` = `value`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct CutPlane {
    /// The axis the plane is normal to.
    pub axis: Axis,
    /// Where it crosses that axis.
    pub value: f64,
}

impl CutPlane {
    /// Reads `x=VALUE`, `y=VALUE` or `z=VALUE` (a finite number; spaces allowed around
    /// `=`).
    pub fn parse(text: &str) -> Result<CutPlane, String> {
        let expected = "expected x=VALUE, y=VALUE or z=VALUE (e.g. z=0.5)";
        let (a, v) = text.split_once('=').ok_or_else(|| format!("`{text}`: {expected}"))?;
        let axis = match a.trim().to_ascii_lowercase().as_str() {
            "x" => Axis::X,
            "y" => Axis::Y,
            "z" => Axis::Z,
            other => return Err(format!("`{text}`: unknown axis `{other}`; {expected}")),
        };
        let value: f64 =
            v.trim().parse().ok().filter(|v: &f64| v.is_finite()).ok_or_else(|| {
                format!("`{text}`: `{}` is no finite number; {expected}", v.trim())
            })?;
        Ok(CutPlane { axis, value })
    }
}

impl fmt::Display for CutPlane {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}", self.axis.name(), self.value)
    }
}

/// Where a point of the cut comes from: a mesh vertex on the plane, or the crossing of
/// the edge between two vertices (the lower-numbered first) on both sides of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Origin {
    /// A vertex on the plane.
    Vertex(usize),
    /// The crossing of edge (a, b), a < b.
    Edge(usize, usize),
}

/// The cut of a mesh: a planar mesh in the plane's coordinates, the restricted metric at
/// its points, its area and counts.
#[derive(Debug, Clone)]
pub(crate) struct Section {
    /// The cut as a planar mesh: points (u, v, 0); triangles and quads tagged by volume,
    /// counter-clockwise in (u, v); line cells tagged by surface.
    pub mesh: TaggedMesh,
    /// The restriction to the plane of the metric at each point, when a metric was given.
    pub metric: Option<Vec<Sym2>>,
    /// Counts of what was cut.
    pub counts: SectionCounts,
    /// The area of the cut: the sum of its polygons' areas.
    pub area: f64,
}

/// What a cut found.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct SectionCounts {
    /// Tetrahedra of the mesh.
    pub tetrahedra: usize,
    /// Triangles of the cut (faces in the plane included).
    pub triangles: usize,
    /// Quadrilaterals of the cut.
    pub quads: usize,
    /// Faces of the mesh lying in the plane (among `triangles`).
    pub faces_in_plane: usize,
    /// Segments of the surfaces' traces.
    pub trace_segments: usize,
    /// Volume cells other than tetrahedra, left out.
    pub other_volume_cells: usize,
    /// Tetrahedra left out: flat ones with all four corners on the plane, or with a
    /// coordinate that is no finite number.
    pub degenerate: usize,
    /// Tetrahedra crossing the plane whose polygon has no area in floating point (a
    /// corner within rounding of the plane): left out, their area is below what a
    /// double holds.
    pub zero_area: usize,
}

/// Which side of the plane a coordinate is on: exact comparisons, no tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Below,
    On,
    Above,
}

fn side(x: f64, c: f64) -> Side {
    if x < c {
        Side::Below
    } else if x > c {
        Side::Above
    } else {
        Side::On
    }
}

/// The points of the cut, named by their origin, created on first use.
struct Points<'a> {
    mesh: &'a [[f64; 3]],
    plane: CutPlane,
    index: BTreeMap<Origin, usize>,
    origins: Vec<Origin>,
    uv: Vec<[f64; 2]>,
}

impl Points<'_> {
    fn vertex(&mut self, v: usize) -> usize {
        self.get(Origin::Vertex(v))
    }

    fn edge(&mut self, a: usize, b: usize) -> usize {
        self.get(Origin::Edge(a.min(b), a.max(b)))
    }

    fn get(&mut self, o: Origin) -> usize {
        if let Some(&i) = self.index.get(&o) {
            return i;
        }
        let [iu, iv] = self.plane.axis.in_plane();
        let p = match o {
            Origin::Vertex(v) => self.mesh[v],
            Origin::Edge(a, b) => {
                let (pa, pb) = (self.mesh[a], self.mesh[b]);
                let t = crossing(pa, pb, self.plane);
                let mut p = pa;
                for k in [iu, iv] {
                    p[k] = pa[k] + t * (pb[k] - pa[k]);
                }
                p
            }
        };
        let i = self.uv.len();
        self.index.insert(o, i);
        self.origins.push(o);
        self.uv.push([p[iu], p[iv]]);
        i
    }
}

/// The parameter t in [0, 1] where the segment from `a` to `b` (on both sides of the
/// plane) crosses it.
fn crossing(a: [f64; 3], b: [f64; 3], plane: CutPlane) -> f64 {
    let k = plane.axis.index();
    ((plane.value - a[k]) / (b[k] - a[k])).clamp(0.0, 1.0)
}

/// Twice the signed area of polygon `p` (shoelace, about its first point so that a tiny
/// polygon far from the origin keeps its digits), positive when counter-clockwise.
pub(crate) fn twice_area(p: &[[f64; 2]]) -> f64 {
    let Some(&o) = p.first() else { return 0.0 };
    let d: Vec<[f64; 2]> = p.iter().map(|q| [q[0] - o[0], q[1] - o[1]]).collect();
    (1..d.len().saturating_sub(1)).map(|i| d[i][0] * d[i + 1][1] - d[i + 1][0] * d[i][1]).sum()
}

/// The polygon (indices into the tetrahedron's corners `c`) that a tetrahedron crossing
/// the plane cuts, from its corners' sides: its vertices as origins, in cyclic order.
/// `None` when it only touches the plane or misses it; faces in the plane are handled by
/// the caller.
fn tet_polygon(c: [usize; 4], s: [Side; 4]) -> Option<Vec<Origin>> {
    let of = |w: Side| -> Vec<usize> { (0..4).filter(|&i| s[i] == w).map(|i| c[i]).collect() };
    let (below, on, above) = (of(Side::Below), of(Side::On), of(Side::Above));
    let e = |a: usize, b: usize| Origin::Edge(a.min(b), a.max(b));
    match (below.len(), on.len(), above.len()) {
        (1, 0, 3) | (3, 0, 1) => {
            let (lone, rest) = if below.len() == 1 { (below[0], above) } else { (above[0], below) };
            Some(rest.iter().map(|&r| e(lone, r)).collect())
        }
        // Edges b0-a0, b0-a1, b1-a1, b1-a0 run round the quad: each shares a corner
        // with the next.
        (2, 0, 2) => Some(vec![
            e(below[0], above[0]),
            e(below[0], above[1]),
            e(below[1], above[1]),
            e(below[1], above[0]),
        ]),
        (1, 1, 2) | (2, 1, 1) => {
            let (lone, rest) = if below.len() == 1 { (below[0], above) } else { (above[0], below) };
            Some(vec![Origin::Vertex(on[0]), e(lone, rest[0]), e(lone, rest[1])])
        }
        (1, 2, 1) => {
            Some(vec![Origin::Vertex(on[0]), Origin::Vertex(on[1]), e(below[0], above[0])])
        }
        _ => None,
    }
}

/// The cut of `mesh`'s tetrahedra and tagged triangles by `plane`, with `metric` (one
/// tensor per vertex of `mesh`) carried to the cut's points and restricted to the plane.
pub(crate) fn cut(mesh: &TaggedMesh, metric: Option<&[Sym3]>, plane: CutPlane) -> Section {
    let k = plane.axis.index();
    let c = plane.value;
    let mut pts = Points {
        mesh: &mesh.points,
        plane,
        index: BTreeMap::new(),
        origins: Vec::new(),
        uv: Vec::new(),
    };
    let mut counts = SectionCounts::default();
    let mut tris = CellBlock::new(CellKind::Triangle);
    let mut quads = CellBlock::new(CellKind::Quad);
    let mut area = 0.0;
    // Faces in the plane by their sorted corners, in the order first met.
    let mut in_plane: BTreeMap<[usize; 3], ()> = BTreeMap::new();
    let finite = |v: usize| mesh.points[v].iter().all(|x| x.is_finite());

    for (kind, nodes, p, g) in mesh.cells() {
        if kind.dim() != 3 {
            continue;
        }
        if kind != CellKind::Tetra {
            counts.other_volume_cells += 1;
            continue;
        }
        counts.tetrahedra += 1;
        let cs = [0, 1, 2, 3].map(|i| nodes[i] as usize);
        if !cs.iter().all(|&v| finite(v)) {
            counts.degenerate += 1;
            continue;
        }
        let s = cs.map(|v| side(mesh.points[v][k], c));
        let on: Vec<usize> = (0..4).filter(|&i| s[i] == Side::On).map(|i| cs[i]).collect();
        let tag = cell_tag(p, g);
        let polygon = match on.len() {
            4 => {
                counts.degenerate += 1;
                continue;
            }
            3 => {
                let mut key = [on[0], on[1], on[2]];
                key.sort_unstable();
                if in_plane.insert(key, ()).is_some() {
                    continue;
                }
                counts.faces_in_plane += 1;
                key.map(Origin::Vertex).to_vec()
            }
            _ => match tet_polygon(cs, s) {
                Some(poly) => poly,
                None => continue,
            },
        };
        let mut ids: Vec<usize> = polygon.into_iter().map(|o| pts.get(o)).collect();
        let corners: Vec<[f64; 2]> = ids.iter().map(|&i| pts.uv[i]).collect();
        let a = twice_area(&corners);
        if a == 0.0 {
            counts.zero_area += 1;
            continue;
        }
        if a < 0.0 {
            ids.reverse();
        }
        area += 0.5 * a.abs();
        let block = if ids.len() == 3 { &mut tris } else { &mut quads };
        block.nodes.extend(ids.iter().map(|&i| i as NodeIndex));
        block.physical.push(tag);
        block.geometrical.push(tag);
    }
    counts.triangles = tris.len();
    counts.quads = quads.len();
    let lines = traces(mesh, &mut pts, plane);
    counts.trace_segments = lines.len();

    let Points { origins, uv, .. } = pts;
    let restricted = metric.map(|m| restrict_all(mesh, m, &origins, plane));
    let mut out = TaggedMesh::new();
    out.points = uv.iter().map(|p| [p[0], p[1], 0.0]).collect();
    for ((dim, tag), name) in &mesh.tag_names {
        if *dim >= 2 {
            out.tag_names.insert((dim - 1, *tag), name.clone());
        }
    }
    out.blocks = [tris, quads, lines].into_iter().filter(|b| !b.is_empty()).collect();
    Section { mesh: out, metric: restricted, counts, area }
}

/// The traces of `mesh`'s triangles in the plane: line cells tagged by surface, each
/// segment once per tag.
fn traces(mesh: &TaggedMesh, pts: &mut Points<'_>, plane: CutPlane) -> CellBlock {
    let (k, c) = (plane.axis.index(), plane.value);
    let mut seen: BTreeMap<(i32, usize, usize), ()> = BTreeMap::new();
    let mut lines = CellBlock::new(CellKind::Line);
    let mut push = |tag: i32, a: usize, b: usize, lines: &mut CellBlock| {
        if a != b && seen.insert((tag, a.min(b), a.max(b)), ()).is_none() {
            lines.nodes.extend([a as NodeIndex, b as NodeIndex]);
            lines.physical.push(tag);
            lines.geometrical.push(tag);
        }
    };
    // Edges of triangles lying in the plane, per tag, with how many such triangles have
    // each, for their patches' boundaries (pushed after, in key order).
    let mut flat_edges: BTreeMap<(i32, usize, usize), u32> = BTreeMap::new();
    for (kind, nodes, p, g) in mesh.cells() {
        if kind != CellKind::Triangle {
            continue;
        }
        let cs = [0, 1, 2].map(|i| nodes[i] as usize);
        if !cs.iter().all(|&v| mesh.points[v].iter().all(|x| x.is_finite())) {
            continue;
        }
        let tag = cell_tag(p, g);
        let s = cs.map(|v| side(mesh.points[v][k], c));
        let on: Vec<usize> = (0..3).filter(|&i| s[i] == Side::On).collect();
        match on.len() {
            3 => {
                for i in 0..3 {
                    let (a, b) = (cs[i], cs[(i + 1) % 3]);
                    *flat_edges.entry((tag, a.min(b), a.max(b))).or_insert(0) += 1;
                }
            }
            2 => {
                let (a, b) = (pts.vertex(cs[on[0]]), pts.vertex(cs[on[1]]));
                push(tag, a, b, &mut lines);
            }
            1 => {
                let (i, j) = ((on[0] + 1) % 3, (on[0] + 2) % 3);
                if s[i] != s[j] {
                    let (a, b) = (pts.vertex(cs[on[0]]), pts.edge(cs[i], cs[j]));
                    push(tag, a, b, &mut lines);
                }
            }
            _ => {
                // The corner alone on its side and the two edges from it.
                let lone = (0..3).find(|&i| s[i] != s[(i + 1) % 3] && s[i] != s[(i + 2) % 3]);
                if let Some(i) = lone {
                    let (j, l) = ((i + 1) % 3, (i + 2) % 3);
                    let (a, b) = (pts.edge(cs[i], cs[j]), pts.edge(cs[i], cs[l]));
                    push(tag, a, b, &mut lines);
                }
            }
        }
    }
    for ((tag, a, b), n) in flat_edges {
        if n == 1 {
            let (a, b) = (pts.vertex(a), pts.vertex(b));
            push(tag, a, b, &mut lines);
        }
    }
    lines
}

/// The restriction to the plane of the metric at each point of the cut: at an edge
/// crossing, the Log-Euclidean mean of the ends' metrics; at a vertex, its own.
fn restrict_all(mesh: &TaggedMesh, m: &[Sym3], origins: &[Origin], plane: CutPlane) -> Vec<Sym2> {
    let mut logs: BTreeMap<usize, Sym3> = BTreeMap::new();
    let mut log = |v: usize| *logs.entry(v).or_insert_with(|| log_spd3(&m[v]));
    origins
        .iter()
        .map(|o| {
            let full = match *o {
                Origin::Vertex(v) => m[v],
                Origin::Edge(a, b) => {
                    let t = crossing(mesh.points[a], mesh.points[b], plane);
                    let (la, lb) = (log(a), log(b));
                    log_euclidean3(&[1.0 - t, t], &[&la, &lb])
                }
            };
            restrict(&full, plane.axis)
        })
        .collect()
}

/// The restriction of `m` to the plane normal to `axis`: the 2×2 block of the plane's
/// axes (in [`Axis::in_plane`] order), so that uᵀ M u is unchanged for every u in the
/// plane.
pub(crate) fn restrict(m: &Sym3, axis: Axis) -> Sym2 {
    let r = m.rows();
    let [i, j] = axis.in_plane();
    Sym2::new(r[i][i], r[i][j], r[j][j])
}
