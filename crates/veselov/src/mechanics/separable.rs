//! Separable Lagrangians `L = ½ vᵀMv − V(t, q)` and their fast integrator.
//!
//! For separable `L` the Galerkin integrators reduce to the partitioned
//! Runge–Kutta method (a, ā, b, c) of their tableau (Marsden & West 2001,
//! Thm 2.6.1; seed 004 §4.3) applied to `q̈ = f(t, q) = −M⁻¹∇V(t, q)`:
//!
//! `Zᵢ = h cᵢ v_k + h² Σⱼ (AĀ)ᵢⱼ f(t_k + cⱼh, q_k + Zⱼ)`,
//! `q_{k+1} = q_k + h v_k + h² Σⱼ (bᵀĀ)ⱼ fⱼ`, `v_{k+1} = v_k + h Σⱼ bⱼ fⱼ`,
//! with `v = M⁻¹p` and `p_{k+1} = p_k − h Σⱼ bⱼ ∇V(Qⱼ)`. The stage equations are solved by fixed-point iteration
//! (only `∇V` is needed, one forward-mode pass per stage). The start: the
//! stage forces of the last two steps extrapolated by their interpolation
//! polynomial (degree `2s − 1`; the last step's alone, degree `s − 1`, when
//! the two-step extrapolation would amplify round-off by more than 1e5, as
//! for Gauss s ≥ 5, or after a restart), plus the last step's prediction
//! error (converged − predicted forces), which changes slowly along a run:
//! the stage error of the collocation solution, `O(h^{s+1})`, is a smooth
//! function of the state that no extrapolation of stage values removes. A
//! sweep evaluates the forces at the current increments `z` and recomputes
//! `z' = Z(f(z))`; it stops when `‖z' − z‖ ≤ 0.03 ε max(‖q‖, 1)` (so the forces
//! used belong to increments that solve the stage equations below round-off)
//! or when the update stops shrinking at a small size. Kepler e = 0.6 at
//! h = 2π/1000 takes 4.3, 5.4 and 7.0 ∇V evaluations per step for Gauss
//! s = 2, 4, 6 (`tests/mechanics/separable_start.rs`). If the iteration fails to
//! contract, the step falls back to the exact-Newton [`GalerkinIntegrator`]
//! and the step is flagged.

use nalgebra::{SMatrix, SVector};

use super::force::{Force, NoForce};
use super::galerkin::{GalerkinIntegrator, kahan_add};
use super::lagrangian::{Lagrangian, potential_gradient};
use super::scheme::{GalerkinScheme, MAX_STAGES};
use super::state::{OneStepMap, PhaseState, StepStats, continues, restore_step_end, save_step_end};
use crate::ad::Scalar;
use crate::error::{Error, Result};

/// Largest amplification `maxᵢ Σₘ |wᵢₘ|` of the two-step force predictor:
/// beyond it the round-off of the stored forces, amplified, costs more
/// sweeps than the higher degree saves (measured: Gauss s = 6, 3.8e7,
/// needs 1.8 sweeps against 1.1 with the one-step predictor; s = 4, 3.3e4,
/// 1.25 against 1.7).
const MAX_TWO_STEP_AMPLIFICATION: f64 = 1e5;

/// The fixed-point sweeps stop when the stage increments `zᵢ` recomputed
/// from the forces at the current ones move by at most this many units of
/// round-off of `max(‖q‖∞, 1)`: the forces then belong to stage values
/// that solve the stage equations to 3 % of an ulp of `q` (a posteriori:
/// `‖z − z*‖ ≤ ‖Δz‖/(1 − ρ)` for contraction `ρ`). A looser rule (2 ulps,
/// tried) lets a smooth predictor error of that size through every step;
/// it adds up coherently (Kepler e = 0.6, Gauss s = 4, 10⁶ steps: median
/// final error 5.6e-10 and angular-momentum drift 3.4e-14, against 1.1e-10
/// and 1.4e-15 with this rule).
const STAGE_TOLERANCE: f64 = 0.03;

/// Marks the predictor's part of the checkpoint carry (never a flag word).
const PREDICTOR_CARRY_TAG: f64 = -2.0;

/// A potential `V(t, q)`, generic over the AD scalar.
pub trait Potential<const N: usize> {
    /// `V(t, q)`.
    fn potential<D: Scalar>(&self, t: D, q: &SVector<D, N>) -> D;
}

