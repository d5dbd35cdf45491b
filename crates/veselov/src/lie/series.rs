//! Coefficient functions of the SO(3)/SE(3) closed forms, each a smooth
//! (even) function of θ evaluated **as a function of x = θ²**.
//!
//! Below a threshold the Taylor series in x is summed by Horner's rule on the
//! scalar type `D`, so the value *and every dual part* are exact to round-off
//! down to x = 0 (no `sqrt(x)`, whose derivative is infinite at 0, is ever
//! taken on that branch). Above the threshold the closed form is used; the
//! thresholds are placed where the closed form has lost at most a few ulps to
//! cancellation, and the truncated series is below 1e-16 relative:
//!
//! | function | closed form | series used for |
//! |---|---|---|
//! | [`sinc`] | sin θ/θ | x < 1 |
//! | [`cosc`] | (1 − cos θ)/θ² = 2 sin²(θ/2)/θ² | x < 1 |
//! | [`sin3`] | (θ − sin θ)/θ³ | x < 4 |
//! | [`q2`] | (θ² + 2cos θ − 2)/(2θ⁴) | x < 4 |
//! | [`q3`] | (2θ − 3sin θ + θ cos θ)/(2θ⁵) | x < 4 |
//! | [`dlog`] | 1/θ² − cos(θ/2)/(2θ sin(θ/2)) | x < 4 |
//! | [`half_angle_ratio`] | 2 atan2(n, w)/n | n² < w²/100 |
//!
//! Series coefficients are the exact rationals rounded to f64
//! (`dlog` uses the Bernoulli numbers: (θ/2)cot(θ/2) = Σ (−1)ⁿB₂ₙθ²ⁿ/(2n)!).

use num_dual::DualNum;

/// sin θ/θ = Σ (−1)ⁿ xⁿ/(2n+1)!.
const SIN_C: [f64; 16] = [
    1.0,
    -0.16666666666666666,
    0.008333333333333333,
    -0.0001984126984126984,
    2.7557319223985893e-06,
    -2.505210838544172e-08,
    1.6059043836821613e-10,
    -7.647163731819816e-13,
    2.8114572543455206e-15,
    -8.22063524662433e-18,
    1.9572941063391263e-20,
    -3.868170170630684e-23,
    6.446950284384474e-26,
    -9.183689863795546e-29,
    1.1309962886447716e-31,
    -1.216125041553518e-34,
];
/// (1 − cos θ)/θ² = Σ (−1)ⁿ xⁿ/(2n+2)!.
const COS_C: [f64; 16] = [
    0.5,
    -0.041666666666666664,
    0.001388888888888889,
    -2.48015873015873e-05,
    2.755731922398589e-07,
    -2.08767569878681e-09,
    1.1470745597729725e-11,
    -4.779477332387385e-14,
    1.5619206968586225e-16,
    -4.110317623312165e-19,
    8.896791392450574e-22,
    -1.6117375710961184e-24,
    2.4795962632247976e-27,
    -3.279889237069838e-30,
    3.7699876288159054e-33,
    -3.8003907548547434e-36,
];
/// (θ − sin θ)/θ³ = Σ (−1)ⁿ xⁿ/(2n+3)!.
const SIN3_C: [f64; 16] = [
    0.16666666666666666,
    -0.008333333333333333,
    0.0001984126984126984,
    -2.7557319223985893e-06,
    2.505210838544172e-08,
    -1.6059043836821613e-10,
    7.647163731819816e-13,
    -2.8114572543455206e-15,
    8.22063524662433e-18,
    -1.9572941063391263e-20,
    3.868170170630684e-23,
    -6.446950284384474e-26,
    9.183689863795546e-29,
    -1.1309962886447716e-31,
    1.216125041553518e-34,
    -1.151633562077195e-37,
];
/// (θ² + 2 cos θ − 2)/(2θ⁴) = Σ (−1)ⁿ xⁿ/(2n+4)!.
const Q2_C: [f64; 16] = [
    0.041666666666666664,
    -0.001388888888888889,
    2.48015873015873e-05,
    -2.755731922398589e-07,
    2.08767569878681e-09,
    -1.1470745597729725e-11,
    4.779477332387385e-14,
    -1.5619206968586225e-16,
    4.110317623312165e-19,
    -8.896791392450574e-22,
    1.6117375710961184e-24,
    -2.4795962632247976e-27,
    3.279889237069838e-30,
    -3.7699876288159054e-33,
    3.8003907548547434e-36,
    -3.387157535521162e-39,
];
/// (2θ − 3 sin θ + θ cos θ)/(2θ⁵) = Σ (−1)ⁿ (n+1) xⁿ/(2n+5)!.
const Q3_C: [f64; 16] = [
    0.008333333333333333,
    -0.0003968253968253968,
    8.267195767195768e-06,
    -1.0020843354176688e-07,
    8.029521918410807e-10,
    -4.58829823909189e-12,
    1.9680200780418645e-14,
    -6.576508197299464e-17,
    1.7615646957052136e-19,
    -3.868170170630684e-22,
    7.091645312822921e-25,
    -1.1020427836554655e-27,
    1.4702951752382032e-30,
    -1.7025750581749252e-33,
    1.7274503431157927e-36,
    -1.5484148733811025e-39,
];
/// 1/θ² − (1 + cos θ)/(2θ sin θ) = Σ_{n≥1} (−1)ⁿ⁺¹ B₂ₙ x^{n−1}/(2n)! (Bernoulli numbers; radius θ < 2π).
const DLOG_C: [f64; 16] = [
    0.08333333333333333,
    0.001388888888888889,
    3.306878306878307e-05,
    8.267195767195768e-07,
    2.08767569878681e-08,
    5.284190138687493e-10,
    1.3382536530684679e-11,
    3.3896802963225827e-13,
    8.586062056277845e-15,
    2.174868698558062e-16,
    5.5090028283602295e-18,
    1.3954464685812522e-19,
    3.534707039629467e-21,
    8.953517427037546e-23,
    2.267952452337683e-24,
    5.744790668872202e-26,
];
/// atan(t)/t = Σ (−1)ⁿ t²ⁿ/(2n+1).
const ATAN_C: [f64; 12] = [
    1.0,
    -0.3333333333333333,
    0.2,
    -0.14285714285714285,
    0.1111111111111111,
    -0.09090909090909091,
    0.07692307692307693,
    -0.06666666666666667,
    0.058823529411764705,
    -0.05263157894736842,
    0.047619047619047616,
    -0.043478260869565216,
];

