//! Expressions in a rod scenario: an initial centreline `r(s)` in the
//! material coordinate `s` (`Centreline`, `[initial] shape = "curve"`),
//! driven ends in the run's time `t`, and the parsing that these and the
//! initial field `r(s, t)`, `θ(s, t)` of [`super::initial`] share.
//!
//! Driven rod ends from the command line: `[ends] start = "driven"` (or
//! `end`) with `[ends.start_motion]` giving the end's motion as expressions in
//! the run's time `t` (the expression language of custom models: `t`, `pi`,
//! `e`, the operators and functions `veselov expressions` lists):
//!
//! ```toml
//! [ends]
//! start = "driven"
//! [ends.start_motion]
//! displacement = ["0", "0.01*sin(20*t)", "0"]   # m, added to the initial position
//! rotation = ["0", "0", "0.2*sin(10*t)"]        # rad, a rotation vector applied to the initial frame
//! ```
//!
//! The end's pose at time `t` is `(r₀ + Δr(t), exp(θ(t)) R₀)`, `(r₀, R₀)` its
//! initial pose; `Δr` and `θ` default to zero and must vanish at `t = 0` (the
//! end starts where the rod is).

use std::path::Path;
use std::sync::Arc;

use nalgebra::Vector3;
use serde::Deserialize;
use veselov::expr::{Expr, SymbolTable};
use veselov::field::fibre::Pose;
use veselov::lie::so3;
use veselov::models::rod::EndCondition;

use crate::error::CliError;
use crate::scenario::{Array, key_error};

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

/// The driven end `which` (`start` or `end`) from `spec`, starting at `rest`;
/// the march's lattice time `t_lattice` is the run's `t_lattice − offset`.
pub(crate) fn driven_end(
    file: &Path,
    which: &str,
    spec: &MotionSpec,
    rest: Pose<f64>,
    offset: f64,
) -> Result<EndCondition, CliError> {
    let motion = EndMotion::parse(file, which, spec)?;
    Ok(EndCondition::Driven(Arc::new(move |t_lattice| {
        motion.pose(&rest, t_lattice - offset)
    })))
}

/// An initial centreline `r(s)`, three expressions in the material
/// coordinate `s` (arc length of the unstressed rod: where `|dr/ds| ≠ 1` the
/// rod starts stretched or compressed). The frame at `s` is the smallest
/// rotation taking `e₃` to the unit tangent `r'(s)/|r'(s)|`, the tangent
/// computed exactly (dual numbers).
#[derive(Debug, Clone)]
pub(crate) struct Centreline {
    position: Arc<[Expr; 3]>,
}

impl Centreline {
    /// Parse `[initial] position` and check it at the material points
    /// `points` (finite, with a non-zero tangent), naming `key`.
    pub fn new(file: &Path, key: &str, sources: &Array<String, 3>, points: &[f64]) -> Result<Self, CliError> {
        let position = parse_in(file, key, sources, &["s"])?;
        let curve = Self {
            position: Arc::new(position),
        };
        for &s in points {
            let (r, tangent) = (curve.position(s), curve.tangent(s));
            if r.iter().chain(tangent.iter()).any(|v| !v.is_finite()) || tangent.norm() < 1e-12 {
                return Err(key_error(
                    file,
                    key,
                    format!(
                        "at s = {s}: r = {:?}, dr/ds = {:?}; the centreline must be finite with a non-zero tangent",
                        r.as_slice(),
                        tangent.as_slice()
                    ),
                ));
            }
        }
        Ok(curve)
    }

    /// `r(s)`.
    pub fn position(&self, s: f64) -> Vector3<f64> {
        Vector3::from_fn(|a, _| self.position[a].eval(&[s]))
    }

    /// `dr/ds` at `s`.
    pub fn tangent(&self, s: f64) -> Vector3<f64> {
        use veselov::num_dual::Dual64;
        Vector3::from_fn(|a, _| self.position[a].eval(&[Dual64::new(s, 1.0)]).eps)
    }
}
