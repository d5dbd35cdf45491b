//! The simplicial geodesic interpolation at interior nodes (Casimiro–Rodrigo
//! Def. 5.4, Lemmas 5.6, 5.7, 5.12; note 003 §2.5 item 4, test T16): the
//! weighted Karcher mean on SO(3), ℝ³ and ℝ³ × SO(3), and the rule Q_mid
//! (5.2) through it on curved fibres (Prop. 5.17, derivatives).
//!
//! Tolerances: the mean is converged to a step of a few ulps, so the
//! identities hold to ~10 ulps of the data (1e-14); a weight moved by 1e-9
//! moves the mean by ~1e-10, four orders above, so each identity can fail
//! (checked where a test compares two means).

use crate::shared::{SplitMix, cell, nudged, rel_vec};
use nalgebra::{SMatrix, SVector, Vector3};
use veselov::ad::Scalar;
use veselov::field::cell::{DiscreteLagrangian, vertex_gradient};
use veselov::field::discretize::{CellCheck, CfkNodes, KarcherMidpointRule, MidpointRule, SmoothDensity, karcher_mean};
use veselov::field::fibre::{Euclidean, Fibre, Pose, PositionRotation, Rotations};
use veselov::lie::{SO3, so3};

/// The distance between two rotations, |log(RᵀS)|.
fn dist(r: &SO3<f64>, s: &SO3<f64>) -> f64 {
    Rotations::log(r, s).expect("small").norm()
}

/// Σ_v w_v log_m(y_v): the Riemannian gradient of the weighted energy at m,
/// zero at the mean (Def. 5.4's first-order condition).
fn energy_gradient(m: &SO3<f64>, points: &[SO3<f64>], w: &[f64]) -> f64 {
    points
        .iter()
        .zip(w)
        .fold(Vector3::zeros(), |s, (p, &w)| {
            s + Rotations::log(m, p).expect("small") * w
        })
        .norm()
}

/// Lemma 5.7: on an edge the interpolation is the constant-speed minimal
/// geodesic, Υ(1 − t, t) = R₀ exp(t log(R₀ᵀR₁)); at t = ½ the midpoint.
#[test]
fn two_points_give_the_geodesic_point() {
    let mut rng = SplitMix(21);
    let mut worst: f64 = 0.0;
    for _ in 0..50 {
        let r0 = rng.rotation(3.0);
        let r1 = r0.compose(&rng.rotation(1.4));
        for t in [0.5, 0.2, 0.85] {
            let m = karcher_mean::<Rotations, 3>(&[r0, r1], &[1.0 - t, t]).expect("mean");
            let geodesic = so3::geodesic(&r0, &r1, t).expect("below π");
            worst = worst.max(dist(&m, &geodesic));
        }
    }
    eprintln!("Karcher mean of two rotations vs the geodesic point: {worst:e}");
    assert!(worst <= 1e-14, "{worst:e}");
    // Failing-capable: weights (½ + 1e-9, ½ − 1e-9) give another point.
    let (r0, r1) = (rng.rotation(1.0), rng.rotation(1.0));
    let a = karcher_mean::<Rotations, 3>(&[r0, r1], &[0.5, 0.5]).expect("mean");
    let b = karcher_mean::<Rotations, 3>(&[r0, r1], &[0.5 + 1e-9, 0.5 - 1e-9]).expect("mean");
    assert!(
        dist(&a, &b) > 1e-11,
        "a moved weight must move the mean ({:e})",
        dist(&a, &b)
    );
}

