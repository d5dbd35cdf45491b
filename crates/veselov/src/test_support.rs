//! Helpers shared by the crate's unit tests.

/// Reproducible numbers uniform in [−½, ½) (xorshift64 from `seed`).
pub(crate) fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}
