//! The Cauchy integrator of seed 003 §4 on a spatially periodic CFK lattice
//! of any dimension n, with the flow Δv = v + (1,…,1) (Remark 4.12).
//!
//! Cauchy data are 2n consecutive weight levels k₀ … k₀ + 2n − 1. Solving
//! EL_v = 0 at every vertex v of level k determines level k + n vertex by
//! vertex: EL_v = Leg_v(y_{Δv}) − μ_v (4.4) with
//!
//! * μ_v = −Σ_{β ∈ S_v ∖ S_v^Δ} ∂L_β/∂y_v (4.2), known from earlier levels,
//! * Leg_v(z) = Σ_{σ ∈ Sym(n)} ∂L_{(v,σ)}/∂y_v (4.3), the n! simplices based
//!   at v, all of which contain Δv as their last vertex,
//!
//! solved by Newton in the fibre's chart z·τ(ζ) with the exact Jacobian
//! Σ_σ ∂²L_{(v,σ)}/∂y_v∂y_{Δv} (Def. 4.9), from the linear extrapolation
//! y_v·τ(log(y_{v−Δ}, y_v)), to round-off. Where the marcher solves a
//! vertex itself (a model without a solve of its own), Newton starts from the
//! factors of the Jacobian the solve at the same point kept one flow step
//! before and evaluates a fresh one only when an iteration contracts less
//! than fourfold; from a step that contracts less than 100-fold on, the
//! inverse is corrected by Broyden's update at each step, and the
//! corrected Jacobian is the one kept for the next solve when the solve
//! met the tolerance ([`CauchyMarcher::with_jacobian_reuse`]).
//!
//! Each cell's vertex gradients are computed once, when its last vertex is
//! solved, and kept in a ring of n + 1 base levels; μ_v gathers them in a
//! fixed order. The vertices of one level are solved in parallel (rayon, in
//! chunks sized from the previous level's cost per vertex), in groups of
//! vertices where the model solves several at once
//! ([`DiscreteLagrangian::vertex_lanes`], in runs handed to
//! [`DiscreteLagrangian::solve_vertex_run`]; in a march confined to a window
//! or with prescribed values, only to a model that
//! [solves confined runs](DiscreteLagrangian::solves_confined_runs), each run
//! cut at the vertices without an equation), and every vertex's arithmetic is
//! independent of the partition and of the grouping, so results are
//! bit-identical for every thread count. Storage is allocated once: 2n + 1
//! levels of values, n + 1 levels of cell gradients and n levels of kept
//! Jacobian factors; nothing is allocated inside a level.
//!
//! On the 2-D lattice the march may be confined to a finite body
//! ([`MaterialWindow`], [`CauchyMarcher::with_window`]): only the triangles
//! inside the window enter the action, so the end vertices solve their
//! truncated stars; vertices outside keep their values and are never read.

use std::sync::Arc;

use nalgebra::SVector;

use super::cell::{DiscreteLagrangian, MAX_CELL_VERTICES, SolvedVertex};
use super::fibre::Fibre;
use super::legendre::VertexOutcome;
pub use super::legendre::{CauchyOptions, LevelReport};
use crate::complex::{CfkTorus, LevelReduction, MAX_LATTICE_DIMENSION, MaterialWindow, TopCell};
use crate::solve::SmallLu;
use crate::{Error, Result};

mod build;
mod checkpoint;
mod level;
mod momentum;
mod run;
mod terms;
pub use momentum::STRADDLING_BLOCK;

/// The most vertices a model solves together
/// ([`DiscreteLagrangian::vertex_lanes`]).
const MAX_VERTEX_LANES: usize = 8;

/// What the solve of one vertex v leaves beside its value and its cells'
/// terms: the solve's outcome and, with forces, Σ_β F^{l(v)}_β over the
/// cells through v (all known once v's own cells are), which
/// [`CauchyMarcher::level_impulses`] pairs with the generators.
#[derive(Clone, Copy)]
struct VertexResult<const M: usize> {
    outcome: VertexOutcome,
    force: SVector<f64, M>,
    /// The factors of the Newton Jacobian the marcher's own vertex solve
    /// ended with (`None` for a model's own solve), kept for the solve at
    /// the same point n levels later ([`CauchyMarcher::kept`]).
    factors: Option<SmallLu<M>>,
}

