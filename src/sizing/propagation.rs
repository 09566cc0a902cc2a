//! Neighbour propagation from a source (thesis 2.2.5, 2.2.10.4–5, 4.3.6–4.3.7): every
//! mesh vertex near a source gets its closest point on the source — distance, segment,
//! foot point, parameter, curvilinear abscissa and side — starting at the source and
//! stopping past a maximum distance. This is the engine of distance to border, distance
//! to a vertex, distance between two boundaries and distance to an imaginary polyline.
//!
//! Method. A [`Source`] is a set of segments: polylines along mesh edges (topological
//! curves), free polylines that may cross cells (a wake), and single points. Propagation
//! is a breadth-first search by levels from the source's seed vertices (the vertices of
//! the source, and for free pieces the corners of every cell they touch, so that a
//! coarse mesh is still marked). A vertex of the next level takes as guess the closest
//! segment of its first evaluated neighbour, steps along the polyline while its foot is
//! a segment end and the next segment is closer, then moves to the best segment of its
//! *window* (its segment and two either way, or the two either side of a polyline
//! vertex; thesis 4.3.6.3's march). The answer is then *certified*: by the
//! clearance of that segment or vertex ([`Clearance`]: how far out the window alone
//! decides the closest point, computed once per source), or where the vertex lies beyond
//! it — near the medial axis of a non-convex source, past a sharp corner, where another
//! curve comes close — by a branch-and-bound search over oriented boxes of runs of
//! segments ([`Clearance::closest`]) that opens only boxes nearer than the guess. Pure
//! neighbour propagation stops in local minima near the medial axis of non-convex
//! sources on coarse meshes; the certification makes every answer the exact closest
//! point on the discretised source (ties: smaller segment id), equal bit for bit to
//! [`closest_point_brute_force`], whatever the order or the guess.
//! Since each answer is exact and depends on nothing else, the result is the same with
//! any number of threads: levels are evaluated in parallel (rayon) and committed in order.
//!
//! Stopping. A vertex is expanded (its neighbours queued) when its distance is at most
//! `max_distance` plus its longest incident edge. Then every vertex within
//! `max_distance` is reached whenever the straight segment to its closest point stays in
//! the mesh: each cell crossed by that segment holds a point within `max_distance`, so
//! its corners are expanded, and the last one touches the source. Reported are the seeds
//! and the vertices within `max_distance`; the others are evaluated in transit only.
//!
//! Whole mesh. When a step's reach is sure to cover every vertex (`reach_covers_mesh`:
//! every connected component holds a seed, and a bound of the distances per occupied
//! cell of the graph's grid is within the maximum distance), the sizing driver skips
//! the breadth-first search: `VertexOrder` evaluates the vertices in index order, in
//! runs, each from the closest segment of a nearby vertex evaluated before it in its run,
//! settled and certified as above (with one clearance tier capped just past the
//! farthest vertex, since every vertex asks), and each closest point goes straight to
//! the step's tensor. The same exact closest points, in another order. Its exact
//! queries (the reach test's, a run's first vertex, the vertices past their clearance)
//! all go to the clearances' tree of oriented boxes, built once per source, so that
//! such a step never builds the axis-aligned index, which propagation builds the first
//! time it asks.
//!
//! Cost: O(1) segment projections per vertex for the guess and the window, and O(1) for
//! a clearance certificate; a vertex beyond its clearance costs a box search, O(log m)
//! boxes for m segments. The clearances cost one bounded search per segment side
//! asked (O(m log m)); a polyline vertex's clearance comes from its two segments', with
//! a search of its own only where that falls short. Seeding free pieces scans the cells
//! once (O(cells), with a box test against the source first).

use std::sync::{Arc, OnceLock};

use rayon::prelude::*;

use crate::geometry::clearance::{ChainTree, Links, WINDOW};
use crate::geometry::segment::{orient, point_in_polygon, segment_touches_polygon, segments_touch};
use crate::geometry::{
    Clearance, Nearest, Point2, Projection, QueryStats, SegmentGeom, SegmentIndex,
};
use crate::mesh_graph::{MeshGraph, NO_CORNER};
use crate::topology::Topology;

/// One segment of a source.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourceSegment {
    /// Start point.
    pub a: Point2,
    /// End point (equal to `a` for a point source).
    pub b: Point2,
    /// Index of its polyline in [`Source::polylines`].
    pub polyline: u32,
    /// The previous segment along the polyline (wrapping round a closed one).
    pub prev: Option<u32>,
    /// The next segment along the polyline (wrapping round a closed one).
    pub next: Option<u32>,
    /// Curvilinear abscissa of `a` along its polyline (0 at the polyline's first point).
    pub abscissa: f64,
    /// Length of the segment.
    pub length: f64,
}

/// What a source polyline is made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PieceKind {
    /// Mesh edges between mesh vertices (a topological curve, or a path of the mesh).
    MeshEdges,
    /// A single mesh vertex (a topological point).
    MeshVertex,
    /// A polyline given by coordinates, which may cross cells (a wake).
    Free,
    /// A single point given by coordinates.
    FreePoint,
}

/// One polyline of a source: a run of consecutive segments.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SourcePolyline {
    /// Its first segment in [`Source::segments`].
    pub first_segment: u32,
    /// Number of segments (1 for a point, whose segment has zero length).
    pub num_segments: u32,
    /// Whether its last point joins its first.
    pub closed: bool,
    /// What it is made of.
    pub kind: PieceKind,
    /// Total length.
    pub length: f64,
}

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

/// A discretised source: segments with their polylines, an index over them, and the
/// mesh vertices propagation starts from.
#[derive(Debug, Clone)]
pub struct Source {
    segments: Vec<SourceSegment>,
    geoms: Vec<SegmentGeom>,
    polylines: Vec<SourcePolyline>,
    seeds: Vec<u32>,
    /// A segment each seed lies on (`u32::MAX`: none known), parallel to `seeds`.
    seed_guess: Vec<u32>,
    /// The axis-aligned index, built the first time it is asked for: a step evaluated
    /// in vertex order asks the chain tree instead.
    index: OnceLock<SegmentIndex>,
    /// The box the index has ([`SegmentIndex::bounds_of`]), `None` with no finite
    /// segment.
    bounds: Option<(Point2, Point2)>,
    /// The chain tree of the clearances, built the first time it is asked for, and
    /// shared by the reach test and the clearances.
    chain: OnceLock<Arc<ChainTree>>,
    /// Per segment, bit k set when its window lies behind it as seen from side k (0
    /// left, 1 right): see [`Source::window_behind`].
    behind: Vec<u8>,
    /// Per segment, its unit left normal (NaN for a point), for the side of a foot on a
    /// polyline vertex without two square roots per vertex.
    unit_left: Vec<Point2>,
}

