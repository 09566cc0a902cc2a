//! The starting mesh: a constrained Delaunay triangulation of a planar straight-line graph
//! with quality refinement, as Triangle's `-pq` makes it (thesis 5.4: the SmartMesh loop
//! starts from such a mesh).
//!
//! The graph is a Triangle `.poly` (segments with boundary markers, holes, regions with
//! attributes and area bounds) or the Line cells of any tagged mesh. The triangulation
//! and the Ruppert/Chew refinement are spade's (`ConstrainedDelaunayTriangulation`,
//! `refine`); this module adds what Triangle does around them and spade does not: carving
//! the outside and the holes, regional attributes as face tags, per-region area bounds,
//! segment markers carried to the pieces of the split segments, and the corners of the
//! boundary as Vertex cells.
//!
//! Inside (private modules, one job each):
//! - `pslg` takes the graph out of a mesh and refuses what cannot be meshed;
//! - `refine` builds and refines the triangulation;
//! - `domain` labels triangles outside, in holes, or in a region (flood fills);
//! - `assemble` writes the result as a [`TaggedMesh`].
//!
//! How a mesh that is not a `.poly` is read as a graph: its Line cells (second-order
//! lines by their end points) are the segments and its Vertex cells are kept as corners
//! with their tags; its surface cells are not meshed again, but the centroid of each is a
//! region seed with the cell's tag, and what no centroid reaches is carved (so the inside
//! of a cylinder is a hole without a hole point). Only the points these cells use are
//! vertices of the graph.
//!
//! What spade guarantees, and so what we do: every triangle of the domain has its smallest
//! angle above the bound, except next to input angles too small to be improved (two
//! segments meeting at an acute angle, where spade stops splitting); the triangulation is
//! constrained Delaunay; no domain triangle is larger than the area bound (spade's own
//! bound, then our pass for per-region bounds). Segments are split by spade at their
//! middle the first time and then at powers of two from their ends (Ruppert's remedy
//! against runaway encroachment); the pieces keep the segment's tags.

mod assemble;
mod domain;
mod periodic;
mod pslg;
mod refine;

pub use periodic::triangulate_periodic;

use smartmesh_formats::TaggedMesh;

/// spade's constrained triangulation with plain points.
pub(crate) type Cdt = spade::ConstrainedDelaunayTriangulation<spade::Point2<f64>>;

/// How to mesh. `Default` is Triangle's `-pq` with spade's termination-safe angle:
/// minimum angle 20.7°, no area bound, outside of the segments carved.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshOptions {
    /// Smallest angle wanted in every triangle, degrees (0 to 34; 0 turns angle
    /// refinement off). Ruppert's algorithm provably terminates up to 20.7°; above about
    /// 30° spade may not, and stops at [`MeshOptions::max_vertices`].
    pub min_angle_deg: f64,
    /// Largest triangle area (Triangle's `a`).
    pub max_area: Option<f64>,
    /// Uniform target edge length `h`. It becomes the area bound √3/4·h², the area of the
    /// equilateral triangle of side `h`: no triangle is larger than it, so edges come out
    /// at or somewhat below `h`. With `max_area` too, the smaller bound wins.
    pub size: Option<f64>,
    /// Keep every triangle of the convex hull (Triangle's `c`) instead of carving the
    /// outside of the segments. Holes are carved either way.
    pub keep_convex_hull: bool,
    /// A boundary vertex where the two Line cells meeting there turn by more than this
    /// angle (degrees away from straight) is a corner and gets a Vertex cell.
    pub corner_angle_deg: f64,
    /// Most vertices the mesh may have; refinement stops with an error beyond. `None`:
    /// ten times the input's, plus four per area bound over the convex hull, plus 10 000,
    /// at most [`DEFAULT_MAX_VERTICES`]. Whatever it is, a graph whose area bounds ask for
    /// more vertices than the larger of it and [`DEFAULT_MAX_VERTICES`] is refused before
    /// refinement starts ([`MeshError::TooManyVertices`]).
    pub max_vertices: Option<usize>,
}

/// Vertices a mesh may have unless the caller allows more: 5·10⁶. The peak memory of
/// `smartmesh mesh` grows by about 0.45 KB per vertex (measured with `/usr/bin/time -f
/// %M` on `fixtures/square_hole.poly --size 0.005` and `0.0025`: 69 000 → 276 000
/// vertices, 49 → 141 MB), so the default keeps a run near 2.5 GB.
pub const DEFAULT_MAX_VERTICES: usize = 5_000_000;

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            min_angle_deg: 20.7,
            max_area: None,
            size: None,
            keep_convex_hull: false,
            corner_angle_deg: 30.0,
            max_vertices: None,
        }
    }
}

