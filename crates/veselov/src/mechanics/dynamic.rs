//! Lagrangian systems whose dimension is known only at run time.
//!
//! The user writes `L(t, q, v)` once over slices, generic over the AD scalar,
//! exactly as for the fixed-size [`Lagrangian`](super::Lagrangian). Derivatives
//! are taken by directional forward mode with `Copy` scalars: the gradient by
//! `2n` first-order passes, the Hessian by `n(2n+1)` hyper-dual passes, each
//! writing into buffers allocated once, so a step allocates nothing. The
//! Galerkin equations and discrete Legendre transforms are those of
//! [`GalerkinIntegrator`](super::GalerkinIntegrator) (see there), on heap
//! storage sized at construction. Each step is solved from a
//! constant-position predictor by the library's simplified Newton iteration
//! ([`solve_simplified_newton`]), which keeps the factored exact Jacobian
//! across steps while it contracts and refreshes it when it does not: the
//! Hessian passes, `n(2n+1)` per stage, dominate the cost of a Jacobian,
//! and a residual needs only `2n` first-order passes per stage. Should the
//! simplified iteration fail, the step is solved again by the full Newton
//! iteration [`solve_newton`] (full steps, [`LineSearch::Full`]).

use num_dual::{Dual64, HyperDual64};

use super::galerkin::EULER_LAGRANGE_NEWTON_STEP;
use super::scheme::GalerkinScheme;
use crate::ad::Scalar;
use crate::error::{Error, Result, check_finite, check_step};
use crate::solve::{
    DenseLu, LineSearch, NewtonOptions, NewtonSystem, SimplifiedNewtonSystem, solve_newton, solve_simplified_newton,
};

/// A Lagrangian on `Rⁿ` with `n` fixed at run time.
pub trait DynLagrangian {
    /// The dimension `n`.
    fn dim(&self) -> usize;
    /// `L(t, q, v)` with `q.len() == v.len() == dim()`.
    fn lagrangian<D: Scalar>(&self, t: D, q: &[D], v: &[D]) -> D;
}

/// A phase-space state of run-time dimension.
#[derive(Debug, Clone, PartialEq)]
pub struct DynState {
    /// Time.
    pub t: f64,
    /// Configuration.
    pub q: Vec<f64>,
    /// Momentum.
    pub p: Vec<f64>,
}

/// Directional-AD evaluation buffers.
#[derive(Debug, Clone)]
struct Buffers {
    d1: Vec<Dual64>,
    d2: Vec<HyperDual64>,
}

/// Gradient (length 2n: `∂L/∂q`, `∂L/∂v`) and Hessian (2n × 2n, row-major) of `L` at `(t, x, y)`.
fn derivatives<L: DynLagrangian>(
    l: &L,
    t: f64,
    x: &[f64],
    y: &[f64],
    buf: &mut Buffers,
    grad: &mut [f64],
    hess: Option<&mut [f64]>,
) {
    let n = x.len();
    let m = 2 * n;
    let value = |k: usize| if k < n { x[k] } else { y[k - n] };
    match hess {
        None => {
            for i in 0..m {
                for k in 0..m {
                    buf.d1[k] = Dual64::from(value(k));
                }
                buf.d1[i].eps = 1.0;
                let (q, v) = buf.d1.split_at(n);
                grad[i] = l.lagrangian(Dual64::from(t), q, v).eps;
            }
        }
        Some(hess) => {
            for i in 0..m {
                for j in i..m {
                    for k in 0..m {
                        buf.d2[k] = HyperDual64::from(value(k));
                    }
                    buf.d2[i].eps1 = 1.0;
                    buf.d2[j].eps2 = 1.0;
                    let (q, v) = buf.d2.split_at(n);
                    let r = l.lagrangian(HyperDual64::from(t), q, v);
                    if i == j {
                        grad[i] = r.eps1;
                    }
                    hess[i * m + j] = r.eps1eps2;
                    hess[j * m + i] = r.eps1eps2;
                }
            }
        }
    }
}

