//! `smartmesh remesh MESH --metric M -o OUT`: the native anisotropic remesher, and
//! `--measure` to report how a mesh conforms to a metric without remeshing it (the same
//! measure for our output and another tool's).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use smartmesh::conformity::{metric_field, Conformity};
use smartmesh::formats::{read_path, write_path, Format, TaggedMesh};
use smartmesh::metric::Sym2;
use smartmesh::remesh::{
    interpolate_metric, remesh_with_progress, BoundaryMode, RemeshEvent, RemeshOptions,
};

use super::{parse_format, print_stdout, CliError};

/// Boundary placement, as the command line names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Boundary {
    /// On the original boundary polylines.
    Polyline,
    /// On a smooth (C¹ cubic) reconstruction through the original boundary vertices.
    Smooth,
}

/// Adapt a triangle mesh to a metric field (split, collapse, swap, smooth in the metric).
#[derive(Debug, Args)]
#[command(
    after_help = "The metric is a 9-component (or 3-component m11 m12 m22) point array `metric` on \
MESH's vertices: in the file given with --metric (a .vtu or .msh written by `smartmesh size`, or a .mesh \
with its .sol beside it), or in MESH itself when --metric is left out.

Boundary and interface vertices slide along their own curve, corners (topological points, and curve \
vertices turning by more than --ridge-angle) never move; face and curve tags are kept. The output \
carries the interpolated `metric` (a .mesh output writes it to the .sol beside it).

Examples:
  smartmesh size fixtures/cylinder.msh --recipe fixtures/cylinder.toml -o field.vtu
  smartmesh remesh fixtures/cylinder.msh --metric field.vtu -o adapted.vtu --json
  smartmesh remesh adapted.mesh --measure --json      # conformity of a mesh to its own .sol"
)]
pub struct RemeshArgs {
    /// Input mesh (any readable format; `-` for stdin, with --from).
    mesh: PathBuf,
    /// A file holding point data `metric` on the same vertices as MESH.
    #[arg(long, short = 'm')]
    metric: Option<PathBuf>,
    /// Output mesh (any writable format); required unless --measure.
    #[arg(long, short = 'o', required_unless_present = "measure")]
    output: Option<PathBuf>,
    /// Only measure MESH against the metric (share of edges in [1/√2, √2], metric quality).
    #[arg(long)]
    measure: bool,
    /// With --measure: take the metric from this mesh (the input of a remeshing, with its
    /// `metric`), interpolated at MESH's vertices, instead of MESH's own.
    #[arg(long, requires = "measure", conflicts_with = "metric")]
    background: Option<PathBuf>,
    /// Where boundary vertices go.
    #[arg(long, value_enum, default_value = "polyline")]
    boundary: Boundary,
    /// Passes of split, collapse, swap and smooth at most.
    #[arg(long, default_value_t = RemeshOptions::default().max_passes)]
    max_passes: usize,
    /// Smoothing sweeps per pass.
    #[arg(long, default_value_t = RemeshOptions::default().smooth_sweeps)]
    smooth_sweeps: usize,
    /// A curve turning by more than this many degrees at a vertex makes it a corner.
    #[arg(long, default_value_t = RemeshOptions::default().ridge_angle_degrees)]
    ridge_angle: f64,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    #[command(flatten)]
    output_format: super::MeshOutputArgs,
    /// Print the statistics (or the measure) as JSON on stdout.
    #[arg(long)]
    json: bool,
}

