//! `smartmesh recipe check` and `smartmesh recipe convert`: exit codes, output, files.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "support/cli.rs"]
mod cli;
use cli::{bundled, run, stderr, stdout};

fn has_cpp() -> bool {
    cli::cpp_or_skip("a recipe with #define")
}

const PLAIN: &str = "CREATE_REGIONS = ( { NAME = \"Vane\"; TOPOLOGICAL_ENTITIES = [ 101, 102 ]; } );
CREATE_DISTANCE_FUNCTIONS = ( { NAME = \"F\"; MINSIZE = 0.1; MAXSIZE = 1.0; MAXDISTANCE = 5.0; EXPONENT = 1.0; } );
CREATE_ALGORITHMS = ( { TYPE = \"DISTANCE_TO_BORDER\"; PERPENDICULAR_FUNCTION = \"F\"; PARALLEL_FUNCTION = \"F\"; REGIONS = ( \"Vane\" ); } );
";

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn check_prints_regions_and_algorithms() {
    if !has_cpp() {
        return;
    }
    let o = run(&["recipe", "check", &bundled("appendix-a.cfg"), &bundled("distributor.msh")]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(s.contains("StayVane         7 curves: tags 101, 102, 103, 104, 105, 106, 107"), "{s}");
    assert!(s.contains("Corners          9 points: tags 1, 2, 3, 4, 5, 6, 7, 11, 12"), "{s}");
    assert!(
        s.contains("Inlet            1 curve: tags 301 (\"Inlet\"); unused (no algorithm"),
        "{s}"
    );
    assert!(s.contains("algorithm 3 (DISTANCE_TO_BORDER on \"StayVane\"): 7 curves"), "{s}");

    let o = run(&[
        "recipe",
        "check",
        "--json",
        &bundled("appendix-a.cfg"),
        &bundled("distributor.msh"),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v["regions"].as_array().unwrap().len(), 7);
    let fluid = v["regions"].as_array().unwrap().iter().find(|r| r["name"] == "Fluid").unwrap();
    assert_eq!(fluid["dimension"], 2);
    assert_eq!(fluid["used_by"], serde_json::json!([1, 5]));
    assert_eq!(fluid["cells"], 1988);
    // A region no algorithm uses is looked up, not measured.
    let inlet = v["regions"].as_array().unwrap().iter().find(|r| r["name"] == "Inlet").unwrap();
    assert_eq!(
        (inlet["dimension"].clone(), inlet["vertices"].clone()),
        (1.into(), serde_json::Value::Null)
    );
    assert_eq!(v["algorithms"][4]["type"], "DISTANCE_TO_IMAGINARY_POLYLINE");
    assert_eq!(v["algorithms"][1]["points"], 9);
}

#[test]
fn errors_exit_two_with_file_line_and_suggestion() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = bundled("distributor.msh");
    let bad = write(
        dir.path(),
        "bad.cfg",
        &PLAIN.replace("PARALLEL_FUNCTION = \"F\"", "PARALLEL_FUNCTION = \"G\""),
    );
    let o = run(&["recipe", "check", bad.to_str().unwrap(), &mesh]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("algorithm 1 names function \"G\" at ")
            && stderr(&o).contains("bad.cfg:3"),
        "{}",
        stderr(&o)
    );
    let absent = write(dir.path(), "absent.cfg", &PLAIN.replace("102 ]", "102, 999 ]"));
    let o = run(&["recipe", "check", absent.to_str().unwrap(), &mesh]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("names tag 999, which the mesh does not have"), "{}", stderr(&o));
    let o = run(&["recipe", "check", "no/such/recipe.toml", &mesh]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("no/such/recipe.toml"), "{}", stderr(&o));
    let odd = write(dir.path(), "recipe.txt", PLAIN);
    let o = run(&["recipe", "check", odd.to_str().unwrap(), &mesh]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--recipe-format"), "{}", stderr(&o));
    let o = run(&["recipe", "check", "--recipe-format", "cfg", odd.to_str().unwrap(), &mesh]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let o = run(&["recipe", "check"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn a_missing_preprocessor_is_named_only_when_needed() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = bundled("distributor.msh");
    let plain = write(dir.path(), "plain.cfg", &format!("# hash comments need no cpp\n{PLAIN}"));
    let o = cli::command(&["recipe", "check", plain.to_str().unwrap(), &mesh])
        .env("SMARTMESH_CPP", "/no/such/cpp")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let with = write(
        dir.path(),
        "define.cfg",
        &format!("\n#define VANE 101, 102\n{}", PLAIN.replace("101, 102", "VANE")),
    );
    let o = cli::command(&["recipe", "check", with.to_str().unwrap(), &mesh])
        .env("SMARTMESH_CPP", "/no/such/cpp")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("#define") && e.contains("install") && e.contains("define.cfg:2"), "{e}");
    if has_cpp() {
        let o = run(&["recipe", "check", with.to_str().unwrap(), &mesh]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    }
}

#[test]
fn convert_round_trips_through_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let d = |n: &str| dir.path().join(n).to_string_lossy().into_owned();
    let src = write(dir.path(), "in.cfg", PLAIN);
    for (from, to) in [
        (src.to_string_lossy().into_owned(), d("a.toml")),
        (d("a.toml"), d("a.json")),
        (d("a.json"), d("b.cfg")),
        (d("b.cfg"), d("b.toml")),
    ] {
        let o = run(&["recipe", "convert", &from, &to]);
        assert_eq!(o.status.code(), Some(0), "{from} -> {to}: {}", stderr(&o));
    }
    assert_eq!(
        std::fs::read_to_string(d("a.toml")).unwrap(),
        std::fs::read_to_string(d("b.toml")).unwrap()
    );
    let o = run(&["recipe", "convert", &d("a.toml"), "-", "--to", "json"]);
    assert_eq!(o.status.code(), Some(0));
    assert_eq!(stdout(&o), std::fs::read_to_string(d("a.json")).unwrap());
    // A failed conversion writes nothing.
    let bad = write(dir.path(), "bad.toml", "[regions]\nA = []\n");
    let o = run(&["recipe", "convert", bad.to_str().unwrap(), &d("out.json")]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("region \"A\" names no entity"), "{}", stderr(&o));
    assert!(!dir.path().join("out.json").exists());
    let o = run(&["recipe", "convert", &d("a.toml"), &d("out.xyz")]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--to"), "{}", stderr(&o));
}

#[test]
fn a_deeply_nested_recipe_exits_two_in_every_command_that_reads_one() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = bundled("distributor.msh");
    let deep = write(
        dir.path(),
        "deep.cfg",
        &format!("\nA = {}{};\n", "[".repeat(20_000), "]".repeat(20_000)),
    );
    let deep = deep.to_str().unwrap();
    let out = |n: &str| dir.path().join(n).to_string_lossy().into_owned();
    for args in [
        vec!["recipe", "convert", deep, "-", "--to", "json"],
        vec!["recipe", "check", deep, &mesh],
        vec!["size", &mesh, "--recipe", deep, "-o", &out("f.sol")],
        vec!["adapt", &mesh, "--recipe", deep, "-o", &out("a.msh")],
    ] {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains("nested deeper than 64") && e.contains("deep.cfg:2"), "{args:?}: {e}");
    }
}

#[test]
fn no_preprocess_reads_nothing_but_the_recipe() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = bundled("distributor.msh");
    let plain = write(dir.path(), "plain.cfg", &format!("# a hash comment\n{PLAIN}"));
    let plain = plain.to_str().unwrap();
    let out = |n: &str| dir.path().join(n).to_string_lossy().into_owned();
    // Every command that reads a recipe takes the flag; a plain recipe reads as before.
    for args in [
        vec!["recipe", "convert", "--no-preprocess", plain, "-", "--to", "json"],
        vec!["recipe", "check", "--no-preprocess", plain, &mesh],
        vec!["size", &mesh, "--recipe", plain, "--no-preprocess", "-o", &out("f.sol")],
    ] {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", stderr(&o));
    }
    for (name, text, what) in [
        ("hash.cfg", format!("#include \"/etc/passwd\"\n{PLAIN}"), "#include"),
        ("at.cfg", format!("{PLAIN}@include \"/etc/passwd\"\n"), "@include"),
    ] {
        let r = write(dir.path(), name, &text);
        let r = r.to_str().unwrap();
        for args in [
            vec!["recipe", "check", "--no-preprocess", r, &mesh],
            vec!["recipe", "convert", "--no-preprocess", r, "-", "--to", "toml"],
            vec!["size", &mesh, "-r", r, "--no-preprocess", "-o", &out("g.sol")],
            vec!["adapt", &mesh, "-r", r, "--no-preprocess", "-o", &out("g.msh")],
            vec!["report", &mesh, "-r", r, "--no-preprocess", "-o", &out("g.svg")],
        ] {
            let o = run(&args);
            let e = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
            assert!(e.contains(what) && e.contains("--no-preprocess") && e.contains(name), "{e}");
            assert!(!e.contains("root:"), "{e}");
        }
    }
}

#[cfg(unix)]
#[test]
fn devices_are_refused_at_the_line_that_names_them() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = bundled("distributor.msh");
    for (name, text) in [
        ("hash.cfg", format!("{PLAIN}#include </dev/zero>\n")),
        ("at.cfg", format!("{PLAIN}@include \"/dev/zero\"\n")),
    ] {
        let r = write(dir.path(), name, &text);
        let o = run(&["recipe", "check", r.to_str().unwrap(), &mesh]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(
            e.contains("/dev/zero is not a regular file") && e.contains(&format!("{name}:4")),
            "{e}"
        );
    }
}

/// `(ppid, pgrp)` of every process, from `/proc/PID/stat`.
#[cfg(target_os = "linux")]
fn processes() -> Vec<(u32, u32, u32)> {
    let mut all = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else { continue };
        let Ok(stat) = std::fs::read_to_string(e.path().join("stat")) else { continue };
        // pid (comm) state ppid pgrp …; comm may hold spaces and parentheses.
        let Some(rest) = stat.rfind(')').map(|i| &stat[i + 1..]) else { continue };
        let f: Vec<&str> = rest.split_whitespace().collect();
        if let (Some(ppid), Some(pgrp)) = (f.get(1), f.get(2)) {
            all.push((pid, ppid.parse().unwrap_or(0), pgrp.parse().unwrap_or(0)));
        }
    }
    all
}

#[cfg(target_os = "linux")]
#[test]
fn a_killed_smartmesh_leaves_no_preprocessor_behind() {
    if !has_cpp() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("endless");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    // A computed #include is not checked before cpp runs: cpp (its cc1) blocks on the
    // fifo, which nobody writes.
    let recipe = write(
        dir.path(),
        "slow.cfg",
        &format!("#define SLOW \"{}\"\n#include SLOW\n{PLAIN}", fifo.display()),
    );
    for signal in ["KILL", "TERM"] {
        killed_while_cpp_blocks(&recipe, signal);
    }
}

#[cfg(target_os = "linux")]
fn killed_while_cpp_blocks(recipe: &Path, signal: &str) {
    use std::time::{Duration, Instant};
    let mut child =
        cli::command(&["recipe", "check", recipe.to_str().unwrap(), &bundled("distributor.msh")])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
    let parent = child.id();
    let start = Instant::now();
    // The preprocessor's group: the group of smartmesh's child, once it holds two
    // processes (cpp and the cc1 it starts).
    let group = loop {
        let all = processes();
        let found = all.iter().find(|p| p.1 == parent && p.2 == p.0).map(|p| p.2);
        if let Some(g) = found.filter(|&g| all.iter().filter(|p| p.2 == g).count() >= 2) {
            break g;
        }
        assert!(start.elapsed() < Duration::from_secs(8), "cpp never started");
        std::thread::sleep(Duration::from_millis(20));
    };
    std::thread::sleep(Duration::from_millis(200));
    let sent = Command::new("kill").args([&format!("-{signal}"), &parent.to_string()]).status();
    assert!(sent.unwrap().success());
    child.wait().unwrap();
    let killed = Instant::now();
    let left = loop {
        let left: Vec<u32> = processes().iter().filter(|p| p.2 == group).map(|p| p.0).collect();
        if left.is_empty() || killed.elapsed() > Duration::from_secs(3) {
            break left;
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    if !left.is_empty() {
        // Clean up before failing.
        let _ = Command::new("kill").args(["-KILL", "--", &format!("-{group}")]).status();
    }
    assert!(left.is_empty(), "SIG{signal}: the preprocessor's group still runs: {left:?}");
}
