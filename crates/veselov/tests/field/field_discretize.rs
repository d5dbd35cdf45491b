//! Discretising smooth densities (seed 003 §5): quadrature exactness (T15),
//! Lemma 5.15 on affine data (T17), Prop. 5.20 (T18), seed 002's rules (5.8),
//! (5.12) as instances, the shift symmetry of the wave density (T19),
//! suitability (Cor. 6.3, T30), the orders of the vertex rules (T20) and a
//! rotation fibre on a 2+1 space–time lattice.

use crate::field_discretize_rod::rod_parameters;
use crate::shared::{SplitMix, cell, nodes_of, nudged, rel, rel_vec};
use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};
use veselov::ad::Scalar;
use veselov::complex::TopCell;
use veselov::field::cell::{DiscreteLagrangian, vertex_gradient};
use veselov::field::discretize::{
    CellCheck, CellError, CfkNodes, CubeCentreRule, CubeNodes, MidpointRule, NodeMap, SmoothDensity, VertexRule,
    affine_jet, cube_corner, factorial, vertex_jet,
};
use veselov::field::fibre::{Euclidean, Pose};
use veselov::lie::{SO3, so3};
use veselov::models::rod::{CosseratCell, CosseratDensity};
use veselov::spacetime::SpaceTime;
use veselov::spacetime::{CellLagrangian, NonlinearWave, RectangleRule, SineGordon, TriangleRule, Wave};

/// A random well-conditioned matrix: identity plus a perturbation.
fn random_map<const N: usize>(rng: &mut SplitMix) -> SMatrix<f64, N, N> {
    SMatrix::<f64, N, N>::identity() + rng.mat::<N, N>(0.3)
}

// ---------------------------------------------------------------- densities

/// 𝓛 = c.
struct Constant(f64);
impl<const M: usize, const N: usize> SmoothDensity<Euclidean<M>, M, N> for Constant {
    fn density<D: Scalar>(&self, _x: &SVector<f64, N>, _y: &SVector<D, M>, _j: &SMatrix<D, M, N>) -> D {
        D::from(self.0)
    }
}

/// 𝓛 = α + βᵀx + γᵀy: affine along the simplex for affine data.
struct Affine<const M: usize, const N: usize> {
    alpha: f64,
    beta: SVector<f64, N>,
    gamma: SVector<f64, M>,
}
impl<const M: usize, const N: usize> SmoothDensity<Euclidean<M>, M, N> for Affine<M, N> {
    fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>, _j: &SMatrix<D, M, N>) -> D {
        y.dot(&self.gamma.map(D::from)) + self.alpha + self.beta.dot(x)
    }
}

/// Simplex volume |det X_β|/n! with X_β = [1, xᵀ] rows (Prop. 5.20).
fn x_beta<const N: usize>(x: &[SVector<f64, N>]) -> DMatrix<f64> {
    DMatrix::from_fn(N + 1, N + 1, |i, j| if j == 0 { 1.0 } else { x[i][j - 1] })
}

// ---------------------------------------------------------------- T15

