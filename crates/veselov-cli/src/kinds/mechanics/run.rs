//! `veselov run` for mechanics scenarios: the fixed-step job on the run
//! pipeline ([`crate::pipeline`]), streaming `trajectory.csv`/`.npy` and
//! writing `summary.json` and the plots (the variable-step job is
//! [`super::sem_run`]); the scenario's method, initial state and trajectory
//! columns, which the other jobs read too.

use nalgebra::SVector;
use serde_json::json;
use veselov::mechanics::PhaseStepper;
use veselov::mechanics::{GalerkinScheme, Method, PhaseState};
use veselov::run::{Checkpoint, Stepper};

use super::schema::LoadedScenario;
use super::systems::System;
use crate::catalog::{self, Choice};
use crate::error::CliError;
use crate::output::{Table, approx, count, number};
use crate::pipeline::finish::{Totals, finish, open_table_session, start_or_resume, t_of, totals};
use crate::pipeline::stream::TableSink;
use crate::pipeline::table::{Acc, RowFn, TableObserver};
use crate::pipeline::{RunJob, summary};
use crate::scenario::{List, note_step_length, planned_steps};
use crate::verdict::{Conserved, ENERGY_ERROR_MECHANICS, EnergyCheck, StepAdvice};

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
    let note = format!(" (model `{}` has coordinates {coords})", system.model);
    let vector = |key: &str, x: &List<f64>| -> Result<SVector<f64, N>, CliError> {
        let x = x.values(&scenario.path, key, &[N], &note)?;
        Ok(SVector::from_column_slice(&x))
    };
    let q = vector("initial.q", &init.q)?;
    match (&init.p, &init.v) {
        (Some(p), _) => Ok(PhaseState::new(t0, q, vector("initial.p", p)?)),
        (None, Some(v)) => (system.from_velocity)(t0, q, vector("initial.v", v)?)
            .map_err(|e| scenario.key_error("initial.v", e.to_string())),
        (None, None) => Err(scenario.key_error("initial", "missing `p` or `v`")),
    }
}

/// Columns `t, <coordinates>.., p_<coordinate>.., energy, J_<name>..`, and
/// `work` for forced systems: the coordinates under the names the model or
/// scenario gives them (`x, y, p_x, p_y`). Where a name would clash with
/// another column (a coordinate called `energy`, or both `x` and `p_x`) or
/// names are missing, every coordinate is `q<i>` with momentum `p<i>`.
pub fn trajectory_header<const N: usize>(system: &System<N>) -> Vec<String> {
    let momenta: Vec<String> = system.momenta.iter().map(|(n, _)| n.clone()).collect();
    header_of(&system.coordinates, N, &momenta, system.forced)
}

/// The columns of [`trajectory_header`] for `n` coordinates named `names`,
/// momentum maps named `momenta`, and a `work` column if `forced`.
pub fn header_of(names: &[String], n: usize, momenta: &[String], forced: bool) -> Vec<String> {
    let named = |q: &dyn Fn(usize) -> String, p: &dyn Fn(usize) -> String| {
        let mut header = vec!["t".to_string()];
        header.extend((0..n).map(q));
        header.extend((0..n).map(p));
        header.push("energy".into());
        header.extend(momenta.iter().map(|m| format!("J_{m}")));
        if forced {
            header.push("work".into());
        }
        header
    };
    if names.len() == n {
        let header = named(&|i| names[i].clone(), &|i| format!("p_{}", names[i]));
        let mut sorted: Vec<&String> = header.iter().collect();
        sorted.sort();
        if sorted.windows(2).all(|w| w[0] != w[1]) && names.iter().all(|n| !n.is_empty() && !n.contains(',')) {
            return header;
        }
    }
    named(&|i| format!("q{i}"), &|i| format!("p{i}"))
}

