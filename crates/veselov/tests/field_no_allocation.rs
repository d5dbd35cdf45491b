#![allow(unsafe_code)] // a counting global allocator needs `unsafe impl GlobalAlloc`
//! The lattice paths allocate nothing per level: a counting global
//! allocator watches 200 levels of every fast scheme and of the generic
//! (core) path on triangles and rectangles, periodic and Dirichlet.

use std::sync::atomic::Ordering;

use nalgebra::SVector;
use veselov::field::{
    Boundary, CellLagrangian, FastMarcher, GenericMarcher, InitialData, Lattice, NonlinearWave, RectangleRule, Scheme,
    SineGordon, SolverOptions, TriangleRule,
};

#[path = "support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{ALLOCATIONS, WATCHED};

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
