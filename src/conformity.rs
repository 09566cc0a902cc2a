//! How well a mesh conforms to a metric field: the figures the remesher, the adaptation
//! loop, `info` and `report` share, each edge and triangle measured by the kernels of
//! [`crate::metric::length`] (metric edge length, metric triangle quality); a mesh
//! conforms when its edges have metric lengths in [`CONFORMING`], [1/√2, √2].
//!
//! [`Ugawg`] gives the measures as the UGAWG benchmarks publish them, on planar meshes
//! with a 2D metric and on meshes in space (tetrahedra, surfaces) with a 3D one.

use rayon::prelude::*;
use serde::Serialize;

use crate::metric::length::{metric_edge_length, metric_triangle_quality, CONFORMING};
use crate::metric::length3::{mean_ratio_in_metric, metric_edge_length3};
use crate::metric::{log_euclidean3, log_spd3};
use crate::metric::{Sym2, Sym3};
use crate::metric_field::MetricField;
use smartmesh_formats::{CellKind, TaggedMesh};

pub(crate) use crate::metric_field::MetricFieldError;

/// The metric field named `name` (usually [`crate::metric_field::METRIC`]) of a mesh's
/// point data, one SPD tensor per vertex: [`MetricField::from_point_data`], whose checks
/// every reader of a metric shares. Vertices that no cell uses may carry any value (Gmsh
/// keeps such nodes); they get the identity rather than an error.
pub fn metric_field(mesh: &TaggedMesh, name: &str) -> Result<Vec<Sym2>, MetricFieldError> {
    MetricField::from_point_data(mesh, name).map(MetricField::into_tensors)
}

/// How a triangle mesh conforms to a metric: the figures of issue-level quality bars.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Conformity {
    /// Edges measured (each undirected edge of the triangles once).
    pub edges: usize,
    /// Share of edges with metric length in [1/√2, √2].
    pub conforming_share: f64,
    /// Mean metric edge length.
    pub mean_edge_length: f64,
    /// Shortest and longest metric edge length.
    pub edge_length_range: [f64; 2],
    /// Edge counts in metric-length bins of width 0.1 from 0 to 3 (the last bin holds
    /// everything longer).
    pub edge_length_histogram: Vec<usize>,
    /// Triangles measured.
    pub triangles: usize,
    /// Mean metric quality.
    pub mean_quality: f64,
    /// Smallest metric quality.
    pub min_quality: f64,
    /// Triangle counts in quality bins [0,0.1), … [0.9,1].
    pub quality_histogram: [usize; 10],
}

/// Number of metric-length bins in [`Conformity::edge_length_histogram`].
pub(crate) const LENGTH_BINS: usize = 30;

impl Conformity {
    /// Measures triangles `tris` (counter-clockwise or not, each a triple of indices into
    /// `points`) against `metric` (one per point). `None` when there is no triangle.
    pub fn of(points: &[[f64; 2]], tris: &[[usize; 3]], metric: &[Sym2]) -> Option<Conformity> {
        if tris.is_empty() {
            return None;
        }
        let mut edges: Vec<[usize; 2]> = Vec::with_capacity(tris.len() * 3);
        for t in tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                edges.push([a.min(b), a.max(b)]);
            }
        }
        // Sorted in parallel, measured in parallel, summed in order: the figures do not
        // depend on the thread count.
        edges.par_sort_unstable();
        edges.dedup();
        let mut c = Conformity {
            edges: edges.len(),
            conforming_share: 0.0,
            mean_edge_length: 0.0,
            edge_length_range: [f64::INFINITY, 0.0],
            edge_length_histogram: vec![0; LENGTH_BINS],
            triangles: tris.len(),
            mean_quality: 0.0,
            min_quality: f64::INFINITY,
            quality_histogram: [0; 10],
        };
        let (mut ok, mut sum) = (0usize, 0.0);
        let lengths: Vec<f64> = edges
            .par_iter()
            .map(|&[a, b]| metric_edge_length(points[a], points[b], &metric[a], &metric[b]))
            .collect();
        for l in lengths {
            if (CONFORMING[0]..=CONFORMING[1]).contains(&l) {
                ok += 1;
            }
            sum += l;
            c.edge_length_range[0] = c.edge_length_range[0].min(l);
            c.edge_length_range[1] = c.edge_length_range[1].max(l);
            c.edge_length_histogram[((l * 10.0) as usize).min(LENGTH_BINS - 1)] += 1;
        }
        c.conforming_share = ok as f64 / edges.len() as f64;
        c.mean_edge_length = sum / edges.len() as f64;
        let mut qsum = 0.0;
        let qualities: Vec<f64> =
            tris.par_iter().map(|t| signed_triangle_quality(points, t, metric)).collect();
        for q in qualities {
            qsum += q;
            c.min_quality = c.min_quality.min(q);
            c.quality_histogram[((q.max(0.0) * 10.0) as usize).min(9)] += 1;
        }
        c.mean_quality = qsum / tris.len() as f64;
        Some(c)
    }

    /// Measures the triangles of a tagged mesh (quads split along their first diagonal).
    pub fn of_mesh(mesh: &TaggedMesh, metric: &[Sym2]) -> Option<Conformity> {
        let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
        let mut tris = Vec::new();
        for (kind, n, _, _) in mesh.cells() {
            match kind {
                smartmesh_formats::CellKind::Triangle => {
                    tris.push([n[0] as usize, n[1] as usize, n[2] as usize])
                }
                smartmesh_formats::CellKind::Quad => {
                    tris.push([n[0] as usize, n[1] as usize, n[2] as usize]);
                    tris.push([n[0] as usize, n[2] as usize, n[3] as usize]);
                }
                _ => {}
            }
        }
        Conformity::of(&points, &tris, metric)
    }
}

