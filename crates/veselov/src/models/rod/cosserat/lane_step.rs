//! The split vertex step of note 003 §3.6 ([`crate::models::rod::cosserat_step`])
//! for `L` vertices of a level side by side ([`CosseratCell::solve_group`]):
//! the same operations in the same order, in lanes ([`crate::models::rod::cosserat::lanes`]), so
//! that every vertex gets the bits of its own scalar solve whatever the
//! others. It covers the common vertex — both cells of its star in the
//! action and without the end load (damping included), rotations within the
//! series branches of the SO(3) maps, a Newton solve that ends by the
//! tolerance, the stall test or the remainder bound — and leaves any other
//! vertex to the scalar step, which
//! then reproduces its failure or solves it; a group with a lane outside
//! the series branches is left to it whole.
//!
//! A vertex v of the leapfrog lattice solves for r₂, then for
//! b = log(R₀ᵀR₂) from T(b) = target ([`RotationEquation`]'s formulas).
//!
//! [`RotationEquation`]: crate::models::rod::cosserat_step::RotationEquation

use nalgebra::{Matrix3, SVector};

use crate::field::cell::SolvedVertex;
use crate::field::fibre::Pose;
use crate::field::legendre::{CauchyOptions, VertexOutcome};
use crate::lie::series_lanes;
use crate::lie::so3::SO3;
use crate::models::rod::cosserat::lane_run::LaneInput;
use crate::models::rod::cosserat::lanes::{
    Lanes, M3, V3, add, cross, dexp, dexp_inv, dot, exp, gather_m3, gather_v3, inverse, lane_m3, lane_v3, largest_abs,
    largest_abs_m3, log, mm, mv, neg, renormalize, row_sum_norm, scale, scale_by, sub, tmm, tmv, transpose,
};
use crate::models::rod::cosserat::{CosseratCell, ShearFrame, join};
use crate::models::rod::cosserat_step::remainder_bound;
use crate::models::rod::potential::RodPotential;
use crate::solve::max_abs;

/// [`RotationEquation`](crate::models::rod::cosserat_step::RotationEquation) in
/// lanes: T(b) = D_b x(b) + y(b), x = Xb + x₀, y = Yb + y₀.
struct LaneEquation<const L: usize> {
    linear: M3<L>,
    linear_norm: Lanes<L>,
    offset: V3<L>,
    slope: M3<L>,
    constant: V3<L>,
}

impl<const L: usize> LaneEquation<L> {
    /// T(b) and dT/db (`RotationEquation::value_and_jacobian`), `None`
    /// unless every |b|² < 4.
    #[inline(always)]
    fn value_and_jacobian(&self, b: &V3<L>) -> Option<(V3<L>, M3<L>)> {
        let l = &self.linear;
        let x = add(&mv(l, b), &self.offset);
        let b2 = dot(b, b);
        let (k, dk) = series_lanes::dlog_and_derivative(&b2.0)?;
        let (k, dk) = (Lanes(k), Lanes(dk));
        let bx = dot(b, &x);
        let w = sub(&scale(b, bx), &scale(&x, b2));
        let value = add(
            &add(
                &add(&add(&x, &scale_by(&cross(b, &x), 0.5)), &scale(&w, k)),
                &mv(&self.slope, b),
            ),
            &self.constant,
        );
        let bl = tmv(l, b);
        let diag = Lanes::splat(1.0) - k * b2;
        let dk2 = dk * 2.0;
        let mut jacobian: M3<L> = [[Lanes::splat(0.0); 3]; 3];
        for j in 0..3 {
            let crossed = [
                b[1] * l[2][j] - b[2] * l[1][j],
                b[2] * l[0][j] - b[0] * l[2][j],
                b[0] * l[1][j] - b[1] * l[0][j],
            ];
            for i in 0..3 {
                jacobian[i][j] = l[i][j] * diag
                    + crossed[i] * 0.5
                    + k * (b[i] * (bl[j] + x[j]) - x[i] * 2.0 * b[j])
                    + dk2 * w[i] * b[j]
                    + self.slope[i][j];
            }
        }
        let kbx = k * bx;
        for i in 0..3 {
            jacobian[i][i] = jacobian[i][i] + kbx;
        }
        jacobian[0][1] = jacobian[0][1] + x[2] * 0.5;
        jacobian[0][2] = jacobian[0][2] - x[1] * 0.5;
        jacobian[1][0] = jacobian[1][0] - x[2] * 0.5;
        jacobian[1][2] = jacobian[1][2] + x[0] * 0.5;
        jacobian[2][0] = jacobian[2][0] + x[1] * 0.5;
        jacobian[2][1] = jacobian[2][1] - x[0] * 0.5;
        Some((value, jacobian))
    }
}

