//! Tolerances and finite-difference helpers shared by the tests of the special functions.

use super::{JacobiElliptic, SpecialError, jacobi_elliptic, jacobi_elliptic_complement};

pub(super) type TestResult = Result<(), SpecialError>;

pub(super) const EPS: f64 = f64::EPSILON;
/// `π − fl(π)`.
pub(super) const PI_LO: f64 = 1.224_646_799_147_353_2e-16;

pub(super) fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
    }
}

#[track_caller]
pub(super) fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        rel(a, b) <= tol,
        "{what}: {a:e} vs {b:e}, rel {:e} > {tol:e}",
        rel(a, b)
    );
}

#[track_caller]
pub(super) fn close_abs(a: f64, b: f64, tol: f64, what: &str) {
    assert!(
        (a - b).abs() <= tol,
        "{what}: {a:e} vs {b:e}, diff {:e} > {tol:e}",
        (a - b).abs()
    );
}

/// Fourth-order central difference of `f` at `x`.
pub(super) fn derivative(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (8.0 * (f(x + h) - f(x - h)) - (f(x + 2.0 * h) - f(x - 2.0 * h))) / (12.0 * h)
}

/// Fourth-order central second difference of `f` at `x`.
pub(super) fn second_derivative(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (-(f(x + 2.0 * h) + f(x - 2.0 * h)) + 16.0 * (f(x + h) + f(x - h)) - 30.0 * f(x)) / (12.0 * h * h)
}

pub(super) fn jac(u: f64, m: f64) -> JacobiElliptic {
    jacobi_elliptic(u, m).expect("valid arguments")
}

pub(super) fn jac_c(u: f64, m1: f64) -> JacobiElliptic {
    jacobi_elliptic_complement(u, m1).expect("valid arguments")
}
