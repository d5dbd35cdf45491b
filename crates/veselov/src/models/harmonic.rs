//! Harmonic oscillator `L = ½ m v² − ½ m ω² q²`, with its exact solution.

use nalgebra::{SMatrix, SVector};

use super::positive;
use crate::ad::Scalar;
use crate::error::Result;
use crate::mechanics::{PhaseState, Potential, SeparableLagrangian};

/// Harmonic oscillator with mass `m` and angular frequency `ω`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HarmonicOscillator {
    /// Mass `m`.
    pub mass: f64,
    /// Angular frequency `ω`.
    pub omega: f64,
}

impl HarmonicOscillator {
    /// Oscillator with `m > 0`, `ω > 0`.
    pub fn new(mass: f64, omega: f64) -> Result<Self> {
        Ok(Self {
            mass: positive("mass", mass)?,
            omega: positive("omega", omega)?,
        })
    }
    /// The Lagrangian system.
    pub fn system(&self) -> SeparableLagrangian<Self, 1> {
        SeparableLagrangian::new(SMatrix::<f64, 1, 1>::new(self.mass), *self).expect("validated mass")
    }
    /// Exact state at time `t` from `x0`: `q = q₀ cos ωt + p₀/(mω) sin ωt`.
    pub fn exact(&self, x0: &PhaseState<1>, t: f64) -> PhaseState<1> {
        let (m, w) = (self.mass, self.omega);
        let dt = t - x0.t;
        let (s, c) = (w * dt).sin_cos();
        let (q0, p0) = (x0.q[0], x0.p[0]);
        PhaseState::new(
            t,
            SVector::from([q0 * c + p0 / (m * w) * s]),
            SVector::from([p0 * c - m * w * q0 * s]),
        )
    }
    /// Energy `H = p²/(2m) + ½ m ω² q²`.
    pub fn energy(&self, x: &PhaseState<1>) -> f64 {
        x.p[0] * x.p[0] / (2.0 * self.mass) + 0.5 * self.mass * self.omega * self.omega * x.q[0] * x.q[0]
    }
}

impl Potential<1> for HarmonicOscillator {
    #[inline]
    fn potential<D: Scalar>(&self, _t: D, q: &SVector<D, 1>) -> D {
        q[0] * q[0] * (0.5 * self.mass * self.omega * self.omega)
    }
}
