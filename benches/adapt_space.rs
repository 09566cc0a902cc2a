//! The loop in space's own time against mmg3d's (issue 32, item 8: the loop's sizing,
//! conformity and I/O at most 25 % of an mmg3d run at 10^6 tetrahedra).
//!
//! Two fields:
//!
//! - By default the UGAWG linear metric on the unit cube (benches/ugawg3d.py: h_x = h_y =
//!   0.1, h_z = h0 + 2 (0.1 − h0) |z − 0.5|, h0 = 0.001), every size divided by
//!   `ADAPT_SPACE_SCALE` (default 1: about 4·10^4 tetrahedra), from a Kuhn box of 8 cubes
//!   a side. The field is the analytic function; per iteration the line gives the
//!   sizing, the UGAWG measures with the complexity, the writing of the best mesh and
//!   history (timed around the observer), and mmg3d's remeshing (with its Medit files
//!   written and read back), wall seconds.
//! - With `ADAPT_SPACE_RECIPE=R.toml ADAPT_SPACE_START=M` a recipe's 3D sizing from the
//!   mesh M: the recipe's sizes (`size`, `size_at_source`, `size_at_max_distance`,
//!   `min_size`, `max_size`, `hmin`, `hmax`) divided by `ADAPT_SPACE_SCALE` and its
//!   `size_of_error` by its square (so curvature's sizes scale as the others), distances
//!   kept; no growth limit (so that one iteration reaches the field's count);
//!   `ADAPT_SPACE_MMG` holds arguments for mmg3d_O3 (as `--adapter-arg`);
//!   `ADAPT_SPACE_ITERATIONS` the iteration limit (default 2; 0 sizes and measures the
//!   start alone). The recipe is sized by the calls `RecipeInSpace` makes (checked bit
//!   for bit against it on the start before the timed run), each phase timed apart in
//!   CPU seconds of this process (all its threads) and of its children (mmg3d), from
//!   /proc/self/stat: the topology, the recipe's resolution with the vertex graph, each
//!   step (the closest points and the algorithms' work), the default, bounds and
//!   gradation, the measures, the result files, and in the remeshing this process's
//!   share (the Medit files to and from mmg3d) and mmg3d's own.
//!
//! Run: `ADAPT_SPACE_SCALE=2 cargo bench -p smartmesh --bench adapt_space`, or
//! `ADAPT_SPACE_RECIPE=examples/wing3d/recipe.toml ADAPT_SPACE_START=start.msh
//! ADAPT_SPACE_SCALE=1.8 ADAPT_SPACE_MMG="-hausd 0.001 -hgrad -1" cargo bench -p
//! smartmesh --bench adapt_space` (Linux: the CPU times come from /proc).
#![allow(clippy::print_stdout, clippy::print_stderr)] // A benchmark prints what it measured.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::Path;
use std::rc::Rc;
use std::time::Instant;

use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::space::{
    run_space, RecipeInSpace, SpaceField, SpaceSizing, SpaceSizingError,
};
use smartmesh::adapt::{Observer, Phase};
use smartmesh::formats::{CellKind, TaggedMesh};
use smartmesh::metric::{SizeTensor3, Sym3};
use smartmesh::recipe::RecipeFormat;
use smartmesh::sizing::{compute_size_field3, SpaceMesh, StepEvent};
use smartmesh::{adapter, AdaptOptions, AdapterKind, AdapterOptions, History, Recipe, Topology};
use smartmesh_test_support::grid::kuhn_box;

/// The result files, the seconds each record took kept per iteration, and in recipe
/// mode the CPU ledger the phases are charged to.
struct Timed {
    files: ResultFiles,
    write: Vec<f64>,
    ledger: Option<Rc<RefCell<Ledger>>>,
    printed: usize,
}

