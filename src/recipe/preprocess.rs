//! Before parsing a libconfig recipe: the C preprocessor (thesis 5.3.4) and libconfig's
//! own `@include`, with a map from every line of the result back to its file and line.
//!
//! The thesis runs recipes through `cpp` so that `#define` can name values used many
//! times (appendix A.1.6 defines `GUIDEVANE` as a list of tags). We run the system
//! preprocessor only when the text holds a directive, so a plain recipe needs no
//! compiler installed. Its output keeps `# <line> "<file>"` line markers (no `-P`), which
//! we read to point every error into the original file, also inside `#include`d files.
//!
//! Libconfig also allows `#` comments, which cpp would take for unknown directives: such
//! lines are turned into `//` comments (same line count) before cpp sees them.
//! `-undef` keeps cpp from replacing words such as `unix` or `linux` by `1`; `-nostdinc`
//! keeps system headers out.
//!
//! A recipe is code: cpp and `@include` open whatever file it names. What it may pull in
//! is capped ([`ReadOptions`]): every file is read through a bounded reader that refuses
//! anything but a regular file (`/dev/zero`, a pipe); the text after includes and cpp
//! may not exceed [`MAX_RECIPE_BYTES`]; cpp runs as every external program does
//! (`crate::child`: in a process group of its own, which dies with us however we end),
//! killed when its output passes what is left of that budget or when it runs past
//! [`CPP_TIME_LIMIT`] (one deadline for every cpp run of a recipe). Before cpp runs, the
//! files its literal `#include`s name are checked the same way, so `#include
//! </dev/zero>` is an error at its line rather than a timeout. [`ReadOptions::untrusted`]
//! (the CLI's `--no-preprocess`) turns cpp and `@include` off: the recipe then reads no
//! file but itself.

use std::collections::{BTreeMap, BTreeSet};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use super::error::{RecipeError, RecipeErrorKind};
use crate::child::{self, Ended, Keep, Run};

/// Environment variable naming the preprocessor command (split on spaces, e.g.
/// `gcc -E`); by default `cpp`, then `gcc -E`, `clang -E`, `cc -E` are tried.
pub const CPP_VARIABLE: &str = "SMARTMESH_CPP";

/// How deep `@include` and `#include` may nest before we call it a cycle.
const MAX_INCLUDE_DEPTH: usize = 16;

/// The largest text a recipe may become, its own text, its includes and cpp's output
/// counted (the recipes of the thesis are a few kilobytes; a polyline of 10^5 points
/// is about 4 MiB).
pub const MAX_RECIPE_BYTES: usize = 16 << 20;

/// How long the C preprocessor may run, all its runs for one recipe together (it
/// takes a few milliseconds on the recipes of the thesis).
pub const CPP_TIME_LIMIT: Duration = Duration::from_secs(10);

/// How much of cpp's error output a message quotes.
const MAX_CPP_MESSAGE: usize = 8 << 10;

/// Directives that make a recipe go through cpp.
const DIRECTIVES: &[&str] = &[
    "define",
    "undef",
    "include",
    "include_next",
    "if",
    "ifdef",
    "ifndef",
    "elif",
    "elifdef",
    "elifndef",
    "else",
    "endif",
    "error",
    "warning",
    "pragma",
    "line",
];

/// What reading a recipe may do beyond parsing its own text, and how much it may pull
/// in.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReadOptions {
    /// Run the C preprocessor on a libconfig recipe with directives and follow
    /// `@include`; when false, a directive or an `@include` is an error, and no file
    /// but the recipe itself is read.
    pub preprocess: bool,
    /// The largest text the recipe may become, in bytes (see [`MAX_RECIPE_BYTES`]).
    pub max_bytes: usize,
    /// How long the C preprocessor may run, all its runs together.
    pub cpp_time_limit: Duration,
    /// The preprocessor command (program and arguments, to which `-x c -undef
    /// -nostdinc -w -` are added); `None`: [`CPP_VARIABLE`], else `cpp`, `gcc -E`,
    /// `clang -E`, `cc -E`, the first found.
    pub cpp_command: Option<Vec<String>>,
}

impl Default for ReadOptions {
    fn default() -> ReadOptions {
        ReadOptions {
            preprocess: true,
            max_bytes: MAX_RECIPE_BYTES,
            cpp_time_limit: CPP_TIME_LIMIT,
            cpp_command: None,
        }
    }
}

