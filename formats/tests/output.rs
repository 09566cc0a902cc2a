//! Output files: written as a set or not at all, through links, never over a read-only
//! file, never through a planted temporary; and which I/O errors are the user's (exit 2).
#![cfg(unix)]

use std::os::unix::fs::{symlink, PermissionsExt};
use std::path::{Path, PathBuf};

use smartmesh_formats::{
    read_path, write_all_atomically, write_path, CellBlock, CellKind, ErrorKind, Format,
    TaggedMesh, WriteOptions,
};

fn square() -> TaggedMesh {
    let mut m = TaggedMesh::new();
    m.points = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    let mut t = CellBlock::new(CellKind::Triangle);
    t.push(&[0, 1, 2], 1, 1);
    t.push(&[0, 2, 3], 1, 1);
    m.blocks.push(t);
    m
}

/// The names in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

fn mode(p: &Path) -> u32 {
    std::fs::metadata(p).unwrap().permissions().mode() & 0o7777
}

#[test]
fn a_link_planted_at_a_temporary_name_is_not_followed() {
    let dir = tempfile::tempdir().unwrap();
    let victim = dir.path().join("victim.txt");
    std::fs::write(&victim, "precious").unwrap();
    // The name the temporary had before it was random: `.NAME.smartmesh-PID.tmp`.
    let planted = dir.path().join(format!(".out.txt.smartmesh-{}.tmp", std::process::id()));
    symlink(&victim, &planted).unwrap();
    write_all_atomically(&[(dir.path().join("out.txt"), b"new".to_vec())]).unwrap();
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
    assert_eq!(std::fs::read_to_string(dir.path().join("out.txt")).unwrap(), "new");
}

#[test]
fn no_target_changes_unless_every_file_of_the_set_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let mesh = dir.path().join("out.mesh");
    std::fs::write(&mesh, "old mesh").unwrap();
    // The solution's name is taken by a directory: the set cannot be written.
    std::fs::create_dir(dir.path().join("out.sol")).unwrap();
    let mut m = square();
    m.point_data
        .insert("size".into(), smartmesh_formats::DataArray::new(1, vec![0.1, 0.1, 0.1, 0.1]));
    let e = write_path(&mesh, &m, None, &WriteOptions::default()).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::Unwritable(_)), "{e}");
    assert!(e.is_input_error());
    assert!(e.to_string().starts_with(&dir.path().join("out.sol").display().to_string()), "{e}");
    assert_eq!(std::fs::read_to_string(&mesh).unwrap(), "old mesh");
    assert_eq!(listing(dir.path()), ["out.mesh", "out.sol"]);

    // The same for a Triangle set whose .node cannot be written: the .ele stays as it was.
    let ele = dir.path().join("t.ele");
    std::fs::write(&ele, "old ele").unwrap();
    std::fs::create_dir(dir.path().join("t.node")).unwrap();
    assert!(write_path(&ele, &square(), None, &WriteOptions::default()).is_err());
    assert_eq!(std::fs::read_to_string(&ele).unwrap(), "old ele");
    assert_eq!(listing(dir.path()), ["out.mesh", "out.sol", "t.ele", "t.node"]);
}

#[test]
fn a_read_only_target_is_refused_and_left_as_it_is() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    std::fs::write(&out, "keep me").unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o444)).unwrap();
    let e = write_path(&out, &square(), None, &WriteOptions::default()).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::ReadOnly), "{e}");
    assert!(e.is_input_error());
    assert!(e.to_string().contains("read-only"), "{e}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me");
    assert_eq!(mode(&out), 0o444);
    assert_eq!(listing(dir.path()), ["out.msh"]);
}

