//! The rod's vertices solved side by side (groups of the split step in
//! vector lanes) against the same march one vertex at a time
//! (`with_vertex_lanes(1)`): the same bits at every vertex of every level,
//! on one and two threads, for a free tumbling rod, a clamped rod under a
//! potential with parameters varying along it, a damped cantilever with an
//! end load (the loads' impulses too), and a rod twisted so hard that its
//! groups leave the series branches and fall back.

use nalgebra::Vector3;
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions, LevelSplitting};
use veselov::field::fibre::{Fibre, Pose, PositionRotation};
use veselov::lie::so3;
use veselov::models::rod::{CosseratCell, CosseratDensity, LinearPotential, RodLoads, RodParameters, ShearFrame};
use veselov::models::rod::{EndCondition, RodEnds, RodLattice, load_impulse};

use crate::sample::{tumbling, unit_rod};
use crate::threads::on_threads;

type Rod<P> = CauchyMarcher<PositionRotation, CosseratCell<P>, 6>;

/// Every coordinate of the last `levels` levels of a march of `levels`
/// levels, as bits, with the iterations and Jacobians it reported.
fn history<P: veselov::models::rod::RodPotential + Clone + Send + Sync>(
    mut m: Rod<P>,
    levels: usize,
) -> (Vec<u64>, usize, usize) {
    let (mut bits, mut iterations, mut jacobians) = (Vec::new(), 0, 0);
    for _ in 0..levels {
        let report = m.step().expect("stable step");
        iterations += report.iterations;
        jacobians += report.jacobians;
        // The impulse of the loads, if any: the forces the solves stored.
        if let Some((p, l)) = load_impulse(&m) {
            bits.extend(p.iter().chain(l.iter()).map(|x| x.to_bits()));
        }
        for y in m.level_values(m.top_level()).expect("level") {
            let mut c = [0.0; 12];
            PositionRotation::write(y, &mut c);
            bits.extend(c.iter().map(|x| x.to_bits()));
        }
    }
    (bits, iterations, jacobians)
}

/// The march `make(lanes)` with the model's lanes and one vertex at a
/// time, on one and two threads: all four the same.
fn same_bits<P: veselov::models::rod::RodPotential + Clone + Send + Sync>(
    make: impl Fn(usize) -> Rod<P> + Sync,
    levels: usize,
) {
    let reference = on_threads(1, || history(make(1), levels));
    for threads in [1, 2] {
        let lanes = on_threads(threads, || history(make(8), levels));
        assert!(lanes.0 == reference.0, "{threads} threads: the bits differ");
        assert_eq!((lanes.1, lanes.2), (reference.1, reference.2), "{threads} threads");
    }
}

/// The march of `cell` on `lattice` from `motion`, with `ends` (free if
/// `None`) and at most `lanes` vertices solved together.
fn rod_march<P: veselov::models::rod::RodPotential + Clone + Send + Sync>(
    cell: CosseratCell<P>,
    lattice: &RodLattice,
    ends: Option<&RodEnds>,
    motion: impl Fn(f64, f64) -> Pose<f64>,
    tolerance: f64,
    lanes: usize,
) -> Rod<P> {
    let mut data = lattice.cauchy_data(motion);
    if let Some(ends) = ends {
        ends.apply(lattice, 0, &mut data);
    }
    let options = CauchyOptions {
        tolerance,
        ..CauchyOptions::default()
    };
    let m = CauchyMarcher::with_window(cell, lattice.torus().clone(), 0, &data, options, lattice.window())
        .expect("marcher")
        .with_vertex_lanes(lanes)
        .with_level_splitting(LevelSplitting::Always);
    match ends.and_then(|e| e.dirichlet(lattice)) {
        Some(d) => m.with_dirichlet(d),
        None => m,
    }
}

#[test]
fn free_rod_in_lanes_has_the_bits_of_one_vertex_at_a_time() {
    let lattice = RodLattice::new(61, 1.0, 0.005).expect("lattice");
    let cases = [1e-16, CauchyOptions::default().tolerance]
        .into_iter()
        .flat_map(|t| [(t, ShearFrame::Vertex), (t, ShearFrame::Centred)]);
    for (tolerance, frame) in cases {
        same_bits(
            |lanes| {
                let cell = CosseratCell::new(CosseratDensity::free(unit_rod(0.1)), lattice.ds(), lattice.dt())
                    .expect("spacings")
                    .with_shear_frame(frame);
                rod_march(cell, &lattice, None, tumbling(lattice.length()), tolerance, lanes)
            },
            120,
        );
    }
}

