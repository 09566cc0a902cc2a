//! What a reader could not keep reaches `--json` as `read_notes`, not only stderr
//! (which `-q` silences): a partitioned Gmsh file merged into one mesh.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod cli;

use cli::{fixture, ok, smartmesh};

fn json(text: &str) -> serde_json::Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

/// `convert --json -q` and `info --json -q` of a partitioned MSH 4.1 file: its physical
/// groups are there, and the merged partitions are listed in `read_notes`.
#[test]
fn a_partitioned_file_says_in_json_that_its_partitions_were_merged() {
    let dir = tempfile::tempdir().unwrap();
    let input = fixture("partitioned_t21.msh");
    let out = dir.path().join("p.vtu");
    let o = smartmesh(
        &["convert", input.to_str().unwrap(), out.to_str().unwrap(), "--json", "-q"],
        None,
    );
    let j = json(&ok(&o));
    assert!(o.stderr.is_empty(), "{}", String::from_utf8_lossy(&o.stderr));
    let notes = j["read_notes"].as_array().unwrap();
    assert_eq!(notes.len(), 1, "{j}");
    assert!(notes[0].as_str().unwrap().contains("3 partitions read as one mesh"), "{j}");

    let j = json(&ok(&smartmesh(&["info", "--json", "-q", input.to_str().unwrap()], None)));
    assert_eq!(j["read_notes"], serde_json::json!(notes), "{j}");
    let named: Vec<(&str, u64)> = j["tags"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| (t["name"].as_str().unwrap_or(""), t["cells"].as_u64().unwrap()))
        .collect();
    assert_eq!(named, vec![("Bottom", 5), ("Left", 66), ("Right", 66)], "{j}");
}
