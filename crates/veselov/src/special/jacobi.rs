//! Jacobi elliptic functions `sn`, `cn`, `dn` and the amplitude `am`
//! (parameter convention `m = k²`, see `elliptic.rs`).
//!
//! * Jacobi elliptic functions `sn`, `cn`, `dn` and the amplitude
//!   `am(u|m) = φ` with `u = F(φ|m)`. The argument is reduced with the
//!   periods (A&S 16.8) to `u = 2jK + r`, `|r| ≤ K`, and `|r| > K/2` is
//!   reflected about the quarter period, `sn(K − w) = cd w`,
//!   `cn(K − w) = k' sd w`, `dn(K − w) = k' nd w` (A&S 16.8.1), so only
//!   `0 ≤ w ≤ K/2` is evaluated. There the descending Landen transformation
//!   (A&S 16.12.1–16.12.4) is used, whose moduli are the AGM sequence of
//!   A&S 16.4: with `√μ = (1 − k')/(1 + k')`, `v = u/(1 + √μ)` and
//!   `D = 1 + √μ sn²(v|μ)`,
//!   ```text
//!   sn(u|m) = (1 + √μ) sn(v|μ) / D
//!   cn(u|m) = cn(v|μ) dn(v|μ) / D
//!   dn(u|m) = (cn²(v|μ) + (1 − √μ) sn²(v|μ)) / D = 1 − 2√μ sn²(v|μ) / D
//!   1 − cn(u|m) = (√μ sn² + (1 − cn) dn + (1 − dn)) / D
//!   ```
//!   The recursion descends until `μ < 10⁻¹⁸`, where A&S 16.13 (first order
//!   in `μ`) is exact to round-off, and climbs back carrying `1 − cn` and
//!   `1 − dn` alongside; the complement is the representation used while the
//!   function exceeds ½, since an error in a value close to 1 would
//!   otherwise double at every level. Propagating function values instead of
//!   the amplitude angle of A&S 16.4.3 avoids its `arcsin` of numbers close
//!   to 1, and as every numerator above is a sum of non-negative terms, `cn`
//!   and `dn` keep their *relative* accuracy both near 1 and where they are
//!   as small as `k'` (`u → K`, `m → 1`). The moduli are carried as pairs (`m`, `k'`)
//!   with `√μ = m/(1 + k')²`, `1 − √μ = 2k'/(1 + k')`,
//!   `k'_μ = 2√k'/(1 + k')`, none of which cancels, and the scale
//!   `Π(1 + √μ)` is accumulated in double-word arithmetic. At `m = 1` the
//!   functions are `tanh`, `sech`, `sech` and `am = gd u = arctan(sinh u)`
//!   (A&S 16.6).

use std::f64::consts::{PI, TAU};

use super::elliptic::complete_k;
use super::{SpecialError, finite, in_closed};

/// The Landen descent stops once the parameter falls below this value; the
/// neglected terms of A&S 16.13 are then `O(μ²) ≈ 10⁻³⁶`.
const LANDEN_STOP: f64 = 1e-18;
/// More than enough Landen levels for any `k' ≥` the smallest subnormal.
const LANDEN_MAX_LEVELS: usize = 40;

// ---------------------------------------------------------------------------
// Jacobi elliptic functions
// ---------------------------------------------------------------------------

/// Values of the Jacobi elliptic functions at one point `(u, m)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobiElliptic {
    /// `sn(u|m) = sin φ`.
    pub sn: f64,
    /// `cn(u|m) = cos φ`.
    pub cn: f64,
    /// `dn(u|m) = √(1 − m sin²φ)`.
    pub dn: f64,
    /// The amplitude `φ = am(u|m)`, continuous and increasing in `u`, with
    /// `am(u + 2K) = am(u) + π`.
    pub am: f64,
}