impl ReadOptions {
    /// For a recipe from someone else: no C preprocessor, no `@include`.
    pub fn untrusted() -> ReadOptions {
        ReadOptions { preprocess: false, ..ReadOptions::default() }
    }
}

/// `bytes` in MiB or kB, for messages.
fn size_words(bytes: usize) -> String {
    if bytes >= 1 << 20 {
        format!("{:.0} MiB", bytes as f64 / (1u64 << 20) as f64)
    } else {
        format!("{} kB", bytes.div_ceil(1000))
    }
}

fn limit_error(message: String) -> RecipeError {
    RecipeError::new(RecipeErrorKind::Limit(message))
}

/// Reads a file a recipe names (the recipe itself, or an `@include`d file): a regular
/// file of at most `limit` bytes of UTF-8. A device, pipe or directory is refused
/// before it is opened (opening a pipe would block), and the size is checked again on
/// the open file, whose reading stops past `limit` whatever its metadata said.
/// `budget` is the recipe's whole budget, for the message.
pub fn read_file(path: &Path, limit: usize, budget: usize) -> Result<String, RecipeError> {
    let io = |e: std::io::Error| {
        RecipeError::new(RecipeErrorKind::Io(format!("{}: {e}", path.display())))
    };
    let not_regular = || {
        RecipeError::new(RecipeErrorKind::Io(format!(
            "{} is not a regular file (a device, a pipe or a directory): a recipe reads only regular files",
            path.display()
        )))
    };
    let too_large = || {
        limit_error(format!(
            "{} is larger than the {} a recipe may still take (at most {} in all, includes and the C preprocessor's output counted)",
            path.display(),
            size_words(limit),
            size_words(budget)
        ))
    };
    if !std::fs::metadata(path).map_err(io)?.is_file() {
        return Err(not_regular());
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let meta = file.metadata().map_err(io)?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    if meta.len() > limit as u64 {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit as u64 + 1).read_to_end(&mut bytes).map_err(io)?;
    if bytes.len() > limit {
        return Err(too_large());
    }
    String::from_utf8(bytes).map_err(|e| {
        RecipeError::new(RecipeErrorKind::Io(format!(
            "{}: not UTF-8 text (byte {} is not valid UTF-8)",
            path.display(),
            e.utf8_error().valid_up_to()
        )))
    })
}

/// Text ready for the libconfig parser, with the origin of each of its lines.
#[derive(Debug, Clone, Default)]
pub struct Source {
    /// The text.
    pub text: String,
    /// Every file a line came from.
    pub files: Vec<PathBuf>,
    /// For line `i` (0-based) of `text`: index into `files`, 1-based line there.
    pub lines: Vec<(u32, u32)>,
    /// `files` by path: cpp's line markers may name many files.
    index: BTreeMap<PathBuf, u32>,
}

impl Source {
    /// The file and 1-based line of the 0-based line `line` of `text`.
    pub fn place(&self, line: usize) -> (&Path, usize) {
        match self.lines.get(line).or(self.lines.last()) {
            Some(&(f, l)) => (&self.files[f as usize], l as usize),
            None => (self.files.first().map(PathBuf::as_path).unwrap_or(Path::new("")), 0),
        }
    }

    fn file_index(&mut self, path: &Path) -> u32 {
        if let Some(&i) = self.index.get(path) {
            return i;
        }
        let i = self.files.len() as u32;
        self.files.push(path.to_path_buf());
        self.index.insert(path.to_path_buf(), i);
        i
    }

    fn push_line(&mut self, text: &str, file: u32, line: u32) {
        self.text.push_str(text);
        self.text.push('\n');
        self.lines.push((file, line));
    }
}

/// The first directive line of `text` (1-based line and the directive), if any.
pub fn first_directive(text: &str) -> Option<(usize, String)> {
    text.lines().enumerate().find_map(|(i, l)| directive(l).map(|d| (i + 1, format!("#{d}"))))
}

fn directive(line: &str) -> Option<&'static str> {
    let rest = line.trim_start().strip_prefix('#')?.trim_start();
    let word: &str =
        &rest[..rest.find(|c: char| !c.is_ascii_alphanumeric() && c != '_').unwrap_or(rest.len())];
    DIRECTIVES.iter().copied().find(|d| *d == word)
}

/// One recipe being loaded: its options, the one deadline of its cpp runs, the text so far.
struct Loader<'a> {
    options: &'a ReadOptions,
    deadline: Instant,
    out: Source,
}

