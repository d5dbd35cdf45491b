//! Retractions τ: 𝔤 → G (seed 000 §4, note 000 §12) as types, so that an
//! integrator can be generic over the retraction and over the group.
//!
//! [`Retraction<N>`] is implemented by [`ExpMap`] and [`CayleyMap`] for
//! N = 3 (group [`SO3`]) and N = 6 (group [`SE3`], algebra ordering (ω; v)).
//! Derivatives are right-trivialised (seed 000 eq. (62)):
//! `τ(ξ + εδ) = τ(ε dtau(ξ) δ) τ(ξ) + O(ε²)` and `dtau_inv(ξ) = dtau(ξ)⁻¹`.
//!
//! A generic discrete-velocity computation, ξ = τ⁻¹(g₀⁻¹g₁)/h, reads
//! `R::tau_inv(&g0.between(&g1)).map(|x| x / h)` for any
//! `R: Retraction<N>`; [`GroupOf<R, N, D>`] provides compose/inverse/adjoint through
//! [`LieGroup`](super::LieGroup).

use nalgebra::{SMatrix, SVector};
use num_dual::{DualNum, DualSVec64};

use super::{GroupFamily, LieError, RigidMotions, Rotations, SE3, SO3, se3, so3};

/// The element type, with scalars `D`, of the group a retraction `R` maps into.
pub type GroupOf<R, const N: usize, D> = <<R as Retraction<N>>::Family as GroupFamily<N>>::Element<D>;

/// A retraction τ: 𝔤 ≅ Rᴺ → G with τ(0) = e, its inverse near e, and its
/// right-trivialised derivative and inverse derivative as N×N matrices.
pub trait Retraction<const N: usize> {
    /// The group family τ maps into.
    type Family: GroupFamily<N>;

    /// τ(ξ).
    fn tau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, N>) -> GroupOf<Self, N, D>;

    /// τ⁻¹(g); fails with [`LieError::NearCutLocus`] for rotation angles
    /// within [`CUT_LOCUS_MARGIN`](super::CUT_LOCUS_MARGIN) of π.
    fn tau_inv<D: DualNum<Primitive = f64> + Copy>(g: &GroupOf<Self, N, D>) -> Result<SVector<D, N>, LieError>;

    /// Right-trivialised derivative d^Rτ_ξ: τ(ξ + εδ) = τ(ε dτ_ξ δ) τ(ξ) + O(ε²).
    fn dtau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, N>) -> SMatrix<D, N, N>;

    /// Its inverse d^Rτ⁻¹_ξ = (d^Rτ_ξ)⁻¹ (closed form).
    fn dtau_inv<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, N>) -> SMatrix<D, N, N>;

    /// (d^Rτ⁻¹_ξ)ᵀ p, the pull-back of a covector p (a momentum) by τ⁻¹ —
    /// the product every discrete Legendre transform takes. Default: the
    /// matrix [`dtau_inv`](Self::dtau_inv) transposed times p; the Cayley
    /// map has it without forming the matrix.
    fn dtau_inv_tr_mul<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, N>, p: &SVector<D, N>) -> SVector<D, N> {
        Self::dtau_inv(xi).tr_mul(p)
    }

    /// ∂/∂ξ [(d^Rτ⁻¹_ξ)ᵀ p] at fixed p: with (d^Rτ⁻¹_ξ)ᵀ itself, the Newton
    /// Jacobian of a pulled-back momentum (d/dξ (dτ⁻¹_ξ)ᵀp(ξ) is this plus
    /// (dτ⁻¹_ξ)ᵀ ∂p/∂ξ). Default: one dual pass of N directions over
    /// [`dtau_inv_tr_mul`](Self::dtau_inv_tr_mul); the Cayley map has it in
    /// closed form.
    fn dtau_inv_tr_mul_derivative(xi: &SVector<f64, N>, p: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        let p = p.map(DualSVec64::<N>::from_re);
        num_dual::jacobian(|x| Self::dtau_inv_tr_mul(&x, &p), xi).1
    }

    /// The rotation angle of τ(ξ), from ξ alone: τ⁻¹(τ(ξ)) = ξ exactly when
    /// it is below π − [`CUT_LOCUS_MARGIN`](super::CUT_LOCUS_MARGIN) (the
    /// exponential chart wraps past π; τ⁻¹ refuses angles beyond the margin).
    fn rotation_angle(xi: &SVector<f64, N>) -> f64;
}

