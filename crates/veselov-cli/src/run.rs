//! `veselov run`: integrate a scenario and write trajectory, summary and plots.

use std::path::{Path, PathBuf};
use std::time::Instant;

use nalgebra::SVector;
use serde_json::json;
use veselov::mechanics::{GalerkinScheme, Method, PhaseState, integrate_observed};
use veselov::sem::{SemRule, SemState, run_sem};

use crate::catalog::{self, Choice};
use crate::error::CliError;
use crate::figures;
use crate::output::{Table, prepare_dir, write_json};
use crate::progress::Progress;
use crate::scenario::LoadedScenario;
use crate::systems::{Job, System};

/// Options of `veselov run`.
pub struct RunJob {
    /// `--out`.
    pub out: Option<PathBuf>,
    /// `--quiet`.
    pub quiet: bool,
    /// `--force`.
    pub force: bool,
}

/// The scenario's method, with errors naming the key.
pub fn resolve_choice(scenario: &LoadedScenario) -> Result<Choice, CliError> {
    let m = &scenario.scenario.method;
    catalog::choice(&m.name, m.stages, m.alpha).map_err(|(key, msg)| scenario.key_error(&key, msg))
}

/// The scenario's fixed-step method (errors for variable-step ones, naming the key).
pub fn resolve_method(scenario: &LoadedScenario) -> Result<Method, CliError> {
    match resolve_choice(scenario)? {
        Choice::Fixed(m) => Ok(m),
        Choice::Variable(rule) => Err(scenario.key_error(
            "method.name",
            format!(
                "`{}` is a variable-step method; this command needs a fixed-step one",
                rule.name()
            ),
        )),
    }
}

/// The scenario's initial state (or the model's default), with dimension checks.
pub fn resolve_initial<const N: usize>(
    scenario: &LoadedScenario,
    system: &System<N>,
) -> Result<PhaseState<N>, CliError> {
    let t0 = scenario.scenario.time.t0;
    let Some(init) = &scenario.scenario.initial else {
        return match system.default_initial {
            Some(x) => Ok(PhaseState::new(t0, x.q, x.p)),
            None => Err(scenario.key_error("initial", "missing: custom models need [initial] q and p (or v)")),
        };
    };
    let coords = system.coordinates.join(", ");
    let vector = |key: &str, x: &[f64]| -> Result<SVector<f64, N>, CliError> {
        if x.len() != N {
            return Err(scenario.key_error(
                key,
                format!(
                    "expected {N} values (model `{}` has coordinates {coords}), got {}",
                    system.model,
                    x.len()
                ),
            ));
        }
        Ok(SVector::from_column_slice(x))
    };
    let q = vector("initial.q", &init.q)?;
    match (&init.p, &init.v) {
        (Some(p), _) => Ok(PhaseState::new(t0, q, vector("initial.p", p)?)),
        (None, Some(v)) => (system.from_velocity)(t0, q, vector("initial.v", v)?)
            .map_err(|e| scenario.key_error("initial.v", e.to_string())),
        (None, None) => Err(scenario.key_error("initial", "missing `p` or `v`")),
    }
}

/// Columns `t, q0.., p0.., energy, J_<name>..` for `states`, and `work`
/// (cumulative discrete work of the forces) for forced systems.
pub fn trajectory_table<const N: usize>(system: &System<N>, states: &[PhaseState<N>], work: &[f64]) -> Table {
    let mut header = vec!["t".to_string()];
    header.extend((0..N).map(|i| format!("q{i}")));
    header.extend((0..N).map(|i| format!("p{i}")));
    header.push("energy".into());
    header.extend(system.momenta.iter().map(|(n, _)| format!("J_{n}")));
    if system.forced {
        header.push("work".into());
    }
    let rows = states
        .iter()
        .zip(work)
        .map(|(x, w)| {
            let mut r = Vec::with_capacity(header.len());
            r.push(x.t);
            r.extend(x.q.iter());
            r.extend(x.p.iter());
            r.push((system.energy)(x));
            r.extend(system.momenta.iter().map(|(_, j)| j(x)));
            if system.forced {
                r.push(*w);
            }
            r
        })
        .collect();
    Table { header, rows }
}

fn max_dev(values: &[f64]) -> f64 {
    veselov::diagnostics::max_abs_deviation(values)
}

impl Job for RunJob {
    fn run<const N: usize>(self, scenario: &LoadedScenario, system: System<N>) -> Result<(), CliError> {
        match resolve_choice(scenario)? {
            Choice::Fixed(method) => self.run_fixed(scenario, system, method),
            Choice::Variable(rule) => self.run_variable(scenario, system, rule),
        }
    }
}

