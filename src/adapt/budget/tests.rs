use super::*;
use smartmesh_formats::{CellBlock, CellKind};

/// The unit square as an n×n grid of squares, each cut in two triangles.
fn grid(n: usize) -> TaggedMesh {
    let mut mesh = TaggedMesh::default();
    for j in 0..=n {
        for i in 0..=n {
            mesh.points.push([i as f64 / n as f64, j as f64 / n as f64, 0.0]);
        }
    }
    let at = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut tri = CellBlock::new(CellKind::Triangle);
    for j in 0..n {
        for i in 0..n {
            tri.push(&[at(i, j), at(i + 1, j), at(i + 1, j + 1)], 1, 1);
            tri.push(&[at(i, j), at(i + 1, j + 1), at(i, j + 1)], 1, 1);
        }
    }
    mesh.blocks.push(tri);
    mesh
}

/// A raw field from very fine and very anisotropic near x = 0 to coarse at x = 1.
fn raw_field(mesh: &TaggedMesh) -> Vec<SizeTensor> {
    mesh.points
        .iter()
        .map(|p| {
            let h1 = 1e-4 + 0.5 * p[0] * p[0];
            let h2 = 1e-2 + 0.3 * p[1];
            SizeTensor::from_angle(p[1], h1, h2).unwrap()
        })
        .collect()
}

/// The field at `scale` made by hand: sizes times scale^(-1/2), each clamped to
/// [lo, hi], the larger shrunk to the smaller times `r`.
fn by_hand(raw: &[SizeTensor], scale: f64, lo: f64, hi: f64, r: f64) -> Vec<SizeTensor> {
    raw.iter()
        .map(|t| {
            let mut h = t.sizes().map(|h| (h / scale.sqrt()).max(lo).min(hi));
            let (big, small) = if h[0] >= h[1] { (0, 1) } else { (1, 0) };
            h[big] = h[big].min(h[small] * r);
            SizeTensor::from_parts(t.axis(), h)
        })
        .collect()
}

/// ∫ √det M by the midpoint rule on each triangle cut k² times, M interpolated
/// Log-Euclidean (√det is the exponential of the interpolated half log det): the
/// complexity without the closed form.
fn quadrature(mesh: &TaggedMesh, tensors: &[SizeTensor], k: usize) -> f64 {
    let f: Vec<f64> = tensors.iter().map(|t| -(t.h1() * t.h2()).ln()).collect();
    let (points, tris) = planar_triangles(mesh);
    let mut sum = 0.0;
    for t in &tris {
        let [a, b, c] = t.map(|v| points[v]);
        let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])).abs();
        let small = area / (k * k) as f64;
        // Barycentric centroids of the k² sub-triangles (upward and downward ones).
        for i in 0..k {
            for j in 0..k - i {
                let mut add = |l: [f64; 3]| {
                    let g = l[0] * f[t[0]] + l[1] * f[t[1]] + l[2] * f[t[2]];
                    sum += small * g.exp();
                };
                let (i, j) = (i as f64, j as f64);
                let kk = k as f64;
                add([(i + 1.0 / 3.0) / kk, (j + 1.0 / 3.0) / kk, 1.0 - (i + j + 2.0 / 3.0) / kk]);
                if (i + j + 2.0) as usize <= k {
                    add([
                        (i + 2.0 / 3.0) / kk,
                        (j + 2.0 / 3.0) / kk,
                        1.0 - (i + j + 4.0 / 3.0) / kk,
                    ]);
                }
            }
        }
    }
    vertices_of_complexity(sum)
}

