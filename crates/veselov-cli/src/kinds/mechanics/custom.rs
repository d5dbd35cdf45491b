//! Custom systems from expressions: the Lagrangian and symmetry generators of
//! a scenario, parsed once and evaluated generically over the AD scalar, so
//! every derivative the integrators need stays exact.
//!
//! Variables: the coordinate names, `<name>_dot` for velocities, `t`, and the
//! constants of `[model] constants`.

use nalgebra::SVector;
use veselov::ad::Scalar;
use veselov::expr::{Expr, SymbolTable};
use veselov::mechanics::{DynLagrangian, Force, Lagrangian, Symmetry};

use super::schema::LoadedScenario;
use crate::error::CliError;

/// Largest number of coordinates of a custom system integrated with a
/// dimension fixed at compile time (every method and option); beyond it the
/// run-time-dimension integrator takes over ([`DynCustomLagrangian`]).
pub const MAX_FIXED_DIMENSION: usize = 6;
const MAX_SLOTS: usize = 2 * MAX_FIXED_DIMENSION + 1;

/// Largest number of coordinates of a custom system.
pub const MAX_DIMENSION: usize = 64;

fn symbols(scenario: &LoadedScenario, coordinates: &[String], with_velocities: bool) -> Result<SymbolTable, CliError> {
    let mut table = SymbolTable::new();
    let key = |e: veselov::expr::ExprError| scenario.key_error("model.coordinates", e.to_string());
    for c in coordinates {
        let valid = c.chars().next().is_some_and(|ch| ch.is_ascii_alphabetic() || ch == '_')
            && c.chars().all(|ch| ch.is_ascii_alphanumeric() || ch == '_');
        if !valid || c == "t" {
            return Err(scenario.key_error(
                "model.coordinates",
                format!("`{c}` is not a valid coordinate name (letters, digits, _; not `t`)"),
            ));
        }
        table.variable(c).map_err(key)?;
    }
    if with_velocities {
        for c in coordinates {
            table.variable(&format!("{c}_dot")).map_err(key)?;
        }
    } else {
        // Keep slot positions aligned with the Lagrangian's table.
        for c in coordinates {
            table.variable(&format!("{c}_dot__unused")).map_err(key)?;
        }
    }
    table.variable("t").map_err(key)?;
    for (name, value) in &scenario.scenario.model.constants {
        table
            .constant(name, *value)
            .map_err(|e| scenario.key_error(&format!("model.constants.{name}"), e.to_string()))?;
    }
    Ok(table)
}

/// Eight states `(t, q, v)` in `n` coordinates spread over
/// `|q_i|, |v_i| ∈ [0.3, 1.3]` (either sign) and `t ∈ [0, 1]`, from a fixed
/// pseudo-random sequence, so that the check is the same on every run.
pub(crate) fn invariance_samples(n: usize) -> Vec<(f64, Vec<f64>, Vec<f64>)> {
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
        let sign = if seed & 1 == 0 { 1.0 } else { -1.0 };
        (u, sign)
    };
    (0..8)
        .map(|_| {
            let mut draw = || {
                let (u, sign) = next();
                sign * (0.3 + u)
            };
            let q: Vec<f64> = (0..n).map(|_| draw()).collect();
            let v: Vec<f64> = (0..n).map(|_| draw()).collect();
            (next().0, q, v)
        })
        .collect()
}

/// `[a, b, …]` with each number as [`crate::output::number`] writes it.
fn numbers(x: &[f64]) -> String {
    let items: Vec<String> = x.iter().map(|v| crate::output::number(*v)).collect();
    format!("[{}]", items.join(", "))
}

/// One expression per coordinate (`sources`, the key `key`), over the
/// coordinates and, `with_velocities`, their velocities and `t`; errors name
/// `key` or `key[i]`.
fn components(
    scenario: &LoadedScenario,
    key: &str,
    sources: &[String],
    coordinates: &[String],
    with_velocities: bool,
) -> Result<Vec<Expr>, CliError> {
    if sources.len() != coordinates.len() {
        return Err(scenario.key_error(
            key,
            format!(
                "expected {} expressions (one per coordinate), got {}",
                coordinates.len(),
                sources.len()
            ),
        ));
    }
    let table = symbols(scenario, coordinates, with_velocities)?;
    sources
        .iter()
        .enumerate()
        .map(|(i, src)| {
            Expr::parse(src, &table).map_err(|e| scenario.key_error(&format!("{key}[{i}]"), format!("\n{e}")))
        })
        .collect()
}

