//! The field theory core on CFK lattices: Euler–Lagrange residuals against
//! finite differences of the action for every fibre, the Noether identity on
//! random (non-critical) fields, the n = 1 reduction to discrete mechanics,
//! conservation of level momenta by the Cauchy marcher, and bit-identical
//! results for every thread count.

use nalgebra::{DMatrix, Matrix3, SVector, Vector2, Vector3};
use veselov::ad::Scalar;
use veselov::complex::{CfkSlab, CfkTorus, TopCell, TopCells, permutation};
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::cell::{DiscreteLagrangian, mixed_block_dual, vertex_gradient};
use veselov::field::fibre::{Euclidean, Fibre, Pose, PositionRotation, RigidMotions, Rotations};
use veselov::field::flow::FlowMarcher;
use veselov::field::variational::{action, euler_lagrange, noether_balance};
use veselov::lie::{SE3, SO3, so3};
use veselov::mechanics::{GalerkinIntegrator, GalerkinScheme, Lagrangian, Method, PhaseState, integrate};

use crate::shared::Xorshift;
use crate::threads;
use threads::on_threads;

/// Node map of the n-dimensional space–time CFK lattice:
/// space x_a = Δx(v_a − w/n) (a < n − 1 … here all but the last axis),
/// time t = wΔt/n, w = Σv.
fn node<const N: usize>(v: &[i64], dx: f64, dt: f64) -> SVector<f64, N> {
    let w: i64 = v[..N].iter().sum();
    SVector::from_fn(|a, _| {
        if a + 1 < N {
            dx * (v[a] as f64 - w as f64 / N as f64)
        } else {
            dt * w as f64 / N as f64
        }
    })
}

/// The affine (P1) discretization of 𝓛 = ½φ_t² − ½|∇φ|² − V(|φ|²) on a CFK
/// simplex, for a field in ℝ^K on an N-dimensional space–time lattice
/// (barycentre value, constant gradient, simplex volume): written out here by
/// hand, independently of the library's discretizations.
struct AffineWave<const N: usize, const K: usize> {
    dx: f64,
    dt: f64,
    mass2: f64,
    quartic: f64,
}

impl<const N: usize, const K: usize> AffineWave<N, K> {
    /// The inverse edge matrix (T^X)⁻¹ and volume of the simplex shape σ.
    fn geometry(&self, shape: usize) -> (DMatrix<f64>, f64) {
        let perm = permutation(N, shape);
        let mut v = [0i64; 8];
        let x0 = node::<N>(&v, self.dx, self.dt);
        let mut tx = DMatrix::<f64>::zeros(N, N);
        for l in 0..N {
            v[perm[l]] += 1;
            tx.set_column(l, &(node::<N>(&v, self.dx, self.dt) - x0));
        }
        let det = tx.determinant();
        let fact: f64 = (1..=N).map(|k| k as f64).product();
        (tx.try_inverse().expect("non-degenerate simplex"), det.abs() / fact)
    }
}

impl<const N: usize, const K: usize> DiscreteLagrangian<Euclidean<K>, K> for AffineWave<N, K> {
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SVector<D, K>]) -> D {
        let (inv, vol) = self.geometry(cell.shape);
        let mut lag = D::zero();
        let mut mean = SVector::<D, K>::zeros();
        for yl in y {
            mean += yl;
        }
        mean /= D::from((N + 1) as f64);
        for k in 0..K {
            // Jet row: [y_l − y_0]_l · (T^X)⁻¹ (columns ∂/∂x^a).
            let mut grad = SVector::<D, N>::zeros();
            for a in 0..N {
                for l in 0..N {
                    grad[a] += (y[l + 1][k] - y[0][k]) * inv[(l, a)];
                }
            }
            lag += grad[N - 1] * grad[N - 1] * 0.5;
            for a in 0..N - 1 {
                lag -= grad[a] * grad[a] * 0.5;
            }
        }
        let r2 = mean.dot(&mean);
        lag -= r2 * (0.5 * self.mass2) + r2 * r2 * (0.25 * self.quartic);
        lag * vol
    }
}

