//! The Cauchy integrator on any finite complex (seed 003 §4, with the
//! scheduler of note 003 §2.4 "general complexes"): a first-order flow Δ
//! pairs a vertex v with a vertex Δv in a common top cell; when every vertex
//! of the star of v except Δv is known, EL_v = Leg_v(y_Δv) − μ_v = 0 (4.4)
//! is solved for y_Δv by [`solve_legendre`](super::legendre::solve_legendre), with
//!
//! * S_v^Δ = the cells of S_v that contain Δv (Def. 4.2),
//! * μ_v = −Σ_{β ∈ S_v ∖ S_v^Δ} ∂L_β/∂y_v (4.2), Leg_v = Σ_{β ∈ S_v^Δ} ∂L_β/∂y_v (4.3).
//!
//! When Δv lies in one cell of the star only, as v's successor in it, the
//! Lagrangian may solve the equation itself
//! ([`DiscreteLagrangian::solve_cell_vertex`]: the split Lagrangians of the
//! beam iterate on the one increment Δv enters); the generic Newton in the
//! fibre's chart stays the reference, and solves the pair when the model's
//! solve fails.
//!
//! The caller supplies the schedule (for example seed 000's rows for time
//! evolution, Δ(j, a) = (j + 1, a), or its columns for space evolution,
//! Δ(j, a) = (j, a + 1)); the marcher checks every pair: a flow the complex
//! does not admit (v and Δv in no common cell), a vertex whose star is not
//! yet known, or an unknown already determined are typed errors that name
//! the vertex. A batch of pairs whose stars do not involve each other's
//! unknowns is solved in parallel, with results independent of the thread
//! count.

use nalgebra::{SMatrix, SVector};
use rayon::prelude::*;

use super::cell::{
    DiscreteLagrangian, MAX_CELL_VERTICES, add_vertex_terms, check_closed_form, exact_gradient, vertex_force,
    with_values,
};
use super::fibre::Fibre;
use super::legendre::{CauchyOptions, VertexOutcome, solve_legendre_from};
use crate::complex::{StarEntry, TopCells};
use crate::solve::SmallLu;
use crate::{Error, Result};

/// A pair (v, Δv) of a schedule, checked once, with v's star
/// ([`FlowMarcher::check`]).
#[derive(Clone, Debug)]
pub(crate) struct CheckedPair {
    v: usize,
    dv: usize,
    star: Vec<StarEntry>,
}

/// The Cauchy integrator on a finite complex with a caller-given schedule.
/// The complex is held by value (`&C` is a complex too, so a borrowed one
/// works as well).
pub struct FlowMarcher<C: TopCells, F: Fibre<M>, L, const M: usize> {
    complex: C,
    lag: L,
    values: Vec<F::Point<f64>>,
    known: Vec<bool>,
    options: CauchyOptions,
    /// Star buffer of single solves (no allocation once grown).
    scratch: Vec<StarEntry>,
}

/// Cells whose closed-form gradients a marcher checks against its cell
/// Lagrangian when it is built ([`check_closed_form`]).
const CHECKED_CELLS: usize = 48;

fn flow_error(v: usize, reason: String) -> Error {
    Error::InvalidParameter {
        name: "flow".into(),
        value: format!("vertex {v}"),
        reason,
    }
}

