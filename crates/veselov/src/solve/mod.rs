//! Solvers: dense LU factorisation in place, block-tridiagonal systems and Newton's method.

pub mod block_tridiagonal;
pub mod dense;
pub mod newton;
pub mod scalar;

pub use block_tridiagonal::{BlockTridiagonal, BlockTridiagonalLu};
pub use dense::{DenseLu, SmallLu, largest_abs, lu_factor_in_place, lu_solve_in_place, max_abs, solve_small};
pub use newton::{
    LineSearch, NewtonOptions, NewtonReport, NewtonStop, NewtonSystem, SimplifiedNewtonSystem, solve_newton,
    solve_simplified_newton,
};
