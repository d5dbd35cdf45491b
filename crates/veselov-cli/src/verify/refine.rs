//! `veselov verify` for the kinds discretised in space — lattice fields
//! (1+1 and CFK), the beam and the rod: a refinement study of space and time
//! together.
//!
//! Each run is the scenario with its nodes refined by a ratio r (Δx/r, and
//! Δt/r at the scenario's fixed Courant or step number: a time step the
//! scenario gives is divided by r as well), run as `veselov run` runs it,
//! into the subdirectory `level-<k>` of the study; its observable
//! ([`Observable`]) is read back from its outputs. The error of run k is the
//! Richardson estimate from the next finer run,
//!
//! E_k = ‖u_k − u_{k+1}‖_∞ · ρ^p / (ρ^p − 1),   ρ = r_{k+1}/r_k,
//!
//! p the method's claimed order: for an error C h^p it is the error of run
//! k. The finest run has no estimate. The order is fitted to E_k against
//! the runs' time steps (∝ Δx) by [`super::Study::conclude`].

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use super::observe::{Coarse, Observable, energy_at, final_field, frequency, last_energy_time, tip};
use super::{SPACE_STEP, Study, VerifyJob};
use crate::error::CliError;
use crate::output::Table;
use crate::pipeline::manifest::{Snapshot, prepare_dir};
use crate::pipeline::{MAX_OUTPUT_BYTES, MAX_STEPS, RunJob};

/// Most refinements `--refine` takes (4096 times the scenario's nodes).
pub const MAX_REFINE: usize = 12;

/// What a kind tells a refinement study about its scenario.
pub struct Refinable {
    /// The method's name.
    pub method: String,
    /// Its claimed order in Δx and Δt together.
    pub order: usize,
    /// The key of the nodes (a number, or one per space axis).
    pub nodes_key: &'static str,
    /// The scenario's nodes per space axis.
    pub nodes: Vec<usize>,
    /// Whether the end nodes lie on the boundary ([`Coarse::closed`]).
    pub closed: bool,
    /// Keys divided by the ratio r where the scenario gives them (an
    /// explicit time step, the spacing).
    pub scaled: &'static [&'static str],
    /// Whether the run ends at the first whole step at or after `t_end`
    /// (lattices) rather than landing on it: the finer runs then end at the
    /// coarsest run's final time.
    pub whole_steps: bool,
    /// Output keys set in every run (no figures, fewer snapshots).
    pub outputs: Vec<(&'static str, toml::Value)>,
    /// The observables of the kind, the default first.
    pub observables: Vec<Observable>,
}

/// One run of the study: its nodes per axis and its ratio r to the
/// scenario's grid.
#[derive(Debug, Clone)]
struct Level {
    nodes: Vec<usize>,
    ratio: f64,
}

/// What a run of the study measured.
struct Measured {
    dir: PathBuf,
    dt: f64,
    dx: f64,
    steps: f64,
    value: Option<Vec<f64>>,
}

fn key(file: &Path, key: &str, message: String) -> CliError {
    CliError::Key {
        file: file.to_path_buf(),
        key: key.into(),
        message,
    }
}

impl Refinable {
    /// The number of nodes refined by `ratio` from `n`, if whole.
    fn refined(&self, n: usize, ratio: f64) -> Option<usize> {
        let d = usize::from(self.closed) as f64;
        let m = ratio * (n as f64 - d) + d;
        (m.is_finite() && (m - m.round()).abs() < 1e-9 && m.round() >= 3.0).then_some(m.round() as usize)
    }

