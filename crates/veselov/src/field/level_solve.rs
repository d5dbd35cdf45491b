//! Whole-level solves on any finite complex: when a new level is coupled
//! (seed 002's triangles and rectangles put two or three new vertices in one
//! cell), the Euler–Lagrange equations EL_v = 0 at the vertices of one level
//! are solved together for the values of the next, by Newton in the fibre's
//! chart with the exact Jacobian ∂EL_v/∂y_u = Σ_{β ∋ v, u} ∂²L_β/∂y_v∂y_u
//! (the core's mixed blocks), assembled from the complex's stars and factored
//! as a block-tridiagonal (cyclic) matrix: each equation couples to the
//! unknowns of its own index and its two neighbours, as on every 1+1 lattice.
//! A coupling outside that pattern is a typed error. The residual Newton
//! zeroes is Σ_β ∂L_β/∂y_v by [`exact_gradient`], the gradient the momenta
//! and currents are made of, never the gradient a block evaluation returns
//! beside its block: rounded otherwise, that one would have Newton solve a
//! neighbouring equation and the conserved quantities drift by its rounding
//! (with hyper-dual blocks, whose gradient is rounded otherwise, the phase
//! charge of a complex Klein–Gordon field on the 1+1 generic path drifted 4
//! to 20 times more).
//!
//! [`LevelSolver`] holds everything a level solve needs (the stars of the
//! equations, the column of each unknown, the Jacobian, its factors and the
//! residual vectors), built once for a set of equations and unknowns and
//! reused level after level without allocating.

use nalgebra::SVector;

use super::cell::{DiscreteLagrangian, MAX_CELL_VERTICES, exact_gradient, mixed_block};
use super::fibre::Fibre;
use super::legendre::CauchyOptions;
use crate::complex::{StarEntry, TopCells};
use crate::solve::{BlockTridiagonal, BlockTridiagonalLu};
use crate::{Error, Result};

/// What one level solve cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LevelSolveReport {
    /// Newton iterations.
    pub iterations: usize,
    /// Final max|EL_v| relative to the size of the summed terms.
    pub relative_residual: f64,
}

fn level_error(level: usize, residual: f64, iterations: usize, reason: &str) -> Error {
    Error::LevelSolveFailure {
        level,
        t: f64::NAN,
        residual,
        iterations,
        reason: reason.into(),
    }
}

/// A whole-level Newton solver for fixed equation and unknown vertices of a
/// complex (see the module documentation): equation e is EL at vertex
/// `equations[e]`, its unknown `unknowns[e]`; equation e couples to
/// unknowns e − 1, e, e + 1 (cyclically if `cyclic`).
#[derive(Debug, Clone)]
pub struct LevelSolver<const M: usize> {
    equations: Vec<usize>,
    unknowns: Vec<usize>,
    /// Star of equation e: `stars[star_start[e]..star_start[e + 1]]`.
    stars: Vec<StarEntry>,
    star_start: Vec<usize>,
    /// Column of each vertex of the complex (`NONE` if not an unknown).
    column: Vec<usize>,
    jac: BlockTridiagonal<M>,
    lu: BlockTridiagonalLu<M>,
    residual: Vec<SVector<f64, M>>,
    delta: Vec<SVector<f64, M>>,
}

const NONE: usize = usize::MAX;

impl<const M: usize> LevelSolver<M> {
    /// A solver for EL at `equations` in the values at `unknowns` on `complex`.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] if the lists differ in length, are empty,
    /// or name a vertex outside the complex.
    pub fn new<C: TopCells + ?Sized>(
        complex: &C,
        equations: &[usize],
        unknowns: &[usize],
        cyclic: bool,
    ) -> Result<Self> {
        let m = equations.len();
        let vertices = complex.vertex_count();
        if unknowns.len() != m || m == 0 || equations.iter().chain(unknowns).any(|&v| v >= vertices) {
            return Err(Error::DimensionMismatch {
                what: "level solve (unknowns per equation, vertices of the complex)".into(),
                expected: m,
                got: unknowns.len(),
            });
        }
        let mut column = vec![NONE; vertices];
        for (c, &u) in unknowns.iter().enumerate() {
            column[u] = c;
        }
        let mut stars = Vec::new();
        let mut star_start = vec![0];
        let mut star = Vec::new();
        for &v in equations {
            complex.star(v, &mut star);
            stars.extend_from_slice(&star);
            star_start.push(stars.len());
        }
        Ok(Self {
            equations: equations.to_vec(),
            unknowns: unknowns.to_vec(),
            stars,
            star_start,
            column,
            jac: BlockTridiagonal::zeros(m, cyclic),
            lu: BlockTridiagonalLu::new(m, cyclic),
            residual: vec![SVector::zeros(); m],
            delta: vec![SVector::zeros(); m],
        })
    }

