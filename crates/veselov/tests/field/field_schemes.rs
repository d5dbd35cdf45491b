//! The fast paths solve the printed residual forms (5.8), (5.10), (5.12),
//! (5.14), (5.15) (with the corrected increment forms of note 002 §1.4).

use veselov::spacetime::{FastMarcher, InitialData, Lattice, ScalarPotential, Scheme, SineGordon, SolverOptions};

fn kink_antikink(n: usize, ratio: f64) -> (Lattice, Vec<f64>, Vec<f64>) {
    let lat = Lattice::periodic(n, 40.0, ratio).expect("valid lattice");
    let (y0, y1) = InitialData::KinkAntikink {
        epsilon: 1e-6,
        paper_start: false,
    }
    .levels(&lat)
    .expect("valid data");
    (lat, y0, y1)
}

/// Residual of the scheme at every node of level `j` from levels `j−1, j, j+1`
/// (periodic), and the scale `Σ|terms|` of the largest node.
pub fn residual(scheme: Scheme, lat: &Lattice, ym: &[f64], y: &[f64], yp: &[f64]) -> (f64, f64) {
    let n = y.len();
    let (h, k) = (lat.dt(), lat.dx());
    let pot = SineGordon;
    let np = |v: f64| pot.jet(v)[1];
    let w = |i: isize| ((i + n as isize) % n as isize) as usize;
    let dk = |l: &[f64], i: isize| l[w(i + 1)] - 2.0 * l[w(i)] + l[w(i - 1)];
    let dh = |i: isize| yp[w(i)] - 2.0 * y[w(i)] + ym[w(i)];
    let rect = |a: &[f64], b: &[f64], i: isize| 0.25 * (a[w(i)] + b[w(i)] + b[w(i + 1)] + a[w(i + 1)]);
    let mut worst: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for ii in 0..n as isize {
        let space = (0.25 * dk(yp, ii) + 0.5 * dk(y, ii) + 0.25 * dk(ym, ii)) / (k * k);
        let nbar =
            0.25 * (np(rect(y, yp, ii)) + np(rect(y, yp, ii - 1)) + np(rect(ym, y, ii)) + np(rect(ym, y, ii - 1)));
        // (cos a − cos b)/(a − b) without cancellation (a ≈ b on the plateaus).
        let dd = |a: f64, b: f64| {
            let d = 0.5 * (a - b);
            let sinc = if d == 0.0 { 1.0 } else { d.sin() / d };
            -(0.5 * (a + b)).sin() * sinc
        };
        let i = w(ii);
        let r = match scheme {
            Scheme::Triangle => {
                let c1 = (y[i] + yp[i] + yp[w(ii + 1)]) / 3.0;
                let c2 = (ym[i] + y[i] + y[w(ii + 1)]) / 3.0;
                let c3 = (ym[w(ii - 1)] + y[w(ii - 1)] + y[i]) / 3.0;
                dk(y, ii) / (k * k) - dh(ii) / (h * h) + (np(c1) + np(c2) + np(c3)) / 3.0
            }
            Scheme::Rectangle => space - dh(ii) / (h * h) + nbar,
            Scheme::SymmetricRectangle => {
                space - (0.25 * dh(ii + 1) + 0.5 * dh(ii) + 0.25 * dh(ii - 1)) / (h * h) + nbar
            }
            Scheme::VuQuocLi => space - dh(ii) / (h * h) + 0.5 * (dd(yp[i], y[i]) + dd(y[i], ym[i])),
            Scheme::Guo => dk(y, ii) / (k * k) - dh(ii) / (h * h) + dd(yp[i], ym[i]),
            Scheme::TriangleExplicit => dk(y, ii) / (k * k) - dh(ii) / (h * h) + np(y[i]),
        };
        worst = worst.max(r.abs());
        let ymax = yp[i].abs().max(y[i].abs()).max(ym[i].abs()).max(1.0);
        scale = scale.max(4.0 * ymax / (h * h) + 4.0 * ymax / (k * k) + 1.0);
    }
    (worst, scale)
}

#[test]
fn fast_paths_solve_the_residual_forms() {
    for scheme in Scheme::ALL {
        let (lat, y0, y1) = kink_antikink(64, 8.0);
        let mut m = FastMarcher::new(SineGordon, scheme, lat, &y0, &y1, SolverOptions::default()).expect("valid");
        let mut worst_rel: f64 = 0.0;
        for _ in 0..400 {
            m.step().expect("step");
            let (r, s) = residual(
                scheme,
                &lat,
                m.level_values(2).expect("stored"),
                m.level_values(1).expect("stored"),
                m.level_values(0).expect("stored"),
            );
            worst_rel = worst_rel.max(r / s);
        }
        println!(
            "{scheme:?}: worst relative residual {worst_rel:e}, iterations {}",
            m.total_iterations()
        );
        // The level solves stop at a y-error ≤ 1e-13·max|y|, i.e. a residual
        // ≤ 2·1e-13·max|y|/h² ≤ 0.5e-13·scale; evaluation round-off ≈ 1e-15·scale.
        assert!(worst_rel < 1e-12, "{scheme:?}: {worst_rel:e}");
    }
}
