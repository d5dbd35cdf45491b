//! `veselov verify`: convergence study of the scenario's method.
//!
//! Reference: the exact solution where the model has one for the scenario's
//! initial data; otherwise a run of Galerkin Gauss with s = 5 stages (order 10)
//! at one sixteenth of the smallest requested step — its error is smaller than
//! the studied method's by many orders of magnitude.

use std::path::PathBuf;

use serde_json::json;
use veselov::diagnostics::{fit_order_auto, local_rates};
use veselov::mechanics::{GalerkinScheme, Method, OneStepMap, PhaseState, integrate};
use veselov::sem::run_sem;

use crate::catalog::Choice;
use crate::error::CliError;
use crate::figures::draw_convergence;
use crate::output::{Table, prepare_dir, write_json};
use crate::run::{resolve_choice, resolve_initial, sem_factory};
use crate::scenario::{LoadedScenario, landing_steps, note_step_length};
use crate::systems::{Job, System};

/// Options of `veselov verify`.
pub struct VerifyJob {
    /// `--dt` list.
    pub dts: Vec<f64>,
    /// `--out`.
    pub out: Option<PathBuf>,
    /// `--force`.
    pub force: bool,
    /// `--quiet`.
    pub quiet: bool,
}

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

/// The most steps one `--dt` may ask for (a guard against `--dt 1e-300`).
pub const MAX_VERIFY_STEPS: f64 = 1e8;

/// The step counts of a study: `n = round(span/dt)` steps of `span/n` for each
/// `--dt`, so that every run ends exactly at `t_end` (the same rule as `run`
/// for the beam and rod kinds). Returns the counts and the steps actually
/// taken; an error names `--dt` when a value is not a positive number, or asks
/// for more than [`MAX_VERIFY_STEPS`] steps.
pub fn study_steps(file: &std::path::Path, dts: &[f64], span: f64) -> Result<(Vec<usize>, Vec<f64>), CliError> {
    let bad = |message: String| CliError::Key {
        file: file.to_path_buf(),
        key: "--dt".into(),
        message,
    };
    if !(span.is_finite() && span > 0.0) {
        return Err(bad(format!(
            "the horizon t_end − t0 = {span} must be a positive number"
        )));
    }
    let (mut steps, mut taken) = (Vec::new(), Vec::new());
    for &dt in dts {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(bad(format!("{dt} is not a positive step")));
        }
        let n = landing_steps(span, dt);
        if n > MAX_VERIFY_STEPS {
            return Err(bad(format!(
                "{dt:e} asks for {n:e} steps over t_end − t0 = {span}; at most {MAX_VERIFY_STEPS:e} per run"
            )));
        }
        steps.push(n as usize);
        taken.push(span / n);
    }
    Ok((steps, taken))
}

/// Say which requested steps were adjusted to land on `t_end` (by more than a
/// relative 1e-12).
pub fn note_adjusted(requested: &[f64], taken: &[f64], quiet: bool) {
    for (&r, &t) in requested.iter().zip(taken) {
        note_step_length(r, t, quiet);
    }
}

/// A convergence study: what is measured against what.
pub struct Study {
    /// Method name.
    pub method: String,
    /// Its claimed order.
    pub order: usize,
    /// The reference's description.
    pub reference: String,
    /// Final time.
    pub t_end: f64,
    /// Size of the reference state (sets the round-off floor of the fit).
    pub scale: f64,
}

