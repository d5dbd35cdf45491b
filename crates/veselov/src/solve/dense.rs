//! In-place LU factorisation with partial pivoting on preallocated storage.
//!
//! `nalgebra`'s and `faer`'s dense LU either consume and reallocate the matrix
//! or need a scratch-memory protocol; the Newton steps of the integrators solve
//! many small (n·s ≲ 60) systems per second and must not allocate, so this
//! module factors a row-major slice in place. It is the textbook Doolittle
//! algorithm with row pivoting (Golub & Van Loan, Alg. 3.4.1).

use crate::error::{Error, Result};

/// Factor the `n × n` row-major matrix `a` in place as `P A = L U`, with the
/// unit lower factor below the diagonal and `U` on and above it. `perm[i]` is
/// the original row now at position `i`. Returns the smallest pivot magnitude
/// relative to the largest, or an error if a pivot is exactly zero or not finite.
pub fn lu_factor_in_place(a: &mut [f64], n: usize, perm: &mut [usize], context: &str) -> Result<f64> {
    debug_assert_eq!(a.len(), n * n);
    debug_assert_eq!(perm.len(), n);
    for (i, p) in perm.iter_mut().enumerate() {
        *p = i;
    }
    let mut min_pivot = f64::INFINITY;
    let mut max_pivot = 0.0_f64;
    for k in 0..n {
        let mut piv = k;
        let mut best = a[k * n + k].abs();
        for r in (k + 1)..n {
            let v = a[r * n + k].abs();
            if v > best {
                best = v;
                piv = r;
            }
        }
        if best == 0.0 || !best.is_finite() {
            return Err(Error::SingularJacobian {
                context: context.to_string(),
                pivot: best,
            });
        }
        min_pivot = min_pivot.min(best);
        max_pivot = max_pivot.max(best);
        if piv != k {
            for c in 0..n {
                a.swap(k * n + c, piv * n + c);
            }
            perm.swap(k, piv);
        }
        let inv = 1.0 / a[k * n + k];
        for r in (k + 1)..n {
            let f = a[r * n + k] * inv;
            a[r * n + k] = f;
            if f != 0.0 {
                for c in (k + 1)..n {
                    a[r * n + c] -= f * a[k * n + c];
                }
            }
        }
    }
    Ok(if max_pivot > 0.0 { min_pivot / max_pivot } else { 0.0 })
}

/// Solve `A x = b` in place (`b` becomes `x`) with the factors from
/// [`lu_factor_in_place`]. `work` must have length `n`.
pub fn lu_solve_in_place(lu: &[f64], n: usize, perm: &[usize], b: &mut [f64], work: &mut [f64]) {
    substitute(lu, n, perm, b, work, |i, s| s / lu[i * n + i]);
}

/// Forward and back substitution with the factors of [`lu_factor_in_place`];
/// `divide(i, s)` divides `s` by the pivot `U_ii`.
#[inline]
fn substitute(
    lu: &[f64],
    n: usize,
    perm: &[usize],
    b: &mut [f64],
    work: &mut [f64],
    divide: impl Fn(usize, f64) -> f64,
) {
    let (lu, work) = (&lu[..n * n], &mut work[..n]);
    for (w, &p) in work.iter_mut().zip(perm) {
        *w = b[p];
    }
    for (i, row) in lu.chunks_exact(n).enumerate() {
        let s = row[..i].iter().zip(&work[..i]).fold(work[i], |s, (l, w)| s - l * w);
        work[i] = s;
    }
    for (i, row) in lu.chunks_exact(n).enumerate().rev() {
        let s = row[i + 1..]
            .iter()
            .zip(&work[i + 1..])
            .fold(work[i], |s, (u, w)| s - u * w);
        work[i] = divide(i, s);
    }
    b[..n].copy_from_slice(work);
}