/// `L = ½ vᵀ M v − V(t, q)` with a constant symmetric positive definite mass matrix `M`.
#[derive(Debug, Clone, PartialEq)]
pub struct SeparableLagrangian<V, const N: usize> {
    mass: SMatrix<f64, N, N>,
    mass_inverse: SMatrix<f64, N, N>,
    potential: V,
}

impl<V: Potential<N>, const N: usize> SeparableLagrangian<V, N> {
    /// Build from a mass matrix and a potential; `M` must be symmetric
    /// positive definite with a finite inverse.
    pub fn new(mass: SMatrix<f64, N, N>, potential: V) -> Result<Self> {
        let bad = || Error::InvalidParameter {
            name: "mass".into(),
            value: format!("{:?}", mass.as_slice()),
            reason: "mass matrix must be finite, symmetric and positive definite".into(),
        };
        if mass.iter().any(|x| !x.is_finite()) || (mass - mass.transpose()).amax() > 1e-14 * mass.amax() {
            return Err(bad());
        }
        let chol = mass.cholesky().ok_or_else(bad)?;
        // A subnormal pivot passes the factorisation and overflows here.
        let mass_inverse = chol.inverse();
        if mass_inverse.iter().any(|x| !x.is_finite()) {
            return Err(bad());
        }
        Ok(Self {
            mass,
            mass_inverse,
            potential,
        })
    }
    /// Unit mass matrix.
    pub fn unit_mass(potential: V) -> Self {
        Self {
            mass: SMatrix::identity(),
            mass_inverse: SMatrix::identity(),
            potential,
        }
    }
    /// The mass matrix `M`.
    pub fn mass(&self) -> &SMatrix<f64, N, N> {
        &self.mass
    }
    /// `M⁻¹`.
    pub fn mass_inverse(&self) -> &SMatrix<f64, N, N> {
        &self.mass_inverse
    }
    /// The potential.
    pub fn potential(&self) -> &V {
        &self.potential
    }
    /// The generalised force `−∇V(t, q)`, exact (one forward-mode pass).
    #[inline]
    pub fn conservative_force(&self, t: f64, q: &SVector<f64, N>) -> SVector<f64, N> {
        -potential_gradient(self, t, q).1
    }
}

impl<V: Potential<N>, const N: usize> Lagrangian<N> for SeparableLagrangian<V, N> {
    #[inline]
    fn lagrangian<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        let m: SMatrix<D, N, N> = self.mass.map(D::from);
        (m * v).dot(v) * 0.5 - self.potential.potential(t, q)
    }
    fn constant_mass(&self) -> Option<SMatrix<f64, N, N>> {
        Some(self.mass)
    }
    #[inline]
    fn potential_energy<D: Scalar>(&self, t: D, q: &SVector<D, N>) -> D {
        self.potential.potential(t, q)
    }
}

/// Fast integrator for separable Lagrangians (fixed-point stage iteration with
/// Newton fallback). Produces the same trajectory as [`GalerkinIntegrator`] up
/// to round-off.
#[derive(Debug, Clone)]
pub struct SeparableIntegrator<V, const N: usize, F = NoForce> {
    general: GalerkinIntegrator<SeparableLagrangian<V, N>, N, F>,
    /// `h aᵢⱼ` and `h āᵢⱼ` (forced iteration on stage velocities).
    ha: [[f64; MAX_STAGES]; MAX_STAGES],
    ha_bar: [[f64; MAX_STAGES]; MAX_STAGES],
    last_work: f64,
    h: f64,
    s: usize,
    c: [f64; MAX_STAGES],
    b: [f64; MAX_STAGES],
    /// `h² (AĀ)ᵢⱼ`.
    aab: [[f64; MAX_STAGES]; MAX_STAGES],
    /// `h² (bᵀĀ)ⱼ`.
    bab: [f64; MAX_STAGES],
    extrap: [[f64; MAX_STAGES]; MAX_STAGES],
    /// Two-step predictor: `extrap_two[i][m]` weights the `m`-th distinct
    /// node of the last two steps (`two_nodes[m]` = (steps back − 1, stage)).
    extrap_two: [[f64; 2 * MAX_STAGES]; MAX_STAGES],
    two_nodes: [(usize, usize); 2 * MAX_STAGES],
    n_two: usize,
    forces: [SVector<f64, N>; MAX_STAGES],
    /// Stage forces of the step before the last.
    older_forces: [SVector<f64, N>; MAX_STAGES],
    /// Consecutive earlier steps whose forces are held (0, 1 or 2).
    depth: usize,
    /// This step's prediction before correction, and the last step's
    /// prediction error (converged − predicted) with the predictor it came from.
    /// (Kinds: 1 = one-step, 2 = two-step predictor; an error of kind 0 is none.)
    prediction: ([SVector<f64, N>; MAX_STAGES], usize),
    prediction_error: ([SVector<f64, N>; MAX_STAGES], usize),
    previous: Option<(f64, SVector<f64, N>)>,
    compensation: (SVector<f64, N>, SVector<f64, N>),
    max_iterations: usize,
}

