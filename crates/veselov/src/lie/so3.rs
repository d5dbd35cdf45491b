//! The rotation group SO(3) and its Lie algebra so(3) ≅ (R³, ×).
//!
//! All formulas, sources and conventions are listed in the
//! [module documentation of `lie`](super). In short: rotation vectors ω ∈ R³
//! with `hat(ω) e = ω × e`; exp (Rodrigues, note 003 eq. (6.8)); log on
//! angles < π (note 003 Lemma 6.6); Cayley map cay ω = (I − ω̂/2)⁻¹(I + ω̂/2)
//! (note 000 §13); right-trivialised derivatives dτ_ω with
//! τ(ω + εδ) = τ(ε dτ_ω δ) τ(ω) + O(ε²) (seed 000 eq. (62)).

use std::f64::consts::PI;
use std::ops::Mul;

use nalgebra::{Matrix3, Quaternion, Vector3};
use num_dual::DualNum;

use super::{CUT_LOCUS_MARGIN, LieError, LieGroup, ORTHOGONALITY_TOLERANCE, series};
use crate::ad::{mat3_mul, mat3_tr_mul, mat3_vec};

/// so(3) hat map: `hat(ω) = ω̂` with `ω̂ e = ω × e`.
pub fn hat<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> Matrix3<D> {
    let z = D::from(0.0);
    Matrix3::new(z, -w[2], w[1], w[2], z, -w[0], -w[1], w[0], z)
}

/// so(3) vee map, inverse of [`hat`]. It reads the skew-symmetric part
/// (M − Mᵀ)/2 of its argument, so `vee(hat(ω)) = ω` and any symmetric part of
/// `m` is ignored.
pub fn vee<D: DualNum<Primitive = f64> + Copy>(m: &Matrix3<D>) -> Vector3<D> {
    Vector3::new(
        (m[(2, 1)] - m[(1, 2)]) * 0.5,
        (m[(0, 2)] - m[(2, 0)]) * 0.5,
        (m[(1, 0)] - m[(0, 1)]) * 0.5,
    )
}

/// A rotation, stored as its 3×3 orthogonal matrix R (det R = +1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SO3<D> {
    matrix: Matrix3<D>,
}

impl<D: DualNum<Primitive = f64> + Copy> SO3<D> {
    /// The identity rotation.
    pub fn identity() -> Self {
        SO3 {
            matrix: Matrix3::identity(),
        }
    }

    /// Wrap a matrix after checking (on real parts) that it is orthogonal with
    /// determinant +1 up to [`ORTHOGONALITY_TOLERANCE`].
    pub fn from_matrix(matrix: Matrix3<D>) -> Result<Self, LieError> {
        let defect = rotation_defect(&matrix);
        if defect <= ORTHOGONALITY_TOLERANCE {
            Ok(SO3 { matrix })
        } else {
            Err(LieError::NotARotation { defect })
        }
    }

    /// Wrap a matrix the caller guarantees to be a rotation (not checked).
    pub fn from_matrix_unchecked(matrix: Matrix3<D>) -> Self {
        SO3 { matrix }
    }

    /// The rotation matrix R.
    pub fn matrix(&self) -> &Matrix3<D> {
        &self.matrix
    }

    /// Consume into the rotation matrix R.
    pub fn into_matrix(self) -> Matrix3<D> {
        self.matrix
    }

    /// The product `self · other` (R₁R₂), written out entry by entry
    /// ([`mat3_mul`]).
    pub fn compose(&self, other: &Self) -> Self {
        SO3 {
            matrix: mat3_mul(&self.matrix, &other.matrix),
        }
    }

    /// The inverse rotation Rᵀ.
    pub fn inverse(&self) -> Self {
        SO3 {
            matrix: self.matrix.transpose(),
        }
    }

    /// The relative rotation RᵀS (the same entries as
    /// `self.inverse().compose(other)`, without the transposed copy).
    pub fn between(&self, other: &Self) -> Self {
        SO3 {
            matrix: mat3_tr_mul(&self.matrix, &other.matrix),
        }
    }

    /// Rotate a point: p ↦ Rp (written out, [`mat3_vec`]).
    pub fn act(&self, p: &Vector3<D>) -> Vector3<D> {
        mat3_vec(&self.matrix, p)
    }

