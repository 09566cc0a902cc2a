//! Argument parsing, exit codes and error printing; one file per subcommand.

mod adapt;
mod batch;
mod convert;
mod error;
mod info;
mod info3d;
mod info_metric;
mod layer;
mod mesh;
mod output;
mod recipe;
mod remesh;
mod remesh_space;
mod report;
mod size;
mod solution;
mod spelling;
pub(crate) mod ui;
mod variants;

use std::io::Write;
use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

pub(crate) use error::{CliError, ExitStatus};
pub(crate) use output::{MeshOutputArgs, RecipeInput};

const ABOUT: &str = "Anisotropic metric fields from geometry, and the glue between meshing tools.

Reads and writes Triangle (.node/.ele/.poly/.edge), Gmsh (.msh 2.2 and 4.1, ASCII and \
binary), VTK (.vtk legacy 4.2/5.1, .vtu XML), OBJ, Medit/MMG (.mesh/.meshb with .sol) \
and glTF (.gltf/.glb, write only), keeping topology tags and fields.";

#[derive(Debug, Parser)]
#[command(name = "smartmesh", version, about = ABOUT, propagate_version = true, max_term_width = 100)]
pub(crate) struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Print errors only: no warning, note, progress bar or summary line.
    #[arg(long, short = 'q', global = true, conflicts_with = "verbose")]
    quiet: bool,
    /// Print more: the notes about bookkeeping a format does not keep (Gmsh's entity
    /// table in a .vtu, …).
    #[arg(long, short = 'v', global = true)]
    verbose: bool,
}

#[derive(Debug, Subcommand)]
enum Command {
    Info(info::InfoArgs),
    Convert(convert::ConvertArgs),
    Recipe(recipe::RecipeArgs),
    Size(size::SizeArgs),
    Adapt(Box<adapt::AdaptArgs>),
    Batch(batch::BatchArgs),
    Mesh(mesh::MeshArgs),
    Remesh(remesh::RemeshArgs),
    Report(report::ReportArgs),
    Layer(layer::LayerArgs),
    Variants(variants::VariantsArgs),
}

/// Parses arguments, runs the command, prints errors, maps them to exit codes.
pub(crate) fn main() -> ExitCode {
    let args: Vec<std::ffi::OsString> = std::env::args_os().collect();
    if let Some(message) = spelling::single_dash_option(&Cli::command(), &args) {
        let _ = writeln!(std::io::stderr(), "smartmesh: error: {message}");
        return ExitStatus::Error.into();
    }
    let mut cmd = with_help_usage(Cli::command());
    let parsed = cmd
        .try_get_matches_from_mut(&args)
        .and_then(|m| Cli::from_arg_matches(&m).map_err(|e| e.format(&mut cmd)));
    let cli = match parsed {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return match e.kind() {
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion => {
                    ExitCode::from(0)
                }
                _ => ExitCode::from(2),
            };
        }
    };
    ui::set_level(if cli.quiet {
        ui::Level::Quiet
    } else if cli.verbose {
        ui::Level::Verbose
    } else {
        ui::Level::Normal
    });
    let result = match cli.command {
        Command::Info(a) => info::run(a),
        Command::Convert(a) => convert::run(a),
        Command::Recipe(a) => recipe::run(a),
        Command::Size(a) => size::run(a),
        Command::Adapt(a) => adapt::run(*a),
        Command::Batch(a) => batch::run(a),
        Command::Mesh(a) => mesh::run(a),
        Command::Remesh(a) => remesh::run(a),
        Command::Report(a) => report::run(a),
        Command::Layer(a) => layer::run(a),
        Command::Variants(a) => variants::run(a),
    };
    match result {
        Ok(()) => ExitStatus::Success.into(),
        Err(e) => {
            if e.status != ExitStatus::Success {
                let _ = writeln!(std::io::stderr(), "smartmesh: error: {}", e.render());
            }
            e.status.into()
        }
    }
}

/// Most threads a run starts: starting a thread costs its stack and a few tens of
/// microseconds, and 100 000 of them took over a minute before any work; the largest
/// nodes have a few hundred cores.
pub(crate) const MAX_THREADS: usize = 1024;

