//! What one dimension gives the Lp normaliser of [`super::lp`]: its mesh (points, cells,
//! the complexity integral and the vertex count it predicts), its Hessians (finiteness,
//! |eigenvalues| in decreasing order with their axes) and its size tensors. The
//! normalisation itself (exponent −1/(2p+n), the floors, the bisection, the bounds) is
//! written once over [`LpSpace`]; [`P1Mesh`] (triangles, n = 2) and [`P1Mesh3`]
//! (tetrahedra, n = 3) implement it here.
//!
//! Invariant: each implementation does the floating point operations of the code it
//! replaced in the same order, so the metrics are bit-identical to those of the separate
//! 2D and 3D normalisers; where the plane summed in another order than the general law
//! (the complexity integrand, the error law's constant 1/8), it keeps its own order in an
//! overriding method.

use crate::metric::complexity::{complexity, vertices_of_complexity};
use crate::metric::complexity3::{complexity3, vertices_of_complexity3};
use crate::metric::{SizeBounds, SizeTensor, SizeTensor3, Sym2, Sym3};
use crate::solution::{P1Mesh, P1Mesh3};

/// A mesh of simplices in n = `N` dimensions with its Hessian and size tensor types.
pub(crate) trait LpSpace<const N: usize> {
    /// The Hessian at a vertex.
    type Hessian: Copy;
    /// The eigenvectors a tensor is built on (in 2D the first axis, in 3D the frame).
    type Frame: Copy;
    /// The size tensor of the metric.
    type Tensor: Copy;
    /// A cell with `usize` corners.
    type Cell;
    /// The mean interpolation error factor: the Lp error of the optimal metric is
    /// `ERROR_FACTOR / D · (∫ det|H|^(p/(2p+n)))^(1/p)` (see [`super::lp`] and
    /// [`super::lp3`]).
    const ERROR_FACTOR: f64;

    /// The number of points.
    fn num_points(&self) -> usize;
    /// Whether a cell uses vertex `v`.
    fn is_used(&self, v: usize) -> bool;
    /// The cells.
    fn cells(&self) -> Vec<Self::Cell>;
    /// ∫ exp(f) exactly for `f` linear in each of `cells` (values `half_log_dets`).
    fn complexity(&self, cells: &[Self::Cell], half_log_dets: &[f64]) -> f64;
    /// The vertices of a mesh of complexity `c`.
    fn vertices_of_complexity(c: f64) -> f64;
    /// Whether every entry is finite.
    fn is_finite(h: &Self::Hessian) -> bool;
    /// Whether every entry is zero.
    fn is_zero(h: &Self::Hessian) -> bool;
    /// The |eigenvalues| in decreasing order (ties in the order of the eigensolver) and
    /// the axes that go with them.
    fn abs_eigen(h: &Self::Hessian) -> ([f64; N], Self::Frame);
    /// The tensor of sizes `h` along `frame`, `None` when it cannot be made.
    fn tensor(frame: Self::Frame, h: [f64; N]) -> Option<Self::Tensor>;
    /// The isotropic tensor of size `h`.
    fn isotropic(h: f64) -> Self::Tensor;
    /// `t` within `bounds`.
    fn clamp(t: &Self::Tensor, bounds: &SizeBounds) -> Self::Tensor;
    /// The sizes of `t`.
    fn sizes(t: &Self::Tensor) -> [f64; N];

    /// ½ ln det|H|^(p/(2p+n)) from ln g = ln det|H|^(−1/(2p+n)) and the ln |eigenvalues|:
    /// the integrand of the complexity at D = 1 without bounds.
    fn unit_half_log_det(ln_g: f64, ln_l: &[f64; N]) -> f64 {
        0.5 * (N as f64 * ln_g + ln_l.iter().sum::<f64>())
    }

    /// The ln D at which the predicted error is `e`, `root_ln` = ln (∫ …)^(1/p).
    fn ln_d_of_error(root_ln: f64, e: f64) -> f64 {
        root_ln + Self::ERROR_FACTOR.ln() - e.ln()
    }

    /// The predicted Lp error at D = exp(`ln_d`) of a field of integral `integral`.
    fn error_of(integral: f64, p: f64, ln_d: f64) -> f64 {
        let root_ln = if p.is_infinite() { 0.0 } else { integral.ln() / p };
        (root_ln + Self::ERROR_FACTOR.ln() - ln_d).exp()
    }
}

