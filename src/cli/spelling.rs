//! Options written with one dash, as MMG (`-hausd 0.01`), Gmsh (`-format msh2`) and
//! Triangle users write them. clap reads `-hausd` as the short flag `-h` followed by
//! others, prints the help and exits 0: the run silently does nothing. This check, made
//! before clap parses, refuses such a word (exit 2) and names the option meant.

use std::ffi::OsString;

use clap::Command;

/// The error message for the first argument that is an option name written with one dash
/// (`-hausd` where `--hausd` exists, or any `-h…` longer than `-h`, which clap would take
/// for the help), or `None`. Values of options are skipped (`--adapter-arg -hausd` passes
/// `-hausd` to the tool), and so is everything after `--`.
pub fn single_dash_option(cli: &Command, args: &[OsString]) -> Option<String> {
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
            let name = word.split('=').next().unwrap_or(word);
            let here = current.get_arguments().any(|a| has_long(a, name));
            if here {
                return Some(format!(
                    "unknown option `{arg}`: did you mean `--{name}`? (smartmesh's options take two dashes)"
                ));
            }
            if first == 'h' {
                let elsewhere = subcommands_with(&cmd, name);
                let hint = if elsewhere.is_empty() {
                    String::new()
                } else {
                    format!("; `--{name}` is an option of `{}`", elsewhere.join("`, `"))
                };
                return Some(format!(
                    "unknown option `{arg}` for `{}` (`-h` alone prints the help){hint}",
                    path.join(" ")
                ));
            }
            // A cluster of short flags, or a short option with its value glued on
            // (`-oout.msh`): clap reads those.
            continue;
        }
        if let Some(sub) = current.find_subcommand(arg) {
            path.push(sub.get_name().to_string());
            current = sub;
        }
    }
    None
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
}
