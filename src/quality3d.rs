//! The shape and size of volume cells: the signed volume of every kind, and the quality
//! figures `info` prints for a 3D mesh.
//!
//! Definitions (each has an analytic twin in `tests/quality3d.rs`, and VTK's
//! `vtkMeshQuality`, which runs Verdict, is compared with them in
//! `tests/quality3d_vtk.rs`):
//! - *volume*: the integral of the Jacobian determinant of the cell's map, computed as
//!   (1/3)∮ x·n dA over its faces (divergence theorem), triangles flat and quadrilateral
//!   faces as the bilinear patches the trilinear hexahedron, the wedge and the pyramid
//!   have; 2×2 Gauss points integrate a bilinear face exactly. So a twisted hexahedron's
//!   volume is exact, not that of a split into tetrahedra. A second-order tetrahedron's
//!   is exact too: its Jacobian determinant is a cubic polynomial, integrated by Keast's
//!   5-point degree-3 rule (P. Keast, "Moderate-degree tetrahedral quadrature formulas",
//!   1986). The other second-order kinds are measured through their corners (the volume
//!   of the straight-sided cell): [`exact_volume`] tells which.
//! - tetrahedron *mean ratio*: η = 12 (3|V|)^(2/3) / Σ lᵢ² over the six edges (Liu and
//!   Joe 1994), signed as V: 1 for the regular tetrahedron, 0 for a flat one, negative
//!   for an inverted one. It is the 3D twin of the triangle quality `info` prints for
//!   2D meshes (4√3 A / Σ lᵢ²). VTK 9.7 (Verdict 1.4.5) reports η^(3/2) as "MeanRatio"
//!   (6√2 V / (Σ lᵢ² / 6)^(3/2)).
//! - tetrahedron *dihedral angles*: the interior angle between the two faces at each of
//!   the six edges, in degrees (70.53° everywhere for the regular tetrahedron); Verdict's
//!   "minimum angle" of a tetrahedron is the smallest of them.
//! - tetrahedron *aspect ratio*: Verdict's, h_max / (2√6 r) with h_max the longest edge
//!   and r the inradius (Knupp et al., "The Verdict Geometric Quality Library",
//!   SAND2007-1751, §6.2): 1 for the regular tetrahedron, infinite for a flat one.
//! - *scaled Jacobian* (Verdict's sections on each kind): at each corner, the determinant of
//!   the three edge vectors leaving it over the product of their lengths; the smallest
//!   over the corners. A hexahedron adds the value at its centre from its three principal
//!   axes (9 values). A wedge's value is scaled by 2/√3 so that a right prism on an
//!   equilateral triangle has 1. A tetrahedron's uses, as Verdict's, the corner with the
//!   largest product of edge lengths, times √2. A pyramid's is Verdict's: the smallest
//!   scaled Jacobian of the tetrahedra (0,1,2,4), (0,2,3,4), (0,1,3,4), (1,2,3,4), times
//!   √2, 0 when not positive, and 2 − s when s > 1 (the regular pyramid with equilateral
//!   sides has 1).
//! - *inverted*: a cell with a negative corner Jacobian (a tetrahedron with negative
//!   volume; a pyramid with a negative sub-tetrahedron); *degenerate*: one whose value
//!   is zero up to rounding ([`DEGENERATE`]), flat or with a collapsed edge.
//!
//! Node order is Gmsh's for every kind (see `smartmesh_formats::CellKind`): a positive
//! cell has a positive volume. Hand-written rather than bound to Verdict (C++), whose
//! few formulas used here are short.

use serde::Serialize;
use smartmesh_formats::{CellKind, TaggedMesh};

type P = [f64; 3];

/// |scaled Jacobian| at or below this is degenerate: the relative size of rounding in
/// the determinant of three unit vectors.
pub(crate) const DEGENERATE: f64 = 1e-12;

#[inline]
fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
fn cross(a: P, b: P) -> P {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}
#[inline]
fn norm(a: P) -> f64 {
    dot(a, a).sqrt()
}
#[inline]
fn det(a: P, b: P, c: P) -> f64 {
    dot(a, cross(b, c))
}

/// Whether [`signed_volume`] measures a cell of `kind` exactly (a linear kind, or a
/// second-order tetrahedron), rather than through its corners.
pub fn exact_volume(kind: CellKind) -> bool {
    !kind.is_second_order() || kind == CellKind::Tetra10
}

