//! Special functions and closed-form reference solutions.
//!
//! Everything here is `f64`, depends on `std` only, and is meant as ground
//! truth for the integrators: each routine is accurate to a few units in the
//! last place where the function is well conditioned, and to a few times its
//! condition number in units of `ε` elsewhere.
//!
//! The parameter convention for elliptic integrals and functions is
//! `m = k²` throughout (Abramowitz & Stegun, chapters 16–17).
//!
//! * `elliptic.rs`: complete integrals `K`, `E` and the incomplete integral `F`;
//! * `jacobi.rs`: Jacobi elliptic functions `sn`, `cn`, `dn` and the amplitude `am`;
//! * `kepler.rs`: Kepler's equation and the exact Kepler orbit;
//! * `exact.rs`: exact pendulum and harmonic-oscillator solutions;
//!
//! while this file (`mod.rs`) holds the error type, the argument checks and the argument
//! reductions they share. Every function is re-exported here, so the paths
//! `veselov::special::…` do not depend on the file layout.

mod elliptic;
mod exact;
mod jacobi;
mod kepler;
#[cfg(test)]
mod test_support;

pub use elliptic::{
    complete_elliptic_e, complete_elliptic_e_complement, complete_elliptic_k, complete_elliptic_k_complement,
    incomplete_elliptic_f,
};
pub use exact::{harmonic_exact, pendulum_exact, pendulum_period};
pub use jacobi::{JacobiElliptic, jacobi_elliptic, jacobi_elliptic_complement};
pub use kepler::{kepler_exact, solve_kepler_equation};

use std::f64::consts::{PI, TAU};
use std::fmt;

/// `π/2 − fl(π/2)`.
const FRAC_PI_2_LO: f64 = 6.123_233_995_736_766e-17;
/// `2π − fl(2π)`.
const TAU_LO: f64 = 2.449_293_598_294_706_4e-16;

/// An argument outside the domain of a special function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpecialError {
    /// Name of the offending parameter, e.g. `"m"` or `"e"`.
    pub parameter: &'static str,
    /// The value that was passed.
    pub value: f64,
    /// The condition the parameter has to satisfy.
    pub requirement: &'static str,
}

impl SpecialError {
    fn new(parameter: &'static str, value: f64, requirement: &'static str) -> Self {
        Self {
            parameter,
            value,
            requirement,
        }
    }
}

impl fmt::Display for SpecialError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "invalid {} = {}: {}", self.parameter, self.value, self.requirement)
    }
}

impl std::error::Error for SpecialError {}

fn finite(parameter: &'static str, value: f64) -> Result<f64, SpecialError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SpecialError::new(parameter, value, "must be finite"))
    }
}

/// Checks `lo ≤ x ≤ hi` (false for NaN).
fn in_closed(
    parameter: &'static str,
    x: f64,
    lo: f64,
    hi: f64,
    requirement: &'static str,
) -> Result<f64, SpecialError> {
    if x >= lo && x <= hi {
        Ok(x)
    } else {
        Err(SpecialError::new(parameter, x, requirement))
    }
}

/// `x − jP` with `j = round(x/P)` and `P = hi + lo` given in two parts, so the
/// remainder is correct to its own round-off for moderate `|j|`. Returns the
/// remainder and `j`.
fn reduce(x: f64, hi: f64, lo: f64) -> (f64, f64) {
    let j = (x / hi).round();
    if j == 0.0 {
        return (x, 0.0);
    }
    let r = (-j).mul_add(hi, x);
    ((-j).mul_add(lo, r), j)
}