    /// The vertices whose EL equations are solved.
    pub fn equations(&self) -> &[usize] {
        &self.equations
    }

    /// The vertices whose values are solved for.
    pub fn unknowns(&self) -> &[usize] {
        &self.unknowns
    }

    /// Residuals EL_e and (with `with_jacobian`) the Jacobian at `values`;
    /// returns (max |EL_e|, the largest sum of term sizes of one equation).
    fn assemble<C, F, L>(
        &mut self,
        complex: &C,
        lag: &L,
        values: &[F::Point<f64>],
        with_jacobian: bool,
    ) -> std::result::Result<(f64, f64), (usize, usize)>
    where
        C: TopCells + ?Sized,
        F: Fibre<M>,
        L: DiscreteLagrangian<F, M>,
    {
        let mut verts = [0; MAX_CELL_VERTICES];
        if with_jacobian {
            self.jac.clear();
        }
        let (mut worst, mut size): (f64, f64) = (0.0, 0.0);
        for e in 0..self.equations.len() {
            let mut r = SVector::<f64, M>::zeros();
            let mut scale = 0.0;
            for entry in &self.stars[self.star_start[e]..self.star_start[e + 1]] {
                let k = complex.cell_vertices(entry.cell, &mut verts);
                let y: [F::Point<f64>; MAX_CELL_VERTICES] = std::array::from_fn(|l| values[verts[l.min(k - 1)]]);
                let cell = complex.cell(entry.cell);
                if with_jacobian {
                    for (l, &u) in verts[..k].iter().enumerate() {
                        let col = self.column[u];
                        if col == NONE {
                            continue;
                        }
                        let block = mixed_block::<F, L, M>(lag, &cell, &y[..k], entry.position, l).1;
                        match self.jac.block_mut(e, col) {
                            Some(b) => *b += block,
                            None => return Err((e, col)),
                        }
                    }
                }
                let g = exact_gradient::<F, L, M>(lag, &cell, &y[..k], entry.position);
                r += g;
                scale += g.amax();
            }
            self.residual[e] = r;
            worst = worst.max(r.amax());
            size = size.max(scale);
        }
        Ok((worst, size))
    }

    /// Solve EL_v = 0 at the equations for the values at the unknowns,
    /// starting from (and updating) `values`; `level` names the level in
    /// errors. Stops when max_e |EL_e| ≤ tolerance × (the size of the terms
    /// summed), or when Newton stalls at round-off within 100 × tolerance.
    /// On success the Jacobian is left assembled at the solution (for
    /// [`LevelSolver::linearised`]).
    ///
    /// # Errors
    /// [`Error::LevelSolveFailure`] on a coupling outside the
    /// block-tridiagonal pattern, a singular Jacobian, a non-finite residual
    /// or iterate, or the iteration limit.
    pub fn solve<C, F, L>(
        &mut self,
        complex: &C,
        lag: &L,
        values: &mut [F::Point<f64>],
        options: &CauchyOptions,
        level: usize,
    ) -> Result<LevelSolveReport>
    where
        C: TopCells + ?Sized,
        F: Fibre<M>,
        L: DiscreteLagrangian<F, M>,
    {
        if values.len() != self.column.len() {
            return Err(Error::DimensionMismatch {
                what: "level solve values (one per vertex)".into(),
                expected: self.column.len(),
                got: values.len(),
            });
        }
        let mut previous = f64::INFINITY;
        let mut report = LevelSolveReport::default();
        for it in 0..=options.max_iterations {
            let (worst, size) = self
                .assemble::<C, F, L>(complex, lag, values, true)
                .map_err(|(e, col)| {
                    level_error(
                        level,
                        f64::NAN,
                        it,
                        &format!("equation {e} couples to unknown {col}, outside the block-tridiagonal pattern"),
                    )
                })?;
            report.iterations = it;
            report.relative_residual = worst / size.max(f64::MIN_POSITIVE);
            if !worst.is_finite() {
                return Err(level_error(level, worst, it, "non-finite residual"));
            }
            if worst <= options.tolerance * size
                || (worst <= 100.0 * options.tolerance * size && worst > 0.5 * previous)
            {
                for &u in &self.unknowns {
                    values[u] = F::renormalize(&values[u]);
                }
                return Ok(report);
            }
            previous = worst;
            if it == options.max_iterations {
                break;
            }
            if !self.jac.factor_into(&mut self.lu) {
                return Err(level_error(level, worst, it, "singular Jacobian"));
            }
            for r in &mut self.residual {
                *r = -*r;
            }
            self.lu.solve_into(&self.residual, &mut self.delta);
            for (&u, d) in self.unknowns.iter().zip(&self.delta) {
                values[u] = F::retract(&values[u], d);
                if !F::is_finite(&values[u]) {
                    return Err(level_error(level, worst, it, "non-finite iterate"));
                }
            }
        }
        Err(level_error(
            level,
            report.relative_residual,
            report.iterations,
            "iteration limit",
        ))
    }