impl LpSpace<2> for P1Mesh<'_> {
    type Hessian = Sym2;
    type Frame = [f64; 2];
    type Tensor = SizeTensor;
    type Cell = [usize; 3];
    const ERROR_FACTOR: f64 = 1.0 / 8.0;

    fn num_points(&self) -> usize {
        self.points().len()
    }
    fn is_used(&self, v: usize) -> bool {
        P1Mesh::is_used(self, v)
    }
    fn cells(&self) -> Vec<[usize; 3]> {
        self.triangles().iter().map(|t| t.map(|v| v as usize)).collect()
    }
    fn complexity(&self, cells: &[[usize; 3]], half_log_dets: &[f64]) -> f64 {
        complexity(self.points(), cells, half_log_dets)
    }
    fn vertices_of_complexity(c: f64) -> f64 {
        vertices_of_complexity(c)
    }
    fn is_finite(h: &Sym2) -> bool {
        h.a.is_finite() && h.b.is_finite() && h.c.is_finite()
    }
    fn is_zero(h: &Sym2) -> bool {
        h.a == 0.0 && h.b == 0.0 && h.c == 0.0
    }
    fn abs_eigen(h: &Sym2) -> ([f64; 2], [f64; 2]) {
        let e = h.eigen();
        let (a0, a1) = (e.values[0].abs(), e.values[1].abs());
        if a0 >= a1 {
            ([a0, a1], e.vector)
        } else {
            ([a1, a0], [-e.vector[1], e.vector[0]])
        }
    }
    fn tensor(axis: [f64; 2], h: [f64; 2]) -> Option<SizeTensor> {
        SizeTensor::try_new(axis, h[0], h[1])
    }
    fn isotropic(h: f64) -> SizeTensor {
        SizeTensor::isotropic(h)
    }
    fn clamp(t: &SizeTensor, bounds: &SizeBounds) -> SizeTensor {
        t.clamp(bounds)
    }
    fn sizes(t: &SizeTensor) -> [f64; 2] {
        t.sizes()
    }

    // The plane's own order of the sums (see the module header).
    fn unit_half_log_det(ln_g: f64, ln_l: &[f64; 2]) -> f64 {
        0.5 * (2.0 * ln_g + ln_l[0] + ln_l[1])
    }
    fn ln_d_of_error(root_ln: f64, e: f64) -> f64 {
        root_ln - (8.0 * e).ln()
    }
    fn error_of(integral: f64, p: f64, ln_d: f64) -> f64 {
        let root = if p.is_infinite() { 1.0 } else { integral.powf(1.0 / p) };
        root / (8.0 * ln_d.exp())
    }
}

impl LpSpace<3> for P1Mesh3<'_> {
    type Hessian = Sym3;
    type Frame = [[f64; 3]; 3];
    type Tensor = SizeTensor3;
    type Cell = [usize; 4];
    const ERROR_FACTOR: f64 = 3.0 / 20.0;

    fn num_points(&self) -> usize {
        self.points().len()
    }
    fn is_used(&self, v: usize) -> bool {
        P1Mesh3::is_used(self, v)
    }
    fn cells(&self) -> Vec<[usize; 4]> {
        self.tets().iter().map(|t| t.map(|v| v as usize)).collect()
    }
    fn complexity(&self, cells: &[[usize; 4]], half_log_dets: &[f64]) -> f64 {
        complexity3(self.points(), cells, half_log_dets)
    }
    fn vertices_of_complexity(c: f64) -> f64 {
        vertices_of_complexity3(c)
    }
    fn is_finite(h: &Sym3) -> bool {
        h.is_finite()
    }
    fn is_zero(h: &Sym3) -> bool {
        *h == Sym3::ZERO
    }
    fn abs_eigen(h: &Sym3) -> ([f64; 3], [[f64; 3]; 3]) {
        let e = h.eigen();
        let mut order = [0, 1, 2];
        order.sort_by(|&i, &j| e.values[j].abs().total_cmp(&e.values[i].abs()));
        (order.map(|i| e.values[i].abs()), order.map(|i| e.frame[i]))
    }
    fn tensor(frame: [[f64; 3]; 3], h: [f64; 3]) -> Option<SizeTensor3> {
        SizeTensor3::try_new(frame[0], frame[1], h)
    }
    fn isotropic(h: f64) -> SizeTensor3 {
        SizeTensor3::isotropic(h)
    }
    fn clamp(t: &SizeTensor3, bounds: &SizeBounds) -> SizeTensor3 {
        t.clamp(bounds)
    }
    fn sizes(t: &SizeTensor3) -> [f64; 3] {
        t.sizes()
    }
}
