//! `veselov verify`: convergence study of the scenario's method — the
//! options, the step counts and the study itself (its table, fit, summary
//! and plot), shared by every kind: a study in the time step against a
//! reference for mechanics ([`crate::kinds::mechanics::verify`]) and rigid
//! bodies ([`crate::kinds::rigid::verify`]), a refinement of space and time
//! together for the lattice fields, the beam and the rod ([`refine`]).

pub mod observe;
pub mod refine;

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
    /// `--dt` list (mechanics and rigid bodies).
    pub dts: Vec<f64>,
    /// `--refine K`: the scenario's grid and K refinements by a factor 2
    /// (lattice fields, beam, rod).
    pub refine: Option<usize>,
    /// `--nodes N1,N2,…`: the node counts of the runs (lattice fields, beam,
    /// rod).
    pub nodes: Vec<usize>,
    /// `--observable NAME`: what a refinement study compares.
    pub observable: Option<String>,
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

impl VerifyJob {
    /// Check that the options are those of a study in the time step
    /// (`--dt`, none of the refinement options), for the scenario `file`.
    pub fn time_step_study(&self, file: &std::path::Path) -> Result<(), CliError> {
        let bad = |key: &str, message: &str| CliError::Key {
            file: file.to_path_buf(),
            key: key.into(),
            message: message.into(),
        };
        let refinement = "this kind is verified in its time step alone: give `--dt`, not";
        if self.refine.is_some() {
            return Err(bad(
                "--refine",
                &format!("{refinement} `--refine` (lattice fields, beam, rod)"),
            ));
        }
        if !self.nodes.is_empty() {
            return Err(bad(
                "--nodes",
                &format!("{refinement} `--nodes` (lattice fields, beam, rod)"),
            ));
        }
        if self.observable.is_some() {
            return Err(bad(
                "--observable",
                "this kind measures the error of the whole state (q, p) at t_end; `--observable` is for lattice \
                 fields, the beam and the rod",
            ));
        }
        if self.dts.is_empty() {
            return Err(bad("--dt", "give the steps of the study, e.g. `--dt 0.1,0.05,0.025`"));
        }
        Ok(())
    }
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
    /// What the error measures: the label of the plot's error axis.
    pub error_label: String,
    /// The step the order is fitted in.
    pub step: Step,
    /// Further entries of `summary.json` (an object; others are ignored).
    pub extra: serde_json::Value,
    /// Why the claimed order cannot be expected of this scenario, if the
    /// kind knows (a variable-step start on the degeneracy set): said
    /// instead of the generic advice when the order is not reached, and
    /// written as `caveat` in `summary.json`.
    pub caveat: Option<String>,
}

/// The label of the error axis of a study of the whole state.
pub const STATE_ERROR: &str = "max error in (q, p)";

/// The step a study's order is fitted in: its key in `summary.json` (the
/// list of steps and `fit_<key>_range`) and the plot's axis label.
#[derive(Debug, Clone, Copy)]
pub struct Step {
    /// Key in `summary.json`.
    pub key: &'static str,
    /// Label of the plot's axis.
    pub label: &'static str,
}

/// The time step of a study in time alone.
pub const TIME_STEP: Step = Step {
    key: "dt",
    label: "time step dt",
};

/// The space step of a refinement study (the time step refined with it).
pub const SPACE_STEP: Step = Step {
    key: "dx",
    label: "space step dx (dt refined with it)",
};

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
        self.conclude(dir, &files, &table, &dts, &errs, quiet)
    }

    /// Fit the order of the errors `errs` at the steps `dts` (the study's
    /// [`Step`]) over the asymptotic range, print it (with a warning when the
    /// claimed order is not reached, or when coarser points are left out of
    /// the fit as pre-asymptotic) and write `table` as `convergence.csv`, `summary.json`
    /// and `convergence.svg` into `dir`, listing in its `outputs.json` what
    /// is new there since `files`.
    pub fn conclude(
        &self,
        dir: &std::path::Path,
        files: &crate::pipeline::manifest::Snapshot,
        table: &Table,
        dts: &[f64],
        errs: &[f64],
        quiet: bool,
    ) -> Result<(), CliError> {
        let order = self.order;
        // The asymptotic range: the finest points above the round-off floor
        // whose local rates agree to within 0.25.
        let fit = fit_order_auto(dts, errs, 1e-13 * self.scale, 0.25);
        let range = fit.as_ref().map(|f| {
            let used: Vec<f64> = f.used.iter().map(|&i| dts[i]).collect();
            (
                used.iter().copied().fold(0.0, f64::max),
                used.iter().copied().fold(f64::INFINITY, f64::min),
            )
        });
        let reached = fit.as_ref().is_some_and(|f| f.order >= order as f64 - 0.25);
        // Points above the round-off floor coarser than the fitted range.
        let pre_asymptotic = match &range {
            Some((coarse, _)) => dts
                .iter()
                .zip(errs)
                .filter(|(h, e)| **h > *coarse && e.is_finite() && **e > 1e-13 * self.scale)
                .count(),
            None => 0,
        };
        if !quiet {
            match (&fit, range) {
                (Some(f), Some((coarse, fine))) => {
                    crate::say!(
                        "fitted order {:.3} over {} points, {} from {coarse:.4e} to {fine:.4e} (claimed {order})",
                        f.order,
                        f.used.len(),
                        self.step.key
                    );
                    if pre_asymptotic > 0 {
                        crate::say!(
                            "warning: pre-asymptotic range: the {pre_asymptotic} coarsest point(s), {} above \
                             {coarse:.4e}, are left out of the fit (their local rates differ from the finer ones')",
                            self.step.key
                        );
                    }
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
        let rates: Vec<f64> = local_rates(dts, errs).iter().map(|r| r.2).collect();
        let mut summary = json!({
                "method": self.method,
                "order_claimed": order,
                "order_fitted": fit.as_ref().map(|f| f.order),
                "order_reached": reached,
                "local_rates": rates,
                "pre_asymptotic_points": pre_asymptotic,
                "errors": errs,
                "reference": self.reference,
                "t_end": self.t_end,
                "caveat": self.caveat,
                "error_label": self.error_label,
        });
        if let Some(map) = summary.as_object_mut() {
            map.insert(self.step.key.into(), json!(dts));
            map.insert(
                format!("fit_{}_range", self.step.key),
                json!(range.map(|(coarse, fine)| [coarse, fine])),
            );
            map.insert("step".into(), json!(self.step.key));
            map.insert("step_label".into(), json!(self.step.label));
            if let Some(extra) = self.extra.as_object() {
                map.extend(extra.clone());
            }
        }
        write_json(&dir.join("summary.json"), &summary)?;
        draw_convergence(
            &dir.join("convergence.svg"),
            dts,
            errs,
            order,
            fit.map(|f| f.order),
            (self.step.label, &self.error_label),
        )?;
        crate::pipeline::manifest::record(dir, files)?;
        if !quiet {
            crate::say!("outputs in {}", dir.display());
        }
        Ok(())
    }
}
