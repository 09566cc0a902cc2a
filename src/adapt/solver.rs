//! A solver in the adaptation loop (`adapt --solver 'COMMAND {mesh} {solution}'`): before
//! each mesh is sized, it is written to `{mesh}`, the command runs (through `sh -c`, in
//! the current directory), and the scalar field it wrote to `{solution}` (a mesh file on the same vertices; the
//! extension names its format) is attached to the mesh. The mesh is then sized with the
//! recipe followed by a SOLUTION_HESSIAN step of that field (of those fields, normalised
//! together and intersected in order, when several are named), so the solution's metric
//! is intersected into the recipe's field, as in `size --field`.
//!
//! The vertex count asked of the solution's metric follows a schedule, as pyrefine's:
//! `start · growth^k` at iteration k, up to `target`, so that early iterations, on
//! meshes the solution has not shaped yet, stay cheap. An error target is used as it is.
//!
//! The paths never enter the script: the command's text is the user's, in which each
//! placeholder becomes a reference to an environment variable that holds its path
//! (`SMARTMESH_MESH`, `SMARTMESH_SOLUTION`), quoted for where it stands (`"${…}"` outside
//! quotes, `${…}` inside double quotes, `'"${…}"'` inside single quotes), both in one pass
//! over the user's text ([`script`]). The shell expands a variable once and never reads
//! its value as code, so no character of a path (`$( )`, quotes, `;`, a newline, a
//! `{solution}` inside the other path) is run.
//!
//! The command runs as every external program does (`crate::child`): in a process group
//! of its own that dies with smartmesh, the last bytes of its output kept (a solver that
//! prints gigabytes costs a bounded buffer), stopped on Ctrl-C ([`SolverError::Interrupted`]).
//!
//! Files: `mesh-K.EXT` and `solution-K.EXT` in the loop's directory, kept after the run
//! (the last ones show what the solver saw). A failing command is quoted (the end of its
//! stderr and stdout); a missing solution file, one on other vertices, a field that is
//! absent, not scalar or not finite are errors naming the file: the loop stops there and
//! keeps its best mesh.

use std::path::{Path, PathBuf};
use std::time::Instant;

use smartmesh_formats::{write_path, Format, TaggedMesh, WriteOptions};

use crate::adapters::tool::{finish, quote, Stopped};
use crate::child::Run;
use crate::metric::SizeBounds;
use crate::sizing::plan::Step;
use crate::solution::input::{attach, field_names, read_solution, FieldError};
use crate::solution::{Method, Target};

/// The vertex count asked at each iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Schedule {
    /// At iteration 0.
    pub start: f64,
    /// Factor per iteration (≥ 1).
    pub growth: f64,
    /// The largest.
    pub target: f64,
}

impl Schedule {
    /// The vertex count asked at iteration `k`.
    pub fn at(&self, k: usize) -> f64 {
        (self.start * self.growth.powi(k.min(1000) as i32)).min(self.target)
    }
}

/// What the solution's metric is normalised to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Goal {
    /// A vertex count per iteration.
    Vertices(Schedule),
    /// An Lp error.
    Error(f64),
}

/// The solver and how its solution becomes a metric.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverLoop {
    /// The command, with `{mesh}` and `{solution}`.
    pub command: String,
    /// Where the meshes and solutions go.
    pub dir: PathBuf,
    /// The extension of the mesh file (its format).
    pub mesh_extension: String,
    /// The extension of the solution file (its format).
    pub solution_extension: String,
    /// The fields, normalised together and intersected in this order; when empty, the
    /// solution file's only scalar point array.
    pub fields: Vec<String>,
    /// The normalisation.
    pub goal: Goal,
    /// The norm.
    pub p: f64,
    /// The Hessian recovery.
    pub method: Method,
    /// h_min, h_max, aspect ratio of the solution's metric.
    pub bounds: SizeBounds,
}

