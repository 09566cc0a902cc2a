//! `smartmesh convert IN OUT`: any readable format to any writable one, tags and
//! fields carried; what the output format cannot hold is listed on stderr.

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use smartmesh::formats::{read_path, write_path, Format, GmshVersion, VtuEncoding, WriteOptions};

use super::{parse_format, print_stdout, CliError};

#[derive(Debug, Clone, Copy, ValueEnum)]
enum GmshVersionArg {
    #[value(name = "2.2")]
    V22,
    #[value(name = "4.1")]
    V41,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum VtkVersionArg {
    #[value(name = "4.2")]
    V42,
    #[value(name = "5.1")]
    V51,
}

#[derive(Debug, Clone, Copy, ValueEnum)]
enum VtuEncodingArg {
    Ascii,
    Binary,
    Appended,
}

/// Convert a mesh between formats, keeping tags, tag names and fields.
#[derive(Debug, Args)]
#[command(
    after_help = "Formats come from the extensions: .node .ele .poly .edge (Triangle), .msh (Gmsh), \
.vtk .vtu (VTK), .obj, .mesh .meshb (Medit/MMG; a .sol/.solb beside them carries the metric), \
.gltf .glb (glTF, write only).

Examples:
  smartmesh convert naca.msh naca.vtu
  smartmesh convert box.1.ele box.msh --gmsh-version 2.2 --binary
  smartmesh convert square.msh square.mesh          # writes square.mesh and square.sol
  gmsh -2 -o - model.geo | smartmesh convert --from msh - out.vtu
  smartmesh convert adapted.vtu view.glb --color-field hmin"
)]
pub struct ConvertArgs {
    /// Input mesh (`-` for stdin, with --from).
    input: PathBuf,
    /// Output mesh (`-` for stdout, with --to). Sibling files (.sol, .bin, .node)
    /// are written beside it.
    output: PathBuf,
    /// Input format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    /// Output format, when the extension does not tell.
    #[arg(long, value_parser = parse_format)]
    to: Option<Format>,
    /// Write the binary variant (Gmsh, VTK legacy, Medit .meshb).
    #[arg(long)]
    binary: bool,
    /// Gmsh MSH version to write.
    #[arg(long, value_enum, default_value = "4.1")]
    gmsh_version: GmshVersionArg,
    /// VTK legacy file version to write.
    #[arg(long, value_enum, default_value = "4.2")]
    vtk_version: VtkVersionArg,
    /// VTK XML (.vtu) data encoding.
    #[arg(long, value_enum, default_value = "binary")]
    vtu_encoding: VtuEncodingArg,
    /// Do not zlib-compress .vtu binary or appended data.
    #[arg(long)]
    no_compress: bool,
    /// glTF: the point field that colours the vertices (default: the first scalar).
    #[arg(long)]
    color_field: Option<String>,
    /// Print a JSON summary (formats, counts, dropped items) on stdout.
    #[arg(long)]
    json: bool,
}

#[derive(serde::Serialize)]
struct ConvertSummary<'a> {
    input: String,
    output: String,
    from: Option<Format>,
    to: Option<Format>,
    points: usize,
    cells: usize,
    dropped: &'a [String],
}

/// Runs `convert`.
pub fn run(args: ConvertArgs) -> Result<(), CliError> {
    let from = args.from.or_else(|| Format::from_path(&args.input));
    let to = args.to.or_else(|| Format::from_path(&args.output));
    if args.output.as_os_str() == "-" && args.json {
        return Err(CliError::usage(
            "--json prints on stdout, which `-` already uses for the mesh",
        ));
    }
    let mesh = read_path(&args.input, from)?;
    let opts = WriteOptions {
        binary: args.binary,
        gmsh_version: match args.gmsh_version {
            GmshVersionArg::V22 => GmshVersion::V22,
            GmshVersionArg::V41 => GmshVersion::V41,
        },
        vtk_legacy_version: match args.vtk_version {
            VtkVersionArg::V42 => (4, 2),
            VtkVersionArg::V51 => (5, 1),
        },
        vtu_encoding: match args.vtu_encoding {
            VtuEncodingArg::Ascii => VtuEncoding::Ascii,
            VtuEncodingArg::Binary => VtuEncoding::Binary,
            VtuEncodingArg::Appended => VtuEncoding::Appended,
        },
        compress: !args.no_compress,
        medit_binary: args.binary,
        color_field: args.color_field.clone(),
        glb: args.output.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb")),
        main_name: None,
    };
    if let Some(name) = &args.color_field {
        if !mesh.point_data.contains_key(name) {
            let known: Vec<&str> = mesh.point_data.keys().map(String::as_str).collect();
            return Err(CliError::usage(format!(
                "--color-field: no point field `{name}` (the mesh has: {})",
                known.join(", ")
            )));
        }
    }
    let report = write_path(&args.output, &mesh, to, &opts)?;
    for d in &report.dropped {
        eprintln!("smartmesh: warning: not written: {d}");
    }
    if args.json {
        let s = ConvertSummary {
            input: args.input.display().to_string(),
            output: args.output.display().to_string(),
            from,
            to,
            points: mesh.points.len(),
            cells: mesh.num_cells(),
            dropped: &report.dropped,
        };
        let mut text =
            serde_json::to_string_pretty(&s).map_err(|e| CliError::usage(e.to_string()))?;
        text.push('\n');
        print_stdout(&text)?;
    }
    Ok(())
}
