//! The one run pipeline of the command: every kind of scenario is parsed and
//! validated by its own module into a job, which this module runs on the
//! library's driver ([`veselov::run::drive`]) with the command's observers:
//! streamed writers, progress, diagnostic accumulators, checkpoints.
//!
//! What it adds to the driver:
//! * **Preflight** ([`Plan`]): the step count and output size are known
//!   before integrating; more than [`MAX_STEPS`] steps or [`MAX_OUTPUT_BYTES`]
//!   bytes is refused with an error naming the key, unless `--force-large`.
//! * **Interruption**: SIGINT and SIGTERM (or the caller, through
//!   [`RunJob::interrupt`]) set a flag the driver polls; the
//!   files are closed valid up to their last row and `status = "interrupted"`.
//!   `--time-limit` sets the same flag after a wall-clock budget.
//! * **Checkpoints** every `[output] checkpoint_every` steps, every
//!   `--checkpoint-seconds` of wall time, and at the end ([`checkpoint`]),
//!   from which `--resume DIR` continues bit for bit.
//! * **One summary schema** ([`summary`]): common keys plus each kind's own,
//!   written at the end and on every failure.
//! * **One run per directory** ([`lock`]): the output directory is locked
//!   for the run's lifetime; a second run into it is refused.
//! * **A record of the run's files** ([`manifest`], `outputs.json`): what
//!   `--force` removes before a new run there, and nothing else.

pub mod checkpoint;
pub mod finish;
pub mod identity;
pub mod lock;
pub mod manifest;
pub mod readback;
pub mod stream;
pub mod summary;
pub mod table;

use std::cell::Cell;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use veselov::run::{Checkpoint, Control, Observer, Outcome, Status, StepStats, Stepper, StopWhen, Words, drive};

use crate::error::CliError;
use crate::progress::{Measure, Progress};
use crate::scenario::key_error;
pub use checkpoint::Saved;
use lock::DirLock;
use manifest::Snapshot;
use manifest::prepare_dir;

/// Largest step count run without `--force-large`.
pub const MAX_STEPS: u64 = 1_000_000_000;
/// Largest planned output (bytes) written without `--force-large`.
pub const MAX_OUTPUT_BYTES: u64 = 10 << 30;

/// Options of `veselov run`.
#[derive(Debug, Clone, Default)]
pub struct RunJob {
    /// `--out`.
    pub out: Option<PathBuf>,
    /// `--quiet`.
    pub quiet: bool,
    /// `--force`.
    pub force: bool,
    /// `--force-large`: run beyond the preflight limits.
    pub force_large: bool,
    /// `--resume DIR`: continue the run in DIR from its checkpoint.
    pub resume: Option<PathBuf>,
    /// `--time-limit SECONDS`: end the run as interrupted after this wall time.
    pub time_limit: Option<f64>,
    /// `--checkpoint-seconds SECONDS`: also write a checkpoint whenever this
    /// much wall time has passed since the last one.
    pub checkpoint_seconds: Option<f64>,
    /// A cancellation flag set by the caller (a library embedding the
    /// command); when given, no signal handler is installed and setting the
    /// flag ends the run as SIGINT would.
    pub interrupt: Option<Arc<AtomicBool>>,
    /// The scenario's text (set by [`run_text`](crate::route::run_text)):
    /// checkpoints record it ([`identity`]) and a resume with a scenario
    /// that differs beyond [`identity::RESUMABLE_KEYS`] is refused.
    pub scenario: Option<String>,
}

