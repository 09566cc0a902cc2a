//! The wing3d example in small (examples/wing3d): its `geometry.py` meshes the wing in a
//! box coarser than the example does, and `smartmesh adapt` takes one iteration through
//! `mmg3d_O3` with the example's recipe and options, the growth limited to 1.5 (about
//! 20 s in a debug build). Checked apart from the library: every tetrahedron positive,
//! the fluid's volume (the box less the wing, whose exact volume is computed here), every
//! tag name back, the wing's triangles each the face of one tetrahedron; the recipe's
//! wall size (0.005) along the normal of every wing triangle, up to the gradation; and
//! the example's `figures.py --wall` (the first-cell figures its README prints) against
//! the same measure computed here from the mesh as smartmesh reads it. Also: the script
//! still writes the committed `wake.stl` byte for byte.
//!
//! Needs Python's gmsh, meshio and numpy, and `mmg3d_O3` on PATH (skipped with a message
//! without them, mandatory under CI). The example itself is `bash examples/wing3d/run.sh`.

use std::collections::BTreeMap;
use std::path::Path;

use smartmesh::formats::{read_path, CellKind, TaggedMesh};
use smartmesh_test_support::formats::{python_with, run_python};

#[path = "support/cli.rs"]
mod support;
use support::{program, run, streams};

/// The example's wall size across the wing (recipe.toml, `WallNormal` at 0).
const WALL: f64 = 0.005;

/// NACA 0012 half thickness with the closed trailing edge (geometry.py).
fn half_thickness(x: f64) -> f64 {
    0.6 * (0.2969 * x.sqrt() - 0.1260 * x - 0.3516 * x * x + 0.2843 * x.powi(3)
        - 0.1036 * x.powi(4))
}