/// The Galerkin variational integrator for a [`DynLagrangian`].
#[derive(Debug, Clone)]
pub struct DynGalerkinIntegrator<L> {
    lagrangian: L,
    scheme: GalerkinScheme,
    h: f64,
    n: usize,
    options: NewtonOptions,
    /// Control-point increments `Z^ν`, `(m+1)·n`.
    z: Vec<f64>,
    /// Trial control points of a line search, `(m+1)·n`.
    trial: Vec<f64>,
    base: Vec<f64>,
    /// `G_ν`, `(m+1)·n`.
    g: Vec<f64>,
    /// Per stage: gradient (2n) and Hessian (4n²).
    stage_grad: Vec<f64>,
    stage_hess: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
    delta: Vec<f64>,
    buf: Buffers,
    lu: DenseLu,
    /// Whether `lu` holds a factored Jacobian that may be reused.
    kept: bool,
    /// Exact Jacobians evaluated since construction.
    jacobians: u64,
}

impl<L: DynLagrangian> DynGalerkinIntegrator<L> {
    /// Integrator for `lagrangian` with `scheme` and step `h > 0`.
    pub fn new(lagrangian: L, scheme: GalerkinScheme, h: f64) -> Result<Self> {
        check_step(h)?;
        let n = lagrangian.dim();
        if n == 0 {
            return Err(Error::DimensionMismatch {
                what: "dim()".into(),
                expected: 1,
                got: 0,
            });
        }
        let (m, r) = (scheme.intervals(), scheme.quadrature_len());
        Ok(Self {
            lagrangian,
            h,
            n,
            options: NewtonOptions::default(),
            z: vec![0.0; (m + 1) * n],
            trial: vec![0.0; (m + 1) * n],
            base: vec![0.0; n],
            g: vec![0.0; (m + 1) * n],
            stage_grad: vec![0.0; r * 2 * n],
            stage_hess: vec![0.0; r * 4 * n * n],
            x: vec![0.0; n],
            y: vec![0.0; n],
            delta: vec![0.0; m * n],
            buf: Buffers {
                d1: vec![Dual64::from(0.0); 2 * n],
                d2: vec![HyperDual64::from(0.0); 2 * n],
            },
            lu: DenseLu::new(m * n),
            kept: false,
            jacobians: 0,
            scheme,
        })
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// Exact Jacobians evaluated since construction (full or simplified
    /// Newton).
    pub fn jacobians(&self) -> u64 {
        self.jacobians
    }

    /// Append what the next step depends on besides the state (the kept
    /// Jacobian's factors, if any) as checkpoint words, so that a resumed run
    /// repeats the iterations of an uninterrupted one bit for bit.
    pub fn save_carry(&self, out: &mut Vec<f64>) {
        out.push(f64::from(u8::from(self.kept)));
        if self.kept {
            self.lu.save_factors(out);
        }
    }

    /// Restore what [`DynGalerkinIntegrator::save_carry`] wrote.
    ///
    /// # Errors
    /// If the words run out or do not fit this integrator.
    pub fn restore_carry(&mut self, words: &mut crate::run::Words<'_>) -> Result<()> {
        self.kept = words.flag()?;
        if self.kept {
            self.lu.restore_factors(words)?;
        }
        Ok(())
    }

    /// The time step `h`.
    pub fn step_size(&self) -> f64 {
        self.h
    }

    /// The options of each step's Newton iteration (tolerance, iteration
    /// limit); the default is [`NewtonOptions::default`].
    pub fn with_newton_options(mut self, options: NewtonOptions) -> Self {
        self.options = options;
        self
    }

    /// Stage derivatives at the current control points; then `G_ν`.
    fn evaluate(&mut self, t: f64, with_hessian: bool) {
        let (n, m1, r) = (self.n, self.scheme.intervals() + 1, self.scheme.quadrature_len());
        for i in 0..r {
            for a in 0..n {
                let (mut xa, mut ya) = (self.base[a], 0.0);
                for nu in 0..m1 {
                    xa += self.scheme.value(i, nu) * self.z[nu * n + a];
                    ya += self.scheme.derivative(i, nu) * self.z[nu * n + a];
                }
                self.x[a] = xa;
                self.y[a] = ya / self.h;
            }
            let ti = t + self.scheme.quadrature_nodes()[i] * self.h;
            let grad = &mut self.stage_grad[i * 2 * n..(i + 1) * 2 * n];
            let hess = with_hessian.then(|| &mut self.stage_hess[i * 4 * n * n..(i + 1) * 4 * n * n]);
            derivatives(&self.lagrangian, ti, &self.x, &self.y, &mut self.buf, grad, hess);
        }
        self.g.fill(0.0);
        for i in 0..r {
            let w = self.h * self.scheme.quadrature_weights()[i];
            for nu in 0..m1 {
                let (mv, dv) = (w * self.scheme.value(i, nu), w * self.scheme.derivative(i, nu) / self.h);
                for a in 0..n {
                    self.g[nu * n + a] += mv * self.stage_grad[i * 2 * n + a] + dv * self.stage_grad[i * 2 * n + n + a];
                }
            }
        }
    }

    /// `∂²S/∂Q^ν_a ∂Q^μ_b` from the stage Hessians.
    fn block(&self, nu: usize, a: usize, mu: usize, b: usize) -> f64 {
        let n = self.n;
        let m = 2 * n;
        let mut s = 0.0;
        for i in 0..self.scheme.quadrature_len() {
            let w = self.h * self.scheme.quadrature_weights()[i];
            let hs = &self.stage_hess[i * m * m..(i + 1) * m * m];
            let (mn, mm) = (self.scheme.value(i, nu), self.scheme.value(i, mu));
            let (dn, dm) = (
                self.scheme.derivative(i, nu) / self.h,
                self.scheme.derivative(i, mu) / self.h,
            );
            s += w
                * (mn * mm * hs[a * m + b]
                    + mn * dm * hs[a * m + n + b]
                    + dn * mm * hs[(n + a) * m + b]
                    + dn * dm * hs[(n + a) * m + n + b]);
        }
        s
    }

    /// `‖R‖∞` of the step equations `p_k + G₀ = 0`, `G_ν = 0 (ν = 1..m−1)` at the last evaluation.
    fn residual_norm(&self, p: &[f64]) -> f64 {
        let n = self.n;
        let mut residual = 0.0_f64;
        for nu in 0..self.scheme.intervals() {
            for a in 0..n {
                residual = residual.max(self.residual(p, nu, a).abs());
            }
        }
        residual
    }

    /// Component `a` of the step equation `ν`: `G_ν + p_k δ_{ν0}` at the last evaluation.
    fn residual(&self, p: &[f64], nu: usize, a: usize) -> f64 {
        self.g[nu * self.n + a] + if nu == 0 { p[a] } else { 0.0 }
    }

    /// One step `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})`; returns the Newton iterations.
    pub fn step(&mut self, index: usize, state: &mut DynState) -> Result<usize> {
        let n = self.n;
        for (what, v) in [("q", &state.q), ("p", &state.p)] {
            if v.len() != n {
                return Err(Error::DimensionMismatch {
                    what: what.into(),
                    expected: n,
                    got: v.len(),
                });
            }
            check_finite(what, v.iter())?;
        }
        let m = self.scheme.intervals();
        self.base.copy_from_slice(&state.q);
        // Predictor: constant position (the Newton iteration converges from it for small h).
        self.z.fill(0.0);
        let options = self.options;
        let mut equations = DynStepEquations {
            integrator: self,
            t: state.t,
            p: &state.p,
        };
        let iterations = match solve_simplified_newton(&mut equations, &options, index, state.t) {
            // Jacobians are counted where they are assembled.
            Ok((report, _)) => report.iterations,
            Err(_) => {
                // Start again from the predictor with full Newton steps.
                equations.integrator.z.fill(0.0);
                let report = solve_newton(&mut equations, &options, LineSearch::Full, index, state.t)?;
                report.iterations
            }
        };
        // q_{k+1} = q_k + Zᵐ, p_{k+1} = p_k + h Σᵢ bᵢ ∂L/∂q(i) (= G_m at the solution).
        for a in 0..n {
            state.q[a] += self.z[m * n + a];
            let mut dp = 0.0;
            for i in 0..self.scheme.quadrature_len() {
                dp += self.h * self.scheme.quadrature_weights()[i] * self.stage_grad[i * 2 * n + a];
            }
            state.p[a] += dp;
        }
        state.t += self.h;
        Ok(iterations)
    }
}

/// The equations of one step of a [`DynGalerkinIntegrator`] at time `t` from
/// the momentum `p = p_k`: unknowns `Z¹..Zᵐ`.
struct DynStepEquations<'a, L> {
    integrator: &'a mut DynGalerkinIntegrator<L>,
    t: f64,
    p: &'a [f64],
}

