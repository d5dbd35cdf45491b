//! The run of a beam scenario ([`super::setup`]) on the shared pipeline:
//! seed 000's multisymplectic Lie-group integrator marching in time (level
//! ℓ = time node j, t = ℓΔt, across the beam's nodes a) or in space (level
//! ℓ = column a, s = ℓΔs, across the time nodes j), one row of every
//! output per `every` levels.
//!
//! Outputs: `frames.npy` (rows × cross nodes × 12: R row by row, then the
//! position), `centerline.npy` in time evolution (rows × nodes × 3: the
//! positions, the rod's layout), `momentum.csv` (level, t or s, then the six components of the
//! evolution momentum map 𝖩⁺ of the cell level below — 𝖩_𝖫 in time, 𝖩_𝖭 in
//! space — angular first), `energy.csv` (level, t or s, E_𝖫 = Δs Σ e_𝖫 or
//! E_𝖭 = Δt Σ e_𝖭), `summary.json` (with the largest change of 𝖩⁺ relative
//! to the size of its terms; for a beam clamped at one end the tip's
//! displacement and rotation, the largest deflection and the reaction of
//! the support, `ShapeChange` and
//! `SupportImpulse`), plots of the centreline, the
//! momentum map and the energy.

use std::path::Path;

use serde_json::json;
use veselov::evolution::marcher::{Direction, EndCondition, EvolutionStepper};
use veselov::evolution::split::KineticQuadrature;
use veselov::field::fibre::RigidMotions;
use veselov::lie::{CayleyMap, ExpMap, Retraction, SE3};
use veselov::models::beam::{BeamDensity, BeamLagrangian, beam_lagrangian};
use veselov::run::{Outcome, Status, StopWhen};

use super::band::{band, held_value};
use super::figures::draw_beam;
use super::observer::{Beam, BeamObserver, DomainCurrent, SupportImpulse};
use super::setup::{BeamEnd, BeamSetup};
use crate::centerline::{Reaction, ShapeChange, centerline_stream, single_support};
use crate::error::CliError;
use crate::pipeline::finish::{Ending, close_run};
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{CSV_BYTES_PER_VALUE, Plan, Resumed, RunJob, Session, open_lattice_run};
use crate::verdict::{Conserved, ENERGY_ERROR_FIELDS, EnergyCheck, StepAdvice, Verdict};

/// Run a beam scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let setup = BeamSetup::parse(path, text)?;
    if setup.cayley {
        march::<CayleyMap>(&setup, job)
    } else {
        march::<ExpMap>(&setup, job)
    }
}

fn march<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
    setup: &BeamSetup,
    job: RunJob,
) -> Result<(), CliError> {
    let s = &setup.scenario;
    if let Some(requested) = setup.dt_requested
        && (requested - setup.dt).abs() > 1e-12 * requested
        && !job.quiet
    {
        eprintln!(
            "note: dt = {} adjusted to {} = t_end/{} so that the run ends at t_end",
            crate::output::number(requested),
            crate::output::number(setup.dt),
            setup.levels
        );
    }
    let (evolution, cross) = start_evolution::<R>(setup)?;
    let (mut session, resumed, mut obs) = open_observer(setup, &job, cross)?;
    let dir = session.dir.clone();
    let x = if setup.space { "s" } else { "t" };
    let mut state = evolution;
    let step_length = if setup.space { setup.ds } else { setup.dt };
    let mut stepper =
        EvolutionStepper::<RigidMotions, BeamLagrangian<R>, 6>::new(step_length).with_origin(setup.level_origin());
    let (first_step, start) = match &resumed {
        Some(r) => (r.restore_run(&dir, |w| obs.restore(w), &mut state)?, Ok(())),
        None => {
            obs.domain.add_band(&state);
            obs.support.add_band(&state);
            // Space evolution: the first given column too (in time evolution
            // the first level recorded is t = 0).
            let first = if setup.space {
                obs.record_previous(&state)
            } else {
                Ok(())
            };
            (0, first.and_then(|()| obs.record(&state)))
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
    if let Some(c) = &mut obs.centerline {
        c.position()?;
    }
    let rows_out = obs.momentum.position()?.rows;
    let level = state.level();
    // The clamped node's equation is complete one level below the last.
    let support_node = |end: usize| if end == 0 { 0 } else { cross - 1 };
    let reaction = obs.support.end.and_then(|end| {
        let at = obs.shape.last_point(support_node(end));
        match outcome.status {
            Status::Completed => obs.support.reaction(level.saturating_sub(1), setup.dt, at),
            _ => None,
        }
    });
    let own = summary(setup, &outcome, (level, cross), &obs, reaction.as_ref());
    let t_final = setup.coordinate(level);
    let ending = Ending {
        status: outcome.status,
        // Time steps from t = 0 (the second given level), or space steps
        // from the first column.
        steps: setup.steps_at(level),
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
                "beam, {} evolution: {} to {x} = {}, max change of the momentum map {} of its terms{}{}",
                if setup.space { "space" } else { "time" },
                if setup.space {
                    crate::output::count(setup.steps_at(level), "space step", "space steps")
                } else {
                    crate::output::count(setup.steps_at(level), "time step", "time steps")
                },
                crate::output::number(t_final),
                crate::output::approx(obs.drift),
                obs.shape.report(),
                Reaction::report(reaction.as_ref()),
            )
        },
    )
}