/// Jacobi functions for `u ≥ 0`, parameter `m`, complementary modulus
/// `kc = √(1 − m)`.
///
/// For `m` not negligible, `u` is first reduced to `r ∈ [−K, K]` with
/// `u = 2jK + r` (A&S 16.8: `sn`, `cn` change sign, `dn` is even, `am` gains
/// `jπ`), and `|r| > K/2` is reflected about the quarter period (A&S 16.8.1:
/// `sn(K − w) = cd w`, `cn(K − w) = k' sd w`, `dn(K − w) = k' nd w`), so the
/// Landen recursion only ever sees arguments in `[0, K/2]`. For `m ≤ 10⁻¹⁸`
/// and `m·u ≤ 10⁻⁹` the first-order form of A&S 16.13 is used directly
/// (exactly `sin`, `cos` at `m = 0`). Returns `None` when `u/(2K) ≥ 2⁵²`,
/// where the spacing of floating-point numbers exceeds the period.
fn jacobi_core(u: f64, m: f64, kc: f64) -> Option<JacobiElliptic> {
    if kc == 0.0 {
        // m = 1 (A&S 16.6): sn = tanh, cn = dn = sech, am = gd.
        let sech = 1.0 / u.cosh();
        return Some(JacobiElliptic {
            sn: u.tanh(),
            cn: sech,
            dn: sech,
            am: u.sinh().atan(),
        });
    }
    if m <= LANDEN_STOP && m * u <= 1e-9 {
        return Some(landen(u, m, kc));
    }
    let k = complete_k(m, kc);
    let periods = 0.5 * u / k;
    if periods >= 4_503_599_627_370_496.0 {
        return None;
    }
    let j = periods.round();
    let r = (-j).mul_add(2.0 * k, u);
    let a = r.abs();
    let (mut sn, mut cn, dn) = if a <= 0.5 * k {
        let l = landen(a, m, kc);
        (l.sn, l.cn, l.dn)
    } else {
        let l = landen((k - a).max(0.0), m, kc);
        // cd w = 1 − (dn − cn)/dn with dn² − cn² = m₁ sn²: no cancellation
        // when sn(K − w) is close to 1.
        let one_minus_cd = (kc * l.sn) * (kc * l.sn) / (l.dn * (l.dn + l.cn));
        (1.0 - one_minus_cd, kc * l.sn / l.dn, kc / l.dn)
    };
    let mut am = sn.atan2(cn); // |am(r)| ≤ π/2
    if r < 0.0 {
        sn = -sn;
        am = -am;
    }
    if j % 2.0 != 0.0 {
        sn = -sn;
        cn = -cn;
    }
    Some(JacobiElliptic {
        sn,
        cn,
        dn,
        am: j.mul_add(PI, am),
    })
}

