//! Node maps x: V₀ → X = ℝ^N (note 003 §1.6, §2.5): the positions of a top
//! cell's ordered vertices in the base space, from its [`TopCell`].
//!
//! * [`CfkNodes`]: CFK simplices (v, σ) (Cor. 2.17) under an affine map
//!   x = A v + b, vertices v₀ = v, v_{i+1} = v_i + e_{σ(i)} with σ decoded by
//!   [`permutation`]; constructors for the rod's leapfrog embedding (6.2)
//!   ([`CfkNodes::leapfrog`]) and its n-dimensional space–time analogue
//!   ([`CfkNodes::space_time`]).
//! * [`CubeNodes`]: cubes of the cubic lattice under an affine map, vertices
//!   in binary order ([`cube_corner`]).

use nalgebra::{SMatrix, SVector};

use crate::complex::{MAX_LATTICE_DIMENSION, TopCell};
use crate::error::Result;
use crate::error::invalid;

/// Positions x(v) ∈ ℝ^N of the ordered vertices of top cells.
pub trait NodeMap<const N: usize>: Send + Sync {
    /// Writes x(v₀), …, x(v_k) of `cell` into `out` and returns their number
    /// k + 1, or 0 if the map does not know the cell (a shape index outside
    /// the complex's shape classes) or `out` is too short.
    fn cell_nodes(&self, cell: &TopCell, out: &mut [SVector<f64, N>]) -> usize;

    /// Whether the edge vectors x(v_l) − x(v₀) of a cell depend on its shape
    /// only, not on its position (true for affine maps of a lattice): rules
    /// may then cache each shape's geometry. Default false.
    fn translation_invariant(&self) -> bool {
        false
    }
}

pub use crate::complex::factorial;

/// Relative size below which a node determinant counts as singular:
/// |det T| ≤ `SINGULAR_NODES` · Π|columns of T|.
pub const SINGULAR_NODES: f64 = 1e-12;

/// Inverse and determinant of a small square matrix by Gauss–Jordan
/// elimination with partial pivoting (`None` if a pivot vanishes).
pub fn invert<const N: usize>(t: &SMatrix<f64, N, N>) -> Option<(SMatrix<f64, N, N>, f64)> {
    let mut a = *t;
    let mut inv = SMatrix::<f64, N, N>::identity();
    let mut det = 1.0;
    for c in 0..N {
        let (p, pivot) =
            (c..N).map(|r| (r, a[(r, c)])).fold(
                (c, 0.0_f64),
                |best, (r, v)| if v.abs() > best.1.abs() { (r, v) } else { best },
            );
        if pivot == 0.0 || !pivot.is_finite() {
            return None;
        }
        if p != c {
            a.swap_rows(p, c);
            inv.swap_rows(p, c);
            det = -det;
        }
        det *= pivot;
        let scale = 1.0 / pivot;
        for j in 0..N {
            a[(c, j)] *= scale;
            inv[(c, j)] *= scale;
        }
        for r in 0..N {
            if r != c {
                let f = a[(r, c)];
                if f != 0.0 {
                    for j in 0..N {
                        a[(r, j)] -= f * a[(c, j)];
                        inv[(r, j)] -= f * inv[(c, j)];
                    }
                }
            }
        }
    }
    Some((inv, det))
}

/// The permutation σ ∈ Sym(n) with index `shape` in the **lexicographic
/// order** of Sym(n) written as sequences (σ(0), …, σ(n−1)): index 0 is the
/// identity, index n! − 1 the reversal. For n = 2, index 0 = (0, 1) is the
/// note's (i, j, +) (v₁ = v₀ + e₀) and index 1 = (1, 0) is (i, j, −).
/// Entries beyond n are zero.
///
/// # Errors
/// [`crate::error::Error::InvalidParameter`] if n > [`MAX_LATTICE_DIMENSION`]
/// or `shape ≥ n!`.
pub fn permutation(n: usize, shape: usize) -> Result<[usize; MAX_LATTICE_DIMENSION]> {
    if n > MAX_LATTICE_DIMENSION {
        return Err(invalid("n", n, "lattice dimension above MAX_LATTICE_DIMENSION"));
    }
    if shape >= factorial(n) {
        return Err(invalid("shape", shape, "permutation index must be below n!"));
    }
    Ok(crate::complex::permutation(n, shape))
}

