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
//! inverse is corrected by Broyden's update at each step
//! ([`CauchyMarcher::with_jacobian_reuse`]).
//!
//! Each cell's vertex gradients are computed once, when its last vertex is
//! solved, and kept in a ring of n + 1 base levels; μ_v gathers them in a
//! fixed order. The vertices of one level are solved in parallel (rayon, in
//! chunks sized from the previous level's cost per vertex), in fixed groups
//! of consecutive vertices where the model solves several at once
//! ([`DiscreteLagrangian::vertex_lanes`]), and every vertex's arithmetic is
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
use rayon::prelude::*;

use super::cell::{
    DiscreteLagrangian, MAX_CELL_VERTICES, SolvedVertex, VertexLane, add_vertex_terms, check_closed_form,
};
use super::complex::{CfkTorus, MAX_LATTICE_DIMENSION, MaterialWindow, TopCell, permutation};
use super::fibre::Fibre;
pub use super::legendre::{CauchyOptions, LevelReport};
use super::legendre::{VertexOutcome, solve_legendre_from};
use crate::solve::SmallLu;
use crate::{Error, Result};

mod checkpoint;
mod momentum;
mod terms;
pub use momentum::STRADDLING_BLOCK;
use terms::Written;

/// One vertex of a level as the solve loop sees it: its index, its new
/// value, its cells' gradients and its result.
type VertexSlot<'a, P, const M: usize> = (usize, ((&'a mut P, &'a mut [SVector<f64, M>]), &'a mut VertexResult<M>));

/// Consecutive vertices of a level solved together: the group's index,
/// their new values, their cells' gradients and their results.
type LaneSlot<'a, P, const M: usize> = (
    usize,
    ((&'a mut [P], &'a mut [SVector<f64, M>]), &'a mut [VertexResult<M>]),
);

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

/// The work one thread takes at least: the chunk is sized from the cost per
/// vertex measured on the last level solved on one thread so that it holds
/// about this much (and at most a thread's share of the level, so that a
/// level worth splitting is split). The first level is always solved on the
/// calling thread (a level solved in parallel is never measured: if the
/// first one were, the chunk would keep its first guess for the whole
/// march). Chunking decides only who solves which vertex, never what is
/// computed: results stay bit-identical for every thread count.
const CHUNK_WORK_NS: f64 = 20_000.0;

/// The least work of a level solved in parallel when the march runs outside
/// the pool (on a thread of its own, e.g. a program's main thread). The
/// hand-over then goes through a sleeping lock: the calling thread blocks
/// until the pool has solved the whole level and is woken up, tens of µs
/// per level; a 41-node loaded rod (about 50 µs per level) ran 30 % slower
/// on two threads than on one when its levels were split.
const PARALLEL_LEVEL_NS: f64 = 150_000.0;

/// The least work of a level solved in parallel when the march runs on a
/// thread of the pool itself ([`crate::run::on_pool`], as the command line
/// runs every scenario): that thread solves its share and hands the rest to
/// the other workers through their queues, a few µs per level. A 100-element
/// rod's levels (about 30 µs each) take 1.7× less wall time on two threads.
const PARALLEL_LEVEL_NS_ON_POOL: f64 = 10_000.0;

/// Vertices whose cells the marcher checks for a closed form that
/// disagrees with the cell Lagrangian when it is built
/// ([`check_closed_form`]).
const CHECKED_VERTICES: usize = 8;

/// Stars whose cells a generic vertex solve gathers once (3! cells, the
/// lattices up to 2+1), of at most [`SMALL_CELL`] vertices each; larger
/// stars gather a cell's values at every evaluation.
const SMALL_STAR: usize = 6;

/// Vertices of a cell of a gathered star (n + 1 ≤ 4).
const SMALL_CELL: usize = 4;

/// Where the values of n + 1 consecutive levels start in the value ring
/// ([`CauchyMarcher::level_rows`]).
type LevelRows = [usize; MAX_LATTICE_DIMENSION + 1];

