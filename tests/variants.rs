//! `smartmesh variants`: NACA 4-digit families against the tabulated NACA 0012 and an
//! independent evaluation of the 4-digit formulas; the symmetric member and the three
//! distributors are the committed example geometries; every member meshes, with the
//! example's tags; a batch over a small family succeeds with one recipe; bad parameters
//! exit 2 and write nothing.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/examples.rs"]
#[allow(dead_code)]
mod support;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use cli::{bad, ok, smartmesh, streams};
use serde_json::Value;
use smartmesh::formats::read_path;
use smartmesh::Topology;
use support::examples;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Writes a family into `dir` and returns the manifest's lines.
fn variants(args: &[&str], dir: &Path) -> Vec<Value> {
    let mut a = args.to_vec();
    a.extend(["-o", s(dir)]);
    ok(&smartmesh(&a, None));
    std::fs::read_to_string(dir.join("manifest.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// The vertices of a `.poly` and their markers.
fn poly_vertices(path: &Path) -> Vec<([f64; 2], i64)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#') && !l.trim().is_empty());
    let n: usize = lines.next().unwrap().split_whitespace().next().unwrap().parse().unwrap();
    (0..n)
        .map(|_| {
            let f: Vec<&str> = lines.next().unwrap().split_whitespace().collect();
            ([f[1].parse().unwrap(), f[2].parse().unwrap()], f[3].parse().unwrap())
        })
        .collect()
}

/// The records of a `.poly` (its lines that are not comments), each as its numbers.
/// `smartmesh variants` writes through the formats crate's Triangle writer (`0.0`,
/// `0.00003531094955`, `100.0 -1.0`), the committed examples come from Python's `%.10g`
/// (`0`, `3.531094955e-05`, `100 -1`): the same values, spelled differently.
fn records(path: &Path) -> Vec<Vec<f64>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().map(|t| t.parse().unwrap()).collect())
        .collect()
}

/// The NACA 4-digit profile, written here from its definition (Abbott & von Doenhoff
/// 6.4) independently of `smartmesh::batch::variants::naca`: (upper, lower) at station x.
fn naca_twin(t: f64, m: f64, p: f64, a4: f64, x: f64) -> ([f64; 2], [f64; 2]) {
    let yt = t / 0.2
        * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x.powi(2)
            + 0.2843 * x.powi(3)
            + a4 * x.powi(4));
    let (yc, dyc) = if m == 0.0 {
        (0.0, 0.0)
    } else if x <= p {
        (m * x / (p * p) * (2.0 * p - x), 2.0 * m * (p - x) / (p * p))
    } else {
        (
            m * (1.0 - x) / ((1.0 - p) * (1.0 - p)) * (1.0 + x - 2.0 * p),
            2.0 * m * (p - x) / ((1.0 - p) * (1.0 - p)),
        )
    };
    let k = 1.0 / (1.0 + dyc * dyc).sqrt(); // cos(atan(dyc)); sin = dyc k
    ([x - yt * dyc * k, yc + yt * k], [x + yt * dyc * k, yc - yt * k])
}

/// The surface's y at abscissa `x` on the polyline of vertices `first..last` (in
/// order of x), linearly interpolated.
fn y_at(vs: &[[f64; 2]], x: f64) -> f64 {
    let w = vs.windows(2).find(|w| w[0][0] <= x && x <= w[1][0]).expect("x within the chord");
    w[0][1] + (w[1][1] - w[0][1]) * (x - w[0][0]) / (w[1][0] - w[0][0])
}

