//! The geometrically exact (Simo–Reissner) beam on SE(3) of seed 000 §5
//! (note 000 §15): configuration g = (Λ, r) of each cross-section, velocity
//! ξ = g⁻¹∂_t g = (ω; γ), strain η = g⁻¹∂_s g = (Ω; Γ), and the Lagrangian
//! density (95)
//!
//! ℒ = ½⟨𝕁ξ, ξ⟩ − ½⟨ℂ(η − E6), η − E6⟩ − Π(g), E6 = (0,0,0,0,0,1),
//!
//! with diagonal 𝕁 and ℂ built from physical inputs ([`section`]) and an
//! optional gravity potential ([`density`]). The discrete Lagrangian on
//! seed 000's triangles is the core's
//! [`SplitLagrangian`](crate::evolution::split::SplitLagrangian) over the group
//! increment τ⁻¹(g₁⁻¹g₂) with τ = Cayley or exp; the beam knows nothing of
//! marchers or solvers.

pub mod density;
pub mod paper;
pub mod section;

pub use density::{BeamDensity, BeamLagrangian, CayleyBeam, E6, ExpBeam, beam_lagrangian, left_generators, straight};
pub use section::{BeamProperties, CrossSection, Material, Shear, StepLimit};
