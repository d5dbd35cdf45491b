//! The general Lie-group variational integrator: Newton on the algebra for
//! the discrete Legendre transform of any reduced Lagrangian, with the exact
//! Jacobian from nested dual numbers.

use std::marker::PhantomData;

use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::{Dual64, DualSVec64};

use super::carry::{Carry, spatial_of};
use super::discrete::{action_partials, momentum_residual};
use super::{GroupState, GroupStepMap, ReducedLagrangian};
use crate::error::{Error, Result, check_step};
use crate::lie::{GroupFamily, LieGroup, Retraction};
use crate::mechanics::{FlowJacobian, StepStats};
use crate::solve::{NewtonOptions, solve_small};

/// Simplified Newton iteration for a small system r(ξ) = 0 on the algebra,
/// started at `xi` with the Jacobian `jacobian` if one is given (else
/// `exact_jacobian(xi)`). The Jacobian is kept while the update shrinks by at
/// least a factor 4 per iteration and refreshed at the current iterate
/// otherwise, so a slow iteration turns into Newton's method.
/// Convergence: ‖Δξ‖∞ ≤ tol·max(1, ‖ξ‖∞), or an update that stops shrinking
/// below the stall threshold (round-off reached).
/// Returns (ξ, the Jacobian last used, iterations).
pub(crate) fn newton_on_algebra<const N: usize>(
    mut xi: SVector<f64, N>,
    jacobian: Option<SMatrix<f64, N, N>>,
    options: &NewtonOptions,
    (step, t): (usize, f64),
    residual: impl Fn(&SVector<f64, N>) -> SVector<f64, N>,
    exact_jacobian: impl Fn(&SVector<f64, N>) -> SMatrix<f64, N, N>,
) -> Result<(SVector<f64, N>, SMatrix<f64, N, N>, usize)> {
    let mut fresh = jacobian.is_none();
    let mut jac = jacobian.unwrap_or_else(|| exact_jacobian(&xi));
    let mut previous = f64::INFINITY;
    for iteration in 1..=options.max_iterations {
        let r = residual(&xi);
        let fail = |reason: &str| Error::NewtonFailure {
            step,
            t,
            residual: r.amax(),
            iterations: iteration,
            reason: reason.into(),
        };
        if !r.iter().all(|e| e.is_finite()) {
            return Err(fail("non-finite residual"));
        }
        let (delta, pivot) = solve_small(&jac, &(-r));
        if pivot < 1e-14 || !delta.iter().all(|e| e.is_finite()) {
            return Err(fail("singular Jacobian on the algebra"));
        }
        xi += delta;
        let size = delta.amax() / xi.amax().max(1.0);
        if size <= options.tol || (size >= previous && size <= options.stall_threshold) {
            return Ok((xi, jac, iteration));
        }
        if size > 0.25 * previous && !fresh {
            jac = exact_jacobian(&xi);
            fresh = true;
        } else {
            fresh = false;
        }
        previous = size;
    }
    Err(Error::NewtonFailure {
        step,
        t,
        residual: residual(&xi).amax(),
        iterations: options.max_iterations,
        reason: "iteration limit".into(),
    })
}

/// Lie-group variational integrator for a general reduced Lagrangian
/// ℓ(g, ξ) (see the [module documentation](super) for the equations).
pub struct LieGroupIntegrator<G: GroupFamily<N>, R, L, const N: usize> {
    lagrangian: L,
    h: f64,
    options: NewtonOptions,
    guess: Option<SVector<f64, N>>,
    jacobian: Option<SMatrix<f64, N, N>>,
    carry: Option<Carry<G, N>>,
    marker: PhantomData<(G, R)>,
}

