//! The libconfig recipe of thesis appendix A, read into the model and written back.
//!
//! Top-level settings (all optional):
//!
//! | key | model | value |
//! | --- | --- | --- |
//! | `HMIN` (`H_MIN`), `HMAX` (`H_MAX`), `MAX_ASPECT_RATIO`, `GRADATION` | `global` | numbers |
//! | `CREATE_REGIONS` | `regions` | list of `{ NAME; TOPOLOGICAL_ENTITIES }` (or `ENTITIES`) |
//! | `CREATE_POLYLINES` | `polylines` | list of `{ NAME; X_COORDS; Y_COORDS }`, and `Z_COORDS` for a polyline in space |
//! | `CREATE_DISTANCE_FUNCTIONS` | `functions` (distance) | `{ NAME; MINSIZE; MAXSIZE; MAXDISTANCE; EXPONENT }` |
//! | `CREATE_PROJECTION_FUNCTIONS` | `functions` (projection) | `{ NAME; MAXSIZE; MAXDISTANCE; EXPONENT }` |
//! | `CREATE_CURVATURE_TO_SIZE_FUNCTIONS` | `functions` (curvature) | `{ NAME; MINSIZE; MAXSIZE; SIZE_OF_ERROR }` |
//! | `CREATE_ALGORITHMS` | `algorithms` | list of `{ TYPE; … }` in the order they run |
//! | `LAYER` | `layer` | `{ CURVES; FIRST_HEIGHT; RATIO; LAYERS; THICKNESS; … }` (see [`super::layer`]) |
//! | `PERIODIC` | `periodic` | list of `{ MASTER; SLAVE; TRANSLATION }` or `{ MASTER; SLAVE; CENTRE; ANGLE }` (see [`super::periodic`]) |
//!
//! Spellings found in the thesis, all accepted: `MINSIZE`/`MIN_SIZE` (and, for distance
//! functions, `SIZE_AT_BORDER`/`SIZE_AT_TOPOLOGICAL_VERTEX`, thesis 7.4.3),
//! `MAXSIZE`/`MAX_SIZE`/`SIZE_AT_MAX_DISTANCE`, `MAXDISTANCE`/`MAX_DISTANCE`,
//! `TOPOLOGICAL_ENTITIES`/`ENTITIES`, `PROJECTION_FUNCTION`/`PARALLEL_PROJECTION_FUNCTION`,
//! and, for DISTANCE_TO_IMAGINARY_POLYLINE, `POLYLINE_DISTANCE_FUNCTION` (the example of
//! A.1.6) or `PARALLEL_FUNCTION` (the syntax of A.1.5.6). `COORDINATES` names a polyline
//! of `CREATE_POLYLINES`. `REGIONS`/`REGIONS2` take one name or a list or array of names;
//! entity lists may be nested (`( [1, 2], [3, 4] )`, thesis figure 5.1) and mix numbers
//! and names.
//!
//! Appendix A.1.4 lists MIN_SIZE for projection functions, but a projection function
//! takes its size at the source from the border it starts on (thesis 4.3.5.2): such a
//! key is an error that says so, rather than a value silently ignored.

use super::error::{RecipeError, RecipeErrorKind};
use super::layer::{CurveValues, LayerSpec};
use super::libconfig::{self, Node, Setting, Value};
use super::model::{
    AlgorithmSpec, EntityRef, FunctionSpec, Places, PolylinePoints, Recipe, SpecValue,
};
use super::periodic::PeriodicSpec;
use super::preprocess::{self, Source};
use super::suggest::nearest;
use crate::sizing::algorithms::{infinite_norm, Entry, ParameterKind, TABLE};

mod write;
pub use write::write;

/// A key of an item: the model field and the spellings accepted (the first is written).
struct Key {
    field: &'static str,
    spellings: &'static [&'static str],
    required: bool,
}

