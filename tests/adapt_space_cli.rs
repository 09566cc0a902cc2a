//! `smartmesh adapt` on meshes in space: a Gmsh-made cube with named surfaces, curve,
//! point and volume adapted through `mmg3d_O3` to a UNIFORM recipe, checked apart from
//! the library (every tetrahedron positive, the cube's volume, every tag and name back,
//! a history row per iteration, the median edge length over the recipe's size), and
//! Ctrl-C while `mmg3d_O3` or `gmsh` (`--adapter gmsh`) runs (a fake that hangs): exit
//! 130, the history says "interrupted", the program's process group and its temporary
//! directory are gone.
//!
//! Needs Python's `gmsh` and `mmg3d_O3` on PATH for the first (skipped with a message
//! without them, mandatory under CI); the others need only `sh`.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

use smartmesh::formats::{read_path, write_path, CellKind};
use smartmesh_test_support::grid::kuhn_box;
use smartmesh_test_support::space::{gmsh_and_mmg3d, volume6, write_gmsh_cube};

#[path = "support/cli.rs"]
mod support;
use support::{command, run, streams};

/// UNIFORM 0.125 on the volume: the field is 64 I at every vertex.
const UNIFORM: &str = r#"
[global]
h_max = 0.5

[regions]
solid = ["Solid"]

[[algorithms]]
type = "uniform"
regions = ["solid"]
size = 0.125
"#;

#[test]
fn adapt_takes_a_gmsh_cube_through_mmg3d_to_a_uniform_recipe() {
    let Some(py) = gmsh_and_mmg3d() else { return };
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("box.msh");
    write_gmsh_cube(&py, &input, 0.3);
    let recipe = dir.path().join("u.toml");
    std::fs::write(&recipe, UNIFORM).unwrap();
    let out = dir.path().join("adapted.msh");
    let (i, r, o) = (input.to_str().unwrap(), recipe.to_str().unwrap(), out.to_str().unwrap());
    let res = run(&["adapt", i, "-r", r, "-o", o, "--max-iterations", "3", "--json"]);
    assert_eq!(res.status.code(), Some(0), "{}", streams(&res));
    let json: serde_json::Value = serde_json::from_slice(&res.stdout).unwrap();
    assert_eq!(json["adapter"], "mmg3d");
    // A history row per iteration, each with the 3D measures.
    let h: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(dir.path().join("adapted.history.json")).unwrap(),
    )
    .unwrap();
    let rows = h["iterations"].as_array().unwrap();
    assert!(rows.len() >= 2, "{h}");
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row["iteration"], k);
        assert_eq!(row["space"]["cell"], "tetrahedron", "{row}");
    }
    let start = read_path(&input, None).unwrap();
    let mesh = read_path(&out, None).unwrap();
    let best = &rows[h["best_iteration"].as_u64().unwrap() as usize];
    assert_eq!(best["vertices"], mesh.points.len());
    // Every tetrahedron positive, the cube's volume.
    let mut volume = 0.0;
    let mut edges = BTreeSet::new();
    for (k, n, _, _) in mesh.cells() {
        if k == CellKind::Tetra {
            let v = volume6(std::array::from_fn(|i| mesh.points[n[i] as usize])) / 6.0;
            assert!(v > 0.0, "tetrahedron {n:?} has volume {v}");
            volume += v;
            for a in 0..4 {
                for b in a + 1..4 {
                    edges.insert((n[a].min(n[b]), n[a].max(n[b])));
                }
            }
        }
    }
    assert!((volume - 1.0).abs() < 1e-9, "volume {volume}");
    // Every tag and name back.
    let tags = |m: &smartmesh::formats::TaggedMesh| -> BTreeSet<(u8, i32)> {
        m.cells().map(|(k, _, p, _)| (k.dim(), p)).collect()
    };
    assert_eq!(tags(&mesh), tags(&start));
    for (k, name) in
        [(0, "Origin"), (1, "Rim"), (2, "Left"), (2, "Right"), (2, "Walls"), (3, "Solid")]
    {
        assert!(mesh.tag_names.iter().any(|(t, n)| t.0 == k && n == name), "{name} lost");
    }
    assert_eq!(mesh.tag_names, start.tag_names);
    // The median edge length in the field 64 I: |e| / 0.125.
    let mut l: Vec<f64> = edges
        .iter()
        .map(|&(a, b)| {
            let (p, q) = (mesh.points[a as usize], mesh.points[b as usize]);
            (0..3).map(|i| (p[i] - q[i]).powi(2)).sum::<f64>().sqrt() / 0.125
        })
        .collect();
    l.sort_by(f64::total_cmp);
    let median = l[l.len() / 2];
    eprintln!(
        "adapt cube: {} -> {} tetrahedra, median metric length {median:.3}, {}",
        start.num_cells_of(CellKind::Tetra),
        mesh.num_cells_of(CellKind::Tetra),
        h["stopped"]
    );
    assert!((0.7..=1.3).contains(&median), "median metric length {median}");
}

