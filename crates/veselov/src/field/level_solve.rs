//! Whole-level solves on any finite complex: when a new level is coupled
//! (seed 002's triangles and rectangles put two or three new vertices in one
//! cell), the Euler–Lagrange equations EL_v = 0 at the vertices of one level
//! are solved together for the values of the next, by Newton in the fibre's
//! chart with the exact Jacobian ∂EL_v/∂y_u = Σ_{β ∋ v, u} ∂²L_β/∂y_v∂y_u
//! (the core's mixed blocks), assembled from the complex's stars and factored
//! as a block-tridiagonal (cyclic) matrix: each equation couples to the
//! unknowns of its own index and its two neighbours, as on every 1+1 lattice.
//! A coupling outside that pattern is a typed error.

use nalgebra::SVector;

use super::cell::{DiscreteLagrangian, MAX_CELL_VERTICES, mixed_block, vertex_gradient};
use super::complex::{StarEntry, TopCells};
use super::fibre::Fibre;
use super::legendre::CauchyOptions;
use crate::solve::BlockTridiagonal;
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

/// Solves EL_v = 0 at the vertices `equations[e]` for the values at
/// `unknowns[e]` (as many of each; equation e couples to unknowns e − 1, e,
/// e + 1, cyclically if `cyclic`), starting from the values in `values`,
/// which are updated in place. `level` names the level in errors.
///
/// Stops when max_e |EL_e| ≤ tolerance × (the size of the terms summed), or
/// when Newton stalls at round-off within 100 × tolerance.
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
    let m = equations.len();
    if unknowns.len() != m || m == 0 || values.len() != complex.vertex_count() {
        return Err(Error::DimensionMismatch {
            what: "level solve (unknowns per equation, values per vertex)".into(),
            expected: m,
            got: unknowns.len(),
        });
    }
    // Column of each unknown vertex.
    let columns: std::collections::HashMap<usize, usize> = unknowns.iter().enumerate().map(|(c, &u)| (u, c)).collect();
    let column = |u: usize| columns.get(&u).copied();
    let stars: Vec<Vec<StarEntry>> = equations
        .iter()
        .map(|&v| {
            let mut s = Vec::new();
            complex.star(v, &mut s);
            s
        })
        .collect();
    let mut verts = [0; MAX_CELL_VERTICES];
    let mut jac = BlockTridiagonal::<M>::zeros(m, cyclic);
    let mut previous = f64::INFINITY;
    let mut report = LevelSolveReport::default();
    for it in 0..=options.max_iterations {
        jac.clear();
        let mut residual = vec![SVector::<f64, M>::zeros(); m];
        let mut worst: f64 = 0.0;
        let mut size: f64 = 0.0;
        for (e, star) in stars.iter().enumerate() {
            let mut scale = 0.0;
            for entry in star {
                let k = complex.cell_vertices(entry.cell, &mut verts);
                let y: [F::Point<f64>; MAX_CELL_VERTICES] = std::array::from_fn(|l| values[verts[l.min(k - 1)]]);
                let cell = complex.cell(entry.cell);
                let mut grad = None;
                for (l, &u) in verts[..k].iter().enumerate() {
                    let Some(col) = column(u) else { continue };
                    let (g, block) = mixed_block::<F, L, M>(lag, &cell, &y[..k], entry.position, l);
                    grad = Some(g);
                    match jac.block_mut(e, col) {
                        Some(b) => *b += block,
                        None => {
                            return Err(level_error(
                                level,
                                f64::NAN,
                                it,
                                &format!(
                                    "equation {e} couples to unknown {col}, outside the block-tridiagonal pattern"
                                ),
                            ));
                        }
                    }
                }
                let g = grad.unwrap_or_else(|| vertex_gradient::<F, L, M>(lag, &cell, &y[..k], entry.position).1);
                residual[e] += g;
                scale += g.amax();
            }
            worst = worst.max(residual[e].amax());
            size = size.max(scale);
        }
        report.iterations = it;
        report.relative_residual = worst / size.max(f64::MIN_POSITIVE);
        if !worst.is_finite() {
            return Err(level_error(level, worst, it, "non-finite residual"));
        }
        if worst <= options.tolerance * size || (worst <= 100.0 * options.tolerance * size && worst > 0.5 * previous) {
            for &u in unknowns {
                values[u] = F::renormalize(&values[u]);
            }
            return Ok(report);
        }
        previous = worst;
        if it == options.max_iterations {
            break;
        }
        let Some(lu) = jac.factor() else {
            return Err(level_error(level, worst, it, "singular Jacobian"));
        };
        let minus: Vec<SVector<f64, M>> = residual.iter().map(|r| -r).collect();
        let delta = lu.solve(&minus);
        for (&u, d) in unknowns.iter().zip(&delta) {
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
