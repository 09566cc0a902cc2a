//! The options every command that writes a mesh shares (one clap struct, flattened into
//! `convert`, `mesh`, `remesh`, `size` and `adapt`), the writing of a mesh to a file or
//! stdout with the writer's notes, and the reading of a recipe from a file or stdin.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use smartmesh::formats::{
    write_path, CyclicPair, CyclicTransform, Error as FormatError, Format, GltfWrite, GmshVersion,
    GmshWrite, MeditWrite, OpenFoamWrite, StlWrite, TaggedMesh, VtkWrite, VtuEncoding,
    WriteOptions, WriteReport,
};
use smartmesh::periodic::{PeriodicPair, Transform};
use smartmesh::recipe::{GlobalOverrides, Recipe, RecipeFormat};
use smartmesh::Topology;

use super::{parse_format, ui, CliError};

/// Gmsh MSH versions on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum GmshVersionArg {
    /// MSH 2.2.
    #[value(name = "2.2")]
    V22,
    /// MSH 4.1 (Gmsh's own default).
    #[value(name = "4.1")]
    V41,
}

/// VTK legacy versions on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum VtkVersionArg {
    /// 4.2, read by every VTK and meshio.
    #[value(name = "4.2")]
    V42,
    /// 5.1 (offsets and connectivity arrays).
    #[value(name = "5.1")]
    V51,
}

/// VTK XML encodings on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum VtuEncodingArg {
    /// Numbers as text.
    Ascii,
    /// Base64 inline binary.
    Binary,
    /// Raw appended binary.
    Appended,
}

/// Output switches of every command that writes a mesh.
#[derive(Debug, Clone, Args)]
pub(crate) struct MeshOutputArgs {
    /// Output format when the extension does not tell (needed with `-o -`): a format name
    /// or extension (msh, vtu, vtk, mesh, obj, node, gltf, glb, su2, openfoam; `size` also
    /// sol, solb, pos).
    #[arg(long, value_name = "FORMAT", help_heading = "Output")]
    pub to: Option<String>,
    /// Write binary variants (.msh binary, .vtk binary, .meshb/.solb, OpenFOAM binary, binary STL).
    #[arg(long, help_heading = "Output")]
    pub binary: bool,
    /// Gmsh MSH version to write.
    #[arg(long, value_enum, default_value = "4.1", help_heading = "Output")]
    pub gmsh_version: GmshVersionArg,
    /// Same as --gmsh-version 2.2.
    #[arg(long, conflicts_with = "gmsh_version", help_heading = "Output")]
    pub msh2: bool,
    /// VTK legacy file version to write.
    #[arg(long, value_enum, default_value = "4.2", help_heading = "Output")]
    pub vtk_version: VtkVersionArg,
    /// VTK XML (.vtu) data encoding.
    #[arg(long, value_enum, default_value = "binary", help_heading = "Output")]
    pub vtu_encoding: VtuEncodingArg,
    /// Do not zlib-compress .vtu binary or appended data.
    #[arg(long, help_heading = "Output")]
    pub no_compress: bool,
    /// OpenFOAM: the thickness of the one cell layer the 2D mesh is extruded into
    /// (default: a hundredth of the mesh's extent).
    #[arg(long, value_name = "DZ", value_parser = positive_size, help_heading = "Output")]
    pub extrude: Option<f64>,
    /// OpenFOAM: an axisymmetric wedge of ANGLE degrees about the x axis (the mesh in
    /// y >= 0; front and back `wedge` patches) instead of a slab.
    #[arg(long, value_name = "ANGLE", conflicts_with = "extrude", help_heading = "Output")]
    pub wedge: Option<f64>,
    /// OpenFOAM: the type of a patch, over the guess from its name (`wall` for names
    /// like Wall, Airfoil, Cylinder; `patch` otherwise); repeatable.
    #[arg(long, value_name = "NAME=TYPE", value_parser = patch_type, help_heading = "Output")]
    pub patch_type: Vec<(String, String)>,
    /// OpenFOAM, Fluent: a periodic pair written as two `cyclic` patches (Fluent: a
    /// `periodic` and a `periodic-shadow` zone with their face pairs), by tag numbers:
    /// `MASTER=SLAVE:DX,DY[,DZ]` for a translation from master to slave (`302,303,304=
    /// 308,307,306:0,30`), `MASTER=SLAVE@CX,CY,ANGLE` for a rotation of ANGLE degrees
    /// about the z axis through (CX, CY); repeatable. Without it, a recipe's PERIODIC pairs
    /// (`--recipe` of mesh, remesh, layer, adapt, convert) are written so.
    #[arg(long, value_name = "MASTER=SLAVE:DX,DY", value_parser = cyclic_pair, help_heading = "Output")]
    pub cyclic: Vec<CyclicPair>,
    /// The recipe's PERIODIC pairs as `cyclic` pairs, written when `--cyclic` gives
    /// none (set by the commands that read a recipe, not a flag).
    #[arg(skip)]
    pub recipe_cyclic: Vec<CyclicPair>,
}

