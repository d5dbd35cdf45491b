//! The Lagrangian interface and what is derived from it exactly.
//!
//! A system on `Rⁿ` is a function `L(t, q, v)` written once, generic over the
//! AD scalar. From it (Marsden & West 2001, §1.2; seed 004 §2):
//! - momentum `p = ∂L/∂v`,
//! - energy `E = v·∂L/∂v − L`,
//! - the Euler–Lagrange acceleration from `d/dt ∂L/∂v = ∂L/∂q`, i.e.
//!   `W a = ∂L/∂q − (∂²L/∂v∂q) v − ∂²L/∂v∂t`, `W = ∂²L/∂v²`,
//! - the Legendre map both ways (velocity from momentum by Newton on `∂L/∂v = p`).

use nalgebra::{SMatrix, SVector, U1};
use num_dual::{Dual2SVec64, DualSVec64, HyperDualSVec64, partial_hessian};

use super::force::{Force, NoForce};
use crate::ad::{Scalar, lift};
use crate::error::{Error, Result, check_finite};
use crate::solve::dense::solve_small;

/// A Lagrangian system on `Rᴺ`: `L(t, q, v)`, generic over the AD scalar.
///
/// ```
/// use nalgebra::SVector;
/// use veselov::{ad::Scalar, mechanics::Lagrangian};
/// struct Oscillator;
/// impl Lagrangian<1> for Oscillator {
///     fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 1>, v: &SVector<D, 1>) -> D {
///         (v[0] * v[0] - q[0] * q[0]) * 0.5
///     }
/// }
/// ```
pub trait Lagrangian<const N: usize> {
    /// The Lagrangian `L(t, q, v)`.
    fn lagrangian<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D;

    /// `Some(M)` when `L = ½ vᵀMv − V(t, q)` with a constant mass matrix `M`
    /// (then `V(t, q) = −L(t, q, 0)`), so that an integrator may use formulas
    /// that evaluate only `V` and its derivatives. An implementation that
    /// returns `Some` promises this form; the default `None` selects the
    /// general formulas, which are right for every `L`.
    fn constant_mass(&self) -> Option<SMatrix<f64, N, N>> {
        None
    }

    /// `V(t, q) = −L(t, q, 0)`, the potential of a Lagrangian with
    /// [`Lagrangian::constant_mass`]; an implementation may give it directly
    /// (the default evaluates `L` at zero velocity).
    fn potential_energy<D: Scalar>(&self, t: D, q: &SVector<D, N>) -> D {
        -self.lagrangian(t, q, &SVector::zeros())
    }
}

impl<const N: usize, L: Lagrangian<N>> Lagrangian<N> for &L {
    fn lagrangian<D: Scalar>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        (**self).lagrangian(t, q, v)
    }
    fn constant_mass(&self) -> Option<SMatrix<f64, N, N>> {
        (**self).constant_mass()
    }
    fn potential_energy<D: Scalar>(&self, t: D, q: &SVector<D, N>) -> D {
        (**self).potential_energy(t, q)
    }
}

/// Value and first derivatives of `L` at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet<const N: usize> {
    /// `L`.
    pub value: f64,
    /// `∂L/∂q`.
    pub dq: SVector<f64, N>,
    /// `∂L/∂v`.
    pub dv: SVector<f64, N>,
}

/// First and second derivatives of `L` at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hessian<const N: usize> {
    /// Value and gradient.
    pub jet: Jet<N>,
    /// `∂²L/∂q∂q`.
    pub qq: SMatrix<f64, N, N>,
    /// `qv[(i, j)] = ∂²L/∂qᵢ∂vⱼ`.
    pub qv: SMatrix<f64, N, N>,
    /// `∂²L/∂v∂v`.
    pub vv: SMatrix<f64, N, N>,
}

/// `V(t, q)` ([`Lagrangian::potential_energy`]) and `∇V`, exact (one
/// forward-mode pass over `V` alone).
#[inline]
pub(crate) fn potential_gradient<const N: usize, L: Lagrangian<N>>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
) -> (f64, SVector<f64, N>) {
    num_dual::gradient(
        |qd: SVector<DualSVec64<N>, N>| l.potential_energy(DualSVec64::<N>::from(t), &qd),
        q,
    )
}

