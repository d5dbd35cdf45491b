//! No allocation inside a time step or a lattice level: a counting global
//! allocator watches the steps.
//!
//! One test binary per area: the modules below were separate test files,
//! and keep their names (`cargo test -p veselov --test no_allocation <module>::`).

#[allow(unsafe_code)] // a counting global allocator needs `unsafe impl GlobalAlloc`
#[path = "../support/counting_alloc.rs"]
mod counting_alloc;

mod beam_no_allocation;
mod field_no_allocation;
mod no_allocation;
