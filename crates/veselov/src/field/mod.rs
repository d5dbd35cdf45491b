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
//!
//! [`complex`] holds the cellular complexes of seed 003 §2 (abstract complex,
//! chains and cochains, cubic and CFK lattices with windows and periodic
//! quotients, explicit simplicial meshes, the 1+1 lattices of seeds 002 and
//! 000) and their top-cell view [`complex::TopCells`].
//!
//! Files: [`lattice`] (lattice, boundary conditions, cell shapes), [`region`]
//! (interior, closure, boundary, regularity, windows), [`density`] (cell
//! Lagrangians, the triangle and rectangle rules, DELf assembly, discrete
//! action), [`potential`] (sine-Gordon, wave, φ⁴, complex Klein–Gordon),
//! [`generic`] (marching of any density as a use of the core: a
//! three-level window and the core's whole-level Newton solve, tangent-linear steps),
//! [`scheme`] and [`fast`] (the six scalar schemes in O(N) per level, with
//! their energies), [`cyclic`] (prefactored cyclic tridiagonal solves),
//! [`initial`] (kink–antikink, kink, breather, d'Alembert data), [`noether`]
//! (charges, multisymplectic form formula, mod-2π re-centring) and [`run`]
//! (a driver for front ends); [`discretize`] (node maps, smooth densities
//! over a fibre and the quadratures of seed 003 §5 turning them into
//! discrete Lagrangians on cells, the Cosserat rod of §6); [`split`] (seed
//! 000's split cell Lagrangians ΔsΔt[K(ξ) − Φ(η) − Π], ξ, η through a
//! retraction or a difference, with their energies and damping forces) and
//! [`evolution`] (time and space evolution on seed 000's lattice: the flow
//! marcher on a rolling three-level window, slaved nodes, natural or
//! prescribed ends, evolution momentum maps).
//!
//! The field models (sine-Gordon, the wave equation, φ⁴ and complex
//! Klein–Gordon) live here, in [`potential`], rather than in
//! [`crate::models`]: each is only the potential `N(φ)` of the density
//! `½(|φ_t|² − |φ_x|²) + N(φ)`, an implementation of this core's
//! [`Potential`] and [`ScalarPotential`] traits with the closed-form values
//! the fast O(N) kernels need, so the traits and their implementations stay
//! in one place; their initial data are in [`initial`].
//!
//! ```
//! use veselov::field::{FastMarcher, InitialData, Lattice, Scheme, SineGordon, SolverOptions};
//!
//! // Seed 002 §5.2: kink–antikink on a circle of length 40, N = 255, h = k/8.
//! let lattice = Lattice::periodic(255, 40.0, 8.0).unwrap();
//! let data = InitialData::KinkAntikink { epsilon: 1e-6, paper_start: true };
//! let (y0, y1) = data.levels(&lattice).unwrap();
//! let mut m = FastMarcher::new(SineGordon, Scheme::Triangle, lattice, &y0, &y1, SolverOptions::default()).unwrap();
//! m.step().unwrap();
//! let e0 = m.energy();
//! for _ in 0..1000 {
//!     m.step().unwrap();
//! }
//! assert!((m.energy() - e0).abs() < 0.1 * e0.abs());
//! ```

pub mod cauchy;
pub mod cell;
pub mod complex;
pub mod cyclic;
pub mod density;
pub mod density_run;
pub mod discretize;
pub mod energy;
pub mod evolution;
pub mod fast;
pub mod fibre;
pub mod flow;
pub mod generic;
pub mod initial;
pub mod lattice;
pub mod legendre;
pub mod level_solve;
pub mod noether;
pub mod potential;
pub mod region;
pub mod run;
pub mod scheme;
pub mod split;
pub mod stepping;
pub mod trig;
pub mod variational;
pub mod waveform;

pub use density::{
    CellJet, CellLagrangian, CoreCell, Density, RectangleRule, TriangleRule, action, cell_gradient, cell_jet,
    delf_residual,
};
pub use density_run::{DensityRun, DensityRunConfig, Generator, run_density};
pub use energy::{CellEnergy, level_energy};
pub use fast::{FastMarcher, SolverOptions};
pub use generic::{GenericMarcher, Tangent, node_value};
pub use initial::{ComplexPlaneWave, InitialData, Levels, PeriodicKink};
pub use lattice::{Boundary, CellShape, Lattice};
pub use noether::{multisymplectic_boundary_sum, recentre_mod_2pi, shift_charge, split_charge, split_symplectic_form};
pub use potential::{ComplexKleinGordon, NonlinearWave, Phi4, Potential, ScalarPotential, SineGordon, Wave};
pub use region::{Node, Region, window};
pub use run::{BlockAccumulator, BlockStats, FieldRun, FieldRunConfig, LevelInfo, Model, Snapshot, run_lattice};
pub use scheme::Scheme;
pub use stepping::{CauchyStepper, DensityStepper, FastLevels, FastStepper};
pub use waveform::{
    CollisionCounter, fourth_difference_max, guo_printed_energy, highest_mode_amplitude, rectangle_energy,
};
