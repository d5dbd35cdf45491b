//! Lee's discrete mechanics: the SEM equations as a boundary-value problem
//! (seed 001, end of §3; note 001 §2.5). Endpoints `(t₀, q₀)`, `(t_K, q_K)` and
//! the number of steps `K` are fixed; all interior `x_k = (t_k, q_k)` solve
//!
//! `D_{x₁}S(x_{k−1}, x_k) + D_{x₀}S(x_k, x_{k+1}) = 0`,  `k = 1..K−1`,
//!
//! by Newton's method on the block-tridiagonal system (blocks of size `n + 1`,
//! block Thomas elimination). Newton updates are damped so that every step
//! `t_{k+1} − t_k` stays positive: the solution never folds back in time.

use nalgebra::{DMatrix, DVector, SVector};
use num_dual::HyperDual64;

use super::action::SemAction;
use crate::error::{Error, Result};
use crate::mechanics::Lagrangian;

/// Gradient and Hessian of `S(t₀, q₀, t₁, q₁)` in the `2(n+1)` variables
/// `(t₀, q₀, t₁, q₁)`, by hyper-dual numbers (one pass per pair of variables).
fn full_derivatives<L: Lagrangian<N>, const N: usize>(
    action: &SemAction<L, N>,
    x0: &[f64],
    x1: &[f64],
) -> (DVector<f64>, DMatrix<f64>) {
    let m = 2 * (N + 1);
    let base: Vec<f64> = x0.iter().chain(x1).copied().collect();
    let eval = |i: usize, j: usize| {
        let var = |k: usize| {
            let mut d = HyperDual64::from(base[k]);
            if k == i {
                d.eps1 = 1.0;
            }
            if k == j {
                d.eps2 = 1.0;
            }
            d
        };
        let t0 = var(0);
        let q0 = SVector::<HyperDual64, N>::from_fn(|a, _| var(1 + a));
        let t1 = var(N + 1);
        let q1 = SVector::<HyperDual64, N>::from_fn(|a, _| var(N + 2 + a));
        action.action(t0, &q0, &q1, t1 - t0)
    };
    let mut g = DVector::zeros(m);
    let mut h = DMatrix::zeros(m, m);
    for i in 0..m {
        for j in i..m {
            let r = eval(i, j);
            if j == i {
                g[i] = r.eps1;
            }
            h[(i, j)] = r.eps1eps2;
            h[(j, i)] = r.eps1eps2;
        }
    }
    (g, h)
}

/// Max-norm of the discrete Euler–Lagrange residuals at the interior points.
fn residual_norm<L: Lagrangian<N>, const N: usize>(action: &SemAction<L, N>, x: &[Vec<f64>]) -> f64 {
    let d = N + 1;
    let g: Vec<DVector<f64>> = (0..x.len() - 1)
        .map(|k| full_derivatives(action, &x[k], &x[k + 1]).0)
        .collect();
    let r = (1..x.len() - 1).fold(0.0_f64, |m, k| m.max((g[k - 1].rows(d, d) + g[k].rows(0, d)).amax()));
    if r.is_finite() && x.windows(2).all(|w| w[1][0] > w[0][0]) {
        r
    } else {
        f64::INFINITY
    }
}

