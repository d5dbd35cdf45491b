//! Exact solutions of the pendulum and the harmonic oscillator.
//!
//! * **Pendulum** `θ̈ = −ω₀² sin θ`, with conserved energy
//!   `h = ½(θ̇/ω₀)² + 2 sin²(θ/2)` and `m = h/2 = sin²(θ/2) + (θ̇/(2ω₀))²`
//!   (DLMF 22.19.2, 22.19.3):
//!   - libration (`m < 1`): `sin(θ/2) = k sn(τ|m)`, `cos(θ/2) = dn(τ|m)`,
//!     `θ̇ = 2kω₀ cn(τ|m)`, `τ = ω₀t + F(φ₀|m)` where
//!     `φ₀ = atan2(sin(θ₀/2), θ̇₀/(2ω₀))`;
//!   - rotation (`m > 1`): `θ/2 = am(τ|1/m)`, `θ̇ = ±2kω₀ dn(τ|1/m)`,
//!     `τ = F(θ₀/2|1/m) ± kω₀t`, the sign being that of `θ̇₀`;
//!   - separatrix (`m = 1` exactly in floating point), in closed form and
//!     accurate to round-off: `θ = 2 gd(τ) = 4 arctan(e^τ) − π`,
//!     `θ̇ = ±2ω₀ sech τ`, `τ = arsinh(tan(θ₀/2)) ± ω₀t`.
//! * **Harmonic oscillator** `L = ½ m v² − ½ m ω² q²`:
//!   `q = q₀ cos ωt + p₀ sin(ωt)/(mω)`, `p = p₀ cos ωt − mωq₀ sin ωt`.

use std::f64::consts::{FRAC_PI_2, PI};

use super::elliptic::{complete_k, incomplete_f_parts};
use super::jacobi::jacobi_signed;
use super::{FRAC_PI_2_LO, SpecialError, finite, reduce, reduce_tau};

// ---------------------------------------------------------------------------
// Pendulum
// ---------------------------------------------------------------------------

fn check_omega0(omega0: f64) -> Result<f64, SpecialError> {
    if omega0 > 0.0 && omega0.is_finite() {
        Ok(omega0)
    } else {
        Err(SpecialError::new("omega0", omega0, "must be positive and finite"))
    }
}

