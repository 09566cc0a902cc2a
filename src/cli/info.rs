//! `smartmesh info FILE`: counts, bounding box, tags, topology, fields, quality; for a mesh
//! with quads, their quality, the layers of a skin and the validity of the mixed mesh.

use std::fmt::Write as _;
use std::path::PathBuf;

use clap::Args;
use smartmesh::formats::words::count;
use smartmesh::formats::Format;
use smartmesh::layer::stats::{quad_quality, QuadQuality};
use smartmesh::MeshSummary;
use smartmesh::MetricField;
use smartmesh::Topology;
use smartmesh::{check_mesh, Validity};

use super::{parse_format, print_stdout, CliError};

/// Print what a mesh file holds: counts, bounding box, tags and their names, the
/// topology recovered from the tags, data arrays and element quality.
#[derive(Debug, Args)]
#[command(after_help = "Examples:
  smartmesh info naca0012.msh
  smartmesh info --json square.1.ele | jq .topology.curves
  smartmesh info adapted.msh --metric field.vtu
  smartmesh info adapted.mesh --metric adapted.sol --measures ugawg
  smartmesh info cube.meshb --metric cube-metric.solb   # tetrahedra: UGAWG measures
  smartmesh info box.msh --ridge-angle 30             # a 3D mesh: ridges above 30°
  smartmesh info adapted.msh --recipe recipe.toml    # the match of its periodic sides
  cat mesh.vtu | smartmesh info --from vtu -")]
#[command(mut_arg("recipe", |a| a.help("A recipe whose PERIODIC pairs are measured on FILE: vertex counts and the largest distance between a vertex's image and its partner (exit 2 when the sides are not images of each other)")))]
pub(super) struct InfoArgs {
    /// Mesh file (`-` for stdin, with --from).
    file: PathBuf,
    /// Input format, when the extension does not tell (gmsh, vtk, vtu, triangle, obj, medit).
    #[arg(long, value_parser = parse_format)]
    from: Option<Format>,
    /// Print a JSON document instead of text.
    #[arg(long)]
    json: bool,
    /// Read a Medit mesh without the .sol/.solb beside it (one MMG cannot read, or of
    /// another mesh).
    #[arg(long)]
    no_solution: bool,
    /// A metric on FILE's vertices (a mesh file with point data `metric`, a .sol/.solb in
    /// FILE's vertex order, a Gmsh data-only .msh, or a .pos view): adds the share of
    /// edges of metric length in [1/√2, √2] and the metric quality (FILE's own `metric`
    /// array is used when this is not given). On a mesh in space (volume cells, or
    /// vertices off the plane z = constant) the metric is 3D (9 components, ParaView's 6,
    /// or a 3D .sol in MMG's order m11 m12 m22 m13 m23 m33) and measured as the UGAWG does.
    #[arg(long, short = 'm')]
    metric: Option<PathBuf>,
    /// Which measures of the metric to print besides the default ones on a planar mesh:
    /// `ugawg` adds the UGAWG's (edge length by the log-mean of the ends' lengths, its
    /// min, max, mean and geometric mean, and the mean-ratio quality), as the published
    /// benchmark tables and nasa/refine's `ref_histogram` give them (always given in 3D).
    #[arg(long, value_enum)]
    measures: Option<Measures>,
    /// In a mesh in space, mesh edges inside one surface across which the cells' normals
    /// turn by more than this angle (degrees, in [0, 180]) are ridges: topological curves
    /// (MMG's `-ar`).
    #[arg(long, value_name = "DEG", default_value_t = smartmesh::DEFAULT_RIDGE_ANGLE_DEG)]
    ridge_angle: f64,
    /// The recipe whose periodic pairs are measured (its help is set above).
    #[command(flatten)]
    pub recipe: super::RecipeInput,
}

/// The measures `--measures` adds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Measures {
    /// The UGAWG's measures.
    Ugawg,
}

