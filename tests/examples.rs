//! The examples of `examples/`: each recipe resolves on its example's starting mesh
//! (`start.msh`, made from the example's `geometry.poly` by PyPI `triangle`, see
//! `examples/make_examples.py`), and the field that `compute_size_field` gives there has
//! the sizes the recipe asks for near each of its sources: at the topological points, on
//! the walls, across the shocks and wakes, far away. Expected values come from the
//! recipe's own functions, read by name, so a retuned recipe keeps its test.
//!
//! Also: each `geometry.poly` and its `start.msh` carry the same tags at the same places,
//! the starting meshes stay under 200 KB, and (when Python has numpy, triangle and gmsh)
//! the generator still writes the committed `.poly` files byte for byte.
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured or skipped is printed for the log.

use smartmesh_test_support::formats as common;

use std::collections::BTreeSet;

use smartmesh::formats::{read_path, CellKind, TaggedMesh};
use smartmesh::recipe::Recipe;
use smartmesh::sizing::{
    compute_size_field, run_algorithm, CurvatureToSize, DistanceFunction, SizeField, SizingPlan,
};
use smartmesh::{MeshGraph, SizeTensor, Topology};

#[path = "support/examples.rs"]
mod support;

use support::{cpp_or_skip, examples, EXAMPLES};

struct Case {
    name: String,
    mesh: TaggedMesh,
    topo: Topology,
    graph: MeshGraph,
    recipe: Recipe,
    plan: SizingPlan,
    field: SizeField,
}

fn load(folder: &str, recipe_path: &str) -> Case {
    let mesh = read_path(&examples().join(folder).join("start.msh"), None).unwrap();
    let topo = Topology::from_mesh(&mesh);
    let recipe = Recipe::from_path(&examples().join(recipe_path))
        .unwrap_or_else(|e| panic!("{recipe_path}: {e}"));
    let resolved = recipe
        .resolve(&topo)
        .unwrap_or_else(|e| panic!("{recipe_path} on {folder}/start.msh: {e}"));
    let graph = MeshGraph::from_topology(&topo, &mesh).unwrap();
    let field = compute_size_field(&graph, &topo, &resolved.plan, &mut |_| {}).unwrap();
    assert!(field.warnings.is_empty(), "{folder}: {:?}", field.warnings);
    assert!(field.reached.iter().all(|r| *r), "{folder}: some vertex is reached by no algorithm");
    Case { name: folder.to_string(), mesh, topo, graph, recipe, plan: resolved.plan, field }
}

impl Case {
    fn distance(&self, name: &str) -> DistanceFunction {
        self.recipe.functions[name]
            .distance()
            .unwrap_or_else(|| panic!("{name} is not a distance function"))
            .unwrap()
    }

    fn curvature(&self, name: &str) -> CurvatureToSize {
        self.recipe.functions[name]
            .curvature()
            .unwrap_or_else(|| panic!("{name} is not a curvature-to-size function"))
            .unwrap()
    }

    fn polyline(&self, name: &str) -> &[[f64; 2]] {
        self.recipe.polylines[name].plane().expect("a planar polyline")
    }

    fn xy(&self, v: usize) -> [f64; 2] {
        [self.mesh.points[v][0], self.mesh.points[v][1]]
    }

    fn tensor(&self, v: usize) -> &SizeTensor {
        &self.field.tensors[v]
    }

    fn point(&self, tag: i32) -> usize {
        self.topo
            .points
            .iter()
            .find(|p| p.tag == Some(tag))
            .unwrap_or_else(|| panic!("{}: no point {tag}", self.name))
            .vertex
    }

