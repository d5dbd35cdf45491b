//! Split cell Lagrangians on seed 000's triangles △_a^j = ((j,a), (j+1,a),
//! (j,a+1)) (note 000 §12, §15.2):
//!
//! ℒ_d(y₁, y₂, y₃) = ΔsΔt [K(ξ) − Φ(η) − ½(Π(y₁) + Π(y₃))],
//! ξ = τ⁻¹(y₁⁻¹y₂)/Δt, η = τ⁻¹(y₁⁻¹y₃)/Δs (seed 000 eq. (63); the potential
//! averaged over the space edge, see [`SplitLagrangian`]),
//!
//! written once over the AD scalar and generic over the way two vertex values
//! give an increment ([`Increment`]): the difference y₂ − y₁ on ℝ^m (the
//! vector-space case; with quadratic K and Φ the DCEL is the five-point wave
//! scheme), or τ⁻¹(g₁⁻¹g₂) on SE(3) with τ the Cayley map or the exponential
//! ([`GroupIncrement`]). The density ([`SplitDensity`]: K, Φ, Π) is the
//! model's; the increment is the integrator's choice.
//!
//! ℒ_d splits as f(y₁, y₂) + h(y₁, y₃), so ∂ℒ_d/∂y₂ does not depend on y₃
//! nor ∂ℒ_d/∂y₃ on y₂ ([`DiscreteLagrangian::depends`]): the slaved row and
//! column of note 000 §1 are solved node by node.
//!
//! Energies (note 000 §15.1, eqs. (98)–(99); discrete forms defined here):
//! the time-evolution energy density e_𝖫 = ⟨∂K/∂ξ, ξ⟩ − K + Φ + Π and the
//! space-evolution "energy" density e_𝖭 = −⟨∂Φ/∂η, η⟩ − K + Φ + Π, both
//! evaluated at a triangle's (ξ, η) with Π = ½(Π(y₁) + Π(y₃)). E_𝖫(j) = Δs Σ_a e_𝖫(△_a^j) and
//! E_𝖭(a) = Δt Σ_j e_𝖭(△_a^j). For the beam (K = ½⟨𝕁ξ, ξ⟩,
//! Φ = ½⟨ℂ(η − E6), η − E6⟩) e_𝖫 = K + Φ + Π and
//! e_𝖭 = −K − ⟨ℂ(η − E6), E6⟩ − Φ + Π, the note's natural choice.

use std::marker::PhantomData;

use nalgebra::{Const, SMatrix, SVector, U1};
use num_dual::{DualSVec, DualSVec64};

use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::field::cell::DiscreteLagrangian;
use crate::field::fibre::{Euclidean, Fibre, RigidMotions};
use crate::field::legendre::{CauchyOptions, VertexOutcome};
use crate::lie::{LieError, Retraction, SE3};
use crate::solve::SmallLu;
use crate::{Error, Result};

mod diagonal;
mod quadrature;
mod solve;
mod start;

pub use diagonal::DiagonalQuadratic;
pub(crate) use quadrature::CellWeights;
pub use quadrature::KineticQuadrature;

/// How two vertex values give a (dimensionless) increment x with y₂ = y₁·τ(x).
pub trait Increment<F: Fibre<M>, const M: usize>: Send + Sync + 'static {
    /// Short name for messages and outputs (`"difference"`, `"cayley"`, `"exp"`).
    const NAME: &'static str;
    /// x = τ⁻¹(y₁⁻¹y₂) (errors at the cut locus of a rotation part).
    fn increment<D: Scalar>(y1: &F::Point<D>, y2: &F::Point<D>) -> std::result::Result<SVector<D, M>, LieError>;
    /// y₁·τ(x).
    fn advance<D: Scalar>(y1: &F::Point<D>, x: &SVector<D, M>) -> F::Point<D>;
    /// A₁ᵀp with A₁ = ∂x/∂ε₁ the derivative of the increment x in the
    /// fibre's chart y₁·ρ(ε₁) at ε₁ = 0 — a function of x alone (closed
    /// form, for the exact gradients of [`SplitLagrangian`]; the vertex
    /// solve iterates on x).
    fn first_transpose_mul<D: Scalar>(x: &SVector<D, M>, p: &SVector<D, M>) -> SVector<D, M>;
    /// A₂ᵀp with A₂ = ∂x/∂ε₂ in the chart y₂·ρ(ε₂), likewise.
    fn second_transpose_mul<D: Scalar>(x: &SVector<D, M>, p: &SVector<D, M>) -> SVector<D, M>;
    /// ∂(A₁ᵀp)/∂x at fixed p (for the vertex solve's Jacobian).
    fn first_transpose_mul_derivative(x: &SVector<f64, M>, p: &SVector<f64, M>) -> SMatrix<f64, M, M>;
    /// ∂(A₂ᵀp)/∂x at fixed p.
    fn second_transpose_mul_derivative(x: &SVector<f64, M>, p: &SVector<f64, M>) -> SMatrix<f64, M, M>;
    /// Whether [`increment`](Self::increment) reads x back from
    /// [`advance`](Self::advance)`(y₁, x)`.
    fn in_chart(x: &SVector<f64, M>) -> bool;
}

