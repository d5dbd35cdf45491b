//! The validation of a rod scenario ([`super::schema`]) into the library's
//! rod ([`veselov::models::rod`]), section by section: the material and
//! section at the material points, the step against the stability limit,
//! the initial shape, the ends, the loads and the method.

use std::path::{Path, PathBuf};

use nalgebra::Vector3;
use veselov::field::cauchy::CauchyOptions;
use veselov::field::fibre::Pose;
use veselov::lie::so3;
use veselov::models::rod::{
    BENDING_STIFFENING_PER_LOCKING, CrossSection, EndCondition, Material, RodEnds, RodLattice, courant_number,
    largest_step, locking_number, rod_parameters, spacing_for_locking,
};
use veselov::models::rod::{RodLoads, RodParameters, ShearFrame};

use super::motion::{Centreline, MotionSpec, driven_end};
use super::schema::{
    Along, DEFAULT_STEP_NUMBER, EndsSpec, LoadsSpec, ROD_MODEL, RodInitialSpec, RodMethodSpec, RodModelSpec,
    RodScenario,
};
use super::shape::Shape;
use crate::error::CliError;
use crate::scenario::{
    Array, adjusted_step_note, finite_value, key_error, parse_toml, positive_value, shear_from_keys,
};

/// Largest number of material points.
const MAX_NODES: usize = 100_000;

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
    pub shape: Shape,
    pub velocity: Vector3<f64>,
    pub spin: Vector3<f64>,
    pub options: CauchyOptions,
    pub dt: f64,
    /// The `[time] dt` given, if any (dt is adjusted to land on t_end).
    pub dt_requested: Option<f64>,
    pub steps: u64,
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
    /// bring its bending stiffening to [`BENDING_STIFFENING_ADVISED`].
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

/// The bending stiffening from shear locking that a run's advice aims at: 1 %.
pub const BENDING_STIFFENING_ADVISED: f64 = 0.01;

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
            steps,
            lattice,
            courant,
        } = steps(path, &scenario, &body)?;
        let every = scenario.output.rows_every(path, steps)?;
        let i = &scenario.initial;
        let shape = shape(path, i, m.nodes, &lattice, body.length)?;
        let ends = ends(path, &scenario.ends, &shape, body.length, dt)?;
        let (gravity, loads, any_load) = loads(path, &scenario.loads, m.nodes, dt, &ends)?;
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
            velocity: vector(path, "initial.velocity", &i.velocity)?,
            spin: vector(path, "initial.angular_velocity", &i.angular_velocity)?,
            scenario,
            parameters,
            profile: varying.then_some(profile),
            mass,
            lattice,
            ends,
            loads: any_load.then_some(loads),
            gravity,
            shape,
            options,
            dt,
            dt_requested: requested,
            steps,
            every,
            courant,
            dt_limit,
            symmetric,
            shear_frame,
            locking,
            nodes_for_bending,
        })
    }

    /// The initial motion (s, t) ↦ (r, R) in lattice time: the shape moved
    /// rigidly, r = exp(τω̂)r₀(s) + vτ, R = exp(τω̂)R₀(s), τ = t − Δt, so that
    /// the march's first cut (level 2, lattice time Δt) is the run's t = 0.
    pub fn motion(&self) -> impl Fn(f64, f64) -> Pose<f64> + '_ {
        move |s, t| {
            let t = t - self.dt;
            let q = so3::exp(&(self.spin * t));
            let p = self.shape.pose(s);
            Pose::new(q.act(&p.position) + self.velocity * t, q.compose(&p.rotation))
        }
    }
}

/// `[model]`: the rod's length, its material points and the parameters there.
struct RodBody {
    length: f64,
    /// The material points s_k = kL/(N − 1).
    points: Vec<f64>,
    /// Whether any key is an expression in s.
    varying: bool,
    /// The parameters at each material point.
    profile: Vec<RodParameters>,
    /// The parameters at s = 0.
    parameters: RodParameters,
    mass: f64,
    /// The worst shear-locking number and the material points advised for bending.
    locking: f64,
    nodes_for_bending: usize,
}