impl MeshOptions {
    /// The global area bound: `max_area`, or the one `size` gives, whichever is smaller.
    pub fn area_bound(&self) -> Option<f64> {
        let from_size = self.size.map(size_to_area);
        match (self.max_area, from_size) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Refuses angles outside [0, 34], and area bounds or sizes that are not positive.
    pub fn validate(&self) -> Result<(), MeshError> {
        if !(0.0..=34.0).contains(&self.min_angle_deg) {
            return Err(MeshError::BadOption {
                what: format!("minimum angle {} (expected 0 to 34 degrees)", self.min_angle_deg),
            });
        }
        if let Some(a) = self.max_area {
            if !(a > 0.0 && a.is_finite()) {
                return Err(MeshError::BadOption {
                    what: format!("maximum area {a} (expected a positive number)"),
                });
            }
        }
        if let Some(h) = self.size {
            if !(h > 0.0 && h.is_finite()) {
                return Err(MeshError::BadOption {
                    what: format!("size {h} (expected a positive edge length)"),
                });
            }
        }
        if !(0.0..180.0).contains(&self.corner_angle_deg) {
            return Err(MeshError::BadOption {
                what: format!("corner angle {} (expected 0 to 180 degrees)", self.corner_angle_deg),
            });
        }
        Ok(())
    }
}

/// The area of the equilateral triangle of side `h`, √3/4·h²: the area bound that a
/// uniform size `h` stands for.
pub fn size_to_area(h: f64) -> f64 {
    3f64.sqrt() / 4.0 * h * h
}

/// Why a graph could not be meshed. Point numbers are 0-based indices into the input
/// mesh's points (the order of the file); segment, region and hole numbers are 1-based,
/// in the order of the file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// An option out of range.
    #[error("bad option: {what}")]
    BadOption {
        /// The option and what was expected.
        what: String,
    },
    /// A cell refers to a point that does not exist.
    #[error("a cell refers to point {index}, but there are {points} points")]
    BadIndex {
        /// The index.
        index: usize,
        /// Number of points.
        points: usize,
    },
    /// A point with a NaN or infinite coordinate.
    #[error("point {point} has a non-finite coordinate")]
    NonFinite {
        /// The point.
        point: usize,
    },
    /// Points in more than one plane z = const ([`crate::plane`]).
    #[error("{0}")]
    NotPlanar(crate::planar::NotPlanar),
    /// Two points at the same place.
    #[error("points {first} and {second} are both at ({}, {}); expected distinct vertices", at[0], at[1])]
    DuplicatePoint {
        /// The first.
        first: usize,
        /// The second.
        second: usize,
        /// Where.
        at: [f64; 2],
    },
    /// A segment from a point to itself.
    #[error(
        "segment {segment} starts and ends at point {point}; expected two distinct end points"
    )]
    ZeroLengthSegment {
        /// The segment.
        segment: usize,
        /// Its point.
        point: usize,
    },
    /// The same two points joined twice.
    #[error("segment {second} joins the same two points as segment {first}")]
    DuplicateSegment {
        /// The first.
        first: usize,
        /// The repeat.
        second: usize,
    },
    /// Two segments cross at a point that is not an end of both.
    #[error("segment {segment} crosses {}; segments may only meet at their end points (split them there)", other.map_or("another segment".to_string(), |o| format!("segment {o}")))]
    SegmentsCross {
        /// A segment that crosses another.
        segment: usize,
        /// The other, when found.
        other: Option<usize>,
    },
    /// Two collinear segments that overlap.
    #[error("segments {first} and {second} overlap along a line")]
    SegmentsOverlap {
        /// The first.
        first: usize,
        /// The second.
        second: usize,
    },
    /// A region seed in no triangle of the domain.
    #[error("region {region}'s point ({}, {}) is outside the domain (outside the segments or in a hole)", point[0], point[1])]
    RegionOutside {
        /// The region.
        region: usize,
        /// Its point.
        point: [f64; 2],
    },
    /// A hole or region point on a segment or a vertex: which side it means is unclear.
    #[error("{what} {number}'s point ({}, {}) lies on a segment or a vertex; expected a point strictly inside", point[0], point[1])]
    SeedOnSegment {
        /// `hole` or `region`.
        what: &'static str,
        /// Its number.
        number: usize,
        /// Its point.
        point: [f64; 2],
    },
    /// A hole or region point with a NaN or infinite coordinate (or a region with such an
    /// attribute).
    #[error("{what} {number} has a non-finite coordinate or attribute")]
    NonFiniteSeed {
        /// `hole` or `region`.
        what: &'static str,
        /// Its number.
        number: usize,
    },
    /// Nothing is left once the outside and the holes are carved.
    #[error("nothing to mesh: the segments enclose no area outside the holes (an open graph needs keep_convex_hull, Triangle's `c`)")]
    NothingToMesh,
    /// Coordinates that spade cannot triangulate (too large, too small).
    #[error("coordinates spade cannot triangulate: {reason}")]
    Coordinates {
        /// spade's reason.
        reason: String,
    },
    /// The area bounds ask for more vertices than the limit: refused before refining.
    #[error("the area bounds ask for about {} vertices, more than the limit of {limit}; raise it with --max-vertices (max_vertices), or use a larger --size or --max-area", crate::metric::complexity::format_count(*estimate))]
    TooManyVertices {
        /// Expected vertices.
        estimate: f64,
        /// The limit.
        limit: usize,
    },
    /// Refinement reached the vertex budget before meeting the bounds.
    #[error("refinement stopped at {vertices} vertices before meeting the bounds; lower the minimum angle (20.7 degrees always terminates), raise the area bound, or allow more vertices (max_vertices, `--max-vertices`)")]
    RefinementIncomplete {
        /// Vertices when it stopped.
        vertices: usize,
    },
    /// A periodic pair that names no curve of the graph, or whose sides are not images
    /// of each other by its transform.
    #[error(transparent)]
    Periodic(#[from] crate::periodic::PeriodicError),
    /// The refinement kept splitting the two sides of a periodic pair differently.
    #[error("periodic pair {pair}: the sides' vertices still differ after {rounds} triangulations (the refinement splits one side's segments where it does not split the other's); try a smaller --min-angle or a --size that meshes the sides finer")]
    PeriodicUnsettled {
        /// The pair, as `PeriodicPair::label` names it.
        pair: String,
        /// Triangulations made.
        rounds: usize,
    },
    /// A bug: something the mesher relies on did not hold.
    #[error("internal error: {reason}")]
    Internal {
        /// What.
        reason: String,
    },
}

