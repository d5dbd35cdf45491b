//! `veselov run` for custom models with more coordinates than the
//! fixed-size path serves ([`MAX_FIXED_DIMENSION`] < n ≤ [`MAX_DIMENSION`]):
//! the run-time-dimension Galerkin integrator
//! ([`veselov::mechanics::DynGalerkinIntegrator`], Newton with the exact
//! Jacobian) on the same run pipeline, table, summary and plots as every
//! other fixed-step mechanics run ([`super::run::run_fixed_table`]).
//!
//! What it serves: unforced Lagrangians with the fixed-step methods and
//! declared symmetries (checked for invariance as on the fixed-size path).
//! Forces and the variable-step SEM methods need at most
//! [`MAX_FIXED_DIMENSION`] coordinates, and say so naming the key.

use veselov::mechanics::DynStepper;
use veselov::mechanics::{DynGalerkinIntegrator, DynLagrangian, DynState, GalerkinScheme, dyn_energy, dyn_momentum};
use veselov::num_dual::Dual64;

use super::custom::invariance_samples;
use super::custom::{DynCustomLagrangian, DynCustomSymmetry, MAX_DIMENSION, MAX_FIXED_DIMENSION};
use super::run::{FixedRun, header_of, resolve_choice, run_fixed_table};
use super::schema::LoadedScenario;
use super::systems::check_defect;
use crate::catalog::Choice;
use crate::error::CliError;
use crate::pipeline::RunJob;
use crate::scenario::{List, note_step_length};

/// Run the custom model of `scenario` (more than [`MAX_FIXED_DIMENSION`]
/// coordinates) with the options of `job`.
pub fn run(job: &RunJob, scenario: &LoadedScenario) -> Result<(), CliError> {
    let m = &scenario.scenario.model;
    let coordinates = m.coordinates.clone().unwrap_or_default();
    let n = coordinates.len();
    let beyond = format!(
        "with {n} coordinates (more than {MAX_FIXED_DIMENSION}, up to {MAX_DIMENSION}) a custom model runs on the \
         run-time-dimension integrator, which"
    );
    if m.force.is_some() {
        return Err(scenario.key_error(
            "model.force",
            format!("{beyond} takes no forces; forced models have at most {MAX_FIXED_DIMENSION} coordinates"),
        ));
    }
    let method = match resolve_choice(scenario)? {
        Choice::Fixed(method) => method,
        Choice::Variable(rule) => {
            return Err(scenario.key_error(
                "method.name",
                format!(
                    "{beyond} has fixed steps only; `{}` needs at most {MAX_FIXED_DIMENSION} coordinates",
                    rule.name()
                ),
            ));
        }
    };
    let lagrangian = DynCustomLagrangian::new(scenario, &coordinates)?;
    let mut symmetries = Vec::new();
    for (name, generator) in &m.symmetries {
        let s = DynCustomSymmetry::new(scenario, name, generator, &coordinates)?;
        check_invariance(scenario, &lagrangian, &s)?;
        symmetries.push(s);
    }
    let x0 = initial(scenario, &lagrangian, &coordinates)?;
    let e0 = dyn_energy(&lagrangian, x0.t, &x0.q, &x0.p).unwrap_or(f64::NAN);
    if !e0.is_finite() {
        return Err(scenario.key_error(
            "model.lagrangian",
            "the energy is not finite at the initial state (is the Lagrangian defined and regular there?)",
        ));
    }
    let dt = scenario.step_length();
    note_step_length(scenario.scenario.method.dt, dt, job.quiet);
    let scheme = GalerkinScheme::new(method).map_err(|e| CliError::Setup(e.to_string()))?;
    let mut integrator = DynGalerkinIntegrator::new(lagrangian.clone(), scheme, dt)
        .map_err(|e| CliError::Setup(e.to_string()))?
        .with_newton_options(scenario.scenario.method.newton_options());
    let mut stepper = DynStepper::new(&mut integrator, x0.t);
    let momenta: Vec<String> = symmetries.iter().map(|s| s.name.clone()).collect();
    let row = move |x: &DynState, _work: f64| {
        let mut r = Vec::with_capacity(2 + 2 * x.q.len() + symmetries.len());
        r.push(x.t);
        r.extend(&x.q);
        r.extend(&x.p);
        // A state where the inverse Legendre map fails has no energy: NaN,
        // which the run reports as a non-finite output, naming the column.
        r.push(dyn_energy(&lagrangian, x.t, &x.q, &x.p).unwrap_or(f64::NAN));
        r.extend(symmetries.iter().map(|s| s.momentum_map(&x.q, &x.p)));
        r
    };
    let run = FixedRun {
        job,
        scenario,
        model: "custom",
        method,
        dt,
        e0,
        dimension: n,
        header: header_of(&coordinates, n, &momenta, false),
        momenta,
        forced: false,
        row: Box::new(row),
    };
    run_fixed_table(run, &mut stepper, x0)
}

