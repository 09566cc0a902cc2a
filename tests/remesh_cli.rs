//! `smartmesh remesh` end to end: the metric from `--metric` or from the mesh itself,
//! `--json` statistics, `--measure`, identical bytes whatever the thread count, clear
//! errors (exit 2, naming the file and the vertex) for bad metrics, and MMG reading our
//! output (skips unless `mmg2d_O3` is installed or `SMARTMESH_REQUIRE_INTEROP=1`).

use std::path::{Path, PathBuf};
use std::process::Command;

use smartmesh::formats::{read_path, write_path, DataArray, WriteOptions};

#[path = "support/cli.rs"]
mod cli;

use cli::{bad, bundled, ok, smartmesh};

/// The cylinder's recipe field, written as .vtu (mesh + metric).
fn field(dir: &Path) -> PathBuf {
    let f = dir.join("field.vtu");
    ok(&smartmesh(
        &[
            "size",
            &bundled("cylinder.msh"),
            "--recipe",
            &bundled("cylinder.toml"),
            "-o",
            f.to_str().unwrap(),
        ],
        None,
    ));
    f
}

#[test]
fn remesh_writes_a_conforming_mesh_and_json_stats() {
    let dir = tempfile::tempdir().unwrap();
    let f = field(dir.path());
    let out = dir.path().join("out.vtu");
    let json: serde_json::Value = serde_json::from_str(&ok(&smartmesh(
        &[
            "remesh",
            &bundled("cylinder.msh"),
            "--metric",
            f.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--json",
        ],
        None,
    )))
    .unwrap();
    assert!(json["conformity"]["conforming_share"].as_f64().unwrap() >= 0.9, "{json}");
    assert!(json["conformity"]["min_quality"].as_f64().unwrap() > 0.0);
    assert!(json["passes"].as_u64().unwrap() >= 1);
    for k in ["split", "collapse", "swap", "smooth"] {
        assert!(json["seconds"][k].is_number(), "{json}");
    }
    let mesh = read_path(&out, None).unwrap();
    assert_eq!(mesh.point_data["metric"].components, 9);
    assert_eq!(mesh.points.len() as u64, json["output"]["vertices"].as_u64().unwrap());
    // --measure on the output agrees with the stats.
    let m: serde_json::Value = serde_json::from_str(&ok(&smartmesh(
        &["remesh", out.to_str().unwrap(), "--measure", "--json"],
        None,
    )))
    .unwrap();
    assert_eq!(m["edges"], json["conformity"]["edges"]);
    assert_eq!(m["conforming_share"], json["conformity"]["conforming_share"]);
    // The metric can come with the mesh itself (the .vtu of `size`).
    let out2 = dir.path().join("out2.vtu");
    ok(&smartmesh(&["remesh", f.to_str().unwrap(), "-o", out2.to_str().unwrap()], None));
}

#[test]
fn output_bytes_do_not_depend_on_threads_or_runs() {
    let dir = tempfile::tempdir().unwrap();
    let f = field(dir.path());
    let mut outs = Vec::new();
    for (i, threads) in ["1", "2", "2"].iter().enumerate() {
        let out = dir.path().join(format!("out{i}.mesh"));
        ok(&smartmesh(
            &[
                "remesh",
                &bundled("cylinder.msh"),
                "--metric",
                f.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
                "--boundary",
                "smooth",
            ],
            Some(threads),
        ));
        outs.push((
            std::fs::read(&out).unwrap(),
            std::fs::read(out.with_extension("sol")).unwrap(),
        ));
    }
    assert!(outs[0] == outs[1] && outs[1] == outs[2]);
}

