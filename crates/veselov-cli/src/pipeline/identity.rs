//! The run a checkpoint belongs to. A checkpoint records its run's
//! scenario without the keys a resumed run may change ([`RESUMABLE_KEYS`]:
//! the run's length, where and how often checkpoints and plots are made)
//! and its fixed time step, if it has one. `--resume` ([`check_resume`])
//! refuses a scenario that differs anywhere else (a material constant, a
//! step, an initial value, an output cadence), naming the first key that
//! differs, since its continuation would be neither run; and, with fixed
//! steps, a `t_end` that would change the step (the kinds that land on
//! `t_end` take `t_end/n`) or that the checkpoint is already beyond; with
//! variable steps, a `t_end` before both the checkpoint's time and the
//! run's own `t_end`.

use std::path::Path;

use super::Plan;
use super::checkpoint::Saved;
use crate::error::CliError;

/// The keys a resumed run may change.
pub const RESUMABLE_KEYS: [&str; 5] = [
    "time.t_end",
    "time.steps",
    "output.checkpoint_every",
    "output.dir",
    "output.plots",
];

/// Whether the run `saved` in `dir` may be resumed with the scenario
/// `file`, of [`identity`] `scenario` and plan `plan`. A checkpoint written
/// before checkpoints recorded their scenario or step is taken as it is.
///
/// # Errors
/// [`CliError::Key`] naming the first key that differs, or the plan's
/// step-count key (`time.t_end`, `time.steps`) for another step or a
/// shorter run.
pub fn check_resume(
    file: &Path,
    dir: &Path,
    saved: &Saved,
    scenario: Option<&str>,
    plan: &Plan,
) -> Result<(), CliError> {
    let refuse = |key: String, message: String| CliError::Key {
        file: file.to_path_buf(),
        key,
        message,
    };
    if let (Some(there), Some(here)) = (saved.scenario.as_deref(), scenario)
        && let Some((key, there, here)) = first_difference(there, here)
    {
        return Err(refuse(
            key,
            format!(
                "is {here} here but {there} in the run in {} being resumed: a resumed run continues its own \
                 scenario, in which only {} may change",
                dir.display(),
                RESUMABLE_KEYS.join(", ")
            ),
        ));
    }
    if let (Some(current), Some(before)) = (plan.step, saved.step_length)
        && (before - current).abs() > 1e-12 * before.abs()
    {
        return Err(refuse(
            plan.steps_key.to_string(),
            format!(
                "gives the time step dt = {} here, but the run in {} being resumed steps with dt = {}: a \
                 resumed run keeps its step (a t_end a whole number of those steps from the start keeps it)",
                crate::output::number(current),
                dir.display(),
                crate::output::number(before)
            ),
        ));
    }
    check_not_shorter(file, dir, saved, plan)
}

/// The part of [`check_resume`] that refuses a shorter run. A plan that
/// counts its steps exactly (fixed steps, up to the last partial one; or a
/// variable-step run stopped by a step count) refuses a count the run is
/// already beyond. A variable-step run stopped by time only estimates its
/// count: it refuses a `t_end` before both the checkpoint's time and the
/// run's own `t_end` (a finished run whose last step passed its `t_end` may
/// still be resumed to that `t_end`).
fn check_not_shorter(file: &Path, dir: &Path, saved: &Saved, plan: &Plan) -> Result<(), CliError> {
    let shorter = match plan.t_end {
        Some(t_end) => match (saved.time, saved.t_end) {
            (Some(time), Some(before)) => t_end < time && t_end < before,
            // A checkpoint of a run stopped by a step count, or written
            // before times were recorded.
            (Some(time), None) => t_end < time,
            _ => false,
        },
        None => saved.step as f64 > plan.steps.ceil() + 0.5,
    };
    if !shorter {
        return Ok(());
    }
    let here = match plan.t_end {
        Some(t_end) => format!("asks to end at t = {}", crate::output::number(t_end)),
        None => format!("asks for {:.0} {}", (plan.steps / plan.per() as f64).ceil(), plan.unit),
    };
    let step = saved.step / plan.per();
    let there = match saved.time {
        Some(time) => format!("t = {} (step {step})", crate::output::number(time)),
        None => format!("step {step}"),
    };
    Err(CliError::Key {
        file: file.to_path_buf(),
        key: plan.steps_key.to_string(),
        message: format!(
            "{here}, but the run in {} being resumed already stands at {there}: a resume continues a run, \
             it cannot shorten it",
            dir.display()
        ),
    })
}

