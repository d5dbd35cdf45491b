//! The rod's vertex solve split as in note 003 §3.6: the position part of
//! Leg_v(r₂, R₂) = μ_v is linear in r₂ and independent of R₂, so r₂ comes
//! from one 3×3 solve; the rotation part is then a 3-D equation in
//! b = log(R₀ᵀR₂), solved by Newton with its exact Jacobian in closed form
//! ([`RotationEquation`]), to round-off. The generic 6-D Newton
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
//!
//! Having a_σ, D_{a_σ}, b and D_b at hand, the solve also returns the solved
//! cells' gradients at their later vertices
//! ([`CosseratCell::later_gradients`]), which the marcher would otherwise
//! recompute from the vertex values.

use nalgebra::{Matrix3, SVector, Vector3};

use super::cosserat::{CosseratCell, RodParameters};
use super::rod_potential::RodPotential;
use crate::ad::{mat3_mul, mat3_vec};
use crate::field::cell::{DiscreteLagrangian, SolvedVertex, VertexStar};
use crate::field::complex::TopCell;
use crate::field::fibre::{Fibre, Pose, PositionRotation, Rotations};
use crate::field::legendre::{CauchyOptions, Failure, VertexOutcome};
use crate::lie::{series, so3};

/// One cell based at v in the rotation equation: a = log(R₀ᵀR₁) and
/// D_a = dlog a (left-trivialised, `so3::dexp_inv(−a)`).
#[derive(Clone, Copy, Debug)]
pub(super) struct RotationArm {
    pub(super) a: Vector3<f64>,
    pub(super) da: Matrix3<f64>,
}

/// The terms of Σ_σ ∇_{R₀}L_{(v,σ)} that depend on b (note 003 §3.5), over
/// the cells σ based at v (σ cancels: (σΔt/4)·1/(σΔs) = Δt/(4Δs) = κ;
/// λ = Δs/(4Δt)), with a damping −c·b per cell:
///
/// T(b) = Σ_σ [−λ D_b J b + κ(2D_{a_σ} − D_b)C₂(2a_σ − b)] − n c b
///      = D_b x(b) + y(b),
///
/// x(b) = n(κC₂ − λJ) b − 2κC₂ Σa_σ (the vector D_b acts on) and
/// y(b) = 4κ Σ D_{a_σ}C₂a_σ − (2κ (ΣD_{a_σ}) C₂ + n c I) b, both affine.
/// With D_b = I + ½b̂ + k(|b|²)b̂² (k of note 003 Def. 6.9) the Jacobian is
/// dT/db = D_b X + ∂_b(D_b x)|ₓ + Y,
/// ∂_b(D_b x)|ₓ = −½x̂ + k[(b·x)I + bxᵀ − 2xbᵀ] + 2k′(|b|²)(b̂²x)bᵀ.
#[derive(Clone, Copy, Debug)]
pub(super) struct RotationEquation {
    /// X = dx/db.
    linear: Matrix3<f64>,
    /// x(0).
    offset: Vector3<f64>,
    /// Y = dy/db.
    slope: Matrix3<f64>,
    /// y(0).
    constant: Vector3<f64>,
}

/// D_b = I + ½b̂ + k b̂² with b̂² = bbᵀ − |b|²I.
fn dlog_matrix(b: &Vector3<f64>, k: f64) -> Matrix3<f64> {
    Matrix3::identity() * (1.0 - k * b.norm_squared()) + so3::hat(b) * 0.5 + b * b.transpose() * k
}

impl RotationEquation {
    /// The equation of the cells `arms` (one or two) with material
    /// parameters `p`, spacings Δs, Δt and the damping c per cell.
    pub(super) fn new(p: &RodParameters, ds: f64, dt: f64, arms: &[RotationArm], damping: f64) -> Self {
        let n = arms.len() as f64;
        let (kappa, lambda) = (dt / (4.0 * ds), ds / (4.0 * dt));
        let (mut a_sum, mut da_sum, mut constant) = (Vector3::zeros(), Matrix3::zeros(), Vector3::zeros());
        for arm in arms {
            a_sum += arm.a;
            da_sum += arm.da;
            constant += arm.da * (p.c2() * arm.a);
        }
        Self {
            linear: (p.c2() * kappa - p.inertia() * lambda) * n,
            offset: p.c2() * a_sum * (-2.0 * kappa),
            slope: mat3_mul(&da_sum, p.c2()) * (-2.0 * kappa) - Matrix3::identity() * (n * damping),
            constant: constant * (4.0 * kappa),
        }
    }

