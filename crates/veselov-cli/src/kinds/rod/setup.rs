//! The validation of a rod scenario ([`super::schema`]) into the library's
//! rod ([`veselov::models::rod`]), section by section: the parameters at
//! the material points ([`super::body`]), the step against the stability
//! limit and the levels that land on `t_end`, the initial motion
//! ([`super::initial`]), the ends, the loads and the method.

use std::path::{Path, PathBuf};

use nalgebra::Vector3;
use veselov::field::cauchy::CauchyOptions;
use veselov::field::fibre::Pose;
use veselov::models::rod::{EndCondition, RodEnds, RodLattice, courant_number, largest_step};
use veselov::models::rod::{RodLoads, RodParameters, ShearFrame};

use super::body::{RodBody, body};
use super::initial::{FIRST_CUT, Initial, level_at_zero};
use super::motion::driven_end;
use super::schema::{DEFAULT_STEP_NUMBER, EndsSpec, LoadsSpec, RodMethodSpec, RodScenario};
use crate::error::CliError;
use crate::kinds::structure::MotionSpec;
use crate::scenario::{Array, adjusted_step_note, finite_value, key_error, parse_toml, positive_value};

/// The validated rod scenario.
pub(crate) struct RodSetup {
    pub path: PathBuf,
    pub scenario: RodScenario,
    /// The parameters at s = 0 (of the whole rod when uniform).
    pub parameters: RodParameters,
    /// Parameters per material point, when any of them varies along the rod.
    pub profile: Option<Vec<RodParameters>>,
    /// The rod's mass.
    pub mass: f64,
    pub lattice: RodLattice,
    pub ends: RodEnds,
    /// Damping and end load (None when all are zero).
    pub loads: Option<RodLoads>,
    pub gravity: Vector3<f64>,
    /// The initial motion, which also sets the run's clock.
    pub initial: Initial,
    pub options: CauchyOptions,
    pub dt: f64,
    /// The `[time] dt` given, if any (dt is adjusted to land on t_end).
    pub dt_requested: Option<f64>,
    /// The levels (half steps) the run marches from its first cut to t_end.
    pub levels: u64,
    /// The half steps from the lattice's time 0 (level 0) to t_end, whose
    /// count sets dt = 2·t_end/half_steps.
    pub half_steps: u64,
    /// Time steps between output rows.
    pub every: u64,
    /// Step number √((cΔt/Δs)² + (ωΔt/2)²) and the largest stable Δt.
    pub courant: f64,
    pub dt_limit: f64,
    /// Q_sym (`[method] quadrature = "symmetric"`) instead of Prop. 6.5's Q_{v₀}.
    pub symmetric: bool,
    /// The frame of the shear strain (`[method] shear_frame`).
    pub shear_frame: ShearFrame,
    /// The worst shear-locking number κGA·δ²/EI along the rod
    /// (`models::rod::resolution`) and the fewest material points that
    /// bring its bending stiffening to [`super::body::BENDING_STIFFENING_ADVISED`].
    pub locking: f64,
    pub nodes_for_bending: usize,
}

/// The values of `[method] shear_frame` and their frames.
const SHEAR_FRAMES: [(&str, ShearFrame); 2] = [("vertex", ShearFrame::Vertex), ("centred", ShearFrame::Centred)];

/// The name of `frame` in `[method] shear_frame` (and in summary.json).
pub fn shear_frame_name(frame: ShearFrame) -> &'static str {
    SHEAR_FRAMES
        .iter()
        .find(|(_, f)| *f == frame)
        .map_or("vertex", |(name, _)| name)
}

/// The vector key `key` (zero when not given): 3 finite numbers.
fn vector(path: &Path, key: &str, v: &Option<Array<f64, 3>>) -> Result<Vector3<f64>, CliError> {
    Array::or(v, path, key, [0.0; 3]).map(Vector3::from)
}

fn non_negative(path: &Path, key: &str, v: Option<f64>) -> Result<f64, CliError> {
    let v = finite_value(path, key, v.unwrap_or(0.0))?;
    if v < 0.0 {
        return Err(key_error(
            path,
            key,
            format!("must be ≥ 0, got {}", crate::output::number(v)),
        ));
    }
    Ok(v)
}

