//! Options written with one dash, as MMG (`-hausd 0.01`, `-sol m.sol`, `-out o.mesh`),
//! Gmsh (`-format msh2`) and Triangle (`-pq30a0.01`) users write them. clap reads such a
//! word as a cluster of short flags: `-hausd` is the help (exit 0, the run silently does
//! nothing), `-out` is `-o ut`, `-sol` an unexpected `-s` with a tip about `--`. This
//! check, made before clap parses, refuses every one-dash word that is not exactly a
//! cluster clap would read as the user meant (exit 2), and names the option meant.
//!
//! The rule: a word `-xyz…` (two characters or more, the first a letter) passes only
//! when each of its characters is a short flag of the command, the last one possibly a
//! short option whose glued value holds something else than letters (`-oout.msh`,
//! `-rr.toml`: a path). Anything else is refused, with the long option of that name
//! (`-nosurf` → `--nosurf`), the smartmesh spelling of another tool's option (`-sol` →
//! `--metric`, `-pq30a0.01` → `mesh --min-angle 30 --max-area 0.01`), or the reading
//! clap would have made (`-out` would be `-o ut`).

use std::ffi::OsString;

use clap::Command;

/// The error message for the first one-dash word that clap would not read as meant (the
/// rule of the module: `-hausd`, `-sol`, `-out`, `-pq30a0.01`, any `-h…` longer than
/// `-h`), or `None`. Values of options are skipped (`--adapter-arg -hausd` passes
/// `-hausd` to the tool), and so is everything after `--`.
pub(super) fn single_dash_option(cli: &Command, args: &[OsString]) -> Option<String> {
    let mut cmd = cli.clone();
    cmd.build();
    let mut current = &cmd;
    let mut path = vec![cmd.get_name().to_string()];
    let mut skip_value = false;
    for arg in args.iter().skip(1) {
        if std::mem::take(&mut skip_value) {
            continue;
        }
        let Some(arg) = arg.to_str() else { continue };
        if arg == "--" {
            return None;
        }
        if let Some(long) = arg.strip_prefix("--") {
            skip_value = !long.contains('=') && takes_value(current, |a| has_long(a, long));
            continue;
        }
        if let Some(word) = arg.strip_prefix('-') {
            let mut chars = word.chars();
            let Some(first) = chars.next() else { continue };
            if word.len() == 1 {
                skip_value = takes_value(current, |a| a.get_short() == Some(first));
                continue;
            }
            if !first.is_ascii_alphabetic() {
                continue; // a negative number, or `-` (stdin or stdout)
            }
            if let Some(message) = one_dash_word(&cmd, current, &path, arg, word) {
                return Some(message);
            }
            // A cluster of short flags, or a short option with its value glued on
            // (`-oout.msh`): clap reads those as meant. The glued value is the argument.
            continue;
        }
        if let Some(sub) = current.find_subcommand(arg) {
            path.push(sub.get_name().to_string());
            current = sub;
        }
    }
    None
}

