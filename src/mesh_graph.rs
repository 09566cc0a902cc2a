//! The mesh as a graph for neighbour propagation (thesis 2.2.5, 4.3.1.3): vertex
//! adjacency in compressed sparse row form, 2D coordinates, the corners of the surface
//! cells, and for each vertex the length of its longest incident mesh edge; and, built
//! from a mesh, its point-data arrays (scalars by value), for the algorithms that size
//! from a computed field.
//!
//! Built from [`Topology::edges`] (every mesh edge once, sorted) so that the neighbour
//! lists, and so every propagation order, are deterministic: each list is sorted by
//! vertex index. Cost: O(vertices + edges) time and memory; indices are `u32`.

use std::collections::BTreeMap;

use smartmesh_formats::TaggedMesh;

use crate::geometry::Point2;
use crate::topology::Topology;

/// Marks the missing fourth corner of a triangle in [`MeshGraph::cells`].
pub(crate) const NO_CORNER: u32 = u32::MAX;

/// Why a graph could not be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MeshGraphError {
    /// An edge or cell names a vertex the coordinates do not have. Check that the
    /// edges and cells come from the same mesh as the coordinates.
    #[error("vertex {index} is out of range: the mesh has {len} vertices")]
    VertexOutOfRange {
        /// The index found.
        index: usize,
        /// The number of vertices.
        len: usize,
    },
    /// More vertices or adjacency entries than `u32` indices can address.
    #[error("the mesh is too large for 32-bit vertex indices ({0} entries)")]
    TooLarge(usize),
}

/// Vertex adjacency of a 2D mesh in CSR form.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshGraph {
    coords: Vec<Point2>,
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    longest_edge: Vec<f64>,
    cells: Vec<[u32; 4]>,
    /// Connected component of each vertex, numbered from 0 in the order of their
    /// smallest vertex.
    component: Vec<u32>,
    /// Number of connected components.
    num_components: usize,
    /// Box of the coordinates as `f64::min` and `max` fold them (a NaN is skipped),
    /// `None` without vertices.
    extent: Option<(Point2, Point2)>,
    /// Whether every coordinate is finite.
    finite: bool,
    /// The cells of a grid over the bounding box that hold a vertex.
    occupied: Vec<(Point2, Point2)>,
    /// The mesh's point-data arrays, by name.
    point_data: BTreeMap<String, PointValues>,
}

/// A point-data array of the mesh a graph was built from.
#[derive(Debug, Clone, PartialEq)]
pub enum PointValues {
    /// One value per vertex.
    Scalar(Vec<f64>),
    /// Anything else: its components per item and its items.
    Other {
        /// Components per item.
        components: usize,
        /// Items.
        items: usize,
    },
}

impl MeshGraph {
    /// The graph of `mesh`, with the edges and cells its `topology` found. Coordinates
    /// are the x and y of the mesh points.
    pub fn from_topology(
        topology: &Topology,
        mesh: &TaggedMesh,
    ) -> Result<MeshGraph, MeshGraphError> {
        let coords: Vec<Point2> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
        let edges: Vec<[usize; 2]> = topology.edges.iter().map(|e| e.0).collect();
        let cells: Vec<[usize; 4]> = topology.surface_cells.iter().map(|c| c.corners).collect();
        let mut graph = MeshGraph::from_edges(coords, &edges, &cells)?;
        graph.point_data = mesh
            .point_data
            .iter()
            .map(|(name, a)| {
                let values = if a.components == 1 && a.covers(mesh.points.len()) {
                    PointValues::Scalar(a.values.clone())
                } else {
                    PointValues::Other { components: a.components, items: a.len() }
                };
                (name.clone(), values)
            })
            .collect();
        Ok(graph)
    }

