//! `smartmesh recipe check RECIPE MESH` and `smartmesh recipe convert IN OUT`.

use std::fmt::Write as _;
use std::io::Read as _;
use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use smartmesh::adapt::{starting_mesh, StartError};
use smartmesh::formats::{write_all_atomically, Format};
use smartmesh::recipe::{ReadOptions, Recipe, RecipeError, RecipeFormat, RegionReport};
use smartmesh::sizing::{Algorithm, EntitySet};
use smartmesh::Topology;

use super::{parse_format, print_stdout, CliError};

/// Sizing recipes: check one against a mesh, or convert it between libconfig, TOML and JSON.
#[derive(Debug, Args)]
pub(super) struct RecipeArgs {
    #[command(subcommand)]
    command: RecipeCommand,
}

#[derive(Debug, Subcommand)]
enum RecipeCommand {
    Check(CheckArgs),
    Convert(ConvertArgs),
}

fn parse_recipe_format(name: &str) -> Result<RecipeFormat, String> {
    RecipeFormat::from_name(name).ok_or_else(|| {
        format!("unknown recipe format `{name}`; known: libconfig (cfg), toml, json")
    })
}

/// How a command reads its recipe (flattened into every command that takes one).
#[derive(Debug, Clone, Copy, Args)]
pub(crate) struct RecipeReadArgs {
    /// Read the recipe as data, for one you did not write: no C preprocessor and no
    /// @include (both read any file the recipe names); a directive or an @include is then
    /// an error.
    #[arg(long)]
    no_preprocess: bool,
}

impl RecipeReadArgs {
    /// The library's reading options.
    pub(crate) fn options(self) -> ReadOptions {
        if self.no_preprocess {
            ReadOptions::untrusted()
        } else {
            ReadOptions::default()
        }
    }

    /// Reads the recipe at `path` (its extension tells the format).
    pub(crate) fn read(self, path: &Path) -> Result<Recipe, RecipeError> {
        Recipe::from_path_with(path, &self.options())
    }
}

/// Read a recipe, resolve it against a mesh and print how each region and algorithm
/// resolved: the topological entities, their tags and names, the mesh vertices and
/// edges they hold. Exit status 0 when the recipe is valid for the mesh, 2 otherwise.
#[derive(Debug, Args)]
#[command(
    after_help = "Recipe formats come from the extension: .cfg .conf .libconfig (libconfig, thesis \
appendix A; run through the C preprocessor `cpp` when it holds #define, #include or #if), \
.toml, .json.

Examples:
  smartmesh recipe check distributor.cfg distributor.msh
  smartmesh recipe check --json wing.toml wing.msh | jq '.regions[] | {name, dimension}'"
)]
pub(super) struct CheckArgs {
    /// Recipe file (`-` for stdin, with --recipe-format).
    recipe: PathBuf,
    /// Mesh file the recipe names tags of.
    mesh: PathBuf,
    /// Recipe format, when the extension does not tell (libconfig, toml, json).
    // Spelt as in `size`, `adapt`, `mesh` and `layer`; `--format`, its earlier name,
    // still reads (a hidden alias).
    #[arg(long, alias = "format", value_parser = parse_recipe_format, value_name = "FORMAT")]
    recipe_format: Option<RecipeFormat>,
    #[command(flatten)]
    read: RecipeReadArgs,
    /// Mesh format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    /// Print a JSON document instead of text.
    #[arg(long)]
    json: bool,
}

/// Convert a recipe between libconfig (thesis appendix A), TOML and JSON. Reading checks
/// it fully (names, kinds, ranges); no mesh is needed.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  smartmesh recipe convert distributor.cfg distributor.toml
  smartmesh recipe convert wing.toml - --to json")]
pub(super) struct ConvertArgs {
    /// Input recipe (`-` for stdin, with --from).
    input: PathBuf,
    /// Output recipe (`-` for stdout, with --to).
    output: PathBuf,
    /// Input format, when the extension does not tell (libconfig, toml, json).
    #[arg(long, value_parser = parse_recipe_format)]
    from: Option<RecipeFormat>,
    /// Output format, when the extension does not tell.
    #[arg(long, value_parser = parse_recipe_format)]
    to: Option<RecipeFormat>,
    #[command(flatten)]
    read: RecipeReadArgs,
}