#[test]
fn naca_members_follow_the_formula_and_the_tabulated_thickness() {
    let d = tempfile::tempdir().unwrap();
    let recipe = examples().join("naca0012-agard01/recipe.toml");
    for (te, a4, chord) in [("extended", -0.1015, 1.008930411), ("closed", -0.1036, 1.0)] {
        let out = d.path().join(te);
        let lines = variants(
            &[
                "variants",
                "naca",
                "--thickness",
                "0.06:0.18:3",
                "--camber",
                "0,0.04",
                "--camber-position",
                "0.3,0.6",
                "--trailing-edge",
                te,
                "--per-side",
                "60",
                "-r",
                s(&recipe),
            ],
            &out,
        );
        // 3 thicknesses x (no camber, camber at two positions).
        assert_eq!(lines.len(), 9);
        for line in &lines {
            let name = line["name"].as_str().unwrap();
            let (t, m, p) = {
                let mut t = 0.0;
                let mut m = 0.0;
                let mut p = 0.0;
                for part in name.trim_start_matches("naca-").split('-') {
                    let v: f64 = part[1..].parse().unwrap();
                    match &part[..1] {
                        "t" => t = v,
                        "m" => m = v,
                        "p" => p = v,
                        _ => panic!("{name}"),
                    }
                }
                (t, m, p)
            };
            let vs = poly_vertices(&out.join(line["input"].as_str().unwrap()));
            // 2 points, 59 inner vertices a side, 48 on the far field.
            assert_eq!(vs.len(), 2 + 2 * 59 + 48, "{name}");
            assert_eq!(vs[0], ([0.0, 0.0], 11), "{name}: the leading edge");
            let c = vs[1].0[0];
            assert!((c - chord).abs() < 1e-9, "{name}: chord {c}");
            assert_eq!(vs[1].1, 12);
            let (te_up, _) = naca_twin(t, m, p, a4, c);
            assert!((vs[1].0[1] - te_up[1]).abs() < 1e-9, "{name}: the trailing edge");
            let upper: Vec<[f64; 2]> = vs[2..61].iter().map(|v| v.0).collect();
            let lower: Vec<[f64; 2]> = vs[61..120].iter().map(|v| v.0).collect();
            for k in 1..60 {
                let x = c * (1.0 - (std::f64::consts::PI * k as f64 / 60.0).cos()) / 2.0;
                let (u, l) = naca_twin(t, m, p, a4, x);
                for (got, want) in [(upper[k - 1], u), (lower[k - 1], l)] {
                    assert!(
                        (got[0] - want[0]).abs() < 1e-9 && (got[1] - want[1]).abs() < 1e-9,
                        "{name}: station {k}: {got:?} against {want:?}"
                    );
                    assert_eq!(vs[1 + k].1, 0);
                }
            }
            // The written polygon against the tabulated NACA 0012 (Abbott & von
            // Doenhoff, appendix I): thickness 2 x 6.002 % at 30 % of the chord and
            // 2 x 4.683 % at 10 %, scaled by t / 0.12 (polyline interpolation: 1e-4).
            if m == 0.0 {
                for (x, half) in [(0.3, 0.06002), (0.1, 0.04683)] {
                    let th = y_at(&upper, x) - y_at(&lower, x);
                    let want = 2.0 * half * t / 0.12;
                    assert!((th - want).abs() < 2e-4 * t / 0.12 + 1e-5, "{name}: {th} at {x}");
                }
            } else {
                // At x = p the camber line is flat: the mean of both surfaces is m.
                let mean = (y_at(&upper, p) + y_at(&lower, p)) / 2.0;
                assert!((mean - m).abs() < 2e-4, "{name}: mean line {mean} at p");
            }
        }
    }
}

