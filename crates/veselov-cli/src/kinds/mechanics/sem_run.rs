//! `veselov run` for mechanics scenarios with a variable-step method: the
//! symplectic-energy-momentum (SEM) job on the run pipeline
//! ([`crate::pipeline`]), streaming `trajectory.csv`/`.npy` (with the step
//! `h` and the discrete energy) and writing `summary.json` and the plots.

use serde_json::json;
use veselov::mechanics::PhaseState;
use veselov::run::{Checkpoint, StopWhen, Words};
use veselov::sem::SemStepper;
use veselov::sem::{SemRule, SemState, VariableStepMap};

use super::run::{resolve_initial, trajectory_header, trajectory_row};
use super::schema::LoadedScenario;
use super::systems::{SemFactory, System};
use crate::error::CliError;
use crate::output::{approx, number};
use crate::pipeline::finish::{Totals, finish, open_table_session, totals};
use crate::pipeline::stream::TableSink;
use crate::pipeline::table::{Acc, TableObserver, Tracker};
use crate::pipeline::{RunJob, Session, restore, summary, words_error};
use crate::verdict::{DEGENERATE_DOMINANCE, DEGENERATE_DRIFT, STEP_RUNAWAY_FACTOR, StepAdvice, Warning};

/// The system's variable-step integrator factory, or (for a forced model,
/// which no energy-conserving step can integrate) an error naming the key.
pub fn sem_factory<'a, const N: usize>(
    scenario: &LoadedScenario,
    system: &'a System<N>,
    rule: SemRule,
) -> Result<&'a SemFactory<N>, CliError> {
    system.make_sem.as_ref().ok_or_else(|| {
        scenario.key_error(
            "method.name",
            format!(
                "`{}` conserves energy and cannot integrate the forced model `{}`",
                rule.name(),
                system.model
            ),
        )
    })
}

