//! The Cosserat rod discretised (seed 003 §6): the rod's jets (6.7) (T24),
//! Prop. 6.5 against the generic vertex rule (T25), the §3.5 gradients (T26)
//! and the mixed blocks of a vertex solve, symmetry transfer under rigid
//! motions (T19) and the per-cell momentum identities (T27).

use crate::shared::{SplitMix, cell, nodes_of, nudged, rel, rel_vec};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use veselov::complex::TopCell;
use veselov::field::cell::{DiscreteLagrangian, mixed_block, vertex_gradient};
use veselov::field::discretize::{CfkNodes, VertexRule, vertex_jet};
use veselov::field::fibre::{Fibre, Pose, PositionRotation};
use veselov::models::rod::{CosseratCell, CosseratDensity, LinearPotential, RodParameters, ShearFrame};

fn spd(rng: &mut SplitMix) -> Matrix3<f64> {
    let b = rng.mat::<3, 3>(1.0);
    b * b.transpose() + Matrix3::identity() * 0.5
}

pub(crate) fn rod_parameters(rng: &mut SplitMix) -> RodParameters {
    let inertia = Matrix3::from_diagonal(&Vector3::new(
        0.2 + rng.uniform(),
        0.2 + rng.uniform(),
        0.1 + rng.uniform(),
    ));
    RodParameters::new(0.5 + rng.uniform(), inertia, spd(rng), spd(rng), rng.vec(1.0)).expect("valid rod")
}

/// Three poses with rotations within `spread` of a random frame.
fn rod_values(rng: &mut SplitMix, spread: f64) -> [Pose<f64>; 3] {
    let base = rng.rotation(3.0);
    std::array::from_fn(|_| Pose::new(rng.vec(1.0), base.compose(&rng.rotation(spread))))
}

fn rod_cell(rng: &mut SplitMix, index: usize) -> TopCell {
    cell(index, index % 2, &[rng.sym(10.0) as i64, rng.sym(10.0) as i64])
}

fn log6(a: &Pose<f64>, b: &Pose<f64>) -> SVector<f64, 6> {
    PositionRotation::log(a, b).expect("rotations within π")
}

/// The size of the terms of Prop. 6.5 (all with a plus sign), for relative errors.
fn term_size(p: &RodParameters, ds: f64, dt: f64, c: &TopCell, y: &[Pose<f64>; 3], pot: f64) -> f64 {
    let sigma = if c.shape == 0 { 1.0 } else { -1.0 };
    let (d01, d02) = (log6(&y[0], &y[1]), log6(&y[0], &y[2]));
    let part = |v: SVector<f64, 6>, k: usize| Vector3::new(v[k], v[k + 1], v[k + 2]);
    let g = (part(d01, 0) * 2.0 - part(d02, 0)) / (sigma * ds);
    let eps = y[0].rotation.matrix().transpose() * g - p.strain();
    let u = (part(d01, 3) * 2.0 - part(d02, 3)) / (sigma * ds);
    let (w, v) = (part(d02, 3) / dt, part(d02, 0) / dt);
    0.125
        * ds
        * dt
        * (p.rho() * v.norm_squared()
            + w.dot(&(p.inertia() * w))
            + eps.dot(&(p.c1() * eps))
            + u.dot(&(p.c2() * u))
            + pot.abs())
}

// ---------------------------------------------------------------- T24, T25, T26, mixed blocks

