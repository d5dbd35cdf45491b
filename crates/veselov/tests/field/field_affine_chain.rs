//! The midpoint rule's derivatives by the chain rule of its affine
//! interpolant (dual numbers over the density alone, or the closed form of a
//! diagonal jet metric) against the reference dual passes over the whole
//! cell Lagrangian, against central differences of the cell Lagrangian, and
//! through the Cauchy marcher (the rule's own vertex solve against the
//! marcher's generic one, and across a restart).

use nalgebra::{SMatrix, SVector, Vector2};
use veselov::ad::Scalar;
use veselov::complex::{CfkTorus, MAX_LATTICE_DIMENSION, TopCell, factorial};
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::cell::{DiscreteLagrangian, mixed_block_dual, vertex_gradient};
use veselov::field::discretize::{CfkNodes, MidpointRule, SmoothDensity};
use veselov::field::fibre::Euclidean;
use veselov::spacetime::potential::{ComplexKleinGordon, NonlinearWave, SineGordon};

use crate::shared::cauchy_data;
use crate::threads;
use threads::on_threads;

/// A density that reads the base point, so that the rule takes its per-cell
/// geometry: 𝓛 = ½(1 + 0.3x₀)|φ_t|² − ½Σ_a|φ_a|² + (1 + 0.1x₁)Σ_k cos(y_k) + 0.2 y₀φ_{0,0}.
struct Inhomogeneous;

impl<const M: usize, const N: usize> SmoothDensity<Euclidean<M>, M, N> for Inhomogeneous {
    fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>, jet: &SMatrix<D, M, N>) -> D {
        let mut value = D::zero();
        for k in 0..M {
            value += jet[(k, N - 1)] * jet[(k, N - 1)] * (0.5 * (1.0 + 0.3 * x[0]));
            for a in 0..N - 1 {
                value -= jet[(k, a)] * jet[(k, a)] * 0.5;
            }
            value += y[k].cos() * (1.0 + 0.1 * x[1 % N]);
        }
        value + y[0] * jet[(0, 0)] * 0.2
    }
}

/// A density that declares an anisotropic diagonal jet metric and reads the
/// base point in its jet-free part: 𝓛 = ½ Σ_{k,a} η_a φ_{ka}² + (1 + 0.2x₀) Σ_k cos y_k
/// + 0.1 x₁ y₀², η = (0.7, −1.3, 2.1, …).
#[derive(Clone)]
struct Anisotropic;

impl Anisotropic {
    fn eta(a: usize) -> f64 {
        [0.7, -1.3, 2.1, 0.4][a]
    }
}

impl<const M: usize, const N: usize> SmoothDensity<Euclidean<M>, M, N> for Anisotropic {
    fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>, jet: &SMatrix<D, M, N>) -> D {
        let mut value = self.jet_free_part(x, y);
        for k in 0..M {
            for a in 0..N {
                value += jet[(k, a)] * jet[(k, a)] * (0.5 * Self::eta(a));
            }
        }
        value
    }
    fn diagonal_jet_metric(&self) -> Option<SVector<f64, N>> {
        Some(SVector::from_fn(|a, _| Self::eta(a)))
    }
    fn jet_free_part<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>) -> D {
        let mut value = y[0] * y[0] * (0.1 * x[1 % N]);
        for k in 0..M {
            value += y[k].cos() * (1.0 + 0.2 * x[0]);
        }
        value
    }
}

/// A density that does not declare its diagonal jet metric: the rule
/// differentiates it by dual numbers over the whole density.
#[derive(Clone)]
struct Opaque<L>(L);

impl<L: SmoothDensity<Euclidean<M>, M, N>, const M: usize, const N: usize> SmoothDensity<Euclidean<M>, M, N>
    for Opaque<L>
{
    fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>, jet: &SMatrix<D, M, N>) -> D {
        self.0.density(x, y, jet)
    }
    fn depends_on_position(&self) -> bool {
        self.0.depends_on_position()
    }
}