    /// T(b) with D_b given.
    pub(super) fn value_with(&self, b: &Vector3<f64>, db: &Matrix3<f64>) -> Vector3<f64> {
        db * (self.linear * b + self.offset) + self.slope * b + self.constant
    }

    /// T(b), dT/db and D_b.
    pub(super) fn value_and_jacobian(&self, b: &Vector3<f64>) -> (Vector3<f64>, Matrix3<f64>, Matrix3<f64>) {
        let x = self.linear * b + self.offset;
        let b2 = b.norm_squared();
        let (k, dk) = series::dlog_and_derivative(b2);
        let bx = b.dot(&x);
        let b2x = b * bx - x * b2;
        let db = dlog_matrix(b, k);
        let value = x + b.cross(&x) * 0.5 + b2x * k + self.slope * b + self.constant;
        let d_dlog = -so3::hat(&x) * 0.5
            + (Matrix3::identity() * bx + b * x.transpose() - x * b.transpose() * 2.0) * k
            + b2x * b.transpose() * (2.0 * dk);
        (value, mat3_mul(&db, &self.linear) + d_dlog + self.slope, db)
    }
}

/// One cell based at v: the cell (σ = + for shape 0), the value at its
/// middle vertex v₁ and its rotation arm.
#[derive(Clone, Copy)]
struct StarCell {
    cell: TopCell,
    sigma: f64,
    y1: Pose<f64>,
    arm: RotationArm,
}

