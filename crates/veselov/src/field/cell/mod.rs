//! Discrete Lagrangians on complexes (note 003 §1.7): one L_β per top cell,
//! taking the field values at the cell's ordered vertices, written once over
//! the AD scalar; and their exact derivatives in the fibre's chart.
//!
//! * [`vertex_gradient`]: ∂L_β/∂y_l, the covector d_{y_β}L_β ∘ i_{y_l} in the
//!   chart y_l·τ(ξ) (one dual pass of M directions);
//! * [`mixed_block`]: that gradient and its derivative with respect to the
//!   value at another vertex, ∂²L_β/∂y_a∂y_b (hyper-duals), the Jacobian
//!   block of a vertex solve (note 003 §2.4, Def. 4.9).

use nalgebra::{Const, SMatrix, SVector, U1};

use super::fibre::Fibre;
use super::legendre::{CauchyOptions, VertexOutcome};
use crate::ad::Scalar;
use crate::complex::TopCell;
use crate::solve::SmallLu;

mod derivatives;
pub use derivatives::{
    LATER_DIRECTIONS, check_closed_form, exact_gradient, later_gradients, mixed_block, mixed_block_dual, seeds,
    vertex_gradient,
};

/// Largest number of vertices of a top cell the derivative routines accept
/// (simplices up to dimension 15, cubes up to dimension 4).
pub const MAX_CELL_VERTICES: usize = 16;

/// The cells based at a vertex, for [`DiscreteLagrangian::solve_last_vertex`]:
/// `star(σ, out)` writes the vertex values of cell σ into `out` and returns
/// the cell, or `None` when that cell is not part of the action.
pub type VertexStar<'a, P> = dyn Fn(usize, &mut [P]) -> Option<TopCell> + 'a;

