//! `veselov run` for CFK-lattice field scenarios: the initial levels of the
//! model's field, then the Cauchy march on the run pipeline, written by the
//! observer of [`super::observer`] (`energy.csv`, `momentum.csv`,
//! `snapshots.npy`, `snapshot_times.csv`, `summary.json`, the figures).

use std::f64::consts::TAU;
use std::path::Path;

use nalgebra::{SVector, Vector3};
use serde_json::json;
use veselov::complex::CfkTorus;
use veselov::field::CauchyStepper;
use veselov::field::cauchy::CauchyMarcher;
use veselov::field::discretize::{CfkNodes, MidpointRule, SmoothDensity};
use veselov::field::fibre::Euclidean;
use veselov::run::{Outcome, StopWhen};
use veselov::spacetime::{ComplexKleinGordon, NonlinearWave, Phi4, Potential, SineGordon, Wave};

use super::figures::{components, draw};
use super::observer::{CfkObserver, Generator, Marcher, Rule};
use super::schema::Setup;
use crate::error::CliError;
use crate::pipeline::finish::{Ending, close_run};
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{CSV_BYTES_PER_VALUE, Plan, Resumed, RunJob, Session, open_lattice_run};
use crate::scenario::{Array, finite_value, positive_value};
use crate::verdict::{Conserved, ENERGY_ERROR_FIELDS, EnergyCheck, StepAdvice, Verdict};

/// Run a CFK-lattice field scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let setup = Setup::parse(path, text)?;
    match setup.scenario.model.name.as_str() {
        "sine-gordon" => {
            setup.param("m2", 0.0, &[])?;
            // Linearised about φ = 0: N = cos φ ≈ 1 − φ²/2, mass 1.
            march::<SineGordon, 1>(&setup, &job, SineGordon, (1.0, 0.0), None)
        }
        "wave" => {
            setup.param("m2", 0.0, &[])?;
            march::<Wave, 1>(
                &setup,
                &job,
                Wave,
                (0.0, 0.0),
                Some(("shift_momentum", |_| SVector::from([1.0]))),
            )
        }
        "klein-gordon-phi4" => {
            let p = Phi4 {
                m2: setup.param("m2", 1.0, &["m2", "lambda"])?,
                lambda: setup.param("lambda", 1.0, &["m2", "lambda"])?,
            };
            march::<Phi4, 1>(&setup, &job, p, (p.m2, 0.0), None)
        }
        "klein-gordon-complex" => {
            let p = ComplexKleinGordon {
                m2: setup.param("m2", 1.0, &["m2", "lambda"])?,
                lambda: setup.param("lambda", 1.0, &["m2", "lambda"])?,
            };
            march::<ComplexKleinGordon, 2>(
                &setup,
                &job,
                p,
                (p.m2, p.lambda),
                Some(("phase_charge", |y| {
                    SVector::from_fn(|k, _| if k == 0 { -y[1] } else { y[0] })
                })),
            )
        }
        other => Err(setup.key("model.name", format!("unknown field model `{other}`"))),
    }
}

/// A field φ(x, y, t) with M components.
type InitialField<const M: usize> = Box<dyn Fn(&Vector3<f64>) -> SVector<f64, M>>;

/// The model's force ∇N(φ) (the field equation is φ_tt = Δφ + ∇N(φ)).
type Force<const M: usize> = Box<dyn Fn(&SVector<f64, M>) -> SVector<f64, M>>;

