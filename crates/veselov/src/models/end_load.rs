//! A force and a torque at one end of a rod or a beam, in the spatial
//! frame, switched on at a time and ramped linearly from zero: one load for
//! both models.

use nalgebra::{Matrix3, Vector3};

use crate::error::{Result, invalid};

/// A dead end load: force F and torque τ (spatial frame) applied from
/// `start` on, grown linearly from zero over `ramp`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EndLoad {
    /// Force F (spatial frame).
    pub force: Vector3<f64>,
    /// Torque τ (spatial frame).
    pub torque: Vector3<f64>,
    /// Ramp duration (0: the full load from `start` on).
    pub ramp: f64,
    /// Time at which the load is switched on (zero before).
    pub start: f64,
}

impl Default for EndLoad {
    fn default() -> Self {
        Self {
            force: Vector3::zeros(),
            torque: Vector3::zeros(),
            ramp: 0.0,
            start: 0.0,
        }
    }
}

impl EndLoad {
    /// Checks the load.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] naming `end_force`, `end_torque`
    /// (not finite), `ramp` (negative or not finite) or `start` (not finite).
    pub fn validate(&self) -> Result<()> {
        if !(self.ramp.is_finite() && self.ramp >= 0.0) {
            return Err(invalid("ramp", self.ramp, "must be finite and non-negative"));
        }
        if !self.start.is_finite() {
            return Err(invalid("start", self.start, "must be finite"));
        }
        for (name, v) in [("end_force", self.force), ("end_torque", self.torque)] {
            if !v.iter().all(|x| x.is_finite()) {
                return Err(invalid(name, format!("{v}"), "must be finite"));
            }
        }
        Ok(())
    }

    /// Whether the load is zero.
    pub fn is_zero(&self) -> bool {
        self.force == Vector3::zeros() && self.torque == Vector3::zeros()
    }

    /// The fraction of the load applied at time t.
    pub fn factor(&self, t: f64) -> f64 {
        ramp_factor(t, self.start, self.ramp)
    }

    /// The load at time t on a section whose frame Λ maps body to spatial
    /// vectors, in its body frame (ΛᵀF, Λᵀτ): the generalised force of the
    /// charts g·exp(ε) of rigid motions, whose centreline moves by Λv and
    /// whose frame turns by Λω to first order.
    pub fn body<D: crate::ad::Scalar>(&self, frame: &Matrix3<D>, t: f64) -> (Vector3<D>, Vector3<D>) {
        let f = self.factor(t);
        let pull =
            |v: &Vector3<f64>| Vector3::from_fn(|i, _| (0..3).fold(D::zero(), |s, k| s + frame[(k, i)] * (v[k] * f)));
        (pull(&self.force), pull(&self.torque))
    }
}

/// clamp((t − start)/ramp, 0, 1): zero before `start`, then a linear ramp
/// over `ramp` (a step at `start` when `ramp` is 0).
pub fn ramp_factor(t: f64, start: f64, ramp: f64) -> f64 {
    if t < start {
        0.0
    } else if ramp > 0.0 {
        ((t - start) / ramp).clamp(0.0, 1.0)
    } else {
        1.0
    }
}
