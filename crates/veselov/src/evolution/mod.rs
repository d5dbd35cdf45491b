//! Time and space evolution of 1+1 fields on the triangle lattice of
//! Demoures, Gay-Balmaz and Ratiu, "Multisymplectic variational integrators
//! and space/time symplecticity" (note 000 §9–§15): split cell Lagrangians
//! ΔsΔt[K(ξ) − Φ(η) − Π] over ℝ^m or a Lie group, marched either in time
//! (given two levels) or in space (given two columns), with natural or
//! prescribed ends and the evolution momentum maps whose conservation or
//! flux law the covariant and evolutionary Noether theorems state.
//!
//! Files: [`split`] (the split cell Lagrangians, the increments ξ, η through
//! a difference or a retraction τ (Cayley, exp), their energies and damping
//! forces) and [`marcher`] (the core's flow marcher of
//! [`crate::field::flow`] on a rolling three-level window, slaved nodes,
//! ends, evolution momentum maps). The geometrically exact beam of the
//! paper's §5 is a model on these, [`crate::models::beam`].

pub mod marcher;
pub mod split;

pub use marcher::{Direction, EndCondition, EndData, Evolution000, EvolutionMomentum, EvolutionStepper};
pub use split::{
    DiagonalQuadratic, Difference, GroupIncrement, Increment, SplitDensity, SplitLagrangian, chart_gradient,
};
