//! The variable-step symplectic-energy-momentum integrator in fixed-energy form
//! (note 001 §2.2): state `(t_k, q_k, p_k)` and the energy `E_k`; unknowns
//! `(h_k, q_{k+1})`; equations
//!
//! `p_k + ∂S/∂q₀(q_k, q_{k+1}, h_k) = 0`,   `E⁻_k(q_k, q_{k+1}, h_k) = E_k`,
//!
//! then `p_{k+1} = ∂S/∂q₁`, `E_{k+1} = E⁺_{k+1} = −∂S/∂h`, `t_{k+1} = t_k + h_k`
//! (seed 001 (3.3)–(3.4)). For autonomous `L` the discrete energy is conserved
//! exactly (to solver tolerance).
//!
//! Solving: Newton on `(q_{k+1}, h)` with the exact Jacobian from the previous
//! step; if it fails or lands outside `[α, β]·h_{k−1}`, the scalar reduction
//! `f(h) = E⁻(q_k, q_{k+1}(h), h) − E_k` (inner Newton for `q_{k+1}(h)`) is
//! scanned on a geometric grid in `[α, β]·h_{k−1}` and the sign change nearest
//! `h_{k−1}` is refined by regula falsi. A step `h ≤ 0` is never returned (the
//! symmetric rules always admit the backward root `h = −h_{k−1}`).

use nalgebra::{SMatrix, SVector};
use num_dual::Dual2SVec64;

use super::action::SemAction;
use crate::ad::lift;
use crate::error::{Error, Result, check_finite, check_step};
use crate::mechanics::state::continues;
use crate::mechanics::{Lagrangian, velocity_from_momentum};
use crate::solve::dense::solve_small;
use crate::solve::scalar::illinois;
use crate::solve::{DenseLu, NewtonOptions};

/// State of a variable-step run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SemState<const N: usize> {
    /// Time `t_k`.
    pub t: f64,
    /// Position `q_k`.
    pub q: SVector<f64, N>,
    /// Momentum `p_k`.
    pub p: SVector<f64, N>,
    /// Discrete energy `E_k` carried to the next step.
    pub energy: f64,
    /// Previous step `h_{k−1}` (predictor and bracket centre).
    pub h: f64,
}

/// What a step reports.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SemStepInfo {
    /// The step taken.
    pub h: f64,
    /// Newton (or bracket) iterations.
    pub iterations: usize,
    /// A fixed-step fallback was taken: this step is not energy-exact.
    pub fallback: bool,
}

/// Options of the SEM step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SemOptions {
    /// Bracket `[α, β]·h_{k−1}` for the step (default `[0.2, 5]`).
    pub bracket: (f64, f64),
    /// Grid points in the bracket scan (default 32).
    pub samples: usize,
    /// On failure, take a fixed-step variational step with `h_{k−1}` instead
    /// (flagged; energy not conserved on that step). Default off.
    pub fallback: bool,
    /// Newton settings.
    pub newton: NewtonOptions,
}

impl Default for SemOptions {
    fn default() -> Self {
        Self {
            bracket: (0.2, 5.0),
            samples: 32,
            fallback: false,
            newton: NewtonOptions::default(),
        }
    }
}

/// Variable-step SEM integrator for a Lagrangian on `Rᴺ`.
#[derive(Debug, Clone)]
pub struct SemIntegrator<L, const N: usize> {
    action: SemAction<L, N>,
    options: SemOptions,
    lu: DenseLu,
    rhs: Vec<f64>,
    /// End `(t, q)` and mean velocity of the last step: the predictor when the next step continues it.
    last: Option<(f64, SVector<f64, N>, SVector<f64, N>)>,
}

