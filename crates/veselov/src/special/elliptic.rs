//! Complete and incomplete elliptic integrals of the first and second kind.
//!
//! The **parameter convention is `m = k²`** throughout (Abramowitz & Stegun,
//! chapters 16–17), with the complementary parameter `m₁ = 1 − m` and the
//! complementary modulus `k' = √m₁`. Because `1 − m` cannot be formed
//! accurately once `m` is within a few ulps of 1, every routine that matters
//! near `m = 1` also has a `*_complement` variant taking `m₁` directly.
//!
//! * Complete integrals by the arithmetic–geometric mean (A&S 17.6.1–17.6.4):
//!   with `a₀ = 1`, `b₀ = k'`, `c₀ = k`, `aₙ₊₁ = (aₙ + bₙ)/2`,
//!   `bₙ₊₁ = √(aₙbₙ)`, `cₙ₊₁ = cₙ²/(4aₙ₊₁)`,
//!   `K(m) = π / (2a_∞)` and `K − E = K Σₙ 2ⁿ⁻¹ cₙ²`.
//!   For `m > ½` the second integral is taken from Legendre's relation
//!   (A&S 17.3.13) `E K' + E' K − K K' = π/2` in the cancellation-free form
//!   `E = a'_∞ + K (K' − E')/K'`, where primes refer to parameter `m₁`.
//! * Incomplete integral of the first kind (A&S 17.2.6)
//!   `F(φ|m) = ∫₀^φ dθ/√(1 − m sin²θ) = sin φ · R_F(cos²φ, cos²φ + m₁ sin²φ, 1)`
//!   for `|φ| ≤ π/2`, with Carlson's symmetric integral `R_F` (DLMF 19.25.5)
//!   evaluated by duplication (B. C. Carlson, Numer. Algorithms 10 (1995)
//!   13–26). A general `φ` is written `nπ/2 + ρ`, `|ρ| ≤ π/4`, with a
//!   two-part π/2; `F(φ + π|m) = F(φ|m) + 2K(m)` (A&S 17.4.3) and
//!   `F(π/2 − δ|m) = cos δ · R_F(sin²δ, sin²δ + m₁ cos²δ, 1)` then give every
//!   case without cancellation, also next to `φ = π/2` where `dF/dφ = 1/k'`.

use std::f64::consts::FRAC_PI_2;

use super::{FRAC_PI_2_LO, SpecialError, finite, in_closed, reduce};

// ---------------------------------------------------------------------------
// Complete elliptic integrals
// ---------------------------------------------------------------------------

/// Arithmetic–geometric mean `AGM(1, k')` together with the sum
/// `S = Σₙ 2ⁿ⁻¹ cₙ²` of A&S 17.6.3–17.6.4, for `c₀² = m = 1 − k'²`.
/// Then `K = π/(2·AGM)` and `K − E = K S`.
fn agm_with_sum(m: f64, kc: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0_f64, kc);
    let mut c2 = m;
    let mut weight = 0.5;
    let mut sum = 0.5 * m;
    for _ in 0..64 {
        // cₙ ≤ ε aₙ: the next correction to aₙ is cₙ²/(4a) — below round-off.
        if c2 <= (f64::EPSILON * a) * (f64::EPSILON * a) {
            break;
        }
        let a1 = 0.5 * (a + b);
        let b1 = (a * b).sqrt();
        let c1 = c2 / (4.0 * a1);
        c2 = c1 * c1;
        weight *= 2.0;
        sum += weight * c2;
        a = a1;
        b = b1;
    }
    (a, sum)
}

/// `(K, E)` from the parameter and the complementary modulus `k' = √(1 − m)`.
/// Requires `k' > 0`.
fn complete_ke(m: f64, m1: f64, kc: f64) -> (f64, f64) {
    let (a, s) = agm_with_sum(m, kc);
    let k = FRAC_PI_2 / a;
    let e = if m <= 0.5 {
        k * (1.0 - s)
    } else {
        // Legendre's relation: E = π/(2K') + K (K' − E')/K'.
        let (a1, s1) = agm_with_sum(m1, m.sqrt());
        a1 + k * s1
    };
    (k, e)
}

pub(super) fn complete_k(m: f64, kc: f64) -> f64 {
    FRAC_PI_2 / agm_with_sum(m, kc).0
}

