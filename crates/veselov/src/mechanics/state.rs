//! Phase-space states, per-step statistics and the one-step-map abstraction.

use nalgebra::{SMatrix, SVector};

use super::lagrangian::{Lagrangian, momentum};
use crate::error::{Error, Result, check_finite};

/// A point `(t, q, p)` of the extended phase space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseState<const N: usize> {
    /// Time.
    pub t: f64,
    /// Configuration.
    pub q: SVector<f64, N>,
    /// Momentum.
    pub p: SVector<f64, N>,
}

impl<const N: usize> PhaseState<N> {
    /// A state from position and momentum.
    pub fn new(t: f64, q: SVector<f64, N>, p: SVector<f64, N>) -> Self {
        Self { t, q, p }
    }

    /// A state from slices, checking dimension and finiteness.
    pub fn from_slices(t: f64, q: &[f64], p: &[f64]) -> Result<Self> {
        for (what, x) in [("q", q), ("p", p)] {
            if x.len() != N {
                return Err(Error::DimensionMismatch {
                    what: what.to_string(),
                    expected: N,
                    got: x.len(),
                });
            }
        }
        let state = Self::new(t, SVector::from_column_slice(q), SVector::from_column_slice(p));
        state.check()?;
        Ok(state)
    }

    /// A state from position and velocity: `p = ∂L/∂v(t, q, v)`.
    pub fn from_velocity<L: Lagrangian<N>>(l: &L, t: f64, q: SVector<f64, N>, v: SVector<f64, N>) -> Result<Self> {
        check_finite("t", [t].iter())?;
        check_finite("q", q.iter())?;
        check_finite("v", v.iter())?;
        let state = Self::new(t, q, momentum(l, t, &q, &v));
        state.check()?;
        Ok(state)
    }

    /// Error if `t`, `q` or `p` is not finite.
    pub fn check(&self) -> Result<()> {
        check_finite("t", [self.t].iter())?;
        check_finite("q", self.q.iter())?;
        check_finite("p", self.p.iter())
    }
}

/// Whether a step starting at `(t, q)` continues a step that ended at
/// `(t_end, q_end)`: the same configuration, and the same time up to the
/// rounding of `t₀ + k·h` versus repeated addition (a few ulps).
#[inline]
pub(crate) fn continues<const N: usize>(t_end: f64, q_end: &SVector<f64, N>, t: f64, q: &SVector<f64, N>) -> bool {
    q_end == q && (t_end - t).abs() <= 8.0 * f64::EPSILON * t.abs().max(1.0)
}

/// Append the end `(t, q)` of a one-step map's last step (or its absence)
/// to a checkpoint carry.
pub(crate) fn save_step_end<const N: usize>(out: &mut Vec<f64>, end: Option<(f64, SVector<f64, N>)>) {
    let record = end.map(|(t, q)| {
        let mut r = vec![t];
        r.extend(q.iter());
        r
    });
    crate::run::save_option(out, record.as_deref(), 1 + N);
}

/// Read what [`save_step_end`] wrote.
pub(crate) fn restore_step_end<const N: usize>(
    words: &mut crate::run::Words<'_>,
) -> Result<Option<(f64, SVector<f64, N>)>> {
    Ok(crate::run::restore_option(words, 1 + N)?.map(|r| (r[0], SVector::from_column_slice(&r[1..]))))
}

pub use crate::run::StepStats;

/// The Jacobian of a one-step map `(q, p) ↦ (q', p')` in `N × N` blocks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlowJacobian<const N: usize> {
    /// `∂q'/∂q`.
    pub qq: SMatrix<f64, N, N>,
    /// `∂q'/∂p`.
    pub qp: SMatrix<f64, N, N>,
    /// `∂p'/∂q`.
    pub pq: SMatrix<f64, N, N>,
    /// `∂p'/∂p`.
    pub pp: SMatrix<f64, N, N>,
}

/// A one-step map of phase space with a fixed step size.
pub trait OneStepMap<const N: usize> {
    /// The step size `h`.
    fn step_size(&self) -> f64;
    /// Advance `state` by one step; `index` (0-based) is used in error reports.
    fn step(&mut self, index: usize, state: &PhaseState<N>) -> Result<(PhaseState<N>, StepStats)>;
    /// Append what the next step depends on besides the state (predictor
    /// history, compensation terms) as checkpoint words; nothing by default.
    fn save_carry(&self, _out: &mut Vec<f64>) {}
    /// Restore what [`OneStepMap::save_carry`] wrote.
    ///
    /// # Errors
    /// If the words do not fit this map.
    fn restore_carry(&mut self, _words: &mut crate::run::Words<'_>) -> Result<()> {
        Ok(())
    }
}

/// A computed trajectory; a failure mid-way keeps everything computed before it.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory<const N: usize> {
    /// States `x₀, x_every, x_2·every, …` (and the last state reached).
    pub states: Vec<PhaseState<N>>,
    /// Cumulative discrete work of the forces at each stored state.
    pub work: Vec<f64>,
    /// Total nonlinear iterations over all steps taken.
    pub total_iterations: usize,
    /// Steps taken successfully.
    pub steps: usize,
    /// Steps on which a fast path fell back to Newton.
    pub fallback_steps: usize,
    /// Why the run stopped early, if it did.
    pub failure: Option<Error>,
}

impl<const N: usize> Trajectory<N> {
    /// The last state reached.
    pub fn last(&self) -> &PhaseState<N> {
        // Never empty: the initial state is always stored.
        &self.states[self.states.len() - 1]
    }
    /// Mean nonlinear iterations per step.
    pub fn mean_iterations(&self) -> f64 {
        if self.steps == 0 {
            0.0
        } else {
            self.total_iterations as f64 / self.steps as f64
        }
    }
    /// `Ok(self)` if the run completed, else the failure.
    pub fn into_result(self) -> Result<Self> {
        match self.failure {
            Some(e) => Err(e),
            None => Ok(self),
        }
    }
}
