//! Rigid bodies as reduced Lagrangians on SO(3) and SE(3), for the
//! Lie-group variational integrators of [`crate::lgvi`].
//!
//! Body frame throughout: ξ = g⁻¹ġ is the body angular velocity Ω on SO(3)
//! and the body twist (Ω; v) on SE(3); 𝕀 is the inertia tensor about the
//! pivot (heavy top) or the centre of mass (free bodies).

use nalgebra::{Matrix3, SMatrix, Vector3};

use crate::ad::Scalar;
use crate::error::{Error, Result};
use crate::lgvi::{SplitReducedLagrangian, check_inertia};
use crate::lie::{RigidMotions, Rotations, SE3, SO3};

fn check_positive(name: &str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidParameter {
            name: name.into(),
            value: value.to_string(),
            reason: "must be positive and finite".into(),
        })
    }
}

/// The free rigid body on SO(3): ℓ(R, Ω) = ½ Ωᵀ𝕀Ω. Invariant under R ↦ QR,
/// so the spatial angular momentum π = RΠ (Π = 𝕀Ω) is conserved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeRigidBody {
    inertia: Matrix3<f64>,
}

impl FreeRigidBody {
    /// A body with inertia tensor 𝕀 (symmetric positive definite).
    pub fn new(inertia: Matrix3<f64>) -> Result<Self> {
        check_inertia(&inertia)?;
        Ok(Self { inertia })
    }
}

impl SplitReducedLagrangian<Rotations, 3> for FreeRigidBody {
    fn inertia(&self) -> SMatrix<f64, 3, 3> {
        self.inertia
    }
    #[inline]
    fn potential<D: Scalar>(&self, _g: &SO3<D>) -> D {
        D::zero()
    }
}

/// The heavy top: a rigid body with a fixed point in uniform gravity,
/// ℓ(R, Ω) = ½ Ωᵀ𝕀Ω − m g e₃·(Rχ), χ the centre of mass in the body frame,
/// 𝕀 about the fixed point, gravity along −e₃. Invariant under rotations about
/// the vertical, so e₃·(RΠ) is conserved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeavyTop {
    inertia: Matrix3<f64>,
    mass: f64,
    centre_of_mass: Vector3<f64>,
    gravity: f64,
}

impl HeavyTop {
    /// A top with inertia 𝕀 about the pivot, mass m > 0, body-frame centre of
    /// mass χ and gravitational acceleration g ≥ 0.
    pub fn new(inertia: Matrix3<f64>, mass: f64, centre_of_mass: Vector3<f64>, gravity: f64) -> Result<Self> {
        check_inertia(&inertia)?;
        check_positive("mass", mass)?;
        crate::error::check_finite("centre_of_mass", centre_of_mass.as_slice())?;
        if !(gravity.is_finite() && gravity >= 0.0) {
            return Err(Error::InvalidParameter {
                name: "gravity".into(),
                value: gravity.to_string(),
                reason: "must be finite and non-negative".into(),
            });
        }
        Ok(Self {
            inertia,
            mass,
            centre_of_mass,
            gravity,
        })
    }
}

impl SplitReducedLagrangian<Rotations, 3> for HeavyTop {
    fn inertia(&self) -> SMatrix<f64, 3, 3> {
        self.inertia
    }
    #[inline]
    fn potential<D: Scalar>(&self, g: &SO3<D>) -> D {
        let r = g.matrix();
        let c = &self.centre_of_mass;
        (r[(2, 0)] * c[0] + r[(2, 1)] * c[1] + r[(2, 2)] * c[2]) * (self.mass * self.gravity)
    }
}

/// A free rigid body on SE(3) (free flight, no gravity):
/// ℓ((R, x), (Ω; v)) = ½ Ωᵀ𝕀Ω + ½ m |v|², with v the body-frame velocity of
/// the centre of mass. Left invariant, so the spatial momentum
/// (Rm + x × Rf; Rf) = (angular momentum about the origin; linear momentum)
/// is conserved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeRigidBodySE3 {
    inertia: Matrix3<f64>,
    mass: f64,
}

