//! Gmsh as an [`Adapter`]: the mesh becomes a discrete model, the metric a background
//! view, and BAMG — Gmsh's only 2D algorithm that honours an anisotropic tensor view
//! (DESIGN.md) — meshes the model again. This file is the planar path
//! ([`Adapter::adapt`]); a mesh in space ([`Adapter::adapt_space`]: tetrahedra through
//! MMG3D inside Gmsh, a surface in space through BAMG) is [`super::gmsh_space`]'s, with
//! what was measured of Gmsh's 3D algorithms.
//!
//! One run, in a temporary directory that is removed afterwards (also when smartmesh is
//! interrupted: the program is stopped, see [`super::tool`]):
//! 1. the mesh is [prepared](super::prepare) and written as `in.msh` (MSH 4.1, with its
//!    physical groups in `$Entities`), the metric as `bgm.pos` (a `TT` tensor view);
//! 2. `gmsh remesh.geo -setnumber Mesh.Algorithm 7 -setnumber
//!    Mesh.MeshSizeExtendFromBoundary 0 -setnumber Mesh.MeshSizeFromPoints 0 -setnumber
//!    Mesh.MeshSizeFromCurvature 0 [extra arguments…] -v 2 -nopopup -parse_and_exit`
//!    runs the script below, which merges the mesh, rebuilds the topology and a
//!    geometry from it (`CreateTopology; CreateGeometry;`: Gmsh's discrete entities
//!    keep their physical groups), takes the view as background mesh and meshes in 2D;
//! 3. `out.msh` is read back. Gmsh writes only the cells of physical groups; cells
//!    without a physical tag travel in a group of their own (`smartmesh:untagged`, see
//!    the formats crate's `gmsh` writer) and come back untagged, so every tag comes
//!    back as it was.
//!
//! Extra arguments follow smartmesh's on Gmsh's command line, so `-setnumber` there
//! overrides the settings above.
//!
//! Reproducibility: the same command in the same environment gives the same mesh, but
//! Gmsh 4.15's result was seen to change slightly with the process environment (the
//! same run under `env -i` gave another vertex count), which MMG's does not. Each Gmsh
//! remeshing also starts from the previous mesh's boundary polylines (a discrete
//! model), so curved boundaries are not brought back to the CAD curve.

use std::path::Path;

use smartmesh_formats::{read_path, CellKind, Format, TaggedMesh, WriteOptions};

use super::prepare::prepare;
use super::restore::{attach_names, ensure_tags_kept};
use super::tool::{find_program, quote, run};
use super::{Adapted, Adapter, AdapterError, AdapterOptions};
use crate::metric::{Sym2, Sym3};
use crate::metric_field::MetricField;
use crate::topology::Topology;

/// The program looked up on `PATH`.
pub(crate) const PROGRAM: &str = "gmsh";

const HINT: &str = "install Gmsh (`pip install gmsh` puts gmsh on PATH) or name the executable with --adapter-program";

/// The script Gmsh runs.
pub(crate) const SCRIPT: &str =
    "// Written by smartmesh: remesh in.msh to the background view bgm.pos with BAMG.
Merge \"in.msh\";
CreateTopology;
CreateGeometry;
Merge \"bgm.pos\";
Background Mesh View[0];
Mesh 2;
Mesh.MshFileVersion = 4.1;
Save \"out.msh\";
";

/// Gmsh with BAMG and its options.
#[derive(Debug, Clone)]
pub(crate) struct GmshAdapter {
    program: std::path::PathBuf,
    options: AdapterOptions,
}

impl GmshAdapter {
    /// Finds the program (`options.program`, else `gmsh` on `PATH`).
    pub(crate) fn new(options: AdapterOptions) -> Result<GmshAdapter, AdapterError> {
        let program = find_program(PROGRAM, options.program.as_deref(), HINT)?;
        Ok(GmshAdapter { program, options })
    }

