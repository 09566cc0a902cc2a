//! `smartmesh mesh IN -o OUT`: the starting mesh of a planar straight-line graph
//! (constrained Delaunay triangulation with quality refinement), written in any format.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use smartmesh::formats::triangle::poly_lines;
use smartmesh::formats::Format;
use smartmesh::mesher::{triangulate_periodic, MeshError, MeshOptions, Subject};
use smartmesh::QualitySummary;
use smartmesh::Topology;

use super::output::{check_output_dir, is_stdio, shown};
use super::{parse_format, print_stdout, ui, CliError};

/// Mesh a planar straight-line graph: constrained Delaunay triangulation with quality
/// refinement (Triangle's `-pq`, by spade).
#[derive(Debug, Args)]
#[command(mut_arg("recipe", |a| a.help("A recipe whose PERIODIC pairs are meshed matched vertex to vertex (its sizing steps are not used)")))]
#[command(
    after_help = "IN is a Triangle .poly (segments with boundary markers, holes, regions with \
attributes and area bounds) or any mesh whose Line cells are the boundary (its triangles are not \
meshed again: their centroids say which parts are inside and which face tag they get; what they do \
not reach is carved, as a hole).

The output has counter-clockwise triangles tagged with their regional attribute (0 outside every \
region), each input segment as Line cells with its marker, and Vertex cells at the corners (where \
the marker changes, where other than two segments meet, where the boundary turns by more than \
--corner-angle), so that `smartmesh info` and recipes see the same curves and points.

With --recipe, the recipe's PERIODIC pairs are meshed matched: each side must be the other's \
image by its transform (exit 2 naming the pair otherwise), each side's vertices are inserted into \
the other's segments at their exact images, and where the refinement splits a segment of one side \
only, its new vertices go to both sides and the graph is meshed again; every slave vertex is then \
the image of a master vertex (to rounding). The recipe's sizing steps are not used.

--size H is the area bound sqrt(3)/4*H^2 (the equilateral triangle of side H). Region area bounds \
in the .poly are honoured. The minimum angle is guaranteed except next to smaller input angles; \
20.7 degrees always terminates, up to about 30 usually does.

Examples:
  smartmesh mesh fixtures/square_hole.poly -o square.msh
  smartmesh mesh fixtures/naca0012.poly -o naca.vtu --min-angle 30 --max-area 0.001
  smartmesh mesh fixtures/cylinder.msh -o remeshed.mesh --size 0.02 --json
  smartmesh mesh box.poly -o box.1.node --keep-convex-hull      # Triangle's -pqc
  smartmesh mesh channel.poly --recipe periodic.toml -o channel.msh   # periodic sides matched"
)]
pub(super) struct MeshArgs {
    /// Input graph: a .poly, or any mesh with Line cells (`-` for stdin, with --from).
    input: PathBuf,
    /// Output mesh, any writable format (`-` for stdout, with --to).
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// Smallest angle of every triangle, degrees (0 to 34; 0: no angle refinement;
    /// Triangle's `q`).
    #[arg(long, visible_alias = "quality", default_value_t = 20.7)]
    min_angle: f64,
    /// Largest triangle area (Triangle's `a`).
    #[arg(long, visible_alias = "area")]
    max_area: Option<f64>,
    /// Uniform target edge length H, the largest size (area bound sqrt(3)/4*H^2).
    #[arg(long, visible_alias = "hmax")]
    size: Option<f64>,
    /// Keep the whole convex hull instead of carving outside the segments (Triangle's `c`).
    #[arg(long)]
    keep_convex_hull: bool,
    /// A boundary vertex where the boundary turns by more than this (degrees) is a corner.
    #[arg(long, default_value_t = 30.0)]
    corner_angle: f64,
    /// Most vertices refinement may create before it stops with an error (exit 1).
    /// Area bounds asking for more than the larger of this and 5000000 vertices are
    /// refused before refining (exit 2, with the estimate).
    #[arg(long)]
    max_vertices: Option<usize>,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    #[command(flatten)]
    output_format: super::MeshOutputArgs,
    /// The recipe whose periodic pairs are kept (its help is set above).
    #[command(flatten)]
    recipe: super::RecipeInput,
    /// Print a JSON summary on stdout.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct MeshSummary<'a> {
    input: String,
    output: String,
    points: usize,
    triangles: usize,
    lines: usize,
    corners: usize,
    curves: usize,
    faces: usize,
    area_bound: Option<f64>,
    min_angle_bound: f64,
    quality: Option<QualitySummary>,
    dropped: &'a [String],
    periodic: Vec<smartmesh::periodic::PairMatch>,
}

