//! Group families: one marker type per matrix group, naming its elements for
//! every scalar type, so that code written once (a reduced Lagrangian, an
//! integrator) can be evaluated with `f64` and with dual numbers alike.

use std::fmt::Debug;

use nalgebra::{Matrix3, SMatrix, SVector};
use num_dual::{Derivative, DualSVec};

use super::{LieGroup, SE3, SO3, se3, so3};
use crate::ad::Scalar;

/// A matrix Lie group of dimension `N`, as a family of element types indexed
/// by the scalar.
pub trait GroupFamily<const N: usize>: 'static {
    /// The group's elements with scalars of type `D`.
    type Element<D: Scalar>: LieGroup<D, N> + Copy + Debug + PartialEq;

    /// Apply `f` to every scalar of an element (changes the scalar type).
    fn map_scalar<D: Scalar, E: Scalar>(g: &Self::Element<D>, f: impl Fn(D) -> E) -> Self::Element<E>;

    /// Lift an `f64` element into constants of the scalar type `D`.
    fn lift<D: Scalar>(g: &Self::Element<f64>) -> Self::Element<D> {
        Self::map_scalar(g, D::from)
    }

    /// The element with rotation part `r` and translation part `x` (`x` is
    /// ignored on SO(3)). `r` is trusted to be a rotation.
    fn from_parts<D: Scalar>(r: Matrix3<D>, x: SVector<D, 3>) -> Self::Element<D>;

    /// g·(I + η̂) with η the N seed directions of a dual number over `D`:
    /// agrees with g·τ(η) to first order in η for every retraction
    /// (dτ₀ = I), so it gives exact left-trivialised gradients
    /// ∇f(g)ᵢ = d/dε f(g τ(ε eᵢ))|₀ at the price of f64 products (it is not a
    /// group element beyond first order: use it for first derivatives only).
    fn seeded_perturbation<D: Scalar>(g: &Self::Element<D>) -> Self::Element<DualSVec<D, N>>;

    /// The angular and linear parts (ω, v) of an algebra element (v = 0 on
    /// SO(3)).
    fn split_velocity<D: Scalar>(xi: &SVector<D, N>) -> (SVector<D, 3>, SVector<D, 3>);

    /// ad_ξ as an N×N matrix: ad_ξ η = [ξ̂, η̂]ˇ.
    fn ad<D: Scalar>(xi: &SVector<D, N>) -> SMatrix<D, N, N>;

    /// The rotation part R of an element (R itself on SO(3)).
    fn rotation<D: Scalar>(g: &Self::Element<D>) -> Matrix3<D>;

    /// The translation part x of an element (zero on SO(3)).
    fn translation<D: Scalar>(g: &Self::Element<D>) -> SVector<D, 3>;

    /// One Newton–Schulz step R ← R(3I − RᵀR)/2 towards the nearest rotation
    /// (the polar factor). For R orthogonal to δ it returns R orthogonal to
    /// O(δ²) + round-off and moves R by O(δ): applied after every time step it
    /// keeps ‖RᵀR − I‖ at round-off without a measurable change of the
    /// trajectory.
    fn reorthogonalize(g: &Self::Element<f64>) -> Self::Element<f64>;

    /// max |RᵀR − I| over the entries of the rotation part.
    fn orthogonality_defect(g: &Self::Element<f64>) -> f64 {
        let r = Self::rotation(g);
        (r.transpose() * r - Matrix3::identity()).abs().max()
    }
}

/// The rotation group SO(3) (elements [`SO3`], algebra R³).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rotations;

/// The rigid-motion group SE(3) (elements [`SE3`], algebra R⁶ ordered (ω; v)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RigidMotions;

/// Entries R + Σ_m ε_m R ê_m (the rotation part of g·(I + η̂), η = seeds).
fn seeded_rotation<D: Scalar, const N: usize>(r: &Matrix3<D>) -> Matrix3<DualSVec<D, N>> {
    // (R ê_m)_{ij} = Σ_k R_ik (ê_m)_kj with (ê_m)_kj = −ε_{mkj}·(−1) = ε_{kmj}.
    Matrix3::from_fn(|i, j| {
        let mut eps = SVector::<D, N>::zeros();
        for m in 0..3 {
            let mut s = D::zero();
            for k in 0..3 {
                let levi = levi_civita(k, m, j);
                if levi != 0.0 {
                    s += r[(i, k)] * levi;
                }
            }
            eps[m] = s;
        }
        DualSVec::new(r[(i, j)], Derivative::some(eps))
    })
}

