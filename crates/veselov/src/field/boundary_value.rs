//! A global space–time boundary-value solve on a 1+1 lattice, where marching
//! cannot apply: data at both time ends (or any set of known vertices), the
//! discrete Euler–Lagrange equations EL_v = Σ_{β ∋ v} ∂L_β/∂y_v = 0 (seed
//! 000 (25), seed 002 (4.4)) at every unknown vertex solved together by
//! Newton in the fibre's chart, y_v ← y_v·τ(−δ_v), with the exact Jacobian
//! ∂EL_v/∂y_u = Σ_{β ∋ v, u} ∂²L_β/∂y_v∂y_u (the core's mixed blocks).
//! Note 000 §14 names this solve and leaves it out of its example.
//!
//! On a 1+1 lattice every cell spans two consecutive time levels, so the
//! equations of level t couple only to the unknowns of levels t − 1, t and
//! t + 1: the Jacobian is block tridiagonal by levels, each block dense over
//! a level's unknowns, and is factored level by level (block Gaussian
//! elimination without pivoting between levels, LU with partial pivoting
//! inside each block). A problem as large as (level size · M)² per block is
//! meant: a few hundred unknowns per level. Cell forces are not supported.

use nalgebra::{DMatrix, DVector};

use super::cell::{DiscreteLagrangian, MAX_CELL_VERTICES, exact_gradient, mixed_block};
use super::fibre::Fibre;
use super::legendre::CauchyOptions;
use crate::complex::{SpacetimeLattice, StarEntry, TopCells};
use crate::{Error, Result};

/// What a boundary-value solve cost and where it ended.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BoundaryValueReport {
    /// Newton iterations (Jacobian factorisations).
    pub iterations: usize,
    /// Final max|EL_v| over the unknown vertices, relative to the size of
    /// the terms summed.
    pub relative_residual: f64,
    /// The number of unknown vertices.
    pub unknowns: usize,
}

fn failure(residual: f64, iterations: usize, reason: impl Into<String>) -> Error {
    Error::LevelSolveFailure {
        level: 0,
        t: f64::NAN,
        residual,
        iterations,
        reason: format!("space–time boundary-value solve: {}", reason.into()),
    }
}

