//! The geometrically exact beam on SE(3) (`[model] name = "beam"`, seed
//! 000): the scenario schema; its validation into the library's beam
//! ([`veselov::models::beam`]) is [`super::setup`], the run [`super::run`].
//!
//! ```toml
//! [model]
//! name = "beam"
//! length = 0.8                  # m
//! nodes = 41                    # nodes along the beam (Δs = length/(nodes − 1))
//! width = 0.01                  # rectangle (or radius = … for a disc), m
//! height = 0.01
//! density = 7800.0              # kg/m³
//! young = 2.1e11                # Pa
//! poisson = 0.3                 # or shear_modulus = … (Pa)
//! shear_coefficient = 0.85      # κ (default: Cowper's, 6(1+ν)/(7+6ν) disc, 10(1+ν)/(12+11ν) rectangle)
//! [method]
//! evolution = "time"            # time | space
//! retraction = "cayley"         # cayley | exp
//! tolerance = 1e-14
//! max_iterations = 30
//! allow_unstable = false        # march above the step limit (it will blow up)
//! [ends]                        # time evolution
//! start = "clamped"             # free (zero traction) | clamped (held at its initial pose) | driven
//! end = "free"                  # (driven: [ends.start_motion] / [ends.end_motion], as for the rod)
//! [loads]
//! gravity = [0.0, -9.81, 0.0]   # m/s²
//! damping = [0, 0, 0, 0, 0, 0]  # viscous, on the body velocity (angular first)
//! end_force = [0.0, -1.0, 0.0]  # N, at the last node, spatial frame (needs a free end)
//! end_torque = [0.0, 0.0, 0.0]  # N·m
//! ramp = 0.01                   # s: the end load grows linearly from 0
//! [initial]
//! shape = "bent"                # straight | bent (curvature about E1);
//! curvature = 0.5               # space evolution: paper | paper-well-posed (seed 000 §5)
//! velocity = ["0", "0.1*s", "0"]        # m/s, numbers or expressions in s (spatial frame)
//! angular_velocity = [0, 0, 0]          # rad/s
//! # position = ["0", "0.01*sin(s)*cos(t)", "s"]   # instead of shape: r(s, t) and θ(s, t)
//! # rotation_vector = ["0.01*cos(s)*cos(t)", "0", "0"]  # sampled at t = −Δt and 0
//! [time]
//! t_end = 1e-3                  # s (time evolution); dt defaults to 0.8 of the step limit
//! dt = 1e-6
//! [output]
//! every = 10                    # levels between output rows
//! ```
//!
//! Space evolution (seed 000 §5) uses the paper's time grid (Δt = 0.04 s,
//! time nodes j = 0..51, the last one slaved) and its prescribed first two
//! columns; the scenario's Δs must be the paper's 0.02 m, and the march runs
//! to the last node of the beam.

use serde::Deserialize;

use crate::kinds::structure::{Along, MotionSpec};
use crate::scenario::{Array, RowsOutputSpec};

/// The model name of the beam kind.
pub const BEAM_MODEL: &str = "beam";

/// A geometrically exact beam scenario (`[model] name = "beam"`): each
/// table is documented on its own struct.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamScenario {
    pub model: BeamModelSpec,
    #[serde(default)]
    pub method: BeamMethodSpec,
    #[serde(default)]
    pub ends: BeamEndsSpec,
    #[serde(default)]
    pub loads: BeamLoadsSpec,
    #[serde(default)]
    pub initial: BeamInitialSpec,
    #[serde(default)]
    pub time: BeamTimeSpec,
    #[serde(default)]
    pub output: RowsOutputSpec,
    /// The thresholds beyond which the run's summary carries a warning.
    #[serde(default)]
    pub checks: crate::verdict::ChecksSpec,
}