/// ε_{ijk}: (ê_m)_{kj} = (e_m × e_j)_k = ε_{kmj}.
fn levi_civita(i: usize, j: usize, k: usize) -> f64 {
    match (i, j, k) {
        (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
        (0, 2, 1) | (2, 1, 0) | (1, 0, 2) => -1.0,
        _ => 0.0,
    }
}

fn newton_schulz(r: &Matrix3<f64>) -> Matrix3<f64> {
    let rtr = r.transpose() * r;
    r * (Matrix3::identity() * 3.0 - rtr) * 0.5
}

impl GroupFamily<3> for Rotations {
    type Element<D: Scalar> = SO3<D>;
    fn map_scalar<D: Scalar, E: Scalar>(g: &SO3<D>, f: impl Fn(D) -> E) -> SO3<E> {
        SO3::from_matrix_unchecked(g.matrix().map(f))
    }
    fn from_parts<D: Scalar>(r: Matrix3<D>, _x: SVector<D, 3>) -> SO3<D> {
        SO3::from_matrix_unchecked(r)
    }
    fn split_velocity<D: Scalar>(xi: &SVector<D, 3>) -> (SVector<D, 3>, SVector<D, 3>) {
        (*xi, SVector::zeros())
    }
    fn seeded_perturbation<D: Scalar>(g: &SO3<D>) -> SO3<DualSVec<D, 3>> {
        SO3::from_matrix_unchecked(seeded_rotation::<D, 3>(g.matrix()))
    }
    fn ad<D: Scalar>(xi: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        so3::ad(xi)
    }
    fn rotation<D: Scalar>(g: &SO3<D>) -> Matrix3<D> {
        *g.matrix()
    }
    fn translation<D: Scalar>(_g: &SO3<D>) -> SVector<D, 3> {
        SVector::zeros()
    }
    fn reorthogonalize(g: &SO3<f64>) -> SO3<f64> {
        SO3::from_matrix_unchecked(newton_schulz(g.matrix()))
    }
}

impl GroupFamily<6> for RigidMotions {
    type Element<D: Scalar> = SE3<D>;
    fn map_scalar<D: Scalar, E: Scalar>(g: &SE3<D>, f: impl Fn(D) -> E) -> SE3<E> {
        SE3::new(
            SO3::from_matrix_unchecked(g.rotation().matrix().map(&f)),
            g.translation().map(&f),
        )
    }
    fn from_parts<D: Scalar>(r: Matrix3<D>, x: SVector<D, 3>) -> SE3<D> {
        SE3::new(SO3::from_matrix_unchecked(r), x)
    }
    fn split_velocity<D: Scalar>(xi: &SVector<D, 6>) -> (SVector<D, 3>, SVector<D, 3>) {
        se3::split(xi)
    }
    fn seeded_perturbation<D: Scalar>(g: &SE3<D>) -> SE3<DualSVec<D, 6>> {
        // (R, x)(I + η̂) = (R(I + ω̂), x + R v), η = (ω; v) seeds 0..3 and 3..6.
        let r = g.rotation().matrix();
        let rot = seeded_rotation::<D, 6>(r);
        let x = g.translation();
        let trans = SVector::<DualSVec<D, 6>, 3>::from_fn(|i, _| {
            let mut eps = SVector::<D, 6>::zeros();
            for k in 0..3 {
                eps[3 + k] = r[(i, k)];
            }
            DualSVec::new(x[i], Derivative::some(eps))
        });
        SE3::new(SO3::from_matrix_unchecked(rot), trans)
    }
    fn ad<D: Scalar>(xi: &SVector<D, 6>) -> SMatrix<D, 6, 6> {
        se3::ad(xi)
    }
    fn rotation<D: Scalar>(g: &SE3<D>) -> Matrix3<D> {
        *g.rotation().matrix()
    }
    fn translation<D: Scalar>(g: &SE3<D>) -> SVector<D, 3> {
        *g.translation()
    }
    fn reorthogonalize(g: &SE3<f64>) -> SE3<f64> {
        SE3::new(
            SO3::from_matrix_unchecked(newton_schulz(g.rotation().matrix())),
            *g.translation(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newton_schulz_restores_orthogonality() {
        let r = so3::exp(&SVector::<f64, 3>::new(0.3, -1.2, 2.0));
        let perturbed =
            SO3::from_matrix_unchecked(r.matrix() + Matrix3::new(1., 2., 3., 4., 5., 6., 7., 8., 9.) * 1e-9);
        assert!(Rotations::orthogonality_defect(&perturbed) > 1e-9);
        let fixed = Rotations::reorthogonalize(&perturbed);
        assert!(Rotations::orthogonality_defect(&fixed) <= 4.0 * f64::EPSILON);
        assert!((fixed.matrix() - r.matrix()).abs().max() <= 2e-8);
    }
}
