//! What a field's tensor is, in 2D ([`Sym2`]) and in 3D ([`Sym3`]): the one trait the
//! reading, checking and writing of [`super::MetricField`] are generic over, so that a
//! metric on a planar mesh and one on a mesh in space (tetrahedra, surfaces in space) go
//! through the same code and refuse files with the same messages.
//!
//! How each reads a point array's item:
//!
//! | tensor | 9 components (row-major 3×3) | packed |
//! | --- | --- | --- |
//! | [`Sym2`] | its xy block | 3: m11 m12 m22 |
//! | [`Sym3`] | all of it | 6: XX YY ZZ XY YZ XZ, ParaView's order for a symmetric tensor |
//!
//! MMG's `.sol` order (m11 m12 m22 m13 m23 m33) never reaches here: the formats crate
//! reads a `.sol` into 9 row-major components. A tensor is a metric when it is finite,
//! symmetric (off-diagonal pairs within 1e-9 of the diagonal's size) and positive definite
//! (Sylvester's leading minors, all positive).

use std::path::Path;

use crate::metric::{Sym2, Sym3};
use std::collections::BTreeMap;

use super::MetricField;
use smartmesh_formats::{DataArray, Error, TaggedMesh};

/// A symmetric tensor a metric field holds, one per vertex.
pub trait FieldTensor: Copy + PartialEq + std::fmt::Debug + Send + Sync + 'static {
    /// The dimension: 2 or 3.
    const DIM: u8;
    /// The identity, given to vertices no cell uses when they carry no metric.
    const IDENTITY: Self;
    /// The component counts a point array may have, in words, for errors.
    const SHAPES: &'static str;

    /// Whether a point array of `components` components (packed when `packed`, see
    /// [`smartmesh_formats::Layout::Symmetric2`]) holds such tensors.
    fn accepts(components: usize, packed: bool) -> bool;

    /// The tensor of one item of such an array, or why it is no metric (and the tensor as
    /// read, row-major 3×3 in 3D, [[a, b], [b2, c]] in 2D, for the message).
    fn from_item(item: &[f64], packed: bool) -> Result<Self, (&'static str, Vec<f64>)>;

    /// The row-major 3×3 tensor written for it (a 2D tensor's z entry is `zz`).
    fn to_tensor9(&self, zz: f64) -> [f64; 9];

    /// Its largest eigenvalue (1/h_min² of a metric).
    fn largest_eigenvalue(&self) -> f64;

    /// The name of the last view of the `.pos` file at `path` and its tensor at each
    /// vertex of `mesh` (2D: [`super::pos_view`]; 3D: `pos_view3`).
    #[doc(hidden)]
    fn read_pos(path: &Path, mesh: &TaggedMesh) -> Result<(String, Vec<Self>), Error>;

    /// The point array [`super::METRIC`] of `field`, 9 components per vertex, as every
    /// target writes it.
    #[doc(hidden)]
    fn metric_array(field: &MetricField<Self>) -> DataArray;

    /// The arrays written for `field` in a VTK file: [`super::METRIC`] and the sizes
    /// beside it.
    #[doc(hidden)]
    fn vtk_arrays(field: &MetricField<Self>) -> BTreeMap<String, DataArray>;
}

impl FieldTensor for Sym2 {
    const DIM: u8 = 2;
    const IDENTITY: Sym2 = Sym2::IDENTITY;
    const SHAPES: &'static str = "9 (3x3 row-major) or 3 (m11 m12 m22)";

    fn accepts(components: usize, _packed: bool) -> bool {
        components == 9 || components == 3
    }

    fn from_item(t: &[f64], _packed: bool) -> Result<Sym2, (&'static str, Vec<f64>)> {
        let (a, b, b2, c) =
            if t.len() == 9 { (t[0], t[1], t[3], t[4]) } else { (t[0], t[1], t[1], t[2]) };
        match super::not_a_metric(a, b, b2, c) {
            None => Ok(Sym2::new(a, 0.5 * (b + b2), c)),
            Some(why) => Err((why, vec![a, b, b2, c])),
        }
    }

    fn to_tensor9(&self, zz: f64) -> [f64; 9] {
        smartmesh_formats::sym2_to_tensor9(self.a, self.b, self.c, zz)
    }

    fn largest_eigenvalue(&self) -> f64 {
        self.eigen().values[0]
    }

