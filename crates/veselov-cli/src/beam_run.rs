//! The run of a beam scenario ([`crate::beam`]) on the shared pipeline:
//! seed 000's multisymplectic Lie-group integrator marching in time (level
//! ℓ = time node j, t = ℓΔt, across the beam's nodes a) or in space (level
//! ℓ = column a, s = ℓΔs, across the time nodes j), one row of every
//! output per `every` levels.
//!
//! Outputs: `frames.npy` (rows × cross nodes × 12: R row by row, then the
//! position), `momentum.csv` (level, t or s, then the six components of the
//! evolution momentum map 𝖩⁺ of the cell level below — 𝖩_𝖫 in time, 𝖩_𝖭 in
//! space — angular first), `energy.csv` (level, t or s, E_𝖫 = Δs Σ e_𝖫 or
//! E_𝖭 = Δt Σ e_𝖭), `summary.json` (with the largest change of 𝖩⁺ relative
//! to the size of its terms), plots of the centreline, the momentum map and
//! the energy.

use std::path::Path;

use nalgebra::{SMatrix, SVector};
use serde_json::json;
use veselov::field::evolution::{Direction, EndCondition, Evolution000, EvolutionStepper};
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, ExpMap, LieGroup, Retraction, SE3};
use veselov::models::beam::paper::{DS, DT, LAST_TIME_NODE, XI0, prescribed_columns};
use veselov::models::beam::{BeamDensity, BeamLagrangian, beam_lagrangian, left_generators, straight};
use veselov::run::{Control, Observer, Status, StepStats, StopWhen, Words};

use crate::beam::{BeamSetup, BeamStart};
use crate::error::CliError;
use crate::output::Table;
use crate::pipeline::RunJob;
use crate::pipeline::finish::{Ending, close_run};
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{CSV_BYTES_PER_VALUE, Plan, Resumable, Resumed, after_recording, open_lattice_run};

type Beam<R> = Evolution000<RigidMotions, BeamLagrangian<R>, 6>;

/// Run a beam scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let setup = BeamSetup::parse(path, text)?;
    if setup.cayley {
        march::<CayleyMap>(&setup, job)
    } else {
        march::<ExpMap>(&setup, job)
    }
}

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
struct DomainCurrent {
    bottom: [f64; 6],
    sides: [f64; 6],
    scale: f64,
    worst: f64,
    started: bool,
}

impl DomainCurrent {
    /// Add the band between the previous and the current level of `e`.
    fn add_band<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(&mut self, e: &Beam<R>) {
        let generators = |g: &SE3<f64>| -> SMatrix<f64, 6, 6> { left_generators(g) };
        let first = e.cell_currents::<6>(0, generators);
        let last = e.cell_currents::<6>(e.cross() - 1, generators);
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
struct BeamObserver<'a> {
    setup: &'a BeamSetup,
    every: u64,
    frames: NpyStream,
    momentum: CsvStream,
    energy: CsvStream,
    /// 𝖩⁺ at the first row and the largest change since, relative to the
    /// size of its terms.
    first: [f64; 6],
    drift: f64,
    started: bool,
    /// 𝒥 on the whole computed domain (note 000 (58)): the bottom row's
    /// part, the running sum of the side columns' currents, the size of the
    /// terms summed, and the largest |𝒥| relative to it so far.
    domain: DomainCurrent,
    energy_range: [f64; 2],
    row: Vec<f64>,
    error: Option<CliError>,
}

impl BeamObserver<'_> {
    fn io(&mut self, r: Result<(), CliError>) {
        if let Err(e) = r
            && self.error.is_none()
        {
            self.error = Some(e);
        }
    }

    fn record<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
        &mut self,
        e: &Beam<R>,
    ) -> Result<(), veselov::Error> {
        let level = e.level();
        let x = level as f64 * if self.setup.space { self.setup.ds } else { self.setup.dt };
        let j = e.evolution_momentum::<6>(|g: &SE3<f64>| -> SMatrix<f64, 6, 6> { left_generators(g) });
        let mut energy = 0.0;
        e.for_each_cell(|_, _, y| {
            let (el, en) = e.lagrangian().energy_densities::<RigidMotions, 6>(y);
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
        let mut c = [0.0; 12];
        for node in 0..=e.cross() {
            <RigidMotions as veselov::field::fibre::Fibre<6>>::write(&e.value(0, node), &mut c);
            // Fibre order: R row by row, then the translation.
            self.row.extend_from_slice(&c);
        }
        let domain = self.domain.value(e, &j.plus, j.scale);
        let mut m = vec![level as f64, x];
        m.extend_from_slice(j.plus.as_slice());
        m.extend_from_slice(domain.as_slice());
        let r = self
            .frames
            .row(&self.row)
            .and_then(|()| self.momentum.row(&m))
            .and_then(|()| self.energy.row(&[level as f64, x, energy]));
        self.io(r);
        Ok(())
    }
}

impl<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static> Observer<Beam<R>> for BeamObserver<'_> {
    fn observe(&mut self, step: u64, state: &Beam<R>, _: &StepStats) -> Control {
        self.domain.add_band(state);
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
        for p in [
            self.frames.position()?,
            self.momentum.position()?,
            self.energy.position()?,
        ] {
            p.save(out);
        }
        out.extend(self.first);
        out.extend([self.drift, f64::from(u8::from(self.started))]);
        out.extend(self.energy_range);
        self.domain.save(out);
        Ok(())
    }
    fn take_error(&mut self) -> Option<CliError> {
        self.error.take()
    }
}

