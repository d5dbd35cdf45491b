//! Lattice field scenarios: sine-Gordon, the linear wave equation and φ⁴
//! Klein–Gordon on a 1+1 spacetime lattice, with the schemes of seed 002 §5.
//!
//! ```toml
//! [model]
//! name = "sine-gordon"     # sine-gordon | wave | klein-gordon-phi4
//! params = { m2 = 1.0, lambda = 1.0 }   # klein-gordon-phi4: N = −½m²φ² − ¼λφ⁴
//! [lattice]
//! nodes = 255
//! length = 40.0
//! boundary = "periodic"    # periodic | winding (jump = 2π by default)
//! courant = 0.125          # or: dt = 0.0196…
//! [method]
//! scheme = "triangle"      # triangle | triangle-explicit | rectangle | symmetric-rectangle | vu-quoc-li | guo
//! [initial]
//! kind = "kink-antikink"   # kink-antikink | kink | breather | dalembert
//! [time]
//! t_end = 200.0
//! [output]
//! dir = "out/sg"
//! snapshot_every = 100
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use nalgebra::SVector;
use serde::Deserialize;
use serde_json::json;
use veselov::field::{
    BlockAccumulator, Boundary, CellEnergy, ComplexKleinGordon, ComplexPlaneWave, Density, DensityRunConfig,
    FieldRunConfig, Generator, InitialData, Lattice, LevelInfo, Levels, Model, NonlinearWave, Phi4, RectangleRule,
    Scheme, SineGordon, SolverOptions, TriangleRule, Wave, run_density, run_lattice,
};

use crate::error::CliError;
use crate::figures::{FieldView, draw_field};
use crate::output::{Table, npy_header_shape, prepare_dir, write_json};
use crate::progress::Progress;
use crate::run::RunJob;
use crate::scenario::{finite_value, key_error, output_dir, parse_toml, positive_value};

/// The lattice-field model names.
pub const FIELD_MODELS: &[&str] = &["sine-gordon", "wave", "klein-gordon-phi4", "klein-gordon-complex"];

/// A lattice-field scenario file.
#[derive(Debug, Clone, Deserialize)]
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
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldModelSpec {
    /// `sine-gordon | wave | klein-gordon-phi4 | klein-gordon-complex`.
    pub name: String,
    /// `m2`, `lambda` (φ⁴ and complex Klein–Gordon).
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// `[lattice]`.
#[derive(Debug, Clone, Deserialize)]
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
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SchemeSpec {
    /// The scheme.
    pub scheme: String,
    /// Relative tolerance of the level solves (default 1e-13).
    pub tolerance: Option<f64>,
    /// Minimum iterations per level (default 1; the paper used 3 for Guo).
    pub min_iterations: Option<usize>,
}

/// `[initial]`.
#[derive(Debug, Clone, Deserialize)]
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
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldTimeSpec {
    /// Final time (the run stops at the first level with t ≥ t_end).
    pub t_end: f64,
}

/// `[output]`.
#[derive(Debug, Clone, Deserialize)]
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
            plots: true,
            plot_format: svg(),
        }
    }
}

/// A parsed field scenario and its file.
pub struct LoadedField {
    path: PathBuf,
    scenario: FieldScenario,
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

