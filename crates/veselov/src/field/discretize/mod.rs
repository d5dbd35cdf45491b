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
//! the seed 002 adapter [`SpaceTime`]), [`rules`] (Lemma 5.15, Prop. 5.20,
//! quadratures, suitability), [`cosserat`] (the rod), [`error`].
//!
//! [`DiscreteLagrangian::cell_lagrangian`]: crate::field::cell::DiscreteLagrangian::cell_lagrangian

pub mod cosserat;
pub mod error;
pub mod nodes;
pub mod rules;
pub mod smooth;

pub use cosserat::{CosseratCell, CosseratDensity, LinearPotential, NoPotential, RodParameters, RodPotential};
pub use error::CellError;
pub use nodes::{CfkNodes, CubeNodes, NodeMap, cube_corner, factorial, permutation};
pub use rules::{
    AffineJet, CellCheck, CubeCentreRule, GeodesicBall, MidpointRule, SINGULAR_NODES, VertexQuadrature, VertexRule,
    affine_jet, check_rotations, cube_centre_jet, invert, vertex_jet,
};
pub use smooth::{SmoothDensity, SpaceTime};
