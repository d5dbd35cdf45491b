//! Symmetries and their discrete momentum maps (discrete Noether theorem).
//!
//! A symmetry is declared by its infinitesimal generator `ξ_Q(q)` on
//! configuration space, generic over the AD scalar. If `L` is invariant under
//! the flow of `ξ_Q` (lifted to velocities), the discrete Lagrangians built
//! from it are invariant under the diagonal action, and the discrete momentum
//! map `J(q_k, p_k) = ⟨p_k, ξ_Q(q_k)⟩` is conserved exactly by the
//! variational integrator (Marsden & West 2001, Thm 1.3.3; seed 002 (3.11)).

use nalgebra::SVector;

use crate::ad::Scalar;

/// An infinitesimal symmetry `ξ_Q(q)` of configuration space.
pub trait Symmetry<const N: usize> {
    /// Name used in outputs (column `J_<name>`).
    fn name(&self) -> &str;
    /// The generator `ξ_Q(q)`.
    fn generator<D: Scalar>(&self, q: &SVector<D, N>) -> SVector<D, N>;
}

/// Momentum map `J = ⟨p, ξ_Q(q)⟩`.
pub fn momentum_map<const N: usize, S: Symmetry<N> + ?Sized>(
    symmetry: &S,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> f64 {
    p.dot(&symmetry.generator(q))
}

/// How far `L` is from invariant under the lifted flow of a generator at
/// `(t, q, v)`: the two terms of
/// `δL = ∂L/∂q·ξ_Q(q) + ∂L/∂v·(Dξ_Q(q) v)`, which vanishes for a symmetry.
/// Returns `(δL, |∂L/∂q·ξ| + |∂L/∂v·Dξ v|)`: the defect and the size of the
/// terms it is made of, against which round-off is measured. Exact (three
/// forward-mode passes).
pub fn invariance_defect<const N: usize, L, S>(
    lagrangian: &L,
    symmetry: &S,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> (f64, f64)
where
    L: super::Lagrangian<N> + ?Sized,
    S: Symmetry<N> + ?Sized,
{
    use num_dual::Dual64;
    // ξ(q) and Dξ(q)·v in one pass: ξ(q + δ v) = ξ(q) + δ Dξ(q) v.
    let moved: SVector<Dual64, N> = SVector::from_fn(|i, _| Dual64::new(q[i], v[i]));
    let xi = symmetry.generator(&moved);
    let (xi0, dxi) = (xi.map(|x| x.re), xi.map(|x| x.eps));
    let along = |dq: &SVector<f64, N>, dv: &SVector<f64, N>| {
        let qe: SVector<Dual64, N> = SVector::from_fn(|i, _| Dual64::new(q[i], dq[i]));
        let ve: SVector<Dual64, N> = SVector::from_fn(|i, _| Dual64::new(v[i], dv[i]));
        lagrangian.lagrangian(Dual64::from(t), &qe, &ve).eps
    };
    let zero = SVector::<f64, N>::zeros();
    let (a, b) = (along(&xi0, &zero), along(&zero, &dxi));
    (a + b, a.abs() + b.abs())
}

/// A symmetry with an affine generator `ξ_Q(q) = A q + b`: rotations and translations.
#[derive(Debug, Clone, PartialEq)]
pub struct AffineSymmetry<const N: usize> {
    name: String,
    matrix: nalgebra::SMatrix<f64, N, N>,
    offset: SVector<f64, N>,
}

impl<const N: usize> AffineSymmetry<N> {
    /// `ξ_Q(q) = A q + b`.
    pub fn new(name: &str, matrix: nalgebra::SMatrix<f64, N, N>, offset: SVector<f64, N>) -> Self {
        Self {
            name: name.to_string(),
            matrix,
            offset,
        }
    }
    /// Rotation in the plane of coordinates `(i, j)`: `ξ = (…, −q_j, …, q_i, …)`.
    pub fn rotation(name: &str, i: usize, j: usize) -> Self {
        let mut a = nalgebra::SMatrix::<f64, N, N>::zeros();
        a[(i, j)] = -1.0;
        a[(j, i)] = 1.0;
        Self::new(name, a, SVector::zeros())
    }
    /// Translation along coordinate `i`.
    pub fn translation(name: &str, i: usize) -> Self {
        let mut b = SVector::<f64, N>::zeros();
        b[i] = 1.0;
        Self::new(name, nalgebra::SMatrix::zeros(), b)
    }
}

impl<const N: usize> Symmetry<N> for AffineSymmetry<N> {
    fn name(&self) -> &str {
        &self.name
    }
    fn generator<D: Scalar>(&self, q: &SVector<D, N>) -> SVector<D, N> {
        let a = self.matrix.map(D::from);
        a * q + self.offset.map(D::from)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanics::Lagrangian;
    use nalgebra::Vector2;

    /// A charge in a uniform magnetic field, symmetric gauge:
    /// `L = ½|v|² + (B/2)(x v_y − y v_x)`.
    struct Magnetic;
    impl Lagrangian<2> for Magnetic {
        fn lagrangian<D: Scalar>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
            v.dot(v) * 0.5 + (q[0] * v[1] - q[1] * v[0]) * 0.75
        }
    }

    /// Rotations are a symmetry of the symmetric-gauge magnetic Lagrangian only
    /// through the lifted velocity term (both terms of δL are large and
    /// cancel); translations are not (they are a quasi-symmetry).
    #[test]
    fn invariance_defect_tells_symmetries_apart() {
        let (q, v) = (Vector2::new(0.7, -1.1), Vector2::new(0.4, 1.3));
        let (defect, size) = invariance_defect(&Magnetic, &AffineSymmetry::rotation("rot", 0, 1), 0.2, &q, &v);
        assert!(
            size > 0.5 && defect.abs() <= 4.0 * f64::EPSILON * size,
            "{defect:e} of {size}"
        );
        let (defect, size) = invariance_defect(&Magnetic, &AffineSymmetry::translation("x", 0), 0.2, &q, &v);
        // ∂L/∂x = (B/2) v_y = 0.75 · 1.3.
        assert!((defect - 0.975).abs() < 1e-15 && size > 0.9, "{defect}");
    }
}
