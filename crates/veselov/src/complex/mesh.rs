//! Explicit simplicial meshes (seed 003 Defs. 2.5–2.8, note 003 §1.2), after
//! PyDEC's `simplicial_complex`: built from a vertex count and a list of top
//! simplices, with the faces of every dimension derived.
//!
//! Orientation: a k-simplex with k < n is oriented by its sorted vertex list;
//! a top simplex by the vertex order it was given in. The incidence numbers
//! are then (2.7) with o_β = +1 on the cell's own order:
//! \[β : β∖{w_j}\] = (−1)^j · o_α(w₀, …, ŵ_j, …, w_k). The orientation of any
//! ordered simplex follows back from the incidences by (2.6)
//! ([`orientation`](crate::complex::cellular::orientation)).

use std::collections::{BTreeSet, HashMap};

use crate::complex::cellular::{CellComplex, FiniteComplex, Simplicial, sort_sign};
use crate::complex::{MAX_LATTICE_DIMENSION, StarEntry, TopCell, TopCells};
use crate::error::invalid;
use crate::error::{Error, Result};

/// A cell of a [`SimplicialMesh`]: its dimension and its index among the
/// cells of that dimension (top cells keep their input index; the other
/// dimensions are numbered in lexicographic order of their sorted vertices;
/// vertex v is the 0-cell with index v).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct MeshCell {
    /// Dimension.
    pub dim: usize,
    /// Index among the cells of dimension `dim`.
    pub index: usize,
}

/// An explicit pure simplicial complex of dimension n with a vertex → cells
/// table for the stars.
#[derive(Clone, Debug)]
pub struct SimplicialMesh {
    n: usize,
    vertex_count: usize,
    /// Ordered vertices of every cell, per dimension.
    simplices: Vec<Vec<Vec<usize>>>,
    /// Sorted vertex set → index, per dimension.
    lookup: Vec<HashMap<Vec<usize>, usize>>,
    /// Cofaces with incidence, per dimension k < n.
    cofaces: Vec<Vec<Vec<(usize, i8)>>>,
    star_offsets: Vec<usize>,
    star_entries: Vec<StarEntry>,
}