/// Solves the vertex equation of the rod by the split step (see the module
/// documentation) from the value one flow step back, `previous`
/// (y_{v−Δ}: the first guesses are r₂ = 2r₀ − r₋ and b = log(R₋ᵀR₀), the
/// linear extrapolation without its products); reports like the generic
/// solve and writes
/// the solved cells' gradients at positions 1, 2 into `gradients` (the
/// marcher's layout: cell σ at 3σ + l).
pub(crate) fn split_solve<P: RodPotential>(
    lag: &CosseratCell<P>,
    star: &VertexStar<'_, Pose<f64>>,
    mu: &SVector<f64, 6>,
    mu_scale: f64,
    previous: &Pose<f64>,
    options: &CauchyOptions,
    gradients: &mut [SVector<f64, 6>],
) -> SolvedVertex<Pose<f64>> {
    let mut outcome = VertexOutcome::default();
    let fail = |failure, mut outcome: VertexOutcome| {
        outcome.failure = Some(failure);
        SolvedVertex {
            value: *previous,
            outcome,
            gradients_written: false,
        }
    };
    let (ds, dt) = (lag.ds(), lag.dt());
    let (damp_r, damp_q) = lag
        .loads()
        .map_or((0.0, 0.0), |l| (l.damping_linear, l.damping_angular));
    // The cells based at v with the extrapolated top: their Legendre terms
    // at (r₀, R₀)·(Δr, b) are affine in Δr, so one evaluation at the start
    // and the constant ∂Leg_r/∂r₂ give the position exactly.
    let blank = StarCell {
        cell: TopCell {
            index: 0,
            shape: 0,
            origin: [0; crate::field::complex::MAX_LATTICE_DIMENSION],
        },
        sigma: 1.0,
        y1: *previous,
        arm: RotationArm {
            a: Vector3::zeros(),
            da: Matrix3::zeros(),
        },
    };
    let mut cells = [blank; 2];
    let mut count = 0;
    let mut y = [*previous; 3];
    for shape in 0..2 {
        if let Some(cell) = star(shape, &mut y) {
            let Ok(a) = Rotations::log(&y[0].rotation, &y[1].rotation) else {
                return fail(Failure::CutLocus, outcome);
            };
            cells[count] = StarCell {
                cell,
                sigma: if cell.shape == 0 { 1.0 } else { -1.0 },
                y1: y[1],
                arm: RotationArm {
                    a,
                    da: so3::dexp_inv(&(-a)),
                },
            };
            count += 1;
        }
    }
    if count == 0 {
        return fail(Failure::Singular, outcome);
    }
    let cells = &cells[..count];
    // Both cells are based at v: its material point's parameters.
    let s0 = lag.material_coordinate(&cells[0].cell);
    let p = *lag.parameters_at(s0);
    let y0 = y[0];
    let r0m = *y0.rotation.matrix();
    let loaded = damp_r > 0.0 || lag.loads().is_some();
    let mut leg_r = Vector3::zeros();
    let mut scale = mu_scale;
    let start = Pose::new(y0.position * 2.0 - previous.position, y0.rotation);
    let v = (start.position - y0.position) * dt.recip();
    for c in cells {
        let (_, eps) = lag.linear_strain(c.sigma, s0, &y0, &c.y1.position, &start.position);
        let g = lag.position_gradient(c.sigma, s0, &y0, &v, &eps);
        let f = if loaded {
            lag.cell_force(&c.cell, &[y0, c.y1, start], 0)
                .fixed_rows::<3>(0)
                .into_owned()
        } else {
            Vector3::zeros()
        };
        leg_r += g + f;
        scale += g.amax() + f.amax();
    }
    // ∂Leg_r/∂r₂ = −n R₀KR₀ᵀ with K = αI + βC₁, inverted through K alone.
    let n = count as f64;
    let stiffness = Matrix3::identity() * (p.rho() * ds / (4.0 * dt) + lag.area() * damp_r / (2.0 * dt))
        + p.c1() * (dt / (4.0 * ds));
    let Some(compliance) = stiffness.try_inverse() else {
        return fail(Failure::Singular, outcome);
    };
    let rhs = mu.fixed_rows::<3>(0) - leg_r;
    let step = mat3_vec(&r0m, &(compliance * r0m.tr_mul(&rhs))) * (-1.0 / n);
    let r2 = start.position + step;
    let applied = mat3_vec(&r0m, &(stiffness * r0m.tr_mul(&step))) * (-n);
    let residual_r = (leg_r + applied - mu.fixed_rows::<3>(0)).amax();
    if !residual_r.is_finite() {
        return fail(Failure::NonFinite, outcome);
    }
    // The b-independent rotation terms: A_β(R₀ᵀg_σ)^C₁ε_σ (and the end
    // load's torque), with r₂ known.
    let mut fixed = Vector3::zeros();
    let mut fixed_scale = 0.0;
    for c in cells {
        let (g, eps) = lag.linear_strain(c.sigma, s0, &y0, &c.y1.position, &r2);
        let strain_term = lag.strain_torque(s0, &r0m, &g, &eps);
        fixed += strain_term;
        fixed_scale += strain_term.amax();
        if lag.loads().is_some() {
            // The force at (r₂, R₀) has no damping torque (b = 0): only the end load.
            let y = [y0, c.y1, Pose::new(r2, y0.rotation)];
            let load = lag.cell_force(&c.cell, &y, 0).fixed_rows::<3>(3).into_owned();
            fixed += load;
            fixed_scale += load.amax();
        }
    }
    let target = mu.fixed_rows::<3>(3) - fixed;
    let mut arms = [blank.arm; 2];
    for (arm, c) in arms.iter_mut().zip(cells) {
        *arm = c.arm;
    }
    let equation = RotationEquation::new(&p, ds, dt, &arms[..count], lag.area() * damp_q / (2.0 * dt));
    let mut b = Rotations::log(&previous.rotation, &y0.rotation).unwrap_or_else(|_| Vector3::zeros());
    // Newton with the exact Jacobian (closed form, as cheap as the residual).
    let mut previous = f64::INFINITY;
    let mut last_step = f64::INFINITY;
    for it in 0..=options.max_iterations {
        let (value, jacobian, _) = equation.value_and_jacobian(&b);
        outcome.jacobians += 1;
        let residual = value - target;
        let r = crate::solve::max_abs(&residual);
        outcome.iterations = it;
        let terms = scale + fixed_scale + value.amax();
        outcome.relative_residual = r.max(residual_r) / terms.max(f64::MIN_POSITIVE);
        if !r.is_finite() {
            return fail(Failure::NonFinite, outcome);
        }
        let inverse = jacobian.try_inverse();
        let jacobian_scale = jacobian.amax() * (1.0 + b.amax());
        let stalled = r > 0.5 * previous
            && (r <= 100.0 * options.tolerance * (terms + jacobian_scale)
                || last_step <= 64.0 * f64::EPSILON * (1.0 + b.amax()));
        if r <= options.tolerance * terms || stalled {
            // One last correction with the Jacobian at hand (no further
            // evaluation): from a converged iterate Newton's step only
            // removes the remaining residual (quadratic convergence).
            if let Some(inv) = inverse {
                let delta = -(inv * residual);
                if delta.amax() < 1e-3 {
                    b += delta;
                }
            }
            if b.norm() >= std::f64::consts::PI {
                return fail(Failure::CutLocus, outcome);
            }
            let rotation = y0.rotation.compose(&so3::exp(&b));
            let value = PositionRotation::renormalize(&Pose::new(r2, rotation));
            // The gradients from the stored value, as the marcher computes
            // them from values (a resumed march recomputes them so).
            let Ok(b) = Rotations::log(&y0.rotation, &value.rotation) else {
                return fail(Failure::CutLocus, outcome);
            };
            write_gradients(lag, cells, s0, &y0, &r2, &b, gradients);
            return SolvedVertex {
                value,
                outcome,
                gradients_written: true,
            };
        }
        previous = r;
        if it == options.max_iterations {
            break;
        }
        let Some(inv) = inverse else {
            return fail(Failure::Singular, outcome);
        };
        let delta = -(inv * residual);
        last_step = delta.amax();
        b += delta;
        let angle = b.norm();
        if angle.is_nan() || angle >= std::f64::consts::PI {
            return fail(Failure::CutLocus, outcome);
        }
    }
    fail(Failure::IterationLimit, outcome)
}

