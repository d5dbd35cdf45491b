//! Newton iteration settings and reports shared by every implicit step.
//!
//! Convergence is declared on the size of the Newton update relative to the
//! size of the unknowns, `‖Δx‖∞ ≤ tol · max(1, ‖x‖∞)`, with a default `tol`
//! a few units of round-off, so structure is kept to round-off. Because the
//! last digits of a residual are noise, the iteration also stops when the
//! update stops shrinking ("stall") once it is already below `stall_threshold`;
//! a stall above that threshold is a failure.

/// Tolerances and limits of the Newton iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Relative update size at which the iteration has converged.
    pub tol: f64,
    /// A non-decreasing update below this relative size counts as converged (round-off reached).
    pub stall_threshold: f64,
    /// Iteration limit.
    pub max_iterations: usize,
    /// Backtracking halvings allowed in the line search.
    pub max_backtracks: usize,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            tol: 4.0 * f64::EPSILON,
            stall_threshold: 1e-9,
            max_iterations: 50,
            max_backtracks: 20,
        }
    }
}

/// Why a Newton iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NewtonStop {
    /// Update below `tol`.
    Converged,
    /// Update stopped shrinking below `stall_threshold`: round-off reached.
    RoundOff,
}

/// What a converged Newton iteration reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonReport {
    /// Iterations performed (Jacobian evaluations).
    pub iterations: usize,
    /// Infinity norm of the last update, relative to the unknowns.
    pub last_update: f64,
    /// Infinity norm of the residual at the returned point.
    pub residual: f64,
    /// How it stopped.
    pub stop: NewtonStop,
}