    /// The vertices inside the curves with these tags (not their end points), each with
    /// the unit tangent of the curve there.
    fn on_curves(&self, tags: &[i32]) -> Vec<(usize, [f64; 2])> {
        let mut out = Vec::new();
        for c in self.topo.curves.iter().filter(|c| c.tag.is_some_and(|t| tags.contains(&t))) {
            for pl in &c.polylines {
                let n = pl.vertices.len();
                let inner: Box<dyn Iterator<Item = usize>> =
                    if pl.closed { Box::new(0..n) } else { Box::new(1..n.saturating_sub(1)) };
                for i in inner {
                    let (a, b) = (pl.vertices[(i + n - 1) % n], pl.vertices[(i + 1) % n]);
                    let (pa, pb) = (self.xy(a), self.xy(b));
                    out.push((pl.vertices[i], unit([pb[0] - pa[0], pb[1] - pa[1]])));
                }
            }
        }
        assert!(!out.is_empty(), "{}: curves {tags:?} have no inner vertex", self.name);
        out
    }

    /// The vertices that the recipe's algorithm along polyline `name` reaches by its
    /// neighbour propagation (run on its own).
    fn reached_along(&self, name: &str) -> BTreeSet<usize> {
        let quoted = format!("along \"{name}\"");
        let (i, step) = self
            .plan
            .steps
            .iter()
            .enumerate()
            .find(|(_, s)| s.label.contains(&quoted))
            .unwrap_or_else(|| panic!("{}: no algorithm along {name}", self.name));
        let c = run_algorithm(&self.graph, &self.topo, &step.algorithm, i, &step.label).unwrap();
        c.vertices.iter().map(|&v| v as usize).collect()
    }

    /// Mesh vertices within `r` of the polyline whose foot has a curvilinear abscissa in
    /// `[s0, s1]`: (vertex, distance, unit normal from the foot to the vertex).
    fn along(&self, line: &[[f64; 2]], r: f64, s0: f64, s1: f64) -> Vec<(usize, f64, [f64; 2])> {
        (0..self.mesh.points.len())
            .filter(|&v| !matches!(self.topo.vertex_class[v], smartmesh::Classification::Unused))
            .filter_map(|v| {
                let (d, s, n) = foot(line, self.xy(v));
                (d <= r && s >= s0 && s <= s1).then_some((v, d, n))
            })
            .collect()
    }

    /// Every size within the recipe's global bounds.
    fn check_bounds(&self, lo: f64, hi: f64, aspect: f64) {
        for (v, t) in self.field.tensors.iter().enumerate() {
            assert!(
                t.h_min() >= lo * (1.0 - 1e-6) && t.h_max() <= hi * (1.0 + 1e-6),
                "{}: vertex {v} sizes {:?} outside [{lo}, {hi}]",
                self.name,
                t.sizes()
            );
            assert!(
                t.aspect_ratio() <= aspect * (1.0 + 1e-6),
                "{}: vertex {v} aspect ratio {}",
                self.name,
                t.aspect_ratio()
            );
        }
    }

    /// At topological point `tag`: the smaller and the larger size, each within a range.
    fn check_point(&self, tag: i32, smallest: (f64, f64), largest: (f64, f64)) {
        let t = self.tensor(self.point(tag));
        eprintln!(
            "{}: point {tag}: sizes {:.5} {:.5} (expected in {smallest:?} and {largest:?})",
            self.name,
            t.h_min(),
            t.h_max()
        );
        within(&format!("{}: point {tag}, smaller size", self.name), t.h_min(), smallest);
        within(&format!("{}: point {tag}, larger size", self.name), t.h_max(), largest);
    }

