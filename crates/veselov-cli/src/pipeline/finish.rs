//! The tail every kind shares: opening a session around a streamed main
//! table, and closing it with the summary, the plots and the report.

use std::path::Path;

use veselov::run::{Checkpoint, Outcome, Status, Stepper, StopWhen, Words};

use super::readback::table_for_plots;
use super::stream::Position;
use super::table::{TableObserver, restore_positions};
use super::{Plan, Resumable, RunJob, Session, restore, table_bytes, words_error};
use crate::error::CliError;
use crate::figures;
use crate::output::write_json;
use crate::scenario::{OutputSpec, TimeSpec, output_dir};
use crate::verdict::{Verdict, Warning};

/// Run a fixed-step table run from `x0` (state 0) to state `steps`, or,
/// resuming, from the checkpoint: `x` and `stepper` restored from its words,
/// `table` from `words` (the observer words after the file positions). A
/// failure of the first row ends the run before any step.
pub fn start_or_resume<S>(
    session: &mut Session,
    stepper: &mut S,
    x: &mut S::State,
    table: &mut TableObserver<'_, S::State>,
    words: &[f64],
    steps: u64,
) -> Result<Outcome, CliError>
where
    S: Stepper + Checkpoint,
    S::State: Checkpoint + Clone,
{
    let (first, start) = match session.resumed.clone() {
        Some(saved) => {
            restore(&session.dir, x, &mut Words::new(&saved.state))?;
            restore(&session.dir, stepper, &mut Words::new(&saved.stepper))?;
            table
                .resume(saved.step, x, &mut Words::new(words))
                .map_err(|e| words_error(&session.dir, e))?;
            (saved.step, Ok(()))
        }
        None => (0, table.start(0, x)),
    };
    session.execute(start, stepper, x, first, StopWhen::steps(steps), table)
}

/// A session, the positions of its table's files and the rest of the
/// observer words (when resuming).
pub type Opened = (Session, Option<(Position, Position)>, Vec<f64>);

/// The session of a run of `kind` from the scenario `file` whose main table
/// (`trajectory.*`) has `columns` columns, planned to take `steps` steps of
/// the fixed length `step` (`None`: variable steps), with the positions of
/// its files and the rest of the observer words when resuming.
pub fn open_table_session(
    job: &RunJob,
    file: &Path,
    (time, output): (&TimeSpec, &OutputSpec),
    (steps, step): (f64, Option<f64>),
    columns: usize,
    kind: &str,
) -> Result<Opened, CliError> {
    let rows = steps / output.every as f64 + 2.0;
    let plan = Plan {
        steps,
        steps_key: if time.steps.is_some() {
            "time.steps"
        } else {
            "time.t_end"
        },
        bytes: table_bytes(rows, columns, &output.formats),
        bytes_key: "output.every",
        levels_per_step: 1,
        given_steps: 0,
        unit: "steps",
        step,
        t_end: if step.is_none() && time.steps.is_none() {
            time.t_end
        } else {
            None
        },
    };
    let session = Session::open(
        file,
        job,
        output_dir(file, output, job.out.as_deref()),
        &plan,
        Some(output.checkpoint_every),
        kind,
    )?;
    let (positions, rest) = match &session.resumed {
        Some(saved) => {
            let mut w = Words::new(&saved.observer);
            let p = restore_positions(&mut w).map_err(|e| words_error(&session.dir, e))?;
            (Some(p), saved.observer[4..].to_vec())
        }
        None => (None, Vec::new()),
    };
    Ok((session, positions, rest))
}

