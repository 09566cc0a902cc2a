//! The plane a 2D mesh lies in. Until smartmesh meshes surfaces in space, every command
//! that computes in the plane (`mesh`, `size`, `remesh`, `adapt`, `layer`, `report`,
//! `recipe check`) takes only a mesh whose points all have one z, and refuses any other
//! as bad input, as the readers refuse volume cells: read as (x, y), a surface in space
//! would be flattened onto z = 0 into a mesh that looks right and is not (a sphere
//! folded onto a disc, a square in the xz-plane into zero-area triangles). `info` and
//! `convert` take any mesh.
//!
//! Invariants: a mesh is planar when every point has exactly the z of its first point
//! (no tolerance: a 2D mesher writes one z for all; a mesh a few ulps off its plane is
//! named, point and z, and can be fixed at its source), and that z is finite; a mesh
//! without points is planar at z = 0. The commands compute in (x, y) and write their
//! output in the input's plane ([`place`]): a square at z = 5 comes back at z = 5.

use smartmesh_formats::TaggedMesh;

/// A mesh the 2D commands cannot take: volume cells, or points off one plane z = const.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum NotPlanar {
    /// A point lies off the plane of the first point.
    #[error(
        "not planar: point {} has z = {z} where point {} has z = {plane}; smartmesh's 2D \
         commands take a mesh in one plane z = const (a surface in space is not flattened)",
        point + 1,
        first + 1
    )]
    OffPlane {
        /// The first point off the plane, 0-based (the file's point order).
        point: usize,
        /// Its z.
        z: f64,
        /// The point that set the plane, 0-based.
        first: usize,
        /// The plane's z.
        plane: f64,
    },
    /// The mesh has volume cells: a 3D mesh, which the 2D commands do not size or remesh.
    #[error(
        "a 3D mesh: {count} {kind} cells; smartmesh's 2D commands take points, lines and \
         surface cells in one plane z = const (`info` and `convert` take 3D meshes)"
    )]
    Volume {
        /// The first volume kind met.
        kind: &'static str,
        /// How many cells of that kind.
        count: usize,
    },
}

/// The z of the plane every point of `mesh` lies in, or why the mesh is not planar: a
/// volume cell, or the first point off the plane.
pub fn plane(mesh: &TaggedMesh) -> Result<f64, NotPlanar> {
    if let Some(b) = mesh.blocks.iter().find(|b| b.kind.dim() == 3 && !b.is_empty()) {
        return Err(NotPlanar::Volume { kind: b.kind.name(), count: b.len() });
    }
    let Some(first) = mesh.points.first() else { return Ok(0.0) };
    let plane = first[2];
    for (point, p) in mesh.points.iter().enumerate() {
        // A non-finite z is off every plane, the first point's included.
        if p[2] != plane || !p[2].is_finite() {
            return Err(NotPlanar::OffPlane { point, z: p[2], first: 0, plane });
        }
    }
    Ok(plane)
}

/// Puts every point of `mesh` in the plane z = `z` (the input's, from [`plane`]): the
/// commands compute in (x, y) and make their new points at z = 0.
pub fn place(mesh: &mut TaggedMesh, z: f64) {
    for p in &mut mesh.points {
        p[2] = z;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(points: &[[f64; 3]]) -> TaggedMesh {
        TaggedMesh { points: points.to_vec(), ..Default::default() }
    }

    #[test]
    fn one_z_is_a_plane_whatever_its_value() {
        assert_eq!(plane(&mesh(&[])), Ok(0.0));
        assert_eq!(plane(&mesh(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])), Ok(0.0));
        assert_eq!(plane(&mesh(&[[0.0, 0.0, 5.0], [1.0, 0.0, 5.0], [0.0, 1.0, 5.0]])), Ok(5.0));
    }

    #[test]
    fn the_first_point_off_the_plane_is_named() {
        let e = plane(&mesh(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 2.0]]))
            .unwrap_err();
        assert_eq!(e, NotPlanar::OffPlane { point: 2, z: 1.0, first: 0, plane: 0.0 });
        let text = e.to_string();
        assert!(text.contains("point 3 has z = 1 where point 1 has z = 0"), "{text}");
        assert!(text.contains("z = const"), "{text}");
    }

    #[test]
    fn a_volume_cell_is_refused_even_in_a_plane() {
        let mut m = mesh(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]]);
        let mut tets = smartmesh_formats::CellBlock::new(smartmesh_formats::CellKind::Tetra);
        tets.push(&[0u32, 1, 2, 3], 1, 1);
        m.blocks.push(tets);
        let e = plane(&m).unwrap_err();
        assert_eq!(e, NotPlanar::Volume { kind: "tetra", count: 1 });
        assert!(e.to_string().contains("a 3D mesh: 1 tetra cells"), "{e}");
    }

    #[test]
    fn a_non_finite_z_is_off_every_plane() {
        let e = plane(&mesh(&[[0.0, 0.0, f64::NAN], [1.0, 0.0, f64::NAN]])).unwrap_err();
        assert!(matches!(e, NotPlanar::OffPlane { point: 0, .. }), "{e:?}");
        assert!(plane(&mesh(&[[0.0, 0.0, 0.0], [1.0, 0.0, f64::INFINITY]])).is_err());
    }

    #[test]
    fn place_moves_every_point_to_the_plane() {
        let mut m = mesh(&[[0.0, 0.0, 0.0], [1.0, 2.0, 0.0]]);
        place(&mut m, 5.0);
        assert_eq!(m.points, vec![[0.0, 0.0, 5.0], [1.0, 2.0, 5.0]]);
    }
}
