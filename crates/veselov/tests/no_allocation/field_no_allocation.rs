//! The lattice paths allocate nothing per level: a counting global
//! allocator watches 200 levels of every fast scheme and of the generic
//! (core) path on triangles and rectangles, periodic and Dirichlet, and 30
//! levels of the Cauchy marcher on 2+1 fields and on the rod, on one thread
//! and with levels split between two.

use std::sync::atomic::{AtomicUsize, Ordering};

use nalgebra::SVector;
use veselov::spacetime::{
    Boundary, CellLagrangian, FastMarcher, GenericMarcher, InitialData, Lattice, NonlinearWave, RectangleRule, Scheme,
    SineGordon, SolverOptions, TriangleRule,
};

use crate::counting_alloc;
use counting_alloc::{ALLOCATIONS, POOL_ALLOCATIONS, POOL_WATCHED, WATCHED, mark_pool_thread};

#[test]
fn level_updates_do_not_allocate() {
    let lat = Lattice::periodic(255, 40.0, 8.0).expect("valid");
    let (y0, y1) = InitialData::KinkAntikink {
        epsilon: 1e-6,
        paper_start: true,
    }
    .levels(&lat)
    .expect("data");
    for scheme in Scheme::ALL {
        let mut m = FastMarcher::new(SineGordon, scheme, lat, &y0, &y1, SolverOptions::default()).expect("valid");
        m.step().expect("warm-up");
        let before = ALLOCATIONS.load(Ordering::SeqCst);
        WATCHED.with(|w| w.set(true));
        for _ in 0..200 {
            m.step().expect("step");
            std::hint::black_box(m.energy());
        }
        m.recentre_mod_2pi();
        WATCHED.with(|w| w.set(false));
        assert_eq!(ALLOCATIONS.load(Ordering::SeqCst) - before, 0, "{scheme:?}");
    }
}

fn generic_levels_do_not_allocate<L: CellLagrangian<1>>(name: &str, lag: L, lat: Lattice) {
    let n = lat.nodes();
    let y0: Vec<SVector<f64, 1>> = (0..n)
        .map(|i| SVector::<f64, 1>::new(0.5 * (std::f64::consts::PI * i as f64 / (n - 1) as f64).sin()))
        .collect();
    let mut m = GenericMarcher::new(lag, lat, y0.clone(), y0).expect("valid");
    m.step().expect("warm-up");
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    WATCHED.with(|w| w.set(true));
    for _ in 0..200 {
        m.step().expect("step");
        std::hint::black_box(m.current());
    }
    WATCHED.with(|w| w.set(false));
    assert_eq!(ALLOCATIONS.load(Ordering::SeqCst) - before, 0, "{name}");
}

#[test]
fn generic_level_solves_do_not_allocate() {
    let (h, k) = (0.05, 0.1);
    let periodic = Lattice::new(64, k, h, Boundary::Periodic).expect("valid");
    let fixed = Lattice::new(64, k, h, Boundary::Dirichlet { left: 0.0, right: 0.0 }).expect("valid");
    let triangle = TriangleRule {
        density: NonlinearWave(SineGordon),
        dt: h,
        dx: k,
    };
    let rectangle = RectangleRule {
        density: NonlinearWave(SineGordon),
        dt: h,
        dx: k,
        symmetric: true,
    };
    generic_levels_do_not_allocate("periodic triangles", triangle, periodic);
    generic_levels_do_not_allocate("Dirichlet triangles", triangle, fixed);
    generic_levels_do_not_allocate("periodic rectangles", rectangle, periodic);
    generic_levels_do_not_allocate("Dirichlet rectangles", rectangle, fixed);
}

/// `levels` levels of a Cauchy march on a pool of `threads` threads, the
/// allocations of the pool's threads counted (after two warm-up levels, the
/// first measured on one thread and the second possibly split, and the
/// threads' one-time registration with their work queues).
fn cauchy_levels_allocations<F, L, const M: usize>(
    m: &mut veselov::field::cauchy::CauchyMarcher<F, L, M>,
    levels: usize,
    threads: usize,
) -> usize
where
    F: veselov::field::fibre::Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: veselov::field::cell::DiscreteLagrangian<F, M> + Sync,
{
    static POOLS: AtomicUsize = AtomicUsize::new(0);
    let number = POOLS.fetch_add(1, Ordering::SeqCst) + 1;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .start_handler(move |_| mark_pool_thread(number))
        .build()
        .expect("a thread pool");
    pool.install(|| {
        m.step().expect("warm-up");
        m.step().expect("warm-up");
        // A pool thread allocates once in its life, on its first look into
        // a work queue (it registers with the queues' memory reclamation);
        // every thread looks into its queue before it takes a broadcast job.
        pool.broadcast(|_| ());
        pool.broadcast(|_| ());
        let before = POOL_ALLOCATIONS.load(Ordering::SeqCst);
        POOL_WATCHED.store(number, Ordering::SeqCst);
        let mut parallel = 0;
        for _ in 0..levels {
            parallel += usize::from(std::hint::black_box(m.step().expect("level")).parallel);
        }
        POOL_WATCHED.store(0, Ordering::SeqCst);
        if threads > 1 {
            assert_eq!(parallel, levels, "every level split between {threads} threads");
        }
        POOL_ALLOCATIONS.load(Ordering::SeqCst) - before
    })
}

