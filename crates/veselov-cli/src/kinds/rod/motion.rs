//! Expressions in a rod scenario: an initial centreline `r(s)` in the
//! material coordinate `s` (`Centreline`, `[initial] shape = "curve"`) and
//! driven ends in the run's time `t`, as the rod's end conditions (their
//! reading, shared with the beam, is [`crate::kinds::structure`]).
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
use veselov::expr::Expr;
use veselov::field::fibre::Pose;
use veselov::models::rod::EndCondition;

use crate::error::CliError;
use crate::kinds::structure::{EndMotion, MotionSpec, parse_in};
use crate::scenario::{Array, key_error};

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