    /// The linearised level equations at the last solution (vector fibres):
    /// given variations `known(v)` of the vertices that are not unknowns
    /// (`None` counts as zero), writes into `out[e]` the variation of
    /// `unknowns[e]` solving Σ_u ∂EL_e/∂y_u δy_u = 0 — the tangent map of one
    /// level solve, with the Jacobian of the last [`LevelSolver::solve`].
    ///
    /// # Errors
    /// [`Error::LevelSolveFailure`] if the Jacobian is singular.
    pub fn linearised<C, F, L>(
        &mut self,
        complex: &C,
        lag: &L,
        values: &[F::Point<f64>],
        known: impl Fn(usize) -> Option<SVector<f64, M>>,
        out: &mut [SVector<f64, M>],
        level: usize,
    ) -> Result<()>
    where
        C: TopCells + ?Sized,
        F: Fibre<M>,
        L: DiscreteLagrangian<F, M>,
    {
        if !self.jac.factor_into(&mut self.lu) {
            return Err(level_error(level, f64::NAN, 0, "singular tangent Jacobian"));
        }
        let mut verts = [0; MAX_CELL_VERTICES];
        for e in 0..self.equations.len() {
            let mut rhs = SVector::<f64, M>::zeros();
            for entry in &self.stars[self.star_start[e]..self.star_start[e + 1]] {
                let k = complex.cell_vertices(entry.cell, &mut verts);
                let y: [F::Point<f64>; MAX_CELL_VERTICES] = std::array::from_fn(|l| values[verts[l.min(k - 1)]]);
                let cell = complex.cell(entry.cell);
                for (l, &u) in verts[..k].iter().enumerate() {
                    if self.column[u] != NONE {
                        continue;
                    }
                    if let Some(w) = known(u) {
                        let (_, block) = mixed_block::<F, L, M>(lag, &cell, &y[..k], entry.position, l);
                        rhs -= block * w;
                    }
                }
            }
            self.residual[e] = rhs;
        }
        self.lu.solve_into(&self.residual, out);
        Ok(())
    }
}

/// Solves EL_v = 0 at the vertices `equations[e]` for the values at
/// `unknowns[e]` once: a [`LevelSolver`] built and used for one level.
///
/// # Errors
/// As [`LevelSolver::new`] and [`LevelSolver::solve`].
#[allow(clippy::too_many_arguments)]
pub fn solve_level<C, F, L, const M: usize>(
    complex: &C,
    lag: &L,
    values: &mut [F::Point<f64>],
    equations: &[usize],
    unknowns: &[usize],
    cyclic: bool,
    options: &CauchyOptions,
    level: usize,
) -> Result<LevelSolveReport>
where
    C: TopCells + ?Sized,
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
{
    LevelSolver::<M>::new(complex, equations, unknowns, cyclic)?.solve::<C, F, L>(complex, lag, values, options, level)
}
