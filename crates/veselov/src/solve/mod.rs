//! Solvers: dense LU factorisation in place and Newton's method options and reports.

pub mod block_tridiagonal;
pub mod dense;
pub mod newton;
pub mod scalar;

pub use block_tridiagonal::{BlockTridiagonal, BlockTridiagonalLu};
pub use dense::{DenseLu, lu_factor_in_place, lu_solve_in_place, solve_small};
pub use newton::{NewtonOptions, NewtonReport, NewtonStop};