/// Exact solution `(θ(t), θ̇(t))` of the pendulum `θ̈ = −ω₀² sin θ` with
/// `θ(0) = θ₀`, `θ̇(0) = θ̇₀`, for any finite initial data and `ω₀ > 0`.
///
/// With `m = sin²(θ₀/2) + (θ̇₀/(2ω₀))² = k²` (half the energy
/// `½(θ̇/ω₀)² + 2 sin²(θ/2)`, DLMF 22.19):
/// * libration, `m < 1`: `θ = 2 atan2(k sn(τ|m), dn(τ|m))` (i.e.
///   `sin(θ/2) = k sn`, `cos(θ/2) = dn`), `θ̇ = 2kω₀ cn(τ|m)`,
///   `τ = ω₀t + F(φ₀|m)`, `φ₀ = atan2(sin(θ₀/2), θ̇₀/(2ω₀))`;
///   starting at rest from the amplitude `θ_max` this is
///   `sin(θ/2) = k sn(ω₀t + K|m)`;
/// * rotation, `m > 1`: `θ = 2 am(τ|1/m)`, `θ̇ = 2σkω₀ dn(τ|1/m)`,
///   `τ = F(θ₀/2|1/m) + σkω₀t`, `σ = sign θ̇₀`;
/// * separatrix, `m = 1` exactly in floating point: the closed form
///   `θ = 2 gd(τ) = 4 arctan(e^τ) − π`, `θ̇ = 2σω₀ sech τ`,
///   `τ = arsinh(tan(θ₀/2)) + σω₀t`, evaluated as `2 arctan(sinh τ)`,
///   accurate to round-off.
///
/// `θ₀` is first reduced to `[−π, π]` and the multiple of 2π restored, so
/// the returned `θ` is continuous in `t` (it grows without bound for
/// rotation). Near the separatrix `cos(θ/2)` and `θ̇` keep full relative
/// accuracy; the remaining sensitivity is that of the energy itself, whose
/// complement `m₁ = (cos(θ₀/2) − |w|)(cos(θ₀/2) + |w|)`, `w = θ̇₀/(2ω₀)`,
/// inherits the rounding of `cos(θ₀/2)`.
/// Returns an error for non-finite input, `ω₀ ≤ 0`, or a phase `kω₀t` that
/// overflows.
pub fn pendulum_exact(theta0: f64, thetadot0: f64, omega0: f64, t: f64) -> Result<(f64, f64), SpecialError> {
    finite("theta0", theta0)?;
    finite("thetadot0", thetadot0)?;
    finite("t", t)?;
    check_omega0(omega0)?;
    let w = thetadot0 / (2.0 * omega0);
    if !w.is_finite() {
        return Err(SpecialError::new("thetadot0", thetadot0, "θ̇₀/(2ω₀) overflows"));
    }
    // Work with θ₀ mod 2π ∈ [−π, π] and return θ₀ + (θ − θ_r).
    let theta_r = reduce_tau(theta0);
    let restore = |theta: f64| {
        if theta_r == theta0 {
            theta
        } else {
            theta0 + (theta - theta_r)
        }
    };
    let (sh, ch) = (0.5 * theta_r).sin_cos(); // ch > 0
    let aw = w.abs();
    let k = sh.hypot(w);
    let phase = |tau: f64| {
        if tau.is_finite() {
            Ok(tau)
        } else {
            Err(SpecialError::new("t", t, "phase k·ω₀·t overflows"))
        }
    };
    if ch > aw {
        // Libration: m₁ = cos²(θ₀/2) − w² > 0.
        let m = k * k;
        let m1 = (ch - aw) * (ch + aw);
        let kc = m1.sqrt();
        if m == 0.0 {
            return Ok((theta0, 0.0));
        }
        // φ₀ = atan2(sh, w) = nπ/2 + ρ with |ρ| ≤ π/4, ρ formed without
        // rounding π.
        let (n, rho) = if aw >= sh.abs() {
            (if w > 0.0 { 0.0 } else { 2.0 }, (sh / w).atan())
        } else {
            (sh.signum(), -(w / sh).atan())
        };
        let tau = phase(omega0.mul_add(t, incomplete_f_parts(n, rho, m, m1, kc)))?;
        let j = jacobi_signed(tau, m, kc, "t", t)?;
        let theta = 2.0 * (k * j.sn).atan2(j.dn);
        Ok((restore(theta), 2.0 * k * omega0 * j.cn))
    } else if ch == aw {
        // Separatrix (ch > 0, so w ≠ 0).
        let sigma = w.signum();
        let tau = phase((sigma * omega0).mul_add(t, (sh / ch).asinh()))?;
        let theta = 2.0 * tau.sinh().atan();
        Ok((restore(theta), 2.0 * sigma * omega0 / tau.cosh()))
    } else {
        // Rotation: parameter 1/m = 1/k², complement (w² − cos²(θ₀/2))/k².
        let sigma = w.signum();
        let mr = (1.0 / k) * (1.0 / k);
        let m1r = ((aw - ch) / k) * ((aw + ch) / k);
        let kcr = m1r.sqrt();
        let (rho, n) = reduce(0.5 * theta_r, FRAC_PI_2, FRAC_PI_2_LO);
        let tau0 = incomplete_f_parts(n, rho, mr, m1r, kcr);
        let tau = phase((sigma * k * omega0).mul_add(t, tau0))?;
        let j = jacobi_signed(tau, mr, kcr, "t", t)?;
        Ok((restore(2.0 * j.am), 2.0 * sigma * k * omega0 * j.dn))
    }
}

/// Period of the librating pendulum `θ̈ = −ω₀² sin θ` with amplitude
/// `θ_max` (A&S 17.3, DLMF 22.19.2): `T = 4 K(sin²(θ_max/2)) / ω₀`, for
/// `|θ_max| < π` (the sign of `θ_max` is ignored). `K` is evaluated from
/// the complement `cos²(θ_max/2)`, so the logarithmic growth as
/// `θ_max → π` is resolved.
pub fn pendulum_period(theta0_amplitude: f64, omega0: f64) -> Result<f64, SpecialError> {
    finite("theta0_amplitude", theta0_amplitude)?;
    check_omega0(omega0)?;
    let a = theta0_amplitude.abs();
    if a > PI {
        return Err(SpecialError::new(
            "theta0_amplitude",
            theta0_amplitude,
            "libration needs |θ_max| < π",
        ));
    }
    let (sh, ch) = (0.5 * a).sin_cos();
    Ok(4.0 * complete_k(sh * sh, ch) / omega0)
}

// ---------------------------------------------------------------------------
// Harmonic oscillator
// ---------------------------------------------------------------------------

