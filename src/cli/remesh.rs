//! `smartmesh remesh MESH --metric M -o OUT`: the native anisotropic remesher, and
//! `--measure` to report how a mesh conforms to a metric without remeshing it (the same
//! measure for our output and another tool's). A mesh in space (tetrahedra, or with
//! `--adapter mmgs` a surface) goes to MMG, or with `--adapter gmsh` to Gmsh, through
//! `remesh_space`.

use std::path::PathBuf;
use std::time::Instant;

use clap::{Args, ValueEnum};
use smartmesh::formats::Format;
use smartmesh::remesh::{remesh_with_progress, BoundaryMode, RemeshEvent, RemeshOptions};
use smartmesh::Conformity;
use smartmesh::HistogramBins;
use smartmesh::SizeControls as MetricControls;
use smartmesh::{MetricError, MetricField};

use super::output::{check_output_dir, is_stdio, positive_size, shown, SizeControls};
use super::{parse_format, print_stdout, ui, CliError};
use smartmesh::{AdapterKind, AdapterOptions};

/// The remeshers of `remesh`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum RemesherArg {
    /// smartmesh's own remesher (planar meshes).
    Native,
    /// MMG's mmg3d_O3: tetrahedral meshes, to a 3D metric.
    Mmg3d,
    /// MMG's mmgs_O3: triangulated surfaces in space, to a 3D metric.
    Mmgs,
    /// Gmsh on a background view of a 3D metric: tetrahedra through MMG3D inside Gmsh
    /// (Mesh.Algorithm3D 7), a surface in space through BAMG (Mesh.Algorithm 7).
    Gmsh,
}

/// Boundary placement, as the command line names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Boundary {
    /// On the original boundary polylines.
    Polyline,
    /// On a smooth (C¹ cubic) reconstruction through the original boundary vertices,
    /// broken at corners (MMG's default).
    Smooth,
}

/// Adapt a triangle mesh to a metric field (split, collapse, swap, smooth in the metric).
#[derive(Debug, Args)]
#[command(
    after_help = "The metric is a 9-component (or 3-component m11 m12 m22) point array `metric` on \
MESH's vertices: in the file given with --metric (any file `smartmesh size` writes: a .vtu or .msh, \
a .mesh with its .sol beside it, a .sol/.solb alone in MESH's vertex order as mmg2d_O3 -sol takes it, \
or a Gmsh .pos view, taken at MESH's vertices), or in MESH itself when --metric is left out.

