//! The general variational integrator of a Galerkin discrete Lagrangian, solved by
//! simplified Newton with the exact Jacobian kept across steps.
//!
//! With control points `Q⁰ … Qᵐ` (see [`GalerkinScheme`]) and the discrete action
//! `S(Q) = h Σᵢ bᵢ L(t_k + cᵢh, Xᵢ, Yᵢ)`, `Xᵢ = Σ_ν M_{iν}Q^ν`, `Yᵢ = Σ_ν D_{iν}Q^ν/h`,
//! write `G_ν = ∂S/∂Q^ν = h Σᵢ bᵢ [M_{iν} ∂L/∂q(i) + D_{iν}/h ∂L/∂v(i)]`
//! (seed 004 §4.3). The discrete Legendre transforms
//! `p_k = −D₁L_d(q_k, q_{k+1}) = −G₀` and `p_{k+1} = D₂L_d(q_k, q_{k+1}) = G_m`
//! (DESIGN conventions; Marsden & West 2001, eq. (1.5.5)) give the step
//! `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})`:
//!
//! 1. solve `p_k + G₀ = 0`, `G_ν = 0 (ν = 1..m−1)` for `Q¹..Qᵐ`: simplified
//!    Newton ([`crate::solve::solve_simplified_newton`]) whose exact Jacobian
//!    (the Hessian of `S` from the stage Hessians) is kept from step to step
//!    and evaluated afresh when the last contraction factor foretells more
//!    than two further iterations; each iteration needs only the stage
//!    gradients. If it fails, Newton with line search from the same start.
//!    The step statistics count the Jacobians evaluated. With a single
//!    scalar unknown (`N = 1`, one interval) Newton is used directly.
//! 2. `q_{k+1} = Qᵐ`, `p_{k+1} = G_m`.
//!
//! With a generalised force `F` (discrete Lagrange–d'Alembert, seed 004 §2 and
//! Prop. 7.4) every `G_ν` gains the virtual work `h Σᵢ bᵢ M_{iν} F(i)`, so that
//! `p_k = −D₁L_d − f⁻` and `p_{k+1} = D₂L_d + f⁺` with the quadrature forces
//! `f⁻ = h Σᵢ bᵢ M_{i0} F(i)`, `f⁺ = h Σᵢ bᵢ M_{im} F(i)`.
//!
//! The same Hessian of `S` gives the exact Jacobian of the step by the implicit
//! function theorem ([`GalerkinIntegrator::flow_jacobian`]).

use nalgebra::{SMatrix, SVector};

mod extrapolation_error;
mod flow_jacobian;

use super::force::{Force, ForceJet, NoForce, force_jet, force_value};
use super::lagrangian::{Hessian, Jet, Lagrangian, hessian, jet, velocity_from_momentum};
use super::scheme::{GalerkinScheme, Method};
use super::state::{OneStepMap, PhaseState, StepStats, continues, restore_step_end, save_step_end};
use crate::error::{Error, Result, check_finite, check_step};
use crate::solve::{
    DenseLu, LineSearch, NewtonOptions, NewtonReport, NewtonStop, NewtonSystem, SimplifiedNewtonSystem, solve_newton,
    solve_simplified_newton,
};
use extrapolation_error::ExtrapolationCorrection;

/// Value and discrete Legendre transforms of `L_d(q₀, q₁)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscreteLagrangianValue<const N: usize> {
    /// `L_d(q₀, q₁)`.
    pub value: f64,
    /// `p₀ = −D₁L_d(q₀, q₁)` (discrete Legendre transform 𝔽⁻).
    pub minus: SVector<f64, N>,
    /// `p₁ = D₂L_d(q₀, q₁)` (discrete Legendre transform 𝔽⁺).
    pub plus: SVector<f64, N>,
}