/// `V(t, q)`, `∇V` and `∇²V`, exact (one second-order pass over `V` alone).
pub(crate) fn potential_hessian<const N: usize, L: Lagrangian<N>>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
) -> (f64, SVector<f64, N>, SMatrix<f64, N, N>) {
    num_dual::hessian(
        |qd: SVector<Dual2SVec64<N>, N>| l.potential_energy(Dual2SVec64::<N>::from(t), &qd),
        q,
    )
}

/// `L` and its gradient in `q` and `v`, exact (two forward-mode passes; one
/// pass of `V` alone when `L = ½vᵀMv − V` is declared by
/// [`Lagrangian::constant_mass`]: then `∂L/∂v = Mv`, `∂L/∂q = −∇V`).
#[inline]
pub fn jet<const N: usize, L: Lagrangian<N>>(l: &L, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> Jet<N> {
    if let Some(mass) = l.constant_mass() {
        let (potential, gradient) = potential_gradient(l, t, q);
        let momentum = mass * v;
        return Jet {
            value: 0.5 * v.dot(&momentum) - potential,
            dq: -gradient,
            dv: momentum,
        };
    }
    let td = DualSVec64::<N>::from(t);
    let qc: SVector<DualSVec64<N>, N> = lift(q);
    let vc: SVector<DualSVec64<N>, N> = lift(v);
    let qd = SVector::<DualSVec64<N>, N>::from_fn(|i, _| DualSVec64::<N>::from(q[i]).derivative(i));
    let vd = SVector::<DualSVec64<N>, N>::from_fn(|i, _| DualSVec64::<N>::from(v[i]).derivative(i));
    let a = l.lagrangian(td, &qd, &vc);
    let b = l.lagrangian(td, &qc, &vd);
    Jet {
        value: a.re,
        dq: a.eps.unwrap_generic(nalgebra::Const::<N>, U1),
        dv: b.eps.unwrap_generic(nalgebra::Const::<N>, U1),
    }
}

/// `L`, its gradient and all second derivatives in `(q, v)`, exact (three
/// passes; one second-order pass of `V` alone when `L = ½vᵀMv − V` is
/// declared by [`Lagrangian::constant_mass`]: then `∂²L/∂v² = M`,
/// `∂²L/∂q∂v = 0`, `∂²L/∂q² = −∇²V`).
pub fn hessian<const N: usize, L: Lagrangian<N>>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> Hessian<N> {
    if let Some(mass) = l.constant_mass() {
        let (potential, gradient, curvature) = potential_hessian(l, t, q);
        let momentum = mass * v;
        return Hessian {
            jet: Jet {
                value: 0.5 * v.dot(&momentum) - potential,
                dq: -gradient,
                dv: momentum,
            },
            qq: -curvature,
            qv: SMatrix::zeros(),
            vv: mass,
        };
    }
    let (value, dq, dv, qv) = partial_hessian(
        |(qd, vd): (SVector<HyperDualSVec64<N, N>, N>, SVector<HyperDualSVec64<N, N>, N>)| {
            l.lagrangian(HyperDualSVec64::<N, N>::from(t), &qd, &vd)
        },
        (q, v),
    );
    let (_, _, qq) = num_dual::hessian(
        |qd: SVector<Dual2SVec64<N>, N>| l.lagrangian(Dual2SVec64::<N>::from(t), &qd, &lift(v)),
        q,
    );
    let (_, _, vv) = num_dual::hessian(
        |vd: SVector<Dual2SVec64<N>, N>| l.lagrangian(Dual2SVec64::<N>::from(t), &lift(q), &vd),
        v,
    );
    Hessian {
        jet: Jet { value, dq, dv },
        qq,
        qv,
        vv,
    }
}

/// Momentum `p = ∂L/∂v(t, q, v)` (continuous Legendre transform).
pub fn momentum<const N: usize, L: Lagrangian<N>>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> SVector<f64, N> {
    jet(l, t, q, v).dv
}

/// Energy `E = v·∂L/∂v − L` (seed 004 §1.1, `E_L`).
pub fn energy<const N: usize, L: Lagrangian<N>>(l: &L, t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64 {
    let j = jet(l, t, q, v);
    v.dot(&j.dv) - j.value
}

/// Solve `W x = b` for the velocity Hessian `W`, failing with
/// [`Error::SingularVelocityHessian`] when `W` is singular to working precision.
fn solve_velocity_hessian<const N: usize>(
    t: f64,
    w: &SMatrix<f64, N, N>,
    b: &SVector<f64, N>,
) -> Result<SVector<f64, N>> {
    let (x, pivot) = solve_small(w, b);
    if pivot > 1e3 * f64::EPSILON && x.iter().all(|v| v.is_finite()) {
        Ok(x)
    } else {
        Err(Error::SingularVelocityHessian { t, pivot })
    }
}

/// The Euler–Lagrange acceleration `a = W⁻¹(∂L/∂q − (∂²L/∂v∂q) v − ∂²L/∂v∂t)`.
///
/// A singular velocity Hessian `W = ∂²L/∂v²` is the typed error
/// [`Error::SingularVelocityHessian`].
pub fn acceleration<const N: usize, L: Lagrangian<N>>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> Result<SVector<f64, N>> {
    forced_acceleration(l, &NoForce, t, q, v)
}

/// The forced Euler–Lagrange acceleration, from
/// `d/dt ∂L/∂v − ∂L/∂q = F(t, q, v)` (seed 004 §1.1):
/// `a = W⁻¹(∂L/∂q + F − (∂²L/∂v∂q) v − ∂²L/∂v∂t)`.
pub fn forced_acceleration<const N: usize, L: Lagrangian<N>, F: Force<N>>(
    l: &L,
    force: &F,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> Result<SVector<f64, N>> {
    check_finite("q", q.iter())?;
    check_finite("v", v.iter())?;
    let h = hessian(l, t, q, v);
    // ∂²L/∂v∂t by a hyper-dual pass in (v, t).
    let tt = SVector::<f64, 1>::new(t);
    let (_, _, _, vt) = partial_hessian(
        |(vd, td): (SVector<HyperDualSVec64<N, 1>, N>, SVector<HyperDualSVec64<N, 1>, 1>)| {
            l.lagrangian(td[0], &lift(q), &vd)
        },
        (v, &tt),
    );
    let mut rhs = h.jet.dq - h.qv.transpose() * v - vt.column(0);
    if !force.is_zero() {
        rhs += force.force(t, q, v);
    }
    solve_velocity_hessian(t, &h.vv, &rhs)
}

/// Inverse Legendre map: the velocity `v` with `∂L/∂v(t, q, v) = p`, by Newton's
/// method on the exact velocity Hessian, started at `v = 0`.
pub fn velocity_from_momentum<const N: usize, L: Lagrangian<N>>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<SVector<f64, N>> {
    check_finite("q", q.iter())?;
    check_finite("p", p.iter())?;
    let mut v = SVector::<f64, N>::zeros();
    inverse_legendre_iteration(t, || {
        let h = hessian(l, t, q, &v);
        let r = h.jet.dv - p;
        let dv = solve_velocity_hessian(t, &h.vv, &r)?;
        v -= dv;
        Ok((r.amax(), dv.amax() / v.amax().max(1.0)))
    })?;
    Ok(v)
}

/// Iterations of the inverse Legendre map before it is declared failed.
const INVERSE_LEGENDRE_ITERATIONS: usize = 60;

/// The iteration control of the inverse Legendre map `∂L/∂v(t, q, v) = p`,
/// for fixed and run-time dimensions: `newton_step` makes one Newton step on
/// the velocity and returns `‖∂L/∂v − p‖∞` before it and the step relative
/// to `max(‖v‖∞, 1)`. Done when the step is at 4ε, or has stopped
/// decreasing below 1e-9 (round-off); failed after 60 steps or on a
/// non-finite step ([`Error::NewtonFailure`]).
pub(crate) fn inverse_legendre_iteration(t: f64, mut newton_step: impl FnMut() -> Result<(f64, f64)>) -> Result<()> {
    let (mut last, mut residual) = (f64::INFINITY, f64::INFINITY);
    for it in 0..INVERSE_LEGENDRE_ITERATIONS {
        let (r, step) = newton_step()?;
        residual = r;
        if !step.is_finite() {
            break;
        }
        if step <= 4.0 * f64::EPSILON || (it > 2 && step >= last && step < 1e-9) {
            return Ok(());
        }
        last = step;
    }
    Err(Error::NewtonFailure {
        step: 0,
        t,
        residual,
        iterations: INVERSE_LEGENDRE_ITERATIONS,
        reason: "inverse Legendre map ∂L/∂v = p did not converge".to_string(),
    })
}