/// Complete elliptic integral of the first kind (A&S 17.3.1, 17.6.1),
/// `K(m) = ∫₀^{π/2} dθ / √(1 − m sin²θ) = π / (2 AGM(1, √(1 − m)))`,
/// for `0 ≤ m < 1` (parameter `m = k²`).
///
/// For `m` within a few ulps of 1 use [`complete_elliptic_k_complement`].
pub fn complete_elliptic_k(m: f64) -> Result<f64, SpecialError> {
    in_closed("m", m, 0.0, 1.0, "must satisfy 0 ≤ m < 1")?;
    if m == 1.0 {
        return Err(SpecialError::new(
            "m",
            m,
            "must satisfy 0 ≤ m < 1 (K diverges at m = 1)",
        ));
    }
    Ok(complete_k(m, (1.0 - m).sqrt()))
}

/// `K(1 − m₁)` from the complementary parameter `m₁ = 1 − m ∈ (0, 1]`,
/// with no loss of accuracy as `m₁ → 0`, where
/// `K ≈ ln(4/√m₁) + (m₁/4)(ln(4/√m₁) − 1)` (A&S 17.3.26).
pub fn complete_elliptic_k_complement(m1: f64) -> Result<f64, SpecialError> {
    in_closed("m1", m1, 0.0, 1.0, "must satisfy 0 < m1 ≤ 1")?;
    if m1 == 0.0 {
        return Err(SpecialError::new(
            "m1",
            m1,
            "must satisfy 0 < m1 ≤ 1 (K diverges at m1 = 0)",
        ));
    }
    Ok(complete_k(1.0 - m1, m1.sqrt()))
}

/// Complete elliptic integral of the second kind (A&S 17.3.3, 17.6.3–17.6.4),
/// `E(m) = ∫₀^{π/2} √(1 − m sin²θ) dθ = K(m) (1 − Σₙ 2ⁿ⁻¹ cₙ²)`, for
/// `0 ≤ m ≤ 1` (`E(1) = 1`). For `m > ½` Legendre's relation (A&S 17.3.13)
/// is used in a form free of cancellation.
pub fn complete_elliptic_e(m: f64) -> Result<f64, SpecialError> {
    in_closed("m", m, 0.0, 1.0, "must satisfy 0 ≤ m ≤ 1")?;
    if m == 1.0 {
        return Ok(1.0);
    }
    let m1 = 1.0 - m;
    Ok(complete_ke(m, m1, m1.sqrt()).1)
}

/// `E(1 − m₁)` from the complementary parameter `m₁ = 1 − m ∈ [0, 1]`,
/// accurate as `m₁ → 0`, where `E ≈ 1 + (m₁/2)(ln(4/√m₁) − ½)` (A&S 17.3.36).
pub fn complete_elliptic_e_complement(m1: f64) -> Result<f64, SpecialError> {
    in_closed("m1", m1, 0.0, 1.0, "must satisfy 0 ≤ m1 ≤ 1")?;
    if m1 == 0.0 {
        return Ok(1.0);
    }
    Ok(complete_ke(1.0 - m1, m1, m1.sqrt()).1)
}

// ---------------------------------------------------------------------------
// Incomplete integral of the first kind
// ---------------------------------------------------------------------------

/// Carlson's `R_F(x, y, z) = ½∫₀^∞ dt / √((t+x)(t+y)(t+z))` (DLMF 19.16.1) for
/// non-negative arguments, at most one of them zero, by duplication with the
/// fifth-order series of Carlson (1995); relative error about `ε`.
fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    let (x0, y0) = (x, y);
    let (mut x, mut y, mut z) = (x, y, z);
    let a0 = (x + y + z) / 3.0;
    let mut a = a0;
    let spread = (a0 - x).abs().max((a0 - y).abs()).max((a0 - z).abs());
    let mut q = (3.0 * f64::EPSILON).powf(-1.0 / 6.0) * spread;
    let mut scale = 1.0;
    for _ in 0..200 {
        if q < a.abs() {
            break;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        a = 0.25 * (a + lambda);
        q *= 0.25;
        scale *= 0.25;
    }
    let xd = (a0 - x0) * scale / a;
    let yd = (a0 - y0) * scale / a;
    let zd = -(xd + yd);
    let e2 = xd * yd - zd * zd;
    let e3 = xd * yd * zd;
    (1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0) / a.sqrt()
}