Boundary and interface vertices slide along their own curve, corners (topological points, and curve \
vertices turning by more than --ridge-angle) never move; face and curve tags are kept. New boundary \
vertices go on a smooth reconstruction of each curve between corners (straight sides stay straight; \
--boundary polyline keeps the input's polylines), and a coarsening never takes a boundary edge \
further than --hausd from its curve. The output \
carries the interpolated `metric` (a .mesh output writes it to the .sol beside it).

A mesh in space goes to MMG: a mesh with tetrahedra to mmg3d_O3 (chosen by itself; --adapter mmg3d \
says so), a triangulated surface in space to mmgs_O3 with --adapter mmgs (both found on PATH, or \
--adapter-program). Its metric is 3D, on MESH's vertices: a 3D .sol/.solb (m11 m12 m22 m13 m23 m33, \
as mmg3d_O3 -sol takes it), a mesh file with point data `metric` of 9 (row-major) or 6 (XX YY ZZ XY YZ \
XZ) components, or MESH's own (a .mesh with its .sol beside it). Tags and their names (Gmsh physical \
names) come back through MMG's references, topological points as required corners. MMG is run as \
`mmg3d_O3 -in in.mesh -sol in.sol -out out.mesh -v 1 [-hgrad G] [-hausd D] [-hmin H] [-hmax H] \
[-ar A] [-nr] [-nosurf] [--adapter-arg ...]`, from --hgrad, --hausd, --hmin, --hmax, --ridge-angle, \
--no-ridges, --nosurf (not for mmgs); the native remesher's other options do not apply. The result \
has no metric; --measure and --background are planar only.

--adapter gmsh remeshes a mesh in space with Gmsh (on PATH, or --adapter-program) to a .pos view of \
the metric: the mesh as a discrete model (CreateTopology; CreateGeometry;), its surfaces by BAMG \
(Mesh.Algorithm 7), its volume by MMG3D inside Gmsh (Mesh.Algorithm3D 7: Gmsh's only 3D algorithm \
that honours an anisotropic view; Delaunay, Frontal and HXT fill the volume from the surface mesh). \
Gmsh runs MMG3D with its own gradation (1.3) and the boundary frozen: measured on a Gmsh cube with \
a wall layer, 49.5% of the edges in [1/sqrt2, sqrt2] before, 72.8% after (mmg3d_O3: 30.2%, 83.3% \
with --hgrad -1). Of the MMG options it takes none; --adapter-arg goes on its command line. A mesh \
of several physical volumes is refused: Gmsh 4.15.2's MMG3D fails on volumes sharing a surface.

Examples:
  smartmesh size fixtures/cylinder.msh --recipe fixtures/cylinder.toml -o field.vtu
  smartmesh remesh fixtures/cylinder.msh --metric field.vtu -o adapted.vtu --json
  smartmesh remesh adapted.mesh --measure --json      # conformity of a mesh to its own .sol
  smartmesh remesh in.msh --metric field.vtu --recipe periodic.toml -o out.msh   # sides kept matched
  smartmesh remesh box.msh --metric box.sol -o box-adapted.mesh --hausd 0.01     # tetrahedra: mmg3d
  smartmesh remesh hull.mesh --adapter mmgs --metric hull.sol -o hull-adapted.mesh
  smartmesh remesh box.msh --adapter gmsh --metric box.sol -o box-gmsh.msh       # MMG3D inside Gmsh"
)]
#[command(mut_arg("recipe", |a| a.help("A recipe whose PERIODIC pairs the remeshing keeps matched (its sizing steps are not used: the metric is --metric's)")))]
pub(super) struct RemeshArgs {
    /// Input mesh (any readable format; `-` for stdin, with --from).
    mesh: PathBuf,
    /// A metric on MESH's vertices: a mesh file with point data `metric`, a .sol/.solb,
    /// or a .pos view.
    #[arg(long, short = 'm')]
    metric: Option<PathBuf>,
    /// Output mesh (any writable format; `-` for stdout, with --to); required unless
    /// --measure.
    #[arg(long, short = 'o', required_unless_present = "measure")]
    output: Option<PathBuf>,
    /// Split every quad of MESH into two triangles first and remesh them too (without
    /// it, a skin of quads is kept frozen: its cells and vertices unchanged, the
    /// triangles remeshed around it).
    #[arg(long)]
    split_quads: bool,
    /// Only measure MESH against the metric (share of edges in [1/√2, √2], metric quality).
    #[arg(long)]
    measure: bool,
    /// With --measure: take the metric from this mesh (the input of a remeshing, with its
    /// `metric`; a .pos view; a .sol beside its .mesh), interpolated at MESH's vertices,
    /// instead of MESH's own.
    #[arg(long, requires = "measure", conflicts_with = "metric")]
    background: Option<PathBuf>,
    /// Where boundary vertices go: on a smooth reconstruction of curved boundaries, or
    /// on the input's polylines.
    #[arg(long, value_enum, default_value = "smooth")]
    boundary: Boundary,
    /// Passes of split, collapse, swap and smooth at most.
    #[arg(long, default_value_t = RemeshOptions::default().max_passes)]
    max_passes: usize,
    /// Smoothing sweeps per pass.
    #[arg(long, default_value_t = RemeshOptions::default().smooth_sweeps)]
    smooth_sweeps: usize,
    /// A curve turning by more than this many degrees at a vertex makes it a corner (45
    /// when unset); with mmg3d/mmgs, MMG's -ar: the dihedral angle above which an edge is
    /// a ridge (MMG's default, also 45, when unset).
    #[arg(long)]
    ridge_angle: Option<f64>,
    /// The remesher: native for a planar mesh; mmg3d (chosen for a mesh with
    /// tetrahedra), mmgs (a surface in space) or gmsh (either) for a mesh in space.
    #[arg(long, value_enum)]
    adapter: Option<RemesherArg>,
    /// mmg3d/mmgs/gmsh: the executable, instead of the one found on PATH.
    #[arg(long)]
    adapter_program: Option<PathBuf>,
    /// mmg3d/mmgs/gmsh: an argument passed to the program as it is (repeat for several).
    #[arg(long = "adapter-arg", allow_hyphen_values = true, value_name = "ARG")]
    adapter_args: Vec<String>,
    /// mmg3d/mmgs: no ridge detection by angle (MMG's -nr).
    #[arg(long)]
    no_ridges: bool,
    /// mmg3d: leave the boundary surface as it is (MMG's -nosurf).
    #[arg(long)]
    nosurf: bool,
    /// Most vertices the output may have: the metric's complexity (the vertex count it
    /// asks for) is compared with this before any work, and the run is refused with exit
    /// status 2 above it (about 0.6 KB of memory per vertex).
    #[arg(long, default_value_t = smartmesh::remesh::DEFAULT_MAX_VERTICES)]
    max_vertices: usize,
    /// Threads for a large mesh, remeshed part by part (0: every core, or
    /// RAYON_NUM_THREADS). The output is the same whatever the count.
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Cut the mesh into parts remeshed in parallel when the metric asks for at least
    /// this many vertices (smaller meshes: the serial remesher).
    #[arg(long, default_value_t = smartmesh::remesh::DEFAULT_PARTITION_ABOVE)]
    partition_above: usize,
    /// Never cut the mesh into parts: the serial remesher whatever the size.
    #[arg(long, conflicts_with = "partition_above")]
    no_partition: bool,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    #[command(flatten)]
    controls: SizeControls,
    /// Largest distance between a curved boundary and its edges, as MMG's -hausd: limits
    /// the sizes along boundary curves by their curvature, and bounds how far a
    /// coarsening may take an edge from the curve (without it: only the coarsening,
    /// by 0.01 times the largest side of the mesh's bounding box).
    #[arg(long, value_parser = positive_size, help_heading = "Size controls")]
    hausd: Option<f64>,
    #[command(flatten)]
    output_format: super::MeshOutputArgs,
    /// The recipe whose periodic pairs are kept (its help is set above).
    #[command(flatten)]
    recipe: super::RecipeInput,
    /// Print the statistics (or the measure) as JSON on stdout.
    #[arg(long)]
    json: bool,
}