/// The closest point of a source to a mesh vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosestPoint {
    /// Euclidean distance to the source.
    pub distance: f64,
    /// The segment the closest point lies on (the smallest id among equally close ones).
    pub segment: u32,
    /// The closest point.
    pub foot: Point2,
    /// Parameter of the foot along the segment, in `[0, 1]`.
    pub parameter: f64,
    /// Curvilinear abscissa of the foot along its polyline.
    pub abscissa: f64,
    /// +1 when the vertex lies left of the polyline's direction (inside the domain for
    /// a boundary curve, which topology orients with the domain on its left), -1 right,
    /// 0 on the source, beside a point source, or where the side is undefined (beyond
    /// the end of an open polyline on its line, at a fold). At a polyline corner the
    /// side follows the sum of the two segments' unit normals.
    pub side: i8,
}

impl ClosestPoint {
    /// `side × distance`.
    pub fn signed_distance(&self) -> f64 {
        f64::from(self.side) * self.distance
    }
}

impl Source {
    /// A builder for a source on `graph`.
    pub fn builder(graph: &MeshGraph) -> SourceBuilder<'_> {
        SourceBuilder::new(graph)
    }

    /// The segments, polyline by polyline.
    pub fn segments(&self) -> &[SourceSegment] {
        &self.segments
    }

    /// The polylines.
    pub fn polylines(&self) -> &[SourcePolyline] {
        &self.polylines
    }

    /// Mesh vertices propagation starts from, sorted.
    pub fn seeds(&self) -> &[u32] {
        &self.seeds
    }

    /// The segment index.
    pub fn index(&self) -> &SegmentIndex {
        self.index.get_or_init(|| SegmentIndex::new(&self.geoms))
    }

    /// Whether some segment has finite ends (the index holds only those).
    fn has_finite_segment(&self) -> bool {
        self.bounds.is_some()
    }

    /// The chain tree over the segments ([`Clearance::tree_of`]).
    fn chain_tree(&self) -> &Arc<ChainTree> {
        self.chain.get_or_init(|| Clearance::tree_of(&self.geoms, self.scale_and_extent().0))
    }

    /// The exact closest segment to `p` from the chain tree (the answer does not depend
    /// on the guess): the search starts at segment `guess` when there is one and it is
    /// nearer than the tree's own guess ([`ChainTree::guess_near`]).
    fn closest_in_chain(&self, p: Point2, guess: Option<u32>, stats: &mut QueryStats) -> Nearest {
        let tree = self.chain_tree();
        let given = guess.map(|g| {
            stats.segments += 1;
            Nearest { segment: g, projection: self.geoms[g as usize].project(p) }
        });
        let own = tree.guess_near(&self.geoms, p, stats);
        let seed = match (given, own) {
            (Some(a), Some(b)) => {
                if b.beats(&a) {
                    b
                } else {
                    a
                }
            }
            (a, b) => a.or(b).expect("the source has a segment"),
        };
        tree.closest(&self.geoms, p, seed, stats)
    }

    /// The exact closest point of the source to `p`, from the index.
    pub fn closest_point(&self, p: Point2) -> Option<ClosestPoint> {
        self.index().closest(p, &mut QueryStats::default()).map(|n| self.describe(p, n))
    }

    /// Fills in abscissa and side for a projection of `p`.
    #[inline(always)]
    fn describe(&self, p: Point2, n: Nearest) -> ClosestPoint {
        let s = &self.segments[n.segment as usize];
        let Projection { distance_squared, foot, t } = n.projection;
        ClosestPoint {
            distance: distance_squared.sqrt(),
            segment: n.segment,
            foot,
            parameter: t,
            abscissa: s.abscissa + t * s.length,
            side: self.side(p, n.segment as usize, foot, t),
        }
    }

    #[inline(always)]
    fn side(&self, p: Point2, seg: usize, foot: Point2, t: f64) -> i8 {
        let g = &self.geoms[seg];
        if g.inv_len2 == 0.0 {
            return 0;
        }
        let s = &self.segments[seg];
        let other = if t == 0.0 {
            s.prev
        } else if t == 1.0 {
            s.next
        } else {
            None
        };
        // At a polyline vertex the sum of the two unit normals; elsewhere the segment's
        // left normal unscaled, since only the sign of the product is wanted.
        let n = match other.filter(|&o| self.geoms[o as usize].inv_len2 > 0.0) {
            Some(o) => {
                let (a, b) = (self.unit_left[seg], self.unit_left[o as usize]);
                [a[0] + b[0], a[1] + b[1]]
            }
            None => [-g.d[1], g.d[0]],
        };
        let dot = (p[0] - foot[0]) * n[0] + (p[1] - foot[1]) * n[1];
        if dot > 0.0 {
            1
        } else if dot < 0.0 {
            -1
        } else {
            0
        }
    }

    /// The clearances of the source's segments and vertices (see [`Clearance`]),
    /// computed as propagation asks for them.
    fn clearance(&self) -> Clearance {
        let (scale, extent) = self.scale_and_extent();
        Clearance::new_over(
            self.chain_tree().clone(),
            &self.geoms,
            &self.links(),
            scale,
            4.0 * extent,
        )
    }

    /// The clearances for questions no farther than `farthest` from the source
    /// ([`Clearance::up_to`]).
    fn clearance_up_to(&self, farthest: f64) -> Clearance {
        Clearance::up_to_over(
            self.chain_tree().clone(),
            &self.geoms,
            &self.links(),
            self.scale_and_extent().0,
            farthest,
        )
    }

    /// The largest coordinate and the diagonal of the bounding box.
    fn scale_and_extent(&self) -> (f64, f64) {
        let (lo, hi) = self.bounds.unwrap_or(([0.0; 2], [0.0; 2]));
        let scale = lo[0].abs().max(lo[1].abs()).max(hi[0].abs()).max(hi[1].abs());
        (scale, (hi[0] - lo[0]).hypot(hi[1] - lo[1]))
    }

    /// The polyline links of the segments, as the clearances take them.
    fn links(&self) -> Vec<Links> {
        self.segments.iter().map(|s| (s.prev, s.next)).collect()
    }

    /// The segments whose closest points must be compared with `best`'s before its
    /// clearance can decide: [`crate::geometry::clearance::WINDOW`] segments either way
    /// from its segment when the foot is inside it, the two segments either side of the
    /// vertex when the foot is a polyline vertex. Past a polyline's end the entry is
    /// the last segment reached (`best`'s own at worst), so that a caller projects on
    /// all four with no test: a projection made again changes nothing.
    #[inline]
    fn window(&self, best: &Nearest) -> [u32; 4] {
        let s = best.segment;
        let back = |x: u32| self.segments[x as usize].prev.unwrap_or(x);
        let ahead = |x: u32| self.segments[x as usize].next.unwrap_or(x);
        let t = best.projection.t;
        if t > 0.0 && t < 1.0 {
            let (p1, n1) = (back(s), ahead(s));
            [p1, back(p1), n1, ahead(n1)]
        } else if t == 0.0 {
            let p1 = back(s);
            [p1, back(p1), ahead(s), s]
        } else {
            let n1 = ahead(s);
            [back(s), n1, ahead(n1), s]
        }
    }

    /// The sides of segment `s` (bit 0 left, bit 1 right) behind which the rest of its
    /// window lies: every other segment of the window on the far side of the line of
    /// `s` or on it (the exact orientation predicate), and beyond the span of `s` along
    /// it (the segments after `s` past its end, those before it short of its start).
    /// Convex sides of a border and straight runs have both; a side into which the
    /// polyline turns has neither.
    fn window_sides_behind(&self, s: usize) -> u8 {
        let g = &self.geoms[s];
        if g.inv_len2 == 0.0 {
            return 0;
        }
        let (a, b) = (g.a, g.b);
        // Along the line of s: ahead of b, or before a, clearly (or the shared end itself).
        let beyond = |q: Point2, from: Point2, sign: f64| {
            if q == from {
                return true;
            }
            let dot = sign * ((q[0] - from[0]) * g.d[0] + (q[1] - from[1]) * g.d[1]);
            let scale =
                ((q[0] - from[0]).abs() + (q[1] - from[1]).abs()) * (g.d[0].abs() + g.d[1].abs());
            dot > 1e-9 * scale
        };
        let mut sides = 3u8;
        let mut check = |w: u32, forward: bool| {
            if w as usize == s {
                return;
            }
            let gw = &self.geoms[w as usize];
            for q in [gw.a, gw.b] {
                let along = if forward { beyond(q, b, 1.0) } else { beyond(q, a, -1.0) };
                if !along {
                    sides = 0;
                }
                let o = orient(a, b, q);
                if o > 0.0 {
                    sides &= !1;
                } else if o < 0.0 {
                    sides &= !2;
                }
            }
        };
        for forward in [false, true] {
            let mut at = s as u32;
            for _ in 0..WINDOW {
                let step = if forward {
                    self.segments[at as usize].next
                } else {
                    self.segments[at as usize].prev
                };
                match step {
                    Some(w) => {
                        check(w, forward);
                        at = w;
                    }
                    None => break,
                }
            }
        }
        sides
    }

    /// Whether no other segment of `best`'s window can be as close to `p` as `best`,
    /// with no projection on them: the foot lies inside the segment, `p` is on a side
    /// behind which the rest of the window lies ([`Source::window_sides_behind`]), and
    /// the foot is far enough from both ends. Then every point of those segments is at
    /// least `sqrt(y² + m²)` from `p`, `y` its distance to the line and `m` the foot's
    /// distance to the nearer end, and `m² >= 2·10^-12 (d² + len²)` puts that far
    /// beyond the rounding of any computed distance (a few ulps of `d²`), so a scan
    /// computes them all larger, as the projections would.
    #[inline]
    fn window_behind(&self, p: Point2, best: &Nearest) -> bool {
        let t = best.projection.t;
        let bits = self.behind[best.segment as usize];
        if bits == 0 || !(t > 0.0 && t < 1.0) {
            return false;
        }
        let g = &self.geoms[best.segment as usize];
        let cr = g.d[0] * (p[1] - g.a[1]) - g.d[1] * (p[0] - g.a[0]);
        let bit = if cr > 0.0 {
            1
        } else if cr < 0.0 {
            2
        } else {
            return false;
        };
        let len2 = g.d[0] * g.d[0] + g.d[1] * g.d[1];
        let m = t.min(1.0 - t);
        bits & bit != 0 && m * m * len2 >= 2e-12 * (best.projection.distance_squared + len2)
    }

    /// Whether `best`, the best of its window for `p`, is the closest point of the
    /// whole source by the clearance of its segment or vertex (within 0.999 of it, see
    /// [`Clearance`]).
    #[inline]
    fn certified(&self, clearance: &Clearance, p: Point2, best: &Nearest) -> bool {
        let s = best.segment;
        let t = best.projection.t;
        let d = best.projection.distance_squared.sqrt();
        // A point on the source: a clearance of 0 (another curve touching there, whose
        // segments lie outside the window) would still cover it, and a segment of a
        // smaller id at distance 0 too may lie outside the window. The search decides.
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(d > 0.0) {
            return false;
        }
        if t > 0.0 && t < 1.0 {
            return clearance.covers_segment(s, p, d);
        }
        match if t == 0.0 { self.segments[s as usize].prev } else { Some(s) } {
            Some(into) => clearance.covers_vertex(into, p, d),
            None => false,
        }
    }

    /// Corners of every cell that a free piece touches (every edge when the graph has
    /// no cell). Near misses within a few ulps count: an extra seed costs one
    /// evaluation, a missing one could leave a crossed cell unmarked.
    fn free_piece_seeds(&self, graph: &MeshGraph) -> Vec<u32> {
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

/// The brute-force twin of the propagation (test twin): the closest point of `source`
/// to `p` by projecting on every segment, ties to the smaller segment id. O(m) per
/// point; the propagation must agree with it bit for bit.
pub fn closest_point_brute_force(source: &Source, p: Point2) -> Option<ClosestPoint> {
    let mut best: Option<Nearest> = None;
    for (i, g) in source.geoms.iter().enumerate() {
        if !g.a.iter().chain(&g.b).all(|c| c.is_finite()) {
            continue;
        }
        let c = Nearest { segment: i as u32, projection: g.project(p) };
        if best.as_ref().map_or(true, |b| c.beats(b)) {
            best = Some(c);
        }
    }
    best.map(|n| source.describe(p, n))
}

/// Knobs of [`propagate`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PropagationOptions {
    /// Evaluate large levels on the rayon thread pool. The result is the same either
    /// way; only the time changes.
    pub parallel: bool,
}