/// The row of `x` under [`trajectory_header`]; `work` is the cumulative work of the forces.
pub fn trajectory_row<const N: usize>(system: &System<N>, x: &PhaseState<N>, work: f64) -> Vec<f64> {
    let mut r = Vec::with_capacity(2 + 2 * N + system.momenta.len() + 1);
    r.push(x.t);
    r.extend(x.q.iter());
    r.extend(x.p.iter());
    r.push((system.energy)(x));
    r.extend(system.momenta.iter().map(|(_, j)| j(x)));
    if system.forced {
        r.push(work);
    }
    r
}

/// The table of `states` (with the cumulative `work` at each), for studies that keep it in memory.
pub fn trajectory_table<const N: usize>(system: &System<N>, states: &[PhaseState<N>], work: &[f64]) -> Table {
    Table {
        header: trajectory_header(system),
        rows: states
            .iter()
            .zip(work)
            .map(|(x, w)| trajectory_row(system, x, *w))
            .collect(),
    }
}

/// A fixed-step run of `system` with `method`.
pub fn run_fixed<const N: usize>(
    job: &RunJob,
    scenario: &LoadedScenario,
    system: System<N>,
    method: Method,
) -> Result<(), CliError> {
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
    let dt = scenario.step_length();
    note_step_length(scenario.scenario.method.dt, dt, job.quiet);
    let mut map = (system.make_map)(method, dt, scenario.scenario.method.newton_options())
        .map_err(|e| CliError::Setup(e.to_string()))?;
    let mut stepper = PhaseStepper::new(map.as_mut(), x0.t);
    let system = &system;
    let run = FixedRun {
        job,
        scenario,
        model: &system.model,
        method,
        dt,
        e0,
        dimension: N,
        header: trajectory_header(system),
        momenta: system.momenta.iter().map(|(n, _)| n.clone()).collect(),
        forced: system.forced,
        row: Box::new(move |x: &PhaseState<N>, w| trajectory_row(system, x, w)),
    };
    run_fixed_table(run, &mut stepper, x0)
}

/// The end-of-run energy check of a mechanics or rigid-body run, with the
/// threshold of `[checks]`, unless its energy is not conserved (a
/// Lagrangian depending on `t`): the energy balance when `forced`, else the
/// energy; `advice` says which step to lower.
pub fn energy_check(
    scenario: &LoadedScenario,
    forced: bool,
    advice: StepAdvice,
) -> Result<Option<EnergyCheck>, CliError> {
    let limit = scenario
        .scenario
        .checks
        .energy_limit(&scenario.path, ENERGY_ERROR_MECHANICS)?;
    if super::custom::depends_on_time(scenario) {
        return Ok(None);
    }
    Ok(Some(EnergyCheck {
        conserved: if forced {
            Conserved::EnergyBalance
        } else {
            Conserved::Energy
        },
        limit,
        advice,
    }))
}

/// A fixed-step mechanics run once its integrator is built, for systems of
/// fixed or run-time dimension: what it reports besides the states.
pub struct FixedRun<'a, S> {
    /// The command's options.
    pub job: &'a RunJob,
    /// The scenario.
    pub scenario: &'a LoadedScenario,
    /// The model's name.
    pub model: &'a str,
    /// The method.
    pub method: Method,
    /// The step actually taken.
    pub dt: f64,
    /// The energy of the initial state.
    pub e0: f64,
    /// The number of coordinates.
    pub dimension: usize,
    /// The columns of `trajectory.*` ([`header_of`]).
    pub header: Vec<String>,
    /// The names of the momentum maps (columns `J_<name>`).
    pub momenta: Vec<String>,
    /// Whether forces act (the last column is then the work `W`).
    pub forced: bool,
    /// The row of a state given the cumulative work.
    pub row: RowFn<'a, S>,
}