#[test]
fn the_symmetric_member_and_the_distributors_are_the_example_geometries() {
    let d = tempfile::tempdir().unwrap();
    let naca = d.path().join("naca");
    let recipe = examples().join("naca0012-agard01/recipe.toml");
    let lines = variants(&["variants", "naca", "--recipe", s(&recipe)], &naca);
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0]["name"], "naca-t0.12-m0");
    assert_eq!(
        records(&naca.join("naca-t0.12-m0.poly")),
        records(&examples().join("naca0012-agard01/geometry.poly")),
        "NACA 0012: every vertex, segment, hole and region as in the example"
    );
    let dist = d.path().join("dist");
    let recipe = examples().join("distributor/recipe.cfg");
    let lines = variants(&["variants", "distributor", "--recipe", s(&recipe)], &dist);
    let names: Vec<&str> = lines.iter().map(|l| l["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["1-narrow", "2-thick", "3-s-shaped"]);
    for name in names {
        // The committed file but for the line naming its writer and the spelling of the
        // numbers: the same comments, the same records value for value.
        let ours_path = dist.join(format!("{name}.poly"));
        let theirs_path = examples().join(format!("distributor/{name}/geometry.poly"));
        let ours = std::fs::read_to_string(&ours_path).unwrap();
        let theirs = std::fs::read_to_string(&theirs_path).unwrap();
        let comments = |t: &str| {
            t.lines()
                .filter(|l| l.starts_with('#') && !l.starts_with("# Written by "))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(comments(&ours), comments(&theirs), "{name}");
        assert_eq!(records(&ours_path), records(&theirs_path), "{name}");
        assert!(ours.lines().nth(1).unwrap().contains("smartmesh variants"));
        // Ours is what the formats crate writes: the region's attribute and bound are
        // reals, as every number of the file.
        assert!(ours.ends_with(" 1000.0 -1.0\n"), "{name}");
    }
    let only = d.path().join("only");
    let lines =
        variants(&["variants", "distributor", "--only", "2-thick", "--recipe", s(&recipe)], &only);
    assert_eq!(lines.len(), 1);
}

/// Points, curves and faces of a mesh's topology, by tag.
fn tags(mesh: &Path) -> BTreeSet<String> {
    let m = read_path(mesh, None).unwrap();
    let t = Topology::from_mesh(&m);
    let mut out = BTreeSet::new();
    out.extend(t.points.iter().filter(|p| p.tag.is_some()).map(|p| format!("point {:?}", p.tag)));
    out.extend(t.curves.iter().map(|c| format!("curve {:?}", c.tag)));
    out.extend(t.faces.iter().map(|f| format!("face {}", f.tag)));
    out
}

/// Meshes `poly` into `dir` (never beside a committed file).
fn mesh(poly: &Path, dir: &Path) -> PathBuf {
    let stem = poly.parent().unwrap().file_name().unwrap().to_string_lossy().into_owned()
        + "-"
        + &poly.file_stem().unwrap().to_string_lossy();
    let msh = dir.join(stem + ".msh");
    ok(&smartmesh(&["mesh", s(poly), "-o", s(&msh), "-q"], None));
    msh
}

#[test]
fn every_member_meshes_with_the_tags_of_its_example() {
    let d = tempfile::tempdir().unwrap();
    let naca_recipe = examples().join("naca0012-agard01/recipe.toml");
    let lines = variants(
        &[
            "variants",
            "naca",
            "--thickness",
            "0.04,0.12,0.3",
            "--camber",
            "0,0.02,0.09",
            "--camber-position",
            "0.3,0.7",
            "--recipe",
            s(&naca_recipe),
            "--options",
            r#"{"max_iterations": 3}"#,
        ],
        d.path(),
    );
    assert_eq!(lines.len(), 15);
    let want = tags(&mesh(&examples().join("naca0012-agard01/geometry.poly"), d.path()));
    assert!(want.len() >= 6, "{want:?}");
    for line in &lines {
        assert_eq!(line["options"]["max_iterations"], 3);
        // The recipe named relative to the manifest's folder.
        let r = d.path().join(line["recipe"].as_str().unwrap());
        assert_eq!(r.canonicalize().unwrap(), naca_recipe.canonicalize().unwrap());
        let poly = d.path().join(line["input"].as_str().unwrap());
        assert_eq!(tags(&mesh(&poly, d.path())), want, "{}", line["name"]);
        // The example's recipe resolves on every member.
        ok(&smartmesh(&["recipe", "check", s(&naca_recipe), s(&poly)], None));
    }
    let dist = d.path().join("dist");
    let recipe = examples().join("distributor/recipe.cfg");
    variants(&["variants", "distributor", "--recipe", s(&recipe)], &dist);
    let want = tags(&mesh(&examples().join("distributor/1-narrow/geometry.poly"), d.path()));
    for v in ["1-narrow", "2-thick", "3-s-shaped"] {
        assert_eq!(tags(&mesh(&dist.join(format!("{v}.poly")), d.path())), want, "{v}");
    }
}

#[test]
fn a_batch_over_a_small_family_succeeds_with_one_recipe() {
    // A coarse recipe on the example's region names and tags, so that the debug build
    // adapts three members in seconds.
    let d = tempfile::tempdir().unwrap();
    let recipe = d.path().join("coarse.toml");
    std::fs::write(
        &recipe,
        r#"[global]
hmin = 0.002
hmax = 4.0
gradation = 1.5

[regions]
Airfoil = [1, 2]
LeadingEdge = [11]
TrailingEdge = [12]
Fluid = [100]

[functions.Wall]
kind = "distance"
size_at_source = 0.02
size_at_max_distance = 4.0
max_distance = 20.0
exponent = 1.0

[functions.Edge]
kind = "distance"
size_at_source = 0.005
size_at_max_distance = 0.02
max_distance = 0.1
exponent = 1.0

[[algorithms]]
type = "uniform"
size = 4.0
regions = ["Fluid"]

[[algorithms]]
type = "distance_to_border"
perpendicular = "Wall"
parallel = "Wall"
regions = ["Airfoil"]

[[algorithms]]
type = "distance_to_point"
function = "Edge"
regions = ["LeadingEdge", "TrailingEdge"]
"#,
    )
    .unwrap();
    let family = d.path().join("family");
    let lines = variants(
        &[
            "variants",
            "naca",
            "--thickness",
            "0.08,0.16",
            "--camber",
            "0,0.05",
            "--camber-position",
            "0.5",
            "--trailing-edge",
            "closed",
            "--recipe",
            s(&recipe),
        ],
        &family,
    );
    assert_eq!(lines.len(), 4);
    let out = d.path().join("runs");
    let o = smartmesh(
        &["batch", s(&family.join("manifest.jsonl")), "-o", s(&out), "--jobs", "2"],
        None,
    );
    ok(&o);
    let records: Vec<Value> = std::fs::read_to_string(out.join("results.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(records.len(), 4, "{}", streams(&o));
    let want = tags(&mesh(&family.join("naca-t0.08-m0.poly"), d.path()));
    for r in &records {
        assert_eq!(r["status"], "ok", "{r}");
        assert!(r["conformity"].as_f64().unwrap() > 0.85, "{r}");
        let adapted = out.join(r["output"].as_str().unwrap());
        assert_eq!(tags(&adapted), want, "{}", r["name"]);
    }
}

#[test]
fn bad_parameters_exit_2_and_write_nothing() {
    let d = tempfile::tempdir().unwrap();
    let recipe = examples().join("naca0012-agard01/recipe.toml");
    let out = d.path().join("out");
    let cases: &[(&[&str], &str)] = &[
        (&["--thickness", "0"], "thickness 0"),
        // Surfaces 1e-300 apart: `mesh` cannot tell them apart.
        (&["--thickness", "1e-300"], "expected 0.0001 <= t <= 0.5"),
        // Caps are checked on counts, before anything is built: 10^9 combinations, and
        // 1000 members of 300 048 vertices each.
        (
            &[
                "--thickness",
                "0.01:0.5:1000",
                "--camber",
                "0.01:0.2:1000",
                "--camber-position",
                "0.1:0.9:1000",
            ],
            "1000000000 members: at most 100000",
        ),
        (
            &["--thickness", "0.01:0.5:1000", "--per-side", "100000", "--far-points", "100000"],
            "300000000 vertices, at most 20000000",
        ),
        (&["--thickness", "0.1:0.2:0"], "no value"),
        (&["--thickness", "abc"], "not a number"),
        (&["--camber", "0.02", "--camber-position", "1"], "camber position"),
        (&["--per-side", "3"], "segments a side"),
        (&["--far-radius", "1"], "far-field radius"),
        (&["--options", "[1]"], "JSON object"),
        (&["--options", r#"{"hmin": "small"}"#], "option `hmin` must be a number"),
        (&["--options", r#"{"hmn": 1}"#], "did you mean"),
        // A thick profile on a camber this strong this close to the nose folds over.
        (&["--thickness", "0.3", "--camber", "0.2", "--camber-position", "0.05"], "cross"),
    ];
    for (extra, want) in cases {
        let mut a = vec!["variants", "naca", "-r", s(&recipe), "-o", s(&out)];
        a.extend_from_slice(extra);
        let start = std::time::Instant::now();
        let e = bad(&smartmesh(&a, None));
        assert!(e.contains(want), "{extra:?}: {e}");
        assert!(!out.exists(), "{extra:?}: wrote something");
        assert!(start.elapsed().as_secs() < 20, "{extra:?}: {:?}", start.elapsed());
    }
    // The largest layout of one member is checked (its crossings by a sweep) in moments.
    let big = d.path().join("big");
    let start = std::time::Instant::now();
    ok(&smartmesh(
        &["variants", "naca", "--per-side", "100000", "--far-points", "100000"]
            .iter()
            .chain(&["-r", s(&recipe), "-o", s(&big)])
            .copied()
            .collect::<Vec<_>>(),
        None,
    ));
    assert!(start.elapsed().as_secs() < 60, "{:?}", start.elapsed());
    // Legal but sharp: strong camber near the nose turns the boundary by more than
    // `mesh`'s corner angle between two stations, which is said.
    let sharp = d.path().join("sharp");
    let o = smartmesh(
        &["variants", "naca", "--thickness", "0.3", "--camber", "0.09", "--camber-position", "0.1"]
            .iter()
            .chain(&["-r", s(&recipe), "-o", s(&sharp)])
            .copied()
            .collect::<Vec<_>>(),
        None,
    );
    ok(&o);
    assert!(
        streams(&o).contains("warning: naca-t0.3-m0.09-p0.1: the boundary turns by"),
        "{}",
        streams(&o)
    );
    let e = bad(&smartmesh(
        &["variants", "naca", "-r", s(&d.path().join("none.toml")), "-o", s(&out)],
        None,
    ));
    assert!(e.contains("none.toml"), "{e}");
    let e = bad(&smartmesh(
        &["variants", "distributor", "--only", "4-wide", "-r", s(&recipe), "-o", s(&out)],
        None,
    ));
    assert!(e.contains("1-narrow, 2-thick, 3-s-shaped"), "{e}");
    assert!(!out.exists());
}
