//! The mesh as picture layers: faces filled by tag, edges drawn thin, topological curves
//! coloured by tag, in any [`View`].
//!
//! Sizes stay sane for meshes of millions of triangles: a face is filled as the outline
//! of its boundary loops (one even-odd path, O(boundary) long) rather than triangle by
//! triangle, and edges shorter than [`MIN_EDGE_PX`] on screen are not drawn one by one:
//! their length is summed on a grid of [`DENSITY_CELL_PX`]-pixel cells, and each cell is
//! shaded with the ink those edges would have put there (up to [`MAX_SHADING`]). The SVG
//! then grows with the picture's pixel count, not with the mesh.

use crate::topology::Topology;

use super::palette;
use super::svg::{num, PathData, Svg};
use super::view::{Rect, View};

/// Edges shorter than this many pixels are drawn as shading.
pub(super) const MIN_EDGE_PX: f64 = 2.0;
/// Side of the shading cells, in pixels.
pub(super) const DENSITY_CELL_PX: f64 = 2.0;
/// Opacity of the darkest shading: where edges would cover a cell wholly, the face's
/// colour still shows through, so that a dense region reads as dense rather than black.
pub(super) const MAX_SHADING: f64 = 0.5;
/// Levels of shading, from a quarter of [`MAX_SHADING`] to all of it.
pub(super) const SHADING_LEVELS: usize = 4;

/// The mesh prepared for drawing: coordinates, face outlines, edges and curves.
#[derive(Debug, Clone)]
pub(super) struct MeshLayers {
    /// Vertex coordinates (x, y).
    pub points: Vec<[f64; 2]>,
    /// Per topological face, its boundary loops (vertex indices).
    pub face_loops: Vec<Vec<Vec<usize>>>,
    /// Every mesh edge once.
    pub edges: Vec<[usize; 2]>,
    /// Per topological curve, its polylines: vertices and whether closed.
    pub curves: Vec<Vec<(Vec<usize>, bool)>>,
    /// The tagged topological points: their index in the topology and their vertex.
    pub points_0d: Vec<(usize, usize)>,
}

/// How many edges a panel drew, and how many it shaded.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct EdgeStats {
    /// Edges drawn as lines.
    pub drawn: usize,
    /// Edges too short on screen, drawn as shading.
    pub shaded: usize,
}

/// The boundary loops of a set of cells: the edges used an odd number of times, chained
/// into closed vertex loops (each loop a cycle; pinch points are passed through).
pub(super) fn boundary_loops<'a>(cells: impl Iterator<Item = &'a [usize]>) -> Vec<Vec<usize>> {
    let mut all: Vec<[usize; 2]> = Vec::new();
    for c in cells {
        for i in 0..c.len() {
            let (a, b) = (c[i], c[(i + 1) % c.len()]);
            all.push([a.min(b), a.max(b)]);
        }
    }
    all.sort_unstable();
    let mut bnd: Vec<[usize; 2]> = Vec::new();
    let mut i = 0;
    while i < all.len() {
        let mut j = i;
        while j < all.len() && all[j] == all[i] {
            j += 1;
        }
        if (j - i) % 2 == 1 {
            bnd.push(all[i]);
        }
        i = j;
    }
    let mut inc: Vec<(usize, usize)> =
        bnd.iter().enumerate().flat_map(|(k, e)| [(e[0], k), (e[1], k)]).collect();
    inc.sort_unstable();
    let mut used = vec![false; bnd.len()];
    let mut loops = Vec::new();
    for start in 0..bnd.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let [first, mut cur] = bnd[start];
        let mut lp = vec![first];
        while cur != first {
            lp.push(cur);
            let from = inc.partition_point(|&(v, _)| v < cur);
            let next = inc[from..]
                .iter()
                .take_while(|&&(v, _)| v == cur)
                .map(|&(_, k)| k)
                .find(|&k| !used[k]);
            match next {
                Some(k) => {
                    used[k] = true;
                    cur = if bnd[k][0] == cur { bnd[k][1] } else { bnd[k][0] };
                }
                None => break,
            }
        }
        loops.push(lp);
    }
    loops
}

