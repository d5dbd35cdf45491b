//! What a held rod or beam did, read from the rows of its centreline: the
//! tip's displacement and rotation, the largest deflection, and the
//! reaction at the support — the keys of `summary.json` and the words of
//! the final report line shared by the rod and the beam.
//!
//! Conventions (for both kinds):
//!
//! - The reference is the first row written (t = 0); the values are those of
//!   the last row written (t_final for a completed run), the same numbers as
//!   `centerline.npy` and the frames' file hold.
//! - The *tip* is the free end of a structure held at one end only (a
//!   cantilever): the last node when the start is held, node 0 when the end
//!   is. Its displacement is u = r_tip(t) − r_tip(0); its rotation is the
//!   rotation vector θ of R_tip(t) R_tip(0)ᵀ = exp(θ̂) in the spatial frame
//!   (|θ| the angle, θ/|θ| the axis).
//! - The *deflection* of node k is |r_k(t) − r_k(0)|, its distance from its
//!   own place on the initial centreline; `deflection_max` is the largest
//!   over the nodes, at the material coordinate `deflection_max_s`.
//! - The *reaction* is the force F and the moment M that the support exerts
//!   on the structure, M taken about the support point r_s:
//!   M = M_O − r_s × F for the moment M_O about the origin. At a static
//!   cantilever under an end force F_end at r_tip, F = −F_end and
//!   M = −(r_tip − r_s) × F_end.

use nalgebra::{Matrix3, Vector3};
use serde_json::{Map, Value, json};
use veselov::lie::{SO3, so3};
use veselov::run::Words;

use crate::output::{approx, number, significant};

/// The held ends of a rod or beam (start, end).
pub(crate) type Held = [bool; 2];

/// The end a tip or a support is at.
fn end_name(end: usize) -> &'static str {
    if end == 0 { "start" } else { "end" }
}

/// The tip of a structure held at its ends `held`: the other end's node
/// (`nodes` nodes), when exactly one end is held.
fn tip(held: Held, nodes: usize) -> Option<(usize, usize)> {
    match held {
        [true, false] => Some((1, nodes - 1)),
        [false, true] => Some((0, 0)),
        _ => None,
    }
}

/// The first and the last row of a held structure's centreline and of its
/// tip's frame, for the displacements of [`ShapeChange::keys`].
#[derive(Debug, Clone)]
pub(crate) struct ShapeChange {
    /// The material coordinate s_k of each node.
    s: Vec<f64>,
    held: Held,
    /// Positions (nodes × 3) and the tip's frame (R row by row) of the
    /// first row written, then of the last.
    first: Vec<f64>,
    first_frame: [f64; 9],
    last: Vec<f64>,
    last_frame: [f64; 9],
}

impl ShapeChange {
    /// A structure of nodes at the material coordinates `s`, held at `held`.
    pub(crate) fn new(s: Vec<f64>, held: Held) -> Self {
        Self {
            s,
            held,
            first: Vec::new(),
            first_frame: [f64::NAN; 9],
            last: Vec::new(),
            last_frame: [f64::NAN; 9],
        }
    }

    /// The node of the tip, if the structure has one.
    pub(crate) fn tip_node(&self) -> Option<usize> {
        tip(self.held, self.s.len()).map(|(_, node)| node)
    }

    /// A row written: `positions` (nodes × 3) and the tip's frame
    /// `tip_frame` (R row by row; anything when there is no tip).
    pub(crate) fn record(&mut self, positions: &[f64], tip_frame: [f64; 9]) {
        if self.first.is_empty() {
            self.first = positions.to_vec();
            self.first_frame = tip_frame;
        }
        self.last.clear();
        self.last.extend_from_slice(positions);
        self.last_frame = tip_frame;
    }

    /// Position of node `k` in `rows` (nodes × 3).
    fn point(rows: &[f64], k: usize) -> Vector3<f64> {
        Vector3::new(rows[3 * k], rows[3 * k + 1], rows[3 * k + 2])
    }

