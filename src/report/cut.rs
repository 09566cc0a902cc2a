//! `report --cut x|y|z=VALUE`: the planar cut of a tetrahedral mesh, drawn as the report
//! draws a planar mesh. The cut itself (exact polygons, surface traces, the metric
//! carried to the cut's points and restricted to the plane) is the crate's `section`;
//! this file only turns it into a page: the volumes cut are the faces (filled by tag),
//! the surfaces' traces the curves (coloured by tag, named in the legend), and with a 3D
//! metric the ellipses {x in the plane : xᵀ M x = 1} of its *restriction* to the plane
//! (the metric's ellipsoid cut through its centre, not its shadow) on the overview and
//! in zooms around the smallest sizes. No conformity charts: the cut's polygons are no
//! cells of the mesh, and the lengths the metric measures are those of the 3D edges
//! (`info --metric`).

use smartmesh_formats::TaggedMesh;

use crate::history::History;
use crate::metric::Sym3;
use crate::metric_field::MetricField;
use crate::section::{self, Axis, CutPlane, SectionCounts};
use crate::topology::Topology;

use super::{fmt_sig, render_page, CutPage, Report, ReportInput, ReportOptions};

/// What a cut report is drawn from.
#[derive(Debug, Clone, Copy)]
pub struct CutInput<'a> {
    /// The mesh's name for the title (usually its path).
    pub name: &'a str,
    /// The mesh in space, with tetrahedra and tagged surface triangles.
    pub mesh: &'a TaggedMesh,
    /// A 3D metric on its vertices, if any.
    pub metric: Option<&'a MetricField<Sym3>>,
    /// The history of an adaptation run.
    pub history: Option<&'a History>,
    /// The plane.
    pub plane: CutPlane,
}

/// Why a cut cannot be drawn.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CutError {
    /// The mesh has no tetrahedron.
    #[error("no tetrahedron to cut ({other} volume cells of other kinds); --cut draws tetrahedral meshes")]
    NoTetrahedra {
        /// Volume cells of other kinds.
        other: usize,
    },
    /// The plane meets no tetrahedron in a polygon.
    #[error("the plane {plane} cuts no tetrahedron: their {axis} runs over [{lo}, {hi}]", axis = plane.axis.name())]
    Misses {
        /// The plane.
        plane: CutPlane,
        /// The tetrahedra's smallest coordinate along the plane's axis.
        lo: f64,
        /// Their largest.
        hi: f64,
    },
}

/// What a cut report drew, for `--json`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CutSummary {
    /// The plane.
    pub plane: CutPlane,
    /// The picture's horizontal and vertical axes.
    pub axes: [&'static str; 2],
    /// What the cut found.
    pub counts: SectionCounts,
    /// The cut's area (the sum of its polygons').
    pub area: f64,
    /// How the ellipses were made from the 3D metric: always "restriction" (the 2×2
    /// block of the plane's axes), when there is a metric.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ellipses: Option<&'static str>,
}

/// Draws the cut of `input.mesh` by `input.plane`.
pub fn render_cut(input: &CutInput<'_>, options: &ReportOptions) -> Result<Report, CutError> {
    let plane = input.plane;
    let s = section::cut(input.mesh, input.metric.map(MetricField::tensors), plane);
    let c = s.counts;
    if c.tetrahedra == 0 {
        return Err(CutError::NoTetrahedra { other: c.other_volume_cells });
    }
    if c.triangles + c.quads == 0 {
        let (lo, hi) = tetrahedra_range(input.mesh, plane.axis);
        return Err(CutError::Misses { plane, lo, hi });
    }
    let topology = Topology::from_mesh(&s.mesh);
    let axes = plane.axis.in_plane().map(|i| ["x", "y", "z"][i]);
    let metric = s.metric.map(|t| {
        let source = input.metric.map_or("", |m| m.source());
        MetricField::new(t, format!("{source} restricted to {plane}"))
    });
    let mut lines = vec![format!(
        "cut {plane} of {} tetrahedra: {} triangles ({} faces in the plane), {} quads, \
         {} surface segments, area {}; picture axes {} (right), {} (up)",
        c.tetrahedra,
        c.triangles,
        c.faces_in_plane,
        c.quads,
        c.trace_segments,
        fmt_sig(s.area),
        axes[0],
        axes[1]
    )];
    lines.push(match input.metric {
        Some(m) => format!(
            "ellipses: the metric {} restricted to the plane, {{x in the plane : xᵀMx = 1}} \
             (its section, not its projection), Log-Euclidean along the cut edges",
            m.source()
        ),
        None => "no metric: the cut is drawn alone".into(),
    });
    let mut skipped = Vec::new();
    if c.other_volume_cells > 0 {
        skipped.push(format!("{} volume cells that are not tetrahedra", c.other_volume_cells));
    }
    if c.degenerate > 0 {
        skipped.push(format!("{} flat or non-finite tetrahedra", c.degenerate));
    }
    if !skipped.is_empty() {
        lines.push(format!("left out of the cut: {}", skipped.join(", ")));
    }
    let summary = CutSummary {
        plane,
        axes,
        counts: c,
        area: s.area,
        ellipses: input.metric.map(|_| "restriction"),
    };
    let name = format!("{}, cut {plane}", input.name);
    let page = CutPage { lines, summary };
    let report_input = ReportInput {
        name: &name,
        mesh: &s.mesh,
        topology: &topology,
        metric: metric.as_ref(),
        plan: None,
        history: input.history,
    };
    let mut report = render_page(&report_input, options, Some(&page));
    if let Some(l) = page.lines.get(2) {
        report.notes.push(l.clone());
    }
    Ok(report)
}

/// The smallest and largest coordinate along `axis` of the tetrahedra's corners.
fn tetrahedra_range(mesh: &TaggedMesh, axis: Axis) -> (f64, f64) {
    let mut r = (f64::INFINITY, f64::NEG_INFINITY);
    for (kind, nodes, _, _) in mesh.cells() {
        if kind == smartmesh_formats::CellKind::Tetra {
            for &v in &nodes[..4] {
                let x = mesh.points[v as usize][axis.index()];
                r = (r.0.min(x), r.1.max(x));
            }
        }
    }
    r
}
