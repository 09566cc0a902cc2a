//! Periodic sides: the recipe's PERIODIC section in every format, the check that the two
//! sides are images of each other (refused with exit 2 naming the pair otherwise), and
//! the vertex match to 1e-12 after `mesh` (from a `.poly`), `remesh` (the library's
//! frozen curves) and `adapt`, for a translation and a rotation; the LAYER step on a wall
//! that ends on a periodic side.

use std::path::Path;

use smartmesh::formats::{read_path, write_path, TaggedMesh, WriteOptions};
use smartmesh::periodic::{check, check_all, PeriodicPair, Transform};
use smartmesh::recipe::{EntityRef, RecipeFormat};
use smartmesh::{remesh, Recipe, RemeshOptions, Sym2, Topology};
use smartmesh_test_support::grid::{unit_square, SquareGrid};

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;
use cli::{bad, ok, smartmesh, stderr};

/// Left (14, downwards) onto right (12, upwards): x + 1.
fn left_right() -> PeriodicPair {
    PeriodicPair {
        master: vec!["14".into()],
        slave: vec!["12".into()],
        transform: Transform::Translation([1.0, 0.0]),
    }
}

/// Bottom (11) onto left (14): a quarter turn about the origin.
fn bottom_left() -> PeriodicPair {
    PeriodicPair {
        master: vec!["11".into()],
        slave: vec!["14".into()],
        transform: Transform::Rotation { centre: [0.0, 0.0], angle_degrees: 90.0 },
    }
}

/// The match of `pair` on `mesh`, asserted to 1e-12.
fn assert_matched(mesh: &TaggedMesh, pair: &PeriodicPair) -> usize {
    let m = check(&mesh.points, &Topology::from_mesh(mesh), pair).expect("images");
    assert!(m.matched && m.max_distance <= 1e-12, "{m}");
    assert_eq!(m.master_vertices, m.slave_vertices, "{m}");
    m.master_vertices
}

