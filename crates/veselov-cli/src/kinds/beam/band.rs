//! The first two levels of a beam's march, from its validated initial
//! state ([`super::start`]) and its ends.

use nalgebra::{SVector, Vector3};
use veselov::field::fibre::Pose;
use veselov::lie::{LieGroup, Retraction, SE3};
use veselov::models::beam::paper::{DS, DT, LAST_TIME_NODE, XI0, prescribed_columns};
use veselov::models::beam::{BeamLagrangian, straight};

use super::setup::{BeamEnd, BeamSetup};
use super::start::BeamStart;
use crate::error::CliError;

/// The shape at t = 0 of a time evolution started from a named shape.
fn shape<R: Retraction<6, Family = veselov::lie::RigidMotions>>(
    start: BeamStart,
    ds: f64,
    nodes: usize,
) -> Vec<SE3<f64>> {
    match start {
        BeamStart::Bent(kappa) => {
            let step = R::tau(&(SVector::<f64, 6>::from([kappa, 0.0, 0.0, 0.0, 0.0, 1.0]) * ds));
            let mut g = vec![SE3::identity(); nodes];
            for a in 0..nodes - 1 {
                g[a + 1] = g[a].compose(&step);
            }
            g
        }
        _ => (0..nodes).map(|a| straight(ds, a)).collect(),
    }
}

/// The first two levels of a march.
pub(super) type Band = (Vec<SE3<f64>>, Vec<SE3<f64>>);

/// The pose of a frame.
pub(super) fn pose(g: &SE3<f64>) -> Pose<f64> {
    Pose::new(*g.translation(), *g.rotation())
}

/// The frame of a pose.
pub(super) fn frame(p: &Pose<f64>) -> SE3<f64> {
    SE3::new(p.rotation, p.position)
}

/// The value of end `end` at time `t` when it is held (clamped at `rest`,
/// or driven from it), `None` when free.
pub(super) fn held_value(end: &BeamEnd, rest: &SE3<f64>, t: f64) -> Option<SE3<f64>> {
    match end {
        BeamEnd::Free => None,
        BeamEnd::Clamped => Some(*rest),
        BeamEnd::Driven(motion) => Some(frame(&motion.pose(&pose(rest), t))),
    }
}

/// The first two levels of the march: time evolution, the levels at
/// t = −Δt and t = 0 (module documentation); space evolution, the paper's
/// prescribed columns (or, well posed, column 1 the rigid transport of
/// column 0 with a 10⁻³ perturbation of its velocity).
pub(super) fn band<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
    setup: &BeamSetup,
    lag: &BeamLagrangian<R>,
) -> Result<Band, CliError> {
    let nodes = setup.scenario.model.nodes;
    let initial = &setup.initial;
    match initial.start {
        BeamStart::Paper => Ok(prescribed_columns::<R>(LAST_TIME_NODE + 1)),
        BeamStart::PaperWellPosed => {
            let last = LAST_TIME_NODE + 1;
            let (c0, _) = prescribed_columns::<R>(last);
            let h = SE3::from_translation(Vector3::new(0.0, 0.0, DS));
            let xi1 = h.inverse().adjoint() * SVector::from(XI0) + SVector::from([1e-3, 0.0, -1e-3, 0.0, 0.0, 0.0]);
            let step = R::tau(&(xi1 * DT));
            let mut c1 = vec![h; last + 1];
            for j in 0..last {
                c1[j + 1] = c1[j].compose(&step);
            }
            Ok((c0, c1))
        }
        BeamStart::Motion => {
            let Some(motion) = &initial.motion else {
                return Err(setup.key("initial.position", "no motion given"));
            };
            let level = |t: f64| -> Result<Vec<SE3<f64>>, CliError> {
                (0..nodes)
                    .map(|a| {
                        let s = a as f64 * setup.ds;
                        let g = motion.at(s, t);
                        let finite = g.translation().iter().all(|x| x.is_finite())
                            && g.rotation().matrix().iter().all(|x| x.is_finite());
                        if finite {
                            Ok(g)
                        } else {
                            Err(setup.key(
                                "initial.position",
                                format!(
                                    "the frame at s = {}, t = {} is not finite",
                                    crate::output::number(s),
                                    crate::output::number(t)
                                ),
                            ))
                        }
                    })
                    .collect()
            };
            Ok((level(-setup.dt)?, level(0.0)?))
        }
        BeamStart::Straight | BeamStart::Bent(_) => {
            let now = shape::<R>(initial.start, setup.ds, nodes);
            let velocity: Vec<SVector<f64, 6>> = now
                .iter()
                .zip(&initial.velocity)
                .map(|(g, [v, w])| {
                    let lt = g.rotation().matrix().transpose();
                    let (w, v) = (lt * w, lt * v);
                    SVector::from([w[0], w[1], w[2], v[0], v[1], v[2]])
                })
                .collect();
            let last = nodes - 1;
            let held = |a: usize| match a {
                0 => held_value(&setup.ends[0], &now[0], -setup.dt),
                a if a == last => held_value(&setup.ends[1], &now[last], -setup.dt),
                _ => None,
            };
            let before = lag
                .previous_level::<veselov::field::fibre::RigidMotions, 6>(&now, &velocity, held, 1, &setup.options)
                .map_err(|e| setup.key("initial.velocity", e.to_string()))?;
            Ok((before, now))
        }
    }
}
