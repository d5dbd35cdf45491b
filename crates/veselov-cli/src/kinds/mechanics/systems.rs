//! Turning a scenario's `[model]` into a concrete system of fixed dimension,
//! and handing it to a job (run, verify) generic over that dimension.

use std::collections::BTreeMap;
use std::rc::Rc;

use nalgebra::{Matrix1, SVector, Vector1, Vector2};
use veselov::mechanics::{
    Force, GalerkinIntegrator, GalerkinScheme, Lagrangian, Method, NoForce, OneStepMap, PhaseState, Potential,
    SeparableIntegrator, SeparableLagrangian, Symmetry, energy, momentum_map, velocity_from_momentum,
};
use veselov::models::{
    DampedOscillator, DoublePendulum, HarmonicOscillator, HenonHeiles, Kepler, LinearDrag, Pendulum, VanDerPol,
};
use veselov::sem::{SemAction, SemIntegrator, SemRule, VariableStepMap};
use veselov::solve::NewtonOptions;

use super::custom::{CustomForce, CustomLagrangian, CustomSymmetry, MAX_DIMENSION, invariance_samples};
use super::schema::LoadedScenario;
use crate::catalog;
use crate::error::CliError;

/// Builds a one-step map for a method and step.
pub type MapFactory<const N: usize> =
    Box<dyn Fn(Method, f64, NewtonOptions) -> veselov::Result<Box<dyn OneStepMap<N>>>>;
/// A function of the state.
pub type StateFn<const N: usize> = Box<dyn Fn(&PhaseState<N>) -> f64>;
/// The exact state at time `t` from an initial state, where known.
pub type ExactFn<const N: usize> = Box<dyn Fn(&PhaseState<N>, f64) -> Option<PhaseState<N>>>;
/// Initial state from `(t, q, v)`.
pub type FromVelocity<const N: usize> =
    Box<dyn Fn(f64, SVector<f64, N>, SVector<f64, N>) -> veselov::Result<PhaseState<N>>>;

/// A system ready to integrate, with its diagnostics.
pub struct System<const N: usize> {
    /// Model name.
    pub model: String,
    /// Coordinate names.
    pub coordinates: Vec<String>,
    /// Whether a generalised force acts (then the work of forces is reported).
    pub forced: bool,
    /// Integrator factory (fast separable path where the model allows it).
    pub make_map: MapFactory<N>,
    /// Energy `E = v·∂L/∂v − L`.
    pub energy: StateFn<N>,
    /// Momentum maps, by name.
    pub momenta: Vec<(String, StateFn<N>)>,
    /// Default initial state of built-in models.
    pub default_initial: Option<PhaseState<N>>,
    /// Exact solution, where known.
    pub exact: Option<ExactFn<N>>,
    /// Continuous Legendre transform for `[initial] v`.
    pub from_velocity: FromVelocity<N>,
    /// Variable-step SEM integrator factory (unforced systems only).
    pub make_sem: Option<SemFactory<N>>,
}

/// Builds a variable-step SEM integrator for a rule.
pub type SemFactory<const N: usize> = Box<dyn Fn(SemRule) -> veselov::Result<Box<dyn VariableStepMap<N>>>>;

fn sem_factory<const N: usize, L: Lagrangian<N> + Clone + 'static>(l: Rc<L>, forced: bool) -> Option<SemFactory<N>> {
    (!forced).then(|| {
        Box::new(move |rule| {
            Ok(Box::new(SemIntegrator::new(SemAction::new((*l).clone(), rule)?)) as Box<dyn VariableStepMap<N>>)
        }) as SemFactory<N>
    })
}

/// Something to do with a system of any dimension.
pub trait Job {
    /// Do it.
    fn run<const N: usize>(self, scenario: &LoadedScenario, system: System<N>) -> Result<(), CliError>;
    /// Do it for a custom model with more than [`super::custom::MAX_FIXED_DIMENSION`]
    /// coordinates (the run-time-dimension integrator).
    fn run_dynamic(self, scenario: &LoadedScenario) -> Result<(), CliError>;
}

fn general_energy<const N: usize, L: Lagrangian<N> + 'static>(l: Rc<L>) -> StateFn<N> {
    Box::new(
        move |x: &PhaseState<N>| match velocity_from_momentum(&*l, x.t, &x.q, &x.p) {
            Ok(v) => energy(&*l, x.t, &x.q, &v),
            Err(_) => f64::NAN,
        },
    )
}

