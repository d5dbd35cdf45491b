//! An independent reference solution for ℓ = ½ξᵀ𝕀ξ − V(g): classical RK4 on
//! the continuous Euler–Poincaré equations in matrix entries,
//!
//! ```text
//! Ṙ = R ω̂,  ẋ = R v,  μ̇ = ad_ξᵀ μ − ∇V(g),  ξ = (ω; v) = 𝕀⁻¹μ,
//! ```
//!
//! sharing nothing with the variational integrators but ∇V. Intermediate R
//! leave the group by O(h⁵) per step; the result is projected back once.

use nalgebra::{Matrix3, SVector, Vector3};

use super::discrete::left_gradient;
use super::split::inertia_inverse;
use super::{GroupState, SplitReducedLagrangian};
use crate::error::{Result, check_step};
use crate::lie::{GroupFamily, Retraction, so3};

/// Integrate from `x0` to `t_end` with `steps` RK4 steps.
pub fn rk4_group_reference<G, R, L, const N: usize>(
    l: &L,
    x0: &GroupState<G, N>,
    t_end: f64,
    steps: usize,
) -> Result<GroupState<G, N>>
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: SplitReducedLagrangian<G, N>,
{
    x0.check()?;
    let h = (t_end - x0.t) / steps as f64;
    check_step(h)?;
    let inertia_inv = inertia_inverse(&l.inertia())?;
    type Y<const N: usize> = (Matrix3<f64>, Vector3<f64>, SVector<f64, N>);
    let rate = |(r, x, mu): &Y<N>| -> Y<N> {
        let xi = inertia_inv * mu;
        let (w, v) = G::split_velocity(&xi);
        let g = G::from_parts(*r, *x);
        let grad = left_gradient::<G, f64, N>(&g, |gd| l.potential(gd)).1;
        (r * so3::hat(&w), r * v, G::ad(&xi).transpose() * mu - grad)
    };
    let axpy = |y: &Y<N>, k: &Y<N>, a: f64| -> Y<N> { (y.0 + k.0 * a, y.1 + k.1 * a, y.2 + k.2 * a) };
    let mut y: Y<N> = (G::rotation(&x0.g), G::translation(&x0.g), x0.mu);
    for _ in 0..steps {
        let k1 = rate(&y);
        let k2 = rate(&axpy(&y, &k1, 0.5 * h));
        let k3 = rate(&axpy(&y, &k2, 0.5 * h));
        let k4 = rate(&axpy(&y, &k3, h));
        y = (
            y.0 + (k1.0 + (k2.0 + k3.0) * 2.0 + k4.0) * (h / 6.0),
            y.1 + (k1.1 + (k2.1 + k3.1) * 2.0 + k4.1) * (h / 6.0),
            y.2 + (k1.2 + (k2.2 + k3.2) * 2.0 + k4.2) * (h / 6.0),
        );
    }
    let mut g = G::from_parts(y.0, y.1);
    for _ in 0..3 {
        g = G::reorthogonalize(&g);
    }
    Ok(GroupState::new(t_end, g, y.2))
}