/// A metric that could not be had: an unreadable file keeps its own exit code, every
/// other fault is bad input (exit 2).
pub(super) fn metric_error(e: MetricError) -> CliError {
    e.into()
}

/// `--measure --json`: the figures and the edges of their histograms' bins.
#[derive(serde::Serialize)]
struct MeasureJson<'a> {
    #[serde(flatten)]
    conformity: &'a Conformity,
    histogram_bins: HistogramBins,
    /// What the reader could not keep, and the second-order cells made linear.
    read_notes: &'a [String],
}

/// The remesher's statistics as JSON, its `[vertices, triangles]` pairs named, with
/// the input's `read_notes` (what the reader could not keep, the cells made linear).
fn stats_json(
    stats: &smartmesh::remesh::RemeshStats,
    read_notes: &[String],
) -> Result<serde_json::Value, CliError> {
    let mut v = serde_json::to_value(stats)?;
    v["read_notes"] = serde_json::json!(read_notes);
    for key in ["input", "output"] {
        if let Some(pair) = v.get(key).and_then(|p| p.as_array()).filter(|p| p.len() == 2) {
            let named = serde_json::json!({ "vertices": pair[0], "triangles": pair[1] });
            v[key] = named;
        }
    }
    Ok(v)
}

/// Runs `remesh`.
pub(super) fn run(mut args: RemeshArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    // Checked before any input is read (a bad count is usage, whatever the input).
    super::set_threads(args.threads)?;
    let to = match &args.output {
        Some(o) if !args.measure => {
            if is_stdio(o) && args.json {
                return Err(CliError::usage(
                    "--json prints on stdout, which `-o -` already uses for the mesh",
                ));
            }
            let to = args.output_format.mesh_format(o)?;
            check_output_dir(o)?;
            Some(to)
        }
        _ => None,
    };
    let from = args.from.or_else(|| Format::from_path(&args.mesh));
    let (mut mesh, read_notes) = super::read_linear_mesh_noted(&args.mesh, from)?;
    if let Some(kind) = space_remesher(&args, &mesh) {
        return space(args, mesh, kind, read_notes, to, t0);
    }
    let plane_z = planar_input(&args, &mesh)?;
    if args.split_quads {
        let n = mesh.split_quads();
        ui::note(&format!("split {n} quads into {} triangles", 2 * n));
    }
    let mut metric = match &args.background {
        Some(b) => {
            match MetricField::read_background(b, &mesh, &args.mesh).map_err(metric_error)? {
                (Some(bmesh), bfield) => {
                    let pts: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
                    bfield
                        .interpolate(&bmesh, &pts)
                        .map_err(|e| CliError::input(format!("{}: {e}", b.display()), e))?
                }
                // A data-only file: already on the mesh's vertices.
                (None, field) => field,
            }
        }
        None => match args.metric.as_deref() {
            Some(p) => MetricField::read(p, None, &mesh, &args.mesh),
            None => MetricField::own(&mesh, &args.mesh),
        }
        .map_err(metric_error)?,
    }
    .into_tensors();
    let controls = MetricControls {
        h_min: args.controls.hmin,
        h_max: args.controls.hmax,
        gradation: args.controls.hgrad.filter(|&g| g >= 1.0),
        hausd: args.hausd,
    };
    controls.apply(&mesh, &mut metric).map_err(|e| {
        CliError::context(format!("{}: applying the size controls: {e}", args.mesh.display()), e)
    })?;
    if args.measure {
        let c = Conformity::of_mesh(&mesh, &metric).ok_or_else(|| {
            CliError::usage(format!("{}: no triangles to measure", args.mesh.display()))
        })?;
        let text = if args.json {
            serde_json::to_string_pretty(&MeasureJson {
                conformity: &c,
                histogram_bins: HistogramBins::standard(),
                read_notes: &read_notes,
            })? + "\n"
        } else {
            format!(
                "{} edges, {:.1}% in [1/√2, √2], metric length {} to {} (mean {}); {} triangles, metric quality mean {:.3}, min {:.3}\n",
                c.edges,
                100.0 * c.conforming_share,
                ui::sig(c.edge_length_range[0]),
                ui::sig(c.edge_length_range[1]),
                ui::sig(c.mean_edge_length),
                c.triangles,
                c.mean_quality,
                c.min_quality
            )
        };
        return print_stdout(&text);
    }
    let (Some(output), Some(to)) = (args.output.as_deref(), to) else {
        return Err(CliError::usage("-o OUT is required unless --measure"));
    };
    let pairs: Vec<smartmesh::periodic::PeriodicPair> = match &args.recipe.recipe {
        None => Vec::new(),
        Some(_) => args.recipe.read()?.periodic_pairs(),
    };
    smartmesh::periodic::check_all(&mesh, &pairs)
        .map_err(|e| CliError::usage(format!("{e} (input {})", args.mesh.display())))?;
    let opts = RemeshOptions {
        periodic: pairs.clone(),
        max_passes: args.max_passes,
        boundary: match args.boundary {
            Boundary::Polyline => BoundaryMode::Polyline,
            Boundary::Smooth => BoundaryMode::Smooth,
        },
        ridge_angle_degrees: args
            .ridge_angle
            .unwrap_or(RemeshOptions::default().ridge_angle_degrees),
        hausd: args.hausd,
        smooth_sweeps: args.smooth_sweeps,
        max_vertices: Some(args.max_vertices),
        partition: (!args.no_partition).then_some(smartmesh::remesh::Partitioning {
            above: args.partition_above,
            ..Default::default()
        }),
        // The conformity is shown only in the JSON summary: measure it only then.
        measure: args.json,
        ..RemeshOptions::default()
    };
    let bar =
        ui::progress_bar(opts.max_passes as u64, "{bar:30} pass {pos}/{len} {msg} [{elapsed}]");
    let mut observe = |e: RemeshEvent| {
        if let (Some(b), RemeshEvent::Pass { pass, of, triangles }) = (&bar, e) {
            b.set_length(of as u64);
            b.set_position(pass as u64);
            b.set_message(format!("{triangles} triangles"));
        }
    };
    let remeshed = remesh_with_progress(&mesh, &metric, &opts, &mut observe);
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let mut out =
        remeshed.map_err(|e| CliError::context(format!("{}: {e}", args.mesh.display()), e))?;
    smartmesh::place(&mut out.mesh, plane_z);
    for w in &out.stats.warnings {
        ui::warn(w);
    }
    for m in smartmesh::periodic::check_all(&out.mesh, &pairs)
        .map_err(|e| CliError::context(format!("{e} (result)"), e))?
    {
        ui::note(&m.to_string());
    }
    args.output_format.periodic_from_recipe(to, &out.mesh, &pairs)?;
    args.output_format.write(output, &out.mesh, to)?;
    if args.json {
        let mut text = serde_json::to_string_pretty(&stats_json(&out.stats, &read_notes)?)?;
        text.push('\n');
        print_stdout(&text)?;
    }
    ui::done(
        "remesh",
        &format!(
            "wrote {} ({} points, {} triangles, from {} points, {} triangles) in {}",
            shown(output),
            out.mesh.points.len(),
            out.mesh.num_cells_of(smartmesh::formats::CellKind::Triangle),
            mesh.points.len(),
            mesh.num_cells_of(smartmesh::formats::CellKind::Triangle),
            ui::seconds(t0.elapsed())
        ),
    );
    Ok(())
}

