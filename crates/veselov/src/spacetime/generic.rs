//! Generic time marching for any [`CellLagrangian`] (triangles or
//! rectangles, field values in `ℝ^DIM`, any boundary condition), as a use of
//! the field core: the three levels j − 1, j, j + 1 are a window of the
//! [`SpacetimeLattice`] of the cell shape, the cell Lagrangian is seen by the
//! core through [`CoreCell`] (with the winding jump added to the vertices a
//! cell takes across the seam), and level j + 1 is the whole-level Newton
//! solve of the core's [`LevelSolver`]: the DELf equations at every active
//! node of level j (seed 002 (5.2) and its rectangle analogue), the exact
//! Jacobian from the core's mixed blocks, factored as a block-tridiagonal
//! system (cyclic on periodic lattices), O(N·DIM³) per Newton iteration and
//! no allocation inside a level. The scalar schemes of seed 002 have faster
//! paths in [`crate::spacetime::fast`] (fixed-point iterations that need no Hessians).
//!
//! Boundary conditions: periodic/winding (indices mod N, the jump added to
//! every component), Dirichlet (end nodes fixed, equations at the inner
//! nodes), free (the DELf at an end node sums only existing cells; supported
//! for rectangles only — with the one-orientation triangles the equation at
//! node N−1 does not involve level j+1).
//!
//! The same Jacobian propagates first variations (tangent-linear step),
//! used by the multisymplectic form formula.

use nalgebra::SVector;

use crate::ad::Scalar;
use crate::complex::{SpacetimeLattice, TopCell};
use crate::error::invalid;
use crate::error::{Error, Result, check_finite};
use crate::field::cell::DiscreteLagrangian;
use crate::field::fibre::Euclidean;
use crate::field::legendre::CauchyOptions;
use crate::field::level_solve::LevelSolver;
use crate::run::{Checkpoint, Words, save_count};
use crate::spacetime::density::{CellLagrangian, CoreCell};
use crate::spacetime::lattice::{Boundary, CellShape, Lattice};

/// A cell Lagrangian on a periodic lattice with a winding jump: the vertices
/// a cell at the seam (space origin N − 1) takes from node 0 are seen with
/// the jump added to every component, as [`node_value`] does.
#[derive(Debug, Clone, Copy)]
struct Seam<'a, L> {
    lag: &'a L,
    offsets: &'static [(i64, i64)],
    nodes: i64,
    jump: f64,
}

impl<L: CellLagrangian<DIM>, const DIM: usize> DiscreteLagrangian<Euclidean<DIM>, DIM> for Seam<'_, L> {
    fn cell_lagrangian<D: Scalar>(&self, cell: &TopCell, y: &[SVector<D, DIM>]) -> D {
        let core = CoreCell(self.lag);
        if self.jump == 0.0 || cell.origin[0] + 1 < self.nodes {
            return core.cell_lagrangian(cell, y);
        }
        let mut z: [SVector<D, DIM>; 4] = std::array::from_fn(|l| y[l.min(y.len() - 1)]);
        for (zl, &(di, _)) in z.iter_mut().zip(self.offsets).take(y.len()) {
            if cell.origin[0] + di >= self.nodes {
                zl.iter_mut().for_each(|c| *c += D::from(self.jump));
            }
        }
        core.cell_lagrangian(cell, &z[..y.len()])
    }
}

/// Levels `j−1, j` and the solve of `j+1` on a three-level window of the core.
#[derive(Debug, Clone)]
pub struct GenericMarcher<L, const DIM: usize> {
    lag: L,
    lattice: Lattice,
    window: SpacetimeLattice,
    /// Values of the window, level by level: `j−1`, `j`, then the new level.
    values: Vec<SVector<f64, DIM>>,
    solver: LevelSolver<DIM>,
    level: usize,
    /// Relative tolerance of the level residual (max |DELf| over the size of
    /// the terms summed; Newton also stops where it stalls at round-off
    /// within 100 × this).
    pub rel_tol: f64,
    /// Newton iteration cap.
    pub max_iter: usize,
    last_iterations: usize,
}