/// Lemma 5.12 for the isometries of SO(3)'s bi-invariant metric: left and
/// right translations, Υ(QR_v) = QΥ(R_v) and Υ(R_vQ) = Υ(R_v)Q; and the
/// mean does not depend on the order of the points (with their weights),
/// nor on the starting point the iteration takes. The mean solves its
/// first-order condition Σ_v w_v log_m(R_v) = 0 to round-off.
#[test]
fn the_rotation_mean_is_bi_invariant_and_order_free() {
    let mut rng = SplitMix(5);
    let (mut left, mut right, mut order, mut critical): (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 0.0);
    for _ in 0..50 {
        let base = rng.rotation(3.0);
        let points: Vec<SO3<f64>> = (0..4).map(|_| base.compose(&rng.rotation(0.7))).collect();
        let w: Vec<f64> = (0..4).map(|_| 0.1 + rng.uniform()).collect();
        let m = karcher_mean::<Rotations, 3>(&points, &w).expect("mean");
        critical = critical.max(energy_gradient(&m, &points, &w));
        let q = rng.rotation(3.0);
        let lq: Vec<SO3<f64>> = points.iter().map(|p| q.compose(p)).collect();
        let rq: Vec<SO3<f64>> = points.iter().map(|p| p.compose(&q)).collect();
        left = left.max(dist(
            &karcher_mean::<Rotations, 3>(&lq, &w).expect("mean"),
            &q.compose(&m),
        ));
        right = right.max(dist(
            &karcher_mean::<Rotations, 3>(&rq, &w).expect("mean"),
            &m.compose(&q),
        ));
        let perm = [2, 0, 3, 1];
        let (pp, pw): (Vec<SO3<f64>>, Vec<f64>) = perm.iter().map(|&i| (points[i], w[i])).unzip();
        order = order.max(dist(&karcher_mean::<Rotations, 3>(&pp, &pw).expect("mean"), &m));
    }
    eprintln!(
        "Karcher mean on SO(3): left {left:e}, right {right:e}, permutation {order:e}, first-order condition {critical:e}"
    );
    assert!(
        left <= 1e-14 && right <= 1e-14 && order <= 1e-14,
        "{left:e} {right:e} {order:e}"
    );
    assert!(critical <= 1e-15, "{critical:e}");
    // Failing-capable: the permutation applied to the points alone (not to
    // their weights) is another mean.
    let points: Vec<SO3<f64>> = (0..3).map(|_| rng.rotation(0.6)).collect();
    let a = karcher_mean::<Rotations, 3>(&points, &[0.2, 0.3, 0.5]).expect("mean");
    let b = karcher_mean::<Rotations, 3>(&[points[1], points[0], points[2]], &[0.2, 0.3, 0.5]).expect("mean");
    assert!(dist(&a, &b) > 1e-3);
}

/// Lemma 5.6 (product split) and the flat case: on ℝ³ the mean is the
/// weighted arithmetic mean; on ℝ³ × SO(3) it is (arithmetic mean of the
/// positions, Karcher mean of the rotations).
#[test]
fn flat_and_product_means() {
    let mut rng = SplitMix(8);
    let (mut flat, mut product): (f64, f64) = (0.0, 0.0);
    for _ in 0..50 {
        let r: Vec<Vector3<f64>> = (0..3).map(|_| rng.vec::<3>(100.0)).collect();
        let rots: Vec<SO3<f64>> = (0..3).map(|_| rng.rotation(0.8)).collect();
        let w = [0.2 + rng.uniform(), 0.3, 0.1 + rng.uniform()];
        let total: f64 = w.iter().sum();
        let arithmetic = r
            .iter()
            .zip(&w)
            .fold(Vector3::zeros(), |s, (p, &w)| s + p * (w / total));
        let m = karcher_mean::<Euclidean<3>, 3>(&r, &w).expect("mean");
        flat = flat.max((m - arithmetic).amax() / 100.0);
        let poses: Vec<Pose<f64>> = r.iter().zip(&rots).map(|(p, q)| Pose::new(*p, *q)).collect();
        let pm = karcher_mean::<PositionRotation, 6>(&poses, &w).expect("mean");
        let rm = karcher_mean::<Rotations, 3>(&rots, &w).expect("mean");
        product = product.max((pm.position - arithmetic).amax() / 100.0 + dist(&pm.rotation, &rm));
    }
    eprintln!("Karcher mean: ℝ³ vs arithmetic {flat:e}; ℝ³ × SO(3) vs its factors {product:e}");
    assert!(flat <= 1e-15 && product <= 1e-14, "{flat:e} {product:e}");
}