#[test]
fn t24_rod_jets_of_6_7() {
    let mut rng = SplitMix(24);
    let mut worst = 0.0_f64;
    let mut rotation_parts_differ = 0.0_f64;
    for trial in 0..40 {
        let (ds, dt) = (0.1 + rng.uniform(), 0.1 + rng.uniform());
        let map = CfkNodes::leapfrog(ds, dt).expect("spacings");
        let c = rod_cell(&mut rng, trial);
        let sigma = if c.shape == 0 { 1.0 } else { -1.0 };
        let x = nodes_of(&map, &c, 3);
        let y = rod_values(&mut rng, 0.7);
        let d = |i: usize, j: usize| log6(&y[i], &y[j]);
        let want = [
            [(d(0, 1) * 2.0 - d(0, 2)) / (sigma * ds), d(0, 2) / dt],
            [(-d(1, 0) - d(1, 2)) / (sigma * ds), (d(1, 2) - d(1, 0)) / dt],
            [(d(2, 1) * 2.0 - d(2, 0)) / (sigma * ds), -d(2, 0) / dt],
        ];
        let mut jets = Vec::new();
        for u in 0..3 {
            let (jet, jac) = vertex_jet::<PositionRotation, f64, 6, 2>(c.index, &x, &y, u).expect("suitable");
            assert!(rel(jac / 2.0, ds * dt / 4.0) < 1e-14, "area ΔsΔt/4");
            for col in 0..2 {
                worst = worst.max(rel_vec(&jet.column(col).into_owned(), &want[u][col]));
            }
            jets.push(jet);
        }
        // Remark 6.4: equal r-parts, differing SO(3) parts.
        for u in 1..3 {
            worst = worst.max((jets[u].rows(0, 3) - jets[0].rows(0, 3)).norm() / jets[0].rows(0, 3).norm());
            rotation_parts_differ =
                rotation_parts_differ.max((jets[u].rows(3, 3) - jets[0].rows(3, 3)).norm() / jets[0].rows(3, 3).norm());
        }
    }
    println!("T24 max rel deviation from (6.7): {worst:.1e}; SO(3) parts differ by up to {rotation_parts_differ:.1e}");
    assert!(worst < 1e-13, "{worst}");
    assert!(rotation_parts_differ > 1e-3);
}

#[test]
fn t25_prop_6_5_equals_the_vertex_rule_on_the_leapfrog_embedding() {
    let mut rng = SplitMix(25);
    let mut worst = 0.0_f64;
    for trial in 0..200 {
        let p = rod_parameters(&mut rng);
        let (ds, dt) = (0.05 + rng.uniform(), 0.05 + rng.uniform());
        let map = CfkNodes::leapfrog(ds, dt).expect("spacings");
        let c = rod_cell(&mut rng, trial);
        let y = rod_values(&mut rng, 1.2);
        let pot = LinearPotential { gradient: rng.vec(2.0) };
        let density = CosseratDensity {
            parameters: p,
            potential: pot,
        };
        let closed = CosseratCell::new(density, ds, dt).expect("spacings");
        let generic = VertexRule::at_vertex(density, map, 0).expect("u = 0");
        let (a, b) = (closed.cell_lagrangian(&c, &y), generic.cell_lagrangian(&c, &y));
        let size = term_size(&p, ds, dt, &c, &y, pot.gradient.dot(&y[0].position));
        worst = worst.max((a - b).abs() / size);
    }
    println!("T25 max |Prop 6.5 − Q_v0| / term size: {worst:.1e}");
    assert!(worst < 1e-13, "{worst}");
}

