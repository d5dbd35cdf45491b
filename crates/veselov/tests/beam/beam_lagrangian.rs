//! The beam's discrete Lagrangian on seed 000's triangles (note 000 §12,
//! §15): DCEL residuals against finite differences of the discrete action
//! under g → g·τ(ε e_k), the local Noether identity J¹ + J² + J³ = 0 for any
//! field, and the vector-space special case against the five-point wave
//! scheme (through the rolling-window evolution driver).

use nalgebra::{SVector, Vector3};
use veselov::complex::{SpacetimeLattice, TopCells};
use veselov::evolution::split::{DiagonalQuadratic, Difference, GroupIncrement, Increment, SplitLagrangian};
use veselov::field::cell::{DiscreteLagrangian, mixed_block_dual, vertex_gradient};
use veselov::field::fibre::{Euclidean, RigidMotions};
use veselov::field::variational::{action, euler_lagrange};
use veselov::lie::{CayleyMap, ExpMap, Retraction, SE3};
use veselov::models::beam::{BeamDensity, BeamLagrangian, BeamProperties, beam_lagrangian, left_generators, straight};

use crate::five_point;

/// A deterministic sequence in (−1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
    fn vec6(&mut self, size: f64) -> SVector<f64, 6> {
        SVector::from_fn(|_, _| size * self.next())
    }
}

fn density(gravity: bool) -> BeamDensity {
    let p = BeamProperties::from_diagonals([1.0, 1.5, 2.0, 3.0, 3.0, 3.0], [2.0, 2.5, 1.0, 5.0, 6.0, 8.0])
        .expect("positive");
    let d = BeamDensity::new(p);
    if gravity { d.with_gravity([0.3, -9.81, 0.5]) } else { d }
}

/// A random field near the straight beam: g_a^j = (I, (0,0,aΔs))·exp(x).
fn random_field(lat: &SpacetimeLattice, ds: f64, rng: &mut Lcg) -> Vec<SE3<f64>> {
    (0..lat.vertex_count())
        .map(|v| {
            let (a, _) = lat.node(v);
            straight(ds, a as usize).compose(&veselov::lie::se3::exp(&rng.vec6(0.4)))
        })
        .collect()
}

/// EL_v (the scatter of exact cell gradients) against central differences of
/// the whole discrete action under g_v → g_v·τ(ε e_k), at every vertex of a
/// 3 × 4 lattice (interior, both ends, the slaved row and column, corners).
fn dcel_matches_action<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(gravity: bool) {
    let (dt, ds) = (0.1, 0.2);
    let lag: BeamLagrangian<R> = beam_lagrangian(density(gravity), dt, ds).expect("lagrangian");
    let lat = SpacetimeLattice::seed000(3, 4).expect("lattice");
    let mut rng = Lcg(7);
    let y = random_field(&lat, ds, &mut rng);
    let all = 0..lat.cell_count();
    let s = |y: &[SE3<f64>]| action::<RigidMotions, _, _, 6>(&lat, &lag, y, all.clone()).expect("action");
    let h = 1e-5;
    let mut worst_fd: f64 = 0.0;
    for v in 0..lat.vertex_count() {
        let el = euler_lagrange::<RigidMotions, _, _, 6>(&lat, &lag, &y, v).expect("residual");
        let mut fd = SVector::<f64, 6>::zeros();
        for k in 0..6 {
            let e = SVector::<f64, 6>::from_fn(|i, _| if i == k { h } else { 0.0 });
            let mut yp = y.clone();
            yp[v] = y[v].compose(&R::tau(&e));
            let mut ym = y.clone();
            ym[v] = y[v].compose(&R::tau(&(-e)));
            fd[k] = (s(&yp) - s(&ym)) / (2.0 * h);
        }
        // Central differences of an O(1)-curvature action: error ~ h² ≈ 1e-10
        // relative to the terms (|S| is the scale of the summed cells).
        let scale = 1.0 + el.amax() + s(&y).abs();
        worst_fd = worst_fd.max((el - fd).amax() / scale);
        assert!(
            (el - fd).amax() <= 1e-7 * scale,
            "vertex {v} {:?}: EL {el:?} vs FD {fd:?}",
            lat.node(v)
        );
    }
    eprintln!("{}: worst |EL − FD| / scale = {worst_fd:e}", std::any::type_name::<R>());
    // The corner (N, A) is in no triangle: its residual is exactly zero.
    let corner = lat.vertex_at(4, 3).expect("corner");
    assert_eq!(
        euler_lagrange::<RigidMotions, _, _, 6>(&lat, &lag, &y, corner).expect("residual"),
        SVector::<f64, 6>::zeros()
    );
}

#[test]
fn dcel_residual_is_the_derivative_of_the_action_cayley() {
    dcel_matches_action::<CayleyMap>(false);
    dcel_matches_action::<CayleyMap>(true);
}

#[test]
fn dcel_residual_is_the_derivative_of_the_action_exp() {
    dcel_matches_action::<ExpMap>(false);
    dcel_matches_action::<ExpMap>(true);
}

