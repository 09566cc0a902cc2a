//! The command-line contract shared by every subcommand (issue 17, items 5–10, 14, 20):
//! options as MMG users write them, the output options every writer shares, `-` for
//! stdin and stdout, exit codes, what goes to stderr at each verbosity, Ctrl-C during
//! `adapt`.

#[path = "support/cli.rs"]
mod cli;

use std::path::Path;
use std::process::Stdio;

use cli::{bad, bundled, command, ok, smartmesh, streams};
use smartmesh::formats::{read_path, CellKind};

/// A bundled fixture's path for the lifetime of the test binary.
fn fixture(name: &str) -> &'static str {
    Box::leak(bundled(name).into_boxed_str())
}

fn cyl() -> &'static str {
    fixture("cylinder.msh")
}

fn recipe() -> &'static str {
    fixture("cylinder.toml")
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

#[test]
fn single_dash_options_are_refused_with_the_option_meant() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.msh");
    let sol = dir.path().join("o.sol");
    let cases: Vec<(Vec<&str>, &str, &Path)> = vec![
        (vec!["adapt", cyl(), "-r", recipe(), "-o", p(&out), "-hausd", "0.01"], "--hausd", &out),
        (vec!["size", cyl(), "-r", recipe(), "-o", p(&sol), "-hmin", "0.01"], "--hmin", &sol),
        (vec!["remesh", cyl(), "-o", p(&out), "-hgrad", "1.3"], "--hgrad", &out),
    ];
    let poly = bundled("square_hole.poly");
    let mut cases = cases;
    cases.push((vec!["mesh", &poly, "-o", p(&out), "-hmax", "0.1"], "--hmax", &out));
    for (args, meant, written) in cases {
        let err = bad(&smartmesh(&args, None));
        assert!(err.contains(&format!("did you mean `{meant}`")), "{args:?}: {err}");
        assert!(!written.exists(), "{args:?}: nothing may be written");
    }
    // Any `-h…` word is refused rather than taken for the help (exit 0, nothing done),
    // and names the subcommands that have the option.
    let err = bad(&smartmesh(&["convert", cyl(), p(&out), "-hgrad", "1.3"], None));
    assert!(err.contains("-h` alone prints the help") && err.contains("`size`"), "{err}");
    // `-h` and `--help` still print the help.
    assert!(ok(&smartmesh(&["size", "-h"], None)).contains("--hmin"));
}

#[test]
fn other_tools_one_dash_words_exit_two_naming_the_option_meant() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.mesh");
    let poly = bundled("square_hole.poly");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        // MMG's `-out` was read as `-o ut` (a file `ut` written), `-sol` got clap's tip.
        (vec!["remesh", cyl(), "-out", p(&out)], "`-o` or `--output`"),
        (vec!["remesh", cyl(), "-sol", cyl(), "-o", p(&out)], "`--metric`"),
        (vec!["mesh", &poly, "-o", p(&out), "-pq30a0.01"], "--min-angle 30 --max-area 0.01"),
        (vec!["convert", cyl(), p(&out), "-format", "mesh"], "`--to`"),
    ];
    for (args, meant) in cases {
        let err = bad(&smartmesh(&args, None));
        assert!(err.contains(meant), "{args:?}: {err}");
        assert!(!err.contains("tip:"), "{args:?}: {err}");
        assert!(!out.exists() && !Path::new("ut").exists(), "{args:?}: nothing may be written");
    }
}

/// The `Usage:` line of an error message.
fn usage_line(err: &str) -> String {
    err.lines().find(|l| l.starts_with("Usage:")).unwrap_or_else(|| panic!("{err}")).to_string()
}

