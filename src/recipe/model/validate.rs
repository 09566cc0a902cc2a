//! Validation of a recipe: names, kinds and ranges.

use super::{accepts, referrer, AlgorithmSpec, Recipe, SpecValue};
use crate::metric::SizeTensor;
use crate::recipe::error::{RecipeError, RecipeErrorKind};
use crate::recipe::suggest::nearest;
use crate::sizing::algorithms::{Given, ParameterKind};
use crate::sizing::FunctionError;

impl Recipe {
    /// Checks names, kinds and ranges.
    pub fn validate(&self) -> Result<(), RecipeError> {
        self.check_layer_and_periodic()?;
        self.check_global()?;
        self.check_regions_and_polylines()?;
        self.check_functions()?;
        for (i, a) in self.algorithms.iter().enumerate() {
            self.check_algorithm(i, a)?;
        }
        Ok(())
    }

    /// The boundary-layer skin and the periodic pairs.
    fn check_layer_and_periodic(&self) -> Result<(), RecipeError> {
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
        Ok(())
    }

    /// The global bounds, aspect ratio and gradation.
    fn check_global(&self) -> Result<(), RecipeError> {
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
        Ok(())
    }

    /// Regions name entities; polylines have distinct finite points.
    fn check_regions_and_polylines(&self) -> Result<(), RecipeError> {
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
            let n = points.len();
            if let Some(p) =
                (0..n).map(|i| points.point(i)).find(|p| !p.iter().all(|c| c.is_finite()))
            {
                return Err(self.error_at(
                    RecipeErrorKind::Invalid(format!(
                        "polyline \"{name}\" has a point that is not finite: {p:?}"
                    )),
                    &path,
                ));
            }
            if let Some(i) = (1..n).position(|i| points.point(i - 1) == points.point(i)) {
                return Err(self.error_at(RecipeErrorKind::Invalid(format!("polyline \"{name}\" repeats point {} ({:?}) at once: consecutive points must differ", i + 1, points.point(i))), &path));
            }
        }
        Ok(())
    }

    /// Each function's parameters are in range.
    fn check_functions(&self) -> Result<(), RecipeError> {
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
        Ok(())
    }

    /// The `i`-th algorithm: its sizes and choices in range, and every function, region
    /// and polyline it names defined and of the right kind.
    fn check_algorithm(&self, i: usize, a: &AlgorithmSpec) -> Result<(), RecipeError> {
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
