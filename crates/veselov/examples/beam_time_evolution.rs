//! Time evolution of a steel beam (L = 0.8 m, 0.01 m square section,
//! ρ = 7800 kg/m³, E = 210 GPa, ν = 0.3, shear factor 5/6) on seed 000's
//! lattice, two runs:
//!
//! 1. free–free, released at rest from a bent shape (curvature 0.5 m⁻¹
//!    about E1): zero traction at both ends, 𝖩_𝖫 conserved, E_𝖫 bounded;
//! 2. cantilever (clamped at s = 0) released from the same shape.
//!
//! (A damped cantilever settling under gravity is the test
//! `beam_forces::damped_cantilever_settles_to_the_timoshenko_deflection`;
//! for this slender steel beam the step limit, about 2 µs, makes settling
//! take ~10⁵ levels.)
//!
//! Step limit (note 000 §14, `BeamProperties::max_time_step`): time
//! marching is stable only for c_max Δt ≤ Δs (c_max = √(E/ρ) ≈ 5.2 km/s)
//! and Δt²(4c²/Δs² + kGA/ρI) ≤ 4 — the shear–rotation coupling, the
//! binding one for this slender beam (√(kGA/ρI) ≈ 1e6 s⁻¹). Δt is chosen
//! at 0.8 of the limit; a step above it is refused (the example shows the
//! error) unless explicitly allowed.
//!
//! Run: `cargo run --release -p veselov --example beam_time_evolution`.

use nalgebra::SVector;
use veselov::field::cauchy::CauchyOptions;
use veselov::field::evolution::{Direction, EndCondition, Evolution000};
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, Retraction, SE3};
use veselov::models::beam::{
    BeamDensity, BeamProperties, CayleyBeam, CrossSection, Material, ShearProperty, StepLimit, beam_lagrangian,
    left_generators,
};

const LENGTH: f64 = 0.8;
const SIDE: f64 = 0.01;

type Beam = Evolution000<RigidMotions, CayleyBeam, 6>;

fn steel() -> BeamProperties {
    let m = Material {
        density: 7800.0,
        young: 2.1e11,
        shear: ShearProperty::Poisson(0.3),
        shear_correction: 5.0 / 6.0,
    };
    BeamProperties::new(
        &CrossSection::Rectangle {
            width: SIDE,
            height: SIDE,
        },
        &m,
    )
    .expect("steel")
}

/// The beam bent with curvature `kappa` about E1: g_{a+1} = g_a cay(Δs(κe₁ + E6)).
fn bent(cells: usize, kappa: f64) -> Vec<SE3<f64>> {
    let ds = LENGTH / cells as f64;
    let step = CayleyMap::tau(&(SVector::<f64, 6>::from([kappa, 0.0, 0.0, 0.0, 0.0, 1.0]) * ds));
    let mut g = vec![SE3::identity(); cells + 1];
    for a in 0..cells {
        g[a + 1] = g[a].compose(&step);
    }
    g
}

fn energy(evo: &Beam) -> f64 {
    let mut e = 0.0;
    evo.for_each_cell(|_, _, y| e += evo.lagrangian().energy_densities::<RigidMotions, 6>(y).0);
    e * evo.lagrangian().ds()
}

fn release(name: &str, cells: usize, clamped: bool, levels: usize) {
    let props = steel();
    let ds = LENGTH / cells as f64;
    let dt = 0.8 * props.max_time_step(ds);
    if let Err(e) = props.check_step(StepLimit::Time, 2.0 * props.max_time_step(ds), ds, false) {
        println!("{name}: a step twice the limit is refused: {e}");
    }
    let courant = props
        .check_step(StepLimit::Time, dt, ds, false)
        .expect("within the limit");
    let lag = beam_lagrangian(BeamDensity::new(props), dt, ds).expect("lagrangian");
    let g0 = bent(cells, 0.5);
    let near = if clamped {
        EndCondition::Prescribed(Box::new(|_| SE3::identity()))
    } else {
        EndCondition::Natural
    };
    let mut evo = Beam::new(
        Direction::Time,
        lag,
        &g0,
        &g0,
        near,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("beam");
    println!("{name}: A = {cells}, ds = {ds} m, dt = {dt:.3e} s (Courant {courant:.2})");
    println!("{name}: level, t (s), tip y (m), E_L (J), |J_L| linear (N s)");
    let e0 = energy(&evo);
    let mut iterations = 0;
    for level in 1..=levels {
        if level > 1 {
            iterations += evo.step().expect("step").iterations;
        }
        if level % (levels / 20).max(1) == 0 || level == 1 {
            let j = evo.evolution_momentum(left_generators).plus;
            println!(
                "{level:6} {:.5e} {:+.5e} {:.6e} {:.3e}",
                level as f64 * dt,
                evo.value(0, cells).translation()[1],
                energy(&evo),
                SVector::<f64, 3>::new(j[3], j[4], j[5]).norm()
            );
        }
    }
    println!(
        "{name}: E_L relative change {:.2e}; Newton iterations per node {:.2}",
        (energy(&evo) - e0) / e0,
        iterations as f64 / ((levels - 1) * cells) as f64
    );
}

fn main() {
    release("free-free", 20, false, 2000);
    release("cantilever", 20, true, 2000);
}