#[test]
fn usage_lines_show_optional_flags_as_optional() {
    // An error's usage line is the help's: clap built it from the arguments given
    // (`--metric` shown as required) and from `--output`, which `--measure` makes optional.
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["remesh", cyl(), "--metric", cyl()], "Usage: smartmesh remesh [OPTIONS] <MESH>"),
        (vec!["remesh"], "Usage: smartmesh remesh [OPTIONS] <MESH>"),
        (
            vec!["size", cyl(), "--hmin", "0.1"],
            "Usage: smartmesh size [OPTIONS] --output <OUTPUT> <MESH>",
        ),
        (vec!["convert", "--binary", cyl()], "Usage: smartmesh convert [OPTIONS] <INPUT> <OUTPUT>"),
        (
            vec!["recipe", "check", "--json"],
            "Usage: smartmesh recipe check [OPTIONS] <RECIPE> <MESH>",
        ),
    ];
    for (args, usage) in cases {
        let err = bad(&smartmesh(&args, None));
        assert_eq!(usage_line(&err), usage, "{args:?}: {err}");
    }
    assert!(ok(&smartmesh(&["remesh", "--help"], None))
        .contains("Usage: smartmesh remesh [OPTIONS] <MESH>"));
}

#[test]
fn size_controls_override_the_recipe_and_act_on_a_metric() {
    let dir = tempfile::tempdir().unwrap();
    let field = dir.path().join("f.vtu");
    let json = |extra: &[&str]| -> serde_json::Value {
        let mut args = vec!["size", cyl(), "-r", recipe(), "-o", p(&field), "--json"];
        args.extend(extra);
        serde_json::from_str(&ok(&smartmesh(&args, None))).unwrap()
    };
    let plain = json(&[]);
    assert!(plain["smallest_size"].as_f64().unwrap() < 0.01, "{plain}");
    let bounded = json(&["--hmin", "0.01", "--hmax", "0.05"]);
    assert!((bounded["smallest_size"].as_f64().unwrap() - 0.01).abs() < 1e-9, "{bounded}");
    assert!(bounded["largest_size"].as_f64().unwrap() <= 0.05 + 1e-12, "{bounded}");
    let err = bad(&smartmesh(
        &["size", cyl(), "-r", recipe(), "-o", p(&field), "--hmin", "1", "--hmax", "0.1"],
        None,
    ));
    assert!(err.contains("hmin 1 exceeds hmax 0.1"), "{err}");
    assert!(bad(&smartmesh(
        &["size", cyl(), "-r", recipe(), "-o", p(&field), "--hgrad", "0.5"],
        None
    ))
    .contains("gradation"));

    // remesh: the same controls on the metric it reads; --hausd for the native remesher.
    ok(&smartmesh(&["size", cyl(), "-r", recipe(), "-o", p(&field)], None));
    let remeshed = |extra: &[&str]| -> usize {
        let out = dir.path().join("r.msh");
        let mut args = vec!["remesh", cyl(), "--metric", p(&field), "-o", p(&out)];
        args.extend(extra);
        ok(&smartmesh(&args, None));
        read_path(&out, None).unwrap().points.len()
    };
    let base = remeshed(&[]);
    let coarse = remeshed(&["--hmin", "0.03"]);
    assert!(10 * coarse < 9 * base, "--hmin 0.03: {coarse} vertices, {base} without");
    let fine_wall = remeshed(&["--hausd", "1e-5"]);
    assert!(fine_wall > base, "--hausd 1e-5: {fine_wall} vertices, {base} without");

    // mesh: --hmax is --size, --quality and --area are Triangle's q and a.
    let a = dir.path().join("a.msh");
    let b = dir.path().join("b.msh");
    let poly = bundled("square_hole.poly");
    ok(&smartmesh(&["mesh", &poly, "-o", p(&a), "--hmax", "0.1", "--quality", "25"], None));
    ok(&smartmesh(&["mesh", &poly, "-o", p(&b), "--size", "0.1", "--min-angle", "25"], None));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn every_writer_takes_the_same_output_options() {
    let dir = tempfile::tempdir().unwrap();
    let poly = bundled("square_hole.poly");
    let msh = dir.path().join("m.msh");
    let vtu = dir.path().join("m.vtu");
    let field = dir.path().join("f.msh");
    let head =
        |path: &Path| String::from_utf8_lossy(&std::fs::read(path).unwrap()[..40]).into_owned();
    for (args, file) in [
        (vec!["mesh", poly.as_str(), "-o", p(&msh), "--gmsh-version", "2.2"], &msh),
        (vec!["convert", cyl(), p(&msh), "--msh2"], &msh),
        (vec!["size", cyl(), "-r", recipe(), "-o", p(&field), "--msh2"], &field),
    ] {
        ok(&smartmesh(&args, None));
        assert!(head(file).starts_with("$MeshFormat\n2.2 0 8"), "{args:?}: {}", head(file));
    }
    ok(&smartmesh(
        &["mesh", &poly, "-o", p(&vtu), "--vtu-encoding", "ascii", "--no-compress"],
        None,
    ));
    let text = std::fs::read_to_string(&vtu).unwrap();
    assert!(text.contains("format=\"ascii\""), "{}", &text[..400]);
    let vtk = dir.path().join("m.vtk");
    ok(&smartmesh(&["mesh", &poly, "-o", p(&vtk), "--vtk-version", "5.1"], None));
    assert!(std::fs::read_to_string(&vtk).unwrap().starts_with("# vtk DataFile Version 5.1"));
}

#[test]
fn size_and_adapt_read_and_write_stdio() {
    let dir = tempfile::tempdir().unwrap();
    // size -o - --to sol, and the recipe from stdin.
    let toml = std::fs::read(recipe()).unwrap();
    let mut child =
        command(&["size", cyl(), "-r", "-", "--recipe-format", "toml", "-o", "-", "--to", "sol"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
    {
        use std::io::Write;
        child.stdin.take().unwrap().write_all(&toml).unwrap();
    }
    let o = child.wait_with_output().unwrap();
    let sol = ok(&o);
    assert!(sol.starts_with("MeshVersionFormatted") && sol.contains("SolAtVertices"), "{sol:.200}");
    let err = bad(&smartmesh(&["size", cyl(), "-r", "-", "-o", "x.sol"], None));
    assert!(err.contains("--recipe-format"), "{err}");
    assert!(bad(&smartmesh(&["size", cyl(), "-r", recipe(), "-o", "-"], None)).contains("--to"));

    // adapt -o - --to msh writes the best mesh to stdout; the history needs a file.
    let history = dir.path().join("h.json");
    let args = ["adapt", cyl(), "-r", recipe(), "-o", "-", "--to", "msh", "--max-iterations", "1"];
    let err = bad(&smartmesh(&args, None));
    assert!(err.contains("--history"), "{err}");
    let mut with_history = args.to_vec();
    with_history.extend(["--history", p(&history)]);
    let mesh = ok(&smartmesh(&with_history, None));
    assert!(mesh.starts_with("$MeshFormat\n4.1"), "{mesh:.100}");
    let h: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&history).unwrap()).unwrap();
    let best = &h["iterations"][h["best_iteration"].as_u64().unwrap() as usize];
    let elsewhere = tempfile::tempdir().unwrap();
    let copy = elsewhere.path().join("best.msh");
    std::fs::write(&copy, &mesh).unwrap();
    assert_eq!(
        read_path(&copy, None).unwrap().points.len() as u64,
        best["vertices"].as_u64().unwrap()
    );
    let leftovers: Vec<_> =
        std::fs::read_dir(dir.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(leftovers.len(), 1, "only the history is written: {leftovers:?}");
    assert!(best["vertices"].as_u64().unwrap() > 0);
}

#[test]
fn bad_paths_are_usage_errors_in_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let adir = dir.path().join("adir.msh");
    std::fs::create_dir(&adir).unwrap();
    let err = bad(&smartmesh(&["info", p(&adir)], None));
    assert!(err.contains("adir.msh"), "{err}");
    let nodir = dir.path().join("nodir").join("out.msh");
    for args in [
        vec!["convert", cyl(), p(&nodir)],
        vec!["adapt", cyl(), "-r", recipe(), "-o", p(&nodir)],
        vec!["mesh", fixture("square_hole.poly"), "-o", p(&nodir)],
        vec!["size", cyl(), "-r", recipe(), "-o", dir.path().join("nodir/f.sol").to_str().unwrap()],
    ] {
        let err = bad(&smartmesh(&args, None));
        assert!(err.contains("nodir") && err.contains("does not exist"), "{args:?}: {err}");
    }
}

#[cfg(unix)]
#[test]
fn a_pipe_closed_by_its_reader_ends_the_run_quietly() {
    // The VTK text of the distributor is far larger than a pipe's buffer: the writes
    // after `head` has gone meet a closed pipe.
    let script = format!(
        "'{}' convert '{}' - --to vtk 2>err | head -c 10 >/dev/null; echo ${{PIPESTATUS[0]}}",
        env!("CARGO_BIN_EXE_smartmesh"),
        bundled("distributor.msh")
    );
    let dir = tempfile::tempdir().unwrap();
    let o = std::process::Command::new("bash")
        .arg("-c")
        .arg(&script)
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(String::from_utf8_lossy(&o.stdout).trim(), "0", "{}", streams(&o));
    let err = std::fs::read_to_string(dir.path().join("err")).unwrap();
    assert!(!err.contains("error"), "{err}");
}

#[test]
fn tool_and_switch_names_in_messages_are_the_ones_to_type() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o.msh");
    let o = smartmesh(
        &[
            "adapt",
            cyl(),
            "-r",
            recipe(),
            "-o",
            p(&out),
            "--adapter",
            "mmg2d",
            "--adapter-program",
            "/nonexistent/mmg",
        ],
        None,
    );
    // A program the user names that is missing or cannot be run is bad input (2).
    let err = bad(&o);
    assert!(
        err.contains("`/nonexistent/mmg` does not exist") && !err.contains("not found"),
        "{err}"
    );
    let plain = dir.path().join("plain-mmg");
    std::fs::write(&plain, "not a program\n").unwrap();
    let adapt_with = |program: &str, cwd: &Path| {
        command(&[
            "adapt",
            cyl(),
            "-r",
            recipe(),
            "-o",
            p(&out),
            "--adapter",
            "mmg2d",
            "--adapter-program",
            program,
        ])
        .current_dir(cwd)
        .output()
        .unwrap()
    };
    let err = bad(&adapt_with(p(&plain), dir.path()));
    assert!(err.contains("is not an executable file"), "{err}");
    // `./tool.sh` is the one in the current directory, not in the adapter's temporary one:
    // it runs (and fails, saying so in its own words).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let tool = dir.path().join("tool.sh");
        std::fs::write(&tool, "#!/bin/sh\necho 'tool.sh ran' >&2\nexit 3\n").unwrap();
        std::fs::set_permissions(&tool, std::fs::Permissions::from_mode(0o755)).unwrap();
        let o = adapt_with("./tool.sh", dir.path());
        assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
        assert!(String::from_utf8_lossy(&o.stderr).contains("tool.sh ran"), "{}", streams(&o));
    }
    let dots = dir.path().join("dots.node");
    std::fs::write(&dots, "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n").unwrap();
    let err = bad(&smartmesh(&["mesh", p(&dots), "-o", p(&out)], None));
    assert!(err.contains("--keep-convex-hull"), "{err}");
}