/// The evolution of the scenario's beam from its first two levels, with
/// its ends held or free, and the number of nodes across a level. Time
/// evolution takes the trapezoid rule in s, its free end an ordinary node
/// of the end cell ([`KineticQuadrature::Trapezoid`]), with level ℓ at
/// t = (ℓ − 1)Δt; space evolution seed 000's rule.
fn start_evolution<R: Retraction<6, Family = veselov::lie::RigidMotions> + 'static>(
    setup: &BeamSetup,
) -> Result<(Beam<R>, usize), CliError> {
    let density = BeamDensity::new(setup.properties)
        .with_damping(setup.damping)
        .map_err(|e| setup.key("loads.damping", e.to_string()))?
        .with_gravity(setup.gravity)
        .with_end_load(setup.end_load)
        .map_err(|e| setup.key("loads", e.to_string()))?;
    let mut lag = beam_lagrangian::<R>(density, setup.dt, setup.ds).map_err(|e| setup.key("model", e.to_string()))?;
    let nodes = setup.scenario.model.nodes;
    if !setup.space {
        lag = lag
            .with_quadrature(KineticQuadrature::Trapezoid { last: nodes - 1 })
            .with_time_origin(-setup.dt);
    }
    let (first, second) = band::<R>(setup, &lag)?;
    let dt = setup.dt;
    let end = |which: usize, rest: SE3<f64>| -> EndCondition<SE3<f64>> {
        match &setup.ends[which] {
            BeamEnd::Free if which == 1 && !setup.space => EndCondition::EndCell,
            BeamEnd::Free => EndCondition::Natural,
            BeamEnd::Clamped => EndCondition::Prescribed(Box::new(move |_| rest)),
            held => {
                let held = held.clone();
                EndCondition::Prescribed(Box::new(move |level| {
                    held_value(&held, &rest, (level as f64 - 1.0) * dt).unwrap_or(rest)
                }))
            }
        }
    };
    let last = second.len() - 1;
    let direction = if setup.space { Direction::Space } else { Direction::Time };
    let evolution = Beam::<R>::new(
        direction,
        lag,
        &first,
        &second,
        end(0, second[0]),
        end(1, second[last]),
        setup.options,
    )
    .map_err(|e| setup.key("initial", e.to_string()))?;
    let cross = last + 1;
    Ok((evolution, cross))
}

