//! The manifest of a batch: JSON lines, one object per variant,
//! `{"name": ..., "input": ..., "recipe": ..., "options": {...}}`.
//!
//! Invariants of a [`Variant`] once parsed: its name is a plain file name (letters,
//! digits, `.`, `_`, `-`, not starting with `.`), so that its outputs `DIR/NAME.*` stay in
//! the output directory; `input` and `recipe` are resolved against the manifest's folder
//! (absolute paths are kept); `options` name only adapt options of [`OPTION_KEYS`], each with
//! a value of its kind, and become the `adapt` arguments of [`Variant::adapt_args`] in
//! the order of [`OPTION_KEYS`] (so that equal options give equal arguments, and equal
//! content hashes, whatever their order in the line). Blank lines and a byte order mark
//! are skipped; a key given twice in one object is an error (JSON leaves it undefined);
//! every error names the manifest, the line and what was expected, with the line's own
//! text shown escaped ([`shown`]: no control character reaches the terminal).
//!
//! Whether `input` and `recipe` exist is not the manifest's business but the variant's
//! ([`Variant::check_files`]): a batch records a variant whose file is missing as failed
//! and runs the others.

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

/// The JSON keys of the adapt options a manifest line may set, in the order their
/// arguments are written. `format` is the output's extension (`msh` unless said); every
/// other key is the name of an option of `adapt` (its flag with underscores), whose flag
/// and kind come from `adapt`'s own definition ([`AdaptOption`]).
pub const OPTION_KEYS: &[&str] = &[
    "adapter",
    "adapter_program",
    "adapter_args",
    "max_iterations",
    "tol_vertices",
    "tol_conformity",
    "max_vertices",
    "max_growth",
    "hmin",
    "hmax",
    "hgrad",
    "hausd",
    "coarsen_geometry",
    "nosurf",
    "no_preprocess",
    "recipe_format",
    "from",
    "format",
    "binary",
    "gmsh_version",
    "vtk_version",
    "vtu_encoding",
    "no_compress",
    "extrude",
    "wedge",
    "patch_type",
    "cyclic",
];

