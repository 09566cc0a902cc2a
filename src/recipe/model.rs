//! The recipe model: one validated description of a sizing recipe, whatever file it came
//! from (libconfig as in thesis appendix A, TOML or JSON).
//!
//! The model is the serde form: TOML and JSON map onto it field by field, the libconfig
//! reader ([`super::appendix`]) translates the appendix keywords into it. Names are kept
//! (regions, polylines, functions are looked up by name); tags are not yet looked up:
//! [`super::resolve`] does that against one mesh. Beside the model, a table of places
//! remembers the file and line of every item and key, so that errors found later (a
//! misspelt function name, a tag absent from the mesh) still point into the file.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::{RecipeError, RecipeErrorKind};
use super::suggest::nearest;
use crate::metric::SizeTensor;
use crate::sizing::{CurvatureToSize, DistanceFunction, FunctionError, SizeProjectionFunction};

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

/// A topological entity as a recipe names it: a tag number or a tag name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum EntityRef {
    /// A tag number (Gmsh physical or elementary tag, Triangle marker…).
    Tag(i32),
    /// A tag name (Gmsh physical name, OBJ group…).
    Name(String),
}

impl std::fmt::Display for EntityRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EntityRef::Tag(t) => write!(f, "tag {t}"),
            EntityRef::Name(n) => write!(f, "\"{n}\""),
        }
    }
}

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

/// One algorithm of the recipe (thesis 4.3.6–4.3.7, appendix A.1.5), names unresolved.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum AlgorithmSpec {
    /// UNIFORM.
    #[serde(alias = "UNIFORM")]
    Uniform {
        /// SIZE.
        size: f64,
        /// REGIONS.
        regions: Vec<String>,
    },
    /// DISTANCE_TO_POINT.
    #[serde(alias = "DISTANCE_TO_POINT")]
    DistanceToPoint {
        /// FUNCTION: a distance function.
        function: String,
        /// REGIONS.
        regions: Vec<String>,
    },
    /// DISTANCE_TO_BORDER.
    #[serde(alias = "DISTANCE_TO_BORDER")]
    DistanceToBorder {
        /// PERPENDICULAR_FUNCTION: a distance function.
        perpendicular: String,
        /// PARALLEL_FUNCTION: a distance function.
        parallel: String,
        /// REGIONS.
        regions: Vec<String>,
    },
    /// CURVATURE_OF_BORDER.
    #[serde(alias = "CURVATURE_OF_BORDER")]
    CurvatureOfBorder {
        /// PERPENDICULAR_FUNCTION: a distance function.
        perpendicular: String,
        /// CURVATURE_TO_SIZE_FUNCTION.
        curvature_to_size: String,
        /// PROJECTION_FUNCTION.
        projection: String,
        /// REGIONS.
        regions: Vec<String>,
    },
    /// DISTANCE_BETWEEN_TWO_BORDERS.
    #[serde(alias = "DISTANCE_BETWEEN_TWO_BORDERS")]
    DistanceBetweenTwoBorders {
        /// PERPENDICULAR_FUNCTION: a distance function.
        perpendicular: String,
        /// PARALLEL_FUNCTION: a distance function.
        parallel: String,
        /// REGIONS: the first border.
        regions: Vec<String>,
        /// REGIONS2: the second border.
        #[serde(alias = "regions2")]
        second_regions: Vec<String>,
    },
    /// DISTANCE_TO_IMAGINARY_POLYLINE.
    #[serde(alias = "DISTANCE_TO_IMAGINARY_POLYLINE")]
    DistanceToImaginaryPolyline {
        /// PERPENDICULAR_FUNCTION: a distance function.
        perpendicular: String,
        /// POLYLINE_DISTANCE_FUNCTION: a distance function of the curvilinear abscissa.
        polyline_distance: String,
        /// PARALLEL_PROJECTION_FUNCTION / PROJECTION_FUNCTION.
        projection: String,
        /// COORDINATES: a polyline name.
        polyline: String,
        /// REGIONS: faces where it applies; empty for everywhere.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        regions: Vec<String>,
    },
}

