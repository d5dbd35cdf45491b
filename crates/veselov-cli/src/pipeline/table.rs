//! The observer that turns states into the rows of a run's main table
//! (`trajectory.csv`/`.npy`), streams them, and keeps the diagnostics the
//! summary reports: max |x − x₀| of conserved columns, maxima, minima, the
//! energy balance of forced systems. It holds no row once written.

use serde_json::{Value, json};
use veselov::Error;
use veselov::run::{Control, Observer, StepStats, Words};

use super::Resumable;
use super::stream::{Position, TableSink};
use crate::error::CliError;

/// What a tracker accumulates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Acc {
    /// `max_k |x_k − x_0|` (the first value is kept as `first`).
    Dev,
    /// `min_k x_k`.
    Min,
    /// `max_k x_k`.
    Max,
}

/// A running statistic of one series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tracker {
    /// What it accumulates.
    pub acc: Acc,
    /// The first value (NaN until one is seen).
    pub first: f64,
    /// The statistic so far.
    pub value: f64,
}

impl Tracker {
    /// A fresh tracker.
    pub fn new(acc: Acc) -> Self {
        let value = match acc {
            Acc::Dev => 0.0,
            Acc::Min => f64::INFINITY,
            Acc::Max => f64::NEG_INFINITY,
        };
        Self {
            acc,
            first: f64::NAN,
            value,
        }
    }

    /// Add a value (as `fold` with `f64::max`/`min` would: NaN values are skipped).
    pub fn push(&mut self, x: f64) {
        if self.first.is_nan() {
            self.first = x;
        }
        self.value = match self.acc {
            Acc::Dev => self.value.max((x - self.first).abs()),
            Acc::Min => self.value.min(x),
            Acc::Max => self.value.max(x),
        };
    }

    /// Append the words that restore this tracker.
    pub fn save(&self, out: &mut Vec<f64>) {
        out.extend([self.first, self.value]);
    }

    /// Restore what [`Tracker::save`] wrote.
    pub fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        self.first = w.one()?;
        self.value = w.one()?;
        Ok(())
    }
}

/// A quantity of a state.
pub type StateFn<S> = fn(&S) -> f64;

/// Builds a row from a state and the cumulative work of the forces.
pub type RowFn<'a, S> = Box<dyn Fn(&S, f64) -> Vec<f64> + 'a>;

/// The main-table observer (see the module documentation).
pub struct TableObserver<'a, S> {
    /// Column names.
    pub header: Vec<String>,
    row_of: RowFn<'a, S>,
    sink: TableSink,
    every: u64,
    /// If not empty, the steps whose rows are written (sorted), instead of `every`.
    at_steps: Vec<u64>,
    /// Trackers over written rows, by column.
    pub columns: Vec<(usize, Tracker)>,
    /// Trackers over every state.
    pub states: Vec<(StateFn<S>, Tracker)>,
    /// `max |E − E₀ − W|` over rows: (energy column, work column, value).
    pub balance: Option<(usize, usize, f64)>,
    work: f64,
    last: Option<(u64, S)>,
    written: u64,
    error: Option<CliError>,
}

impl<'a, S: Clone> TableObserver<'a, S> {
    /// Stream rows `row_of(state)` of `header` every `every` steps to `sink`.
    pub fn new(header: Vec<String>, row_of: RowFn<'a, S>, sink: TableSink, every: u64) -> Self {
        Self {
            header,
            row_of,
            sink,
            every: every.max(1),
            at_steps: Vec::new(),
            columns: Vec::new(),
            states: Vec::new(),
            balance: None,
            work: 0.0,
            last: None,
            written: u64::MAX,
            error: None,
        }
    }

    /// Write rows only at `steps` (sorted), besides the first and last states.
    pub fn at_steps(mut self, steps: Vec<u64>) -> Self {
        self.at_steps = steps;
        self
    }

    /// Track `acc` of the column called `name` (if there is one).
    pub fn track(&mut self, name: &str, acc: Acc) {
        if let Some(i) = self.header.iter().position(|h| h == name) {
            self.columns.push((i, Tracker::new(acc)));
        }
    }

    /// The tracker of column `name`.
    pub fn column(&self, name: &str) -> Option<Tracker> {
        let i = self.header.iter().position(|h| h == name)?;
        self.columns.iter().find(|(c, _)| *c == i).map(|(_, t)| *t)
    }

    /// `{name: max |x − x₀|}` for the tracked columns `names`.
    pub fn deviations(&self, names: &[String]) -> Value {
        let map: serde_json::Map<String, Value> = names
            .iter()
            .map(|n| {
                (
                    n.clone(),
                    json!(self.column(&format!("J_{n}")).map_or(0.0, |t| t.value)),
                )
            })
            .collect();
        Value::Object(map)
    }

