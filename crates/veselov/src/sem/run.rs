//! Driving a variable-step run to a final time.

use nalgebra::SVector;

use super::stepper::{SemState, VariableStepMap};
use crate::error::Error;

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
/// (or `max_steps`). With `land_on_end`, the last step is instead a fixed-step
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
            run.states.push(SemState {
                t: t0,
                q: q0,
                p: p0,
                energy: f64::NAN,
                h: h0,
            });
            run.failure = Some(e);
            return run;
        }
    };
    run.states.push(s0);
    run.states.push(s1);
    let mut s = s1;
    for k in 1..max_steps {
        if s.t >= t_end {
            break;
        }
        match integrator.step(k, &s) {
            Ok((next, info)) => {
                run.iterations += info.iterations;
                if land_on_end && next.t > t_end {
                    match integrator.fixed_step(&s, t_end - s.t) {
                        Ok((last, _)) => {
                            run.flagged_steps.push(k);
                            run.states.push(last);
                        }
                        Err(e) => run.failure = Some(e),
                    }
                    break;
                }
                if info.fallback {
                    run.flagged_steps.push(k);
                }
                run.states.push(next);
                s = next;
            }
            Err(e) => {
                run.failure = Some(e);
                break;
            }
        }
    }
    run
}