/// The vector-space increment y₂ − y₁ on ℝ^M.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Difference;

impl<const M: usize> Increment<Euclidean<M>, M> for Difference {
    const NAME: &'static str = "difference";
    fn increment<D: Scalar>(y1: &SVector<D, M>, y2: &SVector<D, M>) -> std::result::Result<SVector<D, M>, LieError> {
        Ok(y2 - y1)
    }
    fn advance<D: Scalar>(y1: &SVector<D, M>, x: &SVector<D, M>) -> SVector<D, M> {
        y1 + x
    }
    /// A₁ = −I.
    fn first_transpose_mul<D: Scalar>(_x: &SVector<D, M>, p: &SVector<D, M>) -> SVector<D, M> {
        -p
    }
    /// A₂ = I.
    fn second_transpose_mul<D: Scalar>(_x: &SVector<D, M>, p: &SVector<D, M>) -> SVector<D, M> {
        *p
    }
    /// 0: A₁ is constant.
    fn first_transpose_mul_derivative(_x: &SVector<f64, M>, _p: &SVector<f64, M>) -> SMatrix<f64, M, M> {
        SMatrix::zeros()
    }
    /// 0.
    fn second_transpose_mul_derivative(_x: &SVector<f64, M>, _p: &SVector<f64, M>) -> SMatrix<f64, M, M> {
        SMatrix::zeros()
    }
    /// Always.
    fn in_chart(_x: &SVector<f64, M>) -> bool {
        true
    }
}

/// The group increment τ⁻¹(g₁⁻¹g₂) on SE(3) through the retraction `R`
/// ([`crate::lie::CayleyMap`] or [`crate::lie::ExpMap`]).
pub struct GroupIncrement<R>(PhantomData<fn() -> R>);

impl<R> Increment<RigidMotions, 6> for GroupIncrement<R>
where
    R: Retraction<6, Family = crate::lie::RigidMotions> + 'static,
{
    const NAME: &'static str = "group";
    fn increment<D: Scalar>(g1: &SE3<D>, g2: &SE3<D>) -> std::result::Result<SVector<D, 6>, LieError> {
        R::tau_inv(&g1.between(g2))
    }
    fn advance<D: Scalar>(g1: &SE3<D>, x: &SVector<D, 6>) -> SE3<D> {
        g1.compose(&R::tau(x))
    }
    /// In the charts g·exp(ε) of [`RigidMotions`], with d^Rτ the
    /// right-trivialised derivative ([`Retraction::dtau`]):
    /// exp(−ε₁)τ(x) = τ(x + δ) gives δ = −d^Rτ⁻¹_x ε₁, and τ(x)exp(ε₂) =
    /// τ(x + δ) gives δ = d^Rτ⁻¹_x Ad_{τ(x)} ε₂ = d^Rτ⁻¹_{−x} ε₂: inverting
    /// τ(x + εδ) = τ(ε d^Rτ_x δ)τ(x) gives Ad_{τ(x)} d^Rτ_{−x} = d^Rτ_x for
    /// every retraction with τ(−x) = τ(x)⁻¹, as the exponential and the
    /// Cayley map are. A₁ = −d^Rτ⁻¹_x.
    fn first_transpose_mul<D: Scalar>(x: &SVector<D, 6>, p: &SVector<D, 6>) -> SVector<D, 6> {
        -R::dtau_inv_tr_mul(x, p)
    }
    /// A₂ = d^Rτ⁻¹_{−x}.
    fn second_transpose_mul<D: Scalar>(x: &SVector<D, 6>, p: &SVector<D, 6>) -> SVector<D, 6> {
        R::dtau_inv_tr_mul(&(-x), p)
    }
    fn first_transpose_mul_derivative(x: &SVector<f64, 6>, p: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        -R::dtau_inv_tr_mul_derivative(x, p)
    }
    fn second_transpose_mul_derivative(x: &SVector<f64, 6>, p: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        -R::dtau_inv_tr_mul_derivative(&(-x), p)
    }
    /// τ(x) rotates by less than π − [`crate::lie::CUT_LOCUS_MARGIN`].
    fn in_chart(x: &SVector<f64, 6>) -> bool {
        R::rotation_angle(x) < std::f64::consts::PI - crate::lie::CUT_LOCUS_MARGIN
    }
}

