//! Fields on 1+1 spacetime lattices (Marsden–Patrick–Shkoller,
//! "Multisymplectic geometry, variational integrators, and nonlinear PDEs",
//! §4–§5; note 002): lattices and region topology, discrete Lagrangian
//! densities on triangles and rectangles, time marching (a generic Newton
//! path for any density, through the core of [`crate::field`], and fast O(N)
//! paths for the sine-Gordon family of schemes), discrete energies, Noether
//! charges and the discrete multisymplectic form formula.
//!
//! Index convention: node `(i, j)`, `i` = space (`x = i·dx`), `j` = time
//! (`t = j·dt`). The paper's `h` is the time step `dt` and its `k` the space
//! step `dx`.
//!
//! Files: [`lattice`] (lattice, boundary conditions, cell shapes), [`region`]
//! (interior, closure, boundary, regularity, windows), [`density`] (cell
//! Lagrangians, the triangle and rectangle rules, DELf assembly, discrete
//! action), [`potential`] (sine-Gordon, wave, φ⁴, complex Klein–Gordon),
//! [`smooth`] (these densities as smooth densities of the core, for its
//! quadrature rules on CFK lattices of any dimension), [`generic`] (marching
//! of any density as a use of the core: a three-level window and the core's
//! whole-level Newton solve, tangent-linear steps), [`scheme`] and [`fast`]
//! (the six scalar schemes in O(N) per level, with their energies),
//! [`cyclic`] (prefactored cyclic tridiagonal solves), [`trig`] (sine and
//! cosine in vector lanes for the sine-Gordon kernels), [`initial`]
//! (kink–antikink, kink, breather, d'Alembert data), [`noether`] (charges,
//! multisymplectic form formula, mod-2π re-centring), [`energy`] and
//! [`waveform`] (discrete energies and wave diagnostics), [`stepping`] (the
//! marchers as steppers of the run driver), [`density_run`] and [`run`]
//! (drivers for front ends).
//!
//! The field models (sine-Gordon, the wave equation, φ⁴ and complex
//! Klein–Gordon) live here, in [`potential`], rather than in
//! [`crate::models`]: each is only the potential `N(φ)` of the density
//! `½(|φ_t|² − |φ_x|²) + N(φ)`, an implementation of the [`Potential`] and
//! [`ScalarPotential`] traits with the closed-form values the fast O(N)
//! kernels need, so the traits and their implementations stay in one place;
//! their initial data are in [`initial`]. The same potentials give the
//! nonlinear-wave density on CFK lattices of any dimension ([`smooth`]).
//!
//! ```
//! use veselov::spacetime::{FastMarcher, InitialData, Lattice, Scheme, SineGordon, SolverOptions};
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

pub mod cyclic;
pub mod density;
pub mod density_run;
pub mod energy;
pub mod fast;
pub mod generic;
pub mod initial;
pub mod lattice;
pub mod noether;
pub mod potential;
pub mod region;
pub mod run;
pub mod scheme;
pub mod smooth;
pub mod stepping;
pub mod trig;
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
pub use smooth::SpaceTime;
pub use stepping::{DensityStepper, FastLevels, FastStepper};
pub use waveform::{
    CollisionCounter, fourth_difference_max, guo_printed_energy, highest_mode_amplitude, rectangle_energy,
};