/// Clear errors: rotations not within π/2 of a common one (outside the
/// convex ball of Lemma 5.5), negative weights, mismatched lengths.
#[test]
fn means_outside_a_convex_ball_or_with_bad_weights_are_refused() {
    let r0 = SO3::<f64>::identity();
    let far = so3::exp(&Vector3::new(2.0, 0.0, 0.0));
    let err = karcher_mean::<Rotations, 3>(&[r0, far], &[0.5, 0.5]).expect_err("angle 2 > π/2");
    assert!(err.to_string().contains("convex geodesic ball"), "{err}");
    let err = karcher_mean::<Rotations, 3>(&[r0, r0], &[0.5, -0.5]).expect_err("negative weight");
    assert!(err.to_string().contains("weights"), "{err}");
    let err = karcher_mean::<Rotations, 3>(&[r0, r0], &[1.0]).expect_err("one weight for two points");
    assert!(err.to_string().contains("weights"), "{err}");
}

/// A rigid-body sigma model on 1+1 space–time, 𝓛 = ½(ωᵀJω − ΩᵀKΩ), ω and Ω
/// the time and space columns of the jet (body vectors); invariant under
/// R ↦ QR.
struct Sigma;
impl SmoothDensity<Rotations, 3, 2> for Sigma {
    fn density<D: Scalar>(&self, _x: &SVector<f64, 2>, _y: &SO3<D>, j: &SMatrix<D, 3, 2>) -> D {
        let (om, w) = (j.column(0), j.column(1));
        (w[0] * w[0] + w[1] * w[1] * 2.0 + w[2] * w[2] * 0.5 - om[0] * om[0] * 3.0 - om[1] * om[1] - om[2] * om[2])
            * 0.5
    }
}

/// A rod-like density on ℝ³ × SO(3): ½(|r_t|² − |Rᵀr_s − e₃|² + ωᵀω − ΩᵀΩ),
/// invariant under rigid motions.
struct Rodlike;
impl SmoothDensity<PositionRotation, 6, 2> for Rodlike {
    fn density<D: Scalar>(&self, _x: &SVector<f64, 2>, y: &Pose<D>, j: &SMatrix<D, 6, 2>) -> D {
        let rs = Vector3::new(j[(0, 0)], j[(1, 0)], j[(2, 0)]);
        let rt = Vector3::new(j[(0, 1)], j[(1, 1)], j[(2, 1)]);
        let strain = y.rotation.matrix().transpose() * rs - Vector3::new(D::zero(), D::zero(), D::one());
        let (om, w) = (j.fixed_view::<3, 1>(3, 0), j.fixed_view::<3, 1>(3, 1));
        (rt.dot(&rt) - strain.dot(&strain) + w.dot(&w) - om.dot(&om)) * 0.5
    }
}

/// The exact vertex gradients of a discrete Lagrangian against central
/// differences of its cell Lagrangian in the vertex charts (h = 1e-6; the
/// difference quotient is accurate to ~1e-9 relative).
fn gradient_vs_fd<F: Fibre<M>, L: DiscreteLagrangian<F, M>, const M: usize>(
    lag: &L,
    c: &veselov::complex::TopCell,
    y: &[F::Point<f64>; 3],
) -> f64 {
    let mut worst: f64 = 0.0;
    for k in 0..3 {
        let g = vertex_gradient::<F, L, M>(lag, c, y, k).1;
        let fd = SVector::<f64, M>::from_fn(|i, _| {
            let xi = SVector::<f64, M>::from_fn(|j, _| if i == j { 1e-6 } else { 0.0 });
            let [plus, minus] = nudged::<F, M, 3>(y, k, &xi);
            (lag.cell_lagrangian(c, &plus) - lag.cell_lagrangian(c, &minus)) / 2e-6
        });
        worst = worst.max(rel_vec(&fd, &g));
    }
    worst
}