/// The density of a split Lagrangian: kinetic energy K(ξ), stored energy
/// Φ(η) and potential Π(y), each written once over the AD scalar.
pub trait SplitDensity<F: Fibre<M>, const M: usize>: Send + Sync {
    /// K(ξ).
    fn kinetic<D: Scalar>(&self, xi: &SVector<D, M>) -> D;
    /// Φ(η).
    fn stored<D: Scalar>(&self, eta: &SVector<D, M>) -> D;
    /// ∇K(ξ) (default: one dual pass over K).
    fn kinetic_gradient<D: Scalar>(&self, xi: &SVector<D, M>) -> SVector<D, M> {
        scalar_gradient(|x| self.kinetic(x), xi)
    }
    /// ∇Φ(η) (default: one dual pass over Φ).
    fn stored_gradient<D: Scalar>(&self, eta: &SVector<D, M>) -> SVector<D, M> {
        scalar_gradient(|x| self.stored(x), eta)
    }
    /// ∇²K(ξ) (default: one dual pass over ∇K).
    fn kinetic_hessian(&self, xi: &SVector<f64, M>) -> SMatrix<f64, M, M> {
        num_dual::jacobian(|x| self.kinetic_gradient(&x), xi).1
    }
    /// ∇²Φ(η) (default: one dual pass over ∇Φ).
    fn stored_hessian(&self, eta: &SVector<f64, M>) -> SMatrix<f64, M, M> {
        num_dual::jacobian(|x| self.stored_gradient(&x), eta).1
    }
    /// Π(y) (default 0).
    fn potential<D: Scalar>(&self, _y: &F::Point<D>) -> D {
        D::zero()
    }
    /// ∇Π(y) in the fibre's chart y·ρ(ε), at ε = 0 (default: one dual pass
    /// over Π through the chart, [`chart_gradient`]).
    fn potential_gradient<D: Scalar>(&self, y: &F::Point<D>) -> SVector<D, M> {
        chart_gradient::<F, D, M>(|z| self.potential(z), y)
    }
    /// Whether Π may be non-zero (default `true`; `false` lets the exact
    /// gradients skip ∇Π).
    fn has_potential(&self) -> bool {
        true
    }
    /// Whether [`damping`](Self::damping) is non-zero (default `false`).
    fn is_damped(&self) -> bool {
        false
    }
    /// A velocity-dependent force density f(ξ) per unit length, in the
    /// frame of ξ (for example −diag(c)ξ); default 0.
    fn damping<D: Scalar>(&self, _xi: &SVector<D, M>) -> SVector<D, M> {
        SVector::from_element(D::zero())
    }
    /// ∂f/∂ξ (default: one dual pass over f).
    fn damping_jacobian(&self, xi: &SVector<f64, M>) -> SMatrix<f64, M, M> {
        num_dual::jacobian(|x| self.damping(&x), xi).1
    }
    /// Whether [`end_load`](Self::end_load) is non-zero (default `false`).
    fn has_end_load(&self) -> bool {
        false
    }
    /// A load on the last node of a level at time t, in the fibre's chart
    /// at `y` (a generalised force: its pairing with the chart's ε is the
    /// virtual work); applied by the end cell of
    /// [`KineticQuadrature::Trapezoid`]. Default 0.
    fn end_load<D: Scalar>(&self, _y: &F::Point<D>, _t: f64) -> SVector<D, M> {
        SVector::from_element(D::zero())
    }
}