/// The initial state from `[initial]` (`q` with `p`, or with `v` through the
/// Legendre map), with the lengths checked.
fn initial(scenario: &LoadedScenario, l: &DynCustomLagrangian, coordinates: &[String]) -> Result<DynState, CliError> {
    let t = scenario.scenario.time.t0;
    let Some(init) = &scenario.scenario.initial else {
        return Err(scenario.key_error("initial", "missing: custom models need [initial] q and p (or v)"));
    };
    let check = |key: &str, x: &List<f64>| x.values(&scenario.path, key, &[coordinates.len()], " (one per coordinate)");
    let q = check("initial.q", &init.q)?;
    let p = match (&init.p, &init.v) {
        (Some(p), _) => check("initial.p", p)?,
        (None, Some(v)) => {
            let v = check("initial.v", v)?;
            dyn_momentum(l, t, &q, &v).map_err(|e| scenario.key_error("initial.v", e.to_string()))?
        }
        (None, None) => return Err(scenario.key_error("initial", "missing `p` or `v`")),
    };
    Ok(DynState { t, q, p })
}

/// Refuse `symmetry` if `L` is not invariant under it: the defect
/// `δL = Σ ∂L/∂q_i ξ_i + ∂L/∂v_i (Dξ·v)_i` (each term one dual pass of `L`,
/// `ξ` and `Dξ·v` one dual pass of the generator along `v`) against the
/// size of its terms `Σ |∂L/∂q_i ξ_i| + |∂L/∂v_i (Dξ·v)_i|`, at the same
/// sample states as the fixed-size check.
fn check_invariance(
    scenario: &LoadedScenario,
    l: &DynCustomLagrangian,
    symmetry: &DynCustomSymmetry,
) -> Result<(), CliError> {
    let n = l.dim();
    for (t, q, v) in invariance_samples(n) {
        // ξ(q) and Dξ(q)·v from one dual pass along v.
        let along: Vec<Dual64> = q.iter().zip(&v).map(|(&a, &b)| Dual64::new(a, b)).collect();
        let mut xi = vec![Dual64::from(0.0); n];
        symmetry.generator(&along, &mut xi);
        // Every term ∂L/∂q_i ξ_i and ∂L/∂v_i (Dξ·v)_i, by dual passes.
        let mut terms = Vec::with_capacity(2 * n);
        for i in 0..2 * n {
            let mut qd: Vec<Dual64> = q.iter().map(|&x| Dual64::from(x)).collect();
            let mut vd: Vec<Dual64> = v.iter().map(|&x| Dual64::from(x)).collect();
            if i < n {
                qd[i].eps = xi[i].re;
            } else {
                vd[i - n].eps = xi[i - n].eps;
            }
            terms.push(l.lagrangian(Dual64::from(t), &qd, &vd).eps);
        }
        let defect: f64 = terms.iter().sum();
        let size: f64 = terms.iter().map(|x| x.abs()).sum();
        check_defect(scenario, &symmetry.name, (defect, size), (t, &q, &v))?;
    }
    Ok(())
}
