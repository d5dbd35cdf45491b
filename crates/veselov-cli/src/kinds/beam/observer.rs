//! The observer of a beam run: the rows of `frames.npy`, `centerline.npy`
//! (time evolution), `momentum.csv` and `energy.csv` every `every` levels,
//! the drift of the evolution momentum map, the current 𝒥 of the whole
//! computed domain, and for a beam held at one end the reaction of its
//! support and the motion of its tip.

use nalgebra::{SMatrix, SVector, Vector3};
use veselov::evolution::marcher::Evolution000;
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::fibre::RigidMotions;
use veselov::lie::{Retraction, SE3};
use veselov::models::beam::{BeamLagrangian, left_generators};
use veselov::run::{Control, Observer, StepStats, Words};

use super::setup::BeamSetup;
use crate::centerline::{Reaction, ShapeChange};
use crate::error::CliError;
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{Resumable, after_recording};

/// The beam's march: seed 000's evolution of frames on SE(3).
pub(super) type Beam<R> = Evolution000<RigidMotions, BeamLagrangian<R>, 6>;

/// 𝒥 over all the triangles computed so far: the sum, over the nodes on the
/// boundary of that domain, of the currents `J^k` its triangles put on them.
/// By the Noether identity (J¹ + J² + J³ = 0 on every triangle of a
/// symmetric Lagrangian) it equals minus the sum of the discrete
/// Euler–Lagrange residuals at the interior nodes, so it vanishes on a
/// solution whatever the ends — the check of the whole march, not only of
/// its boundary rows. Per band of triangles (between two levels), with
/// cells 0 … C − 1 and currents `[J^base, J^fwd, J^cross]`:
/// `𝒥(L) = −𝖩⁻(band 0) − J^base₀ − J^cross_{C−1} (band 0)
///        + Σ_bands (J^base₀ + J^fwd₀ + J^cross_{C−1}) + 𝖩⁺(band L) − J^fwd₀ (band L)`.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct DomainCurrent {
    bottom: [f64; 6],
    sides: [f64; 6],
    scale: f64,
    pub(super) worst: f64,
    started: bool,
}

impl DomainCurrent {
    /// Add the band between the previous and the current level of `e`.
    pub(super) fn add_band<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(&mut self, e: &Beam<R>) {
        let generators = |g: &SE3<f64>| -> SMatrix<f64, 6, 6> { left_generators(g) };
        let first = e.cell_currents::<6>(0, generators);
        // With an end cell, its placeholder column closes the band (zero currents).
        let last = e.cell_currents::<6>(e.cells() - 1, generators);
        if !self.started {
            let m = e.evolution_momentum::<6>(generators);
            let bottom = -m.minus - first[0] - last[2];
            self.bottom.copy_from_slice(bottom.as_slice());
            self.scale += m.scale;
            self.started = true;
        }
        let side = first[0] + first[1] + last[2];
        for (s, v) in self.sides.iter_mut().zip(side.iter()) {
            *s += v;
        }
        self.scale += first[0].amax() + first[1].amax() + last[2].amax();
    }

    /// 𝒥 up to the current level of `e`, whose 𝖩⁺ is `plus` (terms of size
    /// `plus_scale`), and the largest |𝒥| relative to its terms so far.
    fn value<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
        &mut self,
        e: &Beam<R>,
        plus: &SVector<f64, 6>,
        plus_scale: f64,
    ) -> SVector<f64, 6> {
        let first = e.cell_currents::<6>(0, |g: &SE3<f64>| -> SMatrix<f64, 6, 6> { left_generators(g) });
        let total = SVector::<f64, 6>::from(self.bottom) + SVector::<f64, 6>::from(self.sides) + plus - first[1];
        let size = (self.scale + plus_scale).max(f64::MIN_POSITIVE);
        self.worst = self.worst.max(total.amax() / size);
        total
    }

    fn save(&self, out: &mut Vec<f64>) {
        out.extend(self.bottom);
        out.extend(self.sides);
        out.extend([self.scale, self.worst, f64::from(u8::from(self.started))]);
    }

    fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        w.fill(&mut self.bottom)?;
        w.fill(&mut self.sides)?;
        self.scale = w.one()?;
        self.worst = w.one()?;
        self.started = w.flag()?;
        Ok(())
    }
}

