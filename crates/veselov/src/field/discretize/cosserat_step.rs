//! The rod's vertex solve split as in note 003 §3.6: the position part of
//! Leg_v(r₂, R₂) = μ_v is linear in r₂ and independent of R₂, so r₂ comes
//! from one 3×3 solve; the rotation part is then a 3-D equation in
//! b = log(R₀ᵀR₂), solved by Newton with its exact Jacobian (forward-mode
//! AD over the b-dependent terms only), to round-off. The generic 6-D Newton
//! ([`solve_legendre`](crate::field::legendre::solve_legendre)) over the
//! same equations stays the reference.
//!
//! Position part (per cell based at v, σ = ±, with the damping of
//! [`RodLoads`](super::RodLoads)):
//! ∂Leg_r/∂r₂ = Σ_σ [−(ρΔs/(4Δt) + A_β c_r/(2Δt)) I − (Δt/(4Δs)) R₀C₁R₀ᵀ],
//! negative definite whenever ρ > 0 or C₁ ≻ 0 (always solvable).
//!
//! Rotation part:
//! Σ_σ [−(Δs/4)D_bJω_d + A_β(R₀ᵀg_σ)^C₁ε_σ + (σΔt/4)(2D_{a_σ} − D_b)C₂u_σ]
//! − Σ_σ (A_β c_R/(2Δt)) b + (loads at an end) = μ_R.

use nalgebra::{Const, Matrix3, SVector, U1, Vector3};
use num_dual::DualSVec64;

use super::cosserat::CosseratCell;
use super::rod_potential::RodPotential;
use crate::field::cell::{DiscreteLagrangian, VertexStar};
use crate::field::complex::TopCell;
use crate::field::fibre::{Fibre, Pose, PositionRotation, Rotations};
use crate::field::legendre::{CauchyOptions, Failure, VertexOutcome};
use crate::lie::so3;

/// The data of one cell based at v for the rotation equation.
#[derive(Clone, Copy)]
struct Arm {
    sigma: f64,
    a: Vector3<f64>,
    da: Matrix3<f64>,
}

