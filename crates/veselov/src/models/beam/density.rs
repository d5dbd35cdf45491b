//! The beam's density K(ξ) − Φ(η) − Π(g) (seed 000 eq. (95)) as a
//! [`SplitDensity`] on SE(3), and its discrete Lagrangian on seed 000's
//! triangles, ℒ̄_d = ΔsΔt [K(ξ) − Φ(η) − ½(Π(g₁) + Π(g₃))] (note 000
//! §15.2, with the potential averaged over the cell's space edge: see
//! [`crate::evolution::split::SplitLagrangian`]).
//!
//! Gravity: Π(g) = −ρA ⟨𝐠, r⟩ per unit length for the acceleration 𝐠 (for
//! example (0, 0, −9.81) m/s²) and the centreline position r of g = (Λ, r).

use nalgebra::{SMatrix, SVector, Vector3};

use super::section::BeamProperties;
use crate::ad::Scalar;
use crate::error::Result;
use crate::evolution::split::{DiagonalQuadratic, GroupIncrement, SplitDensity, SplitLagrangian};
use crate::field::fibre::RigidMotions;
use crate::lie::{CayleyMap, ExpMap, LieGroup, SE3};
use crate::models::end_load::EndLoad;

/// K(ξ) = ½⟨𝕁ξ, ξ⟩, Φ(η) = ½⟨ℂ(η − E6), η − E6⟩, Π(g) = −ρA⟨𝐠, r⟩.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamDensity {
    /// 𝕁 and ℂ.
    pub properties: BeamProperties,
    /// Gravitational acceleration 𝐠 (zero: no potential).
    pub gravity: [f64; 3],
    /// Viscous damping per unit length, diag(c) ≥ 0: force density −cₖξₖ in
    /// the body frame (angular first).
    pub damping: [f64; 6],
    /// A force and a torque on the last node (spatial frame), applied by
    /// the end cell of the trapezoid rule
    /// ([`KineticQuadrature::Trapezoid`](crate::evolution::split::KineticQuadrature)).
    pub end_load: EndLoad,
}

impl BeamDensity {
    /// A beam without gravity.
    pub fn new(properties: BeamProperties) -> Self {
        Self {
            properties,
            gravity: [0.0; 3],
            damping: [0.0; 6],
            end_load: EndLoad::default(),
        }
    }
    /// The same beam with a load on its last node.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] naming the load's part at fault
    /// ([`EndLoad::validate`]).
    pub fn with_end_load(self, end_load: EndLoad) -> Result<Self> {
        end_load.validate()?;
        Ok(Self { end_load, ..self })
    }
    /// The same beam with viscous damping diag(c).
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] naming `damping[k]` when an entry
    /// is negative or not finite (damping must not inject energy).
    pub fn with_damping(self, c: [f64; 6]) -> Result<Self> {
        for (k, &x) in c.iter().enumerate() {
            if !(x.is_finite() && x >= 0.0) {
                return Err(crate::Error::InvalidParameter {
                    name: format!("damping[{k}]"),
                    value: x.to_string(),
                    reason: "must be finite and >= 0".into(),
                });
            }
        }
        Ok(Self { damping: c, ..self })
    }
    /// The same beam under gravity `g` (m/s²).
    pub fn with_gravity(self, g: [f64; 3]) -> Self {
        Self { gravity: g, ..self }
    }
    /// Mass per unit length ρA.
    pub fn mass_per_length(&self) -> f64 {
        self.properties.inertia[3]
    }
}

/// The unstrained reference E6 = (0, 0, 0, 0, 0, 1).
pub const E6: [f64; 6] = [0.0, 0.0, 0.0, 0.0, 0.0, 1.0];

fn quadratic<D: Scalar>(w: &[f64; 6], x: &SVector<D, 6>, r: &[f64; 6]) -> D {
    DiagonalQuadratic::<6>::quadratic(w, x, r)
}

