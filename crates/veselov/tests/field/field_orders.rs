//! Convergence orders on a nonlinear problem: every scheme against the exact
//! sine-Gordon breather (second order in k at fixed h/k).

use veselov::diagnostics::fit_order;
use veselov::spacetime::{FastMarcher, InitialData, Lattice, Scheme, SineGordon, SolverOptions};

/// Breather with ω = 0.5 on a circle of length 60: its tails are
/// ~e^{−30·√(1−ω²)} ≈ 5·10⁻¹² at the seam, far below the errors fitted.
const DATA: InitialData = InitialData::Breather { omega: 0.5, x0: 30.0 };

fn error(scheme: Scheme, n: usize) -> (f64, f64) {
    let lat = Lattice::periodic(n, 60.0, 2.0).expect("valid"); // h = k/2
    let (y0, y1) = DATA.levels(&lat).expect("data");
    let mut m = FastMarcher::new(SineGordon, scheme, lat, &y0, &y1, SolverOptions::default()).expect("valid");
    let levels = (5.0 / lat.dt()).round() as usize; // T = 5: a generic phase of the breather (period 4π)
    while m.level() < levels {
        m.step().expect("step");
    }
    let exact = DATA.exact(&lat, m.time()).expect("valid").expect("known");
    let e = m
        .current()
        .iter()
        .zip(&exact)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    (lat.dx(), e)
}

#[test]
fn all_schemes_are_second_order_on_the_breather() {
    for scheme in Scheme::ALL {
        let (mut ks, mut es) = (Vec::new(), Vec::new());
        for n in [192, 384, 768, 1536] {
            let (k, e) = error(scheme, n);
            ks.push(k);
            es.push(e);
        }
        let fit = fit_order(&ks, &es, 1e-10).expect("fit");
        println!("{}: errors {es:.3?}, order {:.3}", scheme.name(), fit.order);
        assert!((fit.order - 2.0).abs() <= 0.2, "{}: order {}", scheme.name(), fit.order);
    }
}
