//! Planar double pendulum (non-separable: the mass matrix depends on `θ₁ − θ₂`).
//!
//! `L = ½(m₁+m₂)ℓ₁²θ̇₁² + ½m₂ℓ₂²θ̇₂² + m₂ℓ₁ℓ₂θ̇₁θ̇₂cos(θ₁−θ₂) + (m₁+m₂)gℓ₁cos θ₁ + m₂gℓ₂cos θ₂`.

use nalgebra::SVector;

use super::positive;
use crate::ad::Scalar;
use crate::error::Result;
use crate::mechanics::Lagrangian;

/// Double pendulum with point masses `m₁, m₂` on rods `ℓ₁, ℓ₂`, gravity `g`; angles from the downward vertical.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DoublePendulum {
    /// Upper mass.
    pub m1: f64,
    /// Lower mass.
    pub m2: f64,
    /// Upper rod length.
    pub l1: f64,
    /// Lower rod length.
    pub l2: f64,
    /// Gravity.
    pub gravity: f64,
}

impl Default for DoublePendulum {
    fn default() -> Self {
        Self {
            m1: 1.0,
            m2: 1.0,
            l1: 1.0,
            l2: 1.0,
            gravity: 1.0,
        }
    }
}

impl DoublePendulum {
    /// Double pendulum with positive parameters.
    pub fn new(m1: f64, m2: f64, l1: f64, l2: f64, gravity: f64) -> Result<Self> {
        Ok(Self {
            m1: positive("m1", m1)?,
            m2: positive("m2", m2)?,
            l1: positive("l1", l1)?,
            l2: positive("l2", l2)?,
            gravity: positive("gravity", gravity)?,
        })
    }
}

impl Lagrangian<2> for DoublePendulum {
    fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let (m1, m2, l1, l2, g) = (self.m1, self.m2, self.l1, self.l2, self.gravity);
        let kinetic = v[0] * v[0] * (0.5 * (m1 + m2) * l1 * l1)
            + v[1] * v[1] * (0.5 * m2 * l2 * l2)
            + v[0] * v[1] * (q[0] - q[1]).cos() * (m2 * l1 * l2);
        let potential = -q[0].cos() * ((m1 + m2) * g * l1) - q[1].cos() * (m2 * g * l2);
        kinetic - potential
    }
}
