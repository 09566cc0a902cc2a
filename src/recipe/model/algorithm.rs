//! An algorithm of the recipe: a line of the algorithm table and its values, and how
//! TOML/JSON read and write it.

use serde::{Deserialize, Serialize};

use crate::sizing::algorithms::{
    infinite_norm, Entry, FunctionKind, Parameter, ParameterKind, INFINITE_NORM, TABLE,
};

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
                    | ParameterKind::File
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
            ParameterKind::Function(_)
            | ParameterKind::Polyline
            | ParameterKind::File
            | ParameterKind::PointData => SpecValue::Name(String::new()),
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

    /// Every file path it names (`FILE`, a sheet), writable: (model field, path).
    pub(crate) fn files_mut(&mut self) -> impl Iterator<Item = (&'static str, &mut String)> {
        let params = self.entry.declaration.parameters;
        params.iter().zip(self.values.iter_mut()).filter_map(|(p, v)| match (p.kind, v) {
            (ParameterKind::File, SpecValue::Name(n)) => Some((p.field, n)),
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
            | ParameterKind::File
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
