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
mod tests;
