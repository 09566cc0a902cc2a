//! `smartmesh adapt INPUT --recipe R -o OUT`: the adaptation loop (size → remesh → size …)
//! with a remesher, writing the best mesh and the convergence history.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::{
    run as run_loop, start as starting_point, AdaptError, AdaptOptions, Observer, Phase,
    StartError, Tolerances,
};
use smartmesh::adapters::{adapter, AdapterError, AdapterKind, AdapterOptions};
use smartmesh::formats::{Format, TaggedMesh};
use smartmesh::history::History;
use smartmesh::recipe::Recipe;

use super::{parse_format, print_stdout, CliError, ExitStatus};

/// The remeshers on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum AdapterArg {
    /// smartmesh's own anisotropic remesher.
    Native,
    /// MMG's mmg2d_O3 (on PATH, or --adapter-program).
    Mmg2d,
    /// Gmsh with BAMG (Mesh.Algorithm 7) on a background view.
    Gmsh,
}

impl From<AdapterArg> for AdapterKind {
    fn from(a: AdapterArg) -> AdapterKind {
        match a {
            AdapterArg::Native => AdapterKind::Native,
            AdapterArg::Mmg2d => AdapterKind::Mmg2d,
            AdapterArg::Gmsh => AdapterKind::Gmsh,
        }
    }
}

/// Adapt a mesh to a recipe: size, remesh, size again … until the mesh stops changing.
#[derive(Debug, Args)]
#[command(
    after_help = "Each iteration computes the recipe's field on the current mesh and remeshes to it; the \
next iteration sizes the new mesh with the same recipe (the recipe's regions are found again by \
their tag names, so one recipe serves every geometry variant with the same tags). Iteration 0 \
is the input mesh. The loop stops when both the vertex count (|dV|/V <= --tol-vertices) and the \
share of edges of metric length in [1/sqrt2, sqrt2] (|d share| <= --tol-conformity) are stable \
between two iterations, or after --max-iterations remeshings.

OUT holds the best mesh: the iteration with the highest conforming share, ties to the later one. \
It is rewritten whenever a better mesh comes, so it is there even when a later iteration \
fails (exit status 1) or the run is stopped. The history (per-iteration vertices, triangles, \
conformity, metric quality and seconds per phase) is rewritten after every iteration, as \
OUT's name with .history.json unless --history says where.

Remeshers:
  native   smartmesh's own remesher (the default)
  mmg2d    mmg2d_O3 -in in.mesh -sol in.sol -out out.mesh -v 1 [-hgrad G] [-hausd D] [-nosurf]
           [--adapter-arg ...]; tags go through MMG references, topological points as
           required corners
  gmsh     gmsh with the mesh as a discrete model (CreateTopology; CreateGeometry;) and the
           metric as background view, meshed with BAMG (Mesh.Algorithm 7, the only Gmsh
           algorithm that honours an anisotropic view); --adapter-arg goes on its command line