fn cell(shape: usize, origin: [i64; 3]) -> TopCell {
    let mut o = [0; MAX_LATTICE_DIMENSION];
    o[..3].copy_from_slice(&origin);
    TopCell {
        index: shape,
        shape,
        origin: o,
    }
}

/// Vertex values that make the density's nonlinearity matter.
fn values<const M: usize>(count: usize, seed: f64) -> Vec<SVector<f64, M>> {
    (0..count)
        .map(|l| SVector::from_fn(|k, _| (1.7 * l as f64 + 0.9 * k as f64 + seed).sin() * 1.3))
        .collect()
}

fn relative<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax().max(1e-300)
}

/// Every gradient and block of `rule` on the cells of `origins` against the
/// reference passes; returns the worst relative differences (gradients,
/// blocks) and checks the one-vertex gradient equals the all-vertex pass
/// bit for bit.
fn compare<R, const M: usize>(rule: &R, n: usize, origins: &[[i64; 3]]) -> (f64, f64)
where
    R: DiscreteLagrangian<Euclidean<M>, M>,
{
    let (mut grad, mut block) = (0.0_f64, 0.0_f64);
    for (t, origin) in origins.iter().enumerate() {
        for shape in 0..factorial(n) {
            let c = cell(shape, *origin);
            let y = values::<M>(n + 1, 0.37 * (t * 7 + shape) as f64);
            let mut all = [SVector::<f64, M>::zeros(); 4];
            assert!(
                rule.analytic_gradients(&c, &y, &mut all[..=n]),
                "the chain rule applies"
            );
            for l in 0..=n {
                let reference = vertex_gradient::<Euclidean<M>, _, M>(rule, &c, &y, l).1;
                grad = grad.max(relative(&all[l], &reference));
                let one = rule.analytic_gradient(&c, &y, l).expect("one vertex");
                assert_eq!(one, all[l], "the one-vertex pass is the all-vertex pass's entry");
                for b in 0..=n {
                    let (g, j) = rule.analytic_block(&c, &y, l, b).expect("block");
                    let (rg, rj) = mixed_block_dual::<Euclidean<M>, _, M>(rule, &c, &y, l, b);
                    grad = grad.max(relative(&g, &rg));
                    block = block.max(relative(&j, &rj));
                }
            }
        }
    }
    (grad, block)
}