/// A variable-step map: what a run driver needs, object-safe.
pub trait VariableStepMap<const N: usize> {
    /// See [`SemIntegrator::start`].
    fn start(
        &mut self,
        t0: f64,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        h0: f64,
    ) -> Result<(SemState<N>, SemState<N>)>;
    /// See [`SemIntegrator::step`].
    fn step(&mut self, index: usize, s: &SemState<N>) -> Result<(SemState<N>, SemStepInfo)>;
    /// See [`SemIntegrator::fixed_step`].
    fn fixed_step(&mut self, s: &SemState<N>, h: f64) -> Result<(SemState<N>, usize)>;
    /// Append what the next step depends on besides the state as checkpoint
    /// words; nothing by default.
    fn save_carry(&self, _out: &mut Vec<f64>) {}
    /// Restore what [`VariableStepMap::save_carry`] wrote.
    ///
    /// # Errors
    /// If the words do not fit this map.
    fn restore_carry(&mut self, _words: &mut crate::run::Words<'_>) -> Result<()> {
        Ok(())
    }
}

impl<L: Lagrangian<N>, const N: usize> VariableStepMap<N> for SemIntegrator<L, N> {
    fn start(
        &mut self,
        t0: f64,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        h0: f64,
    ) -> Result<(SemState<N>, SemState<N>)> {
        SemIntegrator::start(self, t0, q0, p0, h0)
    }
    fn step(&mut self, index: usize, s: &SemState<N>) -> Result<(SemState<N>, SemStepInfo)> {
        SemIntegrator::step(self, index, s)
    }
    fn fixed_step(&mut self, s: &SemState<N>, h: f64) -> Result<(SemState<N>, usize)> {
        SemIntegrator::fixed_step(self, s, h)
    }
}

/// The Jacobian of the reduced map `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})` at fixed energy.
pub type ReducedJacobian<const N: usize> = crate::mechanics::FlowJacobian<N>;

impl<L: Lagrangian<N>, const N: usize> SemIntegrator<L, N> {
    /// Integrator for `action` with default options.
    pub fn new(action: SemAction<L, N>) -> Self {
        Self::with_options(action, SemOptions::default())
    }

    /// Integrator with `options`.
    pub fn with_options(action: SemAction<L, N>, options: SemOptions) -> Self {
        Self {
            action,
            options,
            lu: DenseLu::new(N + 1),
            rhs: vec![0.0; N + 1],
            last: None,
        }
    }

    /// The action.
    pub fn action(&self) -> &SemAction<L, N> {
        &self.action
    }

    /// Solve `p + ∂S/∂q₀(q, q₁, h) = 0` for `q₁` at fixed `h` (Newton, exact Jacobian).
    fn solve_position(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        h: f64,
        guess: SVector<f64, N>,
    ) -> Option<(SVector<f64, N>, usize)> {
        let mut q1 = guess;
        let mut last = f64::INFINITY;
        for it in 1..=self.options.newton.max_iterations {
            let (_, s_q0, _, s_q0q1) = self.action.momentum_derivatives(t, q, &q1, h);
            let (dq, pivot) = solve_small(&s_q0q1, &(p + s_q0));
            if pivot == 0.0 || dq.iter().any(|x| !x.is_finite()) {
                return None;
            }
            q1 -= dq;
            let upd = dq.amax() / q1.amax().max(1.0);
            if upd <= self.options.newton.tol || (it > 2 && upd >= last && upd <= self.options.newton.stall_threshold) {
                return Some((q1, it));
            }
            last = upd;
        }
        None
    }

    /// A fixed-step variational step with step `h` (no energy equation).
    pub fn fixed_step(&self, state: &SemState<N>, h: f64) -> Result<(SemState<N>, usize)> {
        check_step(h)?;
        let guess = state.q + self.velocity(state) * h;
        let (q1, it) = self
            .solve_position(state.t, &state.q, &state.p, h, guess)
            .ok_or_else(|| Error::NewtonFailure {
                step: 0,
                t: state.t,
                residual: f64::NAN,
                iterations: self.options.newton.max_iterations,
                reason: "fixed-step momentum equation did not converge".into(),
            })?;
        let d = self.action.derivatives(state.t, &state.q, &q1, h);
        Ok((
            SemState {
                t: state.t + h,
                q: q1,
                p: d.q1,
                energy: -d.h,
                h,
            },
            it,
        ))
    }

    fn velocity(&self, state: &SemState<N>) -> SVector<f64, N> {
        velocity_from_momentum(self.action.lagrangian(), state.t, &state.q, &state.p)
            .unwrap_or_else(|_| SVector::zeros())
    }

