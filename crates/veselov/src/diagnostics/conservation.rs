//! Energy and momentum-map series along a trajectory.

use crate::error::Result;
use crate::mechanics::{Lagrangian, PhaseState, Symmetry, energy, momentum_map, velocity_from_momentum};

/// A scalar quantity sampled along a trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct ConservationSeries {
    /// Sample times.
    pub t: Vec<f64>,
    /// Values.
    pub values: Vec<f64>,
}

impl ConservationSeries {
    /// `max_k |x_k − x_0|`.
    pub fn max_abs_error(&self) -> f64 {
        max_abs_deviation(&self.values)
    }
    /// `max_k |x_k − x_0| / max(|x_0|, tiny)`.
    pub fn max_rel_error(&self) -> f64 {
        let x0 = self.values.first().copied().unwrap_or(0.0).abs();
        self.max_abs_error() / x0.max(f64::MIN_POSITIVE)
    }
}

/// `max_k |x_k − x_0|` (0 for an empty series).
pub fn max_abs_deviation(values: &[f64]) -> f64 {
    match values.first() {
        Some(&x0) => values.iter().fold(0.0_f64, |m, &x| m.max((x - x0).abs())),
        None => 0.0,
    }
}

/// Energy `E = v·∂L/∂v − L` at each state, with `v` from the inverse Legendre map.
pub fn energy_series<const N: usize, L: Lagrangian<N>>(l: &L, states: &[PhaseState<N>]) -> Result<ConservationSeries> {
    let mut out = ConservationSeries {
        t: Vec::with_capacity(states.len()),
        values: Vec::with_capacity(states.len()),
    };
    for x in states {
        let v = velocity_from_momentum(l, x.t, &x.q, &x.p)?;
        out.t.push(x.t);
        out.values.push(energy(l, x.t, &x.q, &v));
    }
    Ok(out)
}

/// Momentum map `J = ⟨p, ξ_Q(q)⟩` at each state.
pub fn momentum_series<const N: usize, S: Symmetry<N> + ?Sized>(
    symmetry: &S,
    states: &[PhaseState<N>],
) -> ConservationSeries {
    ConservationSeries {
        t: states.iter().map(|x| x.t).collect(),
        values: states.iter().map(|x| momentum_map(symmetry, &x.q, &x.p)).collect(),
    }
}