#[test]
fn bad_metrics_exit_2_naming_file_and_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let f = field(dir.path());
    let base = read_path(&f, None).unwrap();
    let cyl = bundled("cylinder.msh");
    let write = |name: &str, mesh: &smartmesh::formats::TaggedMesh| {
        let p = dir.path().join(name);
        write_path(&p, mesh, None, &WriteOptions::default()).unwrap();
        p
    };
    let used = base.cells().find(|c| c.0 == smartmesh::formats::CellKind::Triangle).unwrap().1[0];
    for (name, value, why) in
        [("nan.vtu", f64::NAN, "finite"), ("neg.vtu", -1.0, "not positive definite")]
    {
        let mut m = base.clone();
        let a = m.point_data.get_mut("metric").unwrap();
        a.values[used as usize * 9] = value;
        let p = write(name, &m);
        let err = bad(&smartmesh(
            &[
                "remesh",
                &cyl,
                "--metric",
                p.to_str().unwrap(),
                "-o",
                dir.path().join("x.vtu").to_str().unwrap(),
            ],
            None,
        ));
        // The VTU reader refuses a NaN itself (naming the byte); a finite non-SPD tensor
        // gets through and metric_field names the vertex.
        let named =
            err.contains(&format!("vertex {used}")) || (value.is_nan() && err.contains("byte"));
        assert!(err.contains(name) && named && err.contains(why), "{err}");
    }
    // Wrong vertex count: the metric file is another mesh.
    let mut m = base.clone();
    m.points.push([9.0, 9.0, 0.0]);
    m.point_data.retain(|k, _| k == "metric");
    let mut v = m.point_data["metric"].values.clone();
    v.extend_from_slice(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
    m.point_data.insert("metric".into(), DataArray::new(9, v));
    let p = write("count.vtu", &m);
    let err = bad(&smartmesh(
        &[
            "remesh",
            &cyl,
            "--metric",
            p.to_str().unwrap(),
            "-o",
            dir.path().join("x.vtu").to_str().unwrap(),
        ],
        None,
    ));
    assert!(err.contains("count.vtu") && err.contains("vertices"), "{err}");
    // Same count, other vertices.
    let mut m = base.clone();
    m.points[3][0] += 0.25;
    let p = write("moved.vtu", &m);
    let err = bad(&smartmesh(
        &[
            "remesh",
            &cyl,
            "--metric",
            p.to_str().unwrap(),
            "-o",
            dir.path().join("x.vtu").to_str().unwrap(),
        ],
        None,
    ));
    assert!(err.contains("moved.vtu") && err.contains("vertex 3"), "{err}");
    // No metric at all.
    let err =
        bad(&smartmesh(&["remesh", &cyl, "-o", dir.path().join("x.vtu").to_str().unwrap()], None));
    assert!(err.contains("cylinder.msh") && err.contains("no point data `metric`"), "{err}");
    assert!(!dir.path().join("x.vtu").exists());
}

