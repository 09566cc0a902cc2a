//! `smartmesh batch`: a manifest of the bundled fixtures and examples run whole, in
//! parallel and in shards; every record checked against the history the run wrote; the
//! meshes the same bytes whatever the jobs or shards; `--resume` runs only what changed
//! or failed; bad manifests refused before any run, naming the file and the line.

#[path = "support/cli.rs"]
mod cli;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use cli::{bad, bundled, command, smartmesh, streams};
use serde_json::Value;

fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path).display().to_string()
}

/// A manifest of four variants: the cylinder twice (the second with other options and
/// its own copy of the recipe, relative to the manifest), the U-duct for one iteration,
/// and one that fails (the U-duct's recipe on the cylinder).
fn manifest(dir: &Path) -> PathBuf {
    std::fs::copy(repo("fixtures/cylinder.toml"), dir.join("cylinder.toml")).unwrap();
    let lines = [
        format!(
            r#"{{"name":"cyl","input":"{}","recipe":"cylinder.toml"}}"#,
            bundled("cylinder.msh")
        ),
        format!(
            r#"{{"name":"cyl-vtu","input":"{}","recipe":"cylinder.toml","options":{{"format":"vtu","max_iterations":1,"hmax":0.5}}}}"#,
            bundled("cylinder.msh")
        ),
        String::new(),
        format!(
            r#"{{"name":"u-duct","input":"{}","recipe":"{}","options":{{"max_iterations":1}}}}"#,
            repo("examples/u-duct/geometry.poly"),
            repo("examples/u-duct/recipe.cfg")
        ),
        format!(
            r#"{{"name":"wrong-recipe","input":"{}","recipe":"{}"}}"#,
            bundled("cylinder.msh"),
            repo("examples/u-duct/recipe.cfg")
        ),
    ];
    let m = dir.join("variants.jsonl");
    std::fs::write(&m, lines.join("\n") + "\n").unwrap();
    m
}

/// The records of `DIR/results.jsonl`, in file order.
fn records(dir: &Path) -> Vec<Value> {
    std::fs::read_to_string(dir.join("results.jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

fn by_name(records: &[Value]) -> BTreeMap<String, Value> {
    records.iter().map(|r| (r["name"].as_str().unwrap().to_string(), r.clone())).collect()
}

/// Checks every ok record against the history its run left, and the failing one.
fn check_records(dir: &Path, records: &BTreeMap<String, Value>) {
    assert_eq!(records.len(), 4, "{records:?}");
    for (name, r) in records {
        if name == "wrong-recipe" {
            assert_eq!(r["status"], "failed", "{r}");
            assert_eq!(r["line"], 5);
            assert!(r["error"].as_str().unwrap().contains("names tag 100"), "{r}");
            assert!(r["vertices"].is_null());
            continue;
        }
        assert_eq!(r["status"], "ok", "{r}");
        assert!(r["error"].is_null());
        let history: Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(r["history"].as_str().unwrap())).unwrap(),
        )
        .unwrap();
        let best = &history["iterations"][history["best_iteration"].as_u64().unwrap() as usize];
        for (key, field) in [
            ("vertices", "vertices"),
            ("triangles", "triangles"),
            ("conformity", "conforming_share"),
            ("mean_quality", "mean_quality"),
            ("min_quality", "min_quality"),
        ] {
            assert_eq!(r[key], best[field], "{name}: {key}");
        }
        assert_eq!(r["converged"], history["converged"]);
        assert_eq!(
            r["iterations"].as_u64().unwrap() as usize,
            history["iterations"].as_array().unwrap().len() - 1
        );
        // The output is a mesh `info` reads, with the record's vertex count.
        let out = dir.join(r["output"].as_str().unwrap());
        let info = smartmesh(&["info", out.to_str().unwrap(), "--json"], None);
        let info: Value = serde_json::from_str(&cli::ok(&info)).unwrap();
        assert_eq!(info["points"], r["vertices"], "{name}: {info}");
    }
    assert_eq!(records["cyl-vtu"]["output"], "cyl-vtu.vtu");
    assert_eq!(records["cyl-vtu"]["iterations"], 1);
    assert_eq!(records["u-duct"]["line"], 4);
}

#[test]
fn a_batch_runs_every_variant_and_records_each_whatever_the_jobs_or_shards() {
    let d = tempfile::tempdir().unwrap();
    let m = manifest(d.path());
    let m = m.to_str().unwrap();
    let (one, two, sharded) =
        (d.path().join("one"), d.path().join("two"), d.path().join("sharded"));

    // A failing variant stops nothing: the others are recorded, the summary names it, 1.
    let o = smartmesh(&["batch", m, "-o", two.to_str().unwrap(), "--jobs", "2"], None);
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("3 of 4 variants done, 1 failed"), "{err}");
    assert!(err.contains("wrong-recipe (line 5): region"), "{err}");
    check_records(&two, &by_name(&records(&two)));

    let o = smartmesh(&["batch", m, "-o", one.to_str().unwrap(), "--jobs", "1"], None);
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    for shard in ["0/3", "1/3", "2/3"] {
        let o = smartmesh(&["batch", m, "-o", sharded.to_str().unwrap(), "--shard", shard], None);
        assert!(matches!(o.status.code(), Some(0 | 1)), "{}", streams(&o));
    }
    let shard_records = records(&sharded);
    assert_eq!(shard_records.len(), 4, "each variant in exactly one shard");
    check_records(&sharded, &by_name(&shard_records));

    // The meshes are the same bytes whatever the jobs or the shard that ran them.
    for file in ["cyl.msh", "cyl-vtu.vtu", "u-duct.msh"] {
        let a = std::fs::read(one.join(file)).unwrap();
        assert_eq!(a, std::fs::read(two.join(file)).unwrap(), "{file}: 1 job against 2");
        assert_eq!(a, std::fs::read(sharded.join(file)).unwrap(), "{file}: whole against shard");
    }
}

