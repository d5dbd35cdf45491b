//! The expansion of the discrete energy at a start
//! ([`crate::sem::degeneracy`]), measured by trial first steps.

use nalgebra::SVector;

use super::{SemIntegrator, SemState};
use crate::error::Result;
use crate::mechanics::Lagrangian;
use crate::sem::StartExpansion;

impl<L: Lagrangian<N>, const N: usize> SemIntegrator<L, N> {
    /// The expansion of the discrete energy at a start from `(t₀, q₀, p₀)`
    /// with first step `h₀` (module docs): three first steps of the fixed
    /// step map, `h₀`, `h₀/2` and `h₀/4`.
    ///
    /// # Errors
    /// If a first step's momentum equation does not converge.
    pub fn start_expansion(
        &self,
        t0: f64,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        h0: f64,
    ) -> Result<StartExpansion> {
        let s0 = SemState::first(t0, q0, p0, h0);
        let energies = |s: &SemState<N>| -> Result<[f64; 3]> {
            let mut e = [0.0; 3];
            for (i, e) in e.iter_mut().enumerate() {
                let h = h0 / f64::from(1u32 << i);
                let (next, _) = self.fixed_step(s, h)?;
                *e = self.action().leaving(s.t, &s.q, &next.q, h).2;
            }
            Ok(e)
        };
        let (s1, _) = self.fixed_step(&s0, h0)?;
        let order = self.action().rule().order();
        Ok(StartExpansion::from_energies(energies(&s0)?, energies(&s1)?, order))
    }
}
