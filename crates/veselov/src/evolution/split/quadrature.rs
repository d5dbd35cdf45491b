//! The kinetic quadrature of a split Lagrangian: how a level's kinetic
//! energy is spread over its nodes in s, and the weights it gives each
//! cell's terms.

use crate::complex::TopCell;

use super::SplitLagrangian;

/// How a level's kinetic energy is spread over its nodes in s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum KineticQuadrature {
    /// Seed 000 (63): each cell carries the kinetic energy of its first
    /// node, with weight Δs; the last node of a level has none (the slaved
    /// node of note 000 §1). A free end then lacks the half cell of mass that
    /// belongs to it: a cantilever's frequencies converge at first order.
    #[default]
    FirstNode,
    /// The trapezoid rule in s, as the potential already is: the first and
    /// the last node of a level weigh Δs/2, the others Δs. Cell 0 carries
    /// ½K(ξ₀), the cells 1..A − 1 carry K(ξ_a), and the end cell (j, A),
    /// a boundary term of the action, carries ½K(ξ_A) alone (no strain, no
    /// potential, no dependence on its third vertex): the last node `last`
    /// = A becomes an ordinary node with its own inertia
    /// ([`crate::evolution::marcher::EndCondition::EndCell`]), and the
    /// end load of the density acts on it. Frequencies converge at second
    /// order, and a free end needs no consistent initial strain.
    Trapezoid {
        /// The index A of the last node of a level.
        last: usize,
    },
}

/// The weights of a cell's kinetic and stored terms (the potential and the
/// damping follow the stored and the kinetic one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CellWeights {
    pub(crate) kinetic: f64,
    pub(crate) stored: f64,
    /// Whether this is the end cell of a trapezoid rule (it carries the end load).
    pub(crate) end: bool,
}

impl CellWeights {
    pub(crate) const UNIT: CellWeights = CellWeights {
        kinetic: 1.0,
        stored: 1.0,
        end: false,
    };
}

