//! `checkpoint.json`: where a run stood (step number, counters) and the
//! words that restore its state, its integrator's carry and its observers
//! (accumulators and the lengths of the files written so far). Words are
//! stored as the hexadecimal bits of each `f64`, so that they come back
//! exactly. The file is replaced atomically (written aside, then renamed).

use std::path::Path;

use serde_json::json;
use veselov::run::{Checkpoint, Outcome, Stepper};

use super::Resumable;
use crate::error::CliError;

/// The checkpoint's file name in a run's output directory.
pub const FILE: &str = "checkpoint.json";

/// A checkpoint read back.
#[derive(Debug, Clone, PartialEq)]
pub struct Saved {
    /// Number of the state saved.
    pub step: u64,
    /// Nonlinear iterations up to it.
    pub iterations: u64,
    /// Fallback steps up to it.
    pub fallback_steps: u64,
    /// Exact Jacobians evaluated before the checkpoint, where counted.
    pub jacobians: u64,
    /// Gradient evaluations `∇V` before the checkpoint, where counted.
    pub force_evaluations: u64,
    /// Wall time spent up to it.
    pub wall_seconds: f64,
    /// State words.
    pub state: Vec<f64>,
    /// Integrator carry words.
    pub stepper: Vec<f64>,
    /// Observer words.
    pub observer: Vec<f64>,
    /// The run's scenario ([`identity`](super::identity)), absent from
    /// checkpoints written before it was recorded.
    pub scenario: Option<String>,
    /// The run's fixed time step ([`Plan::step`](super::Plan::step)), where
    /// it has one and the checkpoint records it.
    pub step_length: Option<f64>,
    /// The time of the saved state, where the checkpoint records it.
    pub time: Option<f64>,
    /// The final time of a variable-step run stopped by time
    /// ([`Plan::t_end`](super::Plan::t_end)), where recorded.
    pub t_end: Option<f64>,
}

fn hex(words: &[f64]) -> String {
    words
        .iter()
        .map(|w| format!("{:016x}", w.to_bits()))
        .collect::<Vec<_>>()
        .join(" ")
}

fn unhex(path: &Path, text: &str) -> Result<Vec<f64>, CliError> {
    text.split_whitespace()
        .map(|w| {
            u64::from_str_radix(w, 16)
                .map(f64::from_bits)
                .map_err(|e| CliError::Io {
                    path: path.to_path_buf(),
                    message: format!("bad checkpoint word `{w}`: {e}"),
                })
        })
        .collect()
}

/// Write the checkpoint of the `stepper`'s `state` and the `observer`
/// after `outcome` in `dir`, with the run's scenario identity, fixed
/// time step and (variable steps) final time (`run`), and the state's time.
pub fn write<S: Stepper + Checkpoint, O: Resumable + ?Sized>(
    dir: &Path,
    (stepper, state, observer): (&S, &S::State, &mut O),
    outcome: &Outcome,
    wall_seconds: f64,
    (scenario, step_length, t_end): (Option<&str>, Option<f64>, Option<f64>),
) -> Result<(), CliError>
where
    S::State: Checkpoint,
{
    let (mut s, mut c, mut o) = (Vec::new(), Vec::new(), Vec::new());
    state.save(&mut s);
    stepper.save(&mut c);
    observer.save(&mut o)?;
    let value = json!({
        "step": outcome.last_step,
        "iterations": outcome.iterations,
        "fallback_steps": outcome.fallback_steps,
        "jacobians": outcome.jacobians,
        "force_evaluations": outcome.force_evaluations,
        "wall_seconds": wall_seconds,
        "state": hex(&s),
        "stepper": hex(&c),
        "observer": hex(&o),
        "scenario": scenario,
        "step_length": step_length,
        "time": finite(stepper.time(state)),
        "t_end": t_end,
    });
    let tmp = dir.join(format!("{FILE}.tmp"));
    crate::output::write_json(&tmp, &value)?;
    std::fs::rename(&tmp, dir.join(FILE)).map_err(|e| CliError::Io {
        path: dir.join(FILE),
        message: e.to_string(),
    })
}

/// Checkpoints written before their cost is judged (`Cost`).
const COST_SAMPLE: u64 = 100;

/// Share of the wall time spent writing checkpoints beyond which a run is
/// warned ([`Cost`]).
const COST_WARNING: f64 = 0.5;

/// Share of the wall time the suggested checkpoint interval leaves to
/// checkpoints (`Cost`).
const COST_TARGET: f64 = 0.05;

/// What writing checkpoints costs a run, to warn when it dominates: a
/// checkpoint flushes every output file, rewrites the NPY headers and
/// writes and renames `checkpoint.json` — a few hundred microseconds, as
/// long as hundreds of steps of a small mechanical system. Once
/// `COST_SAMPLE` checkpoints are written, if they took more than half
/// of the run's time, a warning (once) gives their measured cost and the
/// interval that would keep them to `COST_TARGET` of it.
#[derive(Debug, Default)]
pub struct Cost {
    /// Checkpoints written by this invocation.
    written: u64,
    /// Time spent writing them.
    spent: std::time::Duration,
    /// Whether the warning was given.
    warned: bool,
}