/// Runs `recipe …`.
pub(super) fn run(args: RecipeArgs) -> Result<(), CliError> {
    match args.command {
        RecipeCommand::Check(a) => check(a),
        RecipeCommand::Convert(a) => convert(a),
    }
}

/// Reads a recipe the user named: `-` for stdin (whose format `flag` must give), a file
/// whose format `flag` forces, or a file whose extension tells it; within the read budget
/// of `read` in every case. The one reader of every command that takes a recipe, so that
/// each refuses the same things with the same exit status: a missing format and a text
/// that is not UTF-8 are bad input (2); a failed read of stdin has the status of its I/O
/// error.
pub(super) fn read_recipe(
    path: &Path,
    format: Option<RecipeFormat>,
    flag: &str,
    read: RecipeReadArgs,
) -> Result<Recipe, CliError> {
    let options = read.options();
    if path.as_os_str() == "-" {
        let format = format.ok_or_else(|| {
            CliError::usage(format!(
                "reading a recipe from stdin (`-`) needs {flag} libconfig, toml or json"
            ))
        })?;
        let mut bytes = Vec::new();
        std::io::stdin()
            .take(options.max_bytes as u64 + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| CliError::context("reading the recipe from stdin", e))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            CliError::usage(format!(
                "<stdin>: the recipe is not UTF-8 text (byte {} is not valid UTF-8)",
                e.utf8_error().valid_up_to()
            ))
        })?;
        return Ok(Recipe::from_str_with(&text, format, Path::new("<stdin>"), &options)?);
    }
    let Some(format) = format.or_else(|| RecipeFormat::from_path(path)) else {
        return Err(CliError::usage(format!(
            "{}: the extension tells no recipe format (.cfg, .conf, .libconfig, .toml, .json); give it with {flag}",
            path.display()
        )));
    };
    let text = smartmesh::recipe::preprocess::read_file(path, options.max_bytes, options.max_bytes)
        .map_err(|e| e.in_file(path))?;
    Ok(Recipe::from_str_with(&text, format, path, &options)?)
}

#[derive(serde::Serialize)]
struct StepSummary<'a> {
    label: &'a str,
    #[serde(rename = "type")]
    keyword: &'a str,
    points: usize,
    curves: usize,
    faces: usize,
    /// Volumes (a mesh in space), left out of the JSON when none.
    #[serde(skip_serializing_if = "is_zero")]
    volumes: usize,
    /// On a mesh in space: whether the step is sized there (left out on a planar mesh).
    #[serde(skip_serializing_if = "Option::is_none")]
    in_space: Option<bool>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

/// What `recipe check` says of periodic pairs on a mesh in space.
const NO_3D_PERIODIC: &str = "periodic pairs are not there yet in space";

/// What `recipe check` says of sizing a mesh in space: which steps are sized there and
/// which are not yet (`size` refuses those, exit 2).
/// Whether `size` sizes `algorithm` on a mesh in space with (`volumes`) or without
/// volume cells.
fn sized_in_space(algorithm: &smartmesh::sizing::Algorithm, volumes: bool) -> bool {
    if volumes {
        algorithm.in_space()
    } else {
        algorithm.on_surface_in_space()
    }
}

fn space_sizing(plan: &smartmesh::sizing::SizingPlan, volumes: bool) -> String {
    let list = |sized: bool| -> Vec<String> {
        plan.steps
            .iter()
            .enumerate()
            .filter(|(_, s)| sized_in_space(&s.algorithm, volumes) == sized)
            .map(|(i, s)| format!("{} ({})", i + 1, s.algorithm.keyword()))
            .collect()
    };
    let (yes, no) = (list(true), list(false));
    match (yes.is_empty(), no.is_empty()) {
        (_, true) => "every step is sized in space".to_string(),
        (true, false) => format!("no step is sized in space yet: {}", no.join(", ")),
        (false, false) => format!(
            "sized in space: steps {}; not yet in space (size refuses them): steps {}",
            yes.join(", "),
            no.join(", ")
        ),
    }
}

