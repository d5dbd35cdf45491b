//! The 1+1 spacetime lattice: nodes `(i, j)` with `i` the space index
//! (`x = i·dx`) and `j` the time index (`t = j·dt`).
//!
//! Seed 002 (§5) calls the time step `h` and the space step `k`; here they are
//! `dt` and `dx`. The Courant number is `dt/dx` (the paper's `h/k`).

use crate::complex::window::Axis;
use crate::complex::{SpacetimeKind, SpacetimeLattice};
use crate::error::{Result, invalid};

/// Spatial boundary condition of a lattice of `nodes` points `i = 0..nodes`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Boundary {
    /// `y_{i+N} = y_i` (the only condition of seed 002 §5.2).
    Periodic,
    /// Winding (quasi-periodic) condition `y_{i+N} = y_i + jump`, e.g.
    /// `jump = 2π` for a single sine-Gordon kink on a circle.
    Winding {
        /// The jump across the seam.
        jump: f64,
    },
    /// Time-independent values at the end nodes `i = 0` and `i = N−1`
    /// (scalar fields; for vector fields every component takes the value).
    Dirichlet {
        /// Value at node 0.
        left: f64,
        /// Value at node N−1.
        right: f64,
    },
    /// Free ends (zero traction): the natural boundary condition, i.e. the
    /// discrete Euler–Lagrange equation at an end node sums only the cells
    /// that exist.
    Free,
}

impl Boundary {
    /// The seam jump of a periodic or winding condition, `None` otherwise.
    pub fn jump(&self) -> Option<f64> {
        match *self {
            Boundary::Periodic => Some(0.0),
            Boundary::Winding { jump } => Some(jump),
            _ => None,
        }
    }
}

/// A validated uniform 1+1 lattice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lattice {
    nodes: usize,
    dx: f64,
    dt: f64,
    boundary: Boundary,
}

impl Lattice {
    /// A lattice of `nodes ≥ 3` points with space step `dx` and time step `dt`
    /// (both positive and finite).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`](crate::Error::InvalidParameter) naming `nodes`, `dx`, `dt` or `boundary`.
    pub fn new(nodes: usize, dx: f64, dt: f64, boundary: Boundary) -> Result<Self> {
        if nodes < 3 {
            return Err(invalid("nodes", nodes, "a lattice needs at least 3 nodes"));
        }
        for (name, v) in [("dx", dx), ("dt", dt)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(name, v, "must be positive and finite"));
            }
        }
        match boundary {
            Boundary::Winding { jump } if !jump.is_finite() => {
                return Err(invalid("boundary", format!("{boundary:?}"), "the jump must be finite"));
            }
            Boundary::Dirichlet { left, right } if !(left.is_finite() && right.is_finite()) => {
                return Err(invalid(
                    "boundary",
                    format!("{boundary:?}"),
                    "boundary values must be finite",
                ));
            }
            _ => {}
        }
        Ok(Self {
            nodes,
            dx,
            dt,
            boundary,
        })
    }

    /// A periodic lattice of `nodes` points on a circle of circumference
    /// `length` (`dx = length/nodes`) with `dt = dx/ratio`.
    ///
    /// # Errors
    /// As [`Lattice::new`], plus `length` and `ratio` must be positive and finite.
    pub fn periodic(nodes: usize, length: f64, ratio: f64) -> Result<Self> {
        for (name, v) in [("length", length), ("ratio", ratio)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(name, v, "must be positive and finite"));
            }
        }
        if nodes < 3 {
            return Err(invalid("nodes", nodes, "a lattice needs at least 3 nodes"));
        }
        let dx = length / nodes as f64;
        Self::new(nodes, dx, dx / ratio, Boundary::Periodic)
    }

    /// Number of spatial nodes `N`.
    pub fn nodes(&self) -> usize {
        self.nodes
    }
    /// Space step (the paper's `k`).
    pub fn dx(&self) -> f64 {
        self.dx
    }
    /// Time step (the paper's `h`).
    pub fn dt(&self) -> f64 {
        self.dt
    }
    /// Boundary condition.
    pub fn boundary(&self) -> Boundary {
        self.boundary
    }
    /// Spatial length `N·dx` of a periodic lattice (`(N−1)·dx` otherwise).
    pub fn length(&self) -> f64 {
        match self.boundary {
            Boundary::Periodic | Boundary::Winding { .. } => self.nodes as f64 * self.dx,
            _ => (self.nodes - 1) as f64 * self.dx,
        }
    }
    /// Position of node `i`.
    pub fn x(&self, i: usize) -> f64 {
        i as f64 * self.dx
    }
    /// Time of level `j`.
    pub fn t(&self, j: usize) -> f64 {
        j as f64 * self.dt
    }
    /// Where node `i` (any integer) is stored and how often it wraps the
    /// seam: `(i mod N, ⌊i/N⌋)` on periodic and winding lattices, whose
    /// values across the seam carry the jump once per wrap; `(i, 0)` for
    /// `0 ≤ i < N` and `None` outside otherwise.
    pub fn wrapped(&self, i: i64) -> Option<(usize, i64)> {
        let n = self.nodes as i64;
        if self.is_periodic() {
            Some((i.rem_euclid(n) as usize, i.div_euclid(n)))
        } else {
            (0..n).contains(&i).then_some((i as usize, 0))
        }
    }
    /// Is the condition periodic or winding (space index taken mod `N`)?
    pub fn is_periodic(&self) -> bool {
        self.boundary.jump().is_some()
    }
}