impl Cost {
    /// Note a checkpoint that took `took`, written after `steps` steps of
    /// this invocation and `elapsed` of wall time since its first step (the
    /// checkpoints' included), with checkpoints due
    /// every `every` steps (0: only by the clock, `--checkpoint-seconds`),
    /// a step being called `unit`; returns the warning to give, if it is due.
    pub fn note(
        &mut self,
        took: std::time::Duration,
        (steps, unit): (u64, &str),
        elapsed: std::time::Duration,
        every: u64,
    ) -> Option<String> {
        self.written += 1;
        self.spent += took;
        let share = self.spent.as_secs_f64() / elapsed.as_secs_f64();
        if self.warned || self.written < COST_SAMPLE || share.is_nan() || share <= COST_WARNING || steps == 0 {
            return None;
        }
        self.warned = true;
        let each = self.spent.as_secs_f64() / self.written as f64;
        let per_step = (elapsed.as_secs_f64() - self.spent.as_secs_f64()).max(0.0) / steps as f64;
        // c/(c + n·s) ≤ target ⇔ n ≥ c(1 − target)/(target·s).
        let needed = each * (1.0 - COST_TARGET) / (COST_TARGET * per_step.max(1e-12));
        let interval = if every > 0 {
            format!("one every {every} {unit}")
        } else {
            "written by the clock".to_string()
        };
        Some(format!(
            "writing checkpoints has taken {:.0} % of this run's time so far ({:.2} ms each, {interval}, against \
             {:.1} µs a step): raise `output.checkpoint_every` (or --checkpoint-seconds) so that they come at \
             most once every {} {unit}, to keep them to {:.0} % of the time",
            100.0 * share,
            1e3 * each,
            1e6 * per_step,
            round_up(needed),
            100.0 * COST_TARGET,
        ))
    }
}

/// The round number (1, 2 or 5 times a power of ten) at or above `x`
/// (at least 1).
fn round_up(x: f64) -> u64 {
    if !(x.is_finite() && x > 1.0) {
        return if x.is_finite() { 1 } else { u64::MAX };
    }
    let power = 10f64.powf(x.log10().floor());
    let nice = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|&v| v >= x)
        .unwrap_or(10.0 * power);
    if nice >= u64::MAX as f64 { u64::MAX } else { nice as u64 }
}

/// `x` if finite (JSON has no NaN or infinity), else `None`.
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

impl Saved {
    /// Read `dir/checkpoint.json`; `kind` is named in errors.
    pub fn read(dir: &Path, kind: &str) -> Result<Self, CliError> {
        let path = dir.join(FILE);
        let bad = |message: String| CliError::Io {
            path: path.clone(),
            message,
        };
        let text = std::fs::read_to_string(&path).map_err(|e| {
            bad(format!(
                "{e} (--resume needs the directory of a {kind} run with a checkpoint)"
            ))
        })?;
        let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
        let int = |k: &str| v[k].as_u64().ok_or_else(|| bad(format!("missing or bad `{k}`")));
        let words = |k: &str| match v[k].as_str() {
            Some(t) => unhex(&path, t),
            None => Err(bad(format!("missing or bad `{k}`"))),
        };
        Ok(Self {
            step: int("step")?,
            iterations: int("iterations")?,
            fallback_steps: int("fallback_steps")?,
            // Absent from checkpoints written before it was counted.
            jacobians: v["jacobians"].as_u64().unwrap_or(0),
            force_evaluations: v["force_evaluations"].as_u64().unwrap_or(0),
            wall_seconds: v["wall_seconds"].as_f64().unwrap_or(0.0),
            state: words("state")?,
            stepper: words("stepper")?,
            observer: words("observer")?,
            scenario: v["scenario"].as_str().map(str::to_owned),
            step_length: v["step_length"].as_f64(),
            time: v["time"].as_f64(),
            t_end: v["t_end"].as_f64(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn dominant_checkpoints_are_warned_once_with_an_interval_that_tames_them() {
        let mut cost = Cost::default();
        let ms = Duration::from_millis;
        // 99 checkpoints of 1 ms every step of 10 µs: too few to judge yet.
        for k in 1..COST_SAMPLE {
            assert_eq!(
                cost.note(ms(1), (k, "steps"), ms(k) + Duration::from_micros(10 * k), 1),
                None
            );
        }
        let n = COST_SAMPLE;
        let warning = cost
            .note(ms(1), (n, "steps"), ms(n) + Duration::from_micros(10 * n), 1)
            .expect("a warning");
        // 1 ms against 10 µs a step: 1900 steps keep them to 5 %; rounded up.
        assert!(warning.contains("once every 2000 steps"), "{warning}");
        assert!(warning.contains("99 %"), "{warning}");
        assert_eq!(cost.note(ms(1), (n + 1, "steps"), ms(n + 1), 1), None, "warned once");
        // Cheap checkpoints are not warned.
        let mut cheap = Cost::default();
        for k in 1..=2 * COST_SAMPLE {
            assert_eq!(
                cheap.note(Duration::from_micros(10), (k * 1000, "steps"), ms(k), 1000),
                None
            );
        }
    }

    #[test]
    fn intervals_are_rounded_up_to_round_numbers() {
        assert_eq!(round_up(0.3), 1);
        assert_eq!(round_up(1900.0), 2000);
        assert_eq!(round_up(2000.0), 2000);
        assert_eq!(round_up(2001.0), 5000);
        assert_eq!(round_up(7.0), 10);
        assert_eq!(round_up(f64::INFINITY), u64::MAX);
    }
}
