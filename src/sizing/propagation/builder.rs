//! Building a [`Source`]: pieces added one by one (topological curves and points,
//! paths of mesh vertices, free polylines and points given by coordinates), checked and
//! turned into segments, with the seed vertices a propagation starts from.
//!
//! Seeds: every mesh vertex of a mesh piece, and for free pieces the corners of every
//! cell (or edge, with no cell) they touch, so that a free polyline marks every cell it
//! crosses even where no vertex lies within reach. Each seed carries a segment it lies
//! on, when one is known, as the guess of its exact search. Seeds are sorted and
//! unique. Errors are found at [`SourceBuilder::build`], in the order pieces were added.

use std::sync::OnceLock;

use super::source::{PieceKind, Source, SourcePolyline, SourceSegment};
use crate::geometry::segment::{point_in_polygon, segment_touches_polygon, segments_touch};
use crate::geometry::{Point2, SegmentGeom, SegmentIndex};
use crate::mesh_graph::{MeshGraph, NO_CORNER};
use crate::topology::Topology;

/// Why a source could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SourceError {
    /// A piece names a mesh vertex the mesh does not have. Check that the source and
    /// the graph come from the same mesh.
    #[error("source piece {piece}: vertex {vertex} is out of range (the mesh has {len} vertices)")]
    VertexOutOfRange {
        /// The piece, in the order pieces were added.
        piece: usize,
        /// The vertex index.
        vertex: usize,
        /// Number of mesh vertices.
        len: usize,
    },
    /// A topological curve or point index the topology does not have.
    #[error("source piece {piece}: topological {what} {index} does not exist ({len} known)")]
    EntityOutOfRange {
        /// The piece.
        piece: usize,
        /// "curve" or "point".
        what: &'static str,
        /// The index asked for.
        index: usize,
        /// How many there are.
        len: usize,
    },
    /// A piece with no point. Give at least one point (a point source) or two.
    #[error("source piece {piece} has no point")]
    EmptyPiece {
        /// The piece.
        piece: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("source piece {piece}: point {point} has a non-finite coordinate")]
    NonFinite {
        /// The piece.
        piece: usize,
        /// The point within the piece.
        point: usize,
    },
}

#[derive(Debug, Clone)]
enum Piece {
    Mesh { vertices: Vec<usize>, closed: bool },
    Free { points: Vec<Point2>, closed: bool },
    Error(SourceError),
}

/// Collects the pieces of a [`Source`] on one mesh; errors are reported by
/// [`SourceBuilder::build`].
#[derive(Debug, Clone)]
pub struct SourceBuilder<'g> {
    graph: &'g MeshGraph,
    pieces: Vec<Piece>,
}

