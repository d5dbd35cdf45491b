//! The march's Noether quantities (note 003 §2.3): the cells straddling a
//! cut, the level momentum of a vertical symmetry and the impulse of the
//! forces on a level.

use nalgebra::SVector;
use rayon::prelude::*;

use super::CauchyMarcher;
use crate::field::cell::DiscreteLagrangian;
use crate::field::complex::{MAX_LATTICE_DIMENSION, TopCell};
use crate::field::fibre::Fibre;

/// Vertices per block of [`CauchyMarcher::sum_straddling_cells`].
pub const STRADDLING_BLOCK: usize = 512;

impl<F, L, const M: usize> CauchyMarcher<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// Calls `f` on every cell straddling the cut below the current level
    /// c = `level()`: the n!·n·(level size) simplices based at levels
    /// c − n … c − 1, with their vertex values. Together they fill one slab
    /// of duration Δt (one flow step) of the lattice, so the sum of a cell
    /// energy over them divided by Δt is a level energy. With a window, only
    /// the cells inside it.
    pub fn for_each_straddling_cell(&self, mut f: impl FnMut(&TopCell, &[F::Point<f64>])) {
        for j in 1..=self.torus.dimension() {
            self.visit_straddling(j, 0..self.torus.level_size(), &mut f);
        }
    }

    /// Calls `f` on the straddling cells based at level `level() − j` on
    /// the vertices `vertices`, in index order (each vertex's base and
    /// values gathered once for its cells).
    fn visit_straddling(
        &self,
        j: usize,
        vertices: std::ops::Range<usize>,
        mut f: impl FnMut(&TopCell, &[F::Point<f64>]),
    ) {
        let n = self.torus.dimension();
        let size = self.torus.level_size();
        let w = self.level - j as i64;
        for i in vertices {
            let at = self.base(w, i);
            let mut y = [self.values[at.slot * size + i]; MAX_LATTICE_DIMENSION + 1];
            for sigma in 0..self.perms.len() {
                if self.cell_active_at(&at, sigma) {
                    let cell = self.cell_values_at(&at, sigma, None, &mut y);
                    f(&cell, &y[..=n]);
                }
            }
        }
    }

    /// Σ_β f(β, y_β) over the cells of
    /// [`for_each_straddling_cell`](Self::for_each_straddling_cell), K sums
    /// at once: blocks of [`STRADDLING_BLOCK`] vertices of one level in
    /// parallel, each summed in index order, then the blocks' sums in block
    /// order, so the bits do not depend on the thread count. The first error
    /// in that order is returned.
    pub fn sum_straddling_cells<const K: usize, E: Send>(
        &self,
        f: impl Fn(&TopCell, &[F::Point<f64>]) -> Result<[f64; K], E> + Sync,
    ) -> Result<[f64; K], E>
    where
        L: Sync,
    {
        let n = self.torus.dimension();
        let size = self.torus.level_size();
        let blocks = size.div_ceil(STRADDLING_BLOCK);
        let block_sum = |b: usize| -> Result<[f64; K], E> {
            let (j, first) = (1 + b / blocks, (b % blocks) * STRADDLING_BLOCK);
            let mut sum = Ok([0.0; K]);
            self.visit_straddling(j, first..(first + STRADDLING_BLOCK).min(size), |cell, y| {
                // After the block's first error its other cells are skipped.
                if let Ok(total) = &mut sum {
                    match f(cell, y) {
                        Ok(value) => total.iter_mut().zip(value).for_each(|(s, v)| *s += v),
                        Err(e) => sum = Err(e),
                    }
                }
            });
            sum
        };
        let sums: Vec<Result<[f64; K], E>> = (0..n * blocks).into_par_iter().map(block_sum).collect();
        let mut total = [0.0; K];
        for sum in sums {
            for (t, v) in total.iter_mut().zip(sum?) {
                *t += v;
            }
        }
        Ok(total)
    }

    /// The level momentum of a vertical symmetry D at the cut below the
    /// current level c = `level()` (note 003 §2.3, in n dimensions):
    /// Φ(c) = Σ_{j=1..n} Σ_{β : w(v₀β) = c − j} Σ_{l ≥ j} ⟨∂L_β/∂y_{v_l}, D(y_{v_l})⟩.
    /// Φ(c) − Φ(c + 1) = Σ_{w(v) = c} ⟨EL_v, D⟩, so Φ is constant along the
    /// march when D is a symmetry (the per-cell identity Σ_l ⟨∂_l L_β, D⟩ = 0
    /// moves the cells based at c across the cut). For n = 1 it is the
    /// discrete Noether momentum ⟨p_k, D(q_k)⟩.
    pub fn level_momentum(&self, generator: impl Fn(&F::Point<f64>) -> SVector<f64, M>) -> f64 {
        self.level_momenta(|y| [generator(y)])[0]
    }

    /// [`level_momentum`](Self::level_momentum) along K vector fields at
    /// once (`generators` returns their values at a point): one sweep over
    /// the stored gradients for all of them, each sum in the order of a
    /// single sweep (the same bits).
    pub fn level_momenta<const K: usize>(
        &self,
        generators: impl Fn(&F::Point<f64>) -> [SVector<f64, M>; K],
    ) -> [f64; K] {
        let n = self.torus.dimension();
        let size = self.torus.level_size();
        let stride = self.stride();
        let c = self.level;
        let mut sum = [0.0; K];
        for j in 1..=n {
            let base_level = c - j as i64;
            let slot = self.grad_slot(base_level);
            for i in 0..size {
                for sigma in 0..self.perms.len() {
                    let g = &self.grads[slot][i * stride + sigma * (n + 1)..][..n + 1];
                    for (l, gl) in g.iter().enumerate().skip(j) {
                        let y = self.value(base_level + l as i64, self.up(i, sigma, l));
                        for (s, d) in sum.iter_mut().zip(&generators(&y)) {
                            *s += gl.dot(d);
                        }
                    }
                }
            }
        }
        sum
    }
}

