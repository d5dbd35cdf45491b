//! The free Cosserat rod on the leapfrog CFK lattice (seed 003 §6, note 003
//! §3): the core's Cauchy march confined to a finite body by a material
//! window, with truncated stars at the free ends.

use nalgebra::{SVector, Vector3};
use veselov::complex::{TopCell, permutation};
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions, LevelSplitting};
use veselov::field::cell::{DiscreteLagrangian, vertex_gradient};
use veselov::field::discretize::{CfkNodes, VertexRule};
use veselov::field::fibre::{Fibre, Pose, PositionRotation};
use veselov::lie::so3;
use veselov::models::rod::{CosseratCell, CosseratDensity, ShearFrame};
use veselov::models::rod::{RodLattice, angular_momentum, linear_momentum};

use crate::sample::{tumbling, unit_rod};
use crate::threads;
use threads::on_threads;

type Rod<L> = CauchyMarcher<PositionRotation, L, 6>;

fn rod_march<L: DiscreteLagrangian<PositionRotation, 6>>(lag: L, lattice: &RodLattice) -> Rod<L> {
    let data = lattice.cauchy_data(tumbling(lattice.length()));
    CauchyMarcher::with_window(
        lag,
        lattice.torus().clone(),
        0,
        &data,
        // Every vertex to round-off (the stall test ends each solve), so
        // that marches through different solvers (the split step of Prop.
        // 6.5's closed form, the generic Newton of the vertex rules) differ
        // by round-off only.
        CauchyOptions {
            tolerance: 1e-16,
            ..CauchyOptions::default()
        },
        lattice.window(),
    )
    .expect("marcher")
}

fn closed_form(lattice: &RodLattice) -> CosseratCell {
    CosseratCell::new(CosseratDensity::free(unit_rod(0.1)), lattice.ds(), lattice.dt()).expect("spacings")
}

fn rel(a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    (a - b).norm() / b.norm()
}

#[test]
fn free_rod_conserves_linear_and_angular_momentum() {
    // 21 material points, Courant number 0.5, 160 levels (80 Δt).
    let lattice = RodLattice::new(21, 1.0, 0.05).expect("lattice");
    let mut m = rod_march(closed_form(&lattice), &lattice);
    let (p0, l0) = (linear_momentum(&m), angular_momentum(&m));
    let (mut dp, mut dl, mut iterations, mut vertices) = (0.0_f64, 0.0_f64, 0, 0);
    for _ in 0..160 {
        let report = m.step().expect("stable step");
        iterations += report.iterations;
        vertices += (0..lattice.torus().level_size())
            .filter(|&i| m.is_active(report.level, i))
            .count();
        dp = dp.max(rel(&linear_momentum(&m), &p0));
        dl = dl.max(rel(&angular_momentum(&m), &l0));
    }
    // An independent reference: ∫ρ∂_t r ds of the sampled motion at
    // t = Δt/2 (Simpson in s, central differences in t); the lattice
    // momentum approximates it to O(Δs + Δt).
    let (f, h, n) = (tumbling(lattice.length()), 1e-5, 200);
    let t = 0.5 * lattice.dt();
    let continuum: Vector3<f64> = (0..=n)
        .map(|k| {
            let s = k as f64 / n as f64 * lattice.length();
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            (f(s, t + h).position - f(s, t - h).position) / (2.0 * h) * w
        })
        .sum::<Vector3<f64>>()
        * (unit_rod(0.1).rho() * lattice.length() / (3.0 * n as f64));
    println!(
        "free rod, 160 levels: P = {p0:?} (∫ρ∂_t r ds = {continuum:?}), max rel drift P {dp:.1e}, L {dl:.1e}, \
         Newton iterations per vertex {:.2}",
        iterations as f64 / vertices as f64
    );
    assert!(rel(&p0, &continuum) < 0.05, "{p0:?}");
    assert!(dp <= 1e-12, "linear momentum drift {dp:.1e}");
    assert!(dl <= 1e-10, "angular momentum drift {dl:.1e}");
    assert!((iterations as f64 / vertices as f64) < 6.0);
}

