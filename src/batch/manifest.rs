//! The manifest of a batch: JSON lines, one object per variant,
//! `{"name": ..., "input": ..., "recipe": ..., "options": {...}}`.
//!
//! Invariants of a [`Variant`] once parsed: its name is a plain file name (letters,
//! digits, `.`, `_`, `-`, not starting with `.`), so that its outputs `DIR/NAME.*` stay in
//! the output directory; `input` and `recipe` are resolved against the manifest's folder
//! (absolute paths are kept); `options` name only adapt options of [`OPTIONS`], each with
//! a value of its kind, and become the `adapt` arguments of [`Variant::adapt_args`] in
//! the order of [`OPTIONS`] (so that equal options give equal arguments, and equal
//! content hashes, whatever their order in the line). Blank lines are skipped; every
//! error names the manifest, the line and what was expected.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value};

/// How the value of an option is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OptionKind {
    /// A string (or a number, for version numbers): `--flag VALUE`.
    Text,
    /// A number: `--flag VALUE`.
    Number,
    /// A whole number >= 0.
    Count,
    /// `true`: `--flag`; `false`: nothing.
    Switch,
    /// A list of strings: `--flag=VALUE` once per item.
    List,
}

/// The adapt options a manifest line may set (JSON key, `adapt` flag, kind), in the order
/// their arguments are written. `format` is the output's extension (`msh` unless said).
pub const OPTIONS: &[(&str, &str, OptionKind)] = &[
    ("adapter", "--adapter", OptionKind::Text),
    ("adapter_program", "--adapter-program", OptionKind::Text),
    ("adapter_args", "--adapter-arg", OptionKind::List),
    ("max_iterations", "--max-iterations", OptionKind::Count),
    ("tol_vertices", "--tol-vertices", OptionKind::Number),
    ("tol_conformity", "--tol-conformity", OptionKind::Number),
    ("max_vertices", "--max-vertices", OptionKind::Count),
    ("max_growth", "--max-growth", OptionKind::Number),
    ("hmin", "--hmin", OptionKind::Number),
    ("hmax", "--hmax", OptionKind::Number),
    ("hgrad", "--hgrad", OptionKind::Number),
    ("hausd", "--hausd", OptionKind::Number),
    ("coarsen_geometry", "--coarsen-geometry", OptionKind::Switch),
    ("nosurf", "--nosurf", OptionKind::Switch),
    ("no_preprocess", "--no-preprocess", OptionKind::Switch),
    ("recipe_format", "--recipe-format", OptionKind::Text),
    ("from", "--from", OptionKind::Text),
    ("format", "", OptionKind::Text),
    ("binary", "--binary", OptionKind::Switch),
    ("gmsh_version", "--gmsh-version", OptionKind::Text),
    ("vtk_version", "--vtk-version", OptionKind::Text),
    ("vtu_encoding", "--vtu-encoding", OptionKind::Text),
    ("no_compress", "--no-compress", OptionKind::Switch),
];

/// The keys of a manifest line.
const KEYS: &[&str] = &["name", "input", "recipe", "options"];

/// One variant of a batch.
#[derive(Debug, Clone, PartialEq)]
pub struct Variant {
    /// Its line in the manifest (from 1), or the task's line for an entry from the
    /// environment (0 when unknown).
    pub line: usize,
    /// Its name: the stem of its output files.
    pub name: String,
    /// The starting mesh or geometry.
    pub input: PathBuf,
    /// The recipe.
    pub recipe: PathBuf,
    /// The output's extension (`msh` by default).
    pub format: String,
    /// The options as `adapt` arguments, in [`OPTIONS`] order.
    pub args: Vec<String>,
}

/// A manifest line that is not a variant.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{source_name}:{line}: {message}")]
pub struct ManifestError {
    /// The manifest (or `HQ_ENTRY`).
    pub source_name: String,
    /// The line, from 1 (0: not known).
    pub line: usize,
    /// What was wrong and what was expected.
    pub message: String,
}

