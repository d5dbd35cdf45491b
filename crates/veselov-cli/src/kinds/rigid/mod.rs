//! Rigid-body scenarios: the free rigid body and the heavy top on SO(3) and
//! the free-flying rigid body on SE(3), integrated by the Lie-group
//! variational integrators of `veselov::lgvi`.
//!
//! ```toml
//! [model]
//! name = "heavy-top"            # rigid-body | heavy-top | rigid-body-se3
//! inertia = [1.0, 1.0, 0.5]     # principal moments, or 9 entries row by row
//! mass = 1.0                    # heavy-top, rigid-body-se3
//! centre_of_mass = [0, 0, 1]    # heavy-top: body frame, from the pivot
//! gravity = 9.81                # heavy-top: along −z
//! [method]
//! retraction = "cayley"         # cayley | exp
//! dt = 0.01
//! [initial]
//! rotation_vector = [0.3, 0, 0] # or quaternion = [w, x, y, z]
//! angular_velocity = [0, 0, 10] # body frame; or angular_momentum (body frame)
//! position = [0, 0, 0]          # rigid-body-se3
//! velocity = [1, 0, 0]          # rigid-body-se3: body frame; or linear_momentum (body frame)
//! [time]
//! t_end = 10.0
//! ```
//!
//! [`schema`] reads the file; [`dispatch`] builds the body and its initial
//! state and hands them to a job: `veselov run` ([`run`]) or `veselov
//! verify` ([`verify`]).

pub mod run;
pub mod schema;
pub mod verify;

use std::path::Path;

use nalgebra::{Matrix3, SVector, Vector3};
use veselov::lgvi::{GroupState, SplitReducedLagrangian};
use veselov::lie::{CayleyMap, ExpMap, GroupFamily, Retraction, RigidMotions, Rotations, SE3, so3};
use veselov::models::{FreeRigidBody, FreeRigidBodySE3, HeavyTop};

use super::ScenarioKind;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;
use schema::LoadedRigid;

/// The rigid-body model names.
pub const RIGID_MODELS: &[&str] = &["rigid-body", "heavy-top", "rigid-body-se3"];

/// Something to do with a rigid-body scenario once its body and initial
/// state are built.
pub trait RigidJob {
    /// Do it with the retraction chosen in `[method]`.
    fn go<G, L, const N: usize>(
        self,
        loaded: &LoadedRigid,
        l: L,
        x0: GroupState<G, N>,
        conserved: &[(&str, usize)],
        retraction: &str,
    ) -> Result<(), CliError>
    where
        G: GroupFamily<N>,
        ExpMap: Retraction<N, Family = G>,
        CayleyMap: Retraction<N, Family = G>,
        L: SplitReducedLagrangian<G, N> + Clone;
}

/// The rigid-body kind.
pub struct RigidKind;

impl ScenarioKind for RigidKind {
    fn name(&self) -> &'static str {
        "rigid"
    }

    fn title(&self) -> &'static str {
        "Rigid-body scenarios on SO(3) and SE(3)"
    }

    fn schema(&self) -> serde_json::Value {
        crate::keys::schema::schema_of::<schema::RigidScenario>()
    }

    fn example(&self) -> (&'static str, &'static str) {
        ("heavy_top.toml", include_str!("../../../../../examples/heavy_top.toml"))
    }

    fn models(&self) -> &'static [&'static str] {
        RIGID_MODELS
    }

    fn check(&self, path: &Path, text: &str) -> Result<(), CliError> {
        LoadedRigid::parse(path, text).map(drop)
    }

    fn run(&self, path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
        dispatch(path, text, job)
    }

    fn verify(&self, path: &Path, text: &str, job: VerifyJob) -> Result<(), CliError> {
        dispatch(path, text, job)
    }
}

