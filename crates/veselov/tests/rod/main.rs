//! The Cosserat rod on the leapfrog CFK lattice (seed 003 §6).
//!
//! One test binary per area: the modules below were separate test files,
//! and keep their names (`cargo test -p veselov --test rod <module>::`).

#[path = "../support/rk4.rs"]
mod rk4;
#[path = "../support/threads.rs"]
mod threads;
#[path = "../support/timoshenko.rs"]
mod timoshenko;

mod reissner;
mod rod_ends;
mod rod_fast;
mod rod_free;
mod rod_lanes;
mod rod_loads;
mod rod_stability;
mod rod_vibration;
mod sample;
