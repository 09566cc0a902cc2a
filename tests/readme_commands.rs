//! The commands of the READMEs (README.md and those of examples/) run as written from a
//! fresh clone without touching a file of the repository: every file a command writes
//! goes under `target/` (or a temporary directory), tools that write beside their input
//! unless told (Gmsh, mmg2d_O3) are told, and scripts that rewrite committed files are
//! not called that way. Each `sh` block is read line by line: commands split at `&&`,
//! `;` and `|`, outputs found by the options of each tool. A command this test does not
//! know fails it, so that a new one is looked at. README.md also says how to put
//! `smartmesh` on PATH before its first bare `smartmesh` command.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The READMEs whose commands are checked.
fn readmes() -> Vec<PathBuf> {
    let mut out = vec![root().join("README.md"), root().join("examples/README.md")];
    let mut sub: Vec<PathBuf> = std::fs::read_dir(root().join("examples"))
        .unwrap()
        .map(|e| e.unwrap().path().join("README.md"))
        .filter(|p| p.is_file())
        .collect();
    sub.sort();
    out.extend(sub);
    out
}

/// The lines of the `sh` blocks of `text`, with their line numbers, comments dropped.
fn sh_lines(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut inside = false;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.starts_with("```") {
            inside = !inside && t == "```sh";
            continue;
        }
        if inside {
            let code = match t.find(" #") {
                Some(k) => &t[..k],
                None if t.starts_with('#') => "",
                None => t,
            };
            if !code.trim().is_empty() {
                out.push((i + 1, code.trim().to_string()));
            }
        }
    }
    out
}

/// Where a command writes: a path it names, and why.
#[derive(Debug)]
struct Write {
    path: String,
    why: &'static str,
}

/// The value after option `name` in `args`.
fn value<'a>(args: &[&'a str], name: &str) -> Option<&'a str> {
    args.iter().position(|a| *a == name).and_then(|i| args.get(i + 1)).copied()
}

/// The outputs of one command (its words), or why it is refused.
fn outputs(words: &[&str]) -> Result<Vec<Write>, String> {
    let mut out = Vec::new();
    // Redirections.
    for (i, w) in words.iter().enumerate() {
        if *w == ">" || *w == ">>" {
            let path = words.get(i + 1).ok_or("a redirection without a file")?;
            out.push(Write { path: path.to_string(), why: "redirection" });
        }
    }
    let words: Vec<&str> =
        words.iter().take_while(|w| **w != ">" && **w != ">>").copied().collect();
    let (program, args) = words.split_first().ok_or("an empty command")?;
    match *program {
        "smartmesh" | "target/release/smartmesh" => out.extend(smartmesh_outputs(args)?),
        "cargo" => match args.first().copied() {
            Some("run") => {
                let k = args.iter().position(|a| *a == "--").ok_or("cargo run without --")?;
                out.extend(smartmesh_outputs(&args[k + 1..])?);
            }
            Some("test") | Some("build") => {}
            Some("install") if value(args, "--path") == Some(".") => {}
            _ => return Err(format!("cargo {args:?}: not a command this test knows")),
        },
        "gmsh" => {
            let o = value(args, "-o").ok_or("Gmsh writes beside the .geo unless given -o")?;
            out.push(Write { path: o.to_string(), why: "gmsh -o" });
        }
        "mmg2d_O3" => {
            let o = value(args, "-out").ok_or("mmg2d_O3 writes beside its input unless -out")?;
            out.push(Write { path: o.to_string(), why: "mmg2d_O3 -out" });
        }
        "bash" if args.first() == Some(&"examples/run.sh") => {
            if args.contains(&"--update-pictures") {
                return Err("examples/run.sh --update-pictures rewrites committed pictures".into());
            }
            if args.contains(&"--update-figures") {
                return Err("examples/run.sh --update-figures rewrites committed READMEs".into());
            }
            // It writes under target/examples/ (examples/run.sh says so).
        }
        "bash" if args.first() == Some(&"examples/ugawg3d/make.sh") => {
            if args.contains(&"--update-pictures") {
                return Err(
                    "examples/ugawg3d/make.sh --update-pictures rewrites committed pictures".into(),
                );
            }
            // Everything under its WORK argument, target/ugawg3d/ when not given.
            let work = args.get(2).copied().unwrap_or("target/ugawg3d/");
            out.push(Write { path: work.to_string(), why: "examples/ugawg3d/make.sh WORK" });
        }
        "bash" if args.first() == Some(&"examples/wing3d/run.sh") => {
            if args.contains(&"--update-figures") {
                return Err(
                    "examples/wing3d/run.sh --update-figures rewrites committed files".into()
                );
            }
            // It writes under target/examples/wing3d/ (its header says so).
        }
        "python3" if args.first() == Some(&"examples/wing3d/geometry.py") => {
            let o = args.get(1).ok_or("geometry.py without its output")?;
            out.push(Write { path: o.to_string(), why: "geometry.py OUT" });
            if let Some(w) = value(args, "--wake") {
                out.push(Write { path: w.to_string(), why: "geometry.py --wake" });
            }
        }
        // It prints to stdout only.
        "python3" if args.first() == Some(&"examples/wing3d/figures.py") => {}
        "python3" if args.first() == Some(&"examples/make_examples.py") => {
            match args.get(1).copied() {
                // Temporary directories only.
                Some("--estimate") | Some("--mmg") => {}
                Some("--out") => out.push(Write {
                    path: args.get(2).ok_or("--out without a folder")?.to_string(),
                    why: "make_examples.py --out",
                }),
                _ => {
                    return Err("make_examples.py without --out rewrites the committed files".into())
                }
            }
        }
        // Into the Python environment, nothing of the repository.
        "python3" if args == ["-m", "pip", "install", "-r", "requirements-interop.txt"] => {}
        "for" | "do" | "done" => {}
        other => return Err(format!("`{other}`: not a command this test knows")),
    }
    Ok(out)
}