    /// The graph of vertices `coords` joined by `edges`; `cells` are the surface cells
    /// (four corners, the fourth `usize::MAX` for a triangle), used to find the cells a
    /// free polyline crosses. Repeated edges and loops are dropped.
    pub fn from_edges(
        coords: Vec<Point2>,
        edges: &[[usize; 2]],
        cells: &[[usize; 4]],
    ) -> Result<MeshGraph, MeshGraphError> {
        let n = coords.len();
        if n >= u32::MAX as usize || 2 * edges.len() >= u32::MAX as usize {
            return Err(MeshGraphError::TooLarge(n.max(2 * edges.len())));
        }
        let check = |v: usize| {
            if v < n {
                Ok(())
            } else {
                Err(MeshGraphError::VertexOutOfRange { index: v, len: n })
            }
        };
        let mut degree = vec![0u32; n + 1];
        for &[a, b] in edges {
            check(a)?;
            check(b)?;
            if a != b {
                degree[a] += 1;
                degree[b] += 1;
            }
        }
        let mut offsets = vec![0u32; n + 1];
        for v in 0..n {
            offsets[v + 1] = offsets[v] + degree[v];
        }
        let mut fill: Vec<u32> = offsets[..n].to_vec();
        let mut neighbours = vec![0u32; offsets[n] as usize];
        for &[a, b] in edges {
            if a != b {
                neighbours[fill[a] as usize] = b as u32;
                fill[a] += 1;
                neighbours[fill[b] as usize] = a as u32;
                fill[b] += 1;
            }
        }
        // Sort and deduplicate each list, compacting in place.
        let mut write = 0usize;
        let mut new_offsets = vec![0u32; n + 1];
        for v in 0..n {
            let (s, e) = (offsets[v] as usize, offsets[v + 1] as usize);
            neighbours[s..e].sort_unstable();
            let start = write;
            for i in s..e {
                if write == start || neighbours[write - 1] != neighbours[i] {
                    neighbours[write] = neighbours[i];
                    write += 1;
                }
            }
            new_offsets[v + 1] = write as u32;
        }
        neighbours.truncate(write);
        let longest_edge = (0..n)
            .map(|v| {
                let p = coords[v];
                neighbours[new_offsets[v] as usize..new_offsets[v + 1] as usize]
                    .iter()
                    .map(|&u| {
                        let q = coords[u as usize];
                        ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt()
                    })
                    .fold(0.0, f64::max)
            })
            .collect();
        let mut out_cells = Vec::with_capacity(cells.len());
        for c in cells {
            let mut k = [NO_CORNER; 4];
            for (i, &v) in c.iter().enumerate() {
                if v != usize::MAX {
                    check(v)?;
                    k[i] = v as u32;
                }
            }
            out_cells.push(k);
        }
        let (component, num_components) = components(&new_offsets, &neighbours);
        let (extent, finite) = extent(&coords);
        let occupied =
            extent.filter(|_| finite).map_or_else(Vec::new, |b| occupied_cells(&coords, b));
        Ok(MeshGraph {
            coords,
            offsets: new_offsets,
            neighbours,
            longest_edge,
            cells: out_cells,
            component,
            num_components,
            extent,
            finite,
            occupied,
            point_data: BTreeMap::new(),
        })
    }

    /// The point-data arrays of the mesh the graph was built from (none for a graph
    /// built from edges).
    pub fn point_data(&self) -> &BTreeMap<String, PointValues> {
        &self.point_data
    }

    /// Number of vertices.
    pub fn num_vertices(&self) -> usize {
        self.coords.len()
    }

    /// Number of edges (each counted once).
    pub fn num_edges(&self) -> usize {
        self.neighbours.len() / 2
    }

    /// Coordinates of vertex `v`.
    #[inline]
    pub fn point(&self, v: usize) -> Point2 {
        self.coords[v]
    }

    /// All coordinates.
    pub fn points(&self) -> &[Point2] {
        &self.coords
    }

    /// Neighbours of vertex `v`, sorted by index.
    #[inline]
    pub fn neighbours(&self, v: usize) -> &[u32] {
        &self.neighbours[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }

    /// Length of the longest mesh edge at `v` (0 for an isolated vertex): no point of
    /// a cell incident to `v` is farther from `v` than this.
    #[inline]
    pub fn longest_edge(&self, v: usize) -> f64 {
        self.longest_edge[v]
    }

    /// Surface cells by their corners (`NO_CORNER` fourth corner for a triangle).
    pub fn cells(&self) -> &[[u32; 4]] {
        &self.cells
    }

    /// The connected component of vertex `v` (components are numbered from 0 in the
    /// order of their smallest vertex).
    #[inline]
    pub fn component(&self, v: usize) -> usize {
        self.component[v] as usize
    }

    /// Number of connected components (0 for a graph without vertices).
    pub fn num_components(&self) -> usize {
        self.num_components
    }

    /// The bounding box of the vertices, `(lo, hi)`: `None` for a graph without
    /// vertices or with a non-finite coordinate.
    pub fn bounds(&self) -> Option<(Point2, Point2)> {
        self.extent.filter(|_| self.finite)
    }

    /// The box of the vertices as `f64::min` and `max` fold the coordinates: a NaN
    /// coordinate is skipped, an infinite one kept. `None` for a graph without
    /// vertices. [`MeshGraph::bounds`] when every coordinate is finite.
    pub fn extent(&self) -> Option<(Point2, Point2)> {
        self.extent
    }

    /// Closed boxes `(lo, hi)` that together hold every vertex: the cells of a grid
    /// over the bounding box (about 64 vertices a cell, at most 64 × 64 cells) that
    /// hold a vertex, grown a little for rounding. Empty without a bounding box.
    pub fn occupied_cells(&self) -> &[(Point2, Point2)] {
        &self.occupied
    }

    /// Iterator over the edges `[a, b]`, `a < b`, in increasing order.
    pub fn edges(&self) -> impl Iterator<Item = [u32; 2]> + '_ {
        (0..self.coords.len()).flat_map(move |a| {
            self.neighbours(a).iter().filter(move |&&b| b as usize > a).map(move |&b| [a as u32, b])
        })
    }
}

