//! The observer of a CFK field run: energy, momenta, snapshots and checkpoints.

use nalgebra::SVector;
use veselov::complex::CfkTorus;
use veselov::field::cauchy::CauchyMarcher;
use veselov::field::discretize::{CfkNodes, MidpointRule, SmoothDensity};
use veselov::field::fibre::Euclidean;
use veselov::run::{Control, Observer, StepStats, Words};
use veselov::spacetime::{NonlinearWave, Potential};

use crate::error::CliError;
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{Resumable, after_recording};

/// A vertical symmetry's generator: the field's variation at a value.
pub(super) type Generator<const M: usize> = fn(&SVector<f64, M>) -> SVector<f64, M>;
/// The midpoint rule of the density on the space–time CFK nodes.
pub(super) type Rule<P> = MidpointRule<NonlinearWave<P>, CfkNodes<3>, 3>;
/// The march of an M-component field.
pub(super) type Marcher<P, const M: usize> = CauchyMarcher<Euclidean<M>, Rule<P>, M>;

/// Writes the rows of one time step Δt (every 3 levels) and the snapshots.
pub(super) struct CfkObserver<P, const M: usize> {
    pub(super) rule: Rule<P>,
    pub(super) torus: CfkTorus,
    pub(super) dt: f64,
    pub(super) symmetry: Option<(&'static str, Generator<M>)>,
    pub(super) snapshot_every: usize,
    pub(super) energy: CsvStream,
    pub(super) momentum: CsvStream,
    pub(super) snapshots: NpyStream,
    pub(super) times: CsvStream,
    pub(super) energy0: f64,
    pub(super) energy_error_max: f64,
    pub(super) charge0: f64,
    pub(super) charge_error_max: f64,
    pub(super) last_snapshot: Option<u64>,
    pub(super) error: Option<CliError>,
}

impl<P: Potential<M> + Copy, const M: usize> CfkObserver<P, M>
where
    NonlinearWave<P>: SmoothDensity<Euclidean<M>, M, 3>,
{
    /// Energy and field momenta of the slab below the cut (summed over the
    /// cells in parallel blocks, the same bits for every thread count).
    fn measure(&self, m: &Marcher<P, M>) -> Result<(f64, [f64; 2]), veselov::Error> {
        let [e, p0, p1] = m.sum_straddling_cells(|cell, y| {
            let mut p = [0.0; 2];
            let e = self.rule.cell_energy_momentum(cell, y, &mut p)?;
            Ok::<_, veselov::field::discretize::CellError>([e, p[0], p[1]])
        })?;
        Ok((e / self.dt, [p0 / self.dt, p1 / self.dt]))
    }

    /// The field at the level of time step k (weight 3k), on the fixed grid:
    /// node (v₀, v₁) of level 3k sits at x = Δx(v₀ − k), y = Δx(v₁ − k).
    fn grid(&self, m: &Marcher<P, M>, k: i64) -> Option<Vec<f64>> {
        let level = m.level_values(3 * k)?;
        let [nx, ny] = [self.torus.periods()[0], self.torus.periods()[1]];
        let mut out = vec![0.0; nx * ny * M];
        for (i, y) in level.iter().enumerate() {
            let v = self.torus.vertex(3 * k, i);
            let gx = (v[0] - k).rem_euclid(nx as i64) as usize;
            let gy = (v[1] - k).rem_euclid(ny as i64) as usize;
            out[(gx * ny + gy) * M..][..M].copy_from_slice(y.as_slice());
        }
        Some(out)
    }

    fn io(&mut self, r: Result<(), CliError>) {
        if let Err(e) = r
            && self.error.is_none()
        {
            self.error = Some(e);
        }
    }

    pub(super) fn record(&mut self, m: &Marcher<P, M>, k: u64) -> Result<(), veselov::Error> {
        let t = k as f64 * self.dt;
        let (e, p) = self.measure(m)?;
        if !e.is_finite() {
            return Err(veselov::Error::NonFiniteState {
                step: k as usize,
                t,
                what: "energy".into(),
            });
        }
        if k == 0 {
            self.energy0 = e;
        }
        // A conservative march never multiplies its energy a hundredfold:
        // such growth is an instability, not physics.
        if k > 0 && (e - self.energy0).abs() > 100.0 * self.energy0.abs().max(f64::MIN_POSITIVE) {
            return Err(veselov::Error::LevelSolveFailure {
                level: 3 * k as usize,
                t,
                residual: e,
                iterations: 0,
                reason: format!("unstable march: the energy grew from {:.6e} to {e:.6e}", self.energy0),
            });
        }
        self.energy_error_max = self.energy_error_max.max((e - self.energy0).abs());
        let mut row = vec![t, p[0], p[1]];
        if let Some((_, d)) = self.symmetry {
            let q = m.level_momentum(d);
            if k == 0 {
                self.charge0 = q;
            }
            self.charge_error_max = self.charge_error_max.max((q - self.charge0).abs());
            row.push(q);
        }
        let r = self.energy.row(&[t, e]).and_then(|()| self.momentum.row(&row));
        self.io(r);
        if self.snapshot_every > 0 && k.is_multiple_of(self.snapshot_every as u64) {
            self.snapshot(m, k);
        }
        Ok(())
    }

    pub(super) fn snapshot(&mut self, m: &Marcher<P, M>, k: u64) {
        let Some(values) = self.grid(m, k as i64) else { return };
        let t = k as f64 * self.dt;
        let r = self.snapshots.row(&values).and_then(|()| self.times.row(&[t]));
        self.io(r);
        self.last_snapshot = Some(k);
    }
}

impl<P: Potential<M> + Copy, const M: usize> Observer<Marcher<P, M>> for CfkObserver<P, M>
where
    NonlinearWave<P>: SmoothDensity<Euclidean<M>, M, 3>,
{
    fn observe(&mut self, step: u64, state: &Marcher<P, M>, _: &StepStats) -> Control {
        // One time step Δt every three levels.
        if !step.is_multiple_of(3) {
            return Control::Continue;
        }
        let recorded = self.record(state, step / 3);
        after_recording(recorded, self.error.is_some())
    }
}

impl<P, const M: usize> CfkObserver<P, M> {
    /// Restore the accumulators after [`Position::read_all`](crate::pipeline::stream::Position::read_all).
    pub(super) fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        [self.energy0, self.energy_error_max, self.charge0, self.charge_error_max] =
            [w.one()?, w.one()?, w.one()?, w.one()?];
        let has = w.flag()?;
        let k = w.one()?.to_bits();
        self.last_snapshot = has.then_some(k);
        Ok(())
    }
}

impl<P, const M: usize> Resumable for CfkObserver<P, M> {
    /// Stream positions first (read before the files are reopened), then the accumulators.
    fn save(&mut self, out: &mut Vec<f64>) -> Result<(), CliError> {
        for p in [
            self.energy.position()?,
            self.momentum.position()?,
            self.snapshots.position()?,
            self.times.position()?,
        ] {
            p.save(out);
        }
        out.extend([self.energy0, self.energy_error_max, self.charge0, self.charge_error_max]);
        out.push(f64::from(u8::from(self.last_snapshot.is_some())));
        out.push(f64::from_bits(self.last_snapshot.unwrap_or(0)));
        Ok(())
    }
    fn take_error(&mut self) -> Option<CliError> {
        self.error.take()
    }
}