/// A variable-step SEM run: `dt` is the first step, the run stops at the first `t_k ≥ t_end`
/// (or after `steps` steps).
pub fn run_variable<const N: usize>(
    job: &RunJob,
    scenario: &LoadedScenario,
    system: System<N>,
    rule: SemRule,
) -> Result<(), CliError> {
    let make = sem_factory(scenario, &system, rule)?;
    let x0 = resolve_initial(scenario, &system)?;
    let mut map = make(rule).map_err(|e| CliError::Setup(e.to_string()))?;
    let s = &scenario.scenario;
    let dt = s.method.dt;
    let (t_end, max_steps) = match (s.time.t_end, s.time.steps) {
        (Some(t), _) => (t, u64::MAX),
        (None, Some(n)) => (f64::INFINITY, n),
        (None, None) => (x0.t, 0),
    };
    // The step count of a variable-step run is estimated from the first step.
    let planned = if max_steps == u64::MAX {
        (t_end - x0.t) / dt
    } else {
        max_steps as f64
    };
    if !s.output.times.is_empty() {
        return Err(scenario.key_error(
            "output.times",
            "a variable-step run does not know its step times in advance; use `every`",
        ));
    }
    let energy_check = super::run::energy_check(
        scenario,
        system.forced,
        StepAdvice {
            key: "method.dt",
            value: dt,
            order: if rule == SemRule::LeftPoint { 1 } else { 2 },
            also: "`dt` is the first step, which sets the discrete energy the steps keep",
        },
    )?;
    let system = &system;
    let (mut session, mut table, words) = open_variable(job, scenario, system, planned)?;
    session.verdict.energy = energy_check;
    // On or near the degeneracy set, the steps do not follow `dt`: the
    // energy check's advice (a smaller dt) would not help.
    if let Some(message) = degenerate_start(map.as_ref(), &x0, dt, rule) {
        session.verdict.warn("degenerate_start", message);
        session.verdict.energy = None;
    }
    let out = &s.output;
    let started = session.resumed.is_none().then(|| map.start(x0.t, x0.q, x0.p, dt));
    let mut stepper = SemStepper::new(map.as_mut(), None);
    let (mut x, first, failure) = start_variable(
        &session,
        started,
        &mut stepper,
        &mut table,
        &words,
        (&x0, dt, max_steps, out.every),
    )?;
    let stop = StopWhen {
        steps: Some(max_steps),
        t_end: Some(t_end),
        interrupt: None,
    };
    let start = failure.map_or(Ok(()), Err);
    let outcome = session.execute(start, &mut stepper, &mut x, first, stop, &mut table)?;
    let Totals {
        iterations,
        fallback_steps: fallback,
        jacobians,
        ..
    } = totals(&outcome);
    let wall = session.wall_seconds();
    let t_final = x.t;
    let h_max = table.states.get(2).map_or(0.0, |(_, t)| t.value);
    if rule == SemRule::LeftPoint && h_max > STEP_RUNAWAY_FACTOR * dt {
        session.verdict.ending.push(Warning {
            code: "step_runaway",
            message: format!(
                "the step grew from dt = {} to {} ({}×): started at or near a turning point, sem-leftpoint \
                 follows the branch of its energy equation whose steps grow with the time since that point, \
                 and a smaller dt does not bring the run closer to the solution; start away from a turning \
                 point, or use sem-midpoint or sem-averaged, which do not have this degeneracy",
                number(dt),
                approx(h_max),
                approx(h_max / dt)
            ),
        });
        session.verdict.energy = None;
    }
    finish(
        &scenario.scenario.output,
        &session,
        table,
        outcome.status.clone(),
        |t, status| {
            let names: Vec<String> = system.momenta.iter().map(|(n, _)| n.clone()).collect();
            let tracked = |i: usize| t.states.get(i).map(|s| s.1);
            let own = json!({
                "scenario": scenario.path.display().to_string(),
                "model": system.model,
                "method": rule.name(),
                "order": if rule == SemRule::LeftPoint { 1 } else { 2 },
                "dt": dt,
                "energy_initial": t.column("energy").map_or(f64::NAN, |c| c.first),
                "energy_error_max": t.column("energy").map_or(0.0, |c| c.value),
                "energy_error_max_relative": t
                    .column("energy")
                    .map_or(serde_json::Value::Null, |c| summary::relative_energy_error(c.value, c.first)),
                "discrete_energy": tracked(0).map(|c| c.first).filter(|e| !e.is_nan()),
                "discrete_energy_error_max": tracked(0).map_or(0.0, |c| c.value),
                "h_min": tracked(1).map_or(f64::INFINITY, |c| c.value),
                "h_max": tracked(2).map_or(0.0, |c| c.value.max(0.0)),
                "fallback_steps": fallback,
                "momentum_error_max": t.deviations(&names),
                "newton_iterations_mean": iterations as f64 / outcome.last_step.max(1) as f64,
                "jacobians_mean": jacobians as f64 / outcome.last_step.max(1) as f64,
            });
            summary::common(status, (outcome.last_step, 1), t_final, wall, iterations, own)
        },
        |_| {
            format!(
                "{}: {} to t = {}",
                rule.name(),
                crate::output::count(outcome.last_step, "step", "steps"),
                crate::output::number(t_final)
            )
        },
    )
}

/// The warning of a start from `x0` with first step `dt` on or near the
/// degeneracy set of the energy equation (its leading term in the step no
/// larger than [`DEGENERATE_DOMINANCE`] times the next:
/// [`veselov::sem::StartExpansion`]), if it is one.
pub(super) fn degenerate_start<const N: usize>(
    map: &dyn VariableStepMap<N>,
    x0: &PhaseState<N>,
    dt: f64,
    rule: SemRule,
) -> Option<String> {
    let expansion = map.start_expansion(x0.t, x0.q, x0.p, dt).ok()?;
    let dominance = expansion.dominance();
    (dominance < DEGENERATE_DOMINANCE && expansion.drift() > DEGENERATE_DRIFT).then(|| {
        let why = if rule == SemRule::LeftPoint {
            "a turning point (p·∇V = 0) or a critical point of V"
        } else {
            "a point where the energy equation's leading coefficient c(q, p) vanishes"
        };
        format!(
            "the start is on or near {why}: in the first step's energy the term c·dt^{} that sets the steps \
             is only {}× the next (below {}), so the steps will not follow dt and a smaller dt may not bring \
             the run closer to the solution; start away from it{}",
            rule.order(),
            approx(dominance),
            number(DEGENERATE_DOMINANCE),
            if rule == SemRule::LeftPoint {
                ", or use sem-midpoint or sem-averaged, which do not have this degeneracy at turning points"
            } else {
                ""
            }
        )
    })
}

