//! Discrete Lagrangian densities on lattice cells, written once generic over
//! the scalar; exact per-cell gradients and Hessians by `num-dual`.
//!
//! Vertex conventions (seed 002 §5.1, note 002 §0.3–0.4):
//! * triangle `Δ(i,j) = ((i,j), (i,j+1), (i+1,j+1))`, `L(y¹, y², y³)`;
//! * rectangle `R(i,j) = ((i,j), (i,j+1), (i+1,j+1), (i+1,j))`, `L(y¹..y⁴)`.
//!
//! The cell area `h·k` is omitted from every discrete Lagrangian (it scales
//! the action and leaves the DELf equations unchanged), so the assembled
//! residuals are exactly the printed forms (5.8), (5.10), (5.12).

use nalgebra::{SMatrix, SVector};

use crate::ad::Scalar;
use crate::complex::{MAX_LATTICE_DIMENSION, TopCell};
use crate::field::cell::{DiscreteLagrangian, mixed_block, vertex_gradient};
use crate::field::fibre::Euclidean;
use crate::spacetime::lattice::CellShape;
use crate::spacetime::region::{Node, Region};

/// A per-cell discrete Lagrangian `L_Δ(y¹, …, yⁿ)` with field values in
/// `ℝ^DIM` (`n = 3` for triangles, `4` for rectangles).
pub trait CellLagrangian<const DIM: usize>: Sync {
    /// The cell shape (fixes the number and order of the vertices).
    fn shape(&self) -> CellShape;
    /// `L(y¹, …, yⁿ)`, `y.len() == self.shape().vertices()`.
    fn lagrangian<D: Scalar>(&self, y: &[SVector<D, DIM>]) -> D;
}

/// A smooth Lagrangian density `𝓛(φ, φ_t, φ_x)`.
pub trait Density<const DIM: usize>: Sync {
    /// `𝓛(φ, φ_t, φ_x)`.
    fn density<D: Scalar>(&self, phi: &SVector<D, DIM>, phi_t: &SVector<D, DIM>, phi_x: &SVector<D, DIM>) -> D;
}

/// Triangle rule of seed 002 (5.8): `φ = (y¹+y²+y³)/3`,
/// `φ_t = (y² − y¹)/h`, `φ_x = (y³ − y²)/k`, `L = 𝓛(φ, φ_t, φ_x)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleRule<F> {
    /// The smooth density.
    pub density: F,
    /// Time step `h`.
    pub dt: f64,
    /// Space step `k`.
    pub dx: f64,
}

/// The jet (φ, φ_t, φ_x) a cell rule evaluates its density at.
pub type Jet<D, const DIM: usize> = (SVector<D, DIM>, SVector<D, DIM>, SVector<D, DIM>);

impl<F> TriangleRule<F> {
    /// (φ, φ_t, φ_x) of the triangle (y¹, y², y³).
    pub fn jet<D: Scalar, const DIM: usize>(&self, y: &[SVector<D, DIM>]) -> Jet<D, DIM> {
        (
            (y[0] + y[1] + y[2]) / D::from(3.0),
            (y[1] - y[0]) / D::from(self.dt),
            (y[2] - y[1]) / D::from(self.dx),
        )
    }
}

impl<const DIM: usize, F: Density<DIM>> CellLagrangian<DIM> for TriangleRule<F> {
    fn shape(&self) -> CellShape {
        CellShape::Triangle
    }
    fn lagrangian<D: Scalar>(&self, y: &[SVector<D, DIM>]) -> D {
        let (phi, phi_t, phi_x) = self.jet(y);
        self.density.density(&phi, &phi_t, &phi_x)
    }
}

/// Rectangle rules: (5.9) and the symmetric (5.12). Both use the vertex
/// average `φ = (y¹+y²+y³+y⁴)/4` and `φ_x = ((y⁴ − y¹) + (y³ − y²))/(2k)`;
/// (5.9) takes `φ_t = (y² − y¹)/h`, (5.12) the average
/// `φ_t = ((y² − y¹) + (y³ − y⁴))/(2h)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectangleRule<F> {
    /// The smooth density.
    pub density: F,
    /// Time step `h`.
    pub dt: f64,
    /// Space step `k`.
    pub dx: f64,
    /// `true` for (5.12), `false` for (5.9).
    pub symmetric: bool,
}

impl<F> RectangleRule<F> {
    /// (φ, φ_t, φ_x) of the rectangle (y¹, y², y³, y⁴).
    pub fn jet<D: Scalar, const DIM: usize>(&self, y: &[SVector<D, DIM>]) -> Jet<D, DIM> {
        let phi = (y[0] + y[1] + y[2] + y[3]) / D::from(4.0);
        let phi_t = if self.symmetric {
            ((y[1] - y[0]) + (y[2] - y[3])) / D::from(2.0 * self.dt)
        } else {
            (y[1] - y[0]) / D::from(self.dt)
        };
        let phi_x = ((y[3] - y[0]) + (y[2] - y[1])) / D::from(2.0 * self.dx);
        (phi, phi_t, phi_x)
    }
}

impl<const DIM: usize, F: Density<DIM>> CellLagrangian<DIM> for RectangleRule<F> {
    fn shape(&self) -> CellShape {
        CellShape::Rectangle
    }
    fn lagrangian<D: Scalar>(&self, y: &[SVector<D, DIM>]) -> D {
        let (phi, phi_t, phi_x) = self.jet(y);
        self.density.density(&phi, &phi_t, &phi_x)
    }
}

