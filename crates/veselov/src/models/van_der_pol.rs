//! Two coupled van der Pol oscillators (seed 004 §7.1; Scheck 2004, eq. 6.38):
//! `L = ½|v|² − ½[q₁² + (1+ρ)q₂²] − λ(q₁ − q₂)²`, `F = ((ε − q₁²)v₁, (ε − q₂²)v₂)`.
//!
//! Energy `E = ½|p|² + ½[q₁² + (1+ρ)q₂²] + λ(q₁ − q₂)²` with `dE/dt = Σᵢ (ε − qᵢ²)vᵢ²`.

use nalgebra::{SVector, Vector2};

use crate::ad::Scalar;
use crate::error::{Error, Result};
use crate::mechanics::{Force, PhaseState, Potential, SeparableLagrangian};

/// Coupled van der Pol oscillators with parameters `(ε, ρ, λ)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VanDerPol {
    /// Anti-damping strength `ε`.
    pub epsilon: f64,
    /// Detuning `ρ` of the second oscillator.
    pub rho: f64,
    /// Coupling `λ`.
    pub lambda: f64,
}

impl Default for VanDerPol {
    /// The paper's parameters `(ε, ρ, λ) = (0.5, 0.02, 0.8)`.
    fn default() -> Self {
        Self {
            epsilon: 0.5,
            rho: 0.02,
            lambda: 0.8,
        }
    }
}

/// The van der Pol force `((ε − q₁²)v₁, (ε − q₂²)v₂)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VanDerPolForce {
    /// `ε`.
    pub epsilon: f64,
}

impl Force<2> for VanDerPolForce {
    fn force<D: Scalar>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> SVector<D, 2> {
        SVector::<D, 2>::new(
            (-q[0] * q[0] + self.epsilon) * v[0],
            (-q[1] * q[1] + self.epsilon) * v[1],
        )
    }
}

impl VanDerPol {
    /// Oscillators with finite parameters.
    pub fn new(epsilon: f64, rho: f64, lambda: f64) -> Result<Self> {
        for (name, v) in [("epsilon", epsilon), ("rho", rho), ("lambda", lambda)] {
            if !v.is_finite() {
                return Err(Error::InvalidParameter {
                    name: name.into(),
                    value: v.to_string(),
                    reason: "must be finite".into(),
                });
            }
        }
        Ok(Self { epsilon, rho, lambda })
    }
    /// The conservative part (unit mass).
    pub fn system(&self) -> SeparableLagrangian<Self, 2> {
        SeparableLagrangian::unit_mass(*self)
    }
    /// The force.
    pub fn force(&self) -> VanDerPolForce {
        VanDerPolForce { epsilon: self.epsilon }
    }
    /// The paper's initial state `q = (−1/2, −1/4)`, `v = p = (0, 4)`.
    pub fn initial_state() -> PhaseState<2> {
        PhaseState::new(0.0, Vector2::new(-0.5, -0.25), Vector2::new(0.0, 4.0))
    }
    /// Energy `E = ½|p|² + V(q)`.
    pub fn energy(&self, x: &PhaseState<2>) -> f64 {
        0.5 * x.p.norm_squared() + self.potential(0.0, &x.q)
    }
}

impl Potential<2> for VanDerPol {
    #[inline]
    fn potential<D: Scalar>(&self, _t: D, q: &SVector<D, 2>) -> D {
        let d = q[0] - q[1];
        (q[0] * q[0] + q[1] * q[1] * (1.0 + self.rho)) * 0.5 + d * d * self.lambda
    }
}