    /// The runs asked for by `--refine` or `--nodes`.
    fn levels(&self, file: &Path, job: &VerifyJob) -> Result<Vec<Level>, CliError> {
        if !job.dts.is_empty() {
            return Err(key(
                file,
                "--dt",
                "this scenario is verified by refining space and time together: give `--refine K` or `--nodes \
                 N1,N2,…` instead of `--dt`"
                    .into(),
            ));
        }
        let Some(&first) = self.nodes.first() else {
            return Err(key(file, self.nodes_key, "the scenario gives no node count".into()));
        };
        let ratios: Vec<f64> = match (job.refine, job.nodes.is_empty()) {
            (Some(_), false) => {
                return Err(key(
                    file,
                    "--refine",
                    "give either `--refine` or `--nodes`, not both".into(),
                ));
            }
            (None, true) => {
                return Err(key(
                    file,
                    "--refine",
                    "give the runs of the study: `--refine K` (the scenario's nodes and K refinements by 2) or \
                     `--nodes N1,N2,…`"
                        .into(),
                ));
            }
            (Some(k), true) => {
                if !(2..=MAX_REFINE).contains(&k) {
                    return Err(key(
                        file,
                        "--refine",
                        format!("{k} refinements: give 2 to {MAX_REFINE} (three runs at least, to fit an order)"),
                    ));
                }
                (0..=k).map(|i| f64::from(1u32 << i)).collect()
            }
            (None, false) => {
                if job.nodes.len() < 3 {
                    return Err(key(
                        file,
                        "--nodes",
                        "give three node counts at least, to fit an order".into(),
                    ));
                }
                if job.nodes.windows(2).any(|w| w[1] <= w[0]) {
                    return Err(key(file, "--nodes", "the node counts must increase".into()));
                }
                let d = usize::from(self.closed) as f64;
                job.nodes.iter().map(|&n| (n as f64 - d) / (first as f64 - d)).collect()
            }
        };
        let flag = if job.refine.is_some() { "--refine" } else { "--nodes" };
        ratios
            .into_iter()
            .map(|ratio| {
                let nodes = self
                    .nodes
                    .iter()
                    .map(|&n| self.refined(n, ratio))
                    .collect::<Option<Vec<usize>>>()
                    .ok_or_else(|| {
                        key(
                            file,
                            flag,
                            format!(
                                "{first} nodes refined by {} is not a whole number of nodes (3 at least) on every axis",
                                crate::output::number(ratio)
                            ),
                        )
                    })?;
                Ok(Level { nodes, ratio })
            })
            .collect()
    }

    /// The scenario `table` of a run at `level` (`t_end` set when given).
    fn text(&self, table: &toml::Table, level: &Level, t_end: Option<f64>) -> Result<String, CliError> {
        let mut table = table.clone();
        let nodes = match &level.nodes[..] {
            [n] => toml::Value::Integer(*n as i64),
            many => toml::Value::Array(many.iter().map(|&n| toml::Value::Integer(n as i64)).collect()),
        };
        set(&mut table, self.nodes_key, nodes);
        for name in self.scaled {
            if let Some(v) = get(&table, name).and_then(toml::Value::as_float) {
                set(&mut table, name, toml::Value::Float(v / level.ratio));
            }
        }
        if let Some(t) = t_end {
            set(&mut table, "time.t_end", toml::Value::Float(t));
        }
        for (name, value) in &self.outputs {
            set(&mut table, name, value.clone());
        }
        toml::to_string(&table).map_err(|e| CliError::Setup(format!("cannot write the scenario of a run: {e}")))
    }

    /// The observable `--observable` names, or the kind's default.
    fn observable(&self, file: &Path, job: &VerifyJob) -> Result<Observable, CliError> {
        let names = || self.observables.iter().map(|o| o.name()).collect::<Vec<_>>().join(", ");
        match &job.observable {
            None => Ok(self.observables[0]),
            Some(name) => Observable::named(name)
                .filter(|o| self.observables.contains(o))
                .ok_or_else(|| {
                    key(
                        file,
                        "--observable",
                        format!(
                            "`{name}` is not an observable of this scenario; expected one of: {}",
                            names()
                        ),
                    )
                }),
        }
    }

