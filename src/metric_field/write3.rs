//! What a 3D field writes (the targets and the writing itself are [`super::write`]'s,
//! shared with 2D):
//!
//! | output | what is written | who reads it |
//! | --- | --- | --- |
//! | `.sol` / `.solb` | `Dimension 3`, `SolAtVertices` of type 3, m11 m12 m22 m13 m23 m33 per vertex | `mmg3d_O3 -in mesh.mesh -sol out.sol`, `mmgs_O3` |
//! | `.msh` | one `$NodeData` view `metric`, 9 components row-major | `gmsh -bgm out.msh` |
//! | `.pos` | one view of `TS` records on the tetrahedra (`TH`/`TI`/`TY` on other volume cells; `TT` on a surface mesh), 9 components per node | `gmsh -bgm out.pos`, with `Mesh.Algorithm3D` 7 (MMG3D) |
//! | `.vtu` / `.vtk` | point data `metric`, `size_tensor`, `h1`, `h2`, `h3`, `anisotropy`, `axis1`, `axis2`, `axis3` | ParaView, VTK |
//!
//! `size_tensor` = R diag(h1, h2, h3) Rᵀ, where M = R diag(1/h²) Rᵀ: ParaView's Tensor
//! Glyph (VTK's `vtkTensorGlyph`, eigenvalue scaling on) stretches its glyph, a sphere of
//! radius 0.5, by each eigenvalue along its eigenvector, so at scale factor 1 the glyph of
//! a vertex spans h_i along axis i: the size ellipsoid, glyphs of neighbours in a mesh
//! that conforms to the field just touching (checked with VTK in `tests/metric3d_interop.rs`).
//! h1 ≥ h2 ≥ h3 are the sizes in decreasing order, `axis_i` the unit axis of h_i scaled by
//! it, `anisotropy` h1/h3.

use std::collections::BTreeMap;

use super::{MetricField, METRIC};
use crate::metric::Sym3;
use smartmesh_formats::DataArray;

/// The sizes h1 ≥ h2 ≥ h3 of a metric and their unit axes.
pub(crate) fn sizes_3d(m: &Sym3) -> ([f64; 3], [[f64; 3]; 3]) {
    let e = m.eigen();
    // Eigenvalues decrease, sizes 1/√λ increase: the largest size is the last.
    let h = [2, 1, 0].map(|i| 1.0 / e.values[i].max(f64::MIN_POSITIVE).sqrt());
    (h, [e.frame[2], e.frame[1], e.frame[0]])
}

impl MetricField<Sym3> {
    /// The point array [`METRIC`]: per vertex the row-major 3×3 tensor.
    pub fn to_array_3d(&self) -> DataArray {
        DataArray::new(9, self.tensors.iter().flat_map(Sym3::to_row_major).collect())
    }

    /// The arrays written for the field in a VTK file (see the module documentation).
    pub fn arrays_3d(&self) -> BTreeMap<String, DataArray> {
        let n = self.tensors.len();
        let mut size = Vec::with_capacity(9 * n);
        let mut h: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(n));
        let mut axes: [Vec<f64>; 3] = std::array::from_fn(|_| Vec::with_capacity(3 * n));
        let mut aniso = Vec::with_capacity(n);
        for m in &self.tensors {
            let (sizes, frame) = sizes_3d(m);
            size.extend_from_slice(&Sym3::from_eigen(sizes, frame).to_row_major());
            for k in 0..3 {
                h[k].push(sizes[k]);
                axes[k].extend(frame[k].iter().map(|c| c * sizes[k]));
            }
            aniso.push(sizes[0] / sizes[2]);
        }
        let mut out = BTreeMap::new();
        out.insert(METRIC.to_string(), self.to_array_3d());
        out.insert("size_tensor".to_string(), DataArray::new(9, size));
        out.insert("anisotropy".to_string(), DataArray::new(1, aniso));
        for (k, (h, axis)) in h.into_iter().zip(axes).enumerate() {
            out.insert(format!("h{}", k + 1), DataArray::new(1, h));
            out.insert(format!("axis{}", k + 1), DataArray::new(3, axis));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_size_tensor_has_the_sizes_along_the_frame() {
        // Sizes 2, 0.5, 0.1 along a rotated frame.
        let (c, s) = (0.6f64, 0.8f64);
        let frame = [[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]];
        let m = Sym3::from_eigen([0.25, 4.0, 100.0], frame);
        let field = MetricField::new(vec![m], "one");
        let a = field.arrays_3d();
        let t = a["size_tensor"].item(0).to_vec();
        let st = Sym3::from_row_major(&t.try_into().unwrap());
        for (h, e) in [(2.0, frame[0]), (0.5, frame[1]), (0.1, frame[2])] {
            let v = st.mul_vec(e);
            for k in 0..3 {
                assert!((v[k] - h * e[k]).abs() < 1e-12, "{h}: {v:?}");
            }
        }
        assert!((a["h1"].values[0] - 2.0).abs() < 1e-12 && (a["h3"].values[0] - 0.1).abs() < 1e-12);
        assert!((a["anisotropy"].values[0] - 20.0).abs() < 1e-9);
        assert_eq!(a["metric"].item(0), m.to_row_major());
    }
}