/// Solves EL_v = 0 at every vertex of `lattice` that is not `known`, for
/// the values `values` there (the starting guess on entry, the solution on
/// return; known values are data and are not changed). Newton stops when
/// max|EL_v| ≤ `options.tolerance` × (the size of the summed terms), or when
/// it stalls at round-off (the residual no longer halves, within 100 ×
/// that), or fails after `options.max_iterations`.
///
/// # Errors
/// [`Error::DimensionMismatch`] when `values` or `known` do not have one
/// entry per vertex; [`Error::InvalidParameter`] for a Lagrangian with cell
/// forces; [`Error::LevelSolveFailure`] when a Jacobian block is singular, a
/// residual is not finite or Newton does not converge (the values are then
/// those of the last iterate).
pub fn solve_boundary_value<F, L, const M: usize>(
    lattice: &SpacetimeLattice,
    lag: &L,
    values: &mut [F::Point<f64>],
    known: &[bool],
    options: &CauchyOptions,
) -> Result<BoundaryValueReport>
where
    F: Fibre<M>,
    L: DiscreteLagrangian<F, M>,
{
    let count = lattice.vertex_count();
    for (what, got) in [("field values", values.len()), ("known flags", known.len())] {
        if got != count {
            return Err(Error::DimensionMismatch {
                what: format!("{what} (one per lattice vertex)"),
                expected: count,
                got,
            });
        }
    }
    if lag.has_forces() {
        return Err(Error::InvalidParameter {
            name: "lagrangian".into(),
            value: "with cell forces".into(),
            reason: "the space–time boundary-value solve takes conservative Lagrangians".into(),
        });
    }
    // The unknowns, level by level; each vertex's level and its slot there.
    let levels = lattice.time_nodes();
    let mut by_level: Vec<Vec<usize>> = vec![Vec::new(); levels];
    let mut slot = vec![(usize::MAX, usize::MAX); count];
    for (v, &k) in known.iter().enumerate() {
        if !k {
            let t = lattice.node(v).1 as usize;
            slot[v] = (t, by_level[t].len());
            by_level[t].push(v);
        }
    }
    let active: Vec<usize> = (0..levels).filter(|&t| !by_level[t].is_empty()).collect();
    let unknowns: usize = active.iter().map(|&t| by_level[t].len()).sum();
    let mut report = BoundaryValueReport {
        unknowns,
        ..BoundaryValueReport::default()
    };
    if unknowns == 0 {
        return Ok(report);
    }
    // Position of each active level in `active`.
    let mut rank = vec![usize::MAX; levels];
    for (i, &t) in active.iter().enumerate() {
        rank[t] = i;
    }
    let mut star: Vec<StarEntry> = Vec::new();
    let mut verts = [0usize; MAX_CELL_VERTICES];
    let mut previous = f64::INFINITY;
    loop {
        // Residuals and the block-tridiagonal Jacobian, level by level.
        let n = active.len();
        let size = |i: usize| by_level[active[i]].len() * M;
        let mut rhs: Vec<DVector<f64>> = (0..n).map(|i| DVector::zeros(size(i))).collect();
        let mut diagonal: Vec<DMatrix<f64>> = (0..n).map(|i| DMatrix::zeros(size(i), size(i))).collect();
        let mut lower: Vec<DMatrix<f64>> = (0..n)
            .map(|i| DMatrix::zeros(size(i), if i > 0 { size(i - 1) } else { 0 }))
            .collect();
        let mut upper: Vec<DMatrix<f64>> = (0..n)
            .map(|i| DMatrix::zeros(size(i), if i + 1 < n { size(i + 1) } else { 0 }))
            .collect();
        let (mut worst, mut scale) = (0.0_f64, 0.0_f64);
        for (i, &t) in active.iter().enumerate() {
            for (e, &v) in by_level[t].iter().enumerate() {
                lattice.star(v, &mut star);
                let mut residual = nalgebra::SVector::<f64, M>::zeros();
                let mut size_v = 0.0_f64;
                for entry in &star {
                    let k = lattice.cell_vertices(entry.cell, &mut verts);
                    let cell = lattice.cell(entry.cell);
                    let y: Vec<F::Point<f64>> = verts[..k].iter().map(|&w| values[w]).collect();
                    let g = exact_gradient::<F, L, M>(lag, &cell, &y, entry.position);
                    residual += g;
                    size_v = size_v.max(g.amax());
                    for (b, &w) in verts[..k].iter().enumerate() {
                        let (tw, sw) = slot[w];
                        if tw == usize::MAX {
                            continue;
                        }
                        let block = mixed_block::<F, L, M>(lag, &cell, &y, entry.position, b).1;
                        let target = match rank[tw] {
                            r if r == i => &mut diagonal[i],
                            r if i > 0 && r == i - 1 => &mut lower[i],
                            r if r == i + 1 => &mut upper[i],
                            _ => {
                                return Err(failure(
                                    f64::NAN,
                                    report.iterations,
                                    format!("vertex {v} couples to vertex {w}, outside the neighbouring levels"),
                                ));
                            }
                        };
                        for r in 0..M {
                            for c in 0..M {
                                target[(e * M + r, sw * M + c)] += block[(r, c)];
                            }
                        }
                    }
                }
                for r in 0..M {
                    rhs[i][e * M + r] = residual[r];
                }
                worst = worst.max(residual.amax());
                scale = scale.max(size_v);
            }
        }
        report.relative_residual = worst / scale.max(f64::MIN_POSITIVE);
        if !report.relative_residual.is_finite() {
            return Err(failure(worst, report.iterations, "non-finite residual"));
        }
        // Converged, or stalled at round-off: the residual no longer halves
        // within 100 × tolerance (the terms' rounding, as the vertex solves
        // recognise it).
        let stalled = worst > 0.5 * previous && report.relative_residual <= 100.0 * options.tolerance;
        if report.relative_residual <= options.tolerance || stalled {
            return Ok(report);
        }
        previous = worst;
        if report.iterations == options.max_iterations {
            return Err(failure(worst, report.iterations, "iteration limit"));
        }
        report.iterations += 1;
        let delta = block_thomas(diagonal, &lower, &upper, rhs)
            .ok_or_else(|| failure(worst, report.iterations, "singular Jacobian block"))?;
        for (i, &t) in active.iter().enumerate() {
            for (e, &v) in by_level[t].iter().enumerate() {
                let d = nalgebra::SVector::<f64, M>::from_fn(|r, _| -delta[i][e * M + r]);
                values[v] = F::renormalize(&F::retract(&values[v], &d));
            }
        }
    }
}

/// Solves the block-tridiagonal system with diagonal blocks `d`, blocks
/// `lower[i]` (coupling to i − 1) and `upper[i]` (to i + 1) for `rhs`, by
/// block Gaussian elimination; `None` where a diagonal block is singular.
fn block_thomas(
    mut d: Vec<DMatrix<f64>>,
    lower: &[DMatrix<f64>],
    upper: &[DMatrix<f64>],
    mut rhs: Vec<DVector<f64>>,
) -> Option<Vec<DVector<f64>>> {
    let n = d.len();
    // Forward: D'_i = D_i − L_i D'_{i−1}⁻¹ U_{i−1}, r'_i = r_i − L_i D'_{i−1}⁻¹ r'_{i−1}.
    let mut factors = Vec::with_capacity(n);
    for i in 0..n {
        if i > 0 {
            let previous: &nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn> = &factors[i - 1];
            let solved_upper = previous.solve(&upper[i - 1])?;
            let solved_rhs = previous.solve(&rhs[i - 1])?;
            d[i] -= &lower[i] * solved_upper;
            let correction = &lower[i] * solved_rhs;
            rhs[i] -= correction;
        }
        let lu = d[i].clone().lu();
        if !lu.is_invertible() {
            return None;
        }
        factors.push(lu);
    }
    // Back: x_i = D'_i⁻¹ (r'_i − U_i x_{i+1}).
    let mut x: Vec<DVector<f64>> = vec![DVector::zeros(0); n];
    for i in (0..n).rev() {
        let mut r = rhs[i].clone();
        if i + 1 < n {
            r -= &upper[i] * &x[i + 1];
        }
        x[i] = factors[i].solve(&r)?;
    }
    Some(x)
}
