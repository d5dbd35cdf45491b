//! The CFK simplicial lattice of dimension n cut into weight levels and
//! wrapped periodically in space: the complex the Cauchy marcher sweeps
//! (note 003 §1.4, §2.4, Remark 4.12).
//!
//! * Vertices v ∈ ℤⁿ; the *weight* w(v) = Σᵢ vᵢ is the level ("time").
//! * Top cells are the path simplices (v, σ), σ ∈ Sym(n) (Cor. 2.17): vertices
//!   v₀ = v, v_{l+1} = v_l + e_{σ(l)}, so w(v_l) = w(v) + l. The flow
//!   Δv = v + (1,…,1) moves a vertex n levels up; the n! simplices based at v
//!   are exactly those containing both v and Δv (S_v^Δ, Def. 4.2).
//! * Space is periodic: v ~ v + N_a (e_a − e_{n−1}) for a < n − 1, so a level
//!   is the torus ℤ_{N_0} × … × ℤ_{N_{n−2}} indexed by (v_0 mod N_0, …); the
//!   last coordinate is v_{n−1} = w − Σ_{a<n−1} v_a. For n = 1 a level is a
//!   single vertex (discrete mechanics).
//! * Permutations σ ∈ Sym(n) are indexed in lexicographic order
//!   ([`permutation`]); index 0 is the identity.
//!
//! [`CfkSlab`] is a finite window of consecutive levels: it implements
//! [`TopCells`] with the cells whose vertices all lie in the window.

use crate::complex::{MAX_LATTICE_DIMENSION, StarEntry, TopCell, TopCells};
use crate::{Error, Result};

pub use crate::complex::window::factorial;

/// The permutation with lexicographic index `index` in Sym(n)
/// (`index < n!`; the indexing of [`crate::complex::window::permutation_into`]);
/// entries beyond `n` are zero.
pub fn permutation(n: usize, index: usize) -> [usize; MAX_LATTICE_DIMENSION] {
    let mut out = [0; MAX_LATTICE_DIMENSION];
    crate::complex::window::permutation_into(n, index, &mut out);
    out
}

/// The shape of a spatially periodic CFK lattice: dimension and periods.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CfkTorus {
    n: usize,
    periods: Vec<usize>,
    level_size: usize,
    strides: Vec<usize>,
}

impl CfkTorus {
    /// The n-dimensional CFK lattice with spatial periods `periods`
    /// (`periods.len() == n − 1`, each ≥ 3 so that a star does not wrap onto
    /// itself).
    pub fn new(n: usize, periods: &[usize]) -> Result<Self> {
        if n == 0 || n > MAX_LATTICE_DIMENSION {
            return Err(Error::InvalidParameter {
                name: "dimension".into(),
                value: n.to_string(),
                reason: format!("the CFK lattice dimension must be 1..={MAX_LATTICE_DIMENSION}"),
            });
        }
        if periods.len() != n - 1 {
            return Err(Error::DimensionMismatch {
                what: "spatial periods of the CFK lattice".into(),
                expected: n - 1,
                got: periods.len(),
            });
        }
        if let Some(&p) = periods.iter().find(|&&p| p < 3) {
            return Err(Error::InvalidParameter {
                name: "nodes".into(),
                value: p.to_string(),
                reason: "each periodic axis needs at least 3 nodes, or a vertex star wraps onto itself".into(),
            });
        }
        let level_size = periods
            .iter()
            .try_fold(1usize, |acc, &p| acc.checked_mul(p))
            .ok_or_else(|| Error::InvalidParameter {
                name: "nodes".into(),
                value: format!("{periods:?}"),
                reason: "too many nodes per level".into(),
            })?;
        let mut strides = vec![1; periods.len()];
        for a in (0..periods.len().saturating_sub(1)).rev() {
            strides[a] = strides[a + 1] * periods[a + 1];
        }
        Ok(Self {
            n,
            periods: periods.to_vec(),
            level_size,
            strides,
        })
    }

