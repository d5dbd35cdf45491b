//! Stokes' theorem on the infinite CFK and cubic lattices (seed 003 §2,
//! note 003 T3): random chains of random cells near the origin, random
//! cochains on their faces, ∂∂ = 0 on the chains (property tests).

use veselov::complex::{
    CellComplex, CfkCell, CfkLattice, Chain, Cochain, CubicLattice, MAX_LATTICE_DIMENSION, carrier_cube,
};

use crate::shared::SplitMix;
use proptest::prelude::*;

/// A random k-cell of the n-dimensional CFK lattice near the origin.
fn random_cfk_cell(n: usize, k: usize, seed: u64) -> CfkCell {
    let mut rng = SplitMix(seed);
    let mut base = [0; MAX_LATTICE_DIMENSION];
    for x in base.iter_mut().take(n) {
        *x = rng.below(5) as i64 - 2;
    }
    // a random surjective labelling of a random subset of axes onto 1..=k
    loop {
        let mut labels = [0u8; MAX_LATTICE_DIMENSION];
        let mut used = 0u32;
        for l in labels.iter_mut().take(n) {
            *l = rng.below(k + 1) as u8;
            used |= 1 << *l;
        }
        if used >> 1 == (1 << k) - 1 {
            return CfkCell {
                base,
                labels,
                k: k as u8,
            };
        }
    }
}

/// ⟨c, dω⟩ and ⟨∂c, ω⟩ for a random cochain ω on the faces of the cells of
/// the chain `c`.
fn stokes_sides<K: CellComplex>(complex: &K, c: &Chain<K::Cell>, rng: &mut SplitMix) -> (f64, f64) {
    let mut omega = Cochain::new();
    let mut faces = Vec::new();
    for (beta, _) in c.iter() {
        complex.faces(beta, &mut faces);
        for (alpha, _) in &faces {
            omega.set(alpha.clone(), 2.0 * rng.uniform() - 1.0);
        }
    }
    (c.pair(&omega.coboundary(complex)), c.boundary(complex).pair(&omega))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Stokes on the infinite lattices: random chains of random cells near the
    /// origin and random cochains on their faces.
    #[test]
    fn stokes_on_infinite_lattices(n in 1usize..=4, k_seed in 0usize..4, seed in any::<u64>(),
                                   coefficients in proptest::collection::vec(-3i64..=3, 1..6)) {
        let k = 1 + k_seed % n;
        let cfk = CfkLattice::new(n).expect("CFK");
        let mut c = Chain::new();
        for (m, &a) in coefficients.iter().enumerate() {
            c.add(random_cfk_cell(n, k, seed.wrapping_add(m as u64)), a);
        }
        let mut rng = SplitMix(seed);
        let (lhs, rhs) = stokes_sides(&cfk, &c, &mut rng);
        prop_assert!((lhs - rhs).abs() <= 1e-13 * (1.0 + lhs.abs()));
        prop_assert!(c.boundary(&cfk).boundary(&cfk).is_zero());

        let cubic = CubicLattice::new(n).expect("cubic");
        let mut cc = Chain::new();
        for (m, &a) in coefficients.iter().enumerate() {
            let cell = random_cfk_cell(n, k, seed.wrapping_add(m as u64));
            cc.add(carrier_cube(&cell), a);
        }
        // (carrier cubes of k-cells may have several dimensions: Stokes holds
        // dimension by dimension, so also for the mixed chain)
        let (lhs, rhs) = stokes_sides(&cubic, &cc, &mut rng);
        prop_assert!((lhs - rhs).abs() <= 1e-13 * (1.0 + lhs.abs()));
    }
}
