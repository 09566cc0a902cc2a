//! What goes to stderr besides errors, and how much of it (`-q`, `-v`): warnings, the
//! writers' notes about what an output format could not hold, progress bars (on a
//! terminal only) and the one-line summary a command prints when it succeeds.
//!
//! Levels, as Triangle's `-Q`/`-V` and Gmsh's `-v`: quiet prints errors only; normal adds
//! warnings, notes and the summary line; verbose adds the notes about bookkeeping that no
//! user of the output misses (Gmsh's entity table, which has no place in VTK, OBJ, …;
//! the tags themselves are kept).

// Printing the run's messages on stderr is this module's job (the only one in the CLI).
#![allow(clippy::print_stderr)]

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU8, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressStyle};

/// How much to print on stderr.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Level {
    /// Errors only (`-q`).
    Quiet = 0,
    /// Warnings, notes, progress on a terminal, the summary line.
    Normal = 1,
    /// Everything (`-v`).
    Verbose = 2,
}

static LEVEL: AtomicU8 = AtomicU8::new(Level::Normal as u8);

/// Sets the level for the run (once, from the command line).
pub(crate) fn set_level(level: Level) {
    LEVEL.store(level as u8, Ordering::Relaxed);
}

/// The level of the run.
pub(crate) fn level() -> Level {
    match LEVEL.load(Ordering::Relaxed) {
        0 => Level::Quiet,
        1 => Level::Normal,
        _ => Level::Verbose,
    }
}

/// `smartmesh: warning: …`, unless quiet.
pub(crate) fn warn(message: &str) {
    if level() >= Level::Normal {
        eprintln!("smartmesh: warning: {message}");
    }
}

/// `smartmesh: note: …`, unless quiet.
pub(crate) fn note(message: &str) {
    if level() >= Level::Normal {
        eprintln!("smartmesh: note: {message}");
    }
}

/// The one line a command prints when it succeeds (`smartmesh: mesh: wrote …`), unless
/// quiet; on stderr, so that it never mixes with a mesh or JSON on stdout.
pub(crate) fn done(command: &str, message: &str) {
    if level() >= Level::Normal {
        eprintln!("smartmesh: {command}: {message}");
    }
}

/// What Ctrl-C does (`\nsmartmesh: adapt: stopping …`), on a line of its own after
/// whatever the terminal shows (the `^C`, a progress bar). Printed whatever the level:
/// the caller decides, since a second Ctrl-C must say why the run ends.
pub(crate) fn interrupted(command: &str, message: &str) {
    eprintln!("\nsmartmesh: {command}: {message}");
}

/// What a writer's report line means for the user. The formats crate lists, in one list,
/// what it left out and what it wrote differently from the input; the wording of each
/// line says which.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum WriteNote {
    /// Something of the input is not in the output.
    NotWritten,
    /// It is in the output, changed (renamed, cut, rounded) or read back differently.
    Changed,
    /// Gmsh's entity table: bookkeeping that other formats have no place for, while the
    /// tags themselves are kept (shown with `-v`).
    Bookkeeping,
}

impl WriteNote {
    /// The kind of a line of a writer's report.
    pub(crate) fn of(line: &str) -> WriteNote {
        let changed =
            ["written as", "written, but", "rounded", "cut to", "reads back", "read back"];
        if line.contains("entity table") || line.contains("Gmsh entities") {
            WriteNote::Bookkeeping
        } else if changed.iter().any(|c| line.contains(c)) {
            WriteNote::Changed
        } else {
            WriteNote::NotWritten
        }
    }
}

/// Prints a writer's report about `output`: each line as what it means.
pub(crate) fn write_notes(output: &str, lines: &[String]) {
    for line in lines {
        match WriteNote::of(line) {
            WriteNote::NotWritten => warn(&format!("{output}: not written: {line}")),
            WriteNote::Changed => note(&format!("{output}: written with a change: {line}")),
            WriteNote::Bookkeeping if level() >= Level::Verbose => {
                note(&format!("{output}: not written (the tags are kept): {line}"))
            }
            WriteNote::Bookkeeping => {}
        }
    }
}

/// A progress bar of `len` steps on a terminal (and not quiet), ticking every 100 ms so
/// that the elapsed time moves during a long step; `None` otherwise.
pub(crate) fn progress_bar(len: u64, template: &str) -> Option<ProgressBar> {
    if level() < Level::Normal || !std::io::stderr().is_terminal() {
        return None;
    }
    let b = ProgressBar::new(len);
    b.set_style(
        ProgressStyle::with_template(template).unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    b.enable_steady_tick(Duration::from_millis(100));
    Some(b)
}

/// A number with 4 significant digits (`0.001234`, `1.235e+300`): what a summary line
/// or a text report needs, never 300 digits.
pub(crate) fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if (1e-4..1e6).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.3e}")
    }
}

/// Seconds as the summary lines print them.
pub(crate) fn seconds(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s < 10.0 {
        format!("{s:.2} s")
    } else {
        format!("{s:.1} s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_four_significant_digits() {
        assert_eq!(sig(0.0012346), "0.001235");
        assert_eq!(sig(2.0), "2");
        assert_eq!(sig(123456.0), "123456");
        assert_eq!(sig(1e300), "1.000e300");
        assert_eq!(sig(-0.5), "-0.5");
    }

    #[test]
    fn report_lines_are_told_apart_by_what_they_mean() {
        assert_eq!(
            WriteNote::of("entity table (12 entities): VTU has no place for it"),
            WriteNote::Bookkeeping
        );
        assert_eq!(WriteNote::of("3 Gmsh entities: Medit has none"), WriteNote::Bookkeeping);
        assert_eq!(
            WriteNote::of("tag name `a b` (dimension 1, tag 3) written as `a_b`: OBJ group names are one line"),
            WriteNote::Changed
        );
        assert_eq!(
            WriteNote::of("coordinates rounded to 32-bit floats (glTF POSITION is FLOAT); largest change 1e-8"),
            WriteNote::Changed
        );
        assert_eq!(
            WriteNote::of("point set `Corners` (4 points): Triangle has no point sets"),
            WriteNote::NotWritten
        );
    }
}