/// Descending Landen transformation (A&S 16.12) for `u ≥ 0`.
fn landen(u: f64, m: f64, kc: f64) -> JacobiElliptic {
    // Descent: level n has parameter mₙ and modulus k'ₙ; record √μ = kₙ₊₁
    // and 1 − kₙ₊₁ for the ascent.
    let mut k_next = [0.0_f64; LANDEN_MAX_LEVELS];
    let mut one_minus_k_next = [0.0_f64; LANDEN_MAX_LEVELS];
    let mut factor_hi = [0.0_f64; LANDEN_MAX_LEVELS];
    let mut factor_lo = [0.0_f64; LANDEN_MAX_LEVELS];
    let mut levels = 0;
    let (mut mm, mut kc) = (m, kc);
    // v = u / Π(1 + kₙ₊₁), the product kept as an unevaluated sum
    // `scale + scale_lo`; near m = 1 the factors are 2 − (1 − kₙ₊₁) with an
    // accurate complement, so the argument loses nothing over many levels.
    let (mut scale, mut scale_lo) = (1.0_f64, 0.0_f64);
    while mm > LANDEN_STOP && levels < LANDEN_MAX_LEVELS {
        let one_plus_kc = 1.0 + kc;
        let k1 = mm / (one_plus_kc * one_plus_kc);
        let om = 2.0 * kc / one_plus_kc;
        k_next[levels] = k1;
        one_minus_k_next[levels] = om;
        let (fh, fl) = if k1 < 0.5 {
            let fh = 1.0 + k1;
            (fh, k1 - (fh - 1.0))
        } else {
            let fh = 2.0 - om;
            (fh, (2.0 - fh) - om)
        };
        factor_hi[levels] = fh;
        factor_lo[levels] = fl;
        let hi = scale * fh;
        let lo = scale.mul_add(fh, -hi) + (scale * fl + scale_lo * fh);
        scale = hi + lo;
        scale_lo = lo - (scale - hi);
        kc = 2.0 * kc.sqrt() / one_plus_kc;
        mm = k1 * k1;
        levels += 1;
    }
    let quotient = u / scale;
    let v = quotient + (-quotient).mul_add(scale, u) / scale - quotient * (scale_lo / scale);
    // Bottom: A&S 16.13.1–16.13.4, first order in the tiny parameter.
    let (s, c) = v.sin_cos();
    let half = (0.5 * v).sin();
    let corr = 0.25 * mm * (v - s * c);
    let am_bottom = v - corr;
    let mut sn = s - corr * c;
    let mut cn = c + corr * s;
    let mut one_minus_cn = 2.0 * half * half - corr * s;
    let mut one_minus_dn = 0.5 * mm * (s * s);
    let mut dn = 1.0 - one_minus_dn;
    if levels == 0 {
        return JacobiElliptic {
            sn,
            cn,
            dn,
            am: am_bottom,
        };
    }
    // Ascent (A&S 16.12.2–16.12.4) with every numerator a sum of
    // non-negative terms: with D = 1 + √μ sn²,
    //   1 − √μ sn² = cn² + (1 − √μ) sn²,
    //   1 − dn(u|m) = 2√μ sn² / D,
    //   1 − cn(u|m) = (√μ sn² + (1 − cn) dn + (1 − dn)) / D.
    // Where cn or dn is close to 1 its information sits in the complement,
    // which is then the representation used; products such as dn ≈ cn²
    // would otherwise double the relative error of the deviation from 1 at
    // every level.
    for n in (0..levels).rev() {
        let k1 = k_next[n];
        let s2 = sn * sn;
        let den = 1.0 + k1 * s2;
        let one_minus_cn_up = (k1 * s2 + one_minus_cn * dn + one_minus_dn) / den;
        let cn_up = cn * dn / den;
        one_minus_dn = 2.0 * k1 * s2 / den;
        dn = if one_minus_dn < 0.5 {
            1.0 - one_minus_dn
        } else {
            (cn * cn + one_minus_k_next[n] * s2) / den
        };
        (cn, one_minus_cn) = if one_minus_cn_up < 0.5 {
            (1.0 - one_minus_cn_up, one_minus_cn_up)
        } else {
            (cn_up, 1.0 - cn_up)
        };
        sn = factor_hi[n].mul_add(sn, factor_lo[n] * sn) / den;
    }
    // am(u) − πu/(2K) lies in (−π/2, π/2) and πu/(2K) ≈ am at the bottom,
    // which fixes the branch of atan2.
    let principal = sn.atan2(cn);
    let turns = ((am_bottom - principal) / TAU).round();
    JacobiElliptic {
        sn,
        cn,
        dn,
        am: turns.mul_add(TAU, principal),
    }
}

/// Jacobi functions for any finite `u` (odd `sn`, `am`; even `cn`, `dn`), or
/// an error naming `parameter` (`value`) when the phase is not representable.
pub(super) fn jacobi_signed(
    u: f64,
    m: f64,
    kc: f64,
    parameter: &'static str,
    value: f64,
) -> Result<JacobiElliptic, SpecialError> {
    let j = jacobi_core(u.abs(), m, kc).ok_or(SpecialError::new(
        parameter,
        value,
        "too large: an elliptic argument beyond 2⁵³ K(m) leaves the phase undetermined",
    ))?;
    Ok(if u.is_sign_negative() {
        JacobiElliptic {
            sn: -j.sn,
            am: -j.am,
            ..j
        }
    } else {
        j
    })
}

/// Jacobi elliptic functions `sn(u|m)`, `cn(u|m)`, `dn(u|m)` and the
/// amplitude `am(u|m)` (A&S 16.1.5), where `u = F(am(u|m)|m)`, for any real
/// `u` and `0 ≤ m ≤ 1` (parameter `m = k²`).
///
/// `m = 0` gives `(sin u, cos u, 1, u)` and `m = 1` gives
/// `(tanh u, sech u, sech u, gd u)`. `sn` and `am` are odd, `cn` and `dn`
/// even in `u`. For `m` within a few ulps of 1 use
/// [`jacobi_elliptic_complement`].
pub fn jacobi_elliptic(u: f64, m: f64) -> Result<JacobiElliptic, SpecialError> {
    finite("u", u)?;
    in_closed("m", m, 0.0, 1.0, "must satisfy 0 ≤ m ≤ 1")?;
    jacobi_signed(u, m, (1.0 - m).sqrt(), "u", u)
}

