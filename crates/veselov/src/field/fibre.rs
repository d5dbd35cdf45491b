//! Fibres: the value space Y_v of a discrete field at a vertex (note 003
//! §1.6), with a chart y·τ(ξ) around every point, so that variations,
//! covectors and Newton updates live in ℝ^M in a fixed trivialisation.
//!
//! * [`Euclidean<M>`]: ℝ^M, chart y + ξ.
//! * [`Rotations`] (SO(3)): chart R·exp(ξ̂), left trivialisation (note 003
//!   §2.6); its [`Fibre::log`] is the Riemannian logarithm of the halved
//!   Frobenius metric, log(RᵀS).
//! * [`RigidMotions`] (SE(3), algebra (ω; v)): chart g·exp(ξ) (the group
//!   exponential; seed 000's fields).
//! * [`PositionRotation`] (ℝ³ × SO(3), the Cosserat rod's fibre, note 003
//!   §3.1): tangent ordered (a; b), chart (r + a, R·exp(b̂)) — the Euclidean
//!   part is *not* rotated, so ∇_r is the Euclidean gradient and ∇_R the
//!   left-trivialised one, as in note 003 §3.5.
//!
//! The gradient of a function f at y in this chart, ∇f(y)ᵢ = d/dε f(y·τ(ε eᵢ)),
//! is what every cell gradient, Euler–Lagrange residual and Noether pairing
//! of the core uses.

use std::fmt::Debug;

use nalgebra::{Matrix3, SVector, Vector3};

use crate::ad::{Scalar, const_mat3_mul, const_mat3_vec};
use crate::lie::{LieError, SE3, SO3, se3, so3};

/// The value space at a vertex, of dimension `M`, with a chart around each point.
pub trait Fibre<const M: usize>: Copy + Debug + Send + Sync + 'static {
    /// A point of the fibre with scalars of type `D`.
    type Point<D: Scalar>: Copy + Debug;

    /// Short name for messages and outputs (`"R^m"`, `"SO(3)"`, …).
    const NAME: &'static str;

    /// Number of `f64` coordinates a point is written with ([`Fibre::write`]).
    const COORDINATES: usize;

    /// The point with every scalar mapped by `f` (for example lifted into
    /// dual numbers).
    fn map<D: Scalar, E: Scalar>(y: &Self::Point<D>, f: impl Fn(D) -> E + Copy) -> Self::Point<E>;

    /// Lift an `f64` point into constants of the scalar type `D`.
    fn lift<D: Scalar>(y: &Self::Point<f64>) -> Self::Point<D> {
        Self::map(y, D::from)
    }

    /// The chart y·τ(ξ).
    fn retract<D: Scalar>(y: &Self::Point<D>, xi: &SVector<D, M>) -> Self::Point<D>;

    /// The chart y·τ(ξ) at a constant point y for a ξ whose entries are
    /// nilpotent of order 3 (every product of three of them vanishes): the
    /// seeded directions of [`crate::field::cell::vertex_gradient`] and
    /// [`crate::field::cell::mixed_block`], one or two levels of dual numbers
    /// with zero real part. It equals `retract(&lift(y), xi)` in that
    /// arithmetic; a fibre may compute it from τ's series truncated after
    /// the quadratic term and with y's `f64` entries (the default does not).
    fn retract_seeded<D: Scalar>(y: &Self::Point<f64>, xi: &SVector<D, M>) -> Self::Point<D> {
        Self::retract(&Self::lift(y), xi)
    }

    /// Its inverse: the ξ with z = y·τ(ξ), |ξ| within the injectivity radius
    /// (errors near the cut locus of a rotation part).
    fn log<D: Scalar>(y: &Self::Point<D>, z: &Self::Point<D>) -> Result<SVector<D, M>, LieError>;

    /// The linear extrapolation z = y·τ(log(x, y)) of the step from x to y
    /// (the Cauchy integrator's first guess for the next value along the
    /// flow); y itself where the logarithm fails. A fibre whose chart is a
    /// group's exponential may compute it as y·x⁻¹·y, the same point without
    /// the logarithm and the exponential.
    fn extrapolate(x: &Self::Point<f64>, y: &Self::Point<f64>) -> Self::Point<f64> {
        match Self::log(x, y) {
            Ok(xi) => Self::retract(y, &xi),
            Err(_) => *y,
        }
    }

    /// Project a point that has drifted from the fibre (a rotation that is no
    /// longer orthogonal to round-off) back onto it; identity on ℝ^M.
    fn renormalize(y: &Self::Point<f64>) -> Self::Point<f64>;

    /// Whether every coordinate of the point is finite.
    fn is_finite(y: &Self::Point<f64>) -> bool {
        let mut c = [0.0; 16];
        Self::write(y, &mut c[..Self::COORDINATES]);
        c[..Self::COORDINATES].iter().all(|x| x.is_finite())
    }

    /// The point's coordinates (ℝ^M: the vector; SO(3): the 9 entries of R
    /// row by row; SE(3) and ℝ³ × SO(3): R's 9 entries, then the position).
    fn write(y: &Self::Point<f64>, out: &mut [f64]);

    /// The point with the coordinates [`write`](Self::write) gave, exactly
    /// (no projection: a checkpoint restores bit for bit).
    fn read(c: &[f64]) -> Self::Point<f64>;
}

