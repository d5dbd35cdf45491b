//! Lagrangian mechanics on `Rⁿ`: the Lagrangian interface, Galerkin discrete
//! Lagrangians, variational integrators and discrete Noether momenta.

pub mod duplication;
pub mod dynamic;
pub mod dynamic_legendre;
pub mod force;
pub mod galerkin;
pub mod lagrangian;
pub mod noether;
pub mod phase_stepper;
pub mod scheme;
pub mod separable;
pub mod state;

pub use duplication::{DuplicatedLagrangian, FlatRetraction, InverseRetraction};
pub use dynamic::{DynGalerkinIntegrator, DynLagrangian, DynState};
pub use dynamic_legendre::{dyn_energy, dyn_momentum, dyn_velocity_from_momentum};
pub use force::{Force, ForceJet, NoForce, force_jet, force_value};
pub use galerkin::{DiscreteLagrangianValue, GalerkinIntegrator};
pub use lagrangian::{
    Hessian, Jet, Lagrangian, acceleration, energy, forced_acceleration, hessian, jet, momentum, velocity_from_momentum,
};
pub use noether::{AffineSymmetry, Symmetry, invariance_defect, momentum_map};
pub use phase_stepper::{DynStepper, PhaseStepper, integrate, integrate_observed};
pub use scheme::{GalerkinScheme, MAX_STAGES, Method};
pub use separable::{Potential, SeparableIntegrator, SeparableLagrangian};
pub use state::{FlowJacobian, OneStepMap, PhaseState, StepStats, Trajectory};