/// Preallocated storage for repeated factor/solve of `n × n` systems.
#[derive(Debug, Clone)]
pub struct DenseLu {
    n: usize,
    /// Row-major matrix; fill it, then call [`DenseLu::factor`].
    pub matrix: Vec<f64>,
    perm: Vec<usize>,
    work: Vec<f64>,
    /// `1/U_ii`: the back substitution multiplies (a division's latency
    /// would chain through every row of a small system).
    inverse_pivots: Vec<f64>,
}

impl DenseLu {
    /// Storage for `n × n` systems.
    pub fn new(n: usize) -> Self {
        Self {
            n,
            matrix: vec![0.0; n * n],
            perm: vec![0; n],
            work: vec![0.0; n],
            inverse_pivots: vec![0.0; n],
        }
    }

    /// Dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Factor the matrix currently stored; returns the relative smallest pivot.
    pub fn factor(&mut self, context: &str) -> Result<f64> {
        let pivot = lu_factor_in_place(&mut self.matrix, self.n, &mut self.perm, context)?;
        self.invert_pivots();
        Ok(pivot)
    }

    fn invert_pivots(&mut self) {
        for (i, inv) in self.inverse_pivots.iter_mut().enumerate() {
            *inv = 1.0 / self.matrix[i * self.n + i];
        }
    }

    /// Solve in place with the factors computed by [`DenseLu::factor`].
    pub fn solve(&mut self, b: &mut [f64]) {
        let inverse = &self.inverse_pivots;
        substitute(&self.matrix, self.n, &self.perm, b, &mut self.work, |i, s| {
            s * inverse[i]
        });
    }

    /// Append the factors (the matrix, then the row permutation) as checkpoint words.
    pub fn save_factors(&self, out: &mut Vec<f64>) {
        out.extend_from_slice(&self.matrix);
        out.extend(self.perm.iter().map(|&p| p as f64));
    }

    /// Restore what [`DenseLu::save_factors`] wrote.
    ///
    /// # Errors
    /// If the words run out or the permutation is not one of `0..n`.
    pub fn restore_factors(&mut self, words: &mut crate::run::Words<'_>) -> Result<()> {
        self.matrix.copy_from_slice(words.take(self.n * self.n)?);
        let perm = words.take(self.n)?;
        let mut seen = vec![false; self.n];
        for (slot, &p) in self.perm.iter_mut().zip(perm) {
            let valid = p >= 0.0 && p.fract() == 0.0 && (p as usize) < self.n && !seen[p as usize];
            if !valid {
                return Err(Error::InvalidParameter {
                    name: "checkpoint".into(),
                    value: p.to_string(),
                    reason: format!("not a row permutation of 0..{}", self.n),
                });
            }
            seen[p as usize] = true;
            *slot = p as usize;
        }
        self.invert_pivots();
        Ok(())
    }
}

/// max |mᵢⱼ| passing over NaN entries, as nalgebra's `amax`, by a fold of
/// `f64::max` without branches: for the sizes of terms that scale a
/// relative residual in the small solves' hot loops.
#[inline]
pub fn largest_abs<const R: usize, const C: usize>(m: &nalgebra::SMatrix<f64, R, C>) -> f64 {
    m.iter().fold(0.0_f64, |largest, x| largest.max(x.abs()))
}

/// max |vᵢ| of a residual, NaN if any vᵢ is: nalgebra's `amax` passes over
/// a NaN next to a number (f64::max), so a residual with one NaN entry
/// would look finite.
pub fn max_abs<const N: usize>(v: &nalgebra::SVector<f64, N>) -> f64 {
    let mut largest = 0.0_f64;
    let mut nan = false;
    for &x in v.iter() {
        largest = largest.max(x.abs());
        nan |= x.is_nan();
    }
    if nan { f64::NAN } else { largest }
}

