//! `smartmesh batch MANIFEST -o DIR`: the adaptation loop over many variants, each run as
//! `smartmesh adapt` in a child process of this same executable (so that a variant that
//! fails, even by a crash, never stops the others, and its memory goes back at its end).
//!
//! Every variant writes `DIR/NAME.EXT`, `DIR/NAME.history.json` and its messages in
//! `DIR/NAME.log`; its result record is appended to `DIR/results.jsonl` as it finishes.
//! The meshes and histories depend on the variant alone, not on the order, `--jobs`,
//! `--shard` or the engine that ran it; the records are in the order the variants
//! finished (each names its manifest line). Which variants run: all of the manifest, or
//! those of `--shard i/N`, or the one line in `HQ_ENTRY` (a HyperQueue task of
//! `hq submit --each-line MANIFEST`); `--resume` skips those recorded as done with the
//! same content hash and their output still there.
//!
//! Many batches (shards, tasks, two users' runs) on many hosts may share DIR. Each
//! variant has one owner at a time: the process holding the `flock` of `DIR/.NAME.lock`
//! ([`VariantLock`]); a batch that finds it held leaves the variant to its owner, and one
//! that finds a record of it appended since it started leaves it too. The lock's open
//! file is the variant's `adapt` process's stdin, so the lock lasts as long as that
//! process, even past this one's death; and that process dies with this one (it runs in
//! a process group of its own under the guard `cpp` runs under,
//! [`smartmesh::batch::GUARD`]). Lock files are never removed (removing one
//! would let two processes hold "the" lock of a name).
//!
//! Before any run: the manifest is a regular file of at most [`MAX_MANIFEST_BYTES`], the
//! options of every variant parse as `adapt`'s, no file a variant may write is a file
//! the batch reads (an input, a recipe, the manifest), and `results.jsonl` can be
//! opened for appending. What concerns one variant alone (a missing input, a log that
//! cannot be created, a process that cannot start) is that variant's `failed` record.