impl Default for PropagationOptions {
    fn default() -> Self {
        PropagationOptions { parallel: true }
    }
}

impl PropagationOptions {
    /// Defaults: parallel.
    pub fn new() -> PropagationOptions {
        PropagationOptions::default()
    }

    /// With or without parallel evaluation.
    pub fn with_parallel(self, parallel: bool) -> PropagationOptions {
        PropagationOptions { parallel }
    }
}

/// What a propagation did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct PropagationReport {
    /// Seed vertices.
    pub seeds: usize,
    /// Vertices whose closest point was computed (reported or in transit).
    pub evaluated: usize,
    /// Vertices reported in the [`Reach`].
    pub reached: usize,
    /// Vertices where the neighbours' guess was not the closest segment and the index
    /// found a strictly closer one: the local minima of pure neighbour propagation.
    pub corrected: usize,
    /// Vertices whose closest point was certified by the clearance of its segment or
    /// vertex (no index search).
    pub certified_locally: usize,
    /// Breadth-first levels.
    pub levels: usize,
    /// Index boxes tested.
    pub boxes_tested: u64,
    /// Segments projected on (guesses and index leaves).
    pub segments_tested: u64,
}

/// The vertices a propagation reached and their closest points on the source, in
/// breadth-first order (seeds first, by index; then level by level, each level in
/// the order its vertices were queued).
///
/// Only the closest segment of each vertex is kept; its closest point is computed again
/// when asked for ([`Reach::closest`]): one projection, the same bits as the
/// propagation's (one function of the same inputs). For a reach of 10^6 vertices that is
/// 4 MB where a table of closest points would be 56 MB of fresh memory, written once and
/// read once by the algorithm that turns them into tensors.
#[derive(Debug, Clone)]
pub struct Reach<'a> {
    graph: &'a MeshGraph,
    source: &'a Source,
    vertices: Vec<u32>,
    /// The closest segment of each vertex of `vertices`.
    segments: Vec<u32>,
    /// Position of each mesh vertex in `vertices`, or `u32::MAX`.
    slot: Vec<u32>,
    report: PropagationReport,
}

