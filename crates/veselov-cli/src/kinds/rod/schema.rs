//! The Cosserat rod (`[model] name = "cosserat-rod"`, seed 003 §6): the
//! scenario schema; its validation into the library's rod
//! ([`veselov::models::rod`]) is [`super::setup`], the run [`super::run`].
//!
//! ```toml
//! [model]
//! name = "cosserat-rod"
//! length = 1.0                  # m
//! nodes = 41                    # material points (≥ 3)
//! radius = 0.02                 # circular section (or width = …, height = …); radius, width, height,
//!                               # density and young may also be expressions in s, e.g. "0.02*(1 - 0.3*s)"
//! density = 1000.0              # kg/m³
//! young = 1e6                   # Pa
//! poisson = 0.5                 # or shear_modulus = … (Pa)
//! shear_coefficient = 0.9       # κ (default: Cowper's, 6(1+ν)/(7+6ν) circle, 10(1+ν)/(12+11ν) rectangle)
//! # Or, instead of the section and material, the rod's own data of (6.1) (all four, uniform):
//! # mass_per_length = 1.0                   # ρ, kg/m
//! # inertia_density = [0.1, 0.1, 0.2]       # J, kg·m: the diagonal, or 9 entries row by row (symmetric, > 0)
//! # shear_stiffness = [1.0, 1.0, 10.0]      # C₁ = diag(shear, shear, extension), N
//! # bending_stiffness = [1.0, 1.0, 0.5]     # C₂ = diag(bending, bending, torsion), N·m²
//! [ends]
//! start = "clamped"             # free | clamped (held at its initial pose) | driven
//! end = "free"                  # (driven: [ends.start_motion], see `motion`)
//! [loads]
//! gravity = [0.0, 0.0, -9.81]   # m/s²
//! damping = 0.5                 # c_r: force −c_r ∂_t r per unit length
//! angular_damping = 0.0         # c_R: body torque −c_R ω per unit length
//! end_force = [0.0, 0.01, 0.0]  # N, at the last material point, spatial frame
//! end_torque = [0.0, 0.0, 0.0]  # N·m
//! ramp = 1.0                    # s: the end load grows linearly from 0
//! [initial]
//! shape = "straight"            # straight | bent | helix | curve (position = three expressions in s)
//! curvature = 2.0               # bent: an arc in the x–z plane
//! helix_radius = 0.1            # helix: radius and pitch (rise per turn)
//! helix_pitch = 0.2
//! velocity = [0.0, 0.0, 0.0]    # a rigid motion: translation velocity …
//! angular_velocity = [0.0, 0.0, 0.0]  # … and spin about the origin
//! # Or any motion, instead of the keys above: expressions in s and t, sampled on the lattice's
//! # first four levels at t = 0, Δt/2, Δt, 3Δt/2 (the run's clock; its first output is at t = Δt):
//! # position = ["0.05*sin(3*s) + 0.2*t", "0.1*t*cos(2*s)", "s + 0.01*t"]   # r(s, t), m
//! # rotation_vector = ["0.3*s", "0.5*t", "0.2*s^2 + 0.4*t"]               # θ(s, t), R = exp(θ̂), rad
//! [time]
//! t_end = 2.0
//! dt = 1e-4                     # adjusted to 2·t_end/round(2·t_end/dt) (levels are half steps);
//!                               # default: at most half the stability limit
//! # step_number = 0.9           # instead of dt: the fewest steps with step number ≤ this (default 0.5)
//! [method]
//! tolerance = 1e-14             # vertex solves (relative)
//! max_iterations = 30
//! allow_unstable = false        # run above the stability limit (it will blow up)
//! quadrature = "vertex"         # vertex: Prop. 6.5 (Q_{v₀}, split step) | symmetric: Q_sym (6-D Newton; no damping or end loads)
//! shear_frame = "vertex"        # vertex: Prop. 6.5 (shear locking) | centred: the frame halfway to the neighbour (no locking; ~11 % more per step)
//! [output]
//! every = 10                    # time steps between output rows (default: ~500 rows)
//! ```

