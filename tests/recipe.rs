//! Recipes: the libconfig syntax, cpp, the spelling variants of the thesis, TOML and
//! JSON, suggestions, resolution against a mesh and its dimension rule, round trips.

use std::path::Path;

use smartmesh::formats::{read_path, CellBlock, CellKind, TaggedMesh};
use smartmesh::recipe::model::SpecValue;
use smartmesh::recipe::{
    AlgorithmSpec, EntityRef, FunctionSpec, PolylinePoints, ReadOptions, Recipe, RecipeError,
    RecipeErrorKind, RecipeFormat,
};
use smartmesh::sizing::{
    Algorithm, DistanceFunction, DistanceToBorder, DistanceToImaginaryPolyline, DistanceToPoint,
    EntitySet, SizeProjectionFunction, Uniform,
};
use smartmesh::Topology;

use smartmesh_test_support::cli::fixture;

fn distributor() -> Topology {
    Topology::from_mesh(&read_path(&fixture("distributor.msh"), None).unwrap())
}

fn cfg(text: &str) -> Result<Recipe, RecipeError> {
    Recipe::from_str(text, RecipeFormat::Libconfig, Path::new("recipe.cfg"))
}

fn toml(text: &str) -> Result<Recipe, RecipeError> {
    Recipe::from_str(text, RecipeFormat::Toml, Path::new("recipe.toml"))
}

/// On CI (which has gcc) a missing cpp is a failure, elsewhere a skipped test.
fn cpp_or_skip() -> bool {
    smartmesh_test_support::cli::cpp_or_skip("the preprocessor tests")
}

/// Indices of the topology entities with one of `tags`, by brute force.
fn by_tags(topo: &Topology, dim: usize, tags: &[i32]) -> Vec<usize> {
    let t: Vec<Option<i32>> = match dim {
        0 => topo.points.iter().map(|p| p.tag).collect(),
        1 => topo.curves.iter().map(|c| c.tag).collect(),
        _ => topo.faces.iter().map(|f| Some(f.tag)).collect(),
    };
    (0..t.len()).filter(|&i| t[i].is_some_and(|x| tags.contains(&x))).collect()
}

fn curves(v: Vec<usize>) -> EntitySet {
    EntitySet { curves: v, ..Default::default() }
}

#[test]
fn appendix_example_parses_and_resolves_on_the_distributor() {
    let shared =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/reference/appendix-a-example.cfg");
    if let Ok(text) = std::fs::read_to_string(&shared) {
        assert_eq!(
            text,
            std::fs::read_to_string(fixture("appendix-a.cfg")).unwrap(),
            "fixtures/appendix-a.cfg is a copy of the reference example"
        );
    }
    if !cpp_or_skip() {
        return;
    }
    let r = Recipe::from_path(&fixture("appendix-a.cfg")).unwrap();
    assert_eq!(r.regions.len(), 7);
    assert_eq!(r.functions.len(), 12);
    assert_eq!(
        r.regions["Corners"],
        [11, 12, 1, 2, 3, 4, 5, 6, 7].map(EntityRef::Tag).to_vec(),
        "the #define expands"
    );
    assert_eq!(
        r.polylines["POLYLINE1"],
        PolylinePoints::Plane(vec![[-50.0, -12.8], [-48.0, -13.5], [-46.0, -13.5], [-44.0, -13.0]])
    );

    let topo = distributor();
    let resolved = r.resolve(&topo).unwrap();
    let plan = &resolved.plan;
    assert_eq!(
        (plan.h_min, plan.h_max, plan.max_aspect_ratio, plan.gradation),
        (None, None, None, None)
    );
    let labels: Vec<&str> = plan.steps.iter().map(|s| s.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "algorithm 1 (UNIFORM on \"Fluid\")",
            "algorithm 2 (DISTANCE_TO_POINT on \"Corners\")",
            "algorithm 3 (DISTANCE_TO_BORDER on \"StayVane\")",
            "algorithm 4 (DISTANCE_TO_BORDER on \"GuideVane\")",
            "algorithm 5 (DISTANCE_TO_IMAGINARY_POLYLINE along \"POLYLINE1\" within \"Fluid\")",
        ]
    );
    // The recipe's names of what each step works on, for captions: its polyline, else
    // its regions.
    let names: Vec<Vec<String>> = plan.steps.iter().map(|s| s.names.clone()).collect();
    assert_eq!(
        names,
        [vec!["Fluid"], vec!["Corners"], vec!["StayVane"], vec!["GuideVane"], vec!["POLYLINE1"]]
    );
    let fluid = EntitySet { faces: by_tags(&topo, 2, &[1000]), ..Default::default() };
    assert_eq!(fluid.faces.len(), 1);
    assert_eq!(
        plan.steps[0].algorithm,
        Algorithm::Uniform(Uniform { size: 2.0, on: fluid.clone() })
    );
    let corners = by_tags(&topo, 0, &[11, 12, 1, 2, 3, 4, 5, 6, 7]);
    assert_eq!(corners.len(), 9);
    assert_eq!(
        plan.steps[1].algorithm,
        Algorithm::DistanceToPoint(DistanceToPoint {
            function: DistanceFunction::try_new(0.02, 0.5, 0.75, 2.0).unwrap(),
            sources: EntitySet { points: corners, ..Default::default() }
        })
    );
    let stay = by_tags(&topo, 1, &[101, 102, 103, 104, 105, 106, 107]);
    assert_eq!(stay.len(), 7);
    assert_eq!(
        plan.steps[2].algorithm,
        Algorithm::DistanceToBorder(DistanceToBorder {
            perpendicular: DistanceFunction::try_new(0.1, 1.0, 5.0, 1.0).unwrap(),
            parallel: DistanceFunction::try_new(1.0, 2.0, 5.0, 1.0).unwrap(),
            borders: curves(stay),
        })
    );
    match &plan.steps[3].algorithm {
        Algorithm::DistanceToBorder(DistanceToBorder { borders, .. }) => {
            assert_eq!(*borders, curves(by_tags(&topo, 1, &[201, 202, 203])))
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(
        plan.steps[4].algorithm,
        Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline {
            perpendicular: DistanceFunction::try_new(0.03, 0.5, 2.0, 1.0).unwrap(),
            polyline_distance: DistanceFunction::try_new(0.03, 1.0, 2.0, 1.0).unwrap(),
            projection: SizeProjectionFunction::try_new(2.0, 1.0, 1.0).unwrap(),
            polyline: PolylinePoints::Plane(vec![
                [-50.0, -12.8],
                [-48.0, -13.5],
                [-46.0, -13.5],
                [-44.0, -13.0]
            ]),
            within: fluid,
        })
    );
    // Region reports: dimension, tags, names and mesh counts against the topology.
    let report = |n: &str| resolved.regions.iter().find(|r| r.name == n).unwrap();
    let periodic = report("Periodic");
    assert_eq!(
        (periodic.dimension, periodic.tags.clone(), periodic.used_by.clone()),
        (Some(1), vec![302, 303, 304, 306, 307, 308], vec![])
    );
    // Unused: its entities are looked up (an absent tag is an error), nothing measured.
    assert_eq!((periodic.vertices, periodic.edges, periodic.cells), (None, None, None));
    let stay = report("StayVane");
    let edges: usize = by_tags(&topo, 1, &stay.tags)
        .iter()
        .map(|&c| topo.curves[c].polylines.iter().map(|p| p.num_edges()).sum::<usize>())
        .sum();
    assert_eq!((stay.used_by.clone(), stay.edges), (vec![3], Some(edges)));
    let f = report("Fluid");
    assert_eq!(
        (f.dimension, f.entity_names.clone(), f.used_by.clone()),
        (Some(2), vec!["Fluid".to_string()], vec![1, 5])
    );
    assert_eq!(f.cells, Some(topo.surface_cells.len()));
    assert_eq!(
        f.vertices,
        Some(
            topo.vertex_class
                .iter()
                .filter(|c| !matches!(c, smartmesh::Classification::Unused))
                .count()
        )
    );
    assert_eq!(report("Inlet").entity_names, ["Inlet"]);
}