/// The box of `coords` as `f64::min` and `max` fold them (`None` without a point), and
/// whether every coordinate is finite: one pass for both.
fn extent(coords: &[Point2]) -> (Option<(Point2, Point2)>, bool) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut finite = true;
    for p in coords {
        finite &= p[0].is_finite() && p[1].is_finite();
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    ((!coords.is_empty()).then_some((lo, hi)), finite)
}

/// Most cells along a side of the grid of [`MeshGraph::occupied_cells`].
const OCCUPANCY_GRID: usize = 64;

/// The cells of a `g × g` grid over `bounds` that hold a point of `coords` (`g` such that
/// a cell holds about 64 points on average, at most [`OCCUPANCY_GRID`]), each grown by
/// a millionth of the box on every side, so that a point that rounding puts in the
/// next cell still lies in the one it was counted in.
fn occupied_cells(coords: &[Point2], (lo, hi): (Point2, Point2)) -> Vec<(Point2, Point2)> {
    let g = ((coords.len() as f64).sqrt() / 8.0).clamp(1.0, OCCUPANCY_GRID as f64) as usize;
    let size = [hi[0] - lo[0], hi[1] - lo[1]];
    let cell = |k: usize, x: f64| {
        if size[k] > 0.0 {
            (((x - lo[k]) / size[k] * g as f64) as usize).min(g - 1)
        } else {
            0
        }
    };
    let mut hit = vec![false; g * g];
    for p in coords {
        hit[cell(1, p[1]) * g + cell(0, p[0])] = true;
    }
    let grow = [1e-6 * size[0] + f64::MIN_POSITIVE, 1e-6 * size[1] + f64::MIN_POSITIVE];
    let edge = |k: usize, i: usize| lo[k] + size[k] * (i as f64 / g as f64);
    (0..g * g)
        .filter(|&c| hit[c])
        .map(|c| {
            let (i, j) = (c % g, c / g);
            (
                [edge(0, i) - grow[0], edge(1, j) - grow[1]],
                [edge(0, i + 1) + grow[0], edge(1, j + 1) + grow[1]],
            )
        })
        .collect()
}

