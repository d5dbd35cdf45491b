//! The schema of a lattice-field scenario file (`[model]`, `[lattice]`,
//! `[method]`, `[initial]`, `[time]`, `[output]`), parsed with key-level
//! errors and validated into the library's model, lattice, scheme and
//! initial data.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use veselov::spacetime::{Boundary, ComplexKleinGordon, InitialData, Lattice, Model, Scheme, SolverOptions};

use crate::error::CliError;
use crate::output::number;
use crate::scenario::{check_plot_format, finite_value, key_error, parse_toml, positive_value};

/// The lattice-field model names.
pub const FIELD_MODELS: &[&str] = &["sine-gordon", "wave", "klein-gordon-phi4", "klein-gordon-complex"];

/// A field scenario on a 1+1 space–time lattice: the field equation, the
/// lattice, the scheme, the initial field, the end time and the outputs, in
/// units where the wave speed is 1.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldScenario {
    /// The field equation: `sine-gordon`, `wave`, `klein-gordon-phi4` or the
    /// two-component `klein-gordon-complex`, with its parameters.
    pub model: FieldModelSpec,
    /// The space–time lattice: its nodes, length and boundary, and the time
    /// step (`dt` or `courant`). Quantities are in units where the wave speed
    /// is 1.
    pub lattice: LatticeSpec,
    /// The scheme that marches the lattice level by level, and the solves of
    /// each level.
    pub method: SchemeSpec,
    /// The initial field (the first two levels): a kind of data and its keys.
    pub initial: FieldInitialSpec,
    /// When the run stops.
    pub time: FieldTimeSpec,
    /// What the run writes (`energy.csv`, `snapshots.npy`, `summary.json`, the
    /// figures) and where.
    #[serde(default)]
    pub output: FieldOutputSpec,
    /// The thresholds beyond which the run's summary carries a warning.
    #[serde(default)]
    pub checks: crate::verdict::ChecksSpec,
}

/// The field equation and its parameters.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldModelSpec {
    /// The field: `sine-gordon` (□φ + sin φ = 0), `wave` (□φ = 0),
    /// `klein-gordon-phi4` (□φ + m²φ + λφ³ = 0) or `klein-gordon-complex` (φ
    /// with two components, □φ + (m² + λ|φ|²)φ = 0), where □φ = φ_tt − ∇²φ
    /// (φ_tt − φ_xx on the 1+1 lattice).
    #[schemars(extend("enum" = ["sine-gordon", "wave", "klein-gordon-phi4", "klein-gordon-complex"]))]
    pub name: String,
    /// Parameters of `klein-gordon-phi4` and `klein-gordon-complex`: `m2` (m²,
    /// default 1) and `lambda` (λ, default 1), e.g. `{ m2 = 1.0, lambda = 0.5 }`;
    /// the other models take none.
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// The space–time lattice: nodes, length, boundary and time step.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// Number of nodes N, at least 3. The space step is dx = length/N on a
    /// `periodic` or `winding` lattice, length/(N − 1) between the end nodes of
    /// a `dirichlet` or `free` one.
    #[schemars(extend("x-type" = "integer ≥ 3"))]
    pub nodes: usize,
    /// Length of space (> 0): the circumference of a `periodic` or `winding`
    /// lattice, the distance between the end nodes of a `dirichlet` or `free`
    /// one.
    pub length: f64,
    /// The boundary: `periodic`; `winding`, periodic up to a jump `jump` of the
    /// field across the seam (a kink on a circle); `dirichlet`, the end values
    /// held fixed (`left`, `right`); or `free`. Dirichlet and free boundaries
    /// run only the schemes `triangle`, `rectangle` and `symmetric-rectangle`.
    #[serde(default = "periodic")]
    #[schemars(extend("enum" = ["periodic", "winding", "dirichlet", "free"]))]
    pub boundary: String,
    /// `winding` boundary only: the jump of the field across the seam (2π: one
    /// kink).
    #[schemars(extend("default" = std::f64::consts::TAU))]
    pub jump: Option<f64>,
    /// `dirichlet` boundary only: the value held at the first node (default:
    /// its initial value).
    pub left: Option<f64>,
    /// `dirichlet` boundary only: the value held at the last node (default: its
    /// initial value).
    pub right: Option<f64>,
    /// Time step (> 0); give either `dt` or `courant`.
    pub dt: Option<f64>,
    /// Courant number dt/dx (> 0), from which the time step is computed; give
    /// either `dt` or `courant`.
    pub courant: Option<f64>,
}

fn periodic() -> String {
    "periodic".into()
}

/// The scheme and the solves of each new level.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SchemeSpec {
    /// The scheme (Marsden–Patrick–Shkoller §5): the multisymplectic `triangle`
    /// (5.8), `triangle-explicit`, `rectangle` (5.10) and `symmetric-rectangle`
    /// (5.12; use an odd number of nodes), or the energy-conserving `vu-quoc-li`
    /// (5.14) and `guo` (5.15). Dirichlet and free boundaries and the complex
    /// field take only `triangle`, `rectangle` and `symmetric-rectangle`.
    /// `name` is accepted too, the spelling of the mechanics kinds.
    #[serde(alias = "name")]
    #[schemars(extend("enum" = [
        "triangle", "triangle-explicit", "rectangle", "symmetric-rectangle", "vu-quoc-li", "guo"
    ]))]
    pub scheme: String,
    /// Relative tolerance (> 0) of the solve of each new level.
    #[schemars(extend("default" = 1e-13))]
    pub tolerance: Option<f64>,
    /// Fewest iterations of each level's solve (the paper used 3 for `guo`);
    /// read on periodic and winding lattices of a real field, not by the
    /// Newton solves of the other boundaries and of the complex field.
    #[schemars(extend("default" = 1))]
    pub min_iterations: Option<usize>,
    /// Run a `triangle`, `triangle-explicit` or `guo` scheme above its
    /// stability limit, Courant number 1 (refused otherwise); the run then
    /// carries the warning `beyond_stability_limit`.
    #[serde(default)]
    pub allow_unstable: bool,
}

