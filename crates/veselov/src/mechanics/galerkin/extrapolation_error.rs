//! The correction of an extrapolated starting guess by the last step's
//! extrapolation error and its trend ([`GalerkinIntegrator`](super::GalerkinIntegrator)'s
//! predictor).
//!
//! Along a smooth trajectory the error `e_k` = converged − extrapolated of
//! step k varies smoothly, so adding `e_k` to the next extrapolation leaves
//! an error about one order of `h` smaller, and adding its trend
//! `e_k − e_{k−1}` as well one order more (the separable path's force
//! predictor uses the same idea). The trend is used only while it is at
//! most half the error (a smooth sequence): where the error is round-off
//! noise its differences would add noise. Measured on Kepler e = 0.6,
//! h = 2π/1000, Gauss s = 2: the first Newton update falls from ~4e-6
//! (extrapolation alone) to ~2e-7 (with `e_k`) and 4e-13 … 1e-8 (with the
//! trend).

use nalgebra::SVector;

use crate::error::{Error, Result};
use crate::run::Words;

/// What the next extrapolation adds of the last step's error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Correction {
    /// Nothing (a new trajectory).
    None,
    /// The error `e_k`.
    Error,
    /// `e_k + (e_k − e_{k−1})`.
    ErrorAndTrend,
}

/// Marks this part of a checkpoint carry.
const CARRY_TAG: f64 = -4.0;

/// The extrapolation errors of the last steps; all storage allocated at
/// construction.
#[derive(Debug, Clone)]
pub(crate) struct ExtrapolationCorrection<const N: usize> {
    /// This step's extrapolation before correction.
    extrapolated: Vec<SVector<f64, N>>,
    /// `e_k` and `e_k − e_{k−1}`.
    error: Vec<SVector<f64, N>>,
    trend: Vec<SVector<f64, N>>,
    correction: Correction,
    /// Whether this step's guess was corrected (an extrapolation).
    active: bool,
}

impl<const N: usize> ExtrapolationCorrection<N> {
    /// Storage for guesses of `len` vectors.
    pub(crate) fn new(len: usize) -> Self {
        let zero = SVector::zeros();
        Self {
            extrapolated: vec![zero; len],
            error: vec![zero; len],
            trend: vec![zero; len],
            correction: Correction::None,
            active: false,
        }
    }

    /// A new trajectory: nothing to correct by, and this step's guess is
    /// not an extrapolation.
    pub(crate) fn reset(&mut self) {
        self.correction = Correction::None;
        self.active = false;
    }

    /// `guess` holds this step's extrapolation: remember it and add the
    /// correction.
    pub(crate) fn correct(&mut self, guess: &mut [SVector<f64, N>]) {
        self.extrapolated.copy_from_slice(guess);
        self.active = true;
        let weight = match self.correction {
            Correction::None => return,
            Correction::Error => 0.0,
            Correction::ErrorAndTrend => 1.0,
        };
        for ((z, e), d) in guess.iter_mut().zip(&self.error).zip(&self.trend) {
            *z += e + d * weight;
        }
    }

    /// Whether this step's guess is an extrapolation of the previous step.
    pub(crate) fn is_active(&self) -> bool {
        self.active
    }

    /// After a converged step from a corrected guess: its error and trend.
    pub(crate) fn remember(&mut self, converged: &[SVector<f64, N>]) {
        if !self.active {
            return;
        }
        let (mut size, mut change) = (0.0_f64, 0.0_f64);
        for (((e, d), z), x) in self
            .error
            .iter_mut()
            .zip(self.trend.iter_mut())
            .zip(converged)
            .zip(&self.extrapolated)
        {
            let error = z - x;
            *d = error - *e;
            *e = error;
            size = size.max(error.amax());
            change = change.max(d.amax());
        }
        self.correction = match self.correction {
            Correction::None => Correction::Error,
            _ if change <= 0.5 * size => Correction::ErrorAndTrend,
            _ => Correction::Error,
        };
    }

    /// Append the correction's state to a checkpoint carry, behind a tag.
    pub(crate) fn save(&self, out: &mut Vec<f64>) {
        out.push(CARRY_TAG);
        out.push(match self.correction {
            Correction::None => 0.0,
            Correction::Error => 1.0,
            Correction::ErrorAndTrend => 2.0,
        });
        for z in self.error.iter().chain(&self.trend) {
            out.extend(z.iter());
        }
    }

    /// Restore what [`save`](Self::save) wrote; a carry without the tag
    /// (an earlier version's) leaves nothing to correct by.
    pub(crate) fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.reset();
        if !words.take_tag(CARRY_TAG) {
            return Ok(());
        }
        let kind = words.one()?;
        self.correction = match kind {
            0.0 => Correction::None,
            1.0 => Correction::Error,
            2.0 => Correction::ErrorAndTrend,
            _ => {
                return Err(Error::InvalidParameter {
                    name: "checkpoint".into(),
                    value: kind.to_string(),
                    reason: "extrapolation correction must be 0, 1 or 2".into(),
                });
            }
        };
        for z in self.error.iter_mut().chain(self.trend.iter_mut()) {
            *z = SVector::from_column_slice(words.take(N)?);
        }
        Ok(())
    }
}
