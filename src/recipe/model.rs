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
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::error::{RecipeError, RecipeErrorKind};
use super::preprocess::ReadOptions;
use super::suggest::nearest;
use crate::metric::SizeTensor;
pub use crate::sizing::algorithms::FunctionKind;
use crate::sizing::algorithms::{
    infinite_norm, Entry, Given, Parameter, ParameterKind, INFINITE_NORM, TABLE,
};
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

/// Refuses the characters that look like a space or like nothing (pasted from a web
/// page or a word processor), naming the character and its line: a parser would quote
/// them invisibly, or not at all.
fn invisible_characters(text: &str, origin: &Path) -> Result<(), RecipeError> {
    const NAMES: [(char, &str); 6] = [
        ('\u{a0}', "U+00A0 NO-BREAK SPACE"),
        ('\u{200b}', "U+200B ZERO WIDTH SPACE"),
        ('\u{200c}', "U+200C ZERO WIDTH NON-JOINER"),
        ('\u{200d}', "U+200D ZERO WIDTH JOINER"),
        ('\u{2060}', "U+2060 WORD JOINER"),
        ('\u{feff}', "U+FEFF BYTE ORDER MARK (ZERO WIDTH NO-BREAK SPACE)"),
    ];
    for (i, line) in text.lines().enumerate() {
        if let Some((c, name)) = NAMES.iter().find(|(c, _)| line.contains(*c)) {
            let column = line[..line.find(*c).unwrap_or(0)].chars().count() + 1;
            return Err(RecipeError::new(RecipeErrorKind::Syntax(format!(
                "column {column} holds an invisible character, {name} (pasted from a web page or a word processor?): replace it with a plain space or remove it"
            )))
            .at(origin, i + 1));
        }
    }
    Ok(())
}

/// A topological entity as a recipe names it: a tag number or a tag name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum EntityRef {
    /// A tag number (Gmsh physical or elementary tag, Triangle marker…).
    Tag(i32),
    /// A tag name (Gmsh physical name, OBJ group…).
    Name(String),
}

/// Read by hand rather than derived (`#[serde(untagged)]`), whose only error is "data did
/// not match any variant of untagged enum EntityRef": this one says what was found and
/// what is expected.
impl<'de> Deserialize<'de> for EntityRef {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<EntityRef, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = EntityRef;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an entity: a tag number (an integer) or a tag name (a string)")
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<EntityRef, E> {
                i32::try_from(v).map(EntityRef::Tag).map_err(|_| {
                    E::custom(format!(
                        "tag {v} is out of range (a tag is a 32-bit integer, at most {})",
                        i32::MAX
                    ))
                })
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<EntityRef, E> {
                self.visit_i64(i64::try_from(v).unwrap_or(i64::MAX))
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<EntityRef, E> {
                Ok(EntityRef::Name(v.to_string()))
            }
        }
        d.deserialize_any(Visitor)
    }
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

/// One algorithm of the recipe (thesis 4.3.6–4.3.7, appendix A.1.5), names unresolved: a
/// line of the algorithm table ([`crate::sizing::algorithms::TABLE`]) and a value for
/// each parameter it declares, in declaration order.
///
/// TOML/JSON: a table with `type` (the keyword in lower case, or the keyword) and one
/// key per parameter (`regions2` for `second_regions`), unknown keys refused.
#[derive(Clone)]
pub struct AlgorithmSpec {
    entry: &'static Entry,
    values: Vec<SpecValue>,
}

/// The value of one algorithm parameter in a recipe.
#[derive(Debug, Clone, PartialEq)]
pub enum SpecValue {
    /// A size.
    Size(f64),
    /// A function or polyline name.
    Name(String),
    /// Region names.
    Names(Vec<String>),
    /// An optional parameter left out.
    Absent,
}

impl SpecValue {
    fn fits(&self, kind: ParameterKind) -> bool {
        matches!(
            (self, kind),
            (
                SpecValue::Size(_),
                ParameterKind::Size | ParameterKind::OptionalSize | ParameterKind::OptionalNorm
            ) | (
                SpecValue::Name(_),
                ParameterKind::Function(_)
                    | ParameterKind::Polyline
                    | ParameterKind::PointData
                    | ParameterKind::Choice(_)
            ) | (SpecValue::Names(_), ParameterKind::Regions { .. })
        ) || (matches!(self, SpecValue::Absent)
            && kind.is_optional()
            && !matches!(kind, ParameterKind::Regions { .. }))
    }

