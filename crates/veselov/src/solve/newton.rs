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
        if let Some(stop) = stopped(it, update, last_update, options) {
            return Ok(NewtonReport {
                iterations: it,
                last_update: update,
                residual: system.accept(),
                stop,
            });
        }
        last_update = update;
    }
    Err(no_convergence(step, t, residual, options, "Newton"))
}

/// Whether an iteration that just made the relative update `update` (the one
/// before: `previous`) has converged (`tol`) or stalled at round-off.
fn stopped(it: usize, update: f64, previous: f64, options: &NewtonOptions) -> Option<NewtonStop> {
    if update <= options.tol {
        Some(NewtonStop::Converged)
    } else if it > 1 && update >= previous && update <= options.stall_threshold {
        Some(NewtonStop::RoundOff)
    } else {
        None
    }
}

/// The failure of an iteration named `what` that ended at `residual`.
fn no_convergence(step: usize, t: f64, residual: f64, options: &NewtonOptions, what: &str) -> Error {
    Error::NewtonFailure {
        step,
        t,
        residual,
        iterations: options.max_iterations,
        reason: if residual.is_finite() {
            format!("{what}: no convergence within the iteration limit")
        } else {
            format!("{what}: non-finite residual or update")
        },
    }
}

/// A [`NewtonSystem`] that can also evaluate its residual alone (cheaper
/// than the Jacobian) and keeps a factored Jacobian between solves: what
/// [`solve_simplified_newton`] needs.
pub trait SimplifiedNewtonSystem: NewtonSystem {
    /// Evaluate the residual alone at the current unknowns and write `−R`
    /// into the update `δ`, leaving the factored Jacobian untouched; returns `‖R‖∞`.
    fn residual_only(&mut self) -> f64;
    /// Whether the linear system holds a factored Jacobian that may be reused
    /// (set by the solver; cleared by whoever overwrites the storage).
    fn kept_jacobian(&mut self) -> &mut bool;
}

/// With the kept Jacobian, at most this many more iterations may be
/// foreseen (from the last contraction factor) before the Jacobian is
/// evaluated afresh: an exact Jacobian costs a few residuals and then
/// converges in one or two. (Measured on the Galerkin benchmarks: 3 lets
/// the double pendulum take 4.6 residuals and 0.26 Jacobians per step,
/// 2 takes 4.0 and 0.62 and is 13 % faster; 1 refreshes almost every step.)
const MAX_FORESEEN_ITERATIONS: i32 = 2;

/// Whether the simplified iteration, contracting by `θ = update / previous`,
/// would need more than [`MAX_FORESEEN_ITERATIONS`] `k` further iterations
/// to bring `update` down to `tol`: `ln(tol/update)/ln θ > k`, that is
/// `update·θᵏ > tol` (both logarithms are negative).
fn slow(update: f64, previous: f64, tol: f64) -> bool {
    let theta = update / previous;
    if theta.is_nan() || theta >= 1.0 {
        return true;
    }
    update * theta.powi(MAX_FORESEEN_ITERATIONS) > tol
}