/// The LU factors of a small fixed-size matrix (Gaussian elimination with
/// partial pivoting, on the stack): factor once, solve many right-hand sides
/// — a simplified Newton keeps its Jacobian's factors for every iteration
/// that reuses it, and from one solve to the next.
#[derive(Clone, Copy, Debug)]
pub struct SmallLu<const N: usize> {
    /// Rows of U on and above the diagonal, the elimination multipliers
    /// below it (plain arrays: fixed bounds, no checks left in the loops).
    factors: [[f64; N]; N],
    /// The row swapped with row k at step k.
    swaps: [usize; N],
    /// 1/u_kk: the back substitution multiplies (a chain of divisions
    /// would bound its speed).
    inverse_pivots: [f64; N],
    /// The largest entry of the factored matrix in absolute value.
    largest: f64,
    /// A⁻¹ from the factors, once [`keep_inverse`](Self::keep_inverse) asked
    /// for it: a solve is then one product (independent multiply-adds,
    /// where the substitutions are a chain of dependent ones).
    inverse: Option<nalgebra::SMatrix<f64, N, N>>,
}

impl<const N: usize> SmallLu<N> {
    /// Room for factors (of the zero matrix: [`refactor`](Self::refactor)
    /// fills it).
    pub fn zeros() -> Self {
        Self {
            factors: [[0.0; N]; N],
            swaps: [0; N],
            inverse_pivots: [0.0; N],
            largest: 0.0,
            inverse: None,
        }
    }

    /// The factors of `a` and its smallest pivot relative to the largest
    /// (0 when a pivot vanishes or a factor is not finite: then `None`).
    pub fn factor(a: &nalgebra::SMatrix<f64, N, N>) -> (Option<Self>, f64) {
        let mut lu = Self::zeros();
        match lu.refactor(a) {
            Some(ratio) => (Some(lu), ratio),
            None => (None, 0.0),
        }
    }

    /// Factors `a` in place of the factors held (no copy of the factors
    /// moves through the stack); its smallest pivot relative to the
    /// largest, or `None` when a pivot vanishes or a factor is not finite (the
    /// factors held are then meaningless).
    pub fn refactor(&mut self, a: &nalgebra::SMatrix<f64, N, N>) -> Option<f64> {
        self.inverse = None;
        let f = &mut self.factors;
        let mut largest = 0.0_f64;
        for (r, row) in f.iter_mut().enumerate() {
            for (c, x) in row.iter_mut().enumerate() {
                *x = a[(r, c)];
                largest = largest.max(x.abs());
            }
        }
        self.largest = largest;
        let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
        for k in 0..N {
            let mut piv = k;
            for r in (k + 1)..N {
                if f[r][k].abs() > f[piv][k].abs() {
                    piv = r;
                }
            }
            let p = f[piv][k].abs();
            if p == 0.0 || !p.is_finite() {
                return None;
            }
            lo = lo.min(p);
            hi = hi.max(p);
            self.swaps[k] = piv;
            if piv != k {
                for c in 0..N {
                    let t = f[k][c];
                    f[k][c] = f[piv][c];
                    f[piv][c] = t;
                }
            }
            for r in (k + 1)..N {
                let m = f[r][k] / f[k][k];
                f[r][k] = m;
                if m != 0.0 {
                    for c in (k + 1)..N {
                        f[r][c] -= m * f[k][c];
                    }
                }
            }
            self.inverse_pivots[k] = 1.0 / f[k][k];
        }
        // A non-finite entry that never reached a pivot (its multipliers
        // were zero) would spoil every solve: such factors are none.
        if !self.is_finite() {
            return None;
        }
        Some(if hi > 0.0 { lo / hi } else { 0.0 })
    }

    /// The largest entry of the factored matrix in absolute value.
    pub fn largest(&self) -> f64 {
        self.largest
    }

    /// Append the factors (the rows, the row swaps, the largest entry) as
    /// checkpoint words.
    pub fn save_factors(&self, out: &mut Vec<f64>) {
        out.extend(self.factors.iter().flatten());
        out.extend(self.swaps.iter().map(|&p| p as f64));
        out.push(self.largest);
    }