/// ε = R₀ᵀ(2r₁ − r₀ − r₂)/(σΔs) − e (`CosseratCell::linear_strain`).
#[inline(always)]
fn linear_strain<const L: usize>(
    sigma_inv_ds: f64,
    r0m: &M3<L>,
    r0: &V3<L>,
    r1: &V3<L>,
    r2: &V3<L>,
    strain: &V3<L>,
) -> V3<L> {
    let g = scale_by(&sub(&sub(&scale_by(r1, 2.0), r0), r2), sigma_inv_ds);
    sub(&tmv(r0m, &g), strain)
}

/// The centred shear frame of a cell in lanes (`CentredFrame`): E = exp(a/2)
/// and J_r(a/2)ᵀ = dexp_{a/2}.
#[derive(Clone, Copy)]
struct LaneFrame<const L: usize> {
    rotation: M3<L>,
    jacobian_t: M3<L>,
}

impl<const L: usize> LaneFrame<L> {
    /// `CentredFrame::at`, `None` unless every |a/2|² < 1.
    #[inline(always)]
    fn at(a: &V3<L>) -> Option<Self> {
        let half = scale_by(a, 0.5);
        Some(Self {
            rotation: exp(&half)?,
            jacobian_t: dexp(&half)?,
        })
    }

    /// `CentredFrame::strain`: Eᵀ(ε₀ + e) − e.
    #[inline(always)]
    fn strain(&self, eps_at_vertex: &V3<L>, e: &V3<L>) -> V3<L> {
        sub(&tmv(&self.rotation, &add(eps_at_vertex, e)), e)
    }

    /// `CentredFrame::torques`: (Eτ − D_a h, D_aᵀh), h = ½J_r(a/2)ᵀτ.
    #[inline(always)]
    fn torques(&self, da: &M3<L>, tau: &V3<L>) -> (V3<L>, V3<L>) {
        let half = scale_by(&mv(&self.jacobian_t, tau), 0.5);
        (sub(&mv(&self.rotation, tau), &mv(da, &half)), tmv(da, &half))
    }
}

/// The solve's state in one lane.
#[derive(Clone, Copy)]
enum LaneState {
    Iterating,
    Solved,
    Scalar,
}

