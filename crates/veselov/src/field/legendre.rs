//! The vertex solve of the Cauchy integrator (seed 003 Thm 4.11, Def. 4.9):
//! find y_{Δv} with Leg_v(y_{Δv}) = μ_v by Newton in the fibre's chart
//! z·τ(ζ), with the exact Jacobian ∂Leg_v/∂ζ, to round-off. One routine for
//! every marcher ([`CauchyMarcher`](super::cauchy::CauchyMarcher) on periodic
//! CFK lattices, [`FlowMarcher`](super::flow::FlowMarcher) on any finite
//! complex).

use nalgebra::{SMatrix, SVector};

use super::fibre::Fibre;
use crate::solve::{SmallLu, max_abs};

/// Options of the vertex solves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CauchyOptions {
    /// Relative tolerance: a vertex is solved when
    /// max|Leg_v(z) − μ_v| ≤ `tolerance` × (the size of the terms summed),
    /// or when Newton stalls at round-off (the residual stops halving) within
    /// 100 × `tolerance` × (that size + |∂Leg/∂ζ|·(1 + |z|)), or stalls
    /// with its last correction below the resolution of the point's
    /// coordinates (see [`solve_legendre`]). The Jacobian term is the
    /// residual change a relative perturbation of the point makes (a
    /// step-size test, note 000 §14): it recognises round-off when the terms
    /// cancel (a stiff strain near its reference, or the single gradient of a
    /// slaved vertex's constraint). Default 1e-14.
    pub tolerance: f64,
    /// Newton iteration limit per vertex. Default 30.
    pub max_iterations: usize,
}

impl Default for CauchyOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-14,
            max_iterations: 30,
        }
    }
}

/// What one level cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LevelReport {
    /// The level whose equations were solved (its Δ images form level + n).
    pub level: i64,
    /// Newton iterations summed over the level's vertices.
    pub iterations: usize,
    /// Jacobian evaluations summed over the level's vertices.
    pub jacobians: usize,
    /// Largest final residual max|Leg_v − μ_v| relative to its scale.
    pub max_relative_residual: f64,
    /// Whether the level's vertices were shared among the threads of the
    /// pool (the values do not depend on it).
    pub parallel: bool,
}

/// How one vertex solve ended.
#[derive(Clone, Copy, Debug, Default)]
pub struct VertexOutcome {
    /// Newton iterations (Jacobian evaluations beyond the first residual).
    pub iterations: usize,
    /// Jacobian evaluations (exact: closed forms or dual passes).
    pub jacobians: usize,
    /// Final max|Leg_v − μ_v| relative to the size of the terms.
    pub relative_residual: f64,
    /// Why it failed, if it did.
    pub failure: Option<Failure>,
}

/// Why a vertex solve failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// ∂Leg_v/∂y_Δv has a zero pivot.
    Singular,
    /// A residual or iterate is not finite.
    NonFinite,
    /// The iteration limit was reached.
    IterationLimit,
    /// A rotation part reached the cut locus of the chart.
    CutLocus,
}

impl Failure {
    /// A message for errors.
    pub fn reason(self) -> &'static str {
        match self {
            Failure::Singular => "singular Legendre map (the Jacobian ∂Leg_v/∂y_Δv has a zero pivot)",
            Failure::NonFinite => "non-finite residual",
            Failure::IterationLimit => "iteration limit",
            Failure::CutLocus => "rotation at the cut locus of the chart",
        }
    }
}

