//! The Lagrangian induced on the cubic lattice by the CFK → cubic map
//! (Casimiro–Rodrigo eq. (3.4), Props. 3.17–3.19, Remark 4.8; note 003
//! §1.5, test T11): on periodic windows of the same extent, a field's
//! action, Euler–Lagrange forms, Noether currents and Legendre maps are the
//! same computed on the cubes with L̄ (3.4) as on the simplices with L.
//!
//! Tolerance: each cubic quantity is the CFK one summed in another order
//! (n! simplices per cube), so they agree to round-off, 1e-13 relative to
//! the size of the terms; leaving one simplex of each cube out of (3.4)
//! changes them by O(1) (checked).

use crate::shared::SplitMix;
use nalgebra::{SMatrix, SVector, Vector3};
use veselov::ad::Scalar;
use veselov::complex::{CfkWindow, CubicWindow, TopCell, TopCells};
use veselov::field::cell::{DiscreteLagrangian, exact_gradient};
use veselov::field::discretize::{CfkNodes, SmoothDensity, VertexRule};
use veselov::field::fibre::{Euclidean, Fibre, Rotations};
use veselov::field::induced::CubicInduced;
use veselov::field::variational::{action, euler_lagrange_all, noether_balance};
use veselov::lie::SO3;

/// An O(2)-invariant wave on ℝ² over n-dimensional space–time (time last):
/// 𝓛 = ½(|φ_t|² − Σ_a |φ_{x_a}|²) − ¼|y|⁴.
#[derive(Clone, Copy)]
struct O2Wave;
impl<const N: usize> SmoothDensity<Euclidean<2>, 2, N> for O2Wave {
    fn density<D: Scalar>(&self, _x: &SVector<f64, N>, y: &SVector<D, 2>, j: &SMatrix<D, 2, N>) -> D {
        let mut l = D::zero();
        for a in 0..N {
            let sq = j[(0, a)] * j[(0, a)] + j[(1, a)] * j[(1, a)];
            l += if a + 1 == N { sq * 0.5 } else { -sq * 0.5 };
        }
        let r2 = y.dot(y);
        l - r2 * r2 * 0.25
    }
}

/// A rigid-body sigma model on 1+1 space–time, invariant under R ↦ QR.
#[derive(Clone, Copy)]
struct Sigma;
impl SmoothDensity<Rotations, 3, 2> for Sigma {
    fn density<D: Scalar>(&self, _x: &SVector<f64, 2>, _y: &SO3<D>, j: &SMatrix<D, 3, 2>) -> D {
        let (om, w) = (j.column(0), j.column(1));
        (w[0] * w[0] + w[1] * w[1] * 2.0 + w[2] * w[2] * 0.5 - om[0] * om[0] * 3.0 - om[1] * om[1] - om[2] * om[2])
            * 0.5
    }
}

/// A CFK Lagrangian with the simplices of one shape left out: (3.4) with a
/// term missing, to show the comparisons can fail.
struct Without<L>(L, usize);
impl<F: Fibre<M>, L: DiscreteLagrangian<F, M>, const M: usize> DiscreteLagrangian<F, M> for Without<L> {
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[F::Point<D>]) -> D {
        if cell.shape == self.1 {
            D::zero()
        } else {
            self.0.cell_lagrangian(cell, y)
        }
    }
}

fn factorial(n: usize) -> usize {
    (1..=n).product()
}