impl<V: Potential<N>, const N: usize> SeparableIntegrator<V, N, NoForce> {
    /// Integrator for `system` with `scheme` and step `h > 0`.
    pub fn new(system: SeparableLagrangian<V, N>, scheme: GalerkinScheme, h: f64) -> Result<Self> {
        Self::with_force(system, NoForce, scheme, h)
    }
}

impl<V: Potential<N>, const N: usize, F: Force<N>> SeparableIntegrator<V, N, F> {
    /// Forced integrator (discrete Lagrange–d'Alembert) for `system` with `force`.
    pub fn with_force(system: SeparableLagrangian<V, N>, force: F, scheme: GalerkinScheme, h: f64) -> Result<Self> {
        let tab = scheme.tableau().clone();
        let s = tab.s;
        let mut out = Self {
            h,
            s,
            c: [0.0; MAX_STAGES],
            b: [0.0; MAX_STAGES],
            aab: [[0.0; MAX_STAGES]; MAX_STAGES],
            bab: [0.0; MAX_STAGES],
            extrap: [[0.0; MAX_STAGES]; MAX_STAGES],
            forces: [SVector::zeros(); MAX_STAGES],
            older_forces: [SVector::zeros(); MAX_STAGES],
            depth: 0,
            prediction: ([SVector::zeros(); MAX_STAGES], 0),
            prediction_error: ([SVector::zeros(); MAX_STAGES], 0),
            extrap_two: [[0.0; 2 * MAX_STAGES]; MAX_STAGES],
            two_nodes: [(0, 0); 2 * MAX_STAGES],
            n_two: 0,
            previous: None,
            compensation: (SVector::zeros(), SVector::zeros()),
            max_iterations: 100,
            ha: [[0.0; MAX_STAGES]; MAX_STAGES],
            ha_bar: [[0.0; MAX_STAGES]; MAX_STAGES],
            last_work: 0.0,
            general: GalerkinIntegrator::with_force(system, force, scheme, h)?,
        };
        for i in 0..s {
            out.c[i] = tab.c[i];
            out.b[i] = tab.b[i];
            for j in 0..s {
                out.aab[i][j] = h * h * (0..s).map(|k| tab.a(i, k) * tab.a_bar(k, j)).sum::<f64>();
                out.extrap[i][j] = out.general.scheme().stage_extrapolation(i, j);
                out.ha[i][j] = h * tab.a(i, j);
                out.ha_bar[i][j] = h * tab.a_bar(i, j);
            }
            out.bab[i] = h * h * (0..s).map(|k| tab.b[k] * tab.a_bar(k, i)).sum::<f64>();
        }
        // Distinct nodes of the last two steps, in units of h from the start
        // of the last one (Lobatto's shared end points counted once).
        let mut nodes = Vec::with_capacity(2 * s);
        for back in [1usize, 0] {
            for j in 0..s {
                let x = tab.c[j] - back as f64;
                if nodes.iter().all(|&y: &f64| (y - x).abs() > 1e-12) {
                    out.two_nodes[nodes.len()] = (back, j);
                    nodes.push(x);
                }
            }
        }
        let at: Vec<f64> = tab.c.iter().map(|c| 1.0 + c).collect();
        if let Ok(w) = crate::tableau::lagrange_interpolation(&nodes, &at) {
            let lebesgue = (0..s)
                .map(|i| {
                    w.values[i * w.n_control..(i + 1) * w.n_control]
                        .iter()
                        .map(|x| x.abs())
                        .sum::<f64>()
                })
                .fold(0.0, f64::max);
            if lebesgue <= MAX_TWO_STEP_AMPLIFICATION {
                out.n_two = nodes.len();
                for i in 0..s {
                    for m in 0..nodes.len() {
                        out.extrap_two[i][m] = w.values[i * w.n_control + m];
                    }
                }
            }
        }
        Ok(out)
    }

    /// Replace the options of the Newton fallback (the fixed-point sweeps
    /// stop at round-off whatever they say).
    pub fn with_newton_options(mut self, options: crate::solve::NewtonOptions) -> Self {
        self.general = self.general.with_options(options);
        self
    }