#[test]
fn a_recipe_that_does_not_fit_is_refused_before_the_tool_is_looked_for() {
    let dir = tempfile::tempdir().unwrap();
    let poly = dir.path().join("square.poly");
    std::fs::write(
        &poly,
        "4 2 0 1\n1 0 0 1\n2 1 0 1\n3 1 1 1\n4 0 1 1\n4 1\n1 1 2 1\n2 2 3 2\n3 3 4 1\n4 4 1 1\n0\n",
    )
    .unwrap();
    let out = dir.path().join("o.msh");
    // An empty PATH: no mmg2d_O3 anywhere.
    let o = command(&["adapt", p(&poly), "-r", recipe(), "-o", p(&out), "--adapter", "mmg2d"])
        .env("PATH", "")
        .output()
        .unwrap();
    let err = bad(&o);
    assert!(err.contains("does not have") && !err.contains("mmg2d_O3"), "{err}");
}

#[test]
fn success_is_one_line_on_stderr_and_quiet_is_silent() {
    let dir = tempfile::tempdir().unwrap();
    let field = dir.path().join("f.vtu");
    let out = dir.path().join("o.vtu");
    let poly = bundled("square_hole.poly");
    let runs: Vec<(&str, Vec<&str>)> = vec![
        ("convert", vec!["convert", cyl(), p(&out)]),
        ("mesh", vec!["mesh", poly.as_str(), "-o", p(&out)]),
        ("size", vec!["size", cyl(), "-r", recipe(), "-o", p(&field)]),
        ("remesh", vec!["remesh", cyl(), "--metric", p(&field), "-o", p(&out)]),
        ("adapt", vec!["adapt", cyl(), "-r", recipe(), "-o", p(&out), "--max-iterations", "1"]),
    ];
    for (name, args) in runs {
        let o = smartmesh(&args, None);
        ok(&o);
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        let lines: Vec<&str> =
            err.lines().filter(|l| l.starts_with(&format!("smartmesh: {name}: "))).collect();
        assert_eq!(lines.len(), 1, "{name}: {err}");
        assert!(lines[0].contains("o.vtu") || lines[0].contains("f.vtu"), "{name}: {err}");
        // A .vtu from a .msh keeps the tags; Gmsh's entity table is bookkeeping.
        assert!(!err.contains("not written: entity table"), "{name}: {err}");
        let mut quiet = args.clone();
        quiet.push("-q");
        let o = smartmesh(&quiet, None);
        ok(&o);
        assert!(o.stderr.is_empty(), "{name} -q: {}", streams(&o));
    }
    let o = smartmesh(&["-v", "convert", cyl(), p(&out)], None);
    assert!(String::from_utf8_lossy(&o.stderr).contains("entity table"), "{}", streams(&o));
}