/// The solved cells' gradients at positions 1 and 2 with the top
/// (r₂, R₀ exp(b̂)), into the marcher's layout (zero elsewhere): the same
/// operations as [`CosseratCell::gradients`] on those values, so the same
/// bits.
fn write_gradients<P: RodPotential>(
    lag: &CosseratCell<P>,
    cells: &[StarCell],
    s0: f64,
    y0: &Pose<f64>,
    r2: &Vector3<f64>,
    b: &Vector3<f64>,
    gradients: &mut [SVector<f64, 6>],
) {
    gradients.fill(SVector::zeros());
    let db = so3::dexp_inv(&(-b));
    let top = Pose::new(*r2, y0.rotation);
    for c in cells {
        let q = lag.quantities(c.sigma, s0, [y0, &c.y1, &top], c.arm.a, *b);
        let later = lag.later_gradients(&q, y0.rotation.matrix(), &c.arm.da, &db);
        let base = 3 * c.cell.shape;
        gradients[base + 1..base + 3].copy_from_slice(&later);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed-form T(b) and dT/db against central differences of T and
    /// against T summed cell by cell from so3::dexp_inv.
    #[test]
    fn rotation_equation_matches_its_definition_and_differences() {
        let inertia = Matrix3::new(2.0, 0.1, 0.0, 0.1, 1.5, 0.2, 0.0, 0.2, 1.0);
        let c2 = Matrix3::new(3.0, 0.2, 0.1, 0.2, 2.0, 0.0, 0.1, 0.0, 4.0);
        let p = RodParameters::new(1.3, inertia, Matrix3::identity() * 5.0, c2, Vector3::new(0.0, 0.0, 1.0))
            .expect("valid");
        let (ds, dt, damping) = (0.1, 0.03, 0.7);
        let arm = |a: Vector3<f64>| RotationArm {
            a,
            da: so3::dexp_inv(&(-a)),
        };
        let arms = [arm(Vector3::new(0.1, -0.05, 0.2)), arm(Vector3::new(-0.3, 0.1, 0.05))];
        let eq = RotationEquation::new(&p, ds, dt, &arms, damping);
        for b in [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1e-4, -2e-4, 3e-5),
            Vector3::new(0.2, -0.1, 0.3),
            Vector3::new(1.5, 0.7, -1.2),
        ] {
            let (value, jacobian, db) = eq.value_and_jacobian(&b);
            assert!((db - so3::dexp_inv(&(-b))).amax() < 1e-15);
            // Cell by cell: −(Δs/4)D_bJb/Δt + (σΔt/4)(2D_a − D_b)C₂(2a − b)/(σΔs) − c b.
            let mut direct = Vector3::zeros();
            for arm in &arms {
                direct += -db * (inertia * b) * (ds / (4.0 * dt))
                    + (arm.da * 2.0 - db) * (c2 * (arm.a * 2.0 - b)) * (dt / (4.0 * ds))
                    - b * damping;
            }
            assert!((value - direct).amax() <= 1e-14 * direct.amax().max(1.0), "T at {b}");
            let h = 1e-6;
            for j in 0..3 {
                let mut e = Vector3::zeros();
                e[j] = h;
                let fd = (eq.value_and_jacobian(&(b + e)).0 - eq.value_and_jacobian(&(b - e)).0) / (2.0 * h);
                let err = (fd - jacobian.column(j)).amax();
                assert!(err <= 1e-8 * jacobian.amax(), "column {j} at {b}: {err:.1e}");
            }
        }
    }
}
