//! The Cosserat rod (seed 003 §6, note 003 §3) as a model: material
//! parameters from physical inputs ([`material`]), the leapfrog lattice of a
//! finite rod with free ends and its Cauchy data ([`lattice`]), the step
//! limit ([`stability`]), how finely the lattice resolves bending
//! ([`resolution`]), the discrete momenta and energy ([`momentum`]) and
//! clamped or driven ends ([`ends`]). The
//! discrete Lagrangian is the core's [`CosseratCell`](crate::field::discretize::CosseratCell)
//! (Prop. 6.5) and the march the core's
//! [`CauchyMarcher::with_window`](crate::field::cauchy::CauchyMarcher::with_window).

pub mod ends;
pub mod lattice;
pub mod material;
pub mod momentum;
pub mod resolution;
pub mod stability;

pub use ends::{EndCondition, RodEnds};
pub use lattice::RodLattice;
pub use material::{CrossSection, Material, Shear, rod_parameters};
pub use momentum::{angular_momentum, energy, linear_momentum, load_impulse, momenta};
pub use resolution::{BENDING_STIFFENING_PER_LOCKING, BendingError, locking_number, spacing_for_locking};
pub use stability::{COURANT_LIMIT, StepCheck, courant_number, largest_step, rotary_frequency, wave_speed};