/// Variational integrator for any Galerkin discrete Lagrangian; the general,
/// exact-Newton path. All workspace is allocated at construction: a step does
/// not allocate.
#[derive(Debug, Clone)]
pub struct GalerkinIntegrator<L, const N: usize, F = NoForce> {
    lagrangian: L,
    force: F,
    stage_forces: Vec<ForceJet<N>>,
    scheme: GalerkinScheme,
    h: f64,
    options: NewtonOptions,
    /// Base point `q_k` (step) or `q₀` (boundary-value mode).
    base: SVector<f64, N>,
    /// Control-point increments `Z^ν = Q^ν − base` (`Z⁰ = 0`): solving for
    /// increments keeps round-off proportional to the step, not to `|q|`.
    controls: Vec<SVector<f64, N>>,
    /// `h Σᵢ bᵢ ∂L/∂q(i)` at the last gradient evaluation.
    force_sum: SVector<f64, N>,
    /// Kahan compensation of the running sums `q_{k+1} = q_k + Zᵐ`, `p_{k+1} = p_k + h Σ bᵢ ∂L/∂q(i)`.
    compensation: (SVector<f64, N>, SVector<f64, N>),
    trial: Vec<SVector<f64, N>>,
    delta: Vec<f64>,
    gradient: Vec<SVector<f64, N>>,
    stage_jets: Vec<Jet<N>>,
    stage_hessians: Vec<Hessian<N>>,
    lu: DenseLu,
    lu_bvp: DenseLu,
    /// Whether `lu` (step) and `lu_bvp` (boundary value) hold a factored
    /// Jacobian that the simplified Newton iteration may reuse.
    jacobian_kept: bool,
    bvp_jacobian_kept: bool,
    /// Jacobians evaluated by the last step.
    last_jacobians: usize,
    /// The predicted controls, to restart from if the simplified iteration fails.
    start: Vec<SVector<f64, N>>,
    previous: Option<(f64, SVector<f64, N>)>,
    previous_controls: Vec<SVector<f64, N>>,
    /// The correction of the extrapolated controls by the last steps'
    /// extrapolation errors.
    correction: ExtrapolationCorrection<N>,
}

/// Which set of equations the Newton solve handles.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Mode {
    /// Unknowns `Q¹..Qᵐ`, equations `p_k + G₀ = 0, G₁..G_{m−1} = 0`.
    Step,
    /// Unknowns `Q¹..Q^{m−1}`, equations `G₁..G_{m−1} = 0` (endpoints fixed).
    BoundaryValue,
}

/// Marks the kept Jacobian's part of the checkpoint carry.
const JACOBIAN_CARRY_TAG: f64 = -3.0;

/// What the Newton iterations of the Galerkin integrators linearise, named in
/// a singular-Jacobian error.
pub(super) const EULER_LAGRANGE_NEWTON_STEP: &str = "Newton step of the discrete Euler–Lagrange equations";

/// The equations of one Newton solve of a [`GalerkinIntegrator`]: the control
/// points of `mode` at time `t`, with `p = p_k` in step mode.
struct ControlPointEquations<'a, L, const N: usize, F> {
    integrator: &'a mut GalerkinIntegrator<L, N, F>,
    mode: Mode,
    t: f64,
    p: SVector<f64, N>,
}

impl Mode {
    /// First equation block `ν` and number of unknown blocks (columns
    /// `μ = 1..=unknowns`) with `m` intervals.
    fn layout(self, m: usize) -> (usize, usize) {
        match self {
            Mode::Step => (0, m),
            Mode::BoundaryValue => (1, m - 1),
        }
    }
}

impl<L, const N: usize, F> ControlPointEquations<'_, L, N, F> {
    fn unknowns(&self) -> usize {
        self.mode.layout(self.integrator.scheme.intervals()).1
    }
}

impl<L: Lagrangian<N>, const N: usize, F: Force<N>> ControlPointEquations<'_, L, N, F> {
    /// `−R` into the update `δ`, from the gradient held.
    fn write_residual(&mut self) {
        let (row0, unknowns) = self.mode.layout(self.integrator.scheme.intervals());
        let s = &mut *self.integrator;
        for (rb, nu) in (row0..row0 + unknowns).enumerate() {
            let mut g = s.gradient[nu];
            if self.mode == Mode::Step && nu == 0 {
                g += self.p;
            }
            for a in 0..N {
                s.delta[rb * N + a] = -g[a];
            }
        }
    }
}

