//! Generic time marching for any [`CellLagrangian`] (triangles or
//! rectangles, field values in `ℝ^DIM`, any boundary condition).
//!
//! Level `j+1` solves the DELf equations at every active node of level `j`
//! (seed 002 (5.2) and its rectangle analogue) by a global Newton iteration on
//! the whole new level: the exact Jacobian `∂R_i/∂y_{m,j+1}` is assembled from
//! the cells' Hessian blocks (hyper-dual numbers) and factored as a
//! block-tridiagonal system (cyclic on periodic lattices; each node couples to
//! its two neighbours on the new level), O(N·DIM³) per Newton iteration
//! ([`crate::solve::BlockTridiagonal`]). This path serves any density,
//! vector-valued fields and every boundary condition; the scalar schemes of
//! seed 002 have faster paths in [`super::fast`] (fixed-point iterations that
//! need no Hessians).
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

use super::density::{CellJet, CellLagrangian, cell_jet, gather};
use super::lattice::{Boundary, CellShape, Lattice, invalid};
use super::region::Node;
use crate::error::{Error, Result, check_finite};
use crate::run::{Checkpoint, Words, save_count};
use crate::solve::BlockTridiagonal;

/// Three stored levels `j−1, j` and the result `j+1`, plus tangents.
#[derive(Debug, Clone)]
pub struct GenericMarcher<L, const DIM: usize> {
    lag: L,
    lattice: Lattice,
    /// Levels `j−1` and `j`.
    prev: Vec<SVector<f64, DIM>>,
    curr: Vec<SVector<f64, DIM>>,
    level: usize,
    /// Relative tolerance of the Newton correction.
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
        if lattice.boundary() == Boundary::Free && lag.shape() == CellShape::Triangle {
            return Err(invalid(
                "boundary",
                "Free",
                "free ends are not supported for triangles (the DELf at node N−1 does not involve the new level)",
            ));
        }
        Ok(Self {
            lag,
            lattice,
            prev: y0,
            curr: y1,
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
        &self.curr
    }
    /// The level before the newest.
    pub fn previous(&self) -> &[SVector<f64, DIM>] {
        &self.prev
    }
    /// Newton iterations of the last step.
    pub fn last_iterations(&self) -> usize {
        self.last_iterations
    }

    /// Nodes whose DELf equation is solved (and whose new value is unknown).
    fn active(&self) -> std::ops::Range<usize> {
        let n = self.lattice.nodes();
        match self.lattice.boundary() {
            Boundary::Dirichlet { .. } => 1..n - 1,
            _ => 0..n,
        }
    }

    /// Value getter over three levels (`dj = −1, 0, 1` relative to `j`).
    fn getter<'a>(&'a self, next: &'a [SVector<f64, DIM>]) -> impl Fn(Node) -> Option<SVector<f64, DIM>> + 'a {
        let lat = self.lattice;
        move |(i, dj): Node| {
            let level: &[SVector<f64, DIM>] = match dj {
                -1 => &self.prev,
                0 => &self.curr,
                1 => next,
                _ => return None,
            };
            node_value(&lat, level, i)
        }
    }

    /// Unknown index of node `i` of the new level (`None` if fixed).
    fn unknown(&self, i: i64) -> Option<usize> {
        let n = self.lattice.nodes() as i64;
        let i = if self.lattice.is_periodic() { i.rem_euclid(n) } else { i };
        let r = self.active();
        (i >= r.start as i64 && i < r.end as i64).then(|| i as usize - r.start)
    }

    /// Residual and Jacobian of the DELf at the active nodes of level `j`
    /// for a trial new level. The Jacobian couples each node only to its two
    /// neighbours on the new level, so it is block tridiagonal (cyclic on
    /// periodic lattices) with DIM×DIM blocks; `None` in the Jacobian slot
    /// means a coupling outside that pattern (not produced by triangles or
    /// rectangles).
    fn assemble(
        &self,
        next: &[SVector<f64, DIM>],
        with_jac: bool,
    ) -> (Vec<SVector<f64, DIM>>, Option<Option<BlockTridiagonal<DIM>>>) {
        let shape = self.lag.shape();
        let nv = shape.vertices();
        let act = self.active();
        let m = act.len();
        let mut r = vec![SVector::<f64, DIM>::zeros(); m];
        let mut jac = with_jac.then(|| Some(BlockTridiagonal::<DIM>::zeros(m, self.lattice.is_periodic())));
        let get = self.getter(next);
        for (row, i) in act.enumerate() {
            for (l, &(di, dj)) in shape.offsets().iter().enumerate() {
                let c = (i as i64 - di, -dj);
                let Some(v) = gather(shape, c, &get) else { continue };
                let jet: CellJet<DIM> = cell_jet(&self.lag, &v[..nv]);
                r[row] += jet.grad[l];
                if let Some(slot) = jac.as_mut() {
                    for (mm, &(ei, ej)) in shape.offsets().iter().enumerate() {
                        if c.1 + ej != 1 {
                            continue;
                        }
                        if let Some(col) = self.unknown(c.0 + ei) {
                            match slot.as_mut().and_then(|j| j.block_mut(row, col)) {
                                Some(block) => *block += jet.hess[l][mm],
                                None => *slot = None,
                            }
                        }
                    }
                }
            }
        }
        (r, jac)
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
        let mut next: Vec<SVector<f64, DIM>> = (0..n).map(|i| self.curr[i] * 2.0 - self.prev[i]).collect();
        if let Boundary::Dirichlet { left, right } = self.lattice.boundary() {
            next[0] = SVector::from_element(left);
            next[n - 1] = SVector::from_element(right);
        }
        let act = self.active();
        let scale = self
            .curr
            .iter()
            .flat_map(|v| v.iter())
            .fold(1.0_f64, |a, b| a.max(b.abs()));
        let tol = self.rel_tol * scale;
        let fail = |residual: f64, iterations: usize, reason: &str| Error::LevelSolveFailure {
            level: self.level + 1,
            t: self.lattice.t(self.level + 1),
            residual,
            iterations,
            reason: reason.to_string(),
        };
        let mut it = 0;
        loop {
            it += 1;
            let (r, jac) = self.assemble(&next, true);
            let Some(Some(jac)) = jac else {
                return Err(fail(f64::NAN, it, "coupling outside the block-tridiagonal pattern"));
            };
            let Some(lu) = jac.factor() else {
                return Err(fail(f64::NAN, it, "singular Jacobian"));
            };
            let minus_r: Vec<SVector<f64, DIM>> = r.iter().map(|v| -v).collect();
            let dx = lu.solve(&minus_r);
            let mut change: f64 = 0.0;
            for (row, i) in act.clone().enumerate() {
                next[i] += dx[row];
                change = change.max(dx[row].amax());
            }
            if !change.is_finite() {
                return Err(fail(change, it, "non-finite iterate"));
            }
            if change <= tol {
                break;
            }
            if it >= self.max_iter {
                return Err(fail(change, it, "iteration limit"));
            }
        }
        if !tangents.is_empty() {
            self.propagate(&next, tangents)
                .ok_or_else(|| fail(f64::NAN, it, "singular tangent Jacobian"))?;
        }
        self.prev = std::mem::replace(&mut self.curr, next);
        self.level += 1;
        self.last_iterations = it;
        Ok(())
    }

    fn propagate(&self, next: &[SVector<f64, DIM>], tangents: &mut [Tangent<DIM>]) -> Option<()> {
        let (_, jac) = self.assemble(next, true);
        let lu = jac??.factor()?;
        let shape = self.lag.shape();
        let nv = shape.vertices();
        let act = self.active();
        let get = self.getter(next);
        let plain = Lattice::new(
            self.lattice.nodes(),
            1.0,
            1.0,
            match self.lattice.boundary() {
                Boundary::Winding { .. } => Boundary::Periodic,
                b => b,
            },
        )
        .ok()?;
        let n = self.lattice.nodes();
        for t in tangents.iter_mut() {
            let mut rhs = vec![SVector::<f64, DIM>::zeros(); act.len()];
            for (row, i) in act.clone().enumerate() {
                for (l, &(di, dj)) in shape.offsets().iter().enumerate() {
                    let c = (i as i64 - di, -dj);
                    let Some(v) = gather(shape, c, &get) else { continue };
                    let jet = cell_jet(&self.lag, &v[..nv]);
                    for (mm, &(ei, ej)) in shape.offsets().iter().enumerate() {
                        let level = match c.1 + ej {
                            -1 => &t.0,
                            0 => &t.1,
                            _ => continue,
                        };
                        if let Some(w) = node_value(&plain, level, c.0 + ei) {
                            rhs[row] -= jet.hess[l][mm] * w;
                        }
                    }
                }
            }
            let x = lu.solve(&rhs);
            let mut new = vec![SVector::zeros(); n];
            for (row, i) in act.clone().enumerate() {
                new[i] = x[row];
            }
            t.0 = std::mem::replace(&mut t.1, new);
        }
        Some(())
    }
}

/// A first variation on two consecutive levels `(V_{j−1}, V_j)`.
pub type Tangent<const DIM: usize> = (Vec<SVector<f64, DIM>>, Vec<SVector<f64, DIM>>);

/// Value of node `i` of a level with the lattice's boundary condition
/// (`None` outside a non-periodic lattice).
pub fn node_value<const DIM: usize>(lat: &Lattice, level: &[SVector<f64, DIM>], i: i64) -> Option<SVector<f64, DIM>> {
    let n = lat.nodes() as i64;
    match lat.boundary().jump() {
        Some(jump) => {
            let wraps = i.div_euclid(n);
            let v = level[i.rem_euclid(n) as usize];
            Some(if wraps == 0 {
                v
            } else {
                v.add_scalar(jump * wraps as f64)
            })
        }
        None => (0..n).contains(&i).then(|| level[i as usize]),
    }
}

/// The two stored levels and the level index (the tolerances are
/// construction data, set again by the caller).
impl<L, const DIM: usize> Checkpoint for GenericMarcher<L, DIM> {
    fn save(&self, out: &mut Vec<f64>) {
        save_count(out, self.level);
        save_count(out, self.last_iterations);
        for v in self.prev.iter().chain(&self.curr) {
            out.extend_from_slice(v.as_slice());
        }
    }

    fn restore(&mut self, w: &mut Words<'_>) -> Result<()> {
        self.level = w.count()?;
        self.last_iterations = w.count()?;
        for v in self.prev.iter_mut().chain(&mut self.curr) {
            w.fill(v.as_mut_slice())?;
        }
        Ok(())
    }
}