use serde::Deserialize;

pub(crate) use crate::kinds::structure::Along;
use crate::kinds::structure::MotionSpec;
use crate::scenario::{Array, List, RowsOutputSpec};

/// The model name of the rod kind.
pub const ROD_MODEL: &str = "cosserat-rod";

/// A Cosserat rod scenario (`[model] name = "cosserat-rod"`): each table
/// is documented on its own struct.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodScenario {
    pub model: RodModelSpec,
    #[serde(default)]
    pub ends: EndsSpec,
    #[serde(default)]
    pub loads: LoadsSpec,
    #[serde(default)]
    pub initial: RodInitialSpec,
    pub time: RodTimeSpec,
    #[serde(default)]
    pub method: RodMethodSpec,
    #[serde(default)]
    pub output: RowsOutputSpec,
    /// The thresholds beyond which the run's summary carries a warning.
    #[serde(default)]
    pub checks: crate::verdict::ChecksSpec,
}

/// The rod's length, its material points, and its parameters in (6.1)
/// of Casimiro and Rodrigo, in one of two styles (not both): a
/// cross-section and a material (`radius` or `width` and `height`,
/// `density`, `young`, `poisson` or `shear_modulus`, `shear_coefficient`),
/// which may vary along the rod (give `radius`, `width`, `height`,
/// `density` or `young` as an expression in the material coordinate `s`,
/// 0 … length, as a string); or the rod's own data, uniform along it:
/// `mass_per_length` (ρ), `inertia_density` (J), `shear_stiffness` (C₁) and
/// `bending_stiffness` (C₂), all four.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodModelSpec {
    /// The model name.
    #[schemars(extend("enum" = ["cosserat-rod"]))]
    pub name: String,
    /// The rod's length when unstressed; the material coordinate `s` runs
    /// from 0 (the start) to `length` (the end).
    #[schemars(extend("unit" = "m"))]
    pub length: f64,
    /// The number of material points, 3 to 100 000, evenly spaced at
    /// `length/(nodes − 1)`. Bending needs a spacing small against the
    /// radius: a run warns when shear locking would leave static bending
    /// deflections more than 5 % short (none with `shear_frame = "centred"`).
    pub nodes: usize,
    /// The radius of a circular cross-section: give either `radius` or
    /// `width` and `height`. A number, or an expression in `s` such as
    /// `"0.05*(1 - 0.3*s)"`, positive at every material point.
    #[schemars(extend("unit" = "m"))]
    pub radius: Option<Along>,
    /// The side of a rectangular cross-section along its first axis, with
    /// `height` (instead of `radius`). A number, or an expression in `s`.
    #[schemars(extend("unit" = "m"))]
    pub width: Option<Along>,
    /// The side of a rectangular cross-section along its second axis, with
    /// `width` (instead of `radius`). A number, or an expression in `s`.
    #[schemars(extend("unit" = "m"))]
    pub height: Option<Along>,
    /// The mass density of the material (with a cross-section). A number,
    /// or an expression in `s`; gravity follows the local mass.
    #[schemars(extend("unit" = "kg/m³"))]
    pub density: Option<Along>,
    /// Young's modulus E (with a cross-section). A number, or an expression
    /// in `s`.
    #[schemars(extend("unit" = "Pa"))]
    pub young: Option<Along>,
    /// Poisson's ratio ν, in (−1, 0.5], giving the shear modulus
    /// E/(2(1 + ν)); exactly one of `poisson` and `shear_modulus`.
    pub poisson: Option<f64>,
    /// The shear modulus G (> 0), instead of `poisson`; exactly one of
    /// `poisson` and `shear_modulus`.
    #[schemars(extend("unit" = "Pa"))]
    pub shear_modulus: Option<f64>,
    /// The shear coefficient κ of the cross-section (> 0). Default:
    /// Cowper's for the section and Poisson's ratio, 6(1 + ν)/(7 + 6ν) for a
    /// circle and 10(1 + ν)/(12 + 11ν) for a rectangle.
    pub shear_coefficient: Option<f64>,
    /// The rod's mass per unit length ρ of (6.1) (> 0), instead of a
    /// cross-section and a material: with `inertia_density`,
    /// `shear_stiffness` and `bending_stiffness`. The kinetic energy density
    /// is ½ρ|∂ₜr|² + ½ωᵀJω.
    #[schemars(extend("unit" = "kg/m"))]
    pub mass_per_length: Option<f64>,
    /// The rotational inertia per unit length J of (6.1), in the body frame
    /// (d₁, d₂, d₃ = the tangent): 3 numbers, the diagonal (I₁, I₂, I₃), or 9,
    /// the full tensor row by row; symmetric and positive definite. With
    /// `mass_per_length`. (A circular section of radius a in a material of
    /// density ρ₀ has J = ρ₀πa⁴/4·(1, 1, 2).)
    #[schemars(extend("unit" = "kg·m"))]
    pub inertia_density: Option<List<f64>>,
    /// The stiffness C₁ of the linear strain ε = Rᵀ∂ₛr − e₃ in (6.1),
    /// diagonal: (shear along d₁, shear along d₂, extension), each > 0
    /// (κGA, κGA, EA for a section of area A). With `mass_per_length`.
    #[schemars(extend("unit" = "N"))]
    pub shear_stiffness: Option<Array<f64, 3>>,
    /// The stiffness C₂ of the angular strain Ω (Ω̂ = Rᵀ∂ₛR) in (6.1),
    /// diagonal: (bending about d₁, bending about d₂, torsion), each > 0
    /// (EI₁, EI₂, GK for a section). With `mass_per_length`.
    #[schemars(extend("unit" = "N·m²"))]
    pub bending_stiffness: Option<Array<f64, 3>>,
}

