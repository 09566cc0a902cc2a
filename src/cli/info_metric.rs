//! What `smartmesh info --metric` adds for a mesh in space (a 3D metric, measured as the
//! UGAWG does) and the lines of the UGAWG measures ([`smartmesh::Ugawg`]), printed for a
//! 3D metric and, with `--measures ugawg`, for a 2D one.

use std::fmt::Write as _;
use std::path::Path;

use smartmesh::formats::words::count;
use smartmesh::formats::TaggedMesh;
use smartmesh::metric::Sym3;
use smartmesh::{MeshSummary, MetricField, Ugawg};

use super::info::fmt_g;
use super::CliError;

/// Whether `mesh` lives in space: it has volume cells, or its vertices are not all on one
/// plane z = constant. Such a mesh is measured against a 3D metric.
pub(super) fn in_space(mesh: &TaggedMesh) -> bool {
    let volume = has_volume(mesh);
    let z0 = mesh.points.first().map_or(0.0, |p| p[2]);
    volume || mesh.points.iter().any(|p| p[2] != z0)
}

/// Whether `mesh` has a volume cell, which a 3D metric's complexity is taken over.
fn has_volume(mesh: &TaggedMesh) -> bool {
    mesh.blocks.iter().any(|b| b.kind.dim() == 3 && !b.is_empty())
}

/// `summary` with the UGAWG measures of `mesh` (read from `file`) against the 3D metric
/// of `metric` (or of the mesh's own `metric` array; a bad own array is a warning), and,
/// on volume cells, the vertex count a unit mesh of it has
/// ([`smartmesh::expected_vertices`]).
pub(super) fn with_metric_3d(
    summary: MeshSummary,
    mesh: &TaggedMesh,
    file: &Path,
    metric: Option<&Path>,
) -> Result<MeshSummary, CliError> {
    match MetricField::<Sym3>::load_field(mesh, file, metric) {
        Ok(Some(m)) => {
            let mut summary = summary.with_metric_3d(mesh, m.tensors(), m.source().to_string());
            if let Some(s) = summary.metric.as_mut().filter(|_| has_volume(mesh)) {
                s.expected_vertices = Some(m.expected_vertices(mesh));
            }
            Ok(summary)
        }
        Ok(None) => Ok(summary),
        Err(e) if metric.is_none() => {
            super::ui::warn(&format!("no metric figures: {e}"));
            Ok(summary)
        }
        Err(e) => Err(e.into()),
    }
}

/// The lines of the UGAWG measures of the metric found at `source`, and the vertex count
/// a unit mesh of it has when `expected` is known.
pub(super) fn render_ugawg(o: &mut String, source: &str, u: &Ugawg, expected: Option<f64>) {
    let _ = writeln!(
        o,
        "  ugawg       {} metric {source}: {}, {:.1}% of metric length in [{:.4}, {:.4}]",
        if u.dimension == 3 { "3D" } else { "2D" },
        count(u.edges, "edge", "edges"),
        100.0 * u.conforming_share,
        smartmesh::metric::length::CONFORMING[0],
        smartmesh::metric::length::CONFORMING[1],
    );
    let _ = writeln!(
        o,
        "              edge length (log-mean of the ends') min {}, max {}, mean {}, geometric mean {}",
        fmt_g(u.edge_length_range[0]),
        fmt_g(u.edge_length_range[1]),
        fmt_g(u.mean_edge_length),
        fmt_g(u.geometric_mean_edge_length)
    );
    let plural = if u.cell == "tetrahedron" { "tetrahedra" } else { "triangles" };
    let left_out = if u.left_out > 0 {
        format!(" ({} other cells left out)", u.left_out)
    } else {
        String::new()
    };
    let _ = writeln!(
        o,
        "              mean ratio over {}: min {:.4}, mean {:.4}, geometric mean {:.4}, {} flat or inverted{left_out}",
        count(u.cells, u.cell, plural),
        u.min_quality,
        u.mean_quality,
        u.geometric_mean_quality,
        u.non_positive
    );
    if let Some(n) = expected {
        let _ = writeln!(
            o,
            "              a unit mesh of this metric has about {} vertices (complexity ∫ √det M)",
            smartmesh::metric::complexity::format_count(n)
        );
    }
}
