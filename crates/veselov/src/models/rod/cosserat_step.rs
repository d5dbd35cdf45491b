//! The rod's vertex solve split as in note 003 §3.6: the position part of
//! Leg_v(r₂, R₂) = μ_v is linear in r₂ and independent of R₂, so r₂ comes
//! from one 3×3 solve; the rotation part is then a 3-D equation in
//! b = log(R₀ᵀR₂), solved by Newton with its exact Jacobian in closed form
//! (`RotationEquation`), to round-off: it stops at the tolerance of
//! [`CauchyOptions`], measured, or after a step whose Taylor remainder
//! bound (`RotationEquation::newton_remainder_bound`) already meets it,
//! without the evaluation that would confirm it. The generic 6-D Newton
//! ([`solve_legendre`](crate::field::legendre::solve_legendre)) over the
//! same equations stays the reference.
//!
//! Position part (per cell based at v, σ = ±, with the damping of
//! [`RodLoads`](crate::models::rod::RodLoads)):
//! ∂Leg_r/∂r₂ = Σ_σ [−(ρΔs/(4Δt) + A_β c_r/(2Δt)) I − (Δt/(4Δs)) R₀C₁R₀ᵀ],
//! negative definite whenever ρ > 0 or C₁ ≻ 0 (always solvable); with the
//! centred shear frame ([`ShearFrame::Centred`], module `cosserat::shear`)
//! R₀ becomes each cell's R₀E_σ, and the shear's torques change as given
//! there.
//!
//! Rotation part:
//! Σ_σ [−(Δs/4)D_bJω_d + A_β(R₀ᵀg_σ)^C₁ε_σ + (σΔt/4)(2D_{a_σ} − D_b)C₂u_σ]
//! − Σ_σ (A_β c_R/(2Δt)) b + (loads at an end) = μ_R.
//!
//! Having a_σ, D_{a_σ}, b and D_b at hand, the solve also returns the solved
//! cells' gradients at their later vertices
//! (`CosseratCell::later_gradients`) and, with loads, their forces
//! (`CosseratCell::forces_with`, b being log(R₀ᵀR₂)), which the marcher
//! would otherwise compute from the vertex values.

use nalgebra::{Matrix3, SVector, Vector3};

use crate::ad::{mat3_mul, mat3_vec};
use crate::complex::TopCell;
use crate::field::cell::{SolvedVertex, VertexStar};
use crate::field::fibre::{Fibre, Pose, PositionRotation, Rotations};
use crate::field::legendre::{CauchyOptions, Failure, VertexOutcome};
use crate::lie::{series, so3};
use crate::models::rod::cosserat::{CentredFrame, CosseratCell, ShearFrame, StepConstants};
use crate::models::rod::potential::RodPotential;
use crate::solve::largest_abs;

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
    /// ‖X‖_F.
    linear_norm: f64,
    /// x(0).
    offset: Vector3<f64>,
    /// Y = dy/db.
    slope: Matrix3<f64>,
    /// y(0).
    constant: Vector3<f64>,
}

impl RotationEquation {
    /// The equation of the cells `arms` (one or two) with the material
    /// point's constants (κC₂ − λJ and −2κC₂ computed once per rod) and the
    /// damping c per cell.
    #[inline]
    pub(super) fn new(constants: &StepConstants, arms: &[RotationArm], damping: f64) -> Self {
        let n = arms.len() as f64;
        let c2 = &constants.c2_minus_two_kappa;
        let (mut a_sum, mut da_sum, mut constant) = (Vector3::zeros(), Matrix3::zeros(), Vector3::zeros());
        for arm in arms {
            a_sum += arm.a;
            da_sum += arm.da;
            constant += mat3_vec(&arm.da, &mat3_vec(c2, &arm.a));
        }
        let mut slope = mat3_mul(&da_sum, c2);
        for i in 0..3 {
            slope[(i, i)] -= n * damping;
        }
        Self {
            linear: constants.rotation_linear * n,
            linear_norm: constants.rotation_linear_norm * n,
            offset: mat3_vec(c2, &a_sum),
            slope,
            constant: constant * -2.0,
        }
    }