/// How the rod is held at its start (s = 0) and at its end
/// (s = length).
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct EndsSpec {
    /// The start (s = 0): `free`, `clamped` (held at its initial pose) or
    /// `driven` (moved as `[ends.start_motion]` prescribes).
    #[schemars(extend("default" = "free", "enum" = ["free", "clamped", "driven"]))]
    pub start: Option<String>,
    /// The end (s = length): `free`, `clamped` (held at its initial pose) or
    /// `driven` (moved as `[ends.end_motion]` prescribes). An end force or
    /// torque needs it free.
    #[schemars(extend("default" = "free", "enum" = ["free", "clamped", "driven"]))]
    pub end: Option<String>,
    /// The motion of a driven start (`start = "driven"`, and only then),
    /// from its initial pose: expressions in the run's time `t`.
    pub start_motion: Option<MotionSpec>,
    /// The motion of a driven end (`end = "driven"`, and only then), from
    /// its initial pose: expressions in the run's time `t`.
    pub end_motion: Option<MotionSpec>,
}

/// Gravity, damping, and a force and torque at the rod's end
/// (s = length). Damping and the end load need `quadrature = "vertex"`;
/// gravity works with both quadratures.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct LoadsSpec {
    /// The gravitational acceleration (x, y, z), acting on the local mass.
    #[schemars(extend("unit" = "m/s²", "default" = [0.0, 0.0, 0.0]))]
    pub gravity: Option<Array<f64, 3>>,
    /// Linear damping c (≥ 0): a force −c ∂ₜr per unit length against the
    /// centreline's velocity.
    #[schemars(extend("unit" = "N·s/m²", "default" = 0.0))]
    pub damping: Option<f64>,
    /// Angular damping c (≥ 0): a torque −c ω per unit length against the
    /// angular velocity of the cross-sections.
    #[schemars(extend("unit" = "N·s", "default" = 0.0))]
    pub angular_damping: Option<f64>,
    /// A force at the last material point, in the spatial frame (x, y, z);
    /// it needs `[ends] end` free.
    #[schemars(extend("unit" = "N", "default" = [0.0, 0.0, 0.0]))]
    pub end_force: Option<Array<f64, 3>>,
    /// A torque at the last material point, in the spatial frame (x, y, z);
    /// it needs `[ends] end` free.
    #[schemars(extend("unit" = "N·m", "default" = [0.0, 0.0, 0.0]))]
    pub end_torque: Option<Array<f64, 3>>,
    /// The time over which the end force and torque grow linearly from zero
    /// to their full value (≥ 0); 0 applies them in full from the start.
    #[schemars(extend("unit" = "s", "default" = 0.0))]
    pub ramp: Option<f64>,
}

