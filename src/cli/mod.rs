//! Argument parsing, exit codes and error printing; one file per subcommand.

mod adapt;
mod convert;
mod info;
mod mesh;
mod recipe;
mod remesh;
mod report;
mod size;

use std::io::Write;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// How a run ended (ruff's `ExitStatus`): 0 success, 1 the work failed, 2 bad usage or
/// input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExitStatus {
    /// Everything done.
    Success,
    /// The work itself failed (I/O error, a tool that failed).
    Failure,
    /// Bad usage or bad input.
    Error,
}

impl From<ExitStatus> for ExitCode {
    fn from(s: ExitStatus) -> ExitCode {
        match s {
            ExitStatus::Success => ExitCode::from(0),
            ExitStatus::Failure => ExitCode::from(1),
            ExitStatus::Error => ExitCode::from(2),
        }
    }
}

/// An error the CLI prints: the message and the exit status it maps to.
#[derive(Debug)]
pub struct CliError {
    /// Exit status.
    pub status: ExitStatus,
    /// What to print after `smartmesh: error: `.
    pub message: String,
}

impl From<smartmesh::formats::Error> for CliError {
    fn from(e: smartmesh::formats::Error) -> Self {
        let broken_pipe = matches!(&e.kind, smartmesh::formats::ErrorKind::Io(io) if io.kind() == std::io::ErrorKind::BrokenPipe);
        CliError {
            status: if broken_pipe {
                ExitStatus::Success
            } else if e.is_input_error()
                || matches!(&e.kind, smartmesh::formats::ErrorKind::Io(io) if io.kind() == std::io::ErrorKind::NotFound)
            {
                ExitStatus::Error
            } else {
                ExitStatus::Failure
            },
            message: e.to_string(),
        }
    }
}

impl CliError {
    /// A usage or input error (exit 2).
    pub fn usage(message: impl Into<String>) -> Self {
        CliError { status: ExitStatus::Error, message: message.into() }
    }
}

const ABOUT: &str = "Anisotropic metric fields from geometry, and the glue between meshing tools.

Reads and writes Triangle (.node/.ele/.poly/.edge), Gmsh (.msh 2.2 and 4.1, ASCII and \
binary), VTK (.vtk legacy 4.2/5.1, .vtu XML), OBJ, Medit/MMG (.mesh/.meshb with .sol) \
and glTF (.gltf/.glb, write only), keeping topology tags and fields.";

#[derive(Debug, Parser)]
#[command(name = "smartmesh", version, about = ABOUT, propagate_version = true, max_term_width = 100)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    Info(info::InfoArgs),
    Convert(convert::ConvertArgs),
    Recipe(recipe::RecipeArgs),
    Size(size::SizeArgs),
    Adapt(adapt::AdaptArgs),
    Mesh(mesh::MeshArgs),
    Remesh(remesh::RemeshArgs),
    Report(report::ReportArgs),
}

/// Parses arguments, runs the command, prints errors, maps them to exit codes.
pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return match e.kind() {
                clap::error::ErrorKind::DisplayHelp | clap::error::ErrorKind::DisplayVersion => {
                    ExitCode::from(0)
                }
                _ => ExitCode::from(2),
            };
        }
    };
    let result = match cli.command {
        Command::Info(a) => info::run(a),
        Command::Convert(a) => convert::run(a),
        Command::Recipe(a) => recipe::run(a),
        Command::Size(a) => size::run(a),
        Command::Adapt(a) => adapt::run(a),
        Command::Mesh(a) => mesh::run(a),
        Command::Remesh(a) => remesh::run(a),
        Command::Report(a) => report::run(a),
    };
    match result {
        Ok(()) => ExitStatus::Success.into(),
        Err(e) => {
            if e.status != ExitStatus::Success {
                let _ = writeln!(std::io::stderr(), "smartmesh: error: {}", e.message);
            }
            e.status.into()
        }
    }
}

/// Writes to stdout; a closed pipe (`smartmesh info x | head`) is not an error.
pub fn print_stdout(text: &str) -> Result<(), CliError> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(CliError {
            status: ExitStatus::Failure,
            message: format!("writing to stdout: {e}"),
        }),
    }
}

/// Parses a `--from`/`--to` format name.
pub fn parse_format(name: &str) -> Result<smartmesh::formats::Format, String> {
    smartmesh::formats::Format::from_name(name).ok_or_else(|| {
        format!("unknown format `{name}`; known: {}", smartmesh::formats::Format::NAMES)
    })
}

/// The output switches of the commands that write a mesh (`mesh`, `remesh`, `size`,
/// `adapt`), flattened into each one's arguments.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct MeshOutputArgs {
    /// Write binary variants (.msh binary, .vtk binary; .meshb/.solb follow the extension).
    #[arg(long)]
    pub binary: bool,
    /// Write Gmsh MSH 2.2 instead of 4.1.
    #[arg(long)]
    pub msh2: bool,
}

impl MeshOutputArgs {
    /// The writer options these switches ask for.
    pub fn write_options(self) -> smartmesh::formats::WriteOptions {
        use smartmesh::formats::{GmshVersion, WriteOptions};
        WriteOptions {
            binary: self.binary,
            gmsh_version: if self.msh2 { GmshVersion::V22 } else { GmshVersion::V41 },
            ..WriteOptions::default()
        }
    }
}