use std::collections::{HashMap, HashSet};
use std::io::{Read, Seek};
use std::path::{Path, PathBuf};
use std::process::{Command as Process, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use std::any::TypeId;

use clap::{ArgAction, Args, Parser};
use smartmesh::batch::manifest::{self, shown, AdaptOption, ManifestError, OptionKind};
use smartmesh::batch::results::{self, RESULTS};
use smartmesh::batch::{content_hash, ResultRecord, Shard, Status, Variant};
use smartmesh::History;

use super::adapt::AdaptArgs;
use super::{ui, CliError, ExitStatus};

/// Run the adaptation loop over the variants of a manifest.
#[derive(Debug, Args)]
#[command(after_help = "The manifest has one JSON object per line (blank lines are skipped):
  {\"name\": \"wing-03\", \"input\": \"wing-03.poly\", \"recipe\": \"wing.toml\", \"options\": {\"hmin\": 0.001}}
name names the outputs (letters, digits, . _ -; unique); input and recipe are absolute or \
relative to the manifest's folder (a missing one makes that variant's record failed; the \
others run); options are adapt's options with underscores (adapter, \
adapter_program, adapter_args [list], max_iterations, tol_vertices, tol_conformity, \
max_vertices, max_growth, hmin, hmax, hgrad, hausd, coarsen_geometry, nosurf, no_preprocess, \
recipe_format, from, binary, gmsh_version, vtk_version, vtu_encoding, no_compress, extrude, wedge, patch_type [list], cyclic [list]) and format, \
the output's extension (msh unless said; su2, or foam for an OpenFOAM case directory). A bad line stops the batch before any run (exit 2, \
naming the file and the line), and so does an output of a variant that would replace a file \
the batch reads (an input, a recipe, the manifest).

Each variant runs `smartmesh adapt` and writes DIR/NAME.EXT, DIR/NAME.history.json and \
DIR/NAME.log (its messages). As each finishes, one JSON line is appended to DIR/results.jsonl: \
name, line, status (ok, failed, interrupted), converged, iterations, vertices, triangles, \
conformity, mean_quality, min_quality, seconds, output, history, log (relative to DIR), error, \
hash. A failing variant does not stop the others; the exit status is then 1, with a summary. \
The file is only appended to: the last record of a name is its result.

--resume skips every variant whose last record is ok, with the same content hash (the bytes \
of its input and recipe, its options, this version of smartmesh) and its output still in DIR; \
the others run again.

Distributed: --shard i/N runs the variants at positions i, i+N, i+2N … (a Slurm array task: \
--shard $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT). With HQ_ENTRY in the environment (a \
HyperQueue task of `hq submit --each-line MANIFEST`), only that line runs. Tasks, shards and \
batches on several hosts may share DIR: a variant has one owner at a time (the lock \
DIR/.NAME.lock); a batch leaves to its owner a variant locked or recorded since it started.

Examples:
  smartmesh batch variants.jsonl -o target/campaign --jobs 2
  smartmesh batch variants.jsonl -o target/campaign --resume
  hq submit --each-line variants.jsonl -- smartmesh batch variants.jsonl -o campaign --resume")]
pub(super) struct BatchArgs {
    /// The manifest (JSON lines, one variant per line).
    manifest: PathBuf,
    /// The output directory (created if missing).
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// Skip the variants already done with the same content hash.
    #[arg(long)]
    resume: bool,
    /// Variants run at once (0: one per core). With more than one, each run's own threads
    /// are shared out (RAYON_NUM_THREADS, unless set).
    #[arg(long, short = 'j', default_value_t = 1)]
    jobs: usize,
    /// Run only shard i of N (i from 0): the variants at positions i, i+N, …
    #[arg(long, value_parser = Shard::parse, value_name = "i/N")]
    shard: Option<Shard>,
}

/// The environment variable of a HyperQueue task of `hq submit --each-line`.
const HQ_ENTRY: &str = "HQ_ENTRY";

/// The largest manifest read, in bytes (about a million variants).
pub(super) const MAX_MANIFEST_BYTES: u64 = 256 << 20;

/// Ctrl-C (or SIGTERM, SIGHUP) received: launch nothing more.
static STOP: AtomicBool = AtomicBool::new(false);
/// The variants' processes under way, told to stop on Ctrl-C.
static RUNNING: Mutex<Vec<i32>> = Mutex::new(Vec::new());

fn handle_interrupts() {
    let installed = ctrlc::set_handler(|| {
        if !STOP.swap(true, Ordering::SeqCst) && ui::level() >= ui::Level::Normal {
            ui::interrupted("batch", "stopping the variants under way; no new one starts");
        }
        #[cfg(unix)]
        if let Ok(running) = RUNNING.lock() {
            for &pid in running.iter() {
                if let Some(pid) = rustix::process::Pid::from_raw(pid) {
                    let _ = rustix::process::kill_process(pid, rustix::process::Signal::TERM);
                }
            }
        }
    });
    if let Err(e) = installed {
        ui::warn(&format!("Ctrl-C will not stop the variants cleanly: {e}"));
    }
}

/// The options a manifest line may set ([`manifest::OPTION_KEYS`]), their flags and
/// kinds read from the definition `adapt` parses ([`AdaptArgs`]): one declaration of the
/// adapt options for the command and for the manifest.
pub(super) fn adapt_options() -> Vec<AdaptOption> {
    let adapt = AdaptArgs::augment_args(clap::Command::new("adapt"));
    manifest::OPTION_KEYS
        .iter()
        .map(|&key| {
            let Some(arg) = adapt.get_arguments().find(|a| a.get_id() == key) else {
                // `format`, the output's extension, is no flag of adapt's.
                return AdaptOption { key, flag: String::new(), kind: OptionKind::Text };
            };
            let kind = match arg.get_action() {
                ArgAction::SetTrue => OptionKind::Switch,
                ArgAction::Append => OptionKind::List,
                _ => {
                    let t = arg.get_value_parser().type_id();
                    if t == TypeId::of::<f64>() {
                        OptionKind::Number
                    } else if t == TypeId::of::<usize>() {
                        OptionKind::Count
                    } else {
                        OptionKind::Text
                    }
                }
            };
            let flag = arg.get_long().map_or_else(String::new, |l| format!("--{l}"));
            AdaptOption { key, flag, kind }
        })
        .collect()
}

fn manifest_error(e: ManifestError) -> CliError {
    CliError::input(e.to_string(), e)
}

/// The manifest's text: a regular file (a device or a pipe is refused before it is
/// opened: opening a pipe blocks) of at most [`MAX_MANIFEST_BYTES`] of UTF-8.
fn read_manifest(path: &Path) -> Result<String, CliError> {
    let context = |e: std::io::Error| {
        CliError::context(format!("reading the manifest {}", path.display()), e)
    };
    let not_regular = || {
        CliError::usage(format!(
            "the manifest {} is not a regular file (a device, a pipe or a directory): expected a file of JSON lines",
            path.display()
        ))
    };
    let too_large = || {
        CliError::usage(format!(
            "the manifest {} is larger than {} MiB: split it (--shard runs part of one)",
            path.display(),
            MAX_MANIFEST_BYTES >> 20
        ))
    };
    if !std::fs::metadata(path).map_err(context)?.is_file() {
        return Err(not_regular());
    }
    let file = std::fs::File::open(path).map_err(context)?;
    let meta = file.metadata().map_err(context)?;
    if !meta.is_file() {
        return Err(not_regular());
    }
    if meta.len() > MAX_MANIFEST_BYTES {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(MAX_MANIFEST_BYTES + 1).read_to_end(&mut bytes).map_err(context)?;
    if bytes.len() as u64 > MAX_MANIFEST_BYTES {
        return Err(too_large());
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        CliError::usage(format!(
            "{}:{line}: not UTF-8 text (byte {at} of the file); expected JSON lines",
            path.display()
        ))
    })
}

/// The variants to run, checked: the manifest's (or its shard's), or `HQ_ENTRY`'s.
fn variants(args: &BatchArgs) -> Result<Vec<Variant>, CliError> {
    let base = match args.manifest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let text = read_manifest(&args.manifest)?;
    let entry = match std::env::var_os(HQ_ENTRY) {
        None => None,
        Some(e) => Some(e.into_string().map_err(|_| {
            CliError::usage(format!(
                "{HQ_ENTRY} holds bytes that are not UTF-8: expected one line of the manifest {} (as `hq submit --each-line` sets it)",
                args.manifest.display()
            ))
        })?),
    };
    let selected = match entry {
        Some(entry) => {
            if args.shard.is_some() {
                return Err(CliError::usage(
                    "--shard and HQ_ENTRY both choose the variants: use one (HQ_ENTRY is set by `hq submit --each-line`)",
                ));
            }
            // The entry's line in the manifest, to name it; the entry itself is what runs.
            let line = text.lines().position(|l| l.trim() == entry.trim()).map_or(0, |i| i + 1);
            let source = match std::env::var("HQ_TASK_ID") {
                Ok(id) => {
                    format!("{HQ_ENTRY} (task {} of {})", shown(&id), args.manifest.display())
                }
                Err(_) => format!("{HQ_ENTRY} ({})", args.manifest.display()),
            };
            match manifest::parse_line(&entry, line, &base, &source, &adapt_options())
                .map_err(manifest_error)?
            {
                Some(v) => vec![v],
                None => {
                    ui::note(&format!("{HQ_ENTRY} is blank: nothing to run"));
                    Vec::new()
                }
            }
        }
        None => {
            let all =
                manifest::parse(&text, &args.manifest, &adapt_options()).map_err(manifest_error)?;
            match args.shard {
                Some(s) => all
                    .into_iter()
                    .enumerate()
                    .filter(|(k, _)| s.holds(*k))
                    .map(|(_, v)| v)
                    .collect(),
                None => all,
            }
        }
    };
    // The options as `adapt` reads them, before any run: once per distinct set of
    // options (paths never change how they parse: see `Variant::adapt_args`), so that a
    // manifest of 10^5 variants builds the parser a handful of times, not 10^5.
    let mut checked: HashSet<(&str, &[String])> = HashSet::new();
    for v in &selected {
        if !checked.insert((v.format.as_str(), v.args.as_slice())) {
            continue;
        }
        let probe =
            Variant { input: PathBuf::from("input"), recipe: PathBuf::from("recipe"), ..v.clone() };
        let mut argv: Vec<std::ffi::OsString> = vec!["smartmesh".into()];
        argv.extend(probe.adapt_args(Path::new("output")));
        if let Err(e) = super::Cli::try_parse_from(&argv) {
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("").trim_start_matches("error: ");
            return Err(CliError::usage(format!(
                "{}:{}: the options of `{}`: {}",
                args.manifest.display(),
                v.line,
                v.name,
                shown(first)
            )));
        }
    }
    Ok(selected)
}

/// Refuses a batch some of whose outputs would replace a file it reads (an input, a
/// recipe, the manifest): `variants --options '{"format":"node"}' -o fam` then `batch
/// fam/manifest.jsonl -o fam` would write each `.poly` over its own geometry. Files are
/// compared as the writer would reach them (links followed) by device and inode.
fn check_outputs_spare_inputs(args: &BatchArgs, selected: &[Variant]) -> Result<(), CliError> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if !args.output.is_dir() {
            return Ok(());
        }
        let id = |p: &Path| std::fs::metadata(p).ok().map(|m| (m.dev(), m.ino()));
        let mut read: HashMap<(u64, u64), String> = HashMap::new();
        if let Some(k) = id(&args.manifest) {
            read.insert(k, "the manifest".to_string());
        }
        for v in selected {
            for (what, p) in [("input", &v.input), ("recipe", &v.recipe)] {
                if let Some(k) = id(p) {
                    read.entry(k).or_insert_with(|| {
                        format!(
                            "the {what} of `{}` (line {}), {}",
                            v.name,
                            v.line,
                            shown(&p.display().to_string())
                        )
                    });
                }
            }
        }
        let shared = [RESULTS.to_string()];
        let owned = |v: &Variant| {
            let mut n = v.output_names();
            n.push(lock_name(v));
            n
        };
        let outputs = selected.iter().flat_map(|v| owned(v).into_iter().map(move |n| (Some(v), n)));
        // One listing of DIR, then a `stat` only of what is there: a batch of 10^5
        // variants on a network file system does not ask for 10^6 missing files.
        let present: HashSet<std::ffi::OsString> = match std::fs::read_dir(&args.output) {
            Ok(entries) => entries.flatten().map(|e| e.file_name()).collect(),
            Err(_) => return Ok(()),
        };
        for (v, name) in shared.iter().map(|n| (None, n.clone())).chain(outputs) {
            if !present.contains(std::ffi::OsStr::new(&name)) {
                continue;
            }
            let path = args.output.join(&name);
            if let Some(what) = id(&path).and_then(|k| read.get(&k)) {
                let writer = match v {
                    Some(v) => format!("`{}` (line {}) writes", v.name, v.line),
                    None => "the batch writes".to_string(),
                };
                return Err(CliError::usage(format!(
                    "{}: {writer} {}, which is {what}: the batch would replace its own inputs; choose another output directory (-o)",
                    args.manifest.display(),
                    path.display()
                )));
            }
        }
    }
    #[cfg(not(unix))]
    let _ = (args, selected);
    Ok(())
}