    /// The general-path integrator used as fallback (and for Jacobians).
    pub fn general(&mut self) -> &mut GalerkinIntegrator<SeparableLagrangian<V, N>, N, F> {
        &mut self.general
    }

    /// Begin a step: if it continues the previous one, predict the stage forces
    /// into `g` (see the module documentation) and return `true`; otherwise
    /// reset the summation compensation and the history and return `false`.
    fn predicted_forces(&mut self, state: &PhaseState<N>, g: &mut [SVector<f64, N>; MAX_STAGES]) -> bool {
        if !matches!(self.previous, Some((te, qe)) if continues(te, &qe, state.t, &state.q)) {
            self.compensation = (SVector::zeros(), SVector::zeros());
            self.depth = 0;
            self.prediction_error.1 = 0;
            return false;
        }
        if self.depth >= 2 && self.n_two > 0 {
            for i in 0..self.s {
                g[i] = (0..self.n_two).fold(SVector::zeros(), |acc, m| {
                    let (back, j) = self.two_nodes[m];
                    let f = if back == 1 {
                        self.older_forces[j]
                    } else {
                        self.forces[j]
                    };
                    acc + f * self.extrap_two[i][m]
                });
            }
        } else {
            for i in 0..self.s {
                g[i] = (0..self.s).fold(SVector::zeros(), |acc, j| acc + self.forces[j] * self.extrap[i][j]);
            }
        }
        let kind = if self.depth >= 2 && self.n_two > 0 { 2 } else { 1 };
        self.prediction.0[..self.s].copy_from_slice(&g[..self.s]);
        self.prediction.1 = kind;
        if self.prediction_error.1 == kind {
            for i in 0..self.s {
                g[i] += self.prediction_error.0[i];
            }
        }
        true
    }

    /// After a converged step with stage forces `g`: shift the force history
    /// and record the prediction error (converged − predicted).
    fn remember(&mut self, g: &[SVector<f64, N>; MAX_STAGES]) {
        let s = self.s;
        self.older_forces[..s].copy_from_slice(&self.forces[..s]);
        self.forces[..s].copy_from_slice(&g[..s]);
        if self.depth > 0 {
            for i in 0..s {
                self.prediction_error.0[i] = g[i] - self.prediction.0[i];
            }
            self.prediction_error.1 = self.prediction.1;
        }
        self.depth = (self.depth + 1).min(2);
    }

