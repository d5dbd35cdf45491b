//! Forced Noether theorems for the SE(3) beam (seed 000 §3.1.4, Thm 3.4,
//! §4.1.4, Thm 4.3; note 000 §8, §12): with discrete forces F^k the
//! momentum maps carry the forces, J^{k,F} = Ad*_{g_k⁻¹}(g_k⁻¹D_kℒ + F̄^k),
//! and on a solution of the forced DCEL the time-evolution momentum
//!
//! 𝖩^F(j) := −Σ_a (J^{1,F} + J^{3,F})(△_a^j) = Σ_a J^{2,F}(△_a^{j−1})
//!
//! changes from row to row by the cells' impulse,
//! 𝖩^F(j + 1) − 𝖩^F(j) = Σ_a Σ_k J^{k,F}(△_a^j) = Σ_a [𝔇 + 𝔉](△_a^j),
//! 𝔇 = Σ_k Ad*_{g_k⁻¹}g_k⁻¹D_kℒ (zero for the symmetries of ℒ, local
//! Noether (36)), 𝔉 = Σ_k Ad*_{g_k⁻¹}F̄^k (the forcing's work on the
//! generators). Under the orthogonality condition (40), 𝔉 = 0, and the
//! forced momentum is conserved (Thms 3.4, 4.3).
//!
//! Bounds: the row balance is a sum of ~3A currents each exact to a few
//! ulps, with the solves converged to round-off: 1e-12 of the currents.

use nalgebra::SVector;
use veselov::ad::Scalar;
use veselov::complex::{SpacetimeLattice, TopCell, TopCells};
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000};
use veselov::field::cauchy::CauchyOptions;
use veselov::field::cell::{DiscreteLagrangian, exact_gradient, vertex_force};
use veselov::field::fibre::RigidMotions;
use veselov::field::variational::{VertexClass, classify};
use veselov::lie::{SE3, se3};
use veselov::models::beam::{BeamDensity, CayleyBeam, E6, beam_lagrangian, left_generators};

use crate::beam_evolution::{DS, DT, full_field, initial_rows, properties};

type V6 = SVector<f64, 6>;

/// The beam with an extra internal force pair on each cell's space edge:
/// F̄³ = −½ΔsΔt c ⊙ (η − E6) at vertex 3 (body frame), and at vertex 1 the
/// reaction F̄¹ = −Ad*_{g₃⁻¹g₁} F̄³, so that
/// Ad*_{g₁⁻¹}F̄¹ + Ad*_{g₃⁻¹}F̄³ = 0: the orthogonality condition (40)
/// (seed 000 §4.1.4, with its erratum F̄³) for every left translation. Not
/// the gradient of a potential: a non-variational force.
struct InternalPair {
    beam: CayleyBeam,
    c: [f64; 6],
}

impl InternalPair {
    fn third<D: Scalar>(&self, y: &[SE3<D>]) -> SVector<D, 6> {
        let ds = self.beam.ds();
        let half = 0.5 * ds * self.beam.dt();
        match se3::cay_inv(&y[0].between(&y[2])) {
            Ok(x) => SVector::from_fn(|k, _| (x[k] * (1.0 / ds) - E6[k]) * (-self.c[k] * half)),
            Err(_) => SVector::from_element(D::from(f64::NAN)),
        }
    }
}

impl DiscreteLagrangian<RigidMotions, 6> for InternalPair {
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SE3<D>]) -> D {
        self.beam.cell_lagrangian(cell, y)
    }
    fn depends(&self, cell: &TopCell, l: usize, k: usize) -> bool {
        <CayleyBeam as DiscreteLagrangian<RigidMotions, 6>>::depends(&self.beam, cell, l, k)
    }
    fn analytic_gradients(&self, cell: &TopCell, y: &[SE3<f64>], out: &mut [V6]) -> bool {
        self.beam.analytic_gradients(cell, y, out)
    }
    fn has_forces(&self) -> bool {
        true
    }
    fn has_force_at(&self, l: usize) -> bool {
        l != 1
    }
    fn cell_force<D: Scalar>(&self, _cell: &TopCell, y: &[SE3<D>], l: usize) -> SVector<D, 6> {
        let f3 = self.third(y);
        match l {
            0 => -(se3::ad_star_matrix(&y[2].between(&y[0])) * f3),
            2 => f3,
            _ => SVector::from_element(D::zero()),
        }
    }
}

/// Per row j of cells: (𝖩^F from the row's lower nodes, 𝖩^F through its
/// upper nodes, 𝔇, 𝔉, the size of the currents), for any forced split
/// Lagrangian marched in time.
struct RowMomenta {
    lower: V6,
    upper: V6,
    defect: V6,
    forcing: V6,
    scale: f64,
}

