//! Rules for the Euclidean fibre ℝ^M (affine bundle, Prop. 5.20):
//! Q_mid at the barycentre of a simplex with the affine interpolant's value
//! and constant gradient (5.6), and the centre rule of the multilinear
//! interpolant on cubes.

use nalgebra::{SMatrix, SVector};

use super::error::CellError;
use super::metric_lanes::{LaneOutput, METRIC_LANES};
use super::nodes::{NodeMap, factorial};
use super::rules::{cell_nodes, finite, invert_nodes, vertex_jet};
use super::smooth::{SmoothDensity, energy_momentum_density};
use super::suitability::CellCheck;
use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::field::cell::{DiscreteLagrangian, MAX_CELL_VERTICES, SolvedVertex, VertexRun, VertexStar};
use crate::field::fibre::Euclidean;
use crate::field::legendre::CauchyOptions;

/// The affine interpolant of a simplex (Prop. 5.20): barycentre x̄, value ȳ
/// there, its constant gradient ∂y/∂x (columns ∂/∂x^a) and the simplex volume
/// vol_β = |det X_β|/n! (= |det T^X|/n!).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AffineJet<D, const M: usize, const N: usize> {
    /// Barycentre x̄ of the nodes.
    pub centre: SVector<f64, N>,
    /// ȳ = mean of the vertex values = the interpolant at x̄.
    pub value: SVector<D, M>,
    /// The gradient, the same at every point of the simplex.
    pub gradient: SMatrix<D, M, N>,
    /// vol_β = |det X_β|/n!.
    pub volume: f64,
}

/// The affine interpolant of values `y` at nodes `x` (n + 1 each), (5.6).
///
/// # Errors
/// [`CellError::Nodes`] for wrong lengths, [`CellError::SingularNodes`] if
/// X_β is singular (the cell is then not suitable, Prop. 5.20).
pub fn affine_jet<D: Scalar, const M: usize, const N: usize>(
    cell: usize,
    x: &[SVector<f64, N>],
    y: &[SVector<D, M>],
) -> std::result::Result<AffineJet<D, M, N>, CellError> {
    let (gradient, jac) = vertex_jet::<Euclidean<M>, D, M, N>(cell, x, y, 0)?;
    let w = 1.0 / (N + 1) as f64;
    let centre = x.iter().fold(SVector::<f64, N>::zeros(), |a, b| a + b) * w;
    let value = y.iter().fold(SVector::<D, M>::from_element(D::zero()), |a, b| a + b) * D::from(w);
    Ok(AffineJet {
        centre,
        value,
        gradient,
        volume: jac / factorial(N) as f64,
    })
}

/// Q_mid for the Euclidean fibre ℝ^M (Prop. 5.20): L = 𝓛(x̄, ȳ, ∂y/∂x)·vol_β
/// with the affine interpolant's barycentre value and constant gradient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MidpointRule<L, X, const N: usize> {
    /// The smooth density.
    pub density: L,
    /// The node map (simplices).
    pub nodes: X,
    /// Per shape (N ≤ 4, translation-invariant node maps): (T^X)⁻¹ and vol_β.
    geometry: [Option<(SMatrix<f64, N, N>, f64)>; SHAPE_CACHE],
    /// Whether the exact derivatives go through the interpolant's chain rule
    /// ([`super::affine_chain`]) rather than dual numbers over the whole cell.
    chain_rule: bool,
}

/// Shapes whose geometry a [`MidpointRule`] caches (4! simplices per cube).
const SHAPE_CACHE: usize = 24;

impl<L, X: NodeMap<N>, const N: usize> MidpointRule<L, X, N> {
    /// Q_mid of `density` on the simplices of `nodes`. For a
    /// translation-invariant node map of dimension N ≤ 4 the inverse edge
    /// matrix and the volume of every shape are computed once here.
    pub fn new(density: L, nodes: X) -> Self {
        let mut geometry = [None; SHAPE_CACHE];
        if nodes.translation_invariant() && N <= 4 {
            let count: usize = (1..=N).product();
            for (shape, slot) in geometry.iter_mut().enumerate().take(count) {
                let probe = TopCell {
                    index: 0,
                    shape,
                    origin: [0; crate::complex::MAX_LATTICE_DIMENSION],
                };
                let mut x = [SVector::<f64, N>::zeros(); MAX_CELL_VERTICES];
                if cell_nodes(&nodes, &probe, &mut x) == N + 1 {
                    let tx = SMatrix::<f64, N, N>::from_fn(|r, c| x[c + 1][r] - x[0][r]);
                    if let Ok((inv, jac)) = invert_nodes(0, &tx) {
                        *slot = Some((inv, jac / factorial(N) as f64));
                    }
                }
            }
        }
        Self {
            density,
            nodes,
            geometry,
            chain_rule: true,
        }
    }

