//! A run of consecutive vertices of one level as a model's own solve sees
//! it ([`VertexRun`], [`DiscreteLagrangian::solve_vertex_run`]): the
//! values of their stars, read straight from the value ring, and their
//! momenta, from the stored cell terms.

use super::{CauchyMarcher, LevelRows};
use crate::complex::TopCell;
use crate::field::cell::{DiscreteLagrangian, VertexLane, VertexRun};
use crate::field::fibre::Fibre;

/// The vertices `first … first + len − 1` of the level of `rows`, every one with an
/// equation to solve; `confined` for a march with a window or prescribed
/// values (its cells then tested one by one).
pub(super) struct LevelRun<'a, F: Fibre<M>, L, const M: usize> {
    pub(super) marcher: &'a CauchyMarcher<F, L, M>,
    pub(super) rows: &'a LevelRows,
    pub(super) first: usize,
    pub(super) len: usize,
    pub(super) lanes: usize,
    pub(super) confined: bool,
}

impl<F, L, const M: usize> VertexRun<F::Point<f64>, M> for LevelRun<'_, F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    fn len(&self) -> usize {
        self.len
    }

    fn lanes(&self) -> usize {
        self.lanes
    }

    fn dimension(&self) -> usize {
        self.marcher.torus.dimension()
    }

    #[inline(always)]
    fn star_values(&self, k: usize, sigma: usize, out: &mut [F::Point<f64>]) {
        self.marcher.star_values_at(self.rows, self.first + k, sigma, out);
    }

    fn star_cell(&self, k: usize, sigma: usize) -> TopCell {
        TopCell {
            index: 0,
            shape: sigma,
            origin: self.marcher.origin_in(self.rows, self.first + k),
        }
    }

    fn confined(&self) -> bool {
        self.confined
    }

    #[inline(always)]
    fn star(&self, k: usize, sigma: usize, out: &mut [F::Point<f64>]) -> Option<TopCell> {
        let m = self.marcher;
        if sigma >= m.perms.len() {
            return None;
        }
        if !self.confined {
            m.star_values_at(self.rows, self.first + k, sigma, out);
            return Some(self.star_cell(k, sigma));
        }
        let base = m.base(self.rows, self.first + k);
        m.cell_active_at(&base, sigma)
            .then(|| m.cell_values_at(self.rows, &base, sigma, None, out))
    }

    #[inline(always)]
    fn lane(&self, k: usize) -> VertexLane<F::Point<f64>, M> {
        let m = self.marcher;
        let (n, i) = (m.torus.dimension(), self.first + k);
        let (mu, mu_scale) = m.momentum(self.rows, i);
        VertexLane {
            mu,
            mu_scale,
            previous: m.values[self.rows.previous + m.down(i, 0, n)],
        }
    }
}
