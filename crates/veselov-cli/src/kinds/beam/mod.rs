//! The geometrically exact beam on SE(3) (`[model] name = "beam"`, seed
//! 000): seed 000's multisymplectic Lie-group integrator on the library's
//! beam ([`veselov::models::beam`]), marching in time, or in space on the
//! paper's time grid and prescribed columns (seed 000 §5).
//!
//! [`schema`] holds the scenario's tables and [`setup`] validates them into
//! the beam; [`run`] marches it with the observer of [`observer`];
//! [`figures`] draws the centreline, the momentum map and the energy.

pub mod figures;
pub mod observer;
pub mod run;
pub mod schema;
pub mod setup;
