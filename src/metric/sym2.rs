//! `Sym2`: a plain symmetric 2×2 matrix `[[a, b], [b, c]]` (thesis 3.1.2 writes a metric
//! tensor with the same three letters).

use std::ops::{Add, Mul};

use super::eigen2::{eigen2, Eigen2};
use super::size_tensor::TensorError;

/// A symmetric 2×2 matrix `[[a, b], [b, c]]`, plain data for hot loops and for files.
///
/// Used for metric tensors (SPD, eigenvalues 1/h²), size matrices (eigenvalues h) and the
/// logarithms of either. Nothing here checks definiteness; [`Sym2::check_spd`] does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sym2 {
    /// Entry (0, 0), the xx component.
    pub a: f64,
    /// Entries (0, 1) and (1, 0), the xy component.
    pub b: f64,
    /// Entry (1, 1), the yy component.
    pub c: f64,
}

impl Sym2 {
    /// The identity matrix.
    pub const IDENTITY: Sym2 = Sym2 { a: 1.0, b: 0.0, c: 1.0 };

    /// The matrix `[[a, b], [b, c]]`.
    pub const fn new(a: f64, b: f64, c: f64) -> Sym2 {
        Sym2 { a, b, c }
    }

    /// The matrix λ1 e eᵀ + λ2 e⊥ e⊥ᵀ, where `axis` = e is a unit vector and e⊥ = (−e_y, e_x)
    /// (thesis Eq. 3.3 with the eigenvalues in `values`).
    pub fn from_eigen(values: [f64; 2], axis: [f64; 2]) -> Sym2 {
        let [x, y] = axis;
        let [l1, l2] = values;
        Sym2 { a: l1 * x * x + l2 * y * y, b: (l1 - l2) * x * y, c: l1 * y * y + l2 * x * x }
    }

    /// The determinant a c − b².
    pub fn det(&self) -> f64 {
        self.a * self.c - self.b * self.b
    }

    /// The trace a + c.
    pub fn trace(&self) -> f64 {
        self.a + self.c
    }

    /// The quadratic form vᵀ M v: the squared metric length of `v` when `self` is a metric.
    pub fn quadratic_form(&self, v: [f64; 2]) -> f64 {
        let [x, y] = v;
        self.a * x * x + 2.0 * self.b * x * y + self.c * y * y
    }

    /// The eigen-decomposition in closed form (see [`eigen2`]).
    pub fn eigen(&self) -> Eigen2 {
        eigen2(*self)
    }

    /// Checks that the matrix is symmetric positive definite, as a metric tensor must be
    /// (thesis 3.1.3): finite entries and both eigenvalues strictly positive.
    pub fn check_spd(&self) -> Result<(), TensorError> {
        if !(self.a.is_finite() && self.b.is_finite() && self.c.is_finite()) {
            return Err(TensorError::NotFinite { a: self.a, b: self.b, c: self.c });
        }
        let smallest = self.eigen().values[1];
        if smallest > 0.0 {
            Ok(())
        } else {
            Err(TensorError::NotPositiveDefinite { smallest_eigenvalue: smallest })
        }
    }

    /// The 9 components of the 3×3 tensor `[[a, b, 0], [b, c, 0], [0, 0, zz]]` in row-major
    /// order, as Gmsh `.pos` tensor views and VTK 9-component tensors carry it. A 2D metric
    /// needs some positive `zz` to stay SPD in 3D (for instance 1, or 1/h_min² for a metric).
    pub fn to_row_major_3x3(&self, zz: f64) -> [f64; 9] {
        [self.a, self.b, 0.0, self.b, self.c, 0.0, 0.0, 0.0, zz]
    }

    /// The in-plane part of a row-major 3×3 tensor (the inverse of
    /// [`Sym2::to_row_major_3x3`]). The xy and yx components are averaged, so a slightly
    /// unsymmetric tensor from a file gives its symmetric part; z components are ignored.
    pub fn from_row_major_3x3(m: &[f64; 9]) -> Sym2 {
        Sym2 { a: m[0], b: 0.5 * m[1] + 0.5 * m[3], c: m[4] }
    }
}

impl Add for Sym2 {
    type Output = Sym2;
    fn add(self, other: Sym2) -> Sym2 {
        Sym2 { a: self.a + other.a, b: self.b + other.b, c: self.c + other.c }
    }
}

impl Mul<Sym2> for f64 {
    type Output = Sym2;
    fn mul(self, m: Sym2) -> Sym2 {
        Sym2 { a: self * m.a, b: self * m.b, c: self * m.c }
    }
}
