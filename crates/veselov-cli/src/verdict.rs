//! The verdict of a run beyond its status: the warnings a run that ended
//! `"ok"` can still carry, and the `[checks]` table that sets their
//! thresholds.
//!
//! `status` says whether the run reached its end (`"ok"`), failed
//! (`"error"`) or was interrupted (`"interrupted"`); it says nothing about
//! accuracy. The warnings do: each is `{code, message}` in `summary.json`'s
//! `warnings` (empty when none) and a `warning:` line on the terminal. The
//! codes:
//!
//! | code | when |
//! |---|---|
//! | `energy_error` | a conservative run's largest relative energy error max |E − E₀|/|E₀| (rods and beams: the energy's range relative to its size) exceeds `[checks] energy_error` |
//! | `energy_balance_error` | a forced run's largest energy-balance error max |E − E₀ − W|/|E₀| exceeds `[checks] energy_error` |
//! | `beyond_stability_limit` | the step exceeds the scheme's stability limit and the run goes on because `allow_unstable = true` |
//! | `near_stability_limit` | a rod's step number is close to its limit, where long runs can still grow |
//! | `shear_locking` | a rod's bending is coarsely resolved by the vertex shear frame |
//! | `degenerate_start` | a variable-step (SEM) run starts on or near the degeneracy set of its energy equation (for `sem-leftpoint`: a turning point or a critical point of V), where its steps do not follow `dt` |
//! | `step_runaway` | a `sem-leftpoint` run's step grew beyond [`STEP_RUNAWAY_FACTOR`] times its first step: the inconsistent branch of the energy equation, which refining `dt` does not cure |

use serde::Deserialize;
use serde_json::{Value, json};

use crate::error::CliError;
use crate::scenario::positive_value;

/// The default `[checks] energy_error` of the mechanics and rigid-body
/// kinds: 1 % of |E₀|. A symplectic method of order p keeps the energy
/// error bounded at O(hᵖ) over exponentially long times; beyond 1 % the
/// step is too large to resolve the motion.
pub const ENERGY_ERROR_MECHANICS: f64 = 1e-2;

/// The default `[checks] energy_error` of the lattice fields, rods and
/// beams: 5 %. Their schemes conserve the multisymplectic form and the
/// momenta, not the energy, whose error oscillates at O(Δx² + Δt²); the
/// shipped examples stay below 2 % (beams: see their pages).
pub const ENERGY_ERROR_FIELDS: f64 = 5e-2;

/// The least [`veselov::sem::StartExpansion::dominance`] (the energy
/// equation's leading term `c·h₀ʳ` against the next, `a·h₀ʳ⁺¹`) of a
/// variable-step start that is not warned about: 4, i.e. for the left-point
/// rule `|c| ≥ 2h₀|∇V|²` (`a = ½|∇V|²`). At a turning point `c = 0` and the
/// dominance is round-off; started at t = 1 on a Kepler orbit of
/// eccentricity 0.1 it is 34 with `dt = 0.005`, and it scales like 1/dt.
pub const DEGENERATE_DOMINANCE: f64 = 4.0;

/// The least [`veselov::sem::StartExpansion::drift`] of a degenerate start
/// that is warned about: 0.01. Below it `c` stays on the degeneracy set
/// along the motion (round-off on a circular Kepler orbit, where the
/// left-point rule keeps its step and is first order).
pub const DEGENERATE_DRIFT: f64 = 0.01;

/// The factor of growth of a `sem-leftpoint` run's step (largest step over
/// the first, `dt`) beyond which the run warns: 10. On its consistent branch
/// the rule's steps follow `dt` (h_k/h₀ tends to a function of the state as
/// `dt` shrinks) and it cannot pass a turning point; started at one, its
/// steps grow like the time since it, to O(1) whatever `dt` (×60 from
/// `dt = 0.005` in one Kepler orbit of eccentricity 0.1).
pub const STEP_RUNAWAY_FACTOR: f64 = 10.0;

/// Thresholds of the warnings of a run: how far it may stray from what its
/// scheme conserves before its summary says so.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ChecksSpec {
    /// The largest relative energy error (> 0) a run may reach without the
    /// warning `energy_error` (a forced run: `energy_balance_error`, on
    /// |E − E₀ − W|/|E₀|). Default 0.01 for mechanics and rigid bodies, 0.05
    /// for lattice fields, rods and beams. Runs whose energy is not
    /// conserved (damped, loaded or driven rods and beams, Lagrangians
    /// depending on t) and runs with E₀ = 0 are not judged.
    pub energy_error: Option<f64>,
}