impl RunJob {
    fn run_fixed<const N: usize>(
        self,
        scenario: &LoadedScenario,
        system: System<N>,
        method: Method,
    ) -> Result<(), CliError> {
        let start = Instant::now();
        let x0 = resolve_initial(scenario, &system)?;
        let e0 = (system.energy)(&x0);
        if !e0.is_finite() {
            return Err(scenario.key_error(
                if system.model == "custom" {
                    "model.lagrangian"
                } else {
                    "initial"
                },
                "the energy is not finite at the initial state (is the Lagrangian defined and regular there?)",
            ));
        }
        let dt = scenario.scenario.method.dt;
        let mut map = (system.make_map)(method, dt).map_err(|e| CliError::Setup(e.to_string()))?;
        let dir = prepare_dir(&scenario.output_dir(self.out.as_deref()), self.force)?;
        let steps = scenario.steps() as usize;
        let every = scenario.scenario.output.every as usize;
        let mut progress = Progress::new(steps as u64, self.quiet);
        let traj = integrate_observed(map.as_mut(), x0, steps, every, |k, _| progress.set(k as u64));
        progress.finish();
        let mut failure = traj.failure.clone();
        let mut table = trajectory_table(&system, &traj.states, &traj.work);
        let energy_col = 1 + 2 * N;
        if failure.is_none()
            && let Some(k) = table.rows.iter().position(|r| !r[energy_col].is_finite())
        {
            failure = Some(veselov::Error::NonFiniteState {
                step: k * every,
                t: table.rows[k][0],
                what: "energy".into(),
            });
            table.rows.truncate(k + 1);
        }
        let energies: Vec<f64> = table.rows.iter().map(|r| r[energy_col]).collect();
        let scheme = GalerkinScheme::new(method).map_err(|e| CliError::Setup(e.to_string()))?;
        let work: Vec<f64> = traj.work[..table.rows.len()].to_vec();
        let balance = energies
            .iter()
            .zip(&work)
            .fold(0.0_f64, |m, (e, w)| m.max((e - e0 - w).abs()));
        let mut summary = json!({
            "status": if failure.is_none() { "ok" } else { "error" },
            "error": failure.as_ref().map(|e| e.to_string()),
            "scenario": scenario.path.display().to_string(),
            "model": system.model,
            "method": method.name(),
            "method_description": scheme.describe(),
            "stages": match method { Method::GalerkinLobatto(s) | Method::GalerkinGauss(s) => Some(s), _ => None },
            "alpha": match method { Method::Alpha(a) => Some(a), _ => None },
            "order": scheme.order(),
            "dt": dt,
            "steps": traj.steps,
            "steps_requested": steps,
            "t_final": traj.last().t,
            "energy_initial": e0,
            "energy_error_max": max_dev(&energies),
            "momentum_error_max": momentum_errors(&system, &table),
            "newton_iterations_mean": traj.mean_iterations(),
            "fallback_steps": traj.fallback_steps,
            "wall_seconds": start.elapsed().as_secs_f64(),
        });
        if system.forced {
            summary["work_of_forces"] = json!(work.last().copied().unwrap_or(0.0));
            summary["energy_balance_error_max"] = json!(balance);
        }
        let report = format!(
            "{}: {} steps to t = {}, max |E − E₀| = {:.3e}",
            scheme.describe(),
            traj.steps,
            traj.last().t,
            max_dev(&energies)
        );
        self.finish::<N>(scenario, dir, &table, &summary, &report, failure)
    }

    /// Write the trajectory, the summary and the plots, report, and turn a
    /// failure into the run error (the partial outputs are already written).
    fn finish<const N: usize>(
        &self,
        scenario: &LoadedScenario,
        dir: PathBuf,
        table: &Table,
        summary: &serde_json::Value,
        report: &str,
        failure: Option<veselov::Error>,
    ) -> Result<(), CliError> {
        write_outputs(scenario, &dir, table)?;
        write_json(&dir.join("summary.json"), summary)?;
        if scenario.scenario.output.plots {
            figures::draw_all(&dir, table, N, &scenario.scenario.output.plot_format)?;
        }
        if !self.quiet {
            eprintln!("{report}; outputs in {}", dir.display());
        }
        match failure {
            Some(error) => Err(CliError::Run { error, dir }),
            None => Ok(()),
        }
    }
}

