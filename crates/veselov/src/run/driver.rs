//! The stepping trait, the observer trait and the driver loop.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::error::Error;

/// What one step reports besides the new state.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepStats {
    /// Nonlinear iterations (Newton or fixed-point) spent on the step.
    pub iterations: usize,
    /// Whether a fast path had to fall back to a general solver (or, for
    /// variable steps, the step is not energy-exact).
    pub fallback: bool,
    /// Exact Jacobians evaluated in the step, in full or in part (reported by
    /// the variable-step integrators; 0 where not counted).
    pub jacobians: usize,
    /// Evaluations of the potential's gradient `∇V` (a batch of `s` per
    /// fixed-point sweep of the separable Galerkin path); 0 where not counted.
    pub force_evaluations: usize,
    /// Largest final residual of the step's equations relative to the size
    /// of their terms, where the integrator reports it (the vertex solves
    /// of the Cauchy marcher: the discrete Euler–Lagrange residual
    /// `Leg_v(y_Δv) − μ_v` at the accepted values); 0 elsewhere.
    pub max_relative_residual: f64,
    /// Discrete work of the generalised forces over the step,
    /// `h Σᵢ bᵢ F(i)·Yᵢ` (zero for unforced systems and for other families).
    pub work: f64,
}

/// One step of an integrator: `x_{k+1} = Φ(x_k)`, in place.
///
/// On error the state must be left as it was (the last good state).
pub trait Stepper {
    /// The state advanced from step to step.
    type State;
    /// Advance `state` by step `index` (0-based: the step from `x_index` to
    /// `x_{index+1}`).
    fn step(&mut self, index: u64, state: &mut Self::State) -> crate::Result<StepStats>;
    /// The time of `state`.
    fn time(&self, state: &Self::State) -> f64;
    /// The name of the first quantity of `state` that is not finite, if any.
    fn non_finite(&self, _state: &Self::State) -> Option<String> {
        None
    }
    /// Called once when the run ends, whatever the reason (a deferred
    /// operation of the last step may complete here).
    fn finish(&mut self, _state: &mut Self::State) {}
}

/// What an observer tells the driver after seeing a state.
#[derive(Debug, Clone, PartialEq)]
pub enum Control {
    /// Go on.
    Continue,
    /// End the run now ([`Status::Stopped`]).
    Stop,
    /// End the run with this failure ([`Status::Failed`]).
    Fail(Error),
}

/// Something that watches a run: sees every new state after a successful step.
pub trait Observer<S> {
    /// `step` is the number of the state (1 for the state after the first
    /// step of a fresh run).
    fn observe(&mut self, step: u64, state: &S, stats: &StepStats) -> Control;
}

impl<S, F: FnMut(u64, &S, &StepStats) -> Control> Observer<S> for F {
    fn observe(&mut self, step: u64, state: &S, stats: &StepStats) -> Control {
        self(step, state, stats)
    }
}

/// When a run ends (the first condition that holds, checked before every step).
#[derive(Debug, Clone, Default)]
pub struct StopWhen {
    /// The step number at which to stop (`x_n` is the last state).
    pub steps: Option<u64>,
    /// Stop at the first state with `t ≥ t_end`.
    pub t_end: Option<f64>,
    /// Stop when this flag is set (for example by a signal handler).
    pub interrupt: Option<Arc<AtomicBool>>,
}

impl StopWhen {
    /// Stop after state `n`.
    pub fn steps(n: u64) -> Self {
        Self {
            steps: Some(n),
            ..Self::default()
        }
    }

    /// Stop at the first state with `t ≥ t_end`.
    pub fn time(t_end: f64) -> Self {
        Self {
            t_end: Some(t_end),
            ..Self::default()
        }
    }

    /// Also stop when `flag` is set.
    pub fn or_interrupted(mut self, flag: Arc<AtomicBool>) -> Self {
        self.interrupt = Some(flag);
        self
    }
}

/// Why a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// A stop condition on steps or time was reached.
    Completed,
    /// The interruption flag was set.
    Interrupted,
    /// An observer asked to stop.
    Stopped,
    /// A step failed, the state stopped being finite, or an observer failed the run.
    Failed(Error),
}

/// What [`drive`] reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Number of the last state reached (the first state's number plus the steps taken).
    pub last_step: u64,
    /// Steps taken by this call.
    pub steps: u64,
    /// Nonlinear iterations over those steps.
    pub iterations: u64,
    /// Steps that reported a fallback.
    pub fallback_steps: u64,
    /// Exact Jacobians evaluated over those steps (where counted).
    pub jacobians: u64,
    /// Gradient evaluations `∇V` over those steps (where counted).
    pub force_evaluations: u64,
    /// Why the run ended.
    pub status: Status,
}

impl Outcome {
    /// The failure, if the run failed.
    pub fn failure(&self) -> Option<&Error> {
        match &self.status {
            Status::Failed(e) => Some(e),
            _ => None,
        }
    }
}

