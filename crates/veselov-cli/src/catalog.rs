//! The built-in models and methods as the command presents them: names,
//! parameters with defaults, coordinates, default initial data, invariants.

use veselov::mechanics::{GalerkinScheme, Method};
use veselov::sem::SemRule;

/// A method as chosen in a scenario: fixed-step variational or variable-step SEM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Choice {
    /// A fixed-step (forced) variational integrator.
    Fixed(Method),
    /// A variable-step symplectic-energy-momentum integrator; `dt` is the first step.
    Variable(SemRule),
}

/// A model parameter with its default.
pub struct Param {
    /// Key in `[model] params`.
    pub name: &'static str,
    /// Default value.
    pub default: f64,
    /// Meaning and unit.
    pub doc: &'static str,
}

/// A structural model (a field on a lattice, with its own tables of keys
/// rather than `params`) as listed by `veselov models`.
pub struct StructureInfo {
    /// Value of `[model] name`.
    pub name: &'static str,
    /// One-line description.
    pub summary: &'static str,
    /// Its tables and main keys.
    pub keys: &'static str,
    /// Where its scenarios are shown.
    pub examples: &'static str,
}

/// The beam and the rod.
pub const STRUCTURES: &[StructureInfo] = &[
    StructureInfo {
        name: "beam",
        summary: "geometrically exact beam on SE(3) (Demoures–Gay-Balmaz–Ratiu §5), marched in time or in space",
        keys: "[model] length, nodes, radius | width + height, density, young, poisson | shear_modulus, \
               shear_coefficient; [method] evolution, retraction; [ends]; [loads] gravity, damping; [initial] shape",
        examples: "examples/beam_*.toml",
    },
    StructureInfo {
        name: "cosserat-rod",
        summary: "Cosserat rod on the leapfrog lattice (Casimiro–Rodrigo §6): conserved discrete momenta, loads and damping",
        keys: "[model] length, nodes, radius | width + height, density, young (numbers or expressions in s), \
               poisson | shear_modulus, shear_coefficient; [ends] free | clamped | driven; [loads] gravity, damping, \
               end_force, end_torque, ramp; [initial] shape = straight | bent | helix | curve; [time] t_end, \
               dt | step_number",
        examples: "examples/rod_*.toml",
    },
];

/// A built-in model as listed by `veselov models`.
pub struct ModelInfo {
    /// Scenario name.
    pub name: &'static str,
    /// One-line description with the Lagrangian.
    pub summary: &'static str,
    /// Coordinate names.
    pub coordinates: &'static [&'static str],
    /// Parameters.
    pub params: &'static [Param],
    /// Default initial data, as documented.
    pub default_initial: &'static str,
    /// Invariants reported as momentum-map columns.
    pub symmetries: &'static [&'static str],
    /// Reference used by `veselov verify`.
    pub reference: &'static str,
}