    /// The position of node `k` in the last row, if any row was written.
    pub(crate) fn last_point(&self, k: usize) -> Option<Vector3<f64>> {
        (self.last.len() >= 3 * (k + 1)).then(|| Self::point(&self.last, k))
    }

    /// Checkpoint words: both rows and frames (the last row only to keep
    /// the layout fixed; it is rewritten by the next row).
    pub(crate) fn save(&self, out: &mut Vec<f64>) {
        let n = 3 * self.s.len();
        let row = |v: &Vec<f64>| if v.len() == n { v.clone() } else { vec![f64::NAN; n] };
        out.extend(row(&self.first));
        out.extend(self.first_frame);
        out.extend(row(&self.last));
        out.extend(self.last_frame);
    }

    /// Read back what [`save`](Self::save) wrote.
    pub(crate) fn restore(&mut self, w: &mut Words<'_>) -> veselov::Result<()> {
        let n = 3 * self.s.len();
        let (mut first, mut last) = (vec![0.0; n], vec![0.0; n]);
        w.fill(&mut first)?;
        w.fill(&mut self.first_frame)?;
        w.fill(&mut last)?;
        w.fill(&mut self.last_frame)?;
        let written = |v: Vec<f64>| if v.iter().all(|x| x.is_nan()) { Vec::new() } else { v };
        self.first = written(first);
        self.last = written(last);
        Ok(())
    }

    /// The tip's displacement u = r_tip(t) − r_tip(0) and rotation vector θ
    /// (R(t)R(0)ᵀ = exp(θ̂); `None` at the angle π, where it is not unique)
    /// with its angle, if there is a tip and a row was written.
    pub(crate) fn tip(&self) -> Option<Tip> {
        let (end, node) = tip(self.held, self.s.len())?;
        if self.last.len() != 3 * self.s.len() || self.first.len() != self.last.len() {
            return None;
        }
        let u = Self::point(&self.last, node) - Self::point(&self.first, node);
        let r0 = Matrix3::from_row_slice(&self.first_frame);
        let r1 = Matrix3::from_row_slice(&self.last_frame);
        let relative = SO3::from_matrix_unchecked(r1 * r0.transpose());
        // The angle from the trace, clamped against round-off: defined at π too.
        let cos = (0.5 * (relative.matrix().trace() - 1.0)).clamp(-1.0, 1.0);
        let vector = so3::log(&relative).ok().filter(|v| v.iter().all(|x| x.is_finite()));
        Some(Tip {
            end: end_name(end),
            s: self.s[node],
            displacement: u,
            rotation_vector: vector,
            rotation_angle: vector.map_or(cos.acos(), |v| v.norm()),
        })
    }

    /// The largest deflection max_k |r_k(t) − r_k(0)| and the material
    /// coordinate of its node (the first of equal ones), if a row was
    /// written and the structure is held.
    pub(crate) fn deflection_max(&self) -> Option<(f64, f64)> {
        if self.held == [false, false] || self.last.len() != 3 * self.s.len() || self.first.len() != self.last.len() {
            return None;
        }
        let mut best: Option<(f64, f64)> = None;
        for (k, &s) in self.s.iter().enumerate() {
            let d = (Self::point(&self.last, k) - Self::point(&self.first, k)).norm();
            // A NaN deflection is reported, not skipped.
            if best.is_none_or(|(b, _)| d > b || d.is_nan() && !b.is_nan()) {
                best = Some((d, s));
            }
        }
        best
    }

