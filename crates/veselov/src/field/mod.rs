//! Discrete multisymplectic field theory on 1+1 spacetime lattices
//! (seed 002 §5): lattices and region topology, discrete Lagrangian
//! densities on triangles and rectangles, time marching (a generic Newton
//! path for any density and fast O(N) paths for the sine-Gordon family of
//! schemes), discrete energies, Noether charges and the discrete
//! multisymplectic form formula.
//!
//! Index convention: node `(i, j)`, `i` = space (`x = i·dx`), `j` = time
//! (`t = j·dt`). The paper's `h` is the time step `dt` and its `k` the space
//! step `dx`.

pub mod cyclic;
pub mod density;
pub mod fast;
pub mod generic;
pub mod initial;
pub mod lattice;
pub mod noether;
pub mod potential;
pub mod region;
pub mod run;
pub mod scheme;

pub use density::{
    CellJet, CellLagrangian, Density, RectangleRule, TriangleRule, action, cell_gradient, cell_jet, delf_residual,
};
pub use fast::{FastMarcher, SolverOptions};
pub use generic::{GenericMarcher, Tangent, node_value};
pub use initial::{InitialData, PeriodicKink};
pub use lattice::{Boundary, CellShape, Lattice};
pub use noether::{multisymplectic_boundary_sum, recentre_mod_2pi, shift_charge, split_charge};
pub use potential::{ComplexKleinGordon, NonlinearWave, Phi4, Potential, ScalarPotential, SineGordon, Wave};
pub use region::{Node, Region, window};
pub use run::{BlockStats, FieldRun, FieldRunConfig, LevelInfo, Model, Snapshot, run_lattice};
pub use scheme::Scheme;