/// The plane z = const of a mesh the native remesher takes (bad input, naming the MMG
/// remeshers, when it is a mesh in space), with no option of theirs given.
fn planar_input(args: &RemeshArgs, mesh: &smartmesh::formats::TaggedMesh) -> Result<f64, CliError> {
    let plane_z = smartmesh::plane(mesh).map_err(|e| {
        CliError::usage(format!(
            "{}: {e}; a mesh in space goes to MMG: --adapter mmg3d (tetrahedra) or mmgs (a surface)",
            super::input_name(&args.mesh)
        ))
    })?;
    let mmg_only = [
        ("--adapter-program", args.adapter_program.is_some()),
        ("--adapter-arg", !args.adapter_args.is_empty()),
        ("--no-ridges", args.no_ridges),
        ("--nosurf", args.nosurf),
    ];
    if let Some((option, _)) = mmg_only.iter().find(|o| o.1) {
        return Err(CliError::usage(format!("{option} is an option of the mmg3d and mmgs remeshers (a mesh in space); the native remesher does not take it")));
    }
    Ok(plane_z)
}

/// The remesher in space a mesh goes to: the one asked for (mmg3d, mmgs, gmsh), else
/// mmg3d for a mesh with volume cells; `None`: the native remesher.
fn space_remesher(args: &RemeshArgs, mesh: &smartmesh::formats::TaggedMesh) -> Option<AdapterKind> {
    match args.adapter {
        Some(RemesherArg::Mmg3d) => Some(AdapterKind::Mmg3d),
        Some(RemesherArg::Mmgs) => Some(AdapterKind::Mmgs),
        Some(RemesherArg::Gmsh) => Some(AdapterKind::Gmsh),
        Some(RemesherArg::Native) => None,
        None => mesh
            .blocks
            .iter()
            .any(|b| b.kind.dim() == 3 && !b.is_empty())
            .then_some(AdapterKind::Mmg3d),
    }
}

