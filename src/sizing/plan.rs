//! The sizing plan: what a recipe becomes once it is resolved against one mesh — global
//! bounds, optional gradation, and the ordered list of algorithms with their size
//! functions built and their regions turned into topological entities of that mesh.
//!
//! The recipe readers (libconfig, TOML, JSON) produce a plan; the sizing engine runs
//! one. Keeping the two apart lets a shape optimiser resolve one recipe against many
//! geometric variants, and lets the engine be tested without any recipe text.
//!
//! Entities are indices into [`crate::Topology`]'s `points`, `curves` and `faces` of the
//! mesh the plan was resolved on; running a plan on another mesh is a caller's error.

use crate::sizing::functions::{CurvatureToSize, DistanceFunction, SizeProjectionFunction};

pub use crate::geometry::Point2;

/// Topological entities of one mesh, by index into [`crate::Topology`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EntitySet {
    /// Indices into `Topology::points`.
    pub points: Vec<usize>,
    /// Indices into `Topology::curves`.
    pub curves: Vec<usize>,
    /// Indices into `Topology::faces`.
    pub faces: Vec<usize>,
}

impl EntitySet {
    /// Whether the set names no entity.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty() && self.curves.is_empty() && self.faces.is_empty()
    }

    /// The union of two sets, each list sorted and without repeats.
    pub fn union(&self, other: &EntitySet) -> EntitySet {
        let merge = |a: &[usize], b: &[usize]| {
            let mut v: Vec<usize> = a.iter().chain(b).copied().collect();
            v.sort_unstable();
            v.dedup();
            v
        };
        EntitySet {
            points: merge(&self.points, &other.points),
            curves: merge(&self.curves, &other.curves),
            faces: merge(&self.faces, &other.faces),
        }
    }
}

/// One algorithm of thesis 4.3.6–4.3.7, its functions built and its regions resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum Algorithm {
    /// UNIFORM: isotropic `size` on every vertex of the entities (a face's vertices
    /// include those of its bounding curves and points).
    Uniform {
        /// The size.
        size: f64,
        /// Where it applies.
        on: EntitySet,
    },
    /// DISTANCE_TO_POINT: isotropic size `function(distance)` from the sources' vertices
    /// (topological points; a curve given here contributes its vertices).
    DistanceToPoint {
        /// Size against distance.
        function: DistanceFunction,
        /// The sources.
        sources: EntitySet,
    },
    /// DISTANCE_TO_BORDER: anisotropic; normal size `perpendicular(distance)`, tangent
    /// size `parallel(distance)`, axes normal and tangent to the border at the closest
    /// point.
    DistanceToBorder {
        /// Size normal to the border against distance.
        perpendicular: DistanceFunction,
        /// Size tangent to the border against distance.
        parallel: DistanceFunction,
        /// The border curves (points are point sources).
        borders: EntitySet,
    },
    /// CURVATURE_OF_BORDER: tangent size from the border's curvature through
    /// `curvature`, carried inward with `projection`; normal size `perpendicular(distance)`.
    CurvatureOfBorder {
        /// Size normal to the border against distance.
        perpendicular: DistanceFunction,
        /// Tangent size on the border against curvature.
        curvature: CurvatureToSize,
        /// How the tangent size on the border grows with distance.
        projection: SizeProjectionFunction,
        /// The border curves.
        borders: EntitySet,
    },
    /// DISTANCE_BETWEEN_TWO_BORDERS: sizes from the local thickness d1 + d2 between
    /// `first` and `second` (thesis figure 4.6).
    DistanceBetweenTwoBorders {
        /// Size normal to the gap against thickness.
        perpendicular: DistanceFunction,
        /// Size along the gap against thickness.
        parallel: DistanceFunction,
        /// The first border (REGIONS).
        first: EntitySet,
        /// The second border (REGIONS2).
        second: EntitySet,
    },
    /// DISTANCE_TO_IMAGINARY_POLYLINE: a user polyline (wake, shock); normal size
    /// `perpendicular(distance)`, tangent size `polyline_distance(abscissa)` projected
    /// with `projection`.
    DistanceToImaginaryPolyline {
        /// Size normal to the polyline against distance.
        perpendicular: DistanceFunction,
        /// Tangent size on the polyline against curvilinear abscissa from its first point.
        polyline_distance: DistanceFunction,
        /// How the tangent size grows away from the polyline.
        projection: SizeProjectionFunction,
        /// The polyline, at least one point; consecutive points distinct.
        polyline: Vec<Point2>,
        /// Where the algorithm applies (faces); empty means everywhere.
        within: EntitySet,
    },
}

impl Algorithm {
    /// The recipe keyword of the algorithm (appendix A).
    pub fn keyword(&self) -> &'static str {
        match self {
            Algorithm::Uniform { .. } => "UNIFORM",
            Algorithm::DistanceToPoint { .. } => "DISTANCE_TO_POINT",
            Algorithm::DistanceToBorder { .. } => "DISTANCE_TO_BORDER",
            Algorithm::CurvatureOfBorder { .. } => "CURVATURE_OF_BORDER",
            Algorithm::DistanceBetweenTwoBorders { .. } => "DISTANCE_BETWEEN_TWO_BORDERS",
            Algorithm::DistanceToImaginaryPolyline { .. } => "DISTANCE_TO_IMAGINARY_POLYLINE",
        }
    }
}

/// One step of a plan: an algorithm and a label for reports and errors
/// (e.g. `algorithm 3 (DISTANCE_TO_BORDER on "StayVane")`).
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Shown in progress bars, summaries and warnings.
    pub label: String,
    /// What the step does.
    pub algorithm: Algorithm,
}

/// A resolved recipe, ready to run on the mesh it was resolved against.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SizingPlan {
    /// Smallest size allowed anywhere (global clamp), if any.
    pub h_min: Option<f64>,
    /// Largest size allowed anywhere, and the size of vertices no step reaches. When
    /// absent, unreached vertices get the bounding-box diagonal (with a warning).
    pub h_max: Option<f64>,
    /// Largest ratio of the two sizes of a tensor, if any.
    pub max_aspect_ratio: Option<f64>,
    /// Gradation: the largest growth factor of sizes per unit of metric length between
    /// neighbours, if the optional gradation pass runs (thesis 7.4.1).
    pub gradation: Option<f64>,
    /// The algorithms, run in this order; each tensor is intersected into the vertex's
    /// current one.
    pub steps: Vec<Step>,
}
