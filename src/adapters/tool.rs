//! External programs: where they are and how a run went. A missing program is said
//! before any work starts; a failing one is quoted (the end of its stderr and stdout),
//! because the tool's own words are what a user needs to fix the problem.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use super::AdapterError;

/// Lines of a failing tool's output quoted in the error.
const QUOTED_LINES: usize = 20;

/// `explicit` when given (it must exist), else the first executable file called `name` in
/// the directories of `PATH`. `hint` says how to get the program. The path returned is
/// absolute: the tool runs in a temporary directory, and a relative `./tool.sh` means
/// the one in the current directory.
pub fn find_program(
    name: &str,
    explicit: Option<&Path>,
    hint: &'static str,
) -> Result<PathBuf, AdapterError> {
    if let Some(p) = explicit {
        let why = if is_executable(p) {
            return std::path::absolute(p).map_err(|source| AdapterError::Io {
                what: format!("finding {}", p.display()),
                source,
            });
        } else if p.exists() {
            "is not an executable file"
        } else {
            "does not exist"
        };
        return Err(AdapterError::Unusable { program: p.display().to_string(), why, hint });
    }
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .filter(|dir| !dir.as_os_str().is_empty())
        .map(|dir| dir.join(name))
        .find(|p| is_executable(p))
        .ok_or_else(|| AdapterError::NotFound { program: name.to_string(), hint })
}

#[cfg(unix)]
fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p)
        .map(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
        .unwrap_or(false)
}

#[cfg(not(unix))]
fn is_executable(p: &Path) -> bool {
    p.is_file() || p.with_extension("exe").is_file()
}

/// Runs `program args…` in `dir` and returns its output when it exits with 0; otherwise
/// an [`AdapterError::Failed`] quoting the end of what it printed.
pub fn run(program: &Path, args: &[impl AsRef<OsStr>], dir: &Path) -> Result<Output, AdapterError> {
    let name = program
        .file_name()
        .map_or_else(|| program.display().to_string(), |n| n.to_string_lossy().into_owned());
    let out = Command::new(program).args(args).current_dir(dir).output().map_err(|source| {
        AdapterError::Io { what: format!("starting {}", program.display()), source }
    })?;
    if out.status.success() {
        return Ok(out);
    }
    let status = match out.status.code() {
        Some(c) => format!("exit status {c}"),
        None => "killed by a signal".to_string(),
    };
    let command = std::iter::once(name)
        .chain(args.iter().map(|a| a.as_ref().to_string_lossy().into_owned()))
        .collect::<Vec<_>>()
        .join(" ");
    Err(AdapterError::Failed { program: command, status, output: quote(&out) })
}

/// The last lines of a run's stderr, then of its stdout, each line indented.
pub fn quote(out: &Output) -> String {
    let mut lines = Vec::new();
    for stream in [&out.stderr, &out.stdout] {
        let text = String::from_utf8_lossy(stream);
        let all: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
        let from = all.len().saturating_sub(QUOTED_LINES);
        lines.extend(all[from..].iter().map(|l| format!("    {l}")));
    }
    if lines.is_empty() {
        "    (it printed nothing)".to_string()
    } else {
        lines.join("\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn explicit_program_must_exist() {
        let e =
            find_program("x", Some(Path::new("/nonexistent/mmg2d_O3")), "install it").unwrap_err();
        assert!(e.to_string().contains("/nonexistent/mmg2d_O3"), "{e}");
    }

    #[cfg(unix)]
    #[test]
    fn a_failing_program_is_quoted() {
        let dir = tempfile::tempdir().unwrap();
        let e = run(
            Path::new("/bin/sh"),
            &["-c", "echo first; echo 'bad thing' >&2; exit 3"],
            dir.path(),
        )
        .unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("exit status 3") && text.contains("bad thing") && text.contains("first"),
            "{text}"
        );
    }
}
