//! How well a mesh conforms to a metric field: metric edge lengths, metric triangle
//! quality, and the figures the remesher, the adaptation loop, `info` and `report` share.
//!
//! - The metric length of an edge ab, with metrics Ma and Mb at its ends, is the length of
//!   the segment in the metric interpolated along it. With la = √(abᵀ Ma ab) and
//!   lb = √(abᵀ Mb ab) and the size varying geometrically along the edge (the
//!   Log-Euclidean interpolation of [`crate::metric`]), the integral is
//!   (la − lb) / ln(la / lb), la when they are equal: the formula MMG and BAMG use.
//! - The metric quality of a triangle is the shape quality q = 4√3·A / Σ l² measured in
//!   the metric at its centroid (the Log-Euclidean mean of its corners' metrics): 1 for a
//!   triangle that is equilateral in the metric, 0 for a flat one, negative for an
//!   inverted one.
//! - A mesh conforms when its edges have metric lengths in [1/√2, √2].

use rayon::prelude::*;
use serde::Serialize;

use crate::formats::TaggedMesh;
use crate::metric::{SizeTensor, Sym2};
use crate::metric_field::MetricField;

/// The band of metric edge lengths that counts as conforming: [1/√2, √2].
pub const CONFORMING: [f64; 2] = [std::f64::consts::FRAC_1_SQRT_2, std::f64::consts::SQRT_2];

/// Metric length of the edge from `a` to `b` whose ends carry metrics `ma` and `mb`.
#[inline]
pub fn metric_edge_length(a: [f64; 2], b: [f64; 2], ma: &Sym2, mb: &Sym2) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1]];
    let la = ma.quadratic_form(e).max(0.0).sqrt();
    let lb = mb.quadratic_form(e).max(0.0).sqrt();
    geometric_mean_length(la, lb)
}

/// The integral of a length that varies geometrically from `la` to `lb`:
/// (la − lb)/ln(la/lb), with a series where they are close (no cancellation).
#[inline]
pub fn geometric_mean_length(la: f64, lb: f64) -> f64 {
    if la <= 0.0 || lb <= 0.0 {
        return 0.5 * (la + lb);
    }
    let r = lb / la;
    let d = r - 1.0;
    if d.abs() < 1e-4 {
        // (r − 1)/ln r = 1 + d/2 − d²/12 + O(d³).
        la * (1.0 + d * (0.5 - d / 12.0))
    } else {
        (la - lb) / (la / lb).ln()
    }
}

/// The metric at a triangle's centroid: the Log-Euclidean mean of its corners' metrics
/// (falls back to the arithmetic mean when a corner is not SPD).
pub fn centroid_metric(m: [&Sym2; 3]) -> Sym2 {
    let sizes: Option<Vec<SizeTensor>> =
        m.iter().map(|x| SizeTensor::try_from_metric(x).ok()).collect();
    match sizes.and_then(|s| SizeTensor::log_euclidean_mean(s.iter().map(|t| (1.0 / 3.0, t)))) {
        Some(t) => t.to_metric(),
        None => (1.0 / 3.0) * (*m[0] + *m[1] + *m[2]),
    }
}

/// Shape quality of triangle `(a, b, c)` measured in the constant metric `m`:
/// 4√3·A_M / (l₁² + l₂² + l₃²) with every length and the area taken in `m`.
#[inline]
pub fn quality_in_metric(a: [f64; 2], b: [f64; 2], c: [f64; 2], m: &Sym2) -> f64 {
    let e = |p: [f64; 2], q: [f64; 2]| m.quadratic_form([q[0] - p[0], q[1] - p[1]]);
    let s = e(a, b) + e(b, c) + e(c, a);
    if s <= 0.0 {
        return 0.0;
    }
    let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    4.0 * 3f64.sqrt() * area * m.det().max(0.0).sqrt() / s
}

/// Metric quality of a triangle whose corners carry metrics `m`.
pub fn metric_triangle_quality(p: [[f64; 2]; 3], m: [&Sym2; 3]) -> f64 {
    quality_in_metric(p[0], p[1], p[2], &centroid_metric(m))
}

pub use crate::metric_field::MetricFieldError;

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
pub const LENGTH_BINS: usize = 30;

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
        let qualities: Vec<f64> = tris
            .par_iter()
            .map(|t| {
                let p = [points[t[0]], points[t[1]], points[t[2]]];
                let q = metric_triangle_quality(p, [&metric[t[0]], &metric[t[1]], &metric[t[2]]]);
                // Orientation is the file's business; quality measures shape.
                if crate::quality::signed_area(p[0], p[1], p[2]) < 0.0 {
                    -q
                } else {
                    q
                }
            })
            .collect();
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
                crate::formats::CellKind::Triangle => {
                    tris.push([n[0] as usize, n[1] as usize, n[2] as usize])
                }
                crate::formats::CellKind::Quad => {
                    tris.push([n[0] as usize, n[1] as usize, n[2] as usize]);
                    tris.push([n[0] as usize, n[2] as usize, n[3] as usize]);
                }
                _ => {}
            }
        }
        Conformity::of(&points, &tris, metric)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute-force twin: the metric length as a Simpson integral of √(eᵀ M(t) e) along the
    /// edge, with M(t) the Log-Euclidean interpolation of the end metrics.
    fn length_by_quadrature(a: [f64; 2], b: [f64; 2], ma: &Sym2, mb: &Sym2) -> f64 {
        let (sa, sb) =
            (SizeTensor::try_from_metric(ma).unwrap(), SizeTensor::try_from_metric(mb).unwrap());
        let e = [b[0] - a[0], b[1] - a[1]];
        let n = 2000;
        let f = |t: f64| {
            SizeTensor::log_euclidean_mean([(1.0 - t, &sa), (t, &sb)])
                .unwrap()
                .to_metric()
                .quadratic_form(e)
                .sqrt()
        };
        let h = 1.0 / n as f64;
        let mut s = f(0.0) + f(1.0);
        for i in 1..n {
            s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i as f64 * h);
        }
        s * h / 3.0
    }

    #[test]
    fn edge_length_matches_quadrature_for_isotropic_and_aligned_metrics() {
        // For metrics sharing their axes, the Log-Euclidean interpolation scales each
        // direction geometrically, so the closed form is exact along an axis.
        let a = [0.0, 0.0];
        let b = [1.0, 0.0];
        for (h0, h1) in [(1.0, 1.0), (0.1, 1.0), (1.0, 1e-3), (0.5, 0.50001)] {
            let ma = SizeTensor::isotropic(h0).to_metric();
            let mb = SizeTensor::isotropic(h1).to_metric();
            let exact = length_by_quadrature(a, b, &ma, &mb);
            let got = metric_edge_length(a, b, &ma, &mb);
            assert!((got - exact).abs() <= 1e-6 * exact, "{h0} {h1}: {got} vs {exact}");
        }
    }

    #[test]
    fn unit_equilateral_has_quality_one_and_length_one() {
        let m = Sym2::IDENTITY;
        let p = [[0.0, 0.0], [1.0, 0.0], [0.5, 3f64.sqrt() / 2.0]];
        assert!((metric_triangle_quality(p, [&m, &m, &m]) - 1.0).abs() < 1e-12);
        assert!((metric_edge_length(p[0], p[1], &m, &m) - 1.0).abs() < 1e-15);
    }

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

    #[test]
    fn metric_field_errors_name_the_vertex() {
        use crate::formats::{CellKind, DataArray};
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
