//! The abstract cellular complex (seed 003 Def. 2.1, note 003 §1.1): cells
//! graded by dimension, incidence numbers \[β:α\] ∈ {−1, 0, +1}, faces and
//! cofaces, ordered vertices and vertex stars (Def. 2.3); integer chains of
//! finite support and real cochains with the boundary ∂, the coboundary d and
//! the pairing ⟨c, ω⟩, so that Stokes' theorem ⟨c, dω⟩ = ⟨∂c, ω⟩ (2.2) holds.
//!
//! Complexes may be infinite (the cubic and CFK lattices): every operation is
//! local (axiom 3), and chains and cochains are stored by their finite support.

use std::collections::BTreeMap;
use std::fmt::Debug;
use std::hash::Hash;

use crate::error::{Error, Result};

/// A cellular complex (V, dim, \[·:·\]) of Def. 2.1.
pub trait CellComplex {
    /// A cell (an element of V).
    type Cell: Clone + Ord + Hash + Debug;
    /// Dimension n of the complex (the largest cell dimension).
    fn dim(&self) -> usize;
    /// dim α.
    fn cell_dimension(&self, cell: &Self::Cell) -> usize;
    /// Replaces `out` by the faces α of `cell` with nonzero incidence, as
    /// `(α, \[cell:α\])`.
    fn faces(&self, cell: &Self::Cell, out: &mut Vec<(Self::Cell, i8)>);
    /// Replaces `out` by the cofaces β of `cell` with nonzero incidence, as
    /// `(β, \[β:cell\])`.
    fn cofaces(&self, cell: &Self::Cell, out: &mut Vec<(Self::Cell, i8)>);
    /// The ordered vertices (0-cells) of `cell` (weight order on lattices,
    /// stored order on meshes).
    fn vertices(&self, cell: &Self::Cell) -> Vec<Self::Cell>;
    /// Replaces `out` by the star S_v (Def. 2.3): the top cells containing the
    /// vertex `v`.
    fn star_cells(&self, v: &Self::Cell, out: &mut Vec<Self::Cell>);
    /// The incidence number \[β:α\] (0 when α is not a face of β).
    fn incidence(&self, beta: &Self::Cell, alpha: &Self::Cell) -> i8 {
        let mut faces = Vec::new();
        self.faces(beta, &mut faces);
        faces.iter().find(|(a, _)| a == alpha).map_or(0, |&(_, s)| s)
    }
}

/// A complex with finitely many cells (a window, a periodic quotient, a mesh).
pub trait FiniteComplex: CellComplex {
    /// All k-cells, sorted.
    fn cells(&self, k: usize) -> Vec<Self::Cell>;
}

/// An abstract simplicial complex (Def. 2.5): a cell is determined by its set
/// of vertices.
pub trait Simplicial: CellComplex {
    /// The cell with the given vertex set (any order), if it exists.
    fn simplex(&self, vertices: &[Self::Cell]) -> Option<Self::Cell>;
}

/// An integer chain of finite support, c ∈ C_k = ⊕_{V_k} ℤ.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Chain<C: Ord> {
    coefficients: BTreeMap<C, i64>,
}

impl<C: Ord + Clone> Default for Chain<C> {
    fn default() -> Self {
        Self::new()
    }
}

impl<C: Ord + Clone> Chain<C> {
    /// The zero chain.
    pub fn new() -> Self {
        Self {
            coefficients: BTreeMap::new(),
        }
    }
    /// The characteristic chain c_A of a finite set of cells (Def. 2.2).
    pub fn characteristic(cells: impl IntoIterator<Item = C>) -> Self {
        let mut c = Self::new();
        for cell in cells {
            c.add(cell, 1);
        }
        c
    }
    /// c(α) += coefficient (zero coefficients are dropped).
    pub fn add(&mut self, cell: C, coefficient: i64) {
        let entry = self.coefficients.entry(cell.clone()).or_insert(0);
        *entry += coefficient;
        if *entry == 0 {
            self.coefficients.remove(&cell);
        }
    }
    /// c(α).
    pub fn get(&self, cell: &C) -> i64 {
        self.coefficients.get(cell).copied().unwrap_or(0)
    }
    /// Is this the zero chain?
    pub fn is_zero(&self) -> bool {
        self.coefficients.is_empty()
    }
    /// The support with its nonzero coefficients.
    pub fn iter(&self) -> impl Iterator<Item = (&C, i64)> {
        self.coefficients.iter().map(|(c, &a)| (c, a))
    }
    /// ∂c: (∂c)(α) = Σ_β \[β:α\] c(β).
    pub fn boundary<K: CellComplex<Cell = C>>(&self, complex: &K) -> Self {
        let mut out = Self::new();
        let mut faces = Vec::new();
        for (beta, &c) in &self.coefficients {
            complex.faces(beta, &mut faces);
            for (alpha, s) in faces.drain(..) {
                out.add(alpha, i64::from(s) * c);
            }
        }
        out
    }
    /// The pairing ⟨c, ω⟩ = Σ_α c(α) ω(α).
    pub fn pair(&self, omega: &Cochain<C>) -> f64 {
        self.coefficients.iter().map(|(a, &c)| c as f64 * omega.get(a)).sum()
    }
}