    /// The refinement study of the scenario `text` in the file `file`, into
    /// `job.out` (default: the scenario's output directory + `/verify`).
    pub fn study(&self, file: &Path, text: &str, job: VerifyJob) -> Result<(), CliError> {
        let levels = self.levels(file, &job)?;
        let observable = self.observable(file, &job)?;
        if observable == Observable::Field {
            let coarse = &levels[0].nodes;
            for level in &levels {
                let nested = level.nodes.iter().zip(coarse).all(|(&f, &c)| {
                    let d = usize::from(self.closed);
                    f > d && c > d && (f - d).is_multiple_of(c - d)
                });
                if !nested {
                    return Err(key(
                        file,
                        "--nodes",
                        format!(
                            "the field is compared at the coarsest run's nodes, which {:?} nodes do not hold: give \
                             counts whose spacings divide the coarsest's (or `--refine K`)",
                            level.nodes
                        ),
                    ));
                }
            }
        }
        let table: toml::Table = crate::scenario::parse_toml(file, text)?;
        // Every run's scenario is valid before the first starts.
        let flag = if job.refine.is_some() { "--refine" } else { "--nodes" };
        for level in &levels {
            crate::route::check_text(file, &self.text(&table, level, None)?).map_err(|e| {
                let why = match e {
                    CliError::Key { key, message, .. } => format!("`{key}`: {message}"),
                    other => other.to_string(),
                };
                key(
                    file,
                    flag,
                    format!("the run with {:?} nodes is refused: {why}", level.nodes),
                )
            })?;
        }
        let default_dir = || {
            let stem = file
                .file_stem()
                .map_or("run".into(), |s| s.to_string_lossy().into_owned());
            get(&table, "output.dir")
                .and_then(toml::Value::as_str)
                .map_or_else(|| PathBuf::from("out").join(stem), PathBuf::from)
                .join("verify")
        };
        let dir = prepare_dir(&job.out.clone().unwrap_or_else(default_dir), job.force)?;
        let files = Snapshot::take(&dir);
        let quiet = job.quiet;
        if !quiet {
            crate::say!(
                "refining space and time together: {} runs, nodes {}; observable: {}",
                levels.len(),
                levels
                    .iter()
                    .map(|l| l.nodes.iter().map(usize::to_string).collect::<Vec<_>>().join("×"))
                    .collect::<Vec<_>>()
                    .join(", "),
                observable.name()
            );
        }
        let coarse = Coarse {
            nodes: levels[0].nodes.clone(),
            closed: self.closed,
        };
        let mut runs: Vec<Measured> = Vec::new();
        let mut t_final = None;
        let mut energy_time = None;
        for (k, level) in levels.iter().enumerate() {
            if job
                .interrupt
                .as_ref()
                .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
            {
                return Err(CliError::Setup(format!(
                    "convergence study interrupted before its run with {} nodes",
                    level.nodes[0]
                )));
            }
            let t_end = match (self.whole_steps, t_final, runs.first()) {
                // A quarter step short of the coarsest run's final time: the
                // first whole step at or after it lands there.
                (true, Some(t), Some(first)) => Some(t - 0.25 * first.dt * levels[0].ratio / level.ratio),
                _ => None,
            };
            let run_dir = dir.join(format!("level-{k}"));
            let run = RunJob {
                out: Some(run_dir.clone()),
                quiet: true,
                force: job.force,
                force_large: false,
                resume: None,
                time_limit: None,
                checkpoint_seconds: None,
                interrupt: job.interrupt.clone(),
                scenario: None,
            };
            let failed = match crate::route::run_text(file, &self.text(&table, level, t_end)?, run) {
                Ok(()) => None,
                Err(CliError::Run { error, .. }) => Some(error),
                Err(e) => return Err(e),
            };
            let summary = read_summary(&run_dir)?;
            let number = |name: &str| summary.get(name).and_then(Value::as_f64).unwrap_or(f64::NAN);
            let (dt, steps) = (number("dt"), number("steps"));
            let dx = ["dx", "ds", "spacing"]
                .iter()
                .map(|n| number(n))
                .find(|v| v.is_finite())
                .unwrap_or(f64::NAN);
            if k == 0 {
                t_final = summary.get("t_final").and_then(Value::as_f64);
                let grow = levels.last().map_or(1.0, |l| l.ratio) / level.ratio;
                self.preflight(file, &job, &run_dir, steps.max(number("levels")), grow)?;
            }
            let value = match failed {
                Some(e) => {
                    if !quiet {
                        crate::say!("run with {} nodes failed: {e}", level.nodes[0]);
                    }
                    None
                }
                None => Some(self.measure(file, observable, &run_dir, &summary, &coarse, &mut energy_time)?),
            };
            runs.push(Measured {
                dir: run_dir,
                dt,
                dx,
                steps,
                value,
            });
        }
        let t_end = t_final.unwrap_or(f64::NAN);
        self.conclude(&dir, &files, (observable, t_end), &levels, &runs, quiet)
    }

