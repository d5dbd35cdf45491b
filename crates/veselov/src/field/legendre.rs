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
/// with the inverse they keep). Stops when
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
/// until an iteration fails to reduce the residual fourfold, then
/// refreshed; the factors in use at the end are left in `kept` for the next
/// solve (and dropped on failure). The root, its tolerance and the stall
/// tests are those of [`solve_legendre`]: only the number of exact Jacobians
/// changes.
pub fn solve_legendre_from<F: Fibre<M>, const M: usize>(
    mu: &SVector<f64, M>,
    mu_scale: f64,
    mut z: F::Point<f64>,
    options: &CauchyOptions,
    kept: &mut Option<SmallLu<M>>,
    mut legendre: impl FnMut(&F::Point<f64>, Option<&mut SMatrix<f64, M, M>>) -> (SVector<f64, M>, f64),
) -> (F::Point<f64>, VertexOutcome) {
    let mut outcome = VertexOutcome::default();
    let mut previous = f64::INFINITY;
    // The factors of the Jacobian in use, in `kept` itself (`None` until one
    // is evaluated, or after a singular one), factored once where it is
    // evaluated; dropped on failure. Factors are finite wherever they come
    // from ([`SmallLu::refactor`], [`SmallLu::restore_factors`]).
    let factors = kept;
    let mut have_jacobian = factors.is_some();
    let mut fresh = false;
    let mut point_scale = factors
        .as_ref()
        .map_or(0.0, |f| f.largest() * (1.0 + coordinate_size::<F, M>(&z)));
    let mut last_step = f64::INFINITY;
    // Where an evaluation writes a fresh Jacobian (no copy moves it).
    let mut jacobian = SMatrix::<f64, M, M>::zeros();
    for it in 0..=options.max_iterations {
        let mut evaluated = !have_jacobian;
        let (mut leg, mut leg_scale) = legendre(&z, evaluated.then_some(&mut jacobian));
        let mut residual = leg - mu;
        let mut r = max_abs(&residual);
        // Whether Newton stops at z: converged, or stalled at round-off (the
        // residual stops halving) by either test of the documentation.
        let stops = |r: f64, scale: f64, point_scale: f64| {
            let stalled = r > 0.5 * previous
                && (r <= 100.0 * options.tolerance * (scale + point_scale) || last_step <= resolution::<F, M>(&z));
            (r <= options.tolerance * scale || stalled, stalled)
        };
        // Poor contraction with an old Jacobian: refresh it at this iterate,
        // unless the iterate is accepted as it is (a fresh Jacobian cannot
        // improve on round-off).
        if have_jacobian
            && !fresh
            && r > 0.25 * previous
            && r.is_finite()
            && !stops(r, leg_scale + mu_scale, point_scale).0
        {
            (leg, leg_scale) = legendre(&z, Some(&mut jacobian));
            evaluated = true;
            residual = leg - mu;
            r = max_abs(&residual);
        }
        if evaluated {
            point_scale = jacobian.amax() * (1.0 + coordinate_size::<F, M>(&z));
            let lu = factors.get_or_insert_with(SmallLu::zeros);
            if lu.refactor(&jacobian).is_none() {
                *factors = None;
            }
            have_jacobian = true;
            fresh = true;
            outcome.jacobians += 1;
        } else {
            fresh = false;
        }
        let scale = leg_scale + mu_scale;
        outcome.iterations = it;
        outcome.relative_residual = r / scale.max(f64::MIN_POSITIVE);
        if !r.is_finite() {
            outcome.failure = Some(Failure::NonFinite);
            *factors = None;
            return (z, outcome);
        }
        let (accepted, stalled) = stops(r, scale, point_scale);
        if stalled && r > options.tolerance * scale {
            // Accepted at round-off: report the residual relative to the
            // scale that accepted it.
            outcome.relative_residual = r / (scale + point_scale).max(f64::MIN_POSITIVE);
        }
        if accepted {
            return (F::renormalize(&z), outcome);
        }
        previous = r;
        if it == options.max_iterations {
            break;
        }
        let Some(lu) = factors.as_mut() else {
            outcome.failure = Some(Failure::Singular);
            return (z, outcome);
        };
        // Factors solving their second right-hand side will likely solve
        // more: from then on a solve is one product with A⁻¹.
        if !fresh {
            lu.keep_inverse();
        }
        let delta = lu.solve(&(-residual));
        last_step = delta.amax();
        let next = F::retract(&z, &delta);
        if !F::is_finite(&next) {
            outcome.failure = Some(Failure::NonFinite);
            *factors = None;
            return (z, outcome);
        }
        // A step with every coordinate below 1 rotates by at most √3 < π
        // minus the margin: only a larger one can reach the cut locus.
        if delta.amax() >= 1.0 && F::log(&z, &next).is_err() {
            outcome.failure = Some(Failure::CutLocus);
            *factors = None;
            return (z, outcome);
        }
        z = next;
    }
    *factors = None;
    outcome.failure = Some(Failure::IterationLimit);
    (z, outcome)
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
}
