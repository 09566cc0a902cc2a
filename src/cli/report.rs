//! `smartmesh report MESH -o FILE.svg|FILE.png`: a picture of a mesh, its metric, its
//! conformity and an adaptation history; with `--cut x|y|z=VALUE`, of the planar cut of a
//! tetrahedral mesh and its 3D metric restricted to the plane.

use std::path::PathBuf;

use clap::Args;
use smartmesh::formats::{write_all_atomically, Format};
use smartmesh::metric::Sym3;
use smartmesh::report::{self, CutInput, CutPlane, ReportFormat, ReportInput, ReportOptions};
use smartmesh::History;
use smartmesh::Topology;
use smartmesh::{MetricError, MetricField};

use super::{parse_format, CliError};

/// Draw a mesh and its metric: the whole mesh, zooms around the recipe's sources with
/// size ellipses, histograms of metric edge length and quality, the convergence history.
#[derive(Debug, Args)]
#[command(
    after_help = "Panels: the whole mesh (faces filled by tag, edges, boundary curves coloured by tag,
tagged points, a legend of the tag names, the zoom windows framed); one zoom per recipe step
with sources (their bounding box grown by the step's reach; for a source as large as the
domain, around where that step asks for its finest sizes), or without a recipe around the
smallest metric sizes, with size ellipses (semi-axes h1, h2 along the metric's axes, at true scale
unless the panel says a factor); histograms of metric edge length (band [1/√2, √2] shaded,
share printed) and metric quality; the history of `smartmesh adapt` with --history.

The metric is the point data `metric` of --metric M (a mesh file on MESH's vertices, as
`smartmesh size -o M.vtu` writes it, a .sol/.solb in MESH's vertex order, or a .pos view),
else MESH's own `metric` array; without either the
report shows the mesh alone and says so. Edges shorter than 2 pixels are drawn as shading,
so that the SVG grows with the picture, not with the mesh (10^6 triangles at 1200 px: about
330 KB).
PNG text uses the system's fonts (DejaVu Sans, Liberation Sans, Arial or any installed).

--cut x|y|z=VALUE draws the planar cut of a tetrahedral mesh instead: the exact polygons
(triangles, quads) where its tetrahedra cross the plane, filled by volume tag (a face in the
plane drawn once); the traces of its tagged surface triangles as lines coloured by surface, named
in the legend; with a 3D metric (--metric or MESH's `metric`), ellipses on the whole cut and in
zooms around the smallest sizes: the metric, interpolated Log-Euclidean along each cut edge,
RESTRICTED to the plane ({x in the plane : xᵀMx = 1}, the ellipsoid's section through its
centre, the sizes it asks of edges lying in the plane), not projected onto it. Picture axes:
(y, z) for x=, (x, z) for y=, (x, y) for z=.

Examples:
  smartmesh size cyl.msh --recipe cyl.toml -o cyl.vtu && smartmesh report cyl.vtu --recipe cyl.toml -o cyl.png
  smartmesh report adapted.msh --metric field.vtu --history history.json -o run.svg
  smartmesh report cube.meshb --metric cube.solb --cut z=0.5 -o cut.png"
)]
pub(super) struct ReportArgs {
    /// The mesh (any readable format; `-` for stdin, with --from).
    mesh: PathBuf,
    /// A metric on MESH's vertices: a mesh file with point data `metric`, a .sol/.solb,
    /// or a .pos view.
    #[arg(long, short = 'm')]
    metric: Option<PathBuf>,
    /// A recipe (.cfg, .toml, .json): zoom windows around its sources.
    #[arg(long, short = 'r')]
    recipe: Option<PathBuf>,
    #[command(flatten)]
    recipe_read: super::recipe::RecipeReadArgs,
    /// The history.json of an adaptation run.
    #[arg(long)]
    history: Option<PathBuf>,
    /// Output: FILE.svg or FILE.png (`-` writes to stdout, with --to).
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// Output kind for `-o -`: svg or png.
    #[arg(long)]
    to: Option<String>,
    /// Picture width in pixels (400 to 8000).
    #[arg(long, default_value_t = report::DEFAULT_WIDTH)]
    width: u32,
    /// PNG with a palette of 256 colours (NeuQuant): about a third of the size.
    #[arg(long)]
    palette: bool,
    /// Print a JSON summary on stdout: size, zoom windows, conformity figures, notes.
    #[arg(long)]
    json: bool,
    /// Input format of MESH, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    /// Draw the planar cut x=VALUE, y=VALUE or z=VALUE of a tetrahedral mesh, with its 3D
    /// metric's ellipses restricted to the plane.
    #[arg(long, value_parser = CutPlane::parse, value_name = "AXIS=VALUE")]
    cut: Option<CutPlane>,
}

