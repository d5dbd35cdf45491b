//! The discrete Lagrangian L_d(g, ξ), its left-trivialised partial
//! derivatives, and the residual of the discrete Legendre transform, all
//! generic over the scalar so that Newton Jacobians are exact.

use nalgebra::{Const, SVector, U1};
use num_dual::DualSVec;

use super::ReducedLagrangian;
use crate::ad::Scalar;
use crate::lie::{GroupFamily, LieGroup, Retraction};

/// L_d(g_k, ξ_k) = h/2 [ℓ(g_k, ξ_k) + ℓ(g_k τ(hξ_k), ξ_k)] (trapezoidal rule
/// at constant body velocity; see the [module documentation](super)).
pub fn discrete_lagrangian<G, R, L, D, const N: usize>(l: &L, g: &G::Element<D>, xi: &SVector<D, N>, h: f64) -> D
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: ReducedLagrangian<G, N>,
    D: Scalar,
{
    let next = g.compose(&R::tau(&(xi * D::from(h))));
    (l.lagrangian(g, xi) + l.lagrangian(&next, xi)) * (0.5 * h)
}

/// Seeds e_i (i = 0..N) of the N-direction dual numbers over `D`.
fn seeds<D: Scalar, const N: usize>() -> SVector<DualSVec<D, N>, N> {
    SVector::from_fn(|i, _| DualSVec::<D, N>::from_re(D::zero()).derivative(i))
}

fn split_dual<D: Scalar, const N: usize>(x: DualSVec<D, N>) -> (D, SVector<D, N>) {
    (x.re, x.eps.unwrap_generic(Const::<N>, U1))
}

/// The left-trivialised gradient of f at g: ∇f(g)ᵢ = d/dε f(g τ(ε eᵢ)) at
/// ε = 0 (the same for every retraction, since dτ₀ = I), evaluated through
/// [`GroupFamily::seeded_perturbation`]. Returns (f(g), ∇f).
pub fn left_gradient<G, D, const N: usize>(
    g: &G::Element<D>,
    f: impl Fn(&G::Element<DualSVec<D, N>>) -> DualSVec<D, N>,
) -> (D, SVector<D, N>)
where
    G: GroupFamily<N>,
    D: Scalar,
{
    split_dual(f(&G::seeded_perturbation(g)))
}

/// The left-trivialised partial derivatives (∂_g L_d, ∂_ξ L_d) of the
/// discrete Lagrangian at (g, ξ): ⟨∂_g L_d, η⟩ = d/dε L_d(g τ(εη), ξ) and
/// ⟨∂_ξ L_d, ζ⟩ = d/dε L_d(g, ξ + εζ).
pub fn action_partials<G, R, L, D, const N: usize>(
    l: &L,
    g: &G::Element<D>,
    xi: &SVector<D, N>,
    h: f64,
) -> (SVector<D, N>, SVector<D, N>)
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: ReducedLagrangian<G, N>,
    D: Scalar,
{
    let (_, dg) = left_gradient::<G, D, N>(g, |gd| {
        discrete_lagrangian::<G, R, L, _, N>(l, gd, &xi.map(DualSVec::<D, N>::from_re), h)
    });
    let gd = G::map_scalar(g, DualSVec::<D, N>::from_re);
    let xid = xi.map(DualSVec::<D, N>::from_re) + seeds::<D, N>();
    let (_, dxi) = split_dual(discrete_lagrangian::<G, R, L, _, N>(l, &gd, &xid, h));
    (dg, dxi)
}

/// ν = (1/h) dτ⁻ᵀ_{hξ} ∂_ξ L_d(g, ξ) and the residual of the discrete
/// Legendre transform r(ξ) = ν − ∂_g L_d(g, ξ) − μ (zero at the step's ξ);
/// see the [module documentation](super). Returns (r, ν).
pub fn momentum_residual<G, R, L, D, const N: usize>(
    l: &L,
    g: &G::Element<D>,
    mu: &SVector<D, N>,
    xi: &SVector<D, N>,
    h: f64,
) -> (SVector<D, N>, SVector<D, N>)
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: ReducedLagrangian<G, N>,
    D: Scalar,
{
    let (dg, dxi) = action_partials::<G, R, L, D, N>(l, g, xi, h);
    let nu = R::dtau_inv_tr_mul(&(xi * D::from(h)), &dxi) / D::from(h);
    (nu - dg - mu, nu)
}