impl<L: Lagrangian<N>, const N: usize, F: Force<N>> SimplifiedNewtonSystem for ControlPointEquations<'_, L, N, F> {
    fn residual_only(&mut self) -> f64 {
        self.integrator.eval_gradient(self.t, false);
        self.write_residual();
        self.integrator.residual_norm(self.mode, &self.p)
    }
    fn kept_jacobian(&mut self) -> &mut bool {
        match self.mode {
            Mode::Step => &mut self.integrator.jacobian_kept,
            Mode::BoundaryValue => &mut self.integrator.bvp_jacobian_kept,
        }
    }
}

impl<L: Lagrangian<N>, const N: usize, F: Force<N>> NewtonSystem for ControlPointEquations<'_, L, N, F> {
    const LINEARISATION: &'static str = EULER_LAGRANGE_NEWTON_STEP;

    fn evaluate(&mut self) -> f64 {
        self.integrator.eval_hessians(self.t);
        self.integrator.residual_norm(self.mode, &self.p)
    }

    /// Right-hand side −R and Jacobian rows ν = row0.., columns μ = 1..=col_end.
    fn assemble(&mut self) {
        self.write_residual();
        self.integrator.fill_jacobian(self.mode);
    }

    fn linear_system(&mut self) -> (&mut DenseLu, &mut [f64]) {
        let dim = N * self.unknowns();
        let s = &mut *self.integrator;
        let lu = match self.mode {
            Mode::Step => &mut s.lu,
            Mode::BoundaryValue => &mut s.lu_bvp,
        };
        (lu, &mut s.delta[..dim])
    }

    fn scale(&self) -> f64 {
        let s = &*self.integrator;
        s.controls
            .iter()
            .fold(1.0_f64.max(s.base.amax()), |acc, z| acc.max(z.amax()))
    }

    fn trial_residual(&mut self, lambda: f64) -> f64 {
        let unknowns = self.unknowns();
        let s = &mut *self.integrator;
        s.trial.copy_from_slice(&s.controls);
        for cb in 0..unknowns {
            for a in 0..N {
                s.trial[cb + 1][a] += lambda * s.delta[cb * N + a];
            }
        }
        s.eval_gradient(self.t, true);
        s.residual_norm(self.mode, &self.p)
    }

    fn update(&mut self, lambda: f64) {
        let unknowns = self.unknowns();
        let s = &mut *self.integrator;
        for cb in 0..unknowns {
            for a in 0..N {
                s.controls[cb + 1][a] += lambda * s.delta[cb * N + a];
            }
        }
    }

    fn accept(&mut self) -> f64 {
        self.integrator.eval_gradient(self.t, false);
        self.integrator.residual_norm(self.mode, &self.p)
    }
}

impl<L: Lagrangian<N>, const N: usize> GalerkinIntegrator<L, N, NoForce> {
    /// Variational integrator for `lagrangian` with `scheme` and step `h > 0`.
    pub fn new(lagrangian: L, scheme: GalerkinScheme, h: f64) -> Result<Self> {
        Self::with_force(lagrangian, NoForce, scheme, h)
    }
}

impl<L: Lagrangian<N>, const N: usize, F: Force<N>> GalerkinIntegrator<L, N, F> {
    /// Forced variational integrator (discrete Lagrange–d'Alembert) for
    /// `lagrangian` with the generalised force `force`.
    pub fn with_force(lagrangian: L, force: F, scheme: GalerkinScheme, h: f64) -> Result<Self> {
        check_step(h)?;
        let m = scheme.intervals();
        let r = scheme.quadrature_len();
        let zero = SVector::<f64, N>::zeros();
        let empty_jet = Jet {
            value: 0.0,
            dq: zero,
            dv: zero,
        };
        let empty_hessian = Hessian {
            jet: empty_jet,
            qq: SMatrix::zeros(),
            qv: SMatrix::zeros(),
            vv: SMatrix::zeros(),
        };
        Ok(Self {
            lagrangian,
            force,
            stage_forces: vec![ForceJet::zero(); r],
            h,
            options: NewtonOptions::default(),
            base: zero,
            controls: vec![zero; m + 1],
            force_sum: zero,
            compensation: (zero, zero),
            trial: vec![zero; m + 1],
            delta: vec![0.0; N * m],
            gradient: vec![zero; m + 1],
            stage_jets: vec![empty_jet; r],
            stage_hessians: vec![empty_hessian; r],
            lu: DenseLu::new(N * m),
            lu_bvp: DenseLu::new(N * (m - 1)),
            jacobian_kept: false,
            bvp_jacobian_kept: false,
            last_jacobians: 0,
            start: vec![zero; m + 1],
            previous: None,
            previous_controls: vec![zero; m + 1],
            correction: ExtrapolationCorrection::new(m + 1),
            scheme,
        })
    }