impl Variant {
    /// The `adapt` arguments of this variant writing into `dir`: input, recipe, output,
    /// history, then the options.
    pub fn adapt_args(&self, dir: &Path) -> Vec<std::ffi::OsString> {
        let mut a: Vec<std::ffi::OsString> = vec![
            "adapt".into(),
            self.input.clone().into_os_string(),
            "--recipe".into(),
            self.recipe.clone().into_os_string(),
            "-o".into(),
            dir.join(self.output_name()).into_os_string(),
            "--history".into(),
            dir.join(self.history_name()).into_os_string(),
        ];
        a.extend(self.args.iter().map(Into::into));
        a
    }

    /// The output mesh's file name, `NAME.EXT`.
    pub fn output_name(&self) -> String {
        format!("{}.{}", self.name, self.format)
    }

    /// The history's file name, `NAME.history.json`.
    pub fn history_name(&self) -> String {
        format!("{}.history.json", self.name)
    }

    /// The log's file name (the run's stderr), `NAME.log`.
    pub fn log_name(&self) -> String {
        format!("{}.log", self.name)
    }
}

/// Parses one manifest line (`line` from 1) whose relative paths are relative to `base`.
/// `Ok(None)` for a blank line.
pub fn parse_line(
    text: &str,
    line: usize,
    base: &Path,
    source_name: &str,
) -> Result<Option<Variant>, ManifestError> {
    let err =
        |message: String| ManifestError { source_name: source_name.to_string(), line, message };
    let text = text.trim();
    if text.is_empty() {
        return Ok(None);
    }
    let value: Value = serde_json::from_str(text).map_err(|e| {
        err(format!(
            "not a JSON object ({e}); expected one variant per line: {{\"name\": ..., \"input\": ..., \"recipe\": ..., \"options\": {{...}}}}"
        ))
    })?;
    let Value::Object(object) = value else {
        return Err(err(format!(
            "expected a JSON object {{\"name\": ..., \"input\": ..., \"recipe\": ...}}, found {}",
            kind_of(&value)
        )));
    };
    if let Some(key) = object.keys().find(|k| !KEYS.contains(&k.as_str())) {
        return Err(err(format!(
            "unknown key `{key}`{}; known: {}",
            did_you_mean(key, KEYS),
            KEYS.join(", ")
        )));
    }
    let text_field = |key: &str| -> Result<String, ManifestError> {
        match object.get(key) {
            Some(Value::String(s)) if !s.is_empty() => Ok(s.clone()),
            Some(v) => {
                Err(err(format!("`{key}` must be a non-empty string, found {}", kind_of(v))))
            }
            None => Err(err(format!("`{key}` is missing"))),
        }
    };
    let name = text_field("name")?;
    check_name(&name).map_err(|m| err(format!("`name` {m}")))?;
    let path = |key: &str| -> Result<PathBuf, ManifestError> {
        let p = PathBuf::from(text_field(key)?);
        let p = if p.is_absolute() { p } else { base.join(p) };
        match std::fs::metadata(&p) {
            Ok(m) if m.is_file() => Ok(p),
            Ok(_) => Err(err(format!("`{key}` {} is not a file", p.display()))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                Err(err(format!("`{key}` {} does not exist (expected a file; relative paths are relative to the manifest's folder)", p.display())))
            }
            Err(e) => Err(err(format!("`{key}` {}: {e}", p.display()))),
        }
    };
    let input = path("input")?;
    let recipe = path("recipe")?;
    let empty = Map::new();
    let options = match object.get("options") {
        None | Some(Value::Null) => &empty,
        Some(Value::Object(o)) => o,
        Some(v) => {
            return Err(err(format!(
                "`options` must be an object of adapt options, found {}",
                kind_of(v)
            )))
        }
    };
    let (format, args) = option_args(options).map_err(err)?;
    Ok(Some(Variant { line, name, input, recipe, format, args }))
}

