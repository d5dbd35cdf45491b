//! The Coxeter–Freudenthal–Kuhn (CFK) simplicial lattice on ℤⁿ (seed 003
//! Defs. 2.11–2.18, note 003 §1.4), implicit, in any dimension
//! n ≤ [`MAX_LATTICE_DIMENSION`].
//!
//! A k-cell is (v, (S₁, …, S_k)) (Lemma 2.12 / Cor. 2.13): a base vertex v (the
//! least-weight vertex) and an ordered sequence of disjoint nonempty subsets
//! of \[n\]; its vertices in weight order are v₀ = v, v_a = v_{a−1} + e_{S_a}. It
//! is stored as the base and a label per axis: label i = a when i ∈ S_a, 0 when
//! i is in no S_a. Top cells are (v, σ), σ ∈ Sym(n), v_{a+1} = v_a + e_{σ_a}
//! (Cor. 2.17); σ is indexed by [`permutation_index`] (lexicographic rank).
//!
//! Incidence, closed form (derived in note 003 §1.4; checked here against the
//! geometric Def. 2.18 in [`crate::complex::cfk_geometry`]): with
//! o(v, (S₁..S_k)) = sgn of the permutation sorting (min S₁, …, min S_k),
//! \[β : β∖{v_j}\] = (−1)^j o_β o_α; the faces are (v₁, (S₂..S_k)) for j = 0,
//! (v₀, (S₁..S_{k−1})) for j = k and (v₀, (S₁, …, S_j ∪ S_{j+1}, …, S_k)) else.

use crate::complex::cellular::{CellComplex, Simplicial, sort_sign};
use crate::complex::window::{Point, check_dimension, factorial, permutation_index, permutation_into};
use crate::complex::{MAX_LATTICE_DIMENSION, TopCell};
use crate::error::Result;

// Labels are u8 and axis sets u32 bit masks.
const _: () = assert!(MAX_LATTICE_DIMENSION <= 8);

/// A cell (v, (S₁, …, S_k)) of the CFK lattice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct CfkCell {
    /// The base (least-weight) vertex v.
    pub base: Point,
    /// Label of each axis: a when the axis is in S_a (1-based), 0 otherwise.
    pub labels: [u8; MAX_LATTICE_DIMENSION],
    /// Dimension k (the number of subsets).
    pub k: u8,
}

impl CfkCell {
    /// The vertex (0-cell) at `p`.
    pub fn vertex(p: &Point) -> Self {
        Self {
            base: *p,
            labels: [0; MAX_LATTICE_DIMENSION],
            k: 0,
        }
    }
    /// The cell (v, (S₁, …, S_k)); `subsets` are lists of 0-based axes.
    /// Returns `None` unless the subsets are nonempty, disjoint, and within
    /// 0..[`MAX_LATTICE_DIMENSION`].
    pub fn new(base: &Point, subsets: &[&[usize]]) -> Option<Self> {
        let mut labels = [0u8; MAX_LATTICE_DIMENSION];
        if subsets.len() > MAX_LATTICE_DIMENSION {
            return None;
        }
        for (a, s) in subsets.iter().enumerate() {
            if s.is_empty() {
                return None;
            }
            for &i in s.iter() {
                if i >= MAX_LATTICE_DIMENSION || labels[i] != 0 {
                    return None;
                }
                labels[i] = a as u8 + 1;
            }
        }
        Some(Self {
            base: *base,
            labels,
            k: subsets.len() as u8,
        })
    }
    /// The top cell (v, σ) of dimension n = `sigma.len()` (σ a permutation of 0..n).
    pub fn top(base: &Point, sigma: &[usize]) -> Self {
        let mut labels = [0u8; MAX_LATTICE_DIMENSION];
        for (a, &i) in sigma.iter().enumerate() {
            labels[i] = a as u8 + 1;
        }
        Self {
            base: *base,
            labels,
            k: sigma.len() as u8,
        }
    }
    /// The top cell with base `base` and permutation index `shape` in Sym(n).
    pub fn top_from_index(n: usize, base: &Point, shape: usize) -> Self {
        let mut sigma = [0usize; MAX_LATTICE_DIMENSION];
        permutation_into(n, shape, &mut sigma);
        Self::top(base, &sigma[..n])
    }
    /// Dimension k.
    pub fn dimension(&self) -> usize {
        self.k as usize
    }
    /// The subset S_a (1 ≤ a ≤ k) as a bit mask of axes.
    pub fn subset(&self, a: usize) -> u32 {
        (0..MAX_LATTICE_DIMENSION)
            .filter(|&i| self.labels[i] as usize == a)
            .fold(0, |m, i| m | 1 << i)
    }
    /// The permutation σ of a top cell (axis σ_a has label a + 1), written into
    /// `sigma[..k]` (`sigma.len() ≥ k`), and its index in Sym(k).
    pub fn sigma(&self, sigma: &mut [usize]) -> usize {
        for (i, &l) in self.labels.iter().enumerate() {
            if l > 0 {
                sigma[l as usize - 1] = i;
            }
        }
        permutation_index(&sigma[..self.dimension()])
    }
    /// Vertex v_a (0 ≤ a ≤ k) in weight order.
    pub fn vertex_at(&self, a: usize) -> Point {
        let mut p = self.base;
        for (x, &l) in p.iter_mut().zip(&self.labels) {
            if l > 0 && l as usize <= a {
                *x += 1;
            }
        }
        p
    }
    /// The orientation sign of the weight-ordered vertex list: the sign of the
    /// permutation sorting (min S₁, …, min S_k).
    pub fn orientation(&self) -> i8 {
        let mut mins = [usize::MAX; MAX_LATTICE_DIMENSION];
        for (i, &l) in self.labels.iter().enumerate().rev() {
            if l > 0 {
                mins[l as usize - 1] = i;
            }
        }
        sort_sign(&mins[..self.dimension()])
    }
    /// The face β∖{v_j} (closed form) and \[β : β∖{v_j}\] = (−1)^j o_β o_α;
    /// `None` for a vertex or j > k.
    pub fn face(&self, j: usize) -> Option<(Self, i8)> {
        let k = self.k;
        if k == 0 || j > k as usize {
            return None;
        }
        let mut f = *self;
        f.k = k - 1;
        for (i, l) in f.labels.iter_mut().enumerate() {
            if j == 0 {
                if *l == 1 {
                    f.base[i] += 1;
                    *l = 0;
                } else if *l > 1 {
                    *l -= 1;
                }
            } else if j == k as usize {
                if *l == k {
                    *l = 0;
                }
            } else if *l as usize > j {
                *l -= 1;
            }
        }
        let parity: i8 = crate::complex::cellular::parity(j);
        Some((f, parity * self.orientation() * f.orientation()))
    }
}