/// `cmd` with every subcommand's usage line fixed to the one its help prints
/// (`smartmesh remesh [OPTIONS] <MESH>`). Left to itself, clap's error messages print a
/// usage line built from the arguments given and those it thinks required, so that
/// `remesh m.msh --metric f.sol` answered `Usage: smartmesh remesh --metric <METRIC>
/// --output <OUTPUT> <MESH>`: an optional flag shown as required, and `--output`, which
/// `--measure` makes unneeded, too.
fn with_help_usage(mut cmd: clap::Command) -> clap::Command {
    cmd.build();
    fix_usage(cmd)
}

fn fix_usage(mut cmd: clap::Command) -> clap::Command {
    let names: Vec<String> = cmd.get_subcommands().map(|s| s.get_name().to_string()).collect();
    for name in names {
        cmd = cmd.mut_subcommand(&name, |sub| {
            let usage = sub.clone().render_usage().to_string();
            let usage = usage.trim_start_matches("Usage:").trim().to_string();
            fix_usage(sub).override_usage(usage)
        });
    }
    cmd
}

/// Sets the thread count of the whole run (`--threads`; 0: rayon's default, every core
/// unless `RAYON_NUM_THREADS` says otherwise), at most [`MAX_THREADS`], checked before
/// any thread starts. Outputs do not depend on it.
pub(crate) fn set_threads(threads: usize) -> Result<(), CliError> {
    if threads > MAX_THREADS {
        return Err(CliError::usage(format!(
            "--threads {threads}: at most {MAX_THREADS} (0: one per core)"
        )));
    }
    if threads == 0 {
        let env = std::env::var("RAYON_NUM_THREADS").ok();
        if let Some(n) = env.as_deref().and_then(|v| v.trim().parse::<usize>().ok()) {
            if n > MAX_THREADS {
                return Err(CliError::usage(format!(
                    "RAYON_NUM_THREADS={n}: at most {MAX_THREADS} threads (0: one per core)"
                )));
            }
        }
        return Ok(());
    }
    let mut pool = rayon::ThreadPoolBuilder::new().num_threads(threads);
    if threads == 1 {
        // The main thread is the pool's one worker: no second thread is started, so none
        // spins or yields waiting for work (a pool of one other thread would, after each
        // parallel call, while the main thread does the rest).
        pool = pool.use_current_thread();
    }
    pool.build_global().map_err(|e| CliError::usage(format!("--threads {threads}: {e}")))
}

/// Writes to stdout; a closed pipe (`smartmesh info x | head`) is not an error.
pub(crate) fn print_stdout(text: &str) -> Result<(), CliError> {
    write_stdout(text.as_bytes())
}

/// Writes bytes to stdout; a closed pipe ends the run quietly ([`error::io_status`]).
pub(crate) fn write_stdout(bytes: &[u8]) -> Result<(), CliError> {
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)
        .and_then(|_| out.flush())
        .map_err(|e| CliError::context("writing to stdout", e))
}

/// Reads a mesh (`-` for stdin, with `format`) and prints as notes what the reader
/// could not keep, unless quiet; returns the notes too (for `--json`'s `read_notes`,
/// which `-q` does not silence). `no_solution`: without the `.sol`/`.solb` beside a
/// Medit mesh (`--no-solution`).
pub(crate) fn read_mesh_noted(
    path: &std::path::Path,
    format: Option<smartmesh::formats::Format>,
    no_solution: bool,
) -> Result<(smartmesh::formats::TaggedMesh, Vec<String>), CliError> {
    read_mesh_noted_keeping_bytes(path, format, no_solution).map(|(mesh, notes, _)| (mesh, notes))
}

/// [`read_mesh_noted`], handing back the buffer the file was read into (for the
/// output to reuse: `convert`).
pub(crate) fn read_mesh_noted_keeping_bytes(
    path: &std::path::Path,
    format: Option<smartmesh::formats::Format>,
    no_solution: bool,
) -> Result<(smartmesh::formats::TaggedMesh, Vec<String>, Vec<u8>), CliError> {
    let left_out: &[&str] = if no_solution { &["sol", "solb"] } else { &[] };
    let (mesh, report, bytes) =
        smartmesh::formats::read_path_keeping_bytes(path, format, left_out)?;
    let name = input_name(path);
    for n in &report.notes {
        ui::note(&format!("{name}: {n}"));
    }
    Ok((mesh, report.notes, bytes))
}