/// The lock file of a variant in DIR: `.NAME.lock` (no variant's output starts with `.`).
fn lock_name(v: &Variant) -> String {
    format!(".{}.lock", v.name)
}

/// The one owner of a variant: this process holds the `flock` of its lock file.
struct VariantLock {
    file: std::fs::File,
}

/// What trying a variant's lock found.
enum Ownership {
    /// Ours until dropped.
    Owned(VariantLock),
    /// Another process (of any host sharing DIR) holds it.
    Busy,
}

/// Warned once: the file system of DIR takes no locks.
static NO_LOCKS: AtomicBool = AtomicBool::new(false);

/// Takes the lock of `v` in `dir` without waiting.
fn try_lock(dir: &Path, v: &Variant) -> std::io::Result<Ownership> {
    let path = dir.join(lock_name(v));
    let file = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .create(true)
        .truncate(false)
        .open(&path)
        .map_err(|e| std::io::Error::new(e.kind(), format!("opening {}: {e}", path.display())))?;
    #[cfg(unix)]
    {
        use rustix::fs::{flock, FlockOperation};
        match flock(&file, FlockOperation::NonBlockingLockExclusive) {
            Ok(()) => {}
            Err(rustix::io::Errno::WOULDBLOCK) => return Ok(Ownership::Busy),
            Err(e) => {
                if !NO_LOCKS.swap(true, Ordering::SeqCst) {
                    ui::warn(&format!(
                        "{} cannot be locked ({e}): batches sharing this directory may run a variant twice",
                        path.display()
                    ));
                }
            }
        }
    }
    Ok(Ownership::Owned(VariantLock { file }))
}