/// The mid-edge nodes of a second-order tetrahedron in Gmsh's order: (corner, corner,
/// node).
const TET10_EDGES: [[usize; 3]; 6] =
    [[0, 1, 4], [1, 2, 5], [0, 2, 6], [0, 3, 7], [2, 3, 8], [1, 3, 9]];

/// Signed volume of a second-order tetrahedron (10 nodes, Gmsh's order): ∫ det J over
/// the reference tetrahedron by Keast's degree-3 rule, exact for the cubic det J.
fn tet10_volume(p: &[P]) -> f64 {
    // Barycentric points and weights (the weights sum to 1; times the reference volume 1/6).
    let (a, b) = (0.5, 1.0 / 6.0);
    let points: [([f64; 4], f64); 5] = [
        ([0.25; 4], -0.8),
        ([a, b, b, b], 0.45),
        ([b, a, b, b], 0.45),
        ([b, b, a, b], 0.45),
        ([b, b, b, a], 0.45),
    ];
    let mut v = 0.0;
    for (l, w) in points {
        // ∂x/∂λ_k: the corner's (4λ_k − 1) x_k and each of its edges' 4 λ_other x_edge.
        let mut g = [[0.0; 3]; 4];
        for k in 0..4 {
            g[k] = p[k].map(|c| (4.0 * l[k] - 1.0) * c);
        }
        for [i, j, m] in TET10_EDGES {
            for c in 0..3 {
                g[i][c] += 4.0 * l[j] * p[m][c];
                g[j][c] += 4.0 * l[i] * p[m][c];
            }
        }
        // λ_0 = 1 − ξ − η − ζ: ∂x/∂ξ = ∂x/∂λ_1 − ∂x/∂λ_0, and so on.
        v += w * det(sub(g[1], g[0]), sub(g[2], g[0]), sub(g[3], g[0]));
    }
    v / 6.0
}

/// Signed volume of a volume cell of `kind` with nodes at `p` (Gmsh's order; see
/// [`exact_volume`] for second-order cells): positive for a cell in Gmsh's orientation.
/// `None` for a kind that is no volume kind.
pub fn signed_volume(kind: CellKind, p: &[P]) -> Option<f64> {
    if kind.dim() != 3 {
        return None;
    }
    if kind == CellKind::Tetra10 {
        return Some(tet10_volume(p));
    }
    let n = kind.linear().nodes_per_cell();
    // Relative to the centroid, so that a small cell far from the origin keeps its digits.
    let mut c = [0.0; 3];
    for q in &p[..n] {
        for k in 0..3 {
            c[k] += q[k] / n as f64;
        }
    }
    let at = |i: usize| sub(p[i], c);
    // The two Gauss points on [0, 1], weight 1/2 each.
    let g = [0.5 - 0.5 / 3f64.sqrt(), 0.5 + 0.5 / 3f64.sqrt()];
    let mut six_v = 0.0; // 6 V = 2 ∮ x·n dA
    for f in kind.faces() {
        if f.len() == 3 {
            six_v += det(at(f[0]), at(f[1]), at(f[2]));
            continue;
        }
        let (a, b, cc, d) = (at(f[0]), at(f[1]), at(f[2]), at(f[3]));
        for &u in &g {
            for &v in &g {
                let mix = |w: [f64; 4]| -> P {
                    let mut x = [0.0; 3];
                    for k in 0..3 {
                        x[k] = w[0] * a[k] + w[1] * b[k] + w[2] * cc[k] + w[3] * d[k];
                    }
                    x
                };
                let x = mix([(1.0 - u) * (1.0 - v), u * (1.0 - v), u * v, (1.0 - u) * v]);
                let xu = mix([-(1.0 - v), 1.0 - v, v, -v]);
                let xv = mix([-(1.0 - u), -u, u, 1.0 - u]);
                // ∫∫ x·(xu × xv) du dv, weights 1/4; times 2 for 6V = 2·3V.
                six_v += 0.5 * dot(x, cross(xu, xv));
            }
        }
    }
    Some(six_v / 6.0)
}