impl SimplicialMesh {
    /// A mesh of `vertex_count` vertices and the given top simplices (each
    /// n + 1 vertex indices in the order that orients it).
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for no cells, cells of different sizes, a
    /// dimension 0 or above [`MAX_LATTICE_DIMENSION`], more than 2³² − 1
    /// vertices, a vertex index out of range, a repeated vertex in a cell, or a
    /// repeated cell.
    pub fn new<C: AsRef<[usize]>>(vertex_count: usize, cells: &[C]) -> Result<Self> {
        let Some(first) = cells.first() else {
            return Err(invalid("cells", "[]", "a mesh needs at least one cell"));
        };
        let size = first.as_ref().len();
        if !(2..=MAX_LATTICE_DIMENSION + 1).contains(&size) {
            return Err(invalid(
                "cells[0]",
                format!("{:?}", first.as_ref()),
                &format!("a top cell needs 2..={} vertices", MAX_LATTICE_DIMENSION + 1),
            ));
        }
        if vertex_count > u32::MAX as usize {
            return Err(invalid("vertex_count", vertex_count, "at most 2^32 − 1 vertices"));
        }
        let n = size - 1;
        let mut top: Vec<Vec<usize>> = Vec::with_capacity(cells.len());
        let mut top_lookup = HashMap::new();
        for (c, cell) in cells.iter().enumerate() {
            let cell = cell.as_ref();
            let name = format!("cells[{c}]");
            if cell.len() != size {
                return Err(invalid(
                    &name,
                    format!("{cell:?}"),
                    &format!("expected {size} vertices"),
                ));
            }
            if let Some(&v) = cell.iter().find(|&&v| v >= vertex_count) {
                return Err(invalid(
                    &name,
                    format!("{cell:?}"),
                    &format!("vertex {v} out of range 0..{vertex_count}"),
                ));
            }
            let mut sorted = cell.to_vec();
            sorted.sort_unstable();
            if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
                return Err(invalid(
                    &name,
                    format!("{cell:?}"),
                    &format!("repeated vertex {}", w[0]),
                ));
            }
            if let Some(other) = top_lookup.insert(sorted, c) {
                return Err(invalid(&name, format!("{cell:?}"), &format!("repeats cells[{other}]")));
            }
            top.push(cell.to_vec());
        }
        let mut sets: Vec<BTreeSet<Vec<usize>>> = vec![BTreeSet::new(); n];
        for cell in top_lookup.keys() {
            for mask in 1u32..(1 << size) - 1 {
                let face: Vec<usize> = (0..size).filter(|&i| mask >> i & 1 == 1).map(|i| cell[i]).collect();
                if face.len() > 1 {
                    sets[face.len() - 1].insert(face);
                }
            }
        }
        let mut simplices: Vec<Vec<Vec<usize>>> = vec![(0..vertex_count).map(|v| vec![v]).collect()];
        simplices.extend(sets.into_iter().skip(1).map(|s| s.into_iter().collect()));
        simplices.push(top);
        let mut lookup: Vec<HashMap<Vec<usize>, usize>> = simplices[..n]
            .iter()
            .map(|cells| cells.iter().enumerate().map(|(i, c)| (c.clone(), i)).collect())
            .collect();
        lookup.push(top_lookup);
        let mut mesh = Self {
            n,
            vertex_count,
            simplices,
            lookup,
            cofaces: Vec::new(),
            star_offsets: Vec::new(),
            star_entries: Vec::new(),
        };
        let mut cofaces: Vec<Vec<Vec<(usize, i8)>>> =
            (0..n).map(|k| vec![Vec::new(); mesh.simplices[k].len()]).collect();
        let mut faces = Vec::new();
        for k in 1..=n {
            for b in 0..mesh.simplices[k].len() {
                mesh.faces(&MeshCell { dim: k, index: b }, &mut faces);
                for (a, s) in &faces {
                    cofaces[k - 1][a.index].push((b, *s));
                }
            }
        }
        mesh.cofaces = cofaces;
        let mut entries: Vec<(usize, StarEntry)> = Vec::with_capacity(cells.len() * size);
        for (c, cell) in mesh.simplices[n].iter().enumerate() {
            for (position, &v) in cell.iter().enumerate() {
                entries.push((v, StarEntry { cell: c, position }));
            }
        }
        entries.sort_unstable_by_key(|(v, e)| (*v, e.cell));
        let mut offsets = vec![0usize; vertex_count + 1];
        for (v, _) in &entries {
            offsets[v + 1] += 1;
        }
        for v in 0..vertex_count {
            offsets[v + 1] += offsets[v];
        }
        mesh.star_offsets = offsets;
        mesh.star_entries = entries.into_iter().map(|(_, e)| e).collect();
        Ok(mesh)
    }

    /// The simplicial mesh of any complex whose top cells are simplices
    /// (n + 1 vertices each), e.g. a CFK window or a 1+1 triangle lattice.
    ///
    /// # Errors
    /// As [`SimplicialMesh::new`], and [`Error::InvalidParameter`] when the
    /// cells are not simplices.
    pub fn from_top_cells(complex: &dyn TopCells) -> Result<Self> {
        let n = complex.dimension();
        let mut out = vec![0usize; complex.max_cell_vertices().max(n + 1)];
        let mut cells = Vec::with_capacity(complex.cell_count());
        for c in 0..complex.cell_count() {
            let m = complex.cell_vertices(c, &mut out);
            if m != n + 1 {
                return Err(invalid(
                    "complex",
                    format!("cell {c} with {m} vertices"),
                    "not a simplex",
                ));
            }
            cells.push(out[..m].to_vec());
        }
        Self::new(complex.vertex_count(), &cells)
    }

    /// Number of k-cells.
    pub fn count(&self, k: usize) -> usize {
        self.simplices.get(k).map_or(0, Vec::len)
    }

    /// The ordered vertex indices of a cell.
    pub fn cell_vertex_indices(&self, cell: &MeshCell) -> &[usize] {
        &self.simplices[cell.dim][cell.index]
    }

    /// Checks that the top cells are coherently oriented (every (n−1)-face
    /// shared by two top cells receives opposite incidences) and that the mesh
    /// is a pseudo-manifold (no (n−1)-face in more than two top cells).
    ///
    /// # Errors
    /// [`Error::Complex`] naming the offending face.
    pub fn check_orientation(&self) -> Result<()> {
        for (f, cof) in self.cofaces[self.n - 1].iter().enumerate() {
            let name = || format!("{:?}", self.simplices[self.n - 1][f]);
            match cof.as_slice() {
                [_] | [] => {}
                [(_, s), (_, t)] if s != t => {}
                [(a, _), (b, _)] => {
                    return Err(Error::Complex {
                        cell: name(),
                        reason: format!("inconsistently oriented: top cells {a} and {b} induce the same orientation"),
                    });
                }
                _ => {
                    return Err(Error::Complex {
                        cell: name(),
                        reason: format!("non-manifold: a face of {} top cells", cof.len()),
                    });
                }
            }
        }
        Ok(())
    }

    /// A coherently oriented copy: top cells are flipped (first two vertices
    /// swapped) where needed, keeping the orientation of the least cell of each
    /// connected component.
    ///
    /// # Errors
    /// [`Error::Complex`] for a non-manifold or non-orientable mesh.
    pub fn oriented(&self) -> Result<Self> {
        let n = self.n;
        let top = &self.simplices[n];
        let mut flip: Vec<Option<bool>> = vec![None; top.len()];
        for start in 0..top.len() {
            if flip[start].is_some() {
                continue;
            }
            flip[start] = Some(false);
            let mut stack = vec![start];
            let mut faces = Vec::new();
            while let Some(c) = stack.pop() {
                let fc = flip[c].unwrap_or(false);
                self.faces(&MeshCell { dim: n, index: c }, &mut faces);
                for (f, s) in &faces {
                    let cof = &self.cofaces[n - 1][f.index];
                    if cof.len() > 2 {
                        return Err(Error::Complex {
                            cell: format!("{:?}", self.simplices[n - 1][f.index]),
                            reason: format!("non-manifold: a face of {} top cells", cof.len()),
                        });
                    }
                    for &(d, t) in cof.iter().filter(|(d, _)| *d != c) {
                        // coherent iff the induced signs are opposite after flips
                        let want = (t == *s) != fc;
                        match flip[d] {
                            None => {
                                flip[d] = Some(want);
                                stack.push(d);
                            }
                            Some(got) if got != want => {
                                return Err(Error::Complex {
                                    cell: format!("{:?}", self.simplices[n - 1][f.index]),
                                    reason: "the mesh is not orientable".to_string(),
                                });
                            }
                            Some(_) => {}
                        }
                    }
                }
            }
        }
        let cells: Vec<Vec<usize>> = top
            .iter()
            .zip(&flip)
            .map(|(c, f)| {
                let mut c = c.clone();
                if *f == Some(true) {
                    c.swap(0, 1);
                }
                c
            })
            .collect();
        Self::new(self.vertex_count, &cells)
    }
}