    fn read_pos(path: &Path, mesh: &TaggedMesh) -> Result<(String, Vec<Sym2>), Error> {
        let view = super::pos_view::read_path(path)?;
        let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
        Ok((view.name().to_string(), view.at(&points)))
    }

    fn metric_array(field: &MetricField<Sym2>) -> DataArray {
        field.to_array()
    }

    fn vtk_arrays(field: &MetricField<Sym2>) -> BTreeMap<String, DataArray> {
        field.arrays()
    }
}

impl FieldTensor for Sym3 {
    const DIM: u8 = 3;
    const IDENTITY: Sym3 = Sym3::IDENTITY;
    const SHAPES: &'static str =
        "9 (3x3 row-major) or 6 (XX YY ZZ XY YZ XZ, as ParaView orders a symmetric tensor)";

    fn accepts(components: usize, packed: bool) -> bool {
        // A packed 2D tensor (a 2D `.sol`) is no 3D metric.
        !packed && (components == 9 || components == 6)
    }

    fn from_item(t: &[f64], _packed: bool) -> Result<Sym3, (&'static str, Vec<f64>)> {
        let rows: [f64; 9] = match t.len() {
            9 => std::array::from_fn(|i| t[i]),
            // XX YY ZZ XY YZ XZ.
            _ => [t[0], t[3], t[5], t[3], t[1], t[4], t[5], t[4], t[2]],
        };
        match not_a_metric3(&rows) {
            None => Ok(Sym3::from_row_major(&rows)),
            Some(why) => Err((why, rows.to_vec())),
        }
    }

    fn to_tensor9(&self, _zz: f64) -> [f64; 9] {
        self.to_row_major()
    }

    fn largest_eigenvalue(&self) -> f64 {
        self.eigen().values[0]
    }

    fn read_pos(path: &Path, mesh: &TaggedMesh) -> Result<(String, Vec<Sym3>), Error> {
        super::pos_view3::read_at(path, mesh)
    }

    fn metric_array(field: &MetricField<Sym3>) -> DataArray {
        field.to_array_3d()
    }

    fn vtk_arrays(field: &MetricField<Sym3>) -> BTreeMap<String, DataArray> {
        field.arrays_3d()
    }
}

/// Why the row-major 3×3 tensor `r` is not a metric, `None` when it is one.
pub(crate) fn not_a_metric3(r: &[f64; 9]) -> Option<&'static str> {
    let scale = r[0].abs() + r[4].abs() + r[8].abs();
    if !r.iter().all(|x| x.is_finite()) {
        Some("not finite")
    } else if [(1, 3), (2, 6), (5, 7)].iter().any(|&(i, j)| (r[i] - r[j]).abs() > 1e-9 * scale) {
        Some("not symmetric")
    } else {
        let m = Sym3::from_row_major(r);
        let minor2 = m.xx * m.yy - m.xy * m.xy;
        if m.xx > 0.0 && minor2 > 0.0 && m.det() > 0.0 {
            None
        } else {
            Some("not positive definite")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn items_of_both_orders_give_the_same_tensor() {
        let m = Sym3 { xx: 4.0, xy: 1.0, yy: 3.0, xz: 0.5, yz: -0.25, zz: 2.0 };
        let nine = Sym3::from_item(&m.to_row_major(), false).unwrap();
        let six = Sym3::from_item(&[4.0, 3.0, 2.0, 1.0, -0.25, 0.5], false).unwrap();
        assert_eq!(nine, m);
        assert_eq!(six, m);
        assert!(Sym3::accepts(6, false) && !Sym3::accepts(3, true) && !Sym3::accepts(3, false));
    }

    #[test]
    fn not_metrics_say_why() {
        // Positive diagonal and first minors, negative determinant.
        let bad = [1.0, 0.0, 0.9, 0.0, 1.0, 0.9, 0.9, 0.9, 1.0];
        assert_eq!(not_a_metric3(&bad), Some("not positive definite"));
        let unsym = [1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        assert_eq!(not_a_metric3(&unsym), Some("not symmetric"));
        let nan = [f64::NAN, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        assert_eq!(not_a_metric3(&nan), Some("not finite"));
        let (why, shown) = Sym3::from_item(&bad, false).unwrap_err();
        assert_eq!((why, shown.len()), ("not positive definite", 9));
    }
}
