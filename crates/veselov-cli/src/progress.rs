//! A progress bar that appears only for runs longer than about a second, and
//! only on a terminal.
//!
//! A run stopped by a step count shows `done/total` in its unit (`steps` for
//! mechanics, `levels` for lattice runs). A run stopped by a final time
//! (the variable-step integrators, whose step count is not known in advance)
//! shows the simulated time reached against the final time; its bar is in
//! thousandths of the interval, so the estimated time left is that of the
//! simulated time, not of a guessed step count.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// Steps between two updates of the bar.
const UPDATE_EVERY: u64 = 1024;

/// Positions of a time bar: thousandths of `[t_start, t_end]`.
const TIME_POSITIONS: u64 = 1000;

/// What the bar counts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Measure {
    /// Whole steps of a fixed count, named by `unit` (`steps`, `levels`).
    Count {
        /// The count at which the run ends.
        total: u64,
        /// Its unit, shown after the numbers.
        unit: &'static str,
    },
    /// Simulated time from `t_start` to `t_end`.
    Time {
        /// Time of the first state of this invocation.
        t_start: f64,
        /// Final time.
        t_end: f64,
    },
}

impl Measure {
    /// The bar's length and template.
    fn layout(self) -> (u64, String) {
        match self {
            Self::Count { total, unit } => (
                total,
                format!("{{bar:40}} {{pos}}/{{len}} {unit}, {{elapsed}} elapsed, eta {{eta}}"),
            ),
            Self::Time { t_end, .. } => (
                TIME_POSITIONS,
                format!("{{bar:40}} t = {{msg}} of {t_end}, {{elapsed}} elapsed, eta {{eta}}"),
            ),
        }
    }

    /// Position of the bar after `done` steps, at time `t`.
    pub fn position(self, done: u64, t: f64) -> u64 {
        match self {
            Self::Count { .. } => done,
            Self::Time { t_start, t_end } => {
                let fraction = (t - t_start) / (t_end - t_start);
                if fraction.is_finite() {
                    (fraction.clamp(0.0, 1.0) * TIME_POSITIONS as f64).round() as u64
                } else {
                    0
                }
            }
        }
    }
}

/// Lazily shown progress bar.
pub struct Progress {
    measure: Measure,
    quiet: bool,
    start: Instant,
    bar: Option<ProgressBar>,
    last_check: u64,
}

impl Progress {
    /// Progress in `measure`; nothing is drawn with `quiet`.
    pub fn new(measure: Measure, quiet: bool) -> Self {
        Self {
            measure,
            quiet,
            start: Instant::now(),
            bar: None,
            last_check: 0,
        }
    }

    /// Measure the rest of the run in `measure` (for example once its start
    /// time is known).
    pub fn measure_in(&mut self, measure: Measure) {
        self.measure = measure;
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }

    /// Report `done` steps, the last of which reached time `t`.
    pub fn set(&mut self, done: u64, t: f64) {
        if self.quiet || done < self.last_check + UPDATE_EVERY {
            return;
        }
        self.last_check = done;
        let position = self.measure.position(done, t);
        match &self.bar {
            Some(bar) => {
                bar.set_position(position);
                if matches!(self.measure, Measure::Time { .. }) {
                    bar.set_message(format!("{t:.6}"));
                }
            }
            None if self.start.elapsed() > Duration::from_secs(1) => {
                let (len, template) = self.measure.layout();
                let bar = ProgressBar::new(len);
                let style = ProgressStyle::with_template(&template).unwrap_or_else(|_| ProgressStyle::default_bar());
                bar.set_style(style);
                bar.set_position(position);
                bar.set_message(format!("{t:.6}"));
                self.bar = Some(bar);
            }
            None => {}
        }
    }

    /// Print `warning: <message>` on standard error, above the bar if it
    /// is shown (even with `quiet`: a warning is not progress).
    pub fn warn(&self, message: &str) {
        match &self.bar {
            Some(bar) => bar.suspend(|| eprintln!("warning: {message}")),
            None => eprintln!("warning: {message}"),
        }
    }

    /// Remove the bar.
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_count_bar_is_at_the_step_count() {
        let m = Measure::Count {
            total: 500,
            unit: "levels",
        };
        assert_eq!(m.position(123, f64::NAN), 123);
        assert!(m.layout().1.contains("levels"));
    }

    #[test]
    fn a_time_bar_is_at_the_fraction_of_the_interval() {
        let m = Measure::Time {
            t_start: 10.0,
            t_end: 20.0,
        };
        assert_eq!(m.position(7, 10.0), 0);
        assert_eq!(m.position(7, 12.5), 250);
        assert_eq!(m.position(7, 20.0 + 1e-3), TIME_POSITIONS);
        assert_eq!(m.position(7, f64::NAN), 0);
        let degenerate = Measure::Time {
            t_start: 1.0,
            t_end: 1.0,
        };
        assert_eq!(degenerate.position(3, 1.0), 0);
        assert!(m.layout().1.contains("of 20"));
    }
}
