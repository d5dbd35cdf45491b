//! Sine-Gordon experiments of seed 002 §5.2 at test scale: bounded energy
//! errors without drift, Guo's exactly conserved energy, the single kink's
//! speed, and the even/odd mode of the symmetric rectangle scheme.

use crate::common;
use common::kink_antikink;
use std::f64::consts::{PI, TAU};

use veselov::spacetime::{Boundary, FastMarcher, InitialData, Lattice, Scheme, SineGordon, SolverOptions};

struct Block {
    min: f64,
    mean: f64,
    max: f64,
}

/// Energies of `levels` levels in blocks of `block`.
fn energy_blocks(scheme: Scheme, levels: usize, block: usize) -> (f64, Vec<Block>) {
    let (lat, y0, y1) = kink_antikink(255, 8.0);
    let mut m = FastMarcher::new(SineGordon, scheme, lat, &y0, &y1, SolverOptions::default()).expect("valid");
    m.step().expect("step");
    let e0 = m.energy();
    let mut blocks = Vec::new();
    let (mut lo, mut hi, mut sum, mut count) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0);
    for _ in 0..levels {
        m.step().expect("step");
        if m.level() % 1000 == 0 {
            m.recentre_mod_2pi();
        }
        let e = m.energy() - e0;
        lo = lo.min(e);
        hi = hi.max(e);
        sum += e;
        count += 1;
        if count == block {
            blocks.push(Block {
                min: lo,
                mean: sum / count as f64,
                max: hi,
            });
            (lo, hi, sum, count) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0);
        }
    }
    (e0, blocks)
}

/// Levels in ten collision periods of the kink–antikink pair: the solitons
/// move at ±c on the circle of length 40 and meet every 40/(2c) time units
/// (≈ 25.73); the energy error oscillates with that period, so means over
/// whole periods remove the oscillation and leave any drift.
fn ten_collision_periods(h: f64) -> usize {
    let c = veselov::spacetime::PeriodicKink::new(10.0, 1e-6).expect("kink").speed;
    (10.0 * 40.0 / (2.0 * c) / h).round() as usize
}

/// The energy error over `time_units` in windows of ten collision periods:
/// (mean of E − E₀ over the first half of the windows, over the second half,
/// the largest |E − E₀| of the first window, the largest |E − E₀|).
fn drift(scheme: Scheme, time_units: f64) -> (f64, f64, f64, f64) {
    let h = 40.0 / 255.0 / 8.0;
    let levels = (time_units / h) as usize;
    let window = ten_collision_periods(h);
    let (_, blocks) = energy_blocks(scheme, levels, window);
    let worst = blocks.iter().map(|b| b.max.abs().max(b.min.abs())).fold(0.0, f64::max);
    let first_excursion = blocks[0].max.abs().max(blocks[0].min.abs());
    let half = blocks.len() / 2;
    let mean = |b: &[Block]| b.iter().map(|b| b.mean).sum::<f64>() / b.len() as f64;
    (mean(&blocks[..half]), mean(&blocks[half..]), first_excursion, worst)
}

/// Asserts, for each scheme with its bound, that the mean energy error over
/// the second half of the run differs from that over the first half by at
/// most the bound (means over whole collision periods remove the collision
/// oscillation, of amplitude ≈ 0.09 for the triangles and rectangles and
/// 2.5·10⁻³ for the symmetric rectangles, |E₀| ≈ 14.6), and that the error
/// stays within 1.5 times its first excursion.
fn assert_no_drift(time_units: f64, cases: &[(Scheme, f64)]) {
    for &(scheme, bound) in cases {
        let (first, second, excursion, worst) = drift(scheme, time_units);
        let d = (second - first).abs();
        println!(
            "{}: mean E − E₀ over the first half {first:.4e}, over the second {second:.4e} (change {d:.2e}), max |ΔE| {worst:.3e}",
            scheme.name()
        );
        assert!(
            d <= bound,
            "{}: drift {d:e} over {time_units} time units",
            scheme.name()
        );
        assert!(worst <= 1.5 * excursion, "{}: unbounded error {worst:e}", scheme.name());
    }
}

#[test]
fn multisymplectic_energy_errors_do_not_drift() {
    // 2000 time units = 102 000 levels at h = k/8 = 0.0196 (≈ 78 collisions,
    // 7 windows). Measured changes of the half-run means: triangle 2·10⁻⁶,
    // symmetric rectangle 7·10⁻⁵ (the settling of its first windows), the
    // paper's two schemes, held to 2·10⁻⁴ (the old test compared against the
    // collision spread and would have passed 0.18). The non-symmetric
    // rectangle (5.10), which the paper did not run for long, shows a slow
    // decline of its means (−2·10⁻³ per 2000 time units at first, about
    // −7·10⁻³ over 30 000 measured), 2 % of its oscillation here: held to
    // 3·10⁻³, and reported.
    assert_no_drift(
        2000.0,
        &[
            (Scheme::Triangle, 2e-4),
            (Scheme::SymmetricRectangle, 2e-4),
            (Scheme::Rectangle, 3e-3),
        ],
    );
}