/// Every built-in model.
pub const MODELS: &[ModelInfo] = &[
    ModelInfo {
        name: "harmonic",
        summary: "harmonic oscillator, L = ½ m v² − ½ m ω² q²",
        coordinates: &["q"],
        params: &[
            Param {
                name: "mass",
                default: 1.0,
                doc: "mass m",
            },
            Param {
                name: "omega",
                default: 1.0,
                doc: "angular frequency ω (rad per time unit)",
            },
        ],
        default_initial: "q = [1.0], p = [0.0]",
        symmetries: &[],
        reference: "exact solution",
    },
    ModelInfo {
        name: "pendulum",
        summary: "simple pendulum, L = ½ m ℓ² θ̇² + m g ℓ cos θ (θ = 0 hangs down)",
        coordinates: &["theta"],
        params: &[
            Param {
                name: "mass",
                default: 1.0,
                doc: "bob mass m",
            },
            Param {
                name: "length",
                default: 1.0,
                doc: "rod length ℓ",
            },
            Param {
                name: "gravity",
                default: 1.0,
                doc: "gravitational acceleration g",
            },
        ],
        default_initial: "q = [1.0] (rad), p = [0.0]",
        symmetries: &[],
        reference: "exact solution (Jacobi elliptic functions)",
    },
    ModelInfo {
        name: "kepler",
        summary: "Kepler problem, L = ½|v|² + 1/|q| (GM = 1; orbits of semi-major axis 1 have period 2π)",
        coordinates: &["x", "y"],
        params: &[Param {
            name: "eccentricity",
            default: 0.5,
            doc: "eccentricity e ∈ [0, 1) of the default orbit",
        }],
        default_initial: "pericentre of the orbit with eccentricity e: q = [1 − e, 0], p = [0, √((1+e)/(1−e))]",
        symmetries: &["angular"],
        reference: "exact solution (Kepler's equation) from the default initial data; otherwise a fine Gauss s = 5 run",
    },
    ModelInfo {
        name: "henon-heiles",
        summary: "Hénon–Heiles, L = ½|v|² − ½(x² + y²) − x²y + y³/3",
        coordinates: &["x", "y"],
        params: &[],
        default_initial: "q = [0, 0.1], p = [√(2(1/8 − V(q))), 0] (energy 1/8)",
        symmetries: &[],
        reference: "fine Gauss s = 5 run",
    },
    ModelInfo {
        name: "double-pendulum",
        summary: "planar double pendulum (non-separable: mass matrix depends on θ₁ − θ₂)",
        coordinates: &["theta1", "theta2"],
        params: &[
            Param {
                name: "m1",
                default: 1.0,
                doc: "upper mass",
            },
            Param {
                name: "m2",
                default: 1.0,
                doc: "lower mass",
            },
            Param {
                name: "l1",
                default: 1.0,
                doc: "upper rod length",
            },
            Param {
                name: "l2",
                default: 1.0,
                doc: "lower rod length",
            },
            Param {
                name: "gravity",
                default: 1.0,
                doc: "gravitational acceleration g",
            },
        ],
        default_initial: "q = [0.5, -0.5] (rad), p = [0, 0]",
        symmetries: &[],
        reference: "fine Gauss s = 5 run",
    },
    ModelInfo {
        name: "damped-oscillator",
        summary: "damped oscillator, L = ½ m v² − ½ k q², force F = −d v (Martín de Diego–Sato Martín de Almagro, Example 7.2 in one dimension)",
        coordinates: &["q"],
        params: &[
            Param {
                name: "mass",
                default: 1.0,
                doc: "mass m",
            },
            Param {
                name: "stiffness",
                default: 1.0,
                doc: "spring constant k",
            },
            Param {
                name: "damping",
                default: 0.1,
                doc: "damping coefficient d (d > 0 dissipates)",
            },
        ],
        default_initial: "q = [1.0], p = [0.0]",
        symmetries: &[],
        reference: "fine Gauss s = 5 run",
    },
    ModelInfo {
        name: "van-der-pol",
        summary: "two coupled van der Pol oscillators (Martín de Diego–Sato Martín de Almagro §7.1), L = ½|v|² − ½[q₁² + (1+ρ)q₂²] − λ(q₁−q₂)², F = ((ε−q₁²)v₁, (ε−q₂²)v₂)",
        coordinates: &["q1", "q2"],
        params: &[
            Param {
                name: "epsilon",
                default: 0.5,
                doc: "anti-damping strength ε",
            },
            Param {
                name: "rho",
                default: 0.02,
                doc: "detuning ρ",
            },
            Param {
                name: "lambda",
                default: 0.8,
                doc: "coupling λ",
            },
        ],
        default_initial: "q = [−0.5, −0.25], p = [0, 4] (the paper's)",
        symmetries: &[],
        reference: "fine Gauss s = 5 run",
    },
    ModelInfo {
        name: "damped-kepler",
        summary: "Kepler problem with linear drag F = −c v: the orbit spirals in",
        coordinates: &["x", "y"],
        params: &[
            Param {
                name: "eccentricity",
                default: 0.5,
                doc: "eccentricity of the initial osculating orbit",
            },
            Param {
                name: "drag",
                default: 0.01,
                doc: "drag coefficient c ≥ 0",
            },
        ],
        default_initial: "pericentre of the orbit with eccentricity e (as for kepler)",
        symmetries: &["angular"],
        reference: "fine Gauss s = 5 run",
    },
    ModelInfo {
        name: "rigid-body",
        summary: "free rigid body on SO(3), ℓ = ½ Ωᵀ𝕀Ω; keys inertia (3 principal moments or 9 entries, default [1, 2, 3])",
        coordinates: &[],
        params: &[],
        default_initial: "identity attitude, Ω = [0.05, 1, 0.05] (near the unstable middle axis: periodic flips)",
        symmetries: &["J_x", "J_y", "J_z (spatial angular momentum)"],
        reference: "RK4 on the Euler–Poincaré equations (test suite)",
    },
    ModelInfo {
        name: "heavy-top",
        summary: "heavy top on SO(3), ℓ = ½ Ωᵀ𝕀Ω − m g e₃·Rχ; keys inertia (about the pivot, default [1, 1, 0.5]), \
                  mass (1), centre_of_mass (body frame, [0, 0, 1]), gravity (9.81, along −z)",
        coordinates: &[],
        params: &[],
        default_initial: "rotation_vector = [0.3, 0, 0], Ω = [0, 0, 20] (fast top: precession and nutation)",
        symmetries: &["J_z (vertical spatial angular momentum)"],
        reference: "RK4 on the Euler–Poincaré equations (test suite)",
    },
    ModelInfo {
        name: "rigid-body-se3",
        summary: "free-flying rigid body on SE(3), ℓ = ½ Ωᵀ𝕀Ω + ½ m|v|²; keys inertia (default [1, 2, 3]), mass (1)",
        coordinates: &[],
        params: &[],
        default_initial: "identity attitude at the origin, Ω = [0.05, 1, 0.05], body velocity v = [1, 0, 0]",
        symmetries: &["J_angular_x..z", "J_linear_x..z (spatial momentum)"],
        reference: "RK4 on the Euler–Poincaré equations (test suite)",
    },
    ModelInfo {
        name: "sine-gordon",
        summary: "lattice field (Marsden–Patrick–Shkoller §5): φ_tt − φ_xx + sin φ = 0, 𝓛 = ½(φ_t² − φ_x²) + cos φ; keys [lattice], [method] scheme",
        coordinates: &[],
        params: &[],
        default_initial: "required: [initial] kind = kink-antikink | kink | breather",
        symmetries: &[],
        reference: "the next finer run of a refinement (`--refine`, `--nodes`; Richardson estimate); test suite: breather and kink",
    },
    ModelInfo {
        name: "wave",
        summary: "lattice field: φ_tt − φ_xx = 0 (N = 0)",
        coordinates: &[],
        params: &[],
        default_initial: "required: [initial] kind = dalembert",
        symmetries: &["shift_charge (periodic lattices)"],
        reference: "the next finer run of a refinement (`--refine`, `--nodes`; Richardson estimate); test suite: d'Alembert",
    },
    ModelInfo {
        name: "klein-gordon-phi4",
        summary: "lattice field: φ_tt − φ_xx + m²φ + λφ³ = 0, N = −½m²φ² − ¼λφ⁴; params m2 (1), lambda (1)",
        coordinates: &[],
        params: &[],
        default_initial: "required: [initial] kind (breather or dalembert profiles as data)",
        symmetries: &[],
        reference: "the next finer run of a refinement (`--refine`, `--nodes`; Richardson estimate)",
    },
    ModelInfo {
        name: "klein-gordon-complex",
        summary: "complex lattice field φ ∈ R²: φ_tt − φ_xx + (m² + λ|φ|²)φ = 0; params m2 (1), lambda (1); generic path",
        coordinates: &[],
        params: &[],
        default_initial: "required: [initial] kind = plane-wave (amplitude, mode): exact",
        symmetries: &["phase_charge (split Noether charge of the phase rotation)"],
        reference: "the next finer run of a refinement (`--refine`, `--nodes`; Richardson estimate); test suite: exact plane wave",
    },
    ModelInfo {
        name: "custom",
        summary: "any Lagrangian given as an expression: keys coordinates, lagrangian, force (optional), constants, symmetries",
        coordinates: &[],
        params: &[],
        default_initial: "required: [initial] q and p or v",
        symmetries: &[],
        reference: "fine Gauss s = 5 run",
    },
];