#[test]
fn an_existing_file_keeps_its_permissions_and_a_new_one_gets_the_usual_ones() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    std::fs::write(&out, "old").unwrap();
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o640)).unwrap();
    write_path(&out, &square(), None, &WriteOptions::default()).unwrap();
    assert_eq!(mode(&out), 0o640);
    assert!(std::fs::read_to_string(&out).unwrap().starts_with("$MeshFormat"));

    let new = dir.path().join("new.msh");
    write_path(&new, &square(), None, &WriteOptions::default()).unwrap();
    // Not the 0600 of a temporary file: readable by others as any output (umask 022
    // or 002 leave the read bits).
    assert_eq!(mode(&new) & 0o044, 0o044, "{:o}", mode(&new));
}

#[test]
fn a_link_is_written_through() {
    let dir = tempfile::tempdir().unwrap();
    let real = dir.path().join("sub").join("real.msh");
    std::fs::create_dir(dir.path().join("sub")).unwrap();
    std::fs::write(&real, "old").unwrap();
    let link = dir.path().join("out.msh");
    symlink(Path::new("sub/real.msh"), &link).unwrap();
    // A chain: link2 -> out.msh -> sub/real.msh.
    let link2 = dir.path().join("link2.msh");
    symlink(&link, &link2).unwrap();
    write_path(&link2, &square(), None, &WriteOptions::default()).unwrap();
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert!(std::fs::symlink_metadata(&link2).unwrap().file_type().is_symlink());
    assert!(std::fs::read_to_string(&real).unwrap().starts_with("$MeshFormat"));

    // A dangling link creates the file it names.
    let dangling = dir.path().join("d.msh");
    symlink(Path::new("sub/made.msh"), &dangling).unwrap();
    write_path(&dangling, &square(), None, &WriteOptions::default()).unwrap();
    assert!(std::fs::symlink_metadata(&dangling).unwrap().file_type().is_symlink());
    assert!(dir.path().join("sub/made.msh").is_file());
}

#[test]
fn a_device_is_written_in_place() {
    use std::os::unix::fs::FileTypeExt;
    let opts = WriteOptions::default();
    write_path(Path::new("/dev/null"), &square(), Some(Format::Gmsh), &opts).unwrap();
    assert!(std::fs::metadata("/dev/null").unwrap().file_type().is_char_device());
    // A full device: the work fails (exit 1), naming the output.
    if Path::new("/dev/full").exists() {
        let e =
            write_path(Path::new("/dev/full"), &square(), Some(Format::Gmsh), &opts).unwrap_err();
        assert!(!e.is_input_error(), "{e}");
        assert!(e.to_string().starts_with("/dev/full: "), "{e}");
    }
}

#[test]
fn inputs_that_cannot_be_read_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.msh");
    let as_dir = dir.path().join("adir.msh");
    std::fs::create_dir(&as_dir).unwrap();
    for p in [&missing, &as_dir] {
        let e = read_path(p, None).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::Unreadable(_)), "{e}");
        assert!(e.is_input_error(), "{e}");
        assert!(e.to_string().starts_with(&p.display().to_string()), "{e}");
    }
}

#[test]
fn an_output_in_a_missing_directory_is_an_input_error() {
    let out: PathBuf = ["/nonexistent-dir-of-smartmesh", "out.msh"].iter().collect();
    let e = write_path(&out, &square(), None, &WriteOptions::default()).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::Unwritable(_)), "{e}");
    assert!(e.is_input_error());
}

#[test]
fn an_unknown_extension_names_the_file_and_the_known_ones() {
    let e =
        write_path(Path::new("cyl.abc"), &square(), None, &WriteOptions::default()).unwrap_err();
    let s = e.to_string();
    assert!(s.starts_with("cyl.abc: "), "{s}");
    assert!(s.contains("`.abc`") && s.contains(".msh") && s.contains(".vtu"), "{s}");
    assert!(!s.contains("<stdin>"), "{s}");
    let e = read_path(Path::new("noext"), None).unwrap_err();
    assert!(e.to_string().starts_with("noext: "), "{e}");
    assert!(e.to_string().contains("without an extension"), "{e}");
}
