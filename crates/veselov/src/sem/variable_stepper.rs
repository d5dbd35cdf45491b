//! The variable-step SEM integrator as a [`Stepper`] of the one run driver
//! ([`crate::run::drive`]).

use super::stepper::{SemState, VariableStepMap};
use crate::error::Result;
use crate::run::{Checkpoint, StepStats, Stepper, Words, first_non_finite};

/// The variable-step SEM integrator as a stepper. With `land_on`, the step
/// that would pass that time is replaced by a fixed-step variational step
/// ending exactly there (reported as a fallback: not energy-exact).
///
/// After the landing step the run is over: [`Stepper::time`] then reports
/// `+∞`, so that any end-time condition holds whatever the rounding of
/// `t_k + (t_end − t_k)`.
pub struct SemStepper<'a, M: ?Sized, const N: usize> {
    map: &'a mut M,
    land_on: Option<f64>,
    landed: bool,
}

impl<'a, M: VariableStepMap<N> + ?Sized, const N: usize> SemStepper<'a, M, N> {
    /// Step with `map`, landing on `land_on` if given.
    pub fn new(map: &'a mut M, land_on: Option<f64>) -> Self {
        Self {
            map,
            land_on,
            landed: false,
        }
    }
}

impl<M: VariableStepMap<N> + ?Sized, const N: usize> Stepper for SemStepper<'_, M, N> {
    type State = SemState<N>;
    fn step(&mut self, index: u64, state: &mut SemState<N>) -> Result<StepStats> {
        let k = usize::try_from(index).unwrap_or(usize::MAX);
        let (next, info) = self.map.step(k, state)?;
        if let Some(t_end) = self.land_on
            && next.t > t_end
        {
            let (last, iterations) = self.map.fixed_step(state, t_end - state.t)?;
            *state = last;
            // The landing step's own iterations are not counted (as ever).
            let _ = iterations;
            return Ok(StepStats {
                max_relative_residual: 0.0,
                iterations: info.iterations,
                fallback: true,
                work: 0.0,
                jacobians: info.jacobian_refreshes + info.jacobian_updates,
                force_evaluations: 0,
            });
        }
        *state = next;
        Ok(StepStats {
            max_relative_residual: 0.0,
            iterations: info.iterations,
            fallback: info.fallback,
            work: 0.0,
            jacobians: info.jacobian_refreshes + info.jacobian_updates,
            force_evaluations: 0,
        })
    }
    fn time(&self, state: &SemState<N>) -> f64 {
        if self.landed { f64::INFINITY } else { state.t }
    }
    fn non_finite(&self, x: &SemState<N>) -> Option<String> {
        first_non_finite([
            ("t", std::slice::from_ref(&x.t)),
            ("q", x.q.as_slice()),
            ("p", x.p.as_slice()),
            ("energy", std::slice::from_ref(&x.energy)),
            ("h", std::slice::from_ref(&x.h)),
        ])
    }
}

impl<M: VariableStepMap<N> + ?Sized, const N: usize> Checkpoint for SemStepper<'_, M, N> {
    fn save(&self, out: &mut Vec<f64>) {
        self.map.save_carry(out);
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.map.restore_carry(words)
    }
}