/// A Lagrangian given as an expression in `N` coordinates.
#[derive(Debug, Clone)]
pub struct CustomLagrangian<const N: usize> {
    expr: Expr,
}

/// Whether a custom scenario's Lagrangian depends on `t` explicitly (its
/// energy is then not conserved); `false` for built-in models and for a
/// Lagrangian that does not parse (the run refuses it elsewhere).
pub fn depends_on_time(scenario: &LoadedScenario) -> bool {
    let model = &scenario.scenario.model;
    if model.name != "custom" {
        return false;
    }
    let coordinates = model.coordinates.as_deref().unwrap_or_default();
    parse_lagrangian(scenario, coordinates).is_ok_and(|e| e.used_variables().iter().any(|v| v == "t"))
}

/// `[model] lagrangian`, parsed over `coordinates`, their velocities and `t`.
fn parse_lagrangian(scenario: &LoadedScenario, coordinates: &[String]) -> Result<Expr, CliError> {
    let table = symbols(scenario, coordinates, true)?;
    let source = scenario.scenario.model.lagrangian.as_deref().unwrap_or_default();
    Expr::parse(source, &table).map_err(|e| scenario.key_error("model.lagrangian", format!("\n{e}")))
}

impl<const N: usize> CustomLagrangian<N> {
    /// Parse `[model] lagrangian` over `coordinates`.
    pub fn new(scenario: &LoadedScenario, coordinates: &[String]) -> Result<Self, CliError> {
        Ok(Self {
            expr: parse_lagrangian(scenario, coordinates)?,
        })
    }
}

impl<const N: usize> Lagrangian<N> for CustomLagrangian<N> {
    fn lagrangian<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        eval_slots::<D, MAX_SLOTS>(&self.expr, t, q.as_slice(), v.as_slice())
    }
}

/// A symmetry generator `ξ_Q(q)` given as one expression per coordinate, in
/// `N` coordinates (the parsed generator of [`DynCustomSymmetry`]).
#[derive(Debug, Clone)]
pub struct CustomSymmetry<const N: usize> {
    inner: DynCustomSymmetry,
}

impl<const N: usize> CustomSymmetry<N> {
    /// Parse `[model] symmetries.<name>` (`coordinates` has `N` names).
    pub fn new(
        scenario: &LoadedScenario,
        name: &str,
        generator: &[String],
        coordinates: &[String],
    ) -> Result<Self, CliError> {
        Ok(Self {
            inner: DynCustomSymmetry::new(scenario, name, generator, coordinates)?,
        })
    }
}

impl<const N: usize> Symmetry<N> for CustomSymmetry<N> {
    fn name(&self) -> &str {
        &self.inner.name
    }
    fn generator<D: Scalar>(&self, q: &SVector<D, N>) -> SVector<D, N> {
        let mut out = SVector::<D, N>::from_element(D::from(0.0));
        self.inner.generator(q.as_slice(), out.as_mut_slice());
        out
    }
}

/// A generalised force `F(t, q, v)` given as one expression per coordinate.
#[derive(Debug, Clone)]
pub struct CustomForce<const N: usize> {
    components: Vec<Expr>,
}

impl<const N: usize> CustomForce<N> {
    /// Parse `[model] force`.
    pub fn new(scenario: &LoadedScenario, force: &[String], coordinates: &[String]) -> Result<Self, CliError> {
        Ok(Self {
            components: components(scenario, "model.force", force, coordinates, true)?,
        })
    }
}

impl<const N: usize> Force<N> for CustomForce<N> {
    fn force<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> SVector<D, N> {
        let vars = slots::<D, MAX_SLOTS>(t, q.as_slice(), v.as_slice());
        SVector::from_fn(|i, _| self.components[i].eval(&vars[..2 * N + 1]))
    }
}

/// The expression slots `[q, v, t]` (`v` may be empty: then zeros) in a
/// stack buffer of `K ≥ 2n + 1` slots, the layout of [`symbols`].
fn slots<D: Scalar, const K: usize>(t: D, q: &[D], v: &[D]) -> [D; K] {
    let n = q.len();
    let mut vars = [D::from(0.0); K];
    vars[..n].copy_from_slice(q);
    vars[n..n + v.len()].copy_from_slice(v);
    vars[2 * n] = t;
    vars
}

/// Evaluate `expr` on the slots `[q, v, t]` in a stack buffer of `K` slots.
fn eval_slots<D: Scalar, const K: usize>(expr: &Expr, t: D, q: &[D], v: &[D]) -> D {
    expr.eval(&slots::<D, K>(t, q, v)[..2 * q.len() + 1])
}