/// The whole horizon of seed 002 §5.2 (t = 129 000, 6.6 million levels per
/// scheme) for the paper's two multisymplectic schemes (measured: changes of
/// the half-run means 1.2·10⁻⁷ for the triangles, 5.6·10⁻⁸ for the symmetric
/// rectangles; six minutes on two busy cores):
/// `cargo test --release -p veselov --test field field_sine_gordon:: -- --ignored --nocapture`.
#[test]
#[ignore = "long: the whole §5.2 horizon, a few minutes"]
fn multisymplectic_energy_errors_do_not_drift_over_the_paper_horizon() {
    assert_no_drift(
        129_000.0,
        &[(Scheme::Triangle, 2e-4), (Scheme::SymmetricRectangle, 2e-4)],
    );
}

#[test]
fn guo_energy_is_conserved_to_round_off() {
    let (lat, y0, y1) = kink_antikink(255, 8.0);
    // E^{j+½} changes per level by k·Σ_i (y⁺ − y⁻)·(residual of (5.15)), so
    // it is conserved to round-off only when the level solves are: solve to
    // ~1 ulp (the per-node contraction is h²/2 ≈ 2·10⁻⁴, so this costs one
    // extra iteration at most).
    let opts = SolverOptions {
        rel_tol: 1e-16,
        ..SolverOptions::default()
    };
    let mut m = FastMarcher::new(SineGordon, Scheme::Guo, lat, &y0, &y1, opts).expect("valid");
    m.step().expect("step");
    let e0 = m.energy();
    let mut worst: f64 = 0.0;
    for _ in 0..20_000 {
        m.step().expect("step");
        worst = worst.max((m.energy() - e0).abs());
    }
    println!("Guo: E = {e0}, max |E^(j+1/2) − E^(1/2)| = {worst:e} over 20000 levels");
    // Rounding: each level's sum has 255 terms of size ≲ 30 (|y_t|² up to
    // 1/(1−c²) ≈ 2.5 and |y_x|² likewise, times k), error ≈ √255·ε·30 ≈ 10⁻¹³
    // absolute per level; a random walk over 2·10⁴ levels ≈ 1.5·10⁻¹¹,
    // i.e. 10⁻¹² relative to |E| ≈ 14.6 (observed ≈ 5·10⁻¹²). The multisymplectic schemes' energy
    // errors are 10⁻³..10⁻¹ by comparison.
    assert!(worst <= 1e-11 * e0.abs(), "{worst:e}");
}

/// Position of the (single) kink: where y crosses an odd multiple of π.
fn kink_position(lat: &Lattice, y: &[f64]) -> f64 {
    let n = y.len();
    for i in 0..n {
        let (a, b) = (y[i], if i + 1 < n { y[i + 1] } else { y[0] + TAU });
        let (fa, fb) = (((a - PI) / TAU).floor(), ((b - PI) / TAU).floor());
        if fa < fb {
            let level = PI + TAU * fb;
            return lat.x(i) + lat.dx() * (level - a) / (b - a);
        }
    }
    f64::NAN
}

#[test]
fn single_kink_travels_at_its_speed() {
    let c = 0.5;
    let lat = Lattice::new(400, 0.1, 0.1 / 8.0, Boundary::Winding { jump: TAU }).expect("valid");
    let data = InitialData::Kink { x0: 20.0, speed: c };
    let (y0, y1) = data.levels(&lat).expect("data");
    for scheme in [
        Scheme::Triangle,
        Scheme::SymmetricRectangle,
        Scheme::Rectangle,
        Scheme::Guo,
    ] {
        let mut m = FastMarcher::new(SineGordon, scheme, lat, &y0, &y1, SolverOptions::default()).expect("valid");
        let l = lat.length();
        let mut x_prev = kink_position(&lat, m.current());
        let x_start = x_prev;
        let mut travelled = 0.0;
        let per_unit = (1.0 / lat.dt()).round() as usize; // 80 levels per time unit
        for _ in 0..100 {
            for _ in 0..per_unit {
                m.step().expect("step");
            }
            let x = kink_position(&lat, m.current());
            let dx = (x - x_prev + 0.5 * l).rem_euclid(l) - 0.5 * l;
            travelled += dx;
            x_prev = x;
        }
        let speed = travelled / (m.time() - lat.dt());
        println!(
            "{}: kink speed {speed:.6} (exact {c}), start {x_start:.3}",
            scheme.name()
        );
        assert!((speed - c).abs() <= 0.005 * c, "{}: {speed}", scheme.name());
    }
}

