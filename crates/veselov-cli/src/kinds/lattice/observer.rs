//! Marching a lattice-field scenario on the run pipeline: the observer that
//! streams `energy.csv`, `snapshots.npy` and `snapshot_times.csv` as levels
//! are computed, accumulates the energy and charge errors and the energy
//! blocks, and writes `summary.json` and the plots at the end. (Parsing and
//! validation live in [`super::schema`].)

use serde_json::json;
use veselov::run::{Checkpoint, Control, Observer, Outcome, StepStats, Stepper, StopWhen, Words, save_count};
use veselov::spacetime::{BlockAccumulator, Lattice};

use super::figures::draw_field_files;
use super::schema::LoadedField;
use crate::error::CliError;
use crate::output::Table;
use crate::pipeline::finish::{Ending, close_run};
use crate::pipeline::readback::table_for_plots;
use crate::pipeline::stream::{CsvStream, NpyStream, Position};
use crate::pipeline::table::{Acc, Tracker};
use crate::pipeline::{Resumable, Session, after_recording, restore, words_error};

/// Measures the newest level pair of a state: (energy, charge).
type Measure<'a, S> = Box<dyn Fn(&S) -> (f64, Option<f64>) + 'a>;
/// The physical values of the newest level, flattened node by node.
type Values<'a, S> = Box<dyn Fn(&S) -> Vec<f64> + 'a>;

/// The field observer (see the module documentation).
pub struct FieldObserver<'a, S> {
    measure: Measure<'a, S>,
    values: Values<'a, S>,
    level_of: fn(&S) -> usize,
    dt: f64,
    /// Level of energy row 0 (`m = level − offset`): 2 on the fast path, 1 on the generic one.
    offset: usize,
    energy_every: usize,
    snapshot_every: usize,
    energy: CsvStream,
    energy_rows: u64,
    snapshots: NpyStream,
    times: CsvStream,
    last_snapshot_time: f64,
    /// The last energy row seen: (m, row), and whether it was written.
    last_row: Option<(usize, Vec<f64>, bool)>,
    e: Tracker,
    q: Tracker,
    blocks: BlockAccumulator,
    error: Option<CliError>,
}

impl<'a, S> FieldObserver<'a, S> {
    fn io(&mut self, r: Result<(), CliError>) {
        if let Err(e) = r
            && self.error.is_none()
        {
            self.error = Some(e);
        }
    }

    /// Record the energy row of `state`; fail on a non-finite energy.
    fn row(&mut self, state: &S) -> Result<(), veselov::Error> {
        let level = (self.level_of)(state);
        let m = level - self.offset;
        let t = (level - 1) as f64 * self.dt;
        let (e, q) = (self.measure)(state);
        if !e.is_finite() {
            return Err(veselov::Error::NonFiniteState {
                step: level,
                t: level as f64 * self.dt,
                what: "energy".into(),
            });
        }
        self.e.push(e);
        if let Some(q) = q {
            self.q.push(q);
        }
        self.blocks.push(m, e - self.e.first);
        let mut row = vec![t, e];
        row.extend(q);
        let write = m.is_multiple_of(self.energy_every);
        if write {
            let r = self.energy.row(&row);
            self.energy_rows += 1;
            self.io(r);
        }
        self.last_row = Some((m, row, write));
        Ok(())
    }

    fn snapshot(&mut self, state: &S, t: f64) {
        let values = (self.values)(state);
        let r = self.snapshots.row(&values).and_then(|()| self.times.row(&[t]));
        self.io(r);
        self.last_snapshot_time = t;
    }
}

impl<S> Observer<S> for FieldObserver<'_, S> {
    fn observe(&mut self, _: u64, state: &S, _: &StepStats) -> Control {
        let recorded = self.row(state);
        if recorded.is_ok() {
            let level = (self.level_of)(state);
            if self.snapshot_every > 0 && level.is_multiple_of(self.snapshot_every) {
                self.snapshot(state, level as f64 * self.dt);
            }
        }
        after_recording(recorded, self.error.is_some())
    }
}

impl<S> FieldObserver<'_, S> {
    /// Restore the accumulators saved by [`Resumable::save`] (after the
    /// stream positions, which [`Position::read_all`] has read).
    fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        self.energy_rows = w.one()?.to_bits();
        self.last_snapshot_time = w.one()?;
        self.last_row = if w.flag()? {
            let m = w.count()?;
            let len = w.count()?;
            let row = w.take(len)?.to_vec();
            Some((m, row, w.flag()?))
        } else {
            None
        };
        self.e.restore(w)?;
        self.q.restore(w)?;
        self.blocks.restore(w)
    }
}

