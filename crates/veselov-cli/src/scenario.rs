//! Scenario files: the tables and checks shared by the kinds of scenario
//! (`[time]` and `[output]` of the mechanics and rigid-body kinds, `[output]`
//! of the beam and rod), parsing with key-level errors, and validation. Each
//! kind's own schema is in its folder under [`crate::kinds`].
//!
//! Every table rejects unknown keys. Errors name the file, the key and what was
//! expected; parse errors also show the line and column. Array keys of every
//! kind are read and checked by one mechanism, [`Array`] and [`List`]: an
//! array of the wrong length or with a bad entry is refused naming the key.

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::CliError;

mod arrays;
pub use arrays::{Array, Entry, List};

/// When the run starts (`t0`) and how long it lasts: exactly one
/// of `t_end` and `steps`.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// The time at which the run ends (> `t0`), instead of `steps`. A
    /// fixed-step run takes n = round((t_end − t0)/dt) steps (at least one)
    /// of (t_end − t0)/n and ends exactly at `t_end` (a note says when that
    /// changes `dt`); a variable-step run stops at its first step at or
    /// after `t_end`.
    #[schemars(extend("unit" = "s"))]
    pub t_end: Option<f64>,
    /// The number of steps to take (≥ 1), instead of `t_end`.
    pub steps: Option<u64>,
    /// The time at which the run starts.
    #[schemars(extend("unit" = "s"))]
    #[serde(default)]
    pub t0: f64,
}

/// Where the run writes its files, which rows and formats, its
/// plots and its checkpoints.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// The output directory; `--out` overrides it. Default:
    /// `out/<scenario file stem>`.
    pub dir: Option<PathBuf>,
    /// Write a row at the start, every `every` steps (≥ 1) and at the end;
    /// not with `times`.
    #[serde(default = "one")]
    pub every: u64,
    /// The formats of the data tables: a list of `csv` and `npy`.
    #[serde(default = "default_formats")]
    pub formats: Vec<String>,
    /// Draw the plots.
    #[serde(default = "yes")]
    pub plots: bool,
    /// The format of the plots: `svg` or `png`.
    #[schemars(extend("enum" = ["svg", "png"]))]
    #[serde(default = "default_plot_format")]
    pub plot_format: String,
    /// Steps between checkpoints; 0 writes one only where the run ends,
    /// finished or interrupted (`--resume` continues from the last one).
    #[serde(default)]
    pub checkpoint_every: u64,
    /// Times at which to write rows, instead of every `every`-th step
    /// (fixed-step runs only): the step nearest each time, with a note when
    /// it is off the grid; the first and last states are always written.
    #[schemars(extend("unit" = "s"))]
    #[serde(default)]
    pub times: Vec<f64>,
}

impl OutputSpec {
    /// The steps at which `times` asks for rows, for a run of `steps` steps of
    /// `dt` from `t0` (sorted, without repeats; none without `times`); a note for each time off the
    /// grid unless `quiet`. An error names `output.times` for a time that is
    /// not finite or lies outside `[t0, t0 + steps·dt]`, or when `every` is
    /// given too.
    pub fn steps_at_times(&self, file: &Path, t0: f64, dt: f64, steps: u64, quiet: bool) -> Result<Vec<u64>, CliError> {
        if self.times.is_empty() {
            return Ok(Vec::new());
        }
        if self.every != 1 {
            return Err(key_error(
                file,
                "output.times",
                "give either `times` or `every`, not both",
            ));
        }
        let end = t0 + steps as f64 * dt;
        let mut out = Vec::with_capacity(self.times.len());
        for &t in &self.times {
            if !(t.is_finite() && t >= t0 - 1e-9 * dt && t <= end + 1e-9 * dt) {
                return Err(key_error(
                    file,
                    "output.times",
                    format!("{t} is not a time of the run, which spans [{t0}, {end}]"),
                ));
            }
            let k = ((t - t0) / dt).round().clamp(0.0, steps as f64) as u64;
            let on_grid = t0 + k as f64 * dt;
            if !quiet && (on_grid - t).abs() > 1e-9 * dt {
                crate::say!("note: output.times: {t} written at the nearest step, t = {on_grid}");
            }
            out.push(k);
        }
        out.sort_unstable();
        out.dedup();
        Ok(out)
    }
}