/// Runs cpp when needed, then expands `@include`; `origin` names the text's file.
pub fn load(text: &str, origin: &Path, options: &ReadOptions) -> Result<Source, RecipeError> {
    if text.len() > options.max_bytes {
        return Err(limit_error(format!(
            "the recipe is larger than {} (the limit on a recipe's text)",
            size_words(options.max_bytes)
        ))
        .in_file(origin));
    }
    let mut loader = Loader {
        options,
        deadline: Instant::now() + options.cpp_time_limit,
        out: Source::default(),
    };
    loader.out.file_index(origin);
    loader.expand(text, origin, 0)?;
    Ok(loader.out)
}

impl Loader<'_> {
    /// What is left of the byte budget.
    fn left(&self) -> usize {
        self.options.max_bytes.saturating_sub(self.out.text.len())
    }

    fn expand(&mut self, text: &str, origin: &Path, depth: usize) -> Result<(), RecipeError> {
        let pre = match first_directive(text) {
            Some((line, d)) if !self.options.preprocess => {
                return Err(RecipeError::new(RecipeErrorKind::NotAllowed(format!(
                    "{d} is a C preprocessor directive, and the preprocessor is off (--no-preprocess)"
                )))
                .at(origin, line))
            }
            Some((line, d)) => {
                check_includes(text, origin, &mut BTreeSet::new(), 0, self.options)?;
                self.run_cpp(text, origin, line, &d)?
            }
            None => identity(text, origin),
        };
        for (i, l) in pre.text.lines().enumerate() {
            let (file, line) = pre.place(i);
            let (file, line) = (file.to_path_buf(), line);
            if let Some(rest) = l.trim_start().strip_prefix("@include") {
                if !self.options.preprocess {
                    return Err(RecipeError::new(RecipeErrorKind::NotAllowed(
                        "@include reads another file, and includes are off (--no-preprocess)"
                            .into(),
                    ))
                    .at(&file, line));
                }
                let name = parse_include_name(rest).ok_or_else(|| {
                    RecipeError::new(RecipeErrorKind::Syntax(
                        "@include needs a file name in double quotes".into(),
                    ))
                    .at(&file, line)
                })?;
                if depth >= MAX_INCLUDE_DEPTH {
                    return Err(RecipeError::new(RecipeErrorKind::Syntax(format!(
                        "@include nested deeper than {MAX_INCLUDE_DEPTH} files (a cycle?)"
                    )))
                    .at(&file, line));
                }
                let target = file.parent().unwrap_or(Path::new("")).join(&name);
                let included = read_file(&target, self.left(), self.options.max_bytes)
                    .map_err(|e| prefixed(e.at(&file, line), &format!("@include \"{name}\"")))?;
                self.expand(&included, &target, depth + 1)?;
                // The @include line itself stays, empty, so that line counts hold.
                let f = self.out.file_index(&file);
                self.out.push_line("", f, line as u32);
            } else {
                let f = self.out.file_index(&file);
                self.out.push_line(l, f, line as u32);
            }
            if self.out.text.len() > self.options.max_bytes {
                return Err(limit_error(format!(
                    "the recipe grows past {} with its includes (the limit on a recipe's text)",
                    size_words(self.options.max_bytes)
                ))
                .at(&file, line));
            }
        }
        Ok(())
    }
}

/// `error` with its message prefixed by `what: ` (the directive that read the file).
fn prefixed(mut error: RecipeError, what: &str) -> RecipeError {
    let kind = std::mem::replace(&mut *error.kind, RecipeErrorKind::Io(String::new()));
    *error.kind = match kind {
        RecipeErrorKind::Io(m) => RecipeErrorKind::Io(format!("{what}: {m}")),
        RecipeErrorKind::Limit(m) => RecipeErrorKind::Limit(format!("{what}: {m}")),
        other => other,
    };
    error
}

fn parse_include_name(rest: &str) -> Option<String> {
    let rest = rest.trim();
    let inner = rest.strip_prefix('"')?;
    let end = inner.find('"')?;
    Some(inner[..end].to_string())
}

fn identity(text: &str, origin: &Path) -> Source {
    let mut s = Source::default();
    let f = s.file_index(origin);
    for (i, l) in text.lines().enumerate() {
        s.push_line(l, f, (i + 1) as u32);
    }
    s
}