/// All values of levels 0 … `levels` − 1 of a march, level by level.
fn history<L: DiscreteLagrangian<PositionRotation, 6>>(m: &mut Rod<L>, levels: i64) -> Vec<Vec<Pose<f64>>> {
    let mut out: Vec<Vec<Pose<f64>>> = (0..4).map(|w| m.level_values(w).expect("data").to_vec()).collect();
    while (out.len() as i64) < levels {
        m.step().expect("stable step");
        out.push(m.level_values(m.top_level()).expect("new level").to_vec());
    }
    out
}

/// The kept triangles of the body based at levels 0 … levels − 3: (cell, [(level, index); 3]).
fn body_cells(lattice: &RodLattice, levels: i64) -> Vec<(TopCell, [(i64, usize); 3])> {
    let (torus, window) = (lattice.torus(), lattice.window());
    let mut out = Vec::new();
    for w in 0..levels - 2 {
        for i in 0..torus.level_size() {
            for sigma in 0..2 {
                let perm = permutation(2, sigma);
                let v = torus.vertex(w, i);
                if window.contains_cell(&v, &perm) {
                    let cell = TopCell {
                        index: out.len(),
                        shape: sigma,
                        origin: window.unwrap(&v),
                    };
                    let verts = std::array::from_fn(|l| (w + l as i64, torus.offset_index(i, &perm, l, 1)));
                    out.push((cell, verts));
                }
            }
        }
    }
    out
}

#[test]
fn marched_rod_is_critical_for_the_truncated_action_at_ends_and_inside() {
    // EL_v = Σ_{β ∋ v, β in the body} ∂L_β/∂y_v (Def. 3.9 with truncated
    // stars) vanishes on the marched field at every vertex whose whole star
    // lies in the recorded levels, the ends included; and it is the
    // derivative of the truncated action (central differences).
    let lattice = RodLattice::new(9, 1.0, 0.05).expect("lattice");
    let lag = closed_form(&lattice);
    let levels = 12;
    let mut m = rod_march(lag.clone(), &lattice);
    let y = history(&mut m, levels);
    let cells = body_cells(&lattice, levels);
    let value = |cell: &TopCell, verts: &[(i64, usize); 3], y: &[Vec<Pose<f64>>]| {
        let vals: [Pose<f64>; 3] = std::array::from_fn(|l| y[verts[l].0 as usize][verts[l].1]);
        lag.cell_lagrangian(cell, &vals)
    };
    let (mut worst_el, mut worst_fd, mut ends) = (0.0_f64, 0.0_f64, 0);
    for w in 2..levels - 2 {
        for i in 0..lattice.torus().level_size() {
            let Some(node) = lattice.node(w, i) else { continue };
            let (mut el, mut scale) = (SVector::<f64, 6>::zeros(), 0.0_f64);
            for (cell, verts) in &cells {
                if let Some(l) = verts.iter().position(|&v| v == (w, i)) {
                    let vals: [Pose<f64>; 3] = std::array::from_fn(|k| y[verts[k].0 as usize][verts[k].1]);
                    let g = vertex_gradient::<PositionRotation, _, 6>(&lag, cell, &vals, l).1;
                    el += g;
                    scale = scale.max(g.amax());
                }
            }
            worst_el = worst_el.max(el.amax() / scale);
            if node == 0 || node == lattice.nodes() - 1 {
                ends += 1;
            }
            // Central differences of the truncated action in the chart at (w, i).
            let e = 1e-6;
            for dir in 0..6 {
                let mut xi = SVector::<f64, 6>::zeros();
                xi[dir] = e;
                let action = |sign: f64| {
                    let mut z = y.clone();
                    z[w as usize][i] = PositionRotation::retract(&y[w as usize][i], &(xi * sign));
                    cells.iter().map(|(c, v)| value(c, v, &z)).sum::<f64>()
                };
                let fd = (action(1.0) - action(-1.0)) / (2.0 * e);
                worst_fd = worst_fd.max((fd - el[dir]).abs() / scale);
            }
        }
    }
    println!(
        "truncated EL: max |EL_v| / term size {worst_el:.1e} ({ends} end vertices); FD of the action {worst_fd:.1e}"
    );
    assert!(ends >= 8);
    assert!(worst_el < 1e-12, "{worst_el:.1e}");
    assert!(worst_fd < 1e-6, "{worst_fd:.1e}");
}

