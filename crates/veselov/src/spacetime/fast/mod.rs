//! Fast O(N)-per-level marching of the scalar schemes of [`Scheme`] on
//! periodic or winding lattices, with the discrete energy of every level.
//!
//! * Triangle (5.8): the only implicit term is `N′` at the centroid of
//!   `Δ(i,j)`; fixed-point iteration `y⁺ = base + (h²/3)N′(ȳ(y⁺))`
//!   (contraction `L = (2/9)h² sup|N″|`).
//! * Rectangle (5.10), symmetric rectangle (5.12), Vu-Quoc–Li (5.14): the
//!   corrected increment forms (note 002 §1.4) for `δ_i = y_{i,j+1} − y_ij`,
//!   a cyclic constant-coefficient tridiagonal system prefactored once
//!   (Sherman–Morrison), the nonlinear term at the current iterate
//!   (`L ≤ c_N sup|N″| / (4(1 − 2|c|))`).
//! * Guo (5.15): a scalar fixed point per node (`L = h² sup|N″|/2`).
//!
//! Seeds: polynomial extrapolation through the last `q ≤ 9` levels
//! (coefficients `(−1)^m C(q, m+1)`; `q = 9` is the authors' 8th-order seed).
//! Stopping: the a posteriori fixed-point bound `L/(1−L)·‖Δ‖∞ ≤ tol` when the
//! potential gives `sup|N″|`, otherwise `‖Δ‖∞ ≤ tol`, with
//! `tol = rel_tol·max(1, max|y|)`. Cached `N, N′` values of the cells of the
//! new level (reused as the "previous" terms of the next level and in the
//! energy) are moved to the final iterate by a first-order Taylor step with
//! `N″` (error `O(‖Δ‖²)`), so one transcendental evaluation per node and
//! iteration suffices. Nothing is allocated after construction.

use crate::error::invalid;
use crate::error::{Error, Result, check_finite};
use crate::spacetime::cyclic::CyclicTridiagonal;
use crate::spacetime::lattice::Lattice;
use crate::spacetime::potential::ScalarPotential;
use crate::spacetime::scheme::Scheme;

mod checkpoint;

/// Iteration controls of the implicit level solves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Relative tolerance (scaled by `max(1, max|y|)`).
    pub rel_tol: f64,
    /// Iteration cap per level.
    pub max_iter: usize,
    /// Minimum iterations per level (the paper's Guo runs used 3).
    pub min_iter: usize,
    /// Number of past levels in the extrapolated seed (1..=9).
    pub extrapolation: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            rel_tol: 1e-13,
            max_iter: 50,
            min_iter: 1,
            extrapolation: 9,
        }
    }
}

/// Marches a scalar field from two levels with one of the [`Scheme`]s.
#[derive(Debug, Clone)]
pub struct FastMarcher<P> {
    potential: P,
    scheme: Scheme,
    lattice: Lattice,
    opts: SolverOptions,
    n: usize,
    jump: f64,
    /// Stored levels, newest first, each with ghosts: `[y_{−1}, y_0..y_{N−1}, y_N]`.
    levels: Vec<Vec<f64>>,
    filled: usize,
    next: Vec<f64>,
    level: usize,
    prev_a: Vec<f64>,
    /// History of `prev_a` (newest first) for the symmetric scheme's seed.
    a_hist: Vec<Vec<f64>>,
    a_filled: usize,
    cur_a: Vec<f64>,
    cur_v: Vec<f64>,
    cur_d2: Vec<f64>,
    at: Vec<f64>,
    base: Vec<f64>,
    delta: Vec<f64>,
    tri: Option<CyclicTridiagonal>,
    last_iterations: usize,
    total_iterations: u64,
    energy: f64,
}