    /// Whether the vertex gradients and Jacobian blocks come from the chain
    /// rule of the affine interpolant with dual numbers over the density
    /// alone (`true`, the default; [`super::affine_chain`]) or from dual
    /// numbers over the whole cell Lagrangian (`false`, the reference: the
    /// same derivatives to round-off, several times slower).
    pub fn with_chain_rule(mut self, on: bool) -> Self {
        self.chain_rule = on;
        self
    }

    /// The cached (T^X)⁻¹ and vol_β of the cell's shape, if any.
    pub(super) fn cached_geometry(&self, cell: &TopCell) -> Option<(SMatrix<f64, N, N>, f64)> {
        self.shape_geometry(cell.shape).copied()
    }

    /// The cached (T^X)⁻¹ and vol_β of a shape, if any, in place.
    #[inline]
    pub(super) fn shape_geometry(&self, shape: usize) -> Option<&(SMatrix<f64, N, N>, f64)> {
        self.geometry.get(shape)?.as_ref()
    }

    /// The affine jet from the cached geometry of the cell's shape, if any
    /// (the centre only where the density depends on position).
    fn cached_jet<D: Scalar, const M: usize>(&self, cell: &TopCell, y: &[SVector<D, M>]) -> Option<AffineJet<D, M, N>>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        let (inv, volume) = self.cached_geometry(cell)?;
        if y.len() != N + 1 || self.density.depends_on_position() {
            return None;
        }
        let gradient = SMatrix::<D, M, N>::from_fn(|k, a| {
            (0..N).fold(D::zero(), |acc, c| acc + (y[c + 1][k] - y[0][k]) * inv[(c, a)])
        });
        let w = D::from(1.0 / (N + 1) as f64);
        let value = y
            .iter()
            .fold(SVector::<D, M>::from_element(D::zero()), |acc, b| acc + b)
            * w;
        Some(AffineJet {
            centre: SVector::zeros(),
            value,
            gradient,
            volume,
        })
    }

    fn jet<D: Scalar, const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<D, M>],
    ) -> std::result::Result<AffineJet<D, M, N>, CellError>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
    {
        if let Some(jet) = self.cached_jet(cell, y) {
            return Ok(jet);
        }
        let mut x = [SVector::<f64, N>::zeros(); MAX_CELL_VERTICES];
        let k = cell_nodes(&self.nodes, cell, &mut x);
        if k != N + 1 {
            return Err(CellError::Nodes {
                cell: cell.index,
                expected: N + 1,
                got: k,
            });
        }
        affine_jet(cell.index, &x[..k], y)
    }

    /// The discrete Lagrangian with its failure named.
    ///
    /// # Errors
    /// As [`affine_jet`]; [`CellError::Nodes`] if the node map does not know
    /// the cell.
    pub fn try_cell_lagrangian<D: Scalar, const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<D, M>],
    ) -> std::result::Result<D, CellError>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        X: NodeMap<N>,
    {
        let a = self.jet(cell, y)?;
        Ok(self.density.density(&a.centre, &a.value, &a.gradient) * a.volume)
    }

    /// The cell's energy vol_β·ℰ and momenta vol_β·𝒫_a (a < N − 1, into
    /// `momenta`) at the rule's node, with the energy density
    /// ℰ = φ_t·∂𝓛/∂φ_t − 𝓛 and momentum density 𝒫_a = −∂𝓛/∂φ_t·φ_{x_a} (time
    /// the last coordinate).
    ///
    /// # Errors
    /// As [`try_cell_lagrangian`](Self::try_cell_lagrangian).
    pub fn cell_energy_momentum<const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<f64, M>],
        momenta: &mut [f64],
    ) -> std::result::Result<f64, CellError>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        X: NodeMap<N>,
    {
        let a = self.jet(cell, y)?;
        let count = momenta.len().min(N - 1);
        let energy = energy_momentum_density(&self.density, &a.centre, &a.value, &a.gradient, &mut momenta[..count]);
        for p in &mut momenta[..count] {
            *p *= a.volume;
        }
        Ok(energy * a.volume)
    }

    /// The cell's energy vol_β·ℰ (see [`cell_energy_momentum`](Self::cell_energy_momentum)).
    ///
    /// # Errors
    /// As [`try_cell_lagrangian`](Self::try_cell_lagrangian).
    pub fn cell_energy<const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<f64, M>],
    ) -> std::result::Result<f64, CellError>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        X: NodeMap<N>,
    {
        self.cell_energy_momentum(cell, y, &mut [])
    }
}

