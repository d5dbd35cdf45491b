//! The Cosserat rod (`[model] name = "cosserat-rod"`, seed 003 §6): the
//! scenario schema; its validation into the library's rod
//! ([`veselov::models::rod`]) is [`super::setup`], the run [`super::run`].
//!
//! ```toml
//! [model]
//! name = "cosserat-rod"
//! length = 1.0                  # m
//! nodes = 41                    # material points (≥ 3)
//! radius = 0.02                 # circular section (or width = …, height = …); radius, width, height,
//!                               # density and young may also be expressions in s, e.g. "0.02*(1 - 0.3*s)"
//! density = 1000.0              # kg/m³
//! young = 1e6                   # Pa
//! poisson = 0.5                 # or shear_modulus = … (Pa)
//! shear_coefficient = 0.9       # κ (default: Cowper's, 6(1+ν)/(7+6ν) circle, 10(1+ν)/(12+11ν) rectangle)
//! [ends]
//! start = "clamped"             # free | clamped (held at its initial pose) | driven
//! end = "free"                  # (driven: [ends.start_motion], see `motion`)
//! [loads]
//! gravity = [0.0, 0.0, -9.81]   # m/s²
//! damping = 0.5                 # c_r: force −c_r ∂_t r per unit length
//! angular_damping = 0.0         # c_R: body torque −c_R ω per unit length
//! end_force = [0.0, 0.01, 0.0]  # N, at the last material point, spatial frame
//! end_torque = [0.0, 0.0, 0.0]  # N·m
//! ramp = 1.0                    # s: the end load grows linearly from 0
//! [initial]
//! shape = "straight"            # straight | bent | helix | curve (position = three expressions in s)
//! curvature = 2.0               # bent: an arc in the x–z plane
//! helix_radius = 0.1            # helix: radius and pitch (rise per turn)
//! helix_pitch = 0.2
//! velocity = [0.0, 0.0, 0.0]    # a rigid motion: translation velocity …
//! angular_velocity = [0.0, 0.0, 0.0]  # … and spin about the origin
//! [time]
//! t_end = 2.0
//! dt = 1e-4                     # adjusted to t_end/round(t_end/dt); default: at most half the stability limit
//! # step_number = 0.9           # instead of dt: the fewest steps with step number ≤ this (default 0.5)
//! [method]
//! tolerance = 1e-14             # vertex solves (relative)
//! max_iterations = 30
//! allow_unstable = false        # run above the stability limit (it will blow up)
//! quadrature = "vertex"         # vertex: Prop. 6.5 (Q_{v₀}, split step) | symmetric: Q_sym (6-D Newton; no damping or end loads)
//! shear_frame = "vertex"        # vertex: Prop. 6.5 (shear locking) | centred: the frame halfway to the neighbour (no locking; ~11 % more per step)
//! [output]
//! every = 10                    # time steps between output rows (default: ~500 rows)
//! ```

use std::path::Path;

use serde::Deserialize;

use super::motion::{MotionSpec, parse_expression};
use crate::error::CliError;
use crate::scenario::{RowsOutputSpec, key_error, positive_value};

/// The model name of the rod kind.
pub const ROD_MODEL: &str = "cosserat-rod";

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodScenario {
    pub model: RodModelSpec,
    #[serde(default)]
    pub ends: EndsSpec,
    #[serde(default)]
    pub loads: LoadsSpec,
    #[serde(default)]
    pub initial: RodInitialSpec,
    pub time: RodTimeSpec,
    #[serde(default)]
    pub method: RodMethodSpec,
    #[serde(default)]
    pub output: RowsOutputSpec,
}

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodModelSpec {
    pub name: String,
    pub length: f64,
    pub nodes: usize,
    pub radius: Option<Along>,
    pub width: Option<Along>,
    pub height: Option<Along>,
    pub density: Along,
    pub young: Along,
    pub poisson: Option<f64>,
    pub shear_modulus: Option<f64>,
    pub shear_coefficient: Option<f64>,
}