/// Why the one-dash word `arg` (`word` without its dash) of command `current` is not
/// what clap would read it as, or `None` when clap reads it as meant (see the module).
fn one_dash_word(
    root: &Command,
    current: &Command,
    path: &[String],
    arg: &str,
    word: &str,
) -> Option<String> {
    let name = word.split('=').next().unwrap_or(word);
    let command = path.join(" ");
    if current.get_arguments().any(|a| has_long(a, name)) {
        return Some(format!(
            "unknown option `{arg}`: did you mean `--{name}`? (smartmesh's options take two dashes)"
        ));
    }
    if let Some(meant) = foreign(current, name) {
        return Some(format!("unknown option `{arg}` for `{command}`: {meant}"));
    }
    if let Some(switches) = triangle_switches(word) {
        return Some(format!(
            "unknown option `{arg}` for `{command}`: Triangle's switches are `smartmesh mesh IN -o OUT{switches}` (smartmesh's options take two dashes)"
        ));
    }
    // As clap reads a cluster: flags, then possibly one option with its value glued on.
    // A cluster with the help in it (`-hausd`) is never meant: clap would print the help.
    for (i, c) in word.char_indices().take_while(|_| !word.starts_with('h')) {
        let Some(a) = current.get_arguments().find(|a| a.get_short() == Some(c)) else {
            break;
        };
        if !a.get_action().takes_values() {
            if i + c.len_utf8() == word.len() {
                return None; // every character a flag
            }
            continue;
        }
        let value = &word[i + c.len_utf8()..];
        let value = value.strip_prefix('=').unwrap_or(value);
        if value.is_empty() || !value.chars().all(|c| c.is_ascii_alphabetic()) {
            return None; // a path glued on, `-oout.msh`, or the value in the next word
        }
        let long = a.get_long().map(|l| format!(" (`--{l}`)")).unwrap_or_default();
        return Some(format!(
            "unknown option `{arg}` for `{command}`: it would read as `-{} {value}`; write `-{} {value}`{long} with a space if that is meant (smartmesh's options take two dashes)",
            &word[..i + c.len_utf8()],
            &word[..i + c.len_utf8()],
        ));
    }
    let mut message = format!(
        "unknown option `{arg}` for `{command}` (smartmesh's options take two dashes{})",
        if word.starts_with('h') { "; `-h` alone prints the help" } else { "" }
    );
    let elsewhere = subcommands_with(root, name);
    if !elsewhere.is_empty() {
        message.push_str(&format!("; `--{name}` is an option of `{}`", elsewhere.join("`, `")));
    }
    Some(message)
}

/// What smartmesh calls the option that MMG (`-sol`, `-met`, `-out`, `-in`) or Gmsh
/// (`-format`, `-bin`, `-bgm`) spells `name`, when `cmd` has it.
fn foreign(cmd: &Command, name: &str) -> Option<String> {
    let (tool, ours): (&str, &[&str]) = match name {
        "sol" | "met" => ("MMG's", &["metric", "solution-file"]),
        "out" => ("MMG's", &["output"]),
        "format" => ("Gmsh's", &["to"]),
        "bin" => ("Gmsh's", &["binary"]),
        "bgm" => ("Gmsh's", &["metric"]),
        "in" => return Some("the input is the first argument, with no option before it".into()),
        _ => return None,
    };
    let arg = ours.iter().find_map(|o| cmd.get_arguments().find(|a| a.get_long() == Some(o)))?;
    let short = arg.get_short().map(|c| format!("`-{c}` or ")).unwrap_or_default();
    Some(format!(
        "`-{name}` is {tool} spelling; smartmesh's is {short}`--{}`",
        arg.get_long().unwrap_or_default()
    ))
}

/// Triangle's switches (`pq30a0.01`: p, q with an optional minimum angle, a with an
/// optional area bound, and the other letters Triangle knows) as `smartmesh mesh`'s
/// options, or `None` when `word` does not read as Triangle switches with a `p` or a `q`.
fn triangle_switches(word: &str) -> Option<String> {
    if !word.starts_with(['p', 'q']) || word.contains('=') {
        return None;
    }
    let mut out = String::new();
    let mut chars = word.chars().peekable();
    while let Some(c) = chars.next() {
        let mut number = String::new();
        while let Some(&d) = chars.peek() {
            if !(d.is_ascii_digit() || d == '.') {
                break;
            }
            number.push(d);
            chars.next();
        }
        match (c, number.is_empty()) {
            ('p', true) => {}
            ('q', true) => out.push_str(" --min-angle 20"),
            ('q', false) => out.push_str(&format!(" --min-angle {number}")),
            ('a', false) => out.push_str(&format!(" --max-area {number}")),
            ('c', true) => out.push_str(" --keep-convex-hull"),
            ('A' | 'z' | 'e' | 'n' | 'Q' | 'V' | 'j' | 'Y' | 'a', true) => {}
            _ => return None,
        }
    }
    Some(out)
}

