//! The cubic lattice complex (seed 003 Def. 2.9, note 003 §1.3) in any
//! dimension n ≤ [`MAX_LATTICE_DIMENSION`], implicit (no stored matrices).
//!
//! A cell α ∈ (½ℤ)ⁿ is the open unit cube centred at α; dim α is the number of
//! half-integer coordinates i₁ < … < i_k. Cells are stored by their *doubled*
//! integer coordinates 2α (odd = half-integer). The boundary is
//! ∂c_β = Σ_{j=1}^{k} Σ_{s=±1} (−1)^{j−1} s · c_{β + (s/2) e_{i_j}}
//! (the paper's "β + s e_{i_j}" is in doubled coordinates: note 003 erratum 1).
//!
//! Vertex order of a cell: binary, vertex b (0 ≤ b < 2^k) has coordinate
//! α_{i_m} + ½ when bit m of b is set and α_{i_m} − ½ otherwise; for a top cell
//! with base vertex v, vertex b is v + Σ_{bit i of b} e_i.

use crate::complex::cellular::{CellComplex, FiniteComplex};
use crate::complex::window::{Axis, Extent, Point, check_dimension, keep_wrapped};
use crate::complex::{MAX_LATTICE_DIMENSION, StarEntry, TopCell, TopCells};
use crate::error::Result;

/// A cell of the cubic lattice: doubled coordinates 2α (zero beyond n).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct CubicCell {
    /// 2α.
    pub doubled: Point,
}

impl CubicCell {
    /// The vertex (0-cell) at the lattice point `p`.
    pub fn vertex(p: &Point) -> Self {
        let mut doubled = [0; MAX_LATTICE_DIMENSION];
        for (d, x) in doubled.iter_mut().zip(p) {
            *d = 2 * x;
        }
        Self { doubled }
    }
    /// The top cell (unit cube) with base vertex `p` in dimension `n`: p + ½(1, …, 1).
    pub fn cube(n: usize, p: &Point) -> Self {
        let mut c = Self::vertex(p);
        for d in c.doubled.iter_mut().take(n) {
            *d += 1;
        }
        c
    }
    /// The least vertex (all coordinates rounded down).
    pub fn base(&self) -> Point {
        let mut p = [0; MAX_LATTICE_DIMENSION];
        for (x, d) in p.iter_mut().zip(&self.doubled) {
            *x = d.div_euclid(2);
        }
        p
    }
}

fn half_positions(n: usize, c: &CubicCell) -> impl Iterator<Item = usize> + '_ {
    (0..n).filter(|&i| c.doubled[i].rem_euclid(2) == 1)
}

fn raw_faces(n: usize, c: &CubicCell, out: &mut Vec<(CubicCell, i8)>) {
    out.clear();
    for (j, h) in half_positions(n, c).enumerate() {
        let parity: i8 = crate::complex::cellular::parity(j);
        for s in [-1i8, 1] {
            let mut a = *c;
            a.doubled[h] += i64::from(s);
            out.push((a, parity * s));
        }
    }
}

fn raw_cofaces(n: usize, c: &CubicCell, out: &mut Vec<(CubicCell, i8)>) {
    out.clear();
    let mut j = 0usize;
    for i in 0..n {
        if c.doubled[i].rem_euclid(2) == 1 {
            j += 1;
            continue;
        }
        let parity: i8 = crate::complex::cellular::parity(j);
        for t in [-1i8, 1] {
            let mut b = *c;
            b.doubled[i] += i64::from(t);
            out.push((b, -parity * t));
        }
    }
}

fn raw_vertices(n: usize, c: &CubicCell) -> Vec<CubicCell> {
    let h: Vec<usize> = half_positions(n, c).collect();
    (0..1usize << h.len())
        .map(|b| {
            let mut v = *c;
            for (m, &i) in h.iter().enumerate() {
                v.doubled[i] += if b >> m & 1 == 1 { 1 } else { -1 };
            }
            v
        })
        .collect()
}

/// The infinite cubic lattice (½ℤ)ⁿ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CubicLattice {
    n: usize,
}

impl CubicLattice {
    /// The lattice in dimension `n`.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] for n = 0 or n > [`MAX_LATTICE_DIMENSION`].
    pub fn new(n: usize) -> Result<Self> {
        check_dimension(n)?;
        Ok(Self { n })
    }
}