/// Jacobi elliptic functions at parameter `m = 1 − m₁`, from the
/// complementary parameter `m₁ ∈ [0, 1]`. Small `m₁` (e.g. `10⁻¹³`, as for
/// kink–antikink data) is resolved exactly: for `|u| ≪ K`,
/// `sn ≈ tanh u + ¼m₁(sinh u cosh u − u) sech²u`,
/// `cn ≈ sech u − ¼m₁(sinh u cosh u − u) tanh u sech u`,
/// `dn ≈ sech u + ¼m₁(sinh u cosh u + u) tanh u sech u` (A&S 16.15), and
/// `dn(K) = √m₁` to full relative accuracy.
pub fn jacobi_elliptic_complement(u: f64, m1: f64) -> Result<JacobiElliptic, SpecialError> {
    finite("u", u)?;
    in_closed("m1", m1, 0.0, 1.0, "must satisfy 0 ≤ m1 ≤ 1")?;
    jacobi_signed(u, 1.0 - m1, m1.sqrt(), "u", u)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::test_support::*;
    use crate::special::*;
    use std::f64::consts::{FRAC_PI_2, PI, TAU};

    // --- Jacobi functions ---------------------------------------------------

    const PARAMETERS: [f64; 9] = [0.0, 1e-20, 1e-10, 0.1, 0.5, 0.9, 0.999, 1.0 - 1e-12, 1.0];

    #[test]
    fn jacobi_pythagorean_identities() {
        for m in PARAMETERS {
            for i in -60..=60 {
                let u = 0.37 * i as f64;
                let j = jac(u, m);
                close_abs(
                    j.sn * j.sn + j.cn * j.cn,
                    1.0,
                    6.0 * EPS,
                    &format!("sn² + cn², u = {u}, m = {m}"),
                );
                close_abs(j.dn * j.dn + m * j.sn * j.sn, 1.0, 6.0 * EPS, "dn² + m sn²");
                close_abs(j.am.sin(), j.sn, 4.0 * EPS * (1.0 + j.am.abs()), "sin am = sn");
                close_abs(j.am.cos(), j.cn, 4.0 * EPS * (1.0 + j.am.abs()), "cos am = cn");
            }
        }
    }

    #[test]
    fn jacobi_reference_values() {
        let table = [
            (
                0.3,
                0.7,
                0.292_571_801_899_204_54,
                0.956_243_557_224_545_5,
                0.969_577_855_828_719_3,
            ),
            (
                1.7,
                0.3,
                0.999_932_478_587_555_9,
                0.011_620_596_617_518_459,
                0.836_684_236_423_589,
            ),
            (
                -2.5,
                0.95,
                -0.995_610_324_285_435,
                0.093_595_310_653_103_58,
                0.241_499_644_031_701_34,
            ),
            (
                10.0,
                0.5,
                0.858_812_505_952_778_7,
                -0.512_290_034_666_992_5,
                0.794_493_889_095_161,
            ),
        ];
        for (u, m, sn, cn, dn) in table {
            let j = jac(u, m);
            // relative condition numbers |u f'/f| of sn, cn, dn
            let kappa = |d: f64, f: f64| 4.0 * EPS * (1.0 + (u * d / f).abs());
            close(j.sn, sn, kappa(cn * dn, sn), "sn reference");
            close(j.cn, cn, kappa(sn * dn, cn), "cn reference");
            close(j.dn, dn, kappa(m * sn * cn, dn), "dn reference");
        }
        // m₁ = 10⁻¹³, up to u = 16 ≈ K.
        let table = [
            (
                1.0,
                0.761_594_155_955_773_4,
                0.648_054_273_663_875_4,
                0.648_054_273_663_920_1,
            ),
            (
                5.0,
                0.999_909_204_262_620_1,
                0.013_475_282_219_451_33,
                0.013_475_282_223_161_153,
            ),
            (
                12.0,
                0.999_999_999_924_522_3,
                1.228_639_027_130_369_5e-5,
                1.229_045_914_108_870_8e-5,
            ),
            (
                16.0,
                0.999_999_999_999_993_5,
                1.139_939_679_322_983_6e-7,
                3.361_467_309_449_083e-7,
            ),
        ];
        for (u, sn, cn, dn) in table {
            let j = jac_c(u, 1e-13);
            close(j.sn, sn, 4.0 * EPS, "sn, m1 = 1e-13");
            // cn, dn have relative condition number ≈ u here.
            close(j.cn, cn, 4.0 * EPS * u, "cn, m1 = 1e-13");
            close(j.dn, dn, 4.0 * EPS * u, "dn, m1 = 1e-13");
        }
    }

    #[test]
    fn jacobi_derivatives() {
        for m in [0.0, 0.2, 0.7, 0.99, 1.0] {
            for i in -12..=12 {
                let u = 0.53 * i as f64 + 0.1;
                let j = jac(u, m);
                let h = 1e-3;
                let tol = 1e-11;
                close_abs(derivative(|x| jac(x, m).sn, u, h), j.cn * j.dn, tol, "sn' = cn dn");
                close_abs(derivative(|x| jac(x, m).cn, u, h), -j.sn * j.dn, tol, "cn' = −sn dn");
                close_abs(
                    derivative(|x| jac(x, m).dn, u, h),
                    -m * j.sn * j.cn,
                    tol,
                    "dn' = −m sn cn",
                );
                close_abs(derivative(|x| jac(x, m).am, u, h), j.dn, tol, "am' = dn");
            }
        }
    }

    #[test]
    fn jacobi_periodicity() -> TestResult {
        for m in [0.0, 0.3, 0.8, 0.99, 1.0 - 1e-9] {
            let k = complete_elliptic_k(m)?;
            for i in -10..=10 {
                let u = 0.61 * i as f64;
                let (a, b, c) = (jac(u, m), jac(u + 4.0 * k, m), jac(u + 2.0 * k, m));
                let tol = 8.0 * EPS * (u.abs() + 4.0 * k);
                close_abs(b.sn, a.sn, tol, "sn(u + 4K)");
                close_abs(b.cn, a.cn, tol, "cn(u + 4K)");
                close_abs(c.sn, -a.sn, tol, "sn(u + 2K)");
                close_abs(c.dn, a.dn, tol, "dn(u + 2K)");
                close_abs(c.am, a.am + PI, tol, "am(u + 2K)");
                close_abs(b.am, a.am + TAU, tol, "am(u + 4K)");
            }
        }
        Ok(())
    }

    #[test]
    fn jacobi_quarter_period() -> TestResult {
        for m1 in [1.0, 0.5, 0.1, 1e-4, 1e-8, 1e-13, 1e-20, 1e-100, 1e-300] {
            let k = complete_elliptic_k_complement(m1)?;
            let kc = m1.sqrt();
            for (n, sn, am) in [(1.0, 1.0, FRAC_PI_2), (-1.0, -1.0, -FRAC_PI_2), (3.0, -1.0, 1.5 * PI)] {
                let j = jac_c(n * k, m1);
                close_abs(j.sn, sn, 2.0 * EPS, "sn(K)");
                // |cn'(K)| = k': the rounding of nK shows up as k'·δu
                close_abs(j.cn, 0.0, 16.0 * EPS * n.abs() * k * kc, "cn(K)");
                close(j.dn, kc, 4.0 * EPS * n.abs(), "dn(K) = √m1");
                close_abs(j.am, am, 4.0 * EPS * k, "am(K)");
            }
        }
        Ok(())
    }

    #[test]
    fn jacobi_limits_and_symmetry() {
        for i in -40..=40 {
            let u = 0.77 * i as f64;
            let j0 = jac(u, 0.0);
            assert_eq!((j0.sn, j0.cn, j0.dn, j0.am), (u.sin(), u.cos(), 1.0, u));
            let j1 = jac(u, 1.0);
            close(j1.sn, u.tanh(), EPS, "sn(u|1) = tanh");
            close(j1.cn, 1.0 / u.cosh(), EPS, "cn(u|1) = sech");
            close(j1.dn, 1.0 / u.cosh(), EPS, "dn(u|1) = sech");
            close(j1.am, 2.0 * (0.5 * u).tanh().atan(), 2.0 * EPS, "am(u|1) = gd");
            for m in [0.25, 0.9, 1.0 - 1e-13] {
                let (p, n) = (jac(u, m), jac(-u, m));
                assert_eq!((n.sn, n.cn, n.dn, n.am), (-p.sn, p.cn, p.dn, -p.am));
            }
        }
        // Continuity into the limits.
        for u in [0.3, 2.0, 7.0] {
            let (a, b) = (jac(u, 1e-300), jac(u, 0.0));
            assert_eq!((a.sn, a.cn, a.dn, a.am), (b.sn, b.cn, b.dn, b.am));
            let (a, b) = (jac_c(u, 1e-300), jac(u, 1.0));
            close(a.cn, b.cn, 4.0 * EPS * (1.0 + u), "cn as m1 → 0");
            close(a.am, b.am, 2.0 * EPS, "am as m1 → 0");
        }
        // Tiny m over many periods: the secular phase shift πu/(2K) ≈ u(1 − m/4)
        // must be kept (periodic corrections are O(m)).
        for m in [1e-19, 1e-17, 1e-14] {
            for u in [1e3, 1e6, 1e9, 1e12] {
                let j = jac(u, m);
                let phase = u - 0.25 * m * u;
                let tol = m + 8.0 * EPS * u;
                close_abs(j.am, phase, tol, "am, small m, large u");
                close_abs(j.sn, phase.sin(), tol, "sn, small m, large u");
                close_abs(j.cn, phase.cos(), tol, "cn, small m, large u");
            }
        }
        // beyond 2⁵³ K the phase is undetermined
        assert!(jacobi_elliptic(1e18, 0.5).is_err());
        assert!(jacobi_elliptic_complement(-1e300, 1e-300).is_err());
        assert!(jacobi_elliptic(1e300, 1.0).is_ok());
        assert!(jacobi_elliptic(1e300, 0.0).is_ok());
    }

    /// Values close to 1 are resolved to about an ulp of 1: `1 − f` (exact in
    /// floating point) against `cn²/(1 + sn)`, `sn²/(1 + cn)`, `m sn²/(1 + dn)`.
    #[test]
    fn jacobi_values_near_one() -> TestResult {
        let ulp = EPS / 2.0;
        for m1 in [0.5, 0.1, 1e-3, 1e-6, 1e-9, 1e-12, 1e-13, 1e-300] {
            let m = 1.0 - m1;
            let k = complete_elliptic_k_complement(m1)?;
            for i in 1..=40 {
                // small u: cn, dn ≈ 1
                let u = 0.3 * i as f64 / 40.0;
                let j = jac_c(u, m1);
                let tol = 2.0 * ulp + 8.0 * EPS * (1.0 - j.cn);
                close_abs(1.0 - j.cn, j.sn * j.sn / (1.0 + j.cn), tol, "1 − cn, small u");
                let tol = 2.0 * ulp + 8.0 * EPS * (1.0 - j.dn);
                close_abs(1.0 - j.dn, m * j.sn * j.sn / (1.0 + j.dn), tol, "1 − dn, small u");
                // u ∈ (K/2, K): sn ≈ 1
                let u = k * (0.5 + 0.5 * i as f64 / 40.0);
                let j = jac_c(u, m1);
                let tol = 2.0 * ulp + 8.0 * EPS * (1.0 - j.sn) * (1.0 + u);
                close_abs(1.0 - j.sn, j.cn * j.cn / (1.0 + j.sn), tol, "1 − sn near K");
            }
        }
        Ok(())
    }

    /// m₁ = 10⁻¹³ against the m = 1 limit with its first-order correction
    /// (A&S 16.15.1–16.15.4); the second-order remainder is below 10⁻¹⁷
    /// relative for |u| ≤ 6.
    #[test]
    fn jacobi_near_one_first_order() {
        let m1 = 1e-13;
        for i in -60..=60 {
            let u = 0.1 * i as f64;
            let (sh, chh, th) = (u.sinh(), u.cosh(), u.tanh());
            let sech = 1.0 / chh;
            let a = 0.25 * m1 * (sh * chh - u);
            let b = 0.25 * m1 * (sh * chh + u);
            let j = jac_c(u, m1);
            close(j.sn, th + a * sech * sech, 4.0 * EPS, "sn ≈ A&S 16.15.1");
            // relative condition number of cn, dn here is |u tanh u|
            close(
                j.cn,
                sech - a * th * sech,
                4.0 * EPS * (1.0 + u.abs()),
                "cn ≈ A&S 16.15.2",
            );
            close(
                j.dn,
                sech + b * th * sech,
                4.0 * EPS * (1.0 + u.abs()),
                "dn ≈ A&S 16.15.3",
            );
            close(
                j.am,
                2.0 * (0.5 * u).tanh().atan() + a * sech,
                4.0 * EPS,
                "am ≈ A&S 16.15.4",
            );
            // The correction is resolved: at u = 6 it is ~10⁻⁹ relative in cn.
            if u >= 5.9 {
                assert!(rel(j.cn, sech) > 1e-10 && rel(j.dn, sech) > 1e-10);
            }
        }
    }

    /// Quarter-period shift (A&S 16.8): cn(K − u) = k' sd(u), dn(K − u) = k' nd(u),
    /// which tests the relative accuracy of cn and dn where they are ~k'.
    #[test]
    fn jacobi_near_one_quarter_shift() -> TestResult {
        for m1 in [1e-13, 1e-6, 0.3] {
            let k = complete_elliptic_k_complement(m1)?;
            let kc = m1.sqrt();
            for i in 1..40 {
                let u = k * i as f64 / 80.0; // u ∈ (0, K/2)
                let (a, b) = (jac_c(u, m1), jac_c(k - u, m1));
                // relative condition number of cn(K − u) is K/u
                let tol = 8.0 * EPS * (1.0 + k / u);
                close(b.cn, kc * a.sn / a.dn, tol, "cn(K − u) = k' sd(u)");
                close(b.dn, kc / a.dn, 4.0 * EPS * (1.0 + k), "dn(K − u) = k'/dn(u)");
                close(b.sn, a.cn / a.dn, 4.0 * EPS * (1.0 + k), "sn(K − u) = cd(u)");
            }
        }
        Ok(())
    }

    #[test]
    fn amplitude_inverts_incomplete_integral() -> TestResult {
        close(
            incomplete_elliptic_f(1.0, 0.5)?,
            1.083_216_772_845_168_8,
            2.0 * EPS,
            "F(1|0.5)",
        );
        close(
            incomplete_elliptic_f(2.5, 0.9)?,
            4.471_319_666_996_252,
            2.0 * EPS,
            "F(2.5|0.9)",
        );
        // both sides of the quarter period, and next to it for m → 1
        close(
            incomplete_elliptic_f(1.2, 0.9)?,
            1.564_898_134_506_671_5,
            2.0 * EPS,
            "F(1.2|0.9)",
        );
        close(
            incomplete_elliptic_f(1.9, 0.9)?,
            3.499_589_485_241_496,
            2.0 * EPS,
            "F(1.9|0.9)",
        );
        close(
            incomplete_elliptic_f(-4.5, 0.7)?,
            -5.844_766_094_118_297,
            2.0 * EPS,
            "F(−4.5|0.7)",
        );
        close(
            incomplete_elliptic_f(FRAC_PI_2 - 1e-8, 0.999_999)?,
            8.294_041_463_601_062,
            4.0 * EPS,
            "F(≈π/2|m ≈ 1)",
        );
        for m in [0.0, 0.4, 0.9, 0.9999, 1.0 - 1e-12] {
            let k = complete_elliptic_k(m)?;
            // fl(π/2) = π/2 − δ and F'(π/2) = 1/k', F''(π/2) = 0
            let shifted = k - FRAC_PI_2_LO / (1.0 - m).sqrt();
            close(incomplete_elliptic_f(FRAC_PI_2, m)?, shifted, 4.0 * EPS, "F(π/2) = K");
            for i in -30..=30 {
                let phi = 0.23 * i as f64;
                let f = incomplete_elliptic_f(phi, m)?;
                close_abs(jac(f, m).am, phi, 8.0 * EPS * (1.0 + phi.abs()), "am(F(φ)) = φ");
                close_abs(
                    incomplete_elliptic_f(phi + PI, m)?,
                    f + 2.0 * k,
                    8.0 * EPS * (1.0 + f.abs() + k),
                    "F(φ + π)",
                );
            }
        }
        Ok(())
    }
}