    /// Dimension n.
    pub fn dimension(&self) -> usize {
        self.n
    }

    /// Spatial periods N_a.
    pub fn periods(&self) -> &[usize] {
        &self.periods
    }

    /// Vertices per level.
    pub fn level_size(&self) -> usize {
        self.level_size
    }

    /// Number of simplices based at a vertex (n!).
    pub fn simplices_per_vertex(&self) -> usize {
        factorial(self.n)
    }

    /// The in-level index of vertex `v` (its level is Σv).
    pub fn index_of(&self, v: &[i64]) -> usize {
        let mut idx = 0;
        for (a, (&p, &s)) in self.periods.iter().zip(&self.strides).enumerate() {
            idx += (v[a].rem_euclid(p as i64) as usize) * s;
        }
        idx
    }

    /// The canonical representative of the vertex at `level` with in-level
    /// index `index`: v_a ∈ [0, N_a) for a < n − 1.
    pub fn vertex(&self, level: i64, index: usize) -> [i64; MAX_LATTICE_DIMENSION] {
        let mut v = [0i64; MAX_LATTICE_DIMENSION];
        let mut sum = 0;
        for (a, (&p, &s)) in self.periods.iter().zip(&self.strides).enumerate() {
            v[a] = ((index / s) % p) as i64;
            sum += v[a];
        }
        v[self.n - 1] = level - sum;
        v
    }

    /// In-level index of v + e_S (the sum of unit vectors e_{σ(l)}, l < j):
    /// the j-th vertex of simplex (v, σ), or with `sign = −1` the base of the
    /// simplex (u, σ) whose j-th vertex is v.
    pub fn offset_index(&self, index: usize, perm: &[usize; MAX_LATTICE_DIMENSION], j: usize, sign: i64) -> usize {
        let mut out = index;
        for &axis in &perm[..j] {
            if axis + 1 < self.n {
                let p = self.periods[axis];
                let s = self.strides[axis];
                let digit = (index / s) % p;
                let moved = (digit as i64 + sign).rem_euclid(p as i64) as usize;
                out = out + moved * s - digit * s;
            }
        }
        out
    }
}

/// A finite window of `levels` consecutive weight levels of a periodic CFK
/// lattice, starting at weight `first_level`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CfkSlab {
    torus: CfkTorus,
    first_level: i64,
    levels: usize,
    perms: Vec<[usize; MAX_LATTICE_DIMENSION]>,
}

impl CfkSlab {
    /// The window; it must hold at least one whole simplex (`levels > n`).
    pub fn new(torus: CfkTorus, first_level: i64, levels: usize) -> Result<Self> {
        if levels <= torus.n {
            return Err(Error::InvalidParameter {
                name: "levels".into(),
                value: levels.to_string(),
                reason: format!(
                    "a window of a {}-dimensional CFK lattice needs more than {} levels",
                    torus.n, torus.n
                ),
            });
        }
        let perms = (0..torus.simplices_per_vertex())
            .map(|s| permutation(torus.n, s))
            .collect();
        Ok(Self {
            torus,
            first_level,
            levels,
            perms,
        })
    }

    /// The periodic lattice.
    pub fn torus(&self) -> &CfkTorus {
        &self.torus
    }

    /// Weight of the first level.
    pub fn first_level(&self) -> i64 {
        self.first_level
    }

    /// Number of levels.
    pub fn levels(&self) -> usize {
        self.levels
    }

    /// Vertex index of (level offset, in-level index).
    pub fn vertex_index(&self, level_offset: usize, index: usize) -> usize {
        level_offset * self.torus.level_size + index
    }

    fn base_levels(&self) -> usize {
        self.levels - self.torus.n
    }
}

