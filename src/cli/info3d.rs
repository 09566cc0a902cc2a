//! The lines `smartmesh info` adds for a mesh in space: cells per dimension, the volume,
//! the topological volumes and the surfaces bounding each, the surfaces with their
//! patches and boundary loops, the curves (tagged, where surfaces meet, ridges) and the
//! points, and the shape of the volume cells ([`smartmesh::VolumeQuality`]).

use std::fmt::Write as _;

use smartmesh::formats::words::count;
use smartmesh::VolumeQuality;
use smartmesh::{CurveOrigin, MeshSummary, PointOrigin, SolidSummary};

use super::info::{fmt_g, named};

/// Cells per dimension, the volume and the topology's summary line with its volumes.
pub(super) fn render_solid(o: &mut String, s: &MeshSummary, solid: &SolidSummary) {
    let [d0, d1, d2, d3] = solid.cells_per_dim;
    let _ = writeln!(o, "  dimensions  3D {d3}, 2D {d2}, 1D {d1}, 0D {d0} cells");
    let by_corners = if solid.volume_by_corners.is_empty() {
        String::new()
    } else {
        format!(" ({} cells through their corners)", solid.volume_by_corners.join(", "))
    };
    let _ = writeln!(o, "  volume      {}{by_corners}", fmt_g(solid.volume));
    let topo = &s.topology;
    let _ = writeln!(
        o,
        "  topology    {}, {}, {}, {}",
        count(solid.volumes.len(), "volume", "volumes"),
        count(topo.faces.len(), "surface", "surfaces"),
        count(topo.curves.len(), "curve", "curves"),
        count(topo.points.len(), "point", "points")
    );
    for v in &solid.volumes {
        let _ = writeln!(
            o,
            "    volume  {:<24} {}, volume {}, {} on the boundary",
            named(Some(v.tag), &v.name),
            count(v.cells, "cell", "cells"),
            fmt_g(v.volume),
            count(v.boundary_faces, "face", "faces")
        );
        let mut by: Vec<String> = v
            .bounded_by
            .iter()
            .map(|b| {
                format!("{} ({})", named(Some(b.tag), &b.name), count(b.faces, "face", "faces"))
            })
            .collect();
        if v.untagged_faces > 0 {
            by.push(format!(
                "{} on no surface of the file",
                count(v.untagged_faces, "face", "faces")
            ));
        }
        if !by.is_empty() {
            let _ = writeln!(o, "            bounded by {}", by.join(", "));
        }
    }
}

/// The shape of the volume cells.
pub(super) fn render_quality(o: &mut String, q: &VolumeQuality) {
    if let Some(t) = &q.tetra {
        let _ = writeln!(
            o,
            "  tetra       {}: mean ratio min {:.4}, mean {:.4}; dihedral angles [{:.2}, {:.2}] deg; aspect ratio max {}, mean {}",
            t.cells,
            t.mean_ratio[0],
            t.mean_ratio[1],
            t.dihedral_deg[0],
            t.dihedral_deg[1],
            fmt_g(t.aspect_ratio[2]),
            fmt_g(t.aspect_ratio[1])
        );
    }
    for k in &q.others {
        let _ = writeln!(
            o,
            "  {:<11} {}: scaled Jacobian min {:.4}, mean {:.4}",
            k.kind, k.cells, k.scaled_jacobian[0], k.scaled_jacobian[1]
        );
    }
    let _ = writeln!(
        o,
        "  validity    {} inverted, {} degenerate volume cells",
        q.inverted, q.degenerate
    );
}

/// The surfaces, curves and points of a mesh in space (the topology line first when the
/// mesh has no volume cell; [`render_solid`] writes it otherwise).
pub(super) fn render_space_topology(o: &mut String, s: &MeshSummary) {
    let topo = &s.topology;
    if s.solid.is_none() {
        let _ = writeln!(
            o,
            "  topology    {}, {}, {}",
            count(topo.faces.len(), "surface", "surfaces"),
            count(topo.curves.len(), "curve", "curves"),
            count(topo.points.len(), "point", "points")
        );
    }
    let curve_label = |i: usize| format!("c{}", i + 1);
    for f in &topo.faces {
        let loops = f.boundary_loops.as_deref().unwrap_or_default();
        let closed = loops.iter().filter(|l| l.closed).count();
        let bounds = if loops.is_empty() {
            "closed (no boundary)".to_string()
        } else {
            let open = if closed < loops.len() {
                format!(" ({} open)", loops.len() - closed)
            } else {
                String::new()
            };
            let curves: Vec<String> = f
                .boundary_curves
                .as_deref()
                .unwrap_or_default()
                .iter()
                .map(|&c| curve_label(c))
                .collect();
            format!(
                "{}{open} on curves {}",
                count(loops.len(), "boundary loop", "boundary loops"),
                curves.join(", ")
            )
        };
        let _ = writeln!(
            o,
            "    surface {:<24} {}, area {}, {}, {bounds}",
            named(Some(f.tag), &f.name),
            count(f.cells, "cell", "cells"),
            fmt_g(f.area),
            count(f.patches.unwrap_or(0), "patch", "patches")
        );
    }
    let angle = topo.ridge_angle_deg.unwrap_or(smartmesh::DEFAULT_RIDGE_ANGLE_DEG);
    for (i, c) in topo.curves.iter().enumerate() {
        let closed = if c.closed_pieces > 0 {
            format!(", {} closed", c.closed_pieces)
        } else {
            String::new()
        };
        let origin = match c.origin {
            Some(CurveOrigin::Tagged) => "line cells".to_string(),
            Some(CurveOrigin::Ridge) => format!("ridge (normals turn by more than {angle}°)"),
            _ if c.on_boundary == Some(true) => "a surface's free edges".to_string(),
            _ => "where surfaces meet".to_string(),
        };
        let _ = writeln!(
            o,
            "    curve {:<4} {:<24} {} edges in {} piece{}{}, length {}, {origin}",
            curve_label(i),
            named(c.tag, &c.name),
            c.edges,
            c.pieces,
            if c.pieces == 1 { "" } else { "s" },
            closed,
            fmt_g(c.length),
        );
    }
    if let Some(n) = topo.file_ridge_edges.filter(|&n| n > 0) {
        let _ = writeln!(
            o,
            "    ridges      {} the file lists (Medit Ridges)",
            count(n, "edge", "edges")
        );
    }
    for p in topo.points.iter().filter(|p| p.tag.is_some()) {
        let _ = writeln!(o, "    point {:<24} vertex {}", named(p.tag, &p.name), p.vertex);
    }
    let of = |origin: PointOrigin| topo.points.iter().filter(|p| p.origin == origin).count();
    let (corners, junctions, ends) =
        (of(PointOrigin::Corner), of(PointOrigin::Junction), of(PointOrigin::CurveEnd));
    if corners + junctions + ends > 0 {
        let listed = if corners > 0 {
            format!(", {corners} listed by the file (Medit Corners, RequiredVertices)")
        } else {
            String::new()
        };
        let _ = writeln!(
            o,
            "    {} recovered: {junctions} where curves meet, {}{listed}",
            count(corners + junctions + ends, "point", "points"),
            count(ends, "end of an open curve", "ends of open curves"),
        );
    }
}
