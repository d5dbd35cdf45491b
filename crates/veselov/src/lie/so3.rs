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
use crate::ad::{mat3_mul, mat3_vec};

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
/// (note 003 Lemma 6.6), computed from the unit quaternion (w ≥ 0, q_v) as
/// ω = 2 atan2(|q_v|, w) q_v/|q_v| with a series for small |q_v|.
///
/// Errors with [`LieError::NearCutLocus`] if the rotation angle exceeds
/// π − [`CUT_LOCUS_MARGIN`].
pub fn log<D: DualNum<Primitive = f64> + Copy>(r: &SO3<D>) -> Result<Vector3<D>, LieError> {
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

/// Inverse Cayley map: ω̂ = 2(R − I)(R + I)⁻¹ (note 000 §13), computed as
/// ω = 2 q_v/q_w from the unit quaternion (equivalent, and accurate up to the
/// cut locus). |ω| = 2 tan(θ/2).
///
/// Errors with [`LieError::NearCutLocus`] if the rotation angle exceeds
/// π − [`CUT_LOCUS_MARGIN`].
pub fn cay_inv<D: DualNum<Primitive = f64> + Copy>(r: &SO3<D>) -> Result<Vector3<D>, LieError> {
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
    let w = log(&r0.inverse().compose(r1))?;
    Ok(r0.compose(&exp(&(w * s))))
}

/// Riemannian distance d(R₀, R₁) = |log(R₀ᵀR₁)| ∈ [0, π] (note 003 Lemma 6.7:
/// 1 + 2 cos d = tr(R₀ᵀR₁)). Defined at every pair, including half-turns;
/// not differentiable where d = 0.
pub fn distance<D: DualNum<Primitive = f64> + Copy>(r0: &SO3<D>, r1: &SO3<D>) -> D {
    r0.inverse().compose(r1).angle()
}

/// d(R₀, R₁)² = |log(R₀ᵀR₁)|², smooth (also at d = 0); errors near the cut locus.
pub fn distance_squared<D: DualNum<Primitive = f64> + Copy>(r0: &SO3<D>, r1: &SO3<D>) -> Result<D, LieError> {
    let w = log(&r0.inverse().compose(r1))?;
    Ok(w.dot(&w))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use num_dual::{Dual2_64, Dual64};
    use proptest::prelude::*;

    const EPS: f64 = f64::EPSILON;

    /// Orthogonality defect max|RᵀR − I| of a single computed exp/cay: each
    /// entry of R carries a few ulps of rounding, so RᵀR − I is a few ε; the
    /// worst case measured over 2·10⁵ random rotations is 8ε (exp) and 4.5ε
    /// (cay), typical ≤ 2ε.
    pub(crate) const ORTH_TOL: f64 = 8.0 * EPS;

    /// Random rotation vectors: uniform direction, angle from a mix that
    /// includes exactly 0, 1e-10, 1e-6, the bulk, and π − 1e-3.
    pub(crate) fn rotvec() -> impl Strategy<Value = Vector3<f64>> {
        let angle = prop_oneof![
            Just(0.0),
            Just(1e-10),
            Just(1e-6),
            1e-12..1e-3,
            1e-3..3.0f64,
            Just(PI - 1e-3),
            (PI - 1e-3)..(PI - 1e-5),
        ];
        (unit(), angle).prop_map(|(n, a)| n * a)
    }

    /// Rotation vectors with angles in [0, 3] only (0, 1e-10, 1e-6, tiny, bulk),
    /// for properties whose finite-difference or domain checks need room
    /// below π.
    pub(crate) fn rotvec_moderate() -> impl Strategy<Value = Vector3<f64>> {
        let angle = prop_oneof![Just(0.0), Just(1e-10), Just(1e-6), 1e-12..1e-3, 1e-3..3.0f64];
        (unit(), angle).prop_map(|(n, a)| n * a)
    }

    /// Uniform unit vector.
    pub(crate) fn unit() -> impl Strategy<Value = Vector3<f64>> {
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("nonzero", |(a, b, c)| a * a + b * b + c * c > 1e-2)
            .prop_map(|(a, b, c)| Vector3::new(a, b, c).normalize())
    }

    /// Random rotation from a uniform random quaternion.
    pub(crate) fn rotation() -> impl Strategy<Value = SO3<f64>> {
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64)
            .prop_filter("nonzero", |(a, b, c, d)| a * a + b * b + c * c + d * d > 1e-2)
            .prop_map(|(a, b, c, d)| SO3::from_quaternion(&Quaternion::new(a, b, c, d)).expect("nonzero quaternion"))
    }

    fn maxabs(m: &Matrix3<f64>) -> f64 {
        m.abs().max()
    }

    /// Bound on |ω − ω'| for a round trip of exp/log at angle θ: the quaternion
    /// route loses O(ε) in the angle and in the axis, so the absolute error is
    /// a few ε·(1 + θ). Measured ≤ 3ε; tolerance 16ε(1 + θ).
    fn exp_tol(w: &Vector3<f64>) -> f64 {
        16.0 * EPS * (1.0 + w.norm())
    }

    /// Round trip of cay/cay⁻¹: |ω| = 2 tan(θ/2) is ill-conditioned near π.
    /// The angle θ is recovered to O(ε) absolute, so |ω| carries a relative
    /// error ε·(d|ω|/dθ)·/|ω| = ε/sin θ; tolerance 16ε(1 + |ω|)(1 + 1/sin θ).
    fn cay_tol(w: &Vector3<f64>) -> f64 {
        let theta = 2.0 * (w.norm() / 2.0).atan();
        16.0 * EPS * (1.0 + w.norm()) * (1.0 + 1.0 / theta.sin().max(1e-300))
    }

    #[test]
    fn hat_vee_and_bracket() {
        let (a, b) = (Vector3::new(0.3, -1.2, 0.7), Vector3::new(-0.4, 0.5, 2.0));
        assert_eq!(vee(&hat(&a)), a);
        assert!((hat(&a) * b - a.cross(&b)).norm() <= 4.0 * EPS);
        let br = hat(&a) * hat(&b) - hat(&b) * hat(&a);
        assert!((vee(&br) - a.cross(&b)).norm() <= 8.0 * EPS);
        assert!(maxabs(&(br - hat(&a.cross(&b)))) <= 8.0 * EPS);
    }

    proptest! {
        #![proptest_config(crate::lie::test_config())]

        #[test]
        fn exp_log_round_trip(w in rotvec()) {
            let r = exp(&w);
            prop_assert!(maxabs(&(r.matrix.transpose() * r.matrix - Matrix3::identity())) <= ORTH_TOL);
            let back = log(&r).expect("angle below π − margin");
            prop_assert!((back - w).norm() <= exp_tol(&w), "ω={w:?} back={back:?} err={}", (back - w).norm());
        }

        #[test]
        fn cay_round_trip(w in rotvec()) {
            // Map the test angle θ to the Cayley vector with the same rotation angle.
            let theta = w.norm();
            let wc = if theta > 0.0 { w * (2.0 * (theta / 2.0).tan() / theta) } else { w };
            let r = cay(&wc);
            prop_assert!(maxabs(&(r.matrix.transpose() * r.matrix - Matrix3::identity())) <= ORTH_TOL);
            prop_assert!((r.angle() - theta).abs() <= 8.0 * EPS * (1.0 + theta));
            let back = cay_inv(&r).expect("angle below π − margin");
            prop_assert!((back - wc).norm() <= cay_tol(&wc), "ω={wc:?} err={}", (back - wc).norm());
        }

        /// τ∘τ⁻¹ = id on random rotations (uniform on SO(3), plus exp of the
        /// angle mix of `rotvec`: 0, 1e-10, 1e-6, …, π − 1e-3 … π − 1e-5). The
        /// element is reproduced to a few ε even near π: R is insensitive to the
        /// ill-conditioned length of the Cayley vector there.
        #[test]
        fn inverse_then_forward(r in prop_oneof![rotation(), rotvec().prop_map(|w| exp(&w))]) {
            prop_assume!(r.angle() < PI - 2.0 * CUT_LOCUS_MARGIN);
            let e = exp(&log(&r).expect("below cut locus"));
            prop_assert!(maxabs(&(e.matrix - r.matrix)) <= 8.0 * EPS);
            let c = cay(&cay_inv(&r).expect("below cut locus"));
            prop_assert!(maxabs(&(c.matrix - r.matrix)) <= 8.0 * EPS);
        }

        #[test]
        fn quaternion_round_trip(r in rotation()) {
            let q = r.to_quaternion();
            prop_assert!(q.coords[3] >= 0.0);
            prop_assert!((q.coords.norm() - 1.0).abs() <= 4.0 * EPS);
            let back = SO3::from_quaternion(&q).expect("unit");
            prop_assert!(maxabs(&(back.matrix - r.matrix)) <= 8.0 * EPS);
            let neg = SO3::from_quaternion(&Quaternion::from(-q.coords)).expect("unit");
            prop_assert!(maxabs(&(neg.matrix - r.matrix)) <= 8.0 * EPS);
        }

        /// exp(ω) via the quaternion (cos θ/2, sin θ/2 n) agrees with Rodrigues.
        #[test]
        fn exp_matches_quaternion(w in rotvec()) {
            let t = w.norm();
            let n = if t > 0.0 { w / t } else { Vector3::zeros() };
            let s = (t / 2.0).sin();
            let q = Quaternion::new((t / 2.0).cos(), s * n[0], s * n[1], s * n[2]);
            let rq = SO3::from_quaternion(&q).expect("unit");
            prop_assert!(maxabs(&(rq.matrix - exp(&w).matrix)) <= 8.0 * EPS);
        }

        /// Right-trivialised dexp and dcay against central differences of the
        /// maps: τ⁻¹(τ(ω + εδ) τ(ω)⁻¹) = ε dτ_ω δ + O(ε²); central difference
        /// with ε = 1e-5 has truncation O(ε²|ω|) ~ 1e-10 and round-off ~ε/ε ~ 1e-11.
        #[test]
        fn dtau_finite_differences(w in rotvec_moderate(), d in unit()) {
            let h = 1e-5;
            let fd_exp = {
                let r0 = exp(&w).inverse();
                let p = log(&exp(&(w + d * h)).compose(&r0)).expect("small");
                let m = log(&exp(&(w - d * h)).compose(&r0)).expect("small");
                (p - m) / (2.0 * h)
            };
            prop_assert!((fd_exp - dexp(&w) * d).norm() <= 1e-8, "dexp err {}", (fd_exp - dexp(&w) * d).norm());
            let fd_cay = {
                let r0 = cay(&w).inverse();
                let p = cay_inv(&cay(&(w + d * h)).compose(&r0)).expect("small");
                let m = cay_inv(&cay(&(w - d * h)).compose(&r0)).expect("small");
                (p - m) / (2.0 * h)
            };
            prop_assert!((fd_cay - dcay(&w) * d).norm() <= 1e-8, "dcay err {}", (fd_cay - dcay(&w) * d).norm());
        }

        /// Exact version of the same identity: the dual part of τ(ω + tδ) at t = 0
        /// times τ(ω)ᵀ is hat(dτ_ω δ), to round-off (‖dτ‖ ≤ 1 + θ; tol 32ε(1+θ)²).
        #[test]
        fn dtau_exact_via_dual(w in rotvec(), d in unit()) {
            let wd = w.map(Dual64::from) + d.map(|e| Dual64::new(0.0, e));
            let tol = 32.0 * EPS * (1.0 + w.norm()).powi(2);
            for (rd, r, dt) in [
                (exp(&wd), exp(&w), dexp(&w)),
                (cay(&wd), cay(&w), dcay(&w)),
            ] {
                let deriv = rd.matrix.map(|e| e.eps) * r.matrix.transpose();
                prop_assert!(maxabs(&(deriv - hat(&(dt * d)))) <= tol);
            }
        }

        /// dτ⁻¹ = (dτ)⁻¹. For θ ≤ π, ‖dexp‖ ≤ 1 and the entries of dexp⁻¹ are
        /// O(1 + θ²); dcay⁻¹ has entries O(1 + |ω|²). The products therefore carry
        /// a few ε × (1 + |ω|²); tolerance 16ε(1 + |ω|²).
        #[test]
        fn dtau_inv_is_inverse(w in rotvec()) {
            let i3 = Matrix3::identity();
            let ce = 16.0 * EPS * (1.0 + w.norm_squared());
            prop_assert!(maxabs(&(dexp_inv(&w) * dexp(&w) - i3)) <= ce);
            prop_assert!(maxabs(&(dexp(&w) * dexp_inv(&w) - i3)) <= ce);
            prop_assert!(maxabs(&(dcay_inv(&w) * dcay(&w) - i3)) <= ce);
            prop_assert!(maxabs(&(dcay(&w) * dcay_inv(&w) - i3)) <= ce);
        }

        /// The dual part of log(R(t)) is dexp⁻¹ applied to the right-trivialised
        /// velocity: d/dt log(exp(εδ)·R) = dexp⁻¹_{log R} δ; same for cay⁻¹.
        #[test]
        fn inverse_derivative_via_dual(w in rotvec_moderate(), d in unit()) {
            let pert = exp(&d.map(|e| Dual64::new(0.0, e)));
            let tol = 1e-13 * (1.0 + w.norm_squared());
            let rd = pert.compose(&SO3::from_matrix_unchecked(exp(&w).matrix.map(Dual64::from)));
            let got = log(&rd).expect("below π").map(|e| e.eps);
            prop_assert!((got - dexp_inv(&w) * d).norm() <= tol);
            let cd = pert.compose(&SO3::from_matrix_unchecked(cay(&w).matrix.map(Dual64::from)));
            let got = cay_inv(&cd).expect("below π").map(|e| e.eps);
            prop_assert!((got - dcay_inv(&w) * d).norm() <= tol * (1.0 + w.norm_squared()));
        }

        /// Ad is a homomorphism and Ad_R ω̂ = R ω̂ Rᵀ; Ad* pairing and coadjoint.
        #[test]
        fn adjoint_identities(r in rotation(), s in rotation(), w in unit(), mu in unit()) {
            prop_assert!(maxabs(&(adjoint(&r.compose(&s)) - adjoint(&r) * adjoint(&s))) <= 8.0 * EPS);
            let lhs = hat(&(adjoint(&r) * w));
            prop_assert!(maxabs(&(lhs - r.matrix * hat(&w) * r.matrix.transpose())) <= 8.0 * EPS);
            let pair = (ad_star_matrix(&r) * mu).dot(&w) - mu.dot(&(adjoint(&r) * w));
            prop_assert!(pair.abs() <= 8.0 * EPS);
            prop_assert!(maxabs(&(coadjoint(&r.compose(&s)) - coadjoint(&r) * coadjoint(&s))) <= 8.0 * EPS);
            prop_assert!(((coadjoint(&r) * mu).dot(&(adjoint(&r) * w)) - mu.dot(&w)).abs() <= 8.0 * EPS);
            prop_assert!(((ad_star(&w) * mu).dot(&r.act(&w)) - mu.dot(&(ad(&w) * r.act(&w)))).abs() <= 8.0 * EPS);
        }

        /// Note 003 §2.6 identities: tr exp v = 1 + 2 cos|v|; log Rᵀ = −log R;
        /// log(R S Rᵀ) = R log S; dlog(−v) = dlog(v)ᵀ; distance symmetric and
        /// bi-invariant; 1 + 2 cos d = tr(R₀ᵀR₁).
        #[test]
        fn note_003_identities(w in rotvec(), r in rotation(), s in rotation()) {
            let e = exp(&w);
            prop_assert!((e.matrix.trace() - 1.0 - 2.0 * w.norm().cos()).abs() <= 8.0 * EPS);
            let l = log(&e).expect("ok");
            prop_assert!((log(&e.inverse()).expect("ok") + l).norm() <= exp_tol(&w));
            let conj = r.compose(&e).compose(&r.inverse());
            prop_assert!((log(&conj).expect("ok") - r.act(&l)).norm() <= 4.0 * exp_tol(&w));
            prop_assert!(maxabs(&(dexp_inv(&(-w)) - dexp_inv(&w).transpose())) <= 8.0 * EPS);
            let d = distance(&r, &s);
            prop_assert!((d - distance(&s, &r)).abs() <= 16.0 * EPS);
            let q = exp(&w);
            prop_assert!((d - distance(&q.compose(&r), &q.compose(&s))).abs() <= 64.0 * EPS / (PI - d).max(1e-3));
            prop_assert!((d - distance(&r.compose(&q), &s.compose(&q))).abs() <= 64.0 * EPS / (PI - d).max(1e-3));
            prop_assert!((1.0 + 2.0 * d.cos() - (r.matrix.transpose() * s.matrix).trace()).abs() <= 16.0 * EPS);
        }

        /// Geodesic: endpoints, constant speed d(γ(s), γ(t)) = |s − t| d(R₀, R₁).
        #[test]
        fn geodesic_properties(r in rotation(), s in rotation(), a in 0.0..1.0f64, b in 0.0..1.0f64) {
            let d = distance(&r, &s);
            prop_assume!(d < PI - 1e-3);
            let g0 = geodesic(&r, &s, 0.0).expect("ok");
            let g1 = geodesic(&r, &s, 1.0).expect("ok");
            prop_assert!(maxabs(&(g0.matrix - r.matrix)) <= 8.0 * EPS);
            prop_assert!(maxabs(&(g1.matrix - s.matrix)) <= 64.0 * EPS);
            let (ga, gb) = (geodesic(&r, &s, a).expect("ok"), geodesic(&r, &s, b).expect("ok"));
            prop_assert!((distance(&ga, &gb) - (a - b).abs() * d).abs() <= 1e-13);
            let d2 = distance_squared(&r, &s).expect("ok");
            prop_assert!((d2 - d * d).abs() <= 1e-13);
        }
    }

    /// Cut locus: angle π − 1e-12 is refused by log and cay⁻¹ with the typed
    /// error; π − 1e-3 is accepted (covered by the round-trip properties).
    #[test]
    fn cut_locus_is_a_typed_error() {
        let n = Vector3::new(1.0, -2.0, 0.5).normalize();
        let r = exp(&(n * (PI - 1e-12)));
        match log(&r) {
            Err(LieError::NearCutLocus { angle }) => assert!((angle - PI).abs() < 1e-9),
            other => panic!("expected NearCutLocus, got {other:?}"),
        }
        assert!(matches!(cay_inv(&r), Err(LieError::NearCutLocus { .. })));
        assert!(matches!(
            geodesic(&SO3::identity(), &r, 0.5),
            Err(LieError::NearCutLocus { .. })
        ));
        // The exact half-turn too, and the distance is still defined there.
        let half = exp(&(n * PI));
        assert!(matches!(log(&half), Err(LieError::NearCutLocus { .. })));
        assert!((distance(&SO3::identity(), &half) - PI).abs() <= 8.0 * EPS);
        // Just outside the margin both inverses work.
        let ok = exp(&(n * (PI - 2.0 * CUT_LOCUS_MARGIN)));
        assert!(log(&ok).is_ok() && cay_inv(&ok).is_ok());
        let msg = LieError::NearCutLocus { angle: 3.1 }.to_string();
        assert!(msg.contains("cut locus"));
    }

    /// Small angles: exp and log are accurate to round-off at 1e-8 and below
    /// (reference: the Taylor expansion, exact to ε at these angles).
    #[test]
    fn small_angle_accuracy() {
        let n = Vector3::new(0.6, -0.8, 0.0);
        for &t in &[0.0, 1e-300, 1e-16, 1e-10, 1e-8, 1e-6] {
            let w = n * t;
            let wh = hat(&w);
            let reference = Matrix3::identity() + wh + wh * wh * 0.5 + wh * wh * wh / 6.0;
            assert!(maxabs(&(exp(&w).matrix - reference)) <= 2.0 * EPS, "t={t}");
            let l = log(&exp(&w)).expect("ok");
            assert!((l - w).norm() <= 2.0 * EPS * t.max(1e-300) + 1e-300, "t={t}: {l:?}");
            let c = cay_inv(&cay(&w)).expect("ok");
            assert!((c - w).norm() <= 2.0 * EPS * t.max(1e-300) + 1e-300, "t={t}");
        }
    }

    /// Dual derivatives at θ = 0 and θ = 1e-9 equal the analytic ones:
    /// d/dt exp(ω + tδ) = hat(dexp_ω δ) exp ω, with dexp_0 = I; d²/dt² exp(tδ)|₀ = δ̂²;
    /// and log∘exp has first derivative δ and second derivative 0 there.
    #[test]
    fn derivatives_at_small_angles() {
        let d = Vector3::new(0.3, -0.5, 0.8);
        for &t in &[0.0, 1e-9] {
            let w = Vector3::new(1.0, 2.0, -2.0) / 3.0 * t;
            let wd = w.map(Dual64::from) + d.map(|e| Dual64::new(0.0, e));
            let deriv = exp(&wd).matrix.map(|e| e.eps);
            let expect = hat(&(dexp(&w) * d)) * exp(&w).matrix;
            assert!(maxabs(&(deriv - expect)) <= 4.0 * EPS, "t={t}");
            let deriv = cay(&wd).matrix.map(|e| e.eps);
            let expect = hat(&(dcay(&w) * d)) * cay(&w).matrix;
            assert!(maxabs(&(deriv - expect)) <= 4.0 * EPS, "t={t}");
            let back = log(&exp(&wd)).expect("ok");
            assert!((back.map(|e| e.eps) - d).norm() <= 4.0 * EPS, "t={t}");
            let back = cay_inv(&cay(&wd)).expect("ok");
            assert!((back.map(|e| e.eps) - d).norm() <= 4.0 * EPS, "t={t}");
            // Second derivatives.
            let w2 = w.map(Dual2_64::from) + d.map(|e| Dual2_64::new(0.0, e, 0.0));
            let e2 = exp(&w2);
            if t == 0.0 {
                assert!(maxabs(&(e2.matrix.map(|e| e.v2) - hat(&d) * hat(&d))) <= 4.0 * EPS);
                assert!(maxabs(&(cay(&w2).matrix.map(|e| e.v2) - hat(&d) * hat(&d))) <= 4.0 * EPS);
            }
            let back = log(&e2).expect("ok");
            assert!(back.map(|e| e.v2).norm() <= 1e-14, "t={t}: {:?}", back.map(|e| e.v2));
            assert!((back.map(|e| e.v1) - d).norm() <= 4.0 * EPS);
        }
    }

    /// The dual derivative of exp at a moderate angle agrees with a central
    /// difference (independent of dexp): tolerance 1e-8 for h = 1e-5.
    #[test]
    fn exp_log_dual_vs_finite_difference() {
        let (w, d) = (Vector3::new(0.9, -0.4, 1.3), Vector3::new(0.2, 0.7, -0.1));
        let h = 1e-5;
        let wd = w.map(Dual64::from) + d.map(|e| Dual64::new(0.0, e));
        let ad = exp(&wd).matrix.map(|e| e.eps);
        let fd = (exp(&(w + d * h)).matrix - exp(&(w - d * h)).matrix) / (2.0 * h);
        assert!(maxabs(&(ad - fd)) <= 1e-8);
        let r = exp(&w);
        let rd = SO3::from_matrix_unchecked(
            r.matrix.map(Dual64::from) + hat(&d).map(|e| Dual64::new(0.0, e)) * r.matrix.map(Dual64::from),
        );
        let ad = log(&rd).expect("ok").map(|e| e.eps);
        let rp = SO3::from_matrix_unchecked(r.matrix + hat(&d) * r.matrix * h);
        let rm = SO3::from_matrix_unchecked(r.matrix - hat(&d) * r.matrix * h);
        let fd = (log(&rp).expect("ok") - log(&rm).expect("ok")) / (2.0 * h);
        assert!((ad - fd).norm() <= 1e-8);
        // log of a slightly non-orthogonal matrix still differentiates through the
        // quaternion; the first-order direction is dexp⁻¹ δ.
        assert!((ad - dexp_inv(&w) * d).norm() <= 1e-13);
    }

    /// Long products drift from orthogonality only at round-off level, and
    /// `renormalize` restores it to a few ε.
    #[test]
    fn orthogonality_after_compositions() {
        let steps = [
            Vector3::new(0.3, -0.2, 0.9),
            Vector3::new(-1.1, 0.4, 0.05),
            Vector3::new(0.7, 2.0, -0.6),
        ];
        let mut r = SO3::identity();
        for i in 0..10 {
            r = r * exp(&steps[i % 3]) * cay(&steps[(i + 1) % 3]);
        }
        // Each product adds O(ε) defect: 20 products, measured ≈ 1e-15.
        assert!(maxabs(&(r.matrix.transpose() * r.matrix - Matrix3::identity())) <= 20.0 * EPS);
        for i in 0..10_000 {
            r = r * exp(&steps[i % 3]);
        }
        let drift = maxabs(&(r.matrix.transpose() * r.matrix - Matrix3::identity()));
        assert!(drift <= 1e-12, "drift {drift}");
        let rn = r.renormalize();
        assert!(maxabs(&(rn.matrix.transpose() * rn.matrix - Matrix3::identity())) <= 1e-15);
        assert!(maxabs(&(rn.matrix - r.matrix)) <= 2.0 * drift + 4.0 * EPS);
    }

    #[test]
    fn checked_constructors() {
        let r = exp(&Vector3::new(0.1, 0.2, 0.3));
        assert!(SO3::from_matrix(*r.matrix()).is_ok());
        assert!(matches!(
            SO3::from_matrix(r.matrix * 1.01),
            Err(LieError::NotARotation { .. })
        ));
        assert!(matches!(
            SO3::from_matrix(-r.matrix),
            Err(LieError::NotARotation { .. })
        ));
        assert!(matches!(
            SO3::<f64>::from_quaternion(&Quaternion::new(0.0, 0.0, 0.0, 0.0)),
            Err(LieError::ZeroQuaternion { .. })
        ));
        // Cayley matches its defining matrix expression (I − ω̂/2)⁻¹(I + ω̂/2).
        let w = Vector3::new(1.5, -0.3, 2.2);
        let h = hat(&w) * 0.5;
        let m = (Matrix3::identity() - h).try_inverse().expect("invertible") * (Matrix3::identity() + h);
        assert!(maxabs(&(m - cay(&w).matrix)) <= 8.0 * EPS);
    }
}