impl TopCells for CfkSlab {
    fn dimension(&self) -> usize {
        self.torus.n
    }
    fn vertex_count(&self) -> usize {
        self.levels * self.torus.level_size
    }
    fn cell_count(&self) -> usize {
        self.base_levels() * self.torus.level_size * self.perms.len()
    }
    fn max_cell_vertices(&self) -> usize {
        self.torus.n + 1
    }
    fn cell(&self, index: usize) -> TopCell {
        let shape = index % self.perms.len();
        let vertex = index / self.perms.len();
        let (level, i) = (vertex / self.torus.level_size, vertex % self.torus.level_size);
        TopCell {
            index,
            shape,
            origin: self.torus.vertex(self.first_level + level as i64, i),
        }
    }
    fn cell_vertices(&self, index: usize, out: &mut [usize]) -> usize {
        let shape = index % self.perms.len();
        let vertex = index / self.perms.len();
        let (level, i) = (vertex / self.torus.level_size, vertex % self.torus.level_size);
        for (j, slot) in out.iter_mut().take(self.torus.n + 1).enumerate() {
            *slot = self.vertex_index(level + j, self.torus.offset_index(i, &self.perms[shape], j, 1));
        }
        self.torus.n + 1
    }
    fn star(&self, v: usize, out: &mut Vec<StarEntry>) {
        out.clear();
        let (level, i) = (v / self.torus.level_size, v % self.torus.level_size);
        for j in 0..=self.torus.n {
            let Some(base_level) = level.checked_sub(j) else {
                continue;
            };
            if base_level >= self.base_levels() {
                continue;
            }
            for (shape, perm) in self.perms.iter().enumerate() {
                let base = self.torus.offset_index(i, perm, j, -1);
                let cell = (self.vertex_index(base_level, base)) * self.perms.len() + shape;
                out.push(StarEntry { cell, position: j });
            }
        }
        out.sort_unstable_by_key(|e| e.cell);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutations_are_lexicographic_and_complete() {
        for n in 1..=5 {
            let mut seen = std::collections::BTreeSet::new();
            for s in 0..factorial(n) {
                let p = permutation(n, s);
                seen.insert(p[..n].to_vec());
            }
            assert_eq!(seen.len(), factorial(n));
            assert_eq!(permutation(n, 0)[..n], (0..n).collect::<Vec<_>>()[..]);
        }
        assert_eq!(permutation(3, 1)[..3], [0, 2, 1]);
        assert_eq!(permutation(3, 5)[..3], [2, 1, 0]);
    }

    #[test]
    fn stars_have_full_size_and_agree_with_cells() {
        for n in 1..=4 {
            let periods = vec![4; n - 1];
            let slab = CfkSlab::new(CfkTorus::new(n, &periods).expect("valid torus"), -3, 2 * n + 1).expect("window");
            let mut star = Vec::new();
            let mut verts = vec![0; n + 1];
            // A vertex in the middle level has the full star of (n+1)! simplices.
            let mid = slab.vertex_index(n, 1 % slab.torus().level_size());
            slab.star(mid, &mut star);
            assert_eq!(star.len(), factorial(n + 1), "n = {n}");
            for e in &star {
                slab.cell_vertices(e.cell, &mut verts);
                assert_eq!(verts[e.position], mid);
            }
            // Every cell is in the star of each of its vertices.
            for c in 0..slab.cell_count() {
                let k = slab.cell_vertices(c, &mut verts);
                for (pos, &v) in verts[..k].iter().enumerate() {
                    slab.star(v, &mut star);
                    assert!(star.contains(&StarEntry { cell: c, position: pos }));
                }
            }
        }
    }

    #[test]
    fn bad_shapes_are_refused() {
        assert!(CfkTorus::new(0, &[]).is_err());
        assert!(CfkTorus::new(3, &[4]).is_err());
        assert!(CfkTorus::new(2, &[2]).is_err());
        let t = CfkTorus::new(2, &[5]).expect("valid");
        assert!(CfkSlab::new(t, 0, 2).is_err());
    }
}
