//! CGNS (`.cgns`, HDF5): round trips (the public 3D meshes, point fields, arbitrary
//! meshes), what the CGNS library's own tools make of what we write (`cgnscheck`),
//! meshio's and VTK's CGNS readers, files the CGNS library writes (`tetgen_to_cgns`,
//! `cgnsconvert`), MIXED sections and several zones (made with h5py), and malformed
//! files. The tools skip, saying so, when absent, unless `SMARTMESH_REQUIRE_INTEROP=1`.
//! Built without the `cgns` feature, the tests check the refusal instead and the rest
//! skip, saying so (`.ci/run` runs them with `--features cgns`).

#[cfg(not(feature = "cgns"))]
#[test]
fn without_the_feature_cgns_is_refused_naming_the_feature_and_libhdf5() {
    use smartmesh_formats::{read_bytes, write_bytes, Format, ReadContext, WriteOptions};
    let mesh = smartmesh_test_support::grid::unit_square(2);
    let e = write_bytes(Format::Cgns, &mesh, &WriteOptions::default()).unwrap_err().to_string();
    assert!(e.contains("`cgns` feature") && e.contains("libhdf5-dev"), "{e}");
    let e =
        read_bytes(Format::Cgns, b"\x89HDF\r\n\x1a\n", &ReadContext::alone("cgns")).unwrap_err();
    assert!(e.to_string().contains("`cgns` feature"), "{e}");
    assert!(e.is_input_error());
    smartmesh_test_support::skip::skip(
        "the CGNS round trips and interop tests need `--features cgns` (and libhdf5)",
    );
}

#[cfg(feature = "cgns")]
#[path = "cgns_support/mod.rs"]
mod with_feature;
