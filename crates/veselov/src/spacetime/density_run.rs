//! A driver for runs of any cell Lagrangian on the generic marcher (vector
//! fields, Dirichlet and free boundaries): energies and an optional Noether
//! charge per level, snapshots, the final level and a status that keeps a
//! failure as a value.

use nalgebra::SVector;

use crate::error::invalid;
use crate::error::{Error, Result};
use crate::run::{Control, StepStats, StopWhen, drive};
use crate::spacetime::energy::{CellEnergy, level_energy};
use crate::spacetime::generic::GenericMarcher;
use crate::spacetime::lattice::Lattice;
use crate::spacetime::noether::split_charge;
use crate::spacetime::run::{LevelInfo, planned_levels};
use crate::spacetime::stepping::DensityStepper;

/// The generator ξ(y) of a vertical symmetry of the field values.
pub type Generator<'a, const DIM: usize> = &'a dyn Fn(&SVector<f64, DIM>) -> SVector<f64, DIM>;

/// Settings of [`run_density`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DensityRunConfig {
    /// Final time (the run stops at the first level with t ≥ t_end).
    pub t_end: f64,
    /// Store a snapshot every this many levels (0: none).
    pub snapshot_every: usize,
    /// Relative tolerance of the Newton correction of each level.
    pub rel_tol: f64,
}

/// Everything a [`run_density`] produced.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityRun<const DIM: usize> {
    /// Entry m: the energy of the cells between levels m and m+1
    /// ([`level_energy`]).
    pub energies: Vec<f64>,
    /// Entry m: the split Noether charge of levels m, m+1 (empty without a
    /// generator).
    pub charges: Vec<f64>,
    /// Snapshots (level, time, values).
    pub snapshots: Vec<(usize, f64, Vec<SVector<f64, DIM>>)>,
    /// The last computed level, its index and time.
    pub final_level: Vec<SVector<f64, DIM>>,
    /// Index of the last computed level.
    pub final_index: usize,
    /// Its time.
    pub final_time: f64,
    /// Total Newton iterations.
    pub iterations: u64,
    /// `Ok` if the run reached `t_end` (or the observer stopped it).
    pub status: Result<(), Error>,
}

/// March `lag` from levels `y0`, `y1` to `config.t_end`; `charge` is the
/// generator ξ(y) of a vertical symmetry whose split charge is recorded.
/// `observer` sees every level; returning `false` stops the run. Runs on
/// [`crate::run::drive`] with a [`DensityStepper`].
///
/// # Errors
/// Invalid configuration or initial data (typed, naming the parameter).
/// Solve failures are reported in [`DensityRun::status`].
pub fn run_density<L: CellEnergy<DIM>, const DIM: usize>(
    lag: L,
    lattice: Lattice,
    y0: Vec<SVector<f64, DIM>>,
    y1: Vec<SVector<f64, DIM>>,
    config: &DensityRunConfig,
    charge: Option<Generator<'_, DIM>>,
    mut observer: impl FnMut(&LevelInfo) -> bool,
) -> Result<DensityRun<DIM>> {
    if !(config.t_end.is_finite() && config.t_end > 0.0) {
        return Err(invalid("t_end", config.t_end, "must be positive and finite"));
    }
    if !(config.rel_tol.is_finite() && config.rel_tol > 0.0) {
        return Err(invalid("rel_tol", config.rel_tol, "must be positive and finite"));
    }
    let mut m = GenericMarcher::new(lag, lattice, y0, y1)?;
    m.rel_tol = config.rel_tol;
    let total_levels = planned_levels(config.t_end, lattice.dt());
    let measure = |m: &GenericMarcher<L, DIM>, run: &mut DensityRun<DIM>| {
        run.energies
            .push(level_energy(m.lagrangian(), &lattice, m.previous(), m.current()));
        if let Some(xi) = charge {
            run.charges
                .push(split_charge(m.lagrangian(), &lattice, m.previous(), m.current(), xi));
        }
    };
    let mut run = DensityRun {
        energies: Vec::new(),
        charges: Vec::new(),
        snapshots: Vec::new(),
        final_level: Vec::new(),
        final_index: m.level(),
        final_time: lattice.t(m.level()),
        iterations: 0,
        status: Ok(()),
    };
    measure(&m, &mut run);
    let mut record = |_: u64, m: &GenericMarcher<L, DIM>, _: &StepStats| {
        measure(m, &mut run);
        let level = m.level();
        if config.snapshot_every > 0 && level.is_multiple_of(config.snapshot_every) {
            run.snapshots.push((level, lattice.t(level), m.current().to_vec()));
        }
        let info = LevelInfo {
            level,
            time: lattice.t(level),
            energy: run.energies.last().copied().unwrap_or(f64::NAN),
            iterations: m.last_iterations(),
            total_levels,
            values: None,
            recentred_by: 0.0,
        };
        if observer(&info) {
            Control::Continue
        } else {
            Control::Stop
        }
    };
    let first = m.level() as u64;
    let outcome = drive(
        &mut DensityStepper::new(),
        &mut m,
        first,
        &StopWhen::steps(total_levels as u64),
        &mut [&mut record],
    );
    run.iterations = outcome.iterations;
    if let Some(e) = outcome.failure() {
        run.status = Err(e.clone());
    }
    run.final_level = m.current().to_vec();
    run.final_index = m.level();
    run.final_time = lattice.t(m.level());
    Ok(run)
}