/// The split Lagrangian's closed-form gradients (increment derivatives and
/// ∇K, ∇Φ, ∇Π) against the dual pass over the whole cell Lagrangian, at
/// every vertex of random triangles: exponential and Cayley increments with
/// and without gravity, and the vector-space difference.
fn closed_form_gradients_match_the_dual_pass<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
    gravity: bool,
) {
    let (dt, ds) = (0.1, 0.2);
    let lag: BeamLagrangian<R> = beam_lagrangian(density(gravity), dt, ds).expect("lagrangian");
    let lat = SpacetimeLattice::seed000(3, 4).expect("lattice");
    let mut rng = Lcg(11);
    let y = random_field(&lat, ds, &mut rng);
    let (mut worst, mut worst_block, mut worst_fd) = (0.0_f64, 0.0_f64, 0.0_f64);
    let mut verts = [0; 16];
    for c in 0..lat.cell_count() {
        let k = lat.cell_vertices(c, &mut verts);
        let values: Vec<SE3<f64>> = verts[..k].iter().map(|&v| y[v]).collect();
        let cell = lat.cell(c);
        let mut exact = [SVector::<f64, 6>::zeros(); 3];
        assert!(lag.analytic_gradients(&cell, &values, &mut exact));
        for (l, g) in exact.iter().enumerate() {
            let reference = vertex_gradient::<RigidMotions, _, 6>(&lag, &cell, &values, l).1;
            worst = worst.max((g - reference).amax() / reference.amax().max(1.0));
        }
        // Every Jacobian block ∂(∂ℒ/∂y_a)/∂y_b, the diagonal ones included.
        for a in 0..3 {
            for b in 0..3 {
                let (g, block) = lag.analytic_block(&cell, &values, a, b).expect("closed form");
                let (g_ref, block_ref) = mixed_block_dual::<RigidMotions, _, 6>(&lag, &cell, &values, a, b);
                worst_block = worst_block.max((g - g_ref).amax() / g_ref.amax().max(1.0));
                worst_block = worst_block.max((block - block_ref).amax() / block_ref.amax().max(1.0));
                // And against central differences of the closed-form
                // gradient under y_b → y_b·exp(±h e_j).
                let h = 1e-6;
                let mut fd = nalgebra::SMatrix::<f64, 6, 6>::zeros();
                for j in 0..6 {
                    let mut e = SVector::<f64, 6>::zeros();
                    e[j] = h;
                    let moved = |sign: f64| {
                        let mut v = values.clone();
                        v[b] = v[b].compose(&veselov::lie::se3::exp(&(e * sign)));
                        let mut out = [SVector::<f64, 6>::zeros(); 3];
                        assert!(lag.analytic_gradients(&cell, &v, &mut out));
                        out[a]
                    };
                    fd.set_column(j, &((moved(1.0) - moved(-1.0)) / (2.0 * h)));
                }
                worst_fd = worst_fd.max((fd - block).amax() / block.amax().max(1.0));
            }
        }
    }
    assert!(worst <= 1e-13, "closed form vs dual pass: {worst:.1e}");
    assert!(
        worst_block <= 1e-13,
        "closed-form blocks vs nested duals: {worst_block:.1e}"
    );
    // Central differences: O(h²) ≈ 1e-12 truncation plus ε/h ≈ 1e-10 round-off.
    assert!(worst_fd <= 1e-8, "blocks vs central differences: {worst_fd:.1e}");
}

#[test]
fn closed_form_gradients_are_the_dual_pass_gradients() {
    closed_form_gradients_match_the_dual_pass::<CayleyMap>(false);
    closed_form_gradients_match_the_dual_pass::<CayleyMap>(true);
    closed_form_gradients_match_the_dual_pass::<ExpMap>(false);
    closed_form_gradients_match_the_dual_pass::<ExpMap>(true);
    let lag = SplitLagrangian::<Difference, _>::new(
        DiagonalQuadratic::<2> {
            inertia: [1.0, 2.0],
            stiffness: [3.0, 0.5],
            reference: [0.1, -0.2],
        },
        0.1,
        0.3,
    )
    .expect("lagrangian");
    let lat = SpacetimeLattice::seed000(2, 3).expect("lattice");
    let y = [
        SVector::<f64, 2>::new(0.3, -0.1),
        SVector::<f64, 2>::new(0.5, 0.2),
        SVector::<f64, 2>::new(-0.4, 0.9),
    ];
    let cell = lat.cell(0);
    let mut exact = [SVector::<f64, 2>::zeros(); 3];
    assert!(DiscreteLagrangian::<Euclidean<2>, 2>::analytic_gradients(
        &lag, &cell, &y, &mut exact
    ));
    for (l, g) in exact.iter().enumerate() {
        let reference = vertex_gradient::<Euclidean<2>, _, 2>(&lag, &cell, &y, l).1;
        assert!(
            (g - reference).amax() <= 1e-14 * reference.amax().max(1.0),
            "position {l}"
        );
    }
}

