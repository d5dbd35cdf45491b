//! Galley duplication: a forced system `(L, F)` on `Qᴺ` as a free Lagrangian
//! system on `Qᴺ × Qᴺ` (seed 004 §4, note 004 §1.5).
//!
//! `𝐋_K(q, v, Q, V) = L(Q, V) − L(q, v) − K̃_F`, with the forcing potential
//! `K̃_F = ½⟨F(Q, V), τ(Q, q)⟩ − ½⟨F(q, v), τ(q, Q)⟩`, where `τ(q, Q)` is the
//! local inverse of a retraction (flat case `τ(q, Q) = Q − q`, so that
//! `K̃_F = ½(F(q, v) + F(Q, V))·(q − Q)`).
//!
//! Sign convention: the **second copy `Q` carries `+L`** and is the physical
//! one; the duplicated coordinates are ordered `(q, Q)`. Under the swap
//! `(q, v) ↔ (Q, V)` the duplicated Lagrangian changes sign, so the diagonal
//! `q = Q` is invariant under the continuous and discrete flows; on it the
//! `Q`-equation is the forced Euler–Lagrange equation. Diagonal initial data:
//! `(q, Q) = (q₀, q₀)`, `(p_q, p_Q) = (−p₀, p₀)`.

use nalgebra::SVector;

use super::force::Force;
use super::lagrangian::Lagrangian;
use super::state::PhaseState;
use crate::ad::Scalar;
use crate::error::{Error, Result};

/// The local inverse `τ(q, Q)` of a retraction `R_q(v) = Q` (Def. 3.3, Lemma 3.4:
/// `τ(q, q) = 0`, `∂τ/∂q = −I`, `∂τ/∂Q = +I` at `Q = q`).
pub trait InverseRetraction<const N: usize> {
    /// `τ(q, Q)`.
    fn tau<D: Scalar>(&self, q: &SVector<D, N>, target: &SVector<D, N>) -> SVector<D, N>;
}

/// The flat retraction of `Rⁿ`: `τ(q, Q) = Q − q`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FlatRetraction;

impl<const N: usize> InverseRetraction<N> for FlatRetraction {
    fn tau<D: Scalar>(&self, q: &SVector<D, N>, target: &SVector<D, N>) -> SVector<D, N> {
        target - q
    }
}

/// The duplicated Lagrangian on `R^M`, `M = 2N`, coordinates `(q, Q)`.
#[derive(Debug, Clone, PartialEq)]
pub struct DuplicatedLagrangian<L, F, R, const N: usize, const M: usize> {
    lagrangian: L,
    force: F,
    retraction: R,
}

impl<L: Lagrangian<N>, F: Force<N>, const N: usize, const M: usize> DuplicatedLagrangian<L, F, FlatRetraction, N, M> {
    /// Duplicate `(L, F)` with the flat retraction; `M` must equal `2N`.
    pub fn new(lagrangian: L, force: F) -> Result<Self> {
        Self::with_retraction(lagrangian, force, FlatRetraction)
    }
}

impl<L: Lagrangian<N>, F: Force<N>, R: InverseRetraction<N>, const N: usize, const M: usize>
    DuplicatedLagrangian<L, F, R, N, M>
{
    /// Duplicate `(L, F)` with the retraction inverse `τ`; `M` must equal `2N`.
    pub fn with_retraction(lagrangian: L, force: F, retraction: R) -> Result<Self> {
        if M != 2 * N {
            return Err(Error::DimensionMismatch {
                what: "duplicated dimension M (must be 2N)".into(),
                expected: 2 * N,
                got: M,
            });
        }
        Ok(Self {
            lagrangian,
            force,
            retraction,
        })
    }

    /// Split a duplicated vector into its copies `(q, Q)`.
    pub fn split<D: Scalar>(x: &SVector<D, M>) -> (SVector<D, N>, SVector<D, N>) {
        (SVector::from_fn(|i, _| x[i]), SVector::from_fn(|i, _| x[N + i]))
    }

    /// Join two copies into a duplicated vector `(q, Q)`.
    pub fn join<D: Scalar>(q: &SVector<D, N>, target: &SVector<D, N>) -> SVector<D, M> {
        SVector::from_fn(|i, _| if i < N { q[i] } else { target[i - N] })
    }

    /// The swap `ι̃`: `(q, Q) ↦ (Q, q)`.
    pub fn swap<D: Scalar>(x: &SVector<D, M>) -> SVector<D, M> {
        let (a, b) = Self::split(x);
        Self::join(&b, &a)
    }

    /// Diagonal initial data for a physical state `(q₀, p₀)`: `(q₀, q₀; −p₀, p₀)`.
    pub fn diagonal_state(x: &PhaseState<N>) -> PhaseState<M> {
        PhaseState::new(x.t, Self::join(&x.q, &x.q), Self::join(&(-x.p), &x.p))
    }

    /// The forcing potential `K̃_F(q, v, Q, V)`.
    pub fn forcing_potential<D: Scalar>(
        &self,
        t: D,
        q: &SVector<D, N>,
        v: &SVector<D, N>,
        target: &SVector<D, N>,
        vt: &SVector<D, N>,
    ) -> D {
        let f_second = self.force.force(t, target, vt);
        let f_first = self.force.force(t, q, v);
        (f_second.dot(&self.retraction.tau(target, q)) - f_first.dot(&self.retraction.tau(q, target))) * 0.5
    }
}

impl<L: Lagrangian<N>, F: Force<N>, R: InverseRetraction<N>, const N: usize, const M: usize> Lagrangian<M>
    for DuplicatedLagrangian<L, F, R, N, M>
{
    fn lagrangian<D: Scalar>(&self, t: D, x: &SVector<D, M>, xdot: &SVector<D, M>) -> D {
        let (q, target) = Self::split(x);
        let (v, vt) = Self::split(xdot);
        self.lagrangian.lagrangian(t, &target, &vt)
            - self.lagrangian.lagrangian(t, &q, &v)
            - self.forcing_potential(t, &q, &v, &target, &vt)
    }
}
