//! The rod's material parameters (6.1) from physical inputs: cross-section,
//! mass density, Young's modulus and shear modulus (or Poisson ratio).
//!
//! The frame's third axis d₃ = R e₃ is the tangent, so the unstressed strain
//! is e = (0, 0, 1) and, with area A, second moments I₁, I₂, torsion constant
//! K and shear coefficient κ:
//!
//! * ρ_line = ρA, J = ρ·diag(I₁, I₂, I₁ + I₂),
//! * C₁ = diag(κGA, κGA, EA) (shear, shear, stretch),
//! * C₂ = diag(EI₁, EI₂, GK) (bending, bending, twist).

use nalgebra::{Matrix3, Vector3};

use crate::error::{Error, Result};
use crate::field::discretize::RodParameters;
use crate::models::positive;

/// The rod's cross-section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CrossSection {
    /// A disc of the given radius.
    Circle {
        /// Radius.
        radius: f64,
    },
    /// A rectangle, `width` along d₁, `height` along d₂.
    Rectangle {
        /// Extent along d₁.
        width: f64,
        /// Extent along d₂.
        height: f64,
    },
}

impl CrossSection {
    fn validate(&self) -> Result<()> {
        match *self {
            CrossSection::Circle { radius } => positive("radius", radius).map(|_| ()),
            CrossSection::Rectangle { width, height } => {
                positive("width", width)?;
                positive("height", height).map(|_| ())
            }
        }
    }

    /// Area A.
    pub fn area(&self) -> f64 {
        match *self {
            CrossSection::Circle { radius } => std::f64::consts::PI * radius * radius,
            CrossSection::Rectangle { width, height } => width * height,
        }
    }

    /// Second moments of area (I₁, I₂) about d₁ and d₂.
    pub fn second_moments(&self) -> (f64, f64) {
        match *self {
            CrossSection::Circle { radius } => {
                let i = std::f64::consts::PI * radius.powi(4) / 4.0;
                (i, i)
            }
            CrossSection::Rectangle { width, height } => (width * height.powi(3) / 12.0, height * width.powi(3) / 12.0),
        }
    }

    /// Saint-Venant torsion constant K: πr⁴/2 for the disc; for a rectangle
    /// with sides a ≥ b the series approximation
    /// K ≈ ab³[1/3 − 0.21(b/a)(1 − b⁴/(12a⁴))] (Roark, Table 10.7).
    pub fn torsion_constant(&self) -> f64 {
        match *self {
            CrossSection::Circle { radius } => std::f64::consts::PI * radius.powi(4) / 2.0,
            CrossSection::Rectangle { width, height } => {
                let (a, b) = (width.max(height), width.min(height));
                a * b.powi(3) * (1.0 / 3.0 - 0.21 * (b / a) * (1.0 - b.powi(4) / (12.0 * a.powi(4))))
            }
        }
    }
}

/// How the shear modulus is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shear {
    /// G directly.
    Modulus(f64),
    /// From the Poisson ratio ν: G = E / (2(1 + ν)), −1 < ν ≤ ½.
    Poisson(f64),
}

/// An elastic material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Mass density ρ (mass per volume).
    pub density: f64,
    /// Young's modulus E.
    pub young: f64,
    /// Shear modulus or Poisson ratio.
    pub shear: Shear,
    /// Timoshenko shear coefficient κ in C₁ (1 if not known).
    pub shear_coefficient: f64,
}

impl Material {
    /// The shear modulus G.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming `shear_modulus` or `poisson_ratio`.
    pub fn shear_modulus(&self) -> Result<f64> {
        match self.shear {
            Shear::Modulus(g) => positive("shear_modulus", g),
            Shear::Poisson(nu) => {
                if nu.is_finite() && nu > -1.0 && nu <= 0.5 {
                    Ok(self.young / (2.0 * (1.0 + nu)))
                } else {
                    Err(Error::InvalidParameter {
                        name: "poisson_ratio".into(),
                        value: nu.to_string(),
                        reason: "must lie in (−1, 0.5]".into(),
                    })
                }
            }
        }
    }
}

/// The rod parameters (6.1) of a uniform rod of `section` and `material`.
///
/// # Errors
/// [`Error::InvalidParameter`] naming the first bad input (`radius`,
/// `width`, `height`, `density`, `young`, `shear_modulus`, `poisson_ratio`,
/// `shear_coefficient`).
pub fn rod_parameters(section: &CrossSection, material: &Material) -> Result<RodParameters> {
    section.validate()?;
    let rho = positive("density", material.density)?;
    let e = positive("young", material.young)?;
    let kappa = positive("shear_coefficient", material.shear_coefficient)?;
    let g = material.shear_modulus()?;
    let a = section.area();
    let (i1, i2) = section.second_moments();
    RodParameters::new(
        rho * a,
        Matrix3::from_diagonal(&Vector3::new(rho * i1, rho * i2, rho * (i1 + i2))),
        Matrix3::from_diagonal(&Vector3::new(kappa * g * a, kappa * g * a, e * a)),
        Matrix3::from_diagonal(&Vector3::new(e * i1, e * i2, g * section.torsion_constant())),
        Vector3::new(0.0, 0.0, 1.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn disc_values_and_named_errors() {
        let m = Material {
            density: 5000.0,
            young: 1e6,
            shear: Shear::Modulus(1e4),
            shear_coefficient: 1.0,
        };
        let p = rod_parameters(&CrossSection::Circle { radius: 0.25 }, &m).expect("valid");
        let a = std::f64::consts::PI / 16.0;
        assert!((p.rho() - 5000.0 * a).abs() < 1e-9);
        assert!((p.c1()[(2, 2)] - 1e6 * a).abs() < 1e-6);
        let i = std::f64::consts::PI * 0.25_f64.powi(4) / 4.0;
        assert!((p.c2()[(0, 0)] - 1e6 * i).abs() < 1e-9 && (p.c2()[(2, 2)] - 1e4 * 2.0 * i).abs() < 1e-9);
        let bad = Material {
            shear: Shear::Poisson(0.7),
            ..m
        };
        let err = rod_parameters(&CrossSection::Circle { radius: 0.25 }, &bad).expect_err("invalid input");
        assert!(err.to_string().contains("poisson_ratio"), "{err}");
        let err = rod_parameters(
            &CrossSection::Rectangle {
                width: 1.0,
                height: -1.0,
            },
            &m,
        )
        .expect_err("invalid input");
        assert!(err.to_string().contains("height"), "{err}");
        let g = Material {
            shear: Shear::Poisson(0.25),
            ..m
        };
        assert!((g.shear_modulus().expect("valid") - 4e5).abs() < 1e-9);
    }
}
