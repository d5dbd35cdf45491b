//! The 1+1 spacetime lattices of seeds 002 and 000 as top-cell complexes.
//!
//! * Seed 002 (§5.1; [`crate::spacetime::lattice`], [`crate::spacetime::density`]):
//!   node (i, j), i = space, j = time; triangle Δ(i,j) = ((i,j), (i,j+1),
//!   (i+1,j+1)) and rectangle R(i,j) = ((i,j), (i,j+1), (i+1,j+1), (i+1,j)).
//!   [`TopCell::origin`] = [i, j]. Spatial boundary: periodic (N nodes, N
//!   cells per level) or open — Dirichlet and free alike (N nodes, N − 1 cells
//!   per level); the boundary values themselves belong to the variational layer.
//! * Seed 000 (note 000 "Grid"): node (j, a), j = time, a = space; triangle
//!   △_a^j = ((j,a), (j+1,a), (j,a+1)) — the other diagonal. Nodes j = 0..=N,
//!   a = 0..=A, N·A triangles; [`TopCell::origin`] = [j, a]. Row N appears only
//!   as vertex 2 and column A only as vertex 3 (the slaved row and column of
//!   note 000), and the corner (N, A) is in no triangle (empty star).
//!
//! Vertices are numbered level by level: seed 002 vertex j·(space nodes) + i,
//! seed 000 vertex j·(A + 1) + a (A + 1 → A on a periodic space axis); cells
//! likewise, cell index = (time origin)·(cells per level) + space origin.

use crate::complex::window::Axis;
use crate::complex::{MAX_LATTICE_DIMENSION, StarEntry, TopCell, TopCells};
use crate::error::Result;
use crate::error::invalid;

/// The cell kind of a 1+1 lattice; [`TopCell::shape`] is [`SpacetimeKind::tag`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SpacetimeKind {
    /// Seed 002 triangle ((i,j), (i,j+1), (i+1,j+1)), tag 0.
    Seed002Triangle,
    /// Seed 002 rectangle ((i,j), (i,j+1), (i+1,j+1), (i+1,j)), tag 1.
    Seed002Rectangle,
    /// Seed 000 triangle ((j,a), (j+1,a), (j,a+1)), tag 2.
    Seed000Triangle,
}

impl SpacetimeKind {
    /// The per-kind shape tag.
    pub fn tag(&self) -> usize {
        match self {
            SpacetimeKind::Seed002Triangle => 0,
            SpacetimeKind::Seed002Rectangle => 1,
            SpacetimeKind::Seed000Triangle => 2,
        }
    }
    /// Vertex offsets (space, time) from the cell's base node, in vertex order.
    fn offsets(&self) -> &'static [(i64, i64)] {
        match self {
            SpacetimeKind::Seed002Triangle => &[(0, 0), (0, 1), (1, 1)],
            SpacetimeKind::Seed002Rectangle => &[(0, 0), (0, 1), (1, 1), (1, 0)],
            SpacetimeKind::Seed000Triangle => &[(0, 0), (0, 1), (1, 0)],
        }
    }
    fn space_first(&self) -> bool {
        !matches!(self, SpacetimeKind::Seed000Triangle)
    }
}

/// A finite 1+1 lattice of one cell kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpacetimeLattice {
    kind: SpacetimeKind,
    space: Axis,
    time_cells: usize,
    /// Added to every cell's (space, time) origin: a window of a larger
    /// lattice reports its cells' coordinates in the larger one.
    offset: (i64, i64),
}

