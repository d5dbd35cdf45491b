//! The extended discrete Lagrangian of the symplectic-energy-momentum (SEM)
//! integrators on `x = (t, q)` (seed 001 §3; note 001 §1, §2.4):
//!
//! `S(t₀, q₀, q₁, h) = h Σᵢ bᵢ L(t₀ + cᵢh, (1 − cᵢ)q₀ + cᵢq₁, (q₁ − q₀)/h)`, `t₁ = t₀ + h`,
//!
//! i.e. `(t₁ − t₀)·𝕃` with `𝕃` a quadrature of `L` along the straight segment.
//! The rules: left point (the paper's (3.18): `c = 0`), midpoint (`c = ½`),
//! trapezoid (`c = 0, 1`) and the Lee-type average (Gauss–Legendre nodes; for
//! `L = ½vᵀMv − V` it averages `V` along the segment).
//!
//! Momenta and energies (note 001 §2.1): `p_k = −∂S/∂q₀`, `p_{k+1} = ∂S/∂q₁`,
//! `E⁻_k = ∂S/∂t₀|_{t₁} = S_{t₀} − S_h` (leaving), `E⁺_{k+1} = −∂S/∂t₁ = −S_h`
//! (arriving); autonomous `L`: `E⁻ = E⁺ = E_d = −∂S/∂h`.

use nalgebra::{SMatrix, SVector, Vector2};
use num_dual::{
    Dual2SVec64, Dual64, DualSVec64, HyperDual64, HyperDualSVec64, first_derivative, gradient, partial_hessian,
    second_partial_derivative,
};

use super::separable;
use crate::ad::{Scalar, lift};
use crate::error::{Error, Result};
use crate::mechanics::Lagrangian;
use crate::tableau;

/// Which quadrature of `L` along the segment defines `𝕃`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SemRule {
    /// `𝕃 = L(q₀, v)`: the paper's (3.18), with its energy equation (3.21).
    ///
    /// What it can do (note 001 §2.7, §3.3; the tests of
    /// `tests/mechanics/sem_left_point.rs`): away from turning points it is
    /// first order (Kepler e = 0.1 started at t = 1: the error at t = 2.5 is
    /// 2.4e-2, 1.2e-2, 6.2e-3, 3.1e-3 for h₀ = 0.02 … 0.0025), and its
    /// consistent branch (h_k/h_{k−1} → 1) cannot pass the next turning
    /// point of r, where the energy equation's leading coefficient
    /// c = −pᵀM⁻¹∇V crosses zero: the run fails there (at the apocentre,
    /// t ≈ π). Started at a turning point it follows the other branch, whose
    /// steps grow like the time since that point, h_k ≈ κ·t_k with κ = 0.154,
    /// 0.479, 0.823 at e = 0.1, 0.3, 0.5 whatever h₀, so its error does not
    /// shrink with h₀ ([`crate::sem::StartExpansion`] detects such a start).
    /// The symmetric rules have no such degeneracy at turning points.
    LeftPoint,
    /// `𝕃 = L((q₀+q₁)/2, v)`: second order, the default.
    Midpoint,
    /// `𝕃 = ½[L(q₀, v) + L(q₁, v)]`: second order.
    Trapezoid,
    /// `𝕃 = Σ bᵢ L(q₀ + cᵢ(q₁ − q₀), v)` with `s` Gauss–Legendre nodes (Lee-type average).
    Averaged(usize),
}

impl SemRule {
    /// Scenario name.
    pub fn name(&self) -> &'static str {
        match self {
            SemRule::LeftPoint => "sem-leftpoint",
            SemRule::Midpoint => "sem-midpoint",
            SemRule::Trapezoid => "sem-trapezoid",
            SemRule::Averaged(_) => "sem-averaged",
        }
    }
    /// Whether `S(x₁, x₀) = −S(x₀, x₁)`: then the backward step `h = −h_{k−1}` always solves the step equations.
    pub fn is_symmetric(&self) -> bool {
        !matches!(self, SemRule::LeftPoint)
    }

    /// The order of the integrator in the first step `h₀` (the later steps
    /// scale with it): 2 for the symmetric rules, 1 for the left point.
    pub fn order(&self) -> usize {
        if self.is_symmetric() { 2 } else { 1 }
    }
}

