//! `smartmesh layer MESH --curves C -o OUT`: a structured skin of quads along curves of a
//! triangle mesh (thesis 5.4.2), the triangles pushed away.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use smartmesh::formats::Format;
use smartmesh::layer::stats::{quad_quality, QuadQuality};
use smartmesh::layer::to_metric::band_to_metric;
use smartmesh::layer::{insert, Growth, LayerReport};
use smartmesh::periodic::PairMatch;
use smartmesh::recipe::{CurveValues, EntityRef, LayerSpec, SpecError};
use smartmesh::remesh::RemeshOptions;
use smartmesh::MetricField;

use super::output::{check_output_dir, is_stdio, shown};
use super::{parse_format, print_stdout, ui, CliError};

/// Insert a structured boundary-layer skin of quadrilaterals along curves of a triangle mesh.
#[derive(Debug, Args)]
#[command(
    after_help = "The heights: any three of --first-height, --ratio, --layers, --thickness fix the \
fourth (the ratio is 1.2 when only two of the others are given). --y-plus with --reynolds and \
--ref-length gives the first height from the flat-plate skin friction at that Reynolds number \
(Blasius's laminar correlation below 5e5, White's turbulent one above).

The triangles in the skin's way are removed and the band between the skin's outer front and the \
rest of the mesh is triangulated again, conforming to both (and, with --metric, remeshed to that \
metric, the skin and the kept mesh frozen); curve, face and point tags stay; the \
skin's cells take the face tags of the triangles they replace (--tag sets their geometrical tag \
apart). Convex corners get a fan (one column per --fan-angle degrees of turn); an open wall ending \
on another boundary slides its side along it; where the gap in front of a wall is narrow, or fronts \
would meet, the skin is thinned (first height kept while the ratio can drop to 1) and the command \
says where and by how much. The result is checked (positive Jacobian at every quad corner, no \
overlap, no hanging node) before it is written.

With --recipe, the recipe's PERIODIC pairs are kept matched: the input's sides must be images of \
each other (exit 2 naming the pair otherwise; slave vertices within 1e-6 of the diagonal of the \
master's images are moved onto them), and a skin whose side slides along one periodic side but not \
alike along its image (a wall ends on one side and not at the image place on the other) is refused \
with exit 2, nothing written. A wall ending on both sides at image places (the bottom of a \
periodic channel) slides alike along both and keeps the match.

Writes quads to .msh, .vtk, .vtu, .mesh and .obj; Triangle and glTF outputs get two triangles per \
quad (--split does it for every format).

Examples:
  smartmesh layer fixtures/cylinder.msh --curves Cylinder --first-height 0.002 --ratio 1.2 \\
      --layers 8 -o target/cylinder-skin.msh
  smartmesh layer naca.msh --curves 4 --y-plus 1 --reynolds 5000 --ref-length 1 --layers 12 \\
      --thickness 0.05 -o naca-skin.vtu --json
  smartmesh layer channel.msh --curves Bottom --first-height 0.01 --ratio 1.2 --layers 5 \\
      --recipe periodic.toml -o channel-skin.msh     # periodic sides kept matched"
)]
#[command(mut_arg("recipe", |a| a.help("A recipe whose PERIODIC pairs the skin must keep matched (its sizing steps and LAYER section are not used)")))]
pub(super) struct LayerArgs {
    /// Input triangle mesh (any readable format; `-` for stdin, with --from).
    mesh: PathBuf,
    /// Output mesh (any writable format; `-` for stdout, with --to).
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// The wall curves, by tag or name, comma-separated.
    #[arg(long, value_delimiter = ',', required = true)]
    curves: Vec<String>,
    /// Height of the first cell at the wall.
    #[arg(long, conflicts_with = "y_plus")]
    first_height: Option<f64>,
    /// Growth ratio of each layer's height over the one below.
    #[arg(long)]
    ratio: Option<f64>,
    /// Number of layers.
    #[arg(long)]
    layers: Option<usize>,
    /// Total thickness of the skin.
    #[arg(long)]
    thickness: Option<f64>,
    /// First height from this y+ (with --reynolds and --ref-length).
    #[arg(long, requires_all = ["reynolds", "ref_length"])]
    y_plus: Option<f64>,
    /// Reynolds number over the reference length (for --y-plus).
    #[arg(long)]
    reynolds: Option<f64>,
    /// Reference length of the Reynolds number (for --y-plus).
    #[arg(long)]
    ref_length: Option<f64>,
    /// Per-curve first height, CURVE=H0 (repeatable); other curves take --first-height.
    #[arg(long, value_name = "CURVE=H0")]
    curve_height: Vec<String>,
    /// Per-curve ratio, CURVE=R (repeatable).
    #[arg(long, value_name = "CURVE=R")]
    curve_ratio: Vec<String>,
    /// Write each quad as two triangles.
    #[arg(long)]
    split: bool,
    /// Geometrical (elementary) tag of the skin's cells; their physical tag stays the
    /// face's.
    #[arg(long)]
    tag: Option<i32>,
    /// Largest angle between two columns of a convex corner's fan, degrees.
    #[arg(long, default_value_t = 30.0)]
    fan_angle: f64,
    /// Largest share of the gap in front of a wall that the skin may fill.
    #[arg(long, default_value_t = 0.4)]
    gap_ratio: f64,
    /// A metric on MESH's vertices (any file `remesh --metric` reads): the band between
    /// the skin's front and the kept mesh is remeshed to it, the skin and the kept mesh
    /// frozen (without it the band keeps the sizes of the kept vertices).
    #[arg(long, short = 'm')]
    metric: Option<PathBuf>,
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
struct Summary<'a> {
    input: String,
    output: String,
    growth: Vec<(String, Growth)>,
    report: &'a LayerReport,
    quality: Option<QuadQuality>,
    dropped: &'a [String],
    periodic: Vec<PairMatch>,
}