/// Writes the rows and keeps the momentum drift.
pub(super) struct BeamObserver<'a> {
    pub(super) setup: &'a BeamSetup,
    pub(super) every: u64,
    pub(super) frames: NpyStream,
    /// `centerline.npy`, in time evolution.
    pub(super) centerline: Option<NpyStream>,
    pub(super) momentum: CsvStream,
    pub(super) energy: CsvStream,
    /// 𝖩⁺ at the first row and the largest change since, relative to the
    /// size of its terms.
    pub(super) first: [f64; 6],
    pub(super) drift: f64,
    pub(super) started: bool,
    /// 𝒥 on the whole computed domain (note 000 (58)): the bottom row's
    /// part, the running sum of the side columns' currents, the size of the
    /// terms summed, and the largest |𝒥| relative to it so far.
    pub(super) domain: DomainCurrent,
    pub(super) energy_range: [f64; 2],
    pub(super) row: Vec<f64>,
    /// The positions of a row (nodes × 3).
    pub(super) line: Vec<f64>,
    /// The first and last rows of the centreline and the tip's frame.
    pub(super) shape: ShapeChange,
    /// The support's reaction, in time evolution with one end clamped.
    pub(super) support: SupportImpulse,
    pub(super) error: Option<CliError>,
}

/// The impulse of the support at the one clamped end of a beam, from the
/// discrete Euler–Lagrange equation at the clamped node, which the march
/// does not impose: with the node's currents J = X(y)ᵀ ∂ℒ/∂y and discrete
/// forces F mapped alike (X = [`left_generators`], spatial, angular part
/// about the origin first), the support's impulse on node (ℓ, c) is
/// I_R = −Σ_cells (J + X(y)ᵀ F), the sum over the cells the node is a
/// vertex of: at the start (c = 0) the base vertex of cell 0 between
/// levels ℓ and ℓ + 1 and the forward vertex of cell 0 between ℓ − 1 and
/// ℓ; at the end (c = C) the cross vertex of cell C − 1 between ℓ and
/// ℓ + 1. Summed over the nodes of a level these equations are the
/// momentum balance of the beam; at a free node the sum is zero.
#[derive(Debug, Clone, Copy)]
pub(super) struct SupportImpulse {
    /// The clamped end (0: start, 1: end), when only one is.
    pub(super) end: Option<usize>,
    /// The start node's terms from the cell below it (J^fwd + X(y)ᵀF^fwd of
    /// cell 0 of the previous band; NaN before the first band).
    below: [f64; 6],
    /// The level ℓ of the last node whose impulse is known, and I_R there
    /// (angular about the origin, then linear; NaN: none yet).
    pub(super) last: [f64; 7],
}

impl SupportImpulse {
    pub(super) fn new(end: Option<usize>) -> Self {
        Self {
            end,
            below: [f64::NAN; 6],
            last: [f64::NAN; 7],
        }
    }

    /// Add the band between the previous and the current level of `e`: the
    /// clamped node on the previous level has all its cells now.
    pub(super) fn add_band<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(&mut self, e: &Beam<R>) {
        let Some(end) = self.end else { return };
        let generators = |g: &SE3<f64>| -> SMatrix<f64, 6, 6> { left_generators(g) };
        let c = if end == 0 { 0 } else { e.cross() - 1 };
        let currents = e.cell_currents::<6>(c, generators);
        // The discrete forces at the cell's vertices, mapped as the currents.
        let lag = e.lagrangian();
        let mut forces = [SVector::<f64, 6>::zeros(); 3];
        e.for_each_cell(|k, cell, y| {
            if k == c && DiscreteLagrangian::<RigidMotions, 6>::has_forces(lag) {
                for (l, f) in forces.iter_mut().enumerate() {
                    let force = DiscreteLagrangian::<RigidMotions, 6>::cell_force::<f64>(lag, cell, y, l);
                    *f = left_generators(&y[l]).transpose() * force;
                }
            }
        });
        let term = |l: usize| currents[l] + forces[l];
        let level = e.level() as f64 - 1.0;
        let impulse = if end == 0 {
            let below = SVector::<f64, 6>::from(self.below);
            self.below.copy_from_slice(term(1).as_slice());
            -(term(0) + below)
        } else {
            -term(2)
        };
        self.last[0] = level;
        self.last[1..].copy_from_slice(impulse.as_slice());
    }

    /// The reaction at the clamped node of level `level`, at `at`, over a
    /// step `dt` ([`Reaction::from_impulse`]), if its impulse is known.
    pub(super) fn reaction(&self, level: usize, dt: f64, at: Option<Vector3<f64>>) -> Option<Reaction> {
        let end = self.end?;
        let i = &self.last;
        if i[0] != level as f64 || i.iter().any(|x| x.is_nan()) {
            return None;
        }
        let angular = Vector3::new(i[1], i[2], i[3]);
        let linear = Vector3::new(i[4], i[5], i[6]);
        Some(Reaction::from_impulse(end, (linear, angular), dt, &at?))
    }

    fn save(&self, out: &mut Vec<f64>) {
        out.extend(self.below);
        out.extend(self.last);
    }

    fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        w.fill(&mut self.below)?;
        w.fill(&mut self.last)
    }
}

