//! The schema of a CFK-lattice field scenario file (`[model]`, `[lattice]`,
//! `[method]`, `[initial]`, `[time]`, `[output]`; the `[model]` and `[time]`
//! tables of the 1+1 lattice kind), parsed with key-level errors and
//! validated into the set-up shared by every model.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use veselov::field::cauchy::CauchyOptions;

use crate::error::CliError;
use crate::kinds::lattice::schema::{FieldModelSpec, FieldTimeSpec};
use crate::scenario::{Array, check_plot_format, finite_value, key_error, parse_toml, positive_value};

/// A field scenario on the CFK simplicial lattice in 2+1 dimensions: the
/// field equation, the lattice, the rule and its solves, the initial field,
/// the end time and the outputs, in units where the wave speed is 1.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkScenario {
    /// The field equation, as on the 1+1 lattice: `sine-gordon`, `wave`,
    /// `klein-gordon-phi4` or the two-component `klein-gordon-complex`, with its
    /// parameters.
    pub(super) model: FieldModelSpec,
    /// The CFK lattice (`kind = "cfk"`, which makes the scenario of this kind):
    /// a grid of nodes periodic in both space directions, its spacing and the
    /// time step (`dt` or `courant`).
    pub(super) lattice: CfkLatticeSpec,
    /// The quadrature rule and the solves at each vertex; the table may be left
    /// out.
    #[serde(default)]
    pub(super) method: CfkMethodSpec,
    /// The initial field: a kind of data and its keys.
    pub(super) initial: CfkInitialSpec,
    /// When the run stops.
    pub(super) time: FieldTimeSpec,
    /// What the run writes (`energy.csv`, `momentum.csv`, `snapshots.npy`,
    /// `summary.json`, the figures) and where.
    #[serde(default)]
    pub(super) output: CfkOutputSpec,
    /// The thresholds beyond which the run's summary carries a warning.
    #[serde(default)]
    pub(super) checks: crate::verdict::ChecksSpec,
}

/// The CFK lattice: periodic nodes in 2 space dimensions, their spacing and
/// the time step.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkLatticeSpec {
    /// The lattice kind, `cfk`: it selects this kind of scenario (a
    /// `[lattice]` without `kind` is the 1+1 lattice).
    #[schemars(extend("enum" = ["cfk"]))]
    pub(super) kind: String,
    /// Number of space dimensions: only 2 runs.
    #[schemars(extend("x-type" = "integer"))]
    pub(super) space_dimension: usize,
    /// Nodes per space axis [nx, ny], each 3 to 4096, with nx·ny at most
    /// 2²⁰ = 1048576; the lattice is periodic in both directions.
    #[schemars(extend("x-type" = "array of 2 integers"))]
    pub(super) nodes: Array<i64, 2>,
    /// The space step Δx (> 0): the periodic domain is nx·Δx by ny·Δx.
    pub(super) spacing: f64,
    /// Time step Δt (> 0), at most 0.4·Δx (the measured stability limit of the
    /// march); give either `dt` or `courant`.
    pub(super) dt: Option<f64>,
    /// Courant number Δt/Δx (> 0), at most 0.4 (the measured stability limit of
    /// the march), from which the time step is computed; give either `dt` or
    /// `courant`.
    pub(super) courant: Option<f64>,
}

/// The quadrature rule on the simplices and the Newton solve at each vertex.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkMethodSpec {
    /// The quadrature rule on each simplex: `midpoint`, at its barycentre (the
    /// only rule on this lattice kind).
    #[schemars(extend("enum" = ["midpoint"], "default" = "midpoint"))]
    pub(super) rule: Option<String>,
    /// Relative tolerance (> 0) of the Newton solve at each vertex.
    #[schemars(extend("default" = 1e-14))]
    pub(super) tolerance: Option<f64>,
    /// Newton iterations per vertex after which the solve fails.
    #[schemars(extend("default" = 30, "x-type" = "integer ≥ 1"))]
    pub(super) max_iterations: Option<usize>,
}

/// The initial field: a kind of data and its keys.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkInitialSpec {
    /// The data: `pulse` (a Gaussian at rest, centred in the domain) or
    /// `standing-wave` for the real fields; `plane-wave` (the exact travelling
    /// wave), the data of `klein-gordon-complex`.
    #[schemars(extend("enum" = ["pulse", "standing-wave", "plane-wave"]))]
    pub(super) kind: String,
    /// Amplitude of the pulse or the wave.
    #[schemars(extend("default" = 1.0))]
    pub(super) amplitude: Option<f64>,
    /// `pulse`: the Gaussian's width σ, in exp(−r²/2σ²) (> 0; default a tenth
    /// of the shorter side of the domain).
    pub(super) width: Option<f64>,
    /// `standing-wave` and `plane-wave`: the mode numbers [mx, my], whole waves
    /// across the domain along x and y.
    #[schemars(extend("default" = [1, 1], "x-type" = "array of 2 integers"))]
    pub(super) mode: Option<Array<i64, 2>>,
}

/// What a CFK run writes and where.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(super) struct CfkOutputSpec {
    /// Directory the outputs go to (default `out/<scenario file stem>`); the
    /// option `--out` overrides it.
    pub(super) dir: Option<PathBuf>,
    /// Time steps Δt between the snapshots of the field in `snapshots.npy`
    /// (0: only the last); the last time step is always stored.
    #[serde(default = "ten")]
    pub(super) snapshot_every: usize,
    /// Time steps Δt between checkpoints (0: a checkpoint only where the run
    /// ends, interrupted or not); `veselov run --resume` continues from the
    /// last one.
    #[serde(default)]
    pub(super) checkpoint_every: u64,
    /// Draw the figures: the energy error and heat maps of a few snapshots.
    #[serde(default = "yes")]
    pub(super) plots: bool,
    /// File format of the energy plot (the heat maps are always PNG).
    #[serde(default = "svg")]
    #[schemars(extend("enum" = ["svg", "png"]))]
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
        let nodes = l.nodes.values(path, "lattice.nodes")?;
        if nodes.iter().any(|n| !(3..=4096).contains(n)) {
            return Err(key(
                "lattice.nodes",
                format!("expected two node counts in 3..=4096, got {nodes:?}"),
            ));
        }
        // In 3..=4096: exact.
        let nodes = nodes.map(|n| n as usize);
        // The march keeps 7 levels of values and 4 levels of cell gradients
        // (about 1 KiB per node of a level): cap a level at 2²⁰ nodes.
        if nodes[0] * nodes[1] > MAX_LEVEL_NODES {
            return Err(key(
                "lattice.nodes",
                format!(
                    "{} × {} nodes per level exceed the limit of {MAX_LEVEL_NODES}",
                    nodes[0], nodes[1]
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
        let t_end = scenario.time.t_end;
        if t_end > 0.0 && dt > t_end {
            let step_key = if l.courant.is_some() {
                "lattice.courant"
            } else {
                "lattice.dt"
            };
            return Err(key(
                step_key,
                format!(
                    "the time step dt = {} is longer than the run (time.t_end = {}): not one step would land \
                     inside it",
                    crate::output::number(dt),
                    crate::output::number(t_end)
                ),
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
            nodes,
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
