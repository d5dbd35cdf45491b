//! The observer of a rod run: the centreline and frames at the cut, the
//! momenta and the energy every `every` time steps, the momentum balance
//! against the impulse of the loads (with a held end: the reaction of the
//! support), the tip's motion, and the largest residual of the discrete
//! Euler–Lagrange equations.

use nalgebra::Vector3;
use veselov::field::cauchy::CauchyMarcher;
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::fibre::{Pose, PositionRotation};
use veselov::lie::so3;
use veselov::models::rod::{CosseratCell, Weight};
use veselov::models::rod::{energy, load_impulse};
use veselov::run::{Control, Observer, StepStats, Words};

use super::initial::FIRST_CUT;
use super::setup::RodSetup;
use crate::centerline::{Reaction, ShapeChange};
use crate::error::CliError;
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{Resumable, after_recording};

/// Prop. 6.5's cell of the rod.
pub(super) type Cell = CosseratCell<Weight>;

pub(super) type Rod<L> = CauchyMarcher<PositionRotation, L, 6>;

/// Writes the rows and keeps the balances.
pub(super) struct RodObserver<'a> {
    pub(super) setup: &'a RodSetup,
    /// Prop. 6.5's cell (with the run's shear frame), whose cell energy is
    /// the energy written (for either quadrature).
    pub(super) lag: Cell,
    pub(super) every_levels: u64,
    pub(super) centerline: NpyStream,
    pub(super) frames: NpyStream,
    pub(super) momentum: CsvStream,
    pub(super) energy: CsvStream,
    /// Momenta at the start, the impulses summed since, the largest balance
    /// errors, the energy at the start and its range.
    pub(super) start: [f64; 6],
    pub(super) impulse: [f64; 6],
    pub(super) balance_error: [f64; 2],
    pub(super) energy0: f64,
    pub(super) energy_range: [f64; 2],
    /// The largest relative residual of the discrete Euler–Lagrange
    /// equations (the vertex equations) at the accepted values.
    pub(super) el_residual_max: f64,
    pub(super) rows_written: u64,
    /// The first and last rows of the centreline and the tip's frame.
    pub(super) shape: ShapeChange,
    /// The end held, when only one is: the support whose reaction is
    /// reported.
    pub(super) support: Option<usize>,
    /// The support's impulse since the start, I_R(c) = P(c) − P(0) − Σ I_loads
    /// (linear, angular about the origin; the discrete momentum balance),
    /// with the step c (levels since the first cut) it was taken at: one
    /// time step before the planned end, and at the last row (NaN: not yet).
    pub(super) support_before: [f64; 7],
    pub(super) support_last: [f64; 7],
    pub(super) error: Option<CliError>,
    pub(super) buffer: Vec<f64>,
    pub(super) before: Vec<Option<Pose<f64>>>,
}

