//! What the rod and the beam read alike: driven ends (`[ends.start_motion]`,
//! `[ends.end_motion]`: a displacement and a rotation vector as expressions
//! in the run's time `t`, zero at t = 0, applied to the end's initial pose
//! (r₀ + Δr(t), exp(θ(t)) R₀)), expressions in several variables (s, t), and
//! material values along the body, a number or an expression in `s`.

use std::path::Path;

use nalgebra::Vector3;
use serde::Deserialize;
use veselov::expr::{Expr, SymbolTable};
use veselov::field::fibre::Pose;
use veselov::lie::so3;

use crate::error::CliError;
use crate::scenario::{Array, key_error, positive_value};

/// `[ends.start_motion]` or `[ends.end_motion]`: the motion of a driven
/// end from its initial pose, as expressions in the run's time `t`; give
/// `displacement`, `rotation` or both, each zero at t = 0.
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub(crate) struct MotionSpec {
    /// The displacement Δr(t) from the initial position: three
    /// expressions in `t` (x, y, z), zero at t = 0.
    #[schemars(extend("unit" = "m", "default" = ["0", "0", "0"]))]
    pub displacement: Option<Array<String, 3>>,
    /// The rotation θ(t) applied to the initial frame, a rotation vector in
    /// the spatial frame: three expressions in `t` (x, y, z), zero at t = 0.
    #[schemars(extend("unit" = "rad", "default" = ["0", "0", "0"]))]
    pub rotation: Option<Array<String, 3>>,
}

/// Largest `|Δr(0)|`, `|θ(0)|` accepted as zero.
const START_TOLERANCE: f64 = 1e-12;

/// Three expressions in `t`, parsed with errors naming `key` (a length
/// other than 3) or `key[i]`.
fn parse_vector(file: &Path, key: &str, sources: &Option<Array<String, 3>>) -> Result<Option<[Expr; 3]>, CliError> {
    match sources {
        Some(sources) => parse_in(file, key, sources, &["t"]).map(Some),
        None => Ok(None),
    }
}

/// Three expressions in `variables` (evaluated with their values in that
/// order), parsed with errors naming `key` (a length other than 3) or
/// `key[i]` (a syntax error, an unknown name).
pub(crate) fn parse_in(
    file: &Path,
    key: &str,
    sources: &Array<String, 3>,
    variables: &[&str],
) -> Result<[Expr; 3], CliError> {
    let sources = sources.values(file, key)?;
    let parse = |i: usize| parse_expression(file, &format!("{key}[{i}]"), &sources[i], variables);
    Ok([parse(0)?, parse(1)?, parse(2)?])
}

/// One expression in `variables` (evaluated with their values in that
/// order), its errors naming `key`.
pub(crate) fn parse_expression(file: &Path, key: &str, source: &str, variables: &[&str]) -> Result<Expr, CliError> {
    let mut table = SymbolTable::new();
    for variable in variables {
        table
            .variable(variable)
            .map_err(|e| key_error(file, key, e.to_string()))?;
    }
    Expr::parse(source, &table).map_err(|e| key_error(file, key, format!("\n{e}")))
}

fn evaluate(v: &Option<[Expr; 3]>, t: f64) -> Vector3<f64> {
    match v {
        Some(e) => Vector3::new(e[0].eval(&[t]), e[1].eval(&[t]), e[2].eval(&[t])),
        None => Vector3::zeros(),
    }
}

/// The motion of a driven end from its initial pose, parsed from a
/// [`MotionSpec`] and checked to vanish at t = 0: one reading for the rod
/// and the beam.
#[derive(Debug, Clone)]
pub(crate) struct EndMotion {
    displacement: Option<[Expr; 3]>,
    rotation: Option<[Expr; 3]>,
}

impl EndMotion {
    /// The motion of end `which` (`start` or `end`) from `spec`, its errors
    /// naming `ends.{which}_motion` and its keys.
    pub fn parse(file: &Path, which: &str, spec: &MotionSpec) -> Result<Self, CliError> {
        let key = format!("ends.{which}_motion");
        let displacement = parse_vector(file, &format!("{key}.displacement"), &spec.displacement)?;
        let rotation = parse_vector(file, &format!("{key}.rotation"), &spec.rotation)?;
        if displacement.is_none() && rotation.is_none() {
            return Err(key_error(
                file,
                &key,
                "a driven end needs `displacement` or `rotation` (three expressions in t each)",
            ));
        }
        for (name, v) in [("displacement", &displacement), ("rotation", &rotation)] {
            let at_start = evaluate(v, 0.0);
            if at_start.iter().any(|v| !v.is_finite()) || at_start.amax() > START_TOLERANCE {
                return Err(key_error(
                    file,
                    &format!("{key}.{name}"),
                    format!(
                        "must vanish at t = 0 (the end starts at its initial pose), got {:?}",
                        at_start.as_slice()
                    ),
                ));
            }
        }
        Ok(Self { displacement, rotation })
    }

