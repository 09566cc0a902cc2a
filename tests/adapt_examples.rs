//! The adaptation loop end to end with the native remesher, as `smartmesh adapt
//! GEOMETRY.poly --recipe R -o OUT` runs it: on every example of `examples/` and on random
//! planar straight-line graphs with recipes written for them. On each result: the loop
//! converged; at least 90% of the edges have metric length in [1/√2, √2]; every triangle
//! is counter-clockwise with a positive area; the ends of every boundary Line cell lie on
//! input segments with the cell's tag (within [`DRIFT`], 1e-9 of the bounding box's
//! diagonal: the `.poly`'s vertices stay vertices of every remeshing) and, along the input
//! polylines, the arcs between them tile each curve; every topological point of the starting mesh
//! (Vertex cells: the .poly's own points and the mesher's corners) is there with its tag
//! at its coordinates; the physical tags and names are those of the starting mesh; the
//! recipe's refinement shows. Also: malformed inputs and metrics that the other CLI tests
//! do not try are refused with exit status 2 and a message naming the file.
#![allow(clippy::print_stdout, clippy::print_stderr)] // What a test measured or skipped is printed for the log.

use std::collections::BTreeMap;
use std::path::Path;

use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::{run, start as starting_point, AdaptOptions};
use smartmesh::formats::{read_path, write_path, CellKind, TaggedMesh, WriteOptions};
use smartmesh::physical_tags;
use smartmesh::History;
use smartmesh::Recipe;
use smartmesh::{adapter, AdapterKind, AdapterOptions};
use smartmesh_test_support::measure::signed_area;

#[path = "support/examples.rs"]
mod support;

use support::{cpp_or_skip, examples, figures_in, grouped, readmes_with_figures, EXAMPLES};

#[path = "support/cli.rs"]
mod cli;
use cli::{bad, bundled};