impl CellComplex for SimplicialMesh {
    type Cell = MeshCell;
    fn dim(&self) -> usize {
        self.n
    }
    fn cell_dimension(&self, cell: &MeshCell) -> usize {
        cell.dim
    }
    fn faces(&self, cell: &MeshCell, out: &mut Vec<(MeshCell, i8)>) {
        out.clear();
        if cell.dim == 0 || cell.dim > self.n {
            return;
        }
        let w = &self.simplices[cell.dim][cell.index];
        for j in 0..w.len() {
            let face: Vec<usize> = w.iter().enumerate().filter(|&(i, _)| i != j).map(|(_, &v)| v).collect();
            let parity: i8 = crate::complex::cellular::parity(j);
            let sign = parity * sort_sign(&face);
            let mut key = face;
            key.sort_unstable();
            if let Some(&index) = self.lookup[cell.dim - 1].get(&key) {
                out.push((
                    MeshCell {
                        dim: cell.dim - 1,
                        index,
                    },
                    sign,
                ));
            }
        }
    }
    fn cofaces(&self, cell: &MeshCell, out: &mut Vec<(MeshCell, i8)>) {
        out.clear();
        if let Some(c) = self.cofaces.get(cell.dim).and_then(|d| d.get(cell.index)) {
            out.extend(c.iter().map(|&(index, s)| {
                (
                    MeshCell {
                        dim: cell.dim + 1,
                        index,
                    },
                    s,
                )
            }));
        }
    }
    fn vertices(&self, cell: &MeshCell) -> Vec<MeshCell> {
        self.simplices[cell.dim][cell.index]
            .iter()
            .map(|&index| MeshCell { dim: 0, index })
            .collect()
    }
    fn star_cells(&self, v: &MeshCell, out: &mut Vec<MeshCell>) {
        out.clear();
        if v.dim == 0 && v.index < self.vertex_count {
            out.extend(
                self.star_entries[self.star_offsets[v.index]..self.star_offsets[v.index + 1]]
                    .iter()
                    .map(|e| MeshCell {
                        dim: self.n,
                        index: e.cell,
                    }),
            );
        }
    }
}

