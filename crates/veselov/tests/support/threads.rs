//! Runs a closure on a rayon pool of a given size (the tests that hold
//! results equal for every thread count).

/// `f` run on a fresh pool of `threads` threads.
pub fn on_threads<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}