impl<S> Resumable for FieldObserver<'_, S> {
    /// Stream positions first (read before the files are reopened), then the accumulators.
    fn save(&mut self, out: &mut Vec<f64>) -> Result<(), CliError> {
        for p in [
            self.energy.position()?,
            self.snapshots.position()?,
            self.times.position()?,
        ] {
            p.save(out);
        }
        out.push(f64::from_bits(self.energy_rows));
        out.push(self.last_snapshot_time);
        match &self.last_row {
            Some((m, row, written)) => {
                out.push(1.0);
                save_count(out, *m);
                save_count(out, row.len());
                out.extend_from_slice(row);
                out.push(f64::from(u8::from(*written)));
            }
            None => out.push(0.0),
        }
        self.e.save(out);
        self.q.save(out);
        self.blocks.save(out);
        Ok(())
    }
    fn take_error(&mut self) -> Option<CliError> {
        self.error.take()
    }
}

/// The parts of a field run the writers need.
pub struct Frame<'a, S> {
    /// Energy and charge of the newest level pair.
    pub measure: Measure<'a, S>,
    /// Physical values of the newest level.
    pub values: Values<'a, S>,
    /// Index of the newest level.
    pub level_of: fn(&S) -> usize,
    /// Name of the charge column, if any.
    pub charge: Option<&'static str>,
    /// Level of energy row 0.
    pub offset: usize,
    /// `fast` or `generic`.
    pub path: &'static str,
    /// Values per node.
    pub components: usize,
    /// The 2π re-centring applied so far (sine-Gordon, fast path).
    pub recentred_by: fn(&S) -> f64,
}

/// March `state` with `stepper` to `t_end` and write everything; resuming,
/// `state` and `stepper` (built from the scenario as for a fresh run) are
/// restored from the checkpoint and the files are continued where it stood.
pub fn march<T>(
    loaded: &LoadedField,
    session: &mut Session,
    lattice: Lattice,
    mut stepper: T,
    mut state: T::State,
    frame: Frame<'_, T::State>,
    y0: Vec<f64>,
) -> Result<(), CliError>
where
    T: Stepper + Checkpoint,
    T::State: Checkpoint,
{
    let s = &loaded.scenario;
    let dir = session.dir.clone();
    let dt = lattice.dt();
    let total = veselov::spacetime::run::planned_levels(s.time.t_end, dt);
    let nodes = lattice.nodes();
    let tail: Vec<usize> = if frame.components == 1 {
        vec![nodes]
    } else {
        vec![nodes, frame.components]
    };
    let mut header = vec!["t".to_string(), "energy".to_string()];
    header.extend(frame.charge.map(String::from));
    let snapshots_planned = match s.output.snapshot_every {
        0 => 2,
        k => (total / k).saturating_add(2),
    };
    let saved = session.resumed.clone();
    let mut words = saved.as_ref().map(|c| Words::new(&c.observer));
    let at = match &mut words {
        Some(w) => Position::read_all(w).map_err(|e| words_error(&dir, e))?.map(Some),
        None => [None; 3],
    };
    let mut obs = FieldObserver {
        measure: frame.measure,
        values: frame.values,
        level_of: frame.level_of,
        dt,
        offset: frame.offset,
        energy_every: s.output.energy_every,
        snapshot_every: s.output.snapshot_every,
        energy: CsvStream::create(&dir.join("energy.csv"), &header, at[0])?,
        energy_rows: 0,
        snapshots: NpyStream::create(&dir.join("snapshots.npy"), &tail, snapshots_planned as u64, at[1])?,
        times: CsvStream::create(&dir.join("snapshot_times.csv"), &["t".to_string()], at[2])?,
        last_snapshot_time: f64::NAN,
        last_row: None,
        e: Tracker::new(Acc::Dev),
        q: Tracker::new(Acc::Dev),
        blocks: BlockAccumulator::new(s.output.energy_block),
        error: None,
    };
    let mut start_failure = None;
    let first = match (&saved, words) {
        (Some(saved), Some(mut w)) => {
            obs.restore(&mut w).map_err(|e| words_error(&dir, e))?;
            restore(&dir, &mut state, &mut Words::new(&saved.state))?;
            restore(&dir, &mut stepper, &mut Words::new(&saved.stepper))?;
            saved.step
        }
        _ => {
            let r = obs.snapshots.row(&y0).and_then(|()| obs.times.row(&[0.0]));
            obs.io(r);
            obs.last_snapshot_time = 0.0;
            let first = (obs.level_of)(&state);
            if frame.offset == first {
                // The generic path measures its initial level pair.
                start_failure = obs.row(&state).err();
            }
            first as u64
        }
    };
    let start = start_failure.map_or(Ok(()), Err);
    let outcome = session.execute(
        start,
        &mut stepper,
        &mut state,
        first,
        StopWhen::steps(total as u64),
        &mut obs,
    )?;
    let recentred_by = (frame.recentred_by)(&state);
    let info = Closing {
        path: frame.path,
        charge: frame.charge,
        components: frame.components,
        recentred_by,
    };
    close(loaded, session, lattice, obs, &state, outcome, &info)
}

