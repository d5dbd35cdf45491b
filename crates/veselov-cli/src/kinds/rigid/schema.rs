//! The schema of a rigid-body scenario file (`[model]`, `[method]`,
//! `[time]`, `[initial]`, `[output]`), parsed with key-level errors, and the
//! values it gives: inertia, attitude, body momenta.

use std::path::{Path, PathBuf};

use nalgebra::{Matrix3, Quaternion, Vector3};
use serde::Deserialize;
use veselov::lie::{SO3, so3};

use crate::error::CliError;
use crate::output::number;
use crate::scenario::{Array, List, OutputSpec, TimeSpec, check_time_and_output, finite_value, key_error, parse_toml};

/// A rigid-body scenario: the body, the Lie-group integrator and its step,
/// the time span, the initial attitude and motion, and the outputs.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidScenario {
    /// The body: the free rigid body (`rigid-body`) or the heavy top
    /// (`heavy-top`) on SO(3), or the free-flying body on SE(3)
    /// (`rigid-body-se3`), with its inertia and, where the model has them, its
    /// mass, centre of mass and gravity.
    pub model: RigidModelSpec,
    /// The Lie-group variational integrator (trapezoidal, order 2, symplectic):
    /// its retraction and time step.
    pub method: RigidMethodSpec,
    /// When the run starts and ends: give either `t_end` or `steps`.
    pub time: TimeSpec,
    /// The initial attitude and motion (and position on SE(3)); every key left
    /// out takes the model's default (`veselov models`), and the whole table
    /// may be left out.
    pub initial: Option<RigidInitialSpec>,
    /// What the run writes (`trajectory.csv`, `summary.json`, the plots) and
    /// where.
    #[serde(default)]
    pub output: OutputSpec,
    /// The thresholds beyond which the run's summary carries a warning.
    #[serde(default)]
    pub checks: crate::verdict::ChecksSpec,
}

/// The body: its model, inertia and, for the heavy top and the SE(3) body,
/// mass, centre of mass and gravity.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidModelSpec {
    /// The model: `rigid-body` (free, on SO(3)), `heavy-top` (a top with a
    /// fixed pivot under gravity, on SO(3)) or `rigid-body-se3` (rotating and
    /// translating in free flight).
    #[schemars(extend("enum" = ["rigid-body", "heavy-top", "rigid-body-se3"]))]
    pub name: String,
    /// Inertia tensor in the body frame (about the pivot for the heavy top): the
    /// 3 principal moments, or the 9 entries of the full tensor row by row.
    /// Default [1, 2, 3] for `rigid-body` and `rigid-body-se3`, [1, 1, 0.5] for
    /// `heavy-top`.
    #[schemars(extend("unit" = "kg·m²", "x-type" = "array of 3 or 9 floats"))]
    pub inertia: Option<List<f64>>,
    /// Mass of the body (`heavy-top` and `rigid-body-se3`; refused by
    /// `rigid-body`).
    #[schemars(extend("unit" = "kg", "default" = 1.0))]
    pub mass: Option<f64>,
    /// `heavy-top` only: the centre of mass in the body frame, measured from
    /// the pivot.
    #[schemars(extend("unit" = "m", "default" = [0.0, 0.0, 1.0]))]
    pub centre_of_mass: Option<Array<f64, 3>>,
    /// `heavy-top` only: the gravitational acceleration, acting along −z.
    #[schemars(extend("unit" = "m/s²", "default" = 9.81))]
    pub gravity: Option<f64>,
}

/// The Lie-group integrator: the retraction that advances the attitude, and
/// the time step.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidMethodSpec {
    /// The map from the Lie algebra to the group that advances the attitude:
    /// `cayley` (the Cayley map, rational and cheap) or `exp` (the exponential,
    /// along the group's geodesics); both are of order 2 and conserve the same
    /// momenta.
    #[serde(default = "cayley")]
    #[schemars(extend("enum" = ["cayley", "exp"]))]
    pub retraction: String,
    /// Time step (> 0). With `t_end` (and no `steps`) it is adjusted to
    /// (t_end − t0)/n, n = round((t_end − t0)/dt), so that the run ends exactly
    /// at `t_end`.
    #[schemars(extend("unit" = "s"))]
    pub dt: f64,
}

fn cayley() -> String {
    "cayley".into()
}

