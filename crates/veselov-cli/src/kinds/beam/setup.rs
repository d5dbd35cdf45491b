//! The validation of a beam scenario ([`super::schema`]) into the library's
//! beam ([`veselov::models::beam`]), section by section: the model and its
//! material, the method, the initial data, the steps and their stability
//! limit, the ends, the loads and the level solves.

use std::path::{Path, PathBuf};

use veselov::field::cauchy::CauchyOptions;
use veselov::models::EndLoad;
use veselov::models::beam::paper;
use veselov::models::beam::{BeamProperties, CrossSection, Material, StepLimit};

use super::schema::{
    BEAM_MODEL, BeamEndsSpec, BeamLoadsSpec, BeamMethodSpec, BeamModelSpec, BeamScenario, BeamTimeSpec,
};
use super::start::BeamInitial;
use crate::error::CliError;
use crate::kinds::structure::{EndMotion, MotionSpec};
use crate::scenario::{Array, adjusted_step_note, key_error, parse_toml, positive_value, shear_from_keys};

/// Largest number of nodes across a level.
const MAX_NODES: usize = 100_000;

/// How an end of the beam is held in time evolution.
#[derive(Debug, Clone)]
pub(crate) enum BeamEnd {
    /// Zero traction.
    Free,
    /// Held at its initial pose.
    Clamped,
    /// Moved from its initial pose.
    Driven(Box<EndMotion>),
}

impl BeamEnd {
    /// Whether the end is clamped.
    pub fn is_clamped(&self) -> bool {
        matches!(self, BeamEnd::Clamped)
    }
    /// Its name in `summary.json`.
    pub fn name(&self) -> &'static str {
        match self {
            BeamEnd::Free => "free",
            BeamEnd::Clamped => "clamped",
            BeamEnd::Driven(_) => "driven",
        }
    }
}

/// The validated beam scenario.
pub(crate) struct BeamSetup {
    pub path: PathBuf,
    pub scenario: BeamScenario,
    pub properties: BeamProperties,
    pub space: bool,
    pub cayley: bool,
    pub ds: f64,
    pub dt: f64,
    /// The `[time] dt` given, if any (adjusted to land on t_end).
    pub dt_requested: Option<f64>,
    /// Levels to march beyond the first two (time steps from t = 0 in time
    /// evolution; columns beyond the second in space evolution).
    pub levels: u64,
    pub every: u64,
    pub ends: [BeamEnd; 2],
    pub initial: BeamInitial,
    pub gravity: [f64; 3],
    pub damping: [f64; 6],
    pub end_load: EndLoad,
    pub options: CauchyOptions,
    /// Courant number of the marching direction and whether it is above 1.
    pub courant: f64,
    pub unstable: Option<String>,
}

impl BeamSetup {
    pub fn key(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    /// The index of the march's level at t = 0 (time evolution: the second
    /// given level) or s = 0 (space evolution: the first column).
    pub fn level_origin(&self) -> f64 {
        if self.space { 0.0 } else { 1.0 }
    }

    /// The time (or arc length, in space evolution) of the march's level `level`.
    pub fn coordinate(&self, level: usize) -> f64 {
        let step = if self.space { self.ds } else { self.dt };
        (level as f64 - self.level_origin()) * step
    }

    /// The time (or space) steps from t = 0 (s = 0) to level `level`.
    pub fn steps_at(&self, level: usize) -> u64 {
        (level as u64).saturating_sub(self.level_origin() as u64)
    }

    /// Parse scenario text attributed to `path` and validate it, section
    /// by section (in this order, the first error found is reported).
    pub fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: BeamScenario = parse_toml(path, text)?;
        let (properties, length, ds) = model(path, &scenario.model)?;
        let (space, cayley) = method(path, &scenario.method)?;
        let initial = super::start::parse(path, &scenario.initial, space, (length, scenario.model.nodes))?;
        let (dt, dt_requested, levels) = steps(path, &scenario.time, &properties, (ds, scenario.model.nodes), space)?;
        let step = (dt, ds, dt_requested);
        let (courant, unstable) = check_step(path, &scenario, &properties, step, space)?;
        let every = scenario.output.rows_every(path, levels)?;
        let ends = ends(path, &scenario.ends, space)?;
        let (gravity, damping, end_load) = loads(path, &scenario.loads, &ends, space)?;
        let options = options(path, &scenario.method)?;
        Ok(Self {
            path: path.to_path_buf(),
            scenario,
            properties,
            space,
            cayley,
            ds,
            dt,
            dt_requested,
            levels,
            every,
            ends,
            initial,
            gravity,
            damping,
            end_load,
            options,
            courant,
            unstable,
        })
    }
}