/// ℒ_d = ΔsΔt [K(ξ) − Φ(η) − ½(Π(y₁) + Π(y₃))] on seed 000's triangles.
///
/// The potential is averaged over the cell's space edge (y₁, y₃), the
/// trapezoid rule in s: summed over a level it weighs every node by Δs and
/// the two ends by Δs/2, so a distributed load (gravity) converges at second
/// order in Δs. (Seed 000 (95) evaluates Π at y₁ alone, which lumps each
/// cell's load on its first node: a first-order error in the static
/// deflection, which left the damped cantilever example 13 % short at ten
/// cells.) In time each level carries its own
/// potential, as the discrete mechanics `L_d = h[K − V(q₀)]` does.
pub struct SplitLagrangian<I, S> {
    density: S,
    dt: f64,
    ds: f64,
    quadrature: KineticQuadrature,
    /// The time of the lattice's level 0 (cell row j spans
    /// [t₀ + jΔt, t₀ + (j + 1)Δt]): for time-dependent loads.
    time_origin: f64,
    increment: PhantomData<fn() -> I>,
}

impl<I, S> SplitLagrangian<I, S> {
    /// The discrete Lagrangian of `density` with time step `dt` and space step `ds`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `dt` or `ds` when not finite and positive.
    pub fn new(density: S, dt: f64, ds: f64) -> Result<Self> {
        for (name, h) in [("dt", dt), ("ds", ds)] {
            if !(h.is_finite() && h > 0.0) {
                return Err(Error::InvalidParameter {
                    name: name.into(),
                    value: h.to_string(),
                    reason: "a step must be finite and > 0".into(),
                });
            }
        }
        Ok(Self {
            density,
            dt,
            ds,
            quadrature: KineticQuadrature::FirstNode,
            time_origin: 0.0,
            increment: PhantomData,
        })
    }
    /// The same Lagrangian with the kinetic energy spread over a level by
    /// `quadrature` ([`KineticQuadrature`]; cells are told apart by their
    /// lattice coordinate a, [`TopCell::origin`]`[1]`).
    pub fn with_quadrature(self, quadrature: KineticQuadrature) -> Self {
        Self { quadrature, ..self }
    }
    /// The same Lagrangian with level 0 of the lattice at time `t0`.
    pub fn with_time_origin(self, t0: f64) -> Self {
        Self {
            time_origin: t0,
            ..self
        }
    }
    /// The density.
    pub fn density(&self) -> &S {
        &self.density
    }
    /// Δt.
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// Δs.
    pub fn ds(&self) -> f64 {
        self.ds
    }
    /// The kinetic quadrature.
    pub fn quadrature(&self) -> KineticQuadrature {
        self.quadrature
    }
    /// The time of the lattice's level `j` (t₀ + jΔt).
    pub fn level_time(&self, j: i64) -> f64 {
        self.time_origin + j as f64 * self.dt
    }
}

/// The triangle's jet (ξ, η) = (τ⁻¹(y₁⁻¹y₂)/Δt, τ⁻¹(y₁⁻¹y₃)/Δs).
pub type Jet<D, const M: usize> = (SVector<D, M>, SVector<D, M>);

impl<I, S> SplitLagrangian<I, S> {
    /// ½(Π(y₁) + Π(y₃)), the potential of the cell's space edge.
    pub(crate) fn cell_potential<F: Fibre<M>, D: Scalar, const M: usize>(&self, y: &[F::Point<D>]) -> D
    where
        S: SplitDensity<F, M>,
    {
        (self.density.potential(&y[0]) + self.density.potential(&y[2])) * 0.5
    }

