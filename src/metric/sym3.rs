//! `Sym3`: a plain symmetric 3×3 matrix, the 3D counterpart of [`super::Sym2`].
//!
//! Its six components are named by their place in the matrix; the orders in which files
//! carry them differ and each has its own conversion here: MMG's `.sol` (m11 m12 m22 m13
//! m23 m33, the lower triangle row by row), and the row-major 3×3 of Gmsh's tensor views
//! and VTK's 9-component tensors.

use std::ops::{Add, Mul};

use super::sym2::Sym2;

/// A symmetric 3×3 matrix, plain data for hot loops and for files.
///
/// Used for metric tensors (SPD, eigenvalues 1/h²), size matrices (eigenvalues h) and the
/// logarithms of either. Nothing here checks definiteness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sym3 {
    /// Entry (0, 0).
    pub xx: f64,
    /// Entries (0, 1) and (1, 0).
    pub xy: f64,
    /// Entry (1, 1).
    pub yy: f64,
    /// Entries (0, 2) and (2, 0).
    pub xz: f64,
    /// Entries (1, 2) and (2, 1).
    pub yz: f64,
    /// Entry (2, 2).
    pub zz: f64,
}

impl Sym3 {
    /// The identity matrix.
    pub const IDENTITY: Sym3 = Sym3 { xx: 1.0, xy: 0.0, yy: 1.0, xz: 0.0, yz: 0.0, zz: 1.0 };

    /// The zero matrix.
    pub const ZERO: Sym3 = Sym3 { xx: 0.0, xy: 0.0, yy: 0.0, xz: 0.0, yz: 0.0, zz: 0.0 };

    /// The diagonal matrix diag(d0, d1, d2).
    pub const fn diagonal(d: [f64; 3]) -> Sym3 {
        Sym3 { xx: d[0], xy: 0.0, yy: d[1], xz: 0.0, yz: 0.0, zz: d[2] }
    }

    /// The matrix Σ λᵢ eᵢ eᵢᵀ for eigenvalues `values` along the unit vectors `frame`
    /// (which should be orthonormal; nothing here checks it).
    pub fn from_eigen(values: [f64; 3], frame: [[f64; 3]; 3]) -> Sym3 {
        let mut m = Sym3::ZERO;
        for (l, e) in values.iter().zip(frame.iter()) {
            m.xx += l * e[0] * e[0];
            m.xy += l * e[0] * e[1];
            m.yy += l * e[1] * e[1];
            m.xz += l * e[0] * e[2];
            m.yz += l * e[1] * e[2];
            m.zz += l * e[2] * e[2];
        }
        m
    }

    /// The in-plane tensor `m` with `zz` on the third axis: `[[a, b, 0], [b, c, 0], [0, 0, zz]]`.
    pub fn from_sym2(m: Sym2, zz: f64) -> Sym3 {
        Sym3 { xx: m.a, xy: m.b, yy: m.c, xz: 0.0, yz: 0.0, zz }
    }