/// The names recorded in `results.jsonl` since this batch started: a variant recorded
/// meanwhile was run by another batch. Read incrementally (each byte once).
struct RecordedSince {
    /// Where the whole lines read so far end.
    offset: u64,
    names: HashSet<String>,
}

impl RecordedSince {
    fn new(path: &Path) -> RecordedSince {
        let offset = std::fs::metadata(path).map_or(0, |m| m.len());
        RecordedSince { offset, names: HashSet::new() }
    }

    /// Whether `name` was recorded since the start (best effort: unreadable is "no").
    fn has(&mut self, path: &Path, name: &str) -> bool {
        if let Ok(mut f) = std::fs::File::open(path) {
            let mut bytes = Vec::new();
            if f.seek(std::io::SeekFrom::Start(self.offset)).is_ok()
                && f.read_to_end(&mut bytes).is_ok()
            {
                let whole = bytes.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
                let names = &mut self.names;
                results::read_records(&bytes[..whole], 1, |r| {
                    names.insert(r.name);
                });
                self.offset += whole as u64;
            }
        }
        self.names.contains(name)
    }
}

/// What a run prints as its error: the `smartmesh: error:` line and the lines after it.
fn error_of(log: &Path) -> Option<String> {
    let text = std::fs::read_to_string(log).ok()?;
    let start = text.find("smartmesh: error: ")?;
    let message = text[start + "smartmesh: error: ".len()..].trim_end();
    Some(message.lines().map(str::trim).collect::<Vec<_>>().join("; "))
}

