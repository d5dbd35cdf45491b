//! `veselov run` for lattice-field scenarios: the lattice, the cell rule and
//! the initial levels built from the validated scenario, and the march on the
//! fast path (the scheme's own O(N) solver on a periodic lattice) or the
//! generic one (a cell Lagrangian, any boundary, the complex field), written
//! by the observer of [`super::observer`].

use std::path::Path;

use nalgebra::SVector;
use veselov::spacetime::{
    Boundary, CellEnergy, ComplexPlaneWave, Density, DensityStepper, FastLevels, FastMarcher, FastStepper,
    FieldRunConfig, Generator, GenericMarcher, Lattice, Levels, Model, NonlinearWave, Phi4, RectangleRule,
    ScalarPotential, Scheme, SineGordon, TriangleRule, Wave, level_energy, shift_charge, split_charge,
};

use super::observer::{Frame, march};
use super::schema::{FieldInitial, FieldModel, FieldScenario, LoadedField};
use crate::error::CliError;
use crate::pipeline::{CSV_BYTES_PER_VALUE, Plan, RunJob, Session};
use crate::scenario::output_dir;
use crate::verdict::{Conserved, ENERGY_ERROR_FIELDS, EnergyCheck, StepAdvice};

/// Run a lattice-field scenario.
pub fn run(path: &Path, text: &str, job: RunJob) -> Result<(), CliError> {
    let loaded = LoadedField::parse(path, text)?;
    let s = &loaded.scenario;
    let solver = loaded.solver()?;
    let model = loaded.model()?;
    let scheme = loaded.scheme()?;
    let mut lattice = loaded.lattice()?;
    let initial = loaded.initial(lattice.length())?;
    let t_end = loaded.positive("time.t_end", s.time.t_end)?;
    crate::scenario::note_lattice_end(t_end, lattice.dt(), job.quiet);
    let mut session = open_session(&loaded, &job, &lattice, t_end)?;
    let progress = &mut session;
    let initial_error = |e: veselov::Error| loaded.key_error("initial", e.to_string());
    match (model, initial) {
        (FieldModel::Scalar(model), FieldInitial::Scalar(data)) => {
            if lattice.is_periodic() {
                let config = FieldRunConfig {
                    model,
                    scheme,
                    lattice,
                    initial: data,
                    t_end,
                    snapshot_every: s.output.snapshot_every,
                    energy_block: 0,
                    keep_energies: true,
                    recentre_every: if model == Model::SineGordon { 1000 } else { 0 },
                    solver,
                };
                march_fast(&loaded, progress, &config)?
            } else {
                let (y0, y1) = data.levels(&lattice).map_err(initial_error)?;
                if let Boundary::Dirichlet { .. } = lattice.boundary() {
                    // Unless given, the end values are the initial ones.
                    let l = &s.lattice;
                    let n = y0.len();
                    let boundary = Boundary::Dirichlet {
                        left: l.left.unwrap_or(y0[0]),
                        right: l.right.unwrap_or(y0[n - 1]),
                    };
                    lattice = Lattice::new(lattice.nodes(), lattice.dx(), lattice.dt(), boundary)
                        .map_err(|e| loaded.key_error("lattice", e.to_string()))?;
                }
                let lift = |y: Vec<f64>| -> Vec<SVector<f64, 1>> { y.into_iter().map(SVector::from_element).collect() };
                let levels = (lift(y0), lift(y1));
                let shift = |_: &SVector<f64, 1>| SVector::<f64, 1>::from_element(1.0);
                // The shift y ↦ y + s is a symmetry of the wave equation that a
                // Dirichlet boundary breaks.
                let charge: Option<(&'static str, Generator<'_, 1>)> = (model == Model::Wave
                    && lattice.boundary() == Boundary::Free)
                    .then_some(("split_shift_charge", &shift));
                match model {
                    Model::SineGordon => variational_rule(
                        &loaded,
                        scheme,
                        NonlinearWave(SineGordon),
                        &lattice,
                        |rule| match rule {
                            Either::Triangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
                            Either::Rectangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
                        },
                    )??,
                    Model::Wave => {
                        variational_rule(&loaded, scheme, NonlinearWave(Wave), &lattice, |rule| match rule {
                            Either::Triangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
                            Either::Rectangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
                        })??
                    }
                    Model::Phi4 { m2, lambda } => {
                        variational_rule(&loaded, scheme, NonlinearWave(Phi4 { m2, lambda }), &lattice, |rule| {
                            match rule {
                                Either::Triangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
                                Either::Rectangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
                            }
                        })??
                    }
                }
            }
        }
        (FieldModel::Complex(kg), FieldInitial::PlaneWave { amplitude, mode }) => {
            let wave = ComplexPlaneWave {
                amplitude,
                mode,
                m2: kg.m2,
                lambda: kg.lambda,
            };
            let levels = wave.levels(&lattice).map_err(initial_error)?;
            let rotation = |y: &SVector<f64, 2>| SVector::<f64, 2>::new(-y[1], y[0]);
            // Fixed end values (every component the same) break the phase symmetry.
            let fixed = matches!(lattice.boundary(), Boundary::Dirichlet { .. });
            let charge: Option<(&'static str, Generator<'_, 2>)> = (!fixed).then_some(("phase_charge", &rotation));
            variational_rule(&loaded, scheme, NonlinearWave(kg), &lattice, |rule| match rule {
                Either::Triangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
                Either::Rectangle(r) => march_generic(&loaded, progress, r, lattice, levels, charge),
            })??
        }
        (FieldModel::Complex(_), FieldInitial::Scalar(_)) => {
            return Err(loaded.key_error(
                "initial.kind",
                "the complex Klein–Gordon field takes `plane-wave` initial data",
            ));
        }
        (FieldModel::Scalar(_), FieldInitial::PlaneWave { .. }) => {
            return Err(loaded.key_error(
                "initial.kind",
                "`plane-wave` initial data are for the complex Klein–Gordon field",
            ));
        }
    };
    Ok(())
}

