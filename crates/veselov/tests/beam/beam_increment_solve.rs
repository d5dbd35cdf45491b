//! The beam's flow step solved in the moving increment
//! (`DiscreteLagrangian::solve_cell_vertex` of the split Lagrangian) against
//! the generic Newton in the chart of SE(3), which stays the reference: the
//! same Lagrangian with that hook switched off marches the same field, to
//! round-off, in time (with gravity and damping, so the fixed terms, the
//! potential and the moving force all enter) and in space, for the Cayley map
//! and the exponential, the slaved node included (its equation, zero
//! traction or zero momentum, solved in the increment of its one cell); and
//! the one-edge gradients equal the three-vertex closed form bit for bit.

use nalgebra::SVector;
use veselov::ad::Scalar;
use veselov::complex::TopCell;
use veselov::evolution::marcher::{Direction, EndCondition, Evolution000};
use veselov::field::cauchy::CauchyOptions;
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, ExpMap, Retraction, SE3, se3};
use veselov::models::beam::{BeamDensity, BeamLagrangian, BeamProperties, beam_lagrangian, straight};

/// The Lagrangian `L` without its own vertex solve: every other hook passes through.
struct ChartSolve<L>(L);

impl<L: DiscreteLagrangian<RigidMotions, 6>> DiscreteLagrangian<RigidMotions, 6> for ChartSolve<L> {
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SE3<D>]) -> D {
        self.0.cell_lagrangian(cell, y)
    }
    fn depends(&self, cell: &TopCell, l: usize, k: usize) -> bool {
        self.0.depends(cell, l, k)
    }
    fn analytic_gradients(&self, cell: &TopCell, y: &[SE3<f64>], out: &mut [SVector<f64, 6>]) -> bool {
        self.0.analytic_gradients(cell, y, out)
    }
    fn analytic_gradient(&self, cell: &TopCell, y: &[SE3<f64>], l: usize) -> Option<SVector<f64, 6>> {
        self.0.analytic_gradient(cell, y, l)
    }
    fn analytic_block(
        &self,
        cell: &TopCell,
        y: &[SE3<f64>],
        a: usize,
        b: usize,
    ) -> Option<(SVector<f64, 6>, nalgebra::SMatrix<f64, 6, 6>)> {
        self.0.analytic_block(cell, y, a, b)
    }
    fn has_forces(&self) -> bool {
        self.0.has_forces()
    }
    fn cell_force<D: Scalar>(&self, cell: &TopCell, y: &[SE3<D>], l: usize) -> SVector<D, 6> {
        self.0.cell_force(cell, y, l)
    }
}

const CELLS: usize = 12;

fn density(loaded: bool) -> BeamDensity {
    let p = BeamProperties::from_diagonals([0.5, 0.5, 1.0, 1.0, 1.0, 1.0], [0.5, 0.5, 0.6, 1.0, 1.0, 1.0])
        .expect("positive");
    let d = BeamDensity::new(p);
    if loaded {
        d.with_gravity([0.0, -0.3, 0.1])
            .with_damping([0.1, 0.2, 0.05, 0.3, 0.1, 0.2])
            .expect("non-negative")
    } else {
        d
    }
}

fn wave(k: usize) -> SVector<f64, 6> {
    let s = k as f64;
    SVector::from([
        0.2 * (0.7 * s).sin(),
        -0.1,
        0.15 * (0.3 * s).cos(),
        0.05,
        -0.1 * (0.5 * s).sin(),
        0.02,
    ])
}

/// The first two levels: a bent beam moving (time), or the first two
/// columns of a beam with a prescribed motion (space).
fn rows(direction: Direction, dt: f64, ds: f64) -> (Vec<SE3<f64>>, Vec<SE3<f64>>) {
    let (first, step, e): (Vec<SE3<f64>>, f64, SVector<f64, 6>) = match direction {
        Direction::Time => (
            (0..=CELLS)
                .map(|a| straight(ds, a).compose(&se3::exp(&(wave(a) * 0.1))))
                .collect(),
            dt,
            SVector::zeros(),
        ),
        Direction::Space => (
            (0..=CELLS).map(|j| se3::exp(&(wave(0) * (j as f64 * dt)))).collect(),
            ds,
            SVector::from([0.0, 0.0, 0.0, 0.0, 0.0, 1.0]),
        ),
    };
    let second = first
        .iter()
        .enumerate()
        .map(|(k, g)| g.compose(&se3::exp(&((e + wave(k + 3) * 0.3) * step))))
        .collect();
    (first, second)
}