    /// The rotation represented by a quaternion q = w + xi + yj + zk
    /// (`Quaternion::new(w, x, y, z)`, Hamilton convention, active rotation
    /// p ↦ q p q̄). q need not be normalised: R = ((w² − |v|²)I + 2vvᵀ + 2w v̂)/|q|²,
    /// so q and −q give the same rotation. Fails for |q| < 1e-150.
    pub fn from_quaternion(q: &Quaternion<D>) -> Result<Self, LieError> {
        let w = q.coords[3];
        let v = Vector3::new(q.coords[0], q.coords[1], q.coords[2]);
        let n2 = w * w + v.dot(&v);
        let n2r = n2.re();
        if !(n2r.is_finite() && n2r > 1e-300) {
            return Err(LieError::ZeroQuaternion { norm: n2r.sqrt() });
        }
        Ok(SO3 {
            matrix: quaternion_matrix(w, &v) / n2,
        })
    }

    /// The unit quaternion of this rotation, `Quaternion::new(w, x, y, z)`,
    /// in the canonical hemisphere w ≥ 0 (Shepperd's method: the largest of
    /// 1 + tr R, 1 + 2Rᵢᵢ − tr R is used as pivot, so the result is accurate for
    /// every angle, including near π). Inverse of [`SO3::from_quaternion`].
    pub fn to_quaternion(&self) -> Quaternion<D> {
        let r = &self.matrix;
        let tr = r[(0, 0)] + r[(1, 1)] + r[(2, 2)];
        let cand = [tr.re(), r[(0, 0)].re(), r[(1, 1)].re(), r[(2, 2)].re()];
        let mut k = 0;
        for i in 1..4 {
            if cand[i] > cand[k] {
                k = i;
            }
        }
        let one = D::from(1.0);
        let (w, x, y, z) = match k {
            0 => {
                let w = (tr + one).sqrt() * 0.5;
                let f = (w * 4.0).recip();
                (
                    w,
                    (r[(2, 1)] - r[(1, 2)]) * f,
                    (r[(0, 2)] - r[(2, 0)]) * f,
                    (r[(1, 0)] - r[(0, 1)]) * f,
                )
            }
            1 => {
                let x = (one + r[(0, 0)] * 2.0 - tr).sqrt() * 0.5;
                let f = (x * 4.0).recip();
                (
                    (r[(2, 1)] - r[(1, 2)]) * f,
                    x,
                    (r[(0, 1)] + r[(1, 0)]) * f,
                    (r[(0, 2)] + r[(2, 0)]) * f,
                )
            }
            2 => {
                let y = (one + r[(1, 1)] * 2.0 - tr).sqrt() * 0.5;
                let f = (y * 4.0).recip();
                (
                    (r[(0, 2)] - r[(2, 0)]) * f,
                    (r[(0, 1)] + r[(1, 0)]) * f,
                    y,
                    (r[(1, 2)] + r[(2, 1)]) * f,
                )
            }
            _ => {
                let z = (one + r[(2, 2)] * 2.0 - tr).sqrt() * 0.5;
                let f = (z * 4.0).recip();
                (
                    (r[(1, 0)] - r[(0, 1)]) * f,
                    (r[(0, 2)] + r[(2, 0)]) * f,
                    (r[(1, 2)] + r[(2, 1)]) * f,
                    z,
                )
            }
        };
        if w.re() < 0.0 {
            Quaternion::new(-w, -x, -y, -z)
        } else {
            Quaternion::new(w, x, y, z)
        }
    }

    /// The rotation angle θ = |log R| ∈ [0, π], computed as 2 atan2(|q_v|, q_w)
    /// (accurate at every angle, including π). Its derivative is undefined at
    /// θ = 0 (|·| is not differentiable there); use
    /// [`distance_squared`] for a smooth quantity.
    pub fn angle(&self) -> D {
        let q = self.to_quaternion();
        let v = Vector3::new(q.coords[0], q.coords[1], q.coords[2]);
        v.dot(&v).sqrt().atan2(q.coords[3]) * 2.0
    }

    /// The nearest rotation to a slightly non-orthogonal matrix, through its
    /// normalised quaternion: removes round-off drift after long products.
    pub fn renormalize(&self) -> Self {
        let q = self.to_quaternion();
        // The quaternion of a near-rotation has norm ≈ 1, so this cannot fail.
        SO3::from_quaternion(&q).unwrap_or(*self)
    }

    /// exp ω (see [`exp`]).
    pub fn exp(w: &Vector3<D>) -> Self {
        exp(w)
    }