/// Upper ends of the ranges of x on which an `f64` evaluation sums only the
/// leading terms of a series ([`term_counts`]).
pub(super) const TIERS: [f64; 5] = [1e-6, 1e-4, 1e-2, 0.1, 1.0];

/// For each bound X of [`TIERS`], the number N of leading coefficients of
/// Σ cₙxⁿ whose omitted tail Σ_{n ≥ N} |cₙ|Xⁿ is at most 2⁻⁵⁸|c₀|: below
/// a quarter of an ulp of every function here, each of which stays above
/// |c₀|/2 on the range its series is used for.
const fn term_counts<const N: usize>(c: &[f64; N]) -> [usize; 5] {
    let mut counts = [N; 5];
    let mut t = 0;
    while t < TIERS.len() {
        let limit = c[0].abs() * (1.0 / 288_230_376_151_711_744.0); // 2⁻⁵⁸|c₀|
        let (mut n, mut tail) = (N, 0.0);
        while n > 1 {
            let mut term = c[n - 1].abs();
            let mut k = 1;
            while k < n {
                term *= TIERS[t];
                k += 1;
            }
            if tail + term > limit {
                break;
            }
            tail += term;
            n -= 1;
        }
        counts[t] = n;
        t += 1;
    }
    counts
}

/// A truncated Taylor series Σ cₙxⁿ with its term counts per tier.
pub(super) struct Series<const N: usize> {
    pub(super) coeffs: [f64; N],
    pub(super) counts: [usize; 5],
}

impl<const N: usize> Series<N> {
    /// The series of `coeffs`; refused at compile time unless its term
    /// counts grow with the tier (which the lanes' evaluation relies on).
    const fn new(coeffs: [f64; N]) -> Self {
        let counts = term_counts(&coeffs);
        let mut t = 1;
        while t < counts.len() {
            assert!(counts[t - 1] <= counts[t], "term counts must grow with the tier");
            t += 1;
        }
        Self { counts, coeffs }
    }

