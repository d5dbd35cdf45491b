//! The run of a Cosserat-rod scenario ([`crate::rod`]) on the shared
//! pipeline: the core's Cauchy march of Prop. 6.5 with the split vertex
//! step, one row of every output per `every` time steps.
//!
//! Outputs: `centerline.npy` (rows × nodes × 3) and `frames.npy` (rows ×
//! nodes × 9, R row by row) at the output times — material points of the
//! cut's level as marched, the others (which the leapfrog lattice holds half
//! a step earlier and later) at the midpoint of their two values (positions
//! averaged, rotations along the geodesic); `momentum.csv` (t, P_x, P_y,
//! P_z, L_x, L_y, L_z: the discrete linear and angular momenta about the
//! origin at the cut, note 003 §3.7); `energy.csv` (t, energy: kinetic +
//! elastic + potential of the slab below the cut over Δt); `summary.json`;
//! plots of the centreline (x–z and y–z projections), the momenta (change
//! from the start) and the energy.
//!
//! With free ends the momenta change exactly by the impulse of gravity,
//! damping and the end load (the discrete Lagrange–d'Alembert balance); the
//! summary reports the largest balance error. With a clamped end the
//! support's reaction is not computed and the balance is not reported.
//! `el_residual_max` in the summary is the largest residual of the discrete
//! Euler–Lagrange equations of the run (each vertex equation at its accepted
//! values, relative to the size of its terms).

use std::path::Path;

use nalgebra::Vector3;
use serde_json::json;
use veselov::field::CauchyStepper;
use veselov::field::cauchy::CauchyMarcher;
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::discretize::{CfkNodes, CosseratCell, CosseratDensity, ShearFrame, VertexRule, Weight};
use veselov::field::fibre::{Pose, PositionRotation};
use veselov::lie::so3;
use veselov::models::rod::{BendingError, EndCondition, energy, load_impulse};
use veselov::run::{Checkpoint, Control, Observer, Status, StepStats, StopWhen, Words};

use crate::error::CliError;
use crate::output::Table;
use crate::pipeline::RunJob;
use crate::pipeline::finish::{Ending, close_run};
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{CSV_BYTES_PER_VALUE, Plan, Resumable, Resumed, after_recording, open_lattice_run};
use crate::rod::RodSetup;

type Cell = CosseratCell<Weight>;
/// The rod with Q_sym (`[method] quadrature = "symmetric"`): the core's
/// generic discretisation of the same density, marched by the 6-D Newton.
type SymmetricCell = VertexRule<PositionRotation, CosseratDensity<Weight>, CfkNodes<2>, 6, 2>;

/// The level of the march's first cut (Cauchy data on levels 0 … 3): the
/// run's t = 0.
const FIRST_CUT: i64 = 2;

/// The run's time of the cut below the marcher's level: (level − 2)Δt/2.
fn run_time<L: DiscreteLagrangian<PositionRotation, 6>>(m: &Rod<L>, dt: f64) -> f64 {
    (m.level() - FIRST_CUT) as f64 * 0.5 * dt
}
type Rod<L> = CauchyMarcher<PositionRotation, L, 6>;

/// Writes the rows and keeps the balances.
struct RodObserver<'a> {
    setup: &'a RodSetup,
    /// Prop. 6.5's cell (with the run's shear frame), whose cell energy is
    /// the energy written (for either quadrature).
    lag: Cell,
    every_levels: u64,
    centerline: NpyStream,
    frames: NpyStream,
    momentum: CsvStream,
    energy: CsvStream,
    /// Momenta at the start, the impulses summed since, the largest balance
    /// errors, the energy at the start and its range.
    start: [f64; 6],
    impulse: [f64; 6],
    balance_error: [f64; 2],
    energy0: f64,
    energy_range: [f64; 2],
    /// The largest relative residual of the discrete Euler–Lagrange
    /// equations (the vertex equations) at the accepted values.
    el_residual_max: f64,
    rows_written: u64,
    error: Option<CliError>,
    buffer: Vec<f64>,
    before: Vec<Option<Pose<f64>>>,
}