/// What a run will do, known before it starts.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Stepper steps planned (levels, for the lattice kinds); for variable
    /// steps an estimate.
    pub steps: f64,
    /// Stepper steps that make one time step: 1, or the levels of one time
    /// step of a lattice (2 for the rod, 3 for a CFK field). Every count a
    /// user reads (preflight, progress, messages, `summary.json`) is in
    /// time steps: stepper steps divided by this.
    pub levels_per_step: u64,
    /// Time steps the initial data already span, counted in what a user
    /// reads but not taken by the stepper: 1 for a lattice started from two
    /// given levels whose stepper counts from 0 (the beam), else 0.
    pub given_steps: u64,
    /// The key that sets the step count (named in a refusal).
    pub steps_key: &'static str,
    /// Planned output size in bytes.
    pub bytes: f64,
    /// The key that sets the output size.
    pub bytes_key: &'static str,
    /// What one time step is called in messages and on the progress bar
    /// (`steps`, `time steps`, `columns`).
    pub unit: &'static str,
    /// The fixed time step of the run's discretization (`None` for
    /// variable steps): recorded in checkpoints, and a resume whose
    /// scenario gives another (a `t_end` a kind lands on by adjusting dt)
    /// is refused.
    pub step: Option<f64>,
    /// The final time of a variable-step run stopped by time (`None`
    /// otherwise: a fixed-step plan counts its steps exactly): recorded in
    /// checkpoints, and a resume to a `t_end` both before the checkpoint's
    /// time and before the run's own `t_end` is refused.
    pub t_end: Option<f64>,
}

impl Plan {
    /// Refuse what is beyond sense unless `force_large`.
    pub fn check(&self, file: &std::path::Path, force_large: bool) -> Result<(), CliError> {
        if force_large {
            return Ok(());
        }
        let steps = self.steps / self.per() as f64;
        if steps.is_nan() || steps > MAX_STEPS as f64 {
            return Err(key_error(
                file,
                self.steps_key,
                format!(
                    "the run would take {} {}, more than the limit of {}; shorten it or pass --force-large",
                    crate::output::approx(steps),
                    self.unit,
                    crate::output::number(MAX_STEPS as f64)
                ),
            ));
        }
        if self.bytes.is_nan() || self.bytes > MAX_OUTPUT_BYTES as f64 {
            return Err(key_error(
                file,
                self.bytes_key,
                format!(
                    "the run would write {:.3e} bytes, more than the limit of 10 GiB; \
                     write rows less often or pass --force-large",
                    self.bytes
                ),
            ));
        }
        Ok(())
    }

    /// Whether the run saved in `saved` has already gone as far as this plan
    /// asks: to its final time (a variable-step run stopped by time), or
    /// through every planned step (a plan that counts its steps; the
    /// lattice kinds plan `t_end/dt` and march to its ceiling).
    pub fn reached_by(&self, saved: &Saved) -> bool {
        match self.t_end {
            Some(t_end) => saved.time.is_some_and(|t| t >= t_end),
            None => self.steps.is_finite() && saved.step as f64 >= self.steps.ceil(),
        }
    }

    /// Planned stepper steps as an integer (saturating).
    pub fn whole_steps(&self) -> u64 {
        if self.steps >= u64::MAX as f64 {
            u64::MAX
        } else {
            self.steps.max(0.0) as u64
        }
    }

    /// [`Plan::levels_per_step`], at least 1.
    pub fn per(&self) -> u64 {
        self.levels_per_step.max(1)
    }
}

/// Bytes of a CSV value (shortest round-trip form, with its separator), for planning.
pub const CSV_BYTES_PER_VALUE: f64 = 22.0;

/// Output bytes of `rows` rows of `columns` values in `formats`.
pub fn table_bytes(rows: f64, columns: usize, formats: &[String]) -> f64 {
    let per_value: f64 = formats
        .iter()
        .map(|f| if f == "npy" { 8.0 } else { CSV_BYTES_PER_VALUE })
        .sum();
    rows * columns as f64 * per_value
}

/// Whether `dir/summary.json` says its run completed (`"status": "ok"`).
fn completed(dir: &std::path::Path) -> bool {
    std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|text| serde_json::from_str::<serde_json::Value>(&text).ok())
        .is_some_and(|v| v["status"] == "ok")
}