/// The record of a variant that did not run: `failed`, saying why.
fn failed_record(v: &Variant, hash: String, why: String) -> ResultRecord {
    ResultRecord {
        name: v.name.clone(),
        line: v.line,
        status: Status::Failed,
        converged: false,
        iterations: 0,
        vertices: None,
        triangles: None,
        conformity: None,
        mean_quality: None,
        min_quality: None,
        seconds: 0.0,
        output: v.output_name(),
        history: v.history_name(),
        log: v.log_name(),
        error: Some(why),
        hash,
    }
}

/// The `adapt` process of a variant: through the guard that kills its process group
/// once this process is gone (Unix), with the variant's lock as its stdin so that the
/// lock lasts as long as it runs.
fn adapt_command(
    program: &Path,
    dir: &Path,
    v: &Variant,
    lock: &VariantLock,
) -> std::io::Result<Process> {
    #[cfg(unix)]
    let mut command = {
        let mut c = Process::new("/bin/sh");
        c.arg("-c")
            .arg(smartmesh::batch::GUARD)
            .arg("sh")
            .arg(std::process::id().to_string())
            .arg(program);
        std::os::unix::process::CommandExt::process_group(&mut c, 0);
        c
    };
    #[cfg(not(unix))]
    let mut command = Process::new(program);
    command.args(v.adapt_args(dir)).stdin(Stdio::from(lock.file.try_clone()?));
    Ok(command)
}