/// One option a manifest line may set: its key (one of [`OPTION_KEYS`]), its `adapt`
/// flag (empty for `format`) and the kind of its value, as the `adapt` command that
/// parses the variant's arguments declares them. Whoever reads a manifest hands them to
/// [`parse`], in [`OPTION_KEYS`] order.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdaptOption {
    /// The JSON key.
    pub key: &'static str,
    /// The flag, `--` included.
    pub flag: String,
    /// How its value is written.
    pub kind: OptionKind,
}

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
    /// The options as `adapt` arguments, in [`OPTION_KEYS`] order, each value apart
    /// from its flag (the parts of the content hash).
    pub args: Vec<String>,
    /// The same arguments as `adapt` is given them: each value joined to its flag
    /// (`--hmin=-1`), so that no value is read as a flag.
    pub argv: Vec<String>,
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
    /// history, then the options. Every value is joined to its flag (`--hmin=-1`) and
    /// every path is kept from starting with `-`, so that no value is read as a flag.
    pub fn adapt_args(&self, dir: &Path) -> Vec<std::ffi::OsString> {
        let mut a: Vec<std::ffi::OsString> = vec![
            "adapt".into(),
            not_a_flag(&self.input),
            "--recipe".into(),
            not_a_flag(&self.recipe),
            "-o".into(),
            not_a_flag(&dir.join(self.output_name())),
            "--history".into(),
            not_a_flag(&dir.join(self.history_name())),
        ];
        a.extend(self.argv.iter().map(Into::into));
        a
    }

    /// Whether its input and recipe are files that can be read: why not, otherwise.
    pub fn check_files(&self) -> Result<(), String> {
        for (key, p) in [("input", &self.input), ("recipe", &self.recipe)] {
            match std::fs::metadata(p) {
                Ok(m) if m.is_file() => {}
                Ok(_) => return Err(format!("`{key}` {} is not a file", shown(&p.display().to_string()))),
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    return Err(format!("`{key}` {} does not exist (expected a file; relative paths are relative to the manifest's folder)", shown(&p.display().to_string())))
                }
                Err(e) => return Err(format!("`{key}` {}: {e}", shown(&p.display().to_string()))),
            }
        }
        Ok(())
    }

    /// Every file a run of this variant may write in its directory, by name: the output
    /// and the files its format writes beside it (Triangle's family, Medit's solution),
    /// the history and the log.
    pub fn output_names(&self) -> Vec<String> {
        let siblings: &[&str] = match smartmesh_formats::Format::from_extension(&self.format) {
            Some(smartmesh_formats::Format::Triangle) => &["node", "ele", "poly", "edge", "area"],
            Some(smartmesh_formats::Format::Medit) => &["sol", "solb"],
            _ => &[],
        };
        let mut names = vec![self.output_name()];
        names.extend(siblings.iter().map(|e| format!("{}.{e}", self.name)));
        names.extend([self.history_name(), self.log_name()]);
        names.sort();
        names.dedup();
        names
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
    table: &[AdaptOption],
) -> Result<Option<Variant>, ManifestError> {
    let err =
        |message: String| ManifestError { source_name: source_name.to_string(), line, message };
    // A byte order mark (a manifest saved by some Windows editors) is not text.
    let text = text.trim_start_matches('\u{feff}').trim();
    if text.is_empty() {
        return Ok(None);
    }
    let value: Value = strict_json(text).map_err(|e| {
        err(format!(
            "not a JSON object ({}); expected one variant per line: {{\"name\": ..., \"input\": ..., \"recipe\": ..., \"options\": {{...}}}}",
            shown(&e)
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
            "unknown key `{}`{}; known: {}",
            shown(key),
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
        Ok(if p.is_absolute() { p } else { base.join(p) })
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
    let (format, args, argv) = option_args(options, table).map_err(err)?;
    Ok(Some(Variant { line, name, input, recipe, format, args, argv }))
}

/// Parses a whole manifest, its options those of `table`; names must be unique.
pub fn parse(
    text: &str,
    manifest: &Path,
    table: &[AdaptOption],
) -> Result<Vec<Variant>, ManifestError> {
    let base = manifest.parent().unwrap_or(Path::new(""));
    let base = if base.as_os_str().is_empty() { Path::new(".") } else { base };
    let source_name = manifest.display().to_string();
    let mut variants: Vec<Variant> = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for (i, line) in text.lines().enumerate() {
        let Some(v) = parse_line(line, i + 1, base, &source_name, table)? else { continue };
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
        return Err(format!(
            "`{}` starts with `.`; expected letters, digits, `.`, `_` or `-`",
            shown(name)
        ));
    }
    if name.len() > 200 {
        return Err(format!("is {} bytes long; at most 200", name.len()));
    }
    match name.chars().find(|c| !(c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-'))) {
        Some(c) => Err(format!("`{}` holds {c:?}; expected letters, digits, `.`, `_` or `-` (it names the output files)", shown(name))),
        None => Ok(()),
    }
}

/// The output extension and the `adapt` arguments of an `options` object (each value
/// apart from its flag, and joined to it: [`Variant::args`], [`Variant::argv`]).
pub fn option_args(
    options: &Map<String, Value>,
    table: &[AdaptOption],
) -> Result<(String, Vec<String>, Vec<String>), String> {
    let known: Vec<&str> = table.iter().map(|o| o.key).collect();
    if let Some(key) = options.keys().find(|k| !known.contains(&k.as_str())) {
        return Err(format!(
            "unknown option `{}`{}; known: {}",
            shown(key),
            did_you_mean(key, &known),
            known.join(", ")
        ));
    }
    let mut format = "msh".to_string();
    let mut args = Vec::new();
    let mut argv = Vec::new();
    for &AdaptOption { key, ref flag, kind } in table {
        let Some(value) = options.get(key) else { continue };
        let flag = flag.as_str();
        let before = args.len();
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
                    return Err(format!("option `format` `{}` is not a mesh file extension (msh, vtu, vtk, mesh, meshb, obj, node, gltf, glb, su2, foam)", shown(&s)));
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
        match &args[before..] {
            [flag, value] if kind != OptionKind::List => argv.push(format!("{flag}={value}")),
            added => argv.extend(added.iter().cloned()),
        }
    }
    Ok((format, args, argv))
}

/// `text` as it may be shown on a terminal: control characters (escape sequences, bells,
/// carriage returns) escaped as Rust writes them (`\u{1b}`), the rest unchanged.
pub fn shown(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    out
}

/// `path` made safe to pass as an argument: a relative path starting with `-` gets `./`
/// before it, so that no parser takes it for a flag.
fn not_a_flag(path: &Path) -> std::ffi::OsString {
    if path.as_os_str().as_encoded_bytes().first() == Some(&b'-') {
        Path::new(".").join(path).into_os_string()
    } else {
        path.as_os_str().to_owned()
    }
}

/// A JSON value, refusing an object that gives a key twice (serde_json keeps the last
/// silently).
fn strict_json(text: &str) -> Result<Value, String> {
    let mut de = serde_json::Deserializer::from_str(text);
    let value =
        serde::Deserialize::deserialize(&mut de).map(|Strict(v)| v).map_err(|e| e.to_string())?;
    de.end().map_err(|e| e.to_string())?;
    Ok(value)
}

/// A [`Value`] read with duplicate keys refused.
struct Strict(Value);

impl<'de> serde::Deserialize<'de> for Strict {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Strict, D::Error> {
        d.deserialize_any(StrictVisitor).map(Strict)
    }
}

struct StrictVisitor;

impl<'de> serde::de::Visitor<'de> for StrictVisitor {
    type Value = Value;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a JSON value")
    }
    fn visit_bool<E>(self, b: bool) -> Result<Value, E> {
        Ok(Value::Bool(b))
    }
    fn visit_i64<E>(self, n: i64) -> Result<Value, E> {
        Ok(Value::from(n))
    }
    fn visit_u64<E>(self, n: u64) -> Result<Value, E> {
        Ok(Value::from(n))
    }
    fn visit_f64<E>(self, n: f64) -> Result<Value, E> {
        Ok(serde_json::Number::from_f64(n).map_or(Value::Null, Value::Number))
    }
    fn visit_str<E>(self, s: &str) -> Result<Value, E> {
        Ok(Value::String(s.to_string()))
    }
    fn visit_string<E>(self, s: String) -> Result<Value, E> {
        Ok(Value::String(s))
    }
    fn visit_unit<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_none<E>(self) -> Result<Value, E> {
        Ok(Value::Null)
    }
    fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<Value, A::Error> {
        let mut items = Vec::new();
        while let Some(Strict(v)) = seq.next_element()? {
            items.push(v);
        }
        Ok(Value::Array(items))
    }
    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Value, A::Error> {
        let mut object = Map::new();
        while let Some(key) = map.next_key::<String>()? {
            let Strict(v) = map.next_value()?;
            if object.contains_key(&key) {
                return Err(serde::de::Error::custom(format!(
                    "the key `{}` is given twice",
                    shown(&key)
                )));
            }
            object.insert(key, v);
        }
        Ok(Value::Object(object))
    }
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

    /// The options as `adapt` declares them (the CLI's test checks its table against
    /// this one).
    fn table() -> Vec<AdaptOption> {
        use OptionKind::*;
        let kinds = [
            Text, Text, List, Count, Number, Number, Count, Number, Number, Number, Number, Number,
            Switch, Switch, Switch, Text, Text, Text, Switch, Text, Text, Text, Switch, Number,
            Number, List,
        ];
        OPTION_KEYS
            .iter()
            .zip(kinds)
            .map(|(&key, kind)| AdaptOption {
                key,
                flag: match key {
                    "format" => String::new(),
                    "adapter_args" => "--adapter-arg".into(),
                    k => format!("--{}", k.replace('_', "-")),
                },
                kind,
            })
            .collect()
    }

    fn parse_line(
        text: &str,
        line: usize,
        base: &Path,
        source_name: &str,
    ) -> Result<Option<Variant>, ManifestError> {
        super::parse_line(text, line, base, source_name, &table())
    }

    fn parse(text: &str, manifest: &Path) -> Result<Vec<Variant>, ManifestError> {
        super::parse(text, manifest, &table())
    }

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
        // Values are joined to their flags: `-1` is a value, not a flag.
        let neg = r#"{"name":"v","input":"a.poly","recipe":"r.toml","options":{"hmin":-1,"nosurf":true,"adapter_args":["-v"]}}"#;
        let v = parse_line(neg, 1, d.path(), "m").unwrap().unwrap();
        let args: Vec<String> = v
            .adapt_args(Path::new("out"))
            .into_iter()
            .skip(8)
            .map(|a| a.into_string().unwrap())
            .collect();
        assert_eq!(args, ["--adapter-arg=-v", "--hmin=-1", "--nosurf"]);
        // A path starting with `-` is not a flag either.
        let dashed = parse_line(neg, 1, Path::new("-dir"), "m").unwrap().unwrap();
        assert_eq!(dashed.adapt_args(Path::new("out"))[1], "./-dir/a.poly");
    }

    #[test]
    fn a_missing_file_is_the_variants_not_the_manifests() {
        let d = files();
        let line = r#"{"name":"a","input":"missing.poly","recipe":"r.toml"}"#;
        let v = parse_line(line, 1, d.path(), "m").unwrap().unwrap();
        let e = v.check_files().unwrap_err();
        assert!(e.contains("missing.poly") && e.contains("does not exist"), "{e}");
        let ok = parse_line(r#"{"name":"a","input":"a.poly","recipe":"r.toml"}"#, 1, d.path(), "m");
        assert_eq!(ok.unwrap().unwrap().check_files(), Ok(()));
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
            (
                r#"{"name":"a","input":"a.poly","recipe":"r.toml","name":"b"}"#,
                "the key `name` is given twice",
            ),
            (
                r#"{"name":"a","input":"a.poly","recipe":"r.toml","options":{"hmin":1,"hmin":2}}"#,
                "the key `hmin` is given twice",
            ),
            (
                r#"{"name":"a\u001b[2Jb","input":"a.poly","recipe":"r.toml"}"#,
                "`a\\u{1b}[2Jb` holds",
            ),
            (
                r#"{"name":"a","in\u0007put":"a.poly","recipe":"r.toml"}"#,
                "unknown key `in\\u{7}put`",
            ),
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
        // A byte order mark before the first line is no part of it.
        let ok = parse(&format!("\u{feff}{v}\n"), &m).unwrap();
        assert_eq!(ok[0].name, "a");
        assert!(parse("\n\n", &m).unwrap_err().message.contains("no variant"));
    }
}
