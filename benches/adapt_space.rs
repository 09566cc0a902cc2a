//! The loop in space's own time against mmg3d's (issue 32, item 8: the loop's sizing,
//! conformity and I/O at most 25 % of an mmg3d run at 10^6 tetrahedra).
//!
//! The UGAWG linear metric on the unit cube (benches/ugawg3d.py: h_x = h_y = 0.1,
//! h_z = h0 + 2 (0.1 − h0) |z − 0.5|, h0 = 0.001), every size divided by
//! `ADAPT_SPACE_SCALE` (default 1: about 4·10^4 tetrahedra; 3: about 10^6), from a Kuhn
//! box of 8 cubes a side, through `run_space` with `mmg3d_O3` on PATH and the result
//! files written to a temporary `.meshb` as `adapt` writes them. The field is the
//! analytic function (the recipe's sizing is timed by the sizing benches); per iteration
//! the line gives the sizing, the UGAWG measures with the complexity, the writing of the
//! best mesh and history (timed around the observer), and mmg3d's remeshing (with its
//! Medit files written and read back). Run:
//! `ADAPT_SPACE_SCALE=3 cargo bench -p smartmesh --bench adapt_space`.
#![allow(clippy::print_stdout, clippy::print_stderr)] // A benchmark prints what it measured.

use std::time::Instant;

use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::space::{run_space, SpaceField, SpaceSizingError};
use smartmesh::adapt::{Observer, Phase};
use smartmesh::formats::TaggedMesh;
use smartmesh::metric::Sym3;
use smartmesh::{adapter, AdaptOptions, AdapterKind, AdapterOptions, History};
use smartmesh_test_support::grid::kuhn_box;

/// The result files, the seconds each record took kept per iteration.
struct Timed {
    files: ResultFiles,
    write: Vec<f64>,
}

impl Observer for Timed {
    fn phase(&mut self, iteration: usize, phase: Phase) {
        eprintln!("iteration {iteration}: {phase}");
    }
    fn record(
        &mut self,
        history: &History,
        best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh::formats::Error> {
        let t = Instant::now();
        self.files.record(history, best)?;
        let k = history.iterations.len() - 1;
        self.write.resize(k + 1, 0.0);
        self.write[k] += t.elapsed().as_secs_f64();
        Ok(())
    }
}

fn main() {
    if std::env::args().any(|a| a == "--list") {
        return;
    }
    let scale: f64 =
        std::env::var("ADAPT_SPACE_SCALE").ok().and_then(|s| s.parse().ok()).unwrap_or(1.0);
    let sizing = move |mesh: &TaggedMesh| -> Result<SpaceField, SpaceSizingError> {
        let metric = mesh
            .points
            .iter()
            .map(|p| {
                let hz = 0.001 + 2.0 * (0.1 - 0.001) * (p[2] - 0.5).abs();
                let h = [0.1, 0.1, hz].map(|h| h / scale);
                Sym3::diagonal(h.map(|h| h.powi(-2)))
            })
            .collect();
        Ok(SpaceField { metric, warnings: Vec::new() })
    };
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cube.meshb");
    let mut timed =
        Timed { files: ResultFiles::new(&out, None, Default::default()), write: Vec::new() };
    let mmg3d = adapter(AdapterKind::Mmg3d, AdapterOptions::default()).expect("mmg3d_O3");
    let options = AdaptOptions { max_iterations: 8, max_vertices: None, ..Default::default() };
    let t = Instant::now();
    let outcome = run_space(
        kuhn_box(8, [1.0; 3]),
        &sizing,
        mmg3d.as_ref(),
        &options,
        "kuhn box 8",
        "ugawg linear",
        &mut timed,
    )
    .unwrap();
    let total = t.elapsed().as_secs_f64();
    let h = &outcome.history;
    println!(
        "adapt_space: UGAWG linear / {scale}, {} threads, mmg3d_O3",
        rayon::current_num_threads()
    );
    println!("iter  vertices      tets  conform  size_s  measure_s  write_s  remesh_s  own/remesh");
    let (mut own_all, mut remesh_all) = (0.0, 0.0);
    for r in &h.iterations {
        let s = &r.seconds;
        let write = timed.write.get(r.iteration).copied().unwrap_or(0.0);
        let own = s.size + s.measure + write;
        own_all += own;
        remesh_all += s.remesh;
        let ratio =
            if s.remesh > 0.0 { format!("{:.1}%", 100.0 * own / s.remesh) } else { "-".into() };
        println!(
            "{:4} {:9} {:9} {:7.3} {:7.3} {:10.3} {:8.3} {:9.3}  {ratio}",
            r.iteration,
            r.vertices,
            r.space.as_ref().map_or(0, |x| x.cells),
            r.conforming_share,
            s.size,
            s.measure,
            write,
            s.remesh
        );
    }
    println!(
        "total {total:.1} s: loop's own {own_all:.2} s, remeshing {remesh_all:.2} s ({:.1}%); {}",
        100.0 * own_all / remesh_all,
        h.stopped
    );
}
