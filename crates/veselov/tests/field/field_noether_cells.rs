//! Seed 002 §5.1's Noether and Cartan-form identities on its own cells, for
//! arbitrary fields (not only solutions), and the boundary-sum Noether law
//! (5.7) on arbitrary — not only periodic-slab — regions of a computed
//! solution:
//!
//! * J¹ + J² + J³ (+ J⁴) = 0 on every cell for the phase rotation of the
//!   complex Klein–Gordon field and the shift of the wave equation,
//!   J^l = ⟨∂L/∂y^l, ξ(y^l)⟩;
//! * Σ_l Θ^l(V) = Σ_l ⟨∂L/∂y^l, V^l⟩ = dL_Δ(V), against central differences
//!   of L_Δ;
//! * on a solution, the current J_ξ(A) through the frontier of a random
//!   domain A of cells vanishes to round-off (the core's Noether balance on
//!   the seed-002 complex), while a non-symmetry leaves a clear defect.

use crate::shared::Xorshift;
use nalgebra::{SVector, Vector2};
use veselov::complex::{SpacetimeLattice, TopCells};
use veselov::field::fibre::Euclidean;
use veselov::field::variational::noether_balance;
use veselov::spacetime::{
    CellLagrangian, CellShape, ComplexKleinGordon, ComplexPlaneWave, CoreCell, GenericMarcher, Lattice, NonlinearWave,
    RectangleRule, TriangleRule, Wave, cell_gradient,
};

const KG: ComplexKleinGordon = ComplexKleinGordon { m2: 1.0, lambda: 0.5 };
const H: f64 = 0.05;
const K: f64 = 0.2;

fn triangle<P>(p: P) -> TriangleRule<NonlinearWave<P>> {
    TriangleRule {
        density: NonlinearWave(p),
        dt: H,
        dx: K,
    }
}

fn rectangle<P>(p: P, symmetric: bool) -> RectangleRule<NonlinearWave<P>> {
    RectangleRule {
        density: NonlinearWave(p),
        dt: H,
        dx: K,
        symmetric,
    }
}

/// max over random cells of |Σ_l J^l| / Σ_l |J^l|.
fn cell_noether<L: CellLagrangian<DIM>, const DIM: usize>(
    lag: &L,
    xi: impl Fn(&SVector<f64, DIM>) -> SVector<f64, DIM>,
    rng: &mut Xorshift,
) -> f64 {
    let n = lag.shape().vertices();
    let mut worst: f64 = 0.0;
    for _ in 0..200 {
        let y: Vec<SVector<f64, DIM>> = (0..n).map(|_| rng.vector::<DIM>(1.0) * 2.0).collect();
        let g = cell_gradient(lag, &y);
        let terms: Vec<f64> = (0..n).map(|l| g[l].dot(&xi(&y[l]))).collect();
        let sum: f64 = terms.iter().sum();
        let size: f64 = terms.iter().map(|t| t.abs()).sum();
        worst = worst.max(sum.abs() / size);
    }
    worst
}

#[test]
fn cell_currents_sum_to_zero_for_arbitrary_fields() {
    let mut rng = Xorshift(0x5eed_0002);
    let rotation = |y: &Vector2<f64>| Vector2::new(-y[1], y[0]);
    let shift = |_: &SVector<f64, 1>| SVector::<f64, 1>::new(1.0);
    let cases = [
        ("KG triangle, phase", cell_noether(&triangle(KG), rotation, &mut rng)),
        (
            "KG rectangle, phase",
            cell_noether(&rectangle(KG, false), rotation, &mut rng),
        ),
        (
            "KG symmetric rectangle, phase",
            cell_noether(&rectangle(KG, true), rotation, &mut rng),
        ),
        ("wave triangle, shift", cell_noether(&triangle(Wave), shift, &mut rng)),
        (
            "wave symmetric rectangle, shift",
            cell_noether(&rectangle(Wave, true), shift, &mut rng),
        ),
    ];
    for (name, worst) in cases {
        println!("{name}: max |ΣJ^l| / Σ|J^l| = {worst:e}");
        assert!(worst < 1e-13, "{name}: {worst:e}");
    }
    // The test can fail: a shift is not a symmetry of the massive field.
    let broken = cell_noether(&triangle(KG), |_| Vector2::new(1.0, 0.0), &mut rng);
    assert!(broken > 1e-3, "a shift of the massive field: {broken:e}");
}