/// Build the scenario's body and initial state and hand them to `job`.
pub fn dispatch<J: RigidJob>(path: &Path, text: &str, job: J) -> Result<(), CliError> {
    let loaded = LoadedRigid::parse(path, text)?;
    let init = loaded.scenario.initial.clone().unwrap_or_default();
    let retraction = loaded.scenario.method.retraction.clone();
    if retraction != "cayley" && retraction != "exp" {
        return Err(loaded.key_error(
            "method.retraction",
            format!("unknown retraction `{retraction}`, expected \"cayley\" or \"exp\""),
        ));
    }
    let m = &loaded.scenario.model;
    let setup = |e: veselov::Error| loaded.key_error("model", e.to_string());
    let so3_only = |keys: &[(&str, bool)]| -> Result<(), CliError> {
        for (k, present) in keys {
            if *present {
                return Err(loaded.key_error(k, format!("not used by model `{}`", m.name)));
            }
        }
        Ok(())
    };
    match m.name.as_str() {
        "rigid-body" => {
            so3_only(&[
                ("model.mass", m.mass.is_some()),
                ("model.centre_of_mass", m.centre_of_mass.is_some()),
                ("model.gravity", m.gravity.is_some()),
                ("initial.position", init.position.is_some()),
                ("initial.velocity", init.velocity.is_some()),
                ("initial.linear_momentum", init.linear_momentum.is_some()),
            ])?;
            let inertia = loaded.inertia([1.0, 2.0, 3.0])?;
            let body = FreeRigidBody::new(inertia).map_err(setup)?;
            let pi = loaded.body_momentum(
                ("angular_velocity", &init.angular_velocity),
                ("angular_momentum", &init.angular_momentum),
                &inertia,
                [0.05, 1.0, 0.05],
            )?;
            let x0 = GroupState::<Rotations, 3>::new(loaded.scenario.time.t0, loaded.attitude(&init)?, pi);
            let conserved: &[(&str, usize)] = &[("J_x", 0), ("J_y", 1), ("J_z", 2)];
            job.go(&loaded, body, x0, conserved, &retraction)
        }
        "heavy-top" => {
            so3_only(&[
                ("initial.position", init.position.is_some()),
                ("initial.velocity", init.velocity.is_some()),
                ("initial.linear_momentum", init.linear_momentum.is_some()),
            ])?;
            let inertia = loaded.inertia([1.0, 1.0, 0.5])?;
            let top = HeavyTop::new(
                inertia,
                loaded.scalar("model.mass", m.mass, 1.0)?,
                loaded.vector3("model.centre_of_mass", &m.centre_of_mass, [0.0, 0.0, 1.0])?,
                loaded.scalar("model.gravity", m.gravity, 9.81)?,
            )
            .map_err(setup)?;
            let pi = loaded.body_momentum(
                ("angular_velocity", &init.angular_velocity),
                ("angular_momentum", &init.angular_momentum),
                &inertia,
                [0.0, 0.0, 20.0],
            )?;
            let attitude = match (&init.rotation_vector, &init.quaternion) {
                (None, None) => so3::exp(&Vector3::new(0.3, 0.0, 0.0)),
                _ => loaded.attitude(&init)?,
            };
            let x0 = GroupState::<Rotations, 3>::new(loaded.scenario.time.t0, attitude, pi);
            job.go(&loaded, top, x0, &[("J_z", 2)], &retraction)
        }
        "rigid-body-se3" => {
            so3_only(&[
                ("model.centre_of_mass", m.centre_of_mass.is_some()),
                ("model.gravity", m.gravity.is_some()),
            ])?;
            let inertia = loaded.inertia([1.0, 2.0, 3.0])?;
            let mass = loaded.scalar("model.mass", m.mass, 1.0)?;
            let body = FreeRigidBodySE3::new(inertia, mass).map_err(setup)?;
            let pi = loaded.body_momentum(
                ("angular_velocity", &init.angular_velocity),
                ("angular_momentum", &init.angular_momentum),
                &inertia,
                [0.05, 1.0, 0.05],
            )?;
            let lin = loaded.body_momentum(
                ("velocity", &init.velocity),
                ("linear_momentum", &init.linear_momentum),
                &(Matrix3::identity() * mass),
                [1.0, 0.0, 0.0],
            )?;
            let position = loaded.vector3("initial.position", &init.position, [0.0; 3])?;
            let g0 = SE3::new(loaded.attitude(&init)?, position);
            let mu = SVector::<f64, 6>::new(pi[0], pi[1], pi[2], lin[0], lin[1], lin[2]);
            let x0 = GroupState::<RigidMotions, 6>::new(loaded.scenario.time.t0, g0, mu);
            let conserved: &[(&str, usize)] = &[
                ("J_angular_x", 0),
                ("J_angular_y", 1),
                ("J_angular_z", 2),
                ("J_linear_x", 3),
                ("J_linear_y", 4),
                ("J_linear_z", 5),
            ];
            job.go(&loaded, body, x0, conserved, &retraction)
        }
        other => Err(loaded.key_error(
            "model.name",
            format!(
                "unknown rigid-body model `{other}`, expected one of {}",
                RIGID_MODELS.join(", ")
            ),
        )),
    }
}