/// The initial field: a kind of data and the keys of that kind (a key of
/// another kind is refused).
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldInitialSpec {
    /// The data: `kink-antikink` (the periodic pair of the paper's §5.2),
    /// `kink` or `breather` (sine-Gordon solutions), `dalembert` (travelling
    /// waves of the wave equation), all for the real fields; or `plane-wave`
    /// (the exact travelling wave), the data of `klein-gordon-complex`.
    #[schemars(extend("enum" = ["kink-antikink", "kink", "breather", "dalembert", "plane-wave"]))]
    pub kind: String,
    /// `kink-antikink`: the elliptic modulus of the pair is κ = 1 − epsilon
    /// (> 0).
    #[schemars(extend("default" = 1e-6))]
    pub epsilon: Option<f64>,
    /// `kink-antikink`: build the second level as the paper did, to first order
    /// (`false`: from the exact travelling solitons).
    #[schemars(extend("default" = true))]
    pub paper_start: Option<bool>,
    /// `kink` and `breather`: the centre (default length/4 for the kink,
    /// length/2 for the breather).
    pub x0: Option<f64>,
    /// `kink`: its speed, |c| < 1.
    #[schemars(extend("default" = 0.5))]
    pub speed: Option<f64>,
    /// `breather`: its frequency, 0 < ω < 1.
    #[schemars(extend("default" = 0.5))]
    pub omega: Option<f64>,
    /// `dalembert` and `plane-wave`: the amplitude.
    #[schemars(extend("default" = 1.0))]
    pub amplitude: Option<f64>,
    /// `dalembert` (≥ 1) and `plane-wave` (any integer; its sign is the
    /// direction of travel): the mode number, waves per length of the lattice.
    #[schemars(extend("default" = 1))]
    pub mode: Option<i32>,
    /// `dalembert`: a uniform drift velocity added to the field.
    #[schemars(extend("default" = 0.0))]
    pub drift: Option<f64>,
}

/// When a lattice run stops.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldTimeSpec {
    /// Final time (> 0): the run ends at the first whole time step at or after
    /// `t_end`, with a note when that is later than `t_end`.
    pub t_end: f64,
}

/// What a lattice run writes and where.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FieldOutputSpec {
    /// Directory the outputs go to (default `out/<scenario file stem>`); the
    /// option `--out` overrides it.
    pub dir: Option<PathBuf>,
    /// Levels between the snapshots of the field in `snapshots.npy` (0: only
    /// the first and the last level).
    #[serde(default = "hundred")]
    pub snapshot_every: usize,
    /// Levels between rows of `energy.csv`; the last level is always written.
    #[serde(default = "one")]
    #[schemars(extend("x-type" = "integer ≥ 1"))]
    pub energy_every: usize,
    /// Levels per block of `energy_blocks.csv`, which holds the minimum, mean
    /// and maximum of E − E₀ over each block (0: no such file).
    #[serde(default)]
    pub energy_block: usize,
    /// Levels between checkpoints (0: a checkpoint only where the run ends,
    /// interrupted or not); `veselov run --resume` continues from the last one.
    #[serde(default)]
    pub checkpoint_every: u64,
    /// Draw the figures: the energy error, the final waveform and the
    /// space–time heat map.
    #[serde(default = "yes")]
    pub plots: bool,
    /// File format of the line plots (the heat map is always PNG).
    #[serde(default = "svg")]
    #[schemars(extend("enum" = ["svg", "png"]))]
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
        let step_key = if l.courant.is_some() {
            "lattice.courant"
        } else {
            "lattice.dt"
        };
        // The ratio as given, else dt/dx with a few ulps of slack: a ratio at
        // the limit must not be refused for the rounding of dt = courant·dx.
        let ratio = l.courant.unwrap_or(dt / dx);
        if let Some(limit) = self.stability_limit()
            && ratio > limit * (1.0 + 4.0 * f64::EPSILON)
            && !self.scenario.method.allow_unstable
        {
            return Err(self.key_error(
                step_key,
                format!(
                    "the Courant number dt/dx = {} exceeds the stability limit {limit} of the `{}` scheme (the \
                     run would grow without bound); lower it, or set [method] allow_unstable = true",
                    number(ratio),
                    self.scenario.method.scheme
                ),
            ));
        }
        let t_end = self.scenario.time.t_end;
        if t_end > 0.0 && dt > t_end {
            return Err(self.key_error(
                step_key,
                format!(
                    "the time step dt = {} is longer than the run (time.t_end = {}): not one step would land \
                     inside it",
                    number(dt),
                    number(t_end)
                ),
            ));
        }
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

    /// The largest Courant number dt/dx at which the scheme is stable, where
    /// it has one: 1 for the explicit-in-time `triangle`,
    /// `triangle-explicit` and `guo` (the wave equation's CFL limit; measured
    /// on the wave equation, 201 nodes to t = 200: stable at 1, growing at
    /// 1.1; sine-Gordon's potential lowers it slightly, and a run at 1 then
    /// ends with an energy warning). The `rectangle`, `symmetric-rectangle`
    /// and `vu-quoc-li` schemes, implicit midpoint rules in time, ran stably
    /// up to 10 and have none.
    pub(super) fn stability_limit(&self) -> Option<f64> {
        matches!(
            self.scenario.method.scheme.as_str(),
            "triangle" | "triangle-explicit" | "guo"
        )
        .then_some(1.0)
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