fn one() -> u64 {
    1
}
fn yes() -> bool {
    true
}
fn default_formats() -> Vec<String> {
    vec!["csv".to_string()]
}
fn default_plot_format() -> String {
    "svg".to_string()
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            dir: None,
            every: 1,
            formats: default_formats(),
            plots: true,
            plot_format: default_plot_format(),
            checkpoint_every: 0,
            times: Vec::new(),
        }
    }
}

/// The error of an `[output] plot_format` (of the scenario `file`) that is
/// not a format the figures are drawn in, if it is not one.
pub fn check_plot_format(file: &Path, format: &str) -> Result<(), CliError> {
    match plot_format_problem(format) {
        Some(message) => Err(key_error(file, "output.plot_format", message)),
        None => Ok(()),
    }
}

/// What is wrong with the plot format `format` (`svg` or `png`), if anything.
pub fn plot_format_problem(format: &str) -> Option<String> {
    (format != "svg" && format != "png").then(|| format!("unknown plot format `{format}`, expected \"svg\" or \"png\""))
}

/// An error about `key` in the scenario `file`.
pub fn key_error(file: &Path, key: &str, message: impl Into<String>) -> CliError {
    CliError::Key {
        file: file.to_path_buf(),
        key: key.to_string(),
        message: message.into(),
    }
}

/// The keys a scenario schema also reads under a former name (its
/// `serde(alias)` attributes): (name, former name). A scenario giving both
/// is refused naming both ([`parse_toml`]).
pub(crate) const FORMER_KEY_NAMES: &[(&str, &str)] = &[
    // The beam's `[model]`.
    ("shear_coefficient", "shear_correction"),
];

/// Parse scenario text of any schema, attributing errors to `file`. A key
/// given under both its name and its former name (`FORMER_KEY_NAMES`) is
/// reported as such (the parser alone says only "duplicate field").
pub fn parse_toml<T: serde::de::DeserializeOwned>(file: &Path, text: &str) -> Result<T, CliError> {
    toml::from_str(text).map_err(|e| {
        let mut message = in_user_words(&clip_lines(&e.to_string(), 200));
        for (name, former) in FORMER_KEY_NAMES {
            if message.contains(&format!("duplicate field `{name}`")) {
                message.push_str(&format!(
                    " (`{former}` is the former name of `{name}`: give one of them)"
                ));
            }
        }
        CliError::Parse {
            file: file.to_path_buf(),
            message,
        }
    })
}

