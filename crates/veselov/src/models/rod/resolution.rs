//! How finely the leapfrog lattice resolves bending: shear locking.
//!
//! Prop. 6.5's Lagrangian takes a cell's shear strain ε = R₀ᵀ(2r₁ − r₀ − r₂)/(σΔs) − e
//! with the frame R₀ of one vertex, while the bending strain comes from the
//! rotation between vertices. In pure bending the continuum's shear
//! vanishes, but on the lattice a curvature ψ′ leaves a shear of order δψ′
//! in each cell (δ the spacing of the material points), whose energy
//! ½κGA(δψ′)² competes with the bending energy ½EIψ′². Their ratio is the
//! locking number
//!
//! Λ = δ² · max(C₁,₁₁ / C₂,₂₂, C₁,₂₂ / C₂,₁₁) = κGA δ² / EI
//!
//! (shear along d₁ with bending about d₂, and the other plane), and the
//! lattice is stiffer in bending than the rod by a relative amount
//! proportional to Λ: second order in δ, but with the constant κGA/EI ≈
//! 4κG/(E r²), large for a slender rod (r its radius). Measured
//! (`tests/rod/`, a circular section, ν = 0.3, κ = 0.9):
//!
//! * a cantilever's settled tip deflection under an end load falls short of
//!   Timoshenko's by 0.23Λ–0.245Λ (Λ from 0.22 down to 0.055);
//! * the first free–free bending frequency is high by 0.11Λ–0.12Λ (Λ from
//!   1.4 down to 0.02), beside an ordinary O(δ²) error that does not grow
//!   with κGA/EI.
//!
//! So δ must be small against the bending length √(EI/κGA) (r/1.18 for
//! a solid circle with ν = 0.3, κ = 0.9), not only against the length
//! of the rod: [`spacing_for_locking`] gives the largest spacing for a
//! chosen Λ.

use crate::field::discretize::RodParameters;

/// The relative shortfall of a bending deflection per unit of the locking
/// number Λ ([`locking_number`]), as measured on a settled cantilever
/// (0.23–0.245; see the module documentation): an estimate, not a bound.
pub const DEFLECTION_DEFICIT_PER_LOCKING: f64 = 0.24;

/// The locking number Λ = δ² · max(C₁,₁₁/C₂,₂₂, C₁,₂₂/C₂,₁₁) of material
/// points `spacing` δ apart (see the module documentation); 0 for a plane
/// without bending or shear stiffness.
pub fn locking_number(p: &RodParameters, spacing: f64) -> f64 {
    let (c1, c2) = (p.c1(), p.c2());
    let plane = |shear: f64, bending: f64| {
        if shear > 0.0 && bending > 0.0 {
            shear / bending
        } else {
            0.0
        }
    };
    spacing * spacing * plane(c1[(0, 0)], c2[(1, 1)]).max(plane(c1[(1, 1)], c2[(0, 0)]))
}

/// The largest spacing of the material points with locking number at most
/// `target`: √(target / max(C₁,₁₁/C₂,₂₂, C₁,₂₂/C₂,₁₁)); infinite for a rod
/// without a bending plane.
pub fn spacing_for_locking(p: &RodParameters, target: f64) -> f64 {
    let per_square = locking_number(p, 1.0);
    if per_square > 0.0 {
        (target / per_square).sqrt()
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::rod::{CrossSection, Material, Shear, rod_parameters};

    #[test]
    fn locking_number_of_a_circle_and_of_a_flat_section() {
        let material = Material {
            density: 1.0,
            young: 1.0,
            shear: Shear::Poisson(0.3),
            shear_coefficient: 0.9,
        };
        // κGA/EI = κ (G/E) (A/I) = 0.9 · (1/2.6) · 4/r².
        let r = 0.05;
        let p = rod_parameters(&CrossSection::Circle { radius: r }, &material).expect("rod");
        let per = 0.9 / 2.6 * 4.0 / (r * r);
        let delta = 0.01;
        assert!((locking_number(&p, delta) - per * delta * delta).abs() <= 1e-12 * per * delta * delta);
        let spacing = spacing_for_locking(&p, 0.1);
        assert!((locking_number(&p, spacing) - 0.1).abs() <= 1e-12);
        // A flat section locks in its thin plane: A/I₁ = 12/h² for the
        // bending about d₁ of a width b, height h section.
        let (b, h) = (0.1, 0.02);
        let p = rod_parameters(&CrossSection::Rectangle { width: b, height: h }, &material).expect("rod");
        let thin = 0.9 / 2.6 * 12.0 / (h * h);
        assert!((locking_number(&p, delta) - thin * delta * delta).abs() <= 1e-9 * thin * delta * delta);
    }
}