#[test]
fn cartan_forms_sum_to_the_differential_of_the_cell_lagrangian() {
    let mut rng = Xorshift(0x5eed_0003);
    fn check<L: CellLagrangian<2>>(name: &str, lag: &L, rng: &mut Xorshift) {
        let n = lag.shape().vertices();
        let mut worst: f64 = 0.0;
        for _ in 0..100 {
            let y: Vec<Vector2<f64>> = (0..n).map(|_| rng.vector::<2>(1.0)).collect();
            let v: Vec<Vector2<f64>> = (0..n).map(|_| rng.vector::<2>(1.0)).collect();
            let g = cell_gradient(lag, &y);
            let theta: f64 = (0..n).map(|l| g[l].dot(&v[l])).sum();
            // Fourth-order central differences of ε ↦ L(y + εV), ε = 10⁻³:
            // truncation ε⁴|L⁽⁵⁾|/30 ≈ 10⁻¹³·|L⁽⁵⁾|, round-off ≈ 10⁻¹⁶|L|/ε.
            let e = 1e-3;
            let at = |s: f64| {
                let z: Vec<Vector2<f64>> = y.iter().zip(&v).map(|(a, b)| a + b * s).collect();
                lag.lagrangian(&z)
            };
            let fd = (at(-2.0 * e) - 8.0 * at(-e) + 8.0 * at(e) - at(2.0 * e)) / (12.0 * e);
            worst = worst.max((theta - fd).abs() / (1.0 + theta.abs()));
        }
        println!("{name}: max |ΣΘ^l(V) − dL(V)| = {worst:e}");
        assert!(worst < 1e-8, "{name}: {worst:e}");
    }
    check("triangle", &triangle(KG), &mut rng);
    check("rectangle", &rectangle(KG, false), &mut rng);
    check("symmetric rectangle", &rectangle(KG, true), &mut rng);
}

/// March the complex Klein–Gordon plane wave (plus a random perturbation)
/// for `levels` levels and return the lattice of all levels with the field.
fn solution<L: CellLagrangian<2> + Clone>(lag: L, lattice: Lattice, levels: usize) -> Vec<Vector2<f64>> {
    let wave = ComplexPlaneWave {
        amplitude: 0.6,
        mode: 1,
        m2: KG.m2,
        lambda: KG.lambda,
    };
    let (mut y0, y1) = wave.levels(&lattice).expect("plane wave");
    let mut rng = Xorshift(0x5eed_0004);
    for y in &mut y0 {
        *y += rng.vector::<2>(1.0) * 0.05;
    }
    let mut m = GenericMarcher::new(lag, lattice, y0.clone(), y1.clone()).expect("marcher");
    m.rel_tol = 1e-15;
    let mut all = y0;
    all.extend_from_slice(&y1);
    for _ in 2..levels {
        m.step().expect("step");
        all.extend_from_slice(m.current());
    }
    all
}

#[test]
fn noether_currents_vanish_on_arbitrary_regions_of_a_solution() {
    let lattice = Lattice::new(24, K, H, veselov::spacetime::Boundary::Periodic).expect("lattice");
    let levels = 12;
    let mut rng = Xorshift(0x5eed_0005);
    for (name, shape, symmetric) in [
        ("triangles", CellShape::Triangle, false),
        ("rectangles", CellShape::Rectangle, false),
        ("symmetric rectangles", CellShape::Rectangle, true),
    ] {
        let complex = SpacetimeLattice::seed002(shape, &lattice, levels).expect("complex");
        let y = match shape {
            CellShape::Triangle => solution(triangle(KG), lattice, levels),
            CellShape::Rectangle => solution(rectangle(KG, symmetric), lattice, levels),
        };
        // A random, ragged domain of cells (holes and islands included),
        // away from the first and last levels, whose vertices are data of
        // the march, not solutions of their Euler–Lagrange equations.
        let per_level = lattice.nodes();
        let domain: Vec<bool> = (0..complex.cell_count())
            .map(|c| (1..levels - 2).contains(&(c / per_level)) && rng.uniform() > -0.2)
            .collect();
        let (current, defect, broken) = match shape {
            CellShape::Triangle => measure(&complex, &CoreCell(&triangle(KG)), &y, &domain),
            CellShape::Rectangle => measure(&complex, &CoreCell(&rectangle(KG, symmetric)), &y, &domain),
        };
        println!("{name}: |J(A)|/scale = {current:e}, identity defect {defect:e}, shift current {broken:e}");
        assert!(
            current < 1e-12,
            "{name}: the current through the frontier is {current:e}"
        );
        assert!(defect < 1e-13, "{name}: Noether identity defect {defect:e}");
        assert!(
            broken > 1e-4,
            "{name}: a non-symmetry must leave a current ({broken:e})"
        );
    }
}

/// (|J_rot(A)|/scale, Noether identity defect, |J_shift(A) + interior|/scale).
fn measure<L: veselov::field::cell::DiscreteLagrangian<Euclidean<2>, 2>>(
    complex: &SpacetimeLattice,
    lag: &L,
    y: &[Vector2<f64>],
    domain: &[bool],
) -> (f64, f64, f64) {
    let rot = noether_balance::<Euclidean<2>, _, _, 2>(complex, lag, y, domain, |p| Vector2::new(-p[1], p[0]))
        .expect("balance");
    let shift =
        noether_balance::<Euclidean<2>, _, _, 2>(complex, lag, y, domain, |_| Vector2::new(1.0, 0.0)).expect("balance");
    (
        rot.current.abs() / rot.scale,
        rot.relative_defect(),
        shift.relative_defect(),
    )
}
