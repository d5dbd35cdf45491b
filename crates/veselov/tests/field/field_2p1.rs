//! Fields in 2+1 dimensions on the CFK lattice, discretized from smooth
//! densities by the midpoint (affine) rule and marched vertex by vertex:
//! sine-Gordon's energy stays bounded without drift, the two translation
//! momenta of a free two-component field and the phase charge of the complex
//! Klein–Gordon field are conserved to round-off.
//!
//! Horizontal translations of the lattice are discrete symmetries only; the
//! discrete theory has no exactly conserved spatial momentum for
//! sine-Gordon (no continuous vertical symmetry generates it), so the exact
//! conservation tested here is that of the vertical symmetries.

use std::f64::consts::PI;

use nalgebra::{SVector, Vector2, Vector3};
use veselov::complex::CfkTorus;
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions, LevelSplitting};
use veselov::field::discretize::{CfkNodes, MidpointRule};
use veselov::field::fibre::Euclidean;
use veselov::spacetime::potential::{ComplexKleinGordon, NonlinearWave, SineGordon};

use crate::shared::cauchy_data;
use crate::threads;
use threads::on_threads;

/// The level energy: Σ of the straddling cells' energies over one Δt.
fn level_energy<P>(
    m: &CauchyMarcher<Euclidean<1>, MidpointRule<NonlinearWave<P>, CfkNodes<3>, 3>, 1>,
    rule: &MidpointRule<NonlinearWave<P>, CfkNodes<3>, 3>,
    dt: f64,
) -> f64
where
    NonlinearWave<P>: veselov::field::discretize::SmoothDensity<Euclidean<1>, 1, 3>,
{
    let mut e = 0.0;
    m.for_each_straddling_cell(|cell, y| e += rule.cell_energy(cell, y).expect("suitable cell"));
    e / dt
}

#[test]
fn sine_gordon_energy_is_bounded_without_drift() {
    let (nodes_per_axis, dx, dt) = (16, 0.25, 0.1);
    let torus = CfkTorus::new(3, &[nodes_per_axis, nodes_per_axis]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(dx, dt).expect("node map");
    let side = nodes_per_axis as f64 * dx;
    let (kx, ky) = (2.0 * PI / side, 4.0 * PI / side);
    let omega = (kx * kx + ky * ky + 1.0).sqrt();
    // A large-amplitude standing pattern (nonlinear: sin φ ≠ φ).
    let y = cauchy_data::<1>(&torus, &nodes, |x| {
        SVector::from([1.5 * (kx * x[0]).cos() * (ky * x[1]).sin() * (omega * x[2]).cos()])
    });
    let rule = MidpointRule::new(NonlinearWave(SineGordon), nodes);
    let mut m = CauchyMarcher::new(rule, torus, 0, &y, CauchyOptions::default()).expect("marcher");
    let e0 = level_energy(&m, &rule, dt);
    let levels = 1500;
    let mut energies = Vec::with_capacity(levels);
    for _ in 0..levels {
        let r = m.step().expect("level");
        assert!(r.max_relative_residual <= 1e-12);
        energies.push(level_energy(&m, &rule, dt));
    }
    let spread = energies.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max) / e0.abs();
    // No drift: the mean over the last tenth against the mean over the first.
    let tenth = levels / 10;
    let mean = |s: &[f64]| s.iter().sum::<f64>() / s.len() as f64;
    let drift = (mean(&energies[levels - tenth..]) - mean(&energies[..tenth])).abs() / e0.abs();
    println!("2+1 sine-Gordon, {levels} levels: energy spread {spread:e}, drift of tenth-means {drift:e}");
    assert!(spread < 0.05, "energy oscillation {spread:e}");
    assert!(drift < 5e-3, "energy drift {drift:e}");
}

