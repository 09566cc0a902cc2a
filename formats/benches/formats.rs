//! Read and write a mesh of about 1.5 million triangles in every format, next to a
//! plain memory copy of the same bytes (the floor for binary formats).
//!
//!   cargo bench -p smartmesh-formats --bench formats
//!   SMARTMESH_BENCH_N=200 cargo bench ...   # a smaller grid for a quick look
//!   SMARTMESH_BENCH_ONLY=vtk42_binary,vtu_appended_raw cargo bench ...   # some cases only
//!     (and only their files written: what a profiler should see)
//!   GLIBC_TUNABLES=glibc.malloc.mmap_threshold=131072 cargo bench ...   # fresh memory
//!     for every large buffer, in the copy and in the read alike. By default glibc
//!     moves its mmap threshold as buffers are freed, so a buffer of a given size is
//!     fresh pages in one run and reused heap in the next: the binary ratios then
//!     swing (a Medit read took 30 or 55 ms in alternate runs of one build). A fixed
//!     threshold makes every run pay what a one-shot `smartmesh convert` pays.
//!
//! The files are also left in `target/bench-meshes/` so that `benches/compare_meshio.py`
//! times meshio on the very same bytes in the same session (see BENCHMARKS.md).

use smartmesh_formats::{GmshWrite, MeditWrite, VtkWrite};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, SamplingMode, Throughput};
use smartmesh_formats::{
    read_bytes, sym2_to_tensor9, write_bytes, CellBlock, CellKind, DataArray, Format, GmshVersion,
    MemorySiblings, ReadContext, TaggedMesh, VtuEncoding, WriteOptions,
};

/// A structured grid of (n-1)^2 * 2 triangles on [0,1]^2 with jittered coordinates,
/// four tagged sides, one face tag and a metric tensor per point.
fn big_mesh(n: usize) -> TaggedMesh {
    let mut m = TaggedMesh::new();
    let h = 1.0 / (n - 1) as f64;
    for j in 0..n {
        for i in 0..n {
            // Irrational-looking jitter so the decimals are not short.
            let jx =
                if i > 0 && i < n - 1 { 0.2 * h * ((i * 7 + j * 13) as f64).sin() } else { 0.0 };
            let jy =
                if j > 0 && j < n - 1 { 0.2 * h * ((i * 11 + j * 5) as f64).cos() } else { 0.0 };
            m.points.push([i as f64 * h + jx, j as f64 * h + jy, 0.0]);
        }
    }
    let id = |i: usize, j: usize| j * n + i;
    let mut lines = CellBlock::new(CellKind::Line);
    for k in 0..n - 1 {
        lines.push(&[id(k, 0), id(k + 1, 0)], 1, 1);
        lines.push(&[id(n - 1, k), id(n - 1, k + 1)], 2, 2);
        lines.push(&[id(k + 1, n - 1), id(k, n - 1)], 3, 3);
        lines.push(&[id(0, k + 1), id(0, k)], 4, 4);
    }
    let mut tris = CellBlock::new(CellKind::Triangle);
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            tris.push(&[id(i, j), id(i + 1, j), id(i + 1, j + 1)], 10, 1);
            tris.push(&[id(i, j), id(i + 1, j + 1), id(i, j + 1)], 10, 1);
        }
    }
    m.blocks = vec![lines, tris];
    for (t, name) in [(1, "Bottom"), (2, "Right"), (3, "Top"), (4, "Left")] {
        m.tag_names.insert((1, t), name.into());
    }
    m.tag_names.insert((2, 10), "Domain".into());
    let metric: Vec<f64> = m
        .points
        .iter()
        .flat_map(|p| {
            let hy = 0.001 + p[1] * 0.1;
            sym2_to_tensor9(1.0 / (0.1 * 0.1), 0.0, 1.0 / (hy * hy), 1.0)
        })
        .collect();
    m.point_data.insert("metric".into(), DataArray::new(9, metric));
    m
}

struct Case {
    name: &'static str,
    format: Format,
    ext: &'static str,
    opts: WriteOptions,
}