/// A real cochain ω ∈ Ω^k = Map(V_k, ℝ), stored by its finite support (zero
/// elsewhere).
#[derive(Clone, Debug, PartialEq)]
pub struct Cochain<C: Ord> {
    values: BTreeMap<C, f64>,
}

impl<C: Ord + Clone> Default for Cochain<C> {
    fn default() -> Self {
        Self::new()
    }
}

impl<C: Ord + Clone> Cochain<C> {
    /// The zero cochain.
    pub fn new() -> Self {
        Self {
            values: BTreeMap::new(),
        }
    }
    /// ω(α) = value.
    pub fn set(&mut self, cell: C, value: f64) {
        if value == 0.0 {
            self.values.remove(&cell);
        } else {
            self.values.insert(cell, value);
        }
    }
    /// ω(α).
    pub fn get(&self, cell: &C) -> f64 {
        self.values.get(cell).copied().unwrap_or(0.0)
    }
    /// The support with its values.
    pub fn iter(&self) -> impl Iterator<Item = (&C, f64)> {
        self.values.iter().map(|(c, &a)| (c, a))
    }
    /// (dω)(β) = Σ_α \[β:α\] ω(α) at one cell β.
    pub fn coboundary_at<K: CellComplex<Cell = C>>(&self, complex: &K, beta: &C) -> f64 {
        let mut faces = Vec::new();
        complex.faces(beta, &mut faces);
        faces.iter().map(|(a, s)| f64::from(*s) * self.get(a)).sum()
    }
    /// dω, computed on the cofaces of the support of ω.
    pub fn coboundary<K: CellComplex<Cell = C>>(&self, complex: &K) -> Self {
        let mut out: BTreeMap<C, f64> = BTreeMap::new();
        let mut cofaces = Vec::new();
        for (alpha, &w) in &self.values {
            complex.cofaces(alpha, &mut cofaces);
            for (beta, s) in cofaces.drain(..) {
                *out.entry(beta).or_insert(0.0) += f64::from(s) * w;
            }
        }
        out.retain(|_, v| *v != 0.0);
        Self { values: out }
    }
}

fn axiom_error<C: Debug>(cell: &C, reason: String) -> Error {
    Error::Complex {
        cell: format!("{cell:?}"),
        reason,
    }
}