impl CellComplex for CubicLattice {
    type Cell = CubicCell;
    fn dim(&self) -> usize {
        self.n
    }
    fn cell_dimension(&self, cell: &CubicCell) -> usize {
        half_positions(self.n, cell).count()
    }
    fn faces(&self, cell: &CubicCell, out: &mut Vec<(CubicCell, i8)>) {
        raw_faces(self.n, cell, out);
    }
    fn cofaces(&self, cell: &CubicCell, out: &mut Vec<(CubicCell, i8)>) {
        raw_cofaces(self.n, cell, out);
    }
    fn vertices(&self, cell: &CubicCell) -> Vec<CubicCell> {
        raw_vertices(self.n, cell)
    }
    fn star_cells(&self, v: &CubicCell, out: &mut Vec<CubicCell>) {
        out.clear();
        let p = v.base();
        for b in 0..1usize << self.n {
            let mut q = p;
            for (i, x) in q.iter_mut().enumerate().take(self.n) {
                *x -= (b >> i & 1) as i64;
            }
            out.push(CubicCell::cube(self.n, &q));
        }
    }
}

/// A finite window of the cubic lattice, each axis open or periodic: the
/// closed unit cubes with base vertex in 0..cells_i along every axis, with
/// coordinates taken mod cells_i along periodic axes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CubicWindow {
    extent: Extent,
}

impl CubicWindow {
    /// A window with the given axes.
    ///
    /// # Errors
    /// As [`Extent::new`].
    pub fn new(axes: &[Axis]) -> Result<Self> {
        Ok(Self {
            extent: Extent::new(axes)?,
        })
    }
    /// An open window of `cells[i]` unit cubes along axis i.
    ///
    /// # Errors
    /// As [`Extent::new`].
    pub fn open(cells: &[usize]) -> Result<Self> {
        Self::new(&cells.iter().map(|&c| Axis::open(c)).collect::<Vec<_>>())
    }
    /// A fully periodic window (an n-torus of `cells[i]` cubes along axis i).
    ///
    /// # Errors
    /// As [`Extent::new`].
    pub fn periodic(cells: &[usize]) -> Result<Self> {
        Self::new(&cells.iter().map(|&c| Axis::periodic(c)).collect::<Vec<_>>())
    }
    /// The vertex and base-vertex numbering.
    pub fn extent(&self) -> &Extent {
        &self.extent
    }
    /// The canonical representative of a lattice cell, `None` outside.
    pub fn wrap(&self, cell: &CubicCell) -> Option<CubicCell> {
        let mut doubled = [0; MAX_LATTICE_DIMENSION];
        for (i, d) in doubled.iter_mut().enumerate().take(self.extent.dimension()) {
            *d = self.extent.wrap_coordinate(i, cell.doubled[i], 2)?;
        }
        Some(CubicCell { doubled })
    }
    /// The top cell with index `index`.
    pub fn top_cell(&self, index: usize) -> CubicCell {
        CubicCell::cube(self.extent.dimension(), &self.extent.base(index))
    }
    /// Index of a top cell, `None` when it is not a top cell of the window.
    pub fn top_index(&self, cell: &CubicCell) -> Option<usize> {
        let c = self.wrap(cell)?;
        if self.cell_dimension(&c) != self.extent.dimension() {
            return None;
        }
        self.extent.base_index(&c.base())
    }
    /// Index of a vertex (0-cell), `None` when it is not a vertex of the window.
    pub fn vertex_index(&self, v: &CubicCell) -> Option<usize> {
        if self.cell_dimension(v) != 0 {
            return None;
        }
        self.extent.vertex_index(&v.base())
    }
}

impl CellComplex for CubicWindow {
    type Cell = CubicCell;
    fn dim(&self) -> usize {
        self.extent.dimension()
    }
    fn cell_dimension(&self, cell: &CubicCell) -> usize {
        half_positions(self.extent.dimension(), cell).count()
    }
    fn faces(&self, cell: &CubicCell, out: &mut Vec<(CubicCell, i8)>) {
        raw_faces(self.extent.dimension(), cell, out);
        keep_wrapped(out, |c| self.wrap(c));
    }
    fn cofaces(&self, cell: &CubicCell, out: &mut Vec<(CubicCell, i8)>) {
        raw_cofaces(self.extent.dimension(), cell, out);
        keep_wrapped(out, |c| self.wrap(c));
    }
    fn vertices(&self, cell: &CubicCell) -> Vec<CubicCell> {
        raw_vertices(self.extent.dimension(), cell)
            .into_iter()
            .filter_map(|v| self.wrap(&v))
            .collect()
    }
    fn star_cells(&self, v: &CubicCell, out: &mut Vec<CubicCell>) {
        out.clear();
        if let Some(index) = self.vertex_index(v) {
            let mut star = Vec::new();
            self.star(index, &mut star);
            out.extend(star.iter().map(|e| self.top_cell(e.cell)));
        }
    }
}

