//! Kepler's equation and the exact Kepler orbit.
//!
//! * **Kepler problem** `L = ½|v|² + 1/|q|` (`μ = 1`, semi-major axis 1,
//!   period 2π): the eccentric anomaly solves Kepler's equation
//!   `E − e sin E = M`; the orbit through the pericentre `q(0) = (1 − e, 0)`,
//!   `p(0) = (0, √((1 + e)/(1 − e)))` is
//!   `q = (cos E − e, √(1 − e²) sin E)`, `p = (−sin E, √(1 − e²) cos E)/(1 − e cos E)`
//!   with `M = t`. The starter is S. Mikkola's cubic approximation
//!   (Celest. Mech. 40 (1987) 329–334), refined by safeguarded Halley steps.

use super::{SpecialError, finite, reduce_tau};

// ---------------------------------------------------------------------------
// Kepler problem
// ---------------------------------------------------------------------------

/// `x − sin x` for `x ≥ 0` without cancellation near 0.
fn x_minus_sin(x: f64) -> f64 {
    if x < 1.0 {
        // x³/3! − x⁵/5! + … + x¹⁹/19!, truncation < 10⁻¹⁷ x³/6.
        let x2 = x * x;
        let mut term = 0.0;
        let mut n = 19.0_f64;
        while n > 3.0 {
            term = x2 / ((n - 1.0) * n) * (1.0 - term);
            n -= 2.0;
        }
        x * x2 / 6.0 * (1.0 - term)
    } else {
        x - x.sin()
    }
}

/// Mikkola's (1987) cubic starter for `E − e sin E = M`, `M ∈ [0, π]`.
fn kepler_starter(mean: f64, e: f64) -> f64 {
    let den = 4.0 * e + 0.5;
    let alpha = (1.0 - e) / den;
    let beta = 0.5 * mean / den;
    let z = (beta + (beta * beta + alpha * alpha * alpha).sqrt()).cbrt();
    let mut s = z - alpha / z;
    s -= 0.078 * s.powi(5) / (1.0 + e);
    mean + e * s * (3.0 - 4.0 * s * s)
}

/// Eccentric anomaly for `M ≥ 0` (reduced, `M ≲ π`) and `0 < e < 1`.
fn kepler_reduced(mean: f64, e: f64) -> f64 {
    if mean == 0.0 {
        return 0.0;
    }
    let one_minus_e = 1.0 - e;
    // f(E) = (1 − e)E + e(E − sin E) − M: increasing, convex on [0, π],
    // evaluated without cancellation; f' = (1 − e) + 2e sin²(E/2).
    let f = |x: f64| one_minus_e.mul_add(x, e * x_minus_sin(x)) - mean;
    // f(M) = −e sin M ≤ 0, f(M + e) = e(1 − sin(M + e)) ≥ 0 and
    // f(M/(1 − e)) = e(x − sin x) ≥ 0.
    let mut lo = mean;
    let mut hi = (mean + e).min(mean / one_minus_e);
    let mut x = kepler_starter(mean, e).clamp(lo, hi);
    for _ in 0..100 {
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        if fx < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let half = (0.5 * x).sin();
        let d1 = one_minus_e + 2.0 * e * half * half;
        let d2 = e * x.sin();
        let step = fx / (d1 - 0.5 * (fx / d1) * d2);
        if step.abs() <= 4.0 * f64::EPSILON * x {
            return x - step;
        }
        let next = x - step;
        x = if next > lo && next < hi { next } else { 0.5 * (lo + hi) };
        if hi - lo <= 2.0 * f64::EPSILON * hi {
            return x;
        }
    }
    x
}

fn check_eccentricity(e: f64) -> Result<f64, SpecialError> {
    if (0.0..1.0).contains(&e) {
        Ok(e)
    } else {
        Err(SpecialError::new("e", e, "eccentricity must satisfy 0 ≤ e < 1"))
    }
}

