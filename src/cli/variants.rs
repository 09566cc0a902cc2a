//! `smartmesh variants FAMILY -o DIR`: geometry variants with one topology and one set
//! of tags, as `.poly` files, and the manifest that `smartmesh batch` runs over them.
//!
//! Everything is checked before anything is written (parameters, the options of the
//! manifest, each geometry), then `DIR/NAME.poly` for every member and
//! `DIR/manifest.jsonl` are written as one set.

use std::path::{Component, Path, PathBuf};
use std::time::Instant;

use clap::{Args, Subcommand};
use serde_json::{Map, Value};
use smartmesh::batch::manifest;
use smartmesh::batch::variants::naca::{
    family, family_size, Layout, TrailingEdge, MAX_FAMILY_VERTICES, MAX_MEMBERS,
};
use smartmesh::batch::variants::{distributor, parse_values, Pslg};

use super::{ui, CliError};

/// Write geometry variants (.poly) that share their tags, and a manifest for `batch`.
#[derive(Debug, Args)]
#[command(
    after_help = "Each member is DIR/NAME.poly (a Triangle PSLG: point tags as vertex markers, \
curve tags as segment markers, the face tag as the region's attribute, tag names in its comment \
header), and DIR/manifest.jsonl has one line per member, {\"name\", \"input\", \"recipe\", \
\"options\"}, ready for `smartmesh batch DIR/manifest.jsonl -o OUT`. Every member has the same \
tags, so one recipe adapts all of them. The geometry is checked before anything is written: no \
crossing segments, a tagged point wherever two curves meet (exit 2 naming the member otherwise).

Examples:
  smartmesh variants naca --thickness 0.08:0.16:5 --camber 0,0.02 --camber-position 0.4 \\
      --recipe examples/naca0012-agard01/recipe.toml -o target/naca-family
  smartmesh batch target/naca-family/manifest.jsonl -o target/naca-runs --jobs 2
  smartmesh variants distributor --recipe examples/distributor/recipe.cfg -o target/distributors"
)]
pub(super) struct VariantsArgs {
    #[command(subcommand)]
    family: Family,
}

#[derive(Debug, Subcommand)]
enum Family {
    Naca(NacaArgs),
    Distributor(DistributorArgs),
}

/// What every family writes.
#[derive(Debug, Args)]
struct Common {
    /// The output directory (created if missing): NAME.poly and manifest.jsonl.
    #[arg(long, short = 'o')]
    output: PathBuf,
    /// The recipe every line of the manifest names (written relative to DIR).
    #[arg(long, short = 'r')]
    recipe: PathBuf,
    /// Adapt options for every line of the manifest, a JSON object as in a manifest
    /// (`{"max_iterations": 4, "hmin": 0.0005}`).
    #[arg(long, value_name = "JSON")]
    options: Option<String>,
}

/// NACA 4-digit airfoils in a circular far field, with the tags of
/// examples/naca0012-agard01 (points 11 LeadingEdge, 12 TrailingEdge; curves 1 Upper,
/// 2 Lower, 3 FarField; face 100 Fluid).
#[derive(Debug, Args)]
#[command(
    after_help = "Each of --thickness, --camber and --camber-position takes one value, a list \
A,B,C or a range A:B:N (N values from A to B, both included); the family is every combination \
(a member without camber once, whatever the positions), named naca-t0.12-m0.02-p0.4 \
(naca-t0.12-m0 without camber).