/// `remesh` of a mesh in space through MMG ([`super::remesh_space`]).
fn space(
    args: RemeshArgs,
    mesh: smartmesh::formats::TaggedMesh,
    kind: AdapterKind,
    read_notes: Vec<String>,
    to: Option<Format>,
    t0: Instant,
) -> Result<(), CliError> {
    let planar_only = [
        ("--measure", args.measure),
        ("--background", args.background.is_some()),
        ("--recipe", args.recipe.recipe.is_some()),
        ("--split-quads", args.split_quads),
    ];
    if let Some((option, _)) = planar_only.iter().find(|o| o.1) {
        return Err(CliError::usage(format!(
            "{option} is planar only; {} is remeshed in space by {}",
            super::input_name(&args.mesh),
            kind.name()
        )));
    }
    if kind == AdapterKind::Gmsh && args.hausd.is_some() {
        return Err(CliError::usage(format!(
            "--hausd is MMG's -hausd in space (--adapter mmg3d|mmgs); Gmsh takes no such bound on {}",
            super::input_name(&args.mesh)
        )));
    }
    if kind == AdapterKind::Gmsh && args.hausd.is_some() {
        return Err(CliError::usage(format!(
            "--hausd is MMG's -hausd in space (--adapter mmg3d|mmgs); Gmsh takes no such bound on {}",
            super::input_name(&args.mesh)
        )));
    }
    let (Some(output), Some(to)) = (args.output.as_deref(), to) else {
        return Err(CliError::usage("-o OUT is required"));
    };
    let options = AdapterOptions {
        program: args.adapter_program.clone(),
        hgrad: args.controls.hgrad,
        hausd: args.hausd,
        nosurf: args.nosurf,
        hmin: args.controls.hmin,
        hmax: args.controls.hmax,
        ridge_angle: args.ridge_angle,
        no_ridges: args.no_ridges,
        extra_args: args.adapter_args.clone(),
        ..AdapterOptions::default()
    };
    super::remesh_space::run(super::remesh_space::SpaceRemesh {
        mesh,
        mesh_path: &args.mesh,
        metric: args.metric.as_deref(),
        output,
        to,
        output_format: &args.output_format,
        kind,
        options,
        json: args.json,
        read_notes,
        t0,
    })
}