/// Q_mid through the Karcher mean on the rod's leapfrog lattice: on ℝ^m it
/// is the affine Q_mid; on SO(3) and ℝ³ × SO(3) the rigid motions that
/// leave 𝓛 invariant leave it invariant (Prop. 5.17, through Lemma 5.12),
/// and its exact vertex gradients (dual numbers through the fixed-point
/// iteration and its λ-derivatives) equal central differences of the cell
/// Lagrangian — the cross-check every discrete Lagrangian of the core passes.
#[test]
fn karcher_midpoint_rule_is_invariant_and_differentiates_exactly() {
    let map = CfkNodes::<2>::leapfrog(0.4, 0.1).expect("spacings");
    let mut rng = SplitMix(12);
    let (mut affine, mut invariance, mut fd_rot, mut fd_pose): (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 0.0);
    // ℝ²: the same as MidpointRule.
    struct Wave;
    impl SmoothDensity<Euclidean<2>, 2, 2> for Wave {
        fn density<D: Scalar>(&self, _x: &SVector<f64, 2>, y: &SVector<D, 2>, j: &SMatrix<D, 2, 2>) -> D {
            (j[(0, 1)] * j[(0, 1)] + j[(1, 1)] * j[(1, 1)] - j[(0, 0)] * j[(0, 0)] - j[(1, 0)] * j[(1, 0)]) * 0.5
                - y[0] * y[0] * y[1] * 0.1
        }
    }
    let karcher_wave = KarcherMidpointRule::<Euclidean<2>, _, _, 2, 2>::new(Wave, map);
    let midpoint = MidpointRule::new(Wave, map);
    let sigma = KarcherMidpointRule::<Rotations, _, _, 3, 2>::new(Sigma, map);
    let rod = KarcherMidpointRule::<PositionRotation, _, _, 6, 2>::new(Rodlike, map);
    for trial in 0..20 {
        let c = cell(trial, trial % 2, &[rng.sym(5.0) as i64, rng.sym(5.0) as i64]);
        let yw: [SVector<f64, 2>; 3] = std::array::from_fn(|_| rng.vec::<2>(1.0));
        let (a, b) = (karcher_wave.cell_lagrangian(&c, &yw), midpoint.cell_lagrangian(&c, &yw));
        affine = affine.max((a - b).abs() / a.abs().max(1e-3));
        let base = rng.rotation(3.0);
        let y: [SO3<f64>; 3] = std::array::from_fn(|_| base.compose(&rng.rotation(0.5)));
        sigma.check_cell(&c, &y).expect("within π/2");
        let q = rng.rotation(3.0);
        let moved: [SO3<f64>; 3] = std::array::from_fn(|k| q.compose(&y[k]));
        let (a, b) = (sigma.cell_lagrangian(&c, &y), sigma.cell_lagrangian(&c, &moved));
        invariance = invariance.max((a - b).abs() / a.abs().max(1e-3));
        fd_rot = fd_rot.max(gradient_vs_fd::<Rotations, _, 3>(&sigma, &c, &y));
        let poses: [Pose<f64>; 3] = std::array::from_fn(|k| Pose::new(rng.vec::<3>(0.3), y[k]));
        let shift = rng.vec::<3>(2.0);
        let moved: [Pose<f64>; 3] =
            std::array::from_fn(|k| Pose::new(q.matrix() * poses[k].position + shift, q.compose(&poses[k].rotation)));
        let (a, b) = (rod.cell_lagrangian(&c, &poses), rod.cell_lagrangian(&c, &moved));
        invariance = invariance.max((a - b).abs() / a.abs().max(1e-3));
        fd_pose = fd_pose.max(gradient_vs_fd::<PositionRotation, _, 6>(&rod, &c, &poses));
    }
    eprintln!(
        "Karcher Q_mid: vs affine Q_mid on ℝ² {affine:e}; rigid-motion invariance {invariance:e}; \
         exact gradient vs FD on SO(3) {fd_rot:e}, on ℝ³ × SO(3) {fd_pose:e}"
    );
    assert!(affine <= 1e-14, "{affine:e}");
    assert!(invariance <= 1e-13, "{invariance:e}");
    // Central differences at h = 1e-6: truncation h²|∂³L| ~1e-12, round-off
    // ε|L|/h ~1e-10 relative to the gradient.
    assert!(fd_rot <= 1e-7 && fd_pose <= 1e-7, "{fd_rot:e} {fd_pose:e}");
}