impl RodObserver<'_> {
    fn io(&mut self, r: Result<(), CliError>) {
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

    fn record<L: DiscreteLagrangian<PositionRotation, 6>>(
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

fn end_name(e: &EndCondition) -> &'static str {
    match e {
        EndCondition::Free => "free",
        EndCondition::Clamped(_) => "clamped",
        EndCondition::Driven(_) => "driven",
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
            self.record(state, run_time(state, self.setup.dt))
        } else {
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
        Ok(())
    }
    fn take_error(&mut self) -> Option<CliError> {
        self.error.take()
    }
}

impl RodObserver<'_> {
    fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
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
        Ok(())
    }
}

/// The shortfall of static bending deflections, estimated from shear
/// locking (`models::rod::resolution`), above which a run warns: 5 %.
const BENDING_ERROR_WARNING: f64 = 0.05;

/// Run a rod scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let setup = RodSetup::parse(path, text)?;
    let lattice = &setup.lattice;
    // Always shown, --quiet or not: the run is expected to blow up.
    if setup.courant > 1.0 {
        eprintln!(
            "warning: dt = {:e} exceeds the stability limit {:e} (step number {}); running because \
             [method] allow_unstable = true",
            setup.dt,
            setup.dt_limit,
            crate::rod::step_number_text(setup.courant)
        );
    }
    // Stable by the linear limit, but close to it a long run can still grow
    // (README, "the step limit"); always shown, as the warning above.
    if setup.courant > crate::rod::LONG_RUN_STEP_NUMBER && setup.courant <= 1.0 {
        eprintln!(
            "warning: step number {} is above {}: close to the stability limit, and sooner for \
             large motions, a long run can still grow (the tumbling rod example failed after 3,405 \
             steps at 0.95); lower dt or step_number for long runs",
            crate::rod::step_number_text(setup.courant),
            crate::rod::LONG_RUN_STEP_NUMBER
        );
    }
    // A silent loss of accuracy otherwise: always shown, as the warnings above.
    let (locking, nodes_advised) = (setup.locking, setup.nodes_for_bending);
    let bending = BendingError::at(locking);
    if setup.shear_frame == ShearFrame::Vertex && bending.deflection_deficit() > BENDING_ERROR_WARNING {
        eprintln!(
            "warning: bending is coarsely resolved: with material points {:e} apart the lattice's shear \
             locking number κGA·δ²/EI is {locking:.3}, so the rod bends as if about {:.0} % stiffer \
             (static bending deflections about {:.0} % short, bending frequencies about {:.0} % high); \
             nodes = {nodes_advised} or more bring it to about 1 %, or [method] shear_frame = \"centred\" \
             removes the locking",
            lattice.spacing(),
            100.0 * bending.stiffening,
            100.0 * bending.deflection_deficit(),
            100.0 * bending.frequency_excess()
        );
    }
    if let Some(requested) = setup.dt_requested
        && (requested - setup.dt).abs() > 1e-12 * requested
        && !job.quiet
    {
        eprintln!(
            "note: dt = {requested:e} adjusted to {:e} = t_end/{} so that the run ends at t_end",
            setup.dt, setup.steps
        );
    }
    let p = setup.parameters;
    let potential = match &setup.profile {
        None => Weight::uniform(setup.gravity, p.rho()),
        Some(profile) => Weight::profiled(setup.gravity, profile.iter().map(|q| q.rho()).collect(), lattice.ds())
            .map_err(|e| setup.key("model", e.to_string()))?,
    };
    let mut lag = CosseratCell::new(
        CosseratDensity {
            parameters: p,
            potential,
        },
        lattice.ds(),
        setup.dt,
    )
    .map_err(|e| setup.key("time.dt", e.to_string()))?;
    if let Some(loads) = setup.loads {
        lag = lag.with_loads(loads).map_err(|e| setup.key("loads", e.to_string()))?;
    }
    if let Some(profile) = &setup.profile {
        lag = lag
            .with_profile(profile.clone())
            .map_err(|e| setup.key("model", e.to_string()))?;
    }
    lag = lag.with_shear_frame(setup.shear_frame);
    if setup.symmetric {
        let nodes = CfkNodes::leapfrog(lattice.ds(), setup.dt).map_err(|e| setup.key("time.dt", e.to_string()))?;
        let rule: SymmetricCell = VertexRule::symmetric(lag.density.clone(), nodes);
        let marcher = start_march(&setup, rule)?;
        march(&setup, job, lag, marcher)
    } else {
        let marcher = start_march(&setup, lag.clone())?;
        march(&setup, job, lag, marcher)
    }
}

