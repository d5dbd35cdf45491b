//! A progress bar that appears only for runs longer than about a second, and
//! only on a terminal.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// Lazily shown progress bar.
pub struct Progress {
    total: u64,
    quiet: bool,
    start: Instant,
    bar: Option<ProgressBar>,
    last_check: u64,
}

impl Progress {
    /// Progress over `total` steps; nothing is drawn with `quiet`.
    pub fn new(total: u64, quiet: bool) -> Self {
        Self {
            total,
            quiet,
            start: Instant::now(),
            bar: None,
            last_check: 0,
        }
    }

    /// Report `done` steps.
    pub fn set(&mut self, done: u64) {
        if self.quiet || done < self.last_check + 1024 {
            return;
        }
        self.last_check = done;
        match &self.bar {
            Some(bar) => bar.set_position(done),
            None if self.start.elapsed() > Duration::from_secs(1) => {
                let bar = ProgressBar::new(self.total);
                let style = ProgressStyle::with_template("{bar:40} {pos}/{len} steps, {elapsed} elapsed, eta {eta}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar());
                bar.set_style(style);
                bar.set_position(done);
                self.bar = Some(bar);
            }
            None => {}
        }
    }

    /// Remove the bar.
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}