/// A `--cyclic` value: `302,303=306,307:0,30` or `1=2@0,0,60`.
fn cyclic_pair(s: &str) -> Result<CyclicPair, String> {
    let bad = || {
        format!("`{s}`: expected MASTER=SLAVE:DX,DY[,DZ] or MASTER=SLAVE@CX,CY,ANGLE, tags as numbers (e.g. 302,303=307,306:0,30)")
    };
    let (sides, rest, rotation) = match (s.split_once(':'), s.split_once('@')) {
        (Some((a, b)), None) => (a, b, false),
        (None, Some((a, b))) => (a, b, true),
        _ => return Err(bad()),
    };
    let (m, sl) = sides.split_once('=').ok_or_else(bad)?;
    let tags = |t: &str| -> Result<Vec<i32>, String> {
        t.split(',').map(|x| x.trim().parse::<i32>().map_err(|_| bad())).collect()
    };
    let nums: Vec<f64> = rest
        .split(',')
        .map(|x| x.trim().parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(bad))
        .collect::<Result<_, _>>()?;
    let transform = match (rotation, nums.as_slice()) {
        (false, &[dx, dy]) => CyclicTransform::Translation([dx, dy, 0.0]),
        (false, &[dx, dy, dz]) => CyclicTransform::Translation([dx, dy, dz]),
        (true, &[cx, cy, angle]) => CyclicTransform::Rotation {
            axis: [0.0, 0.0, 1.0],
            centre: [cx, cy, 0.0],
            angle_degrees: angle,
        },
        _ => return Err(bad()),
    };
    Ok(CyclicPair { master: tags(m)?, slave: tags(sl)?, transform })
}

fn patch_type(s: &str) -> Result<(String, String), String> {
    match s.split_once('=') {
        Some((n, t)) if !n.is_empty() && !t.is_empty() && !t.contains(char::is_whitespace) => {
            Ok((n.to_string(), t.to_string()))
        }
        _ => Err(format!("`{s}`: expected NAME=TYPE (e.g. Outlet=patch, Top=symmetryPlane)")),
    }
}

impl MeshOutputArgs {
    /// The writer options these switches ask for, for the output `path`: the one place
    /// where the flattened flags meet the formats' groups (`--binary` is Gmsh's, legacy
    /// VTK's and Medit's).
    pub(crate) fn write_options(&self, path: &Path) -> WriteOptions {
        WriteOptions {
            gmsh: GmshWrite {
                version: if self.msh2 || self.gmsh_version == GmshVersionArg::V22 {
                    GmshVersion::V22
                } else {
                    GmshVersion::V41
                },
                binary: self.binary,
            },
            vtk: VtkWrite {
                legacy_version: match self.vtk_version {
                    VtkVersionArg::V42 => (4, 2),
                    VtkVersionArg::V51 => (5, 1),
                },
                legacy_binary: self.binary,
                vtu_encoding: match self.vtu_encoding {
                    VtuEncodingArg::Ascii => VtuEncoding::Ascii,
                    VtuEncodingArg::Binary => VtuEncoding::Binary,
                    VtuEncodingArg::Appended => VtuEncoding::Appended,
                },
                compress: !self.no_compress,
            },
            medit: MeditWrite { binary: self.binary },
            gltf: GltfWrite {
                color_field: None,
                glb: path.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb"))
                    || self.to.as_deref().is_some_and(|t| t.eq_ignore_ascii_case("glb")),
            },
            openfoam: OpenFoamWrite {
                extrude: self.extrude,
                patch_types: self.patch_type.iter().cloned().collect(),
                wedge: self.wedge,
                binary: self.binary,
                // The command line wins over the recipe.
                cyclic: if self.cyclic.is_empty() {
                    self.recipe_cyclic.clone()
                } else {
                    self.cyclic.clone()
                },
            },
            stl: StlWrite { binary: self.binary },
            main_name: None,
        }
    }