/// `F(φ|m) = sin φ · R_F(cos²φ, cos²φ + m₁ sin²φ, 1)` for `|φ| ≤ π/2`, from
/// `(sin φ, cos φ)`.
fn incomplete_f_sc(s: f64, c: f64, m1: f64) -> f64 {
    let c2 = c * c;
    s * carlson_rf(c2, c2 + m1 * (s * s), 1.0)
}

/// `F(nπ/2 + ρ|m)` for an integer `n` and `|ρ| ≤ π/4`, `0 ≤ m < 1`, given
/// `m₁ = 1 − m` and `k' = √m₁`. With `H(δ) = F(π/2 − δ|m)`, evaluated from
/// `sin(π/2 − δ) = cos δ` and `cos(π/2 − δ) = sin δ` so that the steep
/// neighbourhood of the quarter period (`dF/dφ` up to `1/k'`) is resolved:
/// * `n` even: `nK + F(ρ)`;
/// * `n` odd: `(n − 1)K + H(−ρ)` for `ρ ≤ 0`, `(n + 1)K − H(ρ)` for `ρ > 0`.
///
/// Every case adds terms of one sign or yields `|F| ≥ K`, so nothing cancels.
pub(super) fn incomplete_f_parts(n: f64, rho: f64, m: f64, m1: f64, kc: f64) -> f64 {
    let (s, c) = rho.sin_cos();
    let (part, multiple) = if n % 2.0 == 0.0 {
        (incomplete_f_sc(s, c, m1), n)
    } else if rho <= 0.0 {
        (incomplete_f_sc(c, -s, m1), n - 1.0)
    } else {
        (-incomplete_f_sc(c, s, m1), n + 1.0)
    };
    if multiple == 0.0 {
        part
    } else {
        multiple.mul_add(complete_k(m, kc), part)
    }
}