/// Simplified Newton for Leg(z) = μ from `z`: `legendre(z, jacobian)`
/// returns (Leg(z), the size of the summed terms) and, when `jacobian` is
/// `Some`, writes ∂Leg/∂ζ at z·τ(ζ), ζ = 0 there. The Jacobian is evaluated
/// at the start and again only when an iteration fails to reduce the
/// residual fourfold at an iterate the stopping tests below do not accept,
/// so most iterations cost one gradient pass (and one solve with the kept LU
/// factors, [`SmallLu`]: from their second right-hand side on, one product
/// with the inverse they keep; after a step with them that reduces the
/// residual less than 100-fold, with that inverse corrected by Broyden's
/// update from each step). Stops when
/// max|Leg − μ| ≤ tolerance × (size of Leg's terms + `mu_scale`), or when it
/// stalls at round-off (the residual stops halving) within 100 × tolerance ×
/// (that size + |∂Leg/∂ζ|·(1 + |z|) from the latest Jacobian), or after a
/// correction below the resolution of the point, max|ζ| ≤ 64 ε_mach (1 + max
/// coordinate of z): then the residual is the round-off of differences of
/// the inputs (positions far from the origin moving little in a step, strains
/// small against |∂_s r|), which no iterate can reduce.
///
/// The point returned is the last one `legendre` was called at
/// ([`Fibre::renormalize`]d when accepted): a caller may keep by-products of
/// that last call (its per-cell gradients, say).
pub fn solve_legendre<F: Fibre<M>, const M: usize>(
    mu: &SVector<f64, M>,
    mu_scale: f64,
    z: F::Point<f64>,
    options: &CauchyOptions,
    legendre: impl FnMut(&F::Point<f64>, Option<&mut SMatrix<f64, M, M>>) -> (SVector<f64, M>, f64),
) -> (F::Point<f64>, VertexOutcome) {
    solve_legendre_from::<F, M>(mu, mu_scale, z, options, &mut None, legendre)
}

/// [`solve_legendre`] starting from the factors of a Jacobian `kept` from an
/// earlier solve (the same vertex equation one level before, say), used
/// (with Broyden's update where they converge slowly) until an iteration
/// fails to reduce the residual fourfold, then refreshed; the factors in
/// use at the end are left in `kept` for the next solve (and dropped on
/// failure): after secant steps that met the tolerance, those of the
/// Jacobian Broyden's updates made (H⁻¹), so that the next solve starts
/// from the corrections this one found. The root, its tolerance and the stall
/// tests are those of [`solve_legendre`]: only the number of exact Jacobians
/// changes.
pub fn solve_legendre_from<F: Fibre<M>, const M: usize>(
    mu: &SVector<f64, M>,
    mu_scale: f64,
    z: F::Point<f64>,
    options: &CauchyOptions,
    kept: &mut Option<SmallLu<M>>,
    legendre: impl FnMut(&F::Point<f64>, Option<&mut SMatrix<f64, M, M>>) -> (SVector<f64, M>, f64),
) -> (F::Point<f64>, VertexOutcome) {
    LegendreNewton::<F, M>::new(*mu, mu_scale, z, *options, kept.take()).run(kept, legendre)
}

/// The Newton of [`solve_legendre_from`] as a state machine that asks for
/// its evaluations ([`wants_jacobian`](Self::wants_jacobian) at
/// [`point`](Self::point)) and is handed their results
/// ([`feed`](Self::feed)), so that a caller may evaluate the equations of
/// many vertices together (all their cells' potentials at once, say) while
/// each vertex iterates, stops and fails exactly as it would alone: the
/// same evaluations at the same points, the same bits.
#[derive(Clone, Copy)]
pub struct LegendreNewton<F: Fibre<M>, const M: usize> {
    mu: SVector<f64, M>,
    mu_scale: f64,
    options: CauchyOptions,
    /// The factors of the Jacobian in use (`None` until one is evaluated,
    /// or after a singular one), factored once where it is evaluated;
    /// dropped on failure. Factors are finite wherever they come from
    /// ([`SmallLu::refactor`], [`SmallLu::restore_factors`]).
    factors: Option<SmallLu<M>>,
    z: F::Point<f64>,
    outcome: VertexOutcome,
    /// The residual of the last iteration.
    previous: f64,
    have_jacobian: bool,
    /// Whether the factors in use were evaluated at this iteration's point.
    fresh: bool,
    point_scale: f64,
    last_step: f64,
    /// The iteration under way.
    iteration: usize,
    /// Whether the evaluation asked for refreshes the Jacobian after a poor
    /// contraction (the iteration's second evaluation, at the same point).
    refreshing: bool,
    done: bool,
    /// The secant steps since the last fresh Jacobian (`None` until a
    /// slowly contracting step with an old Jacobian asks for them,
    /// [`SECANT_CONTRACTION`]).
    secant: Option<Secant<M>>,
    /// Whether the factors left after secant steps are Broyden's (see
    /// [`solve_legendre_from`]) rather than the evaluated Jacobian's
    /// ([`keeping_evaluated_jacobians`](Self::keeping_evaluated_jacobians)).
    carry_secant: bool,
}