const fn req(field: &'static str, spellings: &'static [&'static str]) -> Key {
    Key { field, spellings, required: true }
}

const fn opt(field: &'static str, spellings: &'static [&'static str]) -> Key {
    Key { field, spellings, required: false }
}

const NAME: Key = req("name", &["NAME"]);
const TYPE: Key = req("type", &["TYPE"]);
const MIN_SIZE: &[&str] = &["MINSIZE", "MIN_SIZE"];
const SIZE_AT_SOURCE: &[&str] =
    &["MINSIZE", "MIN_SIZE", "SIZE_AT_BORDER", "SIZE_AT_TOPOLOGICAL_VERTEX"];
const MAX_SIZE: &[&str] = &["MAXSIZE", "MAX_SIZE", "SIZE_AT_MAX_DISTANCE"];
const MAX_DISTANCE: &[&str] = &["MAXDISTANCE", "MAX_DISTANCE"];

const TOP: &[Key] = &[
    opt("hmin", &["HMIN", "H_MIN"]),
    opt("hmax", &["HMAX", "H_MAX"]),
    opt("max_aspect_ratio", &["MAX_ASPECT_RATIO"]),
    opt("gradation", &["GRADATION"]),
    opt("regions", &["CREATE_REGIONS"]),
    opt("polylines", &["CREATE_POLYLINES"]),
    opt("distance", &["CREATE_DISTANCE_FUNCTIONS"]),
    opt("projection", &["CREATE_PROJECTION_FUNCTIONS"]),
    opt("curvature", &["CREATE_CURVATURE_TO_SIZE_FUNCTIONS"]),
    opt("algorithms", &["CREATE_ALGORITHMS"]),
    opt("layer", &["LAYER"]),
    opt("periodic", &["PERIODIC"]),
];
const PERIODIC: &[Key] = &[
    req("master", &["MASTER"]),
    req("slave", &["SLAVE"]),
    opt("translation", &["TRANSLATION"]),
    opt("centre", &["CENTRE", "CENTER"]),
    opt("angle", &["ANGLE"]),
];
const LAYER: &[Key] = &[
    req("curves", &["CURVES"]),
    opt("first_height", &["FIRST_HEIGHT"]),
    opt("ratio", &["RATIO", "GROWTH_RATIO"]),
    opt("layers", &["LAYERS", "NUMBER_OF_LAYERS"]),
    opt("thickness", &["THICKNESS"]),
    opt("y_plus", &["Y_PLUS"]),
    opt("reynolds", &["REYNOLDS"]),
    opt("ref_length", &["REF_LENGTH", "REFERENCE_LENGTH"]),
    opt("split", &["SPLIT"]),
    opt("tag", &["TAG"]),
    opt("fan_angle", &["FAN_ANGLE"]),
    opt("gap_ratio", &["GAP_RATIO"]),
    opt("per_curve", &["PER_CURVE"]),
];
const CURVE_VALUES: &[Key] =
    &[req("curve", &["CURVE"]), opt("first_height", &["FIRST_HEIGHT"]), opt("ratio", &["RATIO"])];
const REGION: &[Key] = &[NAME, req("entities", &["TOPOLOGICAL_ENTITIES", "ENTITIES"])];
const POLYLINE: &[Key] =
    &[NAME, req("x", &["X_COORDS"]), req("y", &["Y_COORDS"]), opt("z", &["Z_COORDS"])];
const DISTANCE: &[Key] = &[
    NAME,
    req("size_at_source", SIZE_AT_SOURCE),
    req("size_at_max_distance", MAX_SIZE),
    req("max_distance", MAX_DISTANCE),
    req("exponent", &["EXPONENT"]),
];
const PROJECTION: &[Key] = &[
    NAME,
    req("size_at_max_distance", MAX_SIZE),
    req("max_distance", MAX_DISTANCE),
    req("exponent", &["EXPONENT"]),
];
const CURVATURE: &[Key] = &[
    NAME,
    req("min_size", MIN_SIZE),
    req("max_size", MAX_SIZE),
    req("size_of_error", &["SIZE_OF_ERROR"]),
];

/// The keys of an algorithm's group: `TYPE`, then each declared parameter.
fn algorithm_keys(entry: &Entry) -> Vec<Key> {
    std::iter::once(TYPE)
        .chain(entry.declaration.parameters.iter().map(|p| Key {
            field: p.field,
            spellings: p.keys,
            required: !p.kind.is_optional(),
        }))
        .collect()
}

struct Reader<'a> {
    source: &'a Source,
    places: Places,
}

/// The settings found for each key of a table, in the table's order.
struct Found<'s> {
    settings: Vec<Option<&'s Setting>>,
}

impl<'s> Found<'s> {
    fn get(&self, keys: &[Key], field: &str) -> Option<&'s Setting> {
        keys.iter().position(|k| k.field == field).and_then(|i| self.settings[i])
    }
}