/// The measures of a mesh against a metric as the Unstructured Grid Adaptation Working
/// Group reports them (UGAWG; nasa/refine's `ref_histogram` on its `ref_node` kernels),
/// in 2D, on surfaces in space and on tetrahedra:
///
/// - the metric length of an edge ab is the log-mean of its ends' lengths,
///   L = (la − lb) / ln(la / lb) with la = √(abᵀ Ma ab), lb = √(abᵀ Mb ab) (la when equal;
///   [`crate::metric::length::geometric_mean_length`]);
/// - the quality of a cell is its mean ratio in the Log-Euclidean mean M of its corners'
///   metrics: 4√3 A_M / Σ l²_M for a triangle and 36/3^(1/3) (V_M)^(2/3) / Σ l²_M for a
///   tetrahedron (A_M, V_M its area, volume in M; l_M its edges' lengths in M), 1 for a
///   cell equilateral in M, negative for an inverted one (a triangle of a 2D mesh, a
///   tetrahedron); a triangle in space has no sign;
/// - refine prints each histogram's min, max and "mean" 2^(mean log2 x), the geometric
///   mean, over the positive observations: both means are given here.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ugawg {
    /// 2 for a planar mesh with a 2D metric, 3 for a mesh in space.
    pub dimension: u8,
    /// Edges measured (each undirected edge of the measured cells once).
    pub edges: usize,
    /// Share of edges with metric length in [1/√2, √2].
    pub conforming_share: f64,
    /// Shortest and longest metric edge length.
    pub edge_length_range: [f64; 2],
    /// Arithmetic mean of the metric edge lengths.
    pub mean_edge_length: f64,
    /// Geometric mean of the positive metric edge lengths (refine's "mean").
    pub geometric_mean_edge_length: f64,
    /// What the measured cells are: "triangle" or "tetrahedron".
    pub cell: &'static str,
    /// Cells measured.
    pub cells: usize,
    /// Smallest mean-ratio quality.
    pub min_quality: f64,
    /// Arithmetic mean quality over every cell.
    pub mean_quality: f64,
    /// Geometric mean quality over the cells of positive quality (refine's "mean").
    pub geometric_mean_quality: f64,
    /// Cells of quality 0 or less (flat or inverted).
    pub non_positive: usize,
    /// Cells of other kinds, not measured (quadrangles; hexahedra, prisms, pyramids).
    pub left_out: usize,
}