/// The six edges of a tetrahedron as corner pairs, with the two other corners.
const TET_EDGES: [[usize; 4]; 6] =
    [[0, 1, 2, 3], [0, 2, 1, 3], [0, 3, 1, 2], [1, 2, 0, 3], [1, 3, 0, 2], [2, 3, 0, 1]];

/// Signed volume of tetrahedron `t`.
pub fn tet_volume(t: &[P; 4]) -> f64 {
    det(sub(t[1], t[0]), sub(t[2], t[0]), sub(t[3], t[0])) / 6.0
}

/// Mean ratio η = 12 (3|V|)^(2/3) / Σ lᵢ², signed as the volume (see the module header).
pub fn tet_mean_ratio(t: &[P; 4]) -> f64 {
    let v = tet_volume(t);
    let s: f64 = TET_EDGES.iter().map(|e| dot(sub(t[e[1]], t[e[0]]), sub(t[e[1]], t[e[0]]))).sum();
    if s == 0.0 {
        return 0.0;
    }
    v.signum() * 12.0 * (3.0 * v.abs()).powf(2.0 / 3.0) / s
}

/// The interior dihedral angle of tetrahedron `t` at each edge, in degrees, edges in the
/// order 01, 02, 03, 12, 13, 23. A flat tetrahedron has 0 and 180 (NaN where a face has
/// no area).
pub fn tet_dihedral_angles(t: &[P; 4]) -> [f64; 6] {
    TET_EDGES.map(|e| {
        let axis = sub(t[e[1]], t[e[0]]);
        // The two other corners, seen along the edge: the normals of the two faces.
        let u = cross(axis, sub(t[e[2]], t[e[0]]));
        let w = cross(axis, sub(t[e[3]], t[e[0]]));
        norm(cross(u, w)).atan2(dot(u, w)).to_degrees()
    })
}

/// Smallest and largest interior dihedral angle of tetrahedron `t`, in degrees.
pub fn tet_dihedral_range(t: &[P; 4]) -> [f64; 2] {
    tet_dihedral_angles(t)
        .iter()
        .fold([f64::INFINITY, f64::NEG_INFINITY], |r, &a| [r[0].min(a), r[1].max(a)])
}

/// Verdict's aspect ratio h_max / (2√6 r) (see the module header); infinite when flat.
pub fn tet_aspect_ratio(t: &[P; 4]) -> f64 {
    let six_v = (6.0 * tet_volume(t)).abs();
    let h_max = TET_EDGES.iter().map(|e| norm(sub(t[e[1]], t[e[0]]))).fold(0.0, f64::max);
    // Twice the total face area.
    let two_a: f64 = CellKind::Tetra
        .faces()
        .iter()
        .map(|f| norm(cross(sub(t[f[1]], t[f[0]]), sub(t[f[2]], t[f[0]]))))
        .sum();
    if six_v == 0.0 {
        return f64::INFINITY;
    }
    // r = 3V / A = six_v / two_a, so h_max / (2√6 r) = h_max two_a / (2√6 six_v).
    h_max * two_a / (2.0 * 6f64.sqrt() * six_v)
}

/// The corner Jacobians of a hexahedron or a wedge: for each corner, the three edge vectors leaving it in
/// right-handed order (Gmsh's node order).
fn corner_frames(kind: CellKind) -> &'static [[usize; 4]] {
    match kind {
        CellKind::Hexa => &[
            [0, 1, 3, 4],
            [1, 2, 0, 5],
            [2, 3, 1, 6],
            [3, 0, 2, 7],
            [4, 7, 5, 0],
            [5, 4, 6, 1],
            [6, 5, 7, 2],
            [7, 6, 4, 3],
        ],
        CellKind::Wedge => {
            &[[0, 1, 2, 3], [1, 2, 0, 4], [2, 0, 1, 5], [3, 5, 4, 0], [4, 3, 5, 1], [5, 4, 3, 2]]
        }
        _ => &[],
    }
}

/// The determinant of the corner frame `f` over the product of its edge lengths.
fn scaled_corner(p: &[P], f: [usize; 4]) -> f64 {
    let (a, b, c) = (sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]), sub(p[f[3]], p[f[0]]));
    let l = norm(a) * norm(b) * norm(c);
    if l == 0.0 {
        0.0
    } else {
        det(a, b, c) / l
    }
}