#[test]
fn t15_quadratures_are_exact_for_constants_and_affine_integrands() {
    let mut rng = SplitMix(15);
    const N: usize = 3;
    // ∫_Δ dλ = 1/n!: constant density 1 on the unit CFK simplices of ℤ³.
    let unit = CfkNodes::<N>::new(SMatrix::identity()).expect("identity map");
    for shape in 0..factorial(N) {
        let c = cell(shape, shape, &[1, -2, 3]);
        let y = [SVector::<f64, 1>::zeros(); 4];
        let q0 = VertexRule::at_vertex(Constant(1.0), unit, 0)
            .expect("u ≤ N")
            .cell_lagrangian(&c, &y);
        assert!((q0 - 1.0 / 6.0).abs() < 1e-15, "∫ dλ = {q0}");
    }
    let mut worst = [0.0_f64; 3];
    let mut q_v_misses = 0.0_f64;
    for trial in 0..50 {
        let map = CfkNodes::<N>::with_offset(random_map(&mut rng), rng.vec(2.0)).expect("random map");
        let c = cell(
            trial,
            trial % factorial(N),
            &[rng.sym(5.0) as i64, rng.sym(5.0) as i64, 2],
        );
        let x = nodes_of(&map, &c, N + 1);
        let vol = x_beta(&x).determinant().abs() / 6.0;
        // Affine data y(x) = y₀ + G x and an affine integrand.
        let (y0, g) = (rng.vec::<2>(1.0), rng.mat::<2, N>(1.0));
        let y: Vec<SVector<f64, 2>> = x.iter().map(|xi| y0 + g * xi).collect();
        let dens = Affine::<2, N> {
            alpha: rng.sym(1.0),
            beta: rng.vec(1.0),
            gamma: rng.vec(1.0),
        };
        let xbar = x.iter().sum::<SVector<f64, N>>() / 4.0;
        let exact = vol * (dens.alpha + dens.beta.dot(&xbar) + dens.gamma.dot(&(y0 + g * xbar)));
        let k = rng.sym(3.0);
        for u in 0..=N {
            let qu = VertexRule::at_vertex(Constant(k), map, u)
                .expect("u ≤ N")
                .cell_lagrangian(&c, &y);
            worst[0] = worst[0].max(rel(qu, k * vol));
            let qa = VertexRule::at_vertex(&dens, map, u)
                .expect("u ≤ N")
                .cell_lagrangian(&c, &y);
            q_v_misses = q_v_misses.max(rel(qa, exact));
        }
        let qs = VertexRule::symmetric(&dens, map).cell_lagrangian(&c, &y);
        let qm = MidpointRule::new(&dens, map).cell_lagrangian(&c, &y);
        worst[1] = worst[1].max(rel(qs, exact));
        worst[2] = worst[2].max(rel(qm, exact));
    }
    println!(
        "T15 max rel: Q_v(const) {:.1e}, Q_sym(affine) {:.1e}, Q_mid(affine) {:.1e}",
        worst[0], worst[1], worst[2]
    );
    assert!(worst.iter().all(|&w| w < 1e-13), "{worst:?}");
    assert!(
        q_v_misses > 1e-3,
        "Q_v is not exact for affine integrands ({q_v_misses})"
    );
}

// ---------------------------------------------------------------- T17, T18

#[test]
fn t17_vertex_jets_of_affine_data_are_the_affine_gradient() {
    let mut rng = SplitMix(17);
    const N: usize = 3;
    let mut worst = (0.0_f64, 0.0_f64);
    for trial in 0..50 {
        let map = CfkNodes::<N>::with_offset(random_map(&mut rng), rng.vec(2.0)).expect("random map");
        let c = cell(trial, trial % 6, &[3, 1, -4]);
        let x = nodes_of(&map, &c, N + 1);
        let vol = x_beta(&x).determinant().abs() / factorial(N) as f64;
        let (y0, g) = (rng.vec::<2>(1.0), rng.mat::<2, N>(1.0));
        let y: Vec<SVector<f64, 2>> = x.iter().map(|xi| y0 + g * xi).collect();
        for u in 0..=N {
            let (jet, jac) = vertex_jet::<Euclidean<2>, f64, 2, N>(c.index, &x, &y, u).expect("suitable cell");
            worst.0 = worst.0.max((jet - g).norm() / g.norm());
            worst.1 = worst.1.max(rel(jac / factorial(N) as f64, vol));
        }
    }
    println!("T17 max rel: jet {:.1e}, Jac/n! vs volume {:.1e}", worst.0, worst.1);
    assert!(worst.0 < 1e-13 && worst.1 < 1e-13, "{worst:?}");
}

/// A node map returning fixed nodes (possibly degenerate) for every cell.
struct Fixed<const N: usize>(Vec<SVector<f64, N>>);
impl<const N: usize> NodeMap<N> for Fixed<N> {
    fn cell_nodes(&self, _c: &TopCell, out: &mut [SVector<f64, N>]) -> usize {
        out[..self.0.len()].copy_from_slice(&self.0);
        self.0.len()
    }
}

