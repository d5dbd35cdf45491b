//! The cell terms the Cauchy marcher stores (module documentation of
//! [`super`]): each cell's vertex gradients and, with forces, its forces,
//! computed once when the cell's last vertex is solved, and μ_v gathered
//! from them.

use nalgebra::SVector;

use super::{CauchyMarcher, LevelRows};
use crate::complex::{MAX_LATTICE_DIMENSION, TopCell};
use crate::field::cell::{DiscreteLagrangian, later_gradients, vertex_gradient};
use crate::field::fibre::Fibre;
use crate::solve::largest_abs;

/// Which of the solved cells' stored terms a model's vertex solve wrote
/// ([`SolvedVertex`](crate::field::cell::SolvedVertex)).
#[derive(Clone, Copy, Default)]
pub(super) struct Written {
    pub(super) gradients: bool,
    pub(super) forces: bool,
}

impl Written {
    /// Whether every stored term is written: the gradients and, when the
    /// Lagrangian has `forces`, the forces.
    #[inline]
    pub(super) fn covers(&self, forces: bool) -> bool {
        self.gradients && (self.forces || !forces)
    }
}

impl<F, L, const M: usize> CauchyMarcher<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// Gradients of the cells based at the n levels below `level()` (all
    /// their vertices are known), computed from the stored values exactly as
    /// the march computes them.
    pub(super) fn fill_gradients(&mut self) {
        let n = self.torus.dimension();
        let size = self.torus.level_size();
        let stride = self.stride();
        let mut out = vec![SVector::zeros(); stride];
        for base in self.level - n as i64..self.level {
            let slot = self.grad_slot(base);
            let rows = self.level_rows(base);
            for i in 0..size {
                self.cell_terms(&rows, i, None, Written::default(), &mut out);
                self.grads[slot][i * stride..(i + 1) * stride].copy_from_slice(&out);
            }
        }
    }

    /// Vectors stored per base vertex: its cells' n!·(n + 1) gradients,
    /// then as many forces when the Lagrangian has forces.
    #[inline]
    pub(super) fn stride(&self) -> usize {
        let per_vertex = self.perms.len() * (self.torus.dimension() + 1);
        if self.lag.has_forces() {
            2 * per_vertex
        } else {
            per_vertex
        }
    }

    /// The stored terms of the n! cells based at (w, i), into `out`
    /// ([`stride`](Self::stride) vectors): their gradients at positions
    /// 1 … n ([`cell_gradients`](Self::cell_gradients)), then their forces
    /// at every position ([`DiscreteLagrangian::cell_forces`]; zero for a
    /// cell outside the window), with the last vertex `top` if given; the
    /// parts a model's solve `written` already are skipped (its caller
    /// skips the call when they are all written, [`Written::covers`]).
    /// `rows` are the [`level_rows`](Self::level_rows) of level w.
    pub(super) fn cell_terms(
        &self,
        rows: &LevelRows,
        i: usize,
        top: Option<F::Point<f64>>,
        written: Written,
        out: &mut [SVector<f64, M>],
    ) {
        let n = self.torus.dimension();
        let width = n + 1;
        let (grads, forces) = out.split_at_mut(self.perms.len() * width);
        let with_forces = !forces.is_empty() && !written.forces;
        // Each cell's values are gathered once for both its terms.
        let base = self.base(rows, i);
        let mut y = [self.values[rows.values[0] + i]; MAX_LATTICE_DIMENSION + 1];
        for sigma in 0..self.perms.len() {
            let g = &mut grads[sigma * width..(sigma + 1) * width];
            let active = self.cell_active_at(&base, sigma);
            let cell = active.then(|| self.cell_values_at(rows, &base, sigma, top, &mut y));
            if !written.gradients {
                match &cell {
                    Some(cell) => self.cell_gradients(cell, &y[..=n], g),
                    None => g.fill(SVector::zeros()),
                }
            }
            if with_forces {
                let f = &mut forces[sigma * width..(sigma + 1) * width];
                match &cell {
                    Some(cell) => self.lag.cell_forces(cell, &y[..=n], f),
                    None => f.fill(SVector::zeros()),
                }
            }
        }
    }

    /// The vertex gradients of the cell with values `y` at positions
    /// 1 … n, into `out` (n + 1 vectors; position 0 is left zero: only
    /// later vertices' momenta and the level momentum read the stored
    /// gradients, always at positions ≥ 1). A cell outside the window is
    /// not part of the action: [`cell_terms`](Self::cell_terms) stores zero
    /// gradients for it.
    fn cell_gradients(&self, cell: &TopCell, y: &[F::Point<f64>], out: &mut [SVector<f64, M>]) {
        let n = y.len() - 1;
        out[0] = SVector::zeros();
        let mut exact = [SVector::zeros(); MAX_LATTICE_DIMENSION + 1];
        if self.lag.analytic_gradients(cell, y, &mut exact[..=n])
            || later_gradients::<F, L, M>(&self.lag, cell, y, &mut exact[..=n])
        {
            out[1..=n].copy_from_slice(&exact[1..=n]);
            return;
        }
        for (l, g) in out.iter_mut().enumerate().take(n + 1).skip(1) {
            *g = vertex_gradient::<F, L, M>(&self.lag, cell, y, l).1;
        }
    }

    /// μ_v = −Σ_{β ∈ S_v ∖ S_v^Δ} (∂L_β/∂y_v + F^{l(v)}_β) for v = (w, i),
    /// with the size of the terms (the forces F of the discrete
    /// Lagrange–d'Alembert principle when the Lagrangian has them), from the
    /// stored gradients and forces of the cells, in the gradient slots of
    /// level w's `rows`.
    pub(super) fn momentum(&self, rows: &LevelRows, i: usize) -> (SVector<f64, M>, f64) {
        let n = self.torus.dimension();
        let cells = self.perms.len();
        let per_vertex = cells * (n + 1);
        let mut mu = SVector::zeros();
        let mut scale = 0.0;
        let terms = &self.momentum_terms[i * n * cells..(i + 1) * n * cells];
        for j in 1..=n {
            let slot = self.grads[rows.grads[j]].as_slice();
            let at = &terms[(j - 1) * cells..j * cells];
            if self.lag.has_force_at(j) {
                for &at in at {
                    let (g, f) = (&slot[at as usize], &slot[at as usize + per_vertex]);
                    mu -= g;
                    scale += largest_abs(g);
                    mu -= f;
                    scale += largest_abs(f);
                }
            } else {
                for &at in at {
                    let g = &slot[at as usize];
                    mu -= g;
                    scale += largest_abs(g);
                }
            }
        }
        (mu, scale)
    }
}
