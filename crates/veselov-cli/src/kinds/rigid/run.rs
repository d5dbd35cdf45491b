//! `veselov run` for rigid-body scenarios: the Lie-group integrator with the
//! chosen retraction on the run pipeline ([`crate::pipeline`]), streaming
//! `trajectory.csv`/`.npy` and writing `summary.json` and the plots.

use serde_json::json;
use veselov::lgvi::GroupStepper;
use veselov::lgvi::{GroupState, GroupStepMap, SplitLieIntegrator, SplitReducedLagrangian, energy, spatial_momentum};
use veselov::lie::{CayleyMap, ExpMap, GroupFamily, Retraction};

use super::RigidJob;
use super::schema::LoadedRigid;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::pipeline::finish::{finish, open_table_session, start_or_resume, t_of, totals};
use crate::pipeline::stream::TableSink;
use crate::pipeline::summary;
use crate::pipeline::table::{Acc, TableObserver};
use crate::scenario::{note_step_length, planned_steps, step_count, step_length};
use crate::verdict::{Conserved, ENERGY_ERROR_MECHANICS, EnergyCheck, StepAdvice};

impl RigidJob for RunJob {
    fn go<G, L, const N: usize>(
        self,
        loaded: &LoadedRigid,
        l: L,
        x0: GroupState<G, N>,
        conserved: &[(&str, usize)],
        retraction: &str,
    ) -> Result<(), CliError>
    where
        G: GroupFamily<N>,
        ExpMap: Retraction<N, Family = G>,
        CayleyMap: Retraction<N, Family = G>,
        L: SplitReducedLagrangian<G, N> + Clone,
    {
        run_with_retraction(loaded, self, l, x0, conserved, retraction)
    }
}

/// Run the body `l` from `x0` with the integrator of `retraction`.
fn run_with_retraction<G, L, const N: usize>(
    loaded: &LoadedRigid,
    job: RunJob,
    l: L,
    x0: GroupState<G, N>,
    conserved: &[(&str, usize)],
    retraction: &str,
) -> Result<(), CliError>
where
    G: GroupFamily<N>,
    ExpMap: Retraction<N, Family = G>,
    CayleyMap: Retraction<N, Family = G>,
    L: SplitReducedLagrangian<G, N> + Clone,
{
    let dt = step_length(&loaded.scenario.time, loaded.scenario.method.dt);
    note_step_length(loaded.scenario.method.dt, dt, job.quiet);
    let setup = |e: veselov::Error| CliError::Setup(e.to_string());
    if retraction == "exp" {
        let map = SplitLieIntegrator::<G, ExpMap, L, N>::new(l.clone(), dt).map_err(setup)?;
        run_map(
            loaded,
            job,
            &l,
            map,
            x0,
            conserved,
            "lie-group trapezoid, exp retraction",
        )
    } else {
        let map = SplitLieIntegrator::<G, CayleyMap, L, N>::new(l.clone(), dt).map_err(setup)?;
        run_map(
            loaded,
            job,
            &l,
            map,
            x0,
            conserved,
            "lie-group trapezoid, Cayley retraction",
        )
    }
}

/// `t, R00..R22, [x0..x2], Pi0..Pi2, [P0..P2], energy, pi_x..pi_z (spatial), J_.., orthogonality_defect`.
fn header_of<const N: usize>(conserved: &[(&str, usize)]) -> Vec<String> {
    let mut header = vec!["t".to_string()];
    header.extend((0..3).flat_map(|i| (0..3).map(move |j| format!("R{i}{j}"))));
    if N == 6 {
        header.extend((0..3).map(|i| format!("x{i}")));
    }
    header.extend((0..3).map(|i| format!("Pi{i}")));
    if N == 6 {
        header.extend((0..3).map(|i| format!("P{i}")));
    }
    header.push("energy".into());
    let axes = ["x", "y", "z"];
    header.extend(axes.iter().map(|a| format!("pi_{a}")));
    if N == 6 {
        header.extend(axes.iter().map(|a| format!("p_{a}")));
    }
    header.extend(conserved.iter().map(|(name, _)| name.to_string()));
    header.push("orthogonality_defect".into());
    header
}