/// Look up a model by name.
pub fn model(name: &str) -> Option<&'static ModelInfo> {
    MODELS.iter().find(|m| m.name == name)
}

/// A method as listed by `veselov methods`.
pub struct MethodInfo {
    /// Scenario name.
    pub name: &'static str,
    /// Keys it takes.
    pub keys: &'static str,
    /// Order and properties.
    pub properties: &'static str,
}

/// Every method.
pub const METHODS: &[MethodInfo] = &[
    MethodInfo {
        name: "midpoint",
        keys: "dt",
        properties: "order 2; symplectic; conserves momentum maps of linear symmetries; = galerkin-gauss s = 1",
    },
    MethodInfo {
        name: "trapezoid",
        keys: "dt",
        properties: "order 2; symplectic; = galerkin-lobatto s = 2 (Störmer–Verlet for separable L)",
    },
    MethodInfo {
        name: "alpha",
        keys: "dt, alpha ∈ [0, 1] (required)",
        properties: "order 2 for α = ½, else 1; symplectic",
    },
    MethodInfo {
        name: "galerkin-lobatto",
        keys: "dt, stages = 2..10 (default 3)",
        properties: "order 2s − 2; symplectic; = Lobatto IIIA–IIIB",
    },
    MethodInfo {
        name: "galerkin-gauss",
        keys: "dt, stages = 1..10 (default 2)",
        properties: "order 2s; symplectic; = Gauss collocation",
    },
    MethodInfo {
        name: "sem-midpoint",
        keys: "dt (first step; later steps follow from the energy equation)",
        properties: "variable step, order 2; discrete energy and Noether momenta exact; the default SEM rule",
    },
    MethodInfo {
        name: "sem-averaged",
        keys: "dt, stages = Gauss nodes of the potential average (default 2)",
        properties: "variable step, order 2; Lee-type average, robust for Kepler-like potentials",
    },
    MethodInfo {
        name: "sem-trapezoid",
        keys: "dt",
        properties: "variable step, order 2; degenerates on every oscillator orbit (reference only)",
    },
    MethodInfo {
        name: "sem-leftpoint",
        keys: "dt",
        properties: "variable step, order 1; the paper's (3.18); fails at turning points (reference only)",
    },
    MethodInfo {
        name: "lie-group trapezoid (rigid-body models)",
        keys: "retraction (cayley | exp, default cayley), dt",
        properties: "order 2; symplectic on T*G; conserves the spatial momentum of symmetric bodies to round-off; \
                     keeps RᵀR = I to round-off",
    },
];