    /// Replace the Newton options.
    pub fn with_options(mut self, options: NewtonOptions) -> Self {
        self.options = options;
        self
    }

    /// The Lagrangian.
    pub fn lagrangian(&self) -> &L {
        &self.lagrangian
    }
    /// The generalised force.
    pub fn force(&self) -> &F {
        &self.force
    }
    /// The discrete Lagrangian's description.
    pub fn scheme(&self) -> &GalerkinScheme {
        &self.scheme
    }
    /// Newton options in force.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    #[inline]
    fn stage_point(&self, i: usize, controls: &[SVector<f64, N>]) -> (SVector<f64, N>, SVector<f64, N>) {
        let mut x = self.base;
        let mut y = SVector::<f64, N>::zeros();
        for (nu, qn) in controls.iter().enumerate() {
            x += qn * self.scheme.value(i, nu);
            y += qn * self.scheme.derivative(i, nu);
        }
        (x, y / self.h)
    }

    /// Stage jets at `controls`, then `G_ν` into `self.gradient`; returns the action value.
    fn eval_gradient(&mut self, t: f64, use_trial: bool) -> f64 {
        let r = self.scheme.quadrature_len();
        let mut action = 0.0;
        for i in 0..r {
            let ctrl = if use_trial { &self.trial } else { &self.controls };
            let (x, y) = self.stage_point(i, ctrl);
            let ti = t + self.scheme.quadrature_nodes()[i] * self.h;
            self.stage_jets[i] = jet(&self.lagrangian, ti, &x, &y);
            if !self.force.is_zero() {
                self.stage_forces[i].value = force_value(&self.force, ti, &x, &y);
            }
            action += self.h * self.scheme.quadrature_weights()[i] * self.stage_jets[i].value;
        }
        self.assemble_gradient(false);
        action
    }

    fn assemble_gradient(&mut self, from_hessians: bool) {
        let m1 = self.scheme.intervals() + 1;
        let mut force_sum = SVector::<f64, N>::zeros();
        for i in 0..self.scheme.quadrature_len() {
            let j = if from_hessians {
                &self.stage_hessians[i].jet
            } else {
                &self.stage_jets[i]
            };
            force_sum += (j.dq + self.stage_forces[i].value) * (self.h * self.scheme.quadrature_weights()[i]);
        }
        self.force_sum = force_sum;
        for nu in 0..m1 {
            let mut g = SVector::<f64, N>::zeros();
            for i in 0..self.scheme.quadrature_len() {
                let w = self.h * self.scheme.quadrature_weights()[i];
                let j = if from_hessians {
                    &self.stage_hessians[i].jet
                } else {
                    &self.stage_jets[i]
                };
                g += (j.dq + self.stage_forces[i].value) * (w * self.scheme.value(i, nu))
                    + j.dv * (w * self.scheme.derivative(i, nu) / self.h);
            }
            self.gradient[nu] = g;
        }
    }

    /// Stage Hessians at `self.controls` (and `G_ν` from them).
    fn eval_hessians(&mut self, t: f64) {
        for i in 0..self.scheme.quadrature_len() {
            let (x, y) = self.stage_point(i, &self.controls);
            let ti = t + self.scheme.quadrature_nodes()[i] * self.h;
            self.stage_hessians[i] = hessian(&self.lagrangian, ti, &x, &y);
            if !self.force.is_zero() {
                self.stage_forces[i] = force_jet(&self.force, ti, &x, &y);
            }
        }
        self.assemble_gradient(true);
    }