/// The initial field φ(x, y, t) of the scenario (M components); the waves
/// take their frequency from ω² = k² + m² (+ λA² for the complex plane
/// wave, which is then exact). The pulse starts at rest, its first Cauchy
/// levels (t ≤ 5Δt/3) from the Taylor expansion of the field equation,
///
/// φ(x, t) = g + ½t² (Δg + N′(g)) + O(t⁴),   Δg = g (r²/σ⁴ − 2/σ²),
///
/// so that the start keeps the march's second order.
fn initial<const M: usize>(
    setup: &Setup,
    (m2, lambda): (f64, f64),
    force: Force<M>,
) -> Result<InitialField<M>, CliError> {
    let i = &setup.scenario.initial;
    let (lx, ly) = (setup.nodes[0] as f64 * setup.dx, setup.nodes[1] as f64 * setup.dx);
    let amplitude = finite_value(&setup.path, "initial.amplitude", i.amplitude.unwrap_or(1.0))?;
    let mode = Array::or(&i.mode, &setup.path, "initial.mode", [1, 1])?;
    let (kx, ky) = (TAU * mode[0] as f64 / lx, TAU * mode[1] as f64 / ly);
    let complex = M == 2;
    match (i.kind.as_str(), complex) {
        ("pulse", false) => {
            let w = positive_value(&setup.path, "initial.width", i.width.unwrap_or(0.1 * lx.min(ly)))?;
            let (cx, cy) = (0.5 * lx, 0.5 * ly);
            Ok(Box::new(move |x| {
                let r2 = (x[0] - cx).powi(2) + (x[1] - cy).powi(2);
                let g = SVector::from_element(amplitude * (-0.5 * r2 / (w * w)).exp());
                let laplacian = g * (r2 / w.powi(4) - 2.0 / (w * w));
                g + (laplacian + force(&g)) * (0.5 * x[2] * x[2])
            }))
        }
        ("standing-wave", false) => {
            let omega = (kx * kx + ky * ky + m2).max(0.0).sqrt();
            Ok(Box::new(move |x| SVector::from_element(amplitude * (kx * x[0]).cos() * (ky * x[1]).sin() * (omega * x[2]).cos())))
        }
        ("plane-wave", true) => {
            let omega = (kx * kx + ky * ky + m2 + lambda * amplitude * amplitude).max(0.0).sqrt();
            Ok(Box::new(move |x| {
                let phase = kx * x[0] + ky * x[1] - omega * x[2];
                SVector::from_fn(|k, _| amplitude * if k == 0 { phase.cos() } else { phase.sin() })
            }))
        }
        (kind, _) => Err(setup.key(
            "initial.kind",
            format!(
                "`{kind}` is not initial data for `{}` (scalar fields: pulse, standing-wave; the complex field: plane-wave)",
                setup.scenario.model.name
            ),
        )),
    }
}

fn march<P: Potential<M> + Copy + 'static, const M: usize>(
    setup: &Setup,
    job: &RunJob,
    potential: P,
    dispersion: (f64, f64),
    symmetry: Option<(&'static str, Generator<M>)>,
) -> Result<(), CliError>
where
    NonlinearWave<P>: SmoothDensity<Euclidean<M>, M, 3>,
{
    let s = &setup.scenario;
    let (rule, torus, marcher) = start_march::<P, M>(setup, potential, dispersion)?;
    let steps = setup.steps();
    let (mut session, resumed, snapshots) = open_session::<M>(setup, job)?;
    let dir = session.dir.clone();
    let mut header = vec!["t".to_string(), "p_x".to_string(), "p_y".to_string()];
    header.extend(symmetry.map(|(name, _)| name.to_string()));
    let tail = if M == 1 {
        vec![setup.nodes[0], setup.nodes[1]]
    } else {
        vec![setup.nodes[0], setup.nodes[1], M]
    };
    let at = Resumed::positions(&resumed);
    let mut obs = CfkObserver {
        rule,
        torus,
        dt: setup.dt,
        symmetry,
        snapshot_every: s.output.snapshot_every,
        energy: CsvStream::create(&dir.join("energy.csv"), &["t".into(), "energy".into()], at[0])?,
        momentum: CsvStream::create(&dir.join("momentum.csv"), &header, at[1])?,
        snapshots: NpyStream::create(&dir.join("snapshots.npy"), &tail, snapshots as u64, at[2])?,
        times: CsvStream::create(&dir.join("snapshot_times.csv"), &["t".to_string()], at[3])?,
        energy0: f64::NAN,
        energy_error_max: 0.0,
        charge0: f64::NAN,
        charge_error_max: 0.0,
        last_snapshot: None,
        error: None,
    };
    let mut state = marcher;
    let mut stepper = CauchyStepper::<Euclidean<M>, Rule<P>, M>::new(setup.dt / 3.0, 3);
    let (first, start) = match &resumed {
        Some(r) => (r.restore_run(&dir, |w| obs.restore(w), &mut state)?, Ok(())),
        None => (0, obs.record(&state, 0)),
    };
    let outcome = session.execute(
        start,
        &mut stepper,
        &mut state,
        first,
        StopWhen::steps(3 * steps as u64),
        &mut obs,
    )?;
    let k_final = outcome.last_step / 3;
    if obs.last_snapshot != Some(k_final) {
        obs.snapshot(&state, k_final);
    }
    obs.energy.position()?;
    obs.momentum.position()?;
    obs.snapshots.position()?;
    let snapshot_rows = obs.times.position()?.rows;
    let t_final = k_final as f64 * setup.dt;
    let own = summary(setup, &outcome, k_final, &obs);
    let ending = Ending {
        status: outcome.status,
        steps: outcome.last_step,
        t_final,
        iterations: outcome.iterations,
    };
    let draw_field = || {
        draw(
            &dir,
            (setup.nodes, setup.dx),
            components(&s.model.name),
            snapshot_rows,
            &s.output.plot_format,
        )
    };
    close_run(
        &session,
        ending,
        own,
        obs.error.take(),
        (s.output.plots, draw_field),
        || {
            format!(
                "{} on a {}×{} CFK lattice: {} to t = {}, max |E − E₀| = {}",
                s.model.name,
                setup.nodes[0],
                setup.nodes[1],
                crate::output::count(k_final, "time step", "time steps"),
                crate::output::number(t_final),
                crate::output::approx(obs.energy_error_max),
            )
        },
    )
}