fn per_curve(items: &[String], what: &str) -> Result<Vec<(String, f64)>, CliError> {
    items
        .iter()
        .map(|s| {
            let (c, v) = s.split_once('=').ok_or_else(|| {
                CliError::usage(format!("--curve-{what} `{s}`: expected CURVE=VALUE"))
            })?;
            let v: f64 = v.trim().parse().map_err(|_| {
                CliError::usage(format!("--curve-{what} `{s}`: `{v}` is not a number"))
            })?;
            Ok((c.trim().to_string(), v))
        })
        .collect()
}

/// A curve of --curves as the layer spec names it: a tag when the text is one as
/// written, else a name (`04` stays the text the user gave).
fn curve_ref(c: &str) -> EntityRef {
    match c.parse::<i32>() {
        Ok(t) if t.to_string() == c => EntityRef::Tag(t),
        _ => EntityRef::Name(c.to_string()),
    }
}

/// The text of [`curve_ref`]'s curve.
/// The skin the flags describe. A curve given twice by --curve-height (or --curve-ratio)
/// takes the last value; a curve --curves does not list comes first, in the flags' order,
/// for the spec to refuse.
fn layer_spec(args: &LayerArgs) -> Result<LayerSpec, CliError> {
    let heights = per_curve(&args.curve_height, "height")?;
    let ratios = per_curve(&args.curve_ratio, "ratio")?;
    let last = |list: &[(String, f64)], c: &str| list.iter().rev().find(|x| x.0 == c).map(|x| x.1);
    let mut values: Vec<CurveValues> = heights
        .iter()
        .map(|(c, h)| CurveValues { curve: curve_ref(c), first_height: Some(*h), ratio: None })
        .chain(ratios.iter().map(|(c, r)| CurveValues {
            curve: curve_ref(c),
            first_height: None,
            ratio: Some(*r),
        }))
        .filter(|v| !args.curves.contains(&v.curve.label()))
        .collect();
    for c in &args.curves {
        let (h, r) = (last(&heights, c), last(&ratios, c));
        if h.is_some() || r.is_some() {
            values.push(CurveValues { curve: curve_ref(c), first_height: h, ratio: r });
        }
    }
    Ok(LayerSpec {
        curves: args.curves.iter().map(|c| curve_ref(c)).collect(),
        first_height: args.first_height,
        ratio: args.ratio,
        layers: args.layers,
        thickness: args.thickness,
        y_plus: args.y_plus,
        reynolds: args.reynolds,
        ref_length: args.ref_length,
        split: args.split,
        tag: args.tag,
        fan_angle: Some(args.fan_angle),
        gap_ratio: Some(args.gap_ratio),
        per_curve: values,
    })
}