#[test]
fn translation_momenta_and_phase_charge_are_conserved() {
    let (n, dx, dt) = (10, 0.3, 0.1);
    let torus = CfkTorus::new(3, &[n, n]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(dx, dt).expect("node map");
    let side = n as f64 * dx;
    let k = 2.0 * PI / side;
    let field = |x: &Vector3<f64>| {
        Vector2::new(
            0.4 * x[2] + 0.3 * (k * x[0] - 1.3 * x[2]).cos() * (k * x[1]).cos(),
            -0.2 * x[2] + 0.5 * (k * x[1] + 0.7 * x[2]).sin(),
        )
    };
    // Free two-component field: both fibre translations are symmetries.
    let free = MidpointRule::new(NonlinearWave(ComplexKleinGordon { m2: 0.0, lambda: 0.0 }), nodes);
    let mut m = CauchyMarcher::new(
        free,
        torus.clone(),
        0,
        &cauchy_data::<2>(&torus, &nodes, field),
        CauchyOptions::default(),
    )
    .expect("marcher");
    let shifts = [
        |_: &SVector<f64, 2>| Vector2::new(1.0, 0.0),
        |_: &SVector<f64, 2>| Vector2::new(0.0, 1.0),
    ];
    let p0: Vec<f64> = shifts.iter().map(|d| m.level_momentum(d)).collect();
    assert!(p0.iter().all(|p| p.abs() > 1e-2), "non-trivial momenta {p0:?}");
    let mut worst: f64 = 0.0;
    for _ in 0..1000 {
        m.step().expect("level");
        for (d, p) in shifts.iter().zip(&p0) {
            worst = worst.max(((m.level_momentum(d) - p) / p).abs());
        }
    }
    println!("free field: translation momenta {p0:?}, relative drift {worst:e}");
    assert!(worst < 1e-12, "translation momentum drift {worst:e}");

    // Complex Klein–Gordon: the phase rotation J = [[0, −1], [1, 0]].
    let kg = MidpointRule::new(NonlinearWave(ComplexKleinGordon { m2: 1.0, lambda: 0.5 }), nodes);
    let wave = |x: &Vector3<f64>| {
        let phase = k * x[0] - 1.5 * x[2];
        let amp = 0.6 + 0.2 * (k * x[1]).cos();
        // The offset gives the shift generator a non-zero net force.
        Vector2::new(0.3 + amp * phase.cos(), amp * phase.sin())
    };
    let mut m = CauchyMarcher::new(
        kg,
        torus.clone(),
        0,
        &cauchy_data::<2>(&torus, &nodes, wave),
        CauchyOptions::default(),
    )
    .expect("marcher");
    let rotation = |y: &SVector<f64, 2>| Vector2::new(-y[1], y[0]);
    let q0 = m.level_momentum(rotation);
    let mut worst: f64 = 0.0;
    for _ in 0..1000 {
        m.step().expect("level");
        worst = worst.max(((m.level_momentum(rotation) - q0) / q0).abs());
    }
    println!("complex Klein-Gordon: charge {q0}, relative drift {worst:e}");
    assert!(worst < 1e-12, "charge drift {worst:e}");
    // The translations are not symmetries of the massive field: its momenta move.
    let p = m.level_momentum(shifts[0]);
    let mut moved: f64 = 0.0;
    for _ in 0..30 {
        m.step().expect("level");
        moved = moved.max((m.level_momentum(shifts[0]) - p).abs());
    }
    assert!(moved > 1e-6, "a non-symmetry's momentum is not conserved ({moved:e})");
}

/// The same density, declared position-dependent: the rule then takes its
/// uncached path (node positions and edge inverse per cell).
struct Uncached<P>(NonlinearWave<P>);

impl<P: veselov::spacetime::potential::Potential<1> + Send + Sync>
    veselov::field::discretize::SmoothDensity<Euclidean<1>, 1, 3> for Uncached<P>
{
    fn density<D: veselov::ad::Scalar>(
        &self,
        x: &SVector<f64, 3>,
        y: &SVector<D, 1>,
        jet: &nalgebra::SMatrix<D, 1, 3>,
    ) -> D {
        veselov::field::discretize::SmoothDensity::<Euclidean<1>, 1, 3>::density(&self.0, x, y, jet)
    }
}

/// The simplex of shape `shape` based at the origin.
fn shape_cell(shape: usize) -> veselov::complex::TopCell {
    veselov::complex::TopCell {
        index: shape,
        shape,
        origin: [0; 8],
    }
}

#[test]
fn cached_shape_geometry_agrees_with_the_per_cell_path() {
    use veselov::complex::factorial;
    use veselov::field::cell::{DiscreteLagrangian, vertex_gradient};
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("node map");
    let cached = MidpointRule::new(NonlinearWave(SineGordon), nodes);
    let plain = MidpointRule::new(Uncached(NonlinearWave(SineGordon)), nodes);
    let mut worst: f64 = 0.0;
    // At the origin both paths form the same edge vectors; elsewhere the
    // per-cell path subtracts large node positions (its own round-off).
    for shape in 0..factorial(3) {
        let cell = shape_cell(shape);
        let y: Vec<SVector<f64, 1>> = (0..4)
            .map(|l| SVector::from([0.7 * l as f64 - 0.3 * shape as f64]))
            .collect();
        let a: f64 = cached.cell_lagrangian(&cell, &y);
        let b: f64 = plain.cell_lagrangian(&cell, &y);
        worst = worst.max((a - b).abs() / a.abs().max(1e-300));
        for l in 0..4 {
            let ga = vertex_gradient::<Euclidean<1>, _, 1>(&cached, &cell, &y, l).1;
            let gb = vertex_gradient::<Euclidean<1>, _, 1>(&plain, &cell, &y, l).1;
            worst = worst.max((ga - gb).amax() / ga.amax().max(1e-300));
        }
    }
    assert!(worst < 1e-13, "cached and per-cell geometry differ by {worst:e}");
}

/// The later vertices' gradients from one wide dual pass equal those of one
/// pass per vertex to round-off, for a scalar field (3 directions) and, on
/// the 1+1 lattice, a two-component field (4 directions); a frame field's
/// 18 directions do not fit and are refused.
#[test]
fn later_gradients_in_one_pass_are_the_per_vertex_gradients() {
    use veselov::complex::factorial;
    use veselov::field::cell::{later_gradients, vertex_gradient};
    use veselov::field::fibre::{Pose, PositionRotation};
    let scalar = MidpointRule::new(
        NonlinearWave(SineGordon),
        CfkNodes::<3>::space_time(0.3, 0.1).expect("node map"),
    );
    let pair = MidpointRule::new(
        NonlinearWave(ComplexKleinGordon { m2: 1.3, lambda: 0.4 }),
        CfkNodes::<2>::space_time(0.3, 0.1).expect("node map"),
    );
    let mut worst: f64 = 0.0;
    for shape in 0..factorial(3) {
        let cell = shape_cell(shape);
        let y: Vec<SVector<f64, 1>> = (0..4)
            .map(|l| SVector::from([(1.3 * l as f64 + 0.4 * shape as f64).sin()]))
            .collect();
        let mut wide = [SVector::zeros(); 4];
        assert!(later_gradients::<Euclidean<1>, _, 1>(&scalar, &cell, &y, &mut wide));
        for l in 1..4 {
            let one = vertex_gradient::<Euclidean<1>, _, 1>(&scalar, &cell, &y, l).1;
            worst = worst.max((wide[l] - one).amax() / one.amax().max(1e-300));
        }
    }
    for shape in 0..factorial(2) {
        let cell = shape_cell(shape);
        let y: Vec<SVector<f64, 2>> = (0..3)
            .map(|l| Vector2::new((0.9 * l as f64 + 0.2).cos(), 0.5 * l as f64 - 0.3 * shape as f64))
            .collect();
        let mut wide = [SVector::zeros(); 3];
        assert!(later_gradients::<Euclidean<2>, _, 2>(&pair, &cell, &y, &mut wide));
        for l in 1..3 {
            let one = vertex_gradient::<Euclidean<2>, _, 2>(&pair, &cell, &y, l).1;
            worst = worst.max((wide[l] - one).amax() / one.amax().max(1e-300));
        }
    }
    assert!(worst < 1e-14, "one wide pass and per-vertex passes differ by {worst:e}");
    let frame = veselov::models::rod::CosseratCell::new(
        veselov::models::rod::CosseratDensity::free(
            veselov::models::rod::RodParameters::new(
                1.0,
                nalgebra::Matrix3::identity(),
                nalgebra::Matrix3::identity(),
                nalgebra::Matrix3::identity(),
                Vector3::new(0.0, 0.0, 1.0),
            )
            .expect("valid"),
        ),
        0.1,
        0.05,
    )
    .expect("spacings");
    let cell = shape_cell(0);
    let y = [Pose::<f64>::new(Vector3::zeros(), veselov::lie::so3::exp(&Vector3::zeros())); 3];
    let mut out = [SVector::<f64, 6>::zeros(); 3];
    assert!(!later_gradients::<PositionRotation, _, 6>(&frame, &cell, &y, &mut out));
}

/// The parallel block sums over the straddling cells: the sequential sum to
/// round-off, the same bits on one and two threads, and a failing cell's
/// error returned (on a level of 24 × 24 = 576 vertices: two blocks of
/// `STRADDLING_BLOCK` per level, six blocks in all).
#[test]
fn straddling_cell_sums_are_the_sequential_sum_on_any_thread_count() {
    use veselov::field::cauchy::STRADDLING_BLOCK;
    let torus = CfkTorus::new(3, &[24, 24]).expect("torus");
    assert!(torus.level_size() > STRADDLING_BLOCK);
    let nodes = CfkNodes::<3>::space_time(0.25, 0.1).expect("node map");
    let y = cauchy_data::<1>(&torus, &nodes, |x| {
        SVector::from([1.2 * (0.8 * x[0] - 0.3 * x[2]).sin() * (0.5 * x[1]).cos()])
    });
    let rule = MidpointRule::new(NonlinearWave(SineGordon), nodes);
    let mut m = CauchyMarcher::new(rule, torus, 0, &y, CauchyOptions::default()).expect("marcher");
    for _ in 0..4 {
        m.step().expect("level");
    }
    let mut sequential = [0.0; 3];
    m.for_each_straddling_cell(|cell, y| {
        let mut p = [0.0; 2];
        sequential[0] += rule.cell_energy_momentum(cell, y, &mut p).expect("cell");
        sequential[1] += p[0];
        sequential[2] += p[1];
    });
    let sums = |threads: usize| {
        on_threads(threads, || {
            m.sum_straddling_cells(|cell, y| {
                let mut p = [0.0; 2];
                let e = rule.cell_energy_momentum(cell, y, &mut p)?;
                Ok::<_, veselov::field::discretize::CellError>([e, p[0], p[1]])
            })
            .expect("sums")
        })
    };
    let (one, two) = (sums(1), sums(2));
    assert_eq!(one.map(f64::to_bits), two.map(f64::to_bits), "thread counts");
    for (a, b) in one.iter().zip(&sequential) {
        assert!(
            (a - b).abs() <= 1e-13 * b.abs().max(1.0),
            "{one:?} against {sequential:?}"
        );
    }
    // The error is that of the first failing cell in the sequential order,
    // on any thread count (here: the first cell of shape 3, named by its
    // origin).
    let mut first = None;
    m.for_each_straddling_cell(|cell, _| {
        if cell.shape == 3 && first.is_none() {
            first = Some(cell.origin);
        }
    });
    for threads in [1, 2] {
        let failing = on_threads(threads, || {
            m.sum_straddling_cells(|cell, _| if cell.shape == 3 { Err(cell.origin) } else { Ok([1.0]) })
        });
        assert_eq!(failing, Err(first.expect("a cell of shape 3")), "{threads} threads");
    }
}

/// The midpoint rule's closed-form vertex solve gives the same field, bit
/// for bit, on one and two threads (levels of 32 × 32 vertices, every one
/// split between the two threads).
#[test]
fn closed_form_march_is_identical_on_one_and_two_threads() {
    let torus = CfkTorus::new(3, &[32, 32]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(0.25, 0.1).expect("node map");
    let y = cauchy_data::<1>(&torus, &nodes, |x| {
        SVector::from([1.5 * (0.8 * x[0] - 0.3 * x[2]).sin() * (0.4 * x[1]).cos()])
    });
    let rule = MidpointRule::new(NonlinearWave(SineGordon), nodes);
    let run = |threads: usize| {
        on_threads(threads, || {
            let mut m = CauchyMarcher::new(rule, torus.clone(), 0, &y, CauchyOptions::default())
                .expect("marcher")
                .with_level_splitting(LevelSplitting::Always);
            let mut parallel = 0;
            for _ in 0..30 {
                parallel += usize::from(m.step().expect("level").parallel);
            }
            (m.level_values(m.top_level()).expect("top level").to_vec(), parallel)
        })
    };
    let ((one, serial), (two, parallel)) = (run(1), run(2));
    assert_eq!(serial, 0, "one thread never splits a level");
    assert_eq!(parallel, 30, "two threads split {parallel} of 30 levels");
    assert!(one.iter().zip(&two).all(|(a, b)| a[0].to_bits() == b[0].to_bits()));
}