#[derive(serde::Serialize)]
struct CheckSummary<'a> {
    recipe: String,
    mesh: String,
    h_min: Option<f64>,
    h_max: Option<f64>,
    max_aspect_ratio: Option<f64>,
    gradation: Option<f64>,
    regions: &'a [RegionReport],
    algorithms: Vec<StepSummary<'a>>,
    /// On a mesh in space: which steps are sized there ([`space_sizing`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    sizing: Option<String>,
    /// Each periodic pair's match on the mesh.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    periodic: &'a [smartmesh::periodic::PairMatch],
}

/// The entities an algorithm works on, all its sets together.
fn entities(a: &Algorithm) -> EntitySet {
    match a.entity_sets().as_slice() {
        [] => EntitySet::default(),
        [one] => (*one).clone(),
        [first, rest @ ..] => rest.iter().fold((*first).clone(), |all, s| all.union(s)),
    }
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

fn check(args: CheckArgs) -> Result<(), CliError> {
    let recipe = read_recipe(&args.recipe, args.recipe_format, "--recipe-format", args.read)?;
    // A .poly (or any graph without surface cells) is meshed first, as `adapt` does: the
    // recipe may name the face tags that only meshing gives.
    // Periodic pairs: a graph is meshed with them matched; on a mesh, images of each
    // other, and how well they match.
    // A mesh in space, as `size` takes it (volume cells, or surface cells off one plane:
    // a surface mesh for mmgs): its regions are resolved on its 3D topology, and each
    // step says whether it is sized in space; nothing is periodic yet.
    let pairs = recipe.periodic_pairs();
    let (mesh, in_space) = match starting_mesh(&args.mesh, args.from, &pairs) {
        Ok(mesh) => (mesh, false),
        Err(StartError::NotPlanar { .. }) => {
            if !pairs.is_empty() {
                return Err(CliError::usage(format!(
                    "{}: a mesh in space; periodic pairs are checked on planar meshes only ({NO_3D_PERIODIC})",
                    args.mesh.display()
                )));
            }
            (super::read_linear_mesh_noted(&args.mesh, args.from)?.0, true)
        }
        Err(e) => return Err(e.into()),
    };
    let topo = Topology::from_mesh(&mesh);
    // A surface alone in space: the steps that need volume cells are not sized there.
    let volumes = mesh.blocks.iter().any(|b| b.kind.dim() == 3);
    let resolved = recipe.resolve(&topo)?;
    let plan = &resolved.plan;
    let sides = if in_space {
        smartmesh::periodic::Sides::default()
    } else {
        smartmesh::periodic::Sides::snap_and_check(&mut mesh.clone(), &pairs)
            .map_err(|e| CliError::usage(format!("{e} (mesh {})", args.mesh.display())))?
    };
    let (periodic, moved) = (&sides.before, &sides.moved);
    let steps: Vec<StepSummary> = plan
        .steps
        .iter()
        .map(|s| {
            let e = entities(&s.algorithm);
            StepSummary {
                label: &s.label,
                keyword: s.algorithm.keyword(),
                points: e.points.len(),
                curves: e.curves.len(),
                faces: e.faces.len(),
                volumes: e.volumes.len(),
                in_space: in_space.then(|| sized_in_space(&s.algorithm, volumes)),
            }
        })
        .collect();
    if args.json {
        let summary = CheckSummary {
            recipe: args.recipe.display().to_string(),
            mesh: args.mesh.display().to_string(),
            h_min: plan.h_min,
            h_max: plan.h_max,
            max_aspect_ratio: plan.max_aspect_ratio,
            gradation: plan.gradation,
            regions: &resolved.regions,
            algorithms: steps,
            sizing: in_space.then(|| space_sizing(plan, volumes)),
            periodic,
        };
        let mut s = serde_json::to_string_pretty(&summary)?;
        s.push('\n');
        return print_stdout(&s);
    }
    let mut o = String::new();
    let _ = writeln!(o, "{} on {}: valid", args.recipe.display(), args.mesh.display());
    let mut global = Vec::new();
    for (k, v) in [
        ("hmin", plan.h_min),
        ("hmax", plan.h_max),
        ("max aspect ratio", plan.max_aspect_ratio),
        ("gradation", plan.gradation),
    ] {
        if let Some(v) = v {
            global.push(format!("{k} {v}"));
        }
    }
    let _ = writeln!(
        o,
        "  global      {}",
        if global.is_empty() {
            "no bounds (vertices no algorithm reaches get the bounding-box diagonal)".into()
        } else {
            global.join(", ")
        }
    );
    let _ = writeln!(o, "  regions");
    let (face, faces) = if in_space { ("surface", "surfaces") } else { ("face", "faces") };
    let dim_names: [&str; 4] = ["points", "curves", faces, "volumes"];
    for r in &resolved.regions {
        let one: [&str; 4] = ["point", "curve", face, "volume"];
        let what = match r.dimension {
            Some(d) => plural(r.entities, one[d], dim_names[d]),
            None => "ambiguous dimension".into(),
        };
        let tags: Vec<String> = r.tags.iter().map(i32::to_string).collect();
        let names = if r.entity_names.is_empty() {
            String::new()
        } else {
            format!(
                " ({})",
                r.entity_names.iter().map(|n| format!("\"{n}\"")).collect::<Vec<_>>().join(", ")
            )
        };
        let mut counts = Vec::new();
        if let Some(v) = r.vertices {
            counts.push(plural(v, "vertex", "vertices"));
        }
        if let Some(e) = r.edges.filter(|_| r.dimension.is_some_and(|d| d > 0)) {
            counts.push(plural(e, "edge", "edges"));
        }
        if let Some(c) = r.cells.filter(|_| r.dimension.is_some_and(|d| d >= 2)) {
            counts.push(plural(c, "cell", "cells"));
        }
        let used = if r.used_by.is_empty() {
            "unused (no algorithm names it: its entities exist, nothing is measured)".to_string()
        } else {
            format!(
                "used by {}",
                r.used_by.iter().map(usize::to_string).collect::<Vec<_>>().join(", ")
            )
        };
        let _ = writeln!(
            o,
            "    {:<16} {what}: tags {}{names}; {}{used}",
            r.name,
            tags.join(", "),
            if counts.is_empty() { String::new() } else { format!("{}; ", counts.join(", ")) }
        );
    }
    let _ = writeln!(o, "  algorithms");
    for s in &steps {
        let mut parts = Vec::new();
        for (n, one, many) in [
            (s.points, "point", "points"),
            (s.curves, "curve", "curves"),
            (s.faces, face, faces),
            (s.volumes, "volume", "volumes"),
        ] {
            if n > 0 {
                parts.push(plural(n, one, many));
            }
        }
        let on = if parts.is_empty() { "everywhere".into() } else { parts.join(", ") };
        let _ = writeln!(o, "    {}: {on}", s.label);
    }
    for (m, d) in periodic.iter().zip(moved) {
        let _ = writeln!(o, "  {m}");
        if *d > 0.0 {
            let _ = writeln!(
                o,
                "    (after moving the slave vertices by at most {d:.3e} onto the master's images, as adapt does)"
            );
        }
    }
    if in_space {
        let _ = writeln!(o, "  sizing      {}", space_sizing(plan, volumes));
    }
    print_stdout(&o)
}

fn convert(args: ConvertArgs) -> Result<(), CliError> {
    let to = match args.to.or_else(|| RecipeFormat::from_path(&args.output)) {
        Some(f) => f,
        None => {
            return Err(CliError::usage(format!(
                "{}: the extension tells no recipe format (.cfg, .toml, .json); give it with --to",
                args.output.display()
            )))
        }
    };
    let mut recipe = read_recipe(&args.input, args.from, "--from", args.read)?;
    // A sheet's FILE is relative to the recipe that names it: the copy names the same file.
    let to_path = (args.output.as_os_str() != "-").then_some(args.output.as_path());
    recipe.rebase_files(to_path).map_err(CliError::usage)?;
    let text = recipe.to_format(to);
    if args.output.as_os_str() == "-" {
        return print_stdout(&text);
    }
    write_all_atomically(&[(args.output.clone(), text.into_bytes())])?;
    Ok(())
}
