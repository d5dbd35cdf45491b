//! One level of the Cauchy march ([`CauchyMarcher::step`]): every vertex
//! solved (by the model's own solve, several at once where the model
//! offers it, or by the marcher's Newton over the cells' exact
//! derivatives), in parallel chunks sized from the measured cost per
//! vertex, then the level stored and the ring advanced.

use nalgebra::SVector;
use rayon::prelude::*;

use super::run::LevelRun;
use super::terms::Written;
use super::{Base, CauchyMarcher, LevelRows, LevelSplitting, VertexResult};
use crate::complex::MAX_LATTICE_DIMENSION;
use crate::field::cell::{DiscreteLagrangian, SolvedVertex, add_vertex_terms};
use crate::field::fibre::Fibre;
use crate::field::legendre::{LevelReport, VertexOutcome, solve_legendre_from};
use crate::solve::SmallLu;
use crate::{Error, Result};

/// One vertex of a level as the solve loop sees it: its index, its new
/// value, its cells' gradients and its result.
type VertexSlot<'a, P, const M: usize> = (usize, ((&'a mut P, &'a mut [SVector<f64, M>]), &'a mut VertexResult<M>));

/// The slots of a run of consecutive vertices of a level: their new values,
/// their cells' terms, their results and the model's results.
struct RunSlots<'a, P, const M: usize> {
    values: &'a mut [P],
    terms: &'a mut [SVector<f64, M>],
    results: &'a mut [VertexResult<M>],
    solved: &'a mut [SolvedVertex<P>],
}

/// A run of consecutive vertices of a level handed to the model: the run's
/// index, their new values, their cells' gradients, their results and the
/// model's results.
type RunSlot<'a, P, const M: usize> = (
    usize,
    (
        ((&'a mut [P], &'a mut [SVector<f64, M>]), &'a mut [VertexResult<M>]),
        &'a mut [SolvedVertex<P>],
    ),
);

/// The work one thread takes at least: the chunk is sized from the cost per
/// vertex measured on the last level solved on one thread so that it holds
/// about this much or more (and at most a thread's share of the level, so
/// that a level worth splitting is split), the same number for every
/// thread ([`chunk_len`]). The first two levels are always solved on the
/// calling thread (the first with cold caches measured ten times the
/// steady cost of a rod's vertex), and a split level's wall time, which
/// holds the hand-over to the pool, is kept apart from this measure (it
/// would shrink the chunks and feed on itself) and only decides whether to
/// split ([`chosen_chunk`]). Chunking decides only who solves which vertex,
/// never what is computed: results stay bit-identical for every thread
/// count.
pub(super) const CHUNK_WORK_NS: f64 = 20_000.0;

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

/// Every this many levels a march whose levels are split solves one whole
/// on the calling thread, and a march that keeps them whole because split
/// ones measured no faster splits one, so that each way's cost per vertex
/// stays measured ([`chosen_chunk`]). The hand-over to the pool costs more
/// when its threads fall asleep between levels (between levels of about
/// 10 µs a caller that records every level kept a 100-element rod 40 %
/// slower split than whole on two threads).
const REMEASURE_EVERY: i64 = 128;

/// Whether level `w` takes the other way than [`chosen_chunk`] prefers,
/// to measure it (every [`REMEASURE_EVERY`] levels).
fn is_probe_level(w: i64) -> bool {
    w.rem_euclid(REMEASURE_EVERY) == 0
}

/// How much slower per vertex split levels must measure than whole ones
/// before levels are kept whole: a margin, so that a machine whose
/// two-thread speed drifts from minute to minute (as the shared one the
/// benches ran on) does not flip a march whose split levels are about as
/// fast; a rod recording every level measured 1.4 times slower split.
const SPLIT_SLOWER: f64 = 1.2;