/// A discrete Lagrangian density on a complex: L_β(y_{v₀}, …, y_{v_k}) for
/// every top cell β, with values in the fibre `F` (Def. 3.6).
pub trait DiscreteLagrangian<F: Fibre<M>, const M: usize>: Send + Sync {
    /// L_β at the ordered vertex values `y` of `cell` (`y.len()` = the cell's
    /// vertex count).
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[F::Point<D>]) -> D;

    /// Whether ∂L_β/∂y_l can depend on the value at position `k` of `cell`
    /// (default: always). A cell Lagrangian that splits as
    /// L(y₀, y₁, y₂) = f(y₀, y₁) + h(y₀, y₂) (seed 000's triangles) answers
    /// `false` for (l, k) = (1, 2) and (2, 1); the flow marcher then solves
    /// the constraint at a slaved vertex while the other vertex of its cell
    /// is still unknown (note 000 §1 "Degeneracy").
    fn depends(&self, _cell: &TopCell, _l: usize, _k: usize) -> bool {
        true
    }

    /// The exact vertex gradients ∂L_β/∂y_l (l = 0 … k, in the chart
    /// y_l·τ(ξ), as [`vertex_gradient`]) of `cell` at `y` into `out[..=k]`,
    /// when the Lagrangian supplies them; returns `false` (default) to use
    /// the dual-number pass, which stays the reference.
    fn analytic_gradients(&self, _cell: &TopCell, _y: &[F::Point<f64>], _out: &mut [SVector<f64, M>]) -> bool {
        false
    }

    /// The one exact gradient ∂L_β/∂y_l, when the Lagrangian computes it
    /// for less than all of them ([`analytic_gradients`](Self::analytic_gradients),
    /// whose value it must equal bit for bit); `None` (default) otherwise.
    fn analytic_gradient(&self, _cell: &TopCell, _y: &[F::Point<f64>], _l: usize) -> Option<SVector<f64, M>> {
        None
    }

    /// ∂L_β/∂y_a and its derivative with respect to y_b (the block of
    /// [`mixed_block`]) when the Lagrangian computes them itself; `None`
    /// (default) for the hyper-dual pass ([`mixed_block_dual`]), which stays
    /// the reference. The vertex and level solvers use only the block: their
    /// residuals are [`exact_gradient`]'s, whatever the rounding of the
    /// gradient returned here.
    fn analytic_block(
        &self,
        _cell: &TopCell,
        _y: &[F::Point<f64>],
        _a: usize,
        _b: usize,
    ) -> Option<(SVector<f64, M>, SMatrix<f64, M, M>)> {
        None
    }

    /// Whether the cells carry discrete forces (default `false`; then
    /// [`cell_force`](Self::cell_force) is never called).
    fn has_forces(&self) -> bool {
        false
    }

    /// Whether F^l_β may be nonzero at position `l` of a cell (default:
    /// [`has_forces`](Self::has_forces)); sums of the forces skip the
    /// positions where it is not.
    fn has_force_at(&self, _l: usize) -> bool {
        self.has_forces()
    }

    /// The discrete Lagrange–d'Alembert force F^l_β at position `l` of
    /// `cell` (seed 000 §3.1.4, note 000 §8): a covector in the fibre's chart
    /// at y_l, added to ∂L_β/∂y_l in the forced Euler–Lagrange equations
    /// Σ_β (∂L_β/∂y_v + F^{l(v)}_β) = 0. Written over the AD scalar so that
    /// the vertex solves get its exact derivative. Default zero.
    fn cell_force<D: Scalar>(&self, _cell: &TopCell, _y: &[F::Point<D>], _l: usize) -> SVector<D, M> {
        SVector::from_element(D::zero())
    }

    /// F^l_β at every position l of `cell` at once, into `out[..y.len()]`
    /// (zero where [`has_force_at`](Self::has_force_at) says none acts):
    /// the forces the Cauchy marcher stores when a cell's last vertex is
    /// solved. The default calls [`cell_force`](Self::cell_force) once per
    /// position; a model whose positions share work (a logarithm, say) may
    /// compute them together, with the bits of `cell_force` at each.
    fn cell_forces(&self, cell: &TopCell, y: &[F::Point<f64>], out: &mut [SVector<f64, M>]) {
        for (l, f) in out.iter_mut().enumerate().take(y.len()) {
            *f = if self.has_force_at(l) {
                self.cell_force(cell, y, l)
            } else {
                SVector::zeros()
            };
        }
    }

    /// A model's own solve of one vertex equation of the Cauchy integrator
    /// (note 003 §2.4): find z with
    /// Σ_σ (∂L_{(v,σ)}/∂y_v + F⁰_{(v,σ)})(y_v, …, z) = μ over the cells
    /// (v, σ) based at v, whose last vertex is z. `star(σ, out)` writes the
    /// values of cell σ (the last one a placeholder) into `out` and returns
    /// the cell, or `None` when the cell is not part of the action;
    /// `previous` is the value one flow step back, y_{v−Δ} (the generic
    /// first guess is [`Fibre::extrapolate`]`(previous, y_v)`; a model may
    /// take a cheaper one of its own), `mu_scale` the size of μ's terms.
    /// Returns `None` (default) to use the generic Newton in the fibre's
    /// chart ([`solve_legendre`](super::legendre::solve_legendre)), which
    /// stays the reference; an implementation must solve the same equations
    /// to round-off and report its outcome the same way.
    ///
    /// An implementation that has the solved cells' gradients at hand may
    /// also write ∂L_{(v,σ)}/∂y_l (l = 1 … n, with z as the last vertex) into
    /// `gradients[σ(n + 1) + l]` — position 0 and the cells outside the
    /// action zero, as the marcher stores them — and say so in
    /// [`SolvedVertex::gradients_written`]; the marcher then skips its own
    /// evaluation of them. They must be the bits the marcher's own evaluation
    /// would give from the stored value z (a march restored from a
    /// checkpoint recomputes them so). When the Lagrangian has forces,
    /// `gradients` continues with room for the cells' forces in the same
    /// layout, F^l_{(v,σ)} at `gradients[n!(n + 1) + σ(n + 1) + l]`
    /// (l = 0 … n; zero for cells outside the action): an implementation
    /// may write those too, with the bits of
    /// [`cell_forces`](Self::cell_forces) at z, and say so in
    /// [`SolvedVertex::forces_written`].
    fn solve_last_vertex(
        &self,
        _star: &VertexStar<'_, F::Point<f64>>,
        _mu: &SVector<f64, M>,
        _mu_scale: f64,
        _previous: &F::Point<f64>,
        _options: &CauchyOptions,
        _gradients: &mut [SVector<f64, M>],
    ) -> Option<SolvedVertex<F::Point<f64>>> {
        None
    }

    /// The number of vertex equations of one Cauchy level a model solves
    /// together ([`solve_vertex_run`](Self::solve_vertex_run)): 1
    /// (default) for one at a time.
    fn vertex_lanes(&self) -> usize {
        1
    }

    /// Whether [`solve_vertex_run`](Self::solve_vertex_run) takes runs of a
    /// march confined to a window or with prescribed values
    /// ([`VertexRun::confined`]: some cells of a vertex's star outside the
    /// action, read through [`VertexRun::star`]); `false` (default): such
    /// a march solves its vertices one at a time.
    fn solves_confined_runs(&self) -> bool {
        false
    }

    /// A model's own solve of a run of consecutive vertices of one Cauchy
    /// level ([`VertexRun`]), in groups of at most
    /// [`VertexRun::lanes`] vertices solved together: vertex k is the
    /// equation of [`solve_last_vertex`](Self::solve_last_vertex) with the
    /// star `run.star_values(k, σ, ·)`, the momentum `run.lane(k)` and its
    /// cells' gradients written to `gradients[k·stride..]`, its result to
    /// `solved[k]`. Every vertex must get the bits it would get alone,
    /// whatever the others (the marcher's results must not depend on how a
    /// level is split into runs and groups). Returns `false` (default) to
    /// have every vertex of the run solved one at a time instead (whatever
    /// the model wrote is then overwritten).
    fn solve_vertex_run<R>(
        &self,
        _run: &R,
        _options: &CauchyOptions,
        _gradients: &mut [SVector<f64, M>],
        _stride: usize,
        _solved: &mut [SolvedVertex<F::Point<f64>>],
    ) -> bool
    where
        R: VertexRun<F::Point<f64>, M>,
    {
        false
    }

    /// A model's own solve of a flow step (v, Δv) of the flow marcher
    /// ([`FlowMarcher`](super::flow::FlowMarcher)) when Δv lies in exactly
    /// one top cell of v's star, `cell`, as its vertex `position` ≥ 1, with
    /// v as vertex `equation` — 0, or `position` itself for a slaved vertex
    /// (Δv = v): find z with ∂L_β/∂y_equation + F^equation_β = μ at the
    /// values `y` with z at `position` (`y[position]` holds the first
    /// guess). `kept` holds the LU factors of the Newton Jacobian of the
    /// same node's last solve, in whatever coordinates this solve iterates
    /// in (it leaves its own there). Returns
    /// `None` (default) to use the generic Newton in the fibre's chart,
    /// which stays the reference and also takes over a failed solve; an
    /// implementation must solve the same equation to round-off and report
    /// its outcome the same way.
    #[allow(clippy::too_many_arguments)]
    fn solve_cell_vertex(
        &self,
        _cell: &TopCell,
        _y: &[F::Point<f64>],
        _equation: usize,
        _position: usize,
        _mu: &SVector<f64, M>,
        _mu_scale: f64,
        _options: &CauchyOptions,
        _kept: &mut Option<SmallLu<M>>,
    ) -> Option<(F::Point<f64>, VertexOutcome)> {
        None
    }
}