impl<'a> Reach<'a> {
    /// Number of reached vertices.
    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    /// Whether nothing was reached.
    pub fn is_empty(&self) -> bool {
        self.vertices.is_empty()
    }

    /// Reached vertices in order; the first `report().seeds` are the seeds.
    pub fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// The closest point of the `i`-th reached vertex (in the order of
    /// [`Reach::vertices`]).
    #[inline]
    pub fn closest(&self, i: usize) -> ClosestPoint {
        let p = self.graph.point(self.vertices[i] as usize);
        let segment = self.segments[i];
        self.source.describe(
            p,
            Nearest { segment, projection: self.source.geoms[segment as usize].project(p) },
        )
    }

    /// Closest points, in the order of [`Reach::vertices`].
    pub fn closest_points(&self) -> impl ExactSizeIterator<Item = ClosestPoint> + '_ {
        (0..self.len()).map(|i| self.closest(i))
    }

    /// The closest point of vertex `v`, if reached.
    pub fn get(&self, v: usize) -> Option<ClosestPoint> {
        match self.slot.get(v) {
            Some(&s) if s != u32::MAX => Some(self.closest(s as usize)),
            _ => None,
        }
    }

    /// `(vertex, closest point)` in order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = (usize, ClosestPoint)> + '_ {
        (0..self.len()).map(|i| (self.vertices[i] as usize, self.closest(i)))
    }

    /// The position of each mesh vertex in [`Reach::vertices`], `u32::MAX` for the
    /// vertices not reached: a lookup by vertex, for a pass in vertex order.
    pub(crate) fn positions(&self) -> &[u32] {
        &self.slot
    }

    /// What the propagation did.
    pub fn report(&self) -> &PropagationReport {
        &self.report
    }

    /// The reached vertices, giving up the rest.
    pub(crate) fn into_vertices(self) -> Vec<u32> {
        self.vertices
    }
}

const UNSEEN: u32 = u32::MAX;
const QUEUED: u32 = u32::MAX - 1;
/// Levels smaller than this are evaluated on the calling thread.
const PARALLEL_MIN_LEVEL: usize = 2048;
/// Closest points that earlier levels must have put on a segment before its clearance
/// is used (see [`evaluate_from_neighbours`]). Two: a first-tier clearance is a short
/// search (a few tens of segment lengths), which the vertices of the second ring out
/// already repay; at six, the first six rings of a border went through the
/// axis-aligned index, and a step reaching ten rings was a quarter slower.
const CLEARANCE_AFTER: u32 = 2;
/// Steps of the march along the polyline from the neighbours' guess.
const MARCH_STEPS: usize = 4;

struct Evaluation {
    nearest: Nearest,
    corrected: bool,
    local: bool,
    stats: QueryStats,
}

