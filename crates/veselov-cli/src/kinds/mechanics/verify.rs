//! `veselov verify` for mechanics scenarios: convergence study of the
//! scenario's method ([`crate::verify::Study`]).
//!
//! Reference: the exact solution where the model has one for the scenario's
//! initial data; otherwise a run of Galerkin Gauss with s = 5 stages (order 10)
//! at one sixteenth of the smallest requested step — its error is smaller than
//! the studied method's by many orders of magnitude.

use veselov::mechanics::{GalerkinScheme, Method, OneStepMap, PhaseState, integrate};
use veselov::sem::run_sem;

use super::run::{resolve_choice, resolve_initial};
use super::schema::LoadedScenario;
use super::sem_run::{degenerate_start, sem_factory};
use super::systems::{Job, System};
use crate::catalog::Choice;
use crate::error::CliError;
use crate::pipeline::manifest::prepare_dir;
use crate::verify::{STATE_ERROR, Study, TIME_STEP, VerifyJob, note_adjusted, study_steps};

fn run_to<const N: usize>(
    map: &mut dyn OneStepMap<N>,
    x0: PhaseState<N>,
    steps: usize,
) -> Result<PhaseState<N>, veselov::Error> {
    let traj = integrate(map, x0, steps, steps.max(1));
    match traj.failure {
        Some(e) => Err(e),
        None => Ok(*traj.last()),
    }
}

/// A variable-step run may take this many times the steps `(t_end − t0)/dt`
/// of its first step before it is reported as not reaching `t_end`.
const SEM_STEP_ALLOWANCE: usize = 100;

impl Job for VerifyJob {
    fn run<const N: usize>(self, scenario: &LoadedScenario, system: System<N>) -> Result<(), CliError> {
        self.time_step_study(&scenario.path)?;
        let choice = resolve_choice(scenario)?;
        let (name, order) = match choice {
            Choice::Fixed(method) => (
                method.name().to_string(),
                GalerkinScheme::new(method)
                    .map_err(|e| CliError::Setup(e.to_string()))?
                    .order(),
            ),
            Choice::Variable(rule) => {
                sem_factory(scenario, &system, rule)?;
                (rule.name().to_string(), rule.order())
            }
        };
        let x0 = resolve_initial(scenario, &system)?;
        let t0 = x0.t;
        let t_end = match scenario.scenario.time.t_end {
            Some(t) => t,
            None => t0 + scenario.steps() as f64 * scenario.scenario.method.dt,
        };
        let span = t_end - t0;
        let (steps, dts) = match choice {
            Choice::Fixed(_) => {
                let (steps, dts) = study_steps(&scenario.path, &self.dts, span)?;
                note_adjusted(&self.dts, &dts, self.quiet);
                (steps, dts)
            }
            // The first step of a variable-step run is taken as given (the
            // last step lands on t_end); `steps` is the count at that step.
            Choice::Variable(_) => (study_steps(&scenario.path, &self.dts, span)?.0, self.dts.clone()),
        };
        let (reference, source) = match system.exact.as_ref().and_then(|f| f(&x0, t_end)) {
            Some(x) => (x, "exact solution".to_string()),
            None => {
                let h_min = dts.iter().copied().fold(f64::INFINITY, f64::min);
                let n = (span / (h_min / 16.0)).ceil() as usize;
                let mut map = (system.make_map)(Method::GalerkinGauss(5), span / n as f64, Default::default())
                    .map_err(|e| CliError::Setup(e.to_string()))?;
                let x =
                    run_to(map.as_mut(), x0, n).map_err(|e| CliError::Setup(format!("reference run failed: {e}")))?;
                (x, format!("galerkin-gauss s = 5, {n} steps"))
            }
        };
        let dir = prepare_dir(
            &self
                .out
                .clone()
                .unwrap_or_else(|| scenario.output_dir(None).join("verify")),
            self.force,
        )?;
        let study = Study {
            method: name,
            order,
            reference: source,
            t_end,
            scale: reference.q.amax().max(reference.p.amax()).max(1.0),
            interrupt: self.interrupt.clone(),
            error_label: STATE_ERROR.into(),
            step: TIME_STEP,
            extra: serde_json::Value::Null,
            caveat: None,
        };
        let options = scenario.scenario.method.newton_options();
        let error = |x: &PhaseState<N>| (x.q - reference.q).amax().max((x.p - reference.p).amax());
        match choice {
            Choice::Variable(rule) => {
                let make = sem_factory(scenario, &system, rule)?;
                // A start on the degeneracy set, even at the finest step:
                // the steps do not follow dt, and no order is to be had.
                let finest = dts.iter().copied().fold(f64::INFINITY, f64::min);
                let map = make(rule).map_err(|e| CliError::Setup(e.to_string()))?;
                let study = Study {
                    caveat: degenerate_start(map.as_ref(), &x0, finest, rule),
                    ..study
                };
                study.run(&dir, &dts, &steps, self.quiet, |n, h0| {
                    // `h0` is the first step; the steps follow from the discrete
                    // energy, and the last is shortened to land on t_end.
                    let mut map = make(rule).map_err(|e| CliError::Setup(e.to_string()))?;
                    let limit = n.saturating_mul(SEM_STEP_ALLOWANCE);
                    let run = run_sem(map.as_mut(), t0, x0.q, x0.p, h0, t_end, limit, true);
                    Ok(match (run.failure, run.states.last()) {
                        (Some(e), _) => Err(e),
                        (None, Some(s)) if s.t == t_end => Ok(error(&PhaseState::new(s.t, s.q, s.p))),
                        (None, s) => Err(veselov::Error::InvalidParameter {
                            name: "--dt".into(),
                            value: format!("{h0:e}"),
                            reason: format!(
                                "the variable steps did not reach t_end = {t_end} within {limit} steps (stopped at \
                                 t = {})",
                                s.map_or(t0, |s| s.t)
                            ),
                        }),
                    })
                })
            }
            Choice::Fixed(method) => study.run(&dir, &dts, &steps, self.quiet, |n, dt| {
                let mut map = (system.make_map)(method, dt, options).map_err(|e| CliError::Setup(e.to_string()))?;
                Ok(run_to(map.as_mut(), x0, n).map(|x| error(&x)))
            }),
        }
    }

    fn run_dynamic(self, scenario: &LoadedScenario) -> Result<(), CliError> {
        Err(scenario.key_error(
            "model.coordinates",
            format!(
                "verify takes custom models of at most {} coordinates (larger ones run with `veselov run`)",
                super::custom::MAX_FIXED_DIMENSION
            ),
        ))
    }
}
