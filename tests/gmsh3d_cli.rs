//! `smartmesh convert` on Gmsh volume meshes: the public 3D fixtures convert between
//! the four MSH encodings with their cells and groups, and a malformed volume file exits
//! with status 2, naming the file and the line, leaving no output behind.

#[path = "support/cli.rs"]
mod cli;
use cli::{bad, ok, run};
use smartmesh_test_support::formats as common;

#[test]
fn convert_carries_3d_gmsh_meshes_through_every_encoding() {
    smartmesh_test_support::require_public_fixtures!();
    let dir = tempfile::tempdir().unwrap();
    for file in
        ["box_cyl.v22_binary.msh", "hex_prism_pyr.v41_ascii.msh", "box_cyl_o2.v41_ascii.msh"]
    {
        let src = common::public_fixture(&format!("3d/{file}"));
        let want = common::read_file(&format!("3d/{file}"));
        for (flags, enc) in [
            (&["--gmsh-version", "2.2"][..], "v22_ascii"),
            (&["--gmsh-version", "2.2", "--binary"][..], "v22_binary"),
            (&[][..], "v41_ascii"),
            (&["--binary"][..], "v41_binary"),
        ] {
            let out = dir.path().join(format!("{file}.{enc}.msh"));
            let mut args = vec!["convert", src.to_str().unwrap(), out.to_str().unwrap()];
            args.extend_from_slice(flags);
            ok(&run(&args));
            let back = smartmesh_formats::read_path(&out, None).unwrap();
            let what = format!("{file} as {enc}");
            assert_eq!(back.points, want.points, "{what}");
            assert_eq!(common::counts_per_tag(&back), common::counts_per_tag(&want), "{what}");
            assert_eq!(back.tag_names, want.tag_names, "{what}");
        }
    }
}

#[test]
fn malformed_volume_file_exits_two_naming_the_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad3d.msh");
    // A tetrahedron of three nodes, on line 19.
    std::fs::write(
        &p,
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3\n$EndElements\n",
    )
    .unwrap();
    let out = dir.path().join("out.msh");
    let e = bad(&run(&["convert", p.to_str().unwrap(), out.to_str().unwrap()]));
    assert!(e.contains("bad3d.msh:19"), "{e}");
    assert!(e.contains("tetra"), "{e}");
    assert!(!out.exists(), "no output may be left behind");
}
