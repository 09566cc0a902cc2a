//! TOML and JSON recipes: the model through serde, with `deny_unknown_fields`, then our
//! own suggestion step on serde's "unknown field" messages, and line numbers.
//!
//! TOML errors carry a byte span, turned into a line. For errors found after parsing
//! (a misspelt function name, a tag absent from the mesh), the TOML text is parsed a
//! second time into spanned tables to record the line of every item and key. JSON has no
//! spans once parsed: its parse errors have a line, later errors name the item
//! (`algorithm 3`) and the file only.
//!
//! TOML layout:
//!
//! ```toml
//! [global]                   # or [mesh]
//! hmin = 0.01
//! hmax = 2.0
//! max_aspect_ratio = 1000
//! gradation = 1.3
//!
//! [regions]
//! StayVane = [101, 102]      # tag numbers
//! Airfoil = ["Airfoil"]      # or tag names
//!
//! [polylines]
//! Wake = [[-50.0, -12.8], [-48.0, -13.5]]         # (x, y): a planar mesh
//! Vortex = [[1.0, 0.0, 0.5], [2.0, 0.0, 0.55]]    # (x, y, z): a mesh in space
//!
//! [functions.FStayVanePerp]
//! kind = "distance"          # or "projection", "curvature_to_size"
//! size_at_source = 0.1
//! size_at_max_distance = 1.0
//! max_distance = 5.0
//! exponent = 1.0
//!
//! [[algorithms]]
//! type = "distance_to_border"
//! perpendicular = "FStayVanePerp"
//! parallel = "FStayVanePara"
//! regions = ["StayVane"]
//! ```

use std::path::Path;

use super::error::{RecipeError, RecipeErrorKind};
use super::model::{Places, Recipe};
use super::suggest::nearest;
use crate::sizing::algorithms::TABLE;

fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Turns serde's `unknown field `x`, expected one of `a`, `b`` into an unknown-key error
/// with the nearest expected name; other messages stay syntax errors.
fn classify(message: &str) -> RecipeError {
    let message = message.trim_end();
    for (prefix, is_field) in [("unknown field `", true), ("unknown variant `", false)] {
        let Some(rest) = message.strip_prefix(prefix) else { continue };
        let Some(end) = rest.find('`') else { continue };
        let word = &rest[..end];
        let expected: Vec<&str> = rest[end + 1..].split('`').skip(1).step_by(2).collect();
        let s = nearest(word, expected.iter().copied());
        return if is_field {
            RecipeError::new(RecipeErrorKind::UnknownKey { key: word.to_string() })
                .suggest(s.map(String::from))
        } else {
            // The model also accepts the appendix's upper-case keywords: list each once.
            let mut known: Vec<&str> = expected
                .iter()
                .copied()
                .filter(|e| !e.chars().any(|c| c.is_ascii_uppercase()))
                .collect();
            if known.is_empty() {
                known = expected.clone();
            }
            let text = match s {
                Some(_) => format!("unknown value \"{word}\""),
                None => format!(
                    "unknown value \"{word}\", expected one of {}",
                    known.iter().map(|k| format!("\"{k}\"")).collect::<Vec<_>>().join(", ")
                ),
            };
            RecipeError::new(RecipeErrorKind::Syntax(text)).suggest(s.map(|s| format!("\"{s}\"")))
        };
    }
    RecipeError::new(RecipeErrorKind::Syntax(message.to_string()))
}

/// Reads a TOML recipe (unvalidated).
pub fn read_toml(text: &str, origin: &Path) -> Result<Recipe, RecipeError> {
    let mut recipe: Recipe = toml::from_str(text).map_err(|e| {
        let err = classify(e.message());
        match e.span() {
            Some(span) => {
                // Inside a tagged table (functions, algorithms) serde reports the whole
                // table: look for the key's own line in it.
                let line = match &*err.kind {
                    RecipeErrorKind::UnknownKey { key } => key_line(text, span.clone(), key),
                    _ => None,
                };
                err.at(origin, line.unwrap_or_else(|| line_of(text, span.start)))
            }
            None => err.in_file(origin),
        }
    })?;
    recipe.places = toml_places(text, origin);
    Ok(recipe)
}

/// The line where `key = …` is written from the start of `span` to the end of its
/// table (the span may cover only the table's header), if it is there.
fn key_line(text: &str, span: std::ops::Range<usize>, key: &str) -> Option<usize> {
    let start = span.start.min(text.len());
    let end = span.end.clamp(start, text.len());
    let mut offset = start;
    for (i, l) in text.get(start..)?.split_inclusive('\n').enumerate() {
        let t = l.trim_start();
        if i > 0 && offset >= end && t.starts_with('[') {
            break;
        }
        let rest = t.strip_prefix(key).or_else(|| t.strip_prefix(&format!("\"{key}\"")));
        if rest.is_some_and(|r| r.trim_start().starts_with('=')) {
            return Some(line_of(text, offset));
        }
        offset += l.len();
    }
    None
}

/// Reads a JSON recipe (unvalidated).
pub fn read_json(text: &str, origin: &Path) -> Result<Recipe, RecipeError> {
    let mut recipe: Recipe = serde_json::from_str(text).map_err(|e| {
        let full = e.to_string();
        let suffix = format!(" at line {} column {}", e.line(), e.column());
        let message = full.strip_suffix(&suffix).unwrap_or(&full);
        classify(message).at(origin, e.line())
    })?;
    recipe.places = Places::new(origin);
    Ok(recipe)
}

