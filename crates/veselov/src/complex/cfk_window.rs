//! Finite windows and periodic quotients of the CFK lattice (note 003 §1.4):
//! the simplices of the unit cubes with base vertex in 0..cells_i along every
//! axis, coordinates taken mod cells_i along periodic axes.
//!
//! Top-cell numbering: cell (v, σ) has index `base_index(v)·n! + index(σ)`,
//! with σ indexed by [`permutation_index`](crate::complex::window::permutation_index)
//! (so [`TopCell::shape`] is the index of σ in Sym(n) and
//! [`TopCell::origin`] the base vertex v); vertices are numbered by
//! [`Extent::vertex_index`]. Stars are computed by arithmetic: the (n + 1)!
//! candidates (v − Σ_{a<q} e_{σ_a}, σ) of [`CfkLattice::star_with_positions`](crate::complex::cfk::CfkLattice::star_with_positions),
//! kept when inside the window.

use crate::complex::cellular::{CellComplex, FiniteComplex, Simplicial};
use crate::complex::cfk::{CfkCell, cofaces_in, faces_of, simplex_of, star_walk, top_record, vertices_of};
use crate::complex::window::{Axis, Extent, factorial, keep_wrapped};
use crate::complex::{MAX_LATTICE_DIMENSION, StarEntry, TopCell, TopCells};
use crate::error::Result;

/// A finite window of the CFK lattice, each axis open or periodic.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CfkWindow {
    extent: Extent,
    simplices_per_cube: usize,
}

impl CfkWindow {
    /// A window with the given axes (mix open and periodic axes freely).
    ///
    /// # Errors
    /// As [`Extent::new`]: [`crate::Error::InvalidParameter`] for a dimension
    /// 0 or above [`MAX_LATTICE_DIMENSION`], an open axis of 0 cells, a
    /// periodic axis of fewer than 3 cells, or a window whose size overflows.
    pub fn new(axes: &[Axis]) -> Result<Self> {
        let extent = Extent::new(axes)?;
        let simplices_per_cube = factorial(extent.dimension());
        extent
            .base_count()
            .checked_mul(simplices_per_cube)
            .ok_or_else(|| crate::error::invalid("axes", format!("{axes:?}"), "the window is too large"))?;
        Ok(Self {
            extent,
            simplices_per_cube,
        })
    }
    /// An open window of `cells[i]` unit cubes along axis i.
    ///
    /// # Errors
    /// As [`CfkWindow::new`].
    pub fn open(cells: &[usize]) -> Result<Self> {
        Self::new(&cells.iter().map(|&c| Axis::open(c)).collect::<Vec<_>>())
    }
    /// A fully periodic window (torus) of `cells[i]` cubes along axis i.
    ///
    /// # Errors
    /// As [`CfkWindow::new`].
    pub fn periodic(cells: &[usize]) -> Result<Self> {
        Self::new(&cells.iter().map(|&c| Axis::periodic(c)).collect::<Vec<_>>())
    }
    /// The vertex and base-vertex numbering.
    pub fn extent(&self) -> &Extent {
        &self.extent
    }
    /// The canonical representative of a lattice cell, `None` when the cell
    /// is not in the window.
    pub fn wrap(&self, cell: &CfkCell) -> Option<CfkCell> {
        let mut c = *cell;
        for i in 0..self.extent.dimension() {
            let top = cell.base[i] + i64::from(cell.labels[i] > 0);
            self.extent.wrap_coordinate(i, top, 1)?;
            c.base[i] = self.extent.wrap_coordinate(i, cell.base[i], 1)?;
        }
        Some(c)
    }
    /// The top cell with index `index`.
    pub fn top_cell(&self, index: usize) -> CfkCell {
        let n = self.extent.dimension();
        let base = self.extent.base(index / self.simplices_per_cube);
        CfkCell::top_from_index(n, &base, index % self.simplices_per_cube)
    }
    /// Index of a top cell, `None` when it is not a top cell of the window.
    pub fn top_index(&self, cell: &CfkCell) -> Option<usize> {
        let n = self.extent.dimension();
        if cell.dimension() != n {
            return None;
        }
        let c = self.wrap(cell)?;
        let base = self.extent.base_index(&c.base)?;
        let mut sigma = [0usize; MAX_LATTICE_DIMENSION];
        Some(base * self.simplices_per_cube + c.sigma(&mut sigma[..n]))
    }
    /// Index of a vertex (0-cell), `None` when it is not in the window.
    pub fn vertex_index(&self, v: &CfkCell) -> Option<usize> {
        if v.k != 0 {
            return None;
        }
        self.extent.vertex_index(&v.base)
    }
}

