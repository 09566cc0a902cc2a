//! The command-line contract: exit codes, what goes to stdout and stderr, files
//! written or not written.

use std::process::Stdio;

#[path = "support/cli.rs"]
mod cli;
use cli::{fixture, program, run, stderr, stdout};
use smartmesh_test_support::formats::public_fixtures;

fn public(rel: &str) -> std::path::PathBuf {
    public_fixtures().join(rel)
}

#[test]
fn help_and_version_exit_zero() {
    let o = run(&["--help"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(stdout(&o).contains("convert"));
    let o = run(&["convert", "--help"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(stdout(&o).contains("Examples:"));
    let o = run(&["--version"]);
    assert_eq!(o.status.code(), Some(0));
}

#[test]
fn bad_usage_exits_two() {
    let o = run(&["convert"]);
    assert_eq!(o.status.code(), Some(2));
    let o = run(&["frobnicate"]);
    assert_eq!(o.status.code(), Some(2));
    let o = run(&["info", "--from", "pdf", "x"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("unknown format"));
}

#[test]
fn missing_file_exits_two_and_names_it() {
    let o = run(&["info", "no/such/mesh.msh"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no/such/mesh.msh"), "{}", stderr(&o));
}

#[test]
fn unknown_extension_asks_for_from() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("mesh.xyz");
    std::fs::write(&p, "hello").unwrap();
    let o = run(&["info", p.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--from"), "{}", stderr(&o));
}

#[test]
fn info_on_the_bundled_example() {
    let o = run(&["info", fixture("cylinder.msh").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s = stdout(&o);
    for name in
        ["\"Inlet\"", "\"Outlet\"", "\"Walls\"", "\"Cylinder\"", "\"Fluid\"", "\"Stagnation\""]
    {
        assert!(s.contains(name), "info should list {name}:\n{s}");
    }
    assert!(s.contains("quality"), "{s}");
}

#[test]
fn info_json_is_machine_readable() {
    let o = run(&["info", "--json", fixture("cylinder.msh").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("valid JSON");
    assert!(v["points"].as_u64().unwrap() > 100);
    let curves = v["topology"]["curves"].as_array().unwrap();
    let cyl = curves.iter().find(|c| c["name"] == "Cylinder").expect("Cylinder curve");
    // The cylinder is one closed loop of four arcs under one tag: with the Stagnation
    // point listed on it, the loop is one piece that starts and ends there.
    assert_eq!(cyl["pieces"], 1);
    let faces = v["topology"]["faces"].as_array().unwrap();
    assert_eq!(faces.len(), 1);
    // Area of the channel minus the disc (the disc is polygonal, so slightly larger area).
    let area = faces[0]["area"].as_f64().unwrap();
    let exact = 4.0 - std::f64::consts::PI * 0.15 * 0.15;
    assert!((area - exact).abs() < 2e-3, "area {area} vs {exact}");
    assert_eq!(v["quality"]["inverted_or_flat"], 0);
}

#[test]
fn convert_chain_keeps_tags_and_names() {
    let dir = tempfile::tempdir().unwrap();
    let src = fixture("cylinder.msh");
    let mut prev = src.clone();
    // Gmsh -> VTU -> legacy VTK -> Gmsh 2.2 binary -> Medit -> Gmsh 4.1: the face and
    // curve cell counts per tag must survive every hop that can hold them.
    let before = run(&["info", "--json", src.to_str().unwrap()]);
    let before: serde_json::Value = serde_json::from_slice(&before.stdout).unwrap();
    for (name, extra) in [
        ("a.vtu", vec![]),
        ("b.vtk", vec!["--binary"]),
        ("c.msh", vec!["--gmsh-version", "2.2", "--binary"]),
        ("d.msh", vec![]),
    ] {
        let out = dir.path().join(name);
        let mut args = vec!["convert", prev.to_str().unwrap(), out.to_str().unwrap()];
        args.extend(extra);
        let o = run(&args);
        assert_eq!(o.status.code(), Some(0), "{name}: {}", stderr(&o));
        prev = out;
    }
    let after = run(&["info", "--json", prev.to_str().unwrap()]);
    let after: serde_json::Value = serde_json::from_slice(&after.stdout).unwrap();
    assert_eq!(before["points"], after["points"]);
    assert_eq!(before["cells"], after["cells"]);
    let tags = |v: &serde_json::Value| -> Vec<(u64, i64, u64)> {
        v["tags"]
            .as_array()
            .unwrap()
            .iter()
            .map(|t| {
                (
                    t["dim"].as_u64().unwrap(),
                    t["tag"].as_i64().unwrap(),
                    t["cells"].as_u64().unwrap(),
                )
            })
            .collect()
    };
    assert_eq!(tags(&before), tags(&after));
}

#[test]
fn lossy_conversion_says_what_was_dropped() {
    smartmesh_test_support::require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("naca.obj");
    let o = run(&[
        "convert",
        public("vtk/naca0012_ascii.vtu").to_str().unwrap(),
        out.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("metric"), "dropping the metric must be reported: {}", stderr(&o));
    let o = run(&[
        "convert",
        "--json",
        public("vtk/naca0012_ascii.vtu").to_str().unwrap(),
        out.to_str().unwrap(),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(!v["dropped"].as_array().unwrap().is_empty());
}

#[test]
fn malformed_input_exits_two_with_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.msh");
    std::fs::write(&p, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n2 1 0 2\n1\n2\n0.0 0.0 0.0\nnan 1.0 0.0\n$EndNodes\n").unwrap();
    let out = dir.path().join("out.vtu");
    let o = run(&["convert", p.to_str().unwrap(), out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("bad.msh:"), "{e}");
    assert!(!out.exists(), "no output may be left behind");
    let leftovers: Vec<_> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers.len(), 1, "only the input remains: {leftovers:?}");
}

#[test]
fn stdin_to_stdout() {
    let bytes = std::fs::read(fixture("cylinder.msh")).unwrap();
    let mut child = cli::command(&["convert", "--from", "msh", "--to", "vtk", "-", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    {
        use std::io::Write;
        child.stdin.take().unwrap().write_all(&bytes).unwrap();
    }
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(o.stdout.starts_with(b"# vtk DataFile Version"));
}

#[test]
fn stdout_needs_a_format() {
    let o = run(&["convert", fixture("cylinder.msh").to_str().unwrap(), "-"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--from/--to"), "{}", stderr(&o));
}

#[test]
fn output_is_deterministic() {
    let dir = tempfile::tempdir().unwrap();
    let mut outputs = Vec::new();
    for ext in ["msh", "vtu", "vtk", "mesh", "obj", "node", "glb"] {
        let a = dir.path().join(format!("a.{ext}"));
        let b = dir.path().join(format!("b.{ext}"));
        for p in [&a, &b] {
            let o =
                run(&["convert", fixture("cylinder.msh").to_str().unwrap(), p.to_str().unwrap()]);
            assert_eq!(o.status.code(), Some(0), "{ext}: {}", stderr(&o));
        }
        assert_eq!(
            std::fs::read(&a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{ext} output differs between runs"
        );
        outputs.push(ext);
    }
    assert_eq!(outputs.len(), 7);
}

#[test]
fn convert_refuses_to_rewrite_its_input_in_place() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mesh = d.join("a.msh");
    std::fs::copy(fixture("cylinder.msh"), &mesh).unwrap();
    let before = std::fs::read(&mesh).unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    std::fs::hard_link(&mesh, d.join("hard.msh")).unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(&mesh, d.join("soft.msh")).unwrap();
    let spellings = [
        mesh.clone(),
        d.join("sub/../a.msh"),
        d.join("./a.msh"),
        d.join("hard.msh"),
        #[cfg(unix)]
        d.join("soft.msh"),
    ];
    for out in &spellings {
        let o = run(&["convert", mesh.to_str().unwrap(), out.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "{}: {}", out.display(), stderr(&o));
        assert!(stderr(&o).contains("the same file"), "{}", stderr(&o));
        assert_eq!(std::fs::read(&mesh).unwrap(), before, "{} rewrote the input", out.display());
    }
    // A copy is another file: converted over as asked.
    let copy = d.join("copy.msh");
    std::fs::copy(&mesh, &copy).unwrap();
    let o = run(&["convert", mesh.to_str().unwrap(), copy.to_str().unwrap(), "--msh2"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn info_and_notes_print_numbers_and_counts_as_read() {
    let dir = tempfile::tempdir().unwrap();
    let vtk = dir.path().join("t.vtk");
    std::fs::write(
        &vtk,
        "# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n\
         -0.0 -0.0 0\n1 0 0\n0 0.07441600000000001 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n\
         POINT_DATA 3\nSCALARS s double 1\nLOOKUP_TABLE default\n0.1 0.30000000000000004 -0.0\n",
    )
    .unwrap();
    let o = run(&["info", vtk.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("bounds      x [0, 1]  y [0, 0.074416]"), "{text}");
    assert!(text.contains("s (1 component) in [0, 0.3]"), "{text}");
    for plural_of_one in [" 1 points", " 1 curves", " 1 faces", " 1 cells,", "1 components"] {
        assert!(!text.contains(plural_of_one), "{plural_of_one}: {text}");
    }
    assert!(!text.contains("-0") && !text.contains("00000"), "{text}");
    // The writers' notes: one component is one.
    let o = run(&["convert", vtk.to_str().unwrap(), dir.path().join("t.obj").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("point data `s` (1 component)"), "{}", stderr(&o));
}

#[test]
fn convert_help_s_gmsh_pipe_runs_as_written() {
    // Gmsh writes its log to stdout: `gmsh -2 -o - model.geo` sent the log, not a mesh,
    // down the pipe (and wrote a file named `-`). The help's line, run with a real Gmsh.
    let help = stdout(&run(&["convert", "--help"]));
    let line = help
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with("gmsh "))
        .unwrap_or_else(|| panic!("no gmsh example in convert --help:\n{help}"));
    let Some(gmsh) = program("gmsh") else { return };
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("model.geo"),
        "Point(1) = {0, 0, 0, 0.3}; Point(2) = {1, 0, 0, 0.3}; Point(3) = {1, 1, 0, 0.3};\n\
         Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};\n\
         Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1}; Physical Surface(\"F\") = {1};\n",
    )
    .unwrap();
    let bin = std::path::Path::new(env!("CARGO_BIN_EXE_smartmesh"));
    let script = line
        .replacen("gmsh ", &format!("'{}' ", gmsh.display()), 1)
        .replace("smartmesh ", &format!("'{}' ", bin.display()));
    let o = std::process::Command::new("sh")
        .args(["-c", &script])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{script}: {}", stderr(&o));
    let mesh = smartmesh::formats::read_path(&dir.path().join("out.vtu"), None).unwrap();
    assert!(mesh.num_cells() > 0, "{script}: an empty mesh");
    assert!(!dir.path().join("-").exists(), "{script}: wrote a file named `-`");
}