/// A rod-like Lagrangian on ℝ³ × SO(3) (simplex cells), invariant under
/// (r, R) ↦ (Qr + c, QR): built from Rᵢᵀ(r_j − r_i), log(RᵢᵀR_j).
struct FrameChain {
    stiff: f64,
}

impl DiscreteLagrangian<PositionRotation, 6> for FrameChain {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[Pose<D>]) -> D {
        let mut lag = D::zero();
        for l in 0..y.len() - 1 {
            let (a, b) = (&y[l], &y[l + 1]);
            let strain = a.rotation.matrix().transpose() * (b.position - a.position)
                - Vector3::new(D::one(), D::zero(), D::zero());
            let bend = so3::log(&a.rotation.inverse().compose(&b.rotation)).expect("small relative rotation");
            let sign = if l == 0 { 1.0 } else { -1.0 };
            lag += (strain.dot(&strain) * 0.5 + bend.dot(&bend) * (0.5 * self.stiff)) * sign;
        }
        lag
    }
}

/// A Lagrangian on SO(3) (left-invariant pairs), and one on SE(3).
struct RotorChain;
impl DiscreteLagrangian<Rotations, 3> for RotorChain {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[SO3<D>]) -> D {
        let mut lag = D::zero();
        for l in 0..y.len() - 1 {
            let w = so3::log(&y[l].inverse().compose(&y[l + 1])).expect("small relative rotation");
            lag += w.dot(&Vector3::new(D::from(1.0), D::from(2.0), D::from(3.0)).component_mul(&w)) * (0.5 + l as f64);
        }
        lag
    }
}
struct MotionChain;
impl DiscreteLagrangian<RigidMotions, 6> for MotionChain {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[SE3<D>]) -> D {
        let mut lag = D::zero();
        for l in 0..y.len() - 1 {
            let rel = y[l].inverse().compose(&y[l + 1]);
            let x = rel.translation();
            let m: Matrix3<D> = *rel.rotation().matrix();
            lag += x.dot(x) * (1.0 + l as f64) + (m[(0, 1)] - m[(1, 0)]) * x[2] + m[(2, 2)].sin();
        }
        lag
    }
}

/// EL_v against central finite differences of the action in the chart y_v·τ(εe_k).
fn check_el_against_fd<F: Fibre<M>, L: DiscreteLagrangian<F, M>, const M: usize>(
    lag: &L,
    slab: &CfkSlab,
    y: &[F::Point<f64>],
    tol: f64,
) {
    let all: Vec<usize> = (0..slab.cell_count()).collect();
    let mid = slab.vertex_index(slab.levels() / 2, 1);
    let el = euler_lagrange::<F, L, CfkSlab, M>(slab, lag, y, mid).expect("EL");
    let eps = 1e-6;
    for k in 0..M {
        let mut plus = y.to_vec();
        let mut minus = y.to_vec();
        let e = SVector::<f64, M>::from_fn(|i, _| if i == k { 1.0 } else { 0.0 });
        plus[mid] = F::retract(&y[mid], &(e * eps));
        minus[mid] = F::retract(&y[mid], &(e * -eps));
        let fd = (action::<F, L, CfkSlab, M>(slab, lag, &plus, all.iter().copied()).expect("action")
            - action::<F, L, CfkSlab, M>(slab, lag, &minus, all.iter().copied()).expect("action"))
            / (2.0 * eps);
        assert!(
            (fd - el[k]).abs() <= tol * (1.0 + el.amax()),
            "{}: component {k}: EL {} vs FD {fd}",
            F::NAME,
            el[k]
        );
    }
}

fn slab(n: usize, period: usize, levels: usize) -> CfkSlab {
    CfkSlab::new(CfkTorus::new(n, &vec![period; n - 1]).expect("torus"), 0, levels).expect("slab")
}

fn random_rotation(rng: &mut Xorshift, scale: f64) -> SO3<f64> {
    so3::exp(&rng.vector::<3>(scale))
}