impl ChecksSpec {
    /// The energy threshold, `default` when not given; an error names
    /// `checks.energy_error`.
    pub fn energy_limit(&self, file: &std::path::Path, default: f64) -> Result<f64, CliError> {
        match self.energy_error {
            Some(v) => positive_value(file, "checks.energy_error", v),
            None => Ok(default),
        }
    }
}

/// One warning: a stable code and a message in the user's words, with what
/// to do about it.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Warning {
    /// The stable code (the table in [`crate::verdict`]).
    pub code: &'static str,
    /// What happened and what to do.
    pub message: String,
}

/// What a run conserves and how its summary reports the error of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Conserved {
    /// The energy: `energy_error_max_relative`.
    Energy,
    /// The energy balance of a forced run: `energy_balance_error_max`
    /// relative to |`energy_initial`|.
    EnergyBalance,
    /// The energy of a rod or beam, whose summary gives its range:
    /// (`energy_max` − `energy_min`)/max(|`energy_max`|, |`energy_min`|).
    EnergyRange,
}

/// How to advise a smaller step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepAdvice {
    /// The key that sets the step (`method.dt`, `lattice.courant`, …).
    pub key: &'static str,
    /// Its value in this run.
    pub value: f64,
    /// The order of the scheme: the error scales as valueᵒʳᵈᵉʳ.
    pub order: u32,
    /// Further advice (another method, more nodes), or empty.
    pub also: &'static str,
}

impl StepAdvice {
    /// The advice of a lattice whose step is `[lattice] courant` when given,
    /// else `[lattice] dt`, of order 2.
    pub fn lattice(courant: Option<f64>, dt: f64, also: &'static str) -> Self {
        match courant {
            Some(c) => Self {
                key: "lattice.courant",
                value: c,
                order: 2,
                also,
            },
            None => Self {
                key: "lattice.dt",
                value: dt,
                order: 2,
                also,
            },
        }
    }
}

/// The end-of-run check of a conservative run.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyCheck {
    /// What is conserved.
    pub conserved: Conserved,
    /// The threshold (`[checks] energy_error`).
    pub limit: f64,
    /// How to advise a smaller step.
    pub advice: StepAdvice,
}

/// The verdict of a run: warnings met on the way (already shown) and the
/// check made on its summary at the end.
#[derive(Debug, Clone, Default)]
pub struct Verdict {
    /// Warnings recorded before and during the run, already shown.
    pub warnings: Vec<Warning>,
    /// The energy check at the end, for conservative runs.
    pub energy: Option<EnergyCheck>,
    /// Warnings found when the run ended, not yet shown: shown after the
    /// report line with the energy check's.
    pub ending: Vec<Warning>,
}

/// Show `message` as a `warning:` line on standard error (`--quiet` or
/// not) and return it as a [`Warning`] of `code`.
pub fn warn(code: &'static str, message: String) -> Warning {
    eprintln!("warning: {message}");
    Warning { code, message }
}

impl Verdict {
    /// Record and show a warning met before or during the run.
    pub fn warn(&mut self, code: &'static str, message: String) {
        self.warnings.push(warn(code, message));
    }

    /// The warnings of a run that ended with `summary`: those recorded,
    /// then the energy check's (unless the run failed: its failure says
    /// more), not yet shown ([`Verdict::show_new`]). The check's measured
    /// value and threshold go into `summary` under `checks`.
    pub fn judge(&self, summary: &mut Value) -> Vec<Warning> {
        let mut all = self.warnings.clone();
        all.extend(self.ending.iter().cloned());
        let failed = summary.get("status").and_then(Value::as_str) == Some("error");
        if let Some(check) = &self.energy {
            let measured = measured(check.conserved, summary);
            if let Value::Object(map) = summary {
                map.insert(
                    "checks".into(),
                    json!({ "energy_error": { "measured": measured, "limit": check.limit } }),
                );
            }
            if let (Some(error), false) = (measured, failed)
                && (error.is_nan() || error > check.limit)
            {
                all.push(Warning {
                    code: match check.conserved {
                        Conserved::EnergyBalance => "energy_balance_error",
                        _ => "energy_error",
                    },
                    message: energy_message(check, error),
                });
            }
        }
        all
    }
}

impl Verdict {
    /// Show the warnings of `all` ([`Verdict::judge`]) not shown before.
    pub fn show_new(&self, all: &[Warning]) {
        for w in all.iter().skip(self.warnings.len()) {
            eprintln!("warning: {}", w.message);
        }
    }
}