/// The line of the `.poly` record a meshing error is about, when the input is a `.poly`
/// file (not stdin) that lists it.
fn poly_line(args: &MeshArgs, from: Option<Format>, e: &MeshError) -> Option<u64> {
    let is_poly = from == Some(Format::Triangle)
        && args.input.extension().is_some_and(|x| x.eq_ignore_ascii_case("poly"));
    if !is_poly {
        return None;
    }
    let lines = poly_lines(&std::fs::read(&args.input).ok()?);
    match e.subject()? {
        Subject::Point(i) => lines.vertices.get(i),
        Subject::Segment(k) => lines.segments.get(k.checked_sub(1)?),
        Subject::Hole(k) => lines.holes.get(k.checked_sub(1)?),
        Subject::Region(k) => lines.regions.get(k.checked_sub(1)?),
    }
    .copied()
}

/// Runs `mesh`.
pub(super) fn run(mut args: MeshArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    if args.output.as_os_str() == "-" && args.json {
        return Err(CliError::usage(
            "--json prints on stdout, which `-` already uses for the mesh",
        ));
    }
    if is_stdio(&args.input) && args.recipe.is_stdin() {
        return Err(CliError::usage("the mesh and the recipe cannot both come from stdin"));
    }
    let opts = MeshOptions {
        min_angle_deg: args.min_angle,
        max_area: args.max_area,
        size: args.size,
        keep_convex_hull: args.keep_convex_hull,
        corner_angle_deg: args.corner_angle,
        max_vertices: args.max_vertices,
    };
    opts.validate().map_err(|e| CliError::context(e.to_string(), e))?;
    let to = args.output_format.mesh_format(&args.output)?;
    check_output_dir(&args.output)?;
    let from = args.from.or_else(|| Format::from_path(&args.input));
    let (pslg, plane_z) = super::read_planar_mesh(&args.input, from)?;
    let pairs: Vec<smartmesh::periodic::PeriodicPair> = match &args.recipe.recipe {
        None => Vec::new(),
        Some(_) => args.recipe.read()?.periodic_pairs(),
    };
    let mut mesh = triangulate_periodic(&pslg, &opts, &pairs).map_err(|e| {
        let at = match poly_line(&args, from, &e) {
            Some(line) => format!("{}:{line}", args.input.display()),
            None => args.input.display().to_string(),
        };
        // The library names its option; the command line has a switch for it.
        let hint = if matches!(e, MeshError::NothingToMesh) {
            " (on the command line: --keep-convex-hull)"
        } else {
            ""
        };
        CliError::context(format!("{at}: {e}{hint}"), e)
    })?;
    smartmesh::place(&mut mesh, plane_z);
    let periodic = smartmesh::periodic::check_all(&mesh, &pairs)
        .map_err(|e| CliError::context(format!("{e} (result)"), e))?;
    for m in &periodic {
        ui::note(&m.to_string());
    }
    args.output_format.periodic_from_recipe(to, &mesh, &pairs)?;
    let report = args.output_format.write(&args.output, &mesh, to)?;
    let count = |k| mesh.num_cells_of(k);
    // The topology and the whole quality summary only for --json; the one-line report
    // needs the smallest angle alone, and a quiet run nothing.
    let mut smallest = None;
    if args.json {
        let topo = Topology::from_mesh(&mesh);
        let quality = QualitySummary::of(&mesh.points, &topo);
        smallest = quality.as_ref().map(|q| q.min_angle_deg);
        let s = MeshSummary {
            input: args.input.display().to_string(),
            output: args.output.display().to_string(),
            points: mesh.points.len(),
            triangles: count(smartmesh::formats::CellKind::Triangle),
            lines: count(smartmesh::formats::CellKind::Line),
            corners: count(smartmesh::formats::CellKind::Vertex),
            curves: topo.curves.len(),
            faces: topo.faces.len(),
            area_bound: opts.area_bound(),
            min_angle_bound: opts.min_angle_deg,
            quality,
            dropped: &report.dropped,
            periodic,
        };
        let mut text = serde_json::to_string_pretty(&s)?;
        text.push('\n');
        print_stdout(&text)?;
    }
    if ui::level() == ui::Level::Quiet {
        return Ok(());
    }
    let angle = smallest
        .or_else(|| QualitySummary::smallest_angle_deg(&mesh))
        .map(|a| format!(", smallest angle {a:.1} deg"))
        .unwrap_or_default();
    ui::done(
        "mesh",
        &format!(
            "wrote {} ({} points, {} triangles{angle}) in {}",
            shown(&args.output),
            mesh.points.len(),
            count(smartmesh::formats::CellKind::Triangle),
            ui::seconds(t0.elapsed())
        ),
    );
    Ok(())
}