impl BeamObserver<'_> {
    fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        for x in &mut self.first {
            *x = w.one()?;
        }
        self.drift = w.one()?;
        self.started = w.one()? != 0.0;
        self.energy_range = [w.one()?, w.one()?];
        self.domain.restore(w)
    }
}

/// The first two levels: time evolution, the beam at rest (straight, or bent
/// with curvature κ about E1: g_{a+1} = g_a τ(Δs(κe₁ + E6))); space
/// evolution, the paper's prescribed columns (or, well posed, column 1 the
/// rigid transport of column 0 with a 10⁻³ perturbation of its velocity).
fn initial<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
    setup: &BeamSetup,
) -> (Vec<SE3<f64>>, Vec<SE3<f64>>) {
    let nodes = setup.scenario.model.nodes;
    match setup.start {
        BeamStart::Straight => {
            let g: Vec<_> = (0..nodes).map(|a| straight(setup.ds, a)).collect();
            (g.clone(), g)
        }
        BeamStart::Bent(kappa) => {
            let step = R::tau(&(SVector::<f64, 6>::from([kappa, 0.0, 0.0, 0.0, 0.0, 1.0]) * setup.ds));
            let mut g = vec![SE3::identity(); nodes];
            for a in 0..nodes - 1 {
                g[a + 1] = g[a].compose(&step);
            }
            (g.clone(), g)
        }
        BeamStart::Paper => prescribed_columns::<R>(LAST_TIME_NODE + 1),
        BeamStart::PaperWellPosed => {
            let last = LAST_TIME_NODE + 1;
            let (c0, _) = prescribed_columns::<R>(last);
            let h = SE3::from_translation(nalgebra::Vector3::new(0.0, 0.0, DS));
            let xi1 = h.inverse().adjoint() * SVector::from(XI0) + SVector::from([1e-3, 0.0, -1e-3, 0.0, 0.0, 0.0]);
            let step = R::tau(&(xi1 * DT));
            let mut c1 = vec![h; last + 1];
            for j in 0..last {
                c1[j + 1] = c1[j].compose(&step);
            }
            (c0, c1)
        }
    }
}

