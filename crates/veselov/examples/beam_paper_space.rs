//! Seed 000 §5: the geometrically exact beam marched in space from the
//! prescribed motion of its first two columns (note 000 §15).
//!
//! Run: `cargo run --release -p veselov --example beam_paper_space`.
//!
//! The paper gives no material constants: this example takes steel
//! (ρ = 7800 kg/m³, E = 210 GPa, ν = 0.3, shear factor 5/6) on the paper's
//! 0.01 m square section. Two runs:
//!
//! * **literal** — the paper's ξ_0, ξ_1 (the root strain reaches large
//!   shear and stretch, note 000 §15.6): reports how many columns the march
//!   completes before a vertex solve fails;
//! * **well-posed** — column 1 is the rigid transport of column 0
//!   (ξ_1 = Ad_{h⁻¹}ξ_0, h = (I, (0, 0, Δs))) plus a 10⁻³ perturbation.
//!
//! For each computed column it prints 𝖩_𝖭 (angular first; constant across
//! columns under zero momentum in time, note 000 §11) and E_𝖭 (the
//! documented discrete form of (99), `field::split`).
//!
//! Index convention: time nodes j = 0..=51 (51 = the slaved node N, g^N =
//! g^{N−1} by zero momentum), space columns a = 0..=40 (s = aΔs, a = 40 ↔ L).

use nalgebra::SVector;
use veselov::field::cauchy::CauchyOptions;
use veselov::field::evolution::{Direction, EndCondition, Evolution000};
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, LieGroup, Retraction, SE3};
use veselov::models::beam::paper::{DS, DT, LAST_SPACE_NODE, LAST_TIME_NODE, SIDE, XI0, prescribed_columns};
use veselov::models::beam::{
    BeamDensity, BeamProperties, CayleyBeam, CrossSection, Material, ShearProperty, StepLimit, beam_lagrangian,
    left_generators,
};

fn march(name: &str, col0: &[SE3<f64>], col1: &[SE3<f64>], props: BeamProperties) {
    let lag: CayleyBeam = beam_lagrangian(BeamDensity::new(props), DT, DS).expect("lagrangian");
    let mut evo = match Evolution000::<RigidMotions, _, 6>::new(
        Direction::Space,
        lag,
        col0,
        col1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    ) {
        Ok(e) => e,
        Err(e) => {
            println!("{name}: the slaved node of column 1 cannot be solved: {e}");
            return;
        }
    };
    println!("{name}: column, J_N (6 components), E_N, Newton iterations per node");
    let report = |evo: &Evolution000<RigidMotions, CayleyBeam, 6>, iterations: f64| {
        let j = evo.evolution_momentum(left_generators);
        let mut e = 0.0;
        evo.for_each_cell(|_, _, y| e += evo.lagrangian().energy_densities::<RigidMotions, 6>(y).1);
        println!(
            "{:3} {:?} {:.6e} {iterations:.2}",
            evo.level() - 1,
            j.plus.as_slice(),
            e * DT
        );
        j.plus
    };
    let first = report(&evo, 0.0);
    let mut spread: f64 = 0.0;
    while evo.level() < LAST_SPACE_NODE {
        match evo.step() {
            Ok(r) => {
                let j = report(&evo, r.iterations as f64 / (LAST_TIME_NODE + 1) as f64);
                spread = spread.max((j - first).amax() / first.amax().max(f64::MIN_POSITIVE));
            }
            Err(e) => {
                println!("{name}: stopped after column {}: {e}", evo.level());
                break;
            }
        }
    }
    println!(
        "{name}: columns computed up to a = {}; max relative change of J_N {spread:.3e}",
        evo.level()
    );
}

fn main() {
    let steel = Material {
        density: 7800.0,
        young: 2.1e11,
        shear: ShearProperty::Poisson(0.3),
        shear_correction: 5.0 / 6.0,
    };
    let props = BeamProperties::new(
        &CrossSection::Rectangle {
            width: SIDE,
            height: SIDE,
        },
        &steel,
    )
    .expect("steel");
    let courant = props
        .check_step(StepLimit::Space, DT, DS, false)
        .expect("space marching limit");
    println!("space-marching Courant number ds/(c_min dt) = {courant:.3e}");
    let last = LAST_TIME_NODE + 1;
    let (c0, c1) = prescribed_columns::<CayleyMap>(last);
    march("literal", &c0, &c1, props);
    // Well-posed: column 1 = h⁻¹-transport of column 0's velocity, perturbed.
    let h = SE3::from_translation(nalgebra::Vector3::new(0.0, 0.0, DS));
    let xi1 = h.inverse().adjoint() * SVector::from(XI0) + SVector::from([1e-3, 0.0, -1e-3, 0.0, 0.0, 0.0]);
    let step = CayleyMap::tau(&(xi1 * DT));
    let mut c1 = vec![h; last + 1];
    for j in 0..last {
        c1[j + 1] = c1[j].compose(&step);
    }
    march("well-posed", &c0, &c1, props);
}