#[test]
fn libconfig_syntax_cases() {
    let text = r#"
        # hash comment
        // line comment
        /* block
           comment */
        HMIN = 1e-2; HMAX : 2,            // ':' and ',' separators
        MAX_ASPECT_RATIO = 1000L;          // integer with L suffix
        CREATE_REGIONS = (
            { NAME = "Wall" "s"; TOPOLOGICAL_ENTITIES = ( [ 0x1, 2 ], [ 3 ], "Plate" ); },
            { NAME = "Plate\x21"; ENTITIES = [ "Plate" ]; }
        );
        CREATE_DISTANCE_FUNCTIONS = ( { NAME = "F"; MINSIZE = 1; MAXSIZE = 2.; MAXDISTANCE = .5; EXPONENT = 1; } );
        CREATE_ALGORITHMS = ( { TYPE = "UNIFORM"; SIZE = 1; REGIONS = "Walls"; }, );
    "#;
    let r = cfg(text).unwrap();
    assert_eq!(
        (r.global.h_min, r.global.h_max, r.global.max_aspect_ratio),
        (Some(0.01), Some(2.0), Some(1000.0))
    );
    assert_eq!(
        r.regions["Walls"],
        vec![
            EntityRef::Tag(1),
            EntityRef::Tag(2),
            EntityRef::Tag(3),
            EntityRef::Name("Plate".into())
        ]
    );
    assert!(r.regions.contains_key("Plate!"));
    assert_eq!(
        r.functions["F"],
        FunctionSpec::Distance {
            size_at_source: 1.0,
            size_at_max_distance: 2.0,
            max_distance: 0.5,
            exponent: 1.0
        }
    );
    assert_eq!(
        r.algorithms,
        vec![AlgorithmSpec::new(
            "UNIFORM",
            [("size", SpecValue::Size(1.0)), ("regions", SpecValue::Names(vec!["Walls".into()]))]
        )
        .unwrap()]
    );

    let err = |text: &str| cfg(text).unwrap_err();
    let e = err("HMIN = 0.1;\nCREATE_REGIONS = [ { NAME = \"A\"; } ];");
    assert_eq!(e.line, Some(2), "{e}");
    assert!(e.to_string().contains("array [ ] holds scalars only"), "{e}");
    let e = err("CREATE_REGIONS = (\n { NAME = \"A\"; TOPOLOGICAL_ENTITIES = [ 1, 2 ] }\n { NAME = \"B\"; }\n);");
    assert_eq!(e.line, Some(3), "a missing comma between groups: {e}");
    let e = err("HMIN = 0.1;\n\nHMAX = \"big\";");
    assert_eq!(
        (e.line, *e.kind.clone()),
        (
            Some(3),
            RecipeErrorKind::WrongType {
                key: "HMAX".into(),
                expected: "a number".into(),
                found: "a string".into()
            }
        )
    );
    let e = err("CREATE_REGIONS = (\n  { NAME = \"A\"; TOPOLOGICAL_ENTITIES = [ 1 ];\n");
    assert!(e.to_string().contains("never closed"), "{e}");
    let e = err("NAME = \"unterminated;\n");
    assert!(e.to_string().contains("string") && e.line == Some(1), "{e}");
    let e = err("CREATE_REGIONS = ( { NAME = \"A\"; TOPOLOGICAL_ENTITIES = [ GUIDEVANE ]; } );");
    assert!(e.to_string().contains("#define"), "an undefined macro is named: {e}");
    let e = err("HMIN = 1;\nHMIN = 2;");
    assert!(e.to_string().contains("twice") && e.line == Some(2), "{e}");
    let e = err("CREATE_REGIONS = ( { NAME = \"A\"; TOPOLOGICAL_ENTITIES = [ 1 ]; },\n { NAME = \"A\"; TOPOLOGICAL_ENTITIES = [ 2 ]; } );");
    assert_eq!(
        (e.line, *e.kind.clone()),
        (Some(2), RecipeErrorKind::DuplicateName { what: "region", name: "A".into() })
    );
}

#[test]
fn cpp_define_include_and_if0() {
    if !cpp_or_skip() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("inc")).unwrap();
    std::fs::write(dir.path().join("inc/common.h"), "#define WALLS 1, 2\n#define SMALL 0.01\nCREATE_DISTANCE_FUNCTIONS = ( { NAME = \"F\"; MINSIZE = SMALL; MAXSIZE = 1; MAXDISTANCE = 1; EXPONENT = 1; } );\n").unwrap();
    let main = "# a libconfig hash comment, not a directive\n#include \"inc/common.h\"\n#if 0\nthis is not libconfig at all {{{\n#endif\nCREATE_REGIONS = ( { NAME = \"W\"; TOPOLOGICAL_ENTITIES = [ WALLS ]; } );\nHMIN = SMALL;\n";
    std::fs::write(dir.path().join("main.cfg"), main).unwrap();
    let r = Recipe::from_path(&dir.path().join("main.cfg")).unwrap();
    assert_eq!(r.regions["W"], vec![EntityRef::Tag(1), EntityRef::Tag(2)]);
    assert_eq!(r.global.h_min, Some(0.01));
    assert_eq!(
        r.functions["F"],
        FunctionSpec::Distance {
            size_at_source: 0.01,
            size_at_max_distance: 1.0,
            max_distance: 1.0,
            exponent: 1.0
        }
    );

    // Errors point into the original files and lines, through cpp's line markers.
    std::fs::write(dir.path().join("inc/common.h"), "#define WALLS 1, 2\n#define SMALL 0.01\nCREATE_DISTANCE_FUNCTIONS = ( { NAME = \"F\"; MINSIZ = 1; } );\n").unwrap();
    let e = Recipe::from_path(&dir.path().join("main.cfg")).unwrap_err();
    assert!(e.file.as_ref().unwrap().ends_with("inc/common.h"), "{e}");
    assert_eq!((e.line, e.suggestion.as_deref()), (Some(3), Some("MINSIZE")), "{e}");
    std::fs::write(dir.path().join("inc/common.h"), "#define WALLS 1, 2\n#define SMALL 0.01\n")
        .unwrap();
    std::fs::write(dir.path().join("main.cfg"), format!("{main}\n\nCREATE_ALGORITHMS = ( {{ TYPE = \"UNIFORM\"; SIZE = 1; REGIONS = \"V\"; }} );\n")).unwrap();
    let e = Recipe::from_path(&dir.path().join("main.cfg")).unwrap_err();
    assert!(e.file.as_ref().unwrap().ends_with("main.cfg"), "{e}");
    assert_eq!(e.line, Some(10), "{e}");
    // A preprocessor error is reported with its message.
    std::fs::write(dir.path().join("main.cfg"), "#include \"missing.h\"\n").unwrap();
    let e = Recipe::from_path(&dir.path().join("main.cfg")).unwrap_err();
    assert!(
        matches!(*e.kind, RecipeErrorKind::Preprocessor(_)) && e.to_string().contains("missing.h"),
        "{e}"
    );
}

