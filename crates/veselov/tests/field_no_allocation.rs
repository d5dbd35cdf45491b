#![allow(unsafe_code)] // a counting global allocator needs `unsafe impl GlobalAlloc`
//! The fast lattice paths allocate nothing per level: a counting global
//! allocator watches 200 levels of every scheme.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

use veselov::field::{FastMarcher, InitialData, Lattice, Scheme, SineGordon, SolverOptions};

struct Counting;
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static WATCHED: Cell<bool> = const { Cell::new(false) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if WATCHED.with(|w| w.get()) {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        // SAFETY: forwarding to the system allocator with the caller's layout.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by `System` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

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