impl<C, F, L, const M: usize> FlowMarcher<C, F, L, M>
where
    C: TopCells,
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// A marcher on `complex` with initial values (`values[v]` is read only
    /// where `known[v]`; the others are starting guesses, replaced as they
    /// are solved).
    pub fn new(
        complex: C,
        lag: L,
        values: Vec<F::Point<f64>>,
        known: Vec<bool>,
        options: CauchyOptions,
    ) -> Result<Self> {
        for (what, len) in [("values", values.len()), ("known flags", known.len())] {
            if len != complex.vertex_count() {
                return Err(Error::DimensionMismatch {
                    what: format!("{what} (one per vertex of the complex)"),
                    expected: complex.vertex_count(),
                    got: len,
                });
            }
        }
        if let Some(v) = (0..values.len()).find(|&v| known[v] && !F::is_finite(&values[v])) {
            return Err(Error::NonFinite {
                what: "known field values".into(),
                index: v,
                value: f64::NAN,
            });
        }
        let marcher = Self {
            complex,
            lag,
            values,
            known,
            options,
            scratch: Vec::with_capacity(MAX_CELL_VERTICES),
        };
        marcher.check_closed_forms()?;
        Ok(marcher)
    }

    /// [`check_closed_form`] on the first [`CHECKED_CELLS`] cells whose
    /// vertices are all known.
    fn check_closed_forms(&self) -> Result<()> {
        let mut verts = [0; MAX_CELL_VERTICES];
        let mut checked = 0;
        for index in 0..self.complex.cell_count() {
            if checked == CHECKED_CELLS {
                break;
            }
            let k = self.complex.cell_vertices(index, &mut verts);
            if k == 0
                || k > MAX_CELL_VERTICES
                || !verts[..k].iter().all(|&v| self.known.get(v).copied().unwrap_or(false))
            {
                continue;
            }
            checked += 1;
            let cell = self.complex.cell(index);
            with_values(
                k,
                |i| self.values[verts[i]],
                |y| check_closed_form::<F, L, M>(&self.lag, &cell, y, || format!("cell {index}")),
            )?;
        }
        Ok(())
    }

    /// The complex.
    pub fn complex(&self) -> &C {
        &self.complex
    }

    /// The complex, to move a window along a larger lattice (its vertices
    /// and cells must stay as they are: the checked schedules refer to them).
    pub fn complex_mut(&mut self) -> &mut C {
        &mut self.complex
    }

    /// The cell Lagrangian.
    pub fn lagrangian(&self) -> &L {
        &self.lag
    }

    /// Sets the value at `v`, as data (`known`) or as the starting guess of
    /// a later solve. Lets a driver recycle a small window of the complex
    /// (rolling levels) without allocating.
    pub fn set(&mut self, v: usize, value: F::Point<f64>, known: bool) {
        self.values[v] = value;
        self.known[v] = known;
    }

    /// The field (meaningful where [`is_known`](Self::is_known)).
    pub fn values(&self) -> &[F::Point<f64>] {
        &self.values
    }

    /// Whether the value at `v` is data or has been solved for.
    pub fn is_known(&self, v: usize) -> bool {
        self.known[v]
    }

    /// Checks that (v, Δv) can be solved now.
    fn check_pair(&self, v: usize, dv: usize, star: &mut Vec<StarEntry>) -> Result<()> {
        let nv = self.complex.vertex_count();
        if v >= nv || dv >= nv {
            return Err(flow_error(
                v,
                format!("vertex index out of range (the complex has {nv} vertices; Δv = {dv})"),
            ));
        }
        if self.known[dv] {
            return Err(flow_error(v, format!("Δv = {dv} is already known")));
        }
        self.complex.star(v, star);
        let mut verts = [0; MAX_CELL_VERTICES];
        let admits = star.iter().any(|e| {
            let k = self.complex.cell_vertices(e.cell, &mut verts);
            verts[..k].contains(&dv)
        });
        if !admits {
            return Err(flow_error(
                v,
                format!("v and Δv = {dv} lie in no common top cell: the complex does not admit this flow"),
            ));
        }
        for e in star.iter() {
            let k = self.complex.cell_vertices(e.cell, &mut verts);
            let cell = self.complex.cell(e.cell);
            // An unknown vertex is harmless when ∂L_β/∂y_v does not depend on it.
            if let Some(&u) = verts[..k]
                .iter()
                .enumerate()
                .find(|&(pos, &u)| u != dv && !self.known[u] && self.lag.depends(&cell, e.position, pos))
                .map(|(_, u)| u)
            {
                return Err(flow_error(
                    v,
                    format!("its star holds vertex {u}, not yet known (the Cauchy band is too narrow)"),
                ));
            }
        }
        Ok(())
    }

    /// Solves EL_v = 0 for y_Δv at a checked pair, from the values as they are.
    fn solve_pair(
        &self,
        dv: usize,
        star: &[StarEntry],
        guess: F::Point<f64>,
        kept: &mut Option<SmallLu<M>>,
    ) -> (F::Point<f64>, VertexOutcome) {
        let mut verts = [0; MAX_CELL_VERTICES];
        let mut mu = SVector::<f64, M>::zeros();
        let mut mu_scale = 0.0;
        let contains = |verts: &[usize]| verts.iter().position(|&u| u == dv);
        // The cells holding Δv (the first one, with Δv's position, and how many).
        let (mut holder, mut holders) = (None, 0);
        for e in star {
            let k = self.complex.cell_vertices(e.cell, &mut verts);
            if let Some(pos) = contains(&verts[..k]) {
                holder = holder.or(Some((e, pos, k, verts)));
                holders += 1;
            } else {
                let cell = self.complex.cell(e.cell);
                with_values(
                    k,
                    |l| self.values[verts[l]],
                    |y| {
                        let g = exact_gradient::<F, L, M>(&self.lag, &cell, y, e.position);
                        mu -= g;
                        mu_scale += g.amax();
                        if self.lag.has_forces() {
                            let f = vertex_force::<F, L, M>(&self.lag, &cell, y, e.position);
                            mu -= f;
                            mu_scale += f.amax();
                        }
                    },
                );
            }
        }
        // Δv in one cell only, v its first vertex or Δv itself: the model
        // may solve there.
        if let Some((e, pos, k, cell_verts)) = holder
            && holders == 1
            && (e.position == 0 || e.position == pos)
            && pos > 0
        {
            let cell = self.complex.cell(e.cell);
            let solved = with_values(
                k,
                |l| if l == pos { guess } else { self.values[cell_verts[l]] },
                |y| {
                    self.lag
                        .solve_cell_vertex(&cell, y, e.position, pos, &mu, mu_scale, &self.options, kept)
                },
            );
            match solved {
                Some(solved) if solved.1.failure.is_none() => return solved,
                // Its failure sends the pair to the reference solve, afresh
                // (the kept Jacobian was in the model's coordinates).
                Some(_) => *kept = None,
                None => {}
            }
        }
        let legendre = |z: &F::Point<f64>, mut jac: Option<&mut SMatrix<f64, M, M>>| {
            let mut leg = SVector::<f64, M>::zeros();
            if let Some(j) = jac.as_deref_mut() {
                j.fill(0.0);
            }
            let mut scale = 0.0;
            let mut verts = [0; MAX_CELL_VERTICES];
            for e in star {
                let k = self.complex.cell_vertices(e.cell, &mut verts);
                if let Some(pos) = contains(&verts[..k]) {
                    let cell = self.complex.cell(e.cell);
                    with_values(
                        k,
                        |l| if l == pos { *z } else { self.values[verts[l]] },
                        |y| {
                            // The Jacobian blocks only when Newton asks for them.
                            add_vertex_terms::<F, L, M>(
                                &self.lag,
                                &cell,
                                y,
                                (e.position, pos),
                                &mut leg,
                                &mut scale,
                                jac.as_deref_mut(),
                            );
                        },
                    );
                }
            }
            (leg, scale)
        };
        solve_legendre_from::<F, M>(&mu, mu_scale, guess, &self.options, kept, legendre)
    }

    /// Solves the pair (v, Δv), starting Newton from the current value at Δv,
    /// without allocating. Δv = v is the constraint EL_v = 0 solved for y_v
    /// itself (a slaved vertex, whose star's other unknowns its gradient
    /// does not depend on: [`DiscreteLagrangian::depends`]).
    pub fn solve(&mut self, v: usize, dv: usize) -> Result<VertexOutcome> {
        self.solve_reusing(v, dv, &mut None)
    }

    /// [`solve`](Self::solve) with the Newton Jacobian `kept` from an earlier
    /// solve of a similar equation (the same node one level before), used
    /// while it contracts and refreshed when it does not
    /// ([`solve_legendre_from`]); the Jacobian in use at the end is left in
    /// `kept`.
    pub fn solve_reusing(&mut self, v: usize, dv: usize, kept: &mut Option<SmallLu<M>>) -> Result<VertexOutcome> {
        let mut star = std::mem::take(&mut self.scratch);
        let checked = self.check_pair(v, dv, &mut star);
        let solved = checked.map(|()| self.solve_pair(dv, &star, self.values[dv], kept));
        self.scratch = star;
        self.store(v, dv, solved?)
    }

    /// Checks the pair (v, Δv) as [`solve`](Self::solve) does and keeps it
    /// with its star, for [`solve_checked`](Self::solve_checked): a driver
    /// that repeats one schedule on a rolling window (every level the same
    /// pairs, the same vertices known) checks it once.
    ///
    /// # Errors
    /// Those of [`solve`](Self::solve)'s check.
    pub(crate) fn check(&self, v: usize, dv: usize) -> Result<CheckedPair> {
        let mut star = Vec::new();
        self.check_pair(v, dv, &mut star)?;
        Ok(CheckedPair { v, dv, star })
    }

    /// [`solve_reusing`](Self::solve_reusing) for a pair checked by
    /// [`check`](Self::check) when the vertices of its star known then are
    /// known now (the caller's schedule guarantees it; only Δv's flag is
    /// checked again, and in debug builds the whole check).
    ///
    /// # Errors
    /// Δv already known, or a failed solve, as [`solve`](Self::solve).
    pub(crate) fn solve_checked(&mut self, pair: &CheckedPair, kept: &mut Option<SmallLu<M>>) -> Result<VertexOutcome> {
        let (v, dv) = (pair.v, pair.dv);
        if self.known[dv] {
            return Err(flow_error(v, format!("Δv = {dv} is already known")));
        }
        if cfg!(debug_assertions) {
            // In the star buffer: a level allocates nothing in debug builds either.
            let mut star = std::mem::take(&mut self.scratch);
            let checked = self.check_pair(v, dv, &mut star);
            self.scratch = star;
            assert!(
                checked.is_ok(),
                "the checked pair ({v}, {dv}) no longer checks: {checked:?}"
            );
        }
        let solved = self.solve_pair(dv, &pair.star, self.values[dv], kept);
        self.store(v, dv, solved)
    }

    /// Stores a solved value at Δv, or names the failed pair.
    fn store(&mut self, v: usize, dv: usize, (z, o): (F::Point<f64>, VertexOutcome)) -> Result<VertexOutcome> {
        if o.failure.is_some() {
            return Err(Error::VertexSolveFailure {
                vertex: format!("vertex {v} (Δv = {dv})"),
                residual: o.relative_residual,
                iterations: o.iterations,
                reason: o.failure.map_or("", |f| f.reason()).into(),
            });
        }
        self.values[dv] = z;
        self.known[dv] = true;
        Ok(o)
    }

    /// Solves independent pairs (v, Δv) in parallel. Every pair is checked
    /// first (its star known except Δv, no Δv of the batch in another pair's
    /// star); on a failed solve nothing of the batch is stored and the error
    /// names the first failing pair.
    pub fn solve_batch(&mut self, pairs: &[(usize, usize)]) -> Result<Vec<VertexOutcome>> {
        let mut stars = Vec::with_capacity(pairs.len());
        for &(v, dv) in pairs {
            let mut star = Vec::new();
            self.check_pair(v, dv, &mut star)?;
            stars.push(star);
        }
        // Independence: no unknown of the batch is read by another pair.
        let owner: std::collections::HashMap<usize, usize> =
            pairs.iter().enumerate().map(|(p, &(_, dv))| (dv, p)).collect();
        if owner.len() != pairs.len() {
            return Err(flow_error(
                pairs[0].0,
                "two pairs of the batch solve for the same Δv".into(),
            ));
        }
        let mut verts = [0; MAX_CELL_VERTICES];
        for (p, star) in stars.iter().enumerate() {
            for e in star {
                let k = self.complex.cell_vertices(e.cell, &mut verts);
                if let Some(&q) = verts[..k].iter().find_map(|u| owner.get(u).filter(|&&q| q != p)) {
                    return Err(flow_error(
                        pairs[p].0,
                        format!(
                            "its star holds Δv = {} of the pair {:?} in the same batch",
                            pairs[q].1, pairs[q]
                        ),
                    ));
                }
            }
        }
        let results: Vec<(F::Point<f64>, VertexOutcome)> = pairs
            .par_iter()
            .zip(stars.par_iter())
            .map(|(&(_, dv), star)| self.solve_pair(dv, star, self.values[dv], &mut None))
            .collect();
        if let Some((p, (_, o))) = results.iter().enumerate().find(|(_, (_, o))| o.failure.is_some()) {
            return Err(Error::VertexSolveFailure {
                vertex: format!("vertex {} (Δv = {})", pairs[p].0, pairs[p].1),
                residual: o.relative_residual,
                iterations: o.iterations,
                reason: o.failure.map_or("", |f| f.reason()).into(),
            });
        }
        let mut outcomes = Vec::with_capacity(pairs.len());
        for (&(_, dv), (z, o)) in pairs.iter().zip(results) {
            self.values[dv] = z;
            self.known[dv] = true;
            outcomes.push(o);
        }
        Ok(outcomes)
    }
}
