//! `smartmesh size MESH --recipe R -o OUT`: the metric field of a recipe on a mesh's
//! vertices, written for MMG, Gmsh or ParaView; with `--field u --complexity N` the
//! Lp-optimal metric of a solution field too, intersected after the recipe's steps (or
//! alone, without a recipe); `--field u,p` (or `--field u --field p`) normalises the
//! fields together and intersects them in that order.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use smartmesh::expected_vertices;
use smartmesh::formats::Format;
use smartmesh::metric::{SizeTensor, SizeTensor3, Sym3};
use smartmesh::recipe::{size_mesh_in_space, size_mesh_with_steps, SizeMeshError};
use smartmesh::sizing::solution::input::{attach, field_names, read_solution};
use smartmesh::sizing::{SizeField, SizeField3, StepEvent, StepReport};
use smartmesh::Topology;
use smartmesh::{MetricField, MetricTarget};

use super::output::{check_output_dir, is_stdio, label, shown, SizeControls};
use super::solution::SolutionArgs;
use super::{parse_format, print_stdout, ui, write_stdout, CliError, RecipeInput};

/// Compute the metric field a recipe asks for on a mesh, and write it.
#[derive(Debug, Args)]
#[command(
    after_help = "The recipe is libconfig (.cfg, run through the C preprocessor as in the thesis), \
TOML (.toml) or JSON (.json); `smartmesh recipe check RECIPE MESH` shows how its regions resolve.

The output's extension chooses what is written:
  .sol .solb      the metric alone, for `mmg2d_O3 MESH.mesh -sol OUT.sol`
  .mesh .meshb    the mesh with its metric in the .sol/.solb beside it, for `mmg2d_O3 OUT.mesh`
  .msh            the mesh with a $NodeData view `metric` (9 components), for `gmsh -bgm OUT.msh`
  .pos            a Gmsh tensor view (TT records), for `gmsh -bgm OUT.pos`
  .vtu .vtk       the mesh with point data metric, size_tensor, h1, h2, anisotropy, axis1, axis2
                  (glyph `size_tensor` in ParaView to see the size ellipses at scale 1)
Gmsh honours an anisotropic background mesh only with BAMG: `-setnumber Mesh.Algorithm 7`.
A 3D metric (tetrahedra, a surface in space) goes to the same files: .sol/.solb in MMG's order
m11 m12 m22 m13 m23 m33 (`mmg3d_O3`, `mmgs_O3`), .pos with TS records on the tetrahedra, .vtu/.vtk
with h3 and axis3 too; `recipe check RECIPE MESH` says which of the recipe's steps are sized in
space (the others are refused, exit 2). Inside a volume Gmsh reads a tensor view only with MMG3D
(`-setnumber Mesh.Algorithm3D 7`, the surfaces meshed by BAMG); its Delaunay (1), Frontal (4)
and HXT (10) warn \"No vector or scalar value found in PostView field\" and fill the volume
from the surface mesh. `remesh`/`adapt --adapter gmsh` drive that MMG3D on a tetrahedral mesh
(a Gmsh cube with a wall layer: 49.5% of edges in [1/sqrt2, sqrt2] before, 73.8% after).

Examples:
  smartmesh size naca.msh --recipe agard01.toml -o naca.sol
  smartmesh size distributor.msh --recipe distributor.cfg -o field.vtu
  smartmesh size square.msh --recipe wake.toml -o bgm.pos && gmsh square.geo -2 -bgm bgm.pos -setnumber Mesh.Algorithm 7
  smartmesh size naca.msh -r agard01.toml --hmin 1e-4 -o - --to sol > naca.sol
  smartmesh size flow.vtu --field u --complexity 4000 -o flow.sol
  smartmesh size flow.vtu --field u,p --complexity 4000 -o flow.sol   (both fields, intersected)
  smartmesh size box.vtu --field u --complexity 20000 -o box.sol   (tetrahedra: a 3D metric for mmg3d_O3)
  smartmesh size naca.msh -r agard01.toml --solution-file flow.vtu --field mach --complexity 20000 -o both.sol"
)]
pub(super) struct SizeArgs {
    /// Input mesh (any readable format; `-` for stdin, with --from).
    mesh: PathBuf,
    #[command(flatten)]
    recipe: RecipeInput,
    /// Output: .sol .solb .mesh .meshb .msh .pos .vtu .vtk (`-` for stdout, with --to).
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    #[command(flatten)]
    controls: SizeControls,
    #[command(flatten)]
    solution: SolutionArgs,
    /// A file holding the solution field on the mesh's own vertices (a solver's .vtu,
    /// .msh …, or a Medit .sol alone in the mesh's vertex order), instead of the mesh's
    /// point data.
    #[arg(long, value_name = "FILE", help_heading = "Solution")]
    solution_file: Option<PathBuf>,
    #[command(flatten)]
    output_format: super::MeshOutputArgs,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct SizeSummary<'a> {
    mesh: String,
    recipe: String,
    files: Vec<String>,
    vertices: usize,
    vertices_reached: usize,
    default_size: f64,
    smallest_size: f64,
    largest_size: f64,
    largest_anisotropy: f64,
    steps: &'a [StepReport],
    warnings: &'a [String],
    dropped: &'a [String],
    /// What the reader could not keep, and the second-order cells made linear.
    read_notes: &'a [String],
    #[serde(skip_serializing_if = "Option::is_none")]
    solution: Option<SolutionSummary>,
}

