//! The schema of a lattice-field scenario file (`[model]`, `[lattice]`,
//! `[method]`, `[initial]`, `[time]`, `[output]`), parsed with key-level
//! errors and validated into the library's model, lattice, scheme and
//! initial data.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use veselov::spacetime::{Boundary, ComplexKleinGordon, InitialData, Lattice, Model, Scheme, SolverOptions};

use crate::error::CliError;
use crate::scenario::{check_plot_format, finite_value, key_error, parse_toml, positive_value};

/// The lattice-field model names.
pub const FIELD_MODELS: &[&str] = &["sine-gordon", "wave", "klein-gordon-phi4", "klein-gordon-complex"];

/// A lattice-field scenario file.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldScenario {
    /// The field equation.
    pub model: FieldModelSpec,
    /// The lattice.
    pub lattice: LatticeSpec,
    /// The scheme.
    pub method: SchemeSpec,
    /// Initial data.
    pub initial: FieldInitialSpec,
    /// Horizon.
    pub time: FieldTimeSpec,
    /// Outputs.
    #[serde(default)]
    pub output: FieldOutputSpec,
}

/// `[model]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldModelSpec {
    /// `sine-gordon | wave | klein-gordon-phi4 | klein-gordon-complex`.
    pub name: String,
    /// `m2`, `lambda` (φ⁴ and complex Klein–Gordon).
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// `[lattice]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// Number of nodes N (dx = length/N on a circle, length/(N − 1) between ends).
    pub nodes: usize,
    /// Circumference (periodic, winding) or distance between the end nodes.
    pub length: f64,
    /// `periodic` (default), `winding`, `dirichlet` or `free`.
    #[serde(default = "periodic")]
    pub boundary: String,
    /// Winding boundary: the jump across the seam (default 2π).
    pub jump: Option<f64>,
    /// Dirichlet: the value at the first node (default: its initial value).
    pub left: Option<f64>,
    /// Dirichlet: the value at the last node (default: its initial value).
    pub right: Option<f64>,
    /// Time step.
    pub dt: Option<f64>,
    /// Courant number dt/dx (alternative to `dt`).
    pub courant: Option<f64>,
}

fn periodic() -> String {
    "periodic".into()
}

/// `[method]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SchemeSpec {
    /// The scheme (`name` is accepted too, the spelling of the mechanics kinds).
    #[serde(alias = "name")]
    pub scheme: String,
    /// Relative tolerance of the level solves (default 1e-13).
    pub tolerance: Option<f64>,
    /// Minimum iterations per level (default 1; the paper used 3 for Guo).
    pub min_iterations: Option<usize>,
}

/// `[initial]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldInitialSpec {
    /// `kink-antikink | kink | breather | dalembert | plane-wave`.
    pub kind: String,
    /// Kink–antikink: κ = 1 − epsilon (default 1e-6).
    pub epsilon: Option<f64>,
    /// Kink–antikink: the paper's first-order second level (default true).
    pub paper_start: Option<bool>,
    /// Kink, breather: centre (default length/4 for the kink, length/2 for the breather).
    pub x0: Option<f64>,
    /// Kink: speed |c| < 1 (default 0.5).
    pub speed: Option<f64>,
    /// Breather: frequency 0 < ω < 1 (default 0.5).
    pub omega: Option<f64>,
    /// d'Alembert and plane wave: amplitude (default 1).
    pub amplitude: Option<f64>,
    /// d'Alembert (≥ 1) and plane wave (any integer): mode number (default 1).
    pub mode: Option<i32>,
    /// d'Alembert: uniform drift velocity (default 0).
    pub drift: Option<f64>,
}

/// `[time]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldTimeSpec {
    /// Final time (the run stops at the first level with t ≥ t_end).
    pub t_end: f64,
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldOutputSpec {
    /// Output directory (default `out/<scenario stem>`; `--out` overrides).
    pub dir: Option<PathBuf>,
    /// Levels between stored snapshots (default 100; 0: only the first and last).
    #[serde(default = "hundred")]
    pub snapshot_every: usize,
    /// Levels between rows of `energy.csv` (default 1: every level).
    #[serde(default = "one")]
    pub energy_every: usize,
    /// Block length (levels) of `energy_blocks.csv`: min/mean/max of E − E₀
    /// per block (default 0: none).
    #[serde(default)]
    pub energy_block: usize,
    /// Levels between checkpoints (default 0: a checkpoint only where the
    /// run ends, interrupted or not; `--resume` continues from the last one).
    #[serde(default)]
    pub checkpoint_every: u64,
    /// Draw plots (default true).
    #[serde(default = "yes")]
    pub plots: bool,
    /// `svg` (default) or `png`.
    #[serde(default = "svg")]
    pub plot_format: String,
}