/// The step number (Courant number) for a message: three decimals, in
/// exponent form when it is large (a stiff rod at a given dt can have a
/// step number of 150 digits).
pub fn step_number_text(courant: f64) -> String {
    if courant < 1e6 {
        format!("{courant:.3}")
    } else {
        format!("{courant:.3e}")
    }
}

impl RodSetup {
    pub fn key(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    /// Parse scenario text attributed to `path` and validate it, section
    /// by section (in this order, the first error found is reported).
    pub fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: RodScenario = parse_toml(path, text)?;
        let m = &scenario.model;
        let body = body(path, m)?;
        let Steps {
            dt_limit,
            dt,
            requested,
            levels,
            half_steps,
            lattice,
            courant,
        } = steps(path, &scenario, &body)?;
        let every = scenario.output.rows_every(path, levels.div_ceil(2))?;
        let initial = Initial::parse(path, &scenario.initial, &lattice)?;
        // The lattice time of the run's t = 0.
        let zero = lattice.time(initial.level_at_zero());
        let ends = ends(path, &scenario.ends, &initial, body.length, zero)?;
        let (gravity, loads, any_load) = loads(path, &scenario.loads, m.nodes, zero, &ends)?;
        let (symmetric, shear_frame, options) = method(path, &scenario.method, body.varying, &loads, any_load)?;
        let RodBody {
            varying,
            profile,
            parameters,
            mass,
            locking,
            nodes_for_bending,
            ..
        } = body;
        Ok(Self {
            path: path.to_path_buf(),
            scenario,
            parameters,
            profile: varying.then_some(profile),
            mass,
            lattice,
            ends,
            loads: any_load.then_some(loads),
            gravity,
            initial,
            options,
            dt,
            dt_requested: requested,
            levels,
            half_steps,
            every,
            courant,
            dt_limit,
            symmetric,
            shear_frame,
            locking,
            nodes_for_bending,
        })
    }

    /// The initial motion (s, t) ↦ (r, R) in lattice time (level w at
    /// wΔt/2), sampled as the march's Cauchy data ([`Initial::pose`]).
    pub fn motion(&self) -> impl Fn(f64, f64) -> Pose<f64> + '_ {
        move |s, t| self.initial.pose(s, t, self.dt)
    }

    /// The run's time at marcher level `level` (the time of the cut below
    /// it): (level − level_at_zero)·Δt/2, level_at_zero that of
    /// [`Initial::level_at_zero`].
    pub fn time_at(&self, level: i64) -> f64 {
        (level - self.initial.level_at_zero()) as f64 * 0.5 * self.dt
    }
}

/// The step of a rod run, and its lattice.
struct Steps {
    /// The largest stable step.
    dt_limit: f64,
    dt: f64,
    /// The `[time] dt` given, if any.
    requested: Option<f64>,
    /// Levels marched from the first cut, and half steps from level 0, to t_end.
    levels: u64,
    half_steps: u64,
    lattice: RodLattice,
    /// The largest step number along the rod.
    courant: f64,
}