/// A run in progress: output directory, interruption flag, progress, checkpoints.
pub struct Session {
    /// The output directory.
    pub dir: PathBuf,
    /// `--quiet`.
    pub quiet: bool,
    /// When this invocation started.
    pub start: Instant,
    /// Set by SIGINT, SIGTERM or the time limit.
    pub interrupt: Arc<AtomicBool>,
    /// Steps between checkpoints (`Some(0)`: only at the end; `None`: none,
    /// for kinds that cannot be resumed).
    pub checkpoint_every: Option<u64>,
    /// Wall time between checkpoints (`--checkpoint-seconds`).
    pub checkpoint_seconds: Option<Duration>,
    /// The checkpoint resumed from, if any.
    pub resumed: Option<Saved>,
    /// The scenario's [`identity`], recorded in checkpoints.
    scenario: Option<String>,
    /// [`Plan::step`], recorded in checkpoints.
    step: Option<f64>,
    /// [`Plan::t_end`], recorded in checkpoints.
    t_end: Option<f64>,
    /// [`Plan::unit`], named in messages.
    unit: &'static str,
    /// [`Plan::levels_per_step`] (at least 1): the stepper steps of one
    /// time step.
    pub levels_per_step: u64,
    progress: Progress,
    /// Warnings met so far and the check of the summary at the end.
    pub verdict: crate::verdict::Verdict,
    /// The directory's files when the run opened it: those new or changed
    /// since are the run's, recorded in its [`manifest`].
    outputs: Snapshot,
    /// The directory's lock, held while the session lives (and released
    /// when it is dropped, after the files are recorded).
    _lock: DirLock,
}

impl Drop for Session {
    /// The run's files are recorded, however the run ended (completed,
    /// failed, interrupted, or left by an error), and then the directory's
    /// lock is released.
    fn drop(&mut self) {
        if let Err(e) = self.record_outputs() {
            eprintln!("warning: {e}");
        }
    }
}

/// Steps between two looks at the clock for time-based checkpoints.
const CLOCK_EVERY: u64 = 256;

/// Least wall time between two records of the run's files at checkpoints
/// (each reads the directory): the record is also made when the files are
/// opened and when the run ends.
const RECORD_EVERY: Duration = Duration::from_secs(1);