#[test]
fn the_normalised_field_asks_for_the_target_with_every_bound_acting() {
    let mesh = grid(12);
    let raw = raw_field(&mesh);
    let (lo, hi, r) = (0.004, 0.12, 8.0);
    let limits = Limits { bounds: SizeBounds::try_new(lo, hi, r).unwrap(), gradation: None };
    for target in [150.0, 900.0, 4000.0, 20_000.0] {
        let b = normalise(&mesh, &raw, &limits, target);
        assert!(b.reached, "{target}");
        let (points, tris) = planar_triangles(&mesh);
        let hand = by_hand(&raw, b.scale, lo, hi, r);
        let v = vertices_of(&points, &tris, &hand);
        assert!((v / target - 1.0).abs() < 1e-9, "{target}: {v}");
        assert!((b.vertices / target - 1.0).abs() < 1e-9, "{target}: {}", b.vertices);
        for (x, y) in b.tensors.iter().zip(&hand) {
            for (p, q) in x.sizes().iter().zip(y.sizes()) {
                assert!((p / q - 1.0).abs() < 1e-12);
            }
        }
        // Every bound acts: some sizes at h_min, some at h_max, some shrunk by the ratio.
        let at =
            |h: f64| hand.iter().any(|t| t.sizes().iter().any(|&s| (s / h - 1.0).abs() < 1e-12));
        if target < 20_000.0 {
            assert!(at(hi), "{target}: no size at hmax");
        }
        if target > 150.0 {
            assert!(at(lo), "{target}: no size at hmin");
        }
        assert!(hand.iter().any(|t| (t.aspect_ratio() / r - 1.0).abs() < 1e-9), "{target}");
        // The closed form against a quadrature of the same interpolated field.
        let q = quadrature(&mesh, &hand, 24);
        assert!((q / v - 1.0).abs() < 2e-3, "{target}: quadrature {q} vs {v}");
        // The root is where it is: a scan of scales on both sides brackets it.
        for k in 1..=6 {
            let d = 10f64.powi(-k);
            let below = vertices_of(&points, &tris, &by_hand(&raw, b.scale * (1.0 - d), lo, hi, r));
            let above = vertices_of(&points, &tris, &by_hand(&raw, b.scale * (1.0 + d), lo, hi, r));
            assert!(below <= target && above >= target, "{target} {d}: {below} {above}");
        }
    }
}

#[test]
fn a_target_out_of_the_bounds_reach_gives_the_nearest_end() {
    let mesh = grid(6);
    let raw = raw_field(&mesh);
    let limits = Limits { bounds: SizeBounds::try_new(0.05, 0.2, 10.0).unwrap(), gradation: None };
    let (points, tris) = planar_triangles(&mesh);
    let uniform = |h: f64| vertices_of(&points, &tris, &vec![SizeTensor::isotropic(h); raw.len()]);
    let most = normalise(&mesh, &raw, &limits, 1e9);
    assert!(!most.reached);
    assert!((most.vertices / uniform(0.05) - 1.0).abs() < 1e-12, "{}", most.vertices);
    let least = normalise(&mesh, &raw, &limits, 1.0);
    assert!(!least.reached);
    assert!((least.vertices / uniform(0.2) - 1.0).abs() < 1e-12, "{}", least.vertices);
}

#[test]
fn the_gradation_acts_inside_the_normalisation() {
    let mesh = grid(16);
    let raw = raw_field(&mesh);
    let topology = crate::topology::Topology::from_mesh(&mesh);
    let graph = MeshGraph::from_topology(&topology, &mesh).unwrap();
    let bounds = SizeBounds::try_new(1e-3, 0.3, 50.0).unwrap();
    let target = 2500.0;
    let graded = normalise(&mesh, &raw, &Limits { bounds, gradation: Some((1.3, &graph)) }, target);
    assert!(graded.reached);
    assert!((graded.vertices / target - 1.0).abs() < 1e-9, "{}", graded.vertices);
    let plain = normalise(&mesh, &raw, &Limits { bounds, gradation: None }, target);
    // The gradation only shrinks, so the graded field is coarsened more to meet the count.
    assert!(graded.scale < plain.scale, "{} {}", graded.scale, plain.scale);
    // And it is graded: the field at that scale, graded by hand, is the result.
    let (points, tris) = planar_triangles(&mesh);
    let mut again = by_hand(&raw, graded.scale, 1e-3, 0.3, 50.0);
    apply_gradation(&graph, &mut again, 1.3);
    let v = vertices_of(&points, &tris, &again);
    assert!((v / target - 1.0).abs() < 1e-9, "{v}");
}
