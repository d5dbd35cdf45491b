//! Elastic cross-sections and materials, shared by the geometrically exact
//! beam (seed 000, [`BeamProperties`](super::beam::BeamProperties)) and the
//! Cosserat rod (seed 003 §6, [`rod_parameters`](super::rod::rod_parameters)).
//!
//! A cross-section gives the area A, the second moments I₁ = ∫x₂² dA and
//! I₂ = ∫x₁² dA (bending about the first and second section axes) and the
//! Saint-Venant torsion constant J_t:
//!
//! * rectangle b × h (b along the first axis, h along the second):
//!   A = bh, I₁ = bh³/12, I₂ = hb³/12,
//!   J_t ≈ p q³[1/3 − 0.21 (q/p)(1 − q⁴/(12p⁴))] with p = max(b, h),
//!   q = min(b, h) (Roark, Table 10.7; 0.1408 a⁴ for a square, exact
//!   value 0.1406 a⁴);
//! * disc of radius R: A = πR², I₁ = I₂ = πR⁴/4, J_t = πR⁴/2 (exact).
//!
//! A material gives the mass density ρ, Young's modulus E, the shear
//! modulus G (given, or G = E/(2(1 + ν)) from a Poisson ratio
//! −1 < ν ≤ ½, ν = ½ being the incompressible limit) and the Timoshenko
//! shear coefficient k of the shear stiffness kGA.

use crate::error::{Error, Result};
use crate::models::positive;

/// The shape of the cross-section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CrossSection {
    /// A rectangle of width `width` (along the first section axis) and
    /// height `height` (along the second).
    Rectangle {
        /// Side along the first axis (m).
        width: f64,
        /// Side along the second axis (m).
        height: f64,
    },
    /// A disc of radius `radius` (m).
    Circle {
        /// Radius (m).
        radius: f64,
    },
}

/// What the stiffness and inertia of a section are made of.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionGeometry {
    /// Area A.
    pub area: f64,
    /// Second moment I₁ = ∫x₂² dA (bending about the first axis).
    pub i1: f64,
    /// Second moment I₂ = ∫x₁² dA (bending about the second axis).
    pub i2: f64,
    /// Saint-Venant torsion constant J_t.
    pub torsion: f64,
}

impl CrossSection {
    /// A, I₁, I₂ and J_t (module documentation) of a section whose
    /// dimensions are finite and positive.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `width`, `height` or `radius`
    /// when it is not finite and positive.
    pub fn geometry(&self) -> Result<SectionGeometry> {
        match *self {
            CrossSection::Rectangle { width, height } => {
                let b = positive("width", width)?;
                let h = positive("height", height)?;
                let (p, q) = (b.max(h), b.min(h));
                Ok(SectionGeometry {
                    area: b * h,
                    i1: b * h.powi(3) / 12.0,
                    i2: h * b.powi(3) / 12.0,
                    torsion: p * q.powi(3) * (1.0 / 3.0 - 0.21 * (q / p) * (1.0 - q.powi(4) / (12.0 * p.powi(4)))),
                })
            }
            CrossSection::Circle { radius } => {
                let r = positive("radius", radius)?;
                let pi = std::f64::consts::PI;
                let i = pi * r.powi(4) / 4.0;
                Ok(SectionGeometry {
                    area: pi * r * r,
                    i1: i,
                    i2: i,
                    torsion: 2.0 * i,
                })
            }
        }
    }
}

impl CrossSection {
    /// Cowper's Timoshenko shear coefficient of the section for Poisson
    /// ratio ν: 6(1 + ν)/(7 + 6ν) for a disc, 10(1 + ν)/(12 + 11ν) for a
    /// rectangle (G. R. Cowper, J. Appl. Mech. 33, 1966), with ν clamped
    /// into [−0.99, ½].
    pub fn cowper_shear_coefficient(&self, nu: f64) -> f64 {
        let nu = nu.clamp(-0.99, 0.5);
        match self {
            CrossSection::Circle { .. } => 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu),
            CrossSection::Rectangle { .. } => 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu),
        }
    }
}

/// The second elastic constant: a shear modulus or a Poisson ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shear {
    /// Shear modulus G > 0 (Pa).
    Modulus(f64),
    /// Poisson ratio −1 < ν ≤ ½: G = E/(2(1 + ν)).
    Poisson(f64),
}