/// The beam's length, its nodes, its cross-section and its
/// material. The beam lies along E3; its cross-section's axes are E1 and
/// E2.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamModelSpec {
    /// The model name.
    #[schemars(extend("enum" = ["beam"]))]
    pub name: String,
    /// The beam's length when unstressed.
    #[schemars(extend("unit" = "m"))]
    pub length: f64,
    /// The number of nodes along the beam, 3 to 100 000, evenly spaced at
    /// Δs = length/(nodes − 1); space evolution needs Δs = 0.02 m, that of
    /// its prescribed columns.
    pub nodes: usize,
    /// The radius of a disc cross-section (> 0): give either `radius` or
    /// `width` and `height`.
    #[schemars(extend("unit" = "m"))]
    pub radius: Option<f64>,
    /// The side of a rectangular cross-section along E1 (> 0), with
    /// `height` (instead of `radius`).
    #[schemars(extend("unit" = "m"))]
    pub width: Option<f64>,
    /// The side of a rectangular cross-section along E2 (> 0), with
    /// `width` (instead of `radius`).
    #[schemars(extend("unit" = "m"))]
    pub height: Option<f64>,
    /// The mass density of the material (> 0).
    #[schemars(extend("unit" = "kg/m³"))]
    pub density: f64,
    /// Young's modulus E (> 0).
    #[schemars(extend("unit" = "Pa"))]
    pub young: f64,
    /// Poisson's ratio ν, in (−1, 0.5], giving the shear modulus
    /// E/(2(1 + ν)); exactly one of `poisson` and `shear_modulus`.
    pub poisson: Option<f64>,
    /// The shear modulus G (> 0), instead of `poisson`; exactly one of
    /// `poisson` and `shear_modulus`.
    #[schemars(extend("unit" = "Pa"))]
    pub shear_modulus: Option<f64>,
    /// The shear coefficient κ of the cross-section (> 0). Default:
    /// Cowper's for the section and Poisson's ratio, 6(1 + ν)/(7 + 6ν) for a
    /// disc and 10(1 + ν)/(12 + 11ν) for a rectangle. Its former name
    /// `shear_correction` is still read (give only one of the two).
    #[serde(alias = "shear_correction")]
    pub shear_coefficient: Option<f64>,
}

/// The direction of the march, the retraction of the discrete
/// Lagrangian and the options of the node solves (Newton's method for each
/// new node).
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamMethodSpec {
    /// `time` marches level by level in time from the beam's initial state;
    /// `space` marches column by column along the beam, from the prescribed
    /// motion of its first two columns on a fixed time grid (§5 of Demoures,
    /// Gay-Balmaz and Ratiu), to its last node.
    #[schemars(extend("default" = "time", "enum" = ["time", "space"]))]
    pub evolution: Option<String>,
    /// The map from the Lie algebra to SE(3) in the discrete Lagrangian:
    /// `cayley` (the Cayley map) or `exp` (the exponential).
    #[schemars(extend("default" = "cayley", "enum" = ["cayley", "exp"]))]
    pub retraction: Option<String>,
    /// The relative tolerance at which each node's Newton solve stops (> 0):
    /// the residual against the size of the terms summed.
    #[schemars(extend("default" = 1e-14))]
    pub tolerance: Option<f64>,
    /// The Newton iterations a node may take (≥ 1) before the run stops
    /// with a solve error.
    #[schemars(extend("default" = 30))]
    pub max_iterations: Option<usize>,
    /// Run a step above the step limit of the marching direction instead of
    /// refusing it (the waves will grow without bound).
    #[serde(default)]
    pub allow_unstable: bool,
}

/// How the beam is held at its start (s = 0) and its end
/// (s = length), in time evolution; space evolution takes free ends and
/// accepts only `free`.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamEndsSpec {
    /// The start (s = 0): `free` (zero traction), `clamped` (held at its
    /// initial pose) or `driven` (moved as `[ends.start_motion]` prescribes).
    #[schemars(extend("default" = "free", "enum" = ["free", "clamped", "driven"]))]
    pub start: Option<String>,
    /// The end (s = length): `free` (zero traction), `clamped` (held at
    /// its initial pose) or `driven` (moved as `[ends.end_motion]`
    /// prescribes). An end force or torque needs it free.
    #[schemars(extend("default" = "free", "enum" = ["free", "clamped", "driven"]))]
    pub end: Option<String>,
    /// The motion of a driven start (`start = "driven"`, and only then),
    /// from its initial pose: expressions in the run's time `t`.
    pub start_motion: Option<MotionSpec>,
    /// The motion of a driven end (`end = "driven"`, and only then), from
    /// its initial pose: expressions in the run's time `t`.
    pub end_motion: Option<MotionSpec>,
}