/// Close the table, write the summary and the plots (not for an
/// interrupted run), report, and turn a failure or an interruption into the
/// command's error.
pub fn finish<S: Clone>(
    out: &OutputSpec,
    session: &Session,
    mut table: TableObserver<'_, S>,
    mut status: Status,
    summary: impl FnOnce(&TableObserver<'_, S>, &Status) -> serde_json::Value,
    report: impl FnOnce(&TableObserver<'_, S>) -> String,
) -> Result<(), CliError> {
    let io_error = table.take_error();
    if let Some(e) = table.close()?
        && !matches!(status, Status::Failed(_))
    {
        status = Status::Failed(e);
    }
    let dir = &session.dir;
    let mut value = summary(&table, &status);
    let warnings = super::summary::add_warnings(&mut value, &session.verdict);
    write_json(&dir.join("summary.json"), &value)?;
    if let Some(e) = io_error {
        return Err(e);
    }
    let plots = out.plots && !interrupted(&status);
    if plots {
        let rows = table.positions()?;
        let rows = rows.0.rows.max(rows.1.rows);
        let data = table_for_plots(dir, "trajectory", &table.header, rows)?;
        figures::draw_all(dir, &data, &out.plot_format)?;
    }
    // A failed run's error line says what happened; no success-style line before it.
    if !session.quiet && !matches!(status, Status::Failed(_)) {
        crate::say!("{}; outputs in {}", report(&table), dir.display());
    }
    session.verdict.show_new(&warnings);
    conclude(status, dir, out.plots)
}

/// Whether a run that ended with `status` was interrupted: its plots are
/// not drawn, so that the command exits at once (reading back a long run's
/// output for them can take seconds); `veselov plot DIR` draws them.
fn interrupted(status: &Status) -> bool {
    matches!(status, Status::Interrupted)
}

/// Writes `dir/summary.json`: the common keys of a run that ended with
/// `status` after `steps` stepper steps (`per` of which make a time step) at
/// `t_final`, then the kind's own keys, then the warnings of `verdict`,
/// which it returns.
#[allow(clippy::too_many_arguments)]
pub fn write_summary(
    dir: &Path,
    status: &Status,
    steps: (u64, u64),
    t_final: f64,
    wall_seconds: f64,
    iterations: u64,
    own: serde_json::Value,
    verdict: &Verdict,
) -> Result<Vec<Warning>, CliError> {
    let mut value = super::summary::common(status, steps, t_final, wall_seconds, iterations, own);
    let warnings = super::summary::add_warnings(&mut value, verdict);
    write_json(&dir.join("summary.json"), &value)?;
    Ok(warnings)
}

/// How a lattice run ended, for [`close_run`]: its status, the steps (or
/// levels) it took, its final time and its nonlinear iterations.
pub struct Ending {
    /// How the run ended.
    pub status: Status,
    /// The stepper's steps (levels) taken, resumed parts included.
    pub steps: u64,
    /// The time (or arc length) reached.
    pub t_final: f64,
    /// Nonlinear iterations of the whole run, resumed parts included (as
    /// [`Session::execute`] counts them).
    pub iterations: u64,
}

/// The tail of a run whose observer writes its own files: the summary (the
/// common keys, then `own`), then the observer's first I/O error if it had
/// one (the summary still describes what was computed), the plots
/// (`draw`, when `plots` is on and the run was not interrupted), the
/// one-line report (`report`, followed by where the outputs are) unless
/// quiet, and the command's result.
pub fn close_run(
    session: &Session,
    ending: Ending,
    own: serde_json::Value,
    observer_error: Option<CliError>,
    (plots, draw): (bool, impl FnOnce() -> Result<(), CliError>),
    report: impl FnOnce() -> String,
) -> Result<(), CliError> {
    let dir = &session.dir;
    let warnings = write_summary(
        dir,
        &ending.status,
        (ending.steps, session.levels_per_step),
        ending.t_final,
        session.wall_seconds(),
        ending.iterations,
        own,
        &session.verdict,
    )?;
    if let Some(e) = observer_error {
        return Err(e);
    }
    if plots && !interrupted(&ending.status) {
        draw()?;
    }
    if !session.quiet && !matches!(ending.status, Status::Failed(_)) {
        crate::say!("{}; outputs in {}", report(), dir.display());
    }
    session.verdict.show_new(&warnings);
    conclude(ending.status, dir, plots)
}

/// The command's result for a run that ended with `status`, its outputs in
/// `dir`: `Ok`, or the run's failure or interruption (`plots`: whether the
/// run was to draw plots, which an interrupted run leaves undrawn).
pub fn conclude(status: Status, dir: &Path, plots: bool) -> Result<(), CliError> {
    match status {
        Status::Failed(error) => Err(CliError::Run {
            error,
            dir: dir.to_path_buf(),
        }),
        Status::Interrupted => Err(CliError::Interrupted {
            dir: dir.to_path_buf(),
            plots_skipped: plots,
        }),
        _ => Ok(()),
    }
}

/// An outcome for a run that failed before its first step.
pub fn empty_outcome(status: Status) -> Outcome {
    Outcome {
        last_step: 0,
        steps: 0,
        iterations: 0,
        fallback_steps: 0,
        jacobians: 0,
        force_evaluations: 0,
        status,
    }
}

/// What a whole run spent, resumed parts included.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Totals {
    /// Nonlinear iterations.
    pub iterations: u64,
    /// Steps that fell back (or, for variable steps, are not energy-exact).
    pub fallback_steps: u64,
    /// Exact Jacobians evaluated, where counted.
    pub jacobians: u64,
    /// Gradient evaluations `∇V`, where counted.
    pub force_evaluations: u64,
}

/// Iterations, fallback steps, Jacobians and gradient evaluations over the
/// whole run, resumed parts included: those of the outcome of
/// [`Session::execute`], which counts from the checkpoint's.
pub fn totals(outcome: &Outcome) -> Totals {
    Totals {
        iterations: outcome.iterations,
        fallback_steps: outcome.fallback_steps,
        jacobians: outcome.jacobians,
        force_evaluations: outcome.force_evaluations,
    }
}

/// `t₀ + k·h`, as the stepper sets it.
pub fn t_of(k: u64, t0: f64, h: f64) -> f64 {
    if k == 0 { t0 } else { t0 + k as f64 * h }
}
