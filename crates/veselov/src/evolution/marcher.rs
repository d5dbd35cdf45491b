//! Time and space evolution on seed 000's 1+1 triangle lattice (note 000
//! §9–§10, §14): the core's [`FlowMarcher`] on a rolling window of three
//! levels, so that memory does not grow with the number of levels and
//! nothing is allocated inside a level.
//!
//! Both evolutions are one algorithm in the coordinates (level ℓ, cross
//! index c = 0..=C):
//!
//! * **time**: ℓ = j, c = a, C = A; Δ(j, a) = (j + 1, a); the triangle's
//!   forward vertex is vertex 2 (position 1), its cross vertex vertex 3;
//! * **space**: ℓ = a, c = j, C = N; Δ(j, a) = (j, a + 1); forward vertex 3
//!   (position 2), cross vertex 2.
//!
//! A step solves, in increasing c, the equation EL = 0 at every node (ℓ, c)
//! of the current level for its image (ℓ + 1, c): one local Newton solve of
//! size dim M per node ([`solve_legendre`](crate::field::legendre::solve_legendre),
//! to round-off). The cross ends:
//!
//! * near end c = 0, [`EndCondition::Natural`]: the node's equation is the
//!   natural boundary condition — zero traction (69) in time, zero momentum
//!   (70) in space; [`EndCondition::Prescribed`]: Dirichlet data g(ℓ) for
//!   every level (time-dependent allowed);
//! * far end c = C, natural: the **slaved** node of note 000 §1 — it lies only
//!   in the cell (ℓ, C − 1) (as vertex 3 in time, vertex 2 in space), and its
//!   constraint D₃ℒ = 0 (zero traction; λ = 0 for the beam) or D₂ℒ = 0 (zero
//!   momentum; μ = 0) fixes it from (ℓ, C − 1) alone; it is solved as soon as
//!   its level is complete. Prescribed: Dirichlet data.
//!   [`EndCondition::EndCell`] (time evolution): natural too, but the last
//!   node carries inertia of its own through an end cell (ℓ, C) of the
//!   Lagrangian, a boundary term of the discrete action (for example the
//!   half cell of mass of a trapezoid rule in s); the node is then an
//!   ordinary node of the march. The end cell's third vertex (ℓ, C + 1) is a
//!   placeholder the Lagrangian must not depend on; it is kept equal to the
//!   last node and is not part of [`Evolution000::cross`].
//!
//! The evolution momentum maps (note 000 §11, eqs. (56)–(57), (94)) of the
//! cell level between the previous and the current level are
//! 𝖩⁺ = Σ_c J^fwd and 𝖩⁻ = −Σ_c (J¹ + J^cross), J^k = X(y_k)ᵀ ∂ℒ/∂y_k for
//! the infinitesimal generators X(y): 𝔤 → T_yM in the fibre's chart
//! (left translations of SE(3): X(g) = Ad_{g⁻¹}, giving (77)).
//!
//! The window's cells report the lattice's coordinates in
//! [`TopCell::origin`] ((j, a), with j = 0 the first given level in time
//! evolution, a = 0 the first given column in space evolution): a cell
//! Lagrangian may depend on the cell's position (loads in time, weights at
//! the ends).

use nalgebra::{SMatrix, SVector};

use crate::complex::{SpacetimeLattice, TopCell, TopCells};
use crate::field::cell::{DiscreteLagrangian, exact_gradient};
use crate::field::fibre::{Fibre, read_points};
use crate::field::flow::{CheckedPair, FlowMarcher};
use crate::field::legendre::{CauchyOptions, LevelReport, VertexOutcome};
use crate::run::{Checkpoint, StepStats, Stepper, Words};
use crate::solve::SmallLu;
use crate::{Error, Result};

/// The marching direction on seed 000's lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Direction {
    /// Row by row, Δ(j, a) = (j + 1, a) (𝖫_d, §3.2.1).
    Time,
    /// Column by column, Δ(j, a) = (j, a + 1) (𝖭_d, §3.2.2).
    Space,
}