/// `[time]`: the step and the step count against the stability limit of
/// the `body` (unless `[method] allow_unstable`).
fn steps(path: &Path, scenario: &RodScenario, body: &RodBody) -> Result<Steps, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let m = &scenario.model;
    let (length, points, profile) = (body.length, &body.points, &body.profile);
    let probe = RodLattice::new(m.nodes, length, 1.0).map_err(|e| key("model.nodes", e.to_string()))?;
    let mut dt_limit = f64::INFINITY;
    for (k, q) in profile.iter().enumerate() {
        let limit = largest_step(q, probe.ds()).map_err(|e| key("model", format!("at s = {}: {e}", points[k])))?;
        dt_limit = dt_limit.min(limit);
    }
    // The lattice's levels are half a step apart and level w is at lattice
    // time wΔt/2; the run's clock reads 0 at level z (2, the first cut, for
    // a shape; 0 for expressions in s and t), so its last cut, at t_end, is
    // level n + z with n = 2·t_end/dt half steps. The count is
    // round(2·t_end/dt) (at least one whole step of the march, 2 levels, from
    // the first cut) and dt = 2·t_end/n, so that the run ends at t_end
    // exactly and a t_end of a whole number of half steps keeps the dt
    // asked for; without `dt`, the fewest whole steps with a step number at
    // most `step_number` (dt at most that fraction of the stability limit;
    // half of it by default).
    let t_end = positive_value(path, "time.t_end", scenario.time.t_end)?;
    let zero = level_at_zero(&scenario.initial);
    let fewest = (FIRST_CUT + 2 - zero) as f64;
    // Whether `step_number` sets the step: the errors about it name that key.
    let by_number = scenario.time.step_number.is_some();
    if by_number && scenario.time.dt.is_some() {
        return Err(key(
            "time.step_number",
            "give either `dt` or `step_number`, not both".to_string(),
        ));
    }
    let requested = match scenario.time.dt {
        Some(dt) => Some(positive_value(path, "time.dt", dt)?),
        None => None,
    };
    let half_steps = match requested {
        Some(dt) => (2.0 * t_end / dt).round().max(fewest),
        None => {
            let number = match scenario.time.step_number {
                Some(x) => positive_value(path, "time.step_number", x)?,
                None => DEFAULT_STEP_NUMBER,
            };
            (2.0 * (t_end / (number * dt_limit)).ceil()).max(fewest)
        }
    };
    if half_steps > 2e12 {
        let name = if by_number { "time.step_number" } else { "time.t_end" };
        return Err(key(name, format!("{:e} time steps are too many", half_steps / 2.0)));
    }
    let dt = 2.0 * t_end / half_steps;
    let half_steps = half_steps as u64;
    let levels = half_steps - (FIRST_CUT - zero) as u64;
    let lattice = RodLattice::new(m.nodes, length, dt).map_err(|e| key("time.dt", e.to_string()))?;
    let mut courant: f64 = 0.0;
    for q in profile {
        courant = courant.max(courant_number(q, lattice.ds(), dt).map_err(|e| key("model", e.to_string()))?);
    }
    if courant > 1.0 && !scenario.method.allow_unstable {
        let (name, lower) = if by_number {
            ("time.step_number", "lower step_number to 1 or less")
        } else {
            ("time.dt", "lower dt")
        };
        let adjusted = adjusted_step_note(requested, dt, t_end);
        return Err(key(
            name,
            format!(
                "dt = {}{adjusted} exceeds the stability limit {} of the rod's march (step number {} > 1: \
                 the lattice waves would grow without bound); {lower}, or set [method] allow_unstable = true \
                 to run anyway",
                crate::output::number(dt),
                crate::output::number(dt_limit),
                step_number_text(courant)
            ),
        ));
    }
    Ok(Steps {
        dt_limit,
        dt,
        requested,
        levels,
        half_steps,
        lattice,
        courant,
    })
}

/// `[ends]`: free, clamped at the pose of the `initial` motion there at the
/// run's t = 0, or driven from it (the march's lattice time `zero` is the
/// run's t = 0).
fn ends(path: &Path, e: &EndsSpec, initial: &Initial, length: f64, zero: f64) -> Result<RodEnds, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let end = |which: &str, v: &Option<String>, motion: &Option<MotionSpec>, at: f64| {
        let k = format!("ends.{which}");
        if motion.is_some() && v.as_deref() != Some("driven") {
            return Err(key(
                &format!("ends.{which}_motion"),
                format!("given, but `{k}` is not \"driven\""),
            ));
        }
        match v.as_deref().unwrap_or("free") {
            "free" => Ok(EndCondition::Free),
            "clamped" => Ok(EndCondition::Clamped(initial.rest(at))),
            "driven" => driven_end(path, which, &motion.clone().unwrap_or_default(), initial.rest(at), zero),
            other => Err(key(
                &k,
                format!("unknown end condition `{other}` (free | clamped | driven)"),
            )),
        }
    };
    Ok(RodEnds {
        start: end("start", &e.start, &e.start_motion, 0.0)?,
        end: end("end", &e.end, &e.end_motion, length)?,
    })
}

