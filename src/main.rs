//! The `smartmesh` command line. Thin by design: parsing and printing here, every
//! computation in the library (as ripgrep's `crates/core/main.rs` keeps its `main`).

mod cli;

use std::process::ExitCode;

fn main() -> ExitCode {
    cli::main()
}