    /// Restore what [`SmallLu::save_factors`] wrote.
    ///
    /// # Errors
    /// If the words run out or a row swap is not one of the rows below.
    pub fn restore_factors(words: &mut crate::run::Words<'_>) -> Result<Self> {
        let mut lu = Self::zeros();
        for row in &mut lu.factors {
            words.fill(row)?;
        }
        for (k, inverse) in lu.inverse_pivots.iter_mut().enumerate() {
            *inverse = 1.0 / lu.factors[k][k];
        }
        for (k, swap) in lu.swaps.iter_mut().enumerate() {
            let p = words.one()?;
            if !(p >= k as f64 && p < N as f64 && p.fract() == 0.0) {
                return Err(Error::InvalidParameter {
                    name: "checkpoint".into(),
                    value: p.to_string(),
                    reason: format!("not a row swap of row {k} of {N}"),
                });
            }
            *swap = p as usize;
        }
        lu.largest = words.one()?;
        if !lu.is_finite() || !lu.largest.is_finite() {
            return Err(Error::InvalidParameter {
                name: "checkpoint".into(),
                value: "LU factors".into(),
                reason: "a factor is not finite".into(),
            });
        }
        Ok(lu)
    }

    /// Append kept factors, or their absence, as checkpoint words: tag 2
    /// and [`save_factors`](Self::save_factors), or tag 3.
    pub fn save_kept(kept: &Option<Self>, out: &mut Vec<f64>) {
        match kept {
            Some(lu) => {
                out.push(2.0);
                lu.save_factors(out);
            }
            None => out.push(3.0),
        }
    }

    /// Restore what [`SmallLu::save_kept`] wrote.
    ///
    /// # Errors
    /// If the words run out, the tag is neither 2 nor 3, or the factors do
    /// not restore ([`restore_factors`](Self::restore_factors)).
    pub fn restore_kept(words: &mut crate::run::Words<'_>) -> Result<Option<Self>> {
        match words.one()? {
            2.0 => Ok(Some(Self::restore_factors(words)?)),
            3.0 => Ok(None),
            tag => Err(Error::InvalidParameter {
                name: "checkpoint".into(),
                value: tag.to_string(),
                reason: "not a kept-Jacobian tag".into(),
            }),
        }
    }

    /// Whether every factor is finite.
    pub fn is_finite(&self) -> bool {
        self.factors.iter().flatten().all(|x| x.is_finite())
    }

    /// Computes A⁻¹ from the factors (N substitutions) unless it is held:
    /// for factors that will solve many right-hand sides (a simplified
    /// Newton's kept Jacobian), each [`solve`](Self::solve) is then the
    /// product A⁻¹b. The inverse is a function of the factors alone, so a
    /// run restored from [`save_factors`](Self::save_factors) computes the
    /// same one. Its solutions differ from the substitutions' by rounding
    /// of order κ(A)·ε·|x|, as theirs differ from the exact x.
    pub fn keep_inverse(&mut self) {
        if self.inverse.is_none() {
            let mut inverse = nalgebra::SMatrix::<f64, N, N>::zeros();
            for j in 0..N {
                let mut unit = nalgebra::SVector::<f64, N>::zeros();
                unit[j] = 1.0;
                let column = self.substitute(&unit);
                inverse.set_column(j, &column);
            }
            self.inverse = Some(inverse);
        }
    }

    /// A⁻¹ if [`keep_inverse`](Self::keep_inverse) has computed it.
    pub fn inverse(&self) -> Option<nalgebra::SMatrix<f64, N, N>> {
        self.inverse
    }

    /// x with A x = b: A⁻¹b when [`keep_inverse`](Self::keep_inverse) holds
    /// it, else the forward and back substitutions.
    pub fn solve(&self, b: &nalgebra::SVector<f64, N>) -> nalgebra::SVector<f64, N> {
        match &self.inverse {
            Some(inverse) => inverse * b,
            None => self.substitute(b),
        }
    }