/// Marches `levels` levels with the increment solve and with the chart
/// solve; returns the largest difference of the frames' entries.
fn march<R>(direction: Direction, loaded: bool, levels: usize) -> f64
where
    R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static,
    BeamLagrangian<R>: DiscreteLagrangian<RigidMotions, 6>,
{
    let (dt, ds) = match direction {
        Direction::Time => (0.05, 0.1),
        Direction::Space => (0.1, 0.05),
    };
    let (first, second) = rows(direction, dt, ds);
    let lag = || beam_lagrangian::<R>(density(loaded), dt, ds).expect("lagrangian");
    let options = CauchyOptions::default();
    let mut own = Evolution000::new(
        direction,
        lag(),
        &first,
        &second,
        EndCondition::Natural,
        EndCondition::Natural,
        options,
    )
    .expect("evolution");
    let mut chart = Evolution000::new(
        direction,
        ChartSolve(lag()),
        &first,
        &second,
        EndCondition::Natural,
        EndCondition::Natural,
        options,
    )
    .expect("evolution");
    let mut worst: f64 = 0.0;
    for _ in 0..levels {
        let a = own.step().expect("increment solve");
        let b = chart.step().expect("chart solve");
        assert!(a.max_relative_residual <= 1e-12, "{a:?}");
        assert!(b.max_relative_residual <= 1e-12, "{b:?}");
        for c in 0..=own.cross() {
            let (x, y) = (own.value(0, c), chart.value(0, c));
            worst = worst
                .max((x.rotation().matrix() - y.rotation().matrix()).amax())
                .max((x.translation() - y.translation()).amax());
        }
    }
    worst
}

/// The two solves converge to the same root, each to round-off (the
/// default tolerance, 1e-13 of the terms): their fields differ by the
/// roots' round-off, which a stable march carries along without growth
/// (measured ≤ 2.5e-14 over 40 levels; the bound leaves a factor 40).
#[test]
fn increment_solve_marches_the_chart_solves_field() {
    for (direction, loaded) in [
        (Direction::Time, false),
        (Direction::Time, true),
        (Direction::Space, false),
        (Direction::Space, true),
    ] {
        let cayley = march::<CayleyMap>(direction, loaded, 40);
        let exp = march::<ExpMap>(direction, loaded, 40);
        eprintln!("{direction:?}, loads {loaded}: largest difference cayley {cayley:.1e}, exp {exp:.1e}");
        assert!(cayley <= 1e-12, "{direction:?} (loads {loaded}), Cayley: {cayley:.1e}");
        assert!(exp <= 1e-12, "{direction:?} (loads {loaded}), exp: {exp:.1e}");
    }
}

/// ∂ℒ/∂y_l from the one edge it needs is the three-vertex closed form's, bit for bit.
#[test]
fn one_edge_gradients_are_the_closed_forms_bits() {
    let lag = beam_lagrangian::<CayleyMap>(density(true), 0.05, 0.1).expect("lagrangian");
    let cell = TopCell {
        index: 0,
        shape: 0,
        origin: [0; veselov::complex::MAX_LATTICE_DIMENSION],
    };
    for k in 0..20 {
        let y = [0, 1, 2].map(|l| straight(0.1, l % 2).compose(&se3::exp(&(wave(3 * k + l) * 0.4))));
        let mut all = [SVector::zeros(); 3];
        assert!(lag.analytic_gradients(&cell, &y, &mut all));
        for (l, g) in all.iter().enumerate() {
            assert_eq!(lag.analytic_gradient(&cell, &y, l), Some(*g), "field {k}, vertex {l}");
        }
    }
}
