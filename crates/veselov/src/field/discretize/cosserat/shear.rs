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
//! points, where Prop. 6.5 is off by +14.9 %, +4.0 %, +1.0 %). Its step is
//! the core's generic one (6-D Newton over dual numbers): the split step's
//! closed forms are Prop. 6.5's.

use nalgebra::Vector3;

use super::CosseratCell;
use crate::ad::Scalar;
use crate::field::discretize::rod_potential::RodPotential;
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

/// ε in the centred frame from ε₀ = R₀ᵀg − e in the base vertex's frame:
/// exp(−a/2)(ε₀ + e) − e.
pub(super) fn centred_strain<D: Scalar>(
    eps_at_vertex: &Vector3<D>,
    a: &Vector3<D>,
    strain: &Vector3<f64>,
) -> Vector3<D> {
    let e = strain.map(D::from);
    so3::exp(&(a * D::from(-0.5))).act(&(eps_at_vertex + e)) - e
}

impl<P: RodPotential> CosseratCell<P> {
    /// The cell with its shear strain in `frame` ([`ShearFrame`]). The
    /// closed forms (gradients and split step) are Prop. 6.5's: with
    /// [`ShearFrame::Centred`] the core uses the dual-number passes and
    /// the generic 6-D Newton, whatever
    /// [`with_analytic_gradients`](Self::with_analytic_gradients) says.
    #[must_use]
    pub fn with_shear_frame(mut self, frame: ShearFrame) -> Self {
        self.shear = frame;
        self
    }

    /// The frame of the shear strain.
    pub fn shear_frame(&self) -> ShearFrame {
        self.shear
    }

    /// Whether the closed forms of Prop. 6.5 are in use: enabled, and the
    /// shear measured in the base vertex's frame.
    pub(in crate::field::discretize) fn closed_forms(&self) -> bool {
        self.analytic && self.shear == ShearFrame::Vertex
    }
}