/// Where a level's vertices read ([`CauchyMarcher::level_rows`]): the
/// values of the levels w … w + n, at `values[l]` in the value ring, those
/// of level w − n (y_{v−Δ}) at `previous`, and the stored terms of the
/// cells based at the levels w − j (j = 1 … n), in the gradient slot
/// `grads[j]`.
#[derive(Clone, Copy)]
struct LevelRows {
    values: [usize; MAX_LATTICE_DIMENSION + 1],
    previous: usize,
    grads: [usize; MAX_LATTICE_DIMENSION + 1],
    /// The level w.
    level: i64,
    /// With a window, its reduction of level w ([`MaterialWindow::level_reduction`]).
    reduction: Option<LevelReduction>,
}

/// How a march shares each level among the threads of the pool it runs in
/// ([`CauchyMarcher::with_level_splitting`]). Which thread solves a vertex
/// never changes what is computed: the results are the same, bit for bit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LevelSplitting {
    /// Split a level when its work, measured on the levels solved whole,
    /// is worth a hand-over to the pool, and while split levels measure
    /// faster than whole ones (remeasured every 128 levels). The first two
    /// levels are solved whole.
    #[default]
    Measured,
    /// Split every level among the pool's threads, whatever it costs (to
    /// check that the results do not depend on the thread count, or to
    /// time the hand-over).
    Always,
}

/// A vertex (w, i) as the base of its cells ([`CauchyMarcher::base`]).
#[derive(Clone, Copy)]
struct Base {
    /// The in-level index i.
    index: usize,
    /// Canonical coordinates (the window's representative).
    origin: [i64; MAX_LATTICE_DIMENSION],
    /// With a window, the material point of `origin`, the window's
    /// representative ([`MaterialWindow::unwrapped_point`]); 0 without.
    material: i64,
}

/// The vertex-by-vertex Cauchy integrator on a periodic CFK lattice.
pub struct CauchyMarcher<F: Fibre<M>, L, const M: usize> {
    lag: L,
    torus: CfkTorus,
    perms: Vec<[usize; MAX_LATTICE_DIMENSION]>,
    options: CauchyOptions,
    /// Values of levels k − n … k + n, slot w mod (2n + 1).
    values: Vec<F::Point<f64>>,
    /// Gradients of the cells based at levels k − n … k, slot w mod (n + 1)
    /// (one buffer per slot: a solved level's buffer is swapped in, not
    /// copied); per base vertex n!·(n + 1) vectors, cell σ then position,
    /// followed, when the Lagrangian has forces, by the cells' forces F^l_β
    /// in the same layout ([`stride`](Self::stride) vectors in all), stored
    /// when each cell's last vertex is solved.
    grads: Vec<Vec<SVector<f64, M>>>,
    next_values: Vec<F::Point<f64>>,
    next_grads: Vec<SVector<f64, M>>,
    results: Vec<VertexResult<M>>,
    /// The model's results of a level solved in runs
    /// ([`DiscreteLagrangian::solve_vertex_run`]), one per vertex.
    solved: Vec<SolvedVertex<F::Point<f64>>>,
    /// The level whose vertex forces `results` hold (the last level solved
    /// in full), if any.
    forces_level: Option<i64>,
    /// The factors of the Newton Jacobians of the marcher's own vertex
    /// solves (`solve_vertex_generic`), by level modulo n and in-level
    /// index: the solve of vertex (w, i) leaves its factors at
    /// `kept[w mod n][i]`, and the solve at the same point n levels later,
    /// the vertex (w + n, up(i, 0, n)), starts from them
    /// ([`solve_legendre_from`](super::legendre::solve_legendre_from): refreshed when an iteration contracts less
    /// than fourfold; after a solve's secant steps to the tolerance, the
    /// factors of the Jacobian its Broyden updates made). Per vertex, so the
    /// same bits on any thread count; saved in checkpoints, so a restored
    /// march continues bit for bit. A
    /// slot is empty while its level kept nothing (a model that solves its
    /// vertices itself never fills one); its room is reserved at build.
    kept: Vec<Vec<Option<SmallLu<M>>>>,
    /// Whether the marcher's own vertex solves start from the kept factors
    /// ([`with_jacobian_reuse`](Self::with_jacobian_reuse)).
    reuse_jacobians: bool,
    /// The level at which the marcher was built or restored: the forces of
    /// the cells based below it are not stored, so a level impulse is
    /// defined from the level after it on ([`level_impulses`](Self::level_impulses)).
    start_level: i64,
    /// Wall time per vertex of the last level solved on one thread (ns;
    /// `None` before the first), which sizes the parallel chunks
    /// ([`level::CHUNK_WORK_NS`]).
    vertex_ns: Option<f64>,
    /// Wall time per vertex of the levels split among threads, the
    /// hand-over to the pool included, averaged with weight 1/8 for the
    /// newest (a probe's split level restarts the average; ns; `None`
    /// before the first): it decides whether to split
    /// (`level::chosen_chunk`).
    split_ns: Option<f64>,
    /// Levels solved on one thread so far (saturating): the first is not
    /// trusted to size the chunks (its caches are cold).
    whole_levels: u32,
    splitting: LevelSplitting,
    level: i64,
    /// In-level index of v + e_{σ(0)} + … + e_{σ(l−1)}: `up[(i·n! + σ)·(n+1) + l]`.
    up: Vec<u32>,
    /// In-level index of v − e_{σ(0)} − … − e_{σ(l−1)}: `down[(i·n! + σ)·(n+1) + l]`.
    down: Vec<u32>,
    /// Where μ_v of v = (·, i) finds its terms ([`momentum`](Self::momentum)):
    /// the term of the cell (u, σ) whose vertex j ≥ 1 is v sits at
    /// `momentum_terms[(i·n + j − 1)·n! + σ]` = down(i, σ, j)·stride + σ·(n + 1) + j
    /// in the gradient slot of level w − j (the gather needs no index
    /// arithmetic).
    momentum_terms: Vec<u32>,
    /// Canonical coordinates of each in-level vertex at level 0.
    origins: Vec<[i64; MAX_LATTICE_DIMENSION]>,
    /// The finite body the march is confined to, if any.
    window: Option<MaterialWindow>,
    /// Prescribed values (Dirichlet data), by the canonical coordinates of the vertex.
    dirichlet: Option<Dirichlet<F::Point<f64>>>,
    /// The most vertices solved together ([`with_vertex_lanes`](Self::with_vertex_lanes)).
    lanes_cap: usize,
}