/// The text of a file that may be mid-rename: `None` until it exists whole.
fn read_json(path: &Path) -> Option<serde_json::Value> {
    serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_adapt_with_the_history_and_best_mesh_agreeing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cyl.msh");
    let history = dir.path().join("cyl.history.json");
    let child = command(&[
        "adapt",
        cyl(),
        "-r",
        recipe(),
        "-o",
        p(&out),
        "--max-iterations",
        "40",
        "--tol-vertices",
        "0",
        "--tol-conformity",
        "0",
    ])
    .stdout(Stdio::piped())
    .stderr(Stdio::piped())
    .spawn()
    .unwrap();
    // Wait for iteration 1 to be on disk, then interrupt.
    let t = std::time::Instant::now();
    while read_json(&history).map_or(true, |h| h["iterations"].as_array().unwrap().len() < 2) {
        assert!(t.elapsed().as_secs() < 120, "no iteration 1 after two minutes");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let kill = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(130), "{}", streams(&o));
    let h = read_json(&history).unwrap();
    assert_eq!(h["stopped"], "interrupted", "{h}");
    let best = &h["iterations"][h["best_iteration"].as_u64().unwrap() as usize];
    let mesh = read_path(&out, None).unwrap();
    assert_eq!(mesh.points.len() as u64, best["vertices"].as_u64().unwrap());
    assert_eq!(mesh.num_cells_of(CellKind::Triangle) as u64, best["triangles"].as_u64().unwrap());
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "temporaries left: {names:?}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("interrupted"), "{}", streams(&o));
}

