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

/// A solution's metric: a stretched front along the circle r = 0.6, coarse elsewhere.
fn front_field(mesh: &TaggedMesh) -> Vec<SizeTensor> {
    mesh.points
        .iter()
        .map(|p| {
            let (x, y) = (p[0] + 0.05, p[1] + 0.05);
            let r = x.hypot(y);
            let across = 2e-3 + 0.4 * (r - 0.6).abs();
            SizeTensor::from_angle(y.atan2(x), across, (6.0 * across).min(0.3)).unwrap()
        })
        .collect()
}

/// The intersection of the recipe's part and the scaled solution, made by hand: the
/// recipe scaled to `cap` vertices when it asks for more, the solution's sizes times
/// `scale`^(-1/2), intersected and clamped to [lo, hi].
fn share_by_hand(
    points: &[[f64; 2]],
    tris: &[[usize; 3]],
    recipe: &[SizeTensor],
    solution: &[SizeTensor],
    cap: f64,
    scale: f64,
    (lo, hi): (f64, f64),
) -> (Vec<SizeTensor>, f64) {
    let own = vertices_of(points, tris, recipe);
    let f = if own > cap { (own / cap).sqrt() } else { 1.0 };
    let part: Vec<SizeTensor> =
        recipe.iter().map(|t| SizeTensor::from_parts(t.axis(), t.sizes().map(|h| h * f))).collect();
    let part_vertices = vertices_of(points, tris, &part);
    let bounds = SizeBounds::try_new(lo, hi, f64::INFINITY).unwrap();
    let field = part
        .iter()
        .zip(solution)
        .map(|(r, s)| {
            let s = SizeTensor::from_parts(s.axis(), s.sizes().map(|h| h / scale.sqrt()));
            r.intersection(&s).clamp(&bounds)
        })
        .collect();
    (field, part_vertices)
}

#[test]
fn the_recipe_takes_its_share_and_the_solution_the_rest() {
    let mesh = grid(16);
    let (points, tris) = planar_triangles(&mesh);
    let recipe = raw_field(&mesh);
    let solution = front_field(&mesh);
    let (lo, hi) = (1e-5, 0.5);
    let limits =
        Limits { bounds: SizeBounds::try_new(lo, hi, f64::INFINITY).unwrap(), gradation: None };
    let own = vertices_of(&points, &tris, &recipe);
    // The recipe asks for more than its share (it is coarsened to it), then for less
    // (it is kept as it is: a floor).
    for (target, f) in [(1.2 * own, 0.25), (0.8 * own, 0.4), (8.0 * own, 0.25)] {
        let b = share(&mesh, &recipe, &solution, &limits, target, f);
        assert!(b.reached, "{target} {f}");
        assert!((b.vertices / target - 1.0).abs() < 1e-9, "{target}: {}", b.vertices);
        let cap = f * target;
        let (hand, part) =
            share_by_hand(&points, &tris, &recipe, &solution, cap, b.scale, (lo, hi));
        assert!((part / own.min(cap) - 1.0).abs() < 1e-9, "{target}: recipe's part {part}");
        let v = vertices_of(&points, &tris, &hand);
        assert!((v / target - 1.0).abs() < 1e-9, "{target}: {v}");
        for (x, y) in b.tensors.iter().zip(&hand) {
            let (m, n) = (x.to_metric(), y.to_metric());
            let scale = n.a.abs().max(n.c.abs());
            for (p, q) in [(m.a, n.a), (m.b, n.b), (m.c, n.c)] {
                assert!((p - q).abs() <= 1e-9 * scale, "{target}: {m:?} {n:?}");
            }
        }
        // The solution's scale is the root: a scan on both sides brackets it.
        for k in 1..=6 {
            let d = 10f64.powi(-k);
            let at = |s: f64| {
                vertices_of(
                    &points,
                    &tris,
                    &share_by_hand(&points, &tris, &recipe, &solution, cap, s, (lo, hi)).0,
                )
            };
            let (below, above) = (at(b.scale * (1.0 - d)), at(b.scale * (1.0 + d)));
            assert!(below <= target && above >= target, "{target} {d}: {below} {above}");
        }
        // The recipe's part holds: the result is nowhere coarser than it.
        let f = if own > cap { (own / cap).sqrt() } else { 1.0 };
        let quad = |m: crate::metric::Sym2, d: [f64; 2]| {
            m.a * d[0] * d[0] + 2.0 * m.b * d[0] * d[1] + m.c * d[1] * d[1]
        };
        for (x, r) in b.tensors.iter().zip(&recipe) {
            for d in [[1.0, 0.0], [0.0, 1.0], [0.6, 0.8], [-0.8, 0.6]] {
                let (mx, mr) = (quad(x.to_metric(), d), quad(r.to_metric(), d) / (f * f));
                assert!(mx >= mr * (1.0 - 1e-9), "{target}: {mx} < {mr}");
            }
        }
    }
}