impl<L, X, const M: usize, const N: usize> DiscreteLagrangian<Euclidean<M>, M> for MidpointRule<L, X, N>
where
    L: SmoothDensity<Euclidean<M>, M, N>,
    X: NodeMap<N>,
{
    /// NaN on a degenerate cell; see [`CellCheck::check_cell`].
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SVector<D, M>]) -> D {
        self.try_cell_lagrangian(cell, y).unwrap_or(D::from(f64::NAN))
    }

    /// By the interpolant's chain rule ([`super::affine_chain`]).
    fn analytic_gradients(&self, cell: &TopCell, y: &[SVector<f64, M>], out: &mut [SVector<f64, M>]) -> bool {
        self.chain_rule && self.chain_gradients(cell, y, out)
    }

    /// By the interpolant's chain rule ([`super::affine_chain`]).
    fn analytic_gradient(&self, cell: &TopCell, y: &[SVector<f64, M>], l: usize) -> Option<SVector<f64, M>> {
        self.chain_rule.then(|| self.chain_gradient(cell, y, l))?
    }

    /// By the interpolant's chain rule ([`super::affine_chain`]).
    fn analytic_block(
        &self,
        cell: &TopCell,
        y: &[SVector<f64, M>],
        a: usize,
        b: usize,
    ) -> Option<(SVector<f64, M>, SMatrix<f64, M, M>)> {
        self.chain_rule.then(|| self.chain_block(cell, y, a, b))?
    }

    /// The rule's own Newton over its star cells' interpolants
    /// ([`super::affine_chain`]), which also hands the marcher the solved
    /// cells' gradients.
    fn solve_last_vertex(
        &self,
        star: &VertexStar<'_, SVector<f64, M>>,
        mu: &SVector<f64, M>,
        mu_scale: f64,
        previous: &SVector<f64, M>,
        options: &CauchyOptions,
        gradients: &mut [SVector<f64, M>],
    ) -> Option<SolvedVertex<SVector<f64, M>>> {
        self.chain_rule
            .then(|| self.solve_star(star, mu, mu_scale, previous, options, gradients))?
    }

    /// `METRIC_LANES` (8) for a density with a diagonal jet metric (with the chain rule),
    /// else 1.
    fn vertex_lanes(&self) -> usize {
        if self.chain_rule && self.has_metric_lanes::<M>() {
            METRIC_LANES
        } else {
            1
        }
    }

    /// A run of a level's vertices by the metric solve, eight at a time
    /// (`solve_metric_run`): for a density with a diagonal jet metric, with
    /// the chain rule; `false` (one vertex at a time) otherwise.
    fn solve_vertex_run<R>(
        &self,
        run: &R,
        options: &CauchyOptions,
        gradients: &mut [SVector<f64, M>],
        stride: usize,
        solved: &mut [SolvedVertex<SVector<f64, M>>],
    ) -> bool
    where
        R: VertexRun<SVector<f64, M>, M>,
    {
        let out = LaneOutput {
            gradients,
            stride,
            solved,
        };
        self.chain_rule && self.solve_metric_run(run, options, out)
    }
}

impl<L, X, const M: usize, const N: usize> CellCheck<Euclidean<M>, M> for MidpointRule<L, X, N>
where
    L: SmoothDensity<Euclidean<M>, M, N>,
    X: NodeMap<N>,
{
    fn check_cell(&self, cell: &TopCell, y: &[SVector<f64, M>]) -> std::result::Result<(), CellError> {
        finite(cell.index, self.try_cell_lagrangian(cell, y)?)
    }
}