impl FreeRigidBodySE3 {
    /// A body with inertia 𝕀 about its centre of mass and mass m > 0.
    pub fn new(inertia: Matrix3<f64>, mass: f64) -> Result<Self> {
        check_inertia(&inertia)?;
        check_positive("mass", mass)?;
        Ok(Self { inertia, mass })
    }
}

impl SplitReducedLagrangian<RigidMotions, 6> for FreeRigidBodySE3 {
    fn inertia(&self) -> SMatrix<f64, 6, 6> {
        let mut m = SMatrix::<f64, 6, 6>::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.inertia);
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass));
        m
    }
    #[inline]
    fn potential<D: Scalar>(&self, _g: &SE3<D>) -> D {
        D::zero()
    }
}

impl FreeRigidBody {
    /// The exact body angular velocity Ω(t) of the Euler top (Landau &
    /// Lifshitz, Mechanics §37) for a diagonal inertia I₁ < I₂ < I₃ and an
    /// initial Ω(0) = (Ω₁, 0, Ω₃) with Ω₁, Ω₃ > 0 and M² > 2E·I₂ (rotation
    /// about the axis of largest inertia):
    ///
    /// ```text
    /// Ω₁ = A₁ cn τ,  Ω₂ = A₂ sn τ,  Ω₃ = A₃ dn τ,   τ = ν t,
    /// A₁² = (2E I₃ − M²)/(I₁(I₃ − I₁)),  A₂² = (2E I₃ − M²)/(I₂(I₃ − I₂)),
    /// A₃² = (M² − 2E I₁)/(I₃(I₃ − I₁)),  ν² = (I₃ − I₂)(M² − 2E I₁)/(I₁I₂I₃),
    /// m = k² = (I₂ − I₁)(2E I₃ − M²)/((I₃ − I₂)(M² − 2E I₁)).
    /// ```
    ///
    /// (The sign of Ω₂ follows from I₂Ω̇₂ = (I₃ − I₁)Ω₃Ω₁ > 0 at t = 0.)
    /// Errors name the violated condition.
    pub fn exact_body_angular_velocity(&self, omega0: &Vector3<f64>, t: f64) -> Result<Vector3<f64>> {
        let bad = |name: &str, reason: &str| Error::InvalidParameter {
            name: name.into(),
            value: format!("{:?}", omega0.as_slice()),
            reason: reason.into(),
        };
        let i = self.inertia;
        let off_diagonal = i[(0, 1)].abs() + i[(0, 2)].abs() + i[(1, 2)].abs();
        let (i1, i2, i3) = (i[(0, 0)], i[(1, 1)], i[(2, 2)]);
        if off_diagonal != 0.0 || !(i1 < i2 && i2 < i3) {
            return Err(bad(
                "inertia",
                "the exact solution needs a diagonal inertia with I₁ < I₂ < I₃",
            ));
        }
        if omega0[1] != 0.0 || !(omega0[0] > 0.0 && omega0[2] > 0.0) {
            return Err(bad(
                "omega0",
                "the exact solution is written for Ω(0) = (Ω₁ > 0, 0, Ω₃ > 0)",
            ));
        }
        let m2 = (i1 * omega0[0]).powi(2) + (i3 * omega0[2]).powi(2);
        let e2 = i1 * omega0[0].powi(2) + i3 * omega0[2].powi(2);
        if m2 <= e2 * i2 {
            return Err(bad("omega0", "the exact solution is written for M² > 2E·I₂"));
        }
        let a1 = ((e2 * i3 - m2) / (i1 * (i3 - i1))).sqrt();
        let a2 = ((e2 * i3 - m2) / (i2 * (i3 - i2))).sqrt();
        let a3 = ((m2 - e2 * i1) / (i3 * (i3 - i1))).sqrt();
        let nu = ((i3 - i2) * (m2 - e2 * i1) / (i1 * i2 * i3)).sqrt();
        let k2 = (i2 - i1) * (e2 * i3 - m2) / ((i3 - i2) * (m2 - e2 * i1));
        let j = crate::special::jacobi_elliptic(nu * t, k2).map_err(|e| bad("omega0", &e.to_string()))?;
        Ok(Vector3::new(a1 * j.cn, a2 * j.sn, a3 * j.dn))
    }
}