#[test]
fn t18_affine_bundle_identities_of_prop_5_20() {
    let mut rng = SplitMix(18);
    const N: usize = 2;
    let mut worst = 0.0_f64;
    for trial in 0..50 {
        let x: Vec<SVector<f64, N>> = (0..=N).map(|_| rng.vec(2.0)).collect();
        let y: Vec<SVector<f64, 3>> = (0..=N).map(|_| rng.vec(2.0)).collect();
        let a = affine_jet(trial, &x, &y).expect("generic nodes are suitable");
        // (5.6): [y; ∂₁y; …] = [[1, x̄ᵀ], [0, I]] X_β⁻¹ [y_i].
        let xb = x_beta(&x);
        let inv = xb.clone().try_inverse().expect("nonsingular X_β");
        let mut shift = DMatrix::<f64>::identity(N + 1, N + 1);
        for j in 0..N {
            shift[(0, j + 1)] = a.centre[j];
        }
        for k in 0..3 {
            let yk = DVector::from_fn(N + 1, |i, _| y[i][k]);
            let coeffs = &inv * &yk;
            let jet = &shift * &coeffs;
            worst = worst.max((jet[0] - a.value[k]).abs() / (1.0 + a.value[k].abs()));
            for j in 0..N {
                worst = worst.max((jet[j + 1] - a.gradient[(k, j)]).abs() / (1.0 + a.gradient[(k, j)].abs()));
            }
            // The fit interpolates: y^k(x_i) = [1 x_iᵀ] X_β⁻¹ y^k.
            let fit = &xb * &coeffs;
            worst = worst.max((&fit - &yk).amax() / (1.0 + yk.amax()));
        }
        // Jac = |det X_β| (c = 1), vol_β = |det X_β|/n!.
        worst = worst.max(rel(a.volume, xb.determinant().abs() / 2.0));
    }
    println!("T18 max rel deviation from (5.6): {worst:.1e}");
    assert!(worst < 1e-13, "{worst}");
    // Suitable iff det X_β ≠ 0: collinear nodes are rejected, naming the cell.
    let degenerate = Fixed(vec![
        Vector2::new(0.0, 0.0),
        Vector2::new(1.0, 1.0),
        Vector2::new(2.0, 2.0),
    ]);
    let rule = MidpointRule::new(SpaceTime(NonlinearWave(Wave)), degenerate);
    let y = [SVector::<f64, 1>::zeros(); 3];
    let c = cell(42, 0, &[]);
    match rule.check_cell(&c, &y) {
        Err(CellError::SingularNodes { cell: 42, .. }) => {}
        other => panic!("expected a singular-node error for cell 42, got {other:?}"),
    }
    assert!(rule.cell_lagrangian(&c, &y).is_nan());
}

// ---------------------------------------------------------------- seed 002 instances

#[test]
fn seed_002_triangle_and_symmetric_rectangle_rules_are_instances() {
    let mut rng = SplitMix(2);
    let sg = NonlinearWave(SineGordon);
    let (mut tri, mut rect) = (0.0_f64, 0.0_f64);
    let mut rect_5_9 = f64::INFINITY;
    for trial in 0..100 {
        let (h, k) = (0.05 + rng.uniform(), 0.05 + rng.uniform());
        let (i, j) = ((rng.sym(20.0)) as i64, (rng.sym(20.0)) as i64);
        let y: Vec<SVector<f64, 1>> = (0..4).map(|_| rng.vec(3.0)).collect();
        // (5.8) on ((i,j), (i,j+1), (i+1,j+1)) = CFK simplex (v, σ = (1, 0)) under x = diag(k, h) v.
        let tr = TriangleRule {
            density: sg,
            dt: h,
            dx: k,
        };
        let old = tr.lagrangian(&y[..3]);
        // Relative to the size of the terms (the Lagrangian is a difference).
        let (_, pt, px) = tr.jet(&y[..3]);
        let size = 0.5 * (pt[0] * pt[0] + px[0] * px[0]) + 1.0;
        let nodes = CfkNodes::new(Matrix2::new(k, 0.0, 0.0, h)).expect("grid map");
        let new = MidpointRule::new(SpaceTime(sg), nodes).cell_lagrangian(&cell(trial, 1, &[i, j]), &y[..3]);
        tri = tri.max((old * h * k / 2.0 - new).abs() / (size * h * k / 2.0));
        // (5.12) on ((i,j), (i,j+1), (i+1,j+1), (i+1,j)); binary order (i,j), (i+1,j), (i,j+1), (i+1,j+1).
        let rr = RectangleRule {
            density: sg,
            dt: h,
            dx: k,
            symmetric: true,
        };
        let sym = rr.lagrangian(&y);
        let (_, pt, px) = rr.jet(&y);
        let size = 0.5 * (pt[0] * pt[0] + px[0] * px[0]) + 1.0;
        let binary = [y[0], y[3], y[1], y[2]];
        let grid = CubeNodes::grid(Vector2::new(k, h)).expect("grid");
        let centre = CubeCentreRule::new(SpaceTime(sg), grid).cell_lagrangian(&cell(trial, 0, &[i, j]), &binary);
        rect = rect.max((sym * h * k - centre).abs() / (size * h * k));
        let plain = RectangleRule {
            density: sg,
            dt: h,
            dx: k,
            symmetric: false,
        }
        .lagrangian(&y);
        rect_5_9 = rect_5_9.min((plain * h * k - centre).abs() / (size * h * k));
    }
    println!("(5.8) vs Q_mid {tri:.1e}; (5.12) vs cube centre {rect:.1e}; (5.9) vs cube centre ≥ {rect_5_9:.1e}");
    assert!(tri < 1e-13 && rect < 1e-13, "{tri} {rect}");
    assert!(rect_5_9 > 1e-8, "(5.9) is not the centre rule");
    // Binary cube order as documented.
    assert_eq!(cube_corner(2, 2)[..2], [0, 1]);
}

