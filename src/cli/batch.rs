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

use std::path::{Path, PathBuf};
use std::process::{Command as Process, Stdio};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use clap::{Args, Parser};
use smartmesh::batch::manifest::{self, ManifestError};
use smartmesh::batch::results::{self, RESULTS};
use smartmesh::batch::{content_hash, ResultRecord, Shard, Status, Variant};
use smartmesh::history::History;

use super::{ui, CliError, ExitStatus};

/// Run the adaptation loop over the variants of a manifest.
#[derive(Debug, Args)]
#[command(after_help = "The manifest has one JSON object per line (blank lines are skipped):
  {\"name\": \"wing-03\", \"input\": \"wing-03.poly\", \"recipe\": \"wing.toml\", \"options\": {\"hmin\": 0.001}}
name names the outputs (letters, digits, . _ -; unique); input and recipe are absolute or \
relative to the manifest's folder; options are adapt's options with underscores (adapter, \
adapter_program, adapter_args [list], max_iterations, tol_vertices, tol_conformity, \
max_vertices, max_growth, hmin, hmax, hgrad, hausd, coarsen_geometry, nosurf, no_preprocess, \
recipe_format, from, binary, gmsh_version, vtk_version, vtu_encoding, no_compress) and format, \
the output's extension (msh unless said). A bad line stops the batch before any run (exit 2, \
naming the file and the line).

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
HyperQueue task of `hq submit --each-line MANIFEST`), only that line runs. Tasks and shards \
may share DIR.

Examples:
  smartmesh batch variants.jsonl -o target/campaign --jobs 2
  smartmesh batch variants.jsonl -o target/campaign --resume
  hq submit --each-line variants.jsonl -- smartmesh batch variants.jsonl -o campaign --resume")]
