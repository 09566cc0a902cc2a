//! External programs run as children (the C preprocessor of a recipe, a `--solver`, the
//! `mmg2d_O3` and `gmsh` adapters), all one way:
//!
//! - in a process group of their own, so that whatever the program starts (`cpp` runs
//!   `cc1`, a solver script runs Python) is stopped with it, and a Ctrl-C on the terminal
//!   reaches smartmesh alone, which decides what becomes of the child;
//! - on Unix through a small `sh` guard ([`GUARD`]) whose watcher, in the child's group,
//!   kills the group once smartmesh is gone, however it ended (SIGKILL included).
//!   (`PR_SET_PDEATHSIG` would need `unsafe` in `pre_exec`, which the crate forbids, and
//!   would reach the direct child alone.) The program and its arguments are arguments of
//!   the guard, never part of its script: no text of theirs is read by a shell;
//! - with its output read on threads as it comes, each stream kept whole up to a limit
//!   (past it the child is stopped), or only its first or last bytes ([`Keep`]): a
//!   program that prints gigabytes costs a bounded buffer;
//! - stopped when a deadline passes, when its output passes its limit, or when the user
//!   interrupts smartmesh ([`interrupt`], called by the Ctrl-C handler): SIGTERM to the
//!   group, [`GRACE`] to exit, then SIGKILL. The child is always reaped and its group
//!   killed before [`Run::run`] returns.
//!
//! Every running child is registered, with the scratch directory it works in, so that a
//! second Ctrl-C, which exits at once, still kills the groups and removes those
//! directories ([`stop_all`]).

use std::ffi::OsString;
use std::io::{Read, Write as _};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The `sh -c` script a child is started through on Unix (`sh -c GUARD sh PARENT PROGRAM
/// ARGS…`): a watcher in the background, its streams on `/dev/null` so that the child's
/// pipes close when the child is done, polls every 0.2 s that our process (`PARENT`) and
/// the child are alive; when either is gone it kills the whole group (the child, what it
/// started, itself). The script then becomes the program (`exec`), keeping its pid, which
/// leads the group.
pub const GUARD: &str = "parent=$1; shift; \
( while kill -0 \"$parent\" 2>/dev/null && kill -0 $$ 2>/dev/null; do \
sleep 0.2 2>/dev/null || sleep 1; done; kill -KILL 0 ) </dev/null >/dev/null 2>&1 & \
exec \"$@\"";

/// How long an interrupted child has between SIGTERM and SIGKILL.
pub(crate) const GRACE: Duration = Duration::from_secs(2);

/// How long the output of a child that has exited may still take to reach EOF (a
/// grandchild that left the group may hold its pipes open).
const DRAIN: Duration = Duration::from_secs(2);

/// Set by [`interrupt`]: every child running is stopped, and none starts.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The children running: the group each leads, and the scratch directory it works in.
static LIVE: Mutex<Vec<(u32, Option<PathBuf>)>> = Mutex::new(Vec::new());

/// Asks every child running to stop (SIGTERM to its group, SIGKILL after `GRACE`), and
/// every later `Run::run` to start nothing: the user interrupted smartmesh. Safe to
/// call from a signal-handling thread.
pub fn interrupt() {
    INTERRUPTED.store(true, Ordering::SeqCst);
}

/// Whether [`interrupt`] was called.
pub(crate) fn interrupted() -> bool {
    INTERRUPTED.load(Ordering::SeqCst)
}

/// Kills the group of every child running and removes their scratch directories, at once:
/// for a process about to exit without unwinding (a second Ctrl-C).
pub fn stop_all() {
    let live = match LIVE.lock() {
        Ok(l) => l.clone(),
        Err(p) => p.into_inner().clone(),
    };
    for (pid, _) in &live {
        kill_group(*pid, true);
    }
    for (pid, scratch) in &live {
        // The group's members die at the signal's delivery; a write under way may still
        // land, so the removal is tried again once they are gone.
        let t = Instant::now();
        while group_alive(*pid) && t.elapsed() < Duration::from_millis(500) {
            std::thread::sleep(Duration::from_millis(5));
        }
        if let Some(dir) = scratch {
            if std::fs::remove_dir_all(dir).is_err() {
                let _ = std::fs::remove_dir_all(dir);
            }
        }
    }
}

