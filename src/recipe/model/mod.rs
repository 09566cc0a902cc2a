//! The recipe model: one validated description of a sizing recipe, whatever file it came
//! from (libconfig as in thesis appendix A, TOML or JSON).
//!
//! The model is the serde form: TOML and JSON map onto it field by field, the libconfig
//! reader ([`super::appendix`]) translates the appendix keywords into it. An algorithm
//! is a line of the algorithm table ([`crate::sizing::algorithms::TABLE`]) with a value
//! per parameter its declaration lists: nothing here names an algorithm. Names are kept
//! (regions, polylines, functions are looked up by name); tags are not yet looked up:
//! [`super::resolve`] does that against one mesh. Beside the model, a table of places
//! remembers the file and line of every item and key, so that errors found later (a
//! misspelt function name, a tag absent from the mesh) still point into the file.

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

pub use crate::sizing::algorithms::{FunctionKind, PolylinePoints};
use crate::sizing::{CurvatureToSize, DistanceFunction, FunctionError, SizeProjectionFunction};

mod algorithm;
mod io;
mod places;
mod validate;

pub use algorithm::{AlgorithmSpec, SpecValue};
pub(crate) use places::Places;

/// The file formats of a recipe.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RecipeFormat {
    /// libconfig, through the C preprocessor when it holds directives (thesis appendix A).
    Libconfig,
    /// TOML.
    Toml,
    /// JSON.
    Json,
}

impl RecipeFormat {
    /// The format an extension tells: `.cfg`, `.conf`, `.libconfig` → libconfig,
    /// `.toml`, `.json`.
    pub fn from_path(path: &Path) -> Option<RecipeFormat> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "cfg" | "conf" | "libconfig" => Some(RecipeFormat::Libconfig),
            "toml" => Some(RecipeFormat::Toml),
            "json" => Some(RecipeFormat::Json),
            _ => None,
        }
    }

    /// The format by name (`libconfig`/`cfg`, `toml`, `json`).
    pub fn from_name(name: &str) -> Option<RecipeFormat> {
        match name.to_ascii_lowercase().as_str() {
            "libconfig" | "cfg" | "conf" => Some(RecipeFormat::Libconfig),
            "toml" => Some(RecipeFormat::Toml),
            "json" => Some(RecipeFormat::Json),
            _ => None,
        }
    }
}

/// Global settings: the clamp on every size and the optional gradation pass.
///
/// libconfig keys (top level): `HMIN`, `HMAX`, `MAX_ASPECT_RATIO`, `GRADATION` (also
/// `H_MIN`, `H_MAX`). TOML/JSON: a `[global]` (or `[mesh]`) table with `hmin`, `hmax`,
/// `max_aspect_ratio`, `gradation` (also `h_min`, `h_max`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Global {
    /// Smallest size anywhere.
    #[serde(rename = "hmin", alias = "h_min", default, skip_serializing_if = "Option::is_none")]
    pub h_min: Option<f64>,
    /// Largest size anywhere, and the size where no algorithm reaches.
    #[serde(rename = "hmax", alias = "h_max", default, skip_serializing_if = "Option::is_none")]
    pub h_max: Option<f64>,
    /// Largest ratio between the two sizes of a tensor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_aspect_ratio: Option<f64>,
    /// Growth factor of the optional gradation pass (thesis 7.4.1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gradation: Option<f64>,
}

impl Global {
    fn is_empty(&self) -> bool {
        *self == Global::default()
    }
}

/// A topological entity as a recipe names it: a tag number or a tag name (the topology's,
/// which resolves it).
pub use crate::topology::EntityRef;

/// A named size function (thesis 4.3.5), parameters as given.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum FunctionSpec {
    /// `CREATE_DISTANCE_FUNCTIONS`: see [`DistanceFunction`].
    Distance {
        /// MINSIZE / MIN_SIZE / SIZE_AT_BORDER.
        size_at_source: f64,
        /// MAXSIZE / MAX_SIZE / SIZE_AT_MAX_DISTANCE.
        size_at_max_distance: f64,
        /// MAXDISTANCE / MAX_DISTANCE.
        max_distance: f64,
        /// EXPONENT.
        exponent: f64,
    },
    /// `CREATE_PROJECTION_FUNCTIONS`: see [`SizeProjectionFunction`].
    Projection {
        /// MAXSIZE / MAX_SIZE / SIZE_AT_MAX_DISTANCE.
        size_at_max_distance: f64,
        /// MAXDISTANCE / MAX_DISTANCE.
        max_distance: f64,
        /// EXPONENT.
        exponent: f64,
    },
    /// `CREATE_CURVATURE_TO_SIZE_FUNCTIONS`: see [`CurvatureToSize`].
    CurvatureToSize {
        /// MINSIZE / MIN_SIZE.
        min_size: f64,
        /// MAXSIZE / MAX_SIZE.
        max_size: f64,
        /// SIZE_OF_ERROR.
        size_of_error: f64,
    },
}