/// `count` points of the fibre `F` read from checkpoint words (each its
/// [`Fibre::COORDINATES`] coordinates, as [`Fibre::write`] gave them). A
/// field value is finite: a non-finite one is refused, `describe(i)` naming
/// the i-th point, rather than surfacing later as a failed solve far from
/// its cause.
///
/// # Errors
/// [`Error::InvalidParameter`](crate::Error::InvalidParameter)
/// (`checkpoint`) if the words run out or a point is not finite.
pub(crate) fn read_points<F: Fibre<M>, const M: usize>(
    words: &mut crate::run::Words<'_>,
    count: usize,
    describe: impl Fn(usize) -> String,
) -> crate::Result<Vec<F::Point<f64>>> {
    let mut c = [0.0; 16];
    let k = F::COORDINATES.min(c.len());
    let mut points = Vec::with_capacity(count);
    for i in 0..count {
        words.fill(&mut c[..k])?;
        let point = F::read(&c[..k]);
        if !F::is_finite(&point) {
            return Err(crate::Error::InvalidParameter {
                name: "checkpoint".into(),
                value: format!("{:?}", &c[..k]),
                reason: format!("non-finite value of {}", describe(i)),
            });
        }
        points.push(point);
    }
    Ok(points)
}

/// ℝ^M with the chart y + ξ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Euclidean<const M: usize>;

impl<const M: usize> Fibre<M> for Euclidean<M> {
    type Point<D: Scalar> = SVector<D, M>;
    const NAME: &'static str = "R^m";
    const COORDINATES: usize = M;

    fn map<D: Scalar, E: Scalar>(y: &SVector<D, M>, f: impl Fn(D) -> E + Copy) -> SVector<E, M> {
        y.map(f)
    }
    fn retract<D: Scalar>(y: &SVector<D, M>, xi: &SVector<D, M>) -> SVector<D, M> {
        y + xi
    }
    fn log<D: Scalar>(y: &SVector<D, M>, z: &SVector<D, M>) -> Result<SVector<D, M>, LieError> {
        Ok(z - y)
    }
    fn renormalize(y: &SVector<f64, M>) -> SVector<f64, M> {
        *y
    }
    fn is_finite(y: &SVector<f64, M>) -> bool {
        y.iter().all(|x| x.is_finite())
    }
    fn write(y: &SVector<f64, M>, out: &mut [f64]) {
        out[..M].copy_from_slice(y.as_slice());
    }
    fn read(c: &[f64]) -> SVector<f64, M> {
        SVector::from_fn(|i, _| c[i])
    }
}