impl<P: RodPotential> CosseratCell<P> {
    /// Solves the equations `v` side by side (see the module
    /// documentation), writing the value and outcome of lane l < `count`,
    /// if solved, to `solved[slots[l]]` and its cells' gradients to
    /// `gradients[slots[l]·stride..]`; returns which lanes it solved (the
    /// others are left to the scalar step), `None` for a group with a lane
    /// outside the series branches (nothing written).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub(super) fn solve_group<const L: usize>(
        &self,
        v: &LaneInput<L>,
        options: &CauchyOptions,
        slots: &[usize; L],
        count: usize,
        solved: &mut [SolvedVertex<Pose<f64>>],
        gradients: &mut [SVector<f64, 6>],
        stride: usize,
    ) -> Option<[bool; L]> {
        let (ds, dt) = (self.ds, self.dt);
        // Damping (an end load's cells are never in a group).
        let loads = self.loads.as_ref();
        let zero_v = [Lanes::splat(0.0); 3];
        let mut state = [LaneState::Iterating; L];
        let mut outcome = [VertexOutcome::default(); L];
        // The rotation arms a_σ = log(R₀ᵀR₁) and D_a = dlog a.
        let (r0m, r0) = (v.r0m, v.r0);
        let mut arms_a = [[Lanes::splat(0.0); 3]; 2];
        let mut arms_da = [[[Lanes::splat(0.0); 3]; 3]; 2];
        let mut r1 = [[Lanes::splat(0.0); 3]; 2];
        for c in 0..2 {
            arms_a[c] = log(&tmm(&r0m, &v.r1m[c]))?;
            arms_da[c] = dexp_inv(&neg(&arms_a[c]))?;
            r1[c] = v.r1[c];
        }
        // The centred shear frames (`ShearFrame::Centred`), else none.
        let frames = match self.shear {
            ShearFrame::Vertex => None,
            ShearFrame::Centred => Some([LaneFrame::at(&arms_a[0])?, LaneFrame::at(&arms_a[1])?]),
        };
        let sigma = [1.0, -1.0];
        // The material point's parameters and constants, lane by lane (one
        // for all lanes without a profile).
        let s0 = v.s0;
        let same = self.profile.is_none();
        let p: [_; L] = std::array::from_fn(|l| self.parameters_at(s0[l]));
        let constants: [_; L] = std::array::from_fn(|l| self.constants_at(s0[l]));
        let c1 = gather_m3::<L>(same, |l| &p[l].c1);
        let strain = gather_v3::<L>(same, |l| p[l].strain);
        let n = 2.0;
        // Position: Σ_σ ∇_{r₀}L at the start r₂ = 2r₀ − r₋, then one 3×3 solve.
        let start = sub(&scale_by(&r0, 2.0), &v.previous_r);
        let kinetic = scale(&sub(&start, &r0), Lanes::from_fn(|l| -p[l].rho * ds / (4.0 * dt)));
        let weight = scale_by(
            &gather_v3::<L>(false, |l| self.density.potential.gradient(s0[l], &lane_v3(&r0, l))),
            -(ds * dt / 8.0),
        );
        let mut total = v.mu_scale + (largest_abs(&kinetic) + largest_abs(&weight)) * n;
        let mut strain_sum = [Lanes::splat(0.0); 3];
        let mut forces = zero_v;
        for c in 0..2 {
            let mut eps = linear_strain(sigma[c] * self.inv_ds, &r0m, &r0, &r1[c], &start, &strain);
            if let Some(f) = &frames {
                eps = f[c].strain(&eps, &strain);
            }
            let c1e = scale_by(&mv(&c1, &eps), 0.25 * dt);
            total = total + largest_abs(&c1e);
            let framed = frames.as_ref().map_or(c1e, |f| mv(&f[c].rotation, &c1e));
            strain_sum = add(&strain_sum, &scale_by(&framed, sigma[c]));
            if let Some(loads) = loads {
                // F⁰'s position part at (start, R₀): the linear damping.
                let mut f = zero_v;
                if loads.damped() {
                    f = add(&f, &self.lane_linear_damping(loads, &r0, &start));
                }
                forces = add(&forces, &f);
                total = total + largest_abs(&f);
            }
        }
        let leg_r = add(
            &add(&scale_by(&add(&kinetic, &weight), n), &mv(&r0m, &strain_sum)),
            &forces,
        );
        let zero = Matrix3::zeros();
        for (l, k) in constants.iter().enumerate() {
            if k.compliance.is_none() {
                state[l] = LaneState::Scalar;
            }
        }
        let rhs = tmv(&r0m, &sub(&v.mu_r, &leg_r));
        let mut stiffness = gather_m3::<L>(same, |l| &constants[l].stiffness);
        for x in stiffness.iter_mut().flatten() {
            *x = *x * n;
        }
        let z = match &frames {
            // Σ_σ [K + κ(E_σC₁E_σᵀ − C₁)] (`split_solve`).
            Some(f) => {
                let kappa = dt / (4.0 * ds);
                for frame in f {
                    let spread = mm(&mm(&frame.rotation, &c1), &transpose(&frame.rotation));
                    for i in 0..3 {
                        for j in 0..3 {
                            stiffness[i][j] = stiffness[i][j] + (spread[i][j] - c1[i][j]) * kappa;
                        }
                    }
                }
                let (compliance, regular) = inverse(&stiffness);
                for l in 0..L {
                    if !regular[l] {
                        state[l] = LaneState::Scalar;
                    }
                }
                mv(&compliance, &rhs)
            }
            None => {
                let compliance = gather_m3::<L>(same, |l| constants[l].compliance.as_ref().unwrap_or(&zero));
                scale_by(&mv(&compliance, &rhs), 1.0 / n)
            }
        };
        let r2 = sub(&start, &mv(&r0m, &z));
        let residual_r = largest_abs(&sub(&mv(&stiffness, &z), &rhs));
        for l in 0..L {
            if !residual_r.0[l].is_finite() || !lane_v3(&r2, l).iter().all(|x| x.is_finite()) {
                state[l] = LaneState::Scalar;
            }
        }
        // Rotation: the b-independent terms with r₂ known, then T(b) = target.
        let area = 0.25 * self.ds * self.dt;
        let mut fixed = [Lanes::splat(0.0); 3];
        let mut fixed_scale = Lanes::splat(0.0);
        // C₁ε_σ at r₂ and the centred shear's torque at R₁, kept for the
        // gradients.
        let mut c1_eps = [zero_v; 2];
        let mut middle_torques = [zero_v; 2];
        for c in 0..2 {
            let mut eps = linear_strain(sigma[c] * self.inv_ds, &r0m, &r0, &r1[c], &r2, &strain);
            if let Some(f) = &frames {
                eps = f[c].strain(&eps, &strain);
            }
            c1_eps[c] = mv(&c1, &eps);
            let mut torque = scale_by(&cross(&add(&eps, &strain), &c1_eps[c]), area);
            if let Some(f) = &frames {
                (torque, middle_torques[c]) = f[c].torques(&arms_da[c], &torque);
            }
            fixed = add(&fixed, &torque);
            fixed_scale = fixed_scale + largest_abs(&torque);
            if loads.is_some() {
                // F⁰'s rotation part at (r₂, R₀): no end load here.
                fixed = add(&fixed, &zero_v);
                fixed_scale = fixed_scale + largest_abs(&zero_v);
            }
        }
        let target = sub(&v.mu_q, &fixed);
        let damping = self.area() * loads.map_or(0.0, |l| l.damping_angular) / (2.0 * dt);
        let equation = self.lane_equation(&constants, same, &arms_a, &arms_da, damping);
        let mut b = log(&tmm(&v.previous_m, &r0m))?;
        let mut previous = [f64::INFINITY; L];
        let mut last_step = [f64::INFINITY; L];
        let scale_total = total + fixed_scale;
        for it in 0..=options.max_iterations {
            // A lane left to the scalar step no longer iterates: its b is
            // zeroed so that it cannot take the group off the series.
            for l in 0..L {
                if matches!(state[l], LaneState::Scalar) {
                    for x in b.iter_mut() {
                        x.0[l] = 0.0;
                    }
                }
            }
            if !state.iter().any(|s| matches!(s, LaneState::Iterating)) {
                break;
            }
            let (value, jacobian) = equation.value_and_jacobian(&b)?;
            let residual = sub(&value, &target);
            let terms = (scale_total + largest_abs(&value)).max(Lanes::splat(f64::MIN_POSITIVE));
            let (inv, regular) = inverse(&jacobian);
            let delta = neg(&mv(&inv, &residual));
            let next = add(&b, &delta);
            let (jacobian_size, b_size, delta_size) = (largest_abs_m3(&jacobian), largest_abs(&b), largest_abs(&delta));
            let (b2, next2) = (dot(&b, &b), dot(&next, &next));
            let angle = next2.map(f64::sqrt);
            let x_size = largest_abs(&add(&mv(&equation.linear, &b), &equation.offset));
            let (jacobian_norm, inverse_norm) = (row_sum_norm(&jacobian), row_sum_norm(&inv));
            let take_next = |b: &mut V3<L>, l: usize| {
                for i in 0..3 {
                    b[i].0[l] = next[i].0[l];
                }
            };
            for l in 0..L {
                if !matches!(state[l], LaneState::Iterating) {
                    continue;
                }
                let o = &mut outcome[l];
                o.jacobians += 1;
                let r = max_abs(&lane_v3(&residual, l));
                o.iterations = it;
                let t = terms.0[l];
                o.relative_residual = r.max(residual_r.0[l]) / t;
                if !r.is_finite() || !regular[l] && r > options.tolerance * t {
                    state[l] = LaneState::Scalar;
                    continue;
                }
                let stalled = r > 0.5 * previous[l]
                    && (r <= 100.0 * options.tolerance * (t + jacobian_size.0[l] * (1.0 + b_size.0[l]))
                        || last_step[l] <= 64.0 * f64::EPSILON * (1.0 + b_size.0[l]));
                if r <= options.tolerance * t || stalled {
                    if regular[l] && delta_size.0[l] < 1e-3 {
                        take_next(&mut b, l);
                    }
                    state[l] = LaneState::Solved;
                    continue;
                }
                previous[l] = r;
                if it == options.max_iterations {
                    state[l] = LaneState::Scalar;
                    continue;
                }
                let norm = equation.linear_norm.0[l];
                let remainder = remainder_bound(b2.0[l], next2.0[l], delta_size.0[l], x_size.0[l], norm);
                last_step[l] = delta_size.0[l];
                take_next(&mut b, l);
                let angle = angle.0[l];
                if angle.is_nan() || angle >= std::f64::consts::PI {
                    state[l] = LaneState::Scalar;
                    continue;
                }
                if let Some(remainder) = remainder
                    && remainder <= options.tolerance * t
                {
                    let (nj, ni) = (jacobian_norm.0[l], inverse_norm.0[l]);
                    let bound = remainder + 12.0 * f64::EPSILON * nj * ni * r;
                    if bound <= options.tolerance * t {
                        o.iterations = it + 1;
                        o.relative_residual = bound.max(residual_r.0[l]) / t;
                        state[l] = LaneState::Solved;
                    }
                }
            }
        }
        // The solved vertices: R₂ = R₀ exp(b̂) renormalised, b recomputed
        // from the stored value, and the cells' gradients from it.
        for l in 0..L {
            if matches!(state[l], LaneState::Iterating) {
                state[l] = LaneState::Scalar;
            }
            if matches!(state[l], LaneState::Solved) && lane_v3(&b, l).norm() >= std::f64::consts::PI {
                state[l] = LaneState::Scalar;
            }
            if !matches!(state[l], LaneState::Solved) {
                for x in b.iter_mut() {
                    x.0[l] = 0.0;
                }
            }
        }
        let rotation = renormalize(&mm(&r0m, &exp(&b)?));
        let b = log(&tmm(&r0m, &rotation))?;
        let db = dexp_inv(&neg(&b))?;
        let cell_forces = loads.map(|loads| self.lane_damping_forces(loads, &r0, &r2, &b));
        let later = self.lane_gradients(
            (&p, same),
            &r0m,
            frames.as_ref().map(|f| (f, &middle_torques)),
            &r0,
            &r2,
            (&arms_a, &arms_da),
            &c1_eps,
            &b,
            &db,
        );
        let mut done = [false; L];
        for l in 0..count.min(L) {
            if !matches!(state[l], LaneState::Solved) {
                continue;
            }
            done[l] = true;
            solved[slots[l]] = SolvedVertex {
                value: Pose::new(lane_v3(&r2, l), SO3::from_matrix_unchecked(lane_m3(&rotation, l))),
                outcome: outcome[l],
                gradients_written: true,
                forces_written: loads.is_some(),
            };
            let terms = &mut gradients[slots[l] * stride..(slots[l] + 1) * stride];
            terms.fill(SVector::zeros());
            for (c, [first_r, first_q, second_r, second_q]) in later.iter().enumerate() {
                terms[3 * c + 1] = join(lane_v3(first_r, l), lane_v3(first_q, l));
                terms[3 * c + 2] = join(lane_v3(second_r, l), lane_v3(second_q, l));
                if let Some([first, last]) = &cell_forces {
                    // (F⁰, F¹ = 0, F²) after the gradients (`forces_with`).
                    terms[6 + 3 * c] = join(lane_v3(&first[0], l), lane_v3(&first[1], l));
                    terms[6 + 3 * c + 2] = join(lane_v3(&last[0], l), lane_v3(&last[1], l));
                }
            }
        }
        Some(done)
    }

    /// −(A_β/2)c_r(r₂ − r₀)/Δt in lanes (`CosseratCell::linear_damping`).
    #[inline(always)]
    fn lane_linear_damping<const L: usize>(
        &self,
        loads: &crate::models::rod::cosserat::RodLoads,
        r0: &V3<L>,
        r2: &V3<L>,
    ) -> V3<L> {
        scale_by(&sub(r2, r0), self.damping_weight() * loads.damping_linear)
    }

    /// The damping forces F⁰ = F² of a cell in lanes (`forces_with` on a
    /// cell without the end load): 0 + (linear damping; (A_β/2)c_R b/Δt),
    /// as position and rotation parts; zero without damping.
    #[inline(always)]
    fn lane_damping_forces<const L: usize>(
        &self,
        loads: &crate::models::rod::cosserat::RodLoads,
        r0: &V3<L>,
        r2: &V3<L>,
        b: &V3<L>,
    ) -> [[V3<L>; 2]; 2] {
        let zero = [Lanes::splat(0.0); 3];
        if !loads.damped() {
            return [[zero; 2]; 2];
        }
        let v = self.lane_linear_damping(loads, r0, r2);
        let o = scale_by(b, self.damping_weight() * loads.damping_angular);
        let first = [add(&zero, &v), add(&zero, &o)];
        [first, first]
    }

    /// `RotationEquation::new` for the two cells based at each vertex, with
    /// the angular damping c per cell.
    #[inline(always)]
    fn lane_equation<const L: usize>(
        &self,
        constants: &[&crate::models::rod::cosserat::StepConstants; L],
        same: bool,
        arms_a: &[V3<L>; 2],
        arms_da: &[M3<L>; 2],
        damping: f64,
    ) -> LaneEquation<L> {
        let n = 2.0;
        let c2 = gather_m3::<L>(same, |l| &constants[l].c2_minus_two_kappa);
        let zero_v = [Lanes::splat(0.0); 3];
        let (mut a_sum, mut da_sum, mut constant) = (zero_v, [zero_v; 3], zero_v);
        for c in 0..2 {
            a_sum = add(&a_sum, &arms_a[c]);
            for (sum, row) in da_sum.iter_mut().zip(&arms_da[c]) {
                *sum = add(sum, row);
            }
            constant = add(&constant, &mv(&arms_da[c], &mv(&c2, &arms_a[c])));
        }
        let mut slope = mm(&da_sum, &c2);
        for (i, row) in slope.iter_mut().enumerate() {
            row[i] = row[i] - n * damping;
        }
        let mut linear = gather_m3::<L>(same, |l| &constants[l].rotation_linear);
        for x in linear.iter_mut().flatten() {
            *x = *x * n;
        }
        LaneEquation {
            linear,
            linear_norm: Lanes::from_fn(|l| constants[l].rotation_linear_norm) * n,
            offset: mv(&c2, &a_sum),
            slope,
            constant: scale_by(&constant, -2.0),
        }
    }

    /// The gradients at positions 1 and 2 of both cells of each lane
    /// (`CosseratCell::later_gradients` of the cells' quantities with
    /// b = log(R₀ᵀR₂) and r₂, from C₁ε_σ; with the centred `frames` given,
    /// the shear in R₀E_σ and each cell's torque at R₁ added to ∇_{R₁}), in
    /// the marcher's layout.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn lane_gradients<const L: usize>(
        &self,
        (p, same): (&[&crate::models::rod::cosserat::RodParameters; L], bool),
        r0m: &M3<L>,
        frames: Option<(&[LaneFrame<L>; 2], &[V3<L>; 2])>,
        r0: &V3<L>,
        r2: &V3<L>,
        (arms_a, arms_da): (&[V3<L>; 2], &[M3<L>; 2]),
        c1_eps: &[V3<L>; 2],
        b: &V3<L>,
        db: &M3<L>,
    ) -> [[V3<L>; 4]; 2] {
        let (c2, inertia) = (
            gather_m3::<L>(same, |l| &p[l].c2),
            gather_m3::<L>(same, |l| &p[l].inertia),
        );
        let rho = Lanes::from_fn(|l| p[l].rho);
        let ds = self.ds;
        let omega = scale_by(b, self.inv_dt);
        let velocity = scale_by(&sub(r2, r0), self.inv_dt);
        let mut out = [[[Lanes::splat(0.0); 3]; 4]; 2];
        for (c, cell) in out.iter_mut().enumerate() {
            let sigma = if c == 0 { 1.0 } else { -1.0 };
            let st = sigma * self.dt;
            let u = scale_by(&sub(&scale_by(&arms_a[c], 2.0), b), sigma * self.inv_ds);
            let c1e = match frames {
                None => mv(r0m, &c1_eps[c]),
                Some((f, _)) => mv(&mm(r0m, &f[c].rotation), &c1_eps[c]),
            };
            let c2u = mv(&c2, &u);
            let mut middle_rotation = scale_by(&neg(&tmv(&arms_da[c], &c2u)), st / 2.0);
            if let Some((_, torques)) = frames {
                middle_rotation = add(&middle_rotation, &torques[c]);
            }
            *cell = [
                scale_by(&neg(&c1e), st / 2.0),
                middle_rotation,
                add(&scale(&velocity, rho * ds / 4.0), &scale_by(&c1e, st / 4.0)),
                tmv(
                    db,
                    &add(&scale_by(&mv(&inertia, &omega), ds / 4.0), &scale_by(&c2u, st / 4.0)),
                ),
            ];
        }
        out
    }
}