    /// A bound on the residual a full Newton step δ from b leaves:
    /// |T(b + δ) − T(b) − T′(b)δ|∞ ≤ ½ max_{[b, b+δ]} ‖T″‖ |δ|₂², which is
    /// the residual at b + δ when δ solves T′(b)δ = target − T(b) (up to
    /// that solve's rounding). From T = D_b x(b) + y(b) with x, y affine,
    /// T″[h, h] = 2(D′_b h)Lh + D″_b[h, h] x, and on |b| ≤ 1 (where
    /// 1/12 ≤ k ≤ 0.085, 0 < k′ ≤ 0.0015, 0 < k″ ≤ 1e-4)
    /// ‖D′_b h‖₂ ≤ (½ + 2k|b| + 2k′|b|³)|h| ≤ 0.68|h| and
    /// ‖D″_b[h, h]‖₂ ≤ (2k + 10k′|b|² + 4k″|b|⁴)|h|² ≤ 0.19|h|², so
    /// ‖T″‖ ≤ 1.5‖L‖_F + 0.25 max|x| with |x| ≤ |x(b)| + ‖L‖_F|δ| on the
    /// segment; the 2-norms of x and δ are taken as √3 times their
    /// max-norms (no square roots). `None` unless |b| ≤ 1 and |b + δ| ≤ 1.
    #[inline]
    pub(super) fn newton_remainder_bound(&self, b: &Vector3<f64>, delta: &Vector3<f64>) -> Option<f64> {
        remainder_bound(
            b.norm_squared(),
            (b + delta).norm_squared(),
            largest_abs(delta),
            largest_abs(&(mat3_vec(&self.linear, b) + self.offset)),
            self.linear_norm,
        )
    }

    /// T(b) with D_b given.
    pub(super) fn value_with(&self, b: &Vector3<f64>, db: &Matrix3<f64>) -> Vector3<f64> {
        db * (self.linear * b + self.offset) + self.slope * b + self.constant
    }

    /// T(b) and dT/db, written out entry by entry (see the type's
    /// documentation for the formulas).
    #[inline]
    pub(super) fn value_and_jacobian(&self, b: &Vector3<f64>) -> (Vector3<f64>, Matrix3<f64>) {
        let l = &self.linear;
        let x = mat3_vec(l, b) + self.offset;
        let b2 = b.norm_squared();
        let (k, dk) = series::dlog_and_derivative(b2);
        let bx = b.dot(&x);
        // w = b̂²x = b(b·x) − |b|²x; D_b x = x + ½ b×x + k w.
        let w = b * bx - x * b2;
        let value = x + b.cross(&x) * 0.5 + w * k + mat3_vec(&self.slope, b) + self.constant;
        // bᵀL, the rows of b̂L (b × each column of L), then
        // dT/db = L(1 − k|b|²) + ½b̂L + k b(bᵀL) − ½x̂ + k(b·x I + bxᵀ − 2xbᵀ) + 2k′ w bᵀ + S.
        let bl = Vector3::new(
            b[0] * l[(0, 0)] + b[1] * l[(1, 0)] + b[2] * l[(2, 0)],
            b[0] * l[(0, 1)] + b[1] * l[(1, 1)] + b[2] * l[(2, 1)],
            b[0] * l[(0, 2)] + b[1] * l[(1, 2)] + b[2] * l[(2, 2)],
        );
        let diag = 1.0 - k * b2;
        let dk2 = 2.0 * dk;
        // b̂L row by row: (b × L e_j)_i = b_{i+1}L_{i+2,j} − b_{i+2}L_{i+1,j}.
        let mut jacobian = Matrix3::zeros();
        for j in 0..3 {
            let cross = [
                b[1] * l[(2, j)] - b[2] * l[(1, j)],
                b[2] * l[(0, j)] - b[0] * l[(2, j)],
                b[0] * l[(1, j)] - b[1] * l[(0, j)],
            ];
            for i in 0..3 {
                jacobian[(i, j)] = l[(i, j)] * diag
                    + 0.5 * cross[i]
                    + k * (b[i] * (bl[j] + x[j]) - 2.0 * x[i] * b[j])
                    + dk2 * w[i] * b[j]
                    + self.slope[(i, j)];
            }
        }
        // −½x̂ + k(b·x)I.
        let kbx = k * bx;
        jacobian[(0, 0)] += kbx;
        jacobian[(1, 1)] += kbx;
        jacobian[(2, 2)] += kbx;
        jacobian[(0, 1)] += 0.5 * x[2];
        jacobian[(0, 2)] -= 0.5 * x[1];
        jacobian[(1, 0)] -= 0.5 * x[2];
        jacobian[(1, 2)] += 0.5 * x[0];
        jacobian[(2, 0)] += 0.5 * x[1];
        jacobian[(2, 1)] -= 0.5 * x[0];
        (value, jacobian)
    }
}