/// Steps by an inverse Jacobian that Broyden's update corrects from each
/// step: superlinear where an old Jacobian alone converges slowly.
#[derive(Clone, Copy)]
struct Secant<const M: usize> {
    /// H, the inverse in use.
    inverse: SMatrix<f64, M, M>,
    /// The last step and the residual it started from.
    last: Option<(SVector<f64, M>, SVector<f64, M>)>,
}

impl<const M: usize> Secant<M> {
    /// The step −H·residual, H first corrected by Broyden's update from the
    /// last step ([`broyden_update`]; not for a change of residual near the
    /// rounding of its terms, ε·`scale`, which carries no slope). Out of
    /// line: most solves never take it.
    #[cold]
    #[inline(never)]
    fn step(&mut self, residual: &SVector<f64, M>, scale: f64) -> SVector<f64, M> {
        if let Some((step, from)) = self.last {
            let change = residual - from;
            if max_abs(&change) > SECANT_RESOLUTION * scale {
                broyden_update(&mut self.inverse, &step, &change);
            }
        }
        let delta = -(self.inverse * residual);
        self.last = Some((delta, *residual));
        delta
    }

    /// The factors of H⁻¹, the Jacobian Broyden's updates have made (not
    /// updated from the last step, which ends at round-off: with that
    /// update the beam of the `beam_step` bench took 0.8 % more iterations
    /// and 1.7 times the Jacobians); `None` if H or its inverse is singular
    /// or not finite.
    #[cold]
    #[inline(never)]
    fn corrected_factors(&self) -> Option<SmallLu<M>> {
        let jacobian = self.inverse.try_inverse()?;
        let mut lu = SmallLu::zeros();
        lu.refactor(&jacobian)?;
        Some(lu)
    }
}

impl<F: Fibre<M>, const M: usize> LegendreNewton<F, M> {
    /// Newton for Leg(z) = μ from `z`, with the factors `kept` from an
    /// earlier solve if any (see [`solve_legendre_from`]).
    #[inline]
    pub fn new(
        mu: SVector<f64, M>,
        mu_scale: f64,
        z: F::Point<f64>,
        options: CauchyOptions,
        kept: Option<SmallLu<M>>,
    ) -> Self {
        let point_scale = kept
            .as_ref()
            .map_or(0.0, |f| f.largest() * (1.0 + coordinate_size::<F, M>(&z)));
        Self {
            mu,
            mu_scale,
            options,
            have_jacobian: kept.is_some(),
            factors: kept,
            z,
            outcome: VertexOutcome::default(),
            previous: f64::INFINITY,
            fresh: false,
            point_scale,
            last_step: f64::INFINITY,
            iteration: 0,
            refreshing: false,
            done: false,
            secant: None,
            carry_secant: true,
        }
    }

    /// For a Jacobian in closed form, about as cheap as an evaluation of
    /// Leg: the factors left for the next solve are always those of an
    /// evaluated Jacobian, and a solve's Broyden corrections stay with it.
    /// Carried by the split solves of seed 000's beams (measured with the
    /// rule of [`solve_legendre_from`]), they saved `beam_free_free.toml`
    /// 3 % of its iterations (5.67 → 5.48 per node) but cost
    /// `beam_cantilever_damped.toml` 11 % more (2.32 → 2.57), and let the
    /// momentum maps drift further: the free–free beam's 7.0e-13 against
    /// 2.8e-13, the stiff beam's of `beam_paper_space_well_posed.toml`
    /// 2.4e-13 against 1.5e-13. With a closed-form Jacobian a fresh one is
    /// the cheaper cure of a slow contraction.
    #[must_use]
    pub(crate) fn keeping_evaluated_jacobians(mut self) -> Self {
        self.carry_secant = false;
        self
    }

