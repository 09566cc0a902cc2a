//! Remeshers the adaptation loop drives: one trait, [`Adapter`], and the external tools
//! that implement it — MMG's `mmg2d_O3`, `mmg3d_O3` and `mmgs_O3` ([`mmg::MmgAdapter`])
//! and Gmsh's BAMG on a background view ([`gmsh::GmshAdapter`]) — and smartmesh's own
//! remesher ([`native::NativeAdapter`], the default).
//!
//! Every adapter takes a tagged mesh and a metric per vertex and gives back a new tagged
//! mesh with the same physical tags, tag names and topological points, so that the same
//! recipe resolves on it (thesis 5.5: the remesher's output is the next input).
//!
//! Two dimensions, one trait: [`Adapter::adapt`] takes a planar mesh and a
//! [`Sym2`] per vertex, [`Adapter::adapt_space`] a mesh in space (tetrahedra with their
//! boundary triangles, or a triangulated surface) and a [`Sym3`] per vertex. The native
//! remesher keeps the trait's `adapt_space`, which refuses with [`AdapterError::Space`]
//! naming the tools that take such a mesh; the MMG adapter answers both, each with the
//! program of its kind (`mmg2d_O3`; `mmg3d_O3` or `mmgs_O3`), and so does Gmsh (BAMG in
//! the plane; MMG3D inside Gmsh for tetrahedra, BAMG for a surface in space:
//! [`gmsh_space`]). The 3D metric comes from the metric field (`MetricField<Sym3>`).
//!
//! - [`Controlled`]: any of them with size controls applied to the metric it is given
//!   (`--hausd` for the remeshers without that option);
//! - [`prepare`]: the mesh as the tools want it (linear triangles, no unused vertices);
//! - [`restore`]: the checks that the tags came back;
//! - [`tool`]: finding a program on `PATH` and running it ([`crate::child`]: in a process
//!   group of its own, the end of its output kept, stopped on Ctrl-C), with its output
//!   quoted on failure.

mod controlled;
pub(crate) mod gmsh;
mod gmsh_space;
pub(crate) mod mmg;
pub(crate) mod native;
pub(crate) mod prepare;
pub(crate) mod restore;
pub(crate) mod tool;

use std::path::PathBuf;

use smartmesh_formats::TaggedMesh;

use crate::metric::{Sym2, Sym3};
use crate::remesh::RemeshCounts;
use crate::topology::Topology;
pub(crate) use controlled::Controlled;

/// A remesher: a new mesh of the same domain, with the same tags, that follows `metric`
/// (one SPD tensor per vertex of `mesh`) as well as it can.
pub trait Adapter {
    /// The name the history and the messages use (`mmg2d`, `gmsh`, `native`).
    fn name(&self) -> &str;

    /// Remeshes `mesh`, whose topology the caller has built (`topology`), to `metric`.
    fn adapt(
        &self,
        mesh: &TaggedMesh,
        topology: &Topology,
        metric: &[Sym2],
    ) -> Result<Adapted, AdapterError>;

    /// Remeshes `mesh`, a mesh in space (tetrahedra, or triangles off one plane), to
    /// `metric` (one SPD 3x3 tensor per vertex). The planar remeshers refuse it, naming
    /// the tools that take it.
    fn adapt_space(&self, mesh: &TaggedMesh, metric: &[Sym3]) -> Result<Adapted, AdapterError> {
        let _ = (mesh, metric);
        Err(AdapterError::Space { adapter: self.name().to_string() })
    }
}

/// What a remesher gives back: the new mesh, and what it did when it says (the native
/// remesher's per-pass counts; the external tools report none).
#[derive(Debug, Clone, PartialEq)]
pub struct Adapted {
    /// The new mesh.
    pub mesh: TaggedMesh,
    /// The remesher's counts, which `history.json` records.
    pub stats: Option<RemeshCounts>,
}