/// Corner k (0 ≤ k < 2ⁿ) of the unit cube in **binary order**: coordinate i
/// is bit i of k. Cube k-th vertex = origin + corner.
pub fn cube_corner(n: usize, k: usize) -> [i64; MAX_LATTICE_DIMENSION] {
    std::array::from_fn(|i| if i < n { ((k >> i) & 1) as i64 } else { 0 })
}

fn check_affine<const N: usize>(a: &SMatrix<f64, N, N>, offset: &SVector<f64, N>) -> Result<()> {
    if N == 0 || N > MAX_LATTICE_DIMENSION {
        return Err(invalid("N", N, "dimension must be 1..=MAX_LATTICE_DIMENSION"));
    }
    if !a.iter().chain(offset.iter()).all(|x| x.is_finite()) {
        return Err(invalid("A", format!("{a}"), "entries must be finite"));
    }
    let scale: f64 = a.column_iter().map(|c| c.norm()).product();
    let det = invert(a).map_or(0.0, |(_, d)| d);
    if !(scale > 0.0 && det.abs() > SINGULAR_NODES * scale) {
        return Err(invalid(
            "A",
            format!("{a}"),
            "the node map must be injective (det A ≠ 0)",
        ));
    }
    Ok(())
}

fn affine<const N: usize>(a: &SMatrix<f64, N, N>, b: &SVector<f64, N>, v: &[i64]) -> SVector<f64, N> {
    a * SVector::<f64, N>::from_fn(|i, _| v[i] as f64) + b
}

/// CFK simplices under x = A v + b (an injective affine node map).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CfkNodes<const N: usize> {
    a: SMatrix<f64, N, N>,
    offset: SVector<f64, N>,
}

impl<const N: usize> CfkNodes<N> {
    /// x = A v.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] if A has a non-finite entry,
    /// is singular, or N is 0 or above [`MAX_LATTICE_DIMENSION`].
    pub fn new(a: SMatrix<f64, N, N>) -> Result<Self> {
        Self::with_offset(a, SVector::zeros())
    }

    /// x = A v + b.
    ///
    /// # Errors
    /// As [`CfkNodes::new`], also for a non-finite b.
    pub fn with_offset(a: SMatrix<f64, N, N>, offset: SVector<f64, N>) -> Result<Self> {
        check_affine(&a, &offset)?;
        Ok(Self { a, offset })
    }

    /// The n-dimensional space–time embedding: with w = Σᵢ vᵢ,
    /// x_a = Δx (v_a − w/N) for a < N − 1 (space) and x_{N−1} = t = w Δt/N
    /// (time, last). The flow (1, …, 1) is a pure time step Δt; weight levels
    /// are time levels. For N = 2 this is the leapfrog map (6.2).
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] unless Δx, Δt are positive
    /// and finite and 2 ≤ N ≤ [`MAX_LATTICE_DIMENSION`].
    pub fn space_time(dx: f64, dt: f64) -> Result<Self> {
        for (name, v) in [("dx", dx), ("dt", dt)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(name, v, "must be positive and finite"));
            }
        }
        if N < 2 {
            return Err(invalid("N", N, "a space–time lattice needs N ≥ 2"));
        }
        let n = N as f64;
        let a = SMatrix::<f64, N, N>::from_fn(|r, c| {
            if r + 1 == N {
                dt / n
            } else {
                dx * (f64::from(u8::from(r == c)) - 1.0 / n)
            }
        });
        Self::new(a)
    }

    /// The matrix A.
    pub fn matrix(&self) -> &SMatrix<f64, N, N> {
        &self.a
    }

    /// x(v) for a lattice vertex v (its first N coordinates).
    pub fn node(&self, v: &[i64; MAX_LATTICE_DIMENSION]) -> SVector<f64, N> {
        affine(&self.a, &self.offset, v)
    }
}

impl CfkNodes<2> {
    /// The Cosserat rod's leapfrog embedding (6.2):
    /// x(i, j) = (s, t) = ((i − j)Δs/2, (i + j)Δt/2).
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] unless Δs, Δt are positive and finite.
    pub fn leapfrog(ds: f64, dt: f64) -> Result<Self> {
        Self::space_time(ds, dt)
    }
}

impl<const N: usize> NodeMap<N> for CfkNodes<N> {
    fn translation_invariant(&self) -> bool {
        true
    }
    fn cell_nodes(&self, cell: &TopCell, out: &mut [SVector<f64, N>]) -> usize {
        if out.len() < N + 1 || cell.shape >= factorial(N) {
            return 0;
        }
        let sigma = crate::complex::permutation(N, cell.shape);
        let mut v = cell.origin;
        out[0] = self.node(&v);
        for i in 0..N {
            v[sigma[i]] += 1;
            out[i + 1] = self.node(&v);
        }
        N + 1
    }
}

