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

use crate::sizing::algorithms::solution_hessian::SolutionHessian;
pub use crate::sizing::algorithms::{Algorithm, EntitySet};

pub use crate::geometry::Point2;

/// One step of a plan: an algorithm and a label for reports and errors
/// (e.g. `algorithm 3 (DISTANCE_TO_BORDER on "StayVane")`).
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Shown in progress bars, summaries and warnings.
    pub label: String,
    /// What the step does.
    pub algorithm: Algorithm,
    /// The recipe's names of what the step works on (its polyline, else its regions),
    /// for captions; empty for a plan made in code.
    pub names: Vec<String>,
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

impl Step {
    /// The solution-Hessian step made in code (not from a recipe: `size --field`, `adapt
    /// --solver`) of fields `names`, normalised together to `target` in the Lp norm `p`,
    /// their Hessians recovered by `method`, within `bounds`; labelled by
    /// [`SolutionHessian::label`].
    pub fn solution_hessian(
        names: &[String],
        target: crate::sizing::solution::Target,
        p: f64,
        method: crate::sizing::solution::Method,
        bounds: &crate::metric::SizeBounds,
    ) -> Step {
        let algorithm = SolutionHessian {
            fields: names.to_vec(),
            target,
            p,
            method,
            h_min: Some(bounds.h_min()),
            h_max: Some(bounds.h_max()),
            max_aspect: Some(bounds.max_aspect_ratio()),
        };
        Step {
            label: algorithm.label(),
            algorithm: Algorithm::SolutionHessian(algorithm),
            names: names.to_vec(),
        }
    }
}
