//! Where a run executes: on a thread of the rayon pool.

/// Runs `op` on a thread of the current rayon pool (in place if the caller
/// already is one) and returns its result.
///
/// The lattice marchers solve the vertices of a level in parallel. Called
/// from a thread outside the pool (a program's main thread), every parallel
/// level is a cold hand-over: the caller blocks on a lock until the pool has
/// solved the whole level and then waits to be woken, tens of µs per level,
/// so levels are only split when they cost more than about 150 µs. Called
/// on a thread of the pool, the caller solves its own share and the other
/// threads take the rest from its queue, a few µs per level, and levels from
/// about 10 µs up are split: a 100-element Cosserat rod runs 1.7× faster on
/// two threads. The results are bit-identical either way.
///
/// The command line and the Python package run every scenario through this.
/// A program that drives a marcher itself can do the same
/// (`veselov::run::on_pool(|| { for _ in 0..levels { marcher.step()?; } Ok(()) })`).
pub fn on_pool<R: Send>(op: impl FnOnce() -> R + Send) -> R {
    rayon::scope(|_| op())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `op` runs on a thread of the pool that the caller's context names
    /// (the global pool, or the pool installed around the call), and in
    /// place on a thread of that pool.
    #[test]
    fn runs_on_a_thread_of_the_current_pool() {
        assert!(on_pool(|| rayon::current_thread_index().is_some()));
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().expect("pool");
        let (outer, inner) = pool.install(|| {
            let outer = std::thread::current().id();
            (outer, on_pool(|| std::thread::current().id()))
        });
        assert_eq!(outer, inner, "already on the pool: in place");
        assert_eq!(pool.install(|| on_pool(rayon::current_num_threads)), 2);
    }
}
