//! The march's Noether quantities (note 003 §2.3): the cells straddling a
//! cut, the level momentum of a vertical symmetry and the impulse of the
//! forces on a level.

use nalgebra::SVector;
use rayon::prelude::*;

use super::CauchyMarcher;
use crate::complex::{MAX_LATTICE_DIMENSION, TopCell};
use crate::field::cell::DiscreteLagrangian;
use crate::field::fibre::Fibre;

/// Vertices per block of [`CauchyMarcher::sum_straddling_cells`].
pub const STRADDLING_BLOCK: usize = 512;

/// Cells of a vertex star gathered before the first is visited (the star
/// of a CFK vertex in 2+1 dimensions has six).
const GATHERED_CELLS: usize = 8;

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
    /// the vertices `vertices`, in index order. A vertex's cells are
    /// gathered [`GATHERED_CELLS`] at a time before `f` reads any of them:
    /// a value read right after its store (for a scalar field, two
    /// neighbouring values loaded as one vector) stalls on store-to-load
    /// forwarding.
    fn visit_straddling(
        &self,
        j: usize,
        vertices: std::ops::Range<usize>,
        mut f: impl FnMut(&TopCell, &[F::Point<f64>]),
    ) {
        let n = self.torus.dimension();
        let w = self.level - j as i64;
        let cells = self.perms.len();
        let Some(&blank) = self.values.first() else {
            return;
        };
        let mut values = [[blank; MAX_LATTICE_DIMENSION + 1]; GATHERED_CELLS];
        let mut gathered: [Option<TopCell>; GATHERED_CELLS] = [None; GATHERED_CELLS];
        let rows = self.level_rows(w);
        for i in vertices {
            let at = self.base(&rows, i);
            for first in (0..cells).step_by(GATHERED_CELLS) {
                let count = GATHERED_CELLS.min(cells - first);
                for (k, (y, cell)) in values.iter_mut().zip(&mut gathered).take(count).enumerate() {
                    let sigma = first + k;
                    *cell = self
                        .cell_active_at(&at, sigma)
                        .then(|| self.cell_values_at(&rows, &at, sigma, None, &mut y[..=n]));
                }
                for (y, cell) in values.iter().zip(&gathered).take(count) {
                    if let Some(cell) = cell {
                        f(cell, &y[..=n]);
                    }
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
    /// forces. Defined after a step: the cells through level c are then all
    /// known (Σ_β F_β at each vertex is taken while the level is solved, on
    /// the solving threads). `None` before the first step since the marcher
    /// was built or restored from a checkpoint: the forces of the cells
    /// based at c − n, below the stored levels, are then not known.
    pub fn level_impulse(&self, generator: impl Fn(&F::Point<f64>) -> SVector<f64, M>) -> Option<f64> {
        self.level_impulses(|y| [generator(y)]).map(|[i]| i)
    }

    /// Σ_β F^{l(v)}_β over the cells β through the vertex v = (c, i), from
    /// the stored forces: those of the cells based at v from `own` (v's
    /// [`stride`](Self::stride) stored terms), the others from the ring. A
    /// cell outside the window stores zero terms, so it adds nothing (as in
    /// [`momentum`](Self::momentum)).
    pub(super) fn vertex_force(&self, c: i64, i: usize, own: &[SVector<f64, M>]) -> SVector<f64, M> {
        let n = self.torus.dimension();
        let per_vertex = self.perms.len() * (n + 1);
        let stride = self.stride();
        let mut force = SVector::zeros();
        for j in (0..=n).filter(|&j| self.lag.has_force_at(j)) {
            for sigma in 0..self.perms.len() {
                let at = per_vertex + sigma * (n + 1) + j;
                force += if j == 0 {
                    &own[at]
                } else {
                    &self.grads[self.grad_slot(c - j as i64)][self.down(i, sigma, j) * stride + at]
                };
            }
        }
        force
    }

    /// [`level_impulse`](Self::level_impulse) along K vector fields at once
    /// (`generators` returns their values at a point): one sweep over the
    /// forces stored for the level's cells for all of them.
    pub fn level_impulses<const K: usize>(
        &self,
        generators: impl Fn(&F::Point<f64>) -> [SVector<f64, M>; K],
    ) -> Option<[f64; K]> {
        if self.level <= self.start_level {
            return None;
        }
        let mut sum = [0.0; K];
        if !self.lag.has_forces() {
            return Some(sum);
        }
        let stride = self.stride();
        let c = self.level - 1;
        // Σ_β F_β at each vertex, taken when the level was solved (in
        // parallel) or, after a failed step, from the stored forces by the
        // same operations.
        let fresh = self.forces_level == Some(c);
        // The level's window reduction, formed once (no division per vertex).
        let rows = self.level_rows(c);
        for i in 0..self.torus.level_size() {
            if !self.is_active_in(&rows, i) {
                continue;
            }
            let force = if fresh {
                self.results[i].force
            } else {
                self.vertex_force(c, i, &self.grads[self.grad_slot(c)][i * stride..(i + 1) * stride])
            };
            // One pairing per vertex, not one per cell.
            for (s, dk) in sum.iter_mut().zip(&generators(&self.value(c, i))) {
                *s += force.dot(dk);
            }
        }
        Some(sum)
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Vector3;

    use crate::field::cauchy::{CauchyMarcher, CauchyOptions};
    use crate::field::fibre::Pose;
    use crate::lie::so3;
    use crate::models::rod::{CosseratCell, CosseratDensity, RodLoads};
    use crate::models::rod::{CrossSection, Material, RodLattice, Shear, load_impulse, rod_parameters};

    type LoadedRod = CauchyMarcher<crate::field::fibre::PositionRotation, CosseratCell, 6>;

    /// A damped, end-loaded 12-element rod with a window.
    fn loaded_rod() -> LoadedRod {
        let material = Material {
            density: 5000.0,
            young: 1e6,
            shear: Shear::Modulus(1e4),
            shear_coefficient: 1.0,
        };
        let p = rod_parameters(&CrossSection::Circle { radius: 0.25 }, &material).expect("rod");
        let elements = 12;
        let dt = 0.05 * 3.0 / elements as f64;
        let lattice = RodLattice::new(elements + 1, 3.0, dt).expect("lattice");
        let loads = RodLoads {
            damping_linear: 1.0,
            damping_angular: 0.01,
            end_force: Vector3::new(10.0, -3.0, 1.0),
            end_torque: Vector3::new(0.0, 0.5, 0.2),
            tip: elements as i64,
            ramp: 0.1,
            start: 0.0,
        };
        let cell = CosseratCell::new(CosseratDensity::free(p), lattice.ds(), dt)
            .expect("spacings")
            .with_loads(loads)
            .expect("loads");
        let data = lattice.cauchy_data(|s, t| {
            let wobble = (s * 7.0).sin() * 1e-2;
            Pose::new(
                Vector3::new(wobble * (1.0 + t), 0.3 * wobble, s),
                so3::exp(&Vector3::new(wobble, 0.5 * wobble, -0.2 * wobble)),
            )
        });
        let options = CauchyOptions {
            tolerance: 1e-13,
            ..CauchyOptions::default()
        };
        CauchyMarcher::with_window(cell, lattice.torus().clone(), 0, &data, options, lattice.window()).expect("marcher")
    }

    /// The level impulse from the vertex forces taken while the level was
    /// solved equals, bit for bit, the one summed again from the stored
    /// forces (the path after a failed step), on a damped, end-loaded rod
    /// with a window, level after level.
    #[test]
    fn level_impulses_from_the_solve_equal_those_from_the_stored_forces() {
        let mut m = loaded_rod();
        for _ in 0..8 {
            m.step().expect("stable");
            let fresh = load_impulse(&m).expect("defined after a step");
            assert_eq!(m.forces_level, Some(m.level() - 1));
            m.forces_level = None;
            let summed = load_impulse(&m).expect("defined after a step");
            assert!(fresh.0.amax() > 0.0 && fresh.1.amax() > 0.0, "the loads act");
            for (a, b) in fresh.0.iter().chain(&fresh.1).zip(summed.0.iter().chain(&summed.1)) {
                assert_eq!(a.to_bits(), b.to_bits(), "{fresh:?} against {summed:?}");
            }
        }
    }

    /// Before the first step since the marcher was built or restored the
    /// forces of the cells based below the stored levels are unknown: the
    /// impulse is `None`, not a sum over stale or zero terms. One step
    /// later it is defined, and a march restored from a checkpoint gives
    /// the uninterrupted march's impulses bit for bit.
    #[test]
    fn level_impulses_are_undefined_until_a_step_after_build_or_restore() {
        use crate::run::{Checkpoint, Words};
        let mut m = loaded_rod();
        assert_eq!(load_impulse(&m), None, "just built");
        for _ in 0..5 {
            m.step().expect("stable");
        }
        assert!(load_impulse(&m).is_some(), "after a step");
        let mut saved = Vec::new();
        m.save(&mut saved);
        // A marcher that has marched further, then restored to the saved level.
        let mut restored = loaded_rod();
        for _ in 0..9 {
            restored.step().expect("stable");
        }
        restored.restore(&mut Words::new(&saved)).expect("restore");
        assert_eq!(restored.level(), m.level());
        assert_eq!(load_impulse(&restored), None, "just restored");
        for _ in 0..4 {
            m.step().expect("stable");
            restored.step().expect("stable");
            let (a, b) = (load_impulse(&m), load_impulse(&restored));
            assert!(a.is_some() && a == b, "{a:?} against {b:?}");
        }
    }
}