    /// log R (see [`log`]).
    pub fn log(&self) -> Result<Vector3<D>, LieError> {
        log(self)
    }

    /// cay ω (see [`cay`]).
    pub fn cay(w: &Vector3<D>) -> Self {
        cay(w)
    }

    /// cay⁻¹ R (see [`cay_inv`]).
    pub fn cay_inv(&self) -> Result<Vector3<D>, LieError> {
        cay_inv(self)
    }
}

impl<D: DualNum<Primitive = f64> + Copy> Mul for SO3<D> {
    type Output = SO3<D>;
    fn mul(self, rhs: SO3<D>) -> SO3<D> {
        self.compose(&rhs)
    }
}

impl<D: DualNum<Primitive = f64> + Copy> LieGroup<D, 3> for SO3<D> {
    fn identity() -> Self {
        SO3::identity()
    }
    fn compose(&self, other: &Self) -> Self {
        SO3::compose(self, other)
    }
    fn inverse(&self) -> Self {
        SO3::inverse(self)
    }
    fn between(&self, other: &Self) -> Self {
        SO3::between(self, other)
    }
    fn adjoint(&self) -> Matrix3<D> {
        adjoint(self)
    }
    fn ad_star_matrix(&self) -> Matrix3<D> {
        ad_star_matrix(self)
    }
    fn coadjoint(&self) -> Matrix3<D> {
        coadjoint(self)
    }
}

/// Max of |RᵀR − I| entries and |det R − 1| on real parts.
pub(crate) fn rotation_defect<D: DualNum<Primitive = f64> + Copy>(m: &Matrix3<D>) -> f64 {
    let r = m.map(|e| e.re());
    let orth = (r.transpose() * r - Matrix3::identity()).abs().max();
    let det = (r.determinant() - 1.0).abs();
    let d = orth.max(det);
    if d.is_finite() { d } else { f64::INFINITY }
}

/// Rotation angle (f64) of a unit quaternion with w ≥ 0, and the cut-locus check.
fn check_cut_locus<D: DualNum<Primitive = f64> + Copy>(w: D, n2: D) -> Result<(), LieError> {
    let (w, n2) = (w.re(), n2.re());
    // Angle ≤ π/2 (n² ≤ w², w > 0): far from the cut locus, no atan2 needed.
    if w > 0.0 && n2 <= w * w {
        return Ok(());
    }
    let angle = 2.0 * n2.sqrt().atan2(w);
    if angle > PI - CUT_LOCUS_MARGIN || !angle.is_finite() {
        Err(LieError::NearCutLocus { angle })
    } else {
        Ok(())
    }
}

/// Exponential map (Rodrigues, note 003 eq. (6.8)):
/// exp ω = I + (sin θ/θ) ω̂ + ((1 − cos θ)/θ²) ω̂², θ = |ω|.
pub fn exp<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> SO3<D> {
    let x = w.dot(w);
    SO3 {
        matrix: hat_series(w, series::sinc(x), series::cosc(x)),
    }
}

/// I + a ω̂ + b ω̂², with ω̂² = ωωᵀ − |ω|²I written out entry by entry (over
/// dual numbers this avoids the generic matrix product).
fn hat_series<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>, a: D, b: D) -> Matrix3<D> {
    series_matrix(w, |x| x * a, b)
}

/// I + ω̂ + b ω̂² ([`hat_series`] with a = 1, without its products by 1).
pub(crate) fn unit_hat_series<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>, b: D) -> Matrix3<D> {
    series_matrix(w, |x| x, b)
}

/// I + `scaled`(ω̂) + b ω̂², entry by entry.
fn series_matrix<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>, scaled: impl Fn(D) -> D, b: D) -> Matrix3<D> {
    let (wh, n2) = (hat(w), w.dot(w));
    Matrix3::from_fn(|i, j| {
        let square = if i == j { w[i] * w[j] - n2 } else { w[i] * w[j] };
        let one = if i == j { D::one() } else { D::zero() };
        one + scaled(wh[(i, j)]) + square * b
    })
}

/// (w² − |v|²)I + 2vvᵀ + 2w v̂ = |q|² R(q) for the quaternion q = (w, v).
fn quaternion_matrix<D: DualNum<Primitive = f64> + Copy>(w: D, v: &Vector3<D>) -> Matrix3<D> {
    Matrix3::identity() * (w * w - v.dot(v)) + v * v.transpose() * D::from(2.0) + hat(v) * (w * 2.0)
}

