//! OpenFOAM's own `checkMesh` on the 3D cases `smartmesh convert` writes directly (no
//! extrusion) from Gmsh meshes: box_cyl (a box with a cylindrical hole, tetrahedra)
//! and hex_prism_pyr (hexahedra, prisms, tetrahedra and pyramids, with an inner
//! interface group), ASCII and binary. Each must end with "Mesh OK." and no failed
//! check, with Gmsh's element counts per kind, the surface groups as patches, the
//! volume groups as cell zones and the inner group as a face zone. Skips, saying so,
//! when `checkMesh` is not on PATH, unless `SMARTMESH_REQUIRE_INTEROP=1`.

#[path = "support/cli.rs"]
#[allow(dead_code)]
mod support;

use std::path::Path;
use std::process::Command;

use smartmesh_test_support::formats as common;
use support::{bundled, ok, program, run};

/// Runs `checkMesh -case DIR` and returns its output; asserts it passed every check.
fn check_mesh(check: &Path, case: &Path) -> String {
    let mut c = Command::new(check);
    c.arg("-case").arg(case);
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

/// The number after `label:` in checkMesh's statistics (`prisms: 54`).
fn count(text: &str, label: &str) -> usize {
    let line = text.lines().find(|l| l.trim_start().starts_with(label)).unwrap_or("");
    line.rsplit(' ').next().and_then(|n| n.parse().ok()).unwrap_or(0)
}

#[test]
fn check_mesh_passes_gmsh_3d_meshes_written_directly() {
    smartmesh_test_support::require_public_fixtures!();
    let Some(check) = program("checkMesh") else { return };
    let dir = tempfile::tempdir().unwrap();
    // (fixture, tetrahedra, hexahedra, prisms, pyramids, patches, cell zones, face zones)
    let cases = [
        ("box_cyl", 2187, 0, 0, 0, &["Inlet", "Outlet", "Walls", "Cylinder"][..], 1, 0),
        ("hex_prism_pyr", 152, 27, 54, 9, &["Bottom", "Top", "Sides"][..], 3, 1),
    ];
    for (name, tets, hexes, prisms, pyramids, patches, cell_zones, face_zones) in cases {
        for binary in [false, true] {
            let src = common::public_fixture(&format!("3d/{name}.v41_ascii.msh"));
            let case = dir.path().join(format!("{name}-{binary}.foam"));
            let mut args = vec!["convert", src.to_str().unwrap(), case.to_str().unwrap()];
            if binary {
                args.push("--binary");
            }
            ok(&run(&args));
            let text = check_mesh(&check, &case);
            assert_eq!(count(&text, "tetrahedra:"), tets, "{name}: {text}");
            assert_eq!(count(&text, "hexahedra:"), hexes, "{name}: {text}");
            assert_eq!(count(&text, "prisms:"), prisms, "{name}: {text}");
            assert_eq!(count(&text, "pyramids:"), pyramids, "{name}: {text}");
            assert_eq!(count(&text, "boundary patches:"), patches.len(), "{name}: {text}");
            assert_eq!(count(&text, "cell zones:"), cell_zones, "{name}: {text}");
            assert_eq!(count(&text, "face zones:"), face_zones, "{name}: {text}");
            for patch in patches {
                assert!(text.contains(&format!("    {patch} ")), "{patch}: {text}");
            }
        }
    }
}

/// A 3D case made by OpenFOAM's own `blockMesh` (a 3 x 2 x 2 block of hexahedra, two
/// blocks as two cell zones, every side a named patch) reads back as 12 hexahedra with
/// its patches and zones, and written again passes checkMesh with the same zones.
#[test]
fn a_3d_block_mesh_case_reads_back_as_hexahedra_with_patches_and_zones() {
    let Some(block_mesh) = program("blockMesh") else { return };
    let Some(check) = program("checkMesh") else { return };
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("box");
    let first = dir.path().join("first.foam");
    ok(&run(&["convert", &bundled("cylinder.msh"), first.to_str().unwrap()]));
    let system = case.join("system");
    std::fs::create_dir_all(&system).unwrap();
    for f in ["controlDict", "fvSchemes", "fvSolution"] {
        std::fs::copy(first.join("system").join(f), system.join(f)).unwrap();
    }
    std::fs::write(
        system.join("blockMeshDict"),
        "FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }
convertToMeters 1;
vertices ( (0 0 0) (1 0 0) (1 2 0) (0 2 0) (0 0 2) (1 0 2) (1 2 2) (0 2 2)
           (3 0 0) (3 2 0) (3 0 2) (3 2 2) );
blocks ( hex (0 1 2 3 4 5 6 7) left (1 2 2) simpleGrading (1 1 1)
         hex (1 8 9 2 5 10 11 6) right (2 2 2) simpleGrading (1 1 1) );
edges ();
boundary
(
    inlet { type patch; faces ( (0 4 7 3) ); }
    outlet { type patch; faces ( (8 9 11 10) ); }
    walls { type wall; faces ( (0 1 5 4) (1 8 10 5) (3 7 6 2) (2 6 11 9)
                               (0 3 2 1) (1 2 9 8) (4 5 6 7) (5 10 11 6) ); }
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
    assert!(info.contains("12 hexa, 32 quad"), "{info}");
    for name in ["\"inlet\"", "\"outlet\"", "\"walls\"", "\"left\"", "\"right\""] {
        assert!(info.contains(name), "{name}: {info}");
    }
    let again = dir.path().join("again.foam");
    ok(&run(&["convert", case.to_str().unwrap(), again.to_str().unwrap(), "--from", "openfoam"]));
    let text = check_mesh(&check, &again);
    assert_eq!(count(&text, "hexahedra:"), 12, "{text}");
    assert_eq!(count(&text, "cell zones:"), 2, "{text}");
    let boundary = std::fs::read_to_string(again.join("constant/polyMesh/boundary")).unwrap();
    let walls = &boundary[boundary.find("walls").unwrap()..];
    assert!(walls[..walls.find('}').unwrap()].contains("type            wall;"), "{boundary}");
}