impl SpacetimeLattice {
    /// A lattice of `space.cells` cells per level along an open or periodic
    /// space axis and `time_cells` levels of cells (`time_cells + 1` time levels).
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] for no time cells, an open space
    /// axis of no cells or a periodic one of fewer than 3, or a size overflow.
    pub fn new(kind: SpacetimeKind, space: Axis, time_cells: usize) -> Result<Self> {
        if time_cells == 0 {
            return Err(invalid(
                "time_cells",
                time_cells,
                "at least one level of cells (window too small)",
            ));
        }
        if space.periodic && space.cells < 3 {
            return Err(invalid(
                "space.cells",
                space.cells,
                "a periodic axis needs at least 3 cells",
            ));
        }
        if space.cells == 0 {
            return Err(invalid(
                "space.cells",
                space.cells,
                "at least one cell per level (window too small)",
            ));
        }
        if space.cells > (i64::MAX / 4) as usize || time_cells > (i64::MAX / 4) as usize {
            return Err(invalid("space.cells", space.cells, "the lattice is too large"));
        }
        let l = Self {
            kind,
            space,
            time_cells,
            offset: (0, 0),
        };
        let too_large = || invalid("space.cells", space.cells, "the lattice is too large");
        l.space_nodes().checked_mul(time_cells + 1).ok_or_else(too_large)?;
        i64::try_from(l.space_nodes().max(time_cells + 1)).map_err(|_| too_large())?;
        Ok(l)
    }
    /// The seed 000 beam lattice: nodes j = 0..=`n` (time), a = 0..=`a` (space),
    /// `n`·`a` triangles ((j,a), (j+1,a), (j,a+1)).
    ///
    /// # Errors
    /// As [`SpacetimeLattice::new`].
    pub fn seed000(n: usize, a: usize) -> Result<Self> {
        Self::new(SpacetimeKind::Seed000Triangle, Axis::open(a), n)
    }
    /// Places this lattice as a window of a larger one: the cells report
    /// their [`TopCell::origin`] shifted by (`space`, `time`) (vertex and
    /// cell indices stay the window's). A marcher rolling a window along a
    /// lattice moves it level by level, so that cell Lagrangians that depend
    /// on a cell's position (loads in time, weights at the ends) see the
    /// lattice's coordinates.
    pub fn set_origin_offset(&mut self, space: i64, time: i64) {
        self.offset = (space, time);
    }
    /// The cell kind.
    pub fn kind(&self) -> SpacetimeKind {
        self.kind
    }
    /// Nodes per time level.
    pub fn space_nodes(&self) -> usize {
        self.space.cells + usize::from(!self.space.periodic)
    }
    /// Number of time levels.
    pub fn time_nodes(&self) -> usize {
        self.time_cells + 1
    }
    /// The vertex index of node (space, time), `None` outside (space wrapped
    /// on a periodic axis).
    pub fn vertex_at(&self, space: i64, time: i64) -> Option<usize> {
        let m = self.space_nodes() as i64;
        let x = if self.space.periodic {
            space.rem_euclid(m)
        } else {
            space
        };
        if !(0..m).contains(&x) || !(0..self.time_nodes() as i64).contains(&time) {
            return None;
        }
        Some(time as usize * self.space_nodes() + x as usize)
    }
    /// The node (space, time) of vertex `v`.
    pub fn node(&self, v: usize) -> (i64, i64) {
        ((v % self.space_nodes()) as i64, (v / self.space_nodes()) as i64)
    }
    fn cell_at(&self, space: i64, time: i64) -> Option<usize> {
        let m = self.space.cells as i64;
        let x = if self.space.periodic {
            space.rem_euclid(m)
        } else {
            space
        };
        if !(0..m).contains(&x) || !(0..self.time_cells as i64).contains(&time) {
            return None;
        }
        Some(time as usize * self.space.cells + x as usize)
    }
    fn origin(&self, space: i64, time: i64) -> [i64; MAX_LATTICE_DIMENSION] {
        let (space, time) = (space + self.offset.0, time + self.offset.1);
        let mut o = [0; MAX_LATTICE_DIMENSION];
        if self.kind.space_first() {
            o[0] = space;
            o[1] = time;
        } else {
            o[0] = time;
            o[1] = space;
        }
        o
    }
}

impl TopCells for SpacetimeLattice {
    fn dimension(&self) -> usize {
        2
    }
    fn vertex_count(&self) -> usize {
        self.space_nodes() * self.time_nodes()
    }
    fn cell_count(&self) -> usize {
        self.space.cells * self.time_cells
    }
    fn max_cell_vertices(&self) -> usize {
        self.kind.offsets().len()
    }
    fn cell(&self, index: usize) -> TopCell {
        let x = (index % self.space.cells) as i64;
        let t = (index / self.space.cells) as i64;
        TopCell {
            index,
            shape: self.kind.tag(),
            origin: self.origin(x, t),
        }
    }
    fn cell_vertices(&self, index: usize, out: &mut [usize]) -> usize {
        let x = (index % self.space.cells) as i64;
        let t = (index / self.space.cells) as i64;
        let offsets = self.kind.offsets();
        for (slot, &(dx, dt)) in out.iter_mut().zip(offsets) {
            *slot = self.vertex_at(x + dx, t + dt).unwrap_or(usize::MAX);
        }
        offsets.len()
    }
    fn star(&self, v: usize, out: &mut Vec<StarEntry>) {
        out.clear();
        if v >= self.vertex_count() {
            return;
        }
        let (x, t) = self.node(v);
        for (position, &(dx, dt)) in self.kind.offsets().iter().enumerate() {
            if let Some(cell) = self.cell_at(x - dx, t - dt) {
                out.push(StarEntry { cell, position });
            }
        }
        out.sort_unstable_by_key(|e| e.cell);
    }
}

#[cfg(test)]
mod tests {
    use crate::complex::*;

    #[test]
    fn sizes_and_wrap() {
        let t = SpacetimeLattice::new(SpacetimeKind::Seed002Triangle, Axis::open(4), 2).expect("triangles");
        assert_eq!((t.vertex_count(), t.cell_count(), t.max_cell_vertices()), (15, 8, 3));
        let mut star = Vec::new();
        t.star(t.vertex_at(0, 0).expect("node"), &mut star);
        assert_eq!(star, vec![StarEntry { cell: 0, position: 0 }]);
        let per = SpacetimeLattice::new(SpacetimeKind::Seed002Triangle, Axis::periodic(4), 2).expect("periodic");
        assert_eq!(per.vertex_at(-1, 0), Some(3));
        let mut out = [0; 3];
        per.cell_vertices(3, &mut out);
        assert_eq!(out, [3, 7, 4]);
    }
}
