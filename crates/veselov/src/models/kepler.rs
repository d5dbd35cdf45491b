//! Kepler problem `L = ½|v|² + 1/|q|` in the plane, with its exact solution
//! via Kepler's equation and the angular-momentum symmetry.

use nalgebra::{SVector, Vector2};

use crate::ad::Scalar;
use crate::error::{Error, Result};
use crate::mechanics::{AffineSymmetry, PhaseState, Potential, SeparableLagrangian};
use crate::special;

/// Kepler problem with gravitational parameter 1; orbits are labelled by
/// eccentricity `e ∈ [0, 1)` with semi-major axis 1 and period 2π.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kepler {
    /// Eccentricity of the reference orbit started by [`Kepler::initial_state`].
    pub eccentricity: f64,
}

impl Kepler {
    /// Kepler problem whose reference orbit has eccentricity `e ∈ [0, 1)`.
    pub fn new(eccentricity: f64) -> Result<Self> {
        if !(eccentricity.is_finite() && (0.0..1.0).contains(&eccentricity)) {
            return Err(Error::InvalidParameter {
                name: "eccentricity".into(),
                value: eccentricity.to_string(),
                reason: "must lie in [0, 1)".into(),
            });
        }
        Ok(Self { eccentricity })
    }
    /// The Lagrangian system (unit mass).
    pub fn system(&self) -> SeparableLagrangian<Self, 2> {
        SeparableLagrangian::unit_mass(*self)
    }
    /// Pericentre state `q = (1 − e, 0)`, `p = (0, √((1+e)/(1−e)))`.
    pub fn initial_state(&self) -> PhaseState<2> {
        let e = self.eccentricity;
        PhaseState::new(
            0.0,
            Vector2::new(1.0 - e, 0.0),
            Vector2::new(0.0, ((1.0 + e) / (1.0 - e)).sqrt()),
        )
    }
    /// Exact state at time `t` of the reference orbit (started at `t = 0`).
    pub fn exact(&self, t: f64) -> Result<PhaseState<2>> {
        let (q, p) = special::kepler_exact(self.eccentricity, t).map_err(|e| Error::InvalidParameter {
            name: "t".into(),
            value: t.to_string(),
            reason: e.to_string(),
        })?;
        Ok(PhaseState::new(t, Vector2::from(q), Vector2::from(p)))
    }
    /// Energy `H = ½|p|² − 1/|q|` (−½ on the reference orbit).
    pub fn energy(&self, x: &PhaseState<2>) -> f64 {
        0.5 * x.p.norm_squared() - 1.0 / x.q.norm()
    }
    /// Rotation symmetry `ξ_Q(q) = (−q₁, q₀)`; its momentum map is the angular momentum.
    pub fn angular_symmetry() -> AffineSymmetry<2> {
        AffineSymmetry::rotation("angular", 0, 1)
    }
}

impl Potential<2> for Kepler {
    #[inline]
    fn potential<D: Scalar>(&self, _t: D, q: &SVector<D, 2>) -> D {
        -(q[0] * q[0] + q[1] * q[1]).sqrt().recip()
    }
}