// ---------------------------------------------------------------- T19

#[test]
fn t19_shift_symmetry_of_the_wave_density() {
    let mut rng = SplitMix(190);
    let map = CfkNodes::leapfrog(0.4, 0.1).expect("spacings");
    let grid = CubeNodes::grid(Vector2::new(0.4, 0.1)).expect("grid");
    let wave = SpaceTime(NonlinearWave(Wave));
    let sg = SpaceTime(NonlinearWave(SineGordon));
    let (mut wave_worst, mut sg_worst, mut sg_breaks) = (0.0_f64, 0.0_f64, f64::INFINITY);
    for trial in 0..200 {
        let c = cell(trial, trial % 2, &[rng.sym(10.0) as i64, rng.sym(10.0) as i64]);
        let y: Vec<SVector<f64, 1>> = (0..4).map(|_| rng.vec(2.0)).collect();
        let shift = rng.sym(10.0);
        let tau = std::f64::consts::TAU;
        let moved = |d: f64| y.iter().map(|v| v.add_scalar(d)).collect::<Vec<_>>();
        let eval = |dens: &SpaceTime<NonlinearWave<Wave>>, y: &[SVector<f64, 1>]| {
            [
                VertexRule::at_vertex(dens, map, 1)
                    .expect("u ≤ 2")
                    .cell_lagrangian(&c, &y[..3]),
                VertexRule::symmetric(dens, map).cell_lagrangian(&c, &y[..3]),
                MidpointRule::new(dens, map).cell_lagrangian(&c, &y[..3]),
                CubeCentreRule::new(dens, grid).cell_lagrangian(&c, y),
            ]
        };
        let (a, b) = (eval(&wave, &y), eval(&wave, &moved(shift)));
        for r in 0..4 {
            wave_worst = wave_worst.max(rel(a[r], b[r]));
        }
        let sg_eval = |y: &[SVector<f64, 1>]| {
            [
                VertexRule::symmetric(&sg, map).cell_lagrangian(&c, &y[..3]),
                MidpointRule::new(&sg, map).cell_lagrangian(&c, &y[..3]),
            ]
        };
        let (a, b, d) = (sg_eval(&y), sg_eval(&moved(tau)), sg_eval(&moved(shift.abs() + 0.5)));
        for r in 0..2 {
            sg_worst = sg_worst.max((a[r] - b[r]).abs() / (a[r].abs() + 1.0));
            sg_breaks = sg_breaks.min((a[r] - d[r]).abs());
        }
    }
    println!("T19 wave: max rel change under y + c {wave_worst:.1e}; sine-Gordon under y + 2π {sg_worst:.1e}");
    assert!(wave_worst < 1e-13 && sg_worst < 1e-13, "{wave_worst} {sg_worst}");
    assert!(sg_breaks > 0.0, "a generic shift is no symmetry of sine-Gordon");
}

// ---------------------------------------------------------------- suitability (T30)

