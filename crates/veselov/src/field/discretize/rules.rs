//! Quadrature rules turning a smooth density into a discrete Lagrangian
//! (note 003 §2.5; paper §5): L^x(y_β) = Q(h), h(λ) = 𝓛(j¹y)·Jac(λ) (5.5).
//!
//! * [`VertexRule`]: vertex nodes through Lemma 5.15 for **any** fibre —
//!   Q_u (h(e_u)/n!, exact for constants) and Q_sym (vertex average /n!,
//!   exact for affine h) of (5.2);
//! * [`MidpointRule`](super::MidpointRule): Q_mid (5.2) at the barycentre for the Euclidean
//!   fibre, where the interpolation is affine (Prop. 5.20, (5.6));
//! * [`CubeCentreRule`](super::CubeCentreRule): the one-point centre rule of the multilinear
//!   interpolant on a cube (Euclidean fibre).
//!
//! Seed 002's rules are instances, up to the constant cell area that the
//! 1+1 code omits (it scales the action and leaves the DELf unchanged):
//! the triangle rule (5.8) is (h k/2)⁻¹ × Q_mid on the CFK simplex (v, σ = (1, 0))
//! under x = diag(k, h) v, and the symmetric rectangle rule (5.12) is
//! (h k)⁻¹ × the cube-centre rule. The rectangle rule (5.9) (whose DELf is
//! (5.10)) is **not** an instance: its φ_t = (y² − y¹)/h is the time
//! derivative of the bilinear interpolant on the cell's left edge while φ and
//! φ_x are taken at the centre, so no single node of the interpolant gives it.
//!
//! The rules' [`DiscreteLagrangian::cell_lagrangian`] returns NaN on an
//! unsuitable cell (it cannot return an error); [`CellCheck::check_cell`]
//! names the cell and the reason, and a marcher calls it on every cell of
//! its Cauchy data and after every vertex solve.
use std::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use super::error::CellError;
use super::nodes::{NodeMap, SINGULAR_NODES, factorial, invert};
use super::smooth::SmoothDensity;
use super::suitability::{CellCheck, GeodesicBall};
use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::error::Result;
use crate::error::invalid;
use crate::field::cell::{DiscreteLagrangian, MAX_CELL_VERTICES};
use crate::field::fibre::Fibre;

/// Inverse of a node matrix T (columns = edge vectors) and |det T|.
pub(super) fn invert_nodes<const N: usize>(
    cell: usize,
    t: &SMatrix<f64, N, N>,
) -> std::result::Result<(SMatrix<f64, N, N>, f64), CellError> {
    let scale: f64 = t.column_iter().map(|c| c.norm()).product();
    let Some((inv, det)) = invert(t) else {
        return Err(CellError::SingularNodes {
            cell,
            relative_determinant: 0.0,
        });
    };
    let relative_determinant = det.abs() / scale;
    if !(relative_determinant > SINGULAR_NODES && relative_determinant.is_finite()) {
        return Err(CellError::SingularNodes {
            cell,
            relative_determinant,
        });
    }
    Ok((inv, det.abs()))
}

/// Lemma 5.15 at vertex `u` of a simplex with nodes `x` and values `y`
/// (n + 1 each): t_{uv} = log_{y_u}(y_v) (the fibre's [`Fibre::log`]),
/// T^X = [x(v) − x(u)]_{v≠u}, φ_u = T_Y (T^X)⁻¹ and Jac(e_u) = |det T^X|.
/// Returns (φ_u, Jac(e_u)); Jac/n! is the simplex volume.
///
/// # Errors
/// [`CellError::Nodes`] for wrong lengths or u > N, [`CellError::SingularNodes`],
/// [`CellError::Logarithm`] (cut locus).
pub fn vertex_jet<F: Fibre<M>, D: Scalar, const M: usize, const N: usize>(
    cell: usize,
    x: &[SVector<f64, N>],
    y: &[F::Point<D>],
    u: usize,
) -> std::result::Result<(SMatrix<D, M, N>, f64), CellError> {
    if x.len() != N + 1 || y.len() != N + 1 || u > N {
        return Err(CellError::Nodes {
            cell,
            expected: N + 1,
            got: if x.len() == N + 1 { y.len() } else { x.len() },
        });
    }
    let mut tx = SMatrix::<f64, N, N>::zeros();
    let mut ty = SMatrix::<D, M, N>::from_element(D::zero());
    for (c, v) in (0..=N).filter(|&v| v != u).enumerate() {
        tx.set_column(c, &(x[v] - x[u]));
        let t = F::log(&y[u], &y[v]).map_err(|source| CellError::Logarithm {
            cell,
            from: u,
            to: v,
            source,
        })?;
        ty.set_column(c, &t);
    }
    let (inv, jac) = invert_nodes(cell, &tx)?;
    // φ_u = T_Y·(T^X)⁻¹ with f64 factors (cheaper than lifting the inverse).
    let jet = SMatrix::<D, M, N>::from_fn(|k, a| (0..N).fold(D::zero(), |acc, c| acc + ty[(k, c)] * inv[(c, a)]));
    Ok((jet, jac))
}

/// Which vertex nodes a [`VertexRule`] uses (5.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VertexQuadrature {
    /// Q_u: the single node e_u, u = position in the cell's vertex order
    /// (the rod uses u = 0, the least-weight vertex, Prop. 6.5).
    Vertex(usize),
    /// Q_sym: all n + 1 vertices with weight 1/(n + 1).
    Symmetric,
}