/// `[loads]`: gravity, and the damping and end load of a rod of `nodes`
/// material points (whether any of them acts), which need a free end; the
/// end load is switched on at the run's t = 0, lattice time `zero`.
fn loads(
    path: &Path,
    l: &LoadsSpec,
    nodes: usize,
    zero: f64,
    ends: &RodEnds,
) -> Result<(Vector3<f64>, RodLoads, bool), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let gravity = vector(path, "loads.gravity", &l.gravity)?;
    let loads = RodLoads {
        damping_linear: non_negative(path, "loads.damping", l.damping)?,
        damping_angular: non_negative(path, "loads.angular_damping", l.angular_damping)?,
        end_force: vector(path, "loads.end_force", &l.end_force)?,
        end_torque: vector(path, "loads.end_torque", &l.end_torque)?,
        tip: nodes as i64 - 1,
        ramp: non_negative(path, "loads.ramp", l.ramp)?,
        start: zero,
    };
    let end_loaded = loads.end_force != Vector3::zeros() || loads.end_torque != Vector3::zeros();
    let any_load = loads.damped() || end_loaded;
    if end_loaded && !ends.end.is_free() {
        return Err(key(
            "loads.end_force",
            "the end load acts at the last material point, which is clamped".into(),
        ));
    }
    Ok((gravity, loads, any_load))
}

/// `[method]`: the quadrature (symmetric or not), the shear frame and the
/// options of the vertex solves, checked against a `varying` rod and its
/// `loads`.
fn method(
    path: &Path,
    me: &RodMethodSpec,
    varying: bool,
    loads: &RodLoads,
    any_load: bool,
) -> Result<(bool, ShearFrame, CauchyOptions), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let symmetric = match me.quadrature.as_deref().unwrap_or("vertex") {
        "vertex" => false,
        "symmetric" => true,
        other => {
            return Err(key(
                "method.quadrature",
                format!("unknown quadrature `{other}` (vertex | symmetric)"),
            ));
        }
    };
    let name = me.shear_frame.as_deref().unwrap_or("vertex");
    let Some(&(_, shear_frame)) = SHEAR_FRAMES.iter().find(|(n, _)| *n == name) else {
        let names: Vec<&str> = SHEAR_FRAMES.iter().map(|(n, _)| *n).collect();
        return Err(key(
            "method.shear_frame",
            format!("unknown shear frame `{name}` ({})", names.join(" | ")),
        ));
    };
    if symmetric && shear_frame == ShearFrame::Centred {
        return Err(key(
            "method.shear_frame",
            "\"centred\" is a variant of the vertex rule: use it with quadrature = \"vertex\"".into(),
        ));
    }
    if symmetric && varying {
        return Err(key(
            "method.quadrature",
            "\"symmetric\" needs a uniform rod: give the material and section as numbers, or use \
             quadrature = \"vertex\""
                .into(),
        ));
    }
    if symmetric && any_load {
        let at_fault = [
            ("loads.damping", loads.damping_linear > 0.0),
            ("loads.angular_damping", loads.damping_angular > 0.0),
            ("loads.end_force", loads.end_force != Vector3::zeros()),
            ("loads.end_torque", loads.end_torque != Vector3::zeros()),
        ]
        .into_iter()
        .find_map(|(k, set)| set.then_some(k))
        .unwrap_or("loads");
        return Err(key(
            at_fault,
            "not available with [method] quadrature = \"symmetric\": damping and end loads are discrete \
             forces of the vertex rule (quadrature = \"vertex\"); gravity is available with both"
                .into(),
        ));
    }
    let mut options = CauchyOptions::default();
    if let Some(t) = me.tolerance {
        options.tolerance = positive_value(path, "method.tolerance", t)?;
    }
    if let Some(k) = me.max_iterations {
        if k == 0 {
            return Err(key("method.max_iterations", "expected an integer ≥ 1".into()));
        }
        options.max_iterations = k;
    }
    Ok((symmetric, shear_frame, options))
}
