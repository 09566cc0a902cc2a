//! OpenFOAM's own `checkMesh` on the cases `smartmesh convert` writes: the bundled
//! cylinder (triangles), the cylinder with a boundary-layer skin of quads (`smartmesh
//! layer`, ASCII and binary), and the examples' meshes, periodic distributor included (its
//! periodic sides also as `cyclic` patch pairs, by `--cyclic` or from its recipe's
//! PERIODIC section, with a rotational quarter annulus). Each must end with
//! "Mesh OK." and no failed check. Skips, saying so, when `checkMesh` is not on PATH,
//! unless `SMARTMESH_REQUIRE_INTEROP=1` (CI, where `.ci/run` installs Debian's
//! `openfoam`).

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;
use std::process::Command;

use support::{bundled, ok, program, run, stderr};

/// Runs `checkMesh -case DIR` and returns its output; asserts it passed every check.
fn check_mesh(check: &Path, case: &Path) -> String {
    let mut c = Command::new(check);
    c.arg("-case").arg(case);
    // Debian's OpenFOAM finds its etc/ files there; a user's own setting is kept.
    if std::env::var_os("WM_PROJECT_DIR").is_none() {
        c.env("WM_PROJECT_DIR", "/usr/share/openfoam");
    }
    let out = c.output().expect("run checkMesh");
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success() && text.contains("\nMesh OK.") && !text.contains("Failed "),
        "checkMesh on {}:\n{text}\n{}",
        case.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// The number after `label:` in checkMesh's statistics (`prisms: 2134`).
fn count(text: &str, label: &str) -> usize {
    let line = text.lines().find(|l| l.trim_start().starts_with(label)).unwrap_or("");
    line.rsplit(' ').next().and_then(|n| n.parse().ok()).unwrap_or(0)
}

#[test]
fn check_mesh_passes_the_cylinder_its_skin_of_quads_and_the_examples() {
    let Some(check) = program("checkMesh") else { return };
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));

    // Triangles only: prisms, the four named curves as patches.
    let cyl = dir.path().join("cylinder.foam");
    ok(&run(&["convert", &bundled("cylinder.msh"), cyl.to_str().unwrap()]));
    let text = check_mesh(&check, &cyl);
    assert_eq!(count(&text, "prisms:"), 2134, "{text}");
    for patch in ["Inlet", "Outlet", "Walls", "Cylinder", "front", "back"] {
        assert!(text.contains(&format!("    {patch} ")), "{patch}: {text}");
    }
    let boundary = std::fs::read_to_string(cyl.join("constant/polyMesh/boundary")).unwrap();
    let cylinder = &boundary[boundary.find("Cylinder").unwrap()..];
    assert!(cylinder[..cylinder.find('}').unwrap()].contains("type            wall;"));

    // A skin of quads: hexahedra beside prisms, with --extrude and --to.
    let skin = dir.path().join("skin.msh");
    ok(&run(&[
        "layer",
        &bundled("cylinder.msh"),
        "--curves",
        "Cylinder",
        "--first-height",
        "0.002",
        "--ratio",
        "1.2",
        "--layers",
        "8",
        "-o",
        skin.to_str().unwrap(),
    ]));
    let skin_case = dir.path().join("skin-case");
    let o = run(&[
        "convert",
        skin.to_str().unwrap(),
        skin_case.to_str().unwrap(),
        "--to",
        "openfoam",
        "--extrude",
        "0.1",
    ]);
    ok(&o);
    assert!(!stderr(&o).contains("a hundredth"), "{}", stderr(&o));
    let text = check_mesh(&check, &skin_case);
    assert_eq!(count(&text, "hexahedra:"), 288, "{text}");
    assert!(text.contains("(4 1 0.1)"), "the bounding box ends at z = 0.1: {text}");

    // The same in binary (faceCompactList, 32-bit labels), read back by smartmesh too.
    let binary = dir.path().join("skin-binary.foam");
    ok(&run(&["convert", skin.to_str().unwrap(), binary.to_str().unwrap(), "--binary"]));
    let text = check_mesh(&check, &binary);
    assert_eq!(count(&text, "hexahedra:"), 288, "{text}");
    let info = ok(&run(&["info", binary.to_str().unwrap()]));
    assert!(info.contains("288 quad"), "{info}");

    // An axisymmetric wedge of 5 degrees: the bottom wall (y = 0) is the axis.
    let wedge = dir.path().join("wedge.foam");
    let o = run(&["convert", &bundled("cylinder.msh"), wedge.to_str().unwrap(), "--wedge", "5"]);
    ok(&o);
    assert!(stderr(&o).contains("on the wedge's axis"), "{}", stderr(&o));
    let text = check_mesh(&check, &wedge);
    assert!(text.contains("Mesh has 3 solution (non-empty) directions"), "{text}");
    let boundary = std::fs::read_to_string(wedge.join("constant/polyMesh/boundary")).unwrap();
    assert_eq!(boundary.matches("type            wedge;").count(), 2, "{boundary}");

    // The examples' starting meshes.
    for example in ["naca0012-agard01", "gamm-a7-viscous", "distributor/1-narrow"] {
        let input = root.join("examples").join(example).join("start.msh");
        let case = dir.path().join(example.replace('/', "-") + ".foam");
        ok(&run(&["convert", input.to_str().unwrap(), case.to_str().unwrap()]));
        check_mesh(&check, &case);
    }
}