/// |ω| of the rotation part ω = (ξ₀, ξ₁, ξ₂) (angular first on SE(3)).
fn rotation_norm<const N: usize>(xi: &SVector<f64, N>) -> f64 {
    xi.fixed_rows::<3>(0).norm()
}

/// (dcay⁻¹_ω)ᵀ p = p + ½ ω × p + ¼ ω (ω·p) on so(3) ([`so3::dcay_inv`]).
fn cayley_rotation_pullback<D: DualNum<Primitive = f64> + Copy>(w: &SVector<D, 3>, p: &SVector<D, 3>) -> SVector<D, 3> {
    p + w.cross(p) * D::from(0.5) + w * (w.dot(p) * D::from(0.25))
}

/// ∂/∂ω of [`cayley_rotation_pullback`] at fixed p: −½p̂ + ¼((ω·p)I + ωpᵀ).
fn cayley_rotation_pullback_derivative(w: &SVector<f64, 3>, p: &SVector<f64, 3>) -> SMatrix<f64, 3, 3> {
    so3::hat(p) * -0.5 + (SMatrix::<f64, 3, 3>::identity() * w.dot(p) + w * p.transpose()) * 0.25
}

/// The exponential map as a retraction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ExpMap;

/// The Cayley map cay(ξ) = (I − ξ̂/2)⁻¹(I + ξ̂/2) as a retraction (scaling of
/// note 000 §13: cay(ξ) = exp(ξ) + O(|ξ|³)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct CayleyMap;

impl Retraction<3> for ExpMap {
    type Family = Rotations;
    fn tau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 3>) -> SO3<D> {
        so3::exp(xi)
    }
    fn tau_inv<D: DualNum<Primitive = f64> + Copy>(g: &SO3<D>) -> Result<SVector<D, 3>, LieError> {
        so3::log(g)
    }
    fn dtau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        so3::dexp(xi)
    }
    fn dtau_inv<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        so3::dexp_inv(xi)
    }
    /// |ω|.
    fn rotation_angle(xi: &SVector<f64, 3>) -> f64 {
        rotation_norm(xi)
    }
}

impl Retraction<3> for CayleyMap {
    type Family = Rotations;
    fn tau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 3>) -> SO3<D> {
        so3::cay(xi)
    }
    fn tau_inv<D: DualNum<Primitive = f64> + Copy>(g: &SO3<D>) -> Result<SVector<D, 3>, LieError> {
        so3::cay_inv(g)
    }
    fn dtau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        so3::dcay(xi)
    }
    fn dtau_inv<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        so3::dcay_inv(xi)
    }
    /// (I − ω̂/2 + ωωᵀ/4)ᵀ p = p + ½ ω × p + ¼ ω (ω·p).
    fn dtau_inv_tr_mul<D: DualNum<Primitive = f64> + Copy>(w: &SVector<D, 3>, p: &SVector<D, 3>) -> SVector<D, 3> {
        cayley_rotation_pullback(w, p)
    }
    /// −½p̂ + ¼((ω·p)I + ωpᵀ).
    fn dtau_inv_tr_mul_derivative(w: &SVector<f64, 3>, p: &SVector<f64, 3>) -> SMatrix<f64, 3, 3> {
        cayley_rotation_pullback_derivative(w, p)
    }
    /// 2 atan(|ω|/2).
    fn rotation_angle(xi: &SVector<f64, 3>) -> f64 {
        2.0 * (0.5 * rotation_norm(xi)).atan()
    }
}

impl Retraction<6> for ExpMap {
    type Family = RigidMotions;
    fn tau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 6>) -> SE3<D> {
        se3::exp(xi)
    }
    fn tau_inv<D: DualNum<Primitive = f64> + Copy>(g: &SE3<D>) -> Result<SVector<D, 6>, LieError> {
        se3::log(g)
    }
    fn dtau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 6>) -> SMatrix<D, 6, 6> {
        se3::dexp(xi)
    }
    fn dtau_inv<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 6>) -> SMatrix<D, 6, 6> {
        se3::dexp_inv(xi)
    }
    /// |ω|.
    fn rotation_angle(xi: &SVector<f64, 6>) -> f64 {
        rotation_norm(xi)
    }
}