/// All first and second derivatives of `S` needed by the SEM step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActionDerivatives<const N: usize> {
    /// `S`.
    pub value: f64,
    /// `∂S/∂q₀`.
    pub q0: SVector<f64, N>,
    /// `∂S/∂q₁`.
    pub q1: SVector<f64, N>,
    /// `∂S/∂t₀` at fixed `h`.
    pub t0: f64,
    /// `∂S/∂h` at fixed `t₀`.
    pub h: f64,
    /// `∂²S/∂q₀∂q₁`.
    pub q0q1: SMatrix<f64, N, N>,
    /// `∂²S/∂q₀∂h`.
    pub q0h: SVector<f64, N>,
    /// `∂²S/∂q₀∂t₀`.
    pub q0t0: SVector<f64, N>,
    /// `∂²S/∂q₁∂h`.
    pub q1h: SVector<f64, N>,
    /// `∂²S/∂q₁∂t₀`.
    pub q1t0: SVector<f64, N>,
    /// `∂²S/∂h²`.
    pub hh: f64,
    /// `∂²S/∂t₀∂h`.
    pub t0h: f64,
}

/// The SEM action `S` of a Lagrangian with a quadrature rule.
///
/// For a Lagrangian of the form `½ vᵀMv − V(t, q)`
/// ([`Lagrangian::constant_mass`]) the step's passes (`leaving`, `arrival`,
/// `step_jacobian_along`, `momentum_block`) use closed forms that evaluate
/// only `V` and its derivatives at the rule's nodes (module `separable`);
/// they agree with the general passes over the whole action to round-off
/// (tested). [`SemAction::derivatives`] and
/// [`SemAction::momentum_derivatives`] always take the general passes.
#[derive(Debug, Clone, PartialEq)]
pub struct SemAction<L, const N: usize> {
    lagrangian: L,
    rule: SemRule,
    nodes: Vec<f64>,
    weights: Vec<f64>,
    mass: Option<SMatrix<f64, N, N>>,
}

impl<L: Lagrangian<N>, const N: usize> SemAction<L, N> {
    /// The action of `lagrangian` with `rule`.
    pub fn new(lagrangian: L, rule: SemRule) -> Result<Self> {
        let (nodes, weights) = match rule {
            SemRule::LeftPoint => (vec![0.0], vec![1.0]),
            SemRule::Midpoint => (vec![0.5], vec![1.0]),
            SemRule::Trapezoid => (vec![0.0, 1.0], vec![0.5, 0.5]),
            SemRule::Averaged(s) => {
                let q = tableau::gauss_legendre(s).map_err(|e| Error::InvalidParameter {
                    name: "nodes".into(),
                    value: s.to_string(),
                    reason: e.to_string(),
                })?;
                (q.nodes, q.weights)
            }
        };
        let mass = lagrangian.constant_mass();
        Ok(Self {
            lagrangian,
            rule,
            nodes,
            weights,
            mass,
        })
    }

    /// The rule.
    pub fn rule(&self) -> SemRule {
        self.rule
    }
    /// The Lagrangian.
    pub fn lagrangian(&self) -> &L {
        &self.lagrangian
    }

    /// `S(t₀, q₀, q₁, h)` over any scalar.
    pub fn action<D: Scalar>(&self, t0: D, q0: &SVector<D, N>, q1: &SVector<D, N>, h: D) -> D {
        let v = (q1 - q0) / h;
        let mut s = D::from(0.0);
        for (&c, &b) in self.nodes.iter().zip(&self.weights) {
            let x = q0 * D::from(1.0 - c) + q1 * D::from(c);
            s += self.lagrangian.lagrangian(t0 + h * c, &x, &v) * b;
        }
        s * h
    }