    /// The keys of `summary.json`: `tip_end`, `tip_s`, `tip_displacement`,
    /// `tip_displacement_magnitude`, `tip_rotation_vector`,
    /// `tip_rotation_angle`, `deflection_max`, `deflection_max_s` (`null`
    /// where not defined).
    pub(crate) fn keys(&self) -> Map<String, Value> {
        let tip = self.tip();
        let deflection = self.deflection_max();
        let mut m = Map::new();
        let mut put = |k: &str, v: Value| m.insert(k.to_string(), v);
        put("tip_end", json!(tip.as_ref().map(|t| t.end)));
        put("tip_s", json!(tip.as_ref().map(|t| t.s)));
        put("tip_displacement", json!(tip.as_ref().map(|t| vector(&t.displacement))));
        put(
            "tip_displacement_magnitude",
            json!(tip.as_ref().map(|t| t.displacement.norm())),
        );
        put(
            "tip_rotation_vector",
            json!(tip.as_ref().and_then(|t| t.rotation_vector.as_ref().map(vector))),
        );
        put("tip_rotation_angle", json!(tip.as_ref().map(|t| t.rotation_angle)));
        put("deflection_max", json!(deflection.map(|d| d.0)));
        put("deflection_max_s", json!(deflection.map(|d| d.1)));
        m
    }

    /// The words of the final report line: the tip's displacement and
    /// rotation (or the largest deflection without a tip); empty for a
    /// structure that is not held.
    pub(crate) fn report(&self) -> String {
        if let Some(t) = self.tip() {
            let u = &t.displacement;
            format!(
                ", tip displacement {} m ({}, {}, {}), tip rotation {} rad",
                significant(u.norm(), 4),
                approx(u[0]),
                approx(u[1]),
                approx(u[2]),
                significant(t.rotation_angle, 4)
            )
        } else if let Some((d, s)) = self.deflection_max() {
            format!(", largest deflection {} m at s = {}", significant(d, 4), number(s))
        } else {
            String::new()
        }
    }
}

/// The tip of a cantilever at the last row ([`ShapeChange::tip`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Tip {
    /// `start` or `end`.
    pub end: &'static str,
    /// Its material coordinate.
    pub s: f64,
    /// u = r_tip(t) − r_tip(0).
    pub displacement: Vector3<f64>,
    /// θ with R(t)R(0)ᵀ = exp(θ̂) (`None` at the angle π).
    pub rotation_vector: Option<Vector3<f64>>,
    /// |θ|, in [0, π].
    pub rotation_angle: f64,
}

fn vector(v: &Vector3<f64>) -> [f64; 3] {
    [v[0], v[1], v[2]]
}

/// The reaction of the support at one end: the force F and the moment M
/// (about the support point) the support exerts on the structure, from an
/// impulse over a time `span`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Reaction {
    /// `start` or `end`.
    pub end: &'static str,
    /// F (N).
    pub force: Vector3<f64>,
    /// M about the support point (N·m).
    pub moment: Vector3<f64>,
}

impl Reaction {
    /// The reaction at end `end` (0: start) from the impulse (linear,
    /// angular about the origin) the support gave over `span`, at the
    /// support point `at`: F = I/span, M = I_O/span − at × F.
    pub(crate) fn from_impulse(
        end: usize,
        (linear, angular): (Vector3<f64>, Vector3<f64>),
        span: f64,
        at: &Vector3<f64>,
    ) -> Self {
        let force = linear / span;
        // + 0.0: a zero component is written 0, not −0.
        Self {
            end: end_name(end),
            force: force.map(|x| x + 0.0),
            moment: (angular / span - at.cross(&force)).map(|x| x + 0.0),
        }
    }

    /// The keys of `summary.json`: `reaction_end`, `reaction_force`,
    /// `reaction_moment` (`null` without a reaction).
    pub(crate) fn keys(reaction: Option<&Self>) -> Map<String, Value> {
        let mut m = Map::new();
        m.insert("reaction_end".into(), json!(reaction.map(|r| r.end)));
        m.insert("reaction_force".into(), json!(reaction.map(|r| vector(&r.force))));
        m.insert("reaction_moment".into(), json!(reaction.map(|r| vector(&r.moment))));
        m
    }

