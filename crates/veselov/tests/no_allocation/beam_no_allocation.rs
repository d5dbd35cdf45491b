//! Beam evolution allocates nothing per level: the rolling window of the
//! core's flow marcher is reused for time and space evolution and for the
//! time evolution with the trapezoid rule, its end cell and an end load
//! (100 levels each, the evolution momentum map read after every level).

use std::sync::atomic::Ordering;

use nalgebra::{SVector, Vector3};
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000};
use veselov::evolution::split::KineticQuadrature;
use veselov::field::cauchy::CauchyOptions;
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, Retraction, SE3};
use veselov::models::EndLoad;
use veselov::models::beam::{BeamDensity, BeamProperties, CayleyBeam, beam_lagrangian, left_generators, straight};

use crate::counting_alloc;
use counting_alloc::{ALLOCATIONS, WATCHED};

#[test]
fn evolution_levels_do_not_allocate() {
    let p = BeamProperties::from_diagonals([0.5, 0.5, 1.0, 1.0, 1.0, 1.0], [0.5, 0.5, 0.6, 1.0, 1.0, 1.0])
        .expect("positive");
    let xi = SVector::<f64, 6>::from([0.01, -0.02, 0.03, 0.0, 0.01, 0.0]);
    let cases = [
        (Direction::Time, 0.05, 0.1, false),
        (Direction::Time, 0.05, 0.1, true),
        (Direction::Space, 0.1, 0.05, false),
    ];
    for (direction, dt, ds, trapezoid) in cases {
        let mut lag: CayleyBeam = beam_lagrangian(BeamDensity::new(p), dt, ds).expect("lagrangian");
        let mut far = EndCondition::Natural;
        if trapezoid {
            let load = EndLoad {
                force: Vector3::new(0.0, -0.1, 0.0),
                torque: Vector3::new(0.05, 0.0, 0.0),
                ramp: 0.5,
                start: 0.0,
            };
            let density = BeamDensity::new(p).with_end_load(load).expect("load");
            lag = beam_lagrangian(density, dt, ds)
                .expect("lagrangian")
                .with_quadrature(KineticQuadrature::Trapezoid { last: 6 });
            far = EndCondition::EndCell;
        }
        let (first, second): (Vec<SE3<f64>>, Vec<SE3<f64>>) = match direction {
            Direction::Time => (
                (0..=6).map(|a| straight(ds, a)).collect(),
                (0..=6)
                    .map(|a| straight(ds, a).compose(&CayleyMap::tau(&(xi * dt))))
                    .collect(),
            ),
            Direction::Space => (
                (0..=6).map(|j| CayleyMap::tau(&(xi * (j as f64 * dt)))).collect(),
                (0..=6)
                    .map(|j| CayleyMap::tau(&(xi * (j as f64 * dt))).compose(&straight(ds, 1)))
                    .collect(),
            ),
        };
        let mut evo = Evolution000::<RigidMotions, _, 6>::new(
            direction,
            lag,
            &first,
            &second,
            EndCondition::Natural,
            far,
            CauchyOptions::default(),
        )
        .expect("evolution");
        evo.step().expect("warm-up");
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        WATCHED.with(|w| w.set(true));
        for _ in 0..100 {
            evo.step().expect("step");
            std::hint::black_box(evo.evolution_momentum(left_generators));
        }
        WATCHED.with(|w| w.set(false));
        assert_eq!(
            ALLOCATIONS.load(Ordering::SeqCst) - before,
            0,
            "{direction:?}, trapezoid {trapezoid}"
        );
    }
}