#[cfg(unix)]
#[test]
fn the_adapt_progress_bar_ticks_during_a_long_phase() {
    use std::os::unix::fs::PermissionsExt;
    // util-linux `script` runs the command on a pseudo-terminal: the bar is drawn.
    if cli::program("script").is_none() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    // A remesher that takes 4 s and fails: one long phase with nothing else to redraw.
    let tool = dir.path().join("slow-mmg2d");
    std::fs::write(&tool, "#!/bin/sh\nsleep 4\nexit 3\n").unwrap();
    std::fs::set_permissions(&tool, std::fs::Permissions::from_mode(0o755)).unwrap();
    let out = dir.path().join("cyl.msh");
    let command = format!(
        "'{}' adapt '{}' -r '{}' -o '{}' --adapter mmg2d --adapter-program '{}'",
        env!("CARGO_BIN_EXE_smartmesh"),
        cyl(),
        recipe(),
        p(&out),
        p(&tool)
    );
    let o = std::process::Command::new("script")
        .args(["-qfec", &command, "/dev/null"])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    let screen = String::from_utf8_lossy(&o.stdout).replace('\r', "\n");
    let drawn = |s: u64| screen.contains(&format!("remeshing (mmg2d) [{s}s]"));
    let start = (0..60).find(|&s| drawn(s)).unwrap_or_else(|| panic!("no bar:\n{screen}"));
    // A bar redrawn only when a phase starts shows the phase's first second alone.
    for s in start..start + 3 {
        assert!(drawn(s), "second {s} of the remeshing not drawn:\n{screen}");
    }
}