    fn empty(kind: ParameterKind) -> SpecValue {
        match kind {
            ParameterKind::Size => SpecValue::Size(0.0),
            ParameterKind::OptionalSize
            | ParameterKind::OptionalNorm
            | ParameterKind::Choice(_) => SpecValue::Absent,
            ParameterKind::Regions { .. } => SpecValue::Names(Vec::new()),
            ParameterKind::Function(_) | ParameterKind::Polyline | ParameterKind::PointData => {
                SpecValue::Name(String::new())
            }
        }
    }
}

impl PartialEq for AlgorithmSpec {
    fn eq(&self, other: &AlgorithmSpec) -> bool {
        std::ptr::eq(self.entry.declaration, other.entry.declaration) && self.values == other.values
    }
}

impl std::fmt::Debug for AlgorithmSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut d = f.debug_struct(self.keyword());
        for (p, v) in self.parameters().iter().zip(&self.values) {
            match v {
                SpecValue::Size(x) => d.field(p.field, x),
                SpecValue::Name(n) => d.field(p.field, n),
                SpecValue::Names(n) => d.field(p.field, n),
                SpecValue::Absent => continue,
            };
        }
        d.finish()
    }
}

impl AlgorithmSpec {
    /// The algorithm of keyword (or TOML/JSON type) `algorithm` with the values of its
    /// parameters by field; a parameter left out is empty (its regions, a name "", an
    /// optional one [`SpecValue::Absent`]). `None`
    /// for an unknown algorithm, an unknown field or a value of another kind.
    pub fn new<'a>(
        algorithm: &str,
        values: impl IntoIterator<Item = (&'a str, SpecValue)>,
    ) -> Option<AlgorithmSpec> {
        let entry = Entry::find(algorithm)?;
        let params = entry.declaration.parameters;
        let mut spec = AlgorithmSpec {
            entry,
            values: params.iter().map(|p| SpecValue::empty(p.kind)).collect(),
        };
        for (field, value) in values {
            let i = params.iter().position(|p| p.field == field)?;
            if !value.fits(params[i].kind) {
                return None;
            }
            spec.values[i] = value;
        }
        Some(spec)
    }

    /// The appendix keyword (`DISTANCE_TO_BORDER`).
    pub fn keyword(&self) -> &'static str {
        self.entry.declaration.keyword
    }

    /// The line of the algorithm table.
    pub fn entry(&self) -> &'static Entry {
        self.entry
    }

    /// The declared parameters, in order.
    pub fn parameters(&self) -> &'static [Parameter] {
        self.entry.declaration.parameters
    }

    /// The value of each declared parameter, in order.
    pub fn values(&self) -> &[SpecValue] {
        &self.values
    }

    /// Every parameter with its value.
    pub fn arguments(&self) -> impl Iterator<Item = (&'static Parameter, &SpecValue)> {
        self.parameters().iter().zip(&self.values)
    }

    /// Every region list with its model field name.
    pub fn region_lists(&self) -> Vec<(&'static str, &[String])> {
        self.arguments()
            .filter_map(|(p, v)| match v {
                SpecValue::Names(n) => Some((p.field, n.as_slice())),
                _ => None,
            })
            .collect()
    }

    /// Every function it names: (model field, name, kind needed).
    pub fn function_refs(&self) -> Vec<(&'static str, &str, FunctionKind)> {
        self.arguments()
            .filter_map(|(p, v)| match (p.kind, v) {
                (ParameterKind::Function(k), SpecValue::Name(n)) => Some((p.field, n.as_str(), k)),
                _ => None,
            })
            .collect()
    }

    /// The polyline it names, with its model field, if it takes one.
    pub fn polyline(&self) -> Option<(&'static str, &str)> {
        self.arguments().find_map(|(p, v)| match (p.kind, v) {
            (ParameterKind::Polyline, SpecValue::Name(n)) => Some((p.field, n.as_str())),
            _ => None,
        })
    }

    /// Every size it gives, with its model field.
    pub fn sizes(&self) -> Vec<(&'static str, f64)> {
        self.arguments()
            .filter_map(|(p, v)| match v {
                SpecValue::Size(x) => Some((p.field, *x)),
                _ => None,
            })
            .collect()
    }
}

impl Serialize for AlgorithmSpec {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let d = self.entry.declaration;
        let mut st = serializer.serialize_struct(d.keyword, self.values.len() + 1)?;
        st.serialize_field("type", d.name)?;
        for (p, v) in self.arguments() {
            match v {
                SpecValue::Names(n) if n.is_empty() && p.kind.is_optional() => {
                    st.skip_field(p.field)?
                }
                SpecValue::Names(n) => st.serialize_field(p.field, n)?,
                SpecValue::Name(n) => st.serialize_field(p.field, n)?,
                // JSON has no infinite number: every format writes the word.
                SpecValue::Size(x) if x.is_infinite() => {
                    st.serialize_field(p.field, INFINITE_NORM)?
                }
                SpecValue::Size(x) => st.serialize_field(p.field, x)?,
                SpecValue::Absent => st.skip_field(p.field)?,
            }
        }
        st.end()
    }
}

