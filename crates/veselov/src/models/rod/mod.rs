//! The Cosserat rod (Casimiro–Rodrigo §6, note 003 §3) as a model of the
//! field core: its density (6.1) and Prop. 6.5's closed-form cell on the
//! leapfrog CFK lattice ([`cosserat`], with the centred shear frame, the
//! loads and the split step's eight-lane kernels in its submodules), the
//! step that solves one vertex in closed form ([`cosserat_step`]), external
//! potentials such as gravity ([`potential`]), material parameters from
//! physical inputs ([`material`]), the leapfrog lattice of a finite rod with
//! free ends and its Cauchy data ([`lattice`]), the step limit
//! ([`stability`]), how finely the lattice resolves bending
//! ([`resolution`]), the discrete momenta and energy ([`momentum`]) and
//! clamped or driven ends ([`ends`]). The march is the core's
//! [`CauchyMarcher::with_window`](crate::field::cauchy::CauchyMarcher::with_window).
//!
//! Q_{v₀} of the core's vertex rule on the leapfrog embedding (6.2) and
//! Prop. 6.5's closed form agree, with their gradients:
//!
//! ```
//! use nalgebra::{Matrix3, Vector3};
//! use veselov::field::cell::{DiscreteLagrangian, vertex_gradient};
//! use veselov::complex::TopCell;
//! use veselov::field::discretize::{CellCheck, CfkNodes, VertexRule};
//! use veselov::models::rod::{CosseratCell, CosseratDensity, RodParameters};
//! use veselov::field::fibre::{Pose, PositionRotation};
//! use veselov::lie::so3;
//!
//! let i3 = Matrix3::identity();
//! let rod = CosseratDensity::free(RodParameters::new(1.0, i3 * 0.1, i3, i3, Vector3::x()).unwrap());
//! let (ds, dt) = (0.1, 0.02);
//! // Q_{v₀} on the leapfrog embedding (6.2) and Prop. 6.5's closed form.
//! let generic = VertexRule::at_vertex(rod, CfkNodes::leapfrog(ds, dt).unwrap(), 0).unwrap();
//! let closed = CosseratCell::new(rod, ds, dt).unwrap();
//! let cell = TopCell { index: 0, shape: 0, origin: [0; 8] };
//! let y = [
//!     Pose::new(Vector3::zeros(), so3::exp(&Vector3::zeros())),
//!     Pose::new(Vector3::new(0.05, 0.0, 0.0), so3::exp(&Vector3::new(0.0, 0.1, 0.0))),
//!     Pose::new(Vector3::new(0.0, 0.01, 0.0), so3::exp(&Vector3::new(0.02, 0.0, 0.0))),
//! ];
//! closed.check_cell(&cell, &y).unwrap();
//! let (a, b) = (generic.cell_lagrangian(&cell, &y), closed.cell_lagrangian(&cell, &y));
//! assert!((a - b).abs() < 1e-14 * a.abs().max(1.0));
//! let (_, grad) = vertex_gradient::<PositionRotation, _, 6>(&generic, &cell, &y, 0);
//! let closed_grad = closed.gradients(&cell, &y).unwrap();
//! assert!((grad - closed_grad[0]).norm() < 1e-12 * grad.norm());
//! ```

pub mod cosserat;
pub mod cosserat_step;
pub mod ends;
pub mod lattice;
pub mod material;
pub mod momentum;
pub mod potential;
pub mod resolution;
pub mod stability;

pub use cosserat::{CosseratCell, CosseratDensity, RodLoads, RodParameters, ShearFrame};
pub use ends::{EndCondition, RodEnds};
pub use lattice::RodLattice;
pub use material::{CrossSection, Material, Shear, rod_parameters};
pub use momentum::{angular_momentum, energy, linear_momentum, load_impulse, momenta};
pub use potential::{LinearPotential, NoPotential, RodPotential, Weight};
pub use resolution::{BENDING_STIFFENING_PER_LOCKING, BendingError, locking_number, spacing_for_locking};
pub use stability::{COURANT_LIMIT, StepCheck, courant_number, largest_step, rotary_frequency, wave_speed};