/// max_i |d_i| of the difference of a seeded and an unseeded run after
/// `levels` levels of the symmetric rectangle scheme.
fn seeded_difference(n: usize, levels: usize, eps: f64) -> Vec<f64> {
    let (lat, y0, y1) = kink_antikink(n, 8.0);
    let mut z0 = y0.clone();
    let mut z1 = y1.clone();
    for i in 0..n {
        // Same sign on both levels: (A + Bj)(−1)^{i+j} with A = ε, B = −2ε.
        let s = if i % 2 == 0 { eps } else { -eps };
        z0[i] += s;
        z1[i] += s;
    }
    let o = SolverOptions::default();
    let mut a = FastMarcher::new(SineGordon, Scheme::SymmetricRectangle, lat, &y0, &y1, o).expect("valid");
    let mut b = FastMarcher::new(SineGordon, Scheme::SymmetricRectangle, lat, &z0, &z1, o).expect("valid");
    let mut out = Vec::new();
    for j in 0..levels {
        a.step().expect("step");
        b.step().expect("step");
        if (j + 1) % (levels / 4) == 0 {
            let d = a
                .current()
                .iter()
                .zip(b.current())
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            out.push(d);
        }
    }
    out
}

#[test]
fn symmetric_rectangle_even_odd_mode() {
    let (levels, eps) = (4000, 1e-7);
    let even = seeded_difference(256, levels, eps);
    let odd = seeded_difference(255, levels, eps);
    println!("N = 256: {even:?}\nN = 255: {odd:?}");
    // N = 256: (A + Bj)(−1)^{i+j} solves the scheme linearised about any
    // solution (the four-point averages annihilate it), so the difference
    // grows linearly, |B|·j = 2ε·j = 8·10⁻⁴ at j = 4000.
    let linear = 2.0 * eps * levels as f64;
    assert!(even[3] >= 0.5 * linear, "even N: {:e}", even[3]);
    assert!(even[3] >= 1.5 * even[1], "even N grows linearly");
    // N = 255: no exact mode at θ = π; the nearest modes have distinct roots,
    // the perturbation stays O(ε·k/h) ≲ 20ε. Threshold: 20 times below the
    // linear growth.
    assert!(odd[3] <= 0.05 * linear, "odd N: {:e}", odd[3]);
}

/// The §5.2 initial data as the paper prints its numbers: with κ = 1 − 10⁻⁶
/// and L̃ = 10, `P = 2K(κ) ≈ 15.90` (checked against the arithmetic–geometric
/// mean, `K = π / (2 AGM(1, √(1 − κ²)))`, an independent path) and the kink
/// speed `c = √(1 − L̃²/(κ²P²)) ≈ 0.7773`; the profile solves the
/// travelling-wave ODE `(1 − c²) φ'' = sin φ` (finite differences, step 1e-3:
/// truncation ≈ δ²|φ⁗|/12 ≲ 1e-5) and keeps its first integral
/// `(1 − c²) φ'²/2 + cos φ` constant, with `φ(0) = 0`, `φ(L̃/2) = π`, `φ(L̃) = 2π`.
#[test]
fn kink_profile_has_the_papers_period_speed_and_ode() {
    let kink = veselov::spacetime::PeriodicKink::new(10.0, 1e-6).expect("kink");
    let kappa: f64 = 1.0 - 1e-6;
    // 1 − κ² = ε(2 − ε), without the cancellation of 1 − κ·κ.
    let (mut a, mut b) = (1.0_f64, (1e-6_f64 * (2.0 - 1e-6)).sqrt());
    for _ in 0..40 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    let p_agm = 2.0 * PI / (2.0 * a);
    assert!((kink.p() - p_agm).abs() < 1e-13 * p_agm, "{} vs {p_agm}", kink.p());
    // P = 15.894959…, which the paper prints as 15.90 (15.9 to three figures).
    assert!((kink.p() - 15.90).abs() < 0.01, "P = {}", kink.p());
    let c = kink.speed;
    assert!((c - 0.7773).abs() < 5e-5, "c = {c}");
    assert!((c - (1.0 - 100.0 / (kappa * kappa * p_agm * p_agm)).sqrt()).abs() < 1e-12);
    let phi = |x: f64| kink.profile(x).expect("profile");
    assert!(phi(0.0).abs() < 1e-9 && (phi(5.0) - PI).abs() < 1e-9 && (phi(10.0) - TAU).abs() < 1e-9);
    let d = 1e-3;
    let mut first_integral = Vec::new();
    for k in 0..=40 {
        let x = 1.0 + 0.2 * k as f64;
        let second = (phi(x + d) - 2.0 * phi(x) + phi(x - d)) / (d * d);
        let residual = (1.0 - c * c) * second - phi(x).sin();
        assert!(residual.abs() < 1e-5, "x = {x}: ODE residual {residual:e}");
        let slope = (phi(x + d) - phi(x - d)) / (2.0 * d);
        first_integral.push((1.0 - c * c) * slope * slope / 2.0 + phi(x).cos());
    }
    let (lo, hi) = first_integral
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
    assert!(hi - lo < 1e-5, "first integral varies by {:e}", hi - lo);
}