#[cfg(unix)]
fn kill_group(pid: u32, hard: bool) {
    use rustix::process::{kill_process_group, Pid, Signal};
    if let Some(p) = i32::try_from(pid).ok().and_then(Pid::from_raw) {
        let _ = kill_process_group(p, if hard { Signal::KILL } else { Signal::TERM });
    }
}

#[cfg(not(unix))]
fn kill_group(_pid: u32, _hard: bool) {}

#[cfg(unix)]
fn group_alive(pid: u32) -> bool {
    use rustix::process::{test_kill_process_group, Pid};
    i32::try_from(pid)
        .ok()
        .and_then(Pid::from_raw)
        .is_some_and(|p| test_kill_process_group(p).is_ok())
}

#[cfg(not(unix))]
fn group_alive(_pid: u32) -> bool {
    false
}

/// What is kept of an output stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Keep {
    /// All of it, up to this many bytes; past them the child is stopped
    /// ([`Ended::TooLarge`]).
    All(usize),
    /// Its first bytes; the rest is read and dropped.
    Head(usize),
    /// Its last bytes; the rest is read and dropped.
    Tail(usize),
}

/// What was kept of a stream, and how long the stream was.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Captured {
    /// The bytes kept ([`Keep`]).
    pub bytes: Vec<u8>,
    /// The bytes the stream had in all.
    pub total: u64,
}

impl Captured {
    /// Whether bytes were dropped.
    pub(crate) fn cut(&self) -> bool {
        self.total > self.bytes.len() as u64
    }
}

/// How a run ended.
#[derive(Debug)]
pub(crate) enum Ended {
    /// The child exited of itself.
    Exited {
        /// Its status.
        status: ExitStatus,
        /// What was kept of its stdout.
        stdout: Captured,
        /// What was kept of its stderr.
        stderr: Captured,
    },
    /// An output passed its [`Keep::All`] limit; it was killed.
    TooLarge,
    /// The deadline passed; it was killed.
    TimedOut,
    /// [`interrupt`] was called; it was stopped (or never started).
    Interrupted,
}

/// A program to run as a child (see the module documentation).
#[derive(Debug, Clone)]
pub(crate) struct Run {
    program: PathBuf,
    args: Vec<OsString>,
    dir: Option<PathBuf>,
    env: Vec<(OsString, OsString)>,
    stdin: Option<Vec<u8>>,
    stdout: Keep,
    stderr: Keep,
    deadline: Option<Instant>,
    scratch: Option<PathBuf>,
}

/// The bytes a tail or a head keeps by default: enough for the last lines of a message.
pub(crate) const DEFAULT_KEEP: usize = 64 << 10;

impl Run {
    /// `program` (a path; a bare name is looked up on `PATH` by [`locate`] first), with
    /// no argument, stdin empty, the last [`DEFAULT_KEEP`] bytes of each output kept.
    pub(crate) fn new(program: impl Into<PathBuf>) -> Run {
        Run {
            program: program.into(),
            args: Vec::new(),
            dir: None,
            env: Vec::new(),
            stdin: None,
            stdout: Keep::Tail(DEFAULT_KEEP),
            stderr: Keep::Tail(DEFAULT_KEEP),
            deadline: None,
            scratch: None,
        }
    }

    /// Adds arguments.
    pub(crate) fn args<I, S>(mut self, args: I) -> Run
    where
        I: IntoIterator<Item = S>,
        S: Into<OsString>,
    {
        self.args.extend(args.into_iter().map(Into::into));
        self
    }

    /// Runs in `dir`.
    pub(crate) fn current_dir(mut self, dir: &Path) -> Run {
        self.dir = Some(dir.to_path_buf());
        self
    }