fn march<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
    setup: &BeamSetup,
    job: RunJob,
) -> Result<(), CliError> {
    let s = &setup.scenario;
    if let Some(reason) = &setup.unstable {
        eprintln!("warning: {reason}; running because [method] allow_unstable = true");
    }
    if let Some(requested) = setup.dt_requested
        && (requested - setup.dt).abs() > 1e-12 * requested
        && !job.quiet
    {
        eprintln!(
            "note: dt = {requested:e} adjusted to {:e} = t_end/{} so that the run ends at t_end",
            setup.dt,
            setup.levels + 1
        );
    }
    let density = BeamDensity::new(setup.properties)
        .with_damping(setup.damping)
        .map_err(|e| setup.key("loads.damping", e.to_string()))?
        .with_gravity(setup.gravity);
    let lag = beam_lagrangian::<R>(density, setup.dt, setup.ds).map_err(|e| setup.key("model", e.to_string()))?;
    let (first, second) = initial::<R>(setup);
    let end = |clamped: bool, value: SE3<f64>| -> EndCondition<SE3<f64>> {
        if clamped {
            EndCondition::Prescribed(Box::new(move |_| value))
        } else {
            EndCondition::Natural
        }
    };
    let last = first.len() - 1;
    let direction = if setup.space { Direction::Space } else { Direction::Time };
    let evolution = Beam::<R>::new(
        direction,
        lag,
        &first,
        &second,
        end(setup.clamped[0], first[0]),
        end(setup.clamped[1], first[last]),
        setup.options,
    )
    .map_err(|e| setup.key("initial", e.to_string()))?;
    let cross = last + 1;
    let rows = setup.levels / setup.every + 2;
    let plan = Plan {
        steps: setup.levels as f64,
        steps_key: "time.t_end",
        bytes: rows as f64 * (cross as f64 * 12.0 * 8.0 + 11.0 * CSV_BYTES_PER_VALUE),
        bytes_key: "output.every",
        unit: "levels",
        step: Some(setup.dt),
        t_end: None,
    };
    let (mut session, resumed) = open_lattice_run::<3>(
        &setup.path,
        &job,
        s.output.dir.clone(),
        &plan,
        s.output.checkpoint_every,
        "beam",
    )?;
    let dir = session.dir.clone();
    let at = Resumed::positions(&resumed);
    let x = if setup.space { "s" } else { "t" };
    let names = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let mut obs = BeamObserver {
        setup,
        every: setup.every,
        frames: NpyStream::create(&dir.join("frames.npy"), &[cross, 12], rows, at[0])?,
        momentum: CsvStream::create(
            &dir.join("momentum.csv"),
            &names(&[
                "level",
                x,
                "J_wx",
                "J_wy",
                "J_wz",
                "J_vx",
                "J_vy",
                "J_vz",
                "Jdomain_wx",
                "Jdomain_wy",
                "Jdomain_wz",
                "Jdomain_vx",
                "Jdomain_vy",
                "Jdomain_vz",
            ]),
            at[1],
        )?,
        energy: CsvStream::create(&dir.join("energy.csv"), &names(&["level", x, "energy"]), at[2])?,
        first: [0.0; 6],
        drift: 0.0,
        started: false,
        domain: DomainCurrent::default(),
        energy_range: [f64::NAN; 2],
        row: Vec::with_capacity(cross * 12),
        error: None,
    };
    let mut state = evolution;
    let step_length = if setup.space { setup.ds } else { setup.dt };
    let mut stepper = EvolutionStepper::<RigidMotions, BeamLagrangian<R>, 6>::new(step_length);
    let (first_step, start) = match &resumed {
        Some(r) => (r.restore_run(&dir, |w| obs.restore(w), &mut state)?, Ok(())),
        None => {
            obs.domain.add_band(&state);
            (0, obs.record(&state))
        }
    };
    let outcome = session.execute(
        start,
        &mut stepper,
        &mut state,
        first_step,
        StopWhen::steps(setup.levels),
        &mut obs,
    )?;
    if !outcome.last_step.is_multiple_of(obs.every)
        && matches!(outcome.status, Status::Completed)
        && let Err(e) = obs.record(&state)
    {
        obs.io(Err(CliError::Run {
            error: e,
            dir: dir.clone(),
        }));
    }
    obs.frames.position()?;
    obs.energy.position()?;
    let rows_out = obs.momentum.position()?.rows;
    let level = state.level();
    let own = json!({
        "scenario": setup.path.display().to_string(),
        "model": s.model.name,
        "evolution": if setup.space { "space" } else { "time" },
        "retraction": if setup.cayley { "cayley" } else { "exp" },
        "nodes": s.model.nodes,
        "cross_nodes": cross,
        "ds": setup.ds,
        "dt": setup.dt,
        "dt_requested": setup.dt_requested,
        "courant": setup.courant,
        "levels": level,
        "node_solves": outcome.last_step * cross as u64,
        "newton_iterations_per_node": outcome.iterations as f64 / (outcome.last_step.max(1) * cross as u64) as f64,
        "ends": if setup.space { json!(["natural", "natural"]) } else {
            json!(setup.clamped.map(|c| if c { "clamped" } else { "free" }))
        },
        "momentum_map_drift": obs.drift,
        "domain_current_max": obs.domain.worst,
        "energy_min": obs.energy_range[0],
        "energy_max": obs.energy_range[1],
    });
    let t_final = level as f64 * step_length;
    let ending = Ending {
        status: outcome.status,
        steps: outcome.last_step,
        t_final,
        iterations: outcome.iterations,
    };
    close_run(
        &session,
        ending,
        own,
        obs.error.take(),
        (s.output.plots, || {
            draw_beam(&dir, cross, rows_out, x, &s.output.plot_format)
        }),
        || {
            format!(
                "beam, {} evolution: {} levels to {x} = {t_final}, max change of the momentum map {:.1e} of its terms",
                if setup.space { "space" } else { "time" },
                level,
                obs.drift,
            )
        },
    )
}

/// Centreline snapshots (positions of the frames), the centreline animation
/// (`centerline.gif`), momentum-map changes and energy, read back from the
/// files.
pub fn draw_beam(dir: &Path, cross: usize, rows: u64, x: &str, format: &str) -> Result<(), CliError> {
    crate::centerline::draw_centerline_figures(
        dir,
        ("frames", 12),
        (cross, rows),
        |r, c| [r[12 * c + 9], r[12 * c + 10], r[12 * c + 11]],
        (x, format),
    )?;
    let momentum = Table::read_csv(&dir.join("momentum.csv"))?;
    crate::figures::draw_changes(
        &dir.join(format!("momentum.{format}")),
        &momentum,
        x,
        &["J_wx", "J_wy", "J_wz", "J_vx", "J_vy", "J_vz"],
        ("Evolution momentum map: change since the start", "J − J(first row)"),
    )?;
    let energy = Table::read_csv(&dir.join("energy.csv"))?;
    if let (Some(t), Some(e)) = (energy.column(x), energy.column("energy")) {
        crate::figures::draw_curves(
            &dir.join(format!("energy.{format}")),
            ("Energy", x, "E"),
            &[("energy".to_string(), t, e)],
            false,
        )?;
    }
    Ok(())
}
