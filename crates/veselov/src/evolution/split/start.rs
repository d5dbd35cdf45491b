//! A consistent first level before given data: the level y⁻ such that the
//! march from (y⁻, y⁰) starts from given velocities at second order.
//!
//! Discrete mechanics with L_d = h[K((q₁ − q₀)/h) − V(q₀)] (the time
//! direction of seed 000's triangle, eq. (63), whose strain and potential
//! sit at the first level of a cell) is the Störmer–Verlet scheme in
//! positions; its two-level start from (q⁰, v⁰) at second order is
//! q¹ = q⁰ + hv⁰ + ½h²a⁰, which is what a level before q⁰ whose discrete
//! momentum is the consistent one less half the impulse of the forces at q⁰
//! gives: with the node equation D₂ℒ(y⁻, y⁰) + D₁ℒ(y⁰, y¹) + S(y⁰) = 0 (S
//! every term of the level other than the time edges: strain, potential,
//! end load),
//!
//! D₂ℒ(y⁻_a, y⁰_a) + F²(y⁻_a, y⁰_a) = w_aΔs ∇K(ξ_a) − ½S_a(y⁰),
//!
//! so that the momentum the first step leaves, −D₁ℒ(y⁰, y¹), is
//! w_aΔs∇K(ξ_a) plus half the impulse ½S_a: the trapezoid rule's (in one
//! dimension, (q¹ − q⁰)/h = v⁰ + ½ha⁰). At rest (ξ = 0) a free end then releases its strain over the first
//! step instead of jumping. D₂ℒ of the time edge depends on its increment
//! x = τ⁻¹((y⁻)⁻¹y⁰) alone, so each node is one M-dimensional Newton solve
//! on x, and y⁻ = y⁰·τ(−x) (τ(−x) = τ(x)⁻¹ for the exponential and the
//! Cayley map, and for the difference on ℝ^M).

use nalgebra::SVector;

use crate::complex::{MAX_LATTICE_DIMENSION, SpacetimeKind, TopCell};
use crate::evolution::split::{CellWeights, Increment, KineticQuadrature, SplitDensity, SplitLagrangian};
use crate::field::fibre::{Euclidean, Fibre};
use crate::field::legendre::{CauchyOptions, LegendreNewton};
use crate::{Error, Result};

impl<I, S> SplitLagrangian<I, S> {
    /// The level before `level` (the lattice's level `row`, nodes a =
    /// 0..=A) for the body velocities `velocity` (ξ_a, in the fibre's chart
    /// at `level[a]`, y·ρ(tξ)), by the module's second-order start. Nodes
    /// for which `held(a)` gives a value (clamped or driven ends) take it;
    /// with [`KineticQuadrature::FirstNode`] the last node, which carries no
    /// inertia, keeps its value (the march solves it).
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] unless there are as many velocities as
    /// nodes (at least 2), [`Error::NonFinite`] for a non-finite velocity,
    /// [`Error::VertexSolveFailure`] naming the node whose solve fails
    /// (velocities too large for the step: the rotation reaches the chart's
    /// cut locus).
    pub fn previous_level<F, const M: usize>(
        &self,
        level: &[F::Point<f64>],
        velocity: &[SVector<f64, M>],
        held: impl Fn(usize) -> Option<F::Point<f64>>,
        row: i64,
        options: &CauchyOptions,
    ) -> Result<Vec<F::Point<f64>>>
    where
        F: Fibre<M>,
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        let nodes = level.len();
        if nodes < 2 || velocity.len() != nodes {
            return Err(Error::DimensionMismatch {
                what: "velocities (one per node, at least 2 nodes)".into(),
                expected: nodes.max(2),
                got: velocity.len(),
            });
        }
        if let Some(a) = velocity.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
            return Err(Error::NonFinite {
                what: format!("initial velocity at node {a}"),
                index: a,
                value: f64::NAN,
            });
        }
        let last = nodes - 1;
        let end_cell = matches!(self.quadrature, KineticQuadrature::Trapezoid { .. });
        let cell = |a: usize| {
            let mut origin = [0; MAX_LATTICE_DIMENSION];
            origin[0] = row;
            origin[1] = a as i64;
            TopCell {
                index: a,
                shape: SpacetimeKind::Seed000Triangle.tag(),
                origin,
            }
        };
        // S_a: the level's terms other than the time edges, at y⁰ (the time
        // edges held at rest, y₂ = y₁, and weighed out).
        let mut forces = vec![SVector::<f64, M>::zeros(); nodes];
        let cells = if end_cell { nodes } else { last };
        for a in 0..cells {
            let c = cell(a);
            let w = self.weights(&c);
            let side = level[(a + 1).min(last)];
            let y = [level[a], level[a], side];
            let terms = CellWeights { kinetic: 0.0, ..w };
            let Some([first, _, third]) = self.weighted_gradients::<F, f64, M>(terms, &y) else {
                return Err(Error::InvalidParameter {
                    name: format!("initial level, node {a}"),
                    value: "rotation".into(),
                    reason: "no chart step to its neighbour (a relative rotation of π)".into(),
                });
            };
            forces[a] += first;
            if w.end && self.density.has_end_load() {
                forces[a] += self.end_force::<F, f64, M>(&c, &level[a], 0);
            }
            if a < last {
                forces[a + 1] += third;
            }
        }
        let mut previous = level.to_vec();
        for a in 0..nodes {
            if let Some(y) = held(a) {
                previous[a] = y;
                continue;
            }
            if a == last && !end_cell {
                continue;
            }
            let w = self.weights(&cell(a));
            let momentum = self.density.kinetic_gradient(&velocity[a]) * (w.kinetic * self.ds);
            let target = momentum - forces[a] * 0.5;
            let scale = momentum.amax() + 0.5 * forces[a].amax();
            let start = velocity[a] * self.dt;
            let mut kept = None;
            let (x, outcome) = LegendreNewton::<Euclidean<M>, M>::new(target, scale, start, *options, None)
                .keeping_evaluated_jacobians()
                .run(&mut kept, |x, jacobian| {
                    let (value, closed) = match self.moving_jacobian::<F, M>(w, x, 1, 1) {
                        Some(v) => v,
                        None => return (SVector::from_element(f64::NAN), f64::NAN),
                    };
                    if let Some(j) = jacobian {
                        *j = closed;
                    }
                    (value, value.amax())
                });
            if let Some(failure) = outcome
                .failure
                .or((!I::in_chart(&x)).then_some(crate::field::legendre::Failure::CutLocus))
            {
                return Err(Error::VertexSolveFailure {
                    vertex: format!("node {a} of the level before the initial one"),
                    residual: outcome.relative_residual,
                    iterations: outcome.iterations,
                    reason: failure.reason().into(),
                });
            }
            previous[a] = F::renormalize(&I::advance(&level[a], &(-x)));
        }
        Ok(previous)
    }
}