    /// The Jacobian of `mode`'s equations (rows `ν = row0..`, columns
    /// `μ = 1..=unknowns`) from the stage Hessians, into its linear system.
    fn fill_jacobian(&mut self, mode: Mode) {
        let (row0, unknowns) = mode.layout(self.scheme.intervals());
        let dim = N * unknowns;
        for (rb, nu) in (row0..row0 + unknowns).enumerate() {
            for (cb, mu) in (1..=unknowns).enumerate() {
                let blk = self.action_hessian_block(nu, mu);
                let matrix = match mode {
                    Mode::Step => &mut self.lu.matrix,
                    Mode::BoundaryValue => &mut self.lu_bvp.matrix,
                };
                for a in 0..N {
                    for b in 0..N {
                        matrix[(rb * N + a) * dim + cb * N + b] = blk[(a, b)];
                    }
                }
            }
        }
    }

    /// Block `∂G_ν/∂Q^μ = ∂²S/∂Q^ν∂Q^μ` from the stage Hessians.
    fn action_hessian_block(&self, nu: usize, mu: usize) -> SMatrix<f64, N, N> {
        let mut b = SMatrix::<f64, N, N>::zeros();
        let hinv = 1.0 / self.h;
        for i in 0..self.scheme.quadrature_len() {
            let w = self.h * self.scheme.quadrature_weights()[i];
            let (mn, mm) = (self.scheme.value(i, nu), self.scheme.value(i, mu));
            let (dn, dm) = (
                self.scheme.derivative(i, nu) * hinv,
                self.scheme.derivative(i, mu) * hinv,
            );
            let hs = &self.stage_hessians[i];
            let fj = &self.stage_forces[i];
            b += (hs.qq + fj.dq) * (w * mn * mm)
                + (hs.qv + fj.dv) * (w * mn * dm)
                + hs.qv.transpose() * (w * dn * mm)
                + hs.vv * (w * dn * dm);
        }
        b
    }

    fn residual_norm(&self, mode: Mode, p: &SVector<f64, N>) -> f64 {
        let m = self.scheme.intervals();
        let mut r = 0.0_f64;
        match mode {
            Mode::Step => {
                r = r.max((self.gradient[0] + p).amax());
                for nu in 1..m {
                    r = r.max(self.gradient[nu].amax());
                }
            }
            Mode::BoundaryValue => {
                for nu in 1..m {
                    r = r.max(self.gradient[nu].amax());
                }
            }
        }
        r
    }

    /// Newton's method on the control points for `mode`; `p` is `p_k` in step mode.
    fn newton(&mut self, mode: Mode, t: f64, p: &SVector<f64, N>, step: usize) -> Result<NewtonReport> {
        if mode.layout(self.scheme.intervals()).1 == 0 {
            self.eval_gradient(t, false);
            return Ok(NewtonReport {
                iterations: 0,
                last_update: 0.0,
                residual: self.residual_norm(mode, p),
                stop: NewtonStop::Converged,
            });
        }
        let options = self.options;
        // One scalar unknown (N = 1, one interval): a Jacobian costs about
        // what a residual does, so keeping it saves nothing (measured: the
        // pendulum midpoint step 258 ns with Newton, 390 ns simplified).
        if mode == Mode::Step && N * self.scheme.intervals() > 1 {
            // Simplified Newton with the Jacobian kept across steps; from the
            // same start, Newton with line search if it fails.
            self.start.copy_from_slice(&self.controls);
            let mut equations = ControlPointEquations {
                integrator: &mut *self,
                mode,
                t,
                p: *p,
            };
            if let Ok((report, jacobians)) = solve_simplified_newton(&mut equations, &options, step, t) {
                self.last_jacobians = jacobians;
                return Ok(report);
            }
            self.controls.copy_from_slice(&self.start);
        }
        let mut equations = ControlPointEquations {
            integrator: &mut *self,
            mode,
            t,
            p: *p,
        };
        let report = solve_newton(&mut equations, &options, LineSearch::Backtracking, step, t);
        // Newton overwrote the factors with those of its last iterate: keep them.
        match mode {
            Mode::Step => self.jacobian_kept = report.is_ok(),
            Mode::BoundaryValue => self.bvp_jacobian_kept = false,
        }
        if let Ok(r) = &report {
            self.last_jacobians = r.iterations;
        }
        report
    }