    /// Horner evaluation on the scalar type: every term for dual numbers (so
    /// each derivative part is exact to round-off too), only the terms that
    /// matter at this x for `f64` ([`term_counts`]).
    #[inline]
    fn eval<D: DualNum<Primitive = f64> + Copy>(&self, x: D) -> D {
        if D::NDERIV == 0 {
            let xr = x.re();
            if let Some(t) = TIERS.iter().position(|&bound| xr.abs() <= bound) {
                return D::from(horner(&self.coeffs[..self.counts[t]], xr));
            }
        }
        self.coeffs.iter().rev().fold(D::from(0.0), |acc, &c| acc * x + c)
    }
}

/// Σ_{k<n} c_k x^k by Horner's rule from c_{n−1}, for a finite x and
/// 1 ≤ n ≤ 16 terms, unrolled for each count: the bits of the fold from 0
/// in [`Series::eval`] (0·x + c_{n−1} = c_{n−1} exactly for finite x) in
/// about half the instructions of that loop over a count known only at run
/// time (4.2 % of a rod vertex solve).
#[inline(always)]
fn horner(c: &[f64], x: f64) -> f64 {
    #[inline(always)]
    fn fixed<const K: usize>(c: &[f64], x: f64) -> f64 {
        let mut acc = c[K - 1];
        let mut k = K - 1;
        while k > 0 {
            k -= 1;
            acc = acc * x + c[k];
        }
        acc
    }
    match c.len() {
        1 => fixed::<1>(c, x),
        2 => fixed::<2>(c, x),
        3 => fixed::<3>(c, x),
        4 => fixed::<4>(c, x),
        5 => fixed::<5>(c, x),
        6 => fixed::<6>(c, x),
        7 => fixed::<7>(c, x),
        8 => fixed::<8>(c, x),
        9 => fixed::<9>(c, x),
        10 => fixed::<10>(c, x),
        11 => fixed::<11>(c, x),
        12 => fixed::<12>(c, x),
        13 => fixed::<13>(c, x),
        14 => fixed::<14>(c, x),
        15 => fixed::<15>(c, x),
        _ => c.iter().rev().fold(0.0, |acc, &ck| acc * x + ck),
    }
}

pub(super) const SIN: Series<16> = Series::new(SIN_C);
pub(super) const COS: Series<16> = Series::new(COS_C);
pub(super) const SIN3: Series<16> = Series::new(SIN3_C);
const Q2: Series<16> = Series::new(Q2_C);
const Q3: Series<16> = Series::new(Q3_C);
pub(super) const DLOG: Series<16> = Series::new(DLOG_C);
pub(super) const ATAN: Series<12> = Series::new(ATAN_C);
pub(super) const DLOG_PRIME: Series<15> = Series::new(derivative(&DLOG_C));

/// The coefficients (n + 1)c_{n+1} of the derivative of Σ cₙxⁿ.
const fn derivative(c: &[f64; 16]) -> [f64; 15] {
    let mut d = [0.0; 15];
    let mut n = 0;
    while n < 15 {
        d[n] = (n + 1) as f64 * c[n + 1];
        n += 1;
    }
    d
}

/// sin θ/θ as a function of x = θ².
pub(crate) fn sinc<D: DualNum<Primitive = f64> + Copy>(x: D) -> D {
    if x.re() < 1.0 {
        SIN.eval(x)
    } else {
        let t = x.sqrt();
        t.sin() / t
    }
}

/// (1 − cos θ)/θ² as a function of x = θ².
pub(crate) fn cosc<D: DualNum<Primitive = f64> + Copy>(x: D) -> D {
    if x.re() < 1.0 {
        COS.eval(x)
    } else {
        let s = (x.sqrt() * 0.5).sin();
        s * s * 2.0 / x
    }
}

/// (θ − sin θ)/θ³ as a function of x = θ².
pub(crate) fn sin3<D: DualNum<Primitive = f64> + Copy>(x: D) -> D {
    if x.re() < 4.0 {
        SIN3.eval(x)
    } else {
        let t = x.sqrt();
        (t - t.sin()) / (t * x)
    }
}

