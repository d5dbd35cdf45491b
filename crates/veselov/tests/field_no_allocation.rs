#![allow(unsafe_code)] // a counting global allocator needs `unsafe impl GlobalAlloc`
//! The fast lattice paths allocate nothing per level: a counting global
//! allocator watches 200 levels of every scheme.

use std::sync::atomic::Ordering;

use veselov::field::{FastMarcher, InitialData, Lattice, Scheme, SineGordon, SolverOptions};

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