/// `[model]`: the material and section at every material point, the mass
/// and the resolution of bending.
fn body(path: &Path, m: &RodModelSpec) -> Result<RodBody, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    if m.name != ROD_MODEL {
        return Err(key("model.name", format!("expected \"{ROD_MODEL}\", got `{}`", m.name)));
    }
    if !(3..=MAX_NODES).contains(&m.nodes) {
        return Err(key(
            "model.nodes",
            format!("expected 3..={MAX_NODES} material points, got {}", m.nodes),
        ));
    }
    let length = positive_value(path, "model.length", m.length)?;
    // Material points s_k = kL/(N − 1): each key a number or an
    // expression in s, evaluated there.
    let points: Vec<f64> = (0..m.nodes).map(|k| length * k as f64 / (m.nodes - 1) as f64).collect();
    let varying = [&m.radius, &m.width, &m.height]
        .into_iter()
        .flatten()
        .chain([&m.density, &m.young])
        .any(|v| matches!(v, Along::Expression(_)));
    let along = |k: &str, v: &Along| v.at(path, k, &points);
    let sections: Vec<CrossSection> = match (&m.radius, &m.width, &m.height) {
        (Some(r), None, None) => along("model.radius", r)?
            .into_iter()
            .map(|radius| CrossSection::Circle { radius })
            .collect(),
        (None, Some(w), Some(h)) => along("model.width", w)?
            .into_iter()
            .zip(along("model.height", h)?)
            .map(|(width, height)| CrossSection::Rectangle { width, height })
            .collect(),
        _ => {
            return Err(key(
                "model.radius",
                "give the cross-section as `radius` (circle) or `width` and `height` (rectangle)".into(),
            ));
        }
    };
    let (densities, youngs) = (along("model.density", &m.density)?, along("model.young", &m.young)?);
    let shear = shear_from_keys(path, m.poisson, m.shear_modulus)?;
    let given_kappa = match m.shear_coefficient {
        Some(k) => Some(positive_value(path, "model.shear_coefficient", k)?),
        None => None,
    };
    let profile = (0..m.nodes)
        .map(|k| {
            let young = youngs[k];
            let kappa = given_kappa.unwrap_or_else(|| sections[k].cowper_shear_coefficient(shear.poisson_ratio(young)));
            let material = Material {
                density: densities[k],
                young,
                shear,
                shear_coefficient: kappa,
            };
            rod_parameters(&sections[k], &material).map_err(|e| key("model", format!("at s = {}: {e}", points[k])))
        })
        .collect::<Result<Vec<RodParameters>, CliError>>()?;
    let parameters = profile[0];
    // Mass by the trapezoidal rule over the material points.
    let spacing = length / (m.nodes - 1) as f64;
    let mass = profile
        .windows(2)
        .map(|w| 0.5 * (w[0].rho() + w[1].rho()) * spacing)
        .sum();
    let locking = profile.iter().map(|q| locking_number(q, spacing)).fold(0.0, f64::max);
    let resolved = profile
        .iter()
        .map(|q| spacing_for_locking(q, BENDING_STIFFENING_ADVISED / BENDING_STIFFENING_PER_LOCKING))
        .fold(f64::INFINITY, f64::min);
    // Saturating: a huge count is advice, not an allocation.
    let nodes_for_bending = (length / resolved).ceil().min(u32::MAX as f64) as usize + 1;
    Ok(RodBody {
        length,
        points,
        varying,
        profile,
        parameters,
        mass,
        locking,
        nodes_for_bending,
    })
}

/// The step of a rod run, and its lattice.
struct Steps {
    /// The largest stable step.
    dt_limit: f64,
    dt: f64,
    /// The `[time] dt` given, if any.
    requested: Option<f64>,
    steps: u64,
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
    // The step count is round(t_end/dt) (at least 1) and dt = t_end/count,
    // so that the run ends at t_end exactly; without `dt`, the fewest
    // steps with a step number at most `step_number` (dt at most that
    // fraction of the stability limit; half of it by default).
    let t_end = positive_value(path, "time.t_end", scenario.time.t_end)?;
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
    let steps = match requested {
        Some(dt) => (t_end / dt).round().max(1.0),
        None => {
            let number = match scenario.time.step_number {
                Some(x) => positive_value(path, "time.step_number", x)?,
                None => DEFAULT_STEP_NUMBER,
            };
            (t_end / (number * dt_limit)).ceil().max(1.0)
        }
    };
    if steps > 1e12 {
        let name = if by_number { "time.step_number" } else { "time.t_end" };
        return Err(key(name, format!("{steps:e} time steps are too many")));
    }
    let dt = t_end / steps;
    let steps = steps as u64;
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
        steps,
        lattice,
        courant,
    })
}

/// `[initial]`: the shape of the rod of `nodes` material points over
/// `length` on `lattice`.
fn shape(path: &Path, i: &RodInitialSpec, nodes: usize, lattice: &RodLattice, length: f64) -> Result<Shape, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let shape = match i.shape.as_deref().unwrap_or("straight") {
        "straight" => Shape::Straight,
        "bent" => Shape::Bent {
            curvature: finite_value(path, "initial.curvature", i.curvature.unwrap_or(1.0))?,
        },
        "helix" => Shape::Helix {
            radius: positive_value(path, "initial.helix_radius", i.helix_radius.unwrap_or(0.0))?,
            pitch: finite_value(path, "initial.helix_pitch", i.helix_pitch.unwrap_or(0.0))?,
        },
        "curve" => {
            let Some(sources) = &i.position else {
                return Err(key(
                    "initial.position",
                    "shape = \"curve\" needs three expressions in s".into(),
                ));
            };
            let points: Vec<f64> = (0..nodes)
                .map(|k| lattice.length() * k as f64 / (nodes - 1) as f64)
                .collect();
            Shape::Curve(Centreline::new(path, "initial.position", sources, &points)?)
        }
        other => {
            return Err(key(
                "initial.shape",
                format!("unknown shape `{other}` (straight | bent | helix | curve)"),
            ));
        }
    };
    if i.position.is_some() && !matches!(shape, Shape::Curve(_)) {
        return Err(key(
            "initial.position",
            "given, but `initial.shape` is not \"curve\"".into(),
        ));
    }
    if let Shape::Bent { curvature } = &shape
        && (curvature * length).abs() >= std::f64::consts::PI
    {
        return Err(key(
            "initial.curvature",
            format!(
                "|curvature|·length = {:e} must stay below π",
                (curvature * length).abs()
            ),
        ));
    }
    Ok(shape)
}

/// `[ends]`: free, clamped at the pose of `shape` there, or driven from it
/// (the march's lattice time `dt` is the run's t = 0).
fn ends(path: &Path, e: &EndsSpec, shape: &Shape, length: f64, dt: f64) -> Result<RodEnds, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    // A clamped end holds the initial shape's pose there; a driven one
    // moves from it (the march's lattice time Δt is the run's t = 0).
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
            "clamped" => Ok(EndCondition::Clamped(shape.pose(at))),
            "driven" => driven_end(path, which, &motion.clone().unwrap_or_default(), shape.pose(at), dt),
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
/// material points (whether any of them acts), which need a free end.
fn loads(
    path: &Path,
    l: &LoadsSpec,
    nodes: usize,
    dt: f64,
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
        // Lattice time Δt is the run's t = 0 (see `motion`).
        start: dt,
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
