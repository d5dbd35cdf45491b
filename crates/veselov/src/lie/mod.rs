//! Lie group toolkit for SO(3) and SE(3): exponential and Cayley retractions,
//! their right-trivialised derivatives, adjoint and coadjoint actions,
//! geodesics and distances.
//!
//! Every map is generic over a scalar `D: DualNum<Primitive = f64> + Copy`
//! (`f64` or any `num-dual` number), so exact first and higher derivatives
//! flow through every formula. Coefficients that are removable singularities
//! at zero angle (sin θ/θ, (1 − cos θ)/θ², …) are evaluated as power series
//! **in θ²** below a threshold, never through `sqrt(θ²)`, so values and dual
//! parts are exact to round-off at θ = 0, at θ = 1e-9 and everywhere in
//! between (see the private `series` module for the thresholds).
//!
//! # Sources
//!
//! * *Note 000*: `notes/000-multisymplectic-beam.md` (Demoures, Gay-Balmaz,
//!   Ratiu, arXiv 1310.4772; seed `000_*`), §1 (pairings, Ad\*), §12
//!   (retractions, eq. (62)–(64)), §13 (SE(3) primitives).
//! * *Note 003*: `notes/003-cellular-complexes-cosserat.md` (Casimiro,
//!   Rodrigo; seed `003_*`), §2.6 (SO(3) toolkit, eqs. (6.8), (6.9), Lemma 6.6,
//!   Lemma 6.7, Def. 6.9).
//! * *External*: standard closed forms (Rodrigues; the SE(3) left Jacobian of
//!   Barfoot & Furgale, IEEE T-RO 30(3), 2014, reordered to (ω; v)).
//!   Every derivative formula is tested against central finite differences
//!   and against the exact dual-number derivative of the map itself.
//!
//! # Conventions
//!
//! * **Algebra ordering.** so(3) ≅ R³ through `hat(ω) e = ω × e`
//!   ([`so3::hat`], [`so3::vee`]). se(3) ≅ R⁶ with **angular part first**:
//!   ξ = (ω; v), `hat(ξ) = [[ω̂, v], [0, 0]]` (4×4) ([`se3::hat`],
//!   [`se3::vee`]). This is the ordering of note 000 (E6 = (0,0,0,0,0,1) is the
//!   unit axial strain).
//! * **Group elements.** [`SO3`] wraps a rotation matrix R; [`SE3`] is (R, x)
//!   acting on points by p ↦ Rp + x, with homogeneous matrix [[R, x], [0, 1]].
//! * **Retractions** τ: 𝔤 → G with τ(0) = e (seed 000 §4, note 000 §12):
//!   `exp` and the matrix **Cayley map** `cay(ξ) = (I − ξ̂/2)⁻¹(I + ξ̂/2)`.
//!   The factor ½ inside the Cayley map is the scaling fixed by note 000 §13;
//!   with it cay(ξ) = exp(ξ) + O(|ξ|³) and dcay₀ = I, and a rotation vector ω
//!   is mapped to the rotation of angle θ = 2 atan(|ω|/2) about ω/|ω|.
//! * **Right trivialisation** (seed 000 eq. (62), note 000 §12):
//!   `d^Rτ_ξ(δ) = (T_ξτ · δ) τ(ξ)⁻¹`, i.e.
//!   τ(ξ + εδ) = τ(ε dτ_ξ δ) τ(ξ) + O(ε²); and `dτ⁻¹_ξ := (dτ_ξ)⁻¹`.
//!   The left-trivialised derivative (used in note 003, where dexp and dlog are
//!   left-trivialised) is `d^Lτ_ξ = d^Rτ_{−ξ}` for both exp and cay, because
//!   τ(−ξ) = τ(ξ)⁻¹; and `d^Rτ_ξ = Ad_{τ(ξ)} d^Lτ_ξ`.
//! * **Dual pairing** ⟨μ, ξ⟩ = μᵀξ in the same (ω; v) / (moment; force)
//!   ordering.
//! * **Ad\* — two different objects, two names.**
//!   - `ad_star_matrix(g)` = (Ad_g)ᵀ. This is what seed 000 and note 000 §1
//!     write as Ad\*_g (eq. (64), (68)): ⟨Ad\*_g μ, ξ⟩ = ⟨μ, Ad_g ξ⟩. It is an
//!     anti-homomorphism: Ad\*_{gh} = Ad\*_h Ad\*_g.
//!   - `coadjoint(g)` = (Ad_{g⁻¹})ᵀ, the coadjoint *action* of g on 𝔤\*
//!     (a homomorphism). For SE(3) it maps body momentum (m; f) to spatial
//!     momentum (Rm + x × Rf; Rf) (note 000 §13 "spatial momentum").
//!   - `ad_star(ξ)` = (ad_ξ)ᵀ, the infinitesimal version used in the
//!     Euler–Poincaré equations (note 000 §3, eq. (24)).
//!
//! # Formulas
//!
//! With ω ∈ R³, W = ω̂, θ = |ω|, and the coefficient functions
//! A = sin θ/θ, B = (1 − cos θ)/θ², C = (θ − sin θ)/θ³,
//! k = 1/θ² − (1 + cos θ)/(2θ sin θ) (note 003 Def. 6.9),
//! c₂ = (θ² + 2cos θ − 2)/(2θ⁴), c₃ = (2θ − 3 sin θ + θ cos θ)/(2θ⁵):
//!
//! **SO(3)** ([`so3`])
//! * exp ω = I + A W + B W² (Rodrigues; note 003 eq. (6.8)).
//! * log R: the unique ω with |ω| < π and exp ω = R (note 003 Lemma 6.6),
//!   computed from the unit quaternion (q_w ≥ 0, q_v) of R as
//!   ω = 2 atan2(|q_v|, q_w) q_v/|q_v| (derived; accurate near 0 and π).
//! * cay ω = I + 4/(4 + θ²)(W + W²/2) (note 000 §13);
//!   cay⁻¹ R: ω̂ = 2(R − I)(R + I)⁻¹ (note 000 §13), computed as ω = 2 q_v/q_w
//!   (derived, equivalent).
//! * dexp_ω = I + B W + C W² (right-trivialised; note 003 §2.6 gives the
//!   left-trivialised I − B W + C W²).
//! * dexp⁻¹_ω = I − W/2 + k W² (note 003 Def. 6.9 gives the left-trivialised
//!   dlog v = I + v̂/2 + k v̂² = dexp⁻¹_{−v}).
//! * dcay_ω = 2/(4 + θ²)(2I + W); dcay⁻¹_ω = I − W/2 + ωωᵀ/4
//!   (note 000 §13, upper-left blocks).
//! * Ad_R = R, ad_ω = W, Ad\*_R (`ad_star_matrix`) = Rᵀ, coadjoint(R) = R.
//!
//! **SE(3)** ([`se3`]), ξ = (ω; v), V = v̂, J = dexp_ω (SO(3)):
//! * exp ξ = (exp ω, J v); log (R, x) = (ω, J⁻¹x), ω = log R, J⁻¹ = dexp⁻¹_ω.
//! * cay ξ = (cay ω, 2/(4 + θ²)(2I + W + ωωᵀ/2) v) (note 000 §13);
//!   cay⁻¹ (R, x) = (ω, (I − W/2) x), ω = cay⁻¹ R. The published variant with
//!   translation 2/(4 + θ²)(2I + W) v is **not** the matrix Cayley map
//!   (note 000 §13 pitfall; re-checked here against (I − ξ̂/2)⁻¹(I + ξ̂/2)).
//! * dexp_ξ = [[J, 0], [Q, J]] with
//!   Q = V/2 + C(WV + VW + WVW) + c₂(W²V + VW² − 3WVW) + c₃(WVW² + W²VW)
//!   (external: Barfoot–Furgale's left Jacobian, which is this module's
//!   right-trivialised derivative, with blocks reordered to (ω; v));
//!   dexp⁻¹_ξ = [[J⁻¹, 0], [−J⁻¹QJ⁻¹, J⁻¹]].
//! * In 4×4 form `dcay_ξ(δ) = (I − ξ̂/2)⁻¹ δ̂ (I + ξ̂/2)⁻¹` (derived); in
//!   blocks (note 000 §13):
//!   dcay_ξ = [[2/(4+θ²)(2I + W), 0], [V(2I + W)/(4+θ²), I + (W² + 2W)/(4+θ²)]],
//!   dcay⁻¹_ξ = [[I − W/2 + ωωᵀ/4, 0], [−½(I − W/2)V, I − W/2]].
//! * Ad_(R,x) = [[R, 0], [x̂R, R]], ad_ξ = [[W, 0], [V, W]] (note 000 §13);
//!   `ad_star_matrix(g)` = Ad_gᵀ: (m; f) ↦ (Rᵀ(m − x × f); Rᵀf);
//!   `coadjoint(g)` = Ad_{g⁻¹}ᵀ: (m; f) ↦ (Rm + x × Rf; Rf) (note 000 §13).
//!
//! **Geodesics and distances** (note 003 eq. (6.9), Lemma 6.7):
//! γ(s) = g₀ exp(s log(g₀⁻¹g₁)), d(g₀, g₁) = |log(g₀⁻¹g₁)|. On SO(3) this is
//! the geodesic and distance of the bi-invariant metric ⟨A, B⟩ = ½ tr AᵀB. On
//! SE(3) the curve is the constant-screw motion and the "distance" is the
//! plain Euclidean norm of (ω; v) (radians and lengths mixed, no weights).
//!
//! # Cut locus
//!
//! log and cay⁻¹ are defined for rotation angles θ < π. Within
//! [`CUT_LOCUS_MARGIN`] of π they return [`LieError::NearCutLocus`]: there the
//! logarithm jumps between ±π n and |cay⁻¹| → ∞, so no value is meaningful.