impl Retraction<6> for CayleyMap {
    type Family = RigidMotions;
    fn tau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 6>) -> SE3<D> {
        se3::cay(xi)
    }
    fn tau_inv<D: DualNum<Primitive = f64> + Copy>(g: &SE3<D>) -> Result<SVector<D, 6>, LieError> {
        se3::cay_inv(g)
    }
    fn dtau<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 6>) -> SMatrix<D, 6, 6> {
        se3::dcay(xi)
    }
    fn dtau_inv<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 6>) -> SMatrix<D, 6, 6> {
        se3::dcay_inv(xi)
    }
    /// With ξ = (ω; v), p = (a; b) and [`se3::dcay_inv`]'s blocks
    /// [[I − ω̂/2 + ωωᵀ/4, 0], [−½(I − ω̂/2)v̂, I − ω̂/2]]: c = b + ½ ω × b
    /// and (a + ½ ω × a + ¼ ω (ω·a) + ½ v × c; c).
    fn dtau_inv_tr_mul<D: DualNum<Primitive = f64> + Copy>(xi: &SVector<D, 6>, p: &SVector<D, 6>) -> SVector<D, 6> {
        let (w, v) = se3::split(xi);
        let (a, b) = se3::split(p);
        let half = D::from(0.5);
        let c = b + w.cross(&b) * half;
        let top = cayley_rotation_pullback(&w, &a) + v.cross(&c) * half;
        se3::join(&top, &c)
    }
    /// With c = b + ½ ω × b: [[−½â + ¼((ω·a)I + ωaᵀ) − ¼v̂b̂, −½ĉ], [−½b̂, 0]].
    fn dtau_inv_tr_mul_derivative(xi: &SVector<f64, 6>, p: &SVector<f64, 6>) -> SMatrix<f64, 6, 6> {
        let (w, v) = se3::split(xi);
        let (a, b) = se3::split(p);
        let c = b + w.cross(&b) * 0.5;
        let mut out = SMatrix::<f64, 6, 6>::zeros();
        let top_w = cayley_rotation_pullback_derivative(&w, &a) - so3::hat(&v) * so3::hat(&b) * 0.25;
        out.fixed_view_mut::<3, 3>(0, 0).copy_from(&top_w);
        out.fixed_view_mut::<3, 3>(0, 3).copy_from(&(so3::hat(&c) * -0.5));
        out.fixed_view_mut::<3, 3>(3, 0).copy_from(&(so3::hat(&b) * -0.5));
        out
    }
    /// 2 atan(|ω|/2).
    fn rotation_angle(xi: &SVector<f64, 6>) -> f64 {
        2.0 * (0.5 * rotation_norm(xi)).atan()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::LieGroup;
    use num_dual::{Dual2_64, Dual64};

    /// A routine written once for any group and retraction: the right-
    /// trivialised derivative check τ⁻¹(τ(ξ + εδ)τ(ξ)⁻¹) ≈ ε dτ_ξ δ by central
    /// differences (ε = 1e-5; tolerance 1e-8), the round trip τ⁻¹∘τ, and
    /// dτ⁻¹ dτ = I.
    fn check<R: Retraction<N>, const N: usize>(xi: SVector<f64, N>, d: SVector<f64, N>) {
        let h = 1e-5;
        let g0 = R::tau(&xi).inverse();
        let p = R::tau_inv(&R::tau(&(xi + d * h)).compose(&g0)).expect("small");
        let m = R::tau_inv(&R::tau(&(xi - d * h)).compose(&g0)).expect("small");
        let fd = (p - m) / (2.0 * h);
        assert!((fd - R::dtau(&xi) * d).norm() <= 1e-8);
        let back = R::tau_inv(&R::tau(&xi)).expect("below π");
        assert!((back - xi).norm() <= 1e-14 * (1.0 + xi.norm()));
        let eye = SMatrix::<f64, N, N>::identity();
        assert!((R::dtau_inv(&xi) * R::dtau(&xi) - eye).abs().max() <= 1e-14);
        // The pull-back of a covector without the matrix is its transpose
        // times the covector, to round-off of the products (the entries of
        // dτ⁻¹ are O(1 + |ξ|²) here, p is O(1)).
        let pulled = R::dtau_inv_tr_mul(&xi, &d) - R::dtau_inv(&xi).tr_mul(&d);
        assert!(pulled.amax() <= 8.0 * f64::EPSILON * (1.0 + xi.norm_squared()) * d.amax());
        // Its derivative in ξ against central differences (h = 1e-6:
        // truncation O(h²) and rounding O(ε/h), both ≤ 1e-9 with |ξ|, |p| =
        // O(1)).
        let derivative = R::dtau_inv_tr_mul_derivative(&xi, &d);
        for k in 0..N {
            let e = SVector::<f64, N>::from_fn(|i, _| if i == k { 1e-6 } else { 0.0 });
            let fd = (R::dtau_inv_tr_mul(&(xi + e), &d) - R::dtau_inv_tr_mul(&(xi - e), &d)) / 2e-6;
            assert!((fd - derivative.column(k)).amax() <= 1e-8, "column {k}");
        }
        // And against one dual pass (the default), to round-off.
        let by_duals = num_dual::jacobian(|x| R::dtau_inv_tr_mul(&x, &d.map(DualSVec64::<N>::from_re)), &xi).1;
        assert!((by_duals - derivative).amax() <= 16.0 * f64::EPSILON * (1.0 + xi.norm()) * d.amax());
        // The same generic code runs with dual numbers; the dual part of
        // τ⁻¹(τ(εδ)τ(ξ)) with ε dual is dτ⁻¹_ξ δ.
        let gd = R::tau(&d.map(|e| Dual64::new(0.0, e)));
        let base = R::tau(&xi.map(Dual64::from));
        let got = R::tau_inv(&gd.compose(&base)).expect("below π").map(|e| e.eps);
        assert!((got - R::dtau_inv(&xi) * d).norm() <= 1e-13);
        // Right trivialisation and the adjoint: Ad_{τ(ξ)} = dτ_ξ dτ_{−ξ}⁻¹.
        let ad = R::tau(&xi).adjoint();
        assert!((ad - R::dtau(&xi) * R::dtau_inv(&(-xi))).abs().max() <= 1e-13);
    }

    #[test]
    fn generic_over_group_and_retraction() {
        let w = SVector::<f64, 3>::new(0.4, -1.1, 0.8);
        let dw = SVector::<f64, 3>::new(0.3, 0.2, -0.9);
        let xi = SVector::<f64, 6>::new(0.4, -1.1, 0.8, 1.5, -0.5, 0.25);
        let dx = SVector::<f64, 6>::new(0.3, 0.2, -0.9, -0.7, 0.1, 0.6);
        check::<ExpMap, 3>(w, dw);
        check::<CayleyMap, 3>(w, dw);
        check::<ExpMap, 6>(xi, dx);
        check::<CayleyMap, 6>(xi, dx);
        // Small and zero arguments through the same generic path.
        check::<ExpMap, 6>(xi * 1e-9, dx);
        check::<CayleyMap, 6>(xi * 0.0, dx);
    }

    /// Derivatives of dτ itself (needed by Newton Jacobians) are exact at and
    /// near ξ = 0: d/dt dτ(tδ)|₀ = ad_δ/2 and d/dt dτ⁻¹(tδ)|₀ = −ad_δ/2 for
    /// both retractions (dτ_ξ = I + ad_ξ/2 + O(|ξ|²)), and for exp the second
    /// derivatives are ad_δ²/3 and ad_δ²/6 (dexp_ξ = Σ ad_ξᵏ/(k+1)!,
    /// dexp⁻¹_ξ = I − ad_ξ/2 + ad_ξ²/12 + …). ad_δ is obtained generically as the
    /// dual part of Ad_{τ(tδ)} at t = 0. At t = 1e-9 the first derivative moves
    /// by O(t|δ|²) ≈ 1e-9; tolerances 4ε at 0 and 1e-8 at 1e-9.
    fn check_dtau_derivatives<R: Retraction<N>, const N: usize>(d: SVector<f64, N>, is_exp: bool) {
        let ad = R::tau(&d.map(|e| Dual64::new(0.0, e))).adjoint().map(|e| e.eps);
        for &t in &[0.0, 1e-9] {
            let tol = if t == 0.0 { 4.0 * f64::EPSILON } else { 1e-8 };
            let x = d.map(|e| Dual2_64::new(t * e, e, 0.0));
            let (dt, dti) = (R::dtau(&x), R::dtau_inv(&x));
            assert!((dt.map(|e| e.v1) - ad * 0.5).abs().max() <= tol);
            assert!((dti.map(|e| e.v1) + ad * 0.5).abs().max() <= tol);
            if is_exp {
                assert!((dt.map(|e| e.v2) - ad * ad / 3.0).abs().max() <= tol);
                assert!((dti.map(|e| e.v2) - ad * ad / 6.0).abs().max() <= tol);
            }
        }
    }

    #[test]
    fn dtau_derivatives_near_zero() {
        let dw = SVector::<f64, 3>::new(0.3, 0.2, -0.9);
        let dx = SVector::<f64, 6>::new(0.3, 0.2, -0.9, -0.7, 0.1, 0.6);
        check_dtau_derivatives::<ExpMap, 3>(dw, true);
        check_dtau_derivatives::<CayleyMap, 3>(dw, false);
        check_dtau_derivatives::<ExpMap, 6>(dx, true);
        check_dtau_derivatives::<CayleyMap, 6>(dx, false);
    }

    /// The retraction is selected by the argument type without annotations.
    /// The rotation angle from ξ alone is the angle of τ(ξ) (the norm of
    /// its logarithm), and τ⁻¹(τ(ξ)) = ξ below π − margin; the exponential
    /// chart wraps beyond π.
    #[test]
    fn rotation_angle_is_the_angle_of_tau() {
        use crate::lie::CUT_LOCUS_MARGIN;
        use std::f64::consts::PI;
        let dir = SVector::<f64, 3>::new(0.3, -0.8, 0.5).normalize();
        for scale in [1e-9, 0.3, 1.0, 2.5, 3.0, 10.0, 1e3] {
            let w = dir * scale;
            let x = SVector::<f64, 6>::new(w[0], w[1], w[2], 0.4, -0.2, 1.1);
            for (angle, rotation) in [
                (ExpMap::rotation_angle(&w), ExpMap::tau(&w)),
                (CayleyMap::rotation_angle(&w), CayleyMap::tau(&w)),
                (ExpMap::rotation_angle(&x), *ExpMap::tau(&x).rotation()),
                (CayleyMap::rotation_angle(&x), *CayleyMap::tau(&x).rotation()),
            ] {
                if angle < PI - CUT_LOCUS_MARGIN {
                    let log = so3::log(&rotation).expect("inside the chart");
                    assert!((log.norm() - angle).abs() <= 1e-12 * (1.0 + angle), "{scale}: {angle}");
                }
            }
            if ExpMap::rotation_angle(&x) < PI - CUT_LOCUS_MARGIN {
                assert!((ExpMap::tau_inv(&ExpMap::tau(&x)).expect("chart") - x).amax() < 1e-12 * (1.0 + scale));
            } else if let Ok(back) = ExpMap::tau_inv(&ExpMap::tau(&x)) {
                assert!((back - x).amax() > 1e-3, "the exponential chart wraps past π");
            }
            let back = CayleyMap::tau_inv(&CayleyMap::tau(&x)).expect("Cayley chart");
            assert!((back - x).amax() < 1e-10 * (1.0 + scale * scale), "{scale}");
        }
    }

    #[test]
    fn inference_by_dimension() {
        let r = ExpMap::tau(&SVector::<f64, 3>::new(0.1, 0.2, 0.3));
        let g = CayleyMap::tau(&SVector::<f64, 6>::new(0.1, 0.2, 0.3, 1.0, 2.0, 3.0));
        assert!((r.matrix() - so3::exp(&SVector::<f64, 3>::new(0.1, 0.2, 0.3)).matrix()).norm() == 0.0);
        assert_eq!(g, se3::cay(&SVector::<f64, 6>::new(0.1, 0.2, 0.3, 1.0, 2.0, 3.0)));
    }
}
