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
//! ([`LegendreNewton`] on the vector space of increments, from the node's
//! Jacobian of the last level while it contracts; the factors it keeps are
//! always an evaluated Jacobian's,
//! [`LegendreNewton::keeping_evaluated_jacobians`]), a fresh Jacobian one
//! dual pass over this
//! function alone — and the value is y₁·τ(x) at the end: no group product,
//! inverse or τ⁻¹ inside the iteration. A last pass takes the residual at
//! the increment read back from the stored value (where the terms cancel,
//! its rounding matters) and goes on from there if it must.
//!
//! A slaved vertex (seed 000's last node of a level, note 000 §1) is the
//! unknown of its own equation ∂ℒ/∂y_p + F^p = μ in its one cell: the same
//! solve with A₂ = ∂x/∂ε₂ in place of A₁, no fixed terms, and (at the space
//! end) the half potential ½ΔsΔt∇Π(y₁τ(x)) moving with x.

use nalgebra::{SMatrix, SVector};
use num_dual::DualSVec64;

use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::evolution::split::{CellWeights, Increment, SplitDensity, SplitLagrangian};
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::legendre::{CauchyOptions, Failure, LegendreNewton, VertexOutcome};
use crate::solve::SmallLu;

impl<I, S> SplitLagrangian<I, S> {
    /// The terms of ∂ℒ/∂y_equation + F^equation that move with the
    /// increment x of the edge to vertex `position` (1: time, 2: space);
    /// `equation` is 0, or `position` for a slaved vertex. See the module
    /// documentation.
    fn moving_terms<F, D, const M: usize>(
        &self,
        w: CellWeights,
        y0: &F::Point<f64>,
        x: &SVector<D, M>,
        equation: usize,
        position: usize,
    ) -> SVector<D, M>
    where
        F: Fibre<M>,
        D: Scalar,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        let (ds, dt) = (self.ds, self.dt);
        let pull_back = |p: &SVector<D, M>| {
            if equation == 0 {
                I::first_transpose_mul(x, p)
            } else {
                I::second_transpose_mul(x, p)
            }
        };
        if position == 1 {
            let xi = x.map(|v| v * (1.0 / dt));
            let mut terms = pull_back(&self.density.kinetic_gradient(&xi).map(|v| v * (ds * w.kinetic)));
            // F¹ = F² = ½ΔsΔt f(ξ).
            if self.density.is_damped() {
                terms += self.density.damping(&xi).map(|f| f * (0.5 * ds * dt * w.kinetic));
            }
            terms
        } else {
            let eta = x.map(|v| v * (1.0 / ds));
            let mut terms = pull_back(&self.density.stored_gradient(&eta).map(|v| -(v * (dt * w.stored))));
            // The slaved end of the space edge carries half the potential.
            if equation == 2 && self.density.has_potential() {
                let y2 = I::advance(&F::lift::<D>(y0), x);
                terms -= self
                    .potential_gradient::<F, D, M>(&y2)
                    .map(|v| v * (0.5 * ds * dt * w.stored));
            }
            terms
        }
    }

    /// [`moving_terms`](Self::moving_terms) and their Jacobian in x, in
    /// closed form from the density's Hessians: ∂(Aᵀp)/∂x at fixed p plus
    /// Aᵀ∂p/∂x, column by column. `None` where the moving terms hold the
    /// potential (a slaved space end): its Jacobian is then one dual pass.
    pub(super) fn moving_jacobian<F, const M: usize>(
        &self,
        w: CellWeights,
        x: &SVector<f64, M>,
        equation: usize,
        position: usize,
    ) -> Option<(SVector<f64, M>, SMatrix<f64, M, M>)>
    where
        F: Fibre<M>,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        if equation == 2 && self.density.has_potential() {
            return None;
        }
        let (ds, dt) = (self.ds, self.dt);
        let first = equation == 0;
        let pull_back = |p: &SVector<f64, M>| {
            if first {
                I::first_transpose_mul(x, p)
            } else {
                I::second_transpose_mul(x, p)
            }
        };
        let (p, dp) = if position == 1 {
            let (ds, xi) = (ds * w.kinetic, x.map(|v| v * (1.0 / dt)));
            let p = self.density.kinetic_gradient(&xi).map(|v| v * ds);
            (p, self.density.kinetic_hessian(&xi) * (ds / dt))
        } else {
            let (dt, eta) = (dt * w.stored, x.map(|v| v * (1.0 / ds)));
            let p = self.density.stored_gradient(&eta).map(|v| -(v * dt));
            (p, self.density.stored_hessian(&eta) * (-dt / ds))
        };
        let mut terms = pull_back(&p);
        let mut jacobian = if first {
            I::first_transpose_mul_derivative(x, &p)
        } else {
            I::second_transpose_mul_derivative(x, &p)
        };
        for j in 0..M {
            let column = pull_back(&dp.column(j).into_owned());
            let mut target = jacobian.column_mut(j);
            target += column;
        }
        if position == 1 && self.density.is_damped() {
            let xi = x.map(|v| v * (1.0 / dt));
            terms += self.density.damping(&xi).map(|f| f * (0.5 * ds * dt * w.kinetic));
            jacobian += self.density.damping_jacobian(&xi) * (0.5 * ds * w.kinetic);
        }
        Some((terms, jacobian))
    }

    /// The terms of ∂ℒ/∂y_equation + F^equation fixed while the vertex at
    /// `position` moves (none for a slaved vertex, `equation` = `position`).
    fn fixed_terms<F, const M: usize>(
        &self,
        (cell, w): (&TopCell, CellWeights),
        y: &[F::Point<f64>],
        equation: usize,
        position: usize,
    ) -> Option<SVector<f64, M>>
    where
        F: Fibre<M>,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        if equation != 0 {
            return Some(SVector::zeros());
        }
        let (ds, dt) = (self.ds, self.dt);
        let mut terms = if position == 1 {
            if w.stored == 0.0 {
                SVector::zeros()
            } else {
                let (x, p) = self.space_edge::<F, f64, M>(w, &y[0], &y[2])?;
                I::first_transpose_mul(&x, &p)
            }
        } else {
            let (x, p) = self.time_edge::<F, f64, M>(w, &y[0], &y[1])?;
            let mut t = I::first_transpose_mul(&x, &p);
            if self.density.is_damped() {
                let xi = x.map(|v| v * (1.0 / dt));
                t += self.density.damping(&xi).map(|f| f * (0.5 * ds * dt * w.kinetic));
            }
            t
        };
        if self.density.has_potential() && w.stored != 0.0 {
            terms -= self.potential_gradient::<F, f64, M>(&y[0]) * (0.5 * ds * dt * w.stored);
        }
        if w.end && self.density.has_end_load() {
            terms += self.end_force::<F, f64, M>(cell, &y[0], 0);
        }
        Some(terms)
    }

    /// Solves the equation of vertex `equation` (0, or `position` for a
    /// slaved vertex) of the cell with values `y` for the vertex at
    /// `position` (1 or 2), from `y[position]`, in the moving increment
    /// (module documentation), from the Jacobian factors `kept` by the
    /// node's last solve (in increment coordinates; left there for the
    /// next). `None` — the generic solve then runs — for another shape of
    /// `y`, or when the first guess or the other edge is at the cut locus
    /// of the increment.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve_increment<F, const M: usize>(
        &self,
        cell: &TopCell,
        y: &[F::Point<f64>],
        equation: usize,
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
        if y.len() != 3 || !(1..=2).contains(&position) || !(equation == 0 || equation == position) {
            return None;
        }
        let w = self.weights(cell);
        let fixed = self.fixed_terms::<F, M>((cell, w), y, equation, position)?;
        let start = I::increment(&y[0], &y[position]).ok()?;
        // The size of the terms as the chart solve measures it: the cell's
        // ∂ℒ/∂y₁ + F¹ as a whole (plus μ's terms), so both stop alike.
        let evaluate = |x: &SVector<f64, M>, jacobian: Option<&mut SMatrix<f64, M, M>>| {
            let value = match jacobian {
                Some(j) => match self.moving_jacobian::<F, M>(w, x, equation, position) {
                    Some((value, closed)) => {
                        *j = closed;
                        value
                    }
                    None => {
                        let (value, by_duals) = num_dual::jacobian(
                            |s| self.moving_terms::<F, DualSVec64<M>, M>(w, &y[0], &s, equation, position),
                            x,
                        );
                        *j = by_duals;
                        value
                    }
                },
                None => self.moving_terms::<F, f64, M>(w, &y[0], x, equation, position),
            };
            let leg = value + fixed;
            (leg, leg.amax())
        };
        // The value the cell will hold, and the increment it reads back.
        let stored = |x: &SVector<f64, M>| {
            let z = F::renormalize(&I::advance(&y[0], x));
            (z, I::increment(&y[0], &z))
        };
        // A slaved vertex's equation has no fixed terms (∇Φ(η) = 0, say):
        // its residual in exact increments falls towards 0 without the
        // rounding floor at which the solve stops, so it is solved through
        // the stored value alone, as the chart solve is.
        let (x, mut outcome) = if equation == 0 {
            newton_in_increments::<M>(mu, mu_scale, start, options, kept).run(kept, evaluate)
        } else {
            (start, VertexOutcome::default())
        };
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
        let (x, polish) = newton_in_increments::<M>(mu, mu_scale, x, options, kept).run(kept, |x, jacobian| {
            let (z, read) = stored(x);
            last.set(Some((*x, z)));
            match read {
                Ok(read) => evaluate(&read, jacobian),
                Err(_) => (SVector::from_element(f64::NAN), f64::NAN),
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

/// The Newton of a split solve: on the increments, from the factors `kept`
/// by the last solve of this equation, keeping evaluated Jacobians only
/// ([`LegendreNewton::keeping_evaluated_jacobians`]).
fn newton_in_increments<const M: usize>(
    mu: &SVector<f64, M>,
    mu_scale: f64,
    start: SVector<f64, M>,
    options: &CauchyOptions,
    kept: &mut Option<SmallLu<M>>,
) -> LegendreNewton<Euclidean<M>, M> {
    LegendreNewton::new(*mu, mu_scale, start, *options, kept.take()).keeping_evaluated_jacobians()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evolution::split::{DiagonalQuadratic, Difference, GroupIncrement};
    use crate::field::fibre::RigidMotions;
    use crate::lie::{CayleyMap, ExpMap, Retraction};
    use crate::models::beam::{BeamDensity, BeamProperties};

    /// Weights other than 1, so that a weight dropped anywhere shows.
    const W: CellWeights = CellWeights {
        kinetic: 0.5,
        stored: 0.75,
        end: false,
    };

    /// The closed-form Jacobian against one dual pass over the moving terms,
    /// for every (equation, position) the solve takes.
    fn check<F, I, S, const M: usize>(lag: &SplitLagrangian<I, S>, y0: &F::Point<f64>, x: &SVector<f64, M>)
    where
        F: Fibre<M>,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        for (equation, position) in [(0, 1), (0, 2), (1, 1), (2, 2)] {
            let by_duals = num_dual::jacobian(
                |s| lag.moving_terms::<F, DualSVec64<M>, M>(W, y0, &s, equation, position),
                x,
            )
            .1;
            let Some((value, closed)) = lag.moving_jacobian::<F, M>(W, x, equation, position) else {
                assert!(equation == 2, "only the slaved space end with a potential takes duals");
                continue;
            };
            assert_eq!(value, lag.moving_terms::<F, f64, M>(W, y0, x, equation, position));
            let size = by_duals.amax();
            assert!(
                (closed - by_duals).amax() <= 1e-14 * size,
                "({equation}, {position}): {:.1e} of {size:.1e}",
                (closed - by_duals).amax()
            );
        }
    }

    fn beam(gravity: bool) -> BeamDensity {
        let p = BeamProperties::from_diagonals([0.5, 0.7, 1.1, 1.0, 1.3, 0.9], [0.5, 0.4, 0.6, 1.0, 2.0, 3.0])
            .expect("positive");
        let d = BeamDensity::new(p)
            .with_damping([0.1, 0.2, 0.05, 0.3, 0.1, 0.2])
            .expect("non-negative");
        if gravity { d.with_gravity([0.0, -9.8, 0.0]) } else { d }
    }

    #[test]
    fn closed_form_jacobian_of_the_moving_terms_is_the_dual_one() {
        let x = SVector::<f64, 6>::new(0.3, -0.5, 0.2, 0.04, -0.02, 0.11);
        let g0 = CayleyMap::tau(&SVector::<f64, 6>::new(0.2, 0.1, -0.4, 1.0, 2.0, -0.5));
        for gravity in [false, true] {
            let cayley = SplitLagrangian::<GroupIncrement<CayleyMap>, _>::new(beam(gravity), 0.05, 0.1).expect("lag");
            check::<RigidMotions, _, _, 6>(&cayley, &g0, &x);
            let exp = SplitLagrangian::<GroupIncrement<ExpMap>, _>::new(beam(gravity), 0.05, 0.1).expect("lag");
            check::<RigidMotions, _, _, 6>(&exp, &g0, &x);
        }
        let wave = DiagonalQuadratic::<3> {
            inertia: [1.0, 2.0, 0.5],
            stiffness: [3.0, 1.0, 4.0],
            reference: [0.0, 0.1, 0.0],
        };
        let flat = SplitLagrangian::<Difference, _>::new(wave, 0.05, 0.1).expect("lag");
        check::<Euclidean<3>, _, _, 3>(
            &flat,
            &SVector::from([0.1, 0.2, 0.3]),
            &SVector::from([0.01, -0.02, 0.03]),
        );
    }
}