    /// Initial guess for a step from `(t, q, p)`: extrapolate the previous
    /// step's curve when this step continues it, corrected by the last
    /// steps' extrapolation errors ([`ExtrapolationCorrection`]); else a
    /// straight line with the velocity of the continuous inverse Legendre map.
    fn predict(&mut self, t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) {
        let m = self.scheme.intervals();
        self.base = *q;
        if self.continues(t, q) {
            // Q^ν = Σ_μ l_μ(1 + d_ν) Q^μ_prev and q = Q^m_prev, in increments.
            let last = self.previous_controls[m];
            for nu in 0..=m {
                let mut z = -last;
                for mu in 0..=m {
                    z += self.previous_controls[mu] * self.scheme.extrapolation(nu, mu);
                }
                self.controls[nu] = z;
            }
            self.controls[0] = SVector::zeros();
            self.correction.correct(&mut self.controls);
            return;
        }
        self.compensation = (SVector::zeros(), SVector::zeros());
        self.correction.reset();
        // A new trajectory: no Jacobian kept from another one.
        self.jacobian_kept = false;
        let v = velocity_from_momentum(&self.lagrangian, t, q, p).unwrap_or_else(|_| SVector::zeros());
        for nu in 0..=m {
            self.controls[nu] = v * (self.scheme.control_nodes()[nu] * self.h);
        }
    }

    /// Whether a step from `(t, q)` continues the previous step exactly.
    fn continues(&self, t: f64, q: &SVector<f64, N>) -> bool {
        matches!(self.previous, Some((t_end, q_end)) if continues(t_end, &q_end, t, q))
    }

    /// One step with its Newton report.
    pub fn step_report(&mut self, index: usize, state: &PhaseState<N>) -> Result<(PhaseState<N>, NewtonReport)> {
        state.check()?;
        let (t, q, p) = (state.t, state.q, state.p);
        self.predict(t, &q, &p);
        let m = self.scheme.intervals();
        let predicted = self.controls[m];
        let report = self
            .newton(Mode::Step, t, &p, index)
            .inspect_err(|_| self.previous = None)?;
        // A continuing step's prediction is off by a high power of h. A
        // correction larger than both |q_k| and the predicted increment means
        // Newton found another root of the step equations (they have several
        // when h is far beyond the dynamics' time scale, as past a blow-up):
        // not a continuation of the trajectory.
        let correction = (self.controls[m] - predicted).amax();
        if self.correction.is_active() && correction > q.amax().max(predicted.amax()) {
            self.previous = None;
            return Err(Error::NewtonFailure {
                step: index,
                t,
                residual: report.residual,
                iterations: report.iterations,
                reason: format!(
                    "the step left the solutions continuing the trajectory (its Newton correction {correction:.3e} \
                     exceeds |q| and the predicted increment): the step is too large for the dynamics here"
                ),
            });
        }
        // q_{k+1} = q_k + Zᵐ and p_{k+1} = G_m = p_k + h Σᵢ bᵢ ∂L/∂q(i) (since Σ_ν G_ν =
        // h Σᵢ bᵢ ∂L/∂q(i) and the other G_ν vanish), summed with compensation.
        let (q_next, cq) = kahan_add(&q, &self.controls[m], &self.compensation.0);
        let (p_next, cp) = kahan_add(&p, &self.force_sum, &self.compensation.1);
        self.compensation = (cq, cp);
        let next = PhaseState::new(t + self.h, q_next, p_next);
        if next.check().is_err() {
            self.previous = None;
            return Err(Error::NonFiniteState {
                step: index,
                t,
                what: "(q, p)".into(),
            });
        }
        self.previous = Some((next.t, next.q));
        self.previous_controls.copy_from_slice(&self.controls);
        self.correction.remember(&self.controls);
        Ok((next, report))
    }

    /// The discrete Lagrangian `L_d(q₀, q₁)` on `[t, t + h]` with its discrete
    /// Legendre transforms, solving for the interior control points.
    pub fn discrete_lagrangian(
        &mut self,
        t: f64,
        q0: &SVector<f64, N>,
        q1: &SVector<f64, N>,
    ) -> Result<DiscreteLagrangianValue<N>> {
        check_finite("q0", q0.iter())?;
        check_finite("q1", q1.iter())?;
        let m = self.scheme.intervals();
        self.base = *q0;
        let dq = q1 - q0;
        for nu in 0..=m {
            self.controls[nu] = dq * self.scheme.control_nodes()[nu];
        }
        self.previous = None;
        self.newton(Mode::BoundaryValue, t, &SVector::zeros(), 0)?;
        let value = self.eval_gradient(t, false);
        Ok(DiscreteLagrangianValue {
            value,
            minus: -self.gradient[0],
            plus: self.gradient[m],
        })
    }