/// The model as TOML.
pub fn write_toml(recipe: &Recipe) -> String {
    // The model has string keys, no missing values and finite numbers (validated), all of
    // which TOML can hold; a failure here would be a bug in the model, reported in the text.
    toml::to_string(recipe)
        .unwrap_or_else(|e| format!("# smartmesh could not write this recipe as TOML: {e}\n"))
}

/// The model as pretty JSON.
pub fn write_json(recipe: &Recipe) -> String {
    let mut s =
        serde_json::to_string_pretty(recipe).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
    s.push('\n');
    s
}

/// The line of every item and key of a TOML recipe, by model path.
fn toml_places(text: &str, origin: &Path) -> Places {
    use toml::de::{DeTable, DeValue};
    let mut places = Places::new(origin);
    let Ok(doc) = DeTable::parse(text) else { return places };
    // Line starts searched, not newlines counted per key: O(n log n) for n keys.
    let starts: Vec<usize> = std::iter::once(0)
        .chain(text.bytes().enumerate().filter(|&(_, b)| b == b'\n').map(|(i, _)| i + 1))
        .collect();
    let line = |span: std::ops::Range<usize>| starts.partition_point(|&s| s <= span.start);
    // The model's name of a key written under an alias: the global bounds', and the
    // algorithm parameters' as their declarations give them.
    let canonical = |k: &str| -> String {
        match k {
            "h_min" => "hmin".into(),
            "h_max" => "hmax".into(),
            other => TABLE
                .iter()
                .flat_map(|e| e.declaration.parameters)
                .find(|p| p.aliases.contains(&other))
                .map_or(other, |p| p.field)
                .into(),
        }
    };
    for (section, value) in doc.get_ref().iter() {
        let section_name: &str = section.get_ref();
        match (section_name, value.get_ref()) {
            ("global" | "mesh", DeValue::Table(t)) => {
                for (k, v) in t.iter() {
                    places.insert(
                        format!("global.{}", canonical(k.get_ref())),
                        origin,
                        line(v.span()),
                        k.get_ref(),
                        &format!("[{section_name}]"),
                    );
                }
            }
            ("regions", DeValue::Table(t)) => {
                for (k, v) in t.iter() {
                    let name: &str = k.get_ref();
                    let ctx = format!("region \"{name}\"");
                    places.insert(format!("regions.{name}"), origin, line(k.span()), name, &ctx);
                    if let DeValue::Array(items) = v.get_ref() {
                        for (i, item) in items.iter().enumerate() {
                            places.insert(
                                format!("regions.{name}[{i}]"),
                                origin,
                                line(item.span()),
                                name,
                                &ctx,
                            );
                        }
                    }
                }
            }
            ("polylines", DeValue::Table(t)) => {
                for (k, _) in t.iter() {
                    let name: &str = k.get_ref();
                    places.insert(
                        format!("polylines.{name}"),
                        origin,
                        line(k.span()),
                        name,
                        &format!("polyline \"{name}\""),
                    );
                }
            }
            ("functions", DeValue::Table(t)) => {
                for (k, v) in t.iter() {
                    let name: &str = k.get_ref();
                    let ctx = format!("function \"{name}\"");
                    places.insert(format!("functions.{name}"), origin, line(k.span()), name, &ctx);
                    if let DeValue::Table(f) = v.get_ref() {
                        for (fk, fv) in f.iter() {
                            places.insert(
                                format!("functions.{name}.{}", canonical(fk.get_ref())),
                                origin,
                                line(fv.span()),
                                fk.get_ref(),
                                &ctx,
                            );
                        }
                    }
                }
            }
            ("algorithms", DeValue::Array(items)) => {
                for (i, item) in items.iter().enumerate() {
                    let ctx = format!("[[algorithms]] entry {}", i + 1);
                    let DeValue::Table(a) = item.get_ref() else { continue };
                    // An array-of-tables element spans its keys; take the first key's line
                    // when the element itself has no useful span.
                    let first = a
                        .iter()
                        .map(|(k, _)| line(k.span()))
                        .min()
                        .unwrap_or_else(|| line(item.span()));
                    places.insert(format!("algorithms[{i}]"), origin, first, "algorithms", &ctx);
                    for (k, v) in a.iter() {
                        places.insert(
                            format!("algorithms[{i}].{}", canonical(k.get_ref())),
                            origin,
                            line(v.span()),
                            k.get_ref(),
                            &ctx,
                        );
                    }
                }
            }
            _ => {}
        }
    }
    places
}

#[cfg(test)]
mod tests {
    use super::classify;

    #[test]
    fn serde_messages_become_suggestions() {
        let e = classify("unknown field `max_distnace`, expected one of `size_at_source`, `size_at_max_distance`, `max_distance`, `exponent`");
        assert_eq!(e.to_string(), "unknown key max_distnace, did you mean max_distance?");
        let e = classify("unknown variant `distance_to_boarder`, expected one of `uniform`, `distance_to_border`");
        assert_eq!(e.suggestion.as_deref(), Some("\"distance_to_border\""));
        let e = classify("unknown field `zzz`, expected `a` or `b`");
        assert_eq!(e.suggestion, None);
    }
}