impl Session {
    /// Check the plan, lock the output directory ([`lock`]) and prepare it
    /// (or, resuming, reopen it: a run that has already completed is left
    /// as it is, [`CliError::AlreadyComplete`]), and install the signal
    /// handlers.
    pub fn open(
        file: &std::path::Path,
        job: &RunJob,
        dir: PathBuf,
        plan: &Plan,
        checkpoint_every: Option<u64>,
        kind: &str,
    ) -> Result<Self, CliError> {
        plan.check(file, job.force_large)?;
        let scenario = job.scenario.as_deref().and_then(identity::identity);
        let dir = job.resume.clone().unwrap_or(dir);
        if job.resume.is_none() {
            std::fs::create_dir_all(&dir).map_err(|e| CliError::Io {
                path: dir.clone(),
                message: e.to_string(),
            })?;
        }
        if !dir.is_dir() {
            // A resume of a directory that is not there: the checkpoint's
            // reader says what `--resume` needs.
            Saved::read(&dir, kind)?;
        }
        // Locked before anything in it is read or written.
        let lock = DirLock::acquire(&dir, job.quiet)?;
        let resumed = match &job.resume {
            Some(d) => Some(Saved::read(d, kind)?),
            None => {
                prepare_dir(&dir, job.force)?;
                None
            }
        };
        // Before anything in the directory is touched.
        if let Some(saved) = &resumed {
            identity::check_resume(file, &dir, saved, scenario.as_deref(), plan)?;
            if plan.reached_by(saved) && completed(&dir) {
                return Err(CliError::AlreadyComplete {
                    dir,
                    step: saved.step / plan.per(),
                });
            }
        }
        let interrupt = match &job.interrupt {
            Some(flag) => flag.clone(),
            None => {
                let flag = Arc::new(AtomicBool::new(false));
                for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
                    signal_hook::flag::register(signal, flag.clone()).map_err(|e| CliError::Setup(e.to_string()))?;
                }
                flag
            }
        };
        let checkpoint_seconds = match job.checkpoint_seconds {
            None => None,
            Some(s) if s.is_finite() && s > 0.0 => Some(Duration::from_secs_f64(s.min(1e9))),
            Some(s) => {
                return Err(CliError::Setup(format!(
                    "--checkpoint-seconds: expected a number of seconds > 0, got {s}"
                )));
            }
        };
        if let Some(limit) = job.time_limit {
            if !(limit.is_finite() && limit > 0.0) {
                return Err(CliError::Setup(format!(
                    "--time-limit: expected a number of seconds > 0, got {limit}"
                )));
            }
            let flag = interrupt.clone();
            std::thread::spawn(move || {
                std::thread::sleep(Duration::from_secs_f64(limit.min(1e9)));
                flag.store(true, Ordering::Relaxed);
            });
        }
        if !job.quiet {
            let steps = (plan.steps / plan.per() as f64).ceil() + plan.given_steps as f64;
            let unit = if steps == 1.0 {
                plan.unit.trim_end_matches('s')
            } else {
                plan.unit
            };
            eprintln!(
                "preflight: {steps:.0} {unit}, about {} of output",
                human_bytes(plan.bytes)
            );
        }
        Ok(Self {
            outputs: Snapshot::take(&dir),
            _lock: lock,
            dir,
            quiet: job.quiet,
            start: Instant::now(),
            interrupt,
            checkpoint_every,
            checkpoint_seconds: checkpoint_seconds.filter(|_| checkpoint_every.is_some()),
            resumed,
            scenario,
            step: plan.step,
            t_end: plan.t_end,
            unit: plan.unit,
            levels_per_step: plan.per(),
            progress: Progress::new(
                Measure::Count {
                    total: plan.whole_steps() / plan.per(),
                    unit: plan.unit,
                },
                job.quiet,
            ),
            verdict: crate::verdict::Verdict::default(),
        })
    }

    /// Record the files the run has written so far in the directory's
    /// [`manifest`] (`outputs.json`).
    pub fn record_outputs(&self) -> Result<(), CliError> {
        manifest::record(&self.dir, &self.outputs)
    }

    /// The stop condition `stop` plus the interruption flag.
    pub fn stop(&self, stop: StopWhen) -> StopWhen {
        stop.or_interrupted(self.interrupt.clone())
    }

    /// Wall seconds of this invocation plus those of the runs it resumes.
    pub fn wall_seconds(&self) -> f64 {
        self.start.elapsed().as_secs_f64() + self.resumed.as_ref().map_or(0.0, |s| s.wall_seconds)
    }

    /// Run `stepper` from `state` (number `first`) to `stop` with `observer`,
    /// writing a checkpoint every `checkpoint_every` steps, whenever
    /// `checkpoint_seconds` have passed since the last one (the clock is read
    /// every 256 steps), and at the end (unless the run failed: then the last
    /// checkpoint stands). `start` is how the run began: the recording of a
    /// fresh run's first state, `Ok` for a resumed one; a failed start ends
    /// the run as failed with no step taken.
    ///
    /// The outcome describes the whole run: its `steps` are those of this
    /// invocation, but its iterations, fallback steps, Jacobians and
    /// gradient evaluations count every part, resumed ones included (so do
    /// the checkpoints written from it), so that a resumed run's summary
    /// states what one uninterrupted run would.
    pub fn execute<S, O>(
        &mut self,
        start: Result<(), veselov::Error>,
        stepper: &mut S,
        state: &mut S::State,
        first: u64,
        stop: StopWhen,
        observer: &mut O,
    ) -> Result<Outcome, CliError>
    where
        S: Stepper + Checkpoint,
        S::State: Checkpoint,
        O: Observer<S::State> + Resumable,
    {
        if let Err(e) = start {
            return Ok(finish::empty_outcome(Status::Failed(e)));
        }
        let stop = self.stop(stop);
        if let Some(t_end) = stop.t_end {
            // Stopped by time: the step count is not known in advance.
            self.progress.measure_in(Measure::Time {
                t_start: stepper.time(state),
                t_end,
            });
        }
        let reached = Cell::new(stepper.time(state));
        // The counters run on from those of the parts resumed, so that the
        // outcome (and every checkpoint written from it) counts the whole run.
        let before = self.resumed.as_ref();
        let mut total = Outcome {
            last_step: first,
            steps: 0,
            iterations: before.map_or(0, |s| s.iterations),
            fallback_steps: before.map_or(0, |s| s.fallback_steps),
            jacobians: before.map_or(0, |s| s.jacobians),
            force_evaluations: before.map_or(0, |s| s.force_evaluations),
            status: Status::Completed,
        };
        let mut last_checkpoint = Instant::now();
        // The observer's files are open: a run killed from here on leaves
        // them recorded.
        self.record_outputs()?;
        let mut last_record = Instant::now();
        // What checkpoints cost, against the time of the steps since here.
        let (mut cost, stepping) = (checkpoint::Cost::default(), Instant::now());
        loop {
            let progress = &mut self.progress;
            let mut due = false;
            let clock = self.checkpoint_seconds;
            let reached = &reached;
            let per = self.levels_per_step;
            let mut show = |k: u64, _: &S::State, _: &StepStats| {
                progress.set(k / per, reached.get());
                match clock {
                    Some(every) if k.is_multiple_of(CLOCK_EVERY) && last_checkpoint.elapsed() >= every => {
                        due = true;
                        Control::Stop
                    }
                    _ => Control::Continue,
                }
            };
            let mut chunk = stop.clone();
            let every = self.checkpoint_every.unwrap_or(0);
            if let Some(k) = total.last_step.checked_div(every) {
                let next = (k + 1).saturating_mul(every);
                chunk.steps = Some(chunk.steps.map_or(next, |n| n.min(next)));
            }
            let out = drive(
                &mut TimeKeeping {
                    inner: stepper,
                    reached,
                },
                state,
                total.last_step,
                &chunk,
                &mut [&mut *observer, &mut show],
            );
            total.last_step = out.last_step;
            total.steps += out.steps;
            total.iterations += out.iterations;
            total.fallback_steps += out.fallback_steps;
            total.jacobians += out.jacobians;
            total.force_evaluations += out.force_evaluations;
            total.status = out.status;
            if due && total.status == Status::Stopped {
                // Stopped by the clock, not by an observer: a checkpoint is due.
                total.status = Status::Completed;
                last_checkpoint = Instant::now();
            }
            let done = total.status != Status::Completed
                || stop.steps.is_some_and(|n| total.last_step >= n)
                || stop.t_end.is_some_and(|t| stepper.time(state) >= t);
            if self.checkpoint_every.is_some() && total.status != Status::Stopped && total.failure().is_none() {
                let began = Instant::now();
                checkpoint::write(
                    &self.dir,
                    (stepper, state, observer),
                    &total,
                    self.wall_seconds(),
                    (self.scenario.as_deref(), self.step, self.t_end),
                )?;
                if last_record.elapsed() >= RECORD_EVERY {
                    self.record_outputs()?;
                    last_record = Instant::now();
                }
                let per = self.levels_per_step;
                let steps = total.last_step.saturating_sub(first) / per;
                if let Some(warning) = cost.note(began.elapsed(), (steps, self.unit), stepping.elapsed(), every / per) {
                    self.progress.warn(&warning);
                }
            }
            if done {
                break;
            }
        }
        self.progress.finish();
        Ok(total)
    }
}

