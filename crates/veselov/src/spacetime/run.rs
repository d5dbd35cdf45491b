//! A library-level driver for scalar lattice runs (what a command-line front
//! end calls): model, scheme, lattice, initial data and duration in; energies
//! (per level and per block), charges, snapshots, the final waveform and a
//! status out. A failing solve is kept as a value together with everything
//! computed before it.

use crate::error::invalid;
use crate::error::{Error, Result};
use crate::run::{Checkpoint, Control, Status, StepStats, StopWhen, Words, drive, save_count};
use crate::spacetime::fast::{FastMarcher, SolverOptions};
use crate::spacetime::initial::InitialData;
use crate::spacetime::lattice::Lattice;
use crate::spacetime::noether::shift_charge;
use crate::spacetime::potential::{Phi4, ScalarPotential, SineGordon, Wave};
use crate::spacetime::scheme::Scheme;
use crate::spacetime::stepping::{FastLevels, FastStepper};
use crate::spacetime::waveform::{CollisionCounter, fourth_difference_max};

/// The scalar models of the fast paths.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Model {
    /// `N = cos φ`.
    SineGordon,
    /// `N = 0`.
    Wave,
    /// `N = −½m²φ² − ¼λφ⁴`.
    Phi4 {
        /// `m²`.
        m2: f64,
        /// `λ`.
        lambda: f64,
    },
}

/// Configuration of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldRunConfig {
    /// Model.
    pub model: Model,
    /// Scheme.
    pub scheme: Scheme,
    /// Lattice (periodic or winding).
    pub lattice: Lattice,
    /// Initial data.
    pub initial: InitialData,
    /// Final time (the run stops at the first level with `t ≥ t_end`).
    pub t_end: f64,
    /// Store a snapshot every this many levels (0: none; level 0 and 1 are
    /// never stored, the final level always is in `final_level`).
    pub snapshot_every: usize,
    /// Energy block length in levels for min/mean/max statistics (0: none).
    pub energy_block: usize,
    /// Keep the energy of every level.
    pub keep_energies: bool,
    /// Re-centre mod 2π every this many levels (sine-Gordon only; 0: never).
    pub recentre_every: usize,
    /// Level-solve options.
    pub solver: SolverOptions,
}

impl FieldRunConfig {
    /// Seed 002 §5.2 defaults: sine-Gordon kink–antikink, N = 255 on a circle
    /// of length 40, h = k/8, paper start, blocks of 5000 levels, re-centring
    /// every 1000 levels.
    ///
    /// # Errors
    /// Invalid `t_end`.
    pub fn sine_gordon_section_5_2(scheme: Scheme, t_end: f64) -> Result<Self> {
        Ok(Self {
            model: Model::SineGordon,
            scheme,
            lattice: Lattice::periodic(255, 40.0, 8.0)?,
            initial: InitialData::KinkAntikink {
                epsilon: 1e-6,
                paper_start: true,
            },
            t_end,
            snapshot_every: 0,
            energy_block: 5000,
            keep_energies: false,
            recentre_every: 1000,
            solver: SolverOptions::default(),
        })
    }
}

/// What the observer sees after every level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelInfo<'a> {
    /// Index of the new level.
    pub level: usize,
    /// Its time.
    pub time: f64,
    /// The energy computed with it (see [`FastMarcher::energy`]).
    pub energy: f64,
    /// Iterations of its solve.
    pub iterations: usize,
    /// Planned number of levels.
    pub total_levels: usize,
    /// The new level's values as stored, where the run has scalar values:
    /// the physical field is `values[i] + recentred_by`.
    pub values: Option<&'a [f64]>,
    /// The 2π re-centring applied so far (sine-Gordon; 0 otherwise).
    pub recentred_by: f64,
}

/// Min/mean/max of the energy error `E − E_first` over a block of levels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlockStats {
    /// First level of the block (level index of the energy's first level).
    pub first_level: usize,
    /// Number of levels in the block.
    pub levels: usize,
    /// Minimum error.
    pub min: f64,
    /// Mean error.
    pub mean: f64,
    /// Maximum error.
    pub max: f64,
}

/// Min/mean/max of a series over consecutive blocks of fixed length, fed
/// one value at a time (nothing is stored but the finished blocks).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockAccumulator {
    block: usize,
    first: usize,
    count: usize,
    min: f64,
    max: f64,
    sum: f64,
    blocks: Vec<BlockStats>,
}

impl BlockAccumulator {
    /// Blocks of `block` values (0: no blocks; every value is ignored).
    pub fn new(block: usize) -> Self {
        Self {
            block,
            first: 0,
            count: 0,
            min: f64::INFINITY,
            max: f64::NEG_INFINITY,
            sum: 0.0,
            blocks: Vec::new(),
        }
    }

    /// Add the value `d` of the series at index `index` (the first index of
    /// a block is recorded as its `first_level`).
    pub fn push(&mut self, index: usize, d: f64) {
        if self.block == 0 {
            return;
        }
        if self.count == 0 {
            self.first = index;
        }
        self.min = self.min.min(d);
        self.max = self.max.max(d);
        self.sum += d;
        self.count += 1;
        if self.count == self.block {
            self.close();
        }
    }

