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

use std::path::{Path, PathBuf};

use nalgebra::{Matrix3, Quaternion, SVector, Vector3};
use serde::Deserialize;
use serde_json::json;
use veselov::lgvi::{
    GroupState, GroupStepMap, SplitLieIntegrator, SplitReducedLagrangian, energy, integrate_group, rk4_group_reference,
    spatial_momentum,
};
use veselov::lie::{CayleyMap, ExpMap, GroupFamily, Retraction, RigidMotions, Rotations, SE3, SO3, so3};
use veselov::models::{FreeRigidBody, FreeRigidBodySE3, HeavyTop};
use veselov::run::GroupStepper;

use crate::error::CliError;
use crate::output::prepare_dir;
use crate::pipeline::finish::{finish, open_table_session, start_or_resume, t_of, totals};
use crate::pipeline::stream::TableSink;
use crate::pipeline::summary;
use crate::pipeline::table::{Acc, TableObserver};
use crate::pipeline::RunJob;
use crate::scenario::{
    OutputSpec, TimeSpec, check_time_and_output, finite_value, key_error, note_step_length, output_dir, parse_toml,
    planned_steps, step_count, step_length,
};
use crate::verify::{Study, VerifyJob, note_adjusted, study_steps};

/// The rigid-body model names.
pub const RIGID_MODELS: &[&str] = &["rigid-body", "heavy-top", "rigid-body-se3"];

