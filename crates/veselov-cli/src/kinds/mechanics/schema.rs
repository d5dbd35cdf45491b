//! The schema of a mechanics scenario file (`[model]`, `[method]`,
//! `[time]`, `[initial]`, `[output]`), parsed with key-level errors and
//! checked where the values do not depend on the model.
//!
//! Every table rejects unknown keys. Errors name the file, the key and what was
//! expected; parse errors also show the line and column.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::CliError;
use crate::scenario::{OutputSpec, TimeSpec, check_time_and_output, output_dir, parse_toml, step_count, step_length};

/// A whole scenario file.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The system.
    pub model: ModelSpec,
    /// The integrator.
    pub method: MethodSpec,
    /// Horizon.
    pub time: TimeSpec,
    /// Initial data; optional for built-in models (each has a documented default).
    pub initial: Option<InitialSpec>,
    /// Outputs.
    #[serde(default)]
    pub output: OutputSpec,
}

/// `[model]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// Built-in model name, or `"custom"`.
    pub name: String,
    /// Model parameters (built-in models; defaults listed by `veselov models`).
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
    /// Custom systems: coordinate names.
    pub coordinates: Option<Vec<String>>,
    /// Custom systems: the Lagrangian expression.
    pub lagrangian: Option<String>,
    /// Custom systems: a generalised force, one expression per coordinate.
    pub force: Option<Vec<String>>,
    /// Custom systems: symmetry generators `ξ_Q(q)`, one expression per coordinate.
    #[serde(default)]
    pub symmetries: BTreeMap<String, Vec<String>>,
    /// Custom systems: named constants usable in the expressions.
    #[serde(default)]
    pub constants: BTreeMap<String, f64>,
}

/// `[method]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MethodSpec {
    /// `midpoint | trapezoid | alpha | galerkin-lobatto | galerkin-gauss`
    /// (`scheme` is accepted too, the spelling of the lattice kinds).
    #[serde(alias = "scheme")]
    pub name: String,
    /// Stages of the Galerkin methods.
    pub stages: Option<usize>,
    /// α of the α-rule.
    pub alpha: Option<f64>,
    /// Time step.
    pub dt: f64,
    /// Newton iterations: relative update at which they stop (default 4ε);
    /// the fixed-point sweeps of separable models always go to round-off.
    pub newton_tolerance: Option<f64>,
    /// Newton iterations per step before the step fails (default 50).
    pub newton_max_iterations: Option<usize>,
}

impl MethodSpec {
    /// The Newton options these keys ask for (defaults otherwise).
    pub fn newton_options(&self) -> veselov::solve::NewtonOptions {
        let mut o = veselov::solve::NewtonOptions::default();
        if let Some(t) = self.newton_tolerance {
            o.tol = t;
        }
        if let Some(n) = self.newton_max_iterations {
            o.max_iterations = n;
        }
        o
    }
}

/// `[initial]`: `q` and exactly one of `p` and `v`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// Positions.
    pub q: Vec<f64>,
    /// Momenta.
    pub p: Option<Vec<f64>>,
    /// Velocities.
    pub v: Option<Vec<f64>>,
}

/// A scenario with the path it came from.
#[derive(Debug, Clone)]
pub struct LoadedScenario {
    /// Source file.
    pub path: PathBuf,
    /// Parsed content.
    pub scenario: Scenario,
}

impl LoadedScenario {
    /// Read and parse `path`, then check the values that do not depend on the model.
    pub fn load(path: &Path) -> Result<Self, CliError> {
        let text = std::fs::read_to_string(path).map_err(|e| CliError::Io {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Self::parse(path, &text)
    }

    /// Parse scenario text attributed to `path`.
    pub fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: Scenario = parse_toml(path, text)?;
        let loaded = Self {
            path: path.to_path_buf(),
            scenario,
        };
        loaded.check()?;
        Ok(loaded)
    }

    /// An error about `key` in this file.
    pub fn key_error(&self, key: &str, message: impl Into<String>) -> CliError {
        CliError::Key {
            file: self.path.clone(),
            key: key.to_string(),
            message: message.into(),
        }
    }

    fn finite(&self, key: &str, values: &[f64]) -> Result<(), CliError> {
        for (i, v) in values.iter().enumerate() {
            if !v.is_finite() {
                let k = if values.len() > 1 {
                    format!("{key}[{i}]")
                } else {
                    key.to_string()
                };
                return Err(self.key_error(&k, format!("expected a finite number, got {v}")));
            }
        }
        Ok(())
    }

    fn check(&self) -> Result<(), CliError> {
        let s = &self.scenario;
        check_time_and_output(&self.path, &s.time, s.method.dt, &s.output)?;
        if let Some(t) = s.method.newton_tolerance
            && !(t.is_finite() && (f64::EPSILON..=1e-3).contains(&t))
        {
            return Err(self.key_error(
                "method.newton_tolerance",
                format!("expected a relative tolerance between 2.2e-16 (ε) and 1e-3, got {t}"),
            ));
        }
        if let Some(n) = s.method.newton_max_iterations
            && !(1..=10_000).contains(&n)
        {
            return Err(self.key_error(
                "method.newton_max_iterations",
                format!("expected 1 to 10000 iterations, got {n}"),
            ));
        }
        if let Some(init) = &s.initial {
            self.finite("initial.q", &init.q)?;
            match (&init.p, &init.v) {
                (Some(_), Some(_)) => return Err(self.key_error("initial", "give either `p` or `v`, not both")),
                (None, None) => return Err(self.key_error("initial", "missing `p` or `v`")),
                (Some(p), None) => self.finite("initial.p", p)?,
                (None, Some(v)) => self.finite("initial.v", v)?,
            }
        }
        for (k, v) in &s.model.params {
            self.finite(&format!("model.params.{k}"), &[*v])?;
        }
        for (k, v) in &s.model.constants {
            self.finite(&format!("model.constants.{k}"), &[*v])?;
        }
        Ok(())
    }

    /// Number of steps.
    pub fn steps(&self) -> u64 {
        step_count(&self.scenario.time, self.scenario.method.dt)
    }

    /// The step a fixed-step run takes ([`step_length`]).
    pub fn step_length(&self) -> f64 {
        step_length(&self.scenario.time, self.scenario.method.dt)
    }

    /// The output directory: `--out`, else `output.dir`, else `out/<stem>`.
    pub fn output_dir(&self, cli_out: Option<&Path>) -> PathBuf {
        output_dir(&self.path, &self.scenario.output, cli_out)
    }
}
