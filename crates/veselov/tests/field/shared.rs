//! Helpers that several field tests share: Cauchy data on the 2+1 CFK
//! lattice, top cells with their nodes, relative errors, the two points of
//! a central difference in a fibre's chart and two small reproducible
//! random generators.

use nalgebra::{SMatrix, SVector, Vector3};
use veselov::complex::{CfkTorus, TopCell};
use veselov::field::discretize::{CfkNodes, NodeMap};
use veselov::field::fibre::Fibre;
use veselov::lie::{SO3, so3};

/// The cell values `y` with vertex `k`'s value moved to y_k·τ(±ξ)
/// ([`Fibre::retract`]): the two points of a central difference along ξ in
/// the chart at y_k, (plus, minus).
pub fn nudged<F: Fibre<M>, const M: usize, const V: usize>(
    y: &[F::Point<f64>; V],
    k: usize,
    xi: &SVector<f64, M>,
) -> [[F::Point<f64>; V]; 2] {
    let (mut plus, mut minus) = (*y, *y);
    plus[k] = F::retract(&y[k], xi);
    minus[k] = F::retract(&y[k], &(-xi));
    [plus, minus]
}

/// Cauchy data: the six levels of a prescribed space–time function f(x)
/// at the nodes of `torus` (x = (x, y, t)).
pub fn cauchy_data<const M: usize>(
    torus: &CfkTorus,
    nodes: &CfkNodes<3>,
    f: impl Fn(&Vector3<f64>) -> SVector<f64, M>,
) -> Vec<Vec<SVector<f64, M>>> {
    (0..6)
        .map(|w| {
            (0..torus.level_size())
                .map(|i| f(&nodes.node(&torus.vertex(w, i))))
                .collect()
        })
        .collect()
}

/// The top cell `index` of the given shape at `origin` (missing coordinates
/// are zero).
pub fn cell(index: usize, shape: usize, origin: &[i64]) -> TopCell {
    let mut o = [0; 8];
    o[..origin.len()].copy_from_slice(origin);
    TopCell {
        index,
        shape,
        origin: o,
    }
}

/// The `count` nodes of cell `c` under `map`, which must know the cell.
pub fn nodes_of<const N: usize>(map: &impl NodeMap<N>, c: &TopCell, count: usize) -> Vec<SVector<f64, N>> {
    let mut x = vec![SVector::<f64, N>::zeros(); 16];
    assert_eq!(map.cell_nodes(c, &mut x), count, "node map knows the cell");
    x.truncate(count);
    x
}

/// |a − b| relative to the larger magnitude.
pub fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / a.abs().max(b.abs()).max(1e-300)
}

/// |a − b| relative to the larger norm.
pub fn rel_vec<const K: usize>(a: &SVector<f64, K>, b: &SVector<f64, K>) -> f64 {
    (a - b).norm() / a.norm().max(b.norm()).max(1e-300)
}

/// Xorshift64 from a non-zero seed: numbers uniform in [−1, 1).
pub struct Xorshift(pub u64);

impl Xorshift {
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    /// A vector with entries uniform in [−scale, scale).
    pub fn vector<const K: usize>(&mut self, scale: f64) -> SVector<f64, K> {
        SVector::from_fn(|_, _| scale * self.uniform())
    }
}

/// SplitMix64 from any seed: integers, and numbers uniform in [0, 1) or
/// symmetric about 0.
pub struct SplitMix(pub u64);

impl SplitMix {
    pub fn bits(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in 0..m.
    pub fn below(&mut self, m: usize) -> usize {
        (self.bits() % m as u64) as usize
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.bits() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in (−a, a).
    pub fn sym(&mut self, a: f64) -> f64 {
        a * (2.0 * self.uniform() - 1.0)
    }

    pub fn vec<const K: usize>(&mut self, a: f64) -> SVector<f64, K> {
        SVector::from_fn(|_, _| self.sym(a))
    }

    pub fn mat<const R: usize, const C: usize>(&mut self, a: f64) -> SMatrix<f64, R, C> {
        SMatrix::from_fn(|_, _| self.sym(a))
    }

    /// exp of a vector with entries in (−angle/√3, angle/√3).
    pub fn rotation(&mut self, angle: f64) -> SO3<f64> {
        so3::exp(&self.vec::<3>(angle / 3f64.sqrt()))
    }
}