    /// Takes a recipe's periodic `pairs`, resolved on `mesh` (tag numbers by the curves'
    /// tags or names), as the pairs an output in `format` glues: OpenFOAM's `cyclic`
    /// patches, Fluent's periodic zones. A translation (dx, dy) is (dx, dy, 0); a rotation is about the z axis
    /// through its centre. `--cyclic` wins: given, the recipe's pairs are left, said.
    pub(crate) fn periodic_from_recipe(
        &mut self,
        format: Format,
        mesh: &TaggedMesh,
        pairs: &[PeriodicPair],
    ) -> Result<(), CliError> {
        let what = match format {
            Format::OpenFoam => "cyclic patch pairs",
            Format::Fluent => "periodic and periodic-shadow zones",
            _ => return Ok(()),
        };
        if pairs.is_empty() {
            return Ok(());
        }
        if !self.cyclic.is_empty() {
            ui::note(&format!(
                "--cyclic given: the recipe's {} PERIODIC pair(s) are not written as {what}",
                pairs.len()
            ));
            return Ok(());
        }
        let topology = Topology::from_mesh(mesh);
        self.recipe_cyclic = pairs
            .iter()
            .map(|p| {
                let (master, slave) =
                    p.side_tags(&topology).map_err(|e| CliError::context(e.to_string(), e))?;
                let transform = match p.transform {
                    Transform::Translation([dx, dy]) => CyclicTransform::Translation([dx, dy, 0.0]),
                    Transform::Rotation { centre: [cx, cy], angle_degrees } => {
                        CyclicTransform::Rotation {
                            axis: [0.0, 0.0, 1.0],
                            centre: [cx, cy, 0.0],
                            angle_degrees,
                        }
                    }
                };
                Ok(CyclicPair { master, slave, transform })
            })
            .collect::<Result<_, CliError>>()?;
        ui::note(&format!(
            "the recipe's {} PERIODIC pair(s) written as {what} (--cyclic replaces them)",
            pairs.len()
        ));
        Ok(())
    }

    /// The mesh format of `output`: `--to`, else its extension; a usage error when
    /// neither tells (and before any work is done).
    pub(crate) fn mesh_format(&self, output: &Path) -> Result<Format, CliError> {
        if let Some(t) = &self.to {
            return parse_format(t).map_err(|e| CliError::usage(format!("--to: {e}")));
        }
        Format::from_path(output).ok_or_else(|| {
            if is_stdio(output) {
                CliError::usage("writing to stdout (`-`) needs --to FORMAT")
            } else {
                CliError::usage(format!(
                    "{}: no mesh format has this extension; use one of {} or name it with --to",
                    output.display(),
                    Format::NAMES
                ))
            }
        })
    }

    /// Writes `mesh` to `output` (`-`: stdout) in `format`, and prints the writer's notes.
    pub(crate) fn write(
        &self,
        output: &Path,
        mesh: &TaggedMesh,
        format: Format,
    ) -> Result<WriteReport, CliError> {
        let opts = self.write_options(output);
        let report = write_path(output, mesh, Some(format), &opts).map_err(|e| label(e, output))?;
        ui::write_notes(&shown(output), &report.dropped);
        Ok(report)
    }
}

/// `path` as messages name it: `stdout` for `-`.
pub(super) fn shown(path: &Path) -> String {
    if is_stdio(path) {
        "stdout".into()
    } else {
        path.display().to_string()
    }
}

/// Whether `path` is `-` (stdin or stdout).
pub(super) fn is_stdio(path: &Path) -> bool {
    path.as_os_str() == "-"
}

/// A write error that names `output` (`<stdout>` for `-`, which the formats crate leaves
/// unnamed).
pub(super) fn label(e: FormatError, output: &Path) -> FormatError {
    if is_stdio(output) {
        e.with_path("<stdout>")
    } else {
        e.with_path(output)
    }
}

/// Refuses, before any work, an output whose directory does not exist or is not a
/// directory (exit 2, as every bad path the user names).
pub(super) fn check_output_dir(output: &Path) -> Result<(), CliError> {
    if is_stdio(output) {
        return Ok(());
    }
    let dir = match output.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if dir.is_dir() {
        return Ok(());
    }
    let what = if dir.exists() { "is not a directory" } else { "does not exist" };
    Err(CliError::usage(format!(
        "{}: cannot write there: {} {what}",
        output.display(),
        dir.display()
    )))
}

/// Refuses, before any work, an output that is the input itself (exit 2), as `cp a a`
/// does: the same device and inode, whatever the spelling (`./a.msh`, a symbolic or a
/// hard link). Writing would replace the input before a reader could tell what was lost.
/// Without a file at `output` (or with `-` on either side) there is nothing to compare.
pub(super) fn refuse_same_file(input: &Path, output: &Path) -> Result<(), CliError> {
    if is_stdio(input) || is_stdio(output) {
        return Ok(());
    }
    let (Ok(a), Ok(b)) = (std::fs::metadata(input), std::fs::metadata(output)) else {
        return Ok(());
    };
    if same_file(input, &a, output, &b) {
        return Err(CliError::usage(format!(
            "{} and {} are the same file: write the output elsewhere (the input is not rewritten in place)",
            input.display(),
            output.display()
        )));
    }
    Ok(())
}

#[cfg(unix)]
fn same_file(_: &Path, a: &std::fs::Metadata, _: &Path, b: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::MetadataExt;
    (a.dev(), a.ino()) == (b.dev(), b.ino())
}

