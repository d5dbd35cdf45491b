//! Which kind of scenario a file holds, decided by `[model] name` before the
//! file is parsed against the schema of that kind (each schema rejects the
//! keys of the others).

use std::path::Path;

use crate::error::CliError;

/// The kinds of scenario the command runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScenarioKind {
    /// Lagrangian mechanics in generalised coordinates (built-in or custom).
    Mechanics,
    /// Rigid bodies on SO(3) and SE(3).
    RigidBody,
    /// Fields on a 1+1 spacetime lattice.
    Field,
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
    let table: toml::Table = toml::from_str(text).map_err(|e| CliError::Parse {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let name = table.get("model").and_then(|m| m.get("name")).and_then(|n| n.as_str());
    Ok(match name {
        Some(n) if crate::rigid::RIGID_MODELS.contains(&n) => ScenarioKind::RigidBody,
        Some(n) if crate::field::FIELD_MODELS.contains(&n) => ScenarioKind::Field,
        _ => ScenarioKind::Mechanics,
    })
}
