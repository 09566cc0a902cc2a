//! The examples of `examples/`, as the tests that run them see them: one list, the
//! folder, and the rule for the distributor's preprocessed recipe.

use std::path::{Path, PathBuf};

/// Every example: (folder under examples/, recipe under examples/).
pub(crate) const EXAMPLES: &[(&str, &str)] = &[
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
pub(crate) fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples")
}

/// The distributor's recipe has a `#define`: it needs cpp. On CI a missing cpp is a
/// failure, elsewhere the distributor is skipped.
pub(crate) fn cpp_or_skip() -> bool {
    smartmesh_test_support::cli::cpp_or_skip("examples/distributor/recipe.cfg")
}

#[allow(dead_code)] // used by adapt_examples.rs only
/// One figure a README prints from a run (see `examples/figures.py`): the examples it is
/// of, the field, the text between the two comments, and where it is.
#[derive(Debug)]
pub(crate) struct Figure {
    /// The examples (one, or several for a block of result lines).
    pub examples: Vec<String>,
    /// `vertices`, `triangles`, `conforming`, `quality-mean`, `quality-min`,
    /// `iterations`, `seconds` or `line`.
    pub field: String,
    /// The text printed.
    pub text: String,
    /// The README and the line of the figure.
    pub place: String,
}

#[allow(dead_code)] // used by adapt_examples.rs only
/// The READMEs whose figures come from the examples' runs.
pub(crate) fn readmes_with_figures() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = vec![root.join("README.md"), examples().join("README.md")];
    let mut folders: Vec<PathBuf> = std::fs::read_dir(examples())
        .unwrap()
        .map(|e| e.unwrap().path().join("README.md"))
        .filter(|p| p.is_file())
        .collect();
    folders.sort();
    files.extend(folders);
    files
}

#[allow(dead_code)] // used by adapt_examples.rs only
/// Every `<!--fig:NAMES:FIELD-->TEXT<!--/fig-->` of `path`.
pub(crate) fn figures_in(path: &Path) -> Vec<Figure> {
    const OPEN: &str = "<!--fig:";
    const CLOSE: &str = "<!--/fig-->";
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = Vec::new();
    let mut rest = 0;
    while let Some(i) = text[rest..].find(OPEN).map(|i| rest + i) {
        let place = format!("{}:{}", path.display(), text[..i].lines().count());
        let head_end = i + text[i..].find("-->").expect("a figure's comment is closed");
        let (names, field) = text[i + OPEN.len()..head_end]
            .rsplit_once(':')
            .unwrap_or_else(|| panic!("{place}: a figure is <!--fig:NAMES:FIELD-->"));
        let body = head_end + 3;
        let end = body + text[body..].find(CLOSE).expect("a figure ends with <!--/fig-->");
        out.push(Figure {
            examples: names.split(',').map(str::to_string).collect(),
            field: field.to_string(),
            text: text[body..end].to_string(),
            place,
        });
        rest = end + CLOSE.len();
    }
    out
}

#[allow(dead_code)] // used by adapt_examples.rs only
/// `n` as the READMEs print a count: grouped by thousands from 10 000 (`15 773`, `9749`).
pub(crate) fn grouped(n: usize) -> String {
    if n < 10_000 {
        return n.to_string();
    }
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k) % 3 == 0 {
            out.push(' ');
        }
        out.push(c);
    }
    out
}
