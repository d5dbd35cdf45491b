//! The 1+1 lattice marchers as [`Stepper`]s of the one run driver
//! ([`crate::run::drive`]): the state is the marcher itself (its stored
//! levels and solver caches), one step computes one time level.

use std::marker::PhantomData;

use super::energy::CellEnergy;
use super::fast::FastMarcher;
use super::generic::GenericMarcher;
use super::potential::ScalarPotential;
use crate::error::Result;
use crate::run::{Checkpoint, StepStats, Stepper, Words};

/// The fast marcher of a scalar model, with its 2π re-centring (sine-Gordon).
#[derive(Debug, Clone)]
pub struct FastLevels<P> {
    /// The marcher.
    pub marcher: FastMarcher<P>,
    /// Total re-centring shift applied so far: `stored + recentred_by` is
    /// the unwrapped field.
    pub recentred_by: f64,
    /// A re-centring due at the current level, applied before the next step
    /// (so that observers of this level see it as computed).
    pub pending_recentre: bool,
}

impl<P: ScalarPotential> FastLevels<P> {
    /// Levels held by `marcher`, never re-centred yet.
    pub fn new(marcher: FastMarcher<P>) -> Self {
        Self {
            marcher,
            recentred_by: 0.0,
            pending_recentre: false,
        }
    }

    fn apply_recentre(&mut self) {
        if self.pending_recentre {
            self.recentred_by += self.marcher.recentre_mod_2pi();
            self.pending_recentre = false;
        }
    }
}

/// Steps [`FastLevels`]: one level per step, re-centring mod 2π every
/// `recentre_every` levels (0: never). The level index is the step number.
#[derive(Debug, Clone, Copy)]
pub struct FastStepper<P> {
    recentre_every: usize,
    _potential: PhantomData<P>,
}

impl<P> FastStepper<P> {
    /// A stepper re-centring every `recentre_every` levels (0: never).
    pub fn new(recentre_every: usize) -> Self {
        Self {
            recentre_every,
            _potential: PhantomData,
        }
    }
}

/// `Some("y")` if a value of `level` is not finite.
fn level_non_finite<'a>(mut level: impl Iterator<Item = &'a f64>) -> Option<String> {
    level.any(|v| !v.is_finite()).then(|| "field level y".to_string())
}

impl<P: ScalarPotential> Stepper for FastStepper<P> {
    type State = FastLevels<P>;
    fn step(&mut self, _index: u64, s: &mut FastLevels<P>) -> Result<StepStats> {
        s.apply_recentre();
        s.marcher.step()?;
        let level = s.marcher.level();
        s.pending_recentre = self.recentre_every > 0 && level.is_multiple_of(self.recentre_every);
        Ok(StepStats {
            iterations: s.marcher.last_iterations(),
            ..StepStats::default()
        })
    }
    fn time(&self, s: &FastLevels<P>) -> f64 {
        s.marcher.time()
    }
    fn non_finite(&self, s: &FastLevels<P>) -> Option<String> {
        level_non_finite(s.marcher.current().iter())
    }
    fn finish(&mut self, s: &mut FastLevels<P>) {
        s.apply_recentre();
    }
}

/// Steps a [`GenericMarcher`] (any cell Lagrangian): one level per step.
#[derive(Debug, Clone, Copy, Default)]
pub struct DensityStepper<L, const DIM: usize>(PhantomData<L>);

impl<L, const DIM: usize> DensityStepper<L, DIM> {
    /// The stepper.
    pub fn new() -> Self {
        Self(PhantomData)
    }
}

impl<L: CellEnergy<DIM>, const DIM: usize> Stepper for DensityStepper<L, DIM> {
    type State = GenericMarcher<L, DIM>;
    fn step(&mut self, _index: u64, m: &mut GenericMarcher<L, DIM>) -> Result<StepStats> {
        m.step()?;
        Ok(StepStats {
            iterations: m.last_iterations(),
            ..StepStats::default()
        })
    }
    fn time(&self, m: &GenericMarcher<L, DIM>) -> f64 {
        m.lattice().t(m.level())
    }
    fn non_finite(&self, m: &GenericMarcher<L, DIM>) -> Option<String> {
        level_non_finite(m.current().iter().flat_map(|v| v.iter()))
    }
}

/// The marcher's levels and caches, then the re-centring carried between levels.
impl<P> Checkpoint for FastLevels<P> {
    fn save(&self, out: &mut Vec<f64>) {
        self.marcher.save(out);
        out.push(self.recentred_by);
        out.push(f64::from(u8::from(self.pending_recentre)));
    }
    fn restore(&mut self, w: &mut Words<'_>) -> Result<()> {
        self.marcher.restore(w)?;
        self.recentred_by = w.one()?;
        self.pending_recentre = w.flag()?;
        Ok(())
    }
}

/// The fast stepper carries nothing from level to level (its re-centring
/// period is construction data).
impl<P> Checkpoint for FastStepper<P> {
    fn save(&self, _: &mut Vec<f64>) {}
    fn restore(&mut self, _: &mut Words<'_>) -> Result<()> {
        Ok(())
    }
}

/// The density stepper carries nothing (the marcher is the state).
impl<L, const DIM: usize> Checkpoint for DensityStepper<L, DIM> {
    fn save(&self, _: &mut Vec<f64>) {}
    fn restore(&mut self, _: &mut Words<'_>) -> Result<()> {
        Ok(())
    }
}