/// Consecutive vertices of one Cauchy level handed to a model's
/// [`DiscreteLagrangian::solve_vertex_run`], vertex k = 0 … `len() − 1`
/// of the run, each with an equation to solve (a vertex outside a window
/// or with a prescribed value is never in a run). Every cell of every
/// vertex of a run is in the action unless the run is
/// [`confined`](Self::confined) (handed only to a model that
/// [solves confined runs](DiscreteLagrangian::solves_confined_runs)).
pub trait VertexRun<P, const M: usize> {
    /// The number of vertices of the run.
    fn len(&self) -> usize;

    /// Whether the run has no vertex.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The most vertices the model may solve together (≥ 1).
    fn lanes(&self) -> usize;

    /// The lattice dimension n (a cell has n + 1 vertices, a star n! cells).
    fn dimension(&self) -> usize;

    /// The values of the cell σ based at vertex k at its positions
    /// 0 … n into `out[..=n]`, the last (the unknown y_{Δv}) a placeholder.
    fn star_values(&self, k: usize, sigma: usize, out: &mut [P]);

    /// The cell σ based at vertex k: its origin in the lattice (for a
    /// density that depends on position) and its shape, the same at every
    /// vertex of the run (a run lies on a translation-invariant lattice).
    fn star_cell(&self, k: usize, sigma: usize) -> TopCell;

    /// Vertex k's momentum μ_v, the size of its terms and y_{v−Δ}.
    fn lane(&self, k: usize) -> VertexLane<P, M>;

    /// Whether some cells of the run's stars may lie outside the action (a
    /// march confined to a window or with prescribed values): they are
    /// then known only through [`star`](Self::star).
    fn confined(&self) -> bool {
        false
    }

    /// The cell σ based at vertex k with its values written as by
    /// [`star_values`](Self::star_values), or `None` when the cell is not
    /// part of the action (or σ ≥ n!): the star of
    /// [`DiscreteLagrangian::solve_last_vertex`].
    fn star(&self, k: usize, sigma: usize, out: &mut [P]) -> Option<TopCell> {
        if sigma >= (1..=self.dimension()).product() {
            return None;
        }
        self.star_values(k, sigma, out);
        Some(self.star_cell(k, sigma))
    }
}

