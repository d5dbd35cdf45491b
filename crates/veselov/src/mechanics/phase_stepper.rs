//! The fixed-step maps of phase space (compile-time and run-time
//! dimension) as [`Stepper`]s of the one run driver ([`crate::run::drive`]),
//! and [`integrate`], the driver with an observer that keeps the states.

use super::dynamic::{DynGalerkinIntegrator, DynLagrangian, DynState};
use super::state::{OneStepMap, PhaseState, Trajectory};
use crate::error::Result;
use crate::run::{Checkpoint, Control, StepStats, Stepper, StopWhen, Words, drive, first_non_finite};

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

/// Take `steps` steps from `initial`, keeping every `every`-th state (and the
/// last one). A failing step ends the run; the trajectory keeps what was computed.
pub fn integrate<const N: usize, M: OneStepMap<N> + ?Sized>(
    map: &mut M,
    initial: PhaseState<N>,
    steps: usize,
    every: usize,
) -> Trajectory<N> {
    integrate_observed(map, initial, steps, every, |_, _| {})
}

/// As [`integrate`], calling `observer(k, state)` after every step `k` (1-based count of steps done).
///
/// A thin wrapper over [`crate::run::drive`] with an observer that stores the
/// states; a state that stops being finite ends the run with
/// [`Error::NonFiniteState`](crate::Error::NonFiniteState) and is not stored.
pub fn integrate_observed<const N: usize, M: OneStepMap<N> + ?Sized>(
    map: &mut M,
    initial: PhaseState<N>,
    steps: usize,
    every: usize,
    mut observer: impl FnMut(usize, &PhaseState<N>),
) -> Trajectory<N> {
    let every = every.max(1);
    let mut traj = Trajectory {
        states: Vec::with_capacity((steps / every).saturating_add(2).min(1 << 20)),
        work: Vec::with_capacity((steps / every).saturating_add(2).min(1 << 20)),
        total_iterations: 0,
        steps: 0,
        fallback_steps: 0,
        failure: None,
    };
    traj.states.push(initial);
    traj.work.push(0.0);
    if let Err(e) = initial.check() {
        traj.failure = Some(e);
        return traj;
    }
    let (mut last, mut work) = (initial, 0.0);
    let mut store = |k: u64, x: &PhaseState<N>, stats: &StepStats| {
        let k = k as usize;
        work += stats.work;
        last = *x;
        if k.is_multiple_of(every) || k == steps {
            traj.states.push(*x);
            traj.work.push(work);
        }
        observer(k, x);
        Control::Continue
    };
    let mut x = initial;
    let outcome = drive(
        &mut PhaseStepper::new(map, initial.t),
        &mut x,
        0,
        &StopWhen::steps(steps as u64),
        &mut [&mut store],
    );
    traj.steps = outcome.steps as usize;
    traj.total_iterations = outcome.iterations as usize;
    traj.fallback_steps = outcome.fallback_steps as usize;
    if let Some(e) = outcome.failure() {
        if traj.states.last() != Some(&last) {
            traj.states.push(last);
            traj.work.push(work);
        }
        traj.failure = Some(e.clone());
    }
    traj
}