impl Observer for Timed {
    fn phase(&mut self, iteration: usize, phase: Phase) {
        eprintln!("iteration {iteration}: {phase}");
        if let Some(l) = &self.ledger {
            let name = match phase {
                Phase::Remesh => "remesh",
                Phase::Measure => "measure",
                // The sizing charges its own phases; solving is not run here.
                Phase::Size | Phase::Solve => return,
            };
            l.borrow_mut().enter(iteration, name);
        }
    }
    fn record(
        &mut self,
        history: &History,
        best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh::formats::Error> {
        let k = history.iterations.len() - 1;
        if let Some(l) = &self.ledger {
            l.borrow_mut().enter(k, "files");
        }
        let t = Instant::now();
        self.files.record(history, best)?;
        self.write.resize(k + 1, 0.0);
        self.write[k] += t.elapsed().as_secs_f64();
        if let Some(l) = &self.ledger {
            let mut l = l.borrow_mut();
            l.enter(k, "between");
            // Each iteration's line as soon as it is done (a long run keeps what it did).
            while self.printed < history.iterations.len() {
                let r = &history.iterations[self.printed];
                l.print_row(
                    r.iteration,
                    r.vertices,
                    r.space.as_ref().map_or(0, |x| x.cells),
                    r.conforming_share,
                    r.seconds.remesh,
                );
                self.printed += 1;
            }
        }
        Ok(())
    }
}

/// CPU seconds of this process (every thread) and of its waited-for children, from
/// /proc/self/stat (fields 14–17, in clock ticks of 1/100 s: Linux's USER_HZ).
fn cpu() -> (f64, f64) {
    let stat = std::fs::read_to_string("/proc/self/stat").expect("/proc/self/stat (Linux)");
    // The command name (field 2) may hold spaces: the fields after it follow its ')'.
    let rest = &stat[stat.rfind(')').expect("a ')' in /proc/self/stat") + 2..];
    let f: Vec<f64> = rest.split_whitespace().map(|x| x.parse().unwrap_or(0.0)).collect();
    // rest starts at field 3: utime is field 14, so index 11.
    ((f[11] + f[12]) / 100.0, (f[13] + f[14]) / 100.0)
}

/// CPU seconds (own, children) and wall seconds charged to (iteration, phase) since the
/// last change of phase.
#[derive(Default)]
struct Ledger {
    at: Option<(usize, String, (f64, f64), Instant)>,
    spent: BTreeMap<(usize, String), (f64, f64, f64)>,
    /// Phase names in the order first met (the columns).
    order: Vec<String>,
}

impl Ledger {
    /// Charges the time since the last call to the phase then running, and starts
    /// `phase` of `iteration`.
    fn enter(&mut self, iteration: usize, phase: &str) {
        let now = (cpu(), Instant::now());
        if let Some((k, name, c, t)) = self.at.take() {
            let e = self.spent.entry((k, name.clone())).or_default();
            e.0 += now.0 .0 - c.0;
            e.1 += now.0 .1 - c.1;
            e.2 += t.elapsed().as_secs_f64();
            if !self.order.contains(&name) {
                self.order.push(name);
            }
        }
        self.at = Some((iteration, phase.to_string(), now.0, now.1));
    }

    fn get(&self, k: usize, phase: &str) -> (f64, f64, f64) {
        self.spent.get(&(k, phase.to_string())).copied().unwrap_or_default()
    }

    /// The sizing steps' names (everything charged that is not a fixed phase).
    fn steps(&self) -> Vec<&String> {
        const FIXED: [&str; 7] =
            ["topology", "graph", "gradation", "measure", "files", "between", "remesh"];
        self.order.iter().filter(|n| !FIXED.contains(&n.as_str())).collect()
    }

