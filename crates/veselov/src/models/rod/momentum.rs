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
use crate::models::rod::{CosseratCell, RodPotential};

/// Linear momentum at the cut below the marcher's current level
/// ([`CauchyMarcher::level_momentum`] of the translations; it approximates
/// ∫ρ∂_t r ds).
pub fn linear_momentum<L: DiscreteLagrangian<PositionRotation, 6>>(
    m: &CauchyMarcher<PositionRotation, L, 6>,
) -> Vector3<f64> {
    let p = m.level_momenta(|y: &Pose<f64>| {
        let g = generators(y);
        [g[0], g[1], g[2]]
    });
    Vector3::from(p)
}

/// Angular momentum about the origin at the cut below the current level
/// (approximates ∫(r × ρ∂_t r + RJω) ds).
pub fn angular_momentum<L: DiscreteLagrangian<PositionRotation, 6>>(
    m: &CauchyMarcher<PositionRotation, L, 6>,
) -> Vector3<f64> {
    let l = m.level_momenta(|y: &Pose<f64>| {
        let g = generators(y);
        [g[3], g[4], g[5]]
    });
    Vector3::from(l)
}

/// [`linear_momentum`] and [`angular_momentum`] in one sweep over the level
/// (the same bits).
pub fn momenta<L: DiscreteLagrangian<PositionRotation, 6>>(
    m: &CauchyMarcher<PositionRotation, L, 6>,
) -> (Vector3<f64>, Vector3<f64>) {
    let q = m.level_momenta(generators);
    (Vector3::new(q[0], q[1], q[2]), Vector3::new(q[3], q[4], q[5]))
}

/// The generators of the translations (k = 0, 1, 2) and rotations (k = 3,
/// 4, 5) about the origin, left-trivialised: (e_k, 0) and (ξ × r, Rᵀξ),
/// Rᵀe_k being row k of R; all six at once, since each pairing with a
/// vertex's term needs them all.
fn generators(y: &Pose<f64>) -> [SVector<f64, 6>; 6] {
    let m = y.rotation.matrix();
    let translation = |k: usize| {
        let mut d = SVector::<f64, 6>::zeros();
        d[k] = 1.0;
        d
    };
    let rotation = |k: usize| {
        let a = Vector3::ith(k, 1.0).cross(&y.position);
        SVector::<f64, 6>::from([a[0], a[1], a[2], m[(k, 0)], m[(k, 1)], m[(k, 2)]])
    };
    [
        translation(0),
        translation(1),
        translation(2),
        rotation(0),
        rotation(1),
        rotation(2),
    ]
}

/// The discrete impulse of the loads (damping, end force and torque) on the
/// last solved level, as force and torque about the origin
/// ([`CauchyMarcher::level_impulse`]): with free ends and no potential,
/// [`linear_momentum`] and [`angular_momentum`] change across a step by
/// exactly these (the discrete Lagrange–d'Alembert momentum balance).
/// `None` before the marcher's first step since it was built or restored
/// ([`CauchyMarcher::level_impulses`]).
pub fn load_impulse<L: DiscreteLagrangian<PositionRotation, 6>>(
    m: &CauchyMarcher<PositionRotation, L, 6>,
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let i = m.level_impulses(generators)?;
    Some((Vector3::new(i[0], i[1], i[2]), Vector3::new(i[3], i[4], i[5])))
}

/// The rod's energy at the cut: Σ over the cells of the slab below the
/// current level of [`CosseratCell::cell_energy`], divided by Δt
/// (kinetic + elastic + potential; bounded, not exactly conserved). The
/// field may have been marched with another cell Lagrangian of the same
/// rod (Q_sym, say): the energy is then Prop. 6.5's functional of that
/// field.
///
/// # Errors
/// [`crate::Error::NonFinite`] if a cell of the slab is unsuitable.
pub fn energy<L: DiscreteLagrangian<PositionRotation, 6>, P: RodPotential>(
    m: &CauchyMarcher<PositionRotation, L, 6>,
    lag: &CosseratCell<P>,
) -> crate::Result<f64> {
    let mut sum = 0.0;
    let mut bad = None;
    m.for_each_straddling_cell(|cell, y| match lag.cell_energy(cell, y) {
        Ok(e) => sum += e,
        Err(_) => bad = Some(cell.index),
    });
    if let Some(index) = bad {
        return Err(crate::Error::NonFinite {
            what: "rod cell energy".into(),
            index,
            value: f64::NAN,
        });
    }
    Ok(sum / lag.dt())
}