/// J¹ + J² + J³ = 0 on every triangle of random fields (SE(3)-invariant
/// beam, no gravity), relative to Σ|J^k|; with gravity along E2 only
/// rotations about E2 and translations survive, and their components still
/// balance.
#[test]
fn local_noether_on_every_triangle() {
    let (dt, ds) = (0.05, 0.1);
    let lat = SpacetimeLattice::seed000(4, 5).expect("lattice");
    let mut rng = Lcg(11);
    let mut worst: f64 = 0.0;
    for gravity in [false, true] {
        let d = if gravity {
            density(false).with_gravity([0.0, -9.81, 0.0])
        } else {
            density(false)
        };
        let lag: BeamLagrangian<CayleyMap> = beam_lagrangian(d, dt, ds).expect("lagrangian");
        for _ in 0..5 {
            let y = random_field(&lat, ds, &mut rng);
            let mut verts = [0; 3];
            for c in 0..lat.cell_count() {
                lat.cell_vertices(c, &mut verts);
                let cell = lat.cell(c);
                let yc = [y[verts[0]], y[verts[1]], y[verts[2]]];
                let mut sum = SVector::<f64, 6>::zeros();
                let mut scale = 0.0;
                for l in 0..3 {
                    let g = vertex_gradient::<RigidMotions, _, 6>(&lag, &cell, &yc, l).1;
                    let j = left_generators(&yc[l]).transpose() * g;
                    sum += j;
                    scale += j.amax();
                }
                // Symmetries: all of se(3) without gravity; ω₂, v₁ and v₃ with gravity along E2.
                let comps: &[usize] = if gravity { &[1, 3, 5] } else { &[0, 1, 2, 3, 4, 5] };
                let defect = comps.iter().map(|&k| sum[k].abs()).fold(0.0, f64::max) / scale;
                worst = worst.max(defect);
                if gravity {
                    // Rotations about E1 do not preserve gravity along E2: the identity must fail there.
                    assert!(sum[0].abs() > 1e-8 * scale || sum[2].abs() > 1e-8 * scale);
                }
            }
        }
    }
    eprintln!("local Noether: worst relative defect {worst:e}");
    assert!(worst <= 1e-13, "local Noether defect {worst:e}");
}

/// The increments invert the retraction (ξ = τ⁻¹(g₁⁻¹g₂) for g₂ = g₁τ(ξ)) and
/// a cut-locus rotation yields a non-finite Lagrangian, not a silent value.
#[test]
fn increments_and_cut_locus() {
    let g = straight(0.1, 3).compose(&veselov::lie::se3::exp(&SVector::from([0.2, -0.1, 0.3, 0.0, 0.1, 0.2])));
    let x = SVector::<f64, 6>::from([0.3, 0.2, -0.5, 0.1, 0.0, 0.4]);
    type Cay = GroupIncrement<CayleyMap>;
    let back =
        <Cay as Increment<RigidMotions, 6>>::increment(&g, &<Cay as Increment<RigidMotions, 6>>::advance(&g, &x))
            .expect("small rotation");
    assert!((back - x).amax() < 1e-14);
    let flip = SE3::new(
        veselov::lie::so3::exp(&Vector3::new(std::f64::consts::PI, 0.0, 0.0)),
        Vector3::zeros(),
    );
    let lag: BeamLagrangian<CayleyMap> = beam_lagrangian(density(false), 0.1, 0.1).expect("lagrangian");
    let lat = SpacetimeLattice::seed000(1, 1).expect("lattice");
    let y = vec![SE3::identity(), SE3::identity(), flip, SE3::identity()];
    let s = action::<RigidMotions, _, _, 6>(&lat, &lag, &y, 0..1).expect("action");
    assert!(
        s.is_nan(),
        "a rotation by π between neighbours must not give a finite action: {s}"
    );
    assert!(beam_lagrangian::<CayleyMap>(density(false), 0.0, 0.1).is_err());
}

/// The vector-space case: K = ½ξ², Φ = ½c²η² on ℝ¹ is the wave equation
/// and its time evolution (through the rolling window, Dirichlet ends given
/// level by level) is the five-point scheme
/// u^{j+1} = 2u^j − u^{j−1} + (cΔt/Δs)²(u_{a+1} − 2u_a + u_{a−1}).
#[test]
fn vector_space_case_is_the_five_point_wave_scheme() {
    let (dt, ds, c2) = (0.04, 0.1, 1.5);
    let wave = DiagonalQuadratic::<1> {
        inertia: [1.0],
        stiffness: [c2],
        reference: [0.0],
    };
    let lag = SplitLagrangian::<Difference, _>::new(wave, dt, ds).expect("lagrangian");
    let u0 = move |j: usize, a: usize| {
        let (t, s) = (j as f64 * dt, a as f64 * ds);
        (2.0 * s).sin() * (0.7 * t).cos() + 0.2 * (s - 0.3 * t).cos()
    };
    let r = c2 * dt * dt / (ds * ds);
    let worst = five_point::worst_difference_from_five_point(lag, u0, 16, 200, r, 0.0);
    assert!(
        worst < 1e-12,
        "time evolution differs from the five-point scheme by {worst:e}"
    );
}