/// SO(3) with the chart R·exp(ξ̂).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rotations;

fn read_rotation(c: &[f64]) -> SO3<f64> {
    SO3::from_matrix_unchecked(Matrix3::from_fn(|i, j| c[3 * i + j]))
}

fn write_rotation(r: &Matrix3<f64>, out: &mut [f64]) {
    for i in 0..3 {
        for j in 0..3 {
            out[3 * i + j] = r[(i, j)];
        }
    }
}

/// One Newton–Schulz step towards the nearest rotation (polar factor).
fn newton_schulz(r: &Matrix3<f64>) -> Matrix3<f64> {
    r * (Matrix3::identity() * 3.0 - r.transpose() * r) * 0.5
}

/// R·exp(ω̂) = R(I + ω̂ + ½ω̂²) for a constant R and an ω whose entries are
/// nilpotent of order 3 ([`Fibre::retract_seeded`]), with ω̂² = ωωᵀ − |ω|²I
/// written out and R's `f64` entries scaling the dual ones.
fn seeded_rotation<D: Scalar>(r: &Matrix3<f64>, w: &Vector3<D>) -> SO3<D> {
    let e = so3::unit_hat_series(w, D::from(0.5));
    SO3::from_matrix_unchecked(const_mat3_mul(r, &e))
}

impl Fibre<3> for Rotations {
    type Point<D: Scalar> = SO3<D>;
    const NAME: &'static str = "SO(3)";
    const COORDINATES: usize = 9;

    fn map<D: Scalar, E: Scalar>(y: &SO3<D>, f: impl Fn(D) -> E + Copy) -> SO3<E> {
        SO3::from_matrix_unchecked(y.matrix().map(f))
    }
    fn retract<D: Scalar>(y: &SO3<D>, xi: &SVector<D, 3>) -> SO3<D> {
        y.compose(&so3::exp(xi))
    }
    fn retract_seeded<D: Scalar>(y: &SO3<f64>, xi: &SVector<D, 3>) -> SO3<D> {
        seeded_rotation(y.matrix(), xi)
    }
    #[inline]
    fn log<D: Scalar>(y: &SO3<D>, z: &SO3<D>) -> Result<SVector<D, 3>, LieError> {
        so3::log(&y.between(z))
    }
    /// R_y R_xᵀ R_y = R_y exp(log(R_xᵀR_y)).
    fn extrapolate(x: &SO3<f64>, y: &SO3<f64>) -> SO3<f64> {
        SO3::from_matrix_unchecked(y.matrix() * (x.matrix().transpose() * y.matrix()))
    }
    fn renormalize(y: &SO3<f64>) -> SO3<f64> {
        SO3::from_matrix_unchecked(newton_schulz(y.matrix()))
    }
    fn write(y: &SO3<f64>, out: &mut [f64]) {
        write_rotation(y.matrix(), out);
    }
    fn read(c: &[f64]) -> SO3<f64> {
        read_rotation(c)
    }
}

/// SE(3) (algebra ordered (ω; v)) with the chart g·exp(ξ).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct RigidMotions;

impl Fibre<6> for RigidMotions {
    type Point<D: Scalar> = SE3<D>;
    const NAME: &'static str = "SE(3)";
    const COORDINATES: usize = 12;