fn row_momenta<L: DiscreteLagrangian<RigidMotions, 6>>(evo: &Evolution000<RigidMotions, L, 6>) -> RowMomenta {
    let mut m = RowMomenta {
        lower: V6::zeros(),
        upper: V6::zeros(),
        defect: V6::zeros(),
        forcing: V6::zeros(),
        scale: 0.0,
    };
    evo.for_each_cell(|_, cell, y| {
        let lag = evo.lagrangian();
        for k in 0..3 {
            let x = left_generators(&y[k]).transpose();
            let j = x * exact_gradient::<RigidMotions, L, 6>(lag, cell, y, k);
            let f = x * vertex_force::<RigidMotions, L, 6>(lag, cell, y, k);
            if k == 1 {
                m.upper += j + f;
            } else {
                m.lower -= j + f;
            }
            m.defect += j;
            m.forcing += f;
            m.scale += j.amax() + f.amax();
        }
    });
    m
}

/// Marches `evo` over `levels` rows; returns, per row of cells, its momenta.
fn march<L: DiscreteLagrangian<RigidMotions, 6>>(
    mut evo: Evolution000<RigidMotions, L, 6>,
    levels: usize,
) -> Vec<RowMomenta> {
    let mut rows = vec![row_momenta(&evo)];
    for _ in 1..levels {
        let report = evo.step().expect("step");
        assert!(report.max_relative_residual <= 1e-12, "{report:?}");
        rows.push(row_momenta(&evo));
    }
    rows
}