/// The λ-derivative of the mean, which gives the jet of Q_mid, against
/// central differences of the mean in its weights: ∂Υ/∂t_a at λ̄ along
/// e_a − e_0 equals (log(Υ(λ̄), Υ(λ̄ + h(e_a − e_0))) − log(…, Υ(λ̄ − h(…))))/2h,
/// through the jet of a density that reads it off (𝓛 = c·φ). Shown via
/// the rule: with 𝓛 = ⟨c, φ e_b⟩ the rule returns vol·cᵀφ e_b.
#[test]
fn the_jet_of_the_karcher_rule_is_the_derivative_of_the_mean() {
    struct Linear(SMatrix<f64, 3, 2>);
    impl SmoothDensity<Rotations, 3, 2> for Linear {
        fn density<D: Scalar>(&self, _x: &SVector<f64, 2>, _y: &SO3<D>, j: &SMatrix<D, 3, 2>) -> D {
            (0..3).fold(D::zero(), |s, i| {
                s + j[(i, 0)] * self.0[(i, 0)] + j[(i, 1)] * self.0[(i, 1)]
            })
        }
    }
    let map = CfkNodes::<2>::leapfrog(0.4, 0.1).expect("spacings");
    let mut rng = SplitMix(99);
    let c = cell(0, 1, &[2, 1]);
    let mut x = vec![SVector::<f64, 2>::zeros(); 16];
    veselov::field::discretize::NodeMap::cell_nodes(&map, &c, &mut x);
    let tx = SMatrix::<f64, 2, 2>::from_fn(|r, k| x[k + 1][r] - x[0][r]);
    let vol = tx.determinant().abs() / 2.0;
    let y: [SO3<f64>; 3] = std::array::from_fn(|_| rng.rotation(0.6));
    let third = 1.0 / 3.0;
    let m = karcher_mean::<Rotations, 3>(&y, &[third; 3]).expect("mean");
    let h = 1e-5;
    // dy[:, a] by central differences of the mean along e_{a+1} − e_0.
    let dy = SMatrix::<f64, 3, 2>::from_fn(|i, a| {
        let at = |t: f64| {
            let mut w = [third; 3];
            w[0] -= t;
            w[a + 1] += t;
            Rotations::log(&m, &karcher_mean::<Rotations, 3>(&y, &w).expect("mean")).expect("small")
        };
        (at(h) - at(-h))[i] / (2.0 * h)
    });
    let jet = dy * tx.try_inverse().expect("regular");
    let mut worst: f64 = 0.0;
    for i in 0..3 {
        for b in 0..2 {
            let unit = SMatrix::<f64, 3, 2>::from_fn(|r, k| f64::from(u8::from(r == i && k == b)));
            let rule = KarcherMidpointRule::<Rotations, _, _, 3, 2>::new(Linear(unit), map);
            let value = rule.cell_lagrangian(&c, &y) / vol;
            worst = worst.max((value - jet[(i, b)]).abs() / jet.amax());
        }
    }
    eprintln!("Karcher Q_mid jet vs central differences of the mean: {worst:e}");
    // Central differences at h = 1e-5: truncation h² ~1e-10, round-off ε/h ~1e-11.
    assert!(worst <= 1e-8, "{worst:e}");
}