/// The `Coupled point location match` line of checkMesh: it measures, for every cyclic
/// face, how far its points lie from its partner's transformed points.
fn coupled_match(text: &str) -> &str {
    text.lines().find(|l| l.contains("Coupled point location match")).unwrap_or("")
}

/// Periodic sides as `cyclic` patch pairs (`--cyclic`): the narrow distributor's
/// recipe pair (a translation by the pitch, 30 along y), and a quarter annulus turned
/// by 90 degrees about the z axis. checkMesh matches each face's points with its
/// partner's and says "Mesh OK."; the other sign of the translation is refused.
#[test]
fn check_mesh_matches_the_cyclic_patches_of_periodic_sides() {
    let Some(check) = program("checkMesh") else { return };
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let input = root.join("examples/distributor/1-narrow/start.msh");
    let case = dir.path().join("distributor.foam");
    let pair = "302,303,304=308,307,306:0,30";
    ok(&run(&["convert", input.to_str().unwrap(), case.to_str().unwrap(), "--cyclic", pair]));
    let text = check_mesh(&check, &case);
    assert!(coupled_match(&text).ends_with("OK."), "{text}");
    let boundary = std::fs::read_to_string(case.join("constant/polyMesh/boundary")).unwrap();
    assert_eq!(boundary.matches("type            cyclic;").count(), 2, "{boundary}");
    assert!(boundary.contains("separationVector (0 30 0);"), "{boundary}");
    assert!(boundary.contains("separationVector (0 -30 0);"), "{boundary}");
    // Both halves hold the 71 faces of the three curves of each side.
    assert_eq!(boundary.matches("nFaces          71;").count(), 2, "{boundary}");

    // The sides are not images of each other by (0, -30): refused, nothing written.
    let wrong = dir.path().join("wrong.foam");
    let o = run(&[
        "convert",
        input.to_str().unwrap(),
        wrong.to_str().unwrap(),
        "--cyclic",
        "302,303,304=308,307,306:0,-30",
    ]);
    assert!(
        !o.status.success() && stderr(&o).contains("not images of each other"),
        "{}",
        stderr(&o)
    );
    assert!(!wrong.join("constant/polyMesh").exists());

    // A quarter annulus 1 <= r <= 2, 0 <= theta <= 90 degrees, of 4 x 6 quads: side 1 at
    // theta = 0 turned by 90 degrees onto side 2 at theta = 90.
    let (nr, nt) = (4usize, 6usize);
    let node = |i: usize, j: usize| 1 + j * (nr + 1) + i;
    let mut nodes = String::new();
    for j in 0..=nt {
        for i in 0..=nr {
            let (r, t) =
                (1.0 + i as f64 / nr as f64, (j as f64 / nt as f64) * std::f64::consts::FRAC_PI_2);
            let (x, y) = if j == nt { (0.0, r) } else { (r * t.cos(), r * t.sin()) };
            nodes.push_str(&format!("{} {x:?} {y:?} 0\n", node(i, j)));
        }
    }
    let mut elements = Vec::new();
    for i in 0..nr {
        elements.push(format!("1 2 1 1 {} {}", node(i, 0), node(i + 1, 0)));
        elements.push(format!("1 2 2 2 {} {}", node(i + 1, nt), node(i, nt)));
    }
    for j in 0..nt {
        elements.push(format!("1 2 3 3 {} {}", node(0, j + 1), node(0, j)));
        elements.push(format!("1 2 4 4 {} {}", node(nr, j), node(nr, j + 1)));
        for i in 0..nr {
            let q = [node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)];
            elements.push(format!("3 2 5 5 {} {} {} {}", q[0], q[1], q[2], q[3]));
        }
    }
    let elements: String =
        elements.iter().enumerate().map(|(k, e)| format!("{} {e}\n", k + 1)).collect();
    let msh = format!(
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n4\n1 1 \"Periodic0\"\n1 2 \"Periodic90\"\n1 3 \"Inner\"\n1 4 \"Outer\"\n$EndPhysicalNames\n$Nodes\n{}\n{nodes}$EndNodes\n$Elements\n{}\n{elements}$EndElements\n",
        (nr + 1) * (nt + 1),
        elements.lines().count()
    );
    let msh_path = dir.path().join("annulus.msh");
    std::fs::write(&msh_path, msh).unwrap();
    let sector = dir.path().join("sector.foam");
    ok(&run(&[
        "convert",
        msh_path.to_str().unwrap(),
        sector.to_str().unwrap(),
        "--cyclic",
        "1=2@0,0,90",
        "--extrude",
        "0.1",
    ]));
    let text = check_mesh(&check, &sector);
    assert!(coupled_match(&text).ends_with("OK."), "{text}");
    assert_eq!(count(&text, "hexahedra:"), nr * nt, "{text}");
    let boundary = std::fs::read_to_string(sector.join("constant/polyMesh/boundary")).unwrap();
    assert!(boundary.contains("transform       rotational;"), "{boundary}");
    assert!(boundary.contains("rotationAxis    (0 0 1);"), "{boundary}");
}

