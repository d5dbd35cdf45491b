//! The field theory core: complexes, cell Lagrangians, the Cauchy and level
//! marchers, Noether currents, seed 002's 1+1 schemes and fields in 2+1
//! dimensions.
//!
//! One test binary per area: the modules below were separate test files,
//! and keep their names (`cargo test -p veselov --test field <module>::`).

#[path = "../support/checkpoints.rs"]
mod checkpoints;
#[path = "../common/mod.rs"]
mod common;
#[path = "../support/five_point.rs"]
mod five_point;
#[path = "../support/threads.rs"]
mod threads;

mod field_2p1;
mod field_affine_chain;
mod field_complex;
mod field_complex_stokes;
mod field_core;
mod field_cubic_induced;
mod field_density;
mod field_density_run;
mod field_discretize;
mod field_discretize_rod;
mod field_errors;
mod field_flows;
mod field_generic;
mod field_initial;
mod field_karcher;
mod field_level;
mod field_noether;
mod field_noether_cells;
mod field_orders;
mod field_schemes;
mod field_section_5_2;
mod field_sine_gordon;
mod field_wave;
mod shared;
