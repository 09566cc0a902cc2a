//! The 3D metric that `smartmesh remesh` hands to `mmg3d_O3` or `mmgs_O3`: one SPD
//! [`Sym3`] per vertex of a mesh in space, read through `smartmesh_formats`.
//!
//! This is the route for a 3D metric until [`crate::metric_field::MetricField`], which
//! owns planar metrics (reading, checking, interpolating, writing), carries 3D tensors;
//! then this file goes and `remesh` asks the field. It reads, never writes, and
//! interpolates nothing: the metric is given on the mesh's own vertices.
//!
//! Where the metric comes from:
//! - a `.sol`/`.solb` alone: its `SolAtVertices` of type 3 in 3D (m11 m12 m22 m13 m23
//!   m33, the Medit file order), one per vertex of the mesh in the mesh's order, as
//!   `mmg3d_O3 -sol` takes it;
//! - any other mesh file with the same number of points: its point data `metric`;
//! - no file: the mesh's own point data `metric` (a `.mesh` with its `.sol` beside it,
//!   a `.vtu` that `smartmesh size` or a script wrote).
//!
//! A `metric` array is 9 components (row-major 3×3; a slightly unsymmetric tensor gives
//! the mean of its two off-diagonal entries) or 6 (ParaView's symmetric order XX YY ZZ
//! XY YZ XZ). A 2D metric (Medit `m11 m12 m22`) is refused: it says nothing across the
//! plane. Every tensor must be finite and positive definite (its three leading minors
//! positive), else the vertex is named.

use std::path::Path;

use smartmesh_formats::{DataArray, Layout, TaggedMesh};

use crate::metric::Sym3;

/// The point-data name of a metric.
const METRIC: &str = "metric";

/// Why no 3D metric could be had.
#[derive(Debug, thiserror::Error)]
pub enum SpaceMetricError {
    /// The file could not be read.
    #[error("{file}: {source}")]
    Read {
        /// The file.
        file: String,
        /// The reader's error (with its position).
        source: smartmesh_formats::Error,
    },
    /// The file or the mesh holds no usable 3D metric (bad input).
    #[error("{file}: {what}")]
    Bad {
        /// The file (or the mesh) named.
        file: String,
        /// What is wrong, and what was expected.
        what: String,
    },
}

/// The 3D metric on `mesh`'s vertices: from `file` when given, else from `mesh`'s own
/// point data (`mesh_name` names it in messages). See the module documentation.
pub fn read_space_metric(
    file: Option<&Path>,
    mesh: &TaggedMesh,
    mesh_name: &str,
) -> Result<Vec<Sym3>, SpaceMetricError> {
    let n = mesh.points.len();
    let Some(path) = file else {
        let bad = |what: String| SpaceMetricError::Bad { file: mesh_name.to_string(), what };
        let array = mesh.point_data.get(METRIC).ok_or_else(|| {
            bad("no point data `metric` (give the metric with --metric: a .sol/.solb, or a mesh file with point data `metric`)".into())
        })?;
        return tensors(array, n).map_err(bad);
    };
    let name = path.display().to_string();
    let bad = |what: String| SpaceMetricError::Bad { file: name.clone(), what };
    let read = |source| SpaceMetricError::Read { file: name.clone(), source };
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if matches!(ext.as_deref(), Some("sol" | "solb")) {
        let bytes = std::fs::read(path).map_err(|e| read(e.into()))?;
        let (count, arrays) = smartmesh_formats::medit::read_sol_alone(&bytes)
            .map_err(read)?
            .ok_or_else(|| bad("no SolAtVertices: expected a metric at the vertices".into()))?;
        if count != n {
            return Err(bad(format!(
                "SolAtVertices covers {count} vertices, the mesh {mesh_name} has {n}"
            )));
        }
        let array = arrays.get(METRIC).ok_or_else(|| {
            bad("no solution of type 3 (a symmetric tensor): expected a metric".into())
        })?;
        return tensors(array, n).map_err(bad);
    }
    let other = smartmesh_formats::read_path(path, None).map_err(read)?;
    if other.points.len() != n {
        return Err(bad(format!(
            "{} points, the mesh {mesh_name} has {n}: the metric must be given on the mesh's own vertices",
            other.points.len()
        )));
    }
    let array = other
        .point_data
        .get(METRIC)
        .ok_or_else(|| bad("no point data `metric` (6 or 9 components) on its points".into()))?;
    tensors(array, n).map_err(bad)
}

