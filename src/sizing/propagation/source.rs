//! A source of a propagation: the segments of its polylines (mesh curves, free
//! polylines, single points), their links along each polyline, and the exact closest
//! point of the source to a point of the plane.
//!
//! Invariants: segments are stored polyline by polyline, each polyline's segments
//! consecutive, `prev`/`next` linking them (round a closed one); a point source is one
//! segment of zero length. The closest point of the source to `p` is the segment whose
//! projection is nearest, ties to the smaller segment id ([`Nearest::beats`]); every
//! exact query here (the axis-aligned index, the chain tree of the clearances) and the
//! brute-force twin [`closest_point_brute_force`] return that same segment, and
//! [`Source::describe`] turns it into a [`ClosestPoint`] with one function of the same
//! inputs, so the answers agree bit for bit whichever query found them. The index and
//! the chain tree are built the first time they are asked for; both are fixed
//! functions of the segments.

use std::sync::{Arc, OnceLock};

use crate::geometry::clearance::{ChainTree, Links};
use crate::geometry::{
    Clearance, Nearest, Point2, Projection, QueryStats, SegmentGeom, SegmentIndex,
};
use crate::mesh_graph::MeshGraph;

use super::builder::SourceBuilder;

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

/// A discretised source: segments with their polylines, an index over them, and the
/// mesh vertices propagation starts from.
#[derive(Debug, Clone)]
pub struct Source {
    pub(super) segments: Vec<SourceSegment>,
    pub(super) geoms: Vec<SegmentGeom>,
    pub(super) polylines: Vec<SourcePolyline>,
    pub(super) seeds: Vec<u32>,
    /// A segment each seed lies on (`u32::MAX`: none known), parallel to `seeds`.
    pub(super) seed_guess: Vec<u32>,
    /// The axis-aligned index, built the first time it is asked for: a step evaluated
    /// in vertex order asks the chain tree instead.
    pub(super) index: OnceLock<SegmentIndex>,
    /// The box the index has ([`SegmentIndex::bounds_of`]), `None` with no finite
    /// segment.
    pub(super) bounds: Option<(Point2, Point2)>,
    /// The chain tree of the clearances, built the first time it is asked for, and
    /// shared by the reach test and the clearances.
    pub(super) chain: OnceLock<Arc<ChainTree>>,
    /// Per segment, bit k set when its window lies behind it as seen from side k (0
    /// left, 1 right): see [`Source::window_behind`].
    pub(super) behind: Vec<u8>,
    /// Per segment, its unit left normal (NaN for a point), for the side of a foot on a
    /// polyline vertex without two square roots per vertex.
    pub(super) unit_left: Vec<Point2>,
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
    pub(crate) fn index(&self) -> &SegmentIndex {
        self.index.get_or_init(|| SegmentIndex::new(&self.geoms))
    }

    /// Whether some segment has finite ends (the index holds only those).
    pub(super) fn has_finite_segment(&self) -> bool {
        self.bounds.is_some()
    }

    /// The chain tree over the segments ([`Clearance::tree_of`]).
    pub(super) fn chain_tree(&self) -> &Arc<ChainTree> {
        self.chain.get_or_init(|| Clearance::tree_of(&self.geoms, self.scale_and_extent().0))
    }

    /// The exact closest segment to `p` from the chain tree (the answer does not depend
    /// on the guess): the search starts at segment `guess` when there is one and it is
    /// nearer than the tree's own guess ([`ChainTree::guess_near`]).
    pub(super) fn closest_in_chain(
        &self,
        p: Point2,
        guess: Option<u32>,
        stats: &mut QueryStats,
    ) -> Nearest {
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
    pub(super) fn describe(&self, p: Point2, n: Nearest) -> ClosestPoint {
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
    pub(super) fn clearance(&self) -> Clearance {
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
    /// ([`Clearance::up_to_over`]).
    pub(super) fn clearance_up_to(&self, farthest: f64) -> Clearance {
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