fn hundred() -> usize {
    100
}
fn one() -> usize {
    1
}
fn yes() -> bool {
    true
}
fn svg() -> String {
    "svg".into()
}

impl Default for FieldOutputSpec {
    fn default() -> Self {
        Self {
            dir: None,
            snapshot_every: hundred(),
            energy_every: one(),
            energy_block: 0,
            checkpoint_every: 0,
            plots: true,
            plot_format: svg(),
        }
    }
}

/// A parsed field scenario and its file.
pub struct LoadedField {
    pub(crate) path: PathBuf,
    pub(crate) scenario: FieldScenario,
}

impl LoadedField {
    /// Parse scenario text attributed to `path`.
    pub fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: FieldScenario = parse_toml(path, text)?;
        Ok(Self {
            path: path.to_path_buf(),
            scenario,
        })
    }

    pub(crate) fn key_error(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    pub(super) fn positive(&self, key: &str, v: f64) -> Result<f64, CliError> {
        positive_value(&self.path, key, v)
    }

    pub(super) fn finite(&self, key: &str, v: f64) -> Result<f64, CliError> {
        finite_value(&self.path, key, v)
    }

    pub(super) fn model(&self) -> Result<FieldModel, CliError> {
        let m = &self.scenario.model;
        let allowed: &[&str] = match m.name.as_str() {
            "klein-gordon-phi4" | "klein-gordon-complex" => &["m2", "lambda"],
            _ => &[],
        };
        for (k, v) in &m.params {
            if !allowed.contains(&k.as_str()) {
                return Err(self.key_error(
                    &format!("model.params.{k}"),
                    format!("unknown parameter for `{}` (allowed: {})", m.name, allowed.join(", ")),
                ));
            }
            self.finite(&format!("model.params.{k}"), *v)?;
        }
        let m2 = m.params.get("m2").copied().unwrap_or(1.0);
        let lambda = m.params.get("lambda").copied().unwrap_or(1.0);
        match m.name.as_str() {
            "sine-gordon" => Ok(FieldModel::Scalar(Model::SineGordon)),
            "wave" => Ok(FieldModel::Scalar(Model::Wave)),
            "klein-gordon-phi4" => Ok(FieldModel::Scalar(Model::Phi4 { m2, lambda })),
            "klein-gordon-complex" => Ok(FieldModel::Complex(ComplexKleinGordon { m2, lambda })),
            other => Err(self.key_error(
                "model.name",
                format!(
                    "unknown field model `{other}`, expected one of {}",
                    FIELD_MODELS.join(", ")
                ),
            )),
        }
    }

    pub(super) fn lattice(&self) -> Result<Lattice, CliError> {
        let l = &self.scenario.lattice;
        if l.nodes < 3 {
            return Err(self.key_error("lattice.nodes", format!("expected at least 3 nodes, got {}", l.nodes)));
        }
        let length = self.positive("lattice.length", l.length)?;
        let periodic = matches!(l.boundary.as_str(), "periodic" | "winding");
        let dx = if periodic {
            length / l.nodes as f64
        } else {
            length / (l.nodes - 1) as f64
        };
        if (l.left.is_some() || l.right.is_some()) && l.boundary != "dirichlet" {
            return Err(self.key_error("lattice", "`left` and `right` are values of a `dirichlet` boundary"));
        }
        let dt = match (l.dt, l.courant) {
            (Some(_), Some(_)) => return Err(self.key_error("lattice", "give either `dt` or `courant`, not both")),
            (None, None) => return Err(self.key_error("lattice", "missing `dt` or `courant` (dt = courant·dx)")),
            (Some(dt), None) => self.positive("lattice.dt", dt)?,
            (None, Some(c)) => self.positive("lattice.courant", c)? * dx,
        };
        let boundary = match l.boundary.as_str() {
            "periodic" => Boundary::Periodic,
            "winding" => Boundary::Winding {
                jump: self.finite("lattice.jump", l.jump.unwrap_or(std::f64::consts::TAU))?,
            },
            "dirichlet" => Boundary::Dirichlet {
                left: self.finite("lattice.left", l.left.unwrap_or(0.0))?,
                right: self.finite("lattice.right", l.right.unwrap_or(0.0))?,
            },
            "free" => Boundary::Free,
            other => {
                return Err(self.key_error(
                    "lattice.boundary",
                    format!("unknown boundary `{other}`, expected periodic, winding, dirichlet or free"),
                ));
            }
        };
        if l.jump.is_some() && l.boundary != "winding" {
            return Err(self.key_error("lattice.jump", "only a `winding` boundary has a jump"));
        }
        Lattice::new(l.nodes, dx, dt, boundary).map_err(|e| self.key_error("lattice", e.to_string()))
    }

    pub(super) fn scheme(&self) -> Result<Scheme, CliError> {
        let name = self.scenario.method.scheme.as_str();
        Ok(match name {
            "triangle" => Scheme::Triangle,
            "triangle-explicit" => Scheme::TriangleExplicit,
            "rectangle" => Scheme::Rectangle,
            "symmetric-rectangle" => Scheme::SymmetricRectangle,
            "vu-quoc-li" => Scheme::VuQuocLi,
            "guo" => Scheme::Guo,
            other => {
                return Err(self.key_error(
                    "method.scheme",
                    format!(
                        "unknown scheme `{other}`, expected triangle, triangle-explicit, rectangle, \
                         symmetric-rectangle, vu-quoc-li or guo"
                    ),
                ));
            }
        })
    }

    pub(super) fn initial(&self, length: f64) -> Result<FieldInitial, CliError> {
        let i = &self.scenario.initial;
        let allowed: &[&str] = match i.kind.as_str() {
            "kink-antikink" => &["epsilon", "paper_start"],
            "kink" => &["x0", "speed"],
            "breather" => &["omega", "x0"],
            "dalembert" => &["amplitude", "mode", "drift"],
            "plane-wave" => &["amplitude", "mode"],
            other => {
                return Err(self.key_error(
                    "initial.kind",
                    format!(
                        "unknown initial data `{other}`, expected kink-antikink, kink, breather, dalembert or plane-wave"
                    ),
                ));
            }
        };
        let present = [
            ("epsilon", i.epsilon.is_some()),
            ("paper_start", i.paper_start.is_some()),
            ("x0", i.x0.is_some()),
            ("speed", i.speed.is_some()),
            ("omega", i.omega.is_some()),
            ("amplitude", i.amplitude.is_some()),
            ("mode", i.mode.is_some()),
            ("drift", i.drift.is_some()),
        ];
        for (key, given) in present {
            if given && !allowed.contains(&key) {
                return Err(self.key_error(&format!("initial.{key}"), format!("not used by kind `{}`", i.kind)));
            }
        }
        let data = match i.kind.as_str() {
            "kink-antikink" => InitialData::KinkAntikink {
                epsilon: self.positive("initial.epsilon", i.epsilon.unwrap_or(1e-6))?,
                paper_start: i.paper_start.unwrap_or(true),
            },
            "kink" => InitialData::Kink {
                x0: self.finite("initial.x0", i.x0.unwrap_or(0.25 * length))?,
                speed: self.finite("initial.speed", i.speed.unwrap_or(0.5))?,
            },
            "breather" => InitialData::Breather {
                omega: self.finite("initial.omega", i.omega.unwrap_or(0.5))?,
                x0: self.finite("initial.x0", i.x0.unwrap_or(0.5 * length))?,
            },
            "dalembert" => {
                let mode = i.mode.unwrap_or(1);
                if mode < 1 {
                    return Err(self.key_error("initial.mode", format!("expected an integer ≥ 1, got {mode}")));
                }
                InitialData::DAlembert {
                    amplitude: self.finite("initial.amplitude", i.amplitude.unwrap_or(1.0))?,
                    mode: mode.unsigned_abs(),
                    drift: self.finite("initial.drift", i.drift.unwrap_or(0.0))?,
                }
            }
            "plane-wave" => {
                return Ok(FieldInitial::PlaneWave {
                    amplitude: self.finite("initial.amplitude", i.amplitude.unwrap_or(1.0))?,
                    mode: i.mode.unwrap_or(1),
                });
            }
            other => return Err(self.key_error("initial.kind", format!("unknown initial data `{other}`"))),
        };
        Ok(FieldInitial::Scalar(data))
    }

    pub(super) fn solver(&self) -> Result<SolverOptions, CliError> {
        let s = &self.scenario;
        let mut solver = SolverOptions::default();
        if let Some(tol) = s.method.tolerance {
            solver.rel_tol = self.positive("method.tolerance", tol)?;
        }
        if let Some(m) = s.method.min_iterations {
            solver.min_iter = m;
        }
        if s.output.energy_every == 0 {
            return Err(self.key_error("output.energy_every", "expected an integer ≥ 1"));
        }
        check_plot_format(&self.path, &s.output.plot_format)?;
        Ok(solver)
    }
}

/// The field equation of a scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum FieldModel {
    /// A real scalar field (fast paths on periodic lattices).
    Scalar(Model),
    /// The complex (O(2)-invariant) Klein–Gordon field.
    Complex(ComplexKleinGordon),
}

/// The initial data of a scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum FieldInitial {
    /// Scalar data of the library.
    Scalar(InitialData),
    /// The exact complex plane wave.
    PlaneWave {
        /// Amplitude.
        amplitude: f64,
        /// Mode number.
        mode: i32,
    },
}
