//! The eigen-decomposition of a symmetric 3×3 matrix, the one every 3D conversion uses
//! (size tensor from a metric, logarithm, square root).
//!
//! Today it is nalgebra's symmetric QR iteration, sorted; its contract is what callers
//! rely on: eigenvalues in decreasing order, an orthonormal right-handed frame whose i-th
//! vector belongs to the i-th value, and `Sym3::from_eigen(values, frame)` giving the
//! matrix back to rounding.

use nalgebra::{Matrix3, SymmetricEigen};

use super::sym3::Sym3;

/// Eigenvalues, decreasing, and their unit eigenvectors (`frame[i]` for `values[i]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Eigen3 {
    /// The eigenvalues, largest first.
    pub values: [f64; 3],
    /// The eigenvectors, orthonormal and right-handed, `frame[i]` for `values[i]`.
    pub frame: [[f64; 3]; 3],
}

/// The eigen-decomposition of `m` (see the module header for the contract).
pub fn eigen3(m: Sym3) -> Eigen3 {
    let r = m.rows();
    let matrix = Matrix3::from_fn(|i, j| r[i][j]);
    let decomposition = SymmetricEigen::new(matrix);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| decomposition.eigenvalues[b].total_cmp(&decomposition.eigenvalues[a]));
    let mut values = [0.0; 3];
    let mut frame = [[0.0; 3]; 3];
    for (k, &i) in order.iter().enumerate() {
        values[k] = decomposition.eigenvalues[i];
        let v = decomposition.eigenvectors.column(i);
        frame[k] = [v[0], v[1], v[2]];
    }
    // Right-handed: the third vector is the cross product of the first two.
    let [a, b] = [frame[0], frame[1]];
    let cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    if cross.iter().zip(frame[2]).map(|(c, v)| c * v).sum::<f64>() < 0.0 {
        frame[2] = frame[2].map(|c| -c);
    }
    Eigen3 { values, frame }
}

impl Sym3 {
    /// The eigen-decomposition (see [`eigen3`]).
    pub fn eigen(&self) -> Eigen3 {
        eigen3(*self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decomposition_rebuilds_the_matrix_in_decreasing_order() {
        let m = Sym3 { xx: 4.0, xy: 1.0, yy: 3.0, xz: 0.5, yz: -0.25, zz: 2.0 };
        let e = m.eigen();
        assert!(e.values[0] >= e.values[1] && e.values[1] >= e.values[2]);
        let back = Sym3::from_eigen(e.values, e.frame);
        for (x, y) in back.to_medit().iter().zip(m.to_medit()) {
            assert!((x - y).abs() < 1e-12, "{back:?} != {m:?}");
        }
        let [a, b, c] = e.frame;
        let cross =
            [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
        assert!((cross[0] * c[0] + cross[1] * c[1] + cross[2] * c[2] - 1.0).abs() < 1e-12);
    }
}