/// Extrapolation weights through `q` past values: `(−1)^m C(q, m+1)`.
const BINOM: [[f64; 9]; 9] = [
    [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [2.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0, -3.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [4.0, -6.0, 4.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [5.0, -10.0, 10.0, -5.0, 1.0, 0.0, 0.0, 0.0, 0.0],
    [6.0, -15.0, 20.0, -15.0, 6.0, -1.0, 0.0, 0.0, 0.0],
    [7.0, -21.0, 35.0, -35.0, 21.0, -7.0, 1.0, 0.0, 0.0],
    [8.0, -28.0, 56.0, -70.0, 56.0, -28.0, 8.0, -1.0, 0.0],
    [9.0, -36.0, 84.0, -126.0, 126.0, -84.0, 36.0, -9.0, 1.0],
];

/// The potential's jets at the points `points[1..=n]` of a level into
/// `values`, `first` and `second` at the same indices, all at once
/// ([`ScalarPotential::jets`]).
fn level_jets<P: ScalarPotential>(
    potential: &P,
    points: &[f64],
    n: usize,
    values: &mut [f64],
    first: &mut [f64],
    second: &mut [f64],
) {
    let level = 1..n + 1;
    potential.jets(
        &points[level.clone()],
        &mut values[level.clone()],
        &mut first[level.clone()],
        &mut second[level],
    );
}

fn fill_ghosts(y: &mut [f64], n: usize, jump: f64) {
    y[0] = y[n] - jump;
    y[n + 1] = y[1] + jump;
}

impl<P: ScalarPotential> FastMarcher<P> {
    /// Start from levels `y0` (`j = 0`) and `y1` (`j = 1`).
    ///
    /// # Errors
    /// Non-periodic boundary (`boundary`), wrong lengths, non-finite data,
    /// invalid options (`rel_tol`, `max_iter`, `extrapolation`).
    pub fn new(
        potential: P,
        scheme: Scheme,
        lattice: Lattice,
        y0: &[f64],
        y1: &[f64],
        opts: SolverOptions,
    ) -> Result<Self> {
        let jump = lattice.boundary().jump().ok_or_else(|| {
            invalid(
                "boundary",
                format!("{:?}", lattice.boundary()),
                "the fast paths need a periodic or winding boundary (use the generic marcher)",
            )
        })?;
        let n = lattice.nodes();
        for (what, y) in [("y0", y0), ("y1", y1)] {
            if y.len() != n {
                return Err(Error::DimensionMismatch {
                    what: what.to_string(),
                    expected: n,
                    got: y.len(),
                });
            }
            check_finite(what, y)?;
        }
        if !(opts.rel_tol.is_finite() && opts.rel_tol > 0.0) {
            return Err(invalid("rel_tol", opts.rel_tol, "must be positive and finite"));
        }
        if opts.max_iter == 0 || opts.min_iter > opts.max_iter {
            return Err(invalid("max_iter", opts.max_iter, "must be ≥ 1 and ≥ min_iter"));
        }
        if !(1..=9).contains(&opts.extrapolation) {
            return Err(invalid("extrapolation", opts.extrapolation, "must be in 1..=9"));
        }
        let (h, k) = (lattice.dt(), lattice.dx());
        let tri = match scheme {
            Scheme::Rectangle | Scheme::VuQuocLi => {
                Some(CyclicTridiagonal::new(n, h * h / (2.0 * (h * h + 2.0 * k * k)))?)
            }
            Scheme::SymmetricRectangle => Some(CyclicTridiagonal::new(n, (h * h - k * k) / (2.0 * (h * h + k * k)))?),
            _ => None,
        };
        let cap = opts.extrapolation.max(2);
        let mut levels = vec![vec![0.0; n + 2]; cap];
        levels[0][1..=n].copy_from_slice(y1);
        levels[1][1..=n].copy_from_slice(y0);
        fill_ghosts(&mut levels[0], n, jump);
        fill_ghosts(&mut levels[1], n, jump);
        let mut s = Self {
            potential,
            scheme,
            lattice,
            opts,
            n,
            jump,
            levels,
            filled: 2,
            next: vec![0.0; n + 2],
            level: 1,
            prev_a: vec![0.0; n + 2],
            a_hist: if scheme == Scheme::SymmetricRectangle {
                vec![vec![0.0; n + 2]; cap]
            } else {
                Vec::new()
            },
            a_filled: 0,
            cur_a: vec![0.0; n + 2],
            cur_v: vec![0.0; n + 2],
            cur_d2: vec![0.0; n + 2],
            at: vec![0.0; n + 2],
            base: vec![0.0; n + 2],
            delta: vec![0.0; n],
            tri,
            last_iterations: 0,
            total_iterations: 0,
            energy: f64::NAN,
        };
        s.init_caches();
        Ok(s)
    }

    /// Recompute the cached "previous" terms from the two newest levels.
    fn init_caches(&mut self) {
        let n = self.n;
        let (y, ym) = (&self.levels[0], &self.levels[1]);
        let pot = &self.potential;
        for p in 1..=n {
            self.prev_a[p] = match self.scheme {
                Scheme::Triangle => pot.jet((ym[p] + y[p] + y[p + 1]) / 3.0)[1],
                Scheme::Rectangle | Scheme::SymmetricRectangle => {
                    pot.jet(0.25 * (ym[p] + y[p] + y[p + 1] + ym[p + 1]))[1]
                }
                Scheme::VuQuocLi => pot.divided_difference(y[p], ym[p]),
                Scheme::Guo => pot.jet(y[p])[0],
                Scheme::TriangleExplicit => 0.0,
            };
        }
        self.prev_a[0] = self.prev_a[n];
        if let Some(h0) = self.a_hist.first_mut() {
            h0.copy_from_slice(&self.prev_a);
            self.a_filled = 1;
        }
    }

    /// The scheme.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }
    /// The lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }
    /// The potential.
    pub fn potential(&self) -> &P {
        &self.potential
    }
    /// Index `j` of the newest level.
    pub fn level(&self) -> usize {
        self.level
    }
    /// Time of the newest level.
    pub fn time(&self) -> f64 {
        self.lattice.t(self.level)
    }
    /// Level `level() − back` (`back < stored levels`), without ghosts.
    pub fn level_values(&self, back: usize) -> Option<&[f64]> {
        (back < self.filled).then(|| &self.levels[back][1..=self.n])
    }
    /// The newest level.
    pub fn current(&self) -> &[f64] {
        &self.levels[0][1..=self.n]
    }
    /// The level before the newest.
    pub fn previous(&self) -> &[f64] {
        &self.levels[1][1..=self.n]
    }
    /// Iterations of the last level solve.
    pub fn last_iterations(&self) -> usize {
        self.last_iterations
    }
    /// Iterations of all level solves so far.
    pub fn total_iterations(&self) -> u64 {
        self.total_iterations
    }
    /// Discrete energy computed by the last [`step`](Self::step) (times `k`,
    /// so that it approximates `∫ ½φ_t² + ½φ_x² − N(φ) dx`): `E_{j−1}` of the
    /// scheme for the levels `j−1, j` just completed (Guo: `E^{j−½}`). `NaN`
    /// before the first step.
    pub fn energy(&self) -> f64 {
        self.energy
    }

    /// Subtract `s` from every stored level (the schemes are invariant under
    /// constant shifts when `N` is `s`-periodic, e.g. `s = 2π` for
    /// sine-Gordon). The cached potential values are recomputed.
    pub fn shift_all(&mut self, s: f64) {
        for l in self.levels.iter_mut() {
            for v in l.iter_mut() {
                *v -= s;
            }
        }
        self.init_caches();
    }

    /// Re-centre an S¹-valued field: subtract `2π·round(y_0/2π)` from all
    /// stored levels (`y_0` = node 0 of the newest level). Returns the shift.
    pub fn recentre_mod_2pi(&mut self) -> f64 {
        let tau = std::f64::consts::TAU;
        let s = tau * (self.levels[0][1] / tau).round();
        if s != 0.0 {
            self.shift_all(s);
        }
        s
    }

    fn fail(&self, residual: f64, iterations: usize, reason: &str) -> Error {
        Error::LevelSolveFailure {
            level: self.level + 1,
            t: self.lattice.t(self.level + 1),
            residual,
            iterations,
            reason: reason.to_string(),
        }
    }

    /// Seed `next` by extrapolation; return `max|y|` of the newest level.
    fn seed(&mut self) -> f64 {
        let q = self.opts.extrapolation.min(self.filled);
        let w = &BINOM[q - 1];
        let n = self.n;
        let y = &self.levels[0];
        let mut ymax: f64 = 0.0;
        for p in 1..=n {
            ymax = ymax.max(y[p].abs());
            self.next[p] = w[0] * y[p];
        }
        for m in 1..q {
            let l = &self.levels[m];
            let c = w[m];
            for p in 1..=n {
                self.next[p] += c * l[p];
            }
        }
        ymax
    }

    /// Compute the next level; returns its index. On failure the stored
    /// levels are unchanged.
    ///
    /// # Errors
    /// [`Error::LevelSolveFailure`] (level, time, last correction, iterations).
    pub fn step(&mut self) -> Result<usize> {
        let ymax = self.seed();
        let tol = self.opts.rel_tol * ymax.max(1.0);
        let iterations = match self.scheme {
            Scheme::Triangle => self.step_triangle(tol)?,
            Scheme::TriangleExplicit => self.step_explicit(),
            Scheme::Rectangle | Scheme::SymmetricRectangle | Scheme::VuQuocLi => self.step_rectangle(tol)?,
            Scheme::Guo => self.step_guo(tol)?,
        };
        fill_ghosts(&mut self.next, self.n, self.jump);
        if !self.energy.is_finite() {
            return Err(self.fail(f64::NAN, iterations, "non-finite energy"));
        }
        let cap = self.levels.len();
        std::mem::swap(&mut self.next, &mut self.levels[cap - 1]);
        self.levels.rotate_right(1);
        self.filled = (self.filled + 1).min(cap);
        self.level += 1;
        self.last_iterations = iterations;
        self.total_iterations += iterations as u64;
        Ok(self.level)
    }

    fn stop(&self, it: usize, change: f64, lip: Option<f64>, tol: f64) -> Result<bool> {
        if !change.is_finite() {
            return Err(self.fail(change, it, "non-finite iterate"));
        }
        if it < self.opts.min_iter {
            return Ok(false);
        }
        let bound = match lip {
            Some(l) if l < 0.5 => change * l / (1.0 - l),
            _ => change,
        };
        if bound <= tol {
            return Ok(true);
        }
        if it >= self.opts.max_iter {
            return Err(self.fail(change, it, "iteration limit"));
        }
        Ok(false)
    }

    fn step_triangle(&mut self, tol: f64) -> Result<usize> {
        let (n, jump) = (self.n, self.jump);
        let (h, k) = (self.lattice.dt(), self.lattice.dx());
        let r2 = (h / k) * (h / k);
        let h3 = h * h / 3.0;
        let lip = self.potential.curvature_bound().map(|c| 2.0 / 9.0 * h * h * c);
        {
            let (y, ym) = (&self.levels[0], &self.levels[1]);
            for p in 1..=n {
                self.base[p] = 2.0 * y[p] - ym[p]
                    + r2 * (y[p + 1] - 2.0 * y[p] + y[p - 1])
                    + h3 * (self.prev_a[p] + self.prev_a[p - 1]);
            }
        }
        let mut it = 0;
        loop {
            it += 1;
            fill_ghosts(&mut self.next, n, jump);
            let y = &self.levels[0];
            let mut change: f64 = 0.0;
            // Jacobi sweep: every centroid at the previous iterate (the
            // ghost next[N+1] holds the old next[1]), the potential's jets
            // at all of them at once, then the update.
            for p in 1..=n {
                self.at[p] = (y[p] + self.next[p] + self.next[p + 1]) * (1.0 / 3.0);
            }
            level_jets(
                &self.potential,
                &self.at,
                n,
                &mut self.cur_v,
                &mut self.cur_a,
                &mut self.cur_d2,
            );
            for p in 1..=n {
                let new = self.base[p] + h3 * self.cur_a[p];
                change = change.max((new - self.next[p]).abs());
                self.next[p] = new;
            }
            if self.stop(it, change, lip, tol)? {
                break;
            }
        }
        fill_ghosts(&mut self.next, n, jump);
        let y = &self.levels[0];
        let mut e = 0.0;
        for p in 1..=n {
            let dc = (y[p] + self.next[p] + self.next[p + 1]) * (1.0 / 3.0) - self.at[p];
            let a = self.cur_a[p];
            self.cur_a[p] = a + self.cur_d2[p] * dc;
            let v = self.cur_v[p] + a * dc;
            let vt = (self.next[p] - y[p]) / h;
            let vx = (y[p + 1] - y[p]) / k;
            e += 0.5 * (vt * vt + vx * vx) - v;
        }
        self.energy = e * k;
        std::mem::swap(&mut self.prev_a, &mut self.cur_a);
        self.prev_a[0] = self.prev_a[n];
        Ok(it)
    }

    fn step_explicit(&mut self) -> usize {
        let n = self.n;
        let (h, k) = (self.lattice.dt(), self.lattice.dx());
        let r2 = (h / k) * (h / k);
        let (y, ym) = (&self.levels[0], &self.levels[1]);
        level_jets(
            &self.potential,
            y,
            n,
            &mut self.cur_v,
            &mut self.cur_a,
            &mut self.cur_d2,
        );
        let mut e = 0.0;
        for p in 1..=n {
            let (v, d1) = (self.cur_v[p], self.cur_a[p]);
            let new = 2.0 * y[p] - ym[p] + r2 * (y[p + 1] - 2.0 * y[p] + y[p - 1]) + h * h * d1;
            self.next[p] = new;
            let vt = (new - y[p]) / h;
            let vx = (y[p + 1] - y[p]) / k;
            e += 0.5 * (vt * vt + vx * vx) - v;
        }
        self.energy = e * k;
        1
    }

    fn step_rectangle(&mut self, tol: f64) -> Result<usize> {
        let (n, jump) = (self.n, self.jump);
        let (h, k) = (self.lattice.dt(), self.lattice.dx());
        let (h2, k2) = (h * h, k * k);
        let symmetric = self.scheme == Scheme::SymmetricRectangle;
        let vql = self.scheme == Scheme::VuQuocLi;
        let (ca, cn) = if symmetric {
            (h2 / (2.0 * (h2 + k2)), 2.0 * h2 * k2 / (h2 + k2))
        } else {
            (h2 / (2.0 * (h2 + 2.0 * k2)), 2.0 * h2 * k2 / (h2 + 2.0 * k2))
        };
        let cb = if symmetric {
            k2 / (2.0 * (h2 + k2))
        } else {
            2.0 * k2 / (h2 + 2.0 * k2)
        };
        let Some(tri) = self.tri.as_ref() else {
            return Err(self.fail(f64::NAN, 0, "missing tridiagonal factor"));
        };
        // Lipschitz constant of δ ↦ new δ in ‖·‖∞: the cell averages move by
        // ≤ ½‖δ‖, N̄′ is ½·(two-point average of the new cells' N′), so
        // L ≤ c_N·sup|N″|·‖A⁻¹M‖∞/4 (VQL: ½·DD, ∂DD/∂a ≤ ½ sup|N″|, no
        // average: L ≤ c_N·sup|N″|/(4(1 − 2|c|))).
        let gain = if vql {
            1.0 / (1.0 - 2.0 * tri.c().abs())
        } else {
            tri.inverse_average_norm()
        };
        let lip = self.potential.curvature_bound().map(|c| cn * c * gain / 4.0);
        {
            let (y, ym) = (&self.levels[0], &self.levels[1]);
            for p in 1..=n {
                let d2 = y[p + 1] - 2.0 * y[p] + y[p - 1];
                let d2m = ym[p + 1] - 2.0 * ym[p] + ym[p - 1];
                let time = if symmetric {
                    2.0 * (y[p] - ym[p]) + (y[p + 1] - ym[p + 1]) + (y[p - 1] - ym[p - 1])
                } else {
                    y[p] - ym[p]
                };
                self.base[p] = ca * (3.0 * d2 + d2m) + cb * time;
            }
        }
        if symmetric {
            // Seed pass. The box scheme's solution carries near-(−1)^j content
            // (modes with θ ≈ π have ω ≈ π), which extrapolation in time
            // amplifies up to 2^q-fold; the cell averages in N̄′ annihilate it,
            // so extrapolate the new cells' N′ instead and solve once.
            let q = self.opts.extrapolation.min(self.a_filled);
            let w = &BINOM[q - 1];
            for p in 0..=n {
                let mut v = 0.0;
                for m in 0..q {
                    v += w[m] * self.a_hist[m][p];
                }
                self.cur_a[p] = v;
            }
            for p in 1..=n {
                let nbar = 0.25 * (self.cur_a[p] + self.cur_a[p - 1] + self.prev_a[p] + self.prev_a[p - 1]);
                self.delta[p - 1] = self.base[p] + cn * nbar;
            }
            tri.solve_in_place(&mut self.delta);
            let y = &self.levels[0];
            for p in 1..=n {
                self.next[p] = y[p] + self.delta[p - 1];
            }
        }
        let mut it = 0;
        loop {
            it += 1;
            fill_ghosts(&mut self.next, n, jump);
            let y = &self.levels[0];
            if vql {
                for p in 1..=n {
                    let g = 0.5 * (self.potential.divided_difference(self.next[p], y[p]) + self.prev_a[p]);
                    self.delta[p - 1] = self.base[p] + cn * g;
                }
            } else {
                for p in 1..=n {
                    self.at[p] = 0.25 * (y[p] + self.next[p] + self.next[p + 1] + y[p + 1]);
                }
                level_jets(
                    &self.potential,
                    &self.at,
                    n,
                    &mut self.cur_v,
                    &mut self.cur_a,
                    &mut self.cur_d2,
                );
                self.cur_a[0] = self.cur_a[n];
                for p in 1..=n {
                    let nbar = 0.25 * (self.cur_a[p] + self.cur_a[p - 1] + self.prev_a[p] + self.prev_a[p - 1]);
                    self.delta[p - 1] = self.base[p] + cn * nbar;
                }
            }
            tri.solve_in_place(&mut self.delta);
            let mut change: f64 = 0.0;
            for p in 1..=n {
                let new = y[p] + self.delta[p - 1];
                change = change.max((new - self.next[p]).abs());
                self.next[p] = new;
            }
            if self.stop(it, change, lip, tol)? {
                break;
            }
        }
        fill_ghosts(&mut self.next, n, jump);
        let y = &self.levels[0];
        let mut e = 0.0;
        for p in 1..=n {
            let cfin = 0.25 * (y[p] + self.next[p] + self.next[p + 1] + y[p + 1]);
            let v = if vql {
                self.cur_a[p] = self.potential.divided_difference(self.next[p], y[p]);
                self.potential.jet(cfin)[0]
            } else {
                let dc = cfin - self.at[p];
                let a = self.cur_a[p];
                self.cur_a[p] = a + self.cur_d2[p] * dc;
                self.cur_v[p] + a * dc
            };
            let tt = ((self.next[p] - y[p]) + (self.next[p + 1] - y[p + 1])) / (2.0 * h);
            let dd = ((y[p + 1] - y[p]) + (self.next[p + 1] - self.next[p])) / (2.0 * k);
            e += 0.5 * (tt * tt + dd * dd) - v;
        }
        self.energy = e * k;
        std::mem::swap(&mut self.prev_a, &mut self.cur_a);
        self.prev_a[0] = self.prev_a[n];
        if symmetric {
            self.a_hist.rotate_right(1);
            self.a_hist[0].copy_from_slice(&self.prev_a);
            self.a_filled = (self.a_filled + 1).min(self.a_hist.len());
        }
        Ok(it)
    }

    fn step_guo(&mut self, tol: f64) -> Result<usize> {
        let n = self.n;
        let (h, k) = (self.lattice.dt(), self.lattice.dx());
        let r2 = (h / k) * (h / k);
        let lip = self.potential.curvature_bound().map(|c| 0.5 * h * h * c);
        let mut worst = 0;
        {
            let (y, ym) = (&self.levels[0], &self.levels[1]);
            for p in 1..=n {
                let base = 2.0 * y[p] - ym[p] + r2 * (y[p + 1] - 2.0 * y[p] + y[p - 1]);
                let mut x = self.next[p];
                let mut it = 0;
                loop {
                    it += 1;
                    let new = base + h * h * self.potential.divided_difference(x, ym[p]);
                    let change = (new - x).abs();
                    x = new;
                    if !change.is_finite() {
                        return Err(self.fail(change, it, "non-finite iterate"));
                    }
                    if it >= self.opts.min_iter {
                        let bound = match lip {
                            Some(l) if l < 0.5 => change * l / (1.0 - l),
                            _ => change,
                        };
                        if bound <= tol {
                            break;
                        }
                    }
                    if it >= self.opts.max_iter {
                        return Err(self.fail(change, it, "iteration limit"));
                    }
                }
                self.next[p] = x;
                worst = worst.max(it);
            }
        }
        fill_ghosts(&mut self.next, n, self.jump);
        let y = &self.levels[0];
        let mut e = 0.0;
        for p in 1..=n {
            let nn = self.potential.jet(self.next[p])[0];
            let vt = (self.next[p] - y[p]) / h;
            e += 0.5 * vt * vt + 0.5 * (self.next[p + 1] - self.next[p]) * (y[p + 1] - y[p]) / (k * k)
                - 0.5 * (nn + self.prev_a[p]);
            self.cur_a[p] = nn;
        }
        self.energy = e * k;
        std::mem::swap(&mut self.prev_a, &mut self.cur_a);
        self.prev_a[0] = self.prev_a[n];
        Ok(worst)
    }
}
