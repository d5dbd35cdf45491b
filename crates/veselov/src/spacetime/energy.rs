//! Discrete energies of cell Lagrangians built from a smooth density: the
//! energy density e = ⟨φ_t, ∂𝓛/∂φ_t⟩ − 𝓛 (seed 002 (4.6): minus the
//! multimomentum p) evaluated at each cell's jet, summed over the cells of a
//! time strip and multiplied by the space step k, so that it approximates
//! ∫ e dx.
//!
//! For 𝓛 = ½(|φ_t|² − |φ_x|²) + N(φ) this is e = ½|φ_t|² + ½|φ_x|² − N(φ):
//! with the symmetric rectangle rule it is the footnote-4 energy of seed 002
//! (T and D are that rule's φ_t and φ_x); with the triangle rule it is the
//! footnote-5 energy except that φ_x is taken on the upper edge of the
//! triangle, where the cell's jet puts it. Multisymplectic schemes do not
//! conserve such energies exactly; they keep them bounded.

use nalgebra::{Const, SVector, U1};
use num_dual::DualSVec64;

use crate::spacetime::density::{CellLagrangian, Density, Jet, RectangleRule, TriangleRule, gather};
use crate::spacetime::generic::node_value;
use crate::spacetime::lattice::Lattice;

/// A cell Lagrangian with an energy density.
pub trait CellEnergy<const DIM: usize>: CellLagrangian<DIM> {
    /// e = ⟨φ_t, ∂𝓛/∂φ_t⟩ − 𝓛 at the jet of the cell with vertex values `y`.
    fn energy_density(&self, y: &[SVector<f64, DIM>]) -> f64;
}

fn density_energy<F: Density<DIM>, const DIM: usize>(density: &F, (phi, phi_t, phi_x): Jet<f64, DIM>) -> f64 {
    let seeded = SVector::<DualSVec64<DIM>, DIM>::from_fn(|a, _| DualSVec64::<DIM>::from(phi_t[a]).derivative(a));
    let l = density.density(&phi.map(DualSVec64::from), &seeded, &phi_x.map(DualSVec64::from));
    let p = l.eps.unwrap_generic(Const::<DIM>, U1);
    phi_t.dot(&p) - l.re
}

impl<const DIM: usize, F: Density<DIM>> CellEnergy<DIM> for TriangleRule<F> {
    fn energy_density(&self, y: &[SVector<f64, DIM>]) -> f64 {
        density_energy(&self.density, self.jet(y))
    }
}

impl<const DIM: usize, F: Density<DIM>> CellEnergy<DIM> for RectangleRule<F> {
    fn energy_density(&self, y: &[SVector<f64, DIM>]) -> f64 {
        density_energy(&self.density, self.jet(y))
    }
}

/// E = k Σ_i e(cell (i, j)) over the cells between levels j (`y_j`) and j+1
/// (`y_j1`) (cells i = 0..N on periodic lattices, 0..N−1 otherwise).
pub fn level_energy<L: CellEnergy<DIM>, const DIM: usize>(
    lag: &L,
    lattice: &Lattice,
    y_j: &[SVector<f64, DIM>],
    y_j1: &[SVector<f64, DIM>],
) -> f64 {
    let shape = lag.shape();
    let nv = shape.vertices();
    let get = |(i, j): (i64, i64)| node_value(lattice, if j == 0 { y_j } else { y_j1 }, i);
    let cells = if lattice.is_periodic() {
        lattice.nodes()
    } else {
        lattice.nodes() - 1
    };
    let mut e = 0.0;
    for i in 0..cells {
        if let Some(v) = gather(shape, (i as i64, 0), &get) {
            e += lag.energy_density(&v[..nv]);
        }
    }
    e * lattice.dx()
}