    /// Start a run: a first fixed step with `h0` from `(t0, q0, p0)` fixes the
    /// discrete energy `E := E_d(q₀, q₁, h₀)` (note 001 §2.2; not `H(q₀, p₀)`,
    /// which makes the energy equation degenerate for symmetric rules).
    /// Returns the state at `t₀` (with `E⁻₀`) and at `t₀ + h₀`.
    pub fn start(
        &self,
        t0: f64,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        h0: f64,
    ) -> Result<(SemState<N>, SemState<N>)> {
        check_finite("q0", q0.iter())?;
        check_finite("p0", p0.iter())?;
        let s0 = SemState {
            t: t0,
            q: q0,
            p: p0,
            energy: f64::NAN,
            h: h0,
        };
        let (s1, _) = self.fixed_step(&s0, h0)?;
        let d = self.action.derivatives(t0, &q0, &s1.q, h0);
        Ok((
            SemState {
                energy: d.t0 - d.h,
                ..s0
            },
            s1,
        ))
    }

    /// Newton on `(q₁, h)` from a guess; `None` if it fails.
    fn newton_full(
        &mut self,
        s: &SemState<N>,
        mut q1: SVector<f64, N>,
        mut h: f64,
    ) -> Option<(SVector<f64, N>, f64, usize)> {
        let opts = self.options.newton;
        let mut last = f64::INFINITY;
        let n1 = N + 1;
        // Simplified Newton: the exact Jacobian is refreshed only when the
        // iteration stops contracting fast (ratio > 0.1), otherwise only the
        // residuals are evaluated (one forward-mode pass instead of four).
        let mut fresh = false;
        for it in 1..=opts.max_iterations {
            let (r1, r2) = if fresh {
                self.action.step_residuals(s.t, &s.q, &q1, h)
            } else {
                let d = self.action.derivatives(s.t, &s.q, &q1, h);
                for a in 0..N {
                    for b in 0..N {
                        self.lu.matrix[a * n1 + b] = d.q0q1[(a, b)];
                    }
                    self.lu.matrix[a * n1 + N] = d.q0h[a];
                    self.lu.matrix[N * n1 + a] = d.q1t0[a] - d.q1h[a];
                }
                self.lu.matrix[N * n1 + N] = d.t0h - d.hh;
                self.lu.factor("SEM step").ok()?;
                fresh = true;
                (d.q0, d.t0 - d.h)
            };
            let (r1, r2) = (s.p + r1, r2 - s.energy);
            for a in 0..N {
                self.rhs[a] = -r1[a];
            }
            self.rhs[N] = -r2;
            self.lu.solve(&mut self.rhs);
            if self.rhs.iter().any(|x| !x.is_finite()) {
                return None;
            }
            for a in 0..N {
                q1[a] += self.rhs[a];
            }
            h += self.rhs[N];
            let upd = (0..N).fold(0.0_f64, |m, a| m.max(self.rhs[a].abs())) / q1.amax().max(1.0);
            let upd = upd.max(self.rhs[N].abs() / h.abs().max(f64::MIN_POSITIVE));
            // The h-equation is ill-conditioned (∂E_d/∂h ≈ 2c·h, note 001 §3.4), so
            // the update reaches a noise floor above ε: stop once it no longer
            // shrinks there.
            if upd <= opts.tol || (it > 1 && upd > 0.25 * last && upd <= opts.stall_threshold) {
                return Some((q1, h, it));
            }
            if upd > 0.1 * last {
                fresh = false;
            }
            last = upd;
        }
        None
    }

    /// The energy residual `f(h) = E⁻(q, q₁(h), h) − E` and `q₁(h)`.
    fn energy_residual(&self, s: &SemState<N>, h: f64, guess: SVector<f64, N>) -> Option<(f64, SVector<f64, N>)> {
        let (q1, _) = self.solve_position(s.t, &s.q, &s.p, h, guess)?;
        let d = self.action.derivatives(s.t, &s.q, &q1, h);
        let f = d.t0 - d.h - s.energy;
        f.is_finite().then_some((f, q1))
    }

