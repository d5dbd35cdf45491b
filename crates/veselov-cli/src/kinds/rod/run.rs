//! The run of a Cosserat-rod scenario ([`super::setup`]) on the shared
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
//! summary reports the largest balance error. With one end held (clamped or
//! driven) the same balance gives the support's impulse, I_R = ΔP − I_loads,
//! whose rate over the last time step is the reaction reported
//! (`reaction_force`, `reaction_moment` about the support point); with both
//! ends held the balance gives only the sum of the two reactions, and none
//! is reported. A held rod's summary also has its tip's displacement and
//! rotation (the free end of a cantilever) and its largest deflection, from
//! the first and last rows of `centerline.npy` and `frames.npy`
//! (`ShapeChange`).
//! `el_residual_max` in the summary is the largest residual of the discrete
//! Euler–Lagrange equations of the run (each vertex equation at its accepted
//! values, relative to the size of its terms).

use std::path::Path;

use serde_json::json;
use veselov::field::CauchyStepper;
use veselov::field::cauchy::CauchyMarcher;
use veselov::field::cell::DiscreteLagrangian;
use veselov::field::discretize::{CfkNodes, VertexRule};
use veselov::field::fibre::PositionRotation;
use veselov::models::rod::{BendingError, EndCondition};
use veselov::models::rod::{CosseratCell, CosseratDensity, ShearFrame, Weight};
use veselov::run::{Checkpoint, Outcome, Status, StopWhen};

use super::figures::draw_rod;
use super::initial::FIRST_CUT;
use super::observer::{Cell, Rod, RodObserver};
use super::schema::LONG_RUN_STEP_NUMBER;
use super::setup::{RodSetup, shear_frame_name, step_number_text};
use crate::centerline::{Reaction, ShapeChange, centerline_stream, single_support};
use crate::error::CliError;
use crate::output::{approx, number};
use crate::pipeline::finish::{Ending, close_run};
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{CSV_BYTES_PER_VALUE, Plan, Resumed, RunJob, Session, open_lattice_run};
use crate::verdict::{Conserved, ENERGY_ERROR_FIELDS, EnergyCheck, StepAdvice, Verdict};

/// The rod with Q_sym (`[method] quadrature = "symmetric"`): the core's
/// generic discretisation of the same density, marched by the 6-D Newton.
type SymmetricCell = VertexRule<PositionRotation, CosseratDensity<Weight>, CfkNodes<2>, 6, 2>;

/// The shortfall of static bending deflections, estimated from shear
/// locking (`models::rod::resolution`), above which a run warns: 5 %.
const BENDING_ERROR_WARNING: f64 = 0.05;

