//! Closed forms of the SEM action's derivatives for `L = ½ vᵀMv − V(t, q)`
//! with a constant mass matrix `M` (note 001 §2.1; seed 001 (3.3)–(3.4)).
//!
//! With `Δq = q₁ − q₀`, `v̄ = Δq/h`, nodes `xᵢ = (1 − cᵢ)q₀ + cᵢq₁` at times
//! `τᵢ = t₀ + cᵢh` and `Vᵢ = V(τᵢ, xᵢ)`:
//!
//! `S = h(½ v̄ᵀMv̄ − Σ bᵢVᵢ)`,
//! `∂S/∂q₀ = −Mv̄ − h Σ bᵢ(1 − cᵢ)∇Vᵢ`,  `∂S/∂q₁ = Mv̄ − h Σ bᵢcᵢ∇Vᵢ`,
//! `E⁻ = ∂S/∂t₀ − ∂S/∂h = ½ v̄ᵀMv̄ + Σ bᵢVᵢ − h Σ bᵢ(1 − cᵢ)∂ₜVᵢ`,
//! `E⁺ = −∂S/∂h = ½ v̄ᵀMv̄ + Σ bᵢVᵢ + h Σ bᵢcᵢ∂ₜVᵢ`,
//! `h ∂²S/∂q₀∂q₁ = −M − h² Σ bᵢcᵢ(1 − cᵢ)∇²Vᵢ`.
//!
//! Each needs one pass over `V` ([`Lagrangian::potential_energy`]) per node instead of passes
//! over the whole action; the general passes of [`super::SemAction`] are the
//! reference they are tested against.

use nalgebra::{Const, U1};
use nalgebra::{SMatrix, SVector};
use num_dual::{Derivative, Dual64, HyperDual64, HyperDualSVec64};

use crate::ad::lift;

use crate::mechanics::Lagrangian;
use crate::mechanics::lagrangian::{potential_gradient, potential_hessian};

/// A segment `(t₀, q₀) → (t₀ + h, q₁)` of a Lagrangian with constant mass.
pub(super) struct Segment<'a, L, const N: usize> {
    pub lagrangian: &'a L,
    pub mass: &'a SMatrix<f64, N, N>,
    pub nodes: &'a [f64],
    pub weights: &'a [f64],
    pub t0: f64,
    pub q0: &'a SVector<f64, N>,
    pub q1: &'a SVector<f64, N>,
    pub h: f64,
}