/// The comparisons of one Lagrangian on one window pair: returns the
/// largest relative differences of (action, EL, Legendre map, momentum).
fn compare<F, L, const M: usize>(
    cfk: &CfkWindow,
    cubic: &CubicWindow,
    lag: &L,
    induced: &CubicInduced<impl DiscreteLagrangian<F, M>>,
    y: &[F::Point<f64>],
) -> [f64; 4]
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
{
    let n = cfk.dimension();
    let per = factorial(n);
    let a_cfk = action::<F, _, _, M>(cfk, lag, y, 0..cfk.cell_count()).expect("action");
    let a_cub = action::<F, _, _, M>(cubic, induced, y, 0..cubic.cell_count()).expect("action");
    let el_cfk = euler_lagrange_all::<F, _, _, M>(cfk, lag, y).expect("EL");
    let el_cub = euler_lagrange_all::<F, _, _, M>(cubic, induced, y).expect("EL");
    let el = (0..y.len()).map(|v| (el_cfk[v] - el_cub[v]).amax()).fold(0.0, f64::max)
        / el_cfk.iter().map(|g| g.amax()).fold(0.0, f64::max);
    // Remark 4.8 with the flow Δv = v + (1, …, 1): Leg_v = the gradient at v
    // of S_v^Δ (CFK: the n! simplices based at v, position 0; cubic: the
    // cube based at v, corner 0), μ_v = Leg_v − EL_v.
    let (mut leg, mut mu, mut size): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let mut verts = [0; 16];
    let mut vals = Vec::new();
    for cube in 0..cubic.cell_count() {
        let k = cubic.cell_vertices(cube, &mut verts);
        let v = verts[0];
        vals.clear();
        vals.extend(verts[..k].iter().map(|&u| y[u]));
        let leg_cub = exact_gradient::<F, _, M>(induced, &cubic.cell(cube), &vals, 0);
        let mut leg_cfk = SVector::<f64, M>::zeros();
        for s in 0..per {
            let c = cube * per + s;
            let kk = cfk.cell_vertices(c, &mut verts);
            assert_eq!(verts[0], v, "the simplices of the cube based at v are based at v");
            vals.clear();
            vals.extend(verts[..kk].iter().map(|&u| y[u]));
            leg_cfk += exact_gradient::<F, _, M>(lag, &cfk.cell(c), &vals, 0);
        }
        leg = leg.max((leg_cub - leg_cfk).amax());
        mu = mu.max(((leg_cub - el_cub[v]) - (leg_cfk - el_cfk[v])).amax());
        size = size.max(leg_cfk.amax());
    }
    [(a_cfk - a_cub).abs() / a_cfk.abs(), el, leg / size, mu / size]
}

/// (3.4) numbers the cube's vertices as the CFK window does: the corner of
/// vertex a of (v, σ) in the cube is the CFK window's vertex a of the same
/// simplex.
fn check_corners(cfk: &CfkWindow, cubic: &CubicWindow) {
    let n = cfk.dimension();
    let per = factorial(n);
    let induced = CubicInduced::new((), n).expect("dimension");
    let (mut cube_verts, mut simplex_verts) = ([0; 16], [0; 16]);
    for cube in 0..cubic.cell_count() {
        cubic.cell_vertices(cube, &mut cube_verts);
        for s in 0..per {
            let (record, corners) = induced.simplex(&cubic.cell(cube), s);
            assert_eq!(record, cfk.cell(cube * per + s), "the simplex record");
            cfk.cell_vertices(cube * per + s, &mut simplex_verts);
            for (a, &c) in corners.iter().enumerate() {
                assert_eq!(cube_verts[c], simplex_verts[a], "cube {cube}, σ = {s}, vertex {a}");
            }
        }
    }
}