/// Why an adapter gave no mesh.
#[derive(Debug, thiserror::Error)]
pub enum AdapterError {
    /// The external program is not on `PATH` (nor where the options said).
    #[error("`{program}` not found on PATH; {hint}")]
    NotFound {
        /// The program looked for.
        program: String,
        /// How to get it.
        hint: &'static str,
    },
    /// The program named with `--adapter-program` is not there, or cannot be run.
    #[error("`{program}` {why}; {hint}")]
    Unusable {
        /// The path given.
        program: String,
        /// `does not exist`, `is not an executable file`.
        why: &'static str,
        /// How to get the program.
        hint: &'static str,
    },
    /// The program ran and failed; its last lines are quoted.
    #[error("`{program}` failed ({status}):\n{output}")]
    Failed {
        /// The command line, shortened to the program's name and its arguments.
        program: String,
        /// Its exit status, in words.
        status: String,
        /// The end of what it printed on stderr and stdout.
        output: String,
    },
    /// smartmesh was interrupted while the program ran: it was stopped (its process
    /// group signalled, then killed) and its temporary directory removed.
    #[error("`{program}` was stopped: smartmesh was interrupted")]
    Interrupted {
        /// The program's name.
        program: String,
    },
    /// The program could not be started, or its files not written or read.
    #[error("{what}: {source}")]
    Io {
        /// What was being done.
        what: String,
        /// The error.
        source: std::io::Error,
    },
    /// A file for the tool could not be written, or its output not read back.
    #[error("{0}")]
    Format(#[from] smartmesh_formats::Error),
    /// The mesh cannot be given to the tool (no triangle, metric of the wrong length).
    #[error("{0}")]
    Input(String),
    /// The metric asks for more vertices than the limit allows (valid input, refused).
    #[error("{0}")]
    Limit(String),
    /// Periodic sides (frozen curves) asked of a remesher that places boundary vertices by
    /// its own rules.
    #[error("periodic sides (a recipe's PERIODIC) are kept matching by the native remesher only; the {adapter} adapter places boundary vertices by its own rules")]
    Periodic {
        /// The adapter chosen.
        adapter: &'static str,
    },
    /// A mesh in space given to a planar remesher.
    #[error("the {adapter} adapter remeshes planar meshes only; a tetrahedral mesh goes to mmg3d (mmg3d_O3), a triangulated surface in space to mmgs (mmgs_O3), either to Gmsh: --adapter mmg3d|mmgs|gmsh")]
    Space {
        /// The adapter chosen.
        adapter: String,
    },
    /// A planar mesh, or a mesh of the other kind, given to an MMG adapter of another
    /// dimension (a surface to mmg3d, tetrahedra to mmgs or mmg2d).
    #[error("{0}")]
    Kind(String),
    /// An option the chosen remesher does not take.
    #[error("{option} is an option of the MMG adapters (mmg2d, mmg3d, mmgs); the {adapter} adapter does not take it")]
    Option {
        /// The option, as on the command line.
        option: &'static str,
        /// The adapter chosen.
        adapter: &'static str,
    },
    /// The tool's result lost something the loop needs (a tag, a topological point) or
    /// holds something smartmesh did not give it.
    #[error("{program} output: {what}")]
    Lost {
        /// The tool.
        program: String,
        /// What is missing or unexpected.
        what: String,
    },
}

/// The remeshers `smartmesh adapt --adapter` knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdapterKind {
    /// smartmesh's own anisotropic remesher.
    Native,
    /// MMG's `mmg2d_O3`.
    Mmg2d,
    /// Gmsh on a background view: BAMG in the plane and on surfaces, MMG3D inside
    /// Gmsh for tetrahedra.
    Gmsh,
    /// MMG's `mmg3d_O3`: tetrahedral meshes in space.
    Mmg3d,
    /// MMG's `mmgs_O3`: triangulated surfaces in space.
    Mmgs,
}

impl AdapterKind {
    /// The name on the command line and in `history.json`.
    pub fn name(self) -> &'static str {
        match self {
            AdapterKind::Native => "native",
            AdapterKind::Mmg2d => "mmg2d",
            AdapterKind::Gmsh => "gmsh",
            AdapterKind::Mmg3d => "mmg3d",
            AdapterKind::Mmgs => "mmgs",
        }
    }

    /// Whether MMG runs (and reads its own options: `-hgrad`, `-nosurf`, `-ar`, `-nr`,
    /// `-hmin`, `-hmax`).
    pub fn is_mmg(self) -> bool {
        matches!(self, AdapterKind::Mmg2d | AdapterKind::Mmg3d | AdapterKind::Mmgs)
    }

    /// Whether the remesher takes only meshes in space ([`Adapter::adapt_space`]): mmg3d
    /// and mmgs. (Gmsh takes both kinds; mmg2d and native planar meshes only.)
    pub fn is_space(self) -> bool {
        matches!(self, AdapterKind::Mmg3d | AdapterKind::Mmgs)
    }
}

/// Options of the external adapters; each reads the ones that concern it.
#[derive(Debug, Clone, Default)]
pub struct AdapterOptions {
    /// The program to run instead of the one found on `PATH`.
    pub program: Option<PathBuf>,
    /// MMG `-hgrad`: gradation MMG applies to the metric (`-1` turns it off; MMG's
    /// default, 1.3, when unset).
    pub hgrad: Option<f64>,
    /// MMG `-hausd`: largest distance between a curved boundary and its edges (MMG's
    /// default, 0.01, when unset).
    pub hausd: Option<f64>,
    /// MMG `-nosurf`: leave the boundary as it is (no point added or moved there).
    pub nosurf: bool,
    /// MMG `-hmin`: the smallest edge length MMG makes (its own bound on the metric).
    pub hmin: Option<f64>,
    /// MMG `-hmax`: the largest edge length MMG makes.
    pub hmax: Option<f64>,
    /// MMG `-ar`: the dihedral angle, in degrees, above which an edge is a ridge (MMG's
    /// default, 45°, when unset).
    pub ridge_angle: Option<f64>,
    /// MMG `-nr`: no ridge detection (only the edges and references given are kept).
    pub no_ridges: bool,
    /// Further arguments passed to the program as they are.
    pub extra_args: Vec<String>,
    /// Vertices of the input geometry that every remeshing keeps (the native remesher's
    /// [`RemeshOptions::keep_points`](crate::remesh::RemeshOptions::keep_points)); the
    /// external tools place boundary points by their own rules and do not read it.
    pub keep_points: Vec<[f64; 2]>,
    /// Periodic pairs every remeshing keeps matched (the native remesher's
    /// [`RemeshOptions::periodic`](crate::remesh::RemeshOptions::periodic)); the external
    /// tools do not read it, and [`adapter`] refuses them a non-empty list.
    pub periodic: Vec<crate::periodic::PeriodicPair>,
    /// The native remesher's [`RemeshOptions::max_vertices`](crate::remesh::RemeshOptions::max_vertices)
    /// (the adaptation loop checks the same limit before every remeshing, whatever the
    /// remesher).
    pub max_vertices: Option<usize>,
}