impl<L: CellLagrangian<DIM>, const DIM: usize> GenericMarcher<L, DIM> {
    /// Start from levels `y0` (`j = 0`) and `y1` (`j = 1`).
    ///
    /// # Errors
    /// Wrong lengths, non-finite data, free boundary with triangles.
    pub fn new(lag: L, lattice: Lattice, y0: Vec<SVector<f64, DIM>>, y1: Vec<SVector<f64, DIM>>) -> Result<Self> {
        let n = lattice.nodes();
        for (what, y) in [("y0", &y0), ("y1", &y1)] {
            if y.len() != n {
                return Err(Error::DimensionMismatch {
                    what: what.to_string(),
                    expected: n,
                    got: y.len(),
                });
            }
            check_finite(what, y.iter().flat_map(|v| v.iter()))?;
        }
        let shape = lag.shape();
        if lattice.boundary() == Boundary::Free && shape == CellShape::Triangle {
            return Err(invalid(
                "boundary",
                "Free",
                "free ends are not supported for triangles (the DELf at node N−1 does not involve the new level)",
            ));
        }
        let window = SpacetimeLattice::seed002(shape, &lattice, 3)?;
        let active = match lattice.boundary() {
            Boundary::Dirichlet { .. } => 1..n - 1,
            _ => 0..n,
        };
        let at = |i: usize, j: i64| window.vertex_at(i as i64, j).unwrap_or(usize::MAX);
        let equations: Vec<usize> = active.clone().map(|i| at(i, 1)).collect();
        let unknowns: Vec<usize> = active.map(|i| at(i, 2)).collect();
        let solver = LevelSolver::new(&window, &equations, &unknowns, lattice.is_periodic())?;
        let mut values = y0;
        values.extend_from_slice(&y1);
        values.extend_from_slice(&y1);
        Ok(Self {
            lag,
            lattice,
            window,
            values,
            solver,
            level: 1,
            rel_tol: 1e-14,
            max_iter: 30,
            last_iterations: 0,
        })
    }