/// Translate `[method]` into a [`Choice`], or explain what is wrong with which key.
pub fn choice(name: &str, stages: Option<usize>, alpha: Option<f64>) -> Result<Choice, (String, String)> {
    let rule = match name {
        "sem-midpoint" => Some(SemRule::Midpoint),
        "sem-trapezoid" => Some(SemRule::Trapezoid),
        "sem-leftpoint" => Some(SemRule::LeftPoint),
        "sem-averaged" => Some(SemRule::Averaged(stages.unwrap_or(2))),
        _ => None,
    };
    let Some(rule) = rule else {
        return method(name, stages, alpha).map(Choice::Fixed);
    };
    if alpha.is_some() {
        return Err(("method.alpha".into(), format!("method `{name}` has no α")));
    }
    if stages.is_some() && name != "sem-averaged" {
        return Err(("method.stages".into(), format!("method `{name}` has no stages")));
    }
    if let SemRule::Averaged(s) = rule
        && !(1..=10).contains(&s)
    {
        return Err((
            "method.stages".into(),
            format!("sem-averaged needs 1 ≤ stages ≤ 10, got {s}"),
        ));
    }
    Ok(Choice::Variable(rule))
}

/// Translate a fixed-step `[method]` into a [`Method`], or explain what is wrong with which key.
pub fn method(name: &str, stages: Option<usize>, alpha: Option<f64>) -> Result<Method, (String, String)> {
    let no_stages = |m: Method| match stages {
        Some(_) => Err(("method.stages".to_string(), format!("method `{name}` has no stages"))),
        None => Ok(m),
    };
    let no_alpha = |m: Method| match alpha {
        Some(_) => Err(("method.alpha".to_string(), format!("method `{name}` has no α"))),
        None => Ok(m),
    };
    let m = match name {
        "midpoint" => no_alpha(no_stages(Method::Midpoint)?)?,
        "trapezoid" => no_alpha(no_stages(Method::Trapezoid)?)?,
        "alpha" => {
            let a = alpha.ok_or((
                "method.alpha".to_string(),
                "method `alpha` needs `alpha` in [0, 1]".to_string(),
            ))?;
            no_stages(Method::Alpha(a))?
        }
        "galerkin-lobatto" => no_alpha(Method::GalerkinLobatto(stages.unwrap_or(3)))?,
        "galerkin-gauss" => no_alpha(Method::GalerkinGauss(stages.unwrap_or(2)))?,
        other => {
            let names: Vec<&str> = METHODS.iter().map(|m| m.name).collect();
            return Err((
                "method.name".to_string(),
                format!("unknown method `{other}`, expected one of: {}", names.join(", ")),
            ));
        }
    };
    GalerkinScheme::new(m).map_err(|e| {
        let key = if matches!(m, Method::Alpha(_)) {
            "method.alpha"
        } else {
            "method.stages"
        };
        (key.to_string(), e.to_string())
    })?;
    Ok(m)
}

