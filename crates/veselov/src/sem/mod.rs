//! Variable time-step symplectic-energy-momentum (SEM) integrators: discrete
//! total variation on the extended configuration space `(t, q)` (seed 001;
//! Kane–Marsden–Ortiz; Lee's discrete mechanics).

pub mod action;
mod bordered;
pub mod bvp;
pub mod degeneracy;
mod predictor;
pub mod run;
mod separable;
pub mod stepper;
mod variable_stepper;

pub use action::{ActionDerivatives, SemAction, SemRule};
pub use bvp::solve_lee_bvp;
pub use degeneracy::StartExpansion;
pub use run::{SemRun, run_sem};
pub use stepper::{SemIntegrator, SemOptions, SemState, SemStepInfo, VariableStepMap};
pub use variable_stepper::SemStepper;
