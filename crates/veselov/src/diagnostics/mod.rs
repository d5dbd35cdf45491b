//! Diagnostics that show structure is kept: energy and momentum error series,
//! the symplecticity defect of a one-step map, and convergence-order fits.

pub mod conservation;
pub mod order;
pub mod reference;
pub mod symplectic;

pub use conservation::{ConservationSeries, energy_series, max_abs_deviation, momentum_series};
pub use order::{OrderFit, fit_order, fit_order_asymptotic, fit_order_auto, local_rates};
pub use reference::rk4_reference;
pub use symplectic::symplecticity_defect;