/// Solve Lee's boundary-value problem. `guess` holds `K + 1` points
/// `(t_k, q_k)` including both fixed endpoints; returns the solved points.
pub fn solve_lee_bvp<L: Lagrangian<N>, const N: usize>(
    action: &SemAction<L, N>,
    guess: &[(f64, SVector<f64, N>)],
    max_iterations: usize,
) -> Result<Vec<(f64, SVector<f64, N>)>> {
    let k_total = guess.len();
    if k_total < 3 {
        return Err(Error::InvalidParameter {
            name: "guess".into(),
            value: k_total.to_string(),
            reason: "need at least 3 points (one interior)".into(),
        });
    }
    if guess.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(Error::InvalidParameter {
            name: "guess".into(),
            value: "times".into(),
            reason: "times must increase strictly".into(),
        });
    }
    let d = N + 1;
    let mut x: Vec<Vec<f64>> = guess
        .iter()
        .map(|(t, q)| std::iter::once(*t).chain(q.iter().copied()).collect())
        .collect();
    let interior = k_total - 2;
    let mut last = f64::INFINITY;
    for it in 1..=max_iterations {
        // Per interval: gradient and Hessian of S(x_k, x_{k+1}).
        let derivs: Vec<(DVector<f64>, DMatrix<f64>)> = (0..k_total - 1)
            .map(|k| full_derivatives(action, &x[k], &x[k + 1]))
            .collect();
        let mut a = Vec::with_capacity(interior);
        let mut b = Vec::with_capacity(interior);
        let mut c = Vec::with_capacity(interior);
        let mut r = Vec::with_capacity(interior);
        let mut res_norm = 0.0_f64;
        for k in 1..=interior {
            let (g_prev, h_prev) = &derivs[k - 1];
            let (g_next, h_next) = &derivs[k];
            let rk = -(g_prev.rows(d, d) + g_next.rows(0, d));
            res_norm = res_norm.max(rk.amax());
            a.push(h_prev.view((d, 0), (d, d)).into_owned());
            b.push(h_prev.view((d, d), (d, d)) + h_next.view((0, 0), (d, d)));
            c.push(h_next.view((0, d), (d, d)).into_owned());
            r.push(rk);
        }
        // Block Thomas elimination.
        for k in 1..interior {
            let inv = b[k - 1].clone().try_inverse().ok_or_else(|| Error::SingularJacobian {
                context: "Lee boundary-value problem".into(),
                pivot: 0.0,
            })?;
            let m = &a[k] * inv;
            b[k] = &b[k] - &m * &c[k - 1];
            r[k] = &r[k] - &m * &r[k - 1];
        }
        let mut dx = vec![DVector::<f64>::zeros(d); interior];
        for k in (0..interior).rev() {
            let rhs = if k + 1 < interior {
                &r[k] - &c[k] * &dx[k + 1]
            } else {
                r[k].clone()
            };
            dx[k] = b[k].clone().lu().solve(&rhs).ok_or_else(|| Error::SingularJacobian {
                context: "Lee boundary-value problem".into(),
                pivot: 0.0,
            })?;
        }
        // Damp the update: every step t_{k+1} − t_k may at most halve (times stay
        // strictly increasing), then backtrack until the residual decreases.
        let mut lambda = 1.0_f64;
        for k in 0..=interior {
            let dt_old = x[k + 1][0] - x[k][0];
            let d_next = if k < interior { dx[k][0] } else { 0.0 };
            let d_prev = if k > 0 { dx[k - 1][0] } else { 0.0 };
            let shrink = d_prev - d_next;
            if shrink > 0.0 {
                lambda = lambda.min(0.5 * dt_old / shrink);
            }
        }
        let trial = |lambda: f64| -> Vec<Vec<f64>> {
            let mut y = x.clone();
            for k in 0..interior {
                for i in 0..d {
                    y[k + 1][i] += lambda * dx[k][i];
                }
            }
            y
        };
        let mut y = trial(lambda);
        for _ in 0..40 {
            if residual_norm(action, &y) <= (1.0 - 1e-4 * lambda) * res_norm || res_norm < 1e-12 {
                break;
            }
            lambda *= 0.5;
            y = trial(lambda);
        }
        x = y;
        let upd = dx.iter().fold(0.0_f64, |m, v| m.max(v.amax())) * lambda;
        if !upd.is_finite() {
            break;
        }
        if upd <= 1e-14 || (it > 2 && upd >= last && upd <= 1e-9) {
            return Ok(x.iter().map(|p| (p[0], SVector::from_fn(|i, _| p[1 + i]))).collect());
        }
        last = upd;
    }
    Err(Error::NewtonFailure {
        step: 0,
        t: guess[0].0,
        residual: last,
        iterations: max_iterations,
        reason: "Lee boundary-value Newton did not converge".into(),
    })
}
