//! Region topology of seed 002 §5.1 on the base `X = ℤ × ℤ`, for triangles
//! and rectangles.
//!
//! For a node set `U`:
//! * a cell is *in* `U` when all its vertices are in `U`;
//! * `int U` = nodes of `U` all of whose touching cells are in `U`;
//! * `cl U` = union of the vertex sets of all cells touching an interior node;
//! * `∂U = (U ∩ cl U) \ int U`;
//! * `U` is *regular* iff `U = int U ∪ ∂U`.
//!
//! A full window `[i0, i1] × [j0, j1]` is regular for rectangles but not for
//! triangles: its corners `(i0, j1)` and `(i1, j0)` are in no cell touching an
//! interior node and [`window`] drops them.

use std::collections::BTreeSet;

use crate::spacetime::lattice::CellShape;

/// A node `(i, j)` of `ℤ × ℤ` (space, time).
pub type Node = (i64, i64);

/// A finite set of nodes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Region {
    shape: CellShape,
    nodes: BTreeSet<Node>,
}

impl Region {
    /// A region of the given cell shape from a node set.
    pub fn new(shape: CellShape, nodes: impl IntoIterator<Item = Node>) -> Self {
        Self {
            shape,
            nodes: nodes.into_iter().collect(),
        }
    }
    fn shape(&self) -> CellShape {
        self.shape
    }
    /// The nodes.
    pub fn nodes(&self) -> &BTreeSet<Node> {
        &self.nodes
    }
    /// Membership.
    pub fn contains(&self, p: Node) -> bool {
        self.nodes.contains(&p)
    }
    /// Cell origins of the cells touching node `p` (one per vertex role `l`),
    /// as `(origin, l)` with `l` 0-based.
    pub fn touching(&self, p: Node) -> impl Iterator<Item = (Node, usize)> + '_ {
        self.shape()
            .offsets()
            .iter()
            .enumerate()
            .map(move |(l, &(di, dj))| ((p.0 - di, p.1 - dj), l))
    }
    /// Vertex nodes of the cell with origin `c`.
    pub fn cell_nodes(&self, c: Node) -> impl Iterator<Item = Node> + '_ {
        self.shape().offsets().iter().map(move |&(di, dj)| (c.0 + di, c.1 + dj))
    }
    /// Is the cell with origin `c` in the region (all vertices in `U`)?
    pub fn has_cell(&self, c: Node) -> bool {
        self.cell_nodes(c).all(|p| self.contains(p))
    }
    /// Origins of all cells in the region.
    pub fn cells(&self) -> BTreeSet<Node> {
        let mut out = BTreeSet::new();
        for &p in &self.nodes {
            for (c, _) in self.touching(p) {
                if self.has_cell(c) {
                    out.insert(c);
                }
            }
        }
        out
    }
    /// `int U`.
    pub fn interior(&self) -> BTreeSet<Node> {
        self.nodes
            .iter()
            .copied()
            .filter(|&p| self.touching(p).all(|(c, _)| self.has_cell(c)))
            .collect()
    }
    /// `cl U`.
    pub fn closure(&self) -> BTreeSet<Node> {
        let mut out = BTreeSet::new();
        for p in self.interior() {
            for (c, _) in self.touching(p) {
                out.extend(self.cell_nodes(c));
            }
        }
        out
    }
    /// `∂U = (U ∩ cl U) \ int U`.
    pub fn boundary(&self) -> BTreeSet<Node> {
        let int = self.interior();
        self.closure()
            .into_iter()
            .filter(|p| self.contains(*p) && !int.contains(p))
            .collect()
    }
    /// `U = int U ∪ ∂U`?
    pub fn is_regular(&self) -> bool {
        let mut u: BTreeSet<Node> = self.interior();
        u.extend(self.boundary());
        u == self.nodes
    }
}

/// The regular region spanned by the window `[i0, i1] × [j0, j1]`: the full
/// window for rectangles; for triangles the corners `(i0, j1)` and `(i1, j0)`
/// (outside `cl U`) are dropped.
pub fn window(shape: CellShape, i0: i64, i1: i64, j0: i64, j1: i64) -> Region {
    let mut nodes: Vec<Node> = Vec::new();
    for i in i0..=i1 {
        for j in j0..=j1 {
            nodes.push((i, j));
        }
    }
    let full = Region::new(shape, nodes);
    let mut keep = full.interior();
    keep.extend(full.boundary());
    Region::new(shape, keep)
}