impl CellComplex for CfkWindow {
    type Cell = CfkCell;
    fn dim(&self) -> usize {
        self.extent.dimension()
    }
    fn cell_dimension(&self, cell: &CfkCell) -> usize {
        cell.dimension()
    }
    fn faces(&self, cell: &CfkCell, out: &mut Vec<(CfkCell, i8)>) {
        faces_of(cell, out);
        keep_wrapped(out, |c| self.wrap(c));
    }
    fn cofaces(&self, cell: &CfkCell, out: &mut Vec<(CfkCell, i8)>) {
        cofaces_in(self.extent.dimension(), cell, out);
        keep_wrapped(out, |c| self.wrap(c));
    }
    fn vertices(&self, cell: &CfkCell) -> Vec<CfkCell> {
        vertices_of(cell).into_iter().filter_map(|v| self.wrap(&v)).collect()
    }
    fn star_cells(&self, v: &CfkCell, out: &mut Vec<CfkCell>) {
        out.clear();
        if let Some(index) = self.vertex_index(v) {
            let mut star = Vec::new();
            self.star(index, &mut star);
            out.extend(star.iter().map(|e| self.top_cell(e.cell)));
        }
    }
}

impl Simplicial for CfkWindow {
    /// The cell spanned by the given vertices. On a periodic quotient the
    /// vertices are lifted to the lattice one coordinate at a time: each
    /// periodic coordinate is taken within one period above the least one.
    fn simplex(&self, vertices: &[CfkCell]) -> Option<CfkCell> {
        let n = self.extent.dimension();
        let mut lifted: Vec<CfkCell> = vertices.to_vec();
        for (i, axis) in self.extent.axes().iter().enumerate() {
            if axis.periodic {
                let m = axis.cells as i64;
                let lo = lifted.iter().map(|v| v.base[i]).min()?;
                let hi = lifted.iter().map(|v| v.base[i]).max()?;
                // a cell spans at most one unit along an axis: lift the wrap-around pair
                if hi - lo == m - 1 {
                    for v in lifted.iter_mut() {
                        if v.base[i] == lo {
                            v.base[i] += m;
                        }
                    }
                }
            }
        }
        self.wrap(&simplex_of(n, &lifted)?)
    }
}

impl FiniteComplex for CfkWindow {
    fn cells(&self, k: usize) -> Vec<CfkCell> {
        let n = self.extent.dimension();
        let mut out = Vec::new();
        let labelings = (k + 1).pow(n as u32);
        for v in 0..self.extent.vertex_count() {
            let base = self.extent.vertex(v);
            for mut code in 0..labelings {
                let mut cell = CfkCell::vertex(&base);
                cell.k = k as u8;
                let mut used = 0u32;
                for l in cell.labels.iter_mut().take(n) {
                    *l = (code % (k + 1)) as u8;
                    code /= k + 1;
                    used |= 1 << *l;
                }
                if used >> 1 == (1u32 << k) - 1 && self.wrap(&cell) == Some(cell) {
                    out.push(cell);
                }
            }
        }
        out.sort_unstable();
        out
    }
}

impl TopCells for CfkWindow {
    fn dimension(&self) -> usize {
        self.extent.dimension()
    }
    fn vertex_count(&self) -> usize {
        self.extent.vertex_count()
    }
    fn cell_count(&self) -> usize {
        self.extent.base_count() * self.simplices_per_cube
    }
    fn max_cell_vertices(&self) -> usize {
        self.extent.dimension() + 1
    }
    fn cell(&self, index: usize) -> TopCell {
        top_record(self.extent.dimension(), index, &self.top_cell(index))
    }
    fn cell_vertices(&self, index: usize, out: &mut [usize]) -> usize {
        let n = self.extent.dimension();
        let cell = self.top_cell(index);
        for (a, slot) in out.iter_mut().enumerate().take(n + 1) {
            *slot = self.extent.vertex_index(&cell.vertex_at(a)).unwrap_or(usize::MAX);
        }
        n + 1
    }
    fn star(&self, v: usize, out: &mut Vec<StarEntry>) {
        out.clear();
        if v >= self.extent.vertex_count() {
            return;
        }
        let p = self.extent.vertex(v);
        let per = self.simplices_per_cube;
        star_walk(self.extent.dimension(), &p, &mut |base, shape, position| {
            if let Some(b) = self.extent.base_index(base) {
                out.push(StarEntry {
                    cell: b * per + shape,
                    position,
                });
            }
        });
        out.sort_unstable_by_key(|e| e.cell);
    }
}