impl AlgorithmSpec {
    /// The appendix keyword (`DISTANCE_TO_BORDER`).
    pub fn keyword(&self) -> &'static str {
        match self {
            AlgorithmSpec::Uniform { .. } => "UNIFORM",
            AlgorithmSpec::DistanceToPoint { .. } => "DISTANCE_TO_POINT",
            AlgorithmSpec::DistanceToBorder { .. } => "DISTANCE_TO_BORDER",
            AlgorithmSpec::CurvatureOfBorder { .. } => "CURVATURE_OF_BORDER",
            AlgorithmSpec::DistanceBetweenTwoBorders { .. } => "DISTANCE_BETWEEN_TWO_BORDERS",
            AlgorithmSpec::DistanceToImaginaryPolyline { .. } => "DISTANCE_TO_IMAGINARY_POLYLINE",
        }
    }

    /// Every region list with its model field name.
    pub fn region_lists(&self) -> Vec<(&'static str, &[String])> {
        match self {
            AlgorithmSpec::Uniform { regions, .. }
            | AlgorithmSpec::DistanceToPoint { regions, .. }
            | AlgorithmSpec::DistanceToBorder { regions, .. }
            | AlgorithmSpec::CurvatureOfBorder { regions, .. }
            | AlgorithmSpec::DistanceToImaginaryPolyline { regions, .. } => {
                vec![("regions", regions)]
            }
            AlgorithmSpec::DistanceBetweenTwoBorders { regions, second_regions, .. } => {
                vec![("regions", regions), ("second_regions", second_regions)]
            }
        }
    }

    /// Every function it names: (model field, name, kind needed).
    pub fn function_refs(&self) -> Vec<(&'static str, &str, FunctionKind)> {
        use FunctionKind::*;
        match self {
            AlgorithmSpec::Uniform { .. } => vec![],
            AlgorithmSpec::DistanceToPoint { function, .. } => {
                vec![("function", function, Distance)]
            }
            AlgorithmSpec::DistanceToBorder { perpendicular, parallel, .. }
            | AlgorithmSpec::DistanceBetweenTwoBorders { perpendicular, parallel, .. } => {
                vec![("perpendicular", perpendicular, Distance), ("parallel", parallel, Distance)]
            }
            AlgorithmSpec::CurvatureOfBorder {
                perpendicular,
                curvature_to_size,
                projection,
                ..
            } => {
                vec![
                    ("perpendicular", perpendicular, Distance),
                    ("curvature_to_size", curvature_to_size, Curvature),
                    ("projection", projection, Projection),
                ]
            }
            AlgorithmSpec::DistanceToImaginaryPolyline {
                perpendicular,
                polyline_distance,
                projection,
                ..
            } => {
                vec![
                    ("perpendicular", perpendicular, Distance),
                    ("polyline_distance", polyline_distance, Distance),
                    ("projection", projection, Projection),
                ]
            }
        }
    }
}

/// The kind of function a key needs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FunctionKind {
    /// A distance function.
    Distance,
    /// A projection function.
    Projection,
    /// A curvature-to-size function.
    Curvature,
}

impl FunctionKind {
    fn name(self) -> &'static str {
        match self {
            FunctionKind::Distance => "distance",
            FunctionKind::Projection => "projection",
            FunctionKind::Curvature => "curvature-to-size",
        }
    }

    fn accepts(self, f: &FunctionSpec) -> bool {
        matches!(
            (self, f),
            (FunctionKind::Distance, FunctionSpec::Distance { .. })
                | (FunctionKind::Projection, FunctionSpec::Projection { .. })
                | (FunctionKind::Curvature, FunctionSpec::CurvatureToSize { .. })
        )
    }
}

/// Where an item or a key of the model was written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Place {
    /// Index into [`Places::files`].
    pub file: usize,
    /// 1-based line (0 when unknown).
    pub line: usize,
    /// The key as the file spells it (`MAXDISTANCE`, `max_distance`).
    pub key: String,
    /// The enclosing item as the file names it (`CREATE_ALGORITHMS entry 3`).
    pub context: String,
}

