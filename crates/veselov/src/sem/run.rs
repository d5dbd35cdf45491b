//! Driving a variable-step run to a final time.

use nalgebra::SVector;

use super::stepper::{SemState, VariableStepMap};
use crate::error::Error;
use crate::run::{Control, StepStats, StopWhen, drive};
use crate::sem::SemStepper;

/// A variable-step trajectory; a failure keeps what was computed.
#[derive(Debug, Clone, PartialEq)]
pub struct SemRun<const N: usize> {
    /// States `x₀, x₁, …` (the first carries `E⁻₀`, the others the conserved `E`).
    pub states: Vec<SemState<N>>,
    /// Indices of steps that were fixed-step fallbacks or the final landing step (not energy-exact).
    pub flagged_steps: Vec<usize>,
    /// Total solver iterations.
    pub iterations: usize,
    /// Why the run stopped early.
    pub failure: Option<Error>,
}

/// Run from `(t₀, q₀, p₀)` with first step `h₀` until the first `t_k ≥ t_end`
/// (or `max_steps`), on [`crate::run::drive`]. With `land_on_end`, the last step is instead a fixed-step
/// variational step ending exactly at `t_end`, flagged as not energy-exact.
#[allow(clippy::too_many_arguments)]
pub fn run_sem<const N: usize, M: VariableStepMap<N> + ?Sized>(
    integrator: &mut M,
    t0: f64,
    q0: SVector<f64, N>,
    p0: SVector<f64, N>,
    h0: f64,
    t_end: f64,
    max_steps: usize,
    land_on_end: bool,
) -> SemRun<N> {
    let mut run = SemRun {
        states: Vec::new(),
        flagged_steps: Vec::new(),
        iterations: 0,
        failure: None,
    };
    let (s0, s1) = match integrator.start(t0, q0, p0, h0) {
        Ok(x) => x,
        Err(e) => {
            run.states.push(SemState::first(t0, q0, p0, h0));
            run.failure = Some(e);
            return run;
        }
    };
    run.states.push(s0);
    run.states.push(s1);
    let mut store = |k: u64, x: &SemState<N>, stats: &StepStats| {
        if stats.fallback {
            run.flagged_steps.push(k as usize - 1);
        }
        run.states.push(*x);
        Control::Continue
    };
    let stop = StopWhen {
        steps: Some(max_steps as u64),
        t_end: Some(t_end),
        interrupt: None,
    };
    let mut s = s1;
    let outcome = drive(
        &mut SemStepper::new(integrator, land_on_end.then_some(t_end)),
        &mut s,
        1,
        &stop,
        &mut [&mut store],
    );
    run.iterations = outcome.iterations as usize;
    run.failure = outcome.failure().cloned();
    run
}