fn free<L: DiscreteLagrangian<RigidMotions, 6>>(lag: L, a_max: usize) -> Evolution000<RigidMotions, L, 6> {
    let (g0, g1) = initial_rows(a_max);
    Evolution000::new(
        Direction::Time,
        lag,
        &g0,
        &g1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("evolution")
}

/// (largest |𝖩^F(j+1) − 𝖩^F(j) − impulse(j)| over the components `comps`
/// relative to the currents, largest relative change of 𝖩^F over the run,
/// largest relative total forcing impulse).
fn balance(rows: &[RowMomenta], comps: &[usize], impulse: impl Fn(&RowMomenta) -> V6) -> (f64, f64, f64) {
    let scale = rows.iter().map(|r| r.scale).fold(0.0, f64::max);
    let (mut worst, mut change, mut total): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let mut forcing = V6::zeros();
    for (j, r) in rows.iter().enumerate().skip(1) {
        // Row j's lower nodes are row j − 1's upper nodes (the forced DEL).
        let step = r.lower - rows[j - 1].lower - impulse(&rows[j - 1]);
        let through = r.lower - rows[j - 1].upper;
        forcing += rows[j - 1].forcing;
        for &k in comps {
            worst = worst.max(step[k].abs().max(through[k].abs()) / scale);
            change = change.max((r.lower[k] - rows[0].lower[k]).abs() / scale);
            total = total.max(forcing[k].abs() / scale);
        }
    }
    (worst, change, total)
}

/// Damping (a Lagrange–d'Alembert force violating (40)) and gravity (a
/// potential breaking rotations about E1, E3 and translations along E2):
/// the forced momentum changes by the cells' impulse 𝔇 + 𝔉 in every
/// component, and in the components gravity leaves symmetric (ω₂, v₁, v₃),
/// where 𝔇 = 0, by the forcing's impulse 𝔉 alone.
#[test]
fn damping_and_gravity_change_the_momentum_by_their_impulse() {
    let density = BeamDensity::new(properties())
        .with_gravity([0.0, -2.0, 0.0])
        .with_damping([0.3, 0.3, 0.6, 0.6, 0.6, 0.6])
        .expect("non-negative");
    let lag: CayleyBeam = beam_lagrangian(density, DT, DS).expect("lagrangian");
    let rows = march(free(lag, 5), 80);
    let all = [0, 1, 2, 3, 4, 5];
    let (worst, change, forcing) = balance(&rows, &all, |r| r.defect + r.forcing);
    let symmetric = [1, 3, 5];
    let (worst_f, _, _) = balance(&rows, &symmetric, |r| r.forcing);
    eprintln!(
        "damped beam under gravity: balance {worst:e}, with the forcing alone (ω₂, v₁, v₃) {worst_f:e}; \
         momentum change {change:e}, forcing impulse {forcing:e}"
    );
    assert!(worst <= 1e-12 && worst_f <= 1e-12, "balance {worst:e}, {worst_f:e}");
    assert!(
        change > 1e-2 && forcing > 1e-2,
        "the loads must act: {change:e}, {forcing:e}"
    );
    // The test can fail: without the forcing's impulse each row's balance
    // is off by that row's impulse (far above the bound).
    let (without, _, _) = balance(&rows, &symmetric, |r| r.defect);
    eprintln!("without the forcing's impulse: {without:e}");
    assert!(without > 1e-6, "the balance holds without the forces ({without:e})");
}

/// The covariant current through the frontier of the rectangle of cells
/// `[K, L] × [B, C]` of a field on seed000(N, A), with and without the
/// forces' currents: (𝒥^F, 𝒥, the size of its terms), for the spatial
/// momentum's six components.
fn rectangle_currents<L: DiscreteLagrangian<RigidMotions, 6>>(
    lat: &SpacetimeLattice,
    lag: &L,
    y: &[SE3<f64>],
    [k0, l0, b0, c0]: [usize; 4],
) -> (V6, V6, f64) {
    let a_cells = lat.space_nodes() - 1;
    let in_domain: Vec<bool> = (0..lat.cell_count())
        .map(|cell| (k0..=l0).contains(&(cell / a_cells)) && (b0..=c0).contains(&(cell % a_cells)))
        .collect();
    let class = classify(lat, &in_domain).expect("domain");
    let (mut forced, mut plain, mut scale) = (V6::zeros(), V6::zeros(), 0.0);
    let mut verts = [0; 3];
    for c in (0..lat.cell_count()).filter(|&c| in_domain[c]) {
        lat.cell_vertices(c, &mut verts);
        let (cell, yc) = (lat.cell(c), verts.map(|v| y[v]));
        for l in 0..3 {
            let x = left_generators(&yc[l]).transpose();
            let j = x * exact_gradient::<RigidMotions, L, 6>(lag, &cell, &yc, l);
            let f = x * vertex_force::<RigidMotions, L, 6>(lag, &cell, &yc, l);
            scale += j.amax() + f.amax();
            if class[verts[l]] == VertexClass::Frontier {
                forced += j + f;
                plain += j;
            }
        }
    }
    (forced, plain, scale)
}

/// Thms 3.4 and 4.3: an internal force pair satisfying the orthogonality
/// condition (40) changes the motion but not the covariant forced current:
/// 𝒥^F = 0 through the frontier of every rectangle (K ≥ 1: row 0 is data;
/// L ≤ N − 2: row N satisfies no equation), in all six components, and the
/// evolution momentum 𝖩^F is conserved; the current without the forces'
/// currents, 𝒥, does not vanish on rectangles whose sides cut the pairs.
#[test]
fn an_orthogonal_force_conserves_the_forced_momentum() {
    let beam: CayleyBeam = beam_lagrangian(BeamDensity::new(properties()), DT, DS).expect("lagrangian");
    let lag = InternalPair {
        beam,
        c: [0.3, 0.3, 0.2, 0.5, 0.5, 0.5],
    };
    let a_max = 5;
    let mut evo = free(lag, a_max);
    let mut rows = vec![vec![SE3::identity(); a_max + 1]; 2];
    evo.copy_level(1, &mut rows[0]);
    evo.copy_level(0, &mut rows[1]);
    let mut momenta = vec![row_momenta(&evo)];
    for _ in 1..40 {
        let report = evo.step().expect("step");
        assert!(report.max_relative_residual <= 1e-12, "{report:?}");
        let mut row = vec![SE3::identity(); a_max + 1];
        evo.copy_level(0, &mut row);
        rows.push(row);
        momenta.push(row_momenta(&evo));
    }
    // (40) on every cell: 𝔉 = 0; and 𝖩^F conserved row to row.
    let scale = momenta.iter().map(|r| r.scale).fold(0.0, f64::max);
    let orthogonality = momenta.iter().map(|r| r.forcing.amax()).fold(0.0, f64::max) / scale;
    let (evolution, change, _) = balance(&momenta, &[0, 1, 2, 3, 4, 5], |_| V6::zeros());
    let (lat, y) = full_field(Direction::Time, &rows);
    let lag = evo.lagrangian();
    let n = lat.time_nodes() - 1;
    let (mut worst, mut plain_worst): (f64, f64) = (0.0, 0.0);
    for rect in [
        [1, n - 2, 0, a_max - 1],
        [2, 20, 1, 3],
        [3, 9, 0, 2],
        [5, 30, 2, 4],
        [4, 4, 1, 1],
    ] {
        let (forced, plain, size) = rectangle_currents(&lat, lag, &y, rect);
        worst = worst.max(forced.amax() / size);
        plain_worst = plain_worst.max(plain.amax() / size);
    }
    eprintln!(
        "orthogonal internal force: (40) {orthogonality:e}; 𝖩^F row balance {evolution:e} (change {change:e}); \
         𝒥^F on rectangles {worst:e}, 𝒥 without the forces {plain_worst:e}"
    );
    assert!(orthogonality <= 1e-14, "(40) {orthogonality:e}");
    assert!(
        evolution <= 1e-12 && change <= 1e-12,
        "𝖩^F: balance {evolution:e}, change {change:e}"
    );
    assert!(worst <= 1e-12, "𝒥^F on rectangles {worst:e}");
    // The test can fail: without the forces' currents the rectangles' current is off.
    assert!(
        plain_worst > 1e-4,
        "the force must act on the rectangles ({plain_worst:e})"
    );
}
