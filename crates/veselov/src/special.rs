//! Special functions and closed-form reference solutions.
//!
//! Everything here is `f64`, depends on `std` only, and is meant as ground
//! truth for the integrators: each routine is accurate to a few units in the
//! last place where the function is well conditioned, and to a few times its
//! condition number in units of `ε` elsewhere.
//!
//! # Elliptic integrals and functions
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
//!
//! # Reference solutions
//!
//! * **Kepler problem** `L = ½|v|² + 1/|q|` (`μ = 1`, semi-major axis 1,
//!   period 2π): the eccentric anomaly solves Kepler's equation
//!   `E − e sin E = M`; the orbit through the pericentre `q(0) = (1 − e, 0)`,
//!   `p(0) = (0, √((1 + e)/(1 − e)))` is
//!   `q = (cos E − e, √(1 − e²) sin E)`, `p = (−sin E, √(1 − e²) cos E)/(1 − e cos E)`
//!   with `M = t`. The starter is S. Mikkola's cubic approximation
//!   (Celest. Mech. 40 (1987) 329–334), refined by safeguarded Halley steps.
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

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::fmt;

/// `π/2 − fl(π/2)`.
const FRAC_PI_2_LO: f64 = 6.123_233_995_736_766e-17;
/// `2π − fl(2π)`.
const TAU_LO: f64 = 2.449_293_598_294_706_4e-16;
/// The Landen descent stops once the parameter falls below this value; the
/// neglected terms of A&S 16.13 are then `O(μ²) ≈ 10⁻³⁶`.
const LANDEN_STOP: f64 = 1e-18;
/// More than enough Landen levels for any `k' ≥` the smallest subnormal.
const LANDEN_MAX_LEVELS: usize = 40;

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

fn complete_k(m: f64, kc: f64) -> f64 {
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
fn incomplete_f_parts(n: f64, rho: f64, m: f64, m1: f64, kc: f64) -> f64 {
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
fn jacobi_signed(u: f64, m: f64, kc: f64, parameter: &'static str, value: f64) -> Result<JacobiElliptic, SpecialError> {
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

    type TestResult = Result<(), SpecialError>;

    const EPS: f64 = f64::EPSILON;
    /// `π − fl(π)`.
    const PI_LO: f64 = 1.224_646_799_147_353_2e-16;

    fn rel(a: f64, b: f64) -> f64 {
        if a == b {
            0.0
        } else {
            (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
        }
    }

    #[track_caller]
    fn close(a: f64, b: f64, tol: f64, what: &str) {
        assert!(
            rel(a, b) <= tol,
            "{what}: {a:e} vs {b:e}, rel {:e} > {tol:e}",
            rel(a, b)
        );
    }

    #[track_caller]
    fn close_abs(a: f64, b: f64, tol: f64, what: &str) {
        assert!(
            (a - b).abs() <= tol,
            "{what}: {a:e} vs {b:e}, diff {:e} > {tol:e}",
            (a - b).abs()
        );
    }

    /// Fourth-order central difference of `f` at `x`.
    fn derivative(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
        (8.0 * (f(x + h) - f(x - h)) - (f(x + 2.0 * h) - f(x - 2.0 * h))) / (12.0 * h)
    }

    /// Fourth-order central second difference of `f` at `x`.
    fn second_derivative(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
        (-(f(x + 2.0 * h) + f(x - 2.0 * h)) + 16.0 * (f(x + h) + f(x - h)) - 30.0 * f(x)) / (12.0 * h * h)
    }

    fn jac(u: f64, m: f64) -> JacobiElliptic {
        jacobi_elliptic(u, m).expect("valid arguments")
    }

    fn jac_c(u: f64, m1: f64) -> JacobiElliptic {
        jacobi_elliptic_complement(u, m1).expect("valid arguments")
    }

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

    // --- Errors -------------------------------------------------------------

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