/// Solves the vertex equation of the rod by the split step (see the module
/// documentation), from `start`; reports like the generic solve.
pub(crate) fn split_solve<P: RodPotential>(
    lag: &CosseratCell<P>,
    star: &VertexStar<'_, Pose<f64>>,
    mu: &SVector<f64, 6>,
    mu_scale: f64,
    start: &Pose<f64>,
    options: &CauchyOptions,
) -> (Pose<f64>, VertexOutcome) {
    let mut outcome = VertexOutcome::default();
    let fail = |failure, mut outcome: VertexOutcome| {
        outcome.failure = Some(failure);
        (*start, outcome)
    };
    let (ds, dt) = (lag.ds(), lag.dt());
    let (damp_r, damp_q) = lag
        .loads()
        .map_or((0.0, 0.0), |l| (l.damping_linear, l.damping_angular));
    // The cells based at v with the extrapolated top: their Legendre terms
    // at (r₀, R₀)·(Δr, b) are affine in Δr, so one evaluation at the start
    // and the constant ∂Leg_r/∂r₂ give the position exactly.
    let blank = TopCell {
        index: 0,
        shape: 0,
        origin: [0; crate::field::complex::MAX_LATTICE_DIMENSION],
    };
    let mut cells = [(blank, [*start; 3]); 2];
    let mut count = 0;
    for sigma in 0..2 {
        let mut y = [*start; 3];
        if let Some(cell) = star(sigma, &mut y) {
            y[2] = *start;
            cells[count] = (cell, y);
            count += 1;
        }
    }
    if count == 0 {
        return fail(Failure::Singular, outcome);
    }
    let cells = &cells[..count];
    // Both cells are based at v: its material point's parameters.
    let s0 = lag.material_coordinate(&cells[0].0);
    let p = *lag.parameters_at(s0);
    let y0 = cells[0].1[0];
    let r0m = *y0.rotation.matrix();
    let stiff = r0m * p.c1() * r0m.transpose();
    let mut leg_r = Vector3::zeros();
    let mut scale = mu_scale;
    let mut matrix = Matrix3::zeros();
    let mut arms = [Arm {
        sigma: 1.0,
        a: Vector3::zeros(),
        da: Matrix3::zeros(),
    }; 2];
    for (k, (cell, y)) in cells.iter().enumerate() {
        let sigma = if cell.shape == 0 { 1.0 } else { -1.0 };
        let (_, eps) = lag.linear_strain(sigma, s0, &y0, &y[1].position, &start.position);
        let v = (start.position - y0.position) / dt;
        let g = lag.position_gradient(sigma, s0, &y0, &v, &eps);
        let f = if damp_r > 0.0 || lag.loads().is_some() {
            lag.cell_force(cell, y, 0).fixed_rows::<3>(0).into_owned()
        } else {
            Vector3::zeros()
        };
        leg_r += g + f;
        scale += g.amax() + f.amax();
        matrix -= Matrix3::identity() * (p.rho() * ds / (4.0 * dt) + lag.area() * damp_r / (2.0 * dt))
            + stiff * (dt / (4.0 * ds));
        let Ok(a) = Rotations::log(&y[0].rotation, &y[1].rotation) else {
            return fail(Failure::CutLocus, outcome);
        };
        arms[k] = Arm {
            sigma,
            a,
            da: so3::dexp_inv(&(-a)),
        };
    }
    let rhs = mu.fixed_rows::<3>(0) - leg_r;
    let Some(step) = matrix.lu().solve(&rhs) else {
        return fail(Failure::Singular, outcome);
    };
    let r2 = start.position + step;
    let residual_r = (leg_r + matrix * step - mu.fixed_rows::<3>(0)).amax();
    if !residual_r.is_finite() {
        return fail(Failure::NonFinite, outcome);
    }
    // The b-independent rotation terms: A_β(R₀ᵀg_σ)^C₁ε_σ (and the end
    // load's torque), with r₂ known.
    let mut fixed = Vector3::zeros();
    let mut fixed_scale = 0.0;
    for (cell, y) in cells {
        let mut y = *y;
        y[2] = Pose::new(r2, y0.rotation);
        let sigma = if cell.shape == 0 { 1.0 } else { -1.0 };
        let (g, eps) = lag.linear_strain(sigma, s0, &y0, &y[1].position, &r2);
        let strain_term = lag.strain_torque(s0, &r0m, &g, &eps);
        // The force at (r₂, R₀) has no damping torque (b = 0): only the end load.
        let load = lag.cell_force(cell, &y, 0).fixed_rows::<3>(3).into_owned();
        fixed += strain_term + load;
        fixed_scale += strain_term.amax() + load.amax();
    }
    let target = mu.fixed_rows::<3>(3) - fixed;
    let arms = &arms[..count];
    let damping = lag.area() * damp_q / (2.0 * dt);
    let with_jacobian = |b: &Vector3<f64>| {
        let seeded = Vector3::from_fn(|i, _| DualSVec64::<3>::from_re(b[i]).derivative(i));
        let mut sum = Vector3::from_element(DualSVec64::<3>::from_re(0.0));
        for arm in arms {
            sum += lag.rotation_terms(arm.sigma, s0, &arm.a, &arm.da, &seeded)
                - seeded * DualSVec64::<3>::from_re(damping);
        }
        let jacobian = Matrix3::from_fn(|i, j| sum[i].eps.unwrap_generic(Const::<3>, U1)[j]);
        (sum.map(|x| x.re), Some(jacobian))
    };
    let value_only = |b: &Vector3<f64>| {
        let mut sum = Vector3::zeros();
        for arm in arms {
            sum += lag.rotation_terms(arm.sigma, s0, &arm.a, &arm.da, b) - b * damping;
        }
        (sum, None)
    };
    let mut b = match Rotations::log(&y0.rotation, &start.rotation) {
        Ok(b) => b,
        Err(_) => Vector3::zeros(),
    };
    // Simplified Newton: the exact Jacobian at the start, refreshed when an
    // iteration fails to reduce the residual fourfold.
    let mut previous = f64::INFINITY;
    let mut last_step = f64::INFINITY;
    let mut jacobian = Matrix3::zeros();
    let mut fresh = false;
    for it in 0..=options.max_iterations {
        let (mut value, mut jac) = if it == 0 { with_jacobian(&b) } else { value_only(&b) };
        let mut r = (value - target).amax();
        if jac.is_none() && !fresh && r > 0.25 * previous && r.is_finite() {
            (value, jac) = with_jacobian(&b);
            r = (value - target).amax();
        }
        fresh = jac.is_some();
        if let Some(j) = jac {
            jacobian = j;
            outcome.jacobians += 1;
        }
        let residual = value - target;
        outcome.iterations = it;
        let terms = scale + fixed_scale + value.amax();
        outcome.relative_residual = r.max(residual_r) / terms.max(f64::MIN_POSITIVE);
        if !r.is_finite() {
            return fail(Failure::NonFinite, outcome);
        }
        let jacobian_scale = jacobian.amax() * (1.0 + b.amax());
        let stalled = r > 0.5 * previous
            && (r <= 100.0 * options.tolerance * (terms + jacobian_scale)
                || last_step <= 64.0 * f64::EPSILON * (1.0 + b.amax()));
        if r <= options.tolerance * terms || stalled {
            // One last correction with the Jacobian at hand (no further
            // evaluation): from a converged iterate Newton's step only
            // removes the remaining residual (quadratic convergence).
            if let Some(delta) = jacobian.lu().solve(&(-residual))
                && delta.amax() < 1e-3
            {
                b += delta;
            }
            let rotation = y0.rotation.compose(&so3::exp(&b));
            return (PositionRotation::renormalize(&Pose::new(r2, rotation)), outcome);
        }
        previous = r;
        if it == options.max_iterations {
            break;
        }
        let Some(delta) = jacobian.lu().solve(&(-residual)) else {
            return fail(Failure::Singular, outcome);
        };
        last_step = delta.amax();
        b += delta;
        let angle = b.norm();
        if angle.is_nan() || angle >= std::f64::consts::PI {
            return fail(Failure::CutLocus, outcome);
        }
    }
    fail(Failure::IterationLimit, outcome)
}