/// One vertex equation of [`DiscreteLagrangian::solve_vertex_run`]:
/// its momentum μ_v, the size of μ_v's terms and the value one flow step
/// back, y_{v−Δ}.
#[derive(Clone, Copy, Debug)]
pub struct VertexLane<P, const M: usize> {
    /// μ_v.
    pub mu: SVector<f64, M>,
    /// The size of μ_v's terms.
    pub mu_scale: f64,
    /// y_{v−Δ}.
    pub previous: P,
}

/// A vertex solved by [`DiscreteLagrangian::solve_last_vertex`].
#[derive(Clone, Copy, Debug)]
pub struct SolvedVertex<P> {
    /// The last vertex's value z (unspecified on failure: the marcher
    /// then keeps its state).
    pub value: P,
    /// The solve's outcome.
    pub outcome: VertexOutcome,
    /// Whether the solved cells' gradients at positions 1 … n were written.
    pub gradients_written: bool,
    /// Whether the solved cells' forces were written (after the gradients).
    pub forces_written: bool,
}

/// F^l_β at the vertex values `y` and its derivative with respect to the
/// value at position `b`: `J[(i, j)] = ∂/∂ζ_j F^l_i` at y_b·τ(ζ), ζ = 0.
pub fn force_block<F, L, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    l: usize,
    b: usize,
) -> (SVector<f64, M>, SMatrix<f64, M, M>)
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    let k = y.len();
    debug_assert!(k <= MAX_CELL_VERTICES && l < k && b < k);
    let seeded = F::retract_seeded(&y[b], &seeds::<f64, M>());
    let f = with_values(
        k,
        |i| if i == b { seeded } else { F::lift(&y[i]) },
        |v| lag.cell_force(cell, v, l),
    );
    let mut block = SMatrix::<f64, M, M>::zeros();
    for i in 0..M {
        block.set_row(i, &f[i].eps.unwrap_generic(Const::<M>, U1).transpose());
    }
    (f.map(|x| x.re), block)
}

/// F^l_β at `f64` vertex values.
pub fn vertex_force<F, L, const M: usize>(lag: &L, cell: &TopCell, y: &[F::Point<f64>], l: usize) -> SVector<f64, M>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    lag.cell_force(cell, y, l)
}

/// Adds the terms a vertex Newton sums over the cells holding its unknown
/// y_b into `sum`: ∂L_β/∂y_a, then F^a_β when the Lagrangian has forces,
/// with their derivative in y_b added into `jacobian` when one is asked for
/// ([`mixed_block`], [`force_block`]); and their largest entries into
/// `size`. The terms are always [`exact_gradient`]'s and [`vertex_force`]'s,
/// the ones the momenta are made of, never the values a block evaluation
/// returns beside its block: those are rounded otherwise (the hyper-dual
/// pass on a Lie group differs in the last bits), and Newton would zero a
/// neighbouring equation (see [`crate::field::level_solve`]).
pub(crate) fn add_vertex_terms<F, L, const M: usize>(
    lag: &L,
    cell: &TopCell,
    y: &[F::Point<f64>],
    (a, b): (usize, usize),
    sum: &mut SVector<f64, M>,
    size: &mut f64,
    mut jacobian: Option<&mut SMatrix<f64, M, M>>,
) where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M> + ?Sized,
{
    if let Some(j) = jacobian.as_deref_mut() {
        *j += mixed_block::<F, L, M>(lag, cell, y, a, b).1;
    }
    let g = exact_gradient::<F, L, M>(lag, cell, y, a);
    *sum += g;
    *size += g.amax();
    if lag.has_forces() {
        if let Some(j) = jacobian {
            *j += force_block::<F, L, M>(lag, cell, y, a, b).1;
        }
        let f = vertex_force::<F, L, M>(lag, cell, y, a);
        *sum += f;
        *size += f.amax();
    }
}

/// Vertex counts of the common cells (triangles, rectangles, tetrahedra):
/// their lifted values live in an array of this size, not
/// [`MAX_CELL_VERTICES`] (dual-number points are large, and copying unused
/// slots dominated the cost of a derivative pass).
pub(super) const SMALL_CELL: usize = 4;

/// Calls `f` on the `k` values `value(0) … value(k − 1)` held in a stack
/// array just large enough for common cells.
pub(crate) fn with_values<P: Copy, R>(k: usize, value: impl Fn(usize) -> P, f: impl FnOnce(&[P]) -> R) -> R {
    debug_assert!((1..=MAX_CELL_VERTICES).contains(&k));
    if k <= SMALL_CELL {
        let v: [P; SMALL_CELL] = std::array::from_fn(|i| value(i.min(k - 1)));
        f(&v[..k])
    } else {
        let v: [P; MAX_CELL_VERTICES] = std::array::from_fn(|i| value(i.min(k - 1)));
        f(&v[..k])
    }
}
