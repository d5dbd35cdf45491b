//! Arithmetic in `L` lanes for the rod's vertex solves side by side
//! ([`crate::models::rod::cosserat::lane_step`]): 3-vectors and 3×3 matrices of [`Lanes`], each
//! operation the one the scalar step performs, in the same order (nalgebra's
//! products sum their three terms from the first; [`crate::ad::mat3_vec`]
//! and its siblings likewise), and the SO(3) maps of [`crate::lie::so3`] on
//! their series branches. Every lane therefore gets the bits the scalar
//! step gives it alone (tested against nalgebra and `so3` here); a map
//! returns `None` where some lane needs a branch with a transcendental
//! function, and the group is then solved one vertex at a time.

use std::ops::{Add, Div, Mul, Neg, Sub};

use nalgebra::{Matrix3, Vector3};

use crate::lie::series_lanes;

/// One `f64` per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Lanes<const L: usize>(pub(super) [f64; L]);

impl<const L: usize> Lanes<L> {
    #[inline(always)]
    pub(super) fn splat(x: f64) -> Self {
        Self([x; L])
    }

    #[inline(always)]
    pub(super) fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut out = [0.0; L];
        for (l, x) in out.iter_mut().enumerate() {
            *x = f(l);
        }
        Self(out)
    }

    #[inline(always)]
    pub(super) fn map(mut self, f: impl Fn(f64) -> f64) -> Self {
        for x in self.0.iter_mut() {
            *x = f(*x);
        }
        self
    }

    #[inline(always)]
    pub(super) fn zip(mut self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        for (x, y) in self.0.iter_mut().zip(other.0) {
            *x = f(*x, y);
        }
        self
    }

    #[inline(always)]
    pub(super) fn abs(self) -> Self {
        self.map(f64::abs)
    }

    /// `f64::max` in each lane.
    #[inline(always)]
    pub(super) fn max(self, other: Self) -> Self {
        self.zip(other, f64::max)
    }
}

macro_rules! lane_op {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const L: usize> $trait for Lanes<L> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: Self) -> Self {
                self.zip(rhs, |x, y| x $op y)
            }
        }
        impl<const L: usize> $trait<f64> for Lanes<L> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, rhs: f64) -> Self {
                self.map(|x| x $op rhs)
            }
        }
    };
}
lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl<const L: usize> Neg for Lanes<L> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|x| -x)
    }
}

/// A 3-vector in lanes.
pub(super) type V3<const L: usize> = [Lanes<L>; 3];
/// A 3×3 matrix in lanes, `m[i][j]` its entry (i, j).
pub(super) type M3<const L: usize> = [[Lanes<L>; 3]; 3];

/// The vectors `f(l)` of the lanes; with `same`, `f(0)` in every lane
/// (broadcast, for values known to be one for all lanes).
#[inline(always)]
pub(super) fn gather_v3<const L: usize>(same: bool, f: impl Fn(usize) -> Vector3<f64>) -> V3<L> {
    let mut out = [Lanes::splat(0.0); 3];
    if same {
        let v = f(0);
        for i in 0..3 {
            out[i] = Lanes::splat(v[i]);
        }
        return out;
    }
    for l in 0..L {
        let v = f(l);
        for i in 0..3 {
            out[i].0[l] = v[i];
        }
    }
    out
}

/// The matrices `f(l)` of the lanes; with `same`, `f(0)` in every lane
/// (broadcast, for values known to be one for all lanes).
#[inline(always)]
pub(super) fn gather_m3<'a, const L: usize>(same: bool, f: impl Fn(usize) -> &'a Matrix3<f64>) -> M3<L> {
    let mut out = [[Lanes::splat(0.0); 3]; 3];
    if same {
        let m = f(0);
        for (i, row) in out.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = Lanes::splat(m[(i, j)]);
            }
        }
        return out;
    }
    for l in 0..L {
        let m = f(l);
        for (i, row) in out.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                x.0[l] = m[(i, j)];
            }
        }
    }
    out
}