    /// Forced case: fixed-point iteration on the stage velocities of the
    /// partitioned Runge–Kutta form (seed 004 §4.3)
    /// `Qᵢ = q_k + h Σⱼ aᵢⱼVⱼ`, `M Vᵢ = p_k + h Σⱼ āᵢⱼ (−∇V(Qⱼ) + F(Qⱼ, Vⱼ))`,
    /// then `q_{k+1} = q_k + h Σⱼ bⱼVⱼ`, `p_{k+1} = p_k + h Σⱼ bⱼ(−∇V(Qⱼ) + F(Qⱼ, Vⱼ))`.
    fn fixed_point_forced(&mut self, state: &PhaseState<N>) -> Option<(PhaseState<N>, usize)> {
        let s = self.s;
        // Total generalised forces gⱼ = −∇V(Qⱼ) + F(Qⱼ, Vⱼ), predicted from the previous step.
        let mut g = [SVector::<f64, N>::zeros(); MAX_STAGES];
        let predicted = self.predicted_forces(state, &mut g);
        let sys = self.general.lagrangian();
        let force = self.general.force();
        let minv = *sys.mass_inverse();
        let (t, q) = (state.t, state.q);
        let v = minv * state.p;
        let mut vel = [v; MAX_STAGES];
        let mut pos = [q; MAX_STAGES];
        if predicted {
            for i in 0..s {
                let mut acc = SVector::<f64, N>::zeros();
                for j in 0..s {
                    acc += g[j] * self.ha_bar[i][j];
                }
                vel[i] = v + minv * acc;
            }
        }
        let scale = v.amax().max(1.0);
        let mut last = f64::INFINITY;
        for it in 1..=self.max_iterations {
            for i in 0..s {
                let mut dq = SVector::<f64, N>::zeros();
                for j in 0..s {
                    dq += vel[j] * self.ha[i][j];
                }
                pos[i] = q + dq;
                let ti = t + self.c[i] * self.h;
                g[i] = sys.conservative_force(ti, &pos[i]) + force.force(ti, &pos[i], &vel[i]);
            }
            let mut delta = 0.0_f64;
            for i in 0..s {
                let mut acc = SVector::<f64, N>::zeros();
                for j in 0..s {
                    acc += g[j] * self.ha_bar[i][j];
                }
                let vi = v + minv * acc;
                delta = delta.max((vi - vel[i]).amax());
                vel[i] = vi;
            }
            let update = delta / scale;
            if !update.is_finite() {
                return None;
            }
            if update <= 2.0 * f64::EPSILON || (it > 2 && update >= last && update <= 1e-10) {
                let (mut dq, mut dp, mut work) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros(), 0.0);
                for j in 0..s {
                    let ti = t + self.c[j] * self.h;
                    let fj = force.force(ti, &pos[j], &vel[j]);
                    dq += vel[j] * (self.h * self.b[j]);
                    dp += g[j] * (self.h * self.b[j]);
                    work += self.h * self.b[j] * fj.dot(&vel[j]);
                }
                let (q_next, cq) = kahan_add(&q, &dq, &self.compensation.0);
                let (p_next, cp) = kahan_add(&state.p, &dp, &self.compensation.1);
                self.compensation = (cq, cp);
                self.remember(&g);
                self.last_work = work;
                return Some((PhaseState::new(t + self.h, q_next, p_next), it));
            }
            if it > 3 && update > last {
                return None;
            }
            last = update;
        }
        None
    }

    /// Fixed-point solve of the stage equations; `None` if it does not contract.
    ///
    /// Works with the forces `gⱼ = −∇V(Qⱼ)` and accelerations `fⱼ = M⁻¹gⱼ`;
    /// the momentum update `p_{k+1} = p_k + h Σⱼ bⱼ gⱼ` and the position update
    /// are formed as increments and added with compensated summation.
    fn fixed_point(&mut self, state: &PhaseState<N>) -> Option<(PhaseState<N>, usize)> {
        let s = self.s;
        let mut g = [SVector::<f64, N>::zeros(); MAX_STAGES];
        let predicted = self.predicted_forces(state, &mut g);
        let sys = self.general.lagrangian();
        let minv = *sys.mass_inverse();
        let (t, q) = (state.t, state.q);
        let v = minv * state.p;
        if !predicted {
            g[..s].fill(sys.conservative_force(t, &q));
        }
        // Stage increments from the forces: zᵢ = h cᵢ v + M⁻¹ Σⱼ h²(AĀ)ᵢⱼ gⱼ.
        let increments = |g: &[SVector<f64, N>; MAX_STAGES], z: &mut [SVector<f64, N>; MAX_STAGES]| {
            for i in 0..s {
                let mut acc = SVector::<f64, N>::zeros();
                for j in 0..s {
                    acc += g[j] * self.aab[i][j];
                }
                z[i] = v * (self.h * self.c[i]) + minv * acc;
            }
        };
        let mut z = [SVector::<f64, N>::zeros(); MAX_STAGES];
        let mut next = z;
        increments(&g, &mut z);
        let scale = q.amax().max(1.0);
        let mut last = f64::INFINITY;
        for it in 1..=self.max_iterations {
            for i in 0..s {
                g[i] = sys.conservative_force(t + self.c[i] * self.h, &(q + z[i]));
            }
            increments(&g, &mut next);
            let mut delta = 0.0_f64;
            for i in 0..s {
                delta = delta.max((next[i] - z[i]).amax());
            }
            z[..s].copy_from_slice(&next[..s]);
            let update = delta / scale;
            if !update.is_finite() {
                return None;
            }
            // The forces g = f(z_old) give z = Z(g) with |z − z_old| = update:
            // the stage equations hold to that (times the contraction factor).
            if update <= STAGE_TOLERANCE * f64::EPSILON || (it > 2 && update >= last && update <= 1e-10) {
                let mut dq_force = SVector::<f64, N>::zeros();
                let mut dp = SVector::<f64, N>::zeros();
                for j in 0..s {
                    dq_force += g[j] * self.bab[j];
                    dp += g[j] * (self.h * self.b[j]);
                }
                let dq = v * self.h + minv * dq_force;
                let (q_next, cq) = kahan_add(&q, &dq, &self.compensation.0);
                let (p_next, cp) = kahan_add(&state.p, &dp, &self.compensation.1);
                self.compensation = (cq, cp);
                self.remember(&g);
                return Some((PhaseState::new(t + self.h, q_next, p_next), it));
            }
            if it > 3 && update > last {
                return None;
            }
            last = update;
        }
        None
    }
}

