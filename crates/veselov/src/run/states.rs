//! Checkpoint words of the states of the fixed- and variable-step families.

use nalgebra::SVector;

use super::checkpoint::{Checkpoint, Words};
use crate::error::Result;
use crate::lgvi::GroupState;
use crate::lie::GroupFamily;
use crate::mechanics::{DynState, PhaseState};
use crate::sem::SemState;

fn vector<const N: usize>(words: &mut Words<'_>) -> Result<SVector<f64, N>> {
    Ok(SVector::from_column_slice(words.take(N)?))
}

impl<const N: usize> Checkpoint for PhaseState<N> {
    /// `t, q, p`.
    fn save(&self, out: &mut Vec<f64>) {
        out.push(self.t);
        out.extend(self.q.iter().chain(self.p.iter()));
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.t = words.one()?;
        self.q = vector(words)?;
        self.p = vector(words)?;
        Ok(())
    }
}

impl Checkpoint for DynState {
    /// `t, q, p` (the lengths are those of the state restored into).
    fn save(&self, out: &mut Vec<f64>) {
        out.push(self.t);
        out.extend(self.q.iter().chain(self.p.iter()));
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.t = words.one()?;
        words.fill(&mut self.q)?;
        words.fill(&mut self.p)?;
        Ok(())
    }
}

impl<const N: usize> Checkpoint for SemState<N> {
    /// `t, q, p, E, h`.
    fn save(&self, out: &mut Vec<f64>) {
        out.push(self.t);
        out.extend(self.q.iter().chain(self.p.iter()));
        out.extend([self.energy, self.h]);
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.t = words.one()?;
        self.q = vector(words)?;
        self.p = vector(words)?;
        self.energy = words.one()?;
        self.h = words.one()?;
        Ok(())
    }
}

impl<G: GroupFamily<N>, const N: usize> Checkpoint for GroupState<G, N> {
    /// `t`, the rotation (column-major), the translation, `μ`.
    fn save(&self, out: &mut Vec<f64>) {
        out.push(self.t);
        out.extend(G::rotation(&self.g).iter());
        out.extend(G::translation(&self.g).iter());
        out.extend(self.mu.iter());
    }
    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        self.t = words.one()?;
        let r = nalgebra::Matrix3::from_column_slice(words.take(9)?);
        let x = vector::<3>(words)?;
        self.g = G::from_parts(r, x);
        self.mu = vector(words)?;
        Ok(())
    }
}