/// The file a literal `#include "name"` or `#include <name>` line names, seen from
/// `dir` (cpp's search with `-nostdinc` and no `-I`: a quoted name from the including
/// file's directory, an angled one only when absolute); `None` for other lines and for
/// computed includes (`#include MACRO`), which cpp resolves under the time limit.
fn literal_include(line: &str, dir: &Path) -> Option<PathBuf> {
    let rest = line.trim_start().strip_prefix('#')?.trim_start();
    let rest =
        rest.strip_prefix("include_next").or_else(|| rest.strip_prefix("include"))?.trim_start();
    let (name, quoted) = if let Some(r) = rest.strip_prefix('"') {
        (&r[..r.find('"')?], true)
    } else {
        let r = rest.strip_prefix('<')?;
        (&r[..r.find('>')?], false)
    };
    let path = Path::new(name);
    if path.is_absolute() {
        Some(path.to_path_buf())
    } else if quoted {
        Some(dir.join(path))
    } else {
        None
    }
}

/// Checks every file the literal `#include`s of `text` (and of the files they include)
/// name, as [`read_file`] would read it: a device or a pipe is an error at the line
/// that names it. A file that does not exist is left to cpp, which says so. Each file
/// is read once; conditional sections are not evaluated, so this may refuse a file that
/// an `#if 0` would have skipped.
fn check_includes(
    text: &str,
    file: &Path,
    seen: &mut BTreeSet<PathBuf>,
    depth: usize,
    options: &ReadOptions,
) -> Result<(), RecipeError> {
    let dir = file.parent().unwrap_or(Path::new(""));
    for (i, l) in text.lines().enumerate() {
        let Some(target) = literal_include(l, dir) else { continue };
        if !target.exists() || !seen.insert(target.clone()) {
            continue;
        }
        let included = read_file(&target, options.max_bytes, options.max_bytes)
            .map_err(|e| prefixed(e.at(file, i + 1), "#include"))?;
        if depth < MAX_INCLUDE_DEPTH {
            check_includes(&included, &target, seen, depth + 1, options)?;
        }
    }
    Ok(())
}

/// `#` lines that are not directives are libconfig comments: hide them from cpp.
fn protect_hash_comments(text: &str) -> String {
    let mut s = String::with_capacity(text.len() + 64);
    for l in text.lines() {
        let t = l.trim_start();
        if t.starts_with('#') && directive(l).is_none() {
            s.push_str("//");
            s.push_str(t);
        } else {
            s.push_str(l);
        }
        s.push('\n');
    }
    s
}

fn candidates(options: &ReadOptions) -> Vec<Vec<String>> {
    if let Some(cmd) = options.cpp_command.as_ref().filter(|c| !c.is_empty()) {
        return vec![cmd.clone()];
    }
    if let Ok(cmd) = std::env::var(CPP_VARIABLE) {
        let words: Vec<String> = cmd.split_whitespace().map(String::from).collect();
        if !words.is_empty() {
            return vec![words];
        }
    }
    [&["cpp"][..], &["gcc", "-E"], &["clang", "-E"], &["cc", "-E"]]
        .iter()
        .map(|c| c.iter().map(|s| s.to_string()).collect())
        .collect()
}

