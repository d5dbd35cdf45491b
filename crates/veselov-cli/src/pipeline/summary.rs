//! The one `summary.json` schema: the common keys every kind writes, then
//! the kind's own.
//!
//! Common keys: `status` (`"ok"`, `"error"` or `"interrupted"`), `steps`
//! (time steps taken: a lattice's levels divided by its levels per time
//! step), `t_final`, `wall_seconds`, `iterations_mean` (nonlinear
//! iterations per time step) and `failure` (`null`, or `kind`, `step` (the
//! 0-based time step that failed), `time`, `message`), then `warnings` (a list of `{code, message}`, empty
//! when none: [`crate::verdict`]) and, for runs whose energy is checked,
//! `checks`.

use serde_json::{Map, Value, json};
use veselov::run::Status;

/// The status string of a run that ended with `status`.
pub fn status_name(status: &Status) -> &'static str {
    match status {
        Status::Completed | Status::Stopped => "ok",
        Status::Interrupted => "interrupted",
        Status::Failed(_) => "error",
    }
}

/// `{kind, step, time, message}` of a library failure that ended a run
/// after `levels` stepper steps (`per` of which make a time step) at
/// `t_final`. An error that does not carry its own step and time (a vertex
/// solve, a singular Jacobian, a Lie-group map, a bad value met during the
/// run) is placed at the step the run was taking: `step` = the steps
/// completed (the 0-based index of the failed one) and `time` = `t_final`
/// (the time at its start), as [`veselov::Error::NewtonFailure`] reports its
/// own. `step` counts time steps: a lattice's failed level `k` is in time
/// step `k / per` (the message names the level).
pub fn failure(e: &veselov::Error, (levels, per): (u64, u64), t_final: f64) -> Value {
    use veselov::Error as E;
    let steps = levels;
    let here = (Some(steps), Some(t_final));
    let (kind, (step, time)): (&str, (Option<u64>, Option<f64>)) = match e {
        E::NonFiniteState { step, t, .. } => ("non_finite_state", (Some(*step as u64), Some(*t))),
        E::NewtonFailure { step, t, .. } => ("newton_failure", (Some(*step as u64), Some(*t))),
        E::NoStepRoot { step, t, .. } => ("no_step_root", (Some(*step as u64), Some(*t))),
        E::DegenerateStep { step, t, .. } => ("degenerate_step", (Some(*step as u64), Some(*t))),
        E::NegativeStep { step, t, .. } => ("negative_step", (Some(*step as u64), Some(*t))),
        E::LevelSolveFailure { level, t, .. } => ("level_solve_failure", (Some(*level as u64), Some(*t))),
        E::VertexSolveFailure { .. } => ("vertex_solve_failure", here),
        E::SingularJacobian { .. } => ("singular_jacobian", here),
        E::SingularVelocityHessian { t, .. } => ("singular_velocity_hessian", (Some(steps), Some(*t))),
        E::Lie(_) => ("lie_group", here),
        _ => ("invalid_input", here),
    };
    let step = step.map(|k| k / per.max(1));
    json!({ "kind": kind, "step": step, "time": time, "message": e.to_string() })
}

/// The common keys of a run that took `levels` stepper steps, `per` of
/// which make one time step, followed by `own` (the kind's keys, which keep
/// their order).
pub fn common(
    status: &Status,
    (levels, per): (u64, u64),
    t_final: f64,
    wall_seconds: f64,
    iterations: u64,
    own: Value,
) -> Value {
    let fail = match status {
        Status::Failed(e) => failure(e, (levels, per), t_final),
        _ => Value::Null,
    };
    let steps = levels / per.max(1);
    let mut map = Map::new();
    map.insert("status".into(), json!(status_name(status)));
    map.insert("steps".into(), json!(steps));
    map.insert("t_final".into(), json!(t_final));
    map.insert("wall_seconds".into(), json!(wall_seconds));
    map.insert("iterations_mean".into(), json!(iterations as f64 / steps.max(1) as f64));
    map.insert("failure".into(), fail);
    // The former free-text error key, kept for readers of older summaries.
    map.insert(
        "error".into(),
        match status {
            Status::Failed(e) => json!(e.to_string()),
            _ => Value::Null,
        },
    );
    if let Value::Object(own) = own {
        for (k, v) in own {
            map.entry(k).or_insert(v);
        }
    }
    Value::Object(map)
}

/// Adds `warnings` (a list of `{code, message}`, empty when none) and the
/// `checks` of `verdict` to a run's `summary`; returns the warnings.
pub fn add_warnings(summary: &mut Value, verdict: &crate::verdict::Verdict) -> Vec<crate::verdict::Warning> {
    let warnings = verdict.judge(summary);
    if let Value::Object(map) = summary {
        map.insert("warnings".into(), json!(warnings));
    }
    warnings
}

/// The largest energy error relative to the initial energy, |E − E₀|/|E₀|
/// (`null` where E₀ is zero or not finite: no scale to relate to).
pub fn relative_energy_error(error_max: f64, initial: f64) -> Value {
    if initial.is_finite() && initial != 0.0 && error_max.is_finite() {
        json!(error_max / initial.abs())
    } else {
        Value::Null
    }
}