    /// Sets an environment variable of the child.
    pub(crate) fn env(mut self, name: impl Into<OsString>, value: impl Into<OsString>) -> Run {
        self.env.push((name.into(), value.into()));
        self
    }

    /// What the child reads on stdin (else nothing: stdin is `/dev/null`).
    pub(crate) fn stdin(mut self, bytes: Vec<u8>) -> Run {
        self.stdin = Some(bytes);
        self
    }

    /// What is kept of stdout and of stderr.
    pub(crate) fn keep(mut self, stdout: Keep, stderr: Keep) -> Run {
        self.stdout = stdout;
        self.stderr = stderr;
        self
    }

    /// When the child is killed if it has not exited.
    pub(crate) fn deadline(mut self, deadline: Instant) -> Run {
        self.deadline = Some(deadline);
        self
    }

    /// A directory the child works in, removed by [`stop_all`] when smartmesh exits at
    /// once (its owner removes it otherwise).
    pub(crate) fn scratch(mut self, dir: &Path) -> Run {
        self.scratch = Some(dir.to_path_buf());
        self
    }

    /// The command that starts the program: through [`GUARD`] in a process group of its
    /// own on Unix.
    fn command(&self) -> Command {
        #[cfg(unix)]
        {
            let mut c = Command::new("/bin/sh");
            c.arg("-c").arg(GUARD).arg("sh").arg(std::process::id().to_string());
            c.arg(&self.program).args(&self.args);
            std::os::unix::process::CommandExt::process_group(&mut c, 0);
            c
        }
        #[cfg(not(unix))]
        {
            let mut c = Command::new(&self.program);
            c.args(&self.args);
            c
        }
    }

    /// Runs the program until it exits, passes its output limit or its deadline, or is
    /// interrupted. An error: it could not be started (a program that does not exist
    /// or cannot be run is [`std::io::ErrorKind::NotFound`]).
    pub(crate) fn run(self) -> std::io::Result<Ended> {
        if !runnable(&self.program) {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotFound,
                format!("{} is not an executable file", self.program.display()),
            ));
        }
        if interrupted() {
            return Ok(Ended::Interrupted);
        }
        let mut c = self.command();
        if let Some(d) = &self.dir {
            c.current_dir(d);
        }
        for (k, v) in &self.env {
            c.env(k, v);
        }
        c.stdin(if self.stdin.is_some() { Stdio::piped() } else { Stdio::null() });
        c.stdout(Stdio::piped()).stderr(Stdio::piped());
        let mut child = c.spawn()?;
        let pid = child.id();
        if let Ok(mut live) = LIVE.lock() {
            live.push((pid, self.scratch.clone()));
        }
        // Write and read on other threads: the child may fill one pipe while we wait on
        // another. Nothing waits for the writer: a child that stops reading ends it.
        if let (Some(bytes), Some(mut stdin)) = (self.stdin, child.stdin.take()) {
            std::thread::spawn(move || stdin.write_all(&bytes));
        }
        let too_large = Arc::new(AtomicBool::new(false));
        let out = child.stdout.take().map(|s| Reader::start(s, self.stdout, too_large.clone()));
        let err = child.stderr.take().map(|s| Reader::start(s, self.stderr, too_large.clone()));
        let ended = supervise(&mut child, pid, self.deadline, &too_large);
        if let Ok(mut live) = LIVE.lock() {
            live.retain(|l| l.0 != pid);
        }
        Ok(match ended? {
            Some(status) => {
                let until = Instant::now() + DRAIN;
                let stdout = out.map(|r| r.finish(until)).unwrap_or_default();
                let stderr = err.map(|r| r.finish(until)).unwrap_or_default();
                if too_large.load(Ordering::SeqCst) {
                    Ended::TooLarge
                } else {
                    Ended::Exited { status, stdout, stderr }
                }
            }
            None if too_large.load(Ordering::SeqCst) => Ended::TooLarge,
            None if interrupted() => Ended::Interrupted,
            None => Ended::TimedOut,
        })
    }
}