/// Parses a whole manifest; names must be unique.
pub fn parse(text: &str, manifest: &Path) -> Result<Vec<Variant>, ManifestError> {
    let base = manifest.parent().unwrap_or(Path::new(""));
    let base = if base.as_os_str().is_empty() { Path::new(".") } else { base };
    let source_name = manifest.display().to_string();
    let mut variants: Vec<Variant> = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, line) in text.lines().enumerate() {
        let Some(v) = parse_line(line, i + 1, base, &source_name)? else { continue };
        if let Some(first) = seen.insert(v.name.clone(), v.line) {
            return Err(ManifestError {
                source_name,
                line: v.line,
                message: format!("name `{}` is already used at line {first}; every variant needs a name of its own (its output files)", v.name),
            });
        }
        variants.push(v);
    }
    if variants.is_empty() {
        return Err(ManifestError {
            source_name,
            line: 0,
            message: "no variant: expected one JSON object per line".into(),
        });
    }
    Ok(variants)
}

/// Whether `name` can name files in the output directory.
fn check_name(name: &str) -> Result<(), String> {
    if name.starts_with('.') {
        return Err(format!("`{name}` starts with `.`; expected letters, digits, `.`, `_` or `-`"));
    }
    if name.len() > 200 {
        return Err(format!("is {} bytes long; at most 200", name.len()));
    }
    match name.chars().find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))) {
        Some(c) => Err(format!("`{name}` holds {c:?}; expected letters, digits, `.`, `_` or `-` (it names the output files)")),
        None => Ok(()),
    }
}

/// The output extension and the `adapt` arguments of an `options` object.
pub fn option_args(options: &Map<String, Value>) -> Result<(String, Vec<String>), String> {
    let known: Vec<&str> = OPTIONS.iter().map(|o| o.0).collect();
    if let Some(key) = options.keys().find(|k| !known.contains(&k.as_str())) {
        return Err(format!(
            "unknown option `{key}`{}; known: {}",
            did_you_mean(key, &known),
            known.join(", ")
        ));
    }
    let mut format = "msh".to_string();
    let mut args = Vec::new();
    for &(key, flag, kind) in OPTIONS {
        let Some(value) = options.get(key) else { continue };
        let wrong =
            |expected: &str| format!("option `{key}` must be {expected}, found {}", kind_of(value));
        match (kind, value) {
            (_, Value::Null) => {}
            (OptionKind::Switch, Value::Bool(b)) => {
                if *b {
                    args.push(flag.to_string());
                }
            }
            (OptionKind::Switch, _) => return Err(wrong("true or false")),
            (OptionKind::Number, Value::Number(n)) => {
                args.extend([flag.to_string(), n.to_string()])
            }
            (OptionKind::Number, _) => return Err(wrong("a number")),
            (OptionKind::Count, Value::Number(n)) if n.as_u64().is_some() => {
                args.extend([flag.to_string(), n.to_string()])
            }
            (OptionKind::Count, _) => return Err(wrong("a whole number >= 0")),
            (OptionKind::Text, Value::String(_) | Value::Number(_)) if key == "format" => {
                let s = match value {
                    Value::String(s) => s.clone(),
                    v => v.to_string(),
                };
                let ok = smartmesh_formats::Format::from_extension(&s).is_some()
                    && s.chars().all(|c| c.is_ascii_alphanumeric());
                if !ok {
                    return Err(format!("option `format` `{s}` is not a mesh file extension (msh, vtu, vtk, mesh, meshb, obj, node, gltf, glb)"));
                }
                format = s;
            }
            (OptionKind::Text, Value::String(s)) => args.extend([flag.to_string(), s.clone()]),
            (OptionKind::Text, Value::Number(n)) => args.extend([flag.to_string(), n.to_string()]),
            (OptionKind::Text, _) => return Err(wrong("a string")),
            (OptionKind::List, Value::Array(items)) => {
                for item in items {
                    match item {
                        Value::String(s) => args.push(format!("{flag}={s}")),
                        Value::Number(n) => args.push(format!("{flag}={n}")),
                        _ => return Err(wrong("a list of strings")),
                    }
                }
            }
            (OptionKind::List, _) => return Err(wrong("a list of strings")),
        }
    }
    Ok((format, args))
}

/// ` (did you mean `x`?)` when a known name is close to `key`.
fn did_you_mean(key: &str, known: &[&str]) -> String {
    known
        .iter()
        .map(|k| (strsim::jaro_winkler(key, k), k))
        .filter(|(s, _)| *s > 0.8)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map_or_else(String::new, |(_, k)| format!(" (did you mean `{k}`?)"))
}