/// Runs `info`.
pub(super) fn run(args: InfoArgs) -> Result<(), CliError> {
    let (mesh, read_notes) = super::read_mesh_noted(&args.file, args.from, args.no_solution)?;
    // Described whole, but not as if it were flat ([`smartmesh::plane`]); a 3D mesh is
    // what `info` expects, no warning.
    if let Err(e @ smartmesh::NotPlanar::OffPlane { .. }) = smartmesh::plane(&mesh) {
        super::ui::warn(&format!(
            "{}: {e}; lengths and areas are measured in space",
            args.file.display()
        ));
    }
    if !(0.0..=180.0).contains(&args.ridge_angle) {
        return Err(CliError::usage(format!(
            "--ridge-angle {}: expected an angle in degrees in [0, 180]",
            args.ridge_angle
        )));
    }
    let options = smartmesh::TopologyOptions { ridge_angle_deg: args.ridge_angle };
    let topo = Topology::from_mesh_with(&mesh, &options);
    let mut summary = MeshSummary::of(&mesh, &topo);
    if super::info_metric::in_space(&mesh) {
        summary =
            super::info_metric::with_metric_3d(summary, &mesh, &args.file, args.metric.as_deref())?;
    } else {
        match MetricField::load(&mesh, &args.file, args.metric.as_deref()) {
            Ok(Some(m)) => {
                summary = summary.with_metric(&mesh, m.tensors(), m.source().to_string());
                if args.measures == Some(Measures::Ugawg) {
                    summary = summary.with_ugawg(&mesh, m.tensors());
                }
            }
            Ok(None) => {}
            // The file's own array is only looked at by the way: a bad one is a warning.
            Err(e) if args.metric.is_none() => super::ui::warn(&format!("no metric figures: {e}")),
            Err(e) => return Err(e.into()),
        }
    }
    // Quad figures and validity are taken at the corners, as the topology's. The validity
    // of a mixed planar mesh means nothing for the faces of a 3D mesh.
    let quads = if summary.solid.is_some() {
        None
    } else if mesh.blocks.iter().any(|b| b.kind.is_second_order()) {
        let mut linear = mesh.clone();
        linear.linearise();
        QuadReport::of(&linear)
    } else {
        QuadReport::of(&mesh)
    };
    let periodic = match &args.recipe.recipe {
        None => Vec::new(),
        Some(_) => {
            let recipe = args.recipe.read()?;
            let pairs: Vec<smartmesh::periodic::PeriodicPair> = recipe.periodic_pairs();
            smartmesh::periodic::check_all(&mesh, &pairs)
                .map_err(|e| CliError::usage(format!("{e} (mesh {})", args.file.display())))?
        }
    };
    if args.json {
        let j = InfoJson {
            summary: &summary,
            read_notes: &read_notes,
            quads: quads.as_ref(),
            periodic: &periodic,
        };
        let mut s = serde_json::to_string_pretty(&j)?;
        s.push('\n');
        return print_stdout(&s);
    }
    let mut text = render(&args.file.display().to_string(), &summary);
    if let Some(q) = &quads {
        text.push_str(&render_quads(q));
    }
    for m in &periodic {
        let line = m.to_string();
        text.push_str(&format!("  periodic    {}\n", line.trim_start_matches("periodic ")));
    }
    print_stdout(&text)
}

/// The JSON `info` prints: the summary, and the quads' figures when there are quads.
#[derive(serde::Serialize)]
struct InfoJson<'a> {
    #[serde(flatten)]
    summary: &'a MeshSummary,
    /// What the reader could not keep (also on stderr, which `-q` silences).
    read_notes: &'a [String],
    #[serde(skip_serializing_if = "Option::is_none")]
    quads: Option<&'a QuadReport>,
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    periodic: &'a [smartmesh::periodic::PairMatch],
}

/// What `info` says of a mesh with quads: their quality, the skin's layers, and whether
/// the mixed mesh is valid.
#[derive(serde::Serialize)]
struct QuadReport {
    quality: QuadQuality,
    validity: Validity,
}

impl QuadReport {
    fn of(mesh: &smartmesh::formats::TaggedMesh) -> Option<QuadReport> {
        let mut quality = quad_quality(mesh)?;
        // A skin is quads along walls beside triangles; in a mesh of quads alone every
        // quad along a wall would start a "layer" of nothing.
        if mesh.num_cells_of(smartmesh::formats::CellKind::Triangle) == 0 {
            quality.layers.clear();
        }
        Some(QuadReport { quality, validity: check_mesh(mesh) })
    }
}