impl<'g> SourceBuilder<'g> {
    /// A builder for sources on `graph`.
    pub fn new(graph: &'g MeshGraph) -> SourceBuilder<'g> {
        SourceBuilder { graph, pieces: Vec::new() }
    }

    /// A polyline along mesh vertices (consecutive vertices should share a mesh edge; a
    /// single vertex is a point source).
    pub fn mesh_polyline(&mut self, vertices: &[usize], closed: bool) -> &mut Self {
        self.pieces.push(Piece::Mesh { vertices: vertices.to_vec(), closed });
        self
    }

    /// Every polyline of topological curve `curve`, in its orientation.
    pub fn topology_curve(&mut self, topology: &Topology, curve: usize) -> &mut Self {
        match topology.curves.get(curve) {
            Some(c) => {
                for pl in &c.polylines {
                    self.mesh_polyline(&pl.vertices, pl.closed);
                }
            }
            None => {
                let e = SourceError::EntityOutOfRange {
                    piece: self.pieces.len(),
                    what: "curve",
                    index: curve,
                    len: topology.curves.len(),
                };
                self.pieces.push(Piece::Error(e));
            }
        }
        self
    }

    /// Topological point `point`, as a point source on its mesh vertex.
    pub fn topology_point(&mut self, topology: &Topology, point: usize) -> &mut Self {
        match topology.points.get(point) {
            Some(p) => self.mesh_polyline(&[p.vertex], false),
            None => {
                let e = SourceError::EntityOutOfRange {
                    piece: self.pieces.len(),
                    what: "point",
                    index: point,
                    len: topology.points.len(),
                };
                self.pieces.push(Piece::Error(e));
                self
            }
        }
    }

    /// Mesh vertex `v` as a point source.
    pub fn vertex(&mut self, v: usize) -> &mut Self {
        self.mesh_polyline(&[v], false)
    }

    /// A polyline given by coordinates, which need not follow mesh edges (thesis
    /// 4.3.6.5, the imaginary polyline).
    pub fn polyline(&mut self, points: &[Point2], closed: bool) -> &mut Self {
        self.pieces.push(Piece::Free { points: points.to_vec(), closed });
        self
    }

    /// A point given by coordinates.
    pub fn point(&mut self, p: Point2) -> &mut Self {
        self.polyline(&[p], false)
    }

    /// The source, with its segment index and seed vertices.
    pub fn build(&self) -> Result<Source, SourceError> {
        let n = self.graph.num_vertices();
        let mut segments = Vec::new();
        let mut polylines = Vec::new();
        let mut seeds: Vec<u32> = Vec::new();
        // (seed vertex, a segment it lies on) for the vertices of mesh pieces.
        let mut on_segment: Vec<(u32, u32)> = Vec::new();
        for (piece, pc) in self.pieces.iter().enumerate() {
            let (points, closed, kind): (Vec<Point2>, bool, PieceKind) = match pc {
                Piece::Error(e) => return Err(e.clone()),
                Piece::Mesh { vertices, closed } => {
                    let mut pts = Vec::with_capacity(vertices.len());
                    let first = segments.len() as u32;
                    let last = first
                        + (vertices.len().saturating_sub(if *closed && vertices.len() >= 2 {
                            0
                        } else {
                            1
                        }))
                        .max(1) as u32
                        - 1;
                    for (k, &v) in vertices.iter().enumerate() {
                        if v >= n {
                            return Err(SourceError::VertexOutOfRange { piece, vertex: v, len: n });
                        }
                        seeds.push(v as u32);
                        on_segment.push((v as u32, (first + k as u32).min(last)));
                        pts.push(self.graph.point(v));
                    }
                    let kind = if vertices.len() == 1 {
                        PieceKind::MeshVertex
                    } else {
                        PieceKind::MeshEdges
                    };
                    (pts, *closed, kind)
                }
                Piece::Free { points, closed } => {
                    if let Some(i) =
                        points.iter().position(|p| !(p[0].is_finite() && p[1].is_finite()))
                    {
                        return Err(SourceError::NonFinite { piece, point: i });
                    }
                    let kind =
                        if points.len() == 1 { PieceKind::FreePoint } else { PieceKind::Free };
                    (points.clone(), *closed, kind)
                }
            };
            if points.is_empty() {
                return Err(SourceError::EmptyPiece { piece });
            }
            let pl = polylines.len() as u32;
            let first = segments.len() as u32;
            let closed = closed && points.len() >= 2;
            let k = points.len();
            let count = if k == 1 {
                1
            } else if closed {
                k
            } else {
                k - 1
            };
            let mut s = 0.0;
            for i in 0..count {
                let a = points[i];
                let b = if k == 1 { a } else { points[(i + 1) % k] };
                let length = SegmentGeom::new(a, b).length();
                let id = first + i as u32;
                let prev = if i > 0 {
                    Some(id - 1)
                } else if closed {
                    Some(first + count as u32 - 1)
                } else {
                    None
                };
                let next = if i + 1 < count {
                    Some(id + 1)
                } else if closed {
                    Some(first)
                } else {
                    None
                };
                segments.push(SourceSegment {
                    a,
                    b,
                    polyline: pl,
                    prev,
                    next,
                    abscissa: s,
                    length,
                });
                s += length;
            }
            polylines.push(SourcePolyline {
                first_segment: first,
                num_segments: count as u32,
                closed,
                kind,
                length: s,
            });
        }
        let geoms: Vec<SegmentGeom> = segments.iter().map(|s| SegmentGeom::new(s.a, s.b)).collect();
        let bounds = SegmentIndex::bounds_of(&geoms);
        let unit_left = geoms
            .iter()
            .map(|g| {
                let l = g.length();
                [-g.d[1] / l, g.d[0] / l]
            })
            .collect();
        let mut source = Source {
            segments,
            geoms,
            polylines,
            seeds: Vec::new(),
            seed_guess: Vec::new(),
            index: OnceLock::new(),
            bounds,
            chain: OnceLock::new(),
            behind: Vec::new(),
            unit_left,
        };
        source.behind = (0..source.segments.len()).map(|s| source.window_sides_behind(s)).collect();
        seeds.extend(source.free_piece_seeds(self.graph));
        seeds.sort_unstable();
        seeds.dedup();
        // The smallest segment each seed lies on, as the guess of its exact search.
        on_segment.sort_unstable();
        on_segment.dedup_by_key(|e| e.0);
        let mut at = 0;
        source.seed_guess = seeds
            .iter()
            .map(|&v| {
                while at < on_segment.len() && on_segment[at].0 < v {
                    at += 1;
                }
                if at < on_segment.len() && on_segment[at].0 == v {
                    on_segment[at].1
                } else {
                    u32::MAX
                }
            })
            .collect();
        source.seeds = seeds;
        Ok(source)
    }
}

impl Source {
    /// Corners of every cell that a free piece touches (every edge when the graph has
    /// no cell). Near misses within a few ulps count: an extra seed costs one
    /// evaluation, a missing one could leave a crossed cell unmarked.
    pub(super) fn free_piece_seeds(&self, graph: &MeshGraph) -> Vec<u32> {
        let free: Vec<bool> = self
            .segments
            .iter()
            .map(|s| {
                matches!(
                    self.polylines[s.polyline as usize].kind,
                    PieceKind::Free | PieceKind::FreePoint
                )
            })
            .collect();
        let Some((mut lo, mut hi)) = free.iter().zip(&self.segments).filter(|(f, _)| **f).fold(
            None,
            |acc: Option<(Point2, Point2)>, (_, s)| {
                let (l, h) = acc.unwrap_or(([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]));
                Some((
                    [l[0].min(s.a[0]).min(s.b[0]), l[1].min(s.a[1]).min(s.b[1])],
                    [h[0].max(s.a[0]).max(s.b[0]), h[1].max(s.a[1]).max(s.b[1])],
                ))
            },
        ) else {
            return Vec::new();
        };
        let scale =
            lo[0].abs().max(lo[1].abs()).max(hi[0].abs()).max(hi[1].abs()).max(f64::MIN_POSITIVE);
        let tol = 64.0 * f64::EPSILON * scale;
        for k in 0..2 {
            lo[k] -= tol;
            hi[k] += tol;
        }
        let mut seeds = Vec::new();
        let mut corners: Vec<Point2> = Vec::with_capacity(4);
        let mut visit = |vs: &[u32], seeds: &mut Vec<u32>| {
            corners.clear();
            corners.extend(vs.iter().map(|&v| graph.point(v as usize)));
            let (mut cl, mut ch) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for c in &corners {
                for k in 0..2 {
                    cl[k] = cl[k].min(c[k] - tol);
                    ch[k] = ch[k].max(c[k] + tol);
                }
            }
            if cl[0] > hi[0] || ch[0] < lo[0] || cl[1] > hi[1] || ch[1] < lo[1] {
                return;
            }
            let mut hit = false;
            self.index().for_each_overlapping(cl, ch, |id, g| {
                if !hit && free[id as usize] {
                    hit = if corners.len() == 2 {
                        segments_touch(g.a, g.b, corners[0], corners[1], tol)
                    } else {
                        segment_touches_polygon(g.a, g.b, &corners, tol)
                            || point_in_polygon(g.b, &corners)
                    };
                }
            });
            if hit {
                seeds.extend_from_slice(vs);
            }
        };
        if graph.cells().is_empty() {
            for e in graph.edges() {
                visit(&e, &mut seeds);
            }
        } else {
            for c in graph.cells() {
                let k = if c[3] == NO_CORNER { 3 } else { 4 };
                visit(&c[..k], &mut seeds);
            }
        }
        seeds
    }
}
