//! Hessian recovery, `l2-projection` against `quadratic-fit`, on jittered grids of 10^5
//! and 10^6 vertices in the plane (the unit square, n × n squares each split along one
//! diagonal) and in space (the unit cube, n³ cubes each cut into the six Kuhn
//! tetrahedra), every inner vertex moved by up to 0.25 (plane) or 0.15 (space) of a step
//! along each axis, seeded. The field is sin(3x) cos(2y) + x²y, or
//! sin(2x) cos(1.5y) e^(z/2) + xyz in space. Each line: the mesh, the method, the
//! thread count, the wall time of `recover`/`recover3` (the best of `REPEAT` runs,
//! 3 below 10^6 vertices, 1 above), the wall time per vertex, and the best CPU time of
//! the process over the same runs (every thread; from /proc on Linux, in 1/100 s: a
//! figure for a machine shared with other jobs, where the wall time is the load's).
//!
//! `SMARTMESH_BENCH_MAX_VERTICES=n` skips the meshes above n vertices (default 1.1·10^6).
//! Run: `cargo bench -p smartmesh --bench recovery`.
#![allow(clippy::print_stdout, clippy::print_stderr)] // A benchmark prints what it measured.

use std::time::Instant;

use smartmesh::sizing::solution::{recover, recover3, Method, P1Mesh, P1Mesh3};
use smartmesh_test_support::grid::kuhn_box;
use smartmesh_test_support::{Generator, SplitMix64};

fn square(n: usize) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut rng = SplitMix64(7);
    let h = 1.0 / n as f64;
    let mut points = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..=n {
        for i in 0..=n {
            let mut p = [i as f64 * h, j as f64 * h];
            for (a, c) in [i, j].into_iter().enumerate() {
                let d = rng.range(-0.25, 0.25) * h;
                if c != 0 && c != n {
                    p[a] += d;
                }
            }
            points.push(p);
        }
    }
    let w = (n + 1) as u32;
    let mut triangles = Vec::with_capacity(2 * n * n);
    for j in 0..n as u32 {
        for i in 0..n as u32 {
            let v = j * w + i;
            triangles.push([v, v + 1, v + w + 1]);
            triangles.push([v, v + w + 1, v + w]);
        }
    }
    (points, triangles)
}

fn cube(n: usize) -> (Vec<[f64; 3]>, Vec<[u32; 4]>) {
    let mut mesh = kuhn_box(n, [1.0; 3]);
    let mut rng = SplitMix64(11);
    let h = 1.0 / n as f64;
    for p in &mut mesh.points {
        for x in p.iter_mut() {
            let d = rng.range(-0.15, 0.15) * h;
            if *x > 0.5 * h && *x < 1.0 - 0.5 * h {
                *x += d;
            }
        }
    }
    let tets = mesh
        .cells()
        .filter(|c| c.0 == smartmesh::formats::CellKind::Tetra)
        .map(|(_, v, _, _)| [v[0], v[1], v[2], v[3]])
        .collect();
    (mesh.points, tets)
}

/// CPU seconds of this process (every thread), from /proc/self/stat (fields 14 and 15,
/// in clock ticks of 1/100 s: Linux's USER_HZ); 0 where there is no /proc.
fn cpu() -> f64 {
    let Ok(stat) = std::fs::read_to_string("/proc/self/stat") else { return 0.0 };
    // The command name (field 2) may hold spaces: the fields after it follow its ')'.
    let rest = stat.rfind(')').map_or("", |i| &stat[i + 2..]);
    let f: Vec<f64> = rest.split_whitespace().map(|x| x.parse().unwrap_or(0.0)).collect();
    // rest starts at field 3: utime is field 14, so index 11.
    f.get(11).zip(f.get(12)).map_or(0.0, |(u, s)| (u + s) / 100.0)
}

/// The best wall time and the best CPU time (every thread) of `repeat` runs of `f` on a
/// pool of `threads`.
fn time(threads: usize, repeat: usize, f: impl Fn() + Sync) -> (f64, f64) {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    (0..repeat)
        .map(|_| {
            let (start, c) = (Instant::now(), cpu());
            pool.install(&f);
            (start.elapsed().as_secs_f64(), cpu() - c)
        })
        .fold((f64::INFINITY, f64::INFINITY), |a, b| (a.0.min(b.0), a.1.min(b.1)))
}

fn report(mesh: &str, n: usize, method: Method, threads: usize, (seconds, cpu): (f64, f64)) {
    let per = 1e6 * seconds / n as f64;
    println!(
        "{mesh} {n} vertices, {}, {threads} thread(s): {seconds:.3} s, {per:.2} µs/vertex, CPU {cpu:.2} s",
        method.name()
    );
}

fn main() {
    let max: usize = std::env::var("SMARTMESH_BENCH_MAX_VERTICES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_100_000);
    for n in [316, 1000] {
        let (points, triangles) = square(n);
        if points.len() > max {
            continue;
        }
        let values: Vec<f64> = points
            .iter()
            .map(|p| (3.0 * p[0]).sin() * (2.0 * p[1]).cos() + p[0] * p[0] * p[1])
            .collect();
        let mesh = P1Mesh::from_triangles(&points, &triangles).unwrap();
        let repeat = if points.len() < 1_000_000 { 3 } else { 1 };
        for method in Method::ALL {
            for threads in [1, 2] {
                let s = time(threads, repeat, || {
                    std::hint::black_box(recover(&mesh, &values, method).unwrap());
                });
                report("square", points.len(), method, threads, s);
            }
        }
    }
    for n in [46, 99] {
        let (points, tets) = cube(n);
        if points.len() > max {
            continue;
        }
        let values: Vec<f64> = points
            .iter()
            .map(|p| {
                (2.0 * p[0]).sin() * (1.5 * p[1]).cos() * (0.5 * p[2]).exp() + p[0] * p[1] * p[2]
            })
            .collect();
        let mesh = P1Mesh3::new(&points, &tets).unwrap();
        let repeat = if points.len() < 1_000_000 { 3 } else { 1 };
        for method in Method::ALL {
            for threads in [1, 2] {
                let s = time(threads, repeat, || {
                    std::hint::black_box(recover3(&mesh, &values, method).unwrap());
                });
                report("cube", points.len(), method, threads, s);
            }
        }
    }
}