    fn close(&mut self) {
        self.blocks.push(BlockStats {
            first_level: self.first,
            levels: self.count,
            min: self.min,
            mean: self.sum / self.count as f64,
            max: self.max,
        });
        (self.min, self.max, self.sum, self.count) = (f64::INFINITY, f64::NEG_INFINITY, 0.0, 0);
    }

    /// The blocks, the last one possibly shorter.
    pub fn finish(mut self) -> Vec<BlockStats> {
        if self.count > 0 {
            self.close();
        }
        self.blocks
    }
}

/// The open block and the blocks closed so far.
impl Checkpoint for BlockAccumulator {
    fn save(&self, out: &mut Vec<f64>) {
        for count in [self.block, self.first, self.count, self.blocks.len()] {
            save_count(out, count);
        }
        out.extend([self.min, self.max, self.sum]);
        for b in &self.blocks {
            save_count(out, b.first_level);
            save_count(out, b.levels);
            out.extend([b.min, b.mean, b.max]);
        }
    }
    fn restore(&mut self, w: &mut Words<'_>) -> Result<()> {
        let block = w.count()?;
        if block != self.block {
            return Err(invalid("checkpoint", block, "written with another energy block length"));
        }
        self.first = w.count()?;
        self.count = w.count()?;
        let closed = w.count()?;
        [self.min, self.max, self.sum] = [w.one()?, w.one()?, w.one()?];
        self.blocks.clear();
        for _ in 0..closed {
            let (first_level, levels) = (w.count()?, w.count()?);
            let [min, mean, max] = [w.one()?, w.one()?, w.one()?];
            self.blocks.push(BlockStats {
                first_level,
                levels,
                min,
                mean,
                max,
            });
        }
        Ok(())
    }
}

/// A snapshot of one level.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Level index.
    pub level: usize,
    /// Time.
    pub time: f64,
    /// Field values at the nodes, as stored (the physical values minus
    /// `recentred_by`).
    pub values: Vec<f64>,
    /// The total 2π re-centring shift applied before this snapshot was taken:
    /// `values[i] + recentred_by` is the unwrapped field.
    pub recentred_by: f64,
}

/// Everything a run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldRun {
    /// The first energy (of levels 0, 1; Guo: `E^{½}`).
    pub initial_energy: f64,
    /// Energy per level (if kept): entry `m` is the energy of levels `m, m+1`.
    pub energies: Vec<f64>,
    /// Block statistics of the energy error.
    pub energy_blocks: Vec<BlockStats>,
    /// Block statistics (same blocks) of the high-frequency indicator
    /// [`fourth_difference_max`] of every new level.
    pub high_frequency_blocks: Vec<BlockStats>,
    /// The largest high-frequency indicator of the run.
    pub high_frequency_max: f64,
    /// Sine-Gordon: the times of closest approach of the kink–antikink
    /// collisions ([`CollisionCounter`]); empty for the other models.
    pub collision_times: Vec<f64>,
    /// Wave model: the shift charge `Σ_i (y_{i,j+1} − y_ij)` per level (if
    /// energies are kept); empty otherwise.
    pub charges: Vec<f64>,
    /// Snapshots.
    pub snapshots: Vec<Snapshot>,
    /// The last computed level.
    pub final_level: Vec<f64>,
    /// Its index and time.
    pub final_index: usize,
    /// Its time.
    pub final_time: f64,
    /// Total level-solve iterations.
    pub iterations: u64,
    /// Total 2π re-centring shift applied (the stored values are the
    /// physical ones minus this).
    pub recentred_by: f64,
    /// `Ok` if the run reached `t_end` (or the observer stopped it), the
    /// failure otherwise.
    pub status: Result<(), Error>,
    /// Did the observer stop the run?
    pub stopped: bool,
}

/// Run a scalar lattice simulation on [`crate::run::drive`] with a
/// [`FastStepper`]. `observer` is called after every level;
/// returning `false` stops the run (status stays `Ok`).
///
/// # Errors
/// Invalid configuration (typed, naming the parameter). Solve failures are
/// reported in [`FieldRun::status`].
pub fn run_lattice(config: &FieldRunConfig, observer: impl FnMut(&LevelInfo) -> bool) -> Result<FieldRun> {
    if !(config.t_end.is_finite() && config.t_end > 0.0) {
        return Err(invalid("t_end", config.t_end, "must be positive and finite"));
    }
    match config.model {
        Model::SineGordon => run_with(SineGordon, config, observer),
        Model::Wave => run_with(Wave, config, observer),
        Model::Phi4 { m2, lambda } => {
            if !(m2.is_finite() && lambda.is_finite()) {
                return Err(invalid(
                    "model",
                    format!("{:?}", config.model),
                    "m2 and lambda must be finite",
                ));
            }
            run_with(Phi4 { m2, lambda }, config, observer)
        }
    }
}