    /// Bracket scan and regula falsi on `[α, β]·h_prev`.
    fn bracketed(&self, index: usize, s: &SemState<N>, v: SVector<f64, N>) -> Result<(SVector<f64, N>, f64, usize)> {
        let (alpha, beta) = self.options.bracket;
        let n = self.options.samples.max(4);
        let scan = |sign: f64| -> Vec<(f64, f64)> {
            (0..n)
                .filter_map(|i| {
                    let h = sign * s.h * alpha * (beta / alpha).powf(i as f64 / (n - 1) as f64);
                    self.energy_residual(s, h, s.q + v * h).map(|(f, _)| (h, f))
                })
                .collect()
        };
        let grid = scan(1.0);
        // Sign changes, nearest to h_prev in log distance.
        let best = grid
            .windows(2)
            .filter(|w| w[0].1.signum() != w[1].1.signum() || w[0].1 == 0.0)
            .min_by(|a, b| {
                let da = ((a[0].0 * a[1].0).sqrt() / s.h).ln().abs();
                let db = ((b[0].0 * b[1].0).sqrt() / s.h).ln().abs();
                da.total_cmp(&db)
            })
            .map(|w| (w[0].0, w[1].0));
        if let Some((a, b)) = best {
            let mut evals = 0;
            let h = illinois(
                |h| {
                    evals += 1;
                    self.energy_residual(s, h, s.q + v * h).map(|(f, _)| f)
                },
                a,
                b,
                4.0 * f64::EPSILON,
                200,
            )
            .ok_or_else(|| Error::NoStepRoot {
                step: index,
                t: s.t,
                reason: "root refinement failed".into(),
            })?;
            let (_, q1) = self
                .energy_residual(s, h, s.q + v * h)
                .ok_or_else(|| Error::NoStepRoot {
                    step: index,
                    t: s.t,
                    reason: "momentum equation failed at the root".into(),
                })?;
            return Ok((q1, h, evals + n));
        }
        let near = format!(
            "no sign change of E_d − E for h in [{:.3e}, {:.3e}]",
            alpha * s.h,
            beta * s.h
        );
        if grid.len() < 2 {
            return Err(Error::NoStepRoot {
                step: index,
                t: s.t,
                reason: format!("{near}: momentum equation unsolvable"),
            });
        }
        if !self.action.rule().is_symmetric() {
            let back = scan(-1.0);
            if let Some(w) = back.windows(2).find(|w| w[0].1.signum() != w[1].1.signum()) {
                return Err(Error::NegativeStep {
                    step: index,
                    t: s.t,
                    h: 0.5 * (w[0].0 + w[1].0),
                });
            }
        }
        // An interior minimum of |f| that does not reach zero: a fold of the energy equation.
        let abs: Vec<f64> = grid.iter().map(|(_, f)| f.abs()).collect();
        let imin = abs
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .map_or(0, |(i, _)| i);
        if imin > 0 && imin + 1 < abs.len() {
            return Err(Error::DegenerateStep {
                step: index,
                t: s.t,
                reason: format!(
                    "{near}; |E_d − E| has a minimum {:.3e} at h = {:.3e} (c(q, p) ≈ 0)",
                    abs[imin], grid[imin].0
                ),
            });
        }
        Err(Error::NoStepRoot {
            step: index,
            t: s.t,
            reason: near,
        })
    }