fn from_velocity<const N: usize, L: Lagrangian<N> + 'static>(l: Rc<L>) -> FromVelocity<N> {
    Box::new(move |t, q, v| PhaseState::from_velocity(&*l, t, q, v))
}

/// A system around the Lagrangian `l` with the integrator factory `make_map`.
fn system<const N: usize, L: Lagrangian<N> + Clone + 'static>(
    name: &str,
    coordinates: Vec<String>,
    l: Rc<L>,
    forced: bool,
    make_map: MapFactory<N>,
) -> System<N> {
    System {
        model: name.to_string(),
        coordinates,
        forced,
        make_map,
        energy: general_energy(l.clone()),
        momenta: Vec::new(),
        default_initial: None,
        exact: None,
        make_sem: sem_factory(l.clone(), forced),
        from_velocity: from_velocity(l),
    }
}

/// System for a separable Lagrangian (fast fixed-point path, Newton fallback).
fn separable<const N: usize, V: Potential<N> + Clone + 'static, F: Force<N> + Clone + 'static>(
    name: &str,
    coordinates: &[&str],
    lagrangian: SeparableLagrangian<V, N>,
    force: F,
) -> System<N> {
    let l = Rc::new(lagrangian);
    let factory = l.clone();
    let forced = !force.is_zero();
    let make_map: MapFactory<N> = Box::new(move |m, h, options| {
        let map = SeparableIntegrator::with_force((*factory).clone(), force.clone(), GalerkinScheme::new(m)?, h)?
            .with_newton_options(options);
        Ok(Box::new(map) as Box<dyn OneStepMap<N>>)
    });
    system(
        name,
        coordinates.iter().map(|s| s.to_string()).collect(),
        l,
        forced,
        make_map,
    )
}

/// System for a general Lagrangian (exact-Newton path).
fn general<const N: usize, L: Lagrangian<N> + Clone + 'static, F: Force<N> + Clone + 'static>(
    name: &str,
    coordinates: Vec<String>,
    lagrangian: L,
    force: F,
) -> System<N> {
    let l = Rc::new(lagrangian);
    let factory = l.clone();
    let forced = !force.is_zero();
    let make_map: MapFactory<N> = Box::new(move |m, h, options| {
        let map = GalerkinIntegrator::with_force((*factory).clone(), force.clone(), GalerkinScheme::new(m)?, h)?
            .with_options(options);
        Ok(Box::new(map) as Box<dyn OneStepMap<N>>)
    });
    system(name, coordinates, l, forced, make_map)
}

fn symmetry_fn<const N: usize, S: Symmetry<N> + 'static>(s: S) -> (String, StateFn<N>) {
    (
        s.name().to_string(),
        Box::new(move |x: &PhaseState<N>| momentum_map(&s, &x.q, &x.p)),
    )
}

/// Resolve model parameters against the catalogue: unknown keys are errors, missing ones take defaults.
fn params(scenario: &LoadedScenario, info: &catalog::ModelInfo) -> Result<BTreeMap<&'static str, f64>, CliError> {
    let given = &scenario.scenario.model.params;
    for key in given.keys() {
        if !info.params.iter().any(|p| p.name == key) {
            let known: Vec<&str> = info.params.iter().map(|p| p.name).collect();
            let expected = if known.is_empty() {
                "this model has no parameters".to_string()
            } else {
                format!("expected one of: {}", known.join(", "))
            };
            return Err(scenario.key_error(
                &format!("model.params.{key}"),
                format!("unknown parameter for model `{}`; {expected}", info.name),
            ));
        }
    }
    Ok(info
        .params
        .iter()
        .map(|p| (p.name, given.get(p.name).copied().unwrap_or(p.default)))
        .collect())
}

fn setup<'a>(scenario: &'a LoadedScenario, key: &str) -> impl Fn(veselov::Error) -> CliError + 'a {
    let key = key.to_string();
    move |e| scenario.key_error(&key, e.to_string())
}

fn reject_custom_keys(scenario: &LoadedScenario) -> Result<(), CliError> {
    let m = &scenario.scenario.model;
    let custom_keys = [
        ("coordinates", m.coordinates.is_some()),
        ("lagrangian", m.lagrangian.is_some()),
        ("force", m.force.is_some()),
        ("symmetries", !m.symmetries.is_empty()),
        ("constants", !m.constants.is_empty()),
    ];
    for (key, present) in custom_keys {
        if present {
            return Err(scenario.key_error(
                &format!("model.{key}"),
                format!(
                    "only valid with name = \"custom\", not with the built-in model `{}`",
                    m.name
                ),
            ));
        }
    }
    Ok(())
}