/// Waits until `file` holds a line.
fn wait_for_line(file: &Path, child: &mut std::process::Child) -> String {
    let t = Instant::now();
    loop {
        if let Ok(s) = std::fs::read_to_string(file) {
            if s.ends_with('\n') {
                return s.trim().to_string();
            }
        }
        if let Ok(Some(status)) = child.try_wait() {
            panic!("smartmesh ended ({status}) before its remesher started");
        }
        assert!(t.elapsed() < Duration::from_secs(120), "the remesher did not start");
        std::thread::sleep(Duration::from_millis(20));
    }
}

#[cfg(target_os = "linux")]
#[test]
fn ctrl_c_stops_mmg3d_in_the_loop_and_keeps_the_start() {
    ctrl_c_stops("mmg3d_O3", &[]);
}

#[cfg(target_os = "linux")]
#[test]
fn ctrl_c_stops_gmsh_in_the_loop_and_keeps_the_start() {
    ctrl_c_stops("gmsh", &["--adapter", "gmsh"]);
}

/// Ctrl-C while the remesher `program` (a fake that hangs), chosen by `adapter`, runs
/// on a tetrahedral cube: exit 130, the start kept, the program gone, and no temporary
/// directory left behind.
#[cfg(target_os = "linux")]
fn ctrl_c_stops(program: &str, adapter: &[&str]) {
    use std::os::unix::fs::PermissionsExt;
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("box.msh");
    let mut mesh = kuhn_box(3, [1.0; 3]);
    mesh.tag_names.insert((3, 1), "Solid".into());
    write_path(&input, &mesh, None, &Default::default()).unwrap();
    let recipe = dir.path().join("u.toml");
    std::fs::write(&recipe, UNIFORM).unwrap();
    let pid_file = dir.path().join("remesher.pid");
    let fake = dir.path().join(program);
    std::fs::write(
        &fake,
        format!("#!/bin/sh\necho $$ > '{}'\nwhile :; do sleep 1; done\n", pid_file.display()),
    )
    .unwrap();
    std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).unwrap();
    let out = dir.path().join("o.msh");
    let (i, r, o) = (input.to_str().unwrap(), recipe.to_str().unwrap(), out.to_str().unwrap());
    let mut args = vec!["adapt", i, "-r", r, "-o", o, "--adapter-program", fake.to_str().unwrap()];
    args.extend_from_slice(adapter);
    let mut child = command(&args)
        .env("TMPDIR", &tmp)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let pid = wait_for_line(&pid_file, &mut child);
    assert!(std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap()
        .success());
    let t = Instant::now();
    while child.try_wait().unwrap().is_none() {
        assert!(t.elapsed() < Duration::from_secs(30), "smartmesh still runs after the signal");
        std::thread::sleep(Duration::from_millis(20));
    }
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", streams(&o));
    let h: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("o.history.json")).unwrap())
            .unwrap();
    assert_eq!(h["stopped"], "interrupted", "{h}");
    assert_eq!(h["iterations"].as_array().unwrap().len(), 1, "{h}");
    // The start is the best mesh, written whole.
    assert_eq!(read_path(&out, None).unwrap().points.len(), 64);
    // The remesher's temporary directory is removed.
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().collect();
    assert!(left.is_empty(), "{program}: left in TMPDIR: {left:?}");
    // The fake remesher is gone (a zombie left to an init that does not reap counts).
    let t = Instant::now();
    loop {
        let state = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok();
        let alive =
            state.is_some_and(|s| !s.rsplit_once(')').unwrap().1.trim_start().starts_with('Z'));
        if !alive {
            break;
        }
        assert!(t.elapsed() < Duration::from_secs(5), "{program} ({pid}) lives on");
        std::thread::sleep(Duration::from_millis(20));
    }
}