/// The metric for `mesh`: from `--metric` or from the mesh itself.
fn read_metric(
    mesh_path: &Path,
    mesh: &TaggedMesh,
    metric: Option<&Path>,
) -> Result<Vec<Sym2>, CliError> {
    match metric {
        None => metric_field(mesh, "metric")
            .map_err(|e| CliError::usage(format!("{}: {e}", mesh_path.display()))),
        Some(p) => {
            let m = read_path(p, None)?;
            if m.points.len() != mesh.points.len() {
                return Err(CliError::usage(format!(
                    "{}: {} vertices, but {} has {}; the metric must be on the mesh's vertices",
                    p.display(),
                    m.points.len(),
                    mesh_path.display(),
                    mesh.points.len()
                )));
            }
            // Same count is not enough: the vertices must be MESH's (up to rounding in a
            // text file).
            let (lo, hi) = mesh.bounding_box().unwrap_or(([0.0; 3], [1.0; 3]));
            let tol = 1e-9 * (hi[0] - lo[0]).abs().max((hi[1] - lo[1]).abs()).max(1e-300);
            if let Some(v) = (0..mesh.points.len())
                .find(|&v| (0..2).any(|k| (m.points[v][k] - mesh.points[v][k]).abs() > tol))
            {
                return Err(CliError::usage(format!(
                    "{}: vertex {v} (0-based) is at {:?}, but vertex {v} of {} is at {:?}; the metric must be on the mesh's vertices",
                    p.display(),
                    &m.points[v][..2],
                    mesh_path.display(),
                    &mesh.points[v][..2]
                )));
            }
            metric_field(&m, "metric").map_err(|e| CliError::usage(format!("{}: {e}", p.display())))
        }
    }
}

/// Runs `remesh`.
pub fn run(args: RemeshArgs) -> Result<(), CliError> {
    let from = args.from.or_else(|| Format::from_path(&args.mesh));
    let mesh = read_path(&args.mesh, from)?;
    let metric = match &args.background {
        Some(b) => {
            let bmesh = read_path(b, None)?;
            let bmetric = metric_field(&bmesh, "metric")
                .map_err(|e| CliError::usage(format!("{}: {e}", b.display())))?;
            let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
            interpolate_metric(&bmesh, &bmetric, &pts)
                .map_err(|e| CliError::usage(format!("{}: {e}", b.display())))?
        }
        None => read_metric(&args.mesh, &mesh, args.metric.as_deref())?,
    };
    if args.measure {
        let c = Conformity::of_mesh(&mesh, &metric).ok_or_else(|| {
            CliError::usage(format!("{}: no triangles to measure", args.mesh.display()))
        })?;
        let text = if args.json {
            serde_json::to_string_pretty(&c).map_err(|e| CliError::usage(e.to_string()))? + "\n"
        } else {
            format!(
                "{} edges, {:.1}% in [1/√2, √2], metric length {:.3} to {:.3} (mean {:.3}); {} triangles, metric quality mean {:.3}, min {:.3}\n",
                c.edges,
                100.0 * c.conforming_share,
                c.edge_length_range[0],
                c.edge_length_range[1],
                c.mean_edge_length,
                c.triangles,
                c.mean_quality,
                c.min_quality
            )
        };
        return print_stdout(&text);
    }
    let Some(output) = args.output else {
        return Err(CliError::usage("-o OUT is required unless --measure"));
    };
    let opts = RemeshOptions {
        max_passes: args.max_passes,
        boundary: match args.boundary {
            Boundary::Polyline => BoundaryMode::Polyline,
            Boundary::Smooth => BoundaryMode::Smooth,
        },
        ridge_angle_degrees: args.ridge_angle,
        smooth_sweeps: args.smooth_sweeps,
        ..RemeshOptions::default()
    };
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = ProgressBar::new(opts.max_passes as u64);
        b.set_style(
            ProgressStyle::with_template("{bar:30} pass {pos}/{len} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    });
    let mut observe = |e: RemeshEvent| {
        if let (Some(b), RemeshEvent::Pass { pass, triangles, .. }) = (&bar, e) {
            b.set_position(pass as u64);
            b.set_message(format!("{triangles} triangles"));
        }
    };
    let out = remesh_with_progress(&mesh, &metric, &opts, &mut observe)
        .map_err(|e| CliError::usage(format!("{}: {e}", args.mesh.display())))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    for w in &out.stats.warnings {
        eprintln!("smartmesh: warning: {w}");
    }
    let wopts = args.output_format.write_options();
    let report = write_path(&output, &out.mesh, None, &wopts)?;
    for d in &report.dropped {
        eprintln!("smartmesh: warning: not written: {d}");
    }
    if args.json {
        let mut text =
            serde_json::to_string_pretty(&out.stats).map_err(|e| CliError::usage(e.to_string()))?;
        text.push('\n');
        print_stdout(&text)?;
    }
    Ok(())
}