    /// ξ and η of the triangle with vertex values `y` = (y₁, y₂, y₃).
    ///
    /// # Errors
    /// [`LieError::NearCutLocus`] when y₁⁻¹y₂ or y₁⁻¹y₃ rotates by (nearly) π.
    pub fn jet<F: Fibre<M>, D: Scalar, const M: usize>(
        &self,
        y: &[F::Point<D>],
    ) -> std::result::Result<Jet<D, M>, LieError>
    where
        I: Increment<F, M>,
    {
        let (rdt, rds) = (1.0 / self.dt, 1.0 / self.ds);
        let xi = I::increment(&y[0], &y[1])?.map(|x| x * rdt);
        let eta = I::increment(&y[0], &y[2])?.map(|x| x * rds);
        Ok((xi, eta))
    }

    /// The energy densities (e_𝖫, e_𝖭) of the triangle with vertex values `y`
    /// (module documentation), every term at unit weight; NaN at the cut locus.
    pub fn energy_densities<F: Fibre<M>, const M: usize>(&self, y: &[F::Point<f64>]) -> (f64, f64)
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        self.weighted_energy_densities::<F, M>(CellWeights::UNIT, y)
    }

    /// The energy densities of `cell`, its kinetic and stored terms weighed
    /// by the kinetic quadrature ([`KineticQuadrature`]): summed over a
    /// level (and its end cell) they give the level's energy.
    pub fn cell_energy_densities<F: Fibre<M>, const M: usize>(&self, cell: &TopCell, y: &[F::Point<f64>]) -> (f64, f64)
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        self.weighted_energy_densities::<F, M>(self.weights(cell), y)
    }

    fn weighted_energy_densities<F: Fibre<M>, const M: usize>(&self, w: CellWeights, y: &[F::Point<f64>]) -> (f64, f64)
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        let Ok((xi, eta)) = self.jet::<F, f64, M>(y) else {
            return (f64::NAN, f64::NAN);
        };
        let (k, dk) = (self.density.kinetic(&xi), self.density.kinetic_gradient(&xi));
        let (phi, dphi) = (self.density.stored(&eta), self.density.stored_gradient(&eta));
        let pi = self.cell_potential::<F, f64, M>(y);
        let kinetic = (dk.dot(&xi) - k, -k);
        let stored = (phi + pi, -dphi.dot(&eta) + phi + pi);
        (
            w.kinetic * kinetic.0 + w.stored * stored.0,
            w.kinetic * kinetic.1 + w.stored * stored.1,
        )
    }
}

