//! `veselov verify`: convergence study of the scenario's method — the
//! options, the step counts and the study itself, shared by the kinds that
//! take one (mechanics: [`crate::kinds::mechanics::verify`], rigid bodies:
//! [`crate::kinds::rigid::verify`]), each with its own reference.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use serde_json::json;
use veselov::diagnostics::{fit_order_auto, local_rates};

use crate::error::CliError;
use crate::figures::draw_convergence;
use crate::output::{Table, write_json};
use crate::scenario::{landing_steps, note_step_length};

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
    /// A cancellation flag set by the caller (a library embedding the
    /// command): once set, the study stops before its next run, without
    /// writing its outputs.
    pub interrupt: Option<Arc<AtomicBool>>,
}

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
            return Err(bad(format!("{} is not a positive step", crate::output::number(dt))));
        }
        let n = landing_steps(span, dt);
        if n > MAX_VERIFY_STEPS {
            return Err(bad(format!(
                "{} asks for {} steps over t_end − t0 = {}; at most {} per run",
                crate::output::number(dt),
                crate::output::approx(n),
                crate::output::number(span),
                crate::output::number(MAX_VERIFY_STEPS)
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
    /// [`VerifyJob::interrupt`]: checked before each run of the study.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// Why the claimed order cannot be expected of this scenario, if the
    /// kind knows (a variable-step start on the degeneracy set): said
    /// instead of the generic advice when the order is not reached, and
    /// written as `caveat` in `summary.json`.
    pub caveat: Option<String>,
}

impl Study {
    /// For each `dt` (with `n` steps) measure `error(n, dt)` (an `Err` inside is a
    /// failed run, reported and recorded as NaN), print the table and the
    /// fitted order, and write `convergence.csv`, `summary.json` and
    /// `convergence.svg` into `dir`, listed in its `outputs.json`. An
    /// [`interrupt`](Study::interrupt) set before a run ends the study there
    /// with an error, writing nothing.
    pub fn run(
        &self,
        dir: &std::path::Path,
        dts: &[f64],
        steps: &[usize],
        quiet: bool,
        mut error: impl FnMut(usize, f64) -> Result<Result<f64, veselov::Error>, CliError>,
    ) -> Result<(), CliError> {
        let order = self.order;
        // What is new in `dir` at the end is the study's: recorded for `--force`.
        let files = crate::pipeline::manifest::Snapshot::take(dir);
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
            if self.interrupt.as_ref().is_some_and(|flag| flag.load(Ordering::Relaxed)) {
                return Err(CliError::Setup(format!(
                    "convergence study interrupted before its run with dt = {}",
                    crate::output::number(dt)
                )));
            }
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
                    if let (false, Some(caveat)) = (reached, &self.caveat) {
                        crate::say!("warning: the claimed order {order} is not reached: {caveat}");
                    } else if !reached {
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
                "caveat": self.caveat,
            }),
        )?;
        draw_convergence(&dir.join("convergence.svg"), &dts, &errs, order, fit.map(|f| f.order))?;
        crate::pipeline::manifest::record(dir, &files)?;
        if !quiet {
            crate::say!("outputs in {}", dir.display());
        }
        Ok(())
    }
}