#[test]
fn chain_rule_derivatives_equal_the_dual_passes_over_the_cell() {
    let origins = [[0, 0, 0], [3, -2, 5], [-7, 4, 1]];
    let sg = MidpointRule::new(
        NonlinearWave(SineGordon),
        CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes"),
    );
    let kg = MidpointRule::new(
        NonlinearWave(ComplexKleinGordon { m2: 1.3, lambda: 0.4 }),
        CfkNodes::<3>::space_time(0.25, 0.07).expect("nodes"),
    );
    let kg2 = MidpointRule::new(
        NonlinearWave(ComplexKleinGordon { m2: 0.7, lambda: 1.1 }),
        CfkNodes::<2>::space_time(0.2, 0.05).expect("nodes"),
    );
    let sg_duals = MidpointRule::new(
        Opaque(NonlinearWave(SineGordon)),
        CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes"),
    );
    let kg_duals = MidpointRule::new(
        Opaque(NonlinearWave(ComplexKleinGordon { m2: 1.3, lambda: 0.4 })),
        CfkNodes::<3>::space_time(0.25, 0.07).expect("nodes"),
    );
    let anisotropic = MidpointRule::new(Anisotropic, CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes"));
    let inhomogeneous = MidpointRule::new(Inhomogeneous, CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes"));
    let inhomogeneous2 = MidpointRule::new(Inhomogeneous, CfkNodes::<3>::space_time(0.2, 0.15).expect("nodes"));
    let results = [
        ("sine-Gordon, 2+1 (closed form)", compare::<_, 1>(&sg, 3, &origins)),
        (
            "complex Klein-Gordon, 2+1 (closed form)",
            compare::<_, 2>(&kg, 3, &origins),
        ),
        (
            "complex Klein-Gordon, 1+1 (closed form)",
            compare::<_, 2>(&kg2, 2, &origins),
        ),
        (
            "sine-Gordon, 2+1 (4 directions)",
            compare::<_, 1>(&sg_duals, 3, &origins),
        ),
        (
            "complex Klein-Gordon, 2+1 (8 directions)",
            compare::<_, 2>(&kg_duals, 3, &origins),
        ),
        (
            "anisotropic metric, position-dependent potential, scalar (closed form)",
            compare::<_, 1>(&anisotropic, 3, &origins),
        ),
        (
            "anisotropic metric, position-dependent potential, pair (closed form)",
            compare::<_, 2>(&anisotropic, 3, &origins),
        ),
        (
            "position-dependent scalar",
            compare::<_, 1>(&inhomogeneous, 3, &origins),
        ),
        ("position-dependent pair", compare::<_, 2>(&inhomogeneous2, 3, &origins)),
    ];
    for (name, (grad, block)) in results {
        println!("{name}: gradients {grad:e}, blocks {block:e}");
        assert!(grad < 1e-13, "{name}: gradients differ by {grad:e}");
        assert!(block < 1e-13, "{name}: blocks differ by {block:e}");
    }
}

/// An independent check: the chain-rule gradient against central
/// differences of the cell Lagrangian (step 1e-5: truncation ~ h²|L‴| ≈ 1e-10,
/// rounding ~ ε|L|/h ≈ 1e-11 relative to the gradients here).
#[test]
fn chain_rule_gradients_match_finite_differences_of_the_cell_lagrangian() {
    let rule = MidpointRule::new(Inhomogeneous, CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes"));
    let h = 1e-5;
    let mut worst: f64 = 0.0;
    for shape in 0..6 {
        let c = cell(shape, [2, -1, 3]);
        let y = values::<2>(4, 0.5 + shape as f64);
        let mut all = [SVector::<f64, 2>::zeros(); 4];
        assert!(rule.analytic_gradients(&c, &y, &mut all));
        for l in 0..4 {
            for k in 0..2 {
                let at = |s: f64| {
                    let mut z = y.clone();
                    z[l][k] += s;
                    DiscreteLagrangian::<Euclidean<2>, 2>::cell_lagrangian::<f64>(&rule, &c, &z)
                };
                let fd = (at(h) - at(-h)) / (2.0 * h);
                let scale = all.iter().map(|g| g.amax()).fold(0.0, f64::max);
                worst = worst.max((all[l][k] - fd).abs() / scale);
            }
        }
    }
    println!("chain-rule gradients against central differences: {worst:e}");
    assert!(worst < 1e-8, "gradients and differences differ by {worst:e}");
}

/// The march with the chain rule (here the closed form of the wave's
/// diagonal jet metric, and the rule's own vertex solve) and with the
/// reference dual passes through the marcher's generic solve: the same field
/// to round-off. (6e-15 apart today, on values of size 1; the bound allows a
/// few ulps per level, growing at most like the linearised flow over 120
/// levels.) With a Jacobian at every vertex the generic solve is the same
/// Newton as the rule's own (iterations within 2 %); reusing the kept
/// Jacobians, it reaches the same field with a fraction of the Jacobians.
#[test]
fn marches_with_and_without_the_chain_rule_agree() {
    let torus = CfkTorus::new(3, &[8, 8]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    let data = cauchy_data(&torus, &nodes, |x| {
        Vector2::new((0.9 * x[0] - 0.5 * x[2]).sin(), 0.4 * (0.8 * x[1] + 0.3 * x[2]).cos())
    });
    let density = NonlinearWave(ComplexKleinGordon { m2: 1.0, lambda: 0.8 });
    let fast = MidpointRule::new(density, nodes);
    let reference = MidpointRule::new(density, nodes).with_chain_rule(false);
    let mut a = CauchyMarcher::new(fast, torus.clone(), 0, &data, CauchyOptions::default()).expect("marcher");
    let mut b = CauchyMarcher::new(reference, torus.clone(), 0, &data, CauchyOptions::default())
        .expect("marcher")
        .with_jacobian_reuse(false);
    let mut c = CauchyMarcher::new(reference, torus.clone(), 0, &data, CauchyOptions::default()).expect("marcher");
    let (mut iterations, mut jacobians, mut worst) = ([0usize; 3], [0usize; 3], [0.0_f64; 2]);
    for _ in 0..120 {
        for (k, m) in [&mut a, &mut b, &mut c].into_iter().enumerate() {
            let r = m.step().expect("level");
            (iterations[k], jacobians[k]) = (iterations[k] + r.iterations, jacobians[k] + r.jacobians);
        }
    }
    for w in a.level() - 3..=a.top_level() {
        let va = a.level_values(w).expect("level");
        for (k, other) in [&b, &c].into_iter().enumerate() {
            for (p, q) in va.iter().zip(other.level_values(w).expect("level")) {
                worst[k] = worst[k].max((p - q).amax());
            }
        }
    }
    println!(
        "chain rule against reference (Jacobian per vertex, kept): largest difference {worst:?}, \
         iterations {iterations:?}, Jacobians {jacobians:?}"
    );
    assert!(worst[0] < 1e-11 && worst[1] < 1e-11, "the marches part by {worst:?}");
    assert!(
        iterations[0].abs_diff(iterations[1]) * 50 <= iterations[1],
        "Newton iterations {iterations:?}"
    );
    assert!(jacobians[2] * 4 < jacobians[1], "Jacobians {jacobians:?}");
}

/// The rule's own vertex solve writes the solved cells' gradients; a march
/// restored from a checkpoint recomputes them through the marcher's own
/// evaluation. Both are the same operations on the same numbers, so the
/// restored march goes on bit for bit. Without the chain rule the marcher's
/// own Newton solves each vertex from the Jacobian factors its solve at
/// the same point kept one flow step before; the checkpoint carries them.
#[test]
fn a_restored_march_continues_bit_for_bit() {
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    restored_march_continues(MidpointRule::new(NonlinearWave(SineGordon), nodes));
    restored_march_continues(MidpointRule::new(Opaque(NonlinearWave(SineGordon)), nodes));
    restored_march_continues(MidpointRule::new(NonlinearWave(SineGordon), nodes).with_chain_rule(false));
}

/// 30 levels, a checkpoint, and 30 more levels both ways: the same bits.
fn restored_march_continues<L>(rule: MidpointRule<L, CfkNodes<3>, 3>)
where
    L: SmoothDensity<Euclidean<1>, 1, 3> + Clone,
{
    use veselov::run::{Checkpoint, Words};
    let torus = CfkTorus::new(3, &[6, 6]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    let data = cauchy_data(&torus, &nodes, |x| {
        SVector::from([1.2 * (1.1 * x[0] - 0.4 * x[2]).sin() * (0.9 * x[1]).cos()])
    });
    let new = || CauchyMarcher::new(rule.clone(), torus.clone(), 0, &data, CauchyOptions::default()).expect("marcher");
    let mut whole = new();
    for _ in 0..30 {
        whole.step().expect("level");
    }
    let mut saved = Vec::new();
    whole.save(&mut saved);
    let mut resumed = new();
    resumed.restore(&mut Words::new(&saved)).expect("restore");
    for _ in 0..30 {
        whole.step().expect("level");
        resumed.step().expect("level");
        let w = whole.top_level();
        let (a, b) = (
            whole.level_values(w).expect("level"),
            resumed.level_values(w).expect("level"),
        );
        for (x, y) in a.iter().zip(b) {
            assert_eq!(x[0].to_bits(), y[0].to_bits(), "level {w}");
        }
    }
}

/// A checkpoint whose kept-Jacobian section is damaged (a tag that is not
/// one, or words missing) or whose values are not finite is refused with an error that says so, and the
/// marcher it was read into goes on as if nothing had been read.
#[test]
fn a_damaged_kept_jacobian_section_is_refused() {
    use veselov::run::{Checkpoint, Words};
    let torus = CfkTorus::new(3, &[4, 4]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    let data = cauchy_data(&torus, &nodes, |x| {
        SVector::from([0.8 * (1.1 * x[0] - 0.4 * x[2]).sin()])
    });
    let rule = MidpointRule::new(NonlinearWave(SineGordon), nodes).with_chain_rule(false);
    let new = || CauchyMarcher::new(rule, torus.clone(), 0, &data, CauchyOptions::default()).expect("marcher");
    let mut m = new();
    for _ in 0..4 {
        m.step().expect("level");
    }
    let mut saved = Vec::new();
    m.save(&mut saved);
    let values = 1 + 6 * torus.level_size();
    assert_eq!(saved[values], -17.0, "the section's tag follows the values");
    let mut wrong_tag = saved.clone();
    wrong_tag[values + 1] = 5.0;
    // Read into a marcher two levels further than the checkpoint.
    let (mut target, mut untouched) = (new(), new());
    for _ in 0..6 {
        target.step().expect("level");
        untouched.step().expect("level");
    }
    let err = target.restore(&mut Words::new(&wrong_tag)).expect_err("not a tag");
    assert!(err.to_string().contains("kept-Jacobian tag"), "{err}");
    let mut not_finite = saved.clone();
    not_finite[1 + 2 * torus.level_size() + 3] = f64::NAN;
    let err = target.restore(&mut Words::new(&not_finite)).expect_err("a NaN value");
    assert!(
        err.to_string()
            .contains("non-finite value of vertex 3 of stored level 2"),
        "{err}"
    );
    let truncated = &saved[..saved.len() - 1];
    let err = target.restore(&mut Words::new(truncated)).expect_err("truncated");
    assert!(err.to_string().contains("truncated"), "{err}");
    assert_eq!(target.level(), untouched.level());
    for _ in 0..3 {
        target.step().expect("level");
        untouched.step().expect("level");
    }
    let w = target.top_level();
    let bits = |values: &[SVector<f64, 1>]| -> Vec<u64> { values.iter().map(|y| y[0].to_bits()).collect() };
    assert_eq!(
        bits(target.level_values(w).expect("level")),
        bits(untouched.level_values(w).expect("level")),
        "a refused checkpoint changed the march"
    );
    // Without the section (a checkpoint of an earlier version) the march
    // starts with fresh Jacobians and stays on the same field to round-off.
    let mut fresh = new();
    fresh.restore(&mut Words::new(&saved[..values])).expect("values only");
    let mut whole = m;
    for _ in 0..10 {
        whole.step().expect("level");
        fresh.step().expect("level");
    }
    let w = whole.top_level();
    let (a, b) = (
        whole.level_values(w).expect("level"),
        fresh.level_values(w).expect("level"),
    );
    let worst = a.iter().zip(b).map(|(x, y)| (x[0] - y[0]).abs()).fold(0.0, f64::max);
    assert!(worst < 1e-12, "the marches part by {worst:e}");
}

/// The anisotropic density with one entry of its declared metric wrong, or
/// with a jet-free part that is not its density at a zero jet.
struct Misdeclared {
    /// Which entry of η is declared with the wrong sign (None: η right).
    flipped: Option<usize>,
    /// Whether the jet-free part leaves out the density's cosine.
    wrong_potential: bool,
}

impl<const M: usize, const N: usize> SmoothDensity<Euclidean<M>, M, N> for Misdeclared {
    fn density<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>, jet: &SMatrix<D, M, N>) -> D {
        SmoothDensity::<Euclidean<M>, M, N>::density(&Anisotropic, x, y, jet)
    }
    fn diagonal_jet_metric(&self) -> Option<SVector<f64, N>> {
        Some(SVector::from_fn(|a, _| {
            let eta = Anisotropic::eta(a);
            if self.flipped == Some(a) { -eta } else { eta }
        }))
    }
    fn jet_free_part<D: Scalar>(&self, x: &SVector<f64, N>, y: &SVector<D, M>) -> D {
        let full = SmoothDensity::<Euclidean<M>, M, N>::jet_free_part(&Anisotropic, x, y);
        if self.wrong_potential { full - y[0].cos() } else { full }
    }
}

/// A marcher is not built on a density whose declared jet metric or
/// jet-free part does not hold: the closed form they give is checked
/// against the derivative of the cell Lagrangian on the Cauchy data's first
/// cells (moved off the data by small chart steps), and the error names the
/// cell. The right declaration passes. The data do not vary along x₁, so
/// only the moved values reveal a wrong η₁; a field at rest (all gradients
/// at round-off level on the data themselves) is not refused.
#[test]
fn a_wrong_metric_declaration_is_refused() {
    let torus = CfkTorus::new(3, &[8, 8]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    // Linear in x₀ and t: every cell's jet along x₁ is exactly zero.
    let data = cauchy_data(&torus, &nodes, |x| {
        SVector::<f64, 1>::from([0.4 + 0.3 * x[0] - 0.2 * x[2]])
    });
    let rest = cauchy_data(&torus, &nodes, |_| SVector::<f64, 1>::from([0.1 + 1e-17]));
    let right = || Misdeclared {
        flipped: None,
        wrong_potential: false,
    };
    assert!(
        CauchyMarcher::new(
            MidpointRule::new(right(), nodes),
            torus.clone(),
            0,
            &rest,
            CauchyOptions::default()
        )
        .is_ok(),
        "a field at rest"
    );
    let build = |density: Misdeclared| {
        CauchyMarcher::new(
            MidpointRule::new(density, nodes),
            torus.clone(),
            0,
            &data,
            CauchyOptions::default(),
        )
        .map(|_| ())
    };
    assert!(build(right()).is_ok(), "the right declaration");
    for wrong in [
        Misdeclared {
            flipped: Some(0),
            wrong_potential: false,
        },
        Misdeclared {
            flipped: Some(1),
            wrong_potential: false,
        },
        Misdeclared {
            flipped: Some(2),
            wrong_potential: false,
        },
        Misdeclared {
            flipped: None,
            wrong_potential: true,
        },
    ] {
        let what = format!(
            "η flipped at {:?}, wrong potential {}",
            wrong.flipped, wrong.wrong_potential
        );
        let message = build(wrong).expect_err(&what).to_string();
        println!("{what}: {message}");
        assert!(
            message.contains("cell Lagrangian")
                && message.contains("level 0")
                && message.contains("diagonal_jet_metric"),
            "{what}: {message}"
        );
    }
}

/// The flow marcher (any finite complex) makes the same check on the cells
/// whose values are all known when it is built.
#[test]
fn a_flow_marcher_refuses_a_wrong_metric_declaration() {
    use veselov::complex::{CfkWindow, TopCells};
    use veselov::field::flow::FlowMarcher;
    let window = CfkWindow::open(&[3, 3, 2]).expect("window");
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    let count = window.vertex_count();
    // Linear in x₀ and t: every jet along x₁ is exactly zero.
    let values: Vec<SVector<f64, 1>> = (0..count)
        .map(|v| {
            let x = nodes.node(&window.extent().vertex(v));
            SVector::from([0.4 + 0.3 * x[0] - 0.2 * x[2]])
        })
        .collect();
    let build = |flipped: Option<usize>| {
        let density = Misdeclared {
            flipped,
            wrong_potential: false,
        };
        FlowMarcher::<_, Euclidean<1>, _, 1>::new(
            window.clone(),
            MidpointRule::new(density, nodes),
            values.clone(),
            vec![true; count],
            CauchyOptions::default(),
        )
        .map(|_| ())
    };
    assert!(build(None).is_ok(), "the right declaration");
    let message = build(Some(1)).expect_err("η₁ flipped").to_string();
    assert!(
        message.contains("cell Lagrangian") && message.contains("diagonal_jet_metric"),
        "{message}"
    );
}

/// A level's vertices solved together in lanes (the rule's metric solve,
/// [`DiscreteLagrangian::vertex_lanes`]) get the bits they get one at a
/// time: on a lattice whose levels do not fill the last group of lanes,
/// for a density with a shared geometry per shape (sine-Gordon), one that
/// reads the base point (each cell its own geometry) and a two-component
/// field, on one and two threads.
#[test]
fn vertices_solved_in_lanes_have_the_bits_of_one_at_a_time() {
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    lanes_match_one_at_a_time(MidpointRule::new(NonlinearWave(SineGordon), nodes), |x| {
        SVector::from([1.2 * (1.1 * x[0] - 0.4 * x[2]).sin() * (0.9 * x[1]).cos()])
    });
    lanes_match_one_at_a_time(MidpointRule::new(Anisotropic, nodes), |x| {
        SVector::from([0.8 * (0.7 * x[0] + 0.3 * x[2]).sin() + 0.2 * x[1].cos()])
    });
    lanes_match_one_at_a_time(
        MidpointRule::new(NonlinearWave(ComplexKleinGordon { m2: 1.0, lambda: 0.8 }), nodes),
        |x| Vector2::new((0.9 * x[0] - 0.5 * x[2]).sin(), 0.4 * (0.8 * x[1] + 0.3 * x[2]).cos()),
    );
}

/// 25 levels of a 5 × 3 lattice (15 vertices a level: a group of eight and
/// one of seven; with fewer lanes, groups of two, three and four) in lanes
/// (the level in runs of whole groups,
/// [`DiscreteLagrangian::solve_vertex_run`]) and one vertex at a time.
fn lanes_match_one_at_a_time<L, const M: usize>(
    rule: MidpointRule<L, CfkNodes<3>, 3>,
    f: impl Fn(&SVector<f64, 3>) -> SVector<f64, M>,
) where
    L: SmoothDensity<Euclidean<M>, M, 3> + Clone,
{
    assert!(rule.vertex_lanes() > 1, "the metric solve takes lanes");
    let torus = CfkTorus::new(3, &[5, 3]).expect("torus");
    let nodes = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    let data = cauchy_data(&torus, &nodes, f);
    let march = |lanes: usize, threads: usize| {
        on_threads(threads, || {
            let mut m = CauchyMarcher::new(rule.clone(), torus.clone(), 0, &data, CauchyOptions::default())
                .expect("marcher")
                .with_vertex_lanes(lanes);
            let mut iterations = 0;
            for _ in 0..25 {
                iterations += m.step().expect("level").iterations;
            }
            let bits: Vec<u64> = (m.level()..=m.top_level())
                .flat_map(|w| m.level_values(w).expect("level").to_vec())
                .flat_map(|y| y.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
                .collect();
            (bits, iterations)
        })
    };
    let alone = march(1, 1);
    assert!(alone.1 > 0, "the vertices iterate");
    for threads in [1, 2] {
        assert!(
            march(8, threads) == alone,
            "lanes on {threads} threads differ from one at a time"
        );
    }
    // Groups of two, three and four: every level's runs split otherwise.
    for lanes in [2, 3, 4] {
        assert!(march(lanes, 1) == alone, "groups of {lanes} differ from one at a time");
    }
}
