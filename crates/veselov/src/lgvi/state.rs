//! States, one-step maps and the trajectory driver on a matrix group.

use nalgebra::SVector;

use crate::error::{Error, Result};
use crate::lie::GroupFamily;
use crate::mechanics::StepStats;

/// A point (t, g, μ) of T*G in left trivialisation: configuration g and body
/// momentum μ ∈ 𝔤* ≅ Rᴺ.
pub struct GroupState<G: GroupFamily<N>, const N: usize> {
    /// Time.
    pub t: f64,
    /// Configuration.
    pub g: G::Element<f64>,
    /// Body (left-trivialised) momentum.
    pub mu: SVector<f64, N>,
}

impl<G: GroupFamily<N>, const N: usize> Clone for GroupState<G, N> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<G: GroupFamily<N>, const N: usize> Copy for GroupState<G, N> {}

impl<G: GroupFamily<N>, const N: usize> std::fmt::Debug for GroupState<G, N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GroupState")
            .field("t", &self.t)
            .field("g", &self.g)
            .field("mu", &self.mu)
            .finish()
    }
}

impl<G: GroupFamily<N>, const N: usize> GroupState<G, N> {
    /// A state from its parts.
    pub fn new(t: f64, g: G::Element<f64>, mu: SVector<f64, N>) -> Self {
        Self { t, g, mu }
    }

    /// Check that every number is finite and the rotation part is a rotation
    /// to 1e-9 (`NonFinite` names `t`, `g` or `mu`).
    pub fn check(&self) -> Result<()> {
        crate::error::check_finite("t", &[self.t])?;
        let r = G::rotation(&self.g);
        crate::error::check_finite("g", r.as_slice())?;
        crate::error::check_finite("g", G::translation(&self.g).as_slice())?;
        crate::error::check_finite("mu", self.mu.as_slice())?;
        let defect = G::orthogonality_defect(&self.g);
        if defect > crate::lie::ORTHOGONALITY_TOLERANCE {
            return Err(Error::InvalidParameter {
                name: "g".into(),
                value: format!("max |RᵀR − I| = {defect:e}"),
                reason: "the rotation part must be orthogonal".into(),
            });
        }
        Ok(())
    }
}

/// A one-step map (g, μ) ↦ (g', μ') with a fixed step.
pub trait GroupStepMap<G: GroupFamily<N>, const N: usize> {
    /// The step size h.
    fn step_size(&self) -> f64;
    /// Advance one step; `index` (0-based) is used in error reports.
    fn step(&mut self, index: usize, state: &GroupState<G, N>) -> Result<(GroupState<G, N>, StepStats)>;
    /// Append what the next step depends on besides the state as checkpoint
    /// words; nothing by default.
    fn save_carry(&self, _out: &mut Vec<f64>) {}
    /// Restore what [`GroupStepMap::save_carry`] wrote.
    ///
    /// # Errors
    /// If the words do not fit this map.
    fn restore_carry(&mut self, _words: &mut crate::run::Words<'_>) -> Result<()> {
        Ok(())
    }
}

/// A computed trajectory on a group; a failure keeps what was computed.
pub struct GroupTrajectory<G: GroupFamily<N>, const N: usize> {
    /// States x₀, x_every, x_2·every, … (and the last state reached).
    pub states: Vec<GroupState<G, N>>,
    /// Steps taken.
    pub steps: usize,
    /// Total nonlinear iterations.
    pub total_iterations: usize,
    /// Why the run stopped early, if it did.
    pub failure: Option<Error>,
}

impl<G: GroupFamily<N>, const N: usize> GroupTrajectory<G, N> {
    /// The last state reached (the initial state is always stored).
    pub fn last(&self) -> &GroupState<G, N> {
        &self.states[self.states.len() - 1]
    }
}