#[test]
fn unsuitable_cells_are_named_errors_and_never_panic() {
    let mut rng = SplitMix(30);
    let p = rod_parameters(&mut rng);
    let density = CosseratDensity::free(p);
    let rod = CosseratCell::new(density, 0.5, 0.1).expect("spacings");
    let generic = VertexRule::symmetric(density, CfkNodes::leapfrog(0.5, 0.1).expect("spacings"));
    let c = cell(7, 0, &[2, 3]);
    let at = |w: Vector3<f64>| Pose::new(Vector3::zeros(), so3::exp(&w));
    // Good: all rotations close.
    let good = [
        at(Vector3::zeros()),
        at(Vector3::new(0.3, 0.0, 0.0)),
        at(Vector3::new(0.0, 0.4, 0.0)),
    ];
    rod.check_cell(&c, &good).expect("suitable");
    generic.check_cell(&c, &good).expect("suitable");
    // Cor. 6.3 fails: every pairwise angle above π/2, all logarithms defined.
    let far = [
        at(Vector3::zeros()),
        at(Vector3::new(2.0, 0.0, 0.0)),
        at(Vector3::new(-2.0, 0.0, 0.0)),
    ];
    for result in [rod.check_cell(&c, &far), generic.check_cell(&c, &far)] {
        match result {
            Err(e @ CellError::Unsuitable { cell: 7, .. }) => assert!(e.to_string().contains("cell 7"), "{e}"),
            other => panic!("expected Cor. 6.3 to reject cell 7, got {other:?}"),
        }
    }
    // Cut locus: a logarithm fails; the Lagrangian is NaN, the check names the pair.
    let cut = [
        at(Vector3::zeros()),
        at(Vector3::new(std::f64::consts::PI, 0.0, 0.0)),
        good[2],
    ];
    assert!(rod.cell_lagrangian(&c, &cut).is_nan() && generic.cell_lagrangian(&c, &cut).is_nan());
    match rod.check_cell(&c, &cut) {
        Err(CellError::Logarithm {
            cell: 7,
            from: 0,
            to: 1,
            ..
        }) => {}
        other => panic!("expected a logarithm failure, got {other:?}"),
    }
    // An unknown shape and a non-finite value.
    let bad_shape = cell(8, 2, &[0, 0]);
    assert!(matches!(
        rod.check_cell(&bad_shape, &good),
        Err(CellError::Nodes { cell: 8, .. })
    ));
    assert!(matches!(
        generic.check_cell(&bad_shape, &good),
        Err(CellError::Nodes { cell: 8, .. })
    ));
    let mut nan = good;
    nan[2].position[1] = f64::NAN;
    assert!(matches!(
        generic.check_cell(&c, &nan),
        Err(CellError::NonFinite { cell: 7, .. })
    ));
    // The crate error keeps the cell's name.
    let e: veselov::error::Error = CellError::Unsuitable {
        cell: 9,
        reason: "x".into(),
    }
    .into();
    assert!(e.to_string().contains("cell 9"), "{e}");
}

// ---------------------------------------------------------------- T20

/// 5-point Gauss–Legendre nodes and weights on [0, 1].
const GAUSS: [(f64, f64); 5] = [
    (0.046_910_077_030_668, 0.118_463_442_528_095),
    (0.230_765_344_947_158, 0.239_314_335_249_683),
    (0.5, 0.284_444_444_444_444),
    (0.769_234_655_052_842, 0.239_314_335_249_683),
    (0.953_089_922_969_332, 0.118_463_442_528_095),
];

#[test]
fn t20_vertex_rules_are_consistent_with_orders_one_and_two() {
    // Sine-Gordon on the leapfrog lattice, Δt = Δs/2, fixed domain A·[0, n]²:
    // Σ_β L_β − ∫ 𝓛 is O(h) for Q_{v₀} and O(h²) for Q_sym (an observation, note 003 T20).
    let field = |x: &Vector2<f64>| (x[0] + 0.5 * x[1]).sin() + 0.3 * (2.0 * x[1] - x[0]).cos();
    let grad = |x: &Vector2<f64>| {
        let (a, b) = ((x[0] + 0.5 * x[1]).cos(), 0.3 * (2.0 * x[1] - x[0]).sin());
        Vector2::new(a + b, 0.5 * a - 2.0 * b)
    };
    let sg = NonlinearWave(SineGordon);
    let smooth = |x: &Vector2<f64>| {
        let (f, g) = (field(x), grad(x));
        0.5 * (g[1] * g[1] - g[0] * g[0]) + f.cos()
    };
    let mut errors = Vec::new();
    for n in [8_i64, 16, 32, 64, 128] {
        let ds = 2.0 / n as f64;
        let map = CfkNodes::leapfrog(ds, ds / 2.0).expect("spacings");
        let a = *map.matrix();
        let (v0, vs) = (
            VertexRule::at_vertex(SpaceTime(sg), map, 0).expect("u = 0"),
            VertexRule::symmetric(SpaceTime(sg), map),
        );
        let (mut exact, mut sum0, mut sums) = (0.0, 0.0, 0.0);
        for i in 0..n {
            for j in 0..n {
                for (p, wp) in GAUSS {
                    for (q, wq) in GAUSS {
                        exact += wp * wq * smooth(&(a * Vector2::new(i as f64 + p, j as f64 + q)));
                    }
                }
                for shape in 0..2 {
                    let c = cell(0, shape, &[i, j]);
                    let x = nodes_of(&map, &c, 3);
                    let y: Vec<SVector<f64, 1>> = x.iter().map(|xi| SVector::from([field(xi)])).collect();
                    sum0 += v0.cell_lagrangian(&c, &y);
                    sums += vs.cell_lagrangian(&c, &y);
                }
            }
        }
        exact *= a.determinant().abs();
        errors.push(((sum0 - exact).abs(), (sums - exact).abs()));
    }
    let rates: Vec<(f64, f64)> = errors
        .windows(2)
        .map(|w| ((w[0].0 / w[1].0).log2(), (w[0].1 / w[1].1).log2()))
        .collect();
    for (e, n) in errors.iter().zip([8, 16, 32, 64, 128]) {
        println!("T20 n = {n}: |Σ L − ∫ 𝓛| Q_v0 {:.2e}, Q_sym {:.2e}", e.0, e.1);
    }
    println!("T20 observed orders (Q_v0, Q_sym): {rates:.2?}");
    let last = rates[rates.len() - 1];
    // Q_v0 approaches order 1 from above (a second-order part still shows).
    assert!(last.0 > 0.9 && last.0 < 1.2, "Q_v0 order {}", last.0);
    assert!(last.1 > 1.8, "Q_sym order {}", last.1);
}