fn render_quads(r: &QuadReport) -> String {
    let mut o = String::new();
    let q = &r.quality;
    let _ = writeln!(
        o,
        "  quads       {}: scaled Jacobian min {:.4}, skewness max {:.4}, aspect ratio [{}, {}] mean {}",
        q.quads,
        q.min_scaled_jacobian,
        q.max_skewness,
        fmt_g(q.aspect_ratio[0]),
        fmt_g(q.aspect_ratio[2]),
        fmt_g(q.aspect_ratio[1])
    );
    let in_layers: usize = q.layers.iter().map(|l| l.quads).sum();
    if !q.layers.is_empty() {
        let _ = writeln!(
            o,
            "  layers      {} from the walls ({}; height mean [min, max], ratio to the layer below)",
            q.layers.len(),
            count(in_layers, "quad", "quads")
        );
        for (k, l) in q.layers.iter().enumerate() {
            let ratio = l
                .ratio
                .map(|r| format!(", ratio {} [{}, {}]", fmt_g(r[1]), fmt_g(r[0]), fmt_g(r[2])))
                .unwrap_or_default();
            let _ = writeln!(
                o,
                "    layer {:<4} {}, height {} [{}, {}]{ratio}",
                k + 1,
                count(l.quads, "quad", "quads"),
                fmt_g(l.height[1]),
                fmt_g(l.height[0]),
                fmt_g(l.height[2])
            );
        }
    }
    let v = &r.validity;
    if v.is_valid() {
        let _ = writeln!(
            o,
            "  validity    valid: every cell positive at its corners, no overlap, no hanging vertex"
        );
    } else {
        let _ = writeln!(o, "  validity    NOT VALID: {}", v.problems().join("; "));
    }
    o
}

/// A figure as `info` prints it: six significant digits, no `-0` (see
/// `smartmesh::formats::words::number`).
pub(super) fn fmt_g(v: f64) -> String {
    smartmesh::formats::words::number(v)
}

pub(super) fn named(tag: Option<i32>, name: &Option<String>) -> String {
    match (tag, name) {
        (Some(t), Some(n)) => format!("{t} \"{n}\""),
        (Some(t), None) => t.to_string(),
        (None, _) => "(untagged)".into(),
    }
}

