//! Fields in 2+1 dimensions on the CFK simplicial lattice (`[lattice] kind =
//! "cfk"`): the density 𝓛 = ½(φ_t² − |∇φ|²) + N(φ) discretized by the
//! midpoint rule on the simplices of x_a = Δx(v_a − w/3), t = wΔt/3
//! (w = v₀ + v₁ + v₂), periodic in both space directions, and marched vertex
//! by vertex by the core's Cauchy integrator.
//!
//! ```toml
//! [model]
//! name = "sine-gordon"          # sine-gordon | wave | klein-gordon-phi4 | klein-gordon-complex
//! [lattice]
//! kind = "cfk"
//! space_dimension = 2
//! nodes = [48, 48]              # nodes per space axis (periodic)
//! spacing = 0.25                # Δx
//! courant = 0.4                 # Δt/Δx (or dt = …)
//! [initial]
//! kind = "pulse"                # pulse | standing-wave | plane-wave (complex field)
//! amplitude = 4.0
//! [time]
//! t_end = 10.0
//! [output]
//! snapshot_every = 5            # time steps Δt between snapshots
//! checkpoint_every = 100        # time steps Δt between checkpoints (0: at the end only)
//! ```
//!
//! Outputs: `energy.csv` (t, energy: the cell energies of one slab of
//! duration Δt divided by Δt), `momentum.csv` (t, p_x, p_y — the field's
//! momentum −∫φ_t∇φ, not exactly conserved, since lattice translations are
//! discrete symmetries — then the level momenta of the vertical symmetries,
//! conserved to round-off: `shift_momentum` of the wave equation,
//! `phase_charge` of the complex field), `snapshots.npy` (snapshots × nx × ny
//! [× 2]), `snapshot_times.csv`, `summary.json`, `energy_error.svg` and heat
//! maps `field_<k>.png` of a few snapshots spread over the run.

mod observer;
use observer::CfkObserver;

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use nalgebra::{SVector, Vector3};
use serde::Deserialize;
use serde_json::json;
use veselov::field::cauchy::{CauchyMarcher, CauchyOptions};
use veselov::field::complex::CfkTorus;
use veselov::field::discretize::{CfkNodes, MidpointRule, SmoothDensity};
use veselov::field::fibre::Euclidean;
use veselov::field::{CauchyStepper, ComplexKleinGordon, NonlinearWave, Phi4, Potential, SineGordon, Wave};
use veselov::run::{Control, Observer, StepStats, StopWhen, Words};

use crate::error::CliError;
use crate::kinds::lattice::schema::{FieldModelSpec, FieldTimeSpec};
use crate::output::Table;
use crate::pipeline::RunJob;
use crate::pipeline::finish::{Ending, close_run};
use crate::pipeline::readback::rows_for_plots;
use crate::pipeline::stream::{CsvStream, NpyStream};
use crate::pipeline::{CSV_BYTES_PER_VALUE, Plan, Resumable, Resumed, open_lattice_run};
use crate::scenario::{check_plot_format, finite_value, key_error, parse_toml, positive_value};