/// What the solution's metric was asked and what the whole field asks.
#[derive(serde::Serialize)]
struct SolutionSummary {
    /// The fields, comma-separated as `--field` takes them.
    field: String,
    /// The fields in the order they were intersected.
    fields: Vec<String>,
    /// The vertex count asked of the solution's metric, when one was.
    complexity: Option<f64>,
    /// The error asked, when one was.
    error: Option<f64>,
    p: f64,
    recovery: &'static str,
    /// The vertices a mesh conforming to the whole field (recipe and solution) has.
    expected_vertices: f64,
}

/// Where the field goes: `output`, or for `-` a file of a temporary directory that is
/// copied to stdout once written (the metric writers name files).
struct Target {
    kind: MetricTarget,
    path: PathBuf,
    _dir: Option<tempfile::TempDir>,
}

fn target(args: &SizeArgs) -> Result<Target, CliError> {
    let stdout = is_stdio(&args.output);
    let named = match (&args.output_format.to, stdout) {
        (Some(t), _) => PathBuf::from(format!("field.{t}")),
        (None, true) => {
            return Err(CliError::usage(format!(
                "writing to stdout (`-o -`) needs --to, one of {}",
                MetricTarget::EXTENSIONS
            )))
        }
        (None, false) => args.output.clone(),
    };
    let kind = MetricTarget::from_path(&named).ok_or_else(|| {
        CliError::usage(format!(
            "{}: cannot hold a metric; use one of {}",
            if args.output_format.to.is_some() { named.display() } else { args.output.display() },
            MetricTarget::EXTENSIONS
        ))
    })?;
    if !stdout {
        check_output_dir(&args.output)?;
        return Ok(Target { kind, path: args.output.clone(), _dir: None });
    }
    let dir =
        tempfile::tempdir().map_err(|e| CliError::context("creating a temporary directory", e))?;
    Ok(Target { kind, path: dir.path().join(named), _dir: Some(dir) })
}

