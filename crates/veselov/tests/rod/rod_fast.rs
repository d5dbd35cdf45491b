//! The rod's closed forms in the core's hot path: [`CosseratCell::gradients`]
//! (note 003 §3.5) replaces the dual-number pass over L_β in the stored cell
//! gradients, and the split step of note 003 §3.6 (linear position solve,
//! then a 3-D rotation Newton) replaces the generic 6-D Newton; the AD path
//! with the generic Newton stays selectable and is the reference.

use nalgebra::SVector;
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::cell::{DiscreteLagrangian, vertex_gradient};
use veselov::field::fibre::{Fibre, PositionRotation};
use veselov::models::rod::RodLattice;
use veselov::models::rod::{CosseratCell, CosseratDensity, ShearFrame};

use crate::sample::{tumbling, unit_rod};

fn cell(lattice: &RodLattice, analytic: bool) -> CosseratCell {
    framed_cell(lattice, analytic, ShearFrame::Vertex)
}

fn framed_cell(lattice: &RodLattice, analytic: bool, frame: ShearFrame) -> CosseratCell {
    CosseratCell::new(CosseratDensity::free(unit_rod(0.1)), lattice.ds(), lattice.dt())
        .expect("spacings")
        .with_analytic_gradients(analytic)
        .with_shear_frame(frame)
}

/// Every vertex solved to round-off: with a tolerance below it every solve
/// ends at the stall test, so two solvers' roots differ only by round-off
/// (with the default 10⁻¹⁴ they differ by up to that tolerance per vertex,
/// which accumulates to ~10⁻¹² over 60 levels).
const ROUND_OFF: CauchyOptions = CauchyOptions {
    tolerance: 1e-16,
    max_iterations: 30,
};

fn march(lag: CosseratCell, lattice: &RodLattice) -> CauchyMarcher<PositionRotation, CosseratCell, 6> {
    let data = lattice.cauchy_data(tumbling(lattice.length()));
    CauchyMarcher::with_window(lag, lattice.torus().clone(), 0, &data, ROUND_OFF, lattice.window()).expect("marcher")
}

#[test]
fn analytic_gradients_are_offered_only_when_enabled_and_match_the_ad_pass() {
    let lattice = RodLattice::new(21, 1.0, 0.05).expect("lattice");
    let (on, off) = (cell(&lattice, true), cell(&lattice, false));
    let m = march(on.clone(), &lattice);
    let mut checked = 0;
    m.for_each_straddling_cell(|c, y| {
        let mut out = [SVector::<f64, 6>::zeros(); 3];
        assert!(!off.analytic_gradients(c, y, &mut out));
        assert!(on.analytic_gradients(c, y, &mut out));
        for (l, g) in out.iter().enumerate() {
            let ad = vertex_gradient::<PositionRotation, _, 6>(&off, c, y, l).1;
            assert!(
                (g - ad).amax() <= 1e-12 * ad.amax().max(1e-300),
                "cell {c:?} position {l}: {g} vs {ad}"
            );
        }
        checked += 1;
    });
    assert!(checked > 0);
}

#[test]
fn analytic_and_ad_marches_agree_over_sixty_levels() {
    split_step_meets_the_generic_newton(ShearFrame::Vertex);
}

#[test]
fn with_the_centred_shear_frame_analytic_and_ad_marches_agree() {
    split_step_meets_the_generic_newton(ShearFrame::Centred);
}

fn split_step_meets_the_generic_newton(frame: ShearFrame) {
    let lattice = RodLattice::new(21, 1.0, 0.05).expect("lattice");
    let (mut fast, mut reference) = (
        march(framed_cell(&lattice, true, frame), &lattice),
        march(framed_cell(&lattice, false, frame), &lattice),
    );
    let (mut worst, mut iterations) = (0.0_f64, [0, 0]);
    for _ in 0..60 {
        iterations[0] += fast.step().expect("stable step").iterations;
        iterations[1] += reference.step().expect("stable step").iterations;
        let w = fast.top_level();
        assert_eq!(w, reference.top_level());
        for (a, b) in fast
            .level_values(w)
            .expect("level")
            .iter()
            .zip(reference.level_values(w).expect("level"))
        {
            let (mut ca, mut cb) = ([0.0; 12], [0.0; 12]);
            PositionRotation::write(a, &mut ca);
            PositionRotation::write(b, &mut cb);
            let scale = cb.iter().fold(1.0_f64, |s, x| s.max(x.abs()));
            for (x, y) in ca.iter().zip(&cb) {
                worst = worst.max((x - y).abs() / scale);
            }
        }
    }
    println!(
        "{frame:?} shear frame: split step vs generic AD Newton over 60 levels: {worst:.1e}; iterations {iterations:?}"
    );
    assert!(worst <= 1e-13, "split-step vs AD march differ by {worst:.1e}");
    // The split step (a linear position solve, then a quadratically
    // convergent 3-D Newton) needs no more iterations than the generic
    // simplified 6-D Newton.
    assert!(iterations[0] <= iterations[1], "iterations {iterations:?}");
}

/// The split step writes the solved cells' gradients itself; a march
/// restored from a checkpoint recomputes them from the stored values. Both
/// are the same operations on the same numbers, so the restored march goes
/// on bit for bit.
#[test]
fn a_restored_march_continues_bit_for_bit() {
    restored_march_continues(ShearFrame::Vertex);
    restored_march_continues(ShearFrame::Centred);
}

fn restored_march_continues(frame: ShearFrame) {
    use veselov::run::{Checkpoint, Words};
    let lattice = RodLattice::new(21, 1.0, 0.05).expect("lattice");
    let mut whole = march(framed_cell(&lattice, true, frame), &lattice);
    for _ in 0..30 {
        whole.step().expect("stable step");
    }
    let mut saved = Vec::new();
    whole.save(&mut saved);
    let mut resumed = march(framed_cell(&lattice, true, frame), &lattice);
    resumed.restore(&mut Words::new(&saved)).expect("restore");
    for _ in 0..30 {
        whole.step().expect("stable step");
        resumed.step().expect("stable step");
        let w = whole.top_level();
        let (a, b) = (
            whole.level_values(w).expect("level"),
            resumed.level_values(w).expect("level"),
        );
        for (x, y) in a.iter().zip(b) {
            let (mut cx, mut cy) = ([0.0; 12], [0.0; 12]);
            PositionRotation::write(x, &mut cx);
            PositionRotation::write(y, &mut cy);
            assert_eq!(cx.map(f64::to_bits), cy.map(f64::to_bits), "{frame:?}, level {w}");
        }
    }
}
