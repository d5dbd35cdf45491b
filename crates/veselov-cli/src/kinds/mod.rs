//! The kinds of scenario the command runs, one folder each: its schema, its
//! jobs with their observers, and its figures.

pub mod beam;
pub mod cfk;
pub mod lattice;
pub mod mechanics;
pub mod rigid;
pub mod rod;