    /// The entry at row `i`, column `j` (both below 3).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.rows()[i][j]
    }

    /// The three rows.
    pub fn rows(&self) -> [[f64; 3]; 3] {
        [[self.xx, self.xy, self.xz], [self.xy, self.yy, self.yz], [self.xz, self.yz, self.zz]]
    }

    /// The determinant.
    pub fn det(&self) -> f64 {
        self.xx * (self.yy * self.zz - self.yz * self.yz)
            - self.xy * (self.xy * self.zz - self.yz * self.xz)
            + self.xz * (self.xy * self.yz - self.yy * self.xz)
    }

    /// The trace.
    pub fn trace(&self) -> f64 {
        self.xx + self.yy + self.zz
    }

    /// The product M v.
    pub fn mul_vec(&self, v: [f64; 3]) -> [f64; 3] {
        [
            self.xx * v[0] + self.xy * v[1] + self.xz * v[2],
            self.xy * v[0] + self.yy * v[1] + self.yz * v[2],
            self.xz * v[0] + self.yz * v[1] + self.zz * v[2],
        ]
    }

    /// The quadratic form vᵀ M v: the squared metric length of `v` when `self` is a metric.
    pub fn quadratic_form(&self, v: [f64; 3]) -> f64 {
        let [x, y, z] = v;
        self.xx * x * x
            + self.yy * y * y
            + self.zz * z * z
            + 2.0 * (self.xy * x * y + self.xz * x * z + self.yz * y * z)
    }

    /// Whether all six components are finite.
    pub fn is_finite(&self) -> bool {
        self.to_medit().iter().all(|c| c.is_finite())
    }

    /// The components in MMG's `.sol` order: m11 m12 m22 m13 m23 m33.
    pub fn to_medit(&self) -> [f64; 6] {
        [self.xx, self.xy, self.yy, self.xz, self.yz, self.zz]
    }

    /// The matrix from components in MMG's `.sol` order (the inverse of [`Sym3::to_medit`]).
    pub fn from_medit(c: [f64; 6]) -> Sym3 {
        Sym3 { xx: c[0], xy: c[1], yy: c[2], xz: c[3], yz: c[4], zz: c[5] }
    }

    /// The 9 components in row-major order, as Gmsh `.pos` tensor views, Gmsh 9-component
    /// `$NodeData` and VTK tensors carry them.
    pub fn to_row_major(&self) -> [f64; 9] {
        let r = self.rows();
        [r[0][0], r[0][1], r[0][2], r[1][0], r[1][1], r[1][2], r[2][0], r[2][1], r[2][2]]
    }

    /// The symmetric part of a row-major 3×3 tensor (the inverse of [`Sym3::to_row_major`]):
    /// a slightly unsymmetric tensor from a file gives the mean of its two off-diagonal
    /// entries.
    pub fn from_row_major(m: &[f64; 9]) -> Sym3 {
        Sym3 {
            xx: m[0],
            xy: 0.5 * m[1] + 0.5 * m[3],
            yy: m[4],
            xz: 0.5 * m[2] + 0.5 * m[6],
            yz: 0.5 * m[5] + 0.5 * m[7],
            zz: m[8],
        }
    }
}

impl Add for Sym3 {
    type Output = Sym3;
    fn add(self, o: Sym3) -> Sym3 {
        Sym3 {
            xx: self.xx + o.xx,
            xy: self.xy + o.xy,
            yy: self.yy + o.yy,
            xz: self.xz + o.xz,
            yz: self.yz + o.yz,
            zz: self.zz + o.zz,
        }
    }
}

impl Mul<Sym3> for f64 {
    type Output = Sym3;
    fn mul(self, m: Sym3) -> Sym3 {
        Sym3 {
            xx: self * m.xx,
            xy: self * m.xy,
            yy: self * m.yy,
            xz: self * m.xz,
            yz: self * m.yz,
            zz: self * m.zz,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orders_round_trip_and_agree() {
        let m = Sym3 { xx: 1.0, xy: 2.0, yy: 3.0, xz: 4.0, yz: 5.0, zz: 6.0 };
        assert_eq!(Sym3::from_medit(m.to_medit()), m);
        assert_eq!(Sym3::from_row_major(&m.to_row_major()), m);
        assert_eq!(m.to_row_major(), [1.0, 2.0, 4.0, 2.0, 3.0, 5.0, 4.0, 5.0, 6.0]);
    }

    #[test]
    fn determinant_and_form_match_the_rows() {
        let m = Sym3 { xx: 4.0, xy: 1.0, yy: 3.0, xz: 0.5, yz: -0.25, zz: 2.0 };
        let r = m.rows();
        // Rule of Sarrus, written apart from `det`.
        let sarrus =
            r[0][0] * r[1][1] * r[2][2] + r[0][1] * r[1][2] * r[2][0] + r[0][2] * r[1][0] * r[2][1]
                - r[0][2] * r[1][1] * r[2][0]
                - r[0][0] * r[1][2] * r[2][1]
                - r[0][1] * r[1][0] * r[2][2];
        assert!((m.det() - sarrus).abs() < 1e-12);
        let v = [0.3, -1.2, 2.0];
        let mv = m.mul_vec(v);
        let form = v[0] * mv[0] + v[1] * mv[1] + v[2] * mv[2];
        assert!((m.quadratic_form(v) - form).abs() < 1e-12);
    }

    #[test]
    fn eigen_frame_rebuilds_a_diagonal() {
        let frame = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]];
        let m = Sym3::from_eigen([2.0, 3.0, 5.0], frame);
        assert_eq!(m, Sym3::diagonal([5.0, 2.0, 3.0]));
    }
}