    /// Value and derivatives of `S`, exact (four forward-mode passes).
    pub fn derivatives(&self, t0: f64, q0: &SVector<f64, N>, q1: &SVector<f64, N>, h: f64) -> ActionDerivatives<N> {
        let th = Vector2::new(t0, h);
        let (value, s_q0, s_q1, q0q1) = partial_hessian(
            |(a, b): (SVector<HyperDualSVec64<N, N>, N>, SVector<HyperDualSVec64<N, N>, N>)| {
                self.action(HyperDualSVec64::from(t0), &a, &b, HyperDualSVec64::from(h))
            },
            (q0, q1),
        );
        let (_, _, _, q0th) = partial_hessian(
            |(a, y): (SVector<HyperDualSVec64<N, 2>, N>, SVector<HyperDualSVec64<N, 2>, 2>)| {
                self.action(y[0], &a, &lift(q1), y[1])
            },
            (q0, &th),
        );
        let (_, _, _, q1th) = partial_hessian(
            |(b, y): (SVector<HyperDualSVec64<N, 2>, N>, SVector<HyperDualSVec64<N, 2>, 2>)| {
                self.action(y[0], &lift(q0), &b, y[1])
            },
            (q1, &th),
        );
        let (_, g, hess) = num_dual::hessian(
            |y: SVector<Dual2SVec64<2>, 2>| self.action(y[0], &lift(q0), &lift(q1), y[1]),
            &th,
        );
        ActionDerivatives {
            value,
            q0: s_q0,
            q1: s_q1,
            t0: g[0],
            h: g[1],
            q0q1,
            q0h: q0th.column(1).into_owned(),
            q0t0: q0th.column(0).into_owned(),
            q1h: q1th.column(1).into_owned(),
            q1t0: q1th.column(0).into_owned(),
            hh: hess[(1, 1)],
            t0h: hess[(0, 1)],
        }
    }

    /// `S`, the leaving momentum `∂S/∂q₀` and the leaving energy
    /// `E⁻ = ∂S/∂t₀ − ∂S/∂h`: the ingredients of the step residual (note 001
    /// §2.2; seed 001 (3.3)–(3.4)).
    ///
    /// Two first-order passes: a gradient in `q₀` and one directional
    /// derivative along `(δt₀, δh) = (1, −1)`, which is `E⁻` itself (for
    /// `L = ½ vᵀMv − V`: a gradient and a time-derivative pass over `V` per node).
    pub fn leaving(&self, t0: f64, q0: &SVector<f64, N>, q1: &SVector<f64, N>, h: f64) -> (f64, SVector<f64, N>, f64) {
        if let Some(mass) = &self.mass {
            return self.segment(mass, t0, q0, q1, h).leaving();
        }
        let (value, s_q0) = gradient(
            |a: SVector<DualSVec64<N>, N>| self.action(DualSVec64::from(t0), &a, &lift(q1), DualSVec64::from(h)),
            q0,
        );
        let (_, e_minus) = first_derivative(
            |x: Dual64| self.action(Dual64::from(t0) + x, &lift(q0), &lift(q1), Dual64::from(h) - x),
            0.0,
        );
        (value, s_q0, e_minus)
    }

    /// The second derivatives of the step Jacobian that move along a run, in
    /// the direction `w = (δq₁, δh) = (v̄, 1)` (a longer step at the same mean
    /// velocity `v̄ = (q₁ − q₀)/h`): `∂²S/∂q₀∂w`, `∂E⁻/∂q₁` and `∂E⁻/∂w`, with
    /// `E⁻ = (∂_{t₀} − ∂_h)S` (three small passes; for `L = ½ vᵀMv − V`,
    /// two passes over `V` per node). With `h ∂²S/∂q₀∂q₁`
    /// ([`SemAction::momentum_block`]) they make the Jacobian of the
    /// step residual `(p + ∂S/∂q₀, E⁻ − E)` in the unknowns `(v̄, u = h²)`.
    pub fn step_jacobian_along(
        &self,
        t0: f64,
        q0: &SVector<f64, N>,
        q1: &SVector<f64, N>,
        h: f64,
    ) -> (SVector<f64, N>, SVector<f64, N>, f64) {
        if let Some(mass) = &self.mass {
            return self.segment(mass, t0, q0, q1, h).jacobian_along();
        }
        let vbar = (q1 - q0) / h;
        let zero = nalgebra::Vector1::new(0.0);
        let (_, _, _, momentum_w) = partial_hessian(
            |(a, x): (SVector<HyperDualSVec64<N, 1>, N>, SVector<HyperDualSVec64<N, 1>, 1>)| {
                let b = lift::<HyperDualSVec64<N, 1>, N>(q1) + lift::<HyperDualSVec64<N, 1>, N>(&vbar) * x[0];
                self.action(HyperDualSVec64::from(t0), &a, &b, HyperDualSVec64::from(h) + x[0])
            },
            (q0, &zero),
        );
        let (_, _, _, energy_q1) = partial_hessian(
            |(b, x): (SVector<HyperDualSVec64<N, 1>, N>, SVector<HyperDualSVec64<N, 1>, 1>)| {
                self.action(
                    HyperDualSVec64::from(t0) + x[0],
                    &lift(q0),
                    &b,
                    HyperDualSVec64::from(h) - x[0],
                )
            },
            (q1, &zero),
        );
        let (_, _, _, energy_w) = second_partial_derivative(
            |(x, y): (HyperDual64, HyperDual64)| {
                let b = lift::<HyperDual64, N>(q1) + lift::<HyperDual64, N>(&vbar) * y;
                self.action(HyperDual64::from(t0) + x, &lift(q0), &b, HyperDual64::from(h) - x + y)
            },
            (0.0, 0.0),
        );
        (
            momentum_w.column(0).into_owned(),
            energy_q1.column(0).into_owned(),
            energy_w,
        )
    }