/// Checks axioms 2–4 of Def. 2.1 on the given cells of any complex: every
/// nonzero incidence joins dimensions k and k − 1 and is ±1 (axiom 2); faces
/// and cofaces are finite and agree with each other, with the same sign
/// (axiom 3); and ∂∂ = 0 on every cell: Σ_α \[β:α\]\[α:γ\] = 0 (axiom 4).
///
/// # Errors
/// [`Error::Complex`] naming the first offending cell.
pub fn validate_cells<K: CellComplex>(complex: &K, cells: impl IntoIterator<Item = K::Cell>) -> Result<()> {
    let mut faces = Vec::new();
    let mut back = Vec::new();
    for beta in cells {
        let k = complex.cell_dimension(&beta);
        if k > complex.dim() {
            return Err(axiom_error(&beta, format!("dimension {k} exceeds the complex's")));
        }
        complex.faces(&beta, &mut faces);
        for (alpha, s) in &faces {
            if !(*s == 1 || *s == -1) {
                return Err(axiom_error(&beta, format!("incidence {s} with face {alpha:?}")));
            }
            if k == 0 || complex.cell_dimension(alpha) != k - 1 {
                return Err(axiom_error(&beta, format!("face {alpha:?} has the wrong dimension")));
            }
            complex.cofaces(alpha, &mut back);
            if back.iter().filter(|(b, t)| *b == beta && t == s).count() != 1 {
                return Err(axiom_error(
                    &beta,
                    format!("not a coface of its face {alpha:?} with incidence {s}"),
                ));
            }
        }
        let dd = Chain::characteristic([beta.clone()])
            .boundary(complex)
            .boundary(complex);
        if !dd.is_zero() {
            return Err(axiom_error(&beta, format!("∂∂ ≠ 0: {dd:?}")));
        }
        complex.cofaces(&beta, &mut back);
        for (gamma, s) in &back {
            if complex.cell_dimension(gamma) != k + 1 || complex.incidence(gamma, &beta) != *s {
                return Err(axiom_error(&beta, format!("coface {gamma:?} disagrees with its faces")));
            }
        }
    }
    Ok(())
}

/// [`validate_cells`] on every cell of a finite complex, plus axiom 1 (some
/// cell has dimension n).
///
/// # Errors
/// [`Error::Complex`] naming the first offending cell.
pub fn validate<K: FiniteComplex>(complex: &K) -> Result<()> {
    let n = complex.dim();
    if complex.cells(n).is_empty() {
        return Err(axiom_error(&n, "no cell of the top dimension".to_string()));
    }
    for k in 0..=n {
        validate_cells(complex, complex.cells(k))?;
    }
    Ok(())
}

/// The orientation o_α(v₀, …, v_k) of an ordered simplex from the incidence
/// numbers, (2.6): Π_{j=1}^{k} \[{v_{j−1}, …, v_k} : {v_j, …, v_k}\], and
/// o_α(v) = 1.
///
/// # Errors
/// [`Error::Complex`] when some tail {v_j, …, v_k} is not a cell.
pub fn orientation<K: Simplicial>(complex: &K, ordered: &[K::Cell]) -> Result<i8> {
    let mut sign = 1i8;
    for j in 1..ordered.len() {
        let big = complex
            .simplex(&ordered[j - 1..])
            .ok_or_else(|| axiom_error(&ordered, "not a simplex of the complex".to_string()))?;
        let small = complex
            .simplex(&ordered[j..])
            .ok_or_else(|| axiom_error(&ordered, "not a simplex of the complex".to_string()))?;
        sign *= complex.incidence(&big, &small);
    }
    Ok(sign)
}

/// The incidence number from orientations, (2.7):
/// \[β : β∖{v_j}\] = (−1)^j · o_β(v₀, …, v_k) · o_α(v₀, …, v̂_j, …, v_k).
///
/// # Errors
/// As [`orientation`].
pub fn incidence_from_orientation<K: Simplicial>(complex: &K, ordered: &[K::Cell], j: usize) -> Result<i8> {
    let mut face: Vec<K::Cell> = ordered.to_vec();
    face.remove(j);
    Ok(parity(j) * orientation(complex, ordered)? * orientation(complex, &face)?)
}

/// The sign of the permutation that sorts `keys` (distinct keys).
pub fn sort_sign<T: Ord>(keys: &[T]) -> i8 {
    let mut inversions = 0usize;
    for a in 0..keys.len() {
        for b in a + 1..keys.len() {
            if keys[a] > keys[b] {
                inversions += 1;
            }
        }
    }
    parity(inversions)
}

/// (−1)^j.
pub fn parity(j: usize) -> i8 {
    if j.is_multiple_of(2) { 1 } else { -1 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_cancel_and_signs_sort() {
        let mut c = Chain::new();
        c.add(3u8, 2);
        c.add(3u8, -2);
        assert!(c.is_zero());
        c.add(1, 4);
        let mut w = Cochain::new();
        w.set(1u8, 0.5);
        w.set(2u8, 7.0);
        assert_eq!(c.pair(&w), 2.0);
        assert_eq!(sort_sign(&[0, 1, 2]), 1);
        assert_eq!(sort_sign(&[1, 0, 2]), -1);
        assert_eq!(sort_sign(&[2, 0, 1]), 1);
    }
}