/// The TOML/JSON `type` names: each keyword and its lower case, as serde lists a variant
/// and its alias (sorted).
fn type_names() -> &'static [&'static str] {
    static NAMES: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
    NAMES.get_or_init(|| {
        TABLE.iter().flat_map(|e| [e.declaration.keyword, e.declaration.name]).collect()
    })
}

/// The TOML/JSON keys of the parameters of table line `entry`, as serde lists a field and
/// its aliases (sorted).
fn field_names(entry: &'static Entry) -> &'static [&'static str] {
    static NAMES: std::sync::OnceLock<Vec<Vec<&'static str>>> = std::sync::OnceLock::new();
    let all = NAMES.get_or_init(|| {
        TABLE
            .iter()
            .map(|e| {
                e.declaration
                    .parameters
                    .iter()
                    .flat_map(|p| {
                        let mut names: Vec<&'static str> = p.aliases.to_vec();
                        names.push(p.field);
                        names.sort_unstable();
                        names
                    })
                    .collect()
            })
            .collect()
    });
    let i = TABLE.iter().position(|e| std::ptr::eq(e, entry));
    i.and_then(|i| all.get(i)).map_or(&[], Vec::as_slice)
}

/// Any TOML/JSON value, kept to be checked once the algorithm is known.
enum Raw {
    Bool(bool),
    Signed(i64),
    Unsigned(u64),
    Float(f64),
    Str(String),
    Seq(Vec<Raw>),
    Map,
    Other,
}

impl Raw {
    fn unexpected(&self) -> serde::de::Unexpected<'_> {
        use serde::de::Unexpected;
        match self {
            Raw::Bool(b) => Unexpected::Bool(*b),
            Raw::Signed(i) => Unexpected::Signed(*i),
            Raw::Unsigned(u) => Unexpected::Unsigned(*u),
            Raw::Float(f) => Unexpected::Float(*f),
            Raw::Str(s) => Unexpected::Str(s),
            Raw::Seq(_) => Unexpected::Seq,
            Raw::Map => Unexpected::Map,
            Raw::Other => Unexpected::Other("value"),
        }
    }

    fn string<E: serde::de::Error>(self) -> Result<String, E> {
        match self {
            Raw::Str(s) => Ok(s),
            other => Err(E::invalid_type(other.unexpected(), &"a string")),
        }
    }

    fn into_value<E: serde::de::Error>(self, kind: ParameterKind) -> Result<SpecValue, E> {
        match kind {
            ParameterKind::Size | ParameterKind::OptionalSize => match self {
                Raw::Float(f) => Ok(SpecValue::Size(f)),
                Raw::Signed(i) => Ok(SpecValue::Size(i as f64)),
                Raw::Unsigned(u) => Ok(SpecValue::Size(u as f64)),
                other => Err(E::invalid_type(other.unexpected(), &"f64")),
            },
            ParameterKind::OptionalNorm => match self {
                Raw::Str(s) => infinite_norm(&s).map(SpecValue::Size).ok_or_else(|| {
                    E::invalid_value(serde::de::Unexpected::Str(&s), &"a number or \"inf\"")
                }),
                other => other.into_value(ParameterKind::OptionalSize),
            },
            ParameterKind::Function(_)
            | ParameterKind::Polyline
            | ParameterKind::PointData
            | ParameterKind::Choice(_) => self.string().map(SpecValue::Name),
            ParameterKind::Regions { .. } => match self {
                Raw::Seq(items) => items
                    .into_iter()
                    .map(Raw::string)
                    .collect::<Result<_, E>>()
                    .map(SpecValue::Names),
                other => Err(E::invalid_type(other.unexpected(), &"a sequence")),
            },
        }
    }
}