/// The connected components of a CSR graph: a label per vertex, and their number. One
/// breadth-first sweep from each vertex not yet labelled, in vertex order.
fn components(offsets: &[u32], neighbours: &[u32]) -> (Vec<u32>, usize) {
    let n = offsets.len().saturating_sub(1);
    let mut label = vec![u32::MAX; n];
    let mut queue: Vec<u32> = Vec::new();
    let mut count = 0u32;
    for start in 0..n {
        if label[start] != u32::MAX {
            continue;
        }
        label[start] = count;
        queue.clear();
        queue.push(start as u32);
        let mut head = 0;
        while head < queue.len() {
            let v = queue[head] as usize;
            head += 1;
            for &u in &neighbours[offsets[v] as usize..offsets[v + 1] as usize] {
                if label[u as usize] == u32::MAX {
                    label[u as usize] = count;
                    queue.push(u);
                }
            }
        }
        count += 1;
    }
    (label, count as usize)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_support::Rng;

    #[test]
    fn csr_is_sorted_and_deduplicated() {
        let coords = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let edges = [[2, 0], [0, 1], [1, 2], [0, 2], [2, 3], [3, 0], [3, 3]];
        let g =
            MeshGraph::from_edges(coords, &edges, &[[0, 1, 2, usize::MAX], [0, 2, 3, usize::MAX]])
                .unwrap();
        assert_eq!(g.neighbours(0), &[1, 2, 3]);
        assert_eq!(g.neighbours(2), &[0, 1, 3]);
        assert_eq!(g.num_edges(), 5);
        assert_eq!(g.edges().collect::<Vec<_>>(), vec![[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]);
        assert!((g.longest_edge(0) - 2f64.sqrt()).abs() < 1e-15);
        assert_eq!(g.longest_edge(1), 1.0);
        assert_eq!(g.cells()[1], [0, 2, 3, NO_CORNER]);
        assert_eq!(g.bounds(), Some(([0.0, 0.0], [1.0, 1.0])));
        let with_nan = MeshGraph::from_edges(vec![[0.0, 0.0], [f64::NAN, 1.0]], &[], &[]).unwrap();
        assert_eq!(with_nan.bounds(), None);
        assert_eq!(with_nan.extent(), Some(([0.0, 0.0], [0.0, 1.0])));
        assert_eq!(MeshGraph::from_edges(vec![], &[], &[]).unwrap().bounds(), None);
        assert_eq!(MeshGraph::from_edges(vec![], &[], &[]).unwrap().extent(), None);
    }

    /// Every vertex lies in an occupied cell, and every occupied cell holds a vertex, on
    /// random point sets (flat ones included), up to a grid of 64 × 64.
    #[test]
    fn occupied_cells_hold_every_vertex() {
        let mut rng = Rng(3);
        let mut unit = || rng.unit();
        for case in 0..30 {
            let n = [1, 10, 1000, 40_000][case % 4];
            let flat = case % 5 == 0;
            let coords: Vec<Point2> = (0..n)
                .map(|_| [1e3 + unit().powi(3) * 7.0, if flat { 2.0 } else { -unit() * 0.01 }])
                .collect();
            let g = MeshGraph::from_edges(coords.clone(), &[], &[]).unwrap();
            let cells = g.occupied_cells();
            assert!(cells.len() <= OCCUPANCY_GRID * OCCUPANCY_GRID);
            let inside = |p: &Point2, c: &(Point2, Point2)| {
                c.0[0] <= p[0] && p[0] <= c.1[0] && c.0[1] <= p[1] && p[1] <= c.1[1]
            };
            for p in &coords {
                assert!(cells.iter().any(|c| inside(p, c)), "case {case}: {p:?} in no cell");
            }
            for c in cells {
                assert!(coords.iter().any(|p| inside(p, c)), "case {case}: empty cell {c:?}");
            }
        }
        // The grid's cap: 300 000 points spread over the square fill 64 × 64 cells.
        let coords: Vec<Point2> =
            (0..300_000).map(|k| [(k % 547) as f64, (k / 547) as f64]).collect();
        assert_eq!(
            MeshGraph::from_edges(coords, &[], &[]).unwrap().occupied_cells().len(),
            OCCUPANCY_GRID * OCCUPANCY_GRID
        );
    }

    /// Components against a union-find twin on random sparse graphs, isolated
    /// vertices included.
    #[test]
    fn components_agree_with_union_find() {
        let mut rng = Rng(7);
        let mut next = |m: usize| ((rng.unit() * m as f64) as usize).min(m - 1);
        for case in 0..50 {
            let n = 1 + next(200);
            let edges: Vec<[usize; 2]> =
                (0..next(n + 1) * (case % 3)).map(|_| [next(n), next(n)]).collect();
            let g = MeshGraph::from_edges(vec![[0.0, 0.0]; n], &edges, &[]).unwrap();
            let mut root: Vec<usize> = (0..n).collect();
            fn find(root: &mut [usize], mut v: usize) -> usize {
                while root[v] != v {
                    v = root[v];
                }
                v
            }
            for e in &edges {
                let (a, b) = (find(&mut root, e[0]), find(&mut root, e[1]));
                root[a.max(b)] = a.min(b);
            }
            let mut seen = std::collections::BTreeSet::new();
            for v in 0..n {
                seen.insert(find(&mut root, v));
                for u in 0..n {
                    assert_eq!(
                        g.component(u) == g.component(v),
                        find(&mut root, u) == find(&mut root, v),
                        "case {case}: {u} and {v}"
                    );
                }
            }
            assert_eq!(g.num_components(), seen.len());
            // Numbered in the order of their smallest vertex.
            let firsts: Vec<usize> = (0..n)
                .filter(|&v| (0..v).all(|u| g.component(u) != g.component(v)))
                .map(|v| g.component(v))
                .collect();
            assert_eq!(firsts, (0..g.num_components()).collect::<Vec<_>>());
        }
    }

    #[test]
    fn out_of_range_is_an_error() {
        let e = MeshGraph::from_edges(vec![[0.0, 0.0]], &[[0, 4]], &[]).unwrap_err();
        assert_eq!(e, MeshGraphError::VertexOutOfRange { index: 4, len: 1 });
    }
}
