//! Which kind of scenario a file holds, decided by `[model] name` before the
//! file is parsed against the schema of that kind (each schema rejects the
//! keys of the others): the table of kinds ([`KINDS`]) on which `veselov
//! run` and `veselov verify` dispatch.

use std::path::Path;

use crate::error::CliError;
use crate::kinds::ScenarioKind;
use crate::kinds::beam::BeamKind;
use crate::kinds::cfk::CfkKind;
use crate::kinds::lattice::LatticeKind;
use crate::kinds::mechanics::MechanicsKind;
use crate::kinds::rigid::RigidKind;
use crate::kinds::rod::RodKind;
use crate::pipeline::RunJob;
use crate::verify::VerifyJob;

/// The kinds of scenario the command runs, in the order they are tried: the
/// first that takes a file runs it (the CFK lattice before the 1+1 lattice:
/// both run the field models, the CFK one those on a `[lattice]` of `kind =
/// "cfk"`).
pub const KINDS: &[&dyn ScenarioKind] = &[&RigidKind, &CfkKind, &LatticeKind, &RodKind, &BeamKind, &MechanicsKind];

/// The kind of a file whose `[model] name` is not a string (or is missing):
/// the mechanics schema names what is wrong with it.
const FALLBACK: &dyn ScenarioKind = &MechanicsKind;

/// Read a scenario file.
pub fn read(path: &Path) -> Result<String, CliError> {
    std::fs::read_to_string(path).map_err(|e| CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// The kind of the scenario in `text` (attributed to `path`).
pub fn kind(path: &Path, text: &str) -> Result<&'static dyn ScenarioKind, CliError> {
    let table: toml::Table = crate::scenario::parse_toml(path, text)?;
    let name = table.get("model").and_then(|m| m.get("name")).and_then(|n| n.as_str());
    // A name that is not a string is named by the mechanics schema.
    let Some(name) = name else { return Ok(FALLBACK) };
    if let Some(kind) = KINDS.iter().find(|k| k.takes(name, &table)) {
        return Ok(*kind);
    }
    if !model_names().contains(&name) {
        // Named before the file is read against a kind's schema, which
        // would otherwise report that kind's missing keys first.
        return Err(unknown_model(path, name));
    }
    Ok(FALLBACK)
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
    let kind = kind(path, text)?;
    let quiet = job.quiet;
    match kind.run(path, text, job) {
        // Resuming a completed run does nothing, and that is no failure.
        Err(note @ CliError::AlreadyComplete { .. }) => {
            if !quiet {
                eprintln!("note: {note}");
            }
            Ok(())
        }
        result => result.map_err(|e| point_to_keys(e, kind)),
    }
}

/// A parse error about an unknown or missing key, with where the kind's
/// keys are documented (`veselov keys KIND`).
fn point_to_keys(error: CliError, kind: &dyn ScenarioKind) -> CliError {
    match error {
        CliError::Parse { file, message } if message.contains("unknown field") || message.contains("missing field") => {
            let message = format!("{message}\n(the keys of this kind: `veselov keys {}`)", kind.name());
            CliError::Parse { file, message }
        }
        other => other,
    }
}

/// Parse and validate the scenario `text` attributed to `path`, whatever
/// its kind, without running it.
pub fn check_text(path: &Path, text: &str) -> Result<(), CliError> {
    let kind = kind(path, text)?;
    kind.check(path, text).map_err(|e| point_to_keys(e, kind))
}

/// Convergence study of the scenario file at `path` (`veselov verify`).
pub fn verify_scenario(path: &Path, job: VerifyJob) -> Result<(), CliError> {
    verify_text(path, &read(path)?, job)
}

/// Convergence study of the scenario `text` attributed to `path`.
pub fn verify_text(path: &Path, text: &str, job: VerifyJob) -> Result<(), CliError> {
    let kind = kind(path, text)?;
    kind.verify(path, text, job).map_err(|e| point_to_keys(e, kind))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every model `veselov models` lists is run by a kind of the table.
    #[test]
    fn every_listed_model_has_a_kind() {
        for name in model_names() {
            assert!(
                KINDS.iter().any(|k| k.models().contains(&name)),
                "no kind runs `{name}`"
            );
        }
    }
}