#[test]
fn libconfig_include_is_relative_to_the_including_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("parts")).unwrap();
    std::fs::write(
        dir.path().join("parts/regions.cfg"),
        "CREATE_REGIONS = ( { NAME = \"A\"; ENTITIES = [ 1 ]; } );\n@include \"more.cfg\"\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("parts/more.cfg"), "HMIN = 0.5;\nHMAX = x;\n").unwrap();
    std::fs::write(
        dir.path().join("main.cfg"),
        "// main\n@include \"parts/regions.cfg\"\nGRADATION = 1.5;\n",
    )
    .unwrap();
    let e = Recipe::from_path(&dir.path().join("main.cfg")).unwrap_err();
    assert!(e.file.as_ref().unwrap().ends_with("parts/more.cfg") && e.line == Some(2), "{e}");
    std::fs::write(dir.path().join("parts/more.cfg"), "HMIN = 0.5;\n").unwrap();
    let r = Recipe::from_path(&dir.path().join("main.cfg")).unwrap();
    assert_eq!((r.global.h_min, r.global.gradation, r.regions.len()), (Some(0.5), Some(1.5), 1));
}

const CANONICAL: &str = r#"
HMIN = 0.01; HMAX = 2.0;
CREATE_REGIONS = ( { NAME = "Wall"; TOPOLOGICAL_ENTITIES = [ 1 ]; }, { NAME = "Other"; TOPOLOGICAL_ENTITIES = [ 2 ]; } );
CREATE_POLYLINES = ( { NAME = "Wake"; X_COORDS = [ 0.0, 1.0 ]; Y_COORDS = [ 0.0, 0.5 ]; } );
CREATE_DISTANCE_FUNCTIONS = (
  { NAME = "D1"; MINSIZE = 0.1; MAXSIZE = 1.0; MAXDISTANCE = 2.0; EXPONENT = 1.0; },
  { NAME = "D2"; MINSIZE = 0.5; MAXSIZE = 0.2; MAXDISTANCE = 3.0; EXPONENT = 2.0; } );
CREATE_PROJECTION_FUNCTIONS = ( { NAME = "P"; MAXSIZE = 2.0; MAXDISTANCE = 1.0; EXPONENT = 1.0; } );
CREATE_CURVATURE_TO_SIZE_FUNCTIONS = ( { NAME = "C"; MINSIZE = 0.1; MAXSIZE = 1.0; SIZE_OF_ERROR = 0.01; } );
CREATE_ALGORITHMS = (
  { TYPE = "CURVATURE_OF_BORDER"; PERPENDICULAR_FUNCTION = "D1"; CURVATURE_TO_SIZE_FUNCTION = "C"; PROJECTION_FUNCTION = "P"; REGIONS = ( "Wall" ); },
  { TYPE = "DISTANCE_BETWEEN_TWO_BORDERS"; PERPENDICULAR_FUNCTION = "D1"; PARALLEL_FUNCTION = "D2"; REGIONS = ( "Wall" ); REGIONS2 = ( "Other" ); },
  { TYPE = "DISTANCE_TO_IMAGINARY_POLYLINE"; PERPENDICULAR_FUNCTION = "D1"; POLYLINE_DISTANCE_FUNCTION = "D2"; PARALLEL_PROJECTION_FUNCTION = "P"; COORDINATES = "Wake"; }
);
"#;

#[test]
fn every_spelling_variant_gives_the_same_model() {
    let canonical = cfg(CANONICAL).unwrap();
    let variants: &[(&str, &str)] = &[
        ("HMIN = 0.01", "H_MIN = 0.01"),
        ("HMAX = 2.0", "H_MAX = 2.0"),
        ("NAME = \"Wall\"; TOPOLOGICAL_ENTITIES", "NAME = \"Wall\"; ENTITIES"),
        ("NAME = \"D1\"; MINSIZE", "NAME = \"D1\"; MIN_SIZE"),
        ("NAME = \"D1\"; MINSIZE", "NAME = \"D1\"; SIZE_AT_BORDER"),
        ("NAME = \"D1\"; MINSIZE", "NAME = \"D1\"; SIZE_AT_TOPOLOGICAL_VERTEX"),
        ("0.1; MAXSIZE = 1.0; MAXDISTANCE = 2.0", "0.1; MAX_SIZE = 1.0; MAXDISTANCE = 2.0"),
        (
            "0.1; MAXSIZE = 1.0; MAXDISTANCE = 2.0",
            "0.1; SIZE_AT_MAX_DISTANCE = 1.0; MAXDISTANCE = 2.0",
        ),
        ("0.1; MAXSIZE = 1.0; MAXDISTANCE = 2.0", "0.1; MAXSIZE = 1.0; MAX_DISTANCE = 2.0"),
        ("NAME = \"P\"; MAXSIZE", "NAME = \"P\"; MAX_SIZE"),
        ("NAME = \"P\"; MAXSIZE = 2.0; MAXDISTANCE", "NAME = \"P\"; MAXSIZE = 2.0; MAX_DISTANCE"),
        ("NAME = \"C\"; MINSIZE = 0.1; MAXSIZE", "NAME = \"C\"; MIN_SIZE = 0.1; MAX_SIZE"),
        (
            "CURVATURE_TO_SIZE_FUNCTION = \"C\"; PROJECTION_FUNCTION",
            "CURVATURE_TO_SIZE_FUNCTION = \"C\"; PARALLEL_PROJECTION_FUNCTION",
        ),
        (
            "POLYLINE_DISTANCE_FUNCTION = \"D2\"; PARALLEL_PROJECTION_FUNCTION",
            "PARALLEL_FUNCTION = \"D2\"; PROJECTION_FUNCTION",
        ),
        (
            "REGIONS = ( \"Wall\" ); REGIONS2 = ( \"Other\" )",
            "REGIONS = \"Wall\"; REGIONS2 = [ \"Other\" ]",
        ),
        ("TYPE = \"CURVATURE_OF_BORDER\"", "TYPE = \"curvature_of_border\""),
    ];
    for (from, to) in variants {
        assert!(CANONICAL.contains(from), "{from}");
        let text = CANONICAL.replacen(from, to, 1);
        let r = cfg(&text).unwrap_or_else(|e| panic!("{to}: {e}"));
        assert_eq!(r, canonical, "{to}");
    }
    // Two spellings of one key are an error, not a silent choice.
    let e = cfg(&CANONICAL.replacen(
        "MINSIZE = 0.1; MAXSIZE = 1.0; MAXDISTANCE",
        "MINSIZE = 0.1; SIZE_AT_BORDER = 0.2; MAXSIZE = 1.0; MAXDISTANCE",
        1,
    ))
    .unwrap_err();
    assert_eq!(
        *e.kind,
        RecipeErrorKind::DuplicateKey { key: "SIZE_AT_BORDER".into(), other: "MINSIZE".into() }
    );
    // A projection function has no size at the source (thesis 4.3.5.2).
    let e = cfg(&CANONICAL.replacen(
        "NAME = \"P\"; MAXSIZE",
        "NAME = \"P\"; MIN_SIZE = 0.1; MAXSIZE",
        1,
    ))
    .unwrap_err();
    assert!(e.to_string().contains("MIN_SIZE is not a parameter of a projection function"), "{e}");
}