/// Simplified Newton's method: `J δ = −R` with the factored Jacobian kept
/// in `system` from earlier iterations and solves, re-evaluated (exactly, at
/// the current iterate) only when none is kept or the last contraction
/// factor foretells more than two further iterations. No line search: a failure (non-finite values, no
/// convergence) returns an error and clears the kept Jacobian, and the
/// caller may fall back to [`solve_newton`]. Convergence as in
/// [`solve_newton`]: the update at `options.tol` relative, or stalled below
/// `options.stall_threshold`. Returns the report (iterations = residual
/// evaluations) and the number of Jacobians evaluated.
///
/// # Errors
/// A singular Jacobian, a non-finite residual or update, or no convergence
/// within `options.max_iterations`.
pub fn solve_simplified_newton<S: SimplifiedNewtonSystem>(
    system: &mut S,
    options: &NewtonOptions,
    step: usize,
    t: f64,
) -> Result<(NewtonReport, usize)> {
    // A refresh evaluates the residual with the Jacobian (−R already in δ).
    let refresh = |system: &mut S| -> Result<f64> {
        *system.kept_jacobian() = false;
        let residual = system.evaluate();
        system.assemble();
        system.linear_system().0.factor(S::LINEARISATION)?;
        *system.kept_jacobian() = true;
        Ok(residual)
    };
    let mut jacobians = 0;
    let mut fresh = false;
    let mut pending = None;
    if !*system.kept_jacobian() {
        pending = Some(refresh(system)?);
        jacobians += 1;
        fresh = true;
    }
    let (mut previous, mut residual) = (f64::INFINITY, f64::INFINITY);
    for it in 1..=options.max_iterations {
        residual = match pending.take() {
            Some(r) => r,
            None => system.residual_only(),
        };
        if !residual.is_finite() {
            break;
        }
        let largest = {
            let (lu, delta) = system.linear_system();
            lu.solve(delta);
            if delta.iter().any(|d| !d.is_finite()) {
                break;
            }
            delta.iter().fold(0.0_f64, |s, d| s.max(d.abs()))
        };
        let update = largest / system.scale();
        system.update(1.0);
        if let Some(stop) = stopped(it, update, previous, options) {
            let report = NewtonReport {
                iterations: it,
                last_update: update,
                residual: system.accept(),
                stop,
            };
            return Ok((report, jacobians));
        }
        if !fresh && slow(update, previous, options.tol) {
            pending = Some(refresh(system)?);
            jacobians += 1;
            fresh = true;
        } else {
            fresh = false;
        }
        previous = update;
    }
    *system.kept_jacobian() = false;
    Err(no_convergence(step, t, residual, options, "simplified Newton"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `R(x) = (x₀² + x₁² − 4, x₀ − x₁ + c)`: a circle cut by a line moved by `c`.
    struct Circle {
        x: [f64; 2],
        c: f64,
        delta: [f64; 2],
        lu: DenseLu,
        kept: bool,
        jacobians: usize,
        residuals: usize,
    }

    impl Circle {
        fn new(x: [f64; 2], c: f64) -> Self {
            Self {
                x,
                c,
                delta: [0.0; 2],
                lu: DenseLu::new(2),
                kept: false,
                jacobians: 0,
                residuals: 0,
            }
        }
        fn residual(&self) -> [f64; 2] {
            let [a, b] = self.x;
            [a * a + b * b - 4.0, a - b + self.c]
        }
    }

    impl NewtonSystem for Circle {
        const LINEARISATION: &'static str = "circle";
        fn evaluate(&mut self) -> f64 {
            self.jacobians += 1;
            let r = self.residual();
            r[0].abs().max(r[1].abs())
        }
        fn assemble(&mut self) {
            let r = self.residual();
            self.delta = [-r[0], -r[1]];
            let [a, b] = self.x;
            self.lu.matrix.copy_from_slice(&[2.0 * a, 2.0 * b, 1.0, -1.0]);
        }
        fn linear_system(&mut self) -> (&mut DenseLu, &mut [f64]) {
            (&mut self.lu, &mut self.delta)
        }
        fn scale(&self) -> f64 {
            self.x[0].abs().max(self.x[1].abs()).max(1.0)
        }
        fn trial_residual(&mut self, _lambda: f64) -> f64 {
            unreachable!("no line search in the simplified iteration")
        }
        fn update(&mut self, lambda: f64) {
            self.x[0] += lambda * self.delta[0];
            self.x[1] += lambda * self.delta[1];
        }
        fn accept(&mut self) -> f64 {
            let r = self.residual();
            r[0].abs().max(r[1].abs())
        }
    }

    impl SimplifiedNewtonSystem for Circle {
        fn residual_only(&mut self) -> f64 {
            self.residuals += 1;
            let r = self.residual();
            self.delta = [-r[0], -r[1]];
            r[0].abs().max(r[1].abs())
        }
        fn kept_jacobian(&mut self) -> &mut bool {
            &mut self.kept
        }
    }

    /// Converges to round-off; a nearby problem reuses the kept Jacobian
    /// (no new evaluation); a distant one foresees slow contraction and
    /// evaluates a fresh Jacobian rather than iterating on.
    #[test]
    fn reuses_the_jacobian_while_it_contracts() {
        let options = NewtonOptions::default();
        let mut system = Circle::new([1.5, 1.5], 0.1);
        let (report, jacobians) = solve_simplified_newton(&mut system, &options, 0, 0.0).expect("converges");
        // From a start 0.1 away the first Jacobian contracts slowly at first: refreshed once or twice.
        assert!((1..=3).contains(&jacobians), "{jacobians} {report:?}");
        assert!(report.residual <= 1e-14, "{report:?}");
        // A slightly moved line, from the last solution: the kept factors do.
        system.c = 0.1001;
        let (report, jacobians) = solve_simplified_newton(&mut system, &options, 0, 0.0).expect("converges");
        assert_eq!(jacobians, 0, "{report:?}");
        assert!(report.residual <= 1e-14 && report.iterations <= 5, "{report:?}");
        // A far move: the stale Jacobian contracts too slowly and is refreshed.
        system.c = 1.0;
        let (report, jacobians) = solve_simplified_newton(&mut system, &options, 0, 0.0).expect("converges");
        assert!(jacobians >= 1, "{report:?}");
        assert!(report.residual <= 1e-14, "{report:?}");
        let [a, b] = system.x;
        assert!((a * a + b * b - 4.0).abs() < 1e-14 && (a - b + 1.0).abs() < 1e-14);
    }

    /// A residual that never vanishes (the line misses the circle) is an
    /// error, and the kept Jacobian is dropped.
    #[test]
    fn failure_clears_the_kept_jacobian() {
        let options = NewtonOptions {
            max_iterations: 30,
            ..NewtonOptions::default()
        };
        let mut system = Circle::new([1.5, 1.5], 5.0);
        assert!(solve_simplified_newton(&mut system, &options, 3, 0.5).is_err());
        assert!(!system.kept);
    }
}