// ---------------------------------------------------------------- SO(3) fibre, N = 3

/// A rigid-body sigma model on 2+1 space–time: 𝓛 = ½(ωᵀJω − |Ω₀|² − |Ω₁|²)
/// with ω the time column of the jet (body angular velocity).
struct SigmaModel(Matrix3<f64>);
impl SmoothDensity<veselov::field::fibre::Rotations, 3, 3> for SigmaModel {
    fn density<D: Scalar>(&self, _x: &SVector<f64, 3>, _y: &SO3<D>, j: &SMatrix<D, 3, 3>) -> D {
        let w: Vector3<D> = j.column(2).into_owned();
        let (a, b): (Vector3<D>, Vector3<D>) = (j.column(0).into_owned(), j.column(1).into_owned());
        (w.dot(&(self.0.map(D::from) * w)) - a.dot(&a) - b.dot(&b)) * 0.5
    }
}

#[test]
fn rotation_fibre_on_a_three_dimensional_space_time_lattice() {
    use veselov::field::fibre::Rotations;
    let mut rng = SplitMix(3);
    let map = CfkNodes::<3>::space_time(0.3, 0.1).expect("spacings");
    let dens = SigmaModel(Matrix3::from_diagonal(&Vector3::new(1.0, 2.0, 0.5)));
    let (mut invariance, mut fd_worst) = (0.0_f64, 0.0_f64);
    for trial in 0..100 {
        let c = cell(
            trial,
            trial % 6,
            &[rng.sym(5.0) as i64, rng.sym(5.0) as i64, rng.sym(5.0) as i64],
        );
        let base = rng.rotation(3.0);
        let y: [SO3<f64>; 4] = std::array::from_fn(|_| base.compose(&rng.rotation(0.7)));
        let q = rng.rotation(3.0);
        let moved: [SO3<f64>; 4] = std::array::from_fn(|k| q.compose(&y[k]));
        for rule in [
            VertexRule::at_vertex(&dens, map, 0).expect("u = 0"),
            VertexRule::at_vertex(&dens, map, 3).expect("u = 3"),
            VertexRule::symmetric(&dens, map),
        ] {
            rule.check_cell(&c, &y).expect("rotations within π/2");
            let (a, b) = (rule.cell_lagrangian(&c, &y), rule.cell_lagrangian(&c, &moved));
            invariance = invariance.max((a - b).abs() / a.abs().max(1e-3));
            if trial < 10 {
                for k in 0..4 {
                    let (_, g) = vertex_gradient::<Rotations, _, 3>(&rule, &c, &y, k);
                    let fd = SVector::<f64, 3>::from_fn(|i, _| {
                        let mut xi = Vector3::zeros();
                        xi[i] = 1e-6;
                        let [plus, minus] = nudged::<Rotations, 3, 4>(&y, k, &xi);
                        (rule.cell_lagrangian(&c, &plus) - rule.cell_lagrangian(&c, &minus)) / 2e-6
                    });
                    fd_worst = fd_worst.max(rel_vec(&fd, &g));
                }
            }
        }
    }
    println!("SO(3), N = 3: max rel change under R ↦ QR {invariance:.1e}; exact gradient vs FD {fd_worst:.1e}");
    assert!(invariance < 1e-13 && fd_worst < 1e-7, "{invariance} {fd_worst}");
}