/// The warnings of a rod's setup, shown now (`--quiet` or not: each is a
/// run expected to blow up or to lose accuracy silently), and the energy
/// check at its end when the rod is conservative (no damping, end load or
/// driven end).
fn verdict_of(setup: &RodSetup) -> Result<Verdict, CliError> {
    let lattice = &setup.lattice;
    let mut verdict = Verdict::default();
    if setup.courant > 1.0 {
        verdict.warn(
            "beyond_stability_limit",
            format!(
                "dt = {} exceeds the stability limit {} (step number {}); running because [method] \
                 allow_unstable = true",
                number(setup.dt),
                number(setup.dt_limit),
                step_number_text(setup.courant)
            ),
        );
    }
    // Stable by the linear limit, but close to it a long run can still grow
    // (README, "the step limit").
    if setup.courant > LONG_RUN_STEP_NUMBER && setup.courant <= 1.0 {
        verdict.warn(
            "near_stability_limit",
            format!(
                "step number {} is above {}: close to the stability limit, and sooner for large motions, a \
                 long run can still grow (the tumbling rod example failed after 3,405 steps at 0.95); lower \
                 dt or step_number for long runs",
                step_number_text(setup.courant),
                LONG_RUN_STEP_NUMBER
            ),
        );
    }
    let (locking, nodes_advised) = (setup.locking, setup.nodes_for_bending);
    let bending = BendingError::at(locking);
    if setup.shear_frame == ShearFrame::Vertex && bending.deflection_deficit() > BENDING_ERROR_WARNING {
        verdict.warn(
            "shear_locking",
            format!(
                "bending is coarsely resolved: with material points {} apart the lattice's shear locking \
                 number κGA·δ²/EI is {locking:.3}, so the rod bends as if about {:.0} % stiffer (static \
                 bending deflections about {:.0} % short, bending frequencies about {:.0} % high); nodes = \
                 {nodes_advised} or more bring it to about 1 %, or [method] shear_frame = \"centred\" removes \
                 the locking",
                approx(lattice.spacing()),
                100.0 * bending.stiffening,
                100.0 * bending.deflection_deficit(),
                100.0 * bending.frequency_excess()
            ),
        );
    }
    let driven = |e: &EndCondition| matches!(e, EndCondition::Driven(_));
    let conservative = setup.loads.is_none() && !driven(&setup.ends.start) && !driven(&setup.ends.end);
    let limit = setup.scenario.checks.energy_limit(&setup.path, ENERGY_ERROR_FIELDS)?;
    verdict.energy = conservative.then_some(EnergyCheck {
        conserved: Conserved::EnergyRange,
        limit,
        advice: match setup.scenario.time.dt {
            Some(_) => StepAdvice {
                key: "time.dt",
                value: setup.dt,
                order: 2,
                also: "more `model.nodes` if the space step dominates the error",
            },
            None => StepAdvice {
                key: "time.step_number",
                value: setup.courant,
                order: 2,
                also: "more `model.nodes` if the space step dominates the error",
            },
        },
    });
    Ok(verdict)
}

/// Run a rod scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let setup = RodSetup::parse(path, text)?;
    let lattice = &setup.lattice;
    if let Some(requested) = setup.dt_requested
        && (requested - setup.dt).abs() > 1e-12 * requested
        && !job.quiet
    {
        eprintln!(
            "note: dt = {} adjusted to {} = 2·t_end/{} so that the run ends at t_end (levels are half a step \
             apart)",
            number(requested),
            number(setup.dt),
            setup.half_steps
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
    let nodes = setup.lattice.nodes();
    let (mut session, resumed, mut obs) = open_observer(setup, &job, lag)?;
    let dir = session.dir.clone();
    let mut state = marcher;
    // The driver's step 0 is the first cut; its clock reads 0 at the
    // initial motion's level (the first cut, or level 0 for expressions).
    let mut stepper = CauchyStepper::<PositionRotation, L, 6>::new(0.5 * setup.dt, setup.initial.level_at_zero());
    let (first, start) = match &resumed {
        Some(r) => (r.restore_run(&dir, |w| obs.restore(w), &mut state)?, Ok(())),
        None => {
            let t = setup.time_at(state.level());
            (0, obs.record(&state, t))
        }
    };
    let outcome = session.execute(
        start,
        &mut stepper,
        &mut state,
        first,
        StopWhen::steps(setup.levels),
        &mut obs,
    )?;
    if !outcome.last_step.is_multiple_of(obs.every_levels) && matches!(outcome.status, Status::Completed) {
        let t = setup.time_at(state.level());
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
    let t_final = setup.time_at(state.level());
    let free = setup.ends.start.is_free() && setup.ends.end.is_free();
    let reaction = obs.reaction();
    let own = summary(setup, &outcome, &obs, reaction.as_ref());
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
                    ", momentum balance error {} (linear), {} (angular)",
                    approx(obs.balance_error[0]),
                    approx(obs.balance_error[1])
                )
            } else {
                String::new()
            };
            format!(
                "cosserat-rod, {nodes} nodes: {} of {} to t = {}{balance}{}{}",
                time_steps(outcome.last_step),
                number(setup.dt),
                number(t_final),
                obs.shape.report(),
                Reaction::report(reaction.as_ref()),
            )
        },
    )
}