/// The wing's exact volume: the section's area times the half span 1.5, plus the
/// rounded tip, half a body of revolution of radius t(x) (midpoint rule, 10^5 steps
/// in s with x = s², where t is smooth).
fn wing_volume() -> f64 {
    let n = 100_000;
    let (mut area, mut cap) = (0.0, 0.0);
    for i in 0..n {
        let s = (i as f64 + 0.5) / n as f64;
        let (x, dx) = (s * s, 2.0 * s / n as f64);
        let t = half_thickness(x);
        area += 2.0 * t * dx;
        cap += std::f64::consts::FRAC_PI_2 * t * t * dx;
    }
    1.5 * area + cap
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// numpy's default quantile (linear between the order statistics).
fn quantile(sorted: &[f64], f: f64) -> f64 {
    let at = f * (sorted.len() - 1) as f64;
    let (i, w) = (at.floor() as usize, at - at.floor());
    if i + 1 < sorted.len() {
        sorted[i] + w * (sorted[i + 1] - sorted[i])
    } else {
        sorted[i]
    }
}

/// The heights of the tetrahedra on the Wing triangles (tag 1) and the sizes the mesh's
/// `metric` asks along each triangle's normal (the mean of its corners' tensors), as
/// figures.py measures them; checks that every tetrahedron is positive on the way and
/// returns the fluid's volume too.
fn wall(mesh: &TaggedMesh) -> (Vec<f64>, Vec<f64>, f64) {
    let p = &mesh.points;
    let metric = &mesh.point_data["metric"];
    assert_eq!(metric.components, 9);
    let mut opposite: BTreeMap<[u32; 3], Vec<u32>> = BTreeMap::new();
    let mut volume = 0.0;
    let mut wing = Vec::new();
    for (kind, n, tag, _) in mesh.cells() {
        match kind {
            CellKind::Tetra => {
                let [a, b, c, d] = [0, 1, 2, 3].map(|i| p[n[i] as usize]);
                let v = dot(sub(b, a), cross(sub(c, a), sub(d, a))) / 6.0;
                assert!(v > 0.0, "tetrahedron {n:?} has volume {v}");
                volume += v;
                for k in 0..4 {
                    let mut f: Vec<u32> = (0..4).filter(|&i| i != k).map(|i| n[i]).collect();
                    f.sort_unstable();
                    opposite.entry([f[0], f[1], f[2]]).or_default().push(n[k]);
                }
            }
            CellKind::Triangle if tag == 1 => wing.push([n[0], n[1], n[2]]),
            _ => {}
        }
    }
    let (mut heights, mut asked) = (Vec::new(), Vec::new());
    for t in wing {
        let mut key = t;
        key.sort_unstable();
        let o = &opposite[&key];
        assert_eq!(o.len(), 1, "wing triangle {t:?} on {} tetrahedra", o.len());
        let [a, b, c] = t.map(|v| p[v as usize]);
        let mut nrm = cross(sub(b, a), sub(c, a));
        let len = dot(nrm, nrm).sqrt();
        nrm = nrm.map(|x| x / len);
        heights.push(dot(sub(p[o[0] as usize], a), nrm).abs());
        let mut m = [0.0; 9];
        for v in t {
            for (k, mk) in m.iter_mut().enumerate() {
                *mk += metric.values[9 * v as usize + k] / 3.0;
            }
        }
        let mn: f64 =
            (0..3).map(|i| nrm[i] * (0..3).map(|j| m[3 * i + j] * nrm[j]).sum::<f64>()).sum();
        asked.push(1.0 / mn.sqrt());
    }
    (heights, asked, volume)
}

#[test]
fn the_wing_example_in_small_through_mmg3d() {
    let Some(py) = python_with(&["gmsh", "meshio", "numpy"]) else { return };
    if program("mmg3d_O3").is_none() {
        return;
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/wing3d");
    let dir = tempfile::tempdir().unwrap();
    let (start, wake) = (dir.path().join("start.msh"), dir.path().join("wake.stl"));
    let script = std::fs::read_to_string(root.join("geometry.py")).unwrap();
    let args = [start.to_str().unwrap(), "--size-wing", "0.15", "--size-far", "1.5", "--wake"];
    run_python(&py, &script, &[&args[..], &[wake.to_str().unwrap()]].concat());
    assert_eq!(
        std::fs::read(&wake).unwrap(),
        std::fs::read(root.join("wake.stl")).unwrap(),
        "geometry.py no longer writes the committed wake.stl"
    );
    let out = dir.path().join("adapted.msh");
    let recipe = root.join("recipe.toml");
    let o = run(&[
        "adapt",
        start.to_str().unwrap(),
        "--recipe",
        recipe.to_str().unwrap(),
        "--hausd",
        "0.001",
        "--adapter-arg=-hgrad",
        "--adapter-arg=-1",
        "--max-iterations",
        "1",
        "--max-growth",
        "1.5",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let h: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("adapted.history.json")).unwrap(),
    )
    .unwrap();
    let rows = h["iterations"].as_array().unwrap();
    assert_eq!(rows.len(), 2, "{h}");
    assert_eq!(h["best_iteration"], 1, "{h}");
    let before = read_path(&start, None).unwrap();
    let mesh = read_path(&out, None).unwrap();
    assert!(mesh.points.len() > before.points.len(), "{h}");
    assert_eq!(mesh.tag_names, before.tag_names);
    for (dim, name) in
        [(1, "TrailingEdge"), (2, "Wing"), (2, "Symmetry"), (2, "Farfield"), (3, "Fluid")]
    {
        assert!(mesh.tag_names.iter().any(|(t, n)| t.0 == dim && n == name), "{name} lost");
    }
    let (heights, asked, volume) = wall(&mesh);
    // The box [-3, 6] x [0, 4] x [-3, 3] less the wing, whose faceted surface MMG keeps
    // within its Hausdorff distance 0.001 of the start's.
    let exact = 216.0 - wing_volume();
    assert!((volume - exact).abs() < 2e-3, "fluid volume {volume}, exact {exact}");
    // The field along each wing triangle's normal: the wall size, smaller only where the
    // gradation or the trailing edge asks for less.
    let mut a = asked.clone();
    a.sort_by(f64::total_cmp);
    assert!(a[a.len() - 1] < WALL * 1.05, "asked up to {}", a[a.len() - 1]);
    assert!(quantile(&a, 0.5) > WALL * 0.8, "asked median {}", quantile(&a, 0.5));
    // figures.py --wall on the .vtu of the same mesh: the same figures.
    let vtu = dir.path().join("adapted.vtu");
    let c = run(&["convert", out.to_str().unwrap(), vtu.to_str().unwrap()]);
    assert_eq!(c.status.code(), Some(0), "{}", streams(&c));
    let figures = std::process::Command::new(&py)
        .arg(root.join("figures.py"))
        .args([dir.path().to_str().unwrap(), "--wall"])
        .output()
        .unwrap();
    assert!(figures.status.success(), "{}", streams(&figures));
    let f: serde_json::Value = serde_json::from_slice(&figures.stdout).unwrap();
    let mut hs = heights.clone();
    hs.sort_by(f64::total_cmp);
    let ratios: Vec<f64> = {
        let mut r: Vec<f64> = heights.iter().zip(&asked).map(|(h, s)| h / s).collect();
        r.sort_by(f64::total_cmp);
        r
    };
    let close = |x: &serde_json::Value, y: f64| {
        let x = x.as_f64().unwrap();
        assert!((x - y).abs() <= 1e-9 * y.abs(), "figures.py {x}, here {y}");
    };
    assert_eq!(f["triangles"], heights.len());
    close(&f["height"]["min"], hs[0]);
    close(&f["height"]["median"], quantile(&hs, 0.5));
    close(&f["height"]["p90"], quantile(&hs, 0.9));
    close(&f["asked"]["median"], quantile(&a, 0.5));
    close(&f["ratio"]["median"], quantile(&ratios, 0.5));
    eprintln!(
        "wing3d small: {} -> {} vertices, first cell {:.4} median where {:.4} is asked",
        before.points.len(),
        mesh.points.len(),
        quantile(&hs, 0.5),
        quantile(&a, 0.5)
    );
}