/// Runs `layer`.
pub(super) fn run(mut args: LayerArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    if args.output.as_os_str() == "-" && args.json {
        return Err(CliError::usage(
            "--json prints on stdout, which `-` already uses for the mesh",
        ));
    }
    if is_stdio(&args.mesh) && args.recipe.is_stdin() {
        return Err(CliError::usage("the mesh and the recipe cannot both come from stdin"));
    }
    let opts = layer_spec(&args)?.layer_options().map_err(|e| match e {
        SpecError::YPlus(e) => CliError::input(format!("--y-plus: {e}"), e),
        SpecError::PerCurve(c) => CliError::usage(format!(
            "per-curve value for `{}`, which --curves does not list",
            c.label()
        )),
        SpecError::Curve(c, e) => CliError::input(format!("curve `{}`: {e}", c.label()), e),
        e => CliError::usage(e.to_string()),
    })?;
    let to = args.output_format.mesh_format(&args.output)?;
    check_output_dir(&args.output)?;
    let from = args.from.or_else(|| Format::from_path(&args.mesh));
    let (mut mesh, plane_z) = super::read_planar_mesh(&args.mesh, from)?;
    let pairs = match &args.recipe.recipe {
        None => Vec::new(),
        Some(_) => args.recipe.read()?.periodic_pairs(),
    };
    let sides = super::periodic_sides(&mut mesh, &pairs, &args.mesh)?;
    let metric = match &args.metric {
        Some(p) => Some(
            MetricField::read(p, None, &mesh, &args.mesh)
                .map_err(|e| CliError::context(e.to_string(), e))?
                .into_tensors(),
        ),
        None => None,
    };
    let mut layered = insert(&mesh, &opts)
        .map_err(|e| CliError::context(format!("{}: {e}", args.mesh.display()), e))?;
    if let Some(m) = &metric {
        layered = band_to_metric(&mesh, m, layered, &RemeshOptions::default())
            .map_err(|e| CliError::context(format!("{}: {e}", args.mesh.display()), e))?;
    }
    let checked = sides
        .recheck(&layered.mesh)
        .map_err(|e| CliError::context(format!("{e} (the mesh with its skin)"), e))?;
    for (k, a) in checked.after.iter().enumerate() {
        if checked.broken == Some(k) {
            let b = &sides.before[k];
            return Err(CliError::usage(format!(
                "{a}: the skin's side slides along one periodic side and not alike along the \
                 other ({} vertices more on the master side, {} on the slave side): a wall \
                 ends on one side where the image of its end is not the end of a wall alike; \
                 nothing written (take that wall out of --curves, or give both sides walls \
                 that end at image places)",
                a.master_vertices.saturating_sub(b.master_vertices),
                a.slave_vertices.saturating_sub(b.slave_vertices)
            )));
        }
        ui::note(&a.to_string());
    }
    smartmesh::place(&mut layered.mesh, plane_z);
    args.output_format.periodic_from_recipe(to, &layered.mesh, &pairs)?;
    let written = args.output_format.write(&args.output, &layered.mesh, to)?;
    let r = &layered.report;
    for n in &r.notes {
        ui::note(n);
    }
    if !r.thinned.is_empty() {
        let worst =
            r.thinned.iter().min_by(|a, b| a.factor.total_cmp(&b.factor)).expect("not empty");
        ui::warn(&format!(
            "thinned {} of {} columns; most at ({}, {}): {} of the {} asked ({}); --json lists each",
            r.thinned.len(),
            r.columns,
            ui::sig(worst.at[0]),
            ui::sig(worst.at[1]),
            ui::sig(worst.thickness),
            ui::sig(worst.nominal),
            worst.reason
        ));
    }
    if args.json {
        // The quads' quality is a walk of the whole mesh: only for the summary.
        let quality = quad_quality(&layered.mesh);
        let s = Summary {
            input: args.mesh.display().to_string(),
            output: args.output.display().to_string(),
            growth: opts.curves.iter().map(|c| (c.curve.label(), c.growth)).collect(),
            report: r,
            quality,
            dropped: &written.dropped,
            periodic: checked.after,
        };
        let mut text = serde_json::to_string_pretty(&s)?;
        text.push('\n');
        print_stdout(&text)?;
    }
    ui::done(
        "layer",
        &format!(
            "wrote {} ({} layers, {} quads, {} skin triangles; {} triangles replaced by {}) in {}",
            shown(&args.output),
            r.layers,
            r.quads,
            r.skin_triangles,
            r.removed_triangles,
            r.band_triangles,
            ui::seconds(t0.elapsed())
        ),
    );
    Ok(())
}