/// Propagates from `source` over `graph` up to `max_distance` (thesis Algorithms 4.2–4.5,
/// with exact closest points). A negative or NaN `max_distance` reaches the seeds only;
/// an infinite one reaches the seeds' connected components.
pub fn propagate<'a>(
    graph: &'a MeshGraph,
    source: &'a Source,
    max_distance: f64,
    options: &PropagationOptions,
) -> Reach<'a> {
    let n = graph.num_vertices();
    let max = if max_distance >= 0.0 { max_distance } else { 0.0 };
    let mut report = PropagationReport::default();
    let mut slot = vec![UNSEEN; n];
    // Room for every vertex up front: pages that are never written are never touched,
    // and growing by doubling would copy the largest arrays of the propagation.
    let mut order: Vec<u32> = Vec::with_capacity(n);
    // The closest segment of each evaluated vertex, in evaluation order; the projection
    // is computed again for the reported ones (the same bits: one function of the same
    // inputs), which costs less than keeping it for every vertex.
    let mut found: Vec<u32> = Vec::with_capacity(n);
    // Whether each evaluated vertex is reported: a seed, or within max_distance
    // (parallel to `order`, pushed where the expansion test computes the distance).
    let mut keep: Vec<bool> = Vec::with_capacity(n);
    let mut evaluations: Vec<Evaluation> = Vec::new();
    let mut next: Vec<u32> = Vec::new();
    let mut frontier: Vec<u32> = if !source.has_finite_segment() {
        Vec::new()
    } else {
        source.seeds.iter().copied().filter(|&v| (v as usize) < n).collect()
    };
    // The guess of each seed, by vertex, for the first level.
    let guess_of =
        |v: u32| source.seeds.binary_search(&v).ok().map_or(u32::MAX, |i| source.seed_guess[i]);
    for &v in &frontier {
        slot[v as usize] = QUEUED;
    }
    report.seeds = frontier.len();
    // Built the first time a segment earns its clearance: a fixed function of the
    // source, whichever thread builds it.
    let clearance: OnceLock<Clearance> = OnceLock::new();
    // Closest points committed on each segment so far.
    let mut feet = vec![0u32; source.segments.len()];
    let mut level = 0usize;
    while !frontier.is_empty() {
        let evaluate = |&v: &u32| -> Evaluation {
            if level == 0 {
                let mut stats = QueryStats::default();
                let p = graph.point(v as usize);
                let g = guess_of(v);
                let nearest = if (g as usize) < source.geoms.len() {
                    source.index().certify(
                        p,
                        Nearest { segment: g, projection: source.geoms[g as usize].project(p) },
                        &mut stats,
                    )
                } else {
                    source.index().closest(p, &mut stats).expect("index is not empty")
                };
                Evaluation { nearest, corrected: false, local: false, stats }
            } else {
                evaluate_from_neighbours(
                    graph, source, &clearance, &feet, &slot, &found, v as usize,
                )
            }
        };
        // One buffer for every level's evaluations, reused.
        if options.parallel && frontier.len() >= PARALLEL_MIN_LEVEL {
            frontier.par_iter().with_min_len(256).map(evaluate).collect_into_vec(&mut evaluations);
        } else {
            evaluations.clear();
            evaluations.extend(frontier.iter().map(evaluate));
        }
        // Commit the level, then queue the neighbours of the vertices to expand.
        next.clear();
        for (&v, e) in frontier.iter().zip(&evaluations) {
            slot[v as usize] = found.len() as u32;
            found.push(e.nearest.segment);
            feet[e.nearest.segment as usize] = feet[e.nearest.segment as usize].saturating_add(1);
            order.push(v);
            report.corrected += usize::from(e.corrected);
            report.certified_locally += usize::from(e.local);
            report.boxes_tested += e.stats.boxes;
            report.segments_tested += e.stats.segments;
        }
        for (&v, e) in frontier.iter().zip(&evaluations) {
            let d = e.nearest.projection.distance();
            keep.push(level == 0 || d <= max);
            if d <= max + graph.longest_edge(v as usize) {
                for &u in graph.neighbours(v as usize) {
                    if slot[u as usize] == UNSEEN {
                        slot[u as usize] = QUEUED;
                        next.push(u);
                    }
                }
            }
        }
        std::mem::swap(&mut frontier, &mut next);
        level += 1;
    }
    report.levels = level;
    report.evaluated = order.len();
    // Keep the seeds and the vertices within max_distance, in place; the slot array
    // becomes the lookup of the reported vertices.
    let mut kept = 0;
    for i in 0..order.len() {
        let v = order[i];
        if keep[i] {
            slot[v as usize] = kept as u32;
            order[kept] = v;
            found[kept] = found[i];
            kept += 1;
        } else {
            slot[v as usize] = UNSEEN;
        }
    }
    order.truncate(kept);
    found.truncate(kept);
    report.reached = kept;
    Reach { graph, source, vertices: order, segments: found, slot, report }
}

/// Vertices in a run of [`VertexOrder::for_each`] as the sizing driver cuts them: the
/// first vertex of a run is found by the index, every other one from a vertex before it
/// in the run. A fixed size, so that the work done does not depend on the thread count.
pub(crate) const VERTEX_RUN: usize = 4096;

/// Whether [`propagate`] from `source` up to `max_distance` reports every vertex of the
/// mesh, and if so a distance no vertex is farther than from the source. It does when
/// every connected component of the graph holds a seed and every vertex lies within
/// `max_distance` of the source: then every vertex is expanded, so the breadth-first
/// search visits each component of a seed whole and reports all of it.
///
/// The distances are bounded from above with one closest-point query per cell of the
/// graph's occupancy grid ([`MeshGraph::occupied_cells`], about 64 vertices a cell): no
/// point of a cell is farther from the source than the cell's centre is, plus half its
/// diagonal. The largest of these bounds, plus a margin for rounding, must be within
/// `max_distance`; the first cell past it ends the test. Otherwise, or with
/// non-finite coordinates, the answer is `None` and the caller propagates.
pub(crate) fn reach_covers_mesh(
    graph: &MeshGraph,
    source: &Source,
    max_distance: f64,
) -> Option<f64> {
    let n = graph.num_vertices();
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    if n == 0 || !source.has_finite_segment() || !(max_distance >= 0.0) {
        return None;
    }
    let mut seeded = vec![false; graph.num_components()];
    for &v in source.seeds.iter().filter(|&&v| (v as usize) < n) {
        seeded[graph.component(v as usize)] = true;
    }
    if !seeded.iter().all(|&s| s) {
        return None;
    }
    // Non-finite coordinates: propagation would report only some vertices.
    let (lo, hi) = graph.bounds()?;
    let (slo, shi) = source.bounds?;
    let scale =
        [lo, hi, slo, shi].iter().flat_map(|p| [p[0].abs(), p[1].abs()]).fold(0.0, f64::max);
    if !scale.is_finite() {
        return None;
    }
    // Rounding of the centres, of the distances and of the sums.
    let margin = 64.0 * f64::EPSILON * scale;
    let mut farthest = 0.0f64;
    // Every coordinate is finite here: the chain tree answers, each search from the
    // previous cell's closest segment (cells come in grid order).
    let mut guess = None;
    for &(a, b) in graph.occupied_cells() {
        let centre = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let half_diagonal = 0.5 * (b[0] - a[0]).hypot(b[1] - a[1]);
        let nearest = source.closest_in_chain(centre, guess, &mut QueryStats::default());
        guess = Some(nearest.segment);
        let bound = nearest.projection.distance() + half_diagonal + margin;
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(bound <= max_distance) {
            return None;
        }
        farthest = farthest.max(bound);
    }
    Some(farthest)
}