fn cases() -> Vec<Case> {
    let o = WriteOptions::default;
    vec![
        Case {
            name: "gmsh41_ascii",
            format: Format::Gmsh,
            ext: "msh",
            opts: WriteOptions {
                gmsh: GmshWrite { version: GmshVersion::V41, ..Default::default() },
                ..o()
            },
        },
        Case {
            name: "gmsh41_binary",
            format: Format::Gmsh,
            ext: "msh",
            opts: WriteOptions {
                gmsh: GmshWrite { version: GmshVersion::V41, binary: true },
                ..o()
            },
        },
        Case {
            name: "gmsh22_ascii",
            format: Format::Gmsh,
            ext: "msh",
            opts: WriteOptions {
                gmsh: GmshWrite { version: GmshVersion::V22, ..Default::default() },
                ..o()
            },
        },
        Case {
            name: "gmsh22_binary",
            format: Format::Gmsh,
            ext: "msh",
            opts: WriteOptions {
                gmsh: GmshWrite { version: GmshVersion::V22, binary: true },
                ..o()
            },
        },
        Case {
            name: "vtu_zlib",
            format: Format::Vtu,
            ext: "vtu",
            opts: WriteOptions {
                vtk: VtkWrite {
                    vtu_encoding: VtuEncoding::Binary,
                    compress: true,
                    ..Default::default()
                },
                ..o()
            },
        },
        Case {
            name: "vtu_appended_raw",
            format: Format::Vtu,
            ext: "vtu",
            opts: WriteOptions {
                vtk: VtkWrite {
                    vtu_encoding: VtuEncoding::Appended,
                    compress: false,
                    ..Default::default()
                },
                ..o()
            },
        },
        Case {
            name: "vtu_ascii",
            format: Format::Vtu,
            ext: "vtu",
            opts: WriteOptions {
                vtk: VtkWrite {
                    vtu_encoding: VtuEncoding::Ascii,
                    compress: false,
                    ..Default::default()
                },
                ..o()
            },
        },
        Case { name: "vtk42_ascii", format: Format::VtkLegacy, ext: "vtk", opts: o() },
        Case {
            name: "vtk42_binary",
            format: Format::VtkLegacy,
            ext: "vtk",
            opts: WriteOptions {
                vtk: VtkWrite { legacy_binary: true, ..Default::default() },
                ..o()
            },
        },
        Case {
            name: "vtk51_ascii",
            format: Format::VtkLegacy,
            ext: "vtk",
            opts: WriteOptions {
                vtk: VtkWrite { legacy_version: (5, 1), ..Default::default() },
                ..o()
            },
        },
        Case {
            name: "vtk51_binary",
            format: Format::VtkLegacy,
            ext: "vtk",
            opts: WriteOptions {
                vtk: VtkWrite { legacy_version: (5, 1), legacy_binary: true, ..Default::default() },
                ..o()
            },
        },
        Case { name: "medit_ascii", format: Format::Medit, ext: "mesh", opts: o() },
        Case {
            name: "medit_binary",
            format: Format::Medit,
            ext: "meshb",
            opts: WriteOptions {
                medit: MeditWrite { binary: true },
                main_name: Some("big.meshb".into()),
                ..o()
            },
        },
        Case {
            name: "triangle",
            format: Format::Triangle,
            ext: "ele",
            opts: WriteOptions { main_name: Some("big.ele".into()), ..o() },
        },
        Case { name: "obj", format: Format::Obj, ext: "obj", opts: o() },
    ]
}

fn out_dir() -> PathBuf {
    let target = std::env::var("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|_| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target"));
    let d = target.join("bench-meshes");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn bench(c: &mut Criterion) {
    let n: usize =
        std::env::var("SMARTMESH_BENCH_N").ok().and_then(|s| s.parse().ok()).unwrap_or(867);
    let mesh = big_mesh(n);
    let dir = out_dir();
    eprintln!(
        "mesh: {} points, {} triangles",
        mesh.points.len(),
        mesh.num_cells_of(CellKind::Triangle)
    );
    let only: Option<Vec<String>> = std::env::var("SMARTMESH_BENCH_ONLY")
        .ok()
        .map(|s| s.split(',').map(str::to_string).collect());
    for case in cases()
        .into_iter()
        .filter(|c| only.as_ref().map_or(true, |o| o.iter().any(|n| n == c.name)))
    {
        let written = match write_bytes(case.format, &mesh, &case.opts) {
            Ok(w) => w,
            Err(e) => {
                eprintln!("{}: cannot write: {e}", case.name);
                continue;
            }
        };
        // Leave the files for the meshio comparison.
        std::fs::write(dir.join(format!("{}.{}", case.name, case.ext)), &written.main).unwrap();
        for (ext, b) in &written.siblings {
            std::fs::write(dir.join(format!("{}.{ext}", case.name)), b).unwrap();
        }
        let bytes = written.main.len() as u64
            + written.siblings.iter().map(|s| s.1.len() as u64).sum::<u64>();
        let sib = MemorySiblings::from_written(&written);
        let mut g = c.benchmark_group(case.name);
        // Flat sampling: ten runs of a slow ASCII case rather than criterion's 55, so
        // that the whole bench fits in a few minutes on a shared machine.
        g.sample_size(10)
            .sampling_mode(SamplingMode::Flat)
            .measurement_time(Duration::from_secs(4))
            .warm_up_time(Duration::from_secs(1));
        g.throughput(Throughput::Bytes(bytes));
        g.bench_function("memcpy", |b| {
            b.iter(|| {
                let copy = black_box(&written.main).clone();
                let sibs: Vec<Vec<u8>> = written.siblings.iter().map(|s| s.1.clone()).collect();
                black_box((copy, sibs))
            })
        });
        g.bench_function("read", |b| {
            b.iter(|| {
                let ctx = ReadContext { siblings: &sib, extension: case.ext.to_string() };
                black_box(read_bytes(case.format, black_box(&written.main), &ctx).unwrap())
            })
        });
        g.bench_function("write", |b| {
            b.iter(|| black_box(write_bytes(case.format, black_box(&mesh), &case.opts).unwrap()))
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