    /// The pose at time `t` of an end whose initial pose is `rest`:
    /// (r₀ + Δr(t), exp(θ(t)) R₀).
    pub fn pose(&self, rest: &Pose<f64>, t: f64) -> Pose<f64> {
        let q = so3::exp(&evaluate(&self.rotation, t));
        Pose::new(
            rest.position + evaluate(&self.displacement, t),
            q.compose(&rest.rotation),
        )
    }
}

/// A material quantity: one number for the whole rod or beam, or an
/// expression in the material coordinate `s` (0 … length).
#[derive(Debug, Clone)]
pub(crate) enum Along {
    Value(f64),
    Expression(String),
}

impl<'de> Deserialize<'de> for Along {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Along;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number, or an expression in s as a string (e.g. \"0.02*(1 - 0.3*s)\")")
            }
            fn visit_f64<E>(self, v: f64) -> Result<Along, E> {
                Ok(Along::Value(v))
            }
            fn visit_i64<E>(self, v: i64) -> Result<Along, E> {
                Ok(Along::Value(v as f64))
            }
            fn visit_u64<E>(self, v: u64) -> Result<Along, E> {
                Ok(Along::Value(v as f64))
            }
            fn visit_str<E>(self, v: &str) -> Result<Along, E> {
                Ok(Along::Expression(v.to_string()))
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// An entry of an array of `Along` values (the beam's velocity fields).
impl crate::scenario::Entry for Along {
    const PLURAL: &'static str = "numbers or expressions in s";
    fn entry_schema() -> serde_json::Value {
        serde_json::json!({ "anyOf": [{ "type": "number" }, { "type": "string" }] })
    }
    fn entry(v: &toml::Value) -> Result<Self, String> {
        match v {
            toml::Value::Integer(i) => Ok(Along::Value(*i as f64)),
            toml::Value::Float(x) if x.is_finite() => Ok(Along::Value(*x)),
            toml::Value::String(s) => Ok(Along::Expression(s.clone())),
            other => Err(format!("expected a number or an expression in s, got {other}")),
        }
    }
}

/// A number, or an expression in the material coordinate s.
impl schemars::JsonSchema for Along {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "Along".into()
    }
    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "anyOf": [{ "type": "number" }, { "type": "string" }],
            "x-type": "float, or an expression in s (string)"
        })
    }
}

impl Along {
    /// The values at the material points `points`, each positive and
    /// finite, or an error naming `key` (and the point).
    pub(crate) fn at(&self, path: &Path, key: &str, points: &[f64]) -> Result<Vec<f64>, CliError> {
        match self {
            Along::Value(v) => Ok(vec![positive_value(path, key, *v)?; points.len()]),
            Along::Expression(source) => {
                let e = parse_expression(path, key, source, &["s"])?;
                points
                    .iter()
                    .map(|&s| {
                        let v = e.eval(&[s]);
                        if v.is_finite() && v > 0.0 {
                            Ok(v)
                        } else {
                            Err(key_error(
                                path,
                                key,
                                format!("at s = {s}: {v}, must be positive and finite"),
                            ))
                        }
                    })
                    .collect()
            }
        }
    }

    /// The values at the points `points` (positive or not), each finite, or
    /// an error naming `key` (and the point).
    pub(crate) fn finite_at(&self, path: &Path, key: &str, points: &[f64]) -> Result<Vec<f64>, CliError> {
        let values = match self {
            Along::Value(v) => vec![*v; points.len()],
            Along::Expression(source) => {
                let e = parse_expression(path, key, source, &["s"])?;
                points.iter().map(|&s| e.eval(&[s])).collect()
            }
        };
        match values.iter().zip(points).find(|(v, _)| !v.is_finite()) {
            Some((v, s)) => Err(key_error(path, key, format!("at s = {s}: {v}, must be finite"))),
            None => Ok(values),
        }
    }
}