impl Ugawg {
    /// The figures of edge lengths and cell qualities, in their order.
    fn from_values(
        dimension: u8,
        cell: &'static str,
        lengths: &[f64],
        qualities: &[f64],
        left_out: usize,
    ) -> Option<Ugawg> {
        if qualities.is_empty() {
            return None;
        }
        let geometric = |xs: &[f64]| {
            let (mut n, mut sum) = (0usize, 0.0);
            for &x in xs.iter().filter(|&&x| x > 0.0) {
                n += 1;
                sum += x.log2();
            }
            if n == 0 {
                0.0
            } else {
                (sum / n as f64).exp2()
            }
        };
        let ok = lengths.iter().filter(|l| (CONFORMING[0]..=CONFORMING[1]).contains(*l)).count();
        Some(Ugawg {
            dimension,
            edges: lengths.len(),
            conforming_share: ok as f64 / lengths.len().max(1) as f64,
            edge_length_range: [
                lengths.iter().copied().fold(f64::INFINITY, f64::min),
                lengths.iter().copied().fold(0.0, f64::max),
            ],
            mean_edge_length: lengths.iter().sum::<f64>() / lengths.len().max(1) as f64,
            geometric_mean_edge_length: geometric(lengths),
            cell,
            cells: qualities.len(),
            min_quality: qualities.iter().copied().fold(f64::INFINITY, f64::min),
            mean_quality: qualities.iter().sum::<f64>() / qualities.len() as f64,
            geometric_mean_quality: geometric(qualities),
            non_positive: qualities.iter().filter(|&&q| q <= 0.0).count(),
            left_out,
        })
    }

    /// A planar mesh's triangles against a 2D metric (one tensor per point); `None` when
    /// there is no triangle. Quadrangles are left out (counted).
    pub fn of_mesh_2d(mesh: &TaggedMesh, metric: &[Sym2]) -> Option<Ugawg> {
        let points: Vec<[f64; 2]> = mesh.points.iter().map(|p| [p[0], p[1]]).collect();
        let (cells, left_out) = corners(mesh, CellKind::Triangle);
        let tris: Vec<[usize; 3]> = cells.iter().map(|c| [c[0], c[1], c[2]]).collect();
        let lengths: Vec<f64> = unique_edges(&cells)
            .par_iter()
            .map(|&[a, b]| metric_edge_length(points[a], points[b], &metric[a], &metric[b]))
            .collect();
        let qualities: Vec<f64> =
            tris.par_iter().map(|t| signed_triangle_quality(&points, t, metric)).collect();
        Ugawg::from_values(2, "triangle", &lengths, &qualities, left_out)
    }

    /// A mesh in space against a 3D metric (one tensor per point): its tetrahedra, or,
    /// when it has none, its triangles (a surface in space); `None` when it has neither.
    /// Other cells are left out (counted).
    pub fn of_mesh_3d(mesh: &TaggedMesh, metric: &[Sym3]) -> Option<Ugawg> {
        let (tets, other_volume) = corners(mesh, CellKind::Tetra);
        let (cells, left_out, cell) = if tets.is_empty() {
            let (tris, other) = corners(mesh, CellKind::Triangle);
            (tris, other, "triangle")
        } else {
            (tets, other_volume, "tetrahedron")
        };
        let p = &mesh.points;
        let lengths: Vec<f64> = unique_edges(&cells)
            .par_iter()
            .map(|&[a, b]| metric_edge_length3(p[a], p[b], &metric[a], &metric[b]))
            .collect();
        let qualities: Vec<f64> = cells
            .par_iter()
            .map(|c| {
                let logs: Vec<Sym3> = c.iter().map(|&v| log_spd3(&metric[v])).collect();
                let weights = vec![1.0 / c.len() as f64; c.len()];
                let mean = log_euclidean3(&weights, &logs.iter().collect::<Vec<_>>());
                let x: Vec<[f64; 3]> = c.iter().map(|&v| p[v]).collect();
                if c.len() == 4 {
                    mean_ratio_in_metric([x[0], x[1], x[2], x[3]], &mean)
                } else {
                    triangle_quality_in_3d(&x, &mean)
                }
            })
            .collect();
        Ugawg::from_values(3, cell, &lengths, &qualities, left_out)
    }
}

/// The metric quality of triangle `t`, negative when it turns clockwise. Orientation is
/// the file's business; quality measures shape, and the sign only says the turn.
fn signed_triangle_quality(points: &[[f64; 2]], t: &[usize; 3], metric: &[Sym2]) -> f64 {
    let p = [points[t[0]], points[t[1]], points[t[2]]];
    let q = metric_triangle_quality(p, [&metric[t[0]], &metric[t[1]], &metric[t[2]]]);
    if crate::quality::signed_area(p[0], p[1], p[2]) < 0.0 {
        -q
    } else {
        q
    }
}

