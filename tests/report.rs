//! `smartmesh report` and `smartmesh info --metric`: the pictures parse, show the panels
//! they promise, draw ellipses and histograms that agree with the numbers they picture,
//! rasterise to a real PNG, are deterministic, and refuse bad input with exit code 2.

use std::path::{Path, PathBuf};

use smartmesh::formats::{read_path, write_path, CellKind, DataArray, TaggedMesh, WriteOptions};
use smartmesh::SizeTensor;
use smartmesh::{metric_field, Conformity};
use smartmesh::{History, IterationRecord, PhaseTimes};

#[path = "support/cli.rs"]
mod cli;
use cli::{fixture, run, stderr};
use smartmesh_test_support::grid::unit_square;

fn s(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// The unit square as an `n` × `n` grid of vertices, two triangles per square (face 1
/// "Plate"), the bottom side a curve 11 "Bottom", the other sides a curve 12 "Rest", and a
/// uniform metric of size tensor `t` when given.
fn grid(n: usize, t: Option<SizeTensor>) -> TaggedMesh {
    let mut m = unit_square(n - 1);
    for b in m.blocks.iter_mut().filter(|b| b.kind == CellKind::Line) {
        for tag in b.physical.iter_mut().chain(b.geometrical.iter_mut()) {
            *tag = (*tag).min(12);
        }
    }
    m.tag_names.insert((2, 1), "Plate".into());
    m.tag_names.insert((1, 11), "Bottom".into());
    m.tag_names.insert((1, 12), "Rest".into());
    if let Some(t) = t {
        let mt = t.to_metric().to_row_major_3x3(1.0);
        let values: Vec<f64> = (0..m.points.len()).flat_map(|_| mt).collect();
        m.point_data.insert("metric".into(), DataArray::new(9, values));
    }
    m
}

fn write(dir: &Path, name: &str, mesh: &TaggedMesh) -> PathBuf {
    let p = dir.join(name);
    write_path(&p, mesh, None, &WriteOptions::default()).expect("write test mesh");
    p
}

/// The cylinder fixture with the metric of its recipe, computed once per test that
/// needs it.
fn cylinder_with_metric(dir: &Path) -> PathBuf {
    let out = dir.join("cyl.vtu");
    let o = run(&[
        "size",
        s(&fixture("cylinder.msh")),
        "--recipe",
        s(&fixture("cylinder.toml")),
        "-o",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    out
}

fn report(args: &[&str]) -> String {
    let o = run(args);
    assert_eq!(o.status.code(), Some(0), "report {args:?}: {}", stderr(&o));
    let out = args.iter().position(|a| *a == "-o").map(|i| args[i + 1]).expect("-o");
    std::fs::read_to_string(out).expect("read the SVG")
}

fn by_id<'a>(doc: &'a roxmltree::Document<'a>, id: &str) -> Option<roxmltree::Node<'a, 'a>> {
    doc.descendants().find(|n| n.attribute("id") == Some(id))
}

fn attr(n: &roxmltree::Node<'_, '_>, name: &str) -> f64 {
    n.attribute(name)
        .unwrap_or_else(|| panic!("no {name} on {n:?}"))
        .parse()
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn has_class(n: &roxmltree::Node<'_, '_>, class: &str) -> bool {
    n.attribute("class").is_some_and(|c| c.split(' ').any(|x| x == class))
}

/// `(cx, cy, rx, ry, rotation in degrees)` of the ellipses of zoom panel `zoom`, and the
/// panel's `data-scale` of its ellipses group.
fn ellipses(doc: &roxmltree::Document<'_>, zoom: &str) -> (Vec<(usize, [f64; 5])>, f64) {
    let panel = by_id(doc, zoom).unwrap_or_else(|| panic!("no {zoom}"));
    let group = panel.descendants().find(|n| has_class(n, "ellipses")).expect("an ellipses group");
    let scale = attr(&group, "data-scale");
    let list = group
        .children()
        .filter(|n| n.has_tag_name("ellipse"))
        .map(|e| {
            let rot = e.attribute("transform").expect("transform");
            let angle: f64 =
                rot.trim_start_matches("rotate(").split(' ').next().unwrap().parse().unwrap();
            (
                e.attribute("data-vertex").unwrap().parse().unwrap(),
                [attr(&e, "cx"), attr(&e, "cy"), attr(&e, "rx"), attr(&e, "ry"), angle],
            )
        })
        .collect();
    (list, scale)
}

#[test]
fn svg_is_well_formed_with_the_expected_panels() {
    let dir = tempfile::tempdir().unwrap();
    let cyl = cylinder_with_metric(dir.path());
    let out = dir.path().join("cyl.svg");
    let text =
        report(&["report", s(&cyl), "--recipe", s(&fixture("cylinder.toml")), "-o", s(&out)]);
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    for id in ["title", "overview", "legend", "hist-length", "hist-quality"] {
        assert!(by_id(&doc, id).is_some(), "panel {id} missing");
    }
    assert!(by_id(&doc, "history").is_none(), "no history was given");
    // One zoom per recipe step with sources: the cylinder wall, the stagnation point and
    // the wake polyline (UNIFORM on the face has none); each framed on the overview.
    let zooms: Vec<_> = doc.descendants().filter(|n| has_class(n, "zoom")).collect();
    assert_eq!(zooms.len(), 3);
    let overview = by_id(&doc, "overview").unwrap();
    assert_eq!(overview.descendants().filter(|n| has_class(n, "zoom-frame")).count(), 3);
    let titles: Vec<String> = zooms
        .iter()
        .map(|z| {
            z.children()
                .find(|c| c.has_tag_name("title"))
                .and_then(|t| t.text())
                .unwrap_or("")
                .to_string()
        })
        .collect();
    assert!(
        titles[0].contains("DISTANCE_TO_BORDER") && titles[0].contains("Cylinder"),
        "{titles:?}"
    );
    assert!(titles[1].contains("DISTANCE_TO_POINT"), "{titles:?}");
    assert!(titles[2].contains("DISTANCE_TO_IMAGINARY_POLYLINE"), "{titles:?}");
    for z in ["zoom-1", "zoom-2", "zoom-3"] {
        assert!(!ellipses(&doc, z).0.is_empty(), "{z} has no ellipse");
    }
    // The overview: the face filled, every curve drawn, the edges.
    assert_eq!(overview.descendants().filter(|n| has_class(n, "face")).count(), 1);
    assert_eq!(overview.descendants().filter(|n| has_class(n, "curve")).count(), 4);
    assert!(overview.descendants().any(|n| has_class(&n, "edges")));
    let legend: Vec<&str> = by_id(&doc, "legend")
        .unwrap()
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .collect();
    for entry in ["face 10 Fluid", "curve 1 Inlet", "curve 4 Cylinder"] {
        assert!(legend.contains(&entry), "legend {legend:?} lacks {entry}");
    }
    let title: String =
        by_id(&doc, "title").unwrap().descendants().filter_map(|n| n.text()).collect();
    assert!(title.contains("1148 vertices") && title.contains("2134 surface cells"), "{title}");
}

#[test]
fn isotropic_metric_gives_circles_of_radius_h_times_scale_at_their_vertices() {
    let dir = tempfile::tempdir().unwrap();
    let h = 0.05;
    let mesh = grid(21, Some(SizeTensor::isotropic(h)));
    let path = write(dir.path(), "iso.vtu", &mesh);
    let out = dir.path().join("iso.svg");
    let text = report(&["report", s(&path), "-o", s(&out)]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    // Without a recipe: windows around the smallest sizes; all equal, so one window.
    assert!(by_id(&doc, "zoom-1").is_some() && by_id(&doc, "zoom-2").is_none());
    let (list, scale) = ellipses(&doc, "zoom-1");
    assert!(list.len() >= 3, "{} ellipses", list.len());
    // The panel's own geometry gives the same scale: its clip rectangle over its window.
    let panel = by_id(&doc, "zoom-1").unwrap();
    let clip =
        by_id(&doc, "clip-zoom-1").unwrap().children().find(|n| n.has_tag_name("rect")).unwrap();
    let w: Vec<f64> =
        panel.attribute("data-window").unwrap().split(' ').map(|v| v.parse().unwrap()).collect();
    let (sx, sy, sw, sh) =
        (attr(&clip, "x"), attr(&clip, "y"), attr(&clip, "width"), attr(&clip, "height"));
    let px_per_unit = (sw / (w[2] - w[0])).min(sh / (w[3] - w[1]));
    // The window around the corner vertex was moved inside the square, less a margin of
    // 4 % of the window so that the boundary is not drawn on the panel's border.
    let pad = 0.04 * (w[2] - w[0]).min(w[3] - w[1]) + 1e-9;
    assert!(w[0] >= -pad && w[1] >= -pad && w[2] <= 1.0 + pad && w[3] <= 1.0 + pad, "window {w:?}");
    assert!(w[0] < 0.0 || w[1] < 0.0, "the margin shows beyond the square: {w:?}");
    let factor: f64 = panel
        .descendants()
        .find(|n| has_class(n, "ellipses"))
        .unwrap()
        .attribute("data-factor")
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        (scale - px_per_unit * factor).abs() <= 1e-3 * scale,
        "{scale} vs {px_per_unit} x {factor}"
    );
    for (v, [cx, cy, rx, ry, _]) in list {
        assert!(
            (rx - h * scale).abs() < 2e-3 && (ry - h * scale).abs() < 2e-3,
            "vertex {v}: {rx} {ry} vs {}",
            h * scale
        );
        let p = mesh.points[v];
        let ex = sx + 0.5 * sw + px_per_unit * (p[0] - 0.5 * (w[0] + w[2]));
        let ey = sy + 0.5 * sh - px_per_unit * (p[1] - 0.5 * (w[1] + w[3]));
        assert!(
            (cx - ex).abs() < 0.05 && (cy - ey).abs() < 0.05,
            "vertex {v} at ({cx}, {cy}), expected ({ex}, {ey})"
        );
    }
}

#[test]
fn anisotropic_ellipses_have_their_major_axis_along_the_tensor_axis() {
    let dir = tempfile::tempdir().unwrap();
    let (major, minor) = (0.08, 0.02);
    let t = SizeTensor::from_angle(30f64.to_radians(), major, minor).unwrap();
    let path = write(dir.path(), "aniso.vtu", &grid(21, Some(t)));
    let out = dir.path().join("aniso.svg");
    let text = report(&["report", s(&path), "-o", s(&out)]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let (list, scale) = ellipses(&doc, "zoom-1");
    assert!(!list.is_empty());
    for (v, [_, _, rx, ry, rot]) in list {
        let (big, small) = (rx.max(ry), rx.min(ry));
        assert!(
            (big - major * scale).abs() < 2e-3 && (small - minor * scale).abs() < 2e-3,
            "vertex {v}: {rx} x {ry}"
        );
        // The picture's y points down: a mesh angle θ is drawn as rotate(−θ).
        let major_on_screen = if rx >= ry { rot } else { rot + 90.0 };
        let mesh_angle = (-major_on_screen).rem_euclid(180.0);
        assert!((mesh_angle - 30.0).abs() < 1e-2, "vertex {v}: major axis at {mesh_angle} degrees");
    }
}

fn bars(doc: &roxmltree::Document<'_>, id: &str) -> Vec<usize> {
    by_id(doc, id)
        .unwrap()
        .descendants()
        .filter(|n| has_class(n, "bar"))
        .map(|n| n.attribute("data-count").unwrap().parse().unwrap())
        .collect()
}

#[test]
fn histograms_are_conformitys_counts_and_info_prints_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let cyl = cylinder_with_metric(dir.path());
    let mesh = read_path(&cyl, None).unwrap();
    let c = Conformity::of_mesh(&mesh, &metric_field(&mesh, "metric").unwrap()).unwrap();
    let out = dir.path().join("cyl.svg");
    // The metric given as a separate file on the mesh's vertices.
    let text = report(&["report", s(&fixture("cylinder.msh")), "--metric", s(&cyl), "-o", s(&out)]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    assert_eq!(bars(&doc, "hist-length"), c.edge_length_histogram);
    assert_eq!(bars(&doc, "hist-quality"), c.quality_histogram.to_vec());
    let band = by_id(&doc, "hist-length").unwrap().descendants().find(|n| has_class(n, "band"));
    assert!(band.is_some(), "the conforming band is shaded");
    let heading: String =
        by_id(&doc, "hist-length").unwrap().descendants().filter_map(|n| n.text()).collect();
    assert!(
        heading.contains(&format!("{:.1}% of {} edges", 100.0 * c.conforming_share, c.edges)),
        "{heading}"
    );

    // info --json: the same figures, exactly.
    let o = run(&["info", "--json", s(&fixture("cylinder.msh")), "--metric", s(&cyl)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["metric"]["conformity"], serde_json::to_value(&c).unwrap());
    // Its own array, found without --metric, gives the same.
    let o = run(&["info", "--json", s(&cyl)]);
    let own: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(own["metric"]["conformity"], v["metric"]["conformity"]);
    // And the text names the share and the quality.
    let o = run(&["info", s(&fixture("cylinder.msh")), "--metric", s(&cyl)]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains(&format!(
            "{} edges, {:.1}% of metric length",
            c.edges,
            100.0 * c.conforming_share
        )),
        "{text}"
    );
    assert!(
        text.contains(&format!("min {:.4}, mean {:.4}", c.min_quality, c.mean_quality)),
        "{text}"
    );
    // Without a metric, no metric key at all (the output stays as it was).
    let o = run(&["info", "--json", s(&fixture("cylinder.msh"))]);
    let plain: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(plain.get("metric").is_none());
}

#[test]
fn png_decodes_at_the_requested_width_and_is_not_blank() {
    let dir = tempfile::tempdir().unwrap();
    let cyl = cylinder_with_metric(dir.path());
    let (svg, png) = (dir.path().join("c.svg"), dir.path().join("c.png"));
    let text = report(&[
        "report",
        s(&cyl),
        "--recipe",
        s(&fixture("cylinder.toml")),
        "--width",
        "700",
        "-o",
        s(&svg),
    ]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let height: u32 = doc.root_element().attribute("height").unwrap().parse().unwrap();
    let o = run(&[
        "report",
        s(&cyl),
        "--recipe",
        s(&fixture("cylinder.toml")),
        "--width",
        "700",
        "-o",
        s(&png),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    check_png(&png, 700, height, 1000);
    // The palette variant: indexed, same size, fewer colours, still a picture.
    let pal = dir.path().join("p.png");
    let o = run(&[
        "report",
        s(&cyl),
        "--recipe",
        s(&fixture("cylinder.toml")),
        "--width",
        "700",
        "--palette",
        "-o",
        s(&pal),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let reader = png::Decoder::new(std::fs::File::open(&pal).unwrap()).read_info().unwrap();
    assert_eq!(reader.info().color_type, png::ColorType::Indexed);
    check_png(&pal, 700, height, 50);
    assert!(std::fs::metadata(&pal).unwrap().len() < std::fs::metadata(&png).unwrap().len());
}

/// Decodes `path` (palettes expanded) and checks its size, that a fifth of it at least is
/// drawn on, and that it has more than `colours` colours.
fn check_png(path: &Path, width: u32, height: u32, colours: usize) {
    let mut decoder = png::Decoder::new(std::fs::File::open(path).unwrap());
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (width, height));
    let channels = info.color_type.samples();
    let pixels: Vec<&[u8]> = buf[..info.buffer_size()].chunks(channels).collect();
    let non_white = pixels.iter().filter(|p| p[..3] != [255, 255, 255]).count();
    assert!(non_white * 5 > pixels.len(), "only {non_white} of {} pixels are drawn", pixels.len());
    let mut distinct: Vec<[u8; 3]> = pixels.iter().map(|p| [p[0], p[1], p[2]]).collect();
    distinct.sort_unstable();
    distinct.dedup();
    assert!(distinct.len() > colours, "{} colours", distinct.len());
}

#[test]
fn same_input_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let cyl = cylinder_with_metric(dir.path());
    let recipe = fixture("cylinder.toml");
    for (ext, extra) in [("svg", None), ("png", None), ("png", Some("--palette"))] {
        let (a, b) = (dir.path().join(format!("a.{ext}")), dir.path().join(format!("b.{ext}")));
        for out in [&a, &b] {
            let mut args = vec!["report", s(&cyl), "--recipe", s(&recipe), "-o", s(out)];
            args.extend(extra);
            let o = run(&args);
            assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        }
        assert_eq!(
            std::fs::read(&a).unwrap(),
            std::fs::read(&b).unwrap(),
            "{ext} differs between runs"
        );
    }
}

#[test]
fn history_is_drawn_with_its_best_iteration() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write(dir.path(), "g.vtu", &grid(11, Some(SizeTensor::isotropic(0.1))));
    let rec = |i: usize, v: usize, share: f64| IterationRecord {
        iteration: i,
        vertices: v,
        triangles: 2 * v,
        conforming_share: share,
        mean_edge_length: 1.0,
        mean_quality: 0.8,
        min_quality: 0.2,
        seconds: PhaseTimes::default(),
        remeshing: None,
        solver: None,
        space: None,
    };
    let h = History {
        input: "g.poly".into(),
        recipe: "r.toml".into(),
        adapter: "native".into(),
        converged: true,
        best_iteration: 2,
        stopped: "stable".into(),
        iterations: vec![rec(0, 121, 0.3), rec(1, 400, 0.7), rec(2, 450, 0.9), rec(3, 452, 0.89)],
        best_mesh: Vec::new(),
        layer: None,
        budget: None,
    };
    let hp = dir.path().join("history.json");
    std::fs::write(&hp, h.to_json()).unwrap();
    let out = dir.path().join("h.svg");
    let text = report(&["report", s(&mesh), "--history", s(&hp), "-o", s(&out)]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let panel = by_id(&doc, "history").expect("history panel");
    let best = panel.descendants().find(|n| has_class(n, "best")).expect("best iteration marked");
    assert_eq!(best.attribute("data-iteration"), Some("2"));
    let series: Vec<_> = panel.descendants().filter(|n| has_class(n, "series")).collect();
    assert_eq!(series.len(), 3);
    let vertices: Vec<f64> = series[0]
        .descendants()
        .filter(|n| n.has_tag_name("circle"))
        .map(|c| attr(&c, "data-value"))
        .collect();
    assert_eq!(vertices, vec![121.0, 400.0, 450.0, 452.0]);
    let shares: Vec<f64> = series[1]
        .descendants()
        .filter(|n| n.has_tag_name("circle"))
        .map(|c| attr(&c, "data-value"))
        .collect();
    assert_eq!(shares, vec![0.3, 0.7, 0.9, 0.89]);
}

#[test]
fn a_large_mesh_gives_a_bounded_svg_with_short_edges_shaded() {
    let dir = tempfile::tempdir().unwrap();
    // 2 × 199² = 79 202 triangles; at 600 px their edges are under 2 px.
    let mesh = write(dir.path(), "big.vtu", &grid(200, Some(SizeTensor::isotropic(0.01))));
    let out = dir.path().join("big.svg");
    let text = report(&["report", s(&mesh), "--width", "600", "-o", s(&out)]);
    assert!(text.len() < 2_000_000, "{} bytes", text.len());
    let doc = roxmltree::Document::parse(&text).unwrap();
    let overview = by_id(&doc, "overview").unwrap();
    assert!(overview.descendants().any(|n| has_class(&n, "edge-shading")));
}

#[test]
fn json_summary_lists_the_zooms_and_the_figures() {
    let dir = tempfile::tempdir().unwrap();
    let cyl = cylinder_with_metric(dir.path());
    let out = dir.path().join("c.svg");
    let o = run(&[
        "report",
        s(&cyl),
        "--recipe",
        s(&fixture("cylinder.toml")),
        "--json",
        "-o",
        s(&out),
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let zooms = v["report"]["zooms"].as_array().unwrap();
    assert_eq!(zooms.len(), 3);
    assert_eq!(zooms[0]["label"], "distance to border: Cylinder");
    // The window a panel shows holds the part of its region inside the channel
    // [0, 4] x [0, 1] (it is moved inside the domain where it fits).
    for z in zooms {
        let (r, w) = (&z["region"], &z["shown"]);
        let f = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap();
        assert!(
            f(w, "x0") <= f(r, "x0").max(0.0) + 1e-9 && f(w, "x1") >= f(r, "x1").min(4.0) - 1e-9,
            "{z}"
        );
        assert!(
            f(w, "y0") <= f(r, "y0").max(0.0) + 1e-9 && f(w, "y1") >= f(r, "y1").min(1.0) - 1e-9,
            "{z}"
        );
    }
    let mesh = read_path(&cyl, None).unwrap();
    let c = Conformity::of_mesh(&mesh, &metric_field(&mesh, "metric").unwrap()).unwrap();
    assert_eq!(v["report"]["conformity"], serde_json::to_value(&c).unwrap());
    let text = std::fs::read_to_string(&out).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    assert_eq!(
        v["report"]["height"].as_f64().unwrap().to_string(),
        doc.root_element().attribute("height").unwrap()
    );
}

#[test]
fn stdout_takes_the_kind_from_to() {
    let o = run(&["report", s(&fixture("cylinder.msh")), "--to", "svg", "-o", "-"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(roxmltree::Document::parse(&text).is_ok());
    let o = run(&["report", s(&fixture("cylinder.msh")), "-o", "-"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--to svg or --to png"), "{}", stderr(&o));
}

#[test]
fn without_a_metric_the_mesh_is_drawn_and_the_report_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.svg");
    let o = run(&["report", s(&fixture("cylinder.msh")), "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("no metric"), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    let doc = roxmltree::Document::parse(&text).unwrap();
    assert!(by_id(&doc, "overview").is_some() && by_id(&doc, "hist-length").is_none());
}

fn assert_refused(args: &[&str], out: &Path, expected: &[&str]) {
    let o = run(args);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
    let err = stderr(&o);
    for e in expected {
        assert!(err.contains(e), "{args:?}: `{err}` lacks `{e}`");
    }
    assert!(!err.contains("panicked"), "{err}");
    assert!(!out.exists(), "nothing is written on error");
}

#[test]
fn bad_metrics_and_histories_exit_two_with_a_clear_message() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mesh = write(d, "g.vtu", &grid(6, None));
    let out = d.join("out.svg");
    // Wrong vertex count.
    let other = write(d, "other.vtu", &grid(7, Some(SizeTensor::isotropic(0.1))));
    assert_refused(
        &["report", s(&mesh), "--metric", s(&other), "-o", s(&out)],
        &out,
        &[s(&other), "49 items", "36 vertices"],
    );
    assert_refused(&["info", s(&mesh), "--metric", s(&other)], &out, &["49 items", "36 vertices"]);
    // A NaN: the VTU reader keeps it (a data array may hold NaN); the metric check
    // refuses it where it is used, naming the array and the vertex.
    let mut nan = grid(6, Some(SizeTensor::isotropic(0.1)));
    nan.point_data.get_mut("metric").unwrap().values[9 * 7] = f64::NAN;
    let nan = write(d, "nan.vtu", &nan);
    assert_refused(
        &["report", s(&nan), "-o", s(&out)],
        &out,
        &[s(&nan), "`metric`", "vertex 7", "is not finite"],
    );
    assert_refused(
        &["report", s(&mesh), "--metric", s(&nan), "-o", s(&out)],
        &out,
        &[s(&nan), "vertex 7", "is not finite"],
    );
    assert_refused(
        &["info", s(&mesh), "--metric", s(&nan)],
        &out,
        &[s(&nan), "vertex 7", "is not finite"],
    );
    // A tensor that is finite but not positive definite: the metric check names the vertex.
    let mut neg = grid(6, Some(SizeTensor::isotropic(0.1)));
    neg.point_data.get_mut("metric").unwrap().values[9 * 7] = -1.0;
    let neg = write(d, "neg.vtu", &neg);
    assert_refused(
        &["report", s(&neg), "-o", s(&out)],
        &out,
        &[s(&neg), "vertex 7", "not positive definite"],
    );
    assert_refused(
        &["report", s(&mesh), "--metric", s(&neg), "-o", s(&out)],
        &out,
        &[s(&neg), "vertex 7", "not positive definite"],
    );
    assert_refused(
        &["info", s(&mesh), "--metric", s(&neg)],
        &out,
        &["vertex 7", "not positive definite"],
    );
    // The file's own bad array is only a warning for info, which still prints the rest.
    let o = run(&["info", s(&neg)]);
    assert_eq!(o.status.code(), Some(0));
    assert!(
        stderr(&o).contains("warning: no metric figures") && stderr(&o).contains("vertex 7"),
        "{}",
        stderr(&o)
    );
    // No `metric` array in the metric file.
    assert_refused(
        &["report", s(&mesh), "--metric", s(&mesh), "-o", s(&out)],
        &out,
        &[s(&mesh), "no point data `metric`"],
    );
    // A history that is not one.
    let bad = d.join("history.json");
    std::fs::write(&bad, "{\"input\": \"a\",\n \"iterations\": 3}\n").unwrap();
    assert_refused(
        &["report", s(&mesh), "--history", s(&bad), "-o", s(&out)],
        &out,
        &[s(&bad), "line 2"],
    );
    let missing = d.join("none.json");
    assert_refused(
        &["report", s(&mesh), "--history", s(&missing), "-o", s(&out)],
        &out,
        &[s(&missing), "cannot read"],
    );
    // An output that is neither SVG nor PNG, and a width out of range.
    let pdf = d.join("out.pdf");
    assert_refused(&["report", s(&mesh), "-o", s(&pdf)], &pdf, &[".svg or .png"]);
    assert_refused(&["report", s(&mesh), "--width", "5", "-o", s(&out)], &out, &["--width 5"]);
}

/// A history of four iterations whose best is the last (so that its label would meet the
/// right axis), written to `dir`.
fn history_ending_on_its_best(dir: &Path) -> PathBuf {
    let rec = |i: usize, v: usize, share: f64| IterationRecord {
        iteration: i,
        vertices: v,
        triangles: 2 * v,
        conforming_share: share,
        mean_edge_length: 1.0,
        mean_quality: 0.95,
        min_quality: 0.4,
        seconds: PhaseTimes::default(),
        remeshing: None,
        solver: None,
        space: None,
    };
    let h = History {
        input: "geometry.poly".into(),
        recipe: "recipe.cfg".into(),
        adapter: "native".into(),
        converged: true,
        best_iteration: 3,
        stopped: "stable".into(),
        iterations: vec![
            rec(0, 1148, 0.6),
            rec(1, 6200, 0.97),
            rec(2, 5500, 0.985),
            rec(3, 5467, 0.996),
        ],
        best_mesh: Vec::new(),
        layer: None,
        budget: None,
    };
    let p = dir.join("history.json");
    std::fs::write(&p, h.to_json()).unwrap();
    p
}

/// The examples' U-duct starting mesh with the field of its recipe, as `.vtu`.
fn u_duct_with_metric(dir: &Path) -> (PathBuf, PathBuf) {
    let ex = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/u-duct");
    let out = dir.join("u.vtu");
    let recipe = ex.join("recipe.cfg");
    let o = run(&["size", s(&ex.join("start.msh")), "--recipe", s(&recipe), "-o", s(&out)]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    (out, recipe)
}

#[derive(Debug, Clone, Copy)]
struct Box2 {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl Box2 {
    fn inside(&self, o: &Box2, tol: f64) -> bool {
        self.x0 >= o.x0 - tol
            && self.y0 >= o.y0 - tol
            && self.x1 <= o.x1 + tol
            && self.y1 <= o.y1 + tol
    }
    fn overlaps(&self, o: &Box2) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
    fn area(&self) -> f64 {
        (self.x1 - self.x0) * (self.y1 - self.y0)
    }
}

fn data_box(n: &roxmltree::Node<'_, '_>) -> Option<Box2> {
    let v: Vec<f64> =
        n.attribute("data-box")?.split(' ').map(|x| x.parse().expect("a number")).collect();
    Some(Box2 { x0: v[0], y0: v[1], x1: v[2], y1: v[3] })
}

/// An attribute of `n` or of its nearest ancestor that has it.
fn inherited<'a>(n: &roxmltree::Node<'a, '_>, name: &str) -> Option<&'a str> {
    n.ancestors().find_map(|a| a.attribute(name))
}

/// The box a `<text>` takes: its advance width from the report's own table of the
/// font (which the test below checks against the installed font), from the ascent above
/// its baseline to the descent below.
fn text_box(n: &roxmltree::Node<'_, '_>) -> Box2 {
    use smartmesh::report::{Font, ASCENT, DESCENT};
    let size: f64 = inherited(n, "font-size").unwrap_or("12").parse().unwrap();
    let bold = inherited(n, "font-weight") == Some("bold");
    let w = Font { size, bold }.width(n.text().unwrap_or(""));
    let (x, y) = (attr(n, "x"), attr(n, "y"));
    let x0 = match n.attribute("text-anchor") {
        Some("end") => x - w,
        Some("middle") => x - 0.5 * w,
        _ => x,
    };
    Box2 { x0, y0: y - ASCENT * size, x1: x0 + w, y1: y + DESCENT * size }
}

/// The bounding box of the coordinates of an `M x yL x y…` path.
fn path_box(d: &str) -> Option<Box2> {
    let nums: Vec<f64> = d
        .split(|c: char| c.is_ascii_alphabetic() || c == ' ')
        .filter(|t| !t.is_empty())
        .map(|t| t.parse().expect("a number"))
        .collect();
    let fold = |skip: usize| {
        nums.iter()
            .skip(skip)
            .step_by(2)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)))
    };
    let ((x0, x1), (y0, y1)) = (fold(0), fold(1));
    (x0 <= x1).then_some(Box2 { x0, y0, x1, y1 })
}

/// Checks a report's layout: every panel inside the picture and apart from the others;
/// every text whole (not cut with an ellipsis) and inside its panel, apart from every other text of its panel (labels drawn
/// over the mesh excepted: they sit on white boxes); every zoom frame on the overview
/// inside the mesh's box and smaller than 60 % of it. Returns what it checked, to print.
fn check_layout(text: &str, what: &str) -> String {
    let doc = roxmltree::Document::parse(text).unwrap();
    let root = doc.root_element();
    let page = Box2 { x0: 0.0, y0: 0.0, x1: attr(&root, "width"), y1: attr(&root, "height") };
    let panels: Vec<(roxmltree::Node<'_, '_>, Box2)> =
        doc.descendants().filter_map(|n| data_box(&n).map(|b| (n, b))).collect();
    for id in ["title", "overview", "legend"] {
        assert!(panels.iter().any(|(n, _)| n.attribute("id") == Some(id)), "{what}: no {id}");
    }
    for (i, (n, b)) in panels.iter().enumerate() {
        assert!(
            b.inside(&page, 0.0),
            "{what}: panel {:?} {b:?} leaves the picture",
            n.attribute("id")
        );
        for (m, c) in &panels[i + 1..] {
            assert!(
                !b.overlaps(c),
                "{what}: panels {:?} and {:?} overlap",
                n.attribute("id"),
                m.attribute("id")
            );
        }
    }
    let mut texts = 0;
    let mut placed: Vec<(roxmltree::NodeId, Box2, String, bool)> = Vec::new();
    for t in doc.descendants().filter(|n| n.has_tag_name("text")) {
        let panel = t
            .ancestors()
            .find(|a| a.attribute("data-box").is_some())
            .unwrap_or_else(|| panic!("{what}: text {:?} is in no panel", t.text()));
        let pb = data_box(&panel).unwrap();
        let tb = text_box(&t);
        let content = t.text().unwrap_or("").to_string();
        assert!(
            tb.inside(&pb, 0.5),
            "{what}: `{content}` {tb:?} overflows panel {:?} {pb:?}",
            panel.attribute("id")
        );
        assert!(!content.ends_with('…'), "{what}: `{content}` is cut");
        placed.push((panel.id(), tb, content, has_class(&t, "on-mesh")));
        texts += 1;
    }
    for (i, a) in placed.iter().enumerate() {
        for b in &placed[i + 1..] {
            if a.0 == b.0 && !a.3 && !b.3 {
                assert!(!a.1.overlaps(&b.1), "{what}: `{}` and `{}` overlap", a.2, b.2);
            }
        }
    }
    // Frames: inside the box of the mesh as the overview draws it (its faces' outlines).
    let overview = by_id(&doc, "overview").unwrap();
    let mesh_box = overview
        .descendants()
        .filter(|n| has_class(n, "face"))
        .filter_map(|n| path_box(n.attribute("d").unwrap()))
        .reduce(|a, b| Box2 {
            x0: a.x0.min(b.x0),
            y0: a.y0.min(b.y0),
            x1: a.x1.max(b.x1),
            y1: a.y1.max(b.y1),
        })
        .expect("the overview draws faces");
    let mut frames = 0;
    for f in overview.descendants().filter(|n| has_class(n, "zoom-frame")) {
        let (x, y) = (attr(&f, "x"), attr(&f, "y"));
        let fb = Box2 { x0: x, y0: y, x1: x + attr(&f, "width"), y1: y + attr(&f, "height") };
        assert!(fb.inside(&mesh_box, 0.2), "{what}: frame {fb:?} runs off the mesh {mesh_box:?}");
        assert!(
            fb.area() < 0.6 * mesh_box.area(),
            "{what}: frame {} shows most of the domain",
            f.attribute("data-zoom").unwrap()
        );
        frames += 1;
    }
    format!("{what}: {} panels, {texts} texts, {frames} frames", panels.len())
}

#[test]
fn text_stays_in_its_panel_and_frames_on_the_mesh_at_600_900_1200_px() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let history = history_ending_on_its_best(d);
    let cyl = cylinder_with_metric(d);
    let cyl_recipe = fixture("cylinder.toml");
    let (duct, duct_recipe) = u_duct_with_metric(d);
    for (mesh, recipe) in [(&cyl, &cyl_recipe), (&duct, &duct_recipe)] {
        for width in ["600", "900", "1200"] {
            let out = d.join(format!("r{width}.svg"));
            let text = report(&[
                "report",
                s(mesh),
                "--recipe",
                s(recipe),
                "--history",
                s(&history),
                "--width",
                width,
                "-o",
                s(&out),
            ]);
            let what = format!("{} at {width} px", mesh.file_name().unwrap().to_string_lossy());
            println!("{}", check_layout(&text, &what));
            for id in ["hist-length", "hist-quality", "history"] {
                assert!(text.contains(&format!("id=\"{id}\"")), "{what}: no {id}");
            }
        }
    }
}

#[test]
fn tagged_points_and_the_shading_scale_are_in_the_legend() {
    let dir = tempfile::tempdir().unwrap();
    let (duct, recipe) = u_duct_with_metric(dir.path());
    let out = dir.path().join("u.svg");
    let text =
        report(&["report", s(&duct), "--recipe", s(&recipe), "--width", "900", "-o", s(&out)]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let legend = by_id(&doc, "legend").unwrap();
    let labels: Vec<&str> =
        legend.descendants().filter(|n| n.has_tag_name("text")).filter_map(|n| n.text()).collect();
    for entry in [
        "point 1 InletOuterCorner",
        "point 4 OutletInnerCorner",
        "curve 13 OuterWall",
        "point source of the recipe",
        "imaginary polyline of the recipe",
    ] {
        assert!(labels.contains(&entry), "legend {labels:?} lacks {entry}");
    }
    // Each tagged point is drawn on the overview, in its legend colour.
    let overview = by_id(&doc, "overview").unwrap();
    let drawn: Vec<&str> = overview
        .descendants()
        .filter(|n| has_class(n, "topo-point"))
        .map(|n| n.attribute("fill").unwrap())
        .collect();
    let swatches: Vec<&str> = legend
        .descendants()
        .filter(|n| has_class(n, "point-swatch"))
        .map(|n| n.attribute("fill").unwrap())
        .collect();
    assert_eq!(drawn.len(), 4);
    assert_eq!(drawn, swatches);
    // Nothing is shaded at this width: no scale of shading either.
    assert!(!overview.descendants().any(|n| has_class(&n, "edge-shading")));
    assert!(!legend.descendants().any(|n| has_class(&n, "colour-scale")));
}

#[test]
fn shaded_edges_have_their_colour_scale_in_the_legend() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = write(dir.path(), "big.vtu", &grid(200, Some(SizeTensor::isotropic(0.01))));
    let out = dir.path().join("big.svg");
    let text = report(&["report", s(&mesh), "--width", "600", "-o", s(&out)]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let (overview, legend) = (by_id(&doc, "overview").unwrap(), by_id(&doc, "legend").unwrap());
    // One swatch per level, in the opacities the shading uses, lightest first.
    let used: Vec<f64> = overview
        .descendants()
        .filter(|n| has_class(n, "edge-shading"))
        .map(|n| attr(&n, "fill-opacity"))
        .collect();
    assert!(!used.is_empty(), "the overview shades edges");
    let scale = legend.descendants().find(|n| has_class(n, "colour-scale")).expect("a scale");
    let levels: Vec<f64> = scale
        .children()
        .filter(|n| n.has_tag_name("rect"))
        .map(|n| attr(&n, "fill-opacity"))
        .collect();
    assert!(levels.len() >= used.len() && levels.windows(2).all(|w| w[0] < w[1]), "{levels:?}");
    for u in used {
        assert!(levels.contains(&u), "shading opacity {u} is not on the scale {levels:?}");
    }
    println!("{}", check_layout(&text, "the large grid at 600 px"));
}

/// Every string of a report, laid out by usvg with the installed font, lies inside the
/// box that the report's table of advances gives it: the SVG's layout holds in the PNG.
#[test]
fn the_font_table_holds_every_string_as_the_installed_font_draws_it() {
    use resvg::usvg;
    let mut opt = usvg::Options::default();
    opt.fontdb_mut().load_system_fonts();
    let has_dejavu = opt.fontdb.faces().any(|f| f.families.iter().any(|(n, _)| n == "DejaVu Sans"));
    if !has_dejavu {
        smartmesh_test_support::skip::skip(
            "DejaVu Sans is not installed (the font the report's table measures)",
        );
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let history = history_ending_on_its_best(d);
    let (duct, recipe) = u_duct_with_metric(d);
    let out = d.join("u.svg");
    let text = report(&[
        "report",
        s(&duct),
        "--recipe",
        s(&recipe),
        "--history",
        s(&history),
        "--width",
        "900",
        "-o",
        s(&out),
    ]);
    // Our boxes, in document order.
    let doc = roxmltree::Document::parse(&text).unwrap();
    let ours: Vec<(String, Box2)> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| (n.text().unwrap_or("").to_string(), text_box(&n)))
        .collect();
    // usvg's, in document order too.
    let tree = usvg::Tree::from_str(&text, &opt).unwrap();
    let mut drawn: Vec<(String, usvg::Rect)> = Vec::new();
    fn walk(g: &usvg::Group, out: &mut Vec<(String, usvg::Rect)>) {
        for n in g.children() {
            match n {
                usvg::Node::Group(g) => walk(g, out),
                usvg::Node::Text(t) => {
                    let s: String = t.chunks().iter().map(|c| c.text()).collect();
                    out.push((s, t.abs_bounding_box()));
                }
                _ => {}
            }
        }
    }
    walk(tree.root(), &mut drawn);
    let ours: Vec<&(String, Box2)> = ours.iter().filter(|(s, _)| !s.trim().is_empty()).collect();
    assert_eq!(ours.len(), drawn.len(), "usvg laid out another number of texts");
    for ((s, b), (t, r)) in ours.iter().zip(&drawn) {
        assert_eq!(s, t);
        let ink = Box2 {
            x0: r.left() as f64,
            y0: r.top() as f64,
            x1: r.right() as f64,
            y1: r.bottom() as f64,
        };
        assert!(ink.inside(b, 0.5), "`{s}`: drawn {ink:?}, measured {b:?}");
    }
}

#[test]
fn a_history_of_another_mesh_is_named_whatever_its_file_name() {
    use smartmesh::WrittenFile;
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mesh = d.join("mine.msh");
    std::fs::copy(fixture("cylinder.msh"), &mesh).unwrap();
    let bytes = std::fs::read(&mesh).unwrap();
    let written = history_ending_on_its_best(d);
    let mut h = History::from_json(&std::fs::read_to_string(&written).unwrap()).unwrap();
    let warns = |h: &History| -> bool {
        let path = d.join("h.json");
        std::fs::write(&path, h.to_json()).unwrap();
        let out = d.join("r.svg");
        let o = run(&["report", s(&mesh), "--history", s(&path), "-o", s(&out)]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        stderr(&o).contains("is not the mesh this history describes")
    };
    // Another run's history, its mesh under another name: said.
    h.best_mesh = vec![WrittenFile::of("other.msh", b"another mesh altogether")];
    assert!(warns(&h), "another run's history passed for this mesh's");
    // This mesh's history, its file since renamed: not a mismatch.
    h.best_mesh = vec![WrittenFile::of("adapted.msh", &bytes)];
    assert!(!warns(&h));
    // This mesh's name, other bytes: said, as before.
    h.best_mesh = vec![WrittenFile::of("mine.msh", b"older bytes")];
    assert!(warns(&h));
}

/// The box of a `<rect>`.
fn rect_box(n: &roxmltree::Node<'_, '_>) -> Box2 {
    let (x, y) = (attr(n, "x"), attr(n, "y"));
    Box2 { x0: x, y0: y, x1: x + attr(n, "width"), y1: y + attr(n, "height") }
}

#[test]
fn zoom_tabs_on_the_overview_neither_overlap_nor_hide() {
    // AGARD01's recipe frames the leading edge at several reaches: windows within a few
    // pixels of each other, whose tabs all sat on the same corner (2 hidden, 3 half
    // covered at 1200 px).
    let ex = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/naca0012-agard01");
    let dir = tempfile::tempdir().unwrap();
    for width in ["600", "900", "1200"] {
        let out = dir.path().join(format!("r{width}.svg"));
        let text = report(&[
            "report",
            s(&ex.join("start.msh")),
            "--recipe",
            s(&ex.join("recipe.toml")),
            "--width",
            width,
            "-o",
            s(&out),
        ]);
        let doc = roxmltree::Document::parse(&text).unwrap();
        let overview = by_id(&doc, "overview").unwrap();
        let frames = overview.descendants().filter(|n| has_class(n, "zoom-frame")).count();
        let tabs: Vec<(String, Box2)> = overview
            .descendants()
            .filter(|n| has_class(n, "zoom-tab"))
            .map(|n| (n.attribute("data-zoom").unwrap().to_string(), rect_box(&n)))
            .collect();
        assert!(frames >= 4, "{width} px: {frames} frames: not the case this test is about");
        assert_eq!(tabs.len(), frames, "{width} px: one tab per frame");
        let panel = data_box(&overview).unwrap();
        // Every label drawn over the overview's mesh: the tabs' numbers, the scale bar's.
        let labels: Vec<(String, Box2)> = overview
            .descendants()
            .filter(|n| n.has_tag_name("text") && has_class(n, "on-mesh"))
            .map(|n| (n.text().unwrap_or("").to_string(), text_box(&n)))
            .collect();
        for (i, (id, b)) in tabs.iter().enumerate() {
            assert!(b.inside(&panel, 0.0), "{width} px: tab {id} {b:?} leaves the overview");
            for (other, c) in &tabs[i + 1..] {
                assert!(!b.overlaps(c), "{width} px: tabs {id} and {other} overlap: {b:?} {c:?}");
            }
            // Its number inside it, and no other label on it.
            let (_, number) = labels
                .iter()
                .find(|(t, n)| t == id && n.inside(b, 0.5))
                .unwrap_or_else(|| panic!("{width} px: tab {id} {b:?} has no number inside"));
            for (t, l) in &labels {
                if l.overlaps(b) && !(t == id && l.inside(b, 0.5)) {
                    panic!("{width} px: `{t}` {l:?} covers tab {id} {b:?} (number {number:?})");
                }
            }
        }
    }
}
