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
//! Solving: simplified Newton in the unknowns `(v̄, u)`, `q_{k+1} = q_k + h v̄`,
//! `h = √u`. A step that continues the last
//! one starts from the step extrapolated from the last two and the position
//! interpolated through the last three points (module `predictor`), brought
//! onto the momentum equation by a few gradient passes with the momentum
//! block `h ∂²S/∂q₀∂q₁ = −M + O(h²)` kept along the run (Broyden-corrected);
//! only the rest of the exact Jacobian is evaluated there (three small
//! passes, or closed forms in `V` for `L = ½ vᵀMv − V`, see
//! [`SemAction`]). The Jacobian is kept in bordered form and solved by
//! block elimination through the momentum block (module `bordered`). A Jacobian from the previous step does not do: the `h`-direction
//! of the step equations is a cancellation of `O(1/h)` entries, which it gets
//! wrong by `O(1)`. A step that does not continue (the first step, a
//! restart), or whose first start fails, solves the momentum equation at
//! `h_{k−1}` by exact Newton and evaluates the whole Jacobian there. The
//! Jacobian is evaluated afresh whenever an update shrinks by less than half.
//! The iteration stops when the update is `4ε` relative in `q` and `h`, or
//! the last two contraction factors bound what remains below that, or both
//! residuals are at round-off (a few ε of the terms they are made of: the
//! energy equation is ill-conditioned, `∂E_d/∂h ≈ 2c·h`, note 001 §3.4, so
//! `h` itself may not get to `4ε`). If both starts fail or land outside
//! `[α, β]·h_{k−1}`, the scalar reduction `f(h) = E⁻(q_k, q_{k+1}(h), h) − E_k`
//! (inner Newton for `q_{k+1}(h)`) is scanned on a geometric grid in
//! `[α, β]·h_{k−1}` and the sign change nearest `h_{k−1}` is refined by
//! regula falsi. A step `h ≤ 0` is never returned (the symmetric rules always
//! admit the backward root `h = −h_{k−1}`).

use nalgebra::{SMatrix, SVector};
use num_dual::Dual2SVec64;

use super::action::SemAction;
use super::bordered::BorderedLu;
use super::predictor::StepHistory;
use crate::ad::lift;
use crate::error::{Error, Result, check_finite, check_step};
use crate::mechanics::{Lagrangian, velocity_from_momentum};
use crate::solve::dense::solve_small;
use crate::solve::{DenseLu, NewtonOptions};

mod bracket;
mod expansion;

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

impl<const N: usize> SemState<N> {
    /// The state a run starts from: `(t₀, q₀, p₀)` with first step `h₀`, its
    /// energy not yet set (the first step sets it).
    pub fn first(t0: f64, q0: SVector<f64, N>, p0: SVector<f64, N>, h0: f64) -> Self {
        Self {
            t: t0,
            q: q0,
            p: p0,
            energy: f64::NAN,
            h: h0,
        }
    }
}

/// What a step reports.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SemStepInfo {
    /// The step taken.
    pub h: f64,
    /// Newton (or bracket) iterations: residual evaluations of the step equations.
    pub iterations: usize,
    /// Exact step Jacobians evaluated in full.
    pub jacobian_refreshes: usize,
    /// Exact step Jacobians updated only in the parts that move along a run
    /// (the momentum block kept).
    pub jacobian_updates: usize,
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
    /// Factors of the Jacobian of the step equations in `(v̄, u)`.
    jacobian: Option<BorderedLu<N>>,
    /// The momentum rows' `v̄` block of the step Jacobian, `h ∂²S/∂q₀∂q₁`,
    /// kept along a run (and corrected by secants), if one was evaluated.
    momentum_block: Option<SMatrix<f64, N, N>>,
    /// The last points of the run: the predictor when the next step continues it.
    history: StepHistory<N>,
}

/// Which parts of the step Jacobian a solve evaluates first.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refresh {
    /// All of it.
    Full,
    /// The parts that move along a run ([`SemAction::step_jacobian_along`]);
    /// the momentum block kept.
    Along,
}

/// What a step spent.
#[derive(Debug, Clone, Copy, Default)]
struct StepCount {
    /// Evaluations of a residual of the step equations.
    residuals: usize,
    /// Full Jacobians.
    full: usize,
    /// Partial Jacobians.
    along: usize,
}