    fn map<D: Scalar, E: Scalar>(y: &SE3<D>, f: impl Fn(D) -> E + Copy) -> SE3<E> {
        SE3::new(Rotations::map(y.rotation(), f), y.translation().map(f))
    }
    fn retract<D: Scalar>(y: &SE3<D>, xi: &SVector<D, 6>) -> SE3<D> {
        y.compose(&se3::exp(xi))
    }
    /// exp(ξ) = (I + ω̂ + ½ω̂², v + ½ω̂v) when products of three entries of
    /// ξ = (ω; v) vanish, composed with y's `f64` rotation and translation.
    fn retract_seeded<D: Scalar>(y: &SE3<f64>, xi: &SVector<D, 6>) -> SE3<D> {
        let (w, v) = se3::split(xi);
        let ry = y.rotation().matrix();
        let e_t = v + w.cross(&v) * D::from(0.5);
        let moved = const_mat3_vec(ry, &e_t);
        let translation = Vector3::from_fn(|i, _| moved[i] + y.translation()[i]);
        SE3::new(seeded_rotation(ry, &w), translation)
    }
    fn log<D: Scalar>(y: &SE3<D>, z: &SE3<D>) -> Result<SVector<D, 6>, LieError> {
        se3::log(&y.between(z))
    }
    /// g_y g_x⁻¹ g_y = g_y exp(log(g_x⁻¹g_y)).
    fn extrapolate(x: &SE3<f64>, y: &SE3<f64>) -> SE3<f64> {
        y.compose(&x.between(y))
    }
    fn renormalize(y: &SE3<f64>) -> SE3<f64> {
        SE3::new(Rotations::renormalize(y.rotation()), *y.translation())
    }
    fn write(y: &SE3<f64>, out: &mut [f64]) {
        write_rotation(y.rotation().matrix(), out);
        out[9..12].copy_from_slice(y.translation().as_slice());
    }
    fn read(c: &[f64]) -> SE3<f64> {
        SE3::new(read_rotation(c), Vector3::new(c[9], c[10], c[11]))
    }
}

/// A point (r, R) of ℝ³ × SO(3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<D> {
    /// Position r.
    pub position: Vector3<D>,
    /// Frame R.
    pub rotation: SO3<D>,
}

impl<D: Scalar> Pose<D> {
    /// The pose (r, R).
    pub fn new(position: Vector3<D>, rotation: SO3<D>) -> Self {
        Self { position, rotation }
    }
}

/// ℝ³ × SO(3) (tangent ordered (a; b): position, then rotation) with the
/// chart (r + a, R·exp(b̂)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PositionRotation;

impl Fibre<6> for PositionRotation {
    type Point<D: Scalar> = Pose<D>;
    const NAME: &'static str = "R^3 x SO(3)";
    const COORDINATES: usize = 12;