#[test]
fn generic_discretisation_marches_the_same_rod_and_q_sym_conserves_momentum() {
    // The rod through the core's vertex rule Q_{v₀} of the smooth density
    // (6.1) marches the same field as Prop. 6.5 to round-off; the symmetric
    // rule Q_sym is another exactly symmetric discretisation.
    let lattice = RodLattice::new(9, 1.0, 0.05).expect("lattice");
    let density = CosseratDensity::free(unit_rod(0.1));
    let nodes = CfkNodes::leapfrog(lattice.ds(), lattice.dt()).expect("spacings");
    let mut closed = rod_march(closed_form(&lattice), &lattice);
    let mut generic = rod_march(VertexRule::at_vertex(density, nodes, 0).expect("u = 0"), &lattice);
    let mut sym = rod_march(VertexRule::symmetric(density, nodes), &lattice);
    let (p0, l0) = (linear_momentum(&sym), angular_momentum(&sym));
    let (mut diff, mut dp, mut dl, mut sym_diff) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    for _ in 0..40 {
        closed.step().expect("closed form");
        generic.step().expect("vertex rule");
        sym.step().expect("Q_sym");
        let w = closed.top_level();
        let (a, b, c) = (
            closed.level_values(w).expect("level"),
            generic.level_values(w).expect("level"),
            sym.level_values(w).expect("level"),
        );
        for i in 0..a.len() {
            if lattice.node(w, i).is_some() {
                let d = PositionRotation::log(&a[i], &b[i]).expect("close");
                diff = diff.max(d.amax());
                sym_diff = sym_diff.max(PositionRotation::log(&a[i], &c[i]).expect("close").amax());
            }
        }
        dp = dp.max(rel(&linear_momentum(&sym), &p0));
        dl = dl.max(rel(&angular_momentum(&sym), &l0));
    }
    println!(
        "Prop 6.5 vs Q_v0 march: max chart distance {diff:.1e}; Q_sym differs by {sym_diff:.1e}, \
         momentum drift P {dp:.1e}, L {dl:.1e}"
    );
    assert!(diff < 1e-12, "{diff:.1e}");
    assert!(sym_diff > 1e-6, "Q_sym is a different scheme");
    assert!(dp <= 1e-12 && dl <= 1e-10, "{dp:.1e} {dl:.1e}");
}

#[test]
fn one_and_two_threads_give_identical_bits() {
    for frame in [ShearFrame::Vertex, ShearFrame::Centred] {
        same_bits_on_one_and_two_threads(frame);
    }
}