/// Run `stepper` from `state` (state number `first`) until a condition of
/// `stop` holds, showing every new state to `observers` in order.
///
/// A failing step leaves `state` at the last good state; a non-finite new
/// state ends the run with [`Error::NonFiniteState`] (then `state` holds the
/// non-finite values, which no observer has seen). [`Stepper::finish`] is
/// called at the end in every case.
pub fn drive<S: Stepper + ?Sized>(
    stepper: &mut S,
    state: &mut S::State,
    first: u64,
    stop: &StopWhen,
    observers: &mut [&mut dyn Observer<S::State>],
) -> Outcome {
    let mut out = Outcome {
        last_step: first,
        steps: 0,
        iterations: 0,
        fallback_steps: 0,
        jacobians: 0,
        force_evaluations: 0,
        status: Status::Completed,
    };
    loop {
        if stop.steps.is_some_and(|n| out.last_step >= n) || stop.t_end.is_some_and(|t| stepper.time(state) >= t) {
            break;
        }
        if stop.interrupt.as_ref().is_some_and(|f| f.load(Ordering::Relaxed)) {
            out.status = Status::Interrupted;
            break;
        }
        let stats = match stepper.step(out.last_step, state) {
            Ok(stats) => stats,
            Err(e) => {
                out.status = Status::Failed(e);
                break;
            }
        };
        out.last_step += 1;
        if let Some(what) = stepper.non_finite(state) {
            out.status = Status::Failed(Error::NonFiniteState {
                step: usize::try_from(out.last_step).unwrap_or(usize::MAX),
                t: stepper.time(state),
                what,
            });
            break;
        }
        out.steps += 1;
        out.iterations += stats.iterations as u64;
        out.fallback_steps += u64::from(stats.fallback);
        out.jacobians += stats.jacobians as u64;
        out.force_evaluations += stats.force_evaluations as u64;
        let mut control = Control::Continue;
        for o in observers.iter_mut() {
            control = o.observe(out.last_step, state, &stats);
            if control != Control::Continue {
                break;
            }
        }
        match control {
            Control::Continue => {}
            Control::Stop => {
                out.status = Status::Stopped;
                break;
            }
            Control::Fail(e) => {
                out.status = Status::Failed(e);
                break;
            }
        }
    }
    stepper.finish(state);
    out
}

/// The first non-finite quantity among named slices.
pub(crate) fn first_non_finite<'a>(parts: impl IntoIterator<Item = (&'a str, &'a [f64])>) -> Option<String> {
    parts
        .into_iter()
        .find(|(_, x)| x.iter().any(|v| !v.is_finite()))
        .map(|(name, _)| name.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `x ↦ 2x`, failing at a chosen step, time = step number (1e300·2²⁸ overflows).
    struct Doubling {
        fail_at: u64,
    }

    impl Stepper for Doubling {
        type State = (u64, f64);
        fn step(&mut self, index: u64, state: &mut (u64, f64)) -> crate::Result<StepStats> {
            if index == self.fail_at {
                return Err(Error::InvalidStep { h: 0.0 });
            }
            *state = (index + 1, state.1 * 2.0);
            Ok(StepStats {
                iterations: 2,
                ..StepStats::default()
            })
        }
        fn time(&self, state: &(u64, f64)) -> f64 {
            state.0 as f64
        }
        fn non_finite(&self, state: &(u64, f64)) -> Option<String> {
            (!state.1.is_finite()).then(|| "x".to_string())
        }
    }

    #[test]
    fn stops_on_steps_time_failure_overflow_observer_and_flag() {
        let mut seen = Vec::new();
        let mut record = |k: u64, _: &(u64, f64), _: &StepStats| {
            seen.push(k);
            Control::Continue
        };
        let mut x = (0, 1.0);
        let out = drive(
            &mut Doubling { fail_at: 99 },
            &mut x,
            0,
            &StopWhen::steps(5),
            &mut [&mut record],
        );
        assert_eq!(
            (out.status, out.steps, out.iterations, x),
            (Status::Completed, 5, 10, (5, 32.0))
        );
        assert_eq!(seen, [1, 2, 3, 4, 5]);

        let mut x = (0, 1.0);
        let out = drive(&mut Doubling { fail_at: 99 }, &mut x, 0, &StopWhen::time(3.0), &mut []);
        assert_eq!((out.last_step, x.1), (3, 8.0));

        let mut x = (0, 1.0);
        let out = drive(&mut Doubling { fail_at: 2 }, &mut x, 0, &StopWhen::steps(5), &mut []);
        assert!(matches!(out.status, Status::Failed(Error::InvalidStep { .. })));
        assert_eq!((out.last_step, x.1), (2, 4.0));

        let mut x = (0, 1e300);
        let out = drive(&mut Doubling { fail_at: 99 }, &mut x, 0, &StopWhen::steps(100), &mut []);
        match out.status {
            Status::Failed(Error::NonFiniteState { step, t, what }) => {
                assert_eq!((step, t, what.as_str()), (28, 28.0, "x"));
            }
            other => panic!("expected a non-finite state, got {other:?}"),
        }

        let mut stop_at_3 =
            |k: u64, _: &(u64, f64), _: &StepStats| if k == 3 { Control::Stop } else { Control::Continue };
        let mut x = (0, 1.0);
        let out = drive(
            &mut Doubling { fail_at: 99 },
            &mut x,
            0,
            &StopWhen::steps(9),
            &mut [&mut stop_at_3],
        );
        assert_eq!((out.status, out.last_step), (Status::Stopped, 3));

        let flag = Arc::new(AtomicBool::new(false));
        let raise = flag.clone();
        let mut interrupt_at_4 = move |k: u64, _: &(u64, f64), _: &StepStats| {
            raise.store(k == 4, Ordering::Relaxed);
            Control::Continue
        };
        let mut x = (0, 1.0);
        let stop = StopWhen::steps(9).or_interrupted(flag);
        let out = drive(
            &mut Doubling { fail_at: 99 },
            &mut x,
            0,
            &stop,
            &mut [&mut interrupt_at_4],
        );
        assert_eq!((out.status, out.last_step), (Status::Interrupted, 4));
    }
}
