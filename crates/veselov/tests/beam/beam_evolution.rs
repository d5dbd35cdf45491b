//! Time and space evolution of the SE(3) beam on seed 000's lattice (note
//! 000 §11, §14, §16): evolution momentum maps conserved under matching
//! boundary conditions, the flux law (61) where they are not, the covariant
//! momentum map 𝒥 = 0 on rectangles of solutions, and a bounded energy over
//! 10⁴ levels.

use nalgebra::{SMatrix, SVector};

use crate::checkpoints::check_checkpoint;
use veselov::complex::{SpacetimeLattice, TopCells};
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000, EvolutionMomentum};
use veselov::field::cauchy::CauchyOptions;
use veselov::field::fibre::RigidMotions;
use veselov::field::variational::{euler_lagrange, noether_balance};
use veselov::lie::{CayleyMap, Retraction, SE3, se3};
use veselov::models::beam::{
    BeamDensity, BeamProperties, CayleyBeam, StepLimit, beam_lagrangian, left_generators, straight,
};

pub(crate) type Beam = Evolution000<RigidMotions, CayleyBeam, 6>;

pub(crate) const DT: f64 = 0.05;
pub(crate) const DS: f64 = 0.1;

/// Wave speeds 1, 1, 0.77, 1, 1, 1 (time Courant number ≈ 0.5 at DT, DS; the
/// shear–rotation term raises it from 0.500 to 0.501).
pub(crate) fn properties() -> BeamProperties {
    BeamProperties::from_diagonals([0.5, 0.5, 1.0, 1.0, 1.0, 1.0], [0.5, 0.5, 0.6, 1.0, 1.0, 1.0]).expect("positive")
}

pub(crate) fn lagrangian(dt: f64, ds: f64) -> CayleyBeam {
    beam_lagrangian(BeamDensity::new(properties()), dt, ds).expect("lagrangian")
}

pub(crate) fn wave(a: usize, phase: f64) -> SVector<f64, 6> {
    let s = a as f64;
    SVector::from([
        0.3 * (0.7 * s + phase).sin(),
        -0.2 * (0.5 * s).cos(),
        0.25 * (0.9 * s - phase).sin(),
        0.1 * (0.4 * s).cos(),
        -0.15 * (0.6 * s + 0.3).sin(),
        0.05 * (0.8 * s).cos(),
    ])
}

/// A bent, twisted, moving beam: g_a^0 = straight·exp(0.1 w_a), g_a^1 = g_a^0·cay(Δt ξ_a).
pub(crate) fn initial_rows(a_max: usize) -> (Vec<SE3<f64>>, Vec<SE3<f64>>) {
    let g0: Vec<_> = (0..=a_max)
        .map(|a| straight(DS, a).compose(&se3::exp(&(wave(a, 0.0) * 0.1))))
        .collect();
    let g1 = g0
        .iter()
        .enumerate()
        .map(|(a, g)| g.compose(&CayleyMap::tau(&(wave(a, 1.0) * DT))))
        .collect();
    (g0, g1)
}

