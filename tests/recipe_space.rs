//! Recipes for meshes in space: polylines of (x, y, z) points in every recipe format,
//! written back as read; a mix of 2 and 3 coordinates refused with the file and line;
//! planar polylines written byte for byte as before; a sheet's FILE rewritten by
//! `recipe convert` so that the converted recipe names the same file.

use std::path::Path;

use smartmesh::recipe::{PolylinePoints, Recipe, RecipeError, RecipeFormat};

fn read(text: &str, format: RecipeFormat, name: &str) -> Result<Recipe, RecipeError> {
    Recipe::from_str(text, format, Path::new(name))
}

const FUNCTIONS_CFG: &str = "CREATE_DISTANCE_FUNCTIONS = ( { NAME = \"D\"; MINSIZE = 0.1; MAXSIZE = 1; MAXDISTANCE = 1; EXPONENT = 1; } );\nCREATE_PROJECTION_FUNCTIONS = ( { NAME = \"P\"; MAXSIZE = 1; MAXDISTANCE = 1; EXPONENT = 1; } );\n";

const ALGORITHM_CFG: &str = "CREATE_ALGORITHMS = ( { TYPE = \"DISTANCE_TO_IMAGINARY_POLYLINE\"; PERPENDICULAR_FUNCTION = \"D\"; POLYLINE_DISTANCE_FUNCTION = \"D\"; PROJECTION_FUNCTION = \"P\"; COORDINATES = \"Vortex\"; } );\n";

fn vortex_cfg(z: &str) -> String {
    format!(
        "{FUNCTIONS_CFG}CREATE_POLYLINES = (\n  {{ NAME = \"Vortex\";\n    X_COORDS = [ 0.0, 1.0, 2.5 ];\n    Y_COORDS = [ 0.5, 0.5, 0.75 ];\n{z}  }} );\n{ALGORITHM_CFG}"
    )
}

const VORTEX: [[f64; 3]; 3] = [[0.0, 0.5, 0.1], [1.0, 0.5, 0.2], [2.5, 0.75, -0.3]];

#[test]
fn polylines_in_space_read_alike_in_every_format_and_round_trip() {
    let cfg =
        read(&vortex_cfg("    Z_COORDS = [ 0.1, 0.2, -0.3 ];\n"), RecipeFormat::Libconfig, "r.cfg")
            .unwrap();
    assert_eq!(cfg.polylines["Vortex"], PolylinePoints::Space(VORTEX.to_vec()));
    let toml = cfg.to_toml();
    assert!(
        toml.contains("Vortex = [[0.0, 0.5, 0.1], [1.0, 0.5, 0.2], [2.5, 0.75, -0.3]]"),
        "{toml}"
    );
    let json = cfg.to_json();
    for (text, format, name) in [
        (toml.as_str(), RecipeFormat::Toml, "r.toml"),
        (json.as_str(), RecipeFormat::Json, "r.json"),
    ] {
        let back = read(text, format, name).unwrap();
        assert_eq!(back, cfg, "{name}");
    }
    let written = cfg.to_libconfig();
    assert!(written.contains("Z_COORDS = [ 0.1, 0.2, -0.3 ]"), "{written}");
    let again = read(&written, RecipeFormat::Libconfig, "w.cfg").unwrap();
    assert_eq!(again, cfg);
    assert_eq!(again.to_libconfig(), written, "the written text is stable");
    // TOML written by hand, integers allowed as in the plane.
    let hand = "[polylines]\nLine = [[0, 0, 0], [1, 2, 3]]\n";
    let r = read(hand, RecipeFormat::Toml, "h.toml").unwrap();
    assert_eq!(r.polylines["Line"], PolylinePoints::Space(vec![[0.0, 0.0, 0.0], [1.0, 2.0, 3.0]]));
}