fn xy(m: &TaggedMesh, v: usize) -> [f64; 2] {
    [m.points[v][0], m.points[v][1]]
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Distance from `p` to the segment [a, b].
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let e = [b[0] - a[0], b[1] - a[1]];
    let len2 = e[0] * e[0] + e[1] * e[1];
    let u = if len2 > 0.0 {
        (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    dist(p, [a[0] + u * e[0], a[1] + u * e[1]])
}

/// The input segments with one tag, as a graph on the .poly's vertices.
struct Polylines {
    points: Vec<[f64; 2]>,
    segments: Vec<[usize; 2]>,
    next: Vec<Vec<(usize, f64)>>,
    length: f64,
}

impl Polylines {
    fn new(poly: &TaggedMesh, tag: i32) -> Polylines {
        let points: Vec<[f64; 2]> = (0..poly.points.len()).map(|v| xy(poly, v)).collect();
        let segments: Vec<[usize; 2]> = poly
            .cells()
            .filter(|c| c.0 == CellKind::Line && c.2 == tag)
            .map(|c| [c.1[0] as usize, c.1[1] as usize])
            .collect();
        let mut next = vec![Vec::new(); points.len()];
        let mut length = 0.0;
        for &[a, b] in &segments {
            let l = dist(points[a], points[b]);
            next[a].push((b, l));
            next[b].push((a, l));
            length += l;
        }
        Polylines { points, segments, next, length }
    }

    /// The segments within `tol` of `p`.
    fn holding(&self, p: [f64; 2], tol: f64) -> Vec<[usize; 2]> {
        self.segments
            .iter()
            .copied()
            .filter(|s| to_segment(p, self.points[s[0]], self.points[s[1]]) <= tol)
            .collect()
    }

    /// The nearest point to `p` on these segments.
    fn foot(&self, p: [f64; 2], on: &[[usize; 2]]) -> [f64; 2] {
        let mut best = (f64::INFINITY, p);
        for s in on {
            let (a, b) = (self.points[s[0]], self.points[s[1]]);
            let e = [b[0] - a[0], b[1] - a[1]];
            let u = (((p[0] - a[0]) * e[0] + (p[1] - a[1]) * e[1]) / (e[0] * e[0] + e[1] * e[1]))
                .clamp(0.0, 1.0);
            let f = [a[0] + u * e[0], a[1] + u * e[1]];
            if dist(p, f) < best.0 {
                best = (dist(p, f), f);
            }
        }
        best.1
    }

    /// The length of the shortest path from `p` to `q` along the segments (Dijkstra, brute
    /// force), or None when `p` or `q` is on none of them.
    fn arc(&self, p: [f64; 2], q: [f64; 2], tol: f64) -> Option<f64> {
        let (ps, qs) = (self.holding(p, tol), self.holding(q, tol));
        if ps.is_empty() || qs.is_empty() {
            return None;
        }
        let (p, q) = (self.foot(p, &ps), self.foot(q, &qs));
        let mut best = f64::INFINITY;
        if ps.iter().any(|s| qs.contains(s)) {
            best = dist(p, q);
        }
        let mut d = vec![f64::INFINITY; self.points.len()];
        let mut heap = std::collections::BinaryHeap::new();
        for s in &ps {
            for &v in s {
                let l = dist(p, self.points[v]);
                if l < d[v] {
                    d[v] = l;
                    heap.push((std::cmp::Reverse(l.to_bits()), v));
                }
            }
        }
        let to_q: Vec<(usize, f64)> =
            qs.iter().flat_map(|s| s.iter().map(|&v| (v, dist(self.points[v], q)))).collect();
        while let Some((std::cmp::Reverse(bits), v)) = heap.pop() {
            let dv = f64::from_bits(bits);
            if dv > d[v] {
                continue;
            }
            if dv >= best {
                break;
            }
            for &(w, l) in &to_q {
                if w == v {
                    best = best.min(dv + l);
                }
            }
            for &(w, l) in &self.next[v] {
                if dv + l < d[w] {
                    d[w] = dv + l;
                    heap.push((std::cmp::Reverse((dv + l).to_bits()), w));
                }
            }
        }
        Some(best)
    }
}

/// What one run gave: the starting mesh, the result as written, its history.
struct Adapted {
    start: TaggedMesh,
    result: TaggedMesh,
    history: History,
}

/// `smartmesh adapt POLY --recipe RECIPE -o DIR/out.msh` through the library, as the
/// command does it: the starting mesh, the native remesher, the default options, the
/// result files; the result is read back from the file.
fn adapt(poly: &Path, recipe: &Path) -> Adapted {
    let recipe_model =
        Recipe::from_path(recipe).unwrap_or_else(|e| panic!("{}: {e}", recipe.display()));
    let starting = starting_point(poly, None).unwrap_or_else(|e| panic!("{}: {e}", poly.display()));
    let start = starting.mesh;
    let remesher = adapter(
        AdapterKind::Native,
        AdapterOptions { keep_points: starting.geometry_points, ..Default::default() },
    )
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    let mut files = ResultFiles::new(&out, None, WriteOptions::default());
    let outcome = run(
        start.clone(),
        &recipe_model,
        remesher.as_ref(),
        &AdaptOptions::default(),
        &poly.display().to_string(),
        &recipe.display().to_string(),
        &mut files,
    )
    .unwrap_or_else(|e| panic!("{}: {e}", poly.display()));
    assert!(outcome.failure.is_none(), "{}: {:?}", poly.display(), outcome.failure);
    let result = read_path(&out, None).unwrap();
    let on_disk = History::from_json(&std::fs::read_to_string(&files.history).unwrap()).unwrap();
    // The history on disk is the run's (its numbers read back to within a few ulps: the
    // JSON reader's float parsing is not always correctly rounded).
    let h = &outcome.history;
    assert_eq!(
        (on_disk.converged, on_disk.best_iteration, &on_disk.stopped, on_disk.iterations.len()),
        (h.converged, h.best_iteration, &h.stopped, h.iterations.len()),
        "{}: the history on disk",
        poly.display()
    );
    for (a, b) in on_disk.iterations.iter().zip(&h.iterations) {
        assert_eq!(
            (a.iteration, a.vertices, a.triangles),
            (b.iteration, b.vertices, b.triangles),
            "{}: the history on disk",
            poly.display()
        );
        for (x, y) in [
            (a.conforming_share, b.conforming_share),
            (a.mean_quality, b.mean_quality),
            (a.min_quality, b.min_quality),
            (a.mean_edge_length, b.mean_edge_length),
        ] {
            assert!(
                (x - y).abs() <= 1e-14 * y.abs(),
                "{}: the history on disk has {x}, the run {y}",
                poly.display()
            );
        }
    }
    Adapted { start, result, history: outcome.history }
}

fn bbox_diagonal(m: &TaggedMesh) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &m.points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    dist(lo, hi)
}

/// Every edge of the triangles once: (a, b) with a < b.
fn edges(m: &TaggedMesh) -> Vec<(usize, usize)> {
    let mut e: Vec<(usize, usize)> = m
        .cells()
        .filter(|c| c.0 == CellKind::Triangle)
        .flat_map(|(_, n, _, _)| {
            [
                (n[0] as usize, n[1] as usize),
                (n[1] as usize, n[2] as usize),
                (n[2] as usize, n[0] as usize),
            ]
        })
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    e.sort_unstable();
    e.dedup();
    e
}

/// The figures printed for a run.
struct Figures {
    vertices: usize,
    triangles: usize,
    share: f64,
    mean_quality: f64,
    min_quality: f64,
    iterations: usize,
    finest: f64,
    smallest_near_finest: f64,
    median_edge: f64,
}

/// Every check on one run; `what` names it in messages.
fn check(what: &str, poly_path: &Path, run: &Adapted, boundary: f64) -> Figures {
    let (start, mesh, h) = (&run.start, &run.result, &run.history);

    // The loop converged within the iteration limit, and the result is the best mesh.
    assert!(h.converged, "{what}: not converged: {}", h.stopped);
    assert!(h.iterations.len() >= 2, "{what}: no remeshing");
    let best = &h.iterations[h.best_iteration];
    assert!(
        best.conforming_share >= 0.9,
        "{what}: best conforming share {} (iteration {})",
        best.conforming_share,
        h.best_iteration
    );
    assert!(
        h.iterations.iter().all(|r| r.conforming_share <= best.conforming_share),
        "{what}: the best is not the most conforming"
    );
    assert_eq!(mesh.points.len(), best.vertices, "{what}: the written mesh is the best");

    // Only triangles, lines and points; every triangle counter-clockwise with a positive area.
    let mut triangles = 0;
    for (kind, n, _, _) in mesh.cells() {
        assert!(
            matches!(kind, CellKind::Triangle | CellKind::Line | CellKind::Vertex),
            "{what}: a {kind:?} cell"
        );
        if kind == CellKind::Triangle {
            triangles += 1;
            let a = signed_area(
                xy(mesh, n[0] as usize),
                xy(mesh, n[1] as usize),
                xy(mesh, n[2] as usize),
            );
            assert!(a > 0.0, "{what}: triangle {n:?} has signed area {a}");
        }
    }
    assert_eq!(triangles, best.triangles, "{what}: triangles");

    // The boundary: each end of every Line cell lies on an input segment with the cell's
    // tag (within `boundary` times the bounding box's diagonal), and along the input
    // polylines of each tag the arcs between the feet of its Line cells' ends add up to
    // the polylines' length (they tile them, no gap, no overlap; the remesher may drop
    // input vertices between two of its boundary vertices, so a Line cell may be a chord
    // of the input polyline).
    let poly = read_path(poly_path, None).unwrap();
    let tol = boundary * bbox_diagonal(&poly);
    let mut arcs: BTreeMap<i32, f64> = BTreeMap::new();
    let mut lines = 0;
    let graphs: BTreeMap<i32, Polylines> = physical_tags(&poly)
        .into_iter()
        .filter(|t| t.0 == 1)
        .map(|(_, t)| (t, Polylines::new(&poly, t)))
        .collect();
    for (kind, n, tag, _) in mesh.cells() {
        if kind != CellKind::Line {
            continue;
        }
        lines += 1;
        let (p, q) = (xy(mesh, n[0] as usize), xy(mesh, n[1] as usize));
        let g = graphs.get(&tag).unwrap_or_else(|| {
            panic!("{what}: line {p:?}–{q:?} has tag {tag}, no input segment has")
        });
        let arc = g.arc(p, q, tol).unwrap_or_else(|| panic!("{what}: line {p:?}–{q:?} (tag {tag}): an end lies on no input segment with tag {tag}"));
        *arcs.entry(tag).or_default() += arc;
    }
    let segs = poly.cells().filter(|c| c.0 == CellKind::Line).count();
    assert!(lines > 0, "{what}: no boundary line");
    for (tag, g) in &graphs {
        let covered = arcs.get(tag).copied().unwrap_or(0.0);
        assert!(
            (covered - g.length).abs() <= boundary.max(1e-9) * g.length,
            "{what}: curve {tag} of length {}: the arcs of its lines add up to {covered}",
            g.length
        );
    }
    eprintln!("{what}: {lines} boundary lines on {segs} input segments");

    // Topological points: every Vertex cell of the start, same tags, same coordinates.
    let vertex_cells = |m: &TaggedMesh| -> Vec<(i32, i32, [u64; 2])> {
        let mut v: Vec<_> = m
            .cells()
            .filter(|c| c.0 == CellKind::Vertex)
            .map(|(_, n, p, g)| {
                (p, g, [m.points[n[0] as usize][0].to_bits(), m.points[n[0] as usize][1].to_bits()])
            })
            .collect();
        v.sort_unstable();
        v
    };
    let (before, after) = (vertex_cells(start), vertex_cells(mesh));
    assert!(!before.is_empty(), "{what}: the starting mesh has no Vertex cell");
    for p in &before {
        assert!(
            after.binary_search(p).is_ok(),
            "{what}: point (tags {}, {}) at ({}, {}) lost",
            p.0,
            p.1,
            f64::from_bits(p.2[0]),
            f64::from_bits(p.2[1])
        );
    }

    // Tags and names.
    assert_eq!(physical_tags(mesh), physical_tags(start), "{what}: physical tags");
    assert_eq!(mesh.tag_names, start.tag_names, "{what}: tag names");

    // The refinement: about the vertex with the smallest size of the field, the smallest
    // edge is at least 5 times smaller than the median edge where the field is coarse
    // (both ends at sizes at least half the largest).
    let (hs1, hs2) = (&mesh.point_data["h1"], &mesh.point_data["h2"]);
    let e = edges(mesh);
    let mut used = vec![false; mesh.points.len()];
    for &(a, b) in &e {
        used[a] = true;
        used[b] = true;
    }
    let h_min = |v: usize| hs1.values[v].min(hs2.values[v]);
    let h_max = |v: usize| hs1.values[v].max(hs2.values[v]);
    let finest = (0..mesh.points.len())
        .filter(|&v| used[v])
        .min_by(|&a, &b| h_min(a).total_cmp(&h_min(b)))
        .unwrap();
    let coarsest = (0..mesh.points.len()).filter(|&v| used[v]).map(h_min).fold(0.0f64, f64::max);
    let centre = xy(mesh, finest);
    let radius = 3.0 * h_max(finest);
    let smallest_near = e
        .iter()
        .filter(|&&(a, b)| {
            dist(xy(mesh, a), centre) <= radius || dist(xy(mesh, b), centre) <= radius
        })
        .map(|&(a, b)| dist(xy(mesh, a), xy(mesh, b)))
        .fold(f64::INFINITY, f64::min);
    let mut coarse: Vec<f64> = e
        .iter()
        .filter(|&&(a, b)| h_min(a) >= 0.5 * coarsest && h_min(b) >= 0.5 * coarsest)
        .map(|&(a, b)| dist(xy(mesh, a), xy(mesh, b)))
        .collect();
    assert!(!coarse.is_empty(), "{what}: no edge where the field is coarse");
    coarse.sort_by(f64::total_cmp);
    let median = coarse[coarse.len() / 2];
    // Near the finest size the smallest edge is well below the edges where the field is
    // coarse, or has the finest size itself (an edge conforms up to √2·h).
    assert!(
        smallest_near * 5.0 <= median
            || smallest_near <= std::f64::consts::SQRT_2 * h_min(finest),
        "{what}: smallest edge near the finest size ({} at {centre:?}) is {smallest_near}, median edge where the field is coarse {median}",
        h_min(finest)
    );

    Figures {
        vertices: best.vertices,
        triangles: best.triangles,
        share: best.conforming_share,
        mean_quality: best.mean_quality,
        min_quality: best.min_quality,
        iterations: h.iterations.len() - 1,
        finest: h_min(finest),
        smallest_near_finest: smallest_near,
        median_edge: median,
    }
}

fn print(what: &str, f: &Figures) {
    eprintln!(
        "{what}: {} vertices, {} triangles, {:.1}% conforming, quality mean {:.3} min {:.3}, {} iterations; finest size {:.5}, smallest edge there {:.5}, median coarse edge {:.5}",
        f.vertices,
        f.triangles,
        100.0 * f.share,
        f.mean_quality,
        f.min_quality,
        f.iterations,
        f.finest,
        f.smallest_near_finest,
        f.median_edge
    );
}

/// How far (times the bounding box's diagonal) a boundary vertex of the result may be
/// from the input segments: rounding only. The loop keeps the `.poly`'s vertices as
/// vertices of every remeshing (`AdapterOptions::keep_points`), so every boundary edge
/// stays on an input segment, and new boundary vertices are placed on those segments.
const DRIFT: f64 = 1e-9;

fn example(folder: &str, boundary: f64) {
    let recipe = EXAMPLES.iter().find(|e| e.0 == folder).unwrap().1;
    if recipe.ends_with(".cfg")
        && std::fs::read_to_string(examples().join(recipe)).unwrap().contains("#define")
        && !cpp_or_skip()
    {
        return;
    }
    let poly = examples().join(folder).join("geometry.poly");
    let run = adapt(&poly, &examples().join(recipe));
    let f = check(folder, &poly, &run, boundary);
    print(folder, &f);
    readme_figures_agree(folder, &poly, &examples().join(recipe));
}

/// The figures the READMEs print of example `folder` (between `<!--fig:…-->` comments,
/// rewritten by `bash examples/run.sh --update-figures`) are those of `smartmesh adapt`
/// run as run.sh runs it (the command line sets up periodic sides and the LAYER skin that
/// the library run above leaves out), but the seconds: the run is deterministic (the same
/// on every machine and thread count), its time is not.
fn readme_figures_agree(folder: &str, poly: &Path, recipe: &Path) {
    let dir = tempfile::tempdir().unwrap();
    let (out, history) = (dir.path().join("out.msh"), dir.path().join("out.history.json"));
    let path = |p: &Path| p.to_str().unwrap().to_string();
    let o = cli::run(&[
        "adapt",
        &path(poly),
        "--recipe",
        &path(recipe),
        "-o",
        &path(&out),
        "--history",
        &path(&history),
    ]);
    assert_eq!(o.status.code(), Some(0), "{folder}: {}", cli::stderr(&o));
    let h = History::from_json(&std::fs::read_to_string(&history).unwrap()).unwrap();
    let best = &h.iterations[h.best_iteration];
    let f = Figures {
        vertices: best.vertices,
        triangles: best.triangles,
        share: best.conforming_share,
        mean_quality: best.mean_quality,
        min_quality: best.min_quality,
        iterations: h.iterations.len() - 1,
        finest: 0.0,
        smallest_near_finest: 0.0,
        median_edge: 0.0,
    };
    let end = if h.converged { "converged" } else { h.stopped.as_str() };
    // run.sh's result line, but the seconds.
    let line = format!(
        "{folder:24} {:7} vertices {:7} triangles  {:.1}% conforming  quality {:.3} mean {:.3} min  {} iterations  ({end})",
        f.vertices,
        f.triangles,
        100.0 * f.share,
        f.mean_quality,
        f.min_quality,
        f.iterations
    );
    let without_seconds = |l: &str| -> String {
        match l.rsplit_once(" s  (") {
            Some((head, tail)) => {
                let cut = head.trim_end_matches(|c: char| c.is_ascii_digit() || c == '.');
                format!("{cut}({tail}")
            }
            None => l.to_string(),
        }
    };
    let mut checked = 0;
    for readme in readmes_with_figures() {
        for fig in figures_in(&readme) {
            let Some(k) = fig.examples.iter().position(|e| e == folder) else { continue };
            let expected = match fig.field.as_str() {
                "vertices" => grouped(f.vertices),
                "triangles" => grouped(f.triangles),
                "conforming" => format!("{:.1}", 100.0 * f.share),
                "quality-mean" => format!("{:.3}", f.mean_quality),
                "quality-min" => format!("{:.3}", f.min_quality),
                "iterations" => f.iterations.to_string(),
                "seconds" => continue,
                "line" => {
                    let lines: Vec<&str> = fig
                        .text
                        .lines()
                        .filter(|l| !l.is_empty() && !l.starts_with("```"))
                        .collect();
                    assert_eq!(
                        without_seconds(lines.get(k).copied().unwrap_or_default()),
                        line,
                        "{}: the result line of {folder} is not this run's (`bash examples/run.sh --update-figures` rewrites it)",
                        fig.place
                    );
                    checked += 1;
                    continue;
                }
                other => panic!("{}: unknown figure field `{other}`", fig.place),
            };
            assert_eq!(
                fig.text, expected,
                "{}: the README's {} of {folder} is not this run's (`bash examples/run.sh --update-figures` rewrites it)",
                fig.place, fig.field
            );
            checked += 1;
        }
    }
    assert!(checked > 0, "no README prints the figures of {folder}");
}

#[test]
fn naca0012_agard01_adapts() {
    example("naca0012-agard01", DRIFT);
}

#[test]
fn naca0012_agard02_adapts() {
    example("naca0012-agard02", DRIFT);
}

#[test]
fn naca0012_agard03_adapts() {
    example("naca0012-agard03", DRIFT);
}

#[test]
fn naca0012_agard04_adapts() {
    example("naca0012-agard04", DRIFT);
}

#[test]
fn naca0012_agard05_adapts() {
    example("naca0012-agard05", DRIFT);
}

#[test]
fn gamm_a7_viscous_adapts() {
    example("gamm-a7-viscous", DRIFT);
}

#[test]
fn u_duct_adapts() {
    example("u-duct", DRIFT);
}

#[test]
fn distributor_1_narrow_adapts() {
    example("distributor/1-narrow", DRIFT);
}

#[test]
fn distributor_2_thick_adapts() {
    example("distributor/2-thick", DRIFT);
}

#[test]
fn distributor_3_s_shaped_adapts() {
    example("distributor/3-s-shaped", DRIFT);
}

#[test]
fn every_example_has_a_test() {
    let tested = [
        "naca0012-agard01",
        "gamm-a7-viscous",
        "naca0012-agard02",
        "naca0012-agard03",
        "naca0012-agard04",
        "naca0012-agard05",
        "u-duct",
        "distributor/1-narrow",
        "distributor/2-thick",
        "distributor/3-s-shaped",
    ];
    assert_eq!(EXAMPLES.iter().map(|e| e.0).collect::<Vec<_>>(), tested);
    for (folder, recipe) in EXAMPLES {
        assert!(
            examples().join(folder).join("geometry.poly").is_file()
                && examples().join(recipe).is_file(),
            "{folder}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// Random planar straight-line graphs
// ---------------------------------------------------------------------------------------

use smartmesh_test_support::{Generator, XorShift64Star as Rng};

/// The face tag, the tag of the outer polygon's first vertex (a topological point of
/// its own), and the first tag of the holes' curves.
const FACE: i32 = 7;
const CORNER: i32 = 100;
const HOLE_TAGS: i32 = 50;

/// A random PSLG: a star-shaped outer polygon of 8–20 vertices at radii 0.5–1.5 about
/// the origin, its sides in 2–4 runs tagged 1, 2, …, its first vertex a point tagged
/// [`CORNER`]; 0–2 polygonal holes (tags 50, 51) at 0.2 from the origin, of radius at
/// most 0.15 (inside the polygon: a side between vertices at radius ≥ 0.5 less than
/// 2π·1.3/8 apart stays 0.43 from the origin); one region, seeded at the origin.
/// Returns the .poly text, the curve tags of the outer polygon and the number of holes.
fn random_poly(rng: &mut Rng) -> (String, Vec<i32>, usize) {
    let n = rng.int(8, 20);
    let mut pts: Vec<[f64; 2]> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * (i as f64 + rng.range(-0.3, 0.3)) / n as f64;
            let r = rng.range(0.5, 1.5);
            [r * a.cos(), r * a.sin()]
        })
        .collect();
    let groups = rng.int(2, 4);
    // Run k of the sides starts at side starts[k] (side i joins vertex i and i + 1).
    let mut starts: Vec<usize> = vec![0];
    while starts.len() < groups {
        let s = rng.int(1, n - 1);
        if !starts.contains(&s) {
            starts.push(s);
        }
    }
    starts.sort_unstable();
    let side_tag = |i: usize| starts.iter().rposition(|&s| s <= i).unwrap() as i32 + 1;
    let mut markers: Vec<i32> = vec![0; n];
    markers[0] = CORNER;
    let mut segs: Vec<(usize, usize, i32)> =
        (0..n).map(|i| (i, (i + 1) % n, side_tag(i))).collect();

    let holes = rng.int(0, 2);
    let phi = rng.range(0.0, std::f64::consts::TAU);
    let mut hole_points = Vec::new();
    for h in 0..holes {
        let c = [
            0.2 * (phi + h as f64 * std::f64::consts::PI).cos(),
            0.2 * (phi + h as f64 * std::f64::consts::PI).sin(),
        ];
        let k = rng.int(3, 6);
        let r = rng.range(0.08, 0.15);
        let turn = rng.range(0.0, std::f64::consts::TAU);
        let first = pts.len();
        for j in 0..k {
            let a = turn + std::f64::consts::TAU * j as f64 / k as f64;
            pts.push([c[0] + r * a.cos(), c[1] + r * a.sin()]);
            markers.push(0);
        }
        for j in 0..k {
            segs.push((first + j, first + (j + 1) % k, HOLE_TAGS + h as i32));
        }
        hole_points.push(c);
    }

    let mut s = format!("{} 2 0 1\n", pts.len());
    for (i, p) in pts.iter().enumerate() {
        s += &format!("{} {:?} {:?} {}\n", i + 1, p[0], p[1], markers[i]);
    }
    s += &format!("{} 1\n", segs.len());
    for (i, &(a, b, t)) in segs.iter().enumerate() {
        s += &format!("{} {} {} {}\n", i + 1, a + 1, b + 1, t);
    }
    s += &format!("{}\n", hole_points.len());
    for (i, c) in hole_points.iter().enumerate() {
        s += &format!("{} {:?} {:?}\n", i + 1, c[0], c[1]);
    }
    s += &format!("1\n1 0 0 {FACE} -1\n");
    (s, (1..=groups as i32).collect(), holes)
}

/// A recipe for a random PSLG: a uniform size, a boundary layer on curve `wall`, and,
/// when `point`, a refinement about the [`CORNER`] point.
fn random_recipe(rng: &mut Rng, wall: i32, point: bool) -> String {
    let h0 = rng.range(0.05, 0.1);
    let normal = rng.range(0.004, 0.01);
    let mut s = format!(
        "[global]\nhmin = 0.001\nhmax = 0.3\nmax_aspect_ratio = 20\n\
         [regions]\nWall = [{wall}]\nAll = [{FACE}]\nCorner = [{CORNER}]\n\
         [functions.N]\nkind = \"distance\"\nsize_at_source = {normal}\nsize_at_max_distance = {h0}\nmax_distance = 0.2\nexponent = 1.0\n\
         [functions.T]\nkind = \"distance\"\nsize_at_source = 0.03\nsize_at_max_distance = {h0}\nmax_distance = 0.2\nexponent = 1.0\n\
         [functions.P]\nkind = \"distance\"\nsize_at_source = 0.005\nsize_at_max_distance = {h0}\nmax_distance = 0.2\nexponent = 1.5\n\
         [[algorithms]]\ntype = \"uniform\"\nsize = {h0}\nregions = [\"All\"]\n\
         [[algorithms]]\ntype = \"distance_to_border\"\nperpendicular = \"N\"\nparallel = \"T\"\nregions = [\"Wall\"]\n"
    );
    if point {
        s += "[[algorithms]]\ntype = \"distance_to_point\"\nfunction = \"P\"\nregions = [\"Corner\"]\n";
    }
    s
}

fn random_case(seed: u64, boundary: f64) {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ seed.wrapping_mul(0x1000_0000_01b3));
    rng.next_u64();
    let (poly_text, tags, holes) = random_poly(&mut rng);
    let wall = tags[rng.int(0, tags.len() - 1)];
    let point = rng.unit() < 0.5;
    let recipe_text = random_recipe(&mut rng, wall, point);
    let dir = tempfile::tempdir().unwrap();
    let poly = dir.path().join(format!("random-{seed}.poly"));
    let recipe = dir.path().join(format!("random-{seed}.toml"));
    std::fs::write(&poly, &poly_text).unwrap();
    std::fs::write(&recipe, &recipe_text).unwrap();
    let what = format!(
        "random PSLG, seed {seed} ({} curve tags, {holes} holes, wall {wall}{})",
        tags.len(),
        if point { ", point" } else { "" }
    );
    let run = adapt(&poly, &recipe);
    let f = check(&what, &poly, &run, boundary);
    print(&what, &f);
    assert!(f.iterations <= AdaptOptions::default().max_iterations);
}

#[test]
fn random_pslgs_adapt_validly() {
    for seed in 1..=16 {
        random_case(seed, DRIFT);
    }
}

#[test]
fn the_random_generator_varies_its_cases() {
    // The cases differ: vertex counts, hole counts and tag counts are not all equal.
    let mut seen = std::collections::BTreeSet::new();
    let mut holes = std::collections::BTreeSet::new();
    for seed in 1..=16u64 {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ seed.wrapping_mul(0x1000_0000_01b3));
        rng.next_u64();
        let (text, tags, h) = random_poly(&mut rng);
        seen.insert((text.lines().next().unwrap().to_string(), tags.len()));
        holes.insert(h);
    }
    assert!(seen.len() >= 8, "{seen:?}");
    assert!(holes.len() >= 2, "{holes:?}");
}