/// The Jacobian blocks of the vertex solves, ∂/∂ζ_j (∂L_β/∂y_a)_i at
/// y_b·τ(ζ) (`mixed_block_dual`, hyper-dual numbers), against central
/// differences of the exact vertex gradient with y_b moved to y_b·τ(±εe_j):
/// for b = a the gradient at the moved point in its own chart. Every pair
/// (a, b) of a 2+1 simplex; the gradient returned beside the block is the
/// vertex gradient to round-off.
fn check_blocks_against_fd<F: Fibre<M>, L: DiscreteLagrangian<F, M>, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
) {
    let eps = 1e-5;
    let mut worst: f64 = 0.0;
    for a in 0..y.len() {
        let gradient = vertex_gradient::<F, L, M>(lag, cell, y, a).1;
        for b in 0..y.len() {
            let (g, block) = mixed_block_dual::<F, L, M>(lag, cell, y, a, b);
            assert!(
                (g - gradient).amax() <= 1e-13 * (1.0 + gradient.amax()),
                "{}: the block's gradient at ({a}, {b}) {g} against {gradient}",
                F::NAME
            );
            for j in 0..M {
                let e = SVector::<f64, M>::from_fn(|i, _| if i == j { eps } else { 0.0 });
                let moved = |step: &SVector<f64, M>| {
                    let mut z = y.to_vec();
                    z[b] = F::retract(&y[b], step);
                    vertex_gradient::<F, L, M>(lag, cell, &z, a).1
                };
                let fd = (moved(&e) - moved(&-e)) / (2.0 * eps);
                let err = (fd - block.column(j)).amax() / (1.0 + block.amax());
                worst = worst.max(err);
                assert!(err <= 1e-7, "{}: block ({a}, {b}) column {j}: {err:.1e}", F::NAME);
            }
        }
    }
    println!("{}: mixed blocks against central differences {worst:.1e}", F::NAME);
}

#[test]
fn mixed_blocks_are_the_derivatives_of_the_vertex_gradients_for_every_fibre() {
    let mut rng = Xorshift(0x2545_f491_4f6c_dd1d);
    let cell = TopCell {
        index: 0,
        shape: 3,
        origin: [0; veselov::complex::MAX_LATTICE_DIMENSION],
    };
    let wave = AffineWave::<3, 2> {
        dx: 0.3,
        dt: 0.1,
        mass2: 1.0,
        quartic: 0.7,
    };
    let points: Vec<_> = (0..4).map(|_| rng.vector::<2>(1.0)).collect();
    check_blocks_against_fd::<Euclidean<2>, _, 2>(&wave, &cell, &points);
    let scalar = AffineWave::<3, 1> {
        dx: 0.3,
        dt: 0.1,
        mass2: 1.0,
        quartic: 0.7,
    };
    let values: Vec<_> = (0..4).map(|_| rng.vector::<1>(1.0)).collect();
    check_blocks_against_fd::<Euclidean<1>, _, 1>(&scalar, &cell, &values);
    let base = random_rotation(&mut rng, 1.0);
    let rots: Vec<_> = (0..4).map(|_| base.compose(&random_rotation(&mut rng, 0.3))).collect();
    check_blocks_against_fd::<Rotations, _, 3>(&RotorChain, &cell, &rots);
    let motions: Vec<_> = rots.iter().map(|r| SE3::new(*r, rng.vector::<3>(1.0))).collect();
    check_blocks_against_fd::<RigidMotions, _, 6>(&MotionChain, &cell, &motions);
    let poses: Vec<_> = rots.iter().map(|r| Pose::new(rng.vector::<3>(1.0), *r)).collect();
    check_blocks_against_fd::<PositionRotation, _, 6>(&FrameChain { stiff: 2.0 }, &cell, &poses);
}