/// (θ² + 2 cos θ − 2)/(2θ⁴) as a function of x = θ².
pub(crate) fn q2<D: DualNum<Primitive = f64> + Copy>(x: D) -> D {
    if x.re() < 4.0 {
        Q2.eval(x)
    } else {
        let t = x.sqrt();
        (x + t.cos() * 2.0 - 2.0) / (x * x * 2.0)
    }
}

/// (2θ − 3 sin θ + θ cos θ)/(2θ⁵) as a function of x = θ².
pub(crate) fn q3<D: DualNum<Primitive = f64> + Copy>(x: D) -> D {
    if x.re() < 4.0 {
        Q3.eval(x)
    } else {
        let t = x.sqrt();
        let (s, c) = t.sin_cos();
        (t * 2.0 - s * 3.0 + t * c) / (x * x * t * 2.0)
    }
}

/// k(θ) = 1/θ² − (1 + cos θ)/(2θ sin θ) (note 003 Def. 6.9) as a function of
/// x = θ². Finite for 0 ≤ θ < 2π (k(π) = 1/π²); singular at θ = 2π.
pub(crate) fn dlog<D: DualNum<Primitive = f64> + Copy>(x: D) -> D {
    if x.re() < 4.0 {
        DLOG.eval(x)
    } else {
        let t = x.sqrt();
        let (s, c) = (t * 0.5).sin_cos();
        x.recip() - c / (t * s * 2.0)
    }
}

/// [`dlog`] k(x) and its derivative dk/dx in `f64` (the derivative series
/// summed like the function's; dual numbers on the closed form above x = 4).
pub(crate) fn dlog_and_derivative(x: f64) -> (f64, f64) {
    if x < 4.0 {
        (DLOG.eval(x), DLOG_PRIME.eval(x))
    } else {
        let k = dlog(num_dual::Dual64::from_re(x).derivative());
        (k.re, k.eps)
    }
}

/// θ/sin θ = atan2(n, c)/n for an angle θ < π/2 given by c = cos θ > 0 and
/// n2 = sin²θ (n = √n2): the factor turning s = sin θ·n of a rotation matrix
/// into its rotation vector. Smooth in (c, n2) at n2 = 0 (series in
/// t² = n2/c² = tan²θ below t² = 1/100).
pub(crate) fn angle_over_sine<D: DualNum<Primitive = f64> + Copy>(c: D, n2: D) -> D {
    let cr = c.re();
    if n2.re() < 0.01 * cr * cr {
        // One division: atan(t)/t at t² = n2·(1/c)², times 1/c.
        let inv = c.recip();
        ATAN.eval(n2 * inv * inv) * inv
    } else {
        let n = n2.sqrt();
        n.atan2(c) / n
    }
}