impl<I, S> SplitLagrangian<I, S> {
    /// The weights of `cell`'s terms under the kinetic quadrature.
    pub(crate) fn weights(&self, cell: &TopCell) -> CellWeights {
        match self.quadrature {
            KineticQuadrature::FirstNode => CellWeights::UNIT,
            KineticQuadrature::Trapezoid { last } => {
                let a = cell.origin[1];
                if a >= last as i64 {
                    CellWeights {
                        kinetic: 0.5,
                        stored: 0.0,
                        end: true,
                    }
                } else if a == 0 {
                    CellWeights {
                        kinetic: 0.5,
                        ..CellWeights::UNIT
                    }
                } else {
                    CellWeights::UNIT
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{SVector, Vector3};

    use super::*;
    use crate::complex::{MAX_LATTICE_DIMENSION, SpacetimeKind};
    use crate::evolution::split::{SplitDensity, chart_gradient};
    use crate::field::cell::{DiscreteLagrangian, check_closed_form};
    use crate::field::fibre::RigidMotions;
    use crate::lie::{SE3, se3};
    use crate::models::EndLoad;
    use crate::models::beam::{BeamDensity, BeamProperties, CayleyBeam, beam_lagrangian};

    fn cell(a: i64) -> TopCell {
        let mut origin = [0; MAX_LATTICE_DIMENSION];
        origin[0] = 3;
        origin[1] = a;
        TopCell {
            index: 0,
            shape: SpacetimeKind::Seed000Triangle.tag(),
            origin,
        }
    }

    fn density() -> BeamDensity {
        let p = BeamProperties::from_diagonals([0.5, 0.7, 1.1, 1.0, 1.3, 0.9], [0.5, 0.4, 0.6, 1.0, 2.0, 3.0])
            .expect("positive");
        BeamDensity::new(p).with_gravity([0.0, -9.8, 0.3])
    }

    fn values() -> [SE3<f64>; 3] {
        let g = |x: [f64; 6]| se3::exp(&SVector::from(x));
        [
            g([0.1, -0.2, 0.3, 0.5, 0.1, 0.2]),
            g([0.15, -0.25, 0.32, 0.52, 0.13, 0.21]),
            g([0.12, -0.1, 0.28, 0.45, 0.12, 0.4]),
        ]
    }

    /// Cell 0 carries half its kinetic term, the interior cells all of it,
    /// the end cell half the kinetic term alone; the closed-form gradients
    /// of every kind of cell agree with the dual pass over the weighed cell
    /// Lagrangian (and so, by its own tests, with differences of the action).
    #[test]
    fn the_trapezoid_weighs_the_cells_and_its_gradients_are_exact() {
        let (dt, ds) = (0.05, 0.1);
        let first: CayleyBeam = beam_lagrangian(density(), dt, ds).expect("lagrangian");
        let trapezoid: CayleyBeam = beam_lagrangian(density(), dt, ds)
            .expect("lagrangian")
            .with_quadrature(KineticQuadrature::Trapezoid { last: 4 });
        let y = values();
        let (xi, _) = first.jet::<RigidMotions, f64, 6>(&y).expect("jet");
        let kinetic = SplitDensity::<RigidMotions, 6>::kinetic(first.density(), &xi) * ds * dt;
        let l = |lag: &CayleyBeam, a: i64| DiscreteLagrangian::<RigidMotions, 6>::cell_lagrangian(lag, &cell(a), &y);
        let full = l(&first, 2);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * (a.abs() + b.abs());
        assert!(close(l(&trapezoid, 2), full), "interior cell");
        assert!(close(l(&trapezoid, 0), full - 0.5 * kinetic), "first cell");
        assert!(close(l(&trapezoid, 4), 0.5 * kinetic), "end cell");
        for a in [0, 2, 4] {
            check_closed_form::<RigidMotions, CayleyBeam, 6>(&trapezoid, &cell(a), &y, || format!("cell {a}"))
                .expect("closed form");
        }
        for l in 0..3 {
            assert!(!DiscreteLagrangian::<RigidMotions, 6>::depends(
                &trapezoid,
                &cell(4),
                l,
                2
            ));
        }
    }

    /// The end load's generalised force is the chart derivative of the
    /// work F·r of its force part, and Λᵀτ for its torque; it acts on the end
    /// cell only, by the trapezoid rule in time, ramped at the cell's times.
    #[test]
    fn the_end_load_is_the_virtual_work_of_a_dead_force_and_torque() {
        let (dt, ds) = (0.05, 0.1);
        let load = EndLoad {
            force: Vector3::new(0.3, -1.2, 0.7),
            torque: Vector3::new(-0.2, 0.4, 0.9),
            ramp: 1.0,
            start: 0.0,
        };
        let loaded = density().with_end_load(load).expect("load");
        let lag: CayleyBeam = beam_lagrangian(loaded, dt, ds)
            .expect("lagrangian")
            .with_quadrature(KineticQuadrature::Trapezoid { last: 4 })
            .with_time_origin(-dt);
        let y = values();
        // Cell row 3 spans [t₀ + 3Δt, t₀ + 4Δt] = [0.10, 0.15].
        for (l, t) in [(0, 0.10), (1, 0.15)] {
            let work = chart_gradient::<RigidMotions, f64, 6>(
                |g| {
                    let r = g.translation();
                    r[0] * load.force[0] + r[1] * load.force[1] + r[2] * load.force[2]
                },
                &y[l],
            );
            let torque = y[l].rotation().matrix().transpose() * load.torque;
            let expected = SVector::<f64, 6>::from_fn(|k, _| if k < 3 { torque[k] } else { work[k] }) * (0.5 * dt * t);
            let on_end = DiscreteLagrangian::<RigidMotions, 6>::cell_force(&lag, &cell(4), &y, l);
            assert!(
                (on_end - expected).amax() <= 1e-14 * expected.amax(),
                "vertex {l}: {on_end} against {expected}"
            );
            let inside = DiscreteLagrangian::<RigidMotions, 6>::cell_force(&lag, &cell(2), &y, l);
            assert_eq!(inside, SVector::<f64, 6>::zeros(), "no end load inside");
        }
    }
}