/// Run `stepper` from `x0` to the scenario's end, streaming the trajectory,
/// and close with the summary, the plots and the final line.
pub fn run_fixed_table<St>(run: FixedRun<'_, St::State>, stepper: &mut St, x0: St::State) -> Result<(), CliError>
where
    St: Stepper + Checkpoint,
    St::State: Checkpoint + Clone,
{
    let FixedRun {
        job,
        scenario,
        model,
        method,
        dt,
        e0,
        dimension,
        header,
        momenta,
        forced,
        row,
    } = run;
    let scheme = GalerkinScheme::new(method).map_err(|e| CliError::Setup(e.to_string()))?;
    let steps = scenario.steps();
    let t0 = stepper.time(&x0);
    // Checked before the session opens its output directory.
    let out = &scenario.scenario.output;
    let at_steps = out.steps_at_times(&scenario.path, t0, dt, steps, job.quiet)?;
    let energy_check = energy_check(
        scenario,
        forced,
        StepAdvice {
            key: "method.dt",
            value: dt,
            order: scheme.order() as u32,
            also: "",
        },
    )?;
    let (mut session, positions, words) = open_table_session(
        job,
        &scenario.path,
        (&scenario.scenario.time, &scenario.scenario.output),
        (planned_steps(&scenario.scenario.time, dt), Some(dt)),
        header.len(),
        "mechanics",
    )?;
    let sink = TableSink::create(
        &session.dir,
        "trajectory",
        &header,
        &out.formats,
        steps / out.every + 2,
        positions,
    )?;
    let columns = header.len();
    let mut table = TableObserver::new(header, row, sink, out.every).at_steps(at_steps);
    table.track("energy", Acc::Dev);
    for name in &momenta {
        table.track(&format!("J_{name}"), Acc::Dev);
    }
    if forced {
        table.balance = Some((1 + 2 * dimension, columns - 1, 0.0));
    }
    session.verdict.energy = energy_check;
    let mut x = x0;
    let outcome = start_or_resume(&mut session, stepper, &mut x, &mut table, &words, steps)?;
    let Totals {
        iterations,
        fallback_steps: fallback,
        force_evaluations,
        jacobians,
    } = totals(&outcome);
    let wall = session.wall_seconds();
    let t_final = t_of(outcome.last_step, t0, dt);
    finish(
        &scenario.scenario.output,
        &session,
        table,
        outcome.status.clone(),
        |t, status| {
            let energy = t.column("energy").map_or(0.0, |c| c.value);
            let mut own = json!({
                "scenario": scenario.path.display().to_string(),
                "model": model,
                "coordinates": dimension,
                "method": method.name(),
                "method_description": scheme.describe(),
                "stages": match method { Method::GalerkinLobatto(s) | Method::GalerkinGauss(s) => Some(s), _ => None },
                "alpha": match method { Method::Alpha(a) => Some(a), _ => None },
                "order": scheme.order(),
                "dt": dt,
                "steps_requested": steps,
                "energy_initial": e0,
                "energy_error_max": energy,
                "energy_error_max_relative": summary::relative_energy_error(energy, e0),
                "momentum_error_max": t.deviations(&momenta),
                "newton_iterations_mean": iterations as f64 / outcome.last_step.max(1) as f64,
                // Exact Jacobians per step on the Newton path (null where not counted).
                "jacobians_mean": (jacobians > 0).then(|| jacobians as f64 / outcome.last_step.max(1) as f64),
                // ∇V evaluations per step on the separable path (null on the Newton path).
                "force_evaluations_mean": (force_evaluations > 0)
                    .then(|| force_evaluations as f64 / outcome.last_step.max(1) as f64),
                "fallback_steps": fallback,
            });
            if forced {
                own["work_of_forces"] = json!(t.work());
                own["energy_balance_error_max"] = json!(t.balance.map_or(0.0, |b| b.2));
            }
            summary::common(status, (outcome.last_step, 1), t_final, wall, iterations, own)
        },
        |t| match t.balance {
            // Forced: E is not conserved; the meaningful figure is the energy balance.
            Some((_, _, balance)) => format!(
                "{}: {} to t = {}, max |E − E₀ − W| = {} (energy balance; work of the forces W = {})",
                scheme.describe(),
                count(outcome.last_step, "step", "steps"),
                number(t_final),
                approx(balance),
                approx(t.work())
            ),
            None => format!(
                "{}: {} to t = {}, max |E − E₀| = {}",
                scheme.describe(),
                count(outcome.last_step, "step", "steps"),
                number(t_final),
                approx(t.column("energy").map_or(0.0, |c| c.value))
            ),
        },
    )
}
