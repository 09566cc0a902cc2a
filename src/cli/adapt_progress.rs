//! The adapt command's progress and Ctrl-C: the observer that writes the result files
//! after every iteration (with a progress bar on a terminal), and the handler that asks
//! the loop to stop, or exits between writes on a second press.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;

use indicatif::ProgressBar;
use smartmesh::adapt::files::ResultFiles;
use smartmesh::adapt::{Observer, Phase};
use smartmesh::formats::TaggedMesh;
use smartmesh::History;

use super::ui;

/// Ctrl-C presses so far (the handler counts; the loop reads).
static INTERRUPTS: AtomicUsize = AtomicUsize::new(0);
/// Held while the result files are written: a second Ctrl-C exits only between writes.
pub(super) static WRITING: Mutex<()> = Mutex::new(());
/// Whether the handler is installed (once per process).
static HANDLER: AtomicBool = AtomicBool::new(false);

/// Installs the Ctrl-C (SIGINT, SIGTERM, SIGHUP) handler: the first asks the loop to stop
/// after the current phase, and stops an external program under way (a solver, mmg2d_O3,
/// gmsh: SIGTERM to its process group, SIGKILL if it lingers); the second exits with 130
/// at once, having killed such a program's group and removed its temporary directory,
/// but never during a write of the result files, so that they stay whole and agree.
pub(super) fn handle_interrupts() {
    if HANDLER.swap(true, Ordering::SeqCst) {
        return;
    }
    let installed = ctrlc::set_handler(|| {
        if INTERRUPTS.fetch_add(1, Ordering::SeqCst) == 0 {
            smartmesh::adapt::interrupt();
            if ui::level() >= ui::Level::Normal {
                ui::interrupted(
                    "adapt",
                    "stopping after the current phase (Ctrl-C again to stop now)",
                );
            }
        } else {
            let _writing = WRITING.lock();
            smartmesh::adapt::stop_all();
            ui::interrupted(
                "adapt",
                "stopped; the result files are as the last iteration left them",
            );
            std::process::exit(130);
        }
    });
    if let Err(e) = installed {
        ui::warn(&format!("Ctrl-C will not save the run: {e}"));
    }
}

/// The result files, with a progress bar on a terminal.
pub(super) struct Progress {
    pub(super) files: ResultFiles,
    /// Whether the best mesh goes to stdout at the end instead of to a file.
    pub(super) to_stdout: bool,
    pub(super) bar: Option<ProgressBar>,
    pub(super) adapter: String,
    /// Records already printed above the bar (the last record comes twice: after its
    /// iteration and when the loop stops).
    pub(super) printed: usize,
    /// The z of the input's plane: the loop computes in (x, y), the files are written in
    /// the input's plane ([`smartmesh::plane`]); `None` for a mesh in space, written as
    /// it is.
    pub(super) plane_z: Option<f64>,
}

impl Observer for Progress {
    fn phase(&mut self, iteration: usize, phase: Phase) {
        if let Some(b) = &self.bar {
            let what = if phase == Phase::Remesh {
                format!("{phase} ({})", self.adapter)
            } else {
                phase.to_string()
            };
            b.set_message(format!("iteration {iteration}: {what}"));
        }
    }

    fn interrupted(&mut self) -> bool {
        INTERRUPTS.load(Ordering::SeqCst) > 0
    }

    fn record(
        &mut self,
        history: &History,
        new_best: Option<&TaggedMesh>,
    ) -> Result<(), smartmesh::formats::Error> {
        {
            let _writing = WRITING.lock();
            let placed = new_best.zip(self.plane_z.filter(|&z| z != 0.0)).map(|(m, z)| {
                let mut m = m.clone();
                smartmesh::place(&mut m, z);
                m
            });
            let new_best = placed.as_ref().or(new_best);
            self.files.record(history, if self.to_stdout { None } else { new_best })?;
        }
        if let (Some(b), Some(last)) = (
            &self.bar,
            history.iterations.last().filter(|_| history.iterations.len() > self.printed),
        ) {
            self.printed = history.iterations.len();
            b.set_position(last.iteration as u64);
            let cells = last.space.as_ref().map_or_else(
                || format!("{} triangles", last.triangles),
                |s| format!("{} {}s", s.cells, s.cell),
            );
            b.println(format!(
                "iteration {}: {} vertices, {cells}, {:.1}% conforming, mean quality {:.3}",
                last.iteration,
                last.vertices,
                100.0 * last.conforming_share,
                last.mean_quality
            ));
        }
        Ok(())
    }
}