/// [`RotationEquation::newton_remainder_bound`] from |b|², |b + δ|²,
/// max|δᵢ|, max|x(b)ᵢ| and ‖X‖_F (the scalar and the lane solves alike).
#[inline]
pub(super) fn remainder_bound(b2: f64, next2: f64, delta_size: f64, x_size: f64, linear_norm: f64) -> Option<f64> {
    if b2 > 1.0 || next2 > 1.0 {
        return None;
    }
    const SQRT_3: f64 = 1.732_050_807_568_877_2;
    let d = SQRT_3 * delta_size;
    let x = SQRT_3 * x_size + linear_norm * d;
    Some(0.5 * (1.5 * linear_norm + 0.25 * x) * d * d)
}

/// One cell based at v: the cell (σ = + for shape 0) and the position at
/// its middle vertex v₁ (its rotation arm is kept beside it, at the same
/// index, in the array the rotation equation reads).
#[derive(Clone, Copy)]
struct StarCell {
    cell: TopCell,
    sigma: f64,
    r1: Vector3<f64>,
    /// ε at the solved position r₂ (in the cell's shear frame).
    eps: Vector3<f64>,
    /// The centred shear frame ([`ShearFrame::Centred`]), else `None`.
    frame: Option<CentredFrame>,
    /// The centred shear's torque at R₁ with ε at r₂ (zero in R₀'s frame),
    /// kept for the gradients.
    middle_torque: Vector3<f64>,
}