impl RodObserver<'_> {
    pub(super) fn io(&mut self, r: Result<(), CliError>) {
        if let Err(e) = r
            && self.error.is_none()
        {
            self.error = Some(e);
        }
    }

    fn momenta<L: DiscreteLagrangian<PositionRotation, 6>>(m: &Rod<L>) -> [f64; 6] {
        let (p, l) = veselov::models::rod::momenta(m);
        [p[0], p[1], p[2], l[0], l[1], l[2]]
    }

    /// The impulse of the loads and of gravity on the level just solved
    /// (`None` before the marcher's first step since it was built or
    /// restored, see [`load_impulse`]).
    fn level_impulse<L: DiscreteLagrangian<PositionRotation, 6>>(&self, m: &Rod<L>) -> Option<[f64; 6]> {
        let (mut f, mut tau) = load_impulse(m)?;
        let g = self.setup.gravity;
        if g != Vector3::zeros() {
            // P = −2ρA g·r enters at v₀ only: Σ_k ∇_{r_k}L_β = (ΔsΔt/4)ρA g
            // per cell, torque r₀ × that (note 003 §3.7 with a potential);
            // Q_sym spreads it evenly over the three vertices.
            let c = m.level() - 1;
            let (ds, dt) = (self.setup.lattice.ds(), self.setup.dt);
            let symmetric = self.setup.symmetric;
            m.for_each_straddling_cell(|cell, y| {
                if cell.origin[0] + cell.origin[1] == c {
                    let rho = self.lag.parameters_at(self.lag.material_coordinate(cell)).rho();
                    let weight = g * (0.25 * ds * dt * rho);
                    f += weight;
                    tau += if symmetric {
                        ((y[0].position + y[1].position + y[2].position) / 3.0).cross(&weight)
                    } else {
                        y[0].position.cross(&weight)
                    };
                }
            });
        }
        Some([f[0], f[1], f[2], tau[0], tau[1], tau[2]])
    }

    /// Centreline and frames at the cut (level c: the points of level c as
    /// marched, the others at the midpoint of their values at levels c − 1
    /// and c + 1).
    fn snapshot<L: DiscreteLagrangian<PositionRotation, 6>>(&mut self, m: &Rod<L>) -> Result<(), veselov::Error> {
        let lattice = &self.setup.lattice;
        let nodes = lattice.nodes();
        let c = m.level();
        self.buffer.clear();
        self.buffer.resize(nodes * 12, f64::NAN);
        self.before.clear();
        self.before.resize(nodes, None);
        if let Some(values) = m.level_values(c - 1) {
            for (i, y) in values.iter().enumerate() {
                if let Some(p) = lattice.node(c - 1, i) {
                    self.before[p] = Some(*y);
                }
            }
        }
        for (w, mid) in [(c, false), (c + 1, true)] {
            let Some(values) = m.level_values(w) else { continue };
            for (i, y) in values.iter().enumerate() {
                let Some(p) = lattice.node(w, i) else { continue };
                let pose = match (mid, self.before[p]) {
                    (false, _) => *y,
                    (true, Some(b)) => midpoint(&b, y)?,
                    (true, None) => continue,
                };
                write_pose(&mut self.buffer, nodes, p, &pose);
            }
        }
        Ok(())
    }

    pub(super) fn record<L: DiscreteLagrangian<PositionRotation, 6>>(
        &mut self,
        m: &Rod<L>,
        stepper_t: f64,
    ) -> Result<(), veselov::Error> {
        let momenta = Self::momenta(m);
        let e = energy(m, &self.lag)?;
        if !e.is_finite() {
            return Err(veselov::Error::NonFiniteState {
                // The run's step (levels since the first cut), as the
                // driver counts them: 0 for the initial data.
                step: usize::try_from(m.level() - FIRST_CUT).unwrap_or(0),
                t: stepper_t,
                what: "energy".into(),
            });
        }
        if self.energy0.is_nan() {
            self.energy0 = e;
            self.energy_range = [e, e];
            self.start = momenta;
        }
        self.energy_range = [self.energy_range[0].min(e), self.energy_range[1].max(e)];
        let step = (m.level() - FIRST_CUT) as f64;
        self.support_last = self.support_impulse(step, &momenta);
        if step == self.support_before_step() {
            self.support_before = self.support_last;
        }
        self.snapshot(m)?;
        if self.setup.ends.start.is_free() && self.setup.ends.end.is_free() {
            // Momentum scales: besides the momenta and impulses themselves,
            // √(2ME) bounds |P| for a rod of mass M and energy E without a
            // potential (|Σmv| ≤ √(Σm)·√(Σmv²)), and R·√(2ME) bounds |L|,
            // R the largest distance of the rod from the origin.
            let nodes = self.setup.lattice.nodes();
            let reach = (0..nodes)
                .map(|p| Vector3::new(self.buffer[3 * p], self.buffer[3 * p + 1], self.buffer[3 * p + 2]).norm())
                .fold(0.0, f64::max);
            let mass = self.setup.mass;
            let kinetic_scale = if self.setup.gravity == Vector3::zeros() {
                (2.0 * mass * self.energy_range[1].abs()).sqrt()
            } else {
                0.0
            };
            for (k, half, floor) in [(0, 0..3, kinetic_scale), (1, 3..6, kinetic_scale * reach)] {
                let scale = half
                    .clone()
                    .map(|i| momenta[i].abs().max(self.start[i].abs()).max(self.impulse[i].abs()))
                    .fold(floor.max(f64::MIN_POSITIVE), f64::max);
                let error = half
                    .map(|i| (momenta[i] - self.start[i] - self.impulse[i]).abs())
                    .fold(0.0, f64::max);
                self.balance_error[k] = self.balance_error[k].max(error / scale);
            }
        }
        let nodes = self.setup.lattice.nodes();
        let (line, frames) = self.buffer.split_at(nodes * 3);
        let tip = self.shape.tip_node().unwrap_or(0);
        let mut tip_frame = [0.0; 9];
        tip_frame.copy_from_slice(&frames[9 * tip..9 * tip + 9]);
        self.shape.record(line, tip_frame);
        let mut row = vec![stepper_t];
        row.extend_from_slice(&momenta);
        let r = self
            .centerline
            .row(line)
            .and_then(|()| self.frames.row(frames))
            .and_then(|()| self.momentum.row(&row))
            .and_then(|()| self.energy.row(&[stepper_t, e]));
        self.io(r);
        self.rows_written += 1;
        Ok(())
    }
}