/// The session of the run (planned from the rows and their size), the
/// checkpoint it resumes from, if any, and the observer writing the rows
/// (`lag`: Prop. 6.5's cell with the run's shear frame, for the energy).
fn open_observer<'a>(
    setup: &'a RodSetup,
    job: &RunJob,
    lag: Cell,
) -> Result<(Session, Option<Resumed<4>>, RodObserver<'a>), CliError> {
    let s = &setup.scenario;
    let lattice = &setup.lattice;
    let nodes = lattice.nodes();
    let rows = setup.levels / (2 * setup.every) + 2;
    let plan = Plan {
        steps: setup.levels as f64,
        levels_per_step: 2,
        given_steps: 0,
        steps_key: "time.t_end",
        bytes: rows as f64 * (nodes as f64 * 12.0 * 8.0 + 9.0 * CSV_BYTES_PER_VALUE),
        bytes_key: "output.every",
        unit: "time steps",
        step: Some(setup.dt),
        t_end: None,
    };
    let verdict = verdict_of(setup)?;
    let (session, resumed) = open_lattice_run::<4>(
        &setup.path,
        job,
        (s.output.dir.clone(), &plan),
        s.output.checkpoint_every.saturating_mul(2),
        "cosserat-rod",
        verdict,
    )?;
    let dir = session.dir.clone();
    let at = Resumed::positions(&resumed);
    let names = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let held = [!setup.ends.start.is_free(), !setup.ends.end.is_free()];
    let obs = RodObserver {
        setup,
        lag,
        every_levels: 2 * setup.every,
        centerline: centerline_stream(&dir, nodes, rows, at[0])?,
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
        shape: ShapeChange::new(
            (0..nodes)
                .map(|k| lattice.length() * k as f64 / (nodes - 1) as f64)
                .collect(),
            held,
        ),
        support: single_support(held),
        support_before: [f64::NAN; 7],
        support_last: [f64::NAN; 7],
        error: None,
        buffer: Vec::with_capacity(nodes * 12),
        before: Vec::with_capacity(nodes),
    };
    Ok((session, resumed, obs))
}

/// The kind's own keys of `summary.json`, with those of a held rod's shape
/// and support ([`ShapeChange::keys`], [`Reaction::keys`]).
fn summary(
    setup: &RodSetup,
    outcome: &Outcome,
    obs: &RodObserver<'_>,
    reaction: Option<&Reaction>,
) -> serde_json::Value {
    let s = &setup.scenario;
    let lattice = &setup.lattice;
    let nodes = lattice.nodes();
    let free = setup.ends.start.is_free() && setup.ends.end.is_free();
    let mut own = json!({
        "scenario": setup.path.display().to_string(),
        "model": s.model.name,
        "nodes": nodes,
        "length": lattice.length(),
        "ds": lattice.ds(),
        "dt": setup.dt,
        "dt_requested": setup.dt_requested,
        "dt_stability_limit": setup.dt_limit,
        "step_number": setup.courant,
        "t_start": setup.time_at(FIRST_CUT),
        "time_steps": outcome.last_step / 2,
        "levels": outcome.last_step,
        "vertex_solves": outcome.last_step * (nodes as u64).div_ceil(2),
        "newton_iterations_per_vertex": outcome.iterations as f64 / (outcome.last_step.max(1) * (nodes as u64).div_ceil(2)) as f64,
        "ends": [end_name(&setup.ends.start), end_name(&setup.ends.end)],
        "quadrature": if setup.symmetric { "symmetric" } else { "vertex" },
        "varying_material": setup.profile.is_some(),
        "bending_locking_number": setup.locking,
        "shear_frame": shear_frame_name(setup.shear_frame),
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
    if let Some(own) = own.as_object_mut() {
        own.extend(obs.shape.keys());
        own.extend(Reaction::keys(reaction));
    }
    own
}

/// The time steps of `levels` levels, two per step: "80 time steps", or
/// "79.5 time steps" when the run ends half a step after a whole one.
fn time_steps(levels: u64) -> String {
    if levels.is_multiple_of(2) {
        crate::output::count(levels / 2, "time step", "time steps")
    } else {
        format!("{} time steps", levels as f64 / 2.0)
    }
}

fn end_name(e: &EndCondition) -> &'static str {
    match e {
        EndCondition::Free => "free",
        EndCondition::Clamped(_) => "clamped",
        EndCondition::Driven(_) => "driven",
    }
}