/// Waits for the child, stopping it on its deadline, its output limit or an interruption;
/// reaps it and kills its group. `Some(status)`: it exited of itself.
fn supervise(
    child: &mut std::process::Child,
    pid: u32,
    deadline: Option<Instant>,
    too_large: &AtomicBool,
) -> std::io::Result<Option<ExitStatus>> {
    let start = Instant::now();
    let result = loop {
        match child.try_wait() {
            Ok(Some(status)) => break Ok(Some(status)),
            Ok(None) => {}
            Err(e) => break Err(e),
        }
        if too_large.load(Ordering::SeqCst) || deadline.is_some_and(|d| Instant::now() >= d) {
            kill_group(pid, true);
            break Ok(None);
        }
        if interrupted() {
            // A polite stop first: the program may clean up after itself.
            kill_group(pid, false);
            let until = Instant::now() + GRACE;
            while Instant::now() < until && matches!(child.try_wait(), Ok(None)) {
                std::thread::sleep(Duration::from_millis(5));
            }
            kill_group(pid, true);
            break Ok(None);
        }
        // Short runs (cpp takes milliseconds) are seen at once, long ones cost little.
        let pause = if start.elapsed() < Duration::from_millis(100) { 1 } else { 10 };
        std::thread::sleep(Duration::from_millis(pause));
    };
    // Whatever the program started dies with it; then the leader is reaped (it may be
    // dead already, which `kill` and `wait` take calmly).
    kill_group(pid, true);
    let _ = child.kill();
    let _ = child.wait();
    result
}

/// A thread reading one stream, keeping what [`Keep`] says.
struct Reader {
    keep: Keep,
    kept: Arc<Mutex<Captured>>,
    done: std::sync::mpsc::Receiver<()>,
}

impl Reader {
    fn start(
        mut stream: impl Read + Send + 'static,
        keep: Keep,
        too_large: Arc<AtomicBool>,
    ) -> Reader {
        let kept = Arc::new(Mutex::new(Captured::default()));
        let shared = kept.clone();
        let (sender, done) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut buf = vec![0u8; 64 << 10];
            loop {
                let n = match stream.read(&mut buf) {
                    Ok(0) => break,
                    Ok(n) => n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(_) => break,
                };
                let Ok(mut c) = shared.lock() else { break };
                c.total += n as u64;
                let chunk = &buf[..n];
                match keep {
                    Keep::All(limit) => {
                        if c.bytes.len() + n > limit {
                            too_large.store(true, Ordering::SeqCst);
                            break;
                        }
                        c.bytes.extend_from_slice(chunk);
                    }
                    Keep::Head(limit) => {
                        let room = limit.saturating_sub(c.bytes.len()).min(n);
                        c.bytes.extend_from_slice(&chunk[..room]);
                    }
                    Keep::Tail(limit) => {
                        if n >= limit {
                            c.bytes.clear();
                            c.bytes.extend_from_slice(&chunk[n - limit..]);
                        } else {
                            c.bytes.extend_from_slice(chunk);
                            // Trimmed when twice the limit: each byte moves at most once.
                            if c.bytes.len() > 2 * limit {
                                let from = c.bytes.len() - limit;
                                c.bytes.drain(..from);
                            }
                        }
                    }
                }
            }
            let _ = sender.send(());
        });
        Reader { keep, kept, done }
    }

    /// What was kept, once the stream ended or `until` passed.
    fn finish(self, until: Instant) -> Captured {
        let _ = self.done.recv_timeout(until.saturating_duration_since(Instant::now()));
        let mut c = match self.kept.lock() {
            Ok(mut c) => std::mem::take(&mut *c),
            Err(p) => std::mem::take(&mut *p.into_inner()),
        };
        if let Keep::Tail(limit) = self.keep {
            let from = c.bytes.len().saturating_sub(limit);
            c.bytes.drain(..from);
        }
        c.bytes.shrink_to_fit();
        c
    }
}