/// Dirichlet data of a march: the prescribed value at the vertex with the
/// given canonical lattice coordinates, or `None` where the field is free.
pub type Dirichlet<P> = Arc<dyn Fn(&[i64]) -> Option<P> + Send + Sync>;

impl<F, L, const M: usize> CauchyMarcher<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// A marcher from the Cauchy data `data[l]` = the values of level
    /// `first_level + l`, l = 0 … 2n − 1, each in in-level index order.
    pub fn new(
        lag: L,
        torus: CfkTorus,
        first_level: i64,
        data: &[Vec<F::Point<f64>>],
        options: CauchyOptions,
    ) -> Result<Self> {
        Self::build(lag, torus, first_level, data, options, None)
    }

    /// A marcher confined to the finite body `window` (2-D lattice): the
    /// action keeps only the triangles inside the window (free ends). The
    /// Cauchy data are as for [`CauchyMarcher::new`]; values at vertices
    /// outside the window are never read (any finite value will do).
    ///
    /// # Errors
    /// As [`CauchyMarcher::new`], and [`Error::InvalidParameter`] naming
    /// `period` if the window was made for another lattice period.
    pub fn with_window(
        lag: L,
        torus: CfkTorus,
        first_level: i64,
        data: &[Vec<F::Point<f64>>],
        options: CauchyOptions,
        window: MaterialWindow,
    ) -> Result<Self> {
        if torus.dimension() != 2 || torus.periods()[0] != window.period() {
            return Err(Error::InvalidParameter {
                name: "period".into(),
                value: format!("{:?}", torus.periods()),
                reason: format!(
                    "the material window was made for a 2-D lattice of period {}",
                    window.period()
                ),
            });
        }
        Self::build(lag, torus, first_level, data, options, Some(window))
    }

    /// Prescribes the field at some vertices (Dirichlet data, e.g. a clamped
    /// or driven end of a rod): whenever the march reaches a vertex Δv for
    /// which `data` returns a value (given the canonical coordinates of Δv,
    /// with a window the representative of its material point), that value
    /// is taken instead of solving EL_v = 0; the equation at v then holds
    /// with the reaction of the constraint, which is not computed. The
    /// Cauchy data must agree with `data` (they are not overwritten).
    #[must_use]
    pub fn with_dirichlet(mut self, data: Dirichlet<F::Point<f64>>) -> Self {
        self.dirichlet = Some(data);
        self
    }

    /// How the levels are shared among the threads of the pool the march
    /// runs in ([`LevelSplitting`]; the default measures). The results do
    /// not depend on it, bit for bit.
    #[must_use]
    pub fn with_level_splitting(mut self, splitting: LevelSplitting) -> Self {
        self.splitting = splitting;
        self
    }

    /// Caps the number of vertices of a level the model solves together
    /// ([`DiscreteLagrangian::vertex_lanes`]; 1: one at a time). The
    /// results do not depend on it, bit for bit; the default takes the
    /// model's number (at most 8).
    #[must_use]
    pub fn with_vertex_lanes(mut self, lanes: usize) -> Self {
        self.lanes_cap = lanes.clamp(1, MAX_VERTEX_LANES);
        self
    }

    /// Whether the marcher's own vertex solves (for a model without a solve
    /// of its own) start from the factors of the Newton Jacobian that the
    /// solve at the same point kept n levels before, refreshing them only
    /// when an iteration contracts less than fourfold, and correcting their
    /// inverse by Broyden's update from each step once one contracts less
    /// than 100-fold, the corrected Jacobian then kept for the next solve
    /// when the solve met the tolerance (`true`, the default: far fewer Jacobians for a little
    /// more iterations), or evaluate a Jacobian at every vertex (`false`). The equations and the
    /// tolerance are the same either way; the bits are not. A solve that
    /// ends on an old Jacobian converges linearly, so its last iterate lies
    /// just within the tolerance, where the last step of a fresh Jacobian
    /// squares the error: in the tests a 2+1 field so marched stays within
    /// 1e-13 of the closed-form solve's field over 120 levels, against
    /// 6e-15 with a Jacobian at every vertex.
    #[must_use]
    pub fn with_jacobian_reuse(mut self, on: bool) -> Self {
        self.reuse_jacobians = on;
        if !on {
            self.kept.iter_mut().for_each(Vec::clear);
        }
        self
    }

    /// The periodic lattice.
    pub fn torus(&self) -> &CfkTorus {
        &self.torus
    }

    /// The finite body the march is confined to, if any.
    pub fn window(&self) -> Option<&MaterialWindow> {
        self.window.as_ref()
    }

    /// Whether vertex (w, i) takes part in the march (always, without a window).
    pub fn is_active(&self, w: i64, i: usize) -> bool {
        self.window.as_ref().is_none_or(|m| m.contains(&self.origin(w, i)))
    }

    /// [`is_active`](Self::is_active) for a vertex of the level of `rows`.
    #[inline]
    fn is_active_in(&self, rows: &LevelRows, i: usize) -> bool {
        self.base_active(&self.base(rows, i))
    }

    /// Whether the simplex (v, σ) based at v ([`base`](Self::base)) enters
    /// the action.
    #[inline]
    fn cell_active_at(&self, base: &Base, sigma: usize) -> bool {
        self.window
            .as_ref()
            .is_none_or(|m| m.contains_cell_at(base.material, &self.perms[sigma]))
    }

    /// The vertex (w, i) as the base of its cells: its index and
    /// canonical coordinates, computed once for all of them.
    /// `rows` are the [`level_rows`](Self::level_rows) of v's level.
    #[inline]
    fn base(&self, rows: &LevelRows, i: usize) -> Base {
        let origin = self.origin_in(rows, i);
        Base {
            index: i,
            origin,
            material: self.window.as_ref().map_or(0, |m| m.unwrapped_point(&origin)),
        }
    }

    /// Whether the vertex `base` takes part in the march (always, without
    /// a window).
    #[inline]
    fn base_active(&self, base: &Base) -> bool {
        self.window.as_ref().is_none_or(|m| m.contains_point(base.material))
    }

    /// The next level whose equations [`step`](Self::step) solves.
    pub fn level(&self) -> i64 {
        self.level
    }

    /// The highest known level (`level() + n − 1`).
    pub fn top_level(&self) -> i64 {
        self.level + self.torus.dimension() as i64 - 1
    }

    /// The values of a known level `w` (`level() − n ≤ w ≤ top_level()`).
    pub fn level_values(&self, w: i64) -> Option<&[F::Point<f64>]> {
        let n = self.torus.dimension() as i64;
        if w < self.level - n || w > self.top_level() {
            return None;
        }
        let size = self.torus.level_size();
        let slot = self.value_slot(w);
        Some(&self.values[slot * size..(slot + 1) * size])
    }

    /// In-level index of vertex l of the simplex (v, σ), v = (·, i).
    #[inline]
    fn up(&self, i: usize, sigma: usize, l: usize) -> usize {
        let n = self.torus.dimension();
        self.up[(i * self.perms.len() + sigma) * (n + 1) + l] as usize
    }

    /// In-level index of the base of the simplex (u, σ) whose vertex l is v = (·, i).
    #[inline]
    fn down(&self, i: usize, sigma: usize, l: usize) -> usize {
        let n = self.torus.dimension();
        self.down[(i * self.perms.len() + sigma) * (n + 1) + l] as usize
    }

    /// Canonical coordinates of the vertex (w, i); with a window, the
    /// representative whose material point lies in 0 ≤ p < 2N.
    fn origin(&self, w: i64, i: usize) -> [i64; MAX_LATTICE_DIMENSION] {
        self.origin_at(w, self.window.as_ref().map(|m| m.level_reduction(w)), i)
    }

    /// [`origin`](Self::origin) of a vertex of the level of `rows`, whose
    /// window reduction they hold (no division per vertex).
    #[inline(always)]
    fn origin_in(&self, rows: &LevelRows, i: usize) -> [i64; MAX_LATTICE_DIMENSION] {
        self.origin_at(rows.level, rows.reduction, i)
    }

    /// [`origin`](Self::origin) with level w's window reduction given
    /// (`Some` exactly with a window).
    #[inline(always)]
    fn origin_at(&self, w: i64, reduction: Option<LevelReduction>, i: usize) -> [i64; MAX_LATTICE_DIMENSION] {
        let (o, last) = (&self.origins[i], self.torus.dimension() - 1);
        if let (Some(m), Some(level)) = (&self.window, reduction) {
            // The origins are the window's representatives at level 0.
            return m.unwrap_shifted(o, level);
        }
        // Added whole (in vector lanes) rather than one element stored into
        // a copy: an element stored and then read back within a vector
        // load stalls on store-to-load forwarding.
        let shift: [i64; MAX_LATTICE_DIMENSION] = std::array::from_fn(|k| if k == last { w } else { 0 });
        std::array::from_fn(|k| o[k] + shift[k])
    }

    fn value_slot(&self, w: i64) -> usize {
        w.rem_euclid(2 * self.torus.dimension() as i64 + 1) as usize
    }

    fn grad_slot(&self, w: i64) -> usize {
        w.rem_euclid(self.torus.dimension() as i64 + 1) as usize
    }

    fn value(&self, w: i64, i: usize) -> F::Point<f64> {
        self.values[self.value_slot(w) * self.torus.level_size() + i]
    }

    /// Where the values of the levels w … w + n start in the value ring
    /// (slot(w + l)·(level size) at index l), where those of level w − n
    /// start, and the gradient slots of the levels w − j (at index
    /// j = 1 … n). The vertices of a level share
    /// them: computed once, not per vertex or cell.
    #[inline(always)]
    fn level_rows(&self, w: i64) -> LevelRows {
        let (n, size) = (self.torus.dimension(), self.torus.level_size());
        let slot = self.value_slot(w);
        let ring = 2 * n + 1;
        let mut rows = LevelRows {
            values: [0; MAX_LATTICE_DIMENSION + 1],
            previous: self.value_slot(w - n as i64) * size,
            grads: [0; MAX_LATTICE_DIMENSION + 1],
            level: w,
            reduction: self.window.as_ref().map(|m| m.level_reduction(w)),
        };
        for (l, row) in rows.values.iter_mut().enumerate().take(n + 1) {
            *row = if slot + l >= ring { slot + l - ring } else { slot + l } * size;
        }
        for (j, grads) in rows.grads.iter_mut().enumerate().take(n + 1).skip(1) {
            *grads = self.grad_slot(w - j as i64);
        }
        rows
    }

    /// The values of the cell (v, σ) based at v = (w, i) at its positions
    /// 0 … n into `y[..=n]` (the last one level w + n's), `rows` the
    /// [`level_rows`](Self::level_rows) of level w.
    #[inline(always)]
    fn star_values_at(&self, rows: &LevelRows, i: usize, sigma: usize, y: &mut [F::Point<f64>]) {
        let n = self.torus.dimension();
        let up = &self.up[(i * self.perms.len() + sigma) * (n + 1)..][..=n];
        y[0] = self.values[rows.values[0] + i];
        for l in 1..=n {
            y[l] = self.values[rows.values[l] + up[l] as usize];
        }
    }

    /// The cell (v, σ) based at v ([`base`](Self::base)) and its vertex values
    /// written into `y[..=n]`, the last one replaced by `top` if given;
    /// `rows` are the [`level_rows`](Self::level_rows) of v's level.
    #[inline(always)]
    fn cell_values_at(
        &self,
        rows: &LevelRows,
        base: &Base,
        sigma: usize,
        top: Option<F::Point<f64>>,
        y: &mut [F::Point<f64>],
    ) -> TopCell {
        let n = self.torus.dimension();
        let y = &mut y[..=n];
        self.star_values_at(rows, base.index, sigma, y);
        if let Some(z) = top {
            y[n] = z;
        }
        TopCell {
            index: 0,
            shape: sigma,
            origin: base.origin,
        }
    }
}

// The cell buffers hold every vertex of a CFK simplex of the largest
// lattice dimension (n + 1 vertices).
const _: () = assert!(MAX_CELL_VERTICES > MAX_LATTICE_DIMENSION);
