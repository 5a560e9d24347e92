//! Progress on stderr with `indicatif`: work units done (realisations,
//! patterns, …), their rate, the ETA, and cells done. Hidden with `--quiet` and
//! whenever stderr is not a terminal (CI logs, pipes, files).

use std::io::IsTerminal;
use std::sync::atomic::{AtomicUsize, Ordering};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};

/// A progress bar over the work of the cells a run computes.
#[derive(Debug)]
pub struct Progress {
    bar: ProgressBar,
    unit: &'static str,
    cells_total: usize,
    cells_done: AtomicUsize,
}

impl Progress {
    /// A bar for `work` units of `unit` in `cells_total` cells of which
    /// `cells_done` are already done; drawn only when `visible` and stderr is a
    /// terminal.
    #[must_use]
    pub fn new(
        work: u64,
        unit: &'static str,
        cells_total: usize,
        cells_done: usize,
        visible: bool,
    ) -> Self {
        let target = if visible && std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(work), target);
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} {elapsed_precise} [{bar:30}] {human_pos}/{human_len} {msg} \
             ({rate}, ETA {eta})",
        ) {
            bar.set_style(
                style
                    .with_key("rate", |s: &ProgressState, w: &mut dyn std::fmt::Write| {
                        let _ = write!(w, "{:.0}/s", s.per_sec());
                    })
                    .progress_chars("=> "),
            );
        }
        let p = Progress {
            bar,
            unit,
            cells_total,
            cells_done: AtomicUsize::new(cells_done),
        };
        p.update_message();
        p
    }

    /// `true` when the bar is drawn.
    #[must_use]
    pub fn is_visible(&self) -> bool {
        !self.bar.is_hidden()
    }

    fn update_message(&self) {
        let done = self.cells_done.load(Ordering::Relaxed);
        self.bar
            .set_message(format!("{}, cells {done}/{}", self.unit, self.cells_total));
    }

    /// `n` more units done.
    pub fn advance(&self, n: u64) {
        self.bar.inc(n);
    }

    /// One more cell done.
    pub fn cell_done(&self) {
        self.cells_done.fetch_add(1, Ordering::Relaxed);
        self.update_message();
    }

    /// Removes the bar from the terminal.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