    /// Refuse a study whose finest run, `grow` times finer than the coarsest,
    /// would exceed the limits of a run ([`MAX_STEPS`], [`MAX_OUTPUT_BYTES`]),
    /// extrapolated from the coarsest run in `dir` (`steps` steps): steps
    /// grow as the ratio, output at most as its power axes + 1.
    fn preflight(&self, file: &Path, job: &VerifyJob, dir: &Path, steps: f64, grow: f64) -> Result<(), CliError> {
        let flag = if job.refine.is_some() { "--refine" } else { "--nodes" };
        let finest_steps = steps * grow;
        let bytes: u64 = std::fs::read_dir(dir)
            .map(|d| d.filter_map(|e| e.ok()?.metadata().ok()).map(|m| m.len()).sum())
            .unwrap_or(0);
        let finest_bytes = bytes as f64 * grow.powi(self.nodes.len() as i32 + 1);
        if finest_steps > MAX_STEPS as f64 {
            return Err(key(
                file,
                flag,
                format!(
                    "the finest run would take about {} steps, more than the limit of {} for a run: refine less",
                    crate::output::approx(finest_steps),
                    crate::output::approx(MAX_STEPS as f64)
                ),
            ));
        }
        if finest_bytes > MAX_OUTPUT_BYTES as f64 {
            return Err(key(
                file,
                flag,
                format!(
                    "the finest run would write about {:.3e} bytes, more than the limit of 10 GiB for a run: \
                     refine less, or write fewer rows (`output` keys)",
                    finest_bytes
                ),
            ));
        }
        Ok(())
    }

    /// The observable of the run in `dir`.
    fn measure(
        &self,
        file: &Path,
        observable: Observable,
        dir: &Path,
        summary: &Value,
        coarse: &Coarse,
        energy_time: &mut Option<f64>,
    ) -> Result<Vec<f64>, CliError> {
        Ok(match observable {
            Observable::Field => final_field(dir, coarse)?,
            Observable::Energy => {
                let at = match *energy_time {
                    Some(t) => t,
                    None => *energy_time.insert(last_energy_time(dir)?),
                };
                vec![energy_at(dir, at)?]
            }
            Observable::Tip => tip(summary).ok_or_else(|| {
                key(
                    file,
                    "--observable",
                    "the runs report no tip displacement: the scenario has no free end (choose another observable)"
                        .into(),
                )
            })?,
            Observable::Frequency => vec![frequency(dir)?.ok_or_else(|| {
                key(
                    file,
                    "--observable",
                    format!(
                        "the run in {} does not cross its rest shape twice: the scenario is not a free vibration, \
                         or `time.t_end` is shorter than a period (choose another observable, or lengthen the run)",
                        dir.display()
                    ),
                )
            })?],
        })
    }

    /// Estimate the errors, print the table and conclude the study.
    fn conclude(
        &self,
        dir: &Path,
        files: &Snapshot,
        (observable, t_end): (Observable, f64),
        levels: &[Level],
        runs: &[Measured],
        quiet: bool,
    ) -> Result<(), CliError> {
        let p = self.order as i32;
        let errors: Vec<f64> = runs
            .windows(2)
            .zip(levels.windows(2))
            .map(|(r, l)| match (&r[0].value, &r[1].value) {
                (Some(a), Some(b)) if a.len() == b.len() => {
                    let d = a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
                    let rho = (l[1].ratio / l[0].ratio).powi(p);
                    d * rho / (rho - 1.0)
                }
                _ => f64::NAN,
            })
            .collect();
        let scalar = |v: &Option<Vec<f64>>| match v.as_deref() {
            Some([x]) => *x,
            Some(many) => many.iter().fold(0.0, |m: f64, x| m.max(x.abs())),
            None => f64::NAN,
        };
        let mut table = Table {
            header: ["dx", "dt", "steps", "nodes", "value", "error"]
                .map(String::from)
                .to_vec(),
            rows: Vec::new(),
        };
        if !quiet {
            crate::say!(
                "{:>8} {:>12} {:>12} {:>10} {:>16} {:>12} {:>8}",
                "nodes",
                "dx",
                "dt",
                "steps",
                "value",
                "error",
                "rate"
            );
        }
        for (k, (run, level)) in runs.iter().zip(levels).enumerate() {
            let error = errors.get(k).copied().unwrap_or(f64::NAN);
            let rate = k
                .checked_sub(1)
                .map(|j| (errors[j] / error).ln() / (runs[j].dx / run.dx).ln())
                .filter(|r| r.is_finite());
            let value = scalar(&run.value);
            if !quiet {
                let error = if k + 1 < runs.len() {
                    format!("{error:12.4e}")
                } else {
                    "(finest)".into()
                };
                let rate = rate.map(|r| format!("{r:8.3}")).unwrap_or_default();
                crate::say!(
                    "{:>8} {:>12.4e} {:>12.4e} {:>10} {:>16.9e} {:>12} {rate}",
                    level.nodes[0],
                    run.dx,
                    run.dt,
                    run.steps,
                    value,
                    error
                );
            }
            table
                .rows
                .push(vec![run.dx, run.dt, run.steps, level.nodes[0] as f64, value, error]);
        }
        let dxs: Vec<f64> = runs.iter().take(errors.len()).map(|r| r.dx).collect();
        let scale = runs
            .iter()
            .map(|r| scalar(&r.value))
            .filter(|v| v.is_finite())
            .fold(0.0, |m: f64, v| m.max(v.abs()))
            .max(1e-300);
        let study = Study {
            method: self.method.clone(),
            order: self.order,
            reference: format!(
                "Richardson estimate ‖u_k − u_(k+1)‖·ρ^{p}/(ρ^{p} − 1) from the next finer run (ρ its refinement, {p} the \
                 claimed order)"
            ),
            t_end,
            scale,
            interrupt: None,
            error_label: observable.describe().into(),
            step: SPACE_STEP,
            extra: json!({
                "observable": observable.name(),
                "error_estimate": "richardson",
                "runs": runs.iter().zip(levels).map(|(r, l)| json!({
                    "dir": r.dir.file_name().map(|n| n.to_string_lossy().into_owned()),
                    "nodes": l.nodes,
                    "dx": r.dx,
                    "dt": r.dt,
                    "steps": r.steps,
                    "value": scalar(&r.value),
                })).collect::<Vec<_>>(),
            }),
            caveat: None,
        };
        study.conclude(dir, files, &table, &dxs, &errors, quiet)
    }
}