/// The places of a recipe's items and keys, by model path: `global.hmin`,
/// `regions.NAME`, `regions.NAME[i]`, `polylines.NAME`, `functions.NAME`,
/// `functions.NAME.FIELD`, `algorithms[i]`, `algorithms[i].FIELD`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Places {
    pub files: Vec<PathBuf>,
    pub by_path: BTreeMap<String, Place>,
}

impl Places {
    pub fn new(origin: &Path) -> Places {
        Places { files: vec![origin.to_path_buf()], by_path: BTreeMap::new() }
    }

    pub fn file_index(&mut self, path: &Path) -> usize {
        match self.files.iter().position(|p| p == path) {
            Some(i) => i,
            None => {
                self.files.push(path.to_path_buf());
                self.files.len() - 1
            }
        }
    }

    pub fn insert(&mut self, path: String, file: &Path, line: usize, key: &str, context: &str) {
        let file = self.file_index(file);
        self.by_path
            .insert(path, Place { file, line, key: key.to_string(), context: context.to_string() });
    }

    /// The place of `path`, or of its nearest enclosing item.
    pub fn find(&self, path: &str) -> Option<&Place> {
        let mut p = path;
        loop {
            if let Some(place) = self.by_path.get(p) {
                return Some(place);
            }
            let cut = p.rfind(['.', '['])?;
            p = &p[..cut];
        }
    }

    /// The key as written at `path`, or `default`.
    pub fn key<'a>(&'a self, path: &str, default: &'a str) -> &'a str {
        self.by_path.get(path).map(|p| p.key.as_str()).unwrap_or(default)
    }

    /// `error`, placed at `path`.
    pub fn locate(&self, error: RecipeError, path: &str) -> RecipeError {
        match self.find(path) {
            Some(place) => {
                let e = error.at(&self.files[place.file], place.line);
                if place.context.is_empty() {
                    e
                } else {
                    e.within(place.context.clone())
                }
            }
            None => match self.files.first() {
                Some(f) => error.in_file(f),
                None => error,
            },
        }
    }
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
    /// Polylines: name → points `[x, y]` (for DISTANCE_TO_IMAGINARY_POLYLINE).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub polylines: BTreeMap<String, Vec<[f64; 2]>>,
    /// Functions: name → function (one namespace for the three kinds).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub functions: BTreeMap<String, FunctionSpec>,
    /// The algorithms, in the order they run.
    #[serde(default)]
    pub algorithms: Vec<AlgorithmSpec>,
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
    }
}

/// The `n`-th algorithm (1-based) as messages name it.
pub(crate) fn referrer(i: usize) -> String {
    format!("algorithm {}", i + 1)
}

impl Recipe {
    /// Reads a recipe; the format comes from the extension (`.cfg`, `.conf`,
    /// `.libconfig`: libconfig through cpp when it holds directives; `.toml`; `.json`).
    pub fn from_path(path: &Path) -> Result<Recipe, RecipeError> {
        let format = RecipeFormat::from_path(path)
            .ok_or_else(|| RecipeError::new(RecipeErrorKind::UnknownFormat).in_file(path))?;
        let text = std::fs::read_to_string(path)
            .map_err(|e| RecipeError::new(RecipeErrorKind::Io(e.to_string())).in_file(path))?;
        Recipe::from_str(&text, format, path)
    }

    /// Reads a recipe from text; `origin` names it in errors and anchors relative
    /// `#include` and `@include` paths.
    #[allow(clippy::should_implement_trait)]
    pub fn from_str(
        text: &str,
        format: RecipeFormat,
        origin: &Path,
    ) -> Result<Recipe, RecipeError> {
        let recipe = match format {
            RecipeFormat::Libconfig => super::appendix::read(text, origin)?,
            RecipeFormat::Toml => super::serde_io::read_toml(text, origin)?,
            RecipeFormat::Json => super::serde_io::read_json(text, origin)?,
        };
        recipe.validate()?;
        Ok(recipe)
    }

