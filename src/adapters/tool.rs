//! External programs: where they are and how a run went. A missing program is said
//! before any work starts; a failing one is quoted (the end of its stderr and stdout),
//! because the tool's own words are what a user needs to fix the problem. A run goes
//! through [`crate::child`]: a process group of its own, the last [`KEPT`] bytes of each
//! stream kept, stopped when smartmesh is interrupted ([`AdapterError::Interrupted`],
//! its temporary directory then removed by its owner, or by [`crate::child::stop_all`]
//! on an exit at once).

use super::AdapterError;
use crate::child::{Captured, Ended, Keep, Run};
use std::ffi::OsStr;
use std::path::{Path, PathBuf};

/// Lines of a failing tool's output quoted in the error.
const QUOTED_LINES: usize = 20;

/// `explicit` when given (it must exist), else the first executable file called `name` in
/// the directories of `PATH`. `hint` says how to get the program. The path returned is
/// absolute: the tool runs in a temporary directory, and a relative `./tool.sh` means
/// the one in the current directory.
pub(crate) fn find_program(
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

/// What a program printed: the last [`KEPT`] bytes of each stream.
#[derive(Debug, Clone, Default)]
pub(crate) struct Printed {
    /// Its stdout.
    pub stdout: Captured,
    /// Its stderr.
    pub stderr: Captured,
}

/// The bytes of each output stream kept, at the end: a tool that prints gigabytes costs
/// no more.
pub(crate) const KEPT: usize = 64 << 10;

/// How a run that did not exit with 0 ended.
pub(crate) enum Stopped {
    /// It could not be started.
    Start(std::io::Error),
    /// It exited with another status or was killed; what it printed.
    Failed(String, Printed),
    /// smartmesh was interrupted ([`crate::child::interrupt`]): it was stopped.
    Interrupted,
}

/// Runs `run` (a [`crate::child::Run`] of the program) to its end, keeping the last
/// [`KEPT`] bytes of each stream: what it printed when it exits with 0.
pub(crate) fn finish(run: Run) -> Result<Printed, Stopped> {
    let ended = run.keep(Keep::Tail(KEPT), Keep::Tail(KEPT)).run().map_err(Stopped::Start)?;
    match ended {
        Ended::Exited { status, stdout, stderr } => {
            let printed = Printed { stdout, stderr };
            if status.success() {
                return Ok(printed);
            }
            Err(Stopped::Failed(status_words(status), printed))
        }
        // No deadline and no limit on a tail: only an interruption stops it.
        Ended::Interrupted | Ended::TimedOut | Ended::TooLarge => Err(Stopped::Interrupted),
    }
}

/// An exit status in words.
pub(crate) fn status_words(status: std::process::ExitStatus) -> String {
    if let Some(c) = status.code() {
        return format!("exit status {c}");
    }
    #[cfg(unix)]
    if let Some(s) = std::os::unix::process::ExitStatusExt::signal(&status) {
        return format!("killed by signal {s}");
    }
    "killed by a signal".to_string()
}

/// Runs `program args…` in `dir` (a scratch directory of the run, removed if smartmesh
/// exits at once) and returns what it printed when it exits with 0; otherwise an
/// [`AdapterError::Failed`] quoting the end of what it printed, or
/// [`AdapterError::Interrupted`].
pub(crate) fn run(
    program: &Path,
    args: &[impl AsRef<OsStr>],
    dir: &Path,
) -> Result<Printed, AdapterError> {
    let name = program
        .file_name()
        .map_or_else(|| program.display().to_string(), |n| n.to_string_lossy().into_owned());
    let child = Run::new(program)
        .args(args.iter().map(|a| a.as_ref().to_os_string()))
        .current_dir(dir)
        .scratch(dir);
    match finish(child) {
        Ok(printed) => Ok(printed),
        Err(Stopped::Start(source)) => {
            Err(AdapterError::Io { what: format!("starting {}", program.display()), source })
        }
        Err(Stopped::Interrupted) => Err(AdapterError::Interrupted { program: name }),
        Err(Stopped::Failed(status, printed)) => {
            let command = std::iter::once(name)
                .chain(args.iter().map(|a| a.as_ref().to_string_lossy().into_owned()))
                .collect::<Vec<_>>()
                .join(" ");
            Err(AdapterError::Failed { program: command, status, output: quote(&printed) })
        }
    }
}

/// The longest line quoted, in characters (its end is kept).
const QUOTED_WIDTH: usize = 400;

/// The last lines of a run's stderr, then of its stdout, each line indented, control
/// characters shown escaped, a line longer than [`QUOTED_WIDTH`] cut to its end.
pub(crate) fn quote(printed: &Printed) -> String {
    let mut lines = Vec::new();
    for stream in [&printed.stderr, &printed.stdout] {
        let text = String::from_utf8_lossy(&stream.bytes);
        let all: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
        let from = all.len().saturating_sub(QUOTED_LINES);
        if stream.cut() || from > 0 {
            lines.push(format!("    [… {} bytes in all; the last lines:]", stream.total));
        }
        lines.extend(all[from..].iter().map(|l| format!("    {}", shown(l))));
    }
    if lines.is_empty() {
        "    (it printed nothing)".to_string()
    } else {
        lines.join("\n")
    }
}

/// `line` for a terminal: control characters escaped, at most [`QUOTED_WIDTH`]
/// characters (its end).
fn shown(line: &str) -> String {
    let escaped: String = line
        .chars()
        .flat_map(|c| {
            let e: Vec<char> =
                if c.is_control() && c != '\t' { c.escape_default().collect() } else { vec![c] };
            e
        })
        .collect();
    let n = escaped.chars().count();
    if n <= QUOTED_WIDTH {
        return escaped;
    }
    let tail: String = escaped.chars().skip(n - QUOTED_WIDTH).collect();
    format!("…{tail}")
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
