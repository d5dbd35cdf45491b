//! Discretising a smooth Lagrangian density (Casimiro–Rodrigo §5; note 003
//! §2.5): node maps, quadrature rules and suitability. The Cosserat rod of
//! the paper's §6 is a model built on these rules, [`crate::models::rod`].
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
//! * [`KarcherMidpointRule`] — Q_mid on curved fibres (SO(3), ℝ³ × SO(3))
//!   at the weighted Karcher mean of Def. 5.4 ([`karcher_mean`]);
//! * the rod's [`CosseratCell`](crate::models::rod::CosseratCell) —
//!   Prop. 6.5's closed form for its density (6.1), with the §3.5 gradients.
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
//! the 1+1 adapter is [`crate::spacetime::SpaceTime`]), [`rules`] (Lemma 5.15, vertex
//! quadratures), [`affine`] (Prop. 5.20, Q_mid, cube centre; its exact
//! derivatives by the interpolant's chain rule in [`affine_chain`]),
//! [`karcher`] (Def. 5.4 at interior nodes, Q_mid on curved fibres), [`suitability`]
//! (Def. 5.9, Lemma 5.5, Cor. 6.3), [`error`].
//!
//! [`DiscreteLagrangian::cell_lagrangian`]: crate::field::cell::DiscreteLagrangian::cell_lagrangian

pub mod affine;
pub mod affine_chain;
mod affine_frame;
pub mod error;
pub mod karcher;
mod metric_lanes;
mod metric_run;
mod metric_star;
mod metric_terms;
pub mod nodes;
pub mod rules;
pub mod smooth;
pub mod suitability;

pub use affine::{AffineJet, CubeCentreRule, MidpointRule, affine_jet, cube_centre_jet};
pub use error::CellError;
pub use karcher::{KarcherMidpointRule, RiemannianFibre, karcher_mean};
pub use nodes::{CfkNodes, CubeNodes, NodeMap, SINGULAR_NODES, cube_corner, factorial, invert, permutation};
pub use rules::{VertexQuadrature, VertexRule, vertex_jet};
pub use smooth::{SmoothDensity, energy_density, energy_momentum_density, momentum_density, time_flux};
pub use suitability::{CellCheck, GeodesicBall, check_rotations};