    /// The words of the final report line.
    pub(crate) fn report(reaction: Option<&Self>) -> String {
        match reaction {
            Some(r) => {
                let v = |x: &Vector3<f64>| x.iter().map(|&c| significant(c, 4)).collect::<Vec<_>>().join(", ");
                format!(
                    ", reaction at the {} F = ({}) N, M = ({}) N·m",
                    r.end,
                    v(&r.force),
                    v(&r.moment)
                )
            }
            None => String::new(),
        }
    }
}

/// The structure's held end, if exactly one end is held: where a reaction
/// is reported (with both ends held the momentum balance gives only the
/// sum of the two reactions).
pub(crate) fn single_support(held: Held) -> Option<usize> {
    match held {
        [true, false] => Some(0),
        [false, true] => Some(1),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(r: &SO3<f64>) -> [f64; 9] {
        let m = r.matrix();
        std::array::from_fn(|i| m[(i / 3, i % 3)])
    }

    #[test]
    fn a_cantilever_tip_moves_and_turns_by_the_difference_of_its_rows() {
        let s = vec![0.0, 0.5, 1.0];
        let mut c = ShapeChange::new(s, [true, false]);
        let straight = [0.0, 0.0, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 1.0];
        c.record(&straight, frame(&SO3::identity()));
        let theta = Vector3::new(0.0, 0.02, 0.0);
        let bent = [0.0, 0.0, 0.0, 0.003, 0.0, 0.5, 0.01, 0.0, 0.9999];
        c.record(&bent, frame(&so3::exp(&theta)));
        let t = c.tip().expect("a tip");
        assert_eq!(t.end, "end");
        assert_eq!(t.displacement, Vector3::new(0.01, 0.0, 0.9999 - 1.0));
        let v = t.rotation_vector.expect("a rotation vector");
        assert!((v - theta).norm() < 1e-15, "{v}");
        assert!((t.rotation_angle - 0.02).abs() < 1e-15);
        let (d, at) = c.deflection_max().expect("held");
        assert_eq!((d, at), (t.displacement.norm(), 1.0));
        let keys = c.keys();
        assert_eq!(keys["tip_displacement"], json!([0.01, 0.0, 0.9999 - 1.0]));
        assert!(
            c.report()
                .contains("tip displacement 0.01 m (0.01, 0, -0.0001), tip rotation 0.02 rad"),
            "{}",
            c.report()
        );
        // Held at both ends: no tip, the deflection still; free: neither.
        let mut both = ShapeChange::new(vec![0.0, 0.5, 1.0], [true, true]);
        both.record(&straight, [0.0; 9]);
        let sagging = [0.0, 0.0, 0.0, 0.003, 0.0, 0.5, 0.0, 0.0, 1.0];
        both.record(&sagging, [0.0; 9]);
        assert!(both.tip().is_none() && both.keys()["tip_end"].is_null());
        assert_eq!(both.deflection_max(), Some((0.003, 0.5)));
        let free = ShapeChange::new(vec![0.0, 1.0], [false, false]);
        assert!(free.deflection_max().is_none() && free.report().is_empty());
    }

    #[test]
    fn the_reaction_moment_is_taken_about_the_support() {
        // A static cantilever from (0, 0, 1) to (0, 0, 2) under an end
        // force (1, 0, 0): the support gives −F and, about the origin,
        // −r_tip × F; about itself −(r_tip − r_s) × F.
        let f = Vector3::new(1.0, 0.0, 0.0);
        let (r_s, r_tip) = (Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.0, 0.0, 2.0));
        let span = 0.5;
        let r = Reaction::from_impulse(0, (-f * span, -r_tip.cross(&f) * span), span, &r_s);
        assert_eq!(r.force, -f);
        assert!((r.moment + (r_tip - r_s).cross(&f)).norm() < 1e-15, "{}", r.moment);
        assert_eq!(Reaction::keys(Some(&r))["reaction_end"], json!("start"));
        assert!(Reaction::keys(None)["reaction_force"].is_null());
    }
}