/// The centre jet of the multilinear interpolant on a cube with 2^N vertices
/// in binary order: (x̄, ȳ, ∂y/∂x at the centre, |det ∂x/∂ξ| at the centre).
/// ∂/∂ξ_a at ξ = (½, …, ½) is (Σ_{bit a of k set} − Σ_{bit a clear}) / 2^{N−1}.
///
/// # Errors
/// [`CellError::Nodes`] for wrong lengths, [`CellError::SingularNodes`].
pub fn cube_centre_jet<D: Scalar, const M: usize, const N: usize>(
    cell: usize,
    x: &[SVector<f64, N>],
    y: &[SVector<D, M>],
) -> std::result::Result<AffineJet<D, M, N>, CellError> {
    let count = 1usize << N;
    if x.len() != count || y.len() != count {
        return Err(CellError::Nodes {
            cell,
            expected: count,
            got: if x.len() == count { y.len() } else { x.len() },
        });
    }
    let w = 1.0 / count as f64;
    let half = 2.0 / count as f64;
    let mut centre = SVector::<f64, N>::zeros();
    let mut value = SVector::<D, M>::from_element(D::zero());
    let mut xxi = SMatrix::<f64, N, N>::zeros();
    let mut yxi = SMatrix::<D, M, N>::from_element(D::zero());
    for k in 0..count {
        centre += x[k] * w;
        value += y[k] * D::from(w);
        for a in 0..N {
            let s = if (k >> a) & 1 == 1 { half } else { -half };
            let mut cx = xxi.column_mut(a);
            cx += x[k] * s;
            let mut cy = yxi.column_mut(a);
            cy += y[k] * D::from(s);
        }
    }
    let (inv, jac) = invert_nodes(cell, &xxi)?;
    Ok(AffineJet {
        centre,
        value,
        gradient: yxi * inv.map(D::from),
        volume: jac,
    })
}

/// The one-point centre rule of the multilinear interpolant on cubes
/// (Euclidean fibre): L = 𝓛(x̄, ȳ, ∂y/∂x(x̄))·|det ∂x/∂ξ(centre)|, vertices
/// in binary order. The weight is the exact cell volume for parallelepipeds
/// (affine node maps such as [`super::CubeNodes`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubeCentreRule<L, X, const N: usize> {
    /// The smooth density.
    pub density: L,
    /// The node map (cubes, binary vertex order).
    pub nodes: X,
}

impl<L, X, const N: usize> CubeCentreRule<L, X, N> {
    /// The centre rule of `density` on the cubes of `nodes`.
    pub fn new(density: L, nodes: X) -> Self {
        Self { density, nodes }
    }

    /// The discrete Lagrangian with its failure named.
    ///
    /// # Errors
    /// As [`cube_centre_jet`]; [`CellError::Nodes`] if the node map does not
    /// know the cell.
    pub fn try_cell_lagrangian<D: Scalar, const M: usize>(
        &self,
        cell: &TopCell,
        y: &[SVector<D, M>],
    ) -> std::result::Result<D, CellError>
    where
        L: SmoothDensity<Euclidean<M>, M, N>,
        X: NodeMap<N>,
    {
        let mut x = [SVector::<f64, N>::zeros(); MAX_CELL_VERTICES];
        let k = cell_nodes(&self.nodes, cell, &mut x);
        let a = cube_centre_jet(cell.index, &x[..k], y)?;
        Ok(self.density.density(&a.centre, &a.value, &a.gradient) * a.volume)
    }
}

impl<L, X, const M: usize, const N: usize> DiscreteLagrangian<Euclidean<M>, M> for CubeCentreRule<L, X, N>
where
    L: SmoothDensity<Euclidean<M>, M, N>,
    X: NodeMap<N>,
{
    /// NaN on a degenerate cell; see [`CellCheck::check_cell`].
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SVector<D, M>]) -> D {
        self.try_cell_lagrangian(cell, y).unwrap_or(D::from(f64::NAN))
    }
}

impl<L, X, const M: usize, const N: usize> CellCheck<Euclidean<M>, M> for CubeCentreRule<L, X, N>
where
    L: SmoothDensity<Euclidean<M>, M, N>,
    X: NodeMap<N>,
{
    fn check_cell(&self, cell: &TopCell, y: &[SVector<f64, M>]) -> std::result::Result<(), CellError> {
        finite(cell.index, self.try_cell_lagrangian(cell, y)?)
    }
}
