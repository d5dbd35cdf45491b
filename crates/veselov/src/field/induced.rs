//! The discrete Lagrangian induced on the cubic lattice by the CFK → cubic
//! map (Casimiro–Rodrigo eq. (3.4), Props. 3.17–3.19, Remark 4.8; note 003
//! §1.5): the map i: (v, σ) ↦ v + ½(1, …, 1) sends each CFK n-simplex to
//! the unit cube that carries it, and
//!
//! L̄_{β̄}(y_{β̄}) = Σ_{β: i(β) = β̄} L_β(proj_β y_{β̄})    (3.4)
//!
//! sums the n! simplices (v, σ), σ ∈ Sym(n), of the cube with base v, each
//! reading its n + 1 vertices v_a = v + e_{σ(0)} + … + e_{σ(a−1)} among the
//! cube's 2ⁿ (binary order: corner k has coordinate i = bit i of k, as
//! [`crate::complex::CubicWindow`] orders them).
//!
//! The claims this carries (tested against the CFK complex): the two
//! actions are equal field by field, hence their Euler–Lagrange forms
//! (Prop. 3.17), their symmetries (Prop. 3.18) and their Noether currents
//! over Ā and i⁻¹(Ā) (Prop. 3.19); with the flow Δv = v + (1, …, 1) the
//! cube based at v is S_v^Δ, the n! simplices based at v, so the Legendre
//! maps and momenta agree too (Remark 4.8). Forces are not induced.

use nalgebra::{SMatrix, SVector};

use super::cell::{DiscreteLagrangian, MAX_CELL_VERTICES, with_values};
use super::fibre::Fibre;
use crate::ad::Scalar;
use crate::complex::{MAX_LATTICE_DIMENSION, TopCell, factorial, permutation};
use crate::error::{Result, invalid};

/// Largest dimension whose cubes fit the derivative routines (2ⁿ ≤ 16 vertices).
pub const MAX_INDUCED_DIMENSION: usize = 4;

/// L̄ of (3.4): the CFK cell Lagrangian `L` summed over the n! simplices of
/// each cube of the cubic lattice.
#[derive(Debug, Clone)]
pub struct CubicInduced<L> {
    inner: L,
    n: usize,
    /// Per permutation index σ: the binary corner index of vertex a of (v, σ).
    corners: Vec<[usize; MAX_LATTICE_DIMENSION + 1]>,
}

impl<L> CubicInduced<L> {
    /// The Lagrangian induced by the CFK cell Lagrangian `inner` in dimension `n`.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] naming `n` unless 1 ≤ n ≤
    /// [`MAX_INDUCED_DIMENSION`].
    pub fn new(inner: L, n: usize) -> Result<Self> {
        if !(1..=MAX_INDUCED_DIMENSION).contains(&n) {
            return Err(invalid(
                "n",
                n,
                "the induced cubic Lagrangian needs 1 ≤ n ≤ 4 (a cube has 2ⁿ ≤ 16 vertices)",
            ));
        }
        let corners = (0..factorial(n))
            .map(|shape| {
                let sigma = permutation(n, shape);
                let mut c = [0; MAX_LATTICE_DIMENSION + 1];
                for a in 1..=n {
                    c[a] = c[a - 1] | (1 << sigma[a - 1]);
                }
                c
            })
            .collect();
        Ok(Self { inner, n, corners })
    }

    /// The CFK cell Lagrangian.
    pub fn inner(&self) -> &L {
        &self.inner
    }

    /// The simplex (v, σ) of the cube `cube` (base v): its top-cell record
    /// (index `cube.index`·n! + σ, as a CFK window over the same extent
    /// numbers it) and the cube positions of its vertices.
    pub fn simplex(&self, cube: &TopCell, shape: usize) -> (TopCell, &[usize]) {
        (
            TopCell {
                index: cube.index * self.corners.len() + shape,
                shape,
                origin: cube.origin,
            },
            &self.corners[shape][..=self.n],
        )
    }
}

impl<F, L, const M: usize> DiscreteLagrangian<F, M> for CubicInduced<L>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
{
    /// Σ_σ L_{(v,σ)} at the cube's values; NaN unless `y` holds the cube's 2ⁿ values.
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[F::Point<D>]) -> D {
        if y.len() != 1 << self.n || y.len() > MAX_CELL_VERTICES {
            return D::from(f64::NAN);
        }
        let mut sum = D::zero();
        for shape in 0..self.corners.len() {
            let (simplex, corners) = self.simplex(cell, shape);
            sum += with_values(
                corners.len(),
                |a| y[corners[a]],
                |v| self.inner.cell_lagrangian(&simplex, v),
            );
        }
        sum
    }

    /// The sum of the simplices' exact gradients where the CFK Lagrangian
    /// has them in closed form.
    fn analytic_gradients(&self, cell: &TopCell, y: &[F::Point<f64>], out: &mut [SVector<f64, M>]) -> bool {
        if y.len() != 1 << self.n || out.len() < y.len() {
            return false;
        }
        let mut local = [SVector::<f64, M>::zeros(); MAX_LATTICE_DIMENSION + 1];
        out[..y.len()].fill(SVector::zeros());
        for shape in 0..self.corners.len() {
            let (simplex, corners) = self.simplex(cell, shape);
            let given = with_values(
                corners.len(),
                |a| y[corners[a]],
                |v| self.inner.analytic_gradients(&simplex, v, &mut local[..corners.len()]),
            );
            if !given {
                return false;
            }
            for (a, &c) in corners.iter().enumerate() {
                out[c] += local[a];
            }
        }
        true
    }

    /// Never: the default hyper-dual pass over the summed Lagrangian.
    fn analytic_block(
        &self,
        _cell: &TopCell,
        _y: &[F::Point<f64>],
        _a: usize,
        _b: usize,
    ) -> Option<(SVector<f64, M>, SMatrix<f64, M, M>)> {
        None
    }
}
