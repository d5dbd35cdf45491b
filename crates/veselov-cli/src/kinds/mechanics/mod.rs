//! Mechanics scenarios: Lagrangian mechanics in generalised coordinates, a
//! built-in model of the catalogue or a custom one given by expressions
//! ([`custom`]), integrated by the Galerkin variational integrators with
//! fixed steps (Marsden & West 2001, §2.6; seed 004 §4.3; forces through the
//! discrete Lagrange–d'Alembert principle, seed 004 Prop. 7.4) or by the
//! variable-step symplectic-energy-momentum (SEM) integrators (seed 001).
//!
//! [`schema`] reads the file; [`systems`] turns its `[model]` into a system
//! of fixed dimension and hands it to a job: `veselov run` ([`run`] with
//! fixed steps, [`sem_run`] with variable ones, [`dynamic_run`] for custom
//! models with more coordinates than the fixed dimensions) or `veselov
//! verify` ([`verify`]).

pub mod custom;
pub mod dynamic_run;
pub mod run;
pub mod schema;
pub mod sem_run;
pub mod systems;
pub mod verify;

use std::path::Path;

use super::ScenarioKind;
use crate::catalog::Choice;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;
use run::{resolve_choice, run_fixed};
use schema::LoadedScenario;
use sem_run::run_variable;
use systems::{Job, System, dispatch};

impl Job for RunJob {
    fn run<const N: usize>(self, scenario: &LoadedScenario, system: System<N>) -> Result<(), CliError> {
        match resolve_choice(scenario)? {
            Choice::Fixed(method) => run_fixed(&self, scenario, system, method),
            Choice::Variable(rule) => run_variable(&self, scenario, system, rule),
        }
    }

    fn run_dynamic(self, scenario: &LoadedScenario) -> Result<(), CliError> {
        dynamic_run::run(&self, scenario)
    }
}

/// The mechanics model names: the built-in models and `custom`.
pub const MECHANICS_MODELS: &[&str] = &[
    "harmonic",
    "pendulum",
    "kepler",
    "henon-heiles",
    "double-pendulum",
    "damped-oscillator",
    "van-der-pol",
    "damped-kepler",
    "custom",
];

/// The mechanics kind.
pub struct MechanicsKind;

impl ScenarioKind for MechanicsKind {
    fn name(&self) -> &'static str {
        "mechanics"
    }

    fn title(&self) -> &'static str {
        "Mechanics scenarios (built-in or custom Lagrangians)"
    }

    fn schema(&self) -> serde_json::Value {
        crate::keys::schema::schema_of::<schema::Scenario>()
    }

    fn example(&self) -> (&'static str, &'static str) {
        (
            "kepler_custom.toml",
            include_str!("../../../../../examples/kepler_custom.toml"),
        )
    }

    fn models(&self) -> &'static [&'static str] {
        MECHANICS_MODELS
    }

    fn check(&self, path: &Path, text: &str) -> Result<(), CliError> {
        LoadedScenario::parse(path, text).map(drop)
    }

    fn run(&self, path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
        LoadedScenario::parse(path, text).and_then(|s| dispatch(&s, job))
    }

    fn verify(&self, path: &Path, text: &str, job: VerifyJob) -> Result<(), CliError> {
        LoadedScenario::parse(path, text).and_then(|s| dispatch(&s, job))
    }
}
