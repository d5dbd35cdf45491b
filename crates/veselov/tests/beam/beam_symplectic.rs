//! The time map of the free–free SE(3) beam is symplectic (seed 000 Prop.
//! 3.6, note 000 §16 item 10): in canonical charts g_a = ḡ_a·exp(q_a),
//! p_a = dexp_{−q_a}ᵀ (g_a⁻¹D₂ℒ_a) (the cotangent lift of the chart; the
//! left-trivialised derivative of exp at q is dexp_{−q}), the slaved node
//! a = A removed, the Jacobian 𝐉 of (q¹, p¹) ↦ (q^K, p^K) satisfies
//! 𝐉ᵀΩ𝐉 = Ω. 𝐉 = D(q^K, p^K)/Dz · (D(q¹, p¹)/Dz)⁻¹ for the data
//! z = perturbations of the first two rows, both derivatives by the
//! fourth-order central difference (truncation ~h⁴ ≈ 1e-12 at h = 1e-3).

use nalgebra::{DMatrix, SVector};
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000};
use veselov::field::cauchy::CauchyOptions;
use veselov::field::cell::vertex_gradient;
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, Retraction, SE3, se3};
use veselov::models::beam::{BeamDensity, BeamProperties, CayleyBeam, beam_lagrangian, straight};

const DT: f64 = 0.05;
const DS: f64 = 0.1;
const A: usize = 2;
const DIM: usize = 6 * A;

fn lagrangian() -> CayleyBeam {
    let p = BeamProperties::from_diagonals([0.5, 0.5, 1.0, 1.0, 1.0, 1.0], [0.5, 0.5, 0.6, 1.0, 1.0, 1.0])
        .expect("positive");
    beam_lagrangian(BeamDensity::new(p), DT, DS).expect("lagrangian")
}

fn wave(a: usize, phase: f64) -> SVector<f64, 6> {
    let s = a as f64 + phase;
    SVector::from([
        0.3 * s.sin(),
        -0.2 * s.cos(),
        0.25 * (0.9 * s).sin(),
        0.1,
        -0.15 * s.sin(),
        0.05 * s.cos(),
    ])
}

fn reference_rows() -> (Vec<SE3<f64>>, Vec<SE3<f64>>) {
    let g0: Vec<SE3<f64>> = (0..=A)
        .map(|a| straight(DS, a).compose(&se3::exp(&(wave(a, 0.0) * 0.1))))
        .collect();
    let g1 = g0
        .iter()
        .enumerate()
        .map(|(a, g)| g.compose(&CayleyMap::tau(&(wave(a, 1.0) * DT))))
        .collect();
    (g0, g1)
}

/// (q, p) of the non-slaved nodes of the current level, in the charts
/// centred at `centre` (one per node).
fn canonical(evo: &Evolution000<RigidMotions, CayleyBeam, 6>, centre: &[SE3<f64>]) -> SVector<f64, { 2 * DIM }> {
    let mut out = SVector::<f64, { 2 * DIM }>::zeros();
    evo.for_each_cell(|a, cell, y| {
        let q = se3::log(&centre[a].inverse().compose(&y[1])).expect("inside the chart");
        let grad = vertex_gradient::<RigidMotions, _, 6>(evo.lagrangian(), cell, y, 1).1;
        let p = se3::dexp(&(-q)).transpose() * grad;
        out.fixed_rows_mut::<6>(6 * a).copy_from(&q);
        out.fixed_rows_mut::<6>(DIM + 6 * a).copy_from(&p);
    });
    out
}

/// (q, p) after `steps` levels from the rows perturbed by z (charts centred
/// on the unperturbed run's level, given in `centre`).
fn flow(z: &[f64], steps: usize, centre: &[SE3<f64>]) -> SVector<f64, { 2 * DIM }> {
    let (mut g0, mut g1) = reference_rows();
    for a in 0..A {
        let dz0 = SVector::<f64, 6>::from_fn(|i, _| z[6 * a + i]);
        let dz1 = SVector::<f64, 6>::from_fn(|i, _| z[DIM + 6 * a + i]);
        g0[a] = g0[a].compose(&se3::exp(&dz0));
        g1[a] = g1[a].compose(&se3::exp(&dz1));
    }
    let mut evo = Evolution000::new(
        Direction::Time,
        lagrangian(),
        &g0,
        &g1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("evolution");
    for _ in 0..steps {
        evo.step().expect("step");
    }
    canonical(&evo, centre)
}

fn centre_after(steps: usize) -> Vec<SE3<f64>> {
    let (g0, g1) = reference_rows();
    let mut evo = Evolution000::new(
        Direction::Time,
        lagrangian(),
        &g0,
        &g1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("evolution");
    for _ in 0..steps {
        evo.step().expect("step");
    }
    (0..=A).map(|a| evo.value(0, a)).collect()
}

fn jacobian(steps: usize) -> DMatrix<f64> {
    let centre = centre_after(steps);
    let h = 1e-3;
    let mut jac = DMatrix::<f64>::zeros(2 * DIM, 2 * DIM);
    for k in 0..2 * DIM {
        let at = |t: f64| {
            let mut z = vec![0.0; 2 * DIM];
            z[k] = t;
            flow(&z, steps, &centre)
        };
        let d = ((at(h) - at(-h)) * 8.0 - (at(2.0 * h) - at(-2.0 * h))) / (12.0 * h);
        jac.set_column(k, &d);
    }
    jac
}

#[test]
fn the_time_map_is_symplectic() {
    let steps = 12;
    let start = jacobian(0);
    let end = jacobian(steps);
    let map = &end * start.clone().try_inverse().expect("the data determine (q¹, p¹)");
    let mut omega = DMatrix::<f64>::zeros(2 * DIM, 2 * DIM);
    for i in 0..DIM {
        omega[(i, DIM + i)] = 1.0;
        omega[(DIM + i, i)] = -1.0;
    }
    let defect = (map.transpose() * &omega * &map - &omega).amax();
    let size = map.amax();
    eprintln!("time map over {steps} levels: symplecticity defect {defect:e} (|J| = {size:.3})");
    assert!(defect <= 1e-10, "symplecticity defect {defect:e}");
    // The test can fail: a map that is not symplectic (the Jacobian with one
    // momentum row scaled by 1 + 1e-6) is detected.
    let mut wrong = map.clone();
    for j in 0..2 * DIM {
        wrong[(DIM, j)] *= 1.0 + 1e-6;
    }
    assert!((wrong.transpose() * &omega * &wrong - &omega).amax() > 1e-8);
}