/// Verdict's scaled Jacobian of a tetrahedron: √2 · 6V over the largest product of the
/// three edge lengths at a corner (1 for the regular tetrahedron).
pub fn tet_scaled_jacobian(t: &[P; 4]) -> f64 {
    let l = |i: usize, j: usize| norm(sub(t[j], t[i]));
    let prod = [
        l(0, 1) * l(0, 2) * l(0, 3),
        l(1, 0) * l(1, 2) * l(1, 3),
        l(2, 0) * l(2, 1) * l(2, 3),
        l(3, 0) * l(3, 1) * l(3, 2),
    ];
    let six_v = 6.0 * tet_volume(t);
    let m = prod.iter().copied().fold(six_v.abs(), f64::max);
    if m == 0.0 {
        return 0.0;
    }
    2f64.sqrt() * six_v / m
}

/// Verdict's scaled Jacobian of a hexahedron: the smallest over the eight corners and the
/// centre (its three principal axes).
pub fn hex_scaled_jacobian(p: &[P]) -> f64 {
    let axis = |plus: [usize; 4], minus: [usize; 4]| {
        let mut a = [0.0; 3];
        for k in 0..4 {
            a = [
                a[0] + p[plus[k]][0] - p[minus[k]][0],
                a[1] + p[plus[k]][1] - p[minus[k]][1],
                a[2] + p[plus[k]][2] - p[minus[k]][2],
            ];
        }
        a
    };
    let x = axis([1, 2, 5, 6], [0, 3, 4, 7]);
    let y = axis([3, 2, 7, 6], [0, 1, 4, 5]);
    let z = axis([4, 5, 6, 7], [0, 1, 2, 3]);
    let l = norm(x) * norm(y) * norm(z);
    let centre = if l == 0.0 { 0.0 } else { det(x, y, z) / l };
    corner_frames(CellKind::Hexa).iter().map(|&f| scaled_corner(p, f)).fold(centre, f64::min)
}

/// Verdict's scaled Jacobian of a wedge: the smallest over the six corners, times 2/√3.
pub fn wedge_scaled_jacobian(p: &[P]) -> f64 {
    let m = corner_frames(CellKind::Wedge)
        .iter()
        .map(|&f| scaled_corner(p, f))
        .fold(f64::INFINITY, f64::min);
    m * 2.0 / 3f64.sqrt()
}

/// The four tetrahedra Verdict cuts a pyramid into.
const PYRAMID_TETS: [[usize; 4]; 4] = [[0, 1, 2, 4], [0, 2, 3, 4], [0, 1, 3, 4], [1, 2, 3, 4]];

/// The smallest scaled Jacobian of a pyramid's four tetrahedra, unclamped: its sign
/// tells an inverted pyramid.
fn pyramid_raw(p: &[P]) -> f64 {
    PYRAMID_TETS
        .iter()
        .map(|t| tet_scaled_jacobian(&[p[t[0]], p[t[1]], p[t[2]], p[t[3]]]))
        .fold(f64::INFINITY, f64::min)
}

/// Verdict's scaled Jacobian of a pyramid (see the module header): in [0, 1].
pub fn pyramid_scaled_jacobian(p: &[P]) -> f64 {
    let s = pyramid_raw(p);
    if s <= 0.0 {
        return 0.0;
    }
    let s = s * 2f64.sqrt();
    if s < 1.0 {
        s
    } else {
        2.0 - s
    }
}

/// Scaled Jacobian of a volume cell (a second-order one through its corners), and the
/// signed value that tells inverted (< 0) and degenerate (≈ 0) cells apart.
pub fn scaled_jacobian(kind: CellKind, p: &[P]) -> Option<(f64, f64)> {
    let t = |p: &[P]| [p[0], p[1], p[2], p[3]];
    Some(match kind.linear() {
        CellKind::Tetra => {
            let s = tet_scaled_jacobian(&t(p));
            (s, s)
        }
        CellKind::Hexa => {
            let s = hex_scaled_jacobian(p);
            (s, s)
        }
        CellKind::Wedge => {
            let s = wedge_scaled_jacobian(p);
            (s, s)
        }
        CellKind::Pyramid => (pyramid_scaled_jacobian(p), pyramid_raw(p)),
        _ => return None,
    })
}