impl<I, S> SplitLagrangian<I, S> {
    /// The exact gradients (∂ℒ/∂y₁, ∂ℒ/∂y₂, ∂ℒ/∂y₃) over any scalar, from
    /// the increments' derivatives ([`Increment::first_transpose_mul`], [`Increment::second_transpose_mul`]:
    /// x_t = Δtξ and x_s = Δsη with A₁, A₂ each) and ∇K(ξ), ∇Φ(η), ∇Π(y)
    /// (dual passes over the density alone):
    ///
    /// * ∂ℒ/∂y₁ = ΔsA₁,ₜᵀ∇K − ΔtA₁,ₛᵀ∇Φ − ½ΔsΔt∇Π(y₁)
    /// * ∂ℒ/∂y₂ = ΔsA₂,ₜᵀ∇K
    /// * ∂ℒ/∂y₃ = −ΔtA₂,ₛᵀ∇Φ − ½ΔsΔt∇Π(y₃)
    ///
    /// `None` at the cut locus or unless `y` holds the triangle's three values.
    pub fn closed_gradients<F: Fibre<M>, D: Scalar, const M: usize>(
        &self,
        y: &[F::Point<D>],
    ) -> Option<[SVector<D, M>; 3]>
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        self.weighted_gradients::<F, D, M>(CellWeights::UNIT, y)
    }

    /// [`closed_gradients`](Self::closed_gradients) with the kinetic and
    /// stored terms weighed by `w`.
    pub(crate) fn weighted_gradients<F: Fibre<M>, D: Scalar, const M: usize>(
        &self,
        w: CellWeights,
        y: &[F::Point<D>],
    ) -> Option<[SVector<D, M>; 3]>
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        if y.len() != 3 {
            return None;
        }
        let (xt, pt) = self.time_edge::<F, D, M>(w, &y[0], &y[1])?;
        let mut first = I::first_transpose_mul(&xt, &pt);
        let second = I::second_transpose_mul(&xt, &pt);
        let mut third = SVector::from_element(D::zero());
        if w.stored != 0.0 {
            let (xs, ps) = self.space_edge::<F, D, M>(w, &y[0], &y[2])?;
            first += I::first_transpose_mul(&xs, &ps);
            third = I::second_transpose_mul(&xs, &ps);
            if self.density.has_potential() {
                let half = D::from(0.5 * self.ds * self.dt * w.stored);
                first -= self.potential_gradient::<F, D, M>(&y[0]) * half;
                third -= self.potential_gradient::<F, D, M>(&y[2]) * half;
            }
        }
        Some([first, second, third])
    }

    /// The time edge (y₁, y₂): its increment x = τ⁻¹(y₁⁻¹y₂) and the momentum
    /// p = Δs∇K(x/Δt) whose pull-backs A₁,ₜᵀp and A₂,ₜᵀp are its terms of
    /// ∂ℒ/∂y₁ and ∂ℒ/∂y₂ (each caller pulls back only the one it needs).
    pub(crate) fn time_edge<F: Fibre<M>, D: Scalar, const M: usize>(
        &self,
        w: CellWeights,
        y1: &F::Point<D>,
        y2: &F::Point<D>,
    ) -> Option<(SVector<D, M>, SVector<D, M>)>
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        let x = I::increment(y1, y2).ok()?;
        let dk = self
            .density
            .kinetic_gradient(&x.map(|v| v * (1.0 / self.dt)))
            .map(|v| v * (self.ds * w.kinetic));
        Some((x, dk))
    }

    /// The space edge (y₁, y₃): its increment x and the momentum
    /// p = −Δt∇Φ(x/Δs), pulled back by A₁,ₛᵀ and A₂,ₛᵀ into ∂ℒ/∂y₁ and
    /// ∂ℒ/∂y₃.
    pub(crate) fn space_edge<F: Fibre<M>, D: Scalar, const M: usize>(
        &self,
        w: CellWeights,
        y1: &F::Point<D>,
        y3: &F::Point<D>,
    ) -> Option<(SVector<D, M>, SVector<D, M>)>
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        let x = I::increment(y1, y3).ok()?;
        let dphi = self
            .density
            .stored_gradient(&x.map(|v| v * (1.0 / self.ds)))
            .map(|v| -(v * (self.dt * w.stored)));
        Some((x, dphi))
    }

    /// ∂ℒ/∂y_l alone, from the one edge it needs for l = 1 (time) and
    /// l = 2 (space): the bits of [`closed_gradients`](Self::closed_gradients).
    fn closed_gradient<F: Fibre<M>, const M: usize>(
        &self,
        w: CellWeights,
        y: &[F::Point<f64>],
        l: usize,
    ) -> Option<SVector<f64, M>>
    where
        I: Increment<F, M>,
        S: SplitDensity<F, M>,
    {
        match l {
            1 => {
                let (x, p) = self.time_edge::<F, f64, M>(w, &y[0], &y[1])?;
                Some(I::second_transpose_mul(&x, &p))
            }
            2 if w.stored == 0.0 => Some(SVector::zeros()),
            2 => {
                let (x, p) = self.space_edge::<F, f64, M>(w, &y[0], &y[2])?;
                let mut third = I::second_transpose_mul(&x, &p);
                if self.density.has_potential() {
                    third -= self.potential_gradient::<F, f64, M>(&y[2]) * (0.5 * self.ds * self.dt * w.stored);
                }
                Some(third)
            }
            _ => Some(self.weighted_gradients::<F, f64, M>(w, y)?[0]),
        }
    }

    /// The end load's force on vertex `l` (0 or 1) of an end cell: the
    /// trapezoid rule of the virtual work over the time step,
    /// F¹ = ½Δt f(y₁, t_j), F² = ½Δt f(y₂, t_{j+1}).
    pub(crate) fn end_force<F: Fibre<M>, D: Scalar, const M: usize>(
        &self,
        cell: &TopCell,
        y: &F::Point<D>,
        l: usize,
    ) -> SVector<D, M>
    where
        S: SplitDensity<F, M>,
    {
        let t = self.level_time(cell.origin[0] + l as i64);
        self.density.end_load(y, t).map(|f| f * (0.5 * self.dt))
    }

    /// ∇Π(y) in the fibre's chart y·ρ(ε) ([`SplitDensity::potential_gradient`]).
    fn potential_gradient<F: Fibre<M>, D: Scalar, const M: usize>(&self, y: &F::Point<D>) -> SVector<D, M>
    where
        S: SplitDensity<F, M>,
    {
        self.density.potential_gradient(y)
    }
}