use std::fmt;

use nalgebra::SMatrix;
use num_dual::DualNum;

mod family;
pub mod retraction;
pub mod se3;
pub(crate) mod series;
pub(crate) mod series_lanes;
pub mod so3;

pub use family::{GroupFamily, RigidMotions, Rotations};
pub use retraction::{CayleyMap, ExpMap, GroupOf, Retraction};
pub use se3::SE3;
pub use so3::SO3;

/// log and cay⁻¹ refuse rotations whose angle θ satisfies θ > π − `CUT_LOCUS_MARGIN`
/// (radians). At this margin the inverse Cayley map has |ω| ≈ 4/margin = 4·10⁶
/// and both inverses are still accurate to about ε/margin ≈ 2·10⁻¹⁰ relative.
pub const CUT_LOCUS_MARGIN: f64 = 1e-6;

/// Largest entry of |RᵀR − I| accepted by the checked constructors
/// [`SO3::from_matrix`] and [`SE3::from_matrix`].
pub const ORTHOGONALITY_TOLERANCE: f64 = 1e-9;

/// Errors raised by the Lie group maps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LieError {
    /// log or cay⁻¹ was asked for a rotation whose angle is within
    /// [`CUT_LOCUS_MARGIN`] of π, where the inverse retraction is not defined.
    NearCutLocus {
        /// The rotation angle θ ∈ [0, π] of the offending element (radians).
        angle: f64,
    },
    /// A matrix given as a rotation (or rigid motion) is not orthogonal with
    /// determinant +1 (or has a wrong homogeneous row).
    NotARotation {
        /// Size of the defect: max |RᵀR − I|, |det R − 1| or the homogeneous
        /// row error, whichever is largest.
        defect: f64,
    },
    /// A quaternion of (near) zero norm cannot represent a rotation.
    ZeroQuaternion {
        /// Its norm.
        norm: f64,
    },
}

