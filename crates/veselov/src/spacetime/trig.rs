//! A fused `sin`/`cos` sharing one argument reduction, for the sine-Gordon
//! hot loops (one call per node and level), and the same over a batch of
//! arguments in vector lanes.
//!
//! Constants are fdlibm's, written as the shortest decimals that round-trip
//! to the same doubles.
//!
//! Argument reduction `x = n·π/2 + r` by the three-part Cody–Waite scheme of
//! fdlibm's `__ieee754_rem_pio2` (medium range, `r = y₀ + y₁` to about
//! 118 bits of `π/2`), then fdlibm's `__kernel_sin`/`__kernel_cos` minimax
//! polynomials on `|r| ≤ π/4` (error < 1 ulp). Arguments with
//! `|x| > 2¹⁹·π/2` or non-finite fall back to the standard library.

const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
const PIO2_1: f64 = 1.570_796_326_734_125_6; // first 33 bits of π/2
const PIO2_2: f64 = 6.077_100_506_303_966e-11; // second 33 bits
const PIO2_2T: f64 = 2.022_266_248_795_950_6e-21; // π/2 − (PIO2_1 + PIO2_2)
const TOINT: f64 = 6_755_399_441_055_744.0; // 1.5·2⁵²: round to nearest integer

const S1: f64 = -0.166_666_666_666_666_32;
const S2: f64 = 0.008_333_333_333_322_49;
const S3: f64 = -0.000_198_412_698_298_579_5;
const S4: f64 = 2.755_731_370_707_006_8e-6;
const S5: f64 = -2.505_076_025_340_686_3e-8;
const S6: f64 = 1.589_690_995_211_55e-10;

const C1: f64 = 0.041_666_666_666_666_6;
const C2: f64 = -0.001_388_888_888_887_411;
const C3: f64 = 2.480_158_728_947_673e-5;
const C4: f64 = -2.755_731_435_139_066_3e-7;
const C5: f64 = 2.087_572_321_298_175e-9;
const C6: f64 = -1.135_964_755_778_819_5e-11;

#[inline(always)]
fn kernel_sin(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    x - ((z * (0.5 * y - v * r) - y) - v * S1)
}