#[test]
fn resume_runs_only_what_failed_changed_or_lost_its_output() {
    let d = tempfile::tempdir().unwrap();
    let m = manifest(d.path());
    let m = m.to_str().unwrap();
    let out = d.path().join("out");
    let run = || smartmesh(&["batch", m, "-o", out.to_str().unwrap(), "--resume"], None);
    assert_eq!(run().status.code(), Some(1));
    assert_eq!(records(&out).len(), 4);

    // Nothing changed: only the failed variant runs again.
    let o = run();
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    assert!(String::from_utf8_lossy(&o.stderr).contains("(3 already recorded)"), "{}", streams(&o));
    let r = records(&out);
    assert_eq!(r.len(), 5);
    assert_eq!(r[4]["name"], "wrong-recipe");

    // A changed recipe (both cylinder variants use it) and a lost output run again.
    let recipe = d.path().join("cylinder.toml");
    let text = std::fs::read_to_string(&recipe).unwrap();
    std::fs::write(&recipe, format!("# edited\n{text}")).unwrap();
    std::fs::remove_file(out.join("u-duct.msh")).unwrap();
    let o = run();
    assert_eq!(o.status.code(), Some(1), "{}", streams(&o));
    let r = records(&out);
    let again: Vec<&str> = r[5..].iter().map(|r| r["name"].as_str().unwrap()).collect();
    assert_eq!(again.len(), 4, "{again:?}");
    let latest = by_name(&r);
    assert_ne!(latest["cyl"]["hash"], r[0..4].iter().find(|x| x["name"] == "cyl").unwrap()["hash"]);
    check_records(&out, &latest);

    // With the failing variant gone from the manifest, the batch is complete: exit 0.
    let text = std::fs::read_to_string(m).unwrap();
    let kept: Vec<&str> = text.lines().filter(|l| !l.contains("wrong-recipe")).collect();
    std::fs::write(m, kept.join("\n") + "\n").unwrap();
    let o = run();
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("3 of 3 variants done (3 already recorded)")
    );
    assert_eq!(records(&out).len(), 9);
}

#[test]
fn an_hq_entry_runs_its_line_alone() {
    let d = tempfile::tempdir().unwrap();
    let m = manifest(d.path());
    let line = std::fs::read_to_string(&m).unwrap().lines().nth(3).unwrap().to_string();
    let out = d.path().join("out");
    let o = command(&["batch", m.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .env("HQ_ENTRY", &line)
        .env("HQ_TASK_ID", "3")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    let r = records(&out);
    assert_eq!(r.len(), 1);
    assert_eq!(r[0]["name"], "u-duct");
    assert_eq!(r[0]["line"], 4);
    assert_eq!(r[0]["status"], "ok");
    // A blank entry (a blank manifest line) runs nothing.
    let o = command(&["batch", m.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .env("HQ_ENTRY", "")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
    assert_eq!(records(&out).len(), 1);
    // A bad entry is named as such.
    let o = command(&["batch", m.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .env("HQ_ENTRY", "{\"name\":\"x\"}")
        .env("HQ_TASK_ID", "7")
        .output()
        .unwrap();
    let err = bad(&o);
    assert!(err.contains("HQ_ENTRY (task 7 of"), "{err}");
    assert!(err.contains("`input` is missing"), "{err}");
}

#[test]
fn a_bad_manifest_is_refused_before_any_run_naming_file_and_line() {
    let d = tempfile::tempdir().unwrap();
    let m = manifest(d.path());
    let good = std::fs::read_to_string(&m).unwrap();
    let out = d.path().join("out");
    let cases = [
        ("not json", "not a JSON object"),
        (
            r#"{"name":"cyl","input":"cylinder.toml","recipe":"cylinder.toml"}"#,
            "already used at line 1",
        ),
        (
            r#"{"name":"x","input":"cylinder.toml","recipe":"cylinder.toml","options":{"hgrad":"a"}}"#,
            "must be a number",
        ),
        (
            r#"{"name":"x","input":"cylinder.toml","recipe":"cylinder.toml","options":{"adapter":"mmg"}}"#,
            "the options of `x`: invalid value 'mmg'",
        ),
        (
            r#"{"name":"x","input":"cylinder.toml","recipe":"cylinder.toml","options":{"max_iteration":2}}"#,
            "did you mean `max_iterations`",
        ),
    ];
    for (line, expected) in cases {
        let bad_manifest = d.path().join("bad.jsonl");
        std::fs::write(&bad_manifest, format!("{good}{line}\n")).unwrap();
        let o = smartmesh(
            &["batch", bad_manifest.to_str().unwrap(), "-o", out.to_str().unwrap()],
            None,
        );
        let err = bad(&o);
        assert!(err.contains(&format!("{}:6: ", bad_manifest.display())), "{line}: {err}");
        assert!(err.contains(expected), "{line}: {err}");
        assert!(!out.exists(), "nothing is written before the manifest is checked");
    }
    for shard in ["2/2", "x"] {
        let o = smartmesh(
            &["batch", m.to_str().unwrap(), "-o", out.to_str().unwrap(), "--shard", shard],
            None,
        );
        assert!(bad(&o).contains("is not a shard"));
    }
}
