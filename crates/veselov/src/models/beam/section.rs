//! Beam properties from physical inputs (note 000 §15.1, "conventional
//! choice"; axis E3, angular components first):
//!
//! 𝕁 = diag(ρI₁, ρI₂, ρ(I₁ + I₂), ρA, ρA, ρA),
//! ℂ = diag(EI₁, EI₂, GJ_t, kGA, kGA, EA), G = E/(2(1 + ν)) unless given,
//!
//! with A, I₁ = ∫x₂² dA, I₂ = ∫x₁² dA and the torsion constant J_t of the
//! cross-section: rectangle b × h (b along E1, h along E2): A = bh,
//! I₁ = bh³/12, I₂ = hb³/12, J_t = p q³(1/3 − 0.21 (q/p)(1 − q⁴/(12p⁴)))
//! with p = max(b, h), q = min(b, h) (Roark's formula; 0.1408 a⁴ for a
//! square, exact value 0.1406 a⁴); circle of radius R: A = πR², I₁ = I₂ =
//! πR⁴/4, J_t = πR⁴/2 (exact).
//!
//! Wave speeds of the linearised beam are c_k = √(ℂ_k/𝕁_k) per component
//! (bending and torsion about E1, E2, E3, shear along E1, E2, axial along
//! E3). The marching step limits of note 000 §14 (von Neumann for the
//! five-point scheme the DCEL reduces to): time evolution needs
//! c_max Δt ≤ Δs and, because shear couples to the bending rotations like a
//! Klein–Gordon mass, Δt²(4c²/Δs² + kGA/ρI) ≤ 4 ([`BeamProperties::max_time_step`]);
//! space evolution Δs ≤ c_min Δt.

use crate::error::{Error, Result};
use crate::models::positive;

/// The shape of the cross-section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CrossSection {
    /// A rectangle of width `width` (along E1) and height `height` (along E2).
    Rectangle {
        /// Side along E1 (m).
        width: f64,
        /// Side along E2 (m).
        height: f64,
    },
    /// A disc of radius `radius` (m).
    Circle {
        /// Radius (m).
        radius: f64,
    },
}

/// The second elastic constant: a Poisson ratio or a shear modulus.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShearProperty {
    /// Poisson ratio ν ∈ (−1, 0.5); G = E/(2(1 + ν)).
    Poisson(f64),
    /// Shear modulus G > 0 (Pa).
    Modulus(f64),
}

/// The material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Mass density ρ (kg/m³).
    pub density: f64,
    /// Young's modulus E (Pa).
    pub young: f64,
    /// Poisson ratio or shear modulus.
    pub shear: ShearProperty,
    /// Shear correction factor k (5/6 for rectangles, 0.9 for discs, 1 to switch it off).
    pub shear_correction: f64,
}

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

impl CrossSection {
    /// (A, I₁, I₂, J_t).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the non-positive dimension.
    pub fn geometry(&self) -> Result<(f64, f64, f64, f64)> {
        match *self {
            CrossSection::Rectangle { width, height } => {
                let b = positive("section.width", width)?;
                let h = positive("section.height", height)?;
                let (p, q) = (b.max(h), b.min(h));
                let jt = p * q.powi(3) * (1.0 / 3.0 - 0.21 * (q / p) * (1.0 - q.powi(4) / (12.0 * p.powi(4))));
                Ok((b * h, b * h.powi(3) / 12.0, h * b.powi(3) / 12.0, jt))
            }
            CrossSection::Circle { radius } => {
                let r = positive("section.radius", radius)?;
                let pi = std::f64::consts::PI;
                Ok((
                    pi * r * r,
                    pi * r.powi(4) / 4.0,
                    pi * r.powi(4) / 4.0,
                    pi * r.powi(4) / 2.0,
                ))
            }
        }
    }
}

impl Material {
    /// The shear modulus G.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `young`, `poisson` or `shear_modulus`.
    pub fn shear_modulus(&self) -> Result<f64> {
        let e = positive("young", self.young)?;
        match self.shear {
            ShearProperty::Poisson(nu) => {
                if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
                    return Err(Error::InvalidParameter {
                        name: "poisson".into(),
                        value: nu.to_string(),
                        reason: "a Poisson ratio must lie in (-1, 0.5)".into(),
                    });
                }
                Ok(e / (2.0 * (1.0 + nu)))
            }
            ShearProperty::Modulus(g) => positive("shear_modulus", g),
        }
    }
}

impl BeamProperties {
    /// 𝕁 and ℂ from the section and the material.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first non-positive (or, for ν,
    /// out-of-range) input.
    pub fn new(section: &CrossSection, material: &Material) -> Result<Self> {
        let (a, i1, i2, jt) = section.geometry()?;
        let rho = positive("density", material.density)?;
        let e = positive("young", material.young)?;
        let g = material.shear_modulus()?;
        let k = positive("shear_correction", material.shear_correction)?;
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
            shear: ShearProperty::Poisson(0.3),
            shear_correction: 5.0 / 6.0,
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
            shear: ShearProperty::Poisson(0.7),
            ..m
        };
        assert!(BeamProperties::new(&CrossSection::Circle { radius: 0.01 }, &bad).is_err());
        let err = p.check_step(StepLimit::Time, 1e-3, 0.02, false).expect_err("CFL");
        assert!(err.to_string().contains("dt"), "{err}");
        assert!(p.check_step(StepLimit::Time, 1e-3, 0.02, true).expect("allowed") > 1.0);
        assert!(p.check_step(StepLimit::Time, 1e-6, 0.02, false).expect("fine") < 1.0);
    }
}
