//! Lie-group variational integrators: discrete Euler–Poincaré equations with
//! left trivialisation, for reduced Lagrangians ℓ(g, ξ) on SO(3) and SE(3).
//!
//! # The discretisation
//!
//! A motion t ↦ g(t) in a matrix group G has body velocity ξ = g⁻¹ġ ∈ 𝔤 ≅ Rᴺ.
//! Over a step of length h the discrete motion is g_{k+1} = g_k τ(hξ_k) for a
//! retraction τ ([`ExpMap`](crate::lie::ExpMap) or
//! [`CayleyMap`](crate::lie::CayleyMap)), and the discrete Lagrangian is the
//! trapezoidal rule at constant body velocity,
//!
//! ```text
//! L_d(g_k, ξ_k) = h/2 [ ℓ(g_k, ξ_k) + ℓ(g_k τ(hξ_k), ξ_k) ],
//! ```
//!
//! written once ([`discrete_lagrangian`]) for every scalar type, so all its
//! derivatives are exact. It is symmetric (τ(−ξ) = τ(ξ)⁻¹ for both
//! retractions), hence second order.
//!
//! # Discrete Euler–Poincaré equations (derived here)
//!
//! Left-trivialised variations δg_k = g_k η_k change the body velocity by
//! h δξ_k = dτ⁻¹_{hξ_k}(Ad_{F_k} η_{k+1} − η_k), F_k = τ(hξ_k), with the
//! right-trivialised dτ of [`crate::lie`] (seed 000 eq. (62)). Writing
//! ∂_g L_d for the left-trivialised derivative at g_k (ξ_k fixed) and
//! ν_k = (1/h) dτ⁻ᵀ_{hξ_k} ∂_ξ L_d(g_k, ξ_k), stationarity of Σ L_d gives the
//! discrete momenta (the discrete Legendre transforms, left-trivialised)
//!
//! ```text
//! μ_k     = ν_k − ∂_g L_d(g_k, ξ_k)        (solved for ξ_k)
//! μ_{k+1} = Ad_{F_k}ᵀ ν_k
//! ```
//!
//! and the position–momentum step (g_k, μ_k) ↦ (g_{k+1}, μ_{k+1}). It is
//! symplectic for the canonical form of T*G in left trivialisation,
//! Ω((η₁, δμ₁), (η₂, δμ₂)) = ⟨δμ₂, η₁⟩ − ⟨δμ₁, η₂⟩ + ⟨μ, [η₁, η₂]⟩, and
//! conserves the spatial momentum Ad*_{g⁻¹}μ = [`coadjoint`](crate::lie::LieGroup::coadjoint)(g)·μ
//! whenever ℓ is invariant under g ↦ a·g (discrete Noether theorem).
//!
//! For ℓ = ½ξᵀ𝕀ξ − V(g) the potential at g_{k+1} drops out of the first
//! equation, which becomes dτ⁻ᵀ_{hξ}𝕀ξ = μ_k − (h/2)∇V(g_k) (three or six
//! unknowns, no potential evaluation inside the iteration), and
//! μ_{k+1} = Ad_Fᵀ dτ⁻ᵀ_{hξ}𝕀ξ − (h/2)∇V(g_{k+1}). On SO(3) with the Cayley
//! map this is the scheme of Lee, Leok and McClamroch written in body
//! momentum. [`SplitLieIntegrator`] takes this path;
//! [`LieGroupIntegrator`] solves the general equation by Newton with the
//! exact Jacobian (nested dual numbers).

mod carry;
mod diagnostics;
mod discrete;
mod group_stepper;
mod integrator;
mod lagrangian;
mod reference;
mod split;
mod state;

pub use diagnostics::{body_velocity, energy, lie_symplecticity_defect, spatial_momentum};
pub use discrete::{action_partials, discrete_lagrangian, left_gradient, momentum_residual};
pub use group_stepper::{GroupStepper, integrate_group, integrate_group_observed};
pub use integrator::LieGroupIntegrator;
pub use lagrangian::{ReducedLagrangian, SplitReducedLagrangian};
pub use reference::rk4_group_reference;
pub use split::{SplitLieIntegrator, check_inertia};
pub use state::{GroupState, GroupStepMap, GroupTrajectory};