fn smartmesh_outputs(args: &[&str]) -> Result<Vec<Write>, String> {
    let mut out = Vec::new();
    for name in ["-o", "--output"] {
        if let Some(o) = value(args, name) {
            out.push(Write { path: o.to_string(), why: "smartmesh -o" });
        }
    }
    if let Some(h) = value(args, "--history") {
        // adapt writes it; report reads it.
        if args.first() == Some(&"adapt") {
            out.push(Write { path: h.to_string(), why: "adapt --history" });
        }
    }
    let positional: Vec<&str> = args
        .iter()
        .enumerate()
        .filter(|(i, a)| {
            !a.starts_with('-') && (*i == 0 || !args[i - 1].starts_with('-') || args[i - 1] == "-")
        })
        .map(|(_, a)| *a)
        .collect();
    match positional.as_slice() {
        ["convert", _, o, ..] | ["recipe", "convert", _, o, ..] => {
            out.push(Write { path: o.to_string(), why: "convert's output" })
        }
        [sub, ..]
            if [
                "info", "recipe", "size", "mesh", "remesh", "adapt", "batch", "report", "convert",
                "layer", "variants",
            ]
            .contains(sub) => {}
        _ => return Err(format!("smartmesh {args:?}: not a subcommand this test knows")),
    }
    Ok(out)
}

/// Whether `path` lies under `target/` or a temporary directory, without climbing out.
fn harmless(path: &str) -> bool {
    path == "-"
        || (!path.split('/').any(|c| c == "..")
            && (path.starts_with("target/")
                || path.starts_with("/tmp/")
                || path.starts_with("$TMPDIR/")
                || path.starts_with("\"$TMPDIR\"/")))
}

/// Checks every command of `text`; returns how many commands and outputs it checked.
fn check(name: &Path, text: &str) -> Result<(usize, usize), Vec<String>> {
    let mut errors = Vec::new();
    let (mut commands, mut writes) = (0, 0);
    for (line, code) in sh_lines(text) {
        for command in code.split("&&").flat_map(|c| c.split(';')).flat_map(|c| c.split('|')) {
            let words: Vec<&str> = command.split_whitespace().collect();
            if words.is_empty() {
                continue;
            }
            commands += 1;
            match outputs(&words) {
                Ok(ws) => {
                    for w in ws {
                        writes += 1;
                        if !harmless(&w.path) {
                            errors.push(format!(
                                "{}:{line}: `{}` ({}) is not under target/",
                                name.display(),
                                w.path,
                                w.why
                            ));
                        }
                    }
                }
                Err(e) => {
                    errors.push(format!("{}:{line}: {e}: {}", name.display(), command.trim()))
                }
            }
        }
    }
    if errors.is_empty() {
        Ok((commands, writes))
    } else {
        Err(errors)
    }
}

#[test]
fn readme_commands_write_only_under_target() {
    let (mut commands, mut writes) = (0, 0);
    let mut errors = Vec::new();
    for path in readmes() {
        let text = std::fs::read_to_string(&path).unwrap();
        match check(&path, &text) {
            Ok((c, w)) => {
                commands += c;
                writes += w;
            }
            Err(e) => errors.extend(e),
        }
    }
    assert!(errors.is_empty(), "{}", errors.join("\n"));
    // The READMEs have dozens of commands: a parser that found none would prove nothing.
    assert!(commands >= 40 && writes >= 30, "{commands} commands, {writes} outputs");
    println!("{commands} commands, {writes} outputs, all under target/");
}

#[test]
fn the_checker_refuses_what_the_readme_once_said() {
    let old = "```sh\n\
        smartmesh size fixtures/cylinder.msh --recipe fixtures/cylinder.toml -o bgm.pos\n\
        gmsh fixtures/cylinder.geo -2 -bgm bgm.pos -setnumber Mesh.Algorithm 7\n\
        mmg2d_O3 cyl.mesh -sol cyl.sol\n\
        bash examples/run.sh --update-pictures\n\
        smartmesh convert a.msh ../b.vtu\n\
        smartmesh report x.msh -o target/x.png > out.txt\n\
        ```\n";
    let errors = check(Path::new("old.md"), old).unwrap_err();
    assert_eq!(errors.len(), 6, "{errors:#?}");
    for (e, what) in errors.iter().zip([
        "`bgm.pos`",
        "Gmsh writes beside",
        "mmg2d_O3 writes beside",
        "--update-pictures",
        "`../b.vtu`",
        "`out.txt`",
    ]) {
        assert!(e.contains(what), "{e} lacks {what}");
    }
}

#[test]
fn readme_puts_smartmesh_on_path_before_its_first_bare_use() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let install =
        text.find("cargo install --path .").expect("README says `cargo install --path .`");
    let first_use = sh_lines(&text)
        .into_iter()
        .find(|(_, code)| code.starts_with("smartmesh "))
        .map(|(line, _)| line)
        .expect("a bare smartmesh command");
    let install_line = text[..install].lines().count();
    assert!(
        install_line < first_use,
        "README.md:{first_use} runs smartmesh before line {install_line} says how to install it"
    );
}