/// Exact closest points in vertex order, for a step that reaches every vertex (see
/// [`reach_covers_mesh`]): no breadth-first levels, no list of reached vertices, and
/// each closest point handed on where it is found. A vertex takes as guess the closest
/// segment of the vertex just before it when that one lies within its longest edge,
/// else of its first neighbour evaluated before it in the same run (else, again, of the
/// vertex before), and is then settled and certified as in [`propagate`]: the same
/// exact closest points, bit for bit, in another order.
pub(crate) struct VertexOrder<'a> {
    graph: &'a MeshGraph,
    source: &'a Source,
    /// Clearances for questions up to the farthest vertex ([`Clearance::up_to`]):
    /// every vertex is asked about, so the far questions come for most segments, and
    /// one search per segment side answers them all.
    clearance: OnceLock<Clearance>,
    farthest: f64,
    /// Every vertex is evaluated, on average `n / m` per segment: clearances pay when
    /// that is at least [`CLEARANCE_AFTER`], the share at which [`propagate`] computes
    /// a segment's clearance.
    clearances_pay: bool,
}

impl<'a> VertexOrder<'a> {
    /// The evaluator of the vertices of `graph` against `source`, none of them farther
    /// than `farthest` from it ([`reach_covers_mesh`]).
    pub(crate) fn new(graph: &'a MeshGraph, source: &'a Source, farthest: f64) -> VertexOrder<'a> {
        let clearances_pay =
            graph.num_vertices() >= CLEARANCE_AFTER as usize * source.segments.len();
        VertexOrder { graph, source, clearance: OnceLock::new(), farthest, clearances_pay }
    }

    /// Calls `visit` with each vertex of `range` and its closest point, in order.
    pub(crate) fn for_each(
        &self,
        range: std::ops::Range<usize>,
        mut visit: impl FnMut(usize, &ClosestPoint),
    ) {
        let (graph, source) = (self.graph, self.source);
        let lo = range.start;
        let mut found = vec![u32::MAX; range.len()];
        // Every vertex is evaluated: the clearances will be asked for.
        let clearance = if self.clearances_pay {
            Some(self.clearance.get_or_init(|| source.clearance_up_to(self.farthest)))
        } else {
            None
        };
        if range.is_empty() {
            return;
        }
        // The run's first vertex has nothing before it: the tree answers, before the
        // loop, so that the loop holds only the evaluations from a guess.
        let first = source.closest_in_chain(graph.point(lo), None, &mut QueryStats::default());
        for v in range {
            let p = graph.point(v);
            let earlier = |u: usize| (lo..v).contains(&u).then(|| found[u - lo]);
            // The vertex before, when it lies within the vertex's longest edge (as its
            // neighbours do): the usual case of a mesh numbered with some locality, and
            // one test, where a scan of the neighbours mispredicts on how many come
            // before the first evaluated one. Else that first one, else the vertex before.
            let previous_is_near = v > lo && {
                let q = graph.point(v - 1);
                let reach = graph.longest_edge(v);
                (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) <= reach * reach
            };
            let guess = if previous_is_near {
                Some(found[v - 1 - lo])
            } else {
                graph
                    .neighbours(v)
                    .iter()
                    .find_map(|&u| earlier(u as usize))
                    .or_else(|| v.checked_sub(1).and_then(earlier))
            };
            // Every vertex after the first has a guess (the vertex before, at least).
            let nearest = match guess {
                Some(seg) => settle(source, p, seg, |_| clearance).nearest,
                None => first,
            };
            found[v - lo] = nearest.segment;
            visit(v, &source.describe(p, nearest));
        }
    }
}

/// The projection of `p` on segment `q`, counted in `stats`.
#[inline]
fn project(source: &Source, p: Point2, q: u32, stats: &mut QueryStats) -> Nearest {
    stats.segments += 1;
    Nearest { segment: q, projection: source.geoms[q as usize].project(p) }
}

/// Moves `best` along the polyline while its foot is an end of its segment and the
/// segment across that end is closer.
#[inline]
fn march_across_ends(source: &Source, p: Point2, best: &mut Nearest, stats: &mut QueryStats) {
    for _ in 0..MARCH_STEPS {
        let s = &source.segments[best.segment as usize];
        let step = if best.projection.t == 0.0 {
            s.prev
        } else if best.projection.t == 1.0 {
            s.next
        } else {
            None
        };
        let Some(q) = step else { break };
        let c = project(source, p, q, stats);
        if c.beats(best) {
            *best = c;
        } else {
            break;
        }
    }
}