/// Prescribed values at one cross end, as a function of the level index.
pub type EndData<P> = Box<dyn Fn(usize) -> P + Send + Sync>;

/// The condition at one cross end (c = 0 or c = C).
pub enum EndCondition<P> {
    /// The natural boundary condition of the discrete principle (zero
    /// traction in time evolution, zero momentum in space evolution).
    Natural,
    /// Dirichlet data: the value at every level ℓ ≥ 2 (the first two levels
    /// are the initial data).
    Prescribed(EndData<P>),
    /// The far end of a time evolution, natural, its node an ordinary node
    /// of the Lagrangian's end cell (ℓ, C) (module documentation). The
    /// Lagrangian must declare that no vertex's gradient in the end cell
    /// depends on its third vertex ([`DiscreteLagrangian::depends`]).
    EndCell,
}

impl<P> EndCondition<P> {
    fn is_natural(&self) -> bool {
        matches!(self, EndCondition::Natural)
    }
}

/// 𝖩⁺ and 𝖩⁻ of one cell level (equal when the generators are symmetries).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EvolutionMomentum<const K: usize> {
    /// 𝖩⁺ = Σ_c J^fwd.
    pub plus: SVector<f64, K>,
    /// 𝖩⁻ = −Σ_c (J¹ + J^cross).
    pub minus: SVector<f64, K>,
    /// Σ_c Σ_k |J^k|: the size to compare differences with.
    pub scale: f64,
}

/// Time or space evolution on seed 000's lattice in a three-level window.
pub struct Evolution000<F: Fibre<M>, L, const M: usize> {
    direction: Direction,
    /// The last cross index of the window: C, or C + 1 with an end cell
    /// (its placeholder node).
    cross: usize,
    /// Whether the far end is an [`EndCondition::EndCell`].
    end_cell: bool,
    near: EndCondition<F::Point<f64>>,
    far: EndCondition<F::Point<f64>>,
    marcher: FlowMarcher<SpacetimeLattice, F, L, M>,
    level: usize,
    /// The LU factors of the Newton Jacobian of each cross index's last
    /// solve (reused at the next level while it contracts); allocated once.
    jacobians: Vec<Option<SmallLu<M>>>,
    /// The schedule of a level, checked once: the pairs (ℓ, c) → (ℓ + 1, c)
    /// of the cross indices solved, and the slaved node's (the window's
    /// known vertices are the same at every level).
    pairs: Vec<CheckedPair>,
    slaved_pair: Option<CheckedPair>,
}