/// `program` if it is a runnable file, as an absolute path; a bare name is found on
/// `PATH`.
pub(crate) fn locate(program: &str) -> Option<PathBuf> {
    let found = if program.contains('/') || program.contains(std::path::MAIN_SEPARATOR) {
        let p = PathBuf::from(program);
        runnable(&p).then_some(p)
    } else {
        let path = std::env::var_os("PATH").unwrap_or_default();
        std::env::split_paths(&path)
            .filter(|d| !d.as_os_str().is_empty())
            .map(|d| d.join(program))
            .find(|p| runnable(p))
    };
    // Absolute: the child may run in another directory.
    found.and_then(|p| std::path::absolute(p).ok())
}

/// Whether `p` is a file we may execute.
#[cfg(unix)]
pub(crate) fn runnable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

/// Whether `p` is a file we may execute.
#[cfg(not(unix))]
pub fn runnable(p: &Path) -> bool {
    p.is_file() || p.with_extension("exe").is_file()
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    fn sh(script: &str) -> Run {
        Run::new("/bin/sh").args(["-c", script])
    }

    #[test]
    fn a_tail_keeps_the_last_bytes_and_counts_them_all() {
        let ended = sh("seq 1 200000; seq 1 10 >&2").keep(Keep::Tail(10), Keep::Head(4)).run();
        let Ok(Ended::Exited { status, stdout, stderr }) = ended else { panic!("{ended:?}") };
        assert!(status.success());
        let all: String = (1..=200000).map(|i| format!("{i}\n")).collect();
        assert_eq!(stdout.bytes, &all.as_bytes()[all.len() - 10..]);
        assert_eq!(stdout.total, all.len() as u64);
        assert!(stdout.cut());
        assert_eq!(stderr.bytes, b"1\n2\n");
        assert_eq!(stderr.total, 21);
    }

    #[test]
    fn output_past_its_limit_or_a_deadline_stops_the_child() {
        let ended = sh("yes").keep(Keep::All(1 << 20), Keep::Tail(10)).run().unwrap();
        assert!(matches!(ended, Ended::TooLarge), "{ended:?}");
        let t = Instant::now();
        let ended = sh("sleep 30").deadline(Instant::now() + Duration::from_millis(200)).run();
        assert!(matches!(ended, Ok(Ended::TimedOut)), "{ended:?}");
        assert!(t.elapsed() < Duration::from_secs(10));
    }

    #[test]
    fn what_the_child_started_dies_with_it() {
        // The background sleep holds stdout open: without the group killed at the
        // leader's exit, reading would wait for it.
        let dir = tempfile::tempdir().unwrap();
        let pid = dir.path().join("pid");
        let t = Instant::now();
        let script = format!("sleep 30 & echo $! > '{}'; echo done", pid.display());
        let ended = sh(&script).run().unwrap();
        let Ended::Exited { stdout, .. } = ended else { panic!("{ended:?}") };
        assert_eq!(stdout.bytes, b"done\n");
        assert!(t.elapsed() < Duration::from_secs(10), "{:?}", t.elapsed());
        let sleeper: i32 = std::fs::read_to_string(&pid).unwrap().trim().parse().unwrap();
        let p = rustix::process::Pid::from_raw(sleeper).unwrap();
        let t = Instant::now();
        while rustix::process::test_kill_process(p).is_ok() {
            // A zombie until init reaps it; /proc says which.
            let stat = std::fs::read_to_string(format!("/proc/{sleeper}/stat")).unwrap_or_default();
            if stat.rsplit_once(')').map_or(true, |(_, r)| r.trim_start().starts_with('Z')) {
                break;
            }
            assert!(t.elapsed() < Duration::from_secs(5), "the background sleep lives on");
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    #[test]
    fn stdin_is_given_and_a_missing_program_is_not_found() {
        let ended = Run::new("/bin/cat").stdin(b"text".to_vec()).run().unwrap();
        let Ended::Exited { stdout, .. } = ended else { panic!("{ended:?}") };
        assert_eq!(stdout.bytes, b"text");
        let e = Run::new("/nonexistent/program").run().unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::NotFound);
        assert!(locate("sh").is_some_and(|p| p.is_absolute()));
    }
}