Examples:
  smartmesh adapt fixtures/cylinder.msh --recipe fixtures/cylinder.toml -o cyl.msh --adapter mmg2d
  smartmesh adapt blade-2.msh --recipe distributor.cfg -o blade-2-adapted.msh --adapter mmg2d --hausd 0.001
  smartmesh adapt square.msh -r wake.toml -o out.vtu --adapter gmsh --max-iterations 4 --json"
)]
pub struct AdaptArgs {
    /// Starting mesh (any readable format with triangles or quadrangles).
    input: PathBuf,
    /// The recipe (.cfg libconfig, .toml, .json), used unchanged at every iteration.
    #[arg(long, short = 'r')]
    recipe: PathBuf,
    /// Output mesh (its extension chooses the format).
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// The remesher.
    #[arg(long, value_enum, default_value = "native")]
    adapter: AdapterArg,
    /// Remeshing iterations at most.
    #[arg(long, default_value_t = AdaptOptions::default().max_iterations)]
    max_iterations: usize,
    /// Converged when the vertex count changes by at most this fraction.
    #[arg(long, default_value_t = Tolerances::default().vertices, value_parser = non_negative)]
    tol_vertices: f64,
    /// Converged when the conforming share changes by at most this much (with --tol-vertices).
    #[arg(long, default_value_t = Tolerances::default().conformity, value_parser = non_negative)]
    tol_conformity: f64,
    /// Where to write the history (default: OUT's name with .history.json).
    #[arg(long)]
    history: Option<PathBuf>,
    /// Most vertices a remeshing may be asked for: before each remeshing the field's
    /// complexity (the vertex count it asks for) is compared with this, and the run stops
    /// with exit status 2 above it (about 0.6 KB of memory per vertex).
    #[arg(long, default_value_t = smartmesh::remesh::DEFAULT_MAX_VERTICES)]
    max_vertices: usize,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    /// The remesher's executable, instead of the one found on PATH.
    #[arg(long)]
    adapter_program: Option<PathBuf>,
    /// native, with a .poly INPUT: let remeshing remove the .poly's own vertices where the
    /// field asks for longer boundary edges. By default they stay vertices of every
    /// remeshing, so that every boundary edge lies on an input segment; with this switch
    /// curved boundaries are followed by chords, and each iteration takes the previous
    /// one's chords as its boundary.
    #[arg(long)]
    coarsen_geometry: bool,
    /// mmg2d: gradation MMG applies to the metric (-hgrad; -1 turns it off).
    #[arg(long, allow_negative_numbers = true)]
    hgrad: Option<f64>,
    /// mmg2d: Hausdorff distance of curved boundaries (-hausd).
    #[arg(long)]
    hausd: Option<f64>,
    /// mmg2d: leave the boundary unchanged (-nosurf).
    #[arg(long)]
    nosurf: bool,
    /// An argument passed to the remesher as it is (repeat for several).
    #[arg(long = "adapter-arg", allow_hyphen_values = true, value_name = "ARG")]
    adapter_args: Vec<String>,
    #[command(flatten)]
    output_format: super::MeshOutputArgs,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
}

