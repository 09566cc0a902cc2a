//! Meshes for the tests of this module: structured grids, jittered or mapped, and
//! Delaunay triangulations of scattered points (spade), all deterministic.

use crate::geometry::Point2;
use crate::metric::{log_euclidean, log_spd, SizeTensor, Sym2};
use spade::Triangulation;

/// Points and triangles.
pub(crate) struct Mesh {
    pub points: Vec<Point2>,
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Whether each vertex lies on a boundary edge (an edge of one triangle).
    pub(crate) fn boundary(&self) -> Vec<bool> {
        let mut edges: Vec<[u32; 2]> = self
            .triangles
            .iter()
            .flat_map(|t| (0..3).map(move |i| [t[i].min(t[(i + 1) % 3]), t[i].max(t[(i + 1) % 3])]))
            .collect();
        edges.sort_unstable();
        let mut on = vec![false; self.points.len()];
        let mut i = 0;
        while i < edges.len() {
            let mut j = i;
            while j < edges.len() && edges[j] == edges[i] {
                j += 1;
            }
            if j - i == 1 {
                on[edges[i][0] as usize] = true;
                on[edges[i][1] as usize] = true;
            }
            i = j;
        }
        on
    }
}

/// An `nx` × `ny` grid of rectangles of sides `step` from `origin`, each split along the
/// same diagonal; vertex (i, j) is `j (nx + 1) + i`.
pub(crate) fn grid(nx: usize, ny: usize, origin: Point2, step: [f64; 2]) -> Mesh {
    let mut points = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            points.push([origin[0] + i as f64 * step[0], origin[1] + j as f64 * step[1]]);
        }
    }
    let mut triangles = Vec::new();
    let w = (nx + 1) as u32;
    for j in 0..ny as u32 {
        for i in 0..nx as u32 {
            let v = j * w + i;
            triangles.push([v, v + 1, v + w + 1]);
            triangles.push([v, v + w + 1, v + w]);
        }
    }
    Mesh { points, triangles }
}

/// [`grid`] with every vertex moved by up to `jitter` steps along each axis (seeded by
/// `seed`), a boundary vertex only along its side; panics if a triangle turned.
pub(crate) fn jittered_grid(
    n: [usize; 2],
    origin: Point2,
    step: [f64; 2],
    jitter: f64,
    seed: u64,
) -> Mesh {
    let mut m = grid(n[0], n[1], origin, step);
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for (v, p) in m.points.iter_mut().enumerate() {
        let c = [v % (n[0] + 1), v / (n[0] + 1)];
        for a in 0..2 {
            let d = jitter * step[a] * (2.0 * next() - 1.0);
            if c[a] != 0 && c[a] != n[a] {
                p[a] += d;
            }
        }
    }
    for t in &m.triangles {
        let [a, b, c] = t.map(|v| m.points[v as usize]);
        let area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        assert!(area2 > 0.0, "jitter {jitter} turned a triangle");
    }
    m
}

/// The Delaunay triangulation of about `n` points in the square of side `size` at
/// `origin`: its boundary sampled at the mean spacing, the inside by a seeded generator
/// (`seed`), kept a third of the spacing apart from each other and the boundary.
pub(crate) fn scattered(n: usize, seed: u64, origin: Point2, size: f64) -> Mesh {
    let h = size / (n as f64).sqrt();
    let k = (size / h).round() as usize;
    let mut pts: Vec<Point2> = Vec::new();
    for i in 0..k {
        let t = i as f64 * size / k as f64;
        pts.push([t, 0.0]);
        pts.push([size, t]);
        pts.push([size - t, size]);
        pts.push([0.0, size - t]);
    }
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut tries = 0;
    while pts.len() < n && tries < 100 * n {
        tries += 1;
        let p = [next() * size, next() * size];
        let near_boundary = p.iter().any(|&x| x < h / 3.0 || x > size - h / 3.0);
        if near_boundary || pts.iter().any(|q| (q[0] - p[0]).hypot(q[1] - p[1]) < h / 3.0) {
            continue;
        }
        pts.push(p);
    }
    let mut t = spade::DelaunayTriangulation::<spade::Point2<f64>>::new();
    for p in &pts {
        t.insert(spade::Point2::new(p[0], p[1])).unwrap();
    }
    let points: Vec<Point2> =
        t.vertices().map(|v| [origin[0] + v.position().x, origin[1] + v.position().y]).collect();
    let triangles = t.inner_faces().map(|f| f.vertices().map(|v| v.fix().index() as u32)).collect();
    Mesh { points, triangles }
}

/// [`grid`] of the unit square (`n` × `n`) moved by a smooth map that fixes its
/// boundary: an irregular mesh whose patches become point-symmetric as it is refined
/// ("mildly structured").
pub(crate) fn mapped_grid(n: usize) -> Mesh {
    let mut m = grid(n, n, [0.0, 0.0], [1.0 / n as f64; 2]);
    for p in &mut m.points {
        let [x, y] = *p;
        let bump = (std::f64::consts::PI * x).sin() * (std::f64::consts::PI * y).sin();
        *p = [x + 0.12 * bump * (2.0 * y).cos(), y + 0.1 * bump];
    }
    m
}

/// ∫ √det M over the mesh by brute force: the Log-Euclidean interpolation of the vertex
/// metrics sampled at the centroids of the k² equal sub-triangles of each triangle (a
/// midpoint rule). The closed form's twin.
pub(crate) fn brute_force_vertices(m: &Mesh, tensors: &[SizeTensor], k: usize) -> f64 {
    let logs: Vec<Sym2> = tensors.iter().map(|t| log_spd(&t.to_metric())).collect();
    let mut c = 0.0;
    for t in &m.triangles {
        let [a, b, q] = t.map(|v| m.points[v as usize]);
        let area = 0.5 * ((b[0] - a[0]) * (q[1] - a[1]) - (b[1] - a[1]) * (q[0] - a[0])).abs();
        let l = t.map(|v| &logs[v as usize]);
        let (mut sum, mut count) = (0.0, 0);
        // Centres of the k² sub-triangles of a regular subdivision: a midpoint rule.
        for i in 0..k {
            for j in 0..k - i {
                for (di, dj) in [(1.0 / 3.0, 1.0 / 3.0), (2.0 / 3.0, 2.0 / 3.0)] {
                    if (di > 0.5) && i + j + 1 >= k {
                        continue;
                    }
                    let (x, y) = ((i as f64 + di) / k as f64, (j as f64 + dj) / k as f64);
                    let w = [1.0 - x - y, x, y];
                    sum += log_euclidean(&w, &l).det().sqrt();
                    count += 1;
                }
            }
        }
        c += area * sum / count as f64;
    }
    2.0 * c / 3f64.sqrt()
}