impl<F, L, const M: usize> CauchyMarcher<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// The discrete impulse of the forces on the last solved level
    /// c = `level()` − 1 along a vertical vector field D:
    /// I(c) = Σ_{w(v) = c} Σ_{β ∋ v} ⟨F^{l(v)}_β, D(y_v)⟩ over the vertices
    /// of the window. Where EL_v + F_v = 0 holds (every solved vertex) it is
    /// the change of the level momentum:
    /// [`level_momentum`](Self::level_momentum) after the step minus before
    /// equals I(c) when D is a symmetry of the Lagrangian, the discrete
    /// momentum balance of the Lagrange–d'Alembert principle. Zero without
    /// forces.
    pub fn level_impulse(&self, generator: impl Fn(&F::Point<f64>) -> SVector<f64, M>) -> f64 {
        self.level_impulses(|y| [generator(y)])[0]
    }

    /// [`level_impulse`](Self::level_impulse) along K vector fields at once
    /// (`generators` returns their values at a point): one sweep over the
    /// forces stored for the level's cells for all of them.
    pub fn level_impulses<const K: usize>(
        &self,
        generators: impl Fn(&F::Point<f64>) -> [SVector<f64, M>; K],
    ) -> [f64; K] {
        let mut sum = [0.0; K];
        if !self.lag.has_forces() {
            return sum;
        }
        let n = self.torus.dimension();
        let per_vertex = self.perms.len() * (n + 1);
        let stride = self.stride();
        let c = self.level - 1;
        // The stored terms of the cells through level c at position j: the
        // ring slot of their base level, if they carry forces there.
        let slots: [Option<&[SVector<f64, M>]>; MAX_LATTICE_DIMENSION + 1] = std::array::from_fn(|j| {
            (j <= n && self.lag.has_force_at(j)).then(|| &self.grads[self.grad_slot(c - j as i64)][..])
        });
        for i in 0..self.torus.level_size() {
            // One unwrapped origin serves the vertex's and its cells' window
            // tests.
            let v = self.origin(c, i);
            if !self.window.as_ref().is_none_or(|m| m.contains(&v)) {
                continue;
            }
            // Σ_β F_β at v, then its pairing with each generator (one
            // pairing per vertex, not one per cell).
            let mut force = SVector::<f64, M>::zeros();
            for (j, slot) in slots.iter().enumerate() {
                let Some(slot) = slot else {
                    continue;
                };
                for sigma in 0..self.perms.len() {
                    if !self
                        .window
                        .as_ref()
                        .is_none_or(|m| m.contains_cell_through(&v, &self.perms[sigma], j))
                    {
                        continue;
                    }
                    let base = if j == 0 { i } else { self.down(i, sigma, j) };
                    force += &slot[base * stride + per_vertex + sigma * (n + 1) + j];
                }
            }
            for (s, dk) in sum.iter_mut().zip(&generators(&self.value(c, i))) {
                *s += force.dot(dk);
            }
        }
        sum
    }
}
