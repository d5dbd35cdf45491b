//! Wave equation (N = 0) with the triangle scheme (5.8) = leapfrog:
//! second-order convergence to d'Alembert's solution from an exact second
//! level, stability for h/k < 1 and growth for h/k > 1.

use veselov::diagnostics::fit_order;
use veselov::spacetime::{FastMarcher, InitialData, Lattice, Scheme, SolverOptions, Wave};

const DATA: InitialData = InitialData::DAlembert {
    amplitude: 1.0,
    mode: 1,
    drift: 0.0,
};

fn max_error_at(n: usize, ratio: f64, t_end: f64) -> (f64, f64) {
    let lat = Lattice::periodic(n, 8.0, ratio).expect("valid");
    let (y0, y1) = DATA.levels(&lat).expect("data");
    let mut m = FastMarcher::new(Wave, Scheme::Triangle, lat, &y0, &y1, SolverOptions::default()).expect("valid");
    let levels = (t_end / lat.dt()).round() as usize;
    while m.level() < levels {
        m.step().expect("step");
    }
    let exact = DATA.exact(&lat, m.time()).expect("valid").expect("known");
    let err = m
        .current()
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    (lat.dx(), err)
}

#[test]
fn triangle_scheme_converges_at_second_order() {
    let (mut hs, mut errs) = (Vec::new(), Vec::new());
    for n in [32, 64, 128, 256, 512] {
        // h/k = 0.5, T = 3: at T = L/2 = 4 every mode sits at an extremum of
        // cos(ωT) and the phase error cancels to first order (superconvergence).
        let (k, e) = max_error_at(n, 2.0, 3.0);
        println!("N = {n}: k = {k:.4}, max error {e:.3e}");
        hs.push(k);
        errs.push(e);
    }
    let fit = fit_order(&hs, &errs, 1e-12).expect("fit");
    println!("fitted order {:.3}", fit.order);
    assert!((fit.order - 2.0).abs() <= 0.2, "order {}", fit.order);
}

/// Ratio of the final to the initial max |y| after `levels` levels, or
/// infinity if the run blew up.
fn growth(courant: f64, levels: usize) -> f64 {
    let lat = Lattice::periodic(64, 8.0, 1.0 / courant).expect("valid");
    let (y0, y1) = DATA.levels(&lat).expect("data");
    let max0 = y0.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
    let mut m = FastMarcher::new(Wave, Scheme::Triangle, lat, &y0, &y1, SolverOptions::default()).expect("valid");
    for _ in 0..levels {
        if m.step().is_err() {
            return f64::INFINITY;
        }
    }
    m.current().iter().fold(0.0_f64, |a, b| a.max(b.abs())) / max0
}

#[test]
fn triangle_wave_stability_threshold() {
    // Dispersion sin²(ω/2) = (h/k)² sin²(θ/2): real ω for all θ iff h/k ≤ 1.
    let stable = growth(0.9, 2000);
    // h/k = 1.1: the θ = π mode (seeded by rounding, ~1e-16) has amplification
    // |λ| = r + √(r² − 1) with cosh-type r = 2(h/k)² − 1 = 1.42 → |λ| ≈ 2.4 per
    // level, so 2000 levels overflow.
    let unstable = growth(1.1, 2000);
    println!("max|y| growth: h/k = 0.9: {stable:.3}, h/k = 1.1: {unstable:e}");
    assert!(stable < 1.5, "h/k = 0.9 must stay bounded: {stable}");
    assert!(unstable > 1e6, "h/k = 1.1 must grow: {unstable}");
}