    fn map<D: Scalar, E: Scalar>(y: &Pose<D>, f: impl Fn(D) -> E + Copy) -> Pose<E> {
        Pose::new(y.position.map(f), Rotations::map(&y.rotation, f))
    }
    fn retract<D: Scalar>(y: &Pose<D>, xi: &SVector<D, 6>) -> Pose<D> {
        let a = Vector3::new(xi[0], xi[1], xi[2]);
        let b = Vector3::new(xi[3], xi[4], xi[5]);
        Pose::new(y.position + a, Rotations::retract(&y.rotation, &b))
    }
    fn retract_seeded<D: Scalar>(y: &Pose<f64>, xi: &SVector<D, 6>) -> Pose<D> {
        let a = Vector3::from_fn(|i, _| xi[i] + y.position[i]);
        let b = Vector3::new(xi[3], xi[4], xi[5]);
        Pose::new(a, Rotations::retract_seeded(&y.rotation, &b))
    }
    fn log<D: Scalar>(y: &Pose<D>, z: &Pose<D>) -> Result<SVector<D, 6>, LieError> {
        let a = z.position - y.position;
        let b = Rotations::log(&y.rotation, &z.rotation)?;
        Ok(SVector::<D, 6>::new(a[0], a[1], a[2], b[0], b[1], b[2]))
    }
    /// (2r_y − r_x, R_y R_xᵀ R_y), as [`Rotations::extrapolate`].
    fn extrapolate(x: &Pose<f64>, y: &Pose<f64>) -> Pose<f64> {
        Pose::new(
            y.position * 2.0 - x.position,
            Rotations::extrapolate(&x.rotation, &y.rotation),
        )
    }
    fn renormalize(y: &Pose<f64>) -> Pose<f64> {
        Pose::new(y.position, Rotations::renormalize(&y.rotation))
    }
    fn write(y: &Pose<f64>, out: &mut [f64]) {
        write_rotation(y.rotation.matrix(), out);
        out[9..12].copy_from_slice(y.position.as_slice());
    }
    fn read(c: &[f64]) -> Pose<f64> {
        Pose::new(Vector3::new(c[9], c[10], c[11]), read_rotation(c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip<F: Fibre<M>, const M: usize>(y: F::Point<f64>, xi: SVector<f64, M>) {
        let z = F::retract(&y, &xi);
        let back = F::log(&y, &z).expect("inside the injectivity radius");
        assert!(
            (back - xi).norm() < 1e-14,
            "{} chart round trip: {back} vs {xi}",
            F::NAME
        );
    }

    #[test]
    fn charts_invert() {
        let r = so3::exp(&Vector3::new(0.3, -1.1, 0.7));
        round_trip::<Euclidean<2>, 2>(SVector::from([1.0, -2.0]), SVector::from([0.25, 0.5]));
        round_trip::<Rotations, 3>(r, Vector3::new(0.2, 0.1, -0.4));
        round_trip::<RigidMotions, 6>(
            SE3::new(r, Vector3::new(1.0, 2.0, 3.0)),
            SVector::from([0.1, -0.2, 0.3, 0.5, 0.4, -0.6]),
        );
        round_trip::<PositionRotation, 6>(
            Pose::new(Vector3::new(1.0, 2.0, 3.0), r),
            SVector::from([0.1, -0.2, 0.3, 0.5, 0.4, -0.6]),
        );
    }

    /// The group extrapolations y·x⁻¹·y equal the chart's y·τ(log(x, y)).
    #[test]
    fn extrapolation_is_the_chart_step_repeated() {
        let x = Pose::new(Vector3::new(1.0, 2.0, 3.0), so3::exp(&Vector3::new(0.3, -1.1, 0.7)));
        let y = Pose::new(Vector3::new(0.5, 2.5, 2.0), so3::exp(&Vector3::new(0.9, -0.4, 1.2)));
        let chart = PositionRotation::retract(&y, &PositionRotation::log(&x, &y).expect("inside the cut locus"));
        let group = PositionRotation::extrapolate(&x, &y);
        assert!((chart.position - group.position).amax() < 1e-15);
        assert!((chart.rotation.matrix() - group.rotation.matrix()).amax() < 1e-14);
        let r = Rotations::extrapolate(&x.rotation, &y.rotation);
        assert_eq!(r.matrix(), group.rotation.matrix());
        let (gx, gy) = (SE3::new(x.rotation, x.position), SE3::new(y.rotation, y.position));
        let chart = RigidMotions::retract(&gy, &RigidMotions::log(&gx, &gy).expect("inside the cut locus"));
        let group = RigidMotions::extrapolate(&gx, &gy);
        assert!((chart.rotation().matrix() - group.rotation().matrix()).amax() < 1e-14);
        assert!((chart.translation() - group.translation()).amax() < 1e-14);
    }

    type Outer<const M: usize> = num_dual::DualSVec<num_dual::DualSVec64<M>, M>;

    fn flat1<const M: usize>(x: &num_dual::DualSVec64<M>) -> Vec<f64> {
        let mut v = vec![x.re];
        v.extend(x.eps.unwrap_generic(nalgebra::Const::<M>, nalgebra::U1).iter());
        v
    }

    fn flat2<const M: usize>(x: &Outer<M>) -> Vec<f64> {
        let mut v = flat1(&x.re);
        match &x.eps {
            num_dual::Derivative(Some(e)) => e.iter().for_each(|d| v.extend(flat1(d))),
            num_dual::Derivative(None) => v.extend(vec![0.0; M * (M + 1)]),
        }
        v
    }

    /// The truncated chart equals the full one on seeded directions:
    /// first-order duals, and two nested levels with both present (so that
    /// the quadratic term of the series is exercised). `entries` lists a
    /// point's matrix and vector entries.
    fn seeded_chart_is_the_chart<F: Fibre<M>, const M: usize>(
        y: F::Point<f64>,
        entries1: impl Fn(&F::Point<num_dual::DualSVec64<M>>) -> Vec<num_dual::DualSVec64<M>>,
        entries2: impl Fn(&F::Point<Outer<M>>) -> Vec<Outer<M>>,
    ) {
        use crate::field::cell::seeds;
        let close = |u: Vec<f64>, v: Vec<f64>| u.iter().zip(&v).all(|(p, q)| (p - q).abs() < 1e-15 * (1.0 + q.abs()));
        let first = seeds::<f64, M>();
        let a = entries1(&F::retract_seeded(&y, &first));
        let b = entries1(&F::retract(&F::lift(&y), &first));
        assert!(
            a.iter().zip(&b).all(|(p, q)| close(flat1(p), flat1(q))),
            "{}: first order",
            F::NAME
        );
        let xi: SVector<Outer<M>, M> =
            seeds::<f64, M>().map(Outer::<M>::from_re) + seeds::<num_dual::DualSVec64<M>, M>();
        let a: Vec<f64> = entries2(&F::retract_seeded(&y, &xi)).iter().flat_map(flat2).collect();
        let b: Vec<f64> = entries2(&F::retract(&F::lift(&y), &xi))
            .iter()
            .flat_map(flat2)
            .collect();
        // Mixed second derivatives: entries M + 1 + j(M + 1) + 1 .. of each flattened number.
        let per = (M + 1) * (M + 1);
        let second = b
            .chunks(per)
            .flat_map(|c| (0..M).flat_map(move |j| c[(j + 1) * (M + 1) + 1..(j + 2) * (M + 1)].to_vec()))
            .filter(|x| x.abs() > 1e-3)
            .count();
        assert!(second >= M, "{}: second order present ({second})", F::NAME);
        assert!(close(a, b), "{}: second order", F::NAME);
    }

    #[test]
    fn seeded_charts_are_the_charts() {
        let r = so3::exp(&Vector3::new(0.3, -1.1, 0.7));
        let t = Vector3::new(1.0, -2.0, 3.0);
        seeded_chart_is_the_chart::<Rotations, 3>(
            r,
            |p| p.matrix().iter().copied().collect(),
            |p| p.matrix().iter().copied().collect(),
        );
        seeded_chart_is_the_chart::<RigidMotions, 6>(
            SE3::new(r, t),
            |p| {
                p.rotation()
                    .matrix()
                    .iter()
                    .chain(p.translation().iter())
                    .copied()
                    .collect()
            },
            |p| {
                p.rotation()
                    .matrix()
                    .iter()
                    .chain(p.translation().iter())
                    .copied()
                    .collect()
            },
        );
        seeded_chart_is_the_chart::<PositionRotation, 6>(
            Pose::new(t, r),
            |p| p.rotation.matrix().iter().chain(p.position.iter()).copied().collect(),
            |p| p.rotation.matrix().iter().chain(p.position.iter()).copied().collect(),
        );
    }

    #[test]
    fn coordinates_are_written_and_checked() {
        let y = Pose::new(Vector3::new(1.0, f64::NAN, 3.0), SO3::identity());
        assert!(!PositionRotation::is_finite(&y));
        let mut out = [0.0; 12];
        PositionRotation::write(&Pose::new(Vector3::new(1.0, 2.0, 3.0), SO3::identity()), &mut out);
        assert_eq!(out, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 3.0]);
    }
}
