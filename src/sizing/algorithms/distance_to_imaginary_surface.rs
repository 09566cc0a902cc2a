//! DISTANCE_TO_IMAGINARY_SURFACE: a triangulated sheet in space given by a file (a
//! wake, a shock surface) that need not follow mesh faces, sized as DISTANCE_TO_BORDER
//! sizes a surface: with d the exact distance to the sheet, `perpendicular(d)` along
//! the direction from the closest point to the vertex (the sheet's normal for a vertex
//! on it, area-weighted at a foot on an edge or a corner of its triangles), and
//! `parallel(d)` twice in the plane across it (`super::frame3`).
//!
//! The sheet is read when the recipe is resolved (`FILE`, relative to the recipe file;
//! see `crate::recipe`'s sheet reader); here it is a list of points and triangles. Its
//! closest points are those of the one exact index of `geometry::space`, bit for bit a
//! scan of every triangle.
//!
//! Coarse meshes: the sheet is a free source, so the 3D driver also gives a tensor to the
//! corners of every cell a sheet triangle meets, whatever their distance
//! ([`crate::sizing::field3`]), as the 2D propagation does for the cells an imaginary
//! polyline crosses.
//!
//! `REGIONS` (optional): as for DISTANCE_TO_IMAGINARY_POLYLINE in space, only the
//! vertices of the named volumes (the corners of their cells) and surfaces (the corners
//! of their triangles) get a tensor; the distance is still to the whole sheet, so a
//! region's boundary cuts the field without bending it.
//!
//! A sheet has no meaning on a planar mesh: there the step is refused, naming it
//! (`Failure::OnlyInSpace`).
//!
//! Reach: the larger of the two functions' maximum distances.

use super::distance_to_imaginary_polyline::within_mask;
use super::{across, reach_of, wall_tensor, SpaceTensor, SpaceWork};
use super::{
    Around, Arguments, Declaration, EntitySet, Failure, FunctionKind, Parameter, ParameterKind,
    Sheet, SizingAlgorithm, Work,
};
use crate::mesh_graph::MeshGraph;
use crate::metric::SizeTensor3;
use crate::sizing::functions::DistanceFunction;
use crate::sizing::space::{SpaceClosest, SpaceMesh, SpaceSource, SpaceSourceBuilder};
use crate::topology::Topology;

/// DISTANCE_TO_IMAGINARY_SURFACE: a sheet from a file; normal size
/// `perpendicular(distance)`, tangent size `parallel(distance)`.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceToImaginarySurface {
    /// Size normal to the sheet against distance.
    pub perpendicular: DistanceFunction,
    /// Size tangent to the sheet against distance.
    pub parallel: DistanceFunction,
    /// The sheet.
    pub sheet: Sheet,
    /// Where the algorithm applies (volumes, surfaces); empty means everywhere.
    pub within: EntitySet,
}

impl SizingAlgorithm for DistanceToImaginarySurface {
    const DECLARATION: Declaration = Declaration {
        keyword: "DISTANCE_TO_IMAGINARY_SURFACE",
        name: "distance_to_imaginary_surface",
        doc: "A triangulated sheet in space read from a file (a wake, a shock surface), on a \
              mesh in space: PERPENDICULAR_FUNCTION(d) along the normal, PARALLEL_FUNCTION(d) \
              in the tangent plane at the closest point, as DISTANCE_TO_BORDER sizes a \
              surface.",
        parameters: &[
            Parameter {
                field: "perpendicular",
                aliases: &[],
                keys: &["PERPENDICULAR_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: true,
                doc: "Size normal to the sheet against distance.",
            },
            Parameter {
                field: "parallel",
                aliases: &[],
                keys: &["PARALLEL_FUNCTION"],
                kind: ParameterKind::Function(FunctionKind::Distance),
                line_break_after: true,
                doc: "Size tangent to the sheet against distance.",
            },
            Parameter {
                field: "file",
                aliases: &[],
                keys: &["FILE"],
                kind: ParameterKind::File,
                line_break_after: false,
                doc: "The sheet: a triangulated surface file (.stl, .obj, .mesh, .msh, …), \
                      relative to the recipe file.",
            },
            Parameter {
                field: "regions",
                aliases: &[],
                keys: &["REGIONS"],
                kind: ParameterKind::Regions { dimensions: &[2], optional: true, lift: true },
                line_break_after: false,
                doc: "The volumes or surfaces where it applies; everywhere when left out.",
            },
        ],
    };

    type Tensor<'a> = std::convert::Infallible;

    fn from_arguments(arguments: &mut Arguments) -> Option<DistanceToImaginarySurface> {
        Some(DistanceToImaginarySurface {
            perpendicular: arguments.distance("perpendicular")?,
            parallel: arguments.distance("parallel")?,
            sheet: arguments.sheet("file")?,
            within: arguments.entities("regions")?,
        })
    }

    fn entity_sets(&self) -> Vec<&EntitySet> {
        vec![&self.within]
    }

    fn zoom(&self) -> Option<(Around<'_>, f64)> {
        None
    }

    fn work<'a>(
        &'a self,
        _graph: &'a MeshGraph,
        _topology: &'a Topology,
    ) -> Result<Work<Self::Tensor<'a>>, Failure> {
        Err(Failure::OnlyInSpace { keyword: Self::DECLARATION.keyword })
    }

    const IN_SPACE: bool = true;

    fn work_in_space<'a>(
        &'a self,
        mesh: &'a SpaceMesh<'a>,
        topology: &'a Topology,
    ) -> Result<SpaceWork<'a>, Failure> {
        let mask = within_mask(mesh, topology, &self.within)?;
        let source = sheet_source(mesh, &self.sheet)?;
        let reach = reach_of(&[self.perpendicular.max_distance(), self.parallel.max_distance()]);
        Ok(SpaceWork::FromSource { source, reach, tensor: Box::new(SheetTensor(self, mask)) })
    }
}

/// The sheet as a free source of the 3D driver.
pub(crate) fn sheet_source(mesh: &SpaceMesh<'_>, sheet: &Sheet) -> Result<SpaceSource, Failure> {
    let mut b = SpaceSourceBuilder::new(mesh.points());
    for (i, &p) in sheet.points.iter().enumerate() {
        b.free_point(p, i)?;
    }
    let n = sheet.points.len();
    for t in &sheet.triangles {
        if let Some(&v) = t.iter().find(|&&v| v as usize >= n) {
            return Err(Failure::EntityOutOfRange { what: "sheet point", index: v as usize, len: n });
        }
        b.triangle(*t);
    }
    if b.is_empty() {
        return Err(Failure::NoSource);
    }
    Ok(b.build()?)
}

/// The tensor of DISTANCE_TO_IMAGINARY_SURFACE, and where it applies (`None`: everywhere).
struct SheetTensor<'a>(&'a DistanceToImaginarySurface, Option<Vec<bool>>);

impl SpaceTensor for SheetTensor<'_> {
    fn tensor(
        &self,
        sources: &[SpaceSource],
        v: usize,
        at: [f64; 3],
        closest: &[SpaceClosest],
    ) -> Result<Option<SizeTensor3>, Failure> {
        if self.1.as_ref().is_some_and(|m| !m[v]) {
            return Ok(None);
        }
        let (a, c) = (self.0, &closest[0]);
        let frame = across(&sources[0], c, at);
        wall_tensor(v, frame, a.perpendicular.eval(c.distance), a.parallel.eval(c.distance))
            .map(Some)
    }
}