    fn key_error(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    fn positive(&self, key: &str, v: f64) -> Result<f64, CliError> {
        positive_value(&self.path, key, v)
    }

    fn finite(&self, key: &str, v: f64) -> Result<f64, CliError> {
        finite_value(&self.path, key, v)
    }

    fn model(&self) -> Result<FieldModel, CliError> {
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

    fn lattice(&self) -> Result<Lattice, CliError> {
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

    fn scheme(&self) -> Result<Scheme, CliError> {
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

    fn initial(&self, length: f64) -> Result<FieldInitial, CliError> {
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

    fn solver(&self) -> Result<SolverOptions, CliError> {
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
        if s.output.plot_format != "svg" && s.output.plot_format != "png" {
            return Err(self.key_error(
                "output.plot_format",
                format!(
                    "unknown plot format `{}`, expected \"svg\" or \"png\"",
                    s.output.plot_format
                ),
            ));
        }
        Ok(solver)
    }
}

/// The field equation of a scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
enum FieldModel {
    /// A real scalar field (fast paths on periodic lattices).
    Scalar(Model),
    /// The complex (O(2)-invariant) Klein–Gordon field.
    Complex(ComplexKleinGordon),
}

/// The initial data of a scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
enum FieldInitial {
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

/// Write a float64 `.npy` array of the given shape from rows of values.
fn write_npy(path: &Path, shape: &[usize], rows: &[Vec<f64>]) -> Result<(), CliError> {
    let mut bytes = npy_header_shape(shape);
    for row in rows {
        for v in row {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).map_err(|e| CliError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })
}

/// What either marching path hands to the writers.
struct Outcome {
    /// `fast` (the scheme's own O(N) solver) or `generic` (Newton on the cell Lagrangian).
    path: &'static str,
    /// `(t, energy, charge)` rows, t the time of the first level of the pair.
    energies: Vec<(f64, f64, Option<f64>)>,
    /// Name of the charge column.
    charge: Option<&'static str>,
    /// Snapshot rows: nodes × components values, and their times.
    snapshots: Vec<Vec<f64>>,
    times: Vec<f64>,
    components: usize,
    levels: usize,
    t_final: f64,
    iterations: u64,
    recentred_by: f64,
    status: Result<(), veselov::Error>,
}

fn fast_outcome(loaded: &LoadedField, config: &FieldRunConfig, progress: &mut Progress) -> Result<Outcome, CliError> {
    let lattice = config.lattice;
    let (y0, _) = config
        .initial
        .levels(&lattice)
        .map_err(|e| loaded.key_error("initial", e.to_string()))?;
    let run = run_lattice(config, |info: &LevelInfo| {
        progress.set(info.level as u64);
        true
    })
    .map_err(|e| loaded.key_error("lattice", e.to_string()))?;
    let dt = lattice.dt();
    let charge = (config.model == Model::Wave).then_some("shift_charge");
    // energies[m] is E_{m+1}, of the levels (m + 1, m + 2) (see FastMarcher::energy);
    // charges[m] is that of the levels (m, m + 1).
    let energies = run
        .energies
        .iter()
        .enumerate()
        .map(|(m, e)| {
            let q = charge.and_then(|_| run.charges.get(m + 1).copied());
            ((m + 1) as f64 * dt, *e, q)
        })
        .collect();
    // Snapshots are written unwrapped (the run's 2π re-centring undone), so
    // that all rows share the frame of level 0.
    let mut snapshots = vec![y0];
    let mut times = vec![0.0];
    for snap in &run.snapshots {
        snapshots.push(snap.values.iter().map(|v| v + snap.recentred_by).collect());
        times.push(snap.time);
    }
    if times.last().copied() != Some(run.final_time) && !run.final_level.is_empty() {
        snapshots.push(run.final_level.iter().map(|v| v + run.recentred_by).collect());
        times.push(run.final_time);
    }
    Ok(Outcome {
        path: "fast",
        energies,
        charge,
        snapshots,
        times,
        components: 1,
        levels: run.final_index,
        t_final: run.final_time,
        iterations: run.iterations,
        recentred_by: run.recentred_by,
        status: run.status,
    })
}

/// The generic (density) path for the variational schemes.
fn generic_outcome<L: CellEnergy<DIM>, const DIM: usize>(
    loaded: &LoadedField,
    lag: L,
    lattice: Lattice,
    (y0, y1): Levels<DIM>,
    charge: Option<(&'static str, Generator<'_, DIM>)>,
    progress: &mut Progress,
) -> Result<Outcome, CliError> {
    let s = &loaded.scenario;
    let config = DensityRunConfig {
        t_end: loaded.positive("time.t_end", s.time.t_end)?,
        snapshot_every: s.output.snapshot_every,
        rel_tol: s.method.tolerance.unwrap_or(1e-13),
    };
    let flat = |level: &[SVector<f64, DIM>]| -> Vec<f64> { level.iter().flat_map(|v| v.iter().copied()).collect() };
    let first = flat(&y0);
    let run = run_density(
        lag,
        lattice,
        y0,
        y1,
        &config,
        charge.map(|c| c.1),
        |info: &LevelInfo| {
            progress.set(info.level as u64);
            true
        },
    )
    .map_err(|e| loaded.key_error("lattice", e.to_string()))?;
    let dt = lattice.dt();
    let energies = run
        .energies
        .iter()
        .enumerate()
        .map(|(m, e)| (m as f64 * dt, *e, run.charges.get(m).copied()))
        .collect();
    let mut snapshots = vec![first];
    let mut times = vec![0.0];
    for (_, t, level) in &run.snapshots {
        snapshots.push(flat(level));
        times.push(*t);
    }
    if times.last().copied() != Some(run.final_time) {
        snapshots.push(flat(&run.final_level));
        times.push(run.final_time);
    }
    Ok(Outcome {
        path: "generic",
        energies,
        charge: charge.map(|c| c.0),
        snapshots,
        times,
        components: DIM,
        levels: run.final_index,
        t_final: run.final_time,
        iterations: run.iterations,
        recentred_by: 0.0,
        status: run.status,
    })
}

/// The cell rule of a variational scheme, or an error naming `method.scheme`.
fn variational_rule<F: Density<DIM> + Copy, const DIM: usize, R>(
    loaded: &LoadedField,
    scheme: Scheme,
    density: F,
    lattice: &Lattice,
    go: impl FnOnce(Either<TriangleRule<F>, RectangleRule<F>>) -> R,
) -> Result<R, CliError> {
    let (dt, dx) = (lattice.dt(), lattice.dx());
    match scheme {
        Scheme::Triangle => Ok(go(Either::Triangle(TriangleRule { density, dt, dx }))),
        Scheme::Rectangle | Scheme::SymmetricRectangle => Ok(go(Either::Rectangle(RectangleRule {
            density,
            dt,
            dx,
            symmetric: scheme == Scheme::SymmetricRectangle,
        }))),
        other => Err(loaded.key_error(
            "method.scheme",
            format!(
                "`{}` has no cell Lagrangian: on dirichlet or free boundaries and for the complex field only \
                 the variational schemes triangle, rectangle and symmetric-rectangle run",
                other.name()
            ),
        )),
    }
}

/// One of the two cell rules.
enum Either<T, R> {
    Triangle(T),
    Rectangle(R),
}

/// Run a lattice-field scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let start = Instant::now();
    let loaded = LoadedField::parse(path, text)?;
    let s = &loaded.scenario;
    let solver = loaded.solver()?;
    let model = loaded.model()?;
    let scheme = loaded.scheme()?;
    let mut lattice = loaded.lattice()?;
    let initial = loaded.initial(lattice.length())?;
    let t_end = loaded.positive("time.t_end", s.time.t_end)?;
    let dir = prepare_dir(
        &output_dir(&loaded.path, &output_spec(s), job.out.as_deref()),
        job.force,
    )?;
    let total = (t_end / lattice.dt()).ceil() as u64;
    let mut progress = Progress::new(total, job.quiet);
    let initial_error = |e: veselov::Error| loaded.key_error("initial", e.to_string());
    let outcome = match (model, initial) {
        (FieldModel::Scalar(model), FieldInitial::Scalar(data)) => {
            if lattice.is_periodic() {
                let config = FieldRunConfig {
                    model,
                    scheme,
                    lattice,
                    initial: data,
                    t_end,
                    snapshot_every: s.output.snapshot_every,
                    energy_block: 0,
                    keep_energies: true,
                    recentre_every: if model == Model::SineGordon { 1000 } else { 0 },
                    solver,
                };
                fast_outcome(&loaded, &config, &mut progress)?
            } else {
                let (y0, y1) = data.levels(&lattice).map_err(initial_error)?;
                if let Boundary::Dirichlet { .. } = lattice.boundary() {
                    // Unless given, the end values are the initial ones.
                    let l = &s.lattice;
                    let n = y0.len();
                    let boundary = Boundary::Dirichlet {
                        left: l.left.unwrap_or(y0[0]),
                        right: l.right.unwrap_or(y0[n - 1]),
                    };
                    lattice = Lattice::new(lattice.nodes(), lattice.dx(), lattice.dt(), boundary)
                        .map_err(|e| loaded.key_error("lattice", e.to_string()))?;
                }
                let lift = |y: Vec<f64>| -> Vec<SVector<f64, 1>> { y.into_iter().map(SVector::from_element).collect() };
                let levels = (lift(y0), lift(y1));
                let shift = |_: &SVector<f64, 1>| SVector::<f64, 1>::from_element(1.0);
                // The shift y ↦ y + s is a symmetry of the wave equation that a
                // Dirichlet boundary breaks.
                let charge: Option<(&'static str, Generator<'_, 1>)> = (model == Model::Wave
                    && lattice.boundary() == Boundary::Free)
                    .then_some(("split_shift_charge", &shift));
                match model {
                    Model::SineGordon => variational_rule(
                        &loaded,
                        scheme,
                        NonlinearWave(SineGordon),
                        &lattice,
                        |rule| match rule {
                            Either::Triangle(r) => generic_outcome(&loaded, r, lattice, levels, charge, &mut progress),
                            Either::Rectangle(r) => generic_outcome(&loaded, r, lattice, levels, charge, &mut progress),
                        },
                    )??,
                    Model::Wave => {
                        variational_rule(&loaded, scheme, NonlinearWave(Wave), &lattice, |rule| match rule {
                            Either::Triangle(r) => generic_outcome(&loaded, r, lattice, levels, charge, &mut progress),
                            Either::Rectangle(r) => generic_outcome(&loaded, r, lattice, levels, charge, &mut progress),
                        })??
                    }
                    Model::Phi4 { m2, lambda } => {
                        variational_rule(&loaded, scheme, NonlinearWave(Phi4 { m2, lambda }), &lattice, |rule| {
                            match rule {
                                Either::Triangle(r) => {
                                    generic_outcome(&loaded, r, lattice, levels, charge, &mut progress)
                                }
                                Either::Rectangle(r) => {
                                    generic_outcome(&loaded, r, lattice, levels, charge, &mut progress)
                                }
                            }
                        })??
                    }
                }
            }
        }
        (FieldModel::Complex(kg), FieldInitial::PlaneWave { amplitude, mode }) => {
            let wave = ComplexPlaneWave {
                amplitude,
                mode,
                m2: kg.m2,
                lambda: kg.lambda,
            };
            let levels = wave.levels(&lattice).map_err(initial_error)?;
            let rotation = |y: &SVector<f64, 2>| SVector::<f64, 2>::new(-y[1], y[0]);
            // Fixed end values (every component the same) break the phase symmetry.
            let fixed = matches!(lattice.boundary(), Boundary::Dirichlet { .. });
            let charge: Option<(&'static str, Generator<'_, 2>)> = (!fixed).then_some(("phase_charge", &rotation));
            variational_rule(&loaded, scheme, NonlinearWave(kg), &lattice, |rule| match rule {
                Either::Triangle(r) => generic_outcome(&loaded, r, lattice, levels, charge, &mut progress),
                Either::Rectangle(r) => generic_outcome(&loaded, r, lattice, levels, charge, &mut progress),
            })??
        }
        (FieldModel::Complex(_), FieldInitial::Scalar(_)) => {
            return Err(loaded.key_error(
                "initial.kind",
                "the complex Klein–Gordon field takes `plane-wave` initial data",
            ));
        }
        (FieldModel::Scalar(_), FieldInitial::PlaneWave { .. }) => {
            return Err(loaded.key_error(
                "initial.kind",
                "`plane-wave` initial data are for the complex Klein–Gordon field",
            ));
        }
    };
    progress.finish();
    write_outcome(&loaded, &dir, lattice, &outcome, start, job.quiet)?;
    match outcome.status {
        Ok(()) => Ok(()),
        Err(error) => Err(CliError::Run { error, dir }),
    }
}

/// energy.csv, snapshots.npy, snapshot_times.csv, summary.json and the plots.
fn write_outcome(
    loaded: &LoadedField,
    dir: &Path,
    lattice: Lattice,
    outcome: &Outcome,
    start: Instant,
    quiet: bool,
) -> Result<(), CliError> {
    let s = &loaded.scenario;
    let mut energy = Table {
        header: vec!["t".into(), "energy".into()],
        rows: Vec::new(),
    };
    if let Some(name) = outcome.charge {
        energy.header.push(name.into());
    }
    let count = outcome.energies.len();
    for (m, (t, e, q)) in outcome.energies.iter().enumerate() {
        if m % s.output.energy_every == 0 || m + 1 == count {
            let mut row = vec![*t, *e];
            if outcome.charge.is_some() {
                row.push(q.unwrap_or(f64::NAN));
            }
            energy.rows.push(row);
        }
    }
    energy.write_csv(&dir.join("energy.csv"))?;
    if s.output.energy_block > 0 {
        let e0 = outcome.energies.first().map_or(f64::NAN, |e| e.1);
        let mut blocks = BlockAccumulator::new(s.output.energy_block);
        for (m, e) in outcome.energies.iter().enumerate() {
            blocks.push(m, e.1 - e0);
        }
        // `first_level` is the index into `outcome.energies`; report its time.
        let rows = blocks
            .finish()
            .iter()
            .map(|b| vec![outcome.energies[b.first_level].0, b.levels as f64, b.min, b.mean, b.max])
            .collect();
        Table {
            header: ["t_start", "levels", "min", "mean", "max"].map(String::from).to_vec(),
            rows,
        }
        .write_csv(&dir.join("energy_blocks.csv"))?;
    }
    let nodes = lattice.nodes();
    let shape: Vec<usize> = if outcome.components == 1 {
        vec![outcome.snapshots.len(), nodes]
    } else {
        vec![outcome.snapshots.len(), nodes, outcome.components]
    };
    write_npy(&dir.join("snapshots.npy"), &shape, &outcome.snapshots)?;
    Table {
        header: vec!["t".into()],
        rows: outcome.times.iter().map(|t| vec![*t]).collect(),
    }
    .write_csv(&dir.join("snapshot_times.csv"))?;
    let e0 = outcome.energies.first().map_or(f64::NAN, |e| e.1);
    let energy_error_max = outcome.energies.iter().fold(0.0_f64, |m, e| m.max((e.1 - e0).abs()));
    let charges_error_max = match (outcome.charge, outcome.energies.first().and_then(|e| e.2)) {
        (Some(name), Some(q0)) => {
            let err = outcome
                .energies
                .iter()
                .filter_map(|e| e.2)
                .fold(0.0_f64, |m, q| m.max((q - q0).abs()));
            json!({ name: err })
        }
        _ => json!({}),
    };
    let summary = json!({
        "status": if outcome.status.is_ok() { "ok" } else { "error" },
        "error": outcome.status.as_ref().err().map(|e| e.to_string()),
        "scenario": loaded.path.display().to_string(),
        "model": s.model.name,
        "scheme": s.method.scheme,
        "boundary": s.lattice.boundary,
        "path": outcome.path,
        "nodes": nodes,
        "dx": lattice.dx(),
        "dt": lattice.dt(),
        "courant": lattice.dt() / lattice.dx(),
        "levels": outcome.levels,
        "t_final": outcome.t_final,
        "energy_initial": e0,
        "energy_error_max": energy_error_max,
        "charges_error_max": charges_error_max,
        "iterations_mean": outcome.iterations as f64 / outcome.levels.saturating_sub(1).max(1) as f64,
        "recentred_by": outcome.recentred_by,
        "wall_seconds": start.elapsed().as_secs_f64(),
    });
    write_json(&dir.join("summary.json"), &summary)?;
    if s.output.plots {
        let first_component: Vec<Vec<f64>> = outcome
            .snapshots
            .iter()
            .map(|row| row.iter().step_by(outcome.components).copied().collect())
            .collect();
        draw_field(
            dir,
            &energy,
            &first_component,
            &outcome.times,
            lattice,
            match (s.model.name.as_str(), outcome.components) {
                ("sine-gordon", _) => FieldView::Circle,
                (_, 1) => FieldView::Real,
                _ => FieldView::RealPart,
            },
            &s.output.plot_format,
        )?;
    }
    if !quiet {
        eprintln!(
            "{} / {}: {} levels to t = {}, max |E − E₀| = {:.3e}; outputs in {}",
            s.model.name,
            s.method.scheme,
            outcome.levels,
            outcome.t_final,
            energy_error_max,
            dir.display()
        );
    }
    Ok(())
}

/// The `[output]` keys `output_dir` understands.
fn output_spec(s: &FieldScenario) -> crate::scenario::OutputSpec {
    crate::scenario::OutputSpec {
        dir: s.output.dir.clone(),
        ..Default::default()
    }
}