// ---------------------------------------------------------------------------------------
// Malformed inputs and metrics on the command line
// ---------------------------------------------------------------------------------------

/// Metrics that tests/remesh_cli.rs does not try: NaN in a format that reads it (the
/// vertex is named), a symmetric tensor with positive diagonal but negative determinant,
/// and an unsymmetric one.
#[test]
fn remesh_refuses_more_bad_metrics_naming_file_and_vertex() {
    let dir = tempfile::tempdir().unwrap();
    let field = dir.path().join("field.vtu");
    let o = cli::run(&[
        "size",
        &bundled("cylinder.msh"),
        "--recipe",
        &bundled("cylinder.toml"),
        "-o",
        field.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
    let base = read_path(&field, None).unwrap();
    let cyl = bundled("cylinder.msh");
    let out = dir.path().join("x.vtu");
    let used = base.cells().find(|c| c.0 == CellKind::Triangle).unwrap().1[1];
    let remesh = |name: &str, m: &TaggedMesh| -> String {
        let p = dir.path().join(name);
        write_path(&p, m, None, &WriteOptions::default()).unwrap();
        bad(&cli::run(&[
            "remesh",
            &cyl,
            "--metric",
            p.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]))
    };
    let with = |f: &dyn Fn(&mut [f64])| {
        let mut m = base.clone();
        m.point_data.retain(|k, _| k == "metric");
        let a = m.point_data.get_mut("metric").unwrap();
        f(&mut a.values[used as usize * 9..used as usize * 9 + 9]);
        m
    };
    // NaN through Gmsh's $NodeData, a text format that reads it as a number.
    let err = remesh("nan.msh", &with(&|t| t[4] = f64::NAN));
    assert!(
        err.contains("nan.msh")
            && err.contains(&format!("vertex {used}"))
            && err.contains("not finite"),
        "{err}"
    );
    // Positive diagonal, determinant < 0.
    let err = remesh(
        "indefinite.vtu",
        &with(&|t| {
            let d = 2.0 * (t[0] * t[4]).sqrt();
            t[1] = d;
            t[3] = d;
        }),
    );
    assert!(
        err.contains("indefinite.vtu")
            && err.contains(&format!("vertex {used}"))
            && err.contains("not positive definite"),
        "{err}"
    );
    // Unsymmetric.
    let err = remesh("unsymmetric.vtu", &with(&|t| t[1] += 0.5 * t[0]));
    assert!(
        err.contains("unsymmetric.vtu")
            && err.contains(&format!("vertex {used}"))
            && err.contains("not symmetric"),
        "{err}"
    );
    assert!(!out.exists(), "no output for a bad metric");
}

/// `adapt` on a .poly whose segments cross, and with a recipe naming a tag number the
/// geometry lacks: exit 2, naming the file, nothing written.
#[test]
fn adapt_refuses_crossing_segments_and_absent_tags() {
    let dir = tempfile::tempdir().unwrap();
    let recipe = dir.path().join("r.toml");
    let mut rng = Rng(42);
    std::fs::write(&recipe, random_recipe(&mut rng, 1, true)).unwrap();
    let out = dir.path().join("o.msh");

    let cross = dir.path().join("cross.poly");
    std::fs::write(&cross, "4 2 0 1\n1 0 0 100\n2 1 0 0\n3 1 1 0\n4 0 1 0\n6 1\n1 1 2 1\n2 2 3 1\n3 3 4 2\n4 4 1 2\n5 1 3 1\n6 2 4 1\n0\n1\n1 0.5 0.25 7 -1\n").unwrap();
    let err = bad(&cli::run(&[
        "adapt",
        cross.to_str().unwrap(),
        "-r",
        recipe.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(err.contains("cross.poly") && err.contains("segment 5 crosses segment 6"), "{err}");
    assert!(!out.exists() && !dir.path().join("o.history.json").exists());

    // The same square without the diagonals and without point 100.
    let square = dir.path().join("square.poly");
    std::fs::write(&square, "4 2 0 1\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n4 1\n1 1 2 1\n2 2 3 1\n3 3 4 2\n4 4 1 2\n0\n1\n1 0.5 0.25 7 -1\n").unwrap();
    let err = bad(&cli::run(&[
        "adapt",
        square.to_str().unwrap(),
        "-r",
        recipe.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(
        err.contains("square.poly")
            && err.contains("r.toml")
            && err.contains("tag 100, which the mesh does not have"),
        "{err}"
    );
    assert!(!out.exists() && !dir.path().join("o.history.json").exists());
}