/// The scenario `text` without [`RESUMABLE_KEYS`], as TOML (`None` if it
/// does not parse: such a scenario never reaches a checkpoint).
pub fn identity(text: &str) -> Option<String> {
    let mut table: toml::Table = toml::from_str(text).ok()?;
    for key in RESUMABLE_KEYS {
        if let Some((section, name)) = key.split_once('.')
            && let Some(toml::Value::Table(t)) = table.get_mut(section)
        {
            t.remove(name);
        }
    }
    toml::to_string(&table).ok()
}

/// The first key (in sorted order) whose value differs between the
/// identities `saved` and `current`, with its value in each (`absent` where
/// it is missing); `None` if they agree or one does not parse.
pub fn first_difference(saved: &str, current: &str) -> Option<(String, String, String)> {
    let saved: toml::Value = toml::from_str::<toml::Table>(saved).ok()?.into();
    let current: toml::Value = toml::from_str::<toml::Table>(current).ok()?.into();
    difference("", &saved, &current)
}

fn difference(path: &str, a: &toml::Value, b: &toml::Value) -> Option<(String, String, String)> {
    match (a, b) {
        (toml::Value::Table(x), toml::Value::Table(y)) => {
            let mut keys: Vec<&String> = x.keys().chain(y.keys()).collect();
            keys.sort();
            keys.dedup();
            keys.into_iter().find_map(|k| {
                let key = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                match (x.get(k), y.get(k)) {
                    (Some(u), Some(v)) => difference(&key, u, v),
                    (u, v) => Some((key, shown(u), shown(v))),
                }
            })
        }
        _ if a == b => None,
        _ => Some((path.to_string(), a.to_string(), b.to_string())),
    }
}

fn shown(v: Option<&toml::Value>) -> String {
    v.map_or_else(|| "absent".to_string(), toml::Value::to_string)
}

#[cfg(test)]
mod tests {
    use super::*;

    const RUN: &str = "[model]\nname = \"cosserat-rod\"\nyoung = 1e5 # Pa\n\n[time]\nt_end = 2.0\n\n\
                       [output]\nevery = 10\n";

    #[test]
    fn only_the_resumable_keys_may_change() {
        let saved = identity(RUN).expect("parses");
        let longer = RUN
            .replace("t_end = 2.0", "t_end = 5.0\n# a comment")
            .replace("every = 10", "every = 10\nplots = false\ncheckpoint_every = 7");
        assert_eq!(first_difference(&saved, &identity(&longer).expect("parses")), None);
        let stiffer = RUN.replace("young = 1e5", "young = 2e5");
        assert_eq!(
            first_difference(&saved, &identity(&stiffer).expect("parses")),
            Some(("model.young".into(), "100000.0".into(), "200000.0".into()))
        );
        let denser = RUN.replace("every = 10", "every = 5");
        assert_eq!(
            first_difference(&saved, &identity(&denser).expect("parses")).map(|d| d.0),
            Some("output.every".into())
        );
        let with_dt = RUN.replace("t_end = 2.0", "t_end = 2.0\ndt = 0.001");
        assert_eq!(
            first_difference(&saved, &identity(&with_dt).expect("parses")),
            Some(("time.dt".into(), "absent".into(), "0.001".into()))
        );
    }
}