/// A rigid-body scenario file.
#[derive(Debug, Clone, Deserialize)]
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
#[derive(Debug, Clone, Deserialize)]
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
#[derive(Debug, Clone, Deserialize)]
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
#[derive(Debug, Clone, Default, Deserialize)]
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
    path: PathBuf,
    scenario: RigidScenario,
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

    fn key_error(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    fn vector3(&self, key: &str, value: &Option<Vec<f64>>, default: [f64; 3]) -> Result<Vector3<f64>, CliError> {
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

    fn scalar(&self, key: &str, value: Option<f64>, default: f64) -> Result<f64, CliError> {
        finite_value(&self.path, key, value.unwrap_or(default))
    }

    fn inertia(&self, default: [f64; 3]) -> Result<Matrix3<f64>, CliError> {
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
    fn attitude(&self, init: &RigidInitialSpec) -> Result<SO3<f64>, CliError> {
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
    fn body_momentum(
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

impl RigidJob for RunJob {
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
        L: SplitReducedLagrangian<G, N> + Clone,
    {
        run_with_retraction(loaded, self, l, x0, conserved, retraction)
    }
}

impl RigidJob for VerifyJob {
    /// Convergence study against RK4 on the continuous Euler–Poincaré
    /// equations with 16 times the largest step count.
    fn go<G, L, const N: usize>(
        self,
        loaded: &LoadedRigid,
        l: L,
        x0: GroupState<G, N>,
        _conserved: &[(&str, usize)],
        retraction: &str,
    ) -> Result<(), CliError>
    where
        G: GroupFamily<N>,
        ExpMap: Retraction<N, Family = G>,
        CayleyMap: Retraction<N, Family = G>,
        L: SplitReducedLagrangian<G, N> + Clone,
    {
        let s = &loaded.scenario;
        let t_end = match s.time.t_end {
            Some(t) => t,
            None => x0.t + step_count(&s.time, s.method.dt) as f64 * s.method.dt,
        };
        let span = t_end - x0.t;
        let (steps, dts) = study_steps(&loaded.path, &self.dts, span)?;
        note_adjusted(&self.dts, &dts, self.quiet);
        let n_ref = 16 * steps.iter().copied().max().unwrap_or(1);
        let reference = rk4_group_reference::<G, CayleyMap, L, N>(&l, &x0, t_end, n_ref)
            .map_err(|e| CliError::Setup(format!("reference run failed: {e}")))?;
        let dir = prepare_dir(
            &self
                .out
                .clone()
                .unwrap_or_else(|| output_dir(&loaded.path, &s.output, None).join("verify")),
            self.force,
        )?;
        let study = Study {
            method: format!("lie-group trapezoid, {retraction} retraction"),
            order: 2,
            reference: format!("RK4 on the Euler–Poincaré equations, {n_ref} steps"),
            t_end,
            scale: reference.mu.amax().max(1.0),
        };
        let error = |x: &GroupState<G, N>| {
            let dr = (G::rotation(&x.g) - G::rotation(&reference.g)).amax();
            let dx = (G::translation(&x.g) - G::translation(&reference.g)).amax();
            dr.max(dx).max((x.mu - reference.mu).amax())
        };
        study.run(&dir, &dts, &steps, self.quiet, |n, h| {
            let setup = |e: veselov::Error| CliError::Setup(e.to_string());
            let traj = if retraction == "exp" {
                let mut map = SplitLieIntegrator::<G, ExpMap, L, N>::new(l.clone(), h).map_err(setup)?;
                integrate_group(&mut map, x0, n, n)
            } else {
                let mut map = SplitLieIntegrator::<G, CayleyMap, L, N>::new(l.clone(), h).map_err(setup)?;
                integrate_group(&mut map, x0, n, n)
            };
            Ok(match traj.failure {
                Some(e) => Err(e),
                None => Ok(error(traj.last())),
            })
        })
    }
}

/// Run a rigid-body scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    dispatch(path, text, job)
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

fn run_with_retraction<G, L, const N: usize>(
    loaded: &LoadedRigid,
    job: RunJob,
    l: L,
    x0: GroupState<G, N>,
    conserved: &[(&str, usize)],
    retraction: &str,
) -> Result<(), CliError>
where
    G: GroupFamily<N>,
    ExpMap: Retraction<N, Family = G>,
    CayleyMap: Retraction<N, Family = G>,
    L: SplitReducedLagrangian<G, N> + Clone,
{
    let dt = step_length(&loaded.scenario.time, loaded.scenario.method.dt);
    note_step_length(loaded.scenario.method.dt, dt, job.quiet);
    let setup = |e: veselov::Error| CliError::Setup(e.to_string());
    if retraction == "exp" {
        let map = SplitLieIntegrator::<G, ExpMap, L, N>::new(l.clone(), dt).map_err(setup)?;
        run_map(
            loaded,
            job,
            &l,
            map,
            x0,
            conserved,
            "lie-group trapezoid, exp retraction",
        )
    } else {
        let map = SplitLieIntegrator::<G, CayleyMap, L, N>::new(l.clone(), dt).map_err(setup)?;
        run_map(
            loaded,
            job,
            &l,
            map,
            x0,
            conserved,
            "lie-group trapezoid, Cayley retraction",
        )
    }
}

/// `t, R00..R22, [x0..x2], Pi0..Pi2, [P0..P2], energy, pi_x..pi_z (spatial), J_.., orthogonality_defect`.
fn header_of<const N: usize>(conserved: &[(&str, usize)]) -> Vec<String> {
    let mut header = vec!["t".to_string()];
    header.extend((0..3).flat_map(|i| (0..3).map(move |j| format!("R{i}{j}"))));
    if N == 6 {
        header.extend((0..3).map(|i| format!("x{i}")));
    }
    header.extend((0..3).map(|i| format!("Pi{i}")));
    if N == 6 {
        header.extend((0..3).map(|i| format!("P{i}")));
    }
    header.push("energy".into());
    let axes = ["x", "y", "z"];
    header.extend(axes.iter().map(|a| format!("pi_{a}")));
    if N == 6 {
        header.extend(axes.iter().map(|a| format!("p_{a}")));
    }
    header.extend(conserved.iter().map(|(name, _)| name.to_string()));
    header.push("orthogonality_defect".into());
    header
}

/// The row of `x` under [`header_of`].
fn row_of<G, L, const N: usize>(l: &L, x: &GroupState<G, N>, conserved: &[(&str, usize)]) -> Vec<f64>
where
    G: GroupFamily<N>,
    L: SplitReducedLagrangian<G, N>,
{
    let mut row = vec![x.t];
    let r = G::rotation(&x.g);
    row.extend((0..3).flat_map(|i| (0..3).map(move |j| r[(i, j)])));
    if N == 6 {
        row.extend(G::translation(&x.g).iter());
    }
    row.extend(x.mu.iter());
    row.push(energy(l, x).unwrap_or(f64::NAN));
    let spatial = spatial_momentum(x);
    row.extend(spatial.iter());
    row.extend(conserved.iter().map(|(_, k)| spatial[*k]));
    row.push(G::orthogonality_defect(&x.g));
    row
}

fn run_map<G, L, M, const N: usize>(
    loaded: &LoadedRigid,
    job: RunJob,
    l: &L,
    mut map: M,
    x0: GroupState<G, N>,
    conserved: &[(&str, usize)],
    method: &str,
) -> Result<(), CliError>
where
    G: GroupFamily<N>,
    L: SplitReducedLagrangian<G, N>,
    M: GroupStepMap<G, N>,
{
    x0.check().map_err(|e| loaded.key_error("initial", e.to_string()))?;
    let s = &loaded.scenario;
    let (steps, dt) = (step_count(&s.time, s.method.dt), step_length(&s.time, s.method.dt));
    // Checked before the session opens its output directory.
    let at_steps = s.output.steps_at_times(&loaded.path, x0.t, dt, steps, job.quiet)?;
    let header = header_of::<N>(conserved);
    let (mut session, positions, words) = open_table_session(
        &job,
        &loaded.path,
        (&s.time, &s.output),
        (planned_steps(&s.time, s.method.dt), Some(dt)),
        header.len(),
        "rigid-body",
    )?;
    let sink = TableSink::create(
        &session.dir,
        "trajectory",
        &header,
        &s.output.formats,
        steps / s.output.every + 2,
        positions,
    )?;
    let mut table = TableObserver::new(
        header,
        Box::new(move |x: &GroupState<G, N>, _| row_of(l, x, conserved)),
        sink,
        s.output.every,
    )
    .at_steps(at_steps);
    table.track("energy", Acc::Dev);
    for (name, _) in conserved {
        table.track(name, Acc::Dev);
    }
    table.track("orthogonality_defect", Acc::Max);
    let mut stepper = GroupStepper::new(&mut map, x0.t);
    let mut x = x0;
    let outcome = start_or_resume(&mut session, &mut stepper, &mut x, &mut table, &words, steps)?;
    let iterations = totals(&session, &outcome).iterations;
    let wall = session.wall_seconds();
    let t_final = t_of(outcome.last_step, x0.t, dt);
    let orthogonality =
        |t: &TableObserver<'_, GroupState<G, N>>| t.column("orthogonality_defect").map_or(0.0, |c| c.value.max(0.0));
    finish(
        &s.output,
        &session,
        table,
        outcome.status.clone(),
        |t, status| {
            let momentum_errors: serde_json::Map<String, serde_json::Value> = conserved
                .iter()
                .map(|(name, _)| (name.to_string(), json!(t.column(name).map_or(0.0, |c| c.value))))
                .collect();
            let energy = t.column("energy");
            let own = json!({
                "scenario": loaded.path.display().to_string(),
                "model": s.model.name,
                "method": method,
                "retraction": s.method.retraction,
                "order": 2,
                "dt": dt,
                "steps_requested": steps,
                "energy_initial": energy.map(|c| c.first),
                "energy_error_max": energy.map_or(0.0, |c| c.value),
                "energy_error_max_relative": energy
                    .map_or(serde_json::Value::Null, |c| summary::relative_energy_error(c.value, c.first)),
                "momentum_error_max": momentum_errors,
                "orthogonality_defect_max": orthogonality(t),
            });
            summary::common(status, outcome.last_step, t_final, wall, iterations, own)
        },
        |t| {
            format!(
                "{method}: {} steps to t = {t_final}, max |E − E₀| = {:.3e}, max |RᵀR − I| = {:.1e}",
                outcome.last_step,
                t.column("energy").map_or(0.0, |c| c.value),
                orthogonality(t)
            )
        },
    )
}