/// ε of cell `c` with its top at `r2`, in the cell's shear frame.
#[inline]
fn shear_strain<P: RodPotential>(
    lag: &CosseratCell<P>,
    c: &StarCell,
    s0: f64,
    y0: &Pose<f64>,
    r2: &Vector3<f64>,
) -> Vector3<f64> {
    let eps = lag.linear_strain(c.sigma, s0, y0, &c.r1, r2);
    c.frame.map_or(eps, |f| f.strain(&eps, lag.parameters_at(s0).strain()))
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
            forces_written: false,
        }
    };
    let (ds, dt) = (lag.ds(), lag.dt());
    let damp_q = lag.loads().map_or(0.0, |l| l.damping_angular);
    // The cells based at v with the extrapolated top: their Legendre terms
    // at (r₀, R₀)·(Δr, b) are affine in Δr, so one evaluation at the start
    // and the constant ∂Leg_r/∂r₂ give the position exactly.
    let blank = StarCell {
        cell: TopCell {
            index: 0,
            shape: 0,
            origin: [0; crate::complex::MAX_LATTICE_DIMENSION],
        },
        sigma: 1.0,
        r1: Vector3::zeros(),
        eps: Vector3::zeros(),
        frame: None,
        middle_torque: Vector3::zeros(),
    };
    let centred = lag.shear_frame() == ShearFrame::Centred;
    let mut cells = [blank; 2];
    let mut arms = [RotationArm {
        a: Vector3::zeros(),
        da: Matrix3::zeros(),
    }; 2];
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
                r1: y[1].position,
                eps: Vector3::zeros(),
                frame: centred.then(|| CentredFrame::at(&a)),
                middle_torque: Vector3::zeros(),
            };
            arms[count] = RotationArm {
                a,
                da: so3::dexp_inv(&(-a)),
            };
            count += 1;
        }
    }
    if count == 0 {
        return fail(Failure::Singular, outcome);
    }
    let (cells, arms) = (&mut cells[..count], &arms[..count]);
    // Both cells are based at v: its material point's parameters.
    let s0 = lag.material_coordinate(&cells[0].cell);
    let p = lag.parameters_at(s0);
    let y0 = y[0];
    let r0m = *y0.rotation.matrix();
    let constants = lag.constants_at(s0);
    let n = count as f64;
    // Σ_σ ∇_{r₀}L_{(v,σ)} at the start r₂ = 2r₀ − r₋:
    // n(−(ρΔs/4)v_d − (ΔsΔt/8)∇_rP) + (Δt/4)R₀C₁Σ_σ σε_σ (+ the forces).
    let start = y0.position * 2.0 - previous.position;
    let kinetic = (start - y0.position) * (-p.rho() * ds / (4.0 * dt));
    let weight = lag.density.potential.gradient(s0, &y0.position) * (-(ds * dt / 8.0));
    let mut scale = mu_scale + n * (largest_abs(&kinetic) + largest_abs(&weight));
    let mut strain_sum = Vector3::zeros();
    let mut forces = Vector3::zeros();
    for c in cells.iter() {
        let eps = shear_strain(lag, c, s0, &y0, &start);
        let c1e = p.c1() * eps * (0.25 * dt);
        // |R₀w|∞ ≥ |w|∞/√3: the body vector's size stands for the term's.
        scale += largest_abs(&c1e);
        strain_sum += c.frame.map_or(c1e, |f| f.rotation * c1e) * c.sigma;
        if let Some(loads) = lag.loads() {
            // F⁰'s position part at (start, R₀): the linear damping and the
            // end force ([`CosseratCell::cell_force`]'s terms in its order;
            // its rotation part, with a logarithm, is not needed here).
            let mut f = Vector3::zeros();
            if loads.damped() {
                f += lag.linear_damping(loads, &y0.position, &start);
            }
            if let Some((force, _)) = lag.end_load(loads, &c.cell, &y0) {
                f += force;
            }
            forces += f;
            scale += largest_abs(&f);
        }
    }
    let leg_r = (kinetic + weight) * n + mat3_vec(&r0m, &strain_sum) + forces;
    // ∂Leg_r/∂r₂ = −n R₀KR₀ᵀ: R₀ᵀ(r₂ − start) = −K⁻¹R₀ᵀ(μ_r − Leg_r)/n,
    // with K and K⁻¹ computed once per material point.
    let rhs = r0m.tr_mul(&(mu.fixed_rows::<3>(0) - leg_r));
    let (z, stiffness) = if centred {
        // Σ_σ [K + κ(E_σC₁E_σᵀ − C₁)] (module documentation of `shear`).
        let kappa = dt / (4.0 * ds);
        let mut stiffness = constants.stiffness * n;
        for f in cells.iter().filter_map(|c| c.frame) {
            stiffness += (f.rotation * p.c1() * f.rotation.transpose() - p.c1()) * kappa;
        }
        let Some(compliance) = stiffness.try_inverse() else {
            return fail(Failure::Singular, outcome);
        };
        (compliance * rhs, stiffness)
    } else {
        let Some(compliance) = constants.compliance else {
            return fail(Failure::Singular, outcome);
        };
        (compliance * rhs * n.recip(), constants.stiffness * n)
    };
    let r2 = start - mat3_vec(&r0m, &z);
    // The linear solve's residual, in the body frame.
    let residual_r = largest_abs(&(stiffness * z - rhs));
    if !residual_r.is_finite() || !r2.iter().all(|x| x.is_finite()) {
        // Reported as a NaN residual, not the default zero.
        outcome.relative_residual = f64::NAN;
        return fail(Failure::NonFinite, outcome);
    }
    // The b-independent rotation terms: A_β(R₀ᵀg_σ)^C₁ε_σ (and the end
    // load's torque), with r₂ known; ε_σ is kept for the gradients.
    let mut fixed = Vector3::zeros();
    let mut fixed_scale = 0.0;
    for (c, arm) in cells.iter_mut().zip(arms) {
        let eps = shear_strain(lag, c, s0, &y0, &r2);
        c.eps = eps;
        let torque = lag.strain_torque(s0, &eps);
        let strain_term = match c.frame {
            None => torque,
            Some(f) => {
                let (base, middle) = f.torques(&arm.da, &torque);
                c.middle_torque = middle;
                base
            }
        };
        fixed += strain_term;
        fixed_scale += largest_abs(&strain_term);
        if let Some(loads) = lag.loads() {
            // F⁰'s rotation part at (r₂, R₀) has no damping torque
            // (log(R₀ᵀR₀) = 0 exactly): only the end load's torque.
            let load = lag
                .end_load(loads, &c.cell, &y0)
                .map_or_else(Vector3::zeros, |(_, torque)| torque);
            fixed += load;
            fixed_scale += largest_abs(&load);
        }
    }
    let cells = &cells[..];
    let target = mu.fixed_rows::<3>(3) - fixed;
    // The solved vertex: R₂ = R₀ exp(b̂) projected back onto SO(3), and the
    // solved cells' gradients from the stored value, as the marcher computes
    // them from values (a resumed march recomputes them so).
    let mut finish = |b: Vector3<f64>, outcome: VertexOutcome| {
        if b.norm() >= std::f64::consts::PI {
            return fail(Failure::CutLocus, outcome);
        }
        let rotation = y0.rotation.compose(&so3::exp(&b));
        let value = PositionRotation::renormalize(&Pose::new(r2, rotation));
        let Ok(b) = Rotations::log(&y0.rotation, &value.rotation) else {
            return fail(Failure::CutLocus, outcome);
        };
        write_gradients(lag, (cells, arms), s0, &y0, &r2, &b, gradients);
        let forces_written = write_forces(lag, cells, &y0, &value.position, &b, gradients);
        SolvedVertex {
            value,
            outcome,
            gradients_written: true,
            forces_written,
        }
    };
    let equation = RotationEquation::new(constants, arms, lag.area() * damp_q / (2.0 * dt));
    let mut b = Rotations::log(&previous.rotation, &y0.rotation).unwrap_or_else(|_| Vector3::zeros());
    // Newton with the exact Jacobian (closed form, as cheap as the residual).
    let mut previous = f64::INFINITY;
    let mut last_step = f64::INFINITY;
    for it in 0..=options.max_iterations {
        let (value, jacobian) = equation.value_and_jacobian(&b);
        outcome.jacobians += 1;
        let residual = value - target;
        let r = crate::solve::max_abs(&residual);
        outcome.iterations = it;
        let terms = (scale + fixed_scale + largest_abs(&value)).max(f64::MIN_POSITIVE);
        outcome.relative_residual = r.max(residual_r) / terms;
        if !r.is_finite() {
            // f64::max would hide a NaN behind residual_r.
            outcome.relative_residual = r;
            return fail(Failure::NonFinite, outcome);
        }
        let inverse = jacobian.try_inverse();
        // The size of the Jacobian's terms only where the stall test needs it.
        let stalled = r > 0.5 * previous
            && (r <= 100.0 * options.tolerance * (terms + largest_abs(&jacobian) * (1.0 + largest_abs(&b)))
                || last_step <= 64.0 * f64::EPSILON * (1.0 + largest_abs(&b)));
        if r <= options.tolerance * terms || stalled {
            // One last correction with the Jacobian at hand (no further
            // evaluation): from a converged iterate Newton's step only
            // removes the remaining residual (quadratic convergence).
            if let Some(inv) = inverse {
                let delta = -(inv * residual);
                if largest_abs(&delta) < 1e-3 {
                    b += delta;
                }
            }
            return finish(b, outcome);
        }
        previous = r;
        if it == options.max_iterations {
            break;
        }
        let Some(inv) = inverse else {
            return fail(Failure::Singular, outcome);
        };
        let delta = -(inv * residual);
        let remainder = equation.newton_remainder_bound(&b, &delta);
        last_step = largest_abs(&delta);
        b += delta;
        let angle = b.norm();
        if angle.is_nan() || angle >= std::f64::consts::PI {
            return fail(Failure::CutLocus, outcome);
        }
        if let Some(remainder) = remainder
            && remainder <= options.tolerance * terms
        {
            // Plus the rounding of δ through the computed inverse:
            // |Jδ + residual|∞ ≤ 12ε κ∞(J) |residual|∞.
            let norm = |m: &Matrix3<f64>| largest_abs(&m.abs().column_sum());
            let bound = remainder + 12.0 * f64::EPSILON * norm(&jacobian) * norm(&inv) * r;
            if bound <= options.tolerance * terms {
                // The evaluation that would confirm it is skipped; the
                // bound is reported as the residual.
                outcome.iterations = it + 1;
                outcome.relative_residual = bound.max(residual_r) / terms;
                return finish(b, outcome);
            }
        }
    }
    fail(Failure::IterationLimit, outcome)
}