/// The marcher of cell Lagrangian `lag` on the rod's lattice from its Cauchy
/// data, with the ends' Dirichlet data.
fn start_march<L: DiscreteLagrangian<PositionRotation, 6>>(setup: &RodSetup, lag: L) -> Result<Rod<L>, CliError> {
    let lattice = &setup.lattice;
    let mut data = lattice.cauchy_data(setup.motion());
    setup.ends.apply(lattice, 0, &mut data);
    let mut marcher =
        CauchyMarcher::with_window(lag, lattice.torus().clone(), 0, &data, setup.options, lattice.window())
            .map_err(|e| setup.key("initial", e.to_string()))?;
    if let Some(d) = setup.ends.dirichlet(lattice) {
        marcher = marcher.with_dirichlet(d);
    }
    Ok(marcher)
}

/// March the rod with `marcher` and write everything (`lag`: Prop. 6.5's
/// cell with the run's shear frame, for the energy).
fn march<L>(setup: &RodSetup, job: RunJob, lag: Cell, marcher: Rod<L>) -> Result<(), CliError>
where
    L: DiscreteLagrangian<PositionRotation, 6>,
    Rod<L>: Checkpoint,
{
    let s = &setup.scenario;
    let lattice = &setup.lattice;
    let nodes = lattice.nodes();
    let rows = setup.steps / setup.every + 2;
    let plan = Plan {
        steps: 2.0 * setup.steps as f64,
        steps_key: "time.t_end",
        bytes: rows as f64 * (nodes as f64 * 12.0 * 8.0 + 9.0 * CSV_BYTES_PER_VALUE),
        bytes_key: "output.every",
        unit: "levels",
        step: Some(setup.dt),
        t_end: None,
    };
    let (mut session, resumed) = open_lattice_run::<4>(
        &setup.path,
        &job,
        s.output.dir.clone(),
        &plan,
        s.output.checkpoint_every.saturating_mul(2),
        "cosserat-rod",
    )?;
    let dir = session.dir.clone();
    let at = Resumed::positions(&resumed);
    let names = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let mut obs = RodObserver {
        setup,
        lag,
        every_levels: 2 * setup.every,
        centerline: NpyStream::create(&dir.join("centerline.npy"), &[nodes, 3], rows, at[0])?,
        frames: NpyStream::create(&dir.join("frames.npy"), &[nodes, 9], rows, at[1])?,
        momentum: CsvStream::create(
            &dir.join("momentum.csv"),
            &names(&["t", "P_x", "P_y", "P_z", "L_x", "L_y", "L_z"]),
            at[2],
        )?,
        energy: CsvStream::create(&dir.join("energy.csv"), &names(&["t", "energy"]), at[3])?,
        start: [0.0; 6],
        impulse: [0.0; 6],
        balance_error: [0.0; 2],
        energy0: f64::NAN,
        energy_range: [f64::NAN; 2],
        el_residual_max: 0.0,
        rows_written: 0,
        error: None,
        buffer: Vec::with_capacity(nodes * 12),
        before: Vec::with_capacity(nodes),
    };
    let mut state = marcher;
    let mut stepper = CauchyStepper::<PositionRotation, L, 6>::new(0.5 * setup.dt, FIRST_CUT);
    let (first, start) = match &resumed {
        Some(r) => (r.restore_run(&dir, |w| obs.restore(w), &mut state)?, Ok(())),
        None => {
            let t = run_time(&state, setup.dt);
            (0, obs.record(&state, t))
        }
    };
    let outcome = session.execute(
        start,
        &mut stepper,
        &mut state,
        first,
        StopWhen::steps(2 * setup.steps),
        &mut obs,
    )?;
    if !outcome.last_step.is_multiple_of(obs.every_levels) && matches!(outcome.status, Status::Completed) {
        let t = run_time(&state, setup.dt);
        if let Err(e) = obs.record(&state, t) {
            obs.io(Err(CliError::Run {
                error: e,
                dir: dir.clone(),
            }));
        }
    }
    obs.centerline.position()?;
    obs.frames.position()?;
    obs.energy.position()?;
    let rows_out = obs.momentum.position()?.rows;
    let t_final = run_time(&state, setup.dt);
    let free = setup.ends.start.is_free() && setup.ends.end.is_free();
    let own = json!({
        "scenario": setup.path.display().to_string(),
        "model": s.model.name,
        "nodes": nodes,
        "length": lattice.length(),
        "ds": lattice.ds(),
        "dt": setup.dt,
        "dt_requested": setup.dt_requested,
        "dt_stability_limit": setup.dt_limit,
        "step_number": setup.courant,
        "time_steps": outcome.last_step / 2,
        "levels": outcome.last_step,
        "vertex_solves": outcome.last_step * (nodes as u64).div_ceil(2),
        "newton_iterations_per_vertex": outcome.iterations as f64 / (outcome.last_step.max(1) * (nodes as u64).div_ceil(2)) as f64,
        "ends": [end_name(&setup.ends.start), end_name(&setup.ends.end)],
        "quadrature": if setup.symmetric { "symmetric" } else { "vertex" },
        "varying_material": setup.profile.is_some(),
        "bending_locking_number": setup.locking,
        "shear_frame": crate::rod::shear_frame_name(setup.shear_frame),
        "bending_stiffening_estimate": if setup.shear_frame == ShearFrame::Vertex {
            json!(BendingError::at(setup.locking).stiffening)
        } else {
            json!(null)
        },
        "mass": setup.mass,
        "energy_initial": obs.energy0,
        "energy_min": obs.energy_range[0],
        "energy_max": obs.energy_range[1],
        "el_residual_max": obs.el_residual_max,
        "linear_momentum_balance_error": if free { json!(obs.balance_error[0]) } else { json!(null) },
        "angular_momentum_balance_error": if free { json!(obs.balance_error[1]) } else { json!(null) },
    });
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
            draw_rod(&dir, nodes, rows_out, &s.output.plot_format)
        }),
        || {
            let balance = if free {
                format!(
                    ", momentum balance error {:.1e} (linear), {:.1e} (angular)",
                    obs.balance_error[0], obs.balance_error[1]
                )
            } else {
                String::new()
            };
            format!(
                "cosserat-rod, {nodes} nodes: {} time steps of {:e} to t = {t_final}{balance}",
                outcome.last_step / 2,
                setup.dt,
            )
        },
    )
}

