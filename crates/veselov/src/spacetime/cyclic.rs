//! Cyclic constant-coefficient tridiagonal solves `−c x_{i−1} + x_i − c x_{i+1} = r_i`
//! (indices mod `N`), prefactored once: Thomas algorithm on the
//! Sherman–Morrison-modified matrix (Numerical Recipes §2.7, `γ = −1`).
//! O(N) per solve, no allocation after construction.

use crate::error::Result;
use crate::error::invalid;

/// A prefactored cyclic system with off-diagonal `−c`, `|c| < ½` (strict
/// diagonal dominance, so Thomas needs no pivoting).
#[derive(Debug, Clone)]
pub struct CyclicTridiagonal {
    c: f64,
    /// Modified super-diagonal of the Thomas forward sweep.
    cp: Vec<f64>,
    /// Reciprocal pivots.
    inv: Vec<f64>,
    /// Solution of `T z = u` (Sherman–Morrison vector).
    z: Vec<f64>,
    /// `1 / (1 + z₀ + β z_{N−1}/γ)`.
    sm: f64,
    /// `‖A⁻¹M‖∞`, `M = (I + S⁻¹)/2` the two-point average `(x_i + x_{i−1})/2`.
    inv_avg_norm: f64,
}

impl CyclicTridiagonal {
    /// Prefactor for `n ≥ 3` unknowns.
    ///
    /// # Errors
    /// `c` not finite or `|c| ≥ ½` (`name` names the parameter).
    pub fn new(n: usize, c: f64) -> Result<Self> {
        if n < 3 {
            return Err(invalid("nodes", n, "a cyclic system needs at least 3 unknowns"));
        }
        if !(c.is_finite() && c.abs() < 0.5) {
            return Err(invalid("off-diagonal", c, "|c| < 1/2 required (diagonal dominance)"));
        }
        let (a, gamma) = (-c, -1.0);
        let (alpha, beta) = (a, a); // corner entries A[N−1][0], A[0][N−1]
        let mut diag = vec![1.0; n];
        diag[0] = 1.0 - gamma;
        diag[n - 1] = 1.0 - alpha * beta / gamma;
        let mut cp = vec![0.0; n];
        let mut inv = vec![0.0; n];
        inv[0] = 1.0 / diag[0];
        cp[0] = a * inv[0];
        for i in 1..n {
            inv[i] = 1.0 / (diag[i] - a * cp[i - 1]);
            cp[i] = a * inv[i];
        }
        let mut s = Self {
            c,
            cp,
            inv,
            z: vec![0.0; n],
            sm: 0.0,
            inv_avg_norm: 0.0,
        };
        let mut u = vec![0.0; n];
        u[0] = gamma;
        u[n - 1] = alpha;
        let mut z = vec![0.0; n];
        s.thomas(&u, &mut z);
        s.sm = 1.0 / (1.0 + z[0] + beta * z[n - 1] / gamma);
        s.z = z;
        // A⁻¹ and M are circulant, so ‖A⁻¹M‖∞ is the absolute sum of the
        // first column of A⁻¹M: g_i = ½(a_i + a_{i−1}), a = A⁻¹e₀.
        let mut a = vec![0.0; n];
        a[0] = 1.0;
        s.solve_in_place(&mut a);
        s.inv_avg_norm = (0..n).map(|i| 0.5 * (a[i] + a[(i + n - 1) % n]).abs()).sum();
        Ok(s)
    }

    /// `‖A⁻¹M‖∞` with `M x_i = (x_i + x_{i−1})/2`: the gain of a solve
    /// applied to a two-point average (much smaller than `‖A⁻¹‖∞ = 1/(1 − 2|c|)`
    /// for `c < 0`, whose worst mode `(−1)^i` the average annihilates).
    pub fn inverse_average_norm(&self) -> f64 {
        self.inv_avg_norm
    }

    /// Off-diagonal coefficient `c`.
    pub fn c(&self) -> f64 {
        self.c
    }

    fn thomas(&self, r: &[f64], x: &mut [f64]) {
        let n = r.len();
        let a = -self.c;
        x[0] = r[0] * self.inv[0];
        for i in 1..n {
            x[i] = (r[i] - a * x[i - 1]) * self.inv[i];
        }
        for i in (0..n - 1).rev() {
            x[i] -= self.cp[i] * x[i + 1];
        }
    }

    /// Solve in place: `x` holds `r` on entry and the solution on exit.
    pub fn solve_in_place(&self, x: &mut [f64]) {
        let n = x.len();
        let a = -self.c;
        x[0] *= self.inv[0];
        for i in 1..n {
            x[i] = (x[i] - a * x[i - 1]) * self.inv[i];
        }
        for i in (0..n - 1).rev() {
            x[i] -= self.cp[i] * x[i + 1];
        }
        // Sherman–Morrison: x −= z (x₀ + β x_{N−1}/γ)/(1 + z₀ + β z_{N−1}/γ), β/γ = −a.
        let f = (x[0] - a * x[n - 1]) * self.sm;
        for (xi, zi) in x.iter_mut().zip(&self.z) {
            *xi -= f * zi;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_cyclic_systems() {
        for &(n, c) in &[(3, 0.2), (7, -0.49), (255, -0.4846), (256, 0.33)] {
            let t = CyclicTridiagonal::new(n, c).expect("valid");
            let r: Vec<f64> = (0..n).map(|i| ((i * 37 % 11) as f64 - 5.0) / 3.0).collect();
            let mut x = r.clone();
            t.solve_in_place(&mut x);
            for i in 0..n {
                let ax = x[i] - c * (x[(i + n - 1) % n] + x[(i + 1) % n]);
                // condition number ≤ (1 + 2|c|)/(1 − 2|c|) ≈ 64
                assert!(
                    (ax - r[i]).abs() <= 1e-13,
                    "n = {n}, c = {c}, row {i}: {ax} vs {}",
                    r[i]
                );
            }
        }
        assert!(CyclicTridiagonal::new(10, 0.5).is_err());
        assert!(CyclicTridiagonal::new(2, 0.1).is_err());
    }
}