    /// One fixed-energy step.
    pub fn step(&mut self, index: usize, s: &SemState<N>) -> Result<(SemState<N>, SemStepInfo)> {
        check_finite("q", s.q.iter())?;
        check_finite("p", s.p.iter())?;
        check_finite("energy", [s.energy].iter())?;
        check_step(s.h)?;
        let v = match self.last {
            Some((t, q, v)) if continues(t, &q, s.t, &s.q) => v,
            _ => self.velocity(s),
        };
        let (alpha, beta) = self.options.bracket;
        // Predictor: solve the (well-conditioned) momentum equation at h = h_{k−1}
        // first, so that the joint Newton starts next to the forward root and
        // not between it and the backward root h = −h_{k−1}.
        let newton = self
            .solve_position(s.t, &s.q, &s.p, s.h, s.q + v * s.h)
            .and_then(|(q1, it0)| self.newton_full(s, q1, s.h).map(|(q, h, it)| (q, h, it + it0)))
            .filter(|(_, h, _)| *h >= alpha * s.h && *h <= beta * s.h);
        let solved = match newton {
            Some(x) => Ok(x),
            None => self.bracketed(index, s, v),
        };
        match solved {
            Ok((q1, h, iterations)) => {
                if h <= 0.0 {
                    return Err(Error::NegativeStep { step: index, t: s.t, h });
                }
                let (p1, e1) = self.action.arrival(s.t, &s.q, &q1, h);
                let next = SemState {
                    t: s.t + h,
                    q: q1,
                    p: p1,
                    energy: e1,
                    h,
                };
                self.last = Some((next.t, q1, (q1 - s.q) / h));
                Ok((
                    next,
                    SemStepInfo {
                        h,
                        iterations,
                        fallback: false,
                    },
                ))
            }
            Err(e) if self.options.fallback => {
                let (next, iterations) = self.fixed_step(s, s.h).map_err(|_| e)?;
                Ok((
                    next,
                    SemStepInfo {
                        h: s.h,
                        iterations,
                        fallback: true,
                    },
                ))
            }
            Err(e) => Err(e),
        }
    }

    /// Exact Jacobian of the reduced map `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})` at
    /// fixed energy `E_k` (implicit function theorem on the step equations).
    pub fn reduced_jacobian(&mut self, s: &SemState<N>) -> Result<(SemState<N>, ReducedJacobian<N>)> {
        let (next, info) = self.step(0, s)?;
        let (q0, q1, h, t) = (s.q, next.q, info.h, s.t);
        let d = self.action.derivatives(t, &q0, &q1, h);
        let (_, _, s_q0q0) = num_dual::hessian(
            |x: SVector<Dual2SVec64<N>, N>| {
                self.action
                    .action(Dual2SVec64::from(t), &x, &lift(&q1), Dual2SVec64::from(h))
            },
            &q0,
        );
        let (_, _, s_q1q1) = num_dual::hessian(
            |x: SVector<Dual2SVec64<N>, N>| {
                self.action
                    .action(Dual2SVec64::from(t), &lift(&q0), &x, Dual2SVec64::from(h))
            },
            &q1,
        );
        // Unknowns x = (q₁, h); R₁ = p + S_{q₀}, R₂ = S_{t₀} − S_h − E.
        let n1 = N + 1;
        let mut a = DenseLu::new(n1);
        for i in 0..N {
            for j in 0..N {
                a.matrix[i * n1 + j] = d.q0q1[(i, j)];
            }
            a.matrix[i * n1 + N] = d.q0h[i];
            a.matrix[N * n1 + i] = d.q1t0[i] - d.q1h[i];
        }
        a.matrix[N * n1 + N] = d.t0h - d.hh;
        a.factor("SEM reduced Jacobian")?;
        let mut jac = ReducedJacobian::<N> {
            qq: SMatrix::zeros(),
            qp: SMatrix::zeros(),
            pq: SMatrix::zeros(),
            pp: SMatrix::zeros(),
        };
        let mut rhs = vec![0.0; n1];
        for wrt_p in [false, true] {
            for j in 0..N {
                // −∂R/∂(q or p) along e_j.
                for i in 0..N {
                    rhs[i] = if wrt_p {
                        if i == j { -1.0 } else { 0.0 }
                    } else {
                        -s_q0q0[(i, j)]
                    };
                }
                rhs[N] = if wrt_p { 0.0 } else { -(d.q0t0[j] - d.q0h[j]) };
                a.solve(&mut rhs);
                let dq1 = SVector::<f64, N>::from_fn(|i, _| rhs[i]);
                let dh = rhs[N];
                let mut dp1 = s_q1q1 * dq1 + d.q1h * dh;
                if !wrt_p {
                    dp1 += d.q0q1.transpose().column(j);
                }
                if wrt_p {
                    jac.qp.set_column(j, &dq1);
                    jac.pp.set_column(j, &dp1);
                } else {
                    jac.qq.set_column(j, &dq1);
                    jac.pq.set_column(j, &dp1);
                }
            }
        }
        Ok((next, jac))
    }
}
