//! Cellular complexes (seed 003 §2): the combinatorial half of the discrete
//! field theory core.
//!
//! The variational layer (action, Euler–Lagrange residuals, Noether currents,
//! marching) needs only the *top-cell view* of a finite complex: top cells
//! with their ordered vertices, and the star of every vertex (note 003 §1.1,
//! "implementation note"). That view is the trait [`TopCells`]; every complex
//! kind provides it for a finite window or a periodic quotient.
//!
//! Files: [`cellular`] (the abstract complex of Def. 2.1: [`CellComplex`],
//! chains, cochains, ∂, d, the pairing, axiom checks, orientation (2.6)/(2.7)),
//! [`window`] (finite windows of ℤⁿ with open or periodic axes, Sym(n)
//! indexing), [`cubic`] (the cubic lattice, Def. 2.9), [`cfk`] (the CFK
//! lattice, Defs. 2.11–2.18, closed-form incidence), [`cfk_window`] (its
//! windows and periodic quotients), [`cfk_geometry`] (point location Cor. 2.16,
//! the geometric incidence Def. 2.18, the CFK → cubic map (3.4)), [`mesh`]
//! (explicit simplicial meshes) and [`spacetime`] (the 1+1 lattices of seeds
//! 002 and 000).
//!
//! ```
//! use veselov::complex::{CfkWindow, SpacetimeLattice, StarEntry, TopCells};
//!
//! // A periodic 4 × 5 CFK torus: 2 simplices per square, 6 in every star.
//! let torus = CfkWindow::periodic(&[4, 5]).unwrap();
//! assert_eq!(torus.cell_count(), 40);
//! let mut star: Vec<StarEntry> = Vec::new();
//! torus.star(7, &mut star);
//! assert_eq!(star.len(), 6);
//!
//! // Seed 000's beam lattice, N = 3 time cells, A = 4 space cells.
//! let beam = SpacetimeLattice::seed000(3, 4).unwrap();
//! assert_eq!((beam.vertex_count(), beam.cell_count()), (20, 12));
//! ```

pub mod cellular;
pub mod cfk;
pub mod cfk_geometry;
pub mod cfk_window;
pub mod cubic;
pub mod mesh;
pub mod spacetime;
pub mod window;

pub use crate::complex::cellular::{
    CellComplex, Chain, Cochain, FiniteComplex, Simplicial, incidence_from_orientation, orientation, validate,
    validate_cells,
};
pub use crate::complex::cfk::{CfkCell, CfkLattice};
pub use crate::complex::cfk_geometry::{carrier_cube, geometric_incidence, locate};
pub use crate::complex::cfk_window::CfkWindow;
pub use crate::complex::cubic::{CubicCell, CubicLattice, CubicWindow};
pub use crate::complex::mesh::{MeshCell, SimplicialMesh};
pub use crate::complex::spacetime::{SpacetimeKind, SpacetimeLattice};
pub use crate::complex::window::{Axis, Extent, Point, permutation_index, permutation_into};

pub mod cfk_slab;
pub mod material_window;

pub use crate::complex::cfk_slab::{CfkSlab, CfkTorus, factorial, permutation};
pub use crate::complex::material_window::{LevelReduction, MaterialWindow};

/// Largest lattice dimension whose cells carry their coordinates inline in
/// [`TopCell::origin`].
pub const MAX_LATTICE_DIMENSION: usize = 8;

/// One top (n-)cell of a finite complex, as the variational layer sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TopCell {
    /// Index of the cell in its finite complex (`0..cell_count()`).
    pub index: usize,
    /// Shape class of the cell: the permutation index σ of a CFK simplex
    /// (v, σ), a fixed tag for the cells of 1+1 lattices, 0 for cubes and for
    /// explicit meshes. Cells of one shape class on a lattice are translates
    /// of each other.
    pub shape: usize,
    /// Lattice coordinates of the cell's base (least-weight) vertex, zero
    /// beyond the dimension; zero on explicit meshes.
    pub origin: [i64; MAX_LATTICE_DIMENSION],
}

/// A top cell containing a given vertex, with the vertex's position in the
/// cell's ordered vertex list.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StarEntry {
    /// Index of the top cell.
    pub cell: usize,
    /// Position of the vertex in the cell's ordered vertices.
    pub position: usize,
}

/// The top-cell view of a finite cellular complex (note 003 §1.1): what the
/// action, the Euler–Lagrange residual (3.1) and the Noether current (3.2)
/// need.
pub trait TopCells: Sync {
    /// Dimension n of the complex.
    fn dimension(&self) -> usize;
    /// Number of vertices (`0..vertex_count()` index them).
    fn vertex_count(&self) -> usize;
    /// Number of top cells.
    fn cell_count(&self) -> usize;
    /// Largest number of vertices of a top cell (n + 1 for simplices, 2ⁿ for cubes).
    fn max_cell_vertices(&self) -> usize;
    /// The top cell with index `index`.
    fn cell(&self, index: usize) -> TopCell;
    /// Writes the ordered vertices of cell `index` into `out`
    /// (`out.len() ≥ max_cell_vertices()`) and returns their number.
    fn cell_vertices(&self, index: usize, out: &mut [usize]) -> usize;
    /// Replaces the contents of `out` by the star S_v of vertex `v` (Def. 2.3):
    /// every top cell containing `v`, in increasing cell index.
    fn star(&self, v: usize, out: &mut Vec<StarEntry>);
}

/// A borrowed complex is a complex (marchers may hold theirs by value or by reference).
impl<T: TopCells + ?Sized> TopCells for &T {
    fn dimension(&self) -> usize {
        (**self).dimension()
    }
    fn vertex_count(&self) -> usize {
        (**self).vertex_count()
    }
    fn cell_count(&self) -> usize {
        (**self).cell_count()
    }
    fn max_cell_vertices(&self) -> usize {
        (**self).max_cell_vertices()
    }
    fn cell(&self, index: usize) -> TopCell {
        (**self).cell(index)
    }
    fn cell_vertices(&self, index: usize, out: &mut [usize]) -> usize {
        (**self).cell_vertices(index, out)
    }
    fn star(&self, v: usize, out: &mut Vec<StarEntry>) {
        (**self).star(v, out)
    }
}