#[test]
fn t26_closed_form_gradients_match_the_exact_vertex_gradients() {
    let mut rng = SplitMix(26);
    let (mut worst, mut fd_worst) = (0.0_f64, 0.0_f64);
    for trial in 0..100 {
        let p = rod_parameters(&mut rng);
        let (ds, dt) = (0.05 + rng.uniform(), 0.05 + rng.uniform());
        let c = rod_cell(&mut rng, trial);
        let y = rod_values(&mut rng, 1.2);
        let density = CosseratDensity {
            parameters: p,
            potential: LinearPotential { gradient: rng.vec(2.0) },
        };
        // Prop. 6.5, then the shear in the centred frame (`ShearFrame`).
        let frame = [ShearFrame::Vertex, ShearFrame::Centred][trial % 2];
        let rod = CosseratCell::new(density, ds, dt)
            .expect("spacings")
            .with_shear_frame(frame);
        let closed = rod.gradients(&c, &y).expect("suitable");
        for k in 0..3 {
            let (_, g) = vertex_gradient::<PositionRotation, _, 6>(&rod, &c, &y, k);
            worst = worst.max(rel_vec(&closed[k], &g));
            if trial < 20 {
                // Finite differences in the chart, as a check of the AD path itself.
                let fd = SVector::<f64, 6>::from_fn(|i, _| {
                    let e = 1e-6;
                    let mut xi = SVector::<f64, 6>::zeros();
                    xi[i] = e;
                    let [plus, minus] = nudged::<PositionRotation, 6, 3>(&y, k, &xi);
                    (rod.cell_lagrangian(&c, &plus) - rod.cell_lagrangian(&c, &minus)) / (2.0 * e)
                });
                fd_worst = fd_worst.max(rel_vec(&fd, &g));
            }
        }
    }
    println!("T26 max rel: §3.5 vs exact {worst:.1e}; exact vs central differences {fd_worst:.1e}");
    assert!(worst < 1e-12, "{worst}");
    assert!(fd_worst < 1e-7, "{fd_worst}");
}

#[test]
fn mixed_blocks_of_the_vertex_rule_match_the_closed_form_cell() {
    // The Jacobian block of a vertex solve (∂/∂y₂ of ∂L/∂y₀) through nested
    // duals and the fibre logarithm, against the closed form's and finite
    // differences of the exact gradient.
    let mut rng = SplitMix(27);
    let (mut worst, mut fd_worst) = (0.0_f64, 0.0_f64);
    for trial in 0..40 {
        let p = rod_parameters(&mut rng);
        let (ds, dt) = (0.05 + rng.uniform(), 0.05 + rng.uniform());
        let c = rod_cell(&mut rng, trial);
        let y = rod_values(&mut rng, 1.2);
        let density = CosseratDensity::free(p);
        let rod = CosseratCell::new(density, ds, dt).expect("spacings");
        let generic = VertexRule::at_vertex(density, CfkNodes::leapfrog(ds, dt).expect("spacings"), 0).expect("u = 0");
        let (g1, j1) = mixed_block::<PositionRotation, _, 6>(&rod, &c, &y, 0, 2);
        let (g2, j2) = mixed_block::<PositionRotation, _, 6>(&generic, &c, &y, 0, 2);
        worst = worst.max(rel_vec(&g1, &g2)).max((j1 - j2).norm() / j1.norm());
        let e = 1e-6;
        let fd = SMatrix::<f64, 6, 6>::from_fn(|i, j| {
            let mut xi = SVector::<f64, 6>::zeros();
            xi[j] = e;
            let [plus, minus] = nudged::<PositionRotation, 6, 3>(&y, 2, &xi);
            let gp = vertex_gradient::<PositionRotation, _, 6>(&generic, &c, &plus, 0).1;
            let gm = vertex_gradient::<PositionRotation, _, 6>(&generic, &c, &minus, 0).1;
            (gp[i] - gm[i]) / (2.0 * e)
        });
        fd_worst = fd_worst.max((fd - j2).norm() / j2.norm());
    }
    println!("mixed blocks: closed form vs vertex rule {worst:.1e}; vs central differences {fd_worst:.1e}");
    assert!(worst < 1e-12 && fd_worst < 1e-7, "{worst} {fd_worst}");
}

// ---------------------------------------------------------------- T19