#[test]
fn hausd_is_an_option_of_every_remesher() {
    let dir = tempfile::tempdir().unwrap();
    let vertices = |extra: &[&str]| -> u64 {
        let out = dir.path().join("a.msh");
        let mut args = vec!["adapt", cyl(), "-r", recipe(), "-o", p(&out), "--max-iterations", "1"];
        args.extend(extra);
        args.push("--json");
        let v: serde_json::Value = serde_json::from_str(&ok(&smartmesh(&args, None))).unwrap();
        v["iterations"][1]["vertices"].as_u64().unwrap()
    };
    // The native remesher: a tight bound along the cylinder (radius 0.15) asks for more
    // vertices there than the recipe does.
    let plain = vertices(&[]);
    let tight = vertices(&["--hausd", "1e-6"]);
    assert!(tight > plain, "--hausd 1e-6: {tight} vertices, {plain} without");
}

#[test]
fn every_command_reads_a_recipe_alike_and_names_its_own_format_flag() {
    let dir = tempfile::tempdir().unwrap();
    let sol = dir.path().join("o.sol");
    let odd = dir.path().join("recipe.txt");
    std::fs::copy(recipe(), &odd).unwrap();
    let out = dir.path().join("r.toml");
    // (arguments before the recipe, the recipe's place holder, arguments after, flag)
    let commands: [(&[&str], &[&str], &str); 3] = [
        (&["size", cyl(), "-o", p(&sol), "-r"], &[], "--recipe-format"),
        (&["recipe", "check"], &[cyl()], "--recipe-format"),
        (&["recipe", "convert"], &[p(&out)], "--from"),
    ];
    let with = |pre: &[&str], recipe: &str, post: &[&str], extra: &[&str]| -> Vec<String> {
        let mut a: Vec<String> = pre.iter().map(|s| s.to_string()).collect();
        a.push(recipe.into());
        a.extend(post.iter().map(|s| s.to_string()));
        a.extend(extra.iter().map(|s| s.to_string()));
        a
    };
    let run = |args: &[String], stdin: &[u8]| {
        let mut child = command(&args.iter().map(String::as_str).collect::<Vec<_>>())
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        {
            use std::io::Write;
            let _ = child.stdin.take().unwrap().write_all(stdin);
        }
        child.wait_with_output().unwrap()
    };
    for (pre, post, flag) in commands {
        // An extension that tells no format: refused, naming this command's flag.
        let err = bad(&run(&with(pre, p(&odd), post, &[]), b""));
        assert!(err.contains("recipe.txt") && err.contains(flag), "{pre:?}: {err}");
        // stdin without a format.
        let err = bad(&run(&with(pre, "-", post, &[]), b""));
        assert!(err.contains("stdin") && err.contains(flag), "{pre:?}: {err}");
        // stdin that is not text: bad input (2) for every command.
        let err = bad(&run(&with(pre, "-", post, &[flag, "toml"]), b"a = \"\xff\xfe\"\n"));
        assert!(err.contains("<stdin>") && err.contains("not UTF-8"), "{pre:?}: {err}");
        // The flag forces a format on the odd extension.
        let o = run(&with(pre, p(&odd), post, &[flag, "toml"]), b"");
        assert_eq!(o.status.code(), Some(0), "{pre:?}: {}", streams(&o));
    }
    // One spelling in every help: `recipe check`'s old `--format` still reads, hidden.
    let o = run(&with(&["recipe", "check"], p(&odd), &[cyl()], &["--format", "toml"]), b"");
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let help = ok(&smartmesh(&["recipe", "check", "--help"], None));
    assert!(help.contains("--recipe-format") && !help.contains("--format"), "{help}");
}

