//! External potentials P(s, r) of the Cosserat rod (they enter the density
//! (6.1) as −½P): none, a uniform field, and the rod's weight with a mass
//! per unit length that may vary along it.

use std::sync::Arc;

use nalgebra::{SVector, Vector3};
use num_dual::{DualSVec64, gradient};

use crate::ad::Scalar;
use crate::error::Result;
use crate::error::invalid;

/// The index of the material point s_k = k·`spacing` nearest to `s`, among
/// `points` of them (clamped to the ends): where a profile given per material
/// point is read.
pub(crate) fn nearest_point(s: f64, spacing: f64, points: usize) -> usize {
    let k = (s / spacing).round();
    let k = if k.is_finite() && k > 0.0 { k as usize } else { 0 };
    k.min(points.saturating_sub(1))
}

/// External potential P(s, r) of the rod (enters (6.1) as −½P).
pub trait RodPotential: Send + Sync {
    /// P(s, r).
    fn potential<D: Scalar>(&self, s: f64, r: &Vector3<D>) -> D;

    /// ∇_rP(s, r); by default exact through forward-mode AD of
    /// [`potential`](Self::potential).
    fn gradient(&self, s: f64, r: &Vector3<f64>) -> Vector3<f64> {
        gradient(|r: SVector<DualSVec64<3>, 3>| self.potential(s, &r), r).1
    }
}

/// P ≡ 0: the density is then invariant under the left SE(3) action
/// (r, R) ↦ (Qr + c, QR) (note 003 §3.1, erratum 5).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NoPotential;

impl RodPotential for NoPotential {
    fn potential<D: Scalar>(&self, _s: f64, _r: &Vector3<D>) -> D {
        D::zero()
    }
    fn gradient(&self, _s: f64, _r: &Vector3<f64>) -> Vector3<f64> {
        Vector3::zeros()
    }
}

/// A uniform field P(s, r) = g·r (e.g. gravity with g = 2ρ·gravity vector,
/// since P enters as ½P); breaks all symmetries but translations ⊥ g and
/// rotations about g.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearPotential {
    /// The gradient g.
    pub gradient: Vector3<f64>,
}

/// The rod's weight in a uniform gravity field g: P(s, r) = −2ρ(s)g·r with
/// ρ(s) the mass per unit length (P enters (6.1) as −½P), uniform or given
/// per material point s_k = kΔs/2 (as [`crate::models::rod::CosseratCell::with_profile`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Weight {
    gravity: Vector3<f64>,
    masses: Arc<[f64]>,
    half_ds: f64,
}

impl Weight {
    /// Gravity `g` on a rod of mass `mass` per unit length.
    pub fn uniform(gravity: Vector3<f64>, mass: f64) -> Self {
        Self {
            gravity,
            masses: Arc::new([mass]),
            half_ds: 1.0,
        }
    }

    /// Gravity `g` on a rod of mass `masses[k]` per unit length at
    /// s_k = kΔs/2 (the nearest point, clamped to the ends).
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] naming `masses` if empty,
    /// or `ds` unless positive and finite.
    pub fn profiled(gravity: Vector3<f64>, masses: Vec<f64>, ds: f64) -> Result<Self> {
        if masses.is_empty() {
            return Err(invalid("masses", 0, "needs the mass of at least one material point"));
        }
        if !(ds.is_finite() && ds > 0.0) {
            return Err(invalid("ds", ds, "must be positive and finite"));
        }
        Ok(Self {
            gravity,
            masses: masses.into(),
            half_ds: 0.5 * ds,
        })
    }

    fn gradient_at(&self, s: f64) -> Vector3<f64> {
        self.gravity * (-2.0 * self.masses[nearest_point(s, self.half_ds, self.masses.len())])
    }
}

impl RodPotential for Weight {
    fn potential<D: Scalar>(&self, s: f64, r: &Vector3<D>) -> D {
        r.dot(&self.gradient_at(s).map(D::from))
    }
    fn gradient(&self, s: f64, _r: &Vector3<f64>) -> Vector3<f64> {
        self.gradient_at(s)
    }
}

impl RodPotential for LinearPotential {
    fn potential<D: Scalar>(&self, _s: f64, r: &Vector3<D>) -> D {
        r.dot(&self.gradient.map(D::from))
    }
    fn gradient(&self, _s: f64, _r: &Vector3<f64>) -> Vector3<f64> {
        self.gradient
    }
}
