//! Building a [`CauchyMarcher`]: the Cauchy data and options checked, the
//! neighbour tables, the value and gradient rings allocated once, and the
//! model's closed forms checked against its cell Lagrangian.

use nalgebra::SVector;

use super::{CauchyMarcher, LevelSplitting, MAX_VERTEX_LANES, VertexResult};
use crate::complex::{CfkTorus, MAX_LATTICE_DIMENSION, MaterialWindow, permutation};
use crate::field::cell::{DiscreteLagrangian, SolvedVertex, check_closed_form};
use crate::field::fibre::Fibre;
use crate::field::legendre::{CauchyOptions, VertexOutcome};
use crate::{Error, Result};

/// Vertices whose cells the marcher checks for a closed form that
/// disagrees with the cell Lagrangian when it is built
/// ([`check_closed_form`]).
const CHECKED_VERTICES: usize = 8;

impl<F, L, const M: usize> CauchyMarcher<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// The marcher of [`new`](Self::new) and
    /// [`with_window`](Self::with_window): the Cauchy data checked (2n
    /// levels of the level size, finite) and the options (a positive finite
    /// tolerance, at least one iteration), the neighbour and momentum-term
    /// tables built, the rings allocated once (a request the machine cannot
    /// hold is an error, not an abort), the data stored, the closed forms
    /// checked and the Cauchy levels' cell gradients filled.
    pub(super) fn build(
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
        // Level 0's coordinates; with a window, its representatives.
        let origins = (0..size)
            .map(|i| {
                let v = torus.vertex(0, i);
                window.as_ref().map_or(v, |m| m.unwrap(&v))
            })
            .collect();
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
            solved: vec![
                SolvedVertex {
                    value: data[0][0],
                    outcome: VertexOutcome::default(),
                    gradients_written: false,
                    forces_written: false,
                };
                size
            ],
            forces_level: None,
            // Room for every slot, so that no level allocates.
            kept: (0..n).map(|_| Vec::with_capacity(size)).collect(),
            reuse_jacobians: true,
            start_level: first_level + n as i64,
            vertex_ns: None,
            split_ns: None,
            whole_levels: 0,
            splitting: LevelSplitting::Measured,
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
        let rows = self.level_rows(w);
        let vertices = (0..self.torus.level_size()).filter(|&i| self.is_active_in(&rows, i));
        for i in vertices.take(CHECKED_VERTICES) {
            let at = self.base(&rows, i);
            for sigma in (0..self.perms.len()).filter(|&s| self.cell_active_at(&at, s)) {
                let cell = self.cell_values_at(&rows, &at, sigma, None, &mut y);
                check_closed_form::<F, L, M>(&self.lag, &cell, &y[..=n], || {
                    format!("cell {sigma} based at vertex {i} of level {w}")
                })?;
            }
        }
        Ok(())
    }
}