/// Whether the report of `mesh` with `history` says the two do not belong together.
fn report_says_mismatch(mesh: &Path, history: &Path, dir: &Path) -> bool {
    let svg = dir.join("r.svg");
    let o = smartmesh(&["report", p(mesh), "--history", p(history), "-o", p(&svg)], None);
    ok(&o);
    String::from_utf8_lossy(&o.stderr).contains("is not the mesh this history describes")
}

#[cfg(unix)]
#[test]
fn a_killed_adapt_leaves_a_history_that_knows_its_mesh_and_no_temporaries() {
    use smartmesh::{History, WrittenFile};
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cyl.msh");
    let history = dir.path().join("cyl.history.json");
    let adapt = || {
        command(&[
            "adapt",
            cyl(),
            "-r",
            recipe(),
            "-o",
            p(&out),
            "--max-iterations",
            "6",
            "--tol-vertices",
            "0",
            "-q",
        ])
    };
    // SIGKILL at moments spread over a run (about 0.4 s), from a fixed seed.
    let mut seed: u64 = 0x5eed;
    for _ in 0..6 {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        let delay = std::time::Duration::from_millis(30 + (seed >> 33) % 400);
        let mut child = adapt().spawn().unwrap();
        std::thread::sleep(delay);
        let _ = child.kill();
        child.wait().unwrap();
        let (Ok(bytes), Some(text)) = (std::fs::read(&out), std::fs::read_to_string(&history).ok())
        else {
            continue;
        };
        let h = History::from_json(&text).unwrap();
        let agree = h.best_mesh == [WrittenFile::of("cyl.msh", &bytes)];
        // The history names the mesh beside it, or the report says it does not.
        assert_eq!(report_says_mismatch(&out, &history, dir.path()), !agree, "after {delay:?}");
        if agree {
            let mesh = read_path(&out, None).unwrap();
            assert_eq!(mesh.points.len(), h.iterations[h.best_iteration].vertices);
        }
    }
    // A run to the end in the same directory removes what the killed ones left.
    ok(&adapt().output().unwrap());
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "temporaries left: {names:?}");
    assert!(!report_says_mismatch(&out, &history, dir.path()));
    // A mesh that is not the one described (the history of a later run beside an earlier
    // mesh) is told.
    std::fs::copy(cyl(), &out).unwrap();
    assert!(report_says_mismatch(&out, &history, dir.path()));
}