/// The rod's initial state, in one of two styles. A shape at t = 0 and a
/// rigid motion it starts with (at rest by default): `shape` with its keys,
/// `velocity`, `angular_velocity`. Or any motion, given as expressions in
/// the material coordinate `s` and the time `t`: `position` and
/// `rotation_vector` (both, without the keys of the first style), sampled
/// on the first four levels of the rod's lattice, which fix the positions
/// and velocities. Its unstressed shape is always straight: a rod started
/// bent or coiled springs back.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodInitialSpec {
    /// `straight` (along z from the origin), `bent` (an arc of `curvature`
    /// in the x–z plane, starting along z), `helix` (about the z axis, with
    /// `helix_radius` and `helix_pitch`) or `curve` (the centreline
    /// `position`).
    #[schemars(extend("default" = "straight", "enum" = ["straight", "bent", "helix", "curve"]))]
    pub shape: Option<String>,
    /// The curvature of the `bent` arc; |curvature|·length must stay below π.
    #[schemars(extend("unit" = "1/m", "default" = 1.0))]
    pub curvature: Option<f64>,
    /// The radius of the `helix` (> 0; needed with `shape = "helix"`).
    #[schemars(extend("unit" = "m"))]
    pub helix_radius: Option<f64>,
    /// The rise of the `helix` per turn (0: a flat coil).
    #[schemars(extend("unit" = "m", "default" = 0.0))]
    pub helix_pitch: Option<f64>,
    /// The initial velocity of the whole rod's translation (x, y, z).
    #[schemars(extend("unit" = "m/s", "default" = [0.0, 0.0, 0.0]))]
    pub velocity: Option<Array<f64, 3>>,
    /// The initial angular velocity of the whole rod about the origin
    /// (x, y, z), with `velocity` a rigid motion.
    #[schemars(extend("unit" = "rad/s", "default" = [0.0, 0.0, 0.0]))]
    pub angular_velocity: Option<Array<f64, 3>>,
    /// With `shape = "curve"`: the initial centreline, three expressions x,
    /// y, z in the material coordinate `s`, finite with a non-zero tangent
    /// at every material point; where |dr/ds| ≠ 1 the rod starts stretched
    /// or compressed. With `rotation_vector` instead (no `shape`): the
    /// motion r(s, t) of the centreline, three expressions in `s` and `t`
    /// sampled as (6.4), y_v = (r, R)(s, t) at the vertex's node (6.2): the
    /// lattice starts from four levels w = 0, 1, 2, 3 at t = w·Δt/2, Δt the
    /// time step, each holding every other material point (the even ones,
    /// s = 0, 2δ, …, at t = 0 and Δt; the odd ones at t = Δt/2 and 3Δt/2), so
    /// each point's velocity is that of the motion over Δt. The run's clock
    /// is the one of these expressions: its first output, the cut at level 2,
    /// is at t = Δt, and it ends at `t_end`.
    #[schemars(extend("unit" = "m"))]
    pub position: Option<Array<String, 3>>,
    /// The motion of the frames, with `position` (both needed, and neither
    /// `shape`, `velocity` nor `angular_velocity`): three expressions θ(s, t)
    /// in `s` and `t`, the frame's rotation vector (axis θ/|θ|, angle |θ|):
    /// R = exp(θ̂) by Rodrigues' formula (6.8), sampled at the times of
    /// `position`. The frame's third axis R e₃ is the rod's unstressed
    /// tangent: θ = 0 for a rod along e₃.
    #[schemars(extend("unit" = "rad"))]
    pub rotation_vector: Option<Array<String, 3>>,
}

