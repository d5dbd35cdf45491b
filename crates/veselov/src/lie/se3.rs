//! The rigid-motion group SE(3) and its Lie algebra se(3) ≅ R⁶, with the
//! **angular-first** ordering ξ = (ω; v) of note 000.
//!
//! All formulas, sources and conventions are listed in the
//! [module documentation of `lie`](super). Elements are g = (R, x) acting on
//! points by p ↦ Rp + x; `hat(ξ) = [[ω̂, v], [0, 0]]`; derivatives of
//! retractions are right-trivialised, τ(ξ + εδ) = τ(ε dτ_ξ δ) τ(ξ) + O(ε²)
//! (seed 000 eq. (62)).

use std::ops::Mul;

use nalgebra::{Matrix3, Matrix4, Matrix6, Vector3, Vector6};
use num_dual::DualNum;

use super::so3::{self, SO3, hat as hat3};
use super::{LieError, LieGroup, ORTHOGONALITY_TOLERANCE, series};
use crate::ad::mat3_tr_vec;

/// Angular part ω and linear part v of ξ = (ω; v).
pub fn split<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> (Vector3<D>, Vector3<D>) {
    (Vector3::new(xi[0], xi[1], xi[2]), Vector3::new(xi[3], xi[4], xi[5]))
}

/// ξ = (ω; v) from its angular and linear parts.
pub fn join<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>, v: &Vector3<D>) -> Vector6<D> {
    Vector6::new(w[0], w[1], w[2], v[0], v[1], v[2])
}

/// The 6×6 matrix [[a11, a12], [a21, a22]] from 3×3 blocks.
fn blocks<D: DualNum<Primitive = f64> + Copy>(
    a11: &Matrix3<D>,
    a12: &Matrix3<D>,
    a21: &Matrix3<D>,
    a22: &Matrix3<D>,
) -> Matrix6<D> {
    let mut m = Matrix6::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(a11);
    m.fixed_view_mut::<3, 3>(0, 3).copy_from(a12);
    m.fixed_view_mut::<3, 3>(3, 0).copy_from(a21);
    m.fixed_view_mut::<3, 3>(3, 3).copy_from(a22);
    m
}

/// se(3) hat map: ξ = (ω; v) ↦ [[ω̂, v], [0, 0]] (4×4).
pub fn hat<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> Matrix4<D> {
    let (w, v) = split(xi);
    let mut m = Matrix4::zeros();
    m.fixed_view_mut::<3, 3>(0, 0).copy_from(&hat3(&w));
    m.fixed_view_mut::<3, 1>(0, 3).copy_from(&v);
    m
}

/// se(3) vee map, inverse of [`hat`]: ω from the skew part of the upper-left
/// block (see [`so3::vee`]), v from the last column. The bottom row is ignored.
pub fn vee<D: DualNum<Primitive = f64> + Copy>(m: &Matrix4<D>) -> Vector6<D> {
    let w = so3::vee(&m.fixed_view::<3, 3>(0, 0).into_owned());
    let v = m.fixed_view::<3, 1>(0, 3).into_owned();
    join(&w, &v)
}

/// A rigid motion g = (R, x): p ↦ Rp + x, homogeneous matrix [[R, x], [0, 1]].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SE3<D> {
    rotation: SO3<D>,
    translation: Vector3<D>,
}

impl<D: DualNum<Primitive = f64> + Copy> SE3<D> {
    /// (R, x) from a rotation and a translation.
    pub fn new(rotation: SO3<D>, translation: Vector3<D>) -> Self {
        SE3 { rotation, translation }
    }

