//! The fast path for ℓ = ½ξᵀ𝕀ξ − V(g): the Legendre equation
//! dτ⁻ᵀ_{hξ}𝕀ξ = μ − (h/2)∇V(g) involves no potential, so the Newton
//! iteration costs a few small dual-number evaluations of dτ⁻¹, and ∇V is
//! evaluated once per step (the value at g_{k+1} is reused at the next step).

use std::marker::PhantomData;

use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::DualSVec64;

use super::carry::{Carry, restore_vector, save_vector, spatial_of};
use super::discrete::left_gradient;
use super::integrator::newton_on_algebra;
use super::{GroupState, GroupStepMap, SplitReducedLagrangian};
use crate::error::{Error, Result, check_step};
use crate::lie::{GroupFamily, LieGroup, Retraction};
use crate::mechanics::StepStats;
use crate::solve::NewtonOptions;

/// Check that an inertia is finite, symmetric and positive definite
/// (`InvalidParameter` naming "inertia" otherwise).
pub fn check_inertia<const N: usize>(inertia: &SMatrix<f64, N, N>) -> Result<()> {
    inertia_inverse(inertia).map(|_| ())
}

/// 𝕀⁻¹ of a checked inertia (see [`check_inertia`]).
pub(crate) fn inertia_inverse<const N: usize>(inertia: &SMatrix<f64, N, N>) -> Result<SMatrix<f64, N, N>> {
    let bad = |reason: &str| Error::InvalidParameter {
        name: "inertia".into(),
        value: format!("{:?}", inertia.as_slice()),
        reason: reason.into(),
    };
    if !inertia.iter().all(|e| e.is_finite()) {
        return Err(bad("entries must be finite"));
    }
    if (inertia - inertia.transpose()).amax() > 1e-12 * inertia.amax() {
        return Err(bad("the inertia tensor must be symmetric"));
    }
    nalgebra::Cholesky::new(*inertia)
        .map(|c| c.inverse())
        .ok_or_else(|| bad("the inertia tensor must be positive definite"))
}

/// Fixed-point iterations before falling back to Newton.
const MAX_FIXED_POINT_ITERATIONS: usize = 40;

/// A fixed-point update that stops shrinking below this relative size has
/// reached round-off.
const ROUND_OFF_PLATEAU: f64 = 1e-13;

/// Lie-group variational integrator for ℓ = ½ξᵀ𝕀ξ − V(g) (see the
/// [module documentation](super)); the same map as
/// [`LieGroupIntegrator`](super::LieGroupIntegrator) on such Lagrangians.
pub struct SplitLieIntegrator<G: GroupFamily<N>, R, L, const N: usize> {
    lagrangian: L,
    h: f64,
    inertia: SMatrix<f64, N, N>,
    inertia_inv: SMatrix<f64, N, N>,
    options: NewtonOptions,
    guess: Option<SVector<f64, N>>,
    previous_guess: Option<SVector<f64, N>>,
    carry: Option<Carry<G, N>>,
    marker: PhantomData<R>,
}