/// [`eval_slots`] with the smallest buffer that holds `2n + 1` slots.
fn eval_any<D: Scalar>(expr: &Expr, t: D, q: &[D], v: &[D]) -> D {
    match 2 * q.len() + 1 {
        0..=17 => eval_slots::<D, 17>(expr, t, q, v),
        18..=33 => eval_slots::<D, 33>(expr, t, q, v),
        34..=65 => eval_slots::<D, 65>(expr, t, q, v),
        _ => eval_slots::<D, { 2 * MAX_DIMENSION + 1 }>(expr, t, q, v),
    }
}

/// A Lagrangian given as an expression in a number of coordinates known at
/// run time (up to [`MAX_DIMENSION`]).
#[derive(Debug, Clone)]
pub struct DynCustomLagrangian {
    expr: Expr,
    n: usize,
}

impl DynCustomLagrangian {
    /// Parse `[model] lagrangian` over `coordinates` (at most [`MAX_DIMENSION`]).
    pub fn new(scenario: &LoadedScenario, coordinates: &[String]) -> Result<Self, CliError> {
        Ok(Self {
            expr: parse_lagrangian(scenario, coordinates)?,
            n: coordinates.len().min(MAX_DIMENSION),
        })
    }
}

impl DynLagrangian for DynCustomLagrangian {
    fn dim(&self) -> usize {
        self.n
    }
    fn lagrangian<D: Scalar>(&self, t: D, q: &[D], v: &[D]) -> D {
        eval_any(&self.expr, t, q, v)
    }
}

/// A symmetry generator `ξ_Q(q)` in a number of coordinates known at run time.
#[derive(Debug, Clone)]
pub struct DynCustomSymmetry {
    /// The name (the column `J_<name>`).
    pub name: String,
    components: Vec<Expr>,
}

impl DynCustomSymmetry {
    /// Parse `[model] symmetries.<name>`.
    pub fn new(
        scenario: &LoadedScenario,
        name: &str,
        generator: &[String],
        coordinates: &[String],
    ) -> Result<Self, CliError> {
        let key = format!("model.symmetries.{name}");
        let components = components(scenario, &key, generator, coordinates, false)?;
        let symmetry = Self {
            name: name.to_string(),
            components,
        };
        symmetry.check_finite(scenario, &key, coordinates.len())?;
        Ok(symmetry)
    }

    /// Refuse a generator that is not finite at the initial state, or at
    /// none of the states the invariance check samples: its momentum could
    /// not be computed (`1/0`, `sqrt(-1)`), and the run would fail at its
    /// first step instead.
    fn check_finite(&self, scenario: &LoadedScenario, key: &str, n: usize) -> Result<(), CliError> {
        let at = |q: &[f64]| {
            let mut xi = vec![0.0; n];
            self.generator(q, &mut xi);
            xi
        };
        let finite = |xi: &[f64]| xi.iter().all(|x| x.is_finite());
        if let Some(init) = &scenario.scenario.initial
            && let Ok(q0) = init.q.values(&scenario.path, "initial.q", &[n], "")
        {
            let xi = at(&q0);
            if !finite(&xi) {
                return Err(scenario.key_error(
                    key,
                    format!(
                        "the generator is not finite at the initial state q = {}: ξ = {}",
                        numbers(&q0),
                        numbers(&xi)
                    ),
                ));
            }
        }
        let samples = invariance_samples(n);
        if samples.iter().all(|(_, q, _)| !finite(&at(q))) {
            let q = samples.first().map(|s| s.1.clone()).unwrap_or_default();
            return Err(scenario.key_error(
                key,
                format!(
                    "the generator is not finite at any state of the invariance check (at q = {}: ξ = {})",
                    numbers(&q),
                    numbers(&at(&q))
                ),
            ));
        }
        Ok(())
    }

    /// `ξ_Q(q)` into `out`.
    pub fn generator<D: Scalar>(&self, q: &[D], out: &mut [D]) {
        for (o, c) in out.iter_mut().zip(&self.components) {
            *o = eval_any(c, D::from(0.0), q, &[]);
        }
    }

    /// The Noether momentum map `J(q, p) = p·ξ_Q(q)`.
    pub fn momentum_map(&self, q: &[f64], p: &[f64]) -> f64 {
        let mut xi = vec![0.0; q.len()];
        self.generator(q, &mut xi);
        p.iter().zip(&xi).map(|(a, b)| a * b).sum()
    }
}
