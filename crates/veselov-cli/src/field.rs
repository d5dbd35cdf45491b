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

use serde::Deserialize;
use serde_json::json;
use veselov::field::{
    Boundary, FieldRunConfig, InitialData, Lattice, LevelInfo, Model, Scheme, SolverOptions, run_lattice,
};

use crate::error::CliError;
use crate::figures::draw_field;
use crate::output::{Table, npy_header, prepare_dir, write_json};
use crate::progress::Progress;
use crate::run::RunJob;
use crate::scenario::output_dir;

/// The lattice-field model names.
pub const FIELD_MODELS: &[&str] = &["sine-gordon", "wave", "klein-gordon-phi4"];

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
    /// `sine-gordon | wave | klein-gordon-phi4`.
    pub name: String,
    /// `m2`, `lambda` (φ⁴).
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// `[lattice]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LatticeSpec {
    /// Number of nodes N (spacing dx = length / N on a circle).
    pub nodes: usize,
    /// Circumference.
    pub length: f64,
    /// `periodic` (default) or `winding`.
    #[serde(default = "periodic")]
    pub boundary: String,
    /// Winding boundary: the jump across the seam (default 2π).
    pub jump: Option<f64>,
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
    /// `kink-antikink | kink | breather | dalembert`.
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
    /// d'Alembert: amplitude (default 1).
    pub amplitude: Option<f64>,
    /// d'Alembert: mode number ≥ 1 (default 1).
    pub mode: Option<u32>,
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
    /// Block length (levels) of `energy_blocks.csv` min/mean/max (default 0: none).
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
        let scenario: FieldScenario = toml::from_str(text).map_err(|e| CliError::Parse {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
        Ok(Self {
            path: path.to_path_buf(),
            scenario,
        })
    }

    fn key_error(&self, key: &str, message: impl Into<String>) -> CliError {
        CliError::Key {
            file: self.path.clone(),
            key: key.to_string(),
            message: message.into(),
        }
    }

    fn positive(&self, key: &str, v: f64) -> Result<f64, CliError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.key_error(key, format!("expected a finite number > 0, got {v}")))
        }
    }

    fn finite(&self, key: &str, v: f64) -> Result<f64, CliError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.key_error(key, format!("expected a finite number, got {v}")))
        }
    }

    fn model(&self) -> Result<Model, CliError> {
        let m = &self.scenario.model;
        let allowed: &[&str] = match m.name.as_str() {
            "klein-gordon-phi4" => &["m2", "lambda"],
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
        match m.name.as_str() {
            "sine-gordon" => Ok(Model::SineGordon),
            "wave" => Ok(Model::Wave),
            "klein-gordon-phi4" => Ok(Model::Phi4 {
                m2: m.params.get("m2").copied().unwrap_or(1.0),
                lambda: m.params.get("lambda").copied().unwrap_or(1.0),
            }),
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
        let dx = length / l.nodes as f64;
        let dt = match (l.dt, l.courant) {
            (Some(_), Some(_)) => return Err(self.key_error("lattice", "give either `dt` or `courant`, not both")),
            (None, None) => return Err(self.key_error("lattice", "missing `dt` or `courant` (dt = courant·dx)")),
            (Some(dt), None) => self.positive("lattice.dt", dt)?,
            (None, Some(c)) => self.positive("lattice.courant", c)? * dx,
        };
        let boundary = match l.boundary.as_str() {
            "periodic" => {
                if l.jump.is_some() {
                    return Err(self.key_error("lattice.jump", "only a `winding` boundary has a jump"));
                }
                Boundary::Periodic
            }
            "winding" => Boundary::Winding {
                jump: self.finite("lattice.jump", l.jump.unwrap_or(std::f64::consts::TAU))?,
            },
            other => {
                return Err(self.key_error(
                    "lattice.boundary",
                    format!("unknown boundary `{other}`, expected \"periodic\" or \"winding\""),
                ));
            }
        };
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

    fn initial(&self, length: f64) -> Result<InitialData, CliError> {
        let i = &self.scenario.initial;
        let unused = |keys: &[(&str, bool)]| -> Result<(), CliError> {
            for (k, present) in keys {
                if *present {
                    return Err(self.key_error(&format!("initial.{k}"), format!("not used by kind `{}`", i.kind)));
                }
            }
            Ok(())
        };
        let data = match i.kind.as_str() {
            "kink-antikink" => {
                unused(&[
                    ("x0", i.x0.is_some()),
                    ("speed", i.speed.is_some()),
                    ("omega", i.omega.is_some()),
                    ("amplitude", i.amplitude.is_some()),
                    ("mode", i.mode.is_some()),
                    ("drift", i.drift.is_some()),
                ])?;
                InitialData::KinkAntikink {
                    epsilon: self.positive("initial.epsilon", i.epsilon.unwrap_or(1e-6))?,
                    paper_start: i.paper_start.unwrap_or(true),
                }
            }
            "kink" => {
                unused(&[
                    ("epsilon", i.epsilon.is_some()),
                    ("paper_start", i.paper_start.is_some()),
                    ("omega", i.omega.is_some()),
                    ("amplitude", i.amplitude.is_some()),
                    ("mode", i.mode.is_some()),
                    ("drift", i.drift.is_some()),
                ])?;
                InitialData::Kink {
                    x0: self.finite("initial.x0", i.x0.unwrap_or(0.25 * length))?,
                    speed: self.finite("initial.speed", i.speed.unwrap_or(0.5))?,
                }
            }
            "breather" => {
                unused(&[
                    ("epsilon", i.epsilon.is_some()),
                    ("paper_start", i.paper_start.is_some()),
                    ("speed", i.speed.is_some()),
                    ("amplitude", i.amplitude.is_some()),
                    ("mode", i.mode.is_some()),
                    ("drift", i.drift.is_some()),
                ])?;
                InitialData::Breather {
                    omega: self.finite("initial.omega", i.omega.unwrap_or(0.5))?,
                    x0: self.finite("initial.x0", i.x0.unwrap_or(0.5 * length))?,
                }
            }
            "dalembert" => {
                unused(&[
                    ("epsilon", i.epsilon.is_some()),
                    ("paper_start", i.paper_start.is_some()),
                    ("x0", i.x0.is_some()),
                    ("speed", i.speed.is_some()),
                    ("omega", i.omega.is_some()),
                ])?;
                InitialData::DAlembert {
                    amplitude: self.finite("initial.amplitude", i.amplitude.unwrap_or(1.0))?,
                    mode: i.mode.unwrap_or(1),
                    drift: self.finite("initial.drift", i.drift.unwrap_or(0.0))?,
                }
            }
            other => {
                return Err(self.key_error(
                    "initial.kind",
                    format!("unknown initial data `{other}`, expected kink-antikink, kink, breather or dalembert"),
                ));
            }
        };
        Ok(data)
    }

    fn config(&self) -> Result<FieldRunConfig, CliError> {
        let lattice = self.lattice()?;
        let s = &self.scenario;
        let t_end = self.positive("time.t_end", s.time.t_end)?;
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
        let model = self.model()?;
        Ok(FieldRunConfig {
            model,
            scheme: self.scheme()?,
            lattice,
            initial: self.initial(lattice.length())?,
            t_end,
            snapshot_every: s.output.snapshot_every,
            energy_block: s.output.energy_block,
            keep_energies: true,
            recentre_every: if model == Model::SineGordon { 1000 } else { 0 },
            solver,
        })
    }
}

/// Write `rows` (levels × nodes) as a float64 `.npy` array.
fn write_matrix_npy(path: &Path, rows: &[Vec<f64>]) -> Result<(), CliError> {
    let cols = rows.first().map_or(0, Vec::len);
    let mut bytes = npy_header(rows.len(), cols);
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

/// Run a lattice-field scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let start = Instant::now();
    let loaded = LoadedField::parse(path, text)?;
    let config = loaded.config()?;
    let lattice = config.lattice;
    let (y0, _) = config
        .initial
        .levels(&lattice)
        .map_err(|e| loaded.key_error("initial", e.to_string()))?;
    let s = &loaded.scenario;
    let dir = prepare_dir(
        &output_dir(&loaded.path, &output_spec(s), job.out.as_deref()),
        job.force,
    )?;
    let total = (config.t_end / lattice.dt()).ceil() as u64;
    let mut progress = Progress::new(total, job.quiet);
    let run = run_lattice(&config, |info: &LevelInfo| {
        progress.set(info.level as u64);
        true
    })
    .map_err(|e| loaded.key_error("lattice", e.to_string()))?;
    progress.finish();
    // energies[m] is the energy of levels (m, m+1), at time (m + 1)·dt for
    // the three-level schemes' pairs: reported at the later level's time.
    let dt = lattice.dt();
    let charge_name = (config.model == Model::Wave).then_some("shift_charge");
    let mut energy = Table {
        header: vec!["t".into(), "energy".into()],
        rows: Vec::new(),
    };
    if let Some(name) = charge_name {
        energy.header.push(name.into());
    }
    for (m, e) in run.energies.iter().enumerate() {
        if m % s.output.energy_every == 0 || m + 1 == run.energies.len() {
            let mut row = vec![(m + 1) as f64 * dt, *e];
            if charge_name.is_some() {
                row.push(run.charges.get(m + 1).copied().unwrap_or(f64::NAN));
            }
            energy.rows.push(row);
        }
    }
    energy.write_csv(&dir.join("energy.csv"))?;
    if !run.energy_blocks.is_empty() {
        let blocks = Table {
            header: vec![
                "t_start".into(),
                "levels".into(),
                "min".into(),
                "mean".into(),
                "max".into(),
            ],
            rows: run
                .energy_blocks
                .iter()
                .map(|b| vec![b.first_level as f64 * dt, b.levels as f64, b.min, b.mean, b.max])
                .collect(),
        };
        blocks.write_csv(&dir.join("energy_blocks.csv"))?;
    }
    let mut snapshots = vec![y0];
    let mut times = vec![0.0];
    // Snapshots are written unwrapped (the run's 2π re-centring undone), so
    // that all rows share the frame of level 0.
    for snap in &run.snapshots {
        snapshots.push(snap.values.iter().map(|v| v + snap.recentred_by).collect());
        times.push(snap.time);
    }
    if times.last().copied() != Some(run.final_time) && !run.final_level.is_empty() {
        snapshots.push(run.final_level.iter().map(|v| v + run.recentred_by).collect());
        times.push(run.final_time);
    }
    write_matrix_npy(&dir.join("snapshots.npy"), &snapshots)?;
    Table {
        header: vec!["t".into()],
        rows: times.iter().map(|t| vec![*t]).collect(),
    }
    .write_csv(&dir.join("snapshot_times.csv"))?;
    let e0 = run.initial_energy;
    let energy_error_max = run.energies.iter().fold(0.0_f64, |m, e| m.max((e - e0).abs()));
    let charges_error_max = run
        .charges
        .first()
        .map(|c0| run.charges.iter().fold(0.0_f64, |m, c| m.max((c - c0).abs())));
    let summary = json!({
        "status": if run.status.is_ok() { "ok" } else { "error" },
        "error": run.status.as_ref().err().map(|e| e.to_string()),
        "scenario": loaded.path.display().to_string(),
        "model": s.model.name,
        "scheme": s.method.scheme,
        "nodes": lattice.nodes(),
        "dx": lattice.dx(),
        "dt": dt,
        "courant": dt / lattice.dx(),
        "levels": run.final_index,
        "t_final": run.final_time,
        "energy_initial": e0,
        "energy_error_max": energy_error_max,
        "charges_error_max": match (charge_name, charges_error_max) {
            (Some(name), Some(err)) => json!({ name: err }),
            _ => json!({}),
        },
        "iterations_mean": run.iterations as f64 / run.final_index.saturating_sub(1).max(1) as f64,
        "recentred_by": run.recentred_by,
        "wall_seconds": start.elapsed().as_secs_f64(),
    });
    write_json(&dir.join("summary.json"), &summary)?;
    if s.output.plots {
        draw_field(
            &dir,
            &energy,
            &snapshots,
            &times,
            lattice.length(),
            config.model == Model::SineGordon,
            &s.output.plot_format,
        )?;
    }
    if !job.quiet {
        eprintln!(
            "{} / {}: {} levels to t = {}, max |E − E₀| = {:.3e}; outputs in {}",
            s.model.name,
            s.method.scheme,
            run.final_index,
            run.final_time,
            energy_error_max,
            dir.display()
        );
    }
    match run.status {
        Ok(()) => Ok(()),
        Err(error) => Err(CliError::Run { error, dir }),
    }
}

/// The `[output]` keys `output_dir` understands.
fn output_spec(s: &FieldScenario) -> crate::scenario::OutputSpec {
    crate::scenario::OutputSpec {
        dir: s.output.dir.clone(),
        ..Default::default()
    }
}