    /// Drives the solve to its end with the evaluations of `legendre`
    /// (what [`solve_legendre_from`] does), leaving the factors in use at
    /// the end in `kept` (`None` after a failure).
    pub(crate) fn run(
        mut self,
        kept: &mut Option<SmallLu<M>>,
        mut legendre: impl FnMut(&F::Point<f64>, Option<&mut SMatrix<f64, M, M>>) -> (SVector<f64, M>, f64),
    ) -> (F::Point<f64>, VertexOutcome) {
        // Where an evaluation writes a fresh Jacobian (no copy moves it).
        let mut jacobian = SMatrix::<f64, M, M>::zeros();
        while let Some(with_jacobian) = self.wants_jacobian() {
            let (leg, scale) = legendre(self.point(), with_jacobian.then_some(&mut jacobian));
            self.feed(&leg, scale, &jacobian);
        }
        let (z, outcome, factors) = self.finish();
        *kept = factors;
        (z, outcome)
    }

    /// Whether Leg at [`point`](Self::point) is wanted with its Jacobian
    /// ∂Leg/∂ζ (`Some(true)`) or alone (`Some(false)`); `None` once the
    /// solve has ended.
    #[inline]
    pub fn wants_jacobian(&self) -> Option<bool> {
        (!self.done).then_some(self.refreshing || !self.have_jacobian)
    }

    /// The point of the evaluation wanted next (the last one evaluated once
    /// the solve has ended).
    #[inline]
    pub fn point(&self) -> &F::Point<f64> {
        &self.z
    }

    /// Whether Newton stops at the current point with residual `r`:
    /// converged, or stalled at round-off (the residual stops halving) by
    /// either test of [`solve_legendre`]'s documentation.
    #[inline]
    fn stops(&self, r: f64, scale: f64, point_scale: f64) -> (bool, bool) {
        let stalled = r > 0.5 * self.previous
            && (r <= 100.0 * self.options.tolerance * (scale + point_scale)
                || self.last_step <= resolution::<F, M>(&self.z));
        (r <= self.options.tolerance * scale || stalled, stalled)
    }