#[test]
fn euler_lagrange_is_the_derivative_of_the_action_for_every_fibre() {
    let mut rng = Xorshift(0x9e3779b97f4a7c15);
    for n in 1..=3 {
        let s = slab(n, 3, 2 * n + 1);
        let wave = AffineWave::<3, 2> {
            dx: 0.3,
            dt: 0.1,
            mass2: 1.0,
            quartic: 0.7,
        };
        if n == 3 {
            let y: Vec<_> = (0..s.vertex_count()).map(|_| rng.vector::<2>(1.0)).collect();
            check_el_against_fd::<Euclidean<2>, _, 2>(&wave, &s, &y, 1e-7);
        }
        let base = random_rotation(&mut rng, 1.0);
        let rots: Vec<_> = (0..s.vertex_count())
            .map(|_| base.compose(&random_rotation(&mut rng, 0.2)))
            .collect();
        check_el_against_fd::<Rotations, _, 3>(&RotorChain, &s, &rots, 1e-7);
        let motions: Vec<_> = rots.iter().map(|r| SE3::new(*r, rng.vector::<3>(1.0))).collect();
        check_el_against_fd::<RigidMotions, _, 6>(&MotionChain, &s, &motions, 1e-7);
        let poses: Vec<_> = rots.iter().map(|r| Pose::new(rng.vector::<3>(1.0), *r)).collect();
        check_el_against_fd::<PositionRotation, _, 6>(&FrameChain { stiff: 2.0 }, &s, &poses, 1e-7);
    }
}

#[test]
fn noether_identity_holds_for_random_fields() {
    let mut rng = Xorshift(0x243f6a8885a308d3);
    let s = slab(2, 5, 7);
    // A domain: a random half of the cells.
    let domain: Vec<bool> = (0..s.cell_count()).map(|_| rng.uniform() > 0.0).collect();
    // ℝ³ × SO(3) under rigid motions: translations (c, 0), rotations (ξ × r, Rᵀξ).
    let base = random_rotation(&mut rng, 1.0);
    let poses: Vec<_> = (0..s.vertex_count())
        .map(|_| Pose::new(rng.vector::<3>(1.0), base.compose(&random_rotation(&mut rng, 0.3))))
        .collect();
    let lag = FrameChain { stiff: 3.0 };
    for axis in 0..3 {
        let e = Vector3::from_fn(|i, _| if i == axis { 1.0 } else { 0.0 });
        let t = noether_balance::<PositionRotation, _, _, 6>(&s, &lag, &poses, &domain, |_| {
            SVector::<f64, 6>::new(e[0], e[1], e[2], 0.0, 0.0, 0.0)
        })
        .expect("balance");
        let r = noether_balance::<PositionRotation, _, _, 6>(&s, &lag, &poses, &domain, |p| {
            let a = e.cross(&p.position);
            let b = p.rotation.matrix().transpose() * e;
            SVector::<f64, 6>::new(a[0], a[1], a[2], b[0], b[1], b[2])
        })
        .expect("balance");
        assert!(
            t.interior.abs() > 1e-3 && r.interior.abs() > 1e-3,
            "random fields are not critical"
        );
        assert!(t.relative_defect() < 1e-13, "translation {axis}: {t:?}");
        assert!(r.relative_defect() < 1e-13, "rotation {axis}: {r:?}");
    }
    // ℝ² field with an O(2)-invariant potential: D(y) = (−y₁, y₀).
    let s3 = slab(3, 3, 7);
    // A slab of whole levels plus a random scatter of other cells: interior
    // and frontier vertices of many kinds.
    let per_level = s3.torus().level_size() * 6;
    let domain: Vec<bool> = (0..s3.cell_count())
        .map(|c| c / per_level <= 2 || rng.uniform() > 0.3)
        .collect();
    let y: Vec<_> = (0..s3.vertex_count()).map(|_| rng.vector::<2>(1.0)).collect();
    let wave = AffineWave::<3, 2> {
        dx: 0.4,
        dt: 0.2,
        mass2: 1.0,
        quartic: 0.5,
    };
    let b = noether_balance::<Euclidean<2>, _, _, 2>(&s3, &wave, &y, &domain, |p| Vector2::new(-p[1], p[0]))
        .expect("balance");
    assert!(b.interior.abs() > 1e-3);
    assert!(b.relative_defect() < 1e-13, "phase rotation: {b:?}");
    // A generator that is not a symmetry breaks the identity (the test can fail).
    let c =
        noether_balance::<Euclidean<2>, _, _, 2>(&s3, &wave, &y, &domain, |_| Vector2::new(1.0, 0.0)).expect("balance");
    assert!(
        c.relative_defect() > 1e-6,
        "a shift is not a symmetry of the massive field: {c:?}"
    );
}