/// The solved cells' forces (F⁰, F¹, F²) with the top (r₂, R₂),
/// b = log(R₀ᵀR₂), after the gradients in the marcher's layout (cell σ at
/// 6 + 3σ + l, zero for a cell outside the action), by
/// [`CosseratCell::forces_with`]: the bits of `cell_forces` at the stored
/// value, without its logarithm. `false` (nothing written) without loads
/// or without room for them.
fn write_forces<P: RodPotential>(
    lag: &CosseratCell<P>,
    cells: &[StarCell],
    y0: &Pose<f64>,
    r2: &Vector3<f64>,
    b: &Vector3<f64>,
    terms: &mut [SVector<f64, 6>],
) -> bool {
    let Some(loads) = lag.loads() else {
        return false;
    };
    let Some(forces) = terms.get_mut(6..12) else {
        return false;
    };
    forces.fill(SVector::zeros());
    for c in cells {
        let base = 3 * c.cell.shape;
        forces[base..base + 3].copy_from_slice(&lag.forces_with(loads, &c.cell, y0, r2, Some(b)));
    }
    true
}

/// The solved cells' gradients at positions 1 and 2 with the top
/// (r₂, R₀ exp(b̂)), into the marcher's layout (zero elsewhere): the same
/// operations as [`CosseratCell::gradients`] on those values, so the same
/// bits.
fn write_gradients<P: RodPotential>(
    lag: &CosseratCell<P>,
    (cells, arms): (&[StarCell], &[RotationArm]),
    s0: f64,
    y0: &Pose<f64>,
    r2: &Vector3<f64>,
    b: &Vector3<f64>,
    gradients: &mut [SVector<f64, 6>],
) {
    gradients.fill(SVector::zeros());
    let db = so3::dexp_inv(&(-b));
    let top = Pose::new(*r2, y0.rotation);
    for (c, arm) in cells.iter().zip(arms) {
        let q = lag.quantities_from_strain(c.sigma, s0, [y0, &top], arm.a, *b, c.eps);
        let base = 3 * c.cell.shape;
        let frame = c
            .frame
            .map_or(*y0.rotation.matrix(), |f| y0.rotation.matrix() * f.rotation);
        let middle = c.frame.map(|_| &c.middle_torque);
        let later = lag.later_gradients(&q, &frame, middle, &arm.da, &db);
        gradients[base + 1..base + 3].copy_from_slice(&later);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::rod::cosserat::RodParameters;

    /// Δs, Δt and the damping of the sample equation.
    const DS: f64 = 0.1;
    const DT: f64 = 0.03;
    const DAMPING: f64 = 0.7;

    /// Sample material parameters (J, C₂ not diagonal) and two rotation
    /// arms: the rotation equation of an interior vertex.
    fn sample() -> (RodParameters, [RotationArm; 2]) {
        let inertia = Matrix3::new(2.0, 0.1, 0.0, 0.1, 1.5, 0.2, 0.0, 0.2, 1.0);
        let c2 = Matrix3::new(3.0, 0.2, 0.1, 0.2, 2.0, 0.0, 0.1, 0.0, 4.0);
        let p = RodParameters::new(1.3, inertia, Matrix3::identity() * 5.0, c2, Vector3::new(0.0, 0.0, 1.0))
            .expect("valid");
        let arm = |a: Vector3<f64>| RotationArm {
            a,
            da: so3::dexp_inv(&(-a)),
        };
        (
            p,
            [arm(Vector3::new(0.1, -0.05, 0.2)), arm(Vector3::new(-0.3, 0.1, 0.05))],
        )
    }

    /// The Taylor remainder bound holds the residual a Newton step actually
    /// leaves (evaluated), from starts at several distances from the
    /// solution, and the curvature bound behind it holds the second
    /// difference of T along random directions on |b| ≤ 1.
    #[test]
    fn newton_remainder_bound_holds_the_residual_left() {
        let (p, arms) = sample();
        let eq = RotationEquation::new(&StepConstants::new(&p, DS, DT, 0.0), &arms, DAMPING);
        let solution = Vector3::new(0.2, -0.1, 0.3);
        let target = eq.value_and_jacobian(&solution).0;
        let mut bounded = 0;
        for distance in [1e-6, 1e-4, 1e-2, 0.1, 0.3] {
            let start = solution + Vector3::new(1.0, -2.0, 0.5) * distance;
            let (value, jacobian) = eq.value_and_jacobian(&start);
            let delta = -(jacobian.try_inverse().expect("regular") * (value - target));
            let left = (eq.value_and_jacobian(&(start + delta)).0 - target).amax();
            if let Some(bound) = eq.newton_remainder_bound(&start, &delta) {
                bounded += 1;
                assert!(
                    left <= bound + 16.0 * f64::EPSILON * target.amax(),
                    "distance {distance}: left {left:.2e} above the bound {bound:.2e}"
                );
            }
        }
        assert_eq!(bounded, 5, "every start lies in |b| ≤ 1");
        // ‖T″[h, h]‖ ≤ (1.5‖L‖_F + 0.25|x|)|h|² by second differences.
        let l = eq.linear.norm();
        let mut uniform = crate::test_support::uniform(0x2545_f491_4f6c_dd1d);
        for _ in 0..200 {
            let b = Vector3::new(uniform(), uniform(), uniform()) * 1.1;
            let h = Vector3::new(uniform(), uniform(), uniform()).normalize();
            let e = 1e-3;
            let t = |z: Vector3<f64>| eq.value_and_jacobian(&z).0;
            let second = (t(b + h * e) - t(b) * 2.0 + t(b - h * e)) / (e * e);
            let x = (eq.linear * b + eq.offset).norm();
            let bound = 1.5 * l + 0.25 * x;
            assert!(
                second.norm() <= bound,
                "T″ {:.3e} above {bound:.3e} at {b}",
                second.norm()
            );
        }
    }

    /// The closed-form T(b) and dT/db against central differences of T and
    /// against T summed cell by cell from so3::dexp_inv.
    #[test]
    fn rotation_equation_matches_its_definition_and_differences() {
        let (p, arms) = sample();
        let (inertia, c2) = (*p.inertia(), *p.c2());
        let (ds, dt, damping) = (DS, DT, DAMPING);
        let eq = RotationEquation::new(&StepConstants::new(&p, ds, dt, 0.0), &arms, damping);
        for b in [
            Vector3::new(0.0, 0.0, 0.0),
            Vector3::new(1e-4, -2e-4, 3e-5),
            Vector3::new(0.2, -0.1, 0.3),
            Vector3::new(1.5, 0.7, -1.2),
        ] {
            let (value, jacobian) = eq.value_and_jacobian(&b);
            let db = so3::dexp_inv(&(-b));
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
