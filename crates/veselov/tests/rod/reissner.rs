//! The static cantilever of Reissner's geometrically exact planar rod (the
//! plane case of the Cosserat rod, linear constitutive law), the continuum
//! reference of the large-deflection test. Clamped at s = 0 along e₃, a dead
//! force F e₁ at the free end s = L. With θ the section's rotation about e₂
//! (R e₃ = (sin θ, 0, cos θ), R e₁ = (cos θ, 0, −sin θ)) the internal force is
//! n = F e₁ all along; its material components Rᵀn = (F cos θ, 0, F sin θ)
//! give the shear and axial strains ε₁ = F cos θ/κGA and ε₃ = F sin θ/EA,
//! the tangent r′ = R(ε₁e₁ + (1 + ε₃)e₃), and the balance of moments
//! m′ + r′ × n = 0 with m = EIθ′e₂ reads
//!
//! EIθ″ = −F r′_z = −F (cos θ (1 + ε₃) − sin θ ε₁),
//!
//! with θ(0) = 0 and θ′(L) = 0 (no end moment). Solved by shooting on θ′(0)
//! (secant iterations from the linear beam's FL/EI) with RK4 along the
//! length. For small F the tip deflection is Timoshenko's FL³/(3EI) +
//! FL/(κGA).

use nalgebra::Vector4;

use crate::rk4::rk4;

/// RK4 steps over the length: the O(h⁴) error is below 1e-14 relative.
const STEPS: usize = 20_000;

/// A uniform planar Reissner rod: EI, κGA, EA and its length.
#[derive(Clone, Copy, Debug)]
pub struct Reissner {
    pub ei: f64,
    pub kga: f64,
    pub ea: f64,
    pub length: f64,
}

impl Reissner {
    /// (θ, θ′, x, z) at s = L from θ′(0) = `slope` under the end force `force`.
    fn shoot(&self, force: f64, slope: f64) -> Vector4<f64> {
        let rhs = |y: &Vector4<f64>| {
            let (sin, cos) = y[0].sin_cos();
            let (shear, axial) = (force * cos / self.kga, force * sin / self.ea);
            let tangent_x = cos * shear + sin * (1.0 + axial);
            let tangent_z = cos * (1.0 + axial) - sin * shear;
            Vector4::new(y[1], -force * tangent_z / self.ei, tangent_x, tangent_z)
        };
        rk4(Vector4::new(0.0, slope, 0.0, 0.0), self.length, STEPS, rhs, |_, _| {})
    }

    /// The tip position (x, z) of the cantilever under the end force `force`
    /// (the shooting converged to |θ′(L)| ≤ 1e-13·θ′(0)).
    pub fn tip(&self, force: f64) -> (f64, f64) {
        let mut a = force * self.length / self.ei;
        let mut fa = self.shoot(force, a)[1];
        let mut b = 1.01 * a;
        for _ in 0..60 {
            let end = self.shoot(force, b);
            if end[1].abs() <= 1e-13 * b.abs() {
                return (end[2], end[3]);
            }
            let next = b - end[1] * (b - a) / (end[1] - fa);
            (a, fa, b) = (b, end[1], next);
        }
        panic!("shooting did not converge");
    }
}