#[test]
fn misspelt_keys_and_names_get_suggestions_with_lines() {
    let e =
        cfg("HMIN = 1;\nCREATE_DISTANCE_FUNCTIONS = (\n { NAME = \"F\";\n   MINSIZ = 0.1; } );")
            .unwrap_err();
    assert_eq!(e.to_string(), "unknown key MINSIZ at recipe.cfg:4 (in CREATE_DISTANCE_FUNCTIONS entry 1), did you mean MINSIZE?");
    let e = cfg("CREATE_REGION = ();").unwrap_err();
    assert_eq!(e.suggestion.as_deref(), Some("CREATE_REGIONS"));
    let e = cfg("CREATE_ALGORITHMS = ( { TYPE = \"UNIFORM\"; SIZE = 1; REGIONS = \"A\"; FUNCTION = \"F\"; } );").unwrap_err();
    assert!(
        matches!(&*e.kind, RecipeErrorKind::UnknownKey { key } if key == "FUNCTION"),
        "a key of another algorithm type: {e}"
    );
    let e = cfg("CREATE_ALGORITHMS = ( { TYPE = \"DISTANCE_TO_BOARDER\"; } );").unwrap_err();
    assert_eq!(e.suggestion.as_deref(), Some("\"DISTANCE_TO_BORDER\""));

    let text = CANONICAL.replace(
        "PERPENDICULAR_FUNCTION = \"D1\"; PARALLEL_FUNCTION = \"D2\"",
        "PERPENDICULAR_FUNCTION = \"D1\"; PARALLEL_FUNCTION = \"D3\"",
    );
    let e = cfg(&text).unwrap_err();
    assert_eq!(
        e.to_string(),
        "algorithm 2 names function \"D3\" at recipe.cfg:12 (in CREATE_ALGORITHMS entry 2, DISTANCE_BETWEEN_TWO_BORDERS), did you mean \"D1\"?"
    );
    let e = cfg(&CANONICAL.replace("REGIONS2 = ( \"Other\" )", "REGIONS2 = ( \"Otter\" )"))
        .unwrap_err();
    assert_eq!((e.line, e.suggestion.as_deref()), (Some(12), Some("\"Other\"")), "{e}");
    let e = cfg(&CANONICAL.replace("COORDINATES = \"Wake\"", "COORDINATES = \"Wak\"")).unwrap_err();
    assert_eq!(e.suggestion.as_deref(), Some("\"Wake\""), "{e}");
    // A function of the wrong kind.
    let e = cfg(&CANONICAL
        .replace("CURVATURE_TO_SIZE_FUNCTION = \"C\"", "CURVATURE_TO_SIZE_FUNCTION = \"D2\""))
    .unwrap_err();
    assert_eq!(e.to_string().split(" at ").next().unwrap(), "algorithm 1: CURVATURE_TO_SIZE_FUNCTION names \"D2\", a distance function; expected a curvature-to-size function");
    // A parameter out of range names the function, key, file and line.
    let e = cfg(&CANONICAL.replace("MAXDISTANCE = 3.0", "MAXDISTANCE = -3.0")).unwrap_err();
    assert_eq!(e.line, Some(7));
    assert!(
        e.to_string()
            .starts_with("function \"D2\": MAXDISTANCE (maximal distance) = -3 is out of range"),
        "{e}"
    );

    let e = toml("[functions.F]\nkind = \"distance\"\nsize_at_source = 0.1\nsize_at_max_distance = 1.0\nmax_distance = 0\nexponent = 1\n").unwrap_err();
    assert_eq!(
        e.to_string(),
        "function \"F\": MAXDISTANCE (maximal distance) = 0 is out of range: expected a finite number > 0 at recipe.toml:5 (in key max_distance of function \"F\")"
    );
    let t =
        "[functions.F]\nkind = \"distance\"\nsize_at_source = 0.1\nsize_at_max_distnace = 1.0\n";
    let e = toml(t).unwrap_err();
    assert_eq!(
        e.to_string(),
        "unknown key size_at_max_distnace at recipe.toml:4, did you mean size_at_max_distance?"
    );
    let e = toml("[[algorithms]]\ntype = \"distance_to_boarder\"\n").unwrap_err();
    assert_eq!((e.line, e.suggestion.as_deref()), (Some(2), Some("\"distance_to_border\"")), "{e}");
    let e = toml("[global]\nhmin = 0.1\nhmaks = 2\n").unwrap_err();
    assert_eq!((e.line, e.suggestion.as_deref()), (Some(3), Some("hmax")), "{e}");
    let e = Recipe::from_str(
        "{\"global\": {\"hmin\": 0.1,\n \"gradaton\": 1.2}}",
        RecipeFormat::Json,
        Path::new("r.json"),
    )
    .unwrap_err();
    assert_eq!((e.line, e.suggestion.as_deref()), (Some(2), Some("gradation")), "{e}");
}

const TOML_OF_CANONICAL: &str = r#"
[mesh]
hmin = 0.01
hmax = 2

[regions]
Wall = [1]
Other = [2]

[polylines]
Wake = [[0, 0], [1, 0.5]]

[functions.D1]
kind = "distance"
size_at_source = 0.1
size_at_max_distance = 1.0
max_distance = 2.0
exponent = 1.0

[functions.D2]
kind = "distance"
size_at_source = 0.5
size_at_max_distance = 0.2
max_distance = 3.0
exponent = 2.0

[functions.P]
kind = "projection"
size_at_max_distance = 2.0
max_distance = 1.0
exponent = 1.0

[functions.C]
kind = "curvature_to_size"
min_size = 0.1
max_size = 1.0
size_of_error = 0.01