/// The adapter of `kind`: the program is looked up now, so that a missing tool is said
/// before any work. The one place that knows which remeshers exist.
pub fn adapter(
    kind: AdapterKind,
    options: AdapterOptions,
) -> Result<Box<dyn Adapter>, AdapterError> {
    if kind != AdapterKind::Native && !options.periodic.is_empty() {
        return Err(AdapterError::Periodic { adapter: kind.name() });
    }
    if !kind.is_mmg() {
        // --hausd is every remesher's (below); MMG's own gradation, bounds, ridge
        // detection and -nosurf are not.
        let mmg_only = [
            ("--hgrad", options.hgrad.is_some()),
            ("--nosurf", options.nosurf),
            ("--hmin", options.hmin.is_some()),
            ("--hmax", options.hmax.is_some()),
            ("--ridge-angle", options.ridge_angle.is_some()),
            ("--no-ridges", options.no_ridges),
        ];
        if let Some(&(option, _)) = mmg_only.iter().find(|o| o.1) {
            return Err(AdapterError::Option { option, adapter: kind.name() });
        }
        if let Some(hausd) = options.hausd {
            let controls =
                crate::size_controls::SizeControls { hausd: Some(hausd), ..Default::default() };
            // The native remesher also bounds its coarsening of curves by it.
            let inner: Box<dyn Adapter> = if kind == AdapterKind::Native {
                Box::new(native_adapter(options, Some(hausd)))
            } else {
                adapter(kind, AdapterOptions { hausd: None, ..options })?
            };
            return Ok(Box::new(Controlled { inner, controls }));
        }
    }
    match kind {
        AdapterKind::Native => Ok(Box::new(native_adapter(options, None))),
        AdapterKind::Mmg2d => Ok(Box::new(mmg::MmgAdapter::new(mmg::Tool::Mmg2d, options)?)),
        AdapterKind::Mmg3d => Ok(Box::new(mmg::MmgAdapter::new(mmg::Tool::Mmg3d, options)?)),
        AdapterKind::Mmgs => Ok(Box::new(mmg::MmgAdapter::new(mmg::Tool::Mmgs, options)?)),
        AdapterKind::Gmsh => Ok(Box::new(gmsh::GmshAdapter::new(options)?)),
    }
}

/// The native remesher with the loop's options; `hausd` bounds how far a coarsening
/// takes a boundary edge from its curve (the remesher's default when `None`).
fn native_adapter(options: AdapterOptions, hausd: Option<f64>) -> native::NativeAdapter {
    native::NativeAdapter {
        options: crate::remesh::RemeshOptions {
            keep_points: options.keep_points,
            periodic: options.periodic,
            max_vertices: options.max_vertices,
            hausd,
            // The loop measures every mesh against the recipe's own field.
            measure: false,
            ..Default::default()
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mmg_options_are_refused_by_the_other_remeshers_and_space_meshes_by_the_planar_ones() {
        for kind in [AdapterKind::Native, AdapterKind::Gmsh] {
            let options = AdapterOptions { ridge_angle: Some(30.0), ..Default::default() };
            let e = adapter(kind, options).err().map(|e| e.to_string()).unwrap_or_default();
            assert!(e.contains("--ridge-angle is an option of the MMG adapters"), "{e}");
        }
        let native = adapter(AdapterKind::Native, AdapterOptions::default()).unwrap();
        let e = native.adapt_space(&TaggedMesh::new(), &[]).unwrap_err().to_string();
        assert!(e.contains("native adapter") && e.contains("mmg3d") && e.contains("mmgs"), "{e}");
        // The wrapper of --hausd refuses the same way, naming the remesher it wraps.
        let options = AdapterOptions { hausd: Some(0.01), ..Default::default() };
        let controlled = adapter(AdapterKind::Native, options).unwrap();
        let e = controlled.adapt_space(&TaggedMesh::new(), &[]).unwrap_err().to_string();
        assert!(e.contains("native adapter"), "{e}");
        assert!(AdapterKind::Mmg3d.is_space() && !AdapterKind::Mmg2d.is_space());
    }
}