impl SplitDensity<RigidMotions, 6> for BeamDensity {
    fn kinetic<D: Scalar>(&self, xi: &SVector<D, 6>) -> D {
        quadratic(&self.properties.inertia, xi, &[0.0; 6])
    }
    fn stored<D: Scalar>(&self, eta: &SVector<D, 6>) -> D {
        quadratic(&self.properties.stiffness, eta, &E6)
    }
    fn kinetic_gradient<D: Scalar>(&self, xi: &SVector<D, 6>) -> SVector<D, 6> {
        DiagonalQuadratic::<6>::quadratic_gradient(&self.properties.inertia, xi, &[0.0; 6])
    }
    fn stored_gradient<D: Scalar>(&self, eta: &SVector<D, 6>) -> SVector<D, 6> {
        DiagonalQuadratic::<6>::quadratic_gradient(&self.properties.stiffness, eta, &E6)
    }
    /// diag(𝕁).
    fn kinetic_hessian(&self, _xi: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        SMatrix::from_diagonal(&SVector::from(self.properties.inertia))
    }
    /// diag(ℂ).
    fn stored_hessian(&self, _eta: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        SMatrix::from_diagonal(&SVector::from(self.properties.stiffness))
    }
    #[inline]
    fn potential<D: Scalar>(&self, g: &SE3<D>) -> D {
        let r = g.translation();
        let m = self.mass_per_length();
        -(r[0] * self.gravity[0] + r[1] * self.gravity[1] + r[2] * self.gravity[2]) * m
    }
    /// ∇Π(g) = (0; −ρA Λᵀ𝐠) in the chart g·exp(ε), ε = (ω; v): the
    /// centreline of g·exp(ε) is r + Λ dexp(ω)v, which moves by Λv to first
    /// order (the dual pass through exp gives the same numbers).
    fn potential_gradient<D: Scalar>(&self, g: &SE3<D>) -> SVector<D, 6> {
        let lambda = g.rotation().matrix();
        let m = self.mass_per_length();
        let gr = &self.gravity;
        SVector::from_fn(|k, _| {
            if k < 3 {
                D::zero()
            } else {
                let j = k - 3;
                -(lambda[(0, j)] * gr[0] + lambda[(1, j)] * gr[1] + lambda[(2, j)] * gr[2]) * m
            }
        })
    }
    fn has_potential(&self) -> bool {
        self.gravity.iter().any(|&g| g != 0.0)
    }
    fn is_damped(&self) -> bool {
        self.damping.iter().any(|&c| c > 0.0)
    }
    fn damping<D: Scalar>(&self, xi: &SVector<D, 6>) -> SVector<D, 6> {
        SVector::from_fn(|k, _| xi[k] * (-self.damping[k]))
    }
    /// −diag(c).
    fn damping_jacobian(&self, _xi: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        SMatrix::from_diagonal(&SVector::from(self.damping.map(|c| -c)))
    }
    fn has_end_load(&self) -> bool {
        !self.end_load.is_zero()
    }
    /// (Λᵀτ; ΛᵀF) at time t ([`EndLoad::body`]), angular first.
    fn end_load<D: Scalar>(&self, g: &SE3<D>, t: f64) -> SVector<D, 6> {
        let (force, torque) = self.end_load.body(g.rotation().matrix(), t);
        SVector::from_fn(|k, _| if k < 3 { torque[k] } else { force[k - 3] })
    }
}

/// The beam's discrete Lagrangian with the retraction `R`.
pub type BeamLagrangian<R> = SplitLagrangian<GroupIncrement<R>, BeamDensity>;
/// With the Cayley map (the paper's choice).
pub type CayleyBeam = BeamLagrangian<CayleyMap>;
/// With the exponential map.
pub type ExpBeam = BeamLagrangian<ExpMap>;

/// ℒ̄_d for `density` with steps `dt`, `ds`.
///
/// # Errors
/// [`crate::Error::InvalidParameter`] naming `dt` or `ds` when not positive.
pub fn beam_lagrangian<R>(density: BeamDensity, dt: f64, ds: f64) -> Result<BeamLagrangian<R>> {
    SplitLagrangian::new(density, dt, ds)
}

/// The generators of left translations in the chart g·τ(x): X(g) = Ad_{g⁻¹},
/// so that J = X(g)ᵀ ∂ℒ/∂g = Ad*_{g⁻¹}(g⁻¹D_gℒ) is the spatial momentum map
/// (note 000 (77): angular part first).
pub fn left_generators(g: &SE3<f64>) -> SMatrix<f64, 6, 6> {
    g.inverse().adjoint()
}

/// A reference configuration: the straight beam along E3, node a at
/// (I, (0, 0, a·Δs)).
pub fn straight(ds: f64, a: usize) -> SE3<f64> {
    SE3::from_translation(Vector3::new(0.0, 0.0, a as f64 * ds))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::evolution::split::chart_gradient;
    use crate::lie::se3;

    /// The closed-form ∇Π against the dual pass through the chart and
    /// against central differences of Π(g·exp(ε)), at random frames.
    #[test]
    fn potential_gradient_is_the_chart_derivative() {
        let properties =
            BeamProperties::from_diagonals([5e-4, 4e-4, 9e-4, 2.5, 2.5, 2.5], [1e3, 2e3, 3e3, 1e5, 1e5, 2e5])
                .expect("section");
        let density = BeamDensity::new(properties).with_gravity([0.3, -9.81, 1.2]);
        let mut uniform = crate::test_support::uniform(0x9e37_79b9_7f4a_7c15);
        for _ in 0..20 {
            let xi = SVector::<f64, 6>::from_fn(|_, _| 2.0 * uniform());
            let g = se3::exp(&xi);
            let closed = density.potential_gradient(&g);
            let dual = chart_gradient::<RigidMotions, f64, 6>(|z| density.potential(z), &g);
            let scale = closed.amax();
            assert!(
                (closed - dual).amax() <= 4.0 * f64::EPSILON * scale,
                "{closed} against {dual}"
            );
            let h = 1e-6;
            for k in 0..6 {
                let e = SVector::<f64, 6>::ith(k, h);
                let moved = |e: SVector<f64, 6>| density.potential(&g.compose(&se3::exp(&e)));
                let fd = (moved(e) - moved(-e)) / (2.0 * h);
                assert!(
                    (fd - closed[k]).abs() <= 1e-8 * scale,
                    "direction {k}: {fd} against {}",
                    closed[k]
                );
            }
        }
    }
}