    /// The leaving momentum `∂S/∂q₀` alone (one gradient pass).
    pub fn leaving_momentum(&self, t0: f64, q0: &SVector<f64, N>, q1: &SVector<f64, N>, h: f64) -> SVector<f64, N> {
        if let Some(mass) = &self.mass {
            return self.segment(mass, t0, q0, q1, h).leaving_momentum();
        }
        gradient(
            |a: SVector<DualSVec64<N>, N>| self.action(DualSVec64::from(t0), &a, &lift(q1), DualSVec64::from(h)),
            q0,
        )
        .1
    }

    /// The arrival momentum and energy `(p₁, E⁺₁) = (∂S/∂q₁, −∂S/∂h)`: a
    /// gradient in `q₁` and a derivative in `h` (two first-order passes).
    pub fn arrival(&self, t0: f64, q0: &SVector<f64, N>, q1: &SVector<f64, N>, h: f64) -> (SVector<f64, N>, f64) {
        if let Some(mass) = &self.mass {
            return self.segment(mass, t0, q0, q1, h).arrival();
        }
        let (_, s_q1) = gradient(
            |b: SVector<DualSVec64<N>, N>| self.action(DualSVec64::from(t0), &lift(q0), &b, DualSVec64::from(h)),
            q1,
        );
        let (_, s_h) = first_derivative(
            |x: Dual64| self.action(Dual64::from(t0), &lift(q0), &lift(q1), Dual64::from(h) + x),
            0.0,
        );
        (s_q1, -s_h)
    }

    /// `S`, `∂S/∂q₀`, `∂S/∂q₁` and `∂²S/∂q₀∂q₁` only (one pass): the fixed-step solve.
    pub fn momentum_derivatives(
        &self,
        t0: f64,
        q0: &SVector<f64, N>,
        q1: &SVector<f64, N>,
        h: f64,
    ) -> (f64, SVector<f64, N>, SVector<f64, N>, SMatrix<f64, N, N>) {
        partial_hessian(
            |(a, b): (SVector<HyperDualSVec64<N, N>, N>, SVector<HyperDualSVec64<N, N>, N>)| {
                self.action(HyperDualSVec64::from(t0), &a, &b, HyperDualSVec64::from(h))
            },
            (q0, q1),
        )
    }

    /// The momentum block of the step Jacobian, `h ∂²S/∂q₀∂q₁` (`= −M + O(h²)`):
    /// for `L = ½ vᵀMv − V` the closed form `−M − h² Σᵢ bᵢcᵢ(1 − cᵢ)∇²V(xᵢ)`
    /// (one second-order pass over `V` per node), else one hyper-dual pass over `S`.
    pub fn momentum_block(&self, t0: f64, q0: &SVector<f64, N>, q1: &SVector<f64, N>, h: f64) -> SMatrix<f64, N, N> {
        match &self.mass {
            Some(mass) => self.segment(mass, t0, q0, q1, h).momentum_block(),
            None => self.momentum_derivatives(t0, q0, q1, h).3 * h,
        }
    }

    /// The segment `(t₀, q₀) → (t₀ + h, q₁)` of a Lagrangian with constant mass `mass`.
    fn segment<'a>(
        &'a self,
        mass: &'a SMatrix<f64, N, N>,
        t0: f64,
        q0: &'a SVector<f64, N>,
        q1: &'a SVector<f64, N>,
        h: f64,
    ) -> separable::Segment<'a, L, N> {
        separable::Segment {
            lagrangian: &self.lagrangian,
            mass,
            nodes: &self.nodes,
            weights: &self.weights,
            t0,
            q0,
            q1,
            h,
        }
    }
}