/// The recipe's PERIODIC section as `cyclic` pairs, without `--cyclic`: `convert
/// --recipe` and `adapt -o case.foam` on the narrow distributor write the recipe's pair
/// (302, 303, 304 onto 308, 307, 306 by (0, 30)) as two cyclic patches checkMesh
/// matches; `--cyclic` given beside the recipe wins (only 302 and 308 glued).
#[test]
fn check_mesh_matches_the_cyclic_patches_of_a_recipe_periodic_section() {
    let Some(check) = program("checkMesh") else { return };
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let input = root.join("examples/distributor/1-narrow/start.msh");
    let recipe = root.join("examples/distributor/recipe.cfg");
    let (input, recipe) = (input.to_str().unwrap(), recipe.to_str().unwrap());
    let lower = "LowerPeriodic1_LowerPeriodic2_LowerPeriodic3";
    let upper = "UpperPeriodic1_UpperPeriodic2_UpperPeriodic3";

    let case = dir.path().join("converted.foam");
    let o = run(&["convert", input, case.to_str().unwrap(), "--recipe", recipe]);
    ok(&o);
    assert!(stderr(&o).contains("PERIODIC pair(s) written as cyclic"), "{}", stderr(&o));
    let text = check_mesh(&check, &case);
    assert!(coupled_match(&text).ends_with("OK."), "{text}");
    let boundary = std::fs::read_to_string(case.join("constant/polyMesh/boundary")).unwrap();
    assert_eq!(boundary.matches("type            cyclic;").count(), 2, "{boundary}");
    assert!(boundary.contains(&format!("neighbourPatch  {upper};")), "{boundary}");
    assert!(boundary.contains(&format!("neighbourPatch  {lower};")), "{boundary}");
    assert!(boundary.contains("separationVector (0 30 0);"), "{boundary}");
    assert_eq!(boundary.matches("nFaces          71;").count(), 2, "{boundary}");

    // The command line wins: one curve of each side glued, the others plain patches.
    let flag = dir.path().join("flag.foam");
    let o = run(&[
        "convert",
        input,
        flag.to_str().unwrap(),
        "--recipe",
        recipe,
        "--cyclic",
        "302=308:0,30",
    ]);
    ok(&o);
    assert!(stderr(&o).contains("--cyclic given"), "{}", stderr(&o));
    let text = check_mesh(&check, &flag);
    assert!(coupled_match(&text).ends_with("OK."), "{text}");
    let boundary = std::fs::read_to_string(flag.join("constant/polyMesh/boundary")).unwrap();
    assert_eq!(boundary.matches("type            cyclic;").count(), 2, "{boundary}");
    assert!(boundary.contains("neighbourPatch  UpperPeriodic1;"), "{boundary}");
    assert!(!boundary.contains(lower), "{boundary}");

    // The adaptation loop's result, remeshed twice with the sides kept matched and
    // then skinned: the recipe's pair glued on the case it writes.
    let adapted = dir.path().join("adapted.foam");
    ok(&run(&[
        "adapt",
        input,
        "--recipe",
        recipe,
        "-o",
        adapted.to_str().unwrap(),
        "--max-iterations",
        "2",
    ]));
    let text = check_mesh(&check, &adapted);
    assert!(coupled_match(&text).ends_with("OK."), "{text}");
    let boundary = std::fs::read_to_string(adapted.join("constant/polyMesh/boundary")).unwrap();
    assert_eq!(boundary.matches("type            cyclic;").count(), 2, "{boundary}");
    assert!(boundary.contains(&format!("neighbourPatch  {upper};")), "{boundary}");
}