/// The session of a field run: levels and output size planned from the
/// lattice, the horizon and the output keys.
fn open_session(loaded: &LoadedField, job: &RunJob, lattice: &Lattice, t_end: f64) -> Result<Session, CliError> {
    let o = &loaded.scenario.output;
    let levels = t_end / lattice.dt();
    let components = if loaded.scenario.model.name == "klein-gordon-complex" {
        2.0
    } else {
        1.0
    };
    let snapshots = if o.snapshot_every == 0 {
        2.0
    } else {
        levels / o.snapshot_every as f64 + 2.0
    };
    let snapshot_bytes = snapshots * lattice.nodes() as f64 * components * 8.0;
    let energy_bytes = (levels / o.energy_every as f64 + 2.0) * 3.0 * CSV_BYTES_PER_VALUE;
    let plan = Plan {
        steps: levels,
        steps_key: "time.t_end",
        bytes: snapshot_bytes + energy_bytes,
        bytes_key: if snapshot_bytes > energy_bytes {
            "output.snapshot_every"
        } else {
            "output.energy_every"
        },
        levels_per_step: 1,
        given_steps: 0,
        unit: "time steps",
        step: Some(lattice.dt()),
        t_end: None,
    };
    let limit = loaded.scenario.checks.energy_limit(&loaded.path, ENERGY_ERROR_FIELDS)?;
    let mut session = Session::open(
        &loaded.path,
        job,
        output_dir(&loaded.path, &output_spec(&loaded.scenario), job.out.as_deref()),
        &plan,
        Some(o.checkpoint_every),
        "lattice-field",
    )?;
    let l = &loaded.scenario.lattice;
    let ratio = l.courant.unwrap_or(lattice.dt() / lattice.dx());
    if let Some(limit) = loaded.stability_limit()
        && ratio > limit * (1.0 + 4.0 * f64::EPSILON)
    {
        session.verdict.warn(
            "beyond_stability_limit",
            format!(
                "the Courant number dt/dx = {} exceeds the stability limit {limit} of the `{}` scheme; running \
                 because [method] allow_unstable = true",
                crate::output::number(ratio),
                loaded.scenario.method.scheme
            ),
        );
    }
    session.verdict.energy = Some(EnergyCheck {
        conserved: Conserved::Energy,
        limit,
        advice: StepAdvice::lattice(
            l.courant,
            lattice.dt(),
            "more `lattice.nodes` if the space step dominates the error",
        ),
    });
    Ok(session)
}

/// The `[output]` keys `output_dir` understands.
fn output_spec(s: &FieldScenario) -> crate::scenario::OutputSpec {
    crate::scenario::OutputSpec {
        dir: s.output.dir.clone(),
        ..Default::default()
    }
}