/// Incomplete elliptic integral of the first kind (A&S 17.2.6),
/// `F(φ|m) = ∫₀^φ dθ / √(1 − m sin²θ)`, for any real `φ` and `0 ≤ m < 1`;
/// `F(φ + jπ|m) = F(φ|m) + 2jK(m)` (A&S 17.4.3). It inverts the amplitude:
/// `am(F(φ|m)|m) = φ`.
pub fn incomplete_elliptic_f(phi: f64, m: f64) -> Result<f64, SpecialError> {
    finite("phi", phi)?;
    in_closed("m", m, 0.0, 1.0, "must satisfy 0 ≤ m < 1")?;
    if m == 1.0 {
        return Err(SpecialError::new("m", m, "must satisfy 0 ≤ m < 1"));
    }
    let m1 = 1.0 - m;
    let (rho, n) = reduce(phi, FRAC_PI_2, FRAC_PI_2_LO);
    Ok(incomplete_f_parts(n, rho, m, m1, m1.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::test_support::*;
    use std::f64::consts::FRAC_PI_2;

    // --- complete integrals -------------------------------------------------

    #[test]
    fn complete_integrals_known_values() -> TestResult {
        assert_eq!(complete_elliptic_k(0.0)?, FRAC_PI_2);
        assert_eq!(complete_elliptic_e(0.0)?, FRAC_PI_2);
        assert_eq!(complete_elliptic_e(1.0)?, 1.0);
        assert_eq!(complete_elliptic_e_complement(0.0)?, 1.0);
        let table = [
            (0.1, 1.612_441_348_720_219_4, 1.530_757_636_897_763_2),
            (0.5, 1.854_074_677_301_371_9, 1.350_643_881_047_675_5),
            (0.9, 2.578_092_113_348_173_3, 1.104_774_732_704_073_3),
            (0.99, 3.695_637_362_989_874, 1.015_993_545_025_224),
            (0.999_999, 8.294_051_463_601_062, 1.000_003_897_026_172_2),
        ];
        for (m, k, e) in table {
            close(complete_elliptic_k(m)?, k, 2.0 * EPS, "K(m)");
            close(complete_elliptic_e(m)?, e, 2.0 * EPS, "E(m)");
        }
        // m₁ = 10⁻¹³ through the complement.
        close(
            complete_elliptic_k_complement(1e-13)?,
            16.353_097_465_581_57,
            2.0 * EPS,
            "K(1 − 1e-13)",
        );
        close(
            complete_elliptic_e_complement(1e-13)?,
            1.000_000_000_000_792_7,
            2.0 * EPS,
            "E(1 − 1e-13)",
        );
        Ok(())
    }

    #[test]
    fn legendre_relation() -> TestResult {
        for m1 in [1e-300, 1e-13, 1e-6, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99, 1.0 - 1e-9] {
            let m = 1.0 - m1;
            let (k, e) = (complete_elliptic_k_complement(m1)?, complete_elliptic_e_complement(m1)?);
            let (kp, ep) = (complete_elliptic_k(m1)?, complete_elliptic_e(m1)?);
            let lhs = e * kp + ep * k - k * kp;
            close(lhs, FRAC_PI_2, 4.0 * EPS * (1.0 + k), "Legendre relation");
            // m-input and m₁-input agree when 1 − m is exact.
            if m1 >= 0.5 {
                close(complete_elliptic_k(m)?, k, 2.0 * EPS, "K(m) vs K(1 − m1)");
                close(complete_elliptic_e(m)?, e, 2.0 * EPS, "E(m) vs E(1 − m1)");
            }
        }
        Ok(())
    }

    /// Independent check: the trapezoid rule is spectrally accurate for the
    /// periodic integrands of K and E.
    #[test]
    fn complete_integrals_match_quadrature() -> TestResult {
        for m in [0.05, 0.3, 0.5, 0.6, 0.8, 0.95, 0.99] {
            let n = 4000;
            let h = FRAC_PI_2 / n as f64;
            let (mut kq, mut eq) = (0.0, 0.0);
            for i in 0..=n {
                let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                let s = (i as f64 * h).sin();
                let d = (1.0 - m * s * s).sqrt();
                kq += w * h / d;
                eq += w * h * d;
            }
            close(complete_elliptic_k(m)?, kq, 1e-14, "K vs quadrature");
            close(complete_elliptic_e(m)?, eq, 1e-14, "E vs quadrature");
        }
        Ok(())
    }

    /// dK/dm = (E − m₁K)/(2mm₁) and dE/dm = (E − K)/(2m) (A&S 17.3.43–44).
    #[test]
    fn complete_integral_derivatives() -> TestResult {
        for m in [0.2, 0.45, 0.55, 0.8, 0.97] {
            let (k, e) = (complete_elliptic_k(m)?, complete_elliptic_e(m)?);
            let h = 0.01 * m.min(1.0 - m);
            let dk = derivative(|x| complete_elliptic_k(x).unwrap_or(f64::NAN), m, h);
            let de = derivative(|x| complete_elliptic_e(x).unwrap_or(f64::NAN), m, h);
            close(dk, (e - (1.0 - m) * k) / (2.0 * m * (1.0 - m)), 1e-8, "dK/dm");
            close(de, (e - k) / (2.0 * m), 1e-8, "dE/dm");
        }
        Ok(())
    }

    #[test]
    fn complete_k_logarithmic_asymptote() -> TestResult {
        // K = L + (m₁/4)(L − 1) + O(m₁² L), L = ln(4/√m₁) (A&S 17.3.26).
        for m1 in [1e-8_f64, 1e-10, 1e-12, 1e-13, 1e-16, 1e-50, 1e-300] {
            let l = (4.0 / m1.sqrt()).ln();
            let k = complete_elliptic_k_complement(m1)?;
            close(k, l + 0.25 * m1 * (l - 1.0), 2.0 * EPS, "K asymptote");
            assert!(
                k - l > 0.0 || m1 < 1e-15,
                "first-order correction resolved at m1 = {m1:e}"
            );
            let e = complete_elliptic_e_complement(m1)?;
            close(e, 1.0 + 0.5 * m1 * (l - 0.5), 2.0 * EPS, "E asymptote");
        }
        // The logarithm is reached smoothly from the m-input side as well.
        let l = (4.0 / 1e-6_f64.sqrt()).ln();
        close(
            complete_elliptic_k(1.0 - 1e-6)?,
            l + 0.25e-6 * (l - 1.0),
            1e-10,
            "K(1 − 1e-6)",
        );
        Ok(())
    }
}
