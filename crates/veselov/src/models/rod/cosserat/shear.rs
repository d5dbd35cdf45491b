//! Which frame a rod cell measures its shear strain with.
//!
//! Prop. 6.5 takes the frame R₀ of the cell's base vertex:
//! ε = R₀ᵀg − e with g = (2r₁ − r₀ − r₂)/(σΔs), the chord from the base
//! material point (the mean of r₀ and r₂) to its neighbour r₁. In bending,
//! the chord points along the rod's tangent halfway between the two
//! material points, while R₀'s third axis is the tangent at the base: a
//! curvature ψ′ leaves a spurious shear of about δψ′/2 (δ the spacing of
//! the material points) whose energy stiffens the bending by a relative
//! 0.245κGAδ²/EI — shear locking ([`crate::models::rod::resolution`]).
//!
//! The centred frame R_c = R₀ exp(a/2), a = log(R₀ᵀR₁), lies halfway along
//! the rotation to the neighbour's frame, where the chord is measured:
//!
//! ε = exp(a/2)ᵀR₀ᵀg − e,
//!
//! and the spurious shear is O(δ²ψ′), so the lattice does not lock (the
//! reduced integration of the shear term of finite-element rods). It
//! changes no other term of Prop. 6.5 and keeps the cell Lagrangian
//! invariant under rigid motions (a is, and R_cᵀg is), so the discrete
//! Noether momenta are conserved exactly as before. It is not one of the
//! paper's quadratures of the density (6.1): a departure from Prop. 6.5,
//! measured in `tests/rod/` (the first free–free bending frequency of a
//! rod of radius ℓ/20 off by −0.62 %, −0.16 %, −0.039 % at 21, 41, 81
//! points, where Prop. 6.5 is off by +14.9 %, +4.0 %, +1.0 %).
//!
//! The shear does not depend on R₂, so the split step of note 003 §3.6
//! keeps its shape: with E = exp(a/2), κ = Δt/(4Δs) and each cell's
//! ∂Leg_r/∂r₂ = −R₀[K + κ(EC₁Eᵀ − C₁)]R₀ᵀ (K of `StepConstants`), the
//! position is one 3×3 solve with the matrix summed over the cells based
//! at v. With m = ε + e = EᵀR₀ᵀg and τ = A_β m × C₁ε, the variation
//! δε = −(J_r(a/2)·½δa) × m − Eᵀ(ξ₀ × R₀ᵀg), δa = D_a ξ₁ − D_aᵀ ξ₀
//! (left-trivialised perturbations R_k exp(ξ_k); J_r the right Jacobian of
//! exp, D_a = dlog a) gives the shear's rotation gradients
//!
//! ∇_{R₀} = Eτ − ½D_a J_r(a/2)ᵀτ,  ∇_{R₁} = ½D_aᵀ J_r(a/2)ᵀτ,
//!
//! and its position gradients are Prop. 6.5's with R₀ replaced by R₀E.
//! The rotation equation in b is unchanged. The eight-lane kernel
//! (`lane_step`) does the same, every vertex with its scalar bits.

use nalgebra::{Matrix3, Vector3};

use crate::ad::Scalar;
use crate::lie::so3;

/// The frame of a rod cell's shear strain.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum ShearFrame {
    /// R₀, the base vertex's frame: Prop. 6.5 (the default).
    #[default]
    Vertex,
    /// R₀ exp(a/2), halfway to the neighbour's frame: free of shear
    /// locking (see the module documentation).
    Centred,
}

/// The centred frame of one cell relative to R₀, E = exp(a/2), and the
/// transposed right Jacobian of exp there, J_r(a/2)ᵀ = dexp_{a/2}
/// ([`so3::dexp`] is the left one, J_r(c) = dexp_{−c} = dexp_cᵀ).
#[derive(Clone, Copy, Debug)]
pub(in crate::models::rod) struct CentredFrame {
    pub(in crate::models::rod) rotation: Matrix3<f64>,
    jacobian_t: Matrix3<f64>,
}

impl CentredFrame {
    /// The frame of a cell with a = log(R₀ᵀR₁).
    pub(in crate::models::rod) fn at(a: &Vector3<f64>) -> Self {
        let half = a * 0.5;
        Self {
            rotation: so3::exp(&half).into_matrix(),
            jacobian_t: so3::dexp(&half),
        }
    }

    /// The shear's rotation gradients at the base and middle vertices from
    /// τ = A_β m × C₁ε and D_a: (Eτ − ½D_a J_r(a/2)ᵀτ, ½D_aᵀ J_r(a/2)ᵀτ).
    pub(in crate::models::rod) fn torques(
        &self,
        da: &Matrix3<f64>,
        tau: &Vector3<f64>,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let half = self.jacobian_t * tau * 0.5;
        (self.rotation * tau - da * half, da.tr_mul(&half))
    }

    /// ε = Eᵀ(ε₀ + e) − e from ε₀ = R₀ᵀg − e: the bits of
    /// [`centred_strain`] (a split step's stored gradients are those a
    /// restored march recomputes from the values).
    pub(in crate::models::rod) fn strain(&self, eps_at_vertex: &Vector3<f64>, e: &Vector3<f64>) -> Vector3<f64> {
        self.rotation.transpose() * (eps_at_vertex + e) - e
    }
}

/// ε in the centred frame from ε₀ = R₀ᵀg − e in the base vertex's frame:
/// exp(−a/2)(ε₀ + e) − e.
pub(super) fn centred_strain<D: Scalar>(
    eps_at_vertex: &Vector3<D>,
    a: &Vector3<D>,
    strain: &Vector3<f64>,
) -> Vector3<D> {
    let e = strain.map(D::from);
    so3::exp(&(a * D::from(0.5))).into_matrix().transpose() * (eps_at_vertex + e) - e
}