/// Prop. 3.17 (and (3.4) itself) and Remark 4.8 for a scalar doublet in 1+1
/// and 2+1 dimensions and a rotation field in 1+1, with the weight-order
/// dependent vertex rule Q_{v₀} (and Q_sym): equal actions, Euler–Lagrange
/// forms at every vertex, Legendre maps and momenta.
#[test]
fn induced_cubic_lagrangian_has_the_cfk_equations_and_legendre_maps() {
    let mut rng = SplitMix(17);
    let mut worst = [0.0_f64; 4];
    let mut record = |d: [f64; 4]| {
        for (w, x) in worst.iter_mut().zip(d) {
            *w = w.max(x);
        }
    };
    // 1+1 and 2+1, ℝ².
    let (cfk2, cub2) = (
        CfkWindow::periodic(&[4, 5]).expect("cfk"),
        CubicWindow::periodic(&[4, 5]).expect("cubic"),
    );
    check_corners(&cfk2, &cub2);
    let map2 = CfkNodes::<2>::space_time(0.3, 0.1).expect("nodes");
    let y2: Vec<SVector<f64, 2>> = (0..cfk2.vertex_count()).map(|_| rng.vec::<2>(1.0)).collect();
    for lag in [
        VertexRule::at_vertex(O2Wave, map2, 0).expect("u"),
        VertexRule::symmetric(O2Wave, map2),
    ] {
        let induced = CubicInduced::new(lag, 2).expect("n");
        record(compare::<Euclidean<2>, _, 2>(&cfk2, &cub2, &lag, &induced, &y2));
    }
    let (cfk3, cub3) = (
        CfkWindow::periodic(&[3, 3, 4]).expect("cfk"),
        CubicWindow::periodic(&[3, 3, 4]).expect("cubic"),
    );
    check_corners(&cfk3, &cub3);
    let map3 = CfkNodes::<3>::space_time(0.3, 0.1).expect("nodes");
    let y3: Vec<SVector<f64, 2>> = (0..cfk3.vertex_count()).map(|_| rng.vec::<2>(1.0)).collect();
    let lag3 = VertexRule::at_vertex(O2Wave, map3, 0).expect("u");
    let induced3 = CubicInduced::new(lag3, 3).expect("n");
    record(compare::<Euclidean<2>, _, 2>(&cfk3, &cub3, &lag3, &induced3, &y3));
    // 1+1, SO(3).
    let base = rng.rotation(3.0);
    let rots: Vec<SO3<f64>> = (0..cfk2.vertex_count())
        .map(|_| base.compose(&rng.rotation(0.3)))
        .collect();
    let sigma = VertexRule::at_vertex(Sigma, map2, 0).expect("u");
    let induced_sigma = CubicInduced::new(sigma, 2).expect("n");
    record(compare::<Rotations, _, 3>(&cfk2, &cub2, &sigma, &induced_sigma, &rots));
    eprintln!(
        "CFK vs induced cubic: action {:e}, EL (3.17) {:e}, Legendre map (Remark 4.8) {:e}, momentum {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst.iter().all(|&w| w <= 1e-13), "{worst:?}");
    // The comparison can fail: (3.4) without the simplices of shape 1.
    let lag = VertexRule::at_vertex(O2Wave, map2, 0).expect("u");
    let wrong = CubicInduced::new(Without(lag, 1), 2).expect("n");
    let d = compare::<Euclidean<2>, _, 2>(&cfk2, &cub2, &lag, &wrong, &y2);
    assert!(d[1] > 1e-2 && d[2] > 1e-2, "a missing simplex passes: {d:?}");
}

/// Props. 3.18 and 3.19: the symmetries of L (rotations of the doublet,
/// y ↦ Qy; left rotations of the frame, R ↦ QR) are symmetries of L̄ — the
/// Noether identity of Thm 3.15 holds on the cubic window for any field —
/// and the Noether current and interior sum over a domain Ā of cubes equal
/// those over A = i⁻¹(Ā), the simplices they carry.
#[test]
fn induced_cubic_lagrangian_has_the_cfk_symmetries_and_currents() {
    let mut rng = SplitMix(23);
    let (cfk, cubic) = (
        CfkWindow::periodic(&[5, 4]).expect("cfk"),
        CubicWindow::periodic(&[5, 4]).expect("cubic"),
    );
    let map = CfkNodes::<2>::space_time(0.3, 0.1).expect("nodes");
    let per = 2;
    let (mut identity, mut current, mut size): (f64, f64, f64) = (0.0, 0.0, f64::INFINITY);
    for trial in 0..4 {
        // About 70 % of the cubes at random (with interior vertices and a
        // frontier: the current is not trivially zero).
        let cubes: Vec<bool> = (0..cubic.cell_count()).map(|_| rng.uniform() > 0.3).collect();
        assert!(cubes.iter().any(|&c| c) && !cubes.iter().all(|&c| c));
        let simplices: Vec<bool> = (0..cfk.cell_count()).map(|c| cubes[c / per]).collect();
        let y: Vec<SVector<f64, 2>> = (0..cfk.vertex_count()).map(|_| rng.vec::<2>(1.0)).collect();
        let lag = VertexRule::at_vertex(O2Wave, map, trial % 3).expect("u");
        let induced = CubicInduced::new(lag, 2).expect("n");
        let rotate = |y: &SVector<f64, 2>| SVector::<f64, 2>::new(-y[1], y[0]);
        let b_cub = noether_balance::<Euclidean<2>, _, _, 2>(&cubic, &induced, &y, &cubes, rotate).expect("cubic");
        let b_cfk = noether_balance::<Euclidean<2>, _, _, 2>(&cfk, &lag, &y, &simplices, rotate).expect("cfk");
        identity = identity.max(b_cub.relative_defect());
        current = current
            .max(((b_cub.current - b_cfk.current).abs() + (b_cub.interior - b_cfk.interior).abs()) / b_cfk.scale);
        size = size.min(b_cfk.current.abs() / b_cfk.scale);
        // The frame field under left rotations about each axis.
        let base = rng.rotation(3.0);
        let rots: Vec<SO3<f64>> = (0..cfk.vertex_count())
            .map(|_| base.compose(&rng.rotation(0.3)))
            .collect();
        let sigma = VertexRule::at_vertex(Sigma, map, 0).expect("u");
        let induced = CubicInduced::new(sigma, 2).expect("n");
        for axis in 0..3 {
            let e = Vector3::from_fn(|i, _| f64::from(u8::from(i == axis)));
            // Left rotation exp(tê)R in the chart R·exp(ξ̂): ξ = Rᵀe.
            let generator = |r: &SO3<f64>| r.matrix().transpose() * e;
            let b_cub = noether_balance::<Rotations, _, _, 3>(&cubic, &induced, &rots, &cubes, generator).expect("c");
            let b_cfk = noether_balance::<Rotations, _, _, 3>(&cfk, &sigma, &rots, &simplices, generator).expect("s");
            identity = identity.max(b_cub.relative_defect());
            current = current
                .max(((b_cub.current - b_cfk.current).abs() + (b_cub.interior - b_cfk.interior).abs()) / b_cfk.scale);
            size = size.min(b_cfk.current.abs() / b_cfk.scale);
        }
    }
    eprintln!(
        "induced cubic: Noether identity (3.18) {identity:e}; currents over Ā vs i⁻¹(Ā) (3.19) {current:e} \
         (smallest current {size:e} of its terms)"
    );
    assert!(identity <= 1e-13 && current <= 1e-13, "{identity:e} {current:e}");
    // The currents compared are not trivially zero (the fields are not critical).
    assert!(size > 1e-6, "a current is negligible ({size:e})");
    // The identity can fail: a field direction that is not a symmetry
    // (a shift of the doublet, broken by the quartic potential).
    let y: Vec<SVector<f64, 2>> = (0..cfk.vertex_count()).map(|_| rng.vec::<2>(1.0)).collect();
    let lag = VertexRule::at_vertex(O2Wave, map, 0).expect("u");
    let induced = CubicInduced::new(lag, 2).expect("n");
    let all = vec![true; cubic.cell_count()];
    let shift = |_: &SVector<f64, 2>| SVector::<f64, 2>::new(1.0, 0.0);
    let b = noether_balance::<Euclidean<2>, _, _, 2>(&cubic, &induced, &y, &all, shift).expect("cubic");
    let interior_only = b.interior.abs() / b.scale;
    eprintln!("a shift (not a symmetry): Noether identity defect {interior_only:e}");
    assert!(interior_only > 1e-6, "a broken symmetry passes ({interior_only:e})");
}