/// A stepper that notes the time of each new state (for the progress bar of
/// runs that end at a final time).
struct TimeKeeping<'a, S> {
    inner: &'a mut S,
    reached: &'a Cell<f64>,
}

impl<S: Stepper> Stepper for TimeKeeping<'_, S> {
    type State = S::State;

    fn step(&mut self, index: u64, state: &mut S::State) -> veselov::Result<StepStats> {
        let stats = self.inner.step(index, state)?;
        self.reached.set(self.inner.time(state));
        Ok(stats)
    }

    fn time(&self, state: &S::State) -> f64 {
        self.inner.time(state)
    }

    fn non_finite(&self, state: &S::State) -> Option<String> {
        self.inner.non_finite(state)
    }

    fn finish(&mut self, state: &mut S::State) {
        self.inner.finish(state);
    }
}

/// An observer whose accumulators and open files can be saved in a
/// checkpoint and restored from one.
pub trait Resumable {
    /// Flush the files and append the words that restore this observer.
    fn save(&mut self, out: &mut Vec<f64>) -> Result<(), CliError>;
    /// The error that made the observer stop the run, if any.
    fn take_error(&mut self) -> Option<CliError> {
        None
    }
}

/// What a lattice run does after its observer has recorded a state
/// (`recorded`: whether recording it succeeded): a computation that failed
/// ends the run with that failure; a file the observer could not write
/// (`io_failed`, its error kept for the command) stops it, with what is
/// written kept; otherwise the run goes on.
pub fn after_recording(recorded: Result<(), veselov::Error>, io_failed: bool) -> Control {
    match recorded {
        Err(e) => Control::Fail(e),
        Ok(()) if io_failed => Control::Stop,
        Ok(()) => Control::Continue,
    }
}