/// How long the run lasts and its time step, given as `dt` or as
/// a fraction of the stability limit (`step_number`; not both). The step
/// number √((cΔt/Δs)² + (ωΔt/2)²), c the fastest wave speed and ω the
/// shear–rotation frequency √(κGA/ρI), must stay at most 1.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodTimeSpec {
    /// The time at which the run ends (> 0); it starts at 0 (at Δt when
    /// `[initial]` gives the motion as expressions in `s` and `t`) and ends
    /// at `t_end` exactly.
    #[schemars(extend("unit" = "s"))]
    pub t_end: f64,
    /// The time step, instead of `step_number`. The lattice advances by
    /// levels half a step apart (each material point by dt every two
    /// levels), so the run's clock reaches `t_end` after round(2·t_end/dt)
    /// half steps (at least one whole step of the march), dt adjusted to
    /// 2·t_end divided by that count: a `t_end` of a whole number of half
    /// steps keeps dt as given. A dt above the stability limit is refused unless
    /// `allow_unstable`. Without it the step follows from `step_number`.
    #[schemars(extend("unit" = "s"))]
    pub dt: Option<f64>,
    /// The step as a fraction of the stability limit, instead of `dt`: the
    /// run takes the fewest steps whose step number is at most this (0.5
    /// when neither is given). Above 1 it is refused unless
    /// `allow_unstable`, and above 0.9 the run warns: the limit 1 is that of
    /// the linearised march, and close to it a long run can still grow.
    #[schemars(extend("default" = 0.5))]
    pub step_number: Option<f64>,
}

/// The step number a rod run takes when the scenario gives neither `dt`
/// nor `step_number`: half the stability limit.
pub const DEFAULT_STEP_NUMBER: f64 = 0.5;

/// The largest step number run without a warning: the limit 1 is the
/// linearised march's, and close to it, sooner for large motions, a long
/// run can still grow (`rod_free_tumbling.toml` with 31 material points ran
/// 20 s at 0.9 and failed after 3,405 steps at 0.95 and after 50 at 0.97;
/// the `rod_step` bench's near-straight free rod after 10,870 steps at
/// 0.969).
pub const LONG_RUN_STEP_NUMBER: f64 = 0.9;

/// The discretisation of the rod and the options of the
/// vertex solves (a linear solve for each new position, then Newton's
/// method for its frame).
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct RodMethodSpec {
    /// The relative tolerance at which each vertex's Newton solve stops
    /// (> 0): the residual against the size of the terms summed.
    #[schemars(extend("default" = 1e-14))]
    pub tolerance: Option<f64>,
    /// The Newton iterations a vertex may take (≥ 1) before the run stops
    /// with a vertex-solve error.
    #[schemars(extend("default" = 30))]
    pub max_iterations: Option<usize>,
    /// Run a step above the stability limit instead of refusing it: the
    /// run warns, the waves grow and the run stops with a vertex-solve
    /// error, keeping what it computed.
    #[serde(default)]
    pub allow_unstable: bool,
    /// The quadrature of the discrete Lagrangian: `vertex` (Prop. 6.5 of
    /// Casimiro and Rodrigo, a split step in closed form) or `symmetric` (the density
    /// averaged over each cell's three vertices: much slower, and only for a
    /// uniform rod without damping or end loads).
    #[schemars(extend("default" = "vertex", "enum" = ["vertex", "symmetric"]))]
    pub quadrature: Option<String>,
    /// The frame of each cell's shear strain: `vertex` (the base vertex's, as
    /// in Prop. 6.5: it locks in bending, so it needs material points closer
    /// than the radius) or `centred` (halfway to the neighbouring material
    /// point: no locking, about 11 % more per step; only with
    /// `quadrature = "vertex"`).
    #[schemars(extend("default" = "vertex", "enum" = ["vertex", "centred"]))]
    pub shear_frame: Option<String>,
}
