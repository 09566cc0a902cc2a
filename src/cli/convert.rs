//! `smartmesh convert IN OUT`: any readable format to any writable one, tags and
//! fields carried; what the output format cannot hold is listed on stderr.

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use smartmesh::formats::{write_path_reusing, Format};

use super::output::{check_output_dir, label, refuse_same_file, shown};
use super::{parse_format, print_stdout, ui, CliError, MeshOutputArgs};

/// Convert a mesh between formats, keeping tags, tag names and fields.
#[derive(Debug, Args)]
#[command(
    after_help = "Formats come from the extensions: .node .ele .poly .edge (Triangle), .msh (Gmsh), \
.vtk .vtu (VTK), .obj, .mesh .meshb (Medit/MMG; a .sol/.solb beside them carries the metric), \
.gltf .glb (glTF, write only), .su2 (SU2), .foam (an OpenFOAM case directory, write only: \
`--to openfoam` for another name; --extrude DZ, --patch-type NAME=TYPE), .fluent.msh (Fluent, \
`--from`/`--to fluent` for another name, a .msh starting with `(` read as Fluent; --patch-type NAME=TYPE).

Examples:
  smartmesh convert naca.msh naca.vtu
  smartmesh convert box.1.ele box.msh --gmsh-version 2.2 --binary
  smartmesh convert square.msh square.mesh          # writes square.mesh and square.sol
  gmsh model.geo -2 -format msh -v 0 -o /dev/stdout | smartmesh convert --from msh - out.vtu
  smartmesh convert adapted.vtu view.glb --color-field hmin
  smartmesh convert skin.msh skin-triangles.msh --split-quads
  smartmesh convert naca.msh naca.su2
  smartmesh convert skin.msh case.foam --extrude 0.1     # then: checkMesh -case case.foam
  smartmesh convert adapted.msh case.foam --recipe distributor.cfg   # PERIODIC pairs as cyclic patches"
)]
#[command(mut_arg("recipe", |a| a.help("A recipe whose PERIODIC pairs an OpenFOAM case glues as `cyclic` patch pairs (--cyclic wins); its sizing steps are not used")))]
pub(super) struct ConvertArgs {
    /// Input mesh (`-` for stdin, with --from).
    input: PathBuf,
    /// Output mesh (`-` for stdout, with --to). Sibling files (.sol, .bin, .node)
    /// are written beside it.
    output: PathBuf,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    /// glTF: the point field that colours the vertices (default: the first scalar).
    #[arg(long)]
    color_field: Option<String>,
    /// Write each quad as two triangles (the diagonal giving the better worst triangle;
    /// tags and cell data kept).
    #[arg(long)]
    split_quads: bool,
    /// Read a Medit mesh without the .sol/.solb beside it (one MMG cannot read, or of
    /// another mesh).
    #[arg(long)]
    no_solution: bool,
    /// Print a JSON summary (formats, counts, what the reader and the writer could not
    /// keep) on stdout.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    output_format: MeshOutputArgs,
    /// The recipe whose PERIODIC pairs are written (its help is set above).
    #[command(flatten)]
    recipe: super::RecipeInput,
}

#[derive(serde::Serialize)]
struct ConvertSummary<'a> {
    input: String,
    output: String,
    from: Option<Format>,
    to: Option<Format>,
    points: usize,
    cells: usize,
    /// What the reader could not keep (also on stderr, which `-q` silences).
    read_notes: &'a [String],
    dropped: &'a [String],
}

/// Runs `convert`.
pub(super) fn run(mut args: ConvertArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    let from = args.from.or_else(|| Format::from_path(&args.input));
    if args.output.as_os_str() == "-" && args.json {
        return Err(CliError::usage(
            "--json prints on stdout, which `-` already uses for the mesh",
        ));
    }
    let to = match &args.output_format.to {
        Some(_) => Some(args.output_format.mesh_format(&args.output)?),
        None => Format::from_path(&args.output),
    };
    check_output_dir(&args.output)?;
    refuse_same_file(&args.input, &args.output)?;
    // The input's buffer is handed to the writer: a binary conversion of a large mesh
    // otherwise spends most of its time in the kernel faulting in fresh memory.
    let (mut mesh, read_notes, spare) =
        super::read_mesh_noted_keeping_bytes(&args.input, from, args.no_solution)?;
    if args.split_quads {
        let n = mesh.split_quads();
        ui::note(&format!("split {n} quads into {} triangles", 2 * n));
    }
    if args.recipe.is_stdin() && args.input.as_os_str() == "-" {
        return Err(CliError::usage("the mesh and the recipe cannot both come from stdin"));
    }
    if let (Some(_), Some(to)) = (&args.recipe.recipe, to) {
        let pairs = args.recipe.read()?.periodic_pairs();
        args.output_format.periodic_from_recipe(to, &mesh, &pairs)?;
    }
    let mut opts = args.output_format.write_options(&args.output);
    opts.gltf.color_field = args.color_field.clone();
    if let Some(name) = &args.color_field {
        if !mesh.point_data.contains_key(name) {
            let known: Vec<&str> = mesh.point_data.keys().map(String::as_str).collect();
            return Err(CliError::usage(format!(
                "--color-field: no point field `{name}` (the mesh has: {})",
                known.join(", ")
            )));
        }
    }
    let report = write_path_reusing(&args.output, &mesh, to, &opts, spare)
        .map_err(|e| label(e, &args.output))?;
    ui::write_notes(&shown(&args.output), &report.dropped);
    if args.json {
        let s = ConvertSummary {
            input: args.input.display().to_string(),
            output: args.output.display().to_string(),
            from,
            to,
            points: mesh.points.len(),
            cells: mesh.num_cells(),
            read_notes: &read_notes,
            dropped: &report.dropped,
        };
        let mut text = serde_json::to_string_pretty(&s)?;
        text.push('\n');
        print_stdout(&text)?;
    }
    ui::done(
        "convert",
        &format!(
            "wrote {} ({} points, {} cells) in {}",
            shown(&args.output),
            mesh.points.len(),
            mesh.num_cells(),
            ui::seconds(t0.elapsed())
        ),
    );
    Ok(())
}
