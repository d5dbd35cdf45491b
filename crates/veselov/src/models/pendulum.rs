//! Simple pendulum `L = ½ m ℓ² θ̇² + m g ℓ cos θ`, with its exact solution by
//! Jacobi elliptic functions.

use nalgebra::{SMatrix, SVector};

use super::positive;
use crate::ad::Scalar;
use crate::error::{Error, Result};
use crate::mechanics::{PhaseState, Potential, SeparableLagrangian};
use crate::special;

/// Pendulum of mass `m`, length `ℓ` in gravity `g`; `θ = 0` hangs down.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pendulum {
    /// Mass `m`.
    pub mass: f64,
    /// Length `ℓ`.
    pub length: f64,
    /// Gravitational acceleration `g`.
    pub gravity: f64,
}

impl Default for Pendulum {
    fn default() -> Self {
        Self {
            mass: 1.0,
            length: 1.0,
            gravity: 1.0,
        }
    }
}

impl Pendulum {
    /// Pendulum with positive parameters whose inertia m ℓ² and weight
    /// scale m g ℓ are finite, positive and normal (neither overflows nor
    /// underflows to zero or below the normal range, where 1/(m ℓ²)
    /// would overflow).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the parameter (`mass`, `length`,
    /// `gravity`) or the product (`mass·length²`, `mass·gravity·length`)
    /// at fault.
    pub fn new(mass: f64, length: f64, gravity: f64) -> Result<Self> {
        let p = Self {
            mass: positive("mass", mass)?,
            length: positive("length", length)?,
            gravity: positive("gravity", gravity)?,
        };
        // The products' checks, with the factors in the message.
        let product = |name: &str, value: f64| {
            positive(name, value).map_err(|e| match e {
                Error::InvalidParameter { name, value, reason } => Error::InvalidParameter {
                    name,
                    value,
                    reason: format!("{reason} (mass = {mass}, length = {length}, gravity = {gravity})"),
                },
                other => other,
            })
        };
        product("mass·length²", p.inertia())?;
        product("mass·gravity·length", mass * gravity * length)?;
        Ok(p)
    }
    /// Small-oscillation frequency `ω₀ = √(g/ℓ)`.
    pub fn omega0(&self) -> f64 {
        (self.gravity / self.length).sqrt()
    }
    /// Moment of inertia `m ℓ²` (the mass matrix).
    pub fn inertia(&self) -> f64 {
        self.mass * self.length * self.length
    }
    /// The Lagrangian system.
    ///
    /// # Panics
    /// If m ℓ² is not finite and positive, which [`Pendulum::new`] rules
    /// out (only a pendulum built field by field can have it).
    pub fn system(&self) -> SeparableLagrangian<Self, 1> {
        SeparableLagrangian::new(SMatrix::<f64, 1, 1>::new(self.inertia()), *self).expect("validated parameters")
    }
    /// Energy `H = p²/(2mℓ²) − m g ℓ cos θ`.
    pub fn energy(&self, x: &PhaseState<1>) -> f64 {
        x.p[0] * x.p[0] / (2.0 * self.inertia()) - self.mass * self.gravity * self.length * x.q[0].cos()
    }
    /// Exact state at time `t` from `x0` (libration or rotation), via Jacobi
    /// elliptic functions.
    pub fn exact(&self, x0: &PhaseState<1>, t: f64) -> Result<PhaseState<1>> {
        let thetadot0 = x0.p[0] / self.inertia();
        let (theta, thetadot) = special::pendulum_exact(x0.q[0], thetadot0, self.omega0(), t - x0.t).map_err(|e| {
            Error::InvalidParameter {
                name: "initial state".into(),
                value: format!("θ = {}, θ̇ = {thetadot0}", x0.q[0]),
                reason: e.to_string(),
            }
        })?;
        Ok(PhaseState::new(
            t,
            SVector::from([theta]),
            SVector::from([self.inertia() * thetadot]),
        ))
    }
}

impl Potential<1> for Pendulum {
    #[inline]
    fn potential<D: Scalar>(&self, _t: D, q: &SVector<D, 1>) -> D {
        -q[0].cos() * (self.mass * self.gravity * self.length)
    }
}
