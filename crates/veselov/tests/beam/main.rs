//! The geometrically exact SE(3) beam (seed 000).
//!
//! One test binary per area: the modules below were separate test files,
//! and keep their names (`cargo test -p veselov --test beam <module>::`).

#[path = "../support/checkpoints.rs"]
mod checkpoints;
#[path = "../support/five_point.rs"]
mod five_point;
#[path = "../support/rk4.rs"]
mod rk4;
// The rod's tests also use its mode shapes.
#[allow(dead_code)]
#[path = "../support/timoshenko.rs"]
mod timoshenko;

mod beam_boundary_value;
mod beam_evolution;
mod beam_forces;
mod beam_increment_solve;
mod beam_lagrangian;
mod beam_multisymplectic;
mod beam_noether_forced;
mod beam_paper;
mod beam_space_time;
mod beam_start;
mod beam_symplectic;
mod beam_vibration;