/// The relative error of what `conserved` names, read from `summary`
/// (`None` where the summary has no scale to relate it to).
fn measured(conserved: Conserved, summary: &Value) -> Option<f64> {
    let get = |k: &str| summary.get(k).and_then(Value::as_f64);
    let ratio = |num: f64, den: f64| (den.is_finite() && den > 0.0).then_some(num / den);
    match conserved {
        Conserved::Energy => get("energy_error_max_relative"),
        Conserved::EnergyBalance => ratio(get("energy_balance_error_max")?, get("energy_initial")?.abs()),
        Conserved::EnergyRange => {
            let (hi, lo) = (get("energy_max")?, get("energy_min")?);
            ratio(hi - lo, hi.abs().max(lo.abs()))
        }
    }
}

/// The message of an energy warning of `check` at the relative `error`.
fn energy_message(check: &EnergyCheck, error: f64) -> String {
    let (what, formula) = match check.conserved {
        Conserved::Energy => ("energy error", "max |E − E₀|/|E₀|"),
        Conserved::EnergyBalance => ("energy-balance error", "max |E − E₀ − W|/|E₀|"),
        Conserved::EnergyRange => ("energy variation", "(max E − min E)/max |E|"),
    };
    let a = &check.advice;
    // Error ∝ stepᵖ: the step that would bring it to half the threshold.
    let factor = (0.5 * check.limit / error).powf(1.0 / f64::from(a.order.max(1)));
    let advice = if factor.is_finite() && factor > 0.0 {
        format!(
            "the step is too large for this run; try {} ≤ {}",
            a.key,
            crate::output::approx(a.value * factor)
        )
    } else {
        format!("the step is too large for this run; lower {}", a.key)
    };
    let also = if a.also.is_empty() {
        String::new()
    } else {
        format!("; {}", a.also)
    };
    format!(
        "the {what} {formula} = {} exceeds [checks] energy_error = {}: {advice}{also}",
        percent(error),
        percent(check.limit),
    )
}

/// `x` as a percentage to three digits (`148 %`, `2e11 %`).
fn percent(x: f64) -> String {
    format!("{} %", crate::output::approx(100.0 * x))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(conserved: Conserved, limit: f64) -> Verdict {
        Verdict {
            warnings: Vec::new(),
            energy: Some(EnergyCheck {
                conserved,
                limit,
                advice: StepAdvice {
                    key: "method.dt",
                    value: 0.01,
                    order: 4,
                    also: "",
                },
            }),
            ending: Vec::new(),
        }
    }

    #[test]
    fn an_energy_error_beyond_the_limit_is_a_warning_with_a_smaller_step() {
        let mut s = json!({"status": "ok", "energy_error_max_relative": 1.48});
        let w = check(Conserved::Energy, 0.01).judge(&mut s);
        assert_eq!(w.len(), 1);
        assert_eq!(w[0].code, "energy_error");
        assert!(w[0].message.contains("148 %"), "{}", w[0].message);
        // (0.005/1.48)^(1/4)·0.01 = 2.41e-3.
        assert!(w[0].message.contains("method.dt ≤ 0.00241"), "{}", w[0].message);
        assert_eq!(s["checks"]["energy_error"]["limit"], json!(0.01));
        assert_eq!(s["checks"]["energy_error"]["measured"], json!(1.48));
    }

    #[test]
    fn within_the_limit_or_failed_or_unscaled_is_no_warning() {
        let v = check(Conserved::Energy, 0.01);
        assert!(
            v.judge(&mut json!({"status": "ok", "energy_error_max_relative": 0.009}))
                .is_empty()
        );
        assert!(
            v.judge(&mut json!({"status": "error", "energy_error_max_relative": 5.0}))
                .is_empty()
        );
        assert!(
            v.judge(&mut json!({"status": "ok", "energy_error_max_relative": null}))
                .is_empty()
        );
        // A NaN error is never within the limit.
        let b = check(Conserved::EnergyBalance, 0.01);
        assert!(
            b.judge(&mut json!({"status": "ok", "energy_balance_error_max": 1.0, "energy_initial": 0.0}))
                .is_empty()
        );
        assert_eq!(
            b.judge(&mut json!({"status": "ok", "energy_balance_error_max": 0.1, "energy_initial": -2.0}))[0].code,
            "energy_balance_error"
        );
    }

    #[test]
    fn the_energy_range_is_relative_to_the_largest_energy() {
        let v = check(Conserved::EnergyRange, 0.05);
        let mut s = json!({"status": "ok", "energy_max": 0.2083, "energy_min": 0.1946});
        let w = v.judge(&mut s);
        assert_eq!(w.len(), 1, "6.6 % > 5 %");
        let m = s["checks"]["energy_error"]["measured"].as_f64().unwrap_or(f64::NAN);
        assert!((m - (0.2083 - 0.1946) / 0.2083).abs() < 1e-15);
    }
}