/// Solves Kepler's equation `E − e sin E = M` for the eccentric anomaly `E`,
/// for any finite mean anomaly `M` and `0 ≤ e < 1`.
///
/// `M` is reduced to `M_r ∈ [−π, π]` (two-part 2π, or exact reduction for
/// huge `|M|`), the root is bracketed in `[M_r, min(M_r + e, M_r/(1 − e))]`
/// (for `M_r ≥ 0`; `E` is odd in `M`), started from Mikkola's cubic
/// approximation and refined by Halley steps (bisection if a step leaves the
/// bracket), with `E − e sin E` evaluated as `(1 − e)E + e(E − sin E)` so the
/// root is exact to round-off even for `e → 1`, `M → 0`. For `M ≠ M_r` the
/// result is `M + e sin E_r`, in the same revolution as `M`.
pub fn solve_kepler_equation(mean_anomaly: f64, e: f64) -> Result<f64, SpecialError> {
    finite("mean_anomaly", mean_anomaly)?;
    check_eccentricity(e)?;
    if e == 0.0 {
        return Ok(mean_anomaly);
    }
    let r = reduce_tau(mean_anomaly);
    let ecc = kepler_reduced(r.abs(), e).copysign(r);
    // E = M + e sin E carries the revolution of M exactly.
    Ok(if r == mean_anomaly {
        ecc
    } else {
        e.mul_add(ecc.sin(), mean_anomaly)
    })
}