impl fmt::Display for LieError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LieError::NearCutLocus { angle } => write!(
                f,
                "rotation angle {angle} is within {CUT_LOCUS_MARGIN:e} of π (cut locus): \
                 the inverse retraction is not defined there"
            ),
            LieError::NotARotation { defect } => {
                write!(f, "matrix is not a proper rotation / rigid motion (defect {defect:e})")
            }
            LieError::ZeroQuaternion { norm } => {
                write!(f, "quaternion of norm {norm:e} does not represent a rotation")
            }
        }
    }
}

impl std::error::Error for LieError {}

/// Result alias for this module.
pub type LieResult<T> = Result<T, LieError>;

/// A matrix Lie group of dimension `N` whose elements carry scalars of type
/// `D`: the group operations and the adjoint representations an integrator
/// needs, with the conventions of the [module documentation](self).
pub trait LieGroup<D: DualNum<Primitive = f64> + Copy, const N: usize>: Sized + Clone {
    /// The identity element e.
    fn identity() -> Self;
    /// The product `self · other`.
    fn compose(&self, other: &Self) -> Self;
    /// The inverse element.
    fn inverse(&self) -> Self;
    /// The relative element `self⁻¹ · other` (a group may compute it
    /// without forming the inverse).
    fn between(&self, other: &Self) -> Self {
        self.inverse().compose(other)
    }
    /// Ad_g as an N×N matrix: Ad_g ξ = (g ξ̂ g⁻¹)ˇ.
    fn adjoint(&self) -> SMatrix<D, N, N>;
    /// (Ad_g)ᵀ — the operator seed 000 writes Ad\*_g: ⟨Ad\*_g μ, ξ⟩ = ⟨μ, Ad_g ξ⟩.
    fn ad_star_matrix(&self) -> SMatrix<D, N, N> {
        self.adjoint().transpose()
    }
    /// The coadjoint action (Ad_{g⁻¹})ᵀ on dual vectors (a homomorphism).
    fn coadjoint(&self) -> SMatrix<D, N, N> {
        self.inverse().adjoint().transpose()
    }
}

/// Property-test configuration shared by the module's tests: failing cases
/// are reported but not persisted to regression files.
#[cfg(test)]
pub(crate) fn test_config() -> proptest::test_runner::Config {
    proptest::test_runner::Config {
        failure_persistence: None,
        ..proptest::test_runner::Config::default()
    }
}
