//! The validation of a beam scenario ([`super::schema`]) into the library's
//! beam ([`veselov::models::beam`]), section by section: the model and its
//! material, the method, the initial data, the steps and their stability
//! limit, the ends, the loads and the level solves.

use std::path::{Path, PathBuf};

use veselov::field::cauchy::CauchyOptions;
use veselov::models::beam::paper;
use veselov::models::beam::{BeamProperties, CrossSection, Material, StepLimit};

use super::schema::{
    BEAM_MODEL, BeamEndsSpec, BeamInitialSpec, BeamLoadsSpec, BeamMethodSpec, BeamModelSpec, BeamScenario, BeamTimeSpec,
};
use crate::error::CliError;
use crate::scenario::{
    Array, adjusted_step_note, finite_value, key_error, parse_toml, positive_value, shear_from_keys,
};

/// Largest number of nodes across a level.
const MAX_NODES: usize = 100_000;

/// The initial data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum BeamStart {
    /// Straight along E3 at rest (time evolution).
    Straight,
    /// Bent with curvature κ about E1, at rest (time evolution).
    Bent(f64),
    /// The paper's prescribed columns (space evolution).
    Paper,
    /// The paper's column 0 with column 1 its rigid transport, perturbed.
    PaperWellPosed,
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
    /// Levels to march beyond the first two.
    pub levels: u64,
    pub every: u64,
    pub clamped: [bool; 2],
    pub start: BeamStart,
    pub gravity: [f64; 3],
    pub damping: [f64; 6],
    pub options: CauchyOptions,
    /// Courant number of the marching direction and whether it is above 1.
    pub courant: f64,
    pub unstable: Option<String>,
}

impl BeamSetup {
    pub fn key(&self, key: &str, message: impl Into<String>) -> CliError {
        key_error(&self.path, key, message)
    }

    /// Parse scenario text attributed to `path` and validate it, section
    /// by section (in this order, the first error found is reported).
    pub fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: BeamScenario = parse_toml(path, text)?;
        let (properties, length, ds) = model(path, &scenario.model)?;
        let (space, cayley) = method(path, &scenario.method)?;
        let start = start(path, &scenario.initial, space, length)?;
        let (dt, dt_requested, levels) = steps(path, &scenario.time, &properties, (ds, scenario.model.nodes), space)?;
        let step = (dt, ds, dt_requested);
        let (courant, unstable) = check_step(path, &scenario, &properties, step, space)?;
        let every = scenario.output.rows_every(path, levels)?;
        let clamped = ends(path, &scenario.ends, space)?;
        let (gravity, damping) = loads(path, &scenario.loads)?;
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
            clamped,
            start,
            gravity,
            damping,
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

/// `[initial]`: the first two levels, for the evolution in `space` or time
/// of a beam of `length`.
fn start(path: &Path, initial: &BeamInitialSpec, space: bool, length: f64) -> Result<BeamStart, CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let start = match (initial.shape.as_deref(), space) {
        (None | Some("straight"), false) => BeamStart::Straight,
        (Some("bent"), false) => BeamStart::Bent(finite_value(
            path,
            "initial.curvature",
            initial.curvature.unwrap_or(1.0),
        )?),
        (None | Some("paper"), true) => BeamStart::Paper,
        (Some("paper-well-posed"), true) => BeamStart::PaperWellPosed,
        (Some(other), _) => {
            return Err(key(
                "initial.shape",
                format!(
                    "`{other}` is not a {} evolution start ({})",
                    if space { "space" } else { "time" },
                    if space {
                        "paper | paper-well-posed"
                    } else {
                        "straight | bent"
                    }
                ),
            ));
        }
    };
    if let BeamStart::Bent(k) = start
        && (k * length).abs() >= std::f64::consts::PI
    {
        return Err(key(
            "initial.curvature",
            format!("|curvature|·length = {:e} must stay below π", (k * length).abs()),
        ));
    }
    Ok(start)
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
        // Levels 0 and 1 (t = 0, Δt) are the initial data; the run marches
        // round(t_end/dt) − 1 more (at least one) to end at t_end.
        let steps = match requested {
            Some(dt) => (t_end / dt).round().max(2.0),
            None => (t_end / (0.8 * limit)).ceil().max(2.0),
        };
        if steps > 1e12 {
            return Err(key("time.t_end", format!("{steps:e} levels are too many")));
        }
        (t_end / steps, requested, steps as u64 - 1)
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

/// `[ends]`: whether each end is clamped (time evolution only).
fn ends(path: &Path, ends: &BeamEndsSpec, space: bool) -> Result<[bool; 2], CliError> {
    let key = |k: &str, m: String| key_error(path, k, m);
    let end = |k: &str, v: &Option<String>| -> Result<bool, CliError> {
        match (v.as_deref().unwrap_or("free"), space) {
            ("free", _) => Ok(false),
            ("clamped", false) => Ok(true),
            (other, false) => Err(key(k, format!("unknown end condition `{other}` (free | clamped)"))),
            (_, true) => Err(key(
                k,
                "space evolution takes the paper's natural ends; remove [ends]".into(),
            )),
        }
    };
    Ok([end("ends.start", &ends.start)?, end("ends.end", &ends.end)?])
}

/// `[loads]`: gravity and the viscous damping of the body velocity.
fn loads(path: &Path, loads: &BeamLoadsSpec) -> Result<([f64; 3], [f64; 6]), CliError> {
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
    Ok((gravity, damping))
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