#[test]
fn planar_polylines_are_written_as_before() {
    let cfg = read(&vortex_cfg(""), RecipeFormat::Libconfig, "r.cfg").unwrap();
    assert_eq!(
        cfg.polylines["Vortex"],
        PolylinePoints::Plane(vec![[0.0, 0.5], [1.0, 0.5], [2.5, 0.75]])
    );
    let written = cfg.to_libconfig();
    assert!(
        written.contains(
            "    { NAME = \"Vortex\";\n      X_COORDS = [ 0.0, 1.0, 2.5 ];\n      Y_COORDS = [ 0.5, 0.5, 0.75 ]; }"
        ),
        "{written}"
    );
    assert!(!written.contains("Z_COORDS"));
    assert!(cfg.to_toml().contains("Vortex = [[0.0, 0.5], [1.0, 0.5], [2.5, 0.75]]"));
    assert!(cfg.to_json().contains("\"Vortex\": [\n      [\n        0.0,\n        0.5\n      ],"));
}

/// The error's text: file, line and what was expected.
fn error(text: &str, format: RecipeFormat, name: &str) -> String {
    read(text, format, name).unwrap_err().to_string()
}

#[test]
fn a_mix_of_two_and_three_coordinates_is_refused_with_its_line() {
    let e =
        error(&vortex_cfg("    Z_COORDS = [ 0.1, 0.2 ];\n"), RecipeFormat::Libconfig, "mix.cfg");
    assert!(e.contains("mix.cfg:7"), "{e}");
    assert!(e.contains("3 X_COORDS but 2 Z_COORDS"), "{e}");

    let toml = "[global]\nhmax = 1.0\n\n[polylines]\nWake = [[0.0, 0.0, 1.0], [1.0, 0.0]]\n";
    let e = error(toml, RecipeFormat::Toml, "mix.toml");
    assert!(e.contains("mix.toml:5"), "{e}");
    assert!(e.contains("point 2 has 2 coordinates but point 1 has 3"), "{e}");

    let json = "{\n  \"polylines\": {\n    \"Wake\": [[0, 0], [1, 0, 2]]\n  }\n}\n";
    let e = error(json, RecipeFormat::Json, "mix.json");
    // serde_json reports the line it stands on once the polyline is read.
    assert!(e.contains("mix.json:4"), "{e}");
    assert!(e.contains("point 2 has 3 coordinates but point 1 has 2"), "{e}");

    let four = "[polylines]\nWake = [[0.0, 0.0, 1.0, 2.0]]\n";
    let e = error(four, RecipeFormat::Toml, "four.toml");
    assert!(e.contains("four.toml:2") && e.contains("expected 2 (x, y) or 3 (x, y, z)"), "{e}");

    let repeated = "[polylines]\nWake = [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]]\n";
    let e = error(repeated, RecipeFormat::Toml, "rep.toml");
    assert!(e.contains("rep.toml:2") && e.contains("consecutive points must differ"), "{e}");
}

/// A sheet of two triangles written as ASCII STL in `dir/name`.
fn write_sheet(dir: &Path, name: &str) {
    let stl = "solid wake\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 1 1 0\n  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 1 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid wake\n";
    std::fs::write(dir.join(name), stl).unwrap();
}

const SURFACE_TOML: &str = "[functions.D]\nkind = \"distance\"\nsize_at_source = 0.1\nsize_at_max_distance = 1.0\nmax_distance = 1.0\nexponent = 1.0\n\n[[algorithms]]\ntype = \"distance_to_imaginary_surface\"\nperpendicular = \"D\"\nparallel = \"D\"\nfile = \"sheets/wake.stl\"\n";