/// What [`close`] reports besides the observer.
struct Closing {
    path: &'static str,
    charge: Option<&'static str>,
    components: usize,
    recentred_by: f64,
}

/// Final rows, energy blocks, summary, plots and report.
fn close<S>(
    loaded: &LoadedField,
    session: &Session,
    lattice: Lattice,
    mut obs: FieldObserver<'_, S>,
    state: &S,
    outcome: Outcome,
    info: &Closing,
) -> Result<(), CliError> {
    let s = &loaded.scenario;
    let dir = &session.dir;
    let dt = lattice.dt();
    let level = (obs.level_of)(state);
    let t_final = level as f64 * dt;
    if let Some((_, row, false)) = obs.last_row.take() {
        let r = obs.energy.row(&row);
        obs.energy_rows += 1;
        obs.io(r);
    }
    if obs.last_snapshot_time != t_final && outcome.failure().is_none_or(|_| level != 0) {
        obs.snapshot(state, t_final);
    }
    obs.energy.position()?;
    obs.snapshots.position()?;
    obs.times.position()?;
    let snapshot_rows = obs.times.position()?.rows;
    if s.output.energy_block > 0 {
        let blocks = std::mem::replace(&mut obs.blocks, BlockAccumulator::new(0)).finish();
        let offset = obs.offset;
        Table {
            header: ["t_start", "levels", "min", "mean", "max"].map(String::from).to_vec(),
            rows: blocks
                .iter()
                .map(|b| {
                    vec![
                        (b.first_level + offset - 1) as f64 * dt,
                        b.levels as f64,
                        b.min,
                        b.mean,
                        b.max,
                    ]
                })
                .collect(),
        }
        .write_csv(&dir.join("energy_blocks.csv"))?;
    }
    let status = outcome.status.clone();
    let levels = level;
    let charges_error_max = match info.charge {
        Some(name) if !obs.q.first.is_nan() => json!({ name: obs.q.value }),
        _ => json!({}),
    };
    let energy_error_max = obs.e.value;
    let iterations = outcome.iterations;
    let own = json!({
        "scenario": loaded.path.display().to_string(),
        "model": s.model.name,
        "scheme": s.method.scheme,
        "boundary": s.lattice.boundary,
        "path": info.path,
        "nodes": lattice.nodes(),
        "dx": lattice.dx(),
        "length": lattice.length(),
        "dt": dt,
        "courant": dt / lattice.dx(),
        "levels": levels,
        "energy_initial": if obs.e.first.is_nan() { None } else { Some(obs.e.first) },
        "energy_error_max": energy_error_max,
        "energy_error_max_relative": crate::pipeline::summary::relative_energy_error(energy_error_max, obs.e.first),
        "charges_error_max": charges_error_max,
        "recentred_by": info.recentred_by,
    });
    // Time steps from t = 0 (the second initial level is the first).
    let ending = Ending {
        status,
        steps: levels as u64,
        t_final,
        iterations,
    };
    let draw = || {
        let mut header = vec!["t".to_string(), "energy".to_string()];
        header.extend(info.charge.map(String::from));
        let energy = table_for_plots(dir, "energy", &header, obs.energy_rows)?;
        draw_field_files(
            dir,
            (&s.model.name, info.components),
            (lattice.nodes(), lattice.dx(), lattice.length()),
            (&energy, snapshot_rows),
            &s.output.plot_format,
        )
    };
    close_run(session, ending, own, obs.error.take(), (s.output.plots, draw), || {
        format!(
            "{} / {}: {} to t = {}, max |E − E₀| = {}",
            s.model.name,
            s.method.scheme,
            crate::output::count(levels as u64, "time step", "time steps"),
            crate::output::number(t_final),
            crate::output::approx(energy_error_max),
        )
    })
}