impl<'de> Deserialize<'de> for Raw {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Raw, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Raw;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("any value")
            }
            fn visit_bool<E>(self, v: bool) -> Result<Raw, E> {
                Ok(Raw::Bool(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Raw, E> {
                Ok(Raw::Signed(v))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Raw, E> {
                Ok(Raw::Unsigned(v))
            }
            fn visit_f64<E>(self, v: f64) -> Result<Raw, E> {
                Ok(Raw::Float(v))
            }
            fn visit_str<E>(self, v: &str) -> Result<Raw, E> {
                Ok(Raw::Str(v.to_string()))
            }
            fn visit_string<E>(self, v: String) -> Result<Raw, E> {
                Ok(Raw::Str(v))
            }
            fn visit_unit<E>(self) -> Result<Raw, E> {
                Ok(Raw::Other)
            }
            fn visit_none<E>(self) -> Result<Raw, E> {
                Ok(Raw::Other)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Raw, A::Error> {
                let mut items = Vec::new();
                while let Some(item) = seq.next_element::<Raw>()? {
                    items.push(item);
                }
                Ok(Raw::Seq(items))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Raw, A::Error> {
                while map.next_entry::<serde::de::IgnoredAny, serde::de::IgnoredAny>()?.is_some() {}
                Ok(Raw::Map)
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// The `type` of an algorithm: a line of the table.
struct TypeSeed;

impl<'de> serde::de::DeserializeSeed<'de> for TypeSeed {
    type Value = &'static Entry;
    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<&'static Entry, D::Error> {
        d.deserialize_identifier(TypeSeed)
    }
}

impl<'de> serde::de::Visitor<'de> for TypeSeed {
    type Value = &'static Entry;
    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("variant identifier")
    }
    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<&'static Entry, E> {
        Entry::find(v).ok_or_else(|| E::unknown_variant(v, type_names()))
    }
}

/// An algorithm as TOML/JSON write it, its type known and its other keys kept: as
/// serde's internally tagged enums buffer their content, so that an error in the
/// content is placed where serde places it (the item, not the key).
struct RawAlgorithm {
    entry: &'static Entry,
    rest: Vec<(String, Raw)>,
}

impl<'de> Deserialize<'de> for RawAlgorithm {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<RawAlgorithm, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = RawAlgorithm;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("internally tagged enum AlgorithmSpec")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<RawAlgorithm, A::Error> {
                use serde::de::Error;
                let mut entry: Option<&'static Entry> = None;
                let mut rest: Vec<(String, Raw)> = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    if key == "type" {
                        if entry.is_some() {
                            return Err(A::Error::duplicate_field("type"));
                        }
                        entry = Some(map.next_value_seed(TypeSeed)?);
                    } else {
                        rest.push((key, map.next_value::<Raw>()?));
                    }
                }
                let entry = entry.ok_or_else(|| A::Error::missing_field("type"))?;
                Ok(RawAlgorithm { entry, rest })
            }
        }
        deserializer.deserialize_any(V)
    }
}

impl RawAlgorithm {
    /// The keys checked against the declared parameters, in the order written.
    fn into_spec<E: serde::de::Error>(self) -> Result<AlgorithmSpec, E> {
        let entry = self.entry;
        let params = entry.declaration.parameters;
        let mut values: Vec<Option<SpecValue>> = vec![None; params.len()];
        for (key, raw) in self.rest {
            let Some(i) =
                params.iter().position(|p| p.field == key || p.aliases.contains(&key.as_str()))
            else {
                return Err(E::unknown_field(&key, field_names(entry)));
            };
            if values[i].is_some() {
                return Err(E::duplicate_field(params[i].field));
            }
            values[i] = Some(raw.into_value(params[i].kind)?);
        }
        let values = params
            .iter()
            .zip(values)
            .map(|(p, v)| match v {
                Some(v) => Ok(v),
                None if p.kind.is_optional() => Ok(SpecValue::empty(p.kind)),
                None => Err(E::missing_field(p.field)),
            })
            .collect::<Result<_, _>>()?;
        Ok(AlgorithmSpec { entry, values })
    }
}

impl<'de> Deserialize<'de> for AlgorithmSpec {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> Result<AlgorithmSpec, D::Error> {
        RawAlgorithm::deserialize(deserializer)?.into_spec()
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
    /// Reads a recipe; the format comes from the extension (`.cfg`, `.conf`,
    /// `.libconfig`: libconfig through cpp when it holds directives; `.toml`; `.json`).
    pub fn from_path(path: &Path) -> Result<Recipe, RecipeError> {
        Recipe::from_path_with(path, &ReadOptions::default())
    }

    /// [`Recipe::from_path`] with what reading may do and pull in (a regular file of
    /// at most `options.max_bytes`; cpp and `@include` only when `options.preprocess`).
    pub fn from_path_with(path: &Path, options: &ReadOptions) -> Result<Recipe, RecipeError> {
        let format = RecipeFormat::from_path(path)
            .ok_or_else(|| RecipeError::new(RecipeErrorKind::UnknownFormat).in_file(path))?;
        let text = super::preprocess::read_file(path, options.max_bytes, options.max_bytes)
            .map_err(|e| e.in_file(path))?;
        Recipe::from_str_with(&text, format, path, options)
    }

    /// Reads a recipe from text; `origin` names it in errors and anchors relative
    /// `#include` and `@include` paths.
    #[allow(clippy::should_implement_trait)]
    pub fn from_str(
        text: &str,
        format: RecipeFormat,
        origin: &Path,
    ) -> Result<Recipe, RecipeError> {
        Recipe::from_str_with(text, format, origin, &ReadOptions::default())
    }

    /// [`Recipe::from_str`] with what reading may do and pull in.
    pub fn from_str_with(
        text: &str,
        format: RecipeFormat,
        origin: &Path,
        options: &ReadOptions,
    ) -> Result<Recipe, RecipeError> {
        // A byte-order mark opens many files saved on Windows: skipped, as Python's
        // `utf-8-sig` does.
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        invisible_characters(text, origin)?;
        let recipe = match format {
            RecipeFormat::Libconfig => super::appendix::read(text, origin, options)?,
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
        if let Some(l) = &self.layer {
            if let Err(e) = l.options() {
                return Err(self.error_at(RecipeErrorKind::Invalid(e.to_string()), "layer"));
            }
        }
        for (i, p) in self.periodic.iter().enumerate() {
            if let Err(e) = p.pair() {
                return Err(self.error_at(RecipeErrorKind::Invalid(e), &format!("periodic[{i}]")));
            }
        }
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
            for (field, size) in a.sizes() {
                let norm = a
                    .parameters()
                    .iter()
                    .any(|p| p.field == field && p.kind == ParameterKind::OptionalNorm);
                // A norm below 1 is the algorithm's own refusal, which says why.
                let (fits, expected) = if norm {
                    (!size.is_nan(), "a number >= 1 or \"inf\"")
                } else {
                    (
                        (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&size),
                        "a size in [1e-30, 1e30]",
                    )
                };
                if !fits {
                    let key = self.written_key(&format!("{base}.{field}"), field).to_string();
                    return Err(self.error_at(
                        RecipeErrorKind::Invalid(format!(
                            "{key} = {size} is out of range: expected {expected}"
                        )),
                        &format!("{base}.{field}"),
                    ));
                }
            }
            let sizes = a.sizes();
            if let Err(refusal) = (a.entry().check)(Given { sizes: &sizes }) {
                // The key when the recipe wrote it, else the algorithm's place.
                let path = format!("{base}.{}", refusal.field);
                let (key, path) = match self.places.by_path.get(&path) {
                    Some(place) => (format!("{}: ", place.key), path),
                    None => (String::new(), base.clone()),
                };
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!(
                        "{} {}: {key}{}",
                        referrer(i),
                        a.keyword(),
                        refusal.why
                    )),
                    &path,
                ));
            }
            for (p, value) in a.arguments() {
                let (ParameterKind::Choice(words), SpecValue::Name(word)) = (p.kind, value) else {
                    continue;
                };
                if !words.contains(&word.as_str()) {
                    let path = format!("{base}.{}", p.field);
                    let key = self.written_key(&path, p.field).to_string();
                    let e = self.error_at(
                        RecipeErrorKind::Invalid(format!(
                            "{} {}: {key} = \"{word}\" is none of {}",
                            referrer(i),
                            a.keyword(),
                            words.iter().map(|w| format!("\"{w}\"")).collect::<Vec<_>>().join(", ")
                        )),
                        &path,
                    );
                    let s = nearest(word, words.iter().copied());
                    return Err(e.suggest(s.map(|s| format!("\"{s}\""))));
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
                            .filter(|(_, f)| accepts(kind, f))
                            .map(|(n, _)| n.as_str());
                        let any = self.functions.keys().map(String::as_str);
                        let s = nearest(name, same_kind).or_else(|| nearest(name, any));
                        return Err(e.suggest(s.map(|s| format!("\"{s}\""))));
                    }
                    Some(f) if !accepts(kind, f) => {
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
            for (p, value) in a.arguments() {
                let SpecValue::Names(list) = value else { continue };
                let field = p.field;
                let path = format!("{base}.{field}");
                if list.is_empty() && !p.kind.is_optional() {
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
            if let Some((field, polyline)) = a.polyline() {
                if !self.polylines.contains_key(polyline) {
                    let path = format!("{base}.{field}");
                    let e = self.error_at(
                        RecipeErrorKind::UnknownName {
                            referrer: referrer(i),
                            what: "polyline",
                            name: polyline.to_string(),
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
