//! The fixed-step maps of a matrix group as a [`Stepper`] of the one run
//! driver ([`crate::run::drive`]), and [`integrate_group`], the driver with
//! an observer that keeps the states.

use super::state::{GroupState, GroupStepMap, GroupTrajectory};
use crate::error::Result;
use crate::lie::GroupFamily;
use crate::run::{Checkpoint, Control, StepStats, Stepper, StopWhen, Words, drive, first_non_finite};

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

/// Take `steps` steps from `initial`, storing every `every`-th state.
pub fn integrate_group<G: GroupFamily<N>, const N: usize, M: GroupStepMap<G, N> + ?Sized>(
    map: &mut M,
    initial: GroupState<G, N>,
    steps: usize,
    every: usize,
) -> GroupTrajectory<G, N> {
    integrate_group_observed(map, initial, steps, every, |_, _| {})
}

/// As [`integrate_group`], calling `observer(k, state)` after every step k
/// (1-based). Time is set to t₀ + k h (no accumulated rounding). A thin
/// wrapper over [`crate::run::drive`].
pub fn integrate_group_observed<G: GroupFamily<N>, const N: usize, M: GroupStepMap<G, N> + ?Sized>(
    map: &mut M,
    initial: GroupState<G, N>,
    steps: usize,
    every: usize,
    mut observer: impl FnMut(usize, &GroupState<G, N>),
) -> GroupTrajectory<G, N> {
    let every = every.max(1);
    let mut traj = GroupTrajectory {
        states: Vec::with_capacity((steps / every).saturating_add(2).min(1 << 20)),
        steps: 0,
        total_iterations: 0,
        failure: None,
    };
    traj.states.push(initial);
    if let Err(e) = initial.check() {
        traj.failure = Some(e);
        return traj;
    }
    let mut last = initial;
    let mut store = |k: u64, x: &GroupState<G, N>, _: &StepStats| {
        last = *x;
        observer(k as usize, x);
        if (k as usize).is_multiple_of(every) {
            traj.states.push(*x);
        }
        Control::Continue
    };
    let mut x = initial;
    let outcome = drive(
        &mut GroupStepper::new(map, initial.t),
        &mut x,
        0,
        &StopWhen::steps(steps as u64),
        &mut [&mut store],
    );
    traj.steps = outcome.steps as usize;
    traj.total_iterations = outcome.iterations as usize;
    traj.failure = outcome.failure().cloned();
    if traj.steps % every != 0 {
        traj.states.push(last);
    }
    traj
}
