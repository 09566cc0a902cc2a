//! The examples of `examples/`, as the tests that run them see them: one list, the
//! folder, and the rule for the distributor's preprocessed recipe.

use std::path::{Path, PathBuf};

/// Every example: (folder under examples/, recipe under examples/).
pub const EXAMPLES: &[(&str, &str)] = &[
    ("naca0012-agard01", "naca0012-agard01/recipe.toml"),
    ("gamm-a7-viscous", "gamm-a7-viscous/recipe.toml"),
    ("naca0012-agard02", "naca0012-agard02/recipe.toml"),
    ("naca0012-agard03", "naca0012-agard03/recipe.toml"),
    ("naca0012-agard04", "naca0012-agard04/recipe.toml"),
    ("naca0012-agard05", "naca0012-agard05/recipe.toml"),
    ("u-duct", "u-duct/recipe.cfg"),
    ("distributor/1-narrow", "distributor/recipe.cfg"),
    ("distributor/2-thick", "distributor/recipe.cfg"),
    ("distributor/3-s-shaped", "distributor/recipe.cfg"),
];

/// The `examples/` folder.
pub fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
}

/// The distributor's recipe has a `#define`: it needs cpp. On CI a missing cpp is a
/// failure, elsewhere the distributor is skipped.
pub fn cpp_or_skip() -> bool {
    smartmesh_test_support::cli::cpp_or_skip("examples/distributor/recipe.cfg")
}