pub struct BatchArgs {
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

/// Ctrl-C (or SIGTERM, SIGHUP) received: launch nothing more.
static STOP: AtomicBool = AtomicBool::new(false);
/// The variants' processes under way, told to stop on Ctrl-C.
static RUNNING: Mutex<Vec<i32>> = Mutex::new(Vec::new());

fn handle_interrupts() {
    let installed = ctrlc::set_handler(|| {
        if !STOP.swap(true, Ordering::SeqCst) && ui::level() >= ui::Level::Normal {
            eprintln!("\nsmartmesh: batch: stopping the variants under way; no new one starts");
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

fn manifest_error(e: ManifestError) -> CliError {
    CliError::input(e.to_string(), e)
}

/// The variants to run, checked: the manifest's (or its shard's), or `HQ_ENTRY`'s.
fn variants(args: &BatchArgs) -> Result<Vec<Variant>, CliError> {
    let base = match args.manifest.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let text = std::fs::read_to_string(&args.manifest).map_err(|e| {
        CliError::context(format!("reading the manifest {}", args.manifest.display()), e)
    })?;
    let selected = match std::env::var(HQ_ENTRY) {
        Ok(entry) => {
            if args.shard.is_some() {
                return Err(CliError::usage(
                    "--shard and HQ_ENTRY both choose the variants: use one (HQ_ENTRY is set by `hq submit --each-line`)",
                ));
            }
            // The entry's line in the manifest, to name it; the entry itself is what runs.
            let line = text.lines().position(|l| l.trim() == entry.trim()).map_or(0, |i| i + 1);
            let source = match std::env::var("HQ_TASK_ID") {
                Ok(id) => format!("{HQ_ENTRY} (task {id} of {})", args.manifest.display()),
                Err(_) => format!("{HQ_ENTRY} ({})", args.manifest.display()),
            };
            match manifest::parse_line(&entry, line, &base, &source).map_err(manifest_error)? {
                Some(v) => vec![v],
                None => {
                    ui::note(&format!("{HQ_ENTRY} is blank: nothing to run"));
                    Vec::new()
                }
            }
        }
        Err(_) => {
            let all = manifest::parse(&text, &args.manifest).map_err(manifest_error)?;
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
    // The options as `adapt` reads them, before any run.
    for v in &selected {
        let mut argv: Vec<std::ffi::OsString> = vec!["smartmesh".into()];
        argv.extend(v.adapt_args(&args.output));
        if let Err(e) = super::Cli::try_parse_from(&argv) {
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("").trim_start_matches("error: ");
            return Err(CliError::usage(format!(
                "{}:{}: the options of `{}`: {first}",
                args.manifest.display(),
                v.line,
                v.name
            )));
        }
    }
    Ok(selected)
}

/// What a run prints as its error: the `smartmesh: error:` line and the lines after it.
fn error_of(log: &Path) -> Option<String> {
    let text = std::fs::read_to_string(log).ok()?;
    let start = text.find("smartmesh: error: ")?;
    let message = text[start + "smartmesh: error: ".len()..].trim_end();
    Some(message.lines().map(str::trim).collect::<Vec<_>>().join("; "))
}

/// Runs one variant and makes its record.
fn run_one(
    program: &Path,
    dir: &Path,
    v: &Variant,
    hash: String,
    threads: Option<usize>,
) -> Result<ResultRecord, CliError> {
    let history_path = dir.join(v.history_name());
    let log_path = dir.join(v.log_name());
    // A history left by an earlier run must not be taken for this one's.
    match std::fs::remove_file(&history_path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            return Err(CliError::context(format!("removing {}", history_path.display()), e))
        }
        _ => {}
    }
    let log = std::fs::File::create(&log_path)
        .map_err(|e| CliError::context(format!("creating {}", log_path.display()), e))?;
    let mut command = Process::new(program);
    command.args(v.adapt_args(dir)).stdin(Stdio::null()).stdout(Stdio::null()).stderr(log);
    if let Some(t) = threads {
        command.env("RAYON_NUM_THREADS", t.to_string());
    }
    command.env_remove(HQ_ENTRY);
    let t = Instant::now();
    let mut child = command
        .spawn()
        .map_err(|e| CliError::context(format!("starting {}", program.display()), e))?;
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

/// Runs `batch`.
pub fn run(args: BatchArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    let selected = variants(&args)?;
    std::fs::create_dir_all(&args.output).map_err(|e| {
        CliError::context(format!("creating the output directory {}", args.output.display()), e)
    })?;
    let results_path = args.output.join(RESULTS);
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
        let hash = content_hash(&v).map_err(|e| {
            CliError::context(
                format!("{}:{}: variant `{}`", args.manifest.display(), v.line, v.name),
                e,
            )
        })?;
        let done = recorded.get(&v.name).is_some_and(|r| {
            r.status == Status::Ok && r.hash == hash && args.output.join(&r.output).is_file()
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
    let fatal: Mutex<Option<CliError>> = Mutex::new(None);
    let failures = AtomicUsize::new(0);
    std::thread::scope(|scope| {
        for _ in 0..jobs {
            scope.spawn(|| loop {
                if STOP.load(Ordering::SeqCst) || fatal.lock().is_ok_and(|f| f.is_some()) {
                    return;
                }
                let k = next.fetch_add(1, Ordering::SeqCst);
                let Some((v, hash)) = todo.get(k) else { return };
                let outcome =
                    run_one(&program, &args.output, v, hash.clone(), threads).and_then(|r| {
                        let mut all = finished.lock().map_err(|_| CliError::usage("poisoned"))?;
                        results::append(&results_path, &r).map_err(|e| {
                            CliError::context(format!("appending to {}", results_path.display()), e)
                        })?;
                        all.push(r);
                        Ok(all.last().cloned())
                    });
                match outcome {
                    Ok(Some(r)) => {
                        if r.status == Status::Failed {
                            failures.fetch_add(1, Ordering::SeqCst);
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
                    }
                    Ok(None) => {}
                    Err(e) => {
                        if let Ok(mut f) = fatal.lock() {
                            f.get_or_insert(e);
                        }
                        return;
                    }
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
    let ok = finished.iter().filter(|r| r.status == Status::Ok).count();
    let failed: Vec<&ResultRecord> =
        finished.iter().filter(|r| r.status == Status::Failed).collect();
    let total = todo.len() + skipped;
    let not_run = todo.len() - finished.len();
    let mut summary =
        format!("{} of {total} variant{} done", ok + skipped, if total == 1 { "" } else { "s" });
    if skipped > 0 {
        summary.push_str(&format!(" ({skipped} already recorded)"));
    }
    if !failed.is_empty() {
        summary.push_str(&format!(", {} failed", failed.len()));
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
                r.error.as_deref().unwrap_or("failed")
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