/// Gravity, viscous damping, and a force and torque at the beam's end
/// (s = length), in time evolution.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamLoadsSpec {
    /// The gravitational acceleration (x, y, z), averaged over each cell.
    #[schemars(extend("unit" = "m/s²", "default" = [0.0, 0.0, 0.0]))]
    pub gravity: Option<Array<f64, 3>>,
    /// Six viscous damping coefficients per unit length (each ≥ 0) against
    /// the body velocity, angular first (about E1, E2, E3, in N·s), then
    /// linear (along E1, E2, E3, in N·s/m²).
    #[schemars(extend("default" = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]))]
    pub damping: Option<Array<f64, 6>>,
    /// A force at the last node, in the spatial frame (x, y, z), applied by
    /// the trapezoid rule over each step; it needs `[ends] end` free.
    #[schemars(extend("unit" = "N", "default" = [0.0, 0.0, 0.0]))]
    pub end_force: Option<Array<f64, 3>>,
    /// A torque at the last node, in the spatial frame (x, y, z); it needs
    /// `[ends] end` free.
    #[schemars(extend("unit" = "N·m", "default" = [0.0, 0.0, 0.0]))]
    pub end_torque: Option<Array<f64, 3>>,
    /// The time over which the end force and torque grow linearly from zero
    /// to their full value (≥ 0); 0 applies them in full from the start.
    #[schemars(extend("unit" = "s", "default" = 0.0))]
    pub ramp: Option<f64>,
}

/// The beam's state at t = 0 (time evolution) or its first two
/// columns (space evolution). In time evolution give a `shape` and,
/// optionally, velocity fields, or the whole motion near t = 0 as
/// `position` and `rotation_vector` (not both).
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamInitialSpec {
    /// Time evolution: `straight` (along E3, the default) or `bent` (an arc
    /// of `curvature` about E1). Space evolution: `paper` (the columns of §5
    /// of Demoures, Gay-Balmaz and Ratiu as printed, the default) or
    /// `paper-well-posed` (its second column the rigid transport of the
    /// first, slightly perturbed).
    #[schemars(extend("enum" = ["straight", "bent", "paper", "paper-well-posed"]))]
    pub shape: Option<String>,
    /// The curvature of the `bent` beam about E1; |curvature|·length must
    /// stay below π.
    #[schemars(extend("unit" = "1/m", "default" = 1.0))]
    pub curvature: Option<f64>,
    /// The velocity of the centreline at t = 0, in the spatial frame
    /// (x, y, z): each a number or an expression in the arc length `s`
    /// (0 … length). With `shape`; the run starts from it at second order.
    #[schemars(extend("unit" = "m/s", "default" = [0.0, 0.0, 0.0]))]
    pub velocity: Option<Array<Along, 3>>,
    /// The angular velocity of the cross-sections at t = 0, in the spatial
    /// frame (x, y, z): each a number or an expression in `s`. With `shape`.
    #[schemars(extend("unit" = "rad/s", "default" = [0.0, 0.0, 0.0]))]
    pub angular_velocity: Option<Array<Along, 3>>,
    /// The centreline r(s, t) near t = 0, instead of `shape`: three
    /// expressions (x, y, z) in the arc length `s` and the time `t`,
    /// sampled at t = −Δt and t = 0 (the march's first two levels; the
    /// velocities follow from them). With `rotation_vector`, or alone for
    /// frames that do not turn (the identity).
    #[schemars(extend("unit" = "m"))]
    pub position: Option<Array<String, 3>>,
    /// The rotation of the cross-sections θ(s, t) near t = 0, a rotation
    /// vector in the spatial frame (R = exp(θ̂), taking E1, E2, E3 to the
    /// section's axes): three expressions in `s` and `t`, sampled as
    /// `position`. Needs `position`.
    #[schemars(extend("unit" = "rad"))]
    pub rotation_vector: Option<Array<String, 3>>,
}

/// How long a time evolution runs and its step. Space evolution
/// runs on the time grid of its prescribed columns (Δt = 0.04 s, 52 time
/// nodes) and refuses these keys.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamTimeSpec {
    /// The time at which the run ends (> 0; needed in time evolution).
    #[schemars(extend("unit" = "s"))]
    pub t_end: Option<f64>,
    /// The time step: the run takes round(t_end/dt) steps (at least 2), dt
    /// adjusted to land on `t_end`; a dt above the step limit is refused
    /// unless `allow_unstable`. Default: the fewest steps (at least 2) with
    /// dt at most 0.8 of the step limit.
    #[schemars(extend("unit" = "s"))]
    pub dt: Option<f64>,
}
