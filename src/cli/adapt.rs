//! `smartmesh adapt INPUT --recipe R -o OUT`: the adaptation loop (size → remesh → size …)
//! with a remesher, writing the best mesh and the convergence history.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::solver::{readable_extension, Goal, Schedule, SolverLoop};
use smartmesh::adapt::{
    run_with_solver as run_loop, start_sized, AdaptOptions, Budget, Outcome, Tolerances,
};
use smartmesh::expected_vertices;
use smartmesh::formats::{Format, TaggedMesh};
use smartmesh::layer::LayerOptions;
use smartmesh::metric::complexity::format_count;
use smartmesh::recipe::size_mesh_with_steps;
use smartmesh::History;
use smartmesh::Topology;
use smartmesh::{adapter, AdapterKind, AdapterOptions};

use super::output::{check_output_dir, is_stdio, positive_size, shown, SizeControls};

#[path = "adapt_progress.rs"]
mod progress;
#[path = "adapt_space.rs"]
mod space;
use super::solution::SolutionArgs;
use super::{parse_format, print_stdout, ui, CliError, ExitStatus, RecipeInput};
use progress::{handle_interrupts, Progress, WRITING};

/// The remeshers on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum AdapterArg {
    /// smartmesh's own anisotropic remesher.
    Native,
    /// MMG's mmg2d_O3 (on PATH, or --adapter-program).
    Mmg2d,
    /// Gmsh on a background view: BAMG (Mesh.Algorithm 7); in space MMG3D inside Gmsh
    /// (Mesh.Algorithm3D 7) for tetrahedra.
    Gmsh,
    /// MMG's mmg3d_O3 (tetrahedral meshes; chosen by itself for a mesh with tetrahedra).
    Mmg3d,
    /// MMG's mmgs_O3 (surfaces in space; chosen by itself for a surface off one plane).
    Mmgs,
}

