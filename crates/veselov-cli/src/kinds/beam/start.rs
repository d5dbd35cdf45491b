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
//! Space evolution starts from the paper's prescribed columns. This file
//! reads `[initial]`; [`super::band`] builds the levels.

use std::path::Path;

use nalgebra::Vector3;
use veselov::expr::Expr;
use veselov::lie::{SE3, so3};

use super::schema::BeamInitialSpec;
use crate::error::CliError;
use crate::kinds::structure::{Along, parse_in};
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
    pub(super) fn at(&self, s: f64, t: f64) -> SE3<f64> {
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
    let field = |k: &str, v: &Option<Array<Along, 3>>| -> Result<Vec<Vector3<f64>>, CliError> {
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