fn run_with<P: ScalarPotential>(
    potential: P,
    config: &FieldRunConfig,
    mut observer: impl FnMut(&LevelInfo) -> bool,
) -> Result<FieldRun> {
    let lat = config.lattice;
    let (y0, y1) = config.initial.levels(&lat)?;
    let m = FastMarcher::new(potential, config.scheme, lat, &y0, &y1, config.solver)?;
    let first = m.level() as u64;
    let total_levels = planned_levels(config.t_end, lat.dt());
    let recentre = config.recentre_every > 0 && config.model == Model::SineGordon;
    let mut run = FieldRun {
        initial_energy: f64::NAN,
        energies: Vec::new(),
        energy_blocks: Vec::new(),
        high_frequency_blocks: Vec::new(),
        high_frequency_max: 0.0,
        collision_times: Vec::new(),
        charges: Vec::new(),
        snapshots: Vec::new(),
        final_level: Vec::new(),
        final_index: m.level(),
        final_time: m.time(),
        iterations: 0,
        recentred_by: 0.0,
        status: Ok(()),
        stopped: false,
    };
    let keep_charge = config.keep_energies && config.model == Model::Wave;
    if keep_charge {
        run.charges.push(shift_charge(&y0, &y1));
    }
    let mut blocks = BlockAccumulator::new(config.energy_block);
    let mut high_frequency = BlockAccumulator::new(config.energy_block);
    let mut collisions = (config.model == Model::SineGordon).then(CollisionCounter::new);
    let mut record = |_: u64, s: &FastLevels<P>, _: &StepStats| {
        let m = &s.marcher;
        let e = m.energy();
        if run.initial_energy.is_nan() {
            run.initial_energy = e;
        }
        if config.keep_energies {
            run.energies.push(e);
        }
        if keep_charge {
            run.charges.push(shift_charge(m.previous(), m.current()));
        }
        // The energy's first level is the one before the level just computed.
        blocks.push(m.level() - 1, e - run.initial_energy);
        let hf = fourth_difference_max(&lat, m.current());
        high_frequency.push(m.level() - 1, hf);
        run.high_frequency_max = run.high_frequency_max.max(hf);
        if let Some(c) = collisions.as_mut() {
            c.observe(m.time(), m.current());
        }
        if config.snapshot_every > 0 && m.level().is_multiple_of(config.snapshot_every) {
            run.snapshots.push(Snapshot {
                level: m.level(),
                time: m.time(),
                recentred_by: s.recentred_by,
                values: m.current().to_vec(),
            });
        }
        let info = LevelInfo {
            level: m.level(),
            time: m.time(),
            energy: e,
            iterations: m.last_iterations(),
            total_levels,
            values: Some(m.current()),
            recentred_by: s.recentred_by,
        };
        if observer(&info) {
            Control::Continue
        } else {
            Control::Stop
        }
    };
    let mut levels = FastLevels::new(m);
    let mut stepper = FastStepper::new(if recentre { config.recentre_every } else { 0 });
    let outcome = drive(
        &mut stepper,
        &mut levels,
        first,
        &StopWhen::steps(total_levels as u64),
        &mut [&mut record],
    );
    match outcome.status {
        Status::Failed(e) => run.status = Err(e),
        Status::Stopped => run.stopped = true,
        Status::Completed | Status::Interrupted => {}
    }
    let m = &levels.marcher;
    run.recentred_by = levels.recentred_by;
    run.energy_blocks = blocks.finish();
    run.high_frequency_blocks = high_frequency.finish();
    run.collision_times = collisions.map(|c| c.times().to_vec()).unwrap_or_default();
    run.final_level = m.current().to_vec();
    run.final_index = m.level();
    run.final_time = m.time();
    run.iterations = m.total_iterations();
    Ok(run)
}

/// Levels of a run to `t_end` in steps of `dt`: `⌈t_end/dt⌉`, saturating
/// (a run that long is stopped by other means long before).
pub fn planned_levels(t_end: f64, dt: f64) -> usize {
    let n = (t_end / dt).ceil();
    if n >= usize::MAX as f64 {
        usize::MAX
    } else {
        n.max(0.0) as usize
    }
}

#[cfg(test)]
mod block_tests {
    use super::BlockAccumulator;

    #[test]
    fn blocks_of_fixed_length_and_a_short_last_one() {
        let mut acc = BlockAccumulator::new(3);
        for (i, d) in [1.0, -2.0, 4.0, 0.5, 0.25].into_iter().enumerate() {
            acc.push(10 + i, d);
        }
        let blocks = acc.finish();
        assert_eq!(blocks.len(), 2);
        let (a, b) = (blocks[0], blocks[1]);
        assert_eq!((a.first_level, a.levels, a.min, a.mean, a.max), (10, 3, -2.0, 1.0, 4.0));
        assert_eq!(
            (b.first_level, b.levels, b.min, b.mean, b.max),
            (13, 2, 0.25, 0.375, 0.5)
        );
        let mut none = BlockAccumulator::new(0);
        none.push(0, 1.0);
        assert!(none.finish().is_empty());
    }
}
