//! The rod's material parameters (6.1) from physical inputs: cross-section,
//! mass density, Young's modulus and shear modulus (or Poisson ratio), as
//! in [`elastic`](crate::models::elastic) (the section's axes are d₁, d₂).
//!
//! The frame's third axis d₃ = R e₃ is the tangent, so the unstressed strain
//! is e = (0, 0, 1) and, with area A, second moments I₁, I₂, torsion constant
//! K and shear coefficient κ:
//!
//! * ρ_line = ρA, J = ρ·diag(I₁, I₂, I₁ + I₂),
//! * C₁ = diag(κGA, κGA, EA) (shear, shear, stretch),
//! * C₂ = diag(EI₁, EI₂, GK) (bending, bending, twist).

use nalgebra::{Matrix3, Vector3};

use crate::error::Result;
pub use crate::models::elastic::{CrossSection, Material, Shear};
use crate::models::rod::RodParameters;

/// The rod parameters (6.1) of a uniform rod of `section` and `material`.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming the
/// first bad input (`radius`, `width`, `height`, `density`, `young`,
/// `shear_modulus`, `poisson`, `shear_coefficient`).
pub fn rod_parameters(section: &CrossSection, material: &Material) -> Result<RodParameters> {
    let geometry = section.geometry()?;
    let (a, i1, i2) = (geometry.area, geometry.i1, geometry.i2);
    let (rho, e, g, kappa) = material.constants()?;
    RodParameters::new(
        rho * a,
        Matrix3::from_diagonal(&Vector3::new(rho * i1, rho * i2, rho * (i1 + i2))),
        Matrix3::from_diagonal(&Vector3::new(kappa * g * a, kappa * g * a, e * a)),
        Matrix3::from_diagonal(&Vector3::new(e * i1, e * i2, g * geometry.torsion)),
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
        assert!(err.to_string().contains("poisson"), "{err}");
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