fn same_bits_on_one_and_two_threads(frame: ShearFrame) {
    let lattice = RodLattice::new(101, 1.0, 0.005).expect("lattice");
    let run = |threads: usize| {
        on_threads(threads, || {
            let lag = closed_form(&lattice).with_shear_frame(frame);
            let mut m = rod_march(lag, &lattice).with_level_splitting(LevelSplitting::Always);
            let mut parallel = 0;
            for _ in 0..20 {
                parallel += usize::from(m.step().expect("stable step").parallel);
            }
            // Every level of 51 vertices is split between two threads.
            assert_eq!(
                parallel,
                if threads == 1 { 0 } else { 20 },
                "levels split on {threads} threads"
            );
            let mut bits = Vec::new();
            for w in [m.top_level() - 1, m.top_level()] {
                for y in m.level_values(w).expect("level") {
                    let mut c = [0.0; 12];
                    PositionRotation::write(y, &mut c);
                    bits.extend(c.iter().map(|x| x.to_bits()));
                }
            }
            bits
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn centred_shear_frame_conserves_momentum() {
    // The centred shear frame keeps the cell Lagrangian invariant under
    // rigid motions, so the discrete momenta are conserved as with
    // Prop. 6.5 (the same tumbling rod, 160 levels, the split step).
    let lattice = RodLattice::new(21, 1.0, 0.05).expect("lattice");
    let mut m = rod_march(closed_form(&lattice).with_shear_frame(ShearFrame::Centred), &lattice);
    let (p0, l0) = (linear_momentum(&m), angular_momentum(&m));
    let (mut dp, mut dl) = (0.0_f64, 0.0_f64);
    for _ in 0..160 {
        m.step().expect("stable step");
        dp = dp.max(rel(&linear_momentum(&m), &p0));
        dl = dl.max(rel(&angular_momentum(&m), &l0));
    }
    println!("centred shear frame, 160 levels: max rel drift P {dp:.1e}, L {dl:.1e}");
    assert!(dp <= 1e-12, "linear momentum drift {dp:.1e}");
    assert!(dl <= 1e-10, "angular momentum drift {dl:.1e}");
}

#[test]
fn on_a_circular_arc_the_centred_frame_measures_no_shear() {
    // A rod at rest bent into a circular arc of curvature κ with its frames
    // along the arc (R(s) = exp(sκe₂)): the continuum's shear is zero. The
    // chord between neighbouring material points is parallel to the
    // tangent halfway between them, which is where the centred frame lies,
    // so its shear components vanish to round-off; Prop. 6.5's frame at
    // the base point sees a shear of sin(κδ/2)·(chord/δ) instead.
    let (kappa, delta) = (2.0_f64, 0.05);
    let pose = |s: f64| {
        let frame = so3::exp(&Vector3::new(0.0, kappa * s, 0.0));
        let position = Vector3::new((1.0 - (kappa * s).cos()) / kappa, 0.0, (kappa * s).sin() / kappa);
        Pose::new(position, frame)
    };
    // Cell (0, 0, σ = +): v₀ and v₂ at material point s₀ (the rod at rest),
    // v₁ at s₀ + δ; Δs = 2δ.
    let cell = TopCell {
        index: 0,
        shape: 0,
        origin: Default::default(),
    };
    let s0 = 0.3;
    let y = [pose(s0), pose(s0 + delta), pose(s0)];
    let density = CosseratDensity::free(unit_rod(0.1));
    let energy = |frame: ShearFrame| {
        let c = CosseratCell::new(density, 2.0 * delta, 0.01)
            .expect("spacings")
            .with_shear_frame(frame);
        c.cell_energy(&cell, &y).expect("suitable")
    };
    let (vertex, centred) = (energy(ShearFrame::Vertex), energy(ShearFrame::Centred));
    // The kinetic and bending terms are shared. With c = chord/δ and
    // θ = κδ/2, Prop. 6.5's strain is (c sin θ, 0, c cos θ − 1), the
    // centred one (0, 0, c − 1): the energies differ by
    // A_β[½κGA(c sin θ)² + ½EA((c cos θ − 1)² − (c − 1)²)].
    let p = unit_rod(0.1);
    let (c, theta) = (2.0 * (kappa * delta / 2.0).sin() / kappa / delta, kappa * delta / 2.0);
    let area = 2.0 * delta * 0.01 / 4.0;
    let expected = area
        * (0.5 * p.c1()[(0, 0)] * (c * theta.sin()).powi(2)
            + 0.5 * p.c1()[(2, 2)] * ((c * theta.cos() - 1.0).powi(2) - (c - 1.0).powi(2)));
    println!("arc: Prop. 6.5 cell energy {vertex:.12e}, centred {centred:.12e}, difference expected {expected:.12e}");
    assert!(((vertex - centred) / expected - 1.0).abs() < 1e-9);
}