[[algorithms]]
type = "curvature_of_border"
perpendicular = "D1"
curvature_to_size = "C"
projection = "P"
regions = ["Wall"]

[[algorithms]]
type = "distance_between_two_borders"
perpendicular = "D1"
parallel = "D2"
regions = ["Wall"]
regions2 = ["Other"]

[[algorithms]]
type = "distance_to_imaginary_polyline"
perpendicular = "D1"
polyline_distance = "D2"
projection = "P"
polyline = "Wake"
"#;

#[test]
fn toml_and_json_equivalents_and_round_trips() {
    let from_cfg = cfg(CANONICAL).unwrap();
    let from_toml = toml(TOML_OF_CANONICAL).unwrap();
    assert_eq!(from_toml, from_cfg);
    let json = from_cfg.to_json();
    let from_json = Recipe::from_str(&json, RecipeFormat::Json, Path::new("r.json")).unwrap();
    assert_eq!(from_json, from_cfg);
    // cfg -> toml -> json -> cfg -> model, and the appendix example too when cpp is here.
    let mut models = vec![from_cfg];
    if cpp_or_skip() {
        models.push(Recipe::from_path(&fixture("appendix-a.cfg")).unwrap());
    }
    for m in models {
        let t = Recipe::from_str(&m.to_toml(), RecipeFormat::Toml, Path::new("a.toml")).unwrap();
        let j = Recipe::from_str(&t.to_json(), RecipeFormat::Json, Path::new("a.json")).unwrap();
        let c = cfg(&j.to_libconfig()).unwrap();
        assert_eq!(t, m);
        assert_eq!(j, m);
        assert_eq!(c, m);
        assert_eq!(c.to_toml(), m.to_toml(), "the written text is stable");
    }
    // Mixed tag numbers and names, odd names and exact floats survive libconfig writing.
    let mut odd = toml(TOML_OF_CANONICAL).unwrap();
    odd.regions.insert(
        "we\"ird\\ name\t".into(),
        vec![EntityRef::Tag(-3), EntityRef::Name("Wall \"A\"".into())],
    );
    odd.polylines
        .insert("P2".into(), PolylinePoints::Plane(vec![[0.1 + 0.2, 1e-300], [-7.0, 1.0 / 3.0]]));
    assert_eq!(cfg(&odd.to_libconfig()).unwrap(), odd);
    assert_eq!(toml(&odd.to_toml()).unwrap(), odd);
}

/// A unit square in two triangles, face tag 1 "Plate"; bottom line tag 1 ("Bottom"),
/// right line tag 2; vertex cells tag 2 (top right corner) and tag 5 "Corner" (origin).
/// Tag 1 is a face and a curve, tag 2 a curve and a point.
fn clashing_tags() -> Topology {
    let mut m = TaggedMesh::new();
    m.points = vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
    let mut t = CellBlock::new(CellKind::Triangle);
    t.push(&[0, 1, 2], 1, 1);
    t.push(&[0, 2, 3], 1, 1);
    let mut l = CellBlock::new(CellKind::Line);
    l.push(&[0, 1], 1, 1);
    l.push(&[1, 2], 2, 2);
    let mut v = CellBlock::new(CellKind::Vertex);
    v.push(&[2], 2, 2);
    v.push(&[0], 5, 5);
    m.blocks = vec![v, l, t];
    m.tag_names.insert((2, 1), "Plate".into());
    m.tag_names.insert((1, 1), "Bottom".into());
    m.tag_names.insert((0, 5), "Corner".into());
    Topology::from_mesh(&m)
}

fn with_algorithms(regions: &str, algorithms: &str) -> Recipe {
    let text = format!(
        "CREATE_REGIONS = ( {regions} );\nCREATE_DISTANCE_FUNCTIONS = ( {{ NAME = \"D\"; MINSIZE = 0.1; MAXSIZE = 1; MAXDISTANCE = 1; EXPONENT = 1; }} );\nCREATE_PROJECTION_FUNCTIONS = ( {{ NAME = \"P\"; MAXSIZE = 1; MAXDISTANCE = 1; EXPONENT = 1; }} );\nCREATE_POLYLINES = ( {{ NAME = \"L\"; X_COORDS = [0, 1]; Y_COORDS = [0.5, 0.5]; }} );\nCREATE_ALGORITHMS = ( {algorithms} );"
    );
    cfg(&text).unwrap()
}

const BORDER: &str = "{ TYPE = \"DISTANCE_TO_BORDER\"; PERPENDICULAR_FUNCTION = \"D\"; PARALLEL_FUNCTION = \"D\"; REGIONS = \"R\"; }";
const UNIFORM: &str = "{ TYPE = \"UNIFORM\"; SIZE = 1; REGIONS = \"R\"; }";
const TO_POINT: &str = "{ TYPE = \"DISTANCE_TO_POINT\"; FUNCTION = \"D\"; REGIONS = \"R\"; }";
const POLYLINE: &str = "{ TYPE = \"DISTANCE_TO_IMAGINARY_POLYLINE\"; PERPENDICULAR_FUNCTION = \"D\"; POLYLINE_DISTANCE_FUNCTION = \"D\"; PROJECTION_FUNCTION = \"P\"; COORDINATES = \"L\"; REGIONS = \"R\"; }";

