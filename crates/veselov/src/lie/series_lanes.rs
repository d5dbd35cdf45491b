//! The coefficient functions of [`super::series`] on `f64` in `L` lanes at
//! once, each lane with the bits the scalar function gives it: every lane
//! sums its own tier's number of terms by the same Horner steps
//! ([`Series`]), so lanes solved side by side agree bit for bit with the
//! same values solved one at a time. Only the series branches are here: a
//! function returns `None` when some lane needs the closed form (a larger
//! angle), and the caller then takes the scalar path for the whole group.

use super::series::{ATAN, COS, DLOG, DLOG_PRIME, SIN, SIN3, Series, TIERS};

impl<const N: usize> Series<N> {
    /// [`Series::eval`] on `f64` in each lane (`x` finite): the terms of the
    /// lane's tier (all N beyond the last tier) summed by Horner's rule from
    /// the highest, c_{K−1}, as the scalar sum does.
    #[inline(always)]
    fn eval_lanes<const L: usize>(&self, x: &[f64; L]) -> [f64; L] {
        // The count grows with |x| (`Series::new` checks it), so lanes whose
        // smallest and largest |x| take the same count all take it.
        let count_at = |a: f64| TIERS.iter().position(|&b| a <= b).map_or(N, |t| self.counts[t]);
        let (mut low, mut high) = (f64::INFINITY, 0.0_f64);
        for v in x {
            low = low.min(v.abs());
            high = high.max(v.abs());
        }
        let k = count_at(high);
        if k > 0 && count_at(low) == k {
            // One count for all: the same Horner steps side by side.
            let mut acc = [self.coeffs[k - 1]; L];
            for &c in self.coeffs[..k - 1].iter().rev() {
                for (a, &x) in acc.iter_mut().zip(x) {
                    *a = *a * x + c;
                }
            }
            return acc;
        }
        // The first tier whose bound holds |x| (N terms past the last, or
        // for NaN), as `Series::eval` picks it, by selects over the lanes.
        let count: [usize; L] = std::array::from_fn(|l| {
            let a = x[l].abs();
            let mut count = N;
            for t in (0..TIERS.len()).rev() {
                if a <= TIERS[t] {
                    count = self.counts[t];
                }
            }
            count
        });
        let most = count.iter().copied().max().unwrap_or(0);
        let mut acc = [0.0; L];
        for k in (0..most).rev() {
            let c = self.coeffs[k];
            for l in 0..L {
                let next = acc[l] * x[l] + c;
                acc[l] = if k + 1 < count[l] {
                    next
                } else if k + 1 == count[l] {
                    c
                } else {
                    acc[l]
                };
            }
        }
        acc
    }
}

/// (sinc, cosc) of [`super::series`] at x = θ² in each lane, `None` unless
/// every x < 1 (the series branch of both).
#[inline(always)]
pub(crate) fn sinc_cosc<const L: usize>(x: &[f64; L]) -> Option<([f64; L], [f64; L])> {
    x.iter()
        .all(|&v| v < 1.0)
        .then(|| (SIN.eval_lanes(x), COS.eval_lanes(x)))
}

/// (cosc, sin3) of [`super::series`] at x = θ² in each lane, `None` unless
/// every x < 1 (the series branch of both: `so3::dexp`'s coefficients).
#[inline(always)]
pub(crate) fn cosc_sin3<const L: usize>(x: &[f64; L]) -> Option<([f64; L], [f64; L])> {
    x.iter()
        .all(|&v| v < 1.0)
        .then(|| (COS.eval_lanes(x), SIN3.eval_lanes(x)))
}

/// [`super::series::dlog`] in each lane, `None` unless every x < 4.
#[inline(always)]
pub(crate) fn dlog<const L: usize>(x: &[f64; L]) -> Option<[f64; L]> {
    x.iter().all(|&v| v < 4.0).then(|| DLOG.eval_lanes(x))
}