/// A parser message in the words of a scenario's author: the Rust types it
/// names become what they mean, and the line `invalid type: string "x",
/// expected f64` becomes `expected a number, got the string "x"`.
pub fn in_user_words(message: &str) -> String {
    const TYPES: &[(&str, &str)] = &[
        ("expected u64", "expected a whole number ≥ 0"),
        ("expected usize", "expected a whole number ≥ 0"),
        ("expected u32", "expected a whole number ≥ 0"),
        ("expected u16", "expected a whole number ≥ 0"),
        ("expected u8", "expected a whole number ≥ 0"),
        ("expected i64", "expected a whole number"),
        ("expected i32", "expected a whole number"),
        ("expected f64", "expected a number"),
        ("expected f32", "expected a number"),
    ];
    const FOUND: &[(&str, &str)] = &[
        ("floating point ", "the number "),
        ("integer ", "the whole number "),
        ("string ", "the string "),
        ("boolean ", "the boolean "),
        ("sequence", "a list"),
        ("map", "a table"),
    ];
    message
        .lines()
        .map(|line| {
            let mut line = line.to_string();
            for (rust, words) in TYPES {
                if let Some(at) = line.find(rust)
                    && !line[at + rust.len()..].starts_with(|c: char| c.is_ascii_alphanumeric())
                {
                    line.replace_range(at..at + rust.len(), words);
                }
            }
            for prefix in ["invalid type: ", "invalid value: "] {
                if let Some(rest) = line.strip_prefix(prefix)
                    && let Some((found, expected)) = rest.rsplit_once(", expected ")
                {
                    let found = FOUND
                        .iter()
                        .find_map(|(k, w)| found.strip_prefix(k).map(|v| format!("{w}{v}")))
                        .unwrap_or_else(|| found.to_string());
                    line = format!("expected {expected}, got {found}");
                }
            }
            line
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `message` with every line cut to `width` characters (then `…`): a parse
/// error quotes the offending line, which must not echo a huge input.
pub fn clip_lines(message: &str, width: usize) -> String {
    message
        .lines()
        .map(|l| match l.char_indices().nth(width) {
            Some((cut, _)) => format!("{}…", &l[..cut]),
            None => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `v` if it is finite, else an error naming `key`.
pub fn finite_value(file: &Path, key: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(key_error(
            file,
            key,
            format!("expected a finite number, got {}", crate::output::number(v)),
        ))
    }
}

/// The second elastic constant of `[model]` from its keys `poisson`
/// (−1 < ν ≤ ½) or `shear_modulus` (> 0), exactly one of them given; an
/// error names the key at fault.
pub fn shear_from_keys(
    file: &Path,
    poisson: Option<f64>,
    shear_modulus: Option<f64>,
) -> Result<veselov::models::elastic::Shear, CliError> {
    use veselov::models::elastic::Shear;
    match (poisson, shear_modulus) {
        (Some(nu), None) => {
            let nu = finite_value(file, "model.poisson", nu)?;
            if -1.0 < nu && nu <= 0.5 {
                Ok(Shear::Poisson(nu))
            } else {
                Err(key_error(
                    file,
                    "model.poisson",
                    format!("must lie in (−1, 0.5], got {}", crate::output::number(nu)),
                ))
            }
        }
        (None, Some(g)) => Ok(Shear::Modulus(positive_value(file, "model.shear_modulus", g)?)),
        _ => Err(key_error(
            file,
            "model.poisson",
            "give either `poisson` or `shear_modulus`",
        )),
    }
}

/// For an error about the step a structure's march takes: where landing on
/// `t_end` changed the `dt` asked for, the value asked for (empty otherwise),
/// so that a message quoting the step the march would take does not read as
/// a misreading of the scenario.
pub fn adjusted_step_note(asked: Option<f64>, dt: f64, t_end: f64) -> String {
    match asked {
        Some(asked) if (asked - dt).abs() > 1e-12 * dt => {
            format!(
                " (the {} asked for, adjusted to land on t_end = {})",
                crate::output::number(asked),
                crate::output::number(t_end)
            )
        }
        _ => String::new(),
    }
}

/// `v` if it is finite, positive and not subnormal, else an error naming `key`.
pub fn positive_value(file: &Path, key: &str, v: f64) -> Result<f64, CliError> {
    // Subnormal values are refused as the library's parameter checks
    // refuse them: their reciprocals overflow.
    if v.is_normal() && v > 0.0 {
        Ok(v)
    } else {
        Err(key_error(
            file,
            key,
            if v.is_subnormal() {
                format!("expected a finite number > 0, got the subnormal {v:e}")
            } else {
                format!("expected a finite number > 0, got {}", crate::output::number(v))
            },
        ))
    }
}

/// Check `dt`, the `[time]` table and the `[output]` table shared by every
/// kind of scenario; errors name the key in `file`.
pub fn check_time_and_output(file: &Path, time: &TimeSpec, dt: f64, output: &OutputSpec) -> Result<(), CliError> {
    if !(dt.is_finite() && dt > 0.0) {
        return Err(key_error(
            file,
            "method.dt",
            format!("expected a finite number > 0, got {}", crate::output::number(dt)),
        ));
    }
    if !time.t0.is_finite() {
        return Err(key_error(
            file,
            "time.t0",
            format!("expected a finite number, got {}", time.t0),
        ));
    }
    match (time.t_end, time.steps) {
        (Some(_), Some(_)) => return Err(key_error(file, "time", "give either `t_end` or `steps`, not both")),
        (None, None) => return Err(key_error(file, "time", "missing `t_end` or `steps`")),
        (Some(t), None) if !(t.is_finite() && t > time.t0) => {
            return Err(key_error(
                file,
                "time.t_end",
                format!("expected a finite number > t0 = {}, got {t}", time.t0),
            ));
        }
        (None, Some(0)) => return Err(key_error(file, "time.steps", "expected at least 1 step")),
        _ => {}
    }
    if output.every == 0 {
        return Err(key_error(file, "output.every", "expected an integer ≥ 1"));
    }
    for f in &output.formats {
        if f != "csv" && f != "npy" {
            return Err(key_error(
                file,
                "output.formats",
                format!("unknown format `{f}`, expected \"csv\" or \"npy\""),
            ));
        }
    }
    check_plot_format(file, &output.plot_format)
}

/// Number of steps of a fixed-step run: `steps`, or `round((t_end − t0)/dt)`
/// (at least one), so that the run ends exactly at `t_end` in steps of
/// [`step_length`].
pub fn step_count(time: &TimeSpec, dt: f64) -> u64 {
    match (time.steps, time.t_end) {
        (Some(n), _) => n,
        (None, Some(t_end)) => landing_steps(t_end - time.t0, dt) as u64,
        (None, None) => 1,
    }
}

/// The steps of about `dt` that cover `span` exactly: `round(span/dt)`, at
/// least one (as a float: callers check it against their limits before
/// counting with it). The one rule of fixed-step runs and of `verify`.
pub fn landing_steps(span: f64, dt: f64) -> f64 {
    (span / dt).round().max(1.0)
}

/// The step a fixed-step run takes: `dt`, or with `t_end` (and no `steps`)
/// `(t_end − t0)/n` for the `n` of [`step_count`], which lands on `t_end`.
pub fn step_length(time: &TimeSpec, dt: f64) -> f64 {
    match (time.steps, time.t_end) {
        (None, Some(t_end)) => (t_end - time.t0) / step_count(time, dt) as f64,
        _ => dt,
    }
}

/// Say when [`step_length`] changed the requested `dt` (by more than a relative 1e-12).
pub fn note_step_length(requested: f64, taken: f64, quiet: bool) {
    if !quiet && (taken - requested).abs() > 1e-12 * requested.abs() {
        crate::say!(
            "note: dt = {} adjusted to {} so that the run ends at t_end",
            crate::output::number(requested),
            crate::output::number(taken)
        );
    }
}

/// Say when a lattice run, whose time step `dt` belongs to the lattice,
/// ends after `t_end`: it stops at the first level at or after `t_end`,
/// `ceil(t_end/dt)·dt` (unless within a relative 1e-12 of `t_end`).
pub fn note_lattice_end(t_end: f64, dt: f64, quiet: bool) {
    let end = (t_end / dt).ceil() * dt;
    if !quiet && (end - t_end).abs() > 1e-12 * t_end {
        eprintln!(
            "note: the lattice's time step dt = {} does not divide t_end = {}: the run ends at t = {}, the \
             first step at or after t_end",
            crate::output::number(dt),
            crate::output::number(t_end),
            crate::output::number(end)
        );
    }
}

/// The step count of [`step_count`] as a float, not saturated: what the
/// preflight reports and checks (`t_end = 2e18` is 2e21 steps of 1e-3, not `u64::MAX`).
pub fn planned_steps(time: &TimeSpec, dt: f64) -> f64 {
    match (time.steps, time.t_end) {
        (Some(n), _) => n as f64,
        (None, Some(t_end)) => {
            let n = (t_end - time.t0) / dt;
            if n < u64::MAX as f64 {
                step_count(time, dt) as f64
            } else {
                n
            }
        }
        (None, None) => 1.0,
    }
}

/// The output directory: `--out`, else `output.dir`, else `out/<scenario stem>`.
pub fn output_dir(file: &Path, output: &OutputSpec, cli_out: Option<&Path>) -> PathBuf {
    if let Some(o) = cli_out {
        return o.to_path_buf();
    }
    if let Some(d) = &output.dir {
        return d.clone();
    }
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "run".into());
    PathBuf::from("out").join(stem)
}

/// The dotted key on the line a TOML parse `message` points at
/// (`… at line L, column C …`) in `text`: the key left of `=` on that
/// line, inside the last `[table]` header above it. `None` when the line
/// holds no key (a header, or the message names no line).
pub fn key_at(text: &str, message: &str) -> Option<String> {
    let rest = &message[message.find("line ")? + 5..];
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    let line: usize = digits.parse().ok()?;
    let lines: Vec<&str> = text.lines().collect();
    let here = lines.get(line.checked_sub(1)?)?;
    let (key, _) = here.split_once('=')?;
    let key = key.trim().trim_matches('"');
    if key.is_empty() || key.starts_with('[') {
        return None;
    }
    let table = lines[..line - 1].iter().rev().find_map(|l| {
        let l = l.trim();
        (l.starts_with('[') && !l.starts_with("[[")).then(|| l.trim_matches(|c| c == '[' || c == ']').trim())
    });
    Some(match table {
        Some(t) if !t.is_empty() => format!("{t}.{key}"),
        _ => key.to_string(),
    })
}

/// Where the run writes its files, how often it writes a row,
/// its plots and its checkpoints. Steps are time steps Δt (the rod
/// computes two lattice levels per time step, the beam one; the beam's
/// space evolution counts space steps).
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RowsOutputSpec {
    /// The output directory; `--out` overrides it. Default:
    /// `out/<scenario file stem>`.
    pub dir: Option<PathBuf>,
    /// Steps between output rows (≥ 1). Default: about 500 rows, the
    /// run's steps divided by 500 and rounded up.
    pub every: Option<u64>,
    /// Steps between checkpoints; 0 writes one only where the run ends,
    /// finished or interrupted (`--resume` continues from the last one).
    #[serde(default)]
    pub checkpoint_every: u64,
    /// Draw the plots and the animation of the centreline.
    #[serde(default = "rows_plots")]
    pub plots: bool,
    /// The format of the plots: `svg` or `png`.
    #[schemars(extend("enum" = ["svg", "png"]))]
    #[serde(default = "rows_format")]
    pub plot_format: String,
}

fn rows_plots() -> bool {
    true
}
fn rows_format() -> String {
    "svg".into()
}

impl Default for RowsOutputSpec {
    fn default() -> Self {
        Self {
            dir: None,
            every: None,
            checkpoint_every: 0,
            plots: true,
            plot_format: rows_format(),
        }
    }
}

impl RowsOutputSpec {
    /// Rows every `every` steps of `steps` (about 500 rows by default).
    ///
    /// # Errors
    /// `output.every` = 0 or an unknown `output.plot_format`.
    pub fn rows_every(&self, file: &Path, steps: u64) -> Result<u64, CliError> {
        check_plot_format(file, &self.plot_format)?;
        match self.every {
            Some(0) => Err(key_error(file, "output.every", "expected an integer ≥ 1")),
            Some(k) => Ok(k),
            None => Ok(steps.div_ceil(500).max(1)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parser_messages_name_no_rust_type() {
        let cases = [
            (
                "invalid value: integer `-1`, expected u64",
                "expected a whole number ≥ 0, got the whole number `-1`",
            ),
            (
                "invalid type: floating point `2.5`, expected usize",
                "expected a whole number ≥ 0, got the number `2.5`",
            ),
            (
                "invalid type: string \"x\", expected f64",
                "expected a number, got the string \"x\"",
            ),
            (
                "invalid type: string \"yes\", expected a boolean",
                "expected a boolean, got the string \"yes\"",
            ),
            (
                "invalid type: integer `3`, expected a sequence",
                "expected a sequence, got the whole number `3`",
            ),
        ];
        for (rust, words) in cases {
            let text = format!("TOML parse error at line 5\n  |\n{rust}");
            let got = in_user_words(&text);
            assert!(got.ends_with(words), "{rust} → {got}");
            assert!(got.starts_with("TOML parse error at line 5\n  |\n"), "{got}");
        }
        // A key named like a type is left alone.
        assert_eq!(
            in_user_words("unknown field `u64x`, expected u64x"),
            "unknown field `u64x`, expected u64x"
        );
    }
}