/// The Cauchy marcher's levels allocate nothing: the 2+1 midpoint rule of
/// sine-Gordon and of the complex Klein–Gordon field (closed form of the
/// diagonal jet metric), the same rule through dual numbers over whole
/// cells, and the Cosserat rod's split vertex step, free and with damping
/// and an end load.
#[test]
fn cauchy_levels_do_not_allocate() {
    use veselov::complex::CfkTorus;
    use veselov::field::cauchy::{CauchyMarcher, CauchyOptions, LevelSplitting};
    use veselov::field::discretize::{CfkNodes, MidpointRule};
    use veselov::field::fibre::Pose;
    use veselov::models::rod::{CosseratCell, CosseratDensity, RodParameters};
    use veselov::spacetime::potential::ComplexKleinGordon;
    let torus = CfkTorus::new(3, &[8, 8]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    let data = |m: usize| -> Vec<Vec<SVector<f64, 2>>> {
        (0..6)
            .map(|w| {
                (0..torus.level_size())
                    .map(|i| {
                        let x = nodes.node(&torus.vertex(w, i));
                        SVector::from_fn(|k, _| ((0.9 + k as f64) * x[0] - 0.4 * x[2]).sin() * (0.7 * x[1]).cos())
                            * (m as f64).recip()
                    })
                    .collect()
            })
            .collect()
    };
    let scalar: Vec<Vec<SVector<f64, 1>>> = data(1)
        .iter()
        .map(|level| level.iter().map(|y| SVector::from([y[0]])).collect())
        .collect();
    let sg = MidpointRule::new(NonlinearWave(SineGordon), nodes);
    // Every level split on two threads (whatever the levels measure).
    let mut a = CauchyMarcher::new(sg, torus.clone(), 0, &scalar, CauchyOptions::default())
        .expect("marcher")
        .with_level_splitting(LevelSplitting::Always);
    for threads in [1, 2] {
        assert_eq!(
            cauchy_levels_allocations(&mut a, 30, threads),
            0,
            "sine-Gordon, closed form, {threads} threads"
        );
    }
    let mut b = CauchyMarcher::new(
        sg.with_chain_rule(false),
        torus.clone(),
        0,
        &scalar,
        CauchyOptions::default(),
    )
    .expect("marcher");
    assert_eq!(
        cauchy_levels_allocations(&mut b, 30, 1),
        0,
        "sine-Gordon, dual numbers over cells"
    );
    let kg = MidpointRule::new(NonlinearWave(ComplexKleinGordon { m2: 1.0, lambda: 0.5 }), nodes);
    let mut c = CauchyMarcher::new(kg, torus.clone(), 0, &data(2), CauchyOptions::default()).expect("marcher");
    assert_eq!(
        cauchy_levels_allocations(&mut c, 30, 1),
        0,
        "complex Klein-Gordon, closed form"
    );
    let p = RodParameters::new(
        1.0,
        nalgebra::Matrix3::identity() * 0.1,
        nalgebra::Matrix3::identity() * 10.0,
        nalgebra::Matrix3::identity(),
        nalgebra::Vector3::new(0.0, 0.0, 1.0),
    )
    .expect("parameters");
    // 81 nodes: 41 vertices per level, each level split on two threads.
    let lattice = veselov::models::rod::RodLattice::new(81, 2.0, 0.002).expect("lattice");
    let cell = CosseratCell::new(CosseratDensity::free(p), lattice.ds(), 0.002).expect("cell");
    let rod = lattice.cauchy_data(|s, t| {
        Pose::new(
            nalgebra::Vector3::new(0.01 * (3.0 * s).sin() * (1.0 + t), 0.0, s),
            veselov::lie::so3::exp(&nalgebra::Vector3::new(0.01 * s, 0.0, 0.02 * t)),
        )
    });
    let loads = veselov::models::rod::RodLoads {
        damping_linear: 0.3,
        damping_angular: 0.01,
        end_force: nalgebra::Vector3::new(0.01, -0.02, 0.0),
        end_torque: nalgebra::Vector3::new(0.0, 0.001, 0.0),
        tip: 80,
        ramp: 0.1,
        start: 0.0,
    };
    for (name, cell) in [
        ("free", cell.clone()),
        ("damped and loaded", cell.with_loads(loads).expect("loads")),
    ] {
        let mut d = CauchyMarcher::with_window(
            cell,
            lattice.torus().clone(),
            0,
            &rod,
            CauchyOptions::default(),
            lattice.window(),
        )
        .expect("marcher")
        .with_level_splitting(LevelSplitting::Always);
        for threads in [1, 2] {
            assert_eq!(
                cauchy_levels_allocations(&mut d, 30, threads),
                0,
                "Cosserat rod, {name}, {threads} threads"
            );
        }
    }
}
