//! Newton's method for implicit steps: settings, reports, and the one
//! iteration ([`solve_newton`]) that the Galerkin integrators share.
//!
//! Convergence is declared on the size of the Newton update relative to the
//! size of the unknowns, `‖Δx‖∞ ≤ tol · max(1, ‖x‖∞)`, with a default `tol`
//! a few units of round-off, so structure is kept to round-off. Because the
//! last digits of a residual are noise, the iteration also stops when the
//! update stops shrinking ("stall") once it is already below `stall_threshold`;
//! a stall above that threshold is a failure.
//!
//! [`solve_newton`] runs the iteration on any [`NewtonSystem`]: the system
//! evaluates its residual and exact Jacobian into its own storage (fixed-size
//! vectors with a preallocated [`DenseLu`], or vectors sized at run time), so
//! the iteration itself neither allocates nor knows the storage.

use crate::error::{Error, Result};
use crate::solve::DenseLu;

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

/// How the Newton update is damped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineSearch {
    /// Always take the full Newton update.
    Full,
    /// While the relative update exceeds `10⁻⁶`, halve it (at most
    /// [`NewtonOptions::max_backtracks`] times) until the residual at the trial
    /// point has decreased by the factor `1 − 10⁻⁴λ` (Armijo).
    Backtracking,
}

/// A square system `R(x) = 0` in the unknowns `x`, with its exact Jacobian,
/// solved by [`solve_newton`]. The system owns its unknowns, the Newton update
/// `δ` and the linear-system storage.
pub trait NewtonSystem {
    /// What the linearisation solves, named in a singular-Jacobian error.
    const LINEARISATION: &'static str;
    /// Evaluate everything the residual and the Jacobian need at the current
    /// unknowns; returns `‖R‖∞`.
    fn evaluate(&mut self) -> f64;
    /// Write the Jacobian into the linear system's matrix and `−R` into the update `δ`.
    fn assemble(&mut self);
    /// The linear system: its LU storage (holding the Jacobian after
    /// [`NewtonSystem::assemble`]) and the update `δ` (holding `−R`).
    fn linear_system(&mut self) -> (&mut DenseLu, &mut [f64]);
    /// The size of the unknowns, `max(1, ‖x‖∞)`, that updates are measured against.
    fn scale(&self) -> f64;
    /// `‖R(x + λδ)‖∞`, leaving `x` unchanged (used by [`LineSearch::Backtracking`]).
    fn trial_residual(&mut self, lambda: f64) -> f64;
    /// `x ← x + λδ`.
    fn update(&mut self, lambda: f64);
    /// Called once at the converged point: evaluate what the caller needs
    /// there and return `‖R‖∞`.
    fn accept(&mut self) -> f64;
}

/// Newton's method on `system` with exact Jacobians: `J δ = −R` by dense LU,
/// `x ← x + λδ` (`λ = 1` unless `line_search` backtracks), until the relative
/// update `λ‖δ‖∞ / max(1, ‖x‖∞)` falls below `options.tol`, or stops shrinking
/// below `options.stall_threshold` (round-off). `step` and `t` only label a
/// failure: a non-finite residual or update, or no convergence within
/// `options.max_iterations`, is an [`Error::NewtonFailure`]; a singular
/// Jacobian is the error of [`DenseLu::factor`].
pub fn solve_newton<S: NewtonSystem>(
    system: &mut S,
    options: &NewtonOptions,
    line_search: LineSearch,
    step: usize,
    t: f64,
) -> Result<NewtonReport> {
    let mut last_update = f64::INFINITY;
    let mut residual = f64::INFINITY;
    for it in 1..=options.max_iterations {
        residual = system.evaluate();
        if !residual.is_finite() {
            break;
        }
        system.assemble();
        let largest = {
            let (lu, delta) = system.linear_system();
            lu.factor(S::LINEARISATION)?;
            lu.solve(delta);
            if delta.iter().any(|d| !d.is_finite()) {
                break;
            }
            delta.iter().fold(0.0_f64, |s, d| s.max(d.abs()))
        };
        let full = largest / system.scale();
        let mut lambda = 1.0;
        if line_search == LineSearch::Backtracking && full > 1e-6 {
            for _ in 0..options.max_backtracks {
                let rt = system.trial_residual(lambda);
                if rt.is_finite() && rt <= (1.0 - 1e-4 * lambda) * residual {
                    break;
                }
                lambda *= 0.5;
            }
        }
        system.update(lambda);
        let update = lambda * full;
        let converged = update <= options.tol;
        let stalled = it > 1 && update >= last_update && update <= options.stall_threshold;
        if converged || stalled {
            return Ok(NewtonReport {
                iterations: it,
                last_update: update,
                residual: system.accept(),
                stop: if converged {
                    NewtonStop::Converged
                } else {
                    NewtonStop::RoundOff
                },
            });
        }
        last_update = update;
    }
    Err(Error::NewtonFailure {
        step,
        t,
        residual,
        iterations: options.max_iterations,
        reason: if residual.is_finite() {
            "no convergence within the iteration limit".into()
        } else {
            "non-finite residual".into()
        },
    })
}