    /// Hands over Leg and the size of its terms at the point
    /// [`point`](Self::point) gave, with the Jacobian there when it was
    /// asked for (`jacobian` is read only then), and advances.
    #[inline(always)]
    pub fn feed(&mut self, leg: &SVector<f64, M>, leg_scale: f64, jacobian: &SMatrix<f64, M, M>) {
        if self.done {
            return;
        }
        let residual = leg - self.mu;
        let r = max_abs(&residual);
        let evaluated = if self.refreshing {
            self.refreshing = false;
            true
        } else {
            // Poor contraction with an old Jacobian: refresh it at this
            // iterate, unless the iterate is accepted as it is (a fresh
            // Jacobian cannot improve on round-off).
            if self.have_jacobian
                && !self.fresh
                && r > 0.25 * self.previous
                && r.is_finite()
                && !self.stops(r, leg_scale + self.mu_scale, self.point_scale).0
            {
                self.refreshing = true;
                return;
            }
            !self.have_jacobian
        };
        if evaluated {
            self.point_scale = jacobian.amax() * (1.0 + coordinate_size::<F, M>(&self.z));
            let lu = self.factors.get_or_insert_with(SmallLu::zeros);
            if lu.refactor(jacobian).is_none() {
                self.factors = None;
            }
            self.have_jacobian = true;
            self.fresh = true;
            self.outcome.jacobians += 1;
        } else {
            self.fresh = false;
        }
        let scale = leg_scale + self.mu_scale;
        let it = self.iteration;
        self.outcome.iterations = it;
        self.outcome.relative_residual = r / scale.max(f64::MIN_POSITIVE);
        if !r.is_finite() {
            return self.fail(Failure::NonFinite);
        }
        let (accepted, stalled) = self.stops(r, scale, self.point_scale);
        if stalled && r > self.options.tolerance * scale {
            // Accepted at round-off: report the residual relative to the
            // scale that accepted it.
            self.outcome.relative_residual = r / (scale + self.point_scale).max(f64::MIN_POSITIVE);
        }
        if accepted {
            // After secant steps to the tolerance, the factors left for the
            // next solve are those of the Jacobian Broyden's updates have
            // made, closer to the Jacobian here than the old one they
            // started from (which stays if H cannot be inverted). Not after
            // a solve accepted at round-off by the stall tests: its last
            // slopes are rounding (carried even then, they let the momentum
            // map of the stiff beam of `beam_paper_space_well_posed.toml`
            // drift 1.7e-12 against 2.4e-13, before the beams' split solves
            // stopped carrying them at all).
            if self.carry_secant
                && r <= self.options.tolerance * scale
                && let Some(lu) = self.secant.as_ref().and_then(Secant::corrected_factors)
            {
                self.factors = Some(lu);
            }
            self.z = F::renormalize(&self.z);
            self.done = true;
            return;
        }
        // A slow step: a residual ratio above SECANT_CONTRACTION (never at
        // the first evaluation, previous = ∞).
        let slow = r > SECANT_CONTRACTION * self.previous;
        self.previous = r;
        if it == self.options.max_iterations {
            return self.fail(Failure::IterationLimit);
        }
        let fresh = self.fresh;
        let Some(lu) = self.factors.as_mut() else {
            self.outcome.failure = Some(Failure::Singular);
            self.done = true;
            return;
        };
        let delta = if fresh {
            self.secant = None;
            lu.solve(&(-residual))
        } else {
            // Factors solving their second right-hand side will likely
            // solve more: from then on a solve is one product with A⁻¹.
            // From a slow step on, Broyden's update corrects that inverse
            // from each step (superlinear, where the old Jacobian alone
            // converges slowly).
            lu.keep_inverse();
            if slow && self.secant.is_none() {
                self.secant = lu.inverse().map(|inverse| Secant { inverse, last: None });
            }
            match self.secant.as_mut() {
                Some(secant) => secant.step(&residual, scale),
                None => lu.solve(&(-residual)),
            }
        };
        self.last_step = delta.amax();
        let next = F::retract(&self.z, &delta);
        if !F::is_finite(&next) {
            return self.fail(Failure::NonFinite);
        }
        // A step with every coordinate below 1 rotates by at most √3 < π
        // minus the margin: only a larger one can reach the cut locus.
        if delta.amax() >= 1.0 && F::log(&self.z, &next).is_err() {
            return self.fail(Failure::CutLocus);
        }
        self.z = next;
        self.iteration = it + 1;
    }

    /// Ends the solve with `failure`, dropping the factors.
    #[inline]
    fn fail(&mut self, failure: Failure) {
        self.outcome.failure = Some(failure);
        self.factors = None;
        self.done = true;
    }

    /// The last point evaluated ([`Fibre::renormalize`]d when accepted),
    /// the outcome (a failure if the solve has not ended), and the factors
    /// in use at the end (`None` after a failure).
    #[inline]
    pub fn finish(mut self) -> (F::Point<f64>, VertexOutcome, Option<SmallLu<M>>) {
        if !self.done {
            self.fail(Failure::IterationLimit);
        }
        (self.z, self.outcome, self.factors)
    }
}