    /// The cell Lagrangian.
    pub fn lagrangian(&self) -> &L {
        &self.lag
    }
    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }
    /// Index of the newest level.
    pub fn level(&self) -> usize {
        self.level
    }
    /// The newest level.
    pub fn current(&self) -> &[SVector<f64, DIM>] {
        let n = self.lattice.nodes();
        &self.values[n..2 * n]
    }
    /// The level before the newest.
    pub fn previous(&self) -> &[SVector<f64, DIM>] {
        &self.values[..self.lattice.nodes()]
    }
    /// Newton iterations of the last step.
    pub fn last_iterations(&self) -> usize {
        self.last_iterations
    }

    /// Compute level `j+1`.
    ///
    /// # Errors
    /// [`Error::LevelSolveFailure`] on a singular Jacobian, non-finite
    /// iterate or the iteration cap.
    pub fn step(&mut self) -> Result<()> {
        self.step_with_tangents(&mut [])
    }

    /// Compute level `j+1` and propagate first variations: each tangent is
    /// `(V_{j−1}, V_j)` on entry and `(V_j, V_{j+1})` on exit, where
    /// `V_{j+1}` solves the linearised DELf (the same exact Jacobian as the
    /// Newton solve). Variations are periodic (no jump) and vanish at fixed
    /// Dirichlet nodes.
    ///
    /// # Errors
    /// As [`step`](Self::step); tangents of the wrong length.
    pub fn step_with_tangents(&mut self, tangents: &mut [Tangent<DIM>]) -> Result<()> {
        let n = self.lattice.nodes();
        for t in tangents.iter() {
            if t.0.len() != n || t.1.len() != n {
                return Err(Error::DimensionMismatch {
                    what: "tangent".to_string(),
                    expected: n,
                    got: t.0.len().min(t.1.len()),
                });
            }
        }
        let (old, new) = self.values.split_at_mut(2 * n);
        for (i, z) in new.iter_mut().enumerate() {
            *z = old[n + i] * 2.0 - old[i];
        }
        if let Boundary::Dirichlet { left, right } = self.lattice.boundary() {
            new[0] = SVector::from_element(left);
            new[n - 1] = SVector::from_element(right);
        }
        let seam = Seam {
            lag: &self.lag,
            offsets: self.lag.shape().offsets(),
            nodes: n as i64,
            jump: self.lattice.boundary().jump().unwrap_or(0.0),
        };
        let options = CauchyOptions {
            tolerance: self.rel_tol,
            max_iterations: self.max_iter,
        };
        let next = self.level + 1;
        let t = self.lattice.t(next);
        let at_level = |e: Error| match e {
            Error::LevelSolveFailure {
                residual,
                iterations,
                reason,
                ..
            } => Error::LevelSolveFailure {
                level: next,
                t,
                residual,
                iterations,
                reason,
            },
            other => other,
        };
        let report = self
            .solver
            .solve::<_, Euclidean<DIM>, _>(&self.window, &seam, &mut self.values, &options, next)
            .map_err(at_level)?;
        for tangent in tangents.iter_mut() {
            let mut out = vec![SVector::zeros(); self.solver.unknowns().len()];
            let known = |v: usize| match v / n {
                0 => Some(tangent.0[v % n]),
                1 => Some(tangent.1[v % n]),
                _ => None,
            };
            self.solver
                .linearised::<_, Euclidean<DIM>, _>(&self.window, &seam, &self.values, known, &mut out, next)
                .map_err(at_level)?;
            let mut v_next = vec![SVector::zeros(); n];
            for (&u, x) in self.solver.unknowns().iter().zip(&out) {
                v_next[u - 2 * n] = *x;
            }
            tangent.0 = std::mem::replace(&mut tangent.1, v_next);
        }
        self.values.copy_within(n.., 0);
        self.level = next;
        self.last_iterations = report.iterations;
        Ok(())
    }
}

/// A first variation on two consecutive levels `(V_{j−1}, V_j)`.
pub type Tangent<const DIM: usize> = (Vec<SVector<f64, DIM>>, Vec<SVector<f64, DIM>>);

/// Value of node `i` of a level with the lattice's boundary condition
/// (`None` outside a non-periodic lattice).
pub fn node_value<const DIM: usize>(lat: &Lattice, level: &[SVector<f64, DIM>], i: i64) -> Option<SVector<f64, DIM>> {
    let (k, wraps) = lat.wrapped(i)?;
    let v = level[k];
    Some(if wraps == 0 {
        v
    } else {
        v.add_scalar(lat.boundary().jump().unwrap_or(0.0) * wraps as f64)
    })
}

/// The two stored levels and the level index (the tolerances are
/// construction data, set again by the caller).
impl<L, const DIM: usize> Checkpoint for GenericMarcher<L, DIM> {
    fn save(&self, out: &mut Vec<f64>) {
        save_count(out, self.level);
        save_count(out, self.last_iterations);
        for v in &self.values[..2 * self.lattice.nodes()] {
            out.extend_from_slice(v.as_slice());
        }
    }

    fn restore(&mut self, w: &mut Words<'_>) -> Result<()> {
        // Every word is read before anything is replaced: a damaged
        // checkpoint leaves the marcher as it was.
        let (level, last_iterations) = (w.count()?, w.count()?);
        let n = self.lattice.nodes();
        let values = w.take(2 * n * DIM)?;
        self.level = level;
        self.last_iterations = last_iterations;
        for (v, words) in self.values[..2 * n].iter_mut().zip(values.chunks_exact(DIM)) {
            v.copy_from_slice(words);
        }
        Ok(())
    }
}