/// The free–free beam in time evolution (zero traction at both ends) from
/// the rows `g0`, `g1`, at Δt = DT, Δs = DS.
pub(crate) fn free_beam(g0: &[SE3<f64>], g1: &[SE3<f64>]) -> veselov::Result<Beam> {
    Beam::new(
        Direction::Time,
        lagrangian(DT, DS),
        g0,
        g1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
}

pub(crate) fn basis(k: usize) -> SVector<f64, 6> {
    SVector::from_fn(|i, _| if i == k { 1.0 } else { 0.0 })
}

/// Runs an evolution for `levels` steps, recording every level (c = 0..=C)
/// and 𝖩⁺, 𝖩⁻ of every cell level.
pub(crate) fn run(mut evo: Beam, levels: usize) -> (Vec<Vec<SE3<f64>>>, Vec<EvolutionMomentum<6>>) {
    let c = evo.cross();
    let mut rows = vec![vec![SE3::identity(); c + 1]; 2];
    evo.copy_level(1, &mut rows[0]);
    evo.copy_level(0, &mut rows[1]);
    let m = evo.evolution_momentum(left_generators);
    let mut momenta = vec![m];
    for _ in 1..levels {
        let report = evo.step().expect("step");
        assert!(report.max_relative_residual <= 1e-12, "{report:?}");
        let mut row = vec![SE3::identity(); c + 1];
        evo.copy_level(0, &mut row);
        rows.push(row);
        let m = evo.evolution_momentum(left_generators);
        momenta.push(m);
    }
    (rows, momenta)
}

/// The recorded levels as a field on seed000(N, A) (vertex j·(A + 1) + a).
pub(crate) fn full_field(direction: Direction, rows: &[Vec<SE3<f64>>]) -> (SpacetimeLattice, Vec<SE3<f64>>) {
    let (levels, cross) = (rows.len() - 1, rows[0].len() - 1);
    let lat = match direction {
        Direction::Time => SpacetimeLattice::seed000(levels, cross),
        Direction::Space => SpacetimeLattice::seed000(cross, levels),
    }
    .expect("lattice");
    let mut y = vec![SE3::identity(); lat.vertex_count()];
    for (l, row) in rows.iter().enumerate() {
        for (c, g) in row.iter().enumerate() {
            let (a, j) = match direction {
                Direction::Time => (c, l),
                Direction::Space => (l, c),
            };
            y[lat.vertex_at(a as i64, j as i64).expect("node")] = *g;
        }
    }
    (lat, y)
}

/// max over k and over rectangles [K, L] × [B, C] of |𝒥_k| / scale, with
/// 𝒥 from the core's Noether current (interior EL paired with the
/// generators, frontier current through the cells).
fn worst_rectangle_current(lat: &SpacetimeLattice, lag: &CayleyBeam, y: &[SE3<f64>], rects: &[[usize; 4]]) -> f64 {
    let (n, a_cells) = (lat.time_nodes() - 1, lat.space_nodes() - 1);
    let mut worst: f64 = 0.0;
    for &[k0, l0, b0, c0] in rects {
        assert!(l0 < n && c0 < a_cells);
        let in_domain: Vec<bool> = (0..lat.cell_count())
            .map(|cell| {
                let (j, a) = (cell / a_cells, cell % a_cells);
                (k0..=l0).contains(&j) && (b0..=c0).contains(&a)
            })
            .collect();
        for k in 0..6 {
            let b =
                noether_balance::<RigidMotions, _, _, 6>(lat, lag, y, &in_domain, |g| left_generators(g) * basis(k))
                    .expect("balance");
            worst = worst.max(b.current.abs() / b.scale);
            assert!(
                b.relative_defect() <= 1e-13,
                "Noether identity defect {:e}",
                b.relative_defect()
            );
        }
    }
    worst
}

fn relative_spread(momenta: &[EvolutionMomentum<6>]) -> (f64, f64) {
    let first = momenta[0].plus;
    let scale = momenta.iter().map(|m| m.scale).fold(0.0, f64::max);
    let spread = momenta.iter().map(|m| (m.plus - first).amax()).fold(0.0, f64::max) / scale;
    let plus_minus = momenta.iter().map(|m| (m.plus - m.minus).amax()).fold(0.0, f64::max) / scale;
    (spread, plus_minus)
}

/// Free–free beam (zero traction at both ends, the last node slaved):
/// 𝖩_𝖫 constant across levels, 𝖩⁺ = 𝖩⁻, 𝒥 = 0 on rectangles.
#[test]
fn time_evolution_with_zero_traction_conserves_the_momentum_map() {
    assert!(
        properties()
            .check_step(StepLimit::Time, DT, DS, false)
            .expect("within the limit")
            <= 0.51
    );
    let a_max = 6;
    let (g0, g1) = initial_rows(a_max);
    let evo = free_beam(&g0, &g1).expect("evolution");
    let (rows, momenta) = run(evo, 120);
    let (spread, pm) = relative_spread(&momenta);
    eprintln!("time evolution, zero traction: 𝖩_𝖫 spread {spread:e}, |𝖩⁺ − 𝖩⁻| {pm:e}");
    assert!(spread <= 1e-12 && pm <= 1e-12, "𝖩_𝖫 spread {spread:e}, 𝖩⁺ − 𝖩⁻ {pm:e}");
    // The slaved node carries no strain: λ_{A−1} = 0 ⇔ η_{A−1} = E6.
    let lag = lagrangian(DT, DS);
    let (lat, y) = full_field(Direction::Time, &rows);
    // K ≥ 1: row 0 is data, not a solution of the equations (no zero momentum in time).
    let rects = [[1, 5, 0, 5], [1, 118, 0, 5], [3, 40, 2, 4], [10, 11, 5, 5]];
    let worst = worst_rectangle_current(&lat, &lag, &y, &rects);
    eprintln!("time evolution, zero traction: worst |𝒥|/scale on rectangles {worst:e}");
    assert!(worst <= 1e-12, "𝒥 on rectangles {worst:e}");
    for j in 1..rows.len() - 1 {
        let v = lat.vertex_at(a_max as i64, j as i64).expect("slaved node");
        let el = euler_lagrange::<RigidMotions, _, _, 6>(&lat, &lag, &y, v).expect("residual");
        let eta = CayleyMap::tau_inv(&rows[j][a_max - 1].inverse().compose(&rows[j][a_max])).expect("small") / DS;
        assert!(
            el.amax() <= 1e-13 && (eta - basis(5)).amax() <= 1e-12,
            "slaved node {j}: {el:?} {eta:?}"
        );
    }
}

/// A prescribed time-dependent motion of the end a = 0 (free far end):
/// 𝖩_𝖫 is not conserved but obeys the flux law (61),
/// 𝖩⁺(j) − 𝖩⁻(j − 1) = −Ad*_{g⁻¹}(EL at (j, 0)), the driving end's reaction.
#[test]
fn time_evolution_with_a_driven_end_obeys_the_flux_law() {
    let a_max = 5;
    let (g0, g1) = initial_rows(a_max);
    let drive = SVector::<f64, 6>::from([0.0, 0.8, 0.0, 0.0, -0.2, 0.0]);
    let root0 = g0[0];
    let root = move |j: usize| root0.compose(&se3::exp(&(drive * (j as f64 * DT))));
    let evo = Beam::new(
        Direction::Time,
        lagrangian(DT, DS),
        &g0,
        &g1,
        EndCondition::Prescribed(Box::new(root)),
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("evolution");
    let (rows, momenta) = run(evo, 60);
    let lag = lagrangian(DT, DS);
    let (lat, y) = full_field(Direction::Time, &rows);
    let (mut worst, mut change): (f64, f64) = (0.0, 0.0);
    for j in 1..momenta.len() {
        let v = lat.vertex_at(0, j as i64).expect("end node");
        let el = euler_lagrange::<RigidMotions, _, _, 6>(&lat, &lag, &y, v).expect("residual");
        let flux = left_generators(&y[v]).transpose() * el;
        let scale = momenta[j].scale.max(momenta[j - 1].scale);
        worst = worst.max((momenta[j].plus - momenta[j - 1].minus + flux).amax() / scale);
        change = change.max((momenta[j].plus - momenta[0].plus).amax() / scale);
    }
    eprintln!("driven end: flux-law defect {worst:e}, 𝖩_𝖫 change {change:e}");
    assert!(worst <= 1e-12, "flux law defect {worst:e}");
    assert!(change > 1e-3, "a driven end must change 𝖩_𝖫 (change {change:e})");
    // B ≥ 1: the driven end's equations do not hold (they are the flux).
    let worst = worst_rectangle_current(&lat, &lag, &y, &[[1, 50, 1, 4], [5, 9, 1, 3]]);
    assert!(worst <= 1e-12, "𝒥 on rectangles {worst:e}");
}

/// Space evolution from the first two columns, zero momentum at t = 0 and
/// the slaved last row: 𝖩_𝖭 constant across columns, 𝒥 = 0 on rectangles.
#[test]
fn space_evolution_with_zero_momentum_conserves_the_momentum_map() {
    let (dt, ds) = (0.1, 0.05);
    assert!(
        properties()
            .check_step(StepLimit::Space, dt, ds, false)
            .expect("within the limit")
            < 1.0
    );
    let n = 10;
    let twist = SVector::<f64, 6>::from([0.05, 0.3, -0.1, 0.02, -0.1, 0.0]);
    let col0: Vec<SE3<f64>> = (0..=n).map(|j| se3::exp(&(twist * (j as f64 * dt)))).collect();
    let col1: Vec<SE3<f64>> = col0
        .iter()
        .enumerate()
        .map(|(j, g)| {
            let eta = basis(5) + wave(j, 0.5) * 0.05;
            g.compose(&CayleyMap::tau(&(eta * ds)))
        })
        .collect();
    let lag = beam_lagrangian(BeamDensity::new(properties()), dt, ds).expect("lagrangian");
    let evo = Beam::new(
        Direction::Space,
        lag,
        &col0,
        &col1,
        EndCondition::Natural,
        EndCondition::Natural,
        CauchyOptions::default(),
    )
    .expect("evolution");
    let (cols, momenta) = run(evo, 12);
    let (spread, pm) = relative_spread(&momenta[1..]);
    eprintln!("space evolution, zero momentum: 𝖩_𝖭 spread {spread:e}, |𝖩⁺ − 𝖩⁻| {pm:e}");
    assert!(spread <= 1e-12 && pm <= 1e-12, "𝖩_𝖭 spread {spread:e}, 𝖩⁺ − 𝖩⁻ {pm:e}");
    let lag = beam_lagrangian(BeamDensity::new(properties()), dt, ds).expect("lagrangian");
    let (lat, y) = full_field(Direction::Space, &cols);
    let worst = worst_rectangle_current(&lat, &lag, &y, &[[0, 9, 1, 10], [2, 6, 3, 8], [0, 0, 1, 1]]);
    eprintln!("space evolution: worst |𝒥|/scale on rectangles {worst:e}");
    assert!(worst <= 1e-12, "𝒥 on rectangles {worst:e}");
    // The slaved row: μ = 0 ⇔ g^N = g^{N−1} on every computed column.
    for col in &cols[2..] {
        let d = col[n - 1].inverse().compose(&col[n]);
        assert!((d.translation().amax() + (d.rotation().matrix() - SMatrix::<f64, 3, 3>::identity()).amax()) <= 1e-13);
    }
}

/// E_𝖫 = Δs Σ_a (K + Φ) over 10⁴ levels of a small free–free beam: bounded,
/// no drift (the scheme is symplectic; backward error analysis bounds the
/// energy error by O(Δt²) for exponentially long times).
#[test]
fn time_evolution_energy_is_bounded_over_ten_thousand_levels() {
    let a_max = 3;
    let (g0, g1) = initial_rows(a_max);
    let mut evo = free_beam(&g0, &g1).expect("evolution");
    let energy = |evo: &Beam| {
        let mut e = 0.0;
        evo.for_each_cell(|_, _, y| e += evo.lagrangian().energy_densities::<RigidMotions, 6>(y).0);
        e * DS
    };
    let levels = 10_000;
    let e0 = energy(&evo);
    let mut dev = vec![0.0; levels];
    let mut iterations = 0;
    for d in dev.iter_mut().skip(1) {
        iterations += evo.step().expect("step").iterations;
        *d = (energy(&evo) - e0) / e0;
    }
    let window = |r: std::ops::Range<usize>| dev[r].iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let (early, late) = (window(0..1000), window(levels - 1000..levels));
    let mean = |r: std::ops::Range<usize>| dev[r.clone()].iter().sum::<f64>() / r.len() as f64;
    let drift = (mean(levels - 2000..levels) - mean(0..2000)).abs();
    eprintln!(
        "E_L over {levels} levels: max rel. deviation early {early:e}, late {late:e}, drift of the mean {drift:e}, \
         Newton iterations per node {:.2}",
        iterations as f64 / ((levels - 1) * (a_max + 1)) as f64
    );
    // Bounded: the oscillation does not grow; no drift: the running mean
    // moves by a small fraction of the oscillation (a secular drift of the
    // size of the oscillation per 10⁴ levels would fail both).
    assert!(late <= 1.5 * early, "energy deviation early {early:e}, late {late:e}");
    assert!(drift <= 0.02 * early, "energy drift {drift:e} (oscillation {early:e})");
}

/// Bad initial data are typed errors naming the node: a neighbour rotated
/// by π (the cut locus of the chart) and a non-finite value.
#[test]
fn bad_initial_data_are_named() {
    let (mut g0, g1) = initial_rows(4);
    let flip = SE3::new(
        veselov::lie::so3::exp(&nalgebra::Vector3::new(0.0, std::f64::consts::PI, 0.0)),
        nalgebra::Vector3::zeros(),
    );
    g0[3] = g0[2].compose(&flip);
    let err = free_beam(&g0, &g1).err().expect("a rotation by π between neighbours");
    assert!(
        err.to_string().contains("cross index 2") && err.to_string().contains("cut locus"),
        "{err}"
    );
    let (g0, mut g1) = initial_rows(4);
    g1[1] = SE3::from_translation(nalgebra::Vector3::new(f64::NAN, 0.0, 0.0));
    let err = free_beam(&g0, &g1).err().expect("non-finite data");
    assert!(err.to_string().contains("initial level 1"), "{err}");
}

/// A checkpoint restores an evolution bit for bit, and a damaged one (cut
/// short, or with a kept-Jacobian tag it does not know) is refused and
/// leaves the evolution as it was: it goes on exactly as one never handed
/// the checkpoint.
#[test]
fn a_damaged_checkpoint_leaves_the_evolution_as_it_was() {
    let a_max = 5;
    let (g0, g1) = initial_rows(a_max);
    let beam = || free_beam(&g0, &g1).expect("evolution");
    let bits = |evo: &Beam| -> Vec<u64> {
        (0..=a_max)
            .flat_map(|a| {
                let g = evo.value(0, a);
                let m = *g.rotation().matrix();
                m.iter()
                    .chain(g.translation().iter())
                    .map(|x| x.to_bits())
                    .collect::<Vec<_>>()
            })
            .collect()
    };
    // Cut short by one word, an unknown tag where the kept Jacobians
    // begin (after the level and 2·(A + 1) values of 12 coordinates), or a
    // NaN among the values.
    let damage = |saved: &[f64]| {
        let mut wrong_tag = saved.to_vec();
        wrong_tag[1 + 2 * (a_max + 1) * 12] = 7.0;
        let mut not_finite = saved.to_vec();
        not_finite[1 + 12 + 3] = f64::NAN;
        vec![saved[..saved.len() - 1].to_vec(), wrong_tag, not_finite]
    };
    check_checkpoint(
        beam,
        |evo| {
            evo.step().expect("step");
        },
        bits,
        damage,
    );
}