/// The closest point of vertex `v` from its evaluated neighbours' segments, settled
/// on a local optimum along the polyline, then certified by the clearance of its
/// segment or vertex, or else by the index.
fn evaluate_from_neighbours(
    graph: &MeshGraph,
    source: &Source,
    clearance: &OnceLock<Clearance>,
    feet: &[u32],
    slot: &[u32],
    found: &[u32],
    v: usize,
) -> Evaluation {
    let p = graph.point(v);
    // The guess: the closest segment of the first evaluated neighbour. Neighbours lie
    // within an edge of each other, so their segments are the same or a few steps apart
    // along the polyline, where the march and the window below reach; comparing every
    // neighbour's segment first costs more projections than it saves steps.
    let guess = graph.neighbours(v).iter().find_map(|&u| {
        let s = slot[u as usize];
        (s < QUEUED).then(|| found[s as usize])
    });
    let Some(seg) = guess else {
        // Queued vertices always have an evaluated neighbour; stay exact regardless.
        let mut stats = QueryStats::default();
        let nearest = source.index().closest(p, &mut stats).expect("index is not empty");
        return Evaluation { nearest, corrected: false, local: false, stats };
    };
    // A clearance costs a few index searches to compute: it is asked for only once
    // earlier levels put enough feet on the segment to pay it back.
    settle(source, p, seg, |s| {
        (feet[s as usize] >= CLEARANCE_AFTER).then(|| clearance.get_or_init(|| source.clearance()))
    })
}