    /// The recipe as TOML.
    pub fn to_toml(&self) -> String {
        super::serde_io::write_toml(self)
    }

    /// The recipe as JSON (pretty, newline at the end).
    pub fn to_json(&self) -> String {
        super::serde_io::write_json(self)
    }

    /// The recipe as libconfig, in the keywords of thesis appendix A.
    pub fn to_libconfig(&self) -> String {
        super::appendix::write(self)
    }

    /// The recipe in `format`.
    pub fn to_format(&self, format: RecipeFormat) -> String {
        match format {
            RecipeFormat::Libconfig => self.to_libconfig(),
            RecipeFormat::Toml => self.to_toml(),
            RecipeFormat::Json => self.to_json(),
        }
    }

    /// `error` placed at model path `path`.
    pub(crate) fn error_at(&self, kind: RecipeErrorKind, path: &str) -> RecipeError {
        self.places.locate(RecipeError::new(kind), path)
    }

    /// The key as the recipe's file wrote it at `path`.
    pub(crate) fn written_key<'a>(&'a self, path: &str, default: &'a str) -> &'a str {
        self.places.key(path, default)
    }

    /// Checks names, kinds and ranges.
    pub fn validate(&self) -> Result<(), RecipeError> {
        let g = &self.global;
        for (field, value) in [("hmin", g.h_min), ("hmax", g.h_max)] {
            if let Some(v) = value {
                if !(SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&v) {
                    let key = self.written_key(&format!("global.{field}"), field).to_string();
                    return Err(self.error_at(
                        RecipeErrorKind::Invalid(format!(
                            "{key} = {v} is out of range: expected a size in [1e-30, 1e30]"
                        )),
                        &format!("global.{field}"),
                    ));
                }
            }
        }
        if let (Some(lo), Some(hi)) = (g.h_min, g.h_max) {
            if lo > hi {
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!(
                        "the smallest size ({lo}) exceeds the largest ({hi})"
                    )),
                    "global.hmin",
                ));
            }
        }
        if let Some(r) = g.max_aspect_ratio {
            if !(r.is_finite() && r >= 1.0) {
                let key =
                    self.written_key("global.max_aspect_ratio", "max_aspect_ratio").to_string();
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!(
                        "{key} = {r} is out of range: expected a finite number >= 1"
                    )),
                    "global.max_aspect_ratio",
                ));
            }
        }
        if let Some(r) = g.gradation {
            if !(r.is_finite() && r >= 1.0) {
                let key = self.written_key("global.gradation", "gradation").to_string();
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!(
                        "{key} = {r} is out of range: expected a finite number >= 1"
                    )),
                    "global.gradation",
                ));
            }
        }
        for (name, entities) in &self.regions {
            let path = format!("regions.{name}");
            if name.is_empty() {
                return Err(self.error_at(
                    RecipeErrorKind::Invalid("a region needs a non-empty name".into()),
                    &path,
                ));
            }
            if entities.is_empty() {
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!("region \"{name}\" names no entity")),
                    &path,
                ));
            }
        }
        for (name, points) in &self.polylines {
            let path = format!("polylines.{name}");
            if points.is_empty() {
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!("polyline \"{name}\" has no point")),
                    &path,
                ));
            }
            if let Some(p) = points.iter().find(|p| !p[0].is_finite() || !p[1].is_finite()) {
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!(
                        "polyline \"{name}\" has a point that is not finite: {p:?}"
                    )),
                    &path,
                ));
            }
            if let Some(i) = points.windows(2).position(|w| w[0] == w[1]) {
                return Err(self.error_at(RecipeErrorKind::Invalid(format!("polyline \"{name}\" repeats point {} ({:?}) at once: consecutive points must differ", i + 1, points[i])), &path));
            }
        }
        for (name, f) in &self.functions {
            if let Err(e) = f.check() {
                let (key, shown) = match &e {
                    FunctionError::OutOfRange { parameter, .. } => {
                        (model_field(*parameter), parameter.recipe_key())
                    }
                    FunctionError::MinAboveMax { .. } => ("min_size", "MINSIZE"),
                };
                let path = format!("functions.{name}.{key}");
                let written = self.written_key(&path, key).to_string();
                let mut err = self
                    .error_at(RecipeErrorKind::Function { name: name.clone(), source: e }, &path);
                // The message names the appendix keyword; say so when the file spelt it otherwise.
                if written != shown {
                    err.context = Some(format!("key {written} of function \"{name}\""));
                }
                return Err(err);
            }
        }
        for (i, a) in self.algorithms.iter().enumerate() {
            let base = format!("algorithms[{i}]");
            if let AlgorithmSpec::Uniform { size, .. } = a {
                if !(SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(size) {
                    let key = self.written_key(&format!("{base}.size"), "size").to_string();
                    return Err(self.error_at(
                        RecipeErrorKind::Invalid(format!(
                            "{key} = {size} is out of range: expected a size in [1e-30, 1e30]"
                        )),
                        &format!("{base}.size"),
                    ));
                }
            }
            for (field, name, kind) in a.function_refs() {
                let path = format!("{base}.{field}");
                let key = self.written_key(&path, field).to_string();
                match self.functions.get(name) {
                    None => {
                        let e = self.error_at(
                            RecipeErrorKind::UnknownName {
                                referrer: referrer(i),
                                what: "function",
                                name: name.to_string(),
                            },
                            &path,
                        );
                        let same_kind = self
                            .functions
                            .iter()
                            .filter(|(_, f)| kind.accepts(f))
                            .map(|(n, _)| n.as_str());
                        let any = self.functions.keys().map(String::as_str);
                        let s = nearest(name, same_kind).or_else(|| nearest(name, any));
                        return Err(e.suggest(s.map(|s| format!("\"{s}\""))));
                    }
                    Some(f) if !kind.accepts(f) => {
                        return Err(self.error_at(
                            RecipeErrorKind::WrongFunctionKind {
                                referrer: referrer(i),
                                key,
                                name: name.to_string(),
                                found: f.kind_name(),
                                expected: kind.name(),
                            },
                            &path,
                        ))
                    }
                    Some(_) => {}
                }
            }
            for (field, list) in a.region_lists() {
                let path = format!("{base}.{field}");
                let optional = matches!(a, AlgorithmSpec::DistanceToImaginaryPolyline { .. });
                if list.is_empty() && !optional {
                    let key = self.written_key(&path, field).to_string();
                    return Err(self.error_at(
                        RecipeErrorKind::Invalid(format!("{} {key} names no region", a.keyword())),
                        &path,
                    ));
                }
                for name in list {
                    if !self.regions.contains_key(name) {
                        let e = self.error_at(
                            RecipeErrorKind::UnknownName {
                                referrer: referrer(i),
                                what: "region",
                                name: name.clone(),
                            },
                            &path,
                        );
                        let s = nearest(name, self.regions.keys().map(String::as_str));
                        return Err(e.suggest(s.map(|s| format!("\"{s}\""))));
                    }
                }
            }
            if let AlgorithmSpec::DistanceToImaginaryPolyline { polyline, .. } = a {
                if !self.polylines.contains_key(polyline) {
                    let path = format!("{base}.polyline");
                    let e = self.error_at(
                        RecipeErrorKind::UnknownName {
                            referrer: referrer(i),
                            what: "polyline",
                            name: polyline.clone(),
                        },
                        &path,
                    );
                    let s = nearest(polyline, self.polylines.keys().map(String::as_str));
                    return Err(e.suggest(s.map(|s| format!("\"{s}\""))));
                }
            }
        }
        Ok(())
    }
}

/// The model field of a function parameter (for the place of an out-of-range value).
fn model_field(p: crate::sizing::Parameter) -> &'static str {
    use crate::sizing::Parameter::*;
    match p {
        SizeAtSource => "size_at_source",
        SizeAtMaxDistance => "size_at_max_distance",
        MaxDistance => "max_distance",
        Exponent => "exponent",
        MinSize => "min_size",
        MaxSize => "max_size",
        SizeOfError => "size_of_error",
    }
}