/// [`read_mesh_noted`] for a command that computes on linear cells (sizing, remeshing,
/// the skin): second-order cells are made linear, which a note says (printed, and the
/// last of the notes returned).
pub(crate) fn read_linear_mesh_noted(
    path: &std::path::Path,
    format: Option<smartmesh::formats::Format>,
) -> Result<(smartmesh::formats::TaggedMesh, Vec<String>), CliError> {
    let (mut mesh, mut notes) = read_mesh_noted(path, format, false)?;
    notes.extend(linearise(&mut mesh, path));
    Ok((mesh, notes))
}

/// [`read_linear_mesh_noted`] for the commands that compute in the plane: a mesh that
/// does not lie in one plane z = const is bad input (2), named with the file
/// ([`smartmesh::plane`]).
/// Returns the mesh and the z of its plane, where the command writes its output.
pub(crate) fn read_planar_mesh(
    path: &std::path::Path,
    format: Option<smartmesh::formats::Format>,
) -> Result<(smartmesh::formats::TaggedMesh, f64), CliError> {
    read_planar_mesh_noted(path, format).map(|(mesh, z, _)| (mesh, z))
}

/// [`read_planar_mesh`], with the notes it printed.
pub(crate) fn read_planar_mesh_noted(
    path: &std::path::Path,
    format: Option<smartmesh::formats::Format>,
) -> Result<(smartmesh::formats::TaggedMesh, f64, Vec<String>), CliError> {
    let (mesh, notes) = read_linear_mesh_noted(path, format)?;
    let z = smartmesh::plane(&mesh).map_err(|e| {
        let name = input_name(path);
        CliError::usage(format!("{name}: {e}"))
    })?;
    Ok((mesh, z, notes))
}

/// Makes the second-order cells of `mesh`, read from `path`, linear, saying so; returns
/// the note when there was something to make linear.
pub(crate) fn linearise(
    mesh: &mut smartmesh::formats::TaggedMesh,
    path: &std::path::Path,
) -> Option<String> {
    let n = mesh.linearise()?;
    let name = input_name(path);
    ui::note(&format!("{name}: {n}"));
    Some(n)
}

/// Parses a `--from`/`--to` format name.
pub(crate) fn parse_format(name: &str) -> Result<smartmesh::formats::Format, String> {
    smartmesh::formats::Format::from_name(name).ok_or_else(|| {
        format!("unknown format `{name}`; known: {}", smartmesh::formats::Format::NAMES)
    })
}

/// How messages name an input: its path, or `<stdin>` for `-`.
fn input_name(path: &std::path::Path) -> String {
    if path.as_os_str() == "-" {
        "<stdin>".into()
    } else {
        path.display().to_string()
    }
}

/// The periodic sides of `mesh` (read from `input`) snapped and measured, as `adapt` and
/// `layer` keep them: a note per pair whose slave vertices moved, bad input (2) when a
/// pair's sides are not images of each other, a warning per pair that does not match.
pub(crate) fn periodic_sides(
    mesh: &mut smartmesh::formats::TaggedMesh,
    pairs: &[smartmesh::periodic::PeriodicPair],
    input: &std::path::Path,
) -> Result<smartmesh::periodic::Sides, CliError> {
    let snapped = smartmesh::periodic::Sides::snap(mesh, pairs);
    for (pair, d) in snapped.pairs.iter().zip(&snapped.moved) {
        if *d > 0.0 {
            ui::note(&format!(
                "periodic {}: slave vertices moved by at most {d:.3e} onto the master's images",
                pair.label()
            ));
        }
    }
    let sides = snapped
        .check(mesh)
        .map_err(|e| CliError::usage(format!("{e} (input {})", input.display())))?;
    for m in sides.unmatched() {
        ui::warn(&format!(
            "{m}: the input's sides do not match vertex to vertex; they are kept as they are"
        ));
    }
    Ok(sides)
}