impl<G, R, L, const N: usize> SplitLieIntegrator<G, R, L, N>
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: SplitReducedLagrangian<G, N>,
{
    /// An integrator with step `h`; fails on a non-positive step or an inertia
    /// that is not symmetric positive definite (`InvalidParameter` "inertia").
    pub fn new(lagrangian: L, h: f64) -> Result<Self> {
        check_step(h)?;
        let inertia = lagrangian.inertia();
        let inertia_inv = inertia_inverse(&inertia)?;
        Ok(Self {
            lagrangian,
            h,
            inertia,
            inertia_inv,
            options: NewtonOptions::default(),
            guess: None,
            previous_guess: None,
            carry: None,
            marker: PhantomData,
        })
    }

    /// The reduced Lagrangian.
    pub fn lagrangian(&self) -> &L {
        &self.lagrangian
    }

    /// Fixed-point iteration ξ ← 𝕀⁻¹ dτ_{hξ}ᵀ m for dτ⁻ᵀ_{hξ}𝕀ξ = m (f64 only;
    /// contraction factor ≈ h‖𝕀⁻¹‖|m|/2). `None` if it does not contract.
    fn fixed_point(&self, start: SVector<f64, N>, m: &SVector<f64, N>) -> Option<(SVector<f64, N>, usize)> {
        let h = self.h;
        let mut xi = start;
        let mut previous = f64::INFINITY;
        for iteration in 1..=MAX_FIXED_POINT_ITERATIONS {
            let next = self.inertia_inv * (R::dtau(&(xi * h)).transpose() * m);
            let size = (next - xi).amax() / next.amax().max(1.0);
            xi = next;
            if !size.is_finite() {
                return None;
            }
            if size <= self.options.tol || (size >= previous && size <= ROUND_OFF_PLATEAU) {
                return Some((xi, iteration));
            }
            if iteration > 2 && size > 0.5 * previous {
                return None;
            }
            previous = size;
        }
        None
    }

    /// Newton's method with the exact (dual-number) Jacobian: the fallback
    /// when the fixed-point iteration does not contract (large h|ξ|).
    fn newton(
        &self,
        start: SVector<f64, N>,
        m: &SVector<f64, N>,
        index: usize,
        t: f64,
    ) -> Result<(SVector<f64, N>, usize)> {
        let inertia = self.inertia.map(DualSVec64::<N>::from);
        let h = self.h;
        let hd = DualSVec64::<N>::from(h);
        let residual = |xi: &SVector<f64, N>| R::dtau_inv_tr_mul(&(xi * h), &(self.inertia * xi)) - m;
        let jacobian = |xi: &SVector<f64, N>| {
            let xd = SVector::<DualSVec64<N>, N>::from_fn(|i, _| DualSVec64::<N>::from(xi[i]).derivative(i));
            let r = R::dtau_inv_tr_mul(&(xd * hd), &(inertia * xd));
            SMatrix::<f64, N, N>::from_fn(|i, j| r[i].eps.unwrap_generic(Const::<N>, U1)[j])
        };
        let (xi, _, iterations) = newton_on_algebra(start, None, &self.options, (index, t), residual, jacobian)?;
        Ok((xi, iterations))
    }

    /// The left-trivialised gradient ∇V(g).
    pub fn potential_gradient(&self, g: &G::Element<f64>) -> SVector<f64, N> {
        left_gradient::<G, f64, N>(g, |gd| self.lagrangian.potential(gd)).1
    }
}

impl<G, R, L, const N: usize> GroupStepMap<G, N> for SplitLieIntegrator<G, R, L, N>
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: SplitReducedLagrangian<G, N>,
{
    /// The last two Newton solutions (the predictor) and the carried π, ∇V.
    fn save_carry(&self, out: &mut Vec<f64>) {
        save_vector(&self.guess, out);
        save_vector(&self.previous_guess, out);
        Carry::save(&self.carry, out);
    }
    fn restore_carry(&mut self, words: &mut crate::run::Words<'_>) -> Result<()> {
        self.guess = restore_vector(words)?;
        self.previous_guess = restore_vector(words)?;
        self.carry = Carry::restore(words)?;
        Ok(())
    }
    fn step_size(&self) -> f64 {
        self.h
    }

    fn step(&mut self, index: usize, state: &GroupState<G, N>) -> Result<(GroupState<G, N>, StepStats)> {
        let h = self.h;
        let (spatial0, grad0) = match Carry::matching(&self.carry, state) {
            Some(carried) => carried,
            None => (spatial_of(state), self.potential_gradient(&state.g)),
        };
        let m = state.mu - grad0 * (0.5 * h);
        let start = match (self.guess, self.previous_guess) {
            (Some(a), Some(b)) => a * 2.0 - b,
            (Some(a), None) => a,
            _ => self.inertia_inv * m,
        };
        let (xi, iterations, fallback) = match self.fixed_point(start, &m) {
            Some((xi, iterations)) => (xi, iterations, false),
            None => {
                let (xi, iterations) = self.newton(start, &m, index, state.t)?;
                (xi, iterations, true)
            }
        };
        self.previous_guess = self.guess;
        self.guess = Some(xi);
        let f = R::tau(&(xi * h));
        let g = G::reorthogonalize(&state.g.compose(&f));
        let grad1 = self.potential_gradient(&g);
        // π' = π − (h/2)(Ad*_{g⁻¹}∇V(g) + Ad*_{g'⁻¹}∇V(g')), μ' = Ad_{g'}ᵀπ'
        // (see the `carry` module).
        let spatial = spatial0 - (state.g.coadjoint() * grad0 + g.coadjoint() * grad1) * (0.5 * h);
        let mu = g.ad_star_matrix() * spatial;
        let next = GroupState::new(state.t + h, g, mu);
        self.carry = Some(Carry::new(&next, spatial, grad1));
        if !mu.iter().all(|e| e.is_finite()) {
            return Err(Error::NewtonFailure {
                step: index,
                t: state.t,
                residual: f64::NAN,
                iterations,
                reason: "the step produced a non-finite state".into(),
            });
        }
        Ok((
            next,
            StepStats {
                max_relative_residual: 0.0,
                iterations,
                fallback,
                work: 0.0,
                jacobians: 0,
                force_evaluations: 0,
            },
        ))
    }
}
