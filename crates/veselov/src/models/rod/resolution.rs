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
//! (shear along d₁ with bending about d₂, and the other plane). The lattice
//! bends like a rod of bending stiffness EI·(1 + aΛ), a ≈ 0.245
//! ([`BENDING_STIFFENING_PER_LOCKING`]): second order in δ, but with the
//! constant κGA/EI ≈ 4κG/(E r²), large for a slender rod (r its radius).
//! Measured (`tests/rod/`, a circular section, ν = 0.3, κ = 0.9):
//!
//! * a cantilever's settled tip deflection under an end load falls short of
//!   Timoshenko's by 5.17 % at Λ = 0.22 and 1.35 % at Λ = 0.055, where
//!   aΛ/(1 + aΛ) gives 5.15 % and 1.34 %;
//! * the first free–free bending frequency is high by 14.9 %, 4.0 %, 1.0 %
//!   and 0.25 % at Λ = 1.38, 0.35, 0.087 and 0.022, where √(1 + aΛ) − 1
//!   gives 15.7 %, 4.2 %, 1.1 % and 0.26 % (the rest an ordinary O(δ²)
//!   error that does not grow with κGA/EI);
//! * the symmetric rule Q_sym (the density averaged over a cell's three
//!   vertices, each term with that vertex's frame) locks the same: its
//!   bending frequency is high by 15.0 %, 4.0 % and 1.02 % at Λ = 1.38,
//!   0.35 and 0.087.
//!
//! So δ must be small against the bending length √(EI/κGA) (r/1.18 for a
//! solid circle with ν = 0.3, κ = 0.9), not only against the length of the
//! rod: [`spacing_for_locking`] gives the largest spacing for a chosen Λ.
//! Or the shear is measured in the centred frame
//! ([`ShearFrame::Centred`](crate::models::rod::ShearFrame)), which
//! does not lock; this module's estimates are those of the base vertex's
//! frame (Prop. 6.5 and Q_sym).

use crate::models::rod::RodParameters;

/// The lattice's bending stiffening per unit of the locking number Λ
/// ([`locking_number`]): the lattice bends like a rod of stiffness
/// EI·(1 + 0.245Λ), as measured on a settled cantilever and on the first
/// free–free bending frequency (see the module documentation). An
/// estimate, not a bound.
pub const BENDING_STIFFENING_PER_LOCKING: f64 = 0.245;

/// The estimated bending errors of the lattice at locking number Λ
/// ([`BENDING_STIFFENING_PER_LOCKING`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BendingError {
    /// The relative excess of the bending stiffness, s = 0.245Λ.
    pub stiffening: f64,
}

impl BendingError {
    /// The estimate at locking number `locking`.
    pub fn at(locking: f64) -> Self {
        Self {
            stiffening: BENDING_STIFFENING_PER_LOCKING * locking,
        }
    }
    /// The relative shortfall of a static bending deflection, s/(1 + s).
    pub fn deflection_deficit(&self) -> f64 {
        self.stiffening / (1.0 + self.stiffening)
    }
    /// The relative excess of a bending frequency, √(1 + s) − 1.
    pub fn frequency_excess(&self) -> f64 {
        (1.0 + self.stiffening).sqrt() - 1.0
    }
}

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
