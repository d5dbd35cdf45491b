//! The discrete field theory core (Casimiro–Rodrigo, "Symmetry-preserving
//! discretization of variational field theories", §3–§5; note 003): fields
//! on any cellular complex of [`crate::complex`] with values in any fibre,
//! their discrete Lagrangians, the variational layer and the marchers. The
//! 1+1 front end of Marsden–Patrick–Shkoller ([`crate::spacetime`]), the
//! time and space evolution of Demoures–Gay-Balmaz–Ratiu
//! ([`crate::evolution`]) and the Cosserat rod ([`crate::models::rod`]) are
//! uses of this core.
//!
//! In the order a reader meets them:
//!
//! * [`fibre`] — the value space at a vertex (ℝ^m, SO(3), SE(3), ℝ³ × SO(3))
//!   with a chart y·τ(ξ) and left-trivialised gradients (note 003 §1.6);
//! * [`cell`] — discrete Lagrangians L_β(y_{v₀}, …) on top cells, written once
//!   over the AD scalar, and their exact vertex gradients and mixed blocks
//!   (note 003 §1.7);
//! * [`variational`] — discrete action, Euler–Lagrange residuals by scatter,
//!   vertex classes of a domain and the discrete Noether theorem (§3,
//!   Thm 3.15);
//! * [`legendre`] — the vertex solve Leg_v(y_{Δv}) = μ_v to round-off
//!   (Def. 4.9, Thm 4.11), shared by every marcher;
//! * [`cauchy`] — the Cauchy integrator on periodic CFK lattices of any
//!   dimension with the flow Δv = v + (1,…,1) (§4, Remark 4.12), levels in
//!   parallel;
//! * [`flow`] — the Cauchy integrator on any finite complex with a
//!   first-order flow Δ (note 003 §2.4);
//! * [`level_solve`] — whole-level Newton solves where one cell holds several
//!   new vertices (the rectangles of the 1+1 front end);
//! * [`boundary_value`] — a global Newton solve on a whole 1+1 space–time
//!   domain, for data where marching cannot apply (both time ends);
//! * [`stepping`] — the CFK marcher as a stepper of the one run driver
//!   ([`crate::run::drive`]);
//! * [`induced`] — the Lagrangian induced on the cubic lattice by the CFK →
//!   cubic map (3.4), whose equations, currents and Legendre maps are the
//!   CFK ones (Props. 3.17–3.19, Remark 4.8);
//! * [`discretize`] — quadrature rules that turn a smooth density over a
//!   fibre into discrete Lagrangians on cells (§5: node maps, Lemma 5.15's
//!   vertex rules, Prop. 5.20's midpoint rule, suitability).

pub mod boundary_value;
pub mod cauchy;
pub mod cell;
pub mod discretize;
pub mod fibre;
pub mod flow;
pub mod induced;
pub mod legendre;
pub mod level_solve;
pub mod stepping;
pub mod variational;

pub use stepping::CauchyStepper;