fn has_long(a: &clap::Arg, name: &str) -> bool {
    a.get_long() == Some(name) || a.get_all_aliases().is_some_and(|v| v.contains(&name))
}

fn takes_value(cmd: &Command, matches: impl Fn(&clap::Arg) -> bool) -> bool {
    cmd.get_arguments().find(|a| matches(a)).is_some_and(|a| a.get_action().takes_values())
}

/// The subcommands (by their path, `recipe check`) that have the long option `name`.
fn subcommands_with(cmd: &Command, name: &str) -> Vec<String> {
    let mut found = Vec::new();
    for sub in cmd.get_subcommands() {
        if sub.get_arguments().any(|a| has_long(a, name)) {
            found.push(sub.get_name().to_string());
        }
        for s in subcommands_with(sub, name) {
            found.push(format!("{} {s}", sub.get_name()));
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    use super::*;

    fn check(args: &[&str]) -> Option<String> {
        let args: Vec<OsString> =
            std::iter::once("smartmesh").chain(args.iter().copied()).map(OsString::from).collect();
        single_dash_option(&crate::cli::Cli::command(), &args)
    }

    #[test]
    fn values_and_glued_short_options_pass() {
        // A value of an option, even one that looks like an MMG option.
        assert_eq!(
            check(&["adapt", "m.msh", "-r", "r.toml", "-o", "o.msh", "--adapter-arg", "-hausd"]),
            None
        );
        assert_eq!(
            check(&["adapt", "m.msh", "--adapter-arg=-hausd", "-r", "r.toml", "-o", "o.msh"]),
            None
        );
        // A short option with its value glued on, a negative number, stdin.
        assert_eq!(check(&["size", "-", "-rr.toml", "-oout.sol", "--hgrad", "-1"]), None);
        // Everything after `--`.
        assert_eq!(check(&["info", "--", "-hmin"]), None);
    }

    #[test]
    fn one_dash_option_names_are_caught() {
        let m = check(&["adapt", "m.msh", "-nosurf"]).unwrap();
        assert!(m.contains("did you mean `--nosurf`"), "{m}");
        let m = check(&["recipe", "check", "-hmin"]).unwrap();
        assert!(m.contains("`smartmesh recipe check`") && m.contains("`size`"), "{m}");
    }

    #[test]
    fn other_tools_one_dash_words_name_the_option_meant() {
        // MMG's output: clap would read `-out` as `-o ut`.
        let m = check(&["remesh", "m.msh", "-out", "o.mesh"]).unwrap();
        assert!(m.contains("`-o` or `--output`"), "{m}");
        let m = check(&["remesh", "m.msh", "-sol", "m.sol", "-o", "o.mesh"]).unwrap();
        assert!(m.contains("MMG's") && m.contains("`--metric`"), "{m}");
        let m = check(&["size", "m.msh", "-sol", "f.vtu", "-o", "o.sol"]).unwrap();
        assert!(m.contains("`--solution-file`"), "{m}");
        let m = check(&["convert", "a.msh", "b.msh", "-format", "msh2"]).unwrap();
        assert!(m.contains("`--to`"), "{m}");
        // Triangle's switches, translated.
        let m = check(&["mesh", "a.poly", "-o", "a.msh", "-pq30a0.01"]).unwrap();
        assert!(m.contains("--min-angle 30 --max-area 0.01"), "{m}");
        // A short option with a glued value of letters only: not what the user meant.
        let m = check(&["convert", "a.msh", "b.msh", "-qx"]).unwrap();
        assert!(m.contains("`-qx`"), "{m}");
        let m = check(&["size", "m.msh", "-rtoml", "-o", "o.sol"]).unwrap();
        assert!(m.contains("`-r toml`"), "{m}");
        // An unknown word gets the general rule.
        let m = check(&["info", "-nosuch", "m.msh"]).unwrap();
        assert!(m.contains("unknown option `-nosuch` for `smartmesh info`"), "{m}");
        // Clusters of flags pass.
        assert_eq!(check(&["info", "-qv", "m.msh"]), None);
    }
}