impl<V: Potential<N>, const N: usize, F: Force<N>> OneStepMap<N> for SeparableIntegrator<V, N, F> {
    fn step_size(&self) -> f64 {
        self.h
    }
    /// The end `(t, q)` of the last step, its stage forces (the predictor),
    /// the Kahan compensation terms, then the Newton fallback's own carry.
    fn save_carry(&self, out: &mut Vec<f64>) {
        save_step_end(out, self.previous);
        out.extend(self.forces[..self.s].iter().flat_map(|g| g.iter()));
        out.extend(self.compensation.0.iter().chain(self.compensation.1.iter()));
        out.push(self.last_work);
        // The predictor's history, behind a tag (checkpoints of earlier
        // versions go on to the fallback's carry, whose first word is a flag).
        out.push(PREDICTOR_CARRY_TAG);
        out.push(self.depth as f64);
        out.extend(self.older_forces[..self.s].iter().flat_map(|g| g.iter()));
        out.extend(self.prediction.0[..self.s].iter().flat_map(|g| g.iter()));
        out.push(self.prediction.1 as f64);
        let (e, kind) = &self.prediction_error;
        let error = (*kind > 0).then(|| {
            let mut r: Vec<f64> = e[..self.s].iter().flat_map(|g| g.iter().copied()).collect();
            r.push(*kind as f64);
            r
        });
        crate::run::save_option(out, error.as_deref(), self.s * N + 1);
        self.general.save_carry(out);
    }
    fn restore_carry(&mut self, words: &mut crate::run::Words<'_>) -> Result<()> {
        self.previous = restore_step_end(words)?;
        for g in self.forces[..self.s].iter_mut() {
            *g = SVector::from_column_slice(words.take(N)?);
        }
        self.compensation = (
            SVector::from_column_slice(words.take(N)?),
            SVector::from_column_slice(words.take(N)?),
        );
        self.last_work = words.one()?;
        if words.take_tag(PREDICTOR_CARRY_TAG) {
            let small = |x: f64, name: &str| -> Result<usize> {
                if [0.0, 1.0, 2.0].contains(&x) {
                    Ok(x as usize)
                } else {
                    Err(Error::InvalidParameter {
                        name: "checkpoint".into(),
                        value: x.to_string(),
                        reason: format!("separable predictor {name} must be 0, 1 or 2"),
                    })
                }
            };
            self.depth = small(words.one()?, "depth")?;
            for g in self.older_forces[..self.s].iter_mut() {
                *g = SVector::from_column_slice(words.take(N)?);
            }
            for g in self.prediction.0[..self.s].iter_mut() {
                *g = SVector::from_column_slice(words.take(N)?);
            }
            self.prediction.1 = small(words.one()?, "kind")?;
            self.prediction_error.1 = 0;
            if let Some(r) = crate::run::restore_option(words, self.s * N + 1)? {
                for (i, g) in self.prediction_error.0[..self.s].iter_mut().enumerate() {
                    *g = SVector::from_column_slice(&r[i * N..(i + 1) * N]);
                }
                self.prediction_error.1 = small(r[self.s * N], "kind")?;
            }
        } else {
            // An earlier version's checkpoint: the one-step predictor resumes.
            self.depth = usize::from(self.previous.is_some());
            self.prediction_error.1 = 0;
        }
        self.general.restore_carry(words)
    }
    fn step(&mut self, index: usize, state: &PhaseState<N>) -> Result<(PhaseState<N>, StepStats)> {
        state.check()?;
        let forced = !self.general.force().is_zero();
        let attempt = if forced {
            self.fixed_point_forced(state)
        } else {
            self.fixed_point(state)
        };
        if let Some((next, iterations)) = attempt
            && next.check().is_ok()
        {
            self.previous = Some((next.t, next.q));
            let work = if forced { self.last_work } else { 0.0 };
            return Ok((
                next,
                StepStats {
                    max_relative_residual: 0.0,
                    iterations,
                    fallback: false,
                    work,
                    jacobians: 0,
                    force_evaluations: iterations * self.s,
                },
            ));
        }
        self.previous = None;
        let (next, report) = self.general.step_report(index, state)?;
        Ok((
            next,
            StepStats {
                max_relative_residual: 0.0,
                iterations: report.iterations,
                fallback: true,
                work: self.general.last_work(),
                jacobians: 0,
                // The Newton path evaluates the Lagrangian's derivatives, not ∇V.
                force_evaluations: 0,
            },
        ))
    }
}
