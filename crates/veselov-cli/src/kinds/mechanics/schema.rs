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
use crate::scenario::{
    List, OutputSpec, TimeSpec, check_time_and_output, output_dir, parse_toml, step_count, step_length,
};

/// A mechanics scenario: a built-in model or a Lagrangian given as
/// expressions, the method and its step, the time span, the initial state and
/// the outputs.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// The system: a built-in model (`veselov models` lists them with their
    /// parameters, coordinates and default initial states) or `custom`, a
    /// Lagrangian written as an expression.
    pub model: ModelSpec,
    /// The integrator and its time step: a fixed-step variational method or a
    /// variable-step symplectic-energy-momentum one (`sem-…`); `veselov
    /// methods` lists them with their orders.
    pub method: MethodSpec,
    /// When the run starts and ends: give either `t_end` or `steps`.
    pub time: TimeSpec,
    /// The initial state at `t0`: `q` and exactly one of `p` and `v`. Optional
    /// for the built-in models, which have a default state (`veselov models`);
    /// required for `custom`.
    pub initial: Option<InitialSpec>,
    /// What the run writes (`trajectory.csv`, `summary.json`, the plots) and
    /// where.
    #[serde(default)]
    pub output: OutputSpec,
    /// The thresholds beyond which the run's summary carries a warning.
    #[serde(default)]
    pub checks: crate::verdict::ChecksSpec,
}

/// The system: a built-in model with its parameters, or a custom Lagrangian
/// with its coordinates, constants, forces and symmetries.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// The model: a built-in name, or `custom` with `coordinates` and
    /// `lagrangian`; the keys `coordinates`, `lagrangian`, `force`,
    /// `symmetries` and `constants` are for `custom` only.
    #[schemars(extend("enum" = [
        "harmonic", "pendulum", "kepler", "henon-heiles", "double-pendulum",
        "damped-oscillator", "van-der-pol", "damped-kepler", "custom"
    ]))]
    pub name: String,
    /// Parameters of a built-in model by name, e.g. `{ mass = 1.0, omega = 2.0 }`:
    /// each model takes its own (`veselov models` lists them with their
    /// defaults), and one left out takes its default. Not for `custom`, which
    /// takes `constants`.
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
    /// Custom models: the names of the coordinates, 1 to 64 (letters, digits and
    /// `_`, not starting with a digit, and not `t`); the expressions use them and
    /// their velocities `<name>_dot`. With more than 6 coordinates only the
    /// fixed-step methods without `force` run, and `veselov verify` is refused.
    pub coordinates: Option<Vec<String>>,
    /// Custom models: the Lagrangian L as an expression in the coordinates,
    /// their velocities `<name>_dot`, the time `t` and the `constants`
    /// (`veselov expressions` documents the language). Required for `custom`.
    pub lagrangian: Option<String>,
    /// Custom models: a generalised force, one expression per coordinate (it may
    /// use the velocities and `t`), applied through the Lagrange–d'Alembert
    /// principle; the run then reports the work of the forces. The variable-step
    /// `sem-…` methods refuse a forced model.
    pub force: Option<Vec<String>>,
    /// Custom models: named symmetries, each a generator ξ(q) given as one
    /// expression per coordinate, e.g. `{ angular = ["-y", "x"] }`; the Noether
    /// momentum of each is written in the column `J_<name>`. Each is checked to
    /// leave the Lagrangian invariant before the run.
    #[serde(default)]
    #[schemars(extend("x-type" = "table of arrays of strings"))]
    pub symmetries: BTreeMap<String, Vec<String>>,
    /// Custom models: named numbers the expressions may use, e.g. `{ k = 1.0 }`
    /// (a declared name takes precedence over the built-in `pi` and `e`).
    #[serde(default)]
    pub constants: BTreeMap<String, f64>,
}

/// The integrator: its name, its step and the keys some methods take.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MethodSpec {
    /// The method (`veselov methods` lists them with their orders): the `sem-…`
    /// methods take variable steps, the others fixed ones. `scheme` is accepted
    /// too, the spelling of the lattice kinds.
    #[serde(alias = "scheme")]
    #[schemars(extend("enum" = [
        "midpoint", "trapezoid", "alpha", "galerkin-lobatto", "galerkin-gauss",
        "sem-midpoint", "sem-averaged", "sem-trapezoid", "sem-leftpoint"
    ]))]
    pub name: String,
    /// Stages s of `galerkin-lobatto` (2 to 10, default 3; order 2s − 2) and
    /// `galerkin-gauss` (1 to 10, default 2; order 2s), or the Gauss nodes of
    /// the potential average of `sem-averaged` (1 to 10, default 2); the other
    /// methods take none.
    pub stages: Option<usize>,
    /// The α in [0, 1] of the `alpha` method, which evaluates the Lagrangian at
    /// (1 − α)q₀ + αq₁ (order 2 at α = ½, else 1); required by `alpha`, refused
    /// by the other methods.
    pub alpha: Option<f64>,
    /// Time step (> 0). With `t_end` (and no `steps`) a fixed-step run adjusts
    /// it to (t_end − t0)/n, n = round((t_end − t0)/dt), so that it ends exactly
    /// at `t_end`; for the `sem-…` methods it is the first step, and the later
    /// ones follow from the discrete energy.
    #[schemars(extend("unit" = "s"))]
    pub dt: f64,
    /// Relative update at which each step's Newton iteration stops, between
    /// ε ≈ 2.2e-16 and 1e-3 (default 4ε). It governs the fixed-step methods on
    /// non-separable models and the Newton fallback of separable ones, whose
    /// fixed-point sweeps always go to round-off; the `sem-…` methods do not
    /// read it.
    #[schemars(extend("default" = 4.0 * f64::EPSILON))]
    pub newton_tolerance: Option<f64>,
    /// Newton iterations per step (1 to 10000) after which the step fails;
    /// like `newton_tolerance`, not read by the `sem-…` methods.
    #[schemars(extend("default" = 50, "x-type" = "integer ≥ 1"))]
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

/// The initial state at `t0`: the coordinates `q` and exactly one of the
/// momenta `p` and the velocities `v`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// Initial coordinates, one value per coordinate, in the order of the
    /// model's coordinates (`veselov models`) or of `coordinates`.
    pub q: List<f64>,
    /// Initial momenta p = ∂L/∂v, one per coordinate; give either `p` or `v`.
    pub p: Option<List<f64>>,
    /// Initial velocities, one per coordinate, turned into momenta through the
    /// Lagrangian; give either `p` or `v`.
    pub v: Option<List<f64>>,
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
                format!(
                    "expected a relative tolerance between 2.2e-16 (ε) and 1e-3, got {}",
                    crate::output::number(t)
                ),
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
            // `q`, `p` and `v` are checked, length first, against the
            // model's coordinates once the model is known.
            match (&init.p, &init.v) {
                (Some(_), Some(_)) => return Err(self.key_error("initial", "give either `p` or `v`, not both")),
                (None, None) => return Err(self.key_error("initial", "missing `p` or `v`")),
                _ => {}
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