/// Exact state `(q(t), p(t))` of the Kepler problem `L = ½|v|² + 1/|q|`
/// (`μ = 1`, energy `−½`, semi-major axis 1, period 2π) started at the
/// pericentre `q(0) = (1 − e, 0)`, `p(0) = (0, √((1 + e)/(1 − e)))`:
/// ```text
/// q = (cos E − e, √(1 − e²) sin E),   p = (−sin E, √(1 − e²) cos E) / (1 − e cos E),
/// ```
/// with `E − e sin E = t`. Angular momentum `q × p = √(1 − e²)`.
pub fn kepler_exact(e: f64, t: f64) -> Result<([f64; 2], [f64; 2]), SpecialError> {
    finite("t", t)?;
    check_eccentricity(e)?;
    let r = reduce_tau(t);
    let ecc = if e == 0.0 {
        r
    } else {
        kepler_reduced(r.abs(), e).copysign(r)
    };
    let (s, c) = ecc.sin_cos();
    let half = (0.5 * ecc).sin();
    let two_half2 = 2.0 * half * half; // 1 − cos E
    let one_minus_e = 1.0 - e;
    let b = (one_minus_e * (1.0 + e)).sqrt();
    let den = e.mul_add(two_half2, one_minus_e); // 1 − e cos E
    let q = [one_minus_e - two_half2, b * s];
    let p = [-s / den, b * c / den];
    Ok((q, p))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::test_support::*;
    use std::f64::consts::{PI, TAU};

    // --- Kepler -------------------------------------------------------------

    const ECCENTRICITIES: [f64; 12] = [0.0, 1e-8, 0.05, 0.1, 0.3, 0.5, 0.7, 0.8, 0.9, 0.95, 0.99, 0.999];

    #[test]
    fn kepler_equation_residual() -> TestResult {
        let mut worst: f64 = 0.0;
        for e in ECCENTRICITIES {
            for i in -1000..=1000 {
                let mean = PI * i as f64 / 1000.0;
                let ecc = solve_kepler_equation(mean, e)?;
                let residual = (ecc - e * ecc.sin() - mean).abs();
                worst = worst.max(residual);
                assert!(residual <= 1e-15, "e = {e}, M = {mean}: residual {residual:e}");
            }
            // near M = 0, where e → 1 is ill-conditioned: relative residual.
            for mean in [1e-300, 1e-20, 1e-12, 1e-8, 1e-5, 1e-3] {
                let ecc = solve_kepler_equation(mean, e)?;
                let accurate = (1.0 - e) * ecc + e * x_minus_sin(ecc);
                close(accurate, mean, 4.0 * EPS, "relative residual, small M");
                assert!(ecc >= mean && ecc <= mean / (1.0 - e) * (1.0 + EPS));
            }
        }
        assert!(worst > 0.0);
        Ok(())
    }

    #[test]
    fn kepler_equation_revolutions_and_symmetry() -> TestResult {
        for e in ECCENTRICITIES {
            for i in 0..50 {
                let mean = 0.37 * i as f64 + 0.01;
                let ecc = solve_kepler_equation(mean, e)?;
                assert_eq!(solve_kepler_equation(-mean, e)?, -ecc);
                for rev in [-3.0, 1.0, 7.0] {
                    let shifted = solve_kepler_equation(mean + rev * TAU, e)?;
                    close_abs(shifted, ecc + rev * TAU, 8.0 * EPS * (mean.abs() + 50.0), "E(M + 2πj)");
                }
                for big_mean in [mean + 1e4, mean + 1e12, mean * 1e300] {
                    let big = solve_kepler_equation(big_mean, e)?;
                    let residual = (big - e * big.sin() - big_mean).abs();
                    assert!(residual <= 4.0 * EPS * big_mean, "large M residual {residual:e}");
                }
            }
        }
        Ok(())
    }

    #[test]
    fn kepler_orbit_invariants() -> TestResult {
        for e in [0.0_f64, 0.1, 0.5, 0.7, 0.9, 0.99] {
            let b = (1.0 - e * e).sqrt();
            let (q0, p0) = kepler_exact(e, 0.0)?;
            assert_eq!(q0, [1.0 - e, 0.0]);
            close(p0[1], ((1.0 + e) / (1.0 - e)).sqrt(), 2.0 * EPS, "p(0)");
            assert_eq!(p0[0], 0.0);
            for i in -200..=200 {
                let t = 0.0731 * i as f64;
                let (q, p) = kepler_exact(e, t)?;
                let r = q[0].hypot(q[1]);
                let kinetic = 0.5 * (p[0] * p[0] + p[1] * p[1]);
                // Rounding in ½|p|² − 1/|q| is ≈ ε/(1 − e): scale the tolerance.
                let scale = 1.0 / r;
                close_abs(kinetic - 1.0 / r, -0.5, 1e-14 * scale.max(1.0) / 2.0, "energy");
                close_abs(
                    q[0] * p[1] - q[1] * p[0],
                    b,
                    1e-14 * scale.max(1.0) / 2.0,
                    "angular momentum",
                );
                // Kepler's first law: r = 1 − e cos E.
                close_abs(
                    r,
                    1.0 - e * solve_kepler_equation(t, e)?.cos(),
                    8.0 * EPS,
                    "r = 1 − e cos E",
                );
            }
        }
        Ok(())
    }

    #[test]
    fn kepler_orbit_derivative_and_period() -> TestResult {
        for e in [0.0, 0.3, 0.8, 0.95] {
            let (qa, pa) = kepler_exact(e, 0.0)?;
            let (qb, pb) = kepler_exact(e, TAU)?;
            let (qc, pc) = kepler_exact(e, -5.0 * TAU)?;
            for d in 0..2 {
                // fl(2π) = 2π − 2.4e-16; |ṗ| = 1/r² ≤ 1/(1 − e)² at pericentre
                let slope = 1.0 / ((1.0 - e) * (1.0 - e));
                close_abs(qb[d], qa[d], 4.0 * EPS * (1.0 + pa[1]), "q(2π) = q(0)");
                close_abs(pb[d], pa[d], 4.0 * EPS * (1.0 + slope), "p(2π) = p(0)");
                close_abs(qc[d], qa[d], 1e-14, "q(−10π) = q(0)");
                close_abs(pc[d], pa[d], 40.0 * EPS * (1.0 + slope), "p(−10π) = p(0)");
            }
            for i in -40..=40 {
                let t = 0.157 * i as f64 + 0.05;
                let (q, p) = kepler_exact(e, t)?;
                let h = 1e-3 * (1.0 - e);
                for d in 0..2 {
                    let qd = derivative(|s| kepler_exact(e, s).map(|x| x.0[d]).unwrap_or(f64::NAN), t, h);
                    close_abs(qd, p[d], 1e-9 * p[0].hypot(p[1]), "dq/dt = p");
                    // and ṗ = −q/|q|³
                    let pd = derivative(|s| kepler_exact(e, s).map(|x| x.1[d]).unwrap_or(f64::NAN), t, h);
                    let r = q[0].hypot(q[1]);
                    close_abs(pd, -q[d] / (r * r * r), 1e-8 / (r * r), "dp/dt = −q/|q|³");
                }
            }
        }
        Ok(())
    }
}