#[cfg(not(unix))]
fn same_file(a: &Path, _: &std::fs::Metadata, b: &Path, _: &std::fs::Metadata) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

/// The recipe file of `size` and `adapt`: a path, or `-` for stdin with its format.
#[derive(Debug, Clone, Args)]
pub(crate) struct RecipeInput {
    /// The recipe (.cfg libconfig, .toml, .json; `-` for stdin, with --recipe-format).
    /// Optional only with a solution field (`size --field`, `adapt --solver`).
    #[arg(long, short = 'r')]
    pub recipe: Option<PathBuf>,
    /// Recipe format when the extension does not tell (libconfig, toml, json).
    #[arg(long, value_parser = parse_recipe_format, value_name = "FORMAT")]
    pub recipe_format: Option<RecipeFormat>,
    #[command(flatten)]
    pub read: super::recipe::RecipeReadArgs,
}

fn parse_recipe_format(name: &str) -> Result<RecipeFormat, String> {
    RecipeFormat::from_name(name).ok_or_else(|| {
        format!("unknown recipe format `{name}`; known: libconfig (cfg), toml, json")
    })
}

impl RecipeInput {
    /// Whether the recipe comes from stdin.
    pub(crate) fn is_stdin(&self) -> bool {
        self.recipe.as_deref().is_some_and(is_stdio)
    }

    /// Reads and checks the recipe; an empty one when none is given and `optional`
    /// (`why` says when it may be left out, for the error otherwise).
    pub(crate) fn read_or_empty(&self, optional: bool, why: &str) -> Result<Recipe, CliError> {
        match &self.recipe {
            Some(_) => self.read(),
            None if optional => Ok(Recipe::default()),
            None => Err(CliError::usage(format!("missing --recipe (it may be left out {why})"))),
        }
    }

    /// Reads and checks the recipe.
    pub(crate) fn read(&self) -> Result<Recipe, CliError> {
        let Some(path) = &self.recipe else {
            return Err(CliError::usage("missing --recipe"));
        };
        super::recipe::read_recipe(path, self.recipe_format, "--recipe-format", self.read)
    }

    /// The recipe as the history and summaries name it.
    pub(crate) fn label(&self) -> String {
        match &self.recipe {
            None => "none".into(),
            Some(p) if is_stdio(p) => "<stdin>".into(),
            Some(p) => p.display().to_string(),
        }
    }
}

/// The size controls a user of MMG and Gmsh expects on the command line. For `size` and
/// `adapt` they override the recipe's global bounds and gradation; for `remesh` they act
/// on the metric read.
#[derive(Debug, Clone, Copy, Args)]
pub(super) struct SizeControls {
    /// Smallest size anywhere (size, adapt: replaces the recipe's hmin; remesh: clamps
    /// the metric).
    #[arg(long, value_parser = positive_size, help_heading = "Size controls")]
    pub hmin: Option<f64>,
    /// Largest size anywhere (size, adapt: replaces the recipe's hmax; remesh: clamps the
    /// metric).
    #[arg(long, value_parser = positive_size, help_heading = "Size controls")]
    pub hmax: Option<f64>,
    /// Gradation: how fast sizes may grow from a vertex to its neighbours, a factor >= 1
    /// per unit of metric length (size, adapt: replaces the recipe's gradation; remesh:
    /// grades the metric; -1: none).
    #[arg(long, allow_negative_numbers = true, value_parser = gradation, help_heading = "Size controls")]
    pub hgrad: Option<f64>,
}

pub(super) fn positive_size(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v)
            if (smartmesh::SizeTensor::MIN_SIZE..=smartmesh::SizeTensor::MAX_SIZE).contains(&v) =>
        {
            Ok(v)
        }
        Ok(v) => Err(format!("{v} is not a size (expected a number in [1e-30, 1e30])")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

fn gradation(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v == -1.0 || (v.is_finite() && v >= 1.0) => Ok(v),
        Ok(v) => Err(format!("{v} is not a gradation (expected a factor >= 1, or -1 for none)")),
        Err(e) => Err(format!("`{s}`: {e}")),
    }
}

impl SizeControls {
    /// The global values these controls set over a recipe's.
    pub(super) fn overrides(&self) -> GlobalOverrides {
        GlobalOverrides {
            h_min: self.hmin,
            h_max: self.hmax,
            gradation: self.hgrad.map(|v| (v >= 0.0).then_some(v)),
        }
    }

    /// `recipe` with these controls in place of its global bounds and gradation.
    pub(super) fn over(&self, recipe: Recipe) -> Result<Recipe, CliError> {
        recipe
            .with_overrides(&self.overrides())
            .map_err(|e| CliError::usage(format!("{e} (--hmin and --hmax override the recipe's)")))
    }
}