/// A lattice run resumed from a checkpoint: what was saved, and the
/// positions its `K` output files had, read from the front of the
/// observer's words.
pub struct Resumed<const K: usize> {
    /// The checkpoint as read.
    pub saved: Saved,
    /// Where each output file stood when it was written.
    pub files: [stream::Position; K],
}

impl<const K: usize> Resumed<K> {
    /// The observer's own words, after the files' positions.
    pub fn observer_words(&self) -> Words<'_> {
        Words::new(&self.saved.observer[2 * K..])
    }

    /// A lattice run resumed: its observer (`restore_observer` reads the
    /// observer's own words) and then its state restored from the
    /// checkpoint; returns the step the run stood at.
    ///
    /// # Errors
    /// [`CliError`] naming the checkpoint in `dir` if its words do not fit.
    pub fn restore_run<T: Checkpoint + ?Sized>(
        &self,
        dir: &std::path::Path,
        restore_observer: impl FnOnce(&mut Words<'_>) -> veselov::Result<()>,
        state: &mut T,
    ) -> Result<u64, CliError> {
        restore_observer(&mut self.observer_words()).map_err(|e| words_error(dir, e))?;
        restore(dir, state, &mut Words::new(&self.saved.state))?;
        Ok(self.saved.step)
    }

    /// Where each output file is reopened: at its saved position when
    /// resuming, fresh otherwise.
    pub fn positions(resumed: &Option<Self>) -> [Option<stream::Position>; K] {
        resumed.as_ref().map_or([None; K], |r| r.files.map(Some))
    }
}

/// The session of a lattice run of `kind` from the scenario `file`, whose
/// outputs go to the command line's `--out`, else `[output] dir`
/// (`output_dir`), else beside the scenario, checkpointed every
/// `checkpoint_every` steps of its stepper, with its `K` output files'
/// positions when it resumes, judged by `verdict` at its end.
pub fn open_lattice_run<const K: usize>(
    file: &std::path::Path,
    job: &RunJob,
    (output_dir, plan): (Option<PathBuf>, &Plan),
    checkpoint_every: u64,
    kind: &str,
    verdict: crate::verdict::Verdict,
) -> Result<(Session, Option<Resumed<K>>), CliError> {
    let spec = crate::scenario::OutputSpec {
        dir: output_dir,
        ..Default::default()
    };
    let dir = crate::scenario::output_dir(file, &spec, job.out.as_deref());
    let mut session = Session::open(file, job, dir, plan, Some(checkpoint_every), kind)?;
    session.verdict = verdict;
    let resumed = match &session.resumed {
        Some(saved) => {
            let files = stream::Position::read_all(&mut Words::new(&saved.observer))
                .map_err(|e| words_error(&session.dir, e))?;
            Some(Resumed {
                saved: saved.clone(),
                files,
            })
        }
        None => None,
    };
    Ok((session, resumed))
}

/// Read the `n`-th group of checkpoint words or fail naming the checkpoint.
pub fn words_error(dir: &std::path::Path, e: veselov::Error) -> CliError {
    CliError::Io {
        path: dir.join(checkpoint::FILE),
        message: e.to_string(),
    }
}

/// Restore `target` from the words of a checkpoint.
pub fn restore<T: Checkpoint + ?Sized>(
    dir: &std::path::Path,
    target: &mut T,
    words: &mut Words<'_>,
) -> Result<(), CliError> {
    target.restore(words).map_err(|e| words_error(dir, e))
}

fn human_bytes(b: f64) -> String {
    match b {
        b if b < 1024.0 * 1024.0 => format!("{:.0} KiB", b / 1024.0),
        b if b < 1024.0 * 1024.0 * 1024.0 => format!("{:.1} MiB", b / 1024.0 / 1024.0),
        b => format!("{:.2} GiB", b / 1024.0 / 1024.0 / 1024.0),
    }
}
