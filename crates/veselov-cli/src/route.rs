//! Which kind of scenario a file holds, decided by `[model] name` before the
//! file is parsed against the schema of that kind (each schema rejects the
//! keys of the others).

use std::path::Path;

use crate::error::CliError;
use crate::kinds::{beam, cfk, lattice, mechanics, rigid, rod};
use crate::pipeline::RunJob;
use crate::verify;

/// The kinds of scenario the command runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScenarioKind {
    /// Lagrangian mechanics in generalised coordinates (built-in or custom).
    Mechanics,
    /// Rigid bodies on SO(3) and SE(3).
    RigidBody,
    /// Fields on a 1+1 spacetime lattice.
    Field,
    /// The Cosserat rod on the leapfrog CFK lattice.
    Rod,
    /// The geometrically exact beam on SE(3) (seed 000).
    Beam,
}

/// Read a scenario file.
pub fn read(path: &Path) -> Result<String, CliError> {
    std::fs::read_to_string(path).map_err(|e| CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// The kind of the scenario in `text` (attributed to `path`).
pub fn kind(path: &Path, text: &str) -> Result<ScenarioKind, CliError> {
    let table: toml::Table = crate::scenario::parse_toml(path, text)?;
    let name = table.get("model").and_then(|m| m.get("name")).and_then(|n| n.as_str());
    Ok(match name {
        Some(n) if rigid::RIGID_MODELS.contains(&n) => ScenarioKind::RigidBody,
        Some(n) if lattice::schema::FIELD_MODELS.contains(&n) => ScenarioKind::Field,
        Some(rod::schema::ROD_MODEL) => ScenarioKind::Rod,
        Some(beam::schema::BEAM_MODEL) => ScenarioKind::Beam,
        Some(n) if !model_names().contains(&n) => {
            // Named before the file is read against a kind's schema, which
            // would otherwise report that kind's missing keys first.
            return Err(unknown_model(path, n));
        }
        // A name that is not a string is named by the mechanics schema.
        _ => ScenarioKind::Mechanics,
    })
}

/// Every model name the command knows, of every kind (those `veselov
/// models` lists).
pub fn model_names() -> Vec<&'static str> {
    let catalog = crate::catalog::MODELS.iter().map(|m| m.name);
    catalog
        .chain(crate::catalog::STRUCTURES.iter().map(|m| m.name))
        .collect()
}

/// The error for an unknown `model.name`: every known name, and the one
/// meant when `name` differs from it only in case or in `_` for `-`.
fn unknown_model(path: &Path, name: &str) -> CliError {
    let names = model_names();
    let plain = |s: &str| s.to_lowercase().replace(['_', ' '], "-");
    let hint = names
        .iter()
        .find(|k| plain(k) == plain(name))
        .map(|k| format!(" (did you mean `{k}`?)"))
        .unwrap_or_default();
    crate::scenario::key_error(
        path,
        "model.name",
        format!("unknown model `{name}`{hint}, expected one of: {}", names.join(", ")),
    )
}

/// Run the scenario file at `path` (the entry point of `veselov run`).
pub fn run_scenario(path: &Path, job: RunJob) -> Result<(), CliError> {
    run_text(path, &read(path)?, job)
}

/// Run the scenario `text` attributed to `path` (for messages and the
/// default output directory), whatever its kind: parse and validate, build
/// the kind's job and run it on the pipeline into the job's directory, on a
/// thread of the rayon pool ([`veselov::run::on_pool`]: the lattice
/// marchers' parallel levels are cheap to hand over from there).
pub fn run_text(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let job = RunJob {
        scenario: Some(text.to_owned()),
        ..job
    };
    veselov::run::on_pool(|| run_kind(path, text, job))
}

fn run_kind(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    match kind(path, text)? {
        ScenarioKind::RigidBody => rigid::run(path, text, job),
        ScenarioKind::Field if cfk::is_cfk(text) => cfk::run::run(path, text, job),
        ScenarioKind::Field => lattice::run::run(path, text, job),
        ScenarioKind::Rod => rod::run::run(path, text, job),
        ScenarioKind::Beam => beam::run::run(path, text, job),
        ScenarioKind::Mechanics => mechanics::run(path, text, job),
    }
}

/// Convergence study of the scenario file at `path` (`veselov verify`).
pub fn verify_scenario(path: &Path, job: verify::VerifyJob) -> Result<(), CliError> {
    verify_text(path, &read(path)?, job)
}

/// Convergence study of the scenario `text` attributed to `path`.
pub fn verify_text(path: &Path, text: &str, job: verify::VerifyJob) -> Result<(), CliError> {
    match kind(path, text)? {
        ScenarioKind::RigidBody => rigid::dispatch(path, text, job),
        ScenarioKind::Field => Err(CliError::Setup(format!(
            "{}: `veselov verify` does not take lattice-field scenarios; the convergence of the schemes \
             is measured by the test suite (crates/veselov/tests/field/)",
            path.display()
        ))),
        ScenarioKind::Beam => Err(CliError::Setup(format!(
            "{}: `veselov verify` does not take beam scenarios; the beam's convergence (Timoshenko's \
             frequencies and deflection) is measured by the test suite (crates/veselov/tests/beam/)",
            path.display()
        ))),
        ScenarioKind::Rod => Err(CliError::Setup(format!(
            "{}: `veselov verify` does not take rod scenarios; the rod's convergence (Timoshenko's \
             cantilever deflection at second order) is measured by the test suite (crates/veselov/tests/rod/rod_ends.rs)",
            path.display()
        ))),
        ScenarioKind::Mechanics => mechanics::verify(path, text, job),
    }
}