/// The reference of the expression language of custom models, as
/// `veselov expressions` prints it.
pub fn expressions_reference() -> String {
    let functions = veselov::expr::FUNCTIONS.join(" ");
    let constants: Vec<String> = veselov::expr::CONSTANTS
        .iter()
        .map(|(n, v)| format!("{n} = {v}"))
        .collect();
    format!(
        "\
Custom models: [model] name = \"custom\", with expressions in text.

  [model]
  name = \"custom\"
  coordinates = [\"x\", \"y\"]                      # 1 to {max} names: letters, digits, _ (not t)
  lagrangian = \"0.5*(x_dot^2 + y_dot^2) + k/sqrt(x^2 + y^2)\"
  force = [\"-c*x_dot\", \"-c*y_dot\"]              # optional: a generalised force, one per coordinate
  symmetries = {{ angular = [\"-y\", \"x\"] }}        # optional: generators ξ(q), one per coordinate
  constants = {{ k = 1.0, c = 0.01 }}             # optional: named numbers

Names in an expression:
  x, y, …      the coordinates
  x_dot, …     their velocities (<name>_dot; not in symmetries)
  t            the time
  k, c, …      the [model] constants
  {constants} (built in; a declared name takes precedence)

Operators: + - * / and ^ (right-associative: 2^3^2 = 2^9; -x^2 = -(x^2); 2^-1 = 0.5),
parentheses. Numbers: 1, 2.5, .5, 1e-3.

Functions: {functions}
  one argument each except pow(a, b) and atan2(y, x); log and ln are the natural
  logarithm; abs has derivative ±1 at ±0. a^b with a non-integer constant b uses
  powf, with a non-constant b exp(b·ln a), which needs a > 0.

Every derivative the integrators take is exact (automatic differentiation of the
parsed expression). Limits: {max} coordinates (beyond {fixed}, runs take fixed-step
methods without forces, and verify is not available), {nesting} levels of nested
parentheses, signs, powers and calls, and an expression tree {height} levels tall
(long sums and products are fine). Errors name the key and the column.
",
        max = crate::kinds::mechanics::custom::MAX_DIMENSION,
        fixed = crate::kinds::mechanics::custom::MAX_FIXED_DIMENSION,
        nesting = veselov::expr::MAX_NESTING,
        height = veselov::expr::MAX_HEIGHT,
        constants = constants.join(", "),
    )
}