/// Runs one variant and makes its record; what keeps it from running (its log cannot be
/// created, its process cannot start) is its `failed` record.
fn run_one(
    program: &Path,
    dir: &Path,
    v: &Variant,
    hash: String,
    threads: Option<usize>,
    lock: &VariantLock,
) -> Result<ResultRecord, CliError> {
    let history_path = dir.join(v.history_name());
    let log_path = dir.join(v.log_name());
    let failed = |why: String| Ok(failed_record(v, hash.clone(), why));
    // A history left by an earlier run must not be taken for this one's.
    match std::fs::remove_file(&history_path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            return failed(format!("removing {}: {e}", history_path.display()))
        }
        _ => {}
    }
    let log = match std::fs::File::create(&log_path) {
        Ok(l) => l,
        Err(e) => return failed(format!("creating {}: {e}", log_path.display())),
    };
    let mut command = match adapt_command(program, dir, v, lock) {
        Ok(c) => c,
        Err(e) => return failed(format!("preparing its process: {e}")),
    };
    command.stdout(Stdio::null()).stderr(log);
    if let Some(t) = threads {
        command.env("RAYON_NUM_THREADS", t.to_string());
    }
    command.env_remove(HQ_ENTRY);
    let t = Instant::now();
    let mut child = match command.spawn() {
        Ok(c) => c,
        Err(e) => return failed(format!("starting {}: {e}", program.display())),
    };
    let pid = child.id() as i32;
    RUNNING.lock().map_err(|_| CliError::usage("poisoned"))?.push(pid);
    if STOP.load(Ordering::SeqCst) {
        #[cfg(unix)]
        if let Some(p) = rustix::process::Pid::from_raw(pid) {
            let _ = rustix::process::kill_process(p, rustix::process::Signal::TERM);
        }
    }
    let status = child.wait();
    if let Ok(mut running) = RUNNING.lock() {
        running.retain(|&p| p != pid);
    }
    let status =
        status.map_err(|e| CliError::context(format!("waiting for variant {}", v.name), e))?;
    let seconds = t.elapsed().as_secs_f64();
    let history =
        std::fs::read_to_string(&history_path).ok().and_then(|t| History::from_json(&t).ok());
    let best =
        history.as_ref().map(|h| &h.iterations[h.best_iteration.min(h.iterations.len() - 1)]);
    let (status, error) = match status.code() {
        Some(0) => (Status::Ok, None),
        Some(130) => (Status::Interrupted, Some("interrupted".to_string())),
        // Told to stop by this batch's own Ctrl-C (or SIGTERM), before its handler was up.
        None if STOP.load(Ordering::SeqCst) => {
            (Status::Interrupted, Some(format!("interrupted ({status})")))
        }
        code => {
            let why = error_of(&log_path).unwrap_or_else(|| match code {
                Some(c) => format!("exit status {c}, no error message (see {})", v.log_name()),
                None => format!("killed by a signal ({status})"),
            });
            (Status::Failed, Some(why))
        }
    };
    Ok(ResultRecord {
        name: v.name.clone(),
        line: v.line,
        status,
        converged: history.as_ref().is_some_and(|h| h.converged),
        iterations: history.as_ref().map_or(0, |h| h.iterations.len().saturating_sub(1)),
        // The mesh written: with a LAYER skin, the skinned mesh's counts.
        vertices: history.as_ref().and_then(History::written_counts).map(|c| c.0),
        triangles: history.as_ref().and_then(History::written_counts).map(|c| c.1),
        conformity: best.map(|b| b.conforming_share),
        mean_quality: best.map(|b| b.mean_quality),
        min_quality: best.map(|b| b.min_quality),
        seconds,
        output: v.output_name(),
        history: v.history_name(),
        log: v.log_name(),
        error,
        hash,
    })
}

/// What became of one variant taken by a worker.
enum Outcome {
    /// Run (or found unrunnable) here: its record, appended.
    Recorded(Box<ResultRecord>),
    /// Left to another batch: it holds the lock, or recorded the variant meanwhile.
    Elsewhere,
}