/// Position p of the centreline block and frame p of the frames block.
fn write_pose(buffer: &mut [f64], nodes: usize, p: usize, y: &Pose<f64>) {
    let r = y.rotation.matrix();
    for a in 0..3 {
        buffer[p * 3 + a] = y.position[a];
        for b in 0..3 {
            buffer[nodes * 3 + p * 9 + 3 * a + b] = r[(a, b)];
        }
    }
}

/// The midpoint of two poses: positions averaged, R₀exp(½log(R₀ᵀR₁)).
fn midpoint(a: &Pose<f64>, b: &Pose<f64>) -> Result<Pose<f64>, veselov::Error> {
    let half = so3::log(&a.rotation.inverse().compose(&b.rotation))? * 0.5;
    Ok(Pose::new(
        (a.position + b.position) * 0.5,
        a.rotation.compose(&so3::exp(&half)),
    ))
}

impl<L: DiscreteLagrangian<PositionRotation, 6>> Observer<Rod<L>> for RodObserver<'_> {
    fn observe(&mut self, step: u64, state: &Rod<L>, stats: &StepStats) -> Control {
        self.el_residual_max = self.el_residual_max.max(stats.max_relative_residual);
        // Observed after a step, so the level's impulse is always known.
        if let Some(i) = self.level_impulse(state) {
            for (s, x) in self.impulse.iter_mut().zip(i) {
                *s += x;
            }
        }
        let recorded = if step.is_multiple_of(self.every_levels) {
            self.record(state, self.setup.time_at(state.level()))
        } else {
            if self.support.is_some() && step as f64 == self.support_before_step() {
                self.support_before = self.support_impulse(step as f64, &Self::momenta(state));
            }
            Ok(())
        };
        after_recording(recorded, self.error.is_some())
    }
}

impl Resumable for RodObserver<'_> {
    fn save(&mut self, out: &mut Vec<f64>) -> Result<(), CliError> {
        for p in [
            self.centerline.position()?,
            self.frames.position()?,
            self.momentum.position()?,
            self.energy.position()?,
        ] {
            p.save(out);
        }
        out.extend(self.start);
        out.extend(self.impulse);
        out.extend(self.balance_error);
        out.push(self.energy0);
        out.extend(self.energy_range);
        out.push(self.el_residual_max);
        out.extend(self.support_before);
        out.extend(self.support_last);
        self.shape.save(out);
        Ok(())
    }
    fn take_error(&mut self) -> Option<CliError> {
        self.error.take()
    }
}

impl RodObserver<'_> {
    pub(super) fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        for x in self
            .start
            .iter_mut()
            .chain(&mut self.impulse)
            .chain(&mut self.balance_error)
        {
            *x = w.one()?;
        }
        self.energy0 = w.one()?;
        self.energy_range = [w.one()?, w.one()?];
        self.el_residual_max = w.one()?;
        w.fill(&mut self.support_before)?;
        w.fill(&mut self.support_last)?;
        self.shape.restore(w)
    }

    /// The step one time step (two levels) before the planned end, at which
    /// the support's impulse is kept for the reaction over the last step.
    fn support_before_step(&self) -> f64 {
        self.setup.levels as f64 - 2.0
    }

    /// The support's impulse since the start, at `step` where the momenta are
    /// `momenta`: I_R = P − P(0) − Σ I_loads (the discrete momentum balance
    /// with the support's impulse as the only unknown), after the step.
    fn support_impulse(&self, step: f64, momenta: &[f64; 6]) -> [f64; 7] {
        let mut out = [step; 7];
        for i in 0..6 {
            out[i + 1] = momenta[i] - self.start[i] - self.impulse[i];
        }
        out
    }

    /// The reaction of the support over the run's last time step, from the
    /// momentum balance: F = ΔI_R/Δt (linear), M = ΔI_R,O/Δt − r_s × F about
    /// the support point r_s ([`Reaction::from_impulse`]); `None` without a
    /// single held end or before the run has reached its planned end.
    pub(super) fn reaction(&self) -> Option<Reaction> {
        let end = self.support?;
        let total = self.setup.levels as f64;
        let (before, last) = (&self.support_before, &self.support_last);
        if before[0] != total - 2.0 || last[0] != total {
            return None;
        }
        let node = if end == 0 { 0 } else { self.setup.lattice.nodes() - 1 };
        let at = self.shape.last_point(node)?;
        let d = |i: usize| last[i + 1] - before[i + 1];
        let linear = Vector3::new(d(0), d(1), d(2));
        let angular = Vector3::new(d(3), d(4), d(5));
        Some(Reaction::from_impulse(end, (linear, angular), self.setup.dt, &at))
    }
}