/// The initial attitude (a rotation vector or a quaternion), angular motion
/// (an angular velocity or momentum, body frame) and, on SE(3), position and
/// linear motion; each key left out takes the model's default.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidInitialSpec {
    /// Initial attitude as a rotation vector, the axis times the angle; give
    /// either this or `quaternion`. Default: the identity, except [0.3, 0, 0]
    /// for `heavy-top`.
    #[schemars(extend("unit" = "rad"))]
    pub rotation_vector: Option<Array<f64, 3>>,
    /// Initial attitude as a quaternion [w, x, y, z] (Hamilton convention; it
    /// need not be normalised); give either this or `rotation_vector`.
    pub quaternion: Option<Array<f64, 4>>,
    /// Initial angular velocity Ω in the body frame; give either this or
    /// `angular_momentum`. Default [0.05, 1, 0.05] (near the unstable middle
    /// axis) for `rigid-body` and `rigid-body-se3`, [0, 0, 20] for `heavy-top`.
    #[schemars(extend("unit" = "rad/s"))]
    pub angular_velocity: Option<Array<f64, 3>>,
    /// Initial angular momentum Π = 𝕀Ω in the body frame; give either this or
    /// `angular_velocity`.
    #[schemars(extend("unit" = "kg·m²/s"))]
    pub angular_momentum: Option<Array<f64, 3>>,
    /// `rigid-body-se3` only: the initial position of the centre of mass.
    #[schemars(extend("unit" = "m", "default" = [0.0, 0.0, 0.0]))]
    pub position: Option<Array<f64, 3>>,
    /// `rigid-body-se3` only: the initial velocity of the centre of mass in the
    /// body frame; give either this or `linear_momentum`.
    #[schemars(extend("unit" = "m/s", "default" = [1.0, 0.0, 0.0]))]
    pub velocity: Option<Array<f64, 3>>,
    /// `rigid-body-se3` only: the initial linear momentum m v in the body frame;
    /// give either this or `velocity`.
    #[schemars(extend("unit" = "kg·m/s"))]
    pub linear_momentum: Option<Array<f64, 3>>,
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
        value: &Option<Array<f64, 3>>,
        default: [f64; 3],
    ) -> Result<Vector3<f64>, CliError> {
        Array::or(value, &self.path, key, default).map(Vector3::from)
    }

    pub(super) fn scalar(&self, key: &str, value: Option<f64>, default: f64) -> Result<f64, CliError> {
        finite_value(&self.path, key, value.unwrap_or(default))
    }

    pub(super) fn inertia(&self, default: [f64; 3]) -> Result<Matrix3<f64>, CliError> {
        match &self.scenario.model.inertia {
            None => Ok(Matrix3::from_diagonal(&Vector3::from(default))),
            Some(v) => {
                let v = v.values(
                    &self.path,
                    "model.inertia",
                    &[3, 9],
                    " (the principal moments, or the tensor's entries row by row)",
                )?;
                let inertia = if v.len() == 3 {
                    Matrix3::from_diagonal(&Vector3::new(v[0], v[1], v[2]))
                } else {
                    Matrix3::from_row_slice(&v)
                };
                self.check_principal_moments(&inertia)?;
                Ok(inertia)
            }
        }
    }

    /// Refuse an inertia no rigid body has: the principal moments of a body
    /// satisfy the triangle inequality I₁ + I₂ ≥ I₃ (each moment is a sum of
    /// two of the three second moments ∫x², ∫y², ∫z² ≥ 0), with equality
    /// for a flat body. A round-off of 1e-12 of the largest moment is
    /// allowed. Symmetry and positive definiteness are the library's checks.
    fn check_principal_moments(&self, inertia: &Matrix3<f64>) -> Result<(), CliError> {
        let symmetric = (inertia - inertia.transpose()).amax() <= 1e-12 * inertia.amax();
        if !symmetric {
            return Ok(());
        }
        let mut m: Vec<f64> = inertia.symmetric_eigenvalues().iter().copied().collect();
        m.sort_by(f64::total_cmp);
        if m[0] > 0.0 && m[0] + m[1] < m[2] * (1.0 - 1e-12) {
            return Err(self.key_error(
                "model.inertia",
                format!(
                    "principal moments {}, {} and {} violate the triangle inequality I₁ + I₂ ≥ I₃ that every \
                     rigid body satisfies ({} + {} < {})",
                    number(m[0]),
                    number(m[1]),
                    number(m[2]),
                    number(m[0]),
                    number(m[1]),
                    number(m[2])
                ),
            ));
        }
        Ok(())
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
                let [w, x, y, z] = q.values(&self.path, "initial.quaternion")?;
                SO3::from_quaternion(&Quaternion::new(w, x, y, z))
                    .map_err(|e| self.key_error("initial.quaternion", e.to_string()))
            }
            (None, None) => Ok(SO3::identity()),
        }
    }

    /// Body momentum from `velocity_key`/`momentum_key` (exactly one, or the default velocity).
    pub(super) fn body_momentum(
        &self,
        (velocity_key, velocity): (&str, &Option<Array<f64, 3>>),
        (momentum_key, momentum): (&str, &Option<Array<f64, 3>>),
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
