//! `smartmesh size MESH --recipe R -o OUT`: the metric field of a recipe on a mesh's
//! vertices, written for MMG, Gmsh or ParaView.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use smartmesh::export::{export_metric, MetricTarget};
use smartmesh::formats::{read_path, Format};
use smartmesh::recipe::Recipe;
use smartmesh::sizing::{size_mesh, SizeMeshError, StepEvent, StepReport};

use super::{parse_format, print_stdout, CliError, ExitStatus};

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

Examples:
  smartmesh size naca.msh --recipe agard01.toml -o naca.sol
  smartmesh size distributor.msh --recipe distributor.cfg -o field.vtu
  smartmesh size square.msh --recipe wake.toml -o bgm.pos && gmsh square.geo -2 -bgm bgm.pos -setnumber Mesh.Algorithm 7"
)]
pub struct SizeArgs {
    /// Input mesh (any readable format; `-` for stdin, with --from).
    mesh: PathBuf,
    /// The recipe (.cfg libconfig, .toml, .json).
    #[arg(long, short = 'r')]
    recipe: PathBuf,
    /// Output: .sol .solb .mesh .meshb .msh .pos .vtu .vtk.
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
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
}

/// Runs `size`.
pub fn run(args: SizeArgs) -> Result<(), CliError> {
    let target = MetricTarget::from_path(&args.output).ok_or_else(|| {
        CliError::usage(format!(
            "{}: cannot hold a metric; use one of {}",
            args.output.display(),
            MetricTarget::EXTENSIONS
        ))
    })?;
    let recipe = Recipe::from_path(&args.recipe).map_err(|e| CliError::usage(e.to_string()))?;
    let from = args.from.or_else(|| Format::from_path(&args.mesh));
    let mesh = read_path(&args.mesh, from)?;
    let steps = recipe.algorithms.len() as u64;

    let bar = std::io::stderr().is_terminal().then(|| {
        let b = ProgressBar::new(steps);
        b.set_style(
            ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    });
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
    let field = match size_mesh(&mesh, &recipe, &mut observe) {
        Ok(s) => s.field,
        Err(SizeMeshError::Resolve(e)) => {
            return Err(CliError::usage(format!("{e} (mesh {})", args.mesh.display())))
        }
        Err(SizeMeshError::Graph(e)) => {
            return Err(CliError::usage(format!("{}: {e}", args.mesh.display())))
        }
        Err(e @ SizeMeshError::Sizing(_)) => {
            return Err(CliError { status: ExitStatus::Error, message: e.to_string() })
        }
    };
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    for w in &field.warnings {
        eprintln!("smartmesh: warning: {w}");
    }

    let opts = args.output_format.write_options();
    let report = export_metric(&args.output, &mesh, &field.tensors, target, &opts)?;
    for d in &report.dropped {
        eprintln!("smartmesh: warning: not written: {d}");
    }
    if args.json {
        let (mut lo, mut hi, mut aniso) = (f64::INFINITY, 0.0f64, 1.0f64);
        for t in &field.tensors {
            lo = lo.min(t.h_min());
            hi = hi.max(t.h_max());
            aniso = aniso.max(t.aspect_ratio());
        }
        let s = SizeSummary {
            mesh: args.mesh.display().to_string(),
            recipe: args.recipe.display().to_string(),
            files: report.files.iter().map(|p| p.display().to_string()).collect(),
            vertices: mesh.points.len(),
            vertices_reached: field.reached.iter().filter(|&&r| r).count(),
            default_size: field.default_size,
            smallest_size: lo,
            largest_size: hi,
            largest_anisotropy: aniso,
            steps: &field.steps,
            warnings: &field.warnings,
            dropped: &report.dropped,
        };
        let mut text =
            serde_json::to_string_pretty(&s).map_err(|e| CliError::usage(e.to_string()))?;
        text.push('\n');
        print_stdout(&text)?;
    }
    Ok(())
}