fn kind_of(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "a list",
        Value::Object(_) => "an object",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files() -> tempfile::TempDir {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(d.path().join("a.poly"), "x").unwrap();
        std::fs::write(d.path().join("r.toml"), "x").unwrap();
        d
    }

    #[test]
    fn options_become_arguments_in_a_fixed_order() {
        let d = files();
        let a = r#"{"name":"v1","input":"a.poly","recipe":"r.toml","options":{"hmin":0.01,"max_iterations":3,"coarsen_geometry":true,"format":"vtu","adapter_args":["-v","5"]}}"#;
        let b = r#"{"options":{"adapter_args":["-v","5"],"coarsen_geometry":true,"format":"vtu","max_iterations":3,"hmin":0.01},"recipe":"r.toml","input":"a.poly","name":"v1"}"#;
        let va = parse_line(a, 1, d.path(), "m").unwrap().unwrap();
        let vb = parse_line(b, 1, d.path(), "m").unwrap().unwrap();
        assert_eq!(va, vb);
        assert_eq!(va.format, "vtu");
        assert_eq!(
            va.args,
            [
                "--adapter-arg=-v",
                "--adapter-arg=5",
                "--max-iterations",
                "3",
                "--hmin",
                "0.01",
                "--coarsen-geometry"
            ]
        );
        assert_eq!(va.input, d.path().join("a.poly"));
    }

    #[test]
    fn bad_lines_name_the_line_and_what_was_expected() {
        let d = files();
        let m = d.path().join("m.jsonl");
        let cases = [
            ("[1]", "expected a JSON object"),
            ("{\"name\":\"a\"", "not a JSON object"),
            (
                r#"{"name":"a","input":"a.poly","recipe":"r.toml","optons":{}}"#,
                "did you mean `options`",
            ),
            (
                r#"{"name":"a","input":"a.poly","recipe":"r.toml","options":{"hmn":1}}"#,
                "did you mean `hmin`",
            ),
            (
                r#"{"name":"a","input":"a.poly","recipe":"r.toml","options":{"hmin":"1"}}"#,
                "must be a number",
            ),
            (
                r#"{"name":"a","input":"a.poly","recipe":"r.toml","options":{"max_iterations":-1}}"#,
                "whole number",
            ),
            (
                r#"{"name":"a","input":"a.poly","recipe":"r.toml","options":{"format":"pdf"}}"#,
                "not a mesh file extension",
            ),
            (r#"{"name":"a/b","input":"a.poly","recipe":"r.toml"}"#, "holds '/'"),
            (r#"{"name":"../a","input":"a.poly","recipe":"r.toml"}"#, "starts with `.`"),
            (r#"{"name":".a","input":"a.poly","recipe":"r.toml"}"#, "starts with `.`"),
            (r#"{"name":"a","input":"missing.poly","recipe":"r.toml"}"#, "missing.poly"),
            (r#"{"name":"a","input":"a.poly"}"#, "`recipe` is missing"),
            (
                r#"{"name":3,"input":"a.poly","recipe":"r.toml"}"#,
                "`name` must be a non-empty string",
            ),
        ];
        for (line, expected) in cases {
            let text = format!("\n{line}\n");
            let e = parse(&text, &m).unwrap_err();
            assert_eq!(e.line, 2, "{line}");
            let shown = e.to_string();
            assert!(shown.starts_with(&format!("{}:2: ", m.display())), "{shown}");
            assert!(shown.contains(expected), "{line}: {shown}");
        }
    }

    #[test]
    fn names_are_unique_and_blank_lines_skipped() {
        let d = files();
        let m = d.path().join("m.jsonl");
        let v = r#"{"name":"a","input":"a.poly","recipe":"r.toml"}"#;
        let e = parse(&format!("{v}\n\n{v}\n"), &m).unwrap_err();
        assert_eq!(e.line, 3);
        assert!(e.message.contains("already used at line 1"), "{e}");
        let ok = parse(&format!("\n{v}\n   \n"), &m).unwrap();
        assert_eq!(ok.len(), 1);
        assert_eq!(ok[0].line, 2);
        assert!(parse("\n\n", &m).unwrap_err().message.contains("no variant"));
    }
}
