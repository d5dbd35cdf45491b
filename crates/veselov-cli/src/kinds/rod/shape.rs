//! The initial shape of a rod: the pose s ↦ (r, R) of each material point
//! at rest, its frame along the centreline's tangent.

use nalgebra::Vector3;
use veselov::field::fibre::Pose;
use veselov::lie::so3;

use super::motion::Centreline;

/// The initial shape s ↦ (r, R) at rest.
#[derive(Debug, Clone)]
pub(crate) enum Shape {
    /// Along e₃.
    Straight,
    /// An arc of curvature κ in the x–z plane, tangent e₃ at s = 0.
    Bent { curvature: f64 },
    /// A helix about e₃ of the given radius and pitch, by arc length.
    Helix { radius: f64, pitch: f64 },
    /// A centreline given by expressions in s, framed along its tangent.
    Curve(Centreline),
}

impl Shape {
    /// The pose at material coordinate s: the frame's third axis along the
    /// tangent (the unstressed strain of the rod is e₃).
    pub fn pose(&self, s: f64) -> Pose<f64> {
        match *self {
            Shape::Straight => Pose::new(Vector3::new(0.0, 0.0, s), so3::exp(&Vector3::zeros())),
            Shape::Bent { curvature: k } => {
                let angle = k * s;
                let (x, z) = if k.abs() * s < 1e-8 {
                    (0.5 * k * s * s, s)
                } else {
                    ((1.0 - angle.cos()) / k, angle.sin() / k)
                };
                Pose::new(Vector3::new(x, 0.0, z), so3::exp(&Vector3::new(0.0, angle, 0.0)))
            }
            Shape::Helix { radius, pitch } => {
                // Arc length per turn ℓ = √((2πa)² + h²); φ = 2πs/ℓ.
                let turn = std::f64::consts::TAU;
                let ell = (turn * radius).hypot(pitch);
                let phi = turn * s / ell;
                let r = Vector3::new(radius * phi.cos() - radius, radius * phi.sin(), pitch * phi / turn);
                let tangent = Vector3::new(-radius * phi.sin(), radius * phi.cos(), pitch / turn) * (turn / ell);
                Pose::new(r, frame_along(&tangent))
            }
            Shape::Curve(ref curve) => {
                let tangent = curve.tangent(s);
                Pose::new(curve.position(s), frame_along(&(tangent / tangent.norm())))
            }
        }
    }
}

/// The rotation taking e₃ to the unit vector `t` by the smallest angle.
fn frame_along(t: &Vector3<f64>) -> veselov::lie::SO3<f64> {
    let e3 = Vector3::new(0.0, 0.0, 1.0);
    let axis = e3.cross(t);
    let (sin, cos) = (axis.norm(), e3.dot(t));
    if sin < 1e-15 {
        // Along e₃ (no rotation) or against it (a half turn about e₁).
        let angle = if cos > 0.0 { 0.0 } else { std::f64::consts::PI };
        return so3::exp(&Vector3::new(angle, 0.0, 0.0));
    }
    so3::exp(&(axis / sin * sin.atan2(cos)))
}