#[inline(always)]
fn kernel_cos(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

/// `(sin x, cos x)` with one shared argument reduction (< 1 ulp error in
/// the fast range `|x| ≤ 2¹⁹·π/2`).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() > 823_549.6 {
        return x.sin_cos();
    }
    let f = (x * INV_PIO2 + TOINT) - TOINT;
    let n = f as i64;
    // x − f·π/2 = y₀ + y₁ by the second Cody–Waite round of fdlibm's
    // rem_pio2 (π/2 = PIO2_1 + PIO2_2 + PIO2_2T; f·PIO2_1 and f·PIO2_2 exact).
    let t = x - f * PIO2_1;
    let w = f * PIO2_2;
    let r = t - w;
    let w = f * PIO2_2T - ((t - r) - w);
    let y0 = r - w;
    let y1 = (r - y0) - w;
    let s = kernel_sin(y0, y1);
    let c = kernel_cos(y0, y1);
    match n & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `(sin x_i, cos x_i)` for every `x_i` of `x` into `sin` and `cos` (equal
/// lengths), the bits of [`sin_cos`] for each: the same operations run over
/// lanes of eight, four and two, which the compiler turns into vector
/// instructions, with the quadrant `n mod 4` taken in floating point
/// (f − 4·round(f/4), exact for the integral f of the fast range) and the
/// signs and swaps selected per lane. A group with an argument outside the
/// fast range, or NaN, is done by [`sin_cos`] one by one. Compiled three
/// times, for the baseline instruction set, for AVX2 and for AVX-512 (the
/// widest the processor has is chosen at run time; an eight-lane group is
/// one AVX-512 instruction where AVX2 needs two); none contracts a product
/// and a sum into one rounding, so all give the same bits.
///
/// # Panics
/// If the three slices differ in length (a caller's bug).
#[multiversion::multiversion(targets("x86_64+avx2+avx512f", "x86_64+avx2"))]
pub fn sin_cos_batch(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    batch_in_lanes(x, sin, cos);
}

/// [`sin_cos_batch`]'s body, inlined into each of its versions.
#[inline(always)]
fn batch_in_lanes(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    assert!(
        x.len() == sin.len() && x.len() == cos.len(),
        "sin_cos_batch: lengths differ"
    );
    let mut start = 0;
    while x.len() - start >= 8 {
        lanes::<8>(
            &x[start..start + 8],
            &mut sin[start..start + 8],
            &mut cos[start..start + 8],
        );
        start += 8;
    }
    if x.len() - start >= 4 {
        lanes::<4>(
            &x[start..start + 4],
            &mut sin[start..start + 4],
            &mut cos[start..start + 4],
        );
        start += 4;
    }
    if x.len() - start >= 2 {
        lanes::<2>(
            &x[start..start + 2],
            &mut sin[start..start + 2],
            &mut cos[start..start + 2],
        );
        start += 2;
    }
    if start < x.len() {
        (sin[start], cos[start]) = sin_cos(x[start]);
    }
}

/// [`sin_cos`] over `L` lanes (see [`sin_cos_batch`]).
#[inline(always)]
fn lanes<const L: usize>(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    let x: &[f64; L] = x.try_into().expect("L lanes");
    if !x.iter().all(|v| v.abs() <= 823_549.6) {
        for i in 0..L {
            (sin[i], cos[i]) = sin_cos(x[i]);
        }
        return;
    }
    let (mut y0, mut y1, mut quadrant) = ([0.0; L], [0.0; L], [0.0; L]);
    for i in 0..L {
        let f = (x[i] * INV_PIO2 + TOINT) - TOINT;
        // f − 4·round(f/4) ∈ {−2, −1, 0, 1, 2}, ≡ n (mod 4); exact.
        quadrant[i] = f - 4.0 * ((f * 0.25 + TOINT) - TOINT);
        let t = x[i] - f * PIO2_1;
        let w = f * PIO2_2;
        let r = t - w;
        let w = f * PIO2_2T - ((t - r) - w);
        y0[i] = r - w;
        y1[i] = (r - y0[i]) - w;
    }
    for i in 0..L {
        let s = kernel_sin(y0[i], y1[i]);
        let c = kernel_cos(y0[i], y1[i]);
        let q = quadrant[i];
        // n mod 4 = 0: (s, c); 1: (c, −s); 2 (q = ±2): (−s, −c); 3 (q = −1): (−c, s).
        let (a, b) = if q.abs() == 1.0 { (c, s) } else { (s, c) };
        sin[i] = if q.abs() == 2.0 || q == -1.0 { -a } else { a };
        cos[i] = if q == 1.0 || q.abs() == 2.0 { -b } else { b };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_the_standard_library() {
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let (s, c) = sin_cos(x);
            worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
        };
        let mut s = 12345u64;
        for _ in 0..200_000 {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            check((u - 0.5) * 2000.0);
            check((u - 0.5) * 20.0);
        }
        for k in -200..=200 {
            let m = k as f64 * std::f64::consts::FRAC_PI_2;
            for d in [0.0, 1e-12, -1e-9, 3e-7, f64::EPSILON] {
                check(m + d);
            }
        }
        for x in [0.0, -0.0, 1e-300, 1e6, -3e7, 1e300] {
            check(x);
        }
        // Both are within 1 ulp of the truth: they differ by ≤ 2 ulp of values ≤ 1.
        assert!(worst <= 2.3e-16, "{worst:e}");
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
    }

    /// The batch gives the bits of `sin_cos` for every argument and every
    /// length (groups of eight, four, two and one), in the version the processor
    /// runs and in the baseline one: random arguments, quadrant
    /// boundaries, signed zeros, the edge of the fast range, beyond it,
    /// infinities and NaN mixed into a group.
    #[test]
    fn batch_gives_the_bits_of_sin_cos() {
        let mut x = Vec::new();
        let mut s = 987_654_321u64;
        for _ in 0..2000 {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            x.push((u - 0.5) * 40.0);
            x.push((u - 0.5) * 2e6);
        }
        for k in -40..=40 {
            let m = k as f64 * std::f64::consts::FRAC_PI_2;
            for d in [0.0, 1e-15, -1e-15, 1e-9, -3e-7] {
                x.push(m + d);
            }
        }
        x.extend([0.0, -0.0, 1e-300, -1e-310, 823_549.6, -823_549.6, 823_549.7, 1e300]);
        x.extend([f64::INFINITY, 0.5, f64::NEG_INFINITY, 1.5, f64::NAN, -2.5, 3.5]);
        let bits = |v: f64| if v.is_nan() { u64::MAX } else { v.to_bits() };
        // The version this processor runs, and the baseline one.
        type Batch = fn(&[f64], &mut [f64], &mut [f64]);
        let versions: [(&str, Batch); 2] = [("dispatched", sin_cos_batch), ("baseline", batch_in_lanes)];
        for (version, batch) in versions {
            for len in 1..=19 {
                for chunk in x.chunks(len).filter(|c| c.len() == len) {
                    let (mut sin, mut cos) = (vec![0.0; len], vec![0.0; len]);
                    batch(chunk, &mut sin, &mut cos);
                    for (i, &v) in chunk.iter().enumerate() {
                        let (s, c) = sin_cos(v);
                        let got = (bits(sin[i]), bits(cos[i]));
                        assert_eq!(got, (bits(s), bits(c)), "{version}: x = {v:e}, length {len}");
                    }
                }
            }
        }
    }
}