    /// The identity (I, 0).
    pub fn identity() -> Self {
        SE3 {
            rotation: SO3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// A pure translation (I, x).
    pub fn from_translation(translation: Vector3<D>) -> Self {
        SE3 {
            rotation: SO3::identity(),
            translation,
        }
    }

    /// The rotation part R.
    pub fn rotation(&self) -> &SO3<D> {
        &self.rotation
    }

    /// The translation part x.
    pub fn translation(&self) -> &Vector3<D> {
        &self.translation
    }

    /// The homogeneous 4×4 matrix [[R, x], [0, 1]].
    pub fn to_matrix(&self) -> Matrix4<D> {
        let mut m = Matrix4::identity();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(self.rotation.matrix());
        m.fixed_view_mut::<3, 1>(0, 3).copy_from(&self.translation);
        m
    }

    /// From a homogeneous matrix, checking (on real parts) that the upper-left
    /// block is a rotation and the bottom row is (0, 0, 0, 1) up to
    /// [`ORTHOGONALITY_TOLERANCE`].
    pub fn from_matrix(m: &Matrix4<D>) -> Result<Self, LieError> {
        let r = m.fixed_view::<3, 3>(0, 0).into_owned();
        let row = (m[(3, 0)].re().abs())
            .max(m[(3, 1)].re().abs())
            .max(m[(3, 2)].re().abs())
            .max((m[(3, 3)].re() - 1.0).abs());
        let defect = so3::rotation_defect(&r).max(if row.is_finite() { row } else { f64::INFINITY });
        if defect <= ORTHOGONALITY_TOLERANCE {
            Ok(SE3 {
                rotation: SO3::from_matrix_unchecked(r),
                translation: m.fixed_view::<3, 1>(0, 3).into_owned(),
            })
        } else {
            Err(LieError::NotARotation { defect })
        }
    }

    /// The product `self · other` = (R₁R₂, R₁x₂ + x₁).
    pub fn compose(&self, other: &Self) -> Self {
        SE3 {
            rotation: self.rotation.compose(&other.rotation),
            translation: self.rotation.act(&other.translation) + self.translation,
        }
    }

    /// The inverse (Rᵀ, −Rᵀx).
    pub fn inverse(&self) -> Self {
        let rt = self.rotation.inverse();
        SE3 {
            translation: -rt.act(&self.translation),
            rotation: rt,
        }
    }

    /// The relative motion g⁻¹h = (RᵀS, Rᵀ(y − x)) of g = (R, x) and
    /// h = (S, y): the positions' difference is taken first (what
    /// `self.inverse().compose(other)` computes as Rᵀy − Rᵀx).
    pub fn between(&self, other: &Self) -> Self {
        SE3 {
            rotation: self.rotation.between(&other.rotation),
            translation: mat3_tr_vec(self.rotation.matrix(), &(other.translation - self.translation)),
        }
    }

    /// Act on a point: p ↦ Rp + x.
    pub fn act(&self, p: &Vector3<D>) -> Vector3<D> {
        self.rotation.act(p) + self.translation
    }

    /// Re-orthonormalise the rotation part (see [`SO3::renormalize`]).
    pub fn renormalize(&self) -> Self {
        SE3 {
            rotation: self.rotation.renormalize(),
            translation: self.translation,
        }
    }

    /// exp ξ (see [`exp`]).
    pub fn exp(xi: &Vector6<D>) -> Self {
        exp(xi)
    }

    /// log g (see [`log`]).
    pub fn log(&self) -> Result<Vector6<D>, LieError> {
        log(self)
    }

    /// cay ξ (see [`cay`]).
    pub fn cay(xi: &Vector6<D>) -> Self {
        cay(xi)
    }

    /// cay⁻¹ g (see [`cay_inv`]).
    pub fn cay_inv(&self) -> Result<Vector6<D>, LieError> {
        cay_inv(self)
    }
}

impl<D: DualNum<Primitive = f64> + Copy> Mul for SE3<D> {
    type Output = SE3<D>;
    fn mul(self, rhs: SE3<D>) -> SE3<D> {
        self.compose(&rhs)
    }
}

impl<D: DualNum<Primitive = f64> + Copy> LieGroup<D, 6> for SE3<D> {
    fn identity() -> Self {
        SE3::identity()
    }
    fn compose(&self, other: &Self) -> Self {
        SE3::compose(self, other)
    }
    fn inverse(&self) -> Self {
        SE3::inverse(self)
    }
    fn between(&self, other: &Self) -> Self {
        SE3::between(self, other)
    }
    fn adjoint(&self) -> Matrix6<D> {
        adjoint(self)
    }
    fn ad_star_matrix(&self) -> Matrix6<D> {
        ad_star_matrix(self)
    }
    fn coadjoint(&self) -> Matrix6<D> {
        coadjoint(self)
    }
}

/// Exponential map: exp(ω; v) = (exp ω, J v) with J = [`so3::dexp`]`(ω)`
/// = I + ((1 − cos θ)/θ²) ω̂ + ((θ − sin θ)/θ³) ω̂².
pub fn exp<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> SE3<D> {
    let (w, v) = split(xi);
    SE3 {
        rotation: so3::exp(&w),
        translation: so3::dexp(&w) * v,
    }
}

/// Logarithm: log(R, x) = (ω; J⁻¹x), ω = [`so3::log`]`(R)`, J⁻¹ = [`so3::dexp_inv`]`(ω)`.
/// Errors with [`LieError::NearCutLocus`] near rotation angle π.
pub fn log<D: DualNum<Primitive = f64> + Copy>(g: &SE3<D>) -> Result<Vector6<D>, LieError> {
    let w = so3::log(&g.rotation)?;
    Ok(join(&w, &(so3::dexp_inv(&w) * g.translation)))
}

/// Cayley map cay ξ = (I − ξ̂/2)⁻¹(I + ξ̂/2) (note 000 §13):
/// R = cay ω, x = (I − ω̂/2)⁻¹ v = 2/(4 + |ω|²)(2I + ω̂ + ωωᵀ/2) v.
///
/// (The variant x = 2/(4 + |ω|²)(2I + ω̂) v found in some references is a
/// different map, inconsistent with [`dcay`]; see note 000 §13.)
pub fn cay<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> SE3<D> {
    let (w, v) = split(xi);
    let f = (w.dot(&w) + 4.0).recip() * 2.0;
    let m = Matrix3::identity() * D::from(2.0) + hat3(&w) + w * w.transpose() * D::from(0.5);
    SE3 {
        rotation: so3::cay(&w),
        translation: m * v * f,
    }
}

/// Inverse Cayley map (note 000 §13): ω = [`so3::cay_inv`]`(R)`, v = (I − ω̂/2) x.
/// Errors with [`LieError::NearCutLocus`] near rotation angle π.
pub fn cay_inv<D: DualNum<Primitive = f64> + Copy>(g: &SE3<D>) -> Result<Vector6<D>, LieError> {
    let w = so3::cay_inv(&g.rotation)?;
    let v = g.translation - w.cross(&g.translation) * D::from(0.5);
    Ok(join(&w, &v))
}

/// The off-diagonal block Q(ω, v) of [`dexp`]:
/// Q = V/2 + C(WV + VW + WVW) + c₂(W²V + VW² − 3WVW) + c₃(WVW² + W²VW)
/// (W = ω̂, V = v̂; coefficients in the module docs).
fn dexp_q<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>, v: &Vector3<D>) -> Matrix3<D> {
    let x = w.dot(w);
    let (ww, vv) = (hat3(w), hat3(v));
    let (wv, vw) = (ww * vv, vv * ww);
    let wvw = wv * ww;
    vv * D::from(0.5)
        + (wv + vw + wvw) * series::sin3(x)
        + (ww * wv + vw * ww - wvw * D::from(3.0)) * series::q2(x)
        + (wvw * ww + ww * wvw) * series::q3(x)
}

/// Right-trivialised derivative of exp: dexp_ξ = [[J, 0], [Q, J]], so that
/// exp(ξ + εδ) = exp(ε dexp_ξ δ) exp(ξ) + O(ε²).
pub fn dexp<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> Matrix6<D> {
    let (w, v) = split(xi);
    let j = so3::dexp(&w);
    blocks(&j, &Matrix3::zeros(), &dexp_q(&w, &v), &j)
}

/// Inverse of [`dexp`]: [[J⁻¹, 0], [−J⁻¹QJ⁻¹, J⁻¹]] (rotation angle < 2π).
pub fn dexp_inv<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> Matrix6<D> {
    let (w, v) = split(xi);
    let ji = so3::dexp_inv(&w);
    let q = dexp_q(&w, &v);
    blocks(&ji, &Matrix3::zeros(), &(-(ji * q * ji)), &ji)
}

/// Right-trivialised derivative of the Cayley map (note 000 §13),
/// dcay_ξ(δ) = ((I − ξ̂/2)⁻¹ δ̂ (I + ξ̂/2)⁻¹)ˇ:
/// [[2/(4+|ω|²)(2I + W), 0], [V(2I + W)/(4+|ω|²), I + (W² + 2W)/(4+|ω|²)]].
pub fn dcay<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> Matrix6<D> {
    let (w, v) = split(xi);
    let (ww, vv) = (hat3(&w), hat3(&v));
    let f = (w.dot(&w) + 4.0).recip();
    let two_w = Matrix3::identity() * D::from(2.0) + ww;
    blocks(
        &(two_w * (f * 2.0)),
        &Matrix3::zeros(),
        &(vv * two_w * f),
        &(Matrix3::identity() + (ww * ww + ww * D::from(2.0)) * f),
    )
}

/// Inverse of [`dcay`] (note 000 §13):
/// [[I − W/2 + ωωᵀ/4, 0], [−½(I − W/2)V, I − W/2]].
pub fn dcay_inv<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> Matrix6<D> {
    let (w, v) = split(xi);
    let half = D::from(0.5);
    let i_w = Matrix3::identity() - hat3(&w) * half;
    blocks(
        &(i_w + w * w.transpose() * D::from(0.25)),
        &Matrix3::zeros(),
        &(-(i_w * hat3(&v)) * half),
        &i_w,
    )
}

/// Adjoint representation (note 000 §13): Ad_(R,x) = [[R, 0], [x̂R, R]],
/// Ad_g ξ = (g ξ̂ g⁻¹)ˇ = (Rω; Rv + x × Rω).
pub fn adjoint<D: DualNum<Primitive = f64> + Copy>(g: &SE3<D>) -> Matrix6<D> {
    let r = g.rotation.matrix();
    blocks(r, &Matrix3::zeros(), &(hat3(&g.translation) * r), r)
}

/// Algebra adjoint ad_ξ = [[ω̂, 0], [v̂, ω̂]]: ad_ξ η = [ξ̂, η̂]ˇ.
pub fn ad<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> Matrix6<D> {
    let (w, v) = split(xi);
    let ww = hat3(&w);
    blocks(&ww, &Matrix3::zeros(), &hat3(&v), &ww)
}

/// (ad_ξ)ᵀ: ⟨ad\*_ξ μ, η⟩ = ⟨μ, ad_ξ η⟩ (the ad\* of note 000 eq. (24), (97)).
pub fn ad_star<D: DualNum<Primitive = f64> + Copy>(xi: &Vector6<D>) -> Matrix6<D> {
    ad(xi).transpose()
}

/// (Ad_g)ᵀ — the operator seed 000 and note 000 §1 call Ad\*_g:
/// ⟨Ad\*_g μ, ξ⟩ = ⟨μ, Ad_g ξ⟩, (m; f) ↦ (Rᵀ(m − x × f); Rᵀf).
/// An anti-homomorphism (Ad\*_{gh} = Ad\*_h Ad\*_g). Not the coadjoint action;
/// see [`coadjoint`].
pub fn ad_star_matrix<D: DualNum<Primitive = f64> + Copy>(g: &SE3<D>) -> Matrix6<D> {
    adjoint(g).transpose()
}

/// Coadjoint action of g on se(3)\*: (Ad_{g⁻¹})ᵀ = [[R, x̂R], [0, R]],
/// (m; f) ↦ (Rm + x × Rf; Rf) — body to spatial momentum (note 000 §13).
/// A homomorphism: coadjoint(gh) = coadjoint(g) coadjoint(h).
pub fn coadjoint<D: DualNum<Primitive = f64> + Copy>(g: &SE3<D>) -> Matrix6<D> {
    let r = g.rotation.matrix();
    blocks(r, &(hat3(&g.translation) * r), &Matrix3::zeros(), r)
}

/// One-parameter (screw) interpolation g(s) = g₀ exp(s log(g₀⁻¹g₁)),
/// g(0) = g₀, g(1) = g₁. Errors near the rotational cut locus.
pub fn geodesic<D: DualNum<Primitive = f64> + Copy>(g0: &SE3<D>, g1: &SE3<D>, s: D) -> Result<SE3<D>, LieError> {
    let xi = log(&g0.between(g1))?;
    Ok(g0.compose(&exp(&(xi * s))))
}

/// d(g₀, g₁) = |log(g₀⁻¹g₁)|, the Euclidean norm of (ω; v) (radians and lengths
/// unweighted). Left-invariant. Errors near the rotational cut locus; not
/// differentiable where d = 0.
pub fn distance<D: DualNum<Primitive = f64> + Copy>(g0: &SE3<D>, g1: &SE3<D>) -> Result<D, LieError> {
    let xi = log(&g0.between(g1))?;
    Ok(xi.dot(&xi).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lie::so3::tests::{rotation, rotvec, rotvec_moderate, unit};
    use num_dual::{Dual2_64, Dual64};
    use proptest::prelude::*;
    use std::f64::consts::PI;

    const EPS: f64 = f64::EPSILON;

    fn translation() -> impl Strategy<Value = Vector3<f64>> {
        (-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64).prop_map(|(a, b, c)| Vector3::new(a, b, c))
    }

    fn twist() -> impl Strategy<Value = Vector6<f64>> {
        (rotvec(), translation()).prop_map(|(w, v)| join(&w, &v))
    }

    fn twist_moderate() -> impl Strategy<Value = Vector6<f64>> {
        (rotvec_moderate(), translation()).prop_map(|(w, v)| join(&w, &v))
    }

    fn element() -> impl Strategy<Value = SE3<f64>> {
        (rotation(), translation()).prop_map(|(r, x)| SE3::new(r, x))
    }

    fn dir6() -> impl Strategy<Value = Vector6<f64>> {
        (unit(), unit(), -1.0..1.0f64).prop_map(|(a, b, s)| join(&a, &(b * s)))
    }

    fn maxabs<const R: usize, const C: usize>(m: &nalgebra::SMatrix<f64, R, C>) -> f64 {
        m.abs().max()
    }

    /// Matrix exponential by scaling and squaring of a 20-term Taylor sum
    /// (independent reference for `exp`).
    fn expm(a: &Matrix4<f64>) -> Matrix4<f64> {
        let norm = a.abs().max() * 4.0;
        let s = if norm > 0.5 {
            (norm / 0.5).log2().ceil() as i32
        } else {
            0
        };
        let b = a / 2f64.powi(s);
        let (mut term, mut sum) = (Matrix4::identity(), Matrix4::identity());
        for k in 1..20 {
            term = term * b / k as f64;
            sum += term;
        }
        for _ in 0..s {
            sum = sum * sum;
        }
        sum
    }

    /// Cayley vector with the same rotation angle as the test angle |ω|
    /// (so rotvec()'s near-π cases are near-π for the Cayley map too).
    fn cayley_twist(xi: &Vector6<f64>) -> Vector6<f64> {
        let (w, v) = split(xi);
        let t = w.norm();
        let wc = if t > 0.0 { w * (2.0 * (t / 2.0).tan() / t) } else { w };
        join(&wc, &v)
    }

    proptest! {
        #![proptest_config(crate::lie::test_config())]

        /// g⁻¹h without the inverse: the rotation bit for bit as
        /// inverse-then-compose; the translation Rᵀ(y − x) against Rᵀy − Rᵀx,
        /// each within γ₃Σ_k|R_ki||·| ≤ 3√3ε|·|∞ per dot product (a unit column
        /// has Σ|R_ki| ≤ √3) plus one rounding of the difference: 16ε(|x|∞ + |y|∞).
        #[test]
        fn between_is_inverse_then_compose(g in element(), h in element()) {
            let (fused, reference) = (g.between(&h), g.inverse().compose(&h));
            prop_assert_eq!(fused.rotation().matrix(), reference.rotation().matrix());
            let bound = 16.0 * EPS * (g.translation().amax() + h.translation().amax());
            prop_assert!((fused.translation() - reference.translation()).amax() <= bound);
        }

        /// exp agrees with the 4×4 matrix exponential of hat(ξ); |ξ| ≤ ~4, the
        /// reference loses ~10 ε per squaring: tolerance 1e-13.
        #[test]
        fn exp_is_matrix_exponential(xi in twist()) {
            prop_assert!(maxabs(&(exp(&xi).to_matrix() - expm(&hat(&xi)))) <= 1e-13);
        }

        /// cay agrees with (I − ξ̂/2)⁻¹(I + ξ̂/2); cond(I − ξ̂/2) ≤ 1 + |ξ|²/4 ≤ 8.
        #[test]
        fn cay_is_matrix_cayley(xi in twist()) {
            let h = hat(&xi) * 0.5;
            let m = (Matrix4::identity() - h).try_inverse().expect("always invertible") * (Matrix4::identity() + h);
            prop_assert!(maxabs(&(cay(&xi).to_matrix() - m)) <= 64.0 * EPS);
        }

        /// Round trips τ⁻¹∘τ = id. The rotational part inherits the SO(3)
        /// bounds; the translation adds |J⁻¹| |x| ε-level error, and for the
        /// Cayley map near π the conditioning 1/sin θ of the rotation vector.
        #[test]
        fn round_trips(xi in twist()) {
            let back = log(&exp(&xi)).expect("below π");
            prop_assert!((back - xi).norm() <= 64.0 * EPS * (1.0 + xi.norm()), "exp err {}", (back - xi).norm());
            let xc = cayley_twist(&xi);
            let theta = split(&xi).0.norm();
            let cond = 1.0 + 1.0 / theta.sin().max(1e-300);
            let back = cay_inv(&cay(&xc)).expect("below π");
            prop_assert!((back - xc).norm() <= 64.0 * EPS * (1.0 + xc.norm()) * cond, "cay err {}", (back - xc).norm());
        }

        /// τ∘τ⁻¹ = id on random elements (uniform rotations and exp of the
        /// `twist` mix, angles 0 … π − 1e-5). exp: a few ε. Cayley: the
        /// translation is recovered through v = (I − ω̂/2)x and x = (I − ω̂/2)⁻¹v,
        /// whose condition number is √(1 + |ω|²/4) ≤ 1 + tan(θ/2) (|ω| = 2tan(θ/2)),
        /// so the bound is 16ε(1 + |x|)(1 + tan(θ/2)).
        #[test]
        fn inverse_then_forward(g in prop_oneof![element(), twist().prop_map(|x| exp(&x))]) {
            let theta = g.rotation().angle();
            prop_assume!(theta < PI - 2.0 * crate::lie::CUT_LOCUS_MARGIN);
            let scale = 1.0 + g.translation().norm();
            let e = exp(&log(&g).expect("ok"));
            prop_assert!(maxabs(&(e.to_matrix() - g.to_matrix())) <= 16.0 * EPS * scale);
            let c = cay(&cay_inv(&g).expect("ok"));
            let tol = 16.0 * EPS * scale * (1.0 + (theta / 2.0).tan());
            prop_assert!(maxabs(&(c.to_matrix() - g.to_matrix())) <= tol);
        }

        /// Right-trivialised derivative vs central differences:
        /// τ⁻¹(τ(ξ + εδ) τ(ξ)⁻¹) = ε dτ_ξ δ + O(ε²); ε = 1e-5, tolerance 1e-8.
        #[test]
        fn dtau_finite_differences(xi in twist_moderate(), d in dir6()) {
            let h = 1e-5;
            let fd = |tau: fn(&Vector6<f64>) -> SE3<f64>, inv: fn(&SE3<f64>) -> Result<Vector6<f64>, LieError>| {
                let g0 = tau(&xi).inverse();
                let p = inv(&tau(&(xi + d * h)).compose(&g0)).expect("small");
                let m = inv(&tau(&(xi - d * h)).compose(&g0)).expect("small");
                (p - m) / (2.0 * h)
            };
            let e = fd(exp, log) - dexp(&xi) * d;
            prop_assert!(e.norm() <= 1e-8, "dexp err {}", e.norm());
            let c = fd(cay, cay_inv) - dcay(&xi) * d;
            prop_assert!(c.norm() <= 1e-8, "dcay err {}", c.norm());
        }

        /// Exact version through Dual64: (d/dt τ(ξ + tδ)) τ(ξ)⁻¹ = hat(dτ_ξ δ)
        /// to round-off (‖dτ‖ ≲ (1 + |ξ|)²; tol 64ε(1 + |ξ|)³).
        #[test]
        fn dtau_exact_via_dual(xi in twist(), d in dir6()) {
            let xd = xi.map(Dual64::from) + d.map(|e| Dual64::new(0.0, e));
            let tol = 64.0 * EPS * (1.0 + xi.norm()).powi(3);
            for (gd, g, dt) in [(exp(&xd), exp(&xi), dexp(&xi)), (cay(&xd), cay(&xi), dcay(&xi))] {
                let deriv = gd.to_matrix().map(|e| e.eps) * g.inverse().to_matrix();
                prop_assert!(maxabs(&(deriv - hat(&(dt * d)))) <= tol, "err {}", maxabs(&(deriv - hat(&(dt * d)))));
            }
        }

        /// dτ⁻¹ = (dτ)⁻¹. Block entries are O(1 + |ω|²) on the diagonal and
        /// O((1 + |ω|²)|v|) off it, so the products carry a few ε times
        /// (1 + |ω|²)(1 + |v|)²; tolerance 16ε × that.
        #[test]
        fn dtau_inv_is_inverse(xi in twist()) {
            let i6 = Matrix6::identity();
            let (w, v) = split(&xi);
            let tol = 16.0 * EPS * (1.0 + w.norm_squared()) * (1.0 + v.norm()).powi(2);
            prop_assert!(maxabs(&(dexp_inv(&xi) * dexp(&xi) - i6)) <= tol);
            prop_assert!(maxabs(&(dexp(&xi) * dexp_inv(&xi) - i6)) <= tol);
            prop_assert!(maxabs(&(dcay_inv(&xi) * dcay(&xi) - i6)) <= tol);
            prop_assert!(maxabs(&(dcay(&xi) * dcay_inv(&xi) - i6)) <= tol);
        }

        /// dcay in 4×4 form: dcay_ξ(δ) = (I − ξ̂/2)⁻¹ δ̂ (I + ξ̂/2)⁻¹.
        #[test]
        fn dcay_matrix_form(xi in twist(), d in dir6()) {
            let h = hat(&xi) * 0.5;
            let a = (Matrix4::identity() - h).try_inverse().expect("invertible");
            let b = (Matrix4::identity() + h).try_inverse().expect("invertible");
            prop_assert!((vee(&(a * hat(&d) * b)) - dcay(&xi) * d).norm() <= 64.0 * EPS);
        }

        /// Left and right trivialisations are related by Ad: for both
        /// retractions Ad_{τ(ξ)} = dτ_ξ (dτ_{−ξ})⁻¹ (since τ(−ξ) = τ(ξ)⁻¹).
        #[test]
        fn adjoint_of_retraction(xi in twist_moderate()) {
            let tol = 1e-13 * (1.0 + xi.norm()).powi(3);
            prop_assert!(maxabs(&(adjoint(&exp(&xi)) - dexp(&xi) * dexp_inv(&(-xi)))) <= tol);
            prop_assert!(maxabs(&(adjoint(&cay(&xi)) - dcay(&xi) * dcay_inv(&(-xi)))) <= tol);
        }

        /// Ad homomorphism, Ad_g ξ̂ = g ξ̂ g⁻¹, ad = bracket, Ad* pairing,
        /// coadjoint homomorphism, and note 000 §12's Ad*_{(gτ)⁻¹}Ad*_τ = Ad*_{g⁻¹}.
        #[test]
        fn adjoint_identities(g in element(), h in element(), xi in dir6(), eta in dir6(), mu in dir6()) {
            let tol = 64.0 * EPS * 9.0;
            prop_assert!(maxabs(&(adjoint(&g.compose(&h)) - adjoint(&g) * adjoint(&h))) <= tol);
            let lhs = hat(&(adjoint(&g) * xi));
            let rhs = g.to_matrix() * hat(&xi) * g.inverse().to_matrix();
            prop_assert!(maxabs(&(lhs - rhs)) <= tol);
            let br = hat(&xi) * hat(&eta) - hat(&eta) * hat(&xi);
            prop_assert!((ad(&xi) * eta - vee(&br)).norm() <= 16.0 * EPS);
            prop_assert!(maxabs(&(hat(&(ad(&xi) * eta)) - br)) <= 16.0 * EPS);
            let pair = (ad_star_matrix(&g) * mu).dot(&xi) - mu.dot(&(adjoint(&g) * xi));
            prop_assert!(pair.abs() <= tol);
            prop_assert!(((ad_star(&xi) * mu).dot(&eta) - mu.dot(&(ad(&xi) * eta))).abs() <= 16.0 * EPS);
            prop_assert!(maxabs(&(coadjoint(&g.compose(&h)) - coadjoint(&g) * coadjoint(&h))) <= tol);
            prop_assert!(maxabs(&(coadjoint(&g) - adjoint(&g.inverse()).transpose())) <= tol);
            prop_assert!(maxabs(&(ad_star_matrix(&g.compose(&h)) - ad_star_matrix(&h) * ad_star_matrix(&g))) <= tol);
            let tau = cay(&(eta * 0.7));
            let lhs = ad_star_matrix(&g.compose(&tau).inverse()) * ad_star_matrix(&tau);
            prop_assert!(maxabs(&(lhs - ad_star_matrix(&g.inverse()))) <= tol);
            // Note 000 §13: Ad*_g(m; f) = (Rᵀ(m − x × f); Rᵀ f), coadjoint (m; f) = (Rm + x × Rf; Rf).
            let (m, f) = split(&mu);
            let (r, x) = (g.rotation().matrix(), g.translation());
            let expect = join(&(r.transpose() * (m - x.cross(&f))), &(r.transpose() * f));
            prop_assert!((ad_star_matrix(&g) * mu - expect).norm() <= tol);
            let expect = join(&(r * m + x.cross(&(r * f))), &(r * f));
            prop_assert!((coadjoint(&g) * mu - expect).norm() <= tol);
            // The trait defaults give the same matrices.
            prop_assert!(maxabs(&(LieGroup::coadjoint(&g) - coadjoint(&g))) <= tol);
        }

        /// Geodesic endpoints, constant speed along the screw, left invariance of
        /// the distance.
        #[test]
        fn geodesic_and_distance(g in element(), h in element(), k in element(), a in 0.0..1.0f64, b in 0.0..1.0f64) {
            prop_assume!(g.between(&h).rotation().angle() < PI - 1e-3);
            let g0 = geodesic(&g, &h, 0.0).expect("ok");
            let g1 = geodesic(&g, &h, 1.0).expect("ok");
            prop_assert!(maxabs(&(g0.to_matrix() - g.to_matrix())) <= 64.0 * EPS);
            prop_assert!(maxabs(&(g1.to_matrix() - h.to_matrix())) <= 1e-12);
            let d = distance(&g, &h).expect("ok");
            let (ga, gb) = (geodesic(&g, &h, a).expect("ok"), geodesic(&g, &h, b).expect("ok"));
            prop_assert!((distance(&ga, &gb).expect("ok") - (a - b).abs() * d).abs() <= 1e-11);
            let dk = distance(&k.compose(&g), &k.compose(&h)).expect("ok");
            prop_assert!((dk - d).abs() <= 1e-11);
        }
    }

    /// d/dt Ad_{exp(tξ)}|₀ = ad_ξ and d/dt coadjoint(exp(tξ))|₀ = −ad_ξᵀ, exactly
    /// through Dual64; second derivative of exp at 0 is ξ̂² (Dual2).
    #[test]
    fn infinitesimal_adjoint_and_second_derivatives() {
        let xi = Vector6::new(0.3, -0.7, 0.2, 1.1, -0.4, 0.6);
        let xd = xi.map(|e| Dual64::new(0.0, e));
        let g = exp(&xd);
        assert!(maxabs(&(adjoint(&g).map(|e| e.eps) - ad(&xi))) <= 4.0 * EPS);
        assert!(maxabs(&(coadjoint(&g).map(|e| e.eps) + ad_star(&xi))) <= 4.0 * EPS);
        for &t in &[0.0, 1e-9] {
            let base = xi * t;
            let x2 = base.map(Dual2_64::from) + xi.map(|e| Dual2_64::new(0.0, e, 0.0));
            let h2 = hat(&xi) * hat(&xi);
            for (g2, g, dt) in [(exp(&x2), exp(&base), dexp(&base)), (cay(&x2), cay(&base), dcay(&base))] {
                let m = g2.to_matrix();
                let first = hat(&(dt * xi)) * g.to_matrix();
                assert!(maxabs(&(m.map(|e| e.v1) - first)) <= 4.0 * EPS);
                if t == 0.0 {
                    assert!(maxabs(&(m.map(|e| e.v2) - h2)) <= 4.0 * EPS);
                }
            }
            // log∘exp and cay⁻¹∘cay are the identity: derivative ξ, second derivative 0.
            let back = log(&exp(&x2)).expect("ok");
            assert!((back.map(|e| e.v1) - xi).norm() <= 8.0 * EPS);
            assert!(back.map(|e| e.v2).norm() <= 1e-14);
            let back = cay_inv(&cay(&x2)).expect("ok");
            assert!((back.map(|e| e.v1) - xi).norm() <= 8.0 * EPS);
            assert!(back.map(|e| e.v2).norm() <= 1e-14);
        }
    }

    /// Dual derivative of log at a generic element against a central difference
    /// of log along g ↦ exp(εδ) g (independent of dexp⁻¹), and against dexp⁻¹.
    #[test]
    fn log_dual_vs_finite_difference() {
        let xi = Vector6::new(0.9, -0.4, 1.3, 0.5, 2.0, -1.0);
        let d = Vector6::new(0.2, 0.7, -0.1, -0.3, 0.4, 0.9);
        let g = exp(&xi);
        let gd = SE3::new(
            SO3::from_matrix_unchecked(g.rotation().matrix().map(Dual64::from)),
            g.translation().map(Dual64::from),
        );
        let ad = log(&exp(&d.map(|e| Dual64::new(0.0, e))).compose(&gd))
            .expect("ok")
            .map(|e| e.eps);
        let h = 1e-5;
        let fd =
            (log(&exp(&(d * h)).compose(&g)).expect("ok") - log(&exp(&(-d * h)).compose(&g)).expect("ok")) / (2.0 * h);
        assert!((ad - fd).norm() <= 1e-8);
        assert!((ad - dexp_inv(&xi) * d).norm() <= 1e-13);
        let ad = cay_inv(&exp(&d.map(|e| Dual64::new(0.0, e))).compose(&gd))
            .expect("ok")
            .map(|e| e.eps);
        let w = cay_inv(&g).expect("ok");
        assert!((ad - dcay_inv(&w) * d).norm() <= 1e-12);
    }

    /// The published variant x = 2/(4+|ω|²)(2I + ω̂)v differs from the matrix
    /// Cayley map whenever ω·v ≠ 0 (note 000 §13 pitfall).
    #[test]
    fn cayley_translation_pitfall() {
        let xi = Vector6::new(0.4, 0.3, -0.5, 1.0, 0.2, 0.3);
        let (w, v) = split(&xi);
        let variant: Vector3<f64> = (Matrix3::identity() * 2.0 + hat3(&w)) * v * (2.0 / (4.0 + w.norm_squared()));
        let h = hat(&xi) * 0.5;
        let m = (Matrix4::identity() - h).try_inverse().expect("invertible") * (Matrix4::identity() + h);
        let exact = m.fixed_view::<3, 1>(0, 3).into_owned();
        assert!((cay(&xi).translation() - exact).norm() <= 8.0 * EPS);
        assert!((variant - exact).norm() > 1e-2);
    }

    /// Note 000 §15.3 data: η₀⁰ = cay⁻¹(g₀⁰⁻¹g₁⁰)/Δs = E6 exactly, and the s = 0 end
    /// g₀ʲ⁺¹ = g₀ʲ cay(Δt ξ₀) with ω ∥ v ∥ E2 translates by exactly Δt v per
    /// step while rotating about E2 by 2 atan(0.85 Δt/2) per step.
    #[test]
    fn note_000_beam_data() {
        let (ds, dt) = (0.02, 0.04);
        let g1 = SE3::from_translation(Vector3::new(0.0, 0.0, ds));
        let eta = cay_inv(&SE3::<f64>::identity().between(&g1)).expect("ok") / ds;
        assert_eq!(eta, Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, 1.0));
        let xi0 = Vector6::new(0.0, -0.85, 0.0, 0.0, -0.1, 0.0);
        let mut g = SE3::identity();
        for _ in 0..3 {
            g = g.compose(&cay(&(xi0 * dt)));
        }
        assert!((g.translation() - Vector3::new(0.0, -3.0 * 0.1 * dt, 0.0)).norm() <= 8.0 * EPS);
        let angle = 3.0 * 2.0 * (0.85 * dt / 2.0).atan();
        let expect = so3::exp(&Vector3::new(0.0, -angle, 0.0));
        assert!(maxabs(&(g.rotation().matrix() - expect.matrix())) <= 8.0 * EPS);
    }

    #[test]
    fn cut_locus_and_constructors() {
        let n = Vector3::new(0.0, 0.6, 0.8);
        let g = SE3::new(so3::exp(&(n * (PI - 1e-12))), Vector3::new(1.0, 2.0, 3.0));
        assert!(matches!(log(&g), Err(LieError::NearCutLocus { .. })));
        assert!(matches!(cay_inv(&g), Err(LieError::NearCutLocus { .. })));
        assert!(matches!(
            distance(&SE3::identity(), &g),
            Err(LieError::NearCutLocus { .. })
        ));
        let ok = SE3::new(so3::exp(&(n * (PI - 1e-3))), Vector3::new(1.0, 2.0, 3.0));
        assert!(log(&ok).is_ok() && cay_inv(&ok).is_ok());
        assert_eq!(SE3::from_matrix(&ok.to_matrix()), Ok(ok));
        let mut bad = ok.to_matrix();
        bad[(3, 0)] = 0.1;
        assert!(matches!(SE3::from_matrix(&bad), Err(LieError::NotARotation { .. })));
        let xi = Vector6::new(0.1, -0.2, 0.3, 0.4, 0.5, -0.6);
        assert_eq!(vee(&hat(&xi)), xi);
        let p = Vector3::new(0.3, 0.1, -0.2);
        let g = exp(&xi);
        let hp = g.to_matrix() * nalgebra::Vector4::new(p[0], p[1], p[2], 1.0);
        assert!((g.act(&p) - hp.xyz()).norm() <= 4.0 * EPS);
        assert!(maxabs(&((g * g.inverse()).to_matrix() - Matrix4::identity())) <= 4.0 * EPS);
    }

    /// Rotation blocks stay orthogonal to round-off through long products;
    /// `renormalize` restores orthogonality to a few ε.
    #[test]
    fn orthogonality_after_compositions() {
        let steps = [
            Vector6::new(0.3, -0.2, 0.9, 1.0, 0.0, 0.5),
            Vector6::new(-1.1, 0.4, 0.05, 0.0, -2.0, 0.1),
        ];
        let mut g = SE3::identity();
        for i in 0..10 {
            g = g * exp(&steps[i % 2]) * cay(&steps[(i + 1) % 2]);
        }
        let r = g.rotation().matrix();
        assert!(maxabs(&(r.transpose() * r - Matrix3::identity())) <= 20.0 * EPS);
        for i in 0..10_000 {
            g = g * cay(&steps[i % 2]);
        }
        let g = g.renormalize();
        let r = g.rotation().matrix();
        assert!(maxabs(&(r.transpose() * r - Matrix3::identity())) <= 1e-15);
    }
}