#[test]
fn mmg_reads_our_output() {
    let dir = tempfile::tempdir().unwrap();
    let have = Command::new("mmg2d_O3")
        .arg("-h")
        .output()
        .map(|o| o.status.success() || !o.stdout.is_empty())
        .unwrap_or(false);
    if !have {
        smartmesh_test_support::skip::missing_tool("mmg2d_O3 is not installed");
        return;
    }
    let f = field(dir.path());
    let out = dir.path().join("ours.mesh");
    ok(&smartmesh(
        &[
            "remesh",
            &bundled("cylinder.msh"),
            "--metric",
            f.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ],
        None,
    ));
    let adapted = dir.path().join("mmg.mesh");
    let o = Command::new("mmg2d_O3")
        .args([
            out.to_str().unwrap(),
            "-sol",
            out.with_extension("sol").to_str().unwrap(),
            "-out",
            adapted.to_str().unwrap(),
            "-v",
            "0",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Our output already conforms, so MMG has little to do: the measure stays in band.
    let m: serde_json::Value = serde_json::from_str(&ok(&smartmesh(
        &["remesh", adapted.to_str().unwrap(), "--measure", "--json"],
        None,
    )))
    .unwrap();
    assert!(m["conforming_share"].as_f64().unwrap() > 0.8, "{m}");
}

/// The reproductions of valid but extreme metrics: one vertex of the cylinder's field at
/// h = 1e-6, or with 1e300 in its matrix, made `remesh` allocate until it aborted; now
/// exit 2 at once, with the estimate and the option, and no output. `--max-vertices`
/// raises the limit (here it lowers it under the plain field's count).
#[test]
fn extreme_metrics_are_refused_with_the_estimate_and_the_option() {
    let dir = tempfile::tempdir().unwrap();
    let f = field(dir.path());
    let base = read_path(&f, None).unwrap();
    let cyl = bundled("cylinder.msh");
    let out = dir.path().join("x.vtu");
    let used = base.cells().find(|c| c.0 == smartmesh::formats::CellKind::Triangle).unwrap().1[0];
    for (name, m11) in [("tiny.vtu", 1e12), ("huge.vtu", 1e300)] {
        let mut m = base.clone();
        let a = m.point_data.get_mut("metric").unwrap();
        let v = used as usize * 9;
        a.values[v..v + 9].copy_from_slice(&[m11, 0.0, 0.0, 0.0, m11, 0.0, 0.0, 0.0, m11]);
        let p = dir.path().join(name);
        write_path(&p, &m, None, &WriteOptions::default()).unwrap();
        let started = std::time::Instant::now();
        let err = bad(&smartmesh(
            &["remesh", &cyl, "--metric", p.to_str().unwrap(), "-o", out.to_str().unwrap()],
            None,
        ));
        assert!(started.elapsed().as_secs_f64() < 30.0, "{name}: refused before any work");
        assert!(err.contains("asks for about") && err.contains("--max-vertices"), "{err}");
        assert!(!out.exists());
    }
    let err = bad(&smartmesh(
        &[
            "remesh",
            &cyl,
            "--metric",
            f.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--max-vertices",
            "100",
        ],
        None,
    ));
    assert!(err.contains("more than the limit of 100"), "{err}");
}

/// An allocation failure aborts: under `ulimit -v` (RLIMIT_AS) below what the metric's
/// estimate needs (here about 2 million vertices, 1.1 GB, under a limit of 600 MB, well
/// within --max-vertices), `remesh` refuses at once with exit 2, naming the estimate and
/// the limit, and writes nothing; without the limit the estimate alone is no refusal.
#[test]
fn a_memory_limit_below_the_estimate_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let mut m = read_path(&field(dir.path()), None).unwrap();
    let sym = |v: &[f64]| -> Vec<smartmesh::Sym2> {
        v.chunks(9).map(|t| smartmesh::Sym2 { a: t[0], b: t[1], c: t[4] }).collect()
    };
    let e1 = smartmesh::expected_vertices(&m, &sym(&m.point_data["metric"].values));
    // √det of k·M is k·√det M: the estimate scales with k.
    let k = 2.0e6 / e1;
    for v in m.point_data.get_mut("metric").unwrap().values.chunks_mut(9) {
        for (i, x) in v.iter_mut().enumerate() {
            if i != 8 {
                *x *= k;
            }
        }
    }
    let e = smartmesh::expected_vertices(&m, &sym(&m.point_data["metric"].values));
    assert!((1.5e6..2.5e6).contains(&e), "{e}");
    let big = dir.path().join("big.vtu");
    write_path(&big, &m, None, &WriteOptions::default()).unwrap();
    let out = dir.path().join("x.vtu");
    let started = std::time::Instant::now();
    let o = Command::new("sh")
        .args(["-c", "ulimit -v 600000 && exec \"$0\" \"$@\""])
        .arg(env!("CARGO_BIN_EXE_smartmesh"))
        .args(["remesh", big.to_str().unwrap(), "-o", out.to_str().unwrap(), "--threads", "1"])
        .output()
        .unwrap();
    let err = bad(&o);
    assert!(started.elapsed().as_secs_f64() < 60.0, "refused before any work");
    assert!(err.contains("asks for about 2.") && err.contains("GB of memory"), "{err}");
    assert!(err.contains("address-space limit (ulimit -v) of 614 MB"), "{err}");
    assert!(!out.exists());
}

/// `--threads 100000` started 100 000 threads for over a minute before any work: refused
/// at once, as is RAYON_NUM_THREADS above the cap.
#[test]
fn a_thread_count_past_the_cap_is_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.vtu");
    let cyl = bundled("cylinder.msh");
    let started = std::time::Instant::now();
    let args = ["remesh", &cyl, "-o", out.to_str().unwrap(), "--threads", "100000"];
    let err = bad(&smartmesh(&args, None));
    assert!(err.contains("--threads 100000: at most 1024"), "{err}");
    let err = bad(&smartmesh(&args[..4], Some("100000")));
    assert!(err.contains("RAYON_NUM_THREADS=100000: at most 1024"), "{err}");
    assert!(started.elapsed().as_secs_f64() < 20.0, "{:?}", started.elapsed());
    assert!(!out.exists());
}
