//! `veselov verify`: convergence study of the scenario's method.
//!
//! Reference: the exact solution where the model has one for the scenario's
//! initial data; otherwise a run of Galerkin Gauss with s = 5 stages (order 10)
//! at one sixteenth of the smallest requested step — its error is smaller than
//! the studied method's by many orders of magnitude.

use std::path::PathBuf;

use serde_json::json;
use veselov::diagnostics::fit_order;
use veselov::mechanics::{GalerkinScheme, Method, OneStepMap, PhaseState, integrate};

use crate::error::CliError;
use crate::figures::draw_convergence;
use crate::output::{Table, prepare_dir, write_json};
use crate::run::{resolve_initial, resolve_method};
use crate::scenario::LoadedScenario;
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

/// Step counts that divide the horizon `span` into whole steps of each `dt`
/// (an error naming `--dt` otherwise).
pub fn whole_steps(file: &std::path::Path, dts: &[f64], span: f64) -> Result<Vec<usize>, CliError> {
    let mut steps = Vec::new();
    for &dt in dts {
        let n = span / dt;
        if !(dt.is_finite() && dt > 0.0) || (n - n.round()).abs() > 1e-9 * n.max(1.0) || n.round() < 1.0 {
            return Err(CliError::Key {
                file: file.to_path_buf(),
                key: "--dt".into(),
                message: format!("{dt} does not divide the horizon t_end − t0 = {span} into a whole number of steps"),
            });
        }
        steps.push(n.round() as usize);
    }
    Ok(steps)
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
    /// For each `dt` (with `n` steps) measure `error(n)` (an `Err` inside is a
    /// failed run, reported and recorded as NaN), print the table and the
    /// fitted order, and write `convergence.csv`, `summary.json` and
    /// `convergence.svg` into `dir`.
    pub fn run(
        &self,
        dir: &std::path::Path,
        dts: &[f64],
        steps: &[usize],
        quiet: bool,
        mut error: impl FnMut(usize) -> Result<Result<f64, veselov::Error>, CliError>,
    ) -> Result<(), CliError> {
        let order = self.order;
        let mut table = Table {
            header: vec!["dt".into(), "steps".into(), "error".into()],
            rows: Vec::new(),
        };
        if !quiet {
            println!("reference: {}; method {} (order {order})", self.reference, self.method);
            println!("{:>14} {:>10} {:>14} {:>8}", "dt", "steps", "error", "rate");
        }
        let mut previous: Option<(f64, f64)> = None;
        for (&dt, &n) in dts.iter().zip(steps) {
            let err = match error(n)? {
                Ok(e) => e,
                Err(e) => {
                    if !quiet {
                        println!("{dt:>14e} {n:>10} failed: {e}");
                    }
                    f64::NAN
                }
            };
            let rate = previous.map(|(h, e)| (e / err).ln() / (h / dt).ln());
            if !quiet {
                let rate = rate.map(|r| format!("{r:8.3}")).unwrap_or_default();
                println!("{dt:>14e} {n:>10} {err:>14.6e} {rate}");
            }
            previous = Some((dt, err));
            table.rows.push(vec![dt, n as f64, err]);
        }
        let dts: Vec<f64> = table.rows.iter().map(|r| r[0]).collect();
        let errs: Vec<f64> = table.rows.iter().map(|r| r[2]).collect();
        let fit = fit_order(&dts, &errs, 1e-13 * self.scale);
        if !quiet {
            match &fit {
                Some(f) => println!(
                    "fitted order {:.3} over {} points (claimed {order})",
                    f.order,
                    f.used.len()
                ),
                None => println!("too few points above the round-off floor to fit an order"),
            }
        }
        table.write_csv(&dir.join("convergence.csv"))?;
        write_json(
            &dir.join("summary.json"),
            &json!({
                "method": self.method,
                "order_claimed": order,
                "order_fitted": fit.as_ref().map(|f| f.order),
                "reference": self.reference,
                "t_end": self.t_end,
            }),
        )?;
        draw_convergence(&dir.join("convergence.svg"), &dts, &errs, order, fit.map(|f| f.order))
    }
}

impl Job for VerifyJob {
    fn run<const N: usize>(self, scenario: &LoadedScenario, system: System<N>) -> Result<(), CliError> {
        let method = resolve_method(scenario)?;
        let order = GalerkinScheme::new(method)
            .map_err(|e| CliError::Setup(e.to_string()))?
            .order();
        let x0 = resolve_initial(scenario, &system)?;
        let t0 = x0.t;
        let t_end = match scenario.scenario.time.t_end {
            Some(t) => t,
            None => t0 + scenario.steps() as f64 * scenario.scenario.method.dt,
        };
        let span = t_end - t0;
        let steps = whole_steps(&scenario.path, &self.dts, span)?;
        let (reference, source) = match system.exact.as_ref().and_then(|f| f(&x0, t_end)) {
            Some(x) => (x, "exact solution".to_string()),
            None => {
                let h_min = self.dts.iter().copied().fold(f64::INFINITY, f64::min);
                let n = (span / (h_min / 16.0)).ceil() as usize;
                let mut map = (system.make_map)(Method::GalerkinGauss(5), span / n as f64)
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
            method: method.name().to_string(),
            order,
            reference: source,
            t_end,
            scale: reference.q.amax().max(reference.p.amax()).max(1.0),
        };
        study.run(&dir, &self.dts, &steps, self.quiet, |n| {
            let mut map = (system.make_map)(method, span / n as f64).map_err(|e| CliError::Setup(e.to_string()))?;
            Ok(run_to(map.as_mut(), x0, n).map(|x| (x.q - reference.q).amax().max((x.p - reference.p).amax())))
        })
    }
}