/// Kepler: L = ½|v|² + 1/|q|.
#[derive(Clone, Copy)]
struct Kepler;
impl Lagrangian<2> for Kepler {
    fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        v.dot(v) * 0.5 + q.dot(q).sqrt().recip()
    }
}

/// The midpoint discrete Lagrangian of Kepler as a cell Lagrangian on the
/// 1-dimensional CFK lattice (edges [k, k+1]).
struct MidpointKepler {
    h: f64,
}
impl DiscreteLagrangian<Euclidean<2>, 2> for MidpointKepler {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[SVector<D, 2>]) -> D {
        let q = (y[0] + y[1]) * D::from(0.5);
        let v = (y[1] - y[0]) / D::from(self.h);
        Kepler.lagrangian(D::zero(), &q, &v) * self.h
    }
}

#[test]
fn one_dimensional_core_is_discrete_mechanics() {
    let h = 0.01;
    let mut map =
        GalerkinIntegrator::new(Kepler, GalerkinScheme::new(Method::Midpoint).expect("method"), h).expect("integrator");
    let x0 = PhaseState::new(0.0, Vector2::new(0.4, 0.0), Vector2::new(0.0, 2.0));
    let steps = 2000;
    let run = integrate(&mut map, x0, steps, 1).into_result().expect("mechanics run");
    let torus = CfkTorus::new(1, &[]).expect("1-D lattice");
    let data = vec![vec![run.states[0].q], vec![run.states[1].q]];
    let mut marcher =
        CauchyMarcher::new(MidpointKepler { h }, torus, 0, &data, CauchyOptions::default()).expect("marcher");
    // Angular momentum as the level momentum of the rotation generator.
    let rot = |q: &SVector<f64, 2>| Vector2::new(-q[1], q[0]);
    let j0 = marcher.level_momentum(rot);
    let jmech = run.states[0].q[0] * run.states[0].p[1] - run.states[0].q[1] * run.states[0].p[0];
    assert!((j0 - jmech).abs() < 1e-13, "level momentum {j0} vs q × p {jmech}");
    let (mut worst, mut jdrift) = (0.0f64, 0.0f64);
    for k in 2..=steps {
        marcher.step().expect("vertex solve");
        let q = marcher.level_values(k as i64).expect("known level")[0];
        // Both solve each step to round-off; their difference is round-off
        // carried along by Kepler's linear phase-error growth: bound it per step.
        worst = worst.max((q - run.states[k].q).amax() / k as f64);
        jdrift = jdrift.max((marcher.level_momentum(rot) - j0).abs());
    }
    println!("n = 1: trajectory difference per step {worst:e}, angular momentum drift {jdrift:e} (J = {j0})");
    assert!(jdrift < 1e-12, "angular momentum drift {jdrift:e}");
    assert!(
        worst < 2e-14,
        "core and mechanics trajectories differ by {worst:e} per step"
    );
}

/// March a complex Klein–Gordon field on the 2+1 CFK lattice.
fn complex_field_marcher(period: usize) -> CauchyMarcher<Euclidean<2>, AffineWave<3, 2>, 2> {
    let (dx, dt) = (0.5, 0.2);
    let torus = CfkTorus::new(3, &[period, period]).expect("torus");
    let data: Vec<Vec<SVector<f64, 2>>> = (0..6)
        .map(|w| {
            (0..torus.level_size())
                .map(|i| {
                    let v = torus.vertex(w, i);
                    let x = node::<3>(&v, dx, dt);
                    let k = 2.0 * std::f64::consts::PI / (period as f64 * dx);
                    // A slowly rotating plane wave with a bump.
                    let phase = k * x[0] - 1.1 * x[2];
                    let amp = 0.5 + 0.2 * (k * x[1]).cos();
                    Vector2::new(amp * phase.cos(), amp * phase.sin())
                })
                .collect()
        })
        .collect();
    let lag = AffineWave::<3, 2> {
        dx,
        dt,
        mass2: 1.0,
        quartic: 0.3,
    };
    CauchyMarcher::new(lag, torus, 0, &data, CauchyOptions::default()).expect("marcher")
}