#[test]
fn a_recipe_that_leaves_no_room_shares_in_the_raw_proportions() {
    let mesh = grid(12);
    let recipe = raw_field(&mesh);
    let solution = front_field(&mesh);
    let limits = Limits { bounds: SizeBounds::try_new(1e-5, 0.5, 1e3).unwrap(), gradation: None };
    let (points, tris) = planar_triangles(&mesh);
    let target = 0.5 * vertices_of(&points, &tris, &recipe);
    // With the whole budget for the recipe, the solution has no room: the intersection
    // is scaled as a whole, as `normalise` does it.
    let b = share(&mesh, &recipe, &solution, &limits, target, 1.0);
    let whole: Vec<SizeTensor> =
        recipe.iter().zip(&solution).map(|(r, s)| r.intersection(s)).collect();
    let n = normalise(&mesh, &whole, &limits, target);
    assert!(b.reached && n.reached);
    assert_eq!(b, n);
}

#[test]
fn the_recipes_own_bounds_scale_and_the_command_lines_are_hard() {
    let mut recipe = Recipe::default();
    recipe.global.h_min = Some(0.01);
    recipe.global.h_max = Some(0.2);
    recipe.global.max_aspect_ratio = Some(30.0);
    recipe.global.gradation = Some(1.3);
    let raw = RawRecipe::of(&recipe, (None, Some(0.5))).unwrap();
    // The recipe keeps its sizes' bounds (its shape); the gradation goes in the limits.
    assert_eq!(raw.recipe.global.h_min, Some(0.01));
    assert_eq!(raw.recipe.global.h_max, Some(0.2));
    assert_eq!(raw.recipe.global.gradation, None);
    assert_eq!(raw.gradation, Some(1.3));
    assert_eq!(raw.bounds.h_min(), SizeTensor::MIN_SIZE);
    assert_eq!(raw.bounds.h_max(), 0.5);
    assert_eq!(raw.bounds.max_aspect_ratio(), 30.0);
    assert!(raw.empty.algorithms.is_empty() && raw.empty.global.h_min.is_none());
    assert!(!raw.has_steps());
}

#[test]
fn the_target_is_corrected_by_the_ratio_then_by_the_secant() {
    assert_eq!(corrected_target(1000.0, &[]), 1000.0);
    // One remeshing: the ratio, kept in [1/2, 2].
    assert_eq!(corrected_target(1000.0, &[(1000.0, 1250)]), 800.0);
    assert_eq!(corrected_target(1000.0, &[(1000.0, 5000)]), 500.0);
    // A remesher that makes 1.5 · asked^0.9: the secant through two of its points finds
    // the count that makes 1000 (up to the rounding of the counts made).
    let made = |a: f64| 1.5 * a.powf(0.9);
    let pairs = [(800.0, made(800.0).round() as usize), (1100.0, made(1100.0).round() as usize)];
    let t = corrected_target(1000.0, &pairs);
    let want = (1000.0f64 / 1.5).powf(1.0 / 0.9);
    assert!((t / want - 1.0).abs() < 2e-3, "{t} vs {want}");
    // Two counts too close for a slope: the ratio of the last.
    let t = corrected_target(1000.0, &[(900.0, 1000), (901.0, 1200)]);
    assert!((t - 1000.0 / (1200.0 / 901.0)).abs() < 1e-9, "{t}");
    // A slope past 2 is kept at 2, the result within [n/2, 2n].
    let t = corrected_target(1000.0, &[(500.0, 100), (1000.0, 1000)]);
    assert_eq!(t, 1000.0);
    let t = corrected_target(1000.0, &[(500.0, 2000), (1000.0, 8000)]);
    assert_eq!(t, 500.0);
}

/// A raw field in space on `mesh`: fine and stretched near x = 0, coarse at x = 1, its
/// frame turning with y.
fn raw_field3(mesh: &TaggedMesh) -> Vec<SizeTensor3> {
    mesh.points
        .iter()
        .map(|p| {
            let (s, c) = p[1].sin_cos();
            let h = [1e-3 + 0.4 * p[0] * p[0], 2e-2 + 0.2 * p[1], 5e-2 + 0.1 * p[2]];
            SizeTensor3::new([c, s, 0.0], [-s, c, 0.0], h)
        })
        .collect()
}

/// The field in space at `scale` made by hand: sizes times scale^(-1/2), each clamped to
/// [lo, hi], those above the smallest times `r` shrunk to it.
fn by_hand3(raw: &[SizeTensor3], scale: f64, lo: f64, hi: f64, r: f64) -> Vec<SizeTensor3> {
    raw.iter()
        .map(|t| {
            let h = t.sizes().map(|h| (h / scale.sqrt()).max(lo).min(hi));
            let small = h[0].min(h[1]).min(h[2]);
            SizeTensor3::new(t.frame()[0], t.frame()[1], h.map(|x| x.min(small * r)))
        })
        .collect()
}