impl Simplicial for SimplicialMesh {
    fn simplex(&self, vertices: &[MeshCell]) -> Option<MeshCell> {
        let mut key: Vec<usize> = vertices.iter().map(|v| v.index).collect();
        key.sort_unstable();
        let dim = key.len().checked_sub(1)?;
        let index = *self.lookup.get(dim)?.get(&key)?;
        Some(MeshCell { dim, index })
    }
}

impl FiniteComplex for SimplicialMesh {
    fn cells(&self, k: usize) -> Vec<MeshCell> {
        (0..self.count(k)).map(|index| MeshCell { dim: k, index }).collect()
    }
}

impl TopCells for SimplicialMesh {
    fn dimension(&self) -> usize {
        self.n
    }
    fn vertex_count(&self) -> usize {
        self.vertex_count
    }
    fn cell_count(&self) -> usize {
        self.simplices[self.n].len()
    }
    fn max_cell_vertices(&self) -> usize {
        self.n + 1
    }
    fn cell(&self, index: usize) -> TopCell {
        TopCell {
            index,
            shape: 0,
            origin: [0; MAX_LATTICE_DIMENSION],
        }
    }
    fn cell_vertices(&self, index: usize, out: &mut [usize]) -> usize {
        let c = &self.simplices[self.n][index];
        out[..c.len()].copy_from_slice(c);
        c.len()
    }
    fn star(&self, v: usize, out: &mut Vec<StarEntry>) {
        out.clear();
        if v < self.vertex_count {
            out.extend_from_slice(&self.star_entries[self.star_offsets[v]..self.star_offsets[v + 1]]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_triangles_make_a_square() {
        let m = SimplicialMesh::new(4, &[[0, 1, 2], [0, 2, 3]]).expect("mesh");
        assert_eq!([0, 1, 2].map(|k| m.count(k)), [4, 5, 2]);
        m.check_orientation().expect("coherent");
        let mut star = Vec::new();
        TopCells::star(&m, 2, &mut star);
        assert_eq!(
            star,
            vec![StarEntry { cell: 0, position: 2 }, StarEntry { cell: 1, position: 1 }]
        );
        let diagonal = m.simplex(&[MeshCell { dim: 0, index: 2 }, MeshCell { dim: 0, index: 0 }]);
        let diagonal = diagonal.expect("the diagonal is an edge");
        let mut cof = Vec::new();
        m.cofaces(&diagonal, &mut cof);
        assert_eq!(cof.len(), 2);
        assert_eq!(cof[0].1, -cof[1].1);
    }
}
