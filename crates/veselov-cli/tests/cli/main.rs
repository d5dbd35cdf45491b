//! End-to-end tests of the `veselov` binary: scenario files run as the
//! command would be run, their outputs and messages checked.
//!
//! One test binary: the modules below were one file, and are split by topic
//! (`cargo test -p veselov-cli --test cli examples::` runs one of them).

#[path = "../common/mod.rs"]
mod common;

mod book;
mod counts;
mod custom;
mod examples;
mod faults;
mod inputs;
mod keys;
mod lattice;
mod listings;
mod mechanics;
mod plot_inputs;
mod shared;
mod vectors;
mod verdicts;
mod verify;
mod verify_refine;