impl<L: DynLagrangian> NewtonSystem for DynStepEquations<'_, L> {
    const LINEARISATION: &'static str = EULER_LAGRANGE_NEWTON_STEP;

    fn evaluate(&mut self) -> f64 {
        self.integrator.evaluate(self.t, true);
        self.integrator.residual_norm(self.p)
    }

    fn assemble(&mut self) {
        let s = &mut *self.integrator;
        // The matrix is overwritten: no factored Jacobian is kept any more.
        s.kept = false;
        s.jacobians += 1;
        let (n, m) = (s.n, s.scheme.intervals());
        let dim = m * n;
        for nu in 0..m {
            for a in 0..n {
                s.delta[nu * n + a] = -s.residual(self.p, nu, a);
                for mu in 1..=m {
                    for b in 0..n {
                        s.lu.matrix[(nu * n + a) * dim + (mu - 1) * n + b] = s.block(nu, a, mu, b);
                    }
                }
            }
        }
    }

    fn linear_system(&mut self) -> (&mut DenseLu, &mut [f64]) {
        let s = &mut *self.integrator;
        (&mut s.lu, &mut s.delta)
    }

    fn scale(&self) -> f64 {
        let s = &*self.integrator;
        s.base.iter().chain(&s.z).fold(1.0_f64, |acc, v| acc.max(v.abs()))
    }

    fn trial_residual(&mut self, lambda: f64) -> f64 {
        let s = &mut *self.integrator;
        let n = s.n;
        s.trial.copy_from_slice(&s.z);
        for (k, d) in s.delta.iter().enumerate() {
            s.trial[n + k] += lambda * d;
        }
        std::mem::swap(&mut s.z, &mut s.trial);
        s.evaluate(self.t, false);
        std::mem::swap(&mut s.z, &mut s.trial);
        s.residual_norm(self.p)
    }

    fn update(&mut self, lambda: f64) {
        let s = &mut *self.integrator;
        let n = s.n;
        for (k, d) in s.delta.iter().enumerate() {
            s.z[n + k] += lambda * d;
        }
    }

    fn accept(&mut self) -> f64 {
        self.integrator.evaluate(self.t, false);
        self.integrator.residual_norm(self.p)
    }
}

impl<L: DynLagrangian> SimplifiedNewtonSystem for DynStepEquations<'_, L> {
    fn residual_only(&mut self) -> f64 {
        let s = &mut *self.integrator;
        s.evaluate(self.t, false);
        let n = s.n;
        for nu in 0..s.scheme.intervals() {
            for a in 0..n {
                s.delta[nu * n + a] = -s.residual(self.p, nu, a);
            }
        }
        s.residual_norm(self.p)
    }

    fn kept_jacobian(&mut self) -> &mut bool {
        &mut self.integrator.kept
    }
}