pub(crate) fn faces_of(c: &CfkCell, out: &mut Vec<(CfkCell, i8)>) {
    out.clear();
    if c.k > 0 {
        out.extend((0..=c.dimension()).filter_map(|j| c.face(j)));
    }
}

/// Every coface of `c` in dimension n with its incidence, by inserting one
/// vertex: before v₀, after v_k, or between v_{j−1} and v_j (splitting S_j).
pub(crate) fn cofaces_in(n: usize, c: &CfkCell, out: &mut Vec<(CfkCell, i8)>) {
    out.clear();
    let k = c.dimension();
    if k >= n {
        return;
    }
    let free: Vec<usize> = (0..n).filter(|&i| c.labels[i] == 0).collect();
    let sign = |beta: &CfkCell, j: usize| {
        let parity: i8 = crate::complex::cellular::parity(j);
        parity * beta.orientation() * c.orientation()
    };
    for mask in 1u32..1 << free.len() {
        let mut before = *c;
        let mut after = *c;
        before.k += 1;
        after.k += 1;
        for l in before.labels.iter_mut() {
            if *l > 0 {
                *l += 1;
            }
        }
        for (m, &i) in free.iter().enumerate() {
            if mask >> m & 1 == 1 {
                before.labels[i] = 1;
                before.base[i] -= 1;
                after.labels[i] = k as u8 + 1;
            }
        }
        out.push((before, sign(&before, 0)));
        out.push((after, sign(&after, k + 1)));
    }
    for j in 1..=k {
        let members: Vec<usize> = (0..n).filter(|&i| c.labels[i] as usize == j).collect();
        // ordered splits (A, B) of S_j, both nonempty: B = the masked members
        for mask in 1u32..(1 << members.len()) - 1 {
            let mut beta = *c;
            beta.k += 1;
            for l in beta.labels.iter_mut() {
                if *l as usize > j {
                    *l += 1;
                }
            }
            for (m, &i) in members.iter().enumerate() {
                if mask >> m & 1 == 1 {
                    beta.labels[i] = j as u8 + 1;
                }
            }
            out.push((beta, sign(&beta, j)));
        }
    }
}

/// The infinite CFK lattice on ℤⁿ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CfkLattice {
    n: usize,
}

impl CfkLattice {
    /// The lattice in dimension `n`.
    ///
    /// # Errors
    /// [`crate::Error::InvalidParameter`] for n = 0 or n > [`MAX_LATTICE_DIMENSION`].
    pub fn new(n: usize) -> Result<Self> {
        check_dimension(n)?;
        Ok(Self { n })
    }
    /// The top cells containing `p` with the position of `p` in each, in
    /// order of (σ index, position): (v − Σ_{a<q} e_{σ_a}, σ) has p at position
    /// q; (n + 1)! cells.
    pub fn star_with_positions(&self, p: &Point, mut visit: impl FnMut(&Point, usize, usize)) {
        star_walk(self.n, p, &mut visit);
    }
}