/// Cubes of the cubic lattice under x = A v + b, with the 2^N vertices of the
/// cube based at `origin` in binary order ([`cube_corner`]); N ≤ 4 (at most 16
/// vertices, [`crate::field::cell::MAX_CELL_VERTICES`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubeNodes<const N: usize> {
    a: SMatrix<f64, N, N>,
    offset: SVector<f64, N>,
}

impl<const N: usize> CubeNodes<N> {
    /// x = A v + b.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidParameter`] if A or b has a non-finite
    /// entry, A is singular, or N is 0 or above 4.
    pub fn new(a: SMatrix<f64, N, N>, offset: SVector<f64, N>) -> Result<Self> {
        if N > 4 {
            return Err(invalid("N", N, "cubes have at most 16 vertices (N ≤ 4)"));
        }
        check_affine(&a, &offset)?;
        Ok(Self { a, offset })
    }

    /// The rectangular grid x = (Δ₀ v₀, …, Δ_{N−1} v_{N−1}).
    ///
    /// # Errors
    /// As [`CubeNodes::new`], for a non-positive or non-finite spacing.
    pub fn grid(spacing: SVector<f64, N>) -> Result<Self> {
        if !spacing.iter().all(|h| h.is_finite() && *h > 0.0) {
            return Err(invalid("spacing", format!("{spacing}"), "must be positive and finite"));
        }
        Self::new(SMatrix::from_diagonal(&spacing), SVector::zeros())
    }
}

impl<const N: usize> NodeMap<N> for CubeNodes<N> {
    fn cell_nodes(&self, cell: &TopCell, out: &mut [SVector<f64, N>]) -> usize {
        let count = 1usize << N;
        if out.len() < count {
            return 0;
        }
        for (k, slot) in out.iter_mut().take(count).enumerate() {
            let c = cube_corner(N, k);
            let v: [i64; MAX_LATTICE_DIMENSION] = std::array::from_fn(|i| cell.origin[i] + c[i]);
            *slot = affine(&self.a, &self.offset, &v);
        }
        count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutations_are_lexicographic() {
        let all: Vec<Vec<usize>> = (0..6)
            .map(|s| permutation(3, s).expect("valid index")[..3].to_vec())
            .collect();
        let expected = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
        for (p, e) in all.iter().zip(expected) {
            assert_eq!(p.as_slice(), e.as_slice());
        }
        assert!(permutation(3, 6).is_err());
        assert!(permutation(9, 0).is_err());
        let rev = permutation(8, factorial(8) - 1).expect("valid index");
        assert_eq!(rev, [7, 6, 5, 4, 3, 2, 1, 0]);
    }

    #[test]
    fn leapfrog_is_6_2() {
        let m = CfkNodes::leapfrog(0.3, 0.1).expect("valid");
        let cell = TopCell {
            index: 0,
            shape: 1,
            origin: [2, 1, 0, 0, 0, 0, 0, 0],
        };
        let mut x = [SVector::<f64, 2>::zeros(); 3];
        assert_eq!(m.cell_nodes(&cell, &mut x), 3);
        // (i, j) = (2, 1) → ((2 − 1)·0.15, 3·0.05); σ = − goes to (2, 2) then (3, 2).
        let want = [[0.15, 0.15], [0.0, 0.2], [0.15, 0.25]];
        for (xi, w) in x.iter().zip(want) {
            assert!(
                (xi[0] - w[0]).abs() < 1e-15 && (xi[1] - w[1]).abs() < 1e-15,
                "{xi} vs {w:?}"
            );
        }
        let bad = TopCell { shape: 2, ..cell };
        assert_eq!(m.cell_nodes(&bad, &mut x), 0);
    }

    #[test]
    fn space_time_flow_is_a_time_step() {
        let m = CfkNodes::<4>::space_time(0.5, 0.2).expect("valid");
        let v = [1, -2, 3, 0, 0, 0, 0, 0];
        let w = [2, -1, 4, 1, 0, 0, 0, 0];
        let d = m.node(&w) - m.node(&v);
        assert!(d.rows(0, 3).norm() < 1e-15 && (d[3] - 0.2).abs() < 1e-15, "{d}");
    }
}