/// The cell rule of a variational scheme, or an error naming `method.scheme`.
fn variational_rule<F: Density<DIM> + Copy, const DIM: usize, R>(
    loaded: &LoadedField,
    scheme: Scheme,
    density: F,
    lattice: &Lattice,
    go: impl FnOnce(Either<TriangleRule<F>, RectangleRule<F>>) -> R,
) -> Result<R, CliError> {
    let (dt, dx) = (lattice.dt(), lattice.dx());
    match scheme {
        Scheme::Triangle => Ok(go(Either::Triangle(TriangleRule { density, dt, dx }))),
        Scheme::Rectangle | Scheme::SymmetricRectangle => Ok(go(Either::Rectangle(RectangleRule {
            density,
            dt,
            dx,
            symmetric: scheme == Scheme::SymmetricRectangle,
        }))),
        other => Err(loaded.key_error(
            "method.scheme",
            format!(
                "`{}` has no cell Lagrangian: on dirichlet or free boundaries and for the complex field only \
                 the variational schemes triangle, rectangle and symmetric-rectangle run",
                other.name()
            ),
        )),
    }
}

/// One of the two cell rules.
enum Either<T, R> {
    Triangle(T),
    Rectangle(R),
}

/// The fast path (the scheme's own O(N) solver) on a periodic lattice.
pub fn march_fast(loaded: &LoadedField, session: &mut Session, config: &FieldRunConfig) -> Result<(), CliError> {
    match config.model {
        Model::SineGordon => march_fast_with(loaded, session, config, SineGordon),
        Model::Wave => march_fast_with(loaded, session, config, Wave),
        Model::Phi4 { m2, lambda } => march_fast_with(loaded, session, config, Phi4 { m2, lambda }),
    }
}

fn march_fast_with<P: ScalarPotential>(
    loaded: &LoadedField,
    session: &mut Session,
    config: &FieldRunConfig,
    potential: P,
) -> Result<(), CliError> {
    let lattice = config.lattice;
    let (y0, y1) = config
        .initial
        .levels(&lattice)
        .map_err(|e| loaded.key_error("initial", e.to_string()))?;
    let marcher = FastMarcher::new(potential, config.scheme, lattice, &y0, &y1, config.solver)
        .map_err(|e| loaded.key_error("lattice", e.to_string()))?;
    let wave = config.model == Model::Wave;
    let recentre = if config.model == Model::SineGordon {
        config.recentre_every
    } else {
        0
    };
    let frame = Frame {
        measure: Box::new(move |s: &FastLevels<P>| {
            let m = &s.marcher;
            (m.energy(), wave.then(|| shift_charge(m.previous(), m.current())))
        }),
        values: Box::new(|s: &FastLevels<P>| s.marcher.current().iter().map(|v| v + s.recentred_by).collect()),
        level_of: |s| s.marcher.level(),
        charge: wave.then_some("shift_charge"),
        offset: 2,
        path: "fast",
        components: 1,
        recentred_by: |s| s.recentred_by,
    };
    march(
        loaded,
        session,
        lattice,
        FastStepper::<P>::new(recentre),
        FastLevels::new(marcher),
        frame,
        y0,
    )
}

/// The generic (density) path for the variational schemes.
pub fn march_generic<L: CellEnergy<DIM>, const DIM: usize>(
    loaded: &LoadedField,
    session: &mut Session,
    lag: L,
    lattice: Lattice,
    (y0, y1): Levels<DIM>,
    charge: Option<(&'static str, Generator<'_, DIM>)>,
) -> Result<(), CliError> {
    let flat = |level: &[SVector<f64, DIM>]| -> Vec<f64> { level.iter().flat_map(|v| v.iter().copied()).collect() };
    let first = flat(&y0);
    let mut marcher =
        GenericMarcher::new(lag, lattice, y0, y1).map_err(|e| loaded.key_error("lattice", e.to_string()))?;
    let tol = loaded.scenario.method.tolerance.unwrap_or(1e-13);
    if !(tol.is_finite() && tol > 0.0) {
        return Err(loaded.key_error(
            "method.tolerance",
            format!("expected a finite number > 0, got {}", crate::output::number(tol)),
        ));
    }
    marcher.rel_tol = tol;
    let xi = charge.map(|c| c.1);
    let frame = Frame {
        measure: Box::new(move |m: &GenericMarcher<L, DIM>| {
            let e = level_energy(m.lagrangian(), &lattice, m.previous(), m.current());
            let q = xi.map(|xi| split_charge(m.lagrangian(), &lattice, m.previous(), m.current(), xi));
            (e, q)
        }),
        values: Box::new(move |m: &GenericMarcher<L, DIM>| flat(m.current())),
        level_of: |m| m.level(),
        charge: charge.map(|c| c.0),
        offset: 1,
        path: "generic",
        components: DIM,
        recentred_by: |_| 0.0,
    };
    march(
        loaded,
        session,
        lattice,
        DensityStepper::<L, DIM>::new(),
        marcher,
        frame,
        first,
    )
}
