//! How well a mesh conforms to a metric field: the figures the remesher, the adaptation
//! loop, `info` and `report` share, each edge and triangle measured by the kernels of
//! [`crate::metric::length`] (metric edge length, metric triangle quality); a mesh
//! conforms when its edges have metric lengths in [`CONFORMING`], [1/√2, √2].

use rayon::prelude::*;
use serde::Serialize;

use crate::metric::length::{metric_edge_length, metric_triangle_quality, CONFORMING};
use crate::metric::Sym2;
use crate::metric_field::MetricField;
use smartmesh_formats::TaggedMesh;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metric::length::metric_triangle_quality;
    use crate::metric::SizeTensor;

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