impl Refinable {
    /// The study of a rod or a beam (`method` named) of scenario `table`:
    /// its `model.nodes` refined with its `time.dt` (second order, landing
    /// on `t_end`, no figures), observing by default the first frequency of
    /// a free–free vibration, the tip displacement of a structure with one
    /// free end, else the energy.
    pub fn structure(method: String, table: &toml::Table) -> Self {
        use Observable::{Energy, Frequency, Tip};
        let free = |key: &str| text_at(table, key, "free") == "free";
        Self {
            method,
            order: 2,
            nodes_key: "model.nodes",
            nodes: nodes_at(table, "model.nodes"),
            closed: true,
            scaled: &["time.dt"],
            whole_steps: false,
            outputs: vec![("output.plots", false.into())],
            observables: match (free("ends.start"), free("ends.end")) {
                (true, true) => vec![Frequency, Energy, Tip],
                (false, false) => vec![Energy, Frequency, Tip],
                _ => vec![Tip, Energy, Frequency],
            },
        }
    }
}

/// The string at the dotted `name` of `table`, or `default`.
pub fn text_at<'a>(table: &'a toml::Table, name: &str, default: &'a str) -> &'a str {
    get(table, name).and_then(toml::Value::as_str).unwrap_or(default)
}

/// The node counts at the dotted `name` of `table` (a number or a list).
pub fn nodes_at(table: &toml::Table, name: &str) -> Vec<usize> {
    match get(table, name) {
        Some(toml::Value::Integer(n)) => vec![usize::try_from(*n).unwrap_or(0)],
        Some(toml::Value::Array(a)) => a
            .iter()
            .map(|v| v.as_integer().and_then(|n| usize::try_from(n).ok()).unwrap_or(0))
            .collect(),
        _ => Vec::new(),
    }
}

/// `summary.json` of the run in `dir`.
fn read_summary(dir: &Path) -> Result<Value, CliError> {
    let path = dir.join("summary.json");
    let text = std::fs::read_to_string(&path).map_err(crate::output::io(&path))?;
    serde_json::from_str(&text).map_err(|e| CliError::Io {
        path,
        message: e.to_string(),
    })
}

/// The value at the dotted `name` (table.key) of `table`.
pub fn get<'a>(table: &'a toml::Table, name: &str) -> Option<&'a toml::Value> {
    let (head, rest) = name.split_once('.')?;
    table.get(head)?.as_table()?.get(rest)
}

/// Set the dotted `name` (table.key) of `table`, making the table if needed.
fn set(table: &mut toml::Table, name: &str, value: toml::Value) {
    if let Some((head, rest)) = name.split_once('.') {
        let entry = table
            .entry(head.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if let Some(t) = entry.as_table_mut() {
            t.insert(rest.to_string(), value);
        }
    }
}