impl<F, L, const M: usize> Evolution000<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    /// An evolution from the first two levels `first` (ℓ = 0) and `second`
    /// (ℓ = 1), each with C + 1 values (c = 0..=C). With a natural far end the
    /// value at c = C of `second` is only the starting guess of its
    /// constraint, which is solved here.
    ///
    /// # Errors
    /// [`Error::DimensionMismatch`] for levels of different or too small
    /// sizes, [`Error::NonFinite`] for non-finite data,
    /// [`Error::InvalidParameter`] naming the node when two neighbouring
    /// values are not joined by a chart step (a relative rotation at the cut
    /// locus, angle π),
    /// [`Error::VertexSolveFailure`] when the slaved node cannot be solved.
    pub fn new(
        direction: Direction,
        lag: L,
        first: &[F::Point<f64>],
        second: &[F::Point<f64>],
        near: EndCondition<F::Point<f64>>,
        far: EndCondition<F::Point<f64>>,
        options: CauchyOptions,
    ) -> Result<Self> {
        if first.len() < 2 || second.len() != first.len() {
            return Err(Error::DimensionMismatch {
                what: "second initial level (as many nodes as the first, at least 2)".into(),
                expected: first.len().max(2),
                got: second.len(),
            });
        }
        let end_cell = matches!(far, EndCondition::EndCell);
        let misplaced = if matches!(near, EndCondition::EndCell) {
            Some("near end")
        } else if end_cell && direction != Direction::Time {
            Some("far end")
        } else {
            None
        };
        if let Some(name) = misplaced {
            return Err(Error::InvalidParameter {
                name: name.into(),
                value: "end cell".into(),
                reason: "an end cell closes the far end of a time evolution only".into(),
            });
        }
        // The end cell's placeholder node: the last node again.
        let extended = |level: &[F::Point<f64>]| {
            let mut v = level.to_vec();
            if end_cell {
                v.push(level[level.len() - 1]);
            }
            v
        };
        let (first, second) = (&extended(first)[..], &extended(second)[..]);
        let cross = first.len() - 1;
        // Neighbouring values must be joined by a chart step: a rotation at
        // the cut locus is refused here, naming the node, rather than
        // failing later as a non-finite residual.
        for (l, level) in [first, second].into_iter().enumerate() {
            if let Some(c) = level.iter().position(|y| !F::is_finite(y)) {
                return Err(Error::NonFinite {
                    what: format!("initial level {l}, cross index {c}"),
                    index: c,
                    value: f64::NAN,
                });
            }
        }
        for (l, level) in [first, second].into_iter().enumerate() {
            for c in 0..=cross {
                let pairs = [
                    (c < cross).then(|| (level[c], level[c + 1], "its cross neighbour")),
                    (l == 0).then(|| (first[c], second[c], "the next level")),
                ];
                for (a, b, what) in pairs.into_iter().flatten() {
                    if let Err(e) = F::log(&a, &b) {
                        return Err(Error::InvalidParameter {
                            name: format!("initial level {l}, cross index {c}"),
                            value: format!("{:?} direction", direction).to_lowercase(),
                            reason: format!("no chart step to {what}: {e}"),
                        });
                    }
                }
            }
        }
        let window = match direction {
            Direction::Time => SpacetimeLattice::seed000(2, cross)?,
            Direction::Space => SpacetimeLattice::seed000(cross, 2)?,
        };
        let mut values = vec![first[0]; window.vertex_count()];
        let mut known = vec![false; window.vertex_count()];
        for c in 0..=cross {
            for (w, level) in [(0, first), (1, second), (2, second)] {
                let v = Self::index(direction, cross, w, c);
                values[v] = level[c];
                known[v] = w < 2;
            }
        }
        if far.is_natural() {
            known[Self::index(direction, cross, 1, cross)] = false;
        }
        if end_cell {
            for w in 0..2 {
                known[Self::index(direction, cross, w, cross)] = true;
            }
            let cell = window.cell(cross - 1);
            if (0..2).any(|l| lag.depends(&cell, l, 2)) {
                return Err(Error::InvalidParameter {
                    name: "far end".into(),
                    value: "end cell".into(),
                    reason: format!(
                        "the Lagrangian's cell at cross index {} depends on its third vertex: it has no end cell",
                        cross - 1
                    ),
                });
            }
        }
        let marcher = FlowMarcher::new(window, lag, values, known, options)?;
        let slaved = Self::index(direction, cross, 1, cross);
        let slaved_pair = far.is_natural().then(|| marcher.check(slaved, slaved)).transpose()?;
        let mut evolution = Self {
            direction,
            cross,
            end_cell,
            near,
            far,
            marcher,
            level: 1,
            jacobians: vec![None; cross + 1],
            pairs: Vec::new(),
            slaved_pair,
        };
        if evolution.far.is_natural() {
            evolution.solve_slaved()?;
        }
        // Each pair is checked in the window as a step solves it: every
        // vertex of levels ℓ − 1 and ℓ known (as now), at level ℓ + 1 the
        // prescribed ends and the nodes solved before it (lower c).
        let mut marked: Vec<usize> = [(0, &evolution.near), (cross, &evolution.far)]
            .into_iter()
            .filter(|(_, end)| matches!(end, EndCondition::Prescribed(_)))
            .map(|(c, _)| evolution.vertex(2, c))
            .collect();
        let mark = |evolution: &mut Self, v: usize, known: bool| {
            let value = evolution.marcher.values()[v];
            evolution.marcher.set(v, value, known);
        };
        for &v in &marked {
            mark(&mut evolution, v, true);
        }
        let start = usize::from(!evolution.near.is_natural());
        let (mut pairs, mut failure) = (Vec::with_capacity(cross), None);
        for c in start..cross {
            let (v, dv) = (evolution.vertex(1, c), evolution.vertex(2, c));
            match evolution.marcher.check(v, dv) {
                Ok(pair) => pairs.push(pair),
                Err(e) => {
                    failure = Some(e);
                    break;
                }
            }
            mark(&mut evolution, dv, true);
            marked.push(dv);
        }
        for &v in &marked {
            mark(&mut evolution, v, false);
        }
        if let Some(e) = failure {
            return Err(e);
        }
        evolution.pairs = pairs;
        Ok(evolution)
    }

    /// Window vertex of (window level w, cross index c).
    fn index(direction: Direction, cross: usize, w: usize, c: usize) -> usize {
        match direction {
            Direction::Time => w * (cross + 1) + c,
            Direction::Space => c * 3 + w,
        }
    }

    fn vertex(&self, w: usize, c: usize) -> usize {
        Self::index(self.direction, self.cross, w, c)
    }

    fn solve_slaved(&mut self) -> Result<VertexOutcome> {
        let v = self.vertex(1, self.cross);
        let kept = &mut self.jacobians[self.cross];
        let solved = match &self.slaved_pair {
            Some(pair) => self.marcher.solve_checked(pair, kept),
            None => self.marcher.solve_reusing(v, v, kept),
        };
        solved.map_err(|e| self.name_node(e, self.level, self.cross))
    }

    /// Renames a vertex-solve failure after the lattice node (j, a) whose
    /// equation failed (the marcher knows only window vertices).
    fn name_node(&self, e: Error, level: usize, c: usize) -> Error {
        let (j, a) = match self.direction {
            Direction::Time => (level, c),
            Direction::Space => (c, level),
        };
        let role = if c == self.cross && self.far.is_natural() {
            "slaved node"
        } else if c == self.cross() && self.end_cell {
            "end node"
        } else {
            "node"
        };
        match e {
            Error::VertexSolveFailure {
                residual,
                iterations,
                reason,
                ..
            } => Error::VertexSolveFailure {
                vertex: format!("{role} (j, a) = ({j}, {a}) of the {:?} evolution", self.direction).to_lowercase(),
                residual,
                iterations,
                reason,
            },
            other => other,
        }
    }

    /// The marching direction.
    pub fn direction(&self) -> Direction {
        self.direction
    }

    /// The last cross index C (A in time evolution, N in space evolution).
    pub fn cross(&self) -> usize {
        self.cross - usize::from(self.end_cell)
    }

    /// The cells of a band between two levels: C, or C + 1 with an end cell.
    pub fn cells(&self) -> usize {
        self.cross
    }

    /// Whether the far end is closed by an end cell ([`EndCondition::EndCell`]):
    /// then [`for_each_cell`](Self::for_each_cell) visits C + 1 cells.
    pub fn has_end_cell(&self) -> bool {
        self.end_cell
    }

    /// Keeps the window's cells at the lattice's coordinates: the cells
    /// between the previous and the current level are the lattice's cell
    /// row ℓ − 1 (time) or column ℓ − 1 (space).
    fn place_window(&mut self) {
        let behind = self.level as i64 - 1;
        let lattice = self.marcher.complex_mut();
        match self.direction {
            Direction::Time => lattice.set_origin_offset(0, behind),
            Direction::Space => lattice.set_origin_offset(behind, 0),
        }
    }

    /// The index ℓ of the current (latest complete) level.
    pub fn level(&self) -> usize {
        self.level
    }

    /// The cell Lagrangian.
    pub fn lagrangian(&self) -> &L {
        self.marcher.lagrangian()
    }

    /// The value at cross index `c` of the current level (`back` = 0) or of
    /// the previous one (`back` = 1).
    pub fn value(&self, back: usize, c: usize) -> F::Point<f64> {
        self.marcher.values()[self.vertex(1 - back.min(1), c)]
    }

    /// Copies the current (`back` = 0) or previous (`back` = 1) level into `out` (C + 1 values).
    pub fn copy_level(&self, back: usize, out: &mut [F::Point<f64>]) {
        for (c, slot) in out.iter_mut().enumerate().take(self.cross() + 1) {
            *slot = self.value(back, c);
        }
    }

    /// Computes level ℓ + 1 from levels ℓ − 1 and ℓ. On failure the window
    /// keeps levels ℓ − 1 and ℓ and the error names the failing node (window
    /// vertex; its cross index is the failing c).
    pub fn step(&mut self) -> Result<LevelReport> {
        let cross = self.cross;
        let next = self.level + 1;
        let mut report = LevelReport {
            level: self.level as i64,
            ..LevelReport::default()
        };
        let mut add = |o: VertexOutcome| {
            report.iterations += o.iterations;
            report.jacobians += o.jacobians;
            report.max_relative_residual = report.max_relative_residual.max(o.relative_residual);
        };
        // Starting guesses: the linear extrapolation y_ℓ·τ(log(y_{ℓ−1}, y_ℓ)).
        for c in 0..=cross {
            let guess = F::extrapolate(&self.value(1, c), &self.value(0, c));
            let v = self.vertex(2, c);
            self.marcher.set(v, guess, false);
        }
        for c in [0, cross] {
            let end = if c == 0 { &self.near } else { &self.far };
            if let EndCondition::Prescribed(data) = end {
                let y = data(next);
                if !F::is_finite(&y) {
                    return Err(Error::NonFinite {
                        what: format!("prescribed end value at cross index {c}, level {next}"),
                        index: c,
                        value: f64::NAN,
                    });
                }
                let v = self.vertex(2, c);
                self.marcher.set(v, y, true);
            }
        }
        let start = usize::from(!self.near.is_natural());
        for (c, pair) in (start..cross).zip(&self.pairs) {
            let solved = self.marcher.solve_checked(pair, &mut self.jacobians[c]);
            add(solved.map_err(|e| self.name_node(e, self.level, c))?);
        }
        if self.end_cell {
            let last = self.marcher.values()[self.vertex(2, cross - 1)];
            let v = self.vertex(2, cross);
            self.marcher.set(v, last, true);
        }
        // Roll the window: levels ℓ, ℓ + 1 become the previous and current ones.
        let slaved = self.far.is_natural();
        for c in 0..=cross {
            let (y1, y2) = (self.value(0, c), self.marcher.values()[self.vertex(2, c)]);
            let (v0, v1, v2) = (self.vertex(0, c), self.vertex(1, c), self.vertex(2, c));
            self.marcher.set(v0, y1, true);
            self.marcher.set(v1, y2, !(slaved && c == cross));
            self.marcher.set(v2, y2, false);
        }
        self.level = next;
        self.place_window();
        if slaved {
            add(self.solve_slaved()?);
        }
        Ok(report)
    }

    /// Calls `f(c, cell, y)` for the cells c = 0..C − 1 between the previous
    /// and the current level (and the end cell c = C, if the far end has one),
    /// with their vertex values in seed 000's order
    /// (vertex 1 = (j, a), 2 = (j + 1, a), 3 = (j, a + 1)).
    pub fn for_each_cell(&self, mut f: impl FnMut(usize, &TopCell, &[F::Point<f64>; 3])) {
        let lattice = self.marcher.complex();
        for c in 0..self.cross {
            let (base, fwd, side) = (self.value(1, c), self.value(0, c), self.value(1, c + 1));
            let (index, y) = match self.direction {
                Direction::Time => (c, [base, fwd, side]),
                Direction::Space => (2 * c, [base, side, fwd]),
            };
            f(c, &lattice.cell(index), &y);
        }
    }

    /// Position of the forward vertex in a cell (1 in time, 2 in space).
    pub fn forward_position(&self) -> usize {
        match self.direction {
            Direction::Time => 1,
            Direction::Space => 2,
        }
    }

    /// The currents `[J^base, J^fwd, J^cross]` (the cell's vertices on the
    /// previous level, on the current level, and its neighbour on the
    /// previous level) of cell `c` between the previous and the current
    /// level, `J^k = X(y_k)ᵀ ∂ℒ/∂y_k` for the generators `generator(y)` = X(y)
    /// (∂ℒ/∂y_k in the Lagrangian's closed form where it has one,
    /// [`exact_gradient`]).
    pub fn cell_currents<const K: usize>(
        &self,
        c: usize,
        generator: impl Fn(&F::Point<f64>) -> SMatrix<f64, M, K>,
    ) -> [SVector<f64, K>; 3] {
        let fwd = self.forward_position();
        let side = 3 - fwd;
        let lag = self.marcher.lagrangian();
        let lattice = self.marcher.complex();
        let (base, forward, cross) = (self.value(1, c), self.value(0, c), self.value(1, c + 1));
        let (index, y) = match self.direction {
            Direction::Time => (c, [base, forward, cross]),
            Direction::Space => (2 * c, [base, cross, forward]),
        };
        let cell = lattice.cell(index);
        let j = |l: usize| generator(&y[l]).transpose() * exact_gradient::<F, L, M>(lag, &cell, &y, l);
        [j(0), j(fwd), j(side)]
    }

    /// 𝖩⁺ and 𝖩⁻ of the cell level between the previous and the current
    /// level, for the generators `generator(y)` = X(y) (M × K).
    pub fn evolution_momentum<const K: usize>(
        &self,
        generator: impl Fn(&F::Point<f64>) -> SMatrix<f64, M, K>,
    ) -> EvolutionMomentum<K> {
        let mut out = EvolutionMomentum {
            plus: SVector::zeros(),
            minus: SVector::zeros(),
            scale: 0.0,
        };
        for c in 0..self.cross {
            let [base, fwd, cross] = self.cell_currents(c, &generator);
            out.plus += fwd;
            out.minus -= base + cross;
            out.scale += base.amax() + fwd.amax() + cross.amax();
        }
        out
    }
}

