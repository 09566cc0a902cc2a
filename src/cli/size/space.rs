//! `size` on a mesh of tetrahedra: the Lp-optimal metric of a solution field
//! (`--field u --complexity N` or `--error E`), written as a 3D metric to any metric
//! target (`.sol`/`.solb` in MMG's order, `.mesh`, `.msh`, `.pos`, `.vtu`, `.vtk`). A
//! recipe's own steps in space are refused here (exit 2) until the sizing driver runs
//! them; its global hmin, hmax and aspect ratio bound the solution's metric as in 2D.

use std::path::Path;
use std::time::Instant;

use smartmesh::formats::TaggedMesh;
use smartmesh::metric::Sym3;
use smartmesh::recipe::Recipe;
use smartmesh::sizing::solution::input::{attach, field_names, read_solution};
use smartmesh::sizing::SolutionHessian;
use smartmesh::MetricField;

use super::super::output::{label, shown};
use super::super::{print_stdout, ui, write_stdout, CliError};
use super::{SizeArgs, Target};

/// What `size --json` prints for a metric in space.
#[derive(serde::Serialize)]
struct SpaceSummary {
    mesh: String,
    files: Vec<String>,
    dimension: u8,
    vertices: usize,
    field: String,
    complexity: Option<f64>,
    error: Option<f64>,
    p: f64,
    recovery: &'static str,
    smallest_size: f64,
    largest_size: f64,
    largest_anisotropy: f64,
    /// The vertices a mesh conforming to the metric has (its complexity over the
    /// tetrahedra).
    expected_vertices: f64,
    predicted_error: f64,
    dropped: Vec<String>,
}

/// Runs `size` on `mesh`, a mesh in space read from `args.mesh`, to `target`.
pub(super) fn run(
    args: &SizeArgs,
    mut mesh: TaggedMesh,
    recipe: &Recipe,
    target: &Target,
    t0: Instant,
) -> Result<(), CliError> {
    let path = &args.mesh;
    if !recipe.algorithms.is_empty() {
        return Err(CliError::usage(format!(
            "{}: 3D sizing is not there yet for a recipe's steps; a metric from a solution is (--field u --complexity N)",
            path.display()
        )));
    }
    let goal = args.solution.target().ok_or_else(|| {
        CliError::usage("a metric from a solution needs --complexity N or --error E")
    })?;
    let asked = args.solution.fields()?;
    let names = match &args.solution_file {
        Some(file) => {
            let other = read_solution(file, &mesh)?;
            let names = field_names(&other, file, &asked)?;
            for name in &names {
                attach(&mut mesh, path, &other, file, name)?;
            }
            names
        }
        None => field_names(&mesh, path, &asked)?,
    };
    let bounds = args.solution.bounds(&mesh, recipe)?;
    let step = SolutionHessian {
        fields: names.clone(),
        target: goal,
        p: args.solution.p,
        method: args.solution.recovery,
        h_min: Some(bounds.h_min()),
        h_max: Some(bounds.h_max()),
        max_aspect: Some(bounds.max_aspect_ratio()),
    };
    let metric = step
        .metric_in_space(&mesh)
        .map_err(|e| CliError::usage(format!("{}: {e}", path.display())))?;
    let tensors: Vec<Sym3> = metric.tensors.iter().map(|t| t.to_metric()).collect();
    let opts = args.output_format.write_options(&target.path);
    let report = MetricField::new(tensors, "the solution's metric")
        .write(&target.path, &mesh, target.kind, &opts)
        .map_err(|e| label(e, &args.output))?;
    ui::write_notes(&args.output.display().to_string(), &report.dropped);
    if target._dir.is_some() {
        copy_to_stdout(args, &report.files, &target.path)?;
    }
    let (mut lo, mut hi, mut aniso) = (f64::INFINITY, 0.0f64, 1.0f64);
    for t in &metric.tensors {
        lo = lo.min(t.h_min());
        hi = hi.max(t.h_max());
        aniso = aniso.max(t.aspect_ratio());
    }
    if args.json {
        let s = SpaceSummary {
            mesh: path.display().to_string(),
            files: report.files.iter().map(|p| p.display().to_string()).collect(),
            dimension: 3,
            vertices: mesh.points.len(),
            field: names.join(","),
            complexity: args.solution.complexity,
            error: args.solution.error.filter(|_| args.solution.complexity.is_none()),
            p: args.solution.p,
            recovery: args.solution.recovery.name(),
            smallest_size: lo,
            largest_size: hi,
            largest_anisotropy: aniso,
            expected_vertices: metric.vertices,
            predicted_error: metric.predicted_error,
            dropped: report.dropped.clone(),
        };
        let mut text = serde_json::to_string_pretty(&s)?;
        text.push('\n');
        print_stdout(&text)?;
    }
    ui::done(
        "size",
        &format!(
            "wrote {} (a 3D metric on {} vertices, sizes {} to {}, anisotropy up to {}; a conforming mesh has about {} vertices) in {}",
            shown(&args.output),
            mesh.points.len(),
            ui::sig(lo),
            ui::sig(hi),
            ui::sig(aniso),
            smartmesh::metric::complexity::format_count(metric.vertices),
            ui::seconds(t0.elapsed())
        ),
    );
    Ok(())
}

/// Copies the one file written for `-o -` to stdout.
fn copy_to_stdout(
    args: &SizeArgs,
    files: &[std::path::PathBuf],
    path: &Path,
) -> Result<(), CliError> {
    if files.len() > 1 {
        return Err(CliError::usage(format!(
            "--to {}: the field needs sibling files, which stdout cannot hold; name an output file",
            args.output_format.to.as_deref().unwrap_or_default()
        )));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| CliError::context("reading back the field for stdout", e))?;
    write_stdout(&bytes)
}