#[test]
fn marching_conserves_the_level_charge_and_solves_euler_lagrange() {
    let mut m = complex_field_marcher(6);
    let charge = |p: &SVector<f64, 2>| Vector2::new(-p[1], p[0]);
    let q0 = m.level_momentum(charge);
    assert!(q0.abs() > 1e-2);
    let mut history: Vec<Vec<SVector<f64, 2>>> = (0..6).map(|w| m.level_values(w).expect("data").to_vec()).collect();
    let mut worst: f64 = 0.0;
    for _ in 0..300 {
        let report = m.step().expect("level");
        assert!(report.max_relative_residual <= 1e-12);
        worst = worst.max(((m.level_momentum(charge) - q0) / q0).abs());
        history.push(m.level_values(m.top_level()).expect("new level").to_vec());
    }
    assert!(worst < 1e-12, "charge drift {worst:e}");
    // Independent check: EL_v = 0 through the stars of a finite window built
    // from the stored levels, at every vertex of a solved level.
    let slab = CfkSlab::new(m.torus().clone(), 0, history.len()).expect("window");
    let y: Vec<_> = history.concat();
    let lag = AffineWave::<3, 2> {
        dx: 0.5,
        dt: 0.2,
        mass2: 1.0,
        quartic: 0.3,
    };
    for level in [3usize, 150, 300] {
        for i in 0..slab.torus().level_size() {
            let el = euler_lagrange::<Euclidean<2>, _, _, 2>(&slab, &lag, &y, slab.vertex_index(level, i)).expect("EL");
            assert!(el.amax() < 1e-12, "EL at level {level}, vertex {i}: {el}");
        }
    }
    // The current of the phase symmetry through the frontier of a domain of
    // solved levels vanishes (Thm 3.15 with EL = 0 inside).
    let per_level = slab.torus().level_size() * 6;
    let domain: Vec<bool> = (0..slab.cell_count())
        .map(|c| (10..=200).contains(&(c / per_level)))
        .collect();
    let balance = noether_balance::<Euclidean<2>, _, _, 2>(&slab, &lag, &y, &domain, charge).expect("balance");
    assert!(
        balance.current.abs() < 1e-12 * balance.scale,
        "current through the frontier: {balance:?}"
    );
    // The unsolved Cauchy levels are not critical: the check can fail.
    let el0 = euler_lagrange::<Euclidean<2>, _, _, 2>(&slab, &lag, &y, slab.vertex_index(2, 0)).expect("EL");
    assert!(el0.amax() > 1e-6);
}

#[test]
fn results_are_identical_for_one_and_two_threads() {
    let run = |threads: usize| {
        on_threads(threads, || {
            let mut m = complex_field_marcher(8);
            for _ in 0..40 {
                m.step().expect("level");
            }
            m.level_values(m.top_level()).expect("top level").to_vec()
        })
    };
    let one = run(1);
    let two = run(2);
    assert!(
        one.iter()
            .zip(&two)
            .all(|(a, b)| a[0].to_bits() == b[0].to_bits() && a[1].to_bits() == b[1].to_bits())
    );
}