/// `[model]`: the beam's properties, its length and the node spacing Δs.
fn model(path: &Path, m: &BeamModelSpec) -> Result<(BeamProperties, f64, f64), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    if m.name != BEAM_MODEL {
        return Err(key(
            "model.name",
            format!("expected \"{BEAM_MODEL}\", got `{}`", m.name),
        ));
    }
    if !(3..=MAX_NODES).contains(&m.nodes) {
        return Err(key(
            "model.nodes",
            format!("expected 3..={MAX_NODES} nodes, got {}", m.nodes),
        ));
    }
    let length = positive_value(path, "model.length", m.length)?;
    let section = match (m.radius, m.width, m.height) {
        (Some(r), None, None) => CrossSection::Circle {
            radius: positive_value(path, "model.radius", r)?,
        },
        (None, Some(w), Some(h)) => CrossSection::Rectangle {
            width: positive_value(path, "model.width", w)?,
            height: positive_value(path, "model.height", h)?,
        },
        _ => {
            return Err(key(
                "model.radius",
                "give the cross-section as `radius` (disc) or `width` and `height` (rectangle)".into(),
            ));
        }
    };
    let shear = shear_from_keys(path, m.poisson, m.shear_modulus)?;
    // Cowper's coefficient by default, as for the rod: one rule for
    // both models.
    let shear_coefficient = match m.shear_coefficient {
        Some(k) => positive_value(path, "model.shear_coefficient", k)?,
        None => section.cowper_shear_coefficient(shear.poisson_ratio(m.young)),
    };
    let material = Material {
        density: positive_value(path, "model.density", m.density)?,
        young: positive_value(path, "model.young", m.young)?,
        shear,
        shear_coefficient,
    };
    let properties = BeamProperties::new(&section, &material).map_err(|e| key("model", e.to_string()))?;
    let ds = length / (m.nodes - 1) as f64;
    Ok((properties, length, ds))
}

/// `[method]`: whether the march is in space, and whether by the Cayley map.
fn method(path: &Path, me: &BeamMethodSpec) -> Result<(bool, bool), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let space = match me.evolution.as_deref().unwrap_or("time") {
        "time" => false,
        "space" => true,
        other => {
            return Err(key(
                "method.evolution",
                format!("unknown evolution `{other}` (time | space)"),
            ));
        }
    };
    let cayley = match me.retraction.as_deref().unwrap_or("cayley") {
        "cayley" => true,
        "exp" => false,
        other => {
            return Err(key(
                "method.retraction",
                format!("unknown retraction `{other}` (cayley | exp)"),
            ));
        }
    };
    Ok((space, cayley))
}

/// `[time]`: the step, the `dt` asked for (if any) and the levels to march
/// beyond the first two, for `nodes` nodes `ds` apart; in `space`, the
/// paper's time grid.
fn steps(
    path: &Path,
    time: &BeamTimeSpec,
    properties: &BeamProperties,
    (ds, nodes): (f64, usize),
    space: bool,
) -> Result<(f64, Option<f64>, u64), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    Ok(if space {
        if (ds - paper::DS).abs() > 1e-12 * paper::DS {
            return Err(key(
                "model.nodes",
                format!(
                    "space evolution uses the paper's prescribed columns, built for Δs = {} m; \
                     length/(nodes − 1) = {ds}",
                    paper::DS
                ),
            ));
        }
        if time.t_end.is_some() || time.dt.is_some() {
            return Err(key(
                "time",
                "space evolution runs on the paper's time grid; remove [time]".into(),
            ));
        }
        (paper::DT, None, (nodes - 2) as u64)
    } else {
        let t_end = match time.t_end {
            Some(t) => positive_value(path, "time.t_end", t)?,
            None => return Err(key("time.t_end", "time evolution needs `t_end`".into())),
        };
        let requested = match time.dt {
            Some(dt) => Some(positive_value(path, "time.dt", dt)?),
            None => None,
        };
        let limit = properties.max_time_step(ds);
        // The levels at t = −Δt and 0 are the initial data; the run marches
        // round(t_end/dt) steps (at least one) to end at t_end.
        let steps = match requested {
            Some(dt) => (t_end / dt).round().max(1.0),
            None => (t_end / (0.8 * limit)).ceil().max(1.0),
        };
        if steps > 1e12 {
            return Err(key("time.t_end", format!("{steps:e} levels are too many")));
        }
        (t_end / steps, requested, steps as u64)
    })
}

