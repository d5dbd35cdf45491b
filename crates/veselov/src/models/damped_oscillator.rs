//! Damped linear oscillator `M q̈ + D q̇ + K q = 0` (seed 004, Example 7.2):
//! `L = ½ vᵀMv − ½ qᵀKq` with the dissipative force `F = −D v`.

use nalgebra::{SMatrix, SVector};

use crate::ad::Scalar;
use crate::error::{Error, Result};
use crate::mechanics::{Force, PhaseState, Potential, SeparableLagrangian};

/// Linear oscillator with mass `M`, stiffness `K` and damping `D` (all symmetric).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedOscillator<const N: usize> {
    /// Mass matrix `M` (symmetric positive definite).
    pub mass: SMatrix<f64, N, N>,
    /// Stiffness `K` (symmetric).
    pub stiffness: SMatrix<f64, N, N>,
    /// Damping `D` (symmetric positive semi-definite for dissipation).
    pub damping: SMatrix<f64, N, N>,
}

/// The potential `½ qᵀKq` of a [`DampedOscillator`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stiffness<const N: usize>(pub SMatrix<f64, N, N>);

impl<const N: usize> Potential<N> for Stiffness<N> {
    #[inline]
    fn potential<D: Scalar>(&self, _t: D, q: &SVector<D, N>) -> D {
        let k = self.0.map(D::from);
        (k * q).dot(q) * 0.5
    }
}

/// The damping force `F = −D v` of a [`DampedOscillator`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearDamping<const N: usize>(pub SMatrix<f64, N, N>);

impl<const N: usize> Force<N> for LinearDamping<N> {
    fn force<D: Scalar>(&self, _t: D, _q: &SVector<D, N>, v: &SVector<D, N>) -> SVector<D, N> {
        -(self.0.map(D::from) * v)
    }
}

impl<const N: usize> DampedOscillator<N> {
    /// Oscillator from symmetric `M` (positive definite), `K`, `D`.
    pub fn new(mass: SMatrix<f64, N, N>, stiffness: SMatrix<f64, N, N>, damping: SMatrix<f64, N, N>) -> Result<Self> {
        for (name, m) in [("stiffness", &stiffness), ("damping", &damping)] {
            if m.iter().any(|x| !x.is_finite()) || (m - m.transpose()).amax() > 1e-14 * m.amax() {
                return Err(Error::InvalidParameter {
                    name: name.into(),
                    value: format!("{:?}", m.as_slice()),
                    reason: "must be finite and symmetric".into(),
                });
            }
        }
        SeparableLagrangian::new(mass, Stiffness(stiffness))?;
        Ok(Self {
            mass,
            stiffness,
            damping,
        })
    }
    /// The conservative part `L = ½ vᵀMv − ½ qᵀKq`.
    pub fn system(&self) -> SeparableLagrangian<Stiffness<N>, N> {
        SeparableLagrangian::new(self.mass, Stiffness(self.stiffness)).expect("validated at construction")
    }
    /// The damping force `−D v`.
    pub fn force(&self) -> LinearDamping<N> {
        LinearDamping(self.damping)
    }
    /// Energy `½ pᵀM⁻¹p + ½ qᵀKq`.
    pub fn energy(&self, x: &PhaseState<N>) -> f64 {
        let minv = self.system().mass_inverse().to_owned();
        0.5 * (minv * x.p).dot(&x.p) + 0.5 * (self.stiffness * x.q).dot(&x.q)
    }
}