/// Reads libconfig text (preprocessed when it holds directives, as `options` allow) into
/// an unvalidated model.
pub fn read(
    text: &str,
    origin: &std::path::Path,
    options: &preprocess::ReadOptions,
) -> Result<Recipe, RecipeError> {
    let source = preprocess::load(text, origin, options)?;
    let settings = libconfig::parse(&source)?;
    let mut reader = Reader { source: &source, places: Places::new(origin) };
    let mut recipe = Recipe::default();
    reader.read_top(&settings, &mut recipe)?;
    recipe.places = reader.places;
    Ok(recipe)
}

impl Reader<'_> {
    fn error(&self, line0: usize, kind: RecipeErrorKind, context: &str) -> RecipeError {
        let (f, l) = self.source.place(line0);
        let e = RecipeError::new(kind).at(f, l);
        if context.is_empty() {
            e
        } else {
            e.within(context)
        }
    }

    fn place(&mut self, path: String, line0: usize, key: &str, context: &str) {
        let (f, l) = self.source.place(line0);
        let f = f.to_path_buf();
        self.places.insert(path, &f, l, key, context);
    }

    /// Matches the settings of a group against `keys`: unknown keys (with a suggestion),
    /// two spellings of one key, missing required keys.
    fn fields<'s>(
        &self,
        settings: &'s [Setting],
        keys: &[Key],
        group_line: usize,
        context: &str,
    ) -> Result<Found<'s>, RecipeError> {
        let mut found: Vec<Option<&'s Setting>> = vec![None; keys.len()];
        for s in settings {
            let Some(i) = keys.iter().position(|k| k.spellings.contains(&s.name.as_str())) else {
                let all = keys.iter().flat_map(|k| k.spellings.iter().copied());
                return Err(self
                    .error(s.at, RecipeErrorKind::UnknownKey { key: s.name.clone() }, context)
                    .suggest(nearest(&s.name, all).map(String::from)));
            };
            if let Some(prev) = found[i] {
                return Err(self.error(
                    s.at,
                    RecipeErrorKind::DuplicateKey { key: s.name.clone(), other: prev.name.clone() },
                    context,
                ));
            }
            found[i] = Some(s);
        }
        for (k, f) in keys.iter().zip(&found) {
            if k.required && f.is_none() {
                return Err(self.error(
                    group_line,
                    RecipeErrorKind::MissingKey { key: k.spellings[0].to_string() },
                    context,
                ));
            }
        }
        Ok(Found { settings: found })
    }

    fn wrong(&self, s: &Setting, node: &Node, expected: &str, context: &str) -> RecipeError {
        self.error(
            node.at,
            RecipeErrorKind::WrongType {
                key: s.name.clone(),
                expected: expected.into(),
                found: node.value.describe().into(),
            },
            context,
        )
    }

    fn number(&self, s: &Setting, context: &str) -> Result<f64, RecipeError> {
        match s.value.value {
            Value::Int(i) => Ok(i as f64),
            Value::Float(f) => Ok(f),
            _ => Err(self.wrong(s, &s.value, "a number", context)),
        }
    }

    /// A norm exponent: a number, or the string `"inf"` (libconfig has no infinite literal).
    fn norm(&self, s: &Setting, context: &str) -> Result<f64, RecipeError> {
        match &s.value.value {
            Value::Str(t) => infinite_norm(t)
                .ok_or_else(|| self.wrong(s, &s.value, "a number or \"inf\"", context)),
            _ => self
                .number(s, context)
                .map_err(|_| self.wrong(s, &s.value, "a number or \"inf\"", context)),
        }
    }

    fn string(&self, s: &Setting, context: &str) -> Result<String, RecipeError> {
        match &s.value.value {
            Value::Str(t) => Ok(t.clone()),
            _ => Err(self.wrong(s, &s.value, "a string", context)),
        }
    }

    /// One name, or a list or array of names (nested lists flattened).
    fn names(&self, s: &Setting, context: &str) -> Result<Vec<String>, RecipeError> {
        fn walk(
            r: &Reader,
            s: &Setting,
            n: &Node,
            out: &mut Vec<String>,
            context: &str,
        ) -> Result<(), RecipeError> {
            match &n.value {
                Value::Str(t) => out.push(t.clone()),
                Value::List(items) | Value::Array(items) => {
                    items.iter().try_for_each(|i| walk(r, s, i, out, context))?
                }
                _ => {
                    return Err(r.wrong(
                        s,
                        n,
                        "a region name in quotes, or a list of them",
                        context,
                    ))
                }
            }
            Ok(())
        }
        let mut out = Vec::new();
        walk(self, s, &s.value, &mut out, context)?;
        Ok(out)
    }

    /// Tag numbers and names, nested lists flattened, each with its line.
    fn entities(&self, s: &Setting, context: &str) -> Result<Vec<(EntityRef, usize)>, RecipeError> {
        fn walk(
            r: &Reader,
            s: &Setting,
            n: &Node,
            out: &mut Vec<(EntityRef, usize)>,
            context: &str,
        ) -> Result<(), RecipeError> {
            match &n.value {
                Value::Int(i) => match i32::try_from(*i) {
                    Ok(t) => out.push((EntityRef::Tag(t), n.at)),
                    Err(_) => {
                        return Err(r.error(
                            n.at,
                            RecipeErrorKind::Invalid(format!(
                                "tag {i} in {} does not fit a 32-bit tag",
                                s.name
                            )),
                            context,
                        ))
                    }
                },
                Value::Str(t) => out.push((EntityRef::Name(t.clone()), n.at)),
                Value::List(items) | Value::Array(items) => {
                    items.iter().try_for_each(|i| walk(r, s, i, out, context))?
                }
                _ => return Err(r.wrong(s, n, "tag numbers or tag names", context)),
            }
            Ok(())
        }
        let mut out = Vec::new();
        walk(self, s, &s.value, &mut out, context)?;
        Ok(out)
    }

    fn numbers(&self, s: &Setting, context: &str) -> Result<Vec<f64>, RecipeError> {
        let items = match &s.value.value {
            Value::Array(items) | Value::List(items) => items,
            _ => return Err(self.wrong(s, &s.value, "an array of numbers", context)),
        };
        items
            .iter()
            .map(|n| match n.value {
                Value::Int(i) => Ok(i as f64),
                Value::Float(f) => Ok(f),
                _ => Err(self.wrong(s, n, "an array of numbers", context)),
            })
            .collect()
    }

    /// The groups of a `CREATE_…` list.
    fn groups<'s>(&self, s: &'s Setting) -> Result<Vec<(&'s [Setting], usize)>, RecipeError> {
        let items: &[Node] = match &s.value.value {
            Value::List(items) => items,
            Value::Group(g) => return Ok(vec![(g, s.value.at)]),
            _ => return Err(self.wrong(s, &s.value, "a list ( { … }, … )", "")),
        };
        items
            .iter()
            .map(|n| match &n.value {
                Value::Group(g) => Ok((g.as_slice(), n.at)),
                _ => Err(self.wrong(s, n, "a list of groups { … }", "")),
            })
            .collect()
    }

    fn read_top(&mut self, settings: &[Setting], recipe: &mut Recipe) -> Result<(), RecipeError> {
        let top = self.fields(settings, TOP, 0, "")?;
        for (field, slot) in [
            ("hmin", &mut recipe.global.h_min),
            ("hmax", &mut recipe.global.h_max),
            ("max_aspect_ratio", &mut recipe.global.max_aspect_ratio),
            ("gradation", &mut recipe.global.gradation),
        ] {
            if let Some(s) = top.get(TOP, field) {
                *slot = Some(self.number(s, "")?);
                self.place(format!("global.{field}"), s.at, &s.name, "");
            }
        }
        if let Some(s) = top.get(TOP, "regions") {
            for (i, (g, line)) in self.groups(s)?.into_iter().enumerate() {
                let ctx = format!("{} entry {}", s.name, i + 1);
                let f = self.fields(g, REGION, line, &ctx)?;
                let name_s = f.get(REGION, "name").expect("required");
                let name = self.string(name_s, &ctx)?;
                let ent_s = f.get(REGION, "entities").expect("required");
                let entities = self.entities(ent_s, &ctx)?;
                let ctx = format!("region \"{name}\"");
                if recipe.regions.contains_key(&name) {
                    return Err(self.error(
                        name_s.at,
                        RecipeErrorKind::DuplicateName { what: "region", name },
                        "",
                    ));
                }
                self.place(format!("regions.{name}"), line, &s.name, &ctx);
                for (k, (_, at)) in entities.iter().enumerate() {
                    self.place(format!("regions.{name}[{k}]"), *at, &ent_s.name, &ctx);
                }
                recipe.regions.insert(name, entities.into_iter().map(|(e, _)| e).collect());
            }
        }
        if let Some(s) = top.get(TOP, "polylines") {
            for (i, (g, line)) in self.groups(s)?.into_iter().enumerate() {
                let ctx = format!("{} entry {}", s.name, i + 1);
                let f = self.fields(g, POLYLINE, line, &ctx)?;
                let name_s = f.get(POLYLINE, "name").expect("required");
                let name = self.string(name_s, &ctx)?;
                let xs_s = f.get(POLYLINE, "x").expect("required");
                let ys_s = f.get(POLYLINE, "y").expect("required");
                let (xs, ys) = (self.numbers(xs_s, &ctx)?, self.numbers(ys_s, &ctx)?);
                if xs.len() != ys.len() {
                    return Err(self.error(
                        ys_s.at,
                        RecipeErrorKind::Invalid(format!(
                            "polyline \"{name}\": {} X_COORDS but {} Y_COORDS",
                            xs.len(),
                            ys.len()
                        )),
                        &ctx,
                    ));
                }
                if recipe.polylines.contains_key(&name) {
                    return Err(self.error(
                        name_s.at,
                        RecipeErrorKind::DuplicateName { what: "polyline", name },
                        "",
                    ));
                }
                self.place(
                    format!("polylines.{name}"),
                    line,
                    &s.name,
                    &format!("polyline \"{name}\""),
                );
                let points = match f.get(POLYLINE, "z") {
                    None => {
                        PolylinePoints::Plane(xs.into_iter().zip(ys).map(|(x, y)| [x, y]).collect())
                    }
                    Some(zs_s) => {
                        let zs = self.numbers(zs_s, &ctx)?;
                        if zs.len() != xs.len() {
                            return Err(self.error(
                                zs_s.at,
                                RecipeErrorKind::Invalid(format!(
                                    "polyline \"{name}\": {} X_COORDS but {} Z_COORDS (every point of a polyline in space has x, y and z)",
                                    xs.len(),
                                    zs.len()
                                )),
                                &ctx,
                            ));
                        }
                        PolylinePoints::Space(
                            xs.into_iter().zip(ys).zip(zs).map(|((x, y), z)| [x, y, z]).collect(),
                        )
                    }
                };
                recipe.polylines.insert(name, points);
            }
        }
        for (list, keys) in
            [("distance", DISTANCE), ("projection", PROJECTION), ("curvature", CURVATURE)]
        {
            if let Some(s) = top.get(TOP, list) {
                for (i, (g, line)) in self.groups(s)?.into_iter().enumerate() {
                    let ctx = format!("{} entry {}", s.name, i + 1);
                    if list == "projection" {
                        if let Some(m) =
                            g.iter().find(|m| SIZE_AT_SOURCE.contains(&m.name.as_str()))
                        {
                            return Err(self.error(
                                m.at,
                                RecipeErrorKind::Invalid(format!(
                                    "{} is not a parameter of a projection function: its size at the source is the size found on the border (thesis 4.3.5.2); remove it",
                                    m.name
                                )),
                                &ctx,
                            ));
                        }
                    }
                    let f = self.fields(g, keys, line, &ctx)?;
                    let name_s = f.get(keys, "name").expect("required");
                    let name = self.string(name_s, &ctx)?;
                    let ctx = format!("function \"{name}\"");
                    let mut v = |field: &str| -> Result<f64, RecipeError> {
                        let st = f.get(keys, field).expect("required");
                        self.place(format!("functions.{name}.{field}"), st.at, &st.name, &ctx);
                        self.number(st, &ctx)
                    };
                    let spec = match list {
                        "distance" => FunctionSpec::Distance {
                            size_at_source: v("size_at_source")?,
                            size_at_max_distance: v("size_at_max_distance")?,
                            max_distance: v("max_distance")?,
                            exponent: v("exponent")?,
                        },
                        "projection" => FunctionSpec::Projection {
                            size_at_max_distance: v("size_at_max_distance")?,
                            max_distance: v("max_distance")?,
                            exponent: v("exponent")?,
                        },
                        _ => FunctionSpec::CurvatureToSize {
                            min_size: v("min_size")?,
                            max_size: v("max_size")?,
                            size_of_error: v("size_of_error")?,
                        },
                    };
                    if let Some(prev) = recipe.functions.get(&name) {
                        return Err(self.error(name_s.at, RecipeErrorKind::Invalid(format!("function \"{name}\" is defined twice (already a {} function); function names are shared by the three lists", prev.kind_name())), ""));
                    }
                    self.place(format!("functions.{name}"), line, &s.name, &ctx);
                    recipe.functions.insert(name, spec);
                }
            }
        }
        if let Some(s) = top.get(TOP, "algorithms") {
            for (i, (g, line)) in self.groups(s)?.into_iter().enumerate() {
                let a = self.read_algorithm(&s.name, i, g, line)?;
                recipe.algorithms.push(a);
            }
        }
        if let Some(s) = top.get(TOP, "layer") {
            recipe.layer = Some(self.read_layer(s)?);
        }
        if let Some(s) = top.get(TOP, "periodic") {
            for (i, (g, line)) in self.groups(s)?.into_iter().enumerate() {
                let spec = self.read_periodic(&s.name, i, g, line)?;
                recipe.periodic.push(spec);
            }
        }
        Ok(())
    }

    /// An integer setting in `range`.
    fn integer(
        &self,
        s: &Setting,
        range: std::ops::RangeInclusive<i64>,
        context: &str,
    ) -> Result<i64, RecipeError> {
        match s.value.value {
            Value::Int(i) if range.contains(&i) => Ok(i),
            _ => Err(self.wrong(
                s,
                &s.value,
                &format!("an integer from {} to {}", range.start(), range.end()),
                context,
            )),
        }
    }

    /// Entry `i` of the `PERIODIC = ( … )` list.
    fn read_periodic(
        &mut self,
        list: &str,
        i: usize,
        g: &[Setting],
        line: usize,
    ) -> Result<PeriodicSpec, RecipeError> {
        let ctx = format!("{list} entry {}", i + 1);
        let f = self.fields(g, PERIODIC, line, &ctx)?;
        let curves = |r: &Self, field: &str| -> Result<Vec<EntityRef>, RecipeError> {
            let s = f.get(PERIODIC, field).expect("required");
            Ok(r.entities(s, &ctx)?.into_iter().map(|e| e.0).collect())
        };
        let point = |r: &Self, field: &str| -> Result<Option<[f64; 2]>, RecipeError> {
            let Some(s) = f.get(PERIODIC, field) else { return Ok(None) };
            match r.numbers(s, &ctx)?.as_slice() {
                &[x, y] => Ok(Some([x, y])),
                _ => Err(r.wrong(s, &s.value, "two numbers [x, y]", &ctx)),
            }
        };
        let spec = PeriodicSpec {
            master: curves(self, "master")?,
            slave: curves(self, "slave")?,
            translation: point(self, "translation")?,
            centre: point(self, "centre")?,
            angle: f.get(PERIODIC, "angle").map(|s| self.number(s, &ctx)).transpose()?,
        };
        self.place(format!("periodic[{i}]"), line, list, &ctx);
        Ok(spec)
    }

    /// The `LAYER = { … }` group.
    fn read_layer(&mut self, s: &Setting) -> Result<LayerSpec, RecipeError> {
        let ctx = s.name.clone();
        let groups = self.groups(s)?;
        let [(g, line)] = groups.as_slice() else {
            return Err(self.wrong(s, &s.value, "one group { CURVES = …; … }", ""));
        };
        let f = self.fields(g, LAYER, *line, &ctx)?;
        let mut spec = LayerSpec {
            curves: self
                .entities(f.get(LAYER, "curves").expect("required"), &ctx)?
                .into_iter()
                .map(|e| e.0)
                .collect(),
            ..LayerSpec::default()
        };
        for (field, slot) in [
            ("first_height", &mut spec.first_height),
            ("ratio", &mut spec.ratio),
            ("thickness", &mut spec.thickness),
            ("y_plus", &mut spec.y_plus),
            ("reynolds", &mut spec.reynolds),
            ("ref_length", &mut spec.ref_length),
            ("fan_angle", &mut spec.fan_angle),
            ("gap_ratio", &mut spec.gap_ratio),
        ] {
            if let Some(st) = f.get(LAYER, field) {
                *slot = Some(self.number(st, &ctx)?);
            }
        }
        if let Some(st) = f.get(LAYER, "layers") {
            spec.layers = Some(self.integer(st, 1..=1000, &ctx)? as usize);
        }
        if let Some(st) = f.get(LAYER, "tag") {
            spec.tag = Some(self.integer(st, i32::MIN as i64..=i32::MAX as i64, &ctx)? as i32);
        }
        if let Some(st) = f.get(LAYER, "split") {
            spec.split = match st.value.value {
                Value::Bool(b) => b,
                _ => return Err(self.wrong(st, &st.value, "true or false", &ctx)),
            };
        }
        if let Some(st) = f.get(LAYER, "per_curve") {
            for (i, (pg, pline)) in self.groups(st)?.into_iter().enumerate() {
                let pctx = format!("{} entry {}", st.name, i + 1);
                let pf = self.fields(pg, CURVE_VALUES, pline, &pctx)?;
                let cs = pf.get(CURVE_VALUES, "curve").expect("required");
                let mut curve = self.entities(cs, &pctx)?;
                if curve.len() != 1 {
                    return Err(self.wrong(cs, &cs.value, "one curve tag or name", &pctx));
                }
                let num = |k: &str| -> Result<Option<f64>, RecipeError> {
                    pf.get(CURVE_VALUES, k).map(|x| self.number(x, &pctx)).transpose()
                };
                spec.per_curve.push(CurveValues {
                    curve: curve.remove(0).0,
                    first_height: num("first_height")?,
                    ratio: num("ratio")?,
                });
            }
        }
        self.place("layer".into(), *line, &s.name, &ctx);
        Ok(spec)
    }

    fn read_algorithm(
        &mut self,
        list: &str,
        i: usize,
        g: &[Setting],
        line: usize,
    ) -> Result<AlgorithmSpec, RecipeError> {
        let ctx = format!("{list} entry {}", i + 1);
        let Some(type_s) = g.iter().find(|s| s.name == "TYPE") else {
            return Err(self.error(line, RecipeErrorKind::MissingKey { key: "TYPE".into() }, &ctx));
        };
        let written = self.string(type_s, &ctx)?;
        let upper = written.to_ascii_uppercase();
        let Some(entry) = TABLE.iter().find(|e| e.declaration.keyword == upper) else {
            let e = self.error(
                type_s.at,
                RecipeErrorKind::UnknownName {
                    referrer: format!("algorithm {}", i + 1),
                    what: "algorithm type",
                    name: written.clone(),
                },
                "",
            );
            let types = TABLE.iter().map(|e| e.declaration.keyword);
            return Err(e.suggest(nearest(&written, types).map(|s| format!("\"{s}\""))));
        };
        let t = entry.declaration.keyword;
        let ctx = format!("{list} entry {}, {t}", i + 1);
        let keys = algorithm_keys(entry);
        let f = self.fields(g, &keys, line, &ctx)?;
        let base = format!("algorithms[{i}]");
        self.place(base.clone(), line, list, &ctx);
        for (k, s) in keys.iter().zip(&f.settings) {
            if let Some(s) = s {
                self.place(format!("{base}.{}", k.field), s.at, &s.name, &ctx);
            }
        }
        let mut values = Vec::new();
        for p in entry.declaration.parameters {
            let setting = f.get(&keys, p.field);
            let value = match (p.kind, setting) {
                (ParameterKind::Regions { .. }, Some(s)) => SpecValue::Names(self.names(s, &ctx)?),
                (ParameterKind::Regions { .. }, None) => SpecValue::Names(Vec::new()),
                (ParameterKind::Size | ParameterKind::OptionalSize, Some(s)) => {
                    SpecValue::Size(self.number(s, &ctx)?)
                }
                (
                    ParameterKind::Function(_)
                    | ParameterKind::Polyline
                    | ParameterKind::File
                    | ParameterKind::PointData
                    | ParameterKind::Choice(_),
                    Some(s),
                ) => SpecValue::Name(self.string(s, &ctx)?),
                (ParameterKind::OptionalNorm, Some(s)) => SpecValue::Size(self.norm(s, &ctx)?),
                (
                    ParameterKind::OptionalSize
                    | ParameterKind::OptionalNorm
                    | ParameterKind::Choice(_),
                    None,
                ) => SpecValue::Absent,
                // `fields` has refused a group without a required key.
                (_, None) => {
                    return Err(self.error(
                        line,
                        RecipeErrorKind::MissingKey { key: p.keys[0].to_string() },
                        &ctx,
                    ))
                }
            };
            values.push((p.field, value));
        }
        AlgorithmSpec::new(t, values).ok_or_else(|| {
            self.error(
                line,
                RecipeErrorKind::Invalid(format!(
                    "{t}: parameters that do not match its declaration"
                )),
                &ctx,
            )
        })
    }
}
