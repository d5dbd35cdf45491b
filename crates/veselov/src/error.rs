//! Typed errors. Every failure is a value that carries the context needed to
//! act on it: which input was at fault, or at which step and time a solve failed.

use thiserror::Error;

/// Result alias used throughout the crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Everything that can go wrong in Veselov.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// An input value is NaN or infinite.
    #[error("non-finite value in `{what}` (component {index}: {value})")]
    NonFinite {
        /// Name of the input (e.g. `q0`, `p0`, `h`).
        what: String,
        /// Index of the first offending component.
        index: usize,
        /// The offending value.
        value: f64,
    },
    /// Two objects that must agree in dimension do not.
    #[error("dimension mismatch in `{what}`: expected {expected}, got {got}")]
    DimensionMismatch {
        /// What was being checked.
        what: String,
        /// Expected dimension.
        expected: usize,
        /// Received dimension.
        got: usize,
    },
    /// A step size that is not strictly positive and finite.
    #[error("time step must be positive and finite, got h = {h}")]
    InvalidStep {
        /// The offending step.
        h: f64,
    },
    /// A parameter outside its admissible range.
    #[error("invalid value for `{name}` = {value}: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: String,
        /// Its value, formatted.
        value: String,
        /// What was expected.
        reason: String,
    },
    /// The velocity Hessian ∂²L/∂v² is singular (degenerate Lagrangian) where it must be inverted.
    #[error("singular velocity Hessian ∂²L/∂v² at t = {t} (|pivot| = {pivot:e}): the Lagrangian is degenerate here")]
    SingularVelocityHessian {
        /// Time at which the Hessian was evaluated.
        t: f64,
        /// Smallest pivot magnitude met in the factorisation.
        pivot: f64,
    },
    /// A linear system inside a solver was singular.
    #[error("singular Jacobian in {context} (|pivot| = {pivot:e})")]
    SingularJacobian {
        /// Where it happened.
        context: String,
        /// Smallest pivot magnitude.
        pivot: f64,
    },
    /// Newton's method did not converge.
    #[error(
        "Newton did not converge at step {step} (t = {t}): residual {residual:e} after {iterations} iterations ({reason})"
    )]
    NewtonFailure {
        /// Step index (0-based) of the failed step.
        step: usize,
        /// Time at the start of the failed step.
        t: f64,
        /// Residual norm at the last iterate.
        residual: f64,
        /// Iterations performed.
        iterations: usize,
        /// Why it stopped: stalled, diverged, non-finite, iteration limit.
        reason: String,
    },
    /// The energy equation of a variable-step (SEM) step has no admissible root.
    #[error("no admissible time step at step {step} (t = {t}): {reason}")]
    NoStepRoot {
        /// Step index.
        step: usize,
        /// Time at the start of the step.
        t: f64,
        /// What the bracket search saw.
        reason: String,
    },
    /// The energy equation is degenerate here (its h-derivative vanishes: `c(q, p) ≈ 0`).
    #[error("degenerate energy equation at step {step} (t = {t}): {reason}")]
    DegenerateStep {
        /// Step index.
        step: usize,
        /// Time at the start of the step.
        t: f64,
        /// Details.
        reason: String,
    },
    /// The only continuation of the energy equation is a backward (negative) step.
    #[error("only a negative time step solves the energy equation at step {step} (t = {t}): h ≈ {h}")]
    NegativeStep {
        /// Step index.
        step: usize,
        /// Time at the start of the step.
        t: f64,
        /// The negative root found.
        h: f64,
    },
    /// A computed quantity became NaN or infinite during integration.
    #[error("non-finite state at step {step} (t = {t}) in `{what}`")]
    NonFiniteState {
        /// Step index.
        step: usize,
        /// Time.
        t: f64,
        /// Which quantity.
        what: String,
    },
    /// A Lie-group map failed (cut locus of an inverse retraction, a matrix
    /// that is not a rotation, a zero quaternion).
    #[error("Lie group: {0}")]
    Lie(#[from] crate::lie::LieError),
    /// A cellular complex breaks an axiom of Def. 2.1, or a mesh cannot be
    /// oriented or is not a manifold where an orientation is asked for.
    #[error("cellular complex: cell {cell}: {reason}")]
    Complex {
        /// The offending cell, formatted.
        cell: String,
        /// What fails.
        reason: String,
    },
    /// The implicit solve of a lattice time level did not converge.
    #[error(
        "lattice level {level} (t = {t}) did not converge: correction {residual:e} after {iterations} iterations ({reason})"
    )]
    LevelSolveFailure {
        /// Index of the level being computed.
        level: usize,
        /// Time of that level.
        t: f64,
        /// Size of the last correction (max norm) or residual.
        residual: f64,
        /// Iterations performed.
        iterations: usize,
        /// Why it stopped: iteration limit, non-finite, singular.
        reason: String,
    },
    /// A vertex solve Leg_v(y_{Δv}) = μ_v of a Cauchy marcher failed.
    #[error("{vertex} did not converge: residual {residual:e} after {iterations} iterations ({reason})")]
    VertexSolveFailure {
        /// The vertex whose equation was solved: "vertex i of level w" on a
        /// lattice, "vertex v (Δv = u)" on a complex.
        vertex: String,
        /// Residual (max norm) at the last iterate.
        residual: f64,
        /// Iterations performed.
        iterations: usize,
        /// Why it stopped: singular Legendre map, non-finite, iteration limit, cut locus.
        reason: String,
    },
}

/// Check that every component of `x` is finite.
pub fn check_finite<'a>(what: &str, x: impl IntoIterator<Item = &'a f64>) -> Result<()> {
    for (index, &value) in x.into_iter().enumerate() {
        if !value.is_finite() {
            return Err(Error::NonFinite {
                what: what.to_string(),
                index,
                value,
            });
        }
    }
    Ok(())
}

/// Check that a step size is strictly positive and finite.
pub fn check_step(h: f64) -> Result<()> {
    if h.is_finite() && h > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidStep { h })
    }
}

/// The [`Error::InvalidParameter`] for parameter `name` with `value`, refused
/// for `reason`.
pub(crate) fn invalid(name: &str, value: impl std::fmt::Display, reason: &str) -> Error {
    Error::InvalidParameter {
        name: name.to_string(),
        value: value.to_string(),
        reason: reason.to_string(),
    }
}