/// The gradient of a function f of the fibre's points in the chart
/// y·ρ(ε) at ε = 0, ∂f(y·ρ(ε))/∂ε, by one dual pass of M directions (over
/// any scalar).
pub fn chart_gradient<F: Fibre<M>, D: Scalar, const M: usize>(
    f: impl Fn(&F::Point<DualSVec<D, M>>) -> DualSVec<D, M>,
    y: &F::Point<D>,
) -> SVector<D, M> {
    let seeded = SVector::<DualSVec<D, M>, M>::from_fn(|i, _| DualSVec::<D, M>::from_re(D::zero()).derivative(i));
    let lifted = F::map(y, DualSVec::<D, M>::from_re);
    f(&F::retract(&lifted, &seeded)).eps.unwrap_generic(Const::<M>, U1)
}

/// ∇f(x) over any scalar by one dual pass of M directions.
fn scalar_gradient<D: Scalar, const M: usize>(
    f: impl Fn(&SVector<DualSVec<D, M>, M>) -> DualSVec<D, M>,
    x: &SVector<D, M>,
) -> SVector<D, M> {
    let seeded = SVector::<DualSVec<D, M>, M>::from_fn(|i, _| DualSVec::<D, M>::from_re(x[i]).derivative(i));
    f(&seeded).eps.unwrap_generic(Const::<M>, U1)
}