/// Runs `size`.
pub(super) fn run(args: SizeArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    if is_stdio(&args.mesh) && args.recipe.is_stdin() {
        return Err(CliError::usage("the mesh and the recipe cannot both come from stdin"));
    }
    if is_stdio(&args.output) && args.json {
        return Err(CliError::usage(
            "--json prints on stdout, which `-o -` already uses for the field",
        ));
    }
    let target = target(&args)?;
    let solving = !args.solution.field.is_empty() || args.solution_file.is_some();
    let recipe = args
        .controls
        .over(args.recipe.read_or_empty(solving, "with --field or --solution-file")?)?;
    let from = args.from.or_else(|| Format::from_path(&args.mesh));
    // The field is written on the input's own points. A mesh in space (volume cells, or
    // surface cells off one plane) goes to the 3D engine, the same recipe and steps.
    let (mut mesh, read_notes) = super::read_linear_mesh_noted(&args.mesh, from)?;
    let in_space = smartmesh::plane(&mesh).is_err();
    let mut extra = Vec::new();
    let mut solution = None;
    if solving {
        let goal = args.solution.target().ok_or_else(|| {
            CliError::usage("a metric from a solution needs --complexity N or --error E")
        })?;
        let asked = args.solution.fields()?;
        let names = match &args.solution_file {
            Some(file) => {
                let other = read_solution(file, &mesh)?;
                let names = field_names(&other, file, &asked)?;
                for name in &names {
                    attach(&mut mesh, &args.mesh, &other, file, name)?;
                }
                names
            }
            None => field_names(&mesh, &args.mesh, &asked)?,
        };
        extra.push(args.solution.step(&names, goal, &mesh, &recipe)?);
        solution = Some(names);
    }
    let steps = (recipe.algorithms.len() + extra.len()) as u64;

    let bar = ui::progress_bar(steps, "{bar:30} {pos}/{len} {msg} [{elapsed}]");
    let mut observe = |event: StepEvent| {
        if let Some(b) = &bar {
            match event {
                StepEvent::Started { label, of, .. } => {
                    b.set_length(of as u64);
                    b.set_message(label)
                }
                StepEvent::Finished { .. } => b.inc(1),
            }
        }
    };
    let topology = Topology::from_mesh(&mesh);
    let sized = if in_space {
        size_mesh_in_space(&mesh, &topology, &recipe, &extra, &mut observe)
            .map(|s| Sized::space(s.field))
    } else {
        size_mesh_with_steps(&mesh, &topology, &recipe, &extra, &mut observe)
            .map(|s| Sized::plane(s.field))
    };
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let field = match sized {
        Ok(s) => s,
        Err(e @ SizeMeshError::Resolve(_)) => {
            return Err(CliError::context(format!("{e} (mesh {})", args.mesh.display()), e))
        }
        Err(e @ SizeMeshError::Graph(_)) => {
            return Err(CliError::context(format!("{}: {e}", args.mesh.display()), e))
        }
        Err(e) => return Err(e.into()),
    };
    for w in &field.warnings {
        ui::warn(w);
    }

    let opts = args.output_format.write_options(&target.path);
    let report = match &field.metric {
        Metric::Plane(m) => m.write(&target.path, &mesh, target.kind, &opts),
        Metric::Space(m) => m.write(&target.path, &mesh, target.kind, &opts),
    }
    .map_err(|e| label(e, &args.output))?;
    ui::write_notes(&args.output.display().to_string(), &report.dropped);
    if target._dir.is_some() {
        if report.files.len() > 1 {
            return Err(CliError::usage(format!(
                "--to {}: the field needs sibling files, which stdout cannot hold; name an output file",
                args.output_format.to.as_deref().unwrap_or_default()
            )));
        }
        let bytes = std::fs::read(&target.path)
            .map_err(|e| CliError::context("reading back the field for stdout", e))?;
        write_stdout(&bytes)?;
    }
    let expected = solution.as_ref().map(|_| match &field.metric {
        Metric::Plane(m) => expected_vertices(&mesh, m.tensors()),
        Metric::Space(m) => expected_vertices(&mesh, m.tensors()),
    });
    let (lo, hi, aniso) = field.extremes;
    if args.json {
        let s = SizeSummary {
            mesh: args.mesh.display().to_string(),
            recipe: args.recipe.label(),
            files: report.files.iter().map(|p| p.display().to_string()).collect(),
            vertices: mesh.points.len(),
            vertices_reached: field.reached,
            default_size: field.default_size,
            smallest_size: lo,
            largest_size: hi,
            largest_anisotropy: aniso,
            steps: &field.steps,
            warnings: &field.warnings,
            dropped: &report.dropped,
            read_notes: &read_notes,
            solution: solution.as_ref().map(|names| SolutionSummary {
                field: names.join(","),
                fields: names.clone(),
                complexity: args.solution.complexity,
                error: args.solution.error.filter(|_| args.solution.complexity.is_none()),
                p: args.solution.p,
                recovery: args.solution.recovery.name(),
                expected_vertices: expected.unwrap_or(f64::NAN),
            }),
        };
        let mut text = serde_json::to_string_pretty(&s)?;
        text.push('\n');
        print_stdout(&text)?;
    }
    ui::done(
        "size",
        &format!(
            "wrote {} ({} vertices, sizes {} to {}, anisotropy up to {}{}) in {}",
            shown(&args.output),
            mesh.points.len(),
            ui::sig(lo),
            ui::sig(hi),
            ui::sig(aniso),
            expected.map_or(String::new(), |v| format!(
                "; a conforming mesh has about {} vertices",
                smartmesh::metric::complexity::format_count(v)
            )),
            ui::seconds(t0.elapsed())
        ),
    );
    Ok(())
}

/// The field as a metric of its dimension.
enum Metric {
    Plane(MetricField),
    Space(MetricField<Sym3>),
}

/// A sized field of either dimension, with what the summary says of it.
struct Sized {
    metric: Metric,
    /// Vertices some step reached.
    reached: usize,
    default_size: f64,
    warnings: Vec<String>,
    steps: Vec<StepReport>,
    /// The smallest size, the largest, the largest anisotropy.
    extremes: (f64, f64, f64),
}

/// The smallest and largest sizes and the largest anisotropy of `sizes`.
fn extremes(sizes: impl Iterator<Item = (f64, f64, f64)>) -> (f64, f64, f64) {
    sizes.fold((f64::INFINITY, 0.0f64, 1.0f64), |(lo, hi, an), (a, b, c)| {
        (lo.min(a), hi.max(b), an.max(c))
    })
}

impl Sized {
    fn plane(f: SizeField) -> Sized {
        Sized {
            extremes: extremes(
                f.tensors.iter().map(|t: &SizeTensor| (t.h_min(), t.h_max(), t.aspect_ratio())),
            ),
            metric: Metric::Plane(MetricField::from_sizes(&f.tensors, "the recipe's field")),
            reached: f.reached.iter().filter(|&&r| r).count(),
            default_size: f.default_size,
            warnings: f.warnings,
            steps: f.steps,
        }
    }

    fn space(f: SizeField3) -> Sized {
        Sized {
            extremes: extremes(
                f.tensors.iter().map(|t: &SizeTensor3| (t.h_min(), t.h_max(), t.aspect_ratio())),
            ),
            metric: Metric::Space(f.metric_field("the recipe's field")),
            reached: f.reached.iter().filter(|&&r| r).count(),
            default_size: f.default_size,
            warnings: f.warnings,
            steps: f.steps,
        }
    }
}