The profile is the NACA 4-digit definition: half thickness 5t(0.2969 sqrt(x) - 0.1260 x - \
0.3516 x^2 + 0.2843 x^3 - 0.1015 x^4) offset across the camber line m/p^2 (2px - x^2) before \
p and m/(1-p)^2 (1 - 2p + 2px - x^2) after, cosine-spaced stations. --trailing-edge extended \
(the default) takes the formula to the root of the thickness, x = 1.008930, where the surfaces \
meet: with --thickness 0.12 and no camber the vertices are those of \
examples/naca0012-agard01/geometry.poly. --trailing-edge closed uses -0.1036 for the last \
coefficient: chord 1, thickness 0 at x = 1. An open (blunt) trailing edge would add a curve \
and a point, and so change the tags; it is not offered."
)]
struct NacaArgs {
    /// Largest thickness over chord, t: A, A,B,C or A:B:N.
    #[arg(long, default_value = "0.12", allow_hyphen_values = true)]
    thickness: String,
    /// Largest camber over chord, m.
    #[arg(long, default_value = "0", allow_hyphen_values = true)]
    camber: String,
    /// Where the largest camber is, over chord, p (unused without camber).
    #[arg(long, default_value = "0.4", allow_hyphen_values = true)]
    camber_position: String,
    /// How the trailing edge closes.
    #[arg(long, value_enum, default_value_t = TrailingEdgeArg::Extended)]
    trailing_edge: TrailingEdgeArg,
    /// Segments per side of the airfoil.
    #[arg(long, default_value_t = 100)]
    per_side: usize,
    /// Radius of the far-field circle, in chords.
    #[arg(long, default_value_t = 25.0)]
    far_radius: f64,
    /// Vertices on the far-field circle.
    #[arg(long, default_value_t = 48)]
    far_points: usize,
    #[command(flatten)]
    common: Common,
}

#[derive(Debug, Clone, Copy, clap::ValueEnum)]
enum TrailingEdgeArg {
    Extended,
    Closed,
}

/// The three turbine distributors of examples/distributor (thesis 6.3.1): one stay vane,
/// a narrow, a thick and an S-shaped guide vane, the same tags.
#[derive(Debug, Args)]
struct DistributorArgs {
    /// Only these variants (1-narrow, 2-thick, 3-s-shaped), comma-separated.
    #[arg(long, value_delimiter = ',')]
    only: Vec<String>,
    #[command(flatten)]
    common: Common,
}

/// `smartmesh mesh`'s default corner angle, degrees.
const CORNER_ANGLE: f64 = 30.0;

/// The line naming the writer in each `.poly`.
const WRITER: &str = "Written by smartmesh variants (do not edit by hand).";

pub(super) fn run(args: VariantsArgs) -> Result<(), CliError> {
    let start = Instant::now();
    let (members, common) = match args.family {
        Family::Naca(a) => (naca_members(&a)?, a.common),
        Family::Distributor(a) => (distributor_members(&a)?, a.common),
    };
    write(&members, &common, start)
}

fn values(flag: &str, text: &str) -> Result<Vec<f64>, CliError> {
    parse_values(text).map_err(|e| CliError::usage(format!("--{flag}: {e}")))
}

fn naca_members(a: &NacaArgs) -> Result<Vec<(String, Pslg)>, CliError> {
    let trailing_edge = match a.trailing_edge {
        TrailingEdgeArg::Extended => TrailingEdge::Extended,
        TrailingEdgeArg::Closed => TrailingEdge::Closed,
    };
    let (t, m, p) = (
        values("thickness", &a.thickness)?,
        values("camber", &a.camber)?,
        values("camber-position", &a.camber_position)?,
    );
    // Every cap is checked on counts, before a member is built.
    let count = family_size(&t, &m, &p);
    if count > MAX_MEMBERS {
        return Err(CliError::usage(format!(
            "{count} members: at most {MAX_MEMBERS} in one family"
        )));
    }
    let layout =
        Layout { per_side: a.per_side, far_radius: a.far_radius, far_points: a.far_points };
    layout.check().map_err(CliError::usage)?;
    let vertices = (count as u64).saturating_mul(layout.vertices());
    if vertices > MAX_FAMILY_VERTICES {
        return Err(CliError::usage(format!(
            "{count} members of {} vertices each: {vertices} vertices, at most \
             {MAX_FAMILY_VERTICES} in one family (fewer members, --per-side or --far-points)",
            layout.vertices()
        )));
    }
    let members = family(&t, &m, &p, trailing_edge);
    members
        .iter()
        .map(|m| {
            let g =
                m.geometry(&layout).map_err(|e| CliError::usage(format!("{}: {e}", m.name())))?;
            Ok((m.name(), g))
        })
        .collect()
}

