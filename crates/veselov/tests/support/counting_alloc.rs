//! A counting global allocator for the no-allocation tests: allocations made
//! by the current thread while `WATCHED` is set are counted, and those of
//! the threads of a test's own pool (marked with the pool's number by
//! `mark_pool_thread`) while `POOL_WATCHED` holds that number.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

pub struct Counting;
pub static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);
/// Allocations of the watched pool's threads (a counter of their own: the
/// test harness runs other watched tests at the same time).
#[allow(dead_code)]
pub static POOL_ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    /// Only allocations made by the thread under test count (the test
    /// harness's own threads allocate at unpredictable times).
    pub static WATCHED: Cell<bool> = const { Cell::new(false) };
    /// The number of the test's pool this thread belongs to (0: none).
    static POOL_THREAD: Cell<usize> = const { Cell::new(0) };
}

/// The number of the pool whose threads' allocations count (0: none); the
/// threads of a pool dropped earlier, still winding down, never count.
#[allow(dead_code)] // not every test binary builds a pool
pub static POOL_WATCHED: AtomicUsize = AtomicUsize::new(0);

/// Marks the calling thread as one of pool `number` (≥ 1; a pool's start
/// handler).
#[allow(dead_code)]
pub fn mark_pool_thread(number: usize) {
    POOL_THREAD.with(|p| p.set(number));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if WATCHED.with(|w| w.get()) {
            ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
        }
        let pool = POOL_THREAD.with(|p| p.get());
        if pool != 0 && POOL_WATCHED.load(Ordering::SeqCst) == pool {
            POOL_ALLOCATIONS.fetch_add(1, Ordering::SeqCst);
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
