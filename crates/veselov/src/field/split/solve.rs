//! The flow step of a split Lagrangian in the moving increment alone.
//!
//! Marching in time, the unknown y₂ of the cell based at v enters its
//! vertex equation only through x = Δtξ = τ⁻¹(y₁⁻¹y₂); marching in space,
//! y₃ only through x = Δsη. With A₁(x) = ∂x/∂ε₁
//! ([`Increment::first_transpose_mul`]) the equation ∂ℒ/∂y₁ + F¹ = μ of
//! [`SplitLagrangian::closed_gradients`] reads
//!
//! * time:  ΔsA₁(x)ᵀ∇K(x/Δt) + ½ΔsΔt f(x/Δt) + c = μ,
//! * space: −ΔtA₁(x)ᵀ∇Φ(x/Δs) + c = μ,
//!
//! with c the terms of the other increment, of ∇Π(y₁) and (in space) of the
//! force, fixed during the solve. Newton iterates on x ∈ ℝ^M — the same
//! simplified Newton as every vertex solve
//! ([`solve_legendre_from`](crate::field::legendre::solve_legendre_from),
//! on the vector space of increments, from the node's Jacobian of the last
//! level while it contracts), a fresh Jacobian one dual pass over this
//! function alone — and the value is y₁·τ(x) at the end: no group product,
//! inverse or τ⁻¹ inside the iteration. A last pass takes the residual at
//! the increment read back from the stored value (where the terms cancel,
//! its rounding matters) and goes on from there if it must.

use crate::solve::SmallLu;
use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::DualSVec64;

use super::{Increment, SplitDensity, SplitLagrangian};
use crate::ad::Scalar;
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::legendre::{CauchyOptions, Failure, VertexOutcome, solve_legendre_from};

impl<I, S> SplitLagrangian<I, S> {
    /// The terms of ∂ℒ/∂y₁ + F¹ that move with the increment x of the edge
    /// to vertex `position` (1: time, 2: space); see the module documentation.
    fn moving_terms<F, D, const M: usize>(&self, x: &SVector<D, M>, position: usize) -> SVector<D, M>
    where
        F: Fibre<M>,
        D: Scalar,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        let (ds, dt) = (self.ds, self.dt);
        if position == 1 {
            let xi = x.map(|v| v * (1.0 / dt));
            let mut terms = I::first_transpose_mul(x, &self.density.kinetic_gradient(&xi).map(|v| v * ds));
            if self.density.is_damped() {
                terms += self.density.damping(&xi).map(|f| f * (0.5 * ds * dt));
            }
            terms
        } else {
            let eta = x.map(|v| v * (1.0 / ds));
            I::first_transpose_mul(x, &self.density.stored_gradient(&eta).map(|v| -(v * dt)))
        }
    }

    /// The terms of ∂ℒ/∂y₁ + F¹ fixed while the vertex at `position` moves.
    fn fixed_terms<F, const M: usize>(&self, y: &[F::Point<f64>], position: usize) -> Option<SVector<f64, M>>
    where
        F: Fibre<M>,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        let (ds, dt) = (self.ds, self.dt);
        let mut terms = if position == 1 {
            self.space_edge::<F, f64, M>(&y[0], &y[2])?.0
        } else {
            let mut t = self.time_edge::<F, f64, M>(&y[0], &y[1])?.0;
            if self.density.is_damped() {
                let xi = I::increment(&y[0], &y[1]).ok()?.map(|v| v * (1.0 / dt));
                t += self.density.damping(&xi).map(|f| f * (0.5 * ds * dt));
            }
            t
        };
        if self.density.has_potential() {
            terms -= self.potential_gradient::<F, f64, M>(&y[0]) * (0.5 * ds * dt);
        }
        Some(terms)
    }

    /// Solves the vertex equation of the cell with values `y` (v at 0) for
    /// the vertex at `position` (1 or 2), from `y[position]`, in the moving
    /// increment (module documentation), from the Jacobian `kept` by the
    /// node's last solve (in increment coordinates; left there for the
    /// next). `None` — the generic solve then
    /// runs — for another shape of `y`, or when the first guess or the other
    /// edge is at the cut locus of the increment.
    pub(crate) fn solve_increment<F, const M: usize>(
        &self,
        y: &[F::Point<f64>],
        position: usize,
        mu: &SVector<f64, M>,
        mu_scale: f64,
        options: &CauchyOptions,
        kept: &mut Option<SmallLu<M>>,
    ) -> Option<(F::Point<f64>, VertexOutcome)>
    where
        F: Fibre<M>,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        if y.len() != 3 || !(1..=2).contains(&position) {
            return None;
        }
        let fixed = self.fixed_terms::<F, M>(y, position)?;
        let start = I::increment(&y[0], &y[position]).ok()?;
        // The size of the terms as the chart solve measures it: the cell's
        // ∂ℒ/∂y₁ + F¹ as a whole (plus μ's terms), so both stop alike.
        let evaluate = |x: &SVector<f64, M>, with_jacobian: bool| {
            if with_jacobian {
                let seeded = SVector::<DualSVec64<M>, M>::from_fn(|i, _| DualSVec64::<M>::from_re(x[i]).derivative(i));
                let moving = self.moving_terms::<F, DualSVec64<M>, M>(&seeded, position);
                let value = moving.map(|v| v.re);
                let jacobian = SMatrix::<f64, M, M>::from_fn(|i, j| moving[i].eps.unwrap_generic(Const::<M>, U1)[j]);
                let leg = value + fixed;
                (leg, Some(jacobian), leg.amax())
            } else {
                let value = self.moving_terms::<F, f64, M>(x, position);
                let leg = value + fixed;
                (leg, None, leg.amax())
            }
        };
        // The value the cell will hold, and the increment it reads back.
        let stored = |x: &SVector<f64, M>| {
            let z = F::renormalize(&I::advance(&y[0], x));
            (z, I::increment(&y[0], &z))
        };
        let (x, mut outcome) = solve_legendre_from::<Euclidean<M>, M>(mu, mu_scale, start, options, kept, evaluate);
        if outcome.failure.is_some() {
            return Some((stored(&x).0, outcome));
        }
        // The stored value rounds x: where the terms cancel (a stiff strain
        // near its reference) that rounding can leave more than the
        // tolerance. Newton goes on through the stored value itself — the
        // residual is that of the increment read back from it, the one the
        // march will see — with the same stopping rules; usually one
        // evaluation confirms it.
        // The last stored value evaluated: the one returned on success.
        let last = std::cell::Cell::new(None);
        let (x, polish) = solve_legendre_from::<Euclidean<M>, M>(mu, mu_scale, x, options, kept, |x, with_jacobian| {
            let (z, read) = stored(x);
            last.set(Some((*x, z)));
            match read {
                Ok(read) => evaluate(&read, with_jacobian),
                Err(_) => (SVector::from_element(f64::NAN), None, f64::NAN),
            }
        });
        outcome.iterations += polish.iterations;
        outcome.jacobians += polish.jacobians;
        outcome.relative_residual = polish.relative_residual;
        outcome.failure = polish.failure;
        let z = match last.get() {
            Some((evaluated, z)) if evaluated == x => z,
            _ => stored(&x).0,
        };
        // The solution must be the increment the cell reads back from z (an
        // exponential chart wraps past the cut locus).
        if outcome.failure.is_none() && !I::in_chart(&x) {
            outcome.failure = Some(Failure::CutLocus);
        }
        Some((z, outcome))
    }
}
