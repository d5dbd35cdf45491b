//! Discretising a smooth Lagrangian density (note 003 §2.5; paper §5) and the
//! Cosserat rod (note 003 §3; paper §6).
//!
//! Data: a node map x: V₀ → ℝ^N of top cells ([`NodeMap`]: [`CfkNodes`] for
//! CFK simplices, with the rod's leapfrog embedding (6.2) and its
//! n-dimensional space–time analogue, and [`CubeNodes`] for cubes), a smooth
//! density 𝓛(x, y, φ) over a fibre ([`SmoothDensity`]), and a quadrature rule
//! (5.2). The results implement [`crate::field::cell::DiscreteLagrangian`], so
//! their exact vertex gradients and mixed blocks come from
//! [`crate::field::cell::vertex_gradient`] and
//! [`crate::field::cell::mixed_block`]:
//!
//! * [`VertexRule`] — Q_u and Q_sym at vertex nodes by Lemma 5.15, for any
//!   fibre with a logarithm (ℝ^m, SO(3), SE(3), ℝ³ × SO(3));
//! * [`MidpointRule`] — Q_mid for the Euclidean fibre (affine bundle,
//!   Prop. 5.20, (5.6));
//! * [`CubeCentreRule`] — the multilinear centre rule on cubes;
//! * [`CosseratCell`] — Prop. 6.5's closed form for the rod density
//!   [`CosseratDensity`] (6.1), with the §3.5 gradients.
//!
//! Suitability (Def. 5.9, Cor. 6.3): [`DiscreteLagrangian::cell_lagrangian`]
//! returns NaN on an unsuitable cell; [`CellCheck::check_cell`] returns a
//! [`CellError`] naming the cell. A marcher calls `check_cell` on every cell
//! of its Cauchy data and on every cell it completes with a vertex solve.
//!
//! Symmetry transfer (Prop. 5.17): if the group acts on the fibres by
//! isometries and leaves 𝓛·vol invariant, every rule here gives an invariant
//! discrete Lagrangian, because the fibre logarithms are equivariant.
//!
//! Files: [`nodes`] (node maps, [`permutation`]), [`smooth`] (density trait,
//! the seed 002 adapter [`SpaceTime`]), [`rules`] (Lemma 5.15, vertex
//! quadratures), [`affine`] (Prop. 5.20, Q_mid, cube centre; its exact
//! derivatives by the interpolant's chain rule in [`affine_chain`]), [`suitability`]
//! (Def. 5.9, Lemma 5.5, Cor. 6.3), [`cosserat`] (the rod),
//! [`rod_potential`] (its external potentials), [`error`].
//!
//! ```
//! use nalgebra::{Matrix3, Vector3};
//! use veselov::field::cell::{DiscreteLagrangian, vertex_gradient};
//! use veselov::field::complex::TopCell;
//! use veselov::field::discretize::{CellCheck, CfkNodes, CosseratCell, CosseratDensity, RodParameters, VertexRule};
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
//!
//! [`DiscreteLagrangian::cell_lagrangian`]: crate::field::cell::DiscreteLagrangian::cell_lagrangian

pub mod affine;
pub mod affine_chain;
pub mod cosserat;
pub mod cosserat_step;
pub mod error;
mod metric_run;
mod metric_star;
mod metric_terms;
pub mod nodes;
pub mod rod_potential;
pub mod rules;
pub mod smooth;
pub mod suitability;

pub use affine::{AffineJet, CubeCentreRule, MidpointRule, affine_jet, cube_centre_jet};
pub use cosserat::{CosseratCell, CosseratDensity, RodLoads, RodParameters, ShearFrame};
pub use error::CellError;
pub use nodes::{CfkNodes, CubeNodes, NodeMap, cube_corner, factorial, permutation};
pub use rod_potential::{LinearPotential, NoPotential, RodPotential, Weight};
pub use rules::{SINGULAR_NODES, VertexQuadrature, VertexRule, invert, vertex_jet};
pub use smooth::{SmoothDensity, SpaceTime, energy_density, energy_momentum_density, momentum_density, time_flux};
pub use suitability::{CellCheck, GeodesicBall, check_rotations};
