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

use crate::ad::Scalar;
use crate::lie::{LieError, SE3, SO3, se3, so3};

/// The value space at a vertex, of dimension `M`, with a chart around each point.
pub trait Fibre<const M: usize>: Copy + Debug + Send + Sync + 'static {
    /// A point of the fibre with scalars of type `D`.
    type Point<D: Scalar>: Copy + Debug;

    /// Short name for messages and outputs (`"R^m"`, `"SO(3)"`, …).
    const NAME: &'static str;

    /// Number of `f64` coordinates a point is written with ([`Fibre::write`]).
    const COORDINATES: usize;

    /// Lift an `f64` point into constants of the scalar type `D`.
    fn lift<D: Scalar>(y: &Self::Point<f64>) -> Self::Point<D>;

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

/// ℝ^M with the chart y + ξ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Euclidean<const M: usize>;

impl<const M: usize> Fibre<M> for Euclidean<M> {
    type Point<D: Scalar> = SVector<D, M>;
    const NAME: &'static str = "R^m";
    const COORDINATES: usize = M;

    fn lift<D: Scalar>(y: &SVector<f64, M>) -> SVector<D, M> {
        y.map(D::from)
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

impl Fibre<3> for Rotations {
    type Point<D: Scalar> = SO3<D>;
    const NAME: &'static str = "SO(3)";
    const COORDINATES: usize = 9;

    fn lift<D: Scalar>(y: &SO3<f64>) -> SO3<D> {
        SO3::from_matrix_unchecked(y.matrix().map(D::from))
    }
    fn retract<D: Scalar>(y: &SO3<D>, xi: &SVector<D, 3>) -> SO3<D> {
        y.compose(&so3::exp(xi))
    }
    fn log<D: Scalar>(y: &SO3<D>, z: &SO3<D>) -> Result<SVector<D, 3>, LieError> {
        so3::log(&y.inverse().compose(z))
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

    fn lift<D: Scalar>(y: &SE3<f64>) -> SE3<D> {
        SE3::new(Rotations::lift(y.rotation()), y.translation().map(D::from))
    }
    fn retract<D: Scalar>(y: &SE3<D>, xi: &SVector<D, 6>) -> SE3<D> {
        y.compose(&se3::exp(xi))
    }
    /// exp(ξ) = (I + ω̂ + ½ω̂², v + ½ω̂v) when products of three entries of
    /// ξ = (ω; v) vanish, composed with y's `f64` rotation and translation.
    fn retract_seeded<D: Scalar>(y: &SE3<f64>, xi: &SVector<D, 6>) -> SE3<D> {
        let (w, v) = se3::split(xi);
        let wh = so3::hat(&w);
        let half = D::from(0.5);
        // ω̂² = ωωᵀ − |ω|²I, and ω̂v = ω × v, written out (fewer products).
        let n2 = w.dot(&w);
        let e_rot = Matrix3::from_fn(|i, j| {
            let quadratic = if i == j { w[i] * w[j] - n2 } else { w[i] * w[j] };
            let diagonal = if i == j { D::from(1.0) } else { D::from(0.0) };
            diagonal + wh[(i, j)] + quadratic * half
        });
        let e_t = v + w.cross(&v) * half;
        let (ry, ty) = (y.rotation().matrix(), y.translation());
        let rotation = Matrix3::from_fn(|i, j| {
            e_rot[(0, j)] * ry[(i, 0)] + e_rot[(1, j)] * ry[(i, 1)] + e_rot[(2, j)] * ry[(i, 2)]
        });
        let translation =
            Vector3::from_fn(|i, _| e_t[0] * ry[(i, 0)] + e_t[1] * ry[(i, 1)] + e_t[2] * ry[(i, 2)] + ty[i]);
        SE3::new(SO3::from_matrix_unchecked(rotation), translation)
    }
    fn log<D: Scalar>(y: &SE3<D>, z: &SE3<D>) -> Result<SVector<D, 6>, LieError> {
        se3::log(&y.inverse().compose(z))
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

    fn lift<D: Scalar>(y: &Pose<f64>) -> Pose<D> {
        Pose::new(y.position.map(D::from), Rotations::lift(&y.rotation))
    }
    fn retract<D: Scalar>(y: &Pose<D>, xi: &SVector<D, 6>) -> Pose<D> {
        let a = Vector3::new(xi[0], xi[1], xi[2]);
        let b = Vector3::new(xi[3], xi[4], xi[5]);
        Pose::new(y.position + a, Rotations::retract(&y.rotation, &b))
    }
    fn log<D: Scalar>(y: &Pose<D>, z: &Pose<D>) -> Result<SVector<D, 6>, LieError> {
        let a = z.position - y.position;
        let b = Rotations::log(&y.rotation, &z.rotation)?;
        Ok(SVector::<D, 6>::new(a[0], a[1], a[2], b[0], b[1], b[2]))
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

    /// The truncated chart of SE(3) equals the full one on seeded directions:
    /// first-order duals and two nested levels with both levels present (so
    /// that the quadratic term of the series is exercised).
    #[test]
    fn seeded_chart_of_rigid_motions_is_the_chart() {
        use crate::field::cell::seeds;
        use nalgebra::{Const, U1};
        use num_dual::{Derivative, DualSVec, DualSVec64};
        type Outer = DualSVec<DualSVec64<6>, 6>;
        let y = SE3::new(so3::exp(&Vector3::new(0.3, -1.1, 0.7)), Vector3::new(1.0, -2.0, 3.0));
        let first = seeds::<f64, 6>();
        let (a, b) = (
            RigidMotions::retract_seeded(&y, &first),
            RigidMotions::retract(&RigidMotions::lift(&y), &first),
        );
        let flat1 = |p: &SE3<DualSVec64<6>>| -> Vec<f64> {
            let m = p.rotation().matrix().iter().chain(p.translation().iter());
            m.flat_map(|x| {
                let mut v = vec![x.re];
                v.extend(x.eps.unwrap_generic(Const::<6>, U1).iter());
                v
            })
            .collect()
        };
        let close = |u: Vec<f64>, v: Vec<f64>| u.iter().zip(&v).all(|(p, q)| (p - q).abs() < 1e-15 * (1.0 + q.abs()));
        assert!(close(flat1(&a), flat1(&b)));
        let xi: SVector<Outer, 6> = seeds::<f64, 6>().map(Outer::from_re) + seeds::<DualSVec64<6>, 6>();
        let (a, b) = (
            RigidMotions::retract_seeded(&y, &xi),
            RigidMotions::retract(&RigidMotions::lift(&y), &xi),
        );
        let flat2 = |p: &SE3<Outer>| -> Vec<f64> {
            let m = p.rotation().matrix().iter().chain(p.translation().iter());
            m.flat_map(|x| {
                let mut v = vec![x.re.re];
                v.extend(x.re.eps.unwrap_generic(Const::<6>, U1).iter());
                match &x.eps {
                    Derivative(Some(e)) => {
                        for d in e.iter() {
                            v.push(d.re);
                            v.extend(d.eps.unwrap_generic(Const::<6>, U1).iter());
                        }
                    }
                    Derivative(None) => v.extend([0.0; 42]),
                }
                v
            })
            .collect()
        };
        let (fa, fb) = (flat2(&a), flat2(&b));
        assert!(
            fb.iter().filter(|x| x.abs() > 1e-3).count() > 100,
            "second-order terms present"
        );
        assert!(close(fa, fb));
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
