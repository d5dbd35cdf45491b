//! The free rod under a uniform load (gravity as the potential
//! P(s, r) = G·r of (6.1)): the discrete momentum balance. The per-cell
//! identity of note 003 §3.7 becomes Σ_k ∇_{r_k}L_β = −(ΔsΔt/8)G (the load
//! enters only at v₀ under Q_{v₀}), so each level's change of linear momentum
//! is the discrete impulse of the load over the cells based at it, and the
//! angular momentum about the load's axis (a symmetry that survives, note 003
//! erratum 5) stays constant.

use nalgebra::Vector3;
use veselov::complex::permutation;
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::fibre::Pose;
use veselov::lie::so3;
use veselov::models::rod::{CosseratCell, CosseratDensity, LinearPotential};
use veselov::models::rod::{RodLattice, angular_momentum, linear_momentum, momenta};

use crate::sample::unit_rod;

#[test]
fn momentum_changes_by_the_impulse_of_the_load() {
    let p = unit_rod(0.1);
    let lattice = RodLattice::new(21, 1.0, 0.04).expect("lattice");
    // Gravity g: the potential energy per length is −ρA g·r and enters (6.1)
    // as −½P, so P = −2ρA g·r.
    let g = Vector3::new(0.0, -9.81, 0.0);
    let load = LinearPotential {
        gradient: -g * (2.0 * p.rho()),
    };
    let cell = CosseratCell::new(
        CosseratDensity {
            parameters: p,
            potential: load,
        },
        lattice.ds(),
        lattice.dt(),
    )
    .expect("spacings");
    let data = lattice.cauchy_data(|s, t| {
        let spin = so3::exp(&(Vector3::new(0.0, 0.7, 0.0) * t));
        Pose::new(
            spin.act(&Vector3::new(0.02 * (3.0 * s).sin(), 0.0, s)) + Vector3::new(0.1, 0.3, 0.0) * t,
            spin.compose(&so3::exp(&Vector3::new(0.05 * s, 0.0, 0.0))),
        )
    });
    let mut m = CauchyMarcher::with_window(
        cell,
        lattice.torus().clone(),
        0,
        &data,
        CauchyOptions::default(),
        lattice.window(),
    )
    .expect("marcher");
    let per_cell = load.gradient * (lattice.ds() * lattice.dt() / 8.0);
    let axis = g.normalize();
    let (mut worst, mut worst_axis, mut total) = (0.0_f64, 0.0_f64, Vector3::zeros());
    let l0 = angular_momentum(&m).dot(&axis);
    for _ in 0..120 {
        let before = linear_momentum(&m);
        let w = m.level();
        // Kept cells based at level w.
        let cells = (0..lattice.torus().level_size())
            .flat_map(|i| (0..2).map(move |s| (i, s)))
            .filter(|&(i, s)| {
                lattice
                    .window()
                    .contains_cell(&lattice.torus().vertex(w, i), &permutation(2, s))
            })
            .count();
        m.step().expect("stable step");
        let change = linear_momentum(&m) - before;
        let impulse = -per_cell * cells as f64;
        total += impulse;
        worst = worst.max((change - impulse).norm() / impulse.norm());
        worst_axis = worst_axis.max((angular_momentum(&m).dot(&axis) - l0).abs() / angular_momentum(&m).norm());
    }
    // Over 120 levels (60 Δt) the kept cells are 60 × 2(nodes − 1), each with
    // ΔsΔt/8 of the load: exactly the rod's weight times the time.
    let weight_time = g * (p.rho() * lattice.length() * 60.0 * lattice.dt());
    println!(
        "loaded rod: max rel |ΔP − impulse| per level {worst:.1e}; total impulse {total:?} vs weight·t {weight_time:?}; \
         axial angular momentum drift {worst_axis:.1e}"
    );
    assert!(worst < 1e-10, "{worst:.1e}");
    assert!((total - weight_time).norm() < 1e-12 * weight_time.norm());
    // All six momenta in one sweep are the per-generator sweeps, bit for bit.
    let (p1, l1) = momenta(&m);
    assert_eq!((p1, l1), (linear_momentum(&m), angular_momentum(&m)));
    let vertical = m.level_momentum(|_: &Pose<f64>| nalgebra::SVector::<f64, 6>::ith(1, 1.0));
    assert_eq!(vertical.to_bits(), p1[1].to_bits());
    assert!(worst_axis < 1e-11, "{worst_axis:.1e}");
}