/// The corners of the cells of `kind` (and of its second-order kinds), and the count of
/// cells of the same dimension of other kinds.
fn corners(mesh: &TaggedMesh, kind: CellKind) -> (Vec<Vec<usize>>, usize) {
    let (mut cells, mut other) = (Vec::new(), 0);
    let k = kind.nodes_per_cell();
    for (c, n, _, _) in mesh.cells() {
        if c.linear() == kind {
            cells.push(n[..k].iter().map(|&v| v as usize).collect());
        } else if c.dim() == kind.dim() {
            other += 1;
        }
    }
    (cells, other)
}

/// Each undirected edge of `cells` (every pair of corners: a triangle's three, a
/// tetrahedron's six) once, sorted.
fn unique_edges(cells: &[Vec<usize>]) -> Vec<[usize; 2]> {
    let mut edges: Vec<[usize; 2]> = Vec::with_capacity(cells.len() * 6);
    for c in cells {
        for i in 0..c.len() {
            for j in i + 1..c.len() {
                edges.push([c[i].min(c[j]), c[i].max(c[j])]);
            }
        }
    }
    edges.par_sort_unstable();
    edges.dedup();
    edges
}

fn sub(b: [f64; 3], a: [f64; 3]) -> [f64; 3] {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}

/// Mean ratio of the triangle `x` (3 corners in space) in the constant metric `m`.
fn triangle_quality_in_3d(x: &[[f64; 3]], m: &Sym3) -> f64 {
    let (e1, e2) = (sub(x[1], x[0]), sub(x[2], x[0]));
    let g11 = m.quadratic_form(e1);
    let g22 = m.quadratic_form(e2);
    let me2 = m.mul_vec(e2);
    let g12 = e1[0] * me2[0] + e1[1] * me2[1] + e1[2] * me2[2];
    let l2 = g11 + g22 + m.quadratic_form(sub(x[2], x[1]));
    if l2 <= 0.0 {
        return 0.0;
    }
    let area = 0.5 * (g11 * g22 - g12 * g12).max(0.0).sqrt();
    4.0 * 3f64.sqrt() * area / l2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metric::length::metric_triangle_quality;
    use crate::metric::SizeTensor;
    use crate::metric::Sym3;

    #[test]
    fn stretched_triangle_is_equilateral_in_its_metric() {
        // h1 = 10 along x, h2 = 0.1 along y: the triangle scaled by (10, 0.1) is ideal.
        let m = SizeTensor::new([1.0, 0.0], 10.0, 0.1).to_metric();
        let p = [[0.0, 0.0], [10.0, 0.0], [5.0, 0.1 * 3f64.sqrt() / 2.0]];
        assert!((metric_triangle_quality(p, [&m, &m, &m]) - 1.0).abs() < 1e-9);
        let c = Conformity::of(&p, &[[0, 1, 2]], &[m, m, m]).unwrap();
        assert_eq!(c.conforming_share, 1.0);
        assert_eq!(c.edges, 3);
    }

    /// A cube [0,1]³ cut into its six Kuhn tetrahedra (all around the diagonal 0-7).
    fn kuhn_cube(scale: [f64; 3]) -> TaggedMesh {
        let mut mesh = TaggedMesh::new();
        mesh.points = (0..8)
            .map(|i| {
                [
                    (i & 1) as f64 * scale[0],
                    (i >> 1 & 1) as f64 * scale[1],
                    (i >> 2) as f64 * scale[2],
                ]
            })
            .collect();
        for t in
            [[0, 1, 3, 7], [0, 1, 5, 7], [0, 2, 3, 7], [0, 2, 6, 7], [0, 4, 5, 7], [0, 4, 6, 7]]
        {
            mesh.block_mut(CellKind::Tetra).push(&t, 1, 1);
        }
        mesh
    }

    #[test]
    fn a_regular_tetrahedron_of_the_metric_measures_one() {
        // Sizes 2, 0.5, 0.1 along a rotated frame; the unit regular tetrahedron mapped by
        // M^(-1/2) = R diag(h) Rᵀ has unit metric edges and mean ratio 1.
        let (c, s) = (0.6f64, 0.8f64);
        let frame = [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]];
        let h = [2.0, 0.5, 0.1];
        let m = Sym3::from_eigen(h.map(|h| 1.0 / (h * h)), frame);
        let root = Sym3::from_eigen(h, frame);
        let regular = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 3f64.sqrt() / 2.0, 0.0],
            [0.5, 3f64.sqrt() / 6.0, (2.0f64 / 3.0).sqrt()],
        ];
        let mut mesh = TaggedMesh::new();
        mesh.points = regular.iter().map(|&p| root.mul_vec(p)).collect();
        mesh.block_mut(CellKind::Tetra).push(&[0, 1, 2, 3], 1, 1);
        let u = Ugawg::of_mesh_3d(&mesh, &[m; 4]).unwrap();
        assert_eq!((u.edges, u.cells, u.cell), (6, 1, "tetrahedron"));
        assert!((u.edge_length_range[0] - 1.0).abs() < 1e-12, "{u:?}");
        assert!((u.edge_length_range[1] - 1.0).abs() < 1e-12, "{u:?}");
        assert!((u.min_quality - 1.0).abs() < 1e-12, "{u:?}");
        assert_eq!(u.conforming_share, 1.0);
        // The same tetrahedron inverted (two corners swapped) measures -1.
        mesh.blocks[0].nodes.swap(0, 1);
        let u = Ugawg::of_mesh_3d(&mesh, &[m; 4]).unwrap();
        assert!((u.min_quality + 1.0).abs() < 1e-12 && u.non_positive == 1, "{u:?}");
    }

    #[test]
    fn a_linear_metric_on_tetrahedra_agrees_with_its_twin() {
        // UGAWG's linear metric shape: hx = hy = 0.1, hz linear in z, on a stretched cube.
        let mesh = kuhn_cube([0.3, 0.2, 0.5]);
        let sizes = |p: [f64; 3]| [0.1, 0.1, 0.01 + 0.4 * p[2]];
        let metric: Vec<Sym3> =
            mesh.points.iter().map(|&p| Sym3::diagonal(sizes(p).map(|h| 1.0 / (h * h)))).collect();
        // The twin, written from the definitions alone: lengths at the ends, their
        // log-mean; the mean metric of a corner set of diagonal metrics is diagonal with
        // the geometric means of the entries.
        let length = |a: [f64; 3], b: [f64; 3]| {
            let l = |p: [f64; 3]| {
                let h = sizes(p);
                ((0..3).map(|k| ((b[k] - a[k]) / h[k]).powi(2)).sum::<f64>()).sqrt()
            };
            let (la, lb) = (l(a), l(b));
            if (la - lb).abs() < 1e-14 * la {
                la
            } else {
                (la - lb) / (la / lb).ln()
            }
        };
        let mut lengths = Vec::new();
        let mut edges = std::collections::BTreeSet::new();
        let mut qualities = Vec::new();
        for t in mesh.blocks[0].cells() {
            let x: Vec<[f64; 3]> = t.iter().map(|&v| mesh.points[v as usize]).collect();
            for i in 0..4 {
                for j in i + 1..4 {
                    let (a, b) = (t[i].min(t[j]), t[i].max(t[j]));
                    if edges.insert((a, b)) {
                        lengths.push(length(mesh.points[a as usize], mesh.points[b as usize]));
                    }
                }
            }
            let d: Vec<f64> = (0..3)
                .map(|k| (x.iter().map(|&p| (sizes(p)[k]).powi(-2).ln()).sum::<f64>() / 4.0).exp())
                .collect();
            let e = |i: usize, j: usize| {
                (0..3).map(|k| d[k] * (x[j][k] - x[i][k]).powi(2)).sum::<f64>()
            };
            let l2: f64 = e(0, 1) + e(0, 2) + e(0, 3) + e(1, 2) + e(1, 3) + e(2, 3);
            let [a, b, c] = [1, 2, 3].map(|i| [0, 1, 2].map(|k| x[i][k] - x[0][k]));
            let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
            let v = det.abs() / 6.0 * (d[0] * d[1] * d[2]).sqrt();
            qualities.push(det.signum() * 36.0 / 3f64.cbrt() * v.powf(2.0 / 3.0) / l2);
        }
        let u = Ugawg::of_mesh_3d(&mesh, &metric).unwrap();
        assert_eq!((u.edges, u.cells), (lengths.len(), 6));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
        let (lo, hi) =
            lengths.iter().fold((f64::INFINITY, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
        assert!(close(u.edge_length_range[0], lo) && close(u.edge_length_range[1], hi), "{u:?}");
        let mean = lengths.iter().sum::<f64>() / lengths.len() as f64;
        assert!(close(u.mean_edge_length, mean), "{u:?} {mean}");
        let geo = (lengths.iter().map(|l| l.ln()).sum::<f64>() / lengths.len() as f64).exp();
        assert!(close(u.geometric_mean_edge_length, geo), "{u:?} {geo}");
        let ok = lengths.iter().filter(|&&l| (0.5f64.sqrt()..=2f64.sqrt()).contains(&l)).count();
        assert_eq!(u.conforming_share, ok as f64 / lengths.len() as f64);
        let qmin = qualities.iter().copied().fold(f64::INFINITY, f64::min);
        let qmean = qualities.iter().sum::<f64>() / 6.0;
        assert!(close(u.min_quality, qmin) && close(u.mean_quality, qmean), "{u:?} {qualities:?}");
        // Kuhn's tetrahedra alternate in orientation: three are inverted as listed.
        assert!(qualities.iter().all(|&q| q.abs() > 0.0 && q.abs() < 1.0));
        assert_eq!(u.non_positive, qualities.iter().filter(|&&q| q < 0.0).count());
        assert_eq!(u.non_positive, 3);
    }

    #[test]
    fn a_surface_in_space_is_measured_on_its_triangles() {
        // An equilateral triangle of side 0.1 in the tilted plane x = z, isotropic 0.1.
        let r = 0.5f64.sqrt();
        let p =
            [[0.0, 0.0, 0.0], [0.1 * r, 0.0, 0.1 * r], [0.05 * r, 0.1 * 0.75f64.sqrt(), 0.05 * r]];
        let mut mesh = TaggedMesh::new();
        mesh.points = p.to_vec();
        mesh.block_mut(CellKind::Triangle).push(&[0, 1, 2], 1, 1);
        let m = Sym3::diagonal([100.0; 3]);
        let u = Ugawg::of_mesh_3d(&mesh, &[m; 3]).unwrap();
        assert_eq!((u.cell, u.edges), ("triangle", 3));
        assert!((u.min_quality - 1.0).abs() < 1e-12 && (u.mean_edge_length - 1.0).abs() < 1e-12);
    }

    #[test]
    fn in_two_dimensions_the_ugawg_lengths_are_the_conformity_lengths() {
        let mut mesh = TaggedMesh::new();
        mesh.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        mesh.block_mut(CellKind::Triangle).push(&[0, 1, 2], 1, 1);
        mesh.block_mut(CellKind::Triangle).push(&[1, 3, 2], 1, 1);
        mesh.block_mut(CellKind::Quad).push(&[0, 1, 3, 2], 1, 1);
        let metric: Vec<Sym2> =
            mesh.points.iter().map(|p| Sym2::new(1.0 + 3.0 * p[0], 0.2, 2.0)).collect();
        let u = Ugawg::of_mesh_2d(&mesh, &metric).unwrap();
        let mut tris = mesh.clone();
        tris.blocks.retain(|b| b.kind == CellKind::Triangle);
        let c = Conformity::of_mesh(&tris, &metric).unwrap();
        assert_eq!((u.edges, u.cells, u.left_out), (c.edges, 2, 1));
        assert_eq!(u.edge_length_range, c.edge_length_range);
        assert_eq!(u.conforming_share, c.conforming_share);
        assert!((u.mean_quality - c.mean_quality).abs() < 1e-15);
    }

    #[test]
    fn metric_field_errors_name_the_vertex() {
        use smartmesh_formats::{CellKind, DataArray};
        let mut mesh = TaggedMesh::new();
        mesh.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [5.0, 5.0, 0.0]];
        mesh.block_mut(CellKind::Triangle).push(&[0, 1, 2], 1, 1);
        let good = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        let mut v: Vec<f64> = good.repeat(4);
        v[9 + 4] = -1.0; // vertex 1 not SPD
        mesh.point_data.insert("metric".into(), DataArray::new(9, v.clone()));
        let e = metric_field(&mesh, "metric").unwrap_err();
        assert!(matches!(e, MetricFieldError::NotSpd { vertex: 1, .. }), "{e}");
        // An unused vertex (3) may carry anything.
        v[9 + 4] = 1.0;
        v[27] = f64::NAN;
        mesh.point_data.insert("metric".into(), DataArray::new(9, v));
        let f = metric_field(&mesh, "metric").unwrap();
        assert_eq!(f[3], Sym2::IDENTITY);
        assert!(matches!(metric_field(&mesh, "nope"), Err(MetricFieldError::Missing { .. })));
    }
}