impl From<AdapterArg> for AdapterKind {
    fn from(a: AdapterArg) -> AdapterKind {
        match a {
            AdapterArg::Native => AdapterKind::Native,
            AdapterArg::Mmg2d => AdapterKind::Mmg2d,
            AdapterArg::Gmsh => AdapterKind::Gmsh,
            AdapterArg::Mmg3d => AdapterKind::Mmg3d,
            AdapterArg::Mmgs => AdapterKind::Mmgs,
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
OUT's name with .history.json unless --history says where; a new best mesh and the history \
naming it are written as one set. With `-o -` (and --to) the best mesh goes to stdout once the \
loop ends, and --history FILE is required.

Ctrl-C (or SIGTERM, SIGHUP) stops the run after the current phase; a solver or remesher \
program under way is stopped at once (SIGTERM to its process group, SIGKILL 2 s later) and \
its iteration discarded: the history says \"stopped\": \"interrupted\", OUT keeps the best \
mesh, and the exit status is 130. A second Ctrl-C stops at once, between two writes, leaving \
the same agreeing files (and killing such a program's group).

--hmin, --hmax and --hgrad replace the recipe's global hmin, hmax and gradation (with mmg2d, \
--hgrad is also MMG's own -hgrad). --hausd bounds the sizes along curved boundaries by their \
curvature: MMG's -hausd for mmg2d, the same rule applied to the metric for native and gmsh; native \
also never coarsens a boundary edge further than it from its curve (by default 0.01 times the \
largest side of the bounding box).

Remeshers:
  native   smartmesh's own remesher (the default)
  mmg2d    mmg2d_O3 -in in.mesh -sol in.sol -out out.mesh -v 1 [-hgrad G] [-hausd D] [-nosurf]
           [--adapter-arg ...]; tags go through MMG references, topological points as
           required corners
  gmsh     gmsh with the mesh as a discrete model (CreateTopology; CreateGeometry;) and the
           metric as background view, meshed with BAMG (Mesh.Algorithm 7, the only Gmsh
           algorithm that honours an anisotropic view); --adapter-arg goes on its command line.
           A mesh in space too: tetrahedra by MMG3D inside Gmsh (Mesh.Algorithm3D 7, its
           only 3D algorithm that honours the view; boundary by BAMG), a surface by BAMG
  mmg3d    mmg3d_O3 -in in.mesh -sol in.sol -out out.mesh -v 1 [-hgrad G] [-hausd D] [-nosurf]
           [--adapter-arg ...]: a mesh in space with tetrahedra (chosen by itself)
  mmgs     mmgs_O3, the same way: a triangulated surface in space (chosen by itself)

A mesh in space (tetrahedra, or triangles off one plane) is sized by the recipe's 3D engine \
and remeshed by mmg3d_O3 or mmgs_O3 (tags, tag names, curves and points through MMG's \
references), or by Gmsh with --adapter gmsh (measured on a Gmsh cube with a wall layer: 49.5% \
of edges in [1/sqrt2, sqrt2] before, 73.8% after one remeshing, 80.4% after three; Gmsh runs \
MMG3D with its own gradation 1.3 and the boundary frozen, so its meshes are finer than the \
field asks; --hausd is refused with it in space); each mesh is measured as the UGAWG does (share of edges of metric length in \
[1/sqrt2, sqrt2], mean ratio of each tetrahedron, or triangle of a surface), the history \
recording them per iteration (\"space\"). The best mesh, the stopping rules, the vertex and \
growth limits (complexity over the tetrahedra; none on a surface), the history and Ctrl-C \
are the planar loop's. --solver and --complexity work on tetrahedra as below (the Hessian \
recovered on the tetrahedra, the complexity taken over them; under a budget MMG's own \
gradation is off unless --hgrad, and each target is corrected by what mmg3d made of the \
last two fields); a surface in space takes neither (no volume cell: its field asks for no \
vertex count, and has no tetrahedra to recover a Hessian on). LAYER, periodic sides, \
--split-quads and --coarsen-geometry are planar only (exit status 2).

Examples:
  smartmesh adapt fixtures/cylinder.msh --recipe fixtures/cylinder.toml -o cyl.msh --adapter mmg2d
  smartmesh adapt blade-2.msh --recipe distributor.cfg -o blade-2-adapted.msh --adapter mmg2d --hausd 0.001
  smartmesh adapt square.msh -r wake.toml -o out.vtu --adapter gmsh --max-iterations 4 --json
  smartmesh adapt square.poly --solver 'python3 solve.py {mesh} {solution}' --field u \\
      --complexity-start 400 --complexity-growth 1.6 --complexity 4000 -o adapted.vtu

With --solver, each mesh is first written to {mesh} (mesh-K.vtu in the solver directory, \
--solver-dir, by default OUT's name with .solver for its extension) and the command runs through `sh -c` in \
the current directory, in a process group of its own that dies with smartmesh; it must write the \
solution on the same vertices to {solution} (solution-K.vtu; --solution-format names another \
readable format). No path is ever part of the shell's text: {mesh} and {solution} become \
\"$SMARTMESH_MESH\" and \"$SMARTMESH_SOLUTION\" (quoted as fits where they stand), which hold \
the paths. Its scalar point field \
(--field, else its only one) gives a metric: the Hessian recovered (--recovery), the \
Lp-optimal metric (--p) normalised to the schedule's vertex count, start * growth^K up to \
--complexity (or to --error), intersected into the recipe's field after its steps. The \
recipe may then be left out, and a .poly INPUT is meshed uniformly to about the \
schedule's first vertex count. A failing solver is quoted (the end of its output; the rest \
is read and dropped) and stops the loop with exit status 1; the best mesh stays. The history records per iteration the solver's seconds and the complexity asked \
and obtained.

Vertex budget: with --complexity N (with or without --solver) the final field on every mesh \
is scaled so that a mesh conforming to it has N vertices (the schedule's value at each \
iteration), corrected by the ratio of vertices made to vertices asked of the previous \
remeshing. The recipe's field is a shape: its sizes, HMIN and HMAX included, scale together; \
--hmin, --hmax, the aspect ratio and the gradation act inside the scaling. With a solver, \
the recipe's field takes at most --recipe-share of the budget (scaled down to it when it asks \
for more) and the solution's metric is scaled to the rest of it. A .poly's vertices stay \
vertices of every mesh unless --coarsen-geometry: when they alone are more than N, the \
budget cannot hold, and a warning says so before the loop. With --solver and \
neither --complexity nor --error, the budget is the recipe's own complexity on the starting \
mesh (the history's \"budget\" says so). --error is a bound each field meets: no budget."
)]
pub(super) struct AdaptArgs {
    /// Starting mesh (any readable format with triangles or quadrangles; tetrahedra, or a
    /// triangulated surface in space), or a .poly.
    input: PathBuf,
    #[command(flatten)]
    recipe: RecipeInput,
    /// Output mesh (its extension chooses the format; `-` for stdout, with --to and
    /// --history).
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
    /// Largest growth of the vertex count in one iteration: where the field asks for more
    /// than this many times the current mesh's vertices (a coarse start), the remesher gets
    /// the field scaled down to that count, and the next iterations refine further (0: no
    /// limit).
    #[arg(long, default_value_t = smartmesh::adapt::DEFAULT_MAX_GROWTH, value_parser = non_negative)]
    max_growth: f64,
    /// Threads for the sizing and for remeshing a large mesh part by part (0: every
    /// core, or RAYON_NUM_THREADS). The output is the same whatever the count.
    #[arg(long, default_value_t = 0)]
    threads: usize,
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
    #[command(flatten)]
    controls: SizeControls,
    #[command(flatten)]
    solution: SolutionArgs,
    /// A solver run on every mesh: a shell command with {mesh} (the mesh it reads) and
    /// {solution} (the file it writes the solution to).
    #[arg(long, value_name = "COMMAND", help_heading = "Solution")]
    solver: Option<String>,
    /// The vertex count asked of the solution's metric at iteration 0 (default: the
    /// target, --complexity); with --error, the vertex count a .poly is first meshed to
    /// (default 1000).
    #[arg(long, value_name = "N", value_parser = positive_size, help_heading = "Solution")]
    complexity_start: Option<f64>,
    /// With a budget and a solver, the largest share of the budget the recipe's field
    /// takes (scaled down to it when it asks for more); the solution's metric has the rest.
    #[arg(long, value_name = "F", default_value_t = smartmesh::adapt::budget::RECIPE_SHARE, value_parser = fraction, help_heading = "Solution")]
    recipe_share: f64,
    /// The factor the vertex count asked grows by at each iteration, up to --complexity.
    #[arg(long, value_name = "F", default_value_t = 1.5, value_parser = growth, help_heading = "Solution")]
    complexity_growth: f64,
    /// The extension (format) of the mesh written for the solver.
    #[arg(long, value_name = "EXT", default_value = "vtu", help_heading = "Solution")]
    solver_mesh_format: String,
    /// The extension (format) of the solution file the solver writes.
    #[arg(long, value_name = "EXT", default_value = "vtu", help_heading = "Solution")]
    solution_format: String,
    /// Where the solver's meshes and solutions go (default: OUT's name with .solver for its
    /// extension).
    #[arg(long, value_name = "DIR", help_heading = "Solution")]
    solver_dir: Option<PathBuf>,
    /// Largest distance between a curved boundary and its edges (MMG's -hausd; for native
    /// and gmsh the same bound applied to the metric).
    #[arg(long, value_parser = positive_size, help_heading = "Size controls")]
    hausd: Option<f64>,
    /// mmg2d: leave the boundary unchanged (-nosurf).
    #[arg(long)]
    nosurf: bool,
    /// An argument passed to the remesher as it is (repeat for several).
    #[arg(long = "adapter-arg", allow_hyphen_values = true, value_name = "ARG")]
    adapter_args: Vec<String>,
    /// Insert the recipe's LAYER skin into the best mesh once the loop has stopped (the
    /// thesis's Layer step); a recipe with a LAYER section does it without this switch,
    /// which then only insists that there is one.
    #[arg(long, conflicts_with = "no_layer")]
    layer: bool,
    /// Do not insert the recipe's LAYER skin.
    #[arg(long)]
    no_layer: bool,
    /// Split the quads of the starting mesh into two triangles each, remeshed like the
    /// rest (without it the native remesher keeps a skin of quads frozen: its cells and
    /// vertices unchanged, the triangles adapted around it; MMG and Gmsh are given the
    /// quads split).
    #[arg(long)]
    split_quads: bool,
    #[command(flatten)]
    output_format: super::MeshOutputArgs,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
}

fn fraction(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v > 0.0 && v <= 1.0 => Ok(v),
        Ok(v) => Err(format!("{v} is not a share (expected a number in (0, 1])")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

fn growth(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v >= 1.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("{v} is not a growth factor (expected a finite number >= 1)")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

/// The vertex schedule of `--complexity N` (from --complexity-start, growing by
/// --complexity-growth).
fn schedule(args: &AdaptArgs, target: f64) -> Schedule {
    Schedule {
        start: args.complexity_start.unwrap_or(target).min(target),
        growth: args.complexity_growth,
        target,
    }
}

/// The vertex budget: `--complexity N`, else with a solver and no `--error` the recipe's
/// own complexity on the starting mesh (`recipe_vertices`); `None` otherwise (an error
/// target is a bound each field meets, not a count).
fn budget(args: &AdaptArgs, recipe_vertices: Option<f64>) -> Option<Budget> {
    match (args.solution.complexity, args.solution.error, recipe_vertices) {
        (Some(n), _, _) => Some(Budget {
            schedule: schedule(args, n),
            from: format!("--complexity {}", ui::sig(n)),
            hard: (args.controls.hmin, args.controls.hmax),
            recipe_share: args.recipe_share,
        }),
        (None, None, Some(n)) => Some(Budget {
            schedule: schedule(args, n),
            from: format!(
                "the recipe's own complexity on the starting mesh ({} vertices): --solver without --complexity",
                format_count(n)
            ),
            hard: (args.controls.hmin, args.controls.hmax),
            recipe_share: args.recipe_share,
        }),
        _ => None,
    }
}

/// Whether `kept` geometry vertices, which every mesh keeps, are more than a budget of
/// `target` vertices allows (more than its tolerance above it).
fn geometry_over_budget(kept: usize, target: f64) -> bool {
    kept as f64 > target * (1.0 + smartmesh::adapt::budget::TOLERANCE)
}

/// The recipe's own complexity on `mesh`: the budget of `--solver` without
/// `--complexity` or `--error`.
fn recipe_vertices(
    args: &AdaptArgs,
    mesh: &TaggedMesh,
    recipe: &smartmesh::Recipe,
) -> Result<Option<f64>, CliError> {
    if !own_budget(args, recipe)? {
        return Ok(None);
    }
    let topology = Topology::from_mesh(mesh);
    let sized = size_mesh_with_steps(mesh, &topology, recipe, &[], &mut |_| {})
        .map_err(|e| CliError::context(format!("{e} (input {})", args.input.display()), e))?;
    let metric: Vec<_> = sized.field.tensors.iter().map(|t| t.to_metric()).collect();
    Ok(Some(expected_vertices(mesh, &metric)))
}

/// Whether the budget is the recipe's own complexity on the starting mesh (`--solver`
/// without `--complexity` or `--error`); an error when the recipe has no step to give it.
fn own_budget(args: &AdaptArgs, recipe: &smartmesh::Recipe) -> Result<bool, CliError> {
    if args.solver.is_none() || args.solution.complexity.is_some() || args.solution.error.is_some()
    {
        return Ok(false);
    }
    if recipe.algorithms.is_empty() {
        return Err(CliError::usage(
            "--solver needs --complexity N (or --error E), or a recipe whose field's complexity is the budget",
        ));
    }
    Ok(true)
}

/// The solver of `--solver`, checked before any work; `recipe_vertices` is the budget
/// when no target is given.
fn solver_loop(
    args: &AdaptArgs,
    mesh: &TaggedMesh,
    recipe: &smartmesh::Recipe,
    recipe_vertices: Option<f64>,
) -> Result<Option<SolverLoop>, CliError> {
    let Some(command) = &args.solver else {
        if !args.solution.field.is_empty() {
            return Err(CliError::usage("--field needs --solver"));
        }
        if args.solution.error.is_some() {
            return Err(CliError::usage(
                "--error needs --solver: an interpolation error is measured on a solution (--complexity N sets a vertex budget for the recipe alone)",
            ));
        }
        if args.complexity_start.is_some() && args.solution.complexity.is_none() {
            return Err(CliError::usage("--complexity-start needs --complexity (or --solver)"));
        }
        return Ok(None);
    };
    for p in ["{mesh}", "{solution}"] {
        if !command.contains(p) {
            return Err(CliError::usage(format!(
                "--solver `{command}` has no {p}: the command must read the mesh from {{mesh}} and write its solution to {{solution}}"
            )));
        }
    }
    let goal = match (args.solution.complexity.or(recipe_vertices), args.solution.error) {
        (Some(target), _) => Goal::Vertices(schedule(args, target)),
        (None, Some(e)) => Goal::Error(e),
        (None, None) => {
            return Err(CliError::usage("--solver needs --complexity N (or --error E)"))
        }
    };
    let mesh_ext = &args.solver_mesh_format;
    if !Format::from_extension(mesh_ext).is_some_and(|f| f.can_read()) {
        return Err(CliError::usage(format!(
            "--solver-mesh-format {mesh_ext}: not a mesh format smartmesh reads and writes ({})",
            Format::known_extensions()
        )));
    }
    let ext = &args.solution_format;
    if !readable_extension(ext) {
        return Err(CliError::usage(format!(
            "--solution-format {ext}: not a format smartmesh reads ({}, or a Medit .sol alone)",
            Format::known_extensions()
        )));
    }
    let dir = match &args.solver_dir {
        Some(d) => d.clone(),
        None if is_stdio(&args.output) => {
            return Err(CliError::usage(
                "with `-o -` and --solver, name the solver's directory with --solver-dir",
            ))
        }
        None => {
            let mut name = args.output.file_stem().unwrap_or_default().to_os_string();
            name.push(".solver");
            args.output.with_file_name(name)
        }
    };
    // Under a budget the recipe's HMIN and HMAX are its field's shape, scaled with it
    // (`adapt::budget`), not bounds of the solution's metric: a solution bounded by the
    // recipe's HMAX would carry a uniform background of it that takes the budget. Only
    // --hmin and --hmax (else the mesh's defaults) bound it then.
    let mut bounding = recipe.clone();
    if let Goal::Vertices(_) = goal {
        bounding.global.h_min = args.controls.hmin;
        bounding.global.h_max = args.controls.hmax;
    }
    Ok(Some(SolverLoop {
        command: command.clone(),
        dir,
        mesh_extension: args.solver_mesh_format.to_ascii_lowercase(),
        solution_extension: args.solution_format.to_ascii_lowercase(),
        fields: args.solution.fields()?,
        goal,
        p: args.solution.p,
        method: args.solution.recovery,
        bounds: args.solution.bounds(mesh, &bounding)?,
    }))
}

fn non_negative(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v >= 0.0 && v.is_finite() => Ok(v),
        Ok(v) => Err(format!("{v} is not a tolerance (expected a number >= 0)")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

#[derive(serde::Serialize)]
struct AdaptSummary<'a> {
    output: String,
    history_file: String,
    dropped: &'a [String],
    /// What the reader could not keep of the input, and the second-order cells made
    /// linear ([`smartmesh::adapt::start::Start::notes`]).
    read_notes: &'a [String],
    #[serde(flatten)]
    history: &'a History,
}

/// The output format, checked with the history's place before any work.
fn check_outputs(args: &AdaptArgs) -> Result<Format, CliError> {
    if is_stdio(&args.output) {
        if args.json {
            return Err(CliError::usage(
                "--json prints on stdout, which `-o -` already uses for the mesh",
            ));
        }
        if args.history.as_deref().map_or(true, is_stdio) {
            return Err(CliError::usage(
                "with `-o -` the history has no file to go beside: name one with --history FILE (not stdout)",
            ));
        }
    }
    // A device or a pipe (`-o /dev/null`) is written in place; the history's default
    // place beside it would be a file in /dev.
    let special = std::fs::metadata(&args.output).is_ok_and(|m| !m.is_file() && !m.is_dir());
    if !is_stdio(&args.output) && special && args.history.is_none() {
        return Err(CliError::usage(format!(
            "{} is not a regular file: the history has no place beside it; name one with --history FILE",
            args.output.display()
        )));
    }
    let format = args.output_format.mesh_format(&args.output)?;
    if format == Format::OpenFoam && (is_stdio(&args.output) || special || args.output.is_file()) {
        return Err(CliError::usage(format!(
            "{}: an OpenFOAM case is a directory of files, which a stream, a device or a file cannot hold: name a directory such as case.foam",
            shown(&args.output)
        )));
    }
    check_output_dir(&args.output)?;
    if let Some(h) = &args.history {
        check_output_dir(h)?;
    }
    Ok(format)
}

/// The LAYER skin asked for: the recipe's LAYER section unless --no-layer (--layer
/// insists on one), its curves checked on the starting mesh.
fn layer_options(
    args: &AdaptArgs,
    recipe: &smartmesh::Recipe,
    mesh: &TaggedMesh,
) -> Result<Option<LayerOptions>, CliError> {
    Ok(match (&recipe.layer, args.layer, args.no_layer) {
        (_, _, true) => None,
        (None, true, _) => {
            return Err(CliError::usage(format!(
                "--layer: the recipe {} has no LAYER section",
                args.recipe.label()
            )))
        }
        (Some(l), _, _) => {
            let o = l.options().map_err(|e| CliError::context(e.to_string(), e))?;
            smartmesh::adapt::skin::check_curves(mesh, &o).map_err(|e| {
                CliError::context(format!("LAYER: {e} (input {})", args.input.display()), e)
            })?;
            Some(o)
        }
        (None, false, _) => None,
    })
}

/// What the loop did after it stopped: the LAYER skin it inserted (placed in the input's
/// plane), and each periodic pair measured on the result; a pair whose match the work
/// broke is bad input (2), nothing more written.
fn say_layer_and_sides(outcome: &mut Outcome, plane_z: f64) -> Result<(), CliError> {
    if let Some(l) = &mut outcome.layer {
        if !l.report.thinned.is_empty() {
            ui::warn(&format!(
                "LAYER: thinned {} of {} columns (smartmesh info shows the layers)",
                l.report.thinned.len(),
                l.report.columns
            ));
        }
        ui::note(&format!(
            "LAYER: {} layers, {} quads, {} skin triangles inserted",
            l.report.layers, l.report.quads, l.report.skin_triangles
        ));
        smartmesh::place(&mut l.mesh, plane_z);
    }
    let skinned = outcome.layer.is_some();
    let checked = outcome
        .periodic
        .as_ref()
        .map_err(|e| CliError::context(format!("{e} (result of the loop)"), e.clone()))?;
    for (k, a) in checked.after.iter().enumerate() {
        if checked.broken == Some(k) {
            return Err(CliError::usage(if skinned {
                format!("{a}: the LAYER skin moved or added vertices on a periodic side (a wall ends on it); the skinned mesh is not written (the loop's best mesh is)")
            } else {
                format!("{a}: the remeshing broke the match of the periodic sides")
            }));
        }
        ui::note(&a.to_string());
    }
    Ok(())
}

/// A starting mesh that could not be had; one in space is told where it can go (the
/// recipe sizes in the plane only).
fn start_error(e: smartmesh::adapt::StartError) -> CliError {
    match &e {
        smartmesh::adapt::StartError::NotPlanar { .. } => CliError::usage(format!(
            "{e}; the loop's sizing is planar today: a mesh in space is remeshed to a 3D metric by `smartmesh remesh MESH --metric M.sol -o OUT` (mmg3d for tetrahedra, --adapter mmgs for a surface)"
        )),
        _ => CliError::from(e),
    }
}

/// The vertex count a `.poly` is meshed to before a solver's first solution when the
/// goal is an error (`--error` without `--complexity-start`): enough for the Hessian's
/// quadratic fits (five neighbours each) to resolve a smooth solution.
const ERROR_START_VERTICES: f64 = 1000.0;

/// Runs `adapt`.
pub(super) fn run(mut args: AdaptArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    let format = check_outputs(&args)?;
    super::set_threads(args.threads)?;
    if is_stdio(&args.input) && args.recipe.is_stdin() {
        return Err(CliError::usage("the mesh and the recipe cannot both come from stdin"));
    }
    let recipe =
        args.controls.over(args.recipe.read_or_empty(args.solver.is_some(), "with --solver")?)?;
    // A solver's first solution needs a mesh that resolves something: a .poly is meshed
    // to about the schedule's first vertex count (with --error, which has no schedule,
    // to --complexity-start or ERROR_START_VERTICES: a bare graph's few vertices leave
    // no patch to recover a Hessian on).
    let first = args.solver.as_ref().and(
        args.complexity_start
            .or(args.solution.complexity)
            .or(args.solution.error.map(|_| ERROR_START_VERTICES)),
    );
    let pairs = recipe.periodic_pairs();
    let mut starting = match start_sized(&args.input, args.from, first, &pairs) {
        // A mesh in space goes to the loop in space (its own reading: tetrahedra, or a
        // surface off one plane).
        Err(smartmesh::adapt::StartError::NotPlanar { .. }) => {
            return space::run(&args, &recipe, format, t0)
        }
        s => s.map_err(start_error)?,
    };
    if let AdapterArg::Mmg3d | AdapterArg::Mmgs = args.adapter {
        return Err(CliError::usage(format!(
            "{}: a planar mesh; --adapter {} remeshes meshes in space (tetrahedra, a surface off one plane): a planar mesh goes to native, mmg2d or gmsh",
            super::input_name(&args.input),
            AdapterKind::from(args.adapter).name()
        )));
    }
    let plane_z = starting.plane_z;
    for n in &starting.notes {
        ui::note(&format!("{}: {n}", args.input.display()));
    }
    let read_notes = starting.notes.clone();
    if args.split_quads {
        let n = starting.mesh.split_quads();
        ui::note(&format!("split {n} quads of the starting mesh into {} triangles", 2 * n));
    }
    if !args.split_quads && args.adapter == AdapterArg::Native {
        // Refused before any work: the loop would fail at its first remeshing and
        // write the input back as its "best" mesh.
        smartmesh::remesh::check_quads(&starting.mesh)
            .map_err(|e| CliError::usage(format!("{}: {e}", args.input.display())))?;
    }
    // The input is checked whole before any tool is looked for: a recipe that names tags
    // the mesh does not have is bad input (2) whether or not the remesher is installed.
    recipe
        .resolve(&Topology::from_mesh(&starting.mesh))
        .map_err(|e| CliError::context(format!("{e} (input {})", args.input.display()), e))?;
    let own = recipe_vertices(&args, &starting.mesh, &recipe)?;
    let solver = solver_loop(&args, &starting.mesh, &recipe, own)?;
    let budget = budget(&args, own);
    if let Some(b) = budget.as_ref().filter(|_| own.is_some()) {
        ui::note(&format!("vertex budget: {}", b.from));
    }
    if let Some(b) = &budget {
        let kept = starting.geometry_points.len();
        if !args.coarsen_geometry && geometry_over_budget(kept, b.schedule.target) {
            ui::warn(&format!(
                "the budget of {} vertices cannot hold: the {kept} vertices of {} stay vertices of every mesh (a floor of {kept}); --coarsen-geometry lets the remesher remove them",
                format_count(b.schedule.target),
                args.input.display()
            ));
        }
    }
    let layer = layer_options(&args, &recipe, &starting.mesh)?;
    // Periodic sides: images of each other on the starting mesh (else bad input), frozen
    // through every remeshing, measured again on the result.
    let sides = super::periodic_sides(&mut starting.mesh, &pairs, &args.input)?;
    // Remeshing keeps the sides' curves and tags: resolved once, on the start.
    args.output_format.periodic_from_recipe(format, &starting.mesh, &pairs)?;
    let mmg = args.adapter == AdapterArg::Mmg2d;
    let options = AdapterOptions {
        program: args.adapter_program.clone(),
        hgrad: args.controls.hgrad.filter(|_| mmg),
        hausd: args.hausd,
        nosurf: args.nosurf,
        // The loop's --hmin/--hmax bound the recipe's field, which MMG then follows.
        hmin: None,
        hmax: None,
        ridge_angle: None,
        no_ridges: false,
        extra_args: args.adapter_args.clone(),
        keep_points: if args.coarsen_geometry { Vec::new() } else { starting.geometry_points },
        max_vertices: Some(args.max_vertices),
        periodic: pairs.clone(),
    };
    let start = starting.mesh;
    let remesher = adapter(args.adapter.into(), options)?;

    let opts = AdaptOptions {
        max_iterations: args.max_iterations,
        tolerances: Tolerances { vertices: args.tol_vertices, conformity: args.tol_conformity },
        max_vertices: Some(args.max_vertices),
        max_growth: (args.max_growth > 0.0).then_some(args.max_growth),
        layer,
        periodic: sides,
        budget,
    };
    let to_stdout = is_stdio(&args.output);
    let mesh_file = if to_stdout { Path::new("stdout.msh") } else { args.output.as_path() };
    let mut progress = Progress {
        files: ResultFiles::new(
            mesh_file,
            args.history.as_deref(),
            args.output_format.write_options(&args.output),
        )
        .with_format(format),
        to_stdout,
        bar: ui::progress_bar(opts.max_iterations as u64, "{bar:30} {pos}/{len} {msg} [{elapsed}]"),
        adapter: remesher.name().to_string(),
        printed: 0,
        plane_z: Some(plane_z),
    };
    handle_interrupts();
    let input = args.input.display().to_string();
    let result = run_loop(
        start,
        &recipe,
        solver.as_ref(),
        remesher.as_ref(),
        &opts,
        &input,
        &args.recipe.label(),
        &mut progress,
    );
    finish(&args, result, progress, &read_notes, format, Some(plane_z), t0)
}

/// Says how the run ended and writes what is left to write: the best mesh to stdout
/// with `-o -`, the `--json` summary; the exit status from the outcome. `plane_z`: the
/// input's plane (the result is put back in it), `None` for a mesh in space.
fn finish(
    args: &AdaptArgs,
    result: Result<Outcome, smartmesh::adapt::AdaptError>,
    progress: Progress,
    read_notes: &[String],
    format: Format,
    plane_z: Option<f64>,
    t0: Instant,
) -> Result<(), CliError> {
    let to_stdout = progress.to_stdout;
    if let Some(b) = &progress.bar {
        b.finish_and_clear();
    }
    let mut outcome = result.map_err(|e| match e {
        e @ smartmesh::adapt::AdaptError::Start { .. } => {
            CliError::context(format!("{e} (input {})", args.input.display()), e)
        }
        e => e.into(),
    })?;
    if let Some(z) = plane_z {
        smartmesh::place(&mut outcome.best, z);
    }
    let _writing = WRITING.lock();
    for w in &outcome.warnings {
        ui::warn(w);
    }
    say_layer_and_sides(&mut outcome, plane_z.unwrap_or(0.0))?;
    let h = &outcome.history;
    let best = &h.iterations[h.best_iteration];
    let result_mesh = outcome.layer.as_ref().map_or(&outcome.best, |l| &l.mesh);
    let mut dropped = progress.files.dropped.clone();
    if to_stdout {
        dropped = args.output_format.write(&args.output, result_mesh, format)?.dropped;
    } else {
        ui::write_notes(&args.output.display().to_string(), &dropped);
    }
    if args.json {
        let s = AdaptSummary {
            output: args.output.display().to_string(),
            history_file: progress.files.history.display().to_string(),
            dropped: &dropped,
            read_notes,
            history: h,
        };
        let mut text = serde_json::to_string_pretty(&s)?;
        text.push('\n');
        print_stdout(&text)?;
    }
    let kept = format!(
        "{} holds the best mesh, iteration {}{} ({} vertices, {:.1}% of edges conforming); history in {}",
        if to_stdout { "stdout".into() } else { args.output.display().to_string() },
        h.best_iteration,
        if h.layer.is_some() { " with its LAYER skin" } else { "" },
        h.written_counts().map_or(best.vertices, |c| c.0),
        100.0 * best.conforming_share,
        progress.files.history.display()
    );
    if let Some(e) = outcome.failure {
        // A vertex limit is the user's to raise: bad usage, not a failure of the work.
        let limit = e.is_limit();
        let mut err = CliError::context(format!("{e}\n{kept}"), e);
        if limit {
            err.status = ExitStatus::Error;
        }
        return Err(err);
    }
    if h.stopped == smartmesh::adapt::INTERRUPTED {
        return Err(CliError {
            status: ExitStatus::Interrupted,
            message: format!("interrupted after iteration {}; {kept}", h.iterations.len() - 1),
            source: None,
        });
    }
    if !h.converged {
        ui::warn(&format!("not converged: {}; {kept}", h.stopped));
    }
    ui::done(
        "adapt",
        &format!(
            "{} after {} iteration{}: {kept}; {}",
            if h.converged { "converged" } else { "stopped" },
            h.iterations.len() - 1,
            if h.iterations.len() == 2 { "" } else { "s" },
            ui::seconds(t0.elapsed())
        ),
    );
    Ok(())
}