#[test]
fn an_imaginary_surface_is_read_relative_to_its_recipe_in_every_format() {
    use smartmesh::sizing::Algorithm;
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("sheets")).unwrap();
    write_sheet(&dir.path().join("sheets"), "wake.stl");
    let toml_path = dir.path().join("r.toml");
    std::fs::write(&toml_path, SURFACE_TOML).unwrap();
    let recipe = Recipe::from_path(&toml_path).unwrap();
    let cfg = recipe.to_libconfig();
    assert!(
        cfg.contains("TYPE = \"DISTANCE_TO_IMAGINARY_SURFACE\"")
            && cfg.contains("FILE = \"sheets/wake.stl\""),
        "{cfg}"
    );
    std::fs::write(dir.path().join("r.cfg"), &cfg).unwrap();
    std::fs::write(dir.path().join("r.json"), recipe.to_json()).unwrap();
    let topo = smartmesh::Topology::from_mesh(
        &smartmesh::formats::read_path(
            &smartmesh_test_support::cli::fixture("distributor.msh"),
            None,
        )
        .unwrap(),
    );
    for name in ["r.toml", "r.cfg", "r.json"] {
        let r = Recipe::from_path(&dir.path().join(name)).unwrap();
        assert_eq!(r, recipe, "{name}");
        let plan = r.resolve(&topo).unwrap().plan;
        let Algorithm::DistanceToImaginarySurface(a) = &plan.steps[0].algorithm else {
            panic!("{name}: {:?}", plan.steps[0].algorithm)
        };
        assert_eq!(a.sheet.triangles, vec![[0, 1, 2], [0, 2, 3]], "{name}");
        assert_eq!(a.sheet.points[2], [1.0, 1.0, 0.0]);
    }
    // A missing or unreadable file: the recipe's file and line, the path and the reader's
    // error.
    let bad = SURFACE_TOML.replace("sheets/wake.stl", "sheets/none.stl");
    std::fs::write(&toml_path, bad).unwrap();
    let e = Recipe::from_path(&toml_path).unwrap().resolve(&topo).unwrap_err().to_string();
    assert!(e.contains("r.toml:12") && e.contains("none.stl") && e.contains("cannot read"), "{e}");
    std::fs::write(
        dir.path().join("sheets/wake.stl"),
        "solid x\n facet normal 0 0 1\n  outer loop\n   vertex 0 0\n",
    )
    .unwrap();
    std::fs::write(&toml_path, SURFACE_TOML).unwrap();
    let e = Recipe::from_path(&toml_path).unwrap().resolve(&topo).unwrap_err().to_string();
    assert!(
        e.contains("r.toml:12") && e.contains("wake.stl:5") && e.contains("expected a vertex's z"),
        "{e}"
    );
    // A file with no triangle.
    std::fs::write(dir.path().join("sheets/wake.stl"), "solid x\nendsolid x\n").unwrap();
    let e = Recipe::from_path(&toml_path).unwrap().resolve(&topo).unwrap_err().to_string();
    assert!(e.contains("holds no triangle"), "{e}");
}

/// A polyline of (x, y, z) points on a planar mesh, and a sheet there, are refused by
/// step, saying why (there is no implied z).
#[test]
fn a_polyline_in_space_or_a_sheet_on_a_planar_mesh_is_refused_by_step() {
    let mesh = smartmesh::formats::read_path(
        &smartmesh_test_support::cli::fixture("distributor.msh"),
        None,
    )
    .unwrap();
    let cfg =
        read(&vortex_cfg("    Z_COORDS = [ 0.1, 0.2, -0.3 ];\n"), RecipeFormat::Libconfig, "r.cfg")
            .unwrap();
    let e = smartmesh::recipe::size_mesh(&mesh, &cfg, &mut |_| {}).unwrap_err().to_string();
    assert!(
        e.contains("step 0")
            && e.contains("DISTANCE_TO_IMAGINARY_POLYLINE")
            && e.contains("3 coordinates, but the mesh is planar"),
        "{e}"
    );
    let dir = tempfile::tempdir().unwrap();
    write_sheet(dir.path(), "wake.stl");
    let path = dir.path().join("s.toml");
    std::fs::write(&path, SURFACE_TOML.replace("sheets/", "")).unwrap();
    let r = Recipe::from_path(&path).unwrap();
    let e = smartmesh::recipe::size_mesh(&mesh, &r, &mut |_| {}).unwrap_err().to_string();
    assert!(e.contains("DISTANCE_TO_IMAGINARY_SURFACE sizes a mesh in space only"), "{e}");
}

#[path = "support/cli.rs"]
mod support;

/// The sheet's FILE in the recipe text `text` (TOML `file = "…"`, libconfig or JSON).
fn file_in(text: &str) -> String {
    let at = text.find("wake").expect("a sheet path");
    let start = text[..at].rfind('"').unwrap() + 1;
    let end = at + text[at..].find('"').unwrap();
    text[start..end].to_string()
}

