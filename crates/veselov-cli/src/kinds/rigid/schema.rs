//! The schema of a rigid-body scenario file (`[model]`, `[method]`,
//! `[time]`, `[initial]`, `[output]`), parsed with key-level errors, and the
//! values it gives: inertia, attitude, body momenta.

use std::path::{Path, PathBuf};

use nalgebra::{Matrix3, Quaternion, Vector3};
use serde::Deserialize;
use veselov::lie::{SO3, so3};

use crate::error::CliError;
use crate::scenario::{OutputSpec, TimeSpec, check_time_and_output, finite_value, key_error, parse_toml};

/// A rigid-body scenario file.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidScenario {
    /// The body.
    pub model: RigidModelSpec,
    /// The integrator.
    pub method: RigidMethodSpec,
    /// Horizon.
    pub time: TimeSpec,
    /// Initial data (each model has a documented default).
    pub initial: Option<RigidInitialSpec>,
    /// Outputs.
    #[serde(default)]
    pub output: OutputSpec,
}

/// `[model]` of a rigid-body scenario.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidModelSpec {
    /// `rigid-body | heavy-top | rigid-body-se3`.
    pub name: String,
    /// Principal moments (3 values) or the full tensor (9 values, row by row).
    pub inertia: Option<Vec<f64>>,
    /// Mass.
    pub mass: Option<f64>,
    /// Heavy top: centre of mass in the body frame, measured from the pivot.
    pub centre_of_mass: Option<Vec<f64>>,
    /// Heavy top: gravitational acceleration (along −z).
    pub gravity: Option<f64>,
}

/// `[method]` of a rigid-body scenario.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidMethodSpec {
    /// `cayley` (default) or `exp`.
    #[serde(default = "cayley")]
    pub retraction: String,
    /// Time step.
    pub dt: f64,
}

fn cayley() -> String {
    "cayley".into()
}

/// `[initial]` of a rigid-body scenario.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidInitialSpec {
    /// Attitude as a rotation vector (axis × angle, radians).
    pub rotation_vector: Option<Vec<f64>>,
    /// Attitude as a quaternion [w, x, y, z] (normalised on input).
    pub quaternion: Option<Vec<f64>>,
    /// Body angular velocity Ω.
    pub angular_velocity: Option<Vec<f64>>,
    /// Body angular momentum Π = 𝕀Ω.
    pub angular_momentum: Option<Vec<f64>>,
    /// SE(3): position of the centre of mass.
    pub position: Option<Vec<f64>>,
    /// SE(3): body-frame velocity of the centre of mass.
    pub velocity: Option<Vec<f64>>,
    /// SE(3): body-frame linear momentum m v.
    pub linear_momentum: Option<Vec<f64>>,
}

/// A parsed rigid-body scenario and its file.
pub struct LoadedRigid {
    pub(super) path: PathBuf,
    pub(super) scenario: RigidScenario,
}

impl LoadedRigid {
    /// Parse scenario text attributed to `path`.
    pub fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: RigidScenario = parse_toml(path, text)?;
        check_time_and_output(path, &scenario.time, scenario.method.dt, &scenario.output)?;
        Ok(Self {
            path: path.to_path_buf(),
            scenario,
        })
    }

    pub(super) fn key_error(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    pub(super) fn vector3(
        &self,
        key: &str,
        value: &Option<Vec<f64>>,
        default: [f64; 3],
    ) -> Result<Vector3<f64>, CliError> {
        match value {
            None => Ok(Vector3::from(default)),
            Some(v) if v.len() == 3 => {
                if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                    return Err(self.key_error(
                        &format!("{key}[{i}]"),
                        format!("expected a finite number, got {}", v[i]),
                    ));
                }
                Ok(Vector3::new(v[0], v[1], v[2]))
            }
            Some(v) => Err(self.key_error(key, format!("expected 3 numbers, got {}", v.len()))),
        }
    }

    pub(super) fn scalar(&self, key: &str, value: Option<f64>, default: f64) -> Result<f64, CliError> {
        finite_value(&self.path, key, value.unwrap_or(default))
    }

    pub(super) fn inertia(&self, default: [f64; 3]) -> Result<Matrix3<f64>, CliError> {
        match &self.scenario.model.inertia {
            None => Ok(Matrix3::from_diagonal(&Vector3::from(default))),
            Some(v) => {
                if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                    return Err(self.key_error(
                        &format!("model.inertia[{i}]"),
                        format!("expected a finite number, got {}", v[i]),
                    ));
                }
                match v.len() {
                    3 => Ok(Matrix3::from_diagonal(&Vector3::new(v[0], v[1], v[2]))),
                    9 => Ok(Matrix3::from_row_slice(v)),
                    n => Err(self.key_error(
                        "model.inertia",
                        format!("expected 3 principal moments or 9 tensor entries, got {n} numbers"),
                    )),
                }
            }
        }
    }

    /// The initial attitude: `rotation_vector` or `quaternion` (default: the identity).
    pub(super) fn attitude(&self, init: &RigidInitialSpec) -> Result<SO3<f64>, CliError> {
        match (&init.rotation_vector, &init.quaternion) {
            (Some(_), Some(_)) => {
                Err(self.key_error("initial", "give either `rotation_vector` or `quaternion`, not both"))
            }
            (Some(_), None) => Ok(so3::exp(&self.vector3(
                "initial.rotation_vector",
                &init.rotation_vector,
                [0.0; 3],
            )?)),
            (None, Some(q)) => {
                if q.len() != 4 {
                    return Err(self.key_error(
                        "initial.quaternion",
                        format!("expected 4 numbers [w, x, y, z], got {}", q.len()),
                    ));
                }
                if let Some(i) = q.iter().position(|x| !x.is_finite()) {
                    return Err(self.key_error(
                        &format!("initial.quaternion[{i}]"),
                        format!("expected a finite number, got {}", q[i]),
                    ));
                }
                SO3::from_quaternion(&Quaternion::new(q[0], q[1], q[2], q[3]))
                    .map_err(|e| self.key_error("initial.quaternion", e.to_string()))
            }
            (None, None) => Ok(SO3::identity()),
        }
    }

    /// Body momentum from `velocity_key`/`momentum_key` (exactly one, or the default velocity).
    pub(super) fn body_momentum(
        &self,
        (velocity_key, velocity): (&str, &Option<Vec<f64>>),
        (momentum_key, momentum): (&str, &Option<Vec<f64>>),
        inertia: &Matrix3<f64>,
        default_velocity: [f64; 3],
    ) -> Result<Vector3<f64>, CliError> {
        match (velocity, momentum) {
            (Some(_), Some(_)) => Err(self.key_error(
                "initial",
                format!("give either `{velocity_key}` or `{momentum_key}`, not both"),
            )),
            (None, Some(_)) => self.vector3(&format!("initial.{momentum_key}"), momentum, [0.0; 3]),
            _ => Ok(inertia * self.vector3(&format!("initial.{velocity_key}"), velocity, default_velocity)?),
        }
    }
}
