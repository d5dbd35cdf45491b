//! The geometrically exact beam on SE(3) (`[model] name = "beam"`, seed
//! 000): the scenario schema; its validation into the library's beam
//! ([`veselov::models::beam`]) is [`super::setup`], the run [`super::run`].
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

use serde::Deserialize;

use crate::scenario::RowsOutputSpec;

/// The model name of the beam kind.
pub const BEAM_MODEL: &str = "beam";

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
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

#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
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

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamMethodSpec {
    pub evolution: Option<String>,
    pub retraction: Option<String>,
    pub tolerance: Option<f64>,
    pub max_iterations: Option<usize>,
    #[serde(default)]
    pub allow_unstable: bool,
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamEndsSpec {
    pub start: Option<String>,
    pub end: Option<String>,
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamLoadsSpec {
    pub gravity: Option<[f64; 3]>,
    pub damping: Option<[f64; 6]>,
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamInitialSpec {
    pub shape: Option<String>,
    pub curvature: Option<f64>,
}

#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct BeamTimeSpec {
    pub t_end: Option<f64>,
    pub dt: Option<f64>,
}