/// The brute-force twin of the vertex match: every vertex on the lines of tag `a`, mapped,
/// equals (to 1e-12) one vertex on the lines of tag `b`, and the counts agree.
fn match_by_lines(mesh: &TaggedMesh, a: i32, b: i32, map: impl Fn([f64; 2]) -> [f64; 2]) {
    let on = |tag: i32| {
        let mut v: Vec<usize> = mesh
            .cells()
            .filter(|c| c.0 == smartmesh::formats::CellKind::Line && c.2 == tag)
            .flat_map(|c| c.1.iter().map(|&v| v as usize).collect::<Vec<_>>())
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let (va, vb) = (on(a), on(b));
    assert_eq!(va.len(), vb.len());
    for &v in &va {
        let q = map([mesh.points[v][0], mesh.points[v][1]]);
        let d = vb
            .iter()
            .map(|&w| (mesh.points[w][0] - q[0]).hypot(mesh.points[w][1] - q[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(d <= 1e-12, "vertex {v}: {d}");
    }
}

/// A metric asking for sizes of `across` and `along` the diagonal.
fn anisotropic(mesh: &TaggedMesh, along: f64, across: f64) -> Vec<Sym2> {
    let t = smartmesh::SizeTensor::from_angle(std::f64::consts::FRAC_PI_4, along, across).unwrap();
    vec![t.to_metric(); mesh.points.len()]
}

#[test]
fn the_remesher_keeps_periodic_sides_matched() {
    let mesh = SquareGrid {
        n: 6,
        sides: [11, 12, 13, 14],
        faces: [1, 1],
        interface: None,
        alternate: true,
    }
    .build();
    for pair in [left_right(), bottom_left()] {
        let before = assert_matched(&mesh, &pair);
        // Frozen: the sides keep their vertices.
        let tags = check(&mesh.points, &Topology::from_mesh(&mesh), &pair).unwrap().curve_tags;
        let opts = RemeshOptions { frozen_curves: tags, ..Default::default() };
        let out = remesh(&mesh, &anisotropic(&mesh, 0.5, 0.1), &opts).expect("remeshes").mesh;
        assert_ne!(out.points.len(), mesh.points.len());
        assert_eq!(assert_matched(&out, &pair), before);
        // Periodic: both sides split alike to a finer metric, then frozen.
        let opts = RemeshOptions { periodic: vec![pair.clone()], ..Default::default() };
        let out = remesh(&mesh, &anisotropic(&mesh, 0.25, 0.05), &opts).expect("remeshes").mesh;
        assert!(assert_matched(&out, &pair) > 2 * before);
        // Without either, the sides are resampled to the metric and lose the match.
        let free =
            remesh(&mesh, &anisotropic(&mesh, 0.5, 0.1), &RemeshOptions::default()).unwrap().mesh;
        let m = check(&free.points, &Topology::from_mesh(&free), &pair).unwrap();
        assert!(!m.matched, "{m}");
    }
    // The twin, on the translated pair after remeshing.
    let opts = RemeshOptions { periodic: vec![left_right()], ..Default::default() };
    let out = remesh(&mesh, &anisotropic(&mesh, 0.25, 0.05), &opts).unwrap().mesh;
    match_by_lines(&out, 14, 12, |p| [p[0] + 1.0, p[1]]);
}

#[test]
fn sides_that_are_not_images_are_refused_naming_the_pair() {
    let mesh = unit_square(5);
    let topo = Topology::from_mesh(&mesh);
    // Bottom onto top, but shifted by 0.9 instead of 1.
    let pair = PeriodicPair {
        master: vec!["11".into()],
        slave: vec!["13".into()],
        transform: Transform::Translation([0.0, 0.9]),
    };
    let e = check(&mesh.points, &topo, &pair).unwrap_err().to_string();
    assert!(e.contains("periodic pair master 11 and slave 13: the sides are not images"), "{e}");
    // A rotation by the wrong angle.
    let pair = PeriodicPair {
        transform: Transform::Rotation { centre: [0.0, 0.0], angle_degrees: 89.0 },
        ..bottom_left()
    };
    assert!(check(&mesh.points, &topo, &pair).is_err());
    // A curve the mesh does not have.
    let pair = PeriodicPair { master: vec!["99".into()], ..left_right() };
    let e = check(&mesh.points, &topo, &pair).unwrap_err().to_string();
    assert!(e.contains("no curve `99`"), "{e}");
    // Images, but with vertices that do not meet: measured, not matched.
    let mut shifted = mesh.clone();
    let v = (0..shifted.points.len()).find(|&v| shifted.points[v] == [1.0, 0.4, 0.0]).unwrap();
    shifted.points[v][1] = 0.45;
    let m = check_all(&shifted, &[left_right()]).unwrap().remove(0);
    assert!(!m.matched && (m.max_distance - 0.05).abs() < 1e-12, "{m}");
}

const RECIPE: &str = r#"[regions]
all = [1]

[[algorithms]]
type = "uniform"
size = 0.15
regions = ["all"]
"#;

#[test]
fn the_periodic_section_reads_in_every_format_and_round_trips() {
    let cfg = r#"CREATE_REGIONS = ( { NAME = "all"; TOPOLOGICAL_ENTITIES = [1]; } );
CREATE_ALGORITHMS = ( { TYPE = "UNIFORM"; SIZE = 0.08; REGIONS = ["all"]; } );
PERIODIC = (
  { MASTER = [14]; SLAVE = [12]; TRANSLATION = [1.0, 0.0]; },
  { MASTER = ("Bottom", 7); SLAVE = ("Left"); CENTER = [0, 0]; ANGLE = 90; }
);
"#;
    let r = Recipe::from_str(cfg, RecipeFormat::Libconfig, Path::new("p.cfg")).unwrap();
    assert_eq!(r.periodic.len(), 2);
    assert_eq!(r.periodic[1].pair().unwrap().transform, bottom_left().transform);
    for format in [RecipeFormat::Libconfig, RecipeFormat::Toml, RecipeFormat::Json] {
        let text = r.to_format(format);
        assert_eq!(Recipe::from_str(&text, format, Path::new("p")).unwrap(), r, "{text}");
    }
    let dir = tempfile::tempdir().unwrap();
    let mut from = dir.path().join("p.cfg");
    std::fs::write(&from, cfg).unwrap();
    for ext in ["toml", "json", "cfg"] {
        let to = dir.path().join(format!("converted-{ext}.{ext}"));
        ok(&smartmesh(&["recipe", "convert", from.to_str().unwrap(), to.to_str().unwrap()], None));
        assert_eq!(Recipe::from_path(&to).unwrap(), r, "{ext}");
        from = to;
    }
    // A translation and a rotation at once, or neither, is refused at its line.
    for (keys, says) in [
        ("TRANSLATION = [1, 0]; ANGLE = 3; CENTRE = [0, 0];", "give `translation`, or `centre`"),
        ("", "give `translation`, or `centre`"),
        ("TRANSLATION = [1, 0, 2];", "two numbers [x, y]"),
    ] {
        let text = format!("PERIODIC = (\n  {{ MASTER = [14]; SLAVE = [12];\n {keys} }}\n);\n");
        let e = Recipe::from_str(&text, RecipeFormat::Libconfig, Path::new("p.cfg")).unwrap_err();
        assert!(e.to_string().contains(says), "{keys}: {e}");
        assert!(e.line.is_some_and(|l| l == 2 || l == 3), "{keys}: {e}");
    }
    // TOML and JSON refuse a third component too (TOML dropped it silently), at its line.
    let toml = "[[periodic]]\nmaster = [14]\nslave = [12]\ntranslation = [0.0, 30.0, 5.0]\n";
    let json = "{\"periodic\": [{\"master\": [14], \"slave\": [12],\n \"centre\": [0, 0, 1], \"angle\": 9}]}";
    for (text, format, line) in [(toml, RecipeFormat::Toml, 4), (json, RecipeFormat::Json, 2)] {
        let e = Recipe::from_str(text, format, Path::new("p")).unwrap_err();
        assert!(e.to_string().contains("two numbers [x, y]"), "{text}: {e}");
        assert!(e.to_string().contains("found 3 numbers"), "{text}: {e}");
        assert_eq!(e.line, Some(line), "{text}: {e}");
    }
}

/// `smartmesh adapt` on `mesh` with RECIPE and `periodic` (TOML), output `out.msh`.
fn adapt(dir: &Path, mesh: &TaggedMesh, periodic: &str, extra: &[&str]) -> std::process::Output {
    let input = dir.join("in.msh");
    write_path(&input, mesh, None, &WriteOptions::default()).unwrap();
    let recipe = dir.join("r.toml");
    std::fs::write(&recipe, format!("{RECIPE}\n{periodic}")).unwrap();
    let out = dir.join("out.msh");
    let mut args = vec![
        "adapt",
        input.to_str().unwrap(),
        "--recipe",
        recipe.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    smartmesh(&args, None)
}

#[test]
fn adapt_keeps_periodic_sides_matched_and_refuses_bad_pairs() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = unit_square(4);
    let both = "[[periodic]]\nmaster = [14]\nslave = [12]\ntranslation = [1, 0]\n\n\
                [[periodic]]\nmaster = [11]\nslave = [14]\ncentre = [0, 0]\nangle = 90\n";
    let run = adapt(dir.path(), &mesh, both, &[]);
    ok(&run);
    let err = stderr(&run);
    // Both sides refined alike to the recipe's size 0.15 (the square's 4 edges a side
    // became 8), the rotated pair through the translated one.
    for pair in ["master 14 and slave 12: 9 and 9 vertices", "master 11 and slave 14: 9 and 9"] {
        assert!(err.contains(&format!("periodic {pair}")) && err.contains("(matched)"), "{err}");
    }
    let out = read_path(&dir.path().join("out.msh"), None).unwrap();
    assert!(out.points.len() > 40, "{}", out.points.len());
    assert_matched(&out, &left_right());
    assert_matched(&out, &bottom_left());
    match_by_lines(&out, 14, 12, |p| [p[0] + 1.0, p[1]]);
    match_by_lines(&out, 11, 14, |p| [-p[1], p[0]]);

    // Not images: exit 2 naming the pair, nothing written.
    std::fs::remove_file(dir.path().join("out.msh")).unwrap();
    let shifted = "[[periodic]]\nmaster = [11]\nslave = [13]\ntranslation = [0, 0.9]\n";
    let e = bad(&adapt(dir.path(), &mesh, shifted, &[]));
    assert!(e.contains("periodic pair master 11 and slave 13: the sides are not images"), "{e}");
    assert!(!dir.path().join("out.msh").exists());
    // A remesher that places boundary vertices by its own rules: exit 2.
    let e = bad(&adapt(dir.path(), &mesh, both, &["--adapter", "mmg2d"]));
    assert!(e.contains("kept matching by the native remesher only"), "{e}");
}

#[test]
fn a_layer_on_a_wall_that_ends_on_a_periodic_side_keeps_the_match_or_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = unit_square(4);
    let pair = "[[periodic]]\nmaster = [14]\nslave = [12]\ntranslation = [1, 0]\n\n";
    let layer = |curves: &str| {
        format!(
            "{pair}[layer]\ncurves = [{curves}]\nfirst_height = 0.01\nratio = 1.2\nlayers = 3\n"
        )
    };
    // The bottom wall ends on both sides: its columns slide up both alike, 3 vertices
    // more on each, still matched to 1e-12.
    let run = adapt(dir.path(), &mesh, &layer("11"), &[]);
    ok(&run);
    let out = read_path(&dir.path().join("out.msh"), None).unwrap();
    assert_eq!(out.num_cells_of(smartmesh::formats::CellKind::Quad), 24);
    let m = check_all(&out, &[left_right()]).unwrap().remove(0);
    assert!(m.matched && m.max_distance <= 1e-12 && m.master_vertices == 12, "{m}");
    match_by_lines(&out, 14, 12, |p| [p[0] + 1.0, p[1]]);
    // With the slave side a wall too, the corner is mitred on the slave side while the
    // master side gets the columns: refused with exit 2, the skinned mesh not written
    // (OUT keeps the loop's best mesh, which matches).
    let e = bad(&adapt(dir.path(), &mesh, &layer("11, 12"), &[]));
    assert!(
        e.contains("12 and 9 vertices")
            && e.contains("the LAYER skin moved or added vertices on a periodic side"),
        "{e}"
    );
    let out = read_path(&dir.path().join("out.msh"), None).unwrap();
    assert_eq!(out.num_cells_of(smartmesh::formats::CellKind::Quad), 0);
    assert_matched(&out, &left_right());
}

/// The distributor example (thesis 6.3.2.4), its recipe's PERIODIC section as it is: each
/// variant's graph meshed with matched sides; the start mesh's sides pair up to the 1e-9
/// of its file's digits; adapt (the loop and the LAYER skin) snaps the slave side onto
/// the master's images and the result, read back from its file, matches to 1e-12.
#[test]
fn the_distributor_keeps_its_periodic_sides_matched() {
    let dir = tempfile::tempdir().unwrap();
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/distributor");
    let recipe = base.join("recipe.cfg");
    if !cli::cpp_or_skip("the distributor recipe") {
        return;
    }
    let pair = PeriodicPair {
        master: vec!["302".into(), "303".into(), "304".into()],
        slave: vec!["308".into(), "307".into(), "306".into()],
        transform: Transform::Translation([0.0, 30.0]),
    };
    assert_eq!(
        Recipe::from_path(&recipe).unwrap().periodic[0].pair().unwrap(),
        pair,
        "the recipe's pair"
    );
    for variant in ["1-narrow", "2-thick", "3-s-shaped"] {
        let out = dir.path().join(format!("{variant}.msh"));
        let graph = base.join(variant).join("geometry.poly");
        let run = smartmesh(
            &[
                "mesh",
                graph.to_str().unwrap(),
                "--recipe",
                recipe.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ],
            None,
        );
        ok(&run);
        let mesh = read_path(&out, None).unwrap();
        assert_matched(&mesh, &pair);
        match_by_line_tags(&mesh, &[302, 303, 304], &[306, 307, 308], |p| [p[0], p[1] + 30.0]);
    }
    // recipe check meshes a graph as mesh and adapt do: matched.
    let graph = base.join("2-thick/geometry.poly");
    let text = ok(&smartmesh(
        &["recipe", "check", recipe.to_str().unwrap(), graph.to_str().unwrap()],
        None,
    ));
    assert!(text.contains("periodic master 302, 303, 304") && text.contains("(matched)"), "{text}");
    let start = base.join("1-narrow/start.msh");
    let input = read_path(&start, None).unwrap();
    let m = check_all(&input, std::slice::from_ref(&pair)).unwrap().remove(0);
    assert!(!m.matched && m.max_distance < 1e-8, "{m}");
    let out = dir.path().join("out.msh");
    let run = smartmesh(
        &[
            "adapt",
            start.to_str().unwrap(),
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    );
    ok(&run);
    assert!(stderr(&run).contains("slave vertices moved by at most 5.000e-9"), "{}", stderr(&run));
    // recipe check names the pair and its match on the start mesh, or refuses a wrong
    // transform with exit 2.
    let text = ok(&smartmesh(
        &["recipe", "check", recipe.to_str().unwrap(), start.to_str().unwrap()],
        None,
    ));
    assert!(
        text.contains("periodic master 302, 303, 304 and slave 308, 307, 306: 72 and 72 vertices"),
        "{text}"
    );
    assert!(text.contains("(matched)") && text.contains("at most 5.000e-9"), "{text}");
    let wrong = dir.path().join("wrong.cfg");
    let text = std::fs::read_to_string(&recipe).unwrap().replace("[ 0.0, 30.0 ]", "[ 0.0, 29.0 ]");
    assert!(text.contains("29.0"));
    std::fs::write(&wrong, text).unwrap();
    let e = bad(&smartmesh(
        &["recipe", "check", wrong.to_str().unwrap(), start.to_str().unwrap()],
        None,
    ));
    assert!(e.contains("the sides are not images of each other"), "{e}");
    let adapted = read_path(&out, None).unwrap();
    assert!(adapted.points.len() > 2 * input.points.len());
    assert_matched(&adapted, &pair);
    // size START with the recipe, then remesh it to that field with the recipe: its
    // sides pair up to 5e-9, are snapped, refined alike and stay matched.
    let field = dir.path().join("field.vtu");
    ok(&smartmesh(
        &[
            "size",
            start.to_str().unwrap(),
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            field.to_str().unwrap(),
        ],
        None,
    ));
    let again = dir.path().join("again.msh");
    let run = smartmesh(
        &[
            "remesh",
            start.to_str().unwrap(),
            "--metric",
            field.to_str().unwrap(),
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            again.to_str().unwrap(),
        ],
        None,
    );
    ok(&run);
    assert!(stderr(&run).contains("(matched)"), "{}", stderr(&run));
    let remeshed = read_path(&again, None).unwrap();
    assert!(remeshed.points.len() > 2 * input.points.len());
    assert_matched(&remeshed, &pair);
    // info with the recipe reports the match of the result.
    let text = ok(&smartmesh(
        &["info", out.to_str().unwrap(), "--recipe", recipe.to_str().unwrap()],
        None,
    ));
    assert!(
        text.contains("  periodic    master 302, 303, 304") && text.contains("(matched)"),
        "{text}"
    );
}

/// A hole of a graph: its polygon, its marker, a point inside.
type Hole<'a> = (&'a [[f64; 2]], i32, [f64; 2]);

/// A Triangle `.poly` of the closed loop `pieces` (each a polyline with its marker, the
/// last point of one the first of the next, the last piece ending where the first
/// starts) with holes bounded by `holes` (closed polygons with their marker and a point
/// inside).
fn poly(pieces: &[(&[[f64; 2]], i32)], holes: &[Hole]) -> String {
    let mut points: Vec<[f64; 2]> = vec![pieces[0].0[0]];
    let mut segments: Vec<(usize, usize, i32)> = Vec::new();
    for (k, (pts, tag)) in pieces.iter().enumerate() {
        for (i, p) in pts.iter().enumerate().skip(1) {
            let a = points.len() - 1;
            if k + 1 == pieces.len() && i + 1 == pts.len() {
                segments.push((a, 0, *tag));
            } else {
                points.push(*p);
                segments.push((a, a + 1, *tag));
            }
        }
    }
    let mut seeds = Vec::new();
    for (pts, tag, inside) in holes {
        let start = points.len();
        points.extend(pts.iter().copied());
        for i in 0..pts.len() {
            segments.push((start + i, start + (i + 1) % pts.len(), *tag));
        }
        seeds.push(*inside);
    }
    let mut s = format!("{} 2 0 0\n", points.len());
    for (i, p) in points.iter().enumerate() {
        s += &format!("{} {:.17e} {:.17e}\n", i + 1, p[0], p[1]);
    }
    s += &format!("{} 1\n", segments.len());
    for (i, (a, b, t)) in segments.iter().enumerate() {
        s += &format!("{} {} {} {t}\n", i + 1, a + 1, b + 1);
    }
    s += &format!("{}\n", seeds.len());
    for (i, p) in seeds.iter().enumerate() {
        s += &format!("{} {} {}\n", i + 1, p[0], p[1]);
    }
    s
}

/// The brute-force twin over sets of line tags: every vertex on the lines of `a`,
/// mapped, equals (to 1e-12) one vertex on the lines of `b`, and the reverse; the counts
/// agree.
fn match_by_line_tags(mesh: &TaggedMesh, a: &[i32], b: &[i32], map: impl Fn([f64; 2]) -> [f64; 2]) {
    let on = |tags: &[i32]| {
        let mut v: Vec<usize> = mesh
            .cells()
            .filter(|c| c.0 == smartmesh::formats::CellKind::Line && tags.contains(&c.2))
            .flat_map(|c| c.1.iter().map(|&v| v as usize).collect::<Vec<_>>())
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let (va, vb) = (on(a), on(b));
    assert_eq!(va.len(), vb.len());
    let mut partners: Vec<usize> = va
        .iter()
        .map(|&v| {
            let q = map([mesh.points[v][0], mesh.points[v][1]]);
            let (w, d) = vb
                .iter()
                .map(|&w| (w, (mesh.points[w][0] - q[0]).hypot(mesh.points[w][1] - q[1])))
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .unwrap();
            assert!(d <= 1e-12, "vertex {v}: {d}");
            w
        })
        .collect();
    partners.sort_unstable();
    partners.dedup();
    assert_eq!(partners.len(), vb.len(), "one to one");
}

/// The smallest angle of the mesh's triangles, degrees (by the law of cosines, apart
/// from the library's measure).
fn smallest_angle(mesh: &TaggedMesh) -> f64 {
    let mut worst = 180.0f64;
    for (kind, nodes, _, _) in mesh.cells() {
        if kind != smartmesh::formats::CellKind::Triangle {
            continue;
        }
        let p: Vec<[f64; 2]> = nodes
            .iter()
            .map(|&v| [mesh.points[v as usize][0], mesh.points[v as usize][1]])
            .collect();
        for k in 0..3 {
            let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
            let u = [b[0] - a[0], b[1] - a[1]];
            let w = [c[0] - a[0], c[1] - a[1]];
            let cos = (u[0] * w[0] + u[1] * w[1]) / (u[0].hypot(u[1]) * w[0].hypot(w[1]));
            worst = worst.min(cos.clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    worst
}

/// The distributor's channel (thesis 6.3.2.4): lower side three pieces 302..304, upper
/// side (306..308) the same shifted by the pitch 30, a blade-like hole near the lower
/// side. The upper side has vertices the lower one lacks (and the reverse), so the
/// mesher must put each side's vertices on the other.
fn distributor_like() -> String {
    let lower = [[-100.0, -16.0], [-72.0, -22.0], [-24.0, -36.0], [0.0, -44.0]];
    let up = |p: [f64; 2]| [p[0], p[1] + 30.0];
    let blade: Vec<[f64; 2]> = (0..14)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / 14.0;
            [-50.0 + 9.0 * a.cos(), -24.0 + 1.2 * a.sin() - 0.2 * a.cos()]
        })
        .collect();
    let l1: &[[f64; 2]] = &[lower[0], lower[1]];
    // An extra vertex on the lower middle piece only.
    let l2: &[[f64; 2]] = &[lower[1], [-40.0, -31.333333333333332], lower[2]];
    let l3: &[[f64; 2]] = &[lower[2], lower[3]];
    let outlet: &[[f64; 2]] = &[lower[3], up(lower[3])];
    // Extra vertices on the upper first and last pieces only.
    let u3: &[[f64; 2]] = &[up(lower[3]), [-9.0, -11.0], up(lower[2])];
    let u2: &[[f64; 2]] = &[up(lower[2]), up(lower[1])];
    let u1: &[[f64; 2]] = &[up(lower[1]), [-80.0, 9.714285714285714], [-93.0, 12.5], up(lower[0])];
    let inlet: &[[f64; 2]] = &[up(lower[0]), lower[0]];
    poly(
        &[
            (l1, 302),
            (l2, 303),
            (l3, 304),
            (outlet, 305),
            (u3, 306),
            (u2, 307),
            (u1, 308),
            (inlet, 301),
        ],
        &[(&blade, 101, [-50.0, -24.0])],
    )
}

/// An annular sector of 60 degrees whose straight sides are three-piece polylines (a
/// kink in each), the side at 60 degrees the image of the one at 0 by a rotation of 60 degrees about the origin, with vertices of its own on each.
fn sector() -> String {
    let rot = |p: [f64; 2]| {
        let (s, c) = 60f64.to_radians().sin_cos();
        [c * p[0] - s * p[1], s * p[0] + c * p[1]]
    };
    let master = [[1.0, 0.0], [1.3, 0.05], [1.7, -0.05], [2.0, 0.0]];
    let lerp =
        |a: [f64; 2], b: [f64; 2], t: f64| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
    // The master with a vertex of its own on its last piece; the slave, from outside in,
    // with one of its own on its (image of the) first piece.
    let m: Vec<[f64; 2]> =
        vec![master[0], master[1], master[2], lerp(master[2], master[3], 0.61), master[3]];
    let outer: Vec<[f64; 2]> = (0..=8)
        .map(|i| {
            let a = 60f64.to_radians() * i as f64 / 8.0;
            [2.0 * a.cos(), 2.0 * a.sin()]
        })
        .collect();
    let mut s: Vec<[f64; 2]> = vec![
        rot(master[3]),
        rot(master[2]),
        rot(master[1]),
        rot(lerp(master[0], master[1], 0.37)),
        rot(master[0]),
    ];
    s[0] = outer[8];
    let inner: Vec<[f64; 2]> = (0..=5)
        .rev()
        .map(|i| {
            let a = 60f64.to_radians() * i as f64 / 5.0;
            [a.cos(), a.sin()]
        })
        .collect();
    let mut inner = inner;
    inner[0] = s[4];
    poly(&[(&m, 11), (&outer, 12), (&s, 13), (&inner, 14)], &[])
}

/// `smartmesh mesh` on `poly` with the recipe text `recipe` (libconfig) and `extra`
/// options, to `out.msh` in `dir`.
fn mesh_poly(dir: &Path, poly: &str, recipe: &str, extra: &[&str]) -> std::process::Output {
    let input = dir.join("in.poly");
    std::fs::write(&input, poly).unwrap();
    let r = dir.join("p.cfg");
    std::fs::write(&r, recipe).unwrap();
    let out = dir.join("out.msh");
    let mut args = vec![
        "mesh",
        input.to_str().unwrap(),
        "--recipe",
        r.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    smartmesh(&args, None)
}

#[test]
fn mesh_matches_the_periodic_sides_of_a_graph() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    let translation = "PERIODIC = ( { MASTER = [302, 303, 304]; SLAVE = [308, 307, 306]; TRANSLATION = [0.0, 30.0]; } );\n";
    let up = |p: [f64; 2]| [p[0], p[1] + 30.0];
    let rotation =
        "PERIODIC = ( { MASTER = [11]; SLAVE = [13]; CENTRE = [0, 0]; ANGLE = 60; } );\n";
    let turn = |p: [f64; 2]| {
        let (s, c) = 60f64.to_radians().sin_cos();
        [c * p[0] - s * p[1], s * p[0] + c * p[1]]
    };
    let channel_pair = PeriodicPair {
        master: vec!["302".into(), "303".into(), "304".into()],
        slave: vec!["306".into(), "307".into(), "308".into()],
        transform: Transform::Translation([0.0, 30.0]),
    };
    let sector_pair = PeriodicPair {
        master: vec!["11".into()],
        slave: vec!["13".into()],
        transform: Transform::Rotation { centre: [0.0, 0.0], angle_degrees: 60.0 },
    };
    // Coarse (the refinement splits segments near the hole and the kinks, on one side
    // only) and finer: matched to 1e-12, as many vertices on each side, the angle bound
    // kept.
    for (graph, recipe, pair, size) in [
        (distributor_like(), translation, &channel_pair, None),
        (distributor_like(), translation, &channel_pair, Some("1.5")),
        (sector(), rotation, &sector_pair, None),
        (sector(), rotation, &sector_pair, Some("0.07")),
    ] {
        let mut extra = vec![];
        if let Some(s) = size {
            extra = vec!["--size", s];
        }
        let run = mesh_poly(dir.path(), &graph, recipe, &extra);
        ok(&run);
        assert!(stderr(&run).contains("(matched)"), "{}", stderr(&run));
        let mesh = read_path(&out, None).unwrap();
        let n = assert_matched(&mesh, pair);
        assert!(n > 5, "{n}");
        if pair == &channel_pair {
            match_by_line_tags(&mesh, &[302, 303, 304], &[306, 307, 308], up);
        } else {
            match_by_line_tags(&mesh, &[11], &[13], turn);
        }
        assert!(smallest_angle(&mesh) >= 20.7 - 1e-9, "{}", smallest_angle(&mesh));
        // Without the recipe, the refinement leaves the sides unmatched.
        let plain = dir.path().join("plain.msh");
        ok(&smartmesh(
            &[
                &[
                    "mesh",
                    dir.path().join("in.poly").to_str().unwrap(),
                    "-o",
                    plain.to_str().unwrap(),
                ][..],
                &extra,
            ]
            .concat(),
            None,
        ));
        let m = check_all(&read_path(&plain, None).unwrap(), std::slice::from_ref(pair)).unwrap();
        assert!(!m[0].matched, "{}", m[0]);
    }
    // Sides that are not images: exit 2 naming the pair, nothing written.
    std::fs::remove_file(&out).unwrap();
    let wrong = translation.replace("30.0", "29.0");
    let e = bad(&mesh_poly(dir.path(), &distributor_like(), &wrong, &[]));
    assert!(
        e.contains(
            "periodic pair master 302, 303, 304 and slave 308, 307, 306: the sides are not images"
        ),
        "{e}"
    );
    assert!(!out.exists());
    // A curve the graph does not have.
    let e =
        bad(&mesh_poly(dir.path(), &distributor_like(), &translation.replace("302", "309"), &[]));
    assert!(e.contains("no curve `309`"), "{e}");
    // --json reports each pair's match.
    let json = ok(&mesh_poly(dir.path(), &sector(), rotation, &["--json"]));
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["periodic"][0]["matched"], true, "{json}");
    assert_eq!(v["periodic"][0]["master_vertices"], v["periodic"][0]["slave_vertices"]);
    // The graph and the recipe cannot both be stdin.
    let e = bad(&smartmesh(&["mesh", "-", "--from", "poly", "--recipe", "-", "-o", "x.msh"], None));
    assert!(e.contains("cannot both come from stdin"), "{e}");
}

/// `adapt` from a `.poly` meshes its sides matched, then keeps them so.
#[test]
fn adapt_from_a_graph_starts_with_matched_sides() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.poly");
    std::fs::write(&input, sector()).unwrap();
    let recipe = dir.path().join("r.toml");
    std::fs::write(
        &recipe,
        "[regions]\nall = [0]\n\n[[algorithms]]\ntype = \"uniform\"\nsize = 0.1\nregions = [\"all\"]\n\n\
         [[periodic]]\nmaster = [11]\nslave = [13]\ncentre = [0, 0]\nangle = 60\n",
    )
    .unwrap();
    let out = dir.path().join("out.msh");
    let run = smartmesh(
        &[
            "adapt",
            input.to_str().unwrap(),
            "--recipe",
            recipe.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    );
    ok(&run);
    assert!(!stderr(&run).contains("do not match"), "{}", stderr(&run));
    let mesh = read_path(&out, None).unwrap();
    let pair = PeriodicPair {
        master: vec!["11".into()],
        slave: vec!["13".into()],
        transform: Transform::Rotation { centre: [0.0, 0.0], angle_degrees: 60.0 },
    };
    assert!(assert_matched(&mesh, &pair) >= 10);
}

/// `smartmesh layer` with a recipe of periodic pairs: walls that end on both sides of a
/// pair at image places slide alike along both (translation and rotation), matched to
/// 1e-12; a wall ending on one side only is refused with exit 2, nothing written.
#[test]
fn the_layer_command_keeps_periodic_sides_matched_or_refuses() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("in.msh");
    write_path(&input, &unit_square(4), None, &WriteOptions::default()).unwrap();
    let recipe = dir.path().join("r.toml");
    std::fs::write(
        &recipe,
        "[[periodic]]\nmaster = [14]\nslave = [12]\ntranslation = [1, 0]\n\n\
         [[periodic]]\nmaster = [11]\nslave = [14]\ncentre = [0, 0]\nangle = 90\n",
    )
    .unwrap();
    let out = dir.path().join("out.msh");
    let layer = |curves: &str, recipe: &Path| {
        smartmesh(
            &[
                "layer",
                input.to_str().unwrap(),
                "--curves",
                curves,
                "--first-height",
                "0.01",
                "--ratio",
                "1.2",
                "--layers",
                "3",
                "--recipe",
                recipe.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ],
            None,
        )
    };
    // The bottom wall ends on the left and right sides (the translated pair) alike; the
    // right and top walls end on the bottom at (1, 0) and on the left at (0, 1), images
    // by the quarter turn.
    let translated = dir.path().join("translated.toml");
    std::fs::write(
        &translated,
        "[[periodic]]\nmaster = [14]\nslave = [12]\ntranslation = [1, 0]\n",
    )
    .unwrap();
    let turned = dir.path().join("turned.toml");
    std::fs::write(
        &turned,
        "[[periodic]]\nmaster = [11]\nslave = [14]\ncentre = [0, 0]\nangle = 90\n",
    )
    .unwrap();
    for (curves, recipe, pair) in
        [("11", &translated, left_right()), ("12,13", &turned, bottom_left())]
    {
        let run = layer(curves, recipe);
        ok(&run);
        assert!(stderr(&run).contains("(matched)"), "{}", stderr(&run));
        let mesh = read_path(&out, None).unwrap();
        assert!(mesh.num_cells_of(smartmesh::formats::CellKind::Quad) >= 12);
        assert_eq!(assert_matched(&mesh, &pair), 8, "{curves}");
    }
    let mesh = read_path(&out, None).unwrap();
    match_by_lines(&mesh, 11, 14, |p| [-p[1], p[0]]);
    // The bottom wall slides up the left side, which the quarter turn pairs with the
    // bottom, where nothing slides: refused, nothing written.
    std::fs::remove_file(&out).unwrap();
    let e = bad(&layer("11", &recipe));
    assert!(
        e.contains("periodic master 11 and slave 14")
            && e.contains("the skin's side slides along one periodic side and not alike")
            && e.contains("0 vertices more on the master side, 3 on the slave side"),
        "{e}"
    );
    assert!(!out.exists());
    // Sides that are not images: exit 2 naming the pair.
    let shifted = dir.path().join("shifted.toml");
    std::fs::write(&shifted, "[[periodic]]\nmaster = [14]\nslave = [12]\ntranslation = [0.9, 0]\n")
        .unwrap();
    let e = bad(&layer("11", &shifted));
    assert!(e.contains("periodic pair master 14 and slave 12: the sides are not images"), "{e}");
}

/// A periodic side finer than the metric loses vertices, each with its image: on a grid
/// of 16 edges a side and a uniform size of 1/4, the greedy collapse leaves edges of
/// exactly 1/4 (4 per side, 5 vertices), matched to 1e-12, every triangle positive.
#[test]
fn the_remesher_coarsens_periodic_sides_alike() {
    let mesh = SquareGrid {
        n: 16,
        sides: [11, 12, 13, 14],
        faces: [1, 1],
        interface: None,
        alternate: true,
    }
    .build();
    let t = smartmesh::SizeTensor::from_angle(0.0, 0.25, 0.25).unwrap();
    let metric = vec![t.to_metric(); mesh.points.len()];
    for (pair, map) in [
        (left_right(), (|p: [f64; 2]| [p[0] + 1.0, p[1]]) as fn([f64; 2]) -> [f64; 2]),
        (bottom_left(), |p: [f64; 2]| [-p[1], p[0]]),
    ] {
        assert_eq!(assert_matched(&mesh, &pair), 17);
        // The library step alone: 5 vertices a side, the kept ones where they were.
        let (coarse, m) =
            smartmesh::periodic::coarsen_sides(&mesh, &metric, std::slice::from_ref(&pair));
        assert_eq!(m.len(), coarse.points.len());
        assert_eq!(assert_matched(&coarse, &pair), 5);
        for (kind, nodes, _, _) in coarse.cells() {
            if kind == smartmesh::formats::CellKind::Triangle {
                let p: Vec<[f64; 3]> = nodes.iter().map(|&v| coarse.points[v as usize]).collect();
                let area = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1])
                    - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
                assert!(area > 0.0, "{p:?}");
            }
        }
        // Through the remesher: the same 5, matched, the twin agreeing.
        let opts = RemeshOptions { periodic: vec![pair.clone()], ..Default::default() };
        let out = remesh(&mesh, &metric, &opts).expect("remeshes").mesh;
        assert_eq!(assert_matched(&out, &pair), 5);
        // The stretched triangles the collapses leave inside are remeshed away (34 degrees
        // measured).
        assert!(smallest_angle(&out) > 25.0, "{}", smallest_angle(&out));
        let tag = |e: &EntityRef| match e {
            EntityRef::Tag(t) => *t,
            EntityRef::Name(n) => panic!("a tag, not the name {n}"),
        };
        let tags: (i32, i32) = (tag(&pair.master[0]), tag(&pair.slave[0]));
        match_by_lines(&out, tags.0, tags.1, map);
    }
}