/// `x mod 2π` in `[−π, π]`: two-part reduction for moderate `|x|`, and
/// `atan2(sin x, cos x)` (whose argument reduction is exact) beyond.
fn reduce_tau(x: f64) -> f64 {
    if x.abs() <= PI {
        return x;
    }
    if x.abs() > 1e15 {
        return x.sin().atan2(x.cos());
    }
    let (mut r, _) = reduce(x, TAU, TAU_LO);
    if r.abs() > PI {
        // rounding left the remainder just outside [−π, π]
        let shift = r.signum();
        r = (-shift).mul_add(TAU, (-shift).mul_add(TAU_LO, r));
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_input_is_an_error() {
        let nan = f64::NAN;
        let inf = f64::INFINITY;
        for m in [-1e-300, -0.5, 1.0 + 1e-15, 2.0, nan, inf] {
            assert!(jacobi_elliptic(0.5, m).is_err(), "m = {m}");
            assert!(jacobi_elliptic_complement(0.5, m).is_err(), "m1 = {m}");
            assert!(complete_elliptic_k(m).is_err());
            assert!(complete_elliptic_e(m).is_err());
            assert!(complete_elliptic_k_complement(m).is_err());
            assert!(complete_elliptic_e_complement(m).is_err());
            assert!(incomplete_elliptic_f(0.5, m).is_err());
        }
        assert!(complete_elliptic_k(1.0).is_err());
        assert!(complete_elliptic_k_complement(0.0).is_err());
        assert!(incomplete_elliptic_f(0.5, 1.0).is_err());
        for u in [nan, inf, -inf] {
            assert!(jacobi_elliptic(u, 0.5).is_err());
            assert!(jacobi_elliptic_complement(u, 0.5).is_err());
            assert!(incomplete_elliptic_f(u, 0.5).is_err());
        }
        for e in [1.0, 1.5, -0.1, nan, inf] {
            assert!(solve_kepler_equation(1.0, e).is_err(), "e = {e}");
            assert!(kepler_exact(e, 1.0).is_err(), "e = {e}");
        }
        for x in [nan, inf, -inf] {
            assert!(solve_kepler_equation(x, 0.5).is_err());
            assert!(kepler_exact(0.5, x).is_err());
            assert!(pendulum_exact(x, 0.0, 1.0, 1.0).is_err());
            assert!(pendulum_exact(0.0, x, 1.0, 1.0).is_err());
            assert!(pendulum_exact(0.0, 0.0, x, 1.0).is_err());
            assert!(pendulum_exact(0.0, 0.0, 1.0, x).is_err());
            assert!(pendulum_period(x, 1.0).is_err());
            assert!(harmonic_exact(x, 0.0, 1.0, 1.0, 1.0).is_err());
            assert!(harmonic_exact(0.0, 0.0, 1.0, x, 1.0).is_err());
        }
        assert!(pendulum_exact(0.0, 1e300, 1e-300, 1.0).is_err());
        assert!(pendulum_exact(0.0, 0.1, 0.0, 1.0).is_err());
        assert!(pendulum_exact(0.0, 0.1, -1.0, 1.0).is_err());
        assert!(pendulum_period(3.2, 1.0).is_err());
        assert!(pendulum_period(1.0, 0.0).is_err());
        assert!(harmonic_exact(0.0, 0.0, 0.0, 1.0, 1.0).is_err());
        assert!(harmonic_exact(0.0, 0.0, 1.0, -1.0, 1.0).is_err());
    }

    #[test]
    fn error_names_parameter_and_value() {
        let err = solve_kepler_equation(1.0, 1.5).expect_err("e = 1.5 is invalid");
        assert_eq!((err.parameter, err.value), ("e", 1.5));
        let text = err.to_string();
        assert!(text.contains('e') && text.contains("1.5"), "{text}");
        let err = jacobi_elliptic(0.0, 2.0).expect_err("m = 2 is invalid");
        assert_eq!(err.parameter, "m");
        assert!(err.to_string().contains("m = 2"));
        let err = pendulum_exact(0.0, 1.0, -3.0, 0.0).expect_err("ω₀ < 0 is invalid");
        assert!(err.to_string().contains("omega0 = -3"));
        let boxed: Box<dyn std::error::Error> = Box::new(err);
        assert!(!boxed.to_string().is_empty());
    }
}