/// Whether a field scenario asks for a CFK lattice.
pub fn is_cfk(text: &str) -> bool {
    toml::from_str::<toml::Table>(text)
        .ok()
        .and_then(|t| t.get("lattice")?.get("kind")?.as_str().map(|k| k == "cfk"))
        .unwrap_or(false)
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CfkScenario {
    model: FieldModelSpec,
    lattice: CfkLatticeSpec,
    #[serde(default)]
    method: CfkMethodSpec,
    initial: CfkInitialSpec,
    time: FieldTimeSpec,
    #[serde(default)]
    output: CfkOutputSpec,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CfkLatticeSpec {
    /// `cfk`.
    kind: String,
    /// Space dimension (2).
    space_dimension: usize,
    /// Nodes per space axis.
    nodes: Vec<usize>,
    /// Δx.
    spacing: f64,
    dt: Option<f64>,
    courant: Option<f64>,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct CfkMethodSpec {
    /// `midpoint` (the only rule on this lattice kind).
    rule: Option<String>,
    /// Relative tolerance of the vertex solves (default 1e-14).
    tolerance: Option<f64>,
    /// Newton iterations per vertex (default 30).
    max_iterations: Option<usize>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CfkInitialSpec {
    /// `pulse | standing-wave | plane-wave`.
    kind: String,
    amplitude: Option<f64>,
    /// Pulse: Gaussian width (default a tenth of the shorter side).
    width: Option<f64>,
    /// Standing and plane waves: mode numbers [mx, my] (default [1, 1]).
    mode: Option<Vec<i32>>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct CfkOutputSpec {
    dir: Option<PathBuf>,
    /// Time steps Δt between snapshots (default 10; 0: first and last only).
    #[serde(default = "ten")]
    snapshot_every: usize,
    /// Time steps Δt between checkpoints (default 0: only where the run ends).
    #[serde(default)]
    checkpoint_every: u64,
    #[serde(default = "yes")]
    plots: bool,
    #[serde(default = "svg")]
    plot_format: String,
}

fn ten() -> usize {
    10
}
fn yes() -> bool {
    true
}
fn svg() -> String {
    "svg".into()
}

impl Default for CfkOutputSpec {
    fn default() -> Self {
        Self {
            dir: None,
            snapshot_every: ten(),
            checkpoint_every: 0,
            plots: true,
            plot_format: svg(),
        }
    }
}

/// The validated set-up shared by every model.
struct Setup {
    path: PathBuf,
    scenario: CfkScenario,
    nodes: [usize; 2],
    dx: f64,
    dt: f64,
    t_end: f64,
    options: CauchyOptions,
}

impl Setup {
    fn key(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: CfkScenario = parse_toml(path, text)?;
        let l = &scenario.lattice;
        let key = |k: &str, m: String| key_error(path, k, m);
        if l.kind != "cfk" {
            return Err(key("lattice.kind", format!("expected \"cfk\", got `{}`", l.kind)));
        }
        if l.space_dimension != 2 {
            return Err(key(
                "lattice.space_dimension",
                format!("CFK field runs are in 2 space dimensions, got {}", l.space_dimension),
            ));
        }
        if l.nodes.len() != 2 || l.nodes.iter().any(|&n| !(3..=4096).contains(&n)) {
            return Err(key(
                "lattice.nodes",
                format!("expected two node counts in 3..=4096, got {:?}", l.nodes),
            ));
        }
        // The march keeps 7 levels of values and 4 levels of cell gradients
        // (about 1 KiB per node of a level): cap a level at 2²⁰ nodes.
        if l.nodes[0] * l.nodes[1] > MAX_LEVEL_NODES {
            return Err(key(
                "lattice.nodes",
                format!(
                    "{} × {} nodes per level exceed the limit of {MAX_LEVEL_NODES}",
                    l.nodes[0], l.nodes[1]
                ),
            ));
        }
        let dx = positive_value(path, "lattice.spacing", l.spacing)?;
        let dt = match (l.dt, l.courant) {
            (Some(_), Some(_)) => return Err(key("lattice", "give either `dt` or `courant`, not both".into())),
            (None, None) => {
                return Err(key(
                    "lattice",
                    "missing `dt` or `courant` (dt = courant·spacing)".into(),
                ));
            }
            (Some(dt), None) => positive_value(path, "lattice.dt", dt)?,
            (None, Some(c)) => positive_value(path, "lattice.courant", c)? * dx,
        };
        // Measured: the march of the wave equation on this lattice is stable
        // at Δt/Δx = 0.4 and grows exponentially at 0.45 (a pulse on 24×24
        // nodes to t = 30); the simplices are skewed, so the limit is below
        // the square grid's 1/√2.
        // The ratio as given (`courant`), else dt/dx with a few ulps of
        // slack: a ratio at the limit must not be refused for the rounding
        // of dt = courant·spacing.
        let ratio = l.courant.unwrap_or(dt / dx);
        if ratio > MAX_COURANT * (1.0 + 4.0 * f64::EPSILON) {
            return Err(key(
                "lattice",
                format!("Δt/Δx = {ratio:.3} exceeds the stability limit {MAX_COURANT} of the CFK march"),
            ));
        }
        let m = &scenario.method;
        if let Some(rule) = &m.rule
            && rule != "midpoint"
        {
            return Err(key(
                "method.rule",
                format!("unknown rule `{rule}`, expected \"midpoint\""),
            ));
        }
        let mut options = CauchyOptions::default();
        if let Some(t) = m.tolerance {
            options.tolerance = positive_value(path, "method.tolerance", t)?;
        }
        if let Some(k) = m.max_iterations {
            if k == 0 {
                return Err(key("method.max_iterations", "expected an integer ≥ 1".into()));
            }
            options.max_iterations = k;
        }
        let t_end = positive_value(path, "time.t_end", scenario.time.t_end)?;
        let o = &scenario.output;
        check_plot_format(path, &o.plot_format)?;
        Ok(Self {
            path: path.to_path_buf(),
            nodes: [l.nodes[0], l.nodes[1]],
            scenario,
            dx,
            dt,
            t_end,
            options,
        })
    }

    /// Time steps Δt to run (the run ends at the first whole step ≥ t_end).
    fn steps(&self) -> f64 {
        (self.t_end / self.dt).ceil()
    }

    fn param(&self, name: &str, default: f64, allowed: &[&str]) -> Result<f64, CliError> {
        for k in self.scenario.model.params.keys() {
            if !allowed.contains(&k.as_str()) {
                return Err(self.key(
                    &format!("model.params.{k}"),
                    format!("unknown parameter for `{}`", self.scenario.model.name),
                ));
            }
        }
        let v = self.scenario.model.params.get(name).copied().unwrap_or(default);
        finite_value(&self.path, &format!("model.params.{name}"), v)
    }
}

/// Largest number of nodes per level.
const MAX_LEVEL_NODES: usize = 1 << 20;

/// Largest Δt/Δx accepted.
const MAX_COURANT: f64 = 0.4;

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

/// The initial field φ(x, y, t) of the scenario (M components); the waves
/// take their frequency from ω² = k² + m² (+ λA² for the complex plane
/// wave, which is then exact).
fn initial<const M: usize>(setup: &Setup, (m2, lambda): (f64, f64)) -> Result<InitialField<M>, CliError> {
    let i = &setup.scenario.initial;
    let (lx, ly) = (setup.nodes[0] as f64 * setup.dx, setup.nodes[1] as f64 * setup.dx);
    let amplitude = finite_value(&setup.path, "initial.amplitude", i.amplitude.unwrap_or(1.0))?;
    let mode = i.mode.clone().unwrap_or_else(|| vec![1, 1]);
    if mode.len() != 2 {
        return Err(setup.key("initial.mode", format!("expected two mode numbers, got {mode:?}")));
    }
    let (kx, ky) = (TAU * mode[0] as f64 / lx, TAU * mode[1] as f64 / ly);
    let complex = M == 2;
    match (i.kind.as_str(), complex) {
        ("pulse", false) => {
            let w = positive_value(&setup.path, "initial.width", i.width.unwrap_or(0.1 * lx.min(ly)))?;
            let (cx, cy) = (0.5 * lx, 0.5 * ly);
            // At rest: the same profile on the first Cauchy levels (O(Δt²)).
            Ok(Box::new(move |x| {
                let r2 = (x[0] - cx).powi(2) + (x[1] - cy).powi(2);
                SVector::from_element(amplitude * (-0.5 * r2 / (w * w)).exp())
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

type Generator<const M: usize> = fn(&SVector<f64, M>) -> SVector<f64, M>;
type Rule<P> = MidpointRule<NonlinearWave<P>, CfkNodes<3>, 3>;
type Marcher<P, const M: usize> = CauchyMarcher<Euclidean<M>, Rule<P>, M>;

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
    let field = initial::<M>(setup, dispersion)?;
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
    let steps = setup.steps();
    crate::scenario::note_lattice_end(setup.t_end, setup.dt, job.quiet);
    let cells = (setup.nodes[0] * setup.nodes[1] * M) as f64;
    let snapshots = match s.output.snapshot_every {
        0 => 2.0,
        k => steps / k as f64 + 2.0,
    };
    let plan = Plan {
        steps: 3.0 * steps,
        steps_key: "time.t_end",
        bytes: snapshots * cells * 8.0 + (steps + 1.0) * 7.0 * CSV_BYTES_PER_VALUE,
        bytes_key: "output.snapshot_every",
        unit: "levels",
        step: Some(setup.dt),
        t_end: None,
    };
    let (mut session, resumed) = open_lattice_run::<4>(
        &setup.path,
        job,
        s.output.dir.clone(),
        &plan,
        s.output.checkpoint_every.saturating_mul(3),
        "cfk-field",
    )?;
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
    let own = json!({
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
        "energy_initial": obs.energy0,
        "energy_error_max": obs.energy_error_max,
        "energy_error_max_relative": crate::pipeline::summary::relative_energy_error(obs.energy_error_max, obs.energy0),
        "charges_error_max": match symmetry {
            Some((name, _)) => json!({ name: obs.charge_error_max }),
            None => json!({}),
        },
    });
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
                "{} on a {}×{} CFK lattice: {} time steps to t = {}, max |E − E₀| = {:.3e}",
                s.model.name, setup.nodes[0], setup.nodes[1], k_final, t_final, obs.energy_error_max,
            )
        },
    )
}

/// Values per vertex of the field of `model`: 2 for the complex
/// Klein–Gordon field, else 1.
pub fn components(model: &str) -> usize {
    if model == "klein-gordon-complex" { 2 } else { 1 }
}

/// Energy error and heat maps (first component) of a few snapshots spread
/// over the run, read back from the files: `nodes` per axis with spacing
/// `dx`, `components` values per vertex.
pub fn draw(
    dir: &Path,
    (nodes, dx): ([usize; 2], f64),
    components: usize,
    snapshot_rows: u64,
    format: &str,
) -> Result<(), CliError> {
    let energy = Table::read_csv(&dir.join("energy.csv"))?;
    if let (Some(t), Some(e)) = (energy.column("t"), energy.column("energy")) {
        crate::figures::draw_energy_error(
            &dir.join(format!("energy_error.{format}")),
            "Discrete energy error",
            &t,
            &e,
        )?;
    }
    let [nx, ny] = nodes;
    let width: Vec<String> = (0..nx * ny * components).map(|i| i.to_string()).collect();
    let snaps = rows_for_plots(dir, "snapshots", &width, snapshot_rows, 4)?;
    let times = rows_for_plots(dir, "snapshot_times", &["t".to_string()], snapshot_rows, 4)?;
    for (k, (values, t)) in snaps.rows.iter().zip(&times.rows).enumerate() {
        // Rows along y, columns along x.
        let grid: Vec<Vec<f64>> = (0..ny)
            .map(|gy| (0..nx).map(|gx| values[(gx * ny + gy) * components]).collect())
            .collect();
        let title = format!("{} at t = {:.3}", if components == 2 { "Re φ" } else { "φ" }, t[0]);
        let map = crate::heatmap::Heatmap {
            title: &title,
            x_label: "x",
            y_label: "y",
            x_range: (0.0, nx as f64 * dx),
            y_range: (0.0, ny as f64 * dx),
            values: &grid,
        };
        crate::heatmap::draw_heatmap(&dir.join(format!("field_{k}.png")), &map).map_err(crate::figures::plot_err)?;
    }
    Ok(())
}