/// The session of a variable-step run of about `planned` steps, the
/// observer of its trajectory (with the step `h` and the discrete energy)
/// and the observer's words of the checkpoint it resumes from.
fn open_variable<'a, const N: usize>(
    job: &RunJob,
    scenario: &LoadedScenario,
    system: &'a System<N>,
    planned: f64,
) -> Result<(Session, TableObserver<'a, SemState<N>>, Vec<f64>), CliError> {
    let s = &scenario.scenario;
    let mut header = trajectory_header(system);
    header.push("h".into());
    header.push("discrete_energy".into());
    let (session, positions, words) = open_table_session(
        job,
        &scenario.path,
        (&s.time, &s.output),
        (planned, None),
        header.len(),
        "mechanics",
    )?;
    let out = &s.output;
    let rows = (planned / out.every as f64 + 2.0).min(u64::MAX as f64) as u64;
    let sink = TableSink::create(&session.dir, "trajectory", &header, &out.formats, rows, positions)?;
    let mut table = TableObserver::new(
        header,
        Box::new(move |x: &SemState<N>, _| {
            let mut row = trajectory_row(system, &PhaseState::new(x.t, x.q, x.p), 0.0);
            row.extend([x.h, x.energy]);
            row
        }),
        sink,
        out.every,
    );
    table.track("energy", Acc::Dev);
    for (name, _) in &system.momenta {
        table.track(&format!("J_{name}"), Acc::Dev);
    }
    table.states = vec![
        (|x: &SemState<N>| x.energy, Tracker::new(Acc::Dev)),
        (|x: &SemState<N>| x.h, Tracker::new(Acc::Min)),
        (|x: &SemState<N>| x.h, Tracker::new(Acc::Max)),
    ];
    Ok((session, table, words))
}

/// Where a variable-step run starts: resuming, the state, step and stepper
/// restored from the checkpoint; otherwise the first two states of
/// `started` (the start from `x0` with first step `dt`) recorded, the run
/// at step 1 (at step 0 when `max_steps` is 0), or the start's failure.
/// Returns the state, its step and the failure, if any.
fn start_variable<const N: usize, St: Checkpoint>(
    session: &Session,
    started: Option<veselov::Result<(SemState<N>, SemState<N>)>>,
    stepper: &mut St,
    table: &mut TableObserver<'_, SemState<N>>,
    words: &[f64],
    (x0, dt, max_steps, every): (&PhaseState<N>, f64, u64, u64),
) -> Result<(SemState<N>, u64, Option<veselov::Error>), CliError> {
    Ok(match (session.resumed.clone(), started) {
        (Some(saved), _) => {
            let mut x = SemState {
                t: x0.t,
                q: x0.q,
                p: x0.p,
                energy: 0.0,
                h: dt,
            };
            restore(&session.dir, &mut x, &mut Words::new(&saved.state))?;
            restore(&session.dir, stepper, &mut Words::new(&saved.stepper))?;
            table
                .resume(saved.step, &x, &mut Words::new(words))
                .map_err(|e| words_error(&session.dir, e))?;
            (x, saved.step, None)
        }
        (None, started) => match started.unwrap_or(Err(veselov::Error::InvalidStep { h: dt })) {
            Ok((s0, s1)) => {
                let mut failure = table.start(0, &s0).err();
                if max_steps > 0 && failure.is_none() {
                    for (f, t) in &mut table.states {
                        t.push(f(&s1));
                    }
                    if every == 1 {
                        failure = table.write(1, &s1).err();
                    }
                    table.start_at(1, &s1);
                }
                let first = u64::from(max_steps > 0);
                (if first == 1 { s1 } else { s0 }, first, failure)
            }
            Err(e) => (SemState::first(x0.t, x0.q, x0.p, dt), 0, Some(e)),
        },
    })
}