    /// The whole command line after the program.
    fn args(&self) -> Vec<String> {
        let mut a = vec!["remesh.geo".to_string()];
        for (name, value) in [
            ("Mesh.Algorithm", "7"),
            ("Mesh.MeshSizeExtendFromBoundary", "0"),
            ("Mesh.MeshSizeFromPoints", "0"),
            ("Mesh.MeshSizeFromCurvature", "0"),
        ] {
            a.extend(["-setnumber".to_string(), name.to_string(), value.to_string()]);
        }
        a.extend(self.options.extra_args.iter().cloned());
        a.extend(["-v", "2", "-nopopup", "-parse_and_exit"].iter().map(|s| s.to_string()));
        a
    }
}

impl Adapter for GmshAdapter {
    fn name(&self) -> &str {
        "gmsh"
    }

    fn adapt(
        &self,
        mesh: &TaggedMesh,
        _topology: &Topology,
        metric: &[Sym2],
    ) -> Result<Adapted, AdapterError> {
        let prepared = prepare(mesh, metric)?;
        let dir =
            tempfile::Builder::new().prefix("smartmesh-gmsh-").tempdir().map_err(|source| {
                AdapterError::Io { what: "creating a temporary directory".into(), source }
            })?;
        // zz = the larger in-plane eigenvalue (1/h_min²), as `smartmesh size` writes views:
        // SPD in 3D, and never a size larger than the in-plane ones.
        let pos =
            MetricField::new(prepared.metric(metric), "the metric").pos_bytes(&prepared.mesh)?;
        let msh =
            smartmesh_formats::write_bytes(Format::Gmsh, &prepared.mesh, &WriteOptions::default())?;
        let inputs =
            [("in.msh", &msh.main[..]), ("bgm.pos", &pos[..]), ("remesh.geo", SCRIPT.as_bytes())];
        let mut result = run_script(
            &self.program,
            &self.args(),
            dir.path(),
            &inputs,
            CellKind::Triangle,
            "triangle",
        )?;
        result.point_data.clear();
        result.cell_data.clear();
        for p in &mut result.points {
            p[2] = 0.0;
        }
        result.coordinate_dim = 2;
        attach_names(&prepared.mesh, &mut result);
        ensure_tags_kept(self.name(), &prepared.mesh, &result)?;
        Ok(Adapted { mesh: result, stats: None })
    }

    fn adapt_space(&self, mesh: &TaggedMesh, metric: &[Sym3]) -> Result<Adapted, AdapterError> {
        super::gmsh_space::adapt_space(&self.program, &self.options.extra_args, mesh, metric)
    }
}

/// Writes `bytes` as `dir/name`.
/// Writes `inputs` (name, bytes) in `dir`, runs the Gmsh at `program` with `args` there
/// and reads its `out.msh`. Gmsh may report an error and still exit with 0: no file, or
/// no cell of `kind` (`what`, for the message), is a failure quoted the same way as an
/// exit status.
pub(super) fn run_script(
    program: &Path,
    args: &[String],
    dir: &Path,
    inputs: &[(&str, &[u8])],
    kind: CellKind,
    what: &str,
) -> Result<TaggedMesh, AdapterError> {
    for (name, bytes) in inputs {
        write(dir, name, bytes)?;
    }
    let output = run(program, args, dir)?;
    let out_path = dir.join("out.msh");
    let failed = |why: &str| AdapterError::Failed {
        program: format!("{PROGRAM} remesh.geo"),
        status: why.to_string(),
        output: quote(&output),
    };
    if !out_path.exists() {
        return Err(failed("it wrote no out.msh"));
    }
    let result = read_path(&out_path, Some(Format::Gmsh))?;
    if result.num_cells_of(kind) == 0 {
        return Err(failed(&format!(
            "its out.msh has no {what} (Gmsh saves only the elements of physical groups; its output says whether meshing failed)"
        )));
    }
    Ok(result)
}

pub(super) fn write(dir: &Path, name: &str, bytes: &[u8]) -> Result<(), AdapterError> {
    std::fs::write(dir.join(name), bytes).map_err(|source| AdapterError::Io {
        what: format!("writing {name} in {}", dir.display()),
        source,
    })
}