/// [`super::series::dlog_and_derivative`] in each lane, `None` unless
/// every x < 4.
#[inline(always)]
pub(crate) fn dlog_and_derivative<const L: usize>(x: &[f64; L]) -> Option<([f64; L], [f64; L])> {
    x.iter()
        .all(|&v| v < 4.0)
        .then(|| (DLOG.eval_lanes(x), DLOG_PRIME.eval_lanes(x)))
}

/// [`super::series::angle_over_sine`] (θ/sin θ from c = cos θ and
/// n2 = sin²θ) in each lane, `None` unless every n2 < 0.01c² (the series
/// of atan(t)/t).
#[inline(always)]
pub(crate) fn angle_over_sine<const L: usize>(c: &[f64; L], n2: &[f64; L]) -> Option<[f64; L]> {
    if !(0..L).all(|l| n2[l] < 0.01 * c[l] * c[l]) {
        return None;
    }
    let inv = c.map(f64::recip);
    let mut t = *n2;
    for (t, inv) in t.iter_mut().zip(inv) {
        *t = *t * inv * inv;
    }
    let mut ratio = ATAN.eval_lanes(&t);
    for (r, inv) in ratio.iter_mut().zip(inv) {
        *r *= inv;
    }
    Some(ratio)
}

#[cfg(test)]
mod tests {
    use super::super::series;
    use super::*;

    /// Arguments over every tier and up to the branch points, zero, and
    /// some just past them.
    fn arguments() -> Vec<f64> {
        let mut x = vec![
            0.0,
            1e-300,
            1e-7,
            1e-6,
            1.000_000_1e-6,
            3e-5,
            1e-4,
            5e-3,
            1e-2,
            0.05,
            0.1,
            0.5,
            0.999,
            1.0,
        ];
        let mut s = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..400 {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            x.push(u * u * u * 3.9);
        }
        x
    }

    /// Each lane's value has the bits of the scalar function's at its
    /// argument, whatever its neighbours' tiers, and a group with a lane on
    /// the closed-form branch is refused.
    #[test]
    fn lanes_give_the_bits_of_the_scalar_functions() {
        let x = arguments();
        for group in x.windows(4) {
            let g: [f64; 4] = group.try_into().expect("four");
            if let Some((s, c)) = sinc_cosc(&g) {
                for l in 0..4 {
                    assert_eq!(s[l].to_bits(), series::sinc(g[l]).to_bits(), "sinc at {}", g[l]);
                    assert_eq!(c[l].to_bits(), series::cosc(g[l]).to_bits(), "cosc at {}", g[l]);
                }
            } else {
                assert!(g.iter().any(|&v| v >= 1.0));
            }
            let (k, dk) = dlog_and_derivative(&g).expect("x < 4");
            let k1 = dlog(&g).expect("x < 4");
            for l in 0..4 {
                let (ks, dks) = series::dlog_and_derivative(g[l]);
                assert_eq!(
                    (k[l].to_bits(), dk[l].to_bits()),
                    (ks.to_bits(), dks.to_bits()),
                    "dlog at {}",
                    g[l]
                );
                assert_eq!(k1[l].to_bits(), series::dlog(g[l]).to_bits());
            }
            // cos θ from 1 down to 0.5 and sin²θ up to the series' limit.
            let c: [f64; 4] = std::array::from_fn(|l| 1.0 - g[l] / 8.0);
            let n2: [f64; 4] = std::array::from_fn(|l| g[l] * c[l] * c[l] / 400.0);
            let r = angle_over_sine(&c, &n2).expect("n2 < 0.01 c²");
            for l in 0..4 {
                assert_eq!(r[l].to_bits(), series::angle_over_sine(c[l], n2[l]).to_bits());
            }
        }
        assert!(sinc_cosc(&[0.5, 1.0]).is_none());
        assert!(dlog(&[0.5, 4.0]).is_none());
        assert!(angle_over_sine(&[1.0, 1.0], &[0.0, 0.01]).is_none());
    }
}