/// The chunk of a level of `size` vertices: `chunk`, the cost rule's
/// ([`chunk_len`]), unless it splits the level and split levels measured
/// (`split_ns`, per vertex, hand-over included) [`SPLIT_SLOWER`] times
/// slower than whole ones (`whole_ns`) or more; on a `probe` level the
/// other choice, which measures it.
fn chosen_chunk(size: usize, chunk: usize, whole_ns: f64, split_ns: Option<f64>, probe: bool) -> usize {
    if chunk >= size {
        return size;
    }
    let split = split_ns.is_none_or(|split| split < SPLIT_SLOWER * whole_ns);
    if split != probe { chunk } else { size }
}

/// Stars whose cells a generic vertex solve gathers once (3! cells, the
/// lattices up to 2+1), of at most [`SMALL_CELL`] vertices each; larger
/// stars gather a cell's values at every evaluation.
const SMALL_STAR: usize = 6;

/// Vertices of a cell of a gathered star (n + 1 ≤ 4).
const SMALL_CELL: usize = 4;

/// The vertices per chunk of a level of `size` vertices costing `vertex_ns`
/// each on `threads` threads, `size` (one chunk) below `least` ns of work
/// or on one thread: the level cut into k·threads equal chunks (and a
/// remainder of fewer than k·threads vertices), k the number of chunks of
/// about [`CHUNK_WORK_NS`] each thread can take (at least one), so that
/// every thread gets the same number (seven chunks of 164 vertices on two
/// threads left one thread 57 % of the level). Rounded down, so that rayon,
/// which halves a range while each half keeps the chunk length, splits a
/// level of two chunks (25 + 26 vertices for chunks of 26 would not be).
fn chunk_len(size: usize, vertex_ns: f64, threads: usize, least: f64) -> usize {
    let level_ns = vertex_ns * size as f64;
    if threads < 2 || level_ns < least {
        return size;
    }
    let rounds = (level_ns / (threads as f64 * CHUNK_WORK_NS)).floor().max(1.0) as usize;
    (size / (threads * rounds)).max(1)
}

