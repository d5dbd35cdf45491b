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
