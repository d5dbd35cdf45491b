//! `[initial]` of a rod scenario (`RodInitialSpec`): the
//! motion (s, t) ↦ (r, R) whose samples y_v = (r, R)(x(v)) (6.4) at the
//! nodes x(i, j) = ((i − j)Δs/2, (i + j)Δt/2) (6.2) of the first four levels
//! w = i + j = 0 … 3 of the rod's lattice are the march's Cauchy data (note
//! 003 §3.2: each material point appears on two of them, Δt apart, which fix
//! its position and its velocity).
//!
//! Two styles, with two clocks:
//! * a shape at rest moved rigidly (`shape`, `velocity`, `angular_velocity`):
//!   r = exp(τω̂)r₀(s) + vτ, R = exp(τω̂)R₀(s) with τ = t − Δt, so that the
//!   shape is the rod at the first cut (level 2, lattice time Δt): the
//!   run's t = 0 is level 2, the levels 0 and 1 lie half a step and a step
//!   before it;
//! * any motion as expressions r(s, t), θ(s, t) with R = exp(θ̂) (Rodrigues'
//!   formula (6.8)), sampled at the lattice's own times t = wΔt/2: the run's
//!   clock is the expressions', t = 0 at level 0, and its first output (the
//!   cut at level 2) is at t = Δt.

use std::path::Path;
use std::sync::Arc;

use nalgebra::Vector3;
use veselov::expr::Expr;
use veselov::field::fibre::Pose;
use veselov::lie::so3;
use veselov::models::rod::RodLattice;

use super::motion::Centreline;
use super::schema::RodInitialSpec;
use super::shape::Shape;
use crate::error::CliError;
use crate::kinds::structure::parse_in;
use crate::scenario::{Array, finite_value, key_error, positive_value};

/// The level of the first cut of the march (Cauchy data on levels 0 … 3).
pub(super) const FIRST_CUT: i64 = 2;

/// The Cauchy data's levels.
const BAND: std::ops::Range<i64> = 0..4;

/// The rod's initial motion.
#[derive(Debug, Clone)]
pub(crate) enum Initial {
    /// A shape at rest moved rigidly with `velocity` and `spin` (angular
    /// velocity about the origin); the run's t = 0 is the first cut.
    Rigid {
        shape: Shape,
        velocity: Vector3<f64>,
        spin: Vector3<f64>,
    },
    /// Expressions in s and t; the run's t = 0 is level 0.
    Field(FieldMotion),
}

/// Whether `[initial]` gives the motion as expressions in s and t
/// (`rotation_vector`, or `position` without `shape`).
pub(super) fn by_expressions(i: &RodInitialSpec) -> bool {
    i.rotation_vector.is_some() || (i.position.is_some() && i.shape.is_none())
}

/// The level whose lattice time is the run's t = 0 for `[initial]` `i`:
/// the first cut for a shape, level 0 for expressions.
pub(super) fn level_at_zero(i: &RodInitialSpec) -> i64 {
    if by_expressions(i) { 0 } else { FIRST_CUT }
}

impl Initial {
    /// `[initial]` on `lattice` (its material points and times).
    ///
    /// # Errors
    /// A key of the other style, a missing or malformed key, an unknown
    /// name in an expression or a non-finite sample, naming the key (and the
    /// entry).
    pub fn parse(path: &Path, i: &RodInitialSpec, lattice: &RodLattice) -> Result<Self, CliError> {
        if by_expressions(i) {
            return FieldMotion::parse(path, i, lattice).map(Initial::Field);
        }
        let vector = |key: &str, v: &Option<Array<f64, 3>>| Array::or(v, path, key, [0.0; 3]).map(Vector3::from);
        Ok(Initial::Rigid {
            shape: shape(path, i, lattice)?,
            velocity: vector("initial.velocity", &i.velocity)?,
            spin: vector("initial.angular_velocity", &i.angular_velocity)?,
        })
    }

    /// The level whose lattice time is the run's t = 0.
    pub fn level_at_zero(&self) -> i64 {
        match self {
            Initial::Rigid { .. } => FIRST_CUT,
            Initial::Field(_) => 0,
        }
    }

    /// The pose of material coordinate `s` at lattice time `t` (level w at
    /// wΔt/2) of a lattice of time step `dt`.
    pub fn pose(&self, s: f64, t: f64, dt: f64) -> Pose<f64> {
        match self {
            Initial::Rigid { shape, velocity, spin } => {
                let t = t - dt;
                let q = so3::exp(&(spin * t));
                let p = shape.pose(s);
                Pose::new(q.act(&p.position) + velocity * t, q.compose(&p.rotation))
            }
            Initial::Field(f) => f.pose(s, t),
        }
    }

    /// The pose at `s` at the run's t = 0, where a clamped end is held and
    /// from which a driven one moves.
    pub fn rest(&self, s: f64) -> Pose<f64> {
        match self {
            Initial::Rigid { shape, .. } => shape.pose(s),
            Initial::Field(f) => f.pose(s, 0.0),
        }
    }
}

