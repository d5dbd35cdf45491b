//! The beam's initial state and the first two levels of its march.
//!
//! Time evolution marches from the levels at t = −Δt and t = 0, and writes
//! its rows from t = 0:
//!
//! * a named shape (`straight`, `bent`) with velocity fields v(s), ω(s)
//!   (spatial frame; zero by default): the level at t = 0 is the shape,
//!   the level before it is solved from the velocities by the library's
//!   second-order start
//!   ([`SplitLagrangian::previous_level`](veselov::evolution::split::SplitLagrangian::previous_level)),
//!   so that a beam released bent at rest keeps its energy;
//! * a motion r(s, t), θ(s, t) (`position`, `rotation_vector`): both levels
//!   sampled from it, R = exp(θ̂).
//!
//! Space evolution starts from the paper's prescribed columns.

use std::path::Path;

use nalgebra::{SVector, Vector3};
use veselov::expr::Expr;
use veselov::field::fibre::Pose;
use veselov::lie::{LieGroup, Retraction, SE3, so3};
use veselov::models::beam::paper::{DS, DT, LAST_TIME_NODE, XI0, prescribed_columns};
use veselov::models::beam::{BeamLagrangian, straight};

use super::schema::BeamInitialSpec;
use super::setup::{BeamEnd, BeamSetup};
use crate::error::CliError;
use crate::kinds::rod::motion::parse_in;
use crate::scenario::{Array, finite_value, key_error};

/// The initial data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum BeamStart {
    /// Straight along E3 (time evolution).
    Straight,
    /// Bent with curvature κ about E1 (time evolution).
    Bent(f64),
    /// The motion r(s, t), θ(s, t) ([`BeamInitial::motion`]).
    Motion,
    /// The paper's prescribed columns (space evolution).
    Paper,
    /// The paper's column 0 with column 1 its rigid transport, perturbed.
    PaperWellPosed,
}

/// r(s, t) and θ(s, t) (the identity when no rotation is given).
#[derive(Debug, Clone)]
pub(crate) struct InitialMotion {
    position: [Expr; 3],
    rotation: Option<[Expr; 3]>,
}

impl InitialMotion {
    /// The frame of the section at arc length `s` and time `t`.
    fn at(&self, s: f64, t: f64) -> SE3<f64> {
        let eval = |e: &[Expr; 3]| Vector3::from_fn(|i, _| e[i].eval(&[s, t]));
        let rotation = self.rotation.as_ref().map_or(Vector3::zeros(), eval);
        SE3::new(so3::exp(&rotation), eval(&self.position))
    }
}

/// The validated `[initial]` table.
#[derive(Debug, Clone)]
pub(crate) struct BeamInitial {
    pub start: BeamStart,
    pub motion: Option<InitialMotion>,
    /// The spatial velocity and angular velocity at each node (zero at rest).
    pub velocity: Vec<[Vector3<f64>; 2]>,
}

/// `[initial]` for the evolution in `space` or time of a beam of `length`
/// with `nodes` nodes.
pub(super) fn parse(
    path: &Path,
    initial: &BeamInitialSpec,
    space: bool,
    (length, nodes): (f64, usize),
) -> Result<BeamInitial, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let ds = length / (nodes - 1) as f64;
    let points: Vec<f64> = (0..nodes).map(|a| a as f64 * ds).collect();
    let moving = initial.position.is_some() || initial.rotation_vector.is_some();
    if space && (moving || initial.velocity.is_some() || initial.angular_velocity.is_some()) {
        return Err(key(
            "initial",
            "space evolution starts from the paper's prescribed columns: \
             `velocity`, `angular_velocity`, `position` and `rotation_vector` are for time evolution"
                .into(),
        ));
    }
    if moving {
        for (k, given) in [
            ("initial.shape", initial.shape.is_some()),
            ("initial.curvature", initial.curvature.is_some()),
            ("initial.velocity", initial.velocity.is_some()),
            ("initial.angular_velocity", initial.angular_velocity.is_some()),
        ] {
            if given {
                return Err(key(
                    k,
                    "give either `position` (with `rotation_vector`) or a `shape` with velocities, not both".into(),
                ));
            }
        }
        let Some(position) = &initial.position else {
            return Err(key(
                "initial.rotation_vector",
                "needs `position`, the centreline r(s, t)".into(),
            ));
        };
        let motion = InitialMotion {
            position: parse_in(path, "initial.position", position, &["s", "t"])?,
            rotation: match &initial.rotation_vector {
                Some(r) => Some(parse_in(path, "initial.rotation_vector", r, &["s", "t"])?),
                None => None,
            },
        };
        return Ok(BeamInitial {
            start: BeamStart::Motion,
            motion: Some(motion),
            velocity: vec![[Vector3::zeros(); 2]; nodes],
        });
    }
    let start = match (initial.shape.as_deref(), space) {
        (None | Some("straight"), false) => BeamStart::Straight,
        (Some("bent"), false) => BeamStart::Bent(finite_value(
            path,
            "initial.curvature",
            initial.curvature.unwrap_or(1.0),
        )?),
        (None | Some("paper"), true) => BeamStart::Paper,
        (Some("paper-well-posed"), true) => BeamStart::PaperWellPosed,
        (Some(other), _) => {
            return Err(key(
                "initial.shape",
                format!(
                    "`{other}` is not a {} evolution start ({})",
                    if space { "space" } else { "time" },
                    if space {
                        "paper | paper-well-posed"
                    } else {
                        "straight | bent"
                    }
                ),
            ));
        }
    };
    if let BeamStart::Bent(k) = start
        && (k * length).abs() >= std::f64::consts::PI
    {
        return Err(key(
            "initial.curvature",
            format!(
                "|curvature|·length = {} must stay below π",
                crate::output::number((k * length).abs())
            ),
        ));
    }
    let field =
        |k: &str, v: &Option<Array<crate::kinds::rod::schema::Along, 3>>| -> Result<Vec<Vector3<f64>>, CliError> {
            let Some(v) = v else {
                return Ok(vec![Vector3::zeros(); nodes]);
            };
            let parts = v.values(path, k)?;
            let mut columns = Vec::with_capacity(3);
            for (i, part) in parts.iter().enumerate() {
                columns.push(part.finite_at(path, &format!("{k}[{i}]"), &points)?);
            }
            Ok((0..nodes)
                .map(|a| Vector3::new(columns[0][a], columns[1][a], columns[2][a]))
                .collect())
        };
    let v = field("initial.velocity", &initial.velocity)?;
    let w = field("initial.angular_velocity", &initial.angular_velocity)?;
    Ok(BeamInitial {
        start,
        motion: None,
        velocity: v.into_iter().zip(w).map(|(v, w)| [v, w]).collect(),
    })
}

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