/// Exact state of the harmonic oscillator `L = ½ m v² − ½ m ω² q²`
/// (momentum `p = m v`) from `(q₀, p₀)` at time 0:
/// `q = q₀ cos ωt + p₀ sin(ωt)/(mω)`, `p = p₀ cos ωt − mω q₀ sin ωt`.
/// `mass > 0`; `ω ≥ 0` (`ω = 0` is the free particle `q = q₀ + p₀t/m`).
pub fn harmonic_exact(q0: f64, p0: f64, mass: f64, omega: f64, t: f64) -> Result<(f64, f64), SpecialError> {
    finite("q0", q0)?;
    finite("p0", p0)?;
    finite("t", t)?;
    if !(mass > 0.0 && mass.is_finite()) {
        return Err(SpecialError::new("mass", mass, "must be positive and finite"));
    }
    if !(omega >= 0.0 && omega.is_finite()) {
        return Err(SpecialError::new("omega", omega, "must be non-negative and finite"));
    }
    let (s, c) = (omega * t).sin_cos();
    let sin_over_omega = if omega == 0.0 { t } else { s / omega };
    Ok((q0 * c + p0 * sin_over_omega / mass, p0 * c - mass * omega * q0 * s))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::test_support::*;
    use crate::special::*;
    use std::f64::consts::{PI, TAU};

    // --- Pendulum -----------------------------------------------------------

    fn pendulum_energy(theta: f64, thetadot: f64, omega0: f64) -> f64 {
        let s = (0.5 * theta).sin();
        0.5 * (thetadot / omega0).powi(2) + 2.0 * s * s
    }

    /// Checks initial data, energy and the equation of motion along a trajectory.
    fn check_pendulum(theta0: f64, thetadot0: f64, omega0: f64) -> TestResult {
        let (a, b) = pendulum_exact(theta0, thetadot0, omega0, 0.0)?;
        close_abs(a, theta0, 4.0 * EPS * (1.0 + theta0.abs()), "θ(0) = θ₀");
        close_abs(b, thetadot0, 8.0 * EPS * (omega0 + thetadot0.abs()), "θ̇(0) = θ̇₀");
        let h0 = pendulum_energy(theta0, thetadot0, omega0);
        // time scale 1/(ω₀(1 + k)), k² = h₀/2
        let rate = omega0 * (1.0 + (0.5 * h0).sqrt());
        let h = 2e-3 / rate;
        for i in -50..=50 {
            let t = 0.173 * i as f64 / omega0;
            let (th, thd) = pendulum_exact(theta0, thetadot0, omega0, t)?;
            close_abs(pendulum_energy(th, thd, omega0), h0, 1e-13 * h0.max(1.0), "energy");
            let f = |s: f64| {
                pendulum_exact(theta0, thetadot0, omega0, s)
                    .map(|x| x.0)
                    .unwrap_or(f64::NAN)
            };
            let g = |s: f64| {
                pendulum_exact(theta0, thetadot0, omega0, s)
                    .map(|x| x.1)
                    .unwrap_or(f64::NAN)
            };
            // truncation (h·rate)⁴ ≈ 2e-11 plus round-off of the stencils
            let speed = rate + thd.abs();
            let round1 = 4.0 * EPS * (1.0 + th.abs()) / h;
            let round2 = 16.0 * EPS * (1.0 + th.abs()) / (h * h);
            let accel = -omega0 * omega0 * th.sin();
            close_abs(
                second_derivative(f, t, h),
                accel,
                1e-8 * rate * speed + round2,
                "θ̈ = −ω₀² sin θ",
            );
            close_abs(derivative(f, t, h), thd, 1e-9 * speed + round1, "dθ/dt = θ̇");
            close_abs(
                derivative(g, t, h),
                accel,
                1e-9 * rate * speed + 4.0 * EPS * speed / h,
                "dθ̇/dt",
            );
        }
        Ok(())
    }

    #[test]
    fn pendulum_libration() -> TestResult {
        for omega0 in [0.5, 1.0, 3.0] {
            for i in 1..=31 {
                let amplitude = 0.1 * i as f64;
                check_pendulum(amplitude, 0.0, omega0)?;
                check_pendulum(-amplitude, 0.0, omega0)?;
                // the same orbits entered elsewhere, moving either way
                let (th, thd) = pendulum_exact(amplitude, 0.0, omega0, 0.77 / omega0)?;
                check_pendulum(th, thd, omega0)?;
                check_pendulum(th, -thd, omega0)?;
                check_pendulum(0.0, 2.0 * omega0 * (0.5 * amplitude).sin(), omega0)?;
            }
        }
        // a libration about 2π·3
        let (a, _) = pendulum_exact(1.0, 0.3, 1.0, 2.0)?;
        let (b, _) = pendulum_exact(1.0 + 6.0 * PI, 0.3, 1.0, 2.0)?;
        close_abs(b, a + 6.0 * PI, 1e-14, "θ₀ + 2πj");
        Ok(())
    }

    #[test]
    fn pendulum_rotation_and_separatrix() -> TestResult {
        for omega0 in [0.5, 1.0, 3.0] {
            for (theta0, w) in [
                (0.0, 1.0001),
                (0.0, 1.5),
                (1.0, 1.2),
                (-2.9, -2.0),
                (3.0, 0.9),
                (-1.0, -7.0),
                (0.4, 40.0),
            ] {
                check_pendulum(theta0, 2.0 * omega0 * w, omega0)?;
            }
            // separatrix: θ̇₀ = 2ω₀ at θ₀ = 0 (m = 1 exactly)
            check_pendulum(0.0, 2.0 * omega0, omega0)?;
            check_pendulum(0.0, -2.0 * omega0, omega0)?;
            for i in -20..=20 {
                let t = 0.5 * i as f64;
                let (th, thd) = pendulum_exact(0.0, 2.0 * omega0, omega0, t)?;
                close_abs(
                    th,
                    4.0 * (omega0 * t).exp().atan() - PI,
                    4.0 * EPS * PI,
                    "separatrix closed form",
                );
                close_abs(
                    thd,
                    2.0 * omega0 / (omega0 * t).cosh(),
                    4.0 * EPS * omega0,
                    "separatrix θ̇",
                );
            }
        }
        // rotation is monotone and gains 2π per period
        let (omega0, w) = (1.3, 1.7);
        let k = 0.1_f64.sin().hypot(w);
        let period = 2.0 * complete_elliptic_k(1.0 / (k * k))? / (k * omega0);
        let (a, _) = pendulum_exact(0.2, 2.0 * omega0 * w, omega0, 0.3)?;
        let (b, _) = pendulum_exact(0.2, 2.0 * omega0 * w, omega0, 0.3 + 5.0 * period)?;
        close_abs(b, a + 10.0 * PI, 1e-13, "rotation period");
        Ok(())
    }

    #[test]
    fn pendulum_reference_trajectories() -> TestResult {
        // Taylor-series integrations of θ̈ = −ω₀² sin θ to 20 digits.
        let cases = [
            (2.0, 0.5, 1.3, 3.7, -2.080_244_562_950_316, 0.090_360_939_113_670_21),
            (1.0, 3.0, 1.3, 2.5, 7.409_188_468_043_854, 2.937_361_876_942_078),
            (-0.4, -2.9, 0.7, 6.1, -16.972_149_564_289_38, -2.685_436_331_037_85),
        ];
        for (theta0, thetadot0, omega0, t, theta, thetadot) in cases {
            let (a, b) = pendulum_exact(theta0, thetadot0, omega0, t)?;
            close_abs(a, theta, 2e-14 * (1.0 + theta.abs()), "θ(t) reference");
            close_abs(b, thetadot, 2e-14, "θ̇(t) reference");
        }
        // m₁ = ∓4·10⁻¹²: just above and just below the separatrix, close to
        // the top at t = 12, where θ̇ must keep its relative accuracy.
        let cases = [
            (2.000_000_000_002, 3.141_568_158_125_011, 2.465_823_404_246_078_6e-5),
            (1.999_999_999_998, 3.141_567_995_364_784_6, 2.449_547_381_701_609_6e-5),
        ];
        for (thetadot0, theta, thetadot) in cases {
            let (a, b) = pendulum_exact(0.0, thetadot0, 1.0, 12.0)?;
            close(a, theta, 2.0 * EPS, "θ near the separatrix");
            // relative condition number |θ̈ t/θ̇| ≈ 12
            close(b, thetadot, 40.0 * EPS, "θ̇ near the separatrix");
        }
        // m₁ = ∓3.7·10⁻⁸ with 1/m not exactly representable, just past the top
        let cases = [
            (2.000_000_037_1, 3.142_081_179_506_351_7, 6.221_395_081_679_106e-4),
            (1.999_999_962_9, 3.140_970_514_172_514_8, -4.885_257_859_922_369e-4),
        ];
        for (thetadot0, theta, thetadot) in cases {
            let (a, b) = pendulum_exact(0.0, thetadot0, 1.0, 11.0)?;
            close(a, theta, 2.0 * EPS, "θ near the separatrix");
            close(b, thetadot, 40.0 * EPS, "θ̇ near the separatrix");
        }
        Ok(())
    }

    #[test]
    fn pendulum_period_returns() -> TestResult {
        let omega0 = 1.7;
        for i in 1..=31 {
            let amplitude = 0.1 * i as f64;
            let period = pendulum_period(amplitude, omega0)?;
            let (th, thd) = pendulum_exact(amplitude, 0.0, omega0, period)?;
            close_abs(th, amplitude, 1e-14, "θ(T) = θ₀");
            close_abs(thd, 0.0, 1e-13, "θ̇(T) = 0");
            let (th, _) = pendulum_exact(amplitude, 0.0, omega0, 0.5 * period)?;
            close_abs(th, -amplitude, 1e-14, "θ(T/2) = −θ₀");
            let (th, thd) = pendulum_exact(amplitude, 0.0, omega0, 0.25 * period)?;
            close_abs(th, 0.0, 1e-14, "θ(T/4) = 0");
            close(thd, -2.0 * omega0 * (0.5 * amplitude).sin(), 1e-14, "θ̇(T/4)");
            // the first return to θ₀ (θ̇ = 0 from below) is at T: bracket it
            let (_, before) = pendulum_exact(amplitude, 0.0, omega0, period * (1.0 - 1e-6))?;
            let (_, after) = pendulum_exact(amplitude, 0.0, omega0, period * (1.0 + 1e-6))?;
            assert!(before > 0.0 && after < 0.0);
        }
        // close to the separatrix: the turning points are reproduced exactly
        for amplitude in [PI - 1e-3, PI - 1e-6, PI - 1e-10] {
            let period = pendulum_period(amplitude, omega0)?;
            for (fraction, expected) in [(0.5, -amplitude), (1.0, amplitude), (3.0, amplitude)] {
                let (th, _) = pendulum_exact(amplitude, 0.0, omega0, fraction * period)?;
                close_abs(th, expected, 4.0 * EPS * PI, "turning point near the separatrix");
            }
        }
        // small amplitude → 2π/ω₀ (1 + θ²/16)
        let a = 1e-4;
        close(
            pendulum_period(a, omega0)?,
            TAU / omega0 * (1.0 + a * a / 16.0),
            1e-15,
            "small amplitude",
        );
        close(
            pendulum_period(-0.3, omega0)?,
            pendulum_period(0.3, omega0)?,
            0.0,
            "even in amplitude",
        );
        // near the separatrix the log growth is resolved: T ≈ (4/ω₀) ln(8/(π − θ))
        let amplitude = PI - 1e-9;
        let gap = (PI - amplitude) + PI_LO; // exact π − θ_max
        let asymptote = 4.0 / omega0 * (8.0 / gap).ln();
        close(
            pendulum_period(amplitude, omega0)?,
            asymptote,
            4.0 * EPS,
            "log divergence",
        );
        Ok(())
    }

    #[test]
    fn pendulum_small_amplitude_is_harmonic() -> TestResult {
        let (a, omega0) = (1e-8, 2.3);
        for i in 0..20 {
            let t = 0.41 * i as f64;
            let (th, thd) = pendulum_exact(a, 0.3 * a, omega0, t)?;
            let (q, p) = harmonic_exact(a, 0.3 * a, 1.0, omega0, t)?;
            close_abs(th, q, 1e-14 * a, "θ ≈ harmonic");
            close_abs(thd, p, 1e-14 * a * omega0, "θ̇ ≈ harmonic");
        }
        assert_eq!(pendulum_exact(0.0, 0.0, 1.0, 5.0)?, (0.0, 0.0));
        Ok(())
    }

    // --- Harmonic oscillator -------------------------------------------------

    #[test]
    fn harmonic_oscillator() -> TestResult {
        let (q0, p0, mass, omega) = (0.7, -1.3, 2.5, 1.9);
        let energy = |q: f64, p: f64| p * p / (2.0 * mass) + 0.5 * mass * omega * omega * q * q;
        let e0 = energy(q0, p0);
        for i in -30..=30 {
            let t = 0.21 * i as f64;
            let (q, p) = harmonic_exact(q0, p0, mass, omega, t)?;
            close(energy(q, p), e0, 1e-15, "energy");
            let qd = derivative(
                |s| harmonic_exact(q0, p0, mass, omega, s).map(|x| x.0).unwrap_or(f64::NAN),
                t,
                1e-3,
            );
            close_abs(qd, p / mass, 1e-11, "q̇ = p/m");
        }
        assert_eq!(harmonic_exact(q0, p0, mass, omega, 0.0)?, (q0, p0));
        let (q, p) = harmonic_exact(q0, p0, mass, omega, TAU / omega)?;
        close_abs(q, q0, 1e-14, "q(2π/ω)");
        close_abs(p, p0, 1e-14, "p(2π/ω)");
        assert_eq!(harmonic_exact(1.0, 2.0, 4.0, 0.0, 3.0)?, (2.5, 2.0));
        Ok(())
    }
}