/// The motion r(s, t), R(s, t) = exp(θ̂(s, t)) of `[initial] position` and
/// `rotation_vector`.
#[derive(Debug, Clone)]
pub(crate) struct FieldMotion {
    position: Arc<[Expr; 3]>,
    rotation: Arc<[Expr; 3]>,
}

/// The keys of a shape moved rigidly, refused beside expressions in s and t.
const RIGID_KEYS: [&str; 6] = [
    "shape",
    "curvature",
    "helix_radius",
    "helix_pitch",
    "velocity",
    "angular_velocity",
];

impl FieldMotion {
    /// Parse `position` and `rotation_vector` (both needed, no key of
    /// [`RIGID_KEYS`]) and check them finite at every vertex of the first
    /// four levels of `lattice`.
    fn parse(path: &Path, i: &RodInitialSpec, lattice: &RodLattice) -> Result<Self, CliError> {
        let given = [
            i.shape.is_some(),
            i.curvature.is_some(),
            i.helix_radius.is_some(),
            i.helix_pitch.is_some(),
            i.velocity.is_some(),
            i.angular_velocity.is_some(),
        ];
        if let Some((k, _)) = RIGID_KEYS.iter().zip(given).find(|(_, g)| *g) {
            return Err(key_error(
                path,
                &format!("initial.{k}"),
                "given with `rotation_vector`: the initial motion is either a shape moved rigidly (shape, its \
                 keys, velocity, angular_velocity) or the expressions position and rotation_vector in s and t, \
                 not both",
            ));
        }
        let missing = |k: &str| {
            key_error(
                path,
                &format!("initial.{k}"),
                "missing: a motion given by expressions in s and t needs both `position` and \
                 `rotation_vector` (for a centreline at rest give shape = \"curve\" and `position` in s)",
            )
        };
        let position = i.position.as_ref().ok_or_else(|| missing("position"))?;
        let rotation = i.rotation_vector.as_ref().ok_or_else(|| missing("rotation_vector"))?;
        let motion = Self {
            position: Arc::new(parse_in(path, "initial.position", position, &["s", "t"])?),
            rotation: Arc::new(parse_in(path, "initial.rotation_vector", rotation, &["s", "t"])?),
        };
        for w in BAND {
            for index in 0..lattice.torus().level_size() {
                let Some(p) = lattice.node(w, index) else { continue };
                let (s, t) = (p as f64 * lattice.spacing(), lattice.time(w));
                for (key, e) in [
                    ("initial.position", &motion.position),
                    ("initial.rotation_vector", &motion.rotation),
                ] {
                    for (a, e) in e.iter().enumerate() {
                        let v = e.eval(&[s, t]);
                        if !v.is_finite() {
                            return Err(key_error(
                                path,
                                &format!("{key}[{a}]"),
                                format!("at s = {s}, t = {t}: {v}, must be finite"),
                            ));
                        }
                    }
                }
            }
        }
        Ok(motion)
    }

    /// (r(s, t), exp(θ̂(s, t))).
    pub fn pose(&self, s: f64, t: f64) -> Pose<f64> {
        let at = |e: &[Expr; 3]| Vector3::from_fn(|a, _| e[a].eval(&[s, t]));
        Pose::new(at(&self.position), so3::exp(&at(&self.rotation)))
    }
}

/// `[initial]`: the shape at rest on `lattice` (its material points and length).
fn shape(path: &Path, i: &RodInitialSpec, lattice: &RodLattice) -> Result<Shape, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let (nodes, length) = (lattice.nodes(), lattice.length());
    let shape = match i.shape.as_deref().unwrap_or("straight") {
        "straight" => Shape::Straight,
        "bent" => Shape::Bent {
            curvature: finite_value(path, "initial.curvature", i.curvature.unwrap_or(1.0))?,
        },
        "helix" => Shape::Helix {
            radius: positive_value(path, "initial.helix_radius", i.helix_radius.unwrap_or(0.0))?,
            pitch: finite_value(path, "initial.helix_pitch", i.helix_pitch.unwrap_or(0.0))?,
        },
        "curve" => {
            let Some(sources) = &i.position else {
                return Err(key(
                    "initial.position",
                    "shape = \"curve\" needs three expressions in s".into(),
                ));
            };
            let points: Vec<f64> = (0..nodes).map(|k| length * k as f64 / (nodes - 1) as f64).collect();
            Shape::Curve(Centreline::new(path, "initial.position", sources, &points)?)
        }
        other => {
            return Err(key(
                "initial.shape",
                format!("unknown shape `{other}` (straight | bent | helix | curve)"),
            ));
        }
    };
    if i.position.is_some() && !matches!(shape, Shape::Curve(_)) {
        return Err(key(
            "initial.position",
            "given, but `initial.shape` is not \"curve\"".into(),
        ));
    }
    if let Shape::Bent { curvature } = &shape
        && (curvature * length).abs() >= std::f64::consts::PI
    {
        return Err(key(
            "initial.curvature",
            format!(
                "|curvature|·length = {:e} must stay below π",
                (curvature * length).abs()
            ),
        ));
    }
    Ok(shape)
}