fn non_negative(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v >= 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("{v} is not a tolerance (expected a number >= 0)")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

/// The result files, with a progress bar on a terminal.
struct Progress {
    files: ResultFiles,
    bar: Option<ProgressBar>,
    adapter: String,
    /// Records already printed above the bar (the last record comes twice: after its
    /// iteration and when the loop stops).
    printed: usize,
}

impl Observer for Progress {
    fn phase(&mut self, iteration: usize, phase: Phase) {
        if let Some(b) = &self.bar {
            let what = if phase == Phase::Remesh {
                format!("{phase} ({})", self.adapter)
            } else {
                phase.to_string()
            };
            b.set_message(format!("iteration {iteration}: {what}"));
        }
    }

    fn record(
        &mut self,
        history: &History,
        new_best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh::formats::Error> {
        self.files.record(history, new_best)?;
        if let (Some(b), Some(last)) = (
            &self.bar,
            history.iterations.last().filter(|_| history.iterations.len() > self.printed),
        ) {
            self.printed = history.iterations.len();
            b.set_position(last.iteration as u64);
            b.println(format!(
                "iteration {}: {} vertices, {} triangles, {:.1}% conforming, mean quality {:.3}",
                last.iteration,
                last.vertices,
                last.triangles,
                100.0 * last.conforming_share,
                last.mean_quality
            ));
        }
        Ok(())
    }
}

#[derive(serde::Serialize)]
struct AdaptSummary<'a> {
    output: String,
    history_file: String,
    dropped: &'a [String],
    #[serde(flatten)]
    history: &'a History,
}

fn adapter_error(e: AdapterError) -> CliError {
    let status = if matches!(e, AdapterError::Option { .. }) {
        ExitStatus::Error
    } else {
        ExitStatus::Failure
    };
    CliError { status, message: e.to_string() }
}

/// Runs `adapt`.
pub fn run(args: AdaptArgs) -> Result<(), CliError> {
    if args.output.as_os_str() == "-" {
        return Err(CliError::usage("adapt rewrites OUT whenever a better mesh comes: name a file, not stdout (the --json summary goes to stdout)"));
    }
    if Format::from_path(&args.output).is_none() {
        return Err(CliError::usage(format!(
            "{}: no mesh format has this extension (use .msh, .mesh, .vtu, .vtk, .ele, .obj …)",
            args.output.display()
        )));
    }
    let recipe = Recipe::from_path(&args.recipe).map_err(|e| CliError::usage(e.to_string()))?;
    let starting = starting_point(&args.input, args.from).map_err(|e| match e {
        StartError::Read(e) => CliError::from(e),
        StartError::Mesher { ref source, .. } if !source.is_input_error() => {
            CliError { status: ExitStatus::Failure, message: e.to_string() }
        }
        e @ StartError::Mesher { .. } => CliError::usage(e.to_string()),
    })?;
    let options = AdapterOptions {
        program: args.adapter_program.clone(),
        hgrad: args.hgrad,
        hausd: args.hausd,
        nosurf: args.nosurf,
        extra_args: args.adapter_args.clone(),
        keep_points: if args.coarsen_geometry { Vec::new() } else { starting.geometry_points },
        max_vertices: Some(args.max_vertices),
    };
    let start = starting.mesh;
    let remesher = adapter(args.adapter.into(), options).map_err(adapter_error)?;

    let write = args.output_format.write_options();
    let opts = AdaptOptions {
        max_iterations: args.max_iterations,
        tolerances: Tolerances { vertices: args.tol_vertices, conformity: args.tol_conformity },
        max_vertices: Some(args.max_vertices),
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = ProgressBar::new(opts.max_iterations as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:30} {pos}/{len} {msg} [{elapsed}]")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    });
    let mut progress = Progress {
        files: ResultFiles::new(&args.output, args.history.as_deref(), write),
        bar,
        adapter: remesher.name().to_string(),
        printed: 0,
    };
    let input = args.input.display().to_string();
    let recipe_label = args.recipe.display().to_string();
    let result =
        run_loop(start, &recipe, remesher.as_ref(), &opts, &input, &recipe_label, &mut progress);
    if let Some(b) = &progress.bar {
        b.finish_and_clear();
    }
    let outcome = match result {
        Ok(o) => o,
        Err(e @ AdaptError::Start { .. }) => {
            return Err(CliError::usage(format!("{} (input {})", e, args.input.display())))
        }
        Err(e) => return Err(CliError { status: ExitStatus::Failure, message: e.to_string() }),
    };
    for w in &outcome.warnings {
        eprintln!("smartmesh: warning: {w}");
    }
    for d in &progress.files.dropped {
        eprintln!("smartmesh: warning: not written: {d}");
    }
    let h = &outcome.history;
    let best = &h.iterations[h.best_iteration];
    if args.json {
        let s = AdaptSummary {
            output: args.output.display().to_string(),
            history_file: progress.files.history.display().to_string(),
            dropped: &progress.files.dropped,
            history: h,
        };
        let mut text = serde_json::to_string_pretty(&s)
            .map_err(|e| CliError { status: ExitStatus::Failure, message: e.to_string() })?;
        text.push('\n');
        print_stdout(&text)?;
    }
    let kept = format!(
        "{} holds the best mesh, iteration {} ({} vertices, {:.1}% of edges conforming)",
        args.output.display(),
        h.best_iteration,
        best.vertices,
        100.0 * best.conforming_share
    );
    if let Some(e) = outcome.failure {
        // A vertex limit is the user's to raise: bad usage, not a failure of the work.
        let status = if e.is_limit() { ExitStatus::Error } else { ExitStatus::Failure };
        return Err(CliError { status, message: format!("{e}\n{kept}") });
    }
    if !h.converged {
        eprintln!("smartmesh: warning: not converged: {}; {kept}", h.stopped);
    }
    Ok(())
}
