//! Discrete mechanics: variational integrators, forced systems, variable-step
//! SEM and Lie-group integrators, runs and their resumption.
//!
//! One test binary per area: the modules below were separate test files,
//! and keep their names (`cargo test -p veselov --test mechanics <module>::`).

#[path = "../common/mod.rs"]
mod common;

mod dynamic;
mod forced;
mod kepler_long;
mod lgvi;
mod mechanics_conservation;
mod mechanics_discrete;
mod mechanics_errors;
mod mechanics_orders;
mod mechanics_symplectic;
mod readme_example;
mod run_resume;
mod sem;
mod sem_left_point;
mod sem_reference;
mod sem_structure;
mod separable_start;
mod variational_order;