/// Build the scenario's system and run `job` on it.
pub fn dispatch<J: Job>(scenario: &LoadedScenario, job: J) -> Result<(), CliError> {
    let name = scenario.scenario.model.name.as_str();
    let Some(info) = catalog::model(name) else {
        let names: Vec<&str> = catalog::MODELS.iter().map(|m| m.name).collect();
        return Err(scenario.key_error(
            "model.name",
            format!("unknown model `{name}`, expected one of: {}", names.join(", ")),
        ));
    };
    if name == "custom" {
        return dispatch_custom(scenario, job);
    }
    reject_custom_keys(scenario)?;
    let p = params(scenario, info)?;
    match name {
        "harmonic" => {
            let model = HarmonicOscillator::new(p["mass"], p["omega"]).map_err(setup(scenario, "model.params"))?;
            let mut s = separable("harmonic", info.coordinates, model.system(), NoForce);
            s.default_initial = Some(PhaseState::new(0.0, Vector1::new(1.0), Vector1::new(0.0)));
            s.exact = Some(Box::new(move |x0, t| Some(model.exact(x0, t))));
            job.run(scenario, s)
        }
        "pendulum" => {
            let model = Pendulum::new(p["mass"], p["length"], p["gravity"]).map_err(setup(scenario, "model.params"))?;
            let mut s = separable("pendulum", info.coordinates, model.system(), NoForce);
            s.default_initial = Some(PhaseState::new(0.0, Vector1::new(1.0), Vector1::new(0.0)));
            s.exact = Some(Box::new(move |x0, t| model.exact(x0, t).ok()));
            job.run(scenario, s)
        }
        "kepler" => {
            let model = Kepler::new(p["eccentricity"]).map_err(setup(scenario, "model.params.eccentricity"))?;
            let mut s = separable("kepler", info.coordinates, model.system(), NoForce);
            let reference = model.initial_state();
            s.default_initial = Some(reference);
            s.exact = Some(Box::new(move |x0, t| {
                // Exact only for the documented reference orbit.
                if (x0.q - reference.q).amax() == 0.0 && (x0.p - reference.p).amax() == 0.0 && x0.t == 0.0 {
                    model.exact(t).ok()
                } else {
                    None
                }
            }));
            s.momenta.push(symmetry_fn(Kepler::angular_symmetry()));
            job.run(scenario, s)
        }
        "henon-heiles" => {
            let mut s = separable("henon-heiles", info.coordinates, HenonHeiles.system(), NoForce);
            s.default_initial = Some(HenonHeiles::initial_state());
            job.run(scenario, s)
        }
        "double-pendulum" => {
            let model = DoublePendulum::new(p["m1"], p["m2"], p["l1"], p["l2"], p["gravity"])
                .map_err(setup(scenario, "model.params"))?;
            let mut s = general(
                "double-pendulum",
                info.coordinates.iter().map(|c| c.to_string()).collect(),
                model,
                NoForce,
            );
            s.default_initial = Some(PhaseState::new(0.0, Vector2::new(0.5, -0.5), Vector2::zeros()));
            job.run(scenario, s)
        }
        "damped-oscillator" => {
            let (m, k, d) = (p["mass"], p["stiffness"], p["damping"]);
            let model = DampedOscillator::<1>::new(Matrix1::new(m), Matrix1::new(k), Matrix1::new(d))
                .map_err(setup(scenario, "model.params"))?;
            let mut s = separable("damped-oscillator", info.coordinates, model.system(), model.force());
            s.default_initial = Some(PhaseState::new(0.0, Vector1::new(1.0), Vector1::new(0.0)));
            job.run(scenario, s)
        }
        "van-der-pol" => {
            let model = VanDerPol::new(p["epsilon"], p["rho"], p["lambda"]).map_err(setup(scenario, "model.params"))?;
            let mut s = separable("van-der-pol", info.coordinates, model.system(), model.force());
            s.default_initial = Some(VanDerPol::initial_state());
            job.run(scenario, s)
        }
        "damped-kepler" => {
            let model = Kepler::new(p["eccentricity"]).map_err(setup(scenario, "model.params.eccentricity"))?;
            let drag = LinearDrag::new(p["drag"]).map_err(setup(scenario, "model.params.drag"))?;
            let mut s = separable("damped-kepler", info.coordinates, model.system(), drag);
            s.default_initial = Some(model.initial_state());
            s.momenta.push(symmetry_fn(Kepler::angular_symmetry()));
            job.run(scenario, s)
        }
        _ => Err(scenario.key_error("model.name", format!("model `{name}` is listed but not runnable"))),
    }
}