/// A discrete Lagrangian from a smooth density, a node map and vertex nodes
/// (Lemma 5.15, Def. 5.14): L = (1/n!) Σ_u c_u 𝓛(x(u), y_u, φ_u)·|det T^X_u|
/// on N-simplices, for any fibre with a logarithm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexRule<F, L, X, const M: usize, const N: usize> {
    /// The smooth density.
    pub density: L,
    /// The node map.
    pub nodes: X,
    quadrature: VertexQuadrature,
    fibre: PhantomData<fn() -> F>,
}

impl<F, L, X, const M: usize, const N: usize> VertexRule<F, L, X, M, N> {
    /// Q_u at the vertex in position `u` (0 ≤ u ≤ N) of every cell.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] if u > N.
    pub fn at_vertex(density: L, nodes: X, u: usize) -> Result<Self> {
        if u > N {
            return Err(invalid("u", u, "vertex position must be at most the dimension N"));
        }
        Ok(Self {
            density,
            nodes,
            quadrature: VertexQuadrature::Vertex(u),
            fibre: PhantomData,
        })
    }

    /// Q_sym: the average over the N + 1 vertices.
    pub fn symmetric(density: L, nodes: X) -> Self {
        Self {
            density,
            nodes,
            quadrature: VertexQuadrature::Symmetric,
            fibre: PhantomData,
        }
    }

    /// The quadrature.
    pub fn quadrature(&self) -> VertexQuadrature {
        self.quadrature
    }
}

impl<F, L, X, const M: usize, const N: usize> VertexRule<F, L, X, M, N>
where
    F: Fibre<M>,
    L: SmoothDensity<F, M, N>,
    X: NodeMap<N>,
{
    /// The discrete Lagrangian with its failure named.
    ///
    /// # Errors
    /// As [`vertex_jet`]; [`CellError::Nodes`] if the node map does not know
    /// the cell.
    pub fn try_cell_lagrangian<D: Scalar>(
        &self,
        cell: &TopCell,
        y: &[F::Point<D>],
    ) -> std::result::Result<D, CellError> {
        let mut x = [SVector::<f64, N>::zeros(); MAX_CELL_VERTICES];
        let k = cell_nodes(&self.nodes, cell, &mut x);
        if k != N + 1 || y.len() != N + 1 {
            return Err(CellError::Nodes {
                cell: cell.index,
                expected: N + 1,
                got: if k == N + 1 { y.len() } else { k },
            });
        }
        let x = &x[..k];
        let term = |u: usize| -> std::result::Result<D, CellError> {
            let (jet, jac) = vertex_jet::<F, D, M, N>(cell.index, x, y, u)?;
            Ok(self.density.density(&x[u], &y[u], &jet) * jac)
        };
        let nf = factorial(N) as f64;
        match self.quadrature {
            VertexQuadrature::Vertex(u) => Ok(term(u)? / nf),
            VertexQuadrature::Symmetric => {
                let mut sum = D::zero();
                for u in 0..=N {
                    sum += term(u)?;
                }
                Ok(sum / (nf * (N + 1) as f64))
            }
        }
    }
}

impl<F, L, X, const M: usize, const N: usize> DiscreteLagrangian<F, M> for VertexRule<F, L, X, M, N>
where
    F: Fibre<M>,
    L: SmoothDensity<F, M, N>,
    X: NodeMap<N>,
{
    /// NaN on an unsuitable cell; see [`CellCheck::check_cell`].
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[F::Point<D>]) -> D {
        self.try_cell_lagrangian(cell, y).unwrap_or(D::from(f64::NAN))
    }
}

impl<F, L, X, const M: usize, const N: usize> CellCheck<F, M> for VertexRule<F, L, X, M, N>
where
    F: GeodesicBall<M>,
    L: SmoothDensity<F, M, N>,
    X: NodeMap<N>,
{
    fn check_cell(&self, cell: &TopCell, y: &[F::Point<f64>]) -> std::result::Result<(), CellError> {
        let cell_index = cell.index;
        let mut x = [SVector::<f64, N>::zeros(); MAX_CELL_VERTICES];
        let k = cell_nodes(&self.nodes, cell, &mut x);
        if k != N + 1 || y.len() != N + 1 {
            return Err(CellError::Nodes {
                cell: cell_index,
                expected: N + 1,
                got: if k == N + 1 { y.len() } else { k },
            });
        }
        if !x[..k].iter().all(|xi| xi.iter().all(|c| c.is_finite())) {
            return Err(CellError::NonFinite {
                cell: cell_index,
                what: "node",
            });
        }
        if !y.iter().all(F::is_finite) {
            return Err(CellError::NonFinite {
                cell: cell_index,
                what: "vertex value",
            });
        }
        F::check_simplex(y).map_err(|reason| CellError::Unsuitable {
            cell: cell_index,
            reason,
        })?;
        // Every vertex's jet must exist (the interpolation's suitability on
        // the faces), whatever the quadrature.
        for u in 0..=N {
            vertex_jet::<F, f64, M, N>(cell_index, &x[..k], y, u)?;
        }
        finite(cell_index, self.try_cell_lagrangian(cell, y)?)
    }
}

/// The node map's vertex count, 0 if it claims more than it could write.
pub(super) fn cell_nodes<X: NodeMap<N>, const N: usize>(map: &X, cell: &TopCell, out: &mut [SVector<f64, N>]) -> usize {
    let k = map.cell_nodes(cell, out);
    if k > out.len() { 0 } else { k }
}

pub(super) fn finite(cell: usize, value: f64) -> std::result::Result<(), CellError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(CellError::NonFinite {
            cell,
            what: "discrete Lagrangian",
        })
    }
}