/// `[min, mean, max]` of a stream of values, built one value at a time.
#[derive(Default)]
struct Acc {
    n: usize,
    sum: f64,
    lo: f64,
    hi: f64,
}

impl Acc {
    fn add(&mut self, v: f64) {
        if self.n == 0 {
            (self.lo, self.hi) = (v, v);
        }
        self.n += 1;
        self.sum += v;
        self.lo = self.lo.min(v);
        self.hi = self.hi.max(v);
    }
    fn get(&self) -> [f64; 3] {
        [self.lo, self.sum / self.n.max(1) as f64, self.hi]
    }
}

/// The quality of a mesh's tetrahedra (second-order ones through their corners).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TetraQuality {
    /// Tetrahedra measured.
    pub cells: usize,
    /// Mean ratio `[min, mean, max]`.
    pub mean_ratio: [f64; 3],
    /// Smallest and largest dihedral angle over all tetrahedra, degrees.
    pub dihedral_deg: [f64; 2],
    /// Aspect ratio `[min, mean, max]` (infinite for a flat tetrahedron).
    pub aspect_ratio: [f64; 3],
    /// Counts of tetrahedra whose mean ratio falls in [0,0.1), … [0.9,1] (negative
    /// ones in the first bin).
    pub histogram: [usize; 10],
}

/// The scaled Jacobian of the cells of one kind (hexahedra, wedges, pyramids, and their
/// second-order kinds through their corners).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KindQuality {
    /// The kind's name.
    pub kind: String,
    /// Cells measured.
    pub cells: usize,
    /// Scaled Jacobian `[min, mean, max]`.
    pub scaled_jacobian: [f64; 3],
}

/// What `info` says of the shape of a mesh's volume cells.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VolumeQuality {
    /// Tetrahedra, when there are any.
    pub tetra: Option<TetraQuality>,
    /// The other volume kinds, by kind name.
    pub others: Vec<KindQuality>,
    /// Cells with a negative corner Jacobian (negative volume for a tetrahedron).
    pub inverted: usize,
    /// Cells whose scaled Jacobian is zero up to rounding (at most 1e-12 in magnitude).
    pub degenerate: usize,
}

impl VolumeQuality {
    /// Measures the volume cells of `mesh`; `None` when it has none.
    pub fn of(mesh: &TaggedMesh) -> Option<VolumeQuality> {
        let (mut ratio, mut ar) = (Acc::default(), Acc::default());
        let mut dihedral = [f64::INFINITY, f64::NEG_INFINITY];
        let mut histogram = [0usize; 10];
        let mut others: std::collections::BTreeMap<&str, Acc> = Default::default();
        let (mut inverted, mut degenerate, mut any) = (0, 0, false);
        let mut p = Vec::with_capacity(8);
        for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 3) {
            let lin = b.kind.linear();
            let n = lin.nodes_per_cell();
            for cell in b.cells() {
                any = true;
                p.clear();
                p.extend(cell[..n].iter().map(|&v| mesh.points[v as usize]));
                let (s, signed) = scaled_jacobian(lin, &p).expect("a volume kind");
                if signed.abs() <= DEGENERATE {
                    degenerate += 1;
                } else if signed < 0.0 {
                    inverted += 1;
                }
                if lin == CellKind::Tetra {
                    let t = [p[0], p[1], p[2], p[3]];
                    let q = tet_mean_ratio(&t);
                    ratio.add(q);
                    histogram[((q.max(0.0) * 10.0) as usize).min(9)] += 1;
                    let d = tet_dihedral_range(&t);
                    dihedral = [dihedral[0].min(d[0]), dihedral[1].max(d[1])];
                    ar.add(tet_aspect_ratio(&t));
                } else {
                    others.entry(lin.name()).or_default().add(s);
                }
            }
        }
        if !any {
            return None;
        }
        Some(VolumeQuality {
            tetra: (ratio.n > 0).then(|| TetraQuality {
                cells: ratio.n,
                mean_ratio: ratio.get(),
                dihedral_deg: dihedral,
                aspect_ratio: ar.get(),
                histogram,
            }),
            others: others
                .into_iter()
                .map(|(k, a)| KindQuality {
                    kind: k.to_string(),
                    cells: a.n,
                    scaled_jacobian: a.get(),
                })
                .collect(),
            inverted,
            degenerate,
        })
    }
}