/// The residual ratio r/r_prev of a step with an old Jacobian above which
/// the next steps correct its inverse by Broyden's update (a chord
/// iteration contracting less than 100-fold per step: a frame field's
/// Jacobian from n levels before). Solves that contract faster keep the
/// plain inverse and their bits: there the secant steps save little and
/// leave errors of another pattern (on the n = 1 Kepler march of the tests,
/// secant steps from the first reuse on took 21 % fewer iterations but left
/// the trajectory 4× further from the mechanics integrator's, 5.1e-14
/// against 1.3e-14 per step, with the same final residuals).
const SECANT_CONTRACTION: f64 = 0.01;

/// The least change of the residual, relative to the size of its terms,
/// from which Broyden's update is made: 10⁴ times the rounding of those
/// terms, so that the slope it measures is good to about 10⁻⁴.
const SECANT_RESOLUTION: f64 = 1e4 * f64::EPSILON;

/// Broyden's ("good") update of an inverse Jacobian H from a step s that
/// changed the residual by y: H + (s − Hy)(sᵀH)/(sᵀHy), so that the new H
/// maps y to s (the secant condition), skipped when sᵀHy is too small
/// against |s||Hy| to divide by.
fn broyden_update<const M: usize>(h: &mut SMatrix<f64, M, M>, s: &SVector<f64, M>, y: &SVector<f64, M>) {
    let hy = *h * y;
    let sh = s.transpose() * *h;
    let denominator = s.dot(&hy);
    if denominator.abs() > 1e-8 * s.norm() * hy.norm() && denominator.is_finite() {
        *h += (s - hy) * (sh / denominator);
    }
}

/// The largest coordinate of y in absolute value.
fn coordinate_size<F: Fibre<M>, const M: usize>(y: &F::Point<f64>) -> f64 {
    let mut c = [0.0; 16];
    let n = if F::COORDINATES <= c.len() { F::COORDINATES } else { 0 };
    F::write(y, &mut c[..n]);
    c[..n].iter().fold(0.0_f64, |m, x| m.max(x.abs()))
}

