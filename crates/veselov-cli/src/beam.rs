//! The geometrically exact beam on SE(3) (`[model] name = "beam"`, seed
//! 000): the scenario schema and its validation into the library's beam
//! ([`veselov::models::beam`]); the run is [`crate::beam_run`].
//!
//! ```toml
//! [model]
//! name = "beam"
//! length = 0.8                  # m
//! nodes = 41                    # nodes along the beam (Δs = length/(nodes − 1))
//! width = 0.01                  # rectangle (or radius = … for a disc), m
//! height = 0.01
//! density = 7800.0              # kg/m³
//! young = 2.1e11                # Pa
//! poisson = 0.3                 # or shear_modulus = … (Pa)
//! shear_coefficient = 0.85      # κ (default: Cowper's, 6(1+ν)/(7+6ν) disc, 10(1+ν)/(12+11ν) rectangle)
//! [method]
//! evolution = "time"            # time | space
//! retraction = "cayley"         # cayley | exp
//! tolerance = 1e-14
//! max_iterations = 30
//! allow_unstable = false        # march above the step limit (it will blow up)
//! [ends]                        # time evolution
//! start = "clamped"             # free (zero traction) | clamped (held at its initial pose)
//! end = "free"
//! [loads]
//! gravity = [0.0, -9.81, 0.0]   # m/s²
//! damping = [0, 0, 0, 0, 0, 0]  # viscous, on the body velocity (angular first)
//! [initial]
//! shape = "bent"                # straight | bent (curvature about E1), released at rest;
//! curvature = 0.5               # space evolution: paper | paper-well-posed (seed 000 §5)
//! [time]
//! t_end = 1e-3                  # s (time evolution); dt defaults to 0.8 of the step limit
//! dt = 1e-6
//! [output]
//! every = 10                    # levels between output rows
//! ```
//!
//! Space evolution (seed 000 §5) uses the paper's time grid (Δt = 0.04 s,
//! time nodes j = 0..51, the last one slaved) and its prescribed first two
//! columns; the scenario's Δs must be the paper's 0.02 m, and the march runs
//! to the last node of the beam.

use std::path::{Path, PathBuf};

use serde::Deserialize;
use veselov::field::cauchy::CauchyOptions;
use veselov::models::beam::paper;
use veselov::models::beam::{BeamProperties, CrossSection, Material, StepLimit};

use crate::error::CliError;
use crate::scenario::{
    RowsOutputSpec, adjusted_step_note, finite_value, key_error, parse_toml, positive_value, shear_from_keys,
};

/// The model name of the beam kind.
pub const BEAM_MODEL: &str = "beam";

/// Largest number of nodes across a level.
const MAX_NODES: usize = 100_000;

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamScenario {
    pub model: BeamModelSpec,
    #[serde(default)]
    pub method: BeamMethodSpec,
    #[serde(default)]
    pub ends: BeamEndsSpec,
    #[serde(default)]
    pub loads: BeamLoadsSpec,
    #[serde(default)]
    pub initial: BeamInitialSpec,
    #[serde(default)]
    pub time: BeamTimeSpec,
    #[serde(default)]
    pub output: RowsOutputSpec,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamModelSpec {
    pub name: String,
    pub length: f64,
    pub nodes: usize,
    pub radius: Option<f64>,
    pub width: Option<f64>,
    pub height: Option<f64>,
    pub density: f64,
    pub young: f64,
    pub poisson: Option<f64>,
    pub shear_modulus: Option<f64>,
    /// κ; `shear_correction`, its former name, is still read (listed in
    /// [`FORMER_KEY_NAMES`](crate::scenario::FORMER_KEY_NAMES)).
    #[serde(alias = "shear_correction")]
    pub shear_coefficient: Option<f64>,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamMethodSpec {
    pub evolution: Option<String>,
    pub retraction: Option<String>,
    pub tolerance: Option<f64>,
    pub max_iterations: Option<usize>,
    #[serde(default)]
    pub allow_unstable: bool,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamEndsSpec {
    pub start: Option<String>,
    pub end: Option<String>,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamLoadsSpec {
    pub gravity: Option<[f64; 3]>,
    pub damping: Option<[f64; 6]>,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamInitialSpec {
    pub shape: Option<String>,
    pub curvature: Option<f64>,
}

#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamTimeSpec {
    pub t_end: Option<f64>,
    pub dt: Option<f64>,
}

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

    pub fn parse(path: &Path, text: &str) -> Result<Self, CliError> {
        let scenario: BeamScenario = parse_toml(path, text)?;
        let key = |k: &str, m: String| key_error(path, k, m);
        let m = &scenario.model;
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
        let me = &scenario.method;
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
        let start = match (scenario.initial.shape.as_deref(), space) {
            (None | Some("straight"), false) => BeamStart::Straight,
            (Some("bent"), false) => BeamStart::Bent(finite_value(
                path,
                "initial.curvature",
                scenario.initial.curvature.unwrap_or(1.0),
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
        let (dt, dt_requested, levels) = if space {
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
            if scenario.time.t_end.is_some() || scenario.time.dt.is_some() {
                return Err(key(
                    "time",
                    "space evolution runs on the paper's time grid; remove [time]".into(),
                ));
            }
            (paper::DT, None, (m.nodes - 2) as u64)
        } else {
            let t_end = match scenario.time.t_end {
                Some(t) => positive_value(path, "time.t_end", t)?,
                None => return Err(key("time.t_end", "time evolution needs `t_end`".into())),
            };
            let requested = match scenario.time.dt {
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
        };
        let limit_kind = if space { StepLimit::Space } else { StepLimit::Time };
        let (courant, unstable) = match properties.check_step(limit_kind, dt, ds, false) {
            Ok(c) => (c, None),
            Err(e) if me.allow_unstable => (
                properties.check_step(limit_kind, dt, ds, true).unwrap_or(f64::NAN),
                Some(e.to_string()),
            ),
            Err(e) => {
                // The step quoted again beside the one asked for, where
                // landing on t_end changed it.
                let adjusted = match scenario.time.t_end.map(|t| adjusted_step_note(dt_requested, dt, t)) {
                    Some(note) if !note.is_empty() => format!("; dt = {dt:e}{note}"),
                    _ => String::new(),
                };
                return Err(key(
                    "time.dt",
                    format!("{e}{adjusted}; lower dt, or set [method] allow_unstable = true to run anyway"),
                ));
            }
        };
        let every = scenario.output.rows_every(path, levels)?;
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
        let clamped = [
            end("ends.start", &scenario.ends.start)?,
            end("ends.end", &scenario.ends.end)?,
        ];
        let gravity = scenario.loads.gravity.unwrap_or([0.0; 3]);
        for (i, g) in gravity.iter().enumerate() {
            finite_value(path, &format!("loads.gravity[{i}]"), *g)?;
        }
        let damping = scenario.loads.damping.unwrap_or([0.0; 6]);
        for (i, c) in damping.iter().enumerate() {
            let c = finite_value(path, &format!("loads.damping[{i}]"), *c)?;
            if c < 0.0 {
                return Err(key(&format!("loads.damping[{i}]"), format!("must be ≥ 0, got {c}")));
            }
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