impl Study {
    /// For each `dt` (with `n` steps) measure `error(n, dt)` (an `Err` inside is a
    /// failed run, reported and recorded as NaN), print the table and the
    /// fitted order, and write `convergence.csv`, `summary.json` and
    /// `convergence.svg` into `dir`.
    pub fn run(
        &self,
        dir: &std::path::Path,
        dts: &[f64],
        steps: &[usize],
        quiet: bool,
        mut error: impl FnMut(usize, f64) -> Result<Result<f64, veselov::Error>, CliError>,
    ) -> Result<(), CliError> {
        let order = self.order;
        let mut table = Table {
            header: vec!["dt".into(), "steps".into(), "error".into()],
            rows: Vec::new(),
        };
        if !quiet {
            crate::say!("reference: {}; method {} (order {order})", self.reference, self.method);
            crate::say!("{:>14} {:>10} {:>14} {:>8}", "dt", "steps", "error", "rate");
        }
        let mut previous: Option<(f64, f64)> = None;
        for (&dt, &n) in dts.iter().zip(steps) {
            let err = match error(n, dt)? {
                Ok(e) => e,
                Err(e) => {
                    if !quiet {
                        crate::say!("{dt:>14.6e} {n:>10} failed: {e}");
                    }
                    f64::NAN
                }
            };
            let rate = previous.map(|(h, e)| (e / err).ln() / (h / dt).ln());
            if !quiet {
                let rate = rate.map(|r| format!("{r:8.3}")).unwrap_or_default();
                crate::say!("{dt:>14.6e} {n:>10} {err:>14.6e} {rate}");
            }
            previous = Some((dt, err));
            table.rows.push(vec![dt, n as f64, err]);
        }
        let dts: Vec<f64> = table.rows.iter().map(|r| r[0]).collect();
        let errs: Vec<f64> = table.rows.iter().map(|r| r[2]).collect();
        // The asymptotic range: the finest points above the round-off floor
        // whose local rates agree to within 0.25.
        let fit = fit_order_auto(&dts, &errs, 1e-13 * self.scale, 0.25);
        let range = fit.as_ref().map(|f| {
            let used: Vec<f64> = f.used.iter().map(|&i| dts[i]).collect();
            (
                used.iter().copied().fold(0.0, f64::max),
                used.iter().copied().fold(f64::INFINITY, f64::min),
            )
        });
        let reached = fit.as_ref().is_some_and(|f| f.order >= order as f64 - 0.25);
        if !quiet {
            match (&fit, range) {
                (Some(f), Some((coarse, fine))) => {
                    crate::say!(
                        "fitted order {:.3} over {} points, dt from {coarse:.4e} to {fine:.4e} (claimed {order})",
                        f.order,
                        f.used.len()
                    );
                    if !reached {
                        crate::say!(
                            "warning: the claimed order {order} is not reached; smaller steps may be needed to \
                             reach the asymptotic range (or the error is at its round-off floor)"
                        );
                    } else if f.order > order as f64 + 0.5 {
                        crate::say!(
                            "warning: the fitted order is above the claimed {order}: the steps may not be in the \
                             asymptotic range yet (or the error superconverges at t_end)"
                        );
                    }
                }
                _ => crate::say!("warning: too few points above the round-off floor to fit an order"),
            }
        }
        table.write_csv(&dir.join("convergence.csv"))?;
        let rates: Vec<f64> = local_rates(&dts, &errs).iter().map(|r| r.2).collect();
        write_json(
            &dir.join("summary.json"),
            &json!({
                "method": self.method,
                "order_claimed": order,
                "order_fitted": fit.as_ref().map(|f| f.order),
                "order_reached": reached,
                "fit_dt_range": range.map(|(coarse, fine)| [coarse, fine]),
                "local_rates": rates,
                "dt": dts,
                "errors": errs,
                "reference": self.reference,
                "t_end": self.t_end,
            }),
        )?;
        draw_convergence(&dir.join("convergence.svg"), &dts, &errs, order, fit.map(|f| f.order))?;
        if !quiet {
            crate::say!("outputs in {}", dir.display());
        }
        Ok(())
    }
}

impl Job for VerifyJob {
    fn run<const N: usize>(self, scenario: &LoadedScenario, system: System<N>) -> Result<(), CliError> {
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
        };
        let options = scenario.scenario.method.newton_options();
        let error = |x: &PhaseState<N>| (x.q - reference.q).amax().max((x.p - reference.p).amax());
        match choice {
            Choice::Variable(rule) => {
                let make = sem_factory(scenario, &system, rule)?;
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
                crate::custom::MAX_FIXED_DIMENSION
            ),
        ))
    }
}