/// Contraction factor `‖Δ_k‖/‖Δ_{k−1}‖` of the simplified Newton iteration
/// above which the kept Jacobian is evaluated afresh.
const REFRESH_RATIO: f64 = 0.5;

/// Relative size of the update at which the momentum-equation projection of
/// the start stops (the joint iteration finishes the job).
const PROJECTION_TOL: f64 = 1e-10;

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
    /// See [`SemIntegrator::start_expansion`].
    fn start_expansion(
        &self,
        t0: f64,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        h0: f64,
    ) -> Result<super::StartExpansion>;
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
    fn start_expansion(
        &self,
        t0: f64,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        h0: f64,
    ) -> Result<super::StartExpansion> {
        SemIntegrator::start_expansion(self, t0, q0, p0, h0)
    }
    fn save_carry(&self, out: &mut Vec<f64>) {
        self.history.save(out);
        crate::run::save_option(out, self.momentum_block.as_ref().map(|m| m.as_slice()), N * N);
    }
    fn restore_carry(&mut self, words: &mut crate::run::Words<'_>) -> Result<()> {
        self.history.restore(words)?;
        self.momentum_block = crate::run::restore_option(words, N * N)?.map(SMatrix::from_column_slice);
        Ok(())
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
            jacobian: None,
            momentum_block: None,
            history: StepHistory::default(),
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

    /// Take the last (up to three) states of an earlier run as the history
    /// the next step's starting values are interpolated from, as if this
    /// integrator had computed them; the next step must start from the last of
    /// them. A stored trajectory resumed this way takes the continuing start
    /// (with the momentum block evaluated afresh if this integrator holds
    /// none); to resume bit for bit, use the checkpoint carry instead.
    pub fn seed_history(&mut self, states: &[SemState<N>]) {
        self.history.clear();
        for s in states.iter().rev().take(3).rev() {
            self.history.push(s.t, s.q);
        }
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
        let (p1, e1) = self.action.arrival(state.t, &state.q, &q1, h);
        Ok((
            SemState {
                t: state.t + h,
                q: q1,
                p: p1,
                energy: e1,
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
        let s0 = SemState::first(t0, q0, p0, h0);
        let (s1, _) = self.fixed_step(&s0, h0)?;
        let (_, _, e_minus) = self.action.leaving(t0, &q0, &s1.q, h0);
        Ok((SemState { energy: e_minus, ..s0 }, s1))
    }

    /// Evaluate the exact Jacobian of the step equations at `(q₁, h)` in the
    /// unknowns `(v̄, u)` (see [`Self::newton_full`]) and factor it; with
    /// [`Refresh::Along`] and a kept momentum block, only the parts that move
    /// along a run. `None` if it is singular.
    ///
    /// Rows: `R₁ = p + S_{q₀}` and `R₂ = E⁻ − E = S_{t₀} − S_h − E`; columns:
    /// `∂/∂v̄ = h ∂/∂q₁` and `∂/∂u = ∂/∂w / (2h)` with `w = (δq₁, δh) = (v̄, 1)`.
    fn refresh_jacobian(
        &mut self,
        s: &SemState<N>,
        q1: &SVector<f64, N>,
        h: f64,
        what: Refresh,
        count: &mut StepCount,
    ) -> Option<()> {
        let block = match (what, self.momentum_block) {
            (Refresh::Along, Some(block)) => {
                count.along += 1;
                block
            }
            _ => {
                count.full += 1;
                self.action.momentum_block(s.t, &s.q, q1, h)
            }
        };
        self.momentum_block = Some(block);
        let (momentum_w, energy_q1, energy_w) = self.action.step_jacobian_along(s.t, &s.q, q1, h);
        self.jacobian = BorderedLu::factor(
            &block,
            &(momentum_w / (2.0 * h)),
            &(energy_q1 * h),
            energy_w / (2.0 * h),
        );
        self.jacobian.map(|_| ())
    }

    /// Bring a guess `q₁` near the momentum equation `p + ∂S/∂q₀ = 0` at fixed
    /// `h`: simplified Newton in `v̄` with the kept momentum block
    /// `h ∂²S/∂q₀∂q₁ = −M + O(h²)`, which changes little from step to step,
    /// corrected by Broyden's update from each secant; gradient passes only,
    /// stopped at [`PROJECTION_TOL`]. Without a kept block the guess is
    /// returned. Residual evaluations are added to `count`.
    fn project_on_momentum(
        &mut self,
        s: &SemState<N>,
        mut q1: SVector<f64, N>,
        h: f64,
        count: &mut usize,
    ) -> SVector<f64, N> {
        let Some(mut block) = self.momentum_block else {
            return q1;
        };
        let mut previous: Option<(SVector<f64, N>, SVector<f64, N>)> = None;
        for _ in 0..4 {
            *count += 1;
            let r1 = s.p + self.action.leaving_momentum(s.t, &s.q, &q1, h);
            if let Some((r_old, step)) = previous {
                // Broyden's update: the least change of the block with J Δv̄ = Δr₁.
                let denom = step.norm_squared();
                if denom > 0.0 {
                    block += (r1 - r_old - block * step) * step.transpose() / denom;
                }
            }
            let (dv, pivot) = solve_small(&block, &r1);
            if pivot == 0.0 || dv.iter().any(|x| !x.is_finite()) {
                break;
            }
            q1 -= dv * h;
            previous = Some((r1, -dv));
            if (dv * h).amax() <= PROJECTION_TOL * q1.amax().max(1.0) {
                break;
            }
        }
        self.momentum_block = Some(block);
        q1
    }

    /// Simplified Newton from a guess `(q₁, h)` in the unknowns `(v̄, u)`,
    /// `q₁ = q₀ + √u·v̄`, `h = √u`, with the Jacobian evaluated first as
    /// `first` says and afresh whenever an update shrinks by less than
    /// [`REFRESH_RATIO`]; `None` if it fails. Residual evaluations and
    /// Jacobians are added to `count`.
    ///
    /// In `(q₁, h)` the energy residual is strongly curved in `h` (it vanishes
    /// at the forward root and near the backward root `h ≈ −h_{k−1}`, so a
    /// Jacobian from a start at relative distance `δ` contracts only by `≈ δ`);
    /// in `u = h²` it is nearly linear, which makes the first update from a
    /// fresh Jacobian about 30 times more accurate (measured on Kepler,
    /// contraction 1.2e-4 against 3.6e-3), and `h = √u > 0` holds throughout.
    fn newton_full(
        &mut self,
        s: &SemState<N>,
        mut q1: SVector<f64, N>,
        mut h: f64,
        first: Refresh,
        count: &mut StepCount,
    ) -> Option<(SVector<f64, N>, f64)> {
        let opts = self.options.newton;
        self.refresh_jacobian(s, &q1, h, first, count)?;
        let (mut last, mut last_ratio) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..opts.max_iterations {
            count.residuals += 1;
            let (action, s_q0, e_minus) = self.action.leaving(s.t, &s.q, &q1, h);
            let (r1, r2) = (s.p + s_q0, e_minus - s.energy);
            let (dv, du) = self.jacobian?.solve(&-r1, -r2);
            if dv.iter().any(|x| !x.is_finite()) || !du.is_finite() {
                return None;
            }
            // The update is in (v̄, u): q₁ = q₀ + h v̄, h = √u (u ≤ 0 fails).
            let vbar = (q1 - s.q) / h + dv;
            let u = h * h + du;
            if u.is_nan() || u <= 0.0 {
                return None;
            }
            let (h_old, h_new) = (h, u.sqrt());
            let q_new = s.q + vbar * h_new;
            let (dq, dh) = (q_new - q1, h_new - h);
            q1 = q_new;
            h = h_new;
            // The update against its round-off size (1 = at round-off): `tol`
            // relative in q₁ and in h.
            let scale_q = opts.tol * q1.amax().max(1.0);
            let scale_h = opts.tol * h;
            let size = (dq.amax() / scale_q).max(dh.abs() / scale_h);
            // The contraction factor, infinite until two updates are known.
            let ratio = if last.is_finite() { size / last } else { f64::INFINITY };
            let theta = ratio.max(last_ratio);
            // A stall is told from slow contraction by the residual: at the
            // noise floor both residuals are a few ε of the terms they are
            // made of (momenta; energies, bounded by max(|E|, |𝕃|) = |T| + |V|
            // for T ≥ 0).
            let energy_terms = s.energy.abs().max(e_minus.abs()).max((action / h_old).abs());
            let at_round_off = r1.amax() <= 16.0 * f64::EPSILON * (s.p.amax() + s_q0.amax())
                && r2.abs() <= 16.0 * f64::EPSILON * energy_terms;
            // Converged: the update is at round-off; or the last two
            // contraction factors are at most θ < ½ and the θ/(1 − θ) of the
            // update they leave is below round-off; or the update stopped
            // shrinking at a small size: the noise floor of the
            // ill-conditioned h-equation.
            let converged = size <= 1.0 || at_round_off || (theta < 0.5 && theta / (1.0 - theta) * size <= 1.0);
            if converged {
                return Some((q1, h));
            }
            if last.is_finite() && ratio > REFRESH_RATIO {
                self.refresh_jacobian(s, &q1, h, Refresh::Full, count)?;
                // Contraction is measured afresh with the new Jacobian.
                (last, last_ratio) = (f64::INFINITY, f64::INFINITY);
            } else {
                (last, last_ratio) = (size, ratio);
            }
        }
        None
    }

    /// One fixed-energy step.
    pub fn step(&mut self, index: usize, s: &SemState<N>) -> Result<(SemState<N>, SemStepInfo)> {
        check_finite("q", s.q.iter())?;
        check_finite("p", s.p.iter())?;
        check_finite("energy", [s.energy].iter())?;
        check_step(s.h)?;
        let (alpha, beta) = self.options.bracket;
        let in_bracket = |h: f64| h >= alpha * s.h && h <= beta * s.h;
        let mut count = StepCount::default();
        let continuing = self.history.continues(s.t, &s.q);
        if !continuing {
            // A new trajectory: nothing kept from another one.
            self.history.clear();
            self.history.push(s.t, s.q);
            self.momentum_block = None;
        }
        // First start, continuing a run: the step extrapolated from the last
        // steps and the position interpolated through the last points,
        // brought onto the momentum equation with the kept momentum block;
        // the rest of the Jacobian evaluated there.
        let mut newton = None;
        if let (true, Some(h0)) = (continuing, self.history.step()) {
            let guess = self.history.position(h0).unwrap_or(s.q);
            let start = self.project_on_momentum(s, guess, h0, &mut count.residuals);
            newton = self
                .newton_full(s, start, h0, Refresh::Along, &mut count)
                .filter(|(_, h)| in_bracket(*h));
        }
        let v = match self.history.velocity() {
            Some(v) => v,
            None => self.velocity(s),
        };
        // Second start (the only one on a new trajectory): solve the
        // well-conditioned momentum equation at h = h_{k−1} first, from the
        // velocity of the interpolation through the last points, so that the
        // joint Newton starts next to the forward root and not between it and
        // the backward root h = −h_{k−1}; the whole Jacobian evaluated there.
        if newton.is_none() {
            newton = self
                .solve_position(s.t, &s.q, &s.p, s.h, s.q + v * s.h)
                .and_then(|(q1, it0)| {
                    count.residuals += it0;
                    self.newton_full(s, q1, s.h, Refresh::Full, &mut count)
                })
                .filter(|(_, h)| in_bracket(*h));
        }
        let solved = match newton {
            Some((q1, h)) => Ok((q1, h, 0)),
            None => {
                self.momentum_block = None;
                self.bracketed(index, s, v)
            }
        };
        match solved {
            Ok((q1, h, scan_evaluations)) => {
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
                self.history.push(next.t, q1);
                Ok((
                    next,
                    SemStepInfo {
                        h,
                        iterations: count.residuals + scan_evaluations,
                        jacobian_refreshes: count.full,
                        jacobian_updates: count.along,
                        fallback: false,
                    },
                ))
            }
            Err(e) if self.options.fallback => {
                let (next, it) = self.fixed_step(s, s.h).map_err(|_| e)?;
                self.history.clear();
                Ok((
                    next,
                    SemStepInfo {
                        h: s.h,
                        iterations: count.residuals + it,
                        jacobian_refreshes: count.full,
                        jacobian_updates: count.along,
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