/// A checkpoint of an evolution: the level index, the previous and current
/// levels, each value by its coordinates ([`Fibre::write`], read back
/// exactly by [`Fibre::read`]), and the Newton Jacobians kept for the next
/// level; the window is rebuilt as a step leaves it, so a restored run
/// continues bit for bit. End conditions are part of the set-up.
impl<F, L, const M: usize> Checkpoint for Evolution000<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    fn save(&self, out: &mut Vec<f64>) {
        out.push(self.level as f64);
        let mut c = [0.0; 16];
        let k = F::COORDINATES.min(c.len());
        for back in [1, 0] {
            for node in 0..=self.cross {
                F::write(&self.value(back, node), &mut c[..k]);
                out.extend_from_slice(&c[..k]);
            }
        }
        // The factors of the kept Newton Jacobians: the next level's
        // iterations depend on them. Tag 2: factors follow; tag 3: none.
        // (Earlier versions wrote tag 1 and a Jacobian, or tag 0 and zeros.)
        for j in &self.jacobians {
            SmallLu::save_kept(j, out);
        }
    }

    fn restore(&mut self, words: &mut Words<'_>) -> Result<()> {
        let level = words.one()?;
        if !(level.is_finite() && level >= 1.0 && level.fract() == 0.0 && level < 2f64.powi(52)) {
            return Err(Error::InvalidParameter {
                name: "checkpoint".into(),
                value: level.to_string(),
                reason: "not a level number".into(),
            });
        }
        // Every word is read before anything is replaced: a damaged
        // checkpoint leaves the evolution as it was.
        let nodes = self.cross + 1;
        let levels = read_points::<F, M>(words, 2 * nodes, |i| {
            format!("node {} of stored level {}", i % nodes, i / nodes)
        })?;
        let mut jacobians = Vec::with_capacity(self.jacobians.len());
        for _ in 0..self.jacobians.len() {
            jacobians.push(if words.take_tag(0.0) {
                words.take(M * M)?;
                None
            } else if words.take_tag(1.0) {
                // The Jacobian an earlier version kept, factored as this
                // version factors a fresh one (the run continues, not bit for
                // bit with that version: its back substitution divided).
                let mut m = SMatrix::<f64, M, M>::zeros();
                words.fill(m.as_mut_slice())?;
                SmallLu::factor(&m).0
            } else {
                SmallLu::restore_kept(words)?
            });
        }
        // After a step every value of both levels is known (the slaved
        // node solved as soon as its level is complete).
        for (w, level_values) in levels.chunks(nodes).enumerate() {
            for (node, &y) in level_values.iter().enumerate() {
                self.marcher.set(self.vertex(w, node), y, true);
                if w == 1 {
                    self.marcher.set(self.vertex(2, node), y, false);
                }
            }
        }
        self.jacobians = jacobians;
        self.level = level as usize;
        self.place_window();
        Ok(())
    }
}