/// The step against the stability limit of the marching direction: its
/// Courant number and, where `[method] allow_unstable` lets a step above
/// the limit run, why it is unstable.
fn check_step(
    path: &Path,
    scenario: &BeamScenario,
    properties: &BeamProperties,
    (dt, ds, dt_requested): (f64, f64, Option<f64>),
    space: bool,
) -> Result<(f64, Option<String>), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let me = &scenario.method;
    let limit_kind = if space { StepLimit::Space } else { StepLimit::Time };
    Ok(match properties.check_step(limit_kind, dt, ds, false) {
        Ok(c) => (c, None),
        Err(e) if me.allow_unstable => (
            properties.check_step(limit_kind, dt, ds, true).unwrap_or(f64::NAN),
            Some(e.to_string()),
        ),
        Err(e) => {
            // The step quoted again beside the one asked for, where
            // landing on t_end changed it.
            let adjusted = match scenario.time.t_end.map(|t| adjusted_step_note(dt_requested, dt, t)) {
                Some(note) if !note.is_empty() => format!("; dt = {}{note}", crate::output::number(dt)),
                _ => String::new(),
            };
            return Err(key(
                "time.dt",
                format!("{e}{adjusted}; lower dt, or set [method] allow_unstable = true to run anyway"),
            ));
        }
    })
}

/// `[ends]`: how each end is held (time evolution only).
fn ends(path: &Path, ends: &BeamEndsSpec, space: bool) -> Result<[BeamEnd; 2], CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let end = |which: &str, v: &Option<String>, motion: &Option<MotionSpec>| -> Result<BeamEnd, CliError> {
        let k = format!("ends.{which}");
        let condition = match (v.as_deref().unwrap_or("free"), space) {
            ("free", _) => BeamEnd::Free,
            ("clamped", false) => BeamEnd::Clamped,
            ("driven", false) => match motion {
                Some(m) => BeamEnd::Driven(Box::new(EndMotion::parse(path, which, m)?)),
                None => {
                    return Err(key(
                        &format!("ends.{which}_motion"),
                        format!("`{which} = \"driven\"` needs [ends.{which}_motion] (displacement, rotation)"),
                    ));
                }
            },
            (other, false) => {
                return Err(key(
                    &k,
                    format!("unknown end condition `{other}` (free | clamped | driven)"),
                ));
            }
            (_, true) => {
                return Err(key(
                    &k,
                    "space evolution takes the paper's natural ends; remove [ends]".into(),
                ));
            }
        };
        if motion.is_some() && !matches!(condition, BeamEnd::Driven(_)) {
            return Err(key(
                &format!("ends.{which}_motion"),
                format!("given for an end that is not driven (set `{which} = \"driven\"`)"),
            ));
        }
        Ok(condition)
    };
    Ok([
        end("start", &ends.start, &ends.start_motion)?,
        end("end", &ends.end, &ends.end_motion)?,
    ])
}

/// `[loads]`: gravity, the viscous damping of the body velocity and the end
/// load (time evolution, a free end).
fn loads(
    path: &Path,
    loads: &BeamLoadsSpec,
    ends: &[BeamEnd; 2],
    space: bool,
) -> Result<([f64; 3], [f64; 6], EndLoad), CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let gravity = Array::or(&loads.gravity, path, "loads.gravity", [0.0; 3])?;
    let damping = Array::or(&loads.damping, path, "loads.damping", [0.0; 6])?;
    for (i, &c) in damping.iter().enumerate() {
        if c < 0.0 {
            return Err(key(
                &format!("loads.damping[{i}]"),
                format!("must be ≥ 0, got {}", crate::output::number(c)),
            ));
        }
    }
    let end_load = EndLoad {
        force: Array::or(&loads.end_force, path, "loads.end_force", [0.0; 3])?.into(),
        torque: Array::or(&loads.end_torque, path, "loads.end_torque", [0.0; 3])?.into(),
        ramp: match loads.ramp {
            Some(r) if r.is_finite() && r >= 0.0 => r,
            Some(r) => {
                return Err(key(
                    "loads.ramp",
                    format!("must be ≥ 0, got {}", crate::output::number(r)),
                ));
            }
            None => 0.0,
        },
        start: 0.0,
    };
    if !end_load.is_zero() {
        let k = if end_load.force.iter().any(|&f| f != 0.0) {
            "loads.end_force"
        } else {
            "loads.end_torque"
        };
        if space {
            return Err(key(k, "an end load is for time evolution".into()));
        }
        if !matches!(ends[1], BeamEnd::Free) {
            return Err(key(
                k,
                format!(
                    "the end is {}: an end load needs `[ends] end = \"free\"`",
                    ends[1].name()
                ),
            ));
        }
    }
    Ok((gravity, damping, end_load))
}

/// `[method]`: the options of the level solves.
fn options(path: &Path, me: &BeamMethodSpec) -> Result<CauchyOptions, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
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
    Ok(options)
}