/// The text report.
fn render(file: &str, s: &MeshSummary) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "{file}");
    let _ = write!(o, "  points      {}", s.points);
    if s.unused_points > 0 {
        let _ = write!(o, " ({} used by no cell)", s.unused_points);
    }
    let _ = writeln!(o, ", {}D coordinates", s.coordinate_dim);
    let cells: Vec<String> = s.cells.iter().map(|(k, n)| format!("{n} {k}")).collect();
    let _ = writeln!(
        o,
        "  cells       {}",
        if cells.is_empty() { "none".into() } else { cells.join(", ") }
    );
    if let Some([lo, hi]) = s.bounding_box {
        let _ = writeln!(
            o,
            "  bounds      x [{}, {}]  y [{}, {}]{}",
            fmt_g(lo[0]),
            fmt_g(hi[0]),
            fmt_g(lo[1]),
            fmt_g(hi[1]),
            if lo[2] != hi[2] {
                format!("  z [{}, {}]", fmt_g(lo[2]), fmt_g(hi[2]))
            } else {
                String::new()
            }
        );
    }
    if !s.tags.is_empty() {
        let _ = writeln!(o, "  tags (dimension, tag, name: cells)");
        for t in &s.tags {
            let _ = writeln!(
                o,
                "    {}D {:>6} {:<20} {}{}",
                t.dim,
                t.tag,
                t.name.as_deref().map(|n| format!("\"{n}\"")).unwrap_or_default(),
                t.cells,
                if t.elementary { " (elementary tag: no physical tag)" } else { "" }
            );
        }
    }
    let topo = &s.topology;
    if let Some(solid) = &s.solid {
        super::info3d::render_solid(&mut o, s, solid);
    }
    if topo.ridge_angle_deg.is_some() {
        super::info3d::render_space_topology(&mut o, s);
    } else {
        let _ = writeln!(
            o,
            "  topology    {}, {}, {}",
            count(topo.points.len(), "point", "points"),
            count(topo.curves.len(), "curve", "curves"),
            count(topo.faces.len(), "face", "faces")
        );
        render_planar_topology(&mut o, s);
    }
    for (label, fields) in [("point data", &s.point_data), ("cell data", &s.cell_data)] {
        for f in fields.iter() {
            let range = f
                .range
                .map(|[a, b]| format!(" in [{}, {}]", fmt_g(a), fmt_g(b)))
                .unwrap_or_default();
            let nan = if f.nan_items > 0 {
                format!(", {} items NaN", f.nan_items)
            } else {
                String::new()
            };
            let _ = writeln!(
                o,
                "  {label:<11} {} ({} component{}){range}{nan}",
                f.name,
                f.components,
                if f.components == 1 { "" } else { "s" }
            );
        }
    }
    if let Some(q) = &s.quality {
        let _ = writeln!(
            o,
            "  quality     {}: min {:.4}, mean {:.4}, min angle {:.2} deg, {} inverted or flat",
            count(q.triangles, "triangle", "triangles"),
            q.min_quality,
            q.mean_quality,
            q.min_angle_deg,
            q.inverted_or_flat
        );
        let _ = writeln!(
            o,
            "              edge length [{}, {}], area [{}, {}]",
            fmt_g(q.edge_length_range[0]),
            fmt_g(q.edge_length_range[1]),
            fmt_g(q.area_range[0]),
            fmt_g(q.area_range[1])
        );
    }
    if let Some(q) = s.solid.as_ref().and_then(|v| v.quality.as_ref()) {
        super::info3d::render_quality(&mut o, q);
    }
    if let Some(m) = &s.metric {
        match &m.conformity {
            Some(c) => {
                let _ = writeln!(
                    o,
                    "  metric      {}: {}, {:.1}% of metric length in [{:.4}, {:.4}], mean {}, range [{}, {}]",
                    m.source,
                    count(c.edges, "edge", "edges"),
                    100.0 * c.conforming_share,
                    smartmesh::metric::length::CONFORMING[0],
                    smartmesh::metric::length::CONFORMING[1],
                    fmt_g(c.mean_edge_length),
                    fmt_g(c.edge_length_range[0]),
                    fmt_g(c.edge_length_range[1])
                );
                let _ = writeln!(
                    o,
                    "              metric quality over {}: min {:.4}, mean {:.4}",
                    count(c.triangles, "triangle", "triangles"),
                    c.min_quality,
                    c.mean_quality
                );
            }
            None if m.ugawg.is_none() => {
                let _ = writeln!(o, "  metric      {}: no triangle to measure", m.source);
            }
            None => {}
        }
        if let Some(u) = &m.ugawg {
            super::info_metric::render_ugawg(&mut o, &m.source, u, m.expected_vertices);
        }
    }
    o
}

/// The faces, curves and points of a planar mesh.
fn render_planar_topology(o: &mut String, s: &MeshSummary) {
    let topo = &s.topology;
    let face = "face ";
    for f in &topo.faces {
        let _ = writeln!(
            o,
            "    {face} {:<24} {}, area {}",
            named(Some(f.tag), &f.name),
            count(f.cells, "cell", "cells"),
            fmt_g(f.area)
        );
    }
    for c in &topo.curves {
        let closed = if c.closed_pieces > 0 {
            format!(", {} closed", c.closed_pieces)
        } else {
            String::new()
        };
        let _ = writeln!(
            o,
            "    curve {:<24} {} edges in {} piece{}{}, length {}, {}",
            named(c.tag, &c.name),
            c.edges,
            c.pieces,
            if c.pieces == 1 { "" } else { "s" },
            closed,
            fmt_g(c.length),
            match c.on_boundary {
                Some(true) => "boundary",
                Some(false) => "interior",
                None => "segments (no faces yet: mesh them to see the boundary)",
            }
        );
    }
    let listed: Vec<&_> = topo.points.iter().filter(|p| p.tag.is_some()).collect();
    for p in &listed {
        let _ = writeln!(o, "    point {:<24} vertex {}", named(p.tag, &p.name), p.vertex);
    }
    let recovered = topo.points.len() - listed.len();
    if recovered > 0 {
        let _ = writeln!(o, "    {recovered} more points recovered at curve ends and junctions");
    }
}