/// A Lagrangian that does not see the future vertex: its Legendre map is singular.
struct Blind;
impl DiscreteLagrangian<Euclidean<1>, 1> for Blind {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[SVector<D, 1>]) -> D {
        y[0][0] * y[0][0]
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    let torus = CfkTorus::new(2, &[4]).expect("torus");
    let level = vec![SVector::<f64, 1>::from_element(1.0); 4];
    let err = CauchyMarcher::new(
        Blind,
        torus.clone(),
        0,
        &[level.clone(), level.clone()],
        CauchyOptions::default(),
    )
    .err()
    .expect("too few Cauchy levels");
    assert!(err.to_string().contains("Cauchy data levels"), "{err}");
    let mut bad = level.clone();
    bad[2][0] = f64::NAN;
    let err = CauchyMarcher::new(
        Blind,
        torus.clone(),
        0,
        &[level.clone(), level.clone(), bad, level.clone()],
        CauchyOptions::default(),
    )
    .err()
    .expect("NaN data");
    assert!(err.to_string().contains("non-finite"), "{err}");
    let data = vec![level.clone(); 4];
    let mut m = CauchyMarcher::new(Blind, torus, 0, &data, CauchyOptions::default()).expect("marcher");
    // ∂L/∂y_Δv = 0: Leg_v does not depend on the unknown.
    let err = m.step().expect_err("singular Legendre map");
    assert!(err.to_string().contains("singular Legendre map"), "{err}");
    assert!(err.to_string().contains("vertex 0 of level 2"), "{err}");
    assert_eq!(m.level(), 2, "a failed level leaves the marcher where it was");
    assert!(CfkTorus::new(2, &[2]).is_err(), "a window too small for a star");
}

#[test]
fn flow_marcher_on_a_window_agrees_with_the_ring_marcher() {
    let mut ring = complex_field_marcher(6);
    let torus = ring.torus().clone();
    let levels = 20;
    let window = CfkSlab::new(torus.clone(), 0, levels).expect("window");
    let size = torus.level_size();
    let mut values = vec![SVector::<f64, 2>::zeros(); window.vertex_count()];
    let mut known = vec![false; window.vertex_count()];
    for w in 0..6 {
        let data = ring.level_values(w).expect("Cauchy data");
        values[w as usize * size..(w as usize + 1) * size].copy_from_slice(data);
        known[w as usize * size..(w as usize + 1) * size]
            .iter_mut()
            .for_each(|k| *k = true);
    }
    // Start every unknown from its level-below neighbour (a rough guess).
    for v in 6 * size..values.len() {
        values[v] = values[v - 3 * size];
    }
    let lag = AffineWave::<3, 2> {
        dx: 0.5,
        dt: 0.2,
        mass2: 1.0,
        quartic: 0.3,
    };
    let mut flow = FlowMarcher::<_, Euclidean<2>, _, 2>::new(&window, lag, values, known, CauchyOptions::default())
        .expect("marcher");
    let identity = permutation(3, 0);
    for w in 3..levels - 4 {
        let batch: Vec<(usize, usize)> = (0..size)
            .map(|i| {
                (
                    window.vertex_index(w, i),
                    window.vertex_index(w + 3, torus.offset_index(i, &identity, 3, 1)),
                )
            })
            .collect();
        flow.solve_batch(&batch).expect("level");
        ring.step().expect("level");
    }
    let mut worst: f64 = 0.0;
    for w in 6..levels {
        let a = ring.level_values(w as i64);
        if let Some(a) = a {
            for i in 0..size {
                worst = worst.max((a[i] - flow.values()[window.vertex_index(w, i)]).amax());
            }
        }
    }
    assert!(worst < 1e-13, "flow and ring marchers differ by {worst:e}");
    // Errors name the vertex: a solved unknown, a flow outside the star, an unknown star.
    let v = window.vertex_index(3, 0);
    let err = flow.solve(v, window.vertex_index(6, 1)).expect_err("already known");
    assert!(err.to_string().contains("already known"), "{err}");
    let top = window.vertex_index(levels - 1, 7); // v + e₀ + e₁
    let err = flow
        .solve(window.vertex_index(levels - 4, 0), window.vertex_index(levels - 1, 2))
        .expect_err("no common cell");
    assert!(err.to_string().contains("does not admit"), "{err}");
    let err = flow
        .solve(window.vertex_index(levels - 3, 0), top)
        .expect_err("star not known");
    assert!(err.to_string().contains("not yet known"), "{err}");
}