/// The row of `x` under [`header_of`].
fn row_of<G, L, const N: usize>(l: &L, x: &GroupState<G, N>, conserved: &[(&str, usize)]) -> Vec<f64>
where
    G: GroupFamily<N>,
    L: SplitReducedLagrangian<G, N>,
{
    let mut row = vec![x.t];
    let r = G::rotation(&x.g);
    row.extend((0..3).flat_map(|i| (0..3).map(move |j| r[(i, j)])));
    if N == 6 {
        row.extend(G::translation(&x.g).iter());
    }
    row.extend(x.mu.iter());
    row.push(energy(l, x).unwrap_or(f64::NAN));
    let spatial = spatial_momentum(x);
    row.extend(spatial.iter());
    row.extend(conserved.iter().map(|(_, k)| spatial[*k]));
    row.push(G::orthogonality_defect(&x.g));
    row
}

fn run_map<G, L, M, const N: usize>(
    loaded: &LoadedRigid,
    job: RunJob,
    l: &L,
    mut map: M,
    x0: GroupState<G, N>,
    conserved: &[(&str, usize)],
    method: &str,
) -> Result<(), CliError>
where
    G: GroupFamily<N>,
    L: SplitReducedLagrangian<G, N>,
    M: GroupStepMap<G, N>,
{
    x0.check().map_err(|e| loaded.key_error("initial", e.to_string()))?;
    let s = &loaded.scenario;
    let (steps, dt) = (step_count(&s.time, s.method.dt), step_length(&s.time, s.method.dt));
    // Checked before the session opens its output directory.
    let at_steps = s.output.steps_at_times(&loaded.path, x0.t, dt, steps, job.quiet)?;
    let header = header_of::<N>(conserved);
    let limit = loaded
        .scenario
        .checks
        .energy_limit(&loaded.path, ENERGY_ERROR_MECHANICS)?;
    let (mut session, positions, words) = open_table_session(
        &job,
        &loaded.path,
        (&s.time, &s.output),
        (planned_steps(&s.time, s.method.dt), Some(dt)),
        header.len(),
        "rigid-body",
    )?;
    let sink = TableSink::create(
        &session.dir,
        "trajectory",
        &header,
        &s.output.formats,
        steps / s.output.every + 2,
        positions,
    )?;
    let mut table = TableObserver::new(
        header,
        Box::new(move |x: &GroupState<G, N>, _| row_of(l, x, conserved)),
        sink,
        s.output.every,
    )
    .at_steps(at_steps);
    table.track("energy", Acc::Dev);
    for (name, _) in conserved {
        table.track(name, Acc::Dev);
    }
    table.track("orthogonality_defect", Acc::Max);
    session.verdict.energy = Some(EnergyCheck {
        conserved: Conserved::Energy,
        limit,
        advice: StepAdvice {
            key: "method.dt",
            value: dt,
            order: 2,
            also: "",
        },
    });
    let mut stepper = GroupStepper::new(&mut map, x0.t);
    let mut x = x0;
    let outcome = start_or_resume(&mut session, &mut stepper, &mut x, &mut table, &words, steps)?;
    let iterations = totals(&outcome).iterations;
    let wall = session.wall_seconds();
    let t_final = t_of(outcome.last_step, x0.t, dt);
    let orthogonality =
        |t: &TableObserver<'_, GroupState<G, N>>| t.column("orthogonality_defect").map_or(0.0, |c| c.value.max(0.0));
    finish(
        &s.output,
        &session,
        table,
        outcome.status.clone(),
        |t, status| {
            let momentum_errors: serde_json::Map<String, serde_json::Value> = conserved
                .iter()
                .map(|(name, _)| (name.to_string(), json!(t.column(name).map_or(0.0, |c| c.value))))
                .collect();
            let energy = t.column("energy");
            let own = json!({
                "scenario": loaded.path.display().to_string(),
                "model": s.model.name,
                "method": method,
                "retraction": s.method.retraction,
                "order": 2,
                "dt": dt,
                "steps_requested": steps,
                "energy_initial": energy.map(|c| c.first),
                "energy_error_max": energy.map_or(0.0, |c| c.value),
                "energy_error_max_relative": energy
                    .map_or(serde_json::Value::Null, |c| summary::relative_energy_error(c.value, c.first)),
                "momentum_error_max": momentum_errors,
                "orthogonality_defect_max": orthogonality(t),
            });
            summary::common(status, (outcome.last_step, 1), t_final, wall, iterations, own)
        },
        |t| {
            format!(
                "{method}: {} to t = {}, max |E − E₀| = {}, max |RᵀR − I| = {}",
                crate::output::count(outcome.last_step, "step", "steps"),
                crate::output::number(t_final),
                crate::output::approx(t.column("energy").map_or(0.0, |c| c.value)),
                crate::output::approx(orthogonality(t))
            )
        },
    )
}
