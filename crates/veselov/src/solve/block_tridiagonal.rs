//! Block-tridiagonal systems, optionally cyclic (periodic corner blocks), with
//! B×B blocks: the level Jacobians of 1+1 lattice schemes, whose new-level
//! unknowns couple only to their two neighbours.
//!
//! Non-cyclic systems are solved by block Gaussian elimination without
//! pivoting between blocks (the block Thomas algorithm; stable for block
//! diagonally dominant matrices, which the level Jacobians of the lattice
//! schemes are for admissible steps). Cyclic systems use the Woodbury
//! identity: with Γ = −D₀, A = A′ + U Vᵀ where U = (Γ, 0, …, 0, C_bot)ᵀ,
//! Vᵀ = (I, 0, …, 0, Γ⁻¹C_top), and A′ is block tridiagonal with
//! D′₀ = D₀ − Γ, D′_{n−1} = D_{n−1} − C_bot Γ⁻¹ C_top; then
//! x = y − Z (I + VᵀZ)⁻¹ Vᵀy with A′y = r, A′Z = U. Cost O(n B³) to factor
//! and O(n B²) per solve.

use nalgebra::{SMatrix, SVector};

/// A block-tridiagonal matrix with n block rows; `lower[i]` is block
/// (i, i−1) (`lower[0]` unused), `upper[i]` is block (i, i+1)
/// (`upper[n−1]` unused); the corners are blocks (0, n−1) and (n−1, 0) of a
/// cyclic matrix.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockTridiagonal<const B: usize> {
    /// Sub-diagonal blocks.
    pub lower: Vec<SMatrix<f64, B, B>>,
    /// Diagonal blocks.
    pub diag: Vec<SMatrix<f64, B, B>>,
    /// Super-diagonal blocks.
    pub upper: Vec<SMatrix<f64, B, B>>,
    /// Block (0, n−1) (cyclic only).
    pub corner_top: SMatrix<f64, B, B>,
    /// Block (n−1, 0) (cyclic only).
    pub corner_bottom: SMatrix<f64, B, B>,
    /// Whether the corner blocks are part of the matrix.
    pub cyclic: bool,
}

impl<const B: usize> BlockTridiagonal<B> {
    /// The zero matrix with `n` block rows.
    pub fn zeros(n: usize, cyclic: bool) -> Self {
        Self {
            lower: vec![SMatrix::zeros(); n],
            diag: vec![SMatrix::zeros(); n],
            upper: vec![SMatrix::zeros(); n],
            corner_top: SMatrix::zeros(),
            corner_bottom: SMatrix::zeros(),
            cyclic,
        }
    }

    /// Number of block rows.
    pub fn blocks(&self) -> usize {
        self.diag.len()
    }

    /// Set every block to zero (keeping the sizes).
    pub fn clear(&mut self) {
        for m in self
            .lower
            .iter_mut()
            .chain(self.diag.iter_mut())
            .chain(self.upper.iter_mut())
        {
            *m = SMatrix::zeros();
        }
        self.corner_top = SMatrix::zeros();
        self.corner_bottom = SMatrix::zeros();
    }

    /// The block at (row, col) where it can be stored: the diagonal, the two
    /// neighbours, and (cyclic, n ≥ 3) the corners. `None` for any other
    /// position.
    pub fn block_mut(&mut self, row: usize, col: usize) -> Option<&mut SMatrix<f64, B, B>> {
        let n = self.blocks();
        if row == col {
            Some(&mut self.diag[row])
        } else if col + 1 == row {
            Some(&mut self.lower[row])
        } else if row + 1 == col {
            Some(&mut self.upper[row])
        } else if self.cyclic && n >= 3 && row == 0 && col == n - 1 {
            Some(&mut self.corner_top)
        } else if self.cyclic && n >= 3 && row == n - 1 && col == 0 {
            Some(&mut self.corner_bottom)
        } else {
            None
        }
    }

    /// The product A x.
    pub fn mul(&self, x: &[SVector<f64, B>]) -> Vec<SVector<f64, B>> {
        let n = self.blocks();
        let mut y: Vec<SVector<f64, B>> = (0..n).map(|i| self.diag[i] * x[i]).collect();
        for i in 0..n {
            if i > 0 {
                y[i] += self.lower[i] * x[i - 1];
            }
            if i + 1 < n {
                y[i] += self.upper[i] * x[i + 1];
            }
        }
        if self.cyclic && n >= 3 {
            y[0] += self.corner_top * x[n - 1];
            y[n - 1] += self.corner_bottom * x[0];
        }
        y
    }