impl<F, L, const M: usize> CauchyMarcher<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// Solves EL_v = 0 for y_{Δv}, v = (w, i), w the level of `rows`
    /// ([`LevelRows`]); returns y_{Δv}, the solve's
    /// outcome and which of the solved cells' terms the model's own solve
    /// already wrote into `terms` ([`DiscreteLagrangian::solve_last_vertex`]);
    /// the marcher's own solve leaves its Jacobian's factors in `factors`.
    /// Outside the window y_{Δv} = y_v (never read).
    fn solve_vertex(
        &self,
        rows: &LevelRows,
        i: usize,
        terms: &mut [SVector<f64, M>],
        factors: &mut Option<SmallLu<M>>,
    ) -> (F::Point<f64>, VertexOutcome, Written) {
        *factors = None;
        let (n, w) = (self.torus.dimension(), rows.level);
        // The base's canonical coordinates serve the window test and the star.
        let base = self.base(rows, i);
        if !self.base_active(&base) {
            return (self.value(w, i), VertexOutcome::default(), Written::default());
        }
        if let Some(z) = self.prescribed(w, i) {
            return (z, VertexOutcome::default(), Written::default());
        }
        let (mu, mu_scale) = self.momentum(rows, i);
        let previous = self.values[rows.previous + self.down(i, 0, n)];
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
        let z = F::extrapolate(previous, &self.values[rows.values[0] + base.index]);
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
    /// [`DiscreteLagrangian::vertex_lanes`] (at most [`MAX_VERTEX_LANES`](super::MAX_VERTEX_LANES)),
    /// 1 with a window or Dirichlet data (whose vertices differ from one
    /// another) unless the model
    /// [solves confined runs](DiscreteLagrangian::solves_confined_runs).
    fn vertex_lanes(&self) -> usize {
        if self.confined() && !self.lag.solves_confined_runs() {
            return 1;
        }
        self.lag.vertex_lanes().clamp(1, self.lanes_cap)
    }

    /// Whether the march has a window or Dirichlet data.
    fn confined(&self) -> bool {
        self.window.is_some() || self.dirichlet.is_some()
    }

    /// The value prescribed at y_{Δv}, v = (w, i), by the Dirichlet data,
    /// if any.
    fn prescribed(&self, w: i64, i: usize) -> Option<F::Point<f64>> {
        let data = self.dirichlet.as_ref()?;
        let n = self.torus.dimension();
        data(&self.origin(w + n as i64, self.up(i, 0, n)))
    }

    /// Whether vertex (w, i) has an equation to solve: its base is in the
    /// window and y_{Δv} is not prescribed (as [`solve_vertex`](Self::solve_vertex) decides).
    fn is_free(&self, rows: &LevelRows, i: usize) -> bool {
        self.is_active_in(rows, i) && self.prescribed(rows.level, i).is_none()
    }

    /// Solves vertex (w, i), w the level of `rows`, alone into its value,
    /// cell terms and result.
    #[inline]
    fn solve_one(
        &self,
        rows: &LevelRows,
        i: usize,
        value: &mut F::Point<f64>,
        terms: &mut [SVector<f64, M>],
        result: &mut VertexResult<M>,
    ) {
        let (z, o, written) = self.solve_vertex(rows, i, terms, &mut result.factors);
        *value = z;
        self.store_vertex(rows, i, (z, o, written), terms, result);
    }

    /// The solve of vertex (w, i), w the level of `rows` (y_{Δv}, its outcome and which of its
    /// cells' terms the solve wrote) into its result, with its cells' terms
    /// and, with forces, Σ_β F^{l(v)}_β.
    #[inline]
    fn store_vertex(
        &self,
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
                self.cell_terms(rows, i, Some(z), written, terms);
            }
            if self.lag.has_forces() && self.is_active_in(rows, i) {
                result.force = self.vertex_force(rows.level, i, terms);
            }
        }
    }

    /// Solves the vertices `first …` of the level of `rows` (as many as `slots`) by
    /// the model's [`DiscreteLagrangian::solve_vertex_run`] (groups of at
    /// most `lanes`) and stores each ([`store_vertex`](Self::store_vertex));
    /// in a confined march each stretch of vertices with an equation is a
    /// run, the others are solved alone. `false` (nothing stored) when the
    /// model declines an unconfined run.
    fn solve_run(&self, rows: &LevelRows, first: usize, lanes: usize, slots: RunSlots<'_, F::Point<f64>, M>) -> bool {
        if !self.confined() {
            return self.solve_free_run(rows, first, lanes, slots);
        }
        let (stride, len) = (self.stride(), slots.values.len());
        let RunSlots {
            values,
            terms,
            results,
            solved,
        } = slots;
        let alone =
            |j: usize, values: &mut [F::Point<f64>], terms: &mut [SVector<f64, M>], results: &mut [VertexResult<M>]| {
                let terms = &mut terms[j * stride..(j + 1) * stride];
                self.solve_one(rows, first + j, &mut values[j], terms, &mut results[j]);
            };
        let mut k = 0;
        while k < len {
            let start = k;
            while k < len && self.is_free(rows, first + k) {
                k += 1;
            }
            let stretch = RunSlots {
                values: &mut values[start..k],
                terms: &mut terms[start * stride..k * stride],
                results: &mut results[start..k],
                solved: &mut solved[start..k],
            };
            if k > start && !self.solve_free_run(rows, first + start, lanes, stretch) {
                for j in start..k {
                    alone(j, values, terms, results);
                }
            }
            if k < len {
                alone(k, values, terms, results);
                k += 1;
            }
        }
        true
    }

    /// [`solve_run`](Self::solve_run) for vertices that all have an
    /// equation to solve.
    fn solve_free_run(
        &self,
        rows: &LevelRows,
        first: usize,
        lanes: usize,
        slots: RunSlots<'_, F::Point<f64>, M>,
    ) -> bool {
        let stride = self.stride();
        let RunSlots {
            values,
            terms,
            results,
            solved,
        } = slots;
        let run = LevelRun {
            marcher: self,
            rows,
            first,
            len: values.len(),
            lanes,
            confined: self.confined(),
        };
        if !self.lag.solve_vertex_run(&run, &self.options, terms, stride, solved) {
            return false;
        }
        for (l, (((value, terms), result), s)) in values
            .iter_mut()
            .zip(terms.chunks_mut(stride))
            .zip(results)
            .zip(solved.iter())
            .enumerate()
        {
            let written = Written {
                gradients: s.gradients_written,
                forces: s.forces_written,
            };
            *value = s.value;
            result.factors = None;
            self.store_vertex(rows, first + l, (s.value, s.outcome, written), terms, result);
        }
        true
    }

    /// The vertices per parallel chunk of a level of `size` vertices, `size`
    /// for a level solved on the calling thread alone: one thread in the
    /// pool, fewer than two levels measured, a level too cheap to split
    /// from where the march runs ([`PARALLEL_LEVEL_NS`] outside the pool,
    /// [`PARALLEL_LEVEL_NS_ON_POOL`] on one of its threads), or split levels
    /// measured no faster ([`chosen_chunk`], which also remeasures the other
    /// way every [`REMEASURE_EVERY`] levels).
    fn parallel_chunk(&self, size: usize) -> usize {
        let threads = rayon::current_num_threads();
        if self.splitting == LevelSplitting::Always {
            // Chunks sized as measured if measured, else one per thread.
            return match self.vertex_ns {
                Some(vertex_ns) => chunk_len(size, vertex_ns, threads, 0.0),
                None => (size / threads.max(1)).max(1),
            };
        }
        let Some(vertex_ns) = self.vertex_ns.filter(|_| self.whole_levels >= 2) else {
            return size;
        };
        let least = if rayon::current_thread_index().is_some() {
            PARALLEL_LEVEL_NS_ON_POOL
        } else {
            PARALLEL_LEVEL_NS
        };
        let chunk = chunk_len(size, vertex_ns, threads, least);
        let probe = is_probe_level(self.level);
        chosen_chunk(size, chunk, vertex_ns, self.split_ns, probe)
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
        let mut solved = std::mem::take(&mut self.solved);
        self.forces_level = None;
        let started = std::time::Instant::now();
        let chunk = self.parallel_chunk(size);
        let parallel = chunk < size;
        // The level's rows in the value ring, shared by all its vertices.
        let rows = self.level_rows(w);
        {
            let this = &*self;
            let solve = |(i, ((value, terms), result)): VertexSlot<'_, F::Point<f64>, M>| {
                this.solve_one(&rows, i, value, terms, result);
            };
            let lanes = self.vertex_lanes();
            if lanes > 1 {
                // Runs of whole groups (a vertex's bits never depend on its
                // group or on the partition); a confined march's runs are
                // cut again at the vertices without an equation, so its
                // model groups them itself and its runs are the chunks.
                let run_len = if self.confined() {
                    chunk
                } else {
                    chunk.div_ceil(lanes) * lanes
                };
                let solve_run = |(r, (((values, terms), results), solved)): RunSlot<'_, F::Point<f64>, M>| {
                    let first = r * run_len;
                    let slots = RunSlots {
                        values: &mut *values,
                        terms: &mut *terms,
                        results: &mut *results,
                        solved,
                    };
                    if !this.solve_run(&rows, first, lanes, slots) {
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
                        .par_chunks_mut(run_len)
                        .zip(next_grads.par_chunks_mut(stride * run_len))
                        .zip(results.par_chunks_mut(run_len))
                        .zip(solved.par_chunks_mut(run_len))
                        .enumerate()
                        .for_each(solve_run);
                } else {
                    next_values
                        .chunks_mut(run_len)
                        .zip(next_grads.chunks_mut(stride * run_len))
                        .zip(results.chunks_mut(run_len))
                        .zip(solved.chunks_mut(run_len))
                        .enumerate()
                        .for_each(solve_run);
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
        // The cost per vertex: a level solved on this thread alone sizes the
        // chunks, a split one (hand-over included) is kept apart to compare
        // the two ways ([`CHUNK_WORK_NS`]).
        let vertex_ns = started.elapsed().as_nanos() as f64 / size.max(1) as f64;
        if vertex_ns > 0.0 {
            if parallel {
                // Averaged over split levels (weight 1/8 for the newest), so
                // that one slow level, an interruption, does not keep levels
                // whole; a probe's split level, among whole ones, replaces it.
                let probe = is_probe_level(w);
                self.split_ns = Some(match self.split_ns {
                    Some(old) if !probe => old + (vertex_ns - old) / 8.0,
                    _ => vertex_ns,
                });
            } else {
                self.vertex_ns = Some(vertex_ns);
                self.whole_levels = self.whole_levels.saturating_add(1);
            }
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
            self.solved = solved;
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
        self.solved = solved;
        self.forces_level = Some(w);
        self.level += 1;
        Ok(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With k = ⌊level work / (threads · CHUNK_WORK_NS)⌋ (at least 1)
    /// rounds: the chunk is at most half the level (so that rayon splits
    /// it), holds CHUNK_WORK_NS of work less at most one vertex (when the
    /// level holds a round), and k·threads chunks leave fewer than
    /// k·threads vertices over; a level too cheap to split, or one thread,
    /// is one chunk.
    #[test]
    fn chunks_share_a_level_evenly() {
        for size in [7, 51, 100, 1024, 4096, 100_000] {
            for vertex_ns in [50.0, 122.0, 400.0, 5_000.0] {
                assert_eq!(chunk_len(size, vertex_ns, 1, 0.0), size);
                for threads in [2, 3, 4, 8] {
                    let chunk = chunk_len(size, vertex_ns, threads, 10_000.0);
                    let level_ns = vertex_ns * size as f64;
                    let case = format!("{size} x {vertex_ns} ns on {threads} threads: chunks of {chunk}");
                    if level_ns < 10_000.0 {
                        assert_eq!(chunk, size, "{case}");
                        continue;
                    }
                    assert!(2 * chunk <= size.max(2), "{case}");
                    let rounds = (level_ns / (threads as f64 * CHUNK_WORK_NS)).floor().max(1.0) as usize;
                    if threads as f64 * CHUNK_WORK_NS <= level_ns {
                        assert!((chunk + 1) as f64 * vertex_ns >= CHUNK_WORK_NS, "{case}");
                    }
                    let even = threads * rounds;
                    assert!(chunk == 1 || size - even * chunk < even, "{case}");
                }
            }
        }
        // The level that was cut into seven runs of 164 vertices, one thread
        // taking 656 of 1024: six of 170 (and 4 over) now; and the
        // 100-element rod's level of 51 vertices, split in two.
        assert_eq!(chunk_len(1024, 122.0, 2, 10_000.0), 170);
        assert_eq!(chunk_len(51, 400.0, 2, 10_000.0), 25);
    }

    /// A level the cost rule splits stays split until split levels measure
    /// SPLIT_SLOWER times slower than whole ones, then stays whole; a probe
    /// level takes the other way; a level the cost rule keeps whole is
    /// never split.
    #[test]
    fn levels_are_split_until_splitting_measures_slower() {
        let (size, chunk) = (51, 25);
        assert_eq!(chosen_chunk(size, chunk, 228.0, None, false), chunk);
        assert_eq!(chosen_chunk(size, chunk, 228.0, Some(150.0), false), chunk);
        assert_eq!(chosen_chunk(size, chunk, 228.0, Some(250.0), false), chunk);
        assert_eq!(chosen_chunk(size, chunk, 228.0, Some(320.0), false), size);
        assert_eq!(
            chosen_chunk(size, chunk, 228.0, Some(SPLIT_SLOWER * 228.0), false),
            size
        );
        assert_eq!(chosen_chunk(size, chunk, 228.0, Some(150.0), true), size);
        assert_eq!(chosen_chunk(size, chunk, 228.0, Some(320.0), true), chunk);
        for probe in [false, true] {
            assert_eq!(chosen_chunk(size, size, 228.0, Some(150.0), probe), size);
        }
    }
}