    /// One iteration: CPU seconds of each phase; own = everything but mmg3d's.
    fn print_row(&self, k: usize, vertices: usize, tets: usize, conform: f64, remesh_wall: f64) {
        let steps: f64 = self.steps().iter().map(|s| self.get(k, s).0).sum();
        let [topo, graph, grad, meas, files, between] =
            ["topology", "graph", "gradation", "measure", "files", "between"]
                .map(|p| self.get(k, p).0);
        let (remesh_own, mmg3d, _) = self.get(k, "remesh");
        let io = files + remesh_own;
        let own = topo + graph + steps + grad + meas + io + between;
        let ratio = if mmg3d > 0.0 { format!("{:.1}%", 100.0 * own / mmg3d) } else { "-".into() };
        println!(
            "{k:4} {vertices:9} {tets:9} {conform:7.3} {topo:8.2} {graph:6.2} {steps:7.2} {grad:7.2} {meas:7.2} {files:6.2} {remesh_own:7.2} {own:7.2} {mmg3d:8.2} {remesh_wall:8.1}  {ratio}"
        );
        let per: Vec<String> =
            self.steps().iter().map(|s| format!("{s} {:.2}", self.get(k, s).0)).collect();
        println!("       steps: {}", per.join(", "));
    }
}

/// The recipe's sizing as [`RecipeInSpace`] does it without a budget (the same calls),
/// each phase charged to the ledger.
struct LedgerSizing {
    recipe: Recipe,
    ledger: Rc<RefCell<Ledger>>,
    iteration: RefCell<usize>,
}

impl SpaceSizing for LedgerSizing {
    fn size(&self, mesh: &TaggedMesh) -> Result<SpaceField, SpaceSizingError> {
        let k = *self.iteration.borrow();
        let enter = |p: &str| self.ledger.borrow_mut().enter(k, p);
        enter("topology");
        let topology = Topology::from_mesh(mesh);
        enter("graph");
        let resolved = self.recipe.resolve(&topology)?;
        let space = SpaceMesh::new(mesh, &topology)?;
        let mut labels = BTreeMap::new();
        let mut observe = |e: StepEvent| match e {
            StepEvent::Started { index, label, .. } => {
                let name = labels.entry(index).or_insert(format!("{index}:{label}")).clone();
                enter(&name);
            }
            StepEvent::Finished { .. } => enter("gradation"),
        };
        let field = compute_size_field3(&space, &topology, &resolved.plan, &mut observe)?;
        let metric = field.tensors.iter().map(SizeTensor3::to_metric).collect();
        *self.iteration.borrow_mut() += 1;
        Ok(SpaceField { metric, warnings: field.warnings })
    }
}

/// The recipe at `path` with its sizes divided by `scale` (see the module header).
fn scaled_recipe(path: &Path, scale: f64) -> Recipe {
    let text = std::fs::read_to_string(path).expect("the recipe");
    let mut table: toml::Table = text.parse().expect("a TOML recipe");
    fn walk(v: &mut toml::Value, scale: f64) {
        const SIZES: [&str; 9] = [
            "size",
            "size_at_source",
            "size_at_max_distance",
            "min_size",
            "max_size",
            "hmin",
            "hmax",
            "h_min",
            "h_max",
        ];
        match v {
            toml::Value::Table(t) => {
                for (key, x) in t.iter_mut() {
                    let by = if SIZES.contains(&key.as_str()) {
                        scale
                    } else if key == "size_of_error" {
                        scale * scale
                    } else {
                        walk(x, scale);
                        continue;
                    };
                    if let Some(f) = x.as_float().or(x.as_integer().map(|i| i as f64)) {
                        *x = toml::Value::Float(f / by);
                    }
                }
            }
            toml::Value::Array(a) => a.iter_mut().for_each(|x| walk(x, scale)),
            _ => {}
        }
    }
    for (_, v) in table.iter_mut() {
        walk(v, scale);
    }
    Recipe::from_str(&table.to_string(), RecipeFormat::Toml, path).expect("the scaled recipe")
}

fn main() {
    if std::env::args().any(|a| a == "--list") {
        return;
    }
    let scale: f64 =
        std::env::var("ADAPT_SPACE_SCALE").ok().and_then(|s| s.parse().ok()).unwrap_or(1.0);
    match (std::env::var("ADAPT_SPACE_RECIPE"), std::env::var("ADAPT_SPACE_START")) {
        (Ok(recipe), Ok(start)) => with_recipe(Path::new(&recipe), Path::new(&start), scale),
        _ => analytic(scale),
    }
}

/// The recipe mode (see the module header).
fn with_recipe(recipe_path: &Path, start_path: &Path, scale: f64) {
    let iterations: usize =
        std::env::var("ADAPT_SPACE_ITERATIONS").ok().and_then(|s| s.parse().ok()).unwrap_or(2);
    let extra_args: Vec<String> = std::env::var("ADAPT_SPACE_MMG")
        .map(|s| s.split_whitespace().map(String::from).collect())
        .unwrap_or_default();
    let recipe = scaled_recipe(recipe_path, scale);
    let start = smartmesh::read_path(start_path, None).expect("the start mesh");
    let ledger = Rc::new(RefCell::new(Ledger::default()));
    let sizing =
        LedgerSizing { recipe: recipe.clone(), ledger: ledger.clone(), iteration: RefCell::new(0) };
    // The instrumented sizing is the loop's, bit for bit (outside the timed run).
    let ours = sizing.size(&start).expect("the field on the start");
    let loops = RecipeInSpace(&recipe).size(&start).expect("RecipeInSpace on the start");
    assert!(ours.metric == loops.metric, "the instrumented sizing differs from RecipeInSpace");
    *sizing.iteration.borrow_mut() = 0;
    *ledger.borrow_mut() = Ledger::default();

    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("adapted.meshb");
    let mut timed = Timed {
        files: ResultFiles::new(&out, None, Default::default()),
        write: Vec::new(),
        ledger: Some(ledger.clone()),
        printed: 0,
    };
    let mmg3d = adapter(
        AdapterKind::Mmg3d,
        AdapterOptions { extra_args: extra_args.clone(), ..Default::default() },
    )
    .expect("mmg3d_O3");
    let options = AdaptOptions {
        max_iterations: iterations,
        max_vertices: None,
        max_growth: None,
        ..Default::default()
    };
    println!(
        "adapt_space: {} with sizes / {scale}, from {} ({} vertices, {} tetrahedra), {} threads, mmg3d_O3 {}",
        recipe_path.display(),
        start_path.display(),
        start.points.len(),
        start.num_cells_of(CellKind::Tetra),
        rayon::current_num_threads(),
        extra_args.join(" ")
    );
    println!("CPU seconds; own = topology + graph + steps + gradation + measure + files + mmg3d I/O (+ the driver's bookkeeping); mmg3d = its process's CPU");
    println!("iter  vertices      tets  conform topology  graph   steps gradat. measure  files mmg3dIO     own    mmg3d  wall_rem  own/mmg3d");
    let t = Instant::now();
    let outcome =
        run_space(start, &sizing, mmg3d.as_ref(), &options, "start", "recipe", &mut timed).unwrap();
    ledger.borrow_mut().enter(usize::MAX, "end");
    let total = t.elapsed().as_secs_f64();
    let l = ledger.borrow();
    let (mut own_all, mut mmg_all) = (0.0, 0.0);
    for ((_, name), (own, child, _)) in &l.spent {
        own_all += own;
        if name == "remesh" {
            mmg_all += child;
        }
    }
    let ratio =
        if mmg_all > 0.0 { format!("{:.1}%", 100.0 * own_all / mmg_all) } else { "-".into() };
    println!(
        "total wall {total:.1} s; CPU: loop's own {own_all:.2} s, mmg3d {mmg_all:.2} s ({ratio}); {}",
        outcome.history.stopped
    );
}

/// The analytic mode (see the module header).
fn analytic(scale: f64) {
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
    let mut timed = Timed {
        files: ResultFiles::new(&out, None, Default::default()),
        write: Vec::new(),
        ledger: None,
        printed: 0,
    };
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
