//! [`Stepper`]s for the fixed-step maps of phase space and of matrix groups,
//! and for the variable-step SEM integrator.

use super::checkpoint::{Checkpoint, Words};
use super::driver::{StepStats, Stepper};
use crate::error::Result;
use crate::lgvi::{GroupState, GroupStepMap};
use crate::lie::GroupFamily;
use crate::mechanics::{DynGalerkinIntegrator, DynLagrangian, DynState, OneStepMap, PhaseState};
use crate::sem::{SemState, VariableStepMap};

/// The first non-finite quantity among named slices.
fn first_non_finite<'a>(parts: impl IntoIterator<Item = (&'a str, &'a [f64])>) -> Option<String> {
    parts
        .into_iter()
        .find(|(_, x)| x.iter().any(|v| !v.is_finite()))
        .map(|(name, _)| name.to_string())
}

/// A fixed-step map of phase space as a stepper. Times are set to
/// `t_k = t₀ + k·h`, free of the round-off of repeated addition.
pub struct PhaseStepper<'a, M: ?Sized, const N: usize> {
    map: &'a mut M,
    t0: f64,
    h: f64,
}

impl<'a, M: OneStepMap<N> + ?Sized, const N: usize> PhaseStepper<'a, M, N> {
    /// Step with `map` on a run whose state 0 is at time `t0`.
    pub fn new(map: &'a mut M, t0: f64) -> Self {
        let h = map.step_size();
        Self { map, t0, h }
    }
}

impl<M: OneStepMap<N> + ?Sized, const N: usize> Stepper for PhaseStepper<'_, M, N> {
    type State = PhaseState<N>;
    fn step(&mut self, index: u64, state: &mut PhaseState<N>) -> Result<StepStats> {
        let (mut next, stats) = self.map.step(usize::try_from(index).unwrap_or(usize::MAX), state)?;
        next.t = self.t0 + (index + 1) as f64 * self.h;
        *state = next;
        Ok(stats)
    }
    fn time(&self, state: &PhaseState<N>) -> f64 {
        state.t
    }
    fn non_finite(&self, x: &PhaseState<N>) -> Option<String> {
        first_non_finite([("q", x.q.as_slice()), ("p", x.p.as_slice())])
    }
}

impl<M: OneStepMap<N> + ?Sized, const N: usize> Checkpoint for PhaseStepper<'_, M, N> {
    fn save(&self, out: &mut Vec<f64>) {
        self.map.save_carry(out);
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.map.restore_carry(words)
    }
}

/// The run-time-dimension Galerkin integrator as a stepper
/// (`t_k = t₀ + k·h`).
pub struct DynStepper<'a, L> {
    integrator: &'a mut DynGalerkinIntegrator<L>,
    t0: f64,
}

impl<'a, L: DynLagrangian> DynStepper<'a, L> {
    /// Step with `integrator` on a run whose state 0 is at time `t0`.
    pub fn new(integrator: &'a mut DynGalerkinIntegrator<L>, t0: f64) -> Self {
        Self { integrator, t0 }
    }
}

impl<L: DynLagrangian> Stepper for DynStepper<'_, L> {
    type State = DynState;
    fn step(&mut self, index: u64, state: &mut DynState) -> Result<StepStats> {
        let before = self.integrator.jacobians();
        let iterations = self
            .integrator
            .step(usize::try_from(index).unwrap_or(usize::MAX), state)?;
        state.t = self.t0 + (index + 1) as f64 * self.integrator.step_size();
        Ok(StepStats {
            iterations,
            jacobians: usize::try_from(self.integrator.jacobians() - before).unwrap_or(usize::MAX),
            ..StepStats::default()
        })
    }
    fn time(&self, state: &DynState) -> f64 {
        state.t
    }
    fn non_finite(&self, x: &DynState) -> Option<String> {
        first_non_finite([("q", x.q.as_slice()), ("p", x.p.as_slice())])
    }
}

impl<L: DynLagrangian> Checkpoint for DynStepper<'_, L> {
    /// The integrator's carry (its kept Jacobian).
    fn save(&self, out: &mut Vec<f64>) {
        self.integrator.save_carry(out);
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.integrator.restore_carry(words)
    }
}

/// A fixed-step map of a matrix group as a stepper (`t_k = t₀ + k·h`).
pub struct GroupStepper<'a, M: ?Sized, G, const N: usize> {
    map: &'a mut M,
    t0: f64,
    h: f64,
    _group: std::marker::PhantomData<G>,
}

impl<'a, G: GroupFamily<N>, M: GroupStepMap<G, N> + ?Sized, const N: usize> GroupStepper<'a, M, G, N> {
    /// Step with `map` on a run whose state 0 is at time `t0`.
    pub fn new(map: &'a mut M, t0: f64) -> Self {
        let h = map.step_size();
        Self {
            map,
            t0,
            h,
            _group: std::marker::PhantomData,
        }
    }
}

impl<G: GroupFamily<N>, M: GroupStepMap<G, N> + ?Sized, const N: usize> Stepper for GroupStepper<'_, M, G, N> {
    type State = GroupState<G, N>;
    fn step(&mut self, index: u64, state: &mut GroupState<G, N>) -> Result<StepStats> {
        let (mut next, stats) = self.map.step(usize::try_from(index).unwrap_or(usize::MAX), state)?;
        next.t = self.t0 + (index + 1) as f64 * self.h;
        *state = next;
        Ok(stats)
    }
    fn time(&self, state: &GroupState<G, N>) -> f64 {
        state.t
    }
    fn non_finite(&self, x: &GroupState<G, N>) -> Option<String> {
        let r = G::rotation(&x.g);
        let p = G::translation(&x.g);
        first_non_finite([("g", r.as_slice()), ("g", p.as_slice()), ("mu", x.mu.as_slice())])
    }
}

impl<G: GroupFamily<N>, M: GroupStepMap<G, N> + ?Sized, const N: usize> Checkpoint for GroupStepper<'_, M, G, N> {
    fn save(&self, out: &mut Vec<f64>) {
        self.map.save_carry(out);
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.map.restore_carry(words)
    }
}

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