impl Loader<'_> {
    fn run_cpp(
        &self,
        text: &str,
        origin: &Path,
        directive_line: usize,
        directive: &str,
    ) -> Result<Source, RecipeError> {
        let dir = origin
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .map(Path::to_path_buf)
            .unwrap_or_else(|| PathBuf::from("."));
        let mut tried = Vec::new();
        for cmd in candidates(self.options) {
            let Some(program) = child::locate(&cmd[0]) else {
                tried.push(cmd.join(" "));
                continue;
            };
            let budget = self.left();
            let mut run = Run::new(program)
                .args(&cmd[1..])
                .args(["-x", "c", "-undef", "-nostdinc", "-w", "-"])
                .stdin(protect_hash_comments(text).into_bytes())
                .keep(Keep::All(budget), Keep::Head(MAX_CPP_MESSAGE))
                .deadline(self.deadline);
            if dir.is_dir() {
                run = run.current_dir(&dir);
            }
            let name = cmd.join(" ");
            let ended = match run.run() {
                Ok(ended) => ended,
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    tried.push(name);
                    continue;
                }
                Err(e) => {
                    return Err(RecipeError::new(RecipeErrorKind::Preprocessor(format!(
                        "cannot run the C preprocessor `{name}`: {e}"
                    )))
                    .in_file(origin))
                }
            };
            let output = match ended {
                Ended::Exited { status, stdout, .. } if status.success() => stdout.bytes,
                Ended::Exited { stderr, .. } => {
                    let origin_name = origin.display().to_string();
                    let mut msg =
                        String::from_utf8_lossy(&stderr.bytes).replace("<stdin>", &origin_name);
                    if stderr.cut() {
                        msg.push_str("\n[…]");
                    }
                    return Err(RecipeError::new(RecipeErrorKind::Preprocessor(format!(
                        "the C preprocessor `{name}` failed:\n{}",
                        msg.trim_end()
                    ))));
                }
                Ended::TooLarge => {
                    return Err(limit_error(format!(
                        "the C preprocessor's output passed the {} left to the recipe (at most {} in all): a runaway macro, or an #include of a large file? `{name}` was stopped",
                        size_words(budget),
                        size_words(self.options.max_bytes)
                    ))
                    .in_file(origin))
                }
                Ended::TimedOut => {
                    return Err(limit_error(format!(
                        "the C preprocessor ran past its time limit of {:.3} s: an #include of a device or a pipe, or a runaway macro? `{name}` was stopped",
                        self.options.cpp_time_limit.as_secs_f64()
                    ))
                    .in_file(origin))
                }
                Ended::Interrupted => {
                    return Err(RecipeError::new(RecipeErrorKind::Preprocessor(format!(
                        "the C preprocessor `{name}` was stopped: smartmesh was interrupted"
                    )))
                    .in_file(origin))
                }
            };
            return Ok(read_line_markers(&String::from_utf8_lossy(&output), origin, &dir));
        }
        Err(RecipeError::new(RecipeErrorKind::Preprocessor(format!(
            "the recipe uses the C preprocessor ({directive}) but none was found (tried {}); install one (Debian/Ubuntu: apt-get install cpp; Fedora: dnf install cpp; macOS: xcode-select --install) or set {CPP_VARIABLE}",
            tried.join(", ")
        )))
        .at(origin, directive_line))
    }
}

/// Reads cpp output with `# <line> "<file>" flags…` markers into a [`Source`].
fn read_line_markers(out: &str, origin: &Path, dir: &Path) -> Source {
    let mut s = Source::default();
    let mut file = s.file_index(origin);
    let mut line: u32 = 1;
    for l in out.lines() {
        if let Some((n, name)) = line_marker(l) {
            let path = match name.as_str() {
                "<stdin>" | "-" => origin.to_path_buf(),
                other if Path::new(other).is_relative() && !other.starts_with('<') => {
                    dir.join(other)
                }
                other => PathBuf::from(other),
            };
            file = s.file_index(&path);
            line = n;
            continue;
        }
        s.push_line(l, file, line);
        line = line.saturating_add(1);
    }
    s
}

fn line_marker(l: &str) -> Option<(u32, String)> {
    let rest = l.strip_prefix("# ").or_else(|| l.strip_prefix("#line "))?;
    let (num, rest) = rest.split_once(' ')?;
    let n: u32 = num.parse().ok()?;
    let rest = rest.trim_start().strip_prefix('"')?;
    let mut name = String::new();
    let mut chars = rest.chars();
    while let Some(c) = chars.next() {
        match c {
            '\\' => name.push(chars.next()?),
            '"' => return Some((n, name)),
            c => name.push(c),
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directives_are_told_from_hash_comments() {
        assert_eq!(
            first_directive("a = 1;\n# a comment\n  #define X 3\n"),
            Some((3, "#define".into()))
        );
        assert_eq!(first_directive("# a comment\n#defined_not\n"), None);
        assert_eq!(protect_hash_comments("# note\n#if 0\n"), "//# note\n#if 0\n");
    }

    #[test]
    fn line_markers_map_back() {
        let out = "# 1 \"<stdin>\"\n# 1 \"<built-in>\"\n# 1 \"<stdin>\"\n\na = 1;\n# 1 \"sub/common.h\" 1\nb = 2;\n# 4 \"<stdin>\" 2\nc = 3;\n";
        let s = read_line_markers(out, Path::new("dir/r.cfg"), Path::new("dir"));
        let at = |k: usize| {
            let (f, l) = s.place(k);
            (f.display().to_string(), l)
        };
        assert_eq!(s.text.lines().collect::<Vec<_>>(), ["", "a = 1;", "b = 2;", "c = 3;"]);
        assert_eq!(at(1), ("dir/r.cfg".into(), 2));
        assert_eq!(at(2), ("dir/sub/common.h".into(), 1));
        assert_eq!(at(3), ("dir/r.cfg".into(), 4));
    }
}