/// Logarithm: the rotation vector ω with |ω| < π and exp ω = R
/// (note 003 Lemma 6.6).
///
/// Below a quarter turn it is read off the matrix: with
/// s = ½(R − Rᵀ)ˇ = sin θ·n and c = ½(tr R − 1) = cos θ > 0,
/// ω = (θ/sin θ)s, θ/sin θ = atan(t)/(t c), t = |s|/c = tan θ, by the series
/// of atan(t)/t in t² up to t = 0.1 and by atan2 above. From a quarter turn
/// on (where s loses the angle's resolution) it comes from the unit
/// quaternion (w ≥ 0, q_v): ω = 2 atan2(|q_v|, w) q_v/|q_v|.
///
/// Errors with [`LieError::NearCutLocus`] if the rotation angle exceeds
/// π − [`CUT_LOCUS_MARGIN`].
pub fn log<D: DualNum<Primitive = f64> + Copy>(r: &SO3<D>) -> Result<Vector3<D>, LieError> {
    let m = &r.matrix;
    let c = (m[(0, 0)] + m[(1, 1)] + m[(2, 2)] - 1.0) * 0.5;
    if c.re() > 0.0 {
        let s = Vector3::new(
            (m[(2, 1)] - m[(1, 2)]) * 0.5,
            (m[(0, 2)] - m[(2, 0)]) * 0.5,
            (m[(1, 0)] - m[(0, 1)]) * 0.5,
        );
        return Ok(s * series::angle_over_sine(c, s.dot(&s)));
    }
    let q = r.to_quaternion();
    let (w, v) = (q.coords[3], Vector3::new(q.coords[0], q.coords[1], q.coords[2]));
    let n2 = v.dot(&v);
    check_cut_locus(w, n2)?;
    Ok(v * series::half_angle_ratio(w, n2))
}

/// Cayley map (note 000 §13): cay ω = (I − ω̂/2)⁻¹(I + ω̂/2)
/// = I + 4/(4 + |ω|²)(ω̂ + ω̂²/2). It is the rotation by θ = 2 atan(|ω|/2)
/// about ω/|ω|.
///
/// Evaluated as ((4 − |ω|²)I + 2ωωᵀ + 4ω̂)/(4 + |ω|²), the same function
/// written through the (unnormalised) quaternion (2, ω).
pub fn cay<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> SO3<D> {
    let n2 = w.dot(w);
    SO3 {
        matrix: quaternion_matrix(D::from(2.0), w) / (n2 + 4.0),
    }
}

/// Inverse Cayley map: ω̂ = 2(R − I)(R + I)⁻¹ (note 000 §13). |ω| = 2 tan(θ/2).
///
/// Up to θ = π/2 (1 + tr R = 4cos²(θ/2) ≥ 2) as ω = 2 vee(R − Rᵀ)/(1 + tr R),
/// which is 2 q_v/q_w without the square root of the quaternion; beyond, where
/// 1 + tr R cancels, as ω = 2 q_v/q_w from the unit quaternion (accurate up
/// to the cut locus).
///
/// Errors with [`LieError::NearCutLocus`] if the rotation angle exceeds
/// π − [`CUT_LOCUS_MARGIN`].
pub fn cay_inv<D: DualNum<Primitive = f64> + Copy>(r: &SO3<D>) -> Result<Vector3<D>, LieError> {
    let m = &r.matrix;
    let cos_half_squared_4 = m[(0, 0)] + m[(1, 1)] + m[(2, 2)] + 1.0;
    if cos_half_squared_4.re() >= 2.0 {
        let f = cos_half_squared_4.recip() * 2.0;
        return Ok(Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]) * f);
    }
    let q = r.to_quaternion();
    let (w, v) = (q.coords[3], Vector3::new(q.coords[0], q.coords[1], q.coords[2]));
    check_cut_locus(w, v.dot(&v))?;
    Ok(v * (w.recip() * 2.0))
}

/// Right-trivialised derivative of exp:
/// dexp_ω = I + ((1 − cos θ)/θ²) ω̂ + ((θ − sin θ)/θ³) ω̂², so that
/// exp(ω + εδ) = exp(ε dexp_ω δ) exp(ω) + O(ε²).
/// (The left-trivialised d_v exp of note 003 §2.6 is dexp_{−v} = dexp_vᵀ.)
pub fn dexp<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> Matrix3<D> {
    let x = w.dot(w);
    hat_series(w, series::cosc(x), series::sin3(x))
}