impl<G, R, L, const N: usize> LieGroupIntegrator<G, R, L, N>
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: ReducedLagrangian<G, N>,
{
    /// An integrator with step `h` (positive, finite) and default Newton options.
    pub fn new(lagrangian: L, h: f64) -> Result<Self> {
        check_step(h)?;
        Ok(Self {
            lagrangian,
            h,
            options: NewtonOptions::default(),
            guess: None,
            jacobian: None,
            carry: None,
            marker: PhantomData,
        })
    }

    /// Replace the Newton options.
    pub fn with_options(mut self, options: NewtonOptions) -> Self {
        self.options = options;
        self
    }

    /// The reduced Lagrangian.
    pub fn lagrangian(&self) -> &L {
        &self.lagrangian
    }

    /// ∂r/∂ξ of the Legendre residual at ξ, exact (nested dual numbers).
    fn exact_jacobian(&self, state: &GroupState<G, N>, xi: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        let g = G::lift::<DualSVec64<N>>(&state.g);
        let mu = state.mu.map(DualSVec64::<N>::from);
        let xd = SVector::<DualSVec64<N>, N>::from_fn(|i, _| DualSVec64::<N>::from(xi[i]).derivative(i));
        let (r, _) = momentum_residual::<G, R, L, _, N>(&self.lagrangian, &g, &mu, &xd, self.h);
        SMatrix::<f64, N, N>::from_fn(|i, j| r[i].eps.unwrap_generic(Const::<N>, U1)[j])
    }

    /// Solve μ = ν(ξ) − ∂_g L_d(g, ξ) for the step's body velocity ξ by a
    /// simplified Newton iteration: the exact Jacobian (nested dual numbers,
    /// the expensive part) is evaluated once and reused across iterations and
    /// steps while the iteration contracts by at least a factor 4 per
    /// iteration; otherwise it is refreshed at the current iterate (so a slow
    /// iteration turns into Newton's method).
    /// Returns ξ, ∂r/∂ξ (as last evaluated), and the iteration count.
    pub fn solve_velocity(
        &mut self,
        index: usize,
        state: &GroupState<G, N>,
    ) -> Result<(SVector<f64, N>, SMatrix<f64, N, N>, usize)> {
        let (l, h) = (&self.lagrangian, self.h);
        let residual = |xi: &SVector<f64, N>| momentum_residual::<G, R, L, f64, N>(l, &state.g, &state.mu, xi, h).0;
        let exact_jacobian = |xi: &SVector<f64, N>| self.exact_jacobian(state, xi);
        // First step: the continuous Legendre transform is an O(h) guess.
        let xi = match self.guess {
            Some(xi) => xi,
            None => super::body_velocity(l, state)?,
        };
        let solved = newton_on_algebra(
            xi,
            self.jacobian,
            &self.options,
            (index, state.t),
            residual,
            exact_jacobian,
        );
        match &solved {
            Ok((xi, jac, _)) => {
                self.guess = Some(*xi);
                self.jacobian = Some(*jac);
            }
            Err(_) => self.jacobian = None,
        }
        solved
    }

    /// The exact Jacobian of the step map in left-trivialised coordinates
    /// (g τ(η), μ + δμ) ↦ (g' τ(η'), μ' + δμ'), by the implicit function
    /// theorem on the converged Legendre equation (no finite differences).
    /// Blocks: `qq` = ∂η'/∂η, `qp` = ∂η'/∂δμ, `pq` = ∂δμ'/∂η, `pp` = ∂δμ'/∂δμ.
    pub fn flow_jacobian(&mut self, state: &GroupState<G, N>) -> Result<(GroupState<G, N>, FlowJacobian<N>)> {
        let (xi, _, _) = self.solve_velocity(0, state)?;
        let jac = self.exact_jacobian(state, &xi);
        let (l, h) = (&self.lagrangian, self.h);
        let mut out: FlowJacobian<N> = FlowJacobian {
            qq: SMatrix::zeros(),
            qp: SMatrix::zeros(),
            pq: SMatrix::zeros(),
            pp: SMatrix::zeros(),
        };
        let mut next = None;
        for column in 0..2 * N {
            let mut dir = SVector::<Dual64, N>::zeros();
            dir[column % N] = Dual64::new(0.0, 1.0);
            let base = G::lift::<Dual64>(&state.g);
            let (g, mu) = if column < N {
                (base.compose(&R::tau(&dir)), state.mu.map(Dual64::from))
            } else {
                (base, state.mu.map(Dual64::from) + dir)
            };
            let (r, _) = momentum_residual::<G, R, L, _, N>(l, &g, &mu, &xi.map(Dual64::from), h);
            let (dxi, _) = solve_small(&jac, &(-r.map(|e| e.eps)));
            let xid = SVector::<Dual64, N>::from_fn(|i, _| Dual64::new(xi[i], dxi[i]));
            let (_, nu) = momentum_residual::<G, R, L, _, N>(l, &g, &mu, &xid, h);
            let f = R::tau(&(xid * Dual64::from(h)));
            let g1 = g.compose(&f);
            let mu1 = f.adjoint().transpose() * nu;
            let g1_re = G::map_scalar(&g1, |e| e.re);
            let eta1 = R::tau_inv(&G::lift::<Dual64>(&g1_re).between(&g1))?;
            let deta: SVector<f64, N> = eta1.map(|e| e.eps);
            let dmu: SVector<f64, N> = mu1.map(|e| e.eps);
            if column < N {
                out.qq.set_column(column, &deta);
                out.pq.set_column(column, &dmu);
            } else {
                out.qp.set_column(column - N, &deta);
                out.pp.set_column(column - N, &dmu);
            }
            next = Some(GroupState::new(state.t + h, g1_re, mu1.map(|e| e.re)));
        }
        let next = next.ok_or_else(|| Error::DimensionMismatch {
            what: "algebra".into(),
            expected: 1,
            got: 0,
        })?;
        Ok((next, out))
    }
}

impl<G, R, L, const N: usize> GroupStepMap<G, N> for LieGroupIntegrator<G, R, L, N>
where
    G: GroupFamily<N>,
    R: Retraction<N, Family = G>,
    L: ReducedLagrangian<G, N>,
{
    fn step_size(&self) -> f64 {
        self.h
    }

    fn step(&mut self, index: usize, state: &GroupState<G, N>) -> Result<(GroupState<G, N>, StepStats)> {
        let (xi, _, iterations) = self.solve_velocity(index, state)?;
        let h = self.h;
        let spatial0 = Carry::matching(&self.carry, state).map_or_else(|| spatial_of(state), |c| c.0);
        let (dg, _) = action_partials::<G, R, L, f64, N>(&self.lagrangian, &state.g, &xi, h);
        let g = G::reorthogonalize(&state.g.compose(&R::tau(&(xi * h))));
        // π' = π + Ad*_{g⁻¹}∂_g L_d, μ' = Ad_{g'}ᵀπ' (see the `carry` module).
        let spatial = spatial0 + state.g.coadjoint() * dg;
        let mu = g.ad_star_matrix() * spatial;
        let next = GroupState::new(state.t + h, g, mu);
        self.carry = Some(Carry::new(&next, spatial, SVector::zeros()));
        next.check().map_err(|_| Error::NewtonFailure {
            step: index,
            t: state.t,
            residual: f64::NAN,
            iterations,
            reason: "the step produced a non-finite state".into(),
        })?;
        Ok((
            next,
            StepStats {
                max_relative_residual: 0.0,
                iterations,
                fallback: false,
                work: 0.0,
                jacobians: 0,
                force_evaluations: 0,
            },
        ))
    }
}
