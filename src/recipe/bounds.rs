//! The global sizes a caller sets over a recipe's, and the bounds a solution's metric
//! takes from them: what `size`, `adapt` and `batch` give on the command line (`--hmin`,
//! `--hmax`, `--hgrad`), applied here so that no front end edits a recipe's `global`.
//!
//! Precedence, one rule for every caller: a value given over the recipe replaces the
//! recipe's; a solution's metric is bounded by the caller's aspect ratio, else the
//! resulting global values, else defaults from the mesh's extent
//! ([`SolutionHessian::default_bounds`]), its hmax raised to its hmin. The clamp itself is
//! [`SizeBounds`]' alone ([`crate::metric::SizeTensor::clamp`]).

use smartmesh_formats::TaggedMesh;

use super::model::{Global, Recipe};
use crate::metric::SizeBounds;
use crate::sizing::SolutionHessian;

/// Global values set over a recipe's; `None` leaves the recipe's.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GlobalOverrides {
    /// Smallest size anywhere.
    pub h_min: Option<f64>,
    /// Largest size anywhere.
    pub h_max: Option<f64>,
    /// The gradation: `Some(None)` turns the recipe's off.
    pub gradation: Option<Option<f64>>,
}

/// Why the overrides or the bounds cannot be applied.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BoundsError {
    /// An override leaves hmin above hmax.
    #[error("hmin {h_min} exceeds hmax {h_max}")]
    Inverted {
        /// The resulting hmin.
        h_min: f64,
        /// The resulting hmax.
        h_max: f64,
    },
    /// The mesh has no extent to take default bounds from.
    #[error("the mesh has no extent: no metric from a field")]
    NoExtent,
    /// The mesh's extent gives no bounds.
    #[error("the mesh's extent {0} is out of range")]
    Extent(f64),
    /// The bounds are no range of sizes.
    #[error("bounds hmin {h_min}, hmax {h_max}, aspect ratio {ratio} are out of range")]
    OutOfRange {
        /// hmin.
        h_min: f64,
        /// hmax.
        h_max: f64,
        /// The aspect ratio.
        ratio: f64,
    },
}

impl GlobalOverrides {
    /// Whether nothing is set.
    pub fn is_empty(&self) -> bool {
        *self == GlobalOverrides::default()
    }

    /// `global` with these values in place of its own; an override (of hmin or hmax)
    /// that leaves hmin above hmax is refused.
    pub fn apply(&self, global: &Global) -> Result<Global, BoundsError> {
        let mut g = global.clone();
        if let Some(h) = self.h_min {
            g.h_min = Some(h);
        }
        if let Some(h) = self.h_max {
            g.h_max = Some(h);
        }
        if let Some(v) = self.gradation {
            g.gradation = v;
        }
        if let (Some(h_min), Some(h_max)) = (g.h_min, g.h_max) {
            if h_min > h_max && (self.h_min.is_some() || self.h_max.is_some()) {
                return Err(BoundsError::Inverted { h_min, h_max });
            }
        }
        Ok(g)
    }
}

impl Recipe {
    /// This recipe with `overrides` in place of its global values
    /// ([`GlobalOverrides::apply`]).
    pub fn with_overrides(mut self, overrides: &GlobalOverrides) -> Result<Recipe, BoundsError> {
        self.global = overrides.apply(&self.global)?;
        Ok(self)
    }

    /// The bounds of a solution's metric on `mesh`: `max_aspect` where given, else this
    /// recipe's global values, else defaults from the mesh's extent (see the module
    /// documentation).
    pub fn solution_bounds(
        &self,
        mesh: &TaggedMesh,
        max_aspect: Option<f64>,
    ) -> Result<SizeBounds, BoundsError> {
        // The diagonal in space: a planar mesh's z extent is zero.
        let diagonal = mesh
            .bounding_box()
            .map(|(lo, hi)| (hi[0] - lo[0]).hypot(hi[1] - lo[1]).hypot(hi[2] - lo[2]))
            .filter(|d| d.is_finite() && *d > 0.0)
            .ok_or(BoundsError::NoExtent)?;
        let default =
            SolutionHessian::default_bounds(diagonal).ok_or(BoundsError::Extent(diagonal))?;
        let g = &self.global;
        let h_min = g.h_min.unwrap_or(default.h_min());
        let h_max = g.h_max.unwrap_or(default.h_max()).max(h_min);
        let ratio = max_aspect.or(g.max_aspect_ratio).unwrap_or(default.max_aspect_ratio());
        SizeBounds::try_new(h_min, h_max, ratio).ok_or(BoundsError::OutOfRange {
            h_min,
            h_max,
            ratio,
        })
    }
}