    /// Factor for repeated solves; `None` if a pivot block is singular.
    pub fn factor(&self) -> Option<BlockTridiagonalLu<B>> {
        let mut lu = BlockTridiagonalLu::new(self.blocks(), self.cyclic);
        self.factor_into(&mut lu).then_some(lu)
    }

    /// Factor into `lu` (made by [`BlockTridiagonalLu::new`] for this size),
    /// without allocating; `false` if a pivot block is singular or the sizes
    /// differ.
    pub fn factor_into(&self, lu: &mut BlockTridiagonalLu<B>) -> bool {
        let n = self.blocks();
        if n == 0 || lu.m_inv.len() != n {
            return false;
        }
        let cyclic = self.cyclic && n >= 3;
        lu.diag.copy_from_slice(&self.diag);
        lu.lower.copy_from_slice(&self.lower);
        let mut woodbury = None;
        if cyclic {
            let gamma = -self.diag[0];
            let Some(gamma_inv) = gamma.try_inverse() else {
                return false;
            };
            let vt_last = gamma_inv * self.corner_top;
            lu.diag[0] -= gamma;
            lu.diag[n - 1] -= self.corner_bottom * vt_last;
            woodbury = Some((gamma, vt_last));
        }
        // Block Thomas: M_i = D_i − L_i C′_{i−1}, C′_i = M_i⁻¹ U_i.
        for i in 0..n {
            let m = if i == 0 {
                lu.diag[0]
            } else {
                lu.diag[i] - self.lower[i] * lu.c_prime[i - 1]
            };
            let Some(inv) = m.try_inverse() else {
                return false;
            };
            lu.c_prime[i] = if i + 1 < n {
                inv * self.upper[i]
            } else {
                SMatrix::zeros()
            };
            lu.m_inv[i] = inv;
        }
        lu.woodbury = None;
        if let Some((gamma, vt_last)) = woodbury {
            // Z = A′⁻¹U, one column of blocks per column of U; then the
            // capacitance matrix I + VᵀZ.
            let mut w = std::mem::take(&mut lu.scratch);
            for col in 0..B {
                w.u.iter_mut().for_each(|v| *v = SVector::zeros());
                w.u[0] = gamma.column(col).into_owned();
                w.u[n - 1] = self.corner_bottom.column(col).into_owned();
                lu.solve_plain(&w.u, &mut w.column);
                for (zi, zci) in w.z.iter_mut().zip(&w.column) {
                    zi.set_column(col, zci);
                }
            }
            let capacitance = SMatrix::<f64, B, B>::identity() + w.z[0] + vt_last * w.z[n - 1];
            let inverse = capacitance.try_inverse();
            lu.scratch = w;
            let Some(capacitance_inv) = inverse else {
                return false;
            };
            lu.woodbury = Some((vt_last, capacitance_inv));
        }
        true
    }
}

/// Work space of the cyclic (Woodbury) factorisation.
#[derive(Debug, Clone, PartialEq, Default)]
struct WoodburyScratch<const B: usize> {
    /// Z = A′⁻¹U.
    z: Vec<SMatrix<f64, B, B>>,
    u: Vec<SVector<f64, B>>,
    column: Vec<SVector<f64, B>>,
}

/// A factored [`BlockTridiagonal`].
#[derive(Debug, Clone, PartialEq)]
pub struct BlockTridiagonalLu<const B: usize> {
    lower: Vec<SMatrix<f64, B, B>>,
    diag: Vec<SMatrix<f64, B, B>>,
    m_inv: Vec<SMatrix<f64, B, B>>,
    c_prime: Vec<SMatrix<f64, B, B>>,
    /// (Γ⁻¹C_top, (I + VᵀZ)⁻¹) of a cyclic matrix.
    woodbury: Option<(SMatrix<f64, B, B>, SMatrix<f64, B, B>)>,
    scratch: WoodburyScratch<B>,
}

impl<const B: usize> BlockTridiagonalLu<B> {
    /// Storage for the factors of an `n`-block matrix (cyclic or not), to be
    /// filled by [`BlockTridiagonal::factor_into`].
    pub fn new(n: usize, cyclic: bool) -> Self {
        let zero = vec![SMatrix::zeros(); n];
        let scratch = if cyclic {
            WoodburyScratch {
                z: zero.clone(),
                u: vec![SVector::zeros(); n],
                column: vec![SVector::zeros(); n],
            }
        } else {
            WoodburyScratch::default()
        };
        Self {
            lower: zero.clone(),
            diag: zero.clone(),
            m_inv: zero.clone(),
            c_prime: zero,
            woodbury: None,
            scratch,
        }
    }

