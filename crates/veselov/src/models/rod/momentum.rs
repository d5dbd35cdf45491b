//! The rod's discrete linear and angular momentum at a level (note 003
//! §3.7): the Noether level momenta of the left SE(3) action
//! (r, R) ↦ (Qr + c, QR), with generators (left-trivialised)
//! translation c: D(r, R) = (c, 0), rotation ξ: D(r, R) = (ξ × r, Rᵀξ).
//! Exactly conserved by the march of a free rod with P = 0 (up to the
//! vertex solves' round-off).

use nalgebra::{SVector, Vector3};

use crate::field::cauchy::CauchyMarcher;
use crate::field::cell::DiscreteLagrangian;
use crate::field::fibre::{Pose, PositionRotation};

/// Linear momentum at the cut below the marcher's current level
/// ([`CauchyMarcher::level_momentum`] of the translations; it approximates
/// ∫ρ∂_t r ds).
pub fn linear_momentum<L: DiscreteLagrangian<PositionRotation, 6>>(
    m: &CauchyMarcher<PositionRotation, L, 6>,
) -> Vector3<f64> {
    Vector3::from_fn(|k, _| {
        m.level_momentum(|_: &Pose<f64>| {
            let mut d = SVector::<f64, 6>::zeros();
            d[k] = 1.0;
            d
        })
    })
}

/// Angular momentum about the origin at the cut below the current level
/// (approximates ∫(r × ρ∂_t r + RJω) ds).
pub fn angular_momentum<L: DiscreteLagrangian<PositionRotation, 6>>(
    m: &CauchyMarcher<PositionRotation, L, 6>,
) -> Vector3<f64> {
    Vector3::from_fn(|k, _| {
        m.level_momentum(|y: &Pose<f64>| {
            let xi = Vector3::ith(k, 1.0);
            let a = xi.cross(&y.position);
            let b = y.rotation.matrix().transpose() * xi;
            SVector::<f64, 6>::new(a[0], a[1], a[2], b[0], b[1], b[2])
        })
    })
}
