//! The schema of a CFK-lattice field scenario file (`[model]`, `[lattice]`,
//! `[method]`, `[initial]`, `[time]`, `[output]`; the `[model]` and `[time]`
//! tables of the 1+1 lattice kind), parsed with key-level errors and
//! validated into the set-up shared by every model.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use veselov::field::cauchy::CauchyOptions;

use crate::error::CliError;
use crate::kinds::lattice::schema::{FieldModelSpec, FieldTimeSpec};
use crate::scenario::{check_plot_format, finite_value, key_error, parse_toml, positive_value};

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkScenario {
    pub(super) model: FieldModelSpec,
    pub(super) lattice: CfkLatticeSpec,
    #[serde(default)]
    pub(super) method: CfkMethodSpec,
    pub(super) initial: CfkInitialSpec,
    pub(super) time: FieldTimeSpec,
    #[serde(default)]
    pub(super) output: CfkOutputSpec,
}

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkLatticeSpec {
    /// `cfk`.
    pub(super) kind: String,
    /// Space dimension (2).
    pub(super) space_dimension: usize,
    /// Nodes per space axis.
    pub(super) nodes: Vec<usize>,
    /// Δx.
    pub(super) spacing: f64,
    pub(super) dt: Option<f64>,
    pub(super) courant: Option<f64>,
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkMethodSpec {
    /// `midpoint` (the only rule on this lattice kind).
    pub(super) rule: Option<String>,
    /// Relative tolerance of the vertex solves (default 1e-14).
    pub(super) tolerance: Option<f64>,
    /// Newton iterations per vertex (default 30).
    pub(super) max_iterations: Option<usize>,
}

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkInitialSpec {
    /// `pulse | standing-wave | plane-wave`.
    pub(super) kind: String,
    pub(super) amplitude: Option<f64>,
    /// Pulse: Gaussian width (default a tenth of the shorter side).
    pub(super) width: Option<f64>,
    /// Standing and plane waves: mode numbers [mx, my] (default [1, 1]).
    pub(super) mode: Option<Vec<i32>>,
}

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkOutputSpec {
    pub(super) dir: Option<PathBuf>,
    /// Time steps Δt between snapshots (default 10; 0: first and last only).
    #[serde(default = "ten")]
    pub(super) snapshot_every: usize,
    /// Time steps Δt between checkpoints (default 0: only where the run ends).
    #[serde(default)]
    pub(super) checkpoint_every: u64,
    #[serde(default = "yes")]
    pub(super) plots: bool,
    #[serde(default = "svg")]
    pub(super) plot_format: String,
}

fn ten() -> usize {
    10
}
fn yes() -> bool {
    true
}
fn svg() -> String {
    "svg".into()
}

impl Default for CfkOutputSpec {
    fn default() -> Self {
        Self {
            dir: None,
            snapshot_every: ten(),
            checkpoint_every: 0,
            plots: true,
            plot_format: svg(),
        }
    }
}

/// The validated set-up shared by every model.
pub(super) struct Setup {
    pub(super) path: PathBuf,
    pub(super) scenario: CfkScenario,
    pub(super) nodes: [usize; 2],
    pub(super) dx: f64,
    pub(super) dt: f64,
    pub(super) t_end: f64,
    pub(super) options: CauchyOptions,
}

impl Setup {
    pub(super) fn key(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    pub(super) fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: CfkScenario = parse_toml(path, text)?;
        let l = &scenario.lattice;
        let key = |k: &str, m: String| key_error(path, k, m);
        if l.kind != "cfk" {
            return Err(key("lattice.kind", format!("expected \"cfk\", got `{}`", l.kind)));
        }
        if l.space_dimension != 2 {
            return Err(key(
                "lattice.space_dimension",
                format!("CFK field runs are in 2 space dimensions, got {}", l.space_dimension),
            ));
        }
        if l.nodes.len() != 2 || l.nodes.iter().any(|&n| !(3..=4096).contains(&n)) {
            return Err(key(
                "lattice.nodes",
                format!("expected two node counts in 3..=4096, got {:?}", l.nodes),
            ));
        }
        // The march keeps 7 levels of values and 4 levels of cell gradients
        // (about 1 KiB per node of a level): cap a level at 2²⁰ nodes.
        if l.nodes[0] * l.nodes[1] > MAX_LEVEL_NODES {
            return Err(key(
                "lattice.nodes",
                format!(
                    "{} × {} nodes per level exceed the limit of {MAX_LEVEL_NODES}",
                    l.nodes[0], l.nodes[1]
                ),
            ));
        }
        let dx = positive_value(path, "lattice.spacing", l.spacing)?;
        let dt = match (l.dt, l.courant) {
            (Some(_), Some(_)) => return Err(key("lattice", "give either `dt` or `courant`, not both".into())),
            (None, None) => {
                return Err(key(
                    "lattice",
                    "missing `dt` or `courant` (dt = courant·spacing)".into(),
                ));
            }
            (Some(dt), None) => positive_value(path, "lattice.dt", dt)?,
            (None, Some(c)) => positive_value(path, "lattice.courant", c)? * dx,
        };
        // Measured: the march of the wave equation on this lattice is stable
        // at Δt/Δx = 0.4 and grows exponentially at 0.45 (a pulse on 24×24
        // nodes to t = 30); the simplices are skewed, so the limit is below
        // the square grid's 1/√2.
        // The ratio as given (`courant`), else dt/dx with a few ulps of
        // slack: a ratio at the limit must not be refused for the rounding
        // of dt = courant·spacing.
        let ratio = l.courant.unwrap_or(dt / dx);
        if ratio > MAX_COURANT * (1.0 + 4.0 * f64::EPSILON) {
            return Err(key(
                "lattice",
                format!("Δt/Δx = {ratio:.3} exceeds the stability limit {MAX_COURANT} of the CFK march"),
            ));
        }
        let m = &scenario.method;
        if let Some(rule) = &m.rule
            && rule != "midpoint"
        {
            return Err(key(
                "method.rule",
                format!("unknown rule `{rule}`, expected \"midpoint\""),
            ));
        }
        let mut options = CauchyOptions::default();
        if let Some(t) = m.tolerance {
            options.tolerance = positive_value(path, "method.tolerance", t)?;
        }
        if let Some(k) = m.max_iterations {
            if k == 0 {
                return Err(key("method.max_iterations", "expected an integer ≥ 1".into()));
            }
            options.max_iterations = k;
        }
        let t_end = positive_value(path, "time.t_end", scenario.time.t_end)?;
        let o = &scenario.output;
        check_plot_format(path, &o.plot_format)?;
        Ok(Self {
            path: path.to_path_buf(),
            nodes: [l.nodes[0], l.nodes[1]],
            scenario,
            dx,
            dt,
            t_end,
            options,
        })
    }

    /// Time steps Δt to run (the run ends at the first whole step ≥ t_end).
    pub(super) fn steps(&self) -> f64 {
        (self.t_end / self.dt).ceil()
    }

    pub(super) fn param(&self, name: &str, default: f64, allowed: &[&str]) -> Result<f64, CliError> {
        for k in self.scenario.model.params.keys() {
            if !allowed.contains(&k.as_str()) {
                return Err(self.key(
                    &format!("model.params.{k}"),
                    format!("unknown parameter for `{}`", self.scenario.model.name),
                ));
            }
        }
        let v = self.scenario.model.params.get(name).copied().unwrap_or(default);
        finite_value(&self.path, &format!("model.params.{name}"), v)
    }
}

/// Largest number of nodes per level.
const MAX_LEVEL_NODES: usize = 1 << 20;

/// Largest Δt/Δx accepted.
const MAX_COURANT: f64 = 0.4;
