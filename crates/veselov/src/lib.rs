//! # Veselov
//!
//! Structure-preserving variational integrators. Write a Lagrangian once,
//! generic over an automatic-differentiation scalar; pick a discrete Lagrangian
//! (midpoint, trapezoid, α-rule, Galerkin Lobatto or Gauss of any order); get a
//! trajectory and the diagnostics that show the structure is kept: energy
//! error, Noether momenta, symplecticity defect, measured convergence order.
//!
//! ## Where each concept lives
//!
//! In the order a reader meets them. The five papers are named by their
//! authors: Marsden–Patrick–Shkoller (MPS), "Multisymplectic geometry,
//! variational integrators, and nonlinear PDEs"; Chen–Guo–Wu (CGW), "Total
//! variation and variational symplectic-energy-momentum integrators";
//! Martín de Diego–Sato Martín de Almagro (MdD–SMdA), "Variational order for
//! forced Lagrangian systems"; Demoures–Gay-Balmaz–Ratiu (DGR),
//! "Multisymplectic variational integrators and space/time symplecticity";
//! Casimiro–Rodrigo (CR), "Symmetry-preserving discretization of variational
//! field theories".
//!
//! | module | what it holds | paper |
//! |---|---|---|
//! | [`ad`], [`error`] | the AD scalar bound; typed errors | |
//! | [`tableau`], [`solve`], [`special`] | Lobatto/Gauss coefficients in double-double; Newton, dense and block-tridiagonal solves; elliptic functions, Kepler's equation | |
//! | [`expr`] | user expressions over AD scalars | |
//! | [`mechanics`] | Lagrangians on ℝⁿ, Galerkin discrete Lagrangians, discrete Legendre transforms, forcing, Galley duplication, Noether momenta | MPS §2–3; MdD–SMdA |
//! | [`sem`] | variable-step symplectic-energy-momentum integrators | CGW |
//! | [`lie`], [`lgvi`] | SO(3), SE(3), retractions; Lie-group variational integrators | DGR (Lie-group versions); CR (the SO(3) toolkit) |
//! | [`complex`] | cellular complexes: cubic, CFK, meshes, windows, the 1+1 lattices | CR §2 |
//! | [`field`] | the discrete field theory core on any complex and fibre: cell Lagrangians, Euler–Lagrange, Noether, vertex solve, marchers, quadrature rules | CR §3–5 |
//! | [`spacetime`] | fields on 1+1 lattices: triangle and rectangle rules, the fast sine-Gordon schemes, energies and charges | MPS §4–5 |
//! | [`evolution`] | split Lagrangians, time and space evolution, evolution momentum maps | DGR |
//! | [`models`] | the problem zoo, the geometrically exact beam ([`models::beam`]) and the Cosserat rod ([`models::rod`]) | DGR §5; CR §6 |
//! | [`diagnostics`] | energy, momentum maps, symplecticity defect, order fit | |
//! | [`run`] | one stepping driver with observers and checkpoints | |
//!
//! ## A first integrator
//!
//! ```
//! use nalgebra::{SVector, Vector2};
//! use veselov::ad::Scalar;
//! use veselov::mechanics::{
//!     GalerkinIntegrator, GalerkinScheme, Lagrangian, Method, PhaseState, integrate, momentum_map,
//! };
//! use veselov::models::Kepler;
//!
//! // L = ½|v|² + 1/|q|, written once for every scalar type.
//! struct MyKepler;
//! impl Lagrangian<2> for MyKepler {
//!     fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
//!         (v[0] * v[0] + v[1] * v[1]) * 0.5 + (q[0] * q[0] + q[1] * q[1]).sqrt().recip()
//!     }
//! }
//!
//! let scheme = GalerkinScheme::new(Method::GalerkinGauss(2)).unwrap(); // order 4
//! let mut integrator = GalerkinIntegrator::new(MyKepler, scheme, 0.01).unwrap();
//! let x0 = PhaseState::new(0.0, Vector2::new(0.5, 0.0), Vector2::new(0.0, 3f64.sqrt()));
//! let run = integrate(&mut integrator, x0, 1000, 100);
//! assert!(run.failure.is_none());
//! let angular = Kepler::angular_symmetry();
//! let (j0, j1) = (momentum_map(&angular, &x0.q, &x0.p), momentum_map(&angular, &run.last().q, &run.last().p));
//! assert!((j1 - j0).abs() < 1e-13);
//! ```

pub mod ad;
pub mod complex;
pub mod diagnostics;
pub mod error;
pub mod evolution;
pub mod expr;
pub mod field;
pub mod lgvi;
pub mod lie;
pub mod mechanics;
pub mod models;
pub mod run;
pub mod sem;
pub mod solve;
pub mod spacetime;
pub mod special;
pub mod tableau;
#[cfg(test)]
mod test_support;

pub use error::{Error, Result};
/// The `nalgebra` this crate is built with (vectors and matrices of its API).
pub use nalgebra;
/// The `num_dual` this crate is built with (the dual numbers of [`ad::Scalar`]).
pub use num_dual;

/// The README's Rust examples, compiled and run as doc-tests.
#[cfg(doctest)]
#[doc = include_str!("../../../README.md")]
pub struct ReadmeExamples;