/// Why the solver gave no usable solution.
#[derive(Debug, thiserror::Error)]
pub enum SolverError {
    /// The mesh could not be written for it.
    #[error("writing the mesh for the solver: {0}")]
    Write(smartmesh_formats::Error),
    /// The command could not be started.
    #[error("starting the solver `{command}`: {source}")]
    Start {
        /// The command run.
        command: String,
        /// Why.
        source: std::io::Error,
    },
    /// The command failed.
    #[error("the solver `{command}` failed ({status}):\n{output}")]
    Failed {
        /// The command run.
        command: String,
        /// Its exit status in words.
        status: String,
        /// The end of its stderr and stdout.
        output: String,
    },
    /// smartmesh was interrupted while the solver ran: its process group was stopped.
    #[error("the solver `{command}` was stopped: smartmesh was interrupted")]
    Interrupted {
        /// The command run.
        command: String,
    },
    /// It exited with 0 but wrote no solution.
    #[error("the solver `{command}` exited with 0 but wrote no {path}")]
    Missing {
        /// The command run.
        command: String,
        /// The solution file expected.
        path: String,
    },
    /// The solution file could not be read.
    #[error("reading the solver's solution: {0}")]
    Read(smartmesh_formats::Error),
    /// The field is missing, on other vertices, not scalar or not finite.
    #[error("{0}")]
    Field(#[from] FieldError),
}

impl SolverError {
    /// Whether the user's input is at fault (a field the solution does not hold, a
    /// solver directory that cannot be written) rather than the solver's run.
    pub fn is_input(&self) -> bool {
        matches!(self, SolverError::Write(_) | SolverError::Field(_))
    }
}

/// The environment variable holding the path of the mesh the solver reads.
pub const MESH_VARIABLE: &str = "SMARTMESH_MESH";
/// The environment variable holding the path of the solution the solver writes.
pub const SOLUTION_VARIABLE: &str = "SMARTMESH_SOLUTION";

/// The shell script run for `command`: each `{mesh}` and `{solution}` replaced, in one
/// pass, by a reference to [`MESH_VARIABLE`] or [`SOLUTION_VARIABLE`] quoted for the
/// place it stands in (outside quotes, inside double quotes, inside single quotes, as a
/// shell reads the text: a backslash escapes the next character outside single quotes).
/// The script holds the user's text and these references, nothing else.
pub fn script(command: &str) -> String {
    #[derive(Clone, Copy, PartialEq)]
    enum Quote {
        None,
        Single,
        Double,
    }
    let mut out = String::with_capacity(command.len() + 64);
    let mut state = Quote::None;
    let mut rest = command;
    while let Some(c) = rest.chars().next() {
        let placeholder = [("{mesh}", MESH_VARIABLE), ("{solution}", SOLUTION_VARIABLE)]
            .into_iter()
            .find(|(p, _)| rest.starts_with(p));
        if let Some((p, var)) = placeholder {
            match state {
                Quote::None => out.push_str(&format!("\"${{{var}}}\"")),
                Quote::Double => out.push_str(&format!("${{{var}}}")),
                Quote::Single => out.push_str(&format!("'\"${{{var}}}\"'")),
            }
            rest = &rest[p.len()..];
            continue;
        }
        out.push(c);
        rest = &rest[c.len_utf8()..];
        match (state, c) {
            (Quote::None, '\'') => state = Quote::Single,
            (Quote::Single, '\'') => state = Quote::None,
            (Quote::None, '"') => state = Quote::Double,
            (Quote::Double, '"') => state = Quote::None,
            // The escaped character is copied as it is, whatever it is.
            (Quote::None | Quote::Double, '\\') => {
                if let Some(next) = rest.chars().next() {
                    out.push(next);
                    rest = &rest[next.len_utf8()..];
                }
            }
            _ => {}
        }
    }
    out
}

/// `path` as a program's argument: a relative path that starts with `-` gets `./`, so
/// that it is not taken for an option.
fn argument(path: &Path) -> PathBuf {
    if path.is_relative() && path.as_os_str().as_encoded_bytes().first() == Some(&b'-') {
        Path::new(".").join(path)
    } else {
        path.to_path_buf()
    }
}

/// What the solver did at one iteration, for the history.
#[derive(Debug, Clone, PartialEq)]
pub struct Solved {
    /// Its wall-clock seconds.
    pub seconds: f64,
    /// The fields taken, in order.
    pub fields: Vec<String>,
    /// The vertex count asked of the solution's metric (`None` for an error target).
    pub complexity_asked: Option<f64>,
}

/// `s` quoted for `sh`, as messages show a path in the command (never run).
fn shell_quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

impl SolverLoop {
    /// The command of iteration `k` and its two files.
    fn files(&self, k: usize) -> (PathBuf, PathBuf) {
        (
            self.dir.join(format!("mesh-{k}.{}", self.mesh_extension)),
            self.dir.join(format!("solution-{k}.{}", self.solution_extension)),
        )
    }