/// Inverse of [`dexp`]: dexp⁻¹_ω = I − ω̂/2 + k(θ) ω̂²,
/// k(θ) = 1/θ² − (1 + cos θ)/(2θ sin θ) (note 003 Def. 6.9, whose left-trivialised
/// dlog v equals dexp⁻¹_{−v}). Defined for |ω| < 2π.
#[inline]
pub fn dexp_inv<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> Matrix3<D> {
    hat_series(w, D::from(-0.5), series::dlog(w.dot(w)))
}

/// Right-trivialised derivative of the Cayley map (note 000 §13):
/// dcay_ω = 2/(4 + |ω|²)(2I + ω̂).
pub fn dcay<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> Matrix3<D> {
    let f = (w.dot(w) + 4.0).recip() * 2.0;
    (Matrix3::identity() * D::from(2.0) + hat(w)) * f
}

/// Inverse of [`dcay`] (note 000 §13): dcay⁻¹_ω = I − ω̂/2 + ωωᵀ/4.
pub fn dcay_inv<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> Matrix3<D> {
    Matrix3::identity() - hat(w) * D::from(0.5) + w * w.transpose() * D::from(0.25)
}

/// Adjoint representation Ad_R = R (Ad_R ω = (R ω̂ Rᵀ)ˇ = Rω).
pub fn adjoint<D: DualNum<Primitive = f64> + Copy>(r: &SO3<D>) -> Matrix3<D> {
    r.matrix
}

/// Algebra adjoint ad_ω = ω̂ (ad_ω η = [ω̂, η̂]ˇ = ω × η).
pub fn ad<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> Matrix3<D> {
    hat(w)
}

/// (ad_ω)ᵀ = −ω̂: ⟨ad\*_ω μ, η⟩ = ⟨μ, ad_ω η⟩ (note 000 eq. (24) convention).
pub fn ad_star<D: DualNum<Primitive = f64> + Copy>(w: &Vector3<D>) -> Matrix3<D> {
    -hat(w)
}

/// (Ad_R)ᵀ = Rᵀ — the operator seed 000 calls Ad\*_R (note 000 §1):
/// ⟨Ad\*_R μ, ξ⟩ = ⟨μ, Ad_R ξ⟩. Not the coadjoint action; see [`coadjoint`].
pub fn ad_star_matrix<D: DualNum<Primitive = f64> + Copy>(r: &SO3<D>) -> Matrix3<D> {
    r.matrix.transpose()
}

/// Coadjoint action of R on so(3)\* ≅ R³: (Ad_{R⁻¹})ᵀ = R (body to spatial
/// angular momentum).
pub fn coadjoint<D: DualNum<Primitive = f64> + Copy>(r: &SO3<D>) -> Matrix3<D> {
    r.matrix
}

/// Geodesic of the bi-invariant metric (note 003 eq. (6.9)):
/// γ(s) = R₀ exp(s log(R₀ᵀR₁)), γ(0) = R₀, γ(1) = R₁.
/// Errors if R₀ᵀR₁ is within [`CUT_LOCUS_MARGIN`] of a half-turn (the
/// minimising geodesic is then not unique).
pub fn geodesic<D: DualNum<Primitive = f64> + Copy>(r0: &SO3<D>, r1: &SO3<D>, s: D) -> Result<SO3<D>, LieError> {
    let w = log(&r0.between(r1))?;
    Ok(r0.compose(&exp(&(w * s))))
}

/// Riemannian distance d(R₀, R₁) = |log(R₀ᵀR₁)| ∈ [0, π] (note 003 Lemma 6.7:
/// 1 + 2 cos d = tr(R₀ᵀR₁)). Defined at every pair, including half-turns;
/// not differentiable where d = 0.
pub fn distance<D: DualNum<Primitive = f64> + Copy>(r0: &SO3<D>, r1: &SO3<D>) -> D {
    r0.between(r1).angle()
}

/// d(R₀, R₁)² = |log(R₀ᵀR₁)|², smooth (also at d = 0); errors near the cut locus.
pub fn distance_squared<D: DualNum<Primitive = f64> + Copy>(r0: &SO3<D>, r1: &SO3<D>) -> Result<D, LieError> {
    let w = log(&r0.between(r1))?;
    Ok(w.dot(&w))
}

#[cfg(test)]
pub(crate) mod tests;