fn distributor_members(a: &DistributorArgs) -> Result<Vec<(String, Pslg)>, CliError> {
    let known: Vec<&str> = distributor::VARIANTS.iter().map(|v| v.name).collect();
    if let Some(bad) = a.only.iter().find(|n| !known.contains(&n.as_str())) {
        return Err(CliError::usage(format!(
            "--only: no variant `{bad}`; known: {}",
            known.join(", ")
        )));
    }
    Ok(distributor::VARIANTS
        .iter()
        .filter(|v| a.only.is_empty() || a.only.iter().any(|n| n == v.name))
        .map(|v| (v.name.to_string(), distributor::geometry(v)))
        .collect())
}

/// `path` relative to `base` (both absolute, canonical), or `path` itself when they
/// share no more than the root.
fn relative(path: &Path, base: &Path) -> PathBuf {
    let p: Vec<Component> = path.components().collect();
    let b: Vec<Component> = base.components().collect();
    let common = p.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common <= 1 {
        return path.to_path_buf();
    }
    let mut out = PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c);
    }
    out
}

fn write(members: &[(String, Pslg)], common: &Common, start: Instant) -> Result<(), CliError> {
    let options: Map<String, Value> = match &common.options {
        None => Map::new(),
        Some(text) => match serde_json::from_str(text) {
            Ok(Value::Object(o)) => o,
            Ok(_) | Err(_) => {
                return Err(CliError::usage(format!(
                    "--options `{text}`: expected a JSON object of adapt options, as {{\"max_iterations\": 4}}"
                )))
            }
        },
    };
    manifest::option_args(&options, &super::batch::adapt_options())
        .map_err(|e| CliError::usage(format!("--options: {e}")))?;
    let recipe = common
        .recipe
        .canonicalize()
        .map_err(|e| CliError::usage(format!("--recipe {}: {e}", common.recipe.display())))?;
    if !recipe.is_file() {
        return Err(CliError::usage(format!("--recipe {}: not a file", common.recipe.display())));
    }
    let mut files = Vec::new();
    let mut lines = String::new();
    let mut texts = Vec::new();
    for (name, g) in members {
        let text = g.write_poly(WRITER).map_err(|e| CliError::usage(format!("{name}: {e}")))?;
        if let Some((v, turn)) = g.sharpest_turn().filter(|&(_, t)| t > CORNER_ANGLE) {
            let p = g.vertices[v];
            ui::warn(&format!(
                "{name}: the boundary turns by {turn:.0} degrees at vertex {} ({}, {}): `mesh` and `adapt` make a corner point there, with a tag of its own (more vertices, --per-side, turn less)",
                v + 1,
                p[0],
                p[1]
            ));
        }
        texts.push((name, text));
    }
    if members.is_empty() {
        return Err(CliError::usage("no variant to write"));
    }
    std::fs::create_dir_all(&common.output).map_err(|e| {
        CliError::context(format!("creating the output directory {}", common.output.display()), e)
    })?;
    let dir = common.output.canonicalize().map_err(|e| {
        CliError::context(format!("the output directory {}", common.output.display()), e)
    })?;
    let recipe_text = relative(&recipe, &dir).to_string_lossy().into_owned();
    let options_text = Value::Object(options).to_string();
    for (name, text) in texts {
        let poly = format!("{name}.poly");
        lines.push_str(&format!(
            "{{\"name\": {}, \"input\": {}, \"recipe\": {}, \"options\": {options_text}}}\n",
            Value::from(name.as_str()),
            Value::from(poly.as_str()),
            Value::from(recipe_text.as_str()),
        ));
        files.push((common.output.join(&poly), text.into_bytes()));
    }
    let manifest_path = common.output.join("manifest.jsonl");
    files.push((manifest_path.clone(), lines.into_bytes()));
    smartmesh::formats::write_all_atomically(&files)
        .map_err(|e| CliError::context(format!("writing into {}", common.output.display()), e))?;
    ui::done(
        "variants",
        &format!(
            "wrote {} {} and {} in {}",
            members.len(),
            if members.len() == 1 { "geometry" } else { "geometries" },
            manifest_path.display(),
            ui::seconds(start.elapsed())
        ),
    );
    Ok(())
}