/// A vertex (w, i) as the base of its cells ([`CauchyMarcher::base`]).
#[derive(Clone, Copy)]
struct Base {
    /// The in-level index i.
    index: usize,
    /// Canonical coordinates (the window's representative).
    origin: [i64; MAX_LATTICE_DIMENSION],
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
    /// The level whose vertex forces `results` hold (the last level solved
    /// in full), if any.
    forces_level: Option<i64>,
    /// The factors of the Newton Jacobians of the marcher's own vertex
    /// solves (`solve_vertex_generic`), by level modulo n and in-level
    /// index: the solve of vertex (w, i) leaves its factors at
    /// `kept[w mod n][i]`, and the solve at the same point n levels later,
    /// the vertex (w + n, up(i, 0, n)), starts from them
    /// ([`solve_legendre_from`]: refreshed when an iteration contracts less
    /// than fourfold; a solve's Broyden corrections stay with that solve,
    /// the factors kept are the evaluated Jacobian's). Per vertex, so the
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
    /// ([`CHUNK_WORK_NS`]).
    vertex_ns: Option<f64>,
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

    fn build(
        lag: L,
        torus: CfkTorus,
        first_level: i64,
        data: &[Vec<F::Point<f64>>],
        options: CauchyOptions,
        window: Option<MaterialWindow>,
    ) -> Result<Self> {
        let n = torus.dimension();
        let size = torus.level_size();
        if data.len() != 2 * n {
            return Err(Error::DimensionMismatch {
                what: "Cauchy data levels (2n consecutive weight levels)".into(),
                expected: 2 * n,
                got: data.len(),
            });
        }
        for (l, level) in data.iter().enumerate() {
            if level.len() != size {
                return Err(Error::DimensionMismatch {
                    what: format!("values of Cauchy level {l}"),
                    expected: size,
                    got: level.len(),
                });
            }
            if let Some(i) = level.iter().position(|y| !F::is_finite(y)) {
                return Err(Error::NonFinite {
                    what: format!("Cauchy data, level {l}"),
                    index: i,
                    value: f64::NAN,
                });
            }
        }
        if !(options.tolerance > 0.0 && options.tolerance.is_finite()) || options.max_iterations == 0 {
            return Err(Error::InvalidParameter {
                name: "tolerance".into(),
                value: format!("{} (max_iterations {})", options.tolerance, options.max_iterations),
                reason: "the tolerance must be positive and finite and the iteration limit at least 1".into(),
            });
        }
        let cells = torus.simplices_per_vertex();
        let per_vertex = cells * (n + 1);
        let perms: Vec<_> = (0..cells).map(|s| permutation(n, s)).collect();
        if u32::try_from(size).is_err() {
            return Err(Error::InvalidParameter {
                name: "nodes".into(),
                value: size.to_string(),
                reason: "too many vertices per level".into(),
            });
        }
        // Neighbour tables: no division in the vertex loops.
        let mut up = Vec::with_capacity(size * per_vertex);
        let mut down = Vec::with_capacity(size * per_vertex);
        for i in 0..size {
            for perm in &perms {
                for l in 0..=n {
                    up.push(torus.offset_index(i, perm, l, 1) as u32);
                    down.push(torus.offset_index(i, perm, l, -1) as u32);
                }
            }
        }
        let origins = (0..size).map(|i| torus.vertex(0, i)).collect();
        // Ring storage, allocated once; refuse (rather than abort on) a
        // request the machine cannot hold.
        let too_large = |what: &str| Error::InvalidParameter {
            name: "nodes".into(),
            value: size.to_string(),
            reason: format!("the {what} of the march do not fit in memory"),
        };
        let mut values = Vec::new();
        values
            .try_reserve_exact((2 * n + 1).checked_mul(size).ok_or_else(|| too_large("levels"))?)
            .map_err(|_| too_large("levels"))?;
        values.resize((2 * n + 1) * size, data[0][0]);
        let stride = if lag.has_forces() { 2 * per_vertex } else { per_vertex };
        let grad_count = size.checked_mul(stride).ok_or_else(|| too_large("cell gradients"))?;
        // n + 1 ring slots and the buffer the next level is solved into.
        let mut grads = Vec::with_capacity(n + 2);
        for _ in 0..n + 2 {
            let mut slot = Vec::new();
            slot.try_reserve_exact(grad_count)
                .map_err(|_| too_large("cell gradients"))?;
            slot.resize(grad_count, SVector::zeros());
            grads.push(slot);
        }
        let next_grads = grads.pop().unwrap_or_default();
        // u32 offsets: a slot of more than 2³² vectors would not fit in
        // memory anyway.
        if u32::try_from(grad_count).is_err() {
            return Err(too_large("cell gradients"));
        }
        let mut momentum_terms = Vec::with_capacity(size * n * cells);
        for i in 0..size {
            for j in 1..=n {
                for sigma in 0..cells {
                    let u = down[(i * cells + sigma) * (n + 1) + j] as usize;
                    momentum_terms.push((u * stride + sigma * (n + 1) + j) as u32);
                }
            }
        }
        let mut marcher = Self {
            up,
            down,
            momentum_terms,
            origins,
            perms,
            values,
            grads,
            next_values: vec![data[0][0]; size],
            next_grads,
            results: vec![
                VertexResult {
                    outcome: VertexOutcome::default(),
                    force: SVector::zeros(),
                    factors: None,
                };
                size
            ],
            forces_level: None,
            // Room for every slot, so that no level allocates.
            kept: (0..n).map(|_| Vec::with_capacity(size)).collect(),
            reuse_jacobians: true,
            start_level: first_level + n as i64,
            vertex_ns: None,
            lag,
            torus,
            options,
            level: first_level + n as i64,
            window,
            dirichlet: None,
            lanes_cap: MAX_VERTEX_LANES,
        };
        for (l, level) in data.iter().enumerate() {
            let slot = marcher.value_slot(first_level + l as i64);
            marcher.values[slot * size..(slot + 1) * size].copy_from_slice(level);
        }
        marcher.check_closed_forms(first_level)?;
        marcher.fill_gradients();
        Ok(marcher)
    }