/// Drives an [`Evolution000`] on the run pipeline: one level per step, the
/// level ℓ at time (or arc length) (ℓ − origin)·`step_length`.
pub struct EvolutionStepper<F, L, const M: usize> {
    /// Δt in time evolution, Δs in space evolution.
    pub step_length: f64,
    /// The level at time (or arc length) 0.
    pub origin: f64,
    _evolution: std::marker::PhantomData<fn() -> (F, L)>,
}

impl<F, L, const M: usize> EvolutionStepper<F, L, M> {
    /// A stepper with levels `step_length` apart.
    pub fn new(step_length: f64) -> Self {
        Self {
            step_length,
            origin: 0.0,
            _evolution: std::marker::PhantomData,
        }
    }
    /// The same stepper with level `origin` at time 0 (1 when the first
    /// given level is one step before the start).
    pub fn with_origin(self, origin: f64) -> Self {
        Self { origin, ..self }
    }
}

impl<F, L, const M: usize> Stepper for EvolutionStepper<F, L, M>
where
    F: Fibre<M>,
    F::Point<f64>: Send + Sync,
    L: DiscreteLagrangian<F, M>,
{
    type State = Evolution000<F, L, M>;
    fn step(&mut self, _index: u64, e: &mut Evolution000<F, L, M>) -> Result<StepStats> {
        let report = e.step()?;
        Ok(StepStats {
            iterations: report.iterations,
            ..StepStats::default()
        })
    }
    fn time(&self, e: &Evolution000<F, L, M>) -> f64 {
        (e.level() as f64 - self.origin) * self.step_length
    }
    fn non_finite(&self, e: &Evolution000<F, L, M>) -> Option<String> {
        (0..=e.cross)
            .any(|c| !F::is_finite(&e.value(0, c)))
            .then(|| format!("level {}", e.level()))
    }
}

impl<F, L, const M: usize> Checkpoint for EvolutionStepper<F, L, M> {
    fn save(&self, _: &mut Vec<f64>) {}
    fn restore(&mut self, _: &mut Words<'_>) -> Result<()> {
        Ok(())
    }
}