fn on(plan: &smartmesh::sizing::SizingPlan, i: usize) -> EntitySet {
    match &plan.steps[i].algorithm {
        Algorithm::Uniform(Uniform { on, .. }) => on.clone(),
        Algorithm::DistanceToPoint(DistanceToPoint { sources, .. }) => sources.clone(),
        Algorithm::DistanceToBorder(DistanceToBorder { borders, .. }) => borders.clone(),
        Algorithm::DistanceToImaginaryPolyline(DistanceToImaginaryPolyline { within, .. }) => {
            within.clone()
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_tag_in_several_dimensions_takes_the_dimension_the_algorithm_expects() {
    let topo = clashing_tags();
    let region = |ents: &str| format!("{{ NAME = \"R\"; ENTITIES = ( {ents} ); }}");
    let curve1 = by_tags(&topo, 1, &[1]);
    let face1 = by_tags(&topo, 2, &[1]);
    let point2 = by_tags(&topo, 0, &[2]);
    let curve2 = by_tags(&topo, 1, &[2]);
    assert!(curve1.len() == 1 && face1.len() == 1 && point2.len() == 1 && curve2.len() == 1);

    let plan = |ents: &str, alg: &str| with_algorithms(&region(ents), alg).resolve(&topo);
    assert_eq!(on(&plan("1", BORDER).unwrap().plan, 0), curves(curve1.clone()));
    assert_eq!(
        on(&plan("1", UNIFORM).unwrap().plan, 0),
        EntitySet { faces: face1.clone(), ..Default::default() }
    );
    assert_eq!(
        on(&plan("1", POLYLINE).unwrap().plan, 0),
        EntitySet { faces: face1.clone(), ..Default::default() }
    );
    assert_eq!(
        on(&plan("2", TO_POINT).unwrap().plan, 0),
        EntitySet { points: point2.clone(), ..Default::default() }
    );
    assert_eq!(on(&plan("2", BORDER).unwrap().plan, 0), curves(curve2.clone()));
    // A name that exists in one dimension settles a clashing number.
    let both = plan("1, \"Bottom\"", UNIFORM).unwrap();
    assert_eq!(on(&both.plan, 0), curves(curve1.clone()));
    assert_eq!(both.regions[0].entity_names, ["Bottom"]);
    // Unused and ambiguous: reported without a dimension, no error.
    let unused = with_algorithms(
        &format!("{}, {{ NAME = \"U\"; ENTITIES = [ 1 ]; }}", region("2")),
        TO_POINT,
    )
    .resolve(&topo)
    .unwrap();
    let u = unused.regions.iter().find(|r| r.name == "U").unwrap();
    assert_eq!((u.dimension, u.used_by.clone()), (None, vec![]));

    // Two algorithms wanting different dimensions of one region: ambiguous.
    let e = plan("1", &format!("{UNIFORM}, {BORDER}")).unwrap_err();
    assert!(
        matches!(&*e.kind, RecipeErrorKind::Dimension { region, detail } if region == "R" && detail.contains("ambiguous") && detail.contains("tag 1 is in curves and faces")),
        "{e}"
    );
    assert_eq!(e.line, Some(1));
    // Entities of different dimensions in one region.
    let e = plan("1, 5", UNIFORM).unwrap_err();
    assert!(e.to_string().contains("different dimensions"), "{e}");
    // A dimension the algorithm cannot use.
    let e = plan("\"Corner\"", POLYLINE).unwrap_err();
    assert!(
        e.to_string().contains("holds points, but DISTANCE_TO_IMAGINARY_POLYLINE takes faces"),
        "{e}"
    );
}

#[test]
fn absent_tags_and_names_are_errors() {
    let topo = clashing_tags();
    let e = with_algorithms("{ NAME = \"R\";\n ENTITIES = [ 1,\n 77 ]; }", UNIFORM)
        .resolve(&topo)
        .unwrap_err();
    assert!(
        matches!(&*e.kind, RecipeErrorKind::AbsentEntity { region, entity, .. } if region == "R" && entity == "tag 77"),
        "{e}"
    );
    assert_eq!(e.line, Some(3), "the line of the entity itself");
    assert!(e.to_string().contains("curve tags 1, 2"), "{e}");
    // Unused regions are checked too.
    let e = with_algorithms(
        "{ NAME = \"R\"; ENTITIES = [ 1 ]; }, { NAME = \"S\"; ENTITIES = [ \"Botom\" ]; }",
        UNIFORM,
    )
    .resolve(&topo)
    .unwrap_err();
    assert_eq!(e.suggestion.as_deref(), Some("\"Bottom\""), "{e}");
    // The distributor has no tag 3055.
    let r = toml("[regions]\nOutlet = [3055]\n").unwrap();
    let e = r.resolve(&distributor()).unwrap_err();
    assert_eq!(e.line, Some(2), "{e}");
}

/// Every algorithm of the table, whatever it declares, goes through libconfig, TOML and
/// JSON and comes back equal: the readers and writers know the algorithms only by their
/// declarations, so a new one is covered without a line here.
#[test]
fn every_algorithm_of_the_table_round_trips_in_every_format() {
    use smartmesh::sizing::algorithms::{FunctionKind, ParameterKind, TABLE};
    let mut base = Recipe::default();
    let r = &mut base;
    r.regions.insert("R".into(), vec![EntityRef::Tag(1)]);
    r.polylines.insert("L".into(), PolylinePoints::Plane(vec![[0.0, 0.0], [1.0, 0.5]]));
    r.functions.insert(
        "D".into(),
        FunctionSpec::Distance {
            size_at_source: 0.1,
            size_at_max_distance: 1.0,
            max_distance: 2.0,
            exponent: 1.0,
        },
    );
    r.functions.insert(
        "P".into(),
        FunctionSpec::Projection { size_at_max_distance: 1.0, max_distance: 2.0, exponent: 1.0 },
    );
    r.functions.insert(
        "C".into(),
        FunctionSpec::CurvatureToSize { min_size: 0.01, max_size: 1.0, size_of_error: 0.001 },
    );
    // Every parameter given (a choice its last word), then each optional one left out in
    // turn; the variants the algorithm's own check accepts must round trip, and every
    // parameter must be given in one of them.
    for entry in TABLE {
        let d = entry.declaration;
        let value = |kind: ParameterKind| match kind {
            ParameterKind::Size => SpecValue::Size(0.25),
            ParameterKind::OptionalSize => SpecValue::Size(2.0),
            ParameterKind::OptionalNorm => SpecValue::Size(f64::INFINITY),
            ParameterKind::Choice(words) => SpecValue::Name(words.last().unwrap().to_string()),
            ParameterKind::Function(FunctionKind::Distance) => SpecValue::Name("D".into()),
            ParameterKind::Function(FunctionKind::Projection) => SpecValue::Name("P".into()),
            ParameterKind::Function(FunctionKind::Curvature) => SpecValue::Name("C".into()),
            ParameterKind::Regions { .. } => SpecValue::Names(vec!["R".into()]),
            ParameterKind::Polyline => SpecValue::Name("L".into()),
            ParameterKind::File => SpecValue::Name("sheets/wake.stl".into()),
            ParameterKind::PointData => SpecValue::Name("u".into()),
        };
        let optional: Vec<Option<usize>> = std::iter::once(None)
            .chain(
                d.parameters
                    .iter()
                    .enumerate()
                    .filter(|(_, p)| {
                        matches!(
                            p.kind,
                            ParameterKind::OptionalSize
                                | ParameterKind::OptionalNorm
                                | ParameterKind::Choice(_)
                        )
                    })
                    .map(|(i, _)| Some(i)),
            )
            .collect();
        let mut given = vec![false; d.parameters.len()];
        let mut accepted = 0;
        for left_out in optional {
            let values = d.parameters.iter().enumerate().map(|(i, p)| {
                (p.field, if left_out == Some(i) { SpecValue::Absent } else { value(p.kind) })
            });
            let mut one = base.clone();
            one.algorithms.push(AlgorithmSpec::new(d.keyword, values).unwrap());
            if one.validate().is_err() {
                continue;
            }
            accepted += 1;
            for (i, g) in given.iter_mut().enumerate() {
                *g |= left_out != Some(i);
            }
            for format in [RecipeFormat::Libconfig, RecipeFormat::Toml, RecipeFormat::Json] {
                let text = one.to_format(format);
                let back = Recipe::from_str(&text, format, Path::new("all")).unwrap();
                assert_eq!(back, one, "{format:?}:\n{text}");
                assert_eq!(back.algorithms[0].keyword(), d.keyword);
            }
        }
        assert!(accepted > 0 && given.iter().all(|&g| g), "{}", d.keyword);
    }
}

#[test]
fn values_nested_past_the_limit_are_an_error_not_a_stack_overflow() {
    let deep = |open: &str, close: &str, n: usize| {
        format!("// nested\nA = {}{};\n", open.repeat(n), close.repeat(n))
    };
    for (open, close) in [("[", "]"), ("(", ")"), ("{ a = ", "}")] {
        let e = cfg(&deep(open, close, 20_000)).unwrap_err();
        assert!(
            matches!(&*e.kind, RecipeErrorKind::Limit(m) if m.contains("nested deeper than 64")),
            "{e}"
        );
        assert_eq!((e.file.as_deref(), e.line), (Some(Path::new("recipe.cfg")), Some(2)), "{e}");
    }
    // At the limit the text parses, and is then refused for what it says.
    let e = cfg(&deep("(", ")", 64)).unwrap_err();
    assert!(matches!(&*e.kind, RecipeErrorKind::UnknownKey { key } if key == "A"), "{e}");
    let e = cfg(&deep("(", ")", 65)).unwrap_err();
    assert!(matches!(&*e.kind, RecipeErrorKind::Limit(_)), "{e}");
}

/// Reading options with a byte budget of `max_bytes`.
fn budget(max_bytes: usize) -> ReadOptions {
    ReadOptions { max_bytes, ..ReadOptions::default() }
}

#[cfg(unix)]
#[test]
fn a_recipe_reads_only_regular_files_within_its_budget() {
    let dir = tempfile::tempdir().unwrap();
    let file = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let not_regular = |e: &RecipeError, name: &str, line: usize| {
        assert!(
            matches!(&*e.kind, RecipeErrorKind::Io(m) if m.contains("/dev/zero is not a regular file")),
            "{e}"
        );
        assert!(e.file.as_ref().unwrap().ends_with(name) && e.line == Some(line), "{e}");
    };
    // libconfig's @include and cpp's #include of a device: refused at their line, before
    // anything is read (the #include before cpp runs, so no cpp is needed here).
    let at = file("at.cfg", "HMIN = 1;\n@include \"/dev/zero\"\n");
    not_regular(&Recipe::from_path(&at).unwrap_err(), "at.cfg", 2);
    let hash = file("hash.cfg", "#define X 1\n#include </dev/zero>\nHMIN = X;\n");
    not_regular(&Recipe::from_path(&hash).unwrap_err(), "hash.cfg", 2);
    // Also when an included header includes it.
    file("dev.h", "#define Y 2\n\n#include \"/dev/zero\"\n");
    let nested = file("nested.cfg", "#include \"dev.h\"\nHMIN = Y;\n");
    not_regular(&Recipe::from_path(&nested).unwrap_err(), "dev.h", 3);
    // The recipe itself behind a symbolic link.
    let link = dir.path().join("link.cfg");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let e = Recipe::from_path(&link).unwrap_err();
    assert!(e.to_string().contains("is not a regular file"), "{e}");
    // A pipe would block the reader: refused without opening it.
    if std::process::Command::new("mkfifo").arg(dir.path().join("pipe")).status().is_ok() {
        let e = Recipe::from_path(&file("pipe.cfg", "@include \"pipe\"\n")).unwrap_err();
        assert!(e.to_string().contains("pipe is not a regular file"), "{e}");
    }

    // The byte budget: the recipe, each include and their sum.
    let comment = format!("// {}\n", "x".repeat(97)); // 100 bytes
    let e =
        Recipe::from_path_with(&file("big.cfg", &comment.repeat(11)), &budget(1000)).unwrap_err();
    assert!(matches!(&*e.kind, RecipeErrorKind::Limit(m) if m.contains("big.cfg")), "{e}");
    file("part.cfg", &comment.repeat(4));
    let twice = file("twice.cfg", "@include \"part.cfg\"\n@include \"part.cfg\"\nHMIN = 1;\n");
    assert_eq!(Recipe::from_path_with(&twice, &budget(1000)).unwrap().global.h_min, Some(1.0));
    let thrice = file(
        "thrice.cfg",
        "@include \"part.cfg\"\n@include \"part.cfg\"\n@include \"part.cfg\"\nHMIN = 1;\n",
    );
    let e = Recipe::from_path_with(&thrice, &budget(1000)).unwrap_err();
    assert!(
        matches!(&*e.kind, RecipeErrorKind::Limit(m) if m.contains("@include \"part.cfg\"")),
        "{e}"
    );
    assert!(e.file.as_ref().unwrap().ends_with("thrice.cfg") && e.line == Some(3), "{e}");
    let e = Recipe::from_str_with(
        &comment.repeat(11),
        RecipeFormat::Libconfig,
        Path::new("r.cfg"),
        &budget(1000),
    )
    .unwrap_err();
    assert!(matches!(&*e.kind, RecipeErrorKind::Limit(_)), "{e}");
}

/// An executable shell script in `dir` standing for the C preprocessor.
#[cfg(unix)]
fn fake_cpp(dir: &Path, body: &str) -> Vec<String> {
    use std::os::unix::fs::PermissionsExt as _;
    let p = dir.join("fake-cpp");
    std::fs::write(&p, format!("#!/bin/sh\n{body}\n")).unwrap();
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o755)).unwrap();
    vec![p.to_string_lossy().into_owned()]
}

#[cfg(unix)]
#[test]
fn the_preprocessor_is_stopped_past_its_output_and_time_limits() {
    let dir = tempfile::tempdir().unwrap();
    let text = "#define X 1\nHMIN = X;\n";
    let read = |options: &ReadOptions| {
        Recipe::from_str_with(text, RecipeFormat::Libconfig, &dir.path().join("r.cfg"), options)
    };
    // Endless output: stopped when it passes the budget.
    let options = ReadOptions {
        cpp_command: Some(fake_cpp(dir.path(), "exec yes 'HMIN = 1;'")),
        ..budget(100_000)
    };
    let e = read(&options).unwrap_err();
    assert!(
        matches!(&*e.kind, RecipeErrorKind::Limit(m) if m.contains("output passed the 100 kB")),
        "{e}"
    );
    // No output and no end (an #include of a pipe, say): stopped at the deadline, with
    // what it started (cpp runs cc1; here the shell runs a sleep of its own).
    let pid_file = dir.path().join("pid");
    let options = ReadOptions {
        cpp_command: Some(fake_cpp(
            dir.path(),
            &format!("sleep 60 &\necho $! > '{}'\nwait", pid_file.display()),
        )),
        cpp_time_limit: std::time::Duration::from_millis(500),
        ..ReadOptions::default()
    };
    let e = read(&options).unwrap_err();
    assert!(
        matches!(&*e.kind, RecipeErrorKind::Limit(m) if m.contains("time limit of 0.500 s")),
        "{e}"
    );
    if cfg!(target_os = "linux") {
        let pid = std::fs::read_to_string(&pid_file).unwrap();
        let stat = format!("/proc/{}/stat", pid.trim());
        // Killed: gone, or a zombie until its new parent reaps it.
        let alive = |s: String| s.rsplit(')').next().is_some_and(|r| !r.trim().starts_with('Z'));
        assert!(
            (0..100).any(|_| {
                std::thread::sleep(std::time::Duration::from_millis(20));
                !std::fs::read_to_string(&stat).is_ok_and(alive)
            }),
            "the preprocessor's child {pid} still runs"
        );
    }
    // A real cpp on a macro bomb (10^8 values from 400 bytes): stopped by the budget.
    if cpp_or_skip() {
        let bomb = "#define A0 1,1,1,1,1,1,1,1,1,1\n#define A1 A0,A0,A0,A0,A0,A0,A0,A0,A0,A0\n#define A2 A1,A1,A1,A1,A1,A1,A1,A1,A1,A1\n#define A3 A2,A2,A2,A2,A2,A2,A2,A2,A2,A2\n#define A4 A3,A3,A3,A3,A3,A3,A3,A3,A3,A3\n#define A5 A4,A4,A4,A4,A4,A4,A4,A4,A4,A4\n#define A6 A5,A5,A5,A5,A5,A5,A5,A5,A5,A5\n#define A7 A6,A6,A6,A6,A6,A6,A6,A6,A6,A6\nX = [ A7 ];\n";
        let e = Recipe::from_str_with(
            bomb,
            RecipeFormat::Libconfig,
            Path::new("bomb.cfg"),
            &budget(100_000),
        )
        .unwrap_err();
        assert!(matches!(&*e.kind, RecipeErrorKind::Limit(m) if m.contains("output")), "{e}");
    }
}

#[test]
fn untrusted_recipes_run_no_preprocessor_and_include_nothing() {
    let untrusted = |text: &str| {
        Recipe::from_str_with(
            text,
            RecipeFormat::Libconfig,
            Path::new("u.cfg"),
            &ReadOptions::untrusted(),
        )
    };
    for (text, what, line) in [
        ("HMIN = 1;\n#include \"/etc/passwd\"\n", "#include", 2),
        ("#define X 1\nHMIN = X;\n", "#define", 1),
        ("HMIN = 1;\n\n@include \"/etc/passwd\"\n", "@include", 3),
    ] {
        let e = untrusted(text).unwrap_err();
        assert!(
            matches!(&*e.kind, RecipeErrorKind::NotAllowed(m) if m.contains(what) && m.contains("--no-preprocess")),
            "{e}"
        );
        assert_eq!(e.line, Some(line), "{e}");
        assert!(!e.to_string().contains("root:"), "{e}");
    }
    // Hash comments are libconfig's own: still read.
    let r = untrusted("# a comment\nHMIN = 1; # another\n").unwrap();
    assert_eq!(r.global.h_min, Some(1.0));
}

/// Sizes where the quadratic versions took minutes (10^5 settings in one group: 5·10^9
/// name comparisons; 10^4 TOML regions: a newline count over the text per key, 24 s of
/// CPU; 10^4 regions of a 2 000-cell face: the face measured per region, 79 s; 10^5
/// unused regions, each resolved and measured, 118 s) and the linear ones a fraction of
/// a second, in debug builds.
#[test]
fn many_keys_and_regions_are_read_and_resolved_without_quadratic_work() {
    // libconfig: 10^5 settings in one group, the last a duplicate of the first (found by
    // a map, not by comparing each setting with all before it).
    const SETTINGS: usize = 100_000;
    let mut text = String::from("CREATE_REGIONS = ( {\n");
    for i in 0..SETTINGS {
        text.push_str(&format!("K{i} = {i};\n"));
    }
    text.push_str("K0 = 0; } );\n");
    let e = cfg(&text).unwrap_err();
    assert!(
        e.to_string().contains("setting K0 appears twice in the same group (first at line 2)"),
        "{e}"
    );
    assert_eq!(e.line, Some(SETTINGS + 2));

    // TOML: 10^4 regions of the distributor's face, one used; each line found by a
    // search of the line starts, the entities by an index, only the used region
    // measured.
    const REGIONS: usize = 10_000;
    let topo = distributor();
    let mut text = String::from("[regions]\n");
    for i in 0..REGIONS {
        text.push_str(&format!("R{i} = [1000]\n"));
    }
    let algorithm = "[[algorithms]]\ntype = \"uniform\"\nsize = 1.0\nregions = [\"R7\"]\n";
    let resolved = toml(&format!("{text}{algorithm}")).unwrap().resolve(&topo).unwrap();
    assert_eq!(resolved.regions.len(), REGIONS);
    let used = resolved.regions.iter().find(|r| r.name == "R7").unwrap();
    assert_eq!(
        (used.dimension, used.entities, used.cells, used.used_by.clone()),
        (Some(2), 1, Some(1988), vec![1])
    );
    // Unused regions are looked up (their tags and dimension are reported) but not
    // measured.
    for r in resolved.regions.iter().filter(|r| r.name != "R7") {
        assert_eq!(
            (r.dimension, &r.tags, r.vertices, r.edges, r.cells, r.used_by.is_empty()),
            (Some(2), &vec![1000], None, None, None, true)
        );
    }
    // An absent tag in the last region: its line, through the line index.
    let last = format!("{text}R{REGIONS} = [1000, 4242]\n{algorithm}");
    let e = toml(&last).unwrap().resolve(&topo).unwrap_err();
    assert_eq!(e.line, Some(REGIONS + 2), "{e}");
}

#[test]
fn an_entity_of_the_wrong_type_says_what_an_entity_is() {
    for (text, found) in [
        ("[regions]\nA = [{ x = 1 }]\n", "invalid type: map"),
        ("[regions]\nA = [1.5]\n", "floating point `1.5`"),
        ("[regions]\nA = [true]\n", "boolean `true`"),
    ] {
        let e = toml(text).unwrap_err();
        let m = e.to_string();
        assert!(
            m.contains(found)
                && m.contains("a tag number (an integer) or a tag name (a string)")
                && !m.contains("untagged enum"),
            "{m}"
        );
        assert_eq!(e.line, Some(2), "{m}");
    }
    let e = toml("[regions]\nA = [99999999999]\n").unwrap_err();
    assert!(e.to_string().contains("tag 99999999999 is out of range"), "{e}");
    assert_eq!(toml("[regions]\nA = [3, \"Wall\"]\n").unwrap().regions["A"].len(), 2);
}

#[test]
fn invisible_characters_are_named_and_a_byte_order_mark_is_skipped() {
    let e = toml("[regions]\nA\u{a0}= [1]\n").unwrap_err();
    assert!(
        e.to_string().contains("column 2 holds an invisible character, U+00A0 NO-BREAK SPACE"),
        "{e}"
    );
    assert_eq!(e.line, Some(2));
    let e = cfg("HMIN = 1;\nHMAX\u{200b} = 2;\n").unwrap_err();
    assert!(e.to_string().contains("U+200B ZERO WIDTH SPACE"), "{e}");
    assert_eq!(e.line, Some(2));
    assert_eq!(cfg("\u{feff}HMIN = 1;\n").unwrap().global.h_min, Some(1.0));
    assert_eq!(toml("\u{feff}[global]\nhmin = 1.0\n").unwrap().global.h_min, Some(1.0));
}
