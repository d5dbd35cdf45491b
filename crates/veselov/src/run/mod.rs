//! One run driver for every integrator family, after the executor/observer
//! split of the `argmin` crate.
//!
//! * A [`Stepper`] advances a state by one step and reports [`StepStats`]:
//!   `x_{k+1} = Φ(x_k)`. Every family implements it beside its integrator
//!   ([`crate::mechanics::PhaseStepper`] for fixed-step maps on phase space,
//!   [`crate::lgvi::GroupStepper`] on matrix groups,
//!   [`crate::sem::SemStepper`] for variable steps, and the lattice marchers
//!   of [`crate::field`], [`crate::spacetime`] and [`crate::evolution`]).
//! * [`drive`] runs a stepper until a [`StopWhen`] condition holds (end time,
//!   step count, interruption flag) or a step fails, and shows every new
//!   state to its [`Observer`]s: writers, progress bars, diagnostic
//!   accumulators, checkpoints. Observers may stop the run or fail it.
//! * A state that is no longer finite ends the run with
//!   [`Error::NonFiniteState`](crate::Error::NonFiniteState) naming the step,
//!   the time and the quantity; observers never see it.
//!
//! The driver knows nothing of files: writing rows is an observer's business,
//! and the command-line tool supplies its own. A failure keeps everything
//! the observers saw before it.
//!
//! [`Checkpoint`] lets a stepper save and restore what it carries from step
//! to step (predictor history, compensated-summation terms, lattice levels),
//! so that a resumed run continues bit for bit.
//!
//! [`on_pool`] runs a whole run on a thread of the rayon pool, where the
//! lattice marchers hand a level's vertices to the other threads cheaply.

mod checkpoint;
mod driver;
mod pool;
mod states;

pub use checkpoint::{Checkpoint, Words, save_count};
pub(crate) use checkpoint::{restore_option, save_option};
pub(crate) use driver::first_non_finite;
pub use driver::{Control, Observer, Outcome, Status, StepStats, Stepper, StopWhen, drive};
pub use pool::on_pool;