impl<L: Lagrangian<N>, const N: usize> Segment<'_, L, N> {
    /// `v̄` and `½ v̄ᵀMv̄`.
    fn kinetic(&self) -> (SVector<f64, N>, f64) {
        let vbar = (self.q1 - self.q0) / self.h;
        (vbar, 0.5 * vbar.dot(&(self.mass * vbar)))
    }

    /// The rule's nodes `(bᵢ, cᵢ, τᵢ, xᵢ)`.
    fn nodes(&self) -> impl Iterator<Item = (f64, f64, f64, SVector<f64, N>)> + '_ {
        self.nodes.iter().zip(self.weights).map(|(&c, &b)| {
            let x = self.q0 * (1.0 - c) + self.q1 * c;
            (b, c, self.t0 + self.h * c, x)
        })
    }

    /// `Σ bᵢVᵢ`, `Σ bᵢwᵢ∇Vᵢ` and `Σ bᵢwᵢ∂ₜVᵢ` with `wᵢ = weight(cᵢ)`: a
    /// gradient pass in `q` per node, and a derivative pass in `t` only when
    /// `with_rate` (the momentum alone does not need `∂ₜV`).
    fn weighted_sums(&self, weight: impl Fn(f64) -> f64, with_rate: bool) -> (f64, SVector<f64, N>, f64) {
        let (mut potential, mut gradient, mut rate) = (0.0, SVector::<f64, N>::zeros(), 0.0);
        for (b, c, t, x) in self.nodes() {
            let (value, grad) = potential_gradient(&self.lagrangian, t, &x);
            potential += b * value;
            gradient += grad * (b * weight(c));
            if with_rate {
                let (_, dt) = num_dual::first_derivative(|s: Dual64| self.lagrangian.potential_energy(s, &lift(&x)), t);
                rate += b * weight(c) * dt;
            }
        }
        (potential, gradient, rate)
    }

    /// `(S, ∂S/∂q₀, E⁻)`.
    pub(super) fn leaving(&self) -> (f64, SVector<f64, N>, f64) {
        let (vbar, kinetic) = self.kinetic();
        let (potential, gradient, rate) = self.weighted_sums(|c| 1.0 - c, true);
        let h = self.h;
        (
            h * (kinetic - potential),
            -(self.mass * vbar) - gradient * h,
            kinetic + potential - h * rate,
        )
    }

    /// `∂S/∂q₀` alone (no time-derivative passes).
    pub(super) fn leaving_momentum(&self) -> SVector<f64, N> {
        let (vbar, _) = self.kinetic();
        let (_, gradient, _) = self.weighted_sums(|c| 1.0 - c, false);
        -(self.mass * vbar) - gradient * self.h
    }

    /// `(∂S/∂q₁, E⁺)`.
    pub(super) fn arrival(&self) -> (SVector<f64, N>, f64) {
        let (vbar, kinetic) = self.kinetic();
        let (potential, gradient, rate) = self.weighted_sums(|c| c, true);
        let h = self.h;
        (self.mass * vbar - gradient * h, kinetic + potential + h * rate)
    }

    /// The parts of the step Jacobian that move along a run (see
    /// [`super::SemAction::step_jacobian_along`]): `∂²S/∂q₀∂w`, `∂E⁻/∂q₁` and
    /// `∂E⁻/∂w` along `w = (δq₁, δh) = (v̄, 1)`, which keeps `v̄` and moves node
    /// `i` by `cᵢ(v̄, 1)` in `(q, t)`:
    ///
    /// `∂²S/∂q₀∂w = −Σ bᵢ(1 − cᵢ)[∇Vᵢ + h cᵢ(∇²Vᵢ v̄ + ∂ₜ∇Vᵢ)]`,
    /// `∂E⁻/∂q₁ = Mv̄/h + Σ bᵢ[cᵢ∇Vᵢ − h cᵢ(1 − cᵢ)∂ₜ∇Vᵢ]`,
    /// `∂E⁻/∂w = Σ bᵢ[cᵢ Dᵢ − (1 − cᵢ)∂ₜVᵢ − h cᵢ(1 − cᵢ)∂ₜDᵢ]`, `Dᵢ = ∇Vᵢ·v̄ + ∂ₜVᵢ`.
    ///
    /// Two passes over `V` per node: one with `q` in the first infinitesimal
    /// part and `(v̄, 1)` and `t` in the second, one with `t` and `(v̄, 1)`.
    pub(super) fn jacobian_along(&self) -> (SVector<f64, N>, SVector<f64, N>, f64) {
        let (vbar, _) = self.kinetic();
        let h = self.h;
        let mut momentum_w = SVector::<f64, N>::zeros();
        let mut energy_q1 = self.mass * vbar / h;
        let mut energy_w = 0.0;
        for (b, c, t, x) in self.nodes() {
            type D2<const N: usize> = HyperDualSVec64<N, 2>;
            let q = SVector::<D2<N>, N>::from_fn(|i, _| {
                let mut y = D2::<N>::from(x[i]).derivative1(i);
                y.eps2 = Derivative::some(nalgebra::RowVector2::new(vbar[i], 0.0));
                y
            });
            let mut time = D2::<N>::from(t);
            time.eps2 = Derivative::some(nalgebra::RowVector2::new(1.0, 1.0));
            let v = self.lagrangian.potential_energy(time, &q);
            let gradient = v.eps1.unwrap_generic(Const::<N>, U1);
            let first = v.eps2.unwrap_generic(U1, Const::<2>);
            let second = v.eps1eps2.unwrap_generic(Const::<N>, Const::<2>);
            // Columns of the second part: along (v̄, 1) and along t.
            let (along, rate) = (first[0], first[1]);
            let (gradient_along, gradient_rate) = (second.column(0), second.column(1));
            let (_, _, _, rate_along) = num_dual::second_partial_derivative(
                |(s, e): (HyperDual64, HyperDual64)| {
                    let q = SVector::<HyperDual64, N>::from_fn(|i, _| HyperDual64::from(x[i]) + e * vbar[i]);
                    self.lagrangian.potential_energy(HyperDual64::from(t) + s + e, &q)
                },
                (0.0, 0.0),
            );
            let (inner, outer) = (c, 1.0 - c);
            momentum_w -= (gradient + gradient_along * (h * inner)) * (b * outer);
            energy_q1 += (gradient * inner - gradient_rate * (h * inner * outer)) * b;
            energy_w += b * (inner * along - outer * rate - h * inner * outer * rate_along);
        }
        (momentum_w, energy_q1, energy_w)
    }

    /// `h ∂²S/∂q₀∂q₁`.
    pub(super) fn momentum_block(&self) -> SMatrix<f64, N, N> {
        let mut block = -self.mass;
        for (b, c, t, x) in self.nodes() {
            let (_, _, hessian) = potential_hessian(&self.lagrangian, t, &x);
            block -= hessian * (self.h * self.h * b * c * (1.0 - c));
        }
        block
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix2, Vector2};

    use crate::ad::Scalar;
    use crate::mechanics::{Lagrangian, Potential, SeparableLagrangian};
    use crate::sem::{SemAction, SemRule};

    /// A time-dependent, anharmonic potential.
    #[derive(Debug, Clone, Copy)]
    struct Driven;
    impl Potential<2> for Driven {
        fn potential<D: Scalar>(&self, t: D, q: &Vector2<D>) -> D {
            (t.sin() * 0.3 + 1.0) * (q[0] * q[0] + q[0] * q[1] * q[1] * q[1]) + q[1].cos() - t * q[0] * 0.2
        }
    }

    /// The same Lagrangian without the declaration: the general passes.
    struct Undeclared<L>(L);
    impl<L: Lagrangian<2>> Lagrangian<2> for Undeclared<L> {
        fn lagrangian<D: Scalar>(&self, t: D, q: &Vector2<D>, v: &Vector2<D>) -> D {
            self.0.lagrangian(t, q, v)
        }
    }

    fn close(a: f64, b: f64, scale: f64) -> bool {
        (a - b).abs() <= 1e-13 * scale.max(1.0)
    }

    /// Every closed form against the general passes over the whole action
    /// and against the all-derivatives pass, for every rule, with a
    /// non-diagonal mass matrix and a time-dependent potential.
    #[test]
    fn closed_forms_match_the_general_passes() {
        let mass = Matrix2::new(2.0, 0.3, 0.3, 0.7);
        let system = SeparableLagrangian::new(mass, Driven).expect("SPD");
        assert_eq!(system.constant_mass(), Some(mass));
        let (t0, h) = (0.4, 0.11);
        let (q0, q1) = (Vector2::new(0.3, -0.8), Vector2::new(0.37, -0.71));
        for rule in [
            SemRule::LeftPoint,
            SemRule::Midpoint,
            SemRule::Trapezoid,
            SemRule::Averaged(3),
        ] {
            let fast = SemAction::new(system.clone(), rule).expect("valid");
            let general = SemAction::new(Undeclared(system.clone()), rule).expect("valid");
            let all = general.derivatives(t0, &q0, &q1, h);
            let (s, s_q0, e_minus) = fast.leaving(t0, &q0, &q1, h);
            let (s_ref, s_q0_ref, e_minus_ref) = general.leaving(t0, &q0, &q1, h);
            assert!(
                close(s, s_ref, s_ref.abs()) && close(s, all.value, s.abs()),
                "{rule:?}: S"
            );
            assert!(
                close(e_minus, e_minus_ref, e_minus.abs()),
                "{rule:?}: E⁻ {e_minus} {e_minus_ref}"
            );
            assert!(
                close(e_minus, all.t0 - all.h, e_minus.abs()),
                "{rule:?}: E⁻ = S_t0 − S_h"
            );
            for a in 0..2 {
                assert!(close(s_q0[a], s_q0_ref[a], s_q0.amax()), "{rule:?}: ∂S/∂q₀");
                assert!(close(s_q0[a], all.q0[a], s_q0.amax()), "{rule:?}: ∂S/∂q₀");
            }
            assert_eq!(fast.leaving_momentum(t0, &q0, &q1, h), s_q0);
            let (p1, e_plus) = fast.arrival(t0, &q0, &q1, h);
            let (p1_ref, e_plus_ref) = general.arrival(t0, &q0, &q1, h);
            assert!(
                close(e_plus, e_plus_ref, e_plus.abs()) && close(e_plus, -all.h, e_plus.abs()),
                "{rule:?}: E⁺"
            );
            assert!((p1 - p1_ref).amax() <= 1e-13 * p1.amax() && (p1 - all.q1).amax() <= 1e-13 * p1.amax());
            let block = fast.momentum_block(t0, &q0, &q1, h);
            let block_ref = general.momentum_block(t0, &q0, &q1, h);
            assert!(
                (block - block_ref).amax() <= 1e-13 * block.amax(),
                "{rule:?}: {block} {block_ref}"
            );
            assert!((block - all.q0q1 * h).amax() <= 1e-13 * block.amax());
            let (momentum_w, energy_q1, energy_w) = fast.step_jacobian_along(t0, &q0, &q1, h);
            let (momentum_w_ref, energy_q1_ref, energy_w_ref) = general.step_jacobian_along(t0, &q0, &q1, h);
            assert!(
                (momentum_w - momentum_w_ref).amax() <= 1e-13 * momentum_w.amax(),
                "{rule:?}: ∂²S/∂q₀∂w"
            );
            assert!(
                (energy_q1 - energy_q1_ref).amax() <= 1e-13 * energy_q1.amax(),
                "{rule:?}: ∂E⁻/∂q₁"
            );
            assert!(
                close(energy_w, energy_w_ref, energy_w.abs()),
                "{rule:?}: ∂E⁻/∂w {energy_w} {energy_w_ref}"
            );
            // The time dependence is felt: E⁻ ≠ E⁺ at this segment.
            assert!((e_minus - e_plus).abs() > 1e-3, "{rule:?}");
        }
    }
}
