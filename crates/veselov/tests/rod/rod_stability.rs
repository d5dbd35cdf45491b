//! The step limit of the rod's march (note 003 §3.9 and the rotary
//! oscillator of `models::rod::stability`): below it the march is stable and
//! the vertex Newton converges in a few iterations; above it the march stops
//! with a typed error (never NaN); the check refuses such a step unless
//! overridden.

use nalgebra::Vector3;
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::fibre::{Fibre, Pose, PositionRotation};
use veselov::lie::so3;
use veselov::models::rod::{CosseratCell, CosseratDensity, RodParameters};
use veselov::models::rod::{
    CrossSection, Material, RodLattice, Shear, StepCheck, courant_number, largest_step, rod_parameters,
    rotary_frequency, wave_speed,
};

fn parameters(radius: f64) -> RodParameters {
    let material = Material {
        density: 5000.0,
        young: 1e6,
        shear: Shear::Modulus(1e4),
        shear_coefficient: 1.0,
    };
    rod_parameters(&CrossSection::Circle { radius }, &material).expect("valid rod")
}

/// Marches a noisy straight rod (all wavelengths excited) for `levels`
/// levels at step number `number`; returns the Newton iterations per vertex
/// or the error.
fn march(radius: f64, nodes: usize, number: f64, levels: usize) -> Result<f64, veselov::Error> {
    let p = parameters(radius);
    let ds = 2.0 * 3.0 / (nodes - 1) as f64;
    let dt = number * largest_step(&p, ds).expect("finite speeds");
    let lattice = RodLattice::new(nodes, 3.0, dt)?;
    StepCheck::Override.check(&p, lattice.ds(), dt)?;
    let cell = CosseratCell::new(CosseratDensity::free(p), lattice.ds(), dt)?;
    let data = lattice.cauchy_data(|s, _| {
        let noise = (s * 1234.567).sin() * 1e-3;
        Pose::new(
            Vector3::new(noise, 0.0, s),
            so3::exp(&Vector3::new(noise, 0.5 * noise, 0.2 * noise)),
        )
    });
    let options = CauchyOptions {
        tolerance: 1e-13,
        ..CauchyOptions::default()
    };
    let mut m = CauchyMarcher::with_window(cell, lattice.torus().clone(), 0, &data, options, lattice.window())?;
    let (mut iterations, mut vertices) = (0, 0);
    for _ in 0..levels {
        match m.step() {
            Ok(r) => {
                iterations += r.iterations;
                vertices += (0..lattice.torus().level_size())
                    .filter(|&i| m.is_active(r.level, i))
                    .count();
            }
            Err(e) => {
                // The marcher keeps its last complete state: finite values.
                for w in m.level() - 2..=m.top_level() {
                    assert!(
                        m.level_values(w)
                            .expect("kept level")
                            .iter()
                            .all(PositionRotation::is_finite)
                    );
                }
                return Err(e);
            }
        }
    }
    Ok(iterations as f64 / vertices as f64)
}

#[test]
fn wave_limit_holds_below_and_fails_with_a_typed_error_above() {
    // Thick rod (radius 0.25, PyElastica's example): the axial wave binds,
    // c = √(E/ρ), largest Δt = Δs/c.
    let p = parameters(0.25);
    assert!(wave_speed(&p).expect("finite") * 0.5 > rotary_frequency(&p).expect("finite") * 0.06 / 2.0);
    let per_vertex = march(0.25, 41, 0.95, 400).expect("stable below the limit");
    println!("wave limit: 0.95 × limit stable, {per_vertex:.2} Newton iterations per vertex");
    assert!(per_vertex < 6.0, "{per_vertex}");
    match march(0.25, 41, 1.1, 1500) {
        Err(veselov::Error::VertexSolveFailure { vertex, reason, .. }) => {
            println!("1.1 × limit: {vertex}: {reason}");
        }
        other => panic!("expected a vertex-solve failure above the limit, got {other:?}"),
    }
}

#[test]
fn rotary_limit_of_a_slender_rod_holds_below_and_fails_above() {
    // Slender rod (radius 0.01) on a coarse lattice: the shear–rotation
    // oscillator dominates, ω = √(κGA/(ρI)).
    let p = parameters(0.01);
    let ds = 2.0 * 3.0 / 20.0;
    let (c, omega) = (wave_speed(&p).expect("finite"), rotary_frequency(&p).expect("finite"));
    assert!(0.5 * omega > c / ds, "the rotary term dominates");
    assert!((omega - (1e4 * 4.0 / (5000.0 * 0.01_f64.powi(2))).sqrt()).abs() < 1e-9 * omega);
    let per_vertex = march(0.01, 21, 0.95, 400).expect("stable below the limit");
    println!("rotary limit: 0.95 × limit stable, {per_vertex:.2} Newton iterations per vertex");
    assert!(per_vertex < 6.0, "{per_vertex}");
    assert!(matches!(
        march(0.01, 21, 1.1, 1500),
        Err(veselov::Error::VertexSolveFailure { .. })
    ));
}

#[test]
fn the_step_check_refuses_unstable_steps_unless_overridden() {
    let p = parameters(0.25);
    let ds = 0.06;
    let limit = largest_step(&p, ds).expect("finite speeds");
    assert!((courant_number(&p, ds, limit).expect("finite") - 1.0).abs() < 1e-12);
    StepCheck::Enforce.check(&p, ds, 0.99 * limit).expect("below the limit");
    let err = StepCheck::Enforce
        .check(&p, ds, 1.01 * limit)
        .expect_err("above the limit");
    assert!(
        matches!(&err, veselov::Error::InvalidParameter { name, .. } if name == "dt"),
        "{err}"
    );
    assert!(err.to_string().contains("largest stable dt"), "{err}");
    StepCheck::Override.check(&p, ds, 1.01 * limit).expect("overridden");
}
