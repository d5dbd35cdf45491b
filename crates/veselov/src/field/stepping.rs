//! The CFK lattice marcher as a [`Stepper`] of the one run driver
//! ([`crate::run::drive`]): the state is the marcher itself (its stored
//! levels and solver caches), one step computes one weight level.

use std::marker::PhantomData;

use crate::error::Result;
use crate::field::cauchy::CauchyMarcher;
use crate::field::cell::DiscreteLagrangian;
use crate::field::fibre::Fibre;
use crate::run::{Checkpoint, StepStats, Stepper, Words};

/// Steps a [`CauchyMarcher`] on a periodic CFK lattice: one weight level per
/// step (n steps make one time step Δt of the flow Δv = v + (1,…,1)).
#[derive(Debug, Clone, Copy)]
pub struct CauchyStepper<F, L, const M: usize> {
    /// Time per weight level, Δt/n.
    pub dt_per_level: f64,
    /// The level `level()` of the marcher at time 0.
    pub level_at_zero: i64,
    _marcher: PhantomData<fn() -> (F, L)>,
}

impl<F, L, const M: usize> CauchyStepper<F, L, M> {
    /// A stepper with Δt/n = `dt_per_level` and time 0 at `level_at_zero`.
    pub fn new(dt_per_level: f64, level_at_zero: i64) -> Self {
        Self {
            dt_per_level,
            level_at_zero,
            _marcher: PhantomData,
        }
    }
}

impl<F, L, const M: usize> Stepper for CauchyStepper<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    type State = CauchyMarcher<F, L, M>;
    fn step(&mut self, _index: u64, m: &mut CauchyMarcher<F, L, M>) -> Result<StepStats> {
        let report = m.step()?;
        Ok(StepStats {
            iterations: report.iterations,
            jacobians: report.jacobians,
            max_relative_residual: report.max_relative_residual,
            ..StepStats::default()
        })
    }
    /// The time of the cut below `level()`: (level − level_at_zero)·Δt/n.
    fn time(&self, m: &CauchyMarcher<F, L, M>) -> f64 {
        (m.level() - self.level_at_zero) as f64 * self.dt_per_level
    }
    fn non_finite(&self, m: &CauchyMarcher<F, L, M>) -> Option<String> {
        let top = m.level_values(m.top_level())?;
        top.iter()
            .any(|y| !F::is_finite(y))
            .then(|| format!("field level {}", m.top_level()))
    }
}

/// The CFK stepper carries nothing (its time scale is construction data).
impl<F, L, const M: usize> Checkpoint for CauchyStepper<F, L, M> {
    fn save(&self, _: &mut Vec<f64>) {}
    fn restore(&mut self, _: &mut Words<'_>) -> Result<()> {
        Ok(())
    }
}