impl Shear {
    /// The Poisson ratio ν, given or ν = E/(2G) − 1 for Young's modulus
    /// `young`.
    pub fn poisson_ratio(&self, young: f64) -> f64 {
        match *self {
            Shear::Poisson(nu) => nu,
            Shear::Modulus(g) => young / (2.0 * g) - 1.0,
        }
    }
}

/// An elastic material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Mass density ρ (kg/m³).
    pub density: f64,
    /// Young's modulus E (Pa).
    pub young: f64,
    /// Shear modulus or Poisson ratio.
    pub shear: Shear,
    /// Timoshenko shear coefficient k of the shear stiffness kGA (5/6 for
    /// rectangles, 0.9 for discs; 1 leaves it out).
    pub shear_coefficient: f64,
}

impl Material {
    /// The shear modulus G.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `young`, `shear_modulus` or
    /// `poisson` (outside (−1, ½]).
    pub fn shear_modulus(&self) -> Result<f64> {
        let e = positive("young", self.young)?;
        match self.shear {
            Shear::Modulus(g) => positive("shear_modulus", g),
            Shear::Poisson(nu) if nu.is_finite() && nu > -1.0 && nu <= 0.5 => Ok(e / (2.0 * (1.0 + nu))),
            Shear::Poisson(nu) => Err(Error::InvalidParameter {
                name: "poisson".into(),
                value: nu.to_string(),
                reason: "a Poisson ratio must lie in (−1, 0.5]".into(),
            }),
        }
    }

    /// ρ, E, G and k, each checked.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first bad one (`density`,
    /// `young`, `shear_modulus`, `poisson`, `shear_coefficient`).
    pub fn constants(&self) -> Result<(f64, f64, f64, f64)> {
        let rho = positive("density", self.density)?;
        let g = self.shear_modulus()?;
        let k = positive("shear_coefficient", self.shear_coefficient)?;
        Ok((rho, self.young, g, k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_and_named_errors() {
        let square = CrossSection::Rectangle {
            width: 0.01,
            height: 0.01,
        }
        .geometry()
        .expect("valid");
        assert!((square.i1 - 1e-8 / 12.0).abs() < 1e-22 && square.i1 == square.i2);
        assert!((square.torsion / 1e-8 - 0.1408).abs() < 1e-4);
        let disc = CrossSection::Circle { radius: 0.25 }.geometry().expect("valid");
        let pi = std::f64::consts::PI;
        assert!((disc.area - pi / 16.0).abs() < 1e-15 && (disc.torsion - pi * 0.25f64.powi(4) / 2.0).abs() < 1e-15);
        let err = CrossSection::Rectangle {
            width: 1.0,
            height: -1.0,
        }
        .geometry()
        .expect_err("negative height");
        assert!(err.to_string().contains("height"), "{err}");
        let steel = Material {
            density: 7800.0,
            young: 2.1e11,
            shear: Shear::Poisson(0.3),
            shear_coefficient: 5.0 / 6.0,
        };
        assert!((steel.shear_modulus().expect("valid") - 2.1e11 / 2.6).abs() < 1e-3);
        let incompressible = Material {
            shear: Shear::Poisson(0.5),
            ..steel
        };
        assert!((incompressible.shear_modulus().expect("ν = ½") - 7e10).abs() < 1e-3);
        // Cowper at ν = 0.3 (0.886 disc, 0.850 rectangle); ν from E and G.
        let disc_k = CrossSection::Circle { radius: 1.0 }.cowper_shear_coefficient(0.3);
        assert!((disc_k - 7.8 / 8.8).abs() < 1e-15);
        let rectangle_k = CrossSection::Rectangle {
            width: 1.0,
            height: 2.0,
        }
        .cowper_shear_coefficient(0.3);
        assert!((rectangle_k - 13.0 / 15.3).abs() < 1e-15);
        assert!((Shear::Modulus(2.1e11 / 2.6).poisson_ratio(2.1e11) - 0.3).abs() < 1e-15);
        for (bad, name) in [
            (
                Material {
                    shear: Shear::Poisson(0.7),
                    ..steel
                },
                "poisson",
            ),
            (Material { young: -1.0, ..steel }, "young"),
            (Material { density: 0.0, ..steel }, "density"),
            (
                Material {
                    shear_coefficient: f64::NAN,
                    ..steel
                },
                "shear_coefficient",
            ),
        ] {
            let err = bad.constants().expect_err("invalid");
            assert!(err.to_string().contains(name), "{name}: {err}");
        }
    }
}