/// The input item a [`MeshError`] is about, so that a caller holding the file can name its
/// line (see `formats::triangle::poly_lines`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subject {
    /// A point, 0-based (the input mesh's point order, the file's vertex order).
    Point(usize),
    /// A segment (Line cell), 1-based in file order.
    Segment(usize),
    /// A hole, 1-based.
    Hole(usize),
    /// A region, 1-based.
    Region(usize),
}

impl MeshError {
    /// The input item the error is about, if it is about one.
    pub fn subject(&self) -> Option<Subject> {
        use MeshError::*;
        Some(match *self {
            NonFinite { point } => Subject::Point(point),
            NotPlanar(crate::planar::NotPlanar::OffPlane { point, .. }) => Subject::Point(point),
            NotPlanar(crate::planar::NotPlanar::Volume { .. }) => return None,
            DuplicatePoint { second, .. } => Subject::Point(second),
            ZeroLengthSegment { segment, .. } | SegmentsCross { segment, .. } => {
                Subject::Segment(segment)
            }
            DuplicateSegment { second, .. } | SegmentsOverlap { second, .. } => {
                Subject::Segment(second)
            }
            RegionOutside { region, .. } => Subject::Region(region),
            SeedOnSegment { what, number, .. } | NonFiniteSeed { what, number } => {
                if what == "hole" {
                    Subject::Hole(number)
                } else {
                    Subject::Region(number)
                }
            }
            _ => return None,
        })
    }

    /// Whether the input (or the options) is at fault, rather than the meshing.
    pub fn is_input_error(&self) -> bool {
        !matches!(
            self,
            MeshError::RefinementIncomplete { .. }
                | MeshError::Internal { .. }
                | MeshError::PeriodicUnsettled { .. }
        )
    }
}

/// Meshes the planar straight-line graph of `pslg`: a Triangle `.poly` (segments, holes,
/// regions) or the Line cells of any mesh (the module docs say how a mesh is read as a
/// graph). Returns counter-clockwise triangles tagged with their regional attribute (0
/// outside every region; when the attributes are reals that are not all integers, as
/// Triangle allows, every tag is 0 and the attributes are cell data
/// `triangle:attribute1`, 0 outside every region and on Line and Vertex cells), each input segment as Line cells with its tags, Vertex cells at
/// the corners, and the input's tag names (not its holes and region seeds: the triangles'
/// tags say where the regions are). Deterministic: the same input
/// and options give the same mesh.
pub fn triangulate(pslg: &TaggedMesh, opts: &MeshOptions) -> Result<TaggedMesh, MeshError> {
    opts.validate()?;
    let graph = pslg::extract(pslg)?;
    let mut cdt = refine::build(&graph)?;
    let domain = refine::refine(&mut cdt, &graph, opts)?;
    assemble::assemble(&cdt, &domain, &graph, pslg, opts)
}

/// The vertices [`triangulate`] is expected to make for the area bounds of `opts` and of
/// the regions (what [`MeshOptions::max_vertices`] is compared with before refining), or
/// `None` when no area bound applies (angle refinement alone adds a bounded number).
pub fn expected_vertices(pslg: &TaggedMesh, opts: &MeshOptions) -> Result<Option<f64>, MeshError> {
    opts.validate()?;
    let graph = pslg::extract(pslg)?;
    let cdt = refine::build(&graph)?;
    let labels = domain::classify(&cdt, &graph, opts.keep_convex_hull)?;
    Ok(refine::expected_vertices(&cdt, &labels, opts.area_bound(), &graph))
}