/// Calls `visit(base, σ index, position)` for the (n + 1)! top cells (base, σ)
/// that contain `p`.
pub(crate) fn star_walk(n: usize, p: &Point, visit: &mut impl FnMut(&Point, usize, usize)) {
    let mut sigma = [0usize; MAX_LATTICE_DIMENSION];
    for shape in 0..factorial(n) {
        permutation_into(n, shape, &mut sigma);
        let mut base = *p;
        visit(&base, shape, 0);
        for (q, &axis) in sigma[..n].iter().enumerate() {
            base[axis] -= 1;
            visit(&base, shape, q + 1);
        }
    }
}

/// The cell with the given vertex set, if these points span a CFK cell.
pub(crate) fn simplex_of(n: usize, vertices: &[CfkCell]) -> Option<CfkCell> {
    let mut points: Vec<Point> = vertices.iter().map(|v| v.base).collect();
    points.sort_by_key(|p| (p.iter().sum::<i64>(), *p));
    let mut cell = CfkCell::vertex(&points[0]);
    for (a, w) in points.windows(2).enumerate() {
        let mut any = false;
        for i in 0..MAX_LATTICE_DIMENSION {
            match w[1][i] - w[0][i] {
                0 => {}
                1 if i < n && cell.labels[i] == 0 => {
                    cell.labels[i] = a as u8 + 1;
                    any = true;
                }
                _ => return None,
            }
        }
        if !any {
            return None;
        }
        cell.k += 1;
    }
    Some(cell)
}

pub(crate) fn vertices_of(c: &CfkCell) -> Vec<CfkCell> {
    (0..=c.dimension()).map(|a| CfkCell::vertex(&c.vertex_at(a))).collect()
}

impl CellComplex for CfkLattice {
    type Cell = CfkCell;
    fn dim(&self) -> usize {
        self.n
    }
    fn cell_dimension(&self, cell: &CfkCell) -> usize {
        cell.dimension()
    }
    fn faces(&self, cell: &CfkCell, out: &mut Vec<(CfkCell, i8)>) {
        faces_of(cell, out);
    }
    fn cofaces(&self, cell: &CfkCell, out: &mut Vec<(CfkCell, i8)>) {
        cofaces_in(self.n, cell, out);
    }
    fn vertices(&self, cell: &CfkCell) -> Vec<CfkCell> {
        vertices_of(cell)
    }
    fn star_cells(&self, v: &CfkCell, out: &mut Vec<CfkCell>) {
        out.clear();
        let n = self.n;
        star_walk(n, &v.base, &mut |base, shape, _| {
            out.push(CfkCell::top_from_index(n, base, shape));
        });
        out.sort_unstable();
    }
}

impl Simplicial for CfkLattice {
    fn simplex(&self, vertices: &[CfkCell]) -> Option<CfkCell> {
        simplex_of(self.n, vertices)
    }
}

/// The [`TopCell`] record of a top cell in a window (`index` given).
pub(crate) fn top_record(n: usize, index: usize, cell: &CfkCell) -> TopCell {
    let mut sigma = [0usize; MAX_LATTICE_DIMENSION];
    let shape = cell.sigma(&mut sigma[..n]);
    TopCell {
        index,
        shape,
        origin: cell.base,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faces_of_a_triangle_in_closed_form() {
        let v = [0; MAX_LATTICE_DIMENSION];
        // (i,j,+) = {(0,0), (1,0), (1,1)}: σ = (0, 1), positively oriented
        let t = CfkCell::top(&v, &[0, 1]);
        assert_eq!(t.orientation(), 1);
        let (f0, s0) = t.face(0).expect("face");
        assert_eq!((f0.base[0], f0.base[1], f0.subset(1), s0), (1, 0, 0b10, 1));
        let (f1, s1) = t.face(1).expect("face");
        assert_eq!((f1.subset(1), s1), (0b11, -1));
        let (f2, s2) = t.face(2).expect("face");
        assert_eq!((f2.subset(1), s2), (0b01, 1));
        assert_eq!(t.face(3), None);
        assert_eq!(CfkCell::vertex(&v).face(0), None);
        // (i,j,−) is negatively oriented in weight order
        assert_eq!(CfkCell::top(&v, &[1, 0]).orientation(), -1);
    }

    #[test]
    fn a_vertex_has_two_times_two_to_the_n_minus_one_edges() {
        for n in 1..=4 {
            let mut out = Vec::new();
            cofaces_in(n, &CfkCell::vertex(&[0; MAX_LATTICE_DIMENSION]), &mut out);
            assert_eq!(out.len(), 2 * ((1 << n) - 1));
        }
    }

    #[test]
    fn vertex_sets_determine_cells() {
        let l = CfkLattice::new(3).expect("lattice");
        let c = CfkCell::new(&[1, 2, 3, 0, 0, 0, 0, 0], &[&[1], &[0, 2]]).expect("cell");
        let mut vs = l.vertices(&c);
        vs.reverse();
        assert_eq!(l.simplex(&vs), Some(c));
        let mut far = vs.clone();
        far[0].base[0] += 1;
        assert_eq!(l.simplex(&far), None);
        assert_eq!(CfkCell::new(&[0; MAX_LATTICE_DIMENSION], &[&[0], &[0]]), None);
    }
}
