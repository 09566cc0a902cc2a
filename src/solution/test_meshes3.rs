//! Tetrahedral meshes for the tests of this module: grids of boxes split into the six
//! Freudenthal–Kuhn tetrahedra around each box's diagonal, regular, jittered (every
//! vertex moved by a seeded random offset, boundary vertices within their faces) or
//! moved by a smooth map; all deterministic, every tetrahedron positive.

use super::recovery3::Point3;

/// Points and tetrahedra.
pub(crate) struct Mesh3 {
    pub points: Vec<Point3>,
    pub tets: Vec<[u32; 4]>,
}

impl Mesh3 {
    /// Whether each vertex lies on a boundary face (a face of one tetrahedron).
    pub(crate) fn boundary(&self) -> Vec<bool> {
        let mut faces: Vec<[u32; 3]> = Vec::with_capacity(4 * self.tets.len());
        for t in &self.tets {
            for skip in 0..4 {
                let mut f = [0u32; 3];
                let mut k = 0;
                for (i, &v) in t.iter().enumerate() {
                    if i != skip {
                        f[k] = v;
                        k += 1;
                    }
                }
                f.sort_unstable();
                faces.push(f);
            }
        }
        faces.sort_unstable();
        let mut on = vec![false; self.points.len()];
        let mut i = 0;
        while i < faces.len() {
            let mut j = i;
            while j < faces.len() && faces[j] == faces[i] {
                j += 1;
            }
            if j - i == 1 {
                faces[i].iter().for_each(|&v| on[v as usize] = true);
            }
            i = j;
        }
        on
    }

    /// Six times the signed volume of tetrahedron `t`.
    pub(crate) fn volume6(&self, t: [u32; 4]) -> f64 {
        let [a, b, c, d] = t.map(|v| self.points[v as usize]);
        let e = |p: Point3| [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
        let (u, v, w) = (e(b), e(c), e(d));
        u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
            + u[2] * (v[0] * w[1] - v[1] * w[0])
    }
}

/// An `n[0]` × `n[1]` × `n[2]` grid of boxes of sides `step` from `origin`, each split
/// into the six tetrahedra around its diagonal from the lower corner, all positive;
/// vertex (i, j, k) is `(k (n1 + 1) + j) (n0 + 1) + i`.
pub(crate) fn kuhn(n: [usize; 3], origin: Point3, step: Point3) -> Mesh3 {
    let [nx, ny, nz] = n;
    let id = |i: usize, j: usize, k: usize| ((k * (ny + 1) + j) * (nx + 1) + i) as u32;
    let mut points = Vec::new();
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let c = [i, j, k];
                points.push(std::array::from_fn(|a| origin[a] + c[a] as f64 * step[a]));
            }
        }
    }
    let mut m = Mesh3 { points, tets: Vec::new() };
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let c = |b: usize| id(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2));
                for path in [[1, 3], [1, 5], [2, 3], [2, 6], [4, 5], [4, 6]] {
                    let mut t = [c(0), c(path[0]), c(path[1]), c(7)];
                    if m.volume6(t) < 0.0 {
                        t.swap(2, 3);
                    }
                    m.tets.push(t);
                }
            }
        }
    }
    m
}

/// A seeded generator of uniform numbers in [0, 1).
pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    move || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// [`kuhn`] with every vertex moved by up to `jitter` steps along each axis (seeded by
/// `seed`), a boundary vertex only along its faces; panics if a tetrahedron turned.
pub(crate) fn jittered(
    n: [usize; 3],
    origin: Point3,
    step: Point3,
    jitter: f64,
    seed: u64,
) -> Mesh3 {
    let mut m = kuhn(n, origin, step);
    let mut next = uniform(seed);
    for (v, p) in m.points.iter_mut().enumerate() {
        let (i, rest) = (v % (n[0] + 1), v / (n[0] + 1));
        let c = [i, rest % (n[1] + 1), rest / (n[1] + 1)];
        for a in 0..3 {
            let d = jitter * step[a] * (2.0 * next() - 1.0);
            if c[a] != 0 && c[a] != n[a] {
                p[a] += d;
            }
        }
    }
    for &t in &m.tets {
        assert!(m.volume6(t) > 0.0, "jitter {jitter} turned a tetrahedron");
    }
    m
}

/// [`kuhn`] of the unit cube (`n` a side) moved by a smooth map that fixes its
/// boundary: irregular patches that become point-symmetric as the mesh is refined.
pub(crate) fn mapped(n: usize) -> Mesh3 {
    let h = 1.0 / n as f64;
    let mut m = kuhn([n; 3], [0.0; 3], [h; 3]);
    let pi = std::f64::consts::PI;
    for p in &mut m.points {
        let [x, y, z] = *p;
        let bump = (pi * x).sin() * (pi * y).sin() * (pi * z).sin();
        *p = [x + 0.1 * bump * (2.0 * y).cos(), y + 0.08 * bump, z - 0.06 * bump * (x + 0.5)];
    }
    for &t in &m.tets {
        assert!(m.volume6(t) > 0.0, "the map turned a tetrahedron");
    }
    m
}