#[test]
fn clamped_profiled_rod_under_a_potential_in_lanes_has_the_same_bits() {
    let nodes = 41;
    let lattice = RodLattice::new(nodes, 1.0, 0.004).expect("lattice");
    let profile: Vec<RodParameters> = (0..nodes).map(|k| unit_rod(0.08 + 0.001 * k as f64)).collect();
    let motion = |s: f64, t: f64| {
        Pose::new(
            Vector3::new(0.03 * (3.0 * s).sin() + 0.1 * t, 0.0, s),
            so3::exp(&Vector3::new(0.1 * s * t, 0.09 * (3.0 * s).cos(), 0.2 * s)),
        )
    };
    let ends = RodEnds {
        start: EndCondition::Clamped(motion(0.0, 0.0)),
        end: EndCondition::Free,
    };
    for frame in [ShearFrame::Vertex, ShearFrame::Centred] {
        same_bits(
            |lanes| {
                let cell = CosseratCell::new(
                    CosseratDensity {
                        parameters: unit_rod(0.1),
                        potential: LinearPotential {
                            gradient: Vector3::new(0.0, -0.5, 0.1),
                        },
                    },
                    lattice.ds(),
                    lattice.dt(),
                )
                .expect("spacings")
                .with_profile(profile.clone())
                .expect("profile")
                .with_shear_frame(frame);
                rod_march(cell, &lattice, Some(&ends), motion, 1e-16, lanes)
            },
            100,
        );
    }
}

#[test]
fn a_rod_twisted_beyond_the_series_falls_back_with_the_same_bits() {
    // Between 0 and 0.57 rad of twist from one material point to the next:
    // the logarithms of the cells' arms leave the series branch
    // (tan θ ≤ 0.1) at more than half of the vertices, whose groups are
    // solved one vertex at a time, and stay within it at others.
    let lattice = RodLattice::new(31, 1.0, 0.004).expect("lattice");
    let twist = |s: f64, t: f64| 4.0 * s * (1.0 + 0.5 * (7.0 * s).sin()) + 0.3 * t;
    let spacing = lattice.ds() / 2.0;
    let steps: Vec<f64> = (0..30)
        .map(|k| (twist((k + 1) as f64 * spacing, 0.0) - twist(k as f64 * spacing, 0.0)).abs())
        .collect();
    let (beyond, within) = (
        steps.iter().filter(|&&d| d > 0.11).count(),
        steps.iter().filter(|&&d| d < 0.09).count(),
    );
    assert!(beyond >= 15 && within >= 8, "{steps:?}");
    same_bits(
        |lanes| {
            let cell =
                CosseratCell::new(CosseratDensity::free(unit_rod(0.1)), lattice.ds(), lattice.dt()).expect("spacings");
            let twisted = |s: f64, t: f64| {
                Pose::new(
                    Vector3::new(0.0, 0.01 * t, s),
                    so3::exp(&Vector3::new(0.0, 0.0, twist(s, t))),
                )
            };
            rod_march(cell, &lattice, None, twisted, 1e-16, lanes)
        },
        60,
    );
}

#[test]
fn damped_end_loaded_cantilever_in_lanes_has_the_same_bits_and_impulses() {
    let nodes = 33;
    let lattice = RodLattice::new(nodes, 1.0, 0.004).expect("lattice");
    let straight = |s: f64, _t: f64| Pose::new(Vector3::new(0.0, 0.0, s), so3::exp(&Vector3::zeros()));
    let ends = RodEnds {
        start: EndCondition::Clamped(straight(0.0, 0.0)),
        end: EndCondition::Free,
    };
    let loads = RodLoads {
        damping_linear: 0.5,
        damping_angular: 0.01,
        end_force: Vector3::new(0.02, -0.01, 0.0),
        end_torque: Vector3::new(0.0, 0.0, 0.003),
        tip: (nodes - 1) as i64,
        ramp: 0.05,
        start: 0.0,
    };
    for frame in [ShearFrame::Vertex, ShearFrame::Centred] {
        same_bits(
            |lanes| {
                let cell = CosseratCell::new(CosseratDensity::free(unit_rod(0.1)), lattice.ds(), lattice.dt())
                    .expect("spacings")
                    .with_loads(loads)
                    .expect("loads")
                    .with_shear_frame(frame);
                rod_march(cell, &lattice, Some(&ends), straight, 1e-16, lanes)
            },
            150,
        );
    }
}