    /// Runs the solver on `mesh` (iteration `k`) and attaches its field to `mesh`.
    pub fn solve(&self, k: usize, mesh: &mut TaggedMesh) -> Result<Solved, SolverError> {
        std::fs::create_dir_all(&self.dir).map_err(|e| {
            SolverError::Write(smartmesh_formats::Error::from(e).with_path(&self.dir))
        })?;
        let (mesh_path, solution_path) = self.files(k);
        // A stale solution of an earlier run must not pass for this one's.
        let _ = std::fs::remove_file(&solution_path);
        // The solver sees the mesh alone: no metric or field of an earlier iteration.
        let mut plain = mesh.clone();
        plain.point_data.clear();
        write_path(&mesh_path, &plain, None, &WriteOptions::default())
            .map_err(SolverError::Write)?;
        let (mesh_arg, solution_arg) = (argument(&mesh_path), argument(&solution_path));
        // For messages only: the command as it reads with the paths in place.
        let command = self
            .command
            .replace("{mesh}", "\u{0}")
            .replace("{solution}", &shell_quote(&solution_arg.display().to_string()))
            .replace('\u{0}', &shell_quote(&mesh_arg.display().to_string()));
        let Some(sh) = crate::child::locate("sh") else {
            return Err(SolverError::Start {
                command,
                source: std::io::Error::new(std::io::ErrorKind::NotFound, "no `sh` on PATH"),
            });
        };
        let run = Run::new(sh)
            .args(["-c".into(), script(&self.command)])
            .env(MESH_VARIABLE, &mesh_arg)
            .env(SOLUTION_VARIABLE, &solution_arg);
        let t = Instant::now();
        let ended = finish(run);
        let seconds = t.elapsed().as_secs_f64();
        match ended {
            Ok(_) => {}
            Err(Stopped::Start(source)) => return Err(SolverError::Start { command, source }),
            Err(Stopped::Interrupted) => return Err(SolverError::Interrupted { command }),
            Err(Stopped::Failed(status, printed)) => {
                return Err(SolverError::Failed { command, status, output: quote(&printed) })
            }
        }
        if !solution_path.is_file() {
            return Err(SolverError::Missing {
                command,
                path: solution_path.display().to_string(),
            });
        }
        let other = read_solution(&solution_path, mesh).map_err(SolverError::Read)?;
        let fields = field_names(&other, &solution_path, &self.fields)?;
        for name in &fields {
            attach(mesh, &mesh_path, &other, &solution_path, name)?;
        }
        let complexity_asked = match self.goal {
            Goal::Vertices(s) => Some(s.at(k)),
            Goal::Error(_) => None,
        };
        Ok(Solved { seconds, fields, complexity_asked })
    }

    /// The sizing step of fields `names` at iteration `k`.
    pub fn step(&self, k: usize, names: &[String]) -> Step {
        let target = match self.goal {
            Goal::Vertices(s) => Target::Vertices(s.at(k)),
            Goal::Error(e) => Target::Error(e),
        };
        Step::solution_hessian(names, target, self.p, self.method, &self.bounds)
    }
}

/// Whether `ext` names a format smartmesh reads (for the solution file; a Medit `.sol`
/// or `.solb` alone too, in the mesh's vertex order).
pub fn readable_extension(ext: &str) -> bool {
    matches!(ext.to_ascii_lowercase().as_str(), "sol" | "solb")
        || Format::from_extension(ext).is_some_and(|f| f.can_read())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schedule_grows_to_its_target() {
        let s = Schedule { start: 500.0, growth: 2.0, target: 3000.0 };
        let v: Vec<f64> = (0..5).map(|k| s.at(k)).collect();
        assert_eq!(v, [500.0, 1000.0, 2000.0, 3000.0, 3000.0]);
        assert_eq!(s.at(usize::MAX), 3000.0);
    }

    #[test]
    fn placeholders_become_variables_quoted_for_where_they_stand() {
        assert_eq!(
            script(r#"run {mesh} "x {solution}" 'y {mesh}' \{mesh} "\"{mesh}""#),
            r#"run "${SMARTMESH_MESH}" "x ${SMARTMESH_SOLUTION}" 'y '"${SMARTMESH_MESH}"'' \{mesh} "\"${SMARTMESH_MESH}""#
        );
        // A placeholder inside a path is not the script's: it never reaches `script`.
        assert_eq!(script("a{solution}b"), r#"a"${SMARTMESH_SOLUTION}"b"#);
    }

    #[cfg(unix)]
    #[test]
    fn the_shell_gives_the_solver_each_path_as_it_is_in_every_quoting() {
        let nasty = "d {solution}'\"$(touch X)`touch Y`;x & | < > * ? [a] # ~ \\ \t\n{mesh}${HOME}";
        let mesh = format!("{nasty}/mesh-0.vtu");
        let solution = format!("{nasty}/solution-0.vtu");
        let dir = tempfile::tempdir().unwrap();
        let out = std::process::Command::new("/bin/sh")
            .arg("-c")
            .arg(script(r#"printf '%s\0' {mesh} "{solution}" '{mesh}' "a{solution}b""#))
            .env(MESH_VARIABLE, &mesh)
            .env(SOLUTION_VARIABLE, &solution)
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        let args: Vec<&str> =
            std::str::from_utf8(&out.stdout).unwrap().split_terminator('\0').collect();
        assert_eq!(args, [&mesh, &solution, &mesh, &format!("a{solution}b")]);
        assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none(), "a path was run");
    }

    #[test]
    fn a_path_that_looks_like_an_option_is_not_one() {
        assert_eq!(argument(Path::new("-o/mesh-0.vtu")), Path::new("./-o/mesh-0.vtu"));
        assert_eq!(argument(Path::new("/-o/mesh-0.vtu")), Path::new("/-o/mesh-0.vtu"));
        assert_eq!(argument(Path::new("d/mesh-0.vtu")), Path::new("d/mesh-0.vtu"));
    }

    #[test]
    fn paths_are_quoted_for_the_shell() {
        assert_eq!(shell_quote("a b/it's.vtu"), "'a b/it'\\''s.vtu'");
    }
}