/// The session of the run (planned from the rows and their size), the
/// checkpoint it resumes from, if any, and the observer writing the rows
/// of `cross` nodes.
fn open_observer<'a>(
    setup: &'a BeamSetup,
    job: &RunJob,
    cross: usize,
) -> Result<(Session, Option<Resumed<4>>, BeamObserver<'a>), CliError> {
    let s = &setup.scenario;
    let rows = setup.levels / setup.every + 3;
    let plan = Plan {
        steps: setup.levels as f64,
        steps_key: "time.t_end",
        bytes: rows as f64 * (cross as f64 * 15.0 * 8.0 + 17.0 * CSV_BYTES_PER_VALUE),
        bytes_key: "output.every",
        levels_per_step: 1,
        // Space evolution: the stepper counts from the second given column;
        // time evolution from t = 0.
        given_steps: u64::from(setup.space),
        unit: if setup.space { "space steps" } else { "time steps" },
        step: Some(setup.dt),
        t_end: None,
    };
    let mut verdict = Verdict::default();
    if let Some(reason) = &setup.unstable {
        verdict.warn(
            "beyond_stability_limit",
            format!("{reason}; running because [method] allow_unstable = true"),
        );
    }
    // A time evolution without damping, end load or driven end conserves
    // the energy; a space evolution marches in s, where the energy is no
    // invariant.
    let limit = s.checks.energy_limit(&setup.path, ENERGY_ERROR_FIELDS)?;
    let conservative = setup.damping.iter().all(|d| *d == 0.0)
        && setup.end_load.is_zero()
        && !setup.ends.iter().any(|e| matches!(e, BeamEnd::Driven(_)));
    verdict.energy = (!setup.space && conservative).then_some(EnergyCheck {
        conserved: Conserved::EnergyRange,
        limit,
        advice: StepAdvice {
            key: "time.dt",
            value: setup.dt,
            order: 2,
            also: "more `model.nodes` if the space step dominates the error",
        },
    });
    let (session, resumed) = open_lattice_run::<4>(
        &setup.path,
        job,
        (s.output.dir.clone(), &plan),
        s.output.checkpoint_every,
        "beam",
        verdict,
    )?;
    let dir = session.dir.clone();
    let at = Resumed::positions(&resumed);
    let x = if setup.space { "s" } else { "t" };
    let names = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    // Space evolution marches across the time nodes: nothing is held.
    let held = if setup.space {
        [false; 2]
    } else {
        [setup.ends[0].is_clamped(), setup.ends[1].is_clamped()]
    };
    let obs = BeamObserver {
        setup,
        every: setup.every,
        frames: NpyStream::create(&dir.join("frames.npy"), &[cross, 12], rows, at[0])?,
        centerline: if setup.space {
            None
        } else {
            Some(centerline_stream(&dir, cross, rows, at[3])?)
        },
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
        line: Vec::with_capacity(cross * 3),
        shape: ShapeChange::new((0..cross).map(|a| a as f64 * setup.ds).collect(), held),
        support: SupportImpulse::new(single_support(held)),
        error: None,
    };
    Ok((session, resumed, obs))
}

/// The kind's own keys of `summary.json`: the run ended at `level`, with
/// `cross` nodes across a level; those of a held beam's shape and support
/// ([`ShapeChange::keys`], [`Reaction::keys`]).
fn summary(
    setup: &BeamSetup,
    outcome: &Outcome,
    (level, cross): (usize, usize),
    obs: &BeamObserver<'_>,
    reaction: Option<&Reaction>,
) -> serde_json::Value {
    let s = &setup.scenario;
    let mut own = json!({
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
        "levels": setup.steps_at(level),
        "node_solves": outcome.last_step * cross as u64,
        "newton_iterations_per_node": outcome.iterations as f64 / (outcome.last_step.max(1) * cross as u64) as f64,
        "ends": if setup.space { json!(["natural", "natural"]) } else {
            json!([setup.ends[0].name(), setup.ends[1].name()])
        },
        "kinetic_quadrature": if setup.space { "first-node" } else { "trapezoid" },
        "end_force": setup.end_load.force.as_slice(),
        "end_torque": setup.end_load.torque.as_slice(),
        "momentum_map_drift": obs.drift,
        "domain_current_max": obs.domain.worst,
        "energy_min": obs.energy_range[0],
        "energy_max": obs.energy_range[1],
    });
    if let Some(own) = own.as_object_mut() {
        own.extend(obs.shape.keys());
        own.extend(Reaction::keys(reaction));
    }
    own
}
