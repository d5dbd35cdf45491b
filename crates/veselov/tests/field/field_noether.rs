//! Discrete Noether theorem (5.7) with the space–time split: the shift
//! charge of the wave equation and the phase charge of the complex
//! Klein–Gordon field are conserved over 10⁴ levels.

use nalgebra::{SVector, Vector2};
use veselov::spacetime::{
    Boundary, ComplexKleinGordon, FastMarcher, GenericMarcher, InitialData, Lattice, NonlinearWave, Scheme,
    SolverOptions, TriangleRule, Wave, shift_charge, split_charge,
};

/// A rotating, modulated complex field on `n` nodes:
/// y = r(x)(cos θ, sin θ), r = 1 + 0.3 cos(wx), θ = 0.8t + 0.5 sin(wx).
fn rotating_field(n: usize, t: f64) -> Vec<SVector<f64, 2>> {
    let w = std::f64::consts::TAU / n as f64;
    (0..n)
        .map(|i| {
            let x = i as f64;
            let r = 1.0 + 0.3 * (w * x).cos();
            let th = 0.8 * t + 0.5 * (w * x).sin();
            Vector2::new(r * th.cos(), r * th.sin())
        })
        .collect()
}

#[test]
fn wave_shift_charge_is_conserved() {
    let lat = Lattice::periodic(64, 10.0, 1.25).expect("valid"); // h/k = 0.8
    let data = InitialData::DAlembert {
        amplitude: 1.0,
        mode: 2,
        drift: 0.02, // keeps |y| = O(1): rounding scales with max|y|
    };
    let (y0, y1) = data.levels(&lat).expect("data");
    let mut m = FastMarcher::new(Wave, Scheme::Triangle, lat, &y0, &y1, SolverOptions::default()).expect("valid");
    let q0 = shift_charge(&y0, &y1);
    let mut worst: f64 = 0.0;
    for _ in 0..10_000 {
        m.step().expect("step");
        let (a, b) = (m.previous(), m.current());
        let scale: f64 = a.iter().zip(b).map(|(x, y)| (y - x).abs()).sum();
        worst = worst.max((shift_charge(a, b) - q0).abs() / scale.max(q0.abs()));
    }
    println!("shift charge: worst relative drift {worst:e}");
    // Leapfrog conserves Σ_i δ_i exactly up to rounding: ≈ √N·ε·max|y| per
    // level, a random walk over 10⁴ levels: ≈ 3·10⁻¹³ absolute, ≈ 10⁻¹³
    // relative to Σ|δ_i| ≈ 4 (observed ≈ 6·10⁻¹³).
    assert!(worst <= 1e-12, "{worst:e}");
}

#[test]
fn complex_klein_gordon_phase_charge_is_conserved() {
    let (n, h, k) = (16, 0.05, 0.2);
    let lat = Lattice::new(n, k, h, Boundary::Periodic).expect("valid");
    let model = ComplexKleinGordon { m2: 1.0, lambda: 0.5 };
    let lag = TriangleRule {
        density: NonlinearWave(model),
        dt: h,
        dx: k,
    };
    let field = |t: f64| rotating_field(n, t);
    let (y0, y1) = (field(0.0), field(h));
    let jrot = |y: &SVector<f64, 2>| Vector2::new(-y[1], y[0]);
    let q0 = split_charge(&lag, &lat, &y0, &y1, jrot);
    // Note F4 form: Q = Σ ⟨−(y_{i,j+1} − y_ij)/h² + ⅓∇N(ȳ), J y_ij⟩, with
    // ∇N(y) = −(m² + λ|y|²) y.
    let f4 = |a: &[SVector<f64, 2>], b: &[SVector<f64, 2>]| -> f64 {
        (0..n)
            .map(|i| {
                let c = (a[i] + b[i] + b[(i + 1) % n]) / 3.0;
                let grad_n = -c * (model.m2 + model.lambda * c.norm_squared());
                (-(b[i] - a[i]) / (h * h) + grad_n / 3.0).dot(&jrot(&a[i]))
            })
            .sum()
    };
    assert!(
        (q0 - f4(&y0, &y1)).abs() <= 1e-12 * q0.abs(),
        "generic split charge = F4 formula"
    );
    let naive = |a: &[SVector<f64, 2>], b: &[SVector<f64, 2>]| -> f64 {
        (0..n).map(|i| ((b[i] - a[i]) / h).dot(&jrot(&a[i]))).sum()
    };
    let naive0 = naive(&y0, &y1);
    let mut m = GenericMarcher::new(lag, lat, y0, y1).expect("valid");
    let (mut worst, mut naive_dev): (f64, f64) = (0.0, 0.0);
    for _ in 0..10_000 {
        m.step().expect("step");
        let q = split_charge(m.lagrangian(), &lat, m.previous(), m.current(), jrot);
        worst = worst.max((q - q0).abs() / q0.abs());
        naive_dev = naive_dev.max((naive(m.previous(), m.current()) - naive0).abs() / naive0.abs());
    }
    println!("phase charge: worst relative drift {worst:e}; naive ∫⟨φ_t, Jφ⟩ varies by {naive_dev:e}");
    // Newton converges quadratically, so each level is exact to round-off;
    // the charge's rounding (terms ~ |y|²/h, N = 16) accumulates as a random
    // walk to ≈ 10⁻¹⁴·√(10⁴) relative.
    assert!(worst <= 1e-12, "{worst:e}");
    assert!(naive_dev > 1e-6, "the naive charge is not conserved: {naive_dev:e}");
}

#[test]
fn complex_klein_gordon_phase_charge_with_rectangles() {
    // Rectangles: the split charge is Σ_i (J¹ + J⁴)(R(i,j)) (both vertices on
    // level j), computed generically from ∂L/∂y^l.
    let (n, h, k) = (12, 0.05, 0.2);
    let lat = Lattice::new(n, k, h, Boundary::Periodic).expect("valid");
    let model = ComplexKleinGordon { m2: 1.0, lambda: 0.5 };
    let field = |t: f64| rotating_field(n, t);
    let jrot = |y: &SVector<f64, 2>| Vector2::new(-y[1], y[0]);
    for symmetric in [false, true] {
        let lag = veselov::spacetime::RectangleRule {
            density: NonlinearWave(model),
            dt: h,
            dx: k,
            symmetric,
        };
        let (y0, y1) = (field(0.0), field(h));
        let q0 = split_charge(&lag, &lat, &y0, &y1, jrot);
        let mut m = GenericMarcher::new(lag, lat, y0, y1).expect("valid");
        let mut worst: f64 = 0.0;
        for _ in 0..2000 {
            m.step().expect("step");
            let q = split_charge(m.lagrangian(), &lat, m.previous(), m.current(), jrot);
            worst = worst.max((q - q0).abs() / q0.abs());
        }
        println!("rectangles (symmetric = {symmetric}): phase charge drift {worst:e}");
        // Same round-off argument as for triangles.
        assert!(worst <= 1e-12, "{worst:e}");
    }
}