/// `recipe convert` to another folder makes the sheet's relative FILE relative to the new
/// recipe's folder (and the converted recipe reads the same sheet); written back into the
/// same folder it is kept as written; to standard output it is absolute; an absolute
/// path is kept; a key written in an included file is taken from that file's folder.
#[test]
fn converting_a_recipe_to_another_folder_keeps_its_sheet() {
    use support::{run, streams};
    let dir = tempfile::tempdir().unwrap();
    let root = std::fs::canonicalize(dir.path()).unwrap();
    for d in ["a/sheets", "b/c", "a/inc"] {
        std::fs::create_dir_all(root.join(d)).unwrap();
    }
    write_sheet(&root.join("a/sheets"), "wake.stl");
    write_sheet(&root.join("a/inc"), "wake2.stl");
    let input = root.join("a/r.toml");
    std::fs::write(&input, SURFACE_TOML).unwrap();
    let topo = smartmesh::Topology::from_mesh(
        &smartmesh::formats::read_path(&support::fixture("distributor.msh"), None).unwrap(),
    );
    let sheet_of = |path: &Path| {
        let plan = Recipe::from_path(path).unwrap().resolve(&topo).unwrap().plan;
        match &plan.steps[0].algorithm {
            smartmesh::sizing::Algorithm::DistanceToImaginarySurface(a) => {
                // The same file, however its path reads.
                let file = std::fs::canonicalize(&a.sheet.path).unwrap();
                (file, a.sheet.points.clone(), a.sheet.triangles.clone())
            }
            other => panic!("{other:?}"),
        }
    };
    let want = sheet_of(&input);
    let convert = |from: &Path, to: &str| {
        let mut args = vec!["recipe", "convert", from.to_str().unwrap(), to];
        if to == "-" {
            args.extend(["--to", "json"]);
        }
        let o = run(&args);
        assert_eq!(o.status.code(), Some(0), "{}", streams(&o));
        o
    };
    for (to, path) in [
        ("b/c/r.cfg", "../../a/sheets/wake.stl"),
        ("b/r.json", "../a/sheets/wake.stl"),
        ("a/sheets/r.toml", "wake.stl"),
        ("a/r.json", "sheets/wake.stl"),
    ] {
        let out = root.join(to);
        convert(&input, out.to_str().unwrap());
        assert_eq!(file_in(&std::fs::read_to_string(&out).unwrap()), path, "{to}");
        assert_eq!(sheet_of(&out), want, "{to}");
    }
    // To standard output: absolute.
    let o = convert(&input, "-");
    let absolute = root.join("a/sheets/wake.stl");
    assert_eq!(file_in(&String::from_utf8_lossy(&o.stdout)), absolute.to_str().unwrap());
    // An absolute FILE is kept.
    let abs = root.join("a/abs.toml");
    std::fs::write(&abs, SURFACE_TOML.replace("sheets/wake.stl", absolute.to_str().unwrap()))
        .unwrap();
    let out = root.join("b/c/abs.toml");
    convert(&abs, out.to_str().unwrap());
    assert_eq!(file_in(&std::fs::read_to_string(&out).unwrap()), absolute.to_str().unwrap());
    // A key written in an included file, relative to that file's folder.
    let cfg = Recipe::from_path(&input).unwrap().to_libconfig();
    let (head, algorithms) = cfg.split_at(cfg.find("CREATE_ALGORITHMS").unwrap());
    std::fs::write(root.join("a/inc/algorithms.cfg"), algorithms.replace("sheets/wake", "wake2"))
        .unwrap();
    let main = root.join("a/main.cfg");
    std::fs::write(&main, format!("{head}@include \"inc/algorithms.cfg\"\n")).unwrap();
    let out = root.join("b/c/main.toml");
    convert(&main, out.to_str().unwrap());
    assert_eq!(file_in(&std::fs::read_to_string(&out).unwrap()), "../../a/inc/wake2.stl");
    assert_eq!(sheet_of(&out), sheet_of(&main));
}