fn custom_system<const N: usize>(scenario: &LoadedScenario) -> Result<System<N>, CliError> {
    let m = &scenario.scenario.model;
    let coordinates = m.coordinates.clone().unwrap_or_default();
    let lagrangian = CustomLagrangian::<N>::new(scenario, &coordinates)?;
    let checked = lagrangian.clone();
    let mut system = match &m.force {
        Some(f) => general(
            "custom",
            coordinates.clone(),
            lagrangian,
            CustomForce::<N>::new(scenario, f, &coordinates)?,
        ),
        None => general("custom", coordinates.clone(), lagrangian, NoForce),
    };
    for (name, generator) in &m.symmetries {
        let s = CustomSymmetry::<N>::new(scenario, name, generator, &coordinates)?;
        check_invariance(scenario, name, &checked, &s)?;
        system.momenta.push(symmetry_fn(s));
    }
    Ok(system)
}

/// Refuse a declared symmetry under which the Lagrangian is not invariant:
/// `δL = ∂L/∂q·ξ + ∂L/∂v·Dξ v` is evaluated exactly at eight states spread
/// over `|q_i|, |v_i| ∈ [0.3, 1.3]` (either sign) and `t ∈ [0, 1]` (states
/// where `L` is not finite are skipped), and must be round-off against the
/// terms it is made of (1e-9 of them). Its momentum map would not be
/// conserved, and the run would report the drift as an integrator error.
fn check_invariance<const N: usize>(
    scenario: &LoadedScenario,
    name: &str,
    lagrangian: &CustomLagrangian<N>,
    symmetry: &CustomSymmetry<N>,
) -> Result<(), CliError> {
    for (t, q, v) in invariance_samples(N) {
        let (q, v) = (
            SVector::<f64, N>::from_column_slice(&q),
            SVector::<f64, N>::from_column_slice(&v),
        );
        let (defect, size) = veselov::mechanics::invariance_defect(lagrangian, symmetry, t, &q, &v);
        check_defect(scenario, name, (defect, size), (t, q.as_slice(), v.as_slice()))?;
    }
    Ok(())
}

/// Refuse the symmetry `name` if its invariance defect `δL` at `(t, q, v)`
/// is more than round-off (1e-9) of the `size` of the terms it is made of;
/// states where either is not finite are skipped.
pub(crate) fn check_defect(
    scenario: &LoadedScenario,
    name: &str,
    (defect, size): (f64, f64),
    (t, q, v): (f64, &[f64], &[f64]),
) -> Result<(), CliError> {
    if !(defect.is_finite() && size.is_finite()) || defect.abs() <= 1e-9 * size.max(f64::MIN_POSITIVE) {
        return Ok(());
    }
    Err(scenario.key_error(
        &format!("model.symmetries.{name}"),
        format!(
            "the Lagrangian is not invariant under this generator: δL = ∂L/∂q·ξ + ∂L/∂v·Dξ·v = {defect:e} \
             at t = {t}, q = {q:?}, v = {v:?}, so its momentum map is not conserved (a quasi-symmetry, \
             invariant only up to a total derivative, cannot be declared)"
        ),
    ))
}

fn dispatch_custom<J: Job>(scenario: &LoadedScenario, job: J) -> Result<(), CliError> {
    let m = &scenario.scenario.model;
    if !m.params.is_empty() {
        return Err(scenario.key_error("model.params", "custom models take `constants`, not `params`"));
    }
    let Some(coords) = &m.coordinates else {
        return Err(scenario.key_error("model.coordinates", "custom models need a list of coordinate names"));
    };
    if m.lagrangian.is_none() {
        return Err(scenario.key_error("model.lagrangian", "custom models need a Lagrangian expression"));
    }
    match coords.len() {
        1 => job.run(scenario, custom_system::<1>(scenario)?),
        2 => job.run(scenario, custom_system::<2>(scenario)?),
        3 => job.run(scenario, custom_system::<3>(scenario)?),
        4 => job.run(scenario, custom_system::<4>(scenario)?),
        5 => job.run(scenario, custom_system::<5>(scenario)?),
        6 => job.run(scenario, custom_system::<6>(scenario)?),
        n if n <= MAX_DIMENSION => job.run_dynamic(scenario),
        n => Err(scenario.key_error(
            "model.coordinates",
            format!("expected between 1 and {MAX_DIMENSION} coordinates, got {n}"),
        )),
    }
}
