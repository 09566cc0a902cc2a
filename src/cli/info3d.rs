//! The lines `smartmesh info` adds for a mesh with volume cells: cells per dimension, the
//! volume, the topological volumes and the surfaces bounding each, and the shape of the
//! volume cells ([`smartmesh::VolumeQuality`]).

use std::fmt::Write as _;

use smartmesh::formats::words::count;
use smartmesh::VolumeQuality;
use smartmesh::{MeshSummary, SolidSummary};

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