/// Lane `l` of a vector.
#[inline(always)]
pub(super) fn lane_v3<const L: usize>(v: &V3<L>, l: usize) -> Vector3<f64> {
    Vector3::new(v[0].0[l], v[1].0[l], v[2].0[l])
}

/// Lane `l` of a matrix.
#[inline(always)]
pub(super) fn lane_m3<const L: usize>(m: &M3<L>, l: usize) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| m[i][j].0[l])
}

#[inline(always)]
pub(super) fn add<const L: usize>(a: &V3<L>, b: &V3<L>) -> V3<L> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
pub(super) fn sub<const L: usize>(a: &V3<L>, b: &V3<L>) -> V3<L> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub(super) fn neg<const L: usize>(a: &V3<L>) -> V3<L> {
    [-a[0], -a[1], -a[2]]
}

/// a·s (each entry times the lane's s).
#[inline(always)]
pub(super) fn scale<const L: usize>(a: &V3<L>, s: Lanes<L>) -> V3<L> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// a·s for one factor in every lane.
#[inline(always)]
pub(super) fn scale_by<const L: usize>(a: &V3<L>, s: f64) -> V3<L> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// (a₀b₀ + a₁b₁) + a₂b₂ (nalgebra's `dot`).
#[inline(always)]
pub(super) fn dot<const L: usize>(a: &V3<L>, b: &V3<L>) -> Lanes<L> {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b (nalgebra's `cross`).
#[inline(always)]
pub(super) fn cross<const L: usize>(a: &V3<L>, b: &V3<L>) -> V3<L> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// m v, each entry (m_{i0}v₀ + m_{i1}v₁) + m_{i2}v₂ (nalgebra's product
/// and [`crate::ad::mat3_vec`] alike).
#[inline(always)]
pub(super) fn mv<const L: usize>(m: &M3<L>, v: &V3<L>) -> V3<L> {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// mᵀv, each entry (m_{0i}v₀ + m_{1i}v₁) + m_{2i}v₂ (nalgebra's `tr_mul`
/// and `transpose() *` alike).
#[inline(always)]
pub(super) fn tmv<const L: usize>(m: &M3<L>, v: &V3<L>) -> V3<L> {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

/// a b ([`crate::ad::mat3_mul`], nalgebra's product).
#[inline(always)]
pub(super) fn mm<const L: usize>(a: &M3<L>, b: &M3<L>) -> M3<L> {
    let mut out = [[Lanes::splat(0.0); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    out
}

/// aᵀb ([`crate::ad::mat3_tr_mul`]: `SO3::between`).
#[inline(always)]
pub(super) fn tmm<const L: usize>(a: &M3<L>, b: &M3<L>) -> M3<L> {
    let mut out = [[Lanes::splat(0.0); 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = a[0][i] * b[0][j] + a[1][i] * b[1][j] + a[2][i] * b[2][j];
        }
    }
    out
}

/// max |vᵢ| (`solve::largest_abs`: NaN entries pass unseen).
#[inline(always)]
pub(super) fn largest_abs<const L: usize>(v: &V3<L>) -> Lanes<L> {
    Lanes::splat(0.0).max(v[0].abs()).max(v[1].abs()).max(v[2].abs())
}

/// max |m_ij| (`solve::largest_abs` of a matrix).
#[inline(always)]
pub(super) fn largest_abs_m3<const L: usize>(m: &M3<L>) -> Lanes<L> {
    let mut largest = Lanes::splat(0.0);
    for j in 0..3 {
        for row in m {
            largest = largest.max(row[j].abs());
        }
    }
    largest
}

/// max_i Σ_j |m_ij|, each row summed from its first entry
/// (`m.abs().column_sum()`, then its largest entry).
#[inline(always)]
pub(super) fn row_sum_norm<const L: usize>(m: &M3<L>) -> Lanes<L> {
    let mut sums: V3<L> = [Lanes::splat(0.0); 3];
    for (sum, row) in sums.iter_mut().zip(m) {
        *sum = *sum + row[0].abs() + row[1].abs() + row[2].abs();
    }
    largest_abs(&sums)
}

/// I + a ω̂ + b ω̂², entry by entry as `so3`'s `hat_series`:
/// 1 (or 0) + a·ω̂_ij + b·(ω̂²)_ij, ω̂² = ωωᵀ − |ω|²I.
#[inline(always)]
fn hat_series<const L: usize>(w: &V3<L>, a: Lanes<L>, b: Lanes<L>) -> M3<L> {
    let z = Lanes::splat(0.0);
    let hat = [[z, -w[2], w[1]], [w[2], z, -w[0]], [-w[1], w[0], z]];
    let n2 = dot(w, w);
    let mut out = [[z; 3]; 3];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            let square = if i == j { w[i] * w[j] - n2 } else { w[i] * w[j] };
            let one = Lanes::splat(if i == j { 1.0 } else { 0.0 });
            *x = one + hat[i][j] * a + square * b;
        }
    }
    out
}

/// `so3::exp` (Rodrigues with sinc and cosc at |ω|²), `None` unless every
/// |ω|² < 1.
#[inline(always)]
pub(super) fn exp<const L: usize>(w: &V3<L>) -> Option<M3<L>> {
    let x = dot(w, w);
    let (sinc, cosc) = series_lanes::sinc_cosc(&x.0)?;
    Some(hat_series(w, Lanes(sinc), Lanes(cosc)))
}

/// `so3::dexp(w)` = I + cosc(|ω|²)ω̂ + sin3(|ω|²)ω̂², `None` unless every
/// |ω|² < 1.
#[inline(always)]
pub(super) fn dexp<const L: usize>(w: &V3<L>) -> Option<M3<L>> {
    let (cosc, sin3) = series_lanes::cosc_sin3(&dot(w, w).0)?;
    Some(hat_series(w, Lanes(cosc), Lanes(sin3)))
}

/// mᵀ (the entries moved, no arithmetic).
#[inline(always)]
pub(super) fn transpose<const L: usize>(m: &M3<L>) -> M3<L> {
    std::array::from_fn(|i| std::array::from_fn(|j| m[j][i]))
}

/// `so3::dexp_inv(w)` = I − ω̂/2 + dlog(|ω|²)ω̂², `None` unless every
/// |ω|² < 4.
#[inline(always)]
pub(super) fn dexp_inv<const L: usize>(w: &V3<L>) -> Option<M3<L>> {
    let k = series_lanes::dlog(&dot(w, w).0)?;
    Some(hat_series(w, Lanes::splat(-0.5), Lanes(k)))
}

/// `so3::log` of rotations below a quarter turn with tan θ ≤ 0.1 (its
/// series branch: s·θ/sin θ from s = ½(R − Rᵀ)ˇ and c = ½(tr R − 1)),
/// `None` unless every lane is there.
#[inline(always)]
pub(super) fn log<const L: usize>(m: &M3<L>) -> Option<V3<L>> {
    let c = (m[0][0] + m[1][1] + m[2][2] - 1.0) * 0.5;
    if !c.0.iter().all(|&x| x > 0.0) {
        return None;
    }
    let s = [
        (m[2][1] - m[1][2]) * 0.5,
        (m[0][2] - m[2][0]) * 0.5,
        (m[1][0] - m[0][1]) * 0.5,
    ];
    let ratio = Lanes(series_lanes::angle_over_sine(&c.0, &dot(&s, &s).0)?);
    Some(scale(&s, ratio))
}

/// The Newton–Schulz step R(3I − RᵀR)/2 of `Rotations::renormalize`.
#[inline(always)]
pub(super) fn renormalize<const L: usize>(r: &M3<L>) -> M3<L> {
    let mut m = tmm(r, r);
    for (i, row) in m.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = Lanes::splat(if i == j { 3.0 } else { 0.0 }) - *x;
        }
    }
    let mut p = mm(r, &m);
    for x in p.iter_mut().flatten() {
        *x = *x * 0.5;
    }
    p
}

/// The inverse by nalgebra's cofactors of a 3×3 matrix (`try_inverse`),
/// and in each lane whether it exists (determinant not zero; the lane's
/// entries are then not finite).
#[inline(always)]
pub(super) fn inverse<const L: usize>(m: &M3<L>) -> (M3<L>, [bool; L]) {
    let [[m11, m12, m13], [m21, m22, m23], [m31, m32, m33]] = *m;
    let minor_m12_m23 = m22 * m33 - m32 * m23;
    let minor_m11_m23 = m21 * m33 - m31 * m23;
    let minor_m11_m22 = m21 * m32 - m31 * m22;
    let det = m11 * minor_m12_m23 - m12 * minor_m11_m23 + m13 * minor_m11_m22;
    let regular = det.0.map(|d| d != 0.0);
    let inv = [
        [
            minor_m12_m23 / det,
            (m13 * m32 - m33 * m12) / det,
            (m12 * m23 - m22 * m13) / det,
        ],
        [
            -minor_m11_m23 / det,
            (m11 * m33 - m31 * m13) / det,
            (m13 * m21 - m23 * m11) / det,
        ],
        [
            minor_m11_m22 / det,
            (m12 * m31 - m32 * m11) / det,
            (m11 * m22 - m21 * m12) / det,
        ],
    ];
    (inv, regular)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ad::{mat3_mul, mat3_tr_mul, mat3_vec};
    use crate::field::fibre::{Fibre, Rotations};
    use crate::lie::so3::{self, SO3};
    use crate::solve::largest_abs as scalar_largest_abs;

    const L: usize = 4;

    fn random(seed: u64) -> impl FnMut() -> f64 {
        crate::test_support::uniform(seed)
    }

    fn vectors(next: &mut impl FnMut() -> f64, size: f64) -> [Vector3<f64>; L] {
        std::array::from_fn(|_| Vector3::new(next(), next(), next()) * size)
    }

    fn matrices(next: &mut impl FnMut() -> f64) -> [Matrix3<f64>; L] {
        std::array::from_fn(|_| Matrix3::from_fn(|_, _| next() * 3.0))
    }

    fn same_v(a: &Vector3<f64>, b: &Vector3<f64>, what: &str) {
        for i in 0..3 {
            assert_eq!(a[i].to_bits(), b[i].to_bits(), "{what}[{i}]: {} vs {}", a[i], b[i]);
        }
    }

    fn same_m(a: &Matrix3<f64>, b: &Matrix3<f64>, what: &str) {
        for i in 0..3 {
            for j in 0..3 {
                assert_eq!(a[(i, j)].to_bits(), b[(i, j)].to_bits(), "{what}[{i},{j}]");
            }
        }
    }

    /// The products, sums, norms and the inverse have nalgebra's and the
    /// `ad` helpers' bits in every lane.
    #[test]
    fn linear_algebra_has_the_scalar_bits() {
        let mut next = random(0x51ed_2701_b3c4_9a5f);
        for _ in 0..200 {
            let (a, b) = (vectors(&mut next, 2.0), vectors(&mut next, 1e-3));
            let (m, n) = (matrices(&mut next), matrices(&mut next));
            let (la, lb) = (gather_v3::<L>(false, |l| a[l]), gather_v3::<L>(false, |l| b[l]));
            let (lm, ln) = (gather_m3::<L>(false, |l| &m[l]), gather_m3::<L>(false, |l| &n[l]));
            let (prod, tprod, sq, tsq) = (mv(&lm, &la), tmv(&lm, &la), mm(&lm, &ln), tmm(&lm, &ln));
            let (cr, d, big, bigm, rows) = (
                cross(&la, &lb),
                dot(&la, &lb),
                largest_abs(&la),
                largest_abs_m3(&lm),
                row_sum_norm(&lm),
            );
            let (inv, regular) = inverse(&lm);
            // A broadcast is the gather of one value into every lane.
            let (ba, bm) = (gather_v3::<L>(true, |l| a[l]), gather_m3::<L>(true, |l| &m[l]));
            for l in 0..L {
                same_v(&lane_v3(&ba, l), &a[0], "broadcast vector");
                same_m(&lane_m3(&bm, l), &m[0], "broadcast matrix");
                same_v(&lane_v3(&prod, l), &(m[l] * a[l]), "m v");
                same_v(&lane_v3(&prod, l), &mat3_vec(&m[l], &a[l]), "mat3_vec");
                same_v(&lane_v3(&tprod, l), &m[l].tr_mul(&a[l]), "mᵀ v");
                same_v(&lane_v3(&tprod, l), &(m[l].transpose() * a[l]), "transpose() * v");
                same_m(&lane_m3(&sq, l), &(m[l] * n[l]), "m n");
                same_m(&lane_m3(&sq, l), &mat3_mul(&m[l], &n[l]), "mat3_mul");
                same_m(&lane_m3(&tsq, l), &mat3_tr_mul(&m[l], &n[l]), "mat3_tr_mul");
                same_v(&lane_v3(&cr, l), &a[l].cross(&b[l]), "cross");
                assert_eq!(d.0[l].to_bits(), a[l].dot(&b[l]).to_bits());
                assert_eq!(dot(&la, &la).0[l].to_bits(), a[l].norm_squared().to_bits());
                assert_eq!(big.0[l].to_bits(), scalar_largest_abs(&a[l]).to_bits());
                assert_eq!(bigm.0[l].to_bits(), scalar_largest_abs(&m[l]).to_bits());
                assert_eq!(
                    rows.0[l].to_bits(),
                    scalar_largest_abs(&m[l].abs().column_sum()).to_bits()
                );
                assert!(regular[l]);
                same_m(&lane_m3(&inv, l), &m[l].try_inverse().expect("regular"), "inverse");
            }
        }
        let zero = Matrix3::zeros();
        let (_, regular) = inverse(&gather_m3::<L>(false, |_| &zero));
        assert_eq!(regular, [false; L]);
    }

    /// exp, dexp⁻¹, log and the renormalisation have `so3`'s and the
    /// fibre's bits in every lane on their series branches, over angles
    /// from 0 to the branch points; a group with a lane beyond them is
    /// refused.
    #[test]
    fn so3_maps_have_the_scalar_bits() {
        let mut next = random(0x2b99_2ddf_a232_49d6);
        for size in [0.0, 1e-9, 1e-5, 1e-3, 0.03, 0.09, 0.3] {
            for _ in 0..50 {
                let w = vectors(&mut next, size);
                let lw = gather_v3::<L>(false, |l| w[l]);
                let e = exp(&lw).expect("|ω|² < 1");
                let d = dexp_inv(&lw).expect("|ω|² < 4");
                let rotations: [SO3<f64>; L] = std::array::from_fn(|l| so3::exp(&w[l]));
                let drifted: [Matrix3<f64>; L] = std::array::from_fn(|l| rotations[l].matrix() * (1.0 + 1e-9 * next()));
                let renormalized = renormalize(&gather_m3::<L>(false, |l| &drifted[l]));
                for l in 0..L {
                    same_m(&lane_m3(&e, l), rotations[l].matrix(), "exp");
                    same_m(&lane_m3(&d, l), &so3::dexp_inv(&w[l]), "dexp_inv");
                    let fibre = Rotations::renormalize(&SO3::from_matrix_unchecked(drifted[l]));
                    same_m(&lane_m3(&renormalized, l), fibre.matrix(), "renormalize");
                }
                // Angles with tan θ ≤ 0.1 take the series branch of log.
                if size <= 0.03 {
                    let logs = log(&gather_m3::<L>(false, |l| rotations[l].matrix())).expect("small angles");
                    for l in 0..L {
                        let scalar = so3::log(&rotations[l]).expect("small angle");
                        same_v(&lane_v3(&logs, l), &scalar, "log");
                    }
                }
            }
        }
        let big = [
            Vector3::new(1.2, 0.0, 0.0),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
        ];
        let lb = gather_v3::<L>(false, |l| big[l]);
        assert!(exp(&lb).is_none());
        let turned: [SO3<f64>; L] = std::array::from_fn(|l| so3::exp(&big[l]));
        assert!(log(&gather_m3::<L>(false, |l| turned[l].matrix())).is_none());
    }
}