    /// [`check_closed_form`] on the cells based at the first
    /// [`CHECKED_VERTICES`] vertices of level `w` in the body (all their
    /// vertices are Cauchy data).
    fn check_closed_forms(&self, w: i64) -> Result<()> {
        let n = self.torus.dimension();
        let mut y = [self.values[self.value_slot(w) * self.torus.level_size()]; MAX_LATTICE_DIMENSION + 1];
        let vertices = (0..self.torus.level_size()).filter(|&i| self.is_active(w, i));
        let rows = self.level_rows(w);
        for i in vertices.take(CHECKED_VERTICES) {
            let at = self.base(w, i);
            for sigma in (0..self.perms.len()).filter(|&s| self.cell_active_at(&at, s)) {
                let cell = self.cell_values_at(&rows, &at, sigma, None, &mut y);
                check_closed_form::<F, L, M>(&self.lag, &cell, &y[..=n], || {
                    format!("cell {sigma} based at vertex {i} of level {w}")
                })?;
            }
        }
        Ok(())
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
    /// than 100-fold (`true`, the default: far fewer Jacobians for a little
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

    /// Whether the simplex (v, σ) based at v ([`base`](Self::base)) enters
    /// the action.
    #[inline]
    fn cell_active_at(&self, base: &Base, sigma: usize) -> bool {
        self.window
            .as_ref()
            .is_none_or(|m| m.contains_cell(&base.origin, &self.perms[sigma]))
    }

    /// The vertex (w, i) as the base of its cells: its index and
    /// canonical coordinates, computed once for all of them.
    #[inline]
    fn base(&self, w: i64, i: usize) -> Base {
        Base {
            index: i,
            origin: self.origin(w, i),
        }
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
    #[inline(always)]
    fn origin(&self, w: i64, i: usize) -> [i64; MAX_LATTICE_DIMENSION] {
        // Added whole (in vector lanes) rather than one element stored into
        // a copy: an element stored and then read back within a vector
        // load stalls on store-to-load forwarding.
        let (o, last) = (&self.origins[i], self.torus.dimension() - 1);
        let shift: [i64; MAX_LATTICE_DIMENSION] = std::array::from_fn(|k| if k == last { w } else { 0 });
        let v = std::array::from_fn(|k| o[k] + shift[k]);
        match &self.window {
            Some(m) => m.unwrap(&v),
            None => v,
        }
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

    /// Where the values of the levels w … w + n start in the value ring:
    /// slot(w + l)·(level size) at index l. The vertices of a level share
    /// them: gathered once, not per cell.
    #[inline(always)]
    fn level_rows(&self, w: i64) -> LevelRows {
        let (n, size) = (self.torus.dimension(), self.torus.level_size());
        let slot = self.value_slot(w);
        let ring = 2 * n + 1;
        let mut rows = [0; MAX_LATTICE_DIMENSION + 1];
        for (l, row) in rows.iter_mut().enumerate().take(n + 1) {
            *row = if slot + l >= ring { slot + l - ring } else { slot + l } * size;
        }
        rows
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
        let i = base.index;
        let y = &mut y[..=n];
        let up = &self.up[(i * self.perms.len() + sigma) * (n + 1)..][..=n];
        y[0] = self.values[rows[0] + i];
        for l in 1..=n {
            y[l] = self.values[rows[l] + up[l] as usize];
        }
        if let Some(z) = top {
            y[n] = z;
        }
        TopCell {
            index: 0,
            shape: sigma,
            origin: base.origin,
        }
    }

    /// Solves EL_v = 0 for y_{Δv}, v = (w, i); returns y_{Δv}, the solve's
    /// outcome and which of the solved cells' terms the model's own solve
    /// already wrote into `terms` ([`DiscreteLagrangian::solve_last_vertex`]);
    /// the marcher's own solve leaves its Jacobian's factors in `factors`.
    /// Outside the window y_{Δv} = y_v (never read).
    fn solve_vertex(
        &self,
        w: i64,
        rows: &LevelRows,
        i: usize,
        terms: &mut [SVector<f64, M>],
        factors: &mut Option<SmallLu<M>>,
    ) -> (F::Point<f64>, VertexOutcome, Written) {
        *factors = None;
        let n = self.torus.dimension();
        // The base's canonical coordinates serve the window test and the star.
        let base = self.base(w, i);
        if !self.window.as_ref().is_none_or(|m| m.contains(&base.origin)) {
            return (self.value(w, i), VertexOutcome::default(), Written::default());
        }
        if let Some(data) = &self.dirichlet {
            let target = self.up(i, 0, n);
            if let Some(z) = data(&self.origin(w + n as i64, target)) {
                return (z, VertexOutcome::default(), Written::default());
            }
        }
        let (mu, mu_scale) = self.momentum(w, i);
        let previous = self.value(w - n as i64, self.down(i, 0, n));
        let star = |sigma: usize, out: &mut [F::Point<f64>]| {
            if sigma >= self.perms.len() || !self.cell_active_at(&base, sigma) {
                return None;
            }
            Some(self.cell_values_at(rows, &base, sigma, None, out))
        };
        if let Some(solved) = self
            .lag
            .solve_last_vertex(&star, &mu, mu_scale, &previous, &self.options, terms)
        {
            let written = Written {
                gradients: solved.gradients_written,
                forces: solved.forces_written,
            };
            return (solved.value, solved.outcome, written);
        }
        // The factors the solve at this point left n levels before.
        *factors = self.kept[w.rem_euclid(n as i64) as usize]
            .get(self.down(i, 0, n))
            .copied()
            .flatten();
        let (z, outcome) = self.solve_vertex_generic(rows, &base, &mu, mu_scale, &previous, factors);
        (z, outcome, Written::default())
    }

    /// The marcher's own Newton for EL_v = 0 at the vertex `base` over its
    /// cells' exact derivatives ([`add_vertex_terms`]), for a model without
    /// a solve of its own, from the Jacobian factors `kept` (left there at
    /// the end). Kept out of line: the derivative passes' dual
    /// numbers take a large stack frame, which the models' own solves
    /// should not pay for.
    #[inline(never)]
    fn solve_vertex_generic(
        &self,
        rows: &LevelRows,
        base: &Base,
        mu: &SVector<f64, M>,
        mu_scale: f64,
        previous: &F::Point<f64>,
        kept: &mut Option<SmallLu<M>>,
    ) -> (F::Point<f64>, VertexOutcome) {
        let n = self.torus.dimension();
        let base = *base;
        let z = F::extrapolate(previous, &self.values[rows[0] + base.index]);
        // A star of up to SMALL_STAR cells gathers its cells' known values
        // once: an iterate only replaces the top vertex. Larger stars gather
        // a cell's values at every evaluation.
        let mut gathered = [None; SMALL_STAR];
        let gather = self.perms.len() <= SMALL_STAR && n < SMALL_CELL;
        if gather {
            for (sigma, slot) in gathered.iter_mut().enumerate().take(self.perms.len()) {
                if self.cell_active_at(&base, sigma) {
                    let mut y = [z; SMALL_CELL];
                    *slot = Some((self.cell_values_at(rows, &base, sigma, None, &mut y), y));
                }
            }
        }
        solve_legendre_from::<F, M>(mu, mu_scale, z, &self.options, kept, |z, mut jac| {
            let (mut leg, mut scale) = (SVector::<f64, M>::zeros(), 0.0);
            if let Some(j) = jac.as_deref_mut() {
                j.fill(0.0);
            }
            let mut y = [*z; MAX_LATTICE_DIMENSION + 1];
            for sigma in 0..self.perms.len() {
                let cell = if gather {
                    let Some((cell, known)) = &gathered[sigma] else {
                        continue;
                    };
                    y[..SMALL_CELL].copy_from_slice(known);
                    y[n] = *z;
                    *cell
                } else if self.cell_active_at(&base, sigma) {
                    self.cell_values_at(rows, &base, sigma, Some(*z), &mut y)
                } else {
                    continue;
                };
                add_vertex_terms::<F, L, M>(
                    &self.lag,
                    &cell,
                    &y[..=n],
                    (0, n),
                    &mut leg,
                    &mut scale,
                    jac.as_deref_mut(),
                );
            }
            (leg, scale)
        })
    }

    /// The vertices of a level solved together: the model's
    /// [`DiscreteLagrangian::vertex_lanes`] (at most [`MAX_VERTEX_LANES`]),
    /// 1 with a window or Dirichlet data (whose vertices differ from one
    /// another).
    fn vertex_lanes(&self) -> usize {
        if self.window.is_some() || self.dirichlet.is_some() {
            return 1;
        }
        self.lag.vertex_lanes().clamp(1, self.lanes_cap)
    }

    /// The solve of vertex (w, i) (y_{Δv}, its outcome and which of its
    /// cells' terms the solve wrote) into its result, with its cells' terms
    /// and, with forces, Σ_β F^{l(v)}_β.
    #[inline]
    fn store_vertex(
        &self,
        w: i64,
        rows: &LevelRows,
        i: usize,
        (z, outcome, written): (F::Point<f64>, VertexOutcome, Written),
        terms: &mut [SVector<f64, M>],
        result: &mut VertexResult<M>,
    ) {
        result.outcome = outcome;
        if outcome.failure.is_none() {
            // Checked here, not only in `cell_terms`: its stack frame alone
            // cost about 50 instructions per vertex.
            if !written.covers(self.lag.has_forces()) {
                self.cell_terms(w, rows, i, Some(z), written, terms);
            }
            if self.lag.has_forces() && self.is_active(w, i) {
                result.force = self.vertex_force(w, i, terms);
            }
        }
    }

    /// Solves the vertices `first …` of level `w` (as many as `values`)
    /// together by the model's [`DiscreteLagrangian::solve_last_vertices`]
    /// and stores each ([`store_vertex`](Self::store_vertex)); `false`
    /// (nothing solved) when the model declines.
    fn solve_lanes(
        &self,
        w: i64,
        rows: &LevelRows,
        first: usize,
        values: &mut [F::Point<f64>],
        terms: &mut [SVector<f64, M>],
        results: &mut [VertexResult<M>],
    ) -> bool {
        let n = self.torus.dimension();
        let stride = self.stride();
        let count = values.len().min(MAX_VERTEX_LANES);
        let origin = self.base(w, first);
        let mut bases = [origin; MAX_VERTEX_LANES];
        let placeholder = self.value(w, first);
        let mut lanes = [VertexLane {
            mu: SVector::zeros(),
            mu_scale: 0.0,
            previous: placeholder,
        }; MAX_VERTEX_LANES];
        for (l, (base, lane)) in bases.iter_mut().zip(lanes.iter_mut()).enumerate().take(count) {
            let i = first + l;
            *base = self.base(w, i);
            (lane.mu, lane.mu_scale) = self.momentum(w, i);
            lane.previous = self.value(w - n as i64, self.down(i, 0, n));
        }
        let star = |l: usize, sigma: usize, out: &mut [F::Point<f64>]| {
            (sigma < self.perms.len()).then(|| self.cell_values_at(rows, &bases[l], sigma, None, out))
        };
        let mut solved = [SolvedVertex {
            value: placeholder,
            outcome: VertexOutcome::default(),
            gradients_written: false,
            forces_written: false,
        }; MAX_VERTEX_LANES];
        if !self.lag.solve_last_vertices(
            &star,
            &lanes[..count],
            &self.options,
            terms,
            stride,
            &mut solved[..count],
        ) {
            return false;
        }
        for (l, ((value, terms), result)) in values.iter_mut().zip(terms.chunks_mut(stride)).zip(results).enumerate() {
            let s = &solved[l];
            let written = Written {
                gradients: s.gradients_written,
                forces: s.forces_written,
            };
            *value = s.value;
            result.factors = None;
            self.store_vertex(w, rows, first + l, (s.value, s.outcome, written), terms, result);
        }
        true
    }

    /// The vertices per parallel chunk of a level of `size` vertices, `size`
    /// for a level solved on the calling thread alone: one thread in the
    /// pool, no level measured yet, or a level too cheap to split from where
    /// the march runs ([`PARALLEL_LEVEL_NS`] outside the pool,
    /// [`PARALLEL_LEVEL_NS_ON_POOL`] on one of its threads).
    fn parallel_chunk(&self, size: usize) -> usize {
        let threads = rayon::current_num_threads();
        let Some(vertex_ns) = self.vertex_ns else {
            return size;
        };
        let least = if rayon::current_thread_index().is_some() {
            PARALLEL_LEVEL_NS_ON_POOL
        } else {
            PARALLEL_LEVEL_NS
        };
        if threads < 2 || vertex_ns * (size as f64) < least {
            return size;
        }
        ((CHUNK_WORK_NS / vertex_ns).ceil() as usize).clamp(1, (size / threads).max(1))
    }

    /// Solves every vertex of level `level()`, which determines level
    /// `level() + n`, and advances. On failure nothing is advanced: the
    /// marcher keeps its last complete state, and the error names the first
    /// failing vertex (in index order, whatever the thread count).
    pub fn step(&mut self) -> Result<LevelReport> {
        let n = self.torus.dimension();
        let size = self.torus.level_size();
        let stride = self.stride();
        let w = self.level;
        let mut next_values = std::mem::take(&mut self.next_values);
        let mut next_grads = std::mem::take(&mut self.next_grads);
        let mut results = std::mem::take(&mut self.results);
        self.forces_level = None;
        let started = std::time::Instant::now();
        let chunk = self.parallel_chunk(size);
        let parallel = chunk < size;
        // The level's rows in the value ring, shared by all its vertices.
        let rows = self.level_rows(w);
        {
            let this = &*self;
            let solve = |(i, ((value, terms), result)): VertexSlot<'_, F::Point<f64>, M>| {
                let (z, o, written) = this.solve_vertex(w, &rows, i, terms, &mut result.factors);
                *value = z;
                this.store_vertex(w, &rows, i, (z, o, written), terms, result);
            };
            let lanes = self.vertex_lanes();
            if lanes > 1 {
                let solve_lanes = |(g, ((values, terms), results)): LaneSlot<'_, F::Point<f64>, M>| {
                    let first = g * lanes;
                    if !this.solve_lanes(w, &rows, first, values, terms, results) {
                        for (l, ((value, terms), result)) in values
                            .iter_mut()
                            .zip(terms.chunks_mut(stride))
                            .zip(results.iter_mut())
                            .enumerate()
                        {
                            solve((first + l, ((value, terms), result)));
                        }
                    }
                };
                if parallel {
                    next_values
                        .par_chunks_mut(lanes)
                        .zip(next_grads.par_chunks_mut(stride * lanes))
                        .zip(results.par_chunks_mut(lanes))
                        .with_min_len(chunk.div_ceil(lanes))
                        .enumerate()
                        .for_each(solve_lanes);
                } else {
                    next_values
                        .chunks_mut(lanes)
                        .zip(next_grads.chunks_mut(stride * lanes))
                        .zip(results.chunks_mut(lanes))
                        .enumerate()
                        .for_each(solve_lanes);
                }
            } else if parallel {
                next_values
                    .par_iter_mut()
                    .zip(next_grads.par_chunks_mut(stride))
                    .zip(results.par_iter_mut())
                    .with_min_len(chunk)
                    .enumerate()
                    .for_each(solve);
            } else {
                // One thread, or one chunk: no hand-over to the pool at all.
                next_values
                    .iter_mut()
                    .zip(next_grads.chunks_mut(stride))
                    .zip(results.iter_mut())
                    .enumerate()
                    .for_each(solve);
            }
        }
        // The cost per vertex, measured on a level solved on this thread
        // alone (a parallel level's wall time also holds the hand-over to
        // the pool, which would shrink the chunks and feed on itself).
        let vertex_ns = started.elapsed().as_nanos() as f64 / size.max(1) as f64;
        if !parallel && vertex_ns > 0.0 {
            self.vertex_ns = Some(vertex_ns);
        }
        let outcomes = || results.iter().map(|r| r.outcome);
        let failure = outcomes().enumerate().find_map(|(i, o)| o.failure.map(|f| (i, f, o)));
        let report = LevelReport {
            level: w,
            iterations: outcomes().map(|o| o.iterations).sum(),
            jacobians: outcomes().map(|o| o.jacobians).sum(),
            max_relative_residual: outcomes().map(|o| o.relative_residual).fold(0.0, f64::max),
            parallel,
        };
        if let Some((i, f, o)) = failure {
            self.next_values = next_values;
            self.next_grads = next_grads;
            self.results = results;
            return Err(Error::VertexSolveFailure {
                vertex: format!("vertex {i} of level {w}"),
                residual: o.relative_residual,
                iterations: o.iterations,
                reason: f.reason().into(),
            });
        }
        // Level w + n: its in-level order is that of level w shifted by Δ.
        let top = self.value_slot(w + n as i64);
        for (i, z) in next_values.iter().enumerate() {
            let target = self.up(i, 0, n);
            self.values[top * size + target] = *z;
        }
        // The solved level's gradients take the slot of level w − n − 1,
        // which nothing reads any more; its buffer is overwritten next level.
        let gslot = self.grad_slot(w);
        std::mem::swap(&mut self.grads[gslot], &mut next_grads);
        // The level's Jacobian factors, for the solves n levels up.
        let kept = &mut self.kept[w.rem_euclid(n as i64) as usize];
        kept.clear();
        if self.reuse_jacobians && results.iter().any(|r| r.factors.is_some()) {
            kept.extend(results.iter().map(|r| r.factors));
        }
        self.next_values = next_values;
        self.next_grads = next_grads;
        self.results = results;
        self.forces_level = Some(w);
        self.level += 1;
        Ok(report)
    }
}

// The cell buffers hold every vertex of a CFK simplex of the largest
// lattice dimension (n + 1 vertices).
const _: () = assert!(MAX_CELL_VERTICES > MAX_LATTICE_DIMENSION);