impl MeshLayers {
    /// Prepares `topology`'s mesh, whose vertices are `points`.
    pub(super) fn new(topology: &Topology, points: Vec<[f64; 2]>) -> MeshLayers {
        let face_loops = (0..topology.faces.len())
            .map(|f| {
                boundary_loops(
                    topology.faces[f].cells.iter().map(|&c| topology.surface_cells[c].vertices()),
                )
            })
            .collect();
        let edges = topology.edges.iter().map(|(e, _)| *e).collect();
        let curves = topology
            .curves
            .iter()
            .map(|c| c.polylines.iter().map(|p| (p.vertices.clone(), p.closed)).collect())
            .collect();
        let points_0d = topology
            .points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.tag.is_some() && p.vertex < points.len())
            .map(|(i, p)| (i, p.vertex))
            .collect();
        MeshLayers { points, face_loops, edges, curves, points_0d }
    }

    /// The bounding box of the vertices that faces or curves use.
    pub(super) fn bounds(&self) -> Option<Rect> {
        let used = self
            .face_loops
            .iter()
            .flatten()
            .flatten()
            .chain(self.curves.iter().flatten().flat_map(|(v, _)| v.iter()));
        Rect::bounding(used.map(|&v| self.points[v]))
    }

    /// One even-odd filled path per face, coloured by the face's index.
    pub(super) fn draw_faces(&self, svg: &mut Svg, view: &View) {
        for (f, loops) in self.face_loops.iter().enumerate() {
            let mut d = PathData::new(1);
            for lp in loops {
                for (i, &v) in lp.iter().enumerate() {
                    let p = view.to_px(self.points[v]);
                    if i == 0 {
                        d.move_to(p);
                    } else {
                        d.line_to(p);
                    }
                }
                d.close();
            }
            if !d.is_empty() {
                let class = format!("face face-{f}");
                svg.element(
                    "path",
                    &[
                        ("class", &class),
                        ("d", d.as_str()),
                        ("fill", palette::face(f)),
                        ("fill-rule", "evenodd"),
                        ("stroke", "none"),
                    ],
                );
            }
        }
    }

    /// Edges inside the view: long ones as one path, short ones as shading.
    pub(super) fn draw_edges(&self, svg: &mut Svg, view: &View, stroke_px: f64) -> EdgeStats {
        let mut stats = EdgeStats::default();
        let mut d = PathData::new(1);
        let s = view.screen;
        let cols = (s.width() / DENSITY_CELL_PX).ceil().max(1.0) as usize;
        let rows = (s.height() / DENSITY_CELL_PX).ceil().max(1.0) as usize;
        let mut ink = vec![0f64; cols * rows];
        for &[a, b] in &self.edges {
            let (pa, pb) = (view.to_px(self.points[a]), view.to_px(self.points[b]));
            let bb = Rect::new(pa[0], pa[1], pb[0], pb[1]);
            if bb.intersect(&s).is_none() {
                continue;
            }
            let len = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
            if len >= MIN_EDGE_PX {
                d.move_to(pa);
                d.line_to(pb);
                stats.drawn += 1;
            } else {
                let m = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
                if s.contains(m) {
                    let c = (((m[0] - s.x0) / DENSITY_CELL_PX) as usize).min(cols - 1);
                    let r = (((m[1] - s.y0) / DENSITY_CELL_PX) as usize).min(rows - 1);
                    ink[r * cols + c] += len * stroke_px;
                }
                stats.shaded += 1;
            }
        }
        let sw = num(stroke_px, 2);
        if !d.is_empty() {
            svg.element(
                "path",
                &[
                    ("class", "edges"),
                    ("d", d.as_str()),
                    ("fill", "none"),
                    ("stroke", palette::EDGE),
                    ("stroke-width", &sw),
                    ("stroke-linecap", "round"),
                ],
            );
        }
        if stats.shaded > 0 {
            // The levels of shading, each one path of row runs.
            const LEVELS: usize = SHADING_LEVELS;
            let area = DENSITY_CELL_PX * DENSITY_CELL_PX;
            let mut paths: Vec<PathData> = (0..LEVELS).map(|_| PathData::new(1)).collect();
            for r in 0..rows {
                let mut c = 0;
                while c < cols {
                    let level = |c: usize| {
                        let cover = (ink[r * cols + c] / area).min(1.0);
                        if cover <= 0.0 {
                            0
                        } else {
                            ((cover * LEVELS as f64).ceil() as usize).clamp(1, LEVELS)
                        }
                    };
                    let l = level(c);
                    let mut e = c + 1;
                    while e < cols && level(e) == l {
                        e += 1;
                    }
                    if l > 0 {
                        let x = s.x0 + c as f64 * DENSITY_CELL_PX;
                        let y = s.y0 + r as f64 * DENSITY_CELL_PX;
                        paths[l - 1].rect(x, y, (e - c) as f64 * DENSITY_CELL_PX, DENSITY_CELL_PX);
                    }
                    c = e;
                }
            }
            for (l, p) in paths.iter().enumerate() {
                if !p.is_empty() {
                    let op = num(MAX_SHADING * (l + 1) as f64 / LEVELS as f64, 3);
                    svg.element(
                        "path",
                        &[
                            ("class", "edge-shading"),
                            ("d", p.as_str()),
                            ("fill", palette::EDGE),
                            ("fill-opacity", &op),
                            ("stroke", "none"),
                        ],
                    );
                }
            }
        }
        stats
    }

    /// Whether some edge is shorter than [`MIN_EDGE_PX`] at `scale` pixels per unit, so
    /// that a view of the whole mesh at that scale shades it.
    pub(super) fn has_short_edges(&self, scale: f64) -> bool {
        self.edges.iter().any(|&[a, b]| {
            let (p, q) = (self.points[a], self.points[b]);
            (p[0] - q[0]).hypot(p[1] - q[1]) * scale < MIN_EDGE_PX
        })
    }

    /// The tagged topological points as diamonds of half-diagonal `r` pixels, coloured by
    /// the point's index (the legend's markers).
    pub(super) fn draw_points(&self, svg: &mut Svg, view: &View, r: f64) {
        let reach = view.screen.inflate(r);
        for &(i, v) in &self.points_0d {
            let [x, y] = view.to_px(self.points[v]);
            if !reach.contains([x, y]) {
                continue;
            }
            let class = format!("topo-point topo-point-{i}");
            svg.element(
                "path",
                &[
                    ("class", &class),
                    ("d", &super::legend::diamond(x, y, r)),
                    ("fill", palette::point(i)),
                    ("stroke", "#000"),
                    ("stroke-width", "0.8"),
                ],
            );
        }
    }

    /// The topological curves, one path per curve, coloured by the curve's index; points
    /// closer than half a pixel to the previous one kept are skipped.
    pub(super) fn draw_curves(&self, svg: &mut Svg, view: &View, width_px: f64) {
        let w = num(width_px, 2);
        for (ci, pieces) in self.curves.iter().enumerate() {
            let mut d = PathData::new(1);
            for (verts, closed) in pieces {
                let mut last: Option<[f64; 2]> = None;
                for (i, &v) in verts.iter().enumerate() {
                    let p = view.to_px(self.points[v]);
                    match last {
                        None => d.move_to(p),
                        Some(q)
                            if i + 1 < verts.len() && (p[0] - q[0]).hypot(p[1] - q[1]) < 0.5 =>
                        {
                            continue
                        }
                        Some(_) => d.line_to(p),
                    }
                    last = Some(p);
                }
                if *closed {
                    d.close();
                }
            }
            if !d.is_empty() {
                let class = format!("curve curve-{ci}");
                svg.element(
                    "path",
                    &[
                        ("class", &class),
                        ("d", d.as_str()),
                        ("fill", "none"),
                        ("stroke", palette::curve(ci)),
                        ("stroke-width", &w),
                        ("stroke-linejoin", "round"),
                        ("stroke-linecap", "round"),
                    ],
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_triangles_have_one_square_loop() {
        let cells: Vec<Vec<usize>> = vec![vec![0, 1, 2], vec![0, 2, 3]];
        let loops = boundary_loops(cells.iter().map(|c| c.as_slice()));
        assert_eq!(loops.len(), 1);
        let mut l = loops[0].clone();
        l.sort_unstable();
        assert_eq!(l, vec![0, 1, 2, 3]);
    }

    #[test]
    fn an_annulus_has_two_loops() {
        // A square ring of 8 quads around a hole: outer 0..8, inner 8..16 (3x3 grid of
        // 4x4 vertices with the centre cell missing).
        let id = |i: usize, j: usize| j * 4 + i;
        let mut cells = Vec::new();
        for j in 0..3 {
            for i in 0..3 {
                if (i, j) != (1, 1) {
                    cells.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
        let loops = boundary_loops(cells.iter().map(|c| c.as_slice()));
        let mut sizes: Vec<usize> = loops.iter().map(Vec::len).collect();
        sizes.sort_unstable();
        assert_eq!(sizes, vec![4, 12]);
    }
}