    /// Two-step form of the discrete Euler–Lagrange equations
    /// `D₂L_d(q_{k−1}, q_k) + D₁L_d(q_k, q_{k+1}) = 0`: returns `q_{k+1}` given
    /// `q_{k−1}` at time `t − h` and `q_k` at time `t`.
    pub fn step_two_point(&mut self, t: f64, q_prev: &SVector<f64, N>, q: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        let p = self.discrete_lagrangian(t - self.h, q_prev, q)?.plus;
        Ok(self.step_report(0, &PhaseState::new(t, *q, p))?.0.q)
    }

    /// Discrete work of the forces over the last step, `h Σᵢ bᵢ F(i)·Yᵢ`, at
    /// the converged stage values (zero without forces).
    pub fn last_work(&self) -> f64 {
        if self.force.is_zero() {
            return 0.0;
        }
        (0..self.scheme.quadrature_len())
            .map(|i| {
                let (_, y) = self.stage_point(i, &self.controls);
                self.h * self.scheme.quadrature_weights()[i] * self.stage_forces[i].value.dot(&y)
            })
            .sum()
    }

    /// Whether this is the midpoint/trapezoid/α family (no interior control points).
    pub fn is_two_point(&self) -> bool {
        matches!(
            self.scheme.method(),
            Method::Midpoint | Method::Trapezoid | Method::Alpha(_)
        )
    }
}

impl<L: Lagrangian<N>, const N: usize, F: Force<N>> OneStepMap<N> for GalerkinIntegrator<L, N, F> {
    fn step_size(&self) -> f64 {
        self.h
    }
    /// The end `(t, q)` of the last step and its control points (the
    /// predictor of the next step), and the Kahan compensation terms.
    fn save_carry(&self, out: &mut Vec<f64>) {
        save_step_end(out, self.previous);
        out.extend(self.previous_controls.iter().flat_map(|z| z.iter()));
        out.extend(self.compensation.0.iter().chain(self.compensation.1.iter()));
        // The kept Jacobian's factors, behind a tag (absent from checkpoints
        // of earlier versions: then none is kept).
        out.push(JACOBIAN_CARRY_TAG);
        out.push(f64::from(u8::from(self.jacobian_kept)));
        if self.jacobian_kept {
            self.lu.save_factors(out);
        }
        self.correction.save(out);
    }
    fn restore_carry(&mut self, words: &mut crate::run::Words<'_>) -> Result<()> {
        self.previous = restore_step_end(words)?;
        for z in self.previous_controls.iter_mut() {
            *z = SVector::from_column_slice(words.take(N)?);
        }
        self.compensation = (
            SVector::from_column_slice(words.take(N)?),
            SVector::from_column_slice(words.take(N)?),
        );
        self.jacobian_kept = false;
        if words.take_tag(JACOBIAN_CARRY_TAG) {
            self.jacobian_kept = words.flag()?;
            if self.jacobian_kept {
                self.lu.restore_factors(words)?;
            }
        }
        self.correction.restore(words)?;
        Ok(())
    }
    fn step(&mut self, index: usize, state: &PhaseState<N>) -> Result<(PhaseState<N>, StepStats)> {
        let (next, report) = self.step_report(index, state)?;
        Ok((
            next,
            StepStats {
                max_relative_residual: 0.0,
                iterations: report.iterations,
                fallback: false,
                work: self.last_work(),
                jacobians: self.last_jacobians,
                force_evaluations: 0,
            },
        ))
    }
}

/// Kahan-compensated `x + dx`: returns the new sum and compensation.
#[inline]
pub(crate) fn kahan_add<const N: usize>(
    x: &SVector<f64, N>,
    dx: &SVector<f64, N>,
    compensation: &SVector<f64, N>,
) -> (SVector<f64, N>, SVector<f64, N>) {
    let y = dx - compensation;
    let sum = x + y;
    (sum, (sum - x) - y)
}