impl BeamObserver<'_> {
    pub(super) fn io(&mut self, r: Result<(), CliError>) {
        if let Err(e) = r
            && self.error.is_none()
        {
            self.error = Some(e);
        }
    }

    pub(super) fn record<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
        &mut self,
        e: &Beam<R>,
    ) -> Result<(), veselov::Error> {
        let level = e.level();
        let x = self.setup.coordinate(level);
        let j = e.evolution_momentum::<6>(|g: &SE3<f64>| -> SMatrix<f64, 6, 6> { left_generators(g) });
        let mut energy = 0.0;
        e.for_each_cell(|_, cell, y| {
            let (el, en) = e.lagrangian().cell_energy_densities::<RigidMotions, 6>(cell, y);
            energy += if self.setup.space { en } else { el };
        });
        energy *= if self.setup.space { self.setup.dt } else { self.setup.ds };
        if !energy.is_finite() || !j.plus.iter().all(|v| v.is_finite()) {
            return Err(veselov::Error::NonFiniteState {
                step: level,
                t: x,
                what: "energy or momentum map".into(),
            });
        }
        if !self.started {
            self.first.copy_from_slice(j.plus.as_slice());
            self.energy_range = [energy, energy];
            self.started = true;
        }
        self.energy_range = [self.energy_range[0].min(energy), self.energy_range[1].max(energy)];
        let change = (j.plus - SVector::<f64, 6>::from(self.first)).amax();
        self.drift = self.drift.max(change / j.scale.max(f64::MIN_POSITIVE));
        self.row.clear();
        self.line.clear();
        let mut c = [0.0; 12];
        for node in 0..=e.cross() {
            <RigidMotions as veselov::field::fibre::Fibre<6>>::write(&e.value(0, node), &mut c);
            // Fibre order: R row by row, then the translation.
            self.row.extend_from_slice(&c);
            self.line.extend_from_slice(&c[9..]);
        }
        let tip = self.shape.tip_node().unwrap_or(0);
        let mut tip_frame = [0.0; 9];
        tip_frame.copy_from_slice(&self.row[12 * tip..12 * tip + 9]);
        self.shape.record(&self.line, tip_frame);
        let domain = self.domain.value(e, &j.plus, j.scale);
        let mut m = vec![self.setup.steps_at(level) as f64, x];
        m.extend_from_slice(j.plus.as_slice());
        m.extend_from_slice(domain.as_slice());
        let line = &self.line;
        let r = self
            .frames
            .row(&self.row)
            .and_then(|()| self.centerline.as_mut().map_or(Ok(()), |c| c.row(line)))
            .and_then(|()| self.momentum.row(&m))
            .and_then(|()| self.energy.row(&[self.setup.steps_at(level) as f64, x, energy]));
        self.io(r);
        Ok(())
    }

    /// The first given column of a space evolution, as the first row of
    /// `frames.npy` (its momentum and energy need a band below it: their
    /// rows start at column 1).
    pub(super) fn record_previous<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
        &mut self,
        e: &Beam<R>,
    ) -> Result<(), veselov::Error> {
        self.row.clear();
        let mut c = [0.0; 12];
        for node in 0..=e.cross() {
            <RigidMotions as veselov::field::fibre::Fibre<6>>::write(&e.value(1, node), &mut c);
            self.row.extend_from_slice(&c);
        }
        let r = self.frames.row(&self.row);
        self.io(r);
        Ok(())
    }
}

impl<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static> Observer<Beam<R>> for BeamObserver<'_> {
    fn observe(&mut self, step: u64, state: &Beam<R>, _: &StepStats) -> Control {
        self.domain.add_band(state);
        self.support.add_band(state);
        let recorded = if step.is_multiple_of(self.every) {
            self.record(state)
        } else {
            Ok(())
        };
        after_recording(recorded, self.error.is_some())
    }
}

impl Resumable for BeamObserver<'_> {
    fn save(&mut self, out: &mut Vec<f64>) -> Result<(), CliError> {
        let centerline = match &mut self.centerline {
            Some(c) => c.position()?,
            None => Default::default(),
        };
        for p in [
            self.frames.position()?,
            self.momentum.position()?,
            self.energy.position()?,
            centerline,
        ] {
            p.save(out);
        }
        out.extend(self.first);
        out.extend([self.drift, f64::from(u8::from(self.started))]);
        out.extend(self.energy_range);
        self.domain.save(out);
        self.support.save(out);
        self.shape.save(out);
        Ok(())
    }
    fn take_error(&mut self) -> Option<CliError> {
        self.error.take()
    }
}

impl BeamObserver<'_> {
    pub(super) fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        for x in &mut self.first {
            *x = w.one()?;
        }
        self.drift = w.one()?;
        self.started = w.one()? != 0.0;
        self.energy_range = [w.one()?, w.one()?];
        self.domain.restore(w)?;
        self.support.restore(w)?;
        self.shape.restore(w)
    }
}