/// Exact first and second derivatives of a cell Lagrangian at one cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellJet<const DIM: usize> {
    /// Number of vertices (3 or 4).
    pub vertices: usize,
    /// `∂L/∂y^l`, `l = 0..vertices`.
    pub grad: [SVector<f64, DIM>; 4],
    /// `∂²L/∂y^l∂y^m` blocks.
    pub hess: [[SMatrix<f64, DIM, DIM>; 4]; 4],
}

/// A 1+1 cell Lagrangian seen by the field core: a [`DiscreteLagrangian`]
/// on the Euclidean fibre ℝ^DIM over the cells of a
/// [`SpacetimeLattice`](crate::complex::SpacetimeLattice) of its shape, so
/// that its derivatives come from the core's one differentiation path and it
/// marches on the core's complexes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoreCell<'a, L>(pub &'a L);

impl<L: CellLagrangian<DIM>, const DIM: usize> DiscreteLagrangian<Euclidean<DIM>, DIM> for CoreCell<'_, L> {
    fn cell_lagrangian<D: Scalar>(&self, _cell: &TopCell, y: &[SVector<D, DIM>]) -> D {
        self.0.lagrangian(y)
    }
}

const ANY_CELL: TopCell = TopCell {
    index: 0,
    shape: 0,
    origin: [0; MAX_LATTICE_DIMENSION],
};

/// `∂L/∂y^l` for every vertex `l` (the core's [`vertex_gradient`]).
pub fn cell_gradient<L: CellLagrangian<DIM>, const DIM: usize>(
    lag: &L,
    y: &[SVector<f64, DIM>],
) -> [SVector<f64, DIM>; 4] {
    let core = CoreCell(lag);
    let mut out = [SVector::zeros(); 4];
    for (l, slot) in out.iter_mut().enumerate().take(y.len()) {
        *slot = vertex_gradient::<Euclidean<DIM>, _, DIM>(&core, &ANY_CELL, y, l).1;
    }
    out
}

/// Gradient and Hessian blocks of a cell Lagrangian (the core's
/// [`mixed_block`], one hyper-dual pass per vertex pair `l ≤ m`).
pub fn cell_jet<L: CellLagrangian<DIM>, const DIM: usize>(lag: &L, y: &[SVector<f64, DIM>]) -> CellJet<DIM> {
    let core = CoreCell(lag);
    let n = y.len();
    let mut jet = CellJet {
        vertices: n,
        grad: [SVector::zeros(); 4],
        hess: [[SMatrix::zeros(); 4]; 4],
    };
    for l in 0..n {
        for m in l..n {
            let (gl, h) = mixed_block::<Euclidean<DIM>, _, DIM>(&core, &ANY_CELL, y, l, m);
            if m == l {
                jet.grad[l] = gl;
            }
            jet.hess[l][m] = h;
            jet.hess[m][l] = h.transpose();
        }
    }
    jet
}

/// Value of the cell Lagrangian in `f64`.
pub fn cell_value<L: CellLagrangian<DIM>, const DIM: usize>(lag: &L, y: &[SVector<f64, DIM>]) -> f64 {
    lag.lagrangian(y)
}

/// Gather the vertex values of the cell with origin `c`; `None` if a vertex
/// is missing.
pub fn gather<const DIM: usize>(
    shape: CellShape,
    c: Node,
    get: &impl Fn(Node) -> Option<SVector<f64, DIM>>,
) -> Option<[SVector<f64, DIM>; 4]> {
    let mut v = [SVector::zeros(); 4];
    for (l, &(di, dj)) in shape.offsets().iter().enumerate() {
        v[l] = get((c.0 + di, c.1 + dj))?;
    }
    Some(v)
}

/// The discrete Euler–Lagrange field equation (DELf, seed 002 (5.2) and its
/// rectangle analogue) at node `p`: `Σ_l ∂L/∂y^l` over the cells that touch
/// `p` as vertex `l` and whose vertices all exist (`get` returns `None`
/// outside the lattice; free ends thus get the natural condition).
pub fn delf_residual<L: CellLagrangian<DIM>, const DIM: usize>(
    lag: &L,
    get: &impl Fn(Node) -> Option<SVector<f64, DIM>>,
    p: Node,
) -> SVector<f64, DIM> {
    let shape = lag.shape();
    let n = shape.vertices();
    let mut r = SVector::zeros();
    for (l, &(di, dj)) in shape.offsets().iter().enumerate() {
        let c = (p.0 - di, p.1 - dj);
        if let Some(v) = gather(shape, c, get) {
            r += cell_gradient(lag, &v[..n])[l];
        }
    }
    r
}

/// The discrete action (5.1) of a region: `Σ_{cells ⊆ U} L`.
pub fn action<L: CellLagrangian<DIM>, const DIM: usize>(
    lag: &L,
    region: &Region,
    get: &impl Fn(Node) -> Option<SVector<f64, DIM>>,
) -> f64 {
    let shape = lag.shape();
    let n = shape.vertices();
    region
        .cells()
        .into_iter()
        .filter_map(|c| gather(shape, c, get))
        .map(|v| lag.lagrangian(&v[..n]))
        .sum()
}