#[test]
fn t19_rigid_motions_leave_the_discrete_rod_lagrangian_invariant() {
    let mut rng = SplitMix(19);
    let mut worst = [0.0_f64; 4];
    for trial in 0..200 {
        let p = rod_parameters(&mut rng);
        let (ds, dt) = (0.05 + rng.uniform(), 0.05 + rng.uniform());
        let map = CfkNodes::leapfrog(ds, dt).expect("spacings");
        let c = rod_cell(&mut rng, trial);
        let y = rod_values(&mut rng, 1.2);
        let (q, shift) = (rng.rotation(3.0), rng.vec::<3>(5.0));
        let moved: [Pose<f64>; 3] =
            std::array::from_fn(|k| Pose::new(q.act(&y[k].position) + shift, q.compose(&y[k].rotation)));
        let density = CosseratDensity::free(p);
        let size = term_size(&p, ds, dt, &c, &y, 0.0);
        let v0 = VertexRule::at_vertex(density, map, 0).expect("u = 0");
        let sym = VertexRule::symmetric(density, map);
        let closed = CosseratCell::new(density, ds, dt).expect("spacings");
        worst[0] = worst[0].max((v0.cell_lagrangian(&c, &y) - v0.cell_lagrangian(&c, &moved)).abs() / size);
        worst[1] = worst[1].max((sym.cell_lagrangian(&c, &y) - sym.cell_lagrangian(&c, &moved)).abs() / size);
        worst[2] = worst[2].max((closed.cell_lagrangian(&c, &y) - closed.cell_lagrangian(&c, &moved)).abs() / size);
        let centred = closed.with_shear_frame(ShearFrame::Centred);
        worst[3] = worst[3].max((centred.cell_lagrangian(&c, &y) - centred.cell_lagrangian(&c, &moved)).abs() / size);
    }
    println!(
        "T19 rod max rel change under (Qr + c, QR): Q_v0 {:.1e}, Q_sym {:.1e}, Prop 6.5 {:.1e}, centred shear frame {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst.iter().all(|&w| w <= 1e-13), "{worst:?}");
}

// ---------------------------------------------------------------- T27

#[test]
fn t27_per_cell_momentum_identities_of_the_free_rod() {
    // Σ_k ∇_{r_k}L_β = 0 and Σ_k (r_k × ∇_{r_k}L_β + R_k ∇_{R_k}L_β) = 0 (note 003 §3.7),
    // for the closed form, for Q_sym (symmetry transfer, Prop. 5.17) and for
    // the centred shear frame (dual-number gradients).
    let mut rng = SplitMix(270);
    let mut worst = 0.0_f64;
    for trial in 0..100 {
        let p = rod_parameters(&mut rng);
        let (ds, dt) = (0.05 + rng.uniform(), 0.05 + rng.uniform());
        let c = rod_cell(&mut rng, trial);
        let y = rod_values(&mut rng, 1.2);
        let density = CosseratDensity::free(p);
        let rod = CosseratCell::new(density, ds, dt).expect("spacings");
        let sym = VertexRule::symmetric(density, CfkNodes::leapfrog(ds, dt).expect("spacings"));
        let closed = rod.gradients(&c, &y).expect("suitable");
        let exact: [SVector<f64, 6>; 3] =
            std::array::from_fn(|k| vertex_gradient::<PositionRotation, _, 6>(&sym, &c, &y, k).1);
        let centred = rod
            .with_shear_frame(ShearFrame::Centred)
            .gradients(&c, &y)
            .expect("suitable");
        for g in [closed, exact, centred] {
            let (mut lin, mut ang, mut size) = (Vector3::zeros(), Vector3::zeros(), 0.0_f64);
            for k in 0..3 {
                let gr = Vector3::new(g[k][0], g[k][1], g[k][2]);
                let gq = Vector3::new(g[k][3], g[k][4], g[k][5]);
                lin += gr;
                ang += y[k].position.cross(&gr) + y[k].rotation.act(&gq);
                size += gr.norm() * (1.0 + y[k].position.norm()) + gq.norm();
            }
            worst = worst.max((lin.norm() + ang.norm()) / size);
        }
    }
    println!("T27 max rel per-cell momentum defect: {worst:.1e}");
    assert!(worst < 1e-13, "{worst}");
}
