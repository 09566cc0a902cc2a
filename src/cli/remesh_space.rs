//! `smartmesh remesh` on a mesh in space: a tetrahedral mesh through `mmg3d_O3`, a
//! triangulated surface through `mmgs_O3` ([`smartmesh::Adapter::adapt_space`]), to a
//! 3D metric on the mesh's vertices (a [`smartmesh::MetricField`] of `Sym3`). `remesh.rs`
//! parses the arguments and routes here; this file only reads, runs and writes.

use std::path::Path;
use std::time::Instant;

use smartmesh::formats::{CellKind, Format, TaggedMesh};
use smartmesh::metric::Sym3;
use smartmesh::{adapter, AdapterKind, AdapterOptions, MetricField};

use super::output::{shown, MeshOutputArgs};
use super::{print_stdout, ui, CliError};

/// One remeshing in space, as the command line asked for it.
pub(super) struct SpaceRemesh<'a> {
    /// The input mesh, read and made linear.
    pub mesh: TaggedMesh,
    /// Its path (for messages).
    pub mesh_path: &'a Path,
    /// `--metric`, else the mesh's own point data `metric`.
    pub metric: Option<&'a Path>,
    /// `-o`.
    pub output: &'a Path,
    /// The output format.
    pub to: Format,
    /// How to write it.
    pub output_format: &'a MeshOutputArgs,
    /// mmg3d or mmgs.
    pub kind: AdapterKind,
    /// MMG's options.
    pub options: AdapterOptions,
    /// `--json`.
    pub json: bool,
    /// What the reader could not keep.
    pub read_notes: Vec<String>,
    /// When the command started.
    pub t0: Instant,
}

/// Counts of a mesh in space, for the summary.
#[derive(serde::Serialize)]
struct Counts {
    vertices: usize,
    tetrahedra: usize,
    triangles: usize,
    lines: usize,
}

impl Counts {
    fn of(mesh: &TaggedMesh) -> Counts {
        Counts {
            vertices: mesh.points.len(),
            tetrahedra: mesh.num_cells_of(CellKind::Tetra),
            triangles: mesh.num_cells_of(CellKind::Triangle),
            lines: mesh.num_cells_of(CellKind::Line),
        }
    }
}

#[derive(serde::Serialize)]
struct Summary<'a> {
    adapter: &'a str,
    input: Counts,
    output: Counts,
    seconds: f64,
    read_notes: &'a [String],
}

/// Runs the remeshing and writes the result.
pub(super) fn run(r: SpaceRemesh<'_>) -> Result<(), CliError> {
    let name = r.mesh_path.display().to_string();
    let metric = MetricField::<Sym3>::load_field(&r.mesh, r.mesh_path, r.metric)
        .map_err(super::remesh::metric_error)?
        .ok_or_else(|| {
            CliError::usage(format!(
                "{name}: no point data `metric` (give the metric with --metric: a .sol/.solb, \
                 a .pos view, or a mesh file with point data `metric`)"
            ))
        })?
        .into_tensors();
    let remesher = adapter(r.kind, r.options)?;
    let adapted = remesher
        .adapt_space(&r.mesh, &metric)
        .map_err(|e| CliError::context(format!("{name}: {e}"), e))?;
    let out = adapted.mesh;
    r.output_format.write(r.output, &out, r.to)?;
    let seconds = r.t0.elapsed();
    if r.json {
        let s = Summary {
            adapter: remesher.name(),
            input: Counts::of(&r.mesh),
            output: Counts::of(&out),
            seconds: seconds.as_secs_f64(),
            read_notes: &r.read_notes,
        };
        print_stdout(&(serde_json::to_string_pretty(&s)? + "\n"))?;
    }
    let (i, o) = (Counts::of(&r.mesh), Counts::of(&out));
    ui::done(
        "remesh",
        &format!(
            "wrote {} with {} ({} points, {} tetrahedra, {} triangles, from {} points, {} tetrahedra, {} triangles) in {}",
            shown(r.output),
            remesher.name(),
            o.vertices,
            o.tetrahedra,
            o.triangles,
            i.vertices,
            i.tetrahedra,
            i.triangles,
            ui::seconds(seconds)
        ),
    );
    Ok(())
}