/// Runs `batch`.
pub(super) fn run(args: BatchArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    let selected = variants(&args)?;
    check_outputs_spare_inputs(&args, &selected)?;
    std::fs::create_dir_all(&args.output).map_err(|e| {
        CliError::context(format!("creating the output directory {}", args.output.display()), e)
    })?;
    let results_path = args.output.join(RESULTS);
    // Found now, not after the first variant ran.
    results::open(&results_path).map_err(|e| {
        CliError::context(format!("{} cannot be written", results_path.display()), e)
    })?;
    let since = Mutex::new(RecordedSince::new(&results_path));
    let recorded = if args.resume {
        let (recorded, bad) = results::latest(&results_path)
            .map_err(|e| CliError::context(format!("reading {}", results_path.display()), e))?;
        for (line, why) in bad {
            ui::warn(&format!(
                "{}:{line}: not a result record, ignored: {why}",
                results_path.display()
            ));
        }
        recorded
    } else {
        Default::default()
    };
    let mut todo = Vec::new();
    let mut skipped = 0;
    for v in selected {
        // A variant whose files cannot be read is recorded failed, with no hash.
        let hash = v.check_files().and_then(|()| content_hash(&v).map_err(|e| e.to_string()));
        let done = recorded.get(&v.name).is_some_and(|r| {
            r.status == Status::Ok
                && hash.as_ref().is_ok_and(|h| *h == r.hash)
                && args.output.join(&r.output).is_file()
        });
        if done {
            skipped += 1;
        } else {
            todo.push((v, hash));
        }
    }
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let jobs = if args.jobs == 0 { cores } else { args.jobs }.clamp(1, todo.len().max(1));
    let threads = (jobs > 1 && std::env::var_os("RAYON_NUM_THREADS").is_none())
        .then(|| (cores / jobs).max(1));
    let program = std::env::current_exe()
        .map_err(|e| CliError::context("finding smartmesh's own executable", e))?;
    handle_interrupts();

    let bar = ui::progress_bar(
        todo.len() as u64,
        "{bar:30} {pos}/{len} variants {msg} [{elapsed}<{eta}]",
    );
    let next = AtomicUsize::new(0);
    let finished: Mutex<Vec<ResultRecord>> = Mutex::new(Vec::new());
    let elsewhere: Mutex<Vec<String>> = Mutex::new(Vec::new());
    let fatal: Mutex<Option<CliError>> = Mutex::new(None);
    let failures = AtomicUsize::new(0);
    let dir = args.output.as_path();
    let take = |v: &Variant, hash: &Result<String, String>| -> Result<Outcome, CliError> {
        let lock = match try_lock(dir, v) {
            Ok(Ownership::Owned(lock)) => lock,
            Ok(Ownership::Busy) => return Ok(Outcome::Elsewhere),
            Err(e) => {
                let r = failed_record(v, hash.clone().unwrap_or_default(), e.to_string());
                results::append(&results_path, &r).map_err(|e| {
                    CliError::context(format!("appending to {}", results_path.display()), e)
                })?;
                return Ok(Outcome::Recorded(Box::new(r)));
            }
        };
        if since.lock().map_err(|_| CliError::usage("poisoned"))?.has(&results_path, &v.name) {
            return Ok(Outcome::Elsewhere);
        }
        let r = match hash {
            Ok(h) => run_one(&program, dir, v, h.clone(), threads, &lock)?,
            Err(why) => failed_record(v, String::new(), why.clone()),
        };
        // Appended while the lock is held: whoever takes the lock next sees the record.
        results::append(&results_path, &r).map_err(|e| {
            CliError::context(format!("appending to {}", results_path.display()), e)
        })?;
        drop(lock);
        Ok(Outcome::Recorded(Box::new(r)))
    };
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                if STOP.load(Ordering::SeqCst) || fatal.lock().is_ok_and(|f| f.is_some()) {
                    return;
                }
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some((v, hash)) = todo.get(k) else { return };
                match take(v, hash) {
                    Ok(Outcome::Recorded(r)) => {
                        if r.status == Status::Failed {
                            failures.fetch_add(1, Ordering::SeqCst);
                        }
                        if let Ok(mut all) = finished.lock() {
                            all.push(*r);
                        }
                    }
                    Ok(Outcome::Elsewhere) => {
                        if let Ok(mut e) = elsewhere.lock() {
                            e.push(v.name.clone());
                        }
                    }
                    Err(e) => {
                        if let Ok(mut f) = fatal.lock() {
                            f.get_or_insert(e);
                        }
                        return;
                    }
                }
                if let Some(b) = &bar {
                    b.inc(1);
                    let failed = failures.load(Ordering::SeqCst);
                    b.set_message(if failed > 0 {
                        format!("{failed} failed")
                    } else {
                        String::new()
                    });
                }
            });
        }
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    if let Some(e) = fatal.into_inner().ok().flatten() {
        return Err(e);
    }
    let mut finished = finished.into_inner().unwrap_or_default();
    finished.sort_by_key(|r| r.line);
    let mut elsewhere = elsewhere.into_inner().unwrap_or_default();
    elsewhere.sort();
    let ok = finished.iter().filter(|r| r.status == Status::Ok).count();
    let failed: Vec<&ResultRecord> =
        finished.iter().filter(|r| r.status == Status::Failed).collect();
    let total = todo.len() + skipped;
    let not_run = todo.len() - finished.len() - elsewhere.len();
    let mut summary =
        format!("{} of {total} variant{} done", ok + skipped, if total == 1 { "" } else { "s" });
    if skipped > 0 {
        summary.push_str(&format!(" ({skipped} already recorded)"));
    }
    if !failed.is_empty() {
        summary.push_str(&format!(", {} failed", failed.len()));
    }
    if !elsewhere.is_empty() {
        let names: Vec<&str> = elsewhere.iter().take(5).map(String::as_str).collect();
        summary.push_str(&format!(
            ", {} left to another batch sharing {} ({}{}: locked or recorded meanwhile)",
            elsewhere.len(),
            args.output.display(),
            names.join(", "),
            if elsewhere.len() > 5 { ", …" } else { "" }
        ));
    }
    if not_run > 0 || finished.len() > ok + failed.len() {
        summary.push_str(&format!(
            ", {} stopped or not started",
            not_run + finished.len() - ok - failed.len()
        ));
    }
    summary.push_str(&format!(
        "; results in {}; {} with {jobs} job{}",
        results_path.display(),
        ui::seconds(t0.elapsed()),
        if jobs == 1 { "" } else { "s" }
    ));
    if STOP.load(Ordering::SeqCst) {
        return Err(CliError {
            status: ExitStatus::Interrupted,
            message: format!("interrupted: {summary}; `--resume` runs the rest"),
            source: None,
        });
    }
    if !failed.is_empty() {
        let mut message = summary;
        for r in failed.iter().take(20) {
            message.push_str(&format!(
                "\n  {} (line {}): {}",
                r.name,
                r.line,
                shown(r.error.as_deref().unwrap_or("failed"))
            ));
        }
        if failed.len() > 20 {
            message.push_str(&format!(
                "\n  … and {} more (see {})",
                failed.len() - 20,
                results_path.display()
            ));
        }
        return Err(CliError { status: ExitStatus::Failure, message, source: None });
    }
    ui::done("batch", &summary);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table read from `adapt`'s definition is the one the manifest was documented
    /// with (each flag and kind written out here, apart from the code that derives them).
    #[test]
    fn the_manifest_options_are_adapts_own() {
        use OptionKind::*;
        let written = [
            ("adapter", "--adapter", Text),
            ("adapter_program", "--adapter-program", Text),
            ("adapter_args", "--adapter-arg", List),
            ("max_iterations", "--max-iterations", Count),
            ("tol_vertices", "--tol-vertices", Number),
            ("tol_conformity", "--tol-conformity", Number),
            ("max_vertices", "--max-vertices", Count),
            ("max_growth", "--max-growth", Number),
            ("hmin", "--hmin", Number),
            ("hmax", "--hmax", Number),
            ("hgrad", "--hgrad", Number),
            ("hausd", "--hausd", Number),
            ("coarsen_geometry", "--coarsen-geometry", Switch),
            ("nosurf", "--nosurf", Switch),
            ("no_preprocess", "--no-preprocess", Switch),
            ("recipe_format", "--recipe-format", Text),
            ("from", "--from", Text),
            ("format", "", Text),
            ("binary", "--binary", Switch),
            ("gmsh_version", "--gmsh-version", Text),
            ("vtk_version", "--vtk-version", Text),
            ("vtu_encoding", "--vtu-encoding", Text),
            ("no_compress", "--no-compress", Switch),
            ("extrude", "--extrude", Number),
            ("wedge", "--wedge", Number),
            ("patch_type", "--patch-type", List),
            ("cyclic", "--cyclic", List),
        ];
        let table = adapt_options();
        assert_eq!(table.len(), written.len());
        for (o, (key, flag, kind)) in table.iter().zip(written) {
            assert_eq!((o.key, o.flag.as_str(), o.kind), (key, flag, kind));
        }
    }
}