    fn solve_plain(&self, r: &[SVector<f64, B>], d: &mut [SVector<f64, B>]) {
        let n = self.m_inv.len();
        for i in 0..n {
            let rhs = if i == 0 { r[0] } else { r[i] - self.lower[i] * d[i - 1] };
            d[i] = self.m_inv[i] * rhs;
        }
        for i in (0..n.saturating_sub(1)).rev() {
            let next = d[i + 1];
            d[i] -= self.c_prime[i] * next;
        }
    }

    /// Solve A x = r.
    pub fn solve(&self, r: &[SVector<f64, B>]) -> Vec<SVector<f64, B>> {
        let mut x = vec![SVector::zeros(); self.m_inv.len()];
        self.solve_into(r, &mut x);
        x
    }

    /// Solve A x = r into `x` (as long as `r`), without allocating.
    pub fn solve_into(&self, r: &[SVector<f64, B>], x: &mut [SVector<f64, B>]) {
        self.solve_plain(r, x);
        if let Some((vt_last, capacitance_inv)) = &self.woodbury {
            let n = x.len();
            let vty = x[0] + vt_last * x[n - 1];
            let coef = capacitance_inv * vty;
            for (xi, zi) in x.iter_mut().zip(&self.scratch.z) {
                *xi -= zi * coef;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    fn random_system<const B: usize>(n: usize, cyclic: bool, seed: u64) -> BlockTridiagonal<B> {
        let mut state = seed;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        let mut a = BlockTridiagonal::<B>::zeros(n, cyclic);
        for i in 0..n {
            a.lower[i] = SMatrix::from_fn(|_, _| rnd());
            a.upper[i] = SMatrix::from_fn(|_, _| rnd());
            a.diag[i] = SMatrix::from_fn(|_, _| rnd()) + SMatrix::identity() * (3.0 * B as f64);
        }
        a.corner_top = SMatrix::from_fn(|_, _| rnd());
        a.corner_bottom = SMatrix::from_fn(|_, _| rnd());
        a
    }

    fn dense<const B: usize>(a: &BlockTridiagonal<B>) -> DMatrix<f64> {
        let n = a.blocks();
        let mut d = DMatrix::zeros(n * B, n * B);
        for i in 0..n {
            let mut e = vec![SVector::<f64, B>::zeros(); n];
            for c in 0..B {
                e.iter_mut().for_each(|v| *v = SVector::zeros());
                e[i][c] = 1.0;
                let col = a.mul(&e);
                for (r, v) in col.iter().enumerate() {
                    for k in 0..B {
                        d[(r * B + k, i * B + c)] = v[k];
                    }
                }
            }
        }
        d
    }

    fn check<const B: usize>(n: usize, cyclic: bool) {
        let a = random_system::<B>(n, cyclic, 7 + n as u64);
        let r: Vec<SVector<f64, B>> = (0..n)
            .map(|i| SVector::from_fn(|k, _| (i * B + k) as f64 * 0.1 - 1.0))
            .collect();
        let x = a.factor().expect("nonsingular").solve(&r);
        let back = a.mul(&x);
        let err = back.iter().zip(&r).map(|(a, b)| (a - b).amax()).fold(0.0, f64::max);
        assert!(err <= 1e-13, "n = {n}, cyclic = {cyclic}: residual {err:e}");
        // Against a dense LU of the same matrix.
        let flat = nalgebra::DVector::from_iterator(n * B, r.iter().flat_map(|v| v.iter().copied()));
        let xd = dense(&a).lu().solve(&flat).expect("dense solve");
        let diff = x
            .iter()
            .flat_map(|v| v.iter().copied())
            .zip(xd.iter())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(
            diff <= 1e-12,
            "n = {n}, cyclic = {cyclic}: differs from dense LU by {diff:e}"
        );
    }

    #[test]
    fn solves_cyclic_and_plain_systems() {
        for n in [1usize, 2, 3, 4, 17, 64] {
            check::<1>(n, false);
            check::<2>(n, false);
            check::<3>(n, false);
            if n >= 3 {
                check::<1>(n, true);
                check::<2>(n, true);
                check::<3>(n, true);
            }
        }
    }

    #[test]
    fn block_positions() {
        let mut a = BlockTridiagonal::<2>::zeros(5, true);
        assert!(a.block_mut(0, 4).is_some());
        assert!(a.block_mut(4, 0).is_some());
        assert!(a.block_mut(0, 2).is_none());
        let mut b = BlockTridiagonal::<2>::zeros(5, false);
        assert!(b.block_mut(0, 4).is_none());
    }
}