impl FunctionSpec {
    /// `distance`, `projection` or `curvature-to-size`.
    pub fn kind_name(&self) -> &'static str {
        match self {
            FunctionSpec::Distance { .. } => "distance",
            FunctionSpec::Projection { .. } => "projection",
            FunctionSpec::CurvatureToSize { .. } => "curvature-to-size",
        }
    }

    /// Builds a distance function.
    pub fn distance(&self) -> Option<Result<DistanceFunction, FunctionError>> {
        match *self {
            FunctionSpec::Distance {
                size_at_source,
                size_at_max_distance,
                max_distance,
                exponent,
            } => Some(DistanceFunction::try_new(
                size_at_source,
                size_at_max_distance,
                max_distance,
                exponent,
            )),
            _ => None,
        }
    }

    /// Builds a projection function.
    pub fn projection(&self) -> Option<Result<SizeProjectionFunction, FunctionError>> {
        match *self {
            FunctionSpec::Projection { size_at_max_distance, max_distance, exponent } => {
                Some(SizeProjectionFunction::try_new(size_at_max_distance, max_distance, exponent))
            }
            _ => None,
        }
    }

    /// Builds a curvature-to-size function.
    pub fn curvature(&self) -> Option<Result<CurvatureToSize, FunctionError>> {
        match *self {
            FunctionSpec::CurvatureToSize { min_size, max_size, size_of_error } => {
                Some(CurvatureToSize::try_new(min_size, max_size, size_of_error))
            }
            _ => None,
        }
    }

    fn check(&self) -> Result<(), FunctionError> {
        match self {
            FunctionSpec::Distance { .. } => self.distance().map(|r| r.map(|_| ())),
            FunctionSpec::Projection { .. } => self.projection().map(|r| r.map(|_| ())),
            FunctionSpec::CurvatureToSize { .. } => self.curvature().map(|r| r.map(|_| ())),
        }
        .unwrap_or(Ok(()))
    }
}

/// Whether function `f` is of kind `kind`.
fn accepts(kind: FunctionKind, f: &FunctionSpec) -> bool {
    matches!(
        (kind, f),
        (FunctionKind::Distance, FunctionSpec::Distance { .. })
            | (FunctionKind::Projection, FunctionSpec::Projection { .. })
            | (FunctionKind::Curvature, FunctionSpec::CurvatureToSize { .. })
    )
}

/// A sizing recipe: global bounds, named regions, polylines and functions, and the
/// ordered algorithms that use them. Validated: every name an algorithm uses exists and
/// is of the right kind, every function's parameters are in range.
///
/// Two recipes are equal when their content is, wherever they were read from.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Recipe {
    /// Global bounds and gradation (`[global]` or `[mesh]`).
    #[serde(default, alias = "mesh", skip_serializing_if = "Global::is_empty")]
    pub global: Global,
    /// Regions: name → tag numbers or tag names of entities of one dimension.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub regions: BTreeMap<String, Vec<EntityRef>>,
    /// Polylines: name → points, every one `[x, y]` or every one `[x, y, z]` (for
    /// DISTANCE_TO_IMAGINARY_POLYLINE on a planar mesh or on a mesh in space).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub polylines: BTreeMap<String, PolylinePoints>,
    /// Functions: name → function (one namespace for the three kinds).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub functions: BTreeMap<String, FunctionSpec>,
    /// The algorithms, in the order they run.
    #[serde(default)]
    pub algorithms: Vec<AlgorithmSpec>,
    /// The boundary-layer skin `adapt` inserts after the loop ([`super::LayerSpec`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub layer: Option<super::LayerSpec>,
    /// Periodic pairs of sides, kept matching through remeshing ([`super::PeriodicSpec`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub periodic: Vec<super::PeriodicSpec>,
    #[serde(skip)]
    pub(crate) places: Places,
}

impl PartialEq for Recipe {
    fn eq(&self, other: &Recipe) -> bool {
        self.global == other.global
            && self.regions == other.regions
            && self.polylines == other.polylines
            && self.functions == other.functions
            && self.algorithms == other.algorithms
            && self.layer == other.layer
            && self.periodic == other.periodic
    }
}

/// The `n`-th algorithm (1-based) as messages name it.
pub(crate) fn referrer(i: usize) -> String {
    format!("algorithm {}", i + 1)
}

impl Recipe {
    /// The recipe's periodic pairs, those its checks accepted
    /// ([`super::PeriodicSpec::pair`]).
    pub fn periodic_pairs(&self) -> Vec<crate::periodic::PeriodicPair> {
        self.periodic.iter().filter_map(|p| p.pair().ok()).collect()
    }
}
