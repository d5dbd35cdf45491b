//! Diagnostics of Lie-group integrations: spatial (Noether) momentum, energy,
//! and the symplecticity defect in left-trivialised coordinates.

use nalgebra::{DMatrix, SMatrix, SVector};
use num_dual::hessian;

use super::{GroupState, ReducedLagrangian};
use crate::error::{Error, Result};
use crate::lie::{GroupFamily, LieGroup};
use crate::mechanics::FlowJacobian;
use crate::solve::solve_small;

/// The spatial momentum Ad*_{g⁻¹}μ = `coadjoint(g)·μ` (SO(3): Rμ, the
/// angular momentum in the space frame; SE(3): (Rm + x × Rf; Rf)). Conserved
/// exactly by the discrete flow when ℓ(a·g, ξ) = ℓ(g, ξ) for all a.
pub fn spatial_momentum<G: GroupFamily<N>, const N: usize>(state: &GroupState<G, N>) -> SVector<f64, N> {
    state.g.coadjoint() * state.mu
}

/// The body velocity ξ with ∂ℓ/∂ξ(g, ξ) = μ (inverse continuous Legendre
/// transform, by Newton with the exact Hessian; one step when ℓ is quadratic
/// in ξ).
pub fn body_velocity<G: GroupFamily<N>, L: ReducedLagrangian<G, N>, const N: usize>(
    l: &L,
    state: &GroupState<G, N>,
) -> Result<SVector<f64, N>> {
    let mut xi = SVector::<f64, N>::zeros();
    for iteration in 0..50 {
        let (_, p, hess) = hessian(|x| l.lagrangian(&G::lift(&state.g), &x), &xi);
        let (delta, pivot) = solve_small(&hess, &(state.mu - p));
        if pivot < 1e-14 {
            return Err(Error::SingularVelocityHessian { t: state.t, pivot });
        }
        xi += delta;
        if delta.amax() <= 4.0 * f64::EPSILON * xi.amax().max(1.0) {
            break;
        }
        if iteration == 49 {
            return Err(Error::NewtonFailure {
                step: 0,
                t: state.t,
                residual: delta.amax(),
                iterations: 50,
                reason: "inverse Legendre transform did not converge".into(),
            });
        }
    }
    Ok(xi)
}

/// The energy E = ⟨μ, ξ⟩ − ℓ(g, ξ) at the body velocity ξ of
/// [`body_velocity`].
pub fn energy<G: GroupFamily<N>, L: ReducedLagrangian<G, N>, const N: usize>(
    l: &L,
    state: &GroupState<G, N>,
) -> Result<f64> {
    let xi = body_velocity(l, state)?;
    Ok(state.mu.dot(&xi) - l.lagrangian(&state.g, &xi))
}

/// The canonical symplectic form of T*G in left trivialisation at μ, as the
/// matrix W with Ω(z₁, z₂) = z₁ᵀ W z₂ on z = (η, δμ):
/// Ω = ⟨δμ₂, η₁⟩ − ⟨δμ₁, η₂⟩ + ⟨μ, [η₁, η₂]⟩ (Ω = −dθ, θ = ⟨μ, g⁻¹dg⟩).
fn left_trivialised_form<G: GroupFamily<N>, const N: usize>(mu: &SVector<f64, N>) -> DMatrix<f64> {
    let mut w = DMatrix::<f64>::zeros(2 * N, 2 * N);
    for i in 0..N {
        let e = SVector::<f64, N>::from_fn(|r, _| if r == i { 1.0 } else { 0.0 });
        let ad: SMatrix<f64, N, N> = G::ad(&e);
        for j in 0..N {
            w[(i, j)] = mu.dot(&ad.column(j));
        }
        w[(i, N + i)] = 1.0;
        w[(N + i, i)] = -1.0;
    }
    w
}

/// max |(JᵀW(μ₁)J − W(μ₀))ᵢⱼ| for the flow Jacobian J of a step
/// (g₀, μ₀) ↦ (g₁, μ₁) in left-trivialised coordinates (see
/// [`LieGroupIntegrator::flow_jacobian`](super::LieGroupIntegrator::flow_jacobian)).
pub fn lie_symplecticity_defect<G: GroupFamily<N>, const N: usize>(
    jac: &FlowJacobian<N>,
    mu0: &SVector<f64, N>,
    mu1: &SVector<f64, N>,
) -> f64 {
    let mut full = DMatrix::<f64>::zeros(2 * N, 2 * N);
    full.view_mut((0, 0), (N, N)).copy_from(&jac.qq);
    full.view_mut((0, N), (N, N)).copy_from(&jac.qp);
    full.view_mut((N, 0), (N, N)).copy_from(&jac.pq);
    full.view_mut((N, N), (N, N)).copy_from(&jac.pp);
    let (w0, w1) = (left_trivialised_form::<G, N>(mu0), left_trivialised_form::<G, N>(mu1));
    (full.transpose() * w1 * &full - w0).amax()
}