/// A material quantity: one number for the whole rod, or an expression in
/// the material coordinate `s` (0 … length).
#[derive(Debug, Clone)]
pub(crate) enum Along {
    Value(f64),
    Expression(String),
}

impl<'de> Deserialize<'de> for Along {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Along;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number, or an expression in s as a string (e.g. \"0.02*(1 - 0.3*s)\")")
            }
            fn visit_f64<E>(self, v: f64) -> Result<Along, E> {
                Ok(Along::Value(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Along, E> {
                Ok(Along::Value(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Along, E> {
                Ok(Along::Value(v as f64))
            }
            fn visit_str<E>(self, v: &str) -> Result<Along, E> {
                Ok(Along::Expression(v.to_string()))
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// A number, or an expression in the material coordinate s.
impl schemars::JsonSchema for Along {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Along".into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "anyOf": [{ "type": "number" }, { "type": "string" }],
            "x-type": "float, or an expression in s (string)"
        })
    }
}

impl Along {
    /// The values at the material points `points`, each positive and
    /// finite, or an error naming `key` (and the point).
    pub(super) fn at(&self, path: &Path, key: &str, points: &[f64]) -> Result<Vec<f64>, CliError> {
        match self {
            Along::Value(v) => Ok(vec![positive_value(path, key, *v)?; points.len()]),
            Along::Expression(source) => {
                let e = parse_expression(path, key, source, "s")?;
                points
                    .iter()
                    .map(|&s| {
                        let v = e.eval(&[s]);
                        if v.is_finite() && v > 0.0 {
                            Ok(v)
                        } else {
                            Err(key_error(
                                path,
                                key,
                                format!("at s = {s}: {v}, must be positive and finite"),
                            ))
                        }
                    })
                    .collect()
            }
        }
    }
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct EndsSpec {
    pub start: Option<String>,
    pub end: Option<String>,
    pub start_motion: Option<MotionSpec>,
    pub end_motion: Option<MotionSpec>,
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct LoadsSpec {
    pub gravity: Option<[f64; 3]>,
    pub damping: Option<f64>,
    pub angular_damping: Option<f64>,
    pub end_force: Option<[f64; 3]>,
    pub end_torque: Option<[f64; 3]>,
    pub ramp: Option<f64>,
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodInitialSpec {
    pub shape: Option<String>,
    pub curvature: Option<f64>,
    pub helix_radius: Option<f64>,
    pub helix_pitch: Option<f64>,
    pub velocity: Option<[f64; 3]>,
    pub angular_velocity: Option<[f64; 3]>,
    pub position: Option<[String; 3]>,
}

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodTimeSpec {
    pub t_end: f64,
    pub dt: Option<f64>,
    /// Instead of `dt`: the fewest steps whose step number is at most this
    /// ([`DEFAULT_STEP_NUMBER`] without either). Above 1 it is refused
    /// unless `allow_unstable`, and warned about above
    /// [`LONG_RUN_STEP_NUMBER`] (the limit 1 is the linearised march's).
    pub step_number: Option<f64>,
}

/// The step number a rod run takes when the scenario gives neither `dt`
/// nor `step_number`: half the stability limit.
pub const DEFAULT_STEP_NUMBER: f64 = 0.5;

/// The largest step number run without a warning: the limit 1 is the
/// linearised march's, and close to it, sooner for large motions, a long
/// run can still grow (`rod_free_tumbling.toml` with 31 material points ran
/// 20 s at 0.9 and failed after 3,405 steps at 0.95 and after 50 at 0.97;
/// the `rod_step` bench's near-straight free rod after 10,870 steps at
/// 0.969).
pub const LONG_RUN_STEP_NUMBER: f64 = 0.9;

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodMethodSpec {
    pub tolerance: Option<f64>,
    pub max_iterations: Option<usize>,
    #[serde(default)]
    pub allow_unstable: bool,
    pub quadrature: Option<String>,
    pub shear_frame: Option<String>,
}