impl<F, I, S, const M: usize> DiscreteLagrangian<F, M> for SplitLagrangian<I, S>
where
    F: Fibre<M>,
    I: Increment<F, M>,
    S: SplitDensity<F, M>,
{
    /// ΔsΔt [K(ξ) − Φ(η) − ½(Π(y₁) + Π(y₃))]; NaN at the cut locus (the vertex solves
    /// report it as a non-finite residual).
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[F::Point<D>]) -> D {
        let w = self.weights(cell);
        if w.stored == 0.0 {
            // The end cell: its kinetic term alone.
            return match I::increment(&y[0], &y[1]) {
                Ok(x) => self.density.kinetic(&x.map(|v| v * (1.0 / self.dt))) * (self.ds * self.dt * w.kinetic),
                Err(_) => D::from(f64::NAN),
            };
        }
        match self.jet::<F, D, M>(y) {
            Ok((xi, eta)) => {
                (self.density.kinetic(&xi) * w.kinetic
                    - (self.density.stored(&eta) + self.cell_potential::<F, D, M>(y)) * w.stored)
                    * (self.ds * self.dt)
            }
            Err(_) => D::from(f64::NAN),
        }
    }
    /// The exact gradients in closed form ([`SplitLagrangian::closed_gradients`]).
    fn analytic_gradients(&self, cell: &TopCell, y: &[F::Point<f64>], out: &mut [SVector<f64, M>]) -> bool {
        if y.len() != 3 || out.len() < 3 {
            return false;
        }
        match self.weighted_gradients::<F, f64, M>(self.weights(cell), y) {
            Some(g) => out[..3].copy_from_slice(&g),
            None => out[..3].fill(SVector::from_element(f64::NAN)),
        }
        true
    }
    /// ∂ℒ/∂y_l from the edges it needs ([`SplitLagrangian::closed_gradients`]'s
    /// bits; NaN at the cut locus).
    fn analytic_gradient(&self, cell: &TopCell, y: &[F::Point<f64>], l: usize) -> Option<SVector<f64, M>> {
        if y.len() != 3 || l > 2 {
            return None;
        }
        Some(
            self.closed_gradient::<F, M>(self.weights(cell), y, l)
                .unwrap_or(SVector::from_element(f64::NAN)),
        )
    }
    /// ∂ℒ/∂y_a and its derivative in y_b by one first-order dual pass of
    /// M directions over the closed-form gradients, y_b·exp(ζ) seeded.
    fn analytic_block(
        &self,
        cell: &TopCell,
        y: &[F::Point<f64>],
        a: usize,
        b: usize,
    ) -> Option<(SVector<f64, M>, SMatrix<f64, M, M>)> {
        if y.len() != 3 || a > 2 || b > 2 {
            return None;
        }
        let seeds = SVector::<DualSVec64<M>, M>::from_fn(|i, _| DualSVec64::<M>::from_re(0.0).derivative(i));
        let values: [F::Point<DualSVec64<M>>; 3] = std::array::from_fn(|l| {
            if l == b {
                F::retract_seeded(&y[l], &seeds)
            } else {
                F::lift(&y[l])
            }
        });
        let Some(g) = self.weighted_gradients::<F, DualSVec64<M>, M>(self.weights(cell), &values) else {
            return Some((SVector::from_element(f64::NAN), SMatrix::from_element(f64::NAN)));
        };
        let ga = &g[a];
        Some((
            ga.map(|x| x.re),
            SMatrix::from_fn(|i, j| ga[i].eps.unwrap_generic(Const::<M>, U1)[j]),
        ))
    }
    /// The flow step in the moving increment alone
    /// (`SplitLagrangian::solve_increment`).
    #[allow(clippy::too_many_arguments)]
    fn solve_cell_vertex(
        &self,
        cell: &TopCell,
        y: &[F::Point<f64>],
        equation: usize,
        position: usize,
        mu: &SVector<f64, M>,
        mu_scale: f64,
        options: &CauchyOptions,
        kept: &mut Option<SmallLu<M>>,
    ) -> Option<(F::Point<f64>, VertexOutcome)> {
        self.solve_increment::<F, M>(cell, y, equation, position, mu, mu_scale, options, kept)
    }
    /// ∂ℒ/∂y₂ does not depend on y₃ nor ∂ℒ/∂y₃ on y₂; in the end cell
    /// nothing depends on y₃.
    fn depends(&self, cell: &TopCell, l: usize, k: usize) -> bool {
        if self.weights(cell).stored == 0.0 && (l == 2 || k == 2) {
            return false;
        }
        !matches!((l, k), (1, 2) | (2, 1))
    }
    fn has_forces(&self) -> bool {
        self.density.is_damped() || (self.density.has_end_load() && self.quadrature != KineticQuadrature::FirstNode)
    }
    /// The Lagrange–d'Alembert discretisation of the force density f(ξ)
    /// over the cell's rectangle, split between the two ends of its time
    /// edge: F¹ = F² = ½ΔsΔt f(ξ), F³ = 0 (the discrete forces f⁻ = f⁺ =
    /// (h/2) f of discrete mechanics; on SE(3) both in the body frame of ξ,
    /// an O(Δt) choice of transport at vertex 2). With f = −Cξ, C ≥ 0, it
    /// dissipates E_𝖫 (tested).
    ///
    /// The damping is weighed as the kinetic energy; the end cell of a
    /// trapezoid rule adds the end load ([`SplitDensity::end_load`]).
    fn cell_force<D: Scalar>(&self, cell: &TopCell, y: &[F::Point<D>], l: usize) -> SVector<D, M> {
        if l == 2 {
            return SVector::from_element(D::zero());
        }
        let w = self.weights(cell);
        let mut force = SVector::from_element(D::zero());
        if self.density.is_damped() {
            force = match I::increment(&y[0], &y[1]) {
                Ok(x) => {
                    let xi = x.map(|v| v * (1.0 / self.dt));
                    self.density
                        .damping(&xi)
                        .map(|f| f * (0.5 * self.ds * self.dt * w.kinetic))
                }
                Err(_) => SVector::from_element(D::from(f64::NAN)),
            };
        }
        if w.end && self.density.has_end_load() {
            force += self.end_force::<F, D, M>(cell, &y[l], l);
        }
        force
    }
}