/// 64 ε_mach (1 + the largest coordinate of y): a chart correction below it
/// changes y by round-off only.
fn resolution<F: Fibre<M>, const M: usize>(y: &F::Point<f64>) -> f64 {
    64.0 * f64::EPSILON * (1.0 + coordinate_size::<F, M>(y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::fibre::Euclidean;

    /// A residual with one NaN entry among numbers is a non-finite
    /// residual, not a converged one.
    #[test]
    fn one_nan_entry_is_a_non_finite_residual() {
        let mu = SVector::<f64, 2>::zeros();
        let (_, outcome) = solve_legendre::<Euclidean<2>, 2>(
            &mu,
            0.0,
            SVector::from([1.0, 1.0]),
            &CauchyOptions::default(),
            |z, jacobian| {
                if let Some(j) = jacobian {
                    *j = SMatrix::identity();
                }
                (SVector::from([0.0 * z[0], f64::NAN]), 1.0)
            },
        );
        assert_eq!(outcome.failure, Some(Failure::NonFinite));
        assert!(max_abs(&SVector::from([f64::NAN, 2.0])).is_nan());
        assert_eq!(max_abs(&SVector::from([-3.0, 2.0])), 3.0);
    }

    /// Broyden's update makes the new inverse map the change of residual
    /// to the step (the secant condition), to rounding.
    #[test]
    fn broyden_update_meets_the_secant_condition() {
        let mut uniform = crate::test_support::uniform(0x1405_7b7e_f767_814f);
        for _ in 0..100 {
            let mut h = SMatrix::<f64, 3, 3>::from_fn(|i, j| uniform() + if i == j { 3.0 } else { 0.0 });
            let s = SVector::<f64, 3>::from_fn(|_, _| uniform());
            let y = SVector::<f64, 3>::from_fn(|_, _| uniform());
            broyden_update(&mut h, &s, &y);
            let miss = (h * y - s).amax();
            assert!(miss <= 1e-12 * (1.0 + h.amax() * y.amax()), "H y − s = {miss:e}");
        }
    }

    /// Leg(z) = A z + 0.3 sin z + 0.1 z₀z₁(1, 1, 1) and its Jacobian.
    fn nonlinear(z: &SVector<f64, 3>) -> (SVector<f64, 3>, SMatrix<f64, 3, 3>) {
        let a = SMatrix::<f64, 3, 3>::new(4.0, 1.0, 0.5, 1.0, 3.0, 0.2, 0.5, 0.2, 2.0);
        let value = a * z + z.map(f64::sin) * 0.3 + SVector::repeat(0.1 * z[0] * z[1]);
        let mut jacobian = a + SMatrix::from_diagonal(&(z.map(f64::cos) * 0.3));
        for i in 0..3 {
            jacobian[(i, 0)] += 0.1 * z[1];
            jacobian[(i, 1)] += 0.1 * z[0];
        }
        (value, jacobian)
    }

    /// The matrix whose LU factors `lu` holds.
    fn matrix_of<const N: usize>(lu: &SmallLu<N>) -> SMatrix<f64, N, N> {
        let mut lu = *lu;
        lu.keep_inverse();
        lu.inverse().expect("kept").try_inverse().expect("regular")
    }

    /// After secant steps, the factors a solve leaves are those of the
    /// Jacobian Broyden's updates made: nearer the Jacobian at the root
    /// than the kept ones it started from (15 % off), so that the next
    /// solve, of a nearby equation (the same vertex one level on), needs
    /// fewer iterations from them than from the old ones.
    #[test]
    fn the_factors_left_after_secant_steps_carry_broydens_corrections() {
        let root = SVector::<f64, 3>::new(0.7, -0.4, 0.9);
        let exact = nonlinear(&root).1;
        let old = exact * 1.15;
        let options = CauchyOptions::default();
        let evaluate = |z: &SVector<f64, 3>, jacobian: Option<&mut SMatrix<f64, 3, 3>>| {
            assert!(jacobian.is_none(), "no Jacobian is asked for");
            let (value, _) = nonlinear(z);
            (value, value.amax() + 2.0 * z.amax())
        };
        let solve = |target: &SVector<f64, 3>, kept: &mut Option<SmallLu<3>>| {
            let mu = nonlinear(target).0;
            let start = target + SVector::<f64, 3>::new(0.05, 0.03, -0.04);
            let (z, outcome) = solve_legendre_from::<Euclidean<3>, 3>(&mu, 0.0, start, &options, kept, evaluate);
            assert!(outcome.failure.is_none(), "{outcome:?}");
            assert!((z - target).amax() < 1e-14, "root missed by {:e}", (z - target).amax());
            outcome.iterations
        };
        let mut kept = SmallLu::factor(&old).0;
        solve(&root, &mut kept);
        let carried = matrix_of(&kept.expect("factors left"));
        let (before, after) = ((old - exact).norm(), (carried - exact).norm());
        // Measured: ‖B − J‖_F 0.60 against 0.90 (the steps explore the
        // slow directions of the chord iteration, not all of ℝ³).
        assert!(after < before, "‖B − J‖ {after:.3e} against {before:.3e} before");
        // The next solve, of the equation with a root 1 % away.
        let next = root * 1.01;
        let from_carried = solve(&next, &mut kept);
        let from_old = solve(&next, &mut SmallLu::factor(&old).0);
        println!("{from_carried} iterations from the carried factors, {from_old} from the old");
        assert!(
            from_carried < from_old,
            "{from_carried} iterations from the carried factors, {from_old} from the old"
        );
    }

    /// A solve accepted at round-off by the stall test leaves the factors
    /// it started from, its last secant slopes being rounding; the same
    /// solve to a tolerance it meets leaves Broyden's. Leg(z) =
    /// (P + Jz) − P with P = J = 10⁸ takes values on a grid of 2⁻²⁵ near
    /// the root 0.7, and μ lies half a step off it: no point comes nearer
    /// than 2⁻²⁶ ≈ 1.5e-8, above the tolerance 10⁻¹⁶·|Jz| = 7e-9. The kept
    /// factors are 10 % off J (a chord contraction of 0.09: secant steps,
    /// no refresh).
    #[test]
    fn a_solve_accepted_at_round_off_keeps_the_factors_it_started_from() {
        const P: f64 = 1e8;
        const J: f64 = 1e8;
        let old = SMatrix::<f64, 1, 1>::new(1.1 * J);
        let mu = SVector::from([J * 0.7 + 2f64.powi(-26)]);
        let evaluate = |z: &SVector<f64, 1>, jacobian: Option<&mut SMatrix<f64, 1, 1>>| {
            assert!(jacobian.is_none(), "no Jacobian is asked for");
            (SVector::from([(P + J * z[0]) - P]), (J * z[0]).abs())
        };
        let slope_left = |tolerance: f64| {
            let options = CauchyOptions {
                tolerance,
                ..CauchyOptions::default()
            };
            let mut kept = SmallLu::factor(&old).0;
            let (z, outcome) =
                solve_legendre_from::<Euclidean<1>, 1>(&mu, 0.0, SVector::from([0.9]), &options, &mut kept, evaluate);
            assert!(outcome.failure.is_none(), "{outcome:?}");
            assert!((z[0] - 0.7).abs() < 1e-15, "root missed by {:e}", z[0] - 0.7);
            let residual = (evaluate(&z, None).0 - mu).amax();
            (residual, matrix_of(&kept.expect("factors left"))[(0, 0)])
        };
        let (residual, stalled) = slope_left(1e-16);
        assert!(
            residual > 1e-16 * J * 0.7,
            "accepted by the stall test, not the tolerance: {residual:e}"
        );
        assert_eq!(stalled, old[(0, 0)], "the factors it started from");
        let (_, converged) = slope_left(1e-14);
        assert!(
            (converged - J).abs() < 1e-3 * J,
            "Broyden's slope {converged:e}, the Jacobian {J:e}"
        );
    }

    /// From kept factors 15 % off the Jacobian at the root (a chord
    /// contraction of about 0.13 per step: slow, but not slow enough for a
    /// refresh), the secant steps reach the root to round-off without a
    /// Jacobian and in fewer iterations than the chord iteration with the
    /// same factors, to the same tolerance.
    #[test]
    fn secant_steps_beat_the_chord_iteration_from_a_poor_kept_jacobian() {
        let root = SVector::<f64, 3>::new(0.7, -0.4, 0.9);
        let mu = nonlinear(&root).0;
        let start = root + SVector::<f64, 3>::new(0.05, 0.03, -0.04);
        let options = CauchyOptions::default();
        let kept_matrix = nonlinear(&root).1 * 1.15;
        let evaluate = |z: &SVector<f64, 3>| {
            let (value, _) = nonlinear(z);
            (value, value.amax() + 2.0 * z.amax())
        };
        let mut kept = SmallLu::factor(&kept_matrix).0;
        let (z, outcome) =
            solve_legendre_from::<Euclidean<3>, 3>(&mu, 0.0, start, &options, &mut kept, |z, jacobian| {
                assert!(jacobian.is_none(), "no Jacobian is asked for");
                evaluate(z)
            });
        assert!(outcome.failure.is_none(), "{outcome:?}");
        assert_eq!(outcome.jacobians, 0);
        assert!((z - root).amax() < 1e-14, "root missed by {:e}", (z - root).amax());
        // The chord iteration with the same factors, to the same test.
        let lu = SmallLu::factor(&kept_matrix).0.expect("regular");
        let mut chord = start;
        let mut iterations = 0;
        loop {
            let (value, scale) = evaluate(&chord);
            if (value - mu).amax() <= options.tolerance * (scale + mu.amax()) {
                break;
            }
            chord -= lu.solve(&(value - mu));
            iterations += 1;
            assert!(iterations <= 1000, "the chord iteration does not converge");
        }
        assert!(
            outcome.iterations < iterations,
            "secant {} iterations, chord {iterations}",
            outcome.iterations
        );
    }
}