/// The rule of `potential` on the lattice, its torus, and the march from
/// the initial field of the scenario (its first six levels).
fn start_march<P: Potential<M> + Copy + 'static, const M: usize>(
    setup: &Setup,
    potential: P,
    dispersion: (f64, f64),
) -> Result<(Rule<P>, CfkTorus, Marcher<P, M>), CliError>
where
    NonlinearWave<P>: SmoothDensity<Euclidean<M>, M, 3>,
{
    let force = move |y: &SVector<f64, M>| veselov::spacetime::potential::potential_gradient(&potential, y);
    let field = initial::<M>(setup, dispersion, Box::new(force))?;
    let torus = CfkTorus::new(3, &setup.nodes).map_err(|e| setup.key("lattice.nodes", e.to_string()))?;
    let nodes = CfkNodes::<3>::space_time(setup.dx, setup.dt).map_err(|e| setup.key("lattice", e.to_string()))?;
    let data: Vec<Vec<SVector<f64, M>>> = (0..6)
        .map(|w| {
            (0..torus.level_size())
                .map(|i| field(&nodes.node(&torus.vertex(w, i))))
                .collect()
        })
        .collect();
    let rule = MidpointRule::new(NonlinearWave(potential), nodes);
    let marcher = CauchyMarcher::new(rule, torus.clone(), 0, &data, setup.options)
        .map_err(|e| setup.key("initial", e.to_string()))?;
    Ok((rule, torus, marcher))
}

/// The session of the run, planned from the lattice, the horizon and the
/// snapshots; the checkpoint it resumes from, if any; the snapshots planned.
fn open_session<const M: usize>(setup: &Setup, job: &RunJob) -> Result<(Session, Option<Resumed<4>>, f64), CliError> {
    let s = &setup.scenario;
    let steps = setup.steps();
    crate::scenario::note_lattice_end(setup.t_end, setup.dt, job.quiet);
    let cells = (setup.nodes[0] * setup.nodes[1] * M) as f64;
    let snapshots = match s.output.snapshot_every {
        0 => 2.0,
        k => steps / k as f64 + 2.0,
    };
    let plan = Plan {
        steps: 3.0 * steps,
        levels_per_step: 3,
        given_steps: 0,
        steps_key: "time.t_end",
        bytes: snapshots * cells * 8.0 + (steps + 1.0) * 7.0 * CSV_BYTES_PER_VALUE,
        bytes_key: "output.snapshot_every",
        unit: "time steps",
        step: Some(setup.dt),
        t_end: None,
    };
    let also = "more `lattice.nodes` (and a smaller `lattice.spacing`) if the space step dominates the error";
    let verdict = Verdict {
        warnings: Vec::new(),
        energy: Some(EnergyCheck {
            conserved: Conserved::Energy,
            limit: s.checks.energy_limit(&setup.path, ENERGY_ERROR_FIELDS)?,
            advice: StepAdvice::lattice(s.lattice.courant, setup.dt, also),
        }),
        ending: Vec::new(),
    };
    let (session, resumed) = open_lattice_run::<4>(
        &setup.path,
        job,
        (s.output.dir.clone(), &plan),
        s.output.checkpoint_every.saturating_mul(3),
        "cfk-field",
        verdict,
    )?;
    Ok((session, resumed, snapshots))
}

/// The kind's own keys of `summary.json`.
fn summary<P, const M: usize>(
    setup: &Setup,
    outcome: &Outcome,
    k_final: u64,
    obs: &CfkObserver<P, M>,
) -> serde_json::Value {
    let s = &setup.scenario;
    json!({
        "scenario": setup.path.display().to_string(),
        "model": s.model.name,
        "lattice": "cfk",
        "nodes": setup.nodes,
        "dx": setup.dx,
        "dt": setup.dt,
        "courant": setup.dt / setup.dx,
        "levels": outcome.last_step,
        "time_steps": k_final,
        "vertex_solves": outcome.last_step * (setup.nodes[0] * setup.nodes[1]) as u64,
        "newton_iterations_per_vertex": outcome.iterations as f64
            / (outcome.last_step.max(1) * (setup.nodes[0] * setup.nodes[1]) as u64) as f64,
        "energy_initial": obs.energy0,
        "energy_error_max": obs.energy_error_max,
        "energy_error_max_relative": crate::pipeline::summary::relative_energy_error(obs.energy_error_max, obs.energy0),
        "charges_error_max": match obs.symmetry {
            Some((name, _)) => json!({ name: obs.charge_error_max }),
            None => json!({}),
        },
    })
}