#[test]
fn the_normalised_field_in_space_asks_for_the_target_with_every_bound_acting() {
    let mesh = smartmesh_test_support::grid::kuhn_box(6, [1.0; 3]);
    let raw = raw_field3(&mesh);
    // Every size at h_max asks for 6√2/5.6/0.2³ ≈ 189 vertices, at h_min 10⁸.
    let (lo, hi, r) = (0.004, 0.2, 8.0);
    let limits = Limits3 { bounds: SizeBounds::try_new(lo, hi, r).unwrap(), gradation: None };
    for target in [300.0, 3000.0, 30_000.0] {
        let b = normalise3(&mesh, &raw, &limits, target);
        assert!(b.reached, "{target}");
        let hand = by_hand3(&raw, b.scale, lo, hi, r);
        // The count by another route: the metrics' expected vertices over the cells.
        let metric: Vec<Sym3> = hand.iter().map(SizeTensor3::to_metric).collect();
        let v = crate::metric_field::expected_vertices(&mesh, &metric);
        assert!((v / target - 1.0).abs() < 1e-9, "{target}: {v}");
        for (x, y) in b.tensors.iter().zip(&hand) {
            for (p, q) in x.sizes().iter().zip(y.sizes()) {
                assert!((p / q - 1.0).abs() < 1e-12, "{target}: {p} {q}");
            }
        }
        let at =
            |h: f64| hand.iter().any(|t| t.sizes().iter().any(|&s| (s / h - 1.0).abs() < 1e-12));
        assert!(at(hi), "{target}: no size at hmax");
        if target >= 30_000.0 {
            assert!(at(lo), "{target}: no size at hmin");
        }
        if target > 300.0 {
            let ratio = |t: &SizeTensor3| (t.aspect_ratio() / r - 1.0).abs() < 1e-9;
            assert!(hand.iter().any(ratio), "{target}: no tensor at the aspect ratio");
        }
        // The root is where it is: scales on both sides bracket it.
        let tets = <Sym3 as Complexity>::simplices(&mesh);
        for k in 1..=6 {
            let d = 10f64.powi(-k);
            let below =
                vertices_of3(&mesh.points, &tets, &by_hand3(&raw, b.scale * (1.0 - d), lo, hi, r));
            let above =
                vertices_of3(&mesh.points, &tets, &by_hand3(&raw, b.scale * (1.0 + d), lo, hi, r));
            assert!(below <= target && above >= target, "{target} {d}: {below} {above}");
        }
    }
}

#[test]
fn the_gradation_and_the_share_act_inside_the_normalisation_in_space() {
    let mesh = smartmesh_test_support::grid::kuhn_box(5, [1.0; 3]);
    let topology = crate::topology::Topology::from_mesh(&mesh);
    let space = SpaceMesh::new(&mesh, &topology).unwrap();
    let raw = raw_field3(&mesh);
    let bounds = SizeBounds::try_new(1e-4, 10.0, 1e3).unwrap();
    let graded = Limits3 { bounds, gradation: Some((1.3, &space)) };
    let target = 2000.0;
    let b = normalise3(&mesh, &raw, &graded, target);
    assert!(b.reached && (b.vertices / target - 1.0).abs() < 1e-9, "{}", b.vertices);
    // The graded field is the ungraded one at the same scale, graded: its count is the
    // target, and the ungraded one's at that scale fewer (the gradation only shrinks).
    let mut by_hand = by_hand3(&raw, b.scale, 1e-4, 10.0, 1e3);
    let tets = <Sym3 as Complexity>::simplices(&mesh);
    let ungraded = vertices_of3(&mesh.points, &tets, &by_hand);
    apply_gradation3(&space, &mut by_hand, 1.3);
    let again = vertices_of3(&mesh.points, &tets, &by_hand);
    assert!((again / target - 1.0).abs() < 1e-9 && ungraded < target, "{again} {ungraded}");
    // A recipe asking for more than its share is scaled to it; the solution's uniform
    // field takes the rest, the whole on the target.
    let plain = Limits3 { bounds, gradation: None };
    let solution = vec![SizeTensor3::isotropic(0.3); raw.len()];
    let own = vertices_of3(&mesh.points, &tets, &raw);
    assert!(own > 0.25 * target, "{own}");
    let s = share3(&mesh, &raw, &solution, &plain, target, 0.25);
    assert!(s.reached && (s.vertices / target - 1.0).abs() < 1e-9, "{}", s.vertices);
    let factor = (own / (0.25 * target)).powf(1.0 / 3.0);
    let floor: Vec<SizeTensor3> = raw.iter().map(|t| t.scaled(factor)).collect();
    let capped = vertices_of3(&mesh.points, &tets, &floor);
    assert!((capped / (0.25 * target) - 1.0).abs() < 1e-9, "{capped}");
    for (t, f) in s.tensors.iter().zip(&floor) {
        // Every tensor lies inside the recipe's capped one: no longer along its axes.
        for (axis, h) in f.frame().iter().zip(f.sizes()) {
            assert!(t.size_along(*axis) <= h * (1.0 + 1e-9), "{t:?} not inside {f:?}");
        }
    }
}