/// The tensors of `array` (9 components row-major, or 6 in ParaView's order), each
/// checked SPD; `n` items expected.
fn tensors(array: &DataArray, n: usize) -> Result<Vec<Sym3>, String> {
    if array.layout == Layout::Symmetric2 {
        return Err("a 2D metric (m11 m12 m22): a mesh in space needs a 3D one (m11 m12 m22 m13 m23 m33 in a 3D .sol, or 6 or 9 components)".into());
    }
    if !array.covers(n) {
        return Err(format!(
            "`metric` has {} values of {} components, expected {n} vertices",
            array.values.len(),
            array.components
        ));
    }
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let t = array.item(i);
        let m = match array.components {
            9 => Sym3::from_row_major(&std::array::from_fn(|j| t[j])),
            6 => Sym3 { xx: t[0], yy: t[1], zz: t[2], xy: t[3], yz: t[4], xz: t[5] },
            c => {
                return Err(format!(
                "`metric` has {c} components: expected 9 (row-major 3x3) or 6 (XX YY ZZ XY YZ XZ)"
            ))
            }
        };
        if !is_spd(&m) {
            return Err(format!(
                "the metric at vertex {i} is not symmetric positive definite ({:?}, Medit order m11 m12 m22 m13 m23 m33)",
                m.to_medit()
            ));
        }
        out.push(m);
    }
    Ok(out)
}

/// Whether `m` is finite and positive definite: its three leading principal minors
/// are positive (Sylvester's criterion).
fn is_spd(m: &Sym3) -> bool {
    m.is_finite() && m.xx > 0.0 && m.xx * m.yy - m.xy * m.xy > 0.0 && m.det() > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(n: usize) -> TaggedMesh {
        TaggedMesh { points: vec![[0.0, 0.0, 1.0]; n], ..Default::default() }
    }

    #[test]
    fn both_layouts_give_the_same_tensor_and_bad_ones_are_named() {
        let m = Sym3 { xx: 4.0, xy: 1.0, yy: 3.0, xz: 0.5, yz: -0.25, zz: 2.0 };
        let mut a = mesh(1);
        a.point_data.insert(METRIC.into(), DataArray::new(9, m.to_row_major().to_vec()));
        assert_eq!(read_space_metric(None, &a, "a").unwrap(), [m]);
        let six = vec![m.xx, m.yy, m.zz, m.xy, m.yz, m.xz];
        a.point_data.insert(METRIC.into(), DataArray::new(6, six));
        assert_eq!(read_space_metric(None, &a, "a").unwrap(), [m]);
        // Indefinite: the second minor is negative.
        let bad = Sym3 { xy: 5.0, ..m };
        a.point_data.insert(METRIC.into(), DataArray::new(9, bad.to_row_major().to_vec()));
        let e = read_space_metric(None, &a, "a").unwrap_err().to_string();
        assert!(e.contains("vertex 0") && e.contains("positive definite"), "{e}");
        a.point_data.insert(METRIC.into(), DataArray::symmetric2(vec![1.0, 0.0, 1.0]));
        let e = read_space_metric(None, &a, "a").unwrap_err().to_string();
        assert!(e.contains("2D metric"), "{e}");
        let e = read_space_metric(None, &mesh(2), "b").unwrap_err().to_string();
        assert!(e.starts_with("b: no point data"), "{e}");
    }

    #[test]
    fn a_sol_file_is_read_in_medit_order_and_counted() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("m.sol");
        // One vertex: m11 m12 m22 m13 m23 m33.
        std::fs::write(
            &p,
            "MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n1\n1 3\n4 1 3 0.5 -0.25 2\nEnd\n",
        )
        .unwrap();
        let m = read_space_metric(Some(&p), &mesh(1), "x").unwrap();
        assert_eq!(m, [Sym3 { xx: 4.0, xy: 1.0, yy: 3.0, xz: 0.5, yz: -0.25, zz: 2.0 }]);
        let e = read_space_metric(Some(&p), &mesh(2), "x").unwrap_err().to_string();
        assert!(e.contains("covers 1 vertices") && e.contains("has 2"), "{e}");
    }
}
