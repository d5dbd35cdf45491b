//! Shared helpers of the integration tests.
#![allow(dead_code)]

use veselov::diagnostics::{OrderFit, fit_order_asymptotic};
use veselov::mechanics::{GalerkinScheme, Method, OneStepMap, PhaseState, integrate};

/// Every method of the core with its claimed order.
pub fn all_methods() -> Vec<Method> {
    let mut m = vec![Method::Midpoint, Method::Trapezoid, Method::Alpha(0.3)];
    m.extend((2..=6).map(Method::GalerkinLobatto));
    m.extend((1..=5).map(Method::GalerkinGauss));
    m
}

pub fn scheme(method: Method) -> GalerkinScheme {
    GalerkinScheme::new(method).expect("valid built-in method")
}

/// Error window used for order fits. Above `UPPER` the step is
/// pre-asymptotic for the nonlinear problems used here. Below `LOWER` the
/// round-off plateau begins: with compensated summation the plateau of these
/// runs sits at about 1e-15 for ~10² steps and grows with the step count n;
/// points below `max(LOWER, 1e-16·n)` are masked (a factor ≥ 50 above it).
pub const UPPER: f64 = 1e-3;
pub const LOWER: f64 = 5e-14;

/// How many of the smallest-step points above the plateau enter a fit (the
/// asymptotic range; with step ratio √2 they span a factor 2.8 in h).
pub const FIT_POINTS: usize = 4;

/// Upper end of the error window for a method of order `p`: first-order
/// methods are asymptotic from large steps on (their local rates are already
/// 1.0 at errors ~1e-1), higher orders need the smaller errors.
pub fn upper_for(order: usize) -> f64 {
    if order == 1 { 0.3 } else { UPPER }
}

/// Run a convergence study: for each `n` in `steps`, integrate to `t_end` with
/// `h = t_end / n` and measure the max-norm error of `(q, p)` against `exact`.
/// Points outside the error window are masked; returns the fit and the table.
pub fn study<const N: usize, M: OneStepMap<N>>(
    order: usize,
    mut make: impl FnMut(f64) -> M,
    x0: PhaseState<N>,
    t_end: f64,
    exact: &PhaseState<N>,
    steps: &[usize],
) -> (Option<OrderFit>, Vec<(f64, f64)>) {
    let mut table = Vec::new();
    for &n in steps {
        let h = t_end / n as f64;
        let mut map = make(h);
        let run = integrate(&mut map, x0, n, n);
        assert!(run.failure.is_none(), "h = {h}: {:?}", run.failure);
        let x = run.last();
        let err = (x.q - exact.q).amax().max((x.p - exact.p).amax());
        table.push((h, err));
        if err < floor(n) {
            break;
        }
    }
    (fit_asymptotic(&table, t_end, order), table)
}

/// The round-off mask for a run of `n` steps.
pub fn floor(n: usize) -> f64 {
    LOWER.max(1e-16 * n as f64)
}

/// Fit over the `FIT_POINTS` smallest steps `h` whose error lies in
/// `(floor(n), upper_for(order)]`, `n` the step count over a horizon `t_end = n·h`.
pub fn fit_asymptotic(table: &[(f64, f64)], t_end: f64, order: usize) -> Option<OrderFit> {
    // Mask per point with its own round-off floor, then fit the asymptotic range.
    let (h, e): (Vec<f64>, Vec<f64>) = table
        .iter()
        .map(|&(h, e)| {
            (
                h,
                if e > floor((t_end / h).round() as usize) {
                    e
                } else {
                    0.0
                },
            )
        })
        .unzip();
    fit_order_asymptotic(&h, &e, LOWER, upper_for(order), FIT_POINTS)
}

/// Geometric sequence of step counts from `n0`, ratio about √2.
pub fn step_counts(n0: usize, count: usize) -> Vec<usize> {
    (0..count)
        .map(|k| (n0 as f64 * 2f64.powf(k as f64 / 2.0)).round() as usize)
        .collect()
}

/// The kink–antikink data of seed 002 §5.2 (paper start, ε = 1e-6) on a
/// periodic lattice of `nodes` nodes over length 40 with h = k/`ratio`.
pub fn kink_antikink(nodes: usize, ratio: f64) -> (veselov::spacetime::Lattice, Vec<f64>, Vec<f64>) {
    let lat = veselov::spacetime::Lattice::periodic(nodes, 40.0, ratio).expect("valid lattice");
    let (y0, y1) = veselov::spacetime::InitialData::KinkAntikink {
        epsilon: 1e-6,
        paper_start: true,
    }
    .levels(&lat)
    .expect("initial data");
    (lat, y0, y1)
}
