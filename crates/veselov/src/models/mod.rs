//! The problem zoo: one file per physical model, with exact solutions and
//! invariants where known. Models know nothing about integrators or solvers.
//!
//! The geometrically exact beam ([`beam`]) and the Cosserat rod ([`rod`])
//! are here, as models of the field core ([`crate::evolution`] and
//! [`crate::field`]): each holds everything that is the beam or the rod.
//!
//! The field models (sine-Gordon, wave, φ⁴, complex Klein–Gordon) are not
//! here: each is just a potential N(φ) of the nonlinear-wave density and
//! implements the traits the fast 1+1 kernels need, so they live with those
//! traits in [`crate::spacetime::potential`] (re-exported as
//! `veselov::spacetime::{SineGordon, …}`).

pub mod beam;
pub mod damped_kepler;
pub mod damped_oscillator;
pub mod double_pendulum;
pub mod elastic;
pub mod end_load;
pub mod harmonic;
pub mod henon_heiles;
pub mod kepler;
pub mod pendulum;
pub mod rigid_body;
pub mod rod;
pub mod van_der_pol;

pub use damped_kepler::LinearDrag;
pub use damped_oscillator::DampedOscillator;
pub use double_pendulum::DoublePendulum;
pub use end_load::EndLoad;
pub use harmonic::HarmonicOscillator;
pub use henon_heiles::HenonHeiles;
pub use kepler::Kepler;
pub use pendulum::Pendulum;
pub use rigid_body::{FreeRigidBody, FreeRigidBodySE3, HeavyTop};
pub use van_der_pol::VanDerPol;

use crate::error::{Error, Result};

/// Check that a model parameter is finite, strictly positive and normal.
pub(crate) fn positive(name: &str, value: f64) -> Result<f64> {
    // Subnormal values are refused too: their reciprocals overflow.
    if value.is_normal() && value > 0.0 {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            name: name.to_string(),
            value: value.to_string(),
            reason: "must be finite and > 0 (and not subnormal)".to_string(),
        })
    }
}