/// The exact closest point of `p` from the guess `seg`: settled on a local optimum along
/// the polyline, then certified by the clearance of its segment or vertex (where
/// `clearance_if_it_pays` gives the clearances for the segment reached), or else by an
/// index search.
#[inline]
fn settle<'c>(
    source: &Source,
    p: Point2,
    seg: u32,
    clearance_if_it_pays: impl FnOnce(u32) -> Option<&'c Clearance>,
) -> Evaluation {
    let mut stats = QueryStats::default();
    let mut best = project(source, p, seg, &mut stats);
    // First march along the polyline while the foot sits on a segment end (thesis
    // 4.3.6.3): one projection a step, where the window would take three, and the
    // usual way off a guess, since a neighbour's segment often ends just short of the
    // vertex's foot. Then move to the best segment of the window until it is the best
    // of its own window, and try the clearance; else search.
    march_across_ends(source, p, &mut best, &mut stats);
    if let Some(clearance) = clearance_if_it_pays(best.segment) {
        for _ in 0..MARCH_STEPS {
            let mut moved = false;
            if !source.window_behind(p, &best) {
                // All four, with no test of which were projected before (the march's)
                // or are repeats: the tests mispredicted more than the projections cost.
                for q in source.window(&best) {
                    let c = project(source, p, q, &mut stats);
                    if c.beats(&best) {
                        best = c;
                        moved = true;
                    }
                }
            }
            if !moved {
                if source.certified(clearance, p, &best) {
                    return Evaluation { nearest: best, corrected: false, local: true, stats };
                }
                break;
            }
        }
        // Beyond the clearance, far from the source: the oriented boxes.
        let nearest = clearance.closest(p, best, &mut stats);
        return Evaluation {
            nearest,
            corrected: nearest.projection.distance_squared < best.projection.distance_squared,
            local: false,
            stats,
        };
    }
    // Near the source: the axis-aligned index around the guess's leaf.
    let nearest = source.index().certify(p, best, &mut stats);
    Evaluation {
        nearest,
        corrected: nearest.projection.distance_squared < best.projection.distance_squared,
        local: false,
        stats,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_support::Rng;

    /// A jittered `k × k` grid on [0, 1]² joined by its grid edges, plus `extra`
    /// isolated pairs of vertices far off (other components).
    fn grid(k: usize, rng: &mut Rng, extra: usize) -> MeshGraph {
        let mut coords = Vec::new();
        for j in 0..k {
            for i in 0..k {
                coords.push([
                    (i as f64 + 0.3 * rng.unit()) / k as f64,
                    (j as f64 + 0.3 * rng.unit()) / k as f64,
                ]);
            }
        }
        let mut edges = Vec::new();
        for j in 0..k {
            for i in 0..k {
                if i + 1 < k {
                    edges.push([j * k + i, j * k + i + 1]);
                }
                if j + 1 < k {
                    edges.push([j * k + i, (j + 1) * k + i]);
                }
            }
        }
        for e in 0..extra {
            let v = coords.len();
            coords.push([3.0 + e as f64, 0.0]);
            coords.push([3.0 + e as f64, 0.1]);
            edges.push([v, v + 1]);
        }
        MeshGraph::from_edges(coords, &edges, &[]).unwrap()
    }

    /// Every closest point of `VertexOrder` against the brute-force scan, bit for bit,
    /// over whole meshes: a jittered grid with sources along its vertices that meet
    /// (a comb: a bottom row and columns down onto it, so that three segments meet at
    /// vertices on the source, the smaller ids outside the row's window), a wavy free
    /// curve that doubles back, and a point; runs cut anywhere.
    #[test]
    fn vertex_order_is_the_brute_force_scan() {
        let mut rng = Rng(21);
        let k = 30;
        let graph = grid(k, &mut rng, 0);
        let row: Vec<usize> = (0..k).collect();
        let mut comb = Source::builder(&graph);
        for col in [3, 11, 12, 20] {
            comb.mesh_polyline(&(0..k / 2).rev().map(|j| j * k + col).collect::<Vec<_>>(), false);
        }
        comb.mesh_polyline(&row, false);
        let ring: Vec<usize> =
            (0..k).map(|i| k + i).chain((0..k).rev().map(|i| 5 * k + i)).collect();
        let wavy: Vec<Point2> = (0..300)
            .map(|i| i as f64 / 299.0)
            .map(|t| {
                [0.5 + 0.45 * (9.0 * t).sin() * t, 0.5 + 0.4 * (5.0 * t).cos() * (1.0 - 0.5 * t)]
            })
            .collect();
        let sources = [
            comb.build().unwrap(),
            Source::builder(&graph)
                .mesh_polyline(&ring, true)
                .mesh_polyline(&row, false)
                .build()
                .unwrap(),
            Source::builder(&graph).polyline(&wavy, false).build().unwrap(),
            Source::builder(&graph).point([0.3, 0.7]).build().unwrap(),
        ];
        let n = graph.num_vertices();
        for (case, source) in sources.iter().enumerate() {
            for farthest in [2.0, 0.1] {
                let order = VertexOrder::new(&graph, source, farthest);
                for start in [0, 7, n / 3] {
                    let mut v = start;
                    let mut visited = 0;
                    order.for_each(start..n, |u, c| {
                        assert_eq!(u, v);
                        let want = closest_point_brute_force(source, graph.point(u)).unwrap();
                        assert_eq!(
                            format!("{c:?}"),
                            format!("{want:?}"),
                            "source {case}, vertex {u}, runs from {start}"
                        );
                        v += 1;
                        visited += 1;
                    });
                    assert_eq!(visited, n - start);
                }
            }
        }
    }

    /// The chain tree's exact query against the brute-force scan, bit for bit, from no
    /// guess (the tree's own), from the farthest segment, and from the closest: points
    /// near and far around a closed wavy curve with a row beside it, and a point source.
    #[test]
    fn closest_in_chain_is_the_brute_force_scan() {
        let mut rng = Rng(31);
        let graph = grid(20, &mut rng, 0);
        let wavy: Vec<Point2> = (0..400)
            .map(|i| 2.0 * std::f64::consts::PI * i as f64 / 400.0)
            .map(|a| {
                [
                    0.5 + (0.3 + 0.1 * (5.0 * a).cos()) * a.cos(),
                    0.5 + (0.3 + 0.1 * (5.0 * a).cos()) * a.sin(),
                ]
            })
            .collect();
        let sources = [
            Source::builder(&graph)
                .polyline(&wavy, true)
                .mesh_polyline(&(0..20).collect::<Vec<_>>(), false)
                .build()
                .unwrap(),
            Source::builder(&graph).point([0.3, 0.7]).build().unwrap(),
        ];
        for (case, source) in sources.iter().enumerate() {
            // Segments projected from no guess and from the farthest one.
            let (mut own, mut from_far) = (0u64, 0u64);
            for _ in 0..400 {
                let p = [4.0 * rng.unit() - 1.5, 4.0 * rng.unit() - 1.5];
                let want = closest_point_brute_force(source, p).unwrap();
                let far = (0..source.segments.len() as u32)
                    .max_by(|&a, &b| {
                        source.geoms[a as usize]
                            .project(p)
                            .distance_squared
                            .total_cmp(&source.geoms[b as usize].project(p).distance_squared)
                    })
                    .unwrap();
                for guess in [None, Some(far), Some(want.segment)] {
                    let mut stats = QueryStats::default();
                    let got = source.describe(p, source.closest_in_chain(p, guess, &mut stats));
                    assert_eq!(
                        format!("{got:?}"),
                        format!("{want:?}"),
                        "source {case}, point {p:?}, guess {guess:?}"
                    );
                    if guess.is_none() {
                        own += stats.segments;
                    }
                }
                // The tree's search itself from the farthest segment: the same answer.
                let mut stats = QueryStats { segments: 1, ..QueryStats::default() };
                let seed =
                    Nearest { segment: far, projection: source.geoms[far as usize].project(p) };
                let got = source
                    .describe(p, source.chain_tree().closest(&source.geoms, p, seed, &mut stats));
                assert_eq!(
                    format!("{got:?}"),
                    format!("{want:?}"),
                    "source {case}, point {p:?}, from segment {far}"
                );
                from_far += stats.segments;
            }
            // The tree's own guess keeps the search to a few leaves, where a far one
            // opens much of the tree around a closed curve.
            eprintln!("source {case}: {own} segments projected from the tree's guess, {from_far} from the farthest segment");
            assert!(own <= 40 * 400, "source {case}: {own} segments projected for 400 queries");
            if case == 0 {
                assert!(2 * own < from_far, "source {case}: {own} from the tree's guess against {from_far} from the farthest segment");
            }
        }
    }

    /// The bound of `reach_covers_mesh` against the brute-force distances: never below
    /// the farthest vertex's distance, so that it says the mesh is covered only when
    /// `propagate` reports every vertex; it decides for reaches a little beyond the
    /// farthest vertex; it never decides where a component has no seed.
    #[test]
    fn reach_covers_mesh_bounds_the_farthest_vertex() {
        let mut rng = Rng(11);
        let mut decided = 0;
        for case in 0..60 {
            let graph = grid(12 + case % 7, &mut rng, usize::from(case % 5 == 0));
            // A free wavy polyline, or a single point, somewhere in the square.
            let count = if case % 4 == 3 { 1 } else { 2 + (rng.unit() * 40.0) as usize };
            let (cx, cy, amp) = (rng.unit(), rng.unit(), 0.3 * rng.unit());
            let points: Vec<Point2> = (0..count)
                .map(|i| {
                    [i as f64 / count as f64, cy + amp * (7.0 * i as f64 / count as f64 + cx).sin()]
                })
                .collect();
            let source = Source::builder(&graph).polyline(&points, false).build().unwrap();
            let farthest = (0..graph.num_vertices())
                .map(|v| closest_point_brute_force(&source, graph.point(v)).unwrap().distance)
                .fold(0.0, f64::max);
            // Not so where a component holds no seed (or a point off the mesh none).
            let all = propagate(&graph, &source, f64::INFINITY, &PropagationOptions::new()).len()
                == graph.num_vertices();
            for max in
                [0.5 * farthest, 0.999 * farthest, farthest, 2.0 * farthest, 10.0, f64::INFINITY]
            {
                match reach_covers_mesh(&graph, &source, max) {
                    Some(bound) => {
                        decided += 1;
                        assert!(
                            bound >= farthest && bound <= max,
                            "case {case}: bound {bound}, farthest vertex {farthest}, max {max}"
                        );
                        assert_eq!(
                            propagate(&graph, &source, max, &PropagationOptions::new()).len(),
                            graph.num_vertices(),
                            "case {case}"
                        );
                    }
                    // Undecided: short of twice the farthest distance, or where
                    // propagation does not report every vertex either.
                    None => assert!(
                        max < 2.0 * farthest || !all,
                        "case {case}: undecided at {max} (farthest {farthest})"
                    ),
                }
            }
            if graph.num_components() > 1 {
                assert_eq!(
                    reach_covers_mesh(&graph, &source, f64::INFINITY),
                    None,
                    "case {case}: a component without a seed"
                );
            }
        }
        assert!(decided >= 100, "{decided} of 360 reaches decided");
    }
}