/// 2 atan2(n, w)/n with n = √n2: the factor turning the vector part q_v of a
/// unit quaternion (w ≥ 0) into its rotation vector, ω = (2 atan2(|q_v|, w)/|q_v|) q_v.
/// Smooth in (w, n2) at n2 = 0 (series in t² = n2/w²).
pub(crate) fn half_angle_ratio<D: DualNum<Primitive = f64> + Copy>(w: D, n2: D) -> D {
    let wr = w.re();
    if wr > 0.0 && n2.re() < 0.01 * wr * wr {
        ATAN.eval(n2 / (w * w)) * 2.0 / w
    } else {
        let n = n2.sqrt();
        n.atan2(w) * 2.0 / n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::{Dual2_64, Dual64};

    /// Closed forms evaluated directly in f64 (reference away from θ = 0),
    /// with their cancellation factor Σ|terms| / |result|: the reference itself
    /// is only accurate to a few ε times that factor.
    fn closed(theta: f64) -> [(f64, f64); 6] {
        let (s, c, x) = (theta.sin(), theta.cos(), theta * theta);
        let amp = |terms: &[f64]| terms.iter().map(|t| t.abs()).sum::<f64>() / terms.iter().sum::<f64>().abs();
        [
            (s / theta, 1.0),
            ((1.0 - c) / x, amp(&[1.0, -c])),
            ((theta - s) / (theta * x), amp(&[theta, -s])),
            ((x + 2.0 * c - 2.0) / (2.0 * x * x), amp(&[x, 2.0 * c, -2.0])),
            (
                (2.0 * theta - 3.0 * s + theta * c) / (2.0 * x * x * theta),
                amp(&[2.0 * theta, -3.0 * s, theta * c]),
            ),
            (
                1.0 / x - (1.0 + c) / (2.0 * theta * s),
                amp(&[1.0 / x, -(1.0 + c) / (2.0 * theta * s)]),
            ),
        ]
    }

    fn ours(x: f64) -> [f64; 6] {
        [sinc(x), cosc(x), sin3(x), q2(x), q3(x), dlog(x)]
    }

    /// Series and closed forms agree to 4ε × (cancellation factor of the f64
    /// reference) + 4ε on θ ∈ [0.3, 3] (series and closed branches); and the branches join continuously at
    /// the thresholds x = 1 and x = 4 (both sides within a few ulps there).
    #[test]
    fn series_match_closed_forms() {
        let eps = f64::EPSILON;
        for &theta in &[0.3, 0.6, 0.9, 1.2, 1.5, 1.9, 2.0, 2.5, 3.0] {
            let (a, b) = (ours(theta * theta), closed(theta));
            for i in 0..6 {
                let tol = (4.0 * b[i].1 + 4.0) * eps * b[i].0.abs();
                assert!((a[i] - b[i].0).abs() <= tol, "θ={theta} i={i}: {} vs {}", a[i], b[i].0);
            }
        }
        for &x in &[1.0f64, 4.0] {
            for i in 0..6 {
                let (lo, hi) = (ours(x * (1.0 - 1e-15))[i], ours(x * (1.0 + 1e-15))[i]);
                assert!(
                    (lo - hi).abs() <= 16.0 * eps * hi.abs(),
                    "jump at x={x} i={i}: {lo} vs {hi}"
                );
            }
        }
    }

    /// At tiny angles the two-term Taylor expansion is exact to round-off, so
    /// this checks the series coefficients directly (note 003 T22b: k(α) within
    /// 1e-12 of its series for α ≤ 1e-3).
    #[test]
    fn small_angle_values() {
        for &t in &[0.0, 1e-12, 1e-9, 1e-6, 1e-3] {
            let x: f64 = t * t;
            let expect = [
                1.0 - x / 6.0 + x * x / 120.0,
                0.5 - x / 24.0 + x * x / 720.0,
                1.0 / 6.0 - x / 120.0 + x * x / 5040.0,
                1.0 / 24.0 - x / 720.0 + x * x / 40320.0,
                1.0 / 120.0 - x / 2520.0 + x * x / 120960.0,
                1.0 / 12.0 + x / 720.0 + x * x / 30240.0,
            ];
            let got = ours(x);
            for i in 0..6 {
                assert!((got[i] - expect[i]).abs() <= 1e-15 * expect[i].abs(), "t={t} i={i}");
            }
        }
    }

    /// Dual parts: d/dx of every coefficient at x = 0 equals the linear
    /// Taylor coefficient exactly, and second derivatives are finite and exact
    /// (Dual2), which a sqrt-based evaluation could not give.
    #[test]
    fn derivatives_at_zero_are_exact() {
        let lin = [
            -1.0 / 6.0,
            -1.0 / 24.0,
            -1.0 / 120.0,
            -1.0 / 720.0,
            -1.0 / 2520.0,
            1.0 / 720.0,
        ];
        let quad = [
            1.0 / 120.0,
            1.0 / 720.0,
            1.0 / 5040.0,
            1.0 / 40320.0,
            1.0 / 120960.0,
            1.0 / 30240.0,
        ];
        let x = Dual64::new(0.0, 1.0);
        let d1 = [sinc(x), cosc(x), sin3(x), q2(x), q3(x), dlog(x)];
        let x2 = Dual2_64::new(0.0, 1.0, 0.0);
        let d2 = [sinc(x2), cosc(x2), sin3(x2), q2(x2), q3(x2), dlog(x2)];
        for i in 0..6 {
            assert!((d1[i].eps - lin[i]).abs() <= 1e-18, "i={i}");
            assert!((d2[i].v2 - 2.0 * quad[i]).abs() <= 1e-18, "i={i}");
        }
    }

    /// Above the thresholds the dual part of the closed form matches a central
    /// difference of the f64 function (h = 1e-6: truncation ~1e-12, round-off
    /// ~1e-10 relative; tolerance 1e-8).
    #[test]
    fn derivatives_match_finite_differences() {
        for &x0 in &[0.3, 0.99, 1.01, 2.0, 3.99, 4.01, 6.0, 9.0] {
            let d = Dual64::new(x0, 1.0);
            let ad = [sinc(d).eps, cosc(d).eps, sin3(d).eps, q2(d).eps, q3(d).eps, dlog(d).eps];
            let h = 1e-6;
            let (p, m) = (ours(x0 + h), ours(x0 - h));
            for i in 0..6 {
                let fd = (p[i] - m[i]) / (2.0 * h);
                assert!(
                    (ad[i] - fd).abs() <= 1e-8 * (1.0 + fd.abs()),
                    "x={x0} i={i}: {} vs {fd}",
                    ad[i]
                );
            }
        }
    }

    /// The unrolled Horner sums give the bits of the fold from zero they
    /// replace, for every count of terms of every series and for x across
    /// the tiers, both signs, and zero.
    #[test]
    fn unrolled_horner_gives_the_bits_of_the_fold() {
        let fold = |c: &[f64], x: f64| c.iter().rev().fold(0.0, |acc, &ck| acc * x + ck);
        let series: [&[f64]; 7] = [&SIN_C, &COS_C, &SIN3_C, &Q2_C, &Q3_C, &DLOG_C, &ATAN_C];
        let mut uniform = crate::test_support::uniform(0x9e37_79b9_7f4a_7c15);
        for c in series {
            for n in 1..=c.len() {
                for scale in [0.0, 1e-7, 1e-5, 1e-3, 0.05, 0.5, 1.0] {
                    let x = uniform() * scale;
                    let (ours, theirs) = (horner(&c[..n], x), fold(&c[..n], x));
                    assert_eq!(ours.to_bits(), theirs.to_bits(), "{n} terms at x = {x:e}");
                }
            }
        }
    }

    /// The `f64` sums of fewer terms equal the full sums (the real parts of
    /// the dual evaluations, which sum every term) to an ulp, on each tier and
    /// at its ends; dk/dx likewise against the dual part.
    #[test]
    fn truncated_sums_equal_the_full_sums() {
        let full = |x: f64| {
            let d = Dual64::from_re(x).derivative();
            [sinc(d), cosc(d), sin3(d), q2(d), q3(d), dlog(d)]
        };
        let mut xs = vec![0.0, 3.9];
        for &bound in &TIERS {
            xs.extend([bound * 0.37, bound * 0.999_999, bound, bound * 1.000_001]);
        }
        for &x in &xs {
            let short = ours(x);
            for (k, (a, b)) in short.iter().zip(full(x)).enumerate() {
                if k < 2 && x >= 1.0 {
                    continue;
                }
                assert!(
                    (a - b.re).abs() <= f64::EPSILON * b.re.abs(),
                    "function {k} at x = {x}: {a} vs {}",
                    b.re
                );
            }
            let (k, dk) = dlog_and_derivative(x);
            let d = full(x)[5];
            assert!((k - d.re).abs() <= f64::EPSILON * d.re, "k at x = {x}");
            assert!(
                (dk - d.eps).abs() <= 2.0 * f64::EPSILON * d.eps,
                "dk/dx at x = {x}: {dk} vs {}",
                d.eps
            );
            let (w, n2) = (1.0, 0.0099 * x.min(1.0));
            let t = Dual64::from_re(n2).derivative();
            let r = half_angle_ratio(w, n2);
            assert!((r - half_angle_ratio(Dual64::from_re(w), t).re).abs() <= f64::EPSILON * r);
        }
        // Fewer terms near zero: the point of the tiers.
        assert!(DLOG.counts[0] <= 4 && DLOG.counts[2] <= 8, "{:?}", DLOG.counts);
        assert!(SIN.counts[0] <= 3, "{:?}", SIN.counts);
    }

    #[test]
    fn half_angle_ratio_both_branches() {
        for &theta in &[0.0, 1e-9, 0.1, 0.19, 0.21, 1.0, 3.0] {
            let (w, n): (f64, f64) = ((theta / 2.0).cos(), (theta / 2.0).sin());
            let expect = if theta == 0.0 { 2.0 } else { theta / n };
            let got = half_angle_ratio(w, n * n);
            assert!((got - expect).abs() <= 4e-16 * expect, "θ={theta}");
        }
    }
}