    /// Cumulative work of the forces.
    pub fn work(&self) -> f64 {
        self.work
    }

    /// Write the row of `state` (number `step`); a non-finite value fails the run.
    pub fn write(&mut self, step: u64, state: &S) -> Result<(), Error> {
        let row = (self.row_of)(state, self.work);
        if let Some(i) = row.iter().position(|x| !x.is_finite()) {
            return Err(Error::NonFiniteState {
                step: usize::try_from(step).unwrap_or(usize::MAX),
                t: row[0],
                what: self.header[i].clone(),
            });
        }
        if let Err(e) = self.sink.row(&row) {
            self.error = Some(e);
            return Ok(());
        }
        self.written = step;
        for (i, t) in &mut self.columns {
            t.push(row[*i]);
        }
        if let Some((e, w, max)) = &mut self.balance {
            let e0 = self
                .columns
                .iter()
                .find(|(c, _)| c == e)
                .map_or(row[*e], |(_, t)| t.first);
            *max = max.max((row[*e] - e0 - row[*w]).abs());
        }
        Ok(())
    }

    /// Start the table with state `step` (written, and tracked per state).
    pub fn start(&mut self, step: u64, state: &S) -> Result<(), Error> {
        self.last = Some((step, state.clone()));
        self.write(step, state)
    }

    /// Record state `step` as the last one seen, without writing it.
    pub fn start_at(&mut self, step: u64, state: &S) {
        self.last = Some((step, state.clone()));
    }

    /// Resume after state `step`: restore the accumulators from `words`.
    pub fn resume(&mut self, step: u64, state: &S, w: &mut Words<'_>) -> veselov::Result<()> {
        self.work = w.one()?;
        self.written = w.one()?.to_bits();
        for (_, t) in &mut self.columns {
            t.restore(w)?;
        }
        for (_, t) in &mut self.states {
            t.restore(w)?;
        }
        if let Some((_, _, max)) = &mut self.balance {
            *max = w.one()?;
        }
        self.last = Some((step, state.clone()));
        Ok(())
    }

    /// Write the last state reached if its row is not written yet, and flush.
    pub fn close(&mut self) -> Result<Option<Error>, CliError> {
        let mut failure = None;
        if let Some((step, state)) = self.last.take()
            && step != self.written
            && let Err(e) = self.write(step, &state)
        {
            failure = Some(e);
        }
        self.sink.position()?;
        match self.error.take() {
            Some(e) => Err(e),
            None => Ok(failure),
        }
    }

    /// Positions of the streamed files after a flush.
    pub fn positions(&mut self) -> Result<(Position, Position), CliError> {
        self.sink.position()
    }
}

/// Checkpoint words of the positions of a sink.
pub fn save_positions(out: &mut Vec<f64>, (c, n): (Position, Position)) {
    out.extend([c.bytes, c.rows, n.bytes, n.rows].map(f64::from_bits));
}

/// Read what [`save_positions`] wrote.
pub fn restore_positions(w: &mut Words<'_>) -> veselov::Result<(Position, Position)> {
    let x = w.take(4)?;
    let p = |b: f64, r: f64| Position {
        bytes: b.to_bits(),
        rows: r.to_bits(),
    };
    Ok((p(x[0], x[1]), p(x[2], x[3])))
}

impl<S: Clone> Observer<S> for TableObserver<'_, S> {
    fn observe(&mut self, step: u64, state: &S, stats: &StepStats) -> Control {
        self.work += stats.work;
        for (f, t) in &mut self.states {
            t.push(f(state));
        }
        self.last = Some((step, state.clone()));
        let due = if self.at_steps.is_empty() {
            step.is_multiple_of(self.every)
        } else {
            self.at_steps.binary_search(&step).is_ok()
        };
        if due {
            if let Err(e) = self.write(step, state) {
                return Control::Fail(e);
            }
            if self.error.is_some() {
                return Control::Stop;
            }
        }
        Control::Continue
    }
}

impl<S: Clone> Resumable for TableObserver<'_, S> {
    /// Sink positions first (read before the sink is reopened), then the accumulators.
    fn save(&mut self, out: &mut Vec<f64>) -> Result<(), CliError> {
        save_positions(out, self.sink.position()?);
        out.push(self.work);
        out.push(f64::from_bits(self.written));
        for (_, t) in &self.columns {
            t.save(out);
        }
        for (_, t) in &self.states {
            t.save(out);
        }
        if let Some((_, _, max)) = self.balance {
            out.push(max);
        }
        Ok(())
    }
    fn take_error(&mut self) -> Option<CliError> {
        self.error.take()
    }
}
