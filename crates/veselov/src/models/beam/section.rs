//! Beam properties from physical inputs (note 000 §15.1, "conventional
//! choice"; axis E3, angular components first):
//!
//! 𝕁 = diag(ρI₁, ρI₂, ρ(I₁ + I₂), ρA, ρA, ρA),
//! ℂ = diag(EI₁, EI₂, GJ_t, kGA, kGA, EA), G = E/(2(1 + ν)) unless given,
//!
//! with A, I₁, I₂ and the torsion constant J_t of the cross-section and the
//! material's constants as in [`elastic`](crate::models::elastic) (the
//! section's first axis is E1, its second E2).
//!
//! Wave speeds of the linearised beam are c_k = √(ℂ_k/𝕁_k) per component
//! (bending and torsion about E1, E2, E3, shear along E1, E2, axial along
//! E3). The marching step limits of note 000 §14 (von Neumann for the
//! five-point scheme the DCEL reduces to): time evolution needs
//! c_max Δt ≤ Δs and, because shear couples to the bending rotations like a
//! Klein–Gordon mass, Δt²(4c²/Δs² + kGA/ρI) ≤ 4 ([`BeamProperties::max_time_step`]);
//! space evolution Δs ≤ c_min Δt.

use crate::error::{Error, Result};
pub use crate::models::elastic::{CrossSection, Material, Shear};
use crate::models::positive;

/// The diagonal 𝕁 (inertia per unit length) and ℂ (stiffness) of a beam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamProperties {
    /// diag 𝕁 = (ρI₁, ρI₂, ρ(I₁ + I₂), ρA, ρA, ρA).
    pub inertia: [f64; 6],
    /// diag ℂ = (EI₁, EI₂, GJ_t, kGA, kGA, EA).
    pub stiffness: [f64; 6],
}

/// Which marching step limit applies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepLimit {
    /// Time evolution: c_max Δt ≤ Δs.
    Time,
    /// Space evolution: Δs ≤ c_min Δt.
    Space,
}

impl BeamProperties {
    /// 𝕁 and ℂ from the section and the material.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first non-positive (or, for ν,
    /// out-of-range) input.
    pub fn new(section: &CrossSection, material: &Material) -> Result<Self> {
        let geometry = section.geometry()?;
        let (a, i1, i2, jt) = (geometry.area, geometry.i1, geometry.i2, geometry.torsion);
        let (rho, e, g, k) = material.constants()?;
        Ok(Self {
            inertia: [rho * i1, rho * i2, rho * (i1 + i2), rho * a, rho * a, rho * a],
            stiffness: [e * i1, e * i2, g * jt, k * g * a, k * g * a, e * a],
        })
    }

    /// Diagonal 𝕁 and ℂ given directly.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `inertia[k]` or `stiffness[k]` when not finite and positive.
    pub fn from_diagonals(inertia: [f64; 6], stiffness: [f64; 6]) -> Result<Self> {
        for k in 0..6 {
            positive(&format!("inertia[{k}]"), inertia[k])?;
            positive(&format!("stiffness[{k}]"), stiffness[k])?;
        }
        Ok(Self { inertia, stiffness })
    }

    /// The component wave speeds c_k = √(ℂ_k/𝕁_k).
    pub fn wave_speeds(&self) -> [f64; 6] {
        std::array::from_fn(|k| (self.stiffness[k] / self.inertia[k]).sqrt())
    }

    /// The largest stable time step of time evolution for space step `ds`
    /// (derived, von Neumann for the linearised five-point scheme with a
    /// mass term, like Klein–Gordon): Δt ≤ Δs/c_max, and for the bending
    /// rotations, coupled to shear by kGA(w' − ψ), whose "mass" is
    /// m_k² = ℂ_shear/𝕁_k (rotation about E1 with shear along E2, about E2
    /// with shear along E1): Δt²(4c_k²/Δs² + m_k²) ≤ 4. The second bound is
    /// the one that matters for slender beams (m ≈ √(kG/ρ)/r, r the radius
    /// of gyration of the section).
    pub fn max_time_step(&self, ds: f64) -> f64 {
        let c = self.wave_speeds();
        let mut dt = ds / c.iter().fold(0.0_f64, |m, &x| m.max(x));
        for (k, shear) in [(0, 4), (1, 3)] {
            let m2 = self.stiffness[shear] / self.inertia[k];
            dt = dt.min(2.0 / (4.0 * c[k] * c[k] / (ds * ds) + m2).sqrt());
        }
        dt
    }

    /// Checks the marching step limit (module documentation) for steps
    /// `dt`, `ds`; `allow` turns a violation into `Ok` (the caller warns).
    /// Returns the Courant number: Δt/[`max_time_step`](Self::max_time_step) (time) or Δs/(c_min Δt) (space).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `dt` when the limit is violated and
    /// not allowed, or when a step is not positive.
    pub fn check_step(&self, limit: StepLimit, dt: f64, ds: f64, allow: bool) -> Result<f64> {
        positive("dt", dt)?;
        positive("ds", ds)?;
        let c = self.wave_speeds();
        let (courant, what) = match limit {
            StepLimit::Time => (
                dt / self.max_time_step(ds),
                "time evolution needs (largest wave speed)·dt ≤ ds and, for the bending rotations, \
                 dt²(4c²/ds² + kGA/ρI) ≤ 4",
            ),
            StepLimit::Space => (
                ds / (c.iter().fold(f64::INFINITY, |m, &x| m.min(x)) * dt),
                "space evolution needs ds ≤ (smallest wave speed)·dt",
            ),
        };
        if courant > 1.0 && !allow {
            return Err(Error::InvalidParameter {
                name: "dt".into(),
                value: dt.to_string(),
                reason: format!(
                    "step limit violated (Courant number {courant:.3} > 1): {what}; wave speeds {c:?} m/s, ds = {ds}"
                ),
            });
        }
        Ok(courant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_section_and_errors() {
        let m = Material {
            density: 7800.0,
            young: 2.1e11,
            shear: Shear::Poisson(0.3),
            shear_coefficient: 5.0 / 6.0,
        };
        let p = BeamProperties::new(
            &CrossSection::Rectangle {
                width: 0.01,
                height: 0.01,
            },
            &m,
        )
        .expect("valid");
        let i = 1e-8 / 12.0;
        assert!((p.inertia[0] - 7800.0 * i).abs() < 1e-20);
        assert!((p.stiffness[2] / (2.1e11 / 2.6) / 1e-8 - 0.1408).abs() < 1e-3);
        assert!((p.wave_speeds()[5] - (2.1e11_f64 / 7800.0).sqrt()).abs() < 1e-9);
        let bad = Material { young: -1.0, ..m };
        let err = BeamProperties::new(&CrossSection::Circle { radius: 0.01 }, &bad).expect_err("negative E");
        assert!(err.to_string().contains("young"), "{err}");
        let bad = Material {
            shear: Shear::Poisson(0.7),
            ..m
        };
        assert!(BeamProperties::new(&CrossSection::Circle { radius: 0.01 }, &bad).is_err());
        let err = p.check_step(StepLimit::Time, 1e-3, 0.02, false).expect_err("CFL");
        assert!(err.to_string().contains("dt"), "{err}");
        assert!(p.check_step(StepLimit::Time, 1e-3, 0.02, true).expect("allowed") > 1.0);
        assert!(p.check_step(StepLimit::Time, 1e-6, 0.02, false).expect("fine") < 1.0);
    }
}