/// `max |J_k − J_0|` over the stored rows, for every momentum-map column.
fn momentum_errors<const N: usize>(system: &System<N>, table: &Table) -> serde_json::Map<String, serde_json::Value> {
    system
        .momenta
        .iter()
        .map(|(name, _)| {
            let col = table.column(&format!("J_{name}")).unwrap_or_default();
            (name.clone(), json!(max_dev(&col)))
        })
        .collect()
}

impl RunJob {
    /// A variable-step SEM run: `dt` is the first step, the run stops at the first `t_k ≥ t_end`
    /// (or after `steps` steps).
    fn run_variable<const N: usize>(
        self,
        scenario: &LoadedScenario,
        system: System<N>,
        rule: SemRule,
    ) -> Result<(), CliError> {
        let start = Instant::now();
        let Some(make) = &system.make_sem else {
            return Err(scenario.key_error(
                "method.name",
                format!(
                    "`{}` conserves energy and cannot integrate the forced model `{}`",
                    rule.name(),
                    system.model
                ),
            ));
        };
        let x0 = resolve_initial(scenario, &system)?;
        let mut map = make(rule).map_err(|e| CliError::Setup(e.to_string()))?;
        let dir = prepare_dir(&scenario.output_dir(self.out.as_deref()), self.force)?;
        let (t_end, max_steps) = match (scenario.scenario.time.t_end, scenario.scenario.time.steps) {
            (Some(t), _) => (t, usize::MAX),
            (None, Some(n)) => (f64::INFINITY, n as usize),
            (None, None) => (x0.t, 0),
        };
        let dt = scenario.scenario.method.dt;
        let run = run_sem(map.as_mut(), x0.t, x0.q, x0.p, dt, t_end, max_steps, false);
        let every = scenario.scenario.output.every as usize;
        let kept: Vec<&SemState<N>> = run
            .states
            .iter()
            .enumerate()
            .filter(|(k, _)| k % every == 0 || *k + 1 == run.states.len())
            .map(|(_, s)| s)
            .collect();
        let phase: Vec<PhaseState<N>> = kept.iter().map(|s| PhaseState::new(s.t, s.q, s.p)).collect();
        let mut table = trajectory_table(&system, &phase, &vec![0.0; phase.len()]);
        table.header.push("h".into());
        table.header.push("discrete_energy".into());
        for (row, s) in table.rows.iter_mut().zip(&kept) {
            row.push(s.h);
            row.push(s.energy);
        }
        let energies: Vec<f64> = table.rows.iter().map(|r| r[1 + 2 * N]).collect();
        let e0 = energies.first().copied().unwrap_or(f64::NAN);
        let discrete: Vec<f64> = run.states.iter().skip(1).map(|s| s.energy).collect();
        let steps: Vec<f64> = run.states.iter().skip(1).map(|s| s.h).collect();
        let last = run.states.last().map(|s| s.t).unwrap_or(x0.t);
        let summary = json!({
            "status": if run.failure.is_none() { "ok" } else { "error" },
            "error": run.failure.as_ref().map(|e| e.to_string()),
            "scenario": scenario.path.display().to_string(),
            "model": system.model,
            "method": rule.name(),
            "order": if rule == SemRule::LeftPoint { 1 } else { 2 },
            "dt": dt,
            "steps": run.states.len().saturating_sub(1),
            "t_final": last,
            "energy_initial": e0,
            "energy_error_max": max_dev(&energies),
            "discrete_energy": discrete.first(),
            "discrete_energy_error_max": max_dev(&discrete),
            "h_min": steps.iter().copied().fold(f64::INFINITY, f64::min),
            "h_max": steps.iter().copied().fold(0.0, f64::max),
            "fallback_steps": run.flagged_steps.len(),
            "momentum_error_max": momentum_errors(&system, &table),
            "newton_iterations_mean": run.iterations as f64 / steps.len().max(1) as f64,
            "wall_seconds": start.elapsed().as_secs_f64(),
        });
        let report = format!("{}: {} steps to t = {last}", rule.name(), steps.len());
        self.finish::<N>(scenario, dir, &table, &summary, &report, run.failure)
    }
}

fn write_outputs(scenario: &LoadedScenario, dir: &Path, table: &Table) -> Result<(), CliError> {
    for f in &scenario.scenario.output.formats {
        match f.as_str() {
            "csv" => table.write_csv(&dir.join("trajectory.csv"))?,
            "npy" => table.write_npy(&dir.join("trajectory.npy"))?,
            _ => {}
        }
    }
    Ok(())
}
