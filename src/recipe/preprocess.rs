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

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use super::error::{RecipeError, RecipeErrorKind};

/// Environment variable naming the preprocessor command (split on spaces, e.g.
/// `gcc -E`); by default `cpp`, then `gcc -E`, `clang -E`, `cc -E` are tried.
pub const CPP_VARIABLE: &str = "SMARTMESH_CPP";

/// How deep `@include` and `#include` may nest before we call it a cycle.
const MAX_INCLUDE_DEPTH: usize = 16;

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

/// Text ready for the libconfig parser, with the origin of each of its lines.
#[derive(Debug, Clone, Default)]
pub struct Source {
    /// The text.
    pub text: String,
    /// Every file a line came from.
    pub files: Vec<PathBuf>,
    /// For line `i` (0-based) of `text`: index into `files`, 1-based line there.
    pub lines: Vec<(u32, u32)>,
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
        match self.files.iter().position(|p| p == path) {
            Some(i) => i as u32,
            None => {
                self.files.push(path.to_path_buf());
                (self.files.len() - 1) as u32
            }
        }
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

/// Runs cpp when needed, then expands `@include`; `origin` names the text's file.
pub fn load(text: &str, origin: &Path) -> Result<Source, RecipeError> {
    let mut out = Source::default();
    out.file_index(origin);
    expand(text, origin, &mut out, 0)?;
    Ok(out)
}

fn expand(text: &str, origin: &Path, out: &mut Source, depth: usize) -> Result<(), RecipeError> {
    let pre = if let Some((line, d)) = first_directive(text) {
        run_cpp(text, origin, line, &d)?
    } else {
        identity(text, origin)
    };
    for (i, l) in pre.text.lines().enumerate() {
        let (file, line) = pre.place(i);
        let (file, line) = (file.to_path_buf(), line);
        if let Some(rest) = l.trim_start().strip_prefix("@include") {
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
            let included = std::fs::read_to_string(&target).map_err(|e| {
                RecipeError::new(RecipeErrorKind::Io(format!(
                    "@include \"{name}\": {}: {e}",
                    target.display()
                )))
                .at(&file, line)
            })?;
            expand(&included, &target, out, depth + 1)?;
            // The @include line itself stays, empty, so that line counts hold.
            let f = out.file_index(&file);
            out.push_line("", f, line as u32);
        } else {
            let f = out.file_index(&file);
            out.push_line(l, f, line as u32);
        }
    }
    Ok(())
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

fn candidates() -> Vec<Vec<String>> {
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

fn run_cpp(
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
    let input = protect_hash_comments(text);
    let mut tried = Vec::new();
    for cmd in candidates() {
        let mut c = Command::new(&cmd[0]);
        c.args(&cmd[1..]).args(["-x", "c", "-undef", "-nostdinc", "-w", "-"]);
        if dir.is_dir() {
            c.current_dir(&dir);
        }
        let child = c.stdin(Stdio::piped()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn();
        let mut child = match child {
            Ok(ch) => ch,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                tried.push(cmd.join(" "));
                continue;
            }
            Err(e) => {
                return Err(RecipeError::new(RecipeErrorKind::Preprocessor(format!(
                    "cannot run the C preprocessor `{}`: {e}",
                    cmd.join(" ")
                )))
                .in_file(origin))
            }
        };
        // Write on another thread: a large output could fill the pipe while we write.
        let mut stdin = child.stdin.take().expect("stdin was piped");
        let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
        let output = child.wait_with_output().map_err(|e| {
            RecipeError::new(RecipeErrorKind::Preprocessor(format!(
                "cannot run the C preprocessor `{}`: {e}",
                cmd.join(" ")
            )))
            .in_file(origin)
        })?;
        let _ = writer.join();
        let origin_name = origin.display().to_string();
        if !output.status.success() {
            let msg = String::from_utf8_lossy(&output.stderr).replace("<stdin>", &origin_name);
            return Err(RecipeError::new(RecipeErrorKind::Preprocessor(format!(
                "the C preprocessor `{}` failed:\n{}",
                cmd.join(" "),
                msg.trim_end()
            ))));
        }
        return Ok(read_line_markers(&String::from_utf8_lossy(&output.stdout), origin, &dir));
    }
    Err(RecipeError::new(RecipeErrorKind::Preprocessor(format!(
        "the recipe uses the C preprocessor ({directive}) but none was found (tried {}); install one (Debian/Ubuntu: apt-get install cpp; Fedora: dnf install cpp; macOS: xcode-select --install) or set {CPP_VARIABLE}",
        tried.join(", ")
    )))
    .at(origin, directive_line))
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
        line += 1;
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