/// Centreline snapshots (x–z and y–z), the centreline animation
/// (`centerline.gif`), momentum changes and energy, read back from the files.
pub fn draw_rod(dir: &Path, nodes: usize, rows: u64, format: &str) -> Result<(), CliError> {
    crate::centerline::draw_centerline_figures(
        dir,
        ("centerline", 3),
        (nodes, rows),
        |r, p| [r[3 * p], r[3 * p + 1], r[3 * p + 2]],
        ("t", format),
    )?;
    let momentum = Table::read_csv(&dir.join("momentum.csv"))?;
    crate::figures::draw_changes(
        &dir.join(format!("momentum.{format}")),
        &momentum,
        "t",
        &["P_x", "P_y", "P_z", "L_x", "L_y", "L_z"],
        ("Momenta: change since the start", "P(t) − P(0), L(t) − L(0)"),
    )?;
    let energy = Table::read_csv(&dir.join("energy.csv"))?;
    if let (Some(t), Some(e)) = (energy.column("t"), energy.column("energy")) {
        crate::figures::draw_curves(
            &dir.join(format!("energy.{format}")),
            ("Energy (kinetic + elastic + potential)", "time t", "E"),
            &[("energy".to_string(), t, e)],
            false,
        )?;
    }
    Ok(())
}