/// OpenFOAM's own `blockMesh` writes a 3 x 2 lid-driven cavity (one empty patch
/// `frontAndBack` holding both planes); smartmesh reads it back as 6 quads with the
/// patches' lines, and writes it again as a case checkMesh passes.
#[test]
fn a_case_block_mesh_writes_reads_back_as_quads_with_its_patches() {
    let Some(block_mesh) = program("blockMesh") else { return };
    let Some(check) = program("checkMesh") else { return };
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("cavity");
    // The system/ files come from a case smartmesh writes.
    let first = dir.path().join("first.foam");
    ok(&run(&["convert", &bundled("cylinder.msh"), first.to_str().unwrap()]));
    std::fs::create_dir_all(&case).unwrap();
    let system = case.join("system");
    std::fs::create_dir_all(&system).unwrap();
    for f in ["controlDict", "fvSchemes", "fvSolution"] {
        std::fs::copy(first.join("system").join(f), system.join(f)).unwrap();
    }
    std::fs::write(
        system.join("blockMeshDict"),
        "FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }
convertToMeters 1;
vertices ( (0 0 0) (3 0 0) (3 2 0) (0 2 0) (0 0 0.1) (3 0 0.1) (3 2 0.1) (0 2 0.1) );
blocks ( hex (0 1 2 3 4 5 6 7) (3 2 1) simpleGrading (1 1 1) );
edges ();
boundary
(
    movingWall { type wall; faces ( (3 7 6 2) ); }
    fixedWalls { type wall; faces ( (0 4 7 3) (2 6 5 1) (1 5 4 0) ); }
    frontAndBack { type empty; faces ( (0 3 2 1) (4 5 6 7) ); }
);
",
    )
    .unwrap();
    let mut c = Command::new(block_mesh);
    c.arg("-case").arg(&case);
    if std::env::var_os("WM_PROJECT_DIR").is_none() {
        c.env("WM_PROJECT_DIR", "/usr/share/openfoam");
    }
    let out = c.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stdout));

    let info = ok(&run(&["info", case.to_str().unwrap(), "--from", "openfoam"]));
    assert!(info.contains("10 line, 6 quad"), "{info}");
    assert!(info.contains("\"movingWall\"") && info.contains("\"fixedWalls\""), "{info}");
    let again = dir.path().join("again.foam");
    ok(&run(&["convert", case.to_str().unwrap(), again.to_str().unwrap(), "--from", "openfoam"]));
    let text = check_mesh(&check, &again);
    assert_eq!(count(&text, "hexahedra:"), 6, "{text}");
    let boundary = std::fs::read_to_string(again.join("constant/polyMesh/boundary")).unwrap();
    assert!(boundary.contains("movingWall") && boundary.contains("fixedWalls"), "{boundary}");
}