    /// On the curves: the size across them (normal) and along them (tangent), for the
    /// inner vertices that `keep` accepts.
    fn check_wall(
        &self,
        tags: &[i32],
        keep: impl Fn([f64; 2]) -> bool,
        across: (f64, f64),
        along: (f64, f64),
    ) {
        let vs: Vec<_> =
            self.on_curves(tags).into_iter().filter(|(v, _)| keep(self.xy(*v))).collect();
        assert!(!vs.is_empty(), "{}: no vertex on curves {tags:?} passes the filter", self.name);
        let (mut a_lo, mut a_hi, mut t_lo, mut t_hi) =
            (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
        for &(v, t) in &vs {
            let n = [-t[1], t[0]];
            let (a, b) = (self.tensor(v).size_along(n), self.tensor(v).size_along(t));
            a_lo = a_lo.min(a);
            a_hi = a_hi.max(a);
            t_lo = t_lo.min(b);
            t_hi = t_hi.max(b);
        }
        eprintln!("{}: curves {tags:?} ({} vertices): across [{a_lo:.5}, {a_hi:.5}], along [{t_lo:.5}, {t_hi:.5}]", self.name, vs.len());
        assert!(
            a_lo >= across.0 * (1.0 - 1e-6) && a_hi <= across.1 * (1.0 + 1e-6),
            "{}: curves {tags:?}: across in [{a_lo}, {a_hi}], expected within {across:?}",
            self.name
        );
        assert!(
            t_lo >= along.0 * (1.0 - 1e-6) && t_hi <= along.1 * (1.0 + 1e-6),
            "{}: curves {tags:?}: along in [{t_lo}, {t_hi}], expected within {along:?}",
            self.name
        );
    }

    /// A band along an imaginary polyline (a shock, a wake): at every vertex within the
    /// perpendicular function's maximal distance (foot at a curvilinear abscissa in `s`,
    /// and `keep` true), the size across the line is at least the recipe's size on the
    /// line and at most what the perpendicular function gives at the vertex's distance;
    /// in the inner third of the band the smaller axis is across the line (within
    /// `degrees`) where the tensor is anisotropic.
    fn check_band(
        &self,
        polyline: &str,
        perpendicular: &str,
        s: (f64, f64),
        keep: impl Fn([f64; 2]) -> bool,
        degrees: f64,
    ) {
        let line = self.polyline(polyline);
        let f = self.distance(perpendicular);
        let r = f.max_distance();
        let band: Vec<_> = self
            .along(line, r, s.0, s.1)
            .into_iter()
            .filter(|&(v, _, _)| keep(self.xy(v)))
            .collect();
        // On a coarse mesh a vertex of the band may be linked to the line only through
        // vertices outside it, where the propagation stops (thesis algorithm 4.4): the
        // field has what the algorithm gave to the vertices it reached.
        let reached = self.reached_along(polyline);
        let vs: Vec<_> = band.iter().copied().filter(|(v, _, _)| reached.contains(v)).collect();
        assert!(
            vs.len() >= 5,
            "{}: only {} of {} vertices within {r} of {polyline} reached",
            self.name,
            vs.len(),
            band.len()
        );
        let (mut lo, mut worst_angle) = (f64::INFINITY, 0.0f64);
        for &(v, d, n) in &vs {
            let ten = self.tensor(v);
            let across = ten.size_along(n);
            lo = lo.min(across);
            assert!(
                across >= f.size_at_source() * (1.0 - 1e-6),
                "{}: {polyline}: vertex {v} at distance {d}: size across {across} < {}",
                self.name,
                f.size_at_source()
            );
            assert!(
                across <= f.eval(d) * (1.0 + 1e-6),
                "{}: {polyline}: vertex {v} at distance {d}: size across {across} > {} asked",
                self.name,
                f.eval(d)
            );
            if ten.aspect_ratio() > 1.5 && d < r / 3.0 {
                let small = if ten.h1() <= ten.h2() { ten.axis() } else { ten.second_axis() };
                let angle = (small[0] * n[0] + small[1] * n[1]).abs().min(1.0).acos().to_degrees();
                worst_angle = worst_angle.max(angle);
            }
        }
        eprintln!("{}: {polyline}: {} of {} vertices within {r} reached: smallest size across {lo:.5} (line {}), worst misalignment {worst_angle:.1} deg", self.name, vs.len(), band.len(), f.size_at_source());
        assert!(
            worst_angle <= degrees,
            "{}: {polyline}: smaller axis {worst_angle} deg off the normal",
            self.name
        );
    }

    /// Distance from `p` to the nearest vertex of the curves with these tags.
    fn to_curves(&self, tags: &[i32], p: [f64; 2]) -> f64 {
        self.on_curves(tags).iter().map(|&(v, _)| dist(p, self.xy(v))).fold(f64::INFINITY, f64::min)
    }

    /// Isotropic `size` at the vertices that `keep` accepts (far from every source).
    fn check_far(&self, keep: impl Fn([f64; 2]) -> bool, size: f64, rel: f64) {
        let vs: Vec<usize> = (0..self.mesh.points.len()).filter(|&v| keep(self.xy(v))).collect();
        assert!(!vs.is_empty(), "{}: no far vertex", self.name);
        for &v in &vs {
            let t = self.tensor(v);
            close(
                &format!("{}: far vertex {v} at {:?}, smaller size", self.name, self.xy(v)),
                t.h_min(),
                size,
                rel,
            );
            close(&format!("{}: far vertex {v}, larger size", self.name), t.h_max(), size, rel);
        }
        eprintln!("{}: {} far vertices at size {size}", self.name, vs.len());
    }
}

fn unit(v: [f64; 2]) -> [f64; 2] {
    let l = (v[0] * v[0] + v[1] * v[1]).sqrt();
    [v[0] / l, v[1] / l]
}

fn within(what: &str, got: f64, range: (f64, f64)) {
    assert!(
        got >= range.0 * (1.0 - 1e-6) && got <= range.1 * (1.0 + 1e-6),
        "{what}: {got}, expected within {range:?}"
    );
}

/// `x` give or take `rel`.
fn about(x: f64, rel: f64) -> (f64, f64) {
    (x * (1.0 - rel), x * (1.0 + rel))
}

fn close(what: &str, got: f64, want: f64, rel: f64) {
    assert!(
        (got - want).abs() <= rel * want,
        "{what}: {got}, expected {want} within {}%",
        rel * 100.0
    );
}

/// Distance from `p` to the polyline, the curvilinear abscissa of the foot, and the unit
/// normal from the foot to `p` (the segment's normal when `p` is on it); brute force.
fn foot(line: &[[f64; 2]], p: [f64; 2]) -> (f64, f64, [f64; 2]) {
    let (mut best, mut s_best, mut t_best) = (f64::INFINITY, 0.0, [0.0, 1.0]);
    let mut s = 0.0;
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let e = [b[0] - a[0], b[1] - a[1]];
        let len2 = e[0] * e[0] + e[1] * e[1];
        let u = (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / len2).clamp(0.0, 1.0);
        let q = [a[0] + u * e[0], a[1] + u * e[1]];
        let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
        if d < best {
            best = d;
            s_best = s + u * len2.sqrt();
            t_best = if d > 1e-12 {
                [(p[0] - q[0]) / d, (p[1] - q[1]) / d]
            } else {
                let t = unit(e);
                [-t[1], t[0]]
            };
        }
        s += len2.sqrt();
    }
    (best, s_best, t_best)
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// The two airfoil cases share their recipe's layout: leading (11) and trailing (12)
/// edge points, a wall layer on curves 1 and 2, two shocks, a wake over `wake` (its
/// abscissa range), a uniform far field of size `far_size` beyond `far_radius` from
/// mid-chord; `bounds` are the field's expected (smallest, largest) size.
fn airfoil(
    folder: &str,
    recipe: &str,
    bounds: (f64, f64),
    wake: (f64, f64),
    far_radius: f64,
    far_size: f64,
) {
    let c = load(folder, recipe);
    c.check_bounds(bounds.0, bounds.1, 50.0);
    // Leading edge: the wall's normal size across, the edge's own size along the wall.
    // At the sharp trailing edge the layers of both surfaces cross: both sizes are about
    // the wall's normal size, no more than the edge's.
    let (wall, edge) =
        (c.distance("WallNormal").size_at_source(), c.distance("Edge").size_at_source());
    c.check_point(11, about(wall, 0.02), about(edge, 0.02));
    c.check_point(12, about(wall, 0.05), (wall, edge));
    // The wall layer: the normal size at the wall, along it no more than WallTangent's.
    c.check_wall(
        &[1, 2],
        |_| true,
        about(wall, 0.05),
        (wall, c.distance("WallTangent").size_at_source()),
    );
    // Shocks (away from their foot in the wall layer) and the wake.
    let off_wall = |p: [f64; 2]| c.to_curves(&[1, 2], p) > c.distance("WallNormal").max_distance();
    c.check_band("UpperShock", "ShockNormal", (0.0, 1.0), off_wall, 20.0);
    c.check_band("LowerShock", "ShockNormal", (0.0, 1.0), off_wall, 20.0);
    c.check_band("Wake", "WakeNormal", wake, |_| true, 20.0);
    // The far field keeps the uniform size.
    c.check_far(|p| dist(p, [0.5, 0.0]) > far_radius, far_size, 0.01);
}

/// AGARD02–05 share AGARD01's wall layer and edges and have their own shocks and wakes:
/// every DISTANCE_TO_IMAGINARY_POLYLINE of the recipe is checked as a band
/// ([`Case::check_band`]) away from the wall, the edges and every other line at least as
/// fine across, where that one decides; `bounds` are the field's expected (smallest,
/// largest) size, `far_size` the uniform size beyond `far_radius` from mid-chord.
fn airfoil_lines(folder: &str, bounds: (f64, f64), far_radius: f64, far_size: f64) {
    use smartmesh::recipe::model::SpecValue;
    let c = load(folder, &format!("{folder}/recipe.toml"));
    c.check_bounds(bounds.0, bounds.1, 50.0);
    let (wall, edge) =
        (c.distance("WallNormal").size_at_source(), c.distance("Edge").size_at_source());
    c.check_point(11, about(wall, 0.02), about(edge, 0.02));
    c.check_point(12, about(wall, 0.05), (wall, edge));
    c.check_wall(
        &[1, 2],
        |_| true,
        about(wall, 0.05),
        (wall, c.distance("WallTangent").size_at_source()),
    );
    // (polyline, its perpendicular function) for each line of the recipe.
    let lines: Vec<(String, String)> = c
        .recipe
        .algorithms
        .iter()
        .filter_map(|a| {
            let (_, polyline) = a.polyline()?;
            let normal = a.arguments().find_map(|(p, v)| match (p.field, v) {
                ("perpendicular", SpecValue::Name(n)) => Some(n.clone()),
                _ => None,
            })?;
            Some((polyline.to_string(), normal))
        })
        .collect();
    assert!(lines.len() >= 3, "{folder}: {lines:?}");
    let edge_reach = c.distance("Edge").max_distance();
    let wall_reach = c.distance("WallNormal").max_distance();
    let (le, te) = (c.xy(c.point(11)), c.xy(c.point(12)));
    for (name, normal) in &lines {
        let own = c.distance(normal).size_at_source();
        let others: Vec<(&[[f64; 2]], f64)> = lines
            .iter()
            .filter(|(n, f)| n != name && c.distance(f).size_at_source() <= own)
            .map(|(n, f)| (c.polyline(n), c.distance(f).max_distance()))
            .collect();
        let alone = |p: [f64; 2]| {
            c.to_curves(&[1, 2], p) > wall_reach
                && dist(p, le) > edge_reach
                && dist(p, te) > edge_reach
                && others.iter().all(|(l, r)| foot(l, p).0 > *r)
        };
        c.check_band(name, normal, (0.0, f64::INFINITY), alone, 20.0);
    }
    c.check_far(|p| dist(p, [0.5, 0.0]) > far_radius, far_size, 0.01);
}

#[test]
fn naca0012_agard02() {
    airfoil_lines("naca0012-agard02", (0.0005, 2.0), 24.0, 2.0);
}

#[test]
fn naca0012_agard03() {
    airfoil_lines("naca0012-agard03", (0.0005, 4.0), 70.0, 4.0);
}

#[test]
fn naca0012_agard04() {
    airfoil_lines("naca0012-agard04", (0.0005, 2.0), 24.0, 2.0);
}

#[test]
fn naca0012_agard05() {
    airfoil_lines("naca0012-agard05", (0.0005, 2.0), 24.0, 2.0);
}

#[test]
fn naca0012_agard01() {
    airfoil(
        "naca0012-agard01",
        "naca0012-agard01/recipe.toml",
        (0.0005, 2.0),
        (1.0, 9.0),
        24.0,
        2.0,
    );
}

#[test]
fn gamm_a7_viscous() {
    // The long wake: fine across it all along its 10 chords.
    airfoil("gamm-a7-viscous", "gamm-a7-viscous/recipe.toml", (0.0004, 5.0), (1.0, 9.5), 49.0, 5.0);
}

#[test]
fn u_duct() {
    let c = load("u-duct", "u-duct/recipe.cfg");
    c.check_bounds(0.002, 0.08, 20.0);
    let corner = c.distance("FCorners").size_at_source();
    for tag in [1, 2] {
        c.check_point(tag, about(corner, 0.02), about(corner, 0.02));
    }
    let wall = c.distance("FWallPerp").size_at_source();
    let cw = c.curvature("CWall");
    let (outer, inner) = (cw.eval_radius(1.5), cw.eval_radius(0.5));
    eprintln!("u-duct: curvature sizes: outer bend {outer:.5}, inner bend {inner:.5}");
    // Walls: the normal size everywhere; along them the curvature's size on the bends,
    // finer on the tighter inner bend, and the largest size where they are straight.
    c.check_wall(&[13], |p| p[1] > 0.3, about(wall, 0.02), about(outer, 0.02));
    c.check_wall(&[14], |p| p[1] > 0.15, about(wall, 0.02), about(inner, 0.02));
    c.check_wall(&[13, 14], |p| p[1] < -0.6 && p[1] > -3.5, about(wall, 0.02), about(0.08, 0.02));
    c.check_band("Wake", "FWakePerp", (1.0, 3.8), |_| true, 20.0);
    // The middle of the left leg has the uniform size.
    c.check_far(|p| p[0] > -1.15 && p[0] < -0.85 && p[1] < -1.0 && p[1] > -3.0, 0.08, 0.01);
}

/// The three distributors: one recipe, three guide vanes.
#[test]
fn distributor_variants() {
    if !cpp_or_skip() {
        return;
    }
    let mut le_tangent = Vec::new();
    let mut gap_size = Vec::new();
    for variant in ["1-narrow", "2-thick", "3-s-shaped"] {
        let c = load(&format!("distributor/{variant}"), "distributor/recipe.cfg");
        c.check_bounds(c.distance("Fcorners").size_at_source(), 2.0, f64::INFINITY);
        // Corners (DISTANCE_TO_POINT): the points' own size, isotropic.
        let corner = c.distance("Fcorners").size_at_source();
        for tag in [1, 2, 3, 4, 5, 6, 7, 11, 12] {
            c.check_point(tag, about(corner, 0.02), about(corner, 0.02));
        }
        // The stay vane away from its corners: DISTANCE_TO_BORDER's sizes at the wall.
        // The recipe's gradation shrinks them where the wall bends (the nose, radius 1.6):
        // neighbouring wall tensors of aspect ratio 10 turn by a few degrees from one
        // vertex of this coarse starting mesh to the next, and the gradation pass makes
        // each fit inside its neighbour's grown tensor (to 0.068 instead of 0.1 here).
        let corners: Vec<[f64; 2]> =
            [1, 2, 3, 4, 5, 6, 7].iter().map(|&t| c.xy(c.point(t))).collect();
        let perp = c.distance("FStayVanePerp").size_at_source();
        c.check_wall(
            &[102, 103, 105, 106],
            |p| corners.iter().all(|&q| dist(p, q) > 0.8),
            about(perp, 0.02),
            (perp, c.distance("FStayVanePara").size_at_source()),
        );
        c.check_wall(
            &[101, 107],
            |p| corners.iter().all(|&q| dist(p, q) > 0.8),
            (0.6 * perp, perp),
            (0.6 * perp, c.distance("FStayVanePara").size_at_source()),
        );
        // The guide vane: CURVATURE_OF_BORDER's normal size, tangent sizes from C1 (away
        // from the stay vane's wake, POLYLINE1, which runs onto the guide vane of
        // 3-s-shaped).
        let gperp = c.distance("FGuideVanePerp").size_at_source();
        let c1 = c.curvature("C1");
        let gcorners: Vec<[f64; 2]> = [11, 12].iter().map(|&t| c.xy(c.point(t))).collect();
        let wake = c.distance("FLinePerp").max_distance();
        let off = |p: [f64; 2]| {
            gcorners.iter().all(|&q| dist(p, q) > 0.8) && foot(c.polyline("POLYLINE1"), p).0 > wake
        };
        c.check_wall(
            &[201, 203],
            off,
            (0.5 * gperp, gperp),
            (0.5 * gperp, c1.eval_radius(f64::INFINITY)),
        );
        let le = c.xy(c.point(13));
        let near_le =
            c.on_curves(&[201, 203]).into_iter().filter(|(v, _)| dist(c.xy(*v), le) < 0.3);
        le_tangent
            .push(near_le.map(|(v, t)| c.tensor(v).size_along(t)).fold(f64::INFINITY, f64::min));
        // Between the vanes (DISTANCE_BETWEEN_TWO_BORDERS): the largest size at the eight
        // vertices nearest to the middle of the gap.
        let (sv, gv) =
            (c.on_curves(&[101, 102, 103, 104, 105, 106, 107]), c.on_curves(&[201, 202, 203]));
        let (mut best, mut mid) = (f64::INFINITY, [0.0, 0.0]);
        for (a, _) in &sv {
            for (b, _) in &gv {
                let (pa, pb) = (c.xy(*a), c.xy(*b));
                if dist(pa, pb) < best {
                    best = dist(pa, pb);
                    mid = [(pa[0] + pb[0]) / 2.0, (pa[1] + pb[1]) / 2.0];
                }
            }
        }
        let mut gap: Vec<usize> = (0..c.mesh.points.len())
            .filter(|&v| !matches!(c.topo.vertex_class[v], smartmesh::Classification::Unused))
            .collect();
        gap.sort_by(|&a, &b| dist(c.xy(a), mid).total_cmp(&dist(c.xy(b), mid)));
        gap.truncate(8);
        let largest = gap.iter().map(|&v| c.tensor(v).h_max()).fold(0.0f64, f64::max);
        eprintln!("{variant}: gap {best:.2} at {mid:?}: largest size near its middle {largest:.4}; guide vane leading edge: smallest tangent size {:.4}", le_tangent.last().unwrap());
        gap_size.push(largest);
        // The wakes: the stay vane's (POLYLINE1, short, thesis A.1.6) and the guide vane's.
        let off_vanes =
            |p: [f64; 2]| c.to_curves(&[101, 102, 103, 104, 105, 106, 107, 201, 202, 203], p) > 1.0;
        c.check_band("POLYLINE1", "FLinePerp", (0.0, 10.0), off_vanes, 30.0);
        c.check_band("POLYLINE2", "FLinePerp", (2.0, 30.0), off_vanes, 20.0);
        // Far upstream: the uniform size.
        c.check_far(|p| p[0] < -85.0, 2.0, 0.01);
    }
    // Thesis 6.3.1: the narrow guide vane bends more sharply at its leading edge than the
    // thick one, so the size along its wall there is smaller (the third's leading edge
    // sits in the stay vane's wake, which is finer still); the gap is finest in the third
    // variant (narrowest gap) and coarsest in the second (widest).
    assert!(le_tangent[0] < 0.6 * le_tangent[1], "leading edge tangent sizes {le_tangent:?}");
    assert!(gap_size[2] < gap_size[0] && gap_size[0] < gap_size[1], "gap sizes {gap_size:?}");
}

/// Each `geometry.poly` and its `start.msh` carry the same tags: the .poly's vertex
/// markers are the mesh's topological points (same coordinates), its segment markers
/// the mesh's curves, its region attribute the mesh's face. Starting meshes stay small.
#[test]
fn poly_and_start_mesh_agree() {
    for &(folder, _) in EXAMPLES {
        let dir = examples().join(folder);
        let poly = read_path(&dir.join("geometry.poly"), None).unwrap();
        let mesh = read_path(&dir.join("start.msh"), None).unwrap();
        let topo = Topology::from_mesh(&mesh);
        let bytes = std::fs::metadata(dir.join("start.msh")).unwrap().len();
        assert!(bytes < 200_000, "{folder}/start.msh is {bytes} bytes");
        assert!(
            poly.cells().all(|c| c.0 == CellKind::Line),
            "{folder}: the .poly has only segments"
        );

        let poly_curves: BTreeSet<i32> = poly.cells().map(|c| c.2).collect();
        let mesh_curves: BTreeSet<i32> =
            topo.curves.iter().map(|c| c.tag.expect("every curve is tagged")).collect();
        assert_eq!(poly_curves, mesh_curves, "{folder}: curve tags");
        assert!(!poly_curves.contains(&0), "{folder}: a segment without marker");

        let markers = poly.point_data.get("triangle:marker").expect("vertex markers");
        let mut poly_points = Vec::new();
        for (v, m) in markers.values.iter().enumerate() {
            if *m != 0.0 {
                poly_points.push((*m as i32, [poly.points[v][0], poly.points[v][1]]));
            }
        }
        assert_eq!(
            poly_points.len(),
            topo.points.len(),
            "{folder}: every topological point is a .poly vertex with a marker"
        );
        for (tag, p) in poly_points {
            let v = topo
                .points
                .iter()
                .find(|q| q.tag == Some(tag))
                .unwrap_or_else(|| panic!("{folder}: no point {tag} in start.msh"))
                .vertex;
            assert!(
                dist(p, [mesh.points[v][0], mesh.points[v][1]]) < 1e-9,
                "{folder}: point {tag} moved"
            );
        }

        assert_eq!(poly.regions.len(), 1, "{folder}: one region");
        assert_eq!(topo.faces.len(), 1);
        assert_eq!(poly.regions[0].attribute as i32, topo.faces[0].tag, "{folder}: face tag");
        let bodies = match folder {
            "u-duct" => 0,
            f if f.starts_with("distributor") => 2,
            _ => 1,
        };
        assert_eq!(poly.holes.len(), bodies, "{folder}: one hole per body");
    }
}

/// The generator writes the committed .poly files byte for byte (the starting meshes
/// depend on the Triangle and Gmsh versions; `poly_and_start_mesh_agree` checks them).
#[test]
fn generator_writes_the_committed_poly_files() {
    let Some(py) = common::python_with(&["numpy", "triangle", "gmsh"]) else { return };
    let out = tempfile::tempdir().unwrap();
    let script = examples().join("make_examples.py");
    let o = std::process::Command::new(&py)
        .arg(&script)
        .arg("--out")
        .arg(out.path())
        .output()
        .expect("run python");
    assert!(o.status.success(), "make_examples.py: {}", String::from_utf8_lossy(&o.stderr));
    for &(folder, _) in EXAMPLES {
        let a = std::fs::read(examples().join(folder).join("geometry.poly")).unwrap();
        let b = std::fs::read(out.path().join(folder).join("geometry.poly")).unwrap();
        assert!(a == b, "{folder}/geometry.poly differs from what make_examples.py writes");
    }
}