impl FiniteComplex for CubicWindow {
    fn cells(&self, k: usize) -> Vec<CubicCell> {
        let n = self.extent.dimension();
        let ranges: Vec<i64> = self
            .extent
            .axes()
            .iter()
            .map(|a| 2 * a.cells as i64 + i64::from(!a.periodic))
            .collect();
        let total: usize = ranges.iter().map(|&r| r as usize).product();
        let mut out = Vec::new();
        for mut index in 0..total {
            let mut doubled = [0; MAX_LATTICE_DIMENSION];
            for i in 0..n {
                doubled[i] = (index % ranges[i] as usize) as i64;
                index /= ranges[i] as usize;
            }
            let c = CubicCell { doubled };
            if self.cell_dimension(&c) == k {
                out.push(c);
            }
        }
        out.sort_unstable();
        out
    }
}

impl TopCells for CubicWindow {
    fn dimension(&self) -> usize {
        self.extent.dimension()
    }
    fn vertex_count(&self) -> usize {
        self.extent.vertex_count()
    }
    fn cell_count(&self) -> usize {
        self.extent.base_count()
    }
    fn max_cell_vertices(&self) -> usize {
        1 << self.extent.dimension()
    }
    fn cell(&self, index: usize) -> TopCell {
        TopCell {
            index,
            shape: 0,
            origin: self.extent.base(index),
        }
    }
    fn cell_vertices(&self, index: usize, out: &mut [usize]) -> usize {
        let n = self.extent.dimension();
        let p = self.extent.base(index);
        for (b, slot) in out.iter_mut().enumerate().take(1 << n) {
            let mut q = p;
            for (i, x) in q.iter_mut().enumerate().take(n) {
                *x += (b >> i & 1) as i64;
            }
            *slot = self.extent.vertex_index(&q).unwrap_or(usize::MAX);
        }
        1 << n
    }
    fn star(&self, v: usize, out: &mut Vec<StarEntry>) {
        out.clear();
        let n = self.extent.dimension();
        if v >= self.extent.vertex_count() {
            return;
        }
        let p = self.extent.vertex(v);
        for b in 0..1usize << n {
            let mut q = p;
            for (i, x) in q.iter_mut().enumerate().take(n) {
                *x -= (b >> i & 1) as i64;
            }
            if let Some(cell) = self.extent.base_index(&q) {
                out.push(StarEntry { cell, position: b });
            }
        }
        out.sort_unstable_by_key(|e| e.cell);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::complex::cellular::Chain;

    fn cell(d: &[i64]) -> CubicCell {
        let mut doubled = [0; MAX_LATTICE_DIMENSION];
        doubled[..d.len()].copy_from_slice(d);
        CubicCell { doubled }
    }

    #[test]
    fn boundary_of_an_edge_and_a_square() {
        let l = CubicLattice::new(2).expect("lattice");
        // ∂[0, 1] along x = [1] − [0] ("outward vector first")
        let edge = Chain::characteristic([cell(&[1, 0])]).boundary(&l);
        assert_eq!((edge.get(&cell(&[2, 0])), edge.get(&cell(&[0, 0]))), (1, -1));
        // ∂ of the unit square is its counter-clockwise boundary: edges are
        // oriented along +x or +y, so bottom and right count +1, top and left −1
        let square = Chain::characteristic([cell(&[1, 1])]).boundary(&l);
        assert_eq!(square.get(&cell(&[1, 0])), 1, "bottom");
        assert_eq!(square.get(&cell(&[2, 1])), 1, "right");
        assert_eq!(square.get(&cell(&[1, 2])), -1, "top");
        assert_eq!(square.get(&cell(&[0, 1])), -1, "left");
        assert!(square.boundary(&l).is_zero());
    }

    #[test]
    fn windows_count_their_cells() {
        let w = CubicWindow::open(&[2, 3]).expect("window");
        assert_eq!([0, 1, 2].map(|k| w.cells(k).len()), [12, 17, 6]);
        let t = CubicWindow::periodic(&[3, 4]).expect("torus");
        assert_eq!([0, 1, 2].map(|k| t.cells(k).len()), [12, 24, 12]);
    }
}