/// Cell shape of a lattice discretisation (seed 002 §5.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellShape {
    /// `Δ(i,j) = ((i,j), (i,j+1), (i+1,j+1))`: vertices 1, 2, 3.
    Triangle,
    /// `R(i,j) = ((i,j), (i,j+1), (i+1,j+1), (i+1,j))`: vertices 1..4.
    Rectangle,
}

impl CellShape {
    /// Offsets `(di, dj)` of the vertices from the cell origin `(i, j)`, in
    /// the paper's vertex order.
    pub fn offsets(&self) -> &'static [(i64, i64)] {
        match self {
            CellShape::Triangle => &[(0, 0), (0, 1), (1, 1)],
            CellShape::Rectangle => &[(0, 0), (0, 1), (1, 1), (1, 0)],
        }
    }
    /// Number of vertices.
    pub fn vertices(&self) -> usize {
        self.offsets().len()
    }
}

/// The 1+1 lattices of this module as top-cell complexes of the field core.
impl SpacetimeLattice {
    /// The seed 002 lattice of `shape` cells over `levels ≥ 2` time levels of
    /// `lattice` (space nodes and periodicity from `lattice`).
    ///
    /// # Errors
    /// As [`SpacetimeLattice::new`] (`levels` < 2 is too small).
    pub fn seed002(shape: CellShape, lattice: &Lattice, levels: usize) -> Result<Self> {
        let kind = match shape {
            CellShape::Triangle => SpacetimeKind::Seed002Triangle,
            CellShape::Rectangle => SpacetimeKind::Seed002Rectangle,
        };
        if levels < 2 {
            return Err(invalid("levels", levels, "at least 2 time levels (window too small)"));
        }
        let space = if lattice.is_periodic() {
            Axis::periodic(lattice.nodes())
        } else {
            Axis::open(lattice.nodes() - 1)
        };
        Self::new(kind, space, levels - 1)
    }
}

#[cfg(test)]
mod complex_tests {
    use super::*;
    use crate::complex::TopCells;

    /// A free lattice of 5 nodes over 3 levels: the complex of its triangles.
    #[test]
    fn seed002_complex_of_a_free_lattice() {
        let free = Lattice::new(5, 0.1, 0.1, Boundary::Free).expect("lattice");
        let t = SpacetimeLattice::seed002(CellShape::Triangle, &free, 3).expect("triangles");
        assert_eq!((t.vertex_count(), t.cell_count(), t.max_cell_vertices()), (15, 8, 3));
        assert!(SpacetimeLattice::seed002(CellShape::Triangle, &free, 1).is_err());
    }
}