    /// x with A x = b by the forward and back substitutions.
    fn substitute(&self, b: &nalgebra::SVector<f64, N>) -> nalgebra::SVector<f64, N> {
        let f = &self.factors;
        // Worked on in the vector returned (no copy of an array into it at
        // the end, whose wide loads would wait on the narrow stores).
        let mut x = *b;
        // The rows in their final order (the multipliers moved with them).
        for (k, &p) in self.swaps.iter().enumerate() {
            x.swap_rows(k, p);
        }
        for k in 0..N {
            let xk = x[k];
            for r in (k + 1)..N {
                x[r] -= f[r][k] * xk;
            }
        }
        for i in (0..N).rev() {
            let mut s = x[i];
            for j in (i + 1)..N {
                s -= f[i][j] * x[j];
            }
            x[i] = s * self.inverse_pivots[i];
        }
        x
    }
}

/// Solve the small fixed-size system `A x = b` ([`SmallLu`]). Returns `x`
/// and the smallest pivot relative to the largest (0 when a pivot vanishes,
/// then `x` is meaningless).
pub fn solve_small<const N: usize>(
    a: &nalgebra::SMatrix<f64, N, N>,
    b: &nalgebra::SVector<f64, N>,
) -> (nalgebra::SVector<f64, N>, f64) {
    match SmallLu::factor(a) {
        (Some(lu), ratio) => (lu.solve(b), ratio),
        (None, _) => (*b, 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::uniform;

    /// Elimination with the right-hand side carried along, dividing by each
    /// pivot (the form [`SmallLu`] replaced; it multiplies by the reciprocal).
    fn eliminate_with_rhs<const N: usize>(
        a: &nalgebra::SMatrix<f64, N, N>,
        b: &nalgebra::SVector<f64, N>,
    ) -> nalgebra::SVector<f64, N> {
        let (mut a, mut x) = (*a, *b);
        for k in 0..N {
            let mut piv = k;
            for r in (k + 1)..N {
                if a[(r, k)].abs() > a[(piv, k)].abs() {
                    piv = r;
                }
            }
            a.swap_rows(k, piv);
            x.swap_rows(k, piv);
            for r in (k + 1)..N {
                let f = a[(r, k)] / a[(k, k)];
                for c in k..N {
                    a[(r, c)] -= f * a[(k, c)];
                }
                x[r] -= f * x[k];
            }
        }
        for i in (0..N).rev() {
            let mut s = x[i];
            for j in (i + 1)..N {
                s -= a[(i, j)] * x[j];
            }
            x[i] = s / a[(i, i)];
        }
        x
    }

    #[test]
    fn kept_factors_solve_every_right_hand_side() {
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        for _ in 0..50 {
            let a = nalgebra::SMatrix::<f64, 6, 6>::from_fn(|_, _| next());
            let (lu, ratio) = SmallLu::factor(&a);
            let lu = lu.expect("regular");
            assert!(ratio > 0.0);
            for _ in 0..3 {
                let b = nalgebra::SVector::<f64, 6>::from_fn(|_, _| next());
                let x = lu.solve(&b);
                assert_eq!(x, solve_small(&a, &b).0);
                // Elimination with the right-hand side carried along and a
                // division per row: the same solution up to the forward
                // error of two backward-stable solves, ≤ κ∞(A)·O(nε)·|x|.
                let kappa = a.abs().row_sum().amax() * a.try_inverse().expect("regular").abs().row_sum().amax();
                let reference = eliminate_with_rhs(&a, &b);
                assert!((x - reference).amax() <= 64.0 * f64::EPSILON * kappa * reference.amax());
                assert!((a * x - b).amax() < 1e-12 * (1.0 + x.amax()));
            }
        }
        let singular = nalgebra::SMatrix::<f64, 3, 3>::new(1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 1.0, 1.0);
        assert!(SmallLu::factor(&singular).0.is_none());
        assert_eq!(solve_small(&singular, &nalgebra::SVector::<f64, 3>::zeros()).1, 0.0);
    }

    /// With the inverse kept, a solve is A⁻¹b: within the forward error
    /// of a backward-stable solve, 64ε·κ∞(A)·|x|, of the substitutions;
    /// the inverse is a function of the factors alone (restored factors give
    /// the same bits) and a refactor drops it.
    #[test]
    fn kept_inverse_solves_as_the_substitutions_do() {
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        for _ in 0..50 {
            let a = nalgebra::SMatrix::<f64, 6, 6>::from_fn(|_, _| next());
            let mut lu = SmallLu::factor(&a).0.expect("regular");
            let kappa = a.abs().row_sum().amax() * a.try_inverse().expect("regular").abs().row_sum().amax();
            let b = nalgebra::SVector::<f64, 6>::from_fn(|_, _| next());
            let by_substitution = lu.solve(&b);
            let mut words = Vec::new();
            lu.save_factors(&mut words);
            lu.keep_inverse();
            let by_inverse = lu.solve(&b);
            assert!((by_inverse - by_substitution).amax() <= 64.0 * f64::EPSILON * kappa * by_substitution.amax());
            let mut restored = SmallLu::<6>::restore_factors(&mut crate::run::Words::new(&words)).expect("restore");
            restored.keep_inverse();
            assert_eq!(restored.solve(&b), by_inverse);
            // A refactor solves with the new factors.
            let c = a + nalgebra::SMatrix::<f64, 6, 6>::identity();
            lu.refactor(&c).expect("regular");
            assert_eq!(lu.solve(&b), solve_small(&c, &b).0);
        }
    }

    /// Saved factors restore to the same solves bit for bit; a row swap that
    /// is not a row below is a named error.
    #[test]
    fn small_factors_round_trip_through_checkpoint_words() {
        let a = nalgebra::SMatrix::<f64, 3, 3>::new(0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0);
        let lu = SmallLu::factor(&a).0.expect("regular");
        let mut words = Vec::new();
        lu.save_factors(&mut words);
        assert_eq!(words.len(), 9 + 3 + 1);
        let back = SmallLu::<3>::restore_factors(&mut crate::run::Words::new(&words)).expect("restore");
        let b = nalgebra::SVector::<f64, 3>::new(0.3, -1.0, 2.0);
        assert_eq!(back.solve(&b), lu.solve(&b));
        assert_eq!(back.largest(), 3.0);
        words[9] = 0.5;
        let err = SmallLu::<3>::restore_factors(&mut crate::run::Words::new(&words)).expect_err("not a swap");
        assert!(err.to_string().contains("row swap"), "{err}");
        assert!(SmallLu::<3>::restore_factors(&mut crate::run::Words::new(&words[..5])).is_err());
        words[9] = 0.0;
        words[4] = f64::NAN;
        let err = SmallLu::<3>::restore_factors(&mut crate::run::Words::new(&words)).expect_err("not finite");
        assert!(err.to_string().contains("not finite"), "{err}");
        // A non-finite entry no pivot reaches (its multipliers are zero).
        let hidden = nalgebra::SMatrix::<f64, 3, 3>::new(1.0, 0.0, f64::INFINITY, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert!(SmallLu::factor(&hidden).0.is_none());
    }

    #[test]
    fn solves_a_pivoting_system() {
        // Needs a row swap at the first column.
        let mut lu = DenseLu::new(3);
        lu.matrix
            .copy_from_slice(&[0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0]);
        let a = lu.matrix.clone();
        lu.factor("test").expect("regular");
        let x = [1.0, -2.0, 0.5];
        let mut b: Vec<f64> = (0..3).map(|i| (0..3).map(|j| a[i * 3 + j] * x[j]).sum()).collect();
        lu.solve(&mut b);
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-15, "{b:?}");
        }
    }

    #[test]
    fn singular_matrix_is_an_error() {
        let mut lu = DenseLu::new(2);
        lu.matrix.copy_from_slice(&[1.0, 2.0, 2.0, 4.0]);
        assert!(matches!(lu.factor("test"), Err(Error::SingularJacobian { .. })));
    }
}
