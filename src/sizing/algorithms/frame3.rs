//! The frame of a vertex in space with respect to its closest point on a source, and
//! wall-aligned size tensors from it (the 3D counterpart of `algorithms::frame`).
//!
//! Off the source, the perpendicular direction is the gradient of the distance: the unit
//! vector from the foot to the vertex, whatever the piece (surface, segment or point);
//! the level sets of the distance are the offset surfaces, tubes and spheres whose
//! tangent plane holds the parallel size. On the source — distance at most
//! [`ON_SOURCE`] times the longest edge of the foot's piece, where that direction is
//! rounding noise — it is the surface normal ([`SpaceSource::surface_normal`]); on a
//! segment, the segment's direction is the one direction known (the tangent); on a
//! point, none.

use super::{Failure, ON_SOURCE};
use crate::geometry::space::Point3;
use crate::metric::{SizeTensor, SizeTensor3};
use crate::sizing::space::{unit3, PieceKind3, SpaceClosest, SpaceSource};

/// What is known of the frame at a vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Across {
    /// The unit direction across the level set (off the source), or the surface normal.
    Normal(Point3),
    /// On a segment: its unit tangent.
    Line(Point3),
    /// On a point, or where no direction is known.
    Point,
}

/// The frame of a vertex at `at` with closest point `c` on `source`.
pub(crate) fn across(source: &SpaceSource, c: &SpaceClosest, at: Point3) -> Across {
    let on = c.distance <= ON_SOURCE * source.piece_size(c.piece);
    if !on {
        let d = [at[0] - c.foot[0], at[1] - c.foot[1], at[2] - c.foot[2]];
        return unit3(d).map_or(Across::Point, Across::Normal);
    }
    match source.pieces()[c.piece as usize].kind {
        PieceKind3::Surface => source.surface_normal(c).map_or(Across::Point, Across::Normal),
        PieceKind3::Segment => {
            source.segment_direction(c.piece).map_or(Across::Point, Across::Line)
        }
        PieceKind3::Point => Across::Point,
    }
}

/// A vector not parallel to unit `n`: the coordinate axis it leans on least.
fn other_axis(n: Point3) -> Point3 {
    let a = n.map(f64::abs);
    if a[0] <= a[1] && a[0] <= a[2] {
        [1.0, 0.0, 0.0]
    } else if a[1] <= a[2] {
        [0.0, 1.0, 0.0]
    } else {
        [0.0, 0.0, 1.0]
    }
}

fn in_range(h: f64) -> bool {
    (SizeTensor::MIN_SIZE..=SizeTensor::MAX_SIZE).contains(&h)
}

/// The wall-aligned tensor of `across`: `h_normal` along a normal and `h_tangent` in
/// the plane across it (two equal tangent sizes); on a segment `h_tangent` along it and
/// the smaller of the two across it (the intersection of the tensors of the vertices
/// around the segment, whose normals turn all round it); on a point the isotropic
/// tensor of the smaller size. [`Failure::Degenerate`] for sizes out of range.
pub(crate) fn wall_tensor(
    vertex: usize,
    across: Across,
    h_normal: f64,
    h_tangent: f64,
) -> Result<SizeTensor3, Failure> {
    if !in_range(h_normal) || !in_range(h_tangent) {
        return Err(Failure::Degenerate { vertex });
    }
    let small = h_normal.min(h_tangent);
    let t = match across {
        Across::Normal(n) => {
            SizeTensor3::try_new(n, other_axis(n), [h_normal, h_tangent, h_tangent])
        }
        Across::Line(t) => SizeTensor3::try_new(t, other_axis(t), [h_tangent, small, small]),
        Across::Point => Some(SizeTensor3::isotropic(small)),
    };
    t.ok_or(Failure::Degenerate { vertex })
}