/// Runs `report`.
pub(super) fn run(args: ReportArgs) -> Result<(), CliError> {
    let stdout = args.output.as_os_str() == "-";
    let kind = match (&args.to, stdout) {
        (Some(t), _) => match t.to_ascii_lowercase().as_str() {
            "svg" => ReportFormat::Svg,
            "png" => ReportFormat::Png,
            _ => {
                return Err(CliError::usage(format!("unknown report kind `{t}`; known: svg, png")))
            }
        },
        (None, true) => {
            return Err(CliError::usage("writing to stdout needs --to svg or --to png"))
        }
        (None, false) => ReportFormat::from_path(&args.output).ok_or_else(|| {
            CliError::usage(format!(
                "{}: a report is written as .svg or .png",
                args.output.display()
            ))
        })?,
    };
    if !(report::WIDTH_RANGE[0]..=report::WIDTH_RANGE[1]).contains(&args.width) {
        return Err(CliError::usage(format!(
            "--width {}: expected {} to {} pixels",
            args.width,
            report::WIDTH_RANGE[0],
            report::WIDTH_RANGE[1]
        )));
    }
    let history = read_history(&args)?;
    if let Some(plane) = args.cut {
        if args.recipe.is_some() {
            return Err(CliError::usage(
                "--recipe frames zooms on a planar mesh; it does not go with --cut",
            ));
        }
        let drawn = draw_cut(&args, plane, history.as_ref())?;
        return write_report(&args, kind, stdout, drawn);
    }
    let (mesh, _plane_z) =
        super::read_planar_mesh(&args.mesh, args.from.or_else(|| Format::from_path(&args.mesh)))?;
    let topology = Topology::from_mesh(&mesh);
    let metric =
        MetricField::load(&mesh, &args.mesh, args.metric.as_deref()).map_err(|e| match e {
            MetricError::Read(e) => CliError::from(e),
            e => CliError::from(e),
        })?;
    let plan = match &args.recipe {
        Some(r) => {
            let recipe = args.recipe_read.read(r)?;
            Some(
                recipe
                    .resolve(&topology)
                    .map_err(|e| {
                        CliError::context(format!("{e} (mesh {})", args.mesh.display()), e)
                    })?
                    .plan,
            )
        }
        None => None,
    };
    if let Some(why) = history.as_ref().and_then(|h| h.mismatch(&args.mesh)) {
        super::ui::warn(&why);
    }
    let name = args.mesh.display().to_string();
    let input = ReportInput {
        name: &name,
        mesh: &mesh,
        topology: &topology,
        metric: metric.as_ref(),
        plan: plan.as_ref(),
        history: history.as_ref(),
    };
    let drawn = report::render(&input, &ReportOptions { width: args.width });
    write_report(&args, kind, stdout, drawn)
}

/// The history of `--history`, checked.
fn read_history(args: &ReportArgs) -> Result<Option<History>, CliError> {
    Ok(match &args.history {
        Some(h) => {
            let text = std::fs::read_to_string(h).map_err(|e| {
                CliError::input(format!("{}: cannot read the history: {e}", h.display()), e)
            })?;
            Some(History::from_json(&text).map_err(|e| {
                CliError::input(
                    format!("{}: not a history.json of `smartmesh adapt`: {e}", h.display()),
                    e,
                )
            })?)
        }
        None => None,
    })
}

/// The report of the cut of `args.mesh` by `plane`, with its 3D metric.
fn draw_cut(
    args: &ReportArgs,
    plane: CutPlane,
    history: Option<&History>,
) -> Result<report::Report, CliError> {
    let format = args.from.or_else(|| Format::from_path(&args.mesh));
    let (mesh, _) = super::read_linear_mesh_noted(&args.mesh, format)?;
    let metric = MetricField::<Sym3>::load_field(&mesh, &args.mesh, args.metric.as_deref())?;
    if let Some(why) = history.and_then(|h| h.mismatch(&args.mesh)) {
        super::ui::warn(&why);
    }
    let name = args.mesh.display().to_string();
    let input = CutInput { name: &name, mesh: &mesh, metric: metric.as_ref(), history, plane };
    report::render_cut(&input, &ReportOptions { width: args.width })
        .map_err(|e| CliError::usage(format!("{}: {e}", args.mesh.display())))
}

/// Writes `drawn` as `kind` to `-o` (or stdout), with its notes and the `--json` summary.
fn write_report(
    args: &ReportArgs,
    kind: ReportFormat,
    stdout: bool,
    mut drawn: report::Report,
) -> Result<(), CliError> {
    for n in &drawn.notes {
        super::ui::note(n);
    }
    let bytes = match kind {
        ReportFormat::Svg => std::mem::take(&mut drawn.svg).into_bytes(),
        ReportFormat::Png => {
            let png = report::rasterise(&drawn.svg, &report::PngOptions { palette: args.palette })?;
            for n in &png.notes {
                super::ui::note(n);
            }
            png.bytes
        }
    };
    if stdout {
        if args.json {
            return Err(CliError::usage("--json prints on stdout: write the picture to a file"));
        }
        return super::write_stdout(&bytes);
    }
    write_all_atomically(&[(args.output.clone(), bytes)])?;
    if args.json {
        let mut text = serde_json::to_string_pretty(
            &serde_json::json!({ "output": args.output.display().to_string(), "report": &drawn }),
        )?;
        text.push('\n');
        return super::print_stdout(&text);
    }
    Ok(())
}
